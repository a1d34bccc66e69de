/* frames.c - supports on inclined boundaries (see frames.h). */
#include "frames.h"
#include <math.h>
#include <string.h>

/* per local vertex, the same on every rank: whether x/y support bc holds the
 * vertex, one flag per component (summed over the ranks, tested > 0) */
static PetscErrorCode SupportAtVertices(const M2dMesh *m, const M2dDirichlet *bc, Vec acc)
{
  PetscSection    lsec;
  Vec             g;
  PetscScalar    *a;
  IS              is;
  const PetscInt *pts;
  PetscInt        np;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalSection(m->dm, &lsec));
  PetscCall(VecZeroEntries(acc));
  PetscCall(MeshGetGroupIS(m, bc->group, "-dirichlet", &is));
  PetscCall(ISGetLocalSize(is, &np));
  PetscCall(ISGetIndices(is, &pts));
  PetscCall(VecGetArray(acc, &a));
  for (PetscInt i = 0; i < np; i++) {
    const PetscInt *cone = &pts[i];
    PetscInt        nv   = 1, off;
    if (pts[i] >= m->eStart && pts[i] < m->eEnd) {
      PetscCall(DMPlexGetCone(m->dm, pts[i], &cone));
      nv = 2;
    } else if (pts[i] < m->vStart || pts[i] >= m->vEnd) continue;
    for (PetscInt j = 0; j < nv; j++) {
      PetscCall(PetscSectionGetOffset(lsec, cone[j], &off));
      for (int d = 0; d < 2; d++) a[off + d] = bc->comp[d] ? 1.0 : 0.0;
    }
  }
  PetscCall(VecRestoreArray(acc, &a));
  PetscCall(ISRestoreIndices(is, &pts));
  PetscCall(ISDestroy(&is));
  PetscCall(DMGetGlobalVector(m->dm, &g));
  PetscCall(VecZeroEntries(g));
  PetscCall(DMLocalToGlobal(m->dm, acc, ADD_VALUES, g));
  PetscCall(DMGlobalToLocal(m->dm, g, INSERT_VALUES, acc));
  PetscCall(DMRestoreGlobalVector(m->dm, &g));
  PetscFunctionReturn(0);
}

/* a vertex's identity on every rank: the global dof of its u_x */
static PetscInt VertexId(PetscSection gsec, PetscInt v)
{
  PetscInt off;
  PetscSectionGetOffset(gsec, v, &off);
  return off < 0 ? -(off + 1) : off;
}

typedef struct {
  double id, n[2]; /* vertex id, the outward unit normal of one of its edges (doubles: one MPI type) */
} VertexNormal;

static int CmpVertexNormal(const void *x, const void *y)
{
  double a = ((const VertexNormal *)x)->id, b = ((const VertexNormal *)y)->id;
  return (a > b) - (a < b);
}

/* every edge of the n/t support bc, from every rank, as (vertex, outward
 * normal) for both its ends, sorted by vertex */
static PetscErrorCode SupportNormals(const M2dMesh *m, const M2dDirichlet *bc, PetscInt *nall, VertexNormal **all)
{
  M2dMeshArrays   ar;
  PetscSection    gsec;
  IS              is;
  const PetscInt *pts;
  PetscInt        np, nloc = 0;
  VertexNormal   *loc;
  PetscMPIInt     size, cnt, *counts, *displs;
  MPI_Comm        comm = PetscObjectComm((PetscObject)m->dm);

  PetscFunctionBeginUser;
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(MeshGetGroupIS(m, bc->group, "-dirichlet", &is));
  PetscCall(ISGetLocalSize(is, &np));
  PetscCall(ISGetIndices(is, &pts));
  PetscCall(PetscMalloc1(2 * np + 1, &loc));
  for (PetscInt i = 0; i < np; i++) {
    const PetscInt *cone, *supp;
    PetscInt        e = pts[i], off[2];
    PetscReal       xy[8], cx = 0, cy = 0, n[2], len;
    if (e < m->eStart || e >= m->eEnd || m->edgeghost[e - m->eStart]) continue; /* each edge once, on its owner */
    PetscCall(DMPlexGetCone(m->dm, e, &cone));
    PetscCall(DMPlexGetSupport(m->dm, e, &supp));
    for (int j = 0; j < 2; j++) PetscCall(PetscSectionGetOffset(ar.cs, cone[j], &off[j]));
    n[0] = PetscRealPart(ar.ca[off[1] + 1] - ar.ca[off[0] + 1]);
    n[1] = -PetscRealPart(ar.ca[off[1]] - ar.ca[off[0]]);
    len  = PetscSqrtReal(n[0] * n[0] + n[1] * n[1]);
    MeshCellCoordinates(m, ar.ca, ar.cs, supp[0], xy);
    for (int j = 0; j < 4; j++) cx += 0.25 * xy[2 * j], cy += 0.25 * xy[2 * j + 1];
    if ((0.5 * PetscRealPart(ar.ca[off[0]] + ar.ca[off[1]]) - cx) * n[0] + (0.5 * PetscRealPart(ar.ca[off[0] + 1] + ar.ca[off[1] + 1]) - cy) * n[1] < 0) len = -len; /* outward */
    for (int j = 0; j < 2; j++) loc[nloc++] = (VertexNormal){(double)VertexId(gsec, cone[j]), {n[0] / len, n[1] / len}};
  }
  PetscCall(ISRestoreIndices(is, &pts));
  PetscCall(ISDestroy(&is));
  PetscCall(MeshArraysClose(&ar));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCall(PetscMPIIntCast(3 * nloc, &cnt));
  PetscCallMPI(MPI_Allgather(&cnt, 1, MPI_INT, counts, 1, MPI_INT, comm));
  displs[0] = 0;
  for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + counts[r];
  *nall = displs[size] / 3;
  PetscCall(PetscMalloc1(*nall + 1, all));
  PetscCallMPI(MPI_Allgatherv(loc, cnt, MPI_DOUBLE, *all, counts, displs, MPI_DOUBLE, comm));
  qsort(*all, (size_t)*nall, sizeof(VertexNormal), CmpVertexNormal);
  PetscCall(PetscFree2(counts, displs));
  PetscCall(PetscFree(loc));
  PetscFunctionReturn(0);
}

