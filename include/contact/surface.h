/* surface.h - contact surfaces: the edges of a named boundary part, gathered
 * on every rank (the interface is one dimension lower than the mesh, so this is
 * cheap and keeps the segment search serial and simple).
 *
 * Each edge is oriented with its body on the left, so its outward unit normal
 * is (t_y, -t_x) for the unit tangent t. Nodes are identified by the global dof
 * of their u_x (u_y is the next dof). */
#ifndef M2D_SURFACE_H
#define M2D_SURFACE_H
#include "mesh.h"

typedef struct {
  PetscInt   nnode, nedge;
  PetscReal *x;       /* 2 per node */
  PetscInt  *gdof;    /* global dof of u_x per node */
  PetscInt  *edge;    /* 2 node indices per edge */
  PetscReal *normal;  /* outward unit normal per edge (2 per edge) */
  PetscReal *len;     /* edge lengths */
  PetscInt  *n2e_ptr; /* node -> edges (CSR) */
  PetscInt  *n2e;
  PetscReal  lo[2], hi[2]; /* bounding box */
  PetscInt   body;         /* body index of the surface's cells (-1 if unknown or several) */
} M2dSurface;

/* Build from plain lists (used by SurfaceGather and by the unit tests). Edges
 * must already be oriented body-on-the-left. Copies the arrays. */
PetscErrorCode SurfaceCreate(PetscInt nnode, const PetscReal x[], const PetscInt gdof[], PetscInt nedge, const PetscInt edge[], M2dSurface *s);
/* Gather the edges of physical curve `group` from every rank (a boundary
 * curve with edges: SceneCheckMesh checks it first). */
PetscErrorCode SurfaceGather(const M2dMesh *m, const char *group, const char *option, M2dSurface *s);
PetscErrorCode SurfaceDestroy(M2dSurface *s);
/* outward unit normal at node i: the normals of the edges at i averaged with
 * weights 1/length, which is the circle's normal when the nodes lie on a circle
 * (graded or not); on a straight surface the edges' own normal */
void SurfaceNodeNormal(const M2dSurface *s, PetscInt i, PetscReal n[2]);
#endif
