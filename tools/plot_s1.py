#!/usr/bin/python3
"""Pictures of scene S1 (the seed report's patch test), mortar beside NTS.

docs/s1_stresses.png  3 x 2 panels like the report's figures 5-7: rows sigma_x,
                      sigma_y, sigma_z (cell values, MPa), columns mortar and
                      NTS, at 1x (the report's 10x10 / 5x5 mesh), both bodies on
                      the undeformed mesh (displacements are ~1e-3 of the size;
                      --scale N draws u magnified N times), one colour scale
                      per row.
docs/s1_pressure.png  contact pressure along the interface (nodal values from
                      <run>_contact.csv, joined linearly) for mortar and NTS at
                      1x, 2x, 4x, 8x, with the same method's 16x solution as a
                      thick grey line; bottom row: zoom on the left corner.

Runs the cases itself into --runs (default build/s1_plots), re-using result
files already there when --reuse is given (e.g. --runs build/s1_refinement
--reuse after tools/s1_refinement.py). --mortar-h5 / --nts-h5 take existing
1x outputs for the stress figure instead.

  /usr/bin/python3 tools/plot_s1.py [--runs DIR] [--reuse] [--docs DIR]
"""
import argparse
import os
import sys

import numpy as np

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt                          # noqa: E402
from matplotlib.collections import PolyCollection        # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from s1_refinement import SRC, P, m2d, run_case, read_pressure  # noqa: E402

LABEL = {"mortar": "mortar", "nts": "NTS (node-to-segment)"}


def read_h5(path):
    xy, cells, vf, cf = m2d.read_h5(path)
    return xy, cells, vf["displacement"][:, :2], cf


def get_run(args, level, method):
    """Paths (h5, csv) of a run, running it unless --reuse finds it."""
    name = "%s_%d" % (method, level)
    h5 = os.path.join(args.runs, name + ".h5")
    csv = os.path.join(args.runs, name + "_contact.csv")
    if args.reuse and os.path.exists(h5) and os.path.exists(csv):
        return h5, csv
    r = run_case(args.exe, args.runs, level, method)
    return r["h5"], r["csv"]


