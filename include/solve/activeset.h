/* activeset.h - unilateral contact with Coulomb friction through SNES.
 *
 * Unknowns: the displacement u and one multiplier per contact row (kkt.h):
 * on a normal row the contact pressure lambda_n (>= 0) against the weighted
 * gap g~ = r - C u; on a tangential row (friction, contact.h) the friction
 * force per length lambda_t against the weighted slip of the load step
 * s~ = r - C u (kkt.h, KKTSetLoad). With xi_n = lambda_n - c g~ and
 * xi_t = lambda_t - c s~, each contact node is in one of three states:
 *   open   xi_n < 0                 lambda_n = 0, lambda_t = 0
 *   stick  xi_n >= 0, |xi_t| <= mu xi_n    g~ = 0, s~ = 0
 *   slip   xi_n >= 0, |xi_t| >  mu xi_n    g~ = 0, lambda_t = mu sign(xi_t) xi_n
 * i.e. lambda = P(lambda - c (r - C u)) with P the projection on [0, inf)
 * for a normal row and on [-mu xi_n, mu xi_n] for a tangential one (Coulomb's
 * law; Alart-Curnier, Hueber-Stadler-Wohlmuth 2008). Every row's equation is
 * either a constraint (the gap or the slip is 0: rule "active") or a given
 * force (lambda_j = s_j xi_p, s_j = +-mu on a slipping row whose normal row is
 * p, 0 otherwise): the state is data, one table, the same loop for every row.
 *
 * The loop (deal.II step-41, driven by SNES as a semismooth Newton method,
 * Hueber-Wohlmuth's primal-dual active set): solve the linear problem of the
 * current states, update the states from the new iterate, stop when they no
 * longer change (a direct solve is then the answer; an inexact one also
 * needs its residual at tolerance). The first step of a load step solves the
 * states it is given (-contact_initial, the previous mesh's, or the previous
 * load step's), from u = 0 and lambda = 0 or from the previous load step.
 * c = E* / h^2 from the materials and the non-mortar edge length (unit-free
 * decisions). Before each step the states are checked to hold every body
 * together with the supports (supports.h): a state that frees a body means
 * the contact has opened (one line), or, with friction, that the body slides
 * (one line with its tangential load and the friction it can carry).
 * How each step is solved is the path's (one small table, activeset_paths.c):
 * condensed (K factored once, steps on the multipliers), full (the KKT matrix
 * refactored), iterative (CG + AMG in u), or PETSc's SNESVINEWTONRSLS on the
 * frictionless normal rows (-snes_type vinewtonrsls). */
#ifndef M2D_ACTIVESET_H
#define M2D_ACTIVESET_H
#include "problem.h"

typedef struct {
  PetscInt  iterations; /* active-set steps (SNES iterations), over the load steps */
  PetscInt  nactive;    /* closed contact nodes at the end */
  PetscInt  nstick, nslip; /* of those, sticking and slipping ones (friction) */
  PetscInt  cycles;
  PetscReal c;
  PetscBool vi;
  PetscBool condensed;   /* the condensed path was used */
  PetscReal factor_time; /* its one factorization (seconds) */
  PetscReal factor_flops, factor_flops_max; /* its MUMPS flops: all ranks, the largest rank's share */
  PetscInt  interface_unknowns;               /* separator rows + multipliers */
  PetscInt  ksp_its_max, ksp_its_total;       /* Krylov iterations of the steps' solves (1 per direct solve) */
  PetscInt  pc_setups;                        /* iterative path: preconditioner set-ups */
  struct M2dCondensed *factor;                /* with pb->keep_factor: the condensed path's factorization, the caller's to free (CondensedDestroy), or NULL */
} M2dActiveSetInfo;

typedef struct M2dActiveSet M2dActiveSet;

/* The active-set solver of pb on `path` (condensed, iterative or full; the
 * condensed path gives way to full when the SNES type asks for the VI
 * solver): the SNES, the path's factorization. Collective. */
PetscErrorCode M2dActiveSetCreate(M2dProblem *pb, M2dSolverPath path, M2dActiveSet **as);
/* Solve one load step (pb->f and the KKT's rows set for it: KKTSetLoad),
 * starting from the previous step's answer and states (the first: from 0 and
 * the initial states). u (layout of pb->f), lam and active (layout of
 * pb->kkt.r) receive the displacement, the multipliers (0 on open rows) and
 * the final rules (1: a constraint row, a closed normal row or a sticking
 * tangential one); slip (friction; else NULL) gets the step's weighted slip
 * added on the tangential rows of the closed nodes; info the counts so far.
 * Collective. */
PetscErrorCode M2dActiveSetStep(M2dActiveSet *as, Vec u, Vec lam, Vec active, Vec slip, M2dActiveSetInfo *info);
/* Free the solver; with pb->keep_factor the condensed factorization is left
 * in info->factor for the caller. Collective. */
PetscErrorCode M2dActiveSetDestroy(M2dActiveSet **as, M2dActiveSetInfo *info);
/* default complementarity parameter E* / h^2 (reference units). Not collective. */
PetscReal      ActiveSetDefaultC(const M2dScene *s, const M2dContact *ct);
#endif
