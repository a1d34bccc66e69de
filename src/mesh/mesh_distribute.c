/* mesh_distribute.c - several ranks, -mesh_partitioner metis (see mesh_impl.h):
 * rank 0 splits the cells with libmetis and sends every rank its cells,
 * vertices and edges with their point-SF leaves (a vertex or edge belongs to the
 * lowest rank holding one of its cells), its group entries and cell bodies;
 * every rank builds its own plex. No DMPlexDistribute (the README has the timings). */
#include "mesh_impl.h"
#include <metis.h>
#include "util.h"

/* One rank's package: a header of counts, then the integer lists in this order
 * (PackLayout), and the 2 coordinates of each of its vertices as reals. */
typedef struct {
  PetscInt ncell, nvert, nedge; /* local points: cells, then vertices, then edges */
  PetscInt nleaf;               /* vertices and edges owned by another rank */
  PetscInt nlabel;              /* (group, local point) pairs */
  PetscInt nint;                /* length of the integer package, header included */
} PackHeader;
#define PACK_HEADER_INTS ((PetscInt)(sizeof(PackHeader) / sizeof(PetscInt)))

typedef struct {
  PetscInt *cone;  /* 4 local edges per cell */
  PetscInt *ornt;  /* 4 edge orientations per cell */
  PetscInt *body;  /* body index per cell */
  PetscInt *econe; /* 2 local vertices per edge */
  PetscInt *leaf;  /* 3 per leaf: local point, owner rank, point on the owner */
  PetscInt *label; /* 2 per group entry: group index, local point */
} PackLists;

static PetscInt PackInts(const PackHeader *h)
{
  return PACK_HEADER_INTS + 9 * h->ncell + 2 * h->nedge + 3 * h->nleaf + 2 * h->nlabel;
}

static void PackLayout(PetscInt buf[], const PackHeader *h, PackLists *pl)
{
  pl->cone  = buf + PACK_HEADER_INTS;
  pl->ornt  = pl->cone + 4 * h->ncell;
  pl->body  = pl->ornt + 4 * h->ncell;
  pl->econe = pl->body + h->ncell;
  pl->leaf  = pl->econe + 2 * h->nedge;
  pl->label = pl->leaf + 3 * h->nleaf;
}

/* rank 0: the part of every cell, libmetis on the cells sharing an edge; 0 or a message in err */
static PetscErrorCode PartitionCells(const MeshSkel *sk, PetscMPIInt size, PetscInt where[], char *err, size_t len)
{
  idx_t   *xadj, *adj, *part, nvtx = (idx_t)sk->nc, ncon = 1, nparts = size, objval = 0, opts[METIS_NOPTIONS];
  int      rc = METIS_OK;
  PetscInt k  = 0;

  PetscFunctionBeginUser;
  if (sk->nc < size) {
    PetscCall(PetscSNPrintf(err, len, "option -mesh_partitioner metis: %" PetscInt_FMT " cells cannot be split over %d ranks", sk->nc, (int)size));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscMalloc3(sk->nc + 1, &xadj, 4 * sk->nc + 1, &adj, sk->nc + 1, &part));
  xadj[0] = 0;
  for (PetscInt c = 0; c < sk->nc; c++) {
    for (int j = 0; j < 4; j++) {
      PetscInt e = sk->side[4 * c + j], o = sk->ecell[2 * e] == c ? sk->ecell[2 * e + 1] : sk->ecell[2 * e];
      if (o >= 0) adj[k++] = (idx_t)o;
    }
    xadj[c + 1] = (idx_t)k;
  }
  METIS_SetDefaultOptions(opts);
  opts[METIS_OPTION_NUMBERING] = 0;
  rc = METIS_PartGraphRecursive(&nvtx, &ncon, xadj, adj, NULL, NULL, NULL, &nparts, NULL, NULL, opts, &objval, part);
  M2dMetisSignal((int)rc, METIS_ERROR); /* a SIGTERM that GKlib trapped */
  if (rc != METIS_OK) PetscCall(PetscSNPrintf(err, len, "option -mesh_partitioner metis: METIS_PartGraphRecursive failed (%d) on %" PetscInt_FMT " cells for %d ranks", rc, sk->nc, (int)size));
  PetscCall(PetscInfo(NULL, "METIS: %" PetscInt_FMT " cells in %d parts, %ld cut edges\n", sk->nc, (int)size, (long)objval));
  for (PetscInt c = 0; c < sk->nc; c++) where[c] = (PetscInt)part[c];
  PetscCall(PetscFree3(xadj, adj, part));
  PetscFunctionReturn(0);
}

