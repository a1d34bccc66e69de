/* estimator.c - Zienkiewicz-Zhu stress recovery per body, contact terms on the
 * mortar segments, the true error where the scene knows the answer, and the
 * size field (see estimator.h for the formulas). */
#include "estimator.h"
#include "elasticity.h"
#include "logging.h"
#include <string.h>

static const PetscReal g2[2] = {-0.57735026918962576451, 0.57735026918962576451};
static const PetscReal g3[3] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
static const PetscReal w3[3] = {0.55555555555555555556, 0.88888888888888888889, 0.55555555555555555556};

/* per vertex: the normal matrix of the patch fit (upper triangle, 6) and its
 * right-hand sides (3 basis functions x 3 stress components) */
#define NACC 15

typedef struct {
  PetscReal D[9], C[9], lam; /* material matrix, its inverse (compliance), lambda of the sri split */
  PetscReal Ep;              /* E' = E/(1 - nu^2) in plane strain, E in plane stress */
} BodyMat;

typedef struct {
  const M2dMesh  *m;
  const M2dScene *s;
  M2dMeshArrays   ar; /* coordinates, u's local copy */
  BodyMat         bm[M2D_MAX_BODIES];
} Ctx;

#define MAXQ 9 /* Gauss points of the 3 x 3 rule */

/* one cell and its FE stresses at the points of an n x n Gauss rule */
typedef struct {
  PetscReal xy[8], ue[8], epsc[3]; /* corners, displacements, strain at the centre */
  int       nq;                    /* Gauss points, n * n */
  PetscReal N[MAXQ][4];            /* shape functions at each */
  PetscReal p[MAXQ][2];            /* its position */
  PetscReal sig[MAXQ][3];          /* the FE stress there (StressAt) */
  PetscReal w[MAXQ];               /* quadrature weight x det J */
} CellData;

static void Inverse3(const PetscReal A[9], PetscReal B[9])
{
  PetscReal det = A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) + A[2] * (A[3] * A[7] - A[4] * A[6]);
  B[0]          = (A[4] * A[8] - A[5] * A[7]) / det;
  B[1]          = (A[2] * A[7] - A[1] * A[8]) / det;
  B[2]          = (A[1] * A[5] - A[2] * A[4]) / det;
  B[3]          = (A[5] * A[6] - A[3] * A[8]) / det;
  B[4]          = (A[0] * A[8] - A[2] * A[6]) / det;
  B[5]          = (A[2] * A[3] - A[0] * A[5]) / det;
  B[6]          = (A[3] * A[7] - A[4] * A[6]) / det;
  B[7]          = (A[1] * A[6] - A[0] * A[7]) / det;
  B[8]          = (A[0] * A[4] - A[1] * A[3]) / det;
}

static PetscReal Quad(const PetscReal C[9], const PetscReal v[3])
{
  PetscReal q = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) q += v[i] * C[3 * i + j] * v[j];
  return q;
}

static void BodyMats(const M2dScene *s, BodyMat bm[])
{
  for (PetscInt b = 0; b < s->nbody; b++) {
    M2dMaterialMatrix(s->body[b].E, s->body[b].nu, s->plane, bm[b].D);
    Inverse3(bm[b].D, bm[b].C);
    bm[b].lam = M2dLambda(s->body[b].E, s->body[b].nu, s->plane);
    bm[b].Ep  = s->plane == M2D_PLANE_STRAIN ? s->body[b].E / (1 - s->body[b].nu * s->body[b].nu) : s->body[b].E;
  }
}

/* FE stress at (xi, et), as the stiffness integrates it: D eps, and with sri
 * the lambda part from the centre strain (D = Dr + lam m m^T, m = [1 1 0]).
 * Returns det J; N gets the shape functions there. */
