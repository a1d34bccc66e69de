/* activeset_paths.c - how each solver path takes the active-set loop's steps
 * (activeset_impl.h's table): the condensed path's steps on the multipliers
 * (condensed.h), the full path's KKT solves, the iterative path's inexact
 * steps (iterative.h), the VI solver's bounds. */
#include "activeset_impl.h"

/* the step's linear solve, a shell PC (context: the active set) behind
 * KSPPREONLY: the condensed path's dense LU of its Jacobian, factored at
 * set-up, or the iterative path's solve (set up by the loop's Jacobian) */
static PetscErrorCode StepPCSetUp(PC pc)
{
  M2dActiveSet *as;
  Mat           P;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &as));
  if (as->cond) {
    PetscCall(PCGetOperators(pc, NULL, &P));
    PetscCall(CondensedJacobianFactor(as->cond, P, as->partner, as->used, as->usedcoef, as->c, as->h));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode IterativeStep(M2dActiveSet *as, Vec b, Vec y);

static PetscErrorCode StepPCApply(PC pc, Vec b, Vec y)
{
  M2dActiveSet *as;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &as));
  if (as->cond) PetscCall(CondensedJacobianSolve(as->cond, b, y));
  else PetscCall(IterativeStep(as, b, y));
  PetscFunctionReturn(0);
}

/* the SNES's KSP: the step PC alone, `name` saying what it does (-snes_view) */
static PetscErrorCode SetStepPC(M2dActiveSet *as, const char *name)
{
  KSP ksp;
  PC  pc;

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(as->snes, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, as));
  PetscCall(PCShellSetSetUp(pc, StepPCSetUp));
  PetscCall(PCShellSetApply(pc, StepPCApply));
  PetscCall(PCShellSetName(pc, name));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------- condensed */

/* factor once; the unknown is nu, its dense Jacobian solved by LAPACK on every rank */
static PetscErrorCode CondensedSetup(M2dActiveSet *as, M2dActiveSetInfo *info)
{
  M2dKKT          *kkt = as->kkt;
  M2dCondensedInfo ci;
  PetscInt         n, N;

  PetscFunctionBeginUser;
  PetscCheck(kkt->aij && kkt->gamma > 0, PetscObjectComm((PetscObject)as->snes), PETSC_ERR_USER_INPUT, "option -kkt_path condensed: needs -kkt_mat aij (use -kkt_path full for nest/fieldsplit)");
  PetscCall(CondensedCreateFromKKT(kkt, &as->pb->s, &as->cond));
  PetscCall(SetStepPC(as, "dense LU of the condensed Jacobian (LAPACK, every rank)"));
  PetscCall(CondensedGetInfo(as->cond, &ci));
  info->factor_time        = ci.factor_time;
  info->factor_flops       = ci.flops_sum;
  info->factor_flops_max   = ci.flops_max;
  info->interface_unknowns = ci.interface_unknowns;
  PetscCall(VecDuplicate(kkt->r, &as->cu));
  PetscCall(VecGetLocalSize(kkt->r, &n));
  PetscCall(VecGetSize(kkt->r, &N));
  PetscCall(MatCreateDense(PetscObjectComm((PetscObject)kkt->r), n, n, N, N, NULL, &as->J));
  PetscFunctionReturn(0);
}

/* the factorization condensed the first step's load; a later one's anew */
static PetscErrorCode CondensedLoad(M2dActiveSet *as)
{
  PetscFunctionBeginUser;
  if (as->started) PetscCall(CondensedSetLoad(as->cond, as->kkt->f));
  PetscFunctionReturn(0);
}

/* C u = w + S0 nu and lambda = nu + g C u (condensed.h): the u rows hold for every nu */
static PetscErrorCode CondensedEvaluate(M2dActiveSet *as, Vec nu)
{
  const PetscScalar *v, *cu, *r;
  PetscScalar       *l, *g;
  PetscInt           n;
  PetscReal          gam = as->kkt->gamma;

  PetscFunctionBeginUser;
  PetscCall(CondensedGaps(as->cond, nu, as->cu));
  PetscCall(VecGetLocalSize(nu, &n));
  PetscCall(VecGetArrayRead(nu, &v));
  PetscCall(VecGetArrayRead(as->cu, &cu));
  PetscCall(VecGetArrayRead(as->kkt->r, &r));
  PetscCall(VecGetArrayWrite(as->lam, &l));
  PetscCall(VecGetArrayWrite(as->gm, &g));
  for (PetscInt j = 0; j < n; j++) {
    g[j] = cu[j] - r[j];
    l[j] = v[j] + gam * cu[j];
  }
  PetscCall(VecRestoreArrayWrite(as->gm, &g));
  PetscCall(VecRestoreArrayWrite(as->lam, &l));
  PetscCall(VecRestoreArrayRead(as->kkt->r, &r));
  PetscCall(VecRestoreArrayRead(as->cu, &cu));
  PetscCall(VecRestoreArrayRead(nu, &v));
  PetscFunctionReturn(0);
}

