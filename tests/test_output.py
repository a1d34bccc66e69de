"""The files of a run (output.h, outputpaths.h, tempfile.h): plain files in
-output_dir, each written under a temporary name and renamed into place, the
summary last, every file carrying the run's id; interruptions; the checks
before any work; no output naming an input (issue 22 item 6); Ctrl-C during
MPI's start-up (item 7).

Scene: Hertz (options/hertz.opts) on hertz_2 with two loads, A (0.43) and B
(0.5), so that every file but the .xmf differs between the two sets. D holds
NAME.vtu/.h5/.xmf/_contact.csv and NAME_summary.json. The test hook
M2D_TEST_OUTPUT_DELAY (seconds; read only when set) makes the program sleep
between the steps of writing, closing and renaming, so that the moments of
an interruption spread over the whole output; the moment is drawn after the
run's first temporary appears in D.
  - a good run: only plain files in D (no hidden entries, no links), every
    file with the summary's run_id, the summary's "files" naming them;
  - SIGINT/SIGTERM at any moment (1 rank: to the program; 2 ranks: SIGINT to
    mpiexec as Ctrl-C does, or SIGTERM to every rank as a batch system does):
    exit 1, one line "interrupted by SIG...; no output written, previous
    results kept" (D holds the previous files, the same run ids) or "...; the
    output was already complete" (the new ones), no temporary left, no file
    half-written;
  - SIGKILL (no handler), also between two renames: every file is a complete
    file of one run, and a mix is told by the run ids (a file whose run_id
    differs from the summary's); the next run removes the temporaries.
Also: the byte-identical files of equal runs but for the id; a -summary
outside D; the links an earlier version left in D; -output (a run that
writes part of the set removes the rest of an earlier run's); the summary of a
failed run; a user's file and another -output_name's files
never touched; the up-front checks (one line naming the option, D untouched);
-summary/-mesh_save/the outputs naming a mesh, the .geo, an options file or
each other (one line naming both options, the input untouched), 1 and 2
ranks; outputs named through symbolic links written through to the file
they lead to (the links kept), links to anything else, into /proc
(/dev/stdout) or in a loop refused; -mesh_save under -adapt saves the final mesh; Ctrl-C to mpiexec from
0.05 s on and SIGTERM to a 1-rank run from 0.02 s on: the previous results
kept; Ctrl-C while METIS runs; stdout closed by its reader."""
import json
import os
import random
import re
import shutil
import signal
import stat
import subprocess
import time

import h5py
import numpy as np
from m2d import EXE, MPIEXEC, SRC, Tally, hooks, mesh, opts, read_h5, refusal_problems, workdir

os.environ["OMPI_MCA_orte_execute_quiet"] = "1"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
W = workdir("output")
NAME = "hertz"
PUB = [NAME + s for s in (".vtu", ".h5", ".xmf", "_contact.csv", "_summary.json")]
SUMMARY = NAME + "_summary.json"
DELAY = 0.1  # seconds per hook step
STEPS = 10   # hook steps from the first temporary to the end of a run
LOADS = {"A": "0.43", "B": "0.5"}
SIGS = {"INT": signal.SIGINT, "TERM": signal.SIGTERM, "KILL": signal.SIGKILL}
MSG = re.compile(r"^mortar2d: error: interrupted by SIG(INT|TERM|HUP); (no output written, previous results kept|the output was already complete)$")
RUNID = re.compile(rb"<!-- mortar2d run_id (\S+) -->")
rng = random.Random(20240613)
T = Tally()
report = T.check


def args(d, which, level=2, extra=()):
    return ["-options_file", opts("hertz"), "-mesh", mesh("hertz_%d" % level), "-pressure", "cylinder_top:" + LOADS[which],
            "-output_dir", d, "-output_name", NAME, "-contact_monitor", "0"] + list(extra)


def command(a, ranks):
    return [MPIEXEC, "--oversubscribe", "-n", str(ranks), EXE] + a if ranks > 1 else [EXE] + a


def run(a, ranks=1, env=None, timeout=600):
    p = subprocess.run(command(a, ranks), cwd=SRC, capture_output=True, text=True, env=env or ENV, timeout=timeout)
    return p.returncode, [l for l in p.stderr.splitlines() if l.strip()], p.stdout


def run_id(p):
    """the run id a file carries (None: no file, '?': none found)"""
    if not os.path.exists(p):
        return None
    try:
        if p.endswith(".h5"):
            with h5py.File(p, "r") as f:
                return f.attrs["run_id"].decode()
        if p.endswith(".json"):
            return json.load(open(p))["run_id"]
        if p.endswith(".csv"):
            ids = {l.rsplit(",", 1)[1].strip() for l in open(p).read().splitlines()[1:]}
            return ids.pop() if len(ids) == 1 else "?"
        m = RUNID.search(open(p, "rb").read(400))
        return m.group(1).decode() if m else "?"
    except Exception:
        return "?"


def read_file(p):
    """what a file says without its run id, for comparison: arrays (h5, csv),
    bytes (vtu, xmf), the summary without run id, time and round-off figures;
    None if missing, a string if incomplete or unreadable"""
    if not os.path.exists(p):
        return None
    b = open(p, "rb").read()
    rid = run_id(p)
    try:
        if p.endswith(".h5"):
            xy, cells, vf, cf = read_h5(p)
            return [np.nan_to_num(v) for v in [xy, cells] + [vf[k] for k in sorted(vf)] + [cf[k] for k in sorted(cf)]]
        if p.endswith(".csv"):
            return [np.array([[float(x) for x in l.split(",")[:-1]] for l in b.decode().splitlines()[1:]])]
        if p.endswith(".json"):
            j = json.loads(b)
            for k in ("run_id", "time", "residual_rel", "backward_error", "complementarity", "memory_max_rank_mb"):
                j.pop(k, None)
            return j
        if p.endswith(".vtu"):
            assert b.endswith(b"</VTKFile>\n"), "no </VTKFile> at the end"
            k = b.index(b'<AppendedData encoding="raw">')
            k = b.index(b"_", k) + 1
            nb = int(np.frombuffer(b[k:k + 8], np.uint64)[0])
            return [len(b), np.frombuffer(b[k + 8:k + 8 + nb], np.float64)]
        return b.replace(rid.encode(), b"ID")
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
        return a.shape == b.shape and np.allclose(a, b, rtol=0, atol=1e-8 * max(np.abs(b).max(), 1e-300) if b.size else 0)
    if isinstance(a, float):
        return abs(a - b) <= 1e-8 * max(abs(b), 1e-300)
    return a == b


