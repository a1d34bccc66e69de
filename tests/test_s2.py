"""S2, the non-matching contact patch test: mortar reproduces the uniform
stress sigma_yy = -p, sigma_xx = sigma_xy = 0 to round-off (below 1e-10 of p)
in both bodies, with either body as non-mortar and interface ratios 7:10, 3:10
and 10:31; node-to-segment on the same meshes is printed and must be visibly
worse (it fails the patch test, as the seed report says)."""
from m2d import check, mesh, opts, solve

meshes = {"7:10": "patch_uniform", "3:10": "patch_3_10", "10:31": "patch_10_31"}
sides = {"upper non-mortar": ["-contact_nonmortar", "upper_bottom", "-contact_mortar", "lower_top"],
         "lower non-mortar": ["-contact_nonmortar", "lower_top", "-contact_mortar", "upper_bottom"]}
print("%-8s %-18s %-7s %12s %12s %12s %14s" % ("ratio", "side", "method", "syy+p", "sxx", "sxy", "force/p-1"))
for ratio, m in meshes.items():
    for side, pair in sides.items():
        err = {}
        for method in ("mortar", "nts"):
            s = solve("s2_%s_%s_%s" % (m, side.split()[0], method), ["-options_file", opts("patch_uniform"), "-mesh", mesh(m), "-contact_method", method, "-output_vtu", "0"] + pair)
            e = s["error"]
            err[method] = max(e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"])
            print("%-8s %-18s %-7s %12.3e %12.3e %12.3e %14.3e" % (ratio, side, method, e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"], s["contact_force"] / 1e6 - 1))
            check(abs(s["contact_force"] / 1e6 - 1) < 1e-12, "%s %s %s: total contact force = p x 1 m" % (ratio, side, method))
        check(err["mortar"] < 1e-10, "%s %s: mortar passes the patch test (%.2e)" % (ratio, side, err["mortar"]))
        check(err["nts"] > 1e-3, "%s %s: NTS fails it (%.2e)" % (ratio, side, err["nts"]))
