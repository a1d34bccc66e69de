/* solver.c - the solver path and the linear solves (see solver.h). */
#include "solver.h"
#include "condensed.h"
#include "iterative.h"
#include "method.h"
#include "optcheck.h"
#include <petscsnes.h>
#include <string.h>

/* -kkt_path iterative: what the elimination of the multipliers needs (iterative.h) */
static PetscErrorCode CheckIterative(MPI_Comm comm, const M2dScene *s, PetscBool vi, M2dSolverChoice *c)
{
  PetscFunctionBeginUser;
  if (!s->npair) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < s->npair; k++) { /* every pair's own method */
    const M2dPair *p = &s->pair[k];
    PetscCheck(M2dMethodOf(p->method, p->basis)->row_own_dof, comm, PETSC_ERR_USER_INPUT, "option -kkt_path iterative: standard mortar multipliers couple neighbouring nodes and cannot be eliminated row by row; use -mortar_basis dual (or -kkt_path condensed)%s%s", p->own_method ? "; " : "", p->own_method ? p->what : "");
  }
  PetscCheck(s->kkt_augment == 0, comm, PETSC_ERR_USER_INPUT, "option -kkt_augment: not used by -kkt_path iterative (the multipliers are eliminated; leave it 0)");
  PetscCheck(!vi, comm, PETSC_ERR_USER_INPUT, "option -snes_type vinewtonrsls: -kkt_path iterative takes the primal-dual active set (newtonls)");
  c->kkt_mat = M2D_KKT_NEST; /* the blocks are enough: no monolithic copy */
  PetscFunctionReturn(0);
}

/* the default condensed path, or the full one for a long contact surface */
static PetscErrorCode CondensedOrFull(MPI_Comm comm, const M2dScene *s, const M2dMesh *m, M2dSolverChoice *c)
{
  PetscInt  n = 0;
  PetscBool given;

  PetscFunctionBeginUser;
  c->path = M2D_PATH_CONDENSED;
  PetscCall(PetscOptionsHasName(NULL, NULL, "-kkt_path", &given));
  for (PetscInt k = 0; m && !given && k < s->npair; k++) { /* every pair's non-mortar edges */
    PetscInt nk;
    PetscCall(MeshGroupSize(m, s->pair[k].nm, s->pair[k].opt_nm, &nk));
    n += nk;
  }
  if (n > s->kkt_condensed_max) {
    c->path = M2D_PATH_FULL;
    PetscCall(PetscPrintf(comm, "active set: -kkt_path full (%" PetscInt_FMT " non-mortar edges, more than -kkt_condensed_max %" PetscInt_FMT ": the condensed path's dense interface would cost O(N^3) a step)\n", n, s->kkt_condensed_max));
  } else if (s->kkt_augment == 0) c->kkt_augment = 1.0; /* the condensed path factors K + g C^T C */
  PetscFunctionReturn(0);
}

