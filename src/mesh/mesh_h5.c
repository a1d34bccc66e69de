/* mesh_h5.c - the mesh in PETSc's own HDF5 format (see mesh.h): -mesh_save
 * writes the plex as built (DMView, PETSC_VIEWER_HDF5_PETSC: topology,
 * coordinates and every label, the group labels "m2d:NAME" among them) with the
 * body of each cell as the cell label "m2d:body" and, as attributes of the
 * group /m2d, the names and dimensions of the physical groups and the body
 * names. -mesh F.h5 reads it back on rank 0 into the lists a .msh file gives
 * (MeshReadHDF5, below), so that it takes the .msh path from there. */
#include "options.h"
#include "mesh_impl.h"
#include <petscviewerhdf5.h>
#include "util.h"
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define M2D_H5_GROUP  "/m2d"
#define M2D_H5_FORMAT "mortar2d mesh 1"
#define M2D_BODY_LABEL "m2d:body"

PetscBool MeshIsHDF5(const char *path)
{
  size_t n = strlen(path);
  return (PetscBool)(n > 3 && !strcmp(path + n - 3, ".h5"));
}

/* the groups and bodies as attributes of /m2d */
static PetscErrorCode WriteNames(PetscViewer v, const M2dMesh *m, const M2dScene *s)
{
  char     key[32];
  PetscInt n;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5WriteGroup(v, M2D_H5_GROUP));
  PetscCall(PetscViewerHDF5WriteAttribute(v, M2D_H5_GROUP, "format", PETSC_STRING, M2D_H5_FORMAT));
  PetscCall(PetscViewerHDF5WriteAttribute(v, M2D_H5_GROUP, "ngroup", PETSC_INT, &m->ngroup));
  for (PetscInt g = 0; g < m->ngroup; g++) {
    PetscCall(PetscSNPrintf(key, sizeof(key), "group%" PetscInt_FMT, g));
    PetscCall(PetscViewerHDF5WriteAttribute(v, M2D_H5_GROUP, key, PETSC_STRING, m->group[g]));
    PetscCall(PetscSNPrintf(key, sizeof(key), "groupdim%" PetscInt_FMT, g));
    PetscCall(PetscViewerHDF5WriteAttribute(v, M2D_H5_GROUP, key, PETSC_INT, &m->groupdim[g]));
  }
  n = s->nbody;
  PetscCall(PetscViewerHDF5WriteAttribute(v, M2D_H5_GROUP, "nbody", PETSC_INT, &n));
  for (PetscInt b = 0; b < s->nbody; b++) {
    PetscCall(PetscSNPrintf(key, sizeof(key), "body%" PetscInt_FMT, b));
    PetscCall(PetscViewerHDF5WriteAttribute(v, M2D_H5_GROUP, key, PETSC_STRING, s->body[b].name));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MeshSave(const M2dMesh *m, const M2dScene *s, PetscReal L, const char *path)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)m->dm);
  PetscMPIInt rank;
  char        tmp[PETSC_MAX_PATH_LEN + 32], target[PETSC_MAX_PATH_LEN], err[M2D_ERR_LEN] = "";
  DMLabel     body;
  PetscViewer v;
  DM          dm;
  Vec         xm, x;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) { /* every rank writes the same temporary file, renamed when complete */
    FILE *fp;
    char  why[2 * PETSC_MAX_PATH_LEN + 200];
    if (!MeshIsHDF5(path)) PetscCall(PetscSNPrintf(err, sizeof(err), "option -mesh_save: '%s' does not end in .h5", path));
    else if (M2dOutputTarget(path, target, sizeof(target), why, sizeof(why))) PetscCall(PetscSNPrintf(err, sizeof(err), "option -mesh_save: %s", why));
    else if (M2dTmpName(target, tmp, sizeof(tmp))) PetscCall(PetscSNPrintf(err, sizeof(err), "option -mesh_save: '%s' is too long a path", path));
    else if (!(fp = fopen(tmp, "wb"))) PetscCall(PetscSNPrintf(err, sizeof(err), "option -mesh_save: cannot write '%s': %s", path, strerror(errno)));
    else fclose(fp);
  }
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  PetscCallMPI(MPI_Bcast(tmp, (PetscMPIInt)sizeof(tmp), MPI_CHAR, 0, comm));
  PetscCall(DMClone(m->dm, &dm)); /* the plex and its labels, coordinates of its own: m's times L */
  PetscCall(DMGetCoordinates(m->dm, &xm));
  PetscCall(VecDuplicate(xm, &x));
  PetscCall(VecCopy(xm, x));
  PetscCall(VecScale(x, L));
  PetscCall(DMSetCoordinates(dm, x));
  PetscCall(VecDestroy(&x));
  PetscCall(DMCreateLabel(dm, M2D_BODY_LABEL));
  PetscCall(DMGetLabel(dm, M2D_BODY_LABEL, &body));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) PetscCall(DMLabelSetValue(body, c, m->cellbody[c - m->cStart]));
  PetscCall(PetscViewerHDF5Open(comm, tmp, FILE_MODE_WRITE, &v));
  PetscCall(PetscViewerPushFormat(v, PETSC_VIEWER_HDF5_PETSC));
  PetscCall(DMView(dm, v));
  PetscCall(PetscViewerPopFormat(v));
  PetscCall(WriteNames(v, m, s));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(DMDestroy(&dm));
  if (rank == 0 && rename(tmp, target)) { /* through a link: onto its target */
    PetscCall(PetscSNPrintf(err, sizeof(err), "option -mesh_save: cannot write '%s': %s", path, strerror(errno)));
    remove(tmp);
  }
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

