/* mesh.c - the bodies in one distributed DMPlex (see mesh.h): MeshCreate reads
 * the files on rank 0 and hands them to the same path as MeshCreateFromMsh;
 * rank 0 merges and checks them (mesh_read.c, mesh_check.c), the plex is built
 * whole on rank 0 or per rank (mesh_plex.c, mesh_distribute.c), and every path
 * ends here: labels of the physical groups, cell lists, the displacement section. */
#include "mesh_impl.h"
#include "util.h"
#include <string.h>

static void LabelName(const char *group, char *out, size_t len)
{
  snprintf(out, len, "m2d:%s", group);
}

/* every rank: the groups and bodies rank 0 found, or its error (lists freed first) */
static PetscErrorCode ShareReadInfo(MPI_Comm comm, M2dScene *s, M2dMesh *m, MeshReadInfo *ri, MeshLists *L)
{
  char err[M2D_ERR_LEN];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Bcast(ri, (int)sizeof(*ri), MPI_BYTE, 0, comm));
  if (ri->err[0]) {
    MeshListsFree(L);
    PetscCall(PetscStrncpy(err, ri->err, sizeof(err)));
    PetscCall(PetscFree(ri));
    SETERRQ(comm, PETSC_ERR_USER_INPUT, "%s", err);
  }
  m->ngroup = ri->ngroup;
  for (PetscInt g = 0; g < ri->ngroup; g++) {
    PetscCall(PetscStrncpy(m->group[g], ri->group[g], M2D_NAME_LEN));
    m->groupdim[g] = ri->groupdim[g];
  }
  if (s->nbody == 0) {
    s->nbody = ri->nbody;
    for (PetscInt b = 0; b < ri->nbody; b++) PetscCall(PetscStrncpy(s->body[b].name, ri->body[b], M2D_NAME_LEN));
  }
  for (PetscInt b = 0; b < ri->nbody; b++)
    if (ri->nflip[b]) PetscCall(PetscPrintf(comm, "mesh: body '%s': %" PetscInt_FMT " clockwise quadrilaterals reoriented\n", ri->body[b], ri->nflip[b]));
  PetscFunctionReturn(0);
}

/* the plex: per rank from rank 0's packages (METIS), or whole on rank 0; the
 * body of each local cell (pbody, by point) and the label points (group, point) */
static PetscErrorCode BuildPlex(MPI_Comm comm, const M2dScene *s, const MeshSkel *sk, const MeshLists *L, DM *dm, PetscInt **pbody, PetscInt **lab, PetscInt *nlab)
{
  PetscMPIInt size;
  PetscInt    nc = L->nc, nv = L->nv, ne = sk->ne;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size > 1 && s->mesh_partitioner == M2D_PARTITIONER_METIS) {
    PetscCall(MeshBuildDistributed(comm, sk, L, dm, pbody, lab, nlab));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MESH_PLEX], 0, 0, 0, 0));
  PetscCall(MeshPlexFromLists(comm, nc, nv, ne, sk->side, sk->ornt, sk->ev, L->coords, dm));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MESH_PLEX], 0, 0, 0, 0));
  PetscCall(PetscMalloc1(nc + nv + ne + 1, pbody));
  for (PetscInt p = 0; p < nc + nv + ne; p++) (*pbody)[p] = p < nc ? L->cellbody[p] : -1;
  PetscCall(PetscMalloc1(2 * L->nent + 1, lab));
  for (PetscInt k = 0; k < L->nent; k++) {
    (*lab)[2 * k]     = L->ent[3 * k];
    (*lab)[2 * k + 1] = L->ent[3 * k + 1] ? nc + nv + L->ent[3 * k + 2] : nc + L->ent[3 * k + 2];
  }
  *nlab = L->nent;
  PetscFunctionReturn(0);
}

/* PETSc's partitioner (-mesh_partitioner petsc, .h5 meshes): DMPlexDistribute, the
 * bodies along its migration SF (cheaper than a label) */
