/* remesh.c - a scene's .geo meshed by gmsh's C API into an all-quad MshMesh,
 * optionally driven by a size field on a previous mesh (see remesh.h).
 *
 * The field goes to gmsh as its mesh-size callback (remesh_field.c evaluates
 * it), with every other size source (points, curvature, boundary extension, the
 * .geo's own fields) switched off: the field alone sets the size, on the curves
 * (contact surfaces included) as inside. Why not a post-processing view used as
 * background mesh: gmsh's search in the view misses points of a curved boundary
 * that bulge out of the previous (polygonal) mesh and gives them the largest
 * size; and a view cannot tell the two bodies apart where they touch. */
#define _GNU_SOURCE /* mkstemps, realpath */
#include "remesh.h"
#include "temprecord.h"
#include <gmshc.h>
#include <ctype.h>
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <signal.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

typedef struct {
  const char *geo;
  char       *err;
  size_t      errlen;
  int         failed;
  char        wrapper[PATH_MAX + 64]; /* temporary .geo that sets the numbers, or "" */
  int         slot;                   /* its entry in the temporary-file table, -1 if none */
  int         share;                  /* a worker meshing its share of the surfaces (Share) */
  int         groups;                 /* physical groups of the whole model, when a share */
} Ctx;

static double Now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int Fail(Ctx *c, const char *fmt, ...)
{
  char    where[PATH_MAX + 32];
  va_list ap;
  snprintf(where, sizeof(where), "remeshing '%s'", c->geo ? c->geo : "(null)");
  va_start(ap, fmt);
  MshKeepError(c->err, c->errlen, &c->failed, where, fmt, ap);
  va_end(ap);
  return 1;
}

/* gmsh's library is loaded by the server process (dlopen), not linked: it pulls
 * in some 80 libraries (OpenCASCADE, FLTK, ...) whose start-up every run of the
 * program would pay, remeshing or not, and the program itself never loads it. RTLD_DEEPBIND: their symbols are
 * looked up in their own dependencies first, not through the long list of
 * PETSc's libraries already loaded (most of the cost of the dlopen). */
#ifndef M2D_GMSH_LIBRARY
#define M2D_GMSH_LIBRARY "libgmsh.so.4.8"
#endif
#define GMSH_FUNCTIONS(X) \
  X(gmshFinalize) X(gmshFree) X(gmshInitialize) X(gmshLoggerGet) \
  X(gmshLoggerStart) X(gmshLoggerStop) X(gmshModelGetAdjacencies) X(gmshModelGetEntities) \
  X(gmshModelMeshGetEmbedded) X(gmshModelRemoveEntities) \
  X(gmshModelGetPhysicalGroups) X(gmshModelGetPhysicalGroupsForEntity) X(gmshModelGetPhysicalName) X(gmshModelMeshFieldAdd) \
  X(gmshModelMeshFieldSetAsBackgroundMesh) X(gmshModelMeshFieldSetString) X(gmshModelMeshGenerate) X(gmshModelMeshGetElements) \
  X(gmshModelMeshGetNodes) X(gmshModelMeshSetSizeCallback) X(gmshOpen) \
  X(gmshOptionSetNumber) X(gmshWrite)
static struct {
#define X(f) __typeof__(&f) f;
  GMSH_FUNCTIONS(X)
#undef X
} G;

