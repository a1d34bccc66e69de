/* mesh.c - read, validate and merge the gmsh bodies into one DMPlex (see mesh.h). */
#include "mesh.h"
#include <petscsf.h>
#include "msh.h"
#include <metis.h>
#include "util.h"
#include <string.h>

/* Jacobian determinant of the bilinear map at the four corners: all must be > 0
 * for a valid (convex, counter-clockwise, non-degenerate) Q4. */
static double MinCornerJacobian(const double xy[8])
{
  double jmin = 1e300;
  for (int k = 0; k < 4; k++) {
    const double *p = &xy[2 * k], *n = &xy[2 * ((k + 1) % 4)], *q = &xy[2 * ((k + 3) % 4)];
    double        j = (n[0] - p[0]) * (q[1] - p[1]) - (n[1] - p[1]) * (q[0] - p[0]);
    if (j < jmin) jmin = j;
  }
  return jmin;
}

typedef struct {
  /* everything rank 0 broadcasts after reading */
  char     err[2048];
  PetscInt ngroup;
  char     group[M2D_MAX_GROUPS][M2D_NAME_LEN];
  PetscInt groupdim[M2D_MAX_GROUPS];
  PetscInt nbody;
  char     body[M2D_MAX_BODIES][M2D_NAME_LEN];
} ReadInfo;

static int FindGroup(const ReadInfo *ri, const char *name)
{
  for (int i = 0; i < ri->ngroup; i++)
    if (!strcmp(ri->group[i], name)) return i;
  return -1;
}

/* Rank 0: read every file, check names and cells, and produce the merged cell
 * list (cells, coords) and label assignments. Returns 0 or fills ri->err. */
static int ReadMerge(const M2dScene *s, ReadInfo *ri, PetscInt *nc_out, PetscInt *nv_out, PetscInt **cells_out, PetscReal **coords_out, PetscInt **cellbody_out, MshMesh msh[2], long nodeoff[3], long **nodemap_out)
{
  long      nquad = 0, nnode = 0;
  long     *nodemap = NULL;
  PetscInt *cells = NULL, *cellbody = NULL;
  PetscReal *coords = NULL;
  PetscInt  nv = 0;

  for (int f = 0; f < s->nmesh; f++) {
    if (MshRead(s->mesh[f], &msh[f], ri->err, sizeof(ri->err))) return 1;
    for (int i = 0; i < msh[f].nphys; i++) {
      int g = FindGroup(ri, msh[f].phys[i].name);
      if (g >= 0) {
        if (f > 0 && ri->groupdim[g] >= 0) {
          snprintf(ri->err, sizeof(ri->err), "physical group '%s' is defined in both '%s' and '%s': give the groups of the two bodies different names", msh[f].phys[i].name, s->mesh[0], s->mesh[f]);
        } else {
          snprintf(ri->err, sizeof(ri->err), "mesh file '%s': physical name '%s' is used for two groups", s->mesh[f], msh[f].phys[i].name);
        }
        return 1;
      }
      if (ri->ngroup >= M2D_MAX_GROUPS) {
        snprintf(ri->err, sizeof(ri->err), "mesh file '%s': more than %d physical groups", s->mesh[f], M2D_MAX_GROUPS);
        return 1;
      }
      snprintf(ri->group[ri->ngroup], M2D_NAME_LEN, "%s", msh[f].phys[i].name);
      ri->groupdim[ri->ngroup++] = msh[f].phys[i].dim;
    }
    nodeoff[f] = nnode;
    nnode += msh[f].nnode;
    nquad += msh[f].nquad;
  }
  nodeoff[s->nmesh] = nnode;
  /* bodies */
  if (s->nbody == 0) {
    for (int f = 0; f < s->nmesh; f++)
      for (int i = 0; i < msh[f].nphys; i++)
        if (msh[f].phys[i].dim == 2) {
          if (ri->nbody >= M2D_MAX_BODIES) {
            snprintf(ri->err, sizeof(ri->err), "mesh file '%s': more than %d physical surfaces (bodies)", s->mesh[f], M2D_MAX_BODIES);
            return 1;
          }
          snprintf(ri->body[ri->nbody++], M2D_NAME_LEN, "%s", msh[f].phys[i].name);
        }
    if (ri->nbody == 0) {
      snprintf(ri->err, sizeof(ri->err), "mesh file '%s': no physical surface names a body (add Physical Surface(\"name\") in the .geo)", s->mesh[0]);
      return 1;
    }
  } else {
    ri->nbody = s->nbody;
    for (int b = 0; b < s->nbody; b++) {
      int g = FindGroup(ri, s->body[b].name);
      if (g < 0 || ri->groupdim[g] != 2) {
        snprintf(ri->err, sizeof(ri->err), "option -bodies: mesh file(s) %s%s%s have no physical surface '%s'", s->mesh[0], s->nmesh > 1 ? ", " : "", s->nmesh > 1 ? s->mesh[1] : "", s->body[b].name);
        return 1;
      }
      snprintf(ri->body[b], M2D_NAME_LEN, "%s", s->body[b].name);
    }
  }
  /* cells: body of each quad, corner Jacobians, used nodes */
  nodemap = (long *)malloc((size_t)(nnode + 1) * sizeof(long));
  cells   = (PetscInt *)malloc((size_t)(4 * nquad + 1) * sizeof(PetscInt));
  cellbody = (PetscInt *)malloc((size_t)(nquad + 1) * sizeof(PetscInt));
  if (!nodemap || !cells || !cellbody) {
    snprintf(ri->err, sizeof(ri->err), "out of memory merging the meshes");
    free(nodemap); free(cells); free(cellbody);
    return 1;
  }
  *nodemap_out = nodemap;
  *cells_out   = cells;
  *cellbody_out = cellbody;
  for (long i = 0; i < nnode; i++) nodemap[i] = -1;
  long c = 0;
  for (int f = 0; f < s->nmesh; f++) {
    for (long q = 0; q < msh[f].nquad; q++, c++) {
      const char *pname = MshPhysicalName(&msh[f], 2, msh[f].quadphys[q]);
      int         b     = -1;
      double      xy[8];
      for (int k = 0; pname && k < ri->nbody; k++)
        if (!strcmp(ri->body[k], pname)) b = k;
      if (b < 0) {
        snprintf(ri->err, sizeof(ri->err), "mesh file '%s': quadrilateral %ld lies in %s%s%s, which is not a body (see -bodies)", s->mesh[f], msh[f].quadtag[q], pname ? "physical surface '" : "no physical surface", pname ? pname : "", pname ? "'" : "");
        return 1;
      }
      cellbody[c] = b;
      for (int k = 0; k < 4; k++) {
        long n    = msh[f].quad[4 * q + k];
        xy[2 * k]     = s->mesh_scale * msh[f].xy[2 * n];
        xy[2 * k + 1] = s->mesh_scale * msh[f].xy[2 * n + 1];
        for (int l = 0; l < k; l++)
          if (msh[f].quad[4 * q + l] == n) {
            snprintf(ri->err, sizeof(ri->err), "mesh file '%s': quadrilateral %ld repeats node %ld", s->mesh[f], msh[f].quadtag[q], n);
            return 1;
          }
      }
      double jmin = MinCornerJacobian(xy);
      double a    = 0.5 * ((xy[0] - xy[4]) * (xy[3] - xy[7]) - (xy[2] - xy[6]) * (xy[1] - xy[5]));
      if (!(jmin > 1e-12 * (a > 0 ? a : -a)) || !(a > 0)) {
        snprintf(ri->err, sizeof(ri->err), "mesh file '%s': quadrilateral %ld is %s (area %g, smallest corner Jacobian %g)", s->mesh[f], msh[f].quadtag[q], a < 0 ? "inverted (clockwise)" : a == 0 ? "of zero area" : "degenerate or non-convex", a, jmin);
        return 1;
      }
      for (int k = 0; k < 4; k++) {
        long g = nodeoff[f] + msh[f].quad[4 * q + k];
        if (nodemap[g] < 0) nodemap[g] = nv++;
        cells[4 * c + k] = (PetscInt)nodemap[g];
      }
    }
  }
  coords = (PetscReal *)malloc((size_t)(2 * nv + 1) * sizeof(PetscReal));
  if (!coords) {
    snprintf(ri->err, sizeof(ri->err), "out of memory merging the meshes");
    return 1;
  }
  for (int f = 0; f < s->nmesh; f++)
    for (long n = 0; n < msh[f].nnode; n++) {
      long g = nodemap[nodeoff[f] + n];
      if (g < 0) continue;
      coords[2 * g]     = s->mesh_scale * msh[f].xy[2 * n];
      coords[2 * g + 1] = s->mesh_scale * msh[f].xy[2 * n + 1];
    }
  *coords_out = coords;
  *nc_out     = (PetscInt)nquad;
  *nv_out     = nv;
  return 0;
}

