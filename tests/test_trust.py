"""Trust: a run that exits 0 has checked its own answer, and the answer does not
depend on the units of the input.
 1. Separation is physics: a load that pulls a body held only by contact off
    its support stops with one line naming the body and the free motion (S2
    and Hertz pulled, condensed and full path, PDAS and VI, 1 and 2 ranks);
    bodies pulled apart while both stay supported give the right answer with 0
    active nodes and exit 0 (zero stress, gap = the prescribed opening).
 2. Scale invariance: S2 with E from 1e-20 to 1e20 (the load fixed) and with
    the coordinates in micrometres gives the same stresses / p to 1e-10, on 1
    and 2 ranks; Hertz level 1 with E x 1e12 and the load x 1e12 gives the same
    pressure error and half-width.
 3. Near-incompressible plane strain, nu up to 0.5 - 1e-16, full and sri
    integration, 1 and 2 ranks: either the right answer (patch test to the
    round-off the conditioning allows) or one line, and the same on both rank
    counts.
 4. Every exit 0 reports residual_rel and complementarity below the acceptance
    tolerance it states."""
import os

from m2d import HOOKS, check, hooks, mesh, opts, read_json, refusal_problems, run, solve, workdir

os.environ["OMPI_MCA_orte_execute_quiet"] = "1"
S2 = ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform"), "-output_vtu", "0", "-contact_monitor", "0"]
HZ = ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1"), "-output_vtu", "0", "-contact_monitor", "0"]


def one_line_error(tag, args, ranks):
    rc, out, err = run(args + ["-output_dir", workdir(tag)], ranks=ranks, check=False)
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    return rc, lines


def accepted(s):
    return s["residual_rel"] <= s["residual_tol"] and s["complementarity"] <= s["complementarity_tol"]


