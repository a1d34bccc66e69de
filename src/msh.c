/* msh.c - strict gmsh reader, ASCII 2.2/4.1 and binary 4.1 (see msh.h).
 * Every count read from the file is checked against the bytes that remain, so
 * a corrupted count can never make us allocate or loop beyond the file. */
#include "msh.h"
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct {
  const char *path;
  char       *buf;
  size_t      len, pos;
  char       *err;
  size_t      errlen;
  const char *section;
  int         failed;
  int         binary; /* format 4.1 binary (Mesh.Binary = 1): ints 4 bytes, sizes 8 */
} Parser;

static long LineOf(const Parser *p, size_t pos)
{
  long line = 1;
  for (size_t i = 0; i < pos && i < p->len; i++)
    if (p->buf[i] == '\n') line++;
  return line;
}

static int Fail(Parser *p, const char *fmt, ...)
{
  char    what[512];
  va_list ap;
  if (p->failed) return 1;
  va_start(ap, fmt);
  vsnprintf(what, sizeof(what), fmt, ap);
  va_end(ap);
  if (p->binary) snprintf(p->err, p->errlen, "mesh file '%s' (binary), byte %zu%s%s: %s", p->path, p->pos, p->section ? " in " : "", p->section ? p->section : "", what);
  else snprintf(p->err, p->errlen, "mesh file '%s', line %ld%s%s: %s", p->path, LineOf(p, p->pos), p->section ? " in " : "", p->section ? p->section : "", what);
  p->failed = 1;
  return 1;
}

static void SkipSpace(Parser *p)
{
  while (p->pos < p->len && (p->buf[p->pos] == ' ' || p->buf[p->pos] == '\t' || p->buf[p->pos] == '\r' || p->buf[p->pos] == '\n')) p->pos++;
}

static size_t Remaining(Parser *p)
{
  return p->len - p->pos;
}

static int ReadLong(Parser *p, long *v)
{
  char *end;
  SkipSpace(p);
  if (p->pos >= p->len) return Fail(p, "unexpected end of file (expected an integer)");
  errno = 0;
  *v    = strtol(p->buf + p->pos, &end, 10);
  if (end == p->buf + p->pos || errno) return Fail(p, "expected an integer");
  if (end < p->buf + p->len && !(*end == ' ' || *end == '\t' || *end == '\r' || *end == '\n')) return Fail(p, "expected an integer");
  p->pos = (size_t)(end - p->buf);
  return 0;
}

/* binary: n raw bytes in the file's (= this machine's, checked) byte order */
static int ReadRaw(Parser *p, void *v, size_t n, const char *what)
{
  if (Remaining(p) < n) return Fail(p, "unexpected end of file (expected %s)", what);
  memcpy(v, p->buf + p->pos, n);
  p->pos += n;
  return 0;
}

/* an int field of the 4.1 format (4 bytes in binary) */
static int ReadInt(Parser *p, long *v)
{
  int i = 0;
  if (!p->binary) return ReadLong(p, v);
  if (ReadRaw(p, &i, sizeof(i), "an integer")) return 1;
  *v = i;
  return 0;
}

/* a size_t field of the 4.1 format (8 bytes in binary) */
static int ReadSize(Parser *p, long *v)
{
  unsigned long long u = 0;
  if (!p->binary) return ReadLong(p, v);
  if (ReadRaw(p, &u, sizeof(u), "a size")) return 1;
  if (u > (unsigned long long)1 << 62) return Fail(p, "size %llu is not plausible (corrupted file?)", u);
  *v = (long)u;
  return 0;
}

/* binary sections start after the keyword's line break */
static int BinaryStart(Parser *p)
{
  if (!p->binary) return 0;
  if (p->pos < p->len && p->buf[p->pos] == '\r') p->pos++;
  if (p->pos >= p->len || p->buf[p->pos] != '\n') return Fail(p, "expected a line break before the binary data");
  p->pos++;
  return 0;
}

