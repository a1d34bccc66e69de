/* activeset.c - unilateral contact by semismooth Newton (PDAS) or
 * SNESVINEWTONRSLS (see activeset.h). */
#include "activeset_impl.h"
#include "optcheck.h"

/* c in the user's units (the summary's contact_c): lambda / c is a weighted gap */
static PetscReal CUser(const M2dProblem *pb)
{
  return pb->units.S / (pb->units.L * pb->units.U);
}

PetscReal ActiveSetDefaultC(const M2dScene *s, const M2dContact *ct)
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

static uint64_t Mix(uint64_t x)
{
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/* active mask at (u, lam); counts against `used` */
PetscErrorCode ActiveSetUpdateMask(M2dActiveSet *as)
{
  const PetscScalar *l, *g, *t, *un;
  PetscScalar       *a;
  PetscInt           lo, hi, cnt[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(as->lam, &lo, &hi));
  PetscCall(VecGetArrayRead(as->lam, &l));
  PetscCall(VecGetArrayRead(as->gm, &g));
  PetscCall(VecGetArrayRead(as->tol, &t));
  PetscCall(VecGetArrayRead(as->used, &un));
  PetscCall(VecGetArray(as->active, &a));
  for (PetscInt j = 0; j < hi - lo; j++) {
    PetscBool on;
    if (as->vi) on = (PetscBool)(PetscRealPart(l[j]) > 0);
    else on = (PetscBool)(PetscRealPart(l[j]) / as->c + PetscRealPart(g[j]) >= -PetscRealPart(t[j]));
    a[j] = on ? 1.0 : 0.0;
    cnt[0] += on;
    if (on && PetscRealPart(un[j]) == 0) cnt[1]++;
    if (!on && PetscRealPart(un[j]) != 0) cnt[2]++;
  }
  PetscCall(VecRestoreArray(as->active, &a));
  PetscCall(VecRestoreArrayRead(as->used, &un));
  PetscCall(VecRestoreArrayRead(as->tol, &t));
  PetscCall(VecRestoreArrayRead(as->gm, &g));
  PetscCall(VecRestoreArrayRead(as->lam, &l));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, cnt, 3, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)as->lam)));
  as->nactive = cnt[0];
  as->entered = cnt[1];
  as->left    = cnt[2];
  PetscFunctionReturn(0);
}

/* F_u = K u + C^T lambda - f (+ the augmented rows), F_lambda = c h max(-lambda/c, C u - r) */
PetscErrorCode ActiveSetFunction(SNES snes, Vec z, Vec F, void *ctx)
{
  M2dActiveSet *as  = (M2dActiveSet *)ctx;
  M2dKKT       *kkt = as->kkt;
  Vec           Fu, Fl;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(VecISCopy(z, kkt->isu, SCATTER_REVERSE, as->u));
  PetscCall(VecISCopy(z, kkt->isl, SCATTER_REVERSE, as->lam));
  PetscCall(MatMult(kkt->C, as->u, as->gm));
  PetscCall(VecAXPY(as->gm, -1.0, kkt->r));
  PetscCall(ActiveSetUpdateMask(as));
  PetscCall(VecDuplicate(as->u, &Fu));
  PetscCall(VecDuplicate(as->lam, &Fl));
  PetscCall(MatMult(kkt->K, as->u, Fu));
  PetscCall(MatMultAdd(kkt->Ct, as->lam, Fu, Fu));
  PetscCall(VecAXPY(Fu, -1.0, kkt->f));
  if (as->vi) { /* multiplier rows in force units: c h g~ */
    PetscCall(VecCopy(as->gm, Fl));
    PetscCall(VecScale(Fl, -as->c * as->h));
  } else {
    PetscCall(VecCopy(as->lam, Fl));
    PetscCall(VecScale(Fl, -1.0 / as->c));
    PetscCall(VecPointwiseMax(Fl, Fl, as->gm));
    PetscCall(VecScale(Fl, as->c * as->h));
    if (kkt->gamma > 0 && !as->cond) { /* augmented rows: + gamma C^T diag(active) (C u - r) */
      Vec t, t2;
      PetscCall(VecDuplicate(as->lam, &t));
      PetscCall(VecDuplicate(as->u, &t2));
      PetscCall(VecPointwiseMult(t, as->active, as->gm));
      PetscCall(MatMult(kkt->Ct, t, t2));
      PetscCall(VecAXPY(Fu, kkt->gamma, t2));
      PetscCall(VecDestroy(&t));
      PetscCall(VecDestroy(&t2));
    }
  }
  PetscCall(VecISCopy(F, kkt->isu, SCATTER_FORWARD, Fu));
  PetscCall(VecISCopy(F, kkt->isl, SCATTER_FORWARD, Fl));
  PetscCall(VecDestroy(&Fu));
  PetscCall(VecDestroy(&Fl));
  PetscFunctionReturn(0);
}

