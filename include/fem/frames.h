/* frames.h - supports on inclined boundaries (-dirichlet G:n[:V], G:t[:V]).
 *
 * At a vertex of such a curve the two displacement dofs are written in the
 * curve's frame: u = T u~ with T = [n t] (n the outward unit normal, averaged
 * over the curve's edges at the vertex on every rank; t = (-n_y, n_x)), so
 * u~_0 = u.n and u~_1 = u.t are plain dofs and the support is an ordinary
 * Dirichlet row (u~_0 = V for n, u~_1 = V for t). The solver sees
 * K~ = T^T K T, f~ = T^T f and the contact rows C~ = C T: the same problem in
 * rotated coordinates, symmetric as before. Elements are rotated as they are
 * assembled; the answer is rotated back (u = T u~) before anything is
 * reported. */
#ifndef M2D_FRAMES_H
#define M2D_FRAMES_H
#include "mortar.h"
#include "mesh.h"

/* Every support (-dirichlet, all frames) resolved per vertex, the same on
 * every rank: the vertex's conditions u.d = V are collected (axis directions
 * from x/y supports, n or t of the curve from n/t supports; parallel ones
 * once). One inclined direction d gives the vertex a frame with n = d and its
 * dof 0 held; an axis direction holds that component; two independent
 * directions hold both components (u solved from the two conditions).
 * Conditions that contradict each other (two values along one direction, a
 * third direction the other two fix otherwise) make the vertex's values NaN. */
typedef struct {
  PetscBool  any;    /* some vertex has a frame (on any rank) */
  PetscReal *normal; /* 2 per local vertex (vStart..vEnd): n, or (0, 0) without a frame */
  PetscInt  *mask;   /* per local vertex: bit d = dof d held (in the vertex's frame) */
  PetscReal *value;  /* 2 per local vertex: the held values */
} M2dFrames;

/* The supports of s per vertex. Collective. */
PetscErrorCode M2dFramesCreate(const M2dMesh *m, const M2dScene *s, M2dFrames *fr);
PetscErrorCode M2dFramesDestroy(M2dFrames *fr);
/* The frames of load stage `stage` > 0 (scene.h): fr's supports (the same
 * frames and held dofs) with the values that stage's -stage<k>_dirichlet
 * adds (0 where it adds none), into *frs. Collective. */
PetscErrorCode M2dFramesStage(const M2dMesh *m, const M2dScene *s, PetscInt stage, const M2dFrames *fr, M2dFrames *frs);
/* local vertex v (a point) has a frame; its n in n[2]. Not collective. */
PetscBool M2dFramesAt(const M2dFrames *fr, const M2dMesh *m, PetscInt v, PetscReal n[2]);
/* Ke <- Te^T Ke Te for the cell's 4 vertices (8x8 row major); fe (may be NULL) <- Te^T fe. Not collective. */
void M2dFramesRotateElement(const M2dFrames *fr, const M2dMesh *m, const PetscInt verts[4], PetscReal Ke[64]);
/* In a local vector (2 per vertex, the DM's local section): x <- T^T x
 * (forward, loads) or x <- T x (back, displacements). Not collective. */
PetscErrorCode M2dFramesRotateLocal(const M2dFrames *fr, const M2dMesh *m, Vec xl, PetscBool back);
/* The same on a global vector. Collective. */
PetscErrorCode M2dFramesRotateGlobal(const M2dFrames *fr, const M2dMesh *m, Vec x, PetscBool back);
/* A copy of the contact rows R in the frames' coordinates (C~ = C T). Collective. */
PetscErrorCode M2dFramesRotateRows(const M2dFrames *fr, const M2dMesh *m, const M2dContactRows *R, M2dContactRows *Rt);
#endif
