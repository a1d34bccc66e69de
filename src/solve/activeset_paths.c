/* activeset_paths.c - what each solver path adds to the active-set iteration
 * (see activeset_paths.h): the condensed path's iteration on the multipliers
 * (condensed.h), the iterative path's solve of each step (iterative.h), the
 * VI solver's bounds. */
#include "activeset_paths.h"

/* condensed path: F(nu) = c h max(-lambda/c, C u - r) with C u = w + S0 nu and
 * lambda = nu + g C u (condensed.h); the u rows hold for every nu */
static PetscErrorCode CondensedFunction(SNES snes, Vec nu, Vec F, void *ctx)
{
  M2dActiveSet      *as = (M2dActiveSet *)ctx;
  const PetscScalar *v, *cu, *r;
  PetscScalar       *l, *g, *f;
  PetscInt           n;
  PetscReal          gam = as->kkt->gamma;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(CondensedGaps(as->cond, nu, as->cu));
  PetscCall(VecGetLocalSize(nu, &n));
  PetscCall(VecGetArrayRead(nu, &v));
  PetscCall(VecGetArrayRead(as->cu, &cu));
  PetscCall(VecGetArrayRead(as->kkt->r, &r));
  PetscCall(VecGetArray(as->lam, &l));
  PetscCall(VecGetArray(as->gm, &g));
  for (PetscInt j = 0; j < n; j++) {
    g[j] = cu[j] - r[j];
    l[j] = v[j] + gam * cu[j];
  }
  PetscCall(VecRestoreArray(as->gm, &g));
  PetscCall(VecRestoreArray(as->lam, &l));
  PetscCall(VecRestoreArrayRead(as->kkt->r, &r));
  PetscCall(VecRestoreArrayRead(as->cu, &cu));
  PetscCall(VecRestoreArrayRead(nu, &v));
  PetscCall(ActiveSetUpdateMask(as));
  PetscCall(VecGetArrayRead(as->lam, (const PetscScalar **)&l));
  PetscCall(VecGetArrayRead(as->gm, (const PetscScalar **)&g));
  PetscCall(VecGetArray(F, &f));
  for (PetscInt j = 0; j < n; j++) f[j] = as->c * as->h * PetscMax(-PetscRealPart(l[j]) / as->c, PetscRealPart(g[j]));
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(VecRestoreArrayRead(as->gm, (const PetscScalar **)&g));
  PetscCall(VecRestoreArrayRead(as->lam, (const PetscScalar **)&l));
  PetscFunctionReturn(0);
}

/* Condensed path: the first step as the full path takes it - the set of
 * (u = 0, lambda0) - solved directly: nu0 = -J^-1 F0, F0 the residual of that
 * set's linear piece at nu = 0, where C u(0) = w. The SNES starts from nu0. */
PetscErrorCode ActiveSetCondensedStart(SNES snes, M2dActiveSet *as, Vec z0, Vec *nu, Mat *J)
{
  M2dKKT            *kkt = as->kkt;
  Vec                F0, F;
  PetscInt           n, N;
  const PetscScalar *w, *r, *a;
  PetscScalar       *f;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(kkt->r, &as->cu));
  PetscCall(VecDuplicate(kkt->r, nu));
  PetscCall(VecZeroEntries(*nu));
  PetscCall(CondensedGaps(as->cond, *nu, as->cu)); /* w = C u(0) */
  PetscCall(VecDuplicate(kkt->r, &F0));
  PetscCall(VecGetLocalSize(kkt->r, &n));
  PetscCall(VecGetSize(kkt->r, &N));
  PetscCall(MatCreateDense(PetscObjectComm((PetscObject)kkt->r), n, n, N, N, NULL, J));
  /* the full path's start z0 = (0, lambda0): its residual sets the first mask and
   * the norm the relative tolerance refers to */
  PetscCall(VecDuplicate(z0, &F));
  PetscCall(ActiveSetFunction(snes, z0, F, as));
  PetscCall(VecNorm(F, NORM_2, &as->fnorm0));
  PetscCall(VecDestroy(&F));
  PetscCall(ActiveSetChooseSet(as, PetscObjectComm((PetscObject)snes)));
  PetscCall(CondensedJacobian(as->cond, as->active, as->c, as->h, *J));
  PetscCall(VecGetArrayRead(as->cu, &w));
  PetscCall(VecGetArrayRead(kkt->r, &r));
  PetscCall(VecGetArrayRead(as->active, &a));
  PetscCall(VecGetArray(F0, &f));
  for (PetscInt j = 0; j < n; j++) f[j] = PetscRealPart(a[j]) != 0 ? -as->c * as->h * (w[j] - r[j]) : as->h * kkt->gamma * w[j];
  PetscCall(VecRestoreArray(F0, &f));
  PetscCall(VecRestoreArrayRead(as->active, &a));
  PetscCall(VecRestoreArrayRead(kkt->r, &r));
  PetscCall(VecRestoreArrayRead(as->cu, &w));
  PetscCall(CondensedJacobianFactor(as->cond, *J));
  PetscCall(CondensedJacobianSolve(as->cond, F0, *nu));
  PetscCall(VecDestroy(&F0));
  PetscCall(VecDuplicate(kkt->r, &F));
  PetscCall(SNESSetFunction(snes, F, CondensedFunction, as));
  PetscCall(VecDestroy(&F));
  PetscCall(SNESSetJacobian(snes, *J, *J, ActiveSetJacobian, as));
  PetscFunctionReturn(0);
}

