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
 * On the condensed path (one rank) the same iteration runs on the multipliers
 * alone (condensed.h): the SNES unknown is nu = lambda - g C u, u is recovered
 * once at the end; same active sets, same answer.
 * Second choice, -snes_type vinewtonrsls: PETSc's reduced-space VI solver with
 * lambda >= 0 and the residual g~ on the multiplier rows. */
#ifndef M2D_ACTIVESET_H
#define M2D_ACTIVESET_H
#include "contact.h"

typedef struct {
  PetscInt  iterations; /* active-set steps (SNES iterations) */
  PetscInt  nactive;
  PetscInt  cycles;
  PetscReal c;
  PetscBool vi;
  PetscBool condensed;   /* the fast path was used */
  PetscReal factor_time; /* its one factorization (seconds) */
  PetscReal factor_flops, factor_flops_max; /* its MUMPS flops: all ranks, the largest rank's share */
  PetscInt  interface_unknowns;               /* separator rows + multipliers */
} M2dActiveSetInfo;

/* Solve; u and lam get the solution, active (layout of lam) the final set. */
PetscErrorCode ActiveSetSolve(const M2dScene *s, const M2dMesh *m, M2dContact *ct, M2dKKT *kkt, Vec u, Vec lam, Vec active, M2dActiveSetInfo *info);
/* default complementarity parameter */
PetscReal      ActiveSetDefaultC(const M2dScene *s, const M2dContact *ct);
#endif
