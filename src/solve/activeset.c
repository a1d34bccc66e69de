/* activeset.c - unilateral contact by semismooth Newton (PDAS) or
 * SNESVINEWTONRSLS (see activeset.h): the SNES that drives the steps (set-up,
 * convergence, monitor, failure messages, the solve). One step's pieces (the
 * mask, the residual, the set of the Jacobian) are in activeset_step.c, what
 * each solver path adds in activeset_paths.c. */
#include "activeset_paths.h"
#include "optcheck.h"

/* one pair's c: E* / h^2, E* of its two bodies, h its mean non-mortar edge */
static PetscReal PairC(const M2dScene *s, const M2dContactPair *ct)
{
  PetscReal inv = 0, h = 0;
  PetscInt  b[2] = {ct->nm.body, ct->m.body};
  for (int k = 0; k < 2; k++) {
    const M2dBody *bd = &s->body[b[k] >= 0 ? b[k] : 0];
    PetscReal      Ep = s->plane == M2D_PLANE_STRAIN ? bd->E / (1 - bd->nu * bd->nu) : bd->E;
    inv += 1.0 / Ep;
  }
  for (PetscInt e = 0; e < ct->nm.nedge; e++) h += ct->nm.len[e];
  h /= PetscMax(1, ct->nm.nedge);
  return (1.0 / inv) / (h * h);
}

/* the largest pair's */
PetscReal ActiveSetDefaultC(const M2dScene *s, const M2dContact *ct)
{
  PetscReal c = 0;
  for (PetscInt k = 0; k < ct->npair; k++) c = PetscMax(c, PairC(s, &ct->pair[k]));
  return c;
}

/* Converged: the set is unchanged and the residual at tolerance. A set solved
 * twice whose residual no longer falls is the round-off floor of an
 * ill-conditioned system; it stops the iteration only within 1e-6 of the
 * starting residual - the answer's own checks (verify.h) then decide. */
