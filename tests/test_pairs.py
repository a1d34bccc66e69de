"""Several contact pairs (issue 24), on the stack scene (three blocks, two
non-matching interfaces, options/stack.opts):
- the patch test across both interfaces: mortar (standard and dual) exact to
  1e-12 of p in every body and in every pair's pressure on the condensed and
  iterative paths, 1 and 2 ranks (the full path, MUMPS' LU of the whole KKT
  matrix, to 1e-10: its round-off is 2e-13 on S2's one interface already);
  node-to-segment is not exact;
- condensed = full = iterative (pressures to 1e-8 of the peak);
- three -mesh files give the answer of the one file;
- the summary's list "pairs" (groups, method, nodes, force), the CSV's pair column;
- the shared-node rule: a node on two non-mortar surfaces carries one
  multiplier in each pair (each p in the patch test);
- one-line errors (exit 1): a missing group, a group on two bodies, a pair
  on one body, the same pair twice (either way round), a malformed entry."""
import os

from m2d import Tally, csv_columns, mesh, opts, refusal_problems, run, solve, workdir

P = 1e6
T = Tally()
STACK = ["-options_file", opts("stack"), "-mesh", mesh("stack"), "-output", "csv,summary"]


def stack(name, extra, ranks=1):
    s = solve("pairs/" + name, STACK + ["-output_name", "stack"] + extra, ranks=ranks)
    c = csv_columns(os.path.join(workdir("pairs/" + name), "stack_contact.csv"))
    return s, c


