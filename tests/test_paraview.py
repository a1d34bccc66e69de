"""ParaView reads our output: the .xmf with its XDMF (2) reader "XDMFReader"
and the .vtu with "XMLUnstructuredGridReader", through paraview.simple and
servermanager.Fetch in pvpython (Debian's python3-paraview). Both readers must
see the mesh and the arrays of the HDF5 file (read with h5py), with the same
values. Scenes: the uniform block (options/block.opts on an 8 x 8 mesh), whose
exact solution is known, and two independent held bodies (patch_uniform.msh)."""
import json
import math
import os
import shutil
import subprocess

import numpy as np
from m2d import check, mesh, opts, read_h5, solve, workdir

PVPYTHON = os.environ.get("PVPYTHON", "pvpython")
CELL = ["sigma_x", "sigma_y", "sigma_z", "sigma_xy", "von_mises", "body"]
POINT = ["displacement"]

PV_SCRIPT = r'''
import json, sys
from paraview import servermanager
from paraview.simple import XDMFReader, XMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy


def leaf(d):
    """the dataset itself, or the only leaf of a multiblock"""
    if d.IsA("vtkMultiBlockDataSet"):
        leaves = []
        it = d.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            leaves.append(it.GetCurrentDataObject())
            it.GoToNextItem()
        assert len(leaves) == 1, "%d blocks" % len(leaves)
        return leaves[0]
    return d


def describe(reader, kind):
    reader.UpdatePipeline()
    d = leaf(servermanager.Fetch(reader))
    out = {"reader": kind, "class": d.GetClassName(), "points": d.GetNumberOfPoints(), "cells": d.GetNumberOfCells(), "arrays": []}
    for assoc, data in (("point", d.GetPointData()), ("cell", d.GetCellData())):
        for i in range(data.GetNumberOfArrays()):
            a = data.GetArray(i)
            if a is None:
                continue
            v = vtk_to_numpy(a).astype(float)
            v2 = v.reshape(len(v), -1)
            out["arrays"].append({"name": a.GetName(), "association": assoc, "components": a.GetNumberOfComponents(),
                                  "min": [float(x) for x in v2.min(axis=0)], "max": [float(x) for x in v2.max(axis=0)],
                                  "values": v2.tolist()})
    pts = vtk_to_numpy(d.GetPoints().GetData()).astype(float)
    out["points_xyz"] = pts.tolist()
    out["cell_types"] = sorted(set(d.GetCellType(c) for c in range(d.GetNumberOfCells())))
    return out


xmf, vtu = sys.argv[1], sys.argv[2]
res = [describe(XDMFReader(FileNames=[xmf]), "XDMFReader"),
       describe(XMLUnstructuredGridReader(FileName=[vtu]), "XMLUnstructuredGridReader")]
print("PVJSON " + json.dumps(res))
'''


def paraview_read(d, name):
    exe = shutil.which(PVPYTHON)
    check(exe is not None, "pvpython available (%s)%s" % (exe or PVPYTHON, "" if exe else ": not found, install Debian's python3-paraview"))
    script = os.path.join(d, "pv_read.py")
    with open(script, "w") as f:
        f.write(PV_SCRIPT)
    xmf, vtu = os.path.join(d, name + ".xmf"), os.path.join(d, name + ".vtu")
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    p = subprocess.run([exe, "--force-offscreen-rendering", script, xmf, vtu], capture_output=True, text=True, timeout=120, env=env)
    lines = [l for l in p.stdout.splitlines() if l.startswith("PVJSON ")]
    if p.returncode != 0 or len(lines) != 1:
        print(p.stdout[-3000:])
        print(p.stderr[-3000:])
    check(p.returncode == 0 and len(lines) == 1, "pvpython read %s.xmf and %s.vtu (exit %d)" % (name, name, p.returncode))
    errs = [l for l in p.stderr.splitlines() if "ERROR" in l or "Error" in l]
    check(not errs, "no reader errors on stderr%s" % (": " + " | ".join(errs[:5]) if errs else ""))
    return json.loads(lines[0][len("PVJSON "):])


def arrays(res):
    return {a["name"]: a for a in res["arrays"]}