static PetscErrorCode ActiveHash(M2dActiveSet *as, uint64_t *h)
{
  const PetscScalar *a;
  PetscInt           lo, hi;
  uint64_t           loc = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(as->active, &lo, &hi));
  PetscCall(VecGetArrayRead(as->active, &a));
  for (PetscInt j = lo; j < hi; j++)
    if (PetscRealPart(a[j - lo]) != 0) loc += Mix((uint64_t)j);
  PetscCall(VecRestoreArrayRead(as->active, &a));
  PetscCallMPI(MPI_Allreduce(&loc, h, 1, MPI_UINT64_T, MPI_SUM, PetscObjectComm((PetscObject)as->active)));
  PetscFunctionReturn(0);
}

/* A set that returns to one seen two or more steps ago is a cycle: c is raised
 * tenfold (at most max_cycles times) and the mask recomputed. */
static PetscErrorCode BreakCycle(M2dActiveSet *as, MPI_Comm comm)
{
  M2dSetHistory *hi = &as->hist;
  uint64_t       h;

  PetscFunctionBeginUser;
  PetscCall(ActiveHash(as, &h));
  /* (an unchanged set is not a cycle: the last entry is the previous step's set) */
  for (PetscInt k = 0; k + 1 < hi->n && !(hi->hash[hi->n - 1] == h && hi->count[hi->n - 1] == as->nactive); k++)
    if (hi->hash[k] == h && hi->count[k] == as->nactive) {
      if (++hi->cycles > hi->max_cycles) {
        hi->failed = PETSC_TRUE;
        break;
      }
      PetscCall(PetscPrintf(comm, "  active set cycling at step %" PetscInt_FMT " (back to the set of step %" PetscInt_FMT "): c raised from %g to %g\n", as->step, k, (double)(as->c * CUser(as->pb)), (double)(10 * as->c * CUser(as->pb))));
      as->c *= 10;
      PetscCall(ActiveSetUpdateMask(as));
      PetscCall(ActiveHash(as, &h));
      break;
    }
  if (hi->n < M2D_MAX_HISTORY) {
    hi->hash[hi->n]    = h;
    hi->count[hi->n++] = as->nactive;
  }
  PetscFunctionReturn(0);
}

/* The set of the next step: the current mask, unless it cycles. A set that
 * leaves a body free (no support, no closed contact node against one of its
 * rigid motions) makes the step singular: the contact has opened and nothing
 * holds the body, which is the answer, stated in one line. */
