#!/usr/bin/env python3
"""Cattaneo-Mindlin study (options/cattaneo.opts, docs/results.md, S7): the errors
against the half-space formulas and the run's time per mesh level, the time
of the whole history against its first stage solved in one step, and two
plots for docs/results.md: the shear traction q(x) per level against
Cattaneo-Mindlin's, and the shear unloaded to 0 and reversed against
Mindlin's slip annuli.

    /usr/bin/python3 tools/cattaneo_study.py [--levels 0,1,2,3] [--repeat 3] [--plots docs]
        [--geo rfine=0.11,grading=1]   (graded meshes of one's own: cattaneo.geo's parameters)
        [--args "-contact_reach 0.02"] (further options for every run)

Levels above 3 are meshed here (gmsh) into the build's meshes directory.
Times are the least of --repeat runs (the machine is shared); the ratio is
of two runs made one after the other."""
import argparse
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import m2d  # noqa: E402

MU = 0.3


def mesh_of(level, params=()):
    """cattaneo_N.msh, or with params (NAME=VALUE of cattaneo.geo's parameters) a mesh of its own"""
    path = m2d.mesh("cattaneo_%g%s" % (level, "".join("_%s%s" % tuple(p.split("=")) for p in params)))
    if params or not os.path.exists(path):
        setn = [x for p in params for x in ["-setnumber"] + p.split("=")]
        subprocess.run(["gmsh", "-2", "-format", "msh41", "-v", "0", "-setnumber", "level", str(level)] + setn + [os.path.join(m2d.SRC, "meshes", "cattaneo.geo"), "-o", path], check=True)
    return path


def best(name, args, repeat):
    runs = [m2d.solve(name, args) for _ in range(repeat)]
    return min(runs, key=lambda s: s["time"]["total"])


def hertz(P):
    """a, p0 of plane-strain Hertz for R = 1, E = 200, nu = 0.3 on both sides"""
    Es = 1 / (2 * (1 - 0.09) / 200)
    a = math.sqrt(4 * P / (math.pi * Es))
    return a, 2 * P / (math.pi * a)


def cattaneo(x, a, p0, c, mu=MU):
    q = mu * p0 * math.sqrt(max(0.0, 1 - x * x / (a * a)))
    if abs(x) < c:
        q -= mu * p0 * (c / a) * math.sqrt(1 - x * x / (c * c))
    return q


