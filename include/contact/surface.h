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

/* degrees: a surface that turns by more at a node has a corner there (its
 * edges' averaged normal is the normal of neither: mortar.c takes each
 * edge's own) */
#define M2D_SURFACE_CORNER 45.0

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

/* A bounding-volume tree over a surface's edges, for the searches between two
 * surfaces (mortar segments, node-to-segment projection, the reach checks):
 * each node bounds its edges in a frame turned to their mean direction, so a
 * straight or gently curved run of edges is bounded tightly at any
 * inclination, and also bounds the region within `reach` of them along their
 * normals (the points that project onto an edge within reach). Built in
 * O(m log m), the same on every rank. */
typedef struct {
  PetscReal u[2];         /* the node's frame: u, and v = (-u_y, u_x) */
  PetscReal lo[2], hi[2]; /* its edges' extent along u and v */
  PetscReal nu, nv;       /* the largest |n.u| and |n.v| of its edges' normals */
  PetscInt  first, count; /* its edges: perm[first .. first + count) */
  PetscInt  child;        /* its first child (the second follows it); -1: a leaf */
} M2dTreeNode;

typedef struct {
  const M2dSurface *s;
  PetscInt          nnode;
  M2dTreeNode      *node;
  PetscInt         *perm;
  PetscReal         eps; /* slack for round-off in the bounds */
} M2dSurfaceTree;

PetscErrorCode SurfaceTreeCreate(const M2dSurface *s, M2dSurfaceTree *t);
PetscErrorCode SurfaceTreeDestroy(M2dSurfaceTree *t);
/* The edges f whose region within reach (the points q + g n_f, q on f, |g| <=
 * reach) may meet the segment ab (a == b: a point), in ascending order in
 * list[0 .. *n); *list grows as needed (*cap its size; free with PetscFree).
 * Every edge whose region meets ab is in it. Not collective. */
PetscErrorCode SurfaceTreeNear(const M2dSurfaceTree *t, const PetscReal a[2], const PetscReal b[2], PetscReal reach, PetscInt *n, PetscInt *cap, PetscInt **list);
/* The edge with the least key(ctx, f) (the lowest index among equal keys)
 * over the edges whose key is in [0, bound] (a negative key: not a
 * candidate), and its key in *best (-1 and PETSC_MAX_REAL: none). key(f) must
 * not be below the distance from p to edge f (less 1e-12 of its length): the
 * tree skips nodes farther from p than the best key so far, or than bound (a
 * point with no candidate visits every node within bound of it: keep bound
 * as small as the question allows). Not collective. */
PetscInt SurfaceTreeNearest(const M2dSurfaceTree *t, const PetscReal p[2], PetscReal (*key)(void *, PetscInt), void *ctx, PetscReal bound, PetscReal *best);
/* The edge that point p of another surface (its normal nn there) faces
 * (normals opposed) and projects onto (the foot in the edge), the nearest to
 * p among those at a signed distance d in [dmin, bound] along the edge's
 * normal (> 0: outside the edge's body); its d and the foot's parameter in
 * [0, 1] (from the edge's first node). -1: none. Not collective. */
PetscInt SurfaceTreeFacing(const M2dSurfaceTree *t, const PetscReal p[2], const PetscReal nn[2], PetscReal dmin, PetscReal bound, PetscReal *d, PetscReal *foot);
#endif
