#!/usr/bin/python3
"""Speed against error with adaptive meshes (issue 14, README "S5"): in one run,
on this machine, uniform, graded and adaptive meshes of Hertz (S3) and uniform
and adaptive meshes of S1, each point measured by the whole-process wall time
(min of --repeat runs; the summary's own time.total beside it).

Hertz (options/hertz.opts, error = the summary's pressure_l2_rel: relative L2
of the nodal pressure on [0, 1.5a] against Hertz):
  uniform   meshes/hertz.geo levels 0-5 (hertz_N.msh; level 5 must exist in
            M2D_MESHES or is made by tools/hertz_mesh.sh, ~1 min of gmsh)
  graded    meshes/hertz_graded.geo levels --graded (gmsh -setnumber level N,
            made here once; mesh generation is not part of the wall time,
            as for the uniform meshes)
  adaptive  options/hertz_adapt.opts as it is, and with -adapt_target T
            -adapt_max_dofs N (--adapt T:N,...): every remeshing (gmsh) is
            inside the wall time
  eRef      the same pressure against the program's own finest solution (a
            much finer graded mesh, hertz_graded.geo level --ref-level), both
            joined linearly in x and sampled at 6000 midpoints of [0, 1.5a]
            (as tools/hertz_study.py's eP)
The ratio the issue asks for: wall(hertz_adapt.opts) / wall(uniform level 5),
the two measured alternately, --repeat times each, min of each.

S1 (options/seed_patch.opts, errors as tools/s1_refinement.py against mortar
on a finer uniform mesh, --s1-ref: 32 = 320 x 320 lower cells, made here once):
  uniform   seed_patch 1x, 2x, 4x, 8x, 16x
  adaptive  options/seed_patch_adapt.opts with -adapt_target T (--s1-targets)
  p_L2 (pressure on the contact zone, corners included) and sy_L2 (sigma_y in
  the lower body's band y in [0.4, 0.5]), and the fitted rates r of
  error ~ dofs^-r (least squares in log-log) of each.

Also: steps per adapted mesh, 1 rank against 2 ranks for both adaptive scenes
(meshes and errors), and the estimator's effectivity on MMS (block_N, exact
solution) and Hertz levels 0-2 (against level 4's stresses, as
tests/test_estimator.py does with level 3).

Writes <out>/adapt_study.csv (one row per point) and docs/speed_vs_error_adapt.png
(--png): error against wall time and against dofs, Hertz and S1.

  /usr/bin/python3 tools/adapt_study.py [--out DIR] [--repeat 3] [--quick]
"""
import argparse
import csv
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))
sys.path.insert(0, HERE)
import m2d                                               # noqa: E402
import hertz_study                                       # noqa: E402
import s1_refinement as s1                               # noqa: E402

SRC = m2d.SRC
NGRID = hertz_study.NGRID


def die(msg):
    sys.stderr.write("adapt_study: %s\n" % msg)
    sys.exit(1)


def gmsh_mesh(geo, path, numbers):
    """path (a .msh) from meshes/<geo> with gmsh -setnumber NAME VALUE..., made once."""
    if os.path.exists(path) and os.path.getmtime(path) > os.path.getmtime(os.path.join(SRC, "meshes", geo)):
        return path
    cmd = ["gmsh", "-2", "-format", "msh41", os.path.join(SRC, "meshes", geo), "-o", path + ".tmp"]
    for k, v in numbers:
        cmd += ["-setnumber", k, str(v)]
    r = m2d.launch(cmd, timeout=None)
    if r.rc != 0:
        die("gmsh failed: %s\n%s" % (r.cmdline, r.stdout[-2000:] + r.stderr[-2000:]))
    os.replace(path + ".tmp", path)
    return path


