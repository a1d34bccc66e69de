/* mesh_plex.c - from the merged cell list to a DMPlex (see mesh_impl.h): the
 * skeleton (every edge once, from the vertex pairs of the cells), the physical
 * curves and points as edge and vertex ids, and the plex built from local lists
 * with DMPlexCreateFromDAG (no DMPlexInterpolate). */
#include "mesh_impl.h"
#include <stdlib.h>
#include <string.h>

/* the cell sides grouped by their lower vertex (counting sort: linear time) */
static PetscErrorCode SidesByLowerVertex(PetscInt nc, PetscInt nv, const PetscInt cells[], PetscInt ptr[], PetscInt other[], PetscInt sid[])
{
  PetscFunctionBeginUser;
  PetscCall(PetscArrayzero(ptr, nv + 1));
  for (PetscInt c = 0; c < nc; c++)
    for (int j = 0; j < 4; j++) ptr[PetscMin(cells[4 * c + j], cells[4 * c + (j + 1) % 4]) + 1]++;
  for (PetscInt v = 0; v < nv; v++) ptr[v + 1] += ptr[v];
  for (PetscInt c = 0; c < nc; c++)
    for (int j = 0; j < 4; j++) {
      PetscInt x = cells[4 * c + j], y = cells[4 * c + (j + 1) % 4], lo = PetscMin(x, y);
      other[ptr[lo]] = PetscMax(x, y);
      sid[ptr[lo]++] = 4 * c + j;
    }
  for (PetscInt v = nv; v > 0; v--) ptr[v] = ptr[v - 1];
  ptr[0] = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode MeshSkelBuild(PetscInt nc, PetscInt nv, const PetscInt cells[], MeshSkel *sk)
{
  PetscInt *ptr, *other, *sid;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sk, sizeof(*sk)));
  sk->nc       = nc;
  sk->nv       = nv;
  sk->cells    = cells;
  sk->third[0] = sk->third[1] = -1;
  PetscCall(PetscMalloc3(nv + 1, &ptr, 4 * nc + 1, &other, 4 * nc + 1, &sid));
  PetscCall(PetscMalloc5(4 * nc + 1, &sk->side, 4 * nc + 1, &sk->ornt, 8 * nc + 2, &sk->ev, nv + 1, &sk->eptr, 8 * nc + 2, &sk->ecell));
  PetscCall(SidesByLowerVertex(nc, nv, cells, ptr, other, sid));
  for (PetscInt v = 0; v < nv; v++) {
    sk->eptr[v] = sk->ne;
    for (PetscInt i = ptr[v]; i < ptr[v + 1]; i++) {
      PetscInt e = -1;
      for (PetscInt j = ptr[v]; j < i && e < 0; j++)
        if (other[j] == other[i]) e = sk->side[sid[j]];
      if (e < 0) {
        e                    = sk->ne++;
        sk->ev[2 * e]        = v;
        sk->ev[2 * e + 1]    = other[i];
        sk->ecell[2 * e]     = sid[i] / 4;
        sk->ecell[2 * e + 1] = -1;
      } else if (sk->ecell[2 * e + 1] < 0) sk->ecell[2 * e + 1] = sid[i] / 4;
      else if (sk->third[0] < 0) sk->third[0] = e, sk->third[1] = sid[i] / 4; /* refused by MeshCheckSkeleton */
      sk->side[sid[i]] = e;
    }
  }
  sk->eptr[nv] = sk->ne;
  for (PetscInt i = 0; i < 4 * nc; i++) sk->ornt[i] = sk->ev[2 * sk->side[i]] == cells[i] ? 0 : -1;
  PetscCall(PetscFree3(ptr, other, sid));
  PetscFunctionReturn(0);
}

static PetscInt SkelFindEdge(const MeshSkel *sk, PetscInt a, PetscInt b)
{
  PetscInt lo = PetscMin(a, b), hi = PetscMax(a, b);
  for (PetscInt e = sk->eptr[lo]; e < sk->eptr[lo + 1]; e++)
    if (sk->ev[2 * e + 1] == hi) return e;
  return -1;
}

void MeshSkelFree(MeshSkel *sk)
{
  PetscFree5(sk->side, sk->ornt, sk->ev, sk->eptr, sk->ecell);
}

/* One named line or point of source f: its entry (group, 0 vertex / 1 edge, id),
 * or a message if it is not a vertex / an edge of the merged cells. */
