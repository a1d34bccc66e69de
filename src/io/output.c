/* output.c - gather to rank 0 and write HDF5/XDMF and VTU into an output set. */
#include "output.h"
#include "util.h"
#include <errno.h>
#include <hdf5.h>
#include <string.h>
#include <unistd.h>

typedef struct {
  PetscInt   nv, nc;
  double    *xy;    /* 2 per vertex */
  int64_t   *conn;  /* 4 per cell */
  double    *pdata[M2D_MAX_FIELDS]; /* 3 or 1 per vertex */
  double    *cdata[M2D_MAX_FIELDS]; /* 1 per cell */
} Gathered;

static PetscErrorCode GatherVec(Vec v, VecScatter sc, Vec seq, PetscInt nv, PetscBool vector, PetscInt comp, double **out, PetscMPIInt rank)
{
  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(sc, v, seq, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, v, seq, INSERT_VALUES, SCATTER_FORWARD));
  if (rank == 0) {
    const PetscScalar *a;
    PetscInt           nc = vector ? 3 : 1;
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
  }
  PetscFunctionReturn(0);
}

/* vertex coordinates (in the dof layout, so that the fields' scatter serves them) and point fields */
static PetscErrorCode GatherPoints(const M2dMesh *m, const M2dFieldSet *fs, Gathered *g, PetscMPIInt rank)
{
  M2dMeshArrays ar;
  Vec           xl, xg, seq;
  VecScatter    sc;
  PetscScalar  *xa;

  PetscFunctionBeginUser;
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  PetscCall(DMGetLocalVector(m->dm, &xl));
  PetscCall(DMGetGlobalVector(m->dm, &xg));
  PetscCall(VecGetArray(xl, &xa));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt off, coff;
    PetscCall(PetscSectionGetOffset(ar.lsec, v, &off));
    PetscCall(PetscSectionGetOffset(ar.cs, v, &coff));
    xa[off]     = ar.ca[coff];
    xa[off + 1] = ar.ca[coff + 1];
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
  for (PetscInt f = 0; f < fs->npoint; f++) PetscCall(GatherVec(fs->point[f].v, sc, seq, g->nv, fs->point[f].vector, fs->point[f].comp, &g->pdata[f], rank));
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

static PetscErrorCode Gather(const M2dMesh *m, const M2dFieldSet *fs, Gathered *g)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)m->dm);
  PetscMPIInt rank, size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMemzero(g, sizeof(*g)));
  g->nv = m->nvert_global;
  g->nc = m->ncell_global;
  PetscCall(GatherPoints(m, fs, g, rank));
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
static void VtuHeader(FILE *fp, const Gathered *g, const M2dFieldSet *fs)
{
  uint64_t off = 0, nv = (uint64_t)g->nv, nc = (uint64_t)g->nc;

  fprintf(fp, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
  fprintf(fp, "  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"%llu\" NumberOfCells=\"%llu\">\n", (unsigned long long)nv, (unsigned long long)nc);
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

static PetscErrorCode WriteVTU(const char *path, const Gathered *g, const M2dFieldSet *fs)
{
  M2dFile        f;
  uint64_t       nv = (uint64_t)g->nv, nc = (uint64_t)g->nc;
  double        *pts;
  int64_t       *offs;
  uint8_t       *types;
  PetscErrorCode ierr;

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
  ierr = M2dFileOpen(path, &f);
  if (!ierr) {
    VtuHeader(f.fp, g, fs);
    for (PetscInt k = 0; k < fs->npoint; k++) VtuBlock(f.fp, g->pdata[k], (fs->point[k].vector ? 3 : 1) * nv * sizeof(double));
    for (PetscInt k = 0; k < fs->ncell; k++) VtuBlock(f.fp, g->cdata[k], nc * sizeof(double));
    VtuBlock(f.fp, pts, 3 * nv * sizeof(double));
    VtuBlock(f.fp, g->conn, 4 * nc * sizeof(int64_t));
    VtuBlock(f.fp, offs, nc * sizeof(int64_t));
    VtuBlock(f.fp, types, nc);
    fprintf(f.fp, "\n  </AppendedData>\n</VTKFile>\n");
    ierr = M2dFileCommit(&f);
  }
  PetscCall(PetscFree3(pts, offs, types));
  PetscCall(ierr);
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

static herr_t H5Fields(hid_t file, const Gathered *g, const M2dFieldSet *fs)
{
  herr_t st = 0;
  char   name[256];
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

static PetscErrorCode WriteH5(const char *path, const Gathered *g, const M2dFieldSet *fs)
{
  char   tmp[PETSC_MAX_PATH_LEN];
  hid_t  file, fcpl;
  herr_t st = 0;
  int    slot, e = 0;

  PetscFunctionBeginUser;
  PetscCall(M2dTmpName(path, tmp, sizeof(tmp)));
  PetscCall(M2dTempRecord(tmp, PETSC_FALSE, &slot));
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (fcpl >= 0) H5Pset_obj_track_times(fcpl, 0); /* the root group */
  file = H5Fcreate(tmp, H5F_ACC_TRUNC, fcpl >= 0 ? fcpl : H5P_DEFAULT, H5P_DEFAULT);
  if (fcpl >= 0) H5Pclose(fcpl);
  if (file < 0) st = -1;
  else {
    st |= H5Fields(file, g, fs);
    if (H5Fclose(file) < 0) st = -1;
  }
  if (st >= 0 && rename(tmp, path)) e = errno;
  if (st < 0 || e) unlink(tmp);
  M2dTempForget(&slot);
  PetscCheck(st >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "writing output file '%s' failed (HDF5)", M2dPublicName(path, tmp, sizeof(tmp)));
  PetscCheck(!e, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write output file '%s': %s", M2dPublicName(path, tmp, sizeof(tmp)), strerror(e));
  PetscFunctionReturn(0);
}

/* XDMF 2 description of the HDF5 file h5base (a name beside it); ParaView's "XDMF Reader" opens it */
static PetscErrorCode WriteXMF(const char *path, const char *h5base, const Gathered *g, const M2dFieldSet *fs)
{
  M2dFile    f;
  FILE      *fp;
  long long  nv = (long long)g->nv, nc = (long long)g->nc;
  const char *item = "    <DataItem Dimensions=\"%lld%s\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:/%s/%s</DataItem>\n";

  PetscFunctionBeginUser;
  PetscCall(M2dFileOpen(path, &f));
  fp = f.fp;
  fprintf(fp, "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n <Domain>\n  <Grid Name=\"mortar2d\" GridType=\"Uniform\">\n");
  fprintf(fp, "   <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"%lld\">\n    <DataItem Dimensions=\"%lld 4\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">%s:/topology/cells</DataItem>\n   </Topology>\n", nc, nc, h5base);
  fprintf(fp, "   <Geometry GeometryType=\"XY\">\n");
  fprintf(fp, item, nv, " 2", h5base, "geometry", "vertices");
  fprintf(fp, "   </Geometry>\n");
  for (PetscInt k = 0; k < fs->npoint; k++) {
    fprintf(fp, "   <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", fs->point[k].name, fs->point[k].vector ? "Vector" : "Scalar");
    fprintf(fp, item, nv, fs->point[k].vector ? " 3" : "", h5base, "vertex_fields", fs->point[k].name);
    fprintf(fp, "   </Attribute>\n");
  }
  for (PetscInt k = 0; k < fs->ncell; k++) {
    fprintf(fp, "   <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Cell\">\n", fs->cell[k].name);
    fprintf(fp, item, nc, "", h5base, "cell_fields", fs->cell[k].name);
    fprintf(fp, "   </Attribute>\n");
  }
  fprintf(fp, "  </Grid>\n </Domain>\n</Xdmf>\n");
  PetscCall(M2dFileCommit(&f));
  PetscFunctionReturn(0);
}

/* rank 0: the files of the set, one after the other */
static PetscErrorCode WriteFiles(M2dOutputSet set, PetscBool vtu, PetscBool hdf5, const Gathered *g, const M2dFieldSet *fs)
{
  const char *path;
  char        h5base[M2D_NAME_MAX + 1];

  PetscFunctionBeginUser;
  if (vtu) {
    PetscCall(M2dOutputSetFile(set, ".vtu", &path));
    PetscCall(WriteVTU(path, g, fs));
    M2dTestDelay();
  }
  if (hdf5) {
    PetscCall(M2dOutputSetFile(set, ".h5", &path));
    PetscCall(WriteH5(path, g, fs));
    M2dTestDelay();
    PetscCall(M2dPathPrintf(h5base, sizeof(h5base), "-output_name", "%s.h5", M2dOutputSetName(set)));
    PetscCall(M2dOutputSetFile(set, ".xmf", &path));
    PetscCall(WriteXMF(path, h5base, g, fs));
    M2dTestDelay();
  }
  PetscFunctionReturn(0);
}

PetscErrorCode OutputWriteSet(const M2dMesh *m, M2dOutputSet set, PetscBool vtu, PetscBool hdf5, const M2dFieldSet *fs)
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)m->dm);
  PetscMPIInt    rank;
  Gathered       g;
  char           err[1024] = "";
  PetscErrorCode ierr      = 0;

  PetscFunctionBeginUser;
  if (!vtu && !hdf5) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(Gather(m, fs, &g));
  if (rank == 0) { /* errors here are local to rank 0: catch them and raise them everywhere */
    ierr = WriteFiles(set, vtu, hdf5, &g, fs);
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  GatheredFree(&g);
  PetscCall(M2dCheckCollective(comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputWrite(const M2dMesh *m, const char *dir, const char *name, PetscBool vtu, PetscBool hdf5, const M2dFieldSet *fs)
{
  M2dOutputSet   set = NULL;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  if (!vtu && !hdf5) PetscFunctionReturn(0);
  PetscCall(M2dOutputSetBegin(PetscObjectComm((PetscObject)m->dm), dir, name, NULL, PETSC_TRUE, &set));
  ierr = OutputWriteSet(m, set, vtu, hdf5, fs);
  if (ierr) {
    PetscCall(M2dOutputSetAbort(&set));
    PetscCall(ierr);
  }
  PetscCall(M2dOutputSetCommit(&set));
  PetscFunctionReturn(0);
}
