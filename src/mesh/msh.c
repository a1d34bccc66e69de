/* msh.c - strict gmsh reader, ASCII 2.2/4.1 and binary 4.1 (see msh.h): the
 * file, its header and the loop over its sections. The sections are read in
 * msh_sections.c, the tokens in msh_token.c, the MshMesh kept (and freed) in
 * msh_store.c (msh_impl.h lists the files in the order they call each other). */
#include "msh_impl.h"
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* the whole file into p->buf (NUL-terminated); 0 or 1 with the message in p->err */
static int LoadFile(Parser *p)
{
  struct stat st;
  FILE       *fp;
  long        size;

  if (stat(p->path, &st) == 0 && !S_ISREG(st.st_mode)) {
    snprintf(p->err, p->errlen, "mesh file '%s' is not a regular file (a directory?)", p->path);
    return 1;
  }
  fp = fopen(p->path, "rb");
  if (!fp) {
    snprintf(p->err, p->errlen, "cannot open mesh file '%s': %s", p->path, strerror(errno));
    return 1;
  }
  if (fseek(fp, 0, SEEK_END) || (size = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET)) {
    snprintf(p->err, p->errlen, "cannot read mesh file '%s': %s", p->path, strerror(errno));
    fclose(fp);
    return 1;
  }
  p->buf = (char *)malloc((size_t)size + 1);
  if (!p->buf) {
    snprintf(p->err, p->errlen, "mesh file '%s': out of memory reading %ld bytes", p->path, size);
    fclose(fp);
    return 1;
  }
  if (fread(p->buf, 1, (size_t)size, fp) != (size_t)size) {
    snprintf(p->err, p->errlen, "cannot read mesh file '%s': %s", p->path, ferror(fp) ? strerror(errno) : "short read");
    fclose(fp);
    return 1;
  }
  fclose(fp);
  p->buf[size] = 0;
  p->len       = (size_t)size;
  return 0;
}

/* $MeshFormat: version 2.2 or 4.1, ASCII or (4.1 only) binary in our byte order */
static int ReadHeader(Parser *p, double *version)
{
  long ftype = 0, dsize = 0, one;
  p->section = "$MeshFormat";
  if (MshExpect(p, "$MeshFormat") || MshReadDouble(p, version) || MshReadLong(p, &ftype) || MshReadLong(p, &dsize)) return 1;
  if (!(*version == 2.2 || *version == 4.1)) return MshFail(p, "unsupported .msh format version %g (mortar2d reads 2.2 and 4.1)", *version);
  if (ftype != 0 && ftype != 1) return MshFail(p, "file type %ld is neither 0 (ASCII) nor 1 (binary)", ftype);
  if (ftype == 1) { /* binary 4.1: a one in the file's byte order follows the header line */
    if (*version != 4.1) return MshFail(p, "binary .msh files are read in format 4.1 only (save with Mesh.MshFileVersion = 4.1, or Mesh.Binary = 0)");
    if (dsize != (long)sizeof(size_t)) return MshFail(p, "binary data size %ld is not %d", dsize, (int)sizeof(size_t));
    p->binary = 1;
    if (MshBinaryStart(p) || MshReadInt(p, &one)) return 1;
    if (one != 1) return MshFail(p, "binary file written with another byte order");
  } else if (memchr(p->buf, 0, p->len)) {
    return MshFail(p, "file contains NUL bytes but its header says ASCII (corrupted, or binary with a wrong header?)");
  }
  return MshExpect(p, "$EndMeshFormat");
}

/* an unknown section ($Periodic, $NodeData, ...): skip to its end tag */
static int SkipSection(Parser *p, const char *w)
{
  char        endtag[80];
  const char *q = NULL;
  size_t      n;
  snprintf(endtag, sizeof(endtag), "$End%s", w + 1);
  n = strlen(endtag);
  for (size_t k = p->pos; k + n <= p->len && !q; k++) /* binary sections may hold NUL bytes */
    if (p->buf[k] == '$' && !memcmp(p->buf + k, endtag, n)) q = p->buf + k;
  if (!q) return MshFail(p, "section %.40s has no %.40s", w, endtag);
  p->pos = (size_t)(q - p->buf) + n;
  return 0;
}