def state(d):
    """{name: (the labels of the sets in REFS it equals, run id)} of D's files
    (the .xmf is the same in A and B, the CSV on 1 and 2 ranks)"""
    out = {}
    for n in PUB:
        got = read_file(os.path.join(d, n))
        out[n] = (frozenset(k for k in REFS if got is not None and same(got, REFS[k][n])), run_id(os.path.join(d, n)))
    return out


def of(st, lab):
    """every file of state st is one of set lab's"""
    return all(lab in v[0] for v in st.values())


def label(st):
    """the set ('A' or 'B') the summary of state st belongs to"""
    return sorted(st[SUMMARY][0])[0][0]


def hidden(d, keep=()):
    """entries of d besides the run's files and `keep`: temporaries, links, anything"""
    return sorted(n for n in os.listdir(d) if n not in PUB and n not in keep)


def plain(d):
    return all(stat.S_ISREG(os.lstat(os.path.join(d, n)).st_mode) for n in os.listdir(d))


def reference(which, ranks):
    d = os.path.join(W, "ref_%s_%d" % (which, ranks))
    shutil.rmtree(d, ignore_errors=True)
    rc, err, _ = run(args(d, which), ranks)
    assert rc == 0, "reference run %s failed: %s" % (d, err)
    return d


# ---------------------------------------------------------------- references, run ids
REFD = {(k, r): reference(k, r) for k in LOADS for r in (1, 2)}
REFS = {k + str(r): {n: read_file(os.path.join(REFD[k, r], n)) for n in PUB} for (k, r) in REFD}  # vertex orders differ with the ranks
for (k, r), d in REFD.items():
    ids = {n: run_id(os.path.join(d, n)) for n in PUB}
    s = json.load(open(os.path.join(d, SUMMARY)))
    report(len(set(ids.values())) == 1 and None not in ids.values() and "?" not in ids.values(), "set %s, %d rank(s): the five files carry one run id (%s)" % (k, r, s["run_id"]), str(ids))
    report(s["status"] == "ok" and s["files"] == {"csv": NAME + "_contact.csv", "vtu": NAME + ".vtu", "h5": NAME + ".h5", "xmf": NAME + ".xmf"},
           "set %s, %d rank(s): summary status ok, files named" % (k, r), str(s.get("files")))
    report(plain(d) and sorted(os.listdir(d)) == sorted(PUB), "set %s, %d rank(s): D holds the five plain files and nothing else" % (k, r), str(os.listdir(d)))
report(len({run_id(os.path.join(d, SUMMARY)) for d in REFD.values()}) == 4, "four runs, four run ids")
for r in (1, 2):
    diff = [n for n in PUB if not same(REFS["A%d" % r][n], REFS["B%d" % r][n])]
    report(diff == [n for n in PUB if not n.endswith(".xmf")], "%d rank(s): sets A and B differ in every file but the .xmf" % r, "differ: %s" % diff)
# the writers add nothing that changes from run to run but the run id: the
# same command (the same arguments: on AVX-512 machines OpenBLAS rounds the
# last bits of MUMPS' factors with the alignment of its work arrays, which
# shifts with the length of the arguments and the environment) run again
again = os.path.join(W, "again")
shutil.rmtree(again, ignore_errors=True)
shutil.copytree(REFD["A", 1], again)
run(args(REFD["A", 1], "A"))
bad = []
for n in PUB[:4]:
    a, b = (open(os.path.join(x, n), "rb").read() for x in (again, REFD["A", 1]))
    if a.replace(run_id(os.path.join(again, n)).encode(), b"ID") != b.replace(run_id(os.path.join(REFD["A", 1], n)).encode(), b"ID"):
        bad.append(n)
report(not bad, "the same command run twice on 1 rank gives byte-identical .vtu, .h5, .xmf, .csv but for the run id", "differ: %s" % bad)

# the fields ParaView shows: active on the non-mortar surface, the pressure on both sides, nodal stresses
xy, cells, vf, cf = read_h5(os.path.join(REFD["A", 1], NAME + ".h5"))
vb = np.full(len(xy), -1)
for c, b in zip(cells, cf["body"]):
    vb[c] = int(b)
act, pres = vf["active"], vf["contact_pressure"]
on = ~np.isnan(act)
report(set(np.unique(act[on])) == {0.0, 1.0} and len(set(vb[on])) == 1 and on.sum() > 20, "point field active: 0/1 on one body's surface (%d nodes, %d active), NaN elsewhere" % (on.sum(), (act == 1).sum()))
other = [b for b in np.unique(vb) if b != vb[on][0]][0]
ymax = {b: pres[vb == b].max() for b in (vb[on][0], other)}
report(min(ymax.values()) > 0.9 * max(ymax.values()), "contact_pressure on the mortar body too: peaks %.4f (non-mortar), %.4f (mortar)" % tuple(ymax.values()))
nodal = [k for k in vf if k.endswith("_nodal")]
report(sorted(nodal) == ["sigma_x_nodal", "sigma_xy_nodal", "sigma_y_nodal", "sigma_z_nodal", "von_mises_nodal"] and abs(vf["sigma_y_nodal"].min() / cf["sigma_y"].min() - 1) < 0.1,
       "recovered nodal stresses: %s, min sigma_y %.3f (cells %.3f)" % (nodal, vf["sigma_y_nodal"].min(), cf["sigma_y"].min()))

