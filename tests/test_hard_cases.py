"""S4 hard cases of the mortar method (one check line each, then a count):
 1. interface mesh ratios 1:10 and 1:30 (patch_2_20, patch_20_2, patch_1_30,
    patch_30_1), fine and coarse side as non-mortar: mortar passes the patch
    test in all 8 runs; NTS passes it with the fine side non-mortar and fails
    it by more than half of p with the coarse side non-mortar;
 2. stiffness contrast 1e6 each way (upper E = 1e15 and 1e3, lower 1e9) on S2;
    with the stiff body floating, the round-off floor grows with the contrast
    (held to 3e-14 x contrast at 1e3 ... 1e6), with it supported it is gone;
 3. nearly incompressible bodies, nu = 0.49 and 0.4999 in plane strain: by
    default sri (a note says so), -q4_integration full given runs with a
    warning naming -q4_integration sri (it locks: Hertz level 2 at nu = 0.4999
    has a pressure error of 0.667); with sri (a) the S2 patch test passes, (b)
    the Hertz level 2 error stays within 1.5x of the nu = 0.3 error;
 4. interface inclined at 30 degrees (patch_incl30), self-equilibrated uniaxial
    stress normal to the interface, supports from the exact solution: sigma_nn
    = -p, sigma_tt = sigma_tn = 0 in both bodies, the displacement is the
    exact linear field, contact force p x 1;
 5. contact zones ending inside an edge (S1 with the lower body as
    non-mortar), non-mortar nodes projecting onto mortar nodes (patch_match and
    an exactly matching mesh written here), slivers of 1e-13 at the end of the
    mortar surface (patch_sliver): finite output, patch test / equilibrium;
 6. initial penetration and initial gap closed by a prescribed displacement;
 7. a body held only by contact (default, full KKT path, fieldsplit) and
    bodies held by nothing (one clear error line naming the body).
The "patch test" is max over cells of |sigma - exact| / p below 1e-10."""
import math
import os
import re

import numpy as np
from m2d import Tally, mesh, opts, read_csv, read_h5, read_json, run, workdir

TOL = 1e-10
E, NU, P = 1e9, 0.3, 1e6
S2 = ["-options_file", opts("patch_uniform"), "-mesh", mesh("patch_uniform"), "-output_vtu", "0", "-output_name", "sol"]
LOWER_NM = ["-contact_nonmortar", "lower_top", "-contact_mortar", "upper_bottom"]
T = Tally()
check = T.check


def note(msg):
    print("     " + msg, flush=True)


def solve(tag, args):
    """Run in WORK/hard_<tag>; return (rc, summary or None, stdout, stderr).
    A stale summary is removed first, so a failed run never reads an old one."""
    d = workdir("hard_" + tag)
    sfile = os.path.join(d, "summary.json")
    if os.path.exists(sfile):
        os.remove(sfile)
    rc, out, err = run(list(args) + ["-output_dir", d, "-summary", sfile], check=False)
    s = read_json(sfile) if rc == 0 and os.path.exists(sfile) else None
    return rc, s, out, err


def last_error(err):
    lines = [l for l in err.strip().splitlines() if l.strip()]
    return lines[-1] if lines else "(no message)"


