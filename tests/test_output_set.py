"""The results of a run replace the previous results as a whole (outputset.h).

Scene: Hertz (options/hertz.opts) on hertz_2 with two loads, A (0.43) and B
(0.5), so that every file but the .xmf differs between the two sets.  Each
run writes the other set into the same directory D and is interrupted at a
random moment of its output, on 1 and 2 ranks, by SIGINT, SIGTERM (1 rank: to
the program; 2 ranks: SIGINT to mpiexec, as Ctrl-C does, which passes SIGTERM
on to the ranks about 1 s later, and SIGTERM to every rank, as a batch system
does) and SIGKILL (to rank 0).
The test hook M2D_TEST_OUTPUT_DELAY (seconds; read only when set) makes the
program sleep between the steps of writing and committing, so that the
moments spread over the whole output; the moment is drawn after the staging
directory appears, and one run per case is interrupted right after the switch.
After every run:
  - D's five names (hertz.h5/.xmf/.vtu/_contact.csv, summary.json) are the
    complete previous set or the complete new set, byte for byte (the summary
    without its "time" object and memory figure) -- never a mix, never a missing file;
  - SIGINT/SIGTERM: exit code 1, one stderr line "mortar2d: error: interrupted
    by SIG...; no output written, previous results kept" (then D holds the
    previous set) or "...; the output was already complete" (the new set), and
    nothing else in D (no temporary, no old set);
  - SIGKILL may leave temporaries; the next run removes them.
Also: an interruption before the output; two kills of hertz_4 without the
hook; a -summary outside D (it always matches the set in D); a directory that
holds plain files of an earlier version (kept visible until the switch);
another -output_name's set and a user's file in D are never touched; and the
up-front checks (an unwritable -output_dir or -summary, -output_name with
quotes, '<', '&', too long): one line naming the option, exit 1, D untouched."""
import json
import os
import random
import re
import shutil
import signal
import stat
import subprocess
import sys
import time

import numpy as np
from m2d import EXE, MPIEXEC, SRC, Tally, mesh, opts, read_h5, refusal_problems, workdir

os.environ["OMPI_MCA_orte_execute_quiet"] = "1"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
W = workdir("output_set")
NAME = "hertz"
PUB = [NAME + s for s in (".h5", ".xmf", ".vtu", "_contact.csv")] + ["summary.json"]
DELAY = 0.1        # seconds per step with the hook
STEPS = 14         # hook steps from the staging directory to the end of a run
LOADS = {"A": "0.43", "B": "0.5"}
SIGS = {"INT": signal.SIGINT, "TERM": signal.SIGTERM, "KILL": signal.SIGKILL}
MSG = re.compile(r"^mortar2d: error: interrupted by SIG(INT|TERM|HUP); (no output written, previous results kept|the output was already complete)$")
rng = random.Random(20240613)
T = Tally()
report = T.check


def args(d, which, level=2, summary=None):
    return ["-options_file", opts("hertz"), "-mesh", mesh("hertz_%d" % level), "-pressure", "cylinder_top:" + LOADS[which],
            "-output_dir", d, "-output_name", NAME, "-summary", summary or os.path.join(d, "summary.json"), "-contact_monitor", "0"]


def command(a, ranks):
    cmd = [EXE] + a
    return [MPIEXEC, "--oversubscribe", "-n", str(ranks)] + cmd if ranks > 1 else cmd


def read_file(p, n):
    """what a file says, for comparison: arrays of its numbers (None if missing, a
    string if incomplete or unreadable); the summary without "time"; .xmf bytes"""
    if not os.path.lexists(p) or not os.path.exists(p):
        return None
    with open(p, "rb") as f:
        b = f.read()
    try:
        if n.endswith(".h5"):
            xy, cells, vf, cf = read_h5(p)
            return [np.nan_to_num(v) for v in (xy, cells, vf["displacement"], vf["contact_pressure"], cf["von_mises"])]
        if n.endswith(".vtu"):
            k = b.index(b'<AppendedData encoding="raw">')
            k = b.index(b"_", k) + 1
            nb = int(np.frombuffer(b[k:k + 8], np.uint64)[0])
            assert b.endswith(b"</VTKFile>\n"), "no </VTKFile> at the end"
            return [len(b), np.frombuffer(b[k + 8:k + 8 + nb], np.float64)]
        if n.endswith(".csv"):
            return [np.loadtxt(p, delimiter=",", skiprows=1)]
        if n.endswith(".json"):
            j = json.loads(b)
            for k in ("time", "residual_rel", "complementarity", "memory_max_rank_mb"):  # timings, memory and round-off figures
                j.pop(k, None)
            return j
        return b
    except Exception as e:
        return "unreadable (%s)" % e