static int ReadDouble(Parser *p, double *v)
{
  char *end;
  if (p->binary) {
    if (ReadRaw(p, v, sizeof(*v), "a real number")) return 1;
    if (!(*v == *v) || *v > 1e300 || *v < -1e300) return Fail(p, "coordinate is not a finite number");
    return 0;
  }
  SkipSpace(p);
  if (p->pos >= p->len) return Fail(p, "unexpected end of file (expected a number)");
  errno = 0;
  *v    = strtod(p->buf + p->pos, &end);
  if (end == p->buf + p->pos || errno) return Fail(p, "expected a real number");
  if (end < p->buf + p->len && !(*end == ' ' || *end == '\t' || *end == '\r' || *end == '\n')) return Fail(p, "expected a real number");
  if (!(*v == *v) || *v > 1e300 || *v < -1e300) return Fail(p, "coordinate is not a finite number");
  p->pos = (size_t)(end - p->buf);
  return 0;
}

/* a count that the rest of the file could possibly hold (each item >= 2 bytes) */
static int ReadCount(Parser *p, long *v, long bytes_per_item, const char *what)
{
  if (ReadSize(p, v)) return 1;
  if (*v < 0) return Fail(p, "negative %s", what);
  if ((size_t)*v > Remaining(p) / (size_t)bytes_per_item + 1) return Fail(p, "%s %ld is larger than the rest of the file can hold (truncated or corrupted file?)", what, *v);
  return 0;
}

static int ReadWord(Parser *p, char *w, size_t n)
{
  size_t k = 0;
  SkipSpace(p);
  if (p->pos >= p->len) return Fail(p, "unexpected end of file");
  while (p->pos < p->len && !(p->buf[p->pos] == ' ' || p->buf[p->pos] == '\t' || p->buf[p->pos] == '\r' || p->buf[p->pos] == '\n')) {
    if (k + 1 < n) w[k++] = p->buf[p->pos];
    p->pos++;
  }
  w[k] = 0;
  return 0;
}


static int Expect(Parser *p, const char *word)
{
  char w[64];
  if (ReadWord(p, w, sizeof(w))) return 1;
  if (strcmp(w, word)) return Fail(p, "expected '%s', found '%.40s' (truncated or corrupted file?)", word, w);
  return 0;
}

/* ---------- node lookup: sorted (tag, index) pairs ---------- */
typedef struct {
  long tag, idx;
} TagIdx;

static int CmpTag(const void *a, const void *b)
{
  long x = ((const TagIdx *)a)->tag, y = ((const TagIdx *)b)->tag;
  return (x > y) - (x < y);
}

typedef struct {
  TagIdx *t;
  long    n;
  long   *direct; /* dense tags (gmsh numbers 1..N): index by tag - lo, -1 if none */
  long    lo, hi;
} NodeMap;

static long NodeLookup(const NodeMap *map, long tag)
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

static int BuildNodeMap(Parser *p, NodeMap *map)
{
  if (map->n > 0) { /* dense tags: a table instead of sorting (level 6: 2e6 nodes) */
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
        if (*d >= 0) return Fail(p, "node tag %ld appears twice", map->t[i].tag);
        *d = map->t[i].idx;
      }
      return 0;
    }
  }
  qsort(map->t, (size_t)map->n, sizeof(TagIdx), CmpTag);
  for (long i = 1; i < map->n; i++)
    if (map->t[i].tag == map->t[i - 1].tag) return Fail(p, "node tag %ld appears twice", map->t[i].tag);
  return 0;
}

/* ---------- growable arrays ---------- */
static int Grow(Parser *p, void **a, long *cap, long need, size_t elsize)
{
  if (need <= *cap) return 0;
  long  nc = *cap ? *cap : 64;
  while (nc < need) nc *= 2;
  void *b = realloc(*a, (size_t)nc * elsize);
  if (!b) return Fail(p, "out of memory");
  *a   = b;
  *cap = nc;
  return 0;
}

