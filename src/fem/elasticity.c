/* elasticity.c - Q4 plane elasticity: kernels, assembly, loads, Dirichlet,
 * stresses and the manufactured solution (see elasticity.h). */
#include "elasticity.h"
#include <petscsf.h>
#include <string.h>

static const PetscReal g2[2] = {-0.57735026918962576451, 0.57735026918962576451};
static const PetscReal g3[3] = {-0.77459666924148337704, 0.0, 0.77459666924148337704};
static const PetscReal w3[3] = {0.55555555555555555556, 0.88888888888888888889, 0.55555555555555555556};

void M2dMaterialMatrix(PetscReal E, PetscReal nu, M2dPlane plane, PetscReal D[9])
{
  PetscReal c;
  memset(D, 0, 9 * sizeof(PetscReal));
  if (plane == M2D_PLANE_STRAIN) {
    c    = E / ((1 + nu) * (1 - 2 * nu));
    D[0] = D[4] = c * (1 - nu);
    D[1] = D[3] = c * nu;
    D[8]        = c * (1 - 2 * nu) / 2;
  } else {
    c    = E / (1 - nu * nu);
    D[0] = D[4] = c;
    D[1] = D[3] = c * nu;
    D[8]        = c * (1 - nu) / 2;
  }
}

PetscReal Q4Shape(const PetscReal xy[8], PetscReal xi, PetscReal eta, PetscReal N[4], PetscReal dN[8])
{
  static const PetscReal sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
  PetscReal              dxi[4], deta[4], J[4] = {0, 0, 0, 0}, det;
  for (int a = 0; a < 4; a++) {
    N[a]    = 0.25 * (1 + sx[a] * xi) * (1 + sy[a] * eta);
    dxi[a]  = 0.25 * sx[a] * (1 + sy[a] * eta);
    deta[a] = 0.25 * sy[a] * (1 + sx[a] * xi);
    J[0] += dxi[a] * xy[2 * a];      /* dx/dxi */
    J[1] += deta[a] * xy[2 * a];     /* dx/deta */
    J[2] += dxi[a] * xy[2 * a + 1];  /* dy/dxi */
    J[3] += deta[a] * xy[2 * a + 1]; /* dy/deta */
  }
  det = J[0] * J[3] - J[1] * J[2];
  for (int a = 0; a < 4; a++) {
    dN[2 * a]     = (J[3] * dxi[a] - J[2] * deta[a]) / det;
    dN[2 * a + 1] = (-J[1] * dxi[a] + J[0] * deta[a]) / det;
  }
  return det;
}

PetscReal M2dLambda(PetscReal E, PetscReal nu, M2dPlane plane)
{
  PetscReal mu = E / (2 * (1 + nu)), lam = E * nu / ((1 + nu) * (1 - 2 * nu));
  return plane == M2D_PLANE_STRAIN ? lam : 2 * lam * mu / (lam + 2 * mu);
}

/* B (3x8) at one point from the shape-function derivatives */
static void FillB(const PetscReal dN[8], PetscReal B[3][8])
{
  memset(B, 0, 24 * sizeof(PetscReal));
  for (int a = 0; a < 4; a++) {
    B[0][2 * a]     = dN[2 * a];
    B[1][2 * a + 1] = dN[2 * a + 1];
    B[2][2 * a]     = dN[2 * a + 1];
    B[2][2 * a + 1] = dN[2 * a];
  }
}

static void AddBtDB(PetscReal Ke[64], PetscReal w, const PetscReal B[3][8], const PetscReal D[9])
{
  PetscReal DB[3][8];
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 8; k++) DB[r][k] = D[3 * r] * B[0][k] + D[3 * r + 1] * B[1][k] + D[3 * r + 2] * B[2][k];
  for (int k = 0; k < 8; k++)
    for (int l = 0; l < 8; l++) Ke[8 * k + l] += w * (B[0][k] * DB[0][l] + B[1][k] * DB[1][l] + B[2][k] * DB[2][l]);
}

/* D = Dl + Dr with Dl = lam m m^T: sri integrates Dl at the centre (weight 4) */
static void SplitD(const PetscReal D[9], PetscBool sri, PetscReal lam, PetscReal Dr[9], PetscReal Dl[9])
{
  memcpy(Dr, D, 9 * sizeof(PetscReal));
  memset(Dl, 0, 9 * sizeof(PetscReal));
  if (!sri) return;
  Dl[0] = Dl[1] = Dl[3] = Dl[4] = lam;
  for (int k = 0; k < 9; k++) Dr[k] -= Dl[k];
}

