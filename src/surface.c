/* surface.c - gather the contact surfaces on every rank (see surface.h). */
#include "surface.h"
#include <petscsf.h>

PetscErrorCode SurfaceCreate(PetscInt nnode, const PetscReal x[], const PetscInt gdof[], PetscInt nedge, const PetscInt edge[], M2dSurface *s)
{
  PetscInt *cnt;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof(*s)));
  s->nnode = nnode;
  s->nedge = nedge;
  s->body  = -1;
  PetscCall(PetscMalloc3(2 * nnode + 1, &s->x, nnode + 1, &s->gdof, 2 * nedge + 1, &s->edge));
  PetscCall(PetscMalloc2(2 * nedge + 1, &s->normal, nedge + 1, &s->len));
  PetscCall(PetscArraycpy(s->x, x, 2 * nnode));
  PetscCall(PetscArraycpy(s->gdof, gdof, nnode));
  PetscCall(PetscArraycpy(s->edge, edge, 2 * nedge));
  s->lo[0] = s->lo[1] = PETSC_MAX_REAL;
  s->hi[0] = s->hi[1] = PETSC_MIN_REAL;
  for (PetscInt i = 0; i < nnode; i++)
    for (int d = 0; d < 2; d++) {
      s->lo[d] = PetscMin(s->lo[d], x[2 * i + d]);
      s->hi[d] = PetscMax(s->hi[d], x[2 * i + d]);
    }
  for (PetscInt e = 0; e < nedge; e++) {
    const PetscReal *a = &x[2 * edge[2 * e]], *b = &x[2 * edge[2 * e + 1]];
    PetscReal        t[2] = {b[0] - a[0], b[1] - a[1]}, L = PetscSqrtReal(t[0] * t[0] + t[1] * t[1]);
    s->len[e]             = L;
    s->normal[2 * e]      = t[1] / L;
    s->normal[2 * e + 1]  = -t[0] / L;
  }
  PetscCall(PetscCalloc1(nnode + 1, &s->n2e_ptr));
  PetscCall(PetscMalloc1(2 * nedge + 1, &s->n2e));
  for (PetscInt e = 0; e < 2 * nedge; e++) s->n2e_ptr[edge[e] + 1]++;
  for (PetscInt i = 0; i < nnode; i++) s->n2e_ptr[i + 1] += s->n2e_ptr[i];
  PetscCall(PetscCalloc1(nnode + 1, &cnt));
  for (PetscInt e = 0; e < nedge; e++)
    for (int k = 0; k < 2; k++) {
      PetscInt i                          = edge[2 * e + k];
      s->n2e[s->n2e_ptr[i] + cnt[i]++] = e;
    }
  PetscCall(PetscFree(cnt));
  PetscFunctionReturn(0);
}

PetscErrorCode SurfaceDestroy(M2dSurface *s)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree3(s->x, s->gdof, s->edge));
  PetscCall(PetscFree2(s->normal, s->len));
  PetscCall(PetscFree(s->n2e_ptr));
  PetscCall(PetscFree(s->n2e));
  PetscFunctionReturn(0);
}

void SurfaceNodeNormal(const M2dSurface *s, PetscInt i, PetscReal n[2])
{
  PetscReal l;
  n[0] = n[1] = 0;
  for (PetscInt k = s->n2e_ptr[i]; k < s->n2e_ptr[i + 1]; k++) {
    n[0] += s->normal[2 * s->n2e[k]];
    n[1] += s->normal[2 * s->n2e[k] + 1];
  }
  l = PetscSqrtReal(n[0] * n[0] + n[1] * n[1]);
  if (l > 0) {
    n[0] /= l;
    n[1] /= l;
  }
}

typedef struct {
  PetscInt gdof;
  PetscInt pos;
} DofPos;

static int CmpDofPos(const void *a, const void *b)
{
  PetscInt x = ((const DofPos *)a)->gdof, y = ((const DofPos *)b)->gdof;
  return (x > y) - (x < y);
}

