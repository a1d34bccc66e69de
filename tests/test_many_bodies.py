"""Many bodies (issue 33 item 4): columns of blocks (meshes/column.geo), each
block its own mesh, no two neighbours' meshes matching, every interface a
contact pair (b(i+1)_bottom non-mortar on b(i)_top), the bottom block on
rollers, every left edge held in x, a pressure on the top: the exact answer
is sigma_yy = -p, sigma_xx = sigma_xy = 0 in every block (the patch test
across every interface).
 1. 9 and 40 blocks (before: "option -bodies: at most 8 entries", or "more
    than 8 physical surfaces" without -bodies): exact to 1e-10 on 1 and 2
    ranks, every body's material given (40: 80 options), the condensed path;
    40 blocks on the full and the iterative paths too;
 2. the caps, stated in -help and the README: 256 blocks solve (exact), 257
    are one line naming the cap; 513 contact pairs and 513 loads one line."""
import os
import subprocess

from m2d import SRC, Tally, mesh, refusal_problems, run, solve, workdir

T = Tally()
W = workdir("many_bodies")
P = 1e6


def column(n, path=None, materials=True):
    pairs = ",".join("b%d_bottom:b%d_top" % (i + 1, i) for i in range(1, n))
    args = ["-mesh", path or mesh("column_%d" % n), "-plane", "strain", "-dirichlet", "b1_bottom:y,b1_origin:x,left:x",
            "-pressure", "b%d_top:%r" % (n, P), "-contact_pairs", pairs, "-exact", "uniform", "-output_vtu", "0", "-contact_monitor", "0"]
    for i in range(1, n + 1) if materials else ():
        args += ["-b%d_E" % i, "1e9", "-b%d_nu" % i, "0.25" if i % 2 else "0.3"]
    return args


def exact(s):
    return max(s["error"][k] for k in ("sigma_yy_max_rel", "sigma_xx_max_rel", "sigma_xy_max_rel"))


for n in (9, 40):
    for ranks in (1, 2):
        s = solve("column_%d_%d" % (n, ranks), column(n), ranks=ranks)
        T.check(s["bodies"] == n and exact(s) < 1e-10 and s["active_nodes"] == s["contact_nodes"],
                "%d blocks, %d rank(s): the patch test across %d interfaces" % (n, ranks, n - 1), "%.1e, %d contact nodes, %s path" % (exact(s), s["contact_nodes"], s["kkt_path"]))
for path in ("full", "iterative"):
    s = solve("column_40_%s" % path, column(40) + ["-kkt_path", path, "-mortar_basis", "dual"], ranks=2)
    T.check(exact(s) < 1e-10 and s["kkt_path"] == path, "40 blocks, -kkt_path %s, 2 ranks: the patch test" % path, "%.1e" % exact(s))

# the caps
for n in (256, 257):
    path = os.path.join(W, "column_%d.msh" % n)
    subprocess.run(["gmsh", "-2", "-format", "msh41", "-v", "2", "-setnumber", "nblock", str(n), os.path.join(SRC, "meshes", "column.geo"), "-o", path], check=True, capture_output=True)
    if n == 256:
        s = solve("column_256", column(n, path, materials=False) + ["-pressure", "b256_top:1e-3"])
        T.check(s["bodies"] == 256 and exact(s) < 1e-10, "256 blocks (the cap): the patch test", "%.1e, %.1f s" % (exact(s), s["time"]["total"]))
    else:
        rc, out, err = run(column(n, path, materials=False) + ["-output_dir", W], check=False)
        line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()], ["column_257.msh", "more than 256 physical surfaces"])
        T.check(not problems, "257 blocks: one line naming the cap", line)
        rc, out, err = run(column(n, path, materials=False) + ["-bodies", ",".join("b%d" % i for i in range(1, n + 1)), "-output_dir", W], check=False)
        line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()], ["option -bodies", "at most 256 entries"])
        T.check(not problems, "-bodies with 257 names: one line naming the cap", line)
for opt, value, culprits in (("-contact_pairs", ",".join("b2_bottom:b1_top" for _ in range(513)), ["option -contact_pairs", "at most 512 entries"]),
                             ("-pressure", ",".join("b9_top:1" for _ in range(513)), ["option -pressure", "at most 512"])):
    rc, out, err = run(column(9) + [opt, value, "-output_dir", W], check=False)
    line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()], culprits)
    T.check(not problems, "%s with 513 entries: one line naming the cap" % opt, line)
T.finish()
