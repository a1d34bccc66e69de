/* remesh_field.c - a mesh-size field given on a previous mesh, evaluated anywhere
 * (see remesh.h): per-node sizes interpolated linearly on the two triangles
 * (0,1,2), (0,2,3) of the quad holding the point, per-cell sizes constant in it.
 * Cells are found through buckets at several levels (a quadtree flattened into
 * one sorted key list). A point outside every cell of the body asked for (a
 * curved boundary bulges out of the previous, polygonal mesh of it) takes the
 * value at the closest point of a nearby cell: sizes never jump to a default. */
#include "remesh.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAXLEVEL 24 /* bucket side s0 / 2^level; i, j < 2^24 fit in a key */

struct M2dRemeshField {
  const MshMesh      *m;
  const double       *hnode, *hcell;
  double              hmin, hmax;
  double              x0, y0, s0; /* the square [x0, x0 + s0] x [y0, y0 + s0] holds every node */
  unsigned            levels;     /* bit L set: some cell is filed at level L */
  long                nkey;
  unsigned long long *key;        /* sorted bucket keys (level, i, j) */
  long               *start, *cell; /* cells of bucket k: cell[start[k] .. start[k + 1]) */
  double             *box;          /* xmin, ymin, xmax, ymax of each cell */
};

typedef struct {
  unsigned long long key;
  long               cell;
} Entry;

static unsigned long long Key(int level, long i, long j)
{
  return ((unsigned long long)level << 48) | ((unsigned long long)i << 24) | (unsigned long long)j;
}

static int CmpEntry(const void *a, const void *b)
{
  const Entry *x = (const Entry *)a, *y = (const Entry *)b;
  return x->key != y->key ? (x->key > y->key) - (x->key < y->key) : (x->cell > y->cell) - (x->cell < y->cell);
}

static void CellBox(const MshMesh *m, long q, double box[4])
{
  box[0] = box[2] = m->xy[2 * m->quad[4 * q]];
  box[1] = box[3] = m->xy[2 * m->quad[4 * q] + 1];
  for (int k = 1; k < 4; k++) {
    const double *p = &m->xy[2 * m->quad[4 * q + k]];
    box[0] = fmin(box[0], p[0]), box[2] = fmax(box[2], p[0]);
    box[1] = fmin(box[1], p[1]), box[3] = fmax(box[3], p[1]);
  }
}

/* bucket index of coordinate v at a level, clamped to the grid */
static long Index(const M2dRemeshField *f, int level, double v, double v0)
{
  double n = ldexp(1.0, level), i = floor((v - v0) / f->s0 * n);
  return i < 0 ? 0 : i >= n ? (long)n - 1 : (long)i;
}

/* Each cell is filed in the buckets its box overlaps, at the level whose bucket
 * side is at least the box (so at most 2 x 2 buckets): a graded mesh costs a
 * few buckets per cell at every level, where one uniform grid would hold
 * hundreds of small cells per bucket. */
