"""The one helper module of the mortar2d tests and tools: where things are, how
to start the program (on 1 or N ranks, with every Open MPI setting it needs),
and how to read what it writes (summary JSON, contact CSV, HDF5 fields).

Tests are plain Python scripts run by ctest from this directory (so `import m2d`
works); a test fails by raising (non-zero exit). Tools in tools/ import it with
    sys.path.insert(0, os.path.join(<source>, "tests")); import m2d

Paths come from the environment tests/CMakeLists.txt gives every test; the
defaults are only for running a script by hand from a tree built in build/:
    M2D_EXE     the program              default <source>/build/mortar2d
    M2D_MESHES  the generated .msh files default <source>/build/meshes
    M2D_SOURCE  the source tree          default the parent of this directory
    M2D_WORK    scratch output           default <source>/build/test-output
    MPIEXEC     Open MPI's launcher      default mpiexec

Every process this module starts gets MPI_ENV (running as root in the CI
container, more ranks than cores on a shared machine): nothing else in the
tests or tools sets these."""
import csv
import json
import os
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from typing import NamedTuple

SRC = os.path.abspath(os.environ.get("M2D_SOURCE") or os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXE = os.path.abspath(os.environ.get("M2D_EXE") or os.path.join(SRC, "build", "mortar2d"))
MESHES = os.path.abspath(os.environ.get("M2D_MESHES") or os.path.join(SRC, "build", "meshes"))
WORK = os.path.abspath(os.environ.get("M2D_WORK") or os.path.join(SRC, "build", "test-output"))
MPIEXEC = os.environ.get("MPIEXEC") or "mpiexec"

# Open MPI: allow root (containers, CI), allow more ranks than free cores, and
# no "mpiexec noticed that process rank N exited ..." banner after a rank's
# error exit (the tests check that stderr holds only the program's own line)
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1", "OMPI_MCA_orte_execute_quiet": "1"}


# ---------------------------------------------------------------- paths
def mesh(name):
    """Path of a generated mesh, e.g. mesh("hertz_0")."""
    return os.path.join(MESHES, name + ".msh")


def opts(name):
    """Path of a scene or solver options file, e.g. opts("hertz")."""
    return os.path.join(SRC, "options", name + ".opts")


# the program's M2D_TEST_* environment hooks, compiled in by -DM2D_TEST_HOOKS=ON
# (tools/test.sh); without them the checks that need one are skipped, saying so
HOOKS = os.environ.get("M2D_TEST_HOOKS", "1") not in ("0", "", "OFF")


def hooks(what):
    """HOOKS, and a line saying what is skipped without them"""
    if not HOOKS:
        print("skip %s: this build has no test hooks (configure with -DM2D_TEST_HOOKS=ON, as tools/test.sh does)" % what)
    return HOOKS


def workdir(name):
    """WORK/name, created."""
    d = os.path.join(WORK, name)
    os.makedirs(d, exist_ok=True)
    return d


def hertz_mesh(level):
    """Path of Hertz level N in MESHES; tools/hertz_mesh.sh makes it when it is
    missing or older than meshes/hertz.geo (levels above 4 are not built by CMake)."""
    out = mesh("hertz_%d" % level)
    r = launch(["bash", os.path.join(SRC, "tools", "hertz_mesh.sh"), str(level), out], timeout=None)
    if r.rc != 0:
        raise RuntimeError("tools/hertz_mesh.sh %d %s failed (exit %s): %s" % (level, out, r.rc, r.stderr[-2000:]))
    return out


# ---------------------------------------------------------------- running
def mpi_env(**extra):
    """The environment of every process started here: ours, MPI_ENV, extra."""
    e = dict(os.environ)
    e.update(MPI_ENV)
    e.update(extra)
    return e


def command(args, ranks=1, exe=None, wrapper=()):
    """The command line of the program on `ranks` ranks; `wrapper` goes in front
    of the program on every rank (valgrind, GNU time, ...)."""
    cmd = list(wrapper) + [exe or EXE] + [str(a) for a in args]
    if ranks > 1:
        cmd = [MPIEXEC, "-n", str(ranks)] + cmd
    return cmd


class Run(NamedTuple):
    cmd: list
    rc: object          # exit code (negative: killed by that signal); None: timed out
    stdout: str         # "" when written to a file (launch(stdout=PATH))
    stderr: str         # "" when merged into stdout
    wall: float         # seconds
    timed_out: bool
    maxrss_mb: float    # peak resident memory of the process (of mpiexec's tree on N ranks)
    cpu_s: float        # user + system seconds of the process and its children

    @property
    def cmdline(self):
        return shlex.join(self.cmd)


def _session_members(sid):
    """pids of the live processes of session sid (Linux /proc)."""
    pids = []
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % d) as f:
                fields = f.read().rsplit(")", 1)[1].split()
            if int(fields[3]) == sid:
                pids.append(int(d))
        except (OSError, IndexError, ValueError):
            pass
    return pids


