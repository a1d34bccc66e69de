#!/usr/bin/python3
"""Speed against error (issue "Speed against error").

Runs S3 Hertz (options/hertz.opts, levels 0..4 by default) and S1 (options/
seed_patch.opts, 1x, 2x, 4x, 8x) for every configuration

    method (mortar, nts) x path (condensed, full) x ranks (1, 2)

(the condensed path calls MUMPS itself and runs on 1 and 2 ranks; the path the
program reports, summary "kkt_path", is recorded). Per level also the
REFERENCE: the same mesh tied
(-contact_unilateral 0: every candidate node held closed, one linear KKT solve
with MUMPS, the same solver), on 1 and 2 ranks. All configurations of one level
run back-to-back, so the ratios of a level come from one stretch of machine time
(the machine is shared and noisy; the 1-minute load average before each run is
in the CSV).

Each run has its own directory <out>/<scene>/L<level>/<config>/ holding
summary.json (-summary), log_view.txt (-log_view), stdout.txt and the peak
memory files. Output files (VTU/HDF5/contact CSV) are off in the timed runs.

Peak memory: GNU time (/usr/bin/time -f "%M %e %U %S") around every rank
(2 ranks: mpiexec ... sh -c 'exec /usr/bin/time ... -o mem.$OMPI_COMM_WORLD_RANK
mortar2d ...'), the CSV gives the max over the ranks (peak_mb) and the sum
(peak_mb_sum). Cross-check: ru_maxrss of the launched process (m2d.launch,
os.wait4; for 2 ranks the max over mpiexec and its descendants). Without GNU
time the script falls back to that (and says so); if neither works it stops.

Timings: the summary's time{mesh, contact, assembly, solve, output, total}
(seconds, max over ranks); factorization = MatLUFactorSym + MatLUFactorNum
(PETSc's MUMPS interface: full path, reference) + M2dMumpsAnalysis +
M2dMumpsFactor + M2dInterface (the condensed path's own MUMPS calls), times summed over the
log stages, max over ranks; order = the METIS ordering (M2dCondOrder on the
condensed path, else M2dMetisOrder), from the -log_view file. The active-set
solves are solve - order - factorization (substitutions, dense n_lambda LUs).
wall_s is the wall time of the process (incl. MPI start-up) measured here.

Errors: Hertz pressure_l2_rel (relative L2 error of the nodal pressure on
[0, 1.5a]), |half_width - a| / a and |peak - p0| / p0; S1: contact force error
contact_force / (p * 0.5) - 1, p = 1e6.

Printed: (a) growth exponents (least-squares slope of log time against log dofs,
over all levels and over the three largest), (b) contact solve / reference solve
per level, (c) 2-rank speedups at the two largest levels, (d) per-stage tables
at the two largest levels, (e) condensed = full = 2 ranks (summary numbers to
1e-8 relative; on the small levels also the contact CSV pressures, from extra
untimed runs with output on). Plot: docs/speed_vs_error.png.

--orderings: at the largest Hertz level, the MUMPS orderings
(-mat_mumps_icntl_7 0 AMD, 2 AMF, 4 PORD, 6 QAMD, 7 auto, plus 3 SCOTCH and 5
METIS as extras, plus -kkt_ordering metis if the program has it) for mortar
condensed 1 rank and for the tied reference 1 rank: factorization time, solve
time, MUMPS fill INFOG(20), INFOG(29), flops RINFOG(1), the ordering MUMPS
effectively used INFOG(7) (all from -mat_mumps_icntl_4 2), peak memory; and
the partitioners (-petscpartitioner_type) on 2 ranks for the tied reference.

The executable is copied to <out>/mortar2d at the start (others may rebuild
build/mortar2d while this runs); its sha256 and the git state are printed.
Programs are started and meshes found through tests/m2d.py (M2D_EXE and
M2D_MESHES choose another build; Hertz levels above 4 are made on demand).

  /usr/bin/python3 tools/benchmark.py [--levels 0,1,2,3,4] [--quick]
        [--s1-levels 1,2,4,8] [--orderings] [--only-orderings] [--out DIR]
        [--exe build/mortar2d] [--timeout 3600] [--png docs/speed_vs_error.png]
"""
import argparse
import csv
import hashlib
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests"))
import m2d                                               # noqa: E402

SRC = m2d.SRC
HERTZ_OPTS = m2d.opts("hertz")
S1_OPTS = m2d.opts("seed_patch")
S1_P, S1_WIDTH = 1.0e6, 0.5
QUIET = ["-output_vtu", "0", "-output_hdf5", "0", "-contact_monitor", "0"]
GNU_TIME = "/usr/bin/time"
TIME_FMT = "%M %e %U %S"
REL_TOL = 1e-8

# configuration name -> (method, requested path, ranks, reference)
CONFIGS = [
    ("mortar-condensed-1r", "mortar", "condensed", 1, False),
    ("mortar-full-1r", "mortar", "full", 1, False),
    ("nts-condensed-1r", "nts", "condensed", 1, False),
    ("nts-full-1r", "nts", "full", 1, False),
    ("mortar-condensed-2r", "mortar", "condensed", 2, False),
    ("mortar-full-2r", "mortar", "full", 2, False),
    ("nts-condensed-2r", "nts", "condensed", 2, False),
    ("nts-full-2r", "nts", "full", 2, False),
    ("tied-ref-1r", "mortar", "tied", 1, True),
    ("tied-ref-2r", "mortar", "tied", 2, True),
]

MEM_MODE = None       # "gnu-time" or "wait4"
EXE = None


# ---------------------------------------------------------------- utilities
def die(msg):
    sys.stderr.write("benchmark: " + msg + "\n")
    sys.exit(1)


def check_memory_tool(tmp):
    """GNU time if it works, else wait4's ru_maxrss; stop if neither works."""
    global MEM_MODE
    f = os.path.join(tmp, "time_check")
    try:
        r = m2d.launch([GNU_TIME, "-f", TIME_FMT, "-o", f, "true"], timeout=60)
        if r.rc == 0 and len(open(f).read().split()) == 4:
            MEM_MODE = "gnu-time"
            return
    except OSError:
        pass
    try:
        if m2d.launch(["true"], timeout=60).maxrss_mb > 0:
            MEM_MODE = "wait4"
            sys.stderr.write("benchmark: %s (GNU time) missing or broken (apt-get install time); "
                             "peak memory from os.wait4 ru_maxrss instead (2 ranks: max over "
                             "mpiexec's process tree, not per rank)\n" % GNU_TIME)
            return
    except (OSError, AttributeError):
        pass
    die("cannot measure peak memory: %s (GNU time, Debian package 'time') does not work "
        "and os.wait4 gives no ru_maxrss; install it with apt-get install time" % GNU_TIME)


