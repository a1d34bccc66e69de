"""Options: typos, values outside their domain and broken options files stop the
run with exit code 1 and exactly one stderr line "mortar2d: error: ..." naming
the option or the file (and, for a typo, the closest known name); no crash, no
hang. Each case runs on 1 and 2 ranks. Good runs that use PETSc options read
late or only on some paths must not be refused (no false alarm).

  1. unknown options: the program's (scene, per-body) and PETSc's (a prefix
     typo is caught right after the options are read, a typo under a PETSc
     prefix once the solvers are configured);
  2. values outside their domain, non-numbers, inf and nan;
  3. options files: include cycles (a -> a, a -> b -> a, through
     PETSC_OPTIONS), missing or unreadable files, a line PETSc refuses;
  4. an unknown value of a choice names the option and lists the choices;
  5. options that do nothing, values cut, files cut;
  6. messages that named the wrong cause (issue 33 item 12): two pairs
     sharing non-mortar edges, -iterative_ksp_atol above the steps'
     residuals, a 3,000-digit value, integer options in e-notation, empty
     entries of -output and -output contradicting -output_hdf5/-output_vtu,
     two -hertz_radius values with two pairs, a turn just past 45 degrees, a
     misspelt option after a good run (its summary marked), the program
     started without a mesh or with -h/--help;
and scenes run from any directory, mesh names resolved against -mesh_dir,
-hertz_radius R1:R2 compared through its effective radius.

Open MPI's "job aborted" banner (mpiexec's, not mortar2d's) is switched off
with OMPI_MCA_orte_execute_quiet, as in test_bad_input.py."""
import json
import os
import re
import shutil
import subprocess

from m2d import EXE, SRC, Tally, mesh, opts, refusal_problems, run, workdir

os.environ["OMPI_MCA_orte_execute_quiet"] = "1"
TIMEOUT = 120
W = workdir("options")
OUT = os.path.join(W, "out")
T = Tally()
report = T.check


def write(name, text):
    p = os.path.join(W, name)
    with open(p, "w") as f:
        f.write(text)
    return p


def attempt(args, ranks, env=None, cwd=None):
    """(rc, stdout, stderr lines) or None on a timeout."""
    try:
        if env is None and cwd is None:
            rc, out, err = run(args, ranks=ranks, check=False, timeout=TIMEOUT)
        else:
            cmd = [EXE] + args
            if ranks > 1:
                cmd = [os.environ.get("MPIEXEC", "mpiexec"), "--oversubscribe", "-n", str(ranks)] + cmd
            e = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", **(env or {}))
            p = subprocess.run(cmd, cwd=cwd or SRC, capture_output=True, text=True, timeout=TIMEOUT, env=e)
            rc, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired:
        return None
    return rc, out, [l for l in err.splitlines() if l.strip()]


def bad(name, args, culprits, ranklist=(1, 2), env=None, cwd=None):
    for ranks in ranklist:
        what = "%s [%d rank%s]" % (name, ranks, "s" if ranks > 1 else "")
        r = attempt(args, ranks, env, cwd)
        if r is None:
            report(False, what, "no exit within %d s (hang?)" % TIMEOUT)
            continue
        rc, out, lines = r
        line, problems = refusal_problems(rc, lines, culprits)
        report(not problems, what, ("; ".join(problems) + " -- stderr: " if problems else "") + line)


def good(name, args, ranklist=(1, 2), env=None, cwd=None):
    for ranks in ranklist:
        what = "%s [%d rank%s]" % (name, ranks, "s" if ranks > 1 else "")
        r = attempt(args + ["-output_dir", OUT], ranks, env, cwd)
        if r is None:
            report(False, what, "no exit within %d s (hang?)" % TIMEOUT)
            continue
        rc, out, lines = r
        report(rc == 0 and not lines, what, "exit code %d, stderr: %s" % (rc, " | ".join(lines)[:400]))


BLOCK = ["-options_file", opts("block"), "-output_dir", OUT]
PATCH = ["-options_file", opts("patch_uniform"), "-output_dir", OUT]
HERTZ0 = ["-options_file", opts("hertz"), "-mesh", mesh("hertz_0"), "-output_dir", OUT]

