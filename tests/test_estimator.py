"""The error estimator (estimator.h) on the scenes, through tests/estimator_main
(a copy of main.c with the estimator call):
  * MMS: effectivity (estimate / exact energy-norm error) in [0.5, 3] on
    4x4 ... 64x64, and within 5% of 1 at 64x64 (SPR is asymptotically exact on
    these uniform meshes);
  * S2: mortar reproduces the exact field, the estimate is round-off; NTS's
    effectivity (exact uniform stress) in [0.5, 3];
  * Hertz levels 0 and 1: effectivity against the energy-norm error relative
    to level 3's solution in [0.5, 3]; near the contact the largest indicator
    sits at the zone edge (a, 0), not at the centre;
  * S1: the two largest indicators are the cells at the two corners of the
    upper body on the lower one (x = 0.25, 0.75, y = 0.5), mortar and NTS;
  * 1 and 2 ranks give the same indicators (cells sorted by centroid)."""
import numpy as np

import estimator_study as es
from m2d import check, mesh, opts, sorted_fields

MMS = ["-bodies", "block", "-block_E", "1e3", "-block_nu", "0.3", "-dirichlet", "bottom:xy,right:xy,top:xy,left:xy", "-exact", "mms"]

print("MMS: effectivity")
eff = []
for n in (4, 8, 16, 32, 64):
    s, _ = es.run("test_est_mms_%d" % n, MMS + ["-mesh", mesh("block_%d" % n)])
    eff.append(s["estimator"]["effectivity"])
    print("  %2dx%-2d estimate %.4e, true %.4e (relative), effectivity %.4f" % (n, n, s["error_estimate"], s["estimator"]["true_error_rel"], eff[-1]))
check(all(0.5 <= e <= 3 for e in eff), "MMS effectivity in [0.5, 3] at every level")
check(abs(eff[-1] - 1) < 0.05 and abs(eff[-1] - 1) < abs(eff[0] - 1), "MMS effectivity tends to 1 (%.4f at 64x64)" % eff[-1])

s, _ = es.run("test_est_s2_mortar", ["-options_file", opts("patch_uniform")])
check(s["error_estimate"] < 1e-10, "S2 mortar: exact field, estimate %.1e (round-off)" % s["error_estimate"])
s, _ = es.run("test_est_s2_nts", ["-options_file", opts("patch_uniform"), "-contact_method", "nts"])
e = s["estimator"]["effectivity"]
check(s["error_estimate"] > 1e-3 and 0.5 <= e <= 3, "S2 NTS: estimate %.3e, effectivity %.3f in [0.5, 3]" % (s["error_estimate"], e))

D = es.plane_strain_D(200.0, 0.3)
sref, href = es.run("test_est_hertz_3", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_3")])
for lvl in (0, 1):
    s, h5 = es.run("test_est_hertz_%d" % lvl, ["-options_file", opts("hertz"), "-mesh", mesh("hertz_%d" % lvl)])
    err, _ = es.reference_error(h5, href, D, sub=2 ** (3 - lvl))
    e = s["error_estimate"] / (err / sref["estimator"]["energy_norm"])
    check(0.5 <= e <= 3, "Hertz level %d: estimate %.4e, error against level 3 %.4e, effectivity %.3f in [0.5, 3] (pressure error %.3e)" % (lvl, s["error_estimate"], err / sref["estimator"]["energy_norm"], e, s["pressure_l2_rel"]))
    xy, cells, _, cf = es.m2d.read_h5(h5)
    cen = xy[cells].mean(axis=1)
    near = np.where(np.hypot(cen[:, 0], cen[:, 1]) < 0.5)[0]
    top = near[np.argmax(cf["error_indicator"][near])]
    d = np.hypot(cen[top, 0] - s["hertz_a"], cen[top, 1])
    check(d < 3 * s["half_width_spacing"], "Hertz level %d: largest indicator near the contact at (%.4f, %.4f), %.4f from the zone edge (a, 0) (node spacing %.4f)" % (lvl, cen[top, 0], cen[top, 1], d, s["half_width_spacing"]))

for meth in ("mortar", "nts"):
    s, h5 = es.run("test_est_s1_" + meth, ["-options_file", opts("seed_patch"), "-contact_method", meth])
    cen, eta = es.top_cells(h5, k=2)
    corners = np.array([[0.25, 0.5], [0.75, 0.5]])
    dist = [np.hypot(*(corners - c).T).min() for c in cen]
    check(max(dist) < 0.08 and abs(cen[0, 0] - cen[1, 0]) > 0.4, "S1 %s: the two largest indicators at (%.3f, %.3f) and (%.3f, %.3f), the corners" % (meth, cen[0, 0], cen[0, 1], cen[1, 0], cen[1, 1]))

for name, args in (("mms", MMS + ["-mesh", mesh("block_32")]), ("s1", ["-options_file", opts("seed_patch")]), ("hertz", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1")])):
    f = {}
    for n in (1, 2):
        s, h5 = es.run("test_est_par_%s_%d" % (name, n), args, ranks=n)
        f[n] = (s["error_estimate"], sorted_fields(h5)[1])
    diff = max(np.abs(f[1][1][k] - f[2][1][k]).max() / np.abs(f[1][1][k]).max() for k in ("error_indicator", "error_indicator_volume", "size_factor"))
    check(diff < 1e-9 and abs(f[1][0] - f[2][0]) < 1e-9 * f[1][0], "%s: 1 and 2 ranks give the same indicators and size field (%.1e)" % (name, diff))