static PetscErrorCode Converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm, SNESConvergedReason *reason, void *ctx)
{
  M2dActiveSet *as = (M2dActiveSet *)ctx;
  PetscReal     atol, rtol, stol;
  PetscInt      maxit, maxf, k;
  PetscBool     same;

  PetscFunctionBeginUser;
  (void)xnorm;
  (void)snorm;
  PetscCall(SNESGetTolerances(snes, &atol, &rtol, &stol, &maxit, &maxf));
  *reason = SNES_CONVERGED_ITERATING;
  if (it == 0 && !as->cond) as->fnorm0 = fnorm; /* condensed path: set by CondensedStart */
  k    = it + (as->cond ? 1 : 0);               /* steps taken, as the full path counts them */
  same = (PetscBool)(as->entered + as->left == 0);
  if (as->hist.failed) *reason = SNES_DIVERGED_LOCAL_MIN;
  else if (PetscIsInfOrNanReal(fnorm)) *reason = SNES_DIVERGED_FNORM_NAN;
  else if ((k > 0 || as->nactive == 0) && same && (fnorm <= atol || fnorm <= rtol * as->fnorm0)) *reason = k > 0 ? SNES_CONVERGED_FNORM_RELATIVE : SNES_CONVERGED_FNORM_ABS;
  else if (k > 1 && same && as->unchanged_before && fnorm >= 0.5 * as->fnorm_prev && fnorm <= 1e-6 * as->fnorm0) *reason = SNES_CONVERGED_SNORM_RELATIVE;
  else if (it >= maxit) *reason = SNES_DIVERGED_MAX_IT;
  as->unchanged_before = (PetscBool)(k > 0 && same);
  as->fnorm_prev       = fnorm;
  if (as->iter && !as->proving && it > 0) { /* sets taken from inexact solves that send |F| up: proven from here */
    if (it > 1 && fnorm > M2D_RISE * as->fbest) {
      as->proving = PETSC_TRUE;
      PetscCall(PetscPrintf(PetscObjectComm((PetscObject)snes), "  active set step %2" PetscInt_FMT ": |F| %.3e, %.0f times the least since step 1: each step's set proven from here\n", it, (double)fnorm, (double)(fnorm / as->fbest)));
    }
    as->fbest = it == 1 ? fnorm : PetscMin(as->fbest, fnorm);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Monitor(SNES snes, PetscInt it, PetscReal fnorm, void *ctx)
{
  M2dActiveSet *as = (M2dActiveSet *)ctx;
  Vec           F, fl, z;
  PetscReal     fu_norm, fl_norm;

  PetscFunctionBeginUser;
  if (as->vi && it > 0) { /* the VI solver has no Jacobian hook of ours */
    as->step = it;
    PetscCall(ActiveSetChooseSet(as, PetscObjectComm((PetscObject)snes)));
  }
  if (!as->monitor) PetscFunctionReturn(0);
  PetscCall(SNESGetFunction(snes, &F, NULL, NULL));
  if (as->cond) { /* the u rows hold by construction (round-off: see the final checks) */
    fu_norm = 0;
    fl_norm = fnorm;
    it++; /* the first set was solved before the SNES */
  } else {
    PetscCall(VecISCopy(F, as->kkt->isu, SCATTER_REVERSE, as->u));
    PetscCall(VecNorm(as->u, NORM_2, &fu_norm));
    PetscCall(VecDuplicate(as->lam, &fl));
    PetscCall(VecISCopy(F, as->kkt->isl, SCATTER_REVERSE, fl));
    PetscCall(VecNorm(fl, NORM_2, &fl_norm));
    PetscCall(VecDestroy(&fl));
    PetscCall(SNESGetSolution(snes, &z)); /* as->u held F_u: restore the iterate */
    PetscCall(VecISCopy(z, as->kkt->isu, SCATTER_REVERSE, as->u));
  }
  if (it == 0) PetscCall(PetscPrintf(PetscObjectComm((PetscObject)snes), "  active set step %2" PetscInt_FMT ": %6" PetscInt_FMT " active (initial guess)         |F| %.3e  |F_u| %.3e  |F_lambda| %.3e\n", it, as->nactive, (double)fnorm, (double)fu_norm, (double)fl_norm));
  else PetscCall(PetscPrintf(PetscObjectComm((PetscObject)snes), "  active set step %2" PetscInt_FMT ": %6" PetscInt_FMT " active (+%" PetscInt_FMT " entered, -%" PetscInt_FMT " left)  |F| %.3e  |F_u| %.3e  |F_lambda| %.3e\n", it, as->nactive, as->entered, as->left, (double)fnorm, (double)fu_norm, (double)fl_norm));
  PetscFunctionReturn(0);
}

/* work vectors, c, h and the tie tolerance: 1e-12 of the weight times the reference displacement */
static PetscErrorCode ContextCreate(M2dProblem *pb, Vec u, Vec lam, Vec active, M2dActiveSet *as)
{
  const M2dContact *ct = &pb->contact;
  PetscInt          lo, hi;
  PetscScalar      *t;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(as, sizeof(*as)));
  as->pb              = pb;
  as->kkt             = &pb->kkt;
  as->c               = pb->s.contact_c_set ? pb->s.contact_c : ActiveSetDefaultC(&pb->s, ct);
  as->monitor         = pb->s.contact_monitor;
  as->hist.max_cycles = 5;
  {
    PetscInt ne = 0;
    for (PetscInt k = 0; k < ct->npair; k++) {
      for (PetscInt e = 0; e < ct->pair[k].nm.nedge; e++) as->h += ct->pair[k].nm.len[e];
      ne += ct->pair[k].nm.nedge;
    }
    as->h /= PetscMax(1, ne);
  }
  PetscCall(VecDuplicate(u, &as->u));
  PetscCall(VecDuplicate(lam, &as->lam));
  PetscCall(VecDuplicate(lam, &as->gm));
  PetscCall(VecDuplicate(lam, &as->tol));
  PetscCall(VecDuplicate(lam, &as->used));
  as->active = active;
  PetscCall(VecSet(as->used, 1.0));
  PetscCall(VecSet(as->active, 0.0));
  PetscCall(VecScatterCreateToAll(active, &as->toall, &as->all));
  PetscCall(VecGetOwnershipRange(as->tol, &lo, &hi));
  PetscCall(VecGetArrayWrite(as->tol, &t));
  for (PetscInt j = lo; j < hi; j++) t[j - lo] = 1e-12 * ct->R.w[j];
  PetscCall(VecRestoreArrayWrite(as->tol, &t));
  PetscFunctionReturn(0);
}

static PetscErrorCode ContextDestroy(M2dActiveSet *as)
{
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&as->u));
  PetscCall(VecDestroy(&as->lam));
  PetscCall(VecDestroy(&as->gm));
  PetscCall(VecDestroy(&as->tol));
  PetscCall(VecDestroy(&as->used));
  PetscCall(VecDestroy(&as->cu));
  PetscCall(VecDestroy(&as->du));
  PetscCall(VecDestroy(&as->cdu));
  PetscCall(VecDestroy(&as->m[0]));
  PetscCall(VecDestroy(&as->m[1]));
  PetscCall(VecDestroy(&as->all));
  PetscCall(VecScatterDestroy(&as->toall));
  PetscCall(CondensedDestroy(&as->cond));
  PetscCall(M2dIterativeDestroy(&as->iter));
  PetscFunctionReturn(0);
}