typedef struct {
  long qcap, lcap, pcap;
} Caps;

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

static const char *ElementName(long type)
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

static int NodesPerElement(long type)
{
  switch (type) {
  case 1: return 2;
  case 2: return 3;
  case 3: return 4;
  case 4: return 4;
  case 5: return 8;
  case 6: return 6;
  case 7: return 5;
  case 8: return 3;
  case 9: return 6;
  case 10: return 9;
  case 11: return 10;
  case 15: return 1;
  case 16: return 8;
  default: return -1;
  }
}

static int ElementDim(long type)
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
static int StoreElement(Parser *p, MshMesh *m, Caps *c, long etag, long type, const long *nodes, int phys)
{
  int dim = ElementDim(type);
  if (dim == 2) {
    if (type != 3) {
      const char *pn = MshPhysicalName(m, 2, phys);
      return Fail(p, "element %ld is a %s%s%s%s; mortar2d needs 4-node quadrilaterals (use Recombine in gmsh)", etag, ElementName(type), pn ? " in physical surface '" : "", pn ? pn : "", pn ? "'" : "");
    }
    return AddQuad(p, m, c, nodes, etag, phys);
  }
  if (dim == 1) {
    if (type != 1) return Fail(p, "element %ld is a %s; only first-order (2-node) lines are supported", etag, ElementName(type));
    if (phys < 0) return 0; /* unnamed boundary lines carry no information */
    return AddLine(p, m, c, nodes[0], nodes[1], phys);
  }
  if (dim == 0) {
    if (phys < 0) return 0;
    return AddPoint(p, m, c, nodes[0], phys);
  }
  return Fail(p, "element %ld is a %s (type %ld); mortar2d reads 2D meshes of quadrilaterals", etag, type == 4 ? "tetrahedron" : type == 5 ? "hexahedron" : "3D or unknown element", type);
}

static int ReadPhysicalNamesText(Parser *p, MshMesh *m)
{
  long n;
  p->section = "$PhysicalNames";
  if (ReadCount(p, &n, 6, "number of physical names")) return 1;
  m->phys = (MshPhysical *)calloc((size_t)(n > 0 ? n : 1), sizeof(MshPhysical));
  if (!m->phys) return Fail(p, "out of memory");
  for (long i = 0; i < n; i++) {
    long dim, tag;
    if (ReadLong(p, &dim) || ReadLong(p, &tag)) return 1;
    if (dim < 0 || dim > 3) return Fail(p, "physical group dimension %ld is not 0..3", dim);
    SkipSpace(p);
    if (p->pos >= p->len || p->buf[p->pos] != '"') return Fail(p, "expected a quoted physical name");
    p->pos++;
    size_t k = 0;
    while (p->pos < p->len && p->buf[p->pos] != '"' && p->buf[p->pos] != '\n') {
      if (k + 1 < sizeof(m->phys[i].name)) m->phys[i].name[k++] = p->buf[p->pos];
      p->pos++;
    }
    if (p->pos >= p->len || p->buf[p->pos] != '"') return Fail(p, "unterminated physical name");
    p->pos++;
    m->phys[i].name[k] = 0;
    m->phys[i].dim     = (int)dim;
    m->phys[i].tag     = (int)tag;
    m->nphys++;
  }
  if (Expect(p, "$EndPhysicalNames")) return 1;
  return 0;
}

/* text in binary files too */
static int ReadPhysicalNames(Parser *p, MshMesh *m)
{
  int binary = p->binary, rc;
  p->binary = 0;
  rc        = ReadPhysicalNamesText(p, m);
  p->binary = binary;
  return rc;
}

/* ---------- format 4.1 ---------- */
typedef struct {
  int  dim;
  long tag;
  int  phys; /* first physical tag of the entity, -1 if none */
  long nphys;
  int *physall;
} Entity;