/* rank 0: who owns what, and every rank's cells (in file order), vertices and edges */
typedef struct {
  PetscMPIInt size;
  PetscInt   *where;          /* rank of each cell */
  PetscInt   *vown, *eown;    /* owner rank of each vertex, edge */
  PetscInt   *vidx, *eidx;    /* index among the owner's vertices, edges */
  PetscInt   *vst, *est;      /* scratch: last rank that marked it */
  PetscInt  **cl, **vl, **el; /* per rank: its cells, vertices, edges (global ids, ascending) */
  PetscInt   *ncp, *nvp, *nep;
} RankLists;

static PetscErrorCode RankListsCreate(const MeshSkel *sk, RankLists *R)
{
  PetscInt nc = sk->nc, nv = sk->nv, ne = sk->ne;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(nv + 1, &R->vown, nv + 1, &R->vidx, nv + 1, &R->vst));
  PetscCall(PetscMalloc3(ne + 1, &R->eown, ne + 1, &R->eidx, ne + 1, &R->est));
  PetscCall(PetscCalloc6(R->size, &R->vl, R->size, &R->el, R->size, &R->cl, R->size, &R->ncp, R->size, &R->nvp, R->size, &R->nep));
  for (PetscInt v = 0; v < nv; v++) R->vown[v] = R->size, R->vst[v] = -1;
  for (PetscInt e = 0; e < ne; e++) R->eown[e] = R->size, R->est[e] = -1;
  for (PetscInt c = 0; c < nc; c++) {
    R->ncp[R->where[c]]++;
    for (int j = 0; j < 4; j++) {
      R->vown[sk->cells[4 * c + j]] = PetscMin(R->vown[sk->cells[4 * c + j]], R->where[c]);
      R->eown[sk->side[4 * c + j]]  = PetscMin(R->eown[sk->side[4 * c + j]], R->where[c]);
    }
  }
  /* marked, then collected in one sweep: linear time, no sorting */
  for (PetscMPIInt p = 0; p < R->size; p++) {
    PetscInt n = 0, nvm = 0, nem = 0;
    PetscCall(PetscMalloc1(R->ncp[p] + 1, &R->cl[p]));
    for (PetscInt c = 0; c < nc; c++)
      if (R->where[c] == p) {
        R->cl[p][n++] = c;
        for (int j = 0; j < 4; j++) {
          PetscInt v = sk->cells[4 * c + j], e = sk->side[4 * c + j];
          if (R->vst[v] != p) R->vst[v] = p, nvm++;
          if (R->est[e] != p) R->est[e] = p, nem++;
        }
      }
    PetscCall(PetscMalloc2(nvm + 1, &R->vl[p], nem + 1, &R->el[p]));
    for (PetscInt v = 0; v < nv; v++)
      if (R->vst[v] == p) {
        if (R->vown[v] == p) R->vidx[v] = R->nvp[p];
        R->vl[p][R->nvp[p]++] = v;
      }
    for (PetscInt e = 0; e < ne; e++)
      if (R->est[e] == p) {
        if (R->eown[e] == p) R->eidx[e] = R->nep[p];
        R->el[p][R->nep[p]++] = e;
      }
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode RankListsDestroy(RankLists *R)
{
  PetscFunctionBeginUser;
  for (PetscMPIInt p = 0; p < R->size && R->cl; p++) {
    PetscCall(PetscFree(R->cl[p]));
    PetscCall(PetscFree2(R->vl[p], R->el[p]));
  }
  PetscCall(PetscFree6(R->vl, R->el, R->cl, R->ncp, R->nvp, R->nep));
  PetscCall(PetscFree3(R->vown, R->vidx, R->vst));
  PetscCall(PetscFree3(R->eown, R->eidx, R->est));
  PetscCall(PetscFree(R->where));
  PetscFunctionReturn(0);
}

/* rank 0: rank p's package; vloc/eloc (global -> local, -1 elsewhere) are scratch, left all -1 */
static PetscErrorCode PackRank(const MeshSkel *sk, const MeshLists *L, const RankLists *R, PetscMPIInt p, PetscInt vloc[], PetscInt eloc[], PetscInt **ibuf, PetscReal **rbuf)
{
  PackHeader h = {R->ncp[p], R->nvp[p], R->nep[p], 0, 0, 0};
  PackLists  pl;
  PetscInt   nleaf = 0, nlab = 0;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < h.nvert; i++) vloc[R->vl[p][i]] = i, h.nleaf += R->vown[R->vl[p][i]] != p;
  for (PetscInt i = 0; i < h.nedge; i++) eloc[R->el[p][i]] = i, h.nleaf += R->eown[R->el[p][i]] != p;
  for (PetscInt k = 0; k < L->nent; k++) h.nlabel += (L->ent[3 * k + 1] ? eloc[L->ent[3 * k + 2]] : vloc[L->ent[3 * k + 2]]) >= 0;
  h.nint = PackInts(&h);
  PetscCall(PetscMalloc1(h.nint, ibuf));
  PetscCall(PetscMalloc1(2 * h.nvert + 1, rbuf));
  PetscCall(PetscMemcpy(*ibuf, &h, sizeof(h)));
  PackLayout(*ibuf, &h, &pl);
  for (PetscInt i = 0; i < h.ncell; i++) {
    PetscInt c = R->cl[p][i];
    for (int j = 0; j < 4; j++) pl.cone[4 * i + j] = eloc[sk->side[4 * c + j]], pl.ornt[4 * i + j] = sk->ornt[4 * c + j];
    pl.body[i] = L->cellbody[c];
  }
  for (PetscInt i = 0; i < h.nedge; i++) pl.econe[2 * i] = vloc[sk->ev[2 * R->el[p][i]]], pl.econe[2 * i + 1] = vloc[sk->ev[2 * R->el[p][i] + 1]];
  for (PetscInt i = 0; i < h.nvert; i++) { /* points: cells, vertices, edges */
    PetscInt v = R->vl[p][i], o = R->vown[v];
    (*rbuf)[2 * i] = L->coords[2 * v], (*rbuf)[2 * i + 1] = L->coords[2 * v + 1];
    if (o == p) continue;
    pl.leaf[3 * nleaf] = h.ncell + i, pl.leaf[3 * nleaf + 1] = o, pl.leaf[3 * nleaf + 2] = R->ncp[o] + R->vidx[v];
    nleaf++;
  }
  for (PetscInt i = 0; i < h.nedge; i++) {
    PetscInt e = R->el[p][i], o = R->eown[e];
    if (o == p) continue;
    pl.leaf[3 * nleaf] = h.ncell + h.nvert + i, pl.leaf[3 * nleaf + 1] = o, pl.leaf[3 * nleaf + 2] = R->ncp[o] + R->nvp[o] + R->eidx[e];
    nleaf++;
  }
  for (PetscInt k = 0; k < L->nent; k++) {
    PetscInt loc = L->ent[3 * k + 1] ? eloc[L->ent[3 * k + 2]] : vloc[L->ent[3 * k + 2]];
    if (loc < 0) continue;
    pl.label[2 * nlab]     = L->ent[3 * k];
    pl.label[2 * nlab + 1] = L->ent[3 * k + 1] ? h.ncell + h.nvert + loc : h.ncell + loc;
    nlab++;
  }
  PetscCheck(nleaf == h.nleaf && nlab == h.nlabel, PETSC_COMM_SELF, PETSC_ERR_PLIB, "mesh package for rank %d: %" PetscInt_FMT " leaves, %" PetscInt_FMT " labels counted, %" PetscInt_FMT ", %" PetscInt_FMT " filled", (int)p, h.nleaf, h.nlabel, nleaf, nlab);
  for (PetscInt i = 0; i < h.nvert; i++) vloc[R->vl[p][i]] = -1;
  for (PetscInt i = 0; i < h.nedge; i++) eloc[R->el[p][i]] = -1;
  PetscFunctionReturn(0);
}