# ---------- 1. unknown options ----------
bad("typo of a scene option", BLOCK + ["-contact_metod", "nts"], ["option -contact_metod is unknown", "did you mean -contact_method?"])
bad("typo of a per-body option (-bodies given)", BLOCK + ["-blok_E", "1e9"], ["-blok_E", "did you mean -block_E?"])
nobodies = write("block_no_bodies.opts", "".join(l for l in open(opts("block")) if not l.startswith("-bodies")))
bad("typo of a per-body option (bodies from the mesh)", ["-options_file", nobodies, "-output_dir", OUT, "-blok_nu", "0.3"], ["-blok_nu", "did you mean -block_nu?"])
bad("option of nobody", BLOCK + ["-frobnicate"], ["option -frobnicate is unknown"])
bad("typo of a PETSc prefix", PATCH + ["-kps_type", "preonly"], ["-kps_type", "did you mean -ksp_type?"])
bad("typo under -ksp_ (tied, linear solve)", PATCH + ["-contact_unilateral", "false", "-ksp_tpye", "preonly"], ["-ksp_tpye", "did you mean -ksp_type?"])
bad("typo under -snes_ (active set)", PATCH + ["-snes_max_iter", "5"], ["-snes_max_iter", "did you mean -snes_max_it?"])
bad("typo under -pc_ (no contact)", BLOCK + ["-pc_factor_mat_solver_tpye", "mumps"], ["-pc_factor_mat_solver_tpye", "did you mean -pc_factor_mat_solver_type?"])
bad("typo under a split's prefix", PATCH + ["-options_file", opts("kkt_fieldsplit"), "-fieldsplit_u_pc_tpye", "lu"], ["-fieldsplit_u_pc_tpye", "did you mean -fieldsplit_u_pc_type?"])
bad("typo under an inner solver's prefix", PATCH + ["-kkt_path", "full", "-pc_type", "redundant", "-redundant_pc_tpye", "lu"], ["-redundant_pc_tpye", "did you mean -redundant_pc_type?"])
bad("typo of a MUMPS option", PATCH + ["-kkt_path", "full", "-mat_mumps_icntl7", "2"], ["-mat_mumps_icntl7", "did you mean -mat_mumps_icntl_7?"])
bad("PETSc option nothing reads", BLOCK + ["-dm_refine", "2"], ["-dm_refine"])
# no false alarm: options read late (viewers, finalize), only on some paths, or by a split
good("viewers, reports and finalize-time options", BLOCK + ["-ksp_converged_reason", "-ksp_view", ":" + os.path.join(W, "kspview.txt"),
                                                            "-options_left", "no", "-malloc_dump", "-log_view", ":" + os.path.join(W, "log.txt")])
good("full path with PETSc's MUMPS options", PATCH + ["-kkt_path", "full", "-options_file", opts("kkt_mumps"), "-mat_mumps_icntl_24", "1", "-snes_max_it", "20"])
good("condensed path with PETSc's MUMPS options on the full path", PATCH + ["-kkt_path", "full", "-options_file", opts("kkt_mumps"), "-mat_mumps_cntl_1", "0.01", "-snes_rtol", "1e-10"])
good("fieldsplit (kkt_fieldsplit.opts)", PATCH + ["-options_file", opts("kkt_fieldsplit")])
good("an inner solver's options (PCREDUNDANT: read at its set-up)", PATCH + ["-kkt_path", "full", "-pc_type", "redundant", "-redundant_pc_type", "lu", "-redundant_pc_factor_mat_solver_type", "mumps"])
good("PETSc's partitioner options", PATCH + ["-mesh_partitioner", "petsc", "-petscpartitioner_type", "simple"])
good("option names are case-insensitive (as PETSc)", PATCH + ["-Lower_E", "1e9", "-CONTACT_METHOD", "mortar"])
good("PETSc tolerances inside their domain", PATCH + ["-kkt_path", "full", "-ksp_rtol", "1e-8", "-snes_stol", "1e-8", "-snes_max_it", "2147483647"], ranklist=(1,))
good("automatic values said explicitly", HERTZ0 + ["-contact_c", "auto", "-contact_reach", "AUTO", "-hertz_load", "auto"], ranklist=(1,))

