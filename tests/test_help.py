"""-help documents the program: every option of ours is listed with a non-empty
default and a help string that fits on one line.

The program's options are the lines of its own -help sections (the scene's
"mortar2d: ..." and one "Material of body 'NAME'" per body). A line reads
  -name <now DEFAULT : formerly DEFAULT>: help ()         (strings, integers, choices)
  -name <DEFAULT : DEFAULT>: help ()                      (reals)
  -name: <DEFAULT : DEFAULT> help ()                      (booleans)
  -name <string1,string2,...>: help; default: X ()        (lists: the default is in the help)
An empty default (an empty string option) must say "default: X" in its help.
The help text (without PETSc's decorations) is at most HELP_MAX characters and
nothing in our sections is a continuation line."""
import re

from m2d import check, run

HELP_MAX = 100
OURS = ["-mesh", "-mesh_dir", "-mesh_scale", "-mesh_partitioner", "-mesh_check", "-geo", "-geo_dir", "-bodies",
        "-plane", "-q4_integration", "-dirichlet", "-pressure", "-traction", "-contact_nonmortar", "-contact_mortar",
        "-contact_method", "-mortar_basis", "-contact_unilateral", "-contact_c", "-contact_initial",
        "-contact_monitor", "-contact_reach", "-exact", "-exact_p", "-exact_angle", "-mms_amplitude", "-hertz",
        "-hertz_radius", "-hertz_load", "-kkt_mat", "-kkt_path", "-kkt_ordering", "-kkt_ldlt", "-mat_mumps_icntl_4",
        "-mat_mumps_icntl_7", "-mat_mumps_icntl_8", "-mat_mumps_icntl_14", "-mat_mumps_icntl_58", "-kkt_augment", "-kkt_condensed_max",
        "-output_dir", "-output_name", "-output", "-output_vtu", "-output_hdf5", "-summary",
        "-lower_E", "-lower_nu", "-upper_E", "-upper_nu"]
# defaults that are part of the documented behaviour (README)
DEFAULTS = {"-plane": "strain", "-exact": "none", "-output_dir": "output", "-output_name": "solution",
            "-lower_E": "1.", "-lower_nu": "0.3", "-kkt_path": "condensed", "-kkt_condensed_max": "8000", "-kkt_ordering": "metis",
            "-kkt_ldlt": "TRUE", "-mat_mumps_icntl_14": "20", "-mesh_partitioner": "metis", "-mesh_check": "FALSE",
            "-contact_c": "auto", "-contact_reach": "auto", "-hertz_load": "auto", "-exact_p": "auto",
            "-hertz_radius": "1.", "-contact_method": "mortar", "-contact_initial": "closest", "-geo": "none",
            "-mesh": "none, required", "-summary": "OUTPUT_DIR/N_summary.json", "-output": "h5,vtu,csv,summary", "-exact_angle": "0.", "-mortar_basis": "standard"}

rc, out, err = run(["-help", "-bodies", "lower,upper"])
lines = (out + err).splitlines()

sections, cur = {}, None
for line in lines:
    if (line.startswith("mortar2d: ") or line.startswith("Material of body '")) and line.endswith(":"):
        cur = line
        sections[cur] = []
    elif line.startswith("-----"):
        cur = None
    elif cur is not None:
        sections[cur].append(line)
check(len(sections) == 3, "-help has the program's section and one per body: %s" % list(sections))

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
# PETSc's solver options are documented too (the solvers are configured under -help)
check(any(l.strip().startswith("-ksp_type") for l in lines), "-help lists PETSc's -ksp_type")