def hertz_mesh(level):
    try:
        return m2d.hertz_mesh(level)
    except RuntimeError as e:
        die(str(e))


def s1_mesh(level):
    p = m2d.mesh("seed_patch" if level == 1 else "seed_patch_%d" % level)
    if not os.path.exists(p):
        die("missing %s (the build makes it)" % p)
    return p


def scene_args(scene, level):
    if scene == "hertz":
        return ["-options_file", HERTZ_OPTS, "-mesh", hertz_mesh(level)]
    return ["-options_file", S1_OPTS, "-mesh", s1_mesh(level)]


def config_args(method, path):
    a = ["-contact_method", method]
    if path == "tied":  # every candidate node held closed: on Hertz a strain of 76%, allowed (a workload)
        a += ["-contact_unilateral", "0", "-strain_limit", "1e300"]
    else:
        a += ["-kkt_path", path]
    return a


def run_program(d, args, ranks, timeout, log_view=True):
    """Run mortar2d in directory d; return a dict (rc, wall, peak memory, files)."""
    os.makedirs(d, exist_ok=True)
    for f in os.listdir(d):
        if f.startswith(("mem.", "summary.json", "log_view.txt", "stdout.txt")):
            os.remove(os.path.join(d, f))
    summary = os.path.join(d, "summary.json")
    logv = os.path.join(d, "log_view.txt")
    mem = os.path.join(d, "mem")
    full = list(args) + ["-summary", summary, "-output_dir", os.path.join(d, "output")]
    if log_view:
        full += ["-log_view", ":" + logv]
    wrapper = ()
    if MEM_MODE == "gnu-time":
        if ranks == 1:
            wrapper = (GNU_TIME, "-f", TIME_FMT, "-o", mem + ".0")
        else:
            wrapper = ("/bin/sh", "-c", 'exec %s -f "%s" -o "$0.$OMPI_COMM_WORLD_RANK" "$@"' % (GNU_TIME, TIME_FMT), mem)
    cmd = m2d.command(full, ranks, exe=EXE, wrapper=wrapper)
    with open(os.path.join(d, "cmd.txt"), "w") as f:
        f.write(" ".join(cmd) + "\n")
    load = os.getloadavg()[0]
    r = m2d.launch(cmd, timeout=timeout, stdout=os.path.join(d, "stdout.txt"), merge=True)
    res = {"rc": -9 if r.timed_out else r.rc, "wall": r.wall, "timed_out": r.timed_out, "dir": d,
           "summary": summary, "log_view": logv, "stdout": os.path.join(d, "stdout.txt"),
           "maxrss_wait4_mb": r.maxrss_mb, "load1": load}
    if MEM_MODE == "gnu-time":
        mems, cpu = [], []
        for k in range(ranks):
            try:
                # GNU time writes "Command exited with non-zero status" first on failure
                v = open("%s.%d" % (mem, k)).read().split()[-4:]
                mems.append(float(v[0]) / 1024.0)
                cpu.append(float(v[2]) + float(v[3]))
            except (OSError, ValueError, IndexError):
                pass
        res["peak_mb"] = max(mems) if len(mems) == ranks else float("nan")
        res["peak_mb_sum"] = sum(mems) if len(mems) == ranks else float("nan")
        res["cpu_s"] = sum(cpu) if len(cpu) == ranks else float("nan")
    else:
        res["peak_mb"] = res["maxrss_wait4_mb"]
        res["peak_mb_sum"] = float("nan")
        res["cpu_s"] = r.cpu_s
    return res


def read_text(p):
    try:
        with open(p, errors="replace") as f:
            return f.read()
    except OSError:
        return ""


EVENT_RE = re.compile(r"^(\S+)\s+(\d+)\s+[\d.]+\s+([\d.eE+-]+)\s")


def parse_log_view(path):
    """Sum over stages of (count, max time) per event, from the event table only."""
    ev = {}
    inside = False
    for line in read_text(path).splitlines():
        if line.startswith("Event ") and "Count" in line:
            inside = True
            continue
        if line.startswith("Object Type"):
            break
        if not inside:
            continue
        m = EVENT_RE.match(line)
        if m:
            c, t = ev.get(m.group(1), (0, 0.0))
            ev[m.group(1)] = (c + int(m.group(2)), t + float(m.group(3)))
    return ev


def parse_mumps(text):
    """MUMPS statistics printed with -mat_mumps_icntl_4 2 (first analysis/factorization)."""
    def first(pat, conv=float):
        m = re.search(pat, text)
        return conv(m.group(1).replace("D", "E")) if m else float("nan")
    return {
        "infog20": first(r"\(20\) Number of entries in factors \(estim\.\)\s*=\s*(\d+)"),
        "infog29": first(r"INFOG\(29\)\s+Number of entries in factors\s*=\s*(\d+)"),
        "rinfog1": first(r"RINFOG\(1\) Operations during elimination \(estim\)\s*=\s*([\d.DE+-]+)"),
        "infog7": first(r"\(7\) Ordering option effectively used\s*=\s*(\d+)", int),
        "icntl7": first(r"ICNTL \(7\) Pivot order option\s*=\s*(\d+)", int),
        "mumps_mem_mb": first(r"Memory effectively used, total in Mbytes\s*\(INFOG\(22\)\):\s*(\d+)"),
        # -ksp_view's lines (tied run), as a cross-check
        "kspview_infog20": first(r"INFOG\(20\) \(estimated number of entries in the factors\):\s*(\d+)"),
        "kspview_rinfog1": first(r"RINFOG\(1\) \(global estimated flops for the elimination after analysis\):\s*([\d.eE+-]+)"),
    }