static int BuildBuckets(M2dRemeshField *f)
{
  const MshMesh *m = f->m;
  double         lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  Entry         *e;
  long           n = 0;
  for (long i = 0; i < m->nnode; i++)
    for (int d = 0; d < 2; d++) lo[d] = fmin(lo[d], m->xy[2 * i + d]), hi[d] = fmax(hi[d], m->xy[2 * i + d]);
  f->x0 = lo[0], f->y0 = lo[1], f->s0 = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), 1e-300) * (1 + 1e-9);
  if (!(f->box = (double *)malloc(4 * (size_t)m->nquad * sizeof(double)))) return 1;
  if (!(e = (Entry *)malloc(4 * (size_t)m->nquad * sizeof(Entry)))) return 1;
  for (long q = 0; q < m->nquad; q++) {
    double size = 0, *box = &f->box[4 * q];
    int    level;
    CellBox(m, q, box);
    size  = fmax(box[2] - box[0], box[3] - box[1]);
    level = size > 0 ? (int)floor(log2(f->s0 / size)) : MAXLEVEL;
    level = level < 0 ? 0 : level > MAXLEVEL ? MAXLEVEL : level;
    f->levels |= 1u << level;
    for (long j = Index(f, level, box[1], f->y0); j <= Index(f, level, box[3], f->y0); j++)
      for (long i = Index(f, level, box[0], f->x0); i <= Index(f, level, box[2], f->x0); i++) e[n++] = (Entry){Key(level, i, j), q};
  }
  qsort(e, (size_t)n, sizeof(Entry), CmpEntry);
  f->key   = (unsigned long long *)malloc((size_t)(n ? n : 1) * sizeof(*f->key));
  f->start = (long *)malloc((size_t)(n + 1) * sizeof(long));
  f->cell  = (long *)malloc((size_t)(n ? n : 1) * sizeof(long));
  if (!f->key || !f->start || !f->cell) {
    free(e);
    return 1;
  }
  for (long k = 0; k < n; k++) {
    if (!k || e[k].key != e[k - 1].key) {
      f->key[f->nkey]     = e[k].key;
      f->start[f->nkey++] = k;
    }
    f->cell[k] = e[k].cell;
  }
  f->start[f->nkey] = n;
  free(e);
  return 0;
}

int M2dRemeshFieldCreate(const MshMesh *prev, const double *hnode, const double *hcell, double hmin, double hmax, M2dRemeshField **field)
{
  M2dRemeshField *f = (M2dRemeshField *)calloc(1, sizeof(*f));
  *field          = NULL;
  if (!f) return 1;
  f->m = prev, f->hnode = hnode, f->hcell = hcell, f->hmin = hmin, f->hmax = hmax;
  if (!prev->nquad || BuildBuckets(f)) {
    M2dRemeshFieldDestroy(&f);
    return 1;
  }
  *field = f;
  return 0;
}

void M2dRemeshFieldDestroy(M2dRemeshField **f)
{
  if (!*f) return;
  free((*f)->key);
  free((*f)->start);
  free((*f)->cell);
  free((*f)->box);
  free(*f);
  *f = NULL;
}

/* barycentric coordinates of p in triangle (a, b, c); the smallest one */
static double Bary(const double *a, const double *b, const double *c, double x, double y, double l[3])
{
  double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
  if (det == 0) return -1;
  l[1] = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det;
  l[2] = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
  l[0] = 1 - l[1] - l[2];
  return fmin(l[0], fmin(l[1], l[2]));
}

static double Value(const M2dRemeshField *f, long q, const int k[3], const double l[3])
{
  double h = 0;
  if (f->hcell) h = f->hcell[q];
  else
    for (int i = 0; i < 3; i++) h += l[i] * f->hnode[f->m->quad[4 * q + k[i]]];
  if (f->hmin > 0 && h < f->hmin) h = f->hmin;
  if (f->hmax > 0 && h > f->hmax) h = f->hmax;
  return h;
}

/* in cell q: the value at (x, y) if inside (*dist = 0), else at the cell's
 * closest boundary point and *dist its distance */
static double CellEval(const M2dRemeshField *f, long q, double x, double y, double *dist)
{
  static const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
  const MshMesh   *m         = f->m;
  const double    *p[4];
  double           l[3], best = 1e300, val = 0;
  for (int k = 0; k < 4; k++) p[k] = &m->xy[2 * m->quad[4 * q + k]];
  for (int t = 0; t < 2; t++)
    if (Bary(p[tri[t][0]], p[tri[t][1]], p[tri[t][2]], x, y, l) >= -1e-12) {
      *dist = 0;
      return Value(f, q, tri[t], l);
    }
  for (int k = 0; k < 4; k++) { /* closest point on edge k -> k+1 */
    const double *a = p[k], *b = p[(k + 1) % 4];
    double        e[2] = {b[0] - a[0], b[1] - a[1]}, ee = e[0] * e[0] + e[1] * e[1];
    double        s    = ee > 0 ? ((x - a[0]) * e[0] + (y - a[1]) * e[1]) / ee : 0, d, dx, dy;
    s  = s < 0 ? 0 : s > 1 ? 1 : s;
    dx = a[0] + s * e[0] - x, dy = a[1] + s * e[1] - y;
    d  = dx * dx + dy * dy;
    if (d < best) {
      int    kk[3] = {k, (k + 1) % 4, k};
      double ll[3] = {1 - s, s, 0};
      best         = d;
      val          = Value(f, q, kk, ll);
    }
  }
  *dist = sqrt(best);
  return val;
}

