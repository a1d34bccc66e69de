"""Coulomb friction (docs/friction.md; docs/results.md, S7) against exact answers.

1. The frictional patch test (options/friction_patch.opts: S2's non-matching
   blocks pressed by p and sheared by tau, every face loaded with the traction
   of the uniform state): with MU > tau/p the upper body sticks and mortar
   (standard and dual multipliers, either side non-mortar, the interface
   straight or turned by 30 degrees, the condensed and the full path, 1 and 2
   ranks) gives sigma_yy = -p, sigma_xy = tau, sigma_xx = 0 to 1e-12; NTS
   does not. Full slip (the top moved along the interface, nu = 0): every
   active node carries t = MU p, the tangential force is MU x the normal force
   to 1e-12, the uniform state holds; also with the moduli 1e4 apart and with
   MU = 1 and 5.
2. A body held by friction alone under an inclined load: held inside the
   cone, one line naming the body and the two forces outside it.
3. A load history: frictionless Hertz reached in 3 steps ends on the one-step
   answer; the summary's per-step table, the CSV's step column, the HDF5's
   /steps and the XDMF's temporal collection.
4. Cattaneo-Mindlin (options/cattaneo.opts) on levels 0-2: the stick zone
   within 3% of c and the shear traction's even part within 3 times the
   pressure's error at level 2, the shear error falling with the level,
   Coulomb's law at every node of the CSV (slip: |t| = MU p and the slip
   against t; stick: |t| <= MU p), the same stick/slip sets on 1 and 2 ranks;
   the shear unloaded to 0 (slip annuli of Mindlin's reversal) and reversed.
5. Bad input: MU < 0, NaN, inf, a word; friction on a tied pair; the
   iterative path and the VI solver with friction: one line each, exit 1."""
import math
import os

import numpy as np
from m2d import check, csv_columns, mesh, opts, read_json, refusal_problems, run, solve, workdir

P, TAU = 1e6, 1e5
PATCH = ["-options_file", opts("friction_patch"), "-output_vtu", "0", "-contact_monitor", "0"]
FLIP = ["-contact_nonmortar", "lower_top", "-contact_mortar", "upper_bottom"]