# ---------------------------------------------------------------- one run
def measure(out, scene, level, cfg, timeout, idx, total):
    name, method, path, ranks, ref = cfg
    d = os.path.join(out, scene, "L%d" % level, name)
    args = scene_args(scene, level) + config_args(method, path) + QUIET
    r = run_program(d, args, ranks, timeout)
    so = read_text(r["stdout"])
    if r["rc"] != 0 or not os.path.exists(r["summary"]):
        tail = "\n".join(so.strip().splitlines()[-15:])
        die("run failed (%s, rc %d%s): %s\n%s" % (d, r["rc"], ", TIMED OUT after %g s" % timeout
                                                 if r["timed_out"] else "",
                                                 read_text(os.path.join(d, "cmd.txt")).strip(), tail))
    s = json.load(open(r["summary"]))
    ev = parse_log_view(r["log_view"])
    fs, fn = ev.get("MatLUFactorSym", (0, 0.0)), ev.get("MatLUFactorNum", (0, 0.0))
    cs_, cn_ = ev.get("MatCholFctrSym", (0, 0.0)), ev.get("MatCholFctrNum", (0, 0.0))   # LDL^T (linear solves)
    fs, fn = (fs[0] + cs_[0], fs[1] + cs_[1]), (fn[0] + cn_[0], fn[1] + cn_[1])
    ma, mf = ev.get("M2dMumpsAnalysis", (0, 0.0)), ev.get("M2dMumpsFactor", (0, 0.0))
    mi = ev.get("M2dInterface", (0, 0.0))   # condensed path: the dense interface (separator eliminated)
    fs, fn = (fs[0] + ma[0], fs[1] + ma[1]), (fn[0] + mf[0], fn[1] + mf[1] + mi[1])
    ms = ev.get("MatSolve", (0, 0.0))
    ms = (ms[0] + ev.get("M2dMumpsSolve", (0, 0.0))[0], ms[1] + ev.get("M2dMumpsSolve", (0, 0.0))[1])
    t_order = ev.get("M2dCondOrder", ev.get("M2dMetisOrder", (0, 0.0)))[1]
    t = s["time"]
    row = {
        "scene": scene, "level": level, "dofs": s["dofs"], "config": name, "method": s.get("method", method),
        "path": ("tied" if ref else s.get("kkt_path", "?")), "path_requested": path,
        "switched_msg": int("the condensed path needs" in so),
        "ranks": s["ranks"], "reference": ref,
        "iterations": s.get("iterations"), "active_nodes": s.get("active_nodes"),
        "contact_nodes": s.get("contact_nodes"),
        "t_mesh": t["mesh"], "t_contact": t["contact"], "t_assembly": t["assembly"],
        "t_solve": t["solve"], "t_output": t["output"], "t_total": t["total"],
        "t_fact": fs[1] + fn[1], "n_fact_sym": fs[0], "n_fact_num": fn[0], "t_order": t_order,
        "t_matsolve": ms[1], "n_matsolve": ms[0],
        "t_dense_lu": ev.get("MatLUFactor", (0, 0.0))[1],
        "factor_flops": s.get("factor_flops", float("nan")),           # condensed path: MUMPS RINFO(3), all ranks
        "factor_flops_max_rank": s.get("factor_flops_max_rank", float("nan")),
        "interface_unknowns": s.get("interface_unknowns", -1),
        "wall_s": r["wall"], "cpu_s": r["cpu_s"], "peak_mb": r["peak_mb"], "peak_mb_sum": r["peak_mb_sum"],
        "maxrss_wait4_mb": r["maxrss_wait4_mb"], "load1": r["load1"],
        "contact_force": s.get("contact_force"),
    }
    if scene == "hertz":
        a, p0 = s["hertz_a"], s["hertz_p0"]
        row.update(pressure_l2_rel=s["pressure_l2_rel"], peak_pressure=s["peak_pressure"],
                   half_width=s["half_width"], half_width_err=abs(s["half_width"] - a) / a,
                   peak_err=abs(s["peak_pressure"] - p0) / p0, force_err=float("nan"))
    else:
        row.update(pressure_l2_rel=float("nan"), peak_pressure=float("nan"), half_width=float("nan"),
                   half_width_err=float("nan"), peak_err=float("nan"),
                   force_err=s["contact_force"] / (S1_P * S1_WIDTH) - 1.0)
    err = ("err %.3e" % row["pressure_l2_rel"]) if scene == "hertz" else ("force err %+.1e" % row["force_err"])
    print("[%3d/%3d] %-5s L%-2d %-20s dofs %8d  ranks %d path %-9s wall %8.2f s  solve %8.3f s  "
          "steps %2s  mem %7.1f MB  load %.1f  %s"
          % (idx, total, scene, level, name, row["dofs"], row["ranks"], row["path"], r["wall"],
             row["t_solve"], row["iterations"], row["peak_mb"], r["load1"], "" if ref else err), flush=True)
    return row


# ---------------------------------------------------------------- reports
def fmt(v, f="%.3g"):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return f % v


def slope(x, y):
    x, y = np.log(np.asarray(x, float)), np.log(np.asarray(y, float))
    if len(x) < 2 or not np.all(np.isfinite(y)):
        return float("nan")
    return np.polyfit(x, y, 1)[0]


def report_growth(rows, scene):
    print("\n(a) %s: time growth exponents, least-squares slope of log(time) against log(dofs)"
          % scene)
    print("    'top3' = the three largest levels of that configuration only; fact = MatLUFactorSym+Num")
    print("    %-20s %-12s %10s %10s %10s %10s %10s" % ("config", "levels", "solve", "solve top3", "total",
                                                       "total top3", "fact top3"))
    for cfg in CONFIGS:
        rr = sorted([r for r in rows if r["scene"] == scene and r["config"] == cfg[0]],
                    key=lambda r: r["dofs"])
        if len(rr) < 2:
            continue
        top = rr[-3:]
        print("    %-20s %-12s %10s %10s %10s %10s %10s" % (
            cfg[0], ",".join(str(r["level"]) for r in rr), fmt(slope([r["dofs"] for r in rr], [r["t_solve"] for r in rr]), "%.2f"),
            fmt(slope([r["dofs"] for r in top], [r["t_solve"] for r in top]), "%.2f"),
            fmt(slope([r["dofs"] for r in rr], [r["t_total"] for r in rr]), "%.2f"),
            fmt(slope([r["dofs"] for r in top], [r["t_total"] for r in top]), "%.2f"),
            fmt(slope([r["dofs"] for r in top], [max(r["t_fact"], 1e-9) for r in top]), "%.2f")))


def find(rows, scene, level, config):
    for r in rows:
        if r["scene"] == scene and r["level"] == level and r["config"] == config:
            return r
    return None


