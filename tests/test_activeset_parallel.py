"""Unilateral contact on 1 and 2 MPI ranks agrees: Hertz level 1 (mortar and
NTS) and the eccentric S2 load; same steps, same active set, same fields."""
import numpy as np
from m2d import check, mesh, opts, solve, sorted_fields, workdir

cases = {
    "hertz_mortar": ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1")],
    "hertz_nts": ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1"), "-contact_method", "nts"],
    "eccentric": ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_10_31"), "-pressure", "upper_top:-1e6:4e6:0", "-exact", "none"],
}
for name, args in cases.items():
    out = {}
    for ranks in (1, 2):
        tag = "aspar_%s_%d" % (name, ranks)
        s = solve(tag, args + ["-output_name", "sol"], ranks=ranks)
        out[ranks] = (s, sorted_fields(workdir(tag) + "/sol.h5"))
    (s1, (v1, c1, _, _)), (s2, (v2, c2, _, _)) = out[1], out[2]
    check(s1["iterations"] == s2["iterations"] and s1["active_nodes"] == s2["active_nodes"], "%s: %d steps, %d active on both" % (name, s1["iterations"], s1["active_nodes"]))
    du = np.abs(v1["displacement"] - v2["displacement"]).max() / np.abs(v1["displacement"]).max()
    dp = np.abs(v1["contact_pressure"] - v2["contact_pressure"]).max() / np.abs(v1["contact_pressure"]).max()
    check(du < 1e-10 and dp < 1e-10, "%s: displacement %.1e, pressure %.1e relative" % (name, du, dp))
