/* scenecheck.h - the scene checked against its mesh, in one place, once per
 * mesh (ProblemCreate calls it on every mesh, the adaptive loop's included),
 * before any work is done: every physical group the options name exists, has
 * the dimension its option needs and holds elements; what acts through the
 * boundary (loads, contact surfaces, u.n and u.t supports) lies on it; each
 * contact surface lies on one body and a pair joins two bodies. Corners of
 * a contact surface are fine (the rows take each edge's own normal there);
 * a mortar corner the non-mortar surface reaches on both sides is refused
 * when the segments are built (contact.c, MortarReachedCorner).
 *
 * The mesh's own consistency (cells, orientation, pieces) is checked when it
 * is read (mesh_check.c); what needs the contact search (reach, overlap) when
 * the segments are built (contact.c). */
#ifndef M2D_SCENECHECK_H
#define M2D_SCENECHECK_H
#include "mesh.h"

/* Collective on comm; coordinates in messages are the mesh's (call before the
 * units scale it). */
PetscErrorCode SceneCheckMesh(MPI_Comm comm, const M2dScene *s, const M2dMesh *m);
#endif