/* two values of one displacement (reference units) that differ: the vertex's
 * conditions contradict each other */
static PetscBool Differ(PetscReal a, PetscReal b)
{
  return (PetscBool)(PetscAbsReal(a - b) > 1e-12 * (1 + PetscAbsReal(a) + PetscAbsReal(b)));
}

/* add the constraint u.d = V to vertex v's list (directions kept independent);
 * one that contradicts those held (another value along a held direction, or
 * a third direction the two held ones fix otherwise) makes the vertex's
 * values NaN (frames.h; before, the first value won, silently) */
static void AddConstraint(PetscInt *n, PetscReal dir[][2], PetscReal val[], const PetscReal d[2], PetscReal V)
{
  for (PetscInt k = 0; k < *n; k++)
    if (PetscAbsReal(dir[k][0] * d[1] - dir[k][1] * d[0]) < 1e-10) { /* parallel to one already held */
      if (Differ(val[k], V * (dir[k][0] * d[0] + dir[k][1] * d[1]))) val[k] = NAN;
      return;
    }
  if (*n == 2) {
    PetscReal det = dir[0][0] * dir[1][1] - dir[0][1] * dir[1][0], u[2];
    u[0] = (val[0] * dir[1][1] - val[1] * dir[0][1]) / det;
    u[1] = (dir[0][0] * val[1] - dir[1][0] * val[0]) / det;
    if (Differ(u[0] * d[0] + u[1] * d[1], V)) val[0] = NAN;
    return;
  }
  dir[*n][0] = d[0];
  dir[*n][1] = d[1];
  val[(*n)++] = V;
}

/* vertex v's supports: one inclined direction -> a frame; one axis -> that
 * component; two independent directions -> both components, u solved from
 * the two conditions */
static void Decide(PetscInt n, PetscReal dir[][2], const PetscReal val[], PetscReal frame[2], PetscInt *mask, PetscReal value[2])
{
  frame[0] = frame[1] = 0;
  *mask               = 0;
  if (n == 1) {
    PetscInt ax = PetscAbsReal(dir[0][1]) < 1e-12 ? 0 : PetscAbsReal(dir[0][0]) < 1e-12 ? 1 : -1;
    if (ax >= 0) {
      *mask     = 1 << ax;
      value[ax] = val[0] / dir[0][ax];
    } else {
      frame[0] = dir[0][0], frame[1] = dir[0][1];
      *mask    = 1;
      value[0] = val[0];
    }
  } else if (n == 2) {
    PetscReal det = dir[0][0] * dir[1][1] - dir[0][1] * dir[1][0];
    *mask         = 3;
    value[0]      = (val[0] * dir[1][1] - val[1] * dir[0][1]) / det;
    value[1]      = (dir[0][0] * val[1] - dir[1][0] * val[0]) / det;
  }
}

/* Edges of one n/t support that meet at a vertex at more than this angle
 * make a corner: the normal of each side is a condition of its own (the vertex
 * is held in x and y, as by two supports); below it their normals are
 * averaged (a curved boundary: 12 or more edges per turn). */