# ---------- 2. values outside their domain ----------
for opt, val, base in [("-contact_c", "0", PATCH), ("-contact_c", "-1", PATCH), ("-contact_c", "inf", PATCH), ("-contact_reach", "-1", PATCH),
                       ("-mesh_scale", "0", BLOCK), ("-mesh_scale", "nan", BLOCK), ("-hertz_radius", "0", HERTZ0),
                       ("-hertz_radius", "1:-2", HERTZ0), ("-hertz_radius", "1,2", HERTZ0), ("-hertz_radius", "1:2:3", HERTZ0), ("-hertz_radius", "one", HERTZ0),
                       ("-hertz_load", "0", HERTZ0), ("-kkt_augment", "-1", PATCH), ("-exact_p", "-1", BLOCK),
                       ("-exact_p", "x", BLOCK), ("-exact_angle", "inf", BLOCK), ("-mms_amplitude", "0", BLOCK),
                       ("-block_E", "1e308", BLOCK), ("-block_E", "1e-301", BLOCK), ("-block_E", "0", BLOCK),
                       ("-block_E", "inf", BLOCK), ("-block_E", "nan", BLOCK), ("-block_E", "1e9x", BLOCK),
                       ("-block_nu", "0.5", BLOCK), ("-block_nu", "-1", BLOCK),
                       ("-snes_max_it", "0", PATCH), ("-snes_max_it", "-3", PATCH), ("-snes_max_it", "ten", PATCH),
                       ("-snes_max_it", "99999999999999999999", PATCH), ("-ksp_rtol", "-1", PATCH), ("-ksp_rtol", "1", PATCH),
                       ("-snes_rtol", "-1", PATCH), ("-snes_atol", "nan", PATCH), ("-ksp_atol", "-1e-9", PATCH),
                       ("-mat_mumps_icntl_4", "5", PATCH), ("-mat_mumps_icntl_7", "1", PATCH), ("-mat_mumps_icntl_7", "8", PATCH),
                       ("-mat_mumps_icntl_8", "-1", PATCH), ("-mat_mumps_icntl_14", "-5", PATCH), ("-mat_mumps_icntl_58", "0", PATCH),
                       ("-mat_mumps_icntl_14", "2.5", PATCH), ("-kkt_ldlt", "maybe", PATCH), ("-mesh_check", "2", BLOCK)]:
    bad("%s %s" % (opt, val), base + [opt, val], [opt], ranklist=(1, 2) if opt in ("-contact_c", "-block_E", "-snes_max_it") else (1,))
bad("-dirichlet G:n:inf", BLOCK + ["-dirichlet", "bottom:n:inf"], ["-dirichlet", "inf"], ranklist=(1,))
bad("-dirichlet G:nt", BLOCK + ["-dirichlet", "bottom:nt"], ["-dirichlet", "nt"], ranklist=(1,))

# ---------- 3. options files ----------
selfinc = write("self.opts", "# includes itself\n-options_file %s\n" % os.path.join(W, "self.opts"))
a = os.path.join(W, "cycle_a.opts")
b = write("cycle_b.opts", "-mesh_scale 1\n  -options_file \"%s\" # back to a\n" % a)
write("cycle_a.opts", "-options_file %s\n" % b)
missing = os.path.join(W, "nosuch.opts")
if os.path.exists(missing):
    os.remove(missing)
nested_missing = write("nested_missing.opts", "-options_file %s\n" % missing)
twoopts = write("two_per_line.opts", "-mesh_scale 1 -plane strain\n")
notopt = write("not_an_option.opts", "mesh_scale 1\n")
bad("options file includes itself", ["-options_file", selfinc], ["options file", "self.opts", "includes itself"])
bad("options files a -> b -> a", ["-options_file", a], ["options file", "cycle_a.opts -> ", "cycle_b.opts -> ", "includes itself"])
bad("cycle through PETSC_OPTIONS", BLOCK, ["self.opts", "includes itself"], env={"PETSC_OPTIONS": "-options_file " + selfinc})
bad("missing options file", BLOCK + ["-options_file", missing], ["options file", missing])
bad("missing options file named inside another", ["-options_file", nested_missing], [missing, "nested_missing.opts"])
bad("a directory as options file", ["-options_file", W], ["options file", W, "directory"])
bad("-options_file without a name", BLOCK + ["-options_file"], ["-options_file", "missing file name"])
bad("two options on one line", ["-options_file", twoopts], ["two_per_line.opts", "line 1"], ranklist=(1,))
bad("a line that is not an option", ["-options_file", notopt], ["not_an_option.opts", "line 1"], ranklist=(1,))
if os.geteuid() != 0:  # root reads a chmod 000 file anyway
    unreadable = write("unreadable.opts", "-plane strain\n")
    os.chmod(unreadable, 0)
    bad("unreadable options file", BLOCK + ["-options_file", unreadable], [unreadable])
