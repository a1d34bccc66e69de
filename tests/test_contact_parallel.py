"""Contact on 1 and 2 MPI ranks agrees: S1 and S2, mortar and NTS; fields
compared after sorting by coordinates, contact pressure node by node."""
import numpy as np
from m2d import check, mesh, opts, solve, sorted_fields, workdir

for scene, base, m in (("s2", "patch_uniform", "patch_10_31"), ("s1", "seed_patch", "seed_patch_2")):
    for method in ("mortar", "nts"):
        out = {}
        for ranks in (1, 2):
            tag = "cpar_%s_%s_%d" % (scene, method, ranks)
            s = solve(tag, ["-options_file", opts(base), "-mesh", mesh(m), "-contact_method", method, "-output_name", "sol"], ranks=ranks)
            out[ranks] = (s, sorted_fields(workdir(tag) + "/sol.h5"))
        (s1, (v1, c1, _, _)), (s2, (v2, c2, _, _)) = out[1], out[2]
        check(s2["ranks"] == 2 and s1["contact_nodes"] == s2["contact_nodes"], "%s %s: %d multipliers on 1 and 2 ranks" % (scene, method, s1["contact_nodes"]))
        du = np.abs(v1["displacement"] - v2["displacement"]).max() / np.abs(v1["displacement"]).max()
        dp = np.abs(v1["contact_pressure"] - v2["contact_pressure"]).max() / np.abs(v1["contact_pressure"]).max()
        ds = np.abs(c1["sigma_y"] - c2["sigma_y"]).max() / np.abs(c1["sigma_y"]).max()
        g1, g2 = v1["gap"], v2["gap"]
        check(np.array_equal(np.isnan(g1), np.isnan(g2)), "%s %s: the same nodes carry a gap" % (scene, method))
        check(du < 1e-10 and dp < 1e-10 and ds < 1e-10, "%s %s: displacement %.1e, pressure %.1e, sigma_y %.1e relative" % (scene, method, du, dp, ds))
        check(abs(s1["contact_force"] - s2["contact_force"]) < 1e-10 * abs(s1["contact_force"]), "%s %s: contact force %.12e vs %.12e" % (scene, method, s1["contact_force"], s2["contact_force"]))
