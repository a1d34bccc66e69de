#!/usr/bin/python3
"""The adaptive loop's speed ratio (issue 25 item 1), in one interleaved run:

    wall(options/hertz_adapt.opts) / wall(options/hertz.opts on uniform level 5)

both as they are (their own output files on), whole-process wall time, the
runs interleaved (a slow moment of the shared machine touches one round of
each rather than every round of one), min over --repeat rounds; also the
cpu seconds (user + system of the process and its children, gmsh's included)
and the median walls. Every variant (--variant NAME:ARGS, ARGS appended to
hertz_adapt.opts; --exe2 PATH runs both with another build too, its ratios printed apart)
is a further point of the same rounds, printed with its dofs and its pressure
error against Hertz, so before/after figures come from one stretch of time.
--exe2 may be given more than once (builds exe2, exe3, ...).

  /usr/bin/python3 tools/loop_ratio.py [--repeat 3] [--level 5] [--out DIR]
      [--exe2 OTHER/mortar2d ...] [--variant "name:-adapt_growth 8" ...]
"""
import argparse
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "tests"))
import m2d  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3, help="rounds (min taken)")
    ap.add_argument("--level", type=int, default=5, help="uniform Hertz level of the reference run")
    ap.add_argument("--out", default=os.path.join(m2d.SRC, "build", "loop_ratio"))
    ap.add_argument("--exe2", action="append", default=[], help="another build's mortar2d (e.g. before a change): both runs with it as well; repeatable")
    ap.add_argument("--variant", action="append", default=[], help="NAME:ARGS, hertz_adapt.opts with ARGS appended")
    a = ap.parse_args()
    uniform = ["-options_file", m2d.opts("hertz"), "-mesh", m2d.hertz_mesh(a.level)]
    adapt = ["-options_file", m2d.opts("hertz_adapt")]
    points = [("uniform_L%d" % a.level, None, uniform), ("hertz_adapt", None, adapt)]
    tags = [""] + ["[exe%d]" % (k + 2) for k in range(len(a.exe2))]
    for tag, exe in zip(tags[1:], a.exe2):
        points += [("uniform_L%d%s" % (a.level, tag), os.path.abspath(exe), uniform), ("hertz_adapt" + tag, os.path.abspath(exe), adapt)]
    for v in a.variant:
        name, _, extra = v.partition(":")
        points.append((name, None, adapt + extra.split()))
    res = {p[0]: {"wall": [], "cpu": [], "s": None} for p in points}
    for k in range(a.repeat):
        for name, exe, args in points:
            d = os.path.join(a.out, name.replace("[", "_").replace("]", ""))
            os.makedirs(d, exist_ok=True)
            summ = os.path.join(d, "summary.json")
            if os.path.exists(summ):
                os.remove(summ)
            cmd = m2d.command(args + ["-output_dir", d, "-summary", summ], exe=exe)
            r = m2d.launch(cmd, timeout=3600, stdout=os.path.join(d, "log.txt"), merge=True)
            if r.rc != 0:
                sys.exit("loop_ratio: %s failed (exit %s), log %s" % (r.cmdline, r.rc, os.path.join(d, "log.txt")))
            res[name]["wall"].append(r.wall)
            res[name]["cpu"].append(r.cpu_s)
            res[name]["s"] = m2d.read_json(summ)
        print("round %d/%d: %s" % (k + 1, a.repeat, "  ".join("%s %.2f s" % (n, res[n]["wall"][-1]) for n, _, _ in points)), flush=True)
    ref = res[points[0][0]]
    print("\n| run | dofs | error (Hertz) | wall min (s) | wall median (s) | cpu min (s) | wall / uniform L%d |" % a.level)
    print("|---|---|---|---|---|---|---|")
    for name, _, _ in points:
        r = res[name]
        print("| %s | %d | %.3e | %.3f | %.3f | %.3f | 1/%.1f |" % (name, r["s"]["dofs"], r["s"].get("pressure_l2_rel", float("nan")), min(r["wall"]), statistics.median(r["wall"]),
                                                           min(r["cpu"]), min(ref["wall"]) / min(r["wall"])))
    for tag, exe in zip(tags, [""] + a.exe2):
        u, h = res["uniform_L%d%s" % (a.level, tag)], res["hertz_adapt" + tag]
        print("\nratio hertz_adapt / uniform L%d%s: wall (min) 1/%.1f, wall (median) 1/%.1f, cpu (min) 1/%.1f" % (a.level, " with " + exe if tag else "", min(u["wall"]) / min(h["wall"]),
              statistics.median(u["wall"]) / statistics.median(h["wall"]), min(u["cpu"]) / min(h["cpu"])))


if __name__ == "__main__":
    main()