/* rank 0: send every other rank its package, keep its own (built last) */
static PetscErrorCode SendPackages(MPI_Comm comm, const MeshSkel *sk, const MeshLists *L, RankLists *R, PetscInt **ibuf, PetscReal **rbuf)
{
  PetscInt *vloc, *eloc;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(sk->nv + 1, &vloc, sk->ne + 1, &eloc));
  for (PetscInt v = 0; v < sk->nv; v++) vloc[v] = -1;
  for (PetscInt e = 0; e < sk->ne; e++) eloc[e] = -1;
  for (PetscMPIInt p = R->size - 1; p >= 0; p--) {
    PetscInt   *ip;
    PetscReal  *rp;
    PetscMPIInt nim, nrm;
    PackHeader  h;
    PetscCall(PackRank(sk, L, R, p, vloc, eloc, &ip, &rp));
    if (p == 0) {
      *ibuf = ip, *rbuf = rp;
      break;
    }
    PetscCall(PetscMemcpy(&h, ip, sizeof(h)));
    PetscCall(PetscMPIIntCast(h.nint, &nim));
    PetscCall(PetscMPIIntCast(2 * R->nvp[p], &nrm));
    PetscCallMPI(MPI_Send(ip, (PetscMPIInt)PACK_HEADER_INTS, MPIU_INT, p, 0, comm));
    PetscCallMPI(MPI_Send(ip, nim, MPIU_INT, p, 1, comm));
    PetscCallMPI(MPI_Send(rp, nrm, MPIU_REAL, p, 2, comm));
    PetscCall(PetscFree(ip));
    PetscCall(PetscFree(rp));
  }
  PetscCall(PetscFree2(vloc, eloc));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReceivePackage(MPI_Comm comm, PetscInt **ibuf, PetscReal **rbuf)
{
  PackHeader  h;
  PetscMPIInt nim, nrm;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Recv(&h, (PetscMPIInt)PACK_HEADER_INTS, MPIU_INT, 0, 0, comm, MPI_STATUS_IGNORE));
  PetscCall(PetscMPIIntCast(h.nint, &nim));
  PetscCall(PetscMPIIntCast(2 * h.nvert, &nrm));
  PetscCall(PetscMalloc1(h.nint, ibuf));
  PetscCall(PetscMalloc1(2 * h.nvert + 1, rbuf));
  PetscCallMPI(MPI_Recv(*ibuf, nim, MPIU_INT, 0, 1, comm, MPI_STATUS_IGNORE));
  PetscCallMPI(MPI_Recv(*rbuf, nrm, MPIU_REAL, 0, 2, comm, MPI_STATUS_IGNORE));
  PetscFunctionReturn(0);
}

