"""The bodies can come from one .msh holding both or from one .msh per body:
both ways give the same mesh and the same answer. Two independent bodies, each
held at its bottom edge and loaded on top (no contact involved)."""
import numpy as np
from m2d import check, mesh, solve, sorted_fields, workdir

common = ["-bodies", "lower,upper", "-lower_E", "1e9", "-upper_E", "3e9", "-upper_nu", "0.25",
          "-dirichlet", "lower_bottom:xy,upper_bottom:xy", "-pressure", "upper_top:1e6", "-traction", "lower_right:0:2e5"]
one = solve("files_one", common + ["-mesh", mesh("patch_uniform")])
two = solve("files_two", common + ["-mesh", mesh("patch_uniform_lower") + "," + mesh("patch_uniform_upper")])
check(one["dofs"] == two["dofs"] and one["cells"] == two["cells"], "same size: %d dofs, %d cells" % (one["dofs"], one["cells"]))
v1, c1, x1, _ = sorted_fields(workdir("files_one") + "/solution.h5")
v2, c2, x2, _ = sorted_fields(workdir("files_two") + "/solution.h5")
check(np.allclose(x1, x2, atol=1e-14), "same vertices")
d = np.abs(v1["displacement"] - v2["displacement"]).max() / np.abs(v1["displacement"]).max()
check(d < 1e-12, "same displacement (%.1e)" % d)
check(set(np.unique(c1["body"])) == {0.0, 1.0}, "two bodies")
# the upper body (index 1) carries the pressure: mean sigma_y about -1e6
sy = c1["sigma_y"][c1["body"] == 1]
check(abs(sy.mean() + 1e6) < 0.2e6, "upper body mean sigma_y %.3e" % sy.mean())

# the same mesh saved by gmsh in binary 4.1 (gmsh -bin): the same answer, also
# split over two files and on two ranks
import shutil
import subprocess
gmsh = shutil.which("gmsh")
check(gmsh is not None, "gmsh found for the binary-file check")
binary = []
for name in ("patch_uniform_lower", "patch_uniform_upper"):
    out = workdir("files_binary") + "/" + name + "_bin.msh"
    subprocess.run([gmsh, "-0", "-bin", "-format", "msh41", "-v", "0", mesh(name), "-o", out], check=True)
    with open(out, "rb") as fh:
        check(fh.read(64).split(b"\n")[1].startswith(b"4.1 1 "), "%s written in binary" % name)
    binary.append(out)
for ranks in (1, 2):
    b = solve("files_binary_%d" % ranks, common + ["-mesh", ",".join(binary)], ranks=ranks)
    vb, _, xb, _ = sorted_fields(workdir("files_binary_%d" % ranks) + "/solution.h5")
    db = np.abs(v2["displacement"] - vb["displacement"]).max() / np.abs(v2["displacement"]).max()
    check(b["dofs"] == two["dofs"] and np.allclose(x2, xb, atol=1e-14) and db < 1e-12,
          "binary files, %d rank(s): same mesh and displacement (%.1e)" % (ranks, db))
