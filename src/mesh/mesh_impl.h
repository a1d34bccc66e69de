/* mesh_impl.h - the mesh module's internals, shared by its files (not public):
 *   mesh.c             MeshCreate, MeshCreateFromMsh and what every path does
 *                      once the plex exists (labels, cell lists, section), the API
 *   mesh_read.c        rank 0: merge the sources into one cell list, reorient
 *                      clockwise quads, check every quad and the names
 *   mesh_check.c       rank 0: the skeleton's checks (edges of more than two cells,
 *                      overlapping cells, a body boundary that crosses itself)
 *   mesh_plex.c        rank 0: the skeleton (every edge once), physical groups as
 *                      points, a DMPlex from local lists
 *   mesh_distribute.c  several ranks: METIS partition and the per-rank packages
 *   mesh_matrix.c      MeshCreateMatrix
 *   mesh_modes.c       MeshRigidBodyModes
 *   mesh_h5.c          the mesh in PETSc's HDF5 format: -mesh_save, and -mesh F.h5
 *                      read on rank 0 into an MshMesh (then the .msh path) */
#ifndef M2D_MESH_IMPL_H
#define M2D_MESH_IMPL_H
#include "logging.h"
#include "mesh.h"
#include <petscsf.h>

#define M2D_ERR_LEN 2048

/* What rank 0 learns from the sources and broadcasts (a flat struct: one MPI_Bcast). */
typedef struct {
  char     err[M2D_ERR_LEN]; /* empty: no error */
  PetscInt ngroup;
  char     group[M2D_MAX_GROUPS][M2D_NAME_LEN];
  PetscInt groupdim[M2D_MAX_GROUPS];
  PetscInt nbody;
  char     body[M2D_MAX_BODIES][M2D_NAME_LEN];
  PetscInt nflip[M2D_MAX_BODIES]; /* clockwise quads reoriented, per body */
} MeshReadInfo;

/* The sources being merged (rank 0): nmsh meshes; label[f] names source f in
 * messages ("mesh file 'a.msh'"), all names them together ("a.msh, b.msh"). */
typedef struct {
  const MshMesh *msh;
  PetscInt       nmsh;
  const char   **label;
  const char    *all;
} MeshSources;

/* Rank 0: the merged mesh as lists. Vertices are the used nodes of all sources,
 * numbered in order of first use; cells counter-clockwise. */
typedef struct {
  PetscInt   nc, nv;
  PetscInt  *cells;    /* 4 vertex ids per cell, counter-clockwise */
  PetscReal *coords;   /* 2 per vertex, scaled by -mesh_scale */
  PetscInt  *cellbody; /* body index per cell */
  long      *celltag;  /* element tag per cell (messages) */
  int       *cellsrc;  /* source of each cell (messages) */
  long      *nodemap;  /* source node (nodeoff[f] + index) -> vertex id, -1 if unused */
  long      *nodeoff;  /* nmsh + 1 offsets */
  PetscInt   nent, *ent; /* group entries: (group index, 0 vertex / 1 edge, vertex or edge id) */
} MeshLists;

/* The skeleton of the merged mesh (rank 0): every edge found once from the
 * vertex pairs of the cells (several times faster than DMPlexInterpolate). */
typedef struct {
  PetscInt        nc, nv, ne;
  const PetscInt *cells; /* 4 per cell, vertex ids, counter-clockwise (borrowed) */
  PetscInt       *side;  /* 4 per cell: the edge from cells[4c+j] to cells[4c+(j+1)%4] */
  PetscInt       *ornt;  /* 4 per cell: 0 if that edge runs from cells[4c+j] (its lower vertex), -1 if against */
  PetscInt       *ev;    /* 2 per edge: lower, higher vertex id */
  PetscInt       *eptr;  /* edges whose lower vertex is v: eptr[v] .. eptr[v+1]-1 */
  PetscInt       *ecell; /* 2 per edge: its cells, -1 if none */
  PetscInt        third[2]; /* an edge met by a third cell (edge, cell), -1 if none */
} MeshSkel;

/* mesh_read.c */
int  MeshMerge(const M2dScene *s, const MeshSources *src, MeshReadInfo *ri, MeshLists *L);
void MeshListsFree(MeshLists *L);
/* mesh_check.c: 0, or 1 with one line in err */
int MeshCheckSkeleton(const M2dScene *s, const MeshSources *src, const MeshLists *L, const MeshSkel *sk, char *err, size_t len);
/* mesh_plex.c */
PetscErrorCode MeshSkelBuild(PetscInt nc, PetscInt nv, const PetscInt cells[], MeshSkel *sk);
void           MeshSkelFree(MeshSkel *sk);
PetscErrorCode MeshGroupEntries(const M2dMesh *m, const MeshSources *src, MeshLists *L, const MeshSkel *sk, M2dGroupInner inner[], char *err, size_t len);
PetscErrorCode MeshPlexFromLists(MPI_Comm comm, PetscInt ncl, PetscInt nvl, PetscInt nel, const PetscInt ccone[], const PetscInt cornt[], const PetscInt econe[], const PetscReal xy[], DM *dm);
/* mesh_distribute.c: every rank gets its plex, the body of each local cell
 * (pbody, indexed by point, -1 off cells) and its label points (group, point) */
PetscErrorCode MeshBuildDistributed(MPI_Comm comm, const MeshSkel *sk, const MeshLists *L, DM *dm, PetscInt **pbody, PetscInt **lab, PetscInt *nlab);
/* mesh_h5.c: PETSc's HDF5 format (-mesh F.h5, -mesh_save F.h5) */
PetscBool      MeshIsHDF5(const char *path);
/* rank 0, not collective: the file -mesh_save wrote, checked, as MshRead would
 * give the same mesh from a .msh file; 0, or 1 with one line in err naming it */
int MeshReadHDF5(const char *path, MshMesh *m, char *err, size_t len);
#endif