def same(a, b):
    """equal, numbers to 1e-8 of their size (2 ranks: the solve is not bitwise reproducible)"""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and np.allclose(a, b, rtol=0, atol=1e-8 * max(np.abs(b).max(), 1e-300))
    if isinstance(a, float):
        return abs(a - b) <= 1e-8 * max(abs(b), 1e-300)
    return a == b


def content(d, names=PUB, summary=None):
    return {n: read_file(summary if (summary and n == "summary.json") else os.path.join(d, n), n) for n in names}


def classify(got, refs):
    """'A' or 'B' when every file equals that set (refs: {'A': ..., 'B': ...} or
    {'A1': ..., 'A2': ...} by rank count, whose vertex orders differ), else a
    description of the mix"""
    for k, ref in refs.items():
        if all(same(got[n], ref[n]) for n in ref):
            return k[0]
    return "mix: " + ", ".join("%s=%s" % (n, "missing" if got[n] is None else "/".join(k for k in refs if same(got[n], refs[k][n])) or "other") for n in PUB)


def leftovers(d, keep=()):
    """entries of d besides the public names, the current set and `keep`"""
    ptr = os.path.join(d, ".m2d.set." + NAME)
    cur = os.readlink(ptr) if os.path.islink(ptr) else None
    return sorted(n for n in os.listdir(d) if n not in PUB and n not in keep and n not in (".m2d.set." + NAME, cur))


def good_run(d, which, ranks=1, level=2, summary=None):
    p = subprocess.run(command(args(d, which, level, summary), ranks), cwd=SRC, capture_output=True, text=True, env=ENV, timeout=600)
    if p.returncode != 0:
        print(p.stdout[-2000:], p.stderr[-2000:])
    return p.returncode


def reference(which, ranks, level=2):
    d = os.path.join(W, "ref_%s_%d_%d" % (which, ranks, level))
    shutil.rmtree(d, ignore_errors=True)
    assert good_run(d, which, ranks, level) == 0, "reference run %s failed" % d
    return content(d)


def gens(d):
    return {n for n in os.listdir(d) if n.startswith(".m2d.gen.")}


def interrupted(d, which, ranks, sig, moment, level=2, delay=DELAY, summary=None, wait_for="stage"):
    """start a run, interrupt it `moment` s after its staging directory appears
    (wait_for='switch': right after .m2d.set.NAME changes; 'start': after the
    first line of stdout, before the solve); return (rc, stderr lines, moment)"""
    env = dict(ENV)
    if delay:
        env["M2D_TEST_OUTPUT_DELAY"] = str(delay)
    before = gens(d) if os.path.isdir(d) else set()
    ptr = os.path.join(d, ".m2d.set." + NAME)
    old = os.readlink(ptr) if os.path.islink(ptr) else None
    p = subprocess.Popen(command(args(d, which, level, summary), ranks), cwd=SRC, stdout=subprocess.PIPE if wait_for == "start" else subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, env=env)
    t0, stage = time.time(), None
    if wait_for == "start":  # the first line comes once the mesh is read: the solve is next
        p.stdout.readline()
    while wait_for not in ("start", "end") and p.poll() is None and time.time() - t0 < 300:
        new = gens(d) - before if os.path.isdir(d) else set()
        if new:
            stage = sorted(new)[0]
            if wait_for == "stage":
                break
            if os.path.islink(ptr) and os.readlink(ptr) not in (old,):
                break
        time.sleep(0.002)
    if wait_for == "end" or p.poll() is not None:
        err = p.communicate()[1]
        return p.returncode, [l for l in err.splitlines() if l.strip()], "finished before the signal"
    time.sleep(moment)
    if ranks > 1 and sig == signal.SIGKILL:
        os.kill(int(stage.split(".")[4]), sig)  # rank 0: .m2d.gen.<host>.<pid>.<k>.NAME
    elif ranks > 1 and sig == signal.SIGTERM:  # as a batch system does: every rank
        with open("/proc/%d/task/%d/children" % (p.pid, p.pid)) as f:
            for pid in f.read().split():
                os.kill(int(pid), sig)
    else:
        p.send_signal(sig)  # 1 rank: the program; 2 ranks: mpiexec, which sends SIGTERM to the ranks
    try:
        err = p.communicate(timeout=120)[1]
    except subprocess.TimeoutExpired:
        p.kill()
        return None, ["no exit within 120 s after the signal"], ""
    wait_gone(int(stage.split(".")[4]) if stage else None)
    return p.returncode, [l for l in err.splitlines() if l.strip()], "%s + %.3f s" % (wait_for, moment)


