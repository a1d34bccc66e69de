"""Effectivity study of the error estimator (not a ctest: minutes; the README
tables come from it). Runs build/tests/estimator_main (a copy of main.c with
the estimator call) and prints:
  * MMS (block_N, N = 4..64): estimate / true energy-norm error (exact solution);
  * S2 (patch_uniform), mortar and NTS: estimate, true error (exact uniform stress);
  * Hertz levels: estimate against the pressure error (pressure_l2_rel) and
    against the energy-norm error relative to a finer level's solution (the
    reference stress evaluated at the coarse level's 3x3 Gauss points);
  * where the largest indicators are (S1 corners, Hertz zone edge).

  /usr/bin/python3 tests/estimator_study.py [--hertz 0,1,2,3,4] [--ref 5] [--mms 4,8,16,32,64]

The reference level must exist (level 5: bash tools/hertz_mesh.sh 5)."""
import argparse
import json
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import m2d  # noqa: E402

# the program itself writes the estimator (error_indicator, error_estimate)
EXE = m2d.EXE
G3 = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
W3 = np.array([5 / 9, 8 / 9, 5 / 9])
SX = np.array([-1.0, 1.0, 1.0, -1.0])
SY = np.array([-1.0, -1.0, 1.0, 1.0])


def run(name, args, ranks=1):
    """Run estimator_main with HDF5 output in WORK/name; return (summary, h5 path)."""
    d = m2d.workdir(name)
    summary = os.path.join(d, "summary.json")
    exe, m2d.EXE = m2d.EXE, EXE
    try:
        m2d.run(list(args) + ["-output_dir", d, "-output_name", "out", "-summary", summary, "-output_vtu", "0", "-contact_monitor", "0"], ranks=ranks)
    finally:
        m2d.EXE = exe
    with open(summary) as f:
        return json.load(f), os.path.join(d, "out.h5")


def plane_strain_D(E, nu):
    c = E / ((1 + nu) * (1 - 2 * nu))
    return c * np.array([[1 - nu, nu, 0], [nu, 1 - nu, 0], [0, 0, (1 - 2 * nu) / 2]])


def shape(xi, eta):
    """N (n,4), dN/dxi (n,4), dN/deta (n,4) at reference points."""
    N = 0.25 * (1 + SX * xi[:, None]) * (1 + SY * eta[:, None])
    dxi = 0.25 * SX * (1 + SY * eta[:, None])
    deta = 0.25 * SY * (1 + SX * xi[:, None])
    return N, dxi, deta


def stress(X, U, xi, eta, D):
    """FE stress (n,3) and det J (n) in cells with corners X (n,4,2), displacements U (n,4,2)."""
    _, dxi, deta = shape(xi, eta)
    J00 = (dxi * X[:, :, 0]).sum(1)
    J01 = (deta * X[:, :, 0]).sum(1)
    J10 = (dxi * X[:, :, 1]).sum(1)
    J11 = (deta * X[:, :, 1]).sum(1)
    det = J00 * J11 - J01 * J10
    dx = (J11[:, None] * dxi - J10[:, None] * deta) / det[:, None]
    dy = (-J01[:, None] * dxi + J00[:, None] * deta) / det[:, None]
    eps = np.stack([(dx * U[:, :, 0]).sum(1), (dy * U[:, :, 1]).sum(1), (dy * U[:, :, 0] + dx * U[:, :, 1]).sum(1)], axis=1)
    return eps @ D.T, det


def inverse_map(X, p):
    """Reference coordinates of points p (n,2) in cells X (n,4,2), Newton."""
    xi = np.zeros(len(p))
    eta = np.zeros(len(p))
    for _ in range(12):
        N, dxi, deta = shape(xi, eta)
        r = np.einsum("na,nad->nd", N, X) - p
        J00 = (dxi * X[:, :, 0]).sum(1)
        J01 = (deta * X[:, :, 0]).sum(1)
        J10 = (dxi * X[:, :, 1]).sum(1)
        J11 = (deta * X[:, :, 1]).sum(1)
        det = J00 * J11 - J01 * J10
        xi -= (J11 * r[:, 0] - J01 * r[:, 1]) / det
        eta -= (-J10 * r[:, 0] + J00 * r[:, 1]) / det
        xi = np.clip(xi, -3, 3)
        eta = np.clip(eta, -3, 3)
    return xi, eta


