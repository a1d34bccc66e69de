"""-help documents the program: every option of ours is listed with a non-empty
default and a help string that fits on one line, the program's options first,
grouped by job in the README's order; PETSc's own options only with -help_petsc,
after the program's. Both exit 0 without running. docs/options.md, the full
reference, names every option of the program's sections.

The program's options are the lines of its own -help sections ("mortar2d: JOB"
and one "Material of body 'NAME'" per body). A line reads
  -name <now DEFAULT : formerly DEFAULT>: help ()         (strings, integers, choices)
  -name <DEFAULT : DEFAULT>: help ()                      (reals)
  -name: <DEFAULT : DEFAULT> help ()                      (booleans)
  -name <string1,string2,...>: help; default: X ()        (lists: the default is in the help)
An empty default (an empty string option) must say "default: X" in its help.
The help text (without PETSc's decorations) is at most HELP_MAX characters and
nothing in our sections is a continuation line."""
import os
import re

from m2d import SRC, check, run

HELP_MAX = 100
OURS = ["-mesh", "-mesh_dir", "-mesh_scale", "-mesh_partitioner", "-mesh_check", "-geo", "-geo_dir", "-bodies",
        "-plane", "-q4_integration", "-dirichlet", "-pressure", "-traction", "-contact_nonmortar", "-contact_mortar",
        "-contact_method", "-mortar_basis", "-contact_unilateral", "-contact_c", "-contact_initial",
        "-contact_monitor", "-contact_reach", "-contact_friction", "-load_steps", "-load_stages", "-stage2_pressure", "-stage2_traction",
        "-stage2_dirichlet", "-stage2_steps", "-exact", "-exact_p", "-exact_tau", "-exact_angle", "-mms_amplitude", "-hertz", "-cattaneo",
        "-hertz_radius", "-hertz_pairs", "-hertz_load", "-kkt_mat", "-kkt_path", "-kkt_ordering", "-kkt_ldlt", "-mat_mumps_icntl_4",
        "-mat_mumps_icntl_7", "-mat_mumps_icntl_8", "-mat_mumps_icntl_14", "-mat_mumps_icntl_58", "-kkt_augment", "-kkt_condensed_max",
        "-output_dir", "-output_name", "-output", "-output_vtu", "-output_hdf5", "-summary",
        "-lower_E", "-lower_nu", "-upper_E", "-upper_nu"]
# defaults that are part of the documented behaviour (README)
DEFAULTS = {"-plane": "strain", "-exact": "none", "-output_dir": "output", "-output_name": "solution",
            "-lower_E": "1.", "-lower_nu": "0.3", "-kkt_path": "condensed", "-kkt_condensed_max": "8000", "-kkt_ordering": "auto",
            "-kkt_ldlt": "TRUE", "-mat_mumps_icntl_14": "20", "-mesh_partitioner": "metis", "-mesh_check": "FALSE",
            "-contact_c": "auto", "-contact_reach": "auto", "-hertz_load": "auto", "-exact_p": "auto",
            "-hertz_radius": "1", "-hertz_pairs": "the curved ones", "-contact_method": "mortar", "-contact_initial": "closest", "-geo": "none",
            "-mesh": "none, required", "-summary": "OUTPUT_DIR/N_summary.json", "-output": "h5,vtu,csv,summary", "-exact_angle": "0.", "-mortar_basis": "standard",
            "-contact_friction": "0.", "-load_steps": "1", "-load_stages": "1", "-stage2_steps": "1"}

# the jobs, in the order of the README's Options section
JOBS = ["mortar2d: scene and mesh", "mortar2d: materials", "Material of body 'lower'", "Material of body 'upper'",
        "mortar2d: loads and supports", "mortar2d: load history", "mortar2d: load stage 2", "mortar2d: contact", "mortar2d: solver paths", "mortar2d: solver paths (-kkt_path iterative)",
        "mortar2d: checks against exact answers", "mortar2d: error estimate", "mortar2d: adaptive meshes", "mortar2d: output",
        "mortar2d: output (mesh)"]


def parse(lines):
    sections, order, cur = {}, [], None
    for line in lines:
        if (line.startswith("mortar2d: ") or line.startswith("Material of body '")) and line.endswith(":"):
            cur = line
            sections[cur] = []
            order.append(cur)
        elif line.startswith("-----"):
            cur = None
        elif cur is not None:
            sections[cur].append(line)
    return sections, order


