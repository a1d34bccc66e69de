#!/usr/bin/python3
"""S1 refinement study (docs/results.md, S1): mortar against node-to-segment (NTS).

Runs the seed report's patch test (options/seed_patch.opts) with both contact
methods on the meshes seed_patch.msh (1x), seed_patch_2/4/8.msh, plus the 16x
mesh as the reference solution (mortar 16x; NTS 16x is also run, only to show
how far apart the two methods still are on the reference mesh), and prints:

  force     contact force / (p * 0.5) - 1                        (equilibrium)
  p_L2      ||p_h - p_ref||_L2(0.25..0.75) / (p sqrt(0.5))        (pressure)
  p_L2int   ||p_h - p_ref||_L2(0.30..0.70) / (p sqrt(0.4))        (no corners)
  sy_L2     ||sy_h - sy_ref|| over lower-body cells with centroid y in
            [0.4, 0.5] (area weighted) / (p sqrt(strip area))     (stress)
  sy_L2int  the same, only cells with centroid x in [0.3, 0.7]   (no corners;
            a diagnostic beside sy_L2, which the corner cells dominate)
  osc       max over interface nodes with x in [0.3, 0.7] of
            |p_{i-1} - 2 p_i + p_{i+1}| / p                       (oscillation)

Pressures are the nodal values of <run>_contact.csv (one row per non-mortar
node with a multiplier), taken as piecewise linear in x along the interface
and sampled on a common grid of 4001 points (trapezoidal rule). The reference
sigma_y at a coarse cell centroid is the value of the reference cell that
contains it; since the refined lower meshes are nested in the 160 x 160
reference, coarse centroids fall on reference vertices, and there the mean of
the (up to four) reference cells touching the point is used.

All errors are relative to the load p = 1 MPa (docs/results.md, S1: relative errors
divide by p). CSV: <out>/s1_refinement.csv. Exit status 1 if a run fails.
The program (--exe, default M2D_EXE or build/mortar2d) and the meshes
(M2D_MESHES, default build/meshes) are found and run through tests/m2d.py.

  /usr/bin/python3 tools/s1_refinement.py [--out DIR] [--quick] [--exe PATH]
"""
import argparse
import csv
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests"))
import m2d                                               # noqa: E402

SRC = m2d.SRC
P = 1.0e6                  # load on the upper top edge (options/seed_patch.opts)
WIDTH = 0.5                # upper body width: contact force should be P * WIDTH
X0, X1 = 0.25, 0.75        # upper body / contact zone
XI0, XI1 = 0.30, 0.70      # interior of the contact zone (corners excluded)
LOWER_W, LOWER_H = 1.0, 0.5
STRIP = (0.4, 0.5)         # y band of lower-body cells for the sigma_y error
NGRID = 4001


def mesh_path(level):
    return m2d.mesh("seed_patch" if level == 1 else "seed_patch_%d" % level)


def run_case(exe, out, level, method):
    """Run one case; return dict with summary, paths and wall time. Exit on failure."""
    name = "%s_%d" % (method, level)
    summary = os.path.join(out, name + ".json")
    for ext in (".json", ".h5", "_contact.csv"):
        p = os.path.join(out, name + ext)
        if os.path.exists(p):
            os.remove(p)
    cmd = m2d.command([
        "-options_file", m2d.opts("seed_patch"), "-mesh", mesh_path(level), "-contact_method", method,
        "-output_dir", out, "-output_name", name, "-summary", summary], exe=exe)
    try:
        r = m2d.launch(cmd, timeout=600)
        rc, so, se, wall = (-1 if r.timed_out else r.rc), r.stdout, r.stderr, r.wall
    except OSError as e:
        rc, so, se, wall = -1, "", str(e), 0.0
    files = [summary, os.path.join(out, name + ".h5"), os.path.join(out, name + "_contact.csv")]
    missing = [f for f in files if not os.path.exists(f)]
    if rc != 0 or missing:
        sys.stderr.write("run failed (rc %d%s): %s\n%s\n%s\n" % (
            rc, ", missing " + " ".join(missing) if missing else "", " ".join(cmd), so, se))
        sys.exit(1)
    s = m2d.read_json(summary)
    return {"level": level, "method": method, "summary": s, "wall": wall,
            "h5": files[1], "csv": files[2], "name": name}


def read_pressure(csv_path):
    """Interface nodes sorted by x: (x, pressure)."""
    d = m2d.csv_columns(csv_path)
    o = np.argsort(d["x"])
    return d["x"][o], d["pressure"][o]


def read_lower_sigma_y(h5_path):
    """Lower-body cells: (centroids (n x 2), areas, sigma_y)."""
    xy, cells, _, cf = m2d.read_h5(h5_path)
    sy = cf["sigma_y"]
    c = xy[cells]                                     # (n, 4, 2)
    cen = c.mean(axis=1)
    x, y = c[:, :, 0], c[:, :, 1]                     # shoelace area of the quad
    area = 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1))
    low = cen[:, 1] < LOWER_H
    return cen[low], area[low], sy[low]


