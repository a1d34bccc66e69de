/* condensed.c - factor once with a MUMPS Schur complement (dmumps_c, 1 or 2
 * ranks); the reduced iteration's algebra (see condensed.h). */
#include "condensed.h"
#include <dmumps_c.h>
#include <petscblaslapack.h>

#define ICNTL(I)  icntl[(I) - 1]
#define INFOG(I)  infog[(I) - 1]
#define RINFOG(I) rinfog[(I) - 1]

struct M2dMumps {
  DMUMPS_STRUC_C id;
  MPI_Comm       comm;
};

static PetscLogEvent ev_order, ev_analysis, ev_factor, ev_solve;

static PetscErrorCode RegisterEvents(void)
{
  static PetscBool done = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (done) PetscFunctionReturn(0);
  PetscCall(PetscLogEventRegister("M2dCondOrder", MAT_CLASSID, &ev_order));
  PetscCall(PetscLogEventRegister("M2dMumpsAnalysis", MAT_CLASSID, &ev_analysis));
  PetscCall(PetscLogEventRegister("M2dMumpsFactor", MAT_CLASSID, &ev_factor));
  PetscCall(PetscLogEventRegister("M2dMumpsSolve", MAT_CLASSID, &ev_solve));
  done = PETSC_TRUE;
  PetscFunctionReturn(0);
}

static PetscErrorCode MumpsCall(M2dMumps *mu, int job, const char *what)
{
  PetscFunctionBeginUser;
  mu->id.job = job;
  dmumps_c(&mu->id);
  if (mu->id.INFOG(1) == -10 && job == 2) SETERRQ(mu->comm, PETSC_ERR_USER_INPUT, "the stiffness with every candidate contact node tied is singular: a body is held by nothing (check -dirichlet and the contact pair)");
  PetscCheck(mu->id.INFOG(1) >= 0, mu->comm, PETSC_ERR_LIB, "MUMPS %s failed: INFOG(1) = %d, INFOG(2) = %d%s", what, (int)mu->id.INFOG(1), (int)mu->id.INFOG(2), mu->id.INFOG(1) == -9 ? " (raise -mat_mumps_icntl_14)" : "");
  PetscFunctionReturn(0);
}

/* Pivot position (1-based, MUMPS PERM_IN) of every row of A, on rank 0; the
 * multipliers last. Several ranks: rows of rank p with a u-coupling to a
 * higher rank form the separator; the rest of every rank's rows is ordered by
 * METIS on that rank, all at once; rank 0 puts the interiors rank by rank,
 * then the separators, then the multipliers. */
