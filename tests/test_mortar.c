/* Unit tests of the mortar geometry and integrals (mortar.c):
 *  - D and M of a two-edge configuration against values worked out by hand;
 *  - sum_j D_ij = sum_k M_ik for fully covered non-mortar nodes;
 *  - invariance of the rows under a translation and a rotation of both surfaces;
 *  - non-mortar nodes projecting exactly onto mortar nodes and onto the end of
 *    the mortar surface: no NaN, no lost length (zero-length segments dropped);
 *  - the NTS row of a node;
 *  - a kinked interface (non-matching nodes, a node of both sides at the
 *    kink): the segments cover the non-mortar surface once, and lambda = 1
 *    gives every node the force of a unit pressure on its own edges;
 *  - the surface tree against a loop over every edge, on a circle, a wavy
 *    curve and a long strip at 30 degrees: SurfaceTreeNear holds every edge
 *    whose region within reach a segment meets, in ascending order;
 *    SurfaceTreeFacing finds the same edge and distance as the loop. */
#include "contact.h"
#include "mortar.h"

#include "check.h"

/* value of row j at global dof col (0 if absent) */
static PetscReal RowVal(const M2dContactRows *R, PetscInt j, PetscInt col)
{
  for (PetscInt k = R->ptr[j]; k < R->ptr[j + 1]; k++)
    if (R->col[k] == col) return R->val[k];
  return 0;
}

static PetscInt RowOfNode(const M2dContactRows *R, PetscInt node)
{
  for (PetscInt j = 0; j < R->n; j++)
    if (R->node[j] == node) return j;
  return -1;
}

/* Edges are oriented body-on-the-left (outward normal (t_y, -t_x)).
 * Non-mortar: upper body's bottom edge from (0,0) to (1,0), normal -y. Node a = (1,0) gdof 100, b = (0,0) gdof 102.
 * Mortar: lower body's top edges (1.5,0)-(0.5,0)-(-0.5,0), normal +y, gdofs 4, 2, 0.
 * Worked out by hand with N_a = x, N_b = 1 - x on [0,1]:
 *   D = [1/3 1/6; 1/6 1/3],  M_a = [1/48, 18/48, 5/48],  M_b = [5/48, 18/48, 1/48]. */
static void TwoEdge(PetscReal theta, PetscReal tx, PetscReal ty, M2dSurface *nm, M2dSurface *m)
{
  PetscReal      xn[4] = {1, 0, 0, 0}, xm[6] = {-0.5, 0, 0.5, 0, 1.5, 0};
  const PetscInt gn[2] = {100, 102}, gm[3] = {0, 2, 4}, en[2] = {1, 0}, em[4] = {1, 0, 2, 1};
  PetscReal      c = PetscCosReal(theta), s = PetscSinReal(theta);
  for (int i = 0; i < 2; i++) {
    PetscReal x = xn[2 * i], y = xn[2 * i + 1];
    xn[2 * i]     = c * x - s * y + tx;
    xn[2 * i + 1] = s * x + c * y + ty;
  }
  for (int i = 0; i < 3; i++) {
    PetscReal x = xm[2 * i], y = xm[2 * i + 1];
    xm[2 * i]     = c * x - s * y + tx;
    xm[2 * i + 1] = s * x + c * y + ty;
  }
  SurfaceCreate(2, xn, gn, 1, en, nm);
  SurfaceCreate(3, xm, gm, 2, em, m);
}

/* segments (reach 0.1) and standard mortar rows of c's surfaces; an
 * M2dContactPair holds the pair, its segments and rows as the program's does, and
 * ContactPairDestroy frees them */
static PetscErrorCode MortarPair(M2dContactPair *c)
{
  PetscFunctionBeginUser;
  PetscCall(MortarBuildSegments(&c->nm, &c->m, 0.1, &c->seg));
  PetscCall(MortarRows(&c->nm, &c->m, &c->seg, M2D_MORTAR_STANDARD, PETSC_FALSE, &c->R));
  PetscFunctionReturn(0);
}

/* Kinked interface: the polyline y = |x| tan(20 deg) for x in [-1, 1] on
 * both sides, non-mortar (upper body's bottom, left to right) with nodes at
 * x = -1, -0.6, 0, 0.5, 1 and mortar (lower body's top, right to left) at
 * x = 1, 0.7, 0.3, 0, -0.3, -1. With every multiplier 1 the rows' column sums
 * are the forces B^T lambda: on each node of either side, minus the integral
 * of N_k n over its own edges (n their outward normal), the force of a unit
 * pressure, for either basis (its functions sum to 1). */