else:
    print("skip unreadable (chmod 000) options file: running as root")
# files that never end or block: /dev/zero and a FIFO hung the run (before); a
# binary file's line is shown without control bytes
fifo = os.path.join(W, "fifo.opts")
if not os.path.exists(fifo):
    os.mkfifo(fifo)
bad("/dev/zero as options file", BLOCK + ["-options_file", "/dev/zero"], ["options file", "/dev/zero", "not a regular file (a character device)"])
bad("a FIFO as options file", BLOCK + ["-options_file", fifo], ["options file", "fifo.opts", "not a regular file (a FIFO)"], ranklist=(1,))
binary = os.path.join(W, "binary.opts")
with open(binary, "wb") as f:
    f.write(bytes([0xc3, 0x01, 0x7f, 0x1b]) + b"abc" * 40 + b"\n")
bad("a binary options file", BLOCK + ["-options_file", binary], ["binary.opts", "line 1", "'????abcabc", "...' is not an option"], ranklist=(1,))
good("the same file twice is no cycle", BLOCK + ["-options_file", write("twice.opts", "-options_file %s\n-options_file %s\n" % (opts("block"), opts("block")))], ranklist=(1,))

# ---------- 4. unknown values of a choice ----------
for opt, choices, base in [("-plane", ["strain", "stress"], BLOCK), ("-contact_method", ["mortar", "nts"], PATCH),
                           ("-mesh_partitioner", ["metis", "petsc"], PATCH), ("-kkt_path", ["full", "condensed"], PATCH),
                           ("-contact_initial", ["gap", "closest", "all"], PATCH)]:
    bad("%s foo" % opt, base + [opt, "foo"], [opt, "'foo'"] + choices, ranklist=(1, 2) if opt == "-plane" else (1,))

# ---------- scenes from any directory; mesh names ----------
elsewhere = os.path.join(W, "elsewhere")
shutil.rmtree(elsewhere, ignore_errors=True)
os.makedirs(elsewhere)
good("a scene run from another directory", ["-options_file", opts("hertz"), "-mesh", "hertz_0.msh"], cwd=elsewhere)
with open(os.path.join(elsewhere, "block.msh"), "w") as f:
    f.write("$MeshFormat\n")  # a broken block.msh here must win over the build's
bad("a mesh name found in the current directory wins", ["-options_file", opts("block")], ["block.msh"], ranklist=(1,), cwd=elsewhere)
bad("-mesh_dir without the file", BLOCK + ["-mesh_dir", W], ["-mesh", "block.msh", W], ranklist=(1, 2))
# found (the check of its use comes after): without -adapt it has no effect
bad("-geo by name, from the source tree's meshes/", ["-options_file", opts("block"), "-mesh", mesh("block"), "-geo", "block.geo", "-output_dir", OUT], ["option -geo has no effect without -adapt"], ranklist=(1,), cwd=elsewhere)
bad("-geo that is nowhere", BLOCK + ["-geo", "nosuch.geo"], ["-geo", "nosuch.geo"], ranklist=(1,))

# ---------- -hertz_radius R1:R2: the effective radius R1 R2/(R1 + R2) ----------
def hertz_a(extra, name):
    summary = os.path.join(W, name + ".json")
    rc, out, err = run(HERTZ0 + extra + ["-summary", summary, "-output_vtu", "false", "-output_hdf5", "false"], check=False, timeout=TIMEOUT)
    return (json.load(open(summary))["hertz_a"] if rc == 0 else None), out


(a1, _), (a2, out2) = hertz_a([], "radius_1"), hertz_a(["-hertz_radius", "3:1.5"], "radius_3_1.5")
report(a1 is not None and a2 is not None and abs(a1 - a2) <= 1e-12 * a1, "-hertz_radius 3:1.5 is R = 1", "a = %s and %s" % (a1, a2))
report(re.search(r"radii 3\.? and 1\.5, effective radius R = R1 R2/\(R1 \+ R2\) = 1\.?\n", out2) is not None, "the output states the effective radius")