void Q4Stiffness(const PetscReal xy[8], const PetscReal D[9], PetscBool sri, PetscReal lam, PetscReal Ke[64])
{
  PetscReal Dr[9], Dl[9], N[4], dN[8], B[3][8];
  SplitD(D, sri, lam, Dr, Dl);
  memset(Ke, 0, 64 * sizeof(PetscReal));
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) {
      PetscReal w = Q4Shape(xy, g2[i], g2[j], N, dN);
      FillB(dN, B);
      AddBtDB(Ke, w, B, Dr);
    }
  if (sri) {
    PetscReal w = 4 * Q4Shape(xy, 0, 0, N, dN);
    FillB(dN, B);
    AddBtDB(Ke, w, B, Dl);
  }
}

void Q4Strain(const PetscReal dN[8], const PetscReal ue[8], PetscReal eps[3])
{
  eps[0] = eps[1] = eps[2] = 0;
  for (int a = 0; a < 4; a++) {
    eps[0] += dN[2 * a] * ue[2 * a];
    eps[1] += dN[2 * a + 1] * ue[2 * a + 1];
    eps[2] += dN[2 * a + 1] * ue[2 * a] + dN[2 * a] * ue[2 * a + 1];
  }
}

void Q4AverageStress(const PetscReal xy[8], const PetscReal D[9], PetscBool sri, PetscReal lam, const PetscReal ue[8], PetscReal sig[3])
{
  PetscReal area = 0, Dr[9], Dl[9], N[4], dN[8], eps[3];
  SplitD(D, sri, lam, Dr, Dl);
  sig[0] = sig[1] = sig[2] = 0;
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) {
      PetscReal w = Q4Shape(xy, g2[i], g2[j], N, dN);
      Q4Strain(dN, ue, eps);
      for (int r = 0; r < 3; r++) sig[r] += w * (Dr[3 * r] * eps[0] + Dr[3 * r + 1] * eps[1] + Dr[3 * r + 2] * eps[2]);
      area += w;
    }
  for (int r = 0; r < 3; r++) sig[r] /= area;
  if (sri) { /* the lambda part from the centre strain, as in the stiffness */
    Q4Shape(xy, 0, 0, N, dN);
    Q4Strain(dN, ue, eps);
    sig[0] += lam * (eps[0] + eps[1]);
    sig[1] += lam * (eps[0] + eps[1]);
  }
}

/* ---------- manufactured solution ----------
 * u_x = A sin(pi x) cos(pi y), u_y = A cos(pi x) sin(pi y) on every body, with
 * the body force f = -div sigma(u) for that body's Lame constants (plane stress
 * uses the effective lambda* = 2 lambda mu / (lambda + 2 mu)). */
void M2dMMSDisplacement(const M2dScene *s, PetscReal x, PetscReal y, PetscReal u[2])
{
  const PetscReal A = s->mms_amplitude, k = s->mms_wavenumber;
  u[0]              = A * PetscSinReal(k * x) * PetscCosReal(k * y);
  u[1]              = A * PetscCosReal(k * x) * PetscSinReal(k * y);
}

static void MMSBodyForce(const M2dScene *s, const M2dBody *b, PetscReal x, PetscReal y, PetscReal f[2])
{
  const PetscReal A = s->mms_amplitude, k = s->mms_wavenumber, k2 = k * k;
  PetscReal       mu = b->E / (2 * (1 + b->nu)), lam = b->E * b->nu / ((1 + b->nu) * (1 - 2 * b->nu));
  PetscReal       sx = PetscSinReal(k * x), cx = PetscCosReal(k * x), sy = PetscSinReal(k * y), cy = PetscCosReal(k * y);
  PetscReal       ux = A * sx * cy, uy = A * cx * sy;
  PetscReal       ux_xx = -k2 * ux, ux_yy = -k2 * ux, ux_xy = -A * k2 * cx * sy;
  PetscReal       uy_xx = -k2 * uy, uy_yy = -k2 * uy, uy_xy = -A * k2 * sx * cy;
  if (s->plane == M2D_PLANE_STRESS) lam = 2 * lam * mu / (lam + 2 * mu);
  f[0] = -(mu * (ux_xx + ux_yy) + (lam + mu) * (ux_xx + uy_xy));
  f[1] = -(mu * (uy_xx + uy_yy) + (lam + mu) * (ux_xy + uy_yy));
}

