/* verify.h - a run exits 0 only after its answer has passed its own checks.
 *
 * Equilibrium: the recovered residual r = K u + C^T lambda - f (K, f with the
 * supports eliminated) relative to max(|f|, |K u|), below M2D_VERIFY_TOL; or,
 * for a factorization's answer (M2dSolution.factored), its normwise backward
 * error |r| / (|K| |u| + |C^T| |lambda| + |f|) (infinity norms) below
 * M2D_VERIFY_BACKWARD_TOL: a backward-stable solve delivers a few rounding
 * units of it whatever the conditioning, while |r| / |f| grows with it (thin
 * bodies). Complementarity of the contact conditions in reference units
 * (units.h: pressures relative to the load stress, gaps relative to the
 * reference displacement): the largest of max(-lambda_j, 0), max(-g_j, 0) and
 * |lambda_j g_j| over the multipliers, below M2D_VERIFY_TOL. With friction,
 * Coulomb's law at every contact node (reference units): |lambda_t| <= mu
 * lambda_n (an open node: lambda_t = 0); a sticking node has not slipped in
 * the last load step (|s| <= the tolerance); a slipping one carries
 * |lambda_t| = mu lambda_n and its slip s opposes its friction force
 * (lambda_t s <= 0), below M2D_VERIFY_TOL. Otherwise the run
 * stops with one line that names the figure, its likely cause and what to
 * change. */
#ifndef M2D_VERIFY_H
#define M2D_VERIFY_H
#include "solver.h"

#define M2D_VERIFY_TOL 1e-6
/* the equilibrium's backward error a backward-stable solve delivers (verify.c) */
#define M2D_VERIFY_BACKWARD_TOL 1e-12

/* strains and rotations above this are reported (one line on stdout) */
#define M2D_STRAIN_WARN 0.01

typedef struct {
  PetscReal residual_rel;    /* equilibrium, relative */
  PetscReal backward_error;  /* equilibrium, normwise backward error */
  PetscReal complementarity; /* contact conditions, reference units; 0 without unilateral contact */
  PetscReal coulomb;         /* friction: the largest violation of Coulomb's law, reference units; 0 without friction */
  PetscReal strain_max;      /* the largest principal strain (M2dVerifyStrain) */
  PetscReal rotation_max;    /* the largest rotation, rad */
} M2dVerification;

/* Compute the checks of sol on pb and fail (one line, collective) if one is
 * above M2D_VERIFY_TOL. Collective on the problem's communicator. */
PetscErrorCode M2dVerifyAnswer(const M2dProblem *pb, const M2dSolution *sol, M2dVerification *v);
/* Test hook (tests/test_trust_scenes.py; built only with -DM2D_TEST_HOOKS=ON,
 * tools/test.sh): with M2D_TEST_PERTURB = "noise E" in
 * the environment, adds E |u|_inf times a fixed pseudo-random number in
 * [-1, 1] to every entry of u; with "scale E", E u (a wrong answer that
 * M2dVerifyAnswer must refuse). Collective; nothing without the variable. */
PetscErrorCode M2dVerifyTestPerturb(Vec u);
/* Small strain: the largest principal strain and rotation theta of any body
 * (2x2 Gauss points of every cell), into v->strain_max and v->rotation_max.
 * The measure checked is, cell by cell, the larger of the strain and
 * theta^2/2 (what a rotation theta changes in small-strain results). Above
 * M2D_STRAIN_WARN one line on stdout names the body, the figure and where;
 * above -strain_limit (default 0.1) the run stops with that line: the
 * small-strain answer is off by about the strain (uniaxial: by 1.5 times it)
 * and the body's shape has changed by as much. u: the physical displacement
 * (frames rotated back). Collective. */
PetscErrorCode M2dVerifyStrain(const M2dProblem *pb, Vec u, M2dVerification *v);
/* The non-mortar nodes without a multiplier (beyond -contact_reach when the
 * rows were built) must not end up inside the mortar body: the linearised gap
 * g0 + (u_nm - u_m).n of each, against the mortar edge it faces, is at least
 * -M2D_VERIFY_TOL x the largest surface displacement, or the run stops with
 * one line naming the node and -contact_reach. u: the physical displacement
 * (supports' frames rotated back). Collective. */
PetscErrorCode M2dVerifyReach(const M2dProblem *pb, Vec u);
#endif