def patch_error(s):
    e = s["error"]
    return max(e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"])


# ---------------------------------------------------------------- 1. separation
pulled = [("S2 pulled", S2 + ["-pressure", "upper_top:-1e6"], "upper"),
          ("S2 pulled, full path", S2 + ["-pressure", "upper_top:-1e6", "-kkt_path", "full"], "upper"),
          ("S2 pulled, VI", S2 + ["-pressure", "upper_top:-1e6", "-snes_type", "vinewtonrsls"], "upper"),
          ("Hertz pulled", HZ + ["-pressure", "cylinder_top:-0.43", "-hertz", "0"], "cylinder"),
          ("Hertz pulled, full path", HZ + ["-pressure", "cylinder_top:-0.43", "-hertz", "0", "-kkt_path", "full"], "cylinder")]
for name, args, body in pulled:
    for ranks in (1, 2):
        rc, lines = one_line_error("trust_pulled", args, ranks)
        check(rc == 1 and len(lines) == 1 and ("body '%s' is held by nothing against translation in y" % body) in lines[0],
              "%s, %d rank(s): exit %d, one line: %s" % (name, ranks, rc, lines[-1] if lines else "(none)"))

# both bodies supported: the upper top pulled up by 0.01 (S2 has no initial gap)
for ranks in (1, 2):
    args = S2 + ["-pressure", "", "-exact", "none", "-output_name", "sol",
                 "-dirichlet", "lower_bottom:y,lower_origin:x,lower_left:x,upper_left:x,upper_top:y:0.01"]
    s = solve("trust_apart_%d" % ranks, args, ranks=ranks)
    check(s["active_nodes"] == 0 and abs(s["contact_force"]) == 0 and accepted(s),
          "supported bodies pulled apart, %d rank(s): 0 active nodes, no contact force, checks %.1e / %.1e" % (ranks, s["residual_rel"], s["complementarity"]))
    import csv
    with open(os.path.join(workdir("trust_apart_%d" % ranks), "sol_contact.csv")) as f:
        gaps = [float(r["gap"]) for r in csv.DictReader(f)]
    check(max(abs(g - 0.01) for g in gaps) < 1e-12, "supported bodies pulled apart, %d rank(s): gap = 0.01 at every node (%.1e)" % (ranks, max(abs(g - 0.01) for g in gaps)))

# a -contact_c far from E*/h^2 is named as the cause (before: "keeps cycling ...
# check the load direction and the supports", "did not settle", DIVERGED_FNORM_NAN)
for c in ("1e-20", "1e200"):
    for ranks in (1, 2):
        rc, lines = one_line_error("trust_c", HZ + ["-contact_c", c], ranks)
        check(rc == 1 and len(lines) == 1 and lines[0].startswith("mortar2d: error: active set ") and (": -contact_c %g is" % float(c)) in lines[0] and "times the automatic value" in lines[0],
              "Hertz with -contact_c %s, %d rank(s): one line naming -contact_c: %s" % (c, ranks, lines[-1] if lines else "(none)"))

# nodes beyond -contact_reach carry no multiplier: one that ends inside the
# other body fails the contact check (before: Hertz level 0 with -contact_reach
# 1e-6 exited 0 with 2 multipliers and a pressure 2.2 times off Hertz's)
for ranks in (1, 2):
    rc, lines = one_line_error("trust_reach", HZ + ["-contact_reach", "1e-6"], ranks)
    check(rc == 1 and len(lines) == 1 and "the answer fails its contact check: non-mortar node (" in lines[0] and "inside 'block_top' but carries no multiplier" in lines[0]
          and "raise -contact_reach" in lines[0], "Hertz with -contact_reach 1e-6, %d rank(s): one line: %s" % (ranks, lines[-1] if lines else "(none)"))
# the reach is stated in the user's units (before: S2's -contact_reach 1e-6 was
# reported as "within 5e-07", the reference length being 2)
rc, lines = one_line_error("trust_reach_gap", S2 + ["-mesh", mesh("patch_gap"), "-contact_reach", "1e-6", "-exact", "none"], 1)
check(rc == 1 and len(lines) == 1 and "the two surfaces are 0.01 apart where they face each other, more than -contact_reach 1e-06" in lines[0], "S2 with a gap and -contact_reach 1e-6: the line states the gap and 1e-06: %s" % (lines[-1] if lines else ""))
r1 = solve("trust_reach_ok", HZ + ["-contact_reach", "0.02"])
r0 = solve("trust_reach_auto", HZ)
check(abs(r1["pressure_l2_rel"] - r0["pressure_l2_rel"]) < 1e-9, "Hertz with -contact_reach 0.02 (all the contact zone within reach): the answer of the automatic reach (%.6e = %.6e)" % (r1["pressure_l2_rel"], r0["pressure_l2_rel"]))

# ---------------------------------------------------------------- 2. units
# the load scaled with E: strains of 1e-3, inside small-strain theory (S2 with
# E = 1e-20 under p = 1e6, a strain of 1e26, is refused now: section 6)
ref = None
for E in ("1e-20", "1e-10", "1", "1e9", "1e20"):
    p = 1e-3 * float(E)
    for ranks in (1, 2):
        s = solve("trust_E_%s_%d" % (E, ranks), S2 + ["-lower_E", E, "-upper_E", E, "-pressure", "upper_top:%r" % p], ranks=ranks)
        err = patch_error(s)
        check(err < 1e-10 and accepted(s), "S2, E = %s, p = E/1000, %d rank(s): stresses exact to %.1e of p, contact force %.12e" % (E, ranks, err, s["contact_force"]))
        check(abs(s["contact_force"] / p - 1) < 1e-10 and abs(s["strain_max"] / 1e-3 - 1) < 0.5, "S2, E = %s, %d rank(s): contact force = p x 1 m, strain %.2e" % (E, ranks, s["strain_max"]))
# bodies of very different moduli: ratio 1e15 (stiff body supported) is exact;
# beyond 1/eps one line up front, the same on 1 and 2 ranks (before: E ratio
# 1e19 gave "cycling" on 1 rank and "held by nothing" on 2, 1e309 a MUMPS
# INFOG(1) = -9 blamed on -mat_mumps_icntl_14); a soft support under a stiff
# body held by contact, the load scaled with the soft modulus: ratio 1e9 is
# right to round-off (issue 33 item 2: its |r| / |f| of 1.8e-6 was refused,
# its backward error is 1e-16) and ratio 1e12 fails its contact check, blamed
# on the moduli
for ranks in (1, 2):
    s = solve("trust_ratio15_%d" % ranks, S2 + ["-lower_E", "1e24"], ranks=ranks)
    check(patch_error(s) < 1e-10 and accepted(s), "S2, E 1e24 under 1e9, %d rank(s): exact to %.1e" % (ranks, patch_error(s)))
    s = solve("trust_ratio9_%d" % ranks, S2 + ["-lower_E", "1", "-pressure", "upper_top:1e-3"], ranks=ranks)
    check(patch_error(s) < 1e-5 and s["backward_error"] <= s["backward_error_tol"], "S2, E 1 under 1e9, p = 1e-3, %d rank(s): stresses right to %.1e (|r|/|f| %.1e, backward error %.1e)" % (ranks, patch_error(s), s["residual_rel"], s["backward_error"]))
for lowerE, extra, culprits in (("1e-10", [], ["-lower_E 1e-10", "-upper_E 1e+09", "differ by a factor 1e+19"]),
                                ("1e-300", [], ["-lower_E 1e-300", "differ by a factor 1e+309"]),
                                ("1e-3", ["-pressure", "upper_top:1e-6"], ["contact check", "moduli of 'lower' and 'upper' differ by a factor 1.0e+12", "-lower_E"])):
    got = {}
    for ranks in (1, 2):
        rc, lines = one_line_error("trust_ratio", S2 + ["-lower_E", lowerE] + extra, ranks)
        check(rc == 1 and len(lines) == 1 and all(c in lines[0] for c in culprits),
              "S2, -lower_E %s under 1e9, %d rank(s): one line naming %s: %s" % (lowerE, ranks, culprits, lines[-1] if lines else "(none)"))
        got[ranks] = lines[0].split(":")[2] if not extra else culprits[1]
    check(got[1] == got[2], "S2, -lower_E %s: the same diagnosis on 1 and 2 ranks" % lowerE)
# results that double precision cannot hold in the user's units: one line
# (before: a pressure of 1e-308 on E = 1e9 exited 0 with stresses wrong by
# 3.1e-4, its displacements being subnormal; a traction of 1e308 and a
# prescribed displacement of 1e300 ended in DIVERGED_FNORM_NAN); E = 1e-300
# with p = 1e-290 was a strain of 1e10: E = 1e-297 with p = 1e-300 is exact
for what, extra, culprits in (("pressure 1e-308", ["-pressure", "upper_top:1e-308"], ["stresses of about 1e-308", "displacements of about 1.41421e-317"]),
                              ("traction 1e308", ["-traction", "upper_top:1e6:1e308"], ["stresses of about 1e+308"]),
                              ("displacement 1e300", ["-dirichlet", "lower_bottom:y,lower_origin:x,lower_left:x,upper_left:x:1e300"], ["stresses of about inf"])):
    for ranks in (1, 2):
        rc, lines = one_line_error("trust_range", S2 + extra, ranks)
        check(rc == 1 and len(lines) == 1 and all(c in lines[0] for c in culprits + ["state the loads, moduli and lengths in other units"]),
              "S2 with a %s, %d rank(s): one line: %s" % (what, ranks, lines[-1] if lines else "(none)"))
s = solve("trust_E300", S2 + ["-lower_E", "1e-297", "-upper_E", "1e-297", "-pressure", "upper_top:1e-300"])
check(patch_error(s) < 1e-10 and abs(s["contact_force"] / 1e-300 - 1) < 1e-10 and accepted(s), "S2, E = 1e-297, p = 1e-300: exact to %.1e, force p x 1 m" % patch_error(s))
# the same on the paths that refactor each step: the active set does not
# settle and the moduli are named, or it settles and the lower body's strain
# (p / E = 1e6) is refused naming -lower_E - which of the two depends on the
# round-off of a factorization at a condition number of 1e9 x the mesh's
# (before: "did not settle in 50 steps (-snes_max_it)")
for extra in (["-kkt_path", "full"], ["-snes_type", "vinewtonrsls"]):
    for ranks in (1, 2):
        rc, lines = one_line_error("trust_ratio_full", S2 + ["-lower_E", "1"] + extra, ranks)
        named = len(lines) == 1 and ("the moduli of 'lower' and 'upper' differ by a factor 1.0e+09" in lines[0] or ("body 'lower' strains by" in lines[0] and "(-lower_E)" in lines[0]))
        check(rc == 1 and named, "S2, -lower_E 1 under 1e9, %s, %d rank(s): one line naming the moduli or the strain and -lower_E: %s" % (" ".join(extra), ranks, lines[-1] if lines else "(none)"))
for ranks in (1, 2):
    s = solve("trust_um_%d" % ranks, S2 + ["-mesh_scale", "1e-6"], ranks=ranks)
    check(patch_error(s) < 1e-10 and abs(s["contact_force"] / 1.0 - 1) < 1e-10,
          "S2 in micrometres (-mesh_scale 1e-6), %d rank(s): stresses exact to %.1e, contact force p x 1e-6 m = %.12e" % (ranks, patch_error(s), s["contact_force"]))
h1 = solve("trust_hertz_ref", HZ)
h2 = solve("trust_hertz_scaled", HZ + ["-cylinder_E", "2e14", "-block_E", "2e14", "-pressure", "cylinder_top:4.3e11"])
check(abs(h1["pressure_l2_rel"] - h2["pressure_l2_rel"]) < 1e-10 and abs(h1["half_width"] - h2["half_width"]) < 1e-12 and h1["iterations"] == h2["iterations"],
      "Hertz level 1 with E and the load x 1e12: pressure error %.6e = %.6e, half-width %.6f = %.6f, %d = %d steps"
      % (h1["pressure_l2_rel"], h2["pressure_l2_rel"], h1["half_width"], h2["half_width"], h1["iterations"], h2["iterations"]))

# ---------------------------------------------------------------- 3. near-incompressible
for nu in ("0.49", "0.4999", "0.4999999", "0.499999999", "0.4999999999", "0.49999999999999", "0.4999999999999999"):
    for integ in ("full", "sri"):
        outcome = {}
        for ranks in (1, 2):
            tag = "trust_nu_%s_%s_%d" % (nu, integ, ranks)
            args = S2 + ["-lower_nu", nu, "-upper_nu", nu, "-q4_integration", integ, "-output_name", "sol"]
            rc, out, err = run(args + ["-output_dir", workdir(tag), "-summary", os.path.join(workdir(tag), "s.json")], ranks=ranks, check=False)
            lines = [ln for ln in err.strip().splitlines() if ln.strip()]
            if rc == 0:
                import json
                with open(os.path.join(workdir(tag), "s.json")) as f:
                    s = json.load(f)
                # the round-off the conditioning allows: lambda/mu x 1e-16 x 100
                ratio = 2 * float(nu) / (1 - 2 * float(nu))
                err_p = patch_error(s)
                check(err_p < max(1e-10, 100 * ratio * 2.2e-16) and accepted(s), "nu = %s %s, %d rank(s): answer within round-off (%.1e of p, lambda/mu = %.1e)" % (nu, integ, ranks, err_p, ratio))
                outcome[ranks] = "answer"
            else:
                check(rc == 1 and len(lines) == 1 and lines[0].startswith("mortar2d: error: "), "nu = %s %s, %d rank(s): one line: %s" % (nu, integ, ranks, lines[-1] if lines else "(none)"))
                outcome[ranks] = lines[0] if lines else "?"
        check(outcome[1] == outcome[2], "nu = %s %s: the same diagnosis on 1 and 2 ranks (%s)" % (nu, integ, outcome[1][:90]))

# ---------------------------------------------------------------- 5. scenes users bring
# the S2 patch test turned by 30 degrees, held by rollers along its inclined
# edges (-dirichlet G:n) and checked in the turned frame (-exact_angle 30)
for ranks in (1, 2):
    s = solve("trust_incl_%d" % ranks, S2 + ["-mesh", mesh("patch_incl30"), "-dirichlet", "lower_bottom:n,lower_left:n,upper_left:n", "-exact_angle", "30"], ranks=ranks)
    check(patch_error(s) < 1e-10 and abs(s["contact_force"] / 1e6 - 1) < 1e-10 and accepted(s),
          "S2 turned by 30 degrees on inclined rollers, %d rank(s): exact to %.1e of p, force p x 1 m" % (ranks, patch_error(s)))
# the same held tangentially on the upper body's left edge: nothing holds it along the edge
rc, lines = one_line_error("trust_incl_t", S2 + ["-mesh", mesh("patch_incl30"), "-dirichlet", "lower_bottom:n,lower_left:n,upper_left:t", "-exact_angle", "30"], 1)
check(rc == 1 and len(lines) == 1 and "body 'upper' is held by nothing" in lines[0], "upper left edge held only along itself (G:t): one line: %s" % (lines[-1] if lines else ""))
# the lower body on a tangential support of its bottom and rollers on its left
# edge: both hold the same direction, the lower body (carrying the upper one)
# is free along the bottom's normal (-sin 30, cos 30); before, 1 rank named
# 'lower' and 2 ranks 'upper', both "in y"
for ranks in (1, 2):
    rc, lines = one_line_error("trust_incl_bt", S2 + ["-mesh", mesh("patch_incl30"), "-dirichlet", "lower_bottom:t,lower_left:n,upper_left:n", "-exact_angle", "30"], ranks)
    check(rc == 1 and len(lines) == 1 and "body 'lower' is held by nothing against translation along (-0.5000, 0.8660)" in lines[0],
          "bottom held only tangentially, %d rank(s): one line naming 'lower' and the free direction: %s" % (ranks, lines[-1] if lines else ""))
# rollers along axis-parallel edges are the plain supports: same answer as x/y
a = solve("trust_n_axis", S2 + ["-dirichlet", "lower_bottom:n,lower_origin:x,lower_left:n,upper_left:n"])
check(patch_error(a) < 1e-10, "S2 with G:n rollers on axis-parallel edges: exact to %.1e" % patch_error(a))
# two cylinders: Hertz with the effective radius R1 R2 / (R1 + R2)
two = ["-options_file", opts("hertz_two"), "-mesh", mesh("hertz_two_2"), "-output_vtu", "0", "-contact_monitor", "0"]
rc, out, err = run(two + ["-output_dir", workdir("trust_two")], check=False)
check(rc == 0 and "effective radius R = R1 R2/(R1 + R2) = 0.666667" in out, "two cylinders R1 = 1, R2 = 2: the run states the effective radius")
s = solve("trust_two", two)
s1 = solve("trust_two_r1", two + ["-hertz_radius", "1"])
check(s["pressure_l2_rel"] < 3e-2 and s1["pressure_l2_rel"] > 5 * s["pressure_l2_rel"] and abs(s["hertz_radius"] - 2 / 3) < 1e-12,
      "two cylinders, level 2: pressure error %.2e against Hertz with R = 2/3 (%.2e with R1 alone)" % (s["pressure_l2_rel"], s1["pressure_l2_rel"]))
# the condensed path's dense interface (about 6 G^2 doubles per rank) larger
# than the node's free memory: one line naming the path and the way out, and
# no output, instead of the kernel killing the run without a word (an
# adaptive Hertz run with 22,575 multipliers was killed at 24 GB). The free
# memory is set by the test hook M2D_TEST_MEMORY_MB; Hertz level 1 has 50
# multipliers (0.11 MB), 2 ranks 158 interface unknowns (1.1 MB per rank).
for ranks in ((1, 2) if hooks("the dense interface against the free memory (M2D_TEST_MEMORY_MB)") else ()):
    d = workdir("trust_dense_mem_%d" % ranks)
    rc, out, err = run(HZ + ["-output_dir", d], ranks=ranks, check=False, env={"M2D_TEST_MEMORY_MB": "0.01"})
    line, problems = refusal_problems(rc, [ln for ln in err.strip().splitlines() if ln.strip()], ["-kkt_path condensed", "dense interface", "-kkt_path full", "-kkt_path iterative"])
    check(not problems and not os.path.exists(os.path.join(d, "hertz.h5")), "dense interface larger than the free memory, %d rank(s): %s" % (ranks, "; ".join(problems) or line))
for path in ("full", "iterative") if HOOKS else ():
    rc, out, err = run(HZ + ["-kkt_path", path, "-output_dir", workdir("trust_dense_mem_" + path)], check=False, env={"M2D_TEST_MEMORY_MB": "0.01"})
    check(rc == 0, "the same memory with -kkt_path %s (no dense interface): runs, exit %d" % (path, rc))
# without -kkt_path, a contact surface longer than -kkt_condensed_max edges
# takes the full path (the condensed path's dense interface costs O(N^3) a
# step: README S5); -kkt_path condensed keeps it (the limit, set by an
# options file, then has no effect: a note; typed, an error); the answer is
# the same. Hertz level 1 has 56 non-mortar edges.
paths = {}
limit = os.path.join(workdir("trust_path_forced"), "limit.opts")
with open(limit, "w") as f:
    f.write("-kkt_condensed_max 50\n")
for tag, extra in (("default", []), ("auto_full", ["-kkt_condensed_max", "50"]), ("forced", ["-options_file", limit, "-kkt_path", "condensed"])):
    d = workdir("trust_path_" + tag)
    rc, out, err = run(HZ + extra + ["-output_dir", d, "-summary", os.path.join(d, "s.json")], check=False)
    s = read_json(os.path.join(d, "s.json")) if rc == 0 else {}
    paths[tag] = (s.get("kkt_path"), s.get("pressure_l2_rel"), "56 non-mortar edges, more than -kkt_condensed_max 50" in out)
check(paths["default"][0] == "condensed" and paths["forced"][0] == "condensed" and paths["auto_full"][0] == "full" and paths["auto_full"][2] and not paths["default"][2],
      "path by contact-surface length: default condensed, -kkt_condensed_max 50: full with its line, -kkt_path condensed: kept (%s)" % {k: v[0] for k, v in paths.items()})
check(all(v[1] is not None and abs(v[1] - paths["default"][1]) < 1e-8 for v in paths.values()), "the same pressure error on every path: %s" % [v[1] for v in paths.values()])
rc, lines = one_line_error("trust_path_typed", HZ + ["-kkt_condensed_max", "50", "-kkt_path", "condensed"], 1)
check(rc == 1 and len(lines) == 1 and "option -kkt_condensed_max has no effect with -kkt_path" in lines[0], "-kkt_condensed_max typed with -kkt_path: one line: %s" % (lines[-1] if lines else ""))

# ---------------------------------------------------------------- 6. issue 22 items 8-10
import json
import math
import shutil
import subprocess

import numpy as np
from m2d import SRC, read_h5

SUP = "lower_bottom:y,lower_origin:x,lower_left:x,upper_left:x"


def overlap_mesh(depth):
    """S2 with the upper body moved down by depth (gmsh, patch_uniform.geo's gap)."""
    out = os.path.join(workdir("trust_overlap"), "overlap_%g.msh" % depth)
    if not os.path.exists(out):
        subprocess.run([shutil.which("gmsh"), "-2", "-format", "msh41", "-v", "0", "-setnumber", "gap", repr(-depth),
                        os.path.join(SRC, "meshes", "patch_uniform.geo"), "-o", out], check=True)
    return out


def held(depth, extra=()):
    """S2 squeezed by an overlap held by supports: the strain is depth / height (1)."""
    return S2 + ["-mesh", overlap_mesh(depth), "-pressure", "", "-exact", "none", "-dirichlet", SUP + ",upper_top:y:0"] + list(extra)


# item 8: a strain check after the solve (verify.h): a warning on stdout above
# 1%, a refusal naming the body above -strain_limit (0.1)
for ranks in (1, 2):
    d = workdir("trust_strain_%d" % ranks)
    rc, out, err = run(held(0.002) + ["-output_dir", d, "-summary", os.path.join(d, "s.json")], ranks=ranks, check=False)
    s = read_json(os.path.join(d, "s.json"))
    check(rc == 0 and "warning:" not in out and abs(s["strain_max"] - 0.002) < 1e-9, "overlap 0.002 held by supports, %d rank(s): strain %.12f = 0.002, no warning" % (ranks, s["strain_max"]))
    rc, out, err = run(held(0.09) + ["-output_dir", d, "-summary", os.path.join(d, "s.json")], ranks=ranks, check=False)
    s = read_json(os.path.join(d, "s.json"))
    warn = [ln for ln in out.splitlines() if ln.startswith("warning:")]
    check(rc == 0 and len(warn) == 1 and "strains by 9%" in warn[0] and ("body 'lower'" in warn[0] or "body 'upper'" in warn[0]) and abs(s["strain_max"] - 0.09) < 1e-9,
          "overlap 0.09 (a 9%% strain), %d rank(s): solved, strain %.12f, one warning: %s" % (ranks, s["strain_max"], warn))
    rc, lines = one_line_error("trust_strain_15", held(0.15, ["-contact_reach", "0.2"]), ranks)
    check(rc == 1 and len(lines) == 1 and "strains by 15%" in lines[0] and "more than -strain_limit 0.1" in lines[0] and "small-strain theory does not hold" in lines[0],
          "overlap 0.15 (15%%), %d rank(s): one line naming the strain and -strain_limit: %s" % (ranks, lines[-1] if lines else "(none)"))
s = solve("trust_strain_limit", held(0.15, ["-contact_reach", "0.2", "-strain_limit", "0.2"]))
check(abs(s["strain_max"] - 0.15) < 1e-9 and accepted(s), "overlap 0.15 with -strain_limit 0.2: solved (the user's choice), strain %.12f" % s["strain_max"])
# S2 with E = 1e-20 under p = 1e6 (section 2's old scene: exit 0 before)
rc, lines = one_line_error("trust_strain_E", S2 + ["-lower_E", "1e-20", "-upper_E", "1e-20"], 1)
check(rc == 1 and len(lines) == 1 and "strains by 9.1e+27%" in lines[0], "S2 with E = 1e-20 under p = 1e6: one line: %s" % (lines[-1] if lines else ""))
# a soft punch (PETSc's option names are case-insensitive; punch.opts allows
# 0.5, its foundation turning by 0.3 rad): before, "raise -contact_reach"
for E, ranklist in (("0.1", (1,)), ("0.01", (1, 2))):
    for ranks in ranklist:
        rc, lines = one_line_error("trust_punch", ["-options_file", opts("punch"), "-Punch_E", E, "-contact_monitor", "0", "-output_vtu", "0"], ranks)
        check(rc == 1 and len(lines) == 1 and lines[0].startswith("mortar2d: error: body 'punch' strains by ") and "-strain_limit 0.5" in lines[0] and "-contact_reach" not in lines[0],
              "punch with -Punch_E %s, %d rank(s): one line naming the punch's strain: %s" % (E, ranks, lines[-1] if lines else "(none)"))
rc, out, err = run(["-options_file", opts("punch"), "-Punch_E", "1", "-contact_monitor", "0", "-output_vtu", "0", "-output_dir", workdir("trust_punch_1")], check=False)
check(rc == 0 and "warning: body 'punch' strains by" in out, "punch with -Punch_E 1 (as soft as its foundation): solved, with a warning naming the punch's strain")

# item 10: an interpenetration deeper than the reach (before: "never face each other")
for ranks in (1, 2):
    rc, lines = one_line_error("trust_overlap_25", held(0.25), ranks)
    check(rc == 1 and len(lines) == 1 and "'upper_bottom' lies up to 0.25 inside body 'lower', behind 'lower_top'" in lines[0] and "overlap by 25%" in lines[0] and "-contact_reach 0.1" in lines[0],
          "overlap 0.25, %d rank(s): one line naming the overlap: %s" % (ranks, lines[-1] if lines else "(none)"))

# item 10: inexact linear solves (before: "did not settle in 50 steps", "is every body held?")
BLOCK = ["-options_file", opts("block"), "-output_vtu", "0"]
for what, args, culprits in (("steps to -ksp_rtol 0.9", S2 + ["-kkt_path", "full", "-ksp_type", "gmres", "-pc_type", "jacobi", "-ksp_rtol", "0.9"],
                              ["active set did not settle after 50 steps", "solved only to -ksp_rtol 0.9", "needs exact steps"]),
                             ("a step past -ksp_max_it", S2 + ["-kkt_path", "full", "-ksp_type", "gmres", "-pc_type", "none", "-ksp_max_it", "3"],
                              ["linear solve in active-set step 1 failed", "stopped after 3 iterations (DIVERGED_ITS", "-ksp_max_it 3"]),
                             ("no contact, past -ksp_max_it", BLOCK + ["-ksp_type", "cg", "-pc_type", "none", "-ksp_max_it", "2"],
                              ["linear solve failed: -ksp_type cg stopped after 2 iterations (DIVERGED_ITS", "-ksp_max_it 2"])):
    for ranks in (1, 2):
        rc, lines = one_line_error("trust_inexact", args, ranks)
        check(rc == 1 and len(lines) == 1 and all(c in lines[0] for c in culprits), "%s, %d rank(s): one line: %s" % (what, ranks, lines[-1] if lines else "(none)"))

# item 9: two different values on one vertex (before: the first won); the
# same value twice is no conflict; G:n on a point (before: held nothing)
for ranks in (1, 2):
    rc, lines = one_line_error("trust_dir_conflict", S2 + ["-dirichlet", SUP + ",lower_origin:y:0.01", "-exact", "none"], ranks)
    check(rc == 1 and len(lines) == 1 and "option -dirichlet: the vertex at (0" in lines[0] and "two different displacements along one direction" in lines[0],
          "lower_bottom:y and lower_origin:y:0.01, %d rank(s): one line naming the vertex: %s" % (ranks, lines[-1] if lines else "(none)"))
    rc, lines = one_line_error("trust_dir_point_n", S2 + ["-dirichlet", "lower_bottom:y,lower_origin:n,lower_left:x,upper_left:x"], ranks)
    check(rc == 1 and len(lines) == 1 and "'lower_origin:n' needs a curve" in lines[0], "G:n on a point, %d rank(s): one line: %s" % (ranks, lines[-1] if lines else "(none)"))
s = solve("trust_dir_same", S2 + ["-dirichlet", SUP + ",lower_origin:y:0"])
check(patch_error(s) < 1e-10, "the same value twice on one vertex: exact to %.1e" % patch_error(s))
rc, lines = one_line_error("trust_dir_third", S2 + ["-mesh", mesh("patch_incl30"), "-dirichlet", "lower_bottom:n,lower_left:n,upper_left:n,lower_origin:x:0.001", "-exact_angle", "30"], 1)
check(rc == 1 and len(lines) == 1 and "two different displacements" in lines[0], "a third condition the corner's two normals contradict: one line: %s" % (lines[-1] if lines else ""))

# item 9: results in the user's units must be numbers (before: -pressure 1e200
# wrote inf/null estimates; E = 1e200, p = 1e197 at 1e100 m gave an energy
# norm of 1e394: null in the summary)
rc, lines = one_line_error("trust_p200", S2 + ["-pressure", "upper_top:1e200"], 1)
check(rc == 1 and len(lines) == 1 and "strains by" in lines[0], "S2 with p = 1e200 on E = 1e9: one line (the strain): %s" % (lines[-1] if lines else ""))
for ranks in (1, 2):
    d = workdir("trust_big_%d" % ranks)
    args = S2 + ["-lower_E", "1e200", "-upper_E", "1e200", "-pressure", "upper_top:1e197", "-mesh_scale", "1e100", "-output_name", "sol", "-output_dir", d, "-summary", os.path.join(d, "s.json")]
    rc, out, err = run(args, ranks=ranks, check=False)
    text = open(os.path.join(d, "s.json")).read() if rc == 0 else ""
    _, _, vf, cf = read_h5(os.path.join(d, "sol.h5")) if rc == 0 else (0, 0, {}, {})
    # (the gap and active fields are NaN off the non-mortar surface by design)
    finite = rc == 0 and "null" not in text and all(np.isfinite(np.asarray(v, dtype=float)).all() for k, v in list(vf.items()) + list(cf.items()) if k not in ("gap", "active"))
    s = json.loads(text) if rc == 0 else {}
    check(finite and patch_error(s) < 1e-10 and math.isfinite(s["estimator"]["energy_norm"]) and s["estimator"]["energy_norm"] > 1e196,
          "E = 1e200, p = 1e197, 1e100 m, %d rank(s): exact, every figure a number (energy norm %s)" % (ranks, s.get("estimator", {}).get("energy_norm")))
rc, lines = one_line_error("trust_force", S2 + ["-lower_E", "1e300", "-upper_E", "1e300", "-pressure", "upper_top:1e298", "-mesh_scale", "1e6"], 1)
check(rc == 1 and len(lines) == 1 and "forces of about 1.41421e+304" in lines[0], "forces beyond 1e300: one line: %s" % (lines[-1] if lines else ""))