# ---------- 5. options that do nothing, values cut, files cut (issue 22 items 9, 10) ----------
# an option with no effect in the set-up is refused when typed, like a typo ...
for what, args, culprits in [
        ("-hertz_radius without -hertz", PATCH + ["-hertz_radius", "2"], ["option -hertz_radius has no effect without -hertz"]),
        ("-adapt_target without -adapt", BLOCK + ["-adapt_target", "0.1"], ["option -adapt_target has no effect without -adapt"]),
        ("-geo_setnumber without -adapt", BLOCK + ["-geo_setnumber", "n=8"], ["option -geo_setnumber has no effect without -adapt"]),
        ("-adapt_keep without -adapt", BLOCK + ["-adapt_keep", "last"], ["option -adapt_keep has no effect without -adapt"]),
        ("-mortar_basis dual -contact_method nts", PATCH + ["-mortar_basis", "dual", "-contact_method", "nts"], ["option -mortar_basis has no effect with -contact_method nts"]),
        ("-iterative_ksp_rtol off the iterative path", PATCH + ["-iterative_ksp_rtol", "1e-8"], ["option -iterative_ksp_rtol has no effect on the condensed path"]),
        ("-iterative_inexact off the iterative path", PATCH + ["-iterative_inexact", "0.2"], ["option -iterative_inexact has no effect on the condensed path"]),
        ("-iterative_prove on the tied path", PATCH + ["-contact_unilateral", "0", "-mortar_basis", "dual", "-kkt_path", "iterative", "-iterative_prove"], ["option -iterative_prove has no effect on the tied path"]),
        ("-pc_type on the condensed path", PATCH + ["-pc_type", "lu"], ["option -pc_type has no effect on the condensed path", "-kkt_path full"]),
        ("PETSc's MUMPS option on the condensed path", PATCH + ["-mat_mumps_cntl_1", "0.01"], ["option -mat_mumps_cntl_1 has no effect on the condensed path"]),
        ("-snes_rtol on the tied path", PATCH + ["-contact_unilateral", "0", "-snes_rtol", "1e-8"], ["option -snes_rtol has no effect on the tied path"]),
        ("-snes_type without contact", BLOCK + ["-snes_type", "vinewtonrsls"], ["option -snes_type has no effect on the linear path"]),
        ("-kkt_ldlt on the full path", PATCH + ["-kkt_path", "full", "-kkt_ldlt", "0"], ["option -kkt_ldlt has no effect on the full path"]),
        ("-contact_c without a contact pair", BLOCK + ["-contact_c", "1e10"], ["option -contact_c has no effect without a contact pair"]),
        ("-exact_angle without -exact uniform", PATCH + ["-exact", "none", "-exact_angle", "30"], ["option -exact_angle has no effect without -exact uniform"]),
        ("-estimator_target with -error_estimate false", PATCH + ["-error_estimate", "0", "-estimator_target", "0.1"], ["option -estimator_target has no effect with -error_estimate false"]),
        ("-geo_setnumber of a name the .geo lacks", BLOCK + ["-geo", "block.geo", "-adapt", "-geo_setnumber", "nosuch=3"], ["option -geo_setnumber: 'nosuch' is no name in", "block.geo"]),
        ("a PETSc option read at start-up, misspelt", PATCH + ["-log_vie"], ["option -log_vie is unknown", "did you mean -log_view?"]),
        ("a PETSc option read at the end, misspelt", PATCH + ["-options_lef"], ["option -options_lef is unknown", "did you mean -options_left?"])]:
    bad(what, args, culprits)


# ... and named on stdout when an options file set it (the command line may
# change what the file's scene needs): the run goes on
def noted(name, args, notes):
    for ranks in (1, 2):
        r = attempt(args + ["-output_dir", OUT, "-output_vtu", "0"], ranks)
        ok = r is not None and r[0] == 0 and not r[2] and all(n in r[1] for n in notes)
        report(ok, "%s [%d rank%s]" % (name, ranks, "s" if ranks > 1 else ""), "exit %s, stderr %s" % (r[0], " | ".join(r[2])[:300]) if r else "hang")


noted("hertz.opts (-mortar_basis dual) with -contact_method nts", HERTZ0 + ["-contact_method", "nts"],
      ["note: option -mortar_basis (set in %s) has no effect with -contact_method nts" % opts("hertz")])