/* every rank: its plex from its package, the point SF from the leaves */
static PetscErrorCode BuildFromPackage(MPI_Comm comm, PetscInt ibuf[], const PetscReal rbuf[], DM *dm, PetscInt **pbody, PetscInt **lab, PetscInt *nlab)
{
  PackHeader   h;
  PackLists    pl;
  PetscInt     np, *ilocal;
  PetscSFNode *iremote;
  PetscSF      sf;
  DM           cdm;

  PetscFunctionBeginUser;
  PetscCall(PetscMemcpy(&h, ibuf, sizeof(h)));
  PackLayout(ibuf, &h, &pl);
  np = h.ncell + h.nvert + h.nedge;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MESH_PLEX], 0, 0, 0, 0));
  PetscCall(MeshPlexFromLists(comm, h.ncell, h.nvert, h.nedge, pl.cone, pl.ornt, pl.econe, rbuf, dm));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MESH_PLEX], 0, 0, 0, 0));
  PetscCall(PetscMalloc1(h.nleaf + 1, &ilocal));
  PetscCall(PetscMalloc1(h.nleaf + 1, &iremote));
  for (PetscInt i = 0; i < h.nleaf; i++) {
    ilocal[i]        = pl.leaf[3 * i];
    iremote[i].rank  = pl.leaf[3 * i + 1];
    iremote[i].index = pl.leaf[3 * i + 2];
  }
  PetscCall(PetscSFCreate(comm, &sf));
  PetscCall(PetscSFSetGraph(sf, np, h.nleaf, ilocal, PETSC_OWN_POINTER, iremote, PETSC_OWN_POINTER));
  PetscCall(DMSetPointSF(*dm, sf));
  PetscCall(DMGetCoordinateDM(*dm, &cdm));
  PetscCall(DMSetPointSF(cdm, sf));
  PetscCall(PetscSFDestroy(&sf));
  PetscCall(PetscMalloc1(np + 1, pbody));
  for (PetscInt i = 0; i < np; i++) (*pbody)[i] = i < h.ncell ? pl.body[i] : -1;
  PetscCall(PetscMalloc1(2 * h.nlabel + 1, lab));
  PetscCall(PetscArraycpy(*lab, pl.label, 2 * h.nlabel));
  *nlab = h.nlabel;
  PetscFunctionReturn(0);
}

PetscErrorCode MeshBuildDistributed(MPI_Comm comm, const MeshSkel *sk, const MeshLists *L, DM *dm, PetscInt **pbody, PetscInt **lab, PetscInt *nlab)
{
  PetscMPIInt rank;
  PetscInt   *ibuf = NULL;
  PetscReal  *rbuf = NULL;
  RankLists   R;
  char        err[M2D_ERR_LEN] = "";

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscMemzero(&R, sizeof(R)));
  PetscCallMPI(MPI_Comm_size(comm, &R.size));
  if (rank == 0) {
    PetscCall(PetscMalloc1(sk->nc + 1, &R.where));
    PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MESH_PARTITION], 0, 0, 0, 0));
    PetscCall(PartitionCells(sk, R.size, R.where, err, sizeof(err)));
    PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MESH_PARTITION], 0, 0, 0, 0));
    if (err[0]) PetscCall(PetscFree(R.where));
  }
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  if (rank == 0) {
    PetscCall(RankListsCreate(sk, &R));
    PetscCall(SendPackages(comm, sk, L, &R, &ibuf, &rbuf));
    PetscCall(RankListsDestroy(&R));
  } else PetscCall(ReceivePackage(comm, &ibuf, &rbuf));
  PetscCall(BuildFromPackage(comm, ibuf, rbuf, dm, pbody, lab, nlab));
  PetscCall(PetscFree(ibuf));
  PetscCall(PetscFree(rbuf));
  PetscFunctionReturn(0);
}
