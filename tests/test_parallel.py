"""1 and 2 MPI ranks give the same answer (to 1e-10 relative): uniform
compression and the manufactured solution, compared field by field after
sorting vertices and cells by coordinates. And the same command on 2 ranks
gives the same bits every run: Hertz level 1 on the condensed path (the
default) and on the full path with PCREDUNDANT (PETSc's MUMPS across ranks
sums in the order messages arrive: its last bits vary, docs/trust.md)."""
import os
import re

import numpy as np
from m2d import check, mesh, opts, read_csv, solve, sorted_fields, workdir

cases = {
    "uniform": ["-options_file", opts("block"), "-mesh", mesh("block_16")],
    "mms": ["-bodies", "block", "-block_E", "1e3", "-dirichlet", "bottom:xy,right:xy,top:xy,left:xy", "-exact", "mms", "-mesh", mesh("block_32")],
}
for name, args in cases.items():
    out = {}
    for ranks in (1, 2):
        tag = "par_%s_%d" % (name, ranks)
        s = solve(tag, args + ["-output_name", "sol"], ranks=ranks)
        check(s["ranks"] == ranks, "%s ran on %d ranks" % (name, ranks))
        out[ranks] = (s, sorted_fields(workdir(tag) + "/sol.h5"))
    (s1, (v1, c1, x1, _)), (s2, (v2, c2, x2, _)) = out[1], out[2]
    check(s1["dofs"] == s2["dofs"], "%s: same dofs %d" % (name, s1["dofs"]))
    check(np.allclose(x1, x2, rtol=0, atol=1e-12), "%s: same vertices" % name)
    u1, u2 = v1["displacement"], v2["displacement"]
    du = np.abs(u1 - u2).max() / np.abs(u1).max()
    check(du < 1e-10, "%s: displacement differs by %.2e relative" % (name, du))
    for k in ("sigma_x", "sigma_y", "sigma_xy"):
        scale = max(np.abs(c1["sigma_y"]).max(), np.abs(c1["sigma_x"]).max())
        d = np.abs(c1[k] - c2[k]).max() / scale
        check(d < 1e-10, "%s: %s differs by %.2e relative" % (name, k, d))
    for key in s1.get("error", {}):
        a, b = s1["error"][key], s2["error"][key]
        if key.endswith("_rel") and name == "uniform":
            check(abs(a - b) < 1e-10, "%s: error.%s %.3e vs %.3e" % (name, key, a, b))
        else:
            check(abs(a - b) <= 1e-10 * abs(a), "%s: error.%s %.6e vs %.6e" % (name, key, a, b))


def bits(s):
    """a summary without what varies by design (times, memory, the run's id)"""
    if isinstance(s, dict):
        return {k: bits(v) for k, v in s.items() if not re.search(r"time|seconds|memory|run_id", k)}
    return [bits(v) for v in s] if isinstance(s, list) else s


for name, extra in (("condensed", []), ("full_redundant", ["-kkt_path", "full", "-pc_type", "redundant", "-redundant_pc_type", "lu", "-redundant_pc_factor_mat_solver_type", "mumps"])):
    runs = []
    for k in range(3):
        tag = "bits_%s_%d" % (name, k)
        s = solve(tag, ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1"), "-output_name", "sol", "-output", "csv,summary"] + extra, ranks=2)
        runs.append((bits(s), read_csv(os.path.join(workdir(tag), "sol_contact.csv"))))
    check(all(r == runs[0] for r in runs[1:]), "%s path, 2 ranks: 3 runs give the same summary and contact CSV, bit for bit" % name)
