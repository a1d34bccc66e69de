"""Bad input: every case must end with exit code 1 (no crash, no hang), exactly
one non-empty stderr line "mortar2d: error: ..." that names the culprit (file,
option or physical group), and must leave a previous result in the same
-output_dir untouched (no temporary files left behind); the -summary is the
previous one, or, for input found bad after the output paths were checked,
the summary of the failed run: status "error" and that line. An unusable
TMPDIR (read-only, /dev/null, a file, missing: not created) is refused so, on
1 rank (with mpiexec, mpiexec itself fails in it first, in its own words).

The broken meshes are written into the work directory at test time. Some cases
also run on 2 ranks; there Open MPI's own "job aborted" banner (written by
mpiexec, not by mortar2d) is switched off (OMPI_MCA_orte_execute_quiet in
m2d.MPI_ENV)."""
import os
import random
import shutil
import subprocess

from m2d import MPI_ENV, Tally, mesh, opts, refusal_problems, run, solve, workdir

assert MPI_ENV.get("OMPI_MCA_orte_execute_quiet") == "1"
TIMEOUT = 60

W = workdir("bad_input")
OUT = os.path.join(W, "out")
SUMMARY = os.path.join(OUT, "summary.json")
T = Tally()
report = T.check


# ---------- a good result that the bad runs must not destroy ----------
shutil.rmtree(OUT, ignore_errors=True)
good = solve("bad_input/out", ["-options_file", opts("block"), "-mesh", mesh("block")])
assert good["cells"] == 16, good
KEPT = [os.path.join(OUT, n) for n in ("block.h5", "block.xmf", "block.vtu")]
GOOD_SUMMARY = open(SUMMARY, "rb").read()


def snapshot():
    snap = {}
    for p in KEPT:
        st = os.stat(p)
        with open(p, "rb") as f:
            snap[p] = (f.read(), st.st_mtime_ns, st.st_ino, st.st_size)
    return snap


BEFORE = snapshot()
BEFORE_LIST = sorted(os.listdir(OUT))


def stray_tmp():
    found = []
    for d in (OUT, W):
        found += [os.path.join(d, n) for n in os.listdir(d) if ".tmp" in n]
    return found


def preserved():
    """'' if the good result is intact, else what changed."""
    problems = []
    now = snapshot()
    for p in KEPT:
        if now[p] != BEFORE[p]:
            problems.append("%s changed" % os.path.basename(p))
    if sorted(os.listdir(OUT)) != BEFORE_LIST:
        problems.append("output dir now holds %s" % sorted(os.listdir(OUT)))
    tmp = stray_tmp()
    if tmp:
        problems.append("temporary files left: %s" % tmp)
    return "; ".join(problems)


# ---------- broken inputs ----------
with open(mesh("block")) as f:
    BLOCK = f.read()


def write(name, text, mode="w"):
    p = os.path.join(W, name)
    with open(p, mode) as f:
        f.write(text)
    return p


def edit(name, old, new, count=1):
    assert BLOCK.count(old) == count, (name, old)
    return write(name, BLOCK.replace(old, new))


missing = os.path.join(W, "nosuch.msh")
if os.path.exists(missing):
    os.remove(missing)
adir = os.path.join(W, "a_directory.msh")
os.makedirs(adir, exist_ok=True)

# two triangles, msh 2.2, with the groups block.opts names
tri = write("triangles.msh", """$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
4
0 6 "origin"
1 2 "bottom"
1 4 "top"
2 1 "block"
$EndPhysicalNames
$Nodes
4
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
$EndNodes
$Elements
5
1 15 2 6 1 1
2 1 2 2 1 1 2
3 1 2 4 3 3 4
4 2 2 1 1 1 2 3
5 2 2 1 1 1 3 4
$EndElements
""")
# msh 4.1: block.msh with its last quad (33: 25 10 3 11) split into two triangles
mixed = write("mixed.msh", BLOCK.replace("6 33 1 33\n", "7 34 1 34\n").replace("2 1 3 16\n", "2 1 3 15\n")
              .replace("33 25 10 3 11 \n", "2 1 2 2\n33 25 10 3\n34 25 3 11\n"))