def wait_gone(pid, limit=20):
    """mpiexec may exit before its ranks: wait until rank 0 has ended (zombie or gone)"""
    t0 = time.time()
    while pid and time.time() - t0 < limit:
        try:
            with open("/proc/%d/stat" % pid) as f:
                if f.read().rsplit(")", 1)[1].split()[0] in "ZX":
                    return
        except OSError:
            return
        time.sleep(0.01)


def check_interrupted(what, d, sig, ranks, rc, lines, prev, new, refs, summary=None):
    """the assertions after one interrupted run; returns the set now in d"""
    got = classify(content(d, summary=summary), refs)
    problems = []
    if got not in ("A", "B"):
        problems.append("D holds " + got)
    elif got not in (prev, new):
        problems.append("D holds set %s (previous %s, new %s)" % (got, prev, new))
    if rc == 0:  # the run ended before the signal came: a complete run
        what += " (the run had finished)"
        if got != new or lines:
            problems.append("exit 0 but D holds set %s, stderr %r" % (got, lines[:3]))
    elif sig == signal.SIGKILL:
        if rc is None or rc == 1:
            problems.append("exit code %s after SIGKILL" % rc)
    else:
        if rc != 1:
            problems.append("exit code %s (want 1)" % rc)
        if len(lines) != 1 or not MSG.match(lines[0]):
            problems.append("stderr is not one interruption line: %r" % lines[:4])
        else:
            m = MSG.match(lines[0])
            if ranks == 1 and m.group(1) != {signal.SIGINT: "INT", signal.SIGTERM: "TERM"}[sig]:
                problems.append("the line names SIG%s" % m.group(1))
            want = prev if m.group(2).startswith("no output") else new
            if got != want:
                problems.append("the line says '%s' but D holds set %s" % (m.group(2), got))
    if sig != signal.SIGKILL or rc == 0:
        left = leftovers(d, KEEP)
        if left:
            problems.append("left in D: %s" % left)
    report(not problems, what, "; ".join(problems) if problems else "D holds set %s (%s)" % (got, "previous" if got == prev else "new"))
    return got if got in ("A", "B") else prev


# ---------------------------------------------------------------- references
REFS = {r: {k: reference(k, r) for k in LOADS} for r in (1, 2)}
BOTH = {k + str(r): REFS[r][k] for r in (1, 2) for k in LOADS}  # D holds sets written on 1 or 2 ranks
for r in (1, 2):
    diff = [n for n in PUB if not same(REFS[r]["A"][n], REFS[r]["B"][n])]
    report(diff == [n for n in PUB if not n.endswith(".xmf")], "%d rank(s): sets A and B differ in every file but the .xmf" % r, "differ: %s" % diff)
# the writers add nothing that changes from run to run (no time stamps)
again = os.path.join(W, "again")
shutil.rmtree(again, ignore_errors=True)
good_run(again, "A")
bad = [n for n in PUB[:4] if open(os.path.join(again, n), "rb").read() != open(os.path.join(W, "ref_A_1_2", n), "rb").read()]
report(not bad, "two equal runs on 1 rank give byte-identical .h5, .xmf, .vtu, .csv", "differ: %s" % bad)

# ---------------------------------------------------------------- D with neighbours
D = os.path.join(W, "D")
shutil.rmtree(D, ignore_errors=True)
os.makedirs(D)
with open(os.path.join(D, "notes.txt"), "w") as f:
    f.write("a user's file\n")
p = subprocess.run([EXE, "-options_file", opts("hertz"), "-mesh", mesh("hertz_0"), "-output_dir", D, "-output_name", "other", "-output_vtu", "0"],
                   cwd=SRC, capture_output=True, text=True, env=ENV)
