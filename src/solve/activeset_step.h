/* activeset_step.h - the active-set iteration's context and one step
 * (activeset_step.c: mask, residual, the Jacobian's set), the bottom of the
 * active set's three files: activeset.c (the SNES that drives the steps) ->
 * activeset_paths.c (what each solver path adds) -> activeset_step.c. Not
 * public. */
#ifndef M2D_ACTIVESET_STEP_H
#define M2D_ACTIVESET_STEP_H
#include "activeset.h"
#include "condensed.h"
#include "iterative.h"
#include <petscsnes.h>

#define M2D_MAX_HISTORY 1024
#define M2D_RISE        4.0 /* iterative path: |F| this many times its least since step 1 ends the steps on unproven sets */

/* the sets visited, to detect cycling: a hash and a count per step */
typedef struct {
  PetscInt  n, cycles, max_cycles;
  uint64_t  hash[M2D_MAX_HISTORY];
  PetscInt  count[M2D_MAX_HISTORY];
  PetscBool failed;
} M2dSetHistory;

typedef struct {
  M2dProblem   *pb;
  M2dKKT       *kkt;
  PetscReal     c;      /* complementarity parameter */
  PetscReal     h;      /* mean non-mortar edge length: rows scaled by c h (weighted gap -> force) */
  PetscBool     vi, monitor;
  Vec           u, lam; /* the iterate's displacement and multipliers */
  Vec           gm;     /* C u - r = -(weighted gap) */
  Vec           tol;    /* tie tolerance per multiplier */
  Vec           active; /* mask at the current iterate */
  Vec           used;   /* the mask the last Jacobian used */
  PetscInt      nactive, entered, left;
  PetscReal     fnorm0, fnorm_prev;
  PetscBool     unchanged_before;
  M2dSetHistory hist;
  M2dCondensed *cond;    /* condensed path (the SNES unknown is nu, condensed.h), or NULL */
  M2dIterative *iter;    /* iterative path (each step's solve, iterative.h), or NULL */
  Vec           du, cdu, m[2]; /* iterative path: a step's du, C du and tests of its next set */
  Vec           cu;      /* condensed path: C u(nu) */
  Vec           all;     /* the mask on every rank (the held-bodies check) */
  VecScatter    toall;
  PetscInt      step;    /* active-set steps taken */
  PetscBool     proving; /* iterative path: every step's set proven (-iterative_prove, a warm start, or after a cycle or a rise of |F|) */
  PetscReal     fbest;   /* iterative path: the least |F| since step 1 */
  PetscInt      unproven; /* iterative path: steps that took an inexact solve's set */
} M2dActiveSet;

/* c in the user's units (the summary's contact_c): lambda / c is a weighted gap */
static inline PetscReal CUser(const M2dProblem *pb)
{
  return pb->units.S / (pb->units.L * pb->units.U);
}

/* activeset_step.c */
PetscErrorCode ActiveSetUpdateMask(M2dActiveSet *as);
PetscErrorCode ActiveSetFunction(SNES snes, Vec z, Vec F, void *ctx);
PetscErrorCode ActiveSetJacobian(SNES snes, Vec z, Mat J, Mat P, void *ctx);
PetscErrorCode ActiveSetChooseSet(M2dActiveSet *as, MPI_Comm comm);
#endif