/* the options that do nothing on the path chosen (optcheck.h) */
static PetscErrorCode CheckEffect(MPI_Comm comm, const M2dScene *s, M2dSolverPath path, PetscBool auto_path)
{
  const char *why = ProblemPathSays(s, path);

  PetscFunctionBeginUser;
  if (path != M2D_PATH_CONDENSED) PetscCall(M2dOptionsNoEffect(comm, "-kkt_ldlt", "%s", why));
  if (path != M2D_PATH_ITERATIVE) PetscCall(M2dOptionsNoEffect(comm, "-iterative_inexact -iterative_prove -iterative_reuse -iterative_zone", "%s", why)); /* read by the active set's iterative solver only */
  if (!auto_path) PetscCall(M2dOptionsNoEffect(comm, "-kkt_condensed_max", "%s", path == M2D_PATH_CONDENSED || path == M2D_PATH_FULL ? "with -kkt_path, -kkt_mat nest or -snes_type vinewtonrsls (the path is not chosen by the contact surface's length)" : why));
  if (path == M2D_PATH_LINEAR || path == M2D_PATH_TIED) {
    PetscCall(M2dOptionsNoEffect(comm, "snes_*", "%s", why));
    if (s->kkt_path != M2D_KKT_PATH_ITERATIVE) PetscCall(M2dOptionsNoEffect(comm, "-kkt_path", "%s", why));
  }
  if (path == M2D_PATH_LINEAR) PetscCall(M2dOptionsNoEffect(comm, "-kkt_mat -kkt_augment", "%s", why));
  if (s->kkt_path == M2D_KKT_PATH_ITERATIVE) PetscCall(M2dOptionsNoEffect(comm, "-kkt_mat -kkt_ordering -mat_mumps_icntl_4 -mat_mumps_icntl_7 -mat_mumps_icntl_8 -mat_mumps_icntl_14 -mat_mumps_icntl_58 mat_mumps_*", "%s", why));
  /* read by the SNES's KSP, then replaced by the path's own step solver */
  if (path == M2D_PATH_CONDENSED || path == M2D_PATH_ITERATIVE) PetscCall(M2dOptionsNoEffect(comm, "ksp_* pc_* fieldsplit_* mat_mumps_*", "%s: PETSc's KSP, PC and MUMPS options act on -kkt_path full", why));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSolverChoosePath(MPI_Comm comm, const M2dScene *s, const M2dMesh *m, M2dSolverChoice *c)
{
  char      st[64];
  PetscBool set, vi, auto_path = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-snes_type", st, sizeof(st), &set));
  vi = (PetscBool)(set && !strcmp(st, SNESVINEWTONRSLS));
  *c = (M2dSolverChoice){.kkt_mat = s->kkt_mat, .kkt_augment = s->kkt_augment};
  if (s->kkt_path == M2D_KKT_PATH_ITERATIVE) PetscCall(CheckIterative(comm, s, vi, c));
  if (!s->npair) c->path = M2D_PATH_LINEAR;
  else if (!s->unilateral) c->path = M2D_PATH_TIED;
  else if (s->kkt_path == M2D_KKT_PATH_ITERATIVE) c->path = M2D_PATH_ITERATIVE;
  else if (s->kkt_path == M2D_KKT_PATH_FULL) c->path = M2D_PATH_FULL;
  else {
    if (s->kkt_mat == M2D_KKT_NEST || vi) {
      c->path = M2D_PATH_FULL;
      PetscCall(PetscPrintf(comm, "active set: -kkt_path full (the condensed path needs -kkt_mat aij and newtonls)\n"));
    } else {
      PetscCall(PetscOptionsHasName(NULL, NULL, "-kkt_path", &set));
      auto_path = (PetscBool)!set;
      PetscCall(CondensedOrFull(comm, s, m, c));
    }
  }
  if (m && !s->help) PetscCall(CheckEffect(comm, s, c->path, auto_path));
  PetscFunctionReturn(0);
}

const char *M2dSolverPathName(M2dSolverPath path)
{
  static const char *name[] = {"linear", "tied", "condensed", "full", "iterative"};
  return name[path];
}

/* Linear solves (no contact, or tied) default to MUMPS LDL^T (PCCHOLESKY):
 * the matrix is symmetric, as on the condensed path. The ordering is
 * M2dOrderingSetupKSP's: MUMPS' AMF for a Cholesky factor (PETSc 3.18 hands
 * MUMPS none), METIS for -pc_type lu on one rank. Every choice can be
 * overridden from the options database. */
static PetscErrorCode SetupLinearKSP(KSP ksp, M2dOrdering ord)
{
  PC        pc;
  PetscBool factor, chosen;

  PetscFunctionBeginUser;
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCCHOLESKY));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(KSPSetFromOptions(ksp));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, ""));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-pc_factor_mat_solver_type", &chosen));
  if (factor && !chosen) PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS)); /* -pc_type lu alone: still MUMPS */
  PetscCall(M2dOrderingSetupKSP(ksp, ord, NULL));
  PetscFunctionReturn(0);
}

/* Is the answer of ksp a factorization's (backward stable: verify.c judges
 * its residual by the backward error)? ksp NULL: the options' KSP (the full
 * path's, PREONLY + LU unless the options say otherwise). */
static PetscErrorCode Factored(KSP ksp, PetscBool *factored)
{
  PetscBool preonly, factor;

  PetscFunctionBeginUser;
  if (ksp) {
    PC pc;
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PetscObjectTypeCompare((PetscObject)ksp, KSPPREONLY, &preonly));
    PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, ""));
  } else {
    char kt[64] = KSPPREONLY, pt[64] = PCLU;
    PetscCall(PetscOptionsGetString(NULL, NULL, "-ksp_type", kt, sizeof(kt), NULL));
    PetscCall(PetscOptionsGetString(NULL, NULL, "-pc_type", pt, sizeof(pt), NULL));
    preonly = (PetscBool)!strcmp(kt, KSPPREONLY);
    factor  = (PetscBool)(!strcmp(pt, PCLU) || !strcmp(pt, PCCHOLESKY));
  }
  *factored = (PetscBool)(preonly && factor);
  PetscFunctionReturn(0);
}

/* the one line for a failed linear solve */
static PetscErrorCode LinearSolveFailed(KSP ksp, PetscBool contact, PetscReal gamma)
{
  KSPConvergedReason reason;
  MPI_Comm           comm = PetscObjectComm((PetscObject)ksp);

  PetscFunctionBeginUser;
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  if (reason > 0) PetscFunctionReturn(0);
  if (contact) PetscCall(KKTFieldsplitCheck(ksp, gamma));
  PetscCall(KKTKrylovCheck(ksp, "linear solve failed", PETSC_TRUE));
  SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "linear solve failed: %s (check the supports: is every body held?)", KSPConvergedReasons[reason]);
}

