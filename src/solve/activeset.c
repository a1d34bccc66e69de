/* activeset.c - the active-set loop (see activeset.h): the states of the
 * contact nodes as rules per row, the residual and the step's matrix of the
 * current rules, the checks between steps (cycling, bodies held), the stop,
 * and the load steps. How a step is solved is the path's (activeset_paths.c). */
#include "activeset_impl.h"
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

/* ---------------------------------------------------------------- the rules */

/* the rules into the vectors the paths read (this rank's rows) */
static PetscErrorCode RulesToVecs(M2dActiveSet *as)
{
  const PetscInt *rng;
  PetscScalar    *a, *s;
  PetscMPIInt     rank;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRanges(as->active, &rng));
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)as->active), &rank));
  PetscCall(VecGetArrayWrite(as->active, &a));
  PetscCall(VecGetArrayWrite(as->slip, &s));
  for (PetscInt j = rng[rank]; j < rng[rank + 1]; j++) a[j - rng[rank]] = as->rule[j], s[j - rng[rank]] = as->coef[j];
  PetscCall(VecRestoreArrayWrite(as->slip, &s));
  PetscCall(VecRestoreArrayWrite(as->active, &a));
  PetscFunctionReturn(0);
}

/* The rules of every row at the iterate (lamall, gmall), the same on every
 * rank: a normal row is a constraint where lambda/c - g~ >= -tol (closed); a
 * tangential row of a closed node is a constraint where |xi_t| <= mu xi_n
 * (stick), else a force lambda_t = s xi_n, s = mu sign(xi_t) (slip), and a
 * force with s = 0 where its node is open; the VI solver's: closed where lambda > 0.
 * Counts the states and the rows changed against `used`. */
static PetscErrorCode Rules(M2dActiveSet *as)
{
  const PetscScalar *l, *g;
  PetscInt           cnt[4] = {0, 0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(as->lamall, &l));
  PetscCall(VecGetArrayRead(as->gmall, &g));
  for (PetscInt j = 0; j < as->n; j++) {
    PetscReal lj = PetscRealPart(l[j]), gj = PetscRealPart(g[j]);
    PetscInt  p  = as->partner ? as->partner[j] : -1;
    as->coef[j]  = 0;
    if (p < 0) as->rule[j] = (as->ops->bounds_by_solver ? lj > 0 : lj / as->c + gj >= -as->tol[j]) ? 1.0 : 0.0;
    else if (as->rule[p] == 0) as->rule[j] = 0; /* an open node: no friction force */
    else {
      PetscReal xi = lj + as->c * gj, bound = as->mu[j] * (PetscRealPart(l[p]) + as->c * PetscRealPart(g[p]));
      as->rule[j]  = PetscAbsReal(xi) <= bound + as->c * as->tol[j] ? 1.0 : 0.0;
      if (as->rule[j] == 0) as->coef[j] = xi < 0 ? -as->mu[j] : as->mu[j];
    }
    if (p < 0) cnt[0] += as->rule[j] != 0;
    else cnt[as->rule[j] != 0 ? 1 : 2] += as->rule[p] != 0;
    cnt[3] += as->rule[j] != as->used[j] || as->coef[j] != as->usedcoef[j];
  }
  PetscCall(VecRestoreArrayRead(as->gmall, &g));
  PetscCall(VecRestoreArrayRead(as->lamall, &l));
  as->nclosed = cnt[0], as->nstick = cnt[1], as->nslip = cnt[2], as->changed = cnt[3];
  PetscCall(RulesToVecs(as));
  PetscFunctionReturn(0);
}

/* the loop's own rules replaced by `used` (a load step's first step) */
static PetscErrorCode UseUsed(M2dActiveSet *as)
{
  PetscFunctionBeginUser;
  PetscCall(PetscArraycpy(as->rule, as->used, as->n));
  PetscCall(PetscArraycpy(as->coef, as->usedcoef, as->n));
  PetscCall(RulesToVecs(as));
  PetscFunctionReturn(0);
}

/* ------------------------------------------------------------ residual, steps */

/* F's multiplier rows: a constraint c h (C u - r)_j, a force -h (lambda_j -
 * s_j xi_p); a normal row c h max(-lambda/c, C u - r), the two at once; the
 * VI solver's: the gap in force units, -c h g~ */
