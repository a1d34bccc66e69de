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
static int ReadMerge(const Scene *s, ReadInfo *ri, PetscInt *nc_out, PetscInt *nv_out, PetscInt **cells_out, PetscReal **coords_out, PetscInt **cellbody_out, MshMesh msh[2], long nodeoff[3], long **nodemap_out)
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

/* Rank 0: physical curves and points -> labels on edges and vertices. */
static PetscErrorCode SetGroupLabels(DM dm, const Scene *s, MshMesh msh[2], const long nodeoff[3], const long *nodemap, PetscInt nc, char *err, size_t errlen)
{
  PetscFunctionBeginUser;
  err[0] = 0;
  for (int f = 0; f < s->nmesh; f++) {
    for (long i = 0; i < msh[f].nline; i++) {
      const char     *pname = MshPhysicalName(&msh[f], 1, msh[f].linephys[i]);
      char            lname[M2D_NAME_LEN + 8];
      long            a = nodemap[nodeoff[f] + msh[f].line[2 * i]], b = nodemap[nodeoff[f] + msh[f].line[2 * i + 1]];
      PetscInt        pts[2], njoin;
      const PetscInt *join;
      if (!pname) continue; /* an unnamed physical curve: nothing can refer to it */
      if (a < 0 || b < 0) {
        snprintf(err, errlen, "mesh file '%s': physical curve '%s' has a line whose nodes belong to no quadrilateral", s->mesh[f], pname);
        PetscFunctionReturn(0);
      }
      pts[0] = nc + (PetscInt)a;
      pts[1] = nc + (PetscInt)b;
      PetscCall(DMPlexGetJoin(dm, 2, pts, &njoin, &join));
      if (njoin != 1) {
        PetscCall(DMPlexRestoreJoin(dm, 2, pts, &njoin, &join));
        snprintf(err, errlen, "mesh file '%s': physical curve '%s' has a line (nodes %ld, %ld) that is not an edge of any quadrilateral", s->mesh[f], pname, msh[f].line[2 * i] + 1, msh[f].line[2 * i + 1] + 1);
        PetscFunctionReturn(0);
      }
      LabelName(pname, lname, sizeof(lname));
      PetscCall(DMSetLabelValue(dm, lname, join[0], 1));
      PetscCall(DMPlexRestoreJoin(dm, 2, pts, &njoin, &join));
    }
    for (long i = 0; i < msh[f].npoint; i++) {
      const char *pname = MshPhysicalName(&msh[f], 0, msh[f].pointphys[i]);
      char        lname[M2D_NAME_LEN + 8];
      long        a = nodemap[nodeoff[f] + msh[f].point[i]];
      if (!pname) continue;
      if (a < 0) {
        snprintf(err, errlen, "mesh file '%s': physical point '%s' is not a node of any quadrilateral", s->mesh[f], pname);
        PetscFunctionReturn(0);
      }
      LabelName(pname, lname, sizeof(lname));
      PetscCall(DMSetLabelValue(dm, lname, nc + (PetscInt)a, 1));
    }
  }
  PetscFunctionReturn(0);
}

/* The interpolated plex (cells, vertices, edges) straight from the cell list:
 * the edges are found here from the vertex pairs, several times faster than
 * DMPlexInterpolate on large meshes. Points: cells 0..nc-1, vertices
 * nc..nc+nv-1, then the edges; an edge's cone is (lower vertex, higher
 * vertex), a cell's cone its 4 edges in the order of its vertices, oriented 0
 * when the edge runs along the cell's vertex order and -1 against it
 * (DMPlexCheckFaces agrees: tests/test_mesh_plex.py). */