assert p.returncode == 0, p.stderr
OTHER = sorted(n for n in os.listdir(D) if n not in ("notes.txt",))
KEEP = set(OTHER) | {"notes.txt"} | {os.readlink(os.path.join(D, ".m2d.set.other"))}


def neighbours():
    return {n: (open(os.path.join(D, n), "rb").read(), os.stat(os.path.join(D, n)).st_ino, os.stat(os.path.join(D, n)).st_mtime_ns)
            for n in ["notes.txt", "other.h5", "other.xmf"]}


NB = neighbours()
assert good_run(D, "A") == 0
state = classify(content(D), REFS[1])
report(state == "A" and not leftovers(D, KEEP), "a good run leaves the complete set A and nothing else", "D holds %s, extra %s" % (state, leftovers(D, KEEP)))

# ---------------------------------------------------------------- interrupted runs
counts = {}
for ranks in (1, 2):
    for sname in ("INT", "KILL", "TERM"):
        sig = SIGS[sname]
        # mpiexec passes a SIGINT on as SIGTERM about 1 s later: a longer window
        delay = DELAY if ranks == 1 or sname != "INT" else 2 * DELAY
        span = (STEPS - 1) * delay - (1.0 if delay != DELAY else 0)
        moments = [(i + rng.random()) / 4 * span for i in range(4)]
        rng.shuffle(moments)
        for wait_for, moment in [("stage", m) for m in moments] + [("switch", 0.0)]:
            new = "B" if state == "A" else "A"
            rc, lines, when = interrupted(D, new, ranks, sig, moment, delay=delay, wait_for=wait_for)
            state2 = check_interrupted("%d rank(s), SIG%s at %s" % (ranks, sname, when), D, sig, ranks, rc, lines, state, new, BOTH)
            key = (ranks, sname, "new" if state2 == new else "previous")
            counts[key] = counts.get(key, 0) + 1
            state = state2
print("outcomes (ranks, signal, set in D): count: %s" % sorted(counts.items()))

# before the output: during the solve
for ranks in (1, 2):
    new = "B" if state == "A" else "A"
    rc, lines, when = interrupted(D, new, ranks, signal.SIGINT, 0.02, wait_for="start")
    ok = rc == 1 and len(lines) == 1 and MSG.match(lines[0]) and "no output written" in lines[0]
    got = classify(content(D), BOTH)
    report(ok and got == state and not leftovers(D, KEEP), "%d rank(s), SIGINT during the solve: one line, exit 1, set %s kept" % (ranks, state),
           "rc %s, stderr %r, D holds %s, extra %s" % (rc, lines[:3], got, leftovers(D, KEEP)))

# after a SIGKILL the next complete run leaves nothing behind
rc, lines, when = interrupted(D, "B" if state == "A" else "A", 1, signal.SIGKILL, 0.5 * DELAY)
state = classify(content(D), BOTH)
report(rc == -9 and state in ("A", "B") and leftovers(D, KEEP), "SIGKILL leaves a complete set and temporaries", "D holds %s, left %s" % (state, leftovers(D, KEEP)))
good_run(D, "A")
report(classify(content(D), REFS[1]) == "A" and not leftovers(D, KEEP), "the next run removes what the SIGKILL left", "left %s" % leftovers(D, KEEP))
report(neighbours() == NB and all(os.path.lexists(os.path.join(D, n)) for n in OTHER),
       "the user's file and the other -output_name's set are untouched (bytes, inode, mtime)")

# ---------------------------------------------------------------- hertz_4 without the hook
REF4 = {k: reference(k, 1, 4) for k in LOADS}
D4 = os.path.join(W, "D4")
shutil.rmtree(D4, ignore_errors=True)
good_run(D4, "A", 1, 4)
t0 = time.time()
before = gens(D4)
p4 = subprocess.Popen(command(args(D4, "B", 4), 1), cwd=SRC, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=ENV)
while p4.poll() is None and not gens(D4) - before:
    time.sleep(0.002)
t1 = time.time()
p4.wait()
window = time.time() - t1
print("hertz_4: %.2f s from the start to the staging directory, %.2f s from there to the exit" % (t1 - t0, window))
state4 = classify(content(D4), REF4)
for sname in ("KILL", "INT", "KILL", "TERM"):
    new = "B" if state4 == "A" else "A"
    rc, lines, when = interrupted(D4, new, 1, SIGS[sname], rng.uniform(0, 0.9 * window), level=4, delay=0)
    state4 = check_interrupted("hertz_4, no hook, SIG%s at %s" % (sname, when), D4, SIGS[sname], 1, rc, lines, state4, new, REF4)

