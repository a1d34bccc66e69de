"""Unilateral contact through SNES:
 - S2 with an initial gap 0.01 and the upper top pushed down by delta: below the
   closing value the interface stays open (every node inactive, pressure 0, gap
   = 0.01 - delta, no stress); above it the exact uniform answer
   sigma_yy = -E (delta - 0.01) / ((1 - nu^2) H), H = 1, is reproduced to 1e-10;
 - S2 with an eccentric load p(x) = -p + 4 p x on the upper top: part of the
   interface separates; node by node, pressure 0 and gap > 0 on the separated
   part, pressure > 0 and gap 0 on the rest;
 - SNESVINEWTONRSLS gives the same answers as the semismooth Newton method;
 - a maximum step count ends with a clear message and a nonzero exit."""
import numpy as np
from m2d import check, mesh, opts, read_csv, read_h5, run, solve, workdir

E, nu, g0 = 1e9, 0.3, 0.01
base = ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_gap"), "-pressure", "", "-output_vtu", "0", "-output_name", "sol"]
sup = "lower_bottom:y,lower_origin:x,lower_left:x,upper_left:x"


def contact_csv(tag, name="sol"):
    return read_csv(workdir(tag) + "/%s_contact.csv" % name)


for solver in (["-snes_type", "newtonls"], ["-snes_type", "vinewtonrsls"]):
    sname = solver[1]
    # below the closing displacement
    delta = 0.005
    s = solve("gap_open_" + sname, base + solver + ["-dirichlet", sup + ",upper_top:y:%g" % -delta, "-exact", "uniform", "-exact_p", "1"])
    rows = contact_csv("gap_open_" + sname)
    check(s["active_nodes"] == 0 and all(r["pressure"] == 0 and r["active"] == 0 for r in rows), "%s open: no active node, zero pressure (%d steps)" % (sname, s["iterations"]))
    gerr = max(abs(r["gap"] - (g0 - delta)) for r in rows)
    check(gerr < 1e-12, "%s open: gap = %.4f - %.4f at every node (error %.1e)" % (sname, g0, delta, gerr))
    _, _, _, cf = read_h5(workdir("gap_open_" + sname) + "/sol.h5")
    smax = max(np.abs(cf[k]).max() for k in ("sigma_x", "sigma_y", "sigma_xy"))
    check(smax < 1e-10 * E * delta, "%s open: no stress (max |sigma| = %.1e Pa, E delta = %.1e Pa)" % (sname, smax, E * delta))
    # above it
    delta = 0.02
    p = E * (delta - g0) / (1 - nu * nu)
    s = solve("gap_closed_" + sname, base + solver + ["-dirichlet", sup + ",upper_top:y:%g" % -delta, "-exact", "uniform", "-exact_p", repr(p)])
    e = s["error"]
    check(max(e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"]) < 1e-10, "%s closed: sigma_yy = -%.6e to %.1e relative, %d active, %d steps" % (sname, p, e["sigma_yy_max_rel"], s["active_nodes"], s["iterations"]))
    check(s["active_nodes"] == s["contact_nodes"], "%s closed: every node active" % sname)

# eccentric load: the left part of the interface opens
res = {}
for sname in ("newtonls", "vinewtonrsls"):
    tag = "eccentric_" + sname
    s = solve(tag, ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_10_31"), "-pressure", "upper_top:-1e6:4e6:0", "-exact", "none", "-snes_type", sname, "-output_vtu", "0", "-output_name", "sol"])
    rows = contact_csv(tag)
    res[sname] = rows
    opened = [r for r in rows if r["active"] == 0]
    closed = [r for r in rows if r["active"] == 1]
    check(len(opened) > 0 and len(closed) > 0, "%s eccentric: %d nodes open, %d closed, %d steps" % (sname, len(opened), len(closed), s["iterations"]))
    check(all(r["pressure"] == 0 and r["gap"] > 1e-7 for r in opened), "%s eccentric: pressure 0 and gap > 0 at every open node (min gap %.2e)" % (sname, min(r["gap"] for r in opened)))
    check(all(r["pressure"] > 1e3 and abs(r["gap"]) < 1e-15 for r in closed), "%s eccentric: pressure > 0 and gap 0 at every closed node (min p %.3e, max |gap| %.1e)" % (sname, min(r["pressure"] for r in closed), max(abs(r["gap"]) for r in closed)))
    check(all(a["x"] < b["x"] for a in opened for b in closed), "%s eccentric: the open part is the left part" % sname)
    check(abs(s["contact_force"] / 1e6 - 1) < 1e-10, "%s eccentric: total force = resultant of the load" % sname)
pa = np.array([r["pressure"] for r in res["newtonls"]])
pb = np.array([r["pressure"] for r in res["vinewtonrsls"]])
check(np.abs(pa - pb).max() < 1e-8 * pa.max(), "eccentric: PDAS and VI pressures agree (%.1e)" % (np.abs(pa - pb).max() / pa.max()))

# Hertz: the cylinder is held only by the contact and its gap starts open but
# at one node; the VI solver starts from positive multipliers on the closest
# nodes (before: its first step fixed every multiplier at 0, the cylinder was
# free, and the run stopped with "held by nothing"). Same pressures as PDAS,
# 1 and 2 ranks.
hz = {}
for sname in ("newtonls", "vinewtonrsls"):
    for ranks in (1, 2):
        tag = "hertz1_%s_%d" % (sname, ranks)
        s = solve(tag, ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1"), "-snes_type", sname, "-output_vtu", "0", "-output_name", "sol", "-contact_monitor", "0"], ranks=ranks)
        hz[tag] = (s, np.array([r["pressure"] for r in contact_csv(tag)]))
ref, pref = hz["hertz1_newtonls_1"]
for tag, (s, p) in hz.items():
    check(s["active_nodes"] == ref["active_nodes"] and np.abs(p - pref).max() < 1e-8 * pref.max() and abs(s["pressure_l2_rel"] - ref["pressure_l2_rel"]) < 1e-8,
          "Hertz level 1, %s: %d active nodes, pressures within %.1e of PDAS on 1 rank (%d steps)" % (tag, s["active_nodes"], np.abs(p - pref).max() / pref.max(), s["iterations"]))

rc, out, err = run(["-options_file", opts("hertz"), "-mesh", mesh("hertz_1"), "-snes_max_it", "2", "-output_dir", workdir("maxit")], check=False)
check(rc == 1 and "-snes_max_it" in err and len(err.strip().splitlines()) == 1, "step limit: %s" % err.strip())