def reference_error(coarse_h5, fine_h5, D, sub=1):
    """||sig_fine - sig_coarse|| in the energy (compliance) norm over the coarse mesh,
    body by body: 3x3 Gauss on each of sub x sub pieces of every coarse cell (the
    fine stress is discontinuous inside a coarse cell: sub ~ the size ratio)."""
    C = np.linalg.inv(D)
    xc, cc, vc, fc = m2d.read_h5(coarse_h5)
    xf, cf_, vf, ff = m2d.read_h5(fine_h5)
    uc, uf = vc["displacement"][:, :2], vf["displacement"][:, :2]
    total, outside = 0.0, 0
    for b in np.unique(fc["body"]):
        cs = np.where(fc["body"] == b)[0]
        fs = np.where(ff["body"] == b)[0]
        tree = cKDTree(xf[cf_[fs]].mean(axis=1))
        pts = [(-1 + (si + (1 + G3[i]) / 2) * 2 / sub, -1 + (sj + (1 + G3[j]) / 2) * 2 / sub, W3[i] * W3[j] / sub**2)
               for si in range(sub) for sj in range(sub) for i in range(3) for j in range(3)]
        for gx, gy, w in pts:
            if True:
                xi = np.full(len(cs), gx)
                eta = np.full(len(cs), gy)
                X, U = xc[cc[cs]], uc[cc[cs]]
                sh, det = stress(X, U, xi, eta, D)
                p = np.einsum("na,nad->nd", shape(xi, eta)[0], X)
                _, cand = tree.query(p, k=8)
                found = np.full(len(p), -1)
                rx, ry = np.zeros(len(p)), np.zeros(len(p))
                for k in range(cand.shape[1]):
                    todo = np.where(found < 0)[0]
                    if not len(todo):
                        break
                    cell = fs[cand[todo, k]]
                    a, e = inverse_map(xf[cf_[cell]], p[todo])
                    ok = (np.abs(a) <= 1 + 1e-9) & (np.abs(e) <= 1 + 1e-9)
                    found[todo[ok]] = cell[ok]
                    rx[todo[ok]], ry[todo[ok]] = a[ok], e[ok]
                miss = np.where(found < 0)[0]  # outside the fine body (curved boundary): nearest cell, clipped
                outside += len(miss)
                if len(miss):
                    cell = fs[cand[miss, 0]]
                    a, e = inverse_map(xf[cf_[cell]], p[miss])
                    found[miss], rx[miss], ry[miss] = cell, np.clip(a, -1, 1), np.clip(e, -1, 1)
                sf, _ = stress(xf[cf_[found]], uf[cf_[found]], rx, ry, D)
                d = sf - sh
                total += (w * det * np.einsum("ni,ij,nj->n", d, C, d)).sum()
    return np.sqrt(total), outside


def top_cells(h5, key="error_indicator", k=10):
    xy, cells, _, cf = m2d.read_h5(h5)
    cen = xy[cells].mean(axis=1)
    o = np.argsort(-cf[key])[:k]
    return cen[o], cf[key][o]


def study_mms(levels):
    args = ["-bodies", "block", "-block_E", "1e3", "-block_nu", "0.3", "-dirichlet", "bottom:xy,right:xy,top:xy,left:xy", "-exact", "mms"]
    print("\nMMS (block_N, -exact mms): estimate / true energy-norm error")
    print("%4s %8s | %11s %11s %8s | %11s %8s" % ("N", "dofs", "true rel", "SPR rel", "eff", "average rel", "eff"))
    rows = []
    for n in levels:
        s, _ = run("est_mms_%d" % n, args + ["-mesh", m2d.mesh("block_%d" % n)])
        a, _ = run("est_mms_avg_%d" % n, args + ["-mesh", m2d.mesh("block_%d" % n), "-estimator_recovery", "average"])
        e, ea = s["estimator"], a["estimator"]
        rows.append((n, e["effectivity"], ea["effectivity"]))
        print("%4d %8d | %11.4e %11.4e %8.4f | %11.4e %8.4f" % (n, s["dofs"], e["true_error_rel"], s["error_estimate"], e["effectivity"], a["error_estimate"], ea["effectivity"]))
    return rows


