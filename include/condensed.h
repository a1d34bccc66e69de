/* condensed.h - the fast path: factor once, then each active-set step is a
 * small dense solve.
 *
 * M = [K_g C^T; C 0] with K_g = K + g C^T C over every candidate row (K_g is
 * invertible whenever tying every candidate node would hold the bodies, which
 * covers bodies held only by contact) is factored ONCE by MUMPS with a Schur
 * complement on the multipliers, S0 = -C K_g^-1 C^T (dense, n_lambda^2, on rank 0).
 * The Newton matrix of an active set A,
 *   J = [K C^T; s C_A (active rows); -(s/c) e_j (inactive rows)],
 * is solved exactly through the same factorization: with nu_A = dlambda_A - g t_A
 * and nu_I = -g C_I du, the system becomes M_A [du; nu] = [b_u - C_I^T dlambda_I; t]
 * where M_A differs from M only in its (nu,nu) diagonal (1/g on inactive rows),
 * so its Schur complement is S0 + diag(1/g on I): a dense LU of size n_lambda
 * per step, and one MUMPS forward/back substitution per step. No sparse
 * refactorization after the first. */
#ifndef M2D_CONDENSED_H
#define M2D_CONDENSED_H
#include "kkt.h"

typedef struct {
  KKT       *kkt;
  Mat        F;   /* MUMPS factor of M with the Schur complement */
  Mat        S0;  /* pristine Schur complement (rank 0: n_lambda x n_lambda; others 0 x 0) */
  VecScatter tozero;
  Vec        act0; /* active flags gathered on rank 0 */
  Vec        active, bl, dl, t, vu, rhs, sol;
  PetscReal  c, s;
  PetscLogDouble factor_time;
} Condensed;

/* kkt must have been created with augmentation (kkt->gamma > 0) and aij */
PetscErrorCode CondensedCreate(KKT *kkt, M2dOrdering ord, Condensed *cs);
PetscErrorCode CondensedSetActive(Condensed *cs, Vec active, PetscReal c, PetscReal s);
PetscErrorCode CondensedApply(Condensed *cs, Vec b, Vec x);
PetscErrorCode CondensedDestroy(Condensed *cs);
#endif
