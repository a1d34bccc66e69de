#!/usr/bin/python3
"""S3 Hertz refinement study: mortar and node-to-segment (NTS) on levels 0..4.

Runs mortar2d (--exe, default M2D_EXE or build/mortar2d) -options_file
options/hertz.opts on the graded meshes hertz_N.msh in M2D_MESHES (default
build/meshes; made by tools/hertz_mesh.sh when missing, e.g. level 5) for each
method, through tests/m2d.py, and prints, per method and level:

  dofs     degrees of freedom
  steps    active-set steps (summary "iterations")
  act      active non-mortar nodes
  h_c      mean non-mortar node spacing on [0, 1.5a] (the contact-zone h;
           it halves from one level to the next by construction)
  a_h/a    computed half-width (midway between the last active node and the
           next one) over Hertz's a
  da/h_c   |a_h - a| / node spacing at the edge of the contact zone
  pk/p0    peak nodal pressure over Hertz's p0
  eH       ||p_h - p_Hertz||_L2(0,1.5a) / ||p_Hertz||   (summary pressure_l2_rel)
  eI       ||I_h p_Hertz - p_Hertz|| / ||p_Hertz||, I_h the piecewise-linear
           interpolant on this level's non-mortar nodes: what eH would be if
           every nodal value were exact (the edge of the contact zone, where
           p ~ sqrt(a - x), falls between nodes)
  eP       ||p_h - p_f||_L2(0,1.5a) / ||p_f||, p_f the finest level's pressure
           of the SAME method (self-convergence); both pressures are the nodal
           values of <run>_contact.csv joined linearly in x, sampled at the
           midpoints of 6000 equal intervals of [0, 1.5a]
  eU       ||u_h - u_f|| / ||u_f|| over the level's vertices, u_f the finest
           level's displacement (same method) evaluated at those vertices;
           discrete L2 with lumped (quarter-cell) area weights, so it
           approximates the continuous L2 norm over both bodies. u_f is the
           exact Q4 field: the point is located in the finest mesh of the same
           body (the two bodies touch at the origin) with a trifinder on the
           quads split in two triangles, then the bilinear map is inverted by
           Newton. Vertices on the curved arc that fall just outside the
           finest mesh's polygonal arc (non-nested meshes) are projected on the
           nearest boundary edge of that body (u_f is linear along an edge);
           the projection distance is reported (max_proj in the CSV).
  r        observed rate of the error to the left, log(e_{l-1}/e_l) /
           log(h_{l-1}/h_l) with h = h_c (i.e. ~log2 of the error ratio)
  t        program's own total time (summary time.total) and wall time of the
           whole run (process start to exit, incl. MPI start-up), seconds

The finest level is its own reference, so its eP and eU are 0, and those of the
level just below it are biased low (the reference error is comparable).

CSV: <out>/hertz_study.csv. Runs go to <out>/<method>_<level>/ (h.h5,
h_contact.csv, s.json, log.txt). Exit status 1 if a run fails.

  /usr/bin/python3 tools/hertz_study.py [--levels 0,1,2,3,4] [--methods mortar,nts]
        [--ranks 1|2] [--out build/hertz_study] [--extra "-mortar_basis standard"]
        [--reuse] [--exe build/mortar2d]
"""
import argparse
import csv
import json
import math
import os
import shlex
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests"))
import m2d                                               # noqa: E402

SRC = m2d.SRC
OPTS = m2d.opts("hertz")
NGRID = 6000


def mesh_path(level):
    """Path of level N's mesh, made by tools/hertz_mesh.sh if missing or stale."""
    try:
        return m2d.hertz_mesh(level)
    except RuntimeError as e:
        sys.exit("hertz_study: %s" % e)


def run_case(args, level, method):
    """Run one case (or re-use it with --reuse); return its summary and paths."""
    d = os.path.join(args.out, "%s_%d" % (method, level))
    os.makedirs(d, exist_ok=True)
    summary = os.path.join(d, "s.json")
    log = os.path.join(d, "log.txt")
    files = [summary, os.path.join(d, "h.h5"), os.path.join(d, "h_contact.csv")]
    if args.reuse and all(os.path.exists(f) for f in files):
        s = m2d.read_json(summary)
        wall = s.get("wall", float("nan"))
    else:
        for f in files:
            if os.path.exists(f):
                os.remove(f)
        cmd = m2d.command(["-options_file", OPTS, "-mesh", mesh_path(level),
                           "-output_dir", d, "-output_name", "h", "-summary", summary,
                           "-contact_method", method] + shlex.split(args.extra), args.ranks, exe=args.exe)
        print("  running %s level %d: %s" % (method, level, shlex.join(cmd)), flush=True)
        r = m2d.launch(cmd, timeout=None, stdout=log, merge=True)
        wall = r.wall
        if r.rc != 0 or not all(os.path.exists(f) for f in files):
            with open(log) as f:
                tail = f.readlines()[-25:]
            sys.stderr.write("".join(tail))
            sys.exit("hertz_study: %s level %d failed (exit %d); log: %s"
                     % (method, level, r.rc, log))
        s = m2d.read_json(summary)
        s["wall"] = wall
        with open(summary, "w") as f:      # keep the wall time for --reuse
            json.dump(s, f, indent=1)
    return {"summary": s, "dir": d, "wall": wall, "h5": files[1], "csv": files[2]}


