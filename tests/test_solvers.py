"""MUMPS on the monolithic AIJ matrix and PCFIELDSPLIT (Schur) on the MatNest
and on the AIJ matrix give the same S2 answer to solver tolerance; fieldsplit
without the augmentation (the upper body is held only by contact: K is
singular) either solves it right or stops with one line naming -kkt_augment."""
import os

import numpy as np
from m2d import check, mesh, opts, read_json, run, solve, sorted_fields, workdir

variants = {
    "mumps_aij": ["-options_file", opts("kkt_mumps")],
    "fieldsplit_nest": ["-options_file", opts("kkt_fieldsplit")],
    "fieldsplit_aij": ["-options_file", opts("kkt_fieldsplit"), "-kkt_mat", "aij"],
}
res = {}
for name, extra in variants.items():
    for scene, m in (("s2", "patch_10_31"), ("s1", "seed_patch")):
        tag = "solver_%s_%s" % (scene, name)
        base = opts("patch_uniform") if scene == "s2" else opts("seed_patch")
        s = solve(tag, ["-options_file", base, "-mesh", mesh(m), "-output_name", "sol"] + extra)
        res[(scene, name)] = (s, sorted_fields(workdir(tag) + "/sol.h5"))
        if scene == "s2":
            e = s["error"]
            check(max(e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"]) < 1e-10, "%s: S2 patch test passes (%.2e), at most %d KSP iterations in a solve" % (name, e["sigma_yy_max_rel"], s["ksp_iterations_max"]))
for scene in ("s2", "s1"):
    s0, (v0, c0, _, _) = res[(scene, "mumps_aij")]
    for name in ("fieldsplit_nest", "fieldsplit_aij"):
        s1, (v1, c1, _, _) = res[(scene, name)]
        du = np.abs(v1["displacement"] - v0["displacement"]).max() / np.abs(v0["displacement"]).max()
        p0, p1 = v0["contact_pressure"], v1["contact_pressure"]
        dp = np.abs(p1 - p0).max() / np.abs(p0).max()
        check(du < 1e-9 and dp < 1e-9, "%s %s vs mumps_aij: displacement %.1e, contact pressure %.1e relative" % (scene, name, du, dp))
# Without the augmentation the (u,u) block is singular: whether MUMPS' pivoting
# gets through it depends on the BLAS and the pivot order of the machine. What
# must hold everywhere: either the right answer (exit 0, patch test exact) or
# one line naming -kkt_augment and exit 1, never a wrong answer.
d = workdir("solver_noaug")
summary = d + "/summary.json"
if os.path.exists(summary):
    os.remove(summary)
rc, out, err = run(["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform"), "-options_file", opts("kkt_fieldsplit"), "-kkt_augment", "0", "-output_dir", d, "-summary", summary], check=False)
if rc == 0:
    e = read_json(summary)["error"]
    worst = max(e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"])
    check(worst < 1e-10 and not err.strip(), "fieldsplit without augmentation: solved, patch test passes (%.2e)" % worst)
else:
    check(rc == 1 and "-kkt_augment" in err and len(err.strip().splitlines()) == 1, "fieldsplit without augmentation: one clear line: %s" % err.strip())
rc, out, err = run(["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform"), "-kkt_mat", "nest", "-output_dir", workdir("solver_nestlu")], check=False)
check(rc == 1 and "-kkt_mat" in err, "LU on a MatNest: %s" % err.strip())
