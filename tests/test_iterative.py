"""The iterative path (-kkt_path iterative, src/iterative.c): the multipliers
eliminated row by row and CG + GAMG in u.
 1. Hertz levels 0-2 (dual multipliers), the eccentric S2 load (dual
    multipliers, and NTS), the stack under a pressure that pulls on part of
    its top (the set changes at every step) on 1, 2 and 3 ranks: the same active set as the
    condensed path on one rank (and, with -iterative_prove, the same steps;
    without, at most 3 more), displacement and pressure
    equal to 1e-8 of their maxima; the answer's own checks hold
    (residual_rel < 1e-10); the most CG iterations of a step stays below 60;
 2. the S2 patch test passes on it (unilateral, tied) and a block without
    contact (the linear solve) is exact;
 3. K's block size and near-null space make PETSc's own AMG work from the
    options database on the default (direct) paths' linear solve:
    -ksp_type cg -pc_type gamg on the block and on S2 tied through fieldsplit;
 4. the summary's ksp_iterations_max and memory_max_rank_mb on every path;
 5. what it cannot do is one line: standard multipliers, -kkt_augment,
    vinewtonrsls;
 6. the steps' settings (docs/scaling.md): with each of inexact steps, the
    contact zone and the kept AMG switched off in turn, with every set
    proven, and with steps so inexact that the sets return to an earlier one
    (0.7) or |F| rises (0.9) (then proven from there: a line says so), the
    answer is the same (set, fields to 1e-8); the adaptive punch's warm
    starts take no unproven set, at most one step more per mesh than the
    condensed path (a warm start's first step complete), and give the
    condensed path's answer; the defaults take fewer Krylov iterations
    and fewer AMG set-ups than complete steps with a new AMG each (Hertz
    level 2, 1 and 2 ranks);
 7. a bad value of -iterative_inexact, -iterative_reuse, -iterative_zone is
    one line naming the option (1 and 2 ranks)."""
import json

import numpy as np
from m2d import check, csv_columns, mesh, opts, run, solve, sorted_fields, workdir

cases = [("hertz_%d" % lv, ["-options_file", opts("hertz"), "-mesh", mesh("hertz_%d" % lv)]) for lv in (0, 1, 2)]
ecc = ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_10_31"), "-pressure", "upper_top:-1e6:4e6:0", "-exact", "none"]
cases.append(("s2_eccentric_dual", ecc + ["-mortar_basis", "dual"]))
cases.append(("s2_eccentric_nts", ecc + ["-contact_method", "nts"]))
# the stack under a pressure falling to -0.5e6 across its top (issue 33 item 3):
# the set changes every step and the zone holds every unknown (286); on 2 and
# 3 ranks the zone's LU kept the first set's factors (DIVERGED_INDEFINITE_PC)
cases.append(("stack_gradient_dual", ["-options_file", opts("stack"), "-pressure", "top_top:1e6:-1.5e6:0", "-exact", "none", "-mortar_basis", "dual"]))

# ---------------------------------------------------------------- 1. = the condensed path
for name, base in cases:
    common = base + ["-output_name", "sol", "-output_vtu", "0", "-contact_monitor", "0"]
    ref = solve("iter_%s_ref" % name, common + ["-kkt_path", "condensed"])
    vr = sorted_fields(workdir("iter_%s_ref" % name) + "/sol.h5")[0]
    for nr in (1, 2, 3):
        tag = "iter_%s_%d" % (name, nr)
        s = solve(tag, common + ["-kkt_path", "iterative"], ranks=nr)
        v = sorted_fields(workdir(tag) + "/sol.h5")[0]
        check(s["kkt_path"] == "iterative" and s["ranks"] == nr, "%s %d rank(s): ran the %s path" % (name, nr, s["kkt_path"]))
        check(s["active_nodes"] == ref["active_nodes"] and s["iterations"] <= ref["iterations"] + 3,
              "%s %d rank(s): %d steps, %d active (condensed: %d, %d)" % (name, nr, s["iterations"], s["active_nodes"], ref["iterations"], ref["active_nodes"]))
        du = np.abs(v["displacement"] - vr["displacement"]).max() / np.abs(vr["displacement"]).max()
        dp = np.abs(v["contact_pressure"] - vr["contact_pressure"]).max() / np.abs(vr["contact_pressure"]).max()
        check(du < 1e-8 and dp < 1e-8, "%s %d rank(s): displacement %.1e, pressure %.1e of the condensed path's" % (name, nr, du, dp))
        check(s["residual_rel"] < 1e-10 and s["complementarity"] < 1e-10, "%s %d rank(s): residual %.1e, complementarity %.1e" % (name, nr, s["residual_rel"], s["complementarity"]))
        # the stack's zone is all of it: CG converges in one iteration
        check((0 if name.startswith("stack") else 1) < s["ksp_iterations_max"] <= 60, "%s %d rank(s): at most %d CG iterations in a step (%d in all, %d preconditioner set-ups)" % (name, nr, s["ksp_iterations_max"], s["ksp_iterations_total"], s["pc_setups"]))
    # -iterative_prove: every step's set proven, so the condensed path's steps one by one
    s = solve("iter_%s_prove" % name, common + ["-kkt_path", "iterative", "-iterative_prove"])
    check(s["iterations"] == ref["iterations"] and s["active_nodes"] == ref["active_nodes"],
          "%s -iterative_prove: %d steps, %d active (condensed: %d, %d)" % (name, s["iterations"], s["active_nodes"], ref["iterations"], ref["active_nodes"]))

