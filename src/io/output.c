/* output.c - gather to rank 0, write VTU and HDF5/XDMF under temporary names,
 * and put the run's files in place (see output.h). */
#include "output.h"
#include "util.h"
#include <errno.h>
#include <hdf5.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
  PetscInt   nv, nc;
  double    *xy;    /* 2 per vertex */
  int64_t   *conn;  /* 4 per cell */
  double    *pdata[M2D_MAX_FIELDS]; /* 3 or 1 per vertex */
  double    *cdata[M2D_MAX_FIELDS]; /* 1 per cell */
} Gathered;

/* rank 0: component comp (or, vector, both as a 3-vector with z = 0) of seq, the gathered dof layout */
static PetscErrorCode CopyOut(Vec seq, PetscInt nv, PetscBool vector, PetscInt comp, double **out)
{
  const PetscScalar *a;
  PetscInt           nc = vector ? 3 : 1;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nc * nv + 1, out));
  PetscCall(VecGetArrayRead(seq, &a));
  for (PetscInt i = 0; i < nv; i++) {
    if (vector) {
      (*out)[3 * i]     = PetscRealPart(a[2 * i]);
      (*out)[3 * i + 1] = PetscRealPart(a[2 * i + 1]);
      (*out)[3 * i + 2] = 0;
    } else (*out)[i] = PetscRealPart(a[2 * i + comp]);
  }
  PetscCall(VecRestoreArrayRead(seq, &a));
  PetscFunctionReturn(0);
}

/* vertex coordinates (times L) and the point fields, through the dof layout (2
 * values per vertex) and one scatter to rank 0 each: the coordinates, each
 * vector, and each pair of fields from one array of values per local vertex */