static PetscReal StressAt(const CellData *cd, const BodyMat *bm, PetscBool sri, PetscReal xi, PetscReal et, PetscReal N[4], PetscReal sig[3])
{
  PetscReal dN[8], eps[3], det = Q4Shape(cd->xy, xi, et, N, dN);
  Q4Strain(dN, cd->ue, eps);
  for (int r = 0; r < 3; r++) sig[r] = bm->D[3 * r] * eps[0] + bm->D[3 * r + 1] * eps[1] + bm->D[3 * r + 2] * eps[2];
  if (sri) {
    PetscReal dv = bm->lam * (cd->epsc[0] + cd->epsc[1] - eps[0] - eps[1]);
    sig[0] += dv;
    sig[1] += dv;
  }
  return det;
}

/* cell c (of body b) with its FE stresses at the n x n Gauss points (n = 2 or 3) */
static PetscErrorCode LoadCell(const Ctx *x, PetscInt c, PetscInt b, int n, CellData *cd)
{
  const PetscReal *g = n == 2 ? g2 : g3;
  PetscReal        N[4], dN[8];

  PetscFunctionBeginUser;
  MeshCellCoordinates(x->m, x->ar.ca, x->ar.cs, c, cd->xy);
  for (int a = 0; a < 4; a++) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(x->ar.lsec, x->m->cellverts[4 * (c - x->m->cStart) + a], &off));
    cd->ue[2 * a]     = PetscRealPart(x->ar.ua[off]);
    cd->ue[2 * a + 1] = PetscRealPart(x->ar.ua[off + 1]);
  }
  Q4Shape(cd->xy, 0, 0, N, dN);
  Q4Strain(dN, cd->ue, cd->epsc);
  cd->nq = n * n;
  for (int q = 0; q < cd->nq; q++) {
    int i = q / n, j = q % n;
    cd->w[q] = (n == 2 ? 1.0 : w3[i] * w3[j]) * StressAt(cd, &x->bm[b], x->s->sri, g[i], g[j], cd->N[q], cd->sig[q]);
    cd->p[q][0] = cd->p[q][1] = 0;
    for (int a = 0; a < 4; a++) {
      cd->p[q][0] += cd->N[q][a] * cd->xy[2 * a];
      cd->p[q][1] += cd->N[q][a] * cd->xy[2 * a + 1];
    }
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode CtxOpen(const M2dMesh *m, const M2dScene *s, Vec u, Ctx *x)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(x, sizeof(*x)));
  x->m = m;
  x->s = s;
  BodyMats(s, x->bm);
  PetscCall(MeshArraysOpen(m, u, &x->ar));
  PetscFunctionReturn(0);
}

/* ---------- recovery ---------- */

/* a DM on the same plex and point SF with NACC values per vertex */
static PetscErrorCode CreateRecoveryDM(const M2dMesh *m, DM *dmr)
{
  PetscSection sec;
  PetscInt     pStart, pEnd;

  PetscFunctionBeginUser;
  PetscCall(DMClone(m->dm, dmr));
  PetscCall(PetscSectionCreate(PetscObjectComm((PetscObject)m->dm), &sec));
  PetscCall(DMPlexGetChart(m->dm, &pStart, &pEnd));
  PetscCall(PetscSectionSetChart(sec, pStart, pEnd));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) PetscCall(PetscSectionSetDof(sec, v, NACC));
  PetscCall(PetscSectionSetUp(sec));
  PetscCall(DMSetLocalSection(*dmr, sec));
  PetscCall(PetscSectionDestroy(&sec));
  PetscFunctionReturn(0);
}

/* patch sums of body b's cells: SPR fits a0 + a1 dx + a2 dy (dx from the
 * vertex) to the 2x2 Gauss-point stresses, unweighted; the average fits a0
 * alone with the Gauss weights (area weighting) */