class StructuredLookup:
    """Cell values of a structured nx x ny mesh of [0, W] x [0, H], evaluated at points:
    the containing cell, or the mean of the cells touching the point when it
    lies on cell edges / vertices."""

    def __init__(self, cen, val):
        n = len(cen)
        # grid size from the distinct centroid coordinates
        ux = np.unique(np.round(cen[:, 0], 10))
        uy = np.unique(np.round(cen[:, 1], 10))
        self.nx, self.ny = len(ux), len(uy)
        if self.nx * self.ny != n:
            raise ValueError("reference lower mesh is not structured (%d x %d != %d cells)"
                             % (self.nx, self.ny, n))
        i = np.floor(cen[:, 0] / LOWER_W * self.nx).astype(int)
        j = np.floor(cen[:, 1] / LOWER_H * self.ny).astype(int)
        if not (np.allclose((i + 0.5) * LOWER_W / self.nx, cen[:, 0], atol=1e-9)
                and np.allclose((j + 0.5) * LOWER_H / self.ny, cen[:, 1], atol=1e-9)):
            raise ValueError("reference lower mesh is not a uniform grid of [0,1] x [0,0.5]")
        self.tab = np.full((self.nx, self.ny), np.nan)
        self.tab[i, j] = val
        if np.isnan(self.tab).any():
            raise ValueError("reference lower mesh has holes")

    @staticmethod
    def _candidates(f, n):
        k = np.rint(f)
        if abs(f - k) < 1e-8:                          # on a grid line: both sides
            return [int(c) for c in (k - 1, k) if 0 <= c < n]
        return [min(max(int(np.floor(f)), 0), n - 1)]

    def __call__(self, pts):
        out = np.empty(len(pts))
        for q, (x, y) in enumerate(pts):
            ci = self._candidates(x / LOWER_W * self.nx, self.nx)
            cj = self._candidates(y / LOWER_H * self.ny, self.ny)
            out[q] = np.mean([self.tab[a, b] for a in ci for b in cj])
        return out


def pressure_error(xh, ph, xr, pr, a, b):
    g = np.linspace(a, b, NGRID)
    d = np.interp(g, xh, ph) - np.interp(g, xr, pr)
    return np.sqrt(np.trapz(d * d, g)) / (P * np.sqrt(b - a))


def oscillation(x, p):
    idx = [i for i in range(1, len(x) - 1) if XI0 - 1e-12 <= x[i] <= XI1 + 1e-12]
    if not idx:
        return float("nan")
    return max(abs(p[i - 1] - 2 * p[i] + p[i + 1]) for i in idx) / P


def sigma_y_error(run, ref_lookup, xrange=(0.0, LOWER_W)):
    cen, area, sy = read_lower_sigma_y(run["h5"])
    sel = ((cen[:, 1] >= STRIP[0]) & (cen[:, 1] <= STRIP[1])
           & (cen[:, 0] >= xrange[0]) & (cen[:, 0] <= xrange[1]))
    cen, area, sy = cen[sel], area[sel], sy[sel]
    d = sy - ref_lookup(cen)
    return np.sqrt(np.sum(area * d * d)) / (P * np.sqrt(np.sum(area)))


