"""Fast path = robust path, and the METIS ordering changes nothing but speed:
 - Hertz levels 0-2 and the eccentric S2 load, each solved four ways on one
   rank: -kkt_path condensed (one factorization, steps on the multipliers) and
   full (the KKT matrix refactored each step), each with -kkt_ordering metis
   and mumps. Same number of active-set steps and the same active set; the
   displacement and the contact pressure agree to 1e-9 of their maxima;
 - the condensed path's recovered displacement satisfies K u + C^T lambda = f
   to 1e-10 of |f| (printed under -contact_monitor);
 - the METIS ordering is refused with one clear line nowhere: on 2 ranks it is
   silently MUMPS' own (PETSc hands MUMPS no permutation in parallel)."""
import re
import numpy as np
from m2d import check, mesh, opts, read_h5, run, solve, workdir

ways = [("condensed", "metis"), ("condensed", "mumps"), ("full", "metis"), ("full", "mumps")]
cases = [("hertz_%d" % lv, ["-options_file", opts("hertz"), "-mesh", mesh("hertz_%d" % lv)]) for lv in (0, 1, 2)]
cases.append(("s2_eccentric", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_10_31"), "-pressure", "upper_top:-1e6:4e6:0", "-exact", "none"]))

for name, base in cases:
    res = {}
    for path, order in ways:
        tag = "paths_%s_%s_%s" % (name, path, order)
        s = solve(tag, base + ["-kkt_path", path, "-kkt_ordering", order, "-output_vtu", "0", "-output_name", "sol"])
        _, _, vf, _ = read_h5(workdir(tag) + "/sol.h5")
        res[(path, order)] = (s, vf)
    s0, v0 = res[("full", "mumps")]
    u0 = v0["displacement"]
    p0 = v0["contact_pressure"] if "contact_pressure" in v0 else None
    for (path, order), (s, vf) in res.items():
        if (path, order) == ("full", "mumps"):
            continue
        check(s["kkt_path"] == path, "%s %s/%s: ran the %s path" % (name, path, order, s["kkt_path"]))
        check(s["iterations"] == s0["iterations"] and s["active_nodes"] == s0["active_nodes"],
              "%s %s/%s: %d steps, %d active (full/mumps: %d, %d)" % (name, path, order, s["iterations"], s["active_nodes"], s0["iterations"], s0["active_nodes"]))
        du = np.abs(vf["displacement"] - u0).max() / np.abs(u0).max()
        check(du < 1e-9, "%s %s/%s: displacement equal to %.1e of its maximum" % (name, path, order, du))
        if p0 is not None:
            dp = np.nanmax(np.abs(vf["contact_pressure"] - p0)) / np.nanmax(np.abs(p0))
            check(dp < 1e-9, "%s %s/%s: contact pressure equal to %.1e of its peak" % (name, path, order, dp))

# the recovered displacement of the condensed path satisfies the u rows
rc, out, err = run(["-options_file", opts("hertz"), "-mesh", mesh("hertz_2"), "-contact_monitor", "-output_dir", workdir("paths_monitor")])
m = re.search(r"recovered u: \|K u \+ C\^T lambda - f\| = (\S+) \(\|f\| = (\S+)\)", out)
check(m is not None and float(m.group(1)) < 1e-10 * float(m.group(2)), "condensed: |K u + C^T lambda - f| = %s, |f| = %s" % (m.group(1), m.group(2)) if m else "condensed: no recovered-u line in the monitor output")

# two ranks: the ordering option is accepted and the answer is MUMPS' own
s2 = solve("paths_2ranks", cases[0][1] + ["-kkt_ordering", "metis", "-output_vtu", "0", "-output_name", "sol"], ranks=2)
s1 = res_h0 = solve("paths_1rank_ref", cases[0][1] + ["-kkt_path", "full", "-kkt_ordering", "mumps", "-output_vtu", "0", "-output_name", "sol"])
check(s2["kkt_path"] == "full" and s2["iterations"] == s1["iterations"] and abs(s2["peak_pressure"] / s1["peak_pressure"] - 1) < 1e-9,
      "2 ranks with -kkt_ordering metis: full path, %d steps, peak pressure equal (%.1e)" % (s2["iterations"], abs(s2["peak_pressure"] / s1["peak_pressure"] - 1)))