def step_rows(csv, step):
    rows = [r for r in m2d.read_csv(csv) if int(r["step"]) == step]
    return sorted(rows, key=lambda r: r["x"])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--levels", default="0,1,2,3")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--args", default="", help="further options of the program for every run, e.g. '-contact_reach 0.02'")
    ap.add_argument("--geo", default="", help="cattaneo.geo's parameters for every level, e.g. rfine=0.11,grading=4 (default: the shipped meshes)")
    ap.add_argument("--plots", default="", help="directory for cattaneo_shear.png and cattaneo_reversal.png (none: no plots)")
    opt = ap.parse_args()
    levels = [float(x) if "." in x else int(x) for x in opt.levels.split(",")]   # gmsh takes a fractional level
    params = [p for p in opt.geo.split(",") if p]
    base = ["-options_file", m2d.opts("cattaneo"), "-contact_monitor", "0", "-output", "csv,summary"] + opt.args.split()
    print("| level | dofs | pressure vs Hertz: stage 1 / end (its even part) | c computed / exact | shear (even part) | odd part | active-set steps per load step | both stages (s) | stage 1 in one step (s) | ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    shear = {}
    for level in levels:
        name = "cattaneo_study_%g" % level
        msh = mesh_of(level, params)
        s = best(name, base + ["-mesh", msh], opt.repeat)
        one = best(name + "_one", base + ["-mesh", msh, "-load_stages", "1", "-load_steps", "1", "-output", "summary"], opt.repeat)
        its = "+".join(str(x["iterations"]) for x in s["load_steps"])
        print("| %g | %d | %.2f%% / %.2f%% (%.2f%%) | %.5f / %.5f (%+.2f%%) | %.2f%% | %.2f%% | %s | %.3f | %.3f (%d) | %.2f |" % (
            level, s["dofs"], 100 * one["pressure_l2_rel"], 100 * s["pressure_l2_rel"], 100 * s["pressure_even_l2_rel"], s["stick_half_width"], s["stick_half_width_exact"], 100 * (s["stick_half_width"] / s["stick_half_width_exact"] - 1),
            100 * s["shear_l2_rel"], 100 * s["shear_odd_rel"], its, s["time"]["total"], one["time"]["total"], one["iterations"], s["time"]["total"] / one["time"]["total"]))
        shear[level] = (os.path.join(m2d.workdir(name), "cattaneo_contact.csv"), s)
    if not opt.plots:
        return
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for level, (csv, s) in shear.items():
        rows = step_rows(csv, len(s["load_steps"]))
        x = [r["x"] for r in rows if abs(r["x"]) < 0.15]
        q = [r["traction_t"] for r in rows if abs(r["x"]) < 0.15]
        ax.plot(x, q, ".-", ms=3, lw=0.7, label="level %g (%d dofs)" % (level, s["dofs"]))
    s = shear[levels[-1]][1]
    a, p0 = hertz(s["contact_force"])
    c = s["stick_half_width_exact"]
    xs = [-0.15 + 0.3 * i / 600 for i in range(601)]
    ax.plot(xs, [cattaneo(x, a, p0, c) for x in xs], "k-", lw=1.2, label="Cattaneo-Mindlin, c = %.4f" % c)
    ax.plot(xs, [MU * p0 * math.sqrt(max(0, 1 - x * x / (a * a))) for x in xs], "k:", lw=0.8, label="MU p(x)")
    ax.set_xlabel("x")
    ax.set_ylabel("shear traction q")
    ax.legend(fontsize=8)
    ax.set_title("Cattaneo-Mindlin: Q = %.3f, MU P = %.3f" % (abs(s["tangential_force"]), MU * s["contact_force"]))
    fig.tight_layout()
    fig.savefig(os.path.join(opt.plots, "cattaneo_shear.png"), dpi=110)
    # the shear unloaded to 0 and reversed: Mindlin's q = q* - q'', c' = a sqrt(1 - (Q* - Q)/(2 MU P))
    level = 2 if 2 in levels else levels[-1]
    name = "cattaneo_study_reverse"
    s = m2d.solve(name, base + ["-mesh", mesh_of(level), "-load_stages", "4", "-stage3_dirichlet", "cylinder_top:x:-0.00445", "-stage4_dirichlet", "cylinder_top:x:-0.00445"])
    csv = os.path.join(m2d.workdir(name), "cattaneo_contact.csv")
    fig, ax = plt.subplots(figsize=(7, 4.2))
    steps = s["load_steps"]
    k2 = [i for i, x in enumerate(steps) if x["stage"] == 2][-1]
    P, Qs = steps[k2]["normal_force"][0], steps[k2]["tangential_force"][0]
    a, p0 = hertz(P)
    cs = a * math.sqrt(1 - abs(Qs) / (MU * P))
    for stage, style in ((2, "C0"), (3, "C1"), (4, "C2")):
        k = [i for i, x in enumerate(steps) if x["stage"] == stage][-1]
        Q = steps[k]["tangential_force"][0]
        rows = [r for r in step_rows(csv, k + 1) if abs(r["x"]) < 0.15]
        ax.plot([r["x"] for r in rows], [r["traction_t"] for r in rows], ".", color=style, ms=4, label="stage %d: Q = %+.4f (computed)" % (stage, Q))
        cp = a * math.sqrt(max(0, 1 - (Qs - Q) / (2 * MU * P))) if stage > 2 else None
        exact = [cattaneo(x, a, p0, cs) - (cattaneo(x, a, p0, cp, 2 * MU) if cp is not None else 0) for x in xs]
        ax.plot(xs, exact, "-", color=style, lw=1, label="Mindlin, Q = %+.4f" % Q)
    ax.set_xlabel("x")
    ax.set_ylabel("shear traction q")
    ax.legend(fontsize=7)
    ax.set_title("Unloading the shear to 0 and reversing it (level %g)" % level)
    fig.tight_layout()
    fig.savefig(os.path.join(opt.plots, "cattaneo_reversal.png"), dpi=110)
    print("plots: %s, %s" % (os.path.join(opt.plots, "cattaneo_shear.png"), os.path.join(opt.plots, "cattaneo_reversal.png")))


if __name__ == "__main__":
    main()
