"""Options fuzz: random options and values on S2 (options/patch_uniform.opts,
patch_uniform.msh) and Hertz level 0 (options/hertz.opts, hertz_0.msh), on 1
and 2 ranks, must never crash, hang or exit 0 with a wrong answer.

The option names come from the program at test time: every option in the
sections of `mortar2d -help_petsc -bodies A,B` that are the program's own ("mortar2d:
...", "Material of body 'A'": -A_E, -A_nu become the scene's bodies' options),
the PC and KSP options of that help (PETSc's, after the program's), -snes_type and -snes_max_it (the README's
tables), -snes_rtol, -ksp_rtol, -ksp_max_it (the README: "any PETSc solver
option"), and misspellings of the program's names (PETSc ignores them). Each
run draws 1-4 of them, after an optional solver variant (-kkt_path full,
kkt_fieldsplit.opts, -snes_type vinewtonrsls, -contact_method nts,
-mortar_basis dual|standard, -q4_integration sri, -plane stress,
-contact_unilateral 0). A value is one of
  valid     in the documented domain;
  boundary  in the documented domain but extreme (nu = 0.4999999999999999,
            E = 1e-300, c = 1e300, -kkt_augment 1e12, ...);
  invalid   documented as bad input (README: E <= 0, nu outside (-1, 0.5),
            non-numbers - nan, inf, text - for numeric options, unknown values
            of a choice or a logical, a missing mesh or group), and any option
            typed (drawn or the variant's) that has no effect in the run's
            set-up (inert(): -hertz_radius without -hertz, -mortar_basis with
            nts, PETSc's KSP/PC options on the condensed path, ...): must exit 1;
  odd       out-of-domain values the documentation says nothing about (0, -1,
            1e308, 1e-308, huge integers, empty, garbage, 5000 characters,
            quotes, < >, a newline, no value at all): either exit is fine;
and keeps of the scene its exact answer (same problem, any solver setting), or
only its load (materials, solver and contact parameters: the contact force
must still balance the applied load), or nothing (another load or geometry).
Checks on every run (each failure prints the command to reproduce it):
  hang      it ends within --timeout seconds;
  crash     exit code 0 or 1 (no signal, no other code);
  stderr    exit 1: stderr is exactly one non-empty line "mortar2d: error: ...";
  trace     no PETSc traceback or signal message anywhere;  tmp: no .tmp file;
  accepted  no exit 0 with an invalid value;
  refused   no exit 1 when every value is valid and keeps the answer;
  summary   exit 0: the summary JSON exists and is strict JSON (no NaN);
  item1     its residual_rel / complementarity (issue 13 item 1), when present,
            within the summary's residual_tol / complementarity_tol, else
            RESIDUAL_TOL / COMPLEMENTARITY_TOL below;
  force     exit 0 and the load kept: the vertical contact force = the load
            (S2: p x 1 m, Hertz: 0.43) to FORCE_TOL, or FORCE_TOL_LOAD with boundary or odd
            material/solver values;
  patch     exit 0, S2, mortar, -exact uniform, answer kept: stress error below
            PATCH_TOL of p.
Notes (printed, not failures): an error line that names neither the one invalid
option nor its value, stderr output on exit 0, summaries without the item-1
keys.

  /usr/bin/python3 tests/test_options_fuzz.py [--seed N] [--count N] [--jobs N]
        [--timeout S] [--only I,J,...]"""
import argparse
import json
import math
import os
import random
import re
import shlex
import shutil
import sys
import time
from collections import Counter, defaultdict
from concurrent.futures import ThreadPoolExecutor

from m2d import EXE, MPI_ENV, command, launch, mesh, opts, run, workdir

RESIDUAL_TOL = 1e-8          # |K u + C^T lambda - f| / |f| when the summary states none
COMPLEMENTARITY_TOL = 1e-8   # scaled complementarity when the summary states none
FORCE_TOL = 1e-8             # contact force against the applied load, relative
FORCE_TOL_LOAD = 1e-6        # the same when a material or solver value is extreme (odd)
PATCH_TOL = 1e-6             # S2 stress error / p (mortar, -exact uniform)
PREFIX = "mortar2d: error: "

ap = argparse.ArgumentParser()
ap.add_argument("--seed", type=int, default=20250613)
ap.add_argument("--count", type=int, default=320)
ap.add_argument("--jobs", type=int, default=2)
ap.add_argument("--timeout", type=float, default=60)
ap.add_argument("--only", default="", help="run only these run numbers (comma separated)")
ARGS = ap.parse_args()

W = workdir("options_fuzz")
NOVALUE = None               # the option given alone (a flag)
VALID, BOUNDARY, INVALID, ODD = "valid", "boundary", "invalid", "odd"