static PetscErrorCode GatherPoints(const M2dMesh *m, PetscReal L, const M2dFieldSet *fs, Gathered *g, PetscMPIInt rank)
{
  M2dMeshArrays ar;
  Vec           xl, xg, seq, held = NULL; /* held: the vector seq holds */
  VecScatter    sc;
  PetscScalar  *xa;
  PetscInt      nv = m->vEnd - m->vStart, *off;

  PetscFunctionBeginUser;
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  PetscCall(PetscMalloc1(nv + 1, &off));
  for (PetscInt v = 0; v < nv; v++) PetscCall(PetscSectionGetOffset(ar.lsec, m->vStart + v, &off[v]));
  PetscCall(DMGetLocalVector(m->dm, &xl));
  PetscCall(DMGetGlobalVector(m->dm, &xg));
  PetscCall(VecGetArray(xl, &xa));
  for (PetscInt v = 0; v < nv; v++) {
    PetscInt coff;
    PetscCall(PetscSectionGetOffset(ar.cs, m->vStart + v, &coff));
    xa[off[v]]     = ar.ca[coff] * L;
    xa[off[v] + 1] = ar.ca[coff + 1] * L;
  }
  PetscCall(VecRestoreArray(xl, &xa));
  PetscCall(MeshArraysClose(&ar));
  PetscCall(DMLocalToGlobal(m->dm, xl, INSERT_VALUES, xg));
  PetscCall(VecScatterCreateToZero(xg, &sc, &seq));
  PetscCall(VecScatterBegin(sc, xg, seq, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, xg, seq, INSERT_VALUES, SCATTER_FORWARD));
  if (rank == 0) {
    const PetscScalar *a;
    PetscCall(PetscMalloc1(2 * g->nv + 1, &g->xy));
    PetscCall(VecGetArrayRead(seq, &a));
    for (PetscInt i = 0; i < 2 * g->nv; i++) g->xy[i] = PetscRealPart(a[i]);
    PetscCall(VecRestoreArrayRead(seq, &a));
  }
  for (PetscInt f = 0; f < fs->npoint; f++) {
    const M2dPointField *pf = &fs->point[f], *next = f + 1 < fs->npoint ? &fs->point[f + 1] : NULL;
    if (!pf->v) { /* values per local vertex: this field and the next of the same array in one pass */
      if (next && (next->v || next->data != pf->data)) next = NULL;
      PetscCall(VecGetArray(xl, &xa));
      for (PetscInt v = 0; v < nv; v++) {
        xa[off[v]]     = pf->data[pf->stride * v + pf->comp];
        xa[off[v] + 1] = next ? next->data[next->stride * v + next->comp] : 0;
      }
      PetscCall(VecRestoreArray(xl, &xa));
      PetscCall(DMLocalToGlobal(m->dm, xl, INSERT_VALUES, xg));
      held = NULL;
    }
    if (pf->v != held || !pf->v) {
      PetscCall(VecScatterBegin(sc, pf->v ? pf->v : xg, seq, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecScatterEnd(sc, pf->v ? pf->v : xg, seq, INSERT_VALUES, SCATTER_FORWARD));
      held = pf->v;
    }
    if (rank == 0) PetscCall(CopyOut(seq, g->nv, pf->v ? pf->vector : PETSC_FALSE, pf->v ? pf->comp : 0, &g->pdata[f]));
    if (!pf->v && next) {
      f++;
      if (rank == 0) PetscCall(CopyOut(seq, g->nv, PETSC_FALSE, 1, &g->pdata[f]));
    }
  }
  PetscCall(PetscFree(off));
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(VecDestroy(&seq));
  PetscCall(DMRestoreLocalVector(m->dm, &xl));
  PetscCall(DMRestoreGlobalVector(m->dm, &xg));
  PetscFunctionReturn(0);
}

/* connectivity in global vertex numbers, then the cell fields, in rank order */
static PetscErrorCode GatherCells(const M2dMesh *m, const M2dFieldSet *fs, Gathered *g, PetscMPIInt rank, PetscMPIInt size)
{
  MPI_Comm     comm = PetscObjectComm((PetscObject)m->dm);
  PetscSection gsec;
  PetscMPIInt  nloc, *counts = NULL, *displs = NULL, *c4 = NULL, *d4 = NULL;
  PetscInt     nlc = m->cEnd - m->cStart;
  int64_t     *lconn;
  double      *lbuf;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(PetscMalloc2(4 * nlc + 1, &lconn, nlc + 1, &lbuf));
  for (PetscInt c = 0; c < nlc; c++)
    for (int k = 0; k < 4; k++) {
      PetscInt goff;
      PetscCall(PetscSectionGetOffset(gsec, m->cellverts[4 * c + k], &goff));
      lconn[4 * c + k] = (goff >= 0 ? goff : -(goff + 1)) / 2;
    }
  nloc = (PetscMPIInt)nlc;
  if (rank == 0) PetscCall(PetscMalloc4(size, &counts, size + 1, &displs, size, &c4, size, &d4));
  PetscCallMPI(MPI_Gather(&nloc, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
  if (rank == 0) {
    displs[0] = 0;
    for (PetscMPIInt r = 0; r < size; r++) {
      displs[r + 1] = displs[r] + counts[r];
      c4[r]         = 4 * counts[r];
      d4[r]         = 4 * displs[r];
    }
    PetscCall(PetscMalloc1(4 * g->nc + 1, &g->conn));
    for (PetscInt f = 0; f < fs->ncell; f++) PetscCall(PetscMalloc1(g->nc + 1, &g->cdata[f]));
  }
  PetscCallMPI(MPI_Gatherv(lconn, 4 * nloc, MPI_INT64_T, g->conn, c4, d4, MPI_INT64_T, 0, comm));
  for (PetscInt f = 0; f < fs->ncell; f++) {
    for (PetscInt c = 0; c < nlc; c++) lbuf[c] = fs->cell[f].data[fs->cell[f].stride * c + fs->cell[f].comp];
    PetscCallMPI(MPI_Gatherv(lbuf, nloc, MPI_DOUBLE, g->cdata[f], counts, displs, MPI_DOUBLE, 0, comm));
  }
  PetscCall(PetscFree2(lconn, lbuf));
  if (rank == 0) PetscCall(PetscFree4(counts, displs, c4, d4));
  PetscFunctionReturn(0);
}

static PetscErrorCode Gather(const M2dMesh *m, PetscReal L, const M2dFieldSet *fs, Gathered *g)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)m->dm);
  PetscMPIInt rank, size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMemzero(g, sizeof(*g)));
  g->nv = m->nvert_global;
  g->nc = m->ncell_global;
  PetscCall(GatherPoints(m, L, fs, g, rank));
  PetscCall(GatherCells(m, fs, g, rank, size));
  PetscFunctionReturn(0);
}