static PetscErrorCode DistributeWithPetsc(const M2dScene *s, DM *dm, PetscInt **pbody)
{
  DM               dist = NULL;
  PetscSF          mig  = NULL;
  PetscPartitioner part;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MESH_PARTITION], 0, 0, 0, 0));
  PetscCall(DMPlexGetPartitioner(*dm, &part));
  PetscCall(PetscPartitionerSetFromOptions(part));
  PetscCall(DMPlexDistribute(*dm, 0, &mig, &dist));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MESH_PARTITION], 0, 0, 0, 0));
  if (dist) {
    PetscInt pStart, pEnd, *nb;
    PetscCall(DMPlexGetChart(dist, &pStart, &pEnd));
    PetscCall(PetscMalloc1(pEnd + 1, &nb));
    for (PetscInt p = 0; p < pEnd; p++) nb[p] = -1;
    PetscCall(PetscSFBcastBegin(mig, MPIU_INT, *pbody, nb, MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(mig, MPIU_INT, *pbody, nb, MPI_REPLACE));
    PetscCall(PetscFree(*pbody));
    *pbody = nb;
    PetscCall(DMDestroy(dm));
    *dm = dist;
  }
  PetscCall(PetscSFDestroy(&mig));
  if (s->mesh_check) PetscCall(DMPlexCheckPointSF(*dm, NULL, PETSC_FALSE));
  PetscFunctionReturn(0);
}

/* cell -> 4 vertices (the first vertex of each cone edge, as the edge's
 * orientation in the cell says), body index; pbody is freed */
static PetscErrorCode CellLists(M2dMesh *m, PetscInt **pbody)
{
  PetscInt nlc = m->cEnd - m->cStart;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(4 * nlc, &m->cellverts, nlc, &m->cellbody));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    const PetscInt *cone, *ornt;
    PetscInt        ncone;
    PetscCall(DMPlexGetConeSize(m->dm, c, &ncone));
    PetscCheck(ncone == 4, PETSC_COMM_SELF, PETSC_ERR_PLIB, "cell %" PetscInt_FMT " has %" PetscInt_FMT " edges", c, ncone);
    PetscCall(DMPlexGetCone(m->dm, c, &cone));
    PetscCall(DMPlexGetConeOrientation(m->dm, c, &ornt));
    for (int k = 0; k < 4; k++) {
      const PetscInt *ev;
      PetscCall(DMPlexGetCone(m->dm, cone[k], &ev));
      m->cellverts[4 * (c - m->cStart) + k] = ornt[k] >= 0 ? ev[0] : ev[1];
    }
    m->cellbody[c - m->cStart] = (*pbody)[c];
    PetscCheck((*pbody)[c] >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "cell %" PetscInt_FMT " lost its body", c);
  }
  PetscCall(PetscFree(*pbody));
  PetscFunctionReturn(0);
}

/* edges owned by another rank (leaves of the point SF) */
static PetscErrorCode EdgeGhosts(M2dMesh *m)
{
  PetscSF         sf;
  PetscInt        nleaves;
  const PetscInt *leaves;

  PetscFunctionBeginUser;
  PetscCall(DMGetPointSF(m->dm, &sf));
  PetscCall(PetscSFGetGraph(sf, NULL, &nleaves, &leaves, NULL));
  PetscCall(PetscCalloc1(m->eEnd - m->eStart + 1, &m->edgeghost));
  for (PetscInt i = 0; i < nleaves; i++) {
    PetscInt p = leaves ? leaves[i] : i;
    if (p >= m->eStart && p < m->eEnd) m->edgeghost[p - m->eStart] = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

/* displacement dofs: 2 per vertex */
static PetscErrorCode DisplacementSection(M2dMesh *m)
{
  PetscSection sec;
  PetscInt     pStart, pEnd;

  PetscFunctionBeginUser;
  PetscCall(PetscSectionCreate(PetscObjectComm((PetscObject)m->dm), &sec));
  PetscCall(PetscSectionSetNumFields(sec, 1));
  PetscCall(PetscSectionSetFieldComponents(sec, 0, 2));
  PetscCall(PetscSectionSetFieldName(sec, 0, "displacement"));
  PetscCall(DMPlexGetChart(m->dm, &pStart, &pEnd));
  PetscCall(PetscSectionSetChart(sec, pStart, pEnd));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscCall(PetscSectionSetDof(sec, v, 2));
    PetscCall(PetscSectionSetFieldDof(sec, v, 0, 2));
  }
  PetscCall(PetscSectionSetUp(sec));
  PetscCall(DMSetLocalSection(m->dm, sec));
  PetscCall(PetscSectionDestroy(&sec));
  PetscFunctionReturn(0);
}

/* global sizes, and a check that the plex kept every cell counter-clockwise */
static PetscErrorCode GlobalSizes(M2dMesh *m)
{
  Vec                cl;
  PetscSection       cs, gs;
  const PetscScalar *ca;
  PetscInt           n[2], bad = 0, ndof;

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(VecGetArrayRead(cl, &ca));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    PetscReal xy[8];
    MeshCellCoordinates(m, ca, cs, c, xy);
    for (int k = 0; k < 4; k++) {
      const PetscReal *p = &xy[2 * k], *q = &xy[2 * ((k + 1) % 4)], *r = &xy[2 * ((k + 3) % 4)];
      bad += !((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]) > 0);
    }
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCheck(!bad, PETSC_COMM_SELF, PETSC_ERR_PLIB, "mesh %s: %" PetscInt_FMT " cell corners lost their orientation in the DMPlex (checked counter-clockwise before: a fault of the program)", m->files, bad);
  PetscCall(DMGetGlobalSection(m->dm, &gs));
  PetscCall(PetscSectionGetStorageSize(gs, &ndof));
  n[0] = m->cEnd - m->cStart;
  n[1] = ndof / 2;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, n, 2, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)m->dm)));
  m->ncell_global = n[0];
  m->nvert_global = n[1];
  PetscFunctionReturn(0);
}

