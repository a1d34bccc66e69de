/* dual.c - the dual problem of the contact pressure (see dual.h). */
#include "dual.h"

/* omega_j, every multiplier, every rank: the pressure's interpolation-error
 * indicator h^2 |lambda''| / 8 along the non-mortar surface (second
 * differences over the node's two neighbours; 0 at the ends), scaled to max
 * 1, blended with the pressure's own shape (lambda / max lambda) in the share
 * M2D_DUAL_SHAPE: the first localises the dual at the edge of the contact
 * zone where the pressure error lives, the second gives it the global reach
 * that makes the far field's compliance (which moves the zone's edge) count */
#define M2D_DUAL_SHAPE 0.1
static PetscErrorCode DualWeights(const M2dProblem *pb, const M2dSolution *sol, PetscReal omega[])
{
  const M2dContact  *ct = &pb->contact;
  const M2dSurface  *nm = &ct->nm;
  Vec                all;
  VecScatter         sc;
  const PetscScalar *l;
  PetscInt          *mult, n = ct->R.n;
  PetscReal          wmax = 0;

  PetscFunctionBeginUser;
  PetscCall(VecScatterCreateToAll(sol->lam, &sc, &all));
  PetscCall(VecScatterBegin(sc, sol->lam, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, sol->lam, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(PetscMalloc1(nm->nnode + 1, &mult));
  for (PetscInt i = 0; i < nm->nnode; i++) mult[i] = -1;
  for (PetscInt j = 0; j < n; j++) mult[ct->R.node[j]] = j;
  PetscCall(VecGetArrayRead(all, &l));
  for (PetscInt j = 0; j < n; j++) {
    PetscInt  i = ct->R.node[j], nb[2], k = 0;
    PetscReal lv[2], h[2], li = PetscRealPart(l[j]);
    omega[j] = 0;
    for (PetscInt q = nm->n2e_ptr[i]; q < nm->n2e_ptr[i + 1] && k < 2; q++) {
      PetscInt e = nm->n2e[q], o = nm->edge[2 * e] == i ? nm->edge[2 * e + 1] : nm->edge[2 * e];
      nb[k]      = o;
      h[k]       = nm->len[e];
      lv[k]      = mult[o] >= 0 ? PetscRealPart(l[mult[o]]) : 0.0;
      k++;
    }
    if (k < 2) continue;
    /* h^2/8 |lambda''|, lambda'' from the three nodes' nonuniform second difference */
    omega[j] = PetscSqr(0.5 * (h[0] + h[1])) / 8 * PetscAbsReal(2 * ((lv[1] - li) / h[1] - (li - lv[0]) / h[0]) / (h[0] + h[1]));
    wmax     = PetscMax(wmax, omega[j]);
    (void)nb;
  }
  {
    PetscReal lmax = 0, mix = M2D_DUAL_SHAPE;
    for (PetscInt j = 0; j < n; j++) lmax = PetscMax(lmax, PetscRealPart(l[j]));
    for (PetscInt j = 0; j < n; j++) omega[j] = (1 - mix) * (wmax > 0 ? omega[j] / wmax : 0) + mix * (lmax > 0 ? PetscRealPart(l[j]) / lmax : 0);
  }
  PetscCall(VecRestoreArrayRead(all, &l));
  PetscCall(PetscFree(mult));
  PetscCall(VecDestroy(&all));
  PetscCall(VecScatterDestroy(&sc));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dDualSolve(M2dProblem *pb, const M2dSolution *sol, Vec z)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)z);
  M2dScene           s    = pb->s;
  M2dKKT             dk;
  KSP                ksp;
  PC                 pc;
  Vec                rhs;
  const PetscScalar *a;
  PetscScalar       *r;
  PetscReal         *omega;
  PetscInt           lo, hi;

  PetscFunctionBeginUser;
  s.kkt_mat     = M2D_KKT_AIJ;
  s.kkt_augment = 0;
  PetscCall(KKTCreate(&s, PETSC_FALSE, &pb->Rkkt, pb->K, pb->f, pb->ubc, pb->ndir, pb->drows, &dk));
  PetscCall(KKTSetActive(&dk, sol->active, 1.0, 1.0)); /* the final set: active rows C_j, the others mu_j = 0 */
  PetscCall(PetscMalloc1(pb->contact.R.n + 1, &omega));
  PetscCall(DualWeights(pb, sol, omega));
  PetscCall(VecDuplicate(dk.r, &rhs));
  PetscCall(VecGetOwnershipRange(rhs, &lo, &hi));
  PetscCall(VecGetArrayRead(sol->active, &a));
  PetscCall(VecGetArrayWrite(rhs, &r));
  for (PetscInt j = lo; j < hi; j++) /* opening w_j omega_j on the active set */
    r[j - lo] = PetscRealPart(a[j - lo]) != 0 ? pb->contact.R.w[j] * omega[j] : 0.0;
  PetscCall(VecRestoreArrayWrite(rhs, &r));
  PetscCall(VecRestoreArrayRead(sol->active, &a));
  PetscCall(VecZeroEntries(dk.b));
  PetscCall(VecISCopy(dk.b, dk.isl, SCATTER_FORWARD, rhs));
  PetscCall(KSPCreate(comm, &ksp));
  PetscCall(KSPSetOptionsPrefix(ksp, "dual_"));
  PetscCall(KSPSetOperators(ksp, dk.A, dk.A));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(KSPSolve(ksp, dk.b, dk.x));
  {
    KSPConvergedReason reason;
    PetscCall(KSPGetConvergedReason(ksp, &reason));
    PetscCheck(reason > 0, comm, PETSC_ERR_NOT_CONVERGED, "the dual problem of the contact pressure (-adapt_goal contact) could not be solved: %s", KSPConvergedReasons[reason]);
  }
  PetscCall(VecISCopy(dk.x, dk.isu, SCATTER_REVERSE, z));
  PetscCall(M2dFramesRotateGlobal(&pb->frames, &pb->mesh, z, PETSC_TRUE));
  PetscCall(KSPDestroy(&ksp));
  PetscCall(VecDestroy(&rhs));
  PetscCall(PetscFree(omega));
  PetscCall(KKTDestroy(&dk));
  PetscFunctionReturn(0);
}