rc, out, err = run(["-help", "-bodies", "lower,upper"])
check(rc == 0, "-help exits 0 (%d)" % rc)
lines = (out + err).splitlines()
sections, order = parse(lines)
titles = [t.split(" (and ")[0].split(" (GROUP")[0].rstrip(":") for t in order]
check(titles == JOBS, "-help has the program's sections by job, in order: %s" % titles)
first = next(i for i, l in enumerate(lines) if l.strip().startswith("-mesh "))
check(first < 20, "the program's options come first (-mesh on line %d)" % (first + 1))
check(len(lines) < 150, "-help alone is the program's options (%d lines)" % len(lines))
check(not any(l.strip().startswith("-ksp_type") for l in lines), "-help alone does not list PETSc's -ksp_type")
check("-help_petsc" in lines[-1], "-help ends by naming -help_petsc: %r" % lines[-1])

LINE = re.compile(r"^  -(?P<name>[A-Za-z0-9_]+):? <(?P<dflt>[^>]*)>:? (?P<rest>.*)$")
found = {}
for title, body in sections.items():
    for line in body:
        m = LINE.match(line)
        check(m is not None, "one option per line in '%s': %r" % (title, line[:120]))
        name, dflt, rest = "-" + m.group("name"), m.group("dflt"), m.group("rest")
        rest = re.sub(r" \(\)$", "", rest)  # PETSc's empty man-page reference
        text = rest.split(" (choose one of)")[0]
        value = dflt[4:] if dflt.startswith("now ") else dflt
        value = value.split(" : ")[0].strip()
        in_help = re.search(r"default: (.+)$", text)
        if value in ("", "string1,string2,...") and in_help:
            value = in_help.group(1).strip()
        check(value not in ("", "string1,string2,..."), "%s has a non-empty default (%r)" % (name, value))
        check(text.strip() != "", "%s has a help string" % name)
        check(len(text) <= HELP_MAX, "%s: help fits on one line (%d <= %d characters)" % (name, len(text), HELP_MAX))
        found[name] = value

for opt in OURS:
    check(opt in found, "%s is documented by -help" % opt)
for opt, value in DEFAULTS.items():
    check(found.get(opt) == value, "%s default is %r (-help shows %r)" % (opt, value, found.get(opt)))
# docs/options.md, the full reference, names every option -help lists (stage K's as -stageK_, body A's as -A_)
with open(os.path.join(SRC, "docs", "options.md")) as f:
    reference = f.read()
missing = [o for o in found if re.sub(r"^-(lower|upper)_", "-A_", re.sub(r"^-stage\d+_", "-stageK_", o)) not in reference]
check(not missing, "docs/options.md names every option of -help (missing: %s)" % missing)
# -help_petsc: the same program sections first, then PETSc's solver options (the
# solvers configured as for a run) and PETSc's general options
rc, out, err = run(["-help_petsc", "-bodies", "lower,upper"])
check(rc == 0, "-help_petsc exits 0 (%d)" % rc)
plines = (out + err).splitlines()
psections, porder = parse(plines)
check(porder == order, "-help_petsc starts with the same sections as -help")
last_ours = max(i for i, l in enumerate(plines) if l.startswith("  -adapt") or l.startswith("  -summary") or l.startswith("  -mesh_save"))
ksp = [i for i, l in enumerate(plines) if l.strip().startswith("-ksp_type")]
check(ksp and min(ksp) > last_ours, "-help_petsc lists PETSc's -ksp_type after the program's options")
check(any(l.strip().startswith("-log_view") for l in plines[last_ours:]), "-help_petsc lists PETSc's -log_view")
check(not any(l.strip().startswith("-ksp_type") for l in plines[:last_ours]), "nothing of PETSc's before the program's options")
# a refusal under -help is its one line, without the help collected before it
for extra in (["-hertz"], ["-adapt"]):
    rc, out, err = run(["-help"] + extra, check=False)
    lines = [l for l in (out + err).splitlines() if l.strip()]
    check(rc == 1 and len(lines) == 1 and ("option %s" % extra[0]) in lines[0], "-help %s (no pair, no .geo): one line naming %s, exit 1 (exit %d, %d lines)" % (extra[0], extra[0], rc, len(lines)))
