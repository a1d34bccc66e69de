/* msh_sections.c - the sections of gmsh formats 4.1 (text and binary, through
 * the token layer) and 2.2 (text): $PhysicalNames, $Entities, $Nodes,
 * $Elements (see msh_impl.h). */
#include "msh_impl.h"
#include <stdlib.h>
#include <string.h>

static int ReadPhysicalNamesText(Parser *p, MshMesh *m)
{
  long n;
  p->section = "$PhysicalNames";
  if (MshReadCount(p, &n, 6, "number of physical names")) return 1;
  m->phys = (MshPhysical *)calloc((size_t)(n > 0 ? n : 1), sizeof(MshPhysical));
  if (!m->phys) return MshFail(p, "out of memory");
  for (long i = 0; i < n; i++) {
    long   dim, tag;
    size_t k = 0;
    if (MshReadLong(p, &dim) || MshReadLong(p, &tag)) return 1;
    if (dim < 0 || dim > 3) return MshFail(p, "physical group dimension %ld is not 0..3", dim);
    MshSkipSpace(p);
    if (p->pos >= p->len || p->buf[p->pos] != '"') return MshFail(p, "expected a quoted physical name");
    p->pos++;
    while (p->pos < p->len && p->buf[p->pos] != '"' && p->buf[p->pos] != '\n') {
      if (k + 1 < sizeof(m->phys[i].name)) m->phys[i].name[k++] = p->buf[p->pos];
      p->pos++;
    }
    if (p->pos >= p->len || p->buf[p->pos] != '"') return MshFail(p, "unterminated physical name");
    p->pos++;
    m->phys[i].name[k] = 0;
    m->phys[i].dim     = (int)dim;
    m->phys[i].tag     = (int)tag;
    m->nphys++;
  }
  return MshExpect(p, "$EndPhysicalNames");
}

/* text in binary files too */
int MshReadPhysicalNames(Parser *p, MshMesh *m)
{
  int binary = p->binary, rc;
  p->binary  = 0;
  rc         = ReadPhysicalNamesText(p, m);
  p->binary  = binary;
  return rc;
}

/* ---------- format 4.1 ---------- */
static const Entity *FindEntity(const EntityTable *t, int dim, long tag)
{
  for (long i = 0; i < t->n; i++)
    if (t->e[i].dim == dim && t->e[i].tag == tag) return &t->e[i];
  return NULL;
}

/* one entity: tag, bounding box, physical tags, bounding entities (skipped) */
static int ReadEntity(Parser *p, int d, Entity *e)
{
  double x;
  long   nb, b;
  e->dim = d;
  if (MshReadInt(p, &e->tag)) return 1;
  for (int k = 0; k < (d == 0 ? 3 : 6); k++)
    if (MshReadDouble(p, &x)) return 1;
  if (MshReadCount(p, &e->nphys, 2, "number of physical tags")) return 1;
  e->physall = (int *)malloc((size_t)(e->nphys > 0 ? e->nphys : 1) * sizeof(int));
  if (!e->physall) return MshFail(p, "out of memory");
  e->phys = -1;
  for (long k = 0; k < e->nphys; k++) {
    long ph;
    if (MshReadInt(p, &ph)) return 1;
    e->physall[k] = (int)(ph < 0 ? -ph : ph);
    if (k == 0) e->phys = e->physall[0];
  }
  if (d > 0) {
    if (MshReadCount(p, &nb, 2, "number of bounding entities")) return 1;
    for (long k = 0; k < nb; k++)
      if (MshReadInt(p, &b)) return 1;
  }
  return 0;
}

int MshReadEntities41(Parser *p, EntityTable *t)
{
  long cnt[4], total;
  p->section = "$Entities";
  if (MshBinaryStart(p)) return 1;
  for (int d = 0; d < 4; d++)
    if (MshReadCount(p, &cnt[d], 8, "number of entities")) return 1;
  total = cnt[0] + cnt[1] + cnt[2] + cnt[3];
  t->e  = (Entity *)calloc((size_t)(total > 0 ? total : 1), sizeof(Entity));
  if (!t->e) return MshFail(p, "out of memory");
  for (int d = 0; d < 4; d++)
    for (long i = 0; i < cnt[d]; i++)
      if (ReadEntity(p, d, &t->e[t->n++])) return 1;
  return MshExpect(p, "$EndEntities");
}