/* D and the lambda of the split, per body */
static void BodyMaterials(const M2dScene *s, PetscReal D[][9], PetscReal lam[])
{
  for (PetscInt b = 0; b < s->nbody; b++) {
    M2dMaterialMatrix(s->body[b].E, s->body[b].nu, s->plane, D[b]);
    lam[b] = M2dLambda(s->body[b].E, s->body[b].nu, s->plane);
  }
}

static PetscErrorCode CellDofs(const M2dMesh *m, PetscSection lsec, PetscInt c, PetscInt idx[8])
{
  PetscFunctionBeginUser;
  for (int a = 0; a < 4; a++) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(lsec, m->cellverts[4 * (c - m->cStart) + a], &off));
    idx[2 * a]     = off;
    idx[2 * a + 1] = off + 1;
  }
  PetscFunctionReturn(0);
}

/* the edge loads of load stage `stage` (scene.h) */
static PetscErrorCode AddEdgeLoads(const M2dMesh *m, const M2dScene *s, PetscInt stage, const M2dMeshArrays *ar, PetscScalar *fl)
{
  PetscFunctionBeginUser;
  for (PetscInt l = 0; l < s->nload; l++) {
    const M2dEdgeLoad *ld  = &s->load[l];
    const char     *opt = ld->is_pressure ? "-pressure" : "-traction";
    IS              is;
    const PetscInt *pts;
    PetscInt        n;
    if (ld->stage != stage) continue;
    PetscCall(MeshGetGroupIS(m, ld->group, opt, &is));
    PetscCall(ISGetLocalSize(is, &n));
    PetscCall(ISGetIndices(is, &pts));
    for (PetscInt i = 0; i < n; i++) {
      PetscInt        e = pts[i], nsupp, ncone, c, offa, offb, la, lb;
      const PetscInt *supp, *cone;
      PetscReal       xa[2], xb[2], t[2], nrm[2], len, cx = 0, cy = 0, xy[8];
      if (e < m->eStart || e >= m->eEnd || m->edgeghost[e - m->eStart]) continue;
      PetscCall(DMPlexGetSupportSize(m->dm, e, &nsupp));
      PetscCall(DMPlexGetSupport(m->dm, e, &supp));
      PetscCall(DMPlexGetConeSize(m->dm, e, &ncone));
      PetscCall(DMPlexGetCone(m->dm, e, &cone));
      PetscCheck(nsupp >= 1 && ncone == 2, PETSC_COMM_SELF, PETSC_ERR_PLIB, "edge %" PetscInt_FMT " without cell", e);
      c = supp[0];
      PetscCall(PetscSectionGetOffset(ar->cs, cone[0], &offa));
      PetscCall(PetscSectionGetOffset(ar->cs, cone[1], &offb));
      xa[0] = PetscRealPart(ar->ca[offa]);
      xa[1] = PetscRealPart(ar->ca[offa + 1]);
      xb[0] = PetscRealPart(ar->ca[offb]);
      xb[1] = PetscRealPart(ar->ca[offb + 1]);
      len    = PetscSqrtReal((xb[0] - xa[0]) * (xb[0] - xa[0]) + (xb[1] - xa[1]) * (xb[1] - xa[1]));
      nrm[0] = (xb[1] - xa[1]) / len;
      nrm[1] = -(xb[0] - xa[0]) / len;
      MeshCellCoordinates(m, ar->ca, ar->cs, c, xy);
      for (int k = 0; k < 4; k++) {
        cx += 0.25 * xy[2 * k];
        cy += 0.25 * xy[2 * k + 1];
      }
      if ((0.5 * (xa[0] + xb[0]) - cx) * nrm[0] + (0.5 * (xa[1] + xb[1]) - cy) * nrm[1] < 0) {
        nrm[0] = -nrm[0];
        nrm[1] = -nrm[1];
      }
      PetscCall(PetscSectionGetOffset(ar->lsec, cone[0], &la));
      PetscCall(PetscSectionGetOffset(ar->lsec, cone[1], &lb));
      for (int g = 0; g < 2; g++) { /* 2-point Gauss: exact for linear pressure */
        PetscReal Na = 0.5 * (1 - g2[g]), Nb = 0.5 * (1 + g2[g]);
        PetscReal x = Na * xa[0] + Nb * xb[0], y = Na * xa[1] + Nb * xb[1];
        if (ld->is_pressure) {
          PetscReal p = ld->p + ld->grad[0] * x + ld->grad[1] * y;
          t[0]        = -p * nrm[0];
          t[1]        = -p * nrm[1];
        } else {
          t[0] = ld->t[0];
          t[1] = ld->t[1];
        }
        for (int d = 0; d < 2; d++) {
          fl[la + d] += 0.5 * len * 0.5 * Na * 2 * t[d];
          fl[lb + d] += 0.5 * len * 0.5 * Nb * 2 * t[d];
        }
      }
    }
    PetscCall(ISRestoreIndices(is, &pts));
    PetscCall(ISDestroy(&is));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ElasticityPressureResultant(const M2dMesh *m, const M2dEdgeLoad *l, PetscReal *R, PetscBool *both)
{
  PetscInt        n;
  const PetscInt *pts;
  M2dMeshArrays   ar;
  IS              is;
  PetscReal       sum = 0, ext[2] = {0, 0}; /* -min x, max x */

  PetscFunctionBeginUser;
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  PetscCall(MeshGetGroupIS(m, l->group, "-pressure", &is));
  PetscCall(ISGetLocalSize(is, &n));
  PetscCall(ISGetIndices(is, &pts));
  for (PetscInt i = 0; i < n; i++) {
    const PetscInt *cone;
    PetscInt        oa, ob;
    PetscReal       xa[2], xb[2], len;
    if (pts[i] < m->eStart || pts[i] >= m->eEnd || m->edgeghost[pts[i] - m->eStart]) continue;
    PetscCall(DMPlexGetCone(m->dm, pts[i], &cone));
    PetscCall(PetscSectionGetOffset(ar.cs, cone[0], &oa));
    PetscCall(PetscSectionGetOffset(ar.cs, cone[1], &ob));
    for (int d = 0; d < 2; d++) {
      xa[d] = PetscRealPart(ar.ca[oa + d]);
      xb[d] = PetscRealPart(ar.ca[ob + d]);
    }
    len = PetscSqrtReal(PetscSqr(xb[0] - xa[0]) + PetscSqr(xb[1] - xa[1]));
    sum += len * (l->p + l->grad[0] * 0.5 * (xa[0] + xb[0]) + l->grad[1] * 0.5 * (xa[1] + xb[1]));
    ext[0] = PetscMax(ext[0], -PetscMin(xa[0], xb[0]));
    ext[1] = PetscMax(ext[1], PetscMax(xa[0], xb[0]));
  }
  PetscCall(ISRestoreIndices(is, &pts));
  PetscCall(ISDestroy(&is));
  PetscCall(MeshArraysClose(&ar));
  PetscCallMPI(MPI_Allreduce(&sum, R, 1, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)m->dm)));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, ext, 2, MPIU_REAL, MPIU_MAX, PetscObjectComm((PetscObject)m->dm)));
  *both = (PetscBool)(ext[0] > 1e-9 * (ext[0] + ext[1]) && ext[1] > 1e-9 * (ext[0] + ext[1]));
  PetscFunctionReturn(0);
}