/* Every path ends here with a plex dm (taken), the body of each local cell by
 * point (pbody, taken) and label points lab[2k] = group, lab[2k+1] = point
 * (taken); distribute: PETSc's partitioner distributes dm on several ranks. */
static PetscErrorCode MeshFinish(MPI_Comm comm, const M2dScene *s, M2dMesh *m, DM dm, PetscInt *pbody, PetscInt *lab, PetscInt nlab, PetscBool distribute)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscObjectSetName((PetscObject)dm, "mesh"));
  for (PetscInt g = 0; g < m->ngroup; g++) { /* every group, even where it has no point */
    char lname[M2D_NAME_LEN + 8];
    LabelName(m->group[g], lname, sizeof(lname));
    PetscCall(DMCreateLabel(dm, lname));
  }
  for (PetscInt k = 0; k < nlab; k++) {
    char lname[M2D_NAME_LEN + 8];
    LabelName(m->group[lab[2 * k]], lname, sizeof(lname));
    PetscCall(DMSetLabelValue(dm, lname, lab[2 * k + 1], 1));
  }
  PetscCall(PetscFree(lab));
  if (s->mesh_check) { /* -mesh_check: PETSc's own consistency checks of the plex */
    PetscCall(DMPlexCheckSymmetry(dm));
    PetscCall(DMPlexCheckSkeleton(dm, 0));
    PetscCall(DMPlexCheckFaces(dm, 0));
    PetscCall(DMPlexCheckGeometry(dm));
    if (size > 1) PetscCall(DMPlexCheckPointSF(dm, NULL, PETSC_FALSE));
  }
  if (distribute && size > 1) PetscCall(DistributeWithPetsc(s, &dm, &pbody));
  m->dm = dm;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &m->cStart, &m->cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 1, &m->eStart, &m->eEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &m->vStart, &m->vEnd));
  PetscCall(CellLists(m, &pbody));
  PetscCall(EdgeGhosts(m));
  PetscCall(DisplacementSection(m));
  PetscCall(GlobalSizes(m));
  PetscFunctionReturn(0);
}

/* rank 0: the skeleton, its checks and the group entries; a message in err */
static PetscErrorCode SkeletonAndGroups(const M2dScene *s, M2dMesh *m, const MeshSources *src, MeshLists *L, MeshSkel *sk, char *err, size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MESH_EDGES], 0, 0, 0, 0));
  PetscCall(MeshSkelBuild(L->nc, L->nv, L->cells, sk));
  if (!MeshCheckSkeleton(s, src, L, sk, err, len)) PetscCall(MeshGroupEntries(m, src, L, sk, m->inner, err, len));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MESH_EDGES], 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* The common path of MeshCreate and MeshCreateFromMsh (src->msh used on rank 0 only). */
