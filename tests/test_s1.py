"""S1, the seed report's scene: equilibrium - the total contact force equals
p x 0.5 to 1e-12 relative for mortar and NTS, at 1x and 2x; every non-mortar
node is in contact (gap zero to round-off under the equality constraints)."""
import numpy as np
from m2d import check, mesh, opts, read_h5, solve, workdir

for m in ("seed_patch", "seed_patch_2"):
    for method in ("mortar", "nts"):
        tag = "s1_%s_%s" % (m, method)
        s = solve(tag, ["-options_file", opts("seed_patch"), "-mesh", mesh(m), "-contact_method", method, "-output_name", "sol"])
        f = s["contact_force"] / (1e6 * 0.5) - 1
        fy = s["contact_force_y"] / (1e6 * 0.5) - 1
        check(abs(f) < 1e-12 and abs(fy) < 1e-12 and abs(s["contact_force_x"]) < 1e-12 * 5e5, "%s %s: contact force / (p x 0.5) - 1 = %.1e (y-force %.1e)" % (m, method, f, fy))
        xy, cells, vf, cf = read_h5(workdir(tag) + "/sol.h5")
        nm = ~np.isnan(vf["active"])  # the non-mortar surface
        gap = vf["gap"][nm & ~np.isnan(vf["gap"])]
        gm = vf["gap"][~nm & ~np.isnan(vf["gap"])]  # the mortar surface's, interpolated
        check(len(gap) == s["contact_nodes"] and np.abs(gap).max() < 1e-12 and len(gm) > 0 and np.abs(gm).max() < 1e-12,
              "%s %s: %d contact nodes, max |gap| %.1e m (mortar side %.1e m)" % (m, method, len(gap), np.abs(gap).max(), np.abs(gm).max()))