static void LabelName(const char *group, char *out, size_t len)
{
  snprintf(out, len, "m2d:%s", group);
}

/* The skeleton of the merged mesh on rank 0: every edge found once from the
 * vertex pairs of the cells (several times faster than DMPlexInterpolate). */
typedef struct {
  PetscInt        nc, nv, ne;
  const PetscInt *cells; /* 4 per cell, vertex ids, counter-clockwise (borrowed) */
  PetscInt       *side;  /* 4 per cell: the edge from cells[4c+j] to cells[4c+(j+1)%4] */
  PetscInt       *ornt;  /* 4 per cell: 0 if that edge runs from cells[4c+j] (its lower vertex), -1 if against */
  PetscInt       *ev;    /* 2 per edge: lower, higher vertex id */
  PetscInt       *eptr;  /* edges whose lower vertex is v: eptr[v] .. eptr[v+1]-1 */
  PetscInt       *ecell; /* 2 per edge: its cells, -1 if none */
} Skel;

static PetscErrorCode SkelBuild(PetscInt nc, PetscInt nv, const PetscInt cells[], Skel *sk)
{
  PetscInt *ptr, *other, *sid;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sk, sizeof(*sk)));
  sk->nc    = nc;
  sk->nv    = nv;
  sk->cells = cells;
  PetscCall(PetscCalloc1(nv + 1, &ptr));
  PetscCall(PetscMalloc2(4 * nc + 1, &other, 4 * nc + 1, &sid));
  PetscCall(PetscMalloc5(4 * nc + 1, &sk->side, 4 * nc + 1, &sk->ornt, 8 * nc + 2, &sk->ev, nv + 1, &sk->eptr, 8 * nc + 2, &sk->ecell));
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
      } else sk->ecell[2 * e + 1] = sid[i] / 4;
      sk->side[sid[i]] = e;
    }
  }
  sk->eptr[nv] = sk->ne;
  for (PetscInt i = 0; i < 4 * nc; i++) sk->ornt[i] = sk->ev[2 * sk->side[i]] == cells[i] ? 0 : -1;
  PetscCall(PetscFree(ptr));
  PetscCall(PetscFree2(other, sid));
  PetscFunctionReturn(0);
}

static PetscInt SkelFindEdge(const Skel *sk, PetscInt a, PetscInt b)
{
  PetscInt lo = PetscMin(a, b), hi = PetscMax(a, b);
  for (PetscInt e = sk->eptr[lo]; e < sk->eptr[lo + 1]; e++)
    if (sk->ev[2 * e + 1] == hi) return e;
  return -1;
}