typedef struct {
  Entity *e;
  long    n;
} EntityTable;

static const Entity *FindEntity(const EntityTable *t, int dim, long tag)
{
  for (long i = 0; i < t->n; i++)
    if (t->e[i].dim == dim && t->e[i].tag == tag) return &t->e[i];
  return NULL;
}

static int ReadEntities41(Parser *p, EntityTable *t)
{
  long cnt[4], total;
  p->section = "$Entities";
  if (BinaryStart(p)) return 1;
  for (int d = 0; d < 4; d++)
    if (ReadCount(p, &cnt[d], 8, "number of entities")) return 1;
  total = cnt[0] + cnt[1] + cnt[2] + cnt[3];
  t->e  = (Entity *)calloc((size_t)(total > 0 ? total : 1), sizeof(Entity));
  if (!t->e) return Fail(p, "out of memory");
  for (int d = 0; d < 4; d++) {
    for (long i = 0; i < cnt[d]; i++) {
      Entity *e = &t->e[t->n++];
      double  x;
      long    nb, b;
      e->dim = d;
      if (ReadInt(p, &e->tag)) return 1;
      for (int k = 0; k < (d == 0 ? 3 : 6); k++)
        if (ReadDouble(p, &x)) return 1;
      if (ReadCount(p, &e->nphys, 2, "number of physical tags")) return 1;
      e->physall = (int *)malloc((size_t)(e->nphys > 0 ? e->nphys : 1) * sizeof(int));
      if (!e->physall) return Fail(p, "out of memory");
      e->phys = -1;
      for (long k = 0; k < e->nphys; k++) {
        long ph;
        if (ReadInt(p, &ph)) return 1;
        e->physall[k] = (int)(ph < 0 ? -ph : ph);
        if (k == 0) e->phys = e->physall[0];
      }
      if (d > 0) {
        if (ReadCount(p, &nb, 2, "number of bounding entities")) return 1;
        for (long k = 0; k < nb; k++)
          if (ReadInt(p, &b)) return 1;
      }
    }
  }
  if (Expect(p, "$EndEntities")) return 1;
  return 0;
}

static int ReadNodes41(Parser *p, MshMesh *m, NodeMap *map)
{
  long nblocks, nnodes, mintag, maxtag, filled = 0;
  p->section = "$Nodes";
  if (BinaryStart(p) || ReadCount(p, &nblocks, 8, "number of node blocks") || ReadCount(p, &nnodes, 6, "number of nodes") || ReadSize(p, &mintag) || ReadSize(p, &maxtag)) return 1;
  m->xy  = (double *)malloc((size_t)(nnodes > 0 ? nnodes : 1) * 2 * sizeof(double));
  map->t = (TagIdx *)malloc((size_t)(nnodes > 0 ? nnodes : 1) * sizeof(TagIdx));
  if (!m->xy || !map->t) return Fail(p, "out of memory");
  for (long b = 0; b < nblocks; b++) {
    long edim, etag, param, nin;
    if (ReadInt(p, &edim) || ReadInt(p, &etag) || ReadInt(p, &param) || ReadCount(p, &nin, 6, "number of nodes in block")) return 1;
    if (filled + nin > nnodes) return Fail(p, "node blocks hold more nodes than the %ld announced", nnodes);
    if (param != 0 && param != 1) return Fail(p, "node block parametric flag %ld is not 0 or 1", param);
    for (long i = 0; i < nin; i++) {
      long tag;
      if (ReadSize(p, &tag)) return 1;
      if (tag <= 0) return Fail(p, "node tag %ld is not positive", tag);
      map->t[filled + i].tag = tag;
      map->t[filled + i].idx = filled + i;
    }
    for (long i = 0; i < nin; i++) {
      double z, u;
      if (ReadDouble(p, &m->xy[2 * (filled + i)]) || ReadDouble(p, &m->xy[2 * (filled + i) + 1]) || ReadDouble(p, &z)) return 1;
      if (param)
        for (long k = 0; k < edim; k++)
          if (ReadDouble(p, &u)) return 1;
    }
    filled += nin;
  }
  if (filled != nnodes) return Fail(p, "node blocks hold %ld nodes, header announced %ld", filled, nnodes);
  m->nnode = nnodes;
  map->n   = nnodes;
  if (BuildNodeMap(p, map)) return 1;
  if (Expect(p, "$EndNodes")) return 1;
  return 0;
}