static void GatheredFree(Gathered *g)
{
  PetscFree(g->xy);
  PetscFree(g->conn);
  for (int f = 0; f < M2D_MAX_FIELDS; f++) {
    PetscFree(g->pdata[f]);
    PetscFree(g->cdata[f]);
  }
}

/* ---------- VTU (raw appended binary, UInt64 headers) ---------- */
static void VtuArray(FILE *fp, const char *type, const char *name, int ncomp, uint64_t *offset, uint64_t bytes)
{
  fprintf(fp, "        <DataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%d\" format=\"appended\" offset=\"%llu\"/>\n", type, name, ncomp, (unsigned long long)*offset);
  *offset += sizeof(uint64_t) + bytes;
}

static void VtuBlock(FILE *fp, const void *data, uint64_t bytes)
{
  fwrite(&bytes, sizeof(bytes), 1, fp);
  if (bytes) fwrite(data, 1, (size_t)bytes, fp);
}

/* the VTU header: one DataArray per field, offsets into the appended block */
static void VtuHeader(FILE *fp, const Gathered *g, const M2dFieldSet *fs, const char *run_id)
{
  uint64_t off = 0, nv = (uint64_t)g->nv, nc = (uint64_t)g->nc;

  fprintf(fp, "<?xml version=\"1.0\"?>\n<!-- mortar2d run_id %s -->\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n", run_id);
  fprintf(fp, "  <UnstructuredGrid>\n");
  if (fs->nbody) { /* a string array: each name's characters as numbers, each ended by 0 */
    fprintf(fp, "    <FieldData>\n      <Array type=\"String\" Name=\"body_names\" NumberOfTuples=\"%d\" format=\"ascii\">\n       ", (int)fs->nbody);
    for (PetscInt b = 0; b < fs->nbody; b++)
      for (const char *c = fs->body_names[b];; c++) {
        fprintf(fp, " %d", (int)(unsigned char)*c);
        if (!*c) break;
      }
    fprintf(fp, "\n      </Array>\n    </FieldData>\n");
  }
  fprintf(fp, "    <Piece NumberOfPoints=\"%llu\" NumberOfCells=\"%llu\">\n", (unsigned long long)nv, (unsigned long long)nc);
  fprintf(fp, "      <PointData>\n");
  for (PetscInt k = 0; k < fs->npoint; k++) VtuArray(fp, "Float64", fs->point[k].name, fs->point[k].vector ? 3 : 1, &off, (fs->point[k].vector ? 3 : 1) * nv * sizeof(double));
  fprintf(fp, "      </PointData>\n      <CellData>\n");
  for (PetscInt k = 0; k < fs->ncell; k++) VtuArray(fp, "Float64", fs->cell[k].name, 1, &off, nc * sizeof(double));
  fprintf(fp, "      </CellData>\n      <Points>\n");
  VtuArray(fp, "Float64", "Points", 3, &off, 3 * nv * sizeof(double));
  fprintf(fp, "      </Points>\n      <Cells>\n");
  VtuArray(fp, "Int64", "connectivity", 1, &off, 4 * nc * sizeof(int64_t));
  VtuArray(fp, "Int64", "offsets", 1, &off, nc * sizeof(int64_t));
  VtuArray(fp, "UInt8", "types", 1, &off, nc);
  fprintf(fp, "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _");
}