static void SkelFree(Skel *sk)
{
  PetscFree5(sk->side, sk->ornt, sk->ev, sk->eptr, sk->ecell);
}

/* Rank 0: physical curves and points -> entries (group index, 0 vertex / 1 edge, id) */
static PetscErrorCode GroupEntries(const M2dScene *s, const M2dMesh *m, MshMesh msh[2], const long nodeoff[3], const long *nodemap, const Skel *sk, PetscInt *nent, PetscInt **ent, char *err, size_t errlen)
{
  PetscInt n = 0, cap = 0;

  PetscFunctionBeginUser;
  err[0] = 0;
  for (int f = 0; f < s->nmesh; f++) cap += (PetscInt)(msh[f].nline + msh[f].npoint);
  PetscCall(PetscMalloc1(3 * cap + 3, ent));
  for (int f = 0; f < s->nmesh; f++) {
    for (long i = 0; i < msh[f].nline + msh[f].npoint; i++) {
      PetscBool   line  = (PetscBool)(i < msh[f].nline);
      long        k     = line ? i : i - msh[f].nline;
      const char *pname = line ? MshPhysicalName(&msh[f], 1, msh[f].linephys[k]) : MshPhysicalName(&msh[f], 0, msh[f].pointphys[k]);
      long        a     = line ? nodemap[nodeoff[f] + msh[f].line[2 * k]] : nodemap[nodeoff[f] + msh[f].point[k]];
      long        b     = line ? nodemap[nodeoff[f] + msh[f].line[2 * k + 1]] : 0;
      PetscInt    g     = -1, id;
      if (!pname) continue; /* unnamed: nothing can refer to it */
      if (a < 0 || b < 0) {
        if (line) snprintf(err, errlen, "mesh file '%s': physical curve '%s' has a line whose nodes belong to no quadrilateral", s->mesh[f], pname);
        else snprintf(err, errlen, "mesh file '%s': physical point '%s' is not a node of any quadrilateral", s->mesh[f], pname);
        PetscFunctionReturn(0);
      }
      id = line ? SkelFindEdge(sk, (PetscInt)a, (PetscInt)b) : (PetscInt)a;
      if (id < 0) {
        snprintf(err, errlen, "mesh file '%s': physical curve '%s' has a line (nodes %ld, %ld) that is not an edge of any quadrilateral", s->mesh[f], pname, msh[f].line[2 * k] + 1, msh[f].line[2 * k + 1] + 1);
        PetscFunctionReturn(0);
      }
      for (PetscInt j = 0; j < m->ngroup && g < 0; j++)
        if (!strcmp(m->group[j], pname)) g = j;
      PetscCheck(g >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "physical group '%s' missing from the group list", pname);
      (*ent)[3 * n]     = g;
      (*ent)[3 * n + 1] = line ? 1 : 0;
      (*ent)[3 * n + 2] = id;
      n++;
    }
  }
  *nent = n;
  PetscFunctionReturn(0);
}

/* A plex from local lists: ncl cells (cone: 4 local edges, orientations),
 * nvl vertices, nel edges (cone: 2 local vertices). Points: cells, vertices,
 * edges. A cell's edge is oriented 0 when it runs along the cell's vertex
 * order, -1 against it (DMPlexCheckFaces agrees: tests/test_mesh_plex.py). */
static PetscErrorCode PlexFromLists(MPI_Comm comm, PetscInt ncl, PetscInt nvl, PetscInt nel, const PetscInt ccone[], const PetscInt cornt[], const PetscInt econe[], const PetscReal xy[], DM *dm)
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

static PetscLogEvent ev_read, ev_skel, ev_part, ev_plex; /* phases of the mesh stage */

