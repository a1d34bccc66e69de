/* mortar.h - contact constraints between a non-mortar and a mortar surface.
 *
 * (Non-mortar is what some books call "slave", mortar "master".)
 * Both discretisations produce ContactRows: one row per non-mortar node that
 * carries a Lagrange multiplier (the contact pressure), holding the weighted
 * gap g~_j = sum_dofs B_jd u_d + g~0_j, which must be >= 0.
 *
 * Mortar (seed report section 4, ARCHITECTURE.md): per non-mortar edge e, the
 * mortar segments are the overlaps of e with the mortar edges, found by
 * projecting the ends of one edge onto the other along the mortar normal n
 * (seed eq. 6). On a segment, with N the linear shape functions,
 *   D_ij += int N_i(zeta) N_j(zeta) da,   M_ik += int N_i(zeta) N_k(xi(zeta)) da
 * (seed eqs. 12-15) by 2-point Gauss, exact for straight edges since xi is
 * affine in zeta (also with the dual basis below: the integrands stay quadratic).
 * Row j: D_jk n on non-mortar node k, -M_jl n on mortar node l, with n the
 * row's direction on the segment's non-mortar edge (MortarRowNormals).
 *
 * Node-to-segment (seed section 3): node s projects onto the closest mortar
 * edge (xi), tributary length a_s: row a_s [n, -N_1(xi) n, -N_2(xi) n]. */
#ifndef M2D_MORTAR_H
#define M2D_MORTAR_H
#include "surface.h"

typedef struct {
  PetscInt  nm_edge, m_edge;
  PetscReal zeta[2]; /* segment on the non-mortar edge, zeta[0] < zeta[1] in [-1, 1] */
  PetscReal xi[2];   /* the same points projected on the mortar edge */
} M2dSegment;

typedef struct {
  PetscInt nseg;
  M2dSegment *seg;
} M2dSegmentSet;

typedef struct {
  PetscInt   n;      /* multipliers */
  PetscInt  *node;   /* non-mortar surface node of each multiplier */
  PetscInt  *ptr;    /* CSR row pointers into col/val */
  PetscInt  *col;    /* global dof */
  PetscReal *val;
  PetscReal *g0;     /* weighted gap of the reference configuration */
  PetscReal *w;      /* weight: int N_j da (mortar) or a_j (NTS): pressure x w = force */
} M2dContactRows;

/* The mortar segments of surfaces nm and m (every rank holds both whole:
 * surface.h): candidate pairs by bounding boxes (enlarged by reach), facing
 * normals, then the overlap of each pair; segments with a gap beyond +-reach
 * are dropped. *S is the caller's (SegmentSetDestroy). Not collective. */
PetscErrorCode MortarBuildSegments(const M2dSurface *nm, const M2dSurface *m, PetscReal reach, M2dSegmentSet *S);
PetscErrorCode SegmentSetDestroy(M2dSegmentSet *S);
/* multiplier basis: standard (lambda interpolated by N, seed eq. 10) or dual
 * (biorthogonal psi_1 = 2 N_1 - N_2, psi_2 = 2 N_2 - N_1: int psi_i N_j = delta_ij int N_j,
 * so D is diagonal on fully covered edges and the nodal contact conditions decouple) */
typedef enum {
  M2D_MORTAR_STANDARD,
  M2D_MORTAR_DUAL
} M2dMortarBasis;
/* D (2x2, non-mortar edge nodes i,j) and M (2x2, i and mortar edge nodes k)
 * of one segment, 2-point Gauss (exact for straight edges). Not collective. */
void           MortarSegmentDM(const M2dSurface *nm, const M2dSegment *s, M2dMortarBasis basis, PetscReal D[4], PetscReal M[4]);
/* The direction of each row on each of its non-mortar edges: n[4 e + 2 i]
 * (2 numbers) is the direction of the row of edge e's node i (i = 0, 1) on
 * the segments of e, from the mortar body into the non-mortar one; (0, 0)
 * where e has no segment. It is the bisector of the two surfaces' normals at
 * the node, the non-mortar node's and the mortar surface's where the node
 * projects (read off e's segment nearest the node), each taken from its
 * edge's end normals: the node's normal (SurfaceNodeNormal), continuous along
 * a curved surface, except at a common vertex, a node of both surfaces at one
 * point whose edges lie on each other (a kink of the interface, or any node of
 * coincident polygons, as matching meshes are), where it is the edge's own
 * normal. So
 *  - on coincident polygons a row's direction on an edge is that edge's
 *    normal, and a uniform pressure lambda = p gives every node of either side
 *    the force of p on its own edges: the hydrostatic patch test is exact
 *    across kinks (tests/test_kink.py);
 *  - elsewhere a row has one direction on both its edges, the bisector of the
 *    continuous normals (on Hertz's cylinder on a block it halves the
 *    converged pressure's distance from Hertz against the mortar edges' own
 *    normals, which jump from edge to edge: docs/design.md);
 *  - the direction is constant per row and edge, so the dual basis keeps D
 *    diagonal (each row holds its own node's dofs only).
 * A tangential (friction) row takes t = (-n_y, n_x) of the same n per row and
 * edge (MortarRows with n turned). Not collective. */
PetscErrorCode MortarRowNormals(const M2dSurface *nm, const M2dSurface *m, const M2dSegmentSet *S, PetscReal n[]);
/* The contact rows of the segments S (one per non-mortar node the mortar
 * surface covers), or of node-to-segment projection within reach (NTS); the
 * same on every rank; *R is the caller's (ContactRowsDestroy). Not collective. */
PetscErrorCode MortarRows(const M2dSurface *nm, const M2dSurface *m, const M2dSegmentSet *S, M2dMortarBasis basis, M2dContactRows *R);
PetscErrorCode NTSRows(const M2dSurface *nm, const M2dSurface *m, PetscReal reach, M2dContactRows *R);
PetscErrorCode ContactRowsDestroy(M2dContactRows *R);
#endif