def report_ratios(rows, scene):
    levels = sorted({r["level"] for r in rows if r["scene"] == scene})
    cfgs = [c for c in CONFIGS if not c[4]]
    print("\n(b) %s: contact solve time / reference (tied) solve time, same level and ranks"
          % scene)
    print("    (in brackets: total / reference total)")
    print("    %-6s %8s %8s %8s " % ("level", "dofs", "ref1r_s", "ref2r_s")
          + " ".join("%19s" % c[0] for c in cfgs))
    for lv in levels:
        r1, r2 = find(rows, scene, lv, "tied-ref-1r"), find(rows, scene, lv, "tied-ref-2r")
        any_r = r1 or r2 or [r for r in rows if r["scene"] == scene and r["level"] == lv][0]
        line = "  %s %-6s %8d %8s %8s " % ("*" if lv == levels[-1] else " ", lv, any_r["dofs"],
                                           fmt(r1["t_solve"] if r1 else None, "%.3f"),
                                           fmt(r2["t_solve"] if r2 else None, "%.3f"))
        for c in cfgs:
            r = find(rows, scene, lv, c[0])
            ref = r1 if c[3] == 1 else r2
            if r is None or ref is None:
                line += " %19s" % "not run"
                continue
            line += " %8.2f [%8.2f]" % (r["t_solve"] / ref["t_solve"], r["t_total"] / ref["t_total"])
        print(line)
    print("    * the largest level")


def complete_levels(rows, scene):
    lv = sorted({r["level"] for r in rows if r["scene"] == scene})
    return [l for l in lv if all(find(rows, scene, l, c[0]) for c in CONFIGS)]


def report_speedup(rows, scene):
    print("\n(c) %s: 2-rank speedup = time on 1 rank / time on 2 ranks (>1: 2 ranks faster)" % scene)
    pairs = [("mortar condensed", "mortar-condensed-1r", "mortar-condensed-2r"),
             ("mortar full", "mortar-full-1r", "mortar-full-2r"),
             ("nts condensed", "nts-condensed-1r", "nts-condensed-2r"),
             ("nts full", "nts-full-1r", "nts-full-2r"),
             ("tied reference", "tied-ref-1r", "tied-ref-2r")]
    print("    %-30s %6s %8s %9s %9s %8s %9s %9s %8s" % ("pair", "level", "dofs", "solve1r", "solve2r",
                                                       "speedup", "total1r", "total2r", "speedup"))
    alllv = sorted({r["level"] for r in rows if r["scene"] == scene})
    for lab, a, b in pairs:   # the two largest levels at which the pair ran
        both = [lv for lv in alllv if find(rows, scene, lv, a) and find(rows, scene, lv, b)]
        for lv in both[-2:]:
            ra, rb = find(rows, scene, lv, a), find(rows, scene, lv, b)
            print("    %-30s %6s %8d %9.3f %9.3f %8.2f %9.3f %9.3f %8.2f" % (
                lab, lv, ra["dofs"], ra["t_solve"], rb["t_solve"], ra["t_solve"] / rb["t_solve"],
                ra["t_total"], rb["t_total"], ra["t_total"] / rb["t_total"]))
    # per stage, the condensed paths (the program's default) at the two largest levels they ran
    stages = [("mesh", lambda r: r["t_mesh"]), ("contact", lambda r: r["t_contact"]),
              ("assembly", lambda r: r["t_assembly"]), ("order", lambda r: r["t_order"]),
              ("fact", lambda r: r["t_fact"]), ("steps", lambda r: r["t_solve"] - r["t_fact"] - r["t_order"]),
              ("output", lambda r: r["t_output"]), ("total", lambda r: r["t_total"]),
              ("peak MB", lambda r: r["peak_mb"])]
    print("\n    per stage (seconds on 1 rank / 2 ranks = speedup; steps = solve - order - fact):")
    for lab, a, b in pairs[::2][:2]:
        both = [lv for lv in alllv if find(rows, scene, lv, a) and find(rows, scene, lv, b)]
        for lv in both[-2:]:
            ra, rb = find(rows, scene, lv, a), find(rows, scene, lv, b)
            print("    %-18s L%-2s " % (lab, lv) + "  ".join(
                "%s %.3g/%.3g=%.2f" % (n, f(ra), f(rb), f(ra) / f(rb) if f(rb) > 0 else float("nan")) for n, f in stages))
            fl, fm = rb.get("factor_flops", float("nan")), rb.get("factor_flops_max_rank", float("nan"))
            if fl == fl and fm == fm and fl > 0:   # the 2-rank factorization's balance (1.00 = even)
                print("    %-18s L%-2s 2 ranks: MUMPS flops %.3g (1 rank %.3g), largest rank %.3g = %.2f x the mean; "
                      "interface %d unknowns" % (lab, lv, fl, ra.get("factor_flops", float("nan")), fm,
                                                 fm / (fl / rb["ranks"]), rb.get("interface_unknowns", -1)))


def report_stages(rows, scene):
    comp = complete_levels(rows, scene)
    levels = sorted(set(comp[-2:]) | {l for l in {r["level"] for r in rows if r["scene"] == scene}
                                      if l not in comp and (not comp or l > comp[-1])})
    print("\n(d) %s: where the time goes (seconds; order = METIS ordering, fact = analysis + "
          "numeric factorization, as = active-set solves = solve - order - fact;\n    #f = numeric "
          "factorizations; wall includes process and MPI start-up; mem = peak RSS, max over ranks)" % scene)
    hdr = "    %-5s %-20s %2s %8s %7s %7s %8s %7s %8s %8s %3s %7s %8s %8s %8s %6s %5s" % (
        "level", "config", "np", "dofs", "mesh", "contact", "assembly", "order", "fact", "as", "#f",
        "output", "total", "wall", "cpu", "mem", "steps")
    print(hdr)
    for lv in levels:
        for ranks in (1, 2):
            for c in CONFIGS:
                if c[3] != ranks:
                    continue
                r = find(rows, scene, lv, c[0])
                if r is None:
                    continue
                print("    %-5s %-20s %2d %8d %7.3f %7.4f %8.3f %7.3f %8.3f %8.3f %3d %7.3f %8.3f %8.2f %8.2f %6.0f %5s" % (
                    lv, c[0], r["ranks"], r["dofs"], r["t_mesh"], r["t_contact"], r["t_assembly"], r["t_order"],
                    r["t_fact"], r["t_solve"] - r["t_fact"] - r["t_order"], r["n_fact_num"], r["t_output"],
                    r["t_total"], r["wall_s"], r["cpu_s"], r["peak_mb"], r["iterations"]))
        print()