static PetscErrorCode CreatePlex(MPI_Comm comm, PetscInt nc, PetscInt nv, const PetscInt cells[], const PetscReal coords[], DM *dm)
{
  PetscInt *ptr, *other, *sid, *edge, *ev, ne = 0, numPoints[3], *coneSize, *cones, *orient, np, k = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(nv + 1, &ptr));
  PetscCall(PetscMalloc4(4 * nc + 1, &other, 4 * nc + 1, &sid, 4 * nc + 1, &edge, 8 * nc + 1, &ev));
  for (PetscInt c = 0; c < nc; c++)
    for (int j = 0; j < 4; j++) ptr[PetscMin(cells[4 * c + j], cells[4 * c + (j + 1) % 4]) + 1]++;
  for (PetscInt v = 0; v < nv; v++) ptr[v + 1] += ptr[v];
  for (PetscInt c = 0; c < nc; c++)
    for (int j = 0; j < 4; j++) {
      PetscInt a = cells[4 * c + j], b = cells[4 * c + (j + 1) % 4], lo = PetscMin(a, b);
      other[ptr[lo]] = PetscMax(a, b);
      sid[ptr[lo]++]  = 4 * c + j;
    }
  for (PetscInt v = nv; v > 0; v--) ptr[v] = ptr[v - 1];
  ptr[0] = 0;
  for (PetscInt v = 0; v < nv; v++)
    for (PetscInt i = ptr[v]; i < ptr[v + 1]; i++) {
      PetscInt e = -1;
      for (PetscInt j = ptr[v]; j < i && e < 0; j++)
        if (other[j] == other[i]) e = edge[sid[j]];
      if (e < 0) {
        e             = ne++;
        ev[2 * e]     = v;
        ev[2 * e + 1] = other[i];
      }
      edge[sid[i]] = e;
    }
  numPoints[0] = nv;
  numPoints[1] = ne;
  numPoints[2] = nc;
  np           = nc + nv + ne;
  PetscCall(PetscMalloc3(np + 1, &coneSize, 4 * nc + 2 * ne + 1, &cones, 4 * nc + 2 * ne + 1, &orient));
  for (PetscInt c = 0; c < nc; c++) {
    coneSize[c] = 4;
    for (int j = 0; j < 4; j++, k++) {
      PetscInt e = edge[4 * c + j];
      cones[k]   = nc + nv + e;
      orient[k]  = ev[2 * e] == cells[4 * c + j] ? 0 : -1;
    }
  }
  for (PetscInt v = 0; v < nv; v++) coneSize[nc + v] = 0;
  for (PetscInt e = 0; e < ne; e++, k += 2) {
    coneSize[nc + nv + e] = 2;
    cones[k]              = nc + ev[2 * e];
    cones[k + 1]          = nc + ev[2 * e + 1];
    orient[k] = orient[k + 1] = 0;
  }
  PetscCall(PetscFree(ptr));
  PetscCall(PetscFree4(other, sid, edge, ev));
  PetscCall(DMCreate(comm, dm));
  PetscCall(DMSetType(*dm, DMPLEX));
  PetscCall(DMSetDimension(*dm, 2));
  {
    PetscScalar *xy;
    PetscCall(PetscMalloc1(2 * nv + 1, &xy));
    for (PetscInt i = 0; i < 2 * nv; i++) xy[i] = coords[i];
    PetscCall(DMPlexCreateFromDAG(*dm, 2, numPoints, coneSize, cones, orient, xy));
    PetscCall(PetscFree(xy));
  }
  PetscCall(PetscFree3(coneSize, cones, orient));
  PetscFunctionReturn(0);
}

/* -mesh_partitioner metis: libmetis splits the cells (graph: cells sharing an
 * edge) on rank 0 and DMPlexDistribute gets the result as a shell partition */