#define M2D_CORNER_DEG 30.0

/* vertex v's conditions from n/t support bc: the normals at v (nrm[0..k-1])
 * grouped within M2D_CORNER_DEG of each group's first, each group's mean a condition */
static void AddNormalConstraints(const M2dDirichlet *bc, PetscInt k, const VertexNormal *nrm, PetscInt *ncon, PetscReal dir[][2], PetscReal val[])
{
  PetscReal sum[8][2], first[8][2], c = PetscCosReal(M2D_CORNER_DEG * PETSC_PI / 180);
  PetscInt  ng = 0;

  for (PetscInt i = 0; i < k; i++) {
    PetscInt g = 0;
    while (g < ng && nrm[i].n[0] * first[g][0] + nrm[i].n[1] * first[g][1] < c) g++;
    if (g == ng) {
      if (ng == 8) continue;
      first[ng][0] = nrm[i].n[0], first[ng][1] = nrm[i].n[1];
      sum[ng][0] = sum[ng][1] = 0;
      ng++;
    }
    sum[g][0] += nrm[i].n[0];
    sum[g][1] += nrm[i].n[1];
  }
  for (PetscInt g = 0; g < ng; g++) {
    PetscReal l = PetscSqrtReal(PetscSqr(sum[g][0]) + PetscSqr(sum[g][1])), d[2];
    if (!(l > 0)) continue;
    d[0] = sum[g][0] / l, d[1] = sum[g][1] / l;
    if (bc->frame == M2D_BC_TANGENT) { /* t = (-n_y, n_x) */
      PetscReal t = d[0];
      d[0]        = -d[1], d[1] = t;
    }
    AddConstraint(ncon, dir, val, d, bc->value[0]);
  }
}

PetscErrorCode M2dFramesCreate(const M2dMesh *m, const M2dScene *s, M2dFrames *fr)
{
  PetscSection       lsec, gsec;
  PetscInt           nv = m->vEnd - m->vStart, *ncon;
  PetscReal(*dir)[2][2], (*val)[2];
  Vec                acc;
  const PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(fr, sizeof(*fr)));
  PetscCall(PetscCalloc3(2 * nv + 1, &fr->normal, nv + 1, &fr->mask, 2 * nv + 1, &fr->value));
  PetscCall(PetscCalloc3(nv + 1, &ncon, nv + 1, &dir, nv + 1, &val));
  PetscCall(DMGetLocalSection(m->dm, &lsec));
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(DMGetLocalVector(m->dm, &acc));
  for (PetscInt k = 0; k < s->ndir; k++) {
    const M2dDirichlet *bc = &s->dir[k];
    if (bc->stage) continue; /* a later stage's change of a value: M2dFramesStage */
    if (bc->frame == M2D_BC_XY) {
      PetscCall(SupportAtVertices(m, bc, acc));
      PetscCall(VecGetArrayRead(acc, &a));
      for (PetscInt v = 0; v < nv; v++) {
        PetscInt off;
        PetscCall(PetscSectionGetOffset(lsec, m->vStart + v, &off));
        for (int c = 0; c < 2; c++)
          if (PetscRealPart(a[off + c]) > 0) {
            PetscReal d[2] = {(PetscReal)(c == 0), (PetscReal)(c == 1)};
            AddConstraint(&ncon[v], dir[v], val[v], d, bc->value[c]);
          }
      }
      PetscCall(VecRestoreArrayRead(acc, &a));
    } else {
      VertexNormal *all  = NULL;
      PetscInt      nall = 0;
      PetscCall(SupportNormals(m, bc, &nall, &all));
      for (PetscInt v = 0; v < nv && nall; v++) { /* its entries in all[], by bisection */
        double   id = (double)VertexId(gsec, m->vStart + v);
        PetscInt lo = 0, hi = nall, end;
        while (lo < hi) {
          PetscInt mid = (lo + hi) / 2;
          if (all[mid].id < id) lo = mid + 1;
          else hi = mid;
        }
        for (end = lo; end < nall && all[end].id == id; end++) { }
        AddNormalConstraints(bc, end - lo, &all[lo], &ncon[v], dir[v], val[v]);
      }
      PetscCall(PetscFree(all));
    }
  }
  PetscCall(DMRestoreLocalVector(m->dm, &acc));
  for (PetscInt v = 0; v < nv; v++) {
    Decide(ncon[v], dir[v], val[v], &fr->normal[2 * v], &fr->mask[v], &fr->value[2 * v]);
    if (fr->normal[2 * v] != 0 || fr->normal[2 * v + 1] != 0) fr->any = PETSC_TRUE;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &fr->any, 1, MPIU_BOOL, MPI_LOR, PetscObjectComm((PetscObject)m->dm)));
  PetscCall(PetscFree3(ncon, dir, val));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dFramesStage(const M2dMesh *m, const M2dScene *s, PetscInt stage, const M2dFrames *fr, M2dFrames *frs)
{
  M2dScene *v;
  PetscInt  nv = m->vEnd - m->vStart, same = 1;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&v)); /* the supports, valued by the stage's changes (scene.c checked that each has its support) */
  *v = *s;
  for (PetscInt i = 0; i < v->ndir; i++) {
    M2dDirichlet *e = &v->dir[i];
    if (e->stage) continue;
    e->value[0] = e->value[1] = 0;
    for (PetscInt j = 0; j < s->ndir; j++) {
      const M2dDirichlet *d = &s->dir[j];
      if (d->stage != stage || d->frame != e->frame || strcmp(d->group, e->group)) continue;
      for (int c = 0; c < 2; c++)
        if (e->frame != M2D_BC_XY || (e->comp[c] && d->comp[c])) e->value[c] += d->value[c];
    }
  }
  PetscCall(M2dFramesCreate(m, v, frs));
  PetscCall(PetscFree(v));
  for (PetscInt k = 0; k < nv; k++) same = same && frs->mask[k] == fr->mask[k];
  PetscCheck(same, PETSC_COMM_SELF, PETSC_ERR_PLIB, "load stage %d: its supports differ from the scene's", (int)stage + 1);
  PetscFunctionReturn(0);
}

