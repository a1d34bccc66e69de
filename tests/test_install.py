"""An installable program (cmake --install), on a copy of the source tree:
 1. the copy (no .git: a release tarball's view) configures and builds the
    program and its meshes, and `cmake --install BUILD --prefix P` puts
    P/bin/mortar2d, the scenes in P/share/mortar2d/options, every .geo and
    the .msh the scenes name in P/share/mortar2d/meshes, the README and docs
    in P/share/doc/mortar2d;
 2. with the copy (source and build tree) removed, from another directory:
    `-version` prints the project version (no git commit: not built from git)
    and PETSc's; -help shows -mesh_dir and -geo_dir under P, nothing of the
    removed tree; a shipped scene (hertz.opts: its -mesh found in P) gives the
    answer of the build tree's program (figures to 1e-12); an adaptive scene
    (hertz_adapt.opts: its -geo found in P) runs; the summary records the
    version and PETSc's;
 3. the prefix moved elsewhere still runs (the meshes are found from the
    executable, not from the prefix it was installed to);
 4. the build tree's own program names its git commit when built from git."""
import json
import os
import re
import shutil
import tempfile

from m2d import EXE, SRC, check, launch, opts, run, solve, workdir

W = workdir("install")
root = tempfile.mkdtemp(prefix="m2d_install_", dir=W)
copy, build, prefix, elsewhere = (os.path.join(root, d) for d in ("src", "build", "prefix", "elsewhere"))


def step(cmd, what, cwd=None):
    r = launch(cmd, timeout=1800, cwd=cwd)
    check(r.rc == 0, "%s (%s): exit %s %s" % (what, r.cmdline, r.rc, (r.stdout + r.stderr)[-1500:] if r.rc else ""))
    return r


# ---------------------------------------------------------------- 1. build a copy, install it
shutil.copytree(SRC, copy, ignore=shutil.ignore_patterns(".git", "build", "output", "__pycache__"))
step(["cmake", "-S", copy, "-B", build, "-DCMAKE_BUILD_TYPE=RelWithDebInfo"], "configure the copy")
step(["cmake", "--build", build, "-j", str(os.cpu_count() or 2), "--target", "mortar2d", "meshes"], "build the copy's program and meshes")
step(["cmake", "--install", build, "--prefix", prefix], "cmake --install")
share = os.path.join(prefix, "share", "mortar2d")
scenes = sorted(f for f in os.listdir(os.path.join(SRC, "options")) if f.endswith(".opts"))
geos = sorted(f for f in os.listdir(os.path.join(SRC, "meshes")) if f.endswith(".geo"))
named = set()
for f in scenes:
    with open(os.path.join(SRC, "options", f)) as fh:
        named |= set(re.findall(r"^-mesh +(\S+\.msh)", fh.read(), re.M))
missing = [p for p in ["bin/mortar2d", "share/doc/mortar2d/README.md", "share/doc/mortar2d/docs/adaptivity.md"]
           + ["share/mortar2d/options/" + f for f in scenes] + ["share/mortar2d/meshes/" + f for f in geos + sorted(named)]
           if not os.path.isfile(os.path.join(prefix, p))]
check(not missing, "the install holds the program, %d scenes, %d .geo, the %d .msh the scenes name (%s), README and docs%s" % (
    len(scenes), len(geos), len(named), ", ".join(sorted(named)), ": missing " + ", ".join(missing) if missing else ""))

# ---------------------------------------------------------------- 2. the copy removed, from elsewhere
shutil.rmtree(copy)
shutil.rmtree(build)
os.makedirs(elsewhere)
exe = os.path.join(prefix, "bin", "mortar2d")
r = step([exe, "-version"], "-version", cwd=elsewhere)
lines = r.stdout.splitlines()
check(len(lines) == 2 and re.fullmatch(r"mortar2d \d+\.\d+\.\d+", lines[0]) and re.fullmatch(r"PETSc \d+\.\d+\.\d+", lines[1]),
      "-version of a build without git: the program's version and PETSc's, no commit: %s" % lines)
version = lines[0].split()[1]
r = step([exe, "-help"], "-help", cwd=elsewhere)
dirs = dict(re.findall(r"^\s*-(mesh_dir|geo_dir) <now (\S+) ", r.stdout, re.M))
meshes = os.path.join(os.path.realpath(share), "meshes")
check(dirs.get("mesh_dir") == meshes and dirs.get("geo_dir") == meshes and root not in r.stdout.replace(prefix, "P"),
      "-help: -mesh_dir and -geo_dir default to the installed meshes (%s), nothing of the removed tree" % dirs)

args = ["-options_file", os.path.join(share, "options", "hertz.opts"), "-contact_monitor", "0", "-output_vtu", "0"]
rc, out, err = run(args + ["-output_dir", "out"], exe=exe, cwd=elsewhere)
mine = json.load(open(os.path.join(elsewhere, "out", "hertz_summary.json")))
ref = solve("install_ref", ["-options_file", opts("hertz"), "-contact_monitor", "0", "-output_vtu", "0"])
keys = ("dofs", "pressure_l2_rel", "peak_pressure", "contact_force", "error_estimate")
diff = max(abs(mine[k] - ref[k]) / max(abs(ref[k]), 1e-300) for k in keys)
check(mine["status"] == "ok" and diff < 1e-12, "hertz.opts from the install, run elsewhere: the build tree's answer (%s to %.1e)" % (", ".join(keys), diff))
check(mine.get("version") == version and re.fullmatch(r"\d+\.\d+\.\d+", mine.get("petsc_version", "")) and "git_commit" not in mine,
      "the summary records version %s and petsc_version %s, no git_commit" % (mine.get("version"), mine.get("petsc_version")))
rc, out, err = run(["-options_file", os.path.join(share, "options", "hertz_adapt.opts"), "-adapt_target", "0.04", "-contact_monitor", "0",
                    "-output_vtu", "0", "-output_dir", "adapt"], exe=exe, cwd=elsewhere)
s = json.load(open(os.path.join(elsewhere, "adapt", "hertz_adapt_summary.json")))
check(s["status"] == "ok" and len(s["adapt"]) >= 2, "hertz_adapt.opts from the install: its .geo found in the prefix, %d meshes" % len(s["adapt"]))

# ---------------------------------------------------------------- 3. the prefix moved
moved = prefix + "_moved"
shutil.move(prefix, moved)
rc, out, err = run([a.replace(prefix, moved) for a in args] + ["-output_dir", "moved"], exe=os.path.join(moved, "bin", "mortar2d"), cwd=elsewhere)
s = json.load(open(os.path.join(elsewhere, "moved", "hertz_summary.json")))
d = abs(s["pressure_l2_rel"] - mine["pressure_l2_rel"]) / mine["pressure_l2_rel"]
check(s["dofs"] == ref["dofs"] and d < 1e-12, "the prefix moved: the same scene runs (%d dofs, the pressure error to %.1e)" % (s["dofs"], d))

# ---------------------------------------------------------------- 4. the build tree's program
r = launch([EXE, "-version"])
git = os.path.exists(os.path.join(SRC, ".git"))
first = r.stdout.splitlines()[0] if r.stdout else ""
check(r.rc == 0 and (re.fullmatch(r"mortar2d \d+\.\d+\.\d+ \(git [0-9a-f]{12}(-dirty)?\)", first) if git else first.startswith("mortar2d ")),
      "the build tree's -version%s: %s" % (" (a git checkout: the commit)" if git else "", first))
shutil.rmtree(root)