def _kill_session(pid):
    """End what the process `pid` started: mpiexec puts every rank in a process
    group of its own, but they stay in the session created for it here."""
    try:
        os.kill(pid, signal.SIGTERM)    # mpiexec ends its ranks on SIGTERM
    except ProcessLookupError:
        pass
    for _ in range(20):
        if not _session_members(pid):
            return
        time.sleep(0.1)
    for p in _session_members(pid):
        try:
            os.kill(p, signal.SIGKILL)
        except ProcessLookupError:
            pass


def launch(cmd, timeout=600, cwd=None, env=None, stdout=None, merge=False):
    """Run cmd (a list) in its own session from cwd (default SRC) with
    mpi_env(**env); return a Run. A run longer than `timeout` seconds (None: no
    limit) is ended with everything it started, and Run.rc is None. stdout=PATH
    writes the output to that file instead of Run.stdout; merge=True sends
    stderr there too."""
    out = open(stdout, "w+b") if stdout else tempfile.TemporaryFile()
    err = subprocess.STDOUT if merge else tempfile.TemporaryFile()
    t0 = time.time()
    try:
        p = subprocess.Popen(cmd, cwd=cwd or SRC, env=mpi_env(**(env or {})), stdin=subprocess.DEVNULL,
                             stdout=out, stderr=err, start_new_session=True)
        expired = []

        def expire():
            expired.append(True)
            _kill_session(p.pid)
        timer = threading.Timer(timeout, expire) if timeout else None
        if timer:
            timer.start()
        try:
            _, status, ru = os.wait4(p.pid, 0)
        finally:
            if timer:
                timer.cancel()
        p.returncode = os.waitstatus_to_exitcode(status)
        wall = time.time() - t0
        if expired:
            _kill_session(p.pid)    # what is left of the ranks
        texts = []
        for f in (out, err):
            if f is subprocess.STDOUT or stdout and f is out:
                texts.append("")
                continue
            f.seek(0)
            texts.append(f.read().decode(errors="replace"))
    finally:
        out.close()
        if err is not subprocess.STDOUT:
            err.close()
    return Run(cmd, None if expired else p.returncode, texts[0], texts[1], wall, bool(expired),
               ru.ru_maxrss / 1024.0, ru.ru_utime + ru.ru_stime)


def run(args, ranks=1, check=True, timeout=600, **kw):
    """Run the program with args on `ranks` ranks; return (rc, stdout, stderr).
    check: a non-zero exit prints the command and its output and exits 1.
    A timeout raises subprocess.TimeoutExpired (after ending the run).
    kw: exe, wrapper (see command), cwd, env (see launch)."""
    r = launch(command(args, ranks, kw.pop("exe", None), kw.pop("wrapper", ())), timeout=timeout, **kw)
    if r.timed_out:
        raise subprocess.TimeoutExpired(r.cmd, timeout, r.stdout, r.stderr)
    if check and r.rc != 0:
        sys.stderr.write("command failed (exit %d): %s\n%s\n%s\n" % (r.rc, r.cmdline, r.stdout, r.stderr))
        raise SystemExit(1)
    return r.rc, r.stdout, r.stderr


