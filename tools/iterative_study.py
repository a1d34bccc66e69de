#!/usr/bin/python3
"""The iterative path's settings against the condensed path on Hertz (issue 25
item 2; docs/scaling.md): each configuration of -kkt_path iterative and the
condensed path run in turn, the rounds interleaved (a machine shared with
other work drifts between rounds, not within one), min of the rounds.

    /usr/bin/python3 tools/iterative_study.py [--level 4] [--ranks 1] [--repeat 3]
        [--configs NAME,NAME,...] [--out build/iterative_study]

Per configuration: active-set steps, Krylov iterations (all steps), AMG
set-ups, solve seconds and whole-process wall seconds (min over the rounds),
CPU seconds of the process (min; less sensitive to the load than the wall
time), peak memory of the largest rank, the ratio of the whole-process wall
time to the condensed path's (each round's own ratio; min and median), and
the check: the same active set as the condensed path (the steps that led
there may differ: inexact steps take the set their solve tells), contact
pressures equal to 1e-8 of the peak. A configuration that does not pass the
check is marked NOT EQUAL (and the tool exits 1).
"""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import m2d  # noqa: E402

H = "-iterative_pc_hypre_boomeramg_"
# name -> options after -kkt_path iterative (the defaults: "default")
CONFIGS = {
    "default": [],
    "prove": ["-iterative_prove"],  # every step's set proven: the condensed path's steps one by one (the default before)
    "complete": ["-iterative_inexact", "0", "-iterative_zone", "-1", "-iterative_reuse", "0"],  # each step to 1e-12, a new AMG each step
    # the path before issue 25: complete steps, a new AMG each, BoomerAMG without aggressive coarsening, symmetric Gauss-Seidel
    "before": ["-iterative_inexact", "0", "-iterative_zone", "-1", "-iterative_reuse", "0", H + "agg_nl", "0",
               H + "relax_type_down", "symmetric-SOR/Jacobi", H + "relax_type_up", "symmetric-SOR/Jacobi"],
    "inexact": ["-iterative_zone", "-1", "-iterative_reuse", "0"],
    "no-zone": ["-iterative_zone", "-1"],
    "zone1": ["-iterative_zone", "1"],
    "zone2": ["-iterative_zone", "2"],
    "zone8": ["-iterative_zone", "8"],
    "reuse1.5": ["-iterative_reuse", "1.5"],
    "reuse4": ["-iterative_reuse", "4"],
    "new-amg": ["-iterative_reuse", "0"],
    "inexact0.01": ["-iterative_inexact", "0.01"],
    "inexact0.3": ["-iterative_inexact", "0.3"],
    "inexact0.5": ["-iterative_inexact", "0.5"],
    "sgs": [H + "relax_type_down", "symmetric-SOR/Jacobi", H + "relax_type_up", "symmetric-SOR/Jacobi"],
    "agg0": [H + "agg_nl", "0"],
    "gs": [H + "relax_type_down", "SOR/Jacobi", H + "relax_type_up", "backward-SOR/Jacobi"],
    "agg1": [H + "agg_nl", "1"],
    "pmis": [H + "coarsen_type", "PMIS"],
    "st0.25": [H + "strong_threshold", "0.25"],
    "st0.7": [H + "strong_threshold", "0.7"],
    "pmax2": [H + "P_max", "2"],
    "gamg": ["-iterative_pc_type", "gamg"],
    "gs-pmis": [H + "relax_type_down", "SOR/Jacobi", H + "relax_type_up", "backward-SOR/Jacobi", H + "coarsen_type", "PMIS"],
    "gs-agg1": [H + "relax_type_down", "SOR/Jacobi", H + "relax_type_up", "backward-SOR/Jacobi", H + "agg_nl", "1"],
    "gs-pmis-st0.25": [H + "relax_type_down", "SOR/Jacobi", H + "relax_type_up", "backward-SOR/Jacobi", H + "coarsen_type", "PMIS", H + "strong_threshold", "0.25"],
    "gs-pmax2": [H + "relax_type_down", "SOR/Jacobi", H + "relax_type_up", "backward-SOR/Jacobi", H + "P_max", "2"],
    "gs-l1": [H + "relax_type_down", "l1-Gauss-Seidel", H + "relax_type_up", "backward-l1-Gauss-Seidel"],
    # systems AMG: nodal coarsening (2 unknowns a node), interpolation that keeps the rigid-body modes
    "nodal": [H + "nodal_coarsen", "4", H + "nodal_coarsen_diag", "1"],
    "vec": [H + "nodal_coarsen", "4", H + "nodal_coarsen_diag", "1", H + "vec_interp_variant", "2", H + "vec_interp_qmax", "4",
            H + "vec_interp_smooth", "1", H + "interp_refine", "1"],
    "vec-noagg": [H + "nodal_coarsen", "4", H + "nodal_coarsen_diag", "1", H + "vec_interp_variant", "2", H + "vec_interp_qmax", "4",
                  H + "vec_interp_smooth", "1", H + "interp_refine", "1", H + "agg_nl", "0"],
    "vec1": [H + "nodal_coarsen", "4", H + "nodal_coarsen_diag", "1", H + "vec_interp_variant", "1"],
}