PetscErrorCode ActiveSetChooseSet(M2dActiveSet *as, MPI_Comm comm)
{
  M2dProblem        *pb = as->pb;
  const PetscScalar *a;
  char               when[128];

  PetscFunctionBeginUser;
  PetscCall(BreakCycle(as, comm));
  PetscCall(VecCopy(as->active, as->used));
  PetscCall(VecScatterBegin(as->toall, as->active, as->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(as->toall, as->active, as->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(PetscSNPrintf(when, sizeof(when), "once the contact opens (active-set step %" PetscInt_FMT ": %" PetscInt_FMT " of %" PetscInt_FMT " contact nodes closed)", as->step, as->nactive, as->kkt->nlam));
  PetscCall(VecGetArrayRead(as->all, &a));
  PetscCall(M2dSupportsCheck(&pb->supports, comm, &pb->s, &pb->contact, a, when));
  PetscCall(VecRestoreArrayRead(as->all, &a));
  as->step++;
  PetscFunctionReturn(0);
}

PetscErrorCode ActiveSetJacobian(SNES snes, Vec z, Mat J, Mat P, void *ctx)
{
  M2dActiveSet *as = (M2dActiveSet *)ctx;

  PetscFunctionBeginUser;
  (void)z;
  (void)P;
  if (as->vi) PetscFunctionReturn(0); /* constant Jacobian, built once */
  PetscCall(ActiveSetChooseSet(as, PetscObjectComm((PetscObject)snes)));
  if (as->cond) PetscCall(CondensedJacobian(as->cond, as->active, as->c, as->h, J));
  else PetscCall(KKTSetActive(as->kkt, as->active, as->c, as->c * as->h));
  if (as->iter) PetscCall(M2dIterativeSetActive(as->iter, as->active, as->c, as->c * as->h));
  PetscFunctionReturn(0);
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
  for (PetscInt e = 0; e < ct->nm.nedge; e++) as->h += ct->nm.len[e];
  as->h /= PetscMax(1, ct->nm.nedge);
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
  PetscInt           lo, hi, how = as->pb->s.contact_initial;
  PetscReal          gmin = PETSC_MAX_REAL, L;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(z));
  PetscCall(VecZeroEntries(as->lam));
  if (how == 0 && !as->pb->warm && !as->vi) PetscFunctionReturn(0); /* VI: at least the closest nodes (below) */
  L = PetscSqrtReal(PetscSqr(ct->m.hi[0] - ct->m.lo[0]) + PetscSqr(ct->m.hi[1] - ct->m.lo[1])) * as->pb->units.L / as->pb->units.U;
  PetscCall(VecGetOwnershipRange(as->kkt->r, &lo, &hi));
  PetscCall(VecGetArrayRead(as->kkt->r, &r));
  for (PetscInt j = lo; j < hi; j++) gmin = PetscMin(gmin, PetscRealPart(r[j - lo]) / ct->R.w[j]);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &gmin, 1, MPIU_REAL, MPIU_MIN, PetscObjectComm((PetscObject)z)));
  PetscCall(VecGetArray(as->lam, &l));
  for (PetscInt j = lo; j < hi; j++) {
    PetscReal g = PetscRealPart(r[j - lo]);
    PetscBool on = as->pb->warm ? as->pb->warm[j] : (PetscBool)(how == 2 || g / ct->R.w[j] <= gmin + 1e-6 * L);
    /* the VI solver fixes a multiplier at its bound 0 while the gap is open:
     * a positive start keeps the first set's rows (a body held only by the
     * contact would otherwise be free in the first step) */
    l[j - lo] = on ? as->c * PetscMax(g, as->vi ? 1e-6 * L * ct->R.w[j] : 0) : 0;
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
  PC                 pc;
  PetscBool          fs;

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
  PetscCheck(!as->hist.failed, comm, PETSC_ERR_NOT_CONVERGED, "active set keeps cycling (%" PetscInt_FMT " cycles after raising c to %g): no solution found (check the load direction and the supports)", as->hist.cycles, (double)(as->c * CUser(as->pb)));
  PetscCheck(reason != SNES_DIVERGED_MAX_IT, comm, PETSC_ERR_NOT_CONVERGED, "active set did not settle in %" PetscInt_FMT " steps (-snes_max_it)", steps);
  if (kr < 0) {
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &fs));
    PetscCheck(!(fs && as->kkt->gamma == 0), comm, PETSC_ERR_NOT_CONVERGED, "linear solve failed (%s): the fieldsplit K block cannot be factored when a body is held only by contact; add -kkt_augment 1 or use the monolithic solver (options/kkt_mumps.opts)", KSPConvergedReasons[kr]);
    SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "linear solve in active-set step %" PetscInt_FMT " failed (%s): is every body held (by supports, or by contact)?", steps, KSPConvergedReasons[kr]);
  }
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
  PetscCall(M2dOptionsCheckUnused(comm)); /* the solvers are configured: an option nobody read is a typo */
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
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)as->lam), "active set: %" PetscInt_FMT " Krylov solves, %" PetscInt_FMT " iterations in all, at most %" PetscInt_FMT " in one, %" PetscInt_FMT " preconditioner set-ups\n", ii.solves, ii.its_total, ii.its_max, ii.setups));
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
