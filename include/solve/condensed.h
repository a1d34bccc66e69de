/* condensed.h - the condensed path: one sparse factorization, then the
 * active-set steps run on the multipliers alone (1 or more ranks).
 *
 * M = [K_g C^T; C 0] with K_g = K + g C^T C over every candidate row (K_g is
 * invertible whenever tying every candidate node would hold the bodies, which
 * covers bodies held only by contact) is factored ONCE, and its Schur
 * complement on the multipliers, S0 = -C K_g^-1 C^T (dense, n_lambda^2), is
 * formed. M is read from its blocks K_g, C^T and C: no monolithic copy.
 *
 * The rows are split as the ranks own them: on several ranks the u rows of
 * each rank coupled to a u row of a higher rank form the separator; the
 * interface is the separator and the multipliers; every other row is
 * interior to its rank and couples only to its own interior and to the
 * interface. Every rank factors its interior with its own sequential MUMPS
 * (m2dmumps.h: analysis, factorization and solves run on all ranks at once,
 * nothing is gathered) and a Schur complement on the interface unknowns its
 * interior couples to. The interface matrix (the sum of those, plus its own
 * entries) is dense and on every rank; the separator is eliminated by
 * Cholesky (it is a Schur complement of K_g), which leaves S0. On one rank
 * the interface is the multipliers alone.
 *
 * With nu = lambda - g C u, u(nu) = K_g^-1 (f - C^T nu) satisfies
 * K u + C^T lambda = f for every nu, and C u(nu) = w + S0 nu with
 * w = C K_g^-1 f. The gaps and multipliers of any nu are therefore dense
 * n_lambda algebra: the semismooth Newton iteration (activeset.c) takes its
 * steps on nu, each a dense LU of size n_lambda (every rank holds it), and
 * visits the same active sets as the full path (the problem is linear in u).
 * MUMPS' condensation phase (forward elimination) of f gives w at creation,
 * its expansion phase (backward substitution) u(nu) (CondensedRecover): one
 * solve's work in all.
 *
 * Why not PETSc's MUMPS interface: PETSc 3.18 hands MUMPS no ordering on more
 * than one rank and cannot solve with a Schur complement there, and with a
 * Schur complement MUMPS' own ordering is AMD (more flops than nested
 * dissection: README). Here -kkt_ordering metis gives every rank's MUMPS a
 * METIS nested dissection of its interior, the interface last (ordering.h).
 * Why one MUMPS per rank and not one on all ranks: Debian's MUMPS analyses
 * sequentially (no PT-Scotch/ParMETIS inside) and gathers the matrix on one
 * rank (README: the measurements). */
#ifndef M2D_CONDENSED_H
#define M2D_CONDENSED_H
#include "kkt.h"
#include "m2dmumps.h"
#include "ordering.h"

typedef struct M2dCondensed M2dCondensed;

typedef struct {
  PetscBool       ldlt;     /* LDL^T of the symmetric M (MUMPS SYM = 2), else LU */
  M2dOrdering     ordering; /* METIS nested dissection of each rank's interior, or MUMPS' own */
  M2dMumpsOptions mumps;
} M2dCondensedOptions;

typedef struct {
  PetscLogDouble factor_time;        /* seconds: ordering, factorizations, dense interface */
  PetscLogDouble flops_sum;          /* MUMPS factorization flops (RINFO(3)), all ranks */
  PetscLogDouble flops_max;          /* the largest rank's share */
  PetscInt       separator_rows;     /* all ranks (0 on one rank) */
  PetscInt       multipliers;        /* n_lambda */
  PetscInt       interface_unknowns; /* separator rows + multipliers */
} M2dCondensedInfo;

/* Factor M = [Kg C^T; C 0] and condense f (w = C Kg^-1 f). Kg (u x u), C
 * (multipliers x u) and Ct = C^T are AIJ with matching layouts, f has Kg's
 * row layout; gamma is the g of Kg = K + g C^T C. Collective on Kg's
 * communicator; keeps references to Kg, C, Ct; free *cs with CondensedDestroy. */
PetscErrorCode CondensedCreate(Mat Kg, Mat C, Mat Ct, Vec f, PetscReal gamma, const M2dCondensedOptions *opt, M2dCondensed **cs);
/* The same for the augmented KKT system (kkt->gamma > 0) with the scene's
 * solver options (-kkt_ldlt, -kkt_ordering, -mat_mumps_icntl_*). Collective. */
PetscErrorCode CondensedCreateFromKKT(const M2dKKT *kkt, const M2dScene *s, M2dCondensed **cs);
/* cu = C u(nu) = w + S0 nu (nu, cu: layout of C's rows; nu = 0 gives w). Collective. */
PetscErrorCode CondensedGaps(M2dCondensed *cs, Vec nu, Vec cu);
/* J = d/dnu of F = c h max(-lambda/c, C u - r): rows c h S0 (active != 0) and
 * -h (I + g S0) (inactive); J dense (MATDENSE), layout of C's rows. Collective. */
PetscErrorCode CondensedJacobian(M2dCondensed *cs, Vec active, PetscReal c, PetscReal h, Mat J);
/* LU of the dense J (from CondensedJacobian) on every rank; then x = J^-1 b
 * (layout of C's rows). With friction (partner not NULL; partner, rule and
 * coef: every row, as activeset.c keeps them) a slipping row j (rule 0,
 * coef[j] = s != 0, p = partner[j], a closed normal row) is
 * -h (e_j + g S0_j) + h s (e_p + (g + c) S0_p): the row
 * lambda_j = s (lambda_p + c (C u - r)_p) of the force's rule, added to the
 * gathered rows as h s e_p + s (g + c)/c J_p. Collective. */
PetscErrorCode CondensedJacobianFactor(M2dCondensed *cs, Mat J, const PetscInt partner[], const PetscReal rule[], const PetscReal coef[], PetscReal c, PetscReal h);
/* A new load f (another load step): w = C K_g^-1 f condensed anew (one
 * forward elimination). Collective. */
PetscErrorCode CondensedSetLoad(M2dCondensed *cs, Vec f);
PetscErrorCode CondensedJacobianSolve(M2dCondensed *cs, Vec b, Vec x);
/* u = u(nu) = Kg^-1 (f - C^T nu) by MUMPS' expansion phase (any number of
 * times; u: layout of Kg's rows); without `load` u = -Kg^-1 C^T nu (a dual
 * problem's displacement, dual.h; the rows of its nu come from
 * CondensedJacobian and CondensedJacobianSolve). Collective. */
PetscErrorCode CondensedRecover(M2dCondensed *cs, PetscBool load, Vec nu, Vec u);
/* What the factorization cost and how big the interface is. Not collective. */
PetscErrorCode CondensedGetInfo(const M2dCondensed *cs, M2dCondensedInfo *info);
/* Frees everything (the references to Kg, C, Ct too); *cs = NULL. Collective. */
PetscErrorCode CondensedDestroy(M2dCondensed **cs);
#endif
