/* mesh_h5.c - the mesh in PETSc's own HDF5 format (see mesh.h): -mesh_save
 * writes the plex as built (DMView, PETSC_VIEWER_HDF5_PETSC: topology,
 * coordinates and every label, the group labels "m2d:NAME" among them) with the
 * body of each cell as the cell label "m2d:body" and, as attributes of the
 * group /m2d, the names and dimensions of the physical groups and the body
 * names. -mesh F.h5 loads it on every rank at once (DMLoad: each rank reads a
 * slice; the bodies leave their label before MeshFinish's DMPlexDistribute
 * balances it): no rank reads the whole mesh. */
#include "options.h"
#include "mesh_impl.h"
#include <petscviewerhdf5.h>
#include "util.h"
#include <errno.h>
#include <stdio.h>
#include <string.h>

#define M2D_H5_GROUP  "/m2d"
#define M2D_H5_FORMAT "mortar2d mesh 1"
#define M2D_BODY_LABEL "m2d:body"

PetscErrorCode MeshReadOptions(MPI_Comm comm, char save[], size_t len)
{
  PetscFunctionBeginUser;
  save[0] = 0;
  PetscOptionsBegin(comm, NULL, "mortar2d mesh output", NULL);
  PetscCall(M2dOptionsString(PetscOptionsObject, "-mesh_save", "write the mesh as built to this .h5 file (PETSc's HDF5 format; read back with -mesh F.h5)", save, len, NULL));
  PetscOptionsEnd();
  PetscCall(M2dOptionsRaise(comm));
  PetscFunctionReturn(0);
}

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

PetscErrorCode MeshSave(const M2dMesh *m, const M2dScene *s, const char *path)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)m->dm);
  PetscMPIInt rank;
  char        tmp[PETSC_MAX_PATH_LEN + 32], err[M2D_ERR_LEN] = "";
  DMLabel     body;
  PetscViewer v;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) { /* every rank writes the same temporary file, renamed when complete */
    FILE *fp;
    char  why[PETSC_MAX_PATH_LEN + 160];
    M2dTmpName(path, tmp, sizeof(tmp));
    if (!MeshIsHDF5(path)) PetscCall(PetscSNPrintf(err, sizeof(err), "option -mesh_save: '%s' does not end in .h5", path));
    else if (M2dCheckReplaceable(path, why, sizeof(why))) PetscCall(PetscSNPrintf(err, sizeof(err), "option -mesh_save: %s", why));
    else if (!(fp = fopen(tmp, "wb"))) PetscCall(PetscSNPrintf(err, sizeof(err), "option -mesh_save: cannot write '%s': %s", path, strerror(errno)));
    else fclose(fp);
  }
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  PetscCallMPI(MPI_Bcast(tmp, (PetscMPIInt)sizeof(tmp), MPI_CHAR, 0, comm));
  PetscCall(DMCreateLabel(m->dm, M2D_BODY_LABEL));
  PetscCall(DMGetLabel(m->dm, M2D_BODY_LABEL, &body));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) PetscCall(DMLabelSetValue(body, c, m->cellbody[c - m->cStart]));
  PetscCall(PetscViewerHDF5Open(comm, tmp, FILE_MODE_WRITE, &v));
  PetscCall(PetscViewerPushFormat(v, PETSC_VIEWER_HDF5_PETSC));
  PetscCall(DMView(m->dm, v));
  PetscCall(PetscViewerPopFormat(v));
  PetscCall(WriteNames(v, m, s));
  PetscCall(PetscViewerDestroy(&v));
  PetscCall(DMRemoveLabel(m->dm, M2D_BODY_LABEL, &body));
  PetscCall(DMLabelDestroy(&body));
  if (rank == 0 && rename(tmp, path)) {
    PetscCall(PetscSNPrintf(err, sizeof(err), "option -mesh_save: cannot write '%s': %s", path, strerror(errno)));
    remove(tmp);
  }
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

/* rank 0: the file opens, as HDF5 too (a failed PetscViewerHDF5Open cannot be
 * cleaned up, and HDF5 prints its own error stack: checked here, quietly) */
