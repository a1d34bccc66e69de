"""Uniform compression of one block: sigma_yy = -p in every cell to 1e-12
relative, sigma_xx = sigma_xy = 0, in plane strain and plane stress, on meshes
of 4x4 and 16x16 cells."""
from m2d import check, mesh, opts, solve

for n in (4, 16):
    for plane in ("strain", "stress"):
        s = solve("uniform_%d_%s" % (n, plane), ["-options_file", opts("block"), "-mesh", mesh("block_%d" % n), "-plane", plane])
        e = s["error"]
        msg = "block %dx%d plane %s: max|syy+p|/p = %.2e, max|sxx|/p = %.2e, max|sxy|/p = %.2e" % (n, n, plane, e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"])
        check(e["sigma_yy_max_rel"] < 1e-12 and e["sigma_xx_max_rel"] < 1e-12 and e["sigma_xy_max_rel"] < 1e-12, msg)
        check(s["dofs"] == 2 * (n + 1) ** 2 and s["cells"] == n * n, "dofs %d, cells %d" % (s["dofs"], s["cells"]))