def reldiff(a, b):
    if a == b:
        return 0.0
    return abs(a - b) / max(abs(a), abs(b), 1e-300)


def report_same_answer(rows, scene, csv_checks):
    print("\n(e) %s: condensed (1 rank) = full (1 rank) = condensed and full (2 ranks)? summary numbers, max "
          "relative difference (tolerance %.0e; iterations/active nodes exact)" % (scene, REL_TOL))
    keys = (["pressure_l2_rel", "peak_pressure", "half_width", "contact_force"] if scene == "hertz"
            else ["contact_force"])
    levels = sorted({r["level"] for r in rows if r["scene"] == scene})
    ok_all = True
    print("    %-6s %-7s %-22s " % ("level", "method", "compared") + " ".join("%15s" % k for k in keys)
          + " %11s %7s %5s" % ("iterations", "active", "ok"))
    for lv in levels:
        for m in ("mortar", "nts"):
            base = find(rows, scene, lv, m + "-condensed-1r")
            for other in (m + "-full-1r", m + "-condensed-2r", m + "-full-2r"):
                o = find(rows, scene, lv, other)
                if base is None or o is None:
                    continue
                d = [reldiff(base[k], o[k]) for k in keys]
                same_it = base["iterations"] == o["iterations"]
                same_act = base["active_nodes"] == o["active_nodes"]
                ok = all(x <= REL_TOL for x in d) and same_it and same_act and o["path"] == other.split("-")[1]
                ok_all &= ok
                print("    %-6s %-7s %-22s " % (lv, m, "cond-1r vs " + other.split("-", 1)[1])
                      + " ".join("%15.1e" % x for x in d)
                      + " %5s=%-5s %3s=%-3s %5s" % (base["iterations"], o["iterations"], base["active_nodes"],
                                                    o["active_nodes"], "yes" if ok else "NO"))
    if csv_checks:
        print("    contact CSV pressures (extra untimed runs with output on): max |p - p_cond1r| / max|p_cond1r|")
        for c in csv_checks:
            if c["scene"] != scene:
                continue
            ok = c["max_rel"] <= REL_TOL and c["same_nodes"]
            ok_all &= ok
            print("    %-6s %-7s %-22s nodes %4d same x: %-3s  max rel diff %.1e  %s" % (
                c["level"], c["method"], "cond-1r vs " + c["other"], c["n"], "yes" if c["same_nodes"] else "NO",
                c["max_rel"], "yes" if ok else "NO"))
    print("    => %s" % ("all agree" if ok_all else "DIFFERENCES ABOVE (see NO)"))
    return ok_all


def csv_pressure_checks(out, scene, levels, timeout):
    """Untimed extra runs with output on: compare the contact CSV pressures."""
    res = []
    for lv in levels:
        for m in ("mortar", "nts"):
            data = {}
            for tag, path, ranks in (("condensed-1r", "condensed", 1), ("full-1r", "full", 1),
                                     ("condensed-2r", "condensed", 2), ("full-2r", "full", 2)):
                d = os.path.join(out, "csvcheck", scene, "L%d" % lv, "%s-%s" % (m, tag))
                args = (scene_args(scene, lv) + config_args(m, path)
                        + ["-output_vtu", "1", "-output_hdf5", "0", "-contact_monitor", "0",
                           "-output_name", "c"])
                r = run_program(d, args, ranks, timeout, log_view=False)
                f = os.path.join(d, "output", "c_contact.csv")
                if r["rc"] != 0 or not os.path.exists(f):
                    die("csv check run failed: %s (rc %d)" % (d, r["rc"]))
                a = np.atleast_1d(np.genfromtxt(f, delimiter=",", names=True))
                data[tag] = a
            b = data["condensed-1r"]
            for tag in ("full-1r", "condensed-2r", "full-2r"):
                o = data[tag]
                same = len(o) == len(b) and np.allclose(o["x"], b["x"], rtol=0, atol=1e-12)
                mr = (np.max(np.abs(o["pressure"] - b["pressure"])) / np.max(np.abs(b["pressure"]))
                      if same else float("inf"))
                res.append({"scene": scene, "level": lv, "method": m, "other": tag, "n": len(b),
                            "same_nodes": same, "max_rel": mr})
    return res