static PetscErrorCode CondensedJac(M2dActiveSet *as)
{
  PetscFunctionBeginUser;
  PetscCall(CondensedJacobian(as->cond, as->active, as->c, as->h, as->J));
  PetscFunctionReturn(0);
}

/* lambda from the last residual evaluation, u by one substitution */
static PetscErrorCode CondensedFinish(M2dActiveSet *as, Vec nu, Vec u, Vec lam)
{
  PetscFunctionBeginUser;
  PetscCall(CondensedRecover(as->cond, PETSC_TRUE, nu, u));
  PetscCall(VecCopy(as->lam, lam));
  PetscFunctionReturn(0);
}

static PetscErrorCode CondensedDestroyPath(M2dActiveSet *as, M2dActiveSetInfo *keep)
{
  PetscFunctionBeginUser;
  if (keep) { /* handed over */
    keep->factor = as->cond;
    as->cond     = NULL;
  }
  PetscCall(CondensedDestroy(&as->cond));
  PetscCall(VecDestroy(&as->cu));
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------- full, iterative, VI */

/* the KKT operator (kkt.h) is the step's matrix */
static PetscErrorCode KKTLayout(M2dActiveSet *as)
{
  PetscFunctionBeginUser;
  as->J = as->kkt->A;
  PetscCall(PetscObjectReference((PetscObject)as->J));
  PetscFunctionReturn(0);
}

/* the full path's KSP and PC from the options (MUMPS LU by default) */
static PetscErrorCode FullSetup(M2dActiveSet *as, M2dActiveSetInfo *info)
{
  KSP ksp;

  PetscFunctionBeginUser;
  (void)info;
  PetscCall(KKTLayout(as));
  PetscCall(SNESGetKSP(as->snes, &ksp));
  PetscCall(M2dOrderingSetupKSP(ksp, as->pb->s.kkt_ordering, NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode NoLoad(M2dActiveSet *as)
{
  PetscFunctionBeginUser;
  (void)as;
  PetscFunctionReturn(0);
}

/* u and lambda of z; C u - r */
static PetscErrorCode KKTEvaluate(M2dActiveSet *as, Vec z)
{
  M2dKKT *kkt = as->kkt;

  PetscFunctionBeginUser;
  PetscCall(VecISCopy(z, kkt->isu, SCATTER_REVERSE, as->u));
  PetscCall(VecISCopy(z, kkt->isl, SCATTER_REVERSE, as->lam));
  PetscCall(MatMult(kkt->C, as->u, as->gm));
  PetscCall(VecAXPY(as->gm, -1.0, kkt->r));
  PetscFunctionReturn(0);
}

/* F_u = K u + C^T lambda - f (+ the augmented rows gamma C^T diag(active) (C u - r)) */
static PetscErrorCode KKTResidualU(M2dActiveSet *as, Vec z, Vec F)
{
  M2dKKT *kkt = as->kkt;
  Vec     Fu;

  PetscFunctionBeginUser;
  (void)z;
  PetscCall(VecDuplicate(as->u, &Fu));
  PetscCall(MatMult(kkt->K, as->u, Fu));
  PetscCall(MatMultAdd(kkt->Ct, as->lam, Fu, Fu));
  PetscCall(VecAXPY(Fu, -1.0, kkt->f));
  if (kkt->gamma > 0) { /* (not with the VI solver's bounds: VISetup) */
    Vec t, t2;
    PetscCall(VecDuplicate(as->lam, &t));
    PetscCall(VecDuplicate(as->u, &t2));
    PetscCall(VecPointwiseMult(t, as->active, as->gm));
    PetscCall(MatMult(kkt->Ct, t, t2));
    PetscCall(VecAXPY(Fu, kkt->gamma, t2));
    PetscCall(VecDestroy(&t));
    PetscCall(VecDestroy(&t2));
  }
  PetscCall(VecISCopy(F, kkt->isu, SCATTER_FORWARD, Fu));
  PetscCall(VecDestroy(&Fu));
  PetscFunctionReturn(0);
}

static PetscErrorCode KKTJac(M2dActiveSet *as)
{
  PetscFunctionBeginUser;
  PetscCall(KKTSetActive(as->kkt, as->active, as->partner ? as->slip : NULL, as->c, as->c * as->h));
  if (as->iter) PetscCall(M2dIterativeSetActive(as->iter, as->active, as->c, as->c * as->h));
  PetscFunctionReturn(0);
}

static PetscErrorCode KKTFinish(M2dActiveSet *as, Vec z, Vec u, Vec lam)
{
  PetscFunctionBeginUser;
  PetscCall(VecISCopy(z, as->kkt->isu, SCATTER_REVERSE, u));
  PetscCall(VecISCopy(z, as->kkt->isl, SCATTER_REVERSE, lam));
  PetscFunctionReturn(0);
}

static PetscErrorCode KKTDestroyPath(M2dActiveSet *as, M2dActiveSetInfo *keep)
{
  PetscFunctionBeginUser;
  (void)keep;
  PetscCall(M2dIterativeDestroy(&as->iter));
  PetscCall(VecDestroy(&as->du));
  PetscCall(VecDestroy(&as->cdu));
  PetscCall(VecDestroy(&as->m[0]));
  PetscCall(VecDestroy(&as->m[1]));
  PetscCall(VecDestroy(&as->tolv));
  PetscFunctionReturn(0);
}

/* the full path's KSP, from the options: what went wrong in it */
static PetscErrorCode KKTFailed(M2dActiveSet *as, PetscInt steps)
{
  KSP                ksp;
  KSPConvergedReason kr;
  char               what[64];

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(as->snes, &ksp));
  PetscCall(KSPGetConvergedReason(ksp, &kr));
  PetscCall(KKTFieldsplitCheck(ksp, as->kkt->gamma));
  if (kr < 0) PetscCall(PetscSNPrintf(what, sizeof(what), "linear solve in active-set step %" PetscInt_FMT " failed", steps));
  else PetscCall(PetscSNPrintf(what, sizeof(what), "active set %s after %" PetscInt_FMT " steps", as->hist.failed ? "keeps cycling" : "did not settle", steps));
  PetscCall(KKTKrylovCheck(ksp, what, PETSC_FALSE));
  PetscFunctionReturn(0);
}

/* m = the complementarity test at the step's next iterate z - y (lambda/c + g
 * + tie tolerance: the node is active where m >= 0), from lambda and
 * g = C u - r at z (as->lam, as->gm) */
static PetscErrorCode NextTest(M2dActiveSet *as, Vec y, Vec m)
{
  M2dKKT *kkt = as->kkt;

  PetscFunctionBeginUser;
  PetscCall(VecISCopy(y, kkt->isu, SCATTER_REVERSE, as->du));
  PetscCall(VecISCopy(y, kkt->isl, SCATTER_REVERSE, m));
  PetscCall(MatMult(kkt->C, as->du, as->cdu));
  PetscCall(VecAXPBY(m, 1.0 / as->c, -1.0 / as->c, as->lam)); /* (lambda - dl) / c */
  PetscCall(VecAXPY(m, 1.0, as->gm));
  PetscCall(VecAXPY(m, -1.0, as->cdu));
  PetscCall(VecAXPY(m, 1.0, as->tolv));
  PetscFunctionReturn(0);
}

/* From the tests m1 and m2 of two solves of one step, the second with a
 * residual M2D_REFINE times the first's: *sure when every node's test m2 is
 * farther from 0 than M2D_SURE times it moved from m1 (CG's error in m2 is
 * about M2D_REFINE / (1 - M2D_REFINE) of that move, ~1/9: a margin of 18
 * times it cannot flip the node), *same when the set m2 gives is the step's
 * own (the set has settled). Collective. */
#define M2D_REFINE 0.1 /* each refinement of a step: this much smaller a residual */
#define M2D_SURE   2.0
static PetscErrorCode NextSet(M2dActiveSet *as, Vec m1, Vec m2, PetscBool *sure, PetscBool *same)
{
  const PetscScalar *a, *b;
  PetscInt           n, lo, flags[2] = {1, 1};

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(m1, &n));
  PetscCall(VecGetOwnershipRange(m1, &lo, NULL));
  PetscCall(VecGetArrayRead(m1, &a));
  PetscCall(VecGetArrayRead(m2, &b));
  for (PetscInt j = 0; j < n; j++) {
    PetscReal x = PetscRealPart(b[j]);
    if (!(PetscAbsReal(x) > M2D_SURE * PetscAbsReal(x - PetscRealPart(a[j])))) flags[0] = 0;
    if ((x >= 0) != (as->used[lo + j] != 0)) flags[1] = 0;
  }
  PetscCall(VecRestoreArrayRead(m2, &b));
  PetscCall(VecRestoreArrayRead(m1, &a));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, flags, 2, MPIU_INT, MPI_MIN, PetscObjectComm((PetscObject)m1)));
  *sure = (PetscBool)flags[0];
  *same = (PetscBool)flags[1];
  PetscFunctionReturn(0);
}