static PetscErrorCode CheckFile(const char *path, char *err, size_t len)
{
  static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  unsigned char              head[8];
  FILE                      *fp = fopen(path, "rb");
  H5E_auto2_t                fn = NULL;
  void                      *fd = NULL;
  hid_t                      id;

  PetscFunctionBeginUser;
  if (!fp) {
    PetscCall(PetscSNPrintf(err, len, "cannot open mesh file '%s': %s", path, strerror(errno)));
    PetscFunctionReturn(0);
  }
  if (fread(head, 1, 8, fp) != 8 || memcmp(head, sig, 8)) PetscCall(PetscSNPrintf(err, len, "mesh file '%s' is not an HDF5 file (.h5 meshes are written by -mesh_save)", path));
  fclose(fp);
  if (err[0]) PetscFunctionReturn(0);
  H5open(); /* before any H5E call */
  H5Eget_auto2(H5E_DEFAULT, &fn, &fd);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  id = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) PetscCall(PetscSNPrintf(err, len, "mesh file '%s' cannot be read as a mesh saved by -mesh_save (truncated or corrupted?)", path));
  else H5Fclose(id);
  H5Eset_auto2(H5E_DEFAULT, fn, fd);
  PetscFunctionReturn(0);
}

/* the groups and bodies saved in /m2d; the scene's bodies (if -bodies names them)
 * must be among them: bmap[saved body] = scene body index, -1 if not a body */
static PetscErrorCode ReadNames(PetscViewer v, const char *path, M2dScene *s, M2dMesh *m, PetscInt bmap[], char saved[][M2D_NAME_LEN])
{
  MPI_Comm  comm = PetscObjectComm((PetscObject)v);
  char      key[32], *str;
  PetscInt  nbody, zero = 0;
  PetscBool has;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5HasAttribute(v, M2D_H5_GROUP, "format", &has));
  PetscCheck(has, comm, PETSC_ERR_USER_INPUT, "mesh file '%s' holds no mortar2d mesh (write one with -mesh_save)", path);
  PetscCall(PetscViewerHDF5ReadAttribute(v, M2D_H5_GROUP, "ngroup", PETSC_INT, &zero, &m->ngroup));
  PetscCall(PetscViewerHDF5ReadAttribute(v, M2D_H5_GROUP, "nbody", PETSC_INT, &zero, &nbody));
  PetscCheck(m->ngroup >= 0 && m->ngroup <= M2D_MAX_GROUPS && nbody > 0 && nbody <= M2D_MAX_BODIES, comm, PETSC_ERR_USER_INPUT, "mesh file '%s': %" PetscInt_FMT " groups, %" PetscInt_FMT " bodies (corrupted?)", path, m->ngroup, nbody);
  for (PetscInt g = 0; g < m->ngroup; g++) {
    PetscCall(PetscSNPrintf(key, sizeof(key), "group%" PetscInt_FMT, g));
    PetscCall(PetscViewerHDF5ReadAttribute(v, M2D_H5_GROUP, key, PETSC_STRING, NULL, &str));
    PetscCall(PetscStrncpy(m->group[g], str, M2D_NAME_LEN));
    PetscCall(PetscFree(str));
    PetscCall(PetscSNPrintf(key, sizeof(key), "groupdim%" PetscInt_FMT, g));
    PetscCall(PetscViewerHDF5ReadAttribute(v, M2D_H5_GROUP, key, PETSC_INT, &zero, &m->groupdim[g]));
  }
  for (PetscInt b = 0; b < nbody; b++) {
    PetscCall(PetscSNPrintf(key, sizeof(key), "body%" PetscInt_FMT, b));
    PetscCall(PetscViewerHDF5ReadAttribute(v, M2D_H5_GROUP, key, PETSC_STRING, NULL, &str));
    PetscCall(PetscStrncpy(saved[b], str, M2D_NAME_LEN));
    PetscCall(PetscFree(str));
  }
  if (s->nbody == 0) {
    s->nbody = nbody;
    for (PetscInt b = 0; b < nbody; b++) PetscCall(PetscStrncpy(s->body[b].name, saved[b], M2D_NAME_LEN));
  }
  for (PetscInt k = 0; k < s->nbody; k++) {
    PetscInt b = -1;
    for (PetscInt j = 0; j < nbody && b < 0; j++)
      if (!strcmp(saved[j], s->body[k].name)) b = j;
    PetscCheck(b >= 0, comm, PETSC_ERR_USER_INPUT, "option -bodies: mesh file(s) %s have no physical surface '%s'", path, s->body[k].name);
    bmap[b] = k;
  }
  PetscFunctionReturn(0);
}