def solve(name, args, ranks=1):
    """Run with output in WORK/name (an old summary removed first); return the summary dict."""
    d = workdir(name)
    summary = os.path.join(d, "summary.json")
    if os.path.exists(summary):
        os.remove(summary)
    run(list(args) + ["-output_dir", d, "-summary", summary], ranks=ranks)
    return read_json(summary)


# ---------------------------------------------------------------- reading the output
def read_json(path):
    with open(path) as f:
        return json.load(f)


def read_csv(path):
    """Rows of a CSV written by the program (NAME_contact.csv), as dicts of
    floats (without the run_id column)."""
    with open(path) as f:
        return [{k: float(v) for k, v in r.items() if k != "run_id"} for r in csv.DictReader(f)]


def csv_columns(path):
    """The numeric columns of read_csv(path) as numpy arrays, by name (file order)."""
    import numpy as np
    with open(path) as f:
        names = [n for n in next(csv.reader(f)) if n != "run_id"]
    rows = read_csv(path)
    return {k: np.array([r[k] for r in rows], dtype=float) for k in names}


def read_h5(path):
    """Return (xy, cells, vertex_fields, cell_fields) from our HDF5 output."""
    import h5py
    import numpy as np
    with h5py.File(path, "r") as f:
        xy = np.array(f["geometry/vertices"])
        cells = np.array(f["topology/cells"])
        vf = {k: np.array(v) for k, v in f["vertex_fields"].items()} if "vertex_fields" in f else {}
        cf = {k: np.array(v) for k, v in f["cell_fields"].items()} if "cell_fields" in f else {}
    return xy, cells, vf, cf


def sorted_fields(path, digits=9):
    """Fields re-ordered by coordinates (vertices) and centroids (cells), so
    runs on different rank counts can be compared entry by entry."""
    import numpy as np
    xy, cells, vf, cf = read_h5(path)
    # coincident vertices of two bodies: break ties by the non-mortar flag and
    # the (rounded) displacement, which differ between the two bodies
    ties = []
    if "gap" in vf:
        ties.append(np.isnan(vf["gap"]).astype(int))
    if "displacement" in vf:
        u = vf["displacement"]
        scale = max(np.abs(u).max(), 1e-300)
        ties += [np.round(u[:, 0] / scale, 6), np.round(u[:, 1] / scale, 6)]
    vkey = np.lexsort(tuple(ties) + (np.round(xy[:, 1], digits), np.round(xy[:, 0], digits)))
    cen = xy[cells].mean(axis=1)
    ckey = np.lexsort((np.round(cen[:, 1], digits), np.round(cen[:, 0], digits)))
    return ({k: v[vkey] for k, v in vf.items()}, {k: v[ckey] for k, v in cf.items()}, xy[vkey], cen[ckey])


# ---------------------------------------------------------------- checks
def check(cond, msg):
    """Print the check; stop the test at the first failure."""
    print(("ok   " if cond else "FAIL ") + msg, flush=True)
    if not cond:
        raise SystemExit(1)


def refusal_problems(rc, lines, culprits=()):
    """What is wrong with a run that had to refuse its input: it must exit 1
    with exactly one stderr line "mortar2d: error: ..." that names every
    culprit. lines: the non-empty stderr lines. Returns (the line, or the lines
    joined, for the report; the problems, [] when none)."""
    line = lines[0] if len(lines) == 1 else " | ".join(lines)[:600]
    problems = []
    if rc != 1:
        problems.append("exit code %s (want 1)" % rc)
    if len(lines) != 1 or not lines[0].startswith("mortar2d: error: "):
        problems.append("stderr is not one 'mortar2d: error: ' line")
    problems += ["the line does not name %r" % c for c in culprits if c not in line]
    return line, problems