/* Iterative path: one step, inexact while its set is not the last one. CG
 * stops at -iterative_inexact of the step's right-hand side. The set that
 * solve tells is taken as the next one when it differs from the step's own
 * and holds every body: a node it got wrong is put right by the next step,
 * whose solve tells it again (inexact Newton; the sets visited may differ
 * from the complete solves', their end does not): from a cold start only
 * (IterativeSetup), and until |F| rises or the sets cycle (activeset.c).
 * Otherwise the step is completed to -iterative_ksp_rtol: the last step's
 * answer is a complete solve's, and a set that would free a body is judged
 * on a complete solve. With -iterative_prove (or once the sets have cycled)
 * CG goes on instead by factors of M2D_REFINE; once the next set is sure
 * (NextSet: the set an exact solve gives), a step whose next set is another
 * stops there, and a step whose set has settled (the last one) is
 * completed. A set never sure (a node on the boundary to round-off) ends
 * complete too. */
static PetscErrorCode IterativeStep(M2dActiveSet *as, Vec b, Vec y)
{
  M2dIterativeInfo ii;
  PetscReal        tol;
  PetscBool        sure = PETSC_FALSE, same = PETSC_FALSE, held;

  PetscFunctionBeginUser;
  PetscCall(M2dIterativeGetInfo(as->iter, &ii));
  tol = PetscMax(ii.inexact, ii.rtol);
  /* a warm start's first step: complete. Its set is the previous mesh's, near
   * the answer, and the step starts from u = 0, so the tests sit near their
   * switch while CG's error is still of the whole load: two refinements
   * agreeing (NextSet) did not make the set sure there (the adaptive punch:
   * 66 of 125 nodes dropped, 12 steps where complete solves take 3) */
  if (as->pb->warm && as->step == 1) tol = ii.rtol;
  PetscCall(M2dIterativeSolve(as->iter, b, tol, y));
  if (tol <= ii.rtol) PetscFunctionReturn(0);
  PetscCall(NextTest(as, y, as->m[0]));
  if (!as->proving) {
    PetscCall(NextSet(as, as->m[0], as->m[0], &sure, &same)); /* only *same is wanted */
    if (!same) PetscCall(ActiveSetHeldBy(as, as->m[0], &held));
    if (!same && held) as->unproven++;
    else PetscCall(M2dIterativeRefine(as->iter, 0, y)); /* maybe the last step, or a set that frees a body: complete, the next test exact */
    PetscFunctionReturn(0);
  }
  for (PetscInt k = 1; !sure && tol > ii.rtol; k = 1 - k) {
    tol = PetscMax(M2D_REFINE * tol, ii.rtol);
    PetscCall(M2dIterativeRefine(as->iter, tol, y));
    PetscCall(NextTest(as, y, as->m[k]));
    PetscCall(NextSet(as, as->m[1 - k], as->m[k], &sure, &same));
  }
  if (same && tol > ii.rtol) PetscCall(M2dIterativeRefine(as->iter, 0, y));
  PetscFunctionReturn(0);
}

