/* remesh.c - a scene's .geo meshed by gmsh's C API into an all-quad MshMesh,
 * optionally driven by a size field on a previous mesh (see remesh.h).
 *
 * The field goes to gmsh as its mesh-size callback (remesh_field.c evaluates
 * it), with every other size source (points, curvature, boundary extension, the
 * .geo's own fields) switched off: the field alone sets the size, on the curves
 * (contact surfaces included) as inside. Why not a post-processing view used as
 * background mesh: gmsh's search in the view misses points of a curved boundary
 * that bulge out of the previous (polygonal) mesh and gives them the largest
 * size; and a view cannot tell the two bodies apart where they touch.
 *
 * gmsh runs in a child process per call (InChild): gmsh 4.8 crashes on some
 * inputs (tests/test_fuzz_geo.py: a double free on binary garbage, a
 * segmentation fault with Mesh.Algorithm 8 or with coordinates of 1e300),
 * prints to stdout past General.Terminal (Blossom's warnings) and keeps global
 * state that gmshFinalize does not reset. */
#define _GNU_SOURCE /* realpath, NSIG */
#include "remesh.h"
#include "temprecord.h"
#include <gmshc.h>
#include <ctype.h>
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
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

/* gmsh's library is loaded (dlopen) at the first remeshing, not linked: it
 * pulls in some 90 libraries (OpenCASCADE, ...) whose loading (0.15-0.2 s)
 * every run would pay, remeshing or not. Loaded in the program's process, the
 * children share it. */
#ifndef M2D_GMSH_LIBRARY
#define M2D_GMSH_LIBRARY "libgmsh.so.4.8"
#endif
#define GMSH_FUNCTIONS(X) \
  X(gmshFree) X(gmshInitialize) X(gmshLoggerGet) X(gmshLoggerStart) X(gmshModelGetAdjacencies) X(gmshModelGetEntities) \
  X(gmshModelGetPhysicalGroups) X(gmshModelGetPhysicalGroupsForEntity) X(gmshModelGetPhysicalName) X(gmshModelMeshFieldAdd) \
  X(gmshModelMeshFieldSetAsBackgroundMesh) X(gmshModelMeshFieldSetString) X(gmshModelMeshGenerate) X(gmshModelMeshSetSizeCallback) \
  X(gmshOpen) X(gmshOptionSetNumber) X(gmshWrite)
static struct {
#define X(f) __typeof__(&f) f;
  GMSH_FUNCTIONS(X)
#undef X
  void *lib;
  char  failed[PATH_MAX + 128]; /* why it could not be loaded, "" */
} G;