/* ---------- -mesh F.h5: rank 0 reads the file into an MshMesh ----------
 * The layout -mesh_save writes (PETSc 3.18, storage version 1.0.0):
 * topology/order (the point numbers), topology/cones (the cone size of each
 * of those points), topology/cells (the cones, concatenated),
 * topology/orientation; geometry/vertices (one row per vertex, in point
 * order); labels/NAME/VALUE/indices; the names in /m2d's attributes. PETSc's
 * DMLoad reads this version on rank 0 alone too, and trusts it: an index out
 * of range dropped a load silently, a cone size of 0 or less made it hang.
 * Here every size and index is checked against the file and the topology
 * before it is used, and the mesh then takes the path of a .msh file: every
 * check of mesh_read.c and mesh_check.c, and -mesh_scale. */
typedef struct {
  const char *path;
  hid_t       file;
  hsize_t     fsize; /* bytes: no dataset can hold more */
  char       *err;
  size_t      len;
} H5In;

static int H5Bad(H5In *h, const char *fmt, ...)
{
  char    what[M2D_ERR_LEN];
  va_list ap;

  if (h->err[0]) return 1;
  va_start(ap, fmt);
  vsnprintf(what, sizeof(what), fmt, ap);
  va_end(ap);
  snprintf(h->err, h->len, "mesh file '%s' is corrupted (write it again with -mesh_save): %s", h->path, what);
  return 1;
}

/* the link name exists, with every group on its path (H5Lexists alone fails on a missing group) */
static int H5Has(H5In *h, const char *name)
{
  char   part[2 * M2D_NAME_LEN + 64];
  size_t n = strlen(name);

  if (n >= sizeof(part)) return 0;
  for (size_t i = 1; i <= n; i++)
    if (i == n || name[i] == '/') {
      memcpy(part, name, i);
      part[i] = 0;
      if (H5Lexists(h->file, part, H5P_DEFAULT) <= 0) return 0;
    }
  return 1;
}

/* dataset name: rows of ncol integers (read as long long) or doubles, no more
 * than the file can hold; *data malloc'ed */