# ---------------------------------------------------------------- three runs into one directory, with neighbours
D = os.path.join(W, "D")
shutil.rmtree(D, ignore_errors=True)
os.makedirs(D)
with open(os.path.join(D, "notes.txt"), "w") as f:
    f.write("a user's file\n")
rc, err, _ = run(["-options_file", opts("hertz"), "-mesh", mesh("hertz_0"), "-output_dir", D, "-output_name", "other", "-output_vtu", "0"])
assert rc == 0, err
KEEP = sorted(n for n in os.listdir(D))  # notes.txt and other.*


def neighbours():
    return {n: (open(os.path.join(D, n), "rb").read(), os.stat(os.path.join(D, n)).st_ino, os.stat(os.path.join(D, n)).st_mtime_ns) for n in KEEP}


NB = neighbours()
for which in ("A", "B", "A"):
    rc, err, _ = run(args(D, which))
    assert rc == 0, err
st = state(D)
with h5py.File(os.path.join(D, NAME + ".h5"), "r") as f:
    has_active = "active" in f["vertex_fields"]
s = json.load(open(os.path.join(D, SUMMARY)))
report(plain(D) and not hidden(D, KEEP) and os.path.exists(os.path.join(D, NAME + "_contact.csv")) and has_active and s["status"] == "ok"
       and of(st, "A1") and all(v[1] == s["run_id"] for v in st.values()),
       "after three runs into one directory: only plain files (%s), the contact CSV among them, an 'active' point field in the .h5, status in the summary" % ", ".join(sorted(os.listdir(D))))


# ---------------------------------------------------------------- interrupted runs
def tmps(d):
    return [n for n in os.listdir(d) if n.startswith(".m2d.tmp.")] if os.path.isdir(d) else []


def interrupted(d, which, ranks, sig, moment, level=2, delay=DELAY, wait_for="tmp", extra=()):
    """start a run, interrupt it `moment` s after its first temporary appears in d
    (wait_for 'start': after the first line of stdout, the solve next; 'launch':
    after the start of the command); return (rc, stderr lines, when)"""
    env = dict(ENV)
    if delay:
        env["M2D_TEST_OUTPUT_DELAY"] = str(delay)
    p = subprocess.Popen(command(args(d, which, level, extra), ranks), cwd=SRC, stdout=subprocess.PIPE if wait_for == "start" else subprocess.DEVNULL,
                         stderr=subprocess.PIPE, text=True, env=env)
    t0 = time.time()
    if wait_for == "start":
        p.stdout.readline()
    while wait_for == "tmp" and p.poll() is None and not tmps(d) and time.time() - t0 < 300:
        time.sleep(0.002)
    if p.poll() is not None:
        return p.returncode, [l for l in p.communicate()[1].splitlines() if l.strip()], "finished before the signal"
    time.sleep(moment)
    if ranks > 1 and sig == signal.SIGKILL:  # rank 0, which owns the temporaries .m2d.tmp.<host>.<pid>.NAME
        with open("/proc/%d/task/%d/children" % (p.pid, p.pid)) as f:
            ranks_pids = [int(x) for x in f.read().split()]
        os.kill(next((int(t.split(".")[4]) for t in tmps(d)), min(ranks_pids)), sig)
    elif ranks > 1 and sig == signal.SIGTERM:  # as a batch system does: every rank
        with open("/proc/%d/task/%d/children" % (p.pid, p.pid)) as f:
            for pid in f.read().split():
                os.kill(int(pid), sig)
    else:
        p.send_signal(sig)  # 1 rank: the program; 2 ranks: mpiexec, which sends SIGCONT, then SIGTERM 1 s later
    try:
        err = p.communicate(timeout=120)[1]
    except subprocess.TimeoutExpired:
        p.kill()
        return None, ["no exit within 120 s after the signal"], ""
    time.sleep(0.2)  # mpiexec may exit before its ranks
    return p.returncode, [l for l in err.splitlines() if l.strip()], "%s + %.3f s" % (wait_for, moment)


def check_interrupted(what, d, sig, ranks, rc, lines, prev, new, keep=()):
    """the assertions after one interrupted run; prev: the state before; new:
    the label of the interrupted run's set; returns the state now"""
    now = state(d)
    problems = []
    olds = {n for n in PUB if now[n] == prev[n]}
    news = {n for n in PUB if now[n] != prev[n]}
    if any(new not in now[n][0] for n in news):
        problems.append("a changed file not of the new set (half-written or missing): %s" % {n: sorted(now[n][0]) for n in news})
    if news and len({now[n][1] for n in news}) != 1:
        problems.append("the new files do not share one run id: %s" % {n: now[n][1] for n in news})
    if news and any(now[n][1] == prev[m][1] for n in news for m in PUB):
        problems.append("a new file carries an earlier run id")
    if news and olds and any(now[n][1] == now[SUMMARY][1] for n in (olds if SUMMARY in news else news)):
        problems.append("a mix the run ids do not tell")
    if rc == 0:
        what += " (the run had finished)"
        if olds or lines:
            problems.append("exit 0 but old files %s, stderr %r" % (sorted(olds), lines[:3]))
    elif sig == signal.SIGKILL:
        if rc in (None, 1) or (news and SUMMARY in news and olds):
            problems.append("exit code %s after SIGKILL, or the summary new before the other files" % rc)
    else:
        if rc != 1:
            problems.append("exit code %s (want 1)" % rc)
        if len(lines) != 1 or not MSG.match(lines[0]):
            problems.append("stderr is not one interruption line: %r" % lines[:4])
        else:
            m = MSG.match(lines[0])
            if ranks == 1 and m.group(1) != {signal.SIGINT: "INT", signal.SIGTERM: "TERM"}[sig]:
                problems.append("the line names SIG%s" % m.group(1))
            if (news if m.group(2).startswith("no output") else olds):
                problems.append("the line says '%s' but %s" % (m.group(2), "files changed" if news else "old files remain"))
        if tmps(d) or hidden(d, keep):
            problems.append("left in D: %s" % hidden(d, keep))
    mix = " (a mix: %d of 5 files new, told by their run ids)" % len(news) if news and olds else ""
    report(not problems, what, "; ".join(problems) if problems else "D holds the %s files%s" % ("previous" if not news else "new" if not olds else "mixed", mix))
    return now