# ---------------------------------------------------------------- 2. exact fields
for tag, extra in (("iter_s2", []), ("iter_s2_tied", ["-contact_unilateral", "0"])):
    s = solve(tag, ["-options_file", opts("patch_uniform"), "-mortar_basis", "dual", "-kkt_path", "iterative"] + extra, ranks=2)
    e = max(s["error"][k] for k in ("sigma_yy_max_rel", "sigma_xx_max_rel", "sigma_xy_max_rel"))
    check(e < 1e-10 and s["kkt_path"] == ("iterative" if not extra else "tied"), "%s (%s path, 2 ranks): S2 patch test %.1e, %d CG iterations" % (tag, s["kkt_path"], e, s["ksp_iterations_max"]))
s = solve("iter_block", ["-options_file", opts("block"), "-mesh", mesh("block_16"), "-kkt_path", "iterative"])
check(s["error"]["sigma_yy_max_rel"] < 1e-10 and s["ksp_iterations_max"] > 1, "block, linear solve by CG + GAMG: uniform stress %.1e, %d iterations" % (s["error"]["sigma_yy_max_rel"], s["ksp_iterations_max"]))

# ---------------------------------------------------------------- 3. PETSc's AMG from the options database
amg = ["-ksp_type", "cg", "-pc_type", "gamg", "-ksp_rtol", "1e-12"]
s = solve("iter_block_gamg", ["-options_file", opts("block"), "-mesh", mesh("block_32")] + amg, ranks=2)
check(s["error"]["sigma_yy_max_rel"] < 1e-9 and 1 < s["ksp_iterations"] <= 30, "block 32x32, -pc_type gamg on the direct path's solve (2 ranks): %.1e in %d iterations (block size 2 and rigid-body modes)" % (s["error"]["sigma_yy_max_rel"], s["ksp_iterations"]))
s = solve("iter_s2_fieldsplit_gamg", ["-options_file", opts("patch_uniform"), "-options_file", opts("kkt_fieldsplit"), "-contact_unilateral", "0",
                                      "-fieldsplit_u_ksp_type", "cg", "-fieldsplit_u_pc_type", "gamg", "-fieldsplit_u_ksp_rtol", "1e-13", "-ksp_rtol", "1e-12"])
e = max(s["error"][k] for k in ("sigma_yy_max_rel", "sigma_xx_max_rel", "sigma_xy_max_rel"))
check(e < 1e-8, "S2 tied, fieldsplit with GAMG on the u block: patch test %.1e" % e)

# ---------------------------------------------------------------- 4. summary keys on every path
for path in ("condensed", "full"):
    s = solve("iter_keys_%s" % path, ["-options_file", opts("hertz"), "-mesh", mesh("hertz_0"), "-kkt_path", path])
    check(s["kkt_path"] == path and s["ksp_iterations_max"] == 1 and 10 < s["memory_max_rank_mb"] < 4096, "%s: ksp_iterations_max %d, memory_max_rank_mb %.0f" % (path, s["ksp_iterations_max"], s["memory_max_rank_mb"]))

