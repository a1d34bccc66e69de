/* condensed.c - factor once with a MUMPS Schur complement (see condensed.h). */
#include "condensed.h"

PetscErrorCode CondensedCreate(KKT *kkt, M2dOrdering ord, Condensed *cs)
{
  MPI_Comm      comm = PetscObjectComm((PetscObject)kkt->A);
  PetscMPIInt   rank, size;
  IS            isS, perm = NULL;
  MatFactorInfo info;
  Vec           all;
  VecScatter    sc;
  PetscInt      n = 0, *idx = NULL;
  MatFactorError ferr;
  PetscLogDouble t0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(cs, sizeof(*cs)));
  PetscCheck(kkt->gamma > 0 && kkt->aij, comm, PETSC_ERR_PLIB, "condensed path needs the augmented monolithic KKT matrix");
  cs->kkt = kkt;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  /* the multipliers' indices in A's numbering, all on rank 0 (MUMPS' centralised Schur) */
  {
    Vec li;
    PetscInt        lo, hi, nl;
    const PetscInt *il;
    PetscCall(VecDuplicate(kkt->r, &li));
    PetscCall(VecGetOwnershipRange(li, &lo, &hi));
    PetscCall(ISGetLocalSize(kkt->isl, &nl));
    PetscCall(ISGetIndices(kkt->isl, &il));
    for (PetscInt j = 0; j < nl; j++) PetscCall(VecSetValue(li, lo + j, (PetscScalar)il[j], INSERT_VALUES));
    PetscCall(ISRestoreIndices(kkt->isl, &il));
    PetscCall(VecAssemblyBegin(li));
    PetscCall(VecAssemblyEnd(li));
    PetscCall(VecScatterCreateToZero(li, &sc, &all));
    PetscCall(VecScatterBegin(sc, li, all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(sc, li, all, INSERT_VALUES, SCATTER_FORWARD));
    if (rank == 0) {
      const PetscScalar *a;
      PetscCall(VecGetSize(all, &n));
      PetscCall(PetscMalloc1(n + 1, &idx));
      PetscCall(VecGetArrayRead(all, &a));
      for (PetscInt j = 0; j < n; j++) idx[j] = (PetscInt)PetscRealPart(a[j]);
      PetscCall(VecRestoreArrayRead(all, &a));
    }
    cs->tozero = sc;
    cs->act0   = all;
    PetscCall(VecDestroy(&li));
  }
  PetscCall(ISCreateGeneral(comm, n, idx, PETSC_OWN_POINTER, &isS));
  t0 = MPI_Wtime();
  PetscCall(MatGetFactor(kkt->A, MATSOLVERMUMPS, MAT_FACTOR_LU, &cs->F));
  PetscCall(MatFactorSetSchurIS(cs->F, isS));
  PetscCall(MatFactorInfoInitialize(&info));
  if (ord == M2D_ORDERING_METIS && size == 1) PetscCall(M2dOrderingMetis(kkt->A, isS, &perm));
  PetscCall(MatLUFactorSymbolic(cs->F, kkt->A, perm, perm, &info));
  PetscCall(ISDestroy(&perm));
  PetscCall(MatLUFactorNumeric(cs->F, kkt->A, &info));
  PetscCall(MatFactorGetError(cs->F, &ferr));
  PetscCheck(ferr == MAT_FACTOR_NOERROR, comm, PETSC_ERR_USER_INPUT, "the stiffness with every candidate contact node tied is singular: a body is held by nothing (check -dirichlet and the contact pair)");
  cs->factor_time = MPI_Wtime() - t0;
  PetscCall(MatFactorCreateSchurComplement(cs->F, &cs->S0, NULL));
  PetscCall(ISDestroy(&isS));
  PetscCall(VecDuplicate(kkt->r, &cs->bl));
  PetscCall(VecDuplicate(kkt->r, &cs->dl));
  PetscCall(VecDuplicate(kkt->r, &cs->t));
  PetscCall(VecDuplicate(kkt->r, &cs->active));
  PetscCall(VecDuplicate(kkt->f, &cs->vu));
  PetscCall(VecDuplicate(kkt->b, &cs->rhs));
  PetscCall(VecDuplicate(kkt->b, &cs->sol));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedSetActive(Condensed *cs, Vec active, PetscReal c, PetscReal s)
{
  Mat S;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)active), &rank));
  cs->c = c;
  cs->s = s;
  PetscCall(VecCopy(active, cs->active));
  PetscCall(VecScatterBegin(cs->tozero, active, cs->act0, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(cs->tozero, active, cs->act0, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(MatFactorGetSchurComplement(cs->F, &S, NULL));
  PetscCall(MatSetUnfactored(S)); /* it holds the LU factors of the previous step */
  PetscCall(MatCopy(cs->S0, S, SAME_NONZERO_PATTERN));
  if (rank == 0) {
    const PetscScalar *a;
    PetscInt           n;
    PetscCall(VecGetSize(cs->act0, &n));
    PetscCall(VecGetArrayRead(cs->act0, &a));
    for (PetscInt j = 0; j < n; j++)
      if (PetscRealPart(a[j]) == 0) PetscCall(MatSetValue(S, j, j, 1.0 / cs->kkt->gamma, ADD_VALUES));
    PetscCall(VecRestoreArrayRead(cs->act0, &a));
  }
  PetscCall(MatAssemblyBegin(S, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(S, MAT_FINAL_ASSEMBLY));
  PetscCall(MatFactorRestoreSchurComplement(cs->F, &S, MAT_FACTOR_SCHUR_UNFACTORED));
  PetscCall(MatFactorFactorizeSchurComplement(cs->F));
  PetscFunctionReturn(0);
}

/* x = J^-1 b for the active set of the last CondensedSetActive */
PetscErrorCode CondensedApply(Condensed *cs, Vec b, Vec x)
{
  KKT               *kkt = cs->kkt;
  const PetscScalar *a, *bl;
  PetscScalar       *dl, *t;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(VecISCopy(b, kkt->isl, SCATTER_REVERSE, cs->bl));
  PetscCall(VecISCopy(b, kkt->isu, SCATTER_REVERSE, cs->vu));
  /* inactive rows give dlambda_I directly; active rows the constraint right-hand side t_A */
  PetscCall(VecGetLocalSize(cs->bl, &n));
  PetscCall(VecGetArrayRead(cs->active, &a));
  PetscCall(VecGetArrayRead(cs->bl, &bl));
  PetscCall(VecGetArray(cs->dl, &dl));
  PetscCall(VecGetArray(cs->t, &t));
  for (PetscInt j = 0; j < n; j++) {
    if (PetscRealPart(a[j]) != 0) {
      dl[j] = 0;
      t[j]  = bl[j] / cs->s;
    } else {
      dl[j] = -cs->c * bl[j] / cs->s;
      t[j]  = 0;
    }
  }
  PetscCall(VecRestoreArray(cs->t, &t));
  PetscCall(VecRestoreArray(cs->dl, &dl));
  PetscCall(VecRestoreArrayRead(cs->bl, &bl));
  PetscCall(VecRestoreArrayRead(cs->active, &a));
  /* b_u - C_I^T dlambda_I */
  PetscCall(VecScale(cs->dl, -1.0));
  PetscCall(MatMultAdd(kkt->Ct, cs->dl, cs->vu, cs->vu));
  PetscCall(VecScale(cs->dl, -1.0));
  PetscCall(VecISCopy(cs->rhs, kkt->isu, SCATTER_FORWARD, cs->vu));
  PetscCall(VecISCopy(cs->rhs, kkt->isl, SCATTER_FORWARD, cs->t));
  PetscCall(MatSolve(cs->F, cs->rhs, cs->sol));
  /* du, and dlambda_A = nu_A + g t_A */
  PetscCall(VecISCopy(cs->sol, kkt->isu, SCATTER_REVERSE, cs->vu));
  PetscCall(VecISCopy(cs->sol, kkt->isl, SCATTER_REVERSE, cs->bl));
  PetscCall(VecAXPY(cs->bl, kkt->gamma, cs->t));
  PetscCall(VecGetArrayRead(cs->active, &a));
  PetscCall(VecGetArray(cs->dl, &dl));
  PetscCall(VecGetArrayRead(cs->bl, &bl));
  for (PetscInt j = 0; j < n; j++)
    if (PetscRealPart(a[j]) != 0) dl[j] = bl[j];
  PetscCall(VecRestoreArrayRead(cs->bl, &bl));
  PetscCall(VecRestoreArray(cs->dl, &dl));
  PetscCall(VecRestoreArrayRead(cs->active, &a));
  PetscCall(VecISCopy(x, kkt->isu, SCATTER_FORWARD, cs->vu));
  PetscCall(VecISCopy(x, kkt->isl, SCATTER_FORWARD, cs->dl));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedDestroy(Condensed *cs)
{
  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&cs->F));
  PetscCall(MatDestroy(&cs->S0));
  PetscCall(VecScatterDestroy(&cs->tozero));
  PetscCall(VecDestroy(&cs->act0));
  PetscCall(VecDestroy(&cs->active));
  PetscCall(VecDestroy(&cs->bl));
  PetscCall(VecDestroy(&cs->dl));
  PetscCall(VecDestroy(&cs->t));
  PetscCall(VecDestroy(&cs->vu));
  PetscCall(VecDestroy(&cs->rhs));
  PetscCall(VecDestroy(&cs->sol));
  PetscFunctionReturn(0);
}
