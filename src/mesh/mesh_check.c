/* mesh_check.c - rank 0: cells that overlap, found on the skeleton in linear
 * time (plus a sort of the boundary edges). Every quad is already convex and
 * counter-clockwise (mesh_read.c), so the cells tile each body exactly when
 *  1. no edge has more than two cells;
 *  2. the two cells of an interior edge run through it in opposite directions
 *     (else both lie on the same side of it: a node pulled across a neighbour
 *     gives a clockwise quad, which was reoriented and now overlaps);
 *  3. the boundary of each body does not cross itself (a fold that keeps every
 *     cell convex, e.g. a strip wound over itself);
 *  4. each body is one piece (its cells connected through shared edges): a
 *     second piece may lie inside the first without any crossing (two
 *     surfaces of one physical surface, one drawn inside the other), and a
 *     piece apart from the rest is held by nothing the per-body support
 *     check sees (supports.h) - both were solved with exit 0.
 * (Sum of cell areas = area enclosed by the boundary holds by algebra once 2
 * holds, the shoelace terms of interior edges cancelling: it cannot catch 3.) */
#include "mesh_impl.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const char *BodyName(const M2dScene *s, PetscInt b)
{
  return b >= 0 && b < s->nbody ? s->body[b].name : "?";
}

/* orientation of cell c's traversal of its edge e (0 from the lower vertex, -1 against) */
static PetscInt Traversal(const MeshSkel *sk, PetscInt c, PetscInt e)
{
  for (int j = 0; j < 4; j++)
    if (sk->side[4 * c + j] == e) return sk->ornt[4 * c + j];
  return 1;
}

/* checks 1 and 2 */
static int CheckEdges(const M2dScene *s, const MeshSources *src, const MeshLists *L, const MeshSkel *sk, char *err, size_t len)
{
  if (sk->third[0] >= 0) {
    PetscInt e = sk->third[0], c = sk->third[1];
    snprintf(err, len, "%s, body '%s': quadrilaterals %ld, %ld and %ld share one edge (overlapping cells)", src->label[L->cellsrc[c]], BodyName(s, L->cellbody[c]), L->celltag[sk->ecell[2 * e]], L->celltag[sk->ecell[2 * e + 1]], L->celltag[c]);
    return 1;
  }
  for (PetscInt e = 0; e < sk->ne; e++) {
    PetscInt c0 = sk->ecell[2 * e], c1 = sk->ecell[2 * e + 1];
    if (c1 < 0 || Traversal(sk, c0, e) != Traversal(sk, c1, e)) continue;
    snprintf(err, len, "%s, body '%s': quadrilaterals %ld and %ld overlap (both lie on the same side of their common edge: a node moved across a neighbour?)", src->label[L->cellsrc[c1]], BodyName(s, L->cellbody[c1]), L->celltag[c0], L->celltag[c1]);
    return 1;
  }
  return 0;
}

typedef struct {
  PetscInt  body, e;
  PetscReal xmin, xmax, ymin, ymax;
} BEdge;

static int CmpBEdge(const void *x, const void *y)
{
  const BEdge *a = (const BEdge *)x, *b = (const BEdge *)y;
  if (a->body != b->body) return a->body < b->body ? -1 : 1;
  return (a->xmin > b->xmin) - (a->xmin < b->xmin);
}

/* do edges e and f (no common vertex) cross at a point inside both? Orientations
 * within a relative 1e-10 of zero count as touching, which is allowed (a slit) */
static int Cross(const MeshSkel *sk, const PetscReal *xy, PetscInt e, PetscInt f)
{
  const PetscReal *a = &xy[2 * sk->ev[2 * e]], *b = &xy[2 * sk->ev[2 * e + 1]], *c = &xy[2 * sk->ev[2 * f]], *d = &xy[2 * sk->ev[2 * f + 1]];
  PetscReal        l1 = hypot(b[0] - a[0], b[1] - a[1]), l2 = hypot(d[0] - c[0], d[1] - c[1]), tol = 1e-10 * l1 * l2;
  PetscReal        o1 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  PetscReal        o2 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
  PetscReal        o3 = (d[0] - c[0]) * (a[1] - c[1]) - (d[1] - c[1]) * (a[0] - c[0]);
  PetscReal        o4 = (d[0] - c[0]) * (b[1] - c[1]) - (d[1] - c[1]) * (b[0] - c[0]);
  return ((o1 > tol && o2 < -tol) || (o1 < -tol && o2 > tol)) && ((o3 > tol && o4 < -tol) || (o3 < -tol && o4 > tol));
}

/* check 3: sweep the boundary edges of each body in order of their smallest x;
 * the active list holds those whose x-range reaches the current edge */