static PetscErrorCode WriteVTU(FILE *fp, const Gathered *g, const M2dFieldSet *fs, const char *run_id)
{
  uint64_t nv = (uint64_t)g->nv, nc = (uint64_t)g->nc;
  double  *pts;
  int64_t *offs;
  uint8_t *types;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(3 * nv + 1, &pts, nc + 1, &offs, nc + 1, &types));
  for (uint64_t i = 0; i < nv; i++) {
    pts[3 * i]     = g->xy[2 * i];
    pts[3 * i + 1] = g->xy[2 * i + 1];
    pts[3 * i + 2] = 0;
  }
  for (uint64_t c = 0; c < nc; c++) {
    offs[c]  = 4 * (int64_t)(c + 1);
    types[c] = 9; /* VTK_QUAD */
  }
  VtuHeader(fp, g, fs, run_id);
  for (PetscInt k = 0; k < fs->npoint; k++) VtuBlock(fp, g->pdata[k], (fs->point[k].vector ? 3 : 1) * nv * sizeof(double));
  for (PetscInt k = 0; k < fs->ncell; k++) VtuBlock(fp, g->cdata[k], nc * sizeof(double));
  VtuBlock(fp, pts, 3 * nv * sizeof(double));
  VtuBlock(fp, g->conn, 4 * nc * sizeof(int64_t));
  VtuBlock(fp, offs, nc * sizeof(int64_t));
  VtuBlock(fp, types, nc);
  fprintf(fp, "\n  </AppendedData>\n</VTKFile>\n");
  PetscCall(PetscFree3(pts, offs, types));
  PetscFunctionReturn(0);
}