static PetscErrorCode Ordering(KKT *kkt, const PetscInt lamsorted[], PetscInt N, MUMPS_INT **perm)
{
  Mat             A = kkt->A, Ad = A, Ao = NULL;
  MPI_Comm        comm = PetscObjectComm((PetscObject)A);
  PetscMPIInt     size, rank;
  const PetscInt *ranges, *colmap = NULL, *il, *pos;
  PetscInt        rs, re, n, nl, nsep = 0, *lastidx, *code, cnt[3] = {0, 0, 0}, *allcnt = NULL;
  PetscBool      *islam;
  IS              last, posis;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(MatGetOwnershipRange(A, &rs, &re));
  PetscCall(MatGetOwnershipRanges(A, &ranges));
  n = re - rs;
  if (size > 1) PetscCall(MatMPIAIJGetSeqAIJ(A, &Ad, &Ao, &colmap));
  PetscCall(ISGetLocalSize(kkt->isl, &nl));
  PetscCall(PetscCalloc2(n + 1, &islam, n + 1, &lastidx));
  PetscCall(ISGetIndices(kkt->isl, &il));
  for (PetscInt j = 0; j < nl; j++) islam[il[j] - rs] = PETSC_TRUE;
  PetscCall(ISRestoreIndices(kkt->isl, &il));
  /* separator rows first in `last`, then the multipliers */
  for (PetscInt i = 0; i < n && Ao; i++) {
    PetscInt        nc, loc;
    const PetscInt *cols;
    PetscBool       sep = PETSC_FALSE;
    if (islam[i]) continue;
    PetscCall(MatGetRow(Ao, i, &nc, &cols, NULL));
    for (PetscInt k = 0; k < nc && !sep; k++) {
      PetscInt g = colmap[cols[k]];
      PetscCall(PetscFindInt(g, N, lamsorted, &loc));
      sep = (PetscBool)(loc < 0 && g >= re); /* a u column of a higher rank */
    }
    PetscCall(MatRestoreRow(Ao, i, &nc, &cols, NULL));
    if (sep) lastidx[nsep++] = i;
  }
  nl = nsep;
  for (PetscInt i = 0; i < n; i++)
    if (islam[i]) lastidx[nl++] = i;
  PetscCall(PetscInfo(A, "separator %" PetscInt_FMT " rows, multipliers %" PetscInt_FMT ", interior %" PetscInt_FMT "\n", nsep, nl - nsep, n - nl));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, nl, lastidx, PETSC_USE_POINTER, &last));
  PetscCall(M2dOrderingMetis(Ad, last, &posis));
  PetscCall(ISDestroy(&last));
  /* per row: class (0 interior, 1 separator, 2 multiplier) and rank within it */
  PetscCall(PetscMalloc1(n + 1, &code));
  PetscCall(ISGetIndices(posis, &pos));
  {
    PetscInt nint = n - nl;
    for (PetscInt i = 0; i < n; i++) {
      PetscInt p = pos[i], c = p < nint ? 0 : (p < nint + nsep ? 1 : 2);
      code[i] = 4 * (p - (c == 0 ? 0 : (c == 1 ? nint : nint + nsep))) + c;
      cnt[c]++;
    }
  }
  PetscCall(ISRestoreIndices(posis, &pos));
  PetscCall(ISDestroy(&posis));
  PetscCall(PetscFree2(islam, lastidx));
  /* rank 0: positions */
  {
    PetscMPIInt *rc = NULL, *displ = NULL, nn;
    PetscInt    *allcode = NULL, M = ranges[size];
    if (rank == 0) {
      PetscCall(PetscMalloc4(3 * size, &allcnt, size, &rc, size, &displ, M, &allcode));
      for (PetscMPIInt p = 0; p < size; p++) {
        PetscCall(PetscMPIIntCast(ranges[p + 1] - ranges[p], &rc[p]));
        PetscCall(PetscMPIIntCast(ranges[p], &displ[p]));
      }
    }
    PetscCall(PetscMPIIntCast(n, &nn));
    PetscCallMPI(MPI_Gather(cnt, 3, MPIU_INT, allcnt, 3, MPIU_INT, 0, comm));
    PetscCallMPI(MPI_Gatherv(code, nn, MPIU_INT, allcode, rc, displ, MPIU_INT, 0, comm));
    *perm = NULL;
    if (rank == 0) {
      PetscInt *off, acc = 0;
      PetscCall(PetscMalloc1(3 * size, &off));
      for (int c = 0; c < 3; c++)
        for (PetscMPIInt p = 0; p < size; p++) {
          off[3 * p + c] = acc;
          acc += allcnt[3 * p + c];
        }
      PetscCheck(acc == M, PETSC_COMM_SELF, PETSC_ERR_PLIB, "ordering covers %" PetscInt_FMT " of %" PetscInt_FMT " rows", acc, M);
      PetscCall(PetscMalloc1(M, perm));
      for (PetscMPIInt p = 0; p < size; p++)
        for (PetscInt g = ranges[p]; g < ranges[p + 1]; g++) (*perm)[g] = (MUMPS_INT)(off[3 * p + allcode[g] % 4] + allcode[g] / 4 + 1);
      PetscCall(PetscFree(off));
      PetscCall(PetscFree4(allcnt, rc, displ, allcode));
    }
  }
  PetscCall(PetscFree(code));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedCreate(KKT *kkt, const Scene *s, Condensed *cs)
{
  MPI_Comm        comm = PetscObjectComm((PetscObject)kkt->A);
  PetscMPIInt     size, rank, nn, *rc = NULL, *displ = NULL;
  M2dMumps       *mu;
  PetscInt        rs, re, M, nnz = 0, *lamall, *lamsorted, k = 0;
  const PetscInt *il;
  MUMPS_INT      *irn, *jcn, *perm = NULL, *listvar = NULL;
  PetscScalar    *a, *S = NULL;
  PetscLogDouble  t0;
  M2dOrdering     ord = s->kkt_ordering;
  int             sym = s->kkt_ldlt ? 2 : 0; /* LDL^T of the symmetric matrix, or LU */

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(cs, sizeof(*cs)));
  PetscCheck(kkt->gamma > 0 && kkt->aij, comm, PETSC_ERR_PLIB, "condensed path needs the augmented monolithic KKT matrix");
  PetscCall(RegisterEvents());
  cs->kkt = kkt;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));

  t0 = MPI_Wtime();
  /* the multipliers: global indices of A, in the order of kkt->r (rank by rank) */
  PetscCall(VecGetLocalSize(kkt->r, &cs->n));
  PetscCall(VecGetSize(kkt->r, &cs->N));
  PetscCall(VecGetOwnershipRange(kkt->r, &cs->lo, NULL));
  PetscCall(PetscMalloc2(cs->N + 1, &lamall, cs->N + 1, &lamsorted));
  PetscCall(PetscMalloc2(size, &rc, size, &displ));
  PetscCall(PetscMPIIntCast(cs->n, &nn));
  PetscCallMPI(MPI_Allgather(&nn, 1, MPI_INT, rc, 1, MPI_INT, comm));
  displ[0] = 0;
  for (PetscMPIInt p = 1; p < size; p++) displ[p] = displ[p - 1] + rc[p - 1];
  PetscCall(ISGetIndices(kkt->isl, &il));
  PetscCallMPI(MPI_Allgatherv(il, nn, MPIU_INT, lamall, rc, displ, MPIU_INT, comm));
  PetscCall(ISRestoreIndices(kkt->isl, &il));
  PetscCall(PetscArraycpy(lamsorted, lamall, cs->N));
  PetscCall(PetscSortInt(cs->N, lamsorted));

  PetscCall(PetscLogEventBegin(ev_order, kkt->A, 0, 0, 0));
  if (ord == M2D_ORDERING_METIS) PetscCall(Ordering(kkt, lamsorted, cs->N, &perm));
  PetscCall(PetscLogEventEnd(ev_order, kkt->A, 0, 0, 0));

  /* the local rows as 1-based triples */
  PetscCall(MatGetOwnershipRange(kkt->A, &rs, &re));
  PetscCall(MatGetSize(kkt->A, &M, NULL));
  for (PetscInt i = rs; i < re; i++) {
    PetscInt        nc;
    const PetscInt *cols;
    PetscCall(MatGetRow(kkt->A, i, &nc, &cols, NULL));
    for (PetscInt j = 0; j < nc; j++) nnz += !sym || cols[j] >= i;
    PetscCall(MatRestoreRow(kkt->A, i, &nc, &cols, NULL));
  }
  PetscCall(PetscMalloc3(nnz + 1, &irn, nnz + 1, &jcn, nnz + 1, &a));
  for (PetscInt i = rs; i < re; i++) {
    PetscInt           nc;
    const PetscInt    *cols;
    const PetscScalar *v;
    PetscCall(MatGetRow(kkt->A, i, &nc, &cols, &v));
    for (PetscInt j = 0; j < nc; j++) {
      if (sym && cols[j] < i) continue; /* symmetric: the upper triangle */
      irn[k] = (MUMPS_INT)(i + 1);
      jcn[k] = (MUMPS_INT)(cols[j] + 1);
      a[k++] = v[j];
    }
    PetscCall(MatRestoreRow(kkt->A, i, &nc, &cols, &v));
  }

  PetscCall(PetscNew(&mu));
  cs->mumps = mu;
  PetscCallMPI(MPI_Comm_dup(comm, &mu->comm));
  mu->id.comm_fortran = (MUMPS_INT)MPI_Comm_c2f(mu->comm);
  mu->id.par          = 1;
  mu->id.sym          = (MUMPS_INT)sym;
  PetscCall(MumpsCall(mu, -1, "initialisation"));
  mu->id.ICNTL(1)  = s->icntl4 > 0 ? 6 : -1;
  mu->id.ICNTL(2)  = -1;
  mu->id.ICNTL(3)  = s->icntl4 > 0 ? 6 : -1;
  mu->id.ICNTL(4)  = (MUMPS_INT)s->icntl4;
  mu->id.ICNTL(7)  = ord == M2D_ORDERING_METIS ? 1 : (MUMPS_INT)s->icntl7;
  mu->id.ICNTL(8)  = (MUMPS_INT)s->icntl8;
  mu->id.ICNTL(14) = (MUMPS_INT)s->icntl14;
  mu->id.ICNTL(18) = 3; /* distributed assembled matrix */
  mu->id.ICNTL(19) = 1; /* Schur complement, whole, on rank 0 */
  mu->id.ICNTL(28) = 1; /* sequential analysis (the ordering is given) */
  mu->id.ICNTL(58) = (MUMPS_INT)s->icntl58;
  mu->id.n         = (MUMPS_INT)M;
  mu->id.nnz_loc   = (MUMPS_INT8)nnz;
  mu->id.irn_loc   = irn;
  mu->id.jcn_loc   = jcn;
  mu->id.a_loc     = a;
  if (rank == 0) {
    PetscCall(PetscMalloc2(cs->N + 1, &listvar, cs->N * cs->N + 1, &S));
    for (PetscInt j = 0; j < cs->N; j++) listvar[j] = (MUMPS_INT)(lamall[j] + 1);
    mu->id.perm_in       = perm;
    mu->id.size_schur    = (MUMPS_INT)cs->N;
    mu->id.listvar_schur = listvar;
    mu->id.schur         = S;
    mu->id.schur_lld     = (MUMPS_INT)cs->N;
  }
  PetscCall(PetscLogEventBegin(ev_analysis, kkt->A, 0, 0, 0));
  PetscCall(MumpsCall(mu, 1, "analysis"));
  PetscCall(PetscLogEventEnd(ev_analysis, kkt->A, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_factor, kkt->A, 0, 0, 0));
  PetscCall(MumpsCall(mu, 2, "factorization"));
  PetscCall(PetscLogFlops(mu->id.RINFOG(3) / size));
  PetscCall(PetscInfo(kkt->A, "MUMPS factorization: %g flops on this rank (RINFO(3)), %g in all\n", (double)mu->id.rinfo[2], (double)mu->id.RINFOG(3)));
  PetscCall(PetscLogEventEnd(ev_factor, kkt->A, 0, 0, 0));
  /* the solves need neither the matrix nor the ordering */
  PetscCall(PetscFree3(irn, jcn, a));
  mu->id.irn_loc = mu->id.jcn_loc = NULL;
  mu->id.a_loc   = NULL;
  PetscCall(PetscFree(perm));
  mu->id.perm_in = NULL;

  /* S0 (rows by rows on rank 0) -> rows lo..lo+n-1 on each rank, column-major */
  {
    PetscScalar *buf;
    PetscMPIInt *rc2 = NULL, *d2 = NULL, nr;
    PetscCall(PetscMalloc1(cs->n * cs->N + 1, &buf));
    PetscCall(PetscMalloc1(cs->n * cs->N + 1, &cs->S));
    if (rank == 0) {
      PetscCall(PetscMalloc2(size, &rc2, size, &d2));
      for (PetscMPIInt p = 0; p < size; p++) {
        PetscCall(PetscMPIIntCast(rc[p] * cs->N, &rc2[p]));
        PetscCall(PetscMPIIntCast(displ[p] * cs->N, &d2[p]));
      }
    }
    PetscCall(PetscMPIIntCast(cs->n * cs->N, &nr));
    if (rank == 0 && sym) /* MUMPS returns the lower triangle, by rows: mirror it */
      for (PetscInt i = 0; i < cs->N; i++)
        for (PetscInt j = i + 1; j < cs->N; j++) S[i * cs->N + j] = S[j * cs->N + i];
    PetscCallMPI(MPI_Scatterv(S, rc2, d2, MPIU_SCALAR, buf, nr, MPIU_SCALAR, 0, comm));
    for (PetscInt i = 0; i < cs->n; i++)
      for (PetscInt j = 0; j < cs->N; j++) cs->S[i + j * cs->n] = buf[i * cs->N + j];
    PetscCall(PetscFree(buf));
    if (rank == 0) PetscCall(PetscFree2(rc2, d2));
  }
  if (rank == 0) PetscCall(PetscFree2(listvar, S));
  mu->id.listvar_schur = NULL;
  mu->id.schur         = NULL;
  PetscCall(PetscFree2(rc, displ));
  PetscCall(PetscFree2(lamall, lamsorted));
  cs->factor_time = MPI_Wtime() - t0;

  PetscCall(VecDuplicate(kkt->b, &cs->rhs));
  PetscCall(VecScatterCreateToZero(cs->rhs, &cs->toz, &cs->rhs0));
  PetscCall(VecScatterCreateToAll(kkt->r, &cs->toall, &cs->all));
  PetscCall(VecScatterCreateToZero(kkt->r, &cs->lamz, &cs->lam0));
  PetscCall(PetscMalloc2(cs->N * cs->N + 1, &cs->lu, cs->N + 1, &cs->piv));
  PetscFunctionReturn(0);
}