class Point:
    """One configuration run `repeat` times: the last run's files, min walls."""

    def __init__(self, out, name, args, ranks=1):
        self.name, self.args, self.ranks = name, list(args), ranks
        self.dir = os.path.join(out, name)
        os.makedirs(self.dir, exist_ok=True)
        self.summary_path = os.path.join(self.dir, "s.json")
        self.walls, self.totals = [], []
        self.s = None

    def run(self):
        if os.path.exists(self.summary_path):
            os.remove(self.summary_path)
        args = self.args + ["-output_dir", self.dir, "-output_name", "r", "-summary", self.summary_path]
        r = m2d.launch(m2d.command(args, self.ranks), timeout=3600, stdout=os.path.join(self.dir, "log.txt"), merge=True)
        if r.rc != 0:
            die("run failed (exit %s): %s (log %s)" % (r.rc, r.cmdline, os.path.join(self.dir, "log.txt")))
        self.s = m2d.read_json(self.summary_path)
        self.walls.append(r.wall)
        self.totals.append(self.s.get("adapt_seconds", self.s["time"]["total"]))
        return self

    @property
    def wall(self):
        return min(self.walls)

    @property
    def total(self):
        """the program's own seconds: time.total, or adapt_seconds (every step) when adaptive"""
        return min(self.totals)

    @property
    def csv(self):
        return os.path.join(self.dir, "r_contact.csv")

    @property
    def h5(self):
        return os.path.join(self.dir, "r.h5")


def run_all(points, repeat, label):
    """every point `repeat` times, the points interleaved (a slow moment of the
    machine touches one repeat of each rather than every repeat of one)"""
    t0 = time.time()
    for k in range(repeat):
        for p in points:
            p.run()
        print("  %s: pass %d/%d done (%.0f s)" % (label, k + 1, repeat, time.time() - t0), flush=True)


def fit_rate(dofs, err):
    """r of err ~ dofs^-r, least squares in log-log"""
    x, y = np.log(np.asarray(dofs, float)), np.log(np.asarray(err, float))
    if len(x) < 2:
        return float("nan")
    return -np.polyfit(x, y, 1)[0]


def pressure_on_grid(csv_path, a):
    x, p = hertz_study.read_pressure(csv_path)
    xg = (np.arange(NGRID) + 0.5) * 1.5 * a / NGRID
    return np.interp(xg, x, p)