SCENES = {
    "S2": dict(opts=opts("patch_uniform"), mesh=mesh("patch_uniform"), bodies=("lower", "upper"), E=1e9,
               load=1e6, pair=("upper_bottom", "lower_top"), dirichlet="lower_bottom:y,lower_origin:x,lower_left:x,upper_left:x",
               pressure="upper_top:1e6", other_mesh=mesh("hertz_0"),
               two_files=mesh("patch_uniform_lower") + "," + mesh("patch_uniform_upper"), exact="uniform", c=2.7e10),
    "H0": dict(opts=opts("hertz"), mesh=mesh("hertz_0"), bodies=("cylinder", "block"), E=200.0,
               load=0.43, pair=("cylinder_arc", "block_top"), dirichlet="cylinder_axis:x,block_axis:x,block_bottom:xy",
               pressure="cylinder_top:0.43", other_mesh=mesh("patch_uniform"), two_files=None, exact="none", c=1e5),
}
VARIANTS = [[], ["-kkt_path", "full"], ["-options_file", opts("kkt_fieldsplit")], ["-snes_type", "vinewtonrsls"],
            ["-contact_method", "nts"], ["-mortar_basis", "dual"], ["-mortar_basis", "standard"],
            ["-q4_integration", "sri"], ["-plane", "stress"], ["-contact_unilateral", "0"]]

# values of no documented meaning for any option
LONG = "x" * 5000
GARBAGE = ["garbage", "'quoted'", '"1e6"', "<1>", "a<b>c", "a b", "line1\nline2", LONG, "9" * 400, "%s%d%n", "\\", "::", ","]
NONFINITE = ["nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e400", "-1e400"]
EXTREME = ["0", "-1", "1e308", "-1e308", "1e-308", "4.9e-324", "-0", "0x1p3"]
HUGE_INT = ["2147483647", "2147483648", "-2147483649", "9223372036854775807", "9223372036854775808", "99999999999999999999"]


# ---------------------------------------------------------------- what the program documents
# the program's sections the fuzz leaves alone (the iterative path, the
# estimator and the adaptive loop have their own tests)
NOT_FUZZED = ("mortar2d: solver paths (-kkt_path iterative)", "mortar2d: error estimate", "mortar2d: adaptive meshes")


def documented_options():
    """(program options, per-body option suffixes, PETSc PC/KSP options with their
    choices) from -help; the per-body ones as '_E', '_nu' (for -A_E, -A_nu)."""
    rc, out, err = run(["-help_petsc", "-bodies", "A,B"], check=False, timeout=120)
    own, body, petsc = [], [], {}
    section = None
    for line in (out + err).splitlines():
        if line.startswith("-----"):
            section = "title"
            continue
        if section == "title":
            section = ("other" if line.startswith(NOT_FUZZED) else "own" if line.startswith("mortar2d") else "body" if line.startswith("Material of body 'A'")
                       else "petsc" if line.startswith(("Preconditioner (PC)", "Krylov Method (KSP)")) else "other")
            continue
        m = re.match(r"^\s+(-[A-Za-z][\w]*)", line)
        if not m or section in (None, "other"):
            continue
        name = m.group(1)
        if section == "own":
            own.append(name)
        elif section == "body" and name.startswith("-A_"):
            body.append(name[2:])
        elif section == "petsc":
            ch = re.search(r"\((?:choose )?one of\) ([^(]*)", line)
            petsc[name] = ch.group(1).split() if ch else []
    if not own or not body:
        print("FAIL -help did not list the program's options (exit %s):\n%s" % (rc, (out + err)[-2000:]))
        raise SystemExit(1)
    return own, body, petsc


# ---------------------------------------------------------------- values
# What a value keeps of the scene: ANSWER (the exact answer: same problem, and a
# solver setting that must not change the solution), LOAD (the load and the
# supports, so the contact force must still balance the load: materials,
# solver settings, contact parameters), or nothing (None: the problem changed).
ANSWER, LOAD = "answer", "load"
RANK = {None: 0, LOAD: 1, ANSWER: 2}


def v(value, klass, keeps=None):
    return (value, klass, keeps)


def real_values(valid, odd=(), invalid=(), odd_keeps=None, boundary=(), boundary_keeps=LOAD):
    """valid: [(value, keeps)]; boundary: in the domain but extreme; non-numbers
    are invalid, the universal extremes odd."""
    return ([v(x, VALID, k) for x, k in valid] + [v(x, BOUNDARY, boundary_keeps) for x in boundary]
            + [v(x, ODD, odd_keeps) for x in list(odd) + EXTREME]
            + [v(x, INVALID) for x in list(invalid) + NONFINITE + ["abc", "", "1e", "1,5", "1.2.3", "garbage", LONG]]
            + [v(NOVALUE, INVALID)])


def int_values(valid, odd=(), odd_keeps=LOAD, boundary=()):
    return ([v(x, VALID, ANSWER) for x in valid] + [v(x, BOUNDARY, LOAD) for x in boundary]
            + [v(x, ODD, odd_keeps) for x in list(odd) + ["0", "-1", "1e3"] + HUGE_INT]  # 1e3: the program's read it, PETSc's not
            + [v(x, INVALID) for x in ["abc", "1.5", "2.5e0", "", "nan", "inf", "0x10", LONG]] + [v(NOVALUE, INVALID)])


