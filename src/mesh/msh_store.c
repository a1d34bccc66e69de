/* msh_store.c - what the gmsh reader keeps (see msh_impl.h): the node-tag
 * lookup, the check that every node lies in one plane z = constant, the element
 * type tables and the growable quad/line/point lists of MshMesh, its physical
 * names and MshFree. */
#include "msh_impl.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *MshPhysicalName(const MshMesh *m, int dim, int tag)
{
  for (int i = 0; i < m->nphys; i++)
    if (m->phys[i].dim == dim && m->phys[i].tag == tag) return m->phys[i].name;
  return NULL;
}

void MshFree(MshMesh *m)
{
  free(m->xy);
  free(m->quad);
  free(m->quadtag);
  free(m->quadphys);
  free(m->line);
  free(m->linephys);
  free(m->point);
  free(m->pointphys);
  free(m->phys);
  memset(m, 0, sizeof(*m));
}

/* ---------- node lookup: a direct table for dense tags, else sorted (tag, index) pairs ---------- */
static int CmpTag(const void *a, const void *b)
{
  long x = ((const TagIdx *)a)->tag, y = ((const TagIdx *)b)->tag;
  return (x > y) - (x < y);
}

long MshNodeLookup(const NodeMap *map, long tag)
{
  long lo = 0, hi = map->n - 1;
  if (map->direct) return tag >= map->lo && tag <= map->hi ? map->direct[tag - map->lo] : -1;
  while (lo <= hi) {
    long mid = (lo + hi) / 2;
    if (map->t[mid].tag == tag) return map->t[mid].idx;
    if (map->t[mid].tag < tag) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

int MshBuildNodeMap(Parser *p, NodeMap *map)
{
  if (map->n > 0) { /* dense tags: a table instead of sorting */
    long lo = map->t[0].tag, hi = map->t[0].tag;
    for (long i = 1; i < map->n; i++) {
      if (map->t[i].tag < lo) lo = map->t[i].tag;
      if (map->t[i].tag > hi) hi = map->t[i].tag;
    }
    if (hi - lo < 2 * map->n + 64 && (map->direct = (long *)malloc((size_t)(hi - lo + 1) * sizeof(long)))) {
      map->lo = lo;
      map->hi = hi;
      for (long k = 0; k <= hi - lo; k++) map->direct[k] = -1;
      for (long i = 0; i < map->n; i++) {
        long *d = &map->direct[map->t[i].tag - lo];
        if (*d >= 0) return MshFail(p, "node tag %ld appears twice", map->t[i].tag);
        *d = map->t[i].idx;
      }
      return 0;
    }
  }
  qsort(map->t, (size_t)map->n, sizeof(TagIdx), CmpTag);
  for (long i = 1; i < map->n; i++)
    if (map->t[i].tag == map->t[i - 1].tag) return MshFail(p, "node tag %ld appears twice", map->t[i].tag);
  return 0;
}

/* ---------- every node in one plane z = constant ---------- */
void MshPlaneAdd(Plane *pl, const Parser *p, long tag, double x, double y, double z)
{
  if (pl->n++ == 0) {
    pl->z0 = pl->zfar = z, pl->tag0 = tag, pl->far = 0, pl->tagfar = tag, pl->posfar = p->pos;
    pl->xmin = pl->xmax = x, pl->ymin = pl->ymax = y;
    return;
  }
  pl->xmin = fmin(pl->xmin, x), pl->xmax = fmax(pl->xmax, x);
  pl->ymin = fmin(pl->ymin, y), pl->ymax = fmax(pl->ymax, y);
  if (fabs(z - pl->z0) > pl->far) pl->far = fabs(z - pl->z0), pl->zfar = z, pl->tagfar = tag, pl->posfar = p->pos;
}

/* z may differ from one constant by round-off only (relative to the mesh size),
 * else the mesh is not plane and dropping z would change its geometry */
int MshPlaneCheck(Parser *p, const Plane *pl)
{
  double size = fmax(fmax(pl->xmax - pl->xmin, pl->ymax - pl->ymin), fabs(pl->z0));
  if (pl->n == 0 || pl->far <= 1e-12 * size) return 0;
  p->pos = pl->posfar;
  return MshFail(p, "node %ld has z = %.15g but node %ld has z = %.15g: mortar2d reads plane meshes (every node at one z)", pl->tagfar, pl->zfar, pl->tag0, pl->z0);
}

/* ---------- growable arrays ---------- */
static int Grow(Parser *p, void **a, long *cap, long need, size_t elsize)
{
  if (need <= *cap) return 0;
  long  nc = *cap ? *cap : 64;
  while (nc < need) nc *= 2;
  void *b = realloc(*a, (size_t)nc * elsize);
  if (!b) return MshFail(p, "out of memory");
  *a   = b;
  *cap = nc;
  return 0;
}

static int AddQuad(Parser *p, MshMesh *m, Caps *c, const long nodes[4], long tag, int phys)
{
  long need = m->nquad + 1, cap = c->qcap;
  if (Grow(p, (void **)&m->quad, &cap, need * 4, sizeof(long))) return 1;
  cap = c->qcap;
  if (Grow(p, (void **)&m->quadtag, &cap, need, sizeof(long))) return 1;
  cap = c->qcap;
  if (Grow(p, (void **)&m->quadphys, &cap, need, sizeof(int))) return 1;
  if (need > c->qcap) c->qcap = cap;
  for (int k = 0; k < 4; k++) m->quad[4 * m->nquad + k] = nodes[k];
  m->quadtag[m->nquad]  = tag;
  m->quadphys[m->nquad] = phys;
  m->nquad++;
  return 0;
}

static int AddLine(Parser *p, MshMesh *m, Caps *c, long a, long b, int phys)
{
  long need = m->nline + 1, cap = c->lcap;
  if (Grow(p, (void **)&m->line, &cap, need * 2, sizeof(long))) return 1;
  cap = c->lcap;
  if (Grow(p, (void **)&m->linephys, &cap, need, sizeof(int))) return 1;
  if (need > c->lcap) c->lcap = cap;
  m->line[2 * m->nline]     = a;
  m->line[2 * m->nline + 1] = b;
  m->linephys[m->nline++]   = phys;
  return 0;
}

static int AddPoint(Parser *p, MshMesh *m, Caps *c, long a, int phys)
{
  long need = m->npoint + 1, cap = c->pcap;
  if (Grow(p, (void **)&m->point, &cap, need, sizeof(long))) return 1;
  cap = c->pcap;
  if (Grow(p, (void **)&m->pointphys, &cap, need, sizeof(int))) return 1;
  if (need > c->pcap) c->pcap = cap;
  m->point[m->npoint]       = a;
  m->pointphys[m->npoint++] = phys;
  return 0;
}

/* ---------- gmsh element types ---------- */
const char *MshElementName(long type)
{
  switch (type) {
  case 1: return "2-node line";
  case 2: return "3-node triangle";
  case 3: return "4-node quadrangle";
  case 8: return "3-node line";
  case 9: return "6-node triangle";
  case 10: return "9-node quadrangle";
  case 15: return "point";
  case 16: return "8-node quadrangle";
  default: return "element";
  }
}

int MshNodesPerElement(long type)
{
  static const int n[17] = {-1, 2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, -1, -1, -1, 1, 8};
  return type >= 0 && type <= 16 ? n[type] : -1;
}

int MshElementDim(long type)
{
  switch (type) {
  case 15: return 0;
  case 1:
  case 8: return 1;
  case 2:
  case 3:
  case 9:
  case 10:
  case 16: return 2;
  default: return 3;
  }
}

/* Store one element read from the file. phys is the physical tag (or -1). */
int MshStoreElement(Parser *p, MshMesh *m, Caps *c, long etag, long type, const long *nodes, int phys)
{
  int dim = MshElementDim(type);
  if (dim == 2) {
    if (type != 3) {
      const char *pn = MshPhysicalName(m, 2, phys);
      return MshFail(p, "element %ld is a %s%s%s%s; mortar2d needs 4-node quadrilaterals (use Recombine in gmsh)", etag, MshElementName(type), pn ? " in physical surface '" : "", pn ? pn : "", pn ? "'" : "");
    }
    return AddQuad(p, m, c, nodes, etag, phys);
  }
  if (dim == 1) {
    if (type != 1) return MshFail(p, "element %ld is a %s; only first-order (2-node) lines are supported", etag, MshElementName(type));
    if (phys < 0) return 0; /* unnamed boundary lines carry no information */
    return AddLine(p, m, c, nodes[0], nodes[1], phys);
  }
  if (dim == 0) {
    if (phys < 0) return 0;
    return AddPoint(p, m, c, nodes[0], phys);
  }
  return MshFail(p, "element %ld is a %s (type %ld); mortar2d reads 2D meshes of quadrilaterals", etag, type == 4 ? "tetrahedron" : type == 5 ? "hexahedron" : "3D or unknown element", type);
}
