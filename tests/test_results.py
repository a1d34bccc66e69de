"""An engineer's figures in the summary (pairs[k], body_results), against
exact answers.
- the stack (options/stack.opts: three blocks under a uniform pressure p,
  plane strain, x held on the left, y at the bottom): every pair touches in
  one zone from (0, y) to (1, y), length 1, cut by the surface's ends (no
  half-width), its peak pressure p at its first node along the surface
  (every node ties); every body's largest von Mises stress (cells and
  recovered nodes) is p sqrt(1 - nu + nu^2) to 1e-9 and its largest
  displacement |(eps_x x, eps_y y)| at its top right corner (1, y_top), with
  eps_x = nu (1 + nu) p / E, eps_y = -(1 - nu^2) p / E; on 1 and 2 ranks,
  the same points and the values to 1e-9;
- the indenter (options/indenter.opts, level 2, no -hertz): pair 1's
  half-width within one node spacing of Hertz's a, its peak within 1% of p0
  on the axis, pair 2 carrying pair 1's load; the largest von Mises stress
  of the block (nu 0.45) and of the indenter (nu 0.3) within 3% of Hertz's
  line contact (0.5224 p0 at 0.781 a and 0.5575 p0 at 0.704 a below the
  surface on the axis: the model tilts the pressure by up to a/R and the
  recovered stresses converge to 1.9% above it), on the axis, at the depth
  to 0.1 a (the maximum is flat in depth);
- -hertz on the indenter compares the curved pair 1 only (its pressure
  within 2e-2 of Hertz), -hertz_pairs picks pairs, -hertz_radius gives them
  their radii in the list's order (R1:R2: two cylinders);
- the files name the bodies: the VTU's field data body_names and the .h5's
  /body_names in the order of -bodies."""
import math
import os
import re

from m2d import Tally, mesh, opts, solve, workdir

T = Tally()


def close(a, b, tol):
    return abs(a - b) <= tol * max(abs(b), 1e-300)


# ---------- the stack: a uniform stress ----------
P, E, NU = 1e6, 1e9, 0.3
EX, EY = NU * (1 + NU) * P / E, -(1 - NU * NU) * P / E
VM = P * math.sqrt(1 - NU + NU * NU)
TOPS = {"base": 0.4, "mid": 0.7, "top": 1.0}
PAIR_Y = [0.4, 0.7]
runs = {}
for ranks in (1, 2):
    s = runs[ranks] = solve("results/stack_%d" % ranks, ["-options_file", opts("stack"), "-mesh", mesh("stack"), "-output", "summary"], ranks=ranks)
    bad = []
    for k, y in enumerate(PAIR_Y):
        p = s["pairs"][k]
        if not (p["contact_zones"] == 1 and close(p["contact_extent_from"][0], 0, 0) and close(p["contact_extent_from"][1], y, 1e-12) and close(p["contact_extent_to"][0], 1, 1e-12) and close(p["contact_extent_to"][1], y, 1e-12)):
            bad.append("pair %d extent %s to %s" % (k + 1, p["contact_extent_from"], p["contact_extent_to"]))
        if not (close(p["contact_length"], 1, 1e-12) and "contact_half_width" not in p):
            bad.append("pair %d length %r, half-width %r" % (k + 1, p["contact_length"], p.get("contact_half_width")))
        if not (close(p["peak_pressure"], P, 1e-9) and p["peak_pressure_at"][0] == 0 and close(p["peak_pressure_at"][1], y, 1e-12) and close(p["contact_force"], P, 1e-9)):
            bad.append("pair %d peak %r at %s, force %r" % (k + 1, p["peak_pressure"], p["peak_pressure_at"], p["contact_force"]))
    T.check(not bad and len(s["pairs"]) == 2, "stack, %d rank(s): each pair in one zone from (0, y) to (1, y), length 1, no half-width, peak p at (0, y), force p" % ranks, "; ".join(bad))
    bad = []
    names = [b["name"] for b in s["body_results"]]
    for b in s["body_results"]:
        yt = TOPS[b["name"]]
        umax = math.hypot(EX * 1, EY * yt)
        if not (close(b["von_mises_max"], VM, 1e-9) and close(b["von_mises_nodal_max"], VM, 1e-9)):
            bad.append("%s: von Mises %r, nodal %r (exact %r)" % (b["name"], b["von_mises_max"], b["von_mises_nodal_max"], VM))
        if not (close(b["displacement_max"], umax, 1e-9) and close(b["displacement_max_at"][0], 1, 1e-12) and close(b["displacement_max_at"][1], yt, 1e-12)):
            bad.append("%s: displacement %r at %s (exact %r at (1, %g))" % (b["name"], b["displacement_max"], b["displacement_max_at"], umax, yt))
    T.check(names == ["base", "mid", "top"] and not bad, "stack, %d rank(s): every body's von Mises max p sqrt(1 - nu + nu^2) = %.6g (cells, nodes), its displacement max at its top right corner, to 1e-9" % (ranks, VM), "; ".join(bad) or str(names))
same = True
for key in ("pairs", "body_results"):
    for e1, e2 in zip(runs[1][key], runs[2][key]):
        for k, v in e1.items():
            w = e2.get(k)
            if k.endswith("_at") or k.startswith("contact_extent") or isinstance(v, str):
                same = same and v == w
            elif isinstance(v, (int, float)):
                same = same and close(w, v, 1e-9)
T.check(same, "stack: 2 ranks name the same points as 1, the values to 1e-9")

