/* mesh.h - the two (or more) bodies in one distributed DMPlex.
 *
 * Rank 0 reads the .msh file(s) with the strict reader (msh.h), validates them
 * (quads only, positive corner Jacobians, every physical name the options ask
 * for), merges the files, and builds the interpolated DMPlex from the cell
 * list (its own edge finder: DMPlexCreateFromDAG, no DMPlexInterpolate).
 * Each physical curve or point becomes a DMLabel "m2d:NAME" (value 1) on edges
 * or vertices. The plex is distributed (libmetis partition by default); the
 * body index of each cell travels along the migration SF (no label). One
 * vertex carries the 2 displacement dofs. */
#ifndef M2D_MESH_H
#define M2D_MESH_H
#include <petscdmplex.h>
#include "scene.h"

#define M2D_MAX_GROUPS 256

typedef struct {
  DM        dm;
  PetscInt  cStart, cEnd, eStart, eEnd, vStart, vEnd;
  PetscInt *cellverts; /* 4 vertex points per local cell, counter-clockwise */
  PetscInt *cellbody;  /* body index per local cell */
  PetscBool *edgeghost; /* per local edge: owned by another rank (skip when integrating) */
  PetscInt  ngroup;
  char      group[M2D_MAX_GROUPS][M2D_NAME_LEN];
  PetscInt  groupdim[M2D_MAX_GROUPS];
  PetscInt  ncell_global, nvert_global;
  char      files[2 * PETSC_MAX_PATH_LEN + 8]; /* for messages */
} M2dMesh;

PetscErrorCode MeshCreate(MPI_Comm comm, M2dScene *s, M2dMesh *m);
PetscErrorCode MeshDestroy(M2dMesh *m);
/* dimension of a physical group, -1 if the mesh has none of that name */
PetscInt       MeshGroupDim(const M2dMesh *m, const char *name);
/* Local points of a group: for curves the edges, for points the vertices.
 * Errors with a message naming `option` if the group does not exist. */
/* the stiffness matrix: AIJ, preallocated from the cells, local-to-global map
 * of the DM; plus the couplings within each of the ngrp groups of global dofs
 * gdofs[gptr[j] .. gptr[j+1]-1] (the contact rows: K + g C^T C then keeps K's
 * pattern), stored as explicit zeros. ngrp may be 0. */
PetscErrorCode MeshCreateMatrix(const M2dMesh *m, PetscInt ngrp, const PetscInt gptr[], const PetscInt gdofs[], Mat *K);
PetscErrorCode MeshGetGroupIS(const M2dMesh *m, const char *name, const char *option, IS *is);
/* Cell coordinates, counter-clockwise: xy[8] */
void MeshCellCoordinates(const M2dMesh *m, const PetscScalar *coords, PetscSection csec, PetscInt c, PetscReal xy[8]);
#endif
