/* iterative.h - the iterative path (-kkt_path iterative): each active-set
 * step's KKT solve by eliminating the multipliers and solving a sparse SPD
 * system in u with a Krylov method and an algebraic multigrid (CG +
 * BoomerAMG by default, prefix -iterative_), on any number of ranks: no
 * factorization, no dense block, nothing that grows with the number of
 * ranks (but the contact zone's small exact solve, held by every rank).
 *
 * With dual mortar multipliers (diagonal D) or node-to-segment rows, each
 * contact row j has a dof of its own, s(j): a dof of its non-mortar node that
 * no other row touches (the component along the normal). On an active row
 * the constraint C_j du = t_j gives that dof from the others,
 *   du_s = (t_j - sum_{l != s} C_jl du_l) / C_js,
 * i.e. du = P v + e with P the identity except on the active slave rows
 * (P_sl = -C_jl / C_js, P_ss = 0) and e_s = t_j / C_js. The u rows then give
 *   (P^T K P + D_S) v = P^T (q - K e),   q = b_u - C_I^T dl_I,
 * (D_S = diag K on the active slave dofs, whose v is 0), symmetric positive
 * definite whenever the set holds every body; and the multiplier of row j
 * from row s of K du + C^T dl = b_u: dl_j = (q - K du)_s / C_js. Inactive
 * rows give dl_j directly. This is the condensation of the dual mortar
 * literature (Wohlmuth; Popp et al.) written algebraically: the same Newton
 * step as the full path's factorization, to the Krylov tolerance.
 *
 * P keeps one nonzero pattern for every candidate row (explicit zeros when a
 * row is inactive), so P^T K P keeps its pattern across steps. Between two
 * sets it changes only in the contact zone (the rows' unknowns and their
 * neighbours): the preconditioner is the zone's exact solve around the AMG
 * (symmetric multiplicative), so the AMG of an earlier step still serves
 * and is built anew only when CG slows down (-iterative_reuse). The
 * near-null space of K (rigid-body modes, problem.h) goes to the reduced
 * operator, which keeps K's block size 2. */
#ifndef M2D_ITERATIVE_H
#define M2D_ITERATIVE_H
#include "kkt.h"

typedef struct M2dIterative M2dIterative;

/* the active-set steps' use of the Krylov solver (docs/scaling.md) */
typedef struct {
  PetscReal inexact; /* -iterative_inexact: a step's tolerance while its set may still change */
  PetscReal reuse;   /* -iterative_reuse: keep the AMG while a step converges at most this much slower */
  PetscInt  zone;    /* -iterative_zone: rings around the contact dofs solved exactly (-1: none) */
  PetscBool prove;   /* -iterative_prove: every inexact step refined until its next set is sure */
} M2dIterativeOptions;

typedef struct {
  PetscInt solves;     /* linear solves (active-set steps) */
  PetscInt its_max;    /* most Krylov iterations of one solve */
  PetscInt its_total;  /* all Krylov iterations */
  PetscInt setups;     /* preconditioner set-ups (the others reused an earlier step's) */
  PetscInt slave_dofs; /* candidate rows = dofs eliminated when active */
  PetscInt zone_dofs;  /* unknowns of the contact zone (0: none) */
  PetscReal rtol;      /* a complete solve's tolerance (-iterative_ksp_rtol) */
  PetscReal inexact;   /* -iterative_inexact */
  PetscBool prove;     /* -iterative_prove */
} M2dIterativeInfo;

/* -iterative_inexact and -iterative_reuse (with -help, their help and
 * defaults); one line for a value out of range. Collective. */
PetscErrorCode M2dIterativeReadOptions(MPI_Comm comm, M2dIterativeOptions *opt);

/* Set up the elimination for the candidate rows R (every rank holds all of
 * them, as contact.h builds them; the KKT's rows, i.e. in the frames'
 * coordinates) of kkt (K, C with its Dirichlet columns zeroed); drows are
 * this rank's Dirichlet rows. Errors (one line, every rank) when a row has no
 * dof of its own: standard mortar multipliers couple neighbouring nodes (use
 * -mortar_basis dual). Collective; free with M2dIterativeDestroy. */
PetscErrorCode M2dIterativeCreate(const M2dKKT *kkt, const M2dContactRows *R, PetscInt ndir, const PetscInt drows[], M2dIterative **it);
/* The Jacobian of one active-set step: rows with active != 0 are constraints
 * scale C_j du = b_j, the others -(scale / c) dl_j = b_j (kkt.h,
 * KKTSetActive). Builds P^T K P and sets up the Krylov solver. Collective. */
PetscErrorCode M2dIterativeSetActive(M2dIterative *it, Vec active, PetscReal c, PetscReal scale);
/* y = J^-1 b, b and y in the KKT layout (kkt->isu, kkt->isl), the u system
 * solved to rtol of its right-hand side (0: a complete solve, to
 * -iterative_ksp_rtol). Errors (one line) when the Krylov method does not
 * converge. Collective. */
PetscErrorCode M2dIterativeSolve(M2dIterative *it, Vec b, PetscReal rtol, Vec y);
/* The last solve taken on from where it stopped to the smaller rtol (0: a
 * complete solve); y as in M2dIterativeSolve. Collective. */
PetscErrorCode M2dIterativeRefine(M2dIterative *it, PetscReal rtol, Vec y);
/* Iteration counts so far. Not collective. */
PetscErrorCode M2dIterativeGetInfo(const M2dIterative *it, M2dIterativeInfo *info);
/* The Krylov solver of the u system (CG + GAMG, options prefix -iterative_,
 * configured from the options database); the caller destroys it. Collective. */
PetscErrorCode M2dIterativeCreateKSP(MPI_Comm comm, KSP *ksp);
PetscErrorCode M2dIterativeDestroy(M2dIterative **it);
#endif