def metrics(run, ref_p, ref_lookup):
    x, p = read_pressure(run["csv"])
    s = run["summary"]
    return {
        "level": run["level"], "method": run["method"], "dofs": s["dofs"],
        "contact_nodes": s.get("contact_nodes"),
        "force_err": s["contact_force"] / (P * WIDTH) - 1.0,
        "p_L2": pressure_error(x, p, ref_p[0], ref_p[1], X0, X1),
        "p_L2_interior": pressure_error(x, p, ref_p[0], ref_p[1], XI0, XI1),
        "sy_L2_strip": sigma_y_error(run, ref_lookup),
        "sy_L2_strip_interior": sigma_y_error(run, ref_lookup, (XI0, XI1)),
        "oscillation": oscillation(x, p),
        "wall_s": run["wall"],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(SRC, "build", "s1_refinement"))
    ap.add_argument("--quick", action="store_true", help="1x, 2x against a 4x reference")
    ap.add_argument("--exe", default=m2d.EXE)
    a = ap.parse_args()
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    levels, ref_level = ([1, 2], 4) if a.quick else ([1, 2, 4, 8], 16)
    methods = ["mortar", "nts"]

    t0 = time.time()
    runs = {(l, m): run_case(a.exe, out, l, m) for l in levels + [ref_level] for m in methods}
    t_runs = time.time() - t0

    ref = runs[(ref_level, "mortar")]
    ref_p = read_pressure(ref["csv"])
    rc, _, rsy = read_lower_sigma_y(ref["h5"])
    lookup = StructuredLookup(rc, rsy)

    rows = [metrics(runs[(l, m)], ref_p, lookup) for l in levels for m in methods]
    ref_rows = [metrics(runs[(ref_level, m)], ref_p, lookup) for m in methods]

    keys = ["p_L2", "p_L2_interior", "sy_L2_strip", "sy_L2_strip_interior", "oscillation"]
    print("S1 refinement study: reference = mortar %dx (%d dofs, lower %dx%d cells); p = %g Pa"
          % (ref_level, ref["summary"]["dofs"], lookup.nx, lookup.ny, P))
    print("errors relative to p: p_L2 on x in [%.2f, %.2f], p_L2int on [%.2f, %.2f], "
          "sy_L2 on lower cells with centroid y in [%.1f, %.1f] (sy_L2int: and x in [%.1f, %.1f]);\n"
          "osc = max |p[i-1]-2p[i]+p[i+1]|/p over nodes x_i in [%.1f, %.1f]"
          % (X0, X1, XI0, XI1, STRIP[0], STRIP[1], XI0, XI1, XI0, XI1))
    hdr = "%5s %7s %-6s %5s %10s %10s %10s %10s %10s %10s %7s" % (
        "level", "dofs", "method", "nodes", "force-1", "p_L2", "p_L2int", "sy_L2", "sy_L2int", "osc",
        "wall_s")
    print(hdr)
    print("-" * len(hdr))

    def line(r, tag=None):
        print("%5s %7d %-6s %5s %10.2e %10.3e %10.3e %10.3e %10.3e %10.3e %7.2f" % (
            tag or "%dx" % r["level"], r["dofs"], r["method"], r["contact_nodes"], r["force_err"],
            r["p_L2"], r["p_L2_interior"], r["sy_L2_strip"], r["sy_L2_strip_interior"],
            r["oscillation"], r["wall_s"]))

    for r in rows:
        line(r)
    print("-" * len(hdr))
    for r in ref_rows:
        line(r, "%dx" % ref_level + ("*" if r["method"] == "mortar" else "+"))
    print("  * the reference itself (errors 0 by construction); + NTS on the reference mesh "
          "against it: the size of the method difference at %dx" % ref_level)

    print("\nchecks:")
    ok_all = True
    for m in methods:
        f = max(abs(r["force_err"]) for r in rows + ref_rows if r["method"] == m)
        print("  %-6s equilibrium: max |force/(p*0.5) - 1| = %.1e  %s" % (m, f, "yes" if f < 1e-8 else "NO"))
    for k in keys[:4]:
        for m in methods:
            e = [r[k] for r in rows if r["method"] == m]
            falls = all(e[i + 1] < e[i] for i in range(len(e) - 1))
            rates = ["%.2f" % np.log2(e[i] / e[i + 1]) if e[i + 1] > 0 else "inf" for i in range(len(e) - 1)]
            print("  %-20s %-6s falls with refinement: %-3s (log2 ratios %s)"
                  % (k, m, "yes" if falls else "NO", ", ".join(rates)))
    for k in keys:
        mo = {r["level"]: r[k] for r in rows if r["method"] == "mortar"}
        nt = {r["level"]: r[k] for r in rows if r["method"] == "nts"}
        below = [l for l in levels if mo[l] < nt[l]]
        worse = ["%dx (mortar %.3e vs nts %.3e, x%.2f)" % (l, mo[l], nt[l], mo[l] / nt[l] if nt[l] else np.inf)
                 for l in levels if not mo[l] < nt[l]]
        yes = len(below) == len(levels)
        ok_all &= yes
        print("  %-20s mortar below NTS at every level: %s%s" % (k, "yes" if yes else "NO", "" if yes else
                                                              "; not at " + "; ".join(worse)))
    osc_m = max(r["oscillation"] for r in rows if r["method"] == "mortar")
    print("  mortar max node-to-node oscillation (x in [0.3, 0.7]) over levels: %.3e p" % osc_m)

    path = os.path.join(out, "s1_refinement.csv")
    cols = ["level", "method", "dofs", "contact_nodes", "force_err", "p_L2", "p_L2_interior",
            "sy_L2_strip", "sy_L2_strip_interior", "oscillation", "wall_s", "reference"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows + ref_rows:
            r = dict(r, reference="mortar_%d" % ref_level)
            w.writerow([("%.6e" % r[c]) if isinstance(r[c], float) else r[c] for c in cols])
    print("\n%d runs in %.1f s (total %.1f s); table: %s" % (len(runs), t_runs, time.time() - t0, path))
    return 0


if __name__ == "__main__":
    sys.exit(main())