counts = {}
for ranks in ((1, 2) if hooks("signals at chosen moments of the output (M2D_TEST_OUTPUT_DELAY)") else ()):
    for sname in ("INT", "KILL", "TERM"):
        sig = SIGS[sname]
        moments = [(i + rng.random()) / 3 * STEPS * DELAY for i in range(3)]
        rng.shuffle(moments)
        for moment in moments:
            prev = state(D)
            new = "B" if label(prev) == "A" else "A"
            rc, lines, when = interrupted(D, new, ranks, sig, moment)
            now = check_interrupted("%d rank(s), SIG%s at %s" % (ranks, sname, when), D, sig, ranks, rc, lines, prev, new + str(ranks), KEEP)
            key = (ranks, sname, "previous" if now == prev else "new" if all(now[n][1] == now[SUMMARY][1] for n in PUB) else "mix")
            counts[key] = counts.get(key, 0) + 1
            if sig == signal.SIGKILL:  # the next good run removes what it left
                rc, err, _ = run(args(D, new), ranks)
                report(rc == 0 and not hidden(D, KEEP), "%d rank(s): the run after a SIGKILL leaves nothing behind" % ranks, "left %s" % hidden(D, KEEP))
print("outcomes (ranks, signal, files in D): count: %s" % sorted(counts.items()))

# before the output: during the solve
for ranks in (1, 2):
    prev = state(D)
    rc, lines, when = interrupted(D, "B" if label(prev) == "A" else "A", ranks, signal.SIGINT, 0.02, wait_for="start")
    ok = rc == 1 and len(lines) == 1 and MSG.match(lines[0]) and "no output written" in lines[0]
    report(ok and state(D) == prev and not hidden(D, KEEP), "%d rank(s), SIGINT during the solve: one line, exit 1, the previous files kept" % ranks,
           "rc %s, stderr %r, extra %s" % (rc, lines[:3], hidden(D, KEEP)))
report(neighbours() == NB, "the user's file and the other -output_name's files are untouched (bytes, inode, mtime)")

# hertz_4 without the hook: kills at random moments of its output
D4 = os.path.join(W, "D4")
shutil.rmtree(D4, ignore_errors=True)
REFS.update({k + "4": {n: read_file(os.path.join(W, "ref4_" + k, n)) for n in PUB} for k in LOADS if run(args(os.path.join(W, "ref4_" + k), k, 4))[0] == 0})
t0 = time.time()
p4 = subprocess.Popen(command(args(D4, "A", 4), 1), cwd=SRC, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=ENV)
while p4.poll() is None and not tmps(D4):
    time.sleep(0.002)
t1 = time.time()
p4.wait()
window = time.time() - t1
print("hertz_4: %.2f s from the start to the first temporary, %.2f s from there to the exit" % (t1 - t0, window))
for sname in ("KILL", "INT", "KILL", "TERM", "INT"):
    prev = state(D4)
    new = "B" if label(prev) == "A" else "A"
    rc, lines, when = interrupted(D4, new, 1, SIGS[sname], rng.uniform(0, 0.9 * window), level=4, delay=0)
    check_interrupted("hertz_4, no hook, SIG%s at %s" % (sname, when), D4, SIGS[sname], 1, rc, lines, prev, new + "4")
    if sname == "KILL":
        run(args(D4, new, 4))


# a -summary outside D: renamed last as well, with the other files' run id
DS, OUTS = os.path.join(W, "DS"), os.path.join(W, "outside")
for x in (DS, OUTS):
    shutil.rmtree(x, ignore_errors=True)
SUMO = os.path.join(OUTS, "summary.json")
run(args(DS, "A", 2, ["-summary", SUMO]))
for moment in [rng.uniform(0, STEPS * DELAY) for _ in range(4 if hooks("-summary outside D at chosen moments (M2D_TEST_OUTPUT_DELAY)") else 0)]:
    before = {n: run_id(os.path.join(DS, n)) for n in PUB[:4]}
    rc, lines, when = interrupted(DS, "B", 1, signal.SIGTERM, moment, extra=["-summary", SUMO])
    ids = {n: run_id(os.path.join(DS, n)) for n in PUB[:4]}
    ok = rc == 1 and len(lines) == 1 and MSG.match(lines[0]) and len(set(ids.values())) == 1 and run_id(SUMO) == ids[NAME + ".h5"]
    ok = ok and (ids == before) == ("no output" in lines[0]) and os.listdir(OUTS) == ["summary.json"] and not hidden(DS)
    report(ok, "-summary outside D, SIGTERM at %s: the summary's run id is the files' (%s)" % (when, "previous" if ids == before else "new"), "rc %s %r %s %s" % (rc, lines[:2], ids, run_id(SUMO)))

