/* activeset.h - unilateral frictionless contact through SNES.
 *
 * Unknowns z = [u; lambda] in the layout of the KKT matrix. Default: the
 * primal-dual active set method written as a semismooth Newton method on
 *   F_u      = K u + C^T lambda - f                (K u = f + B^T lambda)
 *   F_lambda = -min(lambda / c, g~),  g~ = r - C u (weighted gap, >= 0)
 * Row j is active when lambda_j / c >= g~_j; then its Jacobian row is C_j
 * (the constraint g~_j = 0), otherwise -e_j / c (lambda_j = 0). A full Newton
 * step is one active-set update (Hueber & Wohlmuth); it stops when the active
 * set is unchanged and the residual is at tolerance. c = E* / h^2 from the
 * materials and the non-mortar edge length (unit-free decisions).
 * On the condensed path the same iteration runs on the multipliers alone
 * (condensed.h): the SNES unknown is nu = lambda - g C u, u is recovered once
 * at the end; same active sets, same answer.
 * Before each step the chosen set is checked to hold every body together with
 * the supports (supports.h): a set that frees a body means the contact has
 * opened and nothing holds it, which stops the run with one line.
 * Second choice, -snes_type vinewtonrsls: PETSc's reduced-space VI solver with
 * lambda >= 0 and the residual g~ on the multiplier rows. */
#ifndef M2D_ACTIVESET_H
#define M2D_ACTIVESET_H
#include "problem.h"

typedef struct {
  PetscInt  iterations; /* active-set steps (SNES iterations) */
  PetscInt  nactive;
  PetscInt  cycles;
  PetscReal c;
  PetscBool vi;
  PetscBool condensed;   /* the condensed path was used */
  PetscReal factor_time; /* its one factorization (seconds) */
  PetscReal factor_flops, factor_flops_max; /* its MUMPS flops: all ranks, the largest rank's share */
  PetscInt  interface_unknowns;               /* separator rows + multipliers */
  PetscInt  ksp_its_max, ksp_its_total;       /* Krylov iterations of the steps' solves (1 per direct solve) */
  PetscInt  pc_setups;                        /* iterative path: preconditioner set-ups */
  struct M2dCondensed *factor;                /* with pb->keep_factor: the condensed path's factorization, the caller's to free (CondensedDestroy), or NULL */
} M2dActiveSetInfo;

/* Solve pb's contact problem on `path` (condensed, iterative or full; the
 * condensed path falls back to full when the SNES type asks for the VI solver); u (layout of pb->f), lam and
 * active (layout of pb->kkt.r) are created by the caller and receive the
 * displacement, the multipliers (zero off the final set) and the final set.
 * Collective. */
PetscErrorCode ActiveSetSolve(M2dProblem *pb, M2dSolverPath path, Vec u, Vec lam, Vec active, M2dActiveSetInfo *info);
/* default complementarity parameter E* / h^2 (reference units). Not collective. */
PetscReal      ActiveSetDefaultC(const M2dScene *s, const M2dContact *ct);
#endif