static PetscErrorCode AccumulatePatches(const Ctx *x, PetscInt b, M2dRecovery rec, PetscSection rsec, PetscScalar *acc)
{
  const M2dMesh *m  = x->m;
  const int      np = rec == M2D_RECOVERY_SPR ? 3 : 1;

  PetscFunctionBeginUser;
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    CellData cd;
    if (m->cellbody[c - m->cStart] != b) continue;
    PetscCall(LoadCell(x, c, b, 2, &cd));
    for (int q = 0; q < cd.nq; q++) {
      PetscReal w = rec == M2D_RECOVERY_SPR ? 1.0 : cd.w[q];
      for (int a = 0; a < 4; a++) {
        PetscInt     off;
        PetscReal    P[3] = {1, cd.p[q][0] - cd.xy[2 * a], cd.p[q][1] - cd.xy[2 * a + 1]};
        PetscScalar *A;
        PetscCall(PetscSectionGetOffset(rsec, m->cellverts[4 * (c - m->cStart) + a], &off));
        A = &acc[off];
        A[0] += w;
        if (np == 3) {
          A[1] += w * P[1];
          A[2] += w * P[2];
          A[3] += w * P[1] * P[1];
          A[4] += w * P[1] * P[2];
          A[5] += w * P[2] * P[2];
        }
        for (int k = 0; k < np; k++)
          for (int r = 0; r < 3; r++) A[6 + 3 * k + r] += w * P[k] * cd.sig[q][r];
      }
    }
  }
  PetscFunctionReturn(0);
}

/* a0 of the patch fit (the recovered stress at the vertex); the basis is
 * scaled by the patch's rms distance so the 3x3 system is well conditioned.
 * Falls back to the plain average if the sample points are (nearly) collinear. */
static void PatchValue(const PetscScalar *A, PetscReal sig[3])
{
  PetscReal n = PetscRealPart(A[0]), h2 = (PetscRealPart(A[3]) + PetscRealPart(A[5])) / n;
  for (int r = 0; r < 3; r++) sig[r] = PetscRealPart(A[6 + r]) / n;
  if (h2 > 0) {
    PetscReal h = PetscSqrtReal(h2), a01 = PetscRealPart(A[1]) / h, a02 = PetscRealPart(A[2]) / h;
    PetscReal a11 = PetscRealPart(A[3]) / h2, a12 = PetscRealPart(A[4]) / h2, a22 = PetscRealPart(A[5]) / h2;
    PetscReal c0 = a11 * a22 - a12 * a12, c1 = a01 * a22 - a12 * a02, c2 = a01 * a12 - a11 * a02;
    PetscReal det = n * c0 - a01 * c1 + a02 * c2;
    if (det > 1e-10 * n * n * n)
      for (int r = 0; r < 3; r++) {
        PetscReal b0 = PetscRealPart(A[6 + r]), b1 = PetscRealPart(A[9 + r]) / h, b2 = PetscRealPart(A[12 + r]) / h;
        sig[r] = (b0 * c0 - b1 * c1 + b2 * c2) / det; /* Cramer, first unknown */
      }
  }
}

/* recovered stresses sv (3 per local vertex) of body b: patch sums over both
 * ranks' cells through local-to-global (ADD) and back; has[v]: body b touches v */
static PetscErrorCode RecoverBody(const Ctx *x, DM dmr, PetscInt b, M2dRecovery rec, PetscReal sv[], PetscBool has[])
{
  const M2dMesh *m = x->m;
  PetscSection   rsec;
  Vec            l, g;
  PetscScalar   *acc;
  PetscMPIInt    size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)dmr), &size));
  PetscCall(DMGetLocalSection(dmr, &rsec));
  PetscCall(DMGetLocalVector(dmr, &l));
  PetscCall(VecZeroEntries(l));
  PetscCall(VecGetArray(l, &acc));
  PetscCall(AccumulatePatches(x, b, rec, rsec, acc));
  PetscCall(VecRestoreArray(l, &acc));
  if (size > 1) { /* the patches of vertices on a rank boundary: sums over both ranks (one rank: the local sums are the patches) */
    PetscCall(DMGetGlobalVector(dmr, &g));
    PetscCall(VecZeroEntries(g));
    PetscCall(DMLocalToGlobal(dmr, l, ADD_VALUES, g));
    PetscCall(DMGlobalToLocal(dmr, g, INSERT_VALUES, l));
    PetscCall(DMRestoreGlobalVector(dmr, &g));
  }
  PetscCall(VecGetArray(l, &acc));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(rsec, v, &off));
    has[v - m->vStart] = (PetscBool)(PetscRealPart(acc[off]) > 0);
    if (has[v - m->vStart]) PatchValue(&acc[off], &sv[3 * (v - m->vStart)]);
  }
  PetscCall(VecRestoreArray(l, &acc));
  PetscCall(DMRestoreLocalVector(dmr, &l));
  PetscFunctionReturn(0);
}