/* ---------- HDF5 + XDMF ---------- */
/* one dataset; no modification times, so that equal runs give equal files */
static herr_t H5Write(hid_t file, const char *name, hid_t type, int rank, hsize_t d0, hsize_t d1, const void *data)
{
  hsize_t dims[2] = {d0, d1};
  hid_t   space   = H5Screate_simple(rank, dims, NULL);
  hid_t   dcpl    = H5Pcreate(H5P_DATASET_CREATE);
  hid_t   ds;
  herr_t  st = -1;
  if (space >= 0 && dcpl >= 0 && H5Pset_obj_track_times(dcpl, 0) >= 0) {
    ds = H5Dcreate2(file, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    if (ds >= 0) {
      st = (d0 == 0) ? 0 : H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
      if (H5Dclose(ds) < 0) st = -1;
    }
  }
  if (dcpl >= 0) H5Pclose(dcpl);
  if (space >= 0) H5Sclose(space);
  return st;
}

static herr_t H5Group(hid_t file, const char *name)
{
  hid_t  gcpl = H5Pcreate(H5P_GROUP_CREATE), grp = -1;
  herr_t st   = -1;
  if (gcpl >= 0 && H5Pset_obj_track_times(gcpl, 0) >= 0) grp = H5Gcreate2(file, name, H5P_DEFAULT, gcpl, H5P_DEFAULT);
  if (grp >= 0) st = H5Gclose(grp);
  if (gcpl >= 0) H5Pclose(gcpl);
  return st;
}

/* the root attribute run_id, a fixed-length string */
static herr_t H5RunId(hid_t file, const char *run_id)
{
  hid_t  type = H5Tcopy(H5T_C_S1), space = H5Screate(H5S_SCALAR), attr = -1;
  herr_t st   = -1;
  if (type >= 0 && space >= 0 && H5Tset_size(type, strlen(run_id)) >= 0) attr = H5Acreate2(file, "run_id", type, space, H5P_DEFAULT, H5P_DEFAULT);
  if (attr >= 0) {
    st = H5Awrite(attr, type, run_id);
    if (H5Aclose(attr) < 0) st = -1;
  }
  if (space >= 0) H5Sclose(space);
  if (type >= 0) H5Tclose(type);
  return st;
}

/* the dataset /body_names: fixed-length strings, the cell field body's names */
static herr_t H5BodyNames(hid_t file, const M2dFieldSet *fs)
{
  size_t len = 1;
  char  *buf;
  hid_t  type;
  herr_t st = -1;
  for (PetscInt b = 0; b < fs->nbody; b++) len = PetscMax(len, strlen(fs->body_names[b]) + 1);
  buf = (char *)calloc((size_t)fs->nbody, len);
  type = H5Tcopy(H5T_C_S1);
  if (buf && type >= 0 && H5Tset_size(type, len) >= 0) {
    for (PetscInt b = 0; b < fs->nbody; b++) memcpy(buf + (size_t)b * len, fs->body_names[b], strlen(fs->body_names[b]));
    st = H5Write(file, "/body_names", type, 1, (hsize_t)fs->nbody, 1, buf);
  }
  if (type >= 0) H5Tclose(type);
  free(buf);
  return st;
}

static herr_t H5Fields(hid_t file, const Gathered *g, const M2dFieldSet *fs, const char *run_id)
{
  herr_t st = 0;
  char   name[256];
  st |= H5RunId(file, run_id);
  if (fs->nbody) st |= H5BodyNames(file, fs);
  st |= H5Group(file, "/geometry");
  st |= H5Group(file, "/topology");
  st |= H5Write(file, "/geometry/vertices", H5T_NATIVE_DOUBLE, 2, (hsize_t)g->nv, 2, g->xy);
  st |= H5Write(file, "/topology/cells", H5T_NATIVE_INT64, 2, (hsize_t)g->nc, 4, g->conn);
  if (fs->npoint) st |= H5Group(file, "/vertex_fields");
  if (fs->ncell) st |= H5Group(file, "/cell_fields");
  for (PetscInt k = 0; k < fs->npoint; k++) {
    if ((size_t)snprintf(name, sizeof(name), "/vertex_fields/%s", fs->point[k].name) >= sizeof(name)) return -1;
    st |= H5Write(file, name, H5T_NATIVE_DOUBLE, fs->point[k].vector ? 2 : 1, (hsize_t)g->nv, 3, g->pdata[k]);
  }
  for (PetscInt k = 0; k < fs->ncell; k++) {
    if ((size_t)snprintf(name, sizeof(name), "/cell_fields/%s", fs->cell[k].name) >= sizeof(name)) return -1;
    st |= H5Write(file, name, H5T_NATIVE_DOUBLE, 1, (hsize_t)g->nc, 1, g->cdata[k]);
  }
  return st;
}

/* an earlier state of a series: its fields in /steps/K/vertex_fields, /steps/K/cell_fields */
static herr_t H5StepFields(hid_t file, PetscInt k, const Gathered *g, const M2dFieldSet *fs)
{
  herr_t st = 0;
  char   name[256];
  if (k == 0) st |= H5Group(file, "/steps");
  snprintf(name, sizeof(name), "/steps/%d", (int)k + 1);
  st |= H5Group(file, name);
  snprintf(name, sizeof(name), "/steps/%d/vertex_fields", (int)k + 1);
  st |= H5Group(file, name);
  snprintf(name, sizeof(name), "/steps/%d/cell_fields", (int)k + 1);
  st |= H5Group(file, name);
  for (PetscInt f = 0; f < fs->npoint; f++) {
    if ((size_t)snprintf(name, sizeof(name), "/steps/%d/vertex_fields/%s", (int)k + 1, fs->point[f].name) >= sizeof(name)) return -1;
    st |= H5Write(file, name, H5T_NATIVE_DOUBLE, fs->point[f].vector ? 2 : 1, (hsize_t)g->nv, 3, g->pdata[f]);
  }
  for (PetscInt f = 0; f < fs->ncell; f++) {
    if ((size_t)snprintf(name, sizeof(name), "/steps/%d/cell_fields/%s", (int)k + 1, fs->cell[f].name) >= sizeof(name)) return -1;
    st |= H5Write(file, name, H5T_NATIVE_DOUBLE, 1, (hsize_t)g->nc, 1, g->cdata[f]);
  }
  return st;
}

static PetscErrorCode WriteH5(const M2dFile *f, const Gathered *g, const M2dFieldSet *fs, const M2dSeries *se, const Gathered *gs, const char *run_id)
{
  hid_t  file, fcpl;
  herr_t st = 0;

  PetscFunctionBeginUser;
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (fcpl >= 0) H5Pset_obj_track_times(fcpl, 0); /* the root group */
  file = H5Fcreate(f->tmp, H5F_ACC_TRUNC, fcpl >= 0 ? fcpl : H5P_DEFAULT, H5P_DEFAULT);
  if (fcpl >= 0) H5Pclose(fcpl);
  if (file < 0) st = -1;
  else {
    st |= H5Fields(file, g, fs, run_id);
    for (PetscInt k = 0; se && k < se->n; k++) st |= H5StepFields(file, k, &gs[k], &se->step[k]);
    if (H5Fclose(file) < 0) st = -1;
  }
  PetscCheck(st >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "writing output file '%s' failed (HDF5)", f->final);
  PetscFunctionReturn(0);
}

/* one grid of an XDMF file: the mesh and the fields fs in the groups under
 * `root` ("" or "/steps/K") of the HDF5 file h5base, at `time` (< 0: none) */
static void WriteXMFGrid(FILE *fp, const char *h5base, const Gathered *g, const M2dFieldSet *fs, const char *root, const char *name, PetscReal time)
{
  long long   nv = (long long)g->nv, nc = (long long)g->nc;
  const char *item = "    <DataItem Dimensions=\"%lld%s\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:%s/%s/%s</DataItem>\n";

  fprintf(fp, "  <Grid Name=\"%s\" GridType=\"Uniform\">\n", name);
  if (time >= 0) fprintf(fp, "   <Time Value=\"%.17g\"/>\n", (double)time);
  fprintf(fp, "   <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"%lld\">\n    <DataItem Dimensions=\"%lld 4\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">%s:/topology/cells</DataItem>\n   </Topology>\n", nc, nc, h5base);
  fprintf(fp, "   <Geometry GeometryType=\"XY\">\n");
  fprintf(fp, item, nv, " 2", h5base, "", "geometry", "vertices");
  fprintf(fp, "   </Geometry>\n");
  for (PetscInt k = 0; k < fs->npoint; k++) {
    fprintf(fp, "   <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", fs->point[k].name, fs->point[k].vector ? "Vector" : "Scalar");
    fprintf(fp, item, nv, fs->point[k].vector ? " 3" : "", h5base, root, "vertex_fields", fs->point[k].name);
    fprintf(fp, "   </Attribute>\n");
  }
  for (PetscInt k = 0; k < fs->ncell; k++) {
    fprintf(fp, "   <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Cell\">\n", fs->cell[k].name);
    fprintf(fp, item, nc, "", h5base, root, "cell_fields", fs->cell[k].name);
    fprintf(fp, "   </Attribute>\n");
  }
  fprintf(fp, "  </Grid>\n");
}

/* XDMF 2 description of the HDF5 file h5base (a name beside it); ParaView's
 * "XDMF Reader" opens it. A series: a temporal collection, one grid per
 * load step, the last one the final state. */
static void WriteXMF(FILE *fp, const char *h5base, const Gathered *g, const M2dFieldSet *fs, const M2dSeries *se, PetscReal time_final, const char *run_id)
{
  fprintf(fp, "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<!-- mortar2d run_id %s -->\n<Xdmf Version=\"2.0\">\n <Domain>\n", run_id);
  if (fs->nbody) { /* the cell field body's names, as "0 name, 1 name, ..." (XML-escaped) */
    fprintf(fp, "  <Information Name=\"body_names\" Value=\"");
    for (PetscInt b = 0; b < fs->nbody; b++) {
      fprintf(fp, "%s%d ", b ? ", " : "", (int)b);
      for (const char *c = fs->body_names[b]; *c; c++) {
        if (*c == '&') fputs("&amp;", fp);
        else if (*c == '<') fputs("&lt;", fp);
        else if (*c == '>') fputs("&gt;", fp);
        else if (*c == '"') fputs("&quot;", fp);
        else fputc(*c, fp);
      }
    }
    fprintf(fp, "\"/>\n");
  }
  if (!se || !se->n) WriteXMFGrid(fp, h5base, g, fs, "", "mortar2d", -1);
  else {
    fprintf(fp, " <Grid Name=\"mortar2d\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
    for (PetscInt k = 0; k < se->n; k++) {
      char root[64], name[64];
      snprintf(root, sizeof(root), "/steps/%d", (int)k + 1);
      snprintf(name, sizeof(name), "step %d", (int)k + 1);
      WriteXMFGrid(fp, h5base, g, &se->step[k], root, name, se->time[k]);
    }
    WriteXMFGrid(fp, h5base, g, fs, "", "final", time_final);
    fprintf(fp, " </Grid>\n");
  }
  fprintf(fp, " </Domain>\n</Xdmf>\n");
}

/* ---------- the run's files ---------- */
PetscErrorCode OutputBegin(MPI_Comm comm, const M2dOutputPaths *paths, M2dOutput *o)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(o, sizeof(*o)));
  o->paths = paths;
  o->comm  = comm;
  PetscCallMPI(MPI_Comm_rank(comm, &o->rank));
  PetscFunctionReturn(0);
}

/* rank 0: the next file of the run (stdio: open for writing) */
static PetscErrorCode AddFile(M2dOutput *o, const char *suffix, PetscBool stdio, M2dFile **f)
{
  char path[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCheck(o->rank == 0 && o->n < M2D_OUTPUT_FILES, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "output: more than %d files, or a file added on rank %d", M2D_OUTPUT_FILES, o->rank);
  if (suffix) PetscCall(M2dPathPrintf(path, sizeof(path), "-output_dir", "%s/%s%s", o->paths->dir, o->paths->name, suffix));
  else PetscCall(PetscStrncpy(path, o->paths->summary_path, sizeof(path)));
  PetscCall(M2dFileOpen(path, stdio, &o->file[o->n]));
  *f = &o->file[o->n++];
  PetscFunctionReturn(0);
}

PetscErrorCode OutputFile(M2dOutput *o, const char *suffix, FILE **fp)
{
  M2dFile *f;

  PetscFunctionBeginUser;
  PetscCall(AddFile(o, suffix, PETSC_TRUE, &f));
  *fp = f->fp;
  PetscFunctionReturn(0);
}

/* rank 0: the field files, one after the other */
static PetscErrorCode WriteFiles(M2dOutput *o, const Gathered *g, const M2dFieldSet *fs, const M2dSeries *se, const Gathered *gs, PetscReal time_final)
{
  const M2dOutputPaths *p = o->paths;
  M2dFile              *f;
  char                  h5base[M2D_NAME_MAX + 1];

  PetscFunctionBeginUser;
  if (p->vtu) {
    PetscCall(AddFile(o, ".vtu", PETSC_TRUE, &f));
    PetscCall(WriteVTU(f->fp, g, fs, p->run_id));
    PetscCall(M2dFileClose(f));
    M2dTestDelay();
  }
  if (p->h5) {
    PetscCall(AddFile(o, ".h5", PETSC_FALSE, &f));
    PetscCall(WriteH5(f, g, fs, se, gs, p->run_id));
    PetscCall(M2dFileClose(f));
    M2dTestDelay();
    PetscCall(M2dPathPrintf(h5base, sizeof(h5base), "-output_name", "%s.h5", p->name));
    PetscCall(AddFile(o, ".xmf", PETSC_TRUE, &f));
    WriteXMF(f->fp, h5base, g, fs, se, time_final, p->run_id);
    PetscCall(M2dFileClose(f));
    M2dTestDelay();
  }
  PetscFunctionReturn(0);
}

PetscErrorCode OutputWriteFields(const M2dMesh *m, PetscReal L, M2dOutput *o, const M2dFieldSet *fs, const M2dSeries *se, PetscReal time_final)
{
  Gathered       g, *gs = NULL;
  char           err[1024] = "";
  PetscErrorCode ierr      = 0;
  PetscInt       ns = se && o->paths->h5 ? se->n : 0;

  PetscFunctionBeginUser;
  if (!o->paths->vtu && !o->paths->h5) PetscFunctionReturn(0);
  PetscCall(Gather(m, L, fs, &g));
  PetscCall(PetscCalloc1(ns + 1, &gs));
  for (PetscInt k = 0; k < ns; k++) PetscCall(Gather(m, L, &se->step[k], &gs[k]));
  if (o->rank == 0) { /* errors here are local to rank 0: catch them and raise them everywhere */
    ierr = WriteFiles(o, &g, fs, ns ? se : NULL, gs, time_final);
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  GatheredFree(&g);
  for (PetscInt k = 0; k < ns; k++) GatheredFree(&gs[k]);
  PetscCall(PetscFree(gs));
  PetscCall(M2dCheckCollective(o->comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

/* a file mortar2d wrote: the run id it carries, where the writers put it */
static PetscBool OursByRunId(const char *path, const char *suffix)
{
  char   head[512] = "";
  FILE  *fp;
  size_t n;

  if (!strcmp(suffix, ".h5")) {
    hid_t     f;
    PetscBool ours = PETSC_FALSE;
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    if (H5Fis_hdf5(path) <= 0 || (f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT)) < 0) return PETSC_FALSE;
    ours = (PetscBool)(H5Aexists(f, "run_id") > 0);
    H5Fclose(f);
    return ours;
  }
  if (!(fp = fopen(path, "rb"))) return PETSC_FALSE;
  n       = fread(head, 1, sizeof(head) - 1, fp);
  head[n] = 0;
  fclose(fp);
  if (!strcmp(suffix, "_contact.csv")) { /* the header's last column */
    char *nl = strchr(head, '\n');
    return (PetscBool)(nl && nl - head >= 7 && !strncmp(nl - 7, ",run_id", 7));
  }
  if (!strcmp(suffix, "_summary.json")) return (PetscBool)(strstr(head, "\"program\": \"mortar2d\"") && strstr(head, "\"run_id\""));
  return (PetscBool)(strstr(head, "<!-- mortar2d run_id ") != NULL);
}

/* Rank 0, once this run's files are in place: the files of the set D/N that
 * this run did not write (-output leaves them out, or the scene has no
 * contact CSV) and that an earlier run of mortar2d wrote (recognised by name
 * and the run id inside) are removed, so that D/N never mixes two runs. Links
 * and anything else are left alone. */
static PetscErrorCode RemoveOtherRuns(M2dOutput *o)
{
  static const char *const suffix[] = {".vtu", ".h5", ".xmf", "_contact.csv", "_summary.json"};
  const M2dOutputPaths    *p        = o->paths;
  char                     gone[5 * PETSC_MAX_PATH_LEN] = "";

  PetscFunctionBeginUser;
  for (int k = 0; k < 5; k++) {
    char        path[PETSC_MAX_PATH_LEN];
    struct stat st, mine;
    PetscBool   written = PETSC_FALSE;
    if ((size_t)snprintf(path, sizeof(path), "%s/%s%s", p->dir, p->name, suffix[k]) >= sizeof(path) || lstat(path, &st) || !S_ISREG(st.st_mode)) continue;
    for (PetscInt j = 0; j < o->n && !written; j++) written = (PetscBool)(!stat(o->file[j].final, &mine) && mine.st_dev == st.st_dev && mine.st_ino == st.st_ino);
    if (written || !OursByRunId(path, suffix[k]) || unlink(path)) continue;
    PetscCall(PetscStrlcat(gone, gone[0] ? ", " : "", sizeof(gone)));
    PetscCall(PetscStrlcat(gone, path, sizeof(gone)));
  }
  if (gone[0]) PetscCall(PetscPrintf(PETSC_COMM_SELF, "output: removed %s: an earlier run's files of the set '%s' that this run did not write (one set, one run)\n", gone, p->name));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputCommit(M2dOutput *o)
{
  char           err[1024] = "";
  PetscErrorCode ierr      = 0;

  PetscFunctionBeginUser;
  if (o->rank == 0) {
    for (PetscInt k = 0; k < o->n && !ierr; k++)
      if (o->file[k].fp) {
        ierr = M2dFileClose(&o->file[k]);
        M2dTestDelay();
      }
    if (!ierr) M2dSignalsAwaitLauncher(); /* results only once a Ctrl-C to mpiexec would have ended the run */
    if (!ierr) ierr = M2dFilePublish(o->n, o->file);
    if (!ierr) ierr = RemoveOtherRuns(o);
    if (ierr) {
      PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
      OutputAbort(o);
    }
  }
  o->n = 0;
  PetscCall(M2dCheckCollective(o->comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

void OutputAbort(M2dOutput *o)
{
  for (PetscInt k = 0; k < o->n; k++) M2dFileAbort(&o->file[k]);
  o->n = 0;
}
