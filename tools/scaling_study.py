#!/usr/bin/python3
"""Scaling study of the two contact solver paths past 2 ranks (issue "Beyond 2
ranks"): the condensed (direct) path and the iterative path, on the S3 Hertz
scene (options/hertz.opts: dual multipliers) at several levels and rank
counts.

    /usr/bin/python3 tools/scaling_study.py [--levels 2,3,4,5] [--ranks 1,2,4,8]
        [--paths condensed,iterative] [--mesh-ranks 1,2,4] [--mesh-level 5]
        [--out build/scaling]

Per run (one directory each under OUT): the summary JSON, -log_view, the contact CSV and the HDF5 fields. The
CSV (OUT/scaling.csv) has per run: level, dofs, path, ranks, active-set steps,
the most Krylov iterations of one step and all of them, preconditioner
set-ups, MUMPS flops (all ranks and the largest rank's share), the dense
interface's unknowns, flops of the busiest rank (PETSc's count: the Krylov
path's work; MUMPS' own is in the factor columns), peak memory of the
largest rank (summary memory_max_rank_mb), seconds per stage, wall time of
the process, the load average before the run.

Ranks beyond the machine's cores are oversubscribed (said in the output):
their wall times measure the machine, not the method; memory per rank and
the work per rank (flops, iterations, interface sizes) do not depend on it.

Checks printed with every level: the iterative path against the condensed
path on one rank - the same final active set (the steps that lead there
may differ: docs/scaling.md), the contact
pressures equal to 1e-8 of their peak (the contact CSVs).

--input h5: every run reads PETSc's HDF5 form of the level's mesh (written once
with -mesh_save): every rank loads its part and DMPlexDistribute partitions,
so no rank holds the whole mesh (msh: rank 0 reads the gmsh file and
partitions with METIS).

--mesh-ranks: the mesh stage at --mesh-level from the gmsh file (rank 0 reads
and partitions) and from PETSc's HDF5 mesh on those rank counts (the tied
problem solved by the iterative path: one CG solve, memory per rank).

Last, a model (least squares on the runs, printed as an ESTIMATE): memory per
rank and work per rank of each path for 1e8 dofs on 64 and 256 ranks.
"""
import argparse
import csv
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import m2d  # noqa: E402


def log_flops(path):
    """(max over ranks, total) of PETSc's flop count in a -log_view file."""
    with open(path) as f:
        for line in f:
            m = re.match(r"\s*Flops?:\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)", line)
            if m:
                return float(m.group(1)), float(m.group(4))
    return float("nan"), float("nan")


def run_case(out, tag, args, ranks):
    d = os.path.join(out, tag)
    os.makedirs(d, exist_ok=True)
    summ = os.path.join(d, "summary.json")
    logv = os.path.join(d, "log_view.txt")
    for f in (summ, logv):
        if os.path.exists(f):
            os.remove(f)
    load = os.getloadavg()[0]
    r = m2d.launch(m2d.command(list(args) + ["-output_dir", d, "-output_name", "sol", "-output_vtu", "0",
                                             "-contact_monitor", "0", "-summary", summ, "-log_view", ":" + logv], ranks), timeout=7200)
    if r.rc != 0:
        sys.stderr.write("run %s failed (exit %s): %s\n%s\n" % (tag, r.rc, r.cmdline, r.stderr[-3000:]))
        raise SystemExit(1)
    s = m2d.read_json(summ)
    fmax, ftot = log_flops(logv)
    return s, fmax, ftot, r.wall, load, os.path.join(d, "sol_contact.csv")


def h5_mesh(out, msh, level):
    """PETSc's HDF5 form of a gmsh mesh (-mesh_save, once)"""
    h5 = os.path.join(out, "hertz_%d.h5" % level)
    if not os.path.exists(h5) or os.path.getmtime(h5) < os.path.getmtime(msh):
        run_case(out, "mesh_save_%d" % level, ["-options_file", m2d.opts("hertz"), "-mesh", msh, "-mesh_save", h5, "-contact_unilateral", "0", "-strain_limit", "1e300"], 1)
    return h5


def fit(xs, ys):
    """least squares y = a + b x"""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else 0.0
    return my - b * mx, b