/* eta_K^2 and the energy int sig_h : C^-1 sig_h of body b's cells (3x3 Gauss) */
static PetscErrorCode CellIndicators(const Ctx *x, PetscInt b, const PetscReal sv[], PetscReal eta2[], PetscReal *energy)
{
  const M2dMesh *m = x->m;

  PetscFunctionBeginUser;
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    CellData cd;
    if (m->cellbody[c - m->cStart] != b) continue;
    PetscCall(LoadCell(x, c, b, 3, &cd));
    for (int q = 0; q < cd.nq; q++) {
      PetscReal d[3];
      for (int r = 0; r < 3; r++) {
        d[r] = -cd.sig[q][r];
        for (int a = 0; a < 4; a++) d[r] += cd.N[q][a] * sv[3 * (m->cellverts[4 * (c - m->cStart) + a] - m->vStart) + r];
      }
      eta2[c - m->cStart] += cd.w[q] * Quad(x->bm[b].C, d);
      *energy += cd.w[q] * Quad(x->bm[b].C, cd.sig[q]);
    }
  }
  PetscFunctionReturn(0);
}

/* ---------- contact terms ---------- */

typedef struct {
  PetscInt  *vnm, *vm;       /* per local vertex: node of the non-mortar / mortar surface, or -1 */
  PetscInt  *nmcell, *mcell; /* per surface edge: local cell (offset from cStart), or -1 */
  PetscReal *snm, *sm;       /* recovered stresses at the surface nodes (3 each), on every rank */
} Surf;

/* the local cell of every surface edge of body b (surface edges lie on one cell) */
static PetscErrorCode EdgeCells(const M2dMesh *m, const M2dSurface *S, const PetscInt vs[], PetscInt cell[])
{
  PetscFunctionBeginUser;
  for (PetscInt e = 0; e < S->nedge; e++) cell[e] = -1;
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    const PetscInt *cv = &m->cellverts[4 * (c - m->cStart)];
    if (m->cellbody[c - m->cStart] != S->body) continue;
    for (int k = 0; k < 4; k++) {
      PetscInt ia = vs[cv[k] - m->vStart], ib = vs[cv[(k + 1) % 4] - m->vStart];
      if (ia < 0 || ib < 0) continue;
      for (PetscInt q = S->n2e_ptr[ia]; q < S->n2e_ptr[ia + 1]; q++) {
        PetscInt e = S->n2e[q];
        if ((S->edge[2 * e] == ia && S->edge[2 * e + 1] == ib) || (S->edge[2 * e] == ib && S->edge[2 * e + 1] == ia)) cell[e] = c - m->cStart;
      }
    }
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode SurfCreate(const M2dMesh *m, const M2dContactPair *ct, Surf *sf)
{
  PetscSection gsec;
  PetscInt     nv = m->vEnd - m->vStart;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(PetscMalloc4(nv + 1, &sf->vnm, nv + 1, &sf->vm, ct->nm.nedge + 1, &sf->nmcell, ct->m.nedge + 1, &sf->mcell));
  PetscCall(PetscCalloc2(3 * ct->nm.nnode + 1, &sf->snm, 3 * ct->m.nnode + 1, &sf->sm));
  for (PetscInt v = 0; v < nv; v++) {
    PetscInt g;
    PetscCall(PetscSectionGetOffset(gsec, v + m->vStart, &g));
    if (g < 0) g = -(g + 1);
    PetscCall(PetscFindInt(g, ct->nm.nnode, ct->nm.gdof, &sf->vnm[v])); /* gdof is sorted (SurfaceGather) */
    PetscCall(PetscFindInt(g, ct->m.nnode, ct->m.gdof, &sf->vm[v]));
    if (sf->vnm[v] < 0) sf->vnm[v] = -1;
    if (sf->vm[v] < 0) sf->vm[v] = -1;
  }
  PetscCall(EdgeCells(m, &ct->nm, sf->vnm, sf->nmcell));
  PetscCall(EdgeCells(m, &ct->m, sf->vm, sf->mcell));
  PetscFunctionReturn(0);
}

static PetscErrorCode SurfDestroy(Surf *sf)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree4(sf->vnm, sf->vm, sf->nmcell, sf->mcell));
  PetscCall(PetscFree2(sf->snm, sf->sm));
  PetscFunctionReturn(0);
}