/* the step's linear solve, a shell PC (context: the active set) behind
 * KSPPREONLY: the condensed path's dense LU of its Jacobian, factored at set-up,
 * or the iterative path's solve (set up by ActiveSetJacobian) */
static PetscErrorCode StepPCSetUp(PC pc)
{
  M2dActiveSet *as;
  Mat           P;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &as));
  if (as->cond) {
    PetscCall(PCGetOperators(pc, NULL, &P));
    PetscCall(CondensedJacobianFactor(as->cond, P));
  }
  PetscFunctionReturn(0);
}

/* m = the complementarity test at the step's next iterate z - y (lambda/c + g
 * + tie tolerance: the node is active where m >= 0, ActiveSetUpdateMask),
 * from lambda and g = C u - r at z (as->lam, as->gm) */
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
  PetscCall(VecAXPY(m, 1.0, as->tol));
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
  const PetscScalar *a, *b, *used;
  PetscInt           n, flags[2] = {1, 1};

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(m1, &n));
  PetscCall(VecGetArrayRead(m1, &a));
  PetscCall(VecGetArrayRead(m2, &b));
  PetscCall(VecGetArrayRead(as->used, &used));
  for (PetscInt j = 0; j < n; j++) {
    PetscReal x = PetscRealPart(b[j]);
    if (!(PetscAbsReal(x) > M2D_SURE * PetscAbsReal(x - PetscRealPart(a[j])))) flags[0] = 0;
    if ((x >= 0) != (PetscRealPart(used[j]) != 0)) flags[1] = 0;
  }
  PetscCall(VecRestoreArrayRead(as->used, &used));
  PetscCall(VecRestoreArrayRead(m2, &b));
  PetscCall(VecRestoreArrayRead(m1, &a));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, flags, 2, MPIU_INT, MPI_MIN, PetscObjectComm((PetscObject)m1)));
  *sure = (PetscBool)flags[0];
  *same = (PetscBool)flags[1];
  PetscFunctionReturn(0);
}

/* *held when the set test m tells (active where m >= 0) leaves no body free;
 * uses as->all. Collective. */
static PetscErrorCode TellsHeldSet(M2dActiveSet *as, Vec m, PetscBool *held)
{
  const PetscScalar *a;
  PetscScalar       *b;
  PetscInt           n;
  Vec                mask;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(m, &mask));
  PetscCall(VecGetLocalSize(m, &n));
  PetscCall(VecGetArrayRead(m, &a));
  PetscCall(VecGetArrayWrite(mask, &b));
  for (PetscInt j = 0; j < n; j++) b[j] = PetscRealPart(a[j]) >= 0 ? 1.0 : 0.0;
  PetscCall(VecRestoreArrayWrite(mask, &b));
  PetscCall(VecRestoreArrayRead(m, &a));
  PetscCall(VecScatterBegin(as->toall, mask, as->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(as->toall, mask, as->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecDestroy(&mask));
  PetscCall(VecGetArrayRead(as->all, &a));
  PetscCall(M2dSupportsHeld(&as->pb->supports, PetscObjectComm((PetscObject)m), &as->pb->contact, a, held));
  PetscCall(VecRestoreArrayRead(as->all, &a));
  PetscFunctionReturn(0);
}

/* Iterative path: one step, inexact while its set is not the last one. CG
 * stops at -iterative_inexact of the step's right-hand side. The set that
 * solve tells is taken as the next one when it differs from the step's own
 * and holds every body: a node it got wrong is put right by the next step,
 * whose solve tells it again (inexact Newton; the sets visited may differ
 * from the complete solves', their end does not): from a cold start only
 * (ActiveSetSetupIterative), and until |F| rises or the sets cycle
 * (activeset.c, activeset_step.c). Otherwise the step is
 * completed to -iterative_ksp_rtol: the last step's answer is a complete
 * solve's, and a set that would free a body is judged on a complete solve.
 * With -iterative_prove (or once the sets have cycled) CG goes on instead
 * by factors of M2D_REFINE; once the next set is sure (NextSet: the set an
 * exact solve gives), a step whose next set is another stops there, and a
 * step whose set has settled (the last one) is completed. A set never sure
 * (a node on the boundary to round-off) ends complete too. */
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
    if (!same) PetscCall(TellsHeldSet(as, as->m[0], &held));
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
static PetscErrorCode SetStepPC(SNES snes, M2dActiveSet *as, const char *name)
{
  KSP ksp;
  PC  pc;

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, as));
  PetscCall(PCShellSetSetUp(pc, StepPCSetUp));
  PetscCall(PCShellSetApply(pc, StepPCApply));
  PetscCall(PCShellSetName(pc, name));
  PetscFunctionReturn(0);
}