/* newtonls with full steps (PDAS) and MUMPS LU, or vinewtonrsls; then the options database */
static PetscErrorCode ConfigureSNES(SNES snes, M2dActiveSet *as, M2dSolverPath path)
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)snes);
  SNESLineSearch ls;
  KSP            ksp;
  PC             pc;
  PetscBool      ok;

  PetscFunctionBeginUser;
  PetscCall(SNESSetType(snes, SNESNEWTONLS));
  PetscCall(SNESGetLineSearch(snes, &ls));
  PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(SNESSetTolerances(snes, 1e-50, 1e-10, 0.0, 50, -1));
  PetscCall(SNESSetFromOptions(snes));
  PetscCall(PetscObjectTypeCompare((PetscObject)snes, SNESVINEWTONRSLS, &as->vi));
  if (as->vi) { /* -snes_type resets the line search: full steps again, unless the options say otherwise */
    PetscCall(SNESGetLineSearch(snes, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
    PetscCall(SNESLineSearchSetFromOptions(ls));
  }
  PetscCall(PetscObjectTypeCompare((PetscObject)snes, SNESNEWTONLS, &ok));
  PetscCheck(ok || as->vi, comm, PETSC_ERR_USER_INPUT, "option -snes_type: contact is solved with newtonls (primal-dual active set) or vinewtonrsls");
  if (path != M2D_PATH_ITERATIVE) PetscCall(KKTSetupKSP(as->kkt, ksp)); /* the iterative path solves by blocks */
  PetscFunctionReturn(0);
}

/* lambda0_j = c max(g~0_j, 0) makes node j active at the start: the set of
 * the previous mesh carried over by position (pb->warm), every candidate
 * (all), or those whose nodal gap g~0/w is within 1e-6 of the mortar
 * surface's size of the smallest one (closest; gaps are in reference
 * displacements, the size in reference lengths: L/U converts) */
static PetscErrorCode InitialMultipliers(M2dActiveSet *as, Vec z)
{
  const M2dContact  *ct = &as->pb->contact;
  const PetscScalar *r;
  PetscScalar       *l;
  PetscInt           lo, hi, how = as->pb->s.contact_initial, np = ct->npair;
  PetscReal          gmin[M2D_MAX_PAIRS], L[M2D_MAX_PAIRS];

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(z));
  PetscCall(VecZeroEntries(as->lam));
  if (how == 0 && !as->pb->warm && !as->vi) PetscFunctionReturn(0); /* VI: at least the closest nodes (below) */
  for (PetscInt k = 0; k < np; k++) { /* each pair's closest nodes: every body held from the first step */
    const M2dSurface *m = &ct->pair[k].m;
    L[k]    = PetscSqrtReal(PetscSqr(m->hi[0] - m->lo[0]) + PetscSqr(m->hi[1] - m->lo[1])) * as->pb->units.L / as->pb->units.U;
    gmin[k] = PETSC_MAX_REAL;
  }
  PetscCall(VecGetOwnershipRange(as->kkt->r, &lo, &hi));
  PetscCall(VecGetArrayRead(as->kkt->r, &r));
  for (PetscInt j = lo; j < hi; j++) gmin[ct->rowpair[j]] = PetscMin(gmin[ct->rowpair[j]], PetscRealPart(r[j - lo]) / ct->R.w[j]);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, gmin, (PetscMPIInt)np, MPIU_REAL, MPIU_MIN, PetscObjectComm((PetscObject)z)));
  PetscCall(VecGetArray(as->lam, &l));
  for (PetscInt j = lo; j < hi; j++) {
    PetscReal g = PetscRealPart(r[j - lo]);
    PetscInt  k = ct->rowpair[j];
    PetscBool on = as->pb->warm ? as->pb->warm[j] : (PetscBool)(how == 2 || g / ct->R.w[j] <= gmin[k] + 1e-6 * L[k]);
    /* the VI solver fixes a multiplier at its bound 0 while the gap is open:
     * a positive start keeps the first set's rows (a body held only by the
     * contact would otherwise be free in the first step) */
    l[j - lo] = on ? as->c * PetscMax(g, as->vi ? 1e-6 * L[k] * ct->R.w[j] : 0) : 0;
  }
  PetscCall(VecRestoreArray(as->lam, &l));
  PetscCall(VecRestoreArrayRead(as->kkt->r, &r));
  PetscCall(VecISCopy(z, as->kkt->isl, SCATTER_FORWARD, as->lam));
  PetscFunctionReturn(0);
}