static int CheckBoundary(const M2dScene *s, const MeshSources *src, const MeshLists *L, const MeshSkel *sk, char *err, size_t len)
{
  BEdge    *be;
  PetscInt *act, nb = 0, na = 0, bad[2] = {-1, -1};

  for (PetscInt e = 0; e < sk->ne; e++) nb += sk->ecell[2 * e + 1] < 0;
  be  = (BEdge *)malloc((size_t)(nb + 1) * sizeof(BEdge));
  act = (PetscInt *)malloc((size_t)(nb + 1) * sizeof(PetscInt));
  if (!be || !act) {
    free(be), free(act);
    snprintf(err, len, "out of memory checking the mesh %s", src->all);
    return 1;
  }
  nb = 0;
  for (PetscInt e = 0; e < sk->ne; e++) {
    const PetscReal *p = &L->coords[2 * sk->ev[2 * e]], *q = &L->coords[2 * sk->ev[2 * e + 1]];
    if (sk->ecell[2 * e + 1] >= 0) continue;
    be[nb++] = (BEdge){L->cellbody[sk->ecell[2 * e]], e, PetscMin(p[0], q[0]), PetscMax(p[0], q[0]), PetscMin(p[1], q[1]), PetscMax(p[1], q[1])};
  }
  qsort(be, (size_t)nb, sizeof(BEdge), CmpBEdge);
  for (PetscInt i = 0; i < nb && bad[0] < 0; i++) {
    PetscInt k = 0;
    for (PetscInt j = 0; j < na; j++) /* drop edges left behind (or of the previous body) */
      if (be[act[j]].body == be[i].body && be[act[j]].xmax >= be[i].xmin) act[k++] = act[j];
    na = k;
    for (PetscInt j = 0; j < na && bad[0] < 0; j++) {
      const BEdge *o = &be[act[j]];
      PetscInt     e = be[i].e, f = o->e;
      if (o->ymax < be[i].ymin || o->ymin > be[i].ymax) continue;
      if (sk->ev[2 * e] == sk->ev[2 * f] || sk->ev[2 * e] == sk->ev[2 * f + 1] || sk->ev[2 * e + 1] == sk->ev[2 * f] || sk->ev[2 * e + 1] == sk->ev[2 * f + 1]) continue;
      if (Cross(sk, L->coords, e, f)) bad[0] = sk->ecell[2 * f], bad[1] = sk->ecell[2 * e];
    }
    act[na++] = i;
  }
  free(be);
  free(act);
  if (bad[0] < 0) return 0;
  snprintf(err, len, "%s, body '%s': the boundary crosses itself at quadrilaterals %ld and %ld (overlapping cells)", src->label[L->cellsrc[bad[1]]], BodyName(s, L->cellbody[bad[1]]), L->celltag[bad[0]], L->celltag[bad[1]]);
  return 1;
}

static PetscInt Root(PetscInt *up, PetscInt c)
{
  while (up[c] != c) c = up[c] = up[up[c]];
  return c;
}

/* check 4: union-find of the cells over the interior edges within a body */
static int CheckPieces(const M2dScene *s, const MeshSources *src, const MeshLists *L, const MeshSkel *sk, char *err, size_t len)
{
  PetscInt *up = (PetscInt *)malloc((size_t)(sk->nc + 1) * sizeof(PetscInt)), first[M2D_MAX_BODIES], second = -1;

  if (!up) {
    snprintf(err, len, "out of memory checking the mesh %s", src->all);
    return 1;
  }
  for (PetscInt c = 0; c < sk->nc; c++) up[c] = c;
  for (PetscInt e = 0; e < sk->ne; e++) {
    PetscInt a = sk->ecell[2 * e], b = sk->ecell[2 * e + 1];
    if (b >= 0 && L->cellbody[a] == L->cellbody[b]) up[Root(up, a)] = Root(up, b);
  }
  for (PetscInt b = 0; b < M2D_MAX_BODIES; b++) first[b] = -1;
  for (PetscInt c = 0; c < sk->nc && second < 0; c++) {
    PetscInt b = L->cellbody[c];
    if (first[b] < 0) first[b] = c;
    else if (Root(up, c) != Root(up, first[b])) second = c;
  }
  free(up);
  if (second < 0) return 0;
  {
    const PetscInt  *v = &L->cells[4 * second];
    const PetscReal *x = L->coords;
    snprintf(err, len, "%s, body '%s': its cells form more than one piece (quadrilaterals %ld and %ld share no chain of edges; the second near (%g, %g)): a piece may overlap another or be held by nothing; give each piece its own physical surface", src->label[L->cellsrc[second]], BodyName(s, L->cellbody[second]), L->celltag[first[L->cellbody[second]]], L->celltag[second],
             0.25 * (x[2 * v[0]] + x[2 * v[1]] + x[2 * v[2]] + x[2 * v[3]]), 0.25 * (x[2 * v[0] + 1] + x[2 * v[1] + 1] + x[2 * v[2] + 1] + x[2 * v[3] + 1]));
  }
  return 1;
}

int MeshCheckSkeleton(const M2dScene *s, const MeshSources *src, const MeshLists *L, const MeshSkel *sk, char *err, size_t len)
{
  return CheckEdges(s, src, L, sk, err, len) || CheckBoundary(s, src, L, sk, err, len) || CheckPieces(s, src, L, sk, err, len);
}
