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

/* ---- the bounding-volume tree (see surface.h) ---- */
#define M2D_TREE_LEAF  4
#define M2D_TREE_STACK 128 /* > 2 log2 of any edge count: the median split halves each node */

static void Swap2(PetscInt *perm, PetscReal *key, PetscInt i, PetscInt j)
{
  PetscInt  p = perm[i];
  PetscReal k = key[i];
  perm[i] = perm[j], perm[j] = p;
  key[i] = key[j], key[j] = k;
}

/* reorder perm[0..n) and key[0..n) so that key[k] is the k-th smallest, the
 * smaller before it and the larger after (a 3-way partition: equal keys cost
 * nothing); deterministic */
static void Select(PetscInt *perm, PetscReal *key, PetscInt n, PetscInt k)
{
  PetscInt lo = 0, hi = n - 1;
  while (lo < hi) {
    PetscReal a = key[lo], b = key[(lo + hi) / 2], c = key[hi], piv = PetscMax(PetscMin(a, b), PetscMin(PetscMax(a, b), c));
    PetscInt  lt = lo, i = lo, gt = hi;
    while (i <= gt) {
      if (key[i] < piv) Swap2(perm, key, lt++, i++);
      else if (key[i] > piv) Swap2(perm, key, i, gt--);
      else i++;
    }
    if (k < lt) hi = lt - 1;
    else if (k > gt) lo = gt + 1;
    else return;
  }
}

/* node id's frame and bounds over its edges, then its children */
static void TreeBuild(M2dSurfaceTree *t, PetscInt id, PetscReal *key)
{
  const M2dSurface *s = t->s;
  M2dTreeNode      *nd = &t->node[id];
  PetscReal         c2 = 0, s2 = 0, al, v[2], clo[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL}, chi[2] = {PETSC_MIN_REAL, PETSC_MIN_REAL};
  int               axis;
  for (PetscInt k = nd->first; k < nd->first + nd->count; k++) { /* the mean direction, t and -t alike: the doubled angle */
    const PetscReal *n = &s->normal[2 * t->perm[k]];
    c2 += s->len[t->perm[k]] * (n[1] * n[1] - n[0] * n[0]);
    s2 += s->len[t->perm[k]] * -2 * n[0] * n[1];
  }
  al       = 0.5 * PetscAtan2Real(s2, c2);
  nd->u[0] = PetscCosReal(al), nd->u[1] = PetscSinReal(al);
  v[0] = -nd->u[1], v[1] = nd->u[0];
  nd->lo[0] = nd->lo[1] = PETSC_MAX_REAL;
  nd->hi[0] = nd->hi[1] = PETSC_MIN_REAL;
  nd->nu = nd->nv = 0;
  for (PetscInt k = nd->first; k < nd->first + nd->count; k++) {
    PetscInt         e = t->perm[k];
    const PetscReal *n = &s->normal[2 * e];
    for (int end = 0; end < 2; end++) {
      const PetscReal *x = &s->x[2 * s->edge[2 * e + end]];
      PetscReal        pu = x[0] * nd->u[0] + x[1] * nd->u[1], pv = x[0] * v[0] + x[1] * v[1];
      nd->lo[0] = PetscMin(nd->lo[0], pu), nd->hi[0] = PetscMax(nd->hi[0], pu);
      nd->lo[1] = PetscMin(nd->lo[1], pv), nd->hi[1] = PetscMax(nd->hi[1], pv);
    }
    nd->nu = PetscMax(nd->nu, PetscAbsReal(n[0] * nd->u[0] + n[1] * nd->u[1]));
    nd->nv = PetscMax(nd->nv, PetscAbsReal(n[0] * v[0] + n[1] * v[1]));
  }
  nd->child = -1;
  if (nd->count <= M2D_TREE_LEAF) return;
  for (PetscInt k = nd->first; k < nd->first + nd->count; k++) { /* split at the median centroid along the longer side */
    const PetscReal *a = &s->x[2 * s->edge[2 * t->perm[k]]], *b = &s->x[2 * s->edge[2 * t->perm[k] + 1]];
    PetscReal        cu = 0.5 * ((a[0] + b[0]) * nd->u[0] + (a[1] + b[1]) * nd->u[1]), cv = 0.5 * ((a[0] + b[0]) * v[0] + (a[1] + b[1]) * v[1]);
    clo[0] = PetscMin(clo[0], cu), chi[0] = PetscMax(chi[0], cu), clo[1] = PetscMin(clo[1], cv), chi[1] = PetscMax(chi[1], cv);
    key[k] = cu, key[k + s->nedge] = cv; /* both axes; the second half of key is scratch */
  }
  axis = chi[1] - clo[1] > chi[0] - clo[0];
  if (axis) for (PetscInt k = nd->first; k < nd->first + nd->count; k++) key[k] = key[k + s->nedge];
  Select(&t->perm[nd->first], &key[nd->first], nd->count, nd->count / 2);
  nd->child = t->nnode;
  t->nnode += 2;
  t->node[nd->child]     = (M2dTreeNode){.first = nd->first, .count = nd->count / 2};
  t->node[nd->child + 1] = (M2dTreeNode){.first = nd->first + nd->count / 2, .count = nd->count - nd->count / 2};
  TreeBuild(t, nd->child, key);
  TreeBuild(t, t->node[id].child + 1, key);
}

