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
 * affine in zeta (also with the dual basis below: the integrands stay quadratic). Row j: D_jk n on non-mortar node k, -M_jl n on mortar node l.
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