int MshReadNodes41(Parser *p, MshMesh *m, NodeMap *map)
{
  long  nblocks, nnodes, mintag, maxtag, filled = 0;
  Plane pl = {0};
  p->section = "$Nodes";
  if (MshBinaryStart(p) || MshReadCount(p, &nblocks, 8, "number of node blocks") || MshReadCount(p, &nnodes, 6, "number of nodes") || MshReadSize(p, &mintag) || MshReadSize(p, &maxtag)) return 1;
  m->xy  = (double *)malloc((size_t)(nnodes > 0 ? nnodes : 1) * 2 * sizeof(double));
  map->t = (TagIdx *)malloc((size_t)(nnodes > 0 ? nnodes : 1) * sizeof(TagIdx));
  if (!m->xy || !map->t) return MshFail(p, "out of memory");
  for (long b = 0; b < nblocks; b++) {
    long edim, etag, param, nin;
    if (MshReadInt(p, &edim) || MshReadInt(p, &etag) || MshReadInt(p, &param) || MshReadCount(p, &nin, 6, "number of nodes in block")) return 1;
    if (filled + nin > nnodes) return MshFail(p, "node blocks hold more nodes than the %ld announced", nnodes);
    if (param != 0 && param != 1) return MshFail(p, "node block parametric flag %ld is not 0 or 1", param);
    for (long i = 0; i < nin; i++) {
      if (MshReadTag(p, &map->t[filled + i].tag, "node")) return 1;
      map->t[filled + i].idx = filled + i;
    }
    for (long i = 0; i < nin; i++) {
      double *xy = &m->xy[2 * (filled + i)], z, u;
      if (MshReadDouble(p, &xy[0]) || MshReadDouble(p, &xy[1]) || MshReadDouble(p, &z)) return 1;
      MshPlaneAdd(&pl, p, map->t[filled + i].tag, xy[0], xy[1], z);
      if (param)
        for (long k = 0; k < edim; k++)
          if (MshReadDouble(p, &u)) return 1;
    }
    filled += nin;
  }
  if (filled != nnodes) return MshFail(p, "node blocks hold %ld nodes, header announced %ld", filled, nnodes);
  m->nnode = nnodes;
  map->n   = nnodes;
  if (MshPlaneCheck(p, &pl) || MshBuildNodeMap(p, map)) return 1;
  return MshExpect(p, "$EndNodes");
}

/* one element block: its header, then nin elements of one type */
static int ReadElementBlock41(Parser *p, MshMesh *m, const NodeMap *map, const EntityTable *ents, Caps *c, long *seen, long nelem)
{
  long          edim, etag, type, nin;
  const Entity *ent;
  int           nn;
  if (MshReadInt(p, &edim) || MshReadInt(p, &etag) || MshReadInt(p, &type) || MshReadCount(p, &nin, 4, "number of elements in block")) return 1;
  nn = MshNodesPerElement(type);
  if (nn < 0) return MshFail(p, "unknown element type %ld", type);
  if (MshElementDim(type) != edim) return MshFail(p, "element type %ld (%s) in an entity of dimension %ld", type, MshElementName(type), edim);
  ent = FindEntity(ents, (int)edim, etag);
  if (!ent) return MshFail(p, "element block refers to entity (%ld, %ld) that $Entities does not list", edim, etag);
  *seen += nin;
  if (*seen > nelem) return MshFail(p, "element blocks hold more elements than the %ld announced", nelem);
  for (long i = 0; i < nin; i++) {
    long tag, nodes[9];
    if (MshReadTag(p, &tag, "element")) return 1;
    for (int k = 0; k < nn; k++) {
      long ntag;
      if (MshReadSize(p, &ntag)) return 1;
      nodes[k] = MshNodeLookup(map, ntag);
      if (nodes[k] < 0) return MshFail(p, "element %ld uses node %ld, which $Nodes does not define", tag, ntag);
    }
    if (edim == 2) {
      if (MshStoreElement(p, m, c, tag, type, nodes, ent->phys)) return 1;
    } else { /* a line or point in several physical groups is stored once per group */
      if (ent->nphys == 0 && MshStoreElement(p, m, c, tag, type, nodes, -1)) return 1;
      for (long k = 0; k < ent->nphys; k++)
        if (MshStoreElement(p, m, c, tag, type, nodes, ent->physall[k])) return 1;
    }
  }
  return 0;
}