def stresses_figure(h5s, path, scale):
    rows = [("sigma_x", r"$\sigma_x$"), ("sigma_y", r"$\sigma_y$"), ("sigma_z", r"$\sigma_z$")]
    data = {m: read_h5(h5s[m]) for m in h5s}
    fig, axes = plt.subplots(3, 2, figsize=(12.5, 13.5), constrained_layout=True)
    for i, (key, tex) in enumerate(rows):
        vals = np.concatenate([data[m][3][key] for m in h5s]) / 1e6
        vmin, vmax = vals.min(), vals.max()
        for j, m in enumerate(["mortar", "nts"]):
            xy, cells, u, cf = data[m]
            pts = xy + scale * u
            ax = axes[i, j]
            pc = PolyCollection(pts[cells], array=cf[key] / 1e6, cmap="turbo",
                                edgecolors="k", linewidths=0.3)
            pc.set_clim(vmin, vmax)
            ax.add_collection(pc)
            ax.plot([0.25, 0.75], [0.5, 0.5], color="w", lw=1.2, ls="--")  # contact interface
            ax.set_xlim(-0.02, 1.02)
            ax.set_ylim(-0.02, 0.77)
            ax.set_aspect("equal")
            ax.set_title("%s, %s: min %.3f, max %.3f MPa" % (tex, LABEL[m], cf[key].min() / 1e6,
                                                            cf[key].max() / 1e6), fontsize=12)
            ax.set_xlabel("x [m]")
            ax.set_ylabel("y [m]")
            # lower-body cell values under the contact zone, printed as numbers in the top row
            # of the lower body so the two methods can be compared cell by cell
            cen = xy[cells].mean(axis=1)
            top = (cen[:, 1] > 0.45) & (cen[:, 1] < 0.5)
            for c, v in zip(cen[top], cf[key][top]):
                ax.text(c[0], c[1], "%.2f" % (v / 1e6), ha="center", va="center", fontsize=7,
                        color="k", bbox=dict(boxstyle="square,pad=0.05", fc="w", ec="none", alpha=0.6))
        cb = fig.colorbar(pc, ax=list(axes[i, :]), shrink=0.9, pad=0.01)
        cb.set_label(tex + " [MPa]", fontsize=12)
    fig.suptitle("S1 (seed report patch test) at 1x: lower 10x10, upper 5x5 Q4, p = 1 MPa, "
                 "E = 1 GPa, nu = 0.3, plane strain; cell values%s"
                 % ("" if scale == 0 else ", displacement x %g" % scale), fontsize=13)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def pressure_figure(csvs, ref_csvs, path):
    """Top row: the whole interface; bottom row: zoom on the left corner."""
    levels = sorted({l for (l, m) in csvs})
    colors = plt.cm.viridis(np.linspace(0.0, 0.85, len(levels)))
    fig, axes = plt.subplots(2, 2, figsize=(13, 9.5), sharey="row", constrained_layout=True)
    for j, m in enumerate(["mortar", "nts"]):
        xr, pr = read_pressure(ref_csvs[m])
        for i in range(2):
            ax = axes[i, j]
            ax.plot(xr, pr / 1e6, "-", color="0.55", lw=3.5, alpha=0.55,
                    label="%s 16x (%d nodes)" % (m if m == "mortar" else "NTS", len(xr)))
            for l, c in zip(levels, colors):
                x, p = read_pressure(csvs[(l, m)])
                ax.plot(x, p / 1e6, "-o", color=c, ms=(4 if l < 8 else 2.5) + 1.5 * i, lw=1.3,
                        label="%dx (%d nodes)" % (l, len(x)))
            ax.axhline(P / 1e6, color="k", lw=0.8, ls=":", label="p = 1 MPa")
            ax.grid(alpha=0.3)
            if i == 0:
                ax.set_title("contact pressure, %s" % LABEL[m], fontsize=12)
                ax.set_xlabel("x [m] (upper body spans 0.25 .. 0.75)")
                ax.axvspan(0.25, 0.40, color="0.9", zorder=-1)
                ax.legend(fontsize=9, loc="upper center")
            else:
                ax.set_title("zoom on the left corner, %s" % LABEL[m], fontsize=12)
                ax.set_xlabel("x [m]")
                ax.set_xlim(0.248, 0.40)
                ax.set_ylim(0.7, 2.2)
        axes[0, 0].set_ylabel("pressure [MPa]\n(nodal values, linear between nodes)")
        axes[1, 0].set_ylabel("pressure [MPa]")
    fig.suptitle("S1: contact pressure on the interface y = 0.5 under refinement "
                 "(corner values leave the zoomed axes)", fontsize=13)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", default=os.path.join(SRC, "build", "s1_plots"))
    ap.add_argument("--reuse", action="store_true", help="use result files already in --runs")
    ap.add_argument("--docs", default=os.path.join(SRC, "docs"))
    ap.add_argument("--exe", default=m2d.EXE)
    ap.add_argument("--mortar-h5", help="existing 1x mortar output for the stress figure")
    ap.add_argument("--nts-h5", help="existing 1x NTS output for the stress figure")
    ap.add_argument("--scale", type=float, default=0.0, help="displacement magnification (0: undeformed)")
    ap.add_argument("--no-pressure", action="store_true", help="only the stress figure")
    a = ap.parse_args()
    a.runs = os.path.abspath(a.runs)
    os.makedirs(a.runs, exist_ok=True)
    os.makedirs(a.docs, exist_ok=True)

    if a.mortar_h5 and a.nts_h5:
        h5s = {"mortar": a.mortar_h5, "nts": a.nts_h5}
    else:
        h5s = {m: get_run(a, 1, m)[0] for m in ("mortar", "nts")}
    p1 = os.path.join(a.docs, "s1_stresses.png")
    stresses_figure(h5s, p1, a.scale)
    print("wrote", p1)
    if not a.no_pressure:
        csvs = {(l, m): get_run(a, l, m)[1] for l in (1, 2, 4, 8) for m in ("mortar", "nts")}
        refs = {m: get_run(a, 16, m)[1] for m in ("mortar", "nts")}
        p2 = os.path.join(a.docs, "s1_pressure.png")
        pressure_figure(csvs, refs, p2)
        print("wrote", p2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