static PetscErrorCode ActiveSetFunction(SNES snes, Vec x, Vec F, void *ctx)
{
  M2dActiveSet      *as = (M2dActiveSet *)ctx;
  const PetscScalar *l, *g, *la, *ga;
  PetscScalar       *f;
  Vec                Fl;
  PetscInt           lo, hi;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(as->ops->evaluate(as, x));
  PetscCall(VecScatterBegin(as->toall, as->lam, as->lamall, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(as->toall, as->lam, as->lamall, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterBegin(as->toall, as->gm, as->gmall, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(as->toall, as->gm, as->gmall, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(Rules(as));
  if (as->forced) PetscCall(UseUsed(as));
  if (as->ops->residual_u) PetscCall(as->ops->residual_u(as, x, F));
  PetscCall(VecGetOwnershipRange(as->lam, &lo, &hi));
  PetscCall(VecDuplicate(as->lam, &Fl));
  PetscCall(VecGetArrayRead(as->lam, &l));
  PetscCall(VecGetArrayRead(as->gm, &g));
  PetscCall(VecGetArrayRead(as->lamall, &la));
  PetscCall(VecGetArrayRead(as->gmall, &ga));
  PetscCall(VecGetArrayWrite(Fl, &f));
  for (PetscInt j = lo; j < hi; j++) {
    PetscReal lj = PetscRealPart(l[j - lo]), gj = PetscRealPart(g[j - lo]);
    PetscInt  p  = as->partner ? as->partner[j] : -1;
    if (as->ops->bounds_by_solver) f[j - lo] = gj * (-as->c * as->h);
    else if (p < 0 && !as->forced) f[j - lo] = as->c * as->h * PetscMax(-lj / as->c, gj);
    else if (as->rule[j] != 0) f[j - lo] = as->c * as->h * gj;
    else f[j - lo] = as->h * ((p < 0 ? 0 : as->coef[j] * (PetscRealPart(la[p]) + as->c * PetscRealPart(ga[p]))) - lj);
  }
  PetscCall(VecRestoreArrayWrite(Fl, &f));
  PetscCall(VecRestoreArrayRead(as->gmall, &ga));
  PetscCall(VecRestoreArrayRead(as->lamall, &la));
  PetscCall(VecRestoreArrayRead(as->gm, &g));
  PetscCall(VecRestoreArrayRead(as->lam, &l));
  if (as->ops->lambda_only) PetscCall(VecCopy(Fl, F));
  else PetscCall(VecISCopy(F, as->kkt->isl, SCATTER_FORWARD, Fl));
  PetscCall(VecDestroy(&Fl));
  PetscFunctionReturn(0);
}

static uint64_t Mix(uint64_t x)
{
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/* the hash of the rules (a sum over the constraint rows, and the slipping rows by direction) */
static uint64_t RulesHash(const M2dActiveSet *as)
{
  uint64_t h = 0;
  for (PetscInt j = 0; j < as->n; j++) {
    if (as->rule[j] != 0) h += Mix((uint64_t)j);
    else if (as->coef[j] != 0) h += Mix((uint64_t)(j + (as->coef[j] > 0 ? 1 : 2) * as->n));
  }
  return h;
}

/* A set that returns to one seen two or more steps ago is a cycle: c is raised
 * tenfold (at most max_cycles times) and the rules recomputed, unless the path
 * answers it (ops->cycled); with the VI solver's bounds the cycles are only
 * counted. */
static PetscErrorCode BreakCycle(M2dActiveSet *as, MPI_Comm comm)
{
  M2dSetHistory *hi = &as->hist;
  uint64_t       h  = RulesHash(as);
  PetscInt       cnt = as->nclosed + as->nstick;

  PetscFunctionBeginUser;
  /* (an unchanged set is not a cycle: the last entry is the previous step's set) */
  for (PetscInt k = 0; k + 1 < hi->n && !(hi->hash[hi->n - 1] == h && hi->count[hi->n - 1] == cnt); k++)
    if (hi->hash[k] == h && hi->count[k] == cnt) {
      PetscBool answered = PETSC_FALSE;
      if (as->ops->cycled) PetscCall(as->ops->cycled(as, k, &answered));
      if (answered) break;
      if (++hi->cycles > hi->max_cycles) {
        hi->failed = PETSC_TRUE;
        break;
      }
      if (as->ops->bounds_by_solver) break; /* the solver's set is its own (lambda > 0) and its Jacobian holds c, built once: a raised c would only make the two disagree */
      PetscCall(PetscPrintf(comm, "  active set cycling at step %" PetscInt_FMT " (back to the set of step %" PetscInt_FMT "): c raised from %g to %g\n", as->step, k, (double)(as->c * CUser(as->pb)), (double)(10 * as->c * CUser(as->pb))));
      as->c *= 10;
      PetscCall(Rules(as));
      h   = RulesHash(as);
      cnt = as->nclosed + as->nstick;
      break;
    }
  if (hi->n < M2D_MAX_HISTORY) {
    hi->hash[hi->n]    = h;
    hi->count[hi->n++] = cnt;
  }
  PetscFunctionReturn(0);
}

/* The external load on each body (the sum of f over its free dofs, frames
 * rotated back), and whether a support holds any of its dofs (load[2 nb + b]
 * = 1), every rank: what friction must carry when a body slides */
static PetscErrorCode BodyLoads(M2dActiveSet *as, PetscReal load[])
{
  M2dProblem        *pb = as->pb;
  const M2dMesh     *m  = &pb->mesh;
  Vec                fg;
  PetscSection       gsec;
  PetscInt          *vbody, nb = pb->s.nbody;
  const PetscScalar *fa;

  PetscFunctionBeginUser;
  PetscCall(PetscArrayzero(load, 3 * nb));
  PetscCall(VecDuplicate(pb->f, &fg));
  PetscCall(VecCopy(pb->f, fg));
  for (PetscInt i = 0; i < pb->ndir; i++) PetscCall(VecSetValue(fg, pb->drows[i], 0.0, INSERT_VALUES)); /* held rows carry no load */
  PetscCall(VecAssemblyBegin(fg));
  PetscCall(VecAssemblyEnd(fg));
  PetscCall(M2dFramesRotateGlobal(&pb->frames, m, fg, PETSC_TRUE));
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(PetscMalloc1(m->vEnd - m->vStart + 1, &vbody));
  for (PetscInt c = m->cStart; c < m->cEnd; c++)
    for (int k = 0; k < 4; k++) vbody[m->cellverts[4 * (c - m->cStart) + k] - m->vStart] = m->cellbody[c - m->cStart];
  PetscCall(VecGetArrayRead(fg, &fa));
  {
    PetscInt lo;
    PetscCall(VecGetOwnershipRange(fg, &lo, NULL));
    for (PetscInt v = m->vStart; v < m->vEnd; v++) {
      PetscInt goff;
      PetscCall(PetscSectionGetOffset(gsec, v, &goff));
      if (goff < 0) continue;
      for (int d = 0; d < 2; d++) load[2 * vbody[v - m->vStart] + d] += PetscRealPart(fa[goff + d - lo]);
      if (pb->frames.mask[v - m->vStart]) load[2 * nb + vbody[v - m->vStart]] = 1;
    }
  }
  PetscCall(VecRestoreArrayRead(fg, &fa));
  PetscCall(PetscFree(vbody));
  PetscCall(VecDestroy(&fg));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, load, 2 * nb, MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)pb->f)));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, load + 2 * nb, nb, MPIU_REAL, MPIU_MAX, PetscObjectComm((PetscObject)pb->f)));
  PetscFunctionReturn(0);
}