def bool_values(keeps=ANSWER):
    return ([v(x, VALID, keeps) for x in ("0", "1", "true", "false", "yes", "no", NOVALUE)]
            + [v(x, ODD, keeps) for x in ("TRUE", "No", "on", "off")]
            + [v(x, INVALID) for x in ("maybe", "2", "tru", "-1", "nan", "garbage", LONG)])


def choice_values(valid, odd=(), odd_keeps=LOAD):
    """valid: [(value, keeps)]; anything else is an unknown value (invalid),
    except spellings of a valid value (case, a trailing blank, a prefix): odd."""
    first = valid[0][0]
    return ([v(x, VALID, k) for x, k in valid] + [v(x, ODD, odd_keeps) for x in odd]
            + [v(x, ODD, LOAD) for x in [first.upper(), first + " ", first[:3]]]
            + [v(x, INVALID) for x in ["foo", "", "none_of_these", "1", LONG, "line1\nline2"]] + [v(NOVALUE, INVALID)])


def string_values(valid=(), odd=(), invalid=(), odd_keeps=None):
    return ([v(x, VALID, k) for x, k in valid] + [v(x, ODD, odd_keeps) for x in list(odd) + GARBAGE + ["", NOVALUE]]
            + [v(x, INVALID) for x in invalid])


def known_values(name, sc):
    """What the fuzz knows about a program option in scene sc; None: unknown option."""
    b0, b1 = sc["bodies"]
    nm, mo = sc["pair"]
    E, c, load = sc["E"], sc["c"], sc["load"]
    pg = sc["pressure"].split(":")[0]
    s2 = sc is SCENES["S2"]
    A, L = ANSWER, LOAD
    table = {
        "-mesh": string_values([(sc["mesh"], A)] + ([(sc["two_files"], A)] if sc["two_files"] else []),
                               odd=[sc["mesh"] + "," + sc["mesh"]],
                               invalid=[sc["other_mesh"], W, os.path.join(W, "nosuch.msh"), "garbage.msh"]),
        "-mesh_scale": real_values([("1", A), ("1000", None), ("1e-3", None)]),
        "-mesh_partitioner": choice_values([("metis", A), ("petsc", A)]),
        "-mesh_check": bool_values(),
        "-bodies": string_values([("%s,%s" % (b0, b1), A), ("%s,%s" % (b1, b0), A)], odd=[b0, b1, "%s,%s,%s" % (b0, b1, b0)],
                                 invalid=["nosuch", "%s,nosuch" % b0]),
        "-plane": choice_values([("strain", A), ("stress", A)]),
        "-q4_integration": choice_values([("full", A), ("sri", A)]),
        "-dirichlet": string_values([(sc["dirichlet"], A)], odd=[sc["dirichlet"] + ",%s:xy" % mo],
                                    invalid=["nosuch:x", "%s:z" % mo, "%s:x:abc" % mo, "%s:x:nan" % mo, "%s:x:inf" % mo, ":x", "%s" % mo]),
        "-pressure": string_values([(sc["pressure"], A)], odd=["%s:%g" % (pg, 2 * load), sc["pressure"] + ":0:0", pg + ":1e308", pg + ":0"],
                                   invalid=["nosuch:1", pg + ":abc", pg + ":nan", pg + ":inf", pg]),
        "-traction": string_values([("%s:0:0" % pg, A)], odd=["%s:1:0" % pg, "%s:0:1e308" % pg],
                                   invalid=["nosuch:0:0", "%s:0" % pg, "%s:0:nan" % pg, "%s:0:inf" % pg]),
        "-exact": choice_values([("none", A), ("uniform", A)], odd=["mms"], odd_keeps=None),
        # README: "auto" or > 0; -mms_amplitude non-zero
        "-exact_p": real_values([("auto", A)] + ([("1e6", A)] if s2 else [("1", L)]), invalid=["0", "-1"], odd_keeps=L),
        "-mms_amplitude": real_values([("0.001", A), ("1", A)], invalid=["0"], odd_keeps=A),
        "-contact_nonmortar": string_values([(nm, A)], odd=[mo, b0], invalid=["nosuch"]),
        "-contact_mortar": string_values([(mo, A)], odd=[nm, b0], invalid=["nosuch"]),
        "-contact_method": choice_values([("mortar", A), ("nts", A)]),
        # tied contact (false) closes every candidate: S2's answer, Hertz's load
        "-contact_unilateral": bool_values(A if s2 else L),
        "-contact_c": real_values([("auto", A)], invalid=["0", "-1"], boundary=["%g" % (c * 1e-3), "%g" % c, "%g" % (c * 1e3), "1e-300", "1e300"], odd_keeps=L),
        "-contact_initial": choice_values([("gap", A), ("closest", A), ("all", A)]),
        "-contact_monitor": bool_values(),
        "-hertz": bool_values(),
        "-hertz_radius": real_values([("1", A), ("2", A), ("1:5", None)], odd_keeps=A),  # R1:R2: two cylinders
        "-hertz_load": real_values([("auto", A), ("0.86", A)], invalid=["0", "-1"], odd_keeps=A),
        "-mortar_basis": choice_values([("standard", A), ("dual", A)]),
        "-contact_reach": real_values([("auto", A), ("0.5", A), ("10", A)], invalid=["0", "-1"], boundary=["1e-3", "1e-12", "1e300"], odd_keeps=L),
        "-kkt_mat": choice_values([("aij", A)], odd=["nest"], odd_keeps=A),
        "-kkt_path": choice_values([("full", A)], odd=["condensed"], odd_keeps=A),
        "-kkt_ordering": choice_values([("metis", A), ("mumps", A), ("auto", A)]),
        "-kkt_ldlt": bool_values(),
        "-mat_mumps_icntl_4": int_values(["0", "1", "2"], odd=["3", "4", "6"]),
        "-mat_mumps_icntl_7": int_values(["0", "2", "5", "7"], odd=["1", "3", "4", "6", "8"]),
        "-mat_mumps_icntl_8": int_values(["0", "77"], odd=["-2", "1", "7", "8", "9"]),
        "-mat_mumps_icntl_14": int_values(["20", "50", "200"], boundary=["1", "100000"]),
        "-mat_mumps_icntl_58": int_values(["1", "2"], odd=["3"]),
        # README: K + w s C^T C, "same solution" (exact at the solution) for any w >= 0
        "-kkt_augment": real_values([("0", A), ("1", A), ("10", A)], boundary=["1e6", "1e12", "1e300"], odd_keeps=L),
        "-output_dir": string_values([("out2", A), ("garbage", A)], odd=["a/b/c", "out dir", "<1>", "'q'", "afile/sub"], odd_keeps=A),
        "-output_name": string_values([("sol", A), ("x.y", A)], odd=["a/b", "<1>", "'q'"], odd_keeps=A),
        "-output_vtu": bool_values(),
        "-output_hdf5": bool_values(),
        "-summary": string_values([("s2.json", A)], odd=["sub/s.json", "<1>.json", "afile/s.json"], odd_keeps=A),
        "-snes_type": choice_values([("newtonls", A), ("vinewtonrsls", A)], odd=["vinewtonssls", "newtontr", "ksponly", "nrichardson"]),
        "-snes_max_it": int_values(["50", "1000"], boundary=["1", "2", "5"]),
    }
    # the strain check (verify.h): a body 10 or 1000 times softer may strain
    # past -strain_limit (Hertz at E/10 turns by 0.14 rad), an extreme value
    table["-strain_limit"] = real_values([("0.1", A), ("0.5", A), ("1e300", A)], invalid=["0", "-1"], odd_keeps=L)
    for b in (b0, b1):
        table["-%s_E" % b] = real_values([("%g" % (E * f), A) for f in (1, 3, 1e3)],
                                         boundary=["%g" % (E * 1e-3), "%g" % (E * 0.1), "1e-300", "1e300", "1e-30", "1e30", "4.9e-324", "1.7976931348623157e308"],
                                         invalid=["0", "-1", "-1e9", "-0"], odd_keeps=L)
        table["-%s_nu" % b] = real_values([(x, A) for x in ("-0.5", "0", "0.25", "0.3", "0.45", "0.49")],
                                          boundary=["-0.999999", "-0.9999999999999999", "0.499999", "0.4999999999999999"],
                                          invalid=["0.5", "-1", "0.7", "1", "-2", "1e308"], odd_keeps=L)
    if name not in table:
        return None
    # the universal extremes overlap some options' own values: those win
    seen = {}
    for x in table[name]:
        if x[0] not in seen or seen[x[0]][1] == ODD:
            seen[x[0]] = x
    return list(seen.values())