/* -kkt_path iterative without the active set: K u = f by CG + AMG, or every
 * candidate held closed by the elimination of iterative.h */
static PetscErrorCode SolveLinearIterative(M2dProblem *pb, M2dSolution *sol)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)pb->K);

  PetscFunctionBeginUser;
  if (sol->path == M2D_PATH_LINEAR) {
    KSP ksp;
    PetscCall(M2dIterativeCreateKSP(comm, &ksp));
    PetscCall(KSPSetOperators(ksp, pb->K, pb->K));
    PetscCall(M2dOptionsCheckUnused(comm, ProblemPathSays(&pb->s, sol->path)));
    PetscCall(KSPSolve(ksp, pb->f, sol->u));
    PetscCall(LinearSolveFailed(ksp, PETSC_FALSE, 0));
    PetscCall(KSPGetIterationNumber(ksp, &sol->ksp_its));
    PetscCall(KSPDestroy(&ksp));
  } else {
    M2dIterative    *it;
    M2dIterativeInfo ii;
    PetscCall(M2dIterativeCreate(&pb->kkt, &pb->Rkkt, pb->ndir, pb->drows, &it));
    PetscCall(M2dOptionsCheckUnused(comm, ProblemPathSays(&pb->s, sol->path)));
    PetscCall(VecSet(sol->active, 1.0));
    PetscCall(M2dIterativeSetActive(it, sol->active, 1.0, 1.0)); /* rows C_j u = r_j */
    PetscCall(M2dIterativeSolve(it, pb->kkt.b, 0, pb->kkt.x));
    PetscCall(VecISCopy(pb->kkt.x, pb->kkt.isu, SCATTER_REVERSE, sol->u));
    PetscCall(VecISCopy(pb->kkt.x, pb->kkt.isl, SCATTER_REVERSE, sol->lam));
    PetscCall(M2dIterativeGetInfo(it, &ii));
    sol->ksp_its = ii.its_max;
    PetscCall(M2dIterativeDestroy(&it));
  }
  PetscFunctionReturn(0);
}

/* no contact, or every candidate held closed: one linear solve */
static PetscErrorCode SolveLinear(M2dProblem *pb, M2dSolution *sol)
{
  KSP      ksp;
  PetscBool contact = (PetscBool)(sol->path == M2D_PATH_TIED);

  PetscFunctionBeginUser;
  if (pb->s.kkt_path == M2D_KKT_PATH_ITERATIVE) PetscFunctionReturn(SolveLinearIterative(pb, sol));
  PetscCall(KSPCreate(PetscObjectComm((PetscObject)pb->K), &ksp));
  PetscCall(KSPSetOperators(ksp, contact ? pb->kkt.A : pb->K, contact ? pb->kkt.A : pb->K));
  PetscCall(SetupLinearKSP(ksp, pb->s.kkt_ordering));
  if (contact) PetscCall(KKTSetupKSP(&pb->kkt, ksp));
  PetscCall(M2dOptionsCheckUnused(PetscObjectComm((PetscObject)ksp), ProblemPathSays(&pb->s, sol->path))); /* the solver is configured: an option nobody read is a typo */
  if (contact) {
    PetscCall(KKTSolve(&pb->kkt, ksp, sol->u, sol->lam));
    PetscCall(VecSet(sol->active, 1.0));
  } else PetscCall(KSPSolve(ksp, pb->f, sol->u));
  PetscCall(LinearSolveFailed(ksp, contact, contact ? pb->kkt.gamma : 0));
  PetscCall(KSPGetIterationNumber(ksp, &sol->ksp_its));
  PetscCall(Factored(ksp, &sol->factored));
  PetscCall(KSPDestroy(&ksp));
  PetscFunctionReturn(0);
}

/* keep load step k's answer (a history of several) */
static PetscErrorCode KeepStep(const M2dProblem *pb, M2dSolution *sol, PetscInt k, PetscInt stage, PetscInt step, PetscInt its)
{
  M2dLoadStep *ls = &sol->steps[k];
  Vec         *to[5] = {&ls->u, &ls->lam, &ls->active, &ls->slip, &ls->r};
  Vec          from[5] = {sol->u, sol->lam, sol->active, sol->slip, pb->has_contact ? pb->kkt.r : NULL};

  PetscFunctionBeginUser;
  ls->stage      = stage;
  ls->step       = step;
  ls->time       = stage + (PetscReal)step / (PetscReal)pb->s.stage_steps[stage];
  ls->iterations = its;
  for (int i = 0; i < 5; i++)
    if (from[i]) {
      PetscCall(VecDuplicate(from[i], to[i]));
      PetscCall(VecCopy(from[i], *to[i]));
    }
  PetscFunctionReturn(0);
}