/* in the server only (the program itself never loads gmsh): 0, or 1 with why in msg */
static int LoadGmsh(char *msg, size_t n)
{
  void *h;
  if (!(h = dlopen(M2D_GMSH_LIBRARY, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND))) return snprintf(msg, n, "cannot load gmsh's library: %s", dlerror()), 1;
#define X(f) \
  if (!(*(void **)&G.f = dlsym(h, #f))) return snprintf(msg, n, "gmsh's library %s has no function %s", M2D_GMSH_LIBRARY, #f), 1;
  GMSH_FUNCTIONS(X)
#undef X
  return 0; /* never closed: gmsh's libraries are not made to be unloaded */
}

/* gmsh reports errors through its logger (General.AbortOnError = 0 keeps its
 * parser usable after a syntax error): fail with the first error line logged. */
static int GmshError(Ctx *c, int ierr, const char *during)
{
  char **log = NULL, first[768] = "";
  size_t n = 0;
  int    e = 0;
  G.gmshLoggerGet(&log, &n, &e);
  for (size_t i = 0; i < n; i++) {
    if (!first[0] && !strncmp(log[i], "Error: ", 7)) snprintf(first, sizeof(first), "%s", log[i] + 7);
    G.gmshFree(log[i]);
  }
  G.gmshFree(log);
  if (first[0]) return Fail(c, "gmsh failed %s: %s", during, first);
  if (ierr) return Fail(c, "gmsh failed %s (no message)", during);
  return 0;
}

static int ValidName(const char *s)
{
  if (!s || !(*s == '_' || (*s >= 'A' && *s <= 'Z') || (*s >= 'a' && *s <= 'z'))) return 0;
  for (s++; *s; s++)
    if (!(*s == '_' || (*s >= 'A' && *s <= 'Z') || (*s >= 'a' && *s <= 'z') || (*s >= '0' && *s <= '9'))) return 0;
  return 1;
}

/* gmsh 4.8 cannot undo a .geo's Transfinite constraints, which would silently
 * override the field: a .geo that has some must skip them under m2d_size_field. */
static int CheckTransfinite(Ctx *c, const char *geo)
{
  FILE  *fp = fopen(geo, "rb");
  char  *text;
  long   n;
  int    bad = 0;
  if (!fp) return Fail(c, "cannot open the .geo file: %s", strerror(errno));
  if (fseek(fp, 0, SEEK_END) || (n = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET) || !(text = (char *)malloc((size_t)n + 1))) {
    fclose(fp);
    return Fail(c, "cannot read the .geo file");
  }
  text[fread(text, 1, (size_t)n, fp)] = 0;
  fclose(fp);
  bad = strstr(text, "Transfinite") && !strstr(text, "m2d_size_field");
  free(text);
  return bad ? Fail(c, "its Transfinite constraints would override the size field: put them in If (!Exists(m2d_size_field)) ... EndIf") : 0;
}

/* a regular file, or the reason it is not; 0 if it is one or is missing (gmsh says so) */
static const char *NotRegular(const char *path)
{
  struct stat st;
  if (stat(path, &st) || S_ISREG(st.st_mode)) return NULL;
  return S_ISDIR(st.st_mode) ? "a directory" : S_ISCHR(st.st_mode) ? "a character device" : S_ISBLK(st.st_mode) ? "a block device" : S_ISFIFO(st.st_mode) ? "a FIFO" : S_ISSOCK(st.st_mode) ? "a socket" : "not a file";
}

/* Include "F" and Merge "F" with a literal name, outside comments: F (relative
 * to the including file's directory, as gmsh resolves it) must not be a device,
 * FIFO or directory, which gmsh would read for ever; included files are scanned
 * in turn (depth 8). A name gmsh builds as it runs (StrCat, Sprintf) is not seen:
 * a .geo is a program, checked here only as far as it can be without running it. */
static int CheckIncludes(Ctx *c, const char *file, int depth)
{
  FILE  *fp = fopen(file, "rb");
  char  *t  = NULL, dir[PATH_MAX];
  long   n  = 0;
  int    rc = 0;
  const char *slash = strrchr(file, '/');
  if (!fp) return 0;
  if (fseek(fp, 0, SEEK_END) || (n = ftell(fp)) < 0 || fseek(fp, 0, SEEK_SET) || !(t = (char *)malloc((size_t)n + 1))) {
    fclose(fp);
    return 0;
  }
  t[fread(t, 1, (size_t)n, fp)] = 0;
  fclose(fp);
  snprintf(dir, sizeof(dir), "%.*s", slash ? (int)(slash - file) : 1, slash ? file : ".");
  for (char *p = t; *p && !rc; p++) {
    int include = 0, merge = 0;
    if (p[0] == '/' && p[1] == '/') p = strchr(p, '\n') ? strchr(p, '\n') : p + strlen(p) - 1;
    else if (p[0] == '/' && p[1] == '*') p = strstr(p + 2, "*/") ? strstr(p + 2, "*/") + 1 : p + strlen(p) - 1;
    else if (*p == '"') p = strchr(p + 1, '"') ? strchr(p + 1, '"') : p + strlen(p) - 1;
    else if ((p == t || !(isalnum((unsigned char)p[-1]) || p[-1] == '_')) && ((include = !strncmp(p, "Include", 7)) || (merge = !strncmp(p, "Merge", 5)))) {
      char *q = p + (include ? 7 : 5), *e, name[PATH_MAX], full[2 * PATH_MAX];
      const char *why;
      while (*q == ' ' || *q == '\t') q++;
      if (*q != '"' || !(e = strchr(q + 1, '"')) || e - q - 1 >= (long)sizeof(name)) continue;
      snprintf(name, sizeof(name), "%.*s", (int)(e - q - 1), q + 1);
      snprintf(full, sizeof(full), name[0] == '/' ? "%s" : "%s/%s", name[0] == '/' ? name : dir, name);
      if ((why = NotRegular(full))) rc = Fail(c, "it %s '%s', which is not a regular file (%s)", include ? "includes" : "merges", name, why);
      else if (include && depth < 8) rc = CheckIncludes(c, full, depth + 1);
      p = e;
    }
  }
  free(t);
  return rc;
}

static int CheckInput(Ctx *c, const M2dRemeshInput *in)
{
  FILE       *fp;
  struct stat st;
  if (!in->geo) return Fail(c, "no .geo file given");
  /* gmsh would read a device or a FIFO for ever (-geo /dev/zero spun) */
  if (stat(in->geo, &st)) return Fail(c, "cannot open the .geo file: %s", strerror(errno));
  if (!S_ISREG(st.st_mode)) return Fail(c, "the .geo file is not a regular file (%s)", NotRegular(in->geo));
  if (!(fp = fopen(in->geo, "r"))) return Fail(c, "cannot open the .geo file: %s", strerror(errno));
  fclose(fp);
  if (CheckIncludes(c, in->geo, 0)) return 1;
  for (int i = 0; i < in->nnumber; i++) {
    if (!ValidName(in->names[i])) return Fail(c, "parameter name '%s' is not an identifier", in->names[i] ? in->names[i] : "(null)");
    if (!isfinite(in->values[i])) return Fail(c, "parameter '%s' is not a finite number", in->names[i]);
  }
  if (!in->prev && !in->hnode && !in->hcell) return 0;
  if (!in->prev || !in->prev->nquad || !!in->hnode == !!in->hcell) return Fail(c, "a size field needs the previous mesh and exactly one of sizes per node, sizes per cell");
  if (in->hmin < 0 || in->hmax < 0 || (in->hmax > 0 && in->hmin > in->hmax)) return Fail(c, "size clamp [%g, %g] is not valid", in->hmin, in->hmax);
  if (in->quads < M2D_QUADS_SUBDIVIDE || in->quads > M2D_QUADS_SIMPLE) return Fail(c, "unknown quad algorithm %d", (int)in->quads);
  {
    long n = in->hnode ? in->prev->nnode : in->prev->nquad;
    const double *h = in->hnode ? in->hnode : in->hcell;
    for (long i = 0; i < n; i++)
      if (!(h[i] > 0) || !isfinite(h[i])) return Fail(c, "size %g at %s %ld of the previous mesh is not a positive number", h[i], in->hnode ? "node" : "cell", i);
  }
  for (long q = 0; q < 4 * in->prev->nquad; q++)
    if (in->prev->quad[q] < 0 || in->prev->quad[q] >= in->prev->nnode) return Fail(c, "previous mesh: quad %ld has node %ld out of range", q / 4, in->prev->quad[q]);
  return CheckTransfinite(c, in->geo);
}

/* gmsh's -setnumber survives gmshFinalize (it would leak into later calls), and
 * 4.8 has no parser API: the numbers go in a wrapper .geo that defines them and
 * includes the scene's .geo, where DefineConstant keeps them and Exists sees them.
 * With a size field it also defines m2d_size_field (see remesh.h). */
static int WriteWrapper(Ctx *c, const M2dRemeshInput *in, char *path)
{
  static unsigned serial;
  char            abs[PATH_MAX];
  const char     *dir = getenv("TMPDIR");
  FILE           *fp  = NULL;
  int             fd  = -1;
  if (!realpath(in->geo, abs)) return Fail(c, "cannot resolve the path: %s", strerror(errno));
  if (strchr(abs, '"')) return Fail(c, "the path holds a double quote");
  /* recorded before it exists (temprecord.h): an interrupt removes it */
  for (int attempt = 0; attempt < 100 && fd < 0; attempt++) {
    snprintf(c->wrapper, sizeof(c->wrapper), "%s/m2d_remesh_%ld_%u.geo", dir && *dir ? dir : "/tmp", (long)getpid(), serial++);
    if ((c->slot = M2dTempRecordFile(c->wrapper)) < 0) break;
    if ((fd = open(c->wrapper, O_WRONLY | O_CREAT | O_EXCL, 0600)) < 0) M2dTempForgetFile(c->slot), c->slot = -1;
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0 || !(fp = fdopen(fd, "w"))) {
    Fail(c, "cannot create a temporary file '%s': %s", c->wrapper, c->slot < 0 && fd < 0 && errno == EEXIST ? "no free name" : c->slot < 0 && fd < 0 ? "the path is too long or too many temporaries" : strerror(errno));
    if (fd >= 0) close(fd), unlink(c->wrapper);
    M2dTempForgetFile(c->slot);
    c->slot       = -1;
    c->wrapper[0] = 0;
    return 1;
  }
  for (int i = 0; i < in->nnumber; i++) fprintf(fp, "%s = %.17g;\n", in->names[i], in->values[i]);
  if (in->prev) fprintf(fp, "m2d_size_field = 1;\n");
  fprintf(fp, "Include \"%s\";\n", abs);
  if (fclose(fp)) return Fail(c, "cannot write the temporary file '%s'", c->wrapper);
  snprintf(path, PATH_MAX + 64, "%s", c->wrapper);
  return 0;
}

static int SetOption(Ctx *c, const char *name, double v)
{
  int ierr = 0;
  G.gmshOptionSetNumber(name, v, &ierr);
  return ierr ? Fail(c, "gmsh rejected option %s = %g", name, v) : 0;
}

/* Which previous cells may size a point of entity (dim, tag): those of the
 * physical surfaces the entity bounds (up to 4, else any), so that each body is
 * sized by its own cells where the bodies touch. */
typedef struct {
  M2dRemeshField *field;
  double        fac;       /* 2 when triangles are split into quads afterwards */
  int           maxtag[3];
  int          *surf[3];   /* [4 tag + k]: physical surface tags, -1 padded; all -1: any */
  MshMesh       view;      /* prev with quadphys in the model's tags (ViewByName) */
  int          *quadphys;
} Driver;

/* The previous mesh's surfaces are named (prev->phys): its quads' tags become
 * the tags the .geo gives the surfaces of those names, so that a mesh from
 * anywhere (an earlier remeshing, a .msh of the same bodies) can drive the
 * field. A previous mesh without names keeps its tags. */
static int ViewByName(Ctx *c, const MshMesh *prev, Driver *d)
{
  int   *pg = NULL, ierr = 0, bad = 0;
  size_t npg = 0;
  d->view = *prev;
  if (!prev->nphys) return 0;
  if (!(d->quadphys = (int *)malloc((size_t)(prev->nquad + 1) * sizeof(int)))) return Fail(c, "out of memory");
  G.gmshModelGetPhysicalGroups(&pg, &npg, 2, &ierr);
  for (long q = 0; q < prev->nquad && !bad; q++) {
    const char *name = MshPhysicalName(prev, 2, prev->quadphys[q]);
    d->quadphys[q]   = -1;
    for (size_t i = 0; name && i + 1 < npg && d->quadphys[q] < 0; i += 2) {
      char *gn = NULL;
      G.gmshModelGetPhysicalName(2, pg[i + 1], &gn, &ierr);
      if (gn && !strcmp(gn, name)) d->quadphys[q] = pg[i + 1];
      G.gmshFree(gn);
    }
    if (d->quadphys[q] < 0) bad = Fail(c, "it has no physical surface '%s', a body of the mesh it is to refine", name ? name : "(unnamed)");
  }
  G.gmshFree(pg);
  d->view.quadphys = d->quadphys;
  return bad;
}

static void AddSurfaces(int dim, int tag, int s[4], int *over)
{
  int   *up = NULL, *down = NULL, *ph = NULL, ierr = 0;
  size_t nup = 0, ndown = 0, nph = 0;
  if (dim == 2) {
    G.gmshModelGetPhysicalGroupsForEntity(2, tag, &ph, &nph, &ierr);
    for (size_t i = 0; i < nph; i++) {
      int k = 0;
      while (k < 4 && s[k] >= 0 && s[k] != ph[i]) k++;
      if (k == 4) *over = 1;
      else s[k] = ph[i];
    }
    G.gmshFree(ph);
    return;
  }
  G.gmshModelGetAdjacencies(dim, tag, &up, &nup, &down, &ndown, &ierr);
  for (size_t i = 0; i < nup; i++) AddSurfaces(dim + 1, up[i], s, over);
  G.gmshFree(up), G.gmshFree(down);
}

static int BuildDriver(Ctx *c, Driver *d)
{
  for (int dim = 0; dim < 3; dim++) {
    int   *ents = NULL, ierr = 0;
    size_t nent = 0;
    G.gmshModelGetEntities(&ents, &nent, dim, &ierr);
    d->maxtag[dim] = 0;
    for (size_t e = 0; e + 1 < nent; e += 2)
      if (ents[e + 1] > d->maxtag[dim]) d->maxtag[dim] = ents[e + 1];
    if (!(d->surf[dim] = (int *)malloc(4 * ((size_t)d->maxtag[dim] + 1) * sizeof(int)))) {
      G.gmshFree(ents);
      return Fail(c, "out of memory");
    }
    for (int i = 0; i < 4 * (d->maxtag[dim] + 1); i++) d->surf[dim][i] = -1;
    for (size_t e = 0; e + 1 < nent; e += 2) {
      int *s = &d->surf[dim][4 * ents[e + 1]], over = 0;
      if (ents[e + 1] < 0) continue;
      AddSurfaces(dim, ents[e + 1], s, &over);
      if (over) s[0] = s[1] = s[2] = s[3] = -1;
    }
    G.gmshFree(ents);
  }
  return 0;
}

static double SizeCallback(int dim, int tag, double x, double y, double z, void *data)
{
  const Driver *d = (const Driver *)data;
  double        h = -1, v;
  (void)z;
  if (dim >= 0 && dim <= 2 && tag >= 0 && tag <= d->maxtag[dim])
    for (const int *s = &d->surf[dim][4 * tag], *e = s + 4; s < e && *s >= 0; s++)
      if ((v = M2dRemeshFieldEval(d->field, *s, x, y)) > 0 && (h < 0 || v < h)) h = v;
  if (h <= 0) h = M2dRemeshFieldEval(d->field, -1, x, y);
  return d->fac * h;
}

/* every cell split into quads after the recombination (Mesh.SubdivisionAlgorithm 1) */
static int Splits(M2dRemeshQuads quads)
{
  return quads == M2D_QUADS_SUBDIVIDE || quads == M2D_QUADS_SIMPLE;
}

/* The field as gmsh's mesh-size callback, and every other size source off: gmsh
 * takes the smallest of the callback, the background field, point sizes,
 * curvature and the model size, so the .geo's own field is replaced by a
 * constant larger than any size. */
static int SetSizeField(Ctx *c, const M2dRemeshInput *in, Driver *d)
{
  int ierr = 0, field;
  /* subdivision splits each triangle edge in two: triangles at 2h give quads at h */
  d->fac = Splits(in->quads) ? 2 : 1;
  if (ViewByName(c, in->prev, d)) return 1;
  if (M2dRemeshFieldCreate(&d->view, in->hnode, in->hcell, in->hmin, in->hmax, &d->field)) return Fail(c, "out of memory for the size field");
  if (BuildDriver(c, d)) return 1;
  field = G.gmshModelMeshFieldAdd("MathEval", -1, &ierr);
  if (!ierr) G.gmshModelMeshFieldSetString(field, "F", "1e22", &ierr);
  if (!ierr) G.gmshModelMeshFieldSetAsBackgroundMesh(field, &ierr);
  if (!ierr) G.gmshModelMeshSetSizeCallback(SizeCallback, d, &ierr);
  if (ierr || GmshError(c, ierr, "to set the size field")) return 1;
  return SetOption(c, "Mesh.MeshSizeFromPoints", 0) || SetOption(c, "Mesh.MeshSizeFromCurvature", 0) || SetOption(c, "Mesh.MeshSizeExtendFromBoundary", 0) || SetOption(c, "Mesh.MeshSizeFactor", 1) ||
         SetOption(c, "Mesh.MeshSizeMin", 0) || SetOption(c, "Mesh.MeshSizeMax", 1e22) || SetOption(c, "Mesh.ElementOrder", 1) || SetOption(c, "Mesh.Algorithm", 6) || SetOption(c, "Mesh.RecombineAll", 1) ||
         SetOption(c, "Mesh.RecombinationAlgorithm", in->quads == M2D_QUADS_FULLQUAD ? 3 : in->quads == M2D_QUADS_SIMPLE ? 0 : 1) || SetOption(c, "Mesh.SubdivisionAlgorithm", Splits(in->quads) ? 1 : 0);
}

/* ---------- the mesh out of gmsh ---------- */
typedef struct {
  long  *pos; /* gmsh node tag -> position in gmsh's node list, -1 if none */
  size_t maxtag;
  long   qcap, lcap, pcap; /* allocated quads, lines, points */
} Tables;

static long Pos(const Tables *t, size_t tag)
{
  return tag <= t->maxtag ? t->pos[tag] : -1;
}

static int Resize(Ctx *c, void **a, long n, size_t size)
{
  void *b = realloc(*a, (size_t)n * size);
  if (!b) return Fail(c, "out of memory");
  *a = b;
  return 0;
}

/* capacity for need entries, doubling */
static long NewCap(long cap, long need)
{
  long nc = cap ? cap : 256;
  if (need <= cap) return cap;
  while (nc < need) nc *= 2;
  return nc;
}

static int AddElement(Ctx *c, MshMesh *m, Tables *t, int dim, const long *node, size_t tag, int phys)
{
  long nc;
  if (dim == 2) {
    if ((nc = NewCap(t->qcap, m->nquad + 1)) > t->qcap) {
      if (Resize(c, (void **)&m->quad, 4 * nc, sizeof(long)) || Resize(c, (void **)&m->quadtag, nc, sizeof(long)) || Resize(c, (void **)&m->quadphys, nc, sizeof(int))) return 1;
      t->qcap = nc;
    }
    memcpy(&m->quad[4 * m->nquad], node, 4 * sizeof(long));
    m->quadtag[m->nquad]    = (long)tag;
    m->quadphys[m->nquad++] = phys;
  } else if (dim == 1) {
    if ((nc = NewCap(t->lcap, m->nline + 1)) > t->lcap) {
      if (Resize(c, (void **)&m->line, 2 * nc, sizeof(long)) || Resize(c, (void **)&m->linephys, nc, sizeof(int))) return 1;
      t->lcap = nc;
    }
    memcpy(&m->line[2 * m->nline], node, 2 * sizeof(long));
    m->linephys[m->nline++] = phys;
  } else {
    if ((nc = NewCap(t->pcap, m->npoint + 1)) > t->pcap) {
      if (Resize(c, (void **)&m->point, nc, sizeof(long)) || Resize(c, (void **)&m->pointphys, nc, sizeof(int))) return 1;
      t->pcap = nc;
    }
    m->point[m->npoint]       = node[0];
    m->pointphys[m->npoint++] = phys;
  }
  return 0;
}

/* Elements of one entity of dimension dim (one copy per physical group for
 * curves and points, as MshRead keeps them); node numbers are gmsh positions. */
static int TakeEntity(Ctx *c, MshMesh *m, Tables *t, int dim, int tag, const int *ph, size_t nph)
{
  int     *types = NULL, ierr = 0, rc = 0;
  int      want = dim == 2 ? 3 : dim == 1 ? 1 : 15, nn = dim == 2 ? 4 : dim == 1 ? 2 : 1;
  size_t   ntypes = 0, **et = NULL, *etn = NULL, etnn = 0, **nt = NULL, *ntn = NULL, ntnn = 0;
  G.gmshModelMeshGetElements(&types, &ntypes, &et, &etn, &etnn, &nt, &ntn, &ntnn, dim, tag, &ierr);
  if (ierr) rc = GmshError(c, ierr, "to return the elements");
  for (size_t k = 0; k < ntypes && !rc; k++) {
    if (types[k] != want) {
      const char *what = dim == 2 ? (types[k] == 2 ? "a triangle is left" : "cells are not 4-node quadrilaterals") : "boundary elements are not first order";
      rc = Fail(c, "%s in %s %d (gmsh element type %d)", what, dim == 2 ? "surface" : dim == 1 ? "curve" : "point", tag, types[k]);
    }
    for (size_t e = 0; e < etn[k] && !rc; e++) {
      long node[4];
      for (int j = 0; j < nn && !rc; j++)
        if ((node[j] = Pos(t, nt[k][nn * e + j])) < 0) rc = Fail(c, "element %zu uses an unknown node", et[k][e]);
      for (size_t g = 0; g < (dim == 2 || !nph ? 1 : nph) && !rc; g++) rc = AddElement(c, m, t, dim, node, et[k][e], nph ? ph[g] : -1);
    }
  }
  for (size_t k = 0; k < ntypes; k++) {
    G.gmshFree(et[k]);
    G.gmshFree(nt[k]);
  }
  G.gmshFree(types), G.gmshFree(et), G.gmshFree(etn), G.gmshFree(nt), G.gmshFree(ntn);
  return rc;
}

static int TakePhysicalNames(Ctx *c, MshMesh *m)
{
  int   *pg = NULL, ierr = 0;
  size_t npg = 0;
  G.gmshModelGetPhysicalGroups(&pg, &npg, -1, &ierr);
  if (ierr) return GmshError(c, ierr, "to list the physical groups");
  if (!(m->phys = (MshPhysical *)calloc(npg / 2 + 1, sizeof(MshPhysical)))) {
    G.gmshFree(pg);
    return Fail(c, "out of memory");
  }
  for (size_t i = 0; i + 1 < npg; i += 2) {
    char        *name = NULL;
    MshPhysical *p    = &m->phys[m->nphys++];
    G.gmshModelGetPhysicalName(pg[i], pg[i + 1], &name, &ierr);
    p->dim = pg[i];
    p->tag = pg[i + 1];
    snprintf(p->name, sizeof(p->name), "%s", name ? name : "");
    G.gmshFree(name);
  }
  G.gmshFree(pg);
  return 0;
}

/* The nodes the elements use, in one plane z = constant (up to round-off
 * relative to the mesh's size, as MshRead's rule): else dropping z would
 * change the geometry. Returns 1 (with the message) if they are not. */
static int Plane(Ctx *c, const long *renum, const double *coord, size_t nnode)
{
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300}, size;
  size_t zlo = nnode, zhi = nnode; /* the nodes of the lowest and highest z */
  for (size_t i = 0; i < nnode; i++) {
    if (renum[i] < 0) continue;
    for (int d = 0; d < 2; d++) lo[d] = fmin(lo[d], coord[3 * i + d]), hi[d] = fmax(hi[d], coord[3 * i + d]);
    if (zlo == nnode || coord[3 * i + 2] < coord[3 * zlo + 2]) zlo = i;
    if (zhi == nnode || coord[3 * i + 2] > coord[3 * zhi + 2]) zhi = i;
  }
  if (zlo == nnode) return 0;
  size = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), fmax(fabs(coord[3 * zlo + 2]), fabs(coord[3 * zhi + 2])));
  if (!(coord[3 * zhi + 2] - coord[3 * zlo + 2] > 1e-12 * size)) return 0;
  return Fail(c, "it is not plane: gmsh put the node at (%g, %g) at z = %g and the one at (%g, %g) at z = %g (mortar2d meshes plane geometry: every point at one z)", coord[3 * zlo], coord[3 * zlo + 1], coord[3 * zlo + 2], coord[3 * zhi], coord[3 * zhi + 1], coord[3 * zhi + 2]);
}

