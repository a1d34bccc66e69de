"""Helpers for the mortar2d tests: run the program, read its summary and output.

Tests are plain Python scripts run by ctest (tests/CMakeLists.txt passes the
paths in the environment); a test fails by raising (non-zero exit)."""
import json
import os
import subprocess
import sys

EXE = os.environ.get("M2D_EXE", "build/mortar2d")
SRC = os.environ.get("M2D_SOURCE", os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MESHES = os.environ.get("M2D_MESHES", os.path.join(SRC, "build", "meshes"))
WORK = os.environ.get("M2D_WORK", os.path.join(SRC, "build", "test-output"))
MPIEXEC = os.environ.get("MPIEXEC", "mpiexec")


def mesh(name):
    return os.path.join(MESHES, name + ".msh")


def opts(name):
    return os.path.join(SRC, "options", name + ".opts")


def workdir(name):
    d = os.path.join(WORK, name)
    os.makedirs(d, exist_ok=True)
    return d


def run(args, ranks=1, check=True, timeout=600):
    """Run mortar2d from the source directory; return (rc, stdout, stderr)."""
    cmd = [EXE] + [str(a) for a in args]
    if ranks > 1:
        cmd = [MPIEXEC, "--oversubscribe", "-n", str(ranks)] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    p = subprocess.run(cmd, cwd=SRC, capture_output=True, text=True, timeout=timeout, env=env)
    if check and p.returncode != 0:
        sys.stderr.write("command failed: %s\n%s\n%s\n" % (" ".join(cmd), p.stdout, p.stderr))
        raise SystemExit(1)
    return p.returncode, p.stdout, p.stderr


def solve(name, args, ranks=1):
    """Run with output in WORK/name; return the summary dict."""
    d = workdir(name)
    summary = os.path.join(d, "summary.json")
    run(list(args) + ["-output_dir", d, "-summary", summary], ranks=ranks)
    with open(summary) as f:
        return json.load(f)


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


def check(cond, msg):
    print(("ok   " if cond else "FAIL ") + msg)
    if not cond:
        raise SystemExit(1)
