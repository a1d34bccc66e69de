#!/usr/bin/python3
"""Adaptive meshes over a sweep of targets, on four scenes, either body
non-mortar, 1 and 2 ranks: what the loop gives when asked for more.

    /usr/bin/python3 tools/adapt_sweep.py [--out DIR] [--targets 0.1,0.04,...]
        [--scenes hertz,hertz_two,seed_patch,punch] [--ranks 1,2] [--png FILE] [--args "OPTIONS"]

Scenes (options files as they are, with -adapt_target T; the cap 5e4 dofs):
  hertz       options/hertz_adapt.opts       error: against Hertz, and against
  hertz_two   options/hertz_two_adapt.opts   the scene's own fine solution
  punch       options/punch.opts             against its own fine solution
  seed_patch  options/seed_patch_adapt.opts  (energy goal) against its own fine
                                             solution, the corners left out
Own fine solutions (each with the scene's own options and the same side
non-mortar as the run: the two choices are two models whose answers differ
by more than the loop's errors, printed per scene): on a fixed fine mesh
of the same bodies, hertz_graded.geo level 5 (grading 1.035, hmax 0.15; 298k
dofs), seed_patch.geo 32x (320 x 320 lower cells, 258k); the punch and
hertz_two adapted with the cap at 6e5 dofs, their last mesh (-adapt_keep last:
the mesh the loop keeps is the one of the smallest estimate, which may be the
sweep's own finest). Uniform meshes were not fine enough there: the punch's
127k-dof one is 5e-3 from the adapted one (its corner and zone edge need
more), hertz_two.geo level 4 (229k) with the lower cylinder non-mortar 4.7e-3
(its lower arc is the coarser).
The pressure is compared per unit x (the multiplier times ds/dx of the
non-mortar surface, so either side's pressure is the same function), joined
linearly, sampled at 6000 points of the zone ([0, 1.5 a] for the cylinders,
the punch's [0, 1.2 x the zone's end], S1's [0.275, 0.725]), relative L2.
Per point: dofs, meshes, the estimate of the goal, the errors, the pressure
ripple of the final mesh (summary pressure_ripple) and the largest over the
meshes with >= 20 active nodes, the whole-process wall time.
Writes DIR/adapt_sweep.csv, prints the table (markdown) and draws the plot
(error against dofs and against wall time per scene) into --png
(default docs/adapt_sweep.png)."""
import argparse
import csv
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))
import m2d  # noqa: E402

SRC = m2d.SRC
NGRID = 6000
SCENES = {
    "hertz": {"opts": "hertz_adapt", "swap": ["-contact_nonmortar", "block_top", "-contact_mortar", "cylinder_arc"],
              "ref": ("hertz_graded.geo", [("level", 5), ("grading", 1.035), ("hmax", 0.15)]), "zone": "hertz"},
    "hertz_two": {"opts": "hertz_two_adapt", "swap": ["-contact_nonmortar", "lower_arc", "-contact_mortar", "upper_arc"],
                  "ref": None, "zone": "hertz"},
    "punch": {"opts": "punch", "swap": ["-contact_nonmortar", "foundation_top", "-contact_mortar", "punch_bottom"],
              "ref": None, "zone": "punch"},
    "seed_patch": {"opts": "seed_patch_adapt", "swap": ["-contact_nonmortar", "lower_top", "-contact_mortar", "upper_bottom"],
                   "ref": ("seed_patch.geo", [("nlx", 320), ("nly", 320), ("nux", 161), ("nuy", 160)]), "zone": "s1"},
}


def die(msg):
    sys.stderr.write("adapt_sweep: %s\n" % msg)
    sys.exit(1)


def gmsh_mesh(geo, path, numbers):
    if os.path.exists(path):
        return path
    cmd = ["gmsh", "-2", "-format", "msh41", "-bin", "-v", "0", os.path.join(SRC, "meshes", geo), "-o", path + ".tmp"]
    for k, v in numbers:
        cmd += ["-setnumber", k, str(v)]
    r = m2d.launch(cmd, timeout=None)
    if r.rc != 0:
        die("gmsh failed: %s\n%s" % (r.cmdline, r.stderr[-2000:]))
    os.replace(path + ".tmp", path)
    return path