/* Keep the nodes the elements use, numbered in gmsh's order (that of its .msh). */
static int Compact(Ctx *c, MshMesh *m, const double *coord, size_t nnode)
{
  long *renum = (long *)malloc((nnode + 1) * sizeof(long)), n = 0;
  if (!renum) return Fail(c, "out of memory");
  for (size_t i = 0; i < nnode; i++) renum[i] = -1;
  for (long i = 0; i < 4 * m->nquad; i++) renum[m->quad[i]] = 0;
  for (long i = 0; i < 2 * m->nline; i++) renum[m->line[i]] = 0;
  for (long i = 0; i < m->npoint; i++) renum[m->point[i]] = 0;
  if (Plane(c, renum, coord, nnode)) {
    free(renum);
    return 1;
  }
  for (size_t i = 0; i < nnode; i++)
    if (!renum[i]) renum[i] = n++;
  if (!(m->xy = (double *)malloc((size_t)(n ? n : 1) * 2 * sizeof(double)))) {
    free(renum);
    return Fail(c, "out of memory");
  }
  for (size_t i = 0; i < nnode; i++)
    if (renum[i] >= 0) {
      m->xy[2 * renum[i]]     = coord[3 * i];
      m->xy[2 * renum[i] + 1] = coord[3 * i + 1];
    }
  m->nnode = n;
  for (long i = 0; i < 4 * m->nquad; i++) m->quad[i] = renum[m->quad[i]];
  for (long i = 0; i < 2 * m->nline; i++) m->line[i] = renum[m->line[i]];
  for (long i = 0; i < m->npoint; i++) m->point[i] = renum[m->point[i]];
  free(renum);
  return 0;
}

