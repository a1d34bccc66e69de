"""The adaptive loop on scenes nobody tuned it for (docs/adaptivity.md): Hertz, the
two cylinders of hertz_two and the rounded punch (options/punch.opts), each
with either body non-mortar. Asserted, on every run:
 1. the same command gives the same meshes and answers (6 runs of Hertz at
    target 0.04, 2 of hertz_two; on AVX-512 machines OpenBLAS rounds the
    last bits by the arrays' alignment, which main.c fixes at 64 bytes for
    PETSc's arrays: before, Open MPI's threads moved it from run to run), and
    1 and 2 ranks give the same meshes;
 2. a tighter target never ends on a worse answer: Hertz at 0.04, 0.01,
    0.0025 (pressure error against Hertz non-increasing within 10%); each
    stops at its target or within -adapt_tolerance (5%) above it, and no mesh
    near the target is followed by a big step (the sizing rule: a mesh whose
    estimate is within 1.3 times the target is followed by at most 1.6 times
    its dofs);
 3. the pressure ripple (max deviation of an interior active node from the
    interpolation of its neighbours, over the peak) is at most 1% on every mesh
    with at least 20 active nodes (the punch: 100; its pressure has a kink where
    the rounded corner meets the flat bottom, the curvature jumping from 0 to
    1/r, and its meshes with some 30 active nodes measure 1.5-2% there and
    near the zone's edge, which is the kink, not ripple), the smallest cell at least 1e-3 of the
    contact zone, no mesh above -adapt_max_dofs, at most 3 active-set steps
    per mesh after the first; hertz_two's error against Hertz falls with the
    target;
 4. -mesh_scale scales the .geo too (the same meshes, the same relative
    errors); -mesh with -adapt starts the loop from that mesh; a first mesh
    past the cap is one line naming -adapt_max_dofs;
 5. the punch with -adapt_grading 1.4 up to the floor (past 1e5 dofs): the
    mortar side stays the finer, ripple <= 1% on every mesh with >= 100 active
    nodes; -adapt_keep last gives the last mesh's results."""
import os

import numpy as np
from m2d import check, opts, read_h5, run, solve, workdir

CAP = 50000


def min_cell(h5):
    xy, cells, vf, cf = read_h5(h5)
    c = xy[cells]
    d1, d2 = c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]
    return np.sqrt(np.abs(0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]))).min()


def adapt(tag, args, ranks=1):
    return solve(tag, list(args) + ["-contact_monitor", "0", "-output_name", "sol"], ranks=ranks)


def sequence(s):
    return [a["dofs"] for a in s["adapt"]]


HERTZ = ["-options_file", opts("hertz_adapt")]
HERTZ_TWO = ["-options_file", opts("hertz_two_adapt")]
PUNCH = ["-options_file", opts("punch")]
SWAP = {"hertz": ["-contact_nonmortar", "block_top", "-contact_mortar", "cylinder_arc"],
        "hertz_two": ["-contact_nonmortar", "lower_arc", "-contact_mortar", "upper_arc"],
        "punch": ["-contact_nonmortar", "foundation_top", "-contact_mortar", "punch_bottom"]}
SCENES = {"hertz": HERTZ, "hertz_two": HERTZ_TWO, "punch": PUNCH}

# ---------------------------------------------------------------- 1. the same answer every run
runs = [adapt("adapt_same", HERTZ + ["-adapt_target", "0.04"]) for k in range(6)]
first = runs[0]
check(all(sequence(s) == sequence(first) and s["pressure_l2_rel"] == first["pressure_l2_rel"] and s["pressure_estimate"] == first["pressure_estimate"] for s in runs),
      "Hertz target 0.04, 6 runs: the same meshes %s and pressure error %.6e every run" % (sequence(first), first["pressure_l2_rel"]))
two = [adapt("adapt_same_two", HERTZ_TWO + ["-adapt_target", "2e-3"]) for k in range(2)]
check(sequence(two[0]) == sequence(two[1]) and two[0]["pressure_l2_rel"] == two[1]["pressure_l2_rel"],
      "hertz_two target 2e-3, 2 runs: the same meshes %s and pressure error %.6e" % (sequence(two[0]), two[0]["pressure_l2_rel"]))
par = adapt("adapt_same_two_2r", HERTZ_TWO + ["-adapt_target", "2e-3"], ranks=2)
d = abs(par["pressure_l2_rel"] - two[0]["pressure_l2_rel"]) / two[0]["pressure_l2_rel"]
check(sequence(par) == sequence(two[0]) and d < 1e-8, "hertz_two on 2 ranks: the same meshes %s, pressure error to %.1e" % (sequence(par), d))

# ---------------------------------------------------------------- 2. a tighter target is never worse
sweep = {t: adapt("adapt_sweep_%s" % t, HERTZ + ["-adapt_target", t]) for t in ("0.04", "0.01", "0.0025")}
errs = [sweep[t]["pressure_l2_rel"] for t in ("0.04", "0.01", "0.0025")]
check(errs[1] <= 1.1 * errs[0] and errs[2] <= 1.1 * errs[1], "Hertz targets 0.04, 0.01, 0.0025: pressure errors %s non-increasing (dofs %s)" % (["%.3e" % e for e in errs], [sweep[t]["dofs"] for t in ("0.04", "0.01", "0.0025")]))
for t in ("0.04", "0.01", "0.0025"):
    s = sweep[t]
    check(s["adapt_stop"] in ("target", "near_target") and s["pressure_estimate"] <= 1.05 * float(t), "Hertz target %s: stopped at the target (%s), estimated pressure error %.3e (against Hertz %.3e)" % (t, s["adapt_stop"], s["pressure_estimate"], s["pressure_l2_rel"]))
    steps = s["adapt"]
    big = [(a["dofs"], a["goal_estimate"], b["dofs"]) for a, b in zip(steps, steps[1:]) if a["goal_estimate"] <= 1.3 * float(t) and b["dofs"] > 1.6 * a["dofs"]]
    check(not big, "Hertz target %s: no big step near the target %s" % (t, ["%d dofs at %.2e then %d" % x for x in big] or sequence(s)))