noted("kkt_mumps.opts on the condensed path", PATCH + ["-options_file", opts("kkt_mumps")],
      ["note: option -%s (set in %s) has no effect on the condensed path" % (o, opts("kkt_mumps")) for o in ("ksp_type", "pc_type", "pc_factor_mat_solver_type")])

# a value is read whole, or refused (before: cut at 255 characters, "1" and
# 300 zeros read as 1e244): 1 and 300 zeros e-294 is 1e6, the S2 patch test exact
for ranks in (1, 2):
    summary = os.path.join(W, "long_value_%d.json" % ranks)
    rc, out, err = run(PATCH + ["-pressure", "upper_top:1" + "0" * 300 + "e-294", "-summary", summary, "-output_vtu", "0"], ranks=ranks, check=False, timeout=TIMEOUT)
    s = json.load(open(summary)) if rc == 0 else {}
    e = max(s.get("error", {}).get(k, 1) for k in ("sigma_yy_max_rel", "sigma_xx_max_rel", "sigma_xy_max_rel")) if s else 1
    report(rc == 0 and abs(s["contact_force"] / 1e6 - 1) < 1e-10 and e < 1e-10, "a 311-character pressure is read whole [%d rank%s]" % (ranks, "s" if ranks > 1 else ""),
           "exit %d, force %s, patch error %.1e" % (rc, s.get("contact_force"), e))
bad("a body name longer than the program holds", PATCH + ["-bodies", "lower,upper" + "x" * 300], ["option -bodies", "305 characters, longer than the 127 allowed"])
bad("a group name longer than the program holds", PATCH + ["-pressure", "x" * 200 + ":1e6"], ["option -pressure", "longer than 127 characters"])
bad("an output name longer than the program holds", PATCH + ["-output_name", "y" * 300], ["option -output_name", "300 characters, longer than"])
bad("a number longer than any value the program reads", PATCH + ["-lower_E", "1" + "0" * 70000], ["option -lower_E", "70001 characters, longer than the 65535 allowed"])
# an options file with a NUL byte: PETSc reads the line up to it
scene = open(opts("patch_uniform"), "rb").read()
with open(os.path.join(W, "nul.opts"), "wb") as f:
    f.write(scene + b"-output_name cut\0-exact none\n")
bad("an options file with a NUL byte", ["-options_file", os.path.join(W, "nul.opts"), "-output_dir", OUT], ["nul.opts", "line %d" % (scene.count(b"\n") + 1), "NUL byte"])
# more options than PETSc holds (512): one line (before: a 533-line trace)
many = [x for i in range(500) for x in ("-opt%d" % i, str(i))]
bad("500 more options", PATCH + many, ["different options given", "PETSc holds at most 500"])

# ---------- 6. unclear messages (issue 33 item 12) ----------
STACK_SPLIT = ["-options_file", opts("stack"), "-mesh", mesh("stack_split"), "-output_dir", OUT,
               "-contact_pairs", "mid_bottom:base_top,mid_bottom_b:base_top,top_bottom:mid_top"]
# before: "active set did not settle", "singular Jacobian", an equilibrium failure, or exit 0 (dual, condensed)
for extra in ([], ["-mortar_basis", "dual"], ["-kkt_path", "full"]):
    bad("two pairs sharing non-mortar edges %s" % " ".join(extra), STACK_SPLIT + extra,
        ["pair 1 'mid_bottom:base_top'", "pair 2 'mid_bottom_b:base_top'", "share 4 non-mortar edges"])
good("two pairs on the two halves of a curve", ["-options_file", opts("stack"), "-mesh", mesh("stack_split"), "-contact_pairs", "mid_bottom_a:base_top,mid_bottom_b:base_top,top_bottom:mid_top"])
# before: "active set did not settle in 50 steps (-snes_max_it)"
bad("-iterative_ksp_atol above the steps' residuals", HERTZ0 + ["-kkt_path", "iterative", "-iterative_ksp_atol", "1e10"], ["option -iterative_ksp_atol: 1e+10 stopped the Krylov solve"])
# before: the line cut at 2,065 characters, before the reason
for name, value, reason in (("3,000 digits", "1" + "0" * 3000, "(3001 characters)' is not a finite number"),
                            ("3,000 zeros after the point", "0." + "0" * 3000 + "1", "is nonzero but below double precision's range")):
    for ranks in (1, 2):
        r = attempt(PATCH + ["-lower_E", value], ranks)
        line, problems = refusal_problems(r[0], r[2], ["option -lower_E", reason])
        report(not problems and len(line) < 300, "a value of %s: the reason in one short line [%d rank%s]" % (name, ranks, "s" if ranks > 1 else ""), line)