/* Surfaces in no physical group are left out when the model has groups, as
 * gmsh's .msh leaves them out (Mesh.SaveAll = 0). */
static int TakeMesh(Ctx *c, MshMesh *m)
{
  size_t   *tags = NULL, ntag = 0, ncoord = 0, npar = 0;
  double   *coord = NULL, *par = NULL;
  int       ierr = 0, rc = 0;
  Tables    t = {NULL, 0, 0, 0, 0};
  if (TakePhysicalNames(c, m)) return 1;
  if (!c->share) c->groups = m->nphys;
  G.gmshModelMeshGetNodes(&tags, &ntag, &coord, &ncoord, &par, &npar, -1, -1, 0, 0, &ierr);
  if (ierr) return GmshError(c, ierr, "to return the nodes");
  for (size_t i = 0; i < ntag; i++)
    if (tags[i] > t.maxtag) t.maxtag = tags[i];
  if (!(t.pos = (long *)malloc((t.maxtag + 1) * sizeof(long)))) rc = Fail(c, "out of memory");
  for (size_t i = 0; !rc && i <= t.maxtag; i++) t.pos[i] = -1;
  for (size_t i = 0; !rc && i < ntag; i++) t.pos[tags[i]] = (long)i;
  for (int dim = 2; dim >= 0 && !rc; dim--) {
    int   *ents = NULL;
    size_t nent = 0;
    G.gmshModelGetEntities(&ents, &nent, dim, &ierr);
    for (size_t e = 0; e + 1 < nent && !rc; e += 2) {
      int   *ph = NULL;
      size_t nph = 0;
      G.gmshModelGetPhysicalGroupsForEntity(dim, ents[e + 1], &ph, &nph, &ierr);
      if (nph || (!c->groups && dim == 2)) rc = TakeEntity(c, m, &t, dim, ents[e + 1], ph, nph);
      G.gmshFree(ph);
    }
    G.gmshFree(ents);
  }
  if (!rc && !m->nquad && !c->share) rc = Fail(c, "the mesh has no quadrilaterals"); /* a share: checked on the joined mesh */
  if (!rc) rc = Compact(c, m, coord, ntag);
  free(t.pos);
  G.gmshFree(tags), G.gmshFree(coord), G.gmshFree(par);
  return rc;
}

/* corner k: Jacobian of the bilinear map = cross product of the two edges */
static void Corner(const MshMesh *m, long q, int k, double *jac, double *deg)
{
  const double *p = &m->xy[2 * m->quad[4 * q + k]], *a = &m->xy[2 * m->quad[4 * q + (k + 1) % 4]], *b = &m->xy[2 * m->quad[4 * q + (k + 3) % 4]];
  double        u[2] = {a[0] - p[0], a[1] - p[1]}, v[2] = {b[0] - p[0], b[1] - p[1]};
  *jac = u[0] * v[1] - u[1] * v[0];
  *deg = atan2(*jac, u[0] * v[0] + u[1] * v[1]) * 180 / M_PI;
}

void M2dQuadQualityCompute(const MshMesh *m, M2dQuadQuality *q)
{
  q->nquad     = m->nquad;
  q->min_angle = 360, q->max_angle = -360, q->min_jratio = 1, q->nbad = 0;
  for (long e = 0; e < m->nquad; e++) {
    double jmin = 1e300, jmax = -1e300, amin = 360, amax = -360, j, a;
    for (int k = 0; k < 4; k++) {
      Corner(m, e, k, &j, &a);
      if (j < jmin) jmin = j;
      if (j > jmax) jmax = j;
      if (a < amin) amin = a;
      if (a > amax) amax = a;
    }
    if (amin < q->min_angle) q->min_angle = amin;
    if (amax > q->max_angle) q->max_angle = amax;
    if (jmax > 0 && jmin / jmax < q->min_jratio) q->min_jratio = jmin / jmax;
    if (jmax <= 0) q->min_jratio = -1;
    if (amin < 30 || amax > 150) q->nbad++;
  }
}

/* every quad counter-clockwise (a clockwise curve loop gives clockwise quads),
 * then convex: all corner Jacobians positive, as mesh.c requires */