def perr(s):
    e = s["error"]
    return max(e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"])


def finite_json(x):
    if isinstance(x, dict):
        return all(finite_json(v) for v in x.values())
    if isinstance(x, list):
        return all(finite_json(v) for v in x)
    if isinstance(x, float):
        return math.isfinite(x)
    return True


def contact_rows(tag, name="sol"):
    rows = read_csv(os.path.join(workdir("hard_" + tag), name + "_contact.csv"))
    return rows, [list(r.values()) for r in rows]


def body_errors(tag, p, name="sol"):
    """max |sigma_y + p|/p, |sigma_x|/p, |sigma_xy|/p per body from the HDF5."""
    _, _, _, cf = read_h5(os.path.join(workdir("hard_" + tag), name + ".h5"))
    b = cf["body"].ravel()
    out = []
    for k in np.unique(b):
        m = b == k
        out.append("body %d: %.1e %.1e %.1e" % (k, np.abs(cf["sigma_y"].ravel()[m] + p).max() / p,
                                               np.abs(cf["sigma_x"].ravel()[m]).max() / p, np.abs(cf["sigma_xy"].ravel()[m]).max() / p))
    return "; ".join(out)


def segments(out):
    m = re.search(r"(\d+) segments", out)
    return int(m.group(1)) if m else -1


# ---------------------------------------------------------------- 1. ratios
print("== 1. interface mesh ratios 1:10 and 1:30 (upper:lower elements along the interface)")
ratio_meshes = {"patch_2_20": (2, 20), "patch_20_2": (20, 2), "patch_1_30": (1, 30), "patch_30_1": (30, 1)}
for m, (nup, nlo) in ratio_meshes.items():
    for side, pair in (("upper", []), ("lower", LOWER_NM)):
        nm_n = nup if side == "upper" else nlo
        kind = "coarse" if nm_n < max(nup, nlo) else "fine"
        err = {}
        for method in ("mortar", "nts"):
            rc, s, out, e = solve("ratio_%s_%s_%s" % (m, side, method), S2 + ["-mesh", mesh(m), "-contact_method", method] + pair)
            err[method] = perr(s) if s else float("nan")
            if rc != 0:
                note("%s %s non-mortar %s: exit %d: %s" % (m, side, method, rc, last_error(e)))
        note("%s (%d:%d), %s (%s side) non-mortar: mortar %.2e, NTS %.2e" % (m, nup, nlo, side, kind, err["mortar"], err["nts"]))
        check(err["mortar"] < TOL, "ratio %d:%d, %s side non-mortar: mortar patch test (%.2e)" % (nup, nlo, kind, err["mortar"]))
        # NTS: the fine side as non-mortar passes the patch test; the coarse
        # side's few nodes cannot carry the uniform pressure: an O(p) error
        if kind == "fine":
            check(err["nts"] < TOL, "ratio %d:%d, fine side non-mortar: NTS passes the patch test too (%.2e)" % (nup, nlo, err["nts"]))
        else:
            check(err["nts"] > 0.5, "ratio %d:%d, coarse side non-mortar: NTS fails the patch test by more than p/2 (%.2e)" % (nup, nlo, err["nts"]))

# ---------------------------------------------------------------- 2. stiffness contrast
print("== 2. stiffness contrast 1e6 (lower E = 1e9)")
for Eu in ("1e15", "1e3"):
    # the soft upper body under p = 1 Pa: a strain of 1e-3 (p = 1e6 Pa strained it
    # by 1000, refused by the strain check: test_trust.py)
    pu = 1.0 if Eu == "1e3" else P
    load = ["-pressure", "upper_top:%r" % pu]
    rc, s, out, e = solve("contrast_%s" % Eu, S2 + ["-upper_E", Eu] + load)
    check(rc == 0, "upper E = %s: the run completes (%s)" % (Eu, "exit 0, %d steps" % s["iterations"] if rc == 0 else last_error(e)))
    tag = "contrast_%s" % Eu
    how = "default settings"
    if rc != 0:
        # measure what the discretisation gives when the active-set stop test is relaxed
        tag = "contrast_%s_rtol" % Eu
        rc, s, out, e = solve(tag, S2 + ["-upper_E", Eu, "-snes_rtol", "1e-6"] + load)
        how = "only with -snes_rtol 1e-6 (exit %d)" % rc
    if s:
        note("upper E = %s (%s): syy %.2e sxx %.2e sxy %.2e, force/p-1 = %.1e; %s" % (
            Eu, how, s["error"]["sigma_yy_max_rel"], s["error"]["sigma_xx_max_rel"], s["error"]["sigma_xy_max_rel"],
            s["contact_force"] / pu - 1, body_errors(tag, pu)))
    # E = 1e15 on a body that floats on the soft one: round-off floor ~ eps x contrast
    # x O(100) (see below; 0.9e-8 .. 1.2e-8 depending on the BLAS and the solve path),
    # so that variant is held to 3e-8; the supported variant below to 1e-10
    tol = TOL if Eu == "1e3" else 3e-8
    check(s is not None and perr(s) < tol, "upper E = %s: patch test to %.0e (%s, %s)" % (Eu, tol, "%.2e" % perr(s) if s else "no result", how))
# The stiff upper body rides on the soft one: it translates rigidly by the soft
# body's compression (~4.6e-4) while its own strain is 1e-6 of that, so one ulp
# of its nodal displacements is already ~ eps (E_up/E_lo)(H/h) p ~ 5e-10 p of stress.
# The error should grow like the contrast (printed), and vanish when the stiff
# body is the supported one (same interface, same contrast, load from below).
# Held to the same 3e-14 x contrast as E = 1e15 above (3e-8 at 1e6).
for Eu in ("1e12", "1e13", "1e14"):
    rc, s, out, e = solve("contrast_scan_%s" % Eu, S2 + ["-upper_E", Eu])
    contrast = float(Eu) / E
    check(s is not None and perr(s) < 3e-14 * contrast, "upper E = %s (contrast %.0e): patch test below 3e-14 x contrast = %.0e (%s)"
          % (Eu, contrast, 3e-14 * contrast, "%.2e" % perr(s) if s else last_error(e)))
rc, s, out, e = solve("contrast_1e15_stiff_held", S2 + ["-upper_E", "1e15", "-dirichlet", "upper_top:y,upper_left:x,lower_left:x,lower_origin:x", "-pressure", "lower_bottom:1e6"])
check(s is not None and perr(s) < TOL, "upper E = 1e15 held at its top, p on the lower bottom (soft body moves): patch test (%s)" % ("%.2e" % perr(s) if s else last_error(e)))

# ---------------------------------------------------------------- 3. incompressibility
print("== 3a. nearly incompressible, S2: sri by default (full integration locks), the patch test passes")
for nu in ("0.49", "0.4999"):
    rc, s, out, e = solve("incomp_s2_%s" % nu, S2 + ["-lower_nu", nu, "-upper_nu", nu])
    check(s is not None and s["q4_integration"] == "sri" and "note: nu = %s (-lower_nu) > 0.45 in plane strain" % nu in out and perr(s) < TOL,
          "S2 nu = %s, default: sri, with a note; patch test (%s)" % (nu, "%.2e" % perr(s) if s else last_error(e)))
    rc, s, out, e = solve("incomp_s2_sri_%s" % nu, S2 + ["-lower_nu", nu, "-upper_nu", nu, "-q4_integration", "sri"])
    check(s is not None and perr(s) < TOL and "note:" not in out, "S2 nu = %s, sri: patch test (%s)" % (nu, "%.2e" % perr(s) if s else last_error(e)))

print("== 3b. Hertz level 2, nu = 0.3, 0.49, 0.4999, -q4_integration full|sri")
_, hout, herr = run(["-help"], check=False)
has_sri = "-q4_integration" in hout + herr
check(has_sri, "-q4_integration is documented in -help")
H = ["-options_file", opts("hertz"), "-mesh", mesh("hertz_2"), "-output_vtu", "0", "-output_hdf5", "0", "-contact_monitor", "0"]
hl2 = {}
for integ in ("full", "sri"):
    for nu in ("0.3", "0.49", "0.4999"):
        args = H + ["-cylinder_nu", nu, "-block_nu", nu, "-q4_integration", integ]
        rc, s, out, e = solve("hertz_%s_%s" % (integ, nu), args)
        if integ == "full" and nu != "0.3":
            warn = [ln for ln in out.splitlines() if ln.startswith("warning: -q4_integration full")]
            check(rc == 0 and len(warn) == 1 and "locks" in warn[0] and "-q4_integration sri" in warn[0], "Hertz level 2, nu = %s, full given: runs with one warning (%s)" % (nu, warn[0] if warn else last_error(e)))
        check(rc == 0, "Hertz level 2, nu = %s, %s: the run completes (%s)" % (nu, integ, "%d steps" % s["iterations"] if rc == 0 else last_error(e)))
        hl2[(integ, nu)] = s["pressure_l2_rel"] if s else float("nan")
        if s:
            note("nu = %-6s %-4s: pressure_l2_rel %.3e, peak/p0 %.3f, %d steps" % (nu, integ, s["pressure_l2_rel"], s["peak_pressure"] / s["hertz_p0"], s["iterations"]))
ref = hl2[("sri", "0.3")]
note("regular case nu = 0.3: full %.3e, sri %.3e" % (hl2[("full", "0.3")], ref))
for nu in ("0.49", "0.4999"):
    check(hl2[("full", nu)] > 2 * hl2[("sri", nu)], "Hertz full nu = %s: locked, error %.3e > 2 x sri's %.3e" % (nu, hl2[("full", nu)], hl2[("sri", nu)]))
    r = hl2[("sri", nu)] / ref
    check(r <= 1.5, "Hertz sri nu = %s: error %.3e = %.2f x the nu = 0.3 error (<= 1.5)" % (nu, hl2[("sri", nu)], r))

# ---------------------------------------------------------------- 4. inclined interface
print("== 4. interface inclined at 30 degrees, uniaxial stress normal to it")
a = math.radians(30)
n = np.array([-math.sin(a), math.cos(a)])
t = np.array([math.cos(a), math.sin(a)])
eps = -P * (1 - NU * NU) / E * np.outer(n, n) + P * NU * (1 + NU) / E * np.outer(t, t)
uc2 = eps @ t            # lower_corner2 = R(30) (1, 0)
uuc = eps @ (0.5 * n)    # upper_corner  = R(30) (0, 0.5)
dirichlet = "lower_origin:xy:0,lower_corner2:x:%r,lower_corner2:y:%r,upper_corner:x:%r,upper_corner:y:%r" % (uc2[0], uc2[1], uuc[0], uuc[1])
for side, pair in (("upper", []), ("lower", LOWER_NM)):
    tag = "incl30_%s" % side
    rc, s, out, e = solve(tag, S2 + ["-mesh", mesh("patch_incl30"), "-exact", "none", "-pressure", "upper_top:%r,lower_bottom:%r" % (P, P), "-dirichlet", dirichlet] + pair)
    if rc != 0:
        check(False, "inclined, %s non-mortar: run failed: %s" % (side, last_error(e)))
        continue
    xy, cells, vf, cf = read_h5(os.path.join(workdir("hard_" + tag), "sol.h5"))
    sx, sy, sxy = cf["sigma_x"].ravel(), cf["sigma_y"].ravel(), cf["sigma_xy"].ravel()

    def proj(u, v):
        return u[0] * v[0] * sx + u[1] * v[1] * sy + (u[0] * v[1] + u[1] * v[0]) * sxy
    snn, stt, stn = proj(n, n), proj(t, t), proj(t, n)
    b = cf["body"].ravel()
    worst = 0.0
    for k in np.unique(b):
        m = b == k
        v = (np.abs(snn[m] + P).max() / P, np.abs(stt[m]).max() / P, np.abs(stn[m]).max() / P)
        worst = max(worst, *v)
        note("%s non-mortar, body %d: |snn+p|/p %.2e, |stt|/p %.2e, |stn|/p %.2e" % (side, k, *v))
    uerr = np.abs(vf["displacement"][:, :2] - xy[:, :2] @ eps.T).max() / np.abs(xy[:, :2] @ eps.T).max()
    check(uerr < TOL, "inclined, %s non-mortar: displacement = exact eps.x to %.1e relative" % (side, uerr))
    check(worst < TOL, "inclined, %s non-mortar: sigma_nn = -p, sigma_tt = sigma_tn = 0 in both bodies (%.2e)" % (side, worst))
    sign = 1 if side == "upper" else -1
    ferr = max(abs(s["contact_force"] / P - 1), abs(s["contact_force_x"] / P - sign * n[0]), abs(s["contact_force_y"] / P - sign * n[1]))
    check(ferr < TOL, "inclined, %s non-mortar: contact force = p x 1 along the normal (%.1e)" % (side, ferr))

# ---------------------------------------------------------------- 5. zone ends, coincident nodes, slivers
print("== 5. contact zones ending inside an edge, coincident nodes, slivers")
S1 = ["-options_file", opts("seed_patch"), "-mesh", mesh("seed_patch"), "-output_vtu", "0", "-output_name", "sol"]
sy_max = {}
for side, pair in (("upper", []), ("lower", LOWER_NM)):
    tag = "s1_%s" % side
    rc, s, out, e = solve(tag, S1 + pair)
    if rc != 0:
        check(False, "S1, %s non-mortar: run failed: %s" % (side, last_error(e)))
        continue
    rows, vals = contact_rows(tag)
    fin = all(math.isfinite(v) for r in vals for v in r) and finite_json(s)
    with open(os.path.join(workdir("hard_" + tag), "summary.json")) as f:
        fin = fin and "nan" not in f.read().lower()
    check(fin, "S1, %s non-mortar: no NaN/Inf in the contact CSV (%d rows x %d columns) or the summary" % (side, len(rows), len(rows[0]) if rows else 0))
    check(abs(s["contact_force"] / (0.5 * P) - 1) < TOL, "S1, %s non-mortar: total contact force = p x 0.5 (%.1e)" % (side, s["contact_force"] / (0.5 * P) - 1))
    _, _, _, cf = read_h5(os.path.join(workdir("hard_" + tag), "sol.h5"))
    sy_max[side] = np.abs(cf["sigma_y"]).max()
    note("S1, %s non-mortar: %d multipliers, weights %s, max |sigma_y| = %.6e" % (side, s["contact_nodes"], ", ".join("%.4g" % r[4] for r in vals), sy_max[side]))
if len(sy_max) == 2:
    note("S1: max |sigma_y| lower non-mortar - upper non-mortar = %.4e (%.3e p)" % (sy_max["lower"] - sy_max["upper"], (sy_max["lower"] - sy_max["upper"]) / P))


def write_match_msh(path, nx=10, ny=5):
    """Gmsh 2.2 S2 mesh with nx:nx elements on the interface, every coordinate
    i/nx, j/(2 ny) computed identically for both bodies: the interface nodes
    coincide bit for bit (gmsh's patch_match has them 1e-12 apart)."""
    nodes, elems = [], []

    def node(x, y):
        nodes.append((x, y))
        return len(nodes)

    def body(y0, phys, curves, corners):
        ids = [[node(i / nx, y0 + j / (2 * ny)) for i in range(nx + 1)] for j in range(ny + 1)]
        for j in range(ny):
            for i in range(nx):
                elems.append((3, phys, [ids[j][i], ids[j][i + 1], ids[j + 1][i + 1], ids[j + 1][i]]))
        bottom, right, top, left = curves
        for i in range(nx):
            elems.append((1, bottom, [ids[0][i], ids[0][i + 1]]))
            elems.append((1, top, [ids[ny][i + 1], ids[ny][i]]))
        for j in range(ny):
            elems.append((1, right, [ids[j][nx], ids[j + 1][nx]]))
            elems.append((1, left, [ids[j + 1][0], ids[j][0]]))
        for tag, (i, j) in corners:
            elems.append((15, tag, [ids[j][i]]))
    body(0.0, 1, (11, 12, 13, 14), [(31, (0, 0)), (33, (nx, 0))])
    body(0.5, 2, (21, 22, 23, 24), [(32, (0, 0))])
    names = [(2, 1, "lower"), (2, 2, "upper"), (1, 11, "lower_bottom"), (1, 12, "lower_right"), (1, 13, "lower_top"), (1, 14, "lower_left"),
             (1, 21, "upper_bottom"), (1, 22, "upper_right"), (1, 23, "upper_top"), (1, 24, "upper_left"),
             (0, 31, "lower_origin"), (0, 32, "upper_corner"), (0, 33, "lower_corner2")]
    with open(path, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n%d\n" % len(names))
        f.writelines('%d %d "%s"\n' % nm for nm in names)
        f.write("$EndPhysicalNames\n$Nodes\n%d\n" % len(nodes))
        f.writelines("%d %r %r 0\n" % (k + 1, x, y) for k, (x, y) in enumerate(nodes))
        f.write("$EndNodes\n$Elements\n%d\n" % len(elems))
        f.writelines("%d %d 2 %d %d %s\n" % (k + 1, typ, ph, ph, " ".join(map(str, c))) for k, (typ, ph, c) in enumerate(elems))
        f.write("$EndElements\n")


exact_match = os.path.join(workdir("hard_meshes"), "patch_match_exact.msh")
write_match_msh(exact_match)
for label, mfile in (("patch_match", mesh("patch_match")), ("exact match", exact_match), ("patch_sliver", mesh("patch_sliver"))):
    for side, pair in (("upper", []), ("lower", LOWER_NM)):
        for basis in ("standard", "dual"):
            tag = "coinc_%s_%s_%s" % (label.replace(" ", "_"), side, basis)
            rc, s, out, e = solve(tag, S2 + ["-mesh", mfile, "-mortar_basis", basis] + pair)
            if rc != 0:
                check(False, "%s, %s non-mortar, %s: run failed: %s" % (label, side, basis, last_error(e)))
                continue
            rows, vals = contact_rows(tag)
            fin = all(math.isfinite(v) for r in vals for v in r) and finite_json(s)
            check(fin and perr(s) < TOL and abs(s["contact_force"] / P - 1) < TOL,
                  "%s, %s non-mortar, %s: patch test %.2e, force/p-1 %.1e, finite output; %d multipliers, %d segments"
                  % (label, side, basis, perr(s), s["contact_force"] / P - 1, s["contact_nodes"], segments(out)))

# ---------------------------------------------------------------- 6. initial gap / penetration
print("== 6. initial penetration and initial gap, upper top pushed down by delta")
SUP = "lower_bottom:y,lower_origin:x,lower_left:x,upper_left:x"
for m, g0, delta in (("patch_pen", -0.01, 0.0), ("patch_pen", -0.01, 0.005), ("patch_gap", 0.01, 0.02)):
    Pex = E * (delta - g0) / ((1 - NU * NU) * 1.0)
    rc, s, out, e = solve("init_%s_%g" % (m, delta), S2 + ["-mesh", mesh(m), "-pressure", "", "-dirichlet", SUP + ",upper_top:y:%r" % -delta, "-exact", "uniform", "-exact_p", repr(Pex)])
    ok = s is not None and perr(s) < TOL and s["active_nodes"] == s["contact_nodes"] and abs(s["contact_force"] / Pex - 1) < TOL
    check(ok, "%s (g0 = %+g), delta = %g: sigma_yy = -%.6e, patch test %s, %s active nodes" % (
        m, g0, delta, Pex, "%.2e" % perr(s) if s else last_error(e), "%d/%d" % (s["active_nodes"], s["contact_nodes"]) if s else "?"))

# ---------------------------------------------------------------- 7. bodies held only by contact / by nothing
print("== 7. a body held only by contact; bodies held by nothing")
for label, extra in (("default solver", []), ("-kkt_path full", ["-kkt_path", "full"]), ("kkt_fieldsplit.opts", ["-options_file", opts("kkt_fieldsplit")])):
    rc, s, out, e = solve("held_%s" % label.split()[0].strip("-").replace(".", "_"), S2 + extra)
    check(s is not None and perr(s) < TOL, "S2, upper body held vertically only by contact, %s: patch test (%s)" % (label, "%.2e" % perr(s) if s else last_error(e)))
free = [("no support in x for 'upper'", S2 + ["-dirichlet", "lower_bottom:y,lower_origin:x,lower_left:x"]),
        ("no contact, no load, 'upper' held only by upper_left:x", S2 + ["-contact_nonmortar", "", "-contact_mortar", "", "-exact", "none", "-pressure", ""])]
for k, (label, args) in enumerate(free):
    rc, s, out, e = solve("free_%d" % k, args)
    lines = [l for l in e.strip().splitlines() if l.strip()]
    msg = lines[0] if lines else "(nothing on stderr)"
    good = (rc == 1 and len(lines) == 1 and msg.startswith("mortar2d: error:") and "'upper'" in msg
            and ("held by nothing" in msg or "rigid" in msg)
            and not re.search(r"factor|mumps|petsc error|singular|pivot", out + e, re.I) and "active set step" not in out)
    check(good, "%s: exit %d, stopped before any solve with: %s" % (label, rc, msg))

T.finish()