def run(name, args, out, ranks=1):
    """Run with -output_dir out/name; (summary, contact csv path, wall seconds)."""
    d = os.path.join(out, name)
    os.makedirs(d, exist_ok=True)
    summary = os.path.join(d, "summary.json")
    if os.path.exists(summary):
        os.remove(summary)
    cmd = m2d.command(list(args) + ["-output_dir", d, "-output_name", "sol", "-summary", summary, "-contact_monitor", "0"], ranks=ranks)
    r = m2d.launch(cmd, timeout=3600)
    if r.rc != 0:
        die("run failed (exit %s): %s\n%s" % (r.rc, r.cmdline, r.stderr[-2000:]))
    return m2d.read_json(summary), os.path.join(d, "sol_contact.csv"), r.wall


def pressure_x(csv_path):
    """(x, pressure per unit x) of the non-mortar nodes, sorted by x."""
    c = m2d.csv_columns(csv_path)
    o = np.argsort(c["x"])
    x, y, p = c["x"][o], c["y"][o], c["pressure"][o]
    dsdx = np.ones_like(x)
    if len(x) > 2:
        ds = np.hypot(np.gradient(x), np.gradient(y))
        dx = np.abs(np.gradient(x))
        dsdx = np.where(dx > 0, ds / np.maximum(dx, 1e-300), 1.0)
    return x, p * dsdx, c["active"][o] > 0


def window(kind, s, ref_csv):
    if kind == "hertz":
        return 0.0, 1.5 * s["hertz_a"]
    if kind == "s1":
        return 0.275, 0.725
    x, _, act = pressure_x(ref_csv)
    return 0.0, 1.2 * x[act].max()


