/* dual.c - the dual problem of the contact pressure (see dual.h). */
#include "dual.h"
#include "condensed.h"

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
  Vec                all;
  VecScatter         sc;
  const PetscScalar *l;
  PetscInt          *mult, n = ct->R.n;
  PetscReal          wmax = 0;

  PetscFunctionBeginUser;
  PetscCall(VecScatterCreateToAll(sol->lam, &sc, &all));
  PetscCall(VecScatterBegin(sc, sol->lam, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, sol->lam, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(all, &l));
  for (PetscInt p = 0; p < ct->npair; p++) { /* each pair along its own non-mortar surface */
    const M2dContactPair *cp = &ct->pair[p];
    const M2dSurface     *nm = &cp->nm;
    PetscCall(PetscMalloc1(nm->nnode + 1, &mult));
    for (PetscInt i = 0; i < nm->nnode; i++) mult[i] = -1;
    for (PetscInt j = cp->off; j < cp->off + cp->R.n; j++) mult[ct->R.node[j]] = j;
    for (PetscInt j = cp->off; j < cp->off + cp->R.n; j++) {
      PetscInt  i = ct->R.node[j], k = 0;
      PetscReal lv[2], h[2], li = PetscRealPart(l[j]);
      omega[j] = 0;
      for (PetscInt q = nm->n2e_ptr[i]; q < nm->n2e_ptr[i + 1] && k < 2; q++) {
        PetscInt e = nm->n2e[q], o = nm->edge[2 * e] == i ? nm->edge[2 * e + 1] : nm->edge[2 * e];
        h[k]       = nm->len[e];
        lv[k]      = mult[o] >= 0 ? PetscRealPart(l[mult[o]]) : 0.0;
        k++;
      }
      if (k < 2) continue;
      /* h^2/8 |lambda''|, lambda'' from the three nodes' nonuniform second difference */
      omega[j] = PetscSqr(0.5 * (h[0] + h[1])) / 8 * PetscAbsReal(2 * ((lv[1] - li) / h[1] - (li - lv[0]) / h[0]) / (h[0] + h[1]));
      wmax     = PetscMax(wmax, omega[j]);
    }
    PetscCall(PetscFree(mult));
  }
  {
    PetscReal lmax = 0, mix = M2D_DUAL_SHAPE;
    for (PetscInt j = 0; j < n; j++) lmax = PetscMax(lmax, PetscRealPart(l[j]));
    for (PetscInt j = 0; j < n; j++) omega[j] = (1 - mix) * (wmax > 0 ? omega[j] / wmax : 0) + mix * (lmax > 0 ? PetscRealPart(l[j]) / lmax : 0);
  }
  PetscCall(VecRestoreArrayRead(all, &l));
  PetscCall(VecDestroy(&all));
  PetscCall(VecScatterDestroy(&sc));
  PetscFunctionReturn(0);
}

/* b_j = w_j omega_j on the final active set, 0 elsewhere (layout of the multipliers) */
static PetscErrorCode DualLoad(const M2dProblem *pb, const M2dSolution *sol, Vec b)
{
  const PetscScalar *a;
  PetscScalar       *r;
  PetscReal         *omega;
  PetscInt           lo, hi;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(pb->contact.R.n + 1, &omega));
  PetscCall(DualWeights(pb, sol, omega));
  PetscCall(VecGetOwnershipRange(b, &lo, &hi));
  PetscCall(VecGetArrayRead(sol->active, &a));
  PetscCall(VecGetArrayWrite(b, &r));
  for (PetscInt j = lo; j < hi; j++) r[j - lo] = PetscRealPart(a[j - lo]) != 0 ? pb->contact.R.w[j] * omega[j] : 0.0;
  PetscCall(VecRestoreArrayWrite(b, &r));
  PetscCall(VecRestoreArrayRead(sol->active, &a));
  PetscCall(PetscFree(omega));
  PetscFunctionReturn(0);
}

/* With the primal's condensed factorization (K_g = K + g C^T C, condensed.h):
 * K z + C^T mu = 0 is K_g z + C^T nu = 0 with nu = mu - g C z, so z =
 * -K_g^-1 C^T nu and C z = S0 nu; the rows are S0 nu = b (active) and mu =
 * nu + g S0 nu = 0 (inactive): the dense Jacobian of the active-set steps on
 * the final set (c = h = 1), one dense LU of the multipliers, then one
 * substitution without the load */
static PetscErrorCode DualSolveCondensed(M2dCondensed *cs, const M2dSolution *sol, Vec b, Vec z)
{
  Mat      J;
  Vec      nu;
  PetscInt n, N;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(b, &n));
  PetscCall(VecGetSize(b, &N));
  PetscCall(MatCreateDense(PetscObjectComm((PetscObject)b), n, n, N, N, NULL, &J));
  PetscCall(CondensedJacobian(cs, sol->active, 1.0, 1.0, J)); /* active rows S0, inactive -(I + g S0) */
  PetscCall(CondensedJacobianFactor(cs, J, NULL, NULL, NULL, 0, 0));
  PetscCall(VecDuplicate(b, &nu));
  PetscCall(CondensedJacobianSolve(cs, b, nu));
  PetscCall(CondensedRecover(cs, PETSC_FALSE, nu, z));
  PetscCall(VecDestroy(&nu));
  PetscCall(MatDestroy(&J));
  PetscFunctionReturn(0);
}

/* Otherwise: the KKT matrix of the final set factored by MUMPS (LU: the
 * inactive rows mu_j = 0 make it unsymmetric) */
static PetscErrorCode DualSolveKKT(M2dProblem *pb, const M2dSolution *sol, Vec b, Vec z)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)z);
  M2dKKT   dk;
  KSP      ksp;
  PC       pc;

  PetscFunctionBeginUser;
  PetscCall(KKTCreate(M2D_KKT_AIJ, 0, PETSC_FALSE, &pb->Rkkt, NULL, pb->K, pb->f, pb->ubc, pb->ndir, pb->drows, &dk));
  PetscCall(KKTSetActive(&dk, sol->active, NULL, 1.0, 1.0)); /* the final set: active rows C_j, the others mu_j = 0 */
  PetscCall(VecZeroEntries(dk.b));
  PetscCall(VecISCopy(dk.b, dk.isl, SCATTER_FORWARD, b));
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
  PetscCall(KSPDestroy(&ksp));
  PetscCall(KKTDestroy(&dk));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dDualSolve(M2dProblem *pb, const M2dSolution *sol, Vec z)
{
  Vec b;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(sol->lam, &b));
  PetscCall(DualLoad(pb, sol, b));
  if (sol->as.factor) PetscCall(DualSolveCondensed(sol->as.factor, sol, b, z));
  else PetscCall(DualSolveKKT(pb, sol, b, z));
  PetscCall(M2dFramesRotateGlobal(&pb->frames, &pb->mesh, z, PETSC_TRUE));
  PetscCall(VecDestroy(&b));
  PetscFunctionReturn(0);
}