# an integer option in e-notation that is an exact integer (docs give -adapt_max_dofs as 1e6)
good("-adapt_max_dofs 1e6", ["-options_file", opts("hertz_adapt"), "-adapt_max_dofs", "1e6", "-adapt_target", "0.05", "-output", "none"])
good("-snes_max_it 1e3", HERTZ0 + ["-snes_max_it", "1e3"])
bad("-adapt_max_dofs 1.5e0", ["-options_file", opts("hertz_adapt"), "-adapt_max_dofs", "1.5e0"], ["option -adapt_max_dofs", "'1.5e0' is not an integer"])
bad("-snes_max_it 1e30", HERTZ0 + ["-snes_max_it", "1e30"], ["option -snes_max_it", "'1e30' is larger than 2147483647"])
# before: "h5,,vtu" accepted, "," refused; -output h5 -output_hdf5 0 wrote nothing with exit 0
for value in ("h5,,vtu", ",", "h5,", ",h5"):
    bad("-output '%s'" % value, BLOCK + ["-output", value], ["option -output", "'%s' has an empty entry" % value], ranklist=(1,))
bad("-output ''", BLOCK + ["-output", ""], ["option -output: needs h5, vtu, csv, summary or none"], ranklist=(1,))
bad("-output h5 -output_hdf5 0", BLOCK + ["-output", "h5", "-output_hdf5", "0"], ["options -output h5 and -output_hdf5 0 contradict each other"])
bad("-output none -output_vtu 1", BLOCK + ["-output", "none", "-output_vtu", "1"], ["options -output none and -output_vtu 1 contradict each other"], ranklist=(1,))
good("-output h5 -output_hdf5 1 -output_vtu 0", BLOCK + ["-output", "h5", "-output_hdf5", "1", "-output_vtu", "0"], ranklist=(1,))
# several radii with several pairs: which pair each is for must be said (-hertz_pairs)
bad("-hertz_radius 1,1 with two pairs", ["-options_file", opts("roller"), "-hertz_radius", "1,1", "-output", "none"], ["option -hertz_radius: 2 radii", "-hertz_pairs"], ranklist=(1,))
bad("-hertz_radius 1,2 with one pair", HERTZ0 + ["-hertz_radius", "1,2"], ["option -hertz_radius: 2 radii for the scene's one pair", "R1:R2"], ranklist=(1,))
bad("-hertz_pairs 2 on a flat pair", ["-options_file", opts("indenter"), "-hertz", "-hertz_pairs", "2", "-output", "none"], ["option -hertz_pairs: pair 2 'block_bottom:base_top' is flat on flat"], ranklist=(1,))
# before: a misspelt option left the previous summary saying "status": "ok"
for ranks in (1, 2):
    d = os.path.join(W, "typo_%d" % ranks)
    shutil.rmtree(d, ignore_errors=True)
    r0 = attempt(BLOCK + ["-output_dir", d], ranks)
    r = attempt(BLOCK + ["-output_dir", d, "-contact_metod", "nts"], ranks)
    sm = json.load(open(os.path.join(d, "block_summary.json")))
    report(r0[0] == 0 and r[0] == 1 and sm["status"] == "error" and "mortar2d: error: " + sm["error"] == r[2][0],
           "a misspelt option after a good run: the summary there says status error and the line [%d rank%s]" % (ranks, "s" if ranks > 1 else ""), str(sm.get("error")))
d = os.path.join(W, "typo_fresh")
shutil.rmtree(d, ignore_errors=True)
r = attempt(BLOCK + ["-output_dir", d, "-contact_metod", "nts"], 1)
report(r[0] == 1 and not os.path.exists(d), "a misspelt option, no earlier run: nothing created")
# before: "no mesh file given (for example -mesh patch_uniform.msh)"
for args, culprits in (([], ["no mesh file given", "mortar2d -help lists the options"]), (["--help"], ["option --help is not mortar2d's", "mortar2d -help"]),
                       (["-h"], ["option -h is not mortar2d's", "mortar2d -help"])):
    bad("mortar2d %s" % " ".join(args), args, culprits, cwd=W)

T.finish()