/* one line for an iteration that ended without an answer */
static PetscErrorCode Failed(SNES snes, M2dActiveSet *as, SNESConvergedReason reason, PetscInt steps)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)snes);
  KSP                ksp;
  KSPConvergedReason kr;
  const M2dProblem  *pb   = as->pb;
  PetscReal          cr   = pb->s.contact_c_set ? pb->s.contact_c / ActiveSetDefaultC(&pb->s, &pb->contact) : 1;

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &kr));
  /* a -contact_c far from E* / h^2 (Hertz: 1e-20 cycles, 1e20 does not settle,
   * 1e200 overflows to NaN) is the likely cause, whatever else the failure says */
  PetscCheck(cr >= 1e-6 && cr <= 1e6, comm, PETSC_ERR_NOT_CONVERGED, "active set %s: -contact_c %g is %.0e times the automatic value E*/h^2 = %g, so the active-set test cannot tell open from closed nodes; omit -contact_c (auto) or keep it within 1e6 of that value",
             as->hist.failed ? "keeps cycling" : reason == SNES_DIVERGED_MAX_IT ? "did not settle in -snes_max_it steps" : "failed", (double)(pb->s.contact_c * pb->units.S / (pb->units.L * pb->units.U)), (double)cr, (double)(pb->s.contact_c / cr * pb->units.S / (pb->units.L * pb->units.U)));
  {
    /* bodies of very different moduli: the steps' round-off, not the step
     * limit (S2 with E 1 under 1e9 on the full path: "did not settle in 50
     * steps (-snes_max_it)"); a step limit below the default of 50 stays the cause */
    PetscInt  soft, stiff;
    PetscReal ratio = SceneModuliRatio(&pb->s, &soft, &stiff);
    PetscCheck(ratio <= 1e6 || !(as->hist.failed || (reason == SNES_DIVERGED_MAX_IT && steps >= 50)), comm, PETSC_ERR_NOT_CONVERGED, "active set %s after %" PetscInt_FMT " steps: the moduli of '%s' and '%s' differ by a factor %.1e and round-off decides the contact state; bring -%s_E within 1e6 of -%s_E (a body a million times stiffer is rigid for the other)",
               as->hist.failed ? "keeps cycling" : "did not settle", steps, pb->s.body[soft].name, pb->s.body[stiff].name, (double)ratio, pb->s.body[soft].name, pb->s.body[stiff].name);
  }
  if (!as->cond && !as->iter) { /* the full path's KSP, from the options */
    char what[64];
    PetscCall(KKTFieldsplitCheck(ksp, as->kkt->gamma));
    if (kr < 0) PetscCall(PetscSNPrintf(what, sizeof(what), "linear solve in active-set step %" PetscInt_FMT " failed", steps));
    else PetscCall(PetscSNPrintf(what, sizeof(what), "active set %s after %" PetscInt_FMT " steps", as->hist.failed ? "keeps cycling" : "did not settle", steps));
    PetscCall(KKTKrylovCheck(ksp, what, PETSC_FALSE));
  }
  PetscCheck(!as->hist.failed, comm, PETSC_ERR_NOT_CONVERGED, "active set keeps cycling (%" PetscInt_FMT " cycles after raising c to %g): no solution found (check the load direction and the supports)", as->hist.cycles, (double)(as->c * CUser(as->pb)));
  PetscCheck(reason != SNES_DIVERGED_MAX_IT, comm, PETSC_ERR_NOT_CONVERGED, "active set did not settle in %" PetscInt_FMT " steps (-snes_max_it)", steps);
  PetscCheck(kr >= 0, comm, PETSC_ERR_NOT_CONVERGED, "linear solve in active-set step %" PetscInt_FMT " failed (%s): is every body held (by supports, or by contact)?", steps, KSPConvergedReasons[kr]);
  SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "active-set iteration failed: %s", SNESConvergedReasons[reason]);
}