static int Orient(Ctx *c, MshMesh *m)
{
  for (long q = 0; q < m->nquad; q++) {
    long  *n = &m->quad[4 * q];
    double area = 0, j, a;
    for (int k = 0; k < 4; k++) area += m->xy[2 * n[k]] * m->xy[2 * n[(k + 1) % 4] + 1] - m->xy[2 * n[(k + 1) % 4]] * m->xy[2 * n[k] + 1];
    if (area < 0) {
      long s = n[1];
      n[1]   = n[3];
      n[3]   = s;
    }
    for (int k = 0; k < 4; k++) {
      Corner(m, q, k, &j, &a);
      if (!(j > 0)) {
        const char *pn = MshPhysicalName(m, 2, m->quadphys[q]);
        return Fail(c, "gmsh made a non-convex or degenerate quadrilateral (element %ld%s%s%s, corner Jacobian %g)", m->quadtag[q], pn ? " in '" : "", pn ? pn : "", pn ? "'" : "", j);
      }
    }
  }
  return 0;
}

static int Write(Ctx *c, const char *path)
{
  int ierr = 0;
  if (SetOption(c, "Mesh.MshFileVersion", 4.1) || SetOption(c, "Mesh.Binary", 0)) return 1;
  G.gmshWrite(path, &ierr);
  return GmshError(c, ierr, "to write the mesh file");
}

/* The recombination (Blossom) prints warnings with printf, past General.Terminal:
 * stdout goes to /dev/null while gmsh meshes, unless verbose. */
static void Quiet(int on, int *saved)
{
  int null;
  fflush(stdout);
  if (on && *saved < 0 && (null = open("/dev/null", O_WRONLY)) >= 0) {
    *saved = dup(STDOUT_FILENO);
    if (*saved >= 0) dup2(null, STDOUT_FILENO);
    close(null);
  } else if (!on && *saved >= 0) {
    dup2(*saved, STDOUT_FILENO);
    close(*saved);
    *saved = -1;
  }
}

/* ---------- the surfaces shared between two workers ----------
 * With a size field the model's surfaces are split into connected groups
 * (surfaces with a curve or point in common, or what is embedded in them, stay
 * together: their common nodes must be one), and the groups are dealt to
 * M2D_SHARES workers by the cells they are expected to get (the previous cells'
 * area over the new size squared, heaviest group first, each to the lightest
 * share); each worker removes the entities of the others and meshes the rest.
 * The two bodies of a scene are thus meshed at once on two cores, each by a gmsh
 * of its own on one thread (the same meshes every run); the parent joins the
 * shares in order (Join). One group: the first share meshes it all. */
#define M2D_SHARES 2

typedef struct {
  long  *key; /* (dim, tag) of the entities in the closure of each surface */
  size_t nkey;
} Closure;

static long Key(int dim, int tag)
{
  return (long)dim << 32 | (long)(unsigned)tag;
}

static int Has(const Closure *cl, long k)
{
  for (size_t i = 0; i < cl->nkey; i++)
    if (cl->key[i] == k) return 1;
  return 0;
}

static int AddKey(Ctx *c, Closure *cl, long k)
{
  long *b;
  if (Has(cl, k)) return 0;
  if (!(b = (long *)realloc(cl->key, (cl->nkey + 1) * sizeof(long)))) return Fail(c, "out of memory");
  cl->key           = b;
  cl->key[cl->nkey++] = k;
  return 0;
}

/* an entity's points, or itself and its points: its curves' points too */
static int AddDown(Ctx *c, Closure *cl, int dim, int tag)
{
  int   *up = NULL, *down = NULL, ierr = 0, rc;
  size_t nup = 0, ndown = 0;
  if ((rc = AddKey(c, cl, Key(dim, tag))) || dim == 0) return rc;
  G.gmshModelGetAdjacencies(dim, tag, &up, &nup, &down, &ndown, &ierr);
  for (size_t i = 0; i < ndown && !rc; i++) rc = AddDown(c, cl, dim - 1, down[i]);
  G.gmshFree(up), G.gmshFree(down);
  return rc;
}

