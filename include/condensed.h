/* condensed.h - the fast path: one sparse factorization, then the active-set
 * steps run on the multipliers alone (1 or 2 ranks).
 *
 * M = [K_g C^T; C 0] with K_g = K + g C^T C over every candidate row (K_g is
 * invertible whenever tying every candidate node would hold the bodies, which
 * covers bodies held only by contact) is factored ONCE by MUMPS, called here
 * directly (dmumps_c), with a Schur complement on the multipliers,
 * S0 = -C K_g^-1 C^T (dense, n_lambda^2, returned on rank 0).
 *
 * With nu = lambda - g C u, u(nu) = K_g^-1 (f - C^T nu) satisfies
 * K u + C^T lambda = f for every nu, and C u(nu) = w + S0 nu with
 * w = C K_g^-1 f. The gaps and multipliers of any nu are therefore dense
 * n_lambda algebra: the semismooth Newton iteration (activeset.c) takes its
 * steps on nu, each a dense LU of size n_lambda (every rank holds it), and
 * visits the same active sets as the full path (the problem is linear in u).
 * MUMPS' condensation phase (forward elimination, ICNTL(26) = 1) gives w
 * (CondensedReducedSetup), its expansion phase (backward, ICNTL(26) = 2) u
 * at the end (CondensedRecover): one solve's work in all.
 *
 * Why not PETSc's MUMPS interface: PETSc 3.18 hands MUMPS no ordering on more
 * than one rank and cannot solve with a Schur complement there, and with a
 * Schur complement MUMPS' own ordering is AMD (2x the flops of nested
 * dissection). Here -kkt_ordering metis gives MUMPS a METIS ordering with the
 * multipliers last (PERM_IN): on one rank of the whole graph; on several, the
 * rows coupled to a higher rank form the top separator and every rank orders
 * the rest of its own rows at the same time. */
#ifndef M2D_CONDENSED_H
#define M2D_CONDENSED_H
#include "kkt.h"
#include "ordering.h"

typedef struct M2dMumps M2dMumps;

typedef struct {
  KKT         *kkt;
  M2dMumps    *mumps;
  PetscInt     n, N, lo;   /* multipliers: local, global, first owned (layout of kkt->r) */
  PetscScalar *S;          /* rows lo..lo+n-1 of S0, column-major, n x N */
  PetscScalar *lu;         /* the reduced Jacobian's LU (N x N, every rank) */
  PetscBLASInt *piv;
  Vec          rhs, rhs0;  /* layout of the KKT matrix; all of it on rank 0 */
  VecScatter   toz;
  Vec          all;        /* a multiplier vector, whole, on every rank */
  VecScatter   toall;
  Vec          lam0;       /* a multiplier vector, whole, on rank 0 (MUMPS' REDRHS) */
  VecScatter   lamz;
  Vec          w;          /* w = C K_g^-1 f */
  PetscLogDouble factor_time;
} Condensed;

/* kkt must have been created with augmentation (kkt->gamma > 0) and aij */
PetscErrorCode CondensedCreate(KKT *kkt, const Scene *s, Condensed *cs);
/* w from MUMPS' condensation phase */
PetscErrorCode CondensedReducedSetup(Condensed *cs);
/* cu = C u(nu) = w + S0 nu (layout of kkt->r) */
PetscErrorCode CondensedReducedGaps(Condensed *cs, Vec nu, Vec cu);
/* J = d/dnu of F = c h max(-lambda/c, C u - r): rows c h S0 (active) and
 * -h (I + g S0) (inactive); J dense (MATDENSE), layout of kkt->r */
PetscErrorCode CondensedReducedJacobian(Condensed *cs, Vec active, PetscReal c, PetscReal h, Mat J);
/* LU of the dense J on every rank; then x = J^-1 b (layout of kkt->r) */
PetscErrorCode CondensedDenseFactor(Condensed *cs, Mat J);
PetscErrorCode CondensedDenseSolve(Condensed *cs, Vec b, Vec x);
/* u = u(nu), MUMPS' expansion phase */
PetscErrorCode CondensedRecover(Condensed *cs, Vec nu, Vec u);
PetscErrorCode CondensedDestroy(Condensed *cs);
#endif