def compare_with_h5(h5, res):
    """common checks: sizes, arrays, and values equal to the HDF5 file"""
    xy, cells, vf, cf = read_h5(h5)
    for r in res:
        who = r["reader"]
        check(r["points"] == len(xy) and r["cells"] == len(cells), "%s: %d points, %d cells (h5py: %d, %d)" % (who, r["points"], r["cells"], len(xy), len(cells)))
        check(r["cell_types"] == [9], "%s: every cell is a VTK_QUAD (types %s)" % (who, r["cell_types"]))
        a = arrays(r)
        for n in CELL:
            check(n in a and a[n]["association"] == "cell" and a[n]["components"] == 1, "%s: cell array %s, 1 component" % (who, n))
        for n in POINT:
            check(n in a and a[n]["association"] == "point" and a[n]["components"] == 3, "%s: point array %s, 3 components" % (who, n))
        pts = np.array(r["points_xyz"])
        check(np.array_equal(pts[:, :2], xy) and not pts[:, 2].any(), "%s: point coordinates equal the h5 geometry" % who)
        for n in CELL:
            v = cf[n]
            same = a[n]["min"] == [float(v.min())] and a[n]["max"] == [float(v.max())]
            check(same, "%s: %s min/max %r/%r equal h5py's %r/%r" % (who, n, a[n]["min"][0], a[n]["max"][0], float(v.min()), float(v.max())))
            check(np.array_equal(np.array(a[n]["values"])[:, 0], v), "%s: %s equals h5py's, cell by cell" % (who, n))
        u = vf["displacement"]
        check(u.shape == (len(xy), 3), "h5 displacement has 3 components")
        for k in range(3):
            same = a["displacement"]["min"][k] == float(u[:, k].min()) and a["displacement"]["max"][k] == float(u[:, k].max())
            check(same, "%s: displacement[%d] min/max %r/%r equal h5py's" % (who, k, a["displacement"]["min"][k], a["displacement"]["max"][k]))
        check(np.array_equal(np.array(a["displacement"]["values"]), u), "%s: displacement equals h5py's, point by point" % who)
    return xy, cells, vf, cf


# ---------- the uniform block: known exact values ----------
E, nu, p = 1e9, 0.3, 1e6
d = workdir("paraview_block")
solve("paraview_block", ["-options_file", opts("block"), "-mesh", mesh("block_8")])
res = paraview_read(d, "block")
xy, cells, vf, cf = compare_with_h5(os.path.join(d, "block.h5"), res)
check(len(cells) == 64 and len(xy) == 81, "block_8: 64 cells, 81 vertices")
sx, sy, sz, sxy, vm = (cf[n] for n in ("sigma_x", "sigma_y", "sigma_z", "sigma_xy", "von_mises"))
check(np.abs(sy + p).max() <= 1e-12 * p, "sigma_y = -1e6 in every cell (max dev %.2e)" % np.abs(sy + p).max())
check(np.abs(sx).max() <= 1e-12 * p and np.abs(sxy).max() <= 1e-12 * p, "|sigma_x|, |sigma_xy| <= 1e-6 (%.2e, %.2e)" % (np.abs(sx).max(), np.abs(sxy).max()))
check(np.abs(sz - nu * (sx + sy)).max() <= 1e-12 * nu * p and np.abs(sz + nu * p).max() <= 1e-12 * nu * p,
      "sigma_z = nu (sigma_x + sigma_y) = -3e5 (max dev %.2e)" % np.abs(sz + nu * p).max())
vm_ref = np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2) + 3 * sxy ** 2)
check(np.abs(vm - vm_ref).max() <= 1e-12 * p, "von_mises matches the formula (max dev %.2e)" % np.abs(vm - vm_ref).max())
check(not np.abs(cf["body"]).any(), "body = 0 everywhere")
uy_exact = -p * (1 - nu ** 2) / E * 1.0
top = np.abs(xy[:, 1] - 1.0) < 1e-9
uy = vf["displacement"][top, 1]
check(top.sum() == 9 and np.abs(uy - uy_exact).max() <= 1e-10 * abs(uy_exact),
      "top u_y = -p (1 - nu^2)/E = %.4e on all %d top vertices (max rel dev %.2e)" % (uy_exact, top.sum(), np.abs(uy / uy_exact - 1).max()))
for r in res:
    a = arrays(r)
    check(math.isclose(a["displacement"]["min"][1], uy_exact, rel_tol=1e-10) and a["sigma_y"]["max"][0] <= -p * (1 - 1e-12),
          "%s: min u_y = %.10e, max sigma_y = %.10e" % (r["reader"], a["displacement"]["min"][1], a["sigma_y"]["max"][0]))

# ---------- two independent held bodies ----------
d = workdir("paraview_two")
solve("paraview_two", ["-mesh", mesh("patch_uniform"), "-bodies", "lower,upper", "-lower_E", "1e9", "-upper_E", "2e9",
                       "-dirichlet", "lower_bottom:xy,upper_bottom:xy", "-pressure", "upper_top:1e6"])
res = paraview_read(d, "solution")
xy, cells, vf, cf = compare_with_h5(os.path.join(d, "solution.h5"), res)
body = cf["body"]
check(set(np.unique(body)) == {0.0, 1.0}, "h5 body takes the values 0 and 1 only (%s)" % sorted(set(np.unique(body))))
counts = {b: int((body == b).sum()) for b in (0.0, 1.0)}
check(counts == {0.0: 50, 1.0: 35}, "h5 cells per body: lower %d (10 x 5), upper %d (7 x 5)" % (counts[0.0], counts[1.0]))
for r in res:
    v = np.array(arrays(r)["body"]["values"])[:, 0]
    pc = {b: int((v == b).sum()) for b in (0.0, 1.0)}
    check(set(np.unique(v)) == {0.0, 1.0} and pc == counts, "%s: body values 0/1, cells per body %s" % (r["reader"], pc))
print("test_paraview: all checks passed")