static PetscErrorCode MeshBuild(MPI_Comm comm, M2dScene *s, const MeshSources *src, M2dMesh *m)
{
  PetscMPIInt   rank;
  MeshReadInfo *ri;
  MeshLists     L;
  MeshSkel      sk;
  DM            dm   = NULL;
  PetscInt     *pbody = NULL, *lab = NULL, nlab = 0;
  char          err[M2D_ERR_LEN] = "";
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscMemzero(&L, sizeof(L)));
  PetscCall(PetscMemzero(&sk, sizeof(sk)));
  PetscCall(PetscStrncpy(m->files, src->all, sizeof(m->files)));
  PetscCall(PetscCalloc1(1, &ri));
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MESH_READ], 0, 0, 0, 0));
  if (rank == 0 && MeshMerge(s, src, ri, &L) && !ri->err[0]) PetscCall(PetscStrncpy(ri->err, "cannot merge the meshes", sizeof(ri->err)));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MESH_READ], 0, 0, 0, 0));
  PetscCall(ShareReadInfo(comm, s, m, ri, &L));
  PetscCall(PetscFree(ri));
  if (rank == 0) PetscCall(SkeletonAndGroups(s, m, src, &L, &sk, err, sizeof(err)));
  if (err[0]) {
    MeshSkelFree(&sk);
    MeshListsFree(&L);
  }
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  PetscCallMPI(MPI_Bcast(m->inner, (int)sizeof(m->inner), MPI_BYTE, 0, comm));
  ierr = BuildPlex(comm, s, &sk, &L, &dm, &pbody, &lab, &nlab);
  if (rank == 0) MeshSkelFree(&sk);
  MeshListsFree(&L);
  PetscCall(ierr);
  PetscCall(MeshFinish(comm, s, m, dm, pbody, lab, nlab, (PetscBool)(s->mesh_partitioner == M2D_PARTITIONER_PETSC)));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshCreateFromMsh(MPI_Comm comm, M2dScene *s, MshMesh msh[], PetscInt nmsh, const char *what, M2dMesh *m)
{
  PetscMPIInt rank;
  MeshSources src;
  char      (*label)[PETSC_MAX_PATH_LEN + 32] = NULL;
  PetscBool   bad;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  PetscCall(M2dLogRegister());
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  bad = (PetscBool)(rank == 0 && (!msh || nmsh < 1));
  PetscCall(M2dCheckCollective(comm, bad, "MeshCreateFromMsh: no mesh given"));
  if (rank != 0) nmsh = 0;
  PetscCall(PetscMalloc1(nmsh + 1, &label));
  PetscCall(PetscMalloc1(nmsh + 1, &src.label));
  for (PetscInt f = 0; f < nmsh; f++) {
    if (nmsh == 1) PetscCall(PetscSNPrintf(label[f], sizeof(label[f]), "mesh '%s'", what));
    else PetscCall(PetscSNPrintf(label[f], sizeof(label[f]), "mesh '%s' (part %" PetscInt_FMT ")", what, f + 1));
    src.label[f] = label[f];
  }
  src.msh  = msh;
  src.nmsh = nmsh;
  src.all  = what;
  ierr     = MeshBuild(comm, s, &src, m);
  PetscCall(PetscFree(src.label));
  PetscCall(PetscFree(label));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

/* the .msh files (or the .h5 of -mesh_save): read on rank 0, then the common path */
static PetscErrorCode CreateFromFiles(MPI_Comm comm, M2dScene *s, M2dMesh *m)
{
  PetscMPIInt rank;
  MshMesh     msh[M2D_MAX_MESH];
  MeshSources src;
  char        label[M2D_MAX_MESH][PETSC_MAX_PATH_LEN + 32], all[M2D_MAX_MESH * (PETSC_MAX_PATH_LEN + 2)] = "", err[M2D_ERR_LEN] = "";
  const char *lp[M2D_MAX_MESH];
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscMemzero(msh, sizeof(msh)));
  for (PetscInt f = 0; f < s->nmesh; f++) {
    if (f) PetscCall(PetscStrlcat(all, ", ", sizeof(all)));
    PetscCall(PetscStrlcat(all, s->mesh[f], sizeof(all)));
    PetscCall(PetscSNPrintf(label[f], sizeof(label[f]), "mesh file '%s'", s->mesh[f]));
    lp[f] = label[f];
  }
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MESH_READ], 0, 0, 0, 0));
  for (PetscInt f = 0; f < s->nmesh && rank == 0 && !err[0]; f++) {
    if (MeshIsHDF5(s->mesh[f])) MeshReadHDF5(s->mesh[f], &msh[f], err, sizeof(err));
    else MshRead(s->mesh[f], &msh[f], err, sizeof(err));
  }
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MESH_READ], 0, 0, 0, 0));
  if (err[0])
    for (int f = 0; f < M2D_MAX_MESH; f++) MshFree(&msh[f]);
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  src.msh   = msh;
  src.nmsh  = rank == 0 ? s->nmesh : 0;
  src.label = lp;
  src.all   = all;
  ierr      = MeshBuild(comm, s, &src, m);
  for (int f = 0; f < M2D_MAX_MESH; f++) MshFree(&msh[f]);
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

