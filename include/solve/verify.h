/* verify.h - a run exits 0 only after its answer has passed its own checks.
 *
 * Equilibrium: the recovered residual |K u + C^T lambda - f| relative to
 * max(|f|, |K u|) (K, f with the supports eliminated). Complementarity of the
 * contact conditions in reference units (units.h: pressures relative to the
 * load stress, gaps relative to the reference displacement): the largest of
 * max(-lambda_j, 0), max(-g_j, 0) and |lambda_j g_j| over the multipliers.
 * Both must be below M2D_VERIFY_TOL; otherwise the run stops with one line
 * that names the figure, its likely cause and what to change. */
#ifndef M2D_VERIFY_H
#define M2D_VERIFY_H
#include "solver.h"

#define M2D_VERIFY_TOL 1e-6

typedef struct {
  PetscReal residual_rel;    /* equilibrium, relative */
  PetscReal complementarity; /* contact conditions, reference units; 0 without unilateral contact */
} M2dVerification;

/* Compute the checks of sol on pb and fail (one line, collective) if one is
 * above M2D_VERIFY_TOL. Collective on the problem's communicator. */
PetscErrorCode M2dVerifyAnswer(const M2dProblem *pb, const M2dSolution *sol, M2dVerification *v);
/* The non-mortar nodes without a multiplier (beyond -contact_reach when the
 * rows were built) must not end up inside the mortar body: the linearised gap
 * g0 + (u_nm - u_m).n of each, against the mortar edge it faces, is at least
 * -M2D_VERIFY_TOL x the largest surface displacement, or the run stops with
 * one line naming the node and -contact_reach. u: the physical displacement
 * (supports' frames rotated back). Collective. */
PetscErrorCode M2dVerifyReach(const M2dProblem *pb, Vec u);
#endif