# a directory the earlier versions wrote (N.h5 and the others symbolic links
# into a hidden .m2d.gen directory): the names become plain files of this run
DL = os.path.join(W, "links")
shutil.rmtree(DL, ignore_errors=True)
os.makedirs(os.path.join(DL, ".m2d.gen.x.0." + NAME))
for n in PUB:
    shutil.copy(os.path.join(REFD["A", 1], n), os.path.join(DL, ".m2d.gen.x.0." + NAME, n))
os.symlink(".m2d.gen.x.0." + NAME, os.path.join(DL, ".m2d.set." + NAME))
for n in PUB:
    os.symlink(os.path.join(".m2d.set." + NAME, n), os.path.join(DL, n))
rc, err, _ = run(args(DL, "B"))
st = state(DL)
report(rc == 0 and all(stat.S_ISREG(os.lstat(os.path.join(DL, n)).st_mode) for n in PUB) and of(st, "B1") and len({v[1] for v in st.values()}) == 1
       and of({n: (frozenset(k for k in REFS if same(read_file(os.path.join(DL, ".m2d.gen.x.0." + NAME, n)), REFS[k][n])), 0) for n in PUB}, "A1"),
       "links of an earlier version: the names become plain files of the new run, what they pointed to is not touched")


# ---------------------------------------------------------------- Ctrl-C during MPI's start-up (issue 22 item 7)
# mpiexec answers a SIGINT with SIGCONT to the ranks and SIGTERM 1 s later; a
# short run used to finish in between, replace the results and then say
# "interrupted by SIGTERM; the output was already complete"
def untouched(d, before):
    return {n: (open(os.path.join(d, n), "rb").read() if os.path.isfile(os.path.join(d, n)) else None) for n in os.listdir(d)} == before


def snapshot_files(d):
    return {n: open(os.path.join(d, n), "rb").read() for n in os.listdir(d)}


DE = os.path.join(W, "early")
shutil.rmtree(DE, ignore_errors=True)
run(args(DE, "A", 1))
BEFORE_E = snapshot_files(DE)
# before main (the dynamic loader: ~0.08 s) a signal kills the process (status
# -15, no line; 2 ranks: mpiexec ends before the ranks exist, exit 1): nothing
# is written either way; once the handler is in place (or the ranks exist),
# one line
def catching(pid):
    """the process has installed its SIGTERM handler (SigCgt in /proc)"""
    try:
        with open("/proc/%d/status" % pid) as f:
            return bool(int(re.search(r"SigCgt:\s*([0-9a-f]+)", f.read()).group(1), 16) & (1 << (signal.SIGTERM - 1)))
    except (OSError, AttributeError):
        return False


for ranks, sig, level, moments in ((2, signal.SIGINT, 1, (0.05, 0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0)), (1, signal.SIGTERM, 3, (0.02, 0.05, 0.1, 0.15, 0.2, 0.3))):
    for moment in moments:
        BEFORE_E = snapshot_files(DE)
        p = subprocess.Popen(command(args(DE, "B", level), ranks), cwd=SRC, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=ENV)
        time.sleep(moment)
        if ranks > 1:  # mpiexec's SIGTERM comes 1 s later: the ranks that exist now will catch it
            with open("/proc/%d/task/%d/children" % (p.pid, p.pid)) as f:
                started = bool(f.read().split())
        else:
            started = catching(p.pid)
        p.send_signal(sig)
        err = p.communicate(timeout=120)[1]
        time.sleep(0.2)
        lines = [l for l in err.splitlines() if l.strip()]
        problems = []
        if p.returncode == 0 or not untouched(DE, BEFORE_E):
            problems.append("exit %d, D changed: %s" % (p.returncode, state(DE)))
        if lines and (len(lines) != 1 or not MSG.match(lines[0]) or "no output written" not in lines[0]):
            problems.append("stderr %r" % lines[:3])
        if not lines and (started or p.returncode != (1 if ranks > 1 else -15)):
            problems.append("no line (exit %d)" % p.returncode)  # only before the program could catch a signal
        report(not problems, "%d rank(s), SIG%s %.2f s after the start: exit %d, %s, the previous results kept" % (ranks, "INT to mpiexec" if ranks > 1 else "TERM", moment, p.returncode, "one line" if lines else "no line (the program had not started)"),
               "; ".join(problems))

# Ctrl-C during the set-up: hertz_4 on 2 ranks, SIGINT to mpiexec while the
# mesh is partitioned and the stiffness ordered (METIS traps the SIGTERM)
DM = os.path.join(W, "metis")
for moment in (0.3, 0.5, 0.7, 0.9, 1.2):
    shutil.rmtree(DM, ignore_errors=True)
    p = subprocess.Popen(command(args(DM, "A", level=4), 2), cwd=SRC, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=ENV)
    time.sleep(moment)
    p.send_signal(signal.SIGINT)
    lines = [l for l in p.communicate(timeout=120)[1].decode().splitlines() if l.strip()]
    report(p.returncode == 1 and len(lines) == 1 and MSG.match(lines[0]) is not None and not (os.path.isdir(DM) and os.listdir(DM)),
           "hertz_4, 2 ranks, SIGINT to mpiexec %.1f s after the start: exit 1, the interrupt's one line, nothing written" % moment, "exit %d, %r" % (p.returncode, lines[:3]))

# a reader that goes away: `mortar2d ... | head -1`
DPIPE = os.path.join(W, "pipe")
shutil.rmtree(DPIPE, ignore_errors=True)
p = subprocess.Popen(command(args(DPIPE, "A"), 1), cwd=SRC, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV)
p.stdout.close()
perr = p.stderr.read().decode()
prc = p.wait(timeout=600)
report(prc == 0 and not perr.strip() and of(state(DPIPE), "A1") and not hidden(DPIPE),
       "stdout closed by its reader: exit 0, no stderr, the complete files", "exit %d, stderr %r" % (prc, perr[-300:]))