def patch_error(s):
    e = s["error"]
    return max(e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"])


def rotated_patch(angle, tau):
    """the stick patch on the interface turned by `angle` degrees: every face's
    traction of the uniform state (sigma_y'y' = -p, sigma_x'y' = tau)"""
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    x, y = (c, s), (-s, c)
    top = (tau * x[0], tau * x[1])  # the pressure p is -pressure upper_top (along -y')
    left, right, bottom = (-tau * y[0], -tau * y[1]), (tau * y[0], tau * y[1]), (-tau * x[0], -tau * x[1])
    tr = "upper_top:%r:%r,upper_left:%r:%r,upper_right:%r:%r,lower_left:%r:%r,lower_right:%r:%r,lower_bottom:%r:%r" % (top + left + right + left + right + bottom)
    return ["-mesh", mesh("patch_incl30"), "-traction", tr, "-dirichlet", "lower_bottom:n,lower_origin:xy", "-exact_angle", str(angle)]


# ---------------------------------------------------------------- 1. stick
for angle in (0, 30):
    geo = [] if angle == 0 else rotated_patch(angle, TAU)
    for basis in ("standard", "dual"):
        for side, pair in (("upper", []), ("lower", FLIP)):
            for path in ("condensed", "full"):
                for ranks in (1, 2):
                    if path == "full" and basis == "dual": continue  # the full path with standard multipliers
                    s = solve("friction_stick", PATCH + geo + pair + ["-mortar_basis", basis, "-kkt_path", path], ranks)
                    check(patch_error(s) < 1e-12 and s["slip_nodes"] == 0 and s["stick_nodes"] == s["active_nodes"] > 0,
                          "stick patch, %d deg, %s, %s non-mortar, %s, %d rank(s): uniform state to %.1e, %d nodes stick" % (angle, basis, side, path, ranks, patch_error(s), s["stick_nodes"]))
s = solve("friction_stick_nts", PATCH + ["-contact_method", "nts"])
check(patch_error(s) > 1e-3, "stick patch, node-to-segment: fails it (%.2e)" % patch_error(s))

# ---------------------------------------------------------------- 1. slip
def slip_args(mu, upper_E=1e9, shift=1e-3):
    t = mu * P
    return PATCH + ["-lower_nu", "0", "-upper_nu", "0", "-upper_E", repr(upper_E), "-contact_friction", repr(mu), "-exact_tau", repr(t),
                    "-dirichlet", "lower_bottom:y,lower_origin:x,upper_top:x:%r" % shift,
                    "-traction", "lower_bottom:%r:0,lower_left:0:%r,lower_right:0:%r,upper_left:0:%r,upper_right:0:%r" % (-t, -t, t, -t, t)]


# (moduli 1e4 apart: round-off grows with the ratio, 1e-12 of it; MU 1 and 5:
# the state's shear is MU p and the slipping rows carry MU, so the round-off
# measured against p grows with MU: 7.8e-13 at MU 5 with OpenBLAS's SkylakeX
# kernels, 4.8e-12 with its Prescott ones; 1e-11, far below any discretisation error)
for name, args, tol in (("MU 0.2", slip_args(0.2), 1e-12), ("MU 0.2, upper E 1e4 x lower", slip_args(0.2, 1e13), 1e-8), ("MU 1", slip_args(1.0, shift=0.01), 1e-11), ("MU 5", slip_args(5.0, shift=0.05), 1e-11)):
    for path, pair in (("condensed", []), ("full", []), ("condensed", FLIP)):
        for ranks in (1, 2):
            if name != "MU 0.2" and (path == "full" or ranks == 2 or pair): continue
            d = workdir("friction_slip")
            s = solve("friction_slip", args + pair + ["-kkt_path", path], ranks)
            c = csv_columns(os.path.join(d, "friction_patch_contact.csv"))
            on = c["active"] == 1
            mu = s["mu"]
            worst = np.abs(np.abs(c["traction_t"][on]) - mu * c["pressure"][on]).max() / (mu * P)
            ratio = abs(s["tangential_force"]) / (mu * s["contact_force"]) - 1
            check(s["stick_nodes"] == 0 and s["slip_nodes"] == s["active_nodes"] > 0 and worst < tol and abs(ratio) < tol and patch_error(s) < tol and s["coulomb"] < tol,
                  "full slip, %s, %s%s, %d rank(s): |t| = MU p at every node to %.1e, tangential force / (MU x normal) - 1 = %.1e, uniform state to %.1e (tolerance %.0e)" % (name, path, ", lower non-mortar" if pair else "", ranks, worst, ratio, patch_error(s), tol))

# the interface turned by 30 degrees: the top moved along -x' (its tangent
# t = (-n_y, n_x)), friction on the upper body along +x': sigma_x'y' = -MU p
for path in ("condensed", "full"):
    for side, pair in (("upper", []), ("lower", FLIP)):
        for ranks in (1, 2):
            mu, tau = 0.2, -0.2 * P
            geo = rotated_patch(30, tau)
            tr = geo[3].split(",", 1)[1]  # no traction on the top: its support carries the friction
            args = PATCH + ["-mesh", geo[1], "-traction", tr, "-dirichlet", "lower_bottom:n,lower_origin:xy,upper_top:t:1e-3", "-exact_angle", "30",
                            "-lower_nu", "0", "-upper_nu", "0", "-contact_friction", repr(mu), "-exact_tau", repr(tau), "-kkt_path", path] + pair
            d = workdir("friction_slip30")
            s = solve("friction_slip30", args, ranks)
            c = csv_columns(os.path.join(d, "friction_patch_contact.csv"))
            on = c["active"] == 1
            worst = np.abs(np.abs(c["traction_t"][on]) - mu * c["pressure"][on]).max() / (mu * P)
            ratio = abs(s["tangential_force"]) / (mu * s["contact_force"]) - 1
            check(s["slip_nodes"] == s["active_nodes"] > 0 and worst < 1e-12 and abs(ratio) < 1e-12 and patch_error(s) < 1e-12,
                  "full slip, 30 deg, %s, %s non-mortar, %d rank(s): |t| = MU p to %.1e, force ratio - 1 = %.1e, uniform state to %.1e" % (path, side, ranks, worst, ratio, patch_error(s)))

# ---------------------------------------------------------------- 2. held by friction alone
for T, held in ((2.5e5, True), (3.5e5, False)):
    args = ["-options_file", opts("friction_patch"), "-output_vtu", "0", "-exact", "none", "-traction", "upper_top:%r:0" % T]
    d = workdir("friction_cone")
    summary = os.path.join(d, "summary.json")
    rc, out, err = run(args + ["-output_dir", d, "-summary", summary], check=False)
    lines = [l for l in err.splitlines() if l.strip()]
    if held:
        s = read_json(summary)
        check(rc == 0 and s["stick_nodes"] > 0 and abs(s["tangential_force"] / T - 1) < 1e-12,
              "inclined load inside the friction cone (T/p = %.2f < 0.3): held by friction alone (%d nodes stick, %d slip, tangential force = T)" % (T / P, s["stick_nodes"], s["slip_nodes"]))
    else:
        line, problems = refusal_problems(rc, lines, ["body 'upper' slides", "tangential load 350000", "MU x normal force 0.3 x 1e+06", "upper_bottom:lower_top"])
        check(not problems, "inclined load outside the cone (T/p = %.2f > 0.3): one line: %s %s" % (T / P, line, problems))

# ---------------------------------------------------------------- 3. a load history
one = solve("friction_hertz_1", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1"), "-contact_monitor", "0"])
d = workdir("friction_hertz_3")
three = solve("friction_hertz_3", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1"), "-contact_monitor", "0", "-load_steps", "3"])
rel = max(abs(three[k] / one[k] - 1) for k in ("pressure_l2_rel", "peak_pressure", "contact_force", "contact_force_x"))
steps = three["load_steps"]
check(rel < 1e-10 and three["active_nodes"] == one["active_nodes"] and len(steps) == 3 and [x["time"] for x in steps] == [1 / 3, 2 / 3, 1.0]
      and abs(steps[0]["normal_force"][0] - one["contact_force"] / 3) < 0.05 * one["contact_force"],
      "frictionless Hertz in 3 steps ends on the one-step answer (%.1e); the summary's table has 3 steps (normal force %.4g, %.4g, %.4g)" % (rel, *[x["normal_force"][0] for x in steps]))
c = csv_columns(os.path.join(d, "hertz_contact.csv"))
check("step" in c and sorted(set(c["step"])) == [1, 2, 3], "the contact CSV has a step column with the 3 steps")
import h5py  # noqa: E402
with h5py.File(os.path.join(d, "hertz.h5"), "r") as f:
    ok = sorted(f["steps"].keys()) == ["1", "2"] and "displacement" in f["steps/1/vertex_fields"] and "contact_pressure" in f["steps/2/vertex_fields"]
xmf = open(os.path.join(d, "hertz.xmf")).read()
check(ok and 'CollectionType="Temporal"' in xmf and xmf.count("<Time Value=") == 3, "the .h5 holds the earlier steps in /steps, the .xmf is a temporal collection of the 3 steps")

# ---------------------------------------------------------------- 4. Cattaneo-Mindlin
res = {}
for level in (0, 1, 2):
    d = workdir("cattaneo_%d" % level)
    s = solve("cattaneo_%d" % level, ["-options_file", opts("cattaneo"), "-mesh", mesh("cattaneo_%d" % level), "-contact_monitor", "0", "-output_vtu", "0"])
    res[level] = s
    print("level %d: %6d dofs, pressure %.3e, c %.5f (exact %.5f, %.2f%%), shear even %.3e, odd %.3e, %d active-set steps" % (
        level, s["dofs"], s["pressure_l2_rel"], s["stick_half_width"], s["stick_half_width_exact"], 100 * abs(s["stick_half_width"] / s["stick_half_width_exact"] - 1), s["shear_l2_rel"], s["shear_odd_rel"], s["iterations"]))
    c = csv_columns(os.path.join(d, "cattaneo_contact.csv"))
    last = c["step"] == c["step"].max()
    t, p, sl, st, ds = c["traction_t"][last], c["pressure"][last], c["slip_increment"][last], c["status"][last], c["slip"][last]
    mu, scale = s["mu"], s["mu"] * s["hertz_p0"]
    stick, slip = st == 1, st == 2
    viol = max((np.abs(t[stick]) - mu * p[stick]).max() if stick.any() else 0, np.abs(np.abs(t[slip]) - mu * p[slip]).max() if slip.any() else 0) / scale
    against = (t[slip] * sl[slip]).max() if slip.any() else 0
    check(viol < 1e-8 and against <= 1e-12 * scale and slip.any() and stick.any(),
          "level %d: Coulomb at every node of the CSV: stick |t| <= MU p, slip |t| = MU p (%.1e), slip against t (max t s %.1e)" % (level, viol, against))
s0, s2 = res[0], res[2]
check(abs(s2["stick_half_width"] / s2["stick_half_width_exact"] - 1) < 0.03 and s2["shear_l2_rel"] <= 3 * s2["pressure_l2_rel"],
      "level 2: stick zone within 3%% of c, shear error %.2e <= 3 x the pressure's %.2e" % (s2["shear_l2_rel"], s2["pressure_l2_rel"]))
check(s2["shear_l2_rel"] < s0["shear_l2_rel"] and s2["pressure_l2_rel"] < s0["pressure_l2_rel"] and s2["pressure_even_l2_rel"] < s0["pressure_even_l2_rel"],
      "the shear and pressure errors (and the pressure's even part's) fall from level 0 to 2")
# Hertz's p is even: on the same symmetric samples the pressure's error splits into its even part's and its odd part
split = max(abs(r["pressure_l2_rel"] ** 2 - r["pressure_even_l2_rel"] ** 2 - r["pressure_odd_rel"] ** 2) / r["pressure_l2_rel"] ** 2 for r in res.values())
check(split < 1e-9, "pressure_l2_rel^2 = pressure_even_l2_rel^2 + pressure_odd_rel^2 on levels 0-2 (to %.1e)" % split)
two = {}
for ranks in (1, 2):
    d = workdir("cattaneo_ranks_%d" % ranks)
    solve("cattaneo_ranks_%d" % ranks, ["-options_file", opts("cattaneo"), "-mesh", mesh("cattaneo_1"), "-contact_monitor", "0", "-output", "csv,summary"], ranks)
    c = csv_columns(os.path.join(d, "cattaneo_contact.csv"))
    two[ranks] = c
same = np.array_equal(two[1]["status"], two[2]["status"]) and np.abs(two[1]["traction_t"] - two[2]["traction_t"]).max() < 1e-9 * np.abs(two[1]["traction_t"]).max()
check(same, "1 and 2 ranks: the same stick/slip sets at every step, the same tractions to 1e-9")
# unloading the shear to 0 and reversing it (stages 3 and 4)
s = solve("cattaneo_reverse", ["-options_file", opts("cattaneo"), "-mesh", mesh("cattaneo_1"), "-contact_monitor", "0", "-output", "summary",
                               "-load_stages", "4", "-stage3_dirichlet", "cylinder_top:x:-0.00445", "-stage4_dirichlet", "cylinder_top:x:-0.00445"])
st = s["load_steps"]
q2, q3, q4 = st[4]["tangential_force"][0], st[5]["tangential_force"][0], st[6]["tangential_force"][0]
check(abs(q3) < 0.2 * abs(q2) and st[5]["slip_nodes"][0] > 0 and abs(q4 + q2) < 0.1 * abs(q2) and st[6]["slip_nodes"][0] > 0,
      "shear unloaded (Q %.4f -> %.4f, %d nodes slip back: the annuli of Mindlin's reversal) and reversed (%.4f)" % (q2, q3, st[5]["slip_nodes"][0], q4))

# ---------------------------------------------------------------- 5. bad input
bad = [("-contact_friction -0.1", ["-contact_friction", "-0.1"], ["-contact_friction", "must be >= 0"]),
       ("-contact_friction nan", ["-contact_friction", "nan"], ["-contact_friction"]),
       ("-contact_friction inf", ["-contact_friction", "inf"], ["-contact_friction"]),
       ("-contact_friction abc", ["-contact_friction", "abc"], ["-contact_friction"]),
       ("a pair's MU -1", ["-contact_nonmortar", "", "-contact_mortar", "", "-contact_pairs", "upper_bottom:lower_top:dual:-1"], ["-contact_pairs", "must be >= 0"]),
       ("a pair's MU inf", ["-contact_nonmortar", "", "-contact_mortar", "", "-contact_pairs", "upper_bottom:lower_top:inf"], ["-contact_pairs", "inf"]),
       ("friction on a tied pair", ["-contact_unilateral", "0"], ["tied pair", "-contact_unilateral"]),
       ("the iterative path", ["-kkt_path", "iterative", "-mortar_basis", "dual"], ["-kkt_path iterative", "condensed", "full"]),
       ("the VI solver", ["-snes_type", "vinewtonrsls", "-kkt_path", "full"], ["vinewtonrsls", "newtonls"])]
for what, extra, culprits in bad:
    rc, out, err = run(PATCH + extra + ["-output_dir", workdir("friction_bad")], check=False)
    line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()], culprits)
    check(not problems, "%s: one line: %s %s" % (what, line, problems))
