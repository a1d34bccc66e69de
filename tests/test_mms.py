"""Manufactured solution with a body force on the unit square:
u = A (sin(pi x) cos(pi y), cos(pi x) sin(pi y)); Dirichlet data from u on the
whole boundary. The L2 displacement error of Q4 must fall at rate 2 (between
1.9 and 2.1) over 4 refinements (4x4 ... 64x64)."""
import math
from m2d import check, mesh, solve

levels = (4, 8, 16, 32, 64)
args = ["-bodies", "block", "-block_E", "1e3", "-block_nu", "0.3", "-dirichlet", "bottom:xy,right:xy,top:xy,left:xy", "-exact", "mms", "-output_vtu", "0"]
rows = []
for n in levels:
    s = solve("mms_%d" % n, args + ["-mesh", mesh("block_%d" % n)])
    rows.append((n, s["dofs"], s["error"]["h"], s["error"]["u_l2"]))
print("%6s %8s %12s %14s %8s" % ("n", "dofs", "h", "L2 error", "rate"))
rates = []
for i, (n, dofs, h, e) in enumerate(rows):
    rate = math.log(rows[i - 1][3] / e) / math.log(rows[i - 1][2] / h) if i else float("nan")
    if i:
        rates.append(rate)
    print("%6d %8d %12.4e %14.6e %8.3f" % (n, dofs, h, e, rate))
for r in rates:
    check(1.9 <= r <= 2.1, "L2 rate %.3f in [1.9, 2.1]" % r)