def read_pressure(path):
    """Nodal (|x|, pressure) of a contact CSV, sorted by x."""
    a = m2d.csv_columns(path)
    x = np.abs(a["x"])
    o = np.argsort(x, kind="stable")
    return x[o], a["pressure"][o]


def read_h5(path):
    """(vertices xy, cells, displacement xy, body of each cell) of an HDF5 output."""
    xy, cells, vf, cf = m2d.read_h5(path)
    return xy[:, :2], cells.astype(np.int64), vf["displacement"][:, :2], np.rint(cf["body"]).astype(int).ravel()


class BodyField:
    """Exact Q4 displacement field of one body of a (fine) mesh."""

    def __init__(self, X, C, U):
        import matplotlib.tri as mtri
        self.X, self.C, self.U = X, C, U
        # orient every quad counter-clockwise for the bilinear inverse map
        P = X[C]
        area2 = ((P[:, 2, 0] - P[:, 0, 0]) * (P[:, 3, 1] - P[:, 1, 1])
                 - (P[:, 3, 0] - P[:, 1, 0]) * (P[:, 2, 1] - P[:, 0, 1]))
        self.C = C = np.where((area2 < 0)[:, None], C[:, ::-1], C)
        tri = np.vstack([C[:, [0, 1, 2]], C[:, [0, 2, 3]]])
        self.nq = len(C)
        self.tri = mtri.Triangulation(X[:, 0], X[:, 1], tri)
        self.finder = self.tri.get_trifinder()
        # boundary edges: edges of exactly one quad
        e = np.vstack([C[:, [0, 1]], C[:, [1, 2]], C[:, [2, 3]], C[:, [3, 0]]])
        es = np.sort(e, axis=1)
        _, idx, cnt = np.unique(es, axis=0, return_index=True, return_counts=True)
        self.bedges = e[idx[cnt == 1]]

    def eval(self, pts):
        """u at pts; returns (u, max projection distance for points outside)."""
        t = self.finder(pts[:, 0], pts[:, 1])
        u = np.full((len(pts), 2), np.nan)
        inside = t >= 0
        if inside.any():
            q = self.C[t[inside] % self.nq]
            u[inside] = self._bilinear(q, pts[inside])
        dmax = 0.0
        out = np.where(~inside)[0]
        if len(out):
            A = self.X[self.bedges[:, 0]]
            B = self.X[self.bedges[:, 1]]
            AB = B - A
            L2 = np.einsum("ij,ij->i", AB, AB)
            for i in out:          # few points (on the arc): plain loop
                ap = pts[i] - A
                s = np.clip(np.einsum("ij,ij->i", ap, AB) / L2, 0, 1)
                d = np.hypot(*(ap - s[:, None] * AB).T)
                k = np.argmin(d)
                dmax = max(dmax, d[k])
                u[i] = (1 - s[k]) * self.U[self.bedges[k, 0]] + s[k] * self.U[self.bedges[k, 1]]
        return u, dmax

    def _bilinear(self, q, p):
        P = self.X[q]                       # (n, 4, 2), counter-clockwise
        xi = np.zeros((len(p), 2))
        for _ in range(30):
            s, t = xi[:, 0], xi[:, 1]
            N = 0.25 * np.stack([(1 - s) * (1 - t), (1 + s) * (1 - t), (1 + s) * (1 + t), (1 - s) * (1 + t)], 1)
            dNs = 0.25 * np.stack([-(1 - t), (1 - t), (1 + t), -(1 + t)], 1)
            dNt = 0.25 * np.stack([-(1 - s), -(1 + s), (1 + s), (1 - s)], 1)
            r = np.einsum("nk,nkd->nd", N, P) - p
            J = np.stack([np.einsum("nk,nkd->nd", dNs, P), np.einsum("nk,nkd->nd", dNt, P)], 2)
            det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
            ds = (J[:, 1, 1] * r[:, 0] - J[:, 0, 1] * r[:, 1]) / det
            dt = (-J[:, 1, 0] * r[:, 0] + J[:, 0, 0] * r[:, 1]) / det
            xi[:, 0] -= ds
            xi[:, 1] -= dt
            if max(np.abs(ds).max(), np.abs(dt).max()) < 1e-13:
                break
        xi = np.clip(xi, -1, 1)
        s, t = xi[:, 0], xi[:, 1]
        N = 0.25 * np.stack([(1 - s) * (1 - t), (1 + s) * (1 - t), (1 + s) * (1 + t), (1 - s) * (1 + t)], 1)
        return np.einsum("nk,nkd->nd", N, self.U[q])