# ---------------------------------------------------------------- Hertz
def hertz(a, out):
    rows = []
    print("Hertz: meshes", flush=True)
    uni = {lev: Point(out, "hertz_uniform_%d" % lev, ["-options_file", m2d.opts("hertz"), "-mesh", hertz_study.mesh_path(lev)]) for lev in a.uniform}
    gdir = os.path.join(out, "meshes")
    os.makedirs(gdir, exist_ok=True)
    gra = {lev: Point(out, "hertz_graded_%d" % lev, ["-options_file", m2d.opts("hertz"), "-mesh", gmsh_mesh("hertz_graded.geo", os.path.join(gdir, "hertz_graded_%d.msh" % lev), [("level", lev)])]) for lev in a.graded}
    base = ["-options_file", m2d.opts("hertz_adapt"), "-geo_dir", os.path.join(SRC, "meshes")]
    ada = {0: Point(out, "hertz_adapt", base)}
    for t, n in a.adapt:
        ada[(t, n)] = Point(out, "hertz_adapt_%g_%d" % (t, n), base + ["-adapt_target", str(t), "-adapt_max_dofs", str(n)])
    def refpoint(level):
        nums = [("level", level)] + [(k, float(v)) for k, v in (x.split("=") for x in a.ref_numbers.split(",") if x)]
        tag = "_".join("%s%g" % kv for kv in nums)
        return Point(out, "hertz_ref_%s" % tag, ["-options_file", m2d.opts("hertz"), "-output_vtu", "0", "-mesh",
                     gmsh_mesh("hertz_graded.geo", os.path.join(gdir, "hertz_graded_%s.msh" % tag), nums)])
    ref, ref1 = refpoint(a.ref_level), refpoint(a.ref_level - 1)
    two = Point(out, "hertz_adapt_2ranks", base, ranks=2)

    # the ratio: level 5 and hertz_adapt.opts alternately
    top = max(a.uniform)
    print("Hertz: uniform level %d and hertz_adapt.opts alternately, %d times" % (top, a.repeat), flush=True)
    run_all([uni[top], ada[0]], a.repeat, "ratio")
    others = [p for lev, p in uni.items() if lev != top] + list(gra.values()) + [p for n, p in ada.items() if n != 0]
    print("Hertz: %d other points, %d times each" % (len(others), a.repeat), flush=True)
    run_all(others, a.repeat, "curves")
    print("Hertz: the reference (graded level %d) and 2 ranks, once" % a.ref_level, flush=True)
    ref.run()
    ref1.run()
    two.run()

    ha = ref.s["hertz_a"]
    pref = pressure_on_grid(ref.csv, ha)
    nref = math.sqrt((pref ** 2).sum())

    def row(kind, label, p):
        s = p.s
        e_ref = math.sqrt(((pressure_on_grid(p.csv, ha) - pref) ** 2).sum()) / nref
        ad = s.get("adapt", [])
        return {"scene": "hertz", "kind": kind, "label": label, "dofs": s["dofs"], "err": s["pressure_l2_rel"],
                "err2": e_ref, "wall": p.wall, "total": p.total, "meshes": len(ad) or 1,
                "steps": " ".join(str(x["iterations"]) for x in ad) if ad else str(s.get("iterations", "")),
                "seconds_gmsh": sum(x.get("seconds_gmsh", 0) for x in ad), "walls": " ".join("%.3f" % w for w in p.walls)}
    rows += [row("uniform", "level %d" % lev, p) for lev, p in sorted(uni.items())]
    rows += [row("graded", "level %d" % lev, p) for lev, p in sorted(gra.items())]
    rows += [row("adaptive", "hertz_adapt.opts" if n == 0 else "target %g, %d" % n, p) for n, p in sorted(ada.items(), key=lambda kv: kv[1].s["dofs"])]
    refrow = row("reference", "graded level %d" % a.ref_level, ref)
    ref1row = row("reference-1", "graded level %d" % (a.ref_level - 1), ref1)

    print("\nHertz (options/hertz.opts scene): err = pressure_l2_rel against Hertz; eRef = against the program's own finest solution\n"
          "(hertz_graded.geo level %d with %s: a finer far field than the graded rows, %d dofs, pressure_l2_rel %.3e);\n"
          "reference-1: the same one level coarser, eRef its distance to the reference; wall = whole process, min of %d; total = the program's own\n"
          "seconds (adapt_seconds when adaptive); steps = active-set steps per mesh; gmsh = seconds in gmsh (all meshes)"
          % (a.ref_level, a.ref_numbers, ref.s["dofs"], ref.s["pressure_l2_rel"], a.repeat))
    hdr = "%-11s %-17s %9s %10s %10s %8s %8s %6s %-16s %6s" % ("kind", "mesh", "dofs", "err", "eRef", "wall s", "total s", "meshes", "steps", "gmsh s")
    print(hdr + "\n" + "-" * len(hdr))
    for r in rows + [ref1row, refrow]:
        print("%-11s %-17s %9d %10.3e %10.3e %8.3f %8.3f %6d %-16s %6.3f" % (r["kind"], r["label"], r["dofs"], r["err"], r["err2"], r["wall"], r["total"], r["meshes"], r["steps"], r["seconds_gmsh"]))

    d = ada[0].s
    l5 = uni[top]
    print("\nThe issue's figures (Hertz):")
    print("  hertz_adapt.opts: %d dofs on the final mesh (<= 5e4: %s), pressure_l2_rel %.4e (<= 1.5e-3: %s), %d meshes, active-set steps %s"
          % (d["dofs"], "yes" if d["dofs"] <= 50000 else "NO", d["pressure_l2_rel"], "yes" if d["pressure_l2_rel"] <= 1.5e-3 else "NO",
             len(d["adapt"]), [x["iterations"] for x in d["adapt"]]))
    print("  wall: adaptive %.3f s (runs %s) / uniform level %d %.3f s (runs %s) = %.4f (<= 0.1: %s); the programs' own seconds: %.3f / %.3f = %.4f"
          % (ada[0].wall, ", ".join("%.2f" % w for w in ada[0].walls), top, l5.wall, ", ".join("%.2f" % w for w in l5.walls),
             ada[0].wall / l5.wall, "yes" if ada[0].wall / l5.wall <= 0.1 else "NO", ada[0].total, l5.total, ada[0].total / l5.total))
    print("  level %d: %d dofs, pressure_l2_rel %.4e: the adaptive run has %.1fx fewer dofs and %.1fx less wall time at %.2fx its error"
          % (top, l5.s["dofs"], l5.s["pressure_l2_rel"], l5.s["dofs"] / d["dofs"], l5.wall / ada[0].wall, d["pressure_l2_rel"] / l5.s["pressure_l2_rel"]))
    after = [x["iterations"] for r in [ada[0]] + list(ada.values()) for x in r.s["adapt"][1:]]
    print("  active-set steps on adapted meshes after the first, every adaptive run: max %d (<= 3: %s)" % (max(after), "yes" if max(after) <= 3 else "NO"))
    same = [x["dofs"] for x in two.s["adapt"]] == [x["dofs"] for x in d["adapt"]]
    dp = abs(two.s["pressure_l2_rel"] - d["pressure_l2_rel"]) / d["pressure_l2_rel"]
    print("  2 ranks: meshes %s (%s), pressure_l2_rel %.6e vs %.6e (relative difference %.1e)"
          % ([x["dofs"] for x in two.s["adapt"]], "the same" if same else "DIFFERENT", two.s["pressure_l2_rel"], d["pressure_l2_rel"], dp))
    ad = [r for r in rows if r["kind"] == "adaptive"]
    print("  adaptive against the program's finest: eRef %s at %s dofs; fitted rate dofs^-%.2f (eRef), dofs^-%.2f (err against Hertz)"
          % (", ".join("%.2e" % r["err2"] for r in ad), ", ".join("%d" % r["dofs"] for r in ad), fit_rate([r["dofs"] for r in ad], [r["err2"] for r in ad]),
             fit_rate([r["dofs"] for r in ad], [r["err"] for r in ad])))
    un = [r for r in rows if r["kind"] == "uniform"]
    print("  uniform level %d against the same reference: eRef %.2e" % (top, un[-1]["err2"]))
    for kind in ("uniform", "graded", "adaptive"):
        rr = [r for r in rows if r["kind"] == kind]
        fit = [r for r in rr if r["dofs"] >= 4000]
        print("  %-8s fitted rate of err (Hertz) dofs^-%.2f, of eRef dofs^-%.2f (points with >= 4000 dofs)" % (kind, fit_rate([r["dofs"] for r in fit], [r["err"] for r in fit]), fit_rate([r["dofs"] for r in fit], [r["err2"] for r in fit])))
    summary = {"ratio": ada[0].wall / l5.wall, "two_ranks_same": same and dp < 1e-8}
    return rows + [ref1row, refrow], summary