static PetscErrorCode PartitionMetis(DM dm, PetscMPIInt size, PetscPartitioner part)
{
  PetscInt  cStart, cEnd, nc, *sizes, *points;
  idx_t    *xadj, *adj, *where, nvtx, ncon = 1, nparts = size, objval = 0, opts[METIS_NOPTIONS];
  PetscInt  k = 0;
  int       rc = METIS_OK;

  PetscFunctionBeginUser;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  nc = cEnd - cStart;
  PetscCall(PetscMalloc5(nc + 1, &xadj, 4 * nc + 1, &adj, nc + 1, &where, size, &sizes, nc + 1, &points));
  xadj[0] = 0;
  for (PetscInt c = cStart; c < cEnd; c++) {
    const PetscInt *cone;
    PetscInt        ncone;
    PetscCall(DMPlexGetConeSize(dm, c, &ncone));
    PetscCall(DMPlexGetCone(dm, c, &cone));
    for (PetscInt j = 0; j < ncone; j++) {
      const PetscInt *sup;
      PetscInt        ns;
      PetscCall(DMPlexGetSupportSize(dm, cone[j], &ns));
      PetscCall(DMPlexGetSupport(dm, cone[j], &sup));
      for (PetscInt i = 0; i < ns; i++)
        if (sup[i] != c) adj[k++] = (idx_t)(sup[i] - cStart);
    }
    xadj[c - cStart + 1] = (idx_t)k;
  }
  nvtx = (idx_t)nc;
  METIS_SetDefaultOptions(opts);
  opts[METIS_OPTION_NUMBERING] = 0;
  if (nc > 0) rc = nc >= size ? METIS_PartGraphRecursive(&nvtx, &ncon, xadj, adj, NULL, NULL, NULL, &nparts, NULL, NULL, opts, &objval, where) : METIS_ERROR_INPUT;
  PetscCheck(rc == METIS_OK, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -mesh_partitioner metis: METIS_PartGraphRecursive failed (%d) on %" PetscInt_FMT " cells for %d ranks", rc, nc, (int)size);
  PetscCall(PetscInfo(dm, "METIS: %" PetscInt_FMT " cells in %d parts, %ld cut edges\n", nc, (int)size, (long)objval));
  for (PetscMPIInt p = 0; p < size; p++) sizes[p] = 0;
  for (PetscInt c = 0; c < nc; c++) sizes[where[c]]++;
  {
    PetscInt off[1024];
    PetscCheck(size <= 1024, PETSC_COMM_SELF, PETSC_ERR_SUP, "option -mesh_partitioner metis: at most 1024 ranks");
    off[0] = 0;
    for (PetscMPIInt p = 1; p < size; p++) off[p] = off[p - 1] + sizes[p - 1];
    for (PetscInt c = 0; c < nc; c++) points[off[where[c]]++] = c + cStart;
  }
  PetscCall(PetscPartitionerSetType(part, PETSCPARTITIONERSHELL));
  PetscCall(PetscPartitionerShellSetPartition(part, size, sizes, points));
  PetscCall(PetscFree5(xadj, adj, where, sizes, points));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshCreate(MPI_Comm comm, Scene *s, Mesh *m)
{
  PetscMPIInt rank, size;
  ReadInfo   *ri;
  MshMesh     msh[2];
  long        nodeoff[3] = {0, 0, 0}, *nodemap = NULL;
  PetscInt    nc = 0, nv = 0, *cells = NULL, *cellbody = NULL, *pbody = NULL;
  PetscSF     mig = NULL;
  PetscReal  *coords = NULL;
  DM          dm;
  char        err[2048];

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(m, sizeof(*m)));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCheck(s->nmesh > 0, comm, PETSC_ERR_USER_INPUT, "option -mesh: no mesh file given (for example -mesh meshes/patch_uniform.msh)");
  PetscCall(PetscSNPrintf(m->files, sizeof(m->files), "%s%s%s", s->mesh[0], s->nmesh > 1 ? ", " : "", s->nmesh > 1 ? s->mesh[1] : ""));
  PetscCall(PetscCalloc1(1, &ri));
  memset(msh, 0, sizeof(msh));
  if (rank == 0) {
    if (ReadMerge(s, ri, &nc, &nv, &cells, &coords, &cellbody, msh, nodeoff, &nodemap)) {
      if (!ri->err[0]) snprintf(ri->err, sizeof(ri->err), "cannot read the mesh");
    }
  }
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

  PetscCall(CreatePlex(comm, nc, nv, cells, coords, &dm));
  if (s->mesh_check) { /* -mesh_check: PETSc's own consistency checks of the plex */
    PetscCall(DMPlexCheckSymmetry(dm));
    PetscCall(DMPlexCheckSkeleton(dm, 0));
    PetscCall(DMPlexCheckFaces(dm, 0));
    PetscCall(DMPlexCheckGeometry(dm));
  }
  PetscCall(PetscObjectSetName((PetscObject)dm, "mesh"));
  for (PetscInt g = 0; g < m->ngroup; g++) {
    char lname[M2D_NAME_LEN + 8];
    LabelName(m->group[g], lname, sizeof(lname));
    PetscCall(DMCreateLabel(dm, lname));
  }
  err[0] = 0;
  { /* the body of every point (cells; -1 elsewhere), carried along by the distribution */
    PetscInt pStart, pEnd;
    PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
    PetscCall(PetscMalloc1(pEnd + 1, &pbody));
    for (PetscInt p = 0; p < pEnd; p++) pbody[p] = p < nc ? cellbody[p] : -1;
  }
  if (rank == 0) PetscCall(SetGroupLabels(dm, s, msh, nodeoff, nodemap, nc, err, sizeof(err)));
  for (int f = 0; f < 2; f++) MshFree(&msh[f]);
  free(nodemap); free(cells); free(coords); free(cellbody);
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));

  if (size > 1) {
    DM               dist = NULL;
    PetscPartitioner part;
    PetscCall(DMPlexGetPartitioner(dm, &part));
    if (s->mesh_partitioner == M2D_PARTITIONER_METIS) PetscCall(PartitionMetis(dm, size, part));
    else PetscCall(PetscPartitionerSetFromOptions(part));
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

PetscErrorCode MeshDestroy(Mesh *m)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree2(m->cellverts, m->cellbody));
  PetscCall(PetscFree(m->edgeghost));
  PetscCall(DMDestroy(&m->dm));
  PetscFunctionReturn(0);
}

PetscInt MeshGroupDim(const Mesh *m, const char *name)
{
  for (PetscInt g = 0; g < m->ngroup; g++)
    if (!strcmp(m->group[g], name)) return m->groupdim[g];
  return -1;
}

PetscErrorCode MeshGetGroupIS(const Mesh *m, const char *name, const char *option, IS *is)
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

void MeshCellCoordinates(const Mesh *m, const PetscScalar *a, PetscSection csec, PetscInt c, PetscReal xy[8])
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
PetscErrorCode MeshCreateMatrix(const Mesh *m, Mat *K)
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
  PetscCall(MatCreate(comm, K));
  PetscCall(MatSetSizes(*K, nloc, nloc, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetType(*K, MATAIJ));
  PetscCall(MatSeqAIJSetPreallocation(*K, 0, dnz));
  PetscCall(MatMPIAIJSetPreallocation(*K, 0, dnz, 0, onz));
  PetscCall(DMGetLocalToGlobalMapping(m->dm, &ltog));
  PetscCall(MatSetLocalToGlobalMapping(*K, ltog, ltog));
  PetscCall(MatSetOption(*K, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscCall(PetscFree2(dnz, onz));
  PetscCall(PetscFree4(cptr, cadj, gdof, cnt));
  PetscFunctionReturn(0);
}