/* Rules that free a body while its slipping nodes, were they sticking, would
 * hold it: the body slides. Its tangential load and the friction its closed
 * nodes can carry (mu x the normal force: a free body's normal load, else
 * the pair's normal multipliers at the iterate): beyond it, one line; within
 * it, the slip was an iterate's and the body's slipping nodes stick for the
 * next step. */
static PetscErrorCode Slides(M2dActiveSet *as, MPI_Comm comm, PetscBool *stuck)
{
  M2dProblem        *pb = as->pb;
  const M2dContact  *ct = &pb->contact;
  const PetscScalar *l;
  PetscReal         *trial, *load;
  PetscBool          held;

  PetscFunctionBeginUser;
  *stuck = PETSC_FALSE;
  if (!as->partner) PetscFunctionReturn(0);
  PetscCall(PetscMalloc1(as->n + 1, &trial));
  for (PetscInt j = 0; j < as->n; j++) trial[j] = as->coef[j] != 0 ? 1.0 : as->rule[j];
  PetscCall(M2dSupportsHeld(&pb->supports, comm, ct, trial, &held));
  if (!held) {
    PetscCall(PetscFree(trial));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscMalloc1(3 * pb->s.nbody + 1, &load));
  PetscCall(BodyLoads(as, load));
  PetscCall(VecGetArrayRead(as->lamall, &l));
  for (PetscInt k = 0; k < ct->npair; k++) { /* the first pair whose non-mortar body slides: its load against its friction */
    const M2dContactPair *p = &ct->pair[k];
    PetscReal             N = 0, t[2] = {0, 0}, T, cap;
    PetscInt              nslip = 0, b = p->nm.body, nb = pb->s.nbody;
    if (!p->T.n || b < 0) continue;
    for (PetscInt i = 0; i < p->T.n; i++) {
      PetscReal nn[2];
      if (as->rule[p->off + i] == 0) continue;
      nslip += as->coef[p->toff + i] != 0;
      N += PetscRealPart(l[p->off + i]) * p->R.w[i];
      SurfaceNodeNormal(&p->nm, p->R.node[i], nn);
      t[0] += -nn[1] * p->R.w[i], t[1] += nn[0] * p->R.w[i];
    }
    if (!nslip) continue;
    T = PetscSqrtReal(t[0] * t[0] + t[1] * t[1]);
    if (T > 0 && load[2 * nb + b] == 0) N = PetscAbsReal(load[2 * b] * t[1] - load[2 * b + 1] * t[0]) / T; /* a free body: its load along the surface's mean normal */
    T = T > 0 ? PetscAbsReal(load[2 * b] * t[0] + load[2 * b + 1] * t[1]) / T : 0; /* along its mean tangent */
    cap = p->mu * N;
    PetscCheck(T <= cap * (1 + 1e-9), comm, PETSC_ERR_USER_INPUT, "body '%s' slides: tangential load %g exceeds MU x normal force %g x %g = %g on pair %s:%s; hold it (-dirichlet) or lower the tangential load", pb->s.body[b].name, (double)(T * pb->units.S * pb->units.L), (double)p->mu,
               (double)(N * pb->units.S * pb->units.L), (double)(cap * pb->units.S * pb->units.L), p->def->nm, p->def->m);
  }
  PetscCall(VecRestoreArrayRead(as->lamall, &l));
  for (PetscInt j = 0; j < as->n; j++) /* within the friction: stick, and try again */
    if (as->coef[j] != 0) as->rule[j] = 1.0, as->coef[j] = 0;
  *stuck = PETSC_TRUE;
  PetscCall(PetscFree(load));
  PetscCall(PetscFree(trial));
  PetscFunctionReturn(0);
}