static int H5ReadTable(H5In *h, const char *name, int ncol, int integer, void **data, long *rows)
{
  hid_t   d = -1, sp = -1, ty = -1;
  hsize_t dims[2] = {0, 1};
  size_t  esz     = 0;
  int     nd = 0, rc = 0;

  *data = NULL;
  *rows = 0;
  if (!H5Has(h, name)) return H5Bad(h, "it has no dataset %s", name);
  if ((d = H5Dopen2(h->file, name, H5P_DEFAULT)) < 0 || (ty = H5Dget_type(d)) < 0 || (sp = H5Dget_space(d)) < 0) rc = H5Bad(h, "dataset %s cannot be opened", name);
  else if (H5Tget_class(ty) != (integer ? H5T_INTEGER : H5T_FLOAT) || !(esz = H5Tget_size(ty)) || esz > 8) rc = H5Bad(h, "dataset %s does not hold %s", name, integer ? "integers" : "floating-point numbers");
  else if ((nd = H5Sget_simple_extent_ndims(sp)) < 1 || nd > 2 || H5Sget_simple_extent_dims(sp, dims, NULL) < 0 || (nd == 1 && ncol != 1) || (nd == 2 && dims[1] != (hsize_t)ncol)) rc = H5Bad(h, "dataset %s is not a table of %d column%s", name, ncol, ncol > 1 ? "s" : "");
  else if (dims[0] > h->fsize / (esz * (hsize_t)ncol)) rc = H5Bad(h, "dataset %s claims %llu rows, more than the file's %llu bytes hold", name, (unsigned long long)dims[0], (unsigned long long)h->fsize);
  else if (!(*data = malloc((size_t)(dims[0] * (hsize_t)ncol + 1) * 8))) rc = H5Bad(h, "out of memory for dataset %s", name);
  else if (dims[0] && H5Dread(d, integer ? H5T_NATIVE_LLONG : H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, *data) < 0) rc = H5Bad(h, "dataset %s cannot be read (truncated?)", name);
  if (sp >= 0) H5Sclose(sp);
  if (ty >= 0) H5Tclose(ty);
  if (d >= 0) H5Dclose(d);
  if (rc) {
    free(*data);
    *data = NULL;
  } else *rows = (long)dims[0];
  return rc;
}

/* attribute name of /m2d: one integer in [lo, hi], or one string of printable characters (len - 1 at most) */
static int H5Attr(H5In *h, const char *name, long long lo, long long hi, long long *ival, char *sval, size_t len)
{
  hid_t a = -1, ty = -1, sp = -1, mem = -1;
  int   rc = 0;

  if (H5Aexists_by_name(h->file, M2D_H5_GROUP, name, H5P_DEFAULT) <= 0) return H5Bad(h, "%s has no attribute %s", M2D_H5_GROUP, name);
  if ((a = H5Aopen_by_name(h->file, M2D_H5_GROUP, name, H5P_DEFAULT, H5P_DEFAULT)) < 0 || (ty = H5Aget_type(a)) < 0 || (sp = H5Aget_space(a)) < 0 || H5Sget_simple_extent_npoints(sp) != 1) rc = H5Bad(h, "attribute %s cannot be read", name);
  else if (ival) {
    if (H5Tget_class(ty) != H5T_INTEGER || H5Aread(a, H5T_NATIVE_LLONG, ival) < 0) rc = H5Bad(h, "attribute %s is not an integer", name);
    else if (*ival < lo || *ival > hi) rc = H5Bad(h, "attribute %s = %lld is outside %lld..%lld", name, *ival, lo, hi);
  } else if (H5Tget_class(ty) != H5T_STRING) rc = H5Bad(h, "attribute %s is not a string", name);
  else if (H5Tis_variable_str(ty) > 0) {
    char *p = NULL;
    if ((mem = H5Tcopy(H5T_C_S1)) < 0 || H5Tset_size(mem, H5T_VARIABLE) < 0 || H5Aread(a, mem, &p) < 0 || !p) rc = H5Bad(h, "attribute %s cannot be read", name);
    else snprintf(sval, len, "%s", strlen(p) < len ? p : "");
    if (p) H5free_memory(p);
  } else {
    char   buf[1024];
    size_t n = H5Tget_size(ty);
    if (!n || n >= sizeof(buf) || (mem = H5Tcopy(H5T_C_S1)) < 0 || H5Tset_size(mem, n) < 0 || H5Aread(a, mem, buf) < 0) rc = H5Bad(h, "attribute %s cannot be read", name);
    else {
      buf[n] = 0;
      snprintf(sval, len, "%s", strlen(buf) < len ? buf : "");
    }
  }
  for (const char *c = sval && !rc ? sval : ""; *c; c++)
    if ((unsigned char)*c < 32 || *c == 127) rc = H5Bad(h, "attribute %s holds a control character", name);
  if (!rc && sval && !sval[0]) rc = H5Bad(h, "attribute %s is empty or longer than %d characters", name, (int)len - 1);
  if (mem >= 0) H5Tclose(mem);
  if (sp >= 0) H5Sclose(sp);
  if (ty >= 0) H5Tclose(ty);
  if (a >= 0) H5Aclose(a);
  return rc;
}