static int Root(int *parent, int i)
{
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

/* a curve or point in common */
static int Shared(const Closure *a, const Closure *b)
{
  for (size_t i = 0; i < a->nkey; i++)
    if ((int)(a->key[i] >> 32) < 2 && Has(b, a->key[i])) return 1;
  return 0;
}

/* Keep share `share` of the model's surfaces (and what bounds or is embedded
 * in them; an entity of no surface stays with share 0), remove the rest;
 * *empty when nothing is left to mesh here. */
static int Share(Ctx *c, Driver *d, int share, int *empty)
{
  int     *ents = NULL, *pg = NULL, *parent = NULL, *owner = NULL, *to = NULL, ierr = 0, rc = 0, ncomp = 0;
  size_t   nent = 0, npg = 0, ns = 0, nrem = 0;
  Closure *cl = NULL;
  double  *weight = NULL, load[M2D_SHARES] = {0};
  int     *rem = NULL;
  *empty = 0;
  G.gmshModelGetPhysicalGroups(&pg, &npg, -1, &ierr);
  G.gmshFree(pg);
  c->share = 1, c->groups = (int)(npg / 2);
  G.gmshModelGetEntities(&ents, &nent, 2, &ierr);
  ns = nent / 2;
  if (!(cl = (Closure *)calloc(ns + 1, sizeof(Closure))) || !(parent = (int *)malloc((ns + 1) * sizeof(int))) || !(owner = (int *)malloc((ns + 1) * sizeof(int))) || !(weight = (double *)calloc(ns + 1, sizeof(double))) || !(to = (int *)calloc(ns + 1, sizeof(int)))) rc = Fail(c, "out of memory");
  for (size_t i = 0; i < ns && !rc; i++) { /* each surface's closure: boundary and embedded entities, down to points */
    int   *emb = NULL;
    size_t nemb = 0;
    parent[i] = (int)i;
    rc        = AddDown(c, &cl[i], 2, ents[2 * i + 1]);
    G.gmshModelMeshGetEmbedded(2, ents[2 * i + 1], &emb, &nemb, &ierr);
    for (size_t k = 0; k + 1 < nemb && !rc; k += 2) rc = AddDown(c, &cl[i], emb[k], emb[k + 1]);
    G.gmshFree(emb);
  }
  for (size_t i = 0; i < ns && !rc; i++)
    for (size_t j = i + 1; j < ns; j++)
      if (Root(parent, (int)i) != Root(parent, (int)j) && Shared(&cl[i], &cl[j])) parent[Root(parent, (int)j)] = Root(parent, (int)i);
  for (size_t i = 0; i < ns && !rc; i++) owner[i] = Root(parent, (int)i) == (int)i ? ncomp++ : -1; /* groups numbered in the order of their roots */
  for (size_t i = 0; i < ns && !rc; i++) owner[i] = owner[Root(parent, (int)i)];
  for (long q = 0; q < d->view.nquad && !rc && ncomp > 1; q++) { /* the cells each group is expected to get */
    const long *n  = &d->view.quad[4 * q];
    double      a  = 0, x = 0, y = 0, h;
    int         ph = d->view.quadphys ? d->view.quadphys[q] : -1;
    size_t      i  = 0;
    for (int k = 0; k < 4; k++) {
      const double *p = &d->view.xy[2 * n[k]], *r = &d->view.xy[2 * n[(k + 1) % 4]];
      a += 0.5 * (p[0] * r[1] - r[0] * p[1]), x += 0.25 * p[0], y += 0.25 * p[1];
    }
    while (i < ns && ph >= 0 && !(ents[2 * i + 1] <= d->maxtag[2] && (d->surf[2][4 * ents[2 * i + 1]] == ph || d->surf[2][4 * ents[2 * i + 1] + 1] == ph || d->surf[2][4 * ents[2 * i + 1] + 2] == ph || d->surf[2][4 * ents[2 * i + 1] + 3] == ph))) i++;
    h = M2dRemeshFieldEval(d->field, ph, x, y);
    if (h > 0) weight[owner[i < ns ? i : 0]] += fabs(a) / (h * h);
  }
  for (int g = 0; g < ncomp && !rc; g++) { /* heaviest group first (the first of equals), to the lightest share (the first of equals) */
    int best = -1, k = 0;
    for (int i = 0; i < ncomp; i++)
      if (weight[i] >= 0 && (best < 0 || weight[i] > weight[best])) best = i;
    for (int j = 1; j < M2D_SHARES; j++)
      if (load[j] < load[k]) k = j;
    load[k] += weight[best] + 1e-300;
    weight[best] = -1, to[best] = k;
  }
  if (!rc && !(rem = (int *)malloc(2 * (nent + 1) * sizeof(int)))) rc = Fail(c, "out of memory");
  for (size_t i = 0; i < ns && !rc; i++) {
    int mine = to[owner[i]] == share;
    if (!mine) rem[2 * nrem] = 2, rem[2 * nrem++ + 1] = ents[2 * i + 1];
  }
  *empty = !rc && nrem == ns;
  for (int dim = 1; dim >= 0 && !rc; dim--) { /* curves and points: those of a surface go with it, the others with share 0 */
    int   *low = NULL;
    size_t nlow = 0;
    G.gmshModelGetEntities(&low, &nlow, dim, &ierr);
    for (size_t e = 0; e + 1 < nlow; e += 2) {
      size_t i = 0;
      int    mine;
      while (i < ns && !Has(&cl[i], Key(dim, low[e + 1]))) i++;
      mine = (i < ns ? to[owner[i]] : 0) == share;
      if (!mine) {
        int *b = (int *)realloc(rem, 2 * (nrem + 1) * sizeof(int));
        if (!b) {
          rc = Fail(c, "out of memory");
          break;
        }
        rem = b, rem[2 * nrem] = dim, rem[2 * nrem++ + 1] = low[e + 1];
      }
    }
    G.gmshFree(low);
  }
  if (!rc && nrem) {
    G.gmshModelRemoveEntities(rem, 2 * nrem, 0, &ierr);
    if (ierr) rc = GmshError(c, ierr, "to leave out the other worker's surfaces");
  }
  for (size_t i = 0; cl && i < ns; i++) free(cl[i].key);
  free(cl), free(parent), free(owner), free(weight), free(to), free(rem);
  G.gmshFree(ents);
  return rc;
}

/* share: this worker's share of the surfaces (0 .. M2D_SHARES - 1), -1: all */
static int Run(Ctx *c, const M2dRemeshInput *in, const char *geo, Driver *d, MshMesh *out, M2dRemeshStats *st, double t0, int share)
{
  int  ierr = 0, *ents = NULL, saved = -1;
  size_t nent = 0;
  if (SetOption(c, "General.Terminal", in->verbose ? 1 : 0) || SetOption(c, "General.Verbosity", in->verbose ? 4 : 2) || SetOption(c, "General.AbortOnError", 0) || SetOption(c, "General.NumThreads", 1) ||
      SetOption(c, "Mesh.MaxNumThreads1D", 1) || SetOption(c, "Mesh.MaxNumThreads2D", 1) || SetOption(c, "Mesh.MaxNumThreads3D", 1)) return 1; /* one thread: the same mesh every run */
  G.gmshLoggerStart(&ierr);
  G.gmshOpen(geo, &ierr);
  if (GmshError(c, ierr, "to read it")) return 1;
  G.gmshModelGetEntities(&ents, &nent, 2, &ierr);
  G.gmshFree(ents);
  if (!nent) return Fail(c, "it defines no surface");
  if ((in->hnode || in->hcell) && SetSizeField(c, in, d)) return 1;
  if (share >= 0) {
    int empty;
    if (Share(c, d, share, &empty)) return 1;
    if (empty) return 0; /* nothing to mesh here: an empty share */
  }
  st->seconds_open = Now() - t0;
  Quiet(!in->verbose, &saved);
  G.gmshModelMeshGenerate(2, &ierr);
  Quiet(0, &saved);
  if (GmshError(c, ierr, "to mesh it")) return 1;
  st->seconds_generate = Now() - t0 - st->seconds_open;
  if (in->write_msh && Write(c, in->write_msh)) return 1;
  return TakeMesh(c, out) || Orient(c, out);
}

/* ---------- gmsh in a server process ----------
 * gmsh 4.8 crashes on some inputs (measured by tests/test_fuzz_geo.py: a
 * double free on binary garbage, a segmentation fault with Mesh.Algorithm 8
 * or with coordinates of 1e300), and a crash inside the program ended it with
 * PETSc's signal trace. gmsh therefore runs outside the program's process, and
 * a crash is one line. The first call forks one server (no MPI or PETSc call
 * there, none of the parent's signal handlers or open files besides stdin,
 * stdout and stderr), which initialises gmsh once and then, for each request
 * read from a socket, forks a worker of its own (with a size field, one per
 * share of the surfaces, at once: Share) that meshes and answers: every
 * mesh is made by a gmsh just out of gmshInitialize, as when each remeshing
 * had a process of its own (the same meshes to the bit), but the fork is of
 * the small server rather than of the program with its solver in memory, and
 * gmsh is initialised once. A worker's crash is told to the parent by the
 * server (which lives on; the first failed share's, when shared); the server's own end (killed) is one line too, on
 * the request that finds it gone and on every later one. The server and its
 * workers die with the parent (PR_SET_PDEATHSIG; an interrupt ends them all),
 * the server also when the parent closes the socket (at exit); the temporary
 * .geo is the parent's (recorded, removed by the parent). */
typedef struct {
  long nnode, nquad, nline, npoint, nphys;
  int  tagged;
} Counts;

typedef struct {
  int            failed;
  char           err[1024];
  M2dRemeshStats st;
  Counts         k;
} Reply;

typedef struct {
  double t0, hmin, hmax;
  int    verbose, quads, field; /* field: 0 none, 1 sizes per node, 2 per cell */
  long   lname, lopen, lmsh;    /* lengths of the strings that follow (with the NUL), 0: NULL */
  Counts k;                     /* the previous mesh, when field */
} Request;

typedef struct {
  int    kind; /* 0: the worker's reply follows; 1: it died of signal code; 2: it exited with status code; 3: fork failed, errno code */
  int    code;
  size_t nbytes;
} Frame;

/* a socket end, or a buffer already read */
typedef struct {
  int         fd;
  const char *buf;
  size_t      len, pos;
} In;

static int WriteAll(int fd, const void *p, size_t n)
{
  for (const char *b = (const char *)p; n;) {
    ssize_t w = send(fd, b, n, MSG_NOSIGNAL); /* a closed peer: EPIPE, no SIGPIPE */
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return 1;
    b += w, n -= (size_t)w;
  }
  return 0;
}

static int ReadAll(int fd, void *p, size_t n)
{
  for (char *b = (char *)p; n;) {
    ssize_t r = read(fd, b, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return 1;
    b += r, n -= (size_t)r;
  }
  return 0;
}

static int Get(In *in, void *p, size_t n)
{
  if (!in->buf) return ReadAll(in->fd, p, n);
  if (n > in->len - in->pos) return 1;
  memcpy(p, in->buf + in->pos, n);
  in->pos += n;
  return 0;
}

/* the mesh's arrays, in this order (both directions) */
#define MESH_ARRAYS(X, m, k) \
  X(m->xy, 2 * k.nnode, double) X(m->quad, 4 * k.nquad, long) X(m->quadtag, k.tagged ? k.nquad : 0, long) X(m->quadphys, k.nquad, int) \
  X(m->line, 2 * k.nline, long) X(m->linephys, k.nline, int) X(m->point, k.npoint, long) X(m->pointphys, k.npoint, int) X(m->phys, k.nphys, MshPhysical)

static Counts CountsOf(const MshMesh *m)
{
  Counts k = {m->nnode, m->nquad, m->nline, m->npoint, m->nphys, m->quadtag != NULL};
  return k;
}

static int PutMesh(int fd, const MshMesh *m, Counts k)
{
#define X(a, n, T) if ((n) > 0 && WriteAll(fd, a, (size_t)(n) * sizeof(T))) return 1;
  MESH_ARRAYS(X, m, k)
#undef X
  return 0;
}

/* counts checked first: the arrays are then allocated and read (MshFree frees them) */
static int GetMesh(In *in, MshMesh *m, Counts k)
{
  if (k.nnode < 0 || k.nquad < 0 || k.nline < 0 || k.npoint < 0 || k.nphys < 0 || k.nphys > INT_MAX || k.nnode > LONG_MAX / 64 || k.nquad > LONG_MAX / 64 || k.nline > LONG_MAX / 64 || k.npoint > LONG_MAX / 64) return 1;
  m->nnode = k.nnode, m->nquad = k.nquad, m->nline = k.nline, m->npoint = k.npoint, m->nphys = (int)k.nphys;
#define X(a, n, T) \
  if ((n) > 0 && (!(a = (T *)malloc((size_t)(n) * sizeof(T))) || Get(in, a, (size_t)(n) * sizeof(T)))) return 1;
  MESH_ARRAYS(X, m, k)
#undef X
  return 0;
}

static int Send(int fd, const Ctx *c, const MshMesh *m, const M2dRemeshStats *st)
{
  Reply r;
  memset(&r, 0, sizeof(r));
  r.failed = c->failed;
  snprintf(r.err, sizeof(r.err), "%s", c->err ? c->err : "");
  r.st = *st;
  if (!c->failed) r.k = CountsOf(m);
  if (WriteAll(fd, &r, sizeof(r))) return 1;
  return c->failed ? 0 : PutMesh(fd, m, r.k);
}

/* one worker's reply. 0: a mesh or gmsh's error in c; 1: a reply that cannot be read */
static int Receive(Ctx *c, In *in, MshMesh *m, M2dRemeshStats *st)
{
  Reply r;
  if (Get(in, &r, sizeof(r))) return 1;
  if (r.failed) {
    r.err[sizeof(r.err) - 1] = 0;
    if (c->err && c->errlen) snprintf(c->err, c->errlen, "%s", r.err);
    c->failed = 1;
    return 0;
  }
  if (GetMesh(in, m, r.k)) return 1;
  *st = r.st;
  return 0;
}

/* b appended to a (a's nodes first), the physical groups merged; b freed */
static int Join(Ctx *c, MshMesh *a, MshMesh *b)
{
  long   nn = a->nnode, tmax = 0;
  size_t np = 0;
  for (long q = 0; a->quadtag && q < a->nquad; q++) tmax = a->quadtag[q] > tmax ? a->quadtag[q] : tmax;
#define GROW(f, n, T) \
  if ((n) > 0) { \
    T *g = (T *)realloc(a->f, (size_t)(n) * sizeof(T)); \
    if (!g) return Fail(c, "out of memory"); \
    a->f = g; \
  }
  GROW(xy, 2 * (a->nnode + b->nnode), double)
  GROW(quad, 4 * (a->nquad + b->nquad), long)
  GROW(quadtag, a->quadtag && b->quadtag ? a->nquad + b->nquad : 0, long)
  GROW(quadphys, a->nquad + b->nquad, int)
  GROW(line, 2 * (a->nline + b->nline), long)
  GROW(linephys, a->nline + b->nline, int)
  GROW(point, a->npoint + b->npoint, long)
  GROW(pointphys, a->npoint + b->npoint, int)
  GROW(phys, a->nphys + b->nphys, MshPhysical)
#undef GROW
  if (b->nnode) memcpy(a->xy + 2 * nn, b->xy, (size_t)(2 * b->nnode) * sizeof(double));
  for (long i = 0; i < 4 * b->nquad; i++) a->quad[4 * a->nquad + i] = b->quad[i] + nn;
  for (long q = 0; q < b->nquad; q++) {
    if (a->quadtag && b->quadtag) a->quadtag[a->nquad + q] = b->quadtag[q] + tmax; /* element tags stay distinct */
    a->quadphys[a->nquad + q] = b->quadphys[q];
  }
  for (long i = 0; i < 2 * b->nline; i++) a->line[2 * a->nline + i] = b->line[i] + nn;
  for (long i = 0; i < b->nline; i++) a->linephys[a->nline + i] = b->linephys[i];
  for (long i = 0; i < b->npoint; i++) a->point[a->npoint + i] = b->point[i] + nn, a->pointphys[a->npoint + i] = b->pointphys[i];
  for (int i = 0; i < b->nphys; i++) {
    int k = 0;
    while (k < a->nphys && !(a->phys[k].dim == b->phys[i].dim && a->phys[k].tag == b->phys[i].tag)) k++;
    if (k == a->nphys) a->phys[a->nphys + (int)np++] = b->phys[i];
  }
  a->nnode += b->nnode, a->nquad += b->nquad, a->nline += b->nline, a->npoint += b->npoint, a->nphys += (int)np;
  MshFree(b);
  return 0;
}

static int PutString(int fd, const char *s, long n)
{
  return n > 0 && WriteAll(fd, s, (size_t)n);
}

static char *GetString(In *in, long n)
{
  char *s;
  if (n <= 0) return NULL;
  if (n > 1L << 20 || !(s = (char *)malloc((size_t)n))) _exit(1);
  if (Get(in, s, (size_t)n)) _exit(0); /* the parent is gone */
  s[n - 1] = 0;
  return s;
}

/* the worker: one mesh (or share, -1: all) by the gmsh the server initialised, the answer sent through fd */
static void Worker(const Request *q, int share, const char *name, const char *open_path, const char *msh, const MshMesh *prev, const double *h, const char *gmsh_err, int fd, pid_t server)
{
  char           err[1024] = "";
  Ctx            c;
  Driver         d;
  MshMesh        out;
  M2dRemeshStats st;
  M2dRemeshInput in;
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != server) _exit(1); /* the server is already gone */
  memset(&c, 0, sizeof(c));
  memset(&d, 0, sizeof(d));
  memset(&out, 0, sizeof(out));
  memset(&st, 0, sizeof(st));
  memset(&in, 0, sizeof(in));
  c.geo = name, c.err = err, c.errlen = sizeof(err), c.slot = -1;
  in.geo = name, in.verbose = q->verbose, in.quads = (M2dRemeshQuads)q->quads, in.hmin = q->hmin, in.hmax = q->hmax, in.write_msh = msh;
  if (q->field) in.prev = prev;
  if (q->field == 1) in.hnode = h;
  if (q->field == 2) in.hcell = h;
  if (!q->verbose) { /* gmsh's own prints, and glibc's on a crash: the parent's line says it */
    int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, STDOUT_FILENO), dup2(null, STDERR_FILENO), close(null);
  }
  if (gmsh_err[0]) Fail(&c, "%s", gmsh_err);
  else Run(&c, &in, open_path, &d, &out, &st, q->t0, share);
  _exit(Send(fd, &c, &out, &st) ? 3 : 0); /* no atexit handler of the parent's, no gmshFinalize: the process ends */
}