def rel_l2(csv_path, ref_csv, lo, hi):
    x1, p1, _ = pressure_x(csv_path)
    x0, p0, _ = pressure_x(ref_csv)
    g = lo + (np.arange(NGRID) + 0.5) * (hi - lo) / NGRID
    a, b = np.interp(g, x1, p1), np.interp(g, x0, p0)
    return float(np.sqrt(np.sum((a - b) ** 2) / np.sum(b ** 2)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(SRC, "build", "adapt_sweep"))
    ap.add_argument("--targets", default="0.1,0.04,0.02,0.01,0.005,0.0025")
    ap.add_argument("--scenes", default="hertz,hertz_two,punch,seed_patch")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--png", default=os.path.join(SRC, "docs", "adapt_sweep.png"))
    ap.add_argument("--args", default="", help="more options for every adaptive run (not the references), space separated")
    args = ap.parse_args()
    os.makedirs(os.path.join(args.out, "ref"), exist_ok=True)
    targets = args.targets.split(",")
    rows = []
    t0 = time.time()
    for name in args.scenes.split(","):
        sc = SCENES[name]
        if sc["ref"]:  # the scene's own options on a fixed fine mesh, solved once (-mesh starts the loop there)
            geo, numbers = sc["ref"]
            msh = gmsh_mesh(geo, os.path.join(args.out, "ref", name + ".msh"), numbers)
            refargs = ["-mesh", msh, "-adapt_max_steps", "1", "-adapt_max_dofs", "100000000"]
        else:  # the scene adapted far past the sweep's cap
            refargs = ["-adapt_target", "1e-6", "-adapt_max_dofs", "600000", "-adapt_keep", "last"]
        refs = {}
        for side, extra in (("given", []), ("swapped", sc["swap"])):  # each side against its own fine solution
            rs, refs[side], rwall = run("ref_" + name + ("" if side == "given" else "_swapped"), ["-options_file", m2d.opts(sc["opts"]), "-output_vtu", "0"] + refargs + extra, args.out)
            print("reference %s, non-mortar %s: %d dofs, %.1f s%s" % (name, side, rs["dofs"], rwall, (", against Hertz %.3e" % rs["pressure_l2_rel"]) if "pressure_l2_rel" in rs else ""), flush=True)
            if side == "given":
                lo, hi = window(sc["zone"], rs, refs[side])
        print("reference %s: the two sides' fine solutions differ by %.2e (relative L2, the swapped against the given)" % (name, rel_l2(refs["swapped"], refs["given"], lo, hi)), flush=True)
        for side, extra in (("given", []), ("swapped", sc["swap"])):
            ref_csv = refs[side]
            for ranks in [int(r) for r in args.ranks.split(",")]:
                for t in targets:
                    s, csv_path, wall = run("%s_%s_%d_%s" % (name, side, ranks, t), ["-options_file", m2d.opts(sc["opts"]), "-adapt_target", t] + extra + args.args.split(), args.out, ranks)
                    steps = s["adapt"]
                    rip20 = max([a.get("pressure_ripple", 0) for a in steps if a.get("active_nodes", 0) >= 20] or [0])
                    row = {"scene": name, "nonmortar": side, "ranks": ranks, "target": float(t), "dofs": s["dofs"], "meshes": len(steps),
                           "dofs_sequence": "/".join(str(a["dofs"]) for a in steps), "stop": s["adapt_stop"],
                           "goal_estimate": steps[s["adapt_best_step"]]["goal_estimate"], "error_ref": rel_l2(csv_path, ref_csv, lo, hi),
                           "error_hertz": s.get("pressure_l2_rel", float("nan")), "ripple": s.get("pressure_ripple", float("nan")), "ripple_max20": rip20,
                           "active_steps": "/".join(str(a["iterations"]) for a in steps), "wall": wall}
                    rows.append(row)
                    print("%-10s %-7s %d rank  target %-6s %6d dofs (%s)  est %.2e  eRef %.2e  eHertz %.2e  ripple %.2f%% (max %.2f%%)  %.2f s" % (
                        name, side, ranks, t, row["dofs"], row["dofs_sequence"], row["goal_estimate"], row["error_ref"], row["error_hertz"],
                        100 * row["ripple"], 100 * rip20, wall), flush=True)
    path = os.path.join(args.out, "adapt_sweep.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("\n%s (%.0f s in all)\n" % (path, time.time() - t0))
    print("| scene | non-mortar | ranks | target | dofs | meshes | estimate | error (own fine) | error (Hertz) | ripple (max, >= 20 active) | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        eh = "%.2e" % r["error_hertz"] if r["error_hertz"] == r["error_hertz"] else "-"
        print("| %s | %s | %d | %g | %d | %d | %.2e | %.2e | %s | %.2f%% (%.2f%%) | %.2f |" % (r["scene"], r["nonmortar"], r["ranks"], r["target"], r["dofs"], r["meshes"],
              r["goal_estimate"], r["error_ref"], eh, 100 * r["ripple"], 100 * r["ripple_max20"], r["wall"]))
    plot(rows, args.png)


def plot(rows, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scenes = sorted(set(r["scene"] for r in rows), key=lambda n: list(SCENES).index(n))
    fig, ax = plt.subplots(2, len(scenes), figsize=(4.2 * len(scenes), 7.5), squeeze=False)
    for j, name in enumerate(scenes):
        for side, mk in (("given", "o"), ("swapped", "s")):
            for ranks, ls in ((1, "-"), (2, ":")):
                sel = [r for r in rows if r["scene"] == name and r["nonmortar"] == side and r["ranks"] == ranks]
                if not sel:
                    continue
                lab = "non-mortar %s, %d rank%s" % (side, ranks, "s" if ranks > 1 else "")
                ax[0, j].loglog([r["dofs"] for r in sel], [r["error_ref"] for r in sel], mk + ls, label=lab)
                ax[1, j].loglog([r["wall"] for r in sel], [r["error_ref"] for r in sel], mk + ls, label=lab)
        ax[0, j].set_title(name)
        ax[0, j].set_xlabel("dofs (final mesh)")
        ax[1, j].set_xlabel("wall time, whole process [s]")
        for i in range(2):
            ax[i, j].set_ylabel("pressure error against its own fine solution")
            ax[i, j].grid(True, which="both", alpha=0.3)
        ax[0, j].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print("plot: %s" % png)


if __name__ == "__main__":
    main()