/* What the file says. Point p's entry in the file's arrays is entry[p]; the
 * cone of entry i starts at off[i] in cone[] and ornt[]. */
typedef struct {
  long       np, nv, vstart, ncone;
  long long *order, *size, *cone, *ornt;
  long      *entry, *off;
  double    *xy;
  long       ngroup, nbody;
  char       group[M2D_MAX_GROUPS][M2D_NAME_LEN], body[M2D_MAX_BODIES][M2D_NAME_LEN];
  long long  groupdim[M2D_MAX_GROUPS];
} H5Mesh;

static void H5MeshFree(H5Mesh *f)
{
  free(f->order), free(f->size), free(f->cone), free(f->ornt), free(f->entry), free(f->off), free(f->xy);
}

static int H5ReadNames(H5In *h, H5Mesh *f)
{
  char      key[32], format[64];
  long long n;

  if (!H5Has(h, M2D_H5_GROUP) || H5Aexists_by_name(h->file, M2D_H5_GROUP, "format", H5P_DEFAULT) <= 0) {
    snprintf(h->err, h->len, "mesh file '%s' holds no mortar2d mesh (write one with -mesh_save)", h->path);
    return 1;
  }
  if (H5Attr(h, "format", 0, 0, NULL, format, sizeof(format))) return 1;
  if (strcmp(format, M2D_H5_FORMAT)) return H5Bad(h, "its format is '%s', not '%s'", format, M2D_H5_FORMAT);
  if (H5Attr(h, "ngroup", 0, M2D_MAX_GROUPS, &n, NULL, 0)) return 1;
  f->ngroup = (long)n;
  if (H5Attr(h, "nbody", 1, M2D_MAX_BODIES, &n, NULL, 0)) return 1;
  f->nbody = (long)n;
  for (long g = 0; g < f->ngroup; g++) {
    snprintf(key, sizeof(key), "group%ld", g);
    if (H5Attr(h, key, 0, 0, NULL, f->group[g], M2D_NAME_LEN)) return 1;
    snprintf(key, sizeof(key), "groupdim%ld", g);
    if (H5Attr(h, key, 0, 2, &f->groupdim[g], NULL, 0)) return 1;
  }
  for (long b = 0; b < f->nbody; b++) {
    snprintf(key, sizeof(key), "body%ld", b);
    if (H5Attr(h, key, 0, 0, NULL, f->body[b], M2D_NAME_LEN)) return 1;
  }
  return 0;
}

/* point p's cone size, -1 outside the chart */
static long long H5Size(const H5Mesh *f, long long p)
{
  return p >= 0 && p < f->np ? f->size[f->entry[p]] : -1;
}

/* the topology: order a permutation of the points, cone sizes 0 (vertex), 2
 * (edge) or 4 (cell) adding up to the cone points; the vertices numbered
 * consecutively, one row of geometry/vertices each */
