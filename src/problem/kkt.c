/* kkt.c - assemble and solve the contact saddle-point system (see kkt.h). */
#include "kkt.h"
#include <string.h>

/* C = -B from rows R (every rank holds them), in K's column layout; with
 * partner, P: row j holds the values of row partner[j] (0 on normal rows),
 * in row j's own columns (a tangential row has its normal row's columns in
 * the same order: mortar.h) */
static PetscErrorCode BuildC(MPI_Comm comm, const M2dContactRows *R, const PetscInt partner[], Mat K, Mat *C, Mat *P)
{
  PetscInt nu, Nu, lo, hi, clo, chi, *dnz, *onz;

  PetscFunctionBeginUser;
  PetscCall(MatGetLocalSize(K, &nu, NULL));
  PetscCall(MatGetSize(K, &Nu, NULL));
  PetscCall(MatGetOwnershipRangeColumn(K, &clo, &chi));
  PetscCall(MatCreate(comm, C));
  PetscCall(MatSetSizes(*C, PETSC_DECIDE, nu, R->n, Nu));
  PetscCall(MatSetType(*C, MATAIJ));
  PetscCall(MatSetUp(*C));
  PetscCall(MatGetOwnershipRange(*C, &lo, &hi));
  PetscCall(PetscCalloc2(hi - lo + 1, &dnz, hi - lo + 1, &onz));
  for (PetscInt j = lo; j < hi; j++)
    for (PetscInt k = R->ptr[j]; k < R->ptr[j + 1]; k++) {
      if (R->col[k] >= clo && R->col[k] < chi) dnz[j - lo]++;
      else onz[j - lo]++;
    }
  PetscCall(MatSeqAIJSetPreallocation(*C, 0, dnz));
  PetscCall(MatMPIAIJSetPreallocation(*C, 0, dnz, 0, onz));
  if (partner) {
    PetscCall(MatDuplicate(*C, MAT_DO_NOT_COPY_VALUES, P));
    PetscCall(MatSetOption(*P, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  }
  PetscCall(PetscFree2(dnz, onz));
  for (PetscInt j = lo; j < hi; j++) {
    PetscInt   n = R->ptr[j + 1] - R->ptr[j], p = partner ? partner[j] : -1;
    PetscReal *v;
    PetscCall(PetscMalloc1(n + 1, &v));
    for (PetscInt k = 0; k < n; k++) v[k] = -R->val[R->ptr[j] + k]; /* C = -B */
    PetscCall(MatSetValues(*C, 1, &j, n, &R->col[R->ptr[j]], v, INSERT_VALUES));
    if (partner) {
      for (PetscInt k = 0; k < n; k++) v[k] = p >= 0 ? -R->val[R->ptr[p] + k] : 0.0;
      PetscCall(MatSetValues(*P, 1, &j, n, &R->col[R->ptr[j]], v, INSERT_VALUES));
    }
    PetscCall(PetscFree(v));
  }
  PetscCall(MatAssemblyBegin(*C, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*C, MAT_FINAL_ASSEMBLY));
  if (partner) {
    PetscCall(MatAssemblyBegin(*P, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(*P, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

/* C = -B (and P) with the Dirichlet columns zeroed, C0 = C before, g0 the rows' constants */
static PetscErrorCode ConstraintRows(const M2dContactRows *R, const PetscInt partner[], Mat K, PetscInt ndir, const PetscInt drows[], M2dKKT *kkt)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)K);
  Vec      mask;
  PetscInt lo, hi;

  PetscFunctionBeginUser;
  PetscCall(BuildC(comm, R, partner, K, &kkt->C, &kkt->P));
  PetscCall(MatDuplicate(kkt->C, MAT_COPY_VALUES, &kkt->C0));
  PetscCall(MatCreateVecs(kkt->C, NULL, &kkt->g0));
  PetscCall(VecDuplicate(kkt->g0, &kkt->r));
  PetscCall(VecGetOwnershipRange(kkt->g0, &lo, &hi));
  for (PetscInt j = lo; j < hi; j++) PetscCall(VecSetValue(kkt->g0, j, R->g0[j], INSERT_VALUES));
  PetscCall(VecAssemblyBegin(kkt->g0));
  PetscCall(VecAssemblyEnd(kkt->g0));
  PetscCall(MatCreateVecs(K, &mask, NULL));
  PetscCall(VecSet(mask, 1.0));
  for (PetscInt i = 0; i < ndir; i++) PetscCall(VecSetValue(mask, drows[i], 0.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(mask));
  PetscCall(VecAssemblyEnd(mask));
  PetscCall(MatDiagonalScale(kkt->C, NULL, mask));
  if (kkt->P) PetscCall(MatDiagonalScale(kkt->P, NULL, mask));
  PetscCall(VecDestroy(&mask));
  PetscCall(MatTranspose(kkt->C, MAT_INITIAL_MATRIX, &kkt->Ct));
  PetscCall(MatDuplicate(kkt->C, MAT_COPY_VALUES, &kkt->CA));
  if (partner) {
    PetscCall(PetscMalloc1(R->n + 1, &kkt->partner));
    PetscCall(PetscArraycpy(kkt->partner, partner, R->n));
  }
  PetscFunctionReturn(0);
}

/* the (u,u) block: K, or with w > 0 K + g C^T C, g = w mean diag(K) / mean diag(C^T C) */
static PetscErrorCode AugmentedBlock(PetscReal w, M2dKKT *kkt)
{
  Vec       dk, dc;
  PetscReal sk, sc;
  PetscInt  n;

  PetscFunctionBeginUser;
  if (!(w > 0)) {
    PetscCall(PetscObjectReference((PetscObject)kkt->K));
    kkt->Kblk = kkt->K;
    PetscFunctionReturn(0);
  }
  PetscCall(MatTransposeMatMult(kkt->CA, kkt->CA, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &kkt->CtCA));
  PetscCall(MatCreateVecs(kkt->K, &dk, NULL));
  PetscCall(VecDuplicate(dk, &dc));
  PetscCall(MatGetDiagonal(kkt->K, dk));
  PetscCall(MatGetDiagonal(kkt->CtCA, dc));
  PetscCall(VecNorm(dk, NORM_1, &sk));
  PetscCall(VecNorm(dc, NORM_1, &sc));
  PetscCall(VecGetSize(dk, &n));
  sk /= n;
  sc /= PetscMax(1, 2 * kkt->nlam);
  kkt->gamma = sc > 0 ? w * sk / sc : 0;
  PetscCall(MatDuplicate(kkt->K, MAT_COPY_VALUES, &kkt->Kblk));
  {
    MatNullSpace nsp;
    PetscCall(MatGetNearNullSpace(kkt->K, &nsp));
    if (nsp) PetscCall(MatSetNearNullSpace(kkt->Kblk, nsp)); /* an AMG on the u split (fieldsplit) */
  }
  PetscCall(MatAXPY(kkt->Kblk, kkt->gamma, kkt->CtCA, SUBSET_NONZERO_PATTERN)); /* K holds C^T C's pattern (MeshCreateMatrix) */
  PetscCall(VecDestroy(&dk));
  PetscCall(VecDestroy(&dc));
  PetscFunctionReturn(0);
}

/* the nest of the four blocks (an explicit zero (lambda, lambda) block keeps
 * the structure symmetric for MUMPS), the operator A, the splits and b, x */
static PetscErrorCode Operator(PetscBool condensed, M2dKKT *kkt)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)kkt->K);
  PetscInt lo, hi, nl, Nl, nu, N;
  IS       isg[2];
  Mat      blocks[4];

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(kkt->r, &nl));
  PetscCall(VecGetSize(kkt->r, &Nl));
  /* a slipping tangential row couples to its normal row (KKTSetActive) */
  PetscCall(MatCreateAIJ(comm, nl, nl, Nl, Nl, kkt->partner ? 2 : 1, NULL, kkt->partner ? 1 : 0, NULL, &kkt->Z));
  PetscCall(VecGetOwnershipRange(kkt->r, &lo, &hi));
  for (PetscInt j = lo; j < hi; j++) {
    PetscCall(MatSetValue(kkt->Z, j, j, 0.0, INSERT_VALUES));
    if (kkt->partner && kkt->partner[j] >= 0) PetscCall(MatSetValue(kkt->Z, j, kkt->partner[j], 0.0, INSERT_VALUES));
  }
  PetscCall(MatAssemblyBegin(kkt->Z, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(kkt->Z, MAT_FINAL_ASSEMBLY));
  blocks[0] = kkt->Kblk, blocks[1] = kkt->Ct, blocks[2] = kkt->CA, blocks[3] = kkt->Z;
  PetscCall(MatCreateNest(comm, 2, NULL, 2, NULL, blocks, &kkt->nest));
  if (condensed) kkt->A = NULL; /* condensed.c reads the blocks */
  else if (kkt->aij) PetscCall(MatConvert(kkt->nest, MATAIJ, MAT_INITIAL_MATRIX, &kkt->A));
  else {
    PetscCall(PetscObjectReference((PetscObject)kkt->nest));
    kkt->A = kkt->nest;
  }
  PetscCall(MatNestGetISs(kkt->nest, isg, NULL));
  PetscCall(PetscObjectReference((PetscObject)isg[0]));
  PetscCall(PetscObjectReference((PetscObject)isg[1]));
  kkt->isu = isg[0];
  kkt->isl = isg[1];
  PetscCall(VecGetLocalSize(kkt->f, &nu));
  PetscCall(VecGetSize(kkt->f, &N));
  PetscCall(VecCreateMPI(comm, nu + nl, N + Nl, &kkt->b));
  PetscCall(VecDuplicate(kkt->b, &kkt->x));
  PetscFunctionReturn(0);
}

PetscErrorCode KKTCreate(M2dKKTMat mat, PetscReal augment, PetscBool condensed, const M2dContactRows *R, const PetscInt partner[], Mat K, Vec f, Vec ubc, PetscInt ndir, const PetscInt drows[], M2dKKT *kkt)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(kkt, sizeof(*kkt)));
  kkt->nlam = R->n;
  kkt->K    = K;
  kkt->f    = f;
  kkt->aij  = (PetscBool)(mat == M2D_KKT_AIJ);
  PetscCall(PetscObjectReference((PetscObject)K));
  PetscCall(PetscObjectReference((PetscObject)f));
  PetscCall(ConstraintRows(R, partner, K, ndir, drows, kkt));
  PetscCall(AugmentedBlock(augment, kkt));
  PetscCall(Operator(condensed, kkt));
  PetscCall(KKTSetLoad(kkt, ubc, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode KKTSetLoad(M2dKKT *kkt, Vec ubc, Vec uprev)
{
  Vec fk;

  PetscFunctionBeginUser;
  PetscCall(MatMult(kkt->C0, ubc, kkt->r));
  PetscCall(VecAYPX(kkt->r, -1.0, kkt->g0));
  if (kkt->partner && uprev) { /* the tangential rows: + C0 uprev */
    Vec                t;
    const PetscScalar *tv;
    PetscScalar       *rv;
    PetscInt           lo, hi;
    PetscCall(VecDuplicate(kkt->r, &t));
    PetscCall(MatMult(kkt->C0, uprev, t));
    PetscCall(VecGetOwnershipRange(t, &lo, &hi));
    PetscCall(VecGetArrayRead(t, &tv));
    PetscCall(VecGetArray(kkt->r, &rv));
    for (PetscInt j = lo; j < hi; j++)
      if (kkt->partner[j] >= 0) rv[j - lo] += tv[j - lo];
    PetscCall(VecRestoreArray(kkt->r, &rv));
    PetscCall(VecRestoreArrayRead(t, &tv));
    PetscCall(VecDestroy(&t));
  }
  PetscCall(VecDuplicate(kkt->f, &fk)); /* the u rows: f, augmented f + g C^T r */
  PetscCall(VecCopy(kkt->f, fk));
  if (kkt->gamma > 0) {
    Vec dk;
    PetscCall(VecDuplicate(fk, &dk));
    PetscCall(MatMultTranspose(kkt->C, kkt->r, dk));
    PetscCall(VecAXPY(fk, kkt->gamma, dk));
    PetscCall(VecDestroy(&dk));
  }
  PetscCall(VecISCopy(kkt->b, kkt->isu, SCATTER_FORWARD, fk));
  PetscCall(VecISCopy(kkt->b, kkt->isl, SCATTER_FORWARD, kkt->r));
  PetscCall(VecDestroy(&fk));
  PetscFunctionReturn(0);
}

/* the slipping rows' parts: CA += scale diag(s) P, Z(j, p) = (scale / c) s_j */
static PetscErrorCode SetSlipRows(M2dKKT *kkt, Vec slip, PetscReal c, PetscReal scale)
{
  const PetscScalar *sv;
  PetscInt           lo, hi;
  Mat                Ps;

  PetscFunctionBeginUser;
  PetscCall(MatDuplicate(kkt->P, MAT_COPY_VALUES, &Ps));
  PetscCall(MatDiagonalScale(Ps, slip, NULL));
  PetscCall(MatAXPY(kkt->CA, scale, Ps, SAME_NONZERO_PATTERN));
  PetscCall(MatDestroy(&Ps));
  PetscCall(VecGetOwnershipRange(slip, &lo, &hi));
  PetscCall(VecGetArrayRead(slip, &sv));
  for (PetscInt j = lo; j < hi; j++)
    if (kkt->partner[j] >= 0) PetscCall(MatSetValue(kkt->Z, j, kkt->partner[j], scale / c * PetscRealPart(sv[j - lo]), INSERT_VALUES));
  PetscCall(VecRestoreArrayRead(slip, &sv));
  PetscCall(MatAssemblyBegin(kkt->Z, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(kkt->Z, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

PetscErrorCode KKTSetActive(M2dKKT *kkt, Vec active, Vec slip, PetscReal c, PetscReal scale)
{
  const PetscScalar *a;
  PetscInt           lo, hi, n = 0, *rows;
  Vec                zd;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(active, &lo, &hi));
  PetscCall(PetscMalloc1(hi - lo + 1, &rows));
  PetscCall(VecDuplicate(active, &zd));
  PetscCall(VecGetArrayRead(active, &a));
  for (PetscInt j = lo; j < hi; j++) {
    if (PetscRealPart(a[j - lo]) == 0) rows[n++] = j;
    PetscCall(VecSetValue(zd, j, PetscRealPart(a[j - lo]) == 0 ? -scale / c : 0.0, INSERT_VALUES));
  }
  PetscCall(VecRestoreArrayRead(active, &a));
  PetscCall(VecAssemblyBegin(zd));
  PetscCall(VecAssemblyEnd(zd));
  PetscCall(MatCopy(kkt->C, kkt->CA, SAME_NONZERO_PATTERN));
  PetscCall(MatSetOption(kkt->CA, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  PetscCall(MatZeroRows(kkt->CA, n, rows, 0.0, NULL, NULL));
  PetscCall(MatScale(kkt->CA, scale));
  PetscCall(MatDiagonalSet(kkt->Z, zd, INSERT_VALUES));
  PetscCall(VecDestroy(&zd));
  PetscCall(PetscFree(rows));
  if (kkt->gamma > 0) { /* the augmentation: the constraint rows only */
    PetscCall(MatTransposeMatMult(kkt->CA, kkt->CA, MAT_REUSE_MATRIX, PETSC_DEFAULT, &kkt->CtCA));
    PetscCall(MatZeroEntries(kkt->Kblk));
    PetscCall(MatAXPY(kkt->Kblk, 1.0, kkt->K, SUBSET_NONZERO_PATTERN));
    PetscCall(MatAXPY(kkt->Kblk, kkt->gamma / (scale * scale), kkt->CtCA, SUBSET_NONZERO_PATTERN));
  }
  if (kkt->partner && slip) PetscCall(SetSlipRows(kkt, slip, c, scale));
  PetscCall(MatAssemblyBegin(kkt->nest, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(kkt->nest, MAT_FINAL_ASSEMBLY));
  if (kkt->aij && kkt->gamma == 0 && !kkt->partner) {
    /* update the monolithic matrix in place: a MatConvert would change its
     * nonzero state on several ranks and make MUMPS redo its analysis */
    const PetscInt    *il;
    const PetscScalar *av;
    PetscInt           nl, na = 0, *rowsA;
    Vec                sv, sl;
    if (!kkt->A0) PetscCall(MatDuplicate(kkt->A, MAT_COPY_VALUES, &kkt->A0));
    PetscCall(MatCopy(kkt->A0, kkt->A, SAME_NONZERO_PATTERN));
    PetscCall(VecDuplicate(kkt->b, &sv));
    PetscCall(VecDuplicate(kkt->r, &sl));
    PetscCall(VecSet(sv, 1.0));
    PetscCall(VecSet(sl, scale));
    PetscCall(VecISCopy(sv, kkt->isl, SCATTER_FORWARD, sl));
    PetscCall(MatDiagonalScale(kkt->A, sv, NULL));
    PetscCall(VecDestroy(&sv));
    PetscCall(VecDestroy(&sl));
    PetscCall(ISGetLocalSize(kkt->isl, &nl));
    PetscCall(ISGetIndices(kkt->isl, &il));
    PetscCall(PetscMalloc1(nl + 1, &rowsA));
    PetscCall(VecGetArrayRead(active, &av));
    for (PetscInt j = 0; j < nl; j++)
      if (PetscRealPart(av[j]) == 0) rowsA[na++] = il[j];
    PetscCall(VecRestoreArrayRead(active, &av));
    PetscCall(ISRestoreIndices(kkt->isl, &il));
    PetscCall(MatSetOption(kkt->A, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
    PetscCall(MatZeroRows(kkt->A, na, rowsA, -scale / c, NULL, NULL));
    PetscCall(PetscFree(rowsA));
  } else if (kkt->aij) PetscCall(MatConvert(kkt->nest, MATAIJ, MAT_REUSE_MATRIX, &kkt->A)); /* friction: the slip rows' couplings come from the blocks */
  PetscFunctionReturn(0);
}

PetscErrorCode KKTSetupKSP(M2dKKT *kkt, KSP ksp)
{
  PC        pc;
  PetscBool fs;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &fs));
  if (kkt->A == kkt->nest && !fs) {
    PetscBool factor;
    PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, PCILU, PCICC, ""));
    PetscCheck(!factor, PetscObjectComm((PetscObject)pc), PETSC_ERR_USER_INPUT, "option -kkt_mat nest: a MatNest cannot be factored directly; use -kkt_mat aij for LU, or PCFIELDSPLIT (options/kkt_fieldsplit.opts)");
  }
  if (fs) {
    PetscCall(PCFieldSplitSetIS(pc, "u", kkt->isu));
    PetscCall(PCFieldSplitSetIS(pc, "lambda", kkt->isl));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode KKTSolve(M2dKKT *kkt, KSP ksp, Vec u, Vec lam)
{
  PetscFunctionBeginUser;
  PetscCall(KSPSolve(ksp, kkt->b, kkt->x));
  PetscCall(VecISCopy(kkt->x, kkt->isu, SCATTER_REVERSE, u));
  PetscCall(VecISCopy(kkt->x, kkt->isl, SCATTER_REVERSE, lam));
  PetscFunctionReturn(0);
}

PetscErrorCode KKTDestroy(M2dKKT *kkt)
{
  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&kkt->C));
  PetscCall(MatDestroy(&kkt->C0));
  PetscCall(MatDestroy(&kkt->P));
  PetscCall(VecDestroy(&kkt->g0));
  PetscCall(PetscFree(kkt->partner));
  PetscCall(MatDestroy(&kkt->CA));
  PetscCall(MatDestroy(&kkt->A0));
  PetscCall(MatDestroy(&kkt->CtCA));
  PetscCall(MatDestroy(&kkt->K));
  PetscCall(VecDestroy(&kkt->f));
  PetscCall(MatDestroy(&kkt->Ct));
  PetscCall(MatDestroy(&kkt->Z));
  PetscCall(MatDestroy(&kkt->Kblk));
  PetscCall(MatDestroy(&kkt->nest));
  PetscCall(MatDestroy(&kkt->A));
  PetscCall(ISDestroy(&kkt->isu));
  PetscCall(ISDestroy(&kkt->isl));
  PetscCall(VecDestroy(&kkt->r));
  PetscCall(VecDestroy(&kkt->b));
  PetscCall(VecDestroy(&kkt->x));
  PetscFunctionReturn(0);
}

PetscErrorCode KKTFieldsplitCheck(KSP ksp, PetscReal gamma)
{
  KSPConvergedReason kr;
  PC                 pc;
  PetscBool          fs;

  PetscFunctionBeginUser;
  PetscCall(KSPGetConvergedReason(ksp, &kr));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &fs));
  PetscCheck(kr >= 0 || !fs || gamma > 0, PetscObjectComm((PetscObject)ksp), PETSC_ERR_NOT_CONVERGED, "linear solve failed (%s): the fieldsplit K block cannot be factored when a body is held only by contact; add -kkt_augment 1 or use the monolithic solver (options/kkt_mumps.opts)", KSPConvergedReasons[kr]);
  PetscFunctionReturn(0);
}

PetscErrorCode KKTKrylovCheck(KSP ksp, const char *what, PetscBool settled)
{
  KSPType            type;
  KSPConvergedReason kr;
  PetscReal          rtol;
  PetscInt           maxit, its;
  MPI_Comm           comm = PetscObjectComm((PetscObject)ksp);

  PetscFunctionBeginUser;
  PetscCall(KSPGetType(ksp, &type));
  if (!strcmp(type, KSPPREONLY)) PetscFunctionReturn(0); /* a direct solve */
  PetscCall(KSPGetConvergedReason(ksp, &kr));
  PetscCall(KSPGetTolerances(ksp, &rtol, NULL, NULL, &maxit));
  PetscCall(KSPGetIterationNumber(ksp, &its));
  PetscCheck(kr >= 0, comm, PETSC_ERR_NOT_CONVERGED, "%s: -ksp_type %s stopped after %" PetscInt_FMT " iterations (%s; -ksp_rtol %g, -ksp_max_it %" PetscInt_FMT "): raise -ksp_max_it, choose a better -pc_type, or solve directly (the default: no -ksp_type)", what, type, its, KSPConvergedReasons[kr], (double)rtol, maxit);
  /* an inexact Newton step moves the multipliers by its error: the set may
   * never settle (S2, full path, -ksp_type gmres -pc_type jacobi -ksp_rtol 0.9:
   * "did not settle in 50 steps") */
  PetscCheck(settled || rtol <= 1e-8, comm, PETSC_ERR_NOT_CONVERGED, "%s: its steps are solved only to -ksp_rtol %g (-ksp_type %s), and an active set needs exact steps: -ksp_rtol 1e-12, or solve directly (the default: no -ksp_type)", what, (double)rtol, type);
  PetscFunctionReturn(0);
}
