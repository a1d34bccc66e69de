#!/usr/bin/python3
"""Pictures of scene S3 (Hertz), mortar beside node-to-segment (NTS).

docs/hertz_pressure.png     top row: contact pressure along the interface
                            (nodal values of <run>_contact.csv as markers,
                            joined linearly) over Hertz's p0 sqrt(1 - x^2/a^2)
                            on [0, 1.5a], mortar (left) and NTS (right), at one
                            level (default 2) or several overlaid (--levels
                            1,2,4); bottom row: nodal deviation from Hertz,
                            (p_h - p_Hertz) / p0.
docs/hertz_convergence.png  from <runs>/hertz_study.csv (tools/hertz_study.py),
                            if present: left, the pressure error against Hertz
                            on [0, 1.5a]; right, the pressure and displacement
                            errors against the finest level of the same method;
                            grey: the error of Hertz's exact pressure joined
                            linearly between the level's nodes (no solver error);
                            all against dofs, log-log, with h and h^2 slopes
                            (h ~ dofs^-1/2).

The pressure figure reads <runs>/<method>_<level>/h_contact.csv as written by
tools/hertz_study.py (default --runs build/hertz_study) and runs the missing
cases itself (same layout) otherwise.

  /usr/bin/python3 tools/plot_hertz.py [--levels 2] [--runs DIR] [--docs DIR]
"""
import argparse
import csv
import json
import os
import sys

import numpy as np

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt                          # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from hertz_study import SRC, m2d, run_case, read_pressure  # noqa: E402

LABEL = {"mortar": "mortar (dual multipliers)", "nts": "node-to-segment (NTS)"}
METHODS = ("mortar", "nts")


def get_case(runs, level, method):
    d = os.path.join(runs, "%s_%d" % (method, level))
    csvp, js = os.path.join(d, "h_contact.csv"), os.path.join(d, "s.json")
    if not (os.path.exists(csvp) and os.path.exists(js)):
        args = argparse.Namespace(out=runs, reuse=True, extra="", ranks=1, exe=m2d.EXE)
        run_case(args, level, method)
    with open(js) as f:
        s = json.load(f)
    x, p = read_pressure(csvp)
    return s, x, p


