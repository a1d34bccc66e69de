/* Unit tests of kkt.c on any number of ranks (ctest: 1 and 2), on the grid
 * system of unit_grid.h with three Dirichlet dofs, two of them in row 0 of C:
 *  - KKTCreate: C = -B with the Dirichlet columns zero, and their part moved
 *    to the right-hand side: r = g0 - C_full u_D = g0 + B u_D;
 *  - KKTSetActive on the monolithic A (-kkt_mat aij, no augmentation): an
 *    active multiplier row is scale C_j with a zero diagonal, an inactive one
 *    -(scale/c) e_j. */
#include "kkt.h"
#include "unit_grid.h"

static const PetscInt  ndir_all             = 3;
static const PetscReal uval[3]              = {0.3, -0.2, 0.5};
static PetscInt        DirDof(int k)
{
  const PetscInt d[3] = {Dof(0, 2, 1), Dof(NX - 1, 2, 1), Dof(0, 2, 0)};
  return d[k];
}

/* the KKT system of the grid with the Dirichlet dofs above (owned ones listed by their rank) */
static PetscErrorCode CreateKKT(MPI_Comm comm, M2dContactRows *R, M2dKKT *kkt)
{
  Mat      K;
  Vec      f, ubc;
  PetscInt drows[3], nd = 0, lo, hi;

  PetscFunctionBeginUser;
  PetscCall(BuildK(comm, &K));
  PetscCall(MatCreateVecs(K, &ubc, &f));
  PetscCall(VecSet(f, 1.0));
  PetscCall(VecGetOwnershipRange(ubc, &lo, &hi));
  for (int k = 0; k < ndir_all; k++)
    if (DirDof(k) >= lo && DirDof(k) < hi) {
      drows[nd++] = DirDof(k);
      PetscCall(VecSetValue(ubc, DirDof(k), uval[k], INSERT_VALUES));
    }
  PetscCall(VecAssemblyBegin(ubc));
  PetscCall(VecAssemblyEnd(ubc));
  PetscCall(KKTCreate(M2D_KKT_AIJ, 0, PETSC_FALSE, R, NULL, K, f, ubc, nd, drows, kkt));
  PetscCall(MatDestroy(&K));
  PetscCall(VecDestroy(&f));
  PetscCall(VecDestroy(&ubc));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckCreate(MPI_Comm comm, const M2dContactRows *R, M2dKKT *kkt)
{
  PetscScalar *Cd, r[NC], rr[NC];
  PetscBool    ok = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(GatherDense(kkt->C, &Cd));
  for (PetscInt k = 0; k < NC; k++) {
    r[k] = R->g0[k];
    for (PetscInt e = R->ptr[k]; e < R->ptr[k + 1]; e++) {
      PetscReal ud  = 0;
      PetscBool dir = PETSC_FALSE;
      for (int d = 0; d < ndir_all; d++)
        if (R->col[e] == DirDof(d)) {
          ud  = uval[d];
          dir = PETSC_TRUE;
        }
      r[k] += R->val[e] * ud;
      ok = (PetscBool)(ok && Cd[k + R->col[e] * NC] == (dir ? 0.0 : -R->val[e]));
    }
  }
  Check(comm, ok, "KKTCreate: C = -B, its Dirichlet columns zero");
  PetscCall(GatherVec(kkt->r, rr));
  Check(comm, RelDiff(NC, rr, r) < 1e-14 && r[0] != R->g0[0], "KKTCreate: r = g0 + B u_D (%.1e)", (double)RelDiff(NC, rr, r));
  PetscCall(PetscFree(Cd));
  PetscFunctionReturn(0);
}

/* inactive rows (even k): -(scale/c) e_k; active: scale C_k, zero diagonal */
static PetscErrorCode CheckSetActive(MPI_Comm comm, M2dKKT *kkt)
{
  PetscReal       c = 2.0, scale = 3.0;
  PetscInt        N, NA, lo, hi;
  PetscScalar    *Cd, *Ad;
  IS              isu, isl;
  const PetscInt *iu, *il;
  Vec             act;
  PetscBool       ok = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(kkt->Ct, &act, NULL));
  PetscCall(VecGetOwnershipRange(act, &lo, &hi));
  for (PetscInt k = lo; k < hi; k++) PetscCall(VecSetValue(act, k, (PetscScalar)(k % 2), INSERT_VALUES));
  PetscCall(VecAssemblyBegin(act));
  PetscCall(VecAssemblyEnd(act));
  PetscCall(KKTSetActive(kkt, act, NULL, c, scale));
  PetscCall(MatGetSize(kkt->C, NULL, &N));
  PetscCall(MatGetSize(kkt->A, &NA, NULL));
  PetscCall(GatherDense(kkt->C, &Cd));
  PetscCall(GatherDense(kkt->A, &Ad));
  PetscCall(ISAllGather(kkt->isu, &isu));
  PetscCall(ISAllGather(kkt->isl, &isl));
  PetscCall(ISGetIndices(isu, &iu));
  PetscCall(ISGetIndices(isl, &il));
  for (PetscInt k = 0; k < NC; k++) {
    PetscInt row = il[k];
    for (PetscInt i = 0; i < N; i++) ok = (PetscBool)(ok && Ad[row + iu[i] * NA] == (k % 2 ? scale * Cd[k + i * NC] : 0.0));
    for (PetscInt m = 0; m < NC; m++) ok = (PetscBool)(ok && Ad[row + il[m] * NA] == (k % 2 || m != k ? 0.0 : -scale / c));
  }
  Check(comm, ok, "KKTSetActive: active rows scale C_j, inactive rows -(scale/c) e_j");
  PetscCall(ISRestoreIndices(isu, &iu));
  PetscCall(ISRestoreIndices(isl, &il));
  PetscCall(ISDestroy(&isu));
  PetscCall(ISDestroy(&isl));
  PetscCall(PetscFree(Ad));
  PetscCall(PetscFree(Cd));
  PetscCall(VecDestroy(&act));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  M2dContactRows R;
  M2dKKT         kkt;
  PetscInt       ptr[NC + 1], col[4 * NC];
  PetscReal      val[4 * NC], g0[NC];
  int            any;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscMemzero(&R, sizeof(R)));
  RowsB(ptr, col, val, g0);
  R.n   = NC;
  R.ptr = ptr;
  R.col = col;
  R.val = val;
  R.g0  = g0;
  PetscCall(CreateKKT(PETSC_COMM_WORLD, &R, &kkt));
  PetscCall(CheckCreate(PETSC_COMM_WORLD, &R, &kkt));
  PetscCall(CheckSetActive(PETSC_COMM_WORLD, &kkt));
  PetscCall(KKTDestroy(&kkt));
  PetscCallMPI(MPI_Allreduce(&failures, &any, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD));
  PetscCall(PetscFinalize());
  return any ? 1 : 0;
}
