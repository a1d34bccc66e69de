"""The adaptive loop (-adapt, src/app/adapt.c):
 1. Hertz with options/hertz_adapt.opts: at most 5e4 dofs on the final mesh
    and the pressure error against Hertz at most 1.5e-3 (issue 14's figure),
    at most 3 active-set steps on every adapted mesh after the first, a
    well-formed "adapt" list in the summary; the same meshes and answers on 2
    ranks. The error bound has a margin of 7% over the measured value, and
    round-off does not move it: 1 and 2 ranks, METIS' and MUMPS' orderings give
    the same meshes and errors to 1e-9. Other meshes of similar size do: other
    gmsh algorithms (Delaunay, simple recombination) gave 1.7e-3 to 2.1e-3, as
    the edge of the contact zone falls between nodes differently; a gmsh other
    than Debian 12's 4.8.4 may need this bound revisited;
 2. the refinement goes where the scene needs it: Hertz's smallest cells at
    the edge of the contact zone (x = a), S1's at the two corners of the upper
    body on the lower one;
 3. the estimate falls from mesh to mesh;
 4. bad input: -adapt without -geo, a missing .geo, a malformed
    -geo_setnumber: one line, exit 1."""
import os

import numpy as np
from m2d import check, opts, read_h5, run, solve, workdir

A_HERTZ = 0.0998217


def cells_and_sizes(h5):
    xy, cells, vf, cf = read_h5(h5)
    c = xy[cells]
    cen = c.mean(axis=1)
    d1, d2 = c[:, 2] - c[:, 0], c[:, 3] - c[:, 1]
    h = np.sqrt(np.abs(0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])))
    return cen, h, cf


# ---------------------------------------------------------------- 1. Hertz
res = {}
for ranks in (1, 2):
    tag = "adapt_hertz_%d" % ranks
    s = solve(tag, ["-options_file", opts("hertz_adapt"), "-contact_monitor", "0", "-output_name", "sol"], ranks=ranks)
    res[ranks] = s
    steps = s["adapt"]
    print("  %d rank(s): " % ranks + ", ".join("%d dofs %.2e (%d steps)" % (a["dofs"], a["pressure_l2_rel"], a["iterations"]) for a in steps))
    check(s["dofs"] <= 50000 and s["pressure_l2_rel"] <= 1.5e-3, "Hertz adaptive, %d rank(s): %d dofs, pressure error %.3e after %d meshes" % (ranks, s["dofs"], s["pressure_l2_rel"], len(steps)))
    check(all(a["iterations"] <= 3 for a in steps[1:]), "Hertz adaptive, %d rank(s): active-set steps per adapted mesh %s (<= 3 after the first)" % (ranks, [a["iterations"] for a in steps]))
    check(all(steps[k + 1]["error_estimate"] < steps[k]["error_estimate"] for k in range(len(steps) - 1)), "Hertz adaptive: the estimate falls from mesh to mesh %s" % ["%.2e" % a["error_estimate"] for a in steps])
    check(steps[-1]["dofs"] == s["dofs"] and all(a["seconds"] > 0 for a in steps), "Hertz adaptive: the adapt list ends with the final mesh")
check([a["dofs"] for a in res[1]["adapt"]] == [a["dofs"] for a in res[2]["adapt"]], "Hertz adaptive: the same meshes on 1 and 2 ranks (%s)" % [a["dofs"] for a in res[1]["adapt"]])
d = abs(res[1]["pressure_l2_rel"] - res[2]["pressure_l2_rel"]) / res[1]["pressure_l2_rel"]
check(d < 1e-8, "Hertz adaptive: the same pressure error on 1 and 2 ranks (%.1e)" % d)

# ---------------------------------------------------------------- 2. where the cells go
cen, h, cf = cells_and_sizes(os.path.join(workdir("adapt_hertz_1"), "sol.h5"))
small = np.argsort(h)[:100]
r = np.hypot(cen[small, 0] - A_HERTZ, cen[small, 1])
# (the refinement is floored at 2e-3 of the zone's length, so the smallest cells
# line the zone up to its edge, not just the edge; they are the mortar side's,
# 1.3 times finer than the non-mortar side's wherever the two touch, so spread
# over the zone: their median distance from the edge point about a/2)
check(np.median(r) < 0.6 * A_HERTZ and r.max() < A_HERTZ, "Hertz: the 100 smallest cells line the contact zone up to its edge (a, 0): median distance %.4f, all within %.4f of it (a = %.4f)" % (np.median(r), r.max(), A_HERTZ))
far = np.hypot(cen[:, 0], cen[:, 1]) > 1
check(np.median(h[far]) > 50 * np.median(h[small]), "Hertz: cells far from the contact stay coarse (median h %.3f against %.5f at the edge)" % (np.median(h[far]), np.median(h[small])))

s = solve("adapt_s1", ["-options_file", opts("seed_patch_adapt"), "-adapt_max_steps", "4", "-contact_monitor", "0", "-output_name", "sol"])
cen, h, cf = cells_and_sizes(os.path.join(workdir("adapt_s1"), "sol.h5"))
small = np.argsort(h)[:20]
corner = np.minimum(np.hypot(cen[small, 0] - 0.25, cen[small, 1] - 0.5), np.hypot(cen[small, 0] - 0.75, cen[small, 1] - 0.5))
check(np.percentile(corner, 90) < 0.03, "S1: 90%% of the 20 smallest cells lie within 0.03 of the two corners (%.4f; the others at the lower body's fixed corners)" % np.percentile(corner, 90))
left, right = (corner < 0.03) & (cen[small, 0] < 0.5), (corner < 0.03) & (cen[small, 0] > 0.5)
check(left.any() and right.any(), "S1: both corners are refined (%d left, %d right of the 20 smallest)" % (left.sum(), right.sum()))
check(s["adapt"][-1]["error_estimate"] < 0.2 * s["adapt"][0]["error_estimate"], "S1: the estimate falls %.2e -> %.2e over %d meshes" % (s["adapt"][0]["error_estimate"], s["adapt"][-1]["error_estimate"], len(s["adapt"])))

# ---------------------------------------------------------------- 4. bad input
bad = [("-adapt without -geo", ["-options_file", opts("hertz"), "-adapt"], "-geo"),
       ("a missing .geo", ["-options_file", opts("hertz_adapt"), "-geo", "nosuch.geo"], "nosuch.geo"),
       ("-geo_setnumber without =", ["-options_file", opts("hertz_adapt"), "-geo_setnumber", "level"], "-geo_setnumber"),
       ("-adapt_target 2", ["-options_file", opts("hertz_adapt"), "-adapt_target", "2"], "-adapt_target")]
for what, args, name in bad:
    rc, out, err = run(args + ["-output_dir", workdir("adapt_bad")], check=False)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    check(rc == 1 and len(lines) == 1 and name in lines[0], "%s: one line naming %s: %s" % (what, name, lines[-1] if lines else "(none)"))
