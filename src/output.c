/* output.c - gather to rank 0 and write HDF5/XDMF, VTU and the JSON summary. */
#include "output.h"
#include "util.h"
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

static PetscErrorCode Gather(const M2dMesh *m, const M2dFieldSet *fs, Gathered *g)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)m->dm);
  PetscMPIInt        rank, size, nloc, *counts = NULL, *displs = NULL;
  PetscSection       lsec, gsec, cs;
  Vec                xl, xg, seq;
  VecScatter         sc;
  const PetscScalar *ca;
  PetscScalar       *xa;
  PetscInt           nlc = m->cEnd - m->cStart;
  int64_t           *lconn;
  double            *lbuf;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMemzero(g, sizeof(*g)));
  g->nv = m->nvert_global;
  g->nc = m->ncell_global;
  PetscCall(DMGetLocalSection(m->dm, &lsec));
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  /* coordinates in the dof layout */
  PetscCall(DMGetLocalVector(m->dm, &xl));
  PetscCall(DMGetGlobalVector(m->dm, &xg));
  {
    Vec cl;
    PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
    PetscCall(VecGetArrayRead(cl, &ca));
  }
  PetscCall(VecGetArray(xl, &xa));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt off, coff;
    PetscCall(PetscSectionGetOffset(lsec, v, &off));
    PetscCall(PetscSectionGetOffset(cs, v, &coff));
    xa[off]     = ca[coff];
    xa[off + 1] = ca[coff + 1];
  }
  PetscCall(VecRestoreArray(xl, &xa));
  {
    Vec cl;
    PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
    PetscCall(VecRestoreArrayRead(cl, &ca));
  }
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

  /* cells: connectivity in global vertex numbers, then the cell fields */
  PetscCall(PetscMalloc2(4 * nlc + 1, &lconn, nlc + 1, &lbuf));
  for (PetscInt c = 0; c < nlc; c++)
    for (int k = 0; k < 4; k++) {
      PetscInt goff;
      PetscCall(PetscSectionGetOffset(gsec, m->cellverts[4 * c + k], &goff));
      lconn[4 * c + k] = (goff >= 0 ? goff : -(goff + 1)) / 2;
    }
  nloc = (PetscMPIInt)nlc;
  if (rank == 0) PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCallMPI(MPI_Gather(&nloc, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
  if (rank == 0) {
    displs[0] = 0;
    for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + counts[r];
    PetscCall(PetscMalloc1(4 * g->nc + 1, &g->conn));
    for (PetscInt f = 0; f < fs->ncell; f++) PetscCall(PetscMalloc1(g->nc + 1, &g->cdata[f]));
  }
  {
    PetscMPIInt *c4 = NULL, *d4 = NULL;
    if (rank == 0) {
      PetscCall(PetscMalloc2(size, &c4, size, &d4));
      for (PetscMPIInt r = 0; r < size; r++) {
        c4[r] = 4 * counts[r];
        d4[r] = 4 * displs[r];
      }
    }
    PetscCallMPI(MPI_Gatherv(lconn, 4 * nloc, MPI_INT64_T, g->conn, c4, d4, MPI_INT64_T, 0, comm));
    if (rank == 0) PetscCall(PetscFree2(c4, d4));
  }
  for (PetscInt f = 0; f < fs->ncell; f++) {
    for (PetscInt c = 0; c < nlc; c++) lbuf[c] = fs->cell[f].data[fs->cell[f].stride * c + fs->cell[f].comp];
    PetscCallMPI(MPI_Gatherv(lbuf, nloc, MPI_DOUBLE, g->cdata[f], counts, displs, MPI_DOUBLE, 0, comm));
  }
  PetscCall(PetscFree2(lconn, lbuf));
  if (rank == 0) PetscCall(PetscFree2(counts, displs));
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

static PetscErrorCode WriteVTU(const char *path, const Gathered *g, const M2dFieldSet *fs)
{
  M2dFile  f;
  FILE    *fp;
  uint64_t off = 0, nv = (uint64_t)g->nv, nc = (uint64_t)g->nc;
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
  PetscCall(M2dFileOpen(path, &f));
  fp = f.fp;
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
  for (PetscInt k = 0; k < fs->npoint; k++) VtuBlock(fp, g->pdata[k], (fs->point[k].vector ? 3 : 1) * nv * sizeof(double));
  for (PetscInt k = 0; k < fs->ncell; k++) VtuBlock(fp, g->cdata[k], nc * sizeof(double));
  VtuBlock(fp, pts, 3 * nv * sizeof(double));
  VtuBlock(fp, g->conn, 4 * nc * sizeof(int64_t));
  VtuBlock(fp, offs, nc * sizeof(int64_t));
  VtuBlock(fp, types, nc);
  fprintf(fp, "\n  </AppendedData>\n</VTKFile>\n");
  PetscCall(PetscFree3(pts, offs, types));
  PetscCall(M2dFileCommit(&f));
  PetscFunctionReturn(0);
}

/* ---------- HDF5 + XDMF ---------- */
static herr_t H5Write(hid_t file, const char *name, hid_t type, int rank, hsize_t d0, hsize_t d1, const void *data)
{
  hsize_t dims[2] = {d0, d1};
  hid_t   space   = H5Screate_simple(rank, dims, NULL);
  hid_t   lcpl    = H5Pcreate(H5P_LINK_CREATE);
  hid_t   ds;
  herr_t  st = -1;
  if (space < 0 || lcpl < 0) return -1;
  H5Pset_create_intermediate_group(lcpl, 1);
  ds = H5Dcreate2(file, name, type, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  if (ds >= 0) {
    st = (d0 == 0) ? 0 : H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data);
    if (H5Dclose(ds) < 0) st = -1;
  }
  H5Pclose(lcpl);
  H5Sclose(space);
  return st;
}

static PetscErrorCode WriteHDF5(const char *h5path, const char *xmfpath, const char *h5base, const Gathered *g, const M2dFieldSet *fs)
{
  char    tmp[PETSC_MAX_PATH_LEN + 32];
  hid_t   file;
  herr_t  st = 0;
  M2dFile x;
  FILE   *fp;

  PetscFunctionBeginUser;
  M2dTmpName(h5path, tmp, sizeof(tmp));
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  file = H5Fcreate(tmp, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  PetscCheck(file >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot create output file '%s'", tmp);
  st |= H5Write(file, "/geometry/vertices", H5T_NATIVE_DOUBLE, 2, (hsize_t)g->nv, 2, g->xy);
  st |= H5Write(file, "/topology/cells", H5T_NATIVE_INT64, 2, (hsize_t)g->nc, 4, g->conn);
  for (PetscInt k = 0; k < fs->npoint; k++) {
    char name[256];
    snprintf(name, sizeof(name), "/vertex_fields/%s", fs->point[k].name);
    st |= H5Write(file, name, H5T_NATIVE_DOUBLE, fs->point[k].vector ? 2 : 1, (hsize_t)g->nv, 3, g->pdata[k]);
  }
  for (PetscInt k = 0; k < fs->ncell; k++) {
    char name[256];
    snprintf(name, sizeof(name), "/cell_fields/%s", fs->cell[k].name);
    st |= H5Write(file, name, H5T_NATIVE_DOUBLE, 1, (hsize_t)g->nc, 1, g->cdata[k]);
  }
  if (H5Fclose(file) < 0) st = -1;
  if (st < 0) {
    unlink(tmp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "writing output file '%s' failed", h5path);
  }
  if (rename(tmp, h5path)) {
    unlink(tmp);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename '%s' to '%s'", tmp, h5path);
  }
  /* XDMF 2 description; ParaView's "XDMF Reader" opens it */
  PetscCall(M2dFileOpen(xmfpath, &x));
  fp = x.fp;
  fprintf(fp, "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n <Domain>\n  <Grid Name=\"mortar2d\" GridType=\"Uniform\">\n");
  fprintf(fp, "   <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"%lld\">\n    <DataItem Dimensions=\"%lld 4\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">%s:/topology/cells</DataItem>\n   </Topology>\n", (long long)g->nc, (long long)g->nc, h5base);
  fprintf(fp, "   <Geometry GeometryType=\"XY\">\n    <DataItem Dimensions=\"%lld 2\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:/geometry/vertices</DataItem>\n   </Geometry>\n", (long long)g->nv, h5base);
  for (PetscInt k = 0; k < fs->npoint; k++) {
    if (fs->point[k].vector)
      fprintf(fp, "   <Attribute Name=\"%s\" AttributeType=\"Vector\" Center=\"Node\">\n    <DataItem Dimensions=\"%lld 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:/vertex_fields/%s</DataItem>\n   </Attribute>\n", fs->point[k].name, (long long)g->nv, h5base, fs->point[k].name);
    else
      fprintf(fp, "   <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Node\">\n    <DataItem Dimensions=\"%lld\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:/vertex_fields/%s</DataItem>\n   </Attribute>\n", fs->point[k].name, (long long)g->nv, h5base, fs->point[k].name);
  }
  for (PetscInt k = 0; k < fs->ncell; k++)
    fprintf(fp, "   <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Cell\">\n    <DataItem Dimensions=\"%lld\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:/cell_fields/%s</DataItem>\n   </Attribute>\n", fs->cell[k].name, (long long)g->nc, h5base, fs->cell[k].name);
  fprintf(fp, "  </Grid>\n </Domain>\n</Xdmf>\n");
  PetscCall(M2dFileCommit(&x));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputWrite(const M2dMesh *m, const char *dir, const char *name, PetscBool vtu, PetscBool hdf5, const M2dFieldSet *fs)
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)m->dm);
  PetscMPIInt    rank;
  Gathered       g;
  char           path[PETSC_MAX_PATH_LEN], xmf[PETSC_MAX_PATH_LEN], h5base[PETSC_MAX_PATH_LEN], err[1024] = "";
  PetscErrorCode ierr = 0;

  PetscFunctionBeginUser;
  if (!vtu && !hdf5) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(Gather(m, fs, &g));
  if (rank == 0) {
    /* errors here are local to rank 0: catch them and raise them everywhere */
    if (vtu) {
      PetscCall(PetscSNPrintf(path, sizeof(path), "%s/%s.vtu", dir, name));
      ierr = WriteVTU(path, &g, fs);
    }
    if (!ierr && hdf5) {
      PetscCall(PetscSNPrintf(path, sizeof(path), "%s/%s.h5", dir, name));
      PetscCall(PetscSNPrintf(xmf, sizeof(xmf), "%s/%s.xmf", dir, name));
      PetscCall(PetscSNPrintf(h5base, sizeof(h5base), "%s.h5", name));
      ierr = WriteHDF5(path, xmf, h5base, &g, fs);
    }
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  GatheredFree(&g);
  PetscCall(M2dCheckCollective(comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

/* ---------- summary ---------- */
static void SummaryAdd(M2dSummary *s, const char *section, const char *key, const char *text)
{
  PetscInt i;
  for (i = 0; i < s->n; i++)
    if (!strcmp(s->section[i], section) && !strcmp(s->key[i], key)) break;
  if (i == s->n) {
    if (s->n >= M2D_MAX_SUMMARY) return;
    s->n++;
  }
  snprintf(s->section[i], sizeof(s->section[i]), "%s", section);
  snprintf(s->key[i], sizeof(s->key[i]), "%s", key);
  snprintf(s->value[i], sizeof(s->value[i]), "%s", text);
}

void SummaryReal(M2dSummary *s, const char *section, const char *key, PetscReal v)
{
  char t[64];
  if (PetscIsInfOrNanReal(v)) snprintf(t, sizeof(t), "null");
  else snprintf(t, sizeof(t), "%.17g", (double)v);
  SummaryAdd(s, section, key, t);
}

void SummaryInt(M2dSummary *s, const char *section, const char *key, PetscInt v)
{
  char t[64];
  snprintf(t, sizeof(t), "%lld", (long long)v);
  SummaryAdd(s, section, key, t);
}

void SummaryString(M2dSummary *s, const char *section, const char *key, const char *v)
{
  char   t[256];
  size_t k = 0;
  t[k++]   = '"';
  for (const char *c = v; *c && k < sizeof(t) - 3; c++) {
    if (*c == '"' || *c == '\\') t[k++] = '\\';
    t[k++] = (*c >= 32) ? *c : ' ';
  }
  t[k++] = '"';
  t[k]   = 0;
  SummaryAdd(s, section, key, t);
}

PetscErrorCode SummaryWrite(MPI_Comm comm, const char *path, const M2dSummary *s)
{
  PetscMPIInt    rank;
  PetscErrorCode ierr = 0;
  char           err[1024] = "";

  PetscFunctionBeginUser;
  if (!path || !path[0]) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    M2dFile f;
    ierr = M2dFileOpen(path, &f);
    if (!ierr) {
      const char *sections[M2D_MAX_SUMMARY];
      PetscInt    ns = 0;
      int         first = 1;
      fprintf(f.fp, "{");
      for (PetscInt i = 0; i < s->n; i++) {
        if (s->section[i][0]) {
          PetscInt k;
          for (k = 0; k < ns; k++)
            if (!strcmp(sections[k], s->section[i])) break;
          if (k == ns) sections[ns++] = s->section[i];
          continue;
        }
        fprintf(f.fp, "%s\n  \"%s\": %s", first ? "" : ",", s->key[i], s->value[i]);
        first = 0;
      }
      for (PetscInt k = 0; k < ns; k++) {
        int firstk = 1;
        fprintf(f.fp, "%s\n  \"%s\": {", first ? "" : ",", sections[k]);
        first = 0;
        for (PetscInt i = 0; i < s->n; i++)
          if (!strcmp(s->section[i], sections[k])) {
            fprintf(f.fp, "%s\"%s\": %s", firstk ? "" : ", ", s->key[i], s->value[i]);
            firstk = 0;
          }
        fprintf(f.fp, "}");
      }
      fprintf(f.fp, "\n}\n");
      ierr = M2dFileCommit(&f);
    }
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  PetscCall(M2dCheckCollective(comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}