def vertex_weights(X, C):
    """Lumped area weight of each vertex (a quarter of each touching cell's area)."""
    P = X[C]
    area = 0.5 * np.abs((P[:, 2, 0] - P[:, 0, 0]) * (P[:, 3, 1] - P[:, 1, 1])
                        - (P[:, 3, 0] - P[:, 1, 0]) * (P[:, 2, 1] - P[:, 0, 1]))
    w = np.zeros(len(X))
    np.add.at(w, C.ravel(), np.repeat(area / 4, 4))
    return w


def vertex_body(X, C, B):
    vb = np.full(len(X), -1)
    for b in np.unique(B):
        vb[np.unique(C[B == b])] = b
    return vb


def displacement_error(h5, ref):
    """Relative (area weighted, and plain) L2 error of u against the finest field."""
    X, C, U, B = read_h5(h5)
    vb = vertex_body(X, C, B)
    w = vertex_weights(X, C)
    Uf = np.full_like(U, np.nan)
    dmax = 0.0
    for b, field in ref.items():
        m = vb == b
        Uf[m], d = field.eval(X[m])
        dmax = max(dmax, d)
    if np.isnan(Uf).any():
        raise RuntimeError("displacement reference missing at %d vertices" % np.isnan(Uf).any(1).sum())
    d2 = ((U - Uf) ** 2).sum(1)
    r2 = (Uf ** 2).sum(1)
    return (math.sqrt((w * d2).sum() / (w * r2).sum()), math.sqrt(d2.sum() / r2.sum()), dmax)


