/* dual.h - the dual (adjoint) problem of the contact pressure, for adaptivity
 * aimed at the contact pressure (-adapt_goal contact).
 *
 * On the final active set, the quantity J(u) = sum_j omega_j w_j lambda_j has
 * the dual solution z of
 *   [K  C_A^T] [z ]   [0        ]
 *   [C_A   0 ] [mu] = [w omega  ]
 * (inactive multipliers held at zero): the displacement that opens the contact
 * zone in the shape omega. omega is the pressure's interpolation-error
 * indicator along the surface (h^2 |lambda''| / 8: the pressure error of
 * mortar Q4 follows the error of interpolating the exact pressure, largest at
 * the zone's edge where p ~ sqrt(a - x)), with a tenth of the pressure's own
 * shape for reach (dual.c). The goal-oriented indicator weighs each
 * cell's primal error by the dual's, eta_K(u) eta_K(z) (dual-weighted
 * residuals with recovered stresses): cells far from the contact zone, whose
 * error barely moves the pressure, weigh little; the edge of the zone weighs
 * most. On the condensed path the primal's factorization is kept
 * (M2dProblem.keep_factor) and the dual costs one dense LU on the multipliers
 * and one substitution; on the other paths, one factorization of the KKT
 * matrix (MUMPS LU). */
#ifndef M2D_DUAL_H
#define M2D_DUAL_H
#include "solver.h"

/* z (global, layout of pb->f, user frame) for the solution sol of pb.
 * Collective. */
PetscErrorCode M2dDualSolve(M2dProblem *pb, const M2dSolution *sol, Vec z);
#endif
