#!/usr/bin/python3
"""How close the adaptive loop's final mesh is to the smallest mesh that
reaches the target, on five scenes, before and after a change: the loop's
sizing rule measured (docs/adaptivity.md, "Sized to the target").

    /usr/bin/python3 tools/adapt_sizing.py [--exe2 OLD/mortar2d] [--repeat 3]
        [--scenes hertz,seed_patch,punch,roller,indenter] [--out DIR]

Scenes, each as its options file gives it (its own -adapt_target T):
  hertz       options/hertz_adapt.opts          T 1e-3 (pressure)   error against Hertz
  seed_patch  options/seed_patch_adapt.opts     T 1e-2 (energy)     against its fine solution
  punch       options/punch.opts                T 2e-3 (pressure)   against its fine solution
  roller      options/roller_adapt.opts         T 1e-3 (pressure)   against Hertz (pair 1)
  indenter    options/indenter.opts -geo indenter.geo -adapt
                                                T 1e-2 (energy, the defaults)  pair 1 against Hertz
The fine solutions are tools/adapt_sweep.py's (seed_patch: a 258k-dof
uniform mesh; the punch: adapted to 6e5 dofs, its last mesh).

Needed dofs (what a perfect loop would end on): the smallest mesh of a sweep
that reaches T - every mesh of every run below (both builds, every step)
whose estimate of the goal is <= T. The sweep: the scene at T x 2, 1.41,
1.19, 1, 0.84, 0.71, and at T with -adapt_growth 2, with this build (M2D_EXE
or build/mortar2d), and at T with --exe2 (the build before).
Per build at T: the final dofs, final/needed, meshes, the estimate, the
error, the loop's time (adapt_seconds, the files not included) and the
whole process's wall time (min over --repeat runs, the two builds
interleaved), the peak memory (memory_max_rank_mb); and on 2 ranks the same
meshes as on 1 (this build). Prints a markdown table."""
import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))
sys.path.insert(0, HERE)
import m2d  # noqa: E402
import adapt_sweep  # noqa: E402

SCENES = {
    "hertz": {"args": ["-options_file", m2d.opts("hertz_adapt")], "target": 1e-3, "error": "hertz"},
    "seed_patch": {"args": ["-options_file", m2d.opts("seed_patch_adapt")], "target": 1e-2, "error": "ref"},
    "punch": {"args": ["-options_file", m2d.opts("punch")], "target": 2e-3, "error": "ref"},
    "roller": {"args": ["-options_file", m2d.opts("roller_adapt")], "target": 1e-3, "error": "hertz"},
    "indenter": {"args": ["-options_file", m2d.opts("indenter"), "-geo", "indenter.geo", "-adapt"], "target": 1e-2, "error": "indenter"},
}
SWEEP = (2, 1.41, 1.19, 0.84, 0.71)
# options/indenter.opts: pair 1 against Hertz (R = 10, E* = 12.538, P = 0.1576)
IND_A = np.sqrt(4 * 0.1576 * 10 / (np.pi / ((1 - 0.3 ** 2) / 2e5 + (1 - 0.45 ** 2) / 10)))
IND_P0 = 2 * 0.1576 / (np.pi * IND_A)


def die(msg):
    sys.stderr.write("adapt_sizing: %s\n" % msg)
    sys.exit(1)


def run(tag, args, out, exe=None, ranks=1):
    """(summary, contact csv, wall seconds) of one run in out/tag."""
    d = os.path.join(out, tag)
    os.makedirs(d, exist_ok=True)
    summary = os.path.join(d, "summary.json")
    if os.path.exists(summary):
        os.remove(summary)
    cmd = m2d.command(list(args) + ["-output_dir", d, "-output_name", "sol", "-summary", summary, "-contact_monitor", "0", "-output_vtu", "0"], ranks=ranks, exe=exe)
    r = m2d.launch(cmd, timeout=3600)
    if r.rc != 0:
        die("run failed (exit %s): %s\n%s" % (r.rc, r.cmdline, r.stderr[-2000:]))
    return m2d.read_json(summary), os.path.join(d, "sol_contact.csv"), r.wall


def reference(name, out):
    """The scene's fine solution (adapt_sweep.py's), made once: (summary, csv)."""
    sc = adapt_sweep.SCENES[name]
    d = os.path.join(out, "ref_" + name)
    if os.path.exists(os.path.join(d, "summary.json")):
        return m2d.read_json(os.path.join(d, "summary.json")), os.path.join(d, "sol_contact.csv")
    if sc["ref"]:
        geo, numbers = sc["ref"]
        os.makedirs(os.path.join(out, "ref"), exist_ok=True)
        msh = adapt_sweep.gmsh_mesh(geo, os.path.join(out, "ref", name + ".msh"), numbers)
        extra = ["-mesh", msh, "-adapt_max_steps", "1", "-adapt_max_dofs", "100000000"]
    else:
        extra = ["-adapt_target", "1e-6", "-adapt_max_dofs", "600000", "-adapt_keep", "last"]
    s, csv_path, wall = run("ref_" + name, SCENES[name]["args"] + extra, out)
    print("reference %s: %d dofs, %.1f s" % (name, s["dofs"], wall), flush=True)
    return s, csv_path