def plot(rows, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.patches
    import matplotlib.pyplot as plt
    from matplotlib.transforms import blended_transform_factory
    h = [r for r in rows if r["scene"] == "hertz"]
    if not h:
        return
    fig, axes = plt.subplots(1, 2, figsize=(15, 7.5))
    styles = {"mortar-condensed-1r": ("C0", "o", "-"), "mortar-full-1r": ("C0", "s", "--"),
              "mortar-condensed-2r": ("C2", "^", "-"), "mortar-full-2r": ("C2", "v", "--"),
              "nts-condensed-1r": ("C3", "o", "-"), "nts-full-1r": ("C3", "s", "--"),
              "nts-condensed-2r": ("C1", "^", "-"), "nts-full-2r": ("C1", "v", "--")}
    labels = {"mortar-condensed-1r": "mortar, condensed, 1 rank", "mortar-full-1r": "mortar, full, 1 rank",
              "mortar-condensed-2r": "mortar, condensed, 2 ranks", "mortar-full-2r": "mortar, full, 2 ranks",
              "nts-condensed-1r": "NTS, condensed, 1 rank", "nts-full-1r": "NTS, full, 1 rank",
              "nts-condensed-2r": "NTS, condensed, 2 ranks", "nts-full-2r": "NTS, full, 2 ranks"}
    for ax, key, title in ((axes[0], "t_solve", "against solve time (summary time.solve)"),
                           (axes[1], "t_total", "against total time (summary time.total)")):
        for cfg, (col, mk, ls) in styles.items():
            rr = sorted([r for r in h if r["config"] == cfg], key=lambda r: r["dofs"])
            if not rr:
                continue
            x = [r[key] for r in rr]
            y = [r["pressure_l2_rel"] for r in rr]
            ax.plot(x, y, color=col, marker=mk, ls=ls, label=labels[cfg], ms=6)
            if cfg == "mortar-condensed-1r" or cfg == "nts-condensed-1r":
                for r in rr:
                    ax.annotate("%d" % r["dofs"], (r[key], r["pressure_l2_rel"]), fontsize=7,
                                xytext=(4, 4 if cfg.startswith("mortar") else -10),
                                textcoords="offset points", color=col)
        tr = blended_transform_factory(ax.transData, ax.transAxes)
        ax.add_patch(matplotlib.patches.Rectangle((0, 0), 1, 0.14, transform=ax.transAxes,
                                                  color="0.92", zorder=0))
        for cfg, mk, col, lab in (("tied-ref-1r", "D", "k", "tied reference, 1 rank (time only)"),
                                  ("tied-ref-2r", "v", "0.45", "tied reference, 2 ranks (time only)")):
            rr = sorted([r for r in h if r["config"] == cfg], key=lambda r: r["dofs"])
            ax.scatter([r[key] for r in rr], [0.04 if cfg.endswith("1r") else 0.09] * len(rr),
                       marker=mk, color=col, transform=tr, label=lab, zorder=5, clip_on=False)
            for r in rr:
                ax.annotate("%d" % r["dofs"], (r[key], 0.04 if cfg.endswith("1r") else 0.09),
                            xycoords=tr, fontsize=6, rotation=60, xytext=(2, 4),
                            textcoords="offset points", color=col)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall seconds (%s)" % key[2:])
        ax.set_ylabel("Hertz pressure error pressure_l2_rel")
        ax.set_title("S3 Hertz: pressure error " + title, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        errs = [r["pressure_l2_rel"] for r in h if not r["reference"] and r["pressure_l2_rel"] > 0]
        ax.set_ylim(min(errs) / 3.0, max(errs) * 1.4)   # room for the reference band at the bottom
    hnd, lab = axes[0].get_legend_handles_labels()
    fig.legend(hnd, lab, fontsize=8.5, loc="lower center", ncol=4, bbox_to_anchor=(0.5, 0.035))
    fig.text(0.5, 0.005, "numbers: dofs (condensed 1-rank runs and references). Tied reference = the same "
             "mesh with every candidate node closed, one MUMPS KKT solve: its pressure is not Hertz, "
             "so it is drawn at the bottom, on the time axis only.", ha="center", fontsize=8)
    fig.tight_layout(rect=(0, 0.13, 1, 1))
    os.makedirs(os.path.dirname(png), exist_ok=True)
    fig.savefig(png, dpi=120)
    plt.close(fig)
    print("\nplot: %s" % png)


# ---------------------------------------------------------------- orderings, partitioners
def has_kkt_ordering():
    rc, out, err = m2d.run(["-help", "-options_file", HERTZ_OPTS], exe=EXE, check=False)
    return "kkt_ordering" in (out + err)


def orderings(out, level, timeout):
    print("\n(f) MUMPS orderings at Hertz level %d, 1 rank (one run each, back-to-back; "
          "-mat_mumps_icntl_4 2 for the statistics)" % level)
    own = ["-kkt_ordering", "mumps", "-mat_mumps_icntl_7"]  # MUMPS' own orderings
    ords = [("0 AMD", own + ["0"]), ("2 AMF", own + ["2"]),
            ("4 PORD", own + ["4"]), ("6 QAMD", own + ["6"]),
            ("7 auto", own + ["7"]), ("3 SCOTCH*", own + ["3"]),
            ("5 METIS*", own + ["5"])]
    if has_kkt_ordering():
        ords.append(("kkt_ordering metis", ["-kkt_ordering", "metis"]))
        print("    -kkt_ordering is in the program's -help: included")
    else:
        print("    -kkt_ordering: NOT in this build's -help (build/mortar2d -help | grep kkt_ordering "
              "finds nothing): skipped")
    print("    * 3 and 5 are extras beyond the brief (SCOTCH / METIS inside MUMPS, if MUMPS was built "
          "with them; INFOG(7) shows what MUMPS really used)")
    rows = []
    for cfgname, method, path in (("mortar-condensed-1r", "mortar", "condensed"),
                                  ("tied-ref-1r", "mortar", "tied")):
        for lab, extra in ords:
            tag = re.sub(r"[^A-Za-z0-9]+", "_", lab).strip("_")
            d = os.path.join(out, "orderings", "L%d" % level, "%s_%s" % (cfgname, tag))
            args = (scene_args("hertz", level) + config_args(method, path) + QUIET
                    + ["-mat_mumps_icntl_4", "2"] + extra + (["-ksp_view"] if path == "tied" else []))
            r = run_program(d, args, 1, timeout)
            so = read_text(r["stdout"])
            if r["rc"] != 0 or not os.path.exists(r["summary"]):
                print("    %-20s %-18s FAILED rc %d: %s" % (cfgname, lab, r["rc"],
                                                           " | ".join(so.strip().splitlines()[-3:])))
                rows.append({"config": cfgname, "ordering": lab, "failed": True})
                continue
            s = json.load(open(r["summary"]))
            ev = parse_log_view(r["log_view"])
            mu = parse_mumps(so)
            rows.append({"config": cfgname, "ordering": lab, "failed": False, "dofs": s["dofs"],
                         "t_fact": sum(ev.get(k, (0, 0))[1] for k in ("MatLUFactorSym", "MatLUFactorNum", "MatCholFctrSym", "MatCholFctrNum", "M2dMumpsAnalysis", "M2dMumpsFactor", "M2dInterface")),
                         "t_solve": s["time"]["solve"], "t_total": s["time"]["total"],
                         "iterations": s.get("iterations"), "peak_mb": r["peak_mb"],
                         "pressure_l2_rel": s.get("pressure_l2_rel"), **mu})
            x = rows[-1]
            print("    ran %-20s %-18s fact %.3f s solve %.3f s INFOG(20) %.3e INFOG(7) %s" % (
                cfgname, lab, x["t_fact"], x["t_solve"], x["infog20"], x["infog7"]), flush=True)
    print("\n    %-20s %-18s %8s %8s %8s %11s %11s %11s %8s %8s %8s %6s" % (
        "config", "ordering", "ICNTL(7)", "INFOG(7)", "fact_s", "solve_s", "INFOG(20)", "RINFOG(1)",
        "MUMPS_MB", "peak_MB", "steps", "ksp20"))
    for x in rows:
        if x["failed"]:
            print("    %-20s %-18s FAILED" % (x["config"], x["ordering"]))
            continue
        print("    %-20s %-18s %8s %8s %8.3f %11.3f %11.4g %11.4g %8s %8.0f %8s %6s" % (
            x["config"], x["ordering"], fmt(x["icntl7"], "%d"), fmt(x["infog7"], "%d"), x["t_fact"],
            x["t_solve"], x["infog20"], x["rinfog1"], fmt(x["mumps_mem_mb"], "%.0f"), x["peak_mb"],
            x["iterations"], "-" if not math.isfinite(x["kspview_infog20"])
            else ("=" if x["kspview_infog20"] == x["infog20"] else "DIFF")))
    print("    INFOG(7): ordering MUMPS effectively used (0 AMD, 2 AMF, 3 SCOTCH, 4 PORD, 5 METIS, 6 QAMD, "
          "1 given by the user); ksp20: -ksp_view's INFOG(20) equals the printed one (tied runs)")
    with open(os.path.join(out, "orderings.csv"), "w", newline="") as f:
        keys = sorted({k for x in rows for k in x})
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for x in rows:
            w.writerow(x)

    # partitioners, 2 ranks, tied reference
    print("\n(g) partitioners on 2 ranks, tied reference at Hertz level %d (-mesh_partitioner metis: libmetis "
          "shell partition; the others -mesh_partitioner petsc -petscpartitioner_type X)" % level)
    cands = ["metis", "ptscotch", "simple", "parmetis", "chaco", "matpartitioning", "gather"]

    def part_args(p):
        return ["-mesh_partitioner", "metis"] if p == "metis" else ["-mesh_partitioner", "petsc", "-petscpartitioner_type", p]
    avail = []
    for p in cands:
        d = os.path.join(out, "partitioners", "probe", p)
        r = run_program(d, scene_args("hertz", 0) + config_args("mortar", "tied") + QUIET
                        + part_args(p), 2, 300, log_view=False)
        if r["rc"] == 0:
            avail.append(p)
        else:
            msg = [l for l in read_text(r["stdout"]).splitlines() if "error" in l.lower()]
            print("    %-16s not available: %s" % (p, msg[0] if msg else "rc %d" % r["rc"]))
    print("    available: %s (matpartitioning = PETSc MatPartitioning, whose default here is ptscotch; "
          "gather = every cell on one rank)" % ", ".join(avail))
    print("    %-16s %8s %8s %9s %8s %8s %8s %8s %8s %8s" % ("partitioner", "mesh", "assembly", "fact",
                                                            "solve", "total", "wall", "mem_max", "mem_sum",
                                                            "load1"))
    prow = []
    for p in avail:
        d = os.path.join(out, "partitioners", "L%d" % level, p)
        r = run_program(d, scene_args("hertz", level) + config_args("mortar", "tied") + QUIET
                        + part_args(p), 2, timeout)
        if r["rc"] != 0:
            print("    %-16s FAILED rc %d" % (p, r["rc"]))
            continue
        s = json.load(open(r["summary"]))
        ev = parse_log_view(r["log_view"])
        t = s["time"]
        fct = sum(ev.get(k, (0, 0))[1] for k in ("MatLUFactorSym", "MatLUFactorNum", "MatCholFctrSym", "MatCholFctrNum", "M2dMumpsAnalysis", "M2dMumpsFactor", "M2dInterface"))
        prow.append({"partitioner": p, **t, "fact": fct, "wall": r["wall"], "peak_mb": r["peak_mb"],
                     "peak_mb_sum": r["peak_mb_sum"], "load1": r["load1"]})
        print("    %-16s %8.3f %8.3f %9.3f %8.3f %8.3f %8.2f %8.0f %8.0f %8.1f" % (
            p, t["mesh"], t["assembly"], fct, t["solve"], t["total"], r["wall"], r["peak_mb"],
            r["peak_mb_sum"], r["load1"]), flush=True)
    return rows, prow


# ---------------------------------------------------------------- main
def main():
    global EXE
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--levels", default="0,1,2,3,4", help="Hertz levels (comma separated)")
    ap.add_argument("--quick", action="store_true", help="Hertz levels 0..2, S1 1x, 2x, 4x")
    ap.add_argument("--s1-levels", default="1,2,4,8", help="S1 refinements (1 = seed_patch.msh)")
    ap.add_argument("--out", default=os.path.join(SRC, "build", "benchmark"))
    ap.add_argument("--exe", default=m2d.EXE)
    ap.add_argument("--png", default=os.path.join(SRC, "docs", "speed_vs_error.png"))
    ap.add_argument("--orderings", action="store_true", help="also the ordering/partitioner comparison")
    ap.add_argument("--only-orderings", action="store_true", help="only the ordering/partitioner comparison")
    ap.add_argument("--csv-check-levels", default="0,1,2",
                    help="Hertz levels with the untimed contact-CSV comparison (S1: 1,2,4); '' = none")
    ap.add_argument("--partial-levels", default="",
                    help="Hertz levels (also listed in --levels) run only with --partial-configs "
                         "(e.g. 5, where each full-path run takes ~10 min)")
    ap.add_argument("--partial-configs", default="mortar-condensed-1r,nts-condensed-1r,tied-ref-1r,tied-ref-2r")
    ap.add_argument("--orderings-level", type=int, default=None,
                    help="Hertz level of the ordering/partitioner comparison (default: the largest "
                         "level not in --partial-levels)")
    ap.add_argument("--plot-only", action="store_true",
                    help="only redraw the PNG from <out>/benchmark.csv of an earlier run")
    ap.add_argument("--timeout", type=float, default=3600.0, help="seconds per run")
    a = ap.parse_args()
    hl = [0, 1, 2] if a.quick else [int(x) for x in a.levels.split(",") if x.strip()]
    sl = [1, 2, 4] if a.quick else [int(x) for x in a.s1_levels.split(",") if x.strip()]
    partial = [int(x) for x in a.partial_levels.split(",") if x.strip()]
    pconf = [x.strip() for x in a.partial_configs.split(",") if x.strip()]
    unknown = [x for x in pconf if x not in [c[0] for c in CONFIGS]]
    if unknown:
        die("unknown --partial-configs %s (known: %s)" % (",".join(unknown), ",".join(c[0] for c in CONFIGS)))
    ord_level = a.orderings_level if a.orderings_level is not None else max(
        [l for l in hl if l not in partial] or hl)
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    t_start = time.time()

    if a.plot_only:
        rows = []
        with open(os.path.join(out, "benchmark.csv")) as f:
            for r in csv.DictReader(f):
                for k, v in r.items():
                    try:
                        r[k] = int(v)
                    except ValueError:
                        try:
                            r[k] = float(v)
                        except ValueError:
                            pass
                r["reference"] = r["reference"] in ("True", "1", True)
                rows.append(r)
        plot(rows, a.png)
        return 0

    if not os.access(a.exe, os.X_OK):
        die("no executable %s (cmake --build build)" % a.exe)
    EXE = os.path.join(out, "mortar2d")
    shutil.copy2(a.exe, EXE)
    sha = hashlib.sha256(open(EXE, "rb").read()).hexdigest()[:16]
    git = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=SRC, capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "status", "--short", "src", "include", "CMakeLists.txt"], cwd=SRC,
                           capture_output=True, text=True).stdout.split("\n")
    dirty = [x.strip() for x in dirty if x.strip()]
    print("benchmark: executable %s copied to %s (sha256 %s, built %s); git %s%s" % (
        a.exe, EXE, sha, time.strftime("%Y-%m-%d %H:%M", time.localtime(os.path.getmtime(a.exe))), git,
        ("; working tree differs in: " + ", ".join(dirty)) if dirty else ""))
    check_memory_tool(out)
    print("benchmark: peak memory by %s; %d cores; load average %.2f %.2f %.2f" % (
        "GNU time on every rank (max over ranks)" if MEM_MODE == "gnu-time" else "os.wait4 ru_maxrss",
        os.cpu_count(), *os.getloadavg()))

    if a.only_orderings:
        orderings(out, ord_level, a.timeout)
        print("\nbenchmark wall time %.1f s" % (time.time() - t_start))
        return 0

    rows = []
    work = [("hertz", lv) for lv in hl] + [("s1", lv) for lv in sl]
    todo = [(scene, lv, cfg) for scene, lv in work for cfg in CONFIGS
            if not (scene == "hertz" and lv in partial and cfg[0] not in pconf)]
    if partial:
        print("benchmark: Hertz level(s) %s only with %s" % (",".join(map(str, partial)), ", ".join(pconf)))
    total = len(todo)
    k = 0
    for scene, lv, cfg in todo:   # all configurations of one level back-to-back
        k += 1
        rows.append(measure(out, scene, lv, cfg, a.timeout, k, total))
    t_runs = time.time() - t_start

    cols = ["scene", "level", "dofs", "method", "path", "path_requested", "switched_msg", "ranks",
            "reference", "config", "iterations", "active_nodes", "contact_nodes",
            "t_mesh", "t_contact", "t_assembly", "t_solve", "t_output", "t_total",
            "t_fact", "n_fact_sym", "n_fact_num", "t_matsolve", "n_matsolve", "t_dense_lu",
            "factor_flops", "factor_flops_max_rank", "interface_unknowns",
            "wall_s", "cpu_s", "peak_mb", "peak_mb_sum", "maxrss_wait4_mb", "load1",
            "pressure_l2_rel", "peak_pressure", "half_width", "half_width_err", "peak_err",
            "contact_force", "force_err", "solve_over_ref", "total_over_ref"]
    for r in rows:
        ref = find(rows, r["scene"], r["level"], "tied-ref-%dr" % r["ranks"])
        r["solve_over_ref"] = r["t_solve"] / ref["t_solve"] if ref else float("nan")
        r["total_over_ref"] = r["t_total"] / ref["t_total"] if ref else float("nan")
    path = os.path.join(out, "benchmark.csv")
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([("%.6e" % r[c]) if isinstance(r[c], float) else r[c] for c in cols])
    print("\nCSV: %s (%d runs, %.1f s)" % (path, len(rows), t_runs))

    # every run took the path it asked for
    for r in rows:
        if not r["reference"] and (r["path"] != r["path_requested"] or r["switched_msg"]):
            print("NOTE: %s %s L%d on %d rank(s) asked for %s, reports path %s, switch message %s" % (
                r["scene"], r["config"], r["level"], r["ranks"], r["path_requested"], r["path"],
                bool(r["switched_msg"])))

    checks = []
    cl = [int(x) for x in a.csv_check_levels.split(",") if x.strip()]
    if cl:
        t0 = time.time()
        checks += csv_pressure_checks(out, "hertz", [lv for lv in cl if lv in hl], a.timeout)
        checks += csv_pressure_checks(out, "s1", [lv for lv in (1, 2, 4) if lv in sl], a.timeout)
        print("contact CSV checks: %d comparisons, %.1f s (untimed extra runs)" % (len(checks), time.time() - t0))

    ok = True
    for scene in ("hertz", "s1"):
        if not any(r["scene"] == scene for r in rows):
            continue
        print("\n" + "=" * 30 + " %s " % ("S3 Hertz" if scene == "hertz" else "S1 seed patch") + "=" * 30)
        print("errors: " + ("pressure_l2_rel, |a_h - a|/a, |peak - p0|/p0" if scene == "hertz"
                            else "contact force / (p * 0.5) - 1"))
        print("    %-5s %-20s %8s %5s %6s %11s %11s %11s %9s %9s" % (
            "level", "config", "dofs", "steps", "active", "p_l2_rel", "a_err", "peak_err", "force_err",
            "solve_s"))
        for r in sorted([r for r in rows if r["scene"] == scene and not r["reference"]],
                        key=lambda r: (r["config"], r["level"])):
            print("    %-5s %-20s %8d %5s %6s %11s %11s %11s %9s %9.3f" % (
                r["level"], r["config"], r["dofs"], r["iterations"], r["active_nodes"],
                fmt(r["pressure_l2_rel"], "%.3e"), fmt(r["half_width_err"], "%.3e"),
                fmt(r["peak_err"], "%.3e"), fmt(r["force_err"], "%.1e"), r["t_solve"]))
        report_growth(rows, scene)
        report_ratios(rows, scene)
        report_speedup(rows, scene)
        report_stages(rows, scene)
        ok &= report_same_answer(rows, scene, checks)

    plot(rows, a.png)
    if a.orderings:
        orderings(out, ord_level, a.timeout)
    print("\nbenchmark wall time %.1f s (%.1f min)" % (time.time() - t_start, (time.time() - t_start) / 60))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
