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
 *  5. the cells' areas sum to the area the body's boundary encloses. With 1
 *     and 2 the number of cells over a point is the winding number of the
 *     boundary edges (each oriented as its cell runs through it) around it,
 *     so the sum of the areas is the integral of that number, and the two
 *     areas differ by the ground two or more cells cover: a convex quad given
 *     another node of its body lies over its neighbours while 1-4 hold (its
 *     new edges and the old ones are boundary edges that do not cross). The
 *     enclosed area is summed over vertical slabs between the boundary's
 *     vertices, where the boundary's edges are ordered bottom to top:
 *     exact for the mesh's own straight edges, whatever the curve they
 *     approximate (a circle's CAD area would differ by the chords).
 * (The shoelace sum over the boundary edges equals the cells' areas by
 * algebra once 2 holds: it cannot tell a boundary wound twice.) */
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

/* check 5, one body: its boundary edges, oriented by their cells, left to right */
typedef struct {
  PetscReal x0, y0, x1, y1; /* x0 < x1 */
  int       dir;            /* +1: the cell runs left to right (it lies above), -1 right to left (below) */
} SEdge;

static int CmpSEdge(const void *x, const void *y)
{
  const SEdge *a = (const SEdge *)x, *b = (const SEdge *)y;
  return (a->x0 > b->x0) - (a->x0 < b->x0);
}

static int CmpReal(const void *x, const void *y)
{
  PetscReal a = *(const PetscReal *)x, b = *(const PetscReal *)y;
  return (a > b) - (a < b);
}

typedef struct {
  PetscReal y;
  int       dir;
} SCut;

static int CmpSCut(const void *x, const void *y)
{
  const SCut *a = (const SCut *)x, *b = (const SCut *)y;
  return (a->y > b->y) - (a->y < b->y);
}

/* the ground covered twice or more between the boundary edges ed[0..n): the
 * integral of (winding number - 1)+ over the slabs; where the most is, in at */
static PetscReal OverlapArea(SEdge *ed, PetscInt n, PetscReal *xs, PetscInt *act, SCut *cut, PetscReal at[2])
{
  PetscInt  nx = 0, na = 0, next = 0;
  PetscReal area = 0, most = 0;

  for (PetscInt i = 0; i < n; i++) xs[nx++] = ed[i].x0, xs[nx++] = ed[i].x1;
  qsort(xs, (size_t)nx, sizeof(PetscReal), CmpReal);
  qsort(ed, (size_t)n, sizeof(SEdge), CmpSEdge);
  for (PetscInt i = 0; i + 1 < nx; i++) {
    PetscReal a = xs[i], b = xs[i + 1], xm = 0.5 * (a + b);
    PetscInt  k = 0, w = 0;
    if (!(b > a)) continue;
    for (PetscInt j = 0; j < na; j++) /* drop the edges that end at a */
      if (ed[act[j]].x1 > a) act[k++] = act[j];
    na = k;
    while (next < n && ed[next].x0 <= a) act[na++] = next++;
    for (PetscInt j = 0; j < na; j++) {
      const SEdge *e = &ed[act[j]];
      cut[j]         = (SCut){e->y0 + (e->y1 - e->y0) * (xm - e->x0) / (e->x1 - e->x0), e->dir};
    }
    qsort(cut, (size_t)na, sizeof(SCut), CmpSCut);
    for (PetscInt j = 0; j + 1 < na; j++) {
      PetscReal band;
      w += cut[j].dir;
      if (w < 2) continue;
      band = (b - a) * (cut[j + 1].y - cut[j].y) * (PetscReal)(w - 1);
      area += band;
      if (band > most) most = band, at[0] = xm, at[1] = 0.5 * (cut[j].y + cut[j + 1].y);
    }
  }
  return area;
}

/* is (x, y) inside convex counter-clockwise quad c? */
static int InQuad(const MeshLists *L, PetscInt c, const PetscReal p[2])
{
  for (int j = 0; j < 4; j++) {
    const PetscReal *a = &L->coords[2 * L->cells[4 * c + j]], *b = &L->coords[2 * L->cells[4 * c + (j + 1) % 4]];
    if ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) <= 0) return 0;
  }
  return 1;
}

