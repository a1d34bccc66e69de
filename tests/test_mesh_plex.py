"""The plex is built from the cell list by our own edge finder (mesh.c,
CreatePlex) instead of DMPlexInterpolate, and split over the ranks by libmetis
(-mesh_partitioner metis, a shell partitioner) by default:
 - PETSc's own checks (DMPlexCheckSymmetry, DMPlexCheckSkeleton,
   DMPlexCheckFaces - the edge orientations in every cell -,
   DMPlexCheckGeometry) pass on every kind of mesh the tests use (-mesh_check);
 - on 2 ranks, METIS and PETSc's partitioner give the same answer as 1 rank
   (Hertz level 1, unilateral contact, and the two-body patch)."""
import numpy as np
from m2d import check, mesh, opts, run, solve, sorted_fields, workdir

cases = [
    ("hertz_0", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_0")]),
    ("hertz_2", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_2")]),
    ("patch_10_31", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_10_31")]),
    ("patch_incl30", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_incl30"), "-exact", "none"]),
    ("patch_sliver", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_sliver"), "-exact", "none"]),
    ("two_files", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform_lower") + "," + mesh("patch_uniform_upper")]),
    ("seed_patch", ["-options_file", opts("seed_patch"), "-mesh", mesh("seed_patch")]),
    ("block_8", ["-options_file", opts("block"), "-mesh", mesh("block_8")]),
]
for name, args in cases:
    rc, out, err = run(args + ["-mesh_check", "-output_dir", workdir("plex_" + name), "-output_vtu", "0"], check=False)
    check(rc == 0 and not err.strip(), "%s: DMPlexCheck* pass on the plex as built (rc %d%s)" % (name, rc, ", " + err.strip().splitlines()[-1] if err.strip() else ""))

for name, args in (cases[1], cases[2]):
    s1 = solve("part_%s_1" % name, args + ["-output_name", "sol"])
    v1 = sorted_fields(workdir("part_%s_1" % name) + "/sol.h5")[0]
    for part in ("metis", "petsc"):
        tag = "part_%s_%s" % (name, part)
        s2 = solve(tag, args + ["-output_name", "sol", "-mesh_partitioner", part], ranks=2)
        v2 = sorted_fields(workdir(tag) + "/sol.h5")[0]
        du = np.abs(v1["displacement"] - v2["displacement"]).max() / np.abs(v1["displacement"]).max()
        check(s2["dofs"] == s1["dofs"] and s2["iterations"] == s1["iterations"] and du < 1e-10,
              "%s, 2 ranks, -mesh_partitioner %s: %d dofs, %d steps, displacement %.1e of 1 rank" % (name, part, s2["dofs"], s2["iterations"], du))