/* -mesh_partitioner metis: the part of every cell, libmetis on the cells sharing an edge (rank 0) */
static PetscErrorCode PartitionCells(const Skel *sk, PetscMPIInt size, PetscInt where[])
{
  idx_t *xadj, *adj, *part, nvtx = (idx_t)sk->nc, ncon = 1, nparts = size, objval = 0, opts[METIS_NOPTIONS];
  int    rc = METIS_OK;
  PetscInt k = 0;

  PetscFunctionBeginUser;
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
  if (sk->nc > 0) rc = sk->nc >= size ? METIS_PartGraphRecursive(&nvtx, &ncon, xadj, adj, NULL, NULL, NULL, &nparts, NULL, NULL, opts, &objval, part) : METIS_ERROR_INPUT;
  PetscCheck(rc == METIS_OK, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -mesh_partitioner metis: METIS_PartGraphRecursive failed (%d) on %" PetscInt_FMT " cells for %d ranks", rc, sk->nc, (int)size);
  PetscCall(PetscInfo(NULL, "METIS: %" PetscInt_FMT " cells in %d parts, %ld cut edges\n", sk->nc, (int)size, (long)objval));
  for (PetscInt c = 0; c < sk->nc; c++) where[c] = (PetscInt)part[c];
  PetscCall(PetscFree3(xadj, adj, part));
  PetscFunctionReturn(0);
}

/* Several ranks, -mesh_partitioner metis: rank 0 splits the skeleton and sends
 * every rank its cells, vertices and edges with their point-SF leaves (a
 * vertex or edge belongs to the lowest rank holding one of its cells), its
 * group entries and cell bodies; every rank builds its own plex. No
 * DMPlexDistribute: at level 5 it took 1.6 s of the 2.4 s mesh stage. */
static PetscErrorCode BuildDistributed(MPI_Comm comm, const Skel *sk, const PetscReal coords[], const PetscInt cellbody[], PetscInt nent, const PetscInt ent[], DM *dm, PetscInt **pbody, PetscInt **lab, PetscInt *nlab)
{
  PetscMPIInt rank, size;
  PetscInt   *ibuf = NULL, hdr[6], ni;
  PetscReal  *rbuf = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (rank == 0) {
    PetscInt   nc = sk->nc, nv = sk->nv, ne = sk->ne, *where, *vown, *eown, *vidx, *eidx, *vst, *est, *vloc, *eloc;
    PetscInt **vl, **el, **cl, *ncp, *nvp, *nep;
    PetscCall(PetscMalloc4(nc + 1, &where, nv + 1, &vown, ne + 1, &eown, nv + 1, &vidx));
    PetscCall(PetscMalloc5(ne + 1, &eidx, nv + 1, &vst, ne + 1, &est, nv + 1, &vloc, ne + 1, &eloc));
    PetscCall(PetscCalloc6(size, &vl, size, &el, size, &cl, size, &ncp, size, &nvp, size, &nep));
    PetscCall(PetscLogEventBegin(ev_part, 0, 0, 0, 0));
    PetscCall(PartitionCells(sk, size, where));
    PetscCall(PetscLogEventEnd(ev_part, 0, 0, 0, 0));
    for (PetscInt v = 0; v < nv; v++) vown[v] = size, vst[v] = -1, vloc[v] = -1;
    for (PetscInt e = 0; e < ne; e++) eown[e] = size, est[e] = -1, eloc[e] = -1;
    for (PetscInt c = 0; c < nc; c++) {
      ncp[where[c]]++;
      for (int j = 0; j < 4; j++) {
        vown[sk->cells[4 * c + j]] = PetscMin(vown[sk->cells[4 * c + j]], where[c]);
        eown[sk->side[4 * c + j]]  = PetscMin(eown[sk->side[4 * c + j]], where[c]);
      }
    }
    /* every rank's cells (in file order), vertices and edges (by global id:
     * marked, then collected in one sweep - linear time, no sorting) */
    for (PetscMPIInt p = 0; p < size; p++) {
      PetscInt n = 0, nvm = 0, nem = 0;
      PetscCall(PetscMalloc1(ncp[p] + 1, &cl[p]));
      for (PetscInt c = 0; c < nc; c++)
        if (where[c] == p) {
          cl[p][n++] = c;
          for (int j = 0; j < 4; j++) {
            PetscInt v = sk->cells[4 * c + j], e = sk->side[4 * c + j];
            if (vst[v] != p) { vst[v] = p; nvm++; }
            if (est[e] != p) { est[e] = p; nem++; }
          }
        }
      PetscCall(PetscMalloc2(nvm + 1, &vl[p], nem + 1, &el[p]));
      for (PetscInt v = 0; v < nv; v++)
        if (vst[v] == p) {
          if (vown[v] == p) vidx[v] = nvp[p];
          vl[p][nvp[p]++] = v;
        }
      for (PetscInt e = 0; e < ne; e++)
        if (est[e] == p) {
          if (eown[e] == p) eidx[e] = nep[p];
          el[p][nep[p]++] = e;
        }
    }
    /* the packages (rank 0's last: it stays here) */
    for (PetscMPIInt p = size - 1; p >= 0; p--) {
      PetscInt nl = 0, nb = 0, *ip, off;
      PetscReal *rp;
      for (PetscInt i = 0; i < nvp[p]; i++) vloc[vl[p][i]] = i;
      for (PetscInt i = 0; i < nep[p]; i++) eloc[el[p][i]] = i;
      for (PetscInt i = 0; i < nvp[p]; i++) nl += vown[vl[p][i]] != p;
      for (PetscInt i = 0; i < nep[p]; i++) nl += eown[el[p][i]] != p;
      for (PetscInt k = 0; k < nent; k++) nb += (ent[3 * k + 1] ? eloc[ent[3 * k + 2]] : vloc[ent[3 * k + 2]]) >= 0;
      ni = 6 + 9 * ncp[p] + 2 * nep[p] + 3 * nl + 2 * nb;
      PetscCall(PetscMalloc1(ni, &ip));
      PetscCall(PetscMalloc1(2 * nvp[p] + 1, &rp));
      ip[0] = ncp[p]; ip[1] = nvp[p]; ip[2] = nep[p]; ip[3] = nl; ip[4] = nb; ip[5] = ni;
      off = 6;
      for (PetscInt i = 0; i < ncp[p]; i++) {
        PetscInt c = cl[p][i];
        for (int j = 0; j < 4; j++) {
          ip[off + 4 * i + j]              = eloc[sk->side[4 * c + j]];
          ip[off + 4 * ncp[p] + 4 * i + j] = sk->ornt[4 * c + j];
        }
        ip[off + 8 * ncp[p] + i] = cellbody[c];
      }
      off += 9 * ncp[p];
      for (PetscInt i = 0; i < nep[p]; i++) {
        PetscInt e = el[p][i];
        ip[off + 2 * i]     = vloc[sk->ev[2 * e]];
        ip[off + 2 * i + 1] = vloc[sk->ev[2 * e + 1]];
      }
      off += 2 * nep[p];
      for (PetscInt i = 0; i < nvp[p]; i++) {
        PetscInt v = vl[p][i], o = vown[v];
        rp[2 * i]     = coords[2 * v];
        rp[2 * i + 1] = coords[2 * v + 1];
        if (o == p) continue;
        ip[off++] = ncp[p] + i;
        ip[off++] = o;
        ip[off++] = ncp[o] + vidx[v];
      }
      for (PetscInt i = 0; i < nep[p]; i++) {
        PetscInt e = el[p][i], o = eown[e];
        if (o == p) continue;
        ip[off++] = ncp[p] + nvp[p] + i;
        ip[off++] = o;
        ip[off++] = ncp[o] + nvp[o] + eidx[e];
      }
      for (PetscInt k = 0; k < nent; k++) {
        PetscInt loc = ent[3 * k + 1] ? eloc[ent[3 * k + 2]] : vloc[ent[3 * k + 2]];
        if (loc < 0) continue;
        ip[off++] = ent[3 * k];
        ip[off++] = ent[3 * k + 1] ? ncp[p] + nvp[p] + loc : ncp[p] + loc;
      }
      PetscCheck(off == ni, PETSC_COMM_SELF, PETSC_ERR_PLIB, "mesh package for rank %d: %" PetscInt_FMT " of %" PetscInt_FMT " entries", (int)p, off, ni);
      for (PetscInt i = 0; i < nvp[p]; i++) vloc[vl[p][i]] = -1;
      for (PetscInt i = 0; i < nep[p]; i++) eloc[el[p][i]] = -1;
      if (p == 0) {
        ibuf = ip;
        rbuf = rp;
      } else {
        PetscMPIInt nim, nrm;
        PetscCall(PetscMPIIntCast(ni, &nim));
        PetscCall(PetscMPIIntCast(2 * nvp[p], &nrm));
        PetscCallMPI(MPI_Send(ip, 6, MPIU_INT, p, 0, comm));
        PetscCallMPI(MPI_Send(ip, nim, MPIU_INT, p, 1, comm));
        PetscCallMPI(MPI_Send(rp, nrm, MPIU_REAL, p, 2, comm));
        PetscCall(PetscFree(ip));
        PetscCall(PetscFree(rp));
      }
    }
    for (PetscMPIInt p = 0; p < size; p++) {
      PetscCall(PetscFree(cl[p]));
      PetscCall(PetscFree2(vl[p], el[p]));
    }
    PetscCall(PetscFree6(vl, el, cl, ncp, nvp, nep));
    PetscCall(PetscFree4(where, vown, eown, vidx));
    PetscCall(PetscFree5(eidx, vst, est, vloc, eloc));
  } else {
    PetscMPIInt nim, nrm;
    PetscCallMPI(MPI_Recv(hdr, 6, MPIU_INT, 0, 0, comm, MPI_STATUS_IGNORE));
    PetscCall(PetscMalloc1(hdr[5], &ibuf));
    PetscCall(PetscMalloc1(2 * hdr[1] + 1, &rbuf));
    PetscCall(PetscMPIIntCast(hdr[5], &nim));
    PetscCall(PetscMPIIntCast(2 * hdr[1], &nrm));
    PetscCallMPI(MPI_Recv(ibuf, nim, MPIU_INT, 0, 1, comm, MPI_STATUS_IGNORE));
    PetscCallMPI(MPI_Recv(rbuf, nrm, MPIU_REAL, 0, 2, comm, MPI_STATUS_IGNORE));
  }
  {
    PetscInt     ncl = ibuf[0], nvl = ibuf[1], nel = ibuf[2], nl = ibuf[3], nb = ibuf[4];
    PetscInt    *cc = ibuf + 6, *co = cc + 4 * ncl, *cb = co + 4 * ncl, *ec = cb + ncl, *lv = ec + 2 * nel, *lb = lv + 3 * nl, *ilocal;
    PetscSFNode *iremote;
    PetscSF      sf;
    DM           cdm;
    PetscCall(PetscLogEventBegin(ev_plex, 0, 0, 0, 0));
    PetscCall(PlexFromLists(comm, ncl, nvl, nel, cc, co, ec, rbuf, dm));
    PetscCall(PetscLogEventEnd(ev_plex, 0, 0, 0, 0));
    PetscCall(PetscMalloc1(nl + 1, &ilocal));
    PetscCall(PetscMalloc1(nl + 1, &iremote));
    for (PetscInt i = 0; i < nl; i++) {
      ilocal[i]        = lv[3 * i];
      iremote[i].rank  = lv[3 * i + 1];
      iremote[i].index = lv[3 * i + 2];
    }
    PetscCall(PetscSFCreate(comm, &sf));
    PetscCall(PetscSFSetGraph(sf, ncl + nvl + nel, nl, ilocal, PETSC_OWN_POINTER, iremote, PETSC_OWN_POINTER));
    PetscCall(DMSetPointSF(*dm, sf));
    PetscCall(DMGetCoordinateDM(*dm, &cdm));
    PetscCall(DMSetPointSF(cdm, sf));
    PetscCall(PetscSFDestroy(&sf));
    PetscCall(PetscMalloc1(ncl + nvl + nel + 1, pbody));
    for (PetscInt i = 0; i < ncl + nvl + nel; i++) (*pbody)[i] = i < ncl ? cb[i] : -1;
    PetscCall(PetscMalloc1(2 * nb + 1, lab));
    PetscCall(PetscArraycpy(*lab, lb, 2 * nb));
    *nlab = nb;
  }
  PetscCall(PetscFree(ibuf));
  PetscCall(PetscFree(rbuf));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshCreate(MPI_Comm comm, M2dScene *s, M2dMesh *m)
{
  PetscMPIInt rank, size;
  ReadInfo   *ri;
  MshMesh     msh[2];
  long        nodeoff[3] = {0, 0, 0}, *nodemap = NULL;
  PetscInt    nc = 0, nv = 0, *cells = NULL, *cellbody = NULL, *pbody = NULL, nent = 0, *ent = NULL, nlab = 0, *lab = NULL;
  PetscSF     mig = NULL;
  Skel        sk;
  PetscReal  *coords = NULL;
  DM          dm;
  char        err[2048];

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (!ev_read) {
    PetscCall(PetscLogEventRegister("M2dMeshRead", DM_CLASSID, &ev_read));
    PetscCall(PetscLogEventRegister("M2dMeshEdges", DM_CLASSID, &ev_skel));
    PetscCall(PetscLogEventRegister("M2dMeshPartition", DM_CLASSID, &ev_part));
    PetscCall(PetscLogEventRegister("M2dMeshPlex", DM_CLASSID, &ev_plex));
  }
  PetscCheck(s->nmesh > 0, comm, PETSC_ERR_USER_INPUT, "option -mesh: no mesh file given (for example -mesh meshes/patch_uniform.msh)");
  PetscCall(PetscSNPrintf(m->files, sizeof(m->files), "%s%s%s", s->mesh[0], s->nmesh > 1 ? ", " : "", s->nmesh > 1 ? s->mesh[1] : ""));
  PetscCall(PetscCalloc1(1, &ri));
  memset(msh, 0, sizeof(msh));
  PetscCall(PetscLogEventBegin(ev_read, 0, 0, 0, 0));
  if (rank == 0) {
    if (ReadMerge(s, ri, &nc, &nv, &cells, &coords, &cellbody, msh, nodeoff, &nodemap)) {
      if (!ri->err[0]) snprintf(ri->err, sizeof(ri->err), "cannot read the mesh");
    }
  }
  PetscCall(PetscLogEventEnd(ev_read, 0, 0, 0, 0));
  PetscCallMPI(MPI_Bcast(ri, (int)sizeof(*ri), MPI_BYTE, 0, comm));
  if (ri->err[0]) {
    for (int f = 0; f < 2; f++) MshFree(&msh[f]);
    free(nodemap); free(cells); free(coords); free(cellbody);
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
  PetscCall(PetscFree(ri));

  err[0] = 0;
  PetscCall(PetscMemzero(&sk, sizeof(sk)));
  PetscCall(PetscLogEventBegin(ev_skel, 0, 0, 0, 0));
  if (rank == 0) {
    PetscCall(SkelBuild(nc, nv, cells, &sk));
    PetscCall(GroupEntries(s, m, msh, nodeoff, nodemap, &sk, &nent, &ent, err, sizeof(err)));
  }
  PetscCall(PetscLogEventEnd(ev_skel, 0, 0, 0, 0));
  for (int f = 0; f < 2; f++) MshFree(&msh[f]);
  free(nodemap);
  if (err[0]) { /* rank 0: a group that names no edge or vertex */
    SkelFree(&sk);
    PetscCall(PetscFree(ent));
    free(cells); free(coords); free(cellbody);
    cells = cellbody = NULL;
    coords = NULL;
  }
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));

  if (size > 1 && s->mesh_partitioner == M2D_PARTITIONER_METIS) PetscCall(BuildDistributed(comm, &sk, coords, cellbody, nent, ent, &dm, &pbody, &lab, &nlab));
  else { /* the whole plex on rank 0 */
    PetscCall(PetscLogEventBegin(ev_plex, 0, 0, 0, 0));
    PetscCall(PlexFromLists(comm, nc, nv, sk.ne, sk.side, sk.ornt, sk.ev, coords, &dm));
    PetscCall(PetscLogEventEnd(ev_plex, 0, 0, 0, 0));
    PetscCall(PetscMalloc1(nc + nv + sk.ne + 1, &pbody));
    for (PetscInt p = 0; p < nc + nv + sk.ne; p++) pbody[p] = p < nc ? cellbody[p] : -1;
    PetscCall(PetscMalloc1(2 * nent + 1, &lab));
    for (PetscInt k = 0; k < nent; k++) {
      lab[2 * k]     = ent[3 * k];
      lab[2 * k + 1] = ent[3 * k + 1] ? nc + nv + ent[3 * k + 2] : nc + ent[3 * k + 2];
    }
    nlab = nent;
  }
  if (rank == 0) SkelFree(&sk);
  PetscCall(PetscFree(ent));
  free(cells); free(coords); free(cellbody);
  PetscCall(PetscObjectSetName((PetscObject)dm, "mesh"));
  for (PetscInt g = 0; g < m->ngroup; g++) {
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

  if (size > 1 && s->mesh_partitioner == M2D_PARTITIONER_PETSC) {
    DM               dist = NULL;
    PetscPartitioner part;
    PetscCall(DMPlexGetPartitioner(dm, &part));
    PetscCall(PetscPartitionerSetFromOptions(part));
    PetscCall(DMPlexDistribute(dm, 0, &mig, &dist));
    if (dist) {
      PetscInt  pStart, pEnd, *nb;
      PetscCall(DMPlexGetChart(dist, &pStart, &pEnd));
      PetscCall(PetscMalloc1(pEnd + 1, &nb));
      for (PetscInt p = 0; p < pEnd; p++) nb[p] = -1;
      PetscCall(PetscSFBcastBegin(mig, MPIU_INT, pbody, nb, MPI_REPLACE));
      PetscCall(PetscSFBcastEnd(mig, MPIU_INT, pbody, nb, MPI_REPLACE));
      PetscCall(PetscFree(pbody));
      pbody = nb;
      PetscCall(DMDestroy(&dm));
      dm = dist;
    }
    PetscCall(PetscSFDestroy(&mig));
    if (s->mesh_check) PetscCall(DMPlexCheckPointSF(dm, NULL, PETSC_FALSE));
  }
  m->dm = dm;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &m->cStart, &m->cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 1, &m->eStart, &m->eEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &m->vStart, &m->vEnd));

  /* cell -> 4 vertices (the first vertex of each cone edge, as the edge's
   * orientation in the cell says), body index */
  {
    PetscInt nlc = m->cEnd - m->cStart;
    PetscCall(PetscMalloc2(4 * nlc, &m->cellverts, nlc, &m->cellbody));
    for (PetscInt c = m->cStart; c < m->cEnd; c++) {
      const PetscInt *cone, *ornt;
      PetscInt        ncone;
      PetscCall(DMPlexGetConeSize(dm, c, &ncone));
      PetscCheck(ncone == 4, PETSC_COMM_SELF, PETSC_ERR_PLIB, "cell %" PetscInt_FMT " has %" PetscInt_FMT " edges", c, ncone);
      PetscCall(DMPlexGetCone(dm, c, &cone));
      PetscCall(DMPlexGetConeOrientation(dm, c, &ornt));
      for (int k = 0; k < 4; k++) {
        const PetscInt *ev;
        PetscCall(DMPlexGetCone(dm, cone[k], &ev));
        m->cellverts[4 * (c - m->cStart) + k] = ornt[k] >= 0 ? ev[0] : ev[1];
      }
      m->cellbody[c - m->cStart] = pbody[c];
      PetscCheck(pbody[c] >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "cell %" PetscInt_FMT " lost its body", c);
    }
    PetscCall(PetscFree(pbody));
  }
  /* edges owned by another rank (leaves of the point SF) */
  {
    PetscSF         sf;
    PetscInt        nleaves;
    const PetscInt *leaves;
    PetscCall(DMGetPointSF(dm, &sf));
    PetscCall(PetscSFGetGraph(sf, NULL, &nleaves, &leaves, NULL));
    PetscCall(PetscCalloc1(m->eEnd - m->eStart + 1, &m->edgeghost));
    for (PetscInt i = 0; i < nleaves && nleaves > 0; i++) {
      PetscInt p = leaves ? leaves[i] : i;
      if (p >= m->eStart && p < m->eEnd) m->edgeghost[p - m->eStart] = PETSC_TRUE;
    }
  }
  /* displacement dofs: 2 per vertex */
  {
    PetscSection sec;
    PetscInt     pStart, pEnd;
    PetscCall(PetscSectionCreate(comm, &sec));
    PetscCall(PetscSectionSetNumFields(sec, 1));
    PetscCall(PetscSectionSetFieldComponents(sec, 0, 2));
    PetscCall(PetscSectionSetFieldName(sec, 0, "displacement"));
    PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
    PetscCall(PetscSectionSetChart(sec, pStart, pEnd));
    for (PetscInt v = m->vStart; v < m->vEnd; v++) {
      PetscCall(PetscSectionSetDof(sec, v, 2));
      PetscCall(PetscSectionSetFieldDof(sec, v, 0, 2));
    }
    PetscCall(PetscSectionSetUp(sec));
    PetscCall(DMSetLocalSection(dm, sec));
    PetscCall(PetscSectionDestroy(&sec));
  }
  /* global sizes, and a check that the closure order kept the orientation */
  {
    Vec                cl;
    PetscSection       cs;
    const PetscScalar *ca;
    PetscInt           n[2], bad = 0;
    PetscCall(DMGetCoordinatesLocal(dm, &cl));
    PetscCall(DMGetCoordinateSection(dm, &cs));
    PetscCall(VecGetArrayRead(cl, &ca));
    for (PetscInt c = m->cStart; c < m->cEnd; c++) {
      PetscReal xy[8];
      MeshCellCoordinates(m, ca, cs, c, xy);
      if (!(MinCornerJacobian(xy) > 0)) bad++;
    }
    PetscCall(VecRestoreArrayRead(cl, &ca));
    PetscCheck(!bad, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%" PetscInt_FMT " cells lost their orientation in the DMPlex", bad);
    n[0] = m->cEnd - m->cStart;
    {
      PetscSection gs;
      PetscInt     lo, hi;
      PetscCall(DMGetGlobalSection(dm, &gs));
      PetscCall(PetscSectionGetStorageSize(gs, &lo));
      (void)hi;
      n[1] = lo / 2;
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, n, 2, MPIU_INT, MPI_SUM, comm));
    m->ncell_global = n[0];
    m->nvert_global = n[1];
  }
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

void MeshCellCoordinates(const M2dMesh *m, const PetscScalar *a, PetscSection csec, PetscInt c, PetscReal xy[8])
{
  for (PetscInt k = 0; k < 4; k++) {
    PetscInt off;
    PetscSectionGetOffset(csec, m->cellverts[4 * (c - m->cStart) + k], &off);
    xy[2 * k]     = PetscRealPart(a[off]);
    xy[2 * k + 1] = PetscRealPart(a[off + 1]);
  }
}

/* K with an exact preallocation from the cell -> vertex lists (2 dofs per
 * vertex). Rows of vertices shared with another rank also receive that rank's
 * cells: their counts add the other rank's (over-estimates, never under). */
PetscErrorCode MeshCreateMatrix(const M2dMesh *m, PetscInt ngrp, const PetscInt gptr[], const PetscInt gdofs[], Mat *K)
{
  MPI_Comm               comm = PetscObjectComm((PetscObject)m->dm);
  PetscSection           gsec;
  PetscSF                sf;
  ISLocalToGlobalMapping ltog;
  PetscInt               nv = m->vEnd - m->vStart, nc = m->cEnd - m->cStart, nloc, *cptr, *cadj, *gdof, *cnt, *dnz, *onz, lo, hi, nrow = 0;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(PetscSectionGetStorageSize(gsec, &nloc));
  PetscCall(PetscMalloc4(nv + 1, &cptr, 4 * nc + 1, &cadj, nv, &gdof, 2 * (m->vEnd + 1), &cnt));
  /* vertex -> cells */
  PetscCall(PetscArrayzero(cptr, nv + 1));
  for (PetscInt i = 0; i < 4 * nc; i++) cptr[m->cellverts[i] - m->vStart + 1]++;
  for (PetscInt v = 0; v < nv; v++) cptr[v + 1] += cptr[v];
  for (PetscInt i = 0; i < 4 * nc; i++) cadj[cptr[m->cellverts[i] - m->vStart]++] = i / 4;
  for (PetscInt v = nv; v > 0; v--) cptr[v] = cptr[v - 1];
  cptr[0] = 0;
  /* global first dof of each vertex; negative: owned by another rank */
  for (PetscInt v = 0; v < nv; v++) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(gsec, m->vStart + v, &off));
    gdof[v] = off;
  }
  PetscCallMPI(MPI_Scan(&nloc, &hi, 1, MPIU_INT, MPI_SUM, comm));
  lo = hi - nloc;
  /* per local vertex (indexed by point): neighbour vertices in my range (cnt[2p]) and outside it (cnt[2p+1]) */
  PetscCall(PetscArrayzero(cnt, 2 * (m->vEnd + 1)));
  for (PetscInt v = 0; v < nv; v++) {
    PetscInt nb[64], n = 0;
    for (PetscInt k = cptr[v]; k < cptr[v + 1]; k++)
      for (int a = 0; a < 4; a++) {
        PetscInt w = m->cellverts[4 * cadj[k] + a] - m->vStart, dup = 0;
        for (PetscInt j = 0; j < n && !dup; j++) dup = nb[j] == w;
        if (!dup) {
          PetscCheck(n < 64, PETSC_COMM_SELF, PETSC_ERR_SUP, "a vertex with more than 63 neighbours: mesh too irregular for the preallocation");
          nb[n++] = w;
        }
      }
    for (PetscInt j = 0; j < n; j++) {
      PetscInt g = gdof[nb[j]] >= 0 ? gdof[nb[j]] : -(gdof[nb[j]] + 1);
      cnt[2 * (m->vStart + v) + (g >= lo && g < hi ? 0 : 1)]++;
    }
  }
  /* shared vertices: the owner adds what the other ranks see (both columns counts, as an upper bound) */
  PetscCall(DMGetPointSF(m->dm, &sf));
  {
    PetscInt *sum, *leafv, nroots, pStart, pEnd;
    PetscCall(PetscSFGetGraph(sf, &nroots, NULL, NULL, NULL));
    PetscCall(DMPlexGetChart(m->dm, &pStart, &pEnd));
    if (nroots >= 0) {
      PetscCall(PetscCalloc2(pEnd + 1, &sum, pEnd + 1, &leafv));
      for (PetscInt p = m->vStart; p < m->vEnd; p++) leafv[p] = cnt[2 * p] + cnt[2 * p + 1];
      PetscCall(PetscSFReduceBegin(sf, MPIU_INT, leafv, sum, MPI_SUM));
      PetscCall(PetscSFReduceEnd(sf, MPIU_INT, leafv, sum, MPI_SUM));
      for (PetscInt v = m->vStart; v < m->vEnd; v++)
        if (gdof[v - m->vStart] >= 0 && sum[v]) {
          cnt[2 * v] += sum[v];
          cnt[2 * v + 1] += sum[v];
        }
      PetscCall(PetscFree2(sum, leafv));
    }
  }
  PetscCall(PetscMalloc2(nloc + 1, &dnz, nloc + 1, &onz));
  for (PetscInt v = 0; v < nv; v++)
    if (gdof[v] >= 0) {
      PetscInt r = gdof[v] - lo;
      dnz[r] = dnz[r + 1] = 2 * PetscMin(cnt[2 * (m->vStart + v)], nloc / 2);
      onz[r] = onz[r + 1] = 2 * cnt[2 * (m->vStart + v) + 1];
      nrow++;
    }
  PetscCheck(2 * nrow == nloc, PETSC_COMM_SELF, PETSC_ERR_PLIB, "preallocation: %" PetscInt_FMT " owned vertices for %" PetscInt_FMT " dofs", nrow, nloc);
  /* the couplings of every dof group (a contact row): room for all of them, both blocks (an upper bound) */
  for (PetscInt j = 0; j < ngrp; j++)
    for (PetscInt k = gptr[j]; k < gptr[j + 1]; k++)
      if (gdofs[k] >= lo && gdofs[k] < hi) {
        dnz[gdofs[k] - lo] = PetscMin(dnz[gdofs[k] - lo] + gptr[j + 1] - gptr[j], nloc);
        onz[gdofs[k] - lo] += gptr[j + 1] - gptr[j];
      }
  PetscCall(MatCreate(comm, K));
  PetscCall(MatSetSizes(*K, nloc, nloc, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetType(*K, MATAIJ));
  PetscCall(MatSeqAIJSetPreallocation(*K, 0, dnz));
  PetscCall(MatMPIAIJSetPreallocation(*K, 0, dnz, 0, onz));
  PetscCall(DMGetLocalToGlobalMapping(m->dm, &ltog));
  PetscCall(MatSetLocalToGlobalMapping(*K, ltog, ltog));
  PetscCall(MatSetOption(*K, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  /* ... and explicit zeros there, in the rows this rank owns, so that K + g C^T C keeps K's pattern */
  for (PetscInt j = 0; j < ngrp; j++) {
    PetscInt     n = gptr[j + 1] - gptr[j];
    PetscScalar *zero;
    PetscCall(PetscCalloc1(n + 1, &zero));
    for (PetscInt k = gptr[j]; k < gptr[j + 1]; k++)
      if (gdofs[k] >= lo && gdofs[k] < hi) PetscCall(MatSetValues(*K, 1, &gdofs[k], n, &gdofs[gptr[j]], zero, ADD_VALUES));
    PetscCall(PetscFree(zero));
  }
  PetscCall(PetscFree2(dnz, onz));
  PetscCall(PetscFree4(cptr, cadj, gdof, cnt));
  PetscFunctionReturn(0);
}