PetscErrorCode ElasticityAssemble(const M2dMesh *m, const M2dScene *s, const M2dFrames *fr, Mat K, Vec f)
{
  M2dMeshArrays ar;
  Vec           fl;
  PetscScalar  *fa;
  PetscReal     D[M2D_MAX_BODIES][9], lam[M2D_MAX_BODIES];

  PetscFunctionBeginUser;
  BodyMaterials(s, D, lam);
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  PetscCall(DMGetLocalVector(m->dm, &fl));
  PetscCall(VecZeroEntries(fl));
  PetscCall(VecGetArray(fl, &fa));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    PetscReal   xy[8], Ke[64];
    PetscInt    idx[8];
    PetscInt    b = m->cellbody[c - m->cStart];
    MeshCellCoordinates(m, ar.ca, ar.cs, c, xy);
    Q4Stiffness(xy, D[b], s->sri, lam[b], Ke);
    M2dFramesRotateElement(fr, m, &m->cellverts[4 * (c - m->cStart)], Ke);
    PetscCall(CellDofs(m, ar.lsec, c, idx));
    PetscCall(MatSetValuesLocal(K, 8, idx, 8, idx, Ke, ADD_VALUES));
    if (s->exact == M2D_EXACT_MMS) { /* body force, 3x3 Gauss */
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
          PetscReal N[4], dN[8], x = 0, y = 0, fb[2];
          PetscReal w = w3[i] * w3[j] * Q4Shape(xy, g3[i], g3[j], N, dN);
          for (int a = 0; a < 4; a++) {
            x += N[a] * xy[2 * a];
            y += N[a] * xy[2 * a + 1];
          }
          MMSBodyForce(s, &s->body[b], x, y, fb);
          for (int a = 0; a < 4; a++) {
            fa[idx[2 * a]] += w * N[a] * fb[0];
            fa[idx[2 * a + 1]] += w * N[a] * fb[1];
          }
        }
    }
  }
  PetscCall(AddEdgeLoads(m, s, 0, &ar, fa));
  PetscCall(VecRestoreArray(fl, &fa));
  PetscCall(M2dFramesRotateLocal(fr, m, fl, PETSC_FALSE)); /* f~ = T^T f, each rank's share */
  PetscCall(MeshArraysClose(&ar));
  PetscCall(MatAssemblyBegin(K, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(K, MAT_FINAL_ASSEMBLY));
  PetscCall(VecZeroEntries(f));
  PetscCall(DMLocalToGlobal(m->dm, fl, ADD_VALUES, f));
  PetscCall(DMRestoreLocalVector(m->dm, &fl));
  PetscFunctionReturn(0);
}

