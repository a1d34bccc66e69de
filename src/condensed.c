/* condensed.c - factor once with a MUMPS Schur complement; the reduced iteration's algebra (see condensed.h). */
#include "condensed.h"

PetscErrorCode CondensedCreate(KKT *kkt, M2dOrdering ord, Condensed *cs)
{
  MPI_Comm      comm = PetscObjectComm((PetscObject)kkt->A);
  PetscMPIInt   size;
  IS            perm = NULL;
  MatFactorInfo info;
  MatFactorError ferr;
  PetscLogDouble t0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(cs, sizeof(*cs)));
  PetscCheck(kkt->gamma > 0 && kkt->aij, comm, PETSC_ERR_PLIB, "condensed path needs the augmented monolithic KKT matrix");
  cs->kkt = kkt;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCheck(size == 1, comm, PETSC_ERR_SUP, "option -kkt_path condensed: one rank only (PETSc 3.18 solves with MUMPS Schur complements sequentially)");
  t0 = MPI_Wtime();
  PetscCall(MatGetFactor(kkt->A, MATSOLVERMUMPS, MAT_FACTOR_LU, &cs->F));
  PetscCall(MatFactorSetSchurIS(cs->F, kkt->isl));
  PetscCall(MatFactorInfoInitialize(&info));
  if (ord == M2D_ORDERING_METIS) PetscCall(M2dOrderingMetis(kkt->A, kkt->isl, &perm));
  PetscCall(MatLUFactorSymbolic(cs->F, kkt->A, perm, perm, &info));
  PetscCall(ISDestroy(&perm));
  PetscCall(MatLUFactorNumeric(cs->F, kkt->A, &info));
  PetscCall(MatFactorGetError(cs->F, &ferr));
  PetscCheck(ferr == MAT_FACTOR_NOERROR, comm, PETSC_ERR_USER_INPUT, "the stiffness with every candidate contact node tied is singular: a body is held by nothing (check -dirichlet and the contact pair)");
  cs->factor_time = MPI_Wtime() - t0;
  PetscCall(MatFactorCreateSchurComplement(cs->F, &cs->S0, NULL));
  PetscCall(MatFactorFactorizeSchurComplement(cs->F)); /* every solve uses S0 */
  PetscCall(VecDuplicate(kkt->b, &cs->rhs));
  PetscCall(VecDuplicate(kkt->b, &cs->sol));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedReducedSetup(Condensed *cs)
{
  KKT *kkt = cs->kkt;
  Vec  cu, u0, nu0;

  PetscFunctionBeginUser;
  PetscCheck(cs->S0 && !cs->w, PetscObjectComm((PetscObject)kkt->A), PETSC_ERR_PLIB, "reduced iteration: needs one rank and one setup");
  /* M [u0; nu0] = [f; 0] */
  PetscCall(VecZeroEntries(cs->rhs));
  PetscCall(VecISCopy(cs->rhs, kkt->isu, SCATTER_FORWARD, kkt->f));
  PetscCall(MatSolve(cs->F, cs->rhs, cs->sol));
  /* C u0 = w + S0 nu0 (= 0 up to round-off) gives w = C u0 - S0 nu0 */
  PetscCall(VecDuplicate(kkt->f, &u0));
  PetscCall(VecDuplicate(kkt->r, &nu0));
  PetscCall(VecISCopy(cs->sol, kkt->isu, SCATTER_REVERSE, u0));
  PetscCall(VecISCopy(cs->sol, kkt->isl, SCATTER_REVERSE, nu0));
  PetscCall(VecDuplicate(kkt->r, &cs->w));
  PetscCall(VecZeroEntries(cs->w));
  PetscCall(VecDuplicate(kkt->r, &cu));
  PetscCall(CondensedReducedGaps(cs, nu0, cu)); /* S0 nu0 (w = 0 still) */
  PetscCall(MatMult(kkt->C, u0, cs->w));
  PetscCall(VecAXPY(cs->w, -1.0, cu));
  PetscCall(VecDestroy(&cu));
  PetscCall(VecDestroy(&u0));
  PetscCall(VecDestroy(&nu0));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedReducedGaps(Condensed *cs, Vec nu, Vec cu)
{
  const PetscScalar *S, *v, *w;
  PetscScalar       *y;
  PetscInt           n, lda;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(nu, &n));
  PetscCall(MatDenseGetLDA(cs->S0, &lda));
  PetscCall(MatDenseGetArrayRead(cs->S0, &S));
  PetscCall(VecGetArrayRead(nu, &v));
  PetscCall(VecGetArrayRead(cs->w, &w));
  PetscCall(VecGetArray(cu, &y));
  for (PetscInt i = 0; i < n; i++) y[i] = w[i];
  for (PetscInt j = 0; j < n; j++) /* column-major: y += S(:, j) v_j */
    for (PetscInt i = 0; i < n; i++) y[i] += S[i + j * lda] * v[j];
  PetscCall(VecRestoreArray(cu, &y));
  PetscCall(VecRestoreArrayRead(cs->w, &w));
  PetscCall(VecRestoreArrayRead(nu, &v));
  PetscCall(MatDenseRestoreArrayRead(cs->S0, &S));
  PetscCall(PetscLogFlops(2.0 * n * n));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedReducedJacobian(Condensed *cs, Vec active, PetscReal c, PetscReal h, Mat J)
{
  const PetscScalar *S, *a;
  PetscScalar       *Jv;
  PetscInt           n, lda, ldj;
  PetscReal          g = cs->kkt->gamma;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(active, &n));
  PetscCall(MatDenseGetLDA(cs->S0, &lda));
  PetscCall(MatDenseGetLDA(J, &ldj));
  PetscCall(MatDenseGetArrayRead(cs->S0, &S));
  PetscCall(VecGetArrayRead(active, &a));
  PetscCall(MatDenseGetArrayWrite(J, &Jv));
  for (PetscInt j = 0; j < n; j++)
    for (PetscInt i = 0; i < n; i++) Jv[i + j * ldj] = PetscRealPart(a[i]) != 0 ? c * h * S[i + j * lda] : -h * (g * S[i + j * lda] + (i == j ? 1.0 : 0.0));
  PetscCall(MatDenseRestoreArrayWrite(J, &Jv));
  PetscCall(VecRestoreArrayRead(active, &a));
  PetscCall(MatDenseRestoreArrayRead(cs->S0, &S));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedRecover(Condensed *cs, Vec nu, Vec u)
{
  KKT *kkt = cs->kkt;
  Vec  cu;

  PetscFunctionBeginUser;
  /* M [u; nu'] = [f; C u(nu)] with the pristine S0 gives nu' = nu and u = u(nu) */
  PetscCall(VecDuplicate(kkt->r, &cu));
  PetscCall(CondensedReducedGaps(cs, nu, cu));
  PetscCall(VecISCopy(cs->rhs, kkt->isu, SCATTER_FORWARD, kkt->f));
  PetscCall(VecISCopy(cs->rhs, kkt->isl, SCATTER_FORWARD, cu));
  PetscCall(MatSolve(cs->F, cs->rhs, cs->sol));
  PetscCall(VecISCopy(cs->sol, kkt->isu, SCATTER_REVERSE, u));
  PetscCall(VecDestroy(&cu));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedDestroy(Condensed *cs)
{
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&cs->w));
  PetscCall(MatDestroy(&cs->F));
  PetscCall(MatDestroy(&cs->S0));
  PetscCall(VecDestroy(&cs->rhs));
  PetscCall(VecDestroy(&cs->sol));
  PetscFunctionReturn(0);
}
