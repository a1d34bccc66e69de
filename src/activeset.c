/* activeset.c - unilateral contact by semismooth Newton (PDAS) or SNESVINEWTONRSLS (see activeset.h). */
#include "activeset.h"
#include "condensed.h"
#include <petscsnes.h>

typedef struct {
  M2dKKT       *kkt;
  PetscReal  c;
  PetscReal  h;               /* mean non-mortar edge length: rows scale c h (weighted gap -> force) */
  PetscBool  vi, monitor;
  Vec        u, lam, gm, tol; /* gm = C u - r = -g~ */
  Vec        active, used;    /* mask at the current iterate, and the one the last Jacobian used */
  PetscInt   nactive, entered, left, cycles, maxcycles;
  PetscReal  fnorm0, fnorm_prev;
  PetscBool  unchanged_before;
  PetscInt   nhist;
  uint64_t   hist[1024];
  PetscInt   histn[1024];
  PetscBool  cycling_failed;
  M2dCondensed *cond; /* fast path (the SNES unknown is nu, condensed.h), or NULL */
  Vec        cu;   /* fast path: C u(nu) */
} Ctx;

PetscReal ActiveSetDefaultC(const M2dScene *s, const M2dContact *ct)
{
  PetscReal inv = 0, h = 0;
  PetscInt  b[2] = {ct->nm.body, ct->m.body};
  for (int k = 0; k < 2; k++) {
    const M2dBody *bd = &s->body[b[k] >= 0 ? b[k] : 0];
    PetscReal   Ep = s->plane == M2D_PLANE_STRAIN ? bd->E / (1 - bd->nu * bd->nu) : bd->E;
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
static PetscErrorCode UpdateMask(Ctx *x)
{
  const PetscScalar *l, *g, *t, *un;
  PetscScalar       *a;
  PetscInt           lo, hi, cnt[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(x->lam, &lo, &hi));
  PetscCall(VecGetArrayRead(x->lam, &l));
  PetscCall(VecGetArrayRead(x->gm, &g));
  PetscCall(VecGetArrayRead(x->tol, &t));
  PetscCall(VecGetArrayRead(x->used, &un));
  PetscCall(VecGetArray(x->active, &a));
  for (PetscInt j = 0; j < hi - lo; j++) {
    PetscBool on;
    if (x->vi) on = (PetscBool)(PetscRealPart(l[j]) > 0);
    else on = (PetscBool)(PetscRealPart(l[j]) / x->c + PetscRealPart(g[j]) >= -PetscRealPart(t[j]));
    a[j] = on ? 1.0 : 0.0;
    cnt[0] += on;
    if (on && PetscRealPart(un[j]) == 0) cnt[1]++;
    if (!on && PetscRealPart(un[j]) != 0) cnt[2]++;
  }
  PetscCall(VecRestoreArray(x->active, &a));
  PetscCall(VecRestoreArrayRead(x->used, &un));
  PetscCall(VecRestoreArrayRead(x->tol, &t));
  PetscCall(VecRestoreArrayRead(x->gm, &g));
  PetscCall(VecRestoreArrayRead(x->lam, &l));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, cnt, 3, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)x->lam)));
  x->nactive = cnt[0];
  x->entered = cnt[1];
  x->left    = cnt[2];
  PetscFunctionReturn(0);
}