def plot_pressure(runs, levels, path):
    cases = {(m, l): get_case(runs, l, m) for m in METHODS for l in levels}
    s0 = cases[METHODS[0], levels[0]][0]
    a, p0 = s0["hertz_a"], s0["hertz_p0"]
    fig, ax = plt.subplots(2, 2, figsize=(12, 7.5), sharex=True,
                           gridspec_kw={"height_ratios": [2.2, 1]})
    xe = np.linspace(0, 1.5 * a, 1501)
    pe = p0 * np.sqrt(np.clip(1 - xe ** 2 / a ** 2, 0, None))
    palette = ["#d95f02", "#1f77b4", "#2ca02c", "#7b3294", "#e7298a", "#8c564b"]
    colors = [palette[i % len(palette)] for i in range(len(levels))] if len(levels) > 1 else ["C0"]
    markers = "osD^v<>"
    dev_max = 0.0
    for j, m in enumerate(METHODS):
        top, bot = ax[0, j], ax[1, j]
        top.plot(xe / a, pe, color="k", lw=2.2, alpha=0.35, label="Hertz, $p_0\\sqrt{1-x^2/a^2}$", zorder=1)
        bot.axhline(0, color="k", lw=1, alpha=0.35)
        for i, l in enumerate(levels):
            s, x, p = cases[m, l]
            keep = x <= 1.5 * a * (1 + 1e-9)
            # one node beyond 1.5a so the line reaches the axis edge
            k = min(int(keep.sum()) + 1, len(x))
            ms = max(2.5, 6.5 - 1.5 * i) if len(levels) > 1 else 5
            top.plot(x[:k] / a, p[:k], "-", marker=markers[i % len(markers)], ms=ms, lw=1.1,
                     color=colors[i], mfc="none" if len(levels) > 1 else colors[i], zorder=2 + i,
                     label="level %d: %d dofs, %d active, $h_c$ = %.2g a, error %.2g%%"
                     % (l, s["dofs"], s["active_nodes"],
                        float(np.mean(np.diff(x[keep]))) / a, 100 * s["pressure_l2_rel"]))
            ph = p0 * np.sqrt(np.clip(1 - x ** 2 / a ** 2, 0, None))
            dev = (p - ph) / p0
            bot.plot(x[:k] / a, dev[:k], "-", marker=markers[i % len(markers)], ms=ms, lw=0.8,
                     color=colors[i], mfc="none" if len(levels) > 1 else colors[i], zorder=2 + i)
            dev_max = max(dev_max, np.abs(dev[:k]).max())
        top.axvline(1, color="0.6", lw=0.8, ls=":")
        bot.axvline(1, color="0.6", lw=0.8, ls=":")
        top.set_title(LABEL[m])
        top.set_ylim(-0.2, 1.12 * p0)
        top.set_xlim(0, 1.5)
        top.legend(loc="lower left", fontsize=8.5, framealpha=0.9)
        top.grid(alpha=0.3)
        bot.grid(alpha=0.3)
        bot.set_xlabel("x / a   (a = %.4f, p$_0$ = %.3f)" % (a, p0))
    lim = min(1.05 * dev_max, 0.5)
    for j in range(2):
        ax[1, j].set_ylim(-lim, lim)
    ax[0, 0].set_ylabel("contact pressure")
    ax[1, 0].set_ylabel("(p$_h$ - p$_{Hertz}$) / p$_0$ at the nodes")
    fig.suptitle("S3 Hertz: quarter cylinder R = 1 on a 4 x 4 block, E = 200, $\\nu$ = 0.3, plane strain, "
                 "P = 0.86 (nodal values joined linearly)", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    print("wrote %s" % path)


def plot_convergence(csvpath, path):
    with open(csvpath) as f:
        rows = list(csv.DictReader(f))
    fine = max(int(r["level"]) for r in rows)
    fig, ax = plt.subplots(1, 2, figsize=(12, 5.2), sharey=True)
    style = {"mortar": dict(color="C0", marker="o"), "nts": dict(color="C3", marker="s")}
    alld = []
    for m in METHODS:
        rr = sorted((r for r in rows if r["method"] == m), key=lambda r: int(r["level"]))
        if not rr:
            continue
        d = np.array([float(r["dofs"]) for r in rr])
        alld += list(d)
        eh = np.array([float(r["err_hertz"]) for r in rr])
        ax[0].loglog(d, eh, "-", ms=7, label="p vs Hertz, " + m, **style[m])
        if m == METHODS[0] and "err_interp_hertz" in rr[0]:
            ax[0].loglog(d, [float(r["err_interp_hertz"]) for r in rr], "-", color="0.55", marker="x",
                         ms=7, lw=1.2, label="Hertz joined linearly between the nodes (no solver error)", zorder=0)
        for r, di, ei in zip(rr, d, eh):
            ax[0].annotate(r["level"], (di, ei), textcoords="offset points", xytext=(4, 4),
                           fontsize=7, color=style[m]["color"])
        sub = [r for r in rr if int(r["level"]) < fine]
        d2 = np.array([float(r["dofs"]) for r in sub])
        ax[1].loglog(d2, [float(r["err_p_finest"]) for r in sub], "-", ms=7,
                     label="p vs level %d, %s" % (fine, m), **style[m])
        ax[1].loglog(d2, [float(r["err_u_finest"]) for r in sub], "--", ms=7, mfc="none",
                     label="u vs level %d, %s" % (fine, m), **style[m])
    d = np.array(sorted(set(alld)))
    for a_, ref, lab in ((ax[0], 3e-2, None), (ax[1], 3e-2, None)):
        a_.loglog(d, ref * (d / d[0]) ** -0.5, ":", color="0.4", lw=1, label="slope h (dofs$^{-1/2}$)")
    ax[1].loglog(d, 6e-3 * (d / d[0]) ** -1.0, "-.", color="0.4", lw=1, label="slope h$^2$ (dofs$^{-1}$)")
    ax[0].set_title("pressure error against Hertz, relative L2 on [0, 1.5a]")
    ax[1].set_title("errors against the finest level (%d) of the same method" % fine)
    for a_ in ax:
        a_.set_xlabel("dofs")
        a_.grid(alpha=0.3, which="both")
        a_.legend(fontsize=8.5)
    ax[0].set_ylabel("relative L2 error")
    fig.suptitle("S3 Hertz refinement (levels %s; level numbers beside the markers)"
                 % ", ".join(sorted({r["level"] for r in rows}, key=int)), fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
    print("wrote %s" % path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--levels", default="2", help="level(s) of the pressure figure, e.g. 1,2,4")
    ap.add_argument("--runs", default=os.path.join(SRC, "build", "hertz_study"))
    ap.add_argument("--docs", default=os.path.join(SRC, "docs"))
    args = ap.parse_args()
    runs = os.path.abspath(args.runs)
    os.makedirs(args.docs, exist_ok=True)
    levels = [int(v) for v in args.levels.split(",")]
    plot_pressure(runs, levels, os.path.join(args.docs, "hertz_pressure.png"))
    study = os.path.join(runs, "hertz_study.csv")
    if os.path.exists(study):
        plot_convergence(study, os.path.join(args.docs, "hertz_convergence.png"))
    else:
        print("no %s: skipped hertz_convergence.png (run tools/hertz_study.py)" % study)
    return 0


if __name__ == "__main__":
    sys.exit(main())