static PetscErrorCode KinkForces(M2dMortarBasis basis)
{
  const PetscReal xn[5] = {-1, -0.6, 0, 0.5, 1}, xm[6] = {1, 0.7, 0.3, 0, -0.3, -1}, tn = PetscTanReal(PETSC_PI / 9);
  PetscReal       pn[10], pm[12], f[2 * 11] = {0}, want[2 * 11] = {0}, err = 0, len = 0;
  PetscInt        gn[5], gm[6], en[8], em[10];
  M2dContactPair  c = {0};

  PetscFunctionBeginUser;
  for (int i = 0; i < 5; i++) pn[2 * i] = xn[i], pn[2 * i + 1] = PetscAbsReal(xn[i]) * tn, gn[i] = 100 + 2 * i;
  for (int i = 0; i < 6; i++) pm[2 * i] = xm[i], pm[2 * i + 1] = PetscAbsReal(xm[i]) * tn, gm[i] = 2 * i;
  for (int e = 0; e < 4; e++) en[2 * e] = e, en[2 * e + 1] = e + 1;
  for (int e = 0; e < 5; e++) em[2 * e] = e, em[2 * e + 1] = e + 1;
  PetscCall(SurfaceCreate(5, pn, gn, 4, en, &c.nm));
  PetscCall(SurfaceCreate(6, pm, gm, 5, em, &c.m));
  PetscCall(MortarBuildSegments(&c.nm, &c.m, 0.1, &c.seg));
  PetscCall(MortarRows(&c.nm, &c.m, &c.seg, basis, PETSC_FALSE, &c.R));
  for (PetscInt k = 0; k < c.seg.nseg; k++) len += 0.5 * (c.seg.seg[k].zeta[1] - c.seg.seg[k].zeta[0]) * c.nm.len[c.seg.seg[k].nm_edge];
  for (PetscInt j = 0; j < c.R.n; j++)
    for (PetscInt k = c.R.ptr[j]; k < c.R.ptr[j + 1]; k++) f[c.R.col[k] >= 100 ? c.R.col[k] - 100 + 12 : c.R.col[k]] += c.R.val[k];
  for (int s = 0; s < 2; s++) { /* s = 0: mortar edges (columns 0..11), 1: non-mortar (12..21) */
    const M2dSurface *sf = s ? &c.nm : &c.m;
    for (PetscInt e = 0; e < sf->nedge; e++)
      for (int end = 0; end < 2; end++)
        for (int d = 0; d < 2; d++) want[(s ? 12 : 0) + 2 * sf->edge[2 * e + end] + d] -= 0.5 * sf->len[e] * sf->normal[2 * e + d];
  }
  for (int k = 0; k < 22; k++) err = PetscMax(err, PetscAbsReal(f[k] - want[k]));
  CHECK(PetscAbsReal(len - 2 / PetscCosReal(PETSC_PI / 9)) < 1e-14, "kink (%s): the segments cover the non-mortar surface once (length %.16g)", basis == M2D_MORTAR_DUAL ? "dual" : "standard", (double)len);
  CHECK(c.R.n == 5 && err < 1e-14, "kink (%s): lambda = 1 gives each node the force of a unit pressure on its edges (error %.1e)", basis == M2D_MORTAR_DUAL ? "dual" : "standard", (double)err);
  PetscCall(ContactPairDestroy(&c));
  PetscFunctionReturn(0);
}

/* a closed circle (shape 0), a wavy open curve (1), a straight strip at 30
 * degrees (2), n edges, body on the left */
static PetscErrorCode SearchSurface(int shape, PetscInt n, M2dSurface *s)
{
  PetscInt   nn = shape == 0 ? n : n + 1, *g, *e;
  PetscReal *x;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(2 * nn, &x, nn, &g, 2 * n, &e));
  for (PetscInt i = 0; i < nn; i++) {
    PetscReal t = (PetscReal)i / n;
    g[i]        = 2 * i;
    if (shape == 0) x[2 * i] = PetscCosReal(2 * PETSC_PI * t), x[2 * i + 1] = PetscSinReal(2 * PETSC_PI * t);
    else if (shape == 1) x[2 * i] = 4 * t, x[2 * i + 1] = 0.3 * PetscSinReal(9 * t) + 0.05 * PetscSinReal(77 * t);
    else x[2 * i] = 50 * t * PetscCosReal(PETSC_PI / 6), x[2 * i + 1] = 50 * t * PetscSinReal(PETSC_PI / 6);
  }
  for (PetscInt k = 0; k < n; k++) e[2 * k] = k, e[2 * k + 1] = (k + 1) % nn;
  PetscCall(SurfaceCreate(nn, x, g, n, e, s));
  PetscCall(PetscFree3(x, g, e));
  PetscFunctionReturn(0);
}