PetscErrorCode ElasticityStageLoad(const M2dMesh *m, const M2dScene *s, const M2dFrames *fr, PetscInt stage, Vec f)
{
  M2dMeshArrays ar;
  Vec           fl;
  PetscScalar  *fa;

  PetscFunctionBeginUser;
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  PetscCall(DMGetLocalVector(m->dm, &fl));
  PetscCall(VecZeroEntries(fl));
  PetscCall(VecGetArray(fl, &fa));
  PetscCall(AddEdgeLoads(m, s, stage, &ar, fa));
  PetscCall(VecRestoreArray(fl, &fa));
  PetscCall(M2dFramesRotateLocal(fr, m, fl, PETSC_FALSE));
  PetscCall(MeshArraysClose(&ar));
  PetscCall(VecZeroEntries(f));
  PetscCall(DMLocalToGlobal(m->dm, fl, ADD_VALUES, f));
  PetscCall(DMRestoreLocalVector(m->dm, &fl));
  PetscFunctionReturn(0);
}

PetscErrorCode ElasticityDirichletRows(const M2dMesh *m, const M2dScene *s, const M2dFrames *fr, PetscInt *n, PetscInt **rows, PetscScalar **vals)
{
  PetscSection  gsec;
  M2dMeshArrays ar;
  PetscInt      nv = m->vEnd - m->vStart, cnt = 0;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  for (PetscInt v = 0; v < nv; v++) {
    PetscInt goff;
    PetscCall(PetscSectionGetOffset(gsec, v + m->vStart, &goff));
    if (goff >= 0) cnt += (fr->mask[v] & 1) + ((fr->mask[v] >> 1) & 1); /* the owner sets them */
  }
  PetscCall(PetscMalloc1(cnt + 1, rows));
  PetscCall(PetscMalloc1(cnt + 1, vals));
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  cnt = 0;
  for (PetscInt v = 0; v < nv; v++) {
    PetscInt  goff, coff;
    PetscReal ue[2], nrm[2];
    PetscCall(PetscSectionGetOffset(gsec, v + m->vStart, &goff));
    if (!fr->mask[v] || goff < 0) continue;
    ue[0] = fr->value[2 * v];
    ue[1] = fr->value[2 * v + 1];
    if (s->exact == M2D_EXACT_MMS) { /* the exact field, in the vertex's frame */
      PetscCall(PetscSectionGetOffset(ar.cs, v + m->vStart, &coff));
      M2dMMSDisplacement(s, PetscRealPart(ar.ca[coff]), PetscRealPart(ar.ca[coff + 1]), ue);
      if (M2dFramesAt(fr, m, v + m->vStart, nrm)) ue[0] = nrm[0] * ue[0] + nrm[1] * ue[1];
    }
    for (int d = 0; d < 2; d++)
      if (fr->mask[v] & (1 << d)) {
        (*rows)[cnt]   = goff + d;
        (*vals)[cnt++] = ue[d];
      }
  }
  PetscCall(MeshArraysClose(&ar));
  *n = cnt;
  PetscFunctionReturn(0);
}