PetscErrorCode SurfaceTreeCreate(const M2dSurface *s, M2dSurfaceTree *t)
{
  PetscReal *key;

  PetscFunctionBeginUser;
  t->s     = s;
  t->nnode = 1;
  t->eps   = 1e-9 * (s->hi[0] - s->lo[0] + s->hi[1] - s->lo[1] + PetscMax(PetscMax(PetscAbsReal(s->lo[0]), PetscAbsReal(s->hi[0])), PetscMax(PetscAbsReal(s->lo[1]), PetscAbsReal(s->hi[1]))));
  PetscCall(PetscMalloc2(2 * s->nedge + 1, &t->node, s->nedge + 1, &t->perm));
  PetscCall(PetscMalloc1(2 * s->nedge + 1, &key));
  for (PetscInt e = 0; e < s->nedge; e++) t->perm[e] = e;
  t->node[0] = (M2dTreeNode){.first = 0, .count = s->nedge};
  if (s->nedge > 0) TreeBuild(t, 0, key);
  PetscCall(PetscFree(key));
  PetscFunctionReturn(0);
}

PetscErrorCode SurfaceTreeDestroy(M2dSurfaceTree *t)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(t->node, t->perm));
  t->nnode = 0;
  PetscFunctionReturn(0);
}

/* do the projections of a and b on d (interval [pa, pb]) miss [lo, hi]? */
static PetscBool Apart(const PetscReal d[2], const PetscReal a[2], const PetscReal b[2], PetscReal lo, PetscReal hi)
{
  PetscReal pa = a[0] * d[0] + a[1] * d[1], pb = b[0] * d[0] + b[1] * d[1];
  return (PetscBool)(PetscMax(pa, pb) < lo || PetscMin(pa, pb) > hi);
}

static int CmpInt(const void *a, const void *b)
{
  PetscInt x = *(const PetscInt *)a, y = *(const PetscInt *)b;
  return (x > y) - (x < y);
}

PetscErrorCode SurfaceTreeNear(const M2dSurfaceTree *t, const PetscReal a[2], const PetscReal b[2], PetscReal reach, PetscInt *n, PetscInt *cap, PetscInt **list)
{
  const M2dSurface *s = t->s;
  PetscInt          stack[M2D_TREE_STACK], top = 0;

  PetscFunctionBeginUser;
  *n = 0;
  if (s->nedge > 0) stack[top++] = 0;
  while (top > 0) {
    const M2dTreeNode *nd = &t->node[stack[--top]];
    PetscReal          v[2] = {-nd->u[1], nd->u[0]}, wu = reach * nd->nu + t->eps, wv = reach * nd->nv + t->eps;
    if (Apart(nd->u, a, b, nd->lo[0] - wu, nd->hi[0] + wu) || Apart(v, a, b, nd->lo[1] - wv, nd->hi[1] + wv)) continue;
    if (nd->child >= 0) {
      PetscCheck(top + 2 <= M2D_TREE_STACK, PETSC_COMM_SELF, PETSC_ERR_PLIB, "surface tree deeper than %d", M2D_TREE_STACK);
      stack[top++] = nd->child + 1;
      stack[top++] = nd->child;
      continue;
    }
    for (PetscInt k = nd->first; k < nd->first + nd->count; k++) { /* the edge's own frame: along it, and along its normal within reach */
      PetscInt         e = t->perm[k];
      const PetscReal *p = &s->x[2 * s->edge[2 * e]], *q = &s->x[2 * s->edge[2 * e + 1]], *nn = &s->normal[2 * e];
      PetscReal        tt[2] = {-nn[1], nn[0]}, tp = p[0] * tt[0] + p[1] * tt[1], tq = q[0] * tt[0] + q[1] * tt[1], h = p[0] * nn[0] + p[1] * nn[1];
      if (Apart(tt, a, b, PetscMin(tp, tq) - t->eps, PetscMax(tp, tq) + t->eps) || Apart(nn, a, b, h - reach - t->eps, h + reach + t->eps)) continue;
      if (*n == *cap) {
        *cap = *cap ? 2 * *cap : 16;
        PetscCall(PetscRealloc(*cap * sizeof(**list), list));
      }
      (*list)[(*n)++] = e;
    }
  }
  qsort(*list, (size_t)*n, sizeof(PetscInt), CmpInt);
  PetscFunctionReturn(0);
}