/* copy body b's recovered stresses at the surface nodes this rank owns */
static PetscErrorCode SurfPick(const M2dMesh *m, const M2dContactPair *ct, PetscInt b, const PetscReal sv[], const PetscBool has[], Surf *sf)
{
  PetscSection gsec;

  PetscFunctionBeginUser;
  if (b != ct->nm.body && b != ct->m.body) PetscFunctionReturn(0); /* not this pair's: bodies x pairs x vertices was 1.6 s for a column of 256 blocks */
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  for (PetscInt v = 0; v < m->vEnd - m->vStart; v++) {
    PetscInt g;
    PetscCall(PetscSectionGetOffset(gsec, v + m->vStart, &g));
    if (g < 0 || !has[v]) continue;
    for (int r = 0; r < 3; r++) {
      if (b == ct->nm.body && sf->vnm[v] >= 0) sf->snm[3 * sf->vnm[v] + r] = sv[3 * v + r];
      if (b == ct->m.body && sf->vm[v] >= 0) sf->sm[3 * sf->vm[v] + r] = sv[3 * v + r];
    }
  }
  PetscFunctionReturn(0);
}

/* normal pressure p = -n.sig.n and tangential traction of stress sig on normal n */
static void Traction(const PetscReal sig[3], const PetscReal n[2], PetscReal *p, PetscReal *tau)
{
  PetscReal t[2] = {sig[0] * n[0] + sig[2] * n[1], sig[2] * n[0] + sig[1] * n[1]};
  *p             = -(t[0] * n[0] + t[1] * n[1]);
  *tau           = -t[0] * n[1] + t[1] * n[0];
}

/* traction jumps on one segment: jn (non-mortar side) and jm (mortar side),
 * int (p* - lambda)^2 + tau*^2 ds, 3-point Gauss (the integrands are quartic) */
static void SegmentJumps(const M2dContactPair *ct, const Surf *sf, const PetscReal lamn[], const PetscReal lamt[], const M2dSegment *sg, PetscReal *jn, PetscReal *jm)
{
  const M2dSurface *nm = &ct->nm, *ms = &ct->m;
  const PetscInt    a = nm->edge[2 * sg->nm_edge], b = nm->edge[2 * sg->nm_edge + 1];
  const PetscInt    ma = ms->edge[2 * sg->m_edge], mb = ms->edge[2 * sg->m_edge + 1];
  const PetscReal   zh = 0.5 * (sg->zeta[1] - sg->zeta[0]), zm = 0.5 * (sg->zeta[1] + sg->zeta[0]);
  *jn = *jm = 0;
  if (!(zh > 0)) return;
  for (int q = 0; q < 3; q++) {
    PetscReal z = zm + zh * g3[q], ds = w3[q] * zh * 0.5 * nm->len[sg->nm_edge];
    PetscReal xi = sg->xi[0] + (sg->xi[1] - sg->xi[0]) * (z - sg->zeta[0]) / (2 * zh);
    PetscReal N1 = 0.5 * (1 - z), N2 = 0.5 * (1 + z), M1 = 0.5 * (1 - xi), M2 = 0.5 * (1 + xi);
    PetscReal lam = N1 * lamn[a] + N2 * lamn[b], lt = N1 * lamt[a] + N2 * lamt[b], sn[3], sm[3], p, tau;
    for (int r = 0; r < 3; r++) {
      sn[r] = N1 * sf->snm[3 * a + r] + N2 * sf->snm[3 * b + r];
      sm[r] = M1 * sf->sm[3 * ma + r] + M2 * sf->sm[3 * mb + r];
    }
    /* the friction force lt acts along the rows' tangent, against each side's own (t = (-n_y, n_x)): tau = -lt */
    Traction(sn, &nm->normal[2 * sg->nm_edge], &p, &tau);
    *jn += ds * (PetscSqr(p - lam) + PetscSqr(tau + lt));
    Traction(sm, &ms->normal[2 * sg->m_edge], &p, &tau);
    *jm += ds * (PetscSqr(p - lam) + PetscSqr(tau + lt));
  }
}