static int ReadElements41(Parser *p, MshMesh *m, const NodeMap *map, const EntityTable *ents, Caps *c)
{
  long nblocks, nelem, mintag, maxtag, seen = 0;
  p->section = "$Elements";
  if (BinaryStart(p) || ReadCount(p, &nblocks, 8, "number of element blocks") || ReadCount(p, &nelem, 4, "number of elements") || ReadSize(p, &mintag) || ReadSize(p, &maxtag)) return 1;
  for (long b = 0; b < nblocks; b++) {
    long          edim, etag, type, nin;
    const Entity *ent;
    int           nn;
    if (ReadInt(p, &edim) || ReadInt(p, &etag) || ReadInt(p, &type) || ReadCount(p, &nin, 4, "number of elements in block")) return 1;
    nn = NodesPerElement(type);
    if (nn < 0) return Fail(p, "unknown element type %ld", type);
    if (ElementDim(type) != edim) return Fail(p, "element type %ld (%s) in an entity of dimension %ld", type, ElementName(type), edim);
    ent = FindEntity(ents, (int)edim, etag);
    if (!ent) return Fail(p, "element block refers to entity (%ld, %ld) that $Entities does not list", edim, etag);
    seen += nin;
    if (seen > nelem) return Fail(p, "element blocks hold more elements than the %ld announced", nelem);
    for (long i = 0; i < nin; i++) {
      long tag, nodes[9];
      if (ReadSize(p, &tag)) return 1;
      for (int k = 0; k < nn; k++) {
        long ntag;
        if (ReadSize(p, &ntag)) return 1;
        nodes[k] = NodeLookup(map, ntag);
        if (nodes[k] < 0) return Fail(p, "element %ld uses node %ld, which $Nodes does not define", tag, ntag);
      }
      if (edim == 2) {
        if (StoreElement(p, m, c, tag, type, nodes, ent->phys)) return 1;
      } else {
        if (ent->nphys == 0 && StoreElement(p, m, c, tag, type, nodes, -1)) return 1;
        for (long k = 0; k < ent->nphys; k++)
          if (StoreElement(p, m, c, tag, type, nodes, ent->physall[k])) return 1;
      }
    }
  }
  if (seen != nelem) return Fail(p, "element blocks hold %ld elements, header announced %ld", seen, nelem);
  if (Expect(p, "$EndElements")) return 1;
  return 0;
}

/* ---------- format 2.2 ---------- */
static int ReadNodes22(Parser *p, MshMesh *m, NodeMap *map)
{
  long n;
  p->section = "$Nodes";
  if (ReadCount(p, &n, 8, "number of nodes")) return 1;
  m->xy  = (double *)malloc((size_t)(n > 0 ? n : 1) * 2 * sizeof(double));
  map->t = (TagIdx *)malloc((size_t)(n > 0 ? n : 1) * sizeof(TagIdx));
  if (!m->xy || !map->t) return Fail(p, "out of memory");
  for (long i = 0; i < n; i++) {
    long   tag;
    double z;
    if (ReadLong(p, &tag) || ReadDouble(p, &m->xy[2 * i]) || ReadDouble(p, &m->xy[2 * i + 1]) || ReadDouble(p, &z)) return 1;
    if (tag <= 0) return Fail(p, "node tag %ld is not positive", tag);
    map->t[i].tag = tag;
    map->t[i].idx = i;
  }
  m->nnode = n;
  map->n   = n;
  if (BuildNodeMap(p, map)) return 1;
  if (Expect(p, "$EndNodes")) return 1;
  return 0;
}