PetscErrorCode M2dFramesDestroy(M2dFrames *fr)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree3(fr->normal, fr->mask, fr->value));
  fr->any = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscBool M2dFramesAt(const M2dFrames *fr, const M2dMesh *m, PetscInt v, PetscReal n[2])
{
  if (!fr->any || !fr->normal) return PETSC_FALSE;
  n[0] = fr->normal[2 * (v - m->vStart)];
  n[1] = fr->normal[2 * (v - m->vStart) + 1];
  return (PetscBool)(n[0] != 0 || n[1] != 0);
}

/* x (2 entries) <- T^T x (forward) or T x (back), T = [n t], t = (-n_y, n_x) */
static void Rotate(const PetscReal n[2], PetscBool back, PetscScalar x[2])
{
  PetscScalar a = x[0], b = x[1];
  if (back) { /* u = n u~_0 + t u~_1 */
    x[0] = n[0] * a - n[1] * b;
    x[1] = n[1] * a + n[0] * b;
  } else { /* u~_0 = n.u, u~_1 = t.u */
    x[0] = n[0] * a + n[1] * b;
    x[1] = -n[1] * a + n[0] * b;
  }
}

void M2dFramesRotateElement(const M2dFrames *fr, const M2dMesh *m, const PetscInt verts[4], PetscReal Ke[64])
{
  PetscReal n[2];
  if (!fr->any) return;
  for (int a = 0; a < 4; a++) {
    if (!M2dFramesAt(fr, m, verts[a], n)) continue;
    for (int r = 0; r < 8; r++) { /* columns 2a, 2a+1: Ke Te */
      PetscScalar x[2] = {Ke[8 * r + 2 * a], Ke[8 * r + 2 * a + 1]};
      Rotate(n, PETSC_FALSE, x);
      Ke[8 * r + 2 * a] = PetscRealPart(x[0]), Ke[8 * r + 2 * a + 1] = PetscRealPart(x[1]);
    }
    for (int c = 0; c < 8; c++) { /* rows 2a, 2a+1: Te^T (Ke Te) */
      PetscScalar x[2] = {Ke[8 * (2 * a) + c], Ke[8 * (2 * a + 1) + c]};
      Rotate(n, PETSC_FALSE, x);
      Ke[8 * (2 * a) + c] = PetscRealPart(x[0]), Ke[8 * (2 * a + 1) + c] = PetscRealPart(x[1]);
    }
  }
}

