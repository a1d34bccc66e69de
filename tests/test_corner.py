"""Corners of contact surfaces (issue 33 item 6; meshes/corner.geo: a square
punch with sharp corners on a foundation whose top may have a groove). A
contact curve with a corner gives the answer of the same curve ended at the
corner, to round-off (displacements and cell stresses to 1e-10 of their
largest), standard and dual multipliers, 1 and 2 ranks:
 - the punch's sharp corners in the non-mortar curve (bottom and both sides)
   and in the mortar curve, against the bottom alone;
 - a groove on the mortar surface that the punch cannot reach, against the
   mortar curve ended before it (the 45-degree check refused this);
 - a groove under the punch on the non-mortar side (the foundation's top with
   the groove's lips, walls and floor), against the two flat parts as two
   pairs.
Refused, one line naming the pair, the curve, the corner and the cure: a
groove under the punch on the mortar side. Its lip is a convex mortar corner
that the punch's rows reach on both sides (the top beside it, the groove's
floor within -contact_reach): the rows hold the punch's nodes and average
the gaps on both sides, and the lip passed between the nodes (27% of the
largest displacement, measured with the check off: docs/trust.md)."""
import numpy as np

from m2d import Tally, mesh, refusal_problems, run, solve, sorted_fields, workdir

T = Tally()
BASE = ["-bodies", "foundation,punch", "-foundation_E", "1e9", "-foundation_nu", "0.3", "-punch_E", "2e9", "-punch_nu", "0.3",
        "-plane", "strain", "-dirichlet", "foundation_bottom:xy,punch_corner:x", "-pressure", "punch_top:1e6",
        "-contact_reach", "0.3", "-output_vtu", "0", "-output_name", "c"]


def pair(nm, m):
    return ["-contact_nonmortar", nm, "-contact_mortar", m]


def fields(tag, msh, extra, ranks):
    s = solve("corner/%s_%d" % (tag, ranks), BASE + ["-mesh", mesh(msh)] + extra, ranks)
    v, c, _, _ = sorted_fields(workdir("corner/%s_%d" % (tag, ranks)) + "/c.h5")
    return s, v, c


CASES = [
    ("the punch's sharp corners in the non-mortar curve", "corner_0", pair("punch_wrap", "foundation_top"), pair("punch_bottom", "foundation_top")),
    ("the punch's sharp corners in the mortar curve", "corner_0", pair("foundation_top", "punch_wrap"), pair("foundation_top", "punch_bottom")),
    ("a groove the punch cannot reach in the mortar curve", "corner_1", pair("punch_bottom", "foundation_top"), pair("punch_bottom", "foundation_left")),
    ("a groove under the punch in the non-mortar curve", "corner_2", pair("foundation_top", "punch_bottom"), ["-contact_pairs", "foundation_left:punch_bottom,foundation_right:punch_bottom"]),
]
for what, msh, with_corner, ended in CASES:
    for basis in ("standard", "dual"):
        for ranks in (1, 2):
            tag = "%s_%s_%s" % (msh, "_".join(with_corner[1::2]), basis)
            sa, va, ca = fields(tag + "_a", msh, with_corner + ["-mortar_basis", basis], ranks)
            sb, vb, cb = fields(tag + "_b", msh, ended + ["-mortar_basis", basis], ranks)
            du = np.abs(va["displacement"] - vb["displacement"]).max() / np.abs(vb["displacement"]).max()
            ds = max(np.abs(ca[k] - cb[k]).max() for k in ("sigma_x", "sigma_y", "sigma_xy")) / np.abs(cb["sigma_y"]).max()
            T.check(du < 1e-10 and ds < 1e-10, "%s (%s, %d rank%s): the answer of the curve ended at the corner" % (what, basis, ranks, "s" if ranks > 1 else ""),
                    "displacement %.1e, cell stress %.1e" % (du, ds))

for ranks in (1, 2):
    rc, _, err = run(BASE + ["-mesh", mesh("corner_2"), "-output_dir", workdir("corner/refused")] + pair("punch_bottom", "foundation_top"), ranks=ranks, check=False)
    line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()],
                                      ("-contact_mortar foundation_top", "mortar surface 'foundation_top' has a corner at (", "turning by 90 degrees", "'punch_bottom' reaches on both sides", "make 'foundation_top' the non-mortar side"))
    T.check(not problems, "a groove under the punch on the mortar side, %d rank%s: refused in one line" % (ranks, "s" if ranks > 1 else ""), "; ".join(problems) or line)
T.finish()
