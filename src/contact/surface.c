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
  for (PetscInt k = s->n2e_ptr[i]; k < s->n2e_ptr[i + 1]; k++) { /* weights 1/length: exact on a circle */
    n[0] += s->normal[2 * s->n2e[k]] / s->len[s->n2e[k]];
    n[1] += s->normal[2 * s->n2e[k] + 1] / s->len[s->n2e[k]];
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

/* one edge of the surface as gathered: its two nodes (global dof of u_x,
 * coordinates), oriented body-on-the-left, and the body of its cell; all
 * doubles so that one MPI datatype carries it */
typedef struct {
  double gdof[2];
  double x[4];
  double body;
} EdgeRecord;
#define M2D_EDGE_DOUBLES ((int)(sizeof(EdgeRecord) / sizeof(double)))

/* the record of local edge e: orient body-on-the-left (the outward normal (t_y, -t_x) points away from its cell) */
static PetscErrorCode EdgeRecordMake(const M2dMesh *m, PetscSection gsec, PetscSection cs, const PetscScalar *ca, PetscInt e, EdgeRecord *r)
{
  const PetscInt *cone, *supp;
  PetscReal       xy[8], cx = 0, cy = 0;
  PetscInt        c;

  PetscFunctionBeginUser;
  PetscCall(DMPlexGetCone(m->dm, e, &cone));
  PetscCall(DMPlexGetSupport(m->dm, e, &supp));
  c = supp[0];
  MeshCellCoordinates(m, ca, cs, c, xy);
  for (int k = 0; k < 4; k++) {
    cx += 0.25 * xy[2 * k];
    cy += 0.25 * xy[2 * k + 1];
  }
  for (int k = 0; k < 2; k++) {
    PetscInt off, g;
    PetscCall(PetscSectionGetOffset(cs, cone[k], &off));
    PetscCall(PetscSectionGetOffset(gsec, cone[k], &g));
    r->gdof[k]     = (double)(g < 0 ? -(g + 1) : g);
    r->x[2 * k]     = PetscRealPart(ca[off]);
    r->x[2 * k + 1] = PetscRealPart(ca[off + 1]);
  }
  if ((0.5 * (r->x[0] + r->x[2]) - cx) * (r->x[3] - r->x[1]) - (0.5 * (r->x[1] + r->x[3]) - cy) * (r->x[2] - r->x[0]) < 0) {
    double t;
    t = r->gdof[0], r->gdof[0] = r->gdof[1], r->gdof[1] = t;
    for (int d = 0; d < 2; d++) t = r->x[d], r->x[d] = r->x[2 + d], r->x[2 + d] = t;
  }
  r->body = (double)m->cellbody[c - m->cStart];
  PetscFunctionReturn(0);
}

/* this rank's owned edges of the group */
static PetscErrorCode LocalEdges(const M2dMesh *m, IS is, PetscInt *nloc, EdgeRecord **rec)
{
  const PetscInt    *pts;
  PetscInt           n;
  PetscSection       gsec, cs;
  Vec                cl;
  const PetscScalar *ca;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(VecGetArrayRead(cl, &ca));
  PetscCall(ISGetLocalSize(is, &n));
  PetscCall(ISGetIndices(is, &pts));
  PetscCall(PetscMalloc1(n + 1, rec));
  *nloc = 0;
  for (PetscInt i = 0; i < n; i++) {
    PetscInt e = pts[i];
    if (e < m->eStart || e >= m->eEnd || m->edgeghost[e - m->eStart]) continue;
    PetscCall(EdgeRecordMake(m, gsec, cs, ca, e, &(*rec)[(*nloc)++]));
  }
  PetscCall(ISRestoreIndices(is, &pts));
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscFunctionReturn(0);
}

/* every rank gets every edge */
static PetscErrorCode AllEdges(MPI_Comm comm, PetscInt nloc, const EdgeRecord *rec, PetscInt *nall, EdgeRecord **all)
{
  PetscMPIInt size, nrec, *counts, *displs;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCall(PetscMPIIntCast(M2D_EDGE_DOUBLES * nloc, &nrec));
  PetscCallMPI(MPI_Allgather(&nrec, 1, MPI_INT, counts, 1, MPI_INT, comm));
  displs[0] = 0;
  for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + counts[r];
  *nall = displs[size] / M2D_EDGE_DOUBLES;
  PetscCall(PetscMalloc1(*nall + 1, all));
  PetscCallMPI(MPI_Allgatherv(rec, nrec, MPI_DOUBLE, *all, counts, displs, MPI_DOUBLE, comm));
  PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(0);
}

/* unique nodes by global dof, in a rank-independent order, and the surface */
static PetscErrorCode SurfaceFromEdges(PetscInt nedge, const EdgeRecord *all, M2dSurface *s)
{
  PetscInt  *edge, *gdof, nnode = 0;
  PetscReal *x;
  DofPos    *dp;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(2 * nedge, &dp));
  for (PetscInt k = 0; k < 2 * nedge; k++) {
    dp[k].gdof = (PetscInt)all[k / 2].gdof[k % 2];
    dp[k].pos  = k;
  }
  qsort(dp, (size_t)(2 * nedge), sizeof(DofPos), CmpDofPos);
  PetscCall(PetscMalloc3(2 * nedge, &edge, 2 * nedge, &gdof, 4 * nedge, &x));
  for (PetscInt k = 0; k < 2 * nedge; k++) {
    PetscInt e = dp[k].pos / 2, end = dp[k].pos % 2;
    if (k == 0 || dp[k].gdof != dp[k - 1].gdof) {
      gdof[nnode]      = dp[k].gdof;
      x[2 * nnode]     = all[e].x[2 * end];
      x[2 * nnode + 1] = all[e].x[2 * end + 1];
      nnode++;
    }
    edge[dp[k].pos] = nnode - 1;
  }
  PetscCall(SurfaceCreate(nnode, x, gdof, nedge, edge, s));
  PetscCall(PetscFree3(edge, gdof, x));
  PetscCall(PetscFree(dp));
  PetscFunctionReturn(0);
}

PetscErrorCode SurfaceGather(const M2dMesh *m, const char *group, const char *option, M2dSurface *s)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)m->dm);
  IS          is;
  PetscInt    nloc = 0, nedge = 0;
  EdgeRecord *rec = NULL, *all = NULL;

  PetscFunctionBeginUser;
  PetscCall(MeshGetGroupIS(m, group, option, &is));
  PetscCall(LocalEdges(m, is, &nloc, &rec));
  PetscCall(ISDestroy(&is));
  PetscCall(AllEdges(comm, nloc, rec, &nedge, &all));
  PetscCall(PetscFree(rec));
  PetscCheck(nedge > 0, comm, PETSC_ERR_PLIB, "option %s: physical group '%s' has no edges (SceneCheckMesh lets none through)", option, group);
  PetscCall(SurfaceFromEdges(nedge, all, s));
  s->body = (PetscInt)all[0].body;
  for (PetscInt e = 1; e < nedge; e++)
    if ((PetscInt)all[e].body != s->body) s->body = -1;
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}
