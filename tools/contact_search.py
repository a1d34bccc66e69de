#!/usr/bin/python3
"""The contact stage's time per contact edge on long interfaces (issue 35).

Two strips (meshes/strips.geo: the lower [0,100]x[-1,0] non-mortar, the upper
[0,95]x[0,1] mortar, one quad through each, 7:10 edges along the interface,
so the non-mortar strip's last 5% face nothing and keep the reach check's
search busy) pressed together under a pressure (S2's supports), for a range
of total contact edges (non-mortar + mortar). Per size: the dofs, the contact
stage (ContactSetup: gathering both surfaces, the mortar segments, the rows;
the summary's time.contact), its time per contact edge, the solve and output
stages (the reach check runs in the solve stage, the contact point fields in
the output stage), the whole run, and the contact stage's share of it. The
meshes are made by gmsh once (kept in --dir) and the program runs on 1 rank
(every rank does the same search) with the default automatic reach (a tenth
of the mortar surface's extent, 9.5: most mortar edges lie within it of a
non-mortar edge's bounding box, which is what made the old search quadratic).

    /usr/bin/python3 tools/contact_search.py [--sizes 1000,...] [--exe PATH] [--repeat 2]

The executable is copied first (others may rebuild build/mortar2d meanwhile);
--exe times another build (e.g. the one before the tree search) on the same
meshes. Timings are wall times of a shared machine: the smallest of --repeat
runs is printed."""
import argparse
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tests"))
import m2d  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--sizes", default="1000,3000,10000,30000,100000,200000,340000")
ap.add_argument("--exe", default=m2d.EXE)
ap.add_argument("--dir", default=os.path.join(m2d.WORK, "contact_search"))
ap.add_argument("--repeat", type=int, default=2)
args = ap.parse_args()

os.makedirs(args.dir, exist_ok=True)
exe = os.path.join(args.dir, "mortar2d")
shutil.copy2(args.exe, exe)
geo = os.path.join(m2d.SRC, "meshes", "strips.geo")
opts = ["-bodies", "lower,upper", "-lower_E", "1e9", "-lower_nu", "0.3", "-upper_E", "1e9", "-upper_nu", "0.3",
        "-plane", "strain", "-dirichlet", "lower_bottom:y,lower_origin:x,upper_left:x", "-pressure", "upper_top:1e6",
        "-contact_nonmortar", "lower_top", "-contact_mortar", "upper_bottom", "-output", "summary"]

print("executable: %s (copied from %s)" % (exe, args.exe))
print("%9s %9s %9s %11s %14s %9s %9s %9s %8s" % ("edges", "nm:m", "dofs", "contact s", "us per edge", "solve s", "output s", "total s", "contact"))
for total in [int(float(x)) for x in args.sizes.split(",")]:
    nl = round(total * 7 / 17)
    nu = total - nl
    msh = os.path.join(args.dir, "strips_%d_%d.msh" % (nl, nu))
    if not os.path.exists(msh):
        tmp = msh + ".tmp.msh"
        subprocess.run(["gmsh", "-2", "-format", "msh41", "-bin", "-v", "2", "-setnumber", "nl", str(nl), "-setnumber", "nu", str(nu),
                        "-setnumber", "Lu", "95", geo, "-o", tmp], check=True)
        os.replace(tmp, msh)
    best = None
    for rep in range(args.repeat):
        out = os.path.join(args.dir, "run")
        summary = os.path.join(out, "summary.json")
        if os.path.exists(summary):
            os.remove(summary)
        r = m2d.launch([exe, "-mesh", msh, "-output_dir", out, "-summary", summary] + opts, timeout=3600)
        if r.rc != 0:
            sys.exit("run failed (exit %s): %s\n%s" % (r.rc, r.cmdline, r.stderr[-2000:]))
        s = m2d.read_json(summary)
        if best is None or s["time"]["contact"] < best["time"]["contact"]:
            best = s
    t = best["time"]
    print("%9d %9s %9d %11.4f %14.3f %9.3f %9.3f %9.3f %7.2f%%" % (total, "%d:%d" % (nl, nu), best["dofs"], t["contact"], 1e6 * t["contact"] / total,
                                                                 t["solve"], t["output"], t["total"], 100 * t["contact"] / t["total"]), flush=True)
