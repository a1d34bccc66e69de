/* mesh.h - the bodies in one distributed DMPlex.
 *
 * Rank 0 reads the .msh file(s) with the strict reader (msh.h), or the .h5
 * file -mesh_save wrote, or takes an MshMesh filled in memory
 * (MeshCreateFromMsh); it merges them, reorients
 * clockwise quads, refuses degenerate or non-convex quads and overlapping cells,
 * checks every physical name the options ask for, and builds the interpolated
 * DMPlex from the cell list (its own edge finder: DMPlexCreateFromDAG, no
 * DMPlexInterpolate). Each physical curve or point becomes a DMLabel "m2d:NAME"
 * (value 1) on edges or vertices. On several ranks libmetis splits the cells on
 * rank 0 and every rank builds its own part (-mesh_partitioner petsc:
 * DMPlexDistribute instead). One vertex carries the 2 displacement dofs. */
#ifndef M2D_MESH_H
#define M2D_MESH_H
#include <petscdmplex.h>
#include "msh.h"
#include "scene.h"

#define M2D_MAX_GROUPS 1024 /* physical groups of the mesh(es): four per body at M2D_MAX_BODIES */

/* A physical curve's edges that lie inside the mesh (an edge of two cells):
 * how many, and the first one (for messages). */
typedef struct {
  PetscInt  n;
  PetscInt  body[2]; /* body index of its two cells */
  PetscReal xy[4]; /* its two ends, in the mesh's coordinates as read (times -mesh_scale) */
} M2dGroupInner;

typedef struct {
  DM        dm;
  PetscInt  cStart, cEnd, eStart, eEnd, vStart, vEnd;
  PetscInt *cellverts; /* 4 vertex points per local cell, counter-clockwise */
  PetscInt *cellbody;  /* body index per local cell */
  PetscBool *edgeghost; /* per local edge: owned by another rank (skip when integrating) */
  PetscInt  ngroup;
  char      group[M2D_MAX_GROUPS][M2D_NAME_LEN];
  PetscInt  groupdim[M2D_MAX_GROUPS];
  M2dGroupInner inner[M2D_MAX_GROUPS]; /* per group: its edges inside a body */
  PetscInt  ncell_global, nvert_global;
  char      files[2 * PETSC_MAX_PATH_LEN + 8]; /* for messages */
} M2dMesh;

/* Collective on comm. Reads s->mesh[0..s->nmesh-1] on rank 0 (.msh, or one .h5
 * file written by -mesh_save; coordinates times s->mesh_scale), and builds *m; fills s->nbody and the body names when s->nbody is 0; writes
 * -mesh_save. Bad input: one-line error on every rank, nothing left allocated. */
PetscErrorCode MeshCreate(MPI_Comm comm, M2dScene *s, M2dMesh *m);
/* Collective on comm. As MeshCreate from nmsh meshes filled in memory on rank 0
 * (msh and nmsh ignored on other ranks; not modified; the caller frees them);
 * `what` names the source in error messages (e.g. "remeshed hertz.geo step 2"). */
PetscErrorCode MeshCreateFromMsh(MPI_Comm comm, M2dScene *s, MshMesh msh[], PetscInt nmsh, const char *what, M2dMesh *m);
/* Collective. Write *m (its coordinates times L) to path in PETSc's HDF5
 * format, as -mesh_save does; the adaptive loop saves its final mesh with it. */
PetscErrorCode MeshSave(const M2dMesh *m, const M2dScene *s, PetscReal L, const char *path);
/* Not collective. Frees what MeshCreate* allocated in *m (not m itself). */
PetscErrorCode MeshDestroy(M2dMesh *m);
/* Not collective. Dimension of a physical group, -1 if the mesh has none of that name. */
PetscInt       MeshGroupDim(const M2dMesh *m, const char *name);
/* Not collective (errors are, as every rank has the same groups). Local points
 * of a group: edges for curves, vertices for points; the caller destroys *is.
 * Errors with a message naming `option` if the group does not exist. */
PetscErrorCode MeshGetGroupIS(const M2dMesh *m, const char *name, const char *option, IS *is);
/* Collective. The number of points of a group (its local points summed over
 * the ranks); the same errors as MeshGetGroupIS. */
PetscErrorCode MeshGroupSize(const M2dMesh *m, const char *name, const char *option, PetscInt *n);
/* Collective. The stiffness matrix K (AIJ, block size 2, the DM's
 * local-to-global map), preallocated from the cells, plus the couplings within
 * each of the ngrp groups of global dofs gdofs[gptr[j] .. gptr[j+1]-1] (the
 * contact rows: K + g C^T C then keeps K's pattern), stored as explicit zeros.
 * ngrp may be 0. The caller destroys *K. */
PetscErrorCode MeshCreateMatrix(const M2dMesh *m, PetscInt ngrp, const PetscInt gptr[], const PetscInt gdofs[], Mat *K);
/* Collective. The rigid-body modes (2 translations and the rotation about the
 * centroid) of every body (per_body; bodies sharing vertices count as one),
 * or of all bodies together (3 vectors: what an algebraic multigrid wants,
 * since its aggregates lie in one body), in the DM's global dof layout,
 * orthonormalised: the near-null space of K. The caller destroys *sp. */
PetscErrorCode MeshRigidBodyModes(const M2dMesh *m, PetscBool per_body, MatNullSpace *sp);
/* Not collective. Cell c's corner coordinates, counter-clockwise, into xy[8]
 * (a: the local coordinate array, csec: the coordinate section). */
void MeshCellCoordinates(const M2dMesh *m, const PetscScalar *coords, PetscSection csec, PetscInt c, PetscReal xy[8]);

/* Read access to the local arrays a loop over cells or vertices needs: the
 * coordinates (section cs, array ca), the dof section lsec and, when opened
 * with a displacement, its local copy with the ghost values (ul, array ua). */
typedef struct {
  DM                 dm;
  PetscSection       lsec, cs;
  Vec                cl, ul;
  const PetscScalar *ca, *ua;
} M2dMeshArrays;
/* Opens *a on m; u (global, may be NULL: no ua) is scattered to ul, which makes
 * the call collective. Every open is closed by MeshArraysClose. */
PetscErrorCode MeshArraysOpen(const M2dMesh *m, Vec u, M2dMeshArrays *a);
/* Not collective. Gives back what MeshArraysOpen took. */
PetscErrorCode MeshArraysClose(M2dMeshArrays *a);
#endif