/* complementarity residual on non-mortar edge e: the NCP function
 * min(lambda, Es g / h_e), zero iff lambda >= 0, g >= 0, lambda g = 0 (the
 * active set's own test, c = Es/h_e), squared and scaled by h_e/Es: a negative
 * pressure counts as lambda^2, a penetration as (Es g/h_e)^2, pressure with an
 * open gap as the smaller of the two; quadratic, so round-off stays round-off */
static PetscReal Complementarity(const M2dSurface *nm, PetscInt e, const PetscReal lamn[], const PetscReal gapn[], const PetscInt mult[], PetscReal Es)
{
  PetscInt  a = nm->edge[2 * e], b = nm->edge[2 * e + 1];
  PetscReal L = nm->len[e], ga, gb, r = 0;
  if (mult[a] < 0 && mult[b] < 0) return 0;
  ga = mult[a] >= 0 ? gapn[a] : gapn[b]; /* a node without multiplier: no contact there */
  gb = mult[b] >= 0 ? gapn[b] : gapn[a];
  for (int q = 0; q < 3; q++) {
    PetscReal N1 = 0.5 * (1 - g3[q]), N2 = 0.5 * (1 + g3[q]), ds = 0.5 * L * w3[q];
    PetscReal lam = N1 * lamn[a] + N2 * lamn[b], g = N1 * ga + N2 * gb;
    r += ds * L / Es * PetscSqr(PetscMin(lam, Es * g / L));
  }
  return r;
}

static PetscErrorCode ContactTerms(const Ctx *x, const M2dContactPair *ct, const Surf *sf, PetscReal eta2[], PetscReal *sum)
{
  const M2dSurface    *nm = &ct->nm, *ms = &ct->m;
  const M2dSegmentSet *S  = &ct->seg;
  M2dSegmentSet        own;
  PetscReal           *lamn, *lamt, *gapn, Enm = x->bm[nm->body].Ep, Em = x->bm[ms->body].Ep, Es = 1 / (1 / Enm + 1 / Em);
  PetscInt            *mult;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&own, sizeof(own)));
  if (S->nseg == 0) { /* node-to-segment: the mortar segments only to integrate the jumps */
    PetscCall(MortarBuildSegments(nm, ms, ct->reach, &own));
    S = &own;
  }
  PetscCall(PetscCalloc4(nm->nnode + 1, &lamn, nm->nnode + 1, &lamt, nm->nnode + 1, &gapn, nm->nnode + 1, &mult));
  for (PetscInt i = 0; i < nm->nnode; i++) mult[i] = -1;
  for (PetscInt j = 0; j < ct->R.n; j++) {
    lamn[ct->R.node[j]] = ct->pressure[j];
    lamt[ct->R.node[j]] = ct->traction[j];
    gapn[ct->R.node[j]] = ct->gap[j];
    mult[ct->R.node[j]] = j;
  }
  for (PetscInt k = 0; k < S->nseg; k++) {
    const M2dSegment *sg = &S->seg[k];
    PetscInt          cn = sf->nmcell[sg->nm_edge], cm = sf->mcell[sg->m_edge];
    PetscReal         jn, jm;
    if (cn < 0 && cm < 0) continue;
    SegmentJumps(ct, sf, lamn, lamt, sg, &jn, &jm);
    if (cn >= 0) {
      eta2[cn] += nm->len[sg->nm_edge] / Enm * jn;
      *sum += nm->len[sg->nm_edge] / Enm * jn;
    }
    if (cm >= 0) {
      eta2[cm] += ms->len[sg->m_edge] / Em * jm;
      *sum += ms->len[sg->m_edge] / Em * jm;
    }
  }
  if (x->s->unilateral)
    for (PetscInt e = 0; e < nm->nedge; e++) {
      PetscReal r;
      if (sf->nmcell[e] < 0) continue;
      r = Complementarity(nm, e, lamn, gapn, mult, Es);
      eta2[sf->nmcell[e]] += r;
      *sum += r;
    }
  PetscCall(PetscFree4(lamn, lamt, gapn, mult));
  PetscCall(SegmentSetDestroy(&own));
  PetscFunctionReturn(0);
}