/* does a point of segment ab (sampled) lie within reach of edge f along its normal, its foot on f? */
static PetscBool SampledHit(const M2dSurface *s, PetscInt f, const PetscReal a[2], const PetscReal b[2], PetscReal reach)
{
  const PetscReal *p = &s->x[2 * s->edge[2 * f]], *q = &s->x[2 * s->edge[2 * f + 1]], *n = &s->normal[2 * f];
  for (int k = 0; k <= 200; k++) {
    PetscReal x[2] = {a[0] + (b[0] - a[0]) * k / 200., a[1] + (b[1] - a[1]) * k / 200.}, l2 = PetscSqr(q[0] - p[0]) + PetscSqr(q[1] - p[1]);
    PetscReal t = ((x[0] - p[0]) * (q[0] - p[0]) + (x[1] - p[1]) * (q[1] - p[1])) / l2, g = (x[0] - p[0]) * n[0] + (x[1] - p[1]) * n[1];
    if (t >= 0 && t <= 1 && PetscAbsReal(g) <= reach) return PETSC_TRUE;
  }
  return PETSC_FALSE;
}

static PetscErrorCode SearchAgainstLoop(void)
{
  PetscRandom r;

  PetscFunctionBeginUser;
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &r));
  PetscCall(PetscRandomSetSeed(r, 7));
  PetscCall(PetscRandomSeed(r));
  for (int shape = 0; shape < 3; shape++) {
    M2dSurface     s;
    M2dSurfaceTree t;
    PetscInt       n = 0, cap = 0, *list = NULL, missed = 0, unsorted = 0, differ = 0, hits = 0, found = 0;
    PetscReal      ext;
    PetscCall(SearchSurface(shape, shape == 2 ? 2000 : 500, &s));
    PetscCall(SurfaceTreeCreate(&s, &t));
    ext = s.hi[0] - s.lo[0] + s.hi[1] - s.lo[1];
    for (int q = 0; q < 300; q++) {
      PetscReal u[4], a[2], b[2], reach = (q % 3 == 0 ? 0.001 : q % 3 == 1 ? 0.02 : 0.2) * ext, nn[2], d = 0, ft = 0, dl = 0, best = PETSC_MAX_REAL;
      PetscInt  el = -1, et;
      for (int k = 0; k < 4; k++) PetscCall(PetscRandomGetValueReal(r, &u[k]));
      a[0] = s.lo[0] + u[0] * (s.hi[0] - s.lo[0]), a[1] = s.lo[1] + u[1] * (s.hi[1] - s.lo[1]);
      b[0] = a[0] + 0.02 * ext * (u[2] - 0.5), b[1] = a[1] + 0.02 * ext * (u[3] - 0.5);
      PetscCall(SurfaceTreeNear(&t, a, b, reach, &n, &cap, &list));
      for (PetscInt k = 1; k < n; k++) unsorted += list[k] <= list[k - 1];
      for (PetscInt f = 0; f < s.nedge; f++) {
        PetscBool in = PETSC_FALSE;
        if (!SampledHit(&s, f, a, b, reach)) continue;
        hits++;
        for (PetscInt k = 0; k < n; k++) in = (PetscBool)(in || list[k] == f);
        missed += !in;
      }
      nn[0] = PetscCosReal(2 * PETSC_PI * u[2]), nn[1] = PetscSinReal(2 * PETSC_PI * u[2]); /* a point of a surface facing some of the edges */
      for (PetscInt f = 0; f < s.nedge; f++) { /* the loop SurfaceTreeFacing replaces */
        const PetscReal *p = &s.x[2 * s.edge[2 * f]], *e2 = &s.x[2 * s.edge[2 * f + 1]], *m = &s.normal[2 * f];
        PetscReal        l2 = PetscSqr(e2[0] - p[0]) + PetscSqr(e2[1] - p[1]), tt, dd;
        if (nn[0] * m[0] + nn[1] * m[1] >= 0) continue;
        tt = ((a[0] - p[0]) * (e2[0] - p[0]) + (a[1] - p[1]) * (e2[1] - p[1])) / l2;
        if (tt < 0 || tt > 1) continue;
        dd = (a[0] - p[0]) * m[0] + (a[1] - p[1]) * m[1];
        if (dd < -reach || PetscAbsReal(dd) >= best) continue;
        best = PetscAbsReal(dd), el = f, dl = dd;
      }
      et = SurfaceTreeFacing(&t, a, nn, -reach, PETSC_MAX_REAL, &d, &ft);
      differ += et != el || (el >= 0 && d != dl);
      found += el >= 0;
    }
    CHECK(hits > 0 && !missed && !unsorted, "surface tree, shape %d: every edge within reach of 300 segments found (%d hits), in ascending order", shape, (int)hits);
    CHECK(found > 0 && !differ, "surface tree, shape %d: the nearest facing edge and its distance as by a loop over every edge (%d found, %d differ)", shape, (int)found, (int)differ);
    PetscCall(PetscFree(list));
    PetscCall(SurfaceTreeDestroy(&t));
    PetscCall(SurfaceDestroy(&s));
  }
  PetscCall(PetscRandomDestroy(&r));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  M2dContactPair a = {0};

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  TwoEdge(0, 0, 0, &a.nm, &a.m);
  PetscCall(MortarPair(&a));
  CHECK(a.seg.nseg == 2, "two segments (%d)", (int)a.seg.nseg);
  {
    PetscInt  ja = RowOfNode(&a.R, 0), jb = RowOfNode(&a.R, 1);
    /* rows hold D n and -M n with n = (0, 1): the y-dofs carry the numbers */
    PetscReal D[4]  = {RowVal(&a.R, ja, 101), RowVal(&a.R, ja, 103), RowVal(&a.R, jb, 101), RowVal(&a.R, jb, 103)};
    PetscReal Ma[3] = {-RowVal(&a.R, ja, 1), -RowVal(&a.R, ja, 3), -RowVal(&a.R, ja, 5)};
    PetscReal Mb[3] = {-RowVal(&a.R, jb, 1), -RowVal(&a.R, jb, 3), -RowVal(&a.R, jb, 5)};
    PetscReal eD = PetscAbsReal(D[0] - 1. / 3) + PetscAbsReal(D[1] - 1. / 6) + PetscAbsReal(D[2] - 1. / 6) + PetscAbsReal(D[3] - 1. / 3);
    PetscReal eM = PetscAbsReal(Ma[0] - 1. / 48) + PetscAbsReal(Ma[1] - 18. / 48) + PetscAbsReal(Ma[2] - 5. / 48) + PetscAbsReal(Mb[0] - 5. / 48) + PetscAbsReal(Mb[1] - 18. / 48) + PetscAbsReal(Mb[2] - 1. / 48);
    CHECK(a.R.n == 2 && ja >= 0 && jb >= 0, "both non-mortar nodes carry a multiplier");
    CHECK(eD < 1e-15, "D against hand values (error %.1e)", (double)eD);
    CHECK(eM < 1e-15, "M against hand values (error %.1e)", (double)eM);
    CHECK(RowVal(&a.R, ja, 100) == 0 && RowVal(&a.R, ja, 0) == 0, "no tangential entries for a horizontal interface");
    for (PetscInt j = 0; j < a.R.n; j++) {
      PetscReal sd = 0, sm = 0;
      for (PetscInt k = a.R.ptr[j]; k < a.R.ptr[j + 1]; k++) {
        if (a.R.col[k] >= 100) sd += a.R.val[k];
        else sm -= a.R.val[k];
      }
      CHECK(PetscAbsReal(sd - sm) < 1e-14, "row %d: sum_j D = sum_k M (%.1e)", (int)j, (double)(sd - sm));
      CHECK(PetscAbsReal(a.R.w[j] - 0.5) < 1e-15 && PetscAbsReal(a.R.g0[j]) < 1e-15, "row %d: weight 1/2 and zero initial gap", (int)j);
    }
  }
  { /* translation + rotation: rows rotate with the normal, weights and gaps stay */
    M2dContactPair b  = {0};
    PetscReal  th = 0.7, err = 0;
    TwoEdge(th, 3.3, -1.7, &b.nm, &b.m);
    PetscCall(MortarPair(&b));
    CHECK(b.R.n == a.R.n && b.seg.nseg == a.seg.nseg, "same segments and multipliers after a rigid motion");
    for (PetscInt j = 0; j < a.R.n && b.R.n == a.R.n; j++) {
      err = PetscMax(err, PetscAbsReal(a.R.w[j] - b.R.w[j]) + PetscAbsReal(b.R.g0[j]));
      for (PetscInt k = a.R.ptr[j]; k < a.R.ptr[j + 1]; k++) {
        PetscInt col = a.R.col[k];
        if (col % 2 == 0) continue;
        /* entry on the y-dof times the rotated normal (-sin, cos) */
        err = PetscMax(err, PetscAbsReal(RowVal(&b.R, j, col - 1) - a.R.val[k] * -PetscSinReal(th)) + PetscAbsReal(RowVal(&b.R, j, col) - a.R.val[k] * PetscCosReal(th)));
      }
    }
    CHECK(err < 1e-14, "rows invariant under translation and rotation (%.1e)", (double)err);
    PetscCall(ContactPairDestroy(&b));
  }
  PetscCall(ContactPairDestroy(&a));

  { /* coincident nodes and the end of the mortar surface: non-mortar edges
     * (0,0)-(0.5,0)-(1,0)-(1.5,0) (upper body), mortar (0,0)-(0.5,0)-(1,0):
     * nodes project exactly onto mortar nodes, the last one beyond the end */
    const PetscReal xn[8] = {1.5, 0, 1, 0, 0.5, 0, 0, 0}, xm[6] = {0, 0, 0.5, 0, 1, 0};
    const PetscInt  gn[4] = {100, 102, 104, 106}, en[6] = {1, 0, 2, 1, 3, 2}, gm[3] = {0, 2, 4}, em[4] = {1, 0, 2, 1};
    M2dContactPair      d   = {0};
    PetscReal       len = 0, sumw = 0;
    PetscBool       finite = PETSC_TRUE;
    PetscCall(SurfaceCreate(4, xn, gn, 3, en, &d.nm));
    PetscCall(SurfaceCreate(3, xm, gm, 2, em, &d.m));
    PetscCall(MortarPair(&d));
    for (PetscInt k = 0; k < d.seg.nseg; k++) {
      len += 0.5 * (d.seg.seg[k].zeta[1] - d.seg.seg[k].zeta[0]) * d.nm.len[d.seg.seg[k].nm_edge];
      finite = (PetscBool)(finite && !PetscIsInfOrNanReal(d.seg.seg[k].zeta[0] + d.seg.seg[k].zeta[1] + d.seg.seg[k].xi[0] + d.seg.seg[k].xi[1]));
    }
    for (PetscInt j = 0; j < d.R.n; j++) {
      sumw += d.R.w[j];
      for (PetscInt k = d.R.ptr[j]; k < d.R.ptr[j + 1]; k++) finite = (PetscBool)(finite && !PetscIsInfOrNanReal(d.R.val[k]));
    }
    CHECK(d.seg.nseg == 2, "coincident nodes: 2 segments, zero-length ones dropped (%d)", (int)d.seg.nseg);
    CHECK(PetscAbsReal(len - 1.0) < 1e-15 && PetscAbsReal(sumw - 1.0) < 1e-15, "covered length 1 kept (segments %.16g, weights %.16g)", (double)len, (double)sumw);
    CHECK(finite, "no NaN or Inf in segments and rows");
    CHECK(d.R.n == 3 && RowOfNode(&d.R, 0) < 0, "the node beyond the mortar surface gets no multiplier (%d multipliers)", (int)d.R.n);
    { /* NTS: node (0.5, 0.02) above mortar node (0.5, 0): xi = 1 on edge 0 or -1 on edge 1 */
      M2dContactRows N;
      PetscInt    j;
      PetscCall(NTSRows(&d.nm, &d.m, 0.1, PETSC_FALSE, &N));
      j = RowOfNode(&N, 2);
      CHECK(N.n == 3 && j >= 0, "NTS: 3 multipliers (nodes over the mortar surface)");
      if (j >= 0) CHECK(PetscAbsReal(N.w[j] - 0.5) < 1e-15 && PetscAbsReal(RowVal(&N, j, 105) - 0.5) < 1e-15 && PetscAbsReal(RowVal(&N, j, 3) + 0.5) < 1e-15, "NTS row: a_s n at the node, -a_s n at the coincident mortar node");
      PetscCall(ContactRowsDestroy(&N));
    }
    PetscCall(ContactPairDestroy(&d));
  }
  PetscCall(KinkForces(M2D_MORTAR_STANDARD));
  PetscCall(KinkForces(M2D_MORTAR_DUAL));
  PetscCall(SearchAgainstLoop());
  PetscCall(PetscFinalize());
  printf("%d failed\n", failures);
  return failures ? 1 : 0;
}