static int H5ReadTopology(H5In *h, H5Mesh *f)
{
  long n[4], vmax = -1;

  if (H5ReadTable(h, "topology/order", 1, 1, (void **)&f->order, &n[0]) || H5ReadTable(h, "topology/cones", 1, 1, (void **)&f->size, &n[1]) || H5ReadTable(h, "topology/cells", 1, 1, (void **)&f->cone, &n[2]) ||
      H5ReadTable(h, "topology/orientation", 1, 1, (void **)&f->ornt, &n[3]) || H5ReadTable(h, "geometry/vertices", 2, 0, (void **)&f->xy, &f->nv))
    return 1;
  f->np = n[0];
  if (n[1] != f->np) return H5Bad(h, "topology/cones has %ld entries for %ld points", n[1], f->np);
  if (n[3] != n[2]) return H5Bad(h, "topology/orientation has %ld entries for %ld cone points", n[3], n[2]);
  f->entry = (long *)malloc((size_t)(f->np + 1) * sizeof(long));
  f->off   = (long *)malloc((size_t)(f->np + 1) * sizeof(long));
  if (!f->entry || !f->off) return H5Bad(h, "out of memory");
  for (long p = 0; p < f->np; p++) f->entry[p] = -1;
  f->ncone = 0;
  for (long i = 0; i < f->np; i++) {
    long long p = f->order[i], s = f->size[i];
    if (p < 0 || p >= f->np) return H5Bad(h, "topology/order names point %lld, outside 0..%ld", p, f->np - 1);
    if (f->entry[p] >= 0) return H5Bad(h, "topology/order names point %lld twice", p);
    if (s != 0 && s != 2 && s != 4) return H5Bad(h, "point %lld has a cone of %lld points (0, 2 or 4 expected)", p, s);
    f->entry[p] = i;
    f->off[i]   = f->ncone;
    f->ncone += (long)s;
  }
  if (f->ncone != n[2]) return H5Bad(h, "the cone sizes add up to %ld, topology/cells has %ld entries", f->ncone, n[2]);
  f->vstart = f->np;
  for (long p = 0; p < f->np; p++)
    if (!H5Size(f, p)) f->vstart = PetscMin(f->vstart, p), vmax = p;
  if (vmax < 0 || vmax - f->vstart + 1 != f->nv) return H5Bad(h, "geometry/vertices has %ld rows for %ld vertex points", f->nv, vmax < 0 ? 0 : vmax - f->vstart + 1);
  for (long p = f->vstart; p <= vmax; p++)
    if (H5Size(f, p)) return H5Bad(h, "the vertices are not numbered consecutively (point %ld)", p);
  for (long i = 0; i < 2 * f->nv; i++)
    if (!isfinite(f->xy[i])) return H5Bad(h, "vertex %ld has a coordinate that is not a finite number", i / 2);
  return 0;
}

/* edge e's vertex k (a node index), checked: an edge's cone is two distinct vertices */
static int H5EdgeVertex(H5In *h, const H5Mesh *f, long long e, int k, long *v)
{
  const long long *c = &f->cone[f->off[f->entry[e]]];
  if (H5Size(f, c[0]) != 0 || H5Size(f, c[1]) != 0 || c[0] == c[1]) return H5Bad(h, "edge %lld has cone (%lld, %lld), not two vertices", e, c[0], c[1]);
  *v = (long)(c[k] - f->vstart);
  return 0;
}

/* the cells as quads: the first vertex of each edge of the cone, as its
 * orientation says (0 along the edge, -1 against), the edges a closed loop */
static int H5Quads(H5In *h, const H5Mesh *f, MshMesh *m)
{
  long nc = 0;

  for (long p = 0; p < f->np; p++) nc += H5Size(f, p) == 4;
  m->nquad    = nc;
  m->quad     = (long *)malloc((size_t)(4 * nc + 1) * sizeof(long));
  m->quadphys = (int *)malloc((size_t)(nc + 1) * sizeof(int));
  if (!m->quad || !m->quadphys) return H5Bad(h, "out of memory");
  nc = 0;
  for (long p = 0; p < f->np; p++) {
    const long long *c = &f->cone[f->off[f->entry[p]]], *o = &f->ornt[f->off[f->entry[p]]];
    long             v[4][2];
    if (H5Size(f, p) != 4) continue;
    for (int k = 0; k < 4; k++) {
      if (H5Size(f, c[k]) != 2) return H5Bad(h, "cell %ld has cone point %lld, which is not an edge", p, c[k]);
      if (o[k] != 0 && o[k] != -1) return H5Bad(h, "cell %ld has edge orientation %lld (0 or -1 expected)", p, o[k]);
      if (H5EdgeVertex(h, f, c[k], o[k] ? 1 : 0, &v[k][0]) || H5EdgeVertex(h, f, c[k], o[k] ? 0 : 1, &v[k][1])) return 1;
    }
    for (int k = 0; k < 4; k++) {
      if (v[k][1] != v[(k + 1) % 4][0]) return H5Bad(h, "the edges of cell %ld do not form a closed loop", p);
      m->quad[4 * nc + k] = v[k][0];
    }
    m->quadphys[nc++] = -1;
  }
  return 0;
}

