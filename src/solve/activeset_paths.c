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

static PetscErrorCode StepPCApply(PC pc, Vec b, Vec y)
{
  M2dActiveSet *as;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &as));
  if (as->cond) PetscCall(CondensedJacobianSolve(as->cond, b, y));
  else PetscCall(M2dIterativeSolve(as->iter, b, y));
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
  PetscFunctionBeginUser;
  PetscCall(M2dIterativeCreate(as->kkt, &as->pb->Rkkt, as->pb->ndir, as->pb->drows, &as->iter));
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