# ---------------------------------------------------------------- -output
for extra, want in ((["-output_vtu", "0", "-output_hdf5", "0"], [NAME + "_contact.csv", SUMMARY]),
                    (["-output", "csv"], [NAME + "_contact.csv"]),
                    (["-output", "h5,summary"], [NAME + ".h5", NAME + ".xmf", SUMMARY]),
                    (["-output", "vtu"], [NAME + ".vtu"]),
                    (["-output", "none"], [])):
    d = os.path.join(W, "choice")
    shutil.rmtree(d, ignore_errors=True)
    rc, err, _ = run(args(d, "A", 1, extra))
    got = sorted(os.listdir(d)) if os.path.isdir(d) else []
    report(rc == 0 and got == sorted(want), "%s: %s" % (" ".join(extra), ", ".join(got) or "nothing"), "exit %d %s" % (rc, err[:2]))
for extra, culprits in ((["-output", "h5,foo"], ["-output", "foo"]), (["-output", "none,csv"], ["-output", "none"]),
                        (["-output", "csv", "-summary", os.path.join(W, "s.json")], ["-summary", "-output"])):
    rc, err, _ = run(args(os.path.join(W, "choice"), "A", 1, extra))
    line, problems = refusal_problems(rc, err, culprits)
    report(not problems, " ".join(extra) + ": refused", ("; ".join(problems) + " -- " if problems else "") + line)

# a run that writes part of the set removes the rest of an earlier run's set
# (issue 33 item 11; before: -output csv after a full run left the summary,
# .h5, .xmf and .vtu of the earlier run beside the new CSV, nothing said);
# only files of mortar2d (by name and the run id inside), never a user's file,
# a link or another -output_name's files
for ranks in (1, 2):
    d = os.path.join(W, "partial")
    shutil.rmtree(d, ignore_errors=True)
    run(args(d, "A", 1), ranks)
    with open(os.path.join(d, NAME + "_notes.txt"), "w") as f:
        f.write("a user's file\n")
    rc, err, out = run(args(d, "B", 1, ["-output", "csv"]), ranks)
    said = [l for l in out.splitlines() if l.startswith("output: removed ")]
    report(rc == 0 and sorted(os.listdir(d)) == sorted([NAME + "_contact.csv", NAME + "_notes.txt"]) and len(said) == 1 and all(n in said[0] for n in PUB if n != NAME + "_contact.csv"),
           "%d rank(s): -output csv after a full run: the earlier run's .vtu, .h5, .xmf and summary removed, said in one line, the user's file kept" % ranks, "%s %s %s" % (sorted(os.listdir(d)), said, err[:1]))
d = os.path.join(W, "partial")
run(args(d, "A", 1))
with open(os.path.join(d, NAME + ".vtu"), "w") as f:
    f.write("<?xml version=\"1.0\"?>\n<VTKFile>a user's own, no run id</VTKFile>\n")
os.remove(os.path.join(d, NAME + ".xmf"))
os.symlink(NAME + "_notes.txt", os.path.join(d, NAME + ".xmf"))
rc, err, out = run(args(d, "B", 1, ["-output", "summary"]))
report(rc == 0 and sorted(os.listdir(d)) == sorted([NAME + ".vtu", NAME + ".xmf", NAME + "_notes.txt", SUMMARY]) and os.path.islink(os.path.join(d, NAME + ".xmf")),
       "-output summary: the earlier run's .h5 and CSV removed; a .vtu without a run id (a user's) and a link kept", str(sorted(os.listdir(d))))
shutil.rmtree(d)
run(args(d, "A", 1))
rc, err, out = run(["-options_file", opts("block"), "-output_dir", d, "-output_name", NAME])
report(rc == 0 and sorted(os.listdir(d)) == sorted(PUB[:3] + [SUMMARY]) and run_id(os.path.join(d, NAME + ".h5")) == run_id(os.path.join(d, SUMMARY)),
       "a scene without contact after one with it, the same -output_name: the earlier contact CSV removed", str(sorted(os.listdir(d))))

# ---------------------------------------------------------------- the summary of a failed run
for ranks in (1, 2):
    d = os.path.join(W, "failed%d" % ranks)
    shutil.rmtree(d, ignore_errors=True)
    run(args(d, "A"), ranks)
    before = {n: open(os.path.join(d, n), "rb").read() for n in PUB[:4]}
    rc, err, _ = run(args(d, "A", 1, ["-pressure", "cylinder_top:-0.43", "-hertz", "0"]), ranks)
    s = json.load(open(os.path.join(d, SUMMARY)))
    report(rc == 1 and len(err) == 1 and s["status"] == "error" and "mortar2d: error: " + s["error"] == err[0] and s["run_id"] != run_id(os.path.join(d, NAME + ".h5"))
           and before == {n: open(os.path.join(d, n), "rb").read() for n in PUB[:4]} and not hidden(d),
           "%d rank(s), a run that fails after the checks: its summary says status error and the line; the other files kept (their run id differs)" % ranks, "%s %s" % (err, s))

# ---------------------------------------------------------------- up-front checks
afile = os.path.join(W, "afile")
with open(afile, "w") as f:
    f.write("a regular file\n")
adir = os.path.join(W, "adir")
os.makedirs(adir, exist_ok=True)
# files that are not regular: renaming over them would replace the node itself
# (as root `-summary /dev/null` replaced /dev/null); a FIFO, a link to one, and
# a link to /dev/null stand in for a device (never /dev itself)
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


# inputs that an output must not replace: copies, named in several spellings
IN = os.path.join(W, "inputs")
shutil.rmtree(IN, ignore_errors=True)
os.makedirs(os.path.join(IN, "sub"))
shutil.copy(mesh("hertz_0"), os.path.join(IN, "m.msh"))
shutil.copy(opts("hertz"), os.path.join(IN, "h.opts"))
with open(os.path.join(IN, "outer.opts"), "w") as f:
    f.write("-options_file %s\n" % os.path.join(IN, "h.opts"))