def rate(e0, e1, h0, h1):
    if not (e0 > 0 and e1 > 0 and h0 > 0 and h1 > 0) or h0 == h1:
        return float("nan")
    return math.log(e0 / e1) / math.log(h0 / h1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--levels", default="0,1,2,3,4")
    ap.add_argument("--methods", default="mortar,nts")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--out", default=os.path.join(SRC, "build", "hertz_study"))
    ap.add_argument("--extra", default="", help="more mortar2d options, one string")
    ap.add_argument("--exe", default=m2d.EXE)
    ap.add_argument("--reuse", action="store_true",
                    help="re-use results already in --out instead of running again")
    args = ap.parse_args()
    levels = sorted(int(v) for v in args.levels.split(","))
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    args.out = os.path.abspath(args.out)
    args.exe = os.path.abspath(args.exe)
    os.makedirs(args.out, exist_ok=True)
    if not os.access(args.exe, os.X_OK):
        sys.exit("hertz_study: no program %s (cmake --build build)" % args.exe)

    runs = {}
    for lev in levels:
        mesh_path(lev)
        for m in methods:
            runs[m, lev] = run_case(args, lev, m)

    rows = []
    fine = levels[-1]
    for m in methods:
        sf = runs[m, fine]["summary"]
        a, p0 = sf["hertz_a"], sf["hertz_p0"]
        xg = (np.arange(NGRID) + 0.5) * 1.5 * a / NGRID
        xf, pf = read_pressure(runs[m, fine]["csv"])
        pg_f = np.interp(xg, xf, pf)
        print("  %s: reading the level-%d displacement as reference" % (m, fine), flush=True)
        X, C, U, B = read_h5(runs[m, fine]["h5"])
        ref = {b: BodyField(X, C[B == b], U) for b in np.unique(B)}
        for lev in levels:
            r = runs[m, lev]
            s = r["summary"]
            x, p = read_pressure(r["csv"])
            pg = np.interp(xg, x, p)
            eP = math.sqrt(((pg - pg_f) ** 2).sum() / (pg_f ** 2).sum())
            pe = p0 * np.sqrt(np.clip(1 - xg ** 2 / a ** 2, 0, None))
            pi = np.interp(xg, x, p0 * np.sqrt(np.clip(1 - x ** 2 / a ** 2, 0, None)))
            eI = math.sqrt(((pi - pe) ** 2).sum() / (pe ** 2).sum())
            inzone = x <= 1.5 * a
            hc = float(np.mean(np.diff(x[inzone]))) if inzone.sum() > 1 else float("nan")
            if lev == fine:
                eU = eUp = dproj = 0.0
            else:
                eU, eUp, dproj = displacement_error(r["h5"], ref)
            rows.append({
                "method": m, "level": lev, "ranks": args.ranks, "dofs": s["dofs"],
                "steps": s["iterations"], "active_nodes": s["active_nodes"],
                "h_c": hc, "a": a, "a_h": s["half_width"], "a_h_over_a": s["half_width"] / a,
                "edge_spacing": s["half_width_spacing"],
                "da_over_h": abs(s["half_width"] - a) / s["half_width_spacing"],
                "p0": p0, "peak": s["peak_pressure"], "peak_over_p0": s["peak_pressure"] / p0,
                "contact_force": s["contact_force"],
                "err_hertz": s["pressure_l2_rel"], "err_interp_hertz": eI, "err_p_finest": eP,
                "err_u_finest": eU, "err_u_finest_plain": eUp, "max_proj": dproj,
                "t_mesh": s["time"]["mesh"], "t_contact": s["time"]["contact"],
                "t_assembly": s["time"]["assembly"], "t_solve": s["time"]["solve"],
                "t_output": s["time"]["output"], "t_total": s["time"]["total"], "t_wall": r["wall"],
            })
    by = {(r["method"], r["level"]): r for r in rows}
    for r in rows:
        prev = by.get((r["method"], r["level"] - 1))
        for k in ("err_hertz", "err_p_finest", "err_u_finest"):
            r["rate_" + k] = (rate(prev[k], r[k], prev["h_c"], r["h_c"]) if prev else float("nan"))
        if r["level"] == fine:     # the reference itself: no error, no rate
            r["rate_err_p_finest"] = r["rate_err_u_finest"] = float("nan")

    f = lambda v, fmt: "-" if v != v else fmt % v                          # noqa: E731
    print()
    print("S3 Hertz: a = %.6g, p0 = %.6g (E* from E = 200, nu = 0.3, plane strain); ranks %d%s"
          % (a, p0, args.ranks, (", extra: " + args.extra) if args.extra else ""))
    print("eH vs Hertz on [0,1.5a] (eI: Hertz's own nodal interpolant); eP, eU vs the finest "
          "level (%d) of the same method; r = rate in h_c" % fine)
    head = ("%-6s %3s %8s %5s %4s %9s %7s %6s %6s %9s %5s %9s %9s %5s %9s %5s %8s %8s"
            % ("method", "lev", "dofs", "steps", "act", "h_c", "a_h/a", "da/h_c", "pk/p0",
               "eH", "r", "eI", "eP", "r", "eU", "r", "t_prog", "t_wall"))
    for m in methods:
        print()
        print(head)
        for lev in levels:
            r = by[m, lev]
            print("%-6s %3d %8d %5d %4d %9.3e %7.4f %6.3f %6.4f %9.3e %5s %9.3e %9.3e %5s %9.3e %5s %8.2f %8.2f"
                  % (m, lev, r["dofs"], r["steps"], r["active_nodes"], r["h_c"], r["a_h_over_a"],
                     r["da_over_h"], r["peak_over_p0"], r["err_hertz"],
                     f(r["rate_err_hertz"], "%5.2f"), r["err_interp_hertz"], r["err_p_finest"],
                     f(r["rate_err_p_finest"], "%5.2f"), r["err_u_finest"],
                     f(r["rate_err_u_finest"], "%5.2f"), r["t_total"], r["t_wall"]))
    if len(methods) > 1:
        print()
        xg = (np.arange(NGRID) + 0.5) * 1.5 * a / NGRID
        pgs = {m: np.interp(xg, *read_pressure(runs[m, fine]["csv"])) for m in methods}
        m0 = methods[0]
        for m in methods[1:]:
            d = math.sqrt(((pgs[m] - pgs[m0]) ** 2).sum() / (pgs[m0] ** 2).sum())
            print("level %d: ||p_%s - p_%s|| / ||p_%s|| on [0,1.5a] = %.3e" % (fine, m, m0, m0, d))

    path = os.path.join(args.out, "hertz_study.csv")
    keys = list(rows[0].keys())
    with open(path, "w", newline="") as fcsv:
        w = csv.DictWriter(fcsv, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: ("%.10g" % v if isinstance(v, float) else v) for k, v in r.items()})
    print("\nCSV: %s" % os.path.relpath(path, SRC) if path.startswith(SRC) else "\nCSV: %s" % path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