/* the unit rows' diagonal: K's mean diagonal, so they do not spoil the conditioning */
static PetscErrorCode DirichletDiagonal(Mat K, PetscReal *diag)
{
  PetscInt N;
  Vec      d;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(K, &d, NULL));
  PetscCall(MatGetDiagonal(K, d));
  PetscCall(VecNorm(d, NORM_1, diag));
  PetscCall(VecGetSize(d, &N));
  PetscCall(VecDestroy(&d));
  *diag = N > 0 && *diag > 0 ? *diag / N : 1.0;
  PetscFunctionReturn(0);
}

/* u: the values on the held rows, 0 elsewhere; *diag: the unit rows' diagonal */
static PetscErrorCode DirichletValues(Mat K, Vec u, PetscInt n, const PetscInt rows[], const PetscScalar vals[], PetscReal *diag)
{
  PetscFunctionBeginUser;
  PetscCall(DirichletDiagonal(K, diag));
  PetscCall(VecZeroEntries(u));
  PetscCall(VecSetValues(u, n, rows, vals, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(u));
  PetscCall(VecAssemblyEnd(u));
  PetscFunctionReturn(0);
}

PetscErrorCode ElasticityLiftDirichlet(Mat K, Vec f, Vec u, PetscInt n, const PetscInt rows[], const PetscScalar vals[])
{
  PetscReal diag;
  Vec       ku;

  PetscFunctionBeginUser;
  PetscCall(DirichletValues(K, u, n, rows, vals, &diag));
  PetscCall(VecDuplicate(f, &ku)); /* as MatZeroRowsColumns: f - K u on the free rows, diag u on the held ones */
  PetscCall(MatMult(K, u, ku));
  PetscCall(VecAXPY(f, -1.0, ku));
  PetscCall(VecDestroy(&ku));
  for (PetscInt i = 0; i < n; i++) PetscCall(VecSetValue(f, rows[i], diag * vals[i], INSERT_VALUES));
  PetscCall(VecAssemblyBegin(f));
  PetscCall(VecAssemblyEnd(f));
  PetscFunctionReturn(0);
}

PetscErrorCode ElasticityApplyDirichlet(Mat K, Vec f, Vec u, PetscInt n, const PetscInt rows[], const PetscScalar vals[])
{
  PetscReal diag;

  PetscFunctionBeginUser;
  PetscCall(DirichletValues(K, u, n, rows, vals, &diag));
  PetscCall(MatZeroRowsColumns(K, n, rows, diag, u, f));
  PetscFunctionReturn(0);
}

PetscErrorCode ElasticityCellStress(const M2dMesh *m, const M2dScene *s, Vec u, PetscReal *stress)
{
  M2dMeshArrays ar;
  PetscReal     D[M2D_MAX_BODIES][9], lam[M2D_MAX_BODIES];

  PetscFunctionBeginUser;
  BodyMaterials(s, D, lam);
  PetscCall(MeshArraysOpen(m, u, &ar));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    PetscReal  xy[8], ue[8], sig[3], sz, *out = &stress[5 * (c - m->cStart)];
    PetscInt   idx[8], b = m->cellbody[c - m->cStart];
    MeshCellCoordinates(m, ar.ca, ar.cs, c, xy);
    PetscCall(CellDofs(m, ar.lsec, c, idx));
    for (int k = 0; k < 8; k++) ue[k] = PetscRealPart(ar.ua[idx[k]]);
    Q4AverageStress(xy, D[b], s->sri, lam[b], ue, sig);
    sz     = s->plane == M2D_PLANE_STRAIN ? s->body[b].nu * (sig[0] + sig[1]) : 0.0;
    out[0] = sig[0];
    out[1] = sig[1];
    out[2] = sz;
    out[3] = sig[2];
    out[4] = PetscSqrtReal(0.5 * ((sig[0] - sig[1]) * (sig[0] - sig[1]) + (sig[1] - sz) * (sig[1] - sz) + (sz - sig[0]) * (sz - sig[0])) + 3 * sig[2] * sig[2]);
  }
  PetscCall(MeshArraysClose(&ar));
  PetscFunctionReturn(0);
}