static PetscReal QuadArea(const MeshLists *L, PetscInt c)
{
  PetscReal a = 0;
  for (int j = 0; j < 4; j++) {
    const PetscReal *p = &L->coords[2 * L->cells[4 * c + j]], *q = &L->coords[2 * L->cells[4 * c + (j + 1) % 4]];
    a += 0.5 * (p[0] * q[1] - q[0] * p[1]);
  }
  return a;
}

/* check 5 */
static int CheckCover(const M2dScene *s, const MeshSources *src, const MeshLists *L, const MeshSkel *sk, char *err, size_t len)
{
  PetscInt  nb = 0, bad = -1;
  SEdge    *ed;
  PetscReal *xs, at[2] = {0, 0}, over = 0, total = 0;
  PetscInt  *act;
  SCut      *cut;

  for (PetscInt e = 0; e < sk->ne; e++) nb += sk->ecell[2 * e + 1] < 0;
  ed  = (SEdge *)malloc((size_t)(nb + 1) * sizeof(SEdge));
  xs  = (PetscReal *)malloc((size_t)(2 * nb + 1) * sizeof(PetscReal));
  act = (PetscInt *)malloc((size_t)(nb + 1) * sizeof(PetscInt));
  cut = (SCut *)malloc((size_t)(nb + 1) * sizeof(SCut));
  if (!ed || !xs || !act || !cut) {
    free(ed), free(xs), free(act), free(cut);
    snprintf(err, len, "out of memory checking the mesh %s", src->all);
    return 1;
  }
  for (PetscInt b = 0; b < s->nbody && bad < 0; b++) {
    PetscInt  n = 0;
    PetscReal amin = PETSC_MAX_REAL;
    total = 0;
    for (PetscInt c = 0; c < sk->nc; c++)
      if (L->cellbody[c] == b) {
        PetscReal a = QuadArea(L, c);
        total += a, amin = PetscMin(amin, a);
      }
    for (PetscInt e = 0; e < sk->ne; e++) {
      PetscInt         c = sk->ecell[2 * e], j = 0;
      const PetscReal *p, *q;
      if (sk->ecell[2 * e + 1] >= 0 || L->cellbody[c] != b) continue;
      while (j < 3 && sk->side[4 * c + j] != e) j++;
      p = &L->coords[2 * L->cells[4 * c + j]], q = &L->coords[2 * L->cells[4 * c + (j + 1) % 4]];
      if (p[0] < q[0]) ed[n++] = (SEdge){p[0], p[1], q[0], q[1], 1};
      else if (q[0] < p[0]) ed[n++] = (SEdge){q[0], q[1], p[0], p[1], -1};
    }
    over = OverlapArea(ed, n, xs, act, cut, at);
    if (over > 1e-3 * amin) bad = b; /* round-off is far below: bands ordered by exact orientations of non-crossing edges */
  }
  free(ed), free(xs), free(act), free(cut);
  if (bad < 0) return 0;
  {
    PetscInt c1 = -1, c2 = -1;
    for (PetscInt c = 0; c < sk->nc && c2 < 0; c++)
      if (L->cellbody[c] == bad && InQuad(L, c, at)) {
        if (c1 < 0) c1 = c;
        else c2 = c;
      }
    if (c2 >= 0)
      snprintf(err, len, "%s, body '%s': quadrilaterals %ld and %ld overlap near (%g, %g) (the cells' areas sum to %g, the body's boundary encloses %g: %g is covered twice)", src->label[L->cellsrc[c2]], BodyName(s, bad), L->celltag[c1], L->celltag[c2], at[0], at[1], total, total - over, over);
    else snprintf(err, len, "%s, body '%s': cells overlap near (%g, %g) (the cells' areas sum to %g, the body's boundary encloses %g: %g is covered twice)", src->all, BodyName(s, bad), at[0], at[1], total, total - over, over);
  }
  return 1;
}

int MeshCheckSkeleton(const M2dScene *s, const MeshSources *src, const MeshLists *L, const MeshSkel *sk, char *err, size_t len)
{
  return CheckEdges(s, src, L, sk, err, len) || CheckBoundary(s, src, L, sk, err, len) || CheckPieces(s, src, L, sk, err, len) || CheckCover(s, src, L, sk, err, len); /* a piece inside the body overlaps it too: the pieces say why */
}