static PetscErrorCode FormFunction(SNES snes, Vec z, Vec F, void *ctx)
{
  Ctx *x   = (Ctx *)ctx;
  M2dKKT *kkt = x->kkt;
  Vec  Fu, Fl;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(VecISCopy(z, kkt->isu, SCATTER_REVERSE, x->u));
  PetscCall(VecISCopy(z, kkt->isl, SCATTER_REVERSE, x->lam));
  PetscCall(MatMult(kkt->C, x->u, x->gm));
  PetscCall(VecAXPY(x->gm, -1.0, kkt->r));
  PetscCall(UpdateMask(x));
  PetscCall(VecDuplicate(x->u, &Fu));
  PetscCall(VecDuplicate(x->lam, &Fl));
  PetscCall(MatMult(kkt->K, x->u, Fu));
  PetscCall(MatMultAdd(kkt->Ct, x->lam, Fu, Fu));
  PetscCall(VecAXPY(Fu, -1.0, kkt->f));
  /* multiplier rows in force units: scaled by c h (c g~ is a pressure) */
  if (x->vi) {
    PetscCall(VecCopy(x->gm, Fl));
    PetscCall(VecScale(Fl, -x->c * x->h)); /* c h g~ */
  } else {
    /* F_lambda = c h max(-lambda/c, C u - r) */
    PetscCall(VecCopy(x->lam, Fl));
    PetscCall(VecScale(Fl, -1.0 / x->c));
    PetscCall(VecPointwiseMax(Fl, Fl, x->gm));
    PetscCall(VecScale(Fl, x->c * x->h));
    if (kkt->gamma > 0 && !x->cond) { /* augmented rows: + gamma C^T diag(active) (C u - r) */
      Vec t, t2;
      PetscCall(VecDuplicate(x->lam, &t));
      PetscCall(VecDuplicate(x->u, &t2));
      PetscCall(VecPointwiseMult(t, x->active, x->gm));
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

static PetscErrorCode ActiveHash(Ctx *x, uint64_t *h)
{
  const PetscScalar *a;
  PetscInt           lo, hi;
  uint64_t           loc = 0;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(x->active, &lo, &hi));
  PetscCall(VecGetArrayRead(x->active, &a));
  for (PetscInt j = lo; j < hi; j++)
    if (PetscRealPart(a[j - lo]) != 0) loc += Mix((uint64_t)j);
  PetscCall(VecRestoreArrayRead(x->active, &a));
  PetscCallMPI(MPI_Allreduce(&loc, h, 1, MPI_UINT64_T, MPI_SUM, PetscObjectComm((PetscObject)x->active)));
  PetscFunctionReturn(0);
}

/* the active set of the next step: the current mask, unless it cycles */
static PetscErrorCode ChooseSet(SNES snes, Ctx *x)
{
  uint64_t h;
  PetscInt it;

  PetscFunctionBeginUser;
  PetscCall(SNESGetIterationNumber(snes, &it));
  /* cycling: the set returns to one seen two or more steps ago */
  PetscCall(ActiveHash(x, &h));
  /* (an unchanged set is not a cycle: the last entry is the previous step's set) */
  for (PetscInt k = 0; k + 1 < x->nhist && !(x->hist[x->nhist - 1] == h && x->histn[x->nhist - 1] == x->nactive); k++)
    if (x->hist[k] == h && x->histn[k] == x->nactive) {
      x->cycles++;
      if (x->cycles > x->maxcycles) {
        x->cycling_failed = PETSC_TRUE;
        break;
      }
      PetscCall(PetscPrintf(PetscObjectComm((PetscObject)snes), "  active set cycling at step %" PetscInt_FMT " (back to the set of step %" PetscInt_FMT "): c raised from %g to %g\n", it, k, (double)x->c, (double)(10 * x->c)));
      x->c *= 10;
      PetscCall(UpdateMask(x));
      PetscCall(ActiveHash(x, &h));
      break;
    }
  if (x->nhist < 1024) {
    x->hist[x->nhist]    = h;
    x->histn[x->nhist++] = x->nactive;
  }
  PetscCall(VecCopy(x->active, x->used));
  PetscFunctionReturn(0);
}

static PetscErrorCode FormJacobian(SNES snes, Vec z, Mat J, Mat P, void *ctx)
{
  Ctx *x = (Ctx *)ctx;

  PetscFunctionBeginUser;
  (void)z;
  (void)P;
  if (x->vi) PetscFunctionReturn(0); /* constant Jacobian, built once */
  PetscCall(ChooseSet(snes, x));
  if (x->cond) PetscCall(CondensedReducedJacobian(x->cond, x->active, x->c, x->h, J));
  else PetscCall(KKTSetActive(x->kkt, x->active, x->c, x->c * x->h));
  PetscFunctionReturn(0);
}

/* reduced iteration: F(nu) = c h max(-lambda/c, C u - r) with C u = w + S0 nu and
 * lambda = nu + g C u (condensed.h); the u rows hold for every nu */
static PetscErrorCode ReducedFunction(SNES snes, Vec nu, Vec F, void *ctx)
{
  Ctx               *x = (Ctx *)ctx;
  const PetscScalar *v, *cu, *r;
  PetscScalar       *l, *g, *f;
  PetscInt           n;
  PetscReal          gam = x->kkt->gamma;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(CondensedReducedGaps(x->cond, nu, x->cu));
  PetscCall(VecGetLocalSize(nu, &n));
  PetscCall(VecGetArrayRead(nu, &v));
  PetscCall(VecGetArrayRead(x->cu, &cu));
  PetscCall(VecGetArrayRead(x->kkt->r, &r));
  PetscCall(VecGetArray(x->lam, &l));
  PetscCall(VecGetArray(x->gm, &g));
  for (PetscInt j = 0; j < n; j++) {
    g[j] = cu[j] - r[j];
    l[j] = v[j] + gam * cu[j];
  }
  PetscCall(VecRestoreArray(x->gm, &g));
  PetscCall(VecRestoreArray(x->lam, &l));
  PetscCall(VecRestoreArrayRead(x->kkt->r, &r));
  PetscCall(VecRestoreArrayRead(x->cu, &cu));
  PetscCall(VecRestoreArrayRead(nu, &v));
  PetscCall(UpdateMask(x));
  PetscCall(VecGetArray(x->lam, &l));
  PetscCall(VecGetArray(x->gm, &g));
  PetscCall(VecGetArray(F, &f));
  for (PetscInt j = 0; j < n; j++) f[j] = x->c * x->h * PetscMax(-PetscRealPart(l[j]) / x->c, PetscRealPart(g[j]));
  PetscCall(VecRestoreArray(F, &f));
  PetscCall(VecRestoreArray(x->gm, &g));
  PetscCall(VecRestoreArray(x->lam, &l));
  PetscFunctionReturn(0);
}

/* Reduced iteration: w, then the first step as the full path takes it - the set
 * of (u = 0, lambda0) - solved directly: nu0 = -J^-1 F0, F0 the residual of that
 * set's linear piece at nu = 0. The SNES starts from nu0. */
static PetscErrorCode ReducedStart(SNES snes, Ctx *x, Vec z0, Vec *nu, Mat *J)
{
  M2dKKT               *kkt = x->kkt;
  Vec                F0, F;
  PetscInt           n, N;
  const PetscScalar *w, *r, *a;
  PetscScalar       *f;

  PetscFunctionBeginUser;
  PetscCall(CondensedReducedSetup(x->cond));
  PetscCall(VecDuplicate(kkt->r, &x->cu));
  PetscCall(VecDuplicate(kkt->r, nu));
  PetscCall(VecDuplicate(kkt->r, &F0));
  PetscCall(VecGetLocalSize(kkt->r, &n));
  PetscCall(VecGetSize(kkt->r, &N));
  PetscCall(MatCreateDense(PetscObjectComm((PetscObject)kkt->r), n, n, N, N, NULL, J));
  /* the full path's start z0 = (0, lambda0): its residual sets the first mask and
   * the norm the relative tolerance refers to */
  PetscCall(VecDuplicate(z0, &F));
  PetscCall(FormFunction(snes, z0, F, x));
  PetscCall(VecNorm(F, NORM_2, &x->fnorm0));
  PetscCall(VecDestroy(&F));
  PetscCall(ChooseSet(snes, x));
  PetscCall(CondensedReducedJacobian(x->cond, x->active, x->c, x->h, *J));
  PetscCall(VecGetArrayRead(x->cond->w, &w));
  PetscCall(VecGetArrayRead(kkt->r, &r));
  PetscCall(VecGetArrayRead(x->active, &a));
  PetscCall(VecGetArray(F0, &f));
  for (PetscInt j = 0; j < n; j++) f[j] = PetscRealPart(a[j]) != 0 ? -x->c * x->h * (w[j] - r[j]) : x->h * kkt->gamma * w[j];
  PetscCall(VecRestoreArray(F0, &f));
  PetscCall(VecRestoreArrayRead(x->active, &a));
  PetscCall(VecRestoreArrayRead(kkt->r, &r));
  PetscCall(VecRestoreArrayRead(x->cond->w, &w));
  PetscCall(CondensedDenseFactor(x->cond, *J));
  PetscCall(CondensedDenseSolve(x->cond, F0, *nu));
  PetscCall(VecDestroy(&F0));
  PetscCall(VecDuplicate(kkt->r, &F));
  PetscCall(SNESSetFunction(snes, F, ReducedFunction, x));
  PetscCall(VecDestroy(&F));
  PetscCall(SNESSetJacobian(snes, *J, *J, FormJacobian, x));
  PetscFunctionReturn(0);
}

static PetscErrorCode DensePCSetUp(PC pc)
{
  M2dCondensed *cs;
  Mat        P;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &cs));
  PetscCall(PCGetOperators(pc, NULL, &P));
  PetscCall(CondensedDenseFactor(cs, P));
  PetscFunctionReturn(0);
}