def hertz_pair1(csv_path):
    """Pair 1's pressure against Hertz on [0, 1.5a] (relative L2, 6000 midpoints, nodes joined linearly in x)."""
    c = m2d.csv_columns(csv_path)
    sel = c["pair"] == 1
    x, p = c["x"][sel], c["pressure"][sel]
    o = np.argsort(x)
    g = (np.arange(6000) + 0.5) * 1.5 * IND_A / 6000
    ph = IND_P0 * np.sqrt(np.clip(1 - (g / IND_A) ** 2, 0, None))
    return float(np.sqrt(np.sum((np.interp(g, x[o], p[o]) - ph) ** 2) / np.sum(ph ** 2)))


def error(name, s, csv_path, ref):
    kind = SCENES[name]["error"]
    if kind == "hertz":
        return s["pressure_l2_rel"]
    if kind == "indenter":
        return hertz_pair1(csv_path)
    rs, rcsv = ref
    lo, hi = adapt_sweep.window(adapt_sweep.SCENES[name]["zone"], rs, rcsv)
    return adapt_sweep.rel_l2(csv_path, rcsv, lo, hi)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(m2d.SRC, "build", "adapt_sizing"))
    ap.add_argument("--exe2", help="the build before (its final meshes join the sweep)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scenes", default=",".join(SCENES))
    args = ap.parse_args()
    builds = [("after", None)] + ([("before", os.path.abspath(args.exe2))] if args.exe2 else [])
    rows = []
    for name in args.scenes.split(","):
        sc, T = SCENES[name], SCENES[name]["target"]
        ref = reference(name, args.out) if sc["error"] == "ref" else None
        meshes = []  # (dofs, goal estimate) of every mesh of every run
        for f in SWEEP:
            s, _, _ = run("%s_t%g" % (name, f), sc["args"] + ["-adapt_target", "%.6g" % (f * T)], args.out)
            meshes += [(a["dofs"], a["goal_estimate"]) for a in s["adapt"]]
        s, _, _ = run("%s_g2" % name, sc["args"] + ["-adapt_growth", "2"], args.out)
        meshes += [(a["dofs"], a["goal_estimate"]) for a in s["adapt"]]
        res = {}
        for k in range(args.repeat):  # the builds interleaved
            for b, exe in builds:
                s, csv_path, wall = run("%s_%s" % (name, b), sc["args"], args.out, exe=exe)
                r = res.setdefault(b, {"s": s, "err": error(name, s, csv_path, ref), "walls": [], "loops": []})
                r["walls"].append(wall)
                r["loops"].append(s["adapt_seconds"])
                meshes += [(a["dofs"], a["goal_estimate"]) for a in s["adapt"]]
        two, _, _ = run("%s_2ranks" % name, sc["args"], args.out, ranks=2)
        same = [a["dofs"] for a in two["adapt"]] == [a["dofs"] for a in res["after"]["s"]["adapt"]]
        reach = [d for d, e in meshes if e <= T]
        needed = min(reach) if reach else float("nan")
        print("%s: target %g, needed %s dofs (%d meshes in the sweep), 2 ranks the same meshes: %s" % (name, T, needed, len(meshes), same), flush=True)
        for b, _ in builds:
            r = res[b]
            s = r["s"]
            row = {"scene": name, "target": T, "build": b, "needed": needed, "dofs": s["dofs"], "meshes": "/".join(str(a["dofs"]) for a in s["adapt"]),
                   "estimate": s["adapt"][s["adapt_best_step"]]["goal_estimate"], "error": r["err"], "stop": s["adapt_stop"],
                   "loop": min(r["loops"]), "wall": min(r["walls"]), "memory": s["memory_max_rank_mb"], "same2": same}
            rows.append(row)
            print("  %-6s %7d dofs (%.2f x needed) %s, estimate %.3e, error %.3e, loop %.2f s, wall %.2f s, %.0f MB" % (
                b, row["dofs"], row["dofs"] / needed, row["meshes"], row["estimate"], row["error"], row["loop"], row["wall"], row["memory"]), flush=True)
    print("\n| scene | target | needed dofs | build | final dofs | final / needed | meshes | estimate | error | loop s | wall s | MB |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print("| %s | %g | %s | %s | %s | %.2f | %s | %.2e | %.2e | %.2f | %.2f | %.0f |" % (
            r["scene"], r["target"], format(r["needed"], ","), r["build"], format(r["dofs"], ","), r["dofs"] / r["needed"], r["meshes"],
            r["estimate"], r["error"], r["loop"], r["wall"], r["memory"]))


if __name__ == "__main__":
    main()