# ---------------------------------------------------------------- -summary outside D
DS, SUM = os.path.join(W, "DS"), os.path.join(W, "outside", "summary.json")
shutil.rmtree(DS, ignore_errors=True)
shutil.rmtree(os.path.dirname(SUM), ignore_errors=True)
good_run(DS, "A", summary=SUM)
st = "A"
for wait_for, moment in [("stage", rng.uniform(0, (STEPS - 1) * DELAY)) for _ in range(3)] + [("switch", 0.0)]:
    new = "B" if st == "A" else "A"
    rc, lines, when = interrupted(DS, new, 1, signal.SIGTERM, moment, summary=SUM, wait_for=wait_for)
    st = check_interrupted("-summary outside D, SIGTERM at %s" % when, DS, signal.SIGTERM, 1, rc, lines, st, new, REFS[1], summary=SUM)
    extra = [n for n in os.listdir(os.path.dirname(SUM)) if n != "summary.json"]
    report(not extra, "nothing but summary.json beside the outside summary", str(extra))

# ---------------------------------------------------------------- plain files of an earlier version
DP = os.path.join(W, "DP")
for k in range(4):
    shutil.rmtree(DP, ignore_errors=True)
    os.makedirs(DP)
    for n in PUB:
        shutil.copy(os.path.join(W, "ref_A_1_2", n), os.path.join(DP, n))  # regular files, set A
    sig = signal.SIGKILL if k < 3 else signal.SIGINT
    rc, lines, when = interrupted(DP, "B", 1, sig, rng.uniform(0, (STEPS - 1) * DELAY) if k < 3 else 0.0, wait_for="stage" if k < 3 else "switch")
    check_interrupted("plain files of set A, SIG%s at %s" % ("KILL" if k < 3 else "INT", when), DP, sig, 1, rc, lines, "A", "B", REFS[1])

# ---------------------------------------------------------------- Ctrl-C during the set-up
# hertz_4 on 2 ranks, SIGINT to mpiexec while the mesh is partitioned and the
# stiffness ordered: METIS (GKlib) trapped the SIGTERM mpiexec passes on and
# the run ended in "option -kkt_ordering metis: METIS_NodeND failed (-4)"
DM = os.path.join(W, "metis")
for moment in (0.3, 0.5, 0.7, 0.9, 1.2):
    shutil.rmtree(DM, ignore_errors=True)
    p = subprocess.Popen(command(args(DM, "A", level=4), 2), cwd=SRC, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=ENV)
    time.sleep(moment)
    p.send_signal(signal.SIGINT)
    perr = p.communicate(timeout=120)[1].decode()
    lines = [l for l in perr.splitlines() if l.strip()]
    report(p.returncode == 1 and len(lines) == 1 and MSG.match(lines[0]) is not None,
           "hertz_4, 2 ranks, SIGINT to mpiexec %.1f s after the start: exit 1 and the interrupt's one line" % moment, "exit %d, %r" % (p.returncode, lines[:3]))

# ---------------------------------------------------------------- a reader that goes away
# `mortar2d ... | head -1`: stdout closed before the first line (before:
# PETSc's "Caught signal 13 Broken Pipe", 6 lines, exit 59, no output)
DPIPE = os.path.join(W, "pipe")
shutil.rmtree(DPIPE, ignore_errors=True)
p = subprocess.Popen(command(args(DPIPE, "A"), 1), cwd=SRC, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV)
p.stdout.close()
perr = p.stderr.read().decode()
prc = p.wait(timeout=600)
report(prc == 0 and not perr.strip() and classify(content(DPIPE), REFS[1]) == "A" and not leftovers(DPIPE),
       "stdout closed by its reader: exit 0, no stderr, the complete set", "exit %d, stderr %r" % (prc, perr[-300:]))

# ---------------------------------------------------------------- up-front checks
afile = os.path.join(W, "afile")
with open(afile, "w") as f:
    f.write("a regular file\n")
adir = os.path.join(W, "adir")
os.makedirs(adir, exist_ok=True)
# files that are not regular: renaming the summary over them would replace the
# node itself (as root `-summary /dev/null` replaced /dev/null); a FIFO, a link
# to one, and a link to /dev/null stand in for a device (never /dev itself)
afifo = os.path.join(W, "afifo")
if not os.path.exists(afifo):
    os.mkfifo(afifo)