static int CmpLong(const void *a, const void *b)
{
  long x = *(const long *)a, y = *(const long *)b;
  return (x > y) - (x < y);
}

/* two quads of one tag would make every message naming it ambiguous */
static int CheckQuadTags(Parser *p, const MshMesh *m)
{
  long *t;
  if (m->nquad < 2 || !m->quadtag) return 0;
  if (!(t = (long *)malloc((size_t)m->nquad * sizeof(long)))) return MshFail(p, "out of memory checking %ld element tags", m->nquad);
  memcpy(t, m->quadtag, (size_t)m->nquad * sizeof(long));
  qsort(t, (size_t)m->nquad, sizeof(long), CmpLong);
  for (long i = 1; i < m->nquad; i++)
    if (t[i] == t[i - 1]) {
      snprintf(p->err, p->errlen, "mesh file '%s': element tag %ld is used by two quadrilaterals", p->path, t[i]);
      p->failed = 1;
      free(t);
      return 1;
    }
  free(t);
  return 0;
}

typedef struct {
  double      version;
  NodeMap     map;
  EntityTable ents;
  Caps        caps;
  int         have_nodes, have_elems;
} Sections;

/* one section, named w (its keyword already read) */
static int ReadSection(Parser *p, MshMesh *m, Sections *s, const char *w)
{
  int v41 = s->version > 4;
  if (!strcmp(w, "$PhysicalNames")) {
    if (m->phys) return MshFail(p, "second $PhysicalNames section");
    return MshReadPhysicalNames(p, m);
  }
  if (!strcmp(w, "$Entities") && v41) {
    if (s->ents.e) return MshFail(p, "second $Entities section");
    return MshReadEntities41(p, &s->ents);
  }
  if (!strcmp(w, "$Nodes")) {
    if (s->have_nodes) return MshFail(p, "second $Nodes section");
    s->have_nodes = 1;
    return v41 ? MshReadNodes41(p, m, &s->map) : MshReadNodes22(p, m, &s->map);
  }
  if (!strcmp(w, "$Elements")) {
    if (!s->have_nodes) return MshFail(p, "$Elements before $Nodes");
    if (s->have_elems) return MshFail(p, "second $Elements section");
    if (v41 && !s->ents.e) return MshFail(p, "$Elements without $Entities");
    s->have_elems = 1;
    if (v41 ? MshReadElements41(p, m, &s->map, &s->ents, &s->caps) : MshReadElements22(p, m, &s->map, &s->caps)) return 1;
    return CheckQuadTags(p, m);
  }
  if (w[0] == '$' && strncmp(w, "$End", 4)) return SkipSection(p, w);
  return MshFail(p, "unexpected text '%.40s' between sections", w);
}

int MshRead(const char *path, MshMesh *m, char *err, size_t errlen)
{
  Parser   p;
  Sections s;
  char     w[64];
  int      rc = 1;

  memset(m, 0, sizeof(*m));
  memset(&p, 0, sizeof(p));
  memset(&s, 0, sizeof(s));
  p.path   = path;
  p.err    = err;
  p.errlen = errlen;
  if (LoadFile(&p) || ReadHeader(&p, &s.version)) goto done;
  while (1) {
    MshSkipSpace(&p);
    if (p.pos >= p.len) break;
    p.section = NULL;
    if (MshReadWord(&p, w, sizeof(w)) || ReadSection(&p, m, &s, w)) goto done;
  }
  if (!s.have_nodes || !s.have_elems) snprintf(err, errlen, "mesh file '%s': no %s section (truncated or not a gmsh mesh?)", path, !s.have_nodes ? "$Nodes" : "$Elements");
  else if (m->nquad == 0) snprintf(err, errlen, "mesh file '%s': no quadrilateral elements", path);
  else rc = 0;
done:
  free(s.map.t);
  free(s.map.direct);
  for (long i = 0; i < s.ents.n; i++) free(s.ents.e[i].physall);
  free(s.ents.e);
  free(p.buf);
  return rc;
}