static PetscErrorCode DensePCApply(PC pc, Vec b, Vec y)
{
  M2dCondensed *cs;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &cs));
  PetscCall(CondensedDenseSolve(cs, b, y));
  PetscFunctionReturn(0);
}

static PetscErrorCode Converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm, SNESConvergedReason *reason, void *ctx)
{
  Ctx      *x = (Ctx *)ctx;
  PetscReal atol, rtol, stol;
  PetscInt  maxit, maxf, k;

  PetscFunctionBeginUser;
  (void)xnorm;
  (void)snorm;
  PetscCall(SNESGetTolerances(snes, &atol, &rtol, &stol, &maxit, &maxf));
  *reason = SNES_CONVERGED_ITERATING;
  if (it == 0 && !x->cond) x->fnorm0 = fnorm; /* fast path: set by ReducedStart */
  k = it + (x->cond ? 1 : 0);                 /* steps taken, as the full path counts them */
  if (x->cycling_failed) *reason = SNES_DIVERGED_LOCAL_MIN;
  else if (PetscIsInfOrNanReal(fnorm)) *reason = SNES_DIVERGED_FNORM_NAN;
  else if ((k > 0 || x->nactive == 0) && x->entered + x->left == 0 && (fnorm <= atol || fnorm <= rtol * x->fnorm0)) *reason = k > 0 ? SNES_CONVERGED_FNORM_RELATIVE : SNES_CONVERGED_FNORM_ABS;
  else if (k > 1 && x->entered + x->left == 0 && x->unchanged_before && fnorm >= 0.5 * x->fnorm_prev) {
    /* the same set solved twice and the residual no longer falls: round-off floor
     * of an ill-conditioned system (e.g. nu -> 0.5); the answer is as exact as it gets */
    *reason = SNES_CONVERGED_SNORM_RELATIVE;
  }
  else if (it >= maxit) *reason = SNES_DIVERGED_MAX_IT;
  x->unchanged_before = (PetscBool)(k > 0 && x->entered + x->left == 0);
  x->fnorm_prev       = fnorm;
  PetscFunctionReturn(0);
}