/* The rules of the next step: the iterate's, unless they cycle. Rules that
 * leave a body free (no support, no closed contact node against one of its
 * rigid motions) make the step singular: the contact has opened and nothing
 * holds the body, which is the answer, stated in one line (or the body
 * slides: Slides). */
static PetscErrorCode ChooseSet(M2dActiveSet *as, MPI_Comm comm)
{
  M2dProblem *pb = as->pb;
  char        when[160];
  PetscBool   held, stuck;

  PetscFunctionBeginUser;
  if (!as->forced) PetscCall(BreakCycle(as, comm));
  PetscCall(M2dSupportsHeld(&pb->supports, comm, &pb->contact, as->rule, &held));
  if (!held) {
    PetscCall(Slides(as, comm, &stuck));
    if (stuck) {
      PetscCall(RulesToVecs(as));
      PetscCall(PetscPrintf(comm, "  active set step %2" PetscInt_FMT ": the slipping nodes of a body that would slide within its friction stick\n", as->total + 1));
    }
  }
  PetscCall(PetscSNPrintf(when, sizeof(when), "once the contact opens (active-set step %" PetscInt_FMT ": %" PetscInt_FMT " of %" PetscInt_FMT " contact nodes closed)", as->total + 1, as->nclosed, as->nn));
  PetscCall(M2dSupportsCheck(&pb->supports, comm, &pb->s, &pb->contact, as->rule, when));
  PetscCall(PetscArraycpy(as->used, as->rule, as->n));
  PetscCall(PetscArraycpy(as->usedcoef, as->coef, as->n));
  as->forced = PETSC_FALSE;
  as->step++;
  as->total++;
  PetscFunctionReturn(0);
}

static PetscErrorCode ActiveSetJacobian(SNES snes, Vec x, Mat J, Mat P, void *ctx)
{
  M2dActiveSet *as = (M2dActiveSet *)ctx;

  PetscFunctionBeginUser;
  (void)x;
  (void)J;
  (void)P;
  PetscCall(ChooseSet(as, PetscObjectComm((PetscObject)snes)));
  PetscCall(as->ops->jacobian(as));
  PetscFunctionReturn(0);
}

/* the VI solver's: its Jacobian is built once (VISetup), its set followed after each step */
static PetscErrorCode SolverJacobian(SNES snes, Vec x, Mat J, Mat P, void *ctx)
{
  PetscFunctionBeginUser;
  (void)snes, (void)x, (void)J, (void)P, (void)ctx;
  PetscFunctionReturn(0);
}

static PetscErrorCode SolverStep(SNES snes, PetscInt it, PetscReal fnorm, void *ctx)
{
  PetscFunctionBeginUser;
  (void)fnorm;
  if (it > 0) PetscCall(ChooseSet((M2dActiveSet *)ctx, PetscObjectComm((PetscObject)snes)));
  PetscFunctionReturn(0);
}

/* Converged: the rules at the iterate are those the last step solved (a
 * direct solve: the iterate is that step's exact answer), and, for an
 * inexact solve, the residual at tolerance. */
static PetscErrorCode Converged(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm, SNESConvergedReason *reason, void *ctx)
{
  M2dActiveSet *as = (M2dActiveSet *)ctx;
  PetscReal     atol, rtol, stol;
  PetscInt      maxit, maxf;
  PetscBool     same = (PetscBool)(as->changed == 0);

  PetscFunctionBeginUser;
  (void)xnorm;
  (void)snorm;
  PetscCall(SNESGetTolerances(snes, &atol, &rtol, &stol, &maxit, &maxf));
  *reason = SNES_CONVERGED_ITERATING;
  if (it == 0) as->fnorm0 = fnorm;
  if (as->hist.failed) *reason = SNES_DIVERGED_LOCAL_MIN;
  else if (PetscIsInfOrNanReal(fnorm)) *reason = SNES_DIVERGED_FNORM_NAN;
  else if (same && ((as->exact && it > 0) || fnorm <= atol || fnorm <= rtol * as->fnorm0)) *reason = it > 0 ? SNES_CONVERGED_FNORM_RELATIVE : SNES_CONVERGED_FNORM_ABS;
  else if (it >= maxit) *reason = SNES_DIVERGED_MAX_IT;
  if (as->ops->watch) PetscCall(as->ops->watch(as, it, fnorm));
  PetscFunctionReturn(0);
}