PetscErrorCode MeshCreate(MPI_Comm comm, M2dScene *s, M2dMesh *m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  PetscCall(M2dLogRegister());
  PetscCheck(s->nmesh > 0, comm, PETSC_ERR_USER_INPUT, "option -mesh: no mesh file given (for example -mesh meshes/patch_uniform.msh)");
  for (PetscInt f = 0; f < s->nmesh && s->nmesh > 1; f++) PetscCheck(!MeshIsHDF5(s->mesh[f]), comm, PETSC_ERR_USER_INPUT, "option -mesh: a .h5 mesh holds every body: give it alone (%s, with %" PetscInt_FMT " other file%s)", s->mesh[f], s->nmesh - 1, s->nmesh > 2 ? "s" : "");
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MESH_CREATE], 0, 0, 0, 0));
  PetscCall(CreateFromFiles(comm, s, m));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MESH_CREATE], 0, 0, 0, 0));
  if (s->mesh_save[0]) PetscCall(MeshSave(m, s, 1.0, s->mesh_save));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshDestroy(M2dMesh *m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(m->cellverts, m->cellbody));
  PetscCall(PetscFree(m->edgeghost));
  PetscCall(DMDestroy(&m->dm));
  PetscFunctionReturn(0);
}

PetscInt MeshGroupDim(const M2dMesh *m, const char *name)
{
  for (PetscInt g = 0; g < m->ngroup; g++)
    if (!strcmp(m->group[g], name)) return m->groupdim[g];
  return -1;
}

PetscErrorCode MeshGetGroupIS(const M2dMesh *m, const char *name, const char *option, IS *is)
{
  char    lname[M2D_NAME_LEN + 8];
  DMLabel label;

  PetscFunctionBeginUser;
  PetscCheck(MeshGroupDim(m, name) >= 0, PetscObjectComm((PetscObject)m->dm), PETSC_ERR_USER_INPUT, "option %s: mesh file(s) %s have no physical group '%s'", option, m->files, name);
  LabelName(name, lname, sizeof(lname));
  PetscCall(DMGetLabel(m->dm, lname, &label));
  PetscCall(DMLabelGetStratumIS(label, 1, is));
  if (!*is) PetscCall(ISCreateGeneral(PETSC_COMM_SELF, 0, NULL, PETSC_COPY_VALUES, is));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshGroupSize(const M2dMesh *m, const char *name, const char *option, PetscInt *n)
{
  IS is;

  PetscFunctionBeginUser;
  PetscCall(MeshGetGroupIS(m, name, option, &is));
  PetscCall(ISGetLocalSize(is, n));
  PetscCall(ISDestroy(&is));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, n, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)m->dm)));
  PetscFunctionReturn(0);
}

void MeshCellCoordinates(const M2dMesh *m, const PetscScalar *a, PetscSection csec, PetscInt c, PetscReal xy[8])
{
  for (PetscInt k = 0; k < 4; k++) {
    PetscInt off;
    PetscSectionGetOffset(csec, m->cellverts[4 * (c - m->cStart) + k], &off);
    xy[2 * k]     = PetscRealPart(a[off]);
    xy[2 * k + 1] = PetscRealPart(a[off + 1]);
  }
}

PetscErrorCode MeshArraysOpen(const M2dMesh *m, Vec u, M2dMeshArrays *a)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(a, sizeof(*a)));
  a->dm = m->dm;
  PetscCall(DMGetLocalSection(m->dm, &a->lsec));
  PetscCall(DMGetCoordinatesLocal(m->dm, &a->cl));
  PetscCall(DMGetCoordinateSection(m->dm, &a->cs));
  PetscCall(VecGetArrayRead(a->cl, &a->ca));
  if (u) {
    PetscCall(DMGetLocalVector(m->dm, &a->ul));
    PetscCall(DMGlobalToLocal(m->dm, u, INSERT_VALUES, a->ul));
    PetscCall(VecGetArrayRead(a->ul, &a->ua));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MeshArraysClose(M2dMeshArrays *a)
{
  PetscFunctionBeginUser;
  if (a->ul) {
    PetscCall(VecRestoreArrayRead(a->ul, &a->ua));
    PetscCall(DMRestoreLocalVector(a->dm, &a->ul));
  }
  PetscCall(VecRestoreArrayRead(a->cl, &a->ca));
  PetscFunctionReturn(0);
}