PetscErrorCode M2dEstimateError(const M2dMesh *m, const M2dScene *s, Vec u, const M2dContact *ct, M2dRecovery rec, PetscReal eta[], PetscReal eta_volume[], PetscReal nodal[], M2dErrorEstimate *e)
{
  MPI_Comm  comm = PetscObjectComm((PetscObject)m->dm);
  Ctx       x;
  DM        dmr;
  PetscReal *sv, loc[3] = {0, 0, 0}, vol = 0, emax = 0; /* loc: volume, contact, energy */
  PetscBool *has;
  PetscInt   nv = m->vEnd - m->vStart, nlc = m->cEnd - m->cStart, np = ct ? ct->npair : 0;
  Surf      *sf = NULL; /* one per pair */

  PetscFunctionBeginUser;
  PetscCall(M2dLogRegister());
  PetscCheck(!ct || ct->pressure || ct->R.n == 0, comm, PETSC_ERR_ORDER, "M2dEstimateError: call ContactResults first");
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_ESTIMATE], 0, 0, 0, 0));
  PetscCall(PetscMemzero(e, sizeof(*e)));
  PetscCall(CtxOpen(m, s, u, &x));
  PetscCall(CreateRecoveryDM(m, &dmr));
  PetscCall(PetscMalloc2(3 * nv + 1, &sv, nv + 1, &has));
  PetscCall(PetscCalloc1(np + 1, &sf));
  for (PetscInt p = 0; p < np; p++) PetscCall(SurfCreate(m, &ct->pair[p], &sf[p]));
  for (PetscInt c = 0; c < nlc; c++) eta[c] = 0;
  for (PetscInt b = 0; b < s->nbody; b++) { /* one body at a time: no smoothing across bodies */
    PetscCall(RecoverBody(&x, dmr, b, rec, sv, has));
    for (PetscInt v = 0; nodal && v < nv; v++) /* the bodies share no vertex */
      if (has[v])
        for (int r = 0; r < 3; r++) nodal[3 * v + r] = sv[3 * v + r];
    PetscCall(CellIndicators(&x, b, sv, eta, &loc[2]));
    for (PetscInt p = 0; p < np; p++) PetscCall(SurfPick(m, &ct->pair[p], b, sv, has, &sf[p]));
  }
  for (PetscInt c = 0; c < nlc; c++) vol += eta[c];
  if (eta_volume)
    for (PetscInt c = 0; c < nlc; c++) eta_volume[c] = PetscSqrtReal(eta[c]);
  loc[0] = vol;
  for (PetscInt p = 0; p < np; p++) { /* every interface */
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sf[p].snm, (PetscMPIInt)(3 * ct->pair[p].nm.nnode), MPIU_REAL, MPI_SUM, comm));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sf[p].sm, (PetscMPIInt)(3 * ct->pair[p].m.nnode), MPIU_REAL, MPI_SUM, comm));
    PetscCall(ContactTerms(&x, &ct->pair[p], &sf[p], eta, &loc[1]));
    PetscCall(SurfDestroy(&sf[p]));
  }
  PetscCall(PetscFree(sf));
  for (PetscInt c = 0; c < nlc; c++) {
    eta[c] = PetscSqrtReal(eta[c]);
    emax   = PetscMax(emax, eta[c]);
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, loc, 3, MPIU_REAL, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(&emax, &e->eta_max, 1, MPIU_REAL, MPI_MAX, comm));
  e->volume       = PetscSqrtReal(loc[0]);
  e->contact      = PetscSqrtReal(loc[1]);
  e->estimate     = PetscSqrtReal(loc[0] + loc[1]);
  e->energy_norm  = PetscSqrtReal(loc[2]);
  e->estimate_rel = e->energy_norm > 0 ? e->estimate / e->energy_norm : 0;
  PetscCall(PetscFree2(sv, has));
  PetscCall(DMDestroy(&dmr));
  PetscCall(MeshArraysClose(&x.ar));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_ESTIMATE], 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* ---------- true error where the answer is known ---------- */

