"""The roller (options/roller.opts): a cylinder between two plates, two Hertz
contacts (issue 24).
- condensed = full = iterative, 1 and 2 ranks: every pressure to 1e-8 of the peak;
- each pair's pressure against Hertz within 1.25 x the error of the one-contact
  Hertz scene at the same level (the same node spacing at the contact);
- the two pressures equal each other to the mesh's symmetry: the contact
  surfaces' nodes are mirror images (checked), the meshes inside are gmsh's
  two nearly mirrored halves, so the two agree to a fraction of their
  distance from Hertz;
- adaptive (options/roller_adapt.opts, 4 meshes): at most 3 active-set steps per
  mesh after the first, both pairs' errors falling."""
import math
import os

from m2d import Tally, csv_columns, mesh, opts, solve, workdir

T = Tally()
ROLLER = ["-options_file", opts("roller"), "-mesh", mesh("roller_1"), "-output", "csv,summary"]


def roller(name, extra, ranks=1):
    s = solve("roller/" + name, ROLLER + extra, ranks=ranks)
    return s, csv_columns(os.path.join(workdir("roller/" + name), "roller_contact.csv"))


ref, c0 = roller("condensed_1", [])
peak = max(c0["pressure"])
for path in ("condensed", "full", "iterative"):
    for ranks in (1, 2):
        if (path, ranks) == ("condensed", 1):
            continue
        s, c = roller("%s_%d" % (path, ranks), ["-kkt_path", path], ranks)
        d = max(abs(c["pressure"] - c0["pressure"])) / peak if len(c["pressure"]) == len(c0["pressure"]) else math.inf
        T.check(d <= 1e-8 and s["active_nodes"] == ref["active_nodes"], "%s path, %d rank(s): the pressures of the condensed path on 1 rank" % (path, ranks), "%.1e of the peak" % d)

hz = solve("roller/hertz_1", ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1"), "-output", "summary"])
e = [p["pressure_l2_rel"] for p in ref["pairs"]]
T.check(len(e) == 2 and max(e) <= 1.25 * hz["pressure_l2_rel"], "each contact within 1.25 x the Hertz scene's error at level 1 (%.3e)" % hz["pressure_l2_rel"], "%.3e, %.3e" % tuple(e))
T.check([p["active_nodes"] for p in ref["pairs"]] == [ref["active_nodes"] // 2] * 2, "as many active nodes at each contact", str([p["active_nodes"] for p in ref["pairs"]]))
top, bot = c0["pair"] == 1, c0["pair"] == 2
T.check(max(abs(c0["x"][top] - c0["x"][bot])) < 1e-7 and max(abs(c0["y"][top] + c0["y"][bot])) < 1e-7, "the two contact surfaces' nodes are mirror images (to gmsh's 4e-9 on the arcs)")
diff = math.sqrt(sum((c0["pressure"][top] - c0["pressure"][bot]) ** 2) / sum(c0["pressure"][top] ** 2))
T.check(diff <= min(e), "the two pressures agree to the mesh's symmetry: relative L2 difference %.2e, below the smaller Hertz error %.2e" % (diff, min(e)))
forces = [p["contact_force_y"] for p in ref["pairs"]]
T.check(abs(forces[0] + 0.43) < 1e-9 and abs(forces[1] - 0.43) < 1e-9, "each contact carries the load 4q = 0.43 (the roller pushed down at the top, up at the bottom)", str(forces))

# the adaptive loop over both contacts
a = solve("roller/adapt", ["-options_file", opts("roller_adapt"), "-adapt_max_dofs", "20000", "-adapt_max_steps", "4", "-output", "summary"])
steps = a["adapt"]
its = [st["iterations"] for st in steps]
T.check(len(steps) == 4 and max(its[1:]) <= 3, "adaptive roller: at most 3 active-set steps per mesh after the first", str(its))
T.check(max(p["pressure_l2_rel"] for p in a["pairs"]) < min(e), "adaptive roller: both contacts' Hertz errors below the level-1 mesh's (%.3e)" % min(e), str([p["pressure_l2_rel"] for p in a["pairs"]]))
T.finish()
