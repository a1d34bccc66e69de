/* kkt.h - the saddle-point system of elasticity with contact multipliers.
 *
 *   [ K  C^T ] [ u      ]   [ f  ]       C = -B (B: weighted-gap rows of mortar.h),
 *   [ C  0   ] [ lambda ] = [ g0 ]       lambda = contact pressure (>= 0)
 *
 * i.e. K u = f + B^T lambda and B u + g~0 = 0 on the constrained rows.
 * Dirichlet dofs: their columns of C are zeroed and their contribution moved
 * to the right-hand side. -kkt_mat picks a MatNest (blocks kept apart, for
 * PCFIELDSPLIT) or the monolithic AIJ converted from it (for MUMPS). With
 * -kkt_augment w > 0 the (u,u) block becomes K + w s C^T C (and f + w s C^T g0),
 * s = mean diag(K) / mean diag(C^T C): the same solution, but the block is
 * invertible when a body is held only by contact. */
#ifndef M2D_KKT_H
#define M2D_KKT_H
#include "mortar.h"
#include "scene.h"
#include <petscksp.h>

/* Which path uses what: every path the problem (K, f, C, Ct, r, nlam); the
 * condensed path the blocks (Kblk, CA, Z, gamma); the full and tied paths and
 * fieldsplit the operator (nest, A, A0, isu, isl, b, x, aij). */
typedef struct {
  /* the problem */
  PetscInt  nlam;    /* multipliers (candidate contact rows) */
  Mat       K;       /* elasticity, Dirichlet rows applied (referenced) */
  Vec       f;       /* load, Dirichlet-lifted (referenced) */
  Mat       C;       /* nlam x Nu, Dirichlet columns zeroed: all candidate rows */
  Mat       Ct;      /* C^T */
  Vec       r;       /* right-hand side of the multiplier rows, g0 - C u_D (KKTSetLoad) */
  /* friction: tangential rows (kkt.h's rows after the normal ones, contact.h) */
  PetscInt *partner; /* each row's normal row (-1: a normal row), every rank; NULL without friction */
  Mat       P;       /* row j: C's row partner[j] (its Dirichlet columns zeroed), 0 on normal rows; C's pattern */
  /* the load step (KKTSetLoad) */
  Mat       C0;      /* C before its Dirichlet columns were zeroed */
  Vec       g0;      /* the rows' constants: the weighted gaps of the reference configuration (0 on tangential rows) */
  /* the blocks of the current active set */
  Mat       CA;    /* the (lambda,u) block: rows of C, inactive ones zeroed, scaled */
  Mat       Kblk;  /* the (u,u) block: K, or K + gamma CA^T CA */
  Mat       CtCA;  /* CA^T CA (augmentation only) */
  Mat       Z;     /* the (lambda,lambda) block: -(scale/c) on inactive rows */
  PetscReal gamma; /* applied augmentation weight (scaled; 0: none) */
  /* the operator of a KSP on the whole system */
  Mat       nest;     /* the four blocks */
  Mat       A;        /* nest, or its monolithic aij copy; NULL on the condensed path */
  Mat       A0;       /* aij with every row active, unscaled: A is updated from it */
  IS        isu, isl; /* u and lambda in the numbering of A */
  Vec       b, x;     /* right-hand side and solution in that numbering */
  PetscBool aij;      /* A is aij */
} M2dKKT;

/* The KKT blocks of rows R on K, f (supports eliminated; ubc holds the
 * prescribed values, drows this rank's Dirichlet rows), A as mat (-kkt_mat),
 * the (u,u) block augmented by weight augment (-kkt_augment; 0: none);
 * partner (R->n entries, or NULL without friction): a tangential row's
 * normal row, -1 for a normal row; with `condensed` the monolithic matrix is
 * not built (condensed.h reads the blocks). K and f are referenced, not
 * copied. Collective. */
PetscErrorCode KKTCreate(M2dKKTMat mat, PetscReal augment, PetscBool condensed, const M2dContactRows *R, const PetscInt partner[], Mat K, Vec f, Vec ubc, PetscInt ndir, const PetscInt drows[], M2dKKT *kkt);
/* A load step: f (referenced: the caller has changed it) and the support
 * values ubc of the step, and uprev, the displacement the step starts from
 * (layout of f; NULL: 0). The rows' right-hand side becomes
 *   r = g0 - C0 ubc + C0 uprev on the tangential rows,
 * so that on a normal row r - C u = g~ (the weighted gap) and on a
 * tangential row r - C u = B_t (u - uprev), the weighted slip of the step,
 * positive when the non-mortar side moves along t relative to the mortar
 * side; and b (the full path's right-hand side). Collective. */
PetscErrorCode KKTSetLoad(M2dKKT *kkt, Vec ubc, Vec uprev);
/* Multiplier rows of A: active[j] != 0 gives the constraint row scale * C_j,
 * active[j] = 0 gives -(scale / c) (e_j - s_j e_p) + s_j scale C_p with
 * s_j = slip[j] and p = partner[j] (a slipping tangential row: lambda_j =
 * s_j (lambda_p + c (C u - r)_p), s_j = +-mu; slip NULL or s_j = 0:
 * lambda_j = 0). Rebuilds the augmented block (from the active rows) and A.
 * `scale` turns weighted gaps into forces (see activeset.c). */
PetscErrorCode KKTSetActive(M2dKKT *kkt, Vec active, Vec slip, PetscReal c, PetscReal scale);
/* A Krylov ksp (not KSPPREONLY: a direct solve passes) that diverged, or, with
 * settled FALSE (an active set that failed), that solved its steps to a
 * -ksp_rtol above 1e-8: one line "WHAT: ..." naming its tolerances. Collective. */
PetscErrorCode KKTKrylovCheck(KSP ksp, const char *what, PetscBool settled);
/* A failed solve (ksp's converged reason < 0) by PCFIELDSPLIT without the
 * augmentation (gamma 0): one line naming -kkt_augment, whatever the failure
 * reads (a singular K block fails in the factorization on one machine and in
 * the Krylov iteration on another, as the pivoting and the BLAS decide).
 * Collective. */
PetscErrorCode KKTFieldsplitCheck(KSP ksp, PetscReal gamma);
/* configure the KSP (after KSPSetFromOptions): fieldsplit gets the u/lambda splits */
PetscErrorCode KKTSetupKSP(M2dKKT *kkt, KSP ksp);
/* solve; u gets the displacement, lam (layout of C's rows) the multipliers */
PetscErrorCode KKTSolve(M2dKKT *kkt, KSP ksp, Vec u, Vec lam);
PetscErrorCode KKTDestroy(M2dKKT *kkt);
#endif