lfifo = os.path.join(W, "lfifo.json")
lnull = os.path.join(W, "lnull.h5")
for l, t in ((lfifo, afifo), (lnull, "/dev/null")):
    if not os.path.islink(l):
        os.symlink(t, l)


def snapshot(d):
    out = {}
    for n in sorted(os.listdir(d)):
        p = os.path.join(d, n)
        st = os.lstat(p)
        out[n] = (st.st_ino, st.st_mtime_ns, os.readlink(p) if os.path.islink(p) else open(p, "rb").read() if os.path.isfile(p) else None)
    return out


good_run(D, "A")
BEFORE = snapshot(D)
CASES = [
    ("-output_dir /proc", ["-output_dir", "/proc"], ["-output_dir", "/proc"]),
    ("-output_dir /proc/m2d_out (cannot be created)", ["-output_dir", "/proc/m2d_out"], ["-output_dir", "/proc/m2d_out"]),
    ("-output_dir /sys", ["-output_dir", "/sys"], ["-output_dir", "/sys"]),
    ("-output_dir through a regular file", ["-output_dir", os.path.join(afile, "sub")], ["-output_dir", "afile"]),
    ("-summary in /proc", ["-summary", "/proc/m2d.json"], ["-summary", "/proc"]),
    ("-summary an existing directory", ["-summary", adir], ["-summary", adir]),
    ("-summary through a regular file", ["-summary", os.path.join(afile, "s.json")], ["-summary", "afile"]),
    ("-summary a FIFO", ["-summary", afifo], ["-summary", "afifo", "FIFO"]),
    ("-summary a link to a FIFO", ["-summary", lfifo], ["-summary", "lfifo.json", "FIFO"]),
    ("-summary a link to /dev/null", ["-summary", lnull], ["-summary", "lnull.h5", "character device"]),
    ("-mesh_save a link to /dev/null", ["-mesh_save", lnull], ["-mesh_save", "lnull.h5", "character device"]),
    ("-summary names an output file", ["-summary", os.path.join(D, NAME + ".h5")], ["-summary", NAME + ".h5"]),
    ("-output_name with a double quote", ["-output_name", 'a"b'], ["-output_name", 'a"b']),
    ("-output_name with a single quote", ["-output_name", "a'b"], ["-output_name"]),
    ("-output_name with '<'", ["-output_name", "a<b"], ["-output_name", "a<b"]),
    ("-output_name with '&'", ["-output_name", "a&b"], ["-output_name", "a&b"]),
    ("-output_name with a space", ["-output_name", "a b"], ["-output_name"]),
    ("-output_name with ':' (XDMF file:path)", ["-output_name", "a:b"], ["-output_name"]),
    ("-output_name with a tab", ["-output_name", "a\tb"], ["-output_name"]),
    ("-output_name starting with '.'", ["-output_name", ".hidden"], ["-output_name"]),
    ("-output_name too long (300 characters)", ["-output_name", "x" * 300], ["-output_name", "longer than"]),
    ("-output_dir too long (5000 characters)", ["-output_dir", "d/" * 2500], ["-output_dir"]),
]
for what, extra, culprits in CASES:
    for ranks in ((1, 2) if what.startswith(("-output_dir /proc", "-output_name with a double", "-summary an existing")) else (1,)):
        a = args(D, "B") + extra
        p = subprocess.run(command(a, ranks), cwd=SRC, capture_output=True, text=True, env=ENV, timeout=120)
        line, problems = refusal_problems(p.returncode, [l for l in p.stderr.splitlines() if l.strip()], culprits)
        if snapshot(D) != BEFORE:
            problems.append("D changed")
        report(not problems, "%s [%d rank%s]" % (what, ranks, "s" if ranks > 1 else ""), ("; ".join(problems) + " -- stderr: " if problems else "") + line)
report(classify(content(D), REFS[1]) == "A" and neighbours() == NB, "after the refused runs D still holds set A and its neighbours")
report(os.path.islink(lnull) and os.readlink(lnull) == "/dev/null" and os.path.islink(lfifo) and stat.S_ISFIFO(os.lstat(afifo).st_mode)
       and stat.S_ISCHR(os.stat("/dev/null").st_mode), "the FIFO, the links and /dev/null are untouched")
T.finish()