/* bucket k, or -1 */
static long Find(const M2dRemeshField *f, unsigned long long key)
{
  long lo = 0, hi = f->nkey - 1;
  while (lo <= hi) {
    long mid = (lo + hi) / 2;
    if (f->key[mid] == key) return mid;
    if (f->key[mid] < key) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

/* distance from (x, y) to the rectangle b = xmin, ymin, xmax, ymax */
static double BoxDist(const double *b, double x, double y)
{
  double dx = fmax(fmax(b[0] - x, x - b[2]), 0), dy = fmax(fmax(b[1] - y, y - b[3]), 0);
  return sqrt(dx * dx + dy * dy);
}

/* The cells of bucket (level, i, j) of surface phys that may hold the point (or,
 * if nearest, be closer than *best): returns 1 when one holds it (*val its
 * value), else keeps the closest in *best, *val. */
static int Scan(const M2dRemeshField *f, int phys, int level, long i, long j, double x, double y, int nearest, double *best, double *val)
{
  long   k = Find(f, Key(level, i, j));
  double d, v, bd;
  for (long c = k < 0 ? 0 : f->start[k]; k >= 0 && c < f->start[k + 1]; c++) {
    long q = f->cell[c];
    if (phys >= 0 && f->m->quadphys && f->m->quadphys[q] != phys) continue;
    bd = BoxDist(&f->box[4 * q], x, y);
    if (nearest ? bd >= *best : bd > 0) continue;
    v = CellEval(f, q, x, y, &d);
    if (d == 0) {
      *val = v;
      return 1;
    }
    if (d < *best) *best = d, *val = v;
  }
  return 0;
}

/* First the bucket holding the point at every level; then the 3 x 3 buckets
 * around it (those closer than the closest cell so far), which hold every cell
 * closer than its level's bucket side, so a cell within its own size of the
 * point; last, if no cell is that close, every cell. */
double M2dRemeshFieldEval(const M2dRemeshField *f, int phys, double x, double y)
{
  double best = 1e300, val = -1, d, v;
  for (int level = 0; level <= MAXLEVEL; level++)
    if ((f->levels >> level & 1) && Scan(f, phys, level, Index(f, level, x, f->x0), Index(f, level, y, f->y0), x, y, 0, &best, &val)) return val;
  for (int level = MAXLEVEL; level >= 0; level--) {
    long   i = Index(f, level, x, f->x0), j = Index(f, level, y, f->y0), n = 1L << level;
    double side = ldexp(f->s0, -level);
    if (!(f->levels >> level & 1)) continue;
    for (long jj = j - 1; jj <= j + 1; jj++)
      for (long ii = i - 1; ii <= i + 1; ii++) {
        double b[4] = {f->x0 + (double)ii * side, f->y0 + (double)jj * side, f->x0 + (double)(ii + 1) * side, f->y0 + (double)(jj + 1) * side};
        if (ii < 0 || jj < 0 || ii >= n || jj >= n || BoxDist(b, x, y) >= best) continue;
        if (Scan(f, phys, level, ii, jj, x, y, 1, &best, &val)) return val;
      }
  }
  if (val >= 0) return val;
  for (long q = 0; q < f->m->nquad; q++) {
    if (phys >= 0 && f->m->quadphys && f->m->quadphys[q] != phys) continue;
    v = CellEval(f, q, x, y, &d);
    if (d < best) best = d, val = v;
  }
  return val;
}