static int GroupEntry(const M2dMesh *m, const MeshSources *src, const MeshLists *L, const MeshSkel *sk, int f, PetscBool line, long k, PetscInt entry[3], char *err, size_t len)
{
  const MshMesh *msh   = &src->msh[f];
  const char    *pname = line ? MshPhysicalName(msh, 1, msh->linephys[k]) : MshPhysicalName(msh, 0, msh->pointphys[k]);
  long           na = line ? msh->line[2 * k] : msh->point[k], nb = line ? msh->line[2 * k + 1] : na;
  long           a, b;

  entry[0] = -1;
  if (!pname) return 0; /* unnamed: nothing can refer to it */
  if (na < 0 || na >= msh->nnode || nb < 0 || nb >= msh->nnode) {
    snprintf(err, len, "%s: physical %s '%s' uses node index %ld, outside 0..%ld", src->label[f], line ? "curve" : "point", pname, na < 0 || na >= msh->nnode ? na : nb, msh->nnode - 1);
    return 1;
  }
  a = L->nodemap[L->nodeoff[f] + na];
  b = L->nodemap[L->nodeoff[f] + nb];
  if (a < 0 || b < 0) {
    if (line) snprintf(err, len, "%s: physical curve '%s' has a line whose nodes belong to no quadrilateral", src->label[f], pname);
    else snprintf(err, len, "%s: physical point '%s' is not a node of any quadrilateral", src->label[f], pname);
    return 1;
  }
  entry[2] = line ? SkelFindEdge(sk, (PetscInt)a, (PetscInt)b) : (PetscInt)a;
  if (entry[2] < 0) {
    snprintf(err, len, "%s: physical curve '%s' has a line (nodes %ld, %ld) that is not an edge of any quadrilateral", src->label[f], pname, na + 1, nb + 1);
    return 1;
  }
  entry[1] = line ? 1 : 0;
  for (PetscInt j = 0; j < m->ngroup && entry[0] < 0; j++)
    if (!strcmp(m->group[j], pname)) entry[0] = j;
  if (entry[0] < 0) {
    snprintf(err, len, "%s: physical group '%s' missing from the group list", src->label[f], pname);
    return 1;
  }
  return 0;
}

/* Rank 0: physical curves and points -> L->ent (group, 0 vertex / 1 edge, id);
 * inner[group]: the curve's edges that have two cells */
PetscErrorCode MeshGroupEntries(const M2dMesh *m, const MeshSources *src, MeshLists *L, const MeshSkel *sk, M2dGroupInner inner[], char *err, size_t len)
{
  long cap = 0;

  PetscFunctionBeginUser;
  err[0] = 0;
  for (int f = 0; f < src->nmsh; f++) cap += src->msh[f].nline + src->msh[f].npoint;
  L->nent = 0;
  L->ent  = (PetscInt *)malloc((size_t)(3 * cap + 3) * sizeof(PetscInt));
  PetscCheck(L->ent, PETSC_COMM_SELF, PETSC_ERR_MEM, "out of memory for %ld physical lines and points", cap);
  for (int f = 0; f < src->nmsh; f++) {
    const MshMesh *msh = &src->msh[f];
    for (long i = 0; i < msh->nline + msh->npoint; i++) {
      PetscInt *entry = &L->ent[3 * L->nent];
      PetscBool line  = (PetscBool)(i < msh->nline);
      if (GroupEntry(m, src, L, sk, f, line, line ? i : i - msh->nline, entry, err, len)) PetscFunctionReturn(0);
      if (entry[0] < 0) continue;
      L->nent++;
      if (entry[1] == 1 && sk->ecell[2 * entry[2] + 1] >= 0 && !inner[entry[0]].n++) {
        M2dGroupInner *in = &inner[entry[0]];
        in->body[0]       = L->cellbody[sk->ecell[2 * entry[2]]];
        in->body[1]       = L->cellbody[sk->ecell[2 * entry[2] + 1]];
        for (int k = 0; k < 2; k++) in->xy[2 * k] = L->coords[2 * sk->ev[2 * entry[2] + k]], in->xy[2 * k + 1] = L->coords[2 * sk->ev[2 * entry[2] + k] + 1];
      }
    }
  }
  PetscFunctionReturn(0);
}

/* A plex from local lists: ncl cells (cone: 4 local edges, orientations),
 * nvl vertices, nel edges (cone: 2 local vertices). Points: cells, vertices,
 * edges. A cell's edge is oriented 0 when it runs along the cell's vertex
 * order, -1 against it (DMPlexCheckFaces agrees: tests/test_mesh_plex.py). */
PetscErrorCode MeshPlexFromLists(MPI_Comm comm, PetscInt ncl, PetscInt nvl, PetscInt nel, const PetscInt ccone[], const PetscInt cornt[], const PetscInt econe[], const PetscReal xy[], DM *dm)
{
  PetscInt     numPoints[3] = {nvl, nel, ncl}, np = ncl + nvl + nel, *coneSize, *cones, *orient, k = 0;
  PetscScalar *xs;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(np + 1, &coneSize, 4 * ncl + 2 * nel + 1, &cones, 4 * ncl + 2 * nel + 1, &orient));
  for (PetscInt c = 0; c < ncl; c++) {
    coneSize[c] = 4;
    for (int j = 0; j < 4; j++, k++) {
      cones[k]  = ncl + nvl + ccone[4 * c + j];
      orient[k] = cornt[4 * c + j];
    }
  }
  for (PetscInt v = 0; v < nvl; v++) coneSize[ncl + v] = 0;
  for (PetscInt e = 0; e < nel; e++, k += 2) {
    coneSize[ncl + nvl + e] = 2;
    cones[k]                = ncl + econe[2 * e];
    cones[k + 1]            = ncl + econe[2 * e + 1];
    orient[k] = orient[k + 1] = 0;
  }
  PetscCall(PetscMalloc1(2 * nvl + 1, &xs));
  for (PetscInt i = 0; i < 2 * nvl; i++) xs[i] = xy[i];
  PetscCall(DMCreate(comm, dm));
  PetscCall(DMSetType(*dm, DMPLEX));
  PetscCall(DMSetDimension(*dm, 2));
  PetscCall(DMPlexCreateFromDAG(*dm, 2, numPoints, coneSize, cones, orient, xs));
  PetscCall(PetscFree(xs));
  PetscCall(PetscFree3(coneSize, cones, orient));
  PetscFunctionReturn(0);
}
