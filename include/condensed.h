/* condensed.h - the fast path: one sparse factorization, then the active-set
 * steps run on the multipliers alone (1 or more ranks).
 *
 * M = [K_g C^T; C 0] with K_g = K + g C^T C over every candidate row (K_g is
 * invertible whenever tying every candidate node would hold the bodies, which
 * covers bodies held only by contact) is factored ONCE, and its Schur
 * complement on the multipliers, S0 = -C K_g^-1 C^T (dense, n_lambda^2), is
 * formed. M is read from the nest's blocks (kkt.h): no monolithic copy.
 *
 * The rows are split as the ranks own them: on several ranks the u rows of
 * each rank coupled to a u row of a higher rank form the separator; the
 * interface is the separator and the multipliers; every other row is
 * interior to its rank and couples only to its own interior and to the
 * interface. Every rank factors its interior with its own sequential MUMPS
 * (dmumps_c on one rank: analysis, factorization and solves run on all
 * ranks at once, nothing is gathered) and a Schur complement on the
 * interface unknowns its interior couples to. The interface matrix (the
 * sum of those, plus its own entries) is dense and on every rank; the
 * separator is eliminated by Cholesky (it is a Schur complement of K_g),
 * which leaves S0. On one rank the interface is the multipliers alone.
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
 * dissection). Here -kkt_ordering metis gives every rank's MUMPS a METIS
 * nested dissection of its interior, the interface last (PERM_IN). Why not
 * one MUMPS on all ranks (as before): its analysis is sequential in
 * Debian's build (no PT-Scotch/ParMETIS in MUMPS) and gathers the matrix,
 * level 6: 5.4 s of analysis and 1.7 s of redistribution on 2 ranks against
 * 1.9 s of analysis here. */
#ifndef M2D_CONDENSED_H
#define M2D_CONDENSED_H
#include "kkt.h"
#include "ordering.h"

typedef struct M2dMumps M2dMumps;

typedef struct {
  M2dKKT         *kkt;
  M2dMumps    *mumps;      /* this rank's own sequential MUMPS, or NULL (no interior rows) */
  PetscInt     n, N, lo;   /* multipliers: local, global, first owned (layout of kkt->r) */
  PetscInt     ns;         /* separator rows (all ranks); the interface has ns + N unknowns */
  PetscInt     nI, ng;     /* this rank: interior rows, interface unknowns its interior couples to */
  PetscInt    *lidx;       /* own u rows, then own multiplier rows: interior index, or -1 - interface index */
  PetscInt    *glist;      /* interface index of each of this rank's ng interface unknowns */
  PetscScalar *L, *X;      /* L L^T = S_ss (ns x ns), X = L^-1 S_sl (ns x N), every rank */
  PetscScalar *b, *red, *g; /* this rank's MUMPS right-hand side (nI + ng) and reduced one (ng); interface vector (ns + N) */
  PetscScalar *S;          /* rows lo..lo+n-1 of S0, column-major, n x N */
  PetscScalar *lu;         /* the reduced Jacobian's LU (N x N, every rank) */
  PetscBLASInt *piv;
  Vec          all;        /* a multiplier vector, whole, on every rank */
  VecScatter   toall;
  Vec          w;          /* w = C K_g^-1 f */
  PetscLogDouble factor_time;
  PetscLogDouble flops_sum, flops_max; /* MUMPS factorization flops (RINFO(3)) over the ranks: sum, largest share */
} M2dCondensed;

/* kkt must have been created with augmentation (kkt->gamma > 0) and aij */
PetscErrorCode CondensedCreate(M2dKKT *kkt, const M2dScene *s, M2dCondensed *cs);
/* w from MUMPS' condensation phase */
PetscErrorCode CondensedReducedSetup(M2dCondensed *cs);
/* cu = C u(nu) = w + S0 nu (layout of kkt->r) */
PetscErrorCode CondensedReducedGaps(M2dCondensed *cs, Vec nu, Vec cu);
/* J = d/dnu of F = c h max(-lambda/c, C u - r): rows c h S0 (active) and
 * -h (I + g S0) (inactive); J dense (MATDENSE), layout of kkt->r */
PetscErrorCode CondensedReducedJacobian(M2dCondensed *cs, Vec active, PetscReal c, PetscReal h, Mat J);
/* LU of the dense J on every rank; then x = J^-1 b (layout of kkt->r) */
PetscErrorCode CondensedDenseFactor(M2dCondensed *cs, Mat J);
PetscErrorCode CondensedDenseSolve(M2dCondensed *cs, Vec b, Vec x);
/* u = u(nu), MUMPS' expansion phase */
PetscErrorCode CondensedRecover(M2dCondensed *cs, Vec nu, Vec u);
PetscErrorCode CondensedDestroy(M2dCondensed *cs);
#endif
