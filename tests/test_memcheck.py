"""Memory check: mortar2d under valgrind (memcheck) and PETSc's malloc checks.

valgrind runs (1 rank, suppressions in tests/valgrind.supp for Open MPI and
the libraries under it):
  S2 patch test      options/patch_uniform.opts
  Hertz level 0      options/hertz.opts -mesh <M2D_MESHES>/hertz_0.msh
  bad input          options/patch_uniform.opts -mesh <missing file>
  two pairs          options/stack.opts (three mesh files; three pairs on stack_split)
  adaptive           options/seed_patch_adapt.opts -adapt_max_steps 2 (gmsh's child
                     processes have logs of their own, checked alike)
Each must exit with its usual code (0, 0, 1; the bad input with its one
"mortar2d: error:" line), and valgrind must report
  - no invalid reads/writes/frees (anywhere),
  - no use of uninitialised values whose stack runs through src/*.c,
  - no definitely lost block allocated from src/*.c.
A frame of main() counts as the program's own code only when the error is in
main() itself (innermost frame): every stack passes through main(), and the
only calls it makes besides Run() are PetscInitialize/PetscFinalize (whose
Open MPI noise the suppressions cover).
Other unsuppressed reports (library-only) are printed as notes.

PETSc's own checks: both good scenes again with -malloc_debug -malloc_dump,
and Hertz level 1 on 2 ranks (condensed, full, tied, PETSc's partitioner);
they must exit 0 and PETSc must not list any unfreed memory.

Options: --error-paths also runs, under valgrind, errors found after the mesh
is set up (a bad material value, a missing contact group, surfaces that never
face each other), S2 read from its -mesh_save .h5 and a corrupted .h5, with
the same assertions; --jobs N (default 2)."""
import argparse
import glob
import os
import re
import shutil
import sys
import time
from concurrent.futures import ThreadPoolExecutor

from m2d import EXE, SRC, Tally, command, launch, mesh, opts, run, workdir

ap = argparse.ArgumentParser()
ap.add_argument("--error-paths", action="store_true")
ap.add_argument("--jobs", type=int, default=2)
ARGS = ap.parse_args()

PREFIX = "mortar2d: error: "
W = workdir("memcheck")
SUPP = os.path.join(SRC, "tests", "valgrind.supp")
TIMEOUT = 900
T = Tally()
report = T.check


# hwloc's x86 CPUID backend does not work under valgrind and says so on
# stderr; the program's stderr is checked here.
ENV = {"HWLOC_COMPONENTS": "-x86"}


missing = os.path.join(W, "nosuch.msh")
if os.path.exists(missing):
    os.remove(missing)