/* condensed path: factor once; the SNES unknown is nu, its dense Jacobian solved by LAPACK on every rank */
PetscErrorCode ActiveSetSetupCondensed(SNES snes, M2dActiveSet *as, M2dActiveSetInfo *info)
{
  M2dCondensedInfo ci;

  PetscFunctionBeginUser;
  PetscCheck(as->kkt->aij && as->kkt->gamma > 0, PetscObjectComm((PetscObject)snes), PETSC_ERR_USER_INPUT, "option -kkt_path condensed: needs -kkt_mat aij (use -kkt_path full for nest/fieldsplit)");
  PetscCall(CondensedCreateFromKKT(as->kkt, &as->pb->s, &as->cond));
  PetscCall(SetStepPC(snes, as, "dense LU of the condensed Jacobian (LAPACK, every rank)"));
  PetscCall(CondensedGetInfo(as->cond, &ci));
  info->factor_time        = ci.factor_time;
  info->factor_flops       = ci.flops_sum;
  info->factor_flops_max   = ci.flops_max;
  info->interface_unknowns = ci.interface_unknowns;
  PetscFunctionReturn(0);
}

/* iterative path: each step's KKT solve by M2dIterativeSolve (the step PC),
 * set up by ActiveSetJacobian for the step's set */
PetscErrorCode ActiveSetSetupIterative(SNES snes, M2dActiveSet *as)
{
  M2dIterativeInfo ii;

  PetscFunctionBeginUser;
  PetscCall(M2dIterativeCreate(as->kkt, &as->pb->Rkkt, as->pb->ndir, as->pb->drows, &as->iter));
  PetscCall(VecDuplicate(as->u, &as->du));
  PetscCall(VecDuplicate(as->lam, &as->cdu));
  PetscCall(VecDuplicate(as->lam, &as->m[0]));
  PetscCall(VecDuplicate(as->lam, &as->m[1]));
  /* -iterative_prove; or a start from the previous mesh's set: it is near the
   * answer, where an inexact solve's set is the least to be trusted (many
   * nodes near the switch: the adaptive punch wandered for 50 steps) */
  PetscCall(M2dIterativeGetInfo(as->iter, &ii));
  as->proving = (PetscBool)(ii.prove || as->pb->warm != NULL);
  PetscCall(SetStepPC(snes, as, "multipliers eliminated, CG + AMG in u (iterative.h)"));
  PetscFunctionReturn(0);
}

/* vinewtonrsls: Jacobian [K C^T; -C 0] (all rows, multiplier rows negated), lambda >= 0 */
PetscErrorCode ActiveSetSetupVI(SNES snes, M2dActiveSet *as, Vec z)
{
  M2dKKT *kkt  = as->kkt;
  MPI_Comm comm = PetscObjectComm((PetscObject)snes);
  Vec     lower, upper, sign;

  PetscFunctionBeginUser;
  PetscCheck(kkt->aij, comm, PETSC_ERR_USER_INPUT, "option -snes_type vinewtonrsls: needs the monolithic matrix (-kkt_mat aij)");
  PetscCheck(kkt->gamma == 0, comm, PETSC_ERR_USER_INPUT, "option -snes_type vinewtonrsls: does not combine with -kkt_augment");
  PetscCall(VecSet(as->active, 1.0));
  PetscCall(KKTSetActive(kkt, as->active, as->c, as->c * as->h));
  PetscCall(VecDuplicate(z, &sign));
  PetscCall(VecSet(sign, 1.0));
  PetscCall(VecSet(as->lam, -1.0));
  PetscCall(VecISCopy(sign, kkt->isl, SCATTER_FORWARD, as->lam));
  PetscCall(MatDiagonalScale(kkt->A, sign, NULL));
  PetscCall(VecDestroy(&sign));
  PetscCall(VecDuplicate(z, &lower));
  PetscCall(VecDuplicate(z, &upper));
  PetscCall(VecSet(upper, PETSC_INFINITY));
  PetscCall(VecSet(lower, PETSC_NINFINITY));
  PetscCall(VecZeroEntries(as->lam));
  PetscCall(VecISCopy(lower, kkt->isl, SCATTER_FORWARD, as->lam));
  PetscCall(SNESVISetVariableBounds(snes, lower, upper));
  PetscCall(VecDestroy(&lower));
  PetscCall(VecDestroy(&upper));
  PetscCall(SNESSetJacobian(snes, kkt->A, kkt->A, ActiveSetJacobian, as));
  PetscFunctionReturn(0);
}