# ---------------------------------------------------------------- 5. one line for what it cannot do
bad = [("standard multipliers", ["-options_file", opts("patch_uniform")], "-mortar_basis dual"),
       ("-kkt_augment", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_0"), "-kkt_augment", "1"], "-kkt_augment"),
       ("vinewtonrsls", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_0"), "-snes_type", "vinewtonrsls"], "vinewtonrsls")]
for what, args, name in bad:
    rc, out, err = run(args + ["-kkt_path", "iterative", "-output_dir", workdir("iter_bad")], check=False)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    check(rc == 1 and len(lines) == 1 and name in lines[0], "%s: one line naming %s: %s" % (what, name, lines[-1] if lines else "(none)"))

# ---------------------------------------------------------------- 6. the steps' settings
h2 = ["-options_file", opts("hertz"), "-mesh", mesh("hertz_2"), "-kkt_path", "iterative", "-output_name", "sol", "-output_vtu", "0", "-contact_monitor", "0"]
complete = ["-iterative_inexact", "0", "-iterative_zone", "-1", "-iterative_reuse", "0"]
for nr in (1, 2):
    ref = solve("iter_set_default_%d" % nr, h2, ranks=nr)
    vr = sorted_fields(workdir("iter_set_default_%d" % nr) + "/sol.h5")[0]
    for k, (what, extra) in enumerate((("complete steps, a new AMG each", complete), ("no inexact steps", ["-iterative_inexact", "0"]), ("proven sets", ["-iterative_prove"]),
                                       ("steps to 0.7 (the sets cycle)", ["-iterative_inexact", "0.7"]),
                                       ("steps to 0.9 (|F| rises)", ["-iterative_inexact", "0.9"]),
                        ("no zone", ["-iterative_zone", "-1"]), ("a new AMG each step", ["-iterative_reuse", "0"]))):
        tag = "iter_set_%d_%d" % (k, nr)
        s = solve(tag, h2 + extra, ranks=nr)
        v = sorted_fields(workdir(tag) + "/sol.h5")[0]
        du = np.abs(v["displacement"] - vr["displacement"]).max() / np.abs(vr["displacement"]).max()
        dp = np.abs(v["contact_pressure"] - vr["contact_pressure"]).max() / np.abs(vr["contact_pressure"]).max()
        check(s["active_nodes"] == ref["active_nodes"] and du < 1e-8 and dp < 1e-8,
              "Hertz 2, %d rank(s), %s: %d steps, %d active, displacement %.1e, pressure %.1e of the defaults'" % (nr, what, s["iterations"], s["active_nodes"], du, dp))
        if extra is complete:
            check(ref["ksp_iterations_total"] < s["ksp_iterations_total"] and ref["pc_setups"] < s["pc_setups"],
                  "Hertz 2, %d rank(s): the defaults take %d Krylov iterations and %d AMG set-ups, complete steps %d and %d" % (nr, ref["ksp_iterations_total"], ref["pc_setups"], s["ksp_iterations_total"], s["pc_setups"]))

# steps so inexact that their sets return to an earlier one, or that |F| rises: from there every set is proven, and the end is the same (above)
for inexact, what, key in (("0.7", "the sets returned to an earlier one", "back to the set of step"), ("0.9", "|F| rose", "times the least since step 1")):
    rc, out, err = run(h2 + ["-iterative_inexact", inexact, "-contact_monitor", "1", "-output_dir", workdir("iter_guard")])
    line = ([ln for ln in out.splitlines() if "proven from here" in ln] or ["(no such line)"])[0].strip()
    check(key in line, "Hertz 2, -iterative_inexact %s: %s, every set proven from there on: %s" % (inexact, what, line))

# a warm start (the adaptive loop's meshes after the first) takes no inexact step's set unproven:
# near the answer they wander (the punch took 50 steps without settling); the answer is the condensed path's
punch = ["-options_file", opts("punch"), "-mortar_basis", "dual", "-adapt_max_dofs", "12000", "-output_name", "sol", "-output_vtu", "0"]
ref_csv = None
for path in ("condensed", "iterative"):
    rc, out, err = run(punch + ["-kkt_path", path, "-output_dir", workdir("iter_punch_%s" % path)])
    cols = csv_columns(workdir("iter_punch_%s" % path) + "/sol_contact.csv")
    steps = [a["iterations"] for a in json.load(open(workdir("iter_punch_%s" % path) + "/sol_summary.json"))["adapt"]]
    if path == "condensed":
        ref_csv, ref_steps = cols, steps
        continue
    # a warm start's first step is complete: the steps of the condensed path (before: 12 on each later mesh)
    check(len(steps) == len(ref_steps) and all(k <= r + 1 for k, r in zip(steps[1:], ref_steps[1:])),
          "adaptive punch on the iterative path: active-set steps per mesh %s, at most one more than the condensed path's %s after the first mesh" % (steps, ref_steps))
    unproven = [int(ln.split(" steps on an inexact")[0].split(", ")[-1]) for ln in out.splitlines() if "steps on an inexact solve's set" in ln]
    dp = max(abs(x - y) for x, y in zip(cols["pressure"], ref_csv["pressure"])) / max(abs(x) for x in ref_csv["pressure"])
    check(len(unproven) >= 2 and all(u == 0 for u in unproven[1:]) and list(cols["active"]) == list(ref_csv["active"]) and dp < 1e-8,
          "adaptive punch on the iterative path: unproven steps per mesh %s (none after the first mesh), the condensed path's set, pressure %.1e of the peak" % (unproven, dp))

# ---------------------------------------------------------------- 7. bad values: one line
for opt, val in (("-iterative_inexact", "1.5"), ("-iterative_inexact", "-1e-3"), ("-iterative_inexact", "abc"), ("-iterative_reuse", "0.5"), ("-iterative_zone", "-2")):
    for nr in (1, 2):
        rc, out, err = run(["-options_file", opts("hertz"), "-mesh", mesh("hertz_0"), "-kkt_path", "iterative", opt, val, "-output_dir", workdir("iter_bad")], ranks=nr, check=False)
        lines = [ln for ln in err.splitlines() if ln.strip()]
        check(rc == 1 and len(lines) == 1 and lines[0].startswith("mortar2d: error: ") and opt in lines[0], "%s %s, %d rank(s): one line naming it: %s" % (opt, val, nr, lines[-1] if lines else "(none)"))