/* the distance from p to node nd's edges' box */
static PetscReal BoxDistance(const M2dTreeNode *nd, const PetscReal p[2])
{
  PetscReal pu = p[0] * nd->u[0] + p[1] * nd->u[1], pv = -p[0] * nd->u[1] + p[1] * nd->u[0];
  PetscReal du = PetscMax(0, PetscMax(nd->lo[0] - pu, pu - nd->hi[0])), dv = PetscMax(0, PetscMax(nd->lo[1] - pv, pv - nd->hi[1]));
  return PetscSqrtReal(du * du + dv * dv);
}

PetscInt SurfaceTreeNearest(const M2dSurfaceTree *t, const PetscReal p[2], PetscReal (*key)(void *, PetscInt), void *ctx, PetscReal bound, PetscReal *best)
{
  PetscInt stack[M2D_TREE_STACK], top = 0, bf = -1;

  *best = bound;
  if (t->s->nedge > 0) stack[top++] = 0;
  while (top > 0) {
    const M2dTreeNode *nd = &t->node[stack[--top]];
    if (BoxDistance(nd, p) - t->eps > *best) continue;
    if (nd->child >= 0) { /* the nearer child first: it tightens the bound */
      PetscBool far0 = (PetscBool)(BoxDistance(&t->node[nd->child], p) > BoxDistance(&t->node[nd->child + 1], p));
      if (top + 2 > M2D_TREE_STACK) return -1; /* cannot happen: the median split halves each node */
      stack[top++] = nd->child + (far0 ? 0 : 1);
      stack[top++] = nd->child + (far0 ? 1 : 0);
      continue;
    }
    for (PetscInt k = nd->first; k < nd->first + nd->count; k++) {
      PetscInt  e = t->perm[k];
      PetscReal d = key(ctx, e);
      if (d >= 0 && d <= bound && (bf < 0 || d < *best || (d == *best && e < bf))) *best = d, bf = e;
    }
  }
  if (bf < 0) *best = PETSC_MAX_REAL;
  return bf;
}

typedef struct {
  const M2dSurface *s;
  const PetscReal  *p, *nn;
  PetscReal         dmin, d, t; /* d and t: of the last edge keyed */
} FacingKey;

static PetscReal FacingDistance(void *ctx, PetscInt e)
{
  FacingKey       *k = (FacingKey *)ctx;
  const PetscReal *a = &k->s->x[2 * k->s->edge[2 * e]], *b = &k->s->x[2 * k->s->edge[2 * e + 1]], *n = &k->s->normal[2 * e], *x = k->p;
  PetscReal        l2 = PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]);
  if (!(l2 > 0) || k->nn[0] * n[0] + k->nn[1] * n[1] >= 0) return -1; /* the edge must face the point's surface */
  k->t = ((x[0] - a[0]) * (b[0] - a[0]) + (x[1] - a[1]) * (b[1] - a[1])) / l2;
  if (k->t < 0 || k->t > 1) return -1;
  k->d = (x[0] - a[0]) * n[0] + (x[1] - a[1]) * n[1];
  return k->d < k->dmin ? -1 : PetscAbsReal(k->d);
}

PetscInt SurfaceTreeFacing(const M2dSurfaceTree *t, const PetscReal p[2], const PetscReal nn[2], PetscReal dmin, PetscReal bound, PetscReal *d, PetscReal *foot)
{
  FacingKey k = {t->s, p, nn, dmin, 0, 0};
  PetscReal best;
  PetscInt  e = SurfaceTreeNearest(t, p, FacingDistance, &k, bound, &best);
  if (e >= 0) {
    FacingDistance(&k, e);
    *d    = k.d;
    *foot = k.t;
  }
  return e;
}