# (name, args, expected exit code)
CASES = [
    ("S2 patch test (patch_uniform)", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform")], 0),
    ("Hertz level 0 (hertz_0)", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_0")], 0),
    ("Hertz level 0, -kkt_path iterative", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_0"), "-kkt_path", "iterative"], 0),
    ("bad input: missing mesh file", ["-options_file", opts("patch_uniform"), "-mesh", missing], 1),
    # several contact pairs (issue 24): two interfaces, the shared-node mesh with three pairs
    ("stack, two pairs, three mesh files", ["-options_file", opts("stack"), "-mesh", ",".join(mesh("stack_%d" % b) for b in (1, 2, 3)), "-dirichlet", "base_bottom:y,base_origin:x,base_left:x,mid_left:x,top_left:x"], 0),
    ("stack_split, three pairs, one shared node", ["-options_file", opts("stack"), "-mesh", mesh("stack_split"), "-contact_pairs", "mid_bottom_a:base_top,mid_bottom_b:base_top:dual,top_bottom:mid_top:nts"], 0),
    # the adaptive loop: two meshes, each by gmsh in a child process (its own log), the size field, the estimator
    ("adaptive, seed_patch_adapt, 2 meshes", ["-options_file", opts("seed_patch_adapt"), "-adapt_max_steps", "2"], 0),
]
# the block with one cell 1e-6 thin: refused while the mesh lists are built (mesh_read.c)
thin = os.path.join(W, "thin_cell.msh")
with open(thin, "w") as f:
    f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n1 10 \"bottom\"\n0 11 \"origin\"\n2 1 \"block\"\n$EndPhysicalNames\n"
            "$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 2 0 0\n4 0 1e-6 0\n5 1 1e-6 0\n6 2 1e-6 0\n$EndNodes\n"
            "$Elements\n5\n1 1 2 10 1 1 2\n2 1 2 10 1 2 3\n3 15 2 11 1 1\n4 3 2 1 1 1 2 5 4\n5 3 2 1 1 2 3 6 5\n$EndElements\n")
# a 2 x 1 strip whose curve 'mid' is the edge between its two cells
strip = os.path.join(W, "strip_mid.msh")
with open(strip, "w") as f:
    f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 10 \"bottom\"\n0 11 \"origin\"\n1 12 \"mid\"\n2 1 \"block\"\n$EndPhysicalNames\n"
            "$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 2 0 0\n4 0 1 0\n5 1 1 0\n6 2 1 0\n$EndNodes\n"
            "$Elements\n6\n1 1 2 10 1 1 2\n2 1 2 10 1 2 3\n3 15 2 11 1 1\n4 1 2 12 1 2 5\n5 3 2 1 1 1 2 5 4\n6 3 2 1 1 2 3 6 5\n$EndElements\n")
S2 = ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform")]
if ARGS.error_paths:
    import h5py
    # mesh_h5.c: S2 saved by -mesh_save and read back; the same with a label index out of range
    s2h5, badh5 = os.path.join(W, "s2.h5"), os.path.join(W, "s2_bad_label.h5")
    run(S2 + ["-mesh_save", s2h5, "-output_dir", os.path.join(W, "save")])
    shutil.copy(s2h5, badh5)
    with h5py.File(badh5, "r+") as f:
        d = f["labels/m2d:upper_top/1/indices"]
        a = d[...]
        a[0] = 99999
        d[...] = a
    CASES += [
        ("S2 from its .h5 (-mesh_save)", ["-options_file", opts("patch_uniform"), "-mesh", s2h5], 0),
        ("error path: a .h5 label index out of range", ["-options_file", opts("patch_uniform"), "-mesh", badh5], 1),
        # problem.c: a load curve with an edge inside the body (the mesh is built)
        ("error path: a load on an edge inside the body", ["-options_file", opts("block"), "-mesh", strip, "-pressure", "mid:1e6", "-exact", "none"], 1),
        # mesh.c: a cell too thin for double precision (after the files are read, before the plex)
        ("error path: a 1e-6 thin cell", ["-options_file", opts("block"), "-mesh", thin, "-pressure", "", "-exact", "none"], 1),
        # problem.c / supports.c: the commonest bad input, before any solve (lost the Dirichlet values)
        ("error path: a body held by nothing", ["-options_file", opts("block"), "-mesh", mesh("block"), "-dirichlet", "bottom:y"], 1),
        # activeset.c / supports.c: the contact opens and the upper body is held by nothing
        ("error path: S2 pulled apart", S2 + ["-pressure", "upper_top:-1e6"], 1),
        # verify.c: after a whole solve, the equilibrium check fails (moduli 1e9 apart)
        ("error path: S2 fails its equilibrium check", S2 + ["-lower_E", "1"], 1),

        ("error path: -lower_E -1", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform"), "-lower_E", "-1"], 1),
        ("error path: -contact_nonmortar nosuch", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform"), "-contact_nonmortar", "nosuch"], 1),
        ("error path: -contact_mortar upper_top", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform"), "-contact_mortar", "upper_top"], 1),
        ("error path: a pair on one body", ["-options_file", opts("stack"), "-mesh", mesh("stack"), "-contact_pairs", "mid_bottom:base_top,top_bottom:top_top"], 1),
    ]

# ---------------------------------------------------------------- valgrind log
FRAME = re.compile(r"^\s+(?:at|by) 0x[0-9A-Fa-f]+: (\S+) \((.*)\)\s*$")
OWN = re.compile(r"^(?:src|include)/[^:]+\.[ch]:\d+$")


def records(log):
    """Valgrind's error records: lists of lines (prefix '==pid== ' removed)."""
    recs, cur = [], []
    for line in log.splitlines():
        m = re.match(r"^==\d+== ?(.*)$", line)
        if not m:
            continue
        text = m.group(1)
        if not text.strip():
            if cur:
                recs.append(cur)
            cur = []
        else:
            cur.append(text)
    if cur:
        recs.append(cur)
    return recs


def own_frames(rec):
    """Frames of the error's own stack (not the origin stack) in src/*.c or
    include/*.h, other than main()."""
    own, first = [], True
    for line in rec[1:]:
        if line.strip().startswith(("Uninitialised value was created", "Address 0x")):
            break
        m = FRAME.match(line)
        if not m:
            continue
        if OWN.match(m.group(2)) and (m.group(1) != "main" or first):
            own.append("%s (%s)" % (m.group(1), m.group(2)))
        first = False
    return own


def classify(log):
    """(problems, notes): lists of (headline, record text)."""
    problems, notes = [], []
    for rec in records(log):
        head = rec[0]
        text = "\n      ".join(rec[:24])
        if re.match(r"^(Invalid (read|write|free)|Mismatched free|Source and destination overlap|"
                     r"Argument '.*' of function .* has a fishy value|Jump to the invalid address|"
                     r"Process terminating with default action)", head):
            problems.append((head, text))
        elif "uninitialised" in head or "unaddressable" in head:
            (problems if own_frames(rec) else notes).append((head, text))
        elif "definitely lost in loss record" in head:
            (problems if own_frames(rec) else notes).append((head, text))
        elif re.match(r"^\d[\d,]* bytes in [\d,]+ blocks are (possibly|indirectly) lost", head):
            notes.append((head, text))
    return problems, notes


def valgrind_case(i, name, args, want_rc):
    out = os.path.join(W, "out%d" % i)
    shutil.rmtree(out, ignore_errors=True)
    logf = os.path.join(W, "valgrind%d.%%p.log" % i)  # one per process: gmsh's child processes have their own
    for f in glob.glob(logf.replace("%p", "*")):
        os.remove(f)
    valgrind = ["valgrind", "--error-exitcode=99", "--leak-check=full", "--errors-for-leak-kinds=definite",
                "--show-leak-kinds=definite", "--suppressions=" + SUPP, "--num-callers=50", "--track-origins=yes",
                "--fullpath-after=" + os.path.join(SRC, ""), "--log-file=" + logf]
    r = launch(command(args + ["-output_dir", out, "-contact_monitor", "0"], wrapper=valgrind), timeout=TIMEOUT, env=ENV)
    # the program's log last (its pid the smallest): its summary is the one reported
    logs = [open(f, errors="replace").read() for f in sorted(glob.glob(logf.replace("%p", "*")), key=lambda f: -int(f.split(".")[-2]))]
    logs = [l for l in logs if "ERROR SUMMARY" in l]  # (Open MPI's orted, forked and exec'd at MPI_Init, has none)
    return dict(name=name, cmd=r.cmd, rc=r.rc, want=want_rc, stdout=r.stdout, stderr=r.stderr, log="".join(logs), logf=logf,
                time=r.wall, out=out, processes=len(logs))


def check_valgrind(r):
    what = "valgrind: %s" % r["name"]
    cmdline = " ".join(r["cmd"])
    if r["rc"] is None:
        report(False, what, "no exit within %d s -- %s" % (TIMEOUT, cmdline))
        return
    if "ERROR SUMMARY" not in r["log"]:
        report(False, what, "valgrind did not finish its report (exit %d) -- %s\n%s" % (r["rc"], cmdline, r["log"][-2000:]))
        return
    problems, notes = classify(r["log"])
    lines = [l for l in r["stderr"].splitlines() if l.strip()]
    bad = []
    # with --error-exitcode=99 valgrind replaces the program's exit code when it
    # reports anything; then only library notes may be the reason
    if r["rc"] == 99:
        if not (problems or notes):
            bad.append("valgrind exit 99 without a record this test understands (see %s)" % r["logf"])
    elif r["rc"] != r["want"]:
        bad.append("exit code %d (want %d)" % (r["rc"], r["want"]))
    if r["want"] == 1:
        if len(lines) != 1 or not lines[0].startswith(PREFIX):
            bad.append("stderr is not one '%s' line: %r" % (PREFIX.strip(), r["stderr"][-600:]))
    elif lines:
        bad.append("stderr not empty: %r" % r["stderr"][-600:])
    if r["want"] == 0 and r["rc"] in (0, 99):
        files = os.listdir(r["out"]) if os.path.isdir(r["out"]) else []
        if not any(f.endswith(".vtu") for f in files):
            bad.append("no output written in %s" % r["out"])
    summary = re.findall(r"ERROR SUMMARY: (\d+) errors from (\d+) contexts \(suppressed: (\d+)", r["log"])
    lost = re.findall(r"definitely lost: ([\d,]+) bytes in ([\d,]+) blocks", r["log"])
    info = "%.0f s, exit %d, %s errors (%s suppressed), definitely lost %s bytes" % (
        r["time"], r["rc"], summary[-1][0] if summary else "?", summary[-1][2] if summary else "?",
        lost[-1][0] if lost else "0")
    if r["processes"] > 1:
        info += " (the program's; gmsh's %d child process(es): %s errors)" % (r["processes"] - 1, "+".join(e for e, _, _ in summary[:-1]))
    if notes:
        info += "; %d library-only report(s) not counted:\n    %s" % (len(notes), "\n    ".join(n[0] for n in notes))
    for head, text in problems:
        bad.append(text)
    if bad:
        report(False, what, "%s\n    command: %s\n    log: %s\n    %s" % (info, cmdline, r["logf"], "\n    ".join(bad)))
    else:
        report(True, what, info)


# ---------------------------------------------------------------- PETSc malloc checks
UNFREED = re.compile(r"^\s*\[\s*\d+\]\s*(?:Total space allocated|Maximum memory|\d+ bytes \S+)|unfreed|"
                     r"Memory (?:leak|still allocated)", re.I | re.M)


def malloc_case(name, args, ranks=1):
    what = "-malloc_debug -malloc_dump: %s" % name
    out = os.path.join(W, "malloc_out")
    shutil.rmtree(out, ignore_errors=True)
    p = launch(command(args + ["-output_dir", out, "-contact_monitor", "0", "-malloc_debug", "-malloc_dump"], ranks),
               timeout=TIMEOUT, env=ENV)
    if p.timed_out:
        report(False, what, "no exit within %d s -- %s" % (TIMEOUT, p.cmdline))
        return
    leaks = [l for l in (p.stdout + "\n" + p.stderr).splitlines() if UNFREED.search(l)]
    bad = []
    if p.rc != 0:
        bad.append("exit code %d (want 0); stderr: %s" % (p.rc, p.stderr[-800:]))
    if p.stderr.strip():
        bad.append("stderr not empty: %r" % p.stderr[-800:])
    if leaks:
        bad.append("PETSc reports %d unfreed block(s):\n      %s" % (len(leaks), "\n      ".join(leaks[:20])))
    detail = "%.1f s, exit %d" % (p.wall, p.rc)
    if bad:
        report(False, what, "%s\n    command: %s\n    %s" % (detail, p.cmdline, "\n    ".join(bad)))
    else:
        report(True, what, detail + ", nothing unfreed")


def main():
    if shutil.which("valgrind") is None:
        report(False, "valgrind is installed", "valgrind not found on PATH (tools/setup.sh installs it)")
        T.finish()
    if not os.path.exists(EXE):
        report(False, "executable %s exists" % EXE, "build first, or set M2D_EXE")
        T.finish()
    if not os.path.exists(SUPP):
        report(False, "suppression file %s exists" % SUPP)
    t0 = time.time()
    with ThreadPoolExecutor(max_workers=ARGS.jobs) as pool:
        futs = [pool.submit(valgrind_case, i, n, a, rc) for i, (n, a, rc) in enumerate(CASES)]
        for f in futs:
            check_valgrind(f.result())
    malloc_case("S2 patch test (patch_uniform)", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform")])
    malloc_case("Hertz level 0 (hertz_0)", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_0")])
    # 2 ranks: the plex built per rank, the condensed path's MUMPS on 2 ranks, the full path, the tied solve, the iterative path
    # (tied Hertz holds every candidate node closed: its cylinder strains by 76%, allowed here)
    for extra in ([], ["-kkt_path", "full"], ["-contact_unilateral", "0", "-strain_limit", "1"], ["-mesh_partitioner", "petsc"], ["-kkt_path", "iterative"]):
        malloc_case("Hertz level 1, 2 ranks %s" % " ".join(extra), ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1")] + extra, ranks=2)
    print("total %.0f s" % (time.time() - t0))
    T.finish()


if __name__ == "__main__":
    sys.exit(main())