/* each step's KKT solve by M2dIterativeSolve (the step PC), set up by the loop's Jacobian */
static PetscErrorCode IterativeSetup(M2dActiveSet *as, M2dActiveSetInfo *info)
{
  M2dIterativeInfo ii;
  PetscInt         lo, hi;
  PetscScalar     *t;

  PetscFunctionBeginUser;
  (void)info;
  PetscCall(KKTLayout(as));
  PetscCall(M2dIterativeCreate(as->kkt, &as->pb->Rkkt, as->pb->ndir, as->pb->drows, &as->iter));
  PetscCall(VecDuplicate(as->u, &as->du));
  PetscCall(VecDuplicate(as->lam, &as->cdu));
  PetscCall(VecDuplicate(as->lam, &as->m[0]));
  PetscCall(VecDuplicate(as->lam, &as->m[1]));
  PetscCall(VecDuplicate(as->lam, &as->tolv));
  PetscCall(VecGetOwnershipRange(as->tolv, &lo, &hi));
  PetscCall(VecGetArrayWrite(as->tolv, &t));
  for (PetscInt j = lo; j < hi; j++) t[j - lo] = as->tol[j];
  PetscCall(VecRestoreArrayWrite(as->tolv, &t));
  /* -iterative_prove; or a start from the previous mesh's set: it is near the
   * answer, where an inexact solve's set is the least to be trusted (many
   * nodes near the switch: the adaptive punch wandered for 50 steps) */
  PetscCall(M2dIterativeGetInfo(as->iter, &ii));
  as->proving = (PetscBool)(ii.prove || as->pb->warm != NULL);
  PetscCall(SetStepPC(as, "multipliers eliminated, CG + AMG in u (iterative.h)"));
  PetscFunctionReturn(0);
}

