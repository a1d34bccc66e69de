"""The condensed path = the full path, and the METIS ordering changes nothing but speed:
 - Hertz levels 0-2 and the eccentric S2 load, each solved five ways on one
   rank: -kkt_path condensed (one factorization, steps on the multipliers) and
   full (the KKT matrix refactored each step), each with -kkt_ordering metis
   and mumps, and the condensed path with LU instead of LDL^T (-kkt_ldlt 0). Same number of active-set steps and the same active set; the
   displacement and the contact pressure agree to 1e-9 of their maxima;
 - the condensed path's recovered displacement satisfies K u + C^T lambda = f
   to 1e-10 of |f| (the summary's residual_rel);
 - 2 ranks: the condensed path runs there too (every rank factors its own
   rows; the rows coupled to a higher rank and the multipliers are the dense
   interface), with the same steps, active set and fields (to 1e-9) as one
   rank's full path, for both orderings; its recovered displacement
   satisfies the u rows as well; 3 ranks (a rank with neighbours on both
   sides) with the METIS ordering give the same;
 - -kkt_ordering auto (the default) orders Hertz level 2 (16,516 dofs) with
   MUMPS' own on 1 rank and METIS on 2, level 4 (249,348) with METIS (the
   summary's kkt_ordering)."""
import numpy as np
from m2d import check, mesh, opts, read_h5, solve, sorted_fields, workdir

ways = [("condensed", "metis"), ("condensed", "mumps"), ("full", "metis"), ("full", "mumps"), ("condensed-lu", "metis")]
cases = [("hertz_%d" % lv, ["-options_file", opts("hertz"), "-mesh", mesh("hertz_%d" % lv)]) for lv in (0, 1, 2)]
cases.append(("s2_eccentric", ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_10_31"), "-pressure", "upper_top:-1e6:4e6:0", "-exact", "none"]))

for name, base in cases:
    res = {}
    for path, order in ways:
        tag = "paths_%s_%s_%s" % (name, path, order)
        extra = ["-kkt_ldlt", "0"] if path == "condensed-lu" else []  # the condensed path's LU instead of LDL^T
        s = solve(tag, base + ["-kkt_path", path.split("-")[0], "-kkt_ordering", order, "-output_vtu", "0", "-output_name", "sol"] + extra)
        _, _, vf, _ = read_h5(workdir(tag) + "/sol.h5")
        res[(path, order)] = (s, vf)
    s0, v0 = res[("full", "mumps")]
    u0 = v0["displacement"]
    p0 = v0["contact_pressure"] if "contact_pressure" in v0 else None
    for (path, order), (s, vf) in res.items():
        if (path, order) == ("full", "mumps"):
            continue
        check(s["kkt_path"] == path.split("-")[0], "%s %s/%s: ran the %s path" % (name, path, order, s["kkt_path"]))
        check(s["iterations"] == s0["iterations"] and s["active_nodes"] == s0["active_nodes"],
              "%s %s/%s: %d steps, %d active (full/mumps: %d, %d)" % (name, path, order, s["iterations"], s["active_nodes"], s0["iterations"], s0["active_nodes"]))
        du = np.abs(vf["displacement"] - u0).max() / np.abs(u0).max()
        check(du < 1e-9, "%s %s/%s: displacement equal to %.1e of its maximum" % (name, path, order, du))
        if p0 is not None:
            dp = np.nanmax(np.abs(vf["contact_pressure"] - p0)) / np.nanmax(np.abs(p0))
            check(dp < 1e-9, "%s %s/%s: contact pressure equal to %.1e of its peak" % (name, path, order, dp))

# the recovered displacement of the condensed path satisfies the u rows (the
# program's own check, written to the summary as residual_rel)
s = solve("paths_monitor", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_2")])
check(s["kkt_path"] == "condensed" and s["residual_rel"] < 1e-10, "condensed: |K u + C^T lambda - f| / |f| = %.2e" % s["residual_rel"])
check(s["complementarity"] < 1e-10, "condensed: complementarity %.2e" % s["complementarity"])
# -kkt_ordering auto (the default): MUMPS' own below 2e5 dofs, METIS from there
s4 = solve("paths_auto_l4", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_4"), "-output_vtu", "0", "-error_estimate", "0"])
check(s["dofs"] < 200000 and s.get("kkt_ordering") == "mumps", "auto ordering: %d dofs ordered by %s (mumps below 2e5)" % (s["dofs"], s.get("kkt_ordering")))
check(s4["dofs"] >= 200000 and s4.get("kkt_ordering") == "metis", "auto ordering: %d dofs ordered by %s (metis from 2e5)" % (s4["dofs"], s4.get("kkt_ordering")))
s2r = solve("paths_auto_2ranks", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_2"), "-output_vtu", "0", "-error_estimate", "0"], ranks=2)
check(s2r.get("kkt_ordering") == "metis", "auto ordering: %d dofs on 2 ranks ordered by %s (metis on several ranks)" % (s2r["dofs"], s2r.get("kkt_ordering")))

# two ranks: the condensed path, both orderings, against one rank's full path
for name, base in cases:
    ref = solve("paths2_%s_ref" % name, base + ["-kkt_path", "full", "-kkt_ordering", "mumps", "-output_name", "sol", "-output_vtu", "0"])
    vr = sorted_fields(workdir("paths2_%s_ref" % name) + "/sol.h5")[0]
    for nr, order in ((2, "metis"), (2, "mumps"), (3, "metis")):
        tag = "paths%d_%s_%s" % (nr, name, order)
        s = solve(tag, base + ["-kkt_path", "condensed", "-kkt_ordering", order, "-output_name", "sol", "-output_vtu", "0"], ranks=nr)
        v = sorted_fields(workdir(tag) + "/sol.h5")[0]
        check(s["kkt_path"] == "condensed" and s["ranks"] == nr, "%s %d ranks/%s: ran the %s path on %d ranks" % (name, nr, order, s["kkt_path"], s["ranks"]))
        check(s["iterations"] == ref["iterations"] and s["active_nodes"] == ref["active_nodes"],
              "%s %d ranks/%s: %d steps, %d active (1 rank full: %d, %d)" % (name, nr, order, s["iterations"], s["active_nodes"], ref["iterations"], ref["active_nodes"]))
        du = np.abs(v["displacement"] - vr["displacement"]).max() / np.abs(vr["displacement"]).max()
        dp = np.abs(v["contact_pressure"] - vr["contact_pressure"]).max() / np.abs(vr["contact_pressure"]).max()
        check(du < 1e-9 and dp < 1e-9, "%s %d ranks/%s: displacement %.1e, pressure %.1e of the 1-rank full path" % (name, nr, order, du, dp))
s = solve("paths_monitor2", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_2")], ranks=2)
check(s["residual_rel"] < 1e-10 and s["complementarity"] < 1e-10, "condensed, 2 ranks: |K u + C^T lambda - f| / |f| = %.2e, complementarity %.2e" % (s["residual_rel"], s["complementarity"]))