class Tally:
    """Checks that all run and are counted; finish() prints the count and exits
    1 if any failed."""

    def __init__(self):
        self.passed = self.failed = 0

    def check(self, cond, msg, detail=""):
        print(("ok   " if cond else "FAIL ") + msg + (": " + detail if detail else ""), flush=True)
        if cond:
            self.passed += 1
        else:
            self.failed += 1
        return cond

    def finish(self):
        print("%d passed, %d failed" % (self.passed, self.failed), flush=True)
        raise SystemExit(1 if self.failed else 0)


# ---------------------------------------------------------------- fuzzing (mesh_fuzz, mesh_fuzz_h5, geo_fuzz)
FUZZ_PREFIX = "mortar2d: error: "


def shown(text):
    """text with control characters escaped, safe to print to a log or terminal"""
    import re
    return re.sub(r"[\x00-\x08\x0b-\x1f\x7f-\x9f\u2028\u2029]", lambda m: "\\x%02x" % ord(m.group(0)), text)


def fuzz_case(i, name, desc, args, out, faildir, timeout, ranks=1, inputs=(), keep=False):
    """Run one fuzz variant (the program with args plus -output_dir out) and
    judge it by the fuzz contract:
      ran      exit 0, quiet stderr, the output (.h5, .xmf, .vtu) written;
      rejected exit 1 and stderr is exactly one line "mortar2d: error: ...";
      failed   anything else: a signal, another exit code, no exit within
               `timeout` s, a multi-line or unprefixed error, noise on success,
               .tmp files left, a traceback or signal message.
    A failure keeps the inputs (files), the command and the output in faildir.
    Returns a dict (i, name, desc, rc, outcome, problems, notes, lines, ...)."""
    import re
    r = launch(command(list(args) + ["-output_dir", out], ranks), timeout=timeout)
    rc, so, se = r.rc, r.stdout, r.stderr
    problems, notes = [], []
    lines = [l for l in se.splitlines() if l.strip()]
    files = sorted(os.listdir(out)) if os.path.isdir(out) else []
    outcome = "failed"
    if rc is None:
        problems.append("no exit within %g s (hang?)" % timeout)
    elif rc == 0:
        outcome = "ran"
        if lines:
            problems.append("exit 0 but stderr is not empty")
        missing = [n for n in ("h5", "xmf", "vtu") if not any(f.endswith("." + n) for f in files)]
        if missing:
            problems.append("exit 0 but no .%s output" % ", .".join(missing))
        if re.search(r"\b-?(nan|inf)\b", so, re.I):
            notes.append("nan/inf in stdout")
    elif rc == 1:
        outcome = "rejected"
        if len(lines) != 1 or not lines[0].startswith(FUZZ_PREFIX):
            problems.append("exit 1 but stderr is not exactly one '%s' line" % FUZZ_PREFIX.strip())
            ctrl = sorted(set(re.findall(r"[\x00-\x08\x0b-\x1f\x7f\x85\u2028\u2029]", se)))
            if se.count("\n") == 1 and ctrl:
                problems.append("the error line (one '\\n') holds raw control characters %s echoed from the input; "
                                "str.splitlines() and terminals break it at \\x0b \\x0c \\x1c-\\x1e" % " ".join(repr(c) for c in ctrl))
    else:
        problems.append("exit code %d%s" % (rc, " (signal %d)" % -rc if rc < 0 else ""))
    tmp = [f for f in files if ".tmp" in f]
    if tmp:
        problems.append("temporary files left in the output dir: %s" % tmp)
    for bad in ("Traceback", "PETSC ERROR", "Caught signal", "Segmentation", "AddressSanitizer", "MPI_ABORT"):
        if bad in so or bad in se:
            problems.append("output contains %r" % bad)
    if problems:
        outcome = "failed"
        os.makedirs(faildir, exist_ok=True)
        for p in inputs:
            if os.path.isfile(p):
                shutil.copy(p, os.path.join(faildir, os.path.basename(p)))
        with open(os.path.join(faildir, "%03d_%s.txt" % (i, name)), "w") as f:
            f.write("mutation: %s\ncommand: %s\nexit: %s\nproblems: %s\n--- stdout\n%s--- stderr\n%s" %
                    (desc, r.cmdline, rc, "; ".join(problems), so, se))
    if not keep:
        shutil.rmtree(out, ignore_errors=True)
        if not problems:
            for p in inputs:
                if os.path.isfile(p):
                    os.remove(p)
    return dict(i=i, name=name, desc=desc, rc=rc, outcome=outcome, problems=problems, notes=notes,
                stdout=so, stderr=se, lines=lines, time=r.wall, cmd=r.cmdline)