os.link(os.path.join(IN, "m.msh"), os.path.join(IN, "hard.json"))
os.symlink(IN, os.path.join(IN, "again"))
run(["-options_file", opts("hertz"), "-mesh", mesh("hertz_0"), "-output_dir", IN, "-output", "none", "-mesh_save", os.path.join(IN, "m.h5")])
shutil.copy(os.path.join(SRC, "meshes", "hertz.geo"), os.path.join(IN, "hertz.geo"))
IN_BEFORE = snapshot(IN)

rc, err, _ = run(args(D, "A"))
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
    ("-mesh_save in a missing directory", ["-mesh_save", os.path.join(W, "nosuch", "m.h5")], ["-mesh_save", "nosuch"]),
    ("-summary names an output file", ["-summary", os.path.join(D, NAME + ".h5")], ["-summary", "-output_dir/-output_name", NAME + ".h5"]),
    ("-mesh_save at the result's own .h5", ["-mesh_save", os.path.join(D, NAME + ".h5")], ["-mesh_save", "-output_dir/-output_name", NAME + ".h5"]),
    ("-mesh_save and -summary one file", ["-mesh_save", os.path.join(W, "x.h5"), "-summary", os.path.join(W, "x.h5")], ["-mesh_save", "-summary"]),
    ("-summary names the mesh", ["-mesh", os.path.join(IN, "m.msh"), "-summary", os.path.join(IN, "m.msh")], ["-summary", "-mesh", "m.msh"]),
    ("-summary names the mesh through ../ and a link", ["-mesh", os.path.join(IN, "m.msh"), "-summary", os.path.join(IN, "sub", "..", "again", "m.msh")], ["-summary", "-mesh"]),
    ("-summary a hard link of the mesh", ["-mesh", os.path.join(IN, "m.msh"), "-summary", os.path.join(IN, "hard.json")], ["-summary", "-mesh", "hard.json"]),
    ("-summary names the options file", ["-options_file", os.path.join(IN, "h.opts"), "-summary", os.path.join(IN, "h.opts")], ["-summary", "-options_file", "h.opts"]),
    ("-summary names an options file read by another", ["-options_file", os.path.join(IN, "outer.opts"), "-summary", os.path.join(IN, "again", "h.opts")], ["-summary", "-options_file"]),
    ("-mesh_save names the mesh", ["-mesh", os.path.join(IN, "m.h5"), "-mesh_save", os.path.join(IN, "m.h5")], ["-mesh_save", "-mesh", "m.h5"]),
    ("the output .h5 is the mesh", ["-mesh", os.path.join(IN, "m.h5"), "-output_dir", IN, "-output_name", "m"], ["-output_dir/-output_name", "-mesh", "m.h5"]),
    ("-summary names the .geo (-adapt)", ["-options_file", opts("hertz_adapt"), "-geo", os.path.join(IN, "hertz.geo"), "-output_dir", D, "-output_name", NAME, "-summary", os.path.join(IN, "hertz.geo")], ["-summary", "-geo", "hertz.geo"]),
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
TWO = ("-output_dir /proc", "-output_name with a double", "-summary an existing", "-summary names the", "-summary a hard", "-mesh_save", "the output .h5")
for what, extra, culprits in CASES:
    for ranks in ((1, 2) if what.startswith(TWO) else (1,)):
        rc, lines, _ = run(args(D, "B", 2, extra), ranks, timeout=120)
        line, problems = refusal_problems(rc, lines, culprits)
        if snapshot(D) != BEFORE:
            problems.append("D changed")
        if snapshot(IN) != IN_BEFORE:
            problems.append("an input changed")
        report(not problems, "%s [%d rank%s]" % (what, ranks, "s" if ranks > 1 else ""), ("; ".join(problems) + " -- stderr: " if problems else "") + line)
report(of(state(D), "A1") and neighbours() == NB, "after the refused runs D still holds set A and its neighbours")
report(os.path.islink(lnull) and os.readlink(lnull) == "/dev/null" and os.path.islink(lfifo) and stat.S_ISFIFO(os.lstat(afifo).st_mode)
       and stat.S_ISCHR(os.stat("/dev/null").st_mode), "the FIFO, the links and /dev/null are untouched")

# ---------------------------------------------------------------- outputs named through links (issue 33 item 9)
# a link to a regular file (or to none yet) is written through: the file it
# leads to gets the output, the link stays (before: the link was replaced by a
# regular file and its target kept its old content); a link to anything else,
# or into /proc (a process's file descriptor: /dev/stdout), is refused
LK = os.path.join(W, "through")


def link_state(d):
    return {n: (os.readlink(os.path.join(d, n)) if os.path.islink(os.path.join(d, n)) else None) for n in os.listdir(d)}