/* the worker's whole answer, read until it closes its end */
static char *Drain(int fd, size_t *n)
{
  size_t cap = 1 << 16;
  char  *b   = (char *)malloc(cap), *nb;
  *n         = 0;
  for (;;) {
    ssize_t r;
    if (!b) _exit(1);
    if (*n == cap) {
      if (!(nb = (char *)realloc(b, cap *= 2))) _exit(1);
      b = nb;
    }
    r = read(fd, b + *n, cap - *n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return b;
    *n += (size_t)r;
  }
}

/* the server: gmsh initialised once, a worker forked per request; ends when the parent closes the socket */
static void Server(int fd, pid_t parent)
{
  const int sigs[] = {SIGINT, SIGTERM, SIGHUP, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGPIPE, SIGCHLD, SIGUSR1, SIGUSR2, SIGALRM, SIGCONT, SIGTSTP, SIGQUIT};
  char     *argv[] = {(char *)"mortar2d", NULL};
  int       ierr   = 0;
  char      gmsh_err[PATH_MAX + 256] = "";
  pid_t     self   = getpid();
  sigset_t  none;
  for (size_t k = 0; k < sizeof(sigs) / sizeof(sigs[0]); k++) signal(sigs[k], SIG_DFL);
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, NULL); /* started early, the parent still held SIGINT, SIGTERM, SIGHUP (tempfile.h) */
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(1); /* the parent is already gone */
  if (fd > 3 && dup2(fd, 3) == 3) close(fd), fd = 3;
  if (fd >= 3) close_range((unsigned)fd + 1, ~0U, 0); /* the parent's files, sockets (MPI's) and pipes: not held open here */
  if (!LoadGmsh(gmsh_err, sizeof(gmsh_err))) {
    G.gmshInitialize(1, argv, 0, &ierr);
    if (ierr) snprintf(gmsh_err, sizeof(gmsh_err), "gmsh did not initialise");
  }
  for (;;) {
    In       in = {fd, NULL, 0, 0};
    Request  q;
    MshMesh  prev;
    double  *h = NULL;
    char    *name, *open_path, *msh, *buf[M2D_SHARES];
    int      w[M2D_SHARES][2], nshare;
    size_t   nbuf[M2D_SHARES];
    Frame    f;
    pid_t    pid[M2D_SHARES];
    memset(&prev, 0, sizeof(prev));
    if (ReadAll(fd, &q, sizeof(q))) _exit(0); /* the parent closed the socket, or is gone */
    name      = GetString(&in, q.lname);
    open_path = GetString(&in, q.lopen);
    msh       = GetString(&in, q.lmsh);
    if (q.field) {
      long nh = q.field == 1 ? q.k.nnode : q.k.nquad;
      if (GetMesh(&in, &prev, q.k) || nh < 0 || !(h = (double *)malloc((size_t)nh * sizeof(double) + 1)) || Get(&in, h, (size_t)nh * sizeof(double))) _exit(1);
    }
    /* with a size field and no .msh to write: the surfaces in M2D_SHARES shares, a worker each, at once */
    nshare = q.field && !msh ? M2D_SHARES : 1;
    memset(&f, 0, sizeof(f));
    for (int k = 0; k < nshare; k++) {
      pid[k] = -1, buf[k] = NULL, nbuf[k] = 0;
      if (f.kind) continue;
      if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, w[k])) f.kind = 3, f.code = errno;
      else if ((pid[k] = fork()) < 0) f.kind = 3, f.code = errno, close(w[k][0]), close(w[k][1]);
      else if (pid[k] == 0) {
        close(fd), close(w[k][0]);
        for (int j = 0; j < k; j++) close(w[j][0]);
        Worker(&q, nshare > 1 ? k : -1, name, open_path, msh, &prev, h, gmsh_err, w[k][1], self);
      } else close(w[k][1]);
    }
    for (int k = 0; k < nshare; k++) { /* every worker started is waited for; the first failure is told */
      int status = 0;
      if (pid[k] <= 0) continue;
      buf[k] = Drain(w[k][0], &nbuf[k]);
      close(w[k][0]);
      while (waitpid(pid[k], &status, 0) < 0 && errno == EINTR) { }
      if (f.kind) continue;
      if (WIFSIGNALED(status)) f.kind = 1, f.code = WTERMSIG(status);
      else if (!WIFEXITED(status) || WEXITSTATUS(status) || !nbuf[k]) f.kind = 2, f.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      else f.nbytes += nbuf[k];
    }
    if (f.kind) f.nbytes = 0;
    if (WriteAll(fd, &f, sizeof(f))) _exit(0);
    for (int k = 0; k < nshare && f.nbytes; k++)
      if (WriteAll(fd, buf[k], nbuf[k])) _exit(0);
    for (int k = 0; k < nshare; k++) free(buf[k]);
    free(h), free(name), free(open_path), free(msh);
    MshFree(&prev);
  }
}

