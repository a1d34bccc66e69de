/* activeset_impl.h - the active-set iteration's context (activeset.c: the
 * loop, the states, the checks) and the table of what a solver path does
 * (activeset_paths.c). Private. */
#ifndef M2D_ACTIVESET_IMPL_H
#define M2D_ACTIVESET_IMPL_H
#include "activeset.h"
#include "condensed.h"
#include "iterative.h"
#include <petscsnes.h>

#define M2D_MAX_HISTORY 1024
#define M2D_RISE        4.0 /* iterative path: |F| this many times its least since step 1 ends the steps on unproven sets */

/* How one solver path takes the loop's steps. The unknown x is the path's:
 * [u; lambda] in the KKT layout, or the condensed path's nu (condensed.h). */
typedef struct {
  const char *name;        /* printed: the method, and how a step is solved */
  PetscBool   lambda_only; /* x and F have the multiplier rows only (the u rows hold by construction): the condensed path */
  /* PETSc's VI solver takes the steps, with lambda >= 0 as its bounds: its set
   * is lambda > 0 (at least the closest nodes at first, VILoad), F's multiplier
   * rows are the gap, its Jacobian is built once, its stop is its own; the
   * loop follows its sets after each step (cycles counted, c kept) */
  PetscBool bounds_by_solver;
  /* factor or build once; the SNES's Jacobian matrix and step solver */
  PetscErrorCode (*setup)(M2dActiveSet *as, M2dActiveSetInfo *info);
  /* a load step begins: the KKT's f and r are the step's */
  PetscErrorCode (*load)(M2dActiveSet *as);
  /* from the iterate x: as->lam (the multipliers) and as->gm (C u - r), this rank's rows */
  PetscErrorCode (*evaluate)(M2dActiveSet *as, Vec x);
  /* the u rows of F at x, with the rules of the iterate (NULL: none, lambda_only) */
  PetscErrorCode (*residual_u)(M2dActiveSet *as, Vec x, Vec F);
  /* the step's matrix for the rules as->active, as->slip (NULL: the solver's, built once) */
  PetscErrorCode (*jacobian)(M2dActiveSet *as);
  /* the sets back to step k's: *answered if the path answers it (NULL: c is raised) */
  PetscErrorCode (*cycled)(M2dActiveSet *as, PetscInt k, PetscBool *answered);
  /* |F| at step it (NULL: nothing to watch) */
  PetscErrorCode (*watch)(M2dActiveSet *as, PetscInt it, PetscReal fnorm);
  /* u and lambda of the answer x */
  PetscErrorCode (*finish)(M2dActiveSet *as, Vec x, Vec u, Vec lam);
  /* the path's own figures of the load step into info, printed (NULL: direct solves, none) */
  PetscErrorCode (*report)(M2dActiveSet *as, M2dActiveSetInfo *info);
  /* the iteration failed after `steps` steps: the step solver's own diagnosis (NULL: none) */
  PetscErrorCode (*failed)(M2dActiveSet *as, PetscInt steps);
  /* keep: the caller keeps what the path hands over (the condensed factorization), or NULL */
  PetscErrorCode (*destroy)(M2dActiveSet *as, M2dActiveSetInfo *keep);
} M2dPathOps;

/* the sets visited, to detect cycling: a hash and a count per step */
typedef struct {
  PetscInt  n, cycles, max_cycles;
  uint64_t  hash[M2D_MAX_HISTORY];
  PetscInt  count[M2D_MAX_HISTORY];
  PetscBool failed;
} M2dSetHistory;

struct M2dActiveSet {
  M2dProblem       *pb;
  M2dKKT           *kkt;
  const M2dPathOps *ops;
  SNES              snes;
  Vec               x, F;   /* the unknown (kept from one load step to the next), the residual */
  Mat               J;      /* the path's Jacobian matrix (the condensed path's dense one), or NULL */
  PetscReal         c;      /* complementarity parameter */
  PetscReal         h;      /* mean non-mortar edge length: rows scaled by c h (weighted gap -> force) */
  PetscBool         monitor;
  PetscBool         exact;  /* each step solved directly: a step whose states stay is the answer */
  /* the rows (every rank holds all of them) */
  PetscInt          n, nn;   /* rows, normal rows */
  const PetscInt   *partner; /* a tangential row's normal row (-1: normal), or NULL without friction */
  PetscReal        *mu;      /* each tangential row's friction coefficient */
  PetscReal        *tol;     /* each row's tie tolerance: 1e-12 of its weight (a reference displacement) */
  /* the iterate: this rank's rows, and whole on every rank */
  Vec               lam, gm;        /* multipliers, C u - r */
  Vec               lamall, gmall;  /* the same, every row */
  VecScatter        toall;
  Vec               active, slip;   /* the rules at the iterate (this rank's rows) */
  PetscReal        *rule, *coef;    /* the same, every row: 1 constraint / 0 force; the force's coefficient s_j */
  PetscReal        *used, *usedcoef; /* the rules of the last step's matrix, every row */
  PetscBool         forced;  /* the next residual and matrix take the rules in used (a load step's first) */
  PetscInt          nclosed, nstick, nslip, changed; /* at the iterate (every rank the same) */
  PetscReal         fnorm0;
  M2dSetHistory     hist;
  PetscInt          step;    /* active-set steps of this load step */
  PetscInt          total;   /* and of every load step */
  PetscBool         started; /* a load step has been solved: x and used hold its answer */
  M2dActiveSetInfo  setup;   /* what the path's set-up reports (factorization) */
  /* the paths' own */
  M2dCondensed     *cond;    /* condensed path (the unknown is nu, condensed.h), or NULL */
  M2dIterative     *iter;    /* iterative path (each step's solve, iterative.h), or NULL */
  Vec               u, du, cdu, cu, m[2], tolv; /* work: u of x; iterative path: a step's du, C du, tests of its next set, the tie tolerances */
  PetscBool         proving; /* iterative path: every step's set proven (-iterative_prove, a warm start, or after a cycle or a rise of |F|) */
  PetscReal         fbest;   /* iterative path: the least |F| since step 1 */
  PetscInt          unproven; /* iterative path: steps that took an inexact solve's set */
};

/* c in the user's units (the summary's contact_c): lambda / c is a weighted gap */
static inline PetscReal CUser(const M2dProblem *pb)
{
  return pb->units.S / (pb->units.L * pb->units.U);
}

/* activeset_paths.c: the paths (the VI solver is the full path's with PETSc's bounds) */
extern const M2dPathOps M2dPathCondensed, M2dPathFull, M2dPathIterative, M2dPathVI;
/* activeset.c, for the iterative path: would the tests m (active where m >= 0) hold every body? */
PetscErrorCode ActiveSetHeldBy(M2dActiveSet *as, Vec m, PetscBool *held);
#endif