assert open(mixed).read() != BLOCK and "2 1 2 2\n" in open(mixed).read()
# node 17 (0.25, 0.25) moved across its neighbour at (0.5, 0.25): the quads around it fold
folded = edit("folded.msh", "0.2499999999998183 0.2500000000006331 0\n", "0.6 0.2500000000006331 0\n")
# node 17 moved onto node 1 (0,0): quad 18 = (0,0),(0.25,0),(0,0),(0,0.25) has zero area
zero = edit("zero_area.msh", "0.2499999999998183 0.2500000000006331 0\n", "0 0 0\n")
truncated = write("truncated.msh", BLOCK[: len(BLOCK) // 2])
rng = random.Random(12345)
binary = write("binary.msh", bytes(rng.randrange(256) for _ in range(4096)), "wb")
afile = write("afile", "a regular file, not a directory\n")
bad_outdir = os.path.join(afile, "sub")

# (name, extra args, strings the error line must contain, ranks to run on)
CASES = [
    ("missing mesh file", ["-mesh", missing], [missing], (1, 2)),
    ("directory as mesh file", ["-mesh", adir], [adir], (1, 2)),
    ("-dirichlet names a missing group", ["-dirichlet", "nosuch:x"], ["-dirichlet", "nosuch"], (1, 2)),
    ("-pressure names a missing group", ["-pressure", "nosuch:1"], ["-pressure", "nosuch"], (1, 2)),
    ("-bodies names a missing group", ["-bodies", "nosuch"], ["-bodies", "nosuch"], (1, 2)),
    ("triangles (msh 2.2)", ["-mesh", tri], [tri, "triangle"], (1,)),
    ("mixed triangles and quads (msh 4.1)", ["-mesh", mixed], [mixed, "triangle"], (1, 2)),
    ("node moved across its neighbour (folded quads)", ["-mesh", folded], [folded, "non-convex"], (1, 2)),
    ("zero-area quad", ["-mesh", zero], [zero, "zero area"], (1,)),
    ("-block_E -1", ["-block_E", "-1"], ["-block_E"], (1, 2)),
    ("-block_E 0", ["-block_E", "0"], ["-block_E"], (1,)),
    ("-block_E abc (not a number)", ["-block_E", "abc"], ["-block_E"], (1,)),
    ("-block_nu 0.5", ["-block_nu", "0.5"], ["-block_nu"], (1,)),
    ("-block_nu -1", ["-block_nu", "-1"], ["-block_nu"], (1,)),
    ("-block_nu 0.7", ["-block_nu", "0.7"], ["-block_nu"], (1,)),
    ("-plane foo", ["-plane", "foo"], ["-plane", "foo"], (1,)),
    ("-exact foo", ["-exact", "foo"], ["-exact", "foo"], (1,)),
    ("-dirichlet bottom:z", ["-dirichlet", "bottom:z"], ["-dirichlet", "bottom:z"], (1,)),
    ("-pressure top:abc", ["-pressure", "top:abc"], ["-pressure", "top:abc"], (1,)),
    ("-output_dir under a regular file", ["-output_dir", bad_outdir], ["-output_dir", "afile"], (1, 2)),
    ("truncated .msh (first half of block.msh)", ["-mesh", truncated], [truncated], (1, 2)),
    ("binary-looking .msh", ["-mesh", binary], [binary], (1,)),
]
if os.geteuid() != 0:  # root reads a chmod 000 file anyway
    unreadable = write("unreadable.msh", BLOCK)
    os.chmod(unreadable, 0)
    CASES.insert(2, ("unreadable (chmod 000) mesh file", ["-mesh", unreadable], [unreadable], (1,)))
else:
    print("skip unreadable (chmod 000) mesh file: running as root")

for name, extra, culprits, ranklist in CASES:
    for ranks in ranklist:
        what = "%s [%d rank%s]" % (name, ranks, "s" if ranks > 1 else "")
        args = ["-options_file", opts("block"), "-mesh", mesh("block"), "-output_dir", OUT, "-summary", SUMMARY] + extra
        try:
            rc, out, err = run(args, ranks=ranks, check=False, timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            report(False, what, "no exit within %d s (hang?)" % TIMEOUT)
            continue
        line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()], culprits)
        if name == "directory as mesh file" and ("directory" not in line.lower() or "out of memory" in line):
            problems.append("error does not say that the mesh path is a directory")
        keep = preserved()
        if keep:
            problems.append("previous result not preserved: " + keep)
        now = open(SUMMARY, "rb").read()
        if now != GOOD_SUMMARY:
            import json
            j = json.loads(now)
            if j.get("status") != "error" or "mortar2d: error: " + j.get("error", "") != line or j.get("run_id") == good["run_id"]:
                problems.append("the summary is neither the previous one nor the failed run's: %r" % now[:300])
            with open(SUMMARY, "wb") as f:  # the next case starts from the good one
                f.write(GOOD_SUMMARY)
        report(not problems, what, ("; ".join(problems) + " -- stderr: " if problems else "") + line)

# ---------- TMPDIR, checked before MPI starts (Open MPI creates a missing one
# and fails in an unusable one with some 40 lines). A read-only one needs a user
# the mode bits bind: as root, the run is made as nobody (setpriv).
AS_USER = [] if os.geteuid() else (["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"] if shutil.which("setpriv") else None)
readonly = os.path.join(W, "tmp_readonly")
os.makedirs(readonly, exist_ok=True)
os.chmod(readonly, 0o555)
afile = write("tmp_afile", "not a directory\n")
missing = os.path.join(W, "tmp_missing")
shutil.rmtree(missing, ignore_errors=True)
TMPCASES = [("/dev/null", "/dev/null", "not a directory", []), ("a regular file", afile, "not a directory", []),
            ("missing", missing, "No such file or directory", [])]
if AS_USER is None:
    print("skip read-only TMPDIR: running as root without setpriv")
else:
    TMPCASES.append(("read-only" + (" (as nobody)" if AS_USER else ""), readonly, "Permission denied", AS_USER))
for name, tmp, why, wrapper in TMPCASES:
    args = ["-options_file", opts("block"), "-mesh", mesh("block"), "-output_dir", OUT, "-summary", SUMMARY]
    rc, out, err = run(args, check=False, timeout=TIMEOUT, env={"TMPDIR": tmp}, wrapper=wrapper)
    line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()], ["TMPDIR", "'%s'" % tmp, why])
    if name == "missing" and os.path.exists(missing):
        problems.append("the missing TMPDIR was created")
    keep = preserved()
    if keep or open(SUMMARY, "rb").read() != GOOD_SUMMARY:
        problems.append("previous result not preserved: %s" % (keep or "the summary changed"))
    report(not problems, "TMPDIR %s [1 rank]" % name, ("; ".join(problems) + " -- stderr: " if problems else "") + line)
os.chmod(readonly, 0o755)

keep = preserved()
report(not keep, "previous result in %s intact, no .tmp files" % OUT, keep)
T.finish()