def fuzz_report(results, t0, seed, faildir, groups=()):
    """Print one line per variant and the summary (per group: the name's
    prefix before ':'); return the exit code of the test (1 if any failed)."""
    passed = failed = 0
    for r in results:
        ok = not r["problems"]
        passed += ok
        failed += not ok
        detail = r["outcome"] if ok else "; ".join(r["problems"])
        if ok and r["outcome"] == "rejected":
            detail += ": " + shown(r["lines"][0][len(FUZZ_PREFIX):][:150])
        if r["notes"]:
            detail += " [%s]" % ", ".join(r["notes"])
        print("%s [%03d %s] %s -- %s" % ("ok  " if ok else "FAIL", r["i"], r["name"], shown(r["desc"]), detail))
    by = {k: [r for r in results if r["outcome"] == k] for k in ("ran", "rejected", "failed")}
    print()
    print("summary: %d variants (seed %d) in %.1f s: %d ran fine (exit 0), %d rejected cleanly (exit 1, one error line), %d failed"
          % (len(results), seed, time.time() - t0, len(by["ran"]), len(by["rejected"]), len(by["failed"])))
    for g in groups:
        rs = [r for r in results if r["name"].split(":")[0] == g]
        print("  %-18s %3d variants: %3d ran, %3d rejected, %3d failed" % (
            g, len(rs), sum(r["outcome"] == "ran" for r in rs), sum(r["outcome"] == "rejected" for r in rs),
            sum(r["outcome"] == "failed" for r in rs)))
    slow = max(results, key=lambda r: r["time"]) if results else None
    if slow:
        print("  slowest: [%03d] %.1f s" % (slow["i"], slow["time"]))
    sus = [r for r in results if r["notes"]]
    if sus:
        print("  note: %d runs exited 0 with nan/inf in their output: %s" % (len(sus), ", ".join("%03d" % r["i"] for r in sus)))
    if by["failed"]:
        print("failures (inputs and output kept in %s):" % faildir)
        for r in by["failed"]:
            print("  [%03d %s] %s\n    %s\n    %s\n    exit %s, stderr: %s" % (
                r["i"], r["name"], shown(r["desc"]), "; ".join(r["problems"]), r["cmd"], r["rc"],
                shown(r["stderr"].rstrip("\n"))[:800] or "(empty)"))
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


def fuzz_args(name, seed, count, timeout):
    """The fuzz tests' command line (--seed, --count, --jobs, --timeout,
    --keep) and their work folders: (ARGS, W, VAR, OUTROOT, FAILDIR), the
    folders emptied."""
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=seed)
    ap.add_argument("--count", type=int, default=count)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--keep", action="store_true")
    ap.add_argument("--timeout", type=float, default=timeout)
    args = ap.parse_args()
    w = workdir(name)
    dirs = [os.path.join(w, d) for d in ("variants", "out", "failures")]
    for d in dirs:
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
    return (args, w, *dirs)


def fuzz_main(args, faildir, groups, generate, run_variant, prepare=None):
    """Generate the variants (generate(rng, *prepare())), run them args.jobs
    at a time, report; the test's exit code."""
    import random
    import time
    from concurrent.futures import ThreadPoolExecutor
    if not os.path.exists(EXE):
        print("FAIL executable %s does not exist (build first, or set M2D_EXE)" % EXE)
        print("0 passed, 1 failed")
        return 1
    t0 = time.time()
    variants = generate(random.Random(args.seed), *(prepare() if prepare else ()))
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        results = list(pool.map(lambda a: run_variant(a[0], *a[1]), enumerate(variants)))
    return fuzz_report(results, t0, args.seed, faildir, groups)