def generic_values(choices=(), keeps=LOAD):
    """An option the fuzz has no table for (a PETSc solver option, or one added
    to the program later: keeps=None): its documented choices and the
    universal values, all odd."""
    return [v(x, ODD, keeps) for x in list(choices) + EXTREME + NONFINITE + HUGE_INT + GARBAGE + ["", NOVALUE]]


def misspell(name, rng, known):
    """A near miss of an option name that is no option (PETSc ignores it)."""
    for _ in range(50):
        s = list(name[1:])
        k = rng.randrange(len(s))
        how = rng.randrange(4)
        if how == 0 and len(s) > 2:
            del s[k]
        elif how == 1:
            s.insert(k, s[k])
        elif how == 2 and k + 1 < len(s):
            s[k], s[k + 1] = s[k + 1], s[k]
        else:
            s.insert(k, rng.choice("_xqz"))
        cand = "-" + "".join(s)
        if re.match(r"^-[A-Za-z]\w*$", cand) and cand.lower() not in known:
            return cand
    return "-" + name[1:] + "_zz"


# ---------------------------------------------------------------- one run
CLASS_WEIGHTS = {VALID: 0.45, BOUNDARY: 0.15, ODD: 0.2, INVALID: 0.2}
# README: -snes_type, -snes_max_it in the options tables; "any PETSc solver option"
README_PETSC = ["-snes_type", "-snes_max_it"]
SOLVER_EXTRA = ["-snes_rtol", "-ksp_rtol", "-ksp_max_it"]