# ---------- the indenter against Hertz ----------
Q, R = 0.00788, 10.0
P_HALF = 10 * Q
E_STAR = 1 / ((1 - 0.3 ** 2) / 2e5 + (1 - 0.45 ** 2) / 10)
A = math.sqrt(4 * 2 * P_HALF * R / (math.pi * E_STAR))
P0 = 2 * 2 * P_HALF / (math.pi * A)


def hertz_von_mises(nu):
    """the largest von Mises stress of Hertz's line contact (on the axis,
    plane strain) over p0, and its depth over a"""
    best = (0, 0)
    for i in range(30001):
        z = 3 * i / 30000
        sz = -1 / math.sqrt(1 + z * z)
        sx = -((1 + 2 * z * z) / math.sqrt(1 + z * z) - 2 * z)
        sy = nu * (sx + sz)
        vm = math.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2))
        best = max(best, (vm, z))
    return best


name = "results/indenter"
s = solve(name, ["-options_file", opts("indenter"), "-mesh", mesh("indenter_2"), "-contact_monitor", "0", "-output_name", "ind", "-output", "vtu,h5,summary"])
p1, p2 = s["pairs"]
spacing = 0.4 / 12  # level 2: 60 tip nodes over 2.0, about 0.033 apart at the zone's end
T.check(abs(p1["contact_half_width"] - A) <= spacing and p1["contact_extent_from"] == [0, 0], "indenter: pair 1's half-width %.4f, Hertz a = %.4f (within the spacing %.3f), from the axis" % (p1["contact_half_width"], A, spacing))
T.check(abs(p1["peak_pressure"] / P0 - 1) <= 0.01 and p1["peak_pressure_at"] == [0, 0], "indenter: pair 1's peak pressure %.5f, p0 = %.5f (1%%), on the axis" % (p1["peak_pressure"], P0), str(p1["peak_pressure_at"]))
T.check(close(p2["contact_force_y"], p1["contact_force_y"], 1e-7) and close(p1["contact_force_y"], P_HALF, 1e-7), "indenter: pair 2 carries pair 1's load P/2 = %.4f" % P_HALF)
for body, nu, sign in (("block", 0.45, -1), ("indenter", 0.3, 1)):
    vm, z = hertz_von_mises(nu)
    b = [e for e in s["body_results"] if e["name"] == body][0]
    for kind in ("von_mises_max", "von_mises_nodal_max"):
        at = b[kind + "_at"]
        ok = abs(b[kind] / (vm * P0) - 1) <= 0.03 and abs(sign * at[1] - z * A) <= 0.1 * A and (kind == "von_mises_max" or at[0] == 0)
        T.check(ok, "indenter: %s's %s %.5f at (%.4f, %.4f), Hertz %.5f at depth %.4f (3%%, 0.1 a)" % (body, kind, b[kind], at[0], at[1], vm * P0, z * A))

# ---------- -hertz compares the curved pairs only ----------
h = solve("results/indenter_hertz", ["-options_file", opts("indenter"), "-mesh", mesh("indenter_2"), "-contact_monitor", "0", "-output", "summary", "-hertz", "-hertz_radius", "10"])
q1, q2 = h["pairs"]
T.check("pressure_l2_rel" in q1 and "pressure_l2_rel" not in q2 and h["pressure_l2_rel"] == q1["pressure_l2_rel"] and q1["pressure_l2_rel"] <= 2e-2 and abs(q1["hertz_a"] / A - 1) < 1e-9,
        "indenter -hertz: pair 1 (curved) compared (%.3e), pair 2 (flat on flat) left out, the top level pair 1's" % q1.get("pressure_l2_rel", -1))
r = solve("results/roller_pairs", ["-options_file", opts("roller"), "-mesh", mesh("roller_1"), "-contact_monitor", "0", "-output", "summary", "-hertz_pairs", "2,1", "-hertz_radius", "1,6:3"])
T.check([p["hertz_radius"] for p in r["pairs"]] == [2.0, 1.0] and r["hertz_radius"] == 2.0, "roller -hertz_pairs 2,1 -hertz_radius 1,6:3: each listed pair its radius in the list's order (pair 2: 1, pair 1: 6:3 = 2)", str([p.get("hertz_radius") for p in r["pairs"]]))
r = solve("results/roller_pair2", ["-options_file", opts("roller"), "-mesh", mesh("roller_1"), "-contact_monitor", "0", "-output", "summary", "-hertz_pairs", "2", "-hertz_radius", "3"])
T.check("hertz_radius" not in r["pairs"][0] and r["pairs"][1]["hertz_radius"] == 3.0 and r["hertz_radius"] == 3.0 and r["pressure_l2_rel"] == r["pairs"][1]["pressure_l2_rel"], "roller -hertz_pairs 2: pair 2 alone, the top level its figures")

# ---------- the body names in the files ----------
d = workdir(name)
with open(os.path.join(d, "ind.vtu"), "rb") as f:
    head = f.read(4096).decode("latin-1")
m = re.search(r'<Array type="String" Name="body_names" NumberOfTuples="(\d+)" format="ascii">([\d\s]+)</Array>', head)
vtu_names = []
if m:
    codes = [int(c) for c in m.group(2).split()]
    vtu_names = bytes(codes).decode().split("\0")[:-1]
T.check(vtu_names == ["indenter", "block", "base"], "the VTU's field data body_names: the bodies in -bodies order", str(vtu_names))
try:
    import h5py
    with h5py.File(os.path.join(d, "ind.h5"), "r") as f:
        h5_names = [n.decode() for n in f["body_names"][:]]
    T.check(h5_names == ["indenter", "block", "base"], "the .h5's /body_names", str(h5_names))
except ImportError:
    print("skip the .h5's /body_names: no h5py")
T.finish()