# ---------------------------------------------------------------- 3. every scene, either side
for name, args in SCENES.items():
    for side, extra in (("as given", []), ("swapped", SWAP[name])):
        tag = "adapt_%s_%s" % (name, "a" if not extra else "b")
        s = adapt(tag, args + extra + ["-adapt_target", "1e-4", "-adapt_max_steps", "6"])
        steps = s["adapt"]
        rip = [(a["dofs"], a["active_nodes"], a["pressure_ripple"]) for a in steps]
        fine = 100 if name == "punch" else 20  # the punch's kink: see the docstring
        bad = [r for r in rip if r[1] >= fine and r[2] > 0.01]
        check(not bad, "%s, non-mortar %s: ripple <= 1%% on every mesh with >= %d active nodes %s" % (name, side, fine, ["%d dofs %d active %.2f%%" % (d, n, 100 * r) for d, n, r in rip]))
        check(all(a["dofs"] <= CAP for a in steps), "%s, %s: no mesh above the cap (%d): %s" % (name, side, CAP, sequence(s)))
        check(all(a["iterations"] <= 3 for a in steps[1:]), "%s, %s: active-set steps per mesh %s (<= 3 after the first)" % (name, side, [a["iterations"] for a in steps]))
        zone = s["half_width"] if "half_width" in s else None
        if zone is None:  # the punch: the active zone from the contact CSV
            import csv
            with open(os.path.join(workdir(tag), "sol_contact.csv")) as f:
                zone = max(float(r["x"]) for r in csv.DictReader(f) if r["active"] == "1")
        h = min_cell(os.path.join(workdir(tag), "sol.h5"))
        check(h >= 1e-3 * zone * 0.99, "%s, %s: smallest cell %.2e >= 1e-3 of the contact zone %.4f" % (name, side, h, zone))

# the balance holds on the sizes asked of gmsh: the floor before it (where the
# floor holds a zone's edge the mortar side facing it still gets its 1.3 times
# finer cells; the floor after the balance made both sides equal there: 6.2%
# ripple on the punch's mesh past 1e5 dofs with -adapt_grading 1.4, 8.5% at
# 4e5 dofs by default), and again after the gradation (which lowers each
# side's sizes on its own: 4.8% on the 1e4-dof mesh with grading 1.4).
# -adapt_keep last: the results are those of the last mesh, whatever its estimate.
s = adapt("adapt_floor", PUNCH + ["-adapt_target", "1e-6", "-adapt_max_dofs", "150000", "-adapt_grading", "1.4", "-adapt_keep", "last", "-output_vtu", "0"])
last = s["adapt"][-1]
check(last["dofs"] > 100000 and s["dofs"] == last["dofs"] and s["adapt_best_step"] == len(s["adapt"]) - 1,
      "-adapt_keep last: the results are the last mesh's (%d dofs, step %d of %s)" % (s["dofs"], s["adapt_best_step"], sequence(s)))
rip = [(a["dofs"], a["active_nodes"], a["pressure_ripple"]) for a in s["adapt"] if a["active_nodes"] >= 100]
check(rip and all(r[2] <= 0.01 for r in rip), "punch with -adapt_grading 1.4 up to the floor: ripple <= 1%% of the peak on every mesh with >= 100 active nodes %s" % ["%d dofs %.2f%%" % (r[0], 100 * r[2]) for r in rip])

# hertz_two: the error against Hertz falls with the target
errs = []
for t in ("0.02", "0.005", "0.001"):
    errs.append(adapt("adapt_two_%s" % t, HERTZ_TWO + ["-adapt_target", t])["pressure_l2_rel"])
check(errs[1] <= 1.1 * errs[0] and errs[2] <= 1.1 * errs[1], "hertz_two targets 0.02, 0.005, 0.001: errors against Hertz %s" % ["%.3e" % e for e in errs])

# ---------------------------------------------------------------- 4. the ways a mesh comes in
a = adapt("adapt_scale1", HERTZ + ["-adapt_target", "0.01"])
b = adapt("adapt_scale2", HERTZ + ["-adapt_target", "0.01", "-mesh_scale", "2", "-hertz_radius", "2"])
d = abs(a["pressure_l2_rel"] - b["pressure_l2_rel"]) / a["pressure_l2_rel"]
check(sequence(a) == sequence(b) and d < 1e-8, "-mesh_scale 2 on the .geo: the same meshes %s, the same relative pressure error (to %.1e)" % (sequence(b), d))
fixed = solve("adapt_fixed_two", ["-options_file", opts("hertz_two"), "-contact_monitor", "0"])
s = adapt("adapt_from_mesh", ["-options_file", opts("hertz_two"), "-geo", "hertz_two.geo", "-adapt", "-adapt_goal", "contact", "-adapt_target", "0.01", "-adapt_max_steps", "2"])
check(s["adapt"][0]["dofs"] == fixed["dofs"], "-mesh with -adapt: the loop starts from that mesh (%d dofs)" % s["adapt"][0]["dofs"])
rc, out, err = run(HERTZ + ["-geo_setnumber", "level=1", "-adapt_max_dofs", "1000", "-output_dir", workdir("adapt_bigfirst")], check=False)
lines = [ln for ln in err.splitlines() if ln.strip()]
check(rc == 1 and len(lines) == 1 and "-adapt_max_dofs" in lines[0], "a first mesh past the cap: one line: %s" % (lines[-1] if lines else "(none)"))
