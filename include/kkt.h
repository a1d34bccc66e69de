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

typedef struct {
  PetscInt  nlam;
  Mat       K;     /* elasticity, Dirichlet rows applied (reference) */
  Vec       f;     /* load, Dirichlet-lifted (reference) */
  Mat       C;     /* nlam x Nu, Dirichlet columns zeroed: all candidate rows */
  Vec       r;     /* right-hand side of the multiplier rows */
  Mat       CA;    /* the (lambda,u) block in use: rows of C, inactive ones zeroed */
  Mat       Kblk;  /* the (u,u) block: K, or K + gamma CA^T CA */
  Mat       CtCA;  /* CA^T CA (augmentation only) */
  Mat       Ct, Z, nest, A; /* Z: (lambda,lambda) block; A: operator for the KSP (nest or aij; NULL on the condensed path, which reads the blocks) */
  Mat       A0;             /* aij with every row active, unscaled: A is updated from it */
  IS        isu, isl;       /* u and lambda in the global numbering of A */
  Vec       b, x;
  PetscReal gamma;          /* applied augmentation weight (scaled) */
  PetscBool aij;
} M2dKKT;

/* The KKT blocks of rows R on K, f (supports eliminated; ubc holds the
 * prescribed values, drows this rank's Dirichlet rows); with `condensed` the
 * monolithic matrix is not built (condensed.h reads the blocks). K and f are
 * referenced, not copied. Collective. */
PetscErrorCode KKTCreate(const M2dScene *s, PetscBool condensed, const M2dContactRows *R, Mat K, Vec f, Vec ubc, PetscInt ndir, const PetscInt drows[], M2dKKT *kkt);
/* Multiplier rows of A: active[j] != 0 gives the constraint row scale * C_j,
 * active[j] = 0 gives -(scale / c) e_j (lambda_j = 0). Rebuilds the augmented
 * block and A. `scale` turns weighted gaps into forces (see activeset.c). */
PetscErrorCode KKTSetActive(M2dKKT *kkt, Vec active, PetscReal c, PetscReal scale);
/* configure the KSP (after KSPSetFromOptions): fieldsplit gets the u/lambda splits */
PetscErrorCode KKTSetupKSP(M2dKKT *kkt, KSP ksp);
/* solve; u gets the displacement, lam (layout of C's rows) the multipliers */
PetscErrorCode KKTSolve(M2dKKT *kkt, KSP ksp, Vec u, Vec lam);
PetscErrorCode KKTDestroy(M2dKKT *kkt);
#endif