def stress_err(s):
    e = s["error"]
    return max(e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"])


# ---------- the patch test on both interfaces ----------
ref = {}
for basis in ("standard", "dual"):
    paths = ("condensed", "full") + (("iterative",) if basis == "dual" else ())
    for path in paths:
        for ranks in (1, 2):
            name = "%s_%s_%d" % (basis, path, ranks)
            s, c = stack(name, ["-mortar_basis", basis, "-kkt_path", path], ranks)
            perr = [max(abs(c["pressure"][c["pair"] == k] / P - 1)) for k in (1, 2)]
            tol = 1e-10 if path == "full" else 1e-12
            T.check(stress_err(s) <= tol and max(perr) <= tol, "%s: mortar %s exact across both interfaces (%g)" % (name, basis, tol),
                    "stress %.2e, pressure pair 1 %.2e, pair 2 %.2e" % (stress_err(s), perr[0], perr[1]))
            T.check(len(s["pairs"]) == 2 and all(abs(p["contact_force"] / P - 1) < 1e-12 for p in s["pairs"]), "%s: each pair carries p x 1 m" % name)
            if basis == "dual":
                if "dual" in ref:
                    d = max(abs(c["pressure"] - ref["dual"]["pressure"])) / max(ref["dual"]["pressure"])
                    T.check(d <= 1e-8 and (c["x"] == ref["dual"]["x"]).all(), "%s: pressures equal those of the condensed path on 1 rank" % name, "%.1e of the peak" % d)
                else:
                    ref["dual"] = c

for ranks in (1, 2):
    s, c = stack("nts_%d" % ranks, ["-contact_method", "nts"], ranks)
    T.check(stress_err(s) > 1e-3, "nts, %d rank(s): not exact (as on one interface)" % ranks, "%.2e" % stress_err(s))

# ---------- the summary and the CSV ----------
s, c = stack("summary", [])
p = s["pairs"]
T.check([(q["nonmortar"], q["mortar"]) for q in p] == [("mid_bottom", "base_top"), ("top_bottom", "mid_top")], "summary: pairs name their groups in order")
T.check([q["method"] for q in p] == ["mortar standard"] * 2, "summary: each pair's method")
T.check([q["contact_nodes"] for q in p] == [8, 14] and [q["active_nodes"] for q in p] == [8, 14] and s["contact_nodes"] == 22, "summary: contact and active nodes per pair (8 and 14, 22 in all)")
T.check(sorted(set(c["pair"])) == [1, 2] and sum(c["pair"] == 1) == 8, "CSV: a pair column, 8 rows of pair 1")
s, c = stack("own_method", ["-contact_pairs", "mid_bottom:base_top:dual,top_bottom:mid_top:nts"])
T.check([q["method"] for q in s["pairs"]] == ["mortar dual", "nts"], "per-pair method NM:M:dual, NM:M:nts")

# ---------- three mesh files ----------
s3, c3 = stack("three_files", ["-mesh", ",".join(mesh("stack_%d" % b) for b in (1, 2, 3)), "-dirichlet", "base_bottom:y,base_origin:x,base_left:x,mid_left:x,top_left:x"])
s1, c1 = stack("one_file", [])
d = max(abs(c3["pressure"] - c1["pressure"]))
T.check(s3["dofs"] == s1["dofs"] and d <= 1e-8 * P and stress_err(s3) <= 1e-12, "-mesh with three files: the one file's answer", "pressure diff %.1e" % d)

# ---------- shared-node rule ----------
s, c = stack("shared", ["-mesh", mesh("stack_split"), "-contact_pairs", "mid_bottom_a:base_top,mid_bottom_b:base_top,top_bottom:mid_top"])
at = abs(c["x"] - 3 / 7) < 1e-12
at &= abs(c["y"] - 0.4) < 1e-12
T.check(sorted(c["pair"][at]) == [1, 2], "shared node (3/7, 0.4): one multiplier in each of its two pairs")
T.check(max(abs(c["pressure"][at] / P - 1)) <= 1e-12 and stress_err(s) <= 1e-12, "shared node: each multiplier is p, the patch test exact")

s, c = stack("shared_iterative", ["-mesh", mesh("stack_split"), "-mortar_basis", "dual", "-kkt_path", "iterative", "-contact_pairs", "mid_bottom_a:base_top,mid_bottom_b:base_top,top_bottom:mid_top"])
at = (abs(c["x"] - 3 / 7) < 1e-12) & (abs(c["y"] - 0.4) < 1e-12)
T.check(sorted(c["pair"][at]) == [1, 2] and max(abs(c["pressure"][at] / P - 1)) <= 1e-12 and stress_err(s) <= 1e-12, "shared node on the iterative path (two rows, one node): exact")

# ---------- errors ----------
cases = [
    (["-contact_pairs", "nothere:base_top"], ["-contact_pairs", "nothere"]),
    (["-contact_pairs", "left:base_top"], ["-contact_pairs", "left", "more than one body"]),
    (["-contact_pairs", "mid_bottom:mid_top"], ["-contact_pairs", "mid_bottom:mid_top", "'mid'"]),
    (["-contact_pairs", "mid_bottom:base_top,top_bottom:mid_top,mid_bottom:base_top"], ["pair 3", "same pair", "pair 1"]),
    (["-contact_pairs", "mid_bottom:base_top,base_top:mid_bottom"], ["pair 2", "same pair"]),
    (["-contact_pairs", "mid_bottom"], ["-contact_pairs", "mid_bottom"]),
    (["-contact_pairs", "mid_bottom:base_top:quad"], ["-contact_pairs", "quad"]),
    (["-contact_nonmortar", "mid_bottom", "-contact_mortar", "base_top"], ["-contact_pairs", "not both"]),
    (["-kkt_path", "iterative", "-mortar_basis", "dual", "-contact_pairs", "mid_bottom:base_top:standard,top_bottom:mid_top"], ["-kkt_path iterative", "pair 1", "mid_bottom:base_top"]),
]
for args, culprits in cases:
    for ranks in (1, 2):
        rc, out, err = run(STACK + ["-output", "none"] + args, ranks=ranks, check=False)
        line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()], culprits)
        T.check(not problems, "%s (%d rank%s): %s" % (" ".join(args), ranks, "s" if ranks > 1 else "", line), "; ".join(problems))
rc, out, err = run(["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform"), "-output", "none", "-contact_nonmortar", "upper_bottom,lower_top"], check=False)
line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()], ["-contact_nonmortar", "-contact_pairs"])
T.check(not problems, "-contact_nonmortar with two groups points to -contact_pairs: " + line, "; ".join(problems))
T.finish()