/* the body of each local cell (by point) from the label; the label removed */
static PetscErrorCode BodiesFromLabel(DM dm, const char *path, const PetscInt bmap[], char saved[][M2D_NAME_LEN], PetscInt **pbody)
{
  DMLabel   label;
  PetscInt  cStart, cEnd, pEnd, badval = 0;
  PetscBool bad = PETSC_FALSE;
  char      err[M2D_ERR_LEN] = "";

  PetscFunctionBeginUser;
  PetscCall(DMGetLabel(dm, M2D_BODY_LABEL, &label));
  PetscCheck(label, PetscObjectComm((PetscObject)dm), PETSC_ERR_USER_INPUT, "mesh file '%s' has no cell label '%s' (not written by -mesh_save?)", path, M2D_BODY_LABEL);
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetChart(dm, NULL, &pEnd));
  PetscCall(PetscMalloc1(pEnd + 1, pbody));
  for (PetscInt p = 0; p < pEnd; p++) (*pbody)[p] = -1;
  for (PetscInt c = cStart; c < cEnd; c++) {
    PetscInt b;
    PetscCall(DMLabelGetValue(label, c, &b));
    (*pbody)[c] = b >= 0 && b < M2D_MAX_BODIES ? bmap[b] : -1;
    if ((*pbody)[c] < 0 && !bad) bad = PETSC_TRUE, badval = b;
  }
  if (bad) PetscCall(PetscSNPrintf(err, sizeof(err), "mesh file '%s': cells of %s%s%s are in no body of this run (see -bodies)", path, badval >= 0 && badval < M2D_MAX_BODIES ? "physical surface '" : "no physical surface", badval >= 0 && badval < M2D_MAX_BODIES ? saved[badval] : "", badval >= 0 && badval < M2D_MAX_BODIES ? "'" : ""));
  PetscCall(DMRemoveLabel(dm, M2D_BODY_LABEL, &label));
  PetscCall(DMLabelDestroy(&label));
  if (err[0]) PetscCall(PetscFree(*pbody));
  PetscCall(M2dCheckCollective(PetscObjectComm((PetscObject)dm), err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

/* dm from the file, HDF5's own error printing off and PETSc's errors turned into
 * one line naming the file (a truncated or corrupted file fails inside HDF5) */
static PetscErrorCode LoadPlex(MPI_Comm comm, const char *path, M2dScene *s, M2dMesh *m, PetscInt bmap[], char saved[][M2D_NAME_LEN], DM *dm)
{
  PetscViewer    v  = NULL;
  H5E_auto2_t    fn = NULL;
  void          *fd = NULL;
  PetscErrorCode ierr, named = 0;

  PetscFunctionBeginUser;
  *dm = NULL;
  H5open(); /* before any H5E call */
  H5Eget_auto2(H5E_DEFAULT, &fn, &fd);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  ierr = PetscViewerHDF5Open(comm, path, FILE_MODE_READ, &v);
  if (!ierr) {
    PetscCall(PetscPopErrorHandler());
    named = ReadNames(v, path, s, m, bmap, saved); /* errors with its own messages */
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  }
  if (!ierr && !named) ierr = DMCreate(comm, dm) || DMSetType(*dm, DMPLEX) || PetscObjectSetName((PetscObject)*dm, "mesh") || PetscViewerPushFormat(v, PETSC_VIEWER_HDF5_PETSC) || DMLoad(*dm, v) || PetscViewerPopFormat(v);
  (void)PetscViewerDestroy(&v); /* after a failed open it fails too: quietly */
  if (ierr || named) (void)DMDestroy(dm);
  PetscCall(PetscPopErrorHandler());
  H5Eset_auto2(H5E_DEFAULT, fn, fd);
  PetscCall(named);
  PetscCheck(!ierr, comm, PETSC_ERR_FILE_READ, "mesh file '%s' cannot be read as a mesh saved by -mesh_save (truncated or corrupted?)", path);
  PetscFunctionReturn(0);
}

PetscErrorCode MeshLoad(MPI_Comm comm, M2dScene *s, const char *path, M2dMesh *m)
{
  PetscMPIInt rank;
  DM          dm;
  PetscInt   *pbody, bmap[M2D_MAX_BODIES];
  char        err[M2D_ERR_LEN] = "", saved[M2D_MAX_BODIES][M2D_NAME_LEN];
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscStrncpy(m->files, path, sizeof(m->files)));
  for (PetscInt b = 0; b < M2D_MAX_BODIES; b++) bmap[b] = -1, saved[b][0] = 0;
  if (rank == 0) PetscCall(CheckFile(path, err, sizeof(err)));
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MESH_READ], 0, 0, 0, 0));
  PetscCall(LoadPlex(comm, path, s, m, bmap, saved, &dm));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MESH_READ], 0, 0, 0, 0));
  ierr = BodiesFromLabel(dm, path, bmap, saved, &pbody);
  if (ierr) PetscCall(DMDestroy(&dm));
  PetscCall(ierr);
  PetscCall(MeshFinish(comm, s, m, dm, pbody, NULL, 0, PETSC_TRUE)); /* DMLoad gave every rank a slice of the file: balanced there */
  PetscFunctionReturn(0);
}