/* MUMPS' solve phase with the Schur complement on the multipliers (ICNTL(26)):
 * phase 1, condensation (forward elimination of [f; 0]): the reduced
 * right-hand side -C K_g^-1 f = -w comes back on rank 0; phase 2, expansion
 * (backward substitution) from the Schur unknowns nu: u = K_g^-1 (f - C^T nu).
 * One solve's work for both; the host vector keeps what phase 1 left. */
static PetscErrorCode SchurPhase(Condensed *cs, int phase, Vec lam, Vec u)
{
  M2dMumps    *mu = cs->mumps;
  PetscScalar *b = NULL, *red = NULL;
  PetscMPIInt  rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(mu->comm, &rank));
  PetscCall(PetscLogEventBegin(ev_solve, 0, 0, 0, 0));
  if (phase == 1) {
    PetscCall(VecZeroEntries(cs->rhs));
    PetscCall(VecISCopy(cs->rhs, cs->kkt->isu, SCATTER_FORWARD, cs->kkt->f));
    PetscCall(VecScatterBegin(cs->toz, cs->rhs, cs->rhs0, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(cs->toz, cs->rhs, cs->rhs0, INSERT_VALUES, SCATTER_FORWARD));
  } else { /* nu -> rank 0 */
    PetscCall(VecScatterBegin(cs->lamz, lam, cs->lam0, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(cs->lamz, lam, cs->lam0, INSERT_VALUES, SCATTER_FORWARD));
  }
  if (rank == 0) {
    PetscCall(VecGetArray(cs->rhs0, &b));
    PetscCall(VecGetArray(cs->lam0, &red));
    mu->id.rhs     = b;
    mu->id.lrhs    = mu->id.n;
    mu->id.redrhs  = red;
    mu->id.lredrhs = (MUMPS_INT)cs->N;
  }
  mu->id.nrhs      = 1;
  mu->id.ICNTL(20) = 0; /* dense right-hand side on rank 0 */
  mu->id.ICNTL(21) = 0; /* solution on rank 0, in place */
  mu->id.ICNTL(26) = phase;
  PetscCall(MumpsCall(mu, 3, phase == 1 ? "solve (condensation)" : "solve (expansion)"));
  if (rank == 0) {
    PetscCall(VecRestoreArray(cs->lam0, &red));
    PetscCall(VecRestoreArray(cs->rhs0, &b));
  }
  mu->id.rhs    = NULL;
  mu->id.redrhs = NULL;
  if (phase == 1) { /* -w -> layout of kkt->r */
    PetscCall(VecScatterBegin(cs->lamz, cs->lam0, lam, INSERT_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(cs->lamz, cs->lam0, lam, INSERT_VALUES, SCATTER_REVERSE));
  } else {
    PetscCall(VecScatterBegin(cs->toz, cs->rhs0, cs->rhs, INSERT_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(cs->toz, cs->rhs0, cs->rhs, INSERT_VALUES, SCATTER_REVERSE));
    PetscCall(VecISCopy(cs->rhs, cs->kkt->isu, SCATTER_REVERSE, u));
  }
  PetscCall(PetscLogEventEnd(ev_solve, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedReducedSetup(Condensed *cs)
{
  KKT *kkt = cs->kkt;

  PetscFunctionBeginUser;
  PetscCheck(cs->S && !cs->w, PetscObjectComm((PetscObject)kkt->A), PETSC_ERR_PLIB, "reduced iteration: one setup after the factorization");
  PetscCall(VecDuplicate(kkt->r, &cs->w));
  PetscCall(SchurPhase(cs, 1, cs->w, NULL)); /* -w */
  PetscCall(VecScale(cs->w, -1.0));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedReducedGaps(Condensed *cs, Vec nu, Vec cu)
{
  const PetscScalar *v, *w;
  PetscScalar       *y;
  PetscInt           n = cs->n, N = cs->N;

  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(cs->toall, nu, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(cs->toall, nu, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(cs->all, &v));
  PetscCall(VecGetArrayRead(cs->w, &w));
  PetscCall(VecGetArray(cu, &y));
  for (PetscInt i = 0; i < n; i++) y[i] = w[i];
  for (PetscInt j = 0; j < N; j++) /* column-major: y += S(:, j) v_j */
    for (PetscInt i = 0; i < n; i++) y[i] += cs->S[i + j * n] * v[j];
  PetscCall(VecRestoreArray(cu, &y));
  PetscCall(VecRestoreArrayRead(cs->w, &w));
  PetscCall(VecRestoreArrayRead(cs->all, &v));
  PetscCall(PetscLogFlops(2.0 * n * N));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedReducedJacobian(Condensed *cs, Vec active, PetscReal c, PetscReal h, Mat J)
{
  const PetscScalar *a;
  PetscScalar       *Jv;
  PetscInt           n = cs->n, N = cs->N, ldj;
  PetscReal          g = cs->kkt->gamma;

  PetscFunctionBeginUser;
  PetscCall(MatDenseGetLDA(J, &ldj));
  PetscCall(VecGetArrayRead(active, &a));
  PetscCall(MatDenseGetArrayWrite(J, &Jv));
  for (PetscInt j = 0; j < N; j++)
    for (PetscInt i = 0; i < n; i++) {
      PetscScalar s = cs->S[i + j * n];
      Jv[i + j * ldj] = PetscRealPart(a[i]) != 0 ? c * h * s : -h * (g * s + (cs->lo + i == j ? 1.0 : 0.0));
    }
  PetscCall(MatDenseRestoreArrayWrite(J, &Jv));
  PetscCall(VecRestoreArrayRead(active, &a));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* every rank: the whole J, gathered by rows (row-major = J^T column-major), LU of J^T */
PetscErrorCode CondensedDenseFactor(Condensed *cs, Mat J)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)J);
  PetscMPIInt        size, nr, *rc, *displ;
  const PetscScalar *Jv;
  PetscScalar       *buf;
  PetscInt           n = cs->n, N = cs->N, ldj;
  PetscBLASInt       bn, info;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc3(n * N + 1, &buf, size, &rc, size, &displ));
  PetscCall(MatDenseGetLDA(J, &ldj));
  PetscCall(MatDenseGetArrayRead(J, &Jv));
  for (PetscInt i = 0; i < n; i++)
    for (PetscInt j = 0; j < N; j++) buf[i * N + j] = Jv[i + j * ldj];
  PetscCall(MatDenseRestoreArrayRead(J, &Jv));
  PetscCall(PetscMPIIntCast(n * N, &nr));
  PetscCallMPI(MPI_Allgather(&nr, 1, MPI_INT, rc, 1, MPI_INT, comm));
  displ[0] = 0;
  for (PetscMPIInt p = 1; p < size; p++) displ[p] = displ[p - 1] + rc[p - 1];
  PetscCallMPI(MPI_Allgatherv(buf, nr, MPIU_SCALAR, cs->lu, rc, displ, MPIU_SCALAR, comm));
  PetscCall(PetscFree3(buf, rc, displ));
  PetscCall(PetscBLASIntCast(N, &bn));
  if (N > 0) {
    PetscCallBLAS("LAPACKgetrf", LAPACKgetrf_(&bn, &bn, cs->lu, &bn, cs->piv, &info));
    PetscCheck(info == 0, comm, PETSC_ERR_NOT_CONVERGED, "reduced active-set Jacobian is singular (LAPACK getrf info %d)", (int)info);
  }
  PetscCall(PetscLogFlops(2.0 * N * N * N / 3.0));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedDenseSolve(Condensed *cs, Vec b, Vec x)
{
  PetscScalar       *v;
  const PetscScalar *va;
  PetscBLASInt       bn, one = 1, info;

  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(cs->toall, b, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(cs->toall, b, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(PetscBLASIntCast(cs->N, &bn));
  PetscCall(VecGetArray(cs->all, &v));
  if (cs->N > 0) PetscCallBLAS("LAPACKgetrs", LAPACKgetrs_("T", &bn, &one, cs->lu, &bn, cs->piv, v, &bn, &info));
  PetscCall(VecRestoreArray(cs->all, &v));
  PetscCall(VecGetArrayRead(cs->all, &va));
  {
    PetscScalar *xv;
    PetscCall(VecGetArray(x, &xv));
    for (PetscInt i = 0; i < cs->n; i++) xv[i] = va[cs->lo + i];
    PetscCall(VecRestoreArray(x, &xv));
  }
  PetscCall(VecRestoreArrayRead(cs->all, &va));
  PetscCall(PetscLogFlops(2.0 * cs->N * cs->N));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedRecover(Condensed *cs, Vec nu, Vec u)
{
  KKT *kkt = cs->kkt;

  PetscFunctionBeginUser;
  PetscCheck(cs->w, PetscObjectComm((PetscObject)kkt->A), PETSC_ERR_PLIB, "reduced iteration: recovery before the setup");
  PetscCall(SchurPhase(cs, 2, nu, u)); /* u = K_g^-1 (f - C^T nu) */
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedDestroy(Condensed *cs)
{
  PetscFunctionBeginUser;
  if (cs->mumps) {
    cs->mumps->id.job = -2;
    dmumps_c(&cs->mumps->id);
    PetscCallMPI(MPI_Comm_free(&cs->mumps->comm));
    PetscCall(PetscFree(cs->mumps));
  }
  PetscCall(VecDestroy(&cs->w));
  PetscCall(PetscFree(cs->S));
  PetscCall(PetscFree2(cs->lu, cs->piv));
  PetscCall(VecDestroy(&cs->rhs));
  PetscCall(VecDestroy(&cs->rhs0));
  PetscCall(VecScatterDestroy(&cs->toz));
  PetscCall(VecDestroy(&cs->all));
  PetscCall(VecScatterDestroy(&cs->toall));
  PetscCall(VecDestroy(&cs->lam0));
  PetscCall(VecScatterDestroy(&cs->lamz));
  PetscFunctionReturn(0);
}