fd_refused = True
for ranks in (1, 2):
    shutil.rmtree(LK, ignore_errors=True)
    os.makedirs(os.path.join(LK, "real"))
    os.makedirs(os.path.join(LK, "adir"))
    with open(os.path.join(LK, "real", "t.json"), "w") as f:
        f.write("old\n")
    shutil.copy(mesh("hertz_0"), os.path.join(LK, "real", "m.h5"))  # any regular file
    with open(os.path.join(LK, "real", "v.vtu"), "w") as f:
        f.write("old\n")
    for name, target in (("s.json", "real/t.json"), ("chain.json", "s.json"), ("new.json", "real/n.json"), ("m.h5", "real/m.h5"),
                         ("dir.json", "adir"), ("fd.json", "/proc/self/fd/1"), ("loop.json", "loop.json")):
        os.symlink(target, os.path.join(LK, name))
    os.makedirs(os.path.join(LK, "D"))
    os.symlink(os.path.join("..", "real", "v.vtu"), os.path.join(LK, "D", NAME + ".vtu"))
    links = link_state(LK)
    for what, extra, target in (("-summary a link to a file", ["-summary", os.path.join(LK, "s.json")], os.path.join(LK, "real", "t.json")),
                                ("-summary a link to a link to a file", ["-summary", os.path.join(LK, "chain.json")], os.path.join(LK, "real", "t.json")),
                                ("-summary a link to no file yet", ["-summary", os.path.join(LK, "new.json")], os.path.join(LK, "real", "n.json"))):
        rc, err, _ = run(args(os.path.join(LK, "D"), "A", 0, extra), ranks)
        ok = rc == 0 and link_state(LK) == links and os.path.isfile(target) and json.load(open(target))["status"] == "ok"
        ok = ok and not [n for n in os.listdir(os.path.join(LK, "real")) if n.startswith(".m2d")]
        report(ok, "%s, %d rank(s): written through, the link kept" % (what, ranks), "exit %d %s" % (rc, err[:1]))
    rc, err, _ = run(args(os.path.join(LK, "D"), "A", 0, ["-output", "h5", "-mesh_save", os.path.join(LK, "m.h5")]), ranks)
    ok = rc == 0 and link_state(LK) == links and h5py.is_hdf5(os.path.join(LK, "real", "m.h5"))
    report(ok, "-mesh_save a link to a file, %d rank(s): the mesh written through, the link kept" % ranks, "exit %d %s" % (rc, err[:1]))
    rc, err, _ = run(args(os.path.join(LK, "D"), "A", 0, ["-output", "vtu"]), ranks)
    ok = rc == 0 and os.path.islink(os.path.join(LK, "D", NAME + ".vtu")) and run_id(os.path.join(LK, "real", "v.vtu")) not in (None, "?")
    report(ok, "-output_dir's N.vtu a link to a file elsewhere, %d rank(s): written through, the link kept" % ranks, "exit %d %s" % (rc, err[:1]))
    for what, name, culprits in (("a link to a directory", "dir.json", ["-summary", "dir.json", "a directory"]),
                                 ("a link to a process's file descriptor, stdout a file", "fd.json", ["-summary", "fd.json", "/proc/self/fd/1", "file descriptor"]),
                                 ("a link to itself", "loop.json", ["-summary", "loop.json", "too many levels of symbolic links"])):
        with open(os.path.join(W, "stdout.txt"), "w") as f:  # /proc/self/fd/1 then leads to a regular file
            p = subprocess.run(command(args(os.path.join(LK, "D"), "A", 0, ["-summary", os.path.join(LK, name)]), ranks), cwd=SRC, stdout=f, stderr=subprocess.PIPE, text=True, env=ENV)
        line, problems = refusal_problems(p.returncode, [l for l in p.stderr.splitlines() if l.strip()], culprits)
        if link_state(LK) != links:
            problems.append("a link changed")
        report(not problems, "-summary %s, %d rank(s): refused" % (what, ranks), ("; ".join(problems) + " -- " if problems else "") + line)
        if name == "fd.json":
            fd_refused = fd_refused and not problems
# /dev/stdout with stdout redirected to a file (as root the program renamed
# its summary over /dev/stdout): tried only once the same through a link of
# our own was refused on 1 and 2 ranks, so that a broken build never touches /dev
if fd_refused and os.path.islink("/dev/stdout"):
    with open(os.path.join(W, "stdout.txt"), "w") as f:
        p = subprocess.run(command(args(os.path.join(LK, "D"), "A", 0, ["-summary", "/dev/stdout"]), 1), cwd=SRC, stdout=f, stderr=subprocess.PIPE, text=True, env=ENV)
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    line, problems = refusal_problems(p.returncode, lines, ["-summary", "/dev/stdout", "file descriptor"])
    if not os.path.islink("/dev/stdout"):
        problems.append("/dev/stdout is no longer a link")
    report(not problems, "-summary /dev/stdout, stdout a file: refused, /dev/stdout untouched", ("; ".join(problems) + " -- " if problems else "") + line)
else:
    report(False, "-summary /dev/stdout not tried: a link of our own to /proc/self/fd/1 was not refused")

# ---------------------------------------------------------------- -mesh_save under -adapt: the final mesh
for ranks in (1, 2):
    da = os.path.join(W, "adapt%d" % ranks)
    shutil.rmtree(da, ignore_errors=True)
    rc, err, _ = run(["-options_file", opts("hertz_adapt"), "-adapt_target", "0.03", "-contact_monitor", "0", "-output_dir", da, "-output_name", "a", "-mesh_save", os.path.join(da, "final.h5")], ranks)
    sa = json.load(open(os.path.join(da, "a_summary.json"))) if rc == 0 else {}
    rc2, err2, _ = run(["-options_file", opts("hertz"), "-mesh", os.path.join(da, "final.h5"), "-contact_monitor", "0", "-output_dir", da, "-output_name", "b"], ranks)
    sb = json.load(open(os.path.join(da, "b_summary.json"))) if rc2 == 0 else {}
    report(rc == 0 and rc2 == 0 and len(sa["adapt"]) > 1 and sa["dofs"] == sb["dofs"] and abs(sa["pressure_l2_rel"] / sb["pressure_l2_rel"] - 1) < 1e-8,
           "%d rank(s): -mesh_save under -adapt saves the final mesh (%s dofs after %d meshes); read back, the same answer (pressure error %s, %s)"
           % (ranks, sa.get("dofs"), len(sa.get("adapt", [])), sa.get("pressure_l2_rel"), sb.get("pressure_l2_rel")), "%s %s" % (err, err2))
T.finish()