PetscErrorCode M2dFramesRotateLocal(const M2dFrames *fr, const M2dMesh *m, Vec xl, PetscBool back)
{
  PetscSection lsec;
  PetscScalar *xa;
  PetscReal    n[2];

  PetscFunctionBeginUser;
  if (!fr->any) PetscFunctionReturn(0);
  PetscCall(DMGetLocalSection(m->dm, &lsec));
  PetscCall(VecGetArray(xl, &xa));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt off;
    if (!M2dFramesAt(fr, m, v, n)) continue;
    PetscCall(PetscSectionGetOffset(lsec, v, &off));
    Rotate(n, back, &xa[off]);
  }
  PetscCall(VecRestoreArray(xl, &xa));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dFramesRotateGlobal(const M2dFrames *fr, const M2dMesh *m, Vec x, PetscBool back)
{
  PetscSection gsec;
  PetscScalar *xa;
  PetscReal    n[2];
  PetscInt     lo;

  PetscFunctionBeginUser;
  if (!fr->any) PetscFunctionReturn(0);
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(VecGetOwnershipRange(x, &lo, NULL));
  PetscCall(VecGetArray(x, &xa));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(gsec, v, &off));
    if (off < 0 || !M2dFramesAt(fr, m, v, n)) continue; /* owned vertices only */
    Rotate(n, back, &xa[off - lo]);
  }
  PetscCall(VecRestoreArray(x, &xa));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dFramesRotateRows(const M2dFrames *fr, const M2dMesh *m, const M2dContactRows *R, M2dContactRows *Rt)
{
  PetscInt           nnz = R->ptr[R->n], *idx;
  Vec                ng, all;
  IS                 is;
  VecScatter         sc;
  const PetscScalar *na;
  PetscSection       gsec;

  PetscFunctionBeginUser;
  Rt->n = R->n;
  PetscCall(PetscMalloc4(R->n + 1, &Rt->node, R->n + 1, &Rt->ptr, R->n + 1, &Rt->g0, R->n + 1, &Rt->w));
  PetscCall(PetscMalloc2(nnz + 1, &Rt->col, nnz + 1, &Rt->val));
  PetscCall(PetscArraycpy(Rt->node, R->node, R->n));
  PetscCall(PetscArraycpy(Rt->ptr, R->ptr, R->n + 1));
  PetscCall(PetscArraycpy(Rt->g0, R->g0, R->n));
  PetscCall(PetscArraycpy(Rt->w, R->w, R->n));
  PetscCall(PetscArraycpy(Rt->col, R->col, nnz));
  PetscCall(PetscArraycpy(Rt->val, R->val, nnz));
  if (!fr->any) PetscFunctionReturn(0);
  /* every rank needs the normals at the rows' columns (the rows are on every rank) */
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(DMGetGlobalVector(m->dm, &ng));
  {
    PetscScalar *ga;
    PetscInt     lo;
    PetscCall(VecGetOwnershipRange(ng, &lo, NULL));
    PetscCall(VecGetArray(ng, &ga));
    for (PetscInt v = m->vStart; v < m->vEnd; v++) {
      PetscInt off;
      PetscCall(PetscSectionGetOffset(gsec, v, &off));
      if (off < 0) continue;
      ga[off - lo]     = fr->normal[2 * (v - m->vStart)];
      ga[off - lo + 1] = fr->normal[2 * (v - m->vStart) + 1];
    }
    PetscCall(VecRestoreArray(ng, &ga));
  }
  PetscCall(PetscMalloc1(nnz + 1, &idx));
  for (PetscInt k = 0; k < nnz; k++) idx[k] = R->col[k] / 2; /* the column's node (2 dofs per vertex) */
  PetscCall(ISCreateBlock(PETSC_COMM_SELF, 2, nnz, idx, PETSC_OWN_POINTER, &is));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2 * nnz, &all));
  PetscCall(VecScatterCreate(ng, is, all, NULL, &sc));
  PetscCall(VecScatterBegin(sc, ng, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, ng, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(all, &na));
  for (PetscInt j = 0; j < R->n; j++) /* rows: C~ = C T, a node's two columns mixed */
    for (PetscInt k = R->ptr[j]; k < R->ptr[j + 1]; k++) {
      PetscReal n[2] = {PetscRealPart(na[2 * k]), PetscRealPart(na[2 * k + 1])}, cx = 0, cy = 0;
      if (n[0] == 0 && n[1] == 0) continue;
      for (PetscInt q = R->ptr[j]; q < R->ptr[j + 1]; q++) { /* the node's two coefficients in this row */
        if (R->col[q] == R->col[k] - R->col[k] % 2) cx = R->val[q];
        if (R->col[q] == R->col[k] - R->col[k] % 2 + 1) cy = R->val[q];
      }
      Rt->val[k] = R->col[k] % 2 == 0 ? n[0] * cx + n[1] * cy : -n[1] * cx + n[0] * cy;
    }
  PetscCall(VecRestoreArrayRead(all, &na));
  PetscCall(VecDestroy(&all));
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(ISDestroy(&is));
  PetscCall(DMRestoreGlobalVector(m->dm, &ng));
  PetscFunctionReturn(0);
}