/* u, lambda (zero off the final set) and the final set from the iteration */
static PetscErrorCode Finish(M2dActiveSet *as, Vec z, Vec nu, Vec u, Vec lam)
{
  PetscFunctionBeginUser;
  if (as->cond) { /* lambda from the last residual evaluation, u by one substitution */
    PetscCall(CondensedRecover(as->cond, PETSC_TRUE, nu, u));
    PetscCall(VecCopy(as->lam, lam));
  } else {
    PetscCall(VecISCopy(z, as->kkt->isu, SCATTER_REVERSE, u));
    PetscCall(VecISCopy(z, as->kkt->isl, SCATTER_REVERSE, lam));
  }
  if (as->vi) { /* active = positive multiplier */
    PetscCall(VecCopy(lam, as->lam));
    PetscCall(ActiveSetUpdateMask(as));
  } else PetscCall(VecPointwiseMult(lam, lam, as->active)); /* inactive rows: lambda = 0 exactly, not round-off */
  PetscFunctionReturn(0);
}

/* what one active-set solve creates, destroyed whether it succeeded or not */
typedef struct {
  M2dActiveSet as;
  SNES         snes;
  Vec          z, F, nu;
  Mat          Jc;
} Solve;

/* the path's solver: the condensed factorization, the iterative elimination, or the full path's LU */
static PetscErrorCode SetupPath(SNES snes, M2dActiveSet *as, M2dSolverPath path, M2dActiveSetInfo *info)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)snes);

  PetscFunctionBeginUser;
  PetscCall(ConfigureSNES(snes, as, path));
  if (path == M2D_PATH_ITERATIVE) PetscCall(ActiveSetSetupIterative(snes, as));
  PetscCall(M2dOptionsCheckUnused(comm, ProblemPathSays(&as->pb->s, path))); /* the solvers are configured: an option nobody read is a typo */
  if (path == M2D_PATH_CONDENSED && !as->vi) PetscCall(ActiveSetSetupCondensed(snes, as, info));
  else if (path != M2D_PATH_ITERATIVE) {
    KSP ksp;
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(M2dOrderingSetupKSP(ksp, as->pb->s.kkt_ordering, NULL));
  }
  PetscFunctionReturn(0);
}