def tables(rows, floor, cores):
    """the per-run table (markdown)"""
    print("\nPer level and rank count (memory per rank above the floor, the floor in brackets; work per rank: the busiest "
          "rank's flops - MUMPS' factorization for condensed, PETSc's count for iterative, which does not see BoomerAMG's own):")
    print("| level | dofs | path | ranks | steps | CG its (max) | interface | memory/rank MB | flops/rank | solve s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        work = r["mumps_flops_max_rank"] if r["path"] == "condensed" else r["petsc_flops_max_rank"]
        print("| %d | %d | %s | %d%s | %d | %s | %s | %.0f (+%.0f) | %.2e | %.2f |" % (
            r["level"], r["dofs"], r["path"], r["ranks"], "*" if r["oversubscribed"] else "", r["steps"],
            r["ksp_its_max"] if r["path"] == "iterative" else "-", r["interface_unknowns"] or "-",
            r["memory_max_rank_mb"] - floor[r["ranks"]], floor[r["ranks"]], work, r["solve_s"]))
    print("(* oversubscribed: %d cores)" % cores)


def model(rows, floor, cores, paths):
    """Least squares over the runs above 1e5 dofs, extrapolated to 1e8 dofs on
    64 and 256 ranks (an ESTIMATE, far beyond the data). Memory per rank above
    the floor ~ c (N/P)^b, plus, on the condensed path, the dense interface
    8 I^2 bytes with I ~ k P^alpha N^beta. Time per rank: condensed, the
    busiest rank's MUMPS flops (~ c (N/P)^b) plus the interface's I^3/3, at
    the flop rate of the 1-rank runs; iterative, the solve seconds of the runs
    that were not oversubscribed ~ c (N/P)^b (iterations stay flat; the
    communication of 64 ranks is not in the data)."""
    import numpy as np
    print("\nModel (least squares over the runs with more than 1e5 dofs; an ESTIMATE, extrapolated far beyond the data):")
    out, fits = {}, {}
    for path in paths:
        R = [r for r in rows if r["path"] == path and r["dofs"] > 1e5]
        if len(R) < 3:
            print("  %s: too few runs above 1e5 dofs for a fit" % path)
            continue
        xs = [math.log(r["dofs"] / r["ranks"]) for r in R]
        dense = [8.0 * r["interface_unknowns"] ** 2 / 2 ** 20 for r in R]
        ys = [math.log(max(r["memory_max_rank_mb"] - floor[r["ranks"]] - d, 1e-3)) for r, d in zip(R, dense)]
        cm, bm = fit(xs, ys)
        text = "  %s: memory/rank = floor + %.3g (N/P)^%.2f MB" % (path, math.exp(cm), bm)
        I = lambda N, P: 0.0  # noqa: E731
        if path == "condensed":
            Rp = [r for r in R if r["ranks"] > 1]
            A = np.array([[1.0, math.log(r["ranks"]), math.log(r["dofs"])] for r in Rp])
            k, al, be = np.linalg.lstsq(A, np.array([math.log(r["interface_unknowns"]) for r in Rp]), rcond=None)[0]
            I = lambda N, P, k=k, al=al, be=be: math.exp(k) * P ** al * N ** be  # noqa: E731
            cw, bw = fit(xs, [math.log(r["mumps_flops_max_rank"]) for r in R])
            one = [r for r in R if r["ranks"] == 1]
            rate = max(r["mumps_flops_max_rank"] / r["solve_s"] for r in one)
            text += " + 8 I^2 bytes, I = %.3g P^%.2f N^%.2f; MUMPS flops/rank %.3g (N/P)^%.2f, at %.2g flop/s (1 rank)" % (math.exp(k), al, be, math.exp(cw), bw, rate)
            secs = lambda N, P, cw=cw, bw=bw, rate=rate, I=I: (math.exp(cw) * (N / P) ** bw + I(N, P) ** 3 / 3.0) / rate  # noqa: E731
            fits[path] = secs
        else:
            Rt = [r for r in R if r["ranks"] <= cores]
            ct, bt = fit([math.log(r["dofs"] / r["ranks"]) for r in Rt], [math.log(r["solve_s"]) for r in Rt])
            text += "; solve seconds/rank %.3g (N/P)^%.2f (runs on <= %d ranks)" % (math.exp(ct), bt, cores)
            secs = lambda N, P, ct=ct, bt=bt: math.exp(ct) * (N / P) ** bt  # noqa: E731
            fits[path] = secs
        print(text)
        for N, P in ((1e8, 64), (1e8, 256)):
            mem = math.exp(cm) * (N / P) ** bm + 8.0 * I(N, P) ** 2 / 2 ** 20
            out[(path, P)] = (mem / 1024, secs(N, P), I(N, P))
    if "condensed" in fits and "iterative" in fits:
        crossover(fits)
    print("\n| ESTIMATE, 1e8 dofs | memory per rank, 64 ranks | solve time, 64 ranks | memory per rank, 256 ranks | solve time, 256 ranks |")
    print("|---|---|---|---|---|")
    for path in paths:
        if (path, 64) not in out:
            continue
        cells = []
        for P in (64, 256):
            mem, t, i = out[(path, P)]
            cells += ["%.3g GB%s" % (mem, " (dense interface %.2g unknowns)" % i if i else ""), "%.2g s" % t]
        print("| %s | %s |" % (path, " | ".join(cells)))


def crossover(fits):
    """where the fitted solve times cross: per dofs N, the estimate of both
    paths on P ranks and the fewest ranks (powers of 2 up to 1024) on which
    the iterative path's is below the condensed path's (an ESTIMATE)"""
    Ps = [2 ** k for k in range(11)]
    print("\nCrossover (ESTIMATE from the fits above): solve seconds per path, condensed / iterative, and the fewest ranks where the iterative path is faster")
    print("| dofs | " + " | ".join("%d ranks" % P for P in (1, 2, 8, 64, 256)) + " | iterative faster from |")
    print("|---|" + "---|" * 6)
    for N in (1e5, 1e6, 1e7, 1e8):
        cells = ["%.3g / %.3g" % (fits["condensed"](N, P), fits["iterative"](N, P)) for P in (1, 2, 8, 64, 256)]
        first = next((P for P in Ps if fits["iterative"](N, P) < fits["condensed"](N, P)), None)
        print("| %.0e | %s | %s |" % (N, " | ".join(cells), "%d ranks" % first if first else "beyond 1024 ranks"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--levels", default="2,3,4,5")
    ap.add_argument("--ranks", default="1,2,4,8")
    ap.add_argument("--paths", default="condensed,iterative")
    ap.add_argument("--mesh-ranks", default="1,2,4")
    ap.add_argument("--mesh-level", type=int, default=5)
    ap.add_argument("--input", choices=("msh", "h5"), default="msh",
                    help="msh: rank 0 reads the gmsh file; h5: PETSc's HDF5 mesh (written once with -mesh_save), every rank loads its part")
    ap.add_argument("--out", default=os.path.join(m2d.SRC, "build", "scaling"))
    ap.add_argument("--model-only", action="store_true", help="print the tables and the model from OUT/scaling.csv of an earlier run")
    a = ap.parse_args()
    levels = [int(x) for x in a.levels.split(",") if x]
    ranks = [int(x) for x in a.ranks.split(",") if x]
    paths = [x for x in a.paths.split(",") if x]
    cores = os.cpu_count()
    os.makedirs(a.out, exist_ok=True)
    if a.model_only:
        with open(os.path.join(a.out, "scaling.csv")) as f:
            rows = [{k: (v if k == "path" else float(v)) for k, v in r.items()} for r in csv.DictReader(f)]
        for r in rows:
            for k in ("level", "dofs", "ranks", "oversubscribed", "steps", "ksp_its_max", "interface_unknowns"):
                r[k] = int(r[k])
        floor = {p: m2d.read_json(os.path.join(a.out, "floor_%d" % p, "summary.json"))["memory_max_rank_mb"] for p in sorted({r["ranks"] for r in rows})}
        tables(rows, floor, cores)
        model(rows, floor, cores, [p for p in paths if any(r["path"] == p for r in rows)])
        return
    print("scaling study: levels %s, ranks %s (this machine has %d cores: more ranks are oversubscribed), paths %s" % (levels, ranks, cores, paths), flush=True)

    # the program's own memory floor per rank count (PETSc, MPI, libraries)
    floor = {}
    for p in ranks:
        s, _, _, _, _, _ = run_case(a.out, "floor_%d" % p, ["-options_file", m2d.opts("block")], p)
        floor[p] = s["memory_max_rank_mb"]
    print("memory floor (a 4x4 block, no contact): " + ", ".join("%d rank(s) %.0f MB" % (p, floor[p]) for p in ranks), flush=True)

    rows = []
    fields = ["level", "dofs", "path", "ranks", "oversubscribed", "steps", "active", "ksp_its_max", "ksp_its_total", "pc_setups",
              "mumps_flops", "mumps_flops_max_rank", "interface_unknowns", "petsc_flops_max_rank", "petsc_flops_total",
              "memory_max_rank_mb", "mesh_s", "assembly_s", "solve_s", "total_s", "wall_s", "load"]
    for lv in levels:
        mesh = m2d.hertz_mesh(lv)
        if a.input == "h5":
            mesh = h5_mesh(a.out, mesh, lv)
        ref_csv = ref = None
        for path in paths:
            for p in ranks:
                tag = "L%d_%s_%dr" % (lv, path, p)
                s, fmax, ftot, wall, load, ccsv = run_case(a.out, tag, ["-options_file", m2d.opts("hertz"), "-mesh", mesh, "-kkt_path", path], p)
                row = dict(level=lv, dofs=s["dofs"], path=path, ranks=p, oversubscribed=int(p > cores), steps=s["iterations"], active=s["active_nodes"],
                           ksp_its_max=s["ksp_iterations_max"], ksp_its_total=s.get("ksp_iterations_total", 0), pc_setups=s.get("pc_setups", 0),
                           mumps_flops=s.get("factor_flops", 0), mumps_flops_max_rank=s.get("factor_flops_max_rank", 0),
                           interface_unknowns=s.get("interface_unknowns", 0), petsc_flops_max_rank=fmax, petsc_flops_total=ftot,
                           memory_max_rank_mb=s["memory_max_rank_mb"], mesh_s=s["time"]["mesh"], assembly_s=s["time"]["assembly"],
                           solve_s=s["time"]["solve"], total_s=s["time"]["total"], wall_s=wall, load=load)
                rows.append(row)
                print("L%d %-9s %d rank(s)%s: %8d dofs, %2d steps, CG its max %3d, interface %5d, memory/rank %6.0f MB, solve %7.2f s, wall %7.2f s" % (
                    lv, path, p, " (oversubscribed)" if p > cores else "", s["dofs"], s["iterations"], s["ksp_iterations_max"],
                    row["interface_unknowns"], s["memory_max_rank_mb"], s["time"]["solve"], wall), flush=True)
                cols = m2d.csv_columns(ccsv)
                if ref is None:
                    ref, ref_csv = s, cols
                    continue
                dp = max(abs(x - y) for x, y in zip(cols["pressure"], ref_csv["pressure"])) / max(abs(x) for x in ref_csv["pressure"])
                same = s["active_nodes"] == ref["active_nodes"] and list(cols["active"]) == list(ref_csv["active"])
                print("    against the condensed path on 1 rank (%d steps): %s active set, pressure %.1e of the peak %s" % (ref["iterations"], "same" if same else "DIFFERENT", dp, "ok" if same and dp < 1e-8 else "NOT EQUAL"), flush=True)
    with open(os.path.join(a.out, "scaling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)

    tables(rows, floor, cores)
    model(rows, floor, cores, paths)

    # ---------------------------------------------------------------- the mesh stage
    mranks = [int(x) for x in a.mesh_ranks.split(",") if x]
    if mranks:
        mesh = m2d.hertz_mesh(a.mesh_level)
        h5 = h5_mesh(a.out, mesh, a.mesh_level)
        print("\nMesh stage at level %d (seconds, max over ranks; memory per rank above the floor):" % a.mesh_level)
        print("| input | " + " | ".join("%d rank(s)" % p for p in mranks) + " |")
        print("|---|" + "---|" * len(mranks))
        for name, m in (("gmsh .msh (rank 0 reads)", mesh), ("PETSc HDF5 (every rank loads)", h5)):
            cells = []
            for p in mranks:
                s, _, _, _, _, _ = run_case(a.out, "mesh_%s_%d" % ("h5" if m == h5 else "msh", p), ["-options_file", m2d.opts("hertz"), "-mesh", m, "-contact_unilateral", "0", "-kkt_path", "iterative", "-strain_limit", "1e300"], p)  # tied Hertz: a 76% strain (a workload)
                cells.append("%.2f s, %.0f MB" % (s["time"]["mesh"], s["memory_max_rank_mb"] - floor.get(p, 0)))
            print("| %s | %s |" % (name, " | ".join(cells)))


if __name__ == "__main__":
    main()