static int ReadElements22(Parser *p, MshMesh *m, const NodeMap *map, Caps *c)
{
  long n;
  p->section = "$Elements";
  if (ReadCount(p, &n, 8, "number of elements")) return 1;
  for (long i = 0; i < n; i++) {
    long tag, type, ntags, phys = -1, t, nodes[9];
    int  nn;
    if (ReadLong(p, &tag) || ReadLong(p, &type) || ReadCount(p, &ntags, 2, "number of element tags")) return 1;
    nn = NodesPerElement(type);
    if (nn < 0) return Fail(p, "element %ld has unknown type %ld", tag, type);
    for (long k = 0; k < ntags; k++) {
      if (ReadLong(p, &t)) return 1;
      if (k == 0) phys = t;
    }
    for (int k = 0; k < nn; k++) {
      long ntag;
      if (ReadLong(p, &ntag)) return 1;
      nodes[k] = NodeLookup(map, ntag);
      if (nodes[k] < 0) return Fail(p, "element %ld uses node %ld, which $Nodes does not define", tag, ntag);
    }
    if (StoreElement(p, m, c, tag, type, nodes, phys > 0 ? (int)phys : -1)) return 1;
  }
  if (Expect(p, "$EndElements")) return 1;
  return 0;
}

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

int MshRead(const char *path, MshMesh *m, char *err, size_t errlen)
{
  Parser      p;
  FILE       *fp;
  long        size;
  char        w[64];
  double      version = 0;
  long        ftype = 0, dsize = 0;
  NodeMap     map   = {NULL, 0, NULL, 0, 0};
  EntityTable ents  = {NULL, 0};
  Caps        caps  = {0, 0, 0};
  int         have_nodes = 0, have_elems = 0, rc = 1;

  memset(m, 0, sizeof(*m));
  memset(&p, 0, sizeof(p));
  p.path   = path;
  p.err    = err;
  p.errlen = errlen;
  {
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
      snprintf(err, errlen, "mesh file '%s' is not a regular file (a directory?)", path);
      return 1;
    }
  }
  fp = fopen(path, "rb");
  if (!fp) {
    snprintf(err, errlen, "cannot open mesh file '%s': %s", path, strerror(errno));
    return 1;
  }
  if (fseek(fp, 0, SEEK_END) || (size = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET)) {
    snprintf(err, errlen, "cannot read mesh file '%s': %s", path, strerror(errno));
    fclose(fp);
    return 1;
  }
  p.buf = (char *)malloc((size_t)size + 1);
  if (!p.buf) {
    snprintf(err, errlen, "mesh file '%s': out of memory reading %ld bytes", path, size);
    fclose(fp);
    return 1;
  }
  if (fread(p.buf, 1, (size_t)size, fp) != (size_t)size) {
    snprintf(err, errlen, "cannot read mesh file '%s': %s", path, ferror(fp) ? strerror(errno) : "short read");
    fclose(fp);
    free(p.buf);
    return 1;
  }
  fclose(fp);
  p.buf[size] = 0;
  p.len       = (size_t)size;
  p.section = "$MeshFormat";
  if (Expect(&p, "$MeshFormat") || ReadDouble(&p, &version) || ReadLong(&p, &ftype) || ReadLong(&p, &dsize)) goto done;
  if (!(version == 2.2 || version == 4.1)) {
    Fail(&p, "unsupported .msh format version %g (mortar2d reads 2.2 and 4.1)", version);
    goto done;
  }
  if (ftype != 0 && ftype != 1) {
    Fail(&p, "file type %ld is neither 0 (ASCII) nor 1 (binary)", ftype);
    goto done;
  }
  if (ftype == 1) { /* binary 4.1: a one in the file's byte order follows the header line */
    long one;
    if (version != 4.1) {
      Fail(&p, "binary .msh files are read in format 4.1 only (save with Mesh.MshFileVersion = 4.1, or Mesh.Binary = 0)");
      goto done;
    }
    if (dsize != (long)sizeof(size_t)) {
      Fail(&p, "binary data size %ld is not %d", dsize, (int)sizeof(size_t));
      goto done;
    }
    p.binary = 1;
    if (BinaryStart(&p) || ReadInt(&p, &one)) goto done;
    if (one != 1) {
      Fail(&p, "binary file written with another byte order");
      goto done;
    }
  } else if (memchr(p.buf, 0, p.len)) {
    Fail(&p, "file contains NUL bytes but its header says ASCII (corrupted, or binary with a wrong header?)");
    goto done;
  }
  if (Expect(&p, "$EndMeshFormat")) goto done;
  while (1) {
    SkipSpace(&p);
    if (p.pos >= p.len) break;
    p.section = NULL;
    if (ReadWord(&p, w, sizeof(w))) goto done;
    if (!strcmp(w, "$PhysicalNames")) {
      if (m->phys) {
        Fail(&p, "second $PhysicalNames section");
        goto done;
      }
      if (ReadPhysicalNames(&p, m)) goto done;
    } else if (!strcmp(w, "$Entities") && version > 4) {
      if (ents.e) {
        Fail(&p, "second $Entities section");
        goto done;
      }
      if (ReadEntities41(&p, &ents)) goto done;
    } else if (!strcmp(w, "$Nodes")) {
      if (have_nodes) {
        Fail(&p, "second $Nodes section");
        goto done;
      }
      if (version > 4 ? ReadNodes41(&p, m, &map) : ReadNodes22(&p, m, &map)) goto done;
      have_nodes = 1;
    } else if (!strcmp(w, "$Elements")) {
      if (!have_nodes) {
        Fail(&p, "$Elements before $Nodes");
        goto done;
      }
      if (have_elems) {
        Fail(&p, "second $Elements section");
        goto done;
      }
      if (version > 4 && !ents.e) {
        Fail(&p, "$Elements without $Entities");
        goto done;
      }
      if (version > 4 ? ReadElements41(&p, m, &map, &ents, &caps) : ReadElements22(&p, m, &map, &caps)) goto done;
      have_elems = 1;
    } else if (w[0] == '$' && strncmp(w, "$End", 4)) {
      /* skip unknown sections ($Periodic, $NodeData, ...) */
      char endtag[80];
      snprintf(endtag, sizeof(endtag), "$End%s", w + 1);
      const char *q = NULL;
      for (size_t k = p.pos; k + strlen(endtag) <= p.len && !q; k++) /* binary sections may hold NUL bytes */
        if (p.buf[k] == '$' && !memcmp(p.buf + k, endtag, strlen(endtag))) q = p.buf + k;
      if (!q) {
        Fail(&p, "section %.40s has no %.40s", w, endtag);
        goto done;
      }
      p.pos = (size_t)(q - p.buf) + strlen(endtag);
    } else {
      Fail(&p, "unexpected text '%.40s' between sections", w);
      goto done;
    }
  }
  p.section = NULL;
  if (!have_nodes || !have_elems) {
    snprintf(err, errlen, "mesh file '%s': no %s section (truncated or not a gmsh mesh?)", path, !have_nodes ? "$Nodes" : "$Elements");
    goto done;
  }
  if (m->nquad == 0) {
    snprintf(err, errlen, "mesh file '%s': no quadrilateral elements", path);
    goto done;
  }
  rc = 0;
done:
  free(map.t);
  free(map.direct);
  for (long i = 0; i < ents.n; i++) free(ents.e[i].physall);
  free(ents.e);
  free(p.buf);
  return rc;
}