/* labels/NAME/VALUE/indices: its points (malloc'ed; none when the label or value is absent) */
static int H5LabelPoints(H5In *h, const H5Mesh *f, const char *name, long value, long long expect, long long **pts, long *n)
{
  char path[2 * M2D_NAME_LEN + 64];

  *pts = NULL;
  *n   = 0;
  snprintf(path, sizeof(path), "labels/%s/%ld/indices", name, value);
  if (!H5Has(h, path)) return 0;
  if (H5ReadTable(h, path, 1, 1, (void **)pts, n)) return 1;
  for (long i = 0; i < *n; i++)
    if (H5Size(f, (*pts)[i]) != expect) {
      H5Bad(h, "label '%s' names point %lld, %s", name, (*pts)[i], H5Size(f, (*pts)[i]) < 0 ? "outside the mesh" : expect == 4 ? "not a cell" : expect == 2 ? "not an edge" : "not a vertex");
      free(*pts);
      *pts = NULL;
      return 1;
    }
  return 0;
}

/* the number of values (links) under labels/NAME, 0 if absent */
static long H5LabelValues(H5In *h, const char *name)
{
  char       path[2 * M2D_NAME_LEN + 64];
  hid_t      g;
  H5G_info_t info;
  long       n = -1;

  snprintf(path, sizeof(path), "labels/%s", name);
  if (!H5Has(h, path)) return 0;
  if ((g = H5Gopen2(h->file, path, H5P_DEFAULT)) >= 0) {
    if (H5Gget_info(g, &info) >= 0) n = (long)info.nlinks;
    H5Gclose(g);
  }
  return n;
}

/* physical groups: the bodies first, in their saved order (they stay the bodies
 * without -bodies), then the others; tag = position + 1. The cells' bodies
 * from the label m2d:body (every cell in exactly one), the curves' edges and
 * the points' vertices from the labels m2d:NAME (value 1). */
static int H5Groups(H5In *h, const H5Mesh *f, MshMesh *m)
{
  long   order[M2D_MAX_GROUPS], n = 0, nset = 0, cap = 0, *cell;
  long long *pts;
  long   npts;

  for (long b = 0; b < f->nbody; b++) {
    long g = 0;
    while (g < f->ngroup && (f->groupdim[g] != 2 || strcmp(f->group[g], f->body[b]))) g++;
    if (g == f->ngroup) return H5Bad(h, "body '%s' is not among its surfaces", f->body[b]);
    order[n++] = g;
  }
  for (long g = 0; g < f->ngroup; g++) {
    long k = 0;
    while (k < f->nbody && order[k] != g) k++;
    if (k == f->nbody) order[n++] = g;
  }
  if (!(m->phys = (MshPhysical *)calloc((size_t)f->ngroup + 1, sizeof(MshPhysical)))) return H5Bad(h, "out of memory");
  for (long i = 0; i < f->ngroup; i++) {
    m->phys[i].dim = (int)f->groupdim[order[i]];
    m->phys[i].tag = (int)i + 1;
    snprintf(m->phys[i].name, sizeof(m->phys[i].name), "%s", f->group[order[i]]);
  }
  m->nphys = (int)f->ngroup;
  /* bodies */
  if (H5LabelValues(h, M2D_BODY_LABEL) > f->nbody) return H5Bad(h, "label '%s' has more values than the %ld bodies", M2D_BODY_LABEL, f->nbody);
  if (!(cell = (long *)malloc((size_t)(f->np + 1) * sizeof(long)))) return H5Bad(h, "out of memory");
  for (long p = 0, c = 0; p < f->np; p++) cell[p] = H5Size(f, p) == 4 ? c++ : -1;
  for (long b = 0; b < f->nbody; b++) {
    if (H5LabelPoints(h, f, M2D_BODY_LABEL, b, 4, &pts, &npts)) break;
    for (long i = 0; i < npts && !h->err[0]; i++) {
      if (m->quadphys[cell[pts[i]]] >= 0) H5Bad(h, "cell %lld is in two bodies", pts[i]);
      m->quadphys[cell[pts[i]]] = (int)b + 1;
      nset++;
    }
    free(pts);
  }
  free(cell);
  if (h->err[0]) return 1;
  if (nset != m->nquad) return H5Bad(h, "%ld of its %ld cells are in no body", m->nquad - nset, m->nquad);
  /* curves and points */
  for (long i = 0; i < f->ngroup; i++) {
    char lname[M2D_NAME_LEN + 8];
    long nval;
    if (m->phys[i].dim == 2) continue;
    snprintf(lname, sizeof(lname), "m2d:%s", m->phys[i].name);
    if ((nval = H5LabelValues(h, lname)) < 0 || nval > 1) return H5Bad(h, "label '%s' has values other than 1", lname);
    if (H5LabelPoints(h, f, lname, 1, m->phys[i].dim == 1 ? 2 : 0, &pts, &npts)) return 1;
    if (nval == 1 && !pts) return H5Bad(h, "label '%s' has values other than 1", lname);
    if (m->phys[i].dim == 1 && m->nline + npts > cap) { /* lines */
      long *l  = (long *)realloc(m->line, (size_t)(2 * (m->nline + npts) + 2) * sizeof(long));
      int  *lp = l ? (int *)realloc(m->linephys, (size_t)(m->nline + npts + 1) * sizeof(int)) : NULL;
      if (l) m->line = l;
      if (lp) m->linephys = lp;
      if (!l || !lp) {
        free(pts);
        return H5Bad(h, "out of memory");
      }
      cap = m->nline + npts;
    }
    if (m->phys[i].dim == 0) {
      long *q  = (long *)realloc(m->point, (size_t)(m->npoint + npts + 1) * sizeof(long));
      int  *qp = q ? (int *)realloc(m->pointphys, (size_t)(m->npoint + npts + 1) * sizeof(int)) : NULL;
      if (q) m->point = q;
      if (qp) m->pointphys = qp;
      if (!q || !qp) {
        free(pts);
        return H5Bad(h, "out of memory");
      }
    }
    for (long k = 0; k < npts && !h->err[0]; k++) {
      if (m->phys[i].dim == 1) {
        if (!H5EdgeVertex(h, f, pts[k], 0, &m->line[2 * m->nline]) && !H5EdgeVertex(h, f, pts[k], 1, &m->line[2 * m->nline + 1])) m->linephys[m->nline++] = (int)i + 1;
      } else {
        m->point[m->npoint]       = (long)(pts[k] - f->vstart);
        m->pointphys[m->npoint++] = (int)i + 1;
      }
    }
    free(pts);
    if (h->err[0]) return 1;
  }
  return 0;
}