static struct {
  pid_t pid, owner; /* the server, the process that started it (0: none yet) */
  int   fd;         /* the parent's end of the socket */
  char  gone[96];   /* why the server is gone, "" while it serves */
} S = {0, 0, -1, ""};

/* at exit: the server ends (it is idle: a request is answered before M2dRemesh returns) */
static void StopServer(void)
{
  if (!S.pid || getpid() != S.owner) return;
  if (S.fd >= 0) close(S.fd), S.fd = -1;
  if (!S.gone[0]) {
    kill(S.pid, SIGKILL);
    while (waitpid(S.pid, NULL, 0) < 0 && errno == EINTR) { }
    snprintf(S.gone, sizeof(S.gone), "stopped at exit");
  }
}

static int StartServer(Ctx *c)
{
  static int registered;
  int        sv[2];
  pid_t      pid, parent = getpid();
  if (!registered && atexit(StopServer)) return Fail(c, "cannot start gmsh's process: atexit failed");
  registered = 1;
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv)) return Fail(c, "cannot create a socket: %s", strerror(errno));
  fflush(stdout);
  fflush(stderr);
  if ((pid = fork()) < 0) {
    close(sv[0]), close(sv[1]);
    return Fail(c, "cannot start gmsh's process: %s", strerror(errno));
  }
  if (pid == 0) {
    close(sv[0]);
    Server(sv[1], parent);
  }
  close(sv[1]);
  S.pid = pid, S.owner = parent, S.fd = sv[0];
  return 0;
}

/* the socket found closed: the server is gone; why, once and for the later calls */
static int Gone(Ctx *c)
{
  int   status = 0;
  pid_t r;
  close(S.fd), S.fd = -1;
  while ((r = waitpid(S.pid, &status, 0)) < 0 && errno == EINTR) { }
  if (r < 0) snprintf(S.gone, sizeof(S.gone), "its status unknown: %s", strerror(errno));
  else if (WIFSIGNALED(status)) snprintf(S.gone, sizeof(S.gone), "signal SIG%s", sigabbrev_np(WTERMSIG(status)) ? sigabbrev_np(WTERMSIG(status)) : "?");
  else snprintf(S.gone, sizeof(S.gone), "exit status %d", WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  return Fail(c, "gmsh's process ended (%s)", S.gone);
}

static int InServer(Ctx *c, const M2dRemeshInput *in, const char *geo, MshMesh *out, M2dRemeshStats *st, double t0)
{
  Request q;
  Frame   f;
  char   *buf = NULL;
  int     lost;
  if (S.gone[0]) return Fail(c, "gmsh's process ended earlier (%s)", S.gone);
  if (!S.pid && StartServer(c)) return 1;
  memset(&q, 0, sizeof(q));
  q.t0 = t0, q.hmin = in->hmin, q.hmax = in->hmax, q.verbose = in->verbose, q.quads = (int)in->quads;
  q.field = !in->prev ? 0 : in->hnode ? 1 : 2;
  q.lname = (long)strlen(in->geo) + 1, q.lopen = (long)strlen(geo) + 1, q.lmsh = in->write_msh ? (long)strlen(in->write_msh) + 1 : 0;
  if (q.field) q.k = CountsOf(in->prev);
  if (WriteAll(S.fd, &q, sizeof(q)) || PutString(S.fd, in->geo, q.lname) || PutString(S.fd, geo, q.lopen) || PutString(S.fd, in->write_msh, q.lmsh) ||
      (q.field && (PutMesh(S.fd, in->prev, q.k) || WriteAll(S.fd, q.field == 1 ? in->hnode : in->hcell, (size_t)(q.field == 1 ? q.k.nnode : q.k.nquad) * sizeof(double)))) ||
      ReadAll(S.fd, &f, sizeof(f)))
    return Gone(c);
  if (f.kind == 1) return Fail(c, "gmsh crashed while meshing it (signal SIG%s)", sigabbrev_np(f.code) ? sigabbrev_np(f.code) : "?");
  if (f.kind == 2) return Fail(c, "gmsh ended without a mesh (exit status %d)", f.code);
  if (f.kind == 3) return Fail(c, "cannot start gmsh's process: %s", strerror(f.code));
  if (f.kind != 0 || !f.nbytes || !(buf = (char *)malloc(f.nbytes))) return Fail(c, "gmsh ended without a mesh (%s)", f.kind ? "a reply the program cannot read" : "out of memory");
  if (ReadAll(S.fd, buf, f.nbytes)) {
    free(buf);
    return Gone(c);
  }
  {
    In             r = {-1, buf, f.nbytes, 0};
    MshMesh        more;
    M2dRemeshStats s2;
    lost = Receive(c, &r, out, st);
    while (!lost && !c->failed && r.pos < r.len) { /* the other shares, joined in order */
      memset(&more, 0, sizeof(more));
      memset(&s2, 0, sizeof(s2));
      lost = Receive(c, &r, &more, &s2);
      if (!lost && !c->failed) {
        st->seconds_open     = fmax(st->seconds_open, s2.seconds_open);
        st->seconds_generate = fmax(st->seconds_generate, s2.seconds_generate);
        lost                 = Join(c, out, &more) ? 2 : 0;
      }
      MshFree(&more);
    }
    lost = lost == 1 || (!lost && !c->failed && r.pos != r.len);
  }
  free(buf);
  if (lost) return Fail(c, "gmsh ended without a mesh (a reply the program cannot read)");
  if (!c->failed && !out->nquad) return Fail(c, "the mesh has no quadrilaterals");
  return c->failed;
}

int M2dRemeshStart(void)
{
  Ctx c;
  memset(&c, 0, sizeof(c));
  c.slot = -1;
  return S.pid ? 0 : StartServer(&c);
}

int M2dRemesh(const M2dRemeshInput *in, MshMesh *out, M2dRemeshStats *stats, char *err, size_t errlen)
{
  Ctx            c;
  M2dRemeshStats st;
  double         t0 = Now();
  char           geo[PATH_MAX + 64];

  memset(out, 0, sizeof(*out));
  memset(&st, 0, sizeof(st));
  memset(&c, 0, sizeof(c));
  c.geo    = in ? in->geo : NULL;
  c.slot   = -1;
  c.err    = err;
  c.errlen = errlen;
  if (err && errlen) err[0] = 0;
  if (!in) return Fail(&c, "no input");
  if (CheckInput(&c, in)) return 1;
  snprintf(geo, sizeof(geo), "%s", in->geo);
  if (!((in->nnumber || in->prev) && WriteWrapper(&c, in, geo))) InServer(&c, in, geo, out, &st, t0);
  if (c.wrapper[0]) unlink(c.wrapper);
  M2dTempForgetFile(c.slot);
  if (c.failed) {
    MshFree(out);
    return 1;
  }
  M2dQuadQualityCompute(out, &st.quality);
  st.seconds_total = Now() - t0;
  if (stats) *stats = st;
  return 0;
}