/* what the solve leaves in info (and, with pb->keep_factor, the condensed factorization) */
static PetscErrorCode Report(M2dActiveSet *as, M2dActiveSetInfo *info)
{
  PetscFunctionBeginUser;
  if (as->pb->keep_factor) { /* handed over: ContextDestroy leaves it */
    info->factor = as->cond;
    as->cond     = NULL;
  }
  info->cycles      = as->hist.cycles;
  info->c           = as->c;
  info->vi          = as->vi;
  info->nactive     = as->nactive;
  info->condensed   = (PetscBool)(as->cond != NULL || info->factor != NULL);
  info->ksp_its_max = 1; /* direct solves */
  if (as->iter) {
    M2dIterativeInfo ii;
    PetscCall(M2dIterativeGetInfo(as->iter, &ii));
    info->ksp_its_max   = ii.its_max;
    info->ksp_its_total = ii.its_total;
    info->pc_setups     = ii.setups;
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)as->lam), "active set: %" PetscInt_FMT " Krylov solves, %" PetscInt_FMT " iterations in all, at most %" PetscInt_FMT " in one, %" PetscInt_FMT " preconditioner set-ups, contact zone of %" PetscInt_FMT " unknowns, %" PetscInt_FMT " steps on an inexact solve's set\n", ii.solves, ii.its_total, ii.its_max, ii.setups, ii.zone_dofs, as->unproven));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode SolveRun(M2dProblem *pb, M2dSolverPath path, Vec u, Vec lam, Vec active, M2dActiveSetInfo *info, Solve *w)
{
  MPI_Comm            comm = PetscObjectComm((PetscObject)u);
  M2dActiveSet       *as   = &w->as;
  SNESConvergedReason reason;

  PetscFunctionBeginUser;
  PetscCall(ContextCreate(pb, u, lam, active, as));
  PetscCall(SNESCreate(comm, &w->snes));
  PetscCall(SetupPath(w->snes, as, path, info));
  PetscCall(VecDuplicate(pb->kkt.x, &w->z));
  PetscCall(VecDuplicate(pb->kkt.x, &w->F));
  PetscCall(InitialMultipliers(as, w->z));
  PetscCall(SNESSetFunction(w->snes, w->F, ActiveSetFunction, as));
  if (as->vi) PetscCall(ActiveSetSetupVI(w->snes, as, w->z));
  else PetscCall(SNESSetConvergenceTest(w->snes, Converged, as, NULL));
  if (as->cond) PetscCall(ActiveSetCondensedStart(w->snes, as, w->z, &w->nu, &w->Jc));
  else if (!as->vi) PetscCall(SNESSetJacobian(w->snes, pb->kkt.A, pb->kkt.A, ActiveSetJacobian, as));
  PetscCall(SNESMonitorSet(w->snes, Monitor, as, NULL));
  PetscCall(PetscPrintf(comm, "active set: %s, %s, c = %g, %" PetscInt_FMT " candidate nodes\n", as->vi ? "SNESVINEWTONRSLS" : "semismooth Newton (primal-dual active set)", as->cond ? "K factored once, steps on the multipliers (condensed)" : as->iter ? "multipliers eliminated, CG + AMG in u (iterative)" : "KKT refactored each step (full)", (double)(as->c * CUser(pb)), pb->kkt.nlam));
  PetscCall(SNESSolve(w->snes, NULL, as->cond ? w->nu : w->z));
  PetscCall(SNESGetConvergedReason(w->snes, &reason));
  PetscCall(SNESGetIterationNumber(w->snes, &info->iterations));
  if (as->cond) info->iterations++; /* the first set was solved before the SNES (CondensedStart) */
  if (reason <= 0) PetscCall(Failed(w->snes, as, reason, info->iterations));
  PetscCall(Finish(as, w->z, w->nu, u, lam));
  PetscCall(Report(as, info));
  PetscCall(PetscPrintf(comm, "active set: converged in %" PetscInt_FMT " steps (%s), %" PetscInt_FMT " active nodes\n", info->iterations, SNESConvergedReasons[reason], info->nactive));
  PetscFunctionReturn(0);
}

PetscErrorCode ActiveSetSolve(M2dProblem *pb, M2dSolverPath path, Vec u, Vec lam, Vec active, M2dActiveSetInfo *info)
{
  Solve          w;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(info, sizeof(*info)));
  PetscCall(PetscMemzero(&w, sizeof(w)));
  /* an error anywhere (a body freed by the contact opening, a failed step)
   * still destroys the SNES, the factorization and the context: they hold
   * references to the DM and the KKT blocks (valgrind: 17 kB lost per error) */
  ierr = SolveRun(pb, path, u, lam, active, info, &w);
  PetscCall(SNESDestroy(&w.snes));
  PetscCall(VecDestroy(&w.z));
  PetscCall(VecDestroy(&w.F));
  PetscCall(VecDestroy(&w.nu));
  PetscCall(MatDestroy(&w.Jc));
  PetscCall(ContextDestroy(&w.as));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}