# ---------------------------------------------------------------- S1
def s1_errors(p, ref_p, lookup):
    x, pr = s1.read_pressure(p.csv)
    return (s1.pressure_error(x, pr, ref_p[0], ref_p[1], s1.X0, s1.X1), s1.sigma_y_error({"h5": p.h5}, lookup))


def s1_more(p, ref, ref_p, lookup):
    """corner-free errors (s1_refinement's p_L2int, sy_L2int) and the energy-norm
    error against the reference's stresses (estimator_study.reference_error),
    relative to the reference's energy norm"""
    import estimator_study as es
    x, pr = s1.read_pressure(p.csv)
    e_pi = s1.pressure_error(x, pr, ref_p[0], ref_p[1], s1.XI0, s1.XI1)
    e_si = s1.sigma_y_error({"h5": p.h5}, lookup, (s1.XI0, s1.XI1))
    err, _ = es.reference_error(p.h5, ref.h5, es.plane_strain_D(1e9, 0.3), sub=2)
    return e_pi, e_si, err / ref.s["estimator"]["energy_norm"]


def seed(a, out):
    print("\nS1: meshes", flush=True)
    gdir = os.path.join(out, "meshes")
    os.makedirs(gdir, exist_ok=True)
    n = a.s1_ref
    refmesh = gmsh_mesh("seed_patch.geo", os.path.join(gdir, "seed_patch_%d.msh" % n), [("nlx", 10 * n), ("nly", 10 * n), ("nux", 5 * n + 1), ("nuy", 5 * n)])
    sopts = ["-options_file", m2d.opts("seed_patch")]
    uni = {lev: Point(out, "s1_uniform_%d" % lev, sopts + ["-mesh", s1.mesh_path(lev)]) for lev in a.s1_uniform}
    base = ["-options_file", m2d.opts("seed_patch_adapt"), "-geo_dir", os.path.join(SRC, "meshes")]
    ada = {k: Point(out, "s1_adapt_%g" % k, base + ["-adapt_target", str(k)]) for k in a.s1_targets}
    ref = Point(out, "s1_ref_%d" % n, sopts + ["-mesh", refmesh, "-output_vtu", "0"])
    k2 = sorted(a.s1_targets)[len(a.s1_targets) // 2]
    two = Point(out, "s1_adapt_%g_2ranks" % k2, ada[k2].args, ranks=2)
    run_all(list(uni.values()) + list(ada.values()), a.repeat, "S1")
    ref.run()
    two.run()
    ref_p = s1.read_pressure(ref.csv)
    rc, _, rsy = s1.read_lower_sigma_y(ref.h5)
    lookup = s1.StructuredLookup(rc, rsy)
    rows = []
    for kind, pts in (("uniform", [(("%dx" % l), p) for l, p in sorted(uni.items())]), ("adaptive", [("target %g" % k, p) for k, p in sorted(ada.items(), reverse=True)])):
        for label, p in pts:
            e_p, e_sy = s1_errors(p, ref_p, lookup)
            e_pi, e_si, e_en = s1_more(p, ref, ref_p, lookup)
            ad = p.s.get("adapt", [])
            rows.append({"scene": "s1", "kind": kind, "label": label, "dofs": p.s["dofs"], "err": e_p, "err2": e_sy, "wall": p.wall, "total": p.total,
                         "meshes": len(ad) or 1, "steps": " ".join(str(x["iterations"]) for x in ad) if ad else str(p.s.get("iterations", "")),
                         "seconds_gmsh": sum(x.get("seconds_gmsh", 0) for x in ad), "walls": " ".join("%.3f" % w for w in p.walls),
                         "estimate": p.s.get("error_estimate", float("nan")), "p_int": e_pi, "sy_int": e_si, "energy": e_en})
    print("\nS1 (options/seed_patch.opts scene) against mortar at %dx (%d dofs): p_L2 = pressure on [0.25, 0.75], sy_L2 = sigma_y in the band\n"
          "y in [0.4, 0.5] (tools/s1_refinement.py), both relative to p; est = the program's relative energy-norm estimate" % (n, ref.s["dofs"]))
    hdr = "%-9s %-12s %7s %9s %9s %9s %9s %9s %9s %7s %7s %6s %-10s" % ("kind", "mesh", "dofs", "p_L2", "p_L2int", "sy_L2", "sy_L2int", "energy", "est", "wall s", "total s", "meshes", "steps")
    print(hdr + "\n" + "-" * len(hdr))
    for r in rows:
        print("%-9s %-12s %7d %9.3e %9.3e %9.3e %9.3e %9.3e %9.3e %7.3f %7.3f %6d %-10s" % (r["kind"], r["label"], r["dofs"], r["err"], r["p_int"], r["err2"], r["sy_int"], r["energy"], r["estimate"], r["wall"], r["total"], r["meshes"], r["steps"]))
    print("energy = ||sigma_ref - sigma_h|| in the energy norm over the mesh / ||sigma_ref|| (tests/estimator_study.py's reference_error); "
          "p_L2int, sy_L2int: x in [%.2f, %.2f] (the corners left out)" % (s1.XI0, s1.XI1))
    print("\nThe issue's figures (S1): fitted rates of error ~ dofs^-r")
    rates = {}
    for kind in ("uniform", "adaptive"):
        rr = [r for r in rows if r["kind"] == kind]
        dd = [r["dofs"] for r in rr]
        rates[kind] = {k: fit_rate(dd, [r[k] for r in rr]) for k in ("err", "p_int", "err2", "sy_int", "energy", "estimate")}
        print("  %-8s p_L2 r = %.2f, p_L2int r = %.2f, sy_L2 r = %.2f, sy_L2int r = %.2f, energy r = %.2f, estimate r = %.2f (%d points, %d to %d dofs)"
              % (kind, rates[kind]["err"], rates[kind]["p_int"], rates[kind]["err2"], rates[kind]["sy_int"], rates[kind]["energy"], rates[kind]["estimate"], len(rr), rr[0]["dofs"], rr[-1]["dofs"]))
    t = next(r for r in rows if r["label"] == "target %g" % k2)
    print("  2 ranks, target %g: meshes %s vs %s, p_L2 %.6e vs %.6e"
          % (k2, [x["dofs"] for x in two.s["adapt"]], [x["dofs"] for x in ada[k2].s["adapt"]], s1_errors(two, ref_p, lookup)[0], t["err"]))
    after = [x["iterations"] for p in ada.values() for x in p.s["adapt"][1:]]
    print("  active-set steps on adapted meshes after the first: max %d" % max(after + [0]))
    return rows, rates


# ---------------------------------------------------------------- effectivity
def effectivity(a):
    import estimator_study as es
    print("\nEffectivity (estimate / true error)", flush=True)
    mms = ["-bodies", "block", "-block_E", "1e3", "-block_nu", "0.3", "-dirichlet", "bottom:xy,right:xy,top:xy,left:xy", "-exact", "mms"]
    out = []
    for n in (4, 8, 16, 32, 64):
        s, _ = es.run("adapt_study_mms_%d" % n, mms + ["-mesh", m2d.mesh("block_%d" % n)])
        out.append(("MMS %dx%d" % (n, n), s["error_estimate"], s["estimator"]["true_error_rel"], s["estimator"]["effectivity"]))
    D = es.plane_strain_D(200.0, 0.3)
    rl = 4
    sref, href = es.run("adapt_study_hertz_%d" % rl, ["-options_file", m2d.opts("hertz"), "-mesh", hertz_study.mesh_path(rl)])
    for lvl in (0, 1, 2):
        s, h5 = es.run("adapt_study_hertz_%d" % lvl, ["-options_file", m2d.opts("hertz"), "-mesh", hertz_study.mesh_path(lvl)])
        err, _ = es.reference_error(h5, href, D, sub=2 ** (rl - lvl))
        tr = err / sref["estimator"]["energy_norm"]
        out.append(("Hertz level %d (vs level %d)" % (lvl, rl), s["error_estimate"], tr, s["error_estimate"] / tr))
    for name, est, tr, eff in out:
        print("  %-26s estimate %.4e  true %.4e  effectivity %.3f %s" % (name, est, tr, eff, "" if 0.5 <= eff <= 3 else "(outside [0.5, 3])"))
    return out


# ---------------------------------------------------------------- plot
def plot(rows, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 2, figsize=(12, 9.5))
    sty = {"uniform": ("o-", "C0"), "graded": ("s-", "C2"), "adaptive": ("^-", "C3")}
    for kind, (m, c) in sty.items():
        rr = sorted([r for r in rows if r["scene"] == "hertz" and r["kind"] == kind], key=lambda r: r["dofs"])
        if not rr:
            continue
        ax[0, 0].loglog([r["wall"] for r in rr], [r["err"] for r in rr], m, color=c, label=kind)
        ax[0, 1].loglog([r["dofs"] for r in rr], [r["err"] for r in rr], m, color=c, label=kind + " (against Hertz)")
        if kind == "adaptive":
            ax[0, 1].loglog([r["dofs"] for r in rr], [r["err2"] for r in rr], "^--", color=c, mfc="none", label="adaptive, against its finest solution")
            o = next(r for r in rr if r["label"] == "hertz_adapt.opts")
            for k in (0, 1):
                ax[0, k].plot(o["wall" if k == 0 else "dofs"], o["err"], "*", ms=16, color="k", label="options/hertz_adapt.opts" if k == 0 else None)
    for k in (0, 1):
        ax[0, k].axhline(1.5e-3, color="gray", ls=":", lw=1)
    ax[0, 0].set(xlabel="whole-process wall time [s] (min of repeats)", ylabel="pressure L2 error on [0, 1.5a]", title="Hertz (S3): error against wall time")
    ax[0, 1].set(xlabel="dofs", ylabel="pressure L2 error on [0, 1.5a]", title="Hertz (S3): error against dofs")
    for kind, (m, c) in sty.items():
        rr = sorted([r for r in rows if r["scene"] == "s1" and r["kind"] == kind], key=lambda r: r["dofs"])
        if not rr:
            continue
        ax[1, 0].loglog([r["wall"] for r in rr], [r["err"] for r in rr], m, color=c, label=kind + " p_L2")
        ax[1, 0].loglog([r["wall"] for r in rr], [r["energy"] for r in rr], m.replace("-", "--"), color=c, mfc="none", label=kind + " energy norm")
        ax[1, 1].loglog([r["dofs"] for r in rr], [r["err"] for r in rr], m, color=c, label=kind + " p_L2")
        ax[1, 1].loglog([r["dofs"] for r in rr], [r["energy"] for r in rr], m.replace("-", "--"), color=c, mfc="none", label=kind + " energy norm")
    ax[1, 0].set(xlabel="whole-process wall time [s] (min of repeats)", ylabel="error / p (against a finer uniform mesh)", title="S1: error against wall time")
    ax[1, 1].set(xlabel="dofs", ylabel="error / p (against a finer uniform mesh)", title="S1: error against dofs")
    for x in ax.flat:
        x.grid(True, which="both", alpha=0.3)
        x.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print("plot: %s" % png)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=os.path.join(SRC, "build", "adapt_study"))
    ap.add_argument("--png", default=os.path.join(SRC, "docs", "speed_vs_error_adapt.png"))
    ap.add_argument("--repeat", type=int, default=3, help="runs per timed point (min taken)")
    ap.add_argument("--uniform", default="0,1,2,3,4,5", help="Hertz uniform levels (the largest is the ratio's reference)")
    ap.add_argument("--graded", default="-1,0,1,2,3,4,5", help="hertz_graded.geo levels")
    ap.add_argument("--adapt", default="0.04:50000,0.02:50000,0.01:200000,0.005:200000", help="Hertz -adapt_target:-adapt_max_dofs pairs (besides hertz_adapt.opts)")
    ap.add_argument("--ref-level", type=int, default=6, help="hertz_graded.geo level of the Hertz reference")
    ap.add_argument("--ref-numbers", default="grading=1.035,hmax=0.15", help="the reference's other hertz_graded.geo parameters (a finer far field)")
    ap.add_argument("--s1-uniform", default="1,2,4,8,16")
    ap.add_argument("--s1-targets", default="0.1,0.05,0.03,0.02,0.01", help="S1 -adapt_target values (seed_patch_adapt.opts' -adapt_max_dofs)")
    ap.add_argument("--s1-ref", type=int, default=32, help="S1 reference: seed_patch.geo refined N times (10N x 10N lower cells)")
    ap.add_argument("--quick", action="store_true", help="small sets, 1 repeat (a check of the tool, not of the figures)")
    ap.add_argument("--skip", default="", help="comma list of parts to skip: hertz, s1, effectivity")
    a = ap.parse_args()
    if a.quick:
        a.repeat, a.uniform, a.graded, a.adapt, a.ref_level = 1, "0,1,2", "-1,0", "0.04:50000", 1
        a.s1_uniform, a.s1_targets, a.s1_ref = "1,2,4", "0.1,0.05", 16
    a.uniform = [int(x) for x in a.uniform.split(",")]
    a.graded = [int(x) for x in a.graded.split(",") if x]
    a.adapt = [(float(x.split(":")[0]), int(x.split(":")[1])) for x in a.adapt.split(",") if x]
    a.s1_uniform = [int(x) for x in a.s1_uniform.split(",")]
    a.s1_targets = [float(x) for x in a.s1_targets.split(",") if x]
    skip = set(a.skip.split(","))
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    t0 = time.time()
    rows = []
    if "hertz" not in skip:
        rows += hertz(a, out)[0]
    if "s1" not in skip:
        rows += seed(a, out)[0]
    if "effectivity" not in skip:
        effectivity(a)
    path = os.path.join(out, "adapt_study.csv")
    cols = ["scene", "kind", "label", "dofs", "err", "err2", "p_int", "sy_int", "energy", "wall", "total", "meshes", "steps", "seconds_gmsh", "walls"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols + ["note"])
        for r in rows:
            w.writerow([("%.6e" % r[c]) if isinstance(r.get(c), float) else r.get(c, "") for c in cols]
                       + ["hertz: err = pressure_l2_rel vs Hertz, err2 = vs own finest; s1: err = p_L2, err2 = sy_L2"])
    if rows:
        plot(rows, a.png)
    print("\ntable: %s; %.0f s in all" % (path, time.time() - t0))
    return 0


if __name__ == "__main__":
    sys.exit(main())