/* the file's signature before HDF5 sees it (HDF5 prints its own error stack otherwise) */
static int H5Signature(H5In *h)
{
  static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  unsigned char              head[8];
  struct stat                st;
  FILE                      *fp;
  int                        bad;

  if (stat(h->path, &st)) snprintf(h->err, h->len, "cannot open mesh file '%s': %s", h->path, strerror(errno));
  else if (!S_ISREG(st.st_mode)) snprintf(h->err, h->len, "mesh file '%s' is not a regular file (a directory?)", h->path);
  else if (!(fp = fopen(h->path, "rb"))) snprintf(h->err, h->len, "cannot open mesh file '%s': %s", h->path, strerror(errno));
  else {
    bad = fread(head, 1, 8, fp) != 8 || memcmp(head, sig, 8);
    fclose(fp);
    if (bad) snprintf(h->err, h->len, "mesh file '%s' is not an HDF5 file (.h5 meshes are written by -mesh_save)", h->path);
    h->fsize = (hsize_t)st.st_size;
  }
  return h->err[0] != 0;
}

int MeshReadHDF5(const char *path, MshMesh *m, char *err, size_t len)
{
  H5In        h  = {path, -1, 0, err, len};
  H5Mesh      f;
  H5E_auto2_t fn = NULL;
  void       *fd = NULL;

  memset(m, 0, sizeof(*m));
  memset(&f, 0, sizeof(f));
  err[0] = 0;
  if (H5Signature(&h)) return 1;
  H5open(); /* before any H5E call */
  H5Eget_auto2(H5E_DEFAULT, &fn, &fd);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  if ((h.file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT)) < 0) snprintf(err, len, "mesh file '%s' cannot be read as HDF5 (truncated or corrupted?)", path);
  else if (!H5ReadNames(&h, &f) && !H5ReadTopology(&h, &f) && !H5Quads(&h, &f, m) && !H5Groups(&h, &f, m)) {
    m->nnode = f.nv;
    m->xy    = f.xy;
    f.xy     = NULL;
  }
  if (h.file >= 0) H5Fclose(h.file);
  H5Eset_auto2(H5E_DEFAULT, fn, fd);
  H5MeshFree(&f);
  if (err[0]) MshFree(m);
  return err[0] != 0;
}
