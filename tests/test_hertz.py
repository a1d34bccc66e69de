"""S3, Hertz: levels 0-3 of the graded mesh (level 4 and 5 are in the benchmark),
mortar (dual multipliers, options/hertz.opts) and NTS. Printed per level:
dofs, active-set steps, computed half-width against a, peak pressure against p0,
relative L2 error of the pressure on [0, 1.5a]. Asserted: the half-width is
within one node spacing of a; the peak within 2% of p0 (mortar); the error falls
from level 0 to level 3 by at least 2x (mortar); mortar's error is below NTS's
at every level; the active set settles in at most 12 steps."""
from m2d import check, mesh, opts, solve

rows = {}
print("%5s %8s %7s %6s %10s %10s %9s %10s %10s" % ("level", "dofs", "method", "steps", "a_h", "a", "spacing", "peak/p0", "L2 error"))
for level in range(4):
    for method in ("mortar", "nts"):
        s = solve("hertz_%d_%s" % (level, method), ["-options_file", opts("hertz"), "-mesh", mesh("hertz_%d" % level), "-contact_method", method, "-output_vtu", "0", "-contact_monitor", "0"])
        rows[(level, method)] = s
        print("%5d %8d %7s %6d %10.5f %10.5f %9.5f %10.5f %10.3e" % (level, s["dofs"], method, s["iterations"], s["half_width"], s["hertz_a"], s["half_width_spacing"], s["peak_pressure"] / s["hertz_p0"], s["pressure_l2_rel"]))
for level in range(4):
    m, n = rows[(level, "mortar")], rows[(level, "nts")]
    for name, s in (("mortar", m), ("nts", n)):
        check(abs(s["half_width"] - s["hertz_a"]) <= s["half_width_spacing"], "level %d %s: |a_h - a| = %.2e within one spacing %.2e" % (level, name, abs(s["half_width"] - s["hertz_a"]), s["half_width_spacing"]))
        check(s["iterations"] <= 12, "level %d %s: %d active-set steps" % (level, name, s["iterations"]))
        check(abs(s["contact_force_y"] / 0.43 - 1) < 1e-10, "level %d %s: vertical contact force on the cylinder = P/2 = 0.43 (%.12f)" % (level, name, s["contact_force_y"]))
    check(abs(m["peak_pressure"] / m["hertz_p0"] - 1) < 0.02, "level %d mortar: peak pressure within 2%% of p0 (%.4f)" % (level, m["peak_pressure"] / m["hertz_p0"]))
    check(m["pressure_l2_rel"] < n["pressure_l2_rel"], "level %d: mortar error %.3e below NTS %.3e at %d dofs" % (level, m["pressure_l2_rel"], n["pressure_l2_rel"], m["dofs"]))
check(rows[(3, "mortar")]["pressure_l2_rel"] < 0.5 * rows[(0, "mortar")]["pressure_l2_rel"], "mortar error falls with refinement: %.3e -> %.3e" % (rows[(0, "mortar")]["pressure_l2_rel"], rows[(3, "mortar")]["pressure_l2_rel"]))