int MshReadElements41(Parser *p, MshMesh *m, const NodeMap *map, const EntityTable *ents, Caps *c)
{
  long nblocks, nelem, mintag, maxtag, seen = 0;
  p->section = "$Elements";
  if (MshBinaryStart(p) || MshReadCount(p, &nblocks, 8, "number of element blocks") || MshReadCount(p, &nelem, 4, "number of elements") || MshReadSize(p, &mintag) || MshReadSize(p, &maxtag)) return 1;
  for (long b = 0; b < nblocks; b++)
    if (ReadElementBlock41(p, m, map, ents, c, &seen, nelem)) return 1;
  if (seen != nelem) return MshFail(p, "element blocks hold %ld elements, header announced %ld", seen, nelem);
  return MshExpect(p, "$EndElements");
}

/* ---------- format 2.2 ---------- */
int MshReadNodes22(Parser *p, MshMesh *m, NodeMap *map)
{
  long  n;
  Plane pl = {0};
  p->section = "$Nodes";
  if (MshReadCount(p, &n, 8, "number of nodes")) return 1;
  m->xy  = (double *)malloc((size_t)(n > 0 ? n : 1) * 2 * sizeof(double));
  map->t = (TagIdx *)malloc((size_t)(n > 0 ? n : 1) * sizeof(TagIdx));
  if (!m->xy || !map->t) return MshFail(p, "out of memory");
  for (long i = 0; i < n; i++) {
    long   tag;
    double z;
    if (MshReadTag(p, &tag, "node") || MshReadDouble(p, &m->xy[2 * i]) || MshReadDouble(p, &m->xy[2 * i + 1]) || MshReadDouble(p, &z)) return 1;
    MshPlaneAdd(&pl, p, tag, m->xy[2 * i], m->xy[2 * i + 1], z);
    map->t[i].tag = tag;
    map->t[i].idx = i;
  }
  m->nnode = n;
  map->n   = n;
  if (MshPlaneCheck(p, &pl) || MshBuildNodeMap(p, map)) return 1;
  return MshExpect(p, "$EndNodes");
}

int MshReadElements22(Parser *p, MshMesh *m, const NodeMap *map, Caps *c)
{
  long n;
  p->section = "$Elements";
  if (MshReadCount(p, &n, 8, "number of elements")) return 1;
  for (long i = 0; i < n; i++) {
    long tag, type, ntags, phys = -1, t, nodes[9];
    int  nn;
    if (MshReadTag(p, &tag, "element") || MshReadLong(p, &type) || MshReadCount(p, &ntags, 2, "number of element tags")) return 1;
    nn = MshNodesPerElement(type);
    if (nn < 0) return MshFail(p, "element %ld has unknown type %ld", tag, type);
    for (long k = 0; k < ntags; k++) {
      if (MshReadLong(p, &t)) return 1;
      if (k == 0) phys = t;
    }
    for (int k = 0; k < nn; k++) {
      long ntag;
      if (MshReadLong(p, &ntag)) return 1;
      nodes[k] = MshNodeLookup(map, ntag);
      if (nodes[k] < 0) return MshFail(p, "element %ld uses node %ld, which $Nodes does not define", tag, ntag);
    }
    if (MshStoreElement(p, m, c, tag, type, nodes, phys > 0 ? (int)phys : -1)) return 1;
  }
  return MshExpect(p, "$EndElements");
}