static PetscErrorCode Monitor(SNES snes, PetscInt it, PetscReal fnorm, void *ctx)
{
  Ctx      *x = (Ctx *)ctx;
  Vec       F;
  PetscReal nu, nl;

  PetscFunctionBeginUser;
  if (!x->monitor) {
    if (x->vi) PetscCall(VecCopy(x->active, x->used));
    PetscFunctionReturn(0);
  }
  PetscCall(SNESGetFunction(snes, &F, NULL, NULL));
  if (x->cond) { /* the u rows hold by construction (round-off: see the final line) */
    nu = 0;
    nl = fnorm;
    it++; /* the first set was solved before the SNES */
  } else {
    Vec fl, z;
    PetscCall(VecISCopy(F, x->kkt->isu, SCATTER_REVERSE, x->u));
    PetscCall(VecNorm(x->u, NORM_2, &nu));
    PetscCall(VecDuplicate(x->lam, &fl));
    PetscCall(VecISCopy(F, x->kkt->isl, SCATTER_REVERSE, fl));
    PetscCall(VecNorm(fl, NORM_2, &nl));
    PetscCall(VecDestroy(&fl));
    /* x->u was overwritten with F_u: restore the iterate */
    PetscCall(SNESGetSolution(snes, &z));
    PetscCall(VecISCopy(z, x->kkt->isu, SCATTER_REVERSE, x->u));
  }
  if (it == 0) PetscCall(PetscPrintf(PetscObjectComm((PetscObject)snes), "  active set step %2" PetscInt_FMT ": %6" PetscInt_FMT " active (initial guess)         |F| %.3e  |F_u| %.3e  |F_lambda| %.3e\n", it, x->nactive, (double)fnorm, (double)nu, (double)nl));
  else PetscCall(PetscPrintf(PetscObjectComm((PetscObject)snes), "  active set step %2" PetscInt_FMT ": %6" PetscInt_FMT " active (+%" PetscInt_FMT " entered, -%" PetscInt_FMT " left)  |F| %.3e  |F_u| %.3e  |F_lambda| %.3e\n", it, x->nactive, x->entered, x->left, (double)fnorm, (double)nu, (double)nl));
  if (x->vi) PetscCall(VecCopy(x->active, x->used)); /* the VI solver has no Jacobian hook of ours */
  PetscFunctionReturn(0);
}

