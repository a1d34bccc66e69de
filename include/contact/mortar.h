/* mortar.h - contact constraints between a non-mortar and a mortar surface.
 *
 * (Non-mortar is what some books call "slave", mortar "master".)
 * Both discretisations produce ContactRows: one row per non-mortar node that
 * carries a Lagrange multiplier (the contact pressure), holding the weighted
 * gap g~_j = sum_dofs B_jd u_d + g~0_j, which must be >= 0.
 *
 * Mortar (seed report section 4, docs/design.md): per non-mortar edge e, the
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
 * a curved surface, except at a sharp node, where it is the edge's own
 * normal: a common vertex, a node of both surfaces at one point whose edges
 * lie on each other (a kink of the interface, or any node of coincident
 * polygons, as matching meshes are), or a corner of its surface (a turn of
 * more than M2D_SURFACE_CORNER degrees: the edges' averaged normal would be
 * the normal of neither). So
 *  - on coincident polygons a row's direction on an edge is that edge's
 *    normal, and a uniform pressure lambda = p gives every node of either side
 *    the force of p on its own edges: the hydrostatic patch test is exact
 *    across kinks (tests/test_kink.py);
 *  - at a corner each edge is pressed along its own normal (a groove's lip,
 *    a punch's sharp edge: the same answer as a surface ended there);
 *  - elsewhere a row has one direction on both its edges, the bisector of the
 *    continuous normals (on Hertz's cylinder on a block it halves the
 *    converged pressure's distance from Hertz against the mortar edges' own
 *    normals, which jump from edge to edge: docs/design.md);
 *  - the direction is constant per row and edge, so the dual basis keeps D
 *    diagonal (each row holds its own node's dofs only).
 * A tangential (friction) row takes t = (-n_y, n_x) of the same n per row and
 * edge (MortarRows with n turned). Not collective. */
PetscErrorCode MortarRowNormals(const M2dSurface *nm, const M2dSurface *m, const M2dSegmentSet *S, PetscReal n[]);
/* A convex corner of the mortar surface (a turn of more than
 * M2D_SURFACE_CORNER degrees, not a common vertex: MortarRowNormals) that a
 * non-mortar row reaches on both sides (its edges have segments on mortar
 * edges before and after the corner along the surface: a ridge, or a
 * groove's lip with the groove's floor within reach). The contact holds the
 * non-mortar nodes and each row's weighted gap averages the gaps on both
 * sides, so such a corner passes between the nodes (a groove's lip under a
 * punch: 27% of the displacement, docs/trust.md). A corner reached on one
 * side only (a punch's edge where the contact ends) is the same as the
 * surface ended there. *corner: the first such mortar node, -1 if none;
 * *turn in degrees. Not collective. */
PetscErrorCode MortarReachedCorner(const M2dSurface *nm, const M2dSurface *m, const M2dSegmentSet *S, PetscInt *corner, PetscReal *turn);
/* The contact rows of the segments S (one per non-mortar node the mortar
 * surface covers), or of node-to-segment projection within reach (NTS); the
 * same on every rank; *R is the caller's (ContactRowsDestroy). With tangent
 * the rows hold the weighted relative displacement along the tangent t =
 * (-n_y, n_x) of each row's normal n instead (Coulomb friction: the same
 * nodes, in the same order, with the same columns; g0 = 0). Not collective. */
PetscErrorCode MortarRows(const M2dSurface *nm, const M2dSurface *m, const M2dSegmentSet *S, M2dMortarBasis basis, PetscBool tangent, M2dContactRows *R);
PetscErrorCode NTSRows(const M2dSurface *nm, const M2dSurface *m, PetscReal reach, PetscBool tangent, M2dContactRows *R);
PetscErrorCode ContactRowsDestroy(M2dContactRows *R);
#endif