def run_one(out, tag, args, ranks):
    d = os.path.join(out, tag)
    os.makedirs(d, exist_ok=True)
    summ = os.path.join(d, "summary.json")
    if os.path.exists(summ):
        os.remove(summ)
    r = m2d.launch(m2d.command(list(args) + ["-output_dir", d, "-output_name", "sol", "-output_vtu", "0",
                                             "-contact_monitor", "0", "-summary", summ], ranks), timeout=7200)
    if r.rc != 0:
        sys.stderr.write("run %s failed (exit %s): %s\n%s\n" % (tag, r.rc, r.cmdline, r.stderr[-3000:]))
        raise SystemExit(1)
    return m2d.read_json(summ), r, m2d.csv_columns(os.path.join(d, "sol_contact.csv"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--level", type=int, default=4)
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--configs", default="default,complete", help="names from: " + ",".join(CONFIGS))
    ap.add_argument("--out", default=os.path.join(m2d.SRC, "build", "iterative_study"))
    a = ap.parse_args()
    names = [x for x in a.configs.split(",") if x]
    for n in names:
        if n not in CONFIGS:
            ap.error("unknown configuration '%s' (known: %s)" % (n, ", ".join(CONFIGS)))
    mesh = m2d.hertz_mesh(a.level)
    base = ["-options_file", m2d.opts("hertz"), "-mesh", mesh]
    res = {n: [] for n in ["condensed"] + names}
    ref = None
    bad = False
    print("iterative study: Hertz level %d, %d rank(s), %d round(s), load %.1f" % (a.level, a.ranks, a.repeat, os.getloadavg()[0]), flush=True)
    for k in range(a.repeat):
        for n in ["condensed"] + names:
            args = base + (["-kkt_path", "condensed"] if n == "condensed" else ["-kkt_path", "iterative"] + CONFIGS[n])
            s, r, cols = run_one(a.out, "L%d_%dr_%s_%d" % (a.level, a.ranks, n, k), args, a.ranks)
            res[n].append((s, r))
            if n == "condensed":
                ref = ref or (s, cols)
                continue
            dp = max(abs(x - y) for x, y in zip(cols["pressure"], ref[1]["pressure"])) / max(abs(x) for x in ref[1]["pressure"])
            same = list(cols["active"]) == list(ref[1]["active"])
            if not (same and dp < 1e-8):
                bad = True
            print("  round %d %-12s wall %7.2f s, cpu %7.2f s, %2d steps (condensed %d), %3d its, %2d set-ups, %s, pressure %.1e of the peak" % (
                k, n, r.wall, r.cpu_s, s["iterations"], ref[0]["iterations"], s.get("ksp_iterations_total", 0), s.get("pc_setups", 0),
                "same set" if same else "DIFFERENT set", dp), flush=True)
        print("  round %d condensed    wall %7.2f s, cpu %7.2f s" % (k, res["condensed"][-1][1].wall, res["condensed"][-1][1].cpu_s), flush=True)
    s0 = res["condensed"][0][0]
    print("\nHertz level %d (%d dofs), %d rank(s), min of %d interleaved rounds:" % (a.level, s0["dofs"], a.ranks, a.repeat))
    print("| configuration | steps | Krylov its | AMG set-ups | solve s | wall s | cpu s | memory MB (max rank) | wall / condensed (min, median) |")
    print("|---|---|---|---|---|---|---|---|---|")
    cw = [r.wall for _, r in res["condensed"]]
    for n in ["condensed"] + names:
        ss = res[n]
        ratios = [r.wall / c for (_, r), c in zip(ss, cw)]
        s = ss[0][0]
        print("| %s | %d | %s | %s | %.2f | %.2f | %.2f | %.0f | %s |" % (
            n, s["iterations"], s.get("ksp_iterations_total", "-") if n != "condensed" else "-",
            s.get("pc_setups", "-") if n != "condensed" else "-", min(x["time"]["solve"] for x, _ in ss),
            min(r.wall for _, r in ss), min(r.cpu_s for _, r in ss), s["memory_max_rank_mb"],
            "1" if n == "condensed" else "%.2f, %.2f" % (min(ratios), statistics.median(ratios))))
    if bad:
        print("NOT EQUAL: a configuration did not give the condensed path's active set and pressures (above)")
        raise SystemExit(1)


if __name__ == "__main__":
    main()