/* the sets back to step k's: an inexact step's set may have been wrong, so
 * the sets are proven from here before c is raised */
static PetscErrorCode IterativeCycled(M2dActiveSet *as, PetscInt k, PetscBool *answered)
{
  PetscFunctionBeginUser;
  if (as->proving) PetscFunctionReturn(0);
  as->proving = *answered = PETSC_TRUE;
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)as->snes), "  active set back to the set of step %" PetscInt_FMT " at step %" PetscInt_FMT ": each step's set proven from here\n", k, as->step));
  PetscFunctionReturn(0);
}

/* sets taken from inexact solves that send |F| up: proven from here */
static PetscErrorCode IterativeWatch(M2dActiveSet *as, PetscInt it, PetscReal fnorm)
{
  PetscFunctionBeginUser;
  if (as->proving || it == 0) PetscFunctionReturn(0);
  if (it > 1 && fnorm > M2D_RISE * as->fbest) {
    as->proving = PETSC_TRUE;
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)as->snes), "  active set step %2" PetscInt_FMT ": |F| %.3e, %.0f times the least since step 1: each step's set proven from here\n", it, (double)fnorm, (double)(fnorm / as->fbest)));
  }
  as->fbest = it == 1 ? fnorm : PetscMin(as->fbest, fnorm);
  PetscFunctionReturn(0);
}

static PetscErrorCode IterativeReport(M2dActiveSet *as, M2dActiveSetInfo *info)
{
  M2dIterativeInfo ii;

  PetscFunctionBeginUser;
  PetscCall(M2dIterativeGetInfo(as->iter, &ii));
  info->ksp_its_max   = ii.its_max;
  info->ksp_its_total = ii.its_total;
  info->pc_setups     = ii.setups;
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)as->snes), "active set: %" PetscInt_FMT " Krylov solves, %" PetscInt_FMT " iterations in all, at most %" PetscInt_FMT " in one, %" PetscInt_FMT " preconditioner set-ups, contact zone of %" PetscInt_FMT " unknowns, %" PetscInt_FMT " steps on an inexact solve's set\n", ii.solves, ii.its_total, ii.its_max, ii.setups, ii.zone_dofs, as->unproven));
  PetscFunctionReturn(0);
}