/* the load history: every step of every stage (one step: the scene's loads
 * as assembled), each from the last one's answer; the active set's solver
 * (its factorization) is made once for all of them */
PetscErrorCode M2dSolverSolve(M2dProblem *pb, const M2dSolverChoice *c, M2dSolution *sol)
{
  M2dActiveSet  *as = NULL;
  PetscInt       n  = SceneLoadSteps(&pb->s), k = 0, its = 0;
  PetscErrorCode ierr = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sol, sizeof(*sol)));
  sol->path = c->path;
  PetscCall(VecDuplicate(pb->f, &sol->u));
  PetscCall(PetscObjectSetName((PetscObject)sol->u, "displacement"));
  if (pb->has_contact) {
    PetscCall(VecDuplicate(pb->kkt.r, &sol->lam));
    PetscCall(VecDuplicate(pb->kkt.r, &sol->active));
    if (pb->kkt.partner) {
      PetscCall(VecDuplicate(pb->kkt.r, &sol->slip));
      PetscCall(VecZeroEntries(sol->slip));
    }
  }
  if (n > 1) PetscCall(PetscCalloc1(n, &sol->steps));
  for (PetscInt stage = 0; stage < pb->s.nstage && !ierr; stage++)
    for (PetscInt step = 1; step <= pb->s.stage_steps[stage] && !ierr; step++, k++) {
      if (n > 1) {
        PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->f), "load step %" PetscInt_FMT " of %" PetscInt_FMT " (stage %" PetscInt_FMT ", %" PetscInt_FMT "/%" PetscInt_FMT ")\n", k + 1, n, stage + 1, step, pb->s.stage_steps[stage]));
        PetscCall(ProblemSetLoad(pb, stage, step));
        if (pb->has_contact) PetscCall(KKTSetLoad(&pb->kkt, pb->ubc, k ? sol->u : NULL));
      }
      if (!as && sol->path != M2D_PATH_LINEAR && sol->path != M2D_PATH_TIED) ierr = M2dActiveSetCreate(pb, sol->path, &as); /* the factorization condenses the first step's load */
      if (ierr) break;
      if (as) {
        its  = sol->as.iterations;
        ierr = M2dActiveSetStep(as, sol->u, sol->lam, sol->active, sol->slip, &sol->as);
        its  = sol->as.iterations - its;
      } else ierr = SolveLinear(pb, sol);
      if (!ierr && n > 1) ierr = KeepStep(pb, sol, k, stage, step, its);
    }
  sol->nstep = k;
  PetscCall(M2dActiveSetDestroy(&as, &sol->as)); /* also after an error: it holds the factorization */
  PetscCall(ierr);
  sol->ksp_its_max = sol->path == M2D_PATH_LINEAR || sol->path == M2D_PATH_TIED ? sol->ksp_its : sol->as.ksp_its_max;
  if (sol->path != M2D_PATH_LINEAR && sol->path != M2D_PATH_TIED) { /* SolveLinear judged its own KSP */
    if (sol->as.condensed) sol->factored = PETSC_TRUE; /* MUMPS' LDL^T of K, a dense LU of the interface */
    else if (sol->path != M2D_PATH_ITERATIVE) PetscCall(Factored(NULL, &sol->factored));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSolverDocumentOptions(MPI_Comm comm, const M2dScene *s)
{
  KSP ksp;

  PetscFunctionBeginUser;
  PetscCall(KSPCreate(comm, &ksp));
  PetscCall(SetupLinearKSP(ksp, s->kkt_ordering));
  PetscCall(KSPDestroy(&ksp));
  PetscCall(M2dIterativeCreateKSP(comm, &ksp));
  PetscCall(KSPDestroy(&ksp));
  {
    M2dIterativeOptions opt;
    PetscCall(M2dIterativeReadOptions(comm, &opt));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSolutionDestroy(M2dSolution *sol)
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; sol->steps && k < sol->nstep; k++) {
    M2dLoadStep *ls = &sol->steps[k];
    PetscCall(VecDestroy(&ls->u));
    PetscCall(VecDestroy(&ls->lam));
    PetscCall(VecDestroy(&ls->active));
    PetscCall(VecDestroy(&ls->slip));
    PetscCall(VecDestroy(&ls->r));
    PetscCall(PetscFree(ls->nodes));
  }
  PetscCall(PetscFree(sol->steps));
  PetscCall(VecDestroy(&sol->slip));
  PetscCall(VecDestroy(&sol->u));
  PetscCall(VecDestroy(&sol->lam));
  PetscCall(VecDestroy(&sol->active));
  PetscCall(PetscFree(sol->eta));
  PetscCall(PetscFree(sol->sv));
  PetscCall(CondensedDestroy(&sol->as.factor));
  PetscFunctionReturn(0);
}