PetscErrorCode ActiveSetSolve(const M2dScene *s, const M2dMesh *m, M2dContact *ct, M2dKKT *kkt, Vec u, Vec lam, Vec active, M2dActiveSetInfo *info)
{
  MPI_Comm            comm = PetscObjectComm((PetscObject)kkt->K);
  SNES                snes;
  KSP                 ksp;
  Ctx                 x;
  Vec                 z, F;
  SNESConvergedReason reason;
  PetscReal           L;
  Vec                 nu = NULL;
  Mat                 Jr = NULL;

  PetscFunctionBeginUser;
  (void)m;
  PetscCall(PetscMemzero(&x, sizeof(x)));
  PetscCall(PetscMemzero(info, sizeof(*info)));
  x.kkt       = kkt;
  x.c         = s->contact_c > 0 ? s->contact_c : ActiveSetDefaultC(s, ct);
  x.monitor   = s->contact_monitor;
  x.maxcycles = 5;
  for (PetscInt e = 0; e < ct->nm.nedge; e++) x.h += ct->nm.len[e];
  x.h /= PetscMax(1, ct->nm.nedge);
  PetscCall(VecDuplicate(u, &x.u));
  PetscCall(VecDuplicate(lam, &x.lam));
  PetscCall(VecZeroEntries(x.lam));
  PetscCall(VecDuplicate(lam, &x.gm));
  PetscCall(VecDuplicate(lam, &x.tol));
  PetscCall(VecDuplicate(lam, &x.used));
  x.active = active;
  PetscCall(VecSet(x.used, 1.0));
  PetscCall(VecSet(x.active, 0.0));
  /* tie tolerance on the weighted gap: 1e-12 of the weight times the mortar surface's size */
  L = PetscSqrtReal(PetscSqr(ct->m.hi[0] - ct->m.lo[0]) + PetscSqr(ct->m.hi[1] - ct->m.lo[1]));
  {
    PetscInt lo, hi;
    PetscCall(VecGetOwnershipRange(x.tol, &lo, &hi));
    for (PetscInt j = lo; j < hi; j++) PetscCall(VecSetValue(x.tol, j, 1e-12 * ct->R.w[j] * L, INSERT_VALUES));
    PetscCall(VecAssemblyBegin(x.tol));
    PetscCall(VecAssemblyEnd(x.tol));
  }

  PetscCall(SNESCreate(comm, &snes));
  PetscCall(SNESSetType(snes, SNESNEWTONLS));
  {
    SNESLineSearch ls;
    PC             pc;
    PetscCall(SNESGetLineSearch(snes, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC)); /* full steps: PDAS */
    PetscCall(SNESGetKSP(snes, &ksp));
    PetscCall(KSPSetType(ksp, KSPPREONLY));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCSetType(pc, PCLU));
    PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  }
  PetscCall(SNESSetTolerances(snes, 1e-50, 1e-10, 0.0, 50, -1));
  PetscCall(SNESSetFromOptions(snes));
  PetscCall(PetscObjectTypeCompare((PetscObject)snes, SNESVINEWTONRSLS, &x.vi));
  if (x.vi) { /* -snes_type resets the line search: full steps again, unless the options say otherwise */
    SNESLineSearch ls;
    PetscCall(SNESGetLineSearch(snes, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
    PetscCall(SNESLineSearchSetFromOptions(ls));
  }
  if (!x.vi) {
    PetscBool ok;
    PetscCall(PetscObjectTypeCompare((PetscObject)snes, SNESNEWTONLS, &ok));
    PetscCheck(ok, comm, PETSC_ERR_USER_INPUT, "option -snes_type: contact is solved with newtonls (primal-dual active set) or vinewtonrsls");
  }
  PetscCall(KKTSetupKSP(kkt, ksp));
  if (s->condensed && !x.vi) {
    PC pc;
    PetscCheck(kkt->aij && kkt->gamma > 0, comm, PETSC_ERR_USER_INPUT, "option -kkt_path condensed: needs -kkt_mat aij (use -kkt_path full for nest/fieldsplit)");
    PetscCall(PetscNew(&x.cond));
    PetscCall(CondensedCreate(kkt, s, x.cond));
    /* the SNES unknown is nu (n_lambda): its Jacobian is dense, LAPACK LU on every rank */
    PetscCall(KSPSetType(ksp, KSPPREONLY));
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCSetType(pc, PCSHELL));
    PetscCall(PCShellSetContext(pc, x.cond));
    PetscCall(PCShellSetSetUp(pc, DensePCSetUp));
    PetscCall(PCShellSetApply(pc, DensePCApply));
    PetscCall(PCShellSetName(pc, "dense LU of the reduced Jacobian (LAPACK, every rank)"));
    info->factor_time = x.cond->factor_time;
    info->factor_flops       = x.cond->flops_sum;
    info->factor_flops_max   = x.cond->flops_max;
    info->interface_unknowns = x.cond->ns + x.cond->N;
  } else PetscCall(M2dOrderingSetupKSP(ksp, s->kkt_ordering, NULL));
  PetscCall(VecDuplicate(kkt->x, &z));
  PetscCall(VecDuplicate(kkt->x, &F));
  PetscCall(VecZeroEntries(z));
  if (s->contact_initial > 0 && !x.vi) {
    /* lambda0_j = c max(g~0_j, 0) makes node j active at the start: every
     * candidate (all), or those whose nodal gap g~0/w is within 1e-6 of the
     * mortar surface's size of the smallest one (closest) */
    const PetscScalar *r;
    PetscScalar       *l;
    PetscInt           lo, hi;
    PetscReal          gmin = PETSC_MAX_REAL;
    PetscCall(VecGetOwnershipRange(kkt->r, &lo, &hi));
    PetscCall(VecGetArrayRead(kkt->r, &r));
    for (PetscInt j = lo; j < hi; j++) gmin = PetscMin(gmin, PetscRealPart(r[j - lo]) / ct->R.w[j]);
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &gmin, 1, MPIU_REAL, MPI_MIN, comm));
    PetscCall(VecGetArray(x.lam, &l));
    for (PetscInt j = lo; j < hi; j++) {
      PetscReal g = PetscRealPart(r[j - lo]);
      l[j - lo]   = (s->contact_initial == 2 || g / ct->R.w[j] <= gmin + 1e-6 * L) ? x.c * PetscMax(g, 0) : 0;
    }
    PetscCall(VecRestoreArray(x.lam, &l));
    PetscCall(VecRestoreArrayRead(kkt->r, &r));
    PetscCall(VecISCopy(z, kkt->isl, SCATTER_FORWARD, x.lam));
  }
  PetscCall(SNESSetFunction(snes, F, FormFunction, &x));
  if (x.vi) {
    Vec xl, xu, sgn;
    PetscCheck(kkt->aij, comm, PETSC_ERR_USER_INPUT, "option -snes_type vinewtonrsls: needs the monolithic matrix (-kkt_mat aij)");
    PetscCheck(kkt->gamma == 0, comm, PETSC_ERR_USER_INPUT, "option -snes_type vinewtonrsls: does not combine with -kkt_augment");
    /* Jacobian [K C^T; -C 0]: all rows, multiplier rows negated */
    PetscCall(VecSet(x.active, 1.0));
    PetscCall(KKTSetActive(kkt, x.active, x.c, x.c * x.h));
    PetscCall(VecDuplicate(z, &sgn));
    PetscCall(VecSet(sgn, 1.0));
    PetscCall(VecSet(x.lam, -1.0));
    PetscCall(VecISCopy(sgn, kkt->isl, SCATTER_FORWARD, x.lam));
    PetscCall(MatDiagonalScale(kkt->A, sgn, NULL));
    PetscCall(VecDestroy(&sgn));
    PetscCall(VecDuplicate(z, &xl));
    PetscCall(VecDuplicate(z, &xu));
    PetscCall(VecSet(xu, PETSC_INFINITY));
    PetscCall(VecSet(xl, PETSC_NINFINITY));
    PetscCall(VecZeroEntries(x.lam));
    PetscCall(VecISCopy(xl, kkt->isl, SCATTER_FORWARD, x.lam));
    PetscCall(SNESVISetVariableBounds(snes, xl, xu));
    PetscCall(VecDestroy(&xl));
    PetscCall(VecDestroy(&xu));
  } else PetscCall(SNESSetConvergenceTest(snes, Converged, &x, NULL));
  if (x.cond) PetscCall(ReducedStart(snes, &x, z, &nu, &Jr));
  else PetscCall(SNESSetJacobian(snes, kkt->A, kkt->A, FormJacobian, &x));
  PetscCall(SNESMonitorSet(snes, Monitor, &x, NULL));
  PetscCall(PetscPrintf(comm, "active set: %s, %s, c = %g, %" PetscInt_FMT " candidate nodes\n", x.vi ? "SNESVINEWTONRSLS" : "semismooth Newton (primal-dual active set)", x.cond ? "K factored once, steps on the multipliers (condensed)" : "KKT refactored each step (full)", (double)x.c, kkt->nlam));
  PetscCall(SNESSolve(snes, NULL, x.cond ? nu : z));
  PetscCall(SNESGetConvergedReason(snes, &reason));
  PetscCall(SNESGetIterationNumber(snes, &info->iterations));
  if (x.cond) info->iterations++; /* the first set was solved before the SNES (ReducedStart) */
  info->cycles = x.cycles;
  info->c      = x.c;
  info->vi     = x.vi;
  if (reason <= 0) {
    KSPConvergedReason kr;
    PetscCall(KSPGetConvergedReason(ksp, &kr));
    PetscCheck(!x.cycling_failed, comm, PETSC_ERR_NOT_CONVERGED, "active set keeps cycling (%" PetscInt_FMT " cycles after raising c to %g): no solution found", x.cycles, (double)x.c);
    PetscCheck(reason != SNES_DIVERGED_MAX_IT, comm, PETSC_ERR_NOT_CONVERGED, "active set did not settle in %" PetscInt_FMT " steps (-snes_max_it)", info->iterations);
    if (kr < 0) {
      PC        pc;
      PetscBool fs;
      PetscCall(KSPGetPC(ksp, &pc));
      PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &fs));
      PetscCheck(!(fs && kkt->gamma == 0), comm, PETSC_ERR_NOT_CONVERGED, "linear solve failed (%s): the fieldsplit K block cannot be factored when a body is held only by contact; add -kkt_augment 1 or use the monolithic solver (options/kkt_mumps.opts)", KSPConvergedReasons[kr]);
      SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "linear solve in active-set step %" PetscInt_FMT " failed (%s): is every body held (by supports, or by contact)?", info->iterations, KSPConvergedReasons[kr]);
    }
    SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "active-set iteration failed: %s", SNESConvergedReasons[reason]);
  }
  if (x.cond) { /* lambda from the last residual evaluation, u by one substitution */
    PetscCall(CondensedRecover(x.cond, nu, u));
    PetscCall(VecCopy(x.lam, lam));
    if (x.monitor) { /* the u rows, which the reduced residual holds by construction */
      Vec       Fu, la;
      PetscReal nf, nff;
      PetscCall(VecDuplicate(u, &Fu));
      PetscCall(VecDuplicate(lam, &la));
      PetscCall(VecPointwiseMult(la, lam, x.active));
      PetscCall(MatMult(kkt->K, u, Fu));
      PetscCall(MatMultAdd(kkt->Ct, la, Fu, Fu));
      PetscCall(VecAXPY(Fu, -1.0, kkt->f));
      PetscCall(VecNorm(Fu, NORM_2, &nf));
      PetscCall(VecNorm(kkt->f, NORM_2, &nff));
      PetscCall(PetscPrintf(comm, "  recovered u: |K u + C^T lambda - f| = %.3e (|f| = %.3e)\n", (double)nf, (double)nff));
      PetscCall(VecDestroy(&Fu));
      PetscCall(VecDestroy(&la));
    }
    PetscCall(VecDestroy(&nu));
    PetscCall(MatDestroy(&Jr));
    PetscCall(VecDestroy(&x.cu));
  } else {
    PetscCall(VecISCopy(z, kkt->isu, SCATTER_REVERSE, u));
    PetscCall(VecISCopy(z, kkt->isl, SCATTER_REVERSE, lam));
  }
  if (x.vi) { /* active = positive multiplier */
    PetscCall(VecCopy(lam, x.lam));
    PetscCall(UpdateMask(&x));
  } else PetscCall(VecPointwiseMult(lam, lam, x.active)); /* inactive rows: lambda = 0 exactly, not round-off */
  info->nactive = x.nactive;
  PetscCall(PetscPrintf(comm, "active set: converged in %" PetscInt_FMT " steps (%s), %" PetscInt_FMT " active nodes\n", info->iterations, SNESConvergedReasons[reason], info->nactive));
  PetscCall(SNESDestroy(&snes));
  PetscCall(VecDestroy(&z));
  PetscCall(VecDestroy(&F));
  PetscCall(VecDestroy(&x.u));
  PetscCall(VecDestroy(&x.lam));
  PetscCall(VecDestroy(&x.gm));
  PetscCall(VecDestroy(&x.tol));
  PetscCall(VecDestroy(&x.used));
  if (x.cond) {
    PetscCall(CondensedDestroy(x.cond));
    PetscCall(PetscFree(x.cond));
  }
  info->condensed = (PetscBool)(info->factor_time > 0);
  PetscFunctionReturn(0);
}