/* one line per step: the states at the iterate, how many rows changed, |F| */
static PetscErrorCode Monitor(SNES snes, PetscInt it, PetscReal fnorm, void *ctx)
{
  M2dActiveSet *as   = (M2dActiveSet *)ctx;
  MPI_Comm      comm = PetscObjectComm((PetscObject)snes);

  PetscFunctionBeginUser;
  (void)it;
  if (!as->monitor) PetscFunctionReturn(0);
  if (as->partner) PetscCall(PetscPrintf(comm, "  active set step %2" PetscInt_FMT ": %6" PetscInt_FMT " closed (%" PetscInt_FMT " stick, %" PetscInt_FMT " slip), %" PetscInt_FMT " rows changed  |F| %.3e\n", as->total, as->nclosed, as->nstick, as->nslip, as->changed, (double)fnorm));
  else PetscCall(PetscPrintf(comm, "  active set step %2" PetscInt_FMT ": %6" PetscInt_FMT " closed, %" PetscInt_FMT " changed  |F| %.3e\n", as->total, as->nclosed, as->changed, (double)fnorm));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------- set-up */

/* newtonls with full steps (PDAS) and MUMPS LU, or vinewtonrsls; then the
 * options database; the path's table */
static PetscErrorCode ConfigureSNES(M2dActiveSet *as, M2dSolverPath path)
{
  SNES           snes = as->snes;
  MPI_Comm       comm = PetscObjectComm((PetscObject)snes);
  SNESLineSearch ls;
  KSP            ksp;
  PC             pc;
  PetscBool      ok, pre, vi;

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
  PetscCall(PetscObjectTypeCompare((PetscObject)snes, SNESVINEWTONRSLS, &vi));
  if (vi) { /* -snes_type resets the line search: full steps again, unless the options say otherwise */
    PetscCall(SNESGetLineSearch(snes, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
    PetscCall(SNESLineSearchSetFromOptions(ls));
  }
  PetscCall(PetscObjectTypeCompare((PetscObject)snes, SNESNEWTONLS, &ok));
  PetscCheck(ok || vi, comm, PETSC_ERR_USER_INPUT, "option -snes_type: contact is solved with newtonls (primal-dual active set) or vinewtonrsls");
  PetscCheck(!vi || !as->partner, comm, PETSC_ERR_USER_INPUT, "option -snes_type vinewtonrsls: PETSc's VI solver bounds the pressure only; with friction use the default newtonls (the condensed or full path)");
  if (path != M2D_PATH_ITERATIVE) PetscCall(KKTSetupKSP(as->kkt, ksp)); /* the iterative path solves by blocks */
  PetscCall(PetscObjectTypeCompare((PetscObject)ksp, KSPPREONLY, &pre));
  as->exact = (PetscBool)(path == M2D_PATH_CONDENSED || (path == M2D_PATH_FULL && pre));
  as->ops   = vi ? &M2dPathVI : path == M2D_PATH_CONDENSED ? &M2dPathCondensed : path == M2D_PATH_ITERATIVE ? &M2dPathIterative : &M2dPathFull;
  PetscFunctionReturn(0);
}

/* the rows' data (every rank), c, h, the tie tolerance, the work vectors */
static PetscErrorCode ContextCreate(M2dProblem *pb, M2dActiveSet *as)
{
  const M2dContact *ct = &pb->contact;
  PetscInt          ne = 0;

  PetscFunctionBeginUser;
  as->pb              = pb;
  as->kkt             = &pb->kkt;
  as->c               = pb->s.contact_c_set ? pb->s.contact_c : ActiveSetDefaultC(&pb->s, ct);
  as->monitor         = pb->s.contact_monitor;
  as->hist.max_cycles = 5;
  as->n               = ct->R.n;
  as->nn              = ct->nnormal;
  as->partner         = as->kkt->partner;
  for (PetscInt k = 0; k < ct->npair; k++) {
    for (PetscInt e = 0; e < ct->pair[k].nm.nedge; e++) as->h += ct->pair[k].nm.len[e];
    ne += ct->pair[k].nm.nedge;
  }
  as->h /= PetscMax(1, ne);
  PetscCall(PetscCalloc6(as->n + 1, &as->mu, as->n + 1, &as->tol, as->n + 1, &as->rule, as->n + 1, &as->coef, as->n + 1, &as->used, as->n + 1, &as->usedcoef));
  for (PetscInt j = 0; j < as->n; j++) {
    as->tol[j] = 1e-12 * ct->R.w[j];
    as->mu[j]  = ct->pair[ct->rowpair[j]].mu;
  }
  PetscCall(VecDuplicate(pb->kkt.r, &as->lam));
  PetscCall(VecDuplicate(pb->kkt.r, &as->gm));
  PetscCall(VecDuplicate(pb->kkt.r, &as->active));
  PetscCall(VecDuplicate(pb->kkt.r, &as->slip));
  PetscCall(VecDuplicate(pb->f, &as->u));
  PetscCall(VecScatterCreateToAll(as->lam, &as->toall, &as->lamall));
  PetscCall(VecDuplicate(as->lamall, &as->gmall));
  PetscFunctionReturn(0);
}

typedef struct {
  PetscReal g;
  PetscInt  j;
} GapRow;

static int CmpGapRow(const void *a, const void *b)
{
  const GapRow *p = (const GapRow *)a, *q = (const GapRow *)b;
  if (p->g != q->g) return p->g < q->g ? -1 : 1;
  return (p->j > q->j) - (p->j < q->j);
}

/* The closest nodes do not hold every body (a free cylinder on its tip: its
 * rolling is free): close each pair's nodes in the order of their gaps, 2, 4,
 * 8, ... of them, until the bodies are held (or every node is closed) */
static PetscErrorCode CloseUntilHeld(M2dActiveSet *as, const PetscScalar r[])
{
  const M2dContact *ct = &as->pb->contact;
  GapRow           *o;
  PetscBool         held;

  PetscFunctionBeginUser;
  PetscCall(M2dSupportsHeld(&as->pb->supports, PetscObjectComm((PetscObject)as->lam), ct, as->used, &held));
  if (held) PetscFunctionReturn(0);
  PetscCall(PetscMalloc1(as->nn + 1, &o));
  for (PetscInt k = 2; !held && k < 2 * as->nn; k *= 2) {
    for (PetscInt q = 0; q < ct->npair; q++) {
      const M2dContactPair *p = &ct->pair[q];
      for (PetscInt i = 0; i < p->R.n; i++) o[i] = (GapRow){PetscRealPart(r[p->off + i]) / p->R.w[i], p->off + i};
      qsort(o, (size_t)p->R.n, sizeof(GapRow), CmpGapRow);
      for (PetscInt i = 0; i < PetscMin(k, p->R.n); i++) as->used[o[i].j] = 1.0;
    }
    for (PetscInt j = as->nn; j < as->n; j++) as->used[j] = as->used[as->partner[j]];
    PetscCall(M2dSupportsHeld(&as->pb->supports, PetscObjectComm((PetscObject)as->lam), ct, as->used, &held));
  }
  PetscCall(PetscFree(o));
  PetscFunctionReturn(0);
}

/* The first load step's states: the previous mesh's (pb->warm), every
 * candidate (-contact_initial all), the closed gaps (gap), or the nodes whose
 * nodal gap g~0/w is within 1e-6 of the mortar surface's size of the smallest
 * one (closest: every body held from the first step, CloseUntilHeld; gaps in
 * reference displacements, sizes in reference lengths: L/U converts). A
 * closed node sticks. */
static PetscErrorCode InitialRules(M2dActiveSet *as)
{
  const M2dContact *ct = &as->pb->contact;
  const PetscScalar *r;
  Vec                rall;
  PetscInt           how = as->pb->s.contact_initial == 0 && as->ops->bounds_by_solver ? 1 : as->pb->s.contact_initial, np = ct->npair; /* the VI solver's: at least the closest nodes (VILoad) */
  PetscReal         *gmin, *L;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(np, &gmin, np, &L));
  for (PetscInt k = 0; k < np; k++) {
    const M2dSurface *m = &ct->pair[k].m;
    L[k]    = PetscSqrtReal(PetscSqr(m->hi[0] - m->lo[0]) + PetscSqr(m->hi[1] - m->lo[1])) * as->pb->units.L / as->pb->units.U;
    gmin[k] = PETSC_MAX_REAL;
  }
  PetscCall(VecDuplicate(as->lamall, &rall));
  PetscCall(VecScatterBegin(as->toall, as->kkt->r, rall, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(as->toall, as->kkt->r, rall, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(rall, &r));
  for (PetscInt j = 0; j < as->nn; j++) gmin[ct->rowpair[j]] = PetscMin(gmin[ct->rowpair[j]], PetscRealPart(r[j]) / ct->R.w[j]);
  for (PetscInt j = 0; j < as->n; j++) {
    PetscInt  p = as->partner ? as->partner[j] : -1, k = ct->rowpair[j];
    PetscReal g = PetscRealPart(r[j]);
    if (p >= 0) as->used[j] = as->used[p];
    else if (as->pb->warm) as->used[j] = as->pb->warm[j];
    else as->used[j] = (how == 2 || (how == 0 ? g <= 1e-12 * ct->R.w[j] : g / ct->R.w[j] <= gmin[k] + 1e-6 * L[k])) ? 1.0 : 0.0;
    as->usedcoef[j] = 0;
  }
  if (how == 1 && !as->pb->warm) PetscCall(CloseUntilHeld(as, r));
  PetscCall(VecRestoreArrayRead(rall, &r));
  PetscCall(VecDestroy(&rall));
  PetscCall(PetscFree2(gmin, L));
  PetscFunctionReturn(0);
}

/* ---------------------------------------------------------------- failures */

/* one line for an iteration that ended without an answer */
static PetscErrorCode Failed(M2dActiveSet *as, SNESConvergedReason reason, PetscInt steps)
{
  SNES               snes = as->snes;
  MPI_Comm           comm = PetscObjectComm((PetscObject)snes);
  KSP                ksp;
  KSPConvergedReason kr;
  const M2dProblem  *pb = as->pb;
  PetscReal          cr = pb->s.contact_c_set ? pb->s.contact_c / ActiveSetDefaultC(&pb->s, &pb->contact) : 1;

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
  if (as->ops->failed) PetscCall(as->ops->failed(as, steps));
  PetscCheck(!as->hist.failed, comm, PETSC_ERR_NOT_CONVERGED, "active set keeps cycling (%" PetscInt_FMT " cycles after raising c to %g): no solution found (check the load direction and the supports)", as->hist.cycles, (double)(as->c * CUser(as->pb)));
  PetscCheck(reason != SNES_DIVERGED_MAX_IT, comm, PETSC_ERR_NOT_CONVERGED, "active set did not settle in %" PetscInt_FMT " steps (-snes_max_it)", steps);
  PetscCheck(kr >= 0, comm, PETSC_ERR_NOT_CONVERGED, "linear solve in active-set step %" PetscInt_FMT " failed (%s): is every body held (by supports, or by contact)?", steps, KSPConvergedReasons[kr]);
  SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "active-set iteration failed: %s", SNESConvergedReasons[reason]);
}

/* ---------------------------------------------------------------- the API */

PetscErrorCode M2dActiveSetCreate(M2dProblem *pb, M2dSolverPath path, M2dActiveSet **asp)
{
  M2dActiveSet *as;
  MPI_Comm      comm = PetscObjectComm((PetscObject)pb->f);

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&as));
  *asp = as;
  PetscCall(ContextCreate(pb, as));
  PetscCall(SNESCreate(comm, &as->snes));
  PetscCall(ConfigureSNES(as, path));
  PetscCheck(!as->partner || path != M2D_PATH_ITERATIVE, comm, PETSC_ERR_USER_INPUT, "option -kkt_path iterative: friction (-contact_friction) is solved on the condensed path (the default) or -kkt_path full");
  PetscCall(VecDuplicate(as->ops->lambda_only ? pb->kkt.r : pb->kkt.x, &as->x));
  PetscCall(VecDuplicate(as->x, &as->F));
  PetscCall(SNESSetFunction(as->snes, as->F, ActiveSetFunction, as));
  PetscCall(as->ops->setup(as, &as->setup)); /* the paths' options are read here */
  PetscCall(M2dOptionsCheckUnused(comm, ProblemPathSays(&pb->s, path))); /* the solvers are configured: an option nobody read is a typo */
  if (as->ops->bounds_by_solver) { /* the solver's steps and stop; its set followed after each step */
    PetscCall(SNESSetJacobian(as->snes, as->J, as->J, SolverJacobian, as));
    PetscCall(SNESMonitorSet(as->snes, SolverStep, as, NULL));
  } else { /* the set chosen before each step's matrix; the loop's stop */
    PetscCall(SNESSetJacobian(as->snes, as->J, as->J, ActiveSetJacobian, as));
    PetscCall(SNESSetConvergenceTest(as->snes, Converged, as, NULL));
  }
  PetscCall(SNESMonitorSet(as->snes, Monitor, as, NULL));
  PetscCall(PetscPrintf(comm, "active set: %s, c = %g, %" PetscInt_FMT " candidate nodes%s\n", as->ops->name, (double)(as->c * CUser(pb)), as->nn, as->partner ? ", Coulomb friction" : ""));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dActiveSetStep(M2dActiveSet *as, Vec u, Vec lam, Vec active, Vec slip, M2dActiveSetInfo *info)
{
  MPI_Comm            comm = PetscObjectComm((PetscObject)as->snes);
  SNESConvergedReason reason;
  PetscInt            its;

  PetscFunctionBeginUser;
  if (!as->started) {
    PetscCall(InitialRules(as));
    PetscCall(VecZeroEntries(as->x));
  }
  PetscCall(as->ops->load(as));
  as->forced  = (PetscBool)!as->ops->bounds_by_solver; /* the step's first solve takes the states it is given (the solver's: lambda > 0) */
  as->step    = 0;
  as->hist.n  = 0;
  PetscCall(SNESSolve(as->snes, NULL, as->x));
  PetscCall(SNESGetConvergedReason(as->snes, &reason));
  PetscCall(SNESGetIterationNumber(as->snes, &its));
  if (reason <= 0) PetscCall(Failed(as, reason, as->total));
  as->started = PETSC_TRUE;
  PetscCall(as->ops->finish(as, as->x, u, lam));
  if (!as->ops->bounds_by_solver) { /* the rows of the answer: open ones exactly 0, not round-off (the solver's: its bounds) */
    const PetscScalar *s;
    PetscScalar       *l;
    PetscInt           lo, hi;
    PetscCall(VecGetOwnershipRange(lam, &lo, &hi));
    PetscCall(VecGetArrayRead(as->slip, &s));
    PetscCall(VecGetArray(lam, &l));
    for (PetscInt j = lo; j < hi; j++)
      if (as->rule[j] == 0 && PetscRealPart(s[j - lo]) == 0) l[j - lo] = 0;
    PetscCall(VecRestoreArray(lam, &l));
    PetscCall(VecRestoreArrayRead(as->slip, &s));
  }
  PetscCall(VecCopy(as->active, active));
  if (slip) { /* the step's weighted slip r - C u, where the node is closed */
    const PetscScalar *g;
    PetscScalar       *sl;
    PetscInt           lo, hi;
    PetscCall(MatMult(as->kkt->C, u, as->gm));
    PetscCall(VecAYPX(as->gm, -1.0, as->kkt->r));
    PetscCall(VecGetOwnershipRange(slip, &lo, &hi));
    PetscCall(VecGetArrayRead(as->gm, &g));
    PetscCall(VecGetArray(slip, &sl));
    for (PetscInt j = lo; j < hi; j++)
      if (as->partner[j] >= 0 && as->rule[as->partner[j]] != 0) sl[j - lo] += g[j - lo];
    PetscCall(VecRestoreArray(slip, &sl));
    PetscCall(VecRestoreArrayRead(as->gm, &g));
  }
  info->factor_time        = as->setup.factor_time;
  info->factor_flops       = as->setup.factor_flops;
  info->factor_flops_max   = as->setup.factor_flops_max;
  info->interface_unknowns = as->setup.interface_unknowns;
  info->iterations         = as->total;
  info->nactive    = as->nclosed;
  info->nstick     = as->nstick;
  info->nslip      = as->nslip;
  info->cycles     = as->hist.cycles;
  info->c          = as->c;
  info->vi         = as->ops->bounds_by_solver;
  info->condensed  = as->ops->lambda_only;
  info->ksp_its_max = 1; /* direct solves, unless the path reports its own */
  if (as->ops->report) PetscCall(as->ops->report(as, info));
  if (as->partner) PetscCall(PetscPrintf(comm, "active set: converged in %" PetscInt_FMT " steps (%s), %" PetscInt_FMT " closed nodes: %" PetscInt_FMT " stick, %" PetscInt_FMT " slip\n", its, SNESConvergedReasons[reason], as->nclosed, as->nstick, as->nslip));
  else PetscCall(PetscPrintf(comm, "active set: converged in %" PetscInt_FMT " steps (%s), %" PetscInt_FMT " active nodes\n", its, SNESConvergedReasons[reason], as->nclosed));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dActiveSetDestroy(M2dActiveSet **asp, M2dActiveSetInfo *info)
{
  M2dActiveSet *as = *asp;

  PetscFunctionBeginUser;
  if (!as) PetscFunctionReturn(0);
  if (as->ops) PetscCall(as->ops->destroy(as, info && as->pb->keep_factor ? info : NULL));
  PetscCall(SNESDestroy(&as->snes));
  PetscCall(VecDestroy(&as->x));
  PetscCall(VecDestroy(&as->F));
  PetscCall(MatDestroy(&as->J));
  PetscCall(VecDestroy(&as->lam));
  PetscCall(VecDestroy(&as->gm));
  PetscCall(VecDestroy(&as->active));
  PetscCall(VecDestroy(&as->slip));
  PetscCall(VecDestroy(&as->lamall));
  PetscCall(VecDestroy(&as->gmall));
  PetscCall(VecDestroy(&as->u));
  PetscCall(VecScatterDestroy(&as->toall));
  PetscCall(PetscFree6(as->mu, as->tol, as->rule, as->coef, as->used, as->usedcoef));
  PetscCall(PetscFree(*asp));
  PetscFunctionReturn(0);
}

PetscErrorCode ActiveSetHeldBy(M2dActiveSet *as, Vec m, PetscBool *held)
{
  const PetscScalar *a;
  PetscReal         *mask;
  Vec                all;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(as->lamall, &all));
  PetscCall(VecScatterBegin(as->toall, m, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(as->toall, m, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(PetscMalloc1(as->n + 1, &mask));
  PetscCall(VecGetArrayRead(all, &a));
  for (PetscInt j = 0; j < as->n; j++) mask[j] = PetscRealPart(a[j]) >= 0 ? 1.0 : 0.0;
  PetscCall(VecRestoreArrayRead(all, &a));
  PetscCall(M2dSupportsHeld(&as->pb->supports, PetscObjectComm((PetscObject)m), &as->pb->contact, mask, held));
  PetscCall(PetscFree(mask));
  PetscCall(VecDestroy(&all));
  PetscFunctionReturn(0);
}