PetscErrorCode ElasticityCellStrain(const M2dMesh *m, const M2dScene *s, Vec u, PetscReal *strain)
{
  M2dMeshArrays ar;

  PetscFunctionBeginUser;
  PetscCall(MeshArraysOpen(m, u, &ar));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    PetscReal xy[8], ue[8], N[4], dN[8], eps[3], *out = &strain[2 * (c - m->cStart)];
    PetscInt  idx[8], b = m->cellbody[c - m->cStart];
    MeshCellCoordinates(m, ar.ca, ar.cs, c, xy);
    PetscCall(CellDofs(m, ar.lsec, c, idx));
    for (int k = 0; k < 8; k++) ue[k] = PetscRealPart(ar.ua[idx[k]]);
    out[0] = out[1] = 0;
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2; j++) {
        PetscReal mean, radius, w = 0, nu = s->body[b].nu;
        Q4Shape(xy, g2[i], g2[j], N, dN);
        Q4Strain(dN, ue, eps);
        for (int a = 0; a < 4; a++) w += 0.5 * (dN[2 * a] * ue[2 * a + 1] - dN[2 * a + 1] * ue[2 * a]); /* (u_y,x - u_x,y) / 2 */
        mean   = 0.5 * (eps[0] + eps[1]);
        radius = PetscSqrtReal(PetscSqr(0.5 * (eps[0] - eps[1])) + PetscSqr(0.5 * eps[2]));
        out[0] = PetscMax(out[0], PetscAbsReal(mean) + radius);
        if (s->plane == M2D_PLANE_STRESS) out[0] = PetscMax(out[0], PetscAbsReal(nu / (1 - nu) * (eps[0] + eps[1]))); /* eps_zz */
        out[1] = PetscMax(out[1], PetscAbsReal(w));
      }
  }
  PetscCall(MeshArraysClose(&ar));
  PetscFunctionReturn(0);
}

PetscErrorCode ElasticityMMSError(const M2dMesh *m, const M2dScene *s, Vec u, PetscReal *err, PetscReal *norm, PetscReal *hmax)
{
  M2dMeshArrays ar;
  PetscReal     loc[2] = {0, 0}, h = 0;

  PetscFunctionBeginUser;
  PetscCall(MeshArraysOpen(m, u, &ar));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    PetscReal xy[8];
    PetscInt  idx[8];
    MeshCellCoordinates(m, ar.ca, ar.cs, c, xy);
    PetscCall(CellDofs(m, ar.lsec, c, idx));
    for (int a = 0; a < 4; a++)
      for (int b = a + 1; b < 4; b++) h = PetscMax(h, PetscSqrtReal(PetscSqr(xy[2 * a] - xy[2 * b]) + PetscSqr(xy[2 * a + 1] - xy[2 * b + 1])));
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        PetscReal N[4], dN[8], x = 0, y = 0, uh[2] = {0, 0}, ue[2];
        PetscReal w = w3[i] * w3[j] * Q4Shape(xy, g3[i], g3[j], N, dN);
        for (int a = 0; a < 4; a++) {
          x += N[a] * xy[2 * a];
          y += N[a] * xy[2 * a + 1];
          uh[0] += N[a] * PetscRealPart(ar.ua[idx[2 * a]]);
          uh[1] += N[a] * PetscRealPart(ar.ua[idx[2 * a + 1]]);
        }
        M2dMMSDisplacement(s, x, y, ue);
        loc[0] += w * (PetscSqr(uh[0] - ue[0]) + PetscSqr(uh[1] - ue[1]));
        loc[1] += w * (PetscSqr(ue[0]) + PetscSqr(ue[1]));
      }
  }
  PetscCall(MeshArraysClose(&ar));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, loc, 2, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)m->dm)));
  PetscCallMPI(MPI_Allreduce(&h, hmax, 1, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)m->dm)));
  *err  = PetscSqrtReal(loc[0]);
  *norm = PetscSqrtReal(loc[1]);
  PetscFunctionReturn(0);
}