/* exact stress at (px, py) in body b: MMS by central differences of the
 * manufactured displacement (step dh), or the uniform sig_y'y' = -p in the
 * frame turned by -exact_angle */
static void ExactStress(const M2dScene *s, const BodyMat *bm, PetscReal px, PetscReal py, PetscReal dh, PetscReal sig[3])
{
  PetscReal eps[3], up[2], um[2], vp[2], vm[2];
  if (s->exact == M2D_EXACT_UNIFORM) { /* -p y' y'^T + tau (x' y'^T + y' x'^T), x' = (cos, sin), y' = (-sin, cos) of -exact_angle */
    PetscReal sn = PetscSinReal(s->exact_angle * PETSC_PI / 180), cs = PetscCosReal(s->exact_angle * PETSC_PI / 180), tau = s->exact_tau;
    sig[0] = -s->exact_p * sn * sn - 2 * tau * sn * cs;
    sig[1] = -s->exact_p * cs * cs + 2 * tau * sn * cs;
    sig[2] = s->exact_p * sn * cs + tau * (cs * cs - sn * sn);
    return;
  }
  M2dMMSDisplacement(s, px + dh, py, up);
  M2dMMSDisplacement(s, px - dh, py, um);
  M2dMMSDisplacement(s, px, py + dh, vp);
  M2dMMSDisplacement(s, px, py - dh, vm);
  eps[0] = (up[0] - um[0]) / (2 * dh);
  eps[1] = (vp[1] - vm[1]) / (2 * dh);
  eps[2] = (vp[0] - vm[0] + up[1] - um[1]) / (2 * dh);
  for (int r = 0; r < 3; r++) sig[r] = bm->D[3 * r] * eps[0] + bm->D[3 * r + 1] * eps[1] + bm->D[3 * r + 2] * eps[2];
}

PetscErrorCode M2dExactEnergyError(const M2dMesh *m, const M2dScene *s, Vec u, PetscReal *err, PetscReal *norm)
{
  Ctx       x;
  PetscReal loc[2] = {0, 0};

  PetscFunctionBeginUser;
  PetscCheck(s->exact == M2D_EXACT_MMS || s->exact == M2D_EXACT_UNIFORM, PetscObjectComm((PetscObject)m->dm), PETSC_ERR_USER_INPUT, "option -exact: the true energy error needs -exact mms or uniform");
  PetscCall(CtxOpen(m, s, u, &x));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    CellData  cd;
    PetscInt  b = m->cellbody[c - m->cStart];
    PetscReal dh;
    PetscCall(LoadCell(&x, c, b, 3, &cd));
    dh = 1e-3 * PetscSqrtReal(PetscSqr(cd.xy[4] - cd.xy[0]) + PetscSqr(cd.xy[5] - cd.xy[1]));
    for (int q = 0; q < cd.nq; q++) {
      PetscReal ex[3], d[3];
      ExactStress(s, &x.bm[b], cd.p[q][0], cd.p[q][1], dh, ex);
      for (int r = 0; r < 3; r++) d[r] = ex[r] - cd.sig[q][r];
      loc[0] += cd.w[q] * Quad(x.bm[b].C, d);
      loc[1] += cd.w[q] * Quad(x.bm[b].C, ex);
    }
  }
  PetscCall(MeshArraysClose(&x.ar));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, loc, 2, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)m->dm)));
  *err  = PetscSqrtReal(loc[0]);
  *norm = PetscSqrtReal(loc[1]);
  PetscFunctionReturn(0);
}