/* vinewtonrsls: Jacobian [K C^T; -C 0] (all rows, multiplier rows negated), lambda >= 0 */
static PetscErrorCode VISetup(M2dActiveSet *as, M2dActiveSetInfo *info)
{
  M2dKKT  *kkt  = as->kkt;
  MPI_Comm comm = PetscObjectComm((PetscObject)as->snes);
  Vec      lower, upper, sign, l;

  PetscFunctionBeginUser;
  PetscCheck(kkt->aij, comm, PETSC_ERR_USER_INPUT, "option -snes_type vinewtonrsls: needs the monolithic matrix (-kkt_mat aij)");
  PetscCheck(kkt->gamma == 0, comm, PETSC_ERR_USER_INPUT, "option -snes_type vinewtonrsls: does not combine with -kkt_augment");
  PetscCall(FullSetup(as, info));
  PetscCall(VecSet(as->active, 1.0));
  PetscCall(KKTSetActive(kkt, as->active, NULL, as->c, as->c * as->h));
  PetscCall(VecDuplicate(as->x, &sign));
  PetscCall(VecDuplicate(as->lam, &l));
  PetscCall(VecSet(sign, 1.0));
  PetscCall(VecSet(l, -1.0));
  PetscCall(VecISCopy(sign, kkt->isl, SCATTER_FORWARD, l));
  PetscCall(MatDiagonalScale(kkt->A, sign, NULL));
  PetscCall(VecDuplicate(as->x, &lower));
  PetscCall(VecDuplicate(as->x, &upper));
  PetscCall(VecSet(upper, PETSC_INFINITY));
  PetscCall(VecSet(lower, PETSC_NINFINITY));
  PetscCall(VecZeroEntries(l));
  PetscCall(VecISCopy(lower, kkt->isl, SCATTER_FORWARD, l));
  PetscCall(SNESVISetVariableBounds(as->snes, lower, upper));
  PetscCall(VecDestroy(&lower));
  PetscCall(VecDestroy(&upper));
  PetscCall(VecDestroy(&sign));
  PetscCall(VecDestroy(&l));
  PetscFunctionReturn(0);
}

/* The VI solver starts from lambda = c max(g~0, 1e-6 of the mortar surface's
 * size) on the initial rules' closed rows: it fixes a multiplier at its bound
 * 0 while the gap is open, and a positive start keeps the first set's rows (a
 * body held only by the contact would otherwise be free in the first step) */
static PetscErrorCode VILoad(M2dActiveSet *as)
{
  const M2dContact  *ct = &as->pb->contact;
  const PetscScalar *r;
  PetscScalar       *l;
  PetscInt           lo, hi;

  PetscFunctionBeginUser;
  if (as->started) PetscFunctionReturn(0);
  PetscCall(VecGetOwnershipRange(as->kkt->r, &lo, &hi));
  PetscCall(VecGetArrayRead(as->kkt->r, &r));
  PetscCall(VecGetArrayWrite(as->lam, &l));
  for (PetscInt j = lo; j < hi; j++) {
    const M2dSurface *m = &ct->pair[ct->rowpair[j]].m;
    PetscReal         L = PetscSqrtReal(PetscSqr(m->hi[0] - m->lo[0]) + PetscSqr(m->hi[1] - m->lo[1])) * as->pb->units.L / as->pb->units.U;
    l[j - lo]           = as->used[j] != 0 ? as->c * PetscMax(PetscRealPart(r[j - lo]), 1e-6 * L * ct->R.w[j]) : 0;
  }
  PetscCall(VecRestoreArrayWrite(as->lam, &l));
  PetscCall(VecRestoreArrayRead(as->kkt->r, &r));
  PetscCall(VecISCopy(as->x, as->kkt->isl, SCATTER_FORWARD, as->lam));
  PetscFunctionReturn(0);
}

#define PDAS "semismooth Newton (primal-dual active set), "
const M2dPathOps M2dPathCondensed = {.name = PDAS "K factored once, steps on the multipliers (condensed)", .lambda_only = PETSC_TRUE, .setup = CondensedSetup, .load = CondensedLoad, .evaluate = CondensedEvaluate, .jacobian = CondensedJac, .finish = CondensedFinish, .destroy = CondensedDestroyPath};
const M2dPathOps M2dPathFull      = {.name = PDAS "KKT refactored each step (full)", .setup = FullSetup, .load = NoLoad, .evaluate = KKTEvaluate, .residual_u = KKTResidualU, .jacobian = KKTJac, .finish = KKTFinish, .failed = KKTFailed, .destroy = KKTDestroyPath};
const M2dPathOps M2dPathIterative = {.name = PDAS "multipliers eliminated, CG + AMG in u (iterative)", .setup = IterativeSetup, .load = NoLoad, .evaluate = KKTEvaluate, .residual_u = KKTResidualU, .jacobian = KKTJac, .cycled = IterativeCycled, .watch = IterativeWatch, .finish = KKTFinish, .report = IterativeReport, .destroy = KKTDestroyPath};
const M2dPathOps M2dPathVI        = {.name = "SNESVINEWTONRSLS, KKT refactored each step (full)", .bounds_by_solver = PETSC_TRUE, .setup = VISetup, .load = VILoad, .evaluate = KKTEvaluate, .residual_u = KKTResidualU, .finish = KKTFinish, .failed = KKTFailed, .destroy = KKTDestroyPath};