PetscErrorCode SurfaceGather(const M2dMesh *m, const char *group, const char *option, M2dSurface *s)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)m->dm);
  IS                 is;
  const PetscInt    *pts;
  PetscInt           n, nloc = 0, nedge, nnode = 0, *edge, *gdof;
  PetscSection       gsec, cs;
  Vec                cl;
  const PetscScalar *ca;
  double            *rec, *all;
  PetscMPIInt        size, nrec, *counts, *displs;
  PetscReal         *x;
  DofPos            *dp;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(MeshGetGroupIS(m, group, option, &is));
  PetscCheck(MeshGroupDim(m, group) == 1, comm, PETSC_ERR_USER_INPUT, "option %s: physical group '%s' is not a curve", option, group);
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(VecGetArrayRead(cl, &ca));
  PetscCall(ISGetLocalSize(is, &n));
  PetscCall(ISGetIndices(is, &pts));
  PetscCall(PetscMalloc1(7 * n + 1, &rec));
  for (PetscInt i = 0; i < n; i++) {
    PetscInt        e = pts[i], c, v[2], off[2], g[2];
    const PetscInt *cone, *supp;
    PetscReal       xy[8], cx = 0, cy = 0, xa[2], xb[2];
    if (e < m->eStart || e >= m->eEnd || m->edgeghost[e - m->eStart]) continue;
    PetscCall(DMPlexGetCone(m->dm, e, &cone));
    PetscCall(DMPlexGetSupport(m->dm, e, &supp));
    c = supp[0];
    MeshCellCoordinates(m, ca, cs, c, xy);
    for (int k = 0; k < 4; k++) {
      cx += 0.25 * xy[2 * k];
      cy += 0.25 * xy[2 * k + 1];
    }
    v[0] = cone[0];
    v[1] = cone[1];
    for (int k = 0; k < 2; k++) {
      PetscCall(PetscSectionGetOffset(cs, v[k], &off[k]));
      PetscCall(PetscSectionGetOffset(gsec, v[k], &g[k]));
      if (g[k] < 0) g[k] = -(g[k] + 1);
    }
    xa[0] = PetscRealPart(ca[off[0]]);
    xa[1] = PetscRealPart(ca[off[0] + 1]);
    xb[0] = PetscRealPart(ca[off[1]]);
    xb[1] = PetscRealPart(ca[off[1] + 1]);
    /* orient body-on-the-left: the outward normal (t_y, -t_x) points away from the cell */
    if ((0.5 * (xa[0] + xb[0]) - cx) * (xb[1] - xa[1]) - (0.5 * (xa[1] + xb[1]) - cy) * (xb[0] - xa[0]) < 0) {
      PetscInt  tg = g[0];
      PetscReal t0 = xa[0], t1 = xa[1];
      g[0]         = g[1];
      g[1]         = tg;
      xa[0]        = xb[0];
      xa[1]        = xb[1];
      xb[0]        = t0;
      xb[1]        = t1;
    }
    rec[7 * nloc + 0] = (double)g[0];
    rec[7 * nloc + 1] = (double)g[1];
    rec[7 * nloc + 2] = xa[0];
    rec[7 * nloc + 3] = xa[1];
    rec[7 * nloc + 4] = xb[0];
    rec[7 * nloc + 5] = xb[1];
    rec[7 * nloc + 6] = (double)m->cellbody[c - m->cStart];
    nloc++;
  }
  PetscCall(ISRestoreIndices(is, &pts));
  PetscCall(ISDestroy(&is));
  PetscCall(VecRestoreArrayRead(cl, &ca));
  /* all ranks get every edge */
  PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  nrec = (PetscMPIInt)(7 * nloc);
  PetscCallMPI(MPI_Allgather(&nrec, 1, MPI_INT, counts, 1, MPI_INT, comm));
  displs[0] = 0;
  for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + counts[r];
  PetscCall(PetscMalloc1(displs[size] + 1, &all));
  PetscCallMPI(MPI_Allgatherv(rec, nrec, MPI_DOUBLE, all, counts, displs, MPI_DOUBLE, comm));
  nedge = displs[size] / 7;
  PetscCall(PetscFree2(counts, displs));
  PetscCall(PetscFree(rec));
  PetscCheck(nedge > 0, comm, PETSC_ERR_USER_INPUT, "option %s: physical group '%s' has no edges", option, group);
  /* unique nodes by global dof, in a rank-independent order */
  PetscCall(PetscMalloc1(2 * nedge, &dp));
  for (PetscInt k = 0; k < 2 * nedge; k++) {
    dp[k].gdof = (PetscInt)all[7 * (k / 2) + (k % 2)];
    dp[k].pos  = k;
  }
  qsort(dp, (size_t)(2 * nedge), sizeof(DofPos), CmpDofPos);
  PetscCall(PetscMalloc3(2 * nedge, &edge, 2 * nedge, &gdof, 4 * nedge, &x));
  for (PetscInt k = 0; k < 2 * nedge; k++) {
    PetscInt e = dp[k].pos / 2, end = dp[k].pos % 2;
    if (k == 0 || dp[k].gdof != dp[k - 1].gdof) {
      gdof[nnode]      = dp[k].gdof;
      x[2 * nnode]     = all[7 * e + 2 + 2 * end];
      x[2 * nnode + 1] = all[7 * e + 3 + 2 * end];
      nnode++;
    }
    edge[dp[k].pos] = nnode - 1;
  }
  PetscCall(SurfaceCreate(nnode, x, gdof, nedge, edge, s));
  s->body = (PetscInt)all[6];
  for (PetscInt e = 1; e < nedge; e++) PetscCheck((PetscInt)all[7 * e + 6] == s->body, comm, PETSC_ERR_USER_INPUT, "option %s: physical curve '%s' lies on more than one body", option, group);
  PetscCall(PetscFree3(edge, gdof, x));
  PetscCall(PetscFree(dp));
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}