def pick(vals, rng):
    """A value: first its class (mostly valid, so that most runs get to the
    answer checks), then one of the class."""
    by = defaultdict(list)
    for x in vals:
        by[x[1]].append(x)
    classes = [k for k in (VALID, BOUNDARY, ODD, INVALID) if by[k]]
    k = rng.choices(classes, [CLASS_WEIGHTS[c] for c in classes])[0]
    return rng.choice(by[k])


def draw(i, rng, own, body, petsc, known):
    scene = "S2" if i % 2 == 0 else "H0"
    ranks = 1 if (i // 2) % 2 == 0 else 2
    sc = SCENES[scene]
    names = own + ["-%s%s" % (b, s) for b in sc["bodies"] for s in body] + README_PETSC
    variant = rng.choice(VARIANTS) if rng.random() < 0.5 else []
    drawn = []
    for _ in range(rng.randint(1, 4)):
        r = rng.random()
        if r < 0.1:
            name = misspell(rng.choice(names), rng, known)
            # README (issue 13 item 4): an unknown option is an error naming it
            vals = [v(x, INVALID) for x in ("1", "0", "garbage", "", NOVALUE)]
        elif r < 0.2:
            name = rng.choice(sorted(petsc) + SOLVER_EXTRA)
            vals = generic_values(list(petsc.get(name, [])) + (["1e-2", "0.5", "1", "2"] if name in SOLVER_EXTRA else []))
        else:
            name = rng.choice(names)
            vals = known_values(name, sc) or generic_values(keeps=None)
        value, klass, keeps = pick(vals, rng)
        drawn.append((name, value, klass, keeps))
    return dict(i=i, scene=scene, ranks=ranks, variant=variant, drawn=drawn)


def effective(spec):
    """The drawn options as the program sees them (the last of a name wins)."""
    eff = {}
    for name, value, klass, keeps in spec["drawn"]:
        eff[name] = (value, klass, keeps)
    return eff


def keeps_of(spec, eff):
    """What the run keeps of the scene: the least any option keeps (tied
    contact keeps only Hertz's load)."""
    k = [keeps for _, _, keeps in eff.values()]
    if spec["scene"] == "H0" and spec["variant"] == ["-contact_unilateral", "0"]:
        k.append(LOAD)
    return min(k + [ANSWER], key=RANK.get)


def argv(spec, rundir):
    sc = SCENES[spec["scene"]]
    a = ["-options_file", sc["opts"]] + spec["variant"] + [
        "-mesh", sc["mesh"], "-output_dir", os.path.join(rundir, "out"), "-summary", os.path.join(rundir, "summary.json"),
        "-output_vtu", "0", "-output_hdf5", "0", "-contact_monitor", "0"]
    for name, value, _, _ in spec["drawn"]:
        a += [name] if value is NOVALUE else [name, value]
    return a


def run_one(spec):
    d = os.path.join(W, "runs", "%03d" % spec["i"])
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    with open(os.path.join(d, "afile"), "w") as f:
        f.write("a regular file, not a directory\n")
    cmd = command(argv(spec, d), spec["ranks"])
    r = launch(cmd, timeout=ARGS.timeout, cwd=d)
    res = dict(spec, dir=d, cmd=cmd, rc=r.rc, stdout=r.stdout, stderr=r.stderr, wall=r.wall)
    res.update(judge(spec, r, d))
    return res


def summary_path(spec, d):
    eff = effective(spec)
    if "-summary" not in eff:
        return os.path.join(d, "summary.json")
    value = eff["-summary"][0]
    return os.path.join(d, value) if value else None     # empty or no value: no summary


def strict_json(path):
    def bad(c):
        raise ValueError("non-finite number %s" % c)
    with open(path) as f:
        return json.loads(f.read(), parse_constant=bad)


def typed(spec):
    """Every option the run's command line gives after the scene file: the
    variant's, then the drawn ones (the last of a name wins)."""
    t, v = {}, spec["variant"]
    for i, x in enumerate(v):
        if x.startswith("-") and x != "-options_file":
            t[x.lower()] = v[i + 1] if i + 1 < len(v) else NOVALUE
    for name, value, _, _ in spec["drawn"]:
        t[name.lower()] = value
    return t


def inert(spec):
    """The typed options that have no effect in the run's set-up: the program
    refuses them like a typo (optcheck.h). A rule is applied only when the
    values it depends on are clear (a valid spelling)."""
    t = typed(spec)
    scene_file = {"S2": {"-hertz": "0", "-exact": "uniform"}, "H0": {"-hertz": "1", "-exact": "none"}}[spec["scene"]]

    def boolean(name, default):
        x = t.get(name, default)
        if x is NOVALUE or str(x).lower() in ("1", "true", "yes", "on"):
            return True
        return False if str(x).lower() in ("0", "false", "no", "off") else None

    def choice(name, default, choices):
        x = t.get(name, default)
        return x.lower() if isinstance(x, str) and x.lower() in choices else None

    fieldsplit = any("kkt_fieldsplit" in str(x) for x in spec["variant"])
    out = []
    if boolean("-hertz", scene_file["-hertz"]) is False:
        out += ["-hertz_radius", "-hertz_load"]
    exact = choice("-exact", scene_file["-exact"], ("none", "uniform", "mms"))
    if exact in ("none", "mms"):
        out += ["-exact_p", "-exact_angle"]
    if exact in ("none", "uniform"):
        out += ["-mms_amplitude"]
    if choice("-contact_method", "mortar", ("mortar", "nts")) == "nts":
        out += ["-mortar_basis"]
    unilateral = boolean("-contact_unilateral", "1")
    kkt_path = choice("-kkt_path", None, ("full", "condensed", "iterative"))
    kkt_mat = "nest" if fieldsplit else choice("-kkt_mat", "aij", ("aij", "nest"))
    snes = choice("-snes_type", "newtonls", ("newtonls", "vinewtonrsls"))
    if "-kkt_path" in t and kkt_path is None:
        return [n for n in out if n in t]
    if kkt_path == "iterative":
        out += ["-kkt_mat", "-kkt_ordering"] + [n for n in t if n.startswith("-mat_mumps_")]
    own_step = [n for n in t if n.startswith(("-ksp_", "-pc_", "-mat_mumps_")) and not re.search(r"_view|_monitor|_converged_reason", n)
                and n not in ("-mat_mumps_icntl_4", "-mat_mumps_icntl_7", "-mat_mumps_icntl_8", "-mat_mumps_icntl_14", "-mat_mumps_icntl_58")]
    if unilateral is False:  # the tied path: one KKT solve
        out += ["-contact_c", "-contact_initial", "-snes_type", "-snes_max_it", "-snes_rtol", "-kkt_ldlt", "-kkt_condensed_max"]
        out += ["-kkt_path"] if kkt_path in ("full", "condensed") else own_step if kkt_path == "iterative" else []
        return [n for n in out if n in t]
    if unilateral is None or kkt_mat is None or snes is None:
        return [n for n in out if n in t]
    forced = kkt_path is not None or kkt_mat == "nest" or snes == "vinewtonrsls"
    path = kkt_path if kkt_path in ("full", "iterative") else "full" if kkt_mat == "nest" or snes == "vinewtonrsls" else "condensed"
    if path != "condensed":
        out.append("-kkt_ldlt")
    if forced:
        out.append("-kkt_condensed_max")
    if path in ("condensed", "iterative"):  # the SNES's KSP is replaced by the path's own step solver
        out += own_step
    return [n for n in out if n in t]


def judge(spec, r, d):
    """Problems (failures, each starting with its tag) and notes of one run."""
    problems, notes = [], []
    eff = effective(spec)
    invalid = [(n, val) for n, (val, k, _) in eff.items() if k == INVALID]
    # an option with no effect in the set-up is refused (optcheck.h)
    invalid += [(n, typed(spec)[n]) for n in inert(spec) if n not in [x.lower() for x, _ in invalid]]
    # README: vinewtonrsls does not combine with -kkt_augment (refused with one line)
    snes = eff.get("-snes_type", (None,))[0] or ("vinewtonrsls" if "vinewtonrsls" in spec["variant"] else None)
    aug = eff.get("-kkt_augment", (None,))[0]
    if aug is None and any("kkt_fieldsplit" in str(x) for x in spec["variant"]):
        aug = "1"  # the fieldsplit options file sets -kkt_augment 1
    if snes == "vinewtonrsls" and aug not in (None, "0", "0.0"):
        try:
            if float(aug) > 0:
                invalid.append(("-kkt_augment", aug))
        except ValueError:
            pass
    all_valid = all(k == VALID for _, k, _ in eff.values())
    keeps = None if invalid else keeps_of(spec, eff)
    lines = [l for l in r.stderr.splitlines() if l.strip()]
    if r.timed_out:
        return dict(outcome="hang", problems=["hang: no exit within %g s" % ARGS.timeout], notes=notes)
    for bad in ("PETSC ERROR", "Caught signal", "Segmentation", "AddressSanitizer", "MPI_ABORT", "Traceback"):
        if bad in r.stdout or bad in r.stderr:
            problems.append("trace: output contains %r" % bad)
    tmp = [os.path.join(root, f) for root, _, files in os.walk(d) for f in files if ".tmp" in f]
    if tmp:
        problems.append("tmp: temporary files left: %s" % tmp[:3])
    if r.rc not in (0, 1):
        problems.append("crash: exit code %d%s" % (r.rc, " (signal %d)" % -r.rc if r.rc < 0 else ""))
        return dict(outcome="crash", problems=problems, notes=notes)
    if r.rc == 1:
        if len(lines) != 1 or not lines[0].startswith(PREFIX):
            problems.append("stderr: exit 1 but stderr is not one '%s' line (%d lines)" % (PREFIX.strip(), len(lines)))
        if all_valid and keeps == ANSWER:
            problems.append("refused: exit 1 although every option was valid")
        if len(invalid) == 1 and lines and all(k in (VALID, INVALID) for _, k, _ in eff.values()):
            n, val = invalid[0]
            if n.lstrip("-") not in lines[0] and not (val and len(val) < 200 and val in lines[0]):
                notes.append("error names neither %s nor its value" % n)
        return dict(outcome="rejected", problems=problems, notes=notes)
    # exit 0
    if lines:
        notes.append("stderr output on exit 0")
    if invalid:
        problems.append("accepted: exit 0 with invalid %s" % ", ".join("%s %r" % (n, short(x)) for n, x in invalid))
    sp = summary_path(spec, d)
    if sp is None:
        notes.append("no summary requested")
        return dict(outcome="ran", problems=problems, notes=notes)
    try:
        s = strict_json(sp)
    except (OSError, ValueError) as e:
        problems.append("summary: exit 0 but the summary %s is missing or not strict JSON: %s" % (os.path.relpath(sp, d), str(e)[:120]))
        return dict(outcome="ran", problems=problems, notes=notes)
    problems += item1(s, notes) + physics(spec, eff, s, keeps)
    return dict(outcome="ran", problems=problems, notes=notes, summary=s)


def item1(s, notes):
    """Equilibrium and complementarity of the answer, as the summary states them."""
    out = []
    tols = {"residual_rel": s.get("residual_tol", RESIDUAL_TOL), "complementarity": s.get("complementarity_tol", COMPLEMENTARITY_TOL)}
    if "contact_nodes" in s and not any(k in s for k in tols):
        notes.append("summary without residual_rel / complementarity")
    for k, tol in tols.items():
        if k in s and not (isinstance(s[k], (int, float)) and s[k] <= tol):
            if k == "residual_rel" and "backward_error_tol" in s and s["backward_error"] <= s["backward_error_tol"]:
                continue  # a factorization's answer, judged by its backward error (issue 33 item 2)
            out.append("item1: summary %s = %r above %g" % (k, s[k], tol))
    return out


def physics(spec, eff, s, keeps):
    """What the scene fixes without trusting the program: the contact force
    balances the load (the bodies' own equilibrium, whatever the material or
    the solver), and S2's uniform stress (mortar, any valid material)."""
    if keeps is None:
        return []
    sc = SCENES[spec["scene"]]
    out = []
    tol = FORCE_TOL if keeps == ANSWER else FORCE_TOL_LOAD
    # the vertical force on the non-mortar body (on Hertz's curved surface the
    # integral of the pressure differs from it by the normals' tilt: 0.43013)
    f = s.get("contact_force_y")
    if not isinstance(f, (int, float)) or not abs(abs(f) / sc["load"] - 1) <= tol:
        out.append("force: vertical contact force %r, not the load %g (to %g)" % (f, sc["load"], tol))
    method = value_of("-contact_method", eff, spec["variant"], "mortar")
    exact = value_of("-exact", eff, spec["variant"], sc["exact"])
    if keeps == ANSWER and spec["scene"] == "S2" and method == "mortar" and exact == "uniform":
        e = s.get("error", {})
        worst = max((e.get(k, math.inf) for k in ("sigma_yy_max_rel", "sigma_xx_max_rel", "sigma_xy_max_rel")), default=math.inf)
        if not worst <= PATCH_TOL:
            out.append("patch: S2 mortar stress error %r of p (> %g)" % (worst, PATCH_TOL))
    return out


def value_of(name, eff, variant, default):
    if name in eff:
        return eff[name][0]
    if name in variant:
        return variant[variant.index(name) + 1]
    return default


def short(x):
    if x is NOVALUE:
        return "(no value)"
    return x if len(x) <= 40 else x[:20] + "...(%d chars)" % len(x)


def repro(res):
    env = " ".join("%s=%s" % kv for kv in MPI_ENV.items())
    return "(mkdir -p %s && cd %s && touch afile && env %s %s)" % (res["dir"], res["dir"], env, shlex.join(res["cmd"]))


# ---------------------------------------------------------------- report
def category(res):
    """Failure category: the first problem's tag and the suspects, the options
    whose value was not a valid, answer-keeping one."""
    eff = effective(res)
    sus = sorted("%s[%s]" % (n, k) for n, (_, k, keeps) in eff.items() if k != VALID or keeps != ANSWER)
    if not sus:
        sus = sorted(eff) + (["variant " + " ".join(res["variant"][-2:])] if res["variant"] else [])
    return "%s | %s" % (res["problems"][0].split(":")[0], ", ".join(sus))


def report(results, t0):
    print("\noutcomes by scene and ranks (seed %d, %d runs, %.0f s):" % (ARGS.seed, len(results), time.time() - t0))
    print("  %-6s %5s %5s %9s %7s %6s %6s" % ("scene", "ranks", "runs", "rejected", "ran", "hang", "FAIL"))
    for scene in SCENES:
        for ranks in (1, 2):
            rs = [r for r in results if r["scene"] == scene and r["ranks"] == ranks]
            c = Counter(r["outcome"] for r in rs)
            print("  %-6s %5d %5d %9d %7d %6d %6d" % (scene, ranks, len(rs), c["rejected"], c["ran"], c["hang"],
                                                    sum(bool(r["problems"]) for r in rs)))
    print("\noutcomes by the class of the drawn values (a run counts once per class it drew):")
    for klass in (VALID, BOUNDARY, ODD, INVALID):
        rs = [r for r in results if any(k == klass for _, _, k, _ in r["drawn"])]
        c = Counter(r["outcome"] for r in rs)
        print("  %-8s %4d runs: %4d exit 0, %4d exit 1, %3d other; %3d failed" % (
            klass, len(rs), c["ran"], c["rejected"], c["crash"] + c["hang"], sum(bool(r["problems"]) for r in rs)))
    per = defaultdict(Counter)
    for r in results:
        for name, _, _, _ in r["drawn"]:
            per[name]["FAIL" if r["problems"] else r["outcome"]] += 1
    print("\noptions drawn (runs with it: exit 0 / exit 1 / failed):")
    print("  " + ", ".join("%s %d/%d/%d" % (n, c["ran"], c["rejected"], c["FAIL"]) for n, c in sorted(per.items())))
    notes = defaultdict(list)
    for r in results:
        for n in r["notes"]:
            notes[n].append(r)
    for n, rs in sorted(notes.items()):
        r = rs[0]
        print("note: %d runs: %s (e.g. run %03d: %s -> %s)" % (
            len(rs), n, r["i"], " ".join("%s %r" % (x, short(y)) for x, y, _, _ in r["drawn"]),
            r["stderr"].strip()[:200].replace("\n", " | ") or "exit %s" % r["rc"]))
    failed = [r for r in results if r["problems"]]
    tags = Counter(p.split(":")[0] for r in failed for p in r["problems"])
    if tags:
        print("\nfailed checks by kind: " + ", ".join("%s %d" % kv for kv in tags.most_common()))
    groups = defaultdict(list)
    for r in failed:
        groups[category(r)].append(r)
    if failed:
        print("\nFAILURES by category (%d runs); one command each to reproduce:" % len(failed))
    for cat, rs in sorted(groups.items(), key=lambda kv: -len(kv[1])):
        r = rs[0]
        print("\n[%d runs] %s\n  runs %s" % (len(rs), cat, " ".join("%03d" % x["i"] for x in rs[:40])))
        print("  e.g. run %03d (%s, %d rank%s): %s" % (r["i"], r["scene"], r["ranks"], "s" if r["ranks"] > 1 else "",
                                                      "; ".join(r["problems"])))
        print("  drawn: %s%s" % (" ".join("%s %r[%s]" % (n, short(x), k) for n, x, k, _ in r["drawn"]),
                                "  variant: " + " ".join(r["variant"]) if r["variant"] else ""))
        print("  stderr: %s" % (r["stderr"].strip()[-400:].replace("\n", " | ") or "(empty)"))
        print("  reproduce: %s" % repro(r))
    return len(failed)


def main():
    if not os.path.exists(EXE):
        print("FAIL executable %s does not exist (build first, or set M2D_EXE)" % EXE)
        return 1
    own, body, petsc = documented_options()
    known = {n.lower() for n in own + ["-snes_type", "-snes_max_it", "-help", "-options_file"] + list(petsc)}
    known |= {("-%s%s" % (b, s)).lower() for sc in SCENES.values() for b in sc["bodies"] for s in body}
    print("seed %d: %d runs; options from -help: %s; per body: %s; PETSc PC/KSP: %d" % (
        ARGS.seed, ARGS.count, " ".join(own), " ".join(body), len(petsc)), flush=True)
    rng = random.Random(ARGS.seed)
    specs = [draw(i, rng, own, body, petsc, known) for i in range(ARGS.count)]
    if ARGS.only:
        keep = {int(x) for x in ARGS.only.split(",")}
        specs = [s for s in specs if s["i"] in keep]
    shutil.rmtree(os.path.join(W, "runs"), ignore_errors=True)
    t0 = time.time()
    with ThreadPoolExecutor(max_workers=ARGS.jobs) as pool:
        results = list(pool.map(run_one, specs))
    for r in results:
        print("%s [%03d %s %dr] %s%s -> %s%s" % (
            "FAIL" if r["problems"] else "ok  ", r["i"], r["scene"], r["ranks"],
            " ".join("%s %r" % (n, short(x)) for n, x, _, _ in r["drawn"]),
            (" (variant %s)" % " ".join(r["variant"]) if r["variant"] else ""),
            "exit %s" % r["rc"], (": " + "; ".join(r["problems"])) if r["problems"] else ""))
        if not r["problems"]:
            shutil.rmtree(r["dir"], ignore_errors=True)
    nfail = report(results, t0)
    print("slowest runs: " + ", ".join("[%03d] %.1f s" % (r["i"], r["wall"]) for r in sorted(results, key=lambda r: -r["wall"])[:5]))
    print("%d passed, %d failed" % (len(results) - nfail, nfail))
    return 1 if nfail else 0


if __name__ == "__main__":
    sys.exit(main())