static int LoadGmsh(Ctx *c)
{
  if (!G.lib && !G.failed[0]) {
    if (!(G.lib = dlopen(M2D_GMSH_LIBRARY, RTLD_NOW | RTLD_LOCAL))) snprintf(G.failed, sizeof(G.failed), "cannot load gmsh's library: %s", dlerror());
#define X(f) \
  if (G.lib && !G.failed[0] && !(*(void **)&G.f = dlsym(G.lib, #f))) snprintf(G.failed, sizeof(G.failed), "gmsh's library %s has no function %s", M2D_GMSH_LIBRARY, #f);
    GMSH_FUNCTIONS(X)
#undef X
  } /* never closed: gmsh's libraries are not made to be unloaded */
  return G.failed[0] ? Fail(c, "%s", G.failed) : 0;
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

/* This run's directory for the files below (temprecord.h: locked while the
 * run lives, removed at its end; a dead run's is removed by the next run) */
static struct {
  char path[PATH_MAX];
  int  lock; /* the lock's descriptor, -1 before the directory is made */
} D = {"", -1};

static int RunDir(Ctx *c)
{
  if (D.lock < 0 && M2dTempMakeDir(M2dTempDir(), M2D_REMESH_DIR_PREFIX, D.path, sizeof(D.path), &D.lock)) return Fail(c, "cannot make a directory in %s '%s': %s", getenv("TMPDIR") && *getenv("TMPDIR") ? "TMPDIR" : "the temporary directory", M2dTempDir(), strerror(errno));
  return 0;
}

/* gmsh 4.8's C API has no -setnumber (no parser API): the numbers go in a
 * wrapper .geo that defines them and includes the scene's .geo, where
 * DefineConstant keeps them and Exists sees them. With a size field it also
 * defines m2d_size_field (see remesh.h). */
static int WriteWrapper(Ctx *c, const M2dRemeshInput *in, char *path, size_t len)
{
  char  abs[PATH_MAX];
  FILE *fp;
  if (!realpath(in->geo, abs)) return Fail(c, "cannot resolve the path: %s", strerror(errno));
  if (strchr(abs, '"')) return Fail(c, "the path holds a double quote");
  snprintf(path, len, "%s/wrapper.geo", D.path);
  if (!(fp = fopen(path, "w"))) return Fail(c, "cannot write the temporary file '%s': %s", path, strerror(errno));
  for (int i = 0; i < in->nnumber; i++) fprintf(fp, "%s = %.17g;\n", in->names[i], in->values[i]);
  if (in->prev) fprintf(fp, "m2d_size_field = 1;\n");
  fprintf(fp, "Include \"%s\";\n", abs);
  if (ferror(fp) | fclose(fp)) return Fail(c, "cannot write the temporary file '%s': %s", path, strerror(errno));
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

/* the mesh into path: .msh 4.1, binary (exact, and fast to read) or text;
 * only the physical groups' elements, as MshRead expects */
static int Write(Ctx *c, const char *path, int binary)
{
  int ierr = 0;
  if (SetOption(c, "Mesh.MshFileVersion", 4.1) || SetOption(c, "Mesh.Binary", binary) || SetOption(c, "Mesh.SaveAll", 0)) return 1;
  G.gmshWrite(path, &ierr);
  return GmshError(c, ierr, "to write the mesh file");
}

/* what the child tells the parent, besides the mesh file */
typedef struct {
  int    failed, oom;
  double seconds_open, seconds_generate;
  char   err[1024];
} Report;

/* in the child: gmsh meshes geo, the mesh goes to msh */
static int Run(Ctx *c, const M2dRemeshInput *in, const char *geo, const char *msh, Driver *d, Report *r, double t0)
{
  int    ierr = 0, *ents = NULL;
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
  r->seconds_open = Now() - t0;
  G.gmshModelMeshGenerate(2, &ierr);
  if (GmshError(c, ierr, "to mesh it")) return 1;
  r->seconds_generate = Now() - t0 - r->seconds_open;
  return (in->write_msh && Write(c, in->write_msh, 0)) || Write(c, msh, 1);
}

/* ---------- gmsh in a child process ----------
 * One child per call, forked by the program after MPI_Init: it calls no MPI or
 * PETSc function, takes the default action of every signal (a crash is no
 * PETSc trace, and leaves no core file), writes to /dev/null (unless verbose),
 * initialises gmsh (loaded by the parent), meshes, writes the mesh as a binary
 * .msh in the run's directory and a Report through a socket, and _exits. The
 * parent reads the report, then the mesh (MshRead). The child ends with the
 * parent, however that ends (Watch), and its memory is bounded (Limit). */
static int child_fd = -1; /* the child's end of the socket */

/* the parent never writes: end of file once it is gone */
static void *Watch(void *arg)
{
  char b;
  while (read(child_fd, &b, 1) < 0 && errno == EINTR) { }
  _exit(1);
  return arg;
}

/* gmsh's operator new found no memory under Limit's bound */
static void OutOfMemory(void)
{
  static Report r;
  r.failed = r.oom = 1;
  if (write(child_fd, &r, sizeof(r)) < 0) _exit(2);
  _exit(1);
}

/* What gmsh may take for a mesh of max_nodes nodes: measured, gmsh's peak is
 * under 0.8 kB per node of the mesh it makes (a Hertz field, 194k nodes,
 * meshes in 150 MB, not in 80), so 4 kB leaves room for a first mesh of a few
 * times the cap (refused then by the cap, in its own words) */
static double Budget(double max_nodes)
{
  return 256e6 + 4e3 * max_nodes;
}

/* The address space the child may grow to: what it has (the parent's memory,
 * gmsh's library) and the Budget. Where its size cannot be read (no /proc), no
 * bound. */
static void Limit(double max_nodes)
{
  FILE         *fp = max_nodes > 0 ? fopen("/proc/self/statm", "r") : NULL;
  unsigned long pages;
  struct rlimit rl;
  if (!fp) return;
  if (fscanf(fp, "%lu", &pages) == 1) {
    rl.rlim_cur = rl.rlim_max = (rlim_t)((double)pages * (double)sysconf(_SC_PAGESIZE) + Budget(max_nodes));
    (void)setrlimit(RLIMIT_AS, &rl);
  }
  fclose(fp);
}

static void Child(Ctx *c, const M2dRemeshInput *in, const char *geo, const char *msh, double t0)
{
  char         *argv[] = {(char *)"mortar2d", NULL};
  struct rlimit nocore = {0, 0};
  Report        r;
  Driver        d;
  sigset_t      none;
  pthread_t     watch;
  void        (*set_new_handler)(void (*)(void));
  int           ierr = 0;

  for (int s = 1; s < NSIG; s++) (void)signal(s, SIG_DFL);
  sigemptyset(&none);
  sigprocmask(SIG_SETMASK, &none, NULL);
  close(D.lock); /* the run's lock stays the parent's alone: it goes when the parent does */
  (void)setrlimit(RLIMIT_CORE, &nocore);
  Limit(in->max_nodes);
  if (!in->verbose) {
    int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, STDOUT_FILENO), dup2(null, STDERR_FILENO), close(null);
  }
  if (pthread_create(&watch, NULL, Watch, NULL)) _exit(1);
  /* std::set_new_handler, from the C++ runtime gmsh brought */
  if ((*(void **)&set_new_handler = dlsym(G.lib, "_ZSt15set_new_handlerPFvvE"))) set_new_handler(OutOfMemory);
  memset(&r, 0, sizeof(r));
  memset(&d, 0, sizeof(d));
  G.gmshInitialize(1, argv, 0, &ierr);
  if (ierr) Fail(c, "gmsh did not initialise");
  else Run(c, in, geo, msh, &d, &r, t0);
  r.failed = c->failed;
  snprintf(r.err, sizeof(r.err), "%s", c->failed && c->err ? c->err : "");
  if (write(child_fd, &r, sizeof(r)) != (ssize_t)sizeof(r)) _exit(2);
  _exit(0); /* no atexit handler of the parent's, no gmshFinalize: the process ends */
}

static const char *SigName(int s)
{
  return s == SIGSEGV ? "SIGSEGV" : s == SIGABRT ? "SIGABRT" : s == SIGBUS ? "SIGBUS" : s == SIGFPE ? "SIGFPE" : s == SIGILL ? "SIGILL" : s == SIGKILL ? "SIGKILL" : s == SIGTERM ? "SIGTERM" : "";
}

static int InChild(Ctx *c, const M2dRemeshInput *in, const char *geo, const char *msh, MshMesh *out, M2dRemeshStats *st, double t0)
{
  int    sv[2], status = 0;
  size_t got = 0;
  Report r;
  pid_t  pid;
  char   err[PATH_MAX + 1024];

  if (socketpair(AF_UNIX, SOCK_STREAM, 0, sv)) return Fail(c, "cannot start gmsh's process: %s", strerror(errno));
  fflush(stdout);
  fflush(stderr);
  if ((pid = fork()) < 0) {
    close(sv[0]), close(sv[1]);
    return Fail(c, "cannot start gmsh's process: %s", strerror(errno));
  }
  if (pid == 0) {
    close(sv[0]);
    child_fd = sv[1];
    Child(c, in, geo, msh, t0);
  }
  close(sv[1]);
  for (ssize_t n = 1; got < sizeof(r) && n;) /* the report, or the child's end */
    if ((n = read(sv[0], (char *)&r + got, sizeof(r) - got)) > 0) got += (size_t)n;
    else if (n < 0 && errno != EINTR) break;
  close(sv[0]);
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) { }
  if (got == sizeof(r) && r.oom) return Fail(c, "gmsh needs more than the %.0f MB allowed for a mesh of at most %.0f nodes: the .geo asks for a far larger mesh (coarsen it, e.g. with -geo_setnumber, or raise -adapt_max_dofs)", Budget(in->max_nodes) / 1e6, in->max_nodes);
  if (got == sizeof(r) && r.failed) {
    r.err[sizeof(r.err) - 1] = 0;
    if (c->err && c->errlen) snprintf(c->err, c->errlen, "%s", r.err);
    return c->failed = 1;
  }
  if (WIFSIGNALED(status)) return Fail(c, "gmsh crashed while meshing it (signal %d%s%s)", WTERMSIG(status), *SigName(WTERMSIG(status)) ? ", " : "", SigName(WTERMSIG(status)));
  if (got != sizeof(r)) return Fail(c, "gmsh ended without a mesh (exit status %d)", WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  st->seconds_open     = r.seconds_open;
  st->seconds_generate = r.seconds_generate;
  if (MshRead(msh, out, err, sizeof(err))) { /* "mesh file 'MSH' (binary), byte N in SECTION: what" */
    const char *what = strstr(err + strlen(msh), ": ");
    return Fail(c, "gmsh's mesh cannot be used: %s", what ? what + 2 : err);
  }
  if (!out->nquad) return Fail(c, "the mesh has no quadrilaterals");
  return Orient(c, out);
}

int M2dRemesh(const M2dRemeshInput *in, MshMesh *out, M2dRemeshStats *stats, char *err, size_t errlen)
{
  Ctx            c;
  M2dRemeshStats st;
  double         t0 = Now();
  char           geo[PATH_MAX + 64], msh[PATH_MAX + 64];

  memset(out, 0, sizeof(*out));
  memset(&st, 0, sizeof(st));
  memset(&c, 0, sizeof(c));
  c.geo    = in ? in->geo : NULL;
  c.err    = err;
  c.errlen = errlen;
  if (err && errlen) err[0] = 0;
  if (!in) return Fail(&c, "no input");
  if (CheckInput(&c, in) || LoadGmsh(&c) || RunDir(&c)) return 1;
  snprintf(geo, sizeof(geo), "%s", in->geo);
  snprintf(msh, sizeof(msh), "%s/mesh.msh", D.path);
  if (!((in->nnumber || in->prev) && WriteWrapper(&c, in, geo, sizeof(geo)))) InChild(&c, in, geo, msh, out, &st, t0);
  if (strcmp(geo, in->geo)) unlink(geo);
  unlink(msh);
  if (c.failed) {
    MshFree(out);
    return 1;
  }
  M2dQuadQualityCompute(out, &st.quality);
  st.seconds_total = Now() - t0;
  if (stats) *stats = st;
  return 0;
}
