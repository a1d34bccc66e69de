/* condensed.h - the fast path: one sparse factorization, then the active-set
 * steps run on the multipliers alone (one rank).
 *
 * M = [K_g C^T; C 0] with K_g = K + g C^T C over every candidate row (K_g is
 * invertible whenever tying every candidate node would hold the bodies, which
 * covers bodies held only by contact) is factored ONCE by MUMPS with a Schur
 * complement on the multipliers, S0 = -C K_g^-1 C^T (dense, n_lambda^2).
 *
 * With nu = lambda - g C u, u(nu) = K_g^-1 (f - C^T nu) satisfies
 * K u + C^T lambda = f for every nu, and C u(nu) = w + S0 nu with
 * w = C K_g^-1 f. The gaps and multipliers of any nu are therefore dense
 * n_lambda algebra: the semismooth Newton iteration (activeset.c) takes its
 * steps on nu, each a dense LU of size n_lambda, and visits the same active
 * sets as the full path (the problem is linear in u). One substitution gives w
 * (CondensedReducedSetup), one gives u at the end (CondensedRecover).
 * -kkt_ordering metis hands MUMPS a METIS ordering with the multipliers last:
 * with a Schur complement MUMPS' own choice is AMD (2x the flops). */
#ifndef M2D_CONDENSED_H
#define M2D_CONDENSED_H
#include "kkt.h"

typedef struct {
  KKT       *kkt;
  Mat        F;   /* MUMPS factor of M with the Schur complement */
  Mat        S0;  /* pristine Schur complement, n_lambda x n_lambda (one rank) */
  Vec        rhs, sol;         /* work, layout of the KKT matrix */
  Vec        w;                /* w = C K_g^-1 f */
  PetscLogDouble factor_time;
} Condensed;

/* kkt must have been created with augmentation (kkt->gamma > 0) and aij; one rank */
PetscErrorCode CondensedCreate(KKT *kkt, M2dOrdering ord, Condensed *cs);
/* reduced iteration (one rank): w from one substitution */
PetscErrorCode CondensedReducedSetup(Condensed *cs);
/* cu = C u(nu) = w + S0 nu (layout of kkt->r) */
PetscErrorCode CondensedReducedGaps(Condensed *cs, Vec nu, Vec cu);
/* J = d/dnu of F = c h max(-lambda/c, C u - r): rows c h S0 (active) and
 * -h (I + g S0) (inactive); J dense n_lambda x n_lambda */
PetscErrorCode CondensedReducedJacobian(Condensed *cs, Vec active, PetscReal c, PetscReal h, Mat J);
/* u = u(nu), one substitution */
PetscErrorCode CondensedRecover(Condensed *cs, Vec nu, Vec u);
PetscErrorCode CondensedDestroy(Condensed *cs);
#endif