def study_s2():
    print("\nS2 (patch_uniform): exact uniform stress")
    print("%8s | %11s %11s %11s %11s %8s" % ("method", "estimate rel", "volume", "contact", "true", "eff"))
    for meth in ("mortar", "nts"):
        s, _ = run("est_s2_" + meth, ["-options_file", m2d.opts("patch_uniform"), "-contact_method", meth])
        e = s["estimator"]
        print("%8s | %11.3e %11.3e %11.3e %11.3e %8.4f" % (meth, s["error_estimate"], e["volume"], e["contact"], e["true_error"], e["effectivity"]))


def study_s1():
    print("\nS1 (seed_patch): the 10 largest indicators (corners at x = 0.25, 0.75, y = 0.5)")
    for meth, lvl in (("mortar", ""), ("nts", ""), ("mortar", "_2"), ("mortar", "_4"), ("nts", "_4")):
        print("mesh seed_patch%s" % lvl, end=", ")
        s, h5 = run("est_s1_" + meth + lvl, ["-options_file", m2d.opts("seed_patch"), "-contact_method", meth, "-mesh", m2d.mesh("seed_patch" + lvl)])
        cen, eta = top_cells(h5)
        print("%s: estimate %.4e (volume %.4e, contact %.4e)" % (meth, s["error_estimate"], s["estimator"]["volume"], s["estimator"]["contact"]))
        print("   " + "  ".join("(%.3f,%.3f) %.2e" % (c[0], c[1], e) for c, e in zip(cen, eta)))


def study_hertz(levels, ref):
    D = plane_strain_D(200.0, 0.3)
    sref, href = run("est_hertz_%d" % ref, ["-options_file", m2d.opts("hertz"), "-mesh", m2d.mesh("hertz_%d" % ref)])
    enorm = sref["estimator"]["energy_norm"]
    a = sref["hertz_a"]
    print("\nHertz (options/hertz.opts): reference level %d (estimate %.4e, pressure error %.4e)" % (ref, sref["error_estimate"], sref["pressure_l2_rel"]))
    print("(E err ref: the energy-norm error against level %d; corr: divided by sqrt(1 - 4^-(%d - lvl)), i.e. assuming" % (ref, ref))
    print(" the error halves per level and is orthogonal to the reference's own, as it is on the MMS meshes)")
    print("%3s %8s | %11s %11s %11s | %11s %8s | %11s %7s %7s | %s" % ("lvl", "dofs", "estimate", "volume", "contact", "p error", "est/p", "E err ref", "eff", "corr", "top-10 at the zone edge (within 3h of (a,0))"))
    for lvl in levels:
        s, h5 = run("est_hertz_%d" % lvl, ["-options_file", m2d.opts("hertz"), "-mesh", m2d.mesh("hertz_%d" % lvl)])
        e = s["estimator"]
        sub = int(max(1, min(2 ** (ref - lvl), np.sqrt(4e6 / (9 * s["cells"])))))
        err, outside = reference_error(h5, href, D, sub)
        rel = err / enorm
        cen, _ = top_cells(h5)
        near = int((np.hypot(cen[:, 0] - a, cen[:, 1]) < 3 * s["half_width_spacing"]).sum())
        corr = rel / np.sqrt(1 - 4.0 ** (lvl - ref))
        print("%3d %8d | %11.4e %11.4e %11.4e | %11.4e %8.3f | %11.4e %7.3f %7.3f | %d/10 (%s)" % (lvl, s["dofs"], s["error_estimate"], e["volume"] / e["energy_norm"], e["contact"] / e["energy_norm"], s["pressure_l2_rel"], s["error_estimate"] / s["pressure_l2_rel"], rel, s["error_estimate"] / rel, s["error_estimate"] / corr, near, " ".join("(%.3f,%.3f)" % tuple(c) for c in cen[:3])))
        if outside:
            print("     (%d coarse Gauss points outside the reference mesh's body: nearest cell)" % outside)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mms", default="4,8,16,32,64")
    ap.add_argument("--hertz", default="0,1,2,3,4")
    ap.add_argument("--ref", type=int, default=5)
    ap.add_argument("--skip", default="", help="comma list of mms,s2,s1,hertz to skip")
    o = ap.parse_args()
    skip = o.skip.split(",")
    if "mms" not in skip:
        study_mms([int(v) for v in o.mms.split(",")])
    if "s2" not in skip:
        study_s2()
    if "s1" not in skip:
        study_s1()
    if "hertz" not in skip:
        study_hertz([int(v) for v in o.hertz.split(",")], o.ref)


if __name__ == "__main__":
    main()
