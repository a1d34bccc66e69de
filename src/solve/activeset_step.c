/* activeset_step.c - one active-set step (activeset_step.h): the active mask
 * at an iterate (the complementarity test lambda/c + g~ >= 0), the residual
 * of the semismooth Newton iteration, and the set its Jacobian uses (the mask,
 * unless the iteration cycles; a set that leaves a body free is refused). */
#include "activeset_step.h"

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
      if (as->iter && !as->proving) { /* an inexact step's set may have been wrong: prove the sets from here before raising c */
        as->proving = PETSC_TRUE;
        PetscCall(PetscPrintf(comm, "  active set back to the set of step %" PetscInt_FMT " at step %" PetscInt_FMT ": each step's set proven from here\n", k, as->step));
        break;
      }
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

