/* Unit tests of the condensed path (condensed.c, condensed_rows.c, mumps.c)
 * on any number of ranks (ctest: 1, 2 and 3).
 *
 * The system (unit_grid.h): a grid of NX x NY nodes, two dofs per node,
 * K = L (x) B with L the 5-point Laplacian plus a small shift and
 * B = [2 1/2; 1/2 1] (both SPD, so K is), distributed by rows (on several
 * ranks the separator is the grid line below the next rank's); C: NC rows
 * like mortar rows, each tying a node of the left side to nodes of the right
 * side (far apart in the numbering, as a contact pair is); K_g = K + g C^T C;
 * f varies along the rows. Against a dense computation (LAPACK Cholesky of
 * the gathered K_g):
 *  - w = C K_g^-1 f (CondensedGaps at nu = 0) and every column of
 *    S0 = -C K_g^-1 C^T (CondensedGaps at nu = e_j, minus w), to 1e-10;
 *  - u(nu) = K_g^-1 (f - C^T nu) (CondensedRecover), to 1e-10, and a second
 *    recovery gives the same u;
 *  - the Jacobian rows c h S0 (active) and -h (I + g S0) (inactive), and
 *    J x = b after CondensedJacobianFactor/Solve;
 * for LDL^T and LU, the METIS ordering and MUMPS' own. Then
 *  - a separator node held by nothing (zero rows and columns, several ranks):
 *    every rank raises the same "singular" error, no hang, and
 *    CondensedDestroy frees what was built;
 *  - create/recover/destroy leaves no PETSc memory behind (-malloc_debug);
 *  - the MUMPS wrapper alone: the Schur complement, condensation and
 *    expansion of a 5 x 5 matrix per rank against LAPACK; a bad pivot order
 *    on one rank raises the same error on every rank (a rank without rows
 *    joins the agreement). */
#include "condensed.h"
#include "util.h"
#include "unit_grid.h"
#include <petscblaslapack.h>

/* the test system: K_g = K + g C^T C, C, C^T, f */
typedef struct {
  Mat       Kg, C, Ct;
  Vec       f;
  PetscReal gamma;
} System;

static PetscErrorCode SystemCreate(MPI_Comm comm, System *sy)
{
  Mat      K, CtC;
  PetscInt lo, hi;

  PetscFunctionBeginUser;
  PetscCall(BuildK(comm, &K));
  PetscCall(BuildC(comm, K, &sy->C));
  PetscCall(MatTranspose(sy->C, MAT_INITIAL_MATRIX, &sy->Ct));
  PetscCall(MatTransposeMatMult(sy->C, sy->C, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &CtC));
  sy->gamma = 7.5;
  PetscCall(MatDuplicate(K, MAT_COPY_VALUES, &sy->Kg));
  PetscCall(MatAXPY(sy->Kg, sy->gamma, CtC, DIFFERENT_NONZERO_PATTERN));
  PetscCall(MatCreateVecs(sy->Kg, NULL, &sy->f));
  PetscCall(VecGetOwnershipRange(sy->f, &lo, &hi));
  for (PetscInt i = lo; i < hi; i++) PetscCall(VecSetValue(sy->f, i, PetscCosReal(0.37 * i) + 0.1, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(sy->f));
  PetscCall(VecAssemblyEnd(sy->f));
  PetscCall(MatDestroy(&K));
  PetscCall(MatDestroy(&CtC));
  PetscFunctionReturn(0);
}

static PetscErrorCode SystemDestroy(System *sy)
{
  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&sy->Kg));
  PetscCall(MatDestroy(&sy->C));
  PetscCall(MatDestroy(&sy->Ct));
  PetscCall(VecDestroy(&sy->f));
  PetscFunctionReturn(0);
}

/* the dense answers: X = K_g^-1 [f, C^T] (N x (1 + NC)), then w, S0 */
typedef struct {
  PetscInt     N;
  PetscScalar *X, *Cd, w[NC], S0[NC * NC];
} Dense;

static PetscErrorCode DenseCreate(System *sy, Dense *d)
{
  PetscScalar *Kd;
  PetscBLASInt bN, nrhs = 1 + NC, info;

  PetscFunctionBeginUser;
  PetscCall(MatGetSize(sy->Kg, &d->N, NULL));
  PetscCall(GatherDense(sy->Kg, &Kd));
  PetscCall(GatherDense(sy->C, &d->Cd)); /* NC x N */
  PetscCall(PetscMalloc1(d->N * (1 + NC), &d->X));
  PetscCall(GatherVec(sy->f, d->X));
  for (PetscInt k = 0; k < NC; k++)
    for (PetscInt i = 0; i < d->N; i++) d->X[i + (1 + k) * d->N] = d->Cd[k + i * NC];
  PetscCall(PetscBLASIntCast(d->N, &bN));
  PetscCallBLAS("LAPACKpotrf", LAPACKpotrf_("L", &bN, Kd, &bN, &info));
  PetscCheck(info == 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "test: K_g not SPD");
  PetscCallBLAS("LAPACKpotrs", LAPACKpotrs_("L", &bN, &nrhs, Kd, &bN, d->X, &bN, &info));
  for (PetscInt k = 0; k < NC; k++) {
    d->w[k] = 0;
    for (PetscInt i = 0; i < d->N; i++) d->w[k] += d->Cd[k + i * NC] * d->X[i];
    for (PetscInt j = 0; j < NC; j++) {
      d->S0[k + j * NC] = 0;
      for (PetscInt i = 0; i < d->N; i++) d->S0[k + j * NC] -= d->Cd[k + i * NC] * d->X[i + (1 + j) * d->N];
    }
  }
  PetscCall(PetscFree(Kd));
  PetscFunctionReturn(0);
}

static PetscErrorCode DenseDestroy(Dense *d)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(d->X));
  PetscCall(PetscFree(d->Cd));
  PetscFunctionReturn(0);
}

/* S0 column by column through CondensedGaps: C u(e_j) - C u(0) */
static PetscErrorCode CheckGaps(MPI_Comm comm, M2dCondensed *cs, System *sy, const Dense *d, const char *label)
{
  Vec         nu, cu;
  PetscScalar w[NC], g[NC], S0[NC * NC];

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(sy->Ct, &nu, NULL));
  PetscCall(VecDuplicate(nu, &cu));
  PetscCall(VecZeroEntries(nu));
  PetscCall(CondensedGaps(cs, nu, cu));
  PetscCall(GatherVec(cu, w));
  Check(comm, RelDiff(NC, w, d->w) < 1e-10, "%s: w = C K_g^-1 f equals the dense one (%.1e)", label, (double)RelDiff(NC, w, d->w));
  for (PetscInt j = 0; j < NC; j++) {
    PetscCall(VecZeroEntries(nu));
    PetscCall(VecSetValue(nu, j, 1.0, INSERT_VALUES));
    PetscCall(VecAssemblyBegin(nu));
    PetscCall(VecAssemblyEnd(nu));
    PetscCall(CondensedGaps(cs, nu, cu));
    PetscCall(GatherVec(cu, g));
    for (PetscInt k = 0; k < NC; k++) S0[k + j * NC] = g[k] - w[k];
  }
  Check(comm, RelDiff(NC * NC, S0, d->S0) < 1e-10, "%s: S0 = -C K_g^-1 C^T equals the dense one (%.1e)", label, (double)RelDiff(NC * NC, S0, d->S0));
  PetscCall(VecDestroy(&nu));
  PetscCall(VecDestroy(&cu));
  PetscFunctionReturn(0);
}

/* u(nu) = K_g^-1 (f - C^T nu), twice */
static PetscErrorCode CheckRecover(MPI_Comm comm, M2dCondensed *cs, System *sy, const Dense *d, const char *label)
{
  Vec          nu, u;
  PetscInt     N = d->N, lo, hi;
  PetscScalar *u1, *u2, *ur, nuv[NC];

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(sy->Ct, &nu, &u));
  PetscCall(VecGetOwnershipRange(nu, &lo, &hi));
  for (PetscInt k = 0; k < NC; k++) nuv[k] = PetscSinReal(k + 1.0);
  for (PetscInt k = lo; k < hi; k++) PetscCall(VecSetValue(nu, k, nuv[k], INSERT_VALUES));
  PetscCall(VecAssemblyBegin(nu));
  PetscCall(VecAssemblyEnd(nu));
  PetscCall(PetscMalloc3(N, &u1, N, &u2, N, &ur));
  for (PetscInt i = 0; i < N; i++) {
    ur[i] = d->X[i];
    for (PetscInt k = 0; k < NC; k++) ur[i] -= d->X[i + (1 + k) * N] * nuv[k];
  }
  PetscCall(CondensedRecover(cs, PETSC_TRUE, nu, u));
  PetscCall(GatherVec(u, u1));
  PetscCall(VecSet(u, -1.0));
  PetscCall(CondensedRecover(cs, PETSC_TRUE, nu, u));
  PetscCall(GatherVec(u, u2));
  Check(comm, RelDiff(N, u1, ur) < 1e-10, "%s: u(nu) = K_g^-1 (f - C^T nu) equals the dense one (%.1e)", label, (double)RelDiff(N, u1, ur));
  Check(comm, RelDiff(N, u2, u1) == 0, "%s: a second recovery gives the same u", label);
  PetscCall(PetscFree3(u1, u2, ur));
  PetscCall(VecDestroy(&nu));
  PetscCall(VecDestroy(&u));
  PetscFunctionReturn(0);
}

/* the Jacobian of the steps on nu and its LU: rows c h S0 / -h (I + g S0), J x = b */
static PetscErrorCode CheckJacobian(MPI_Comm comm, M2dCondensed *cs, System *sy, const Dense *d, const char *label)
{
  Vec          act, b, x, r;
  Mat          J;
  PetscInt     n, lo, hi;
  PetscReal    c = 3.0, h = 0.5, nr, nb;
  PetscScalar *Jd, Jr[NC * NC];

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(sy->Ct, &act, NULL));
  PetscCall(VecGetLocalSize(act, &n));
  PetscCall(VecGetOwnershipRange(act, &lo, &hi));
  for (PetscInt k = lo; k < hi; k++) PetscCall(VecSetValue(act, k, (PetscScalar)(k % 2), INSERT_VALUES));
  PetscCall(VecAssemblyBegin(act));
  PetscCall(VecAssemblyEnd(act));
  PetscCall(MatCreateDense(comm, n, n, NC, NC, NULL, &J));
  PetscCall(CondensedJacobian(cs, act, c, h, J));
  PetscCall(GatherDense(J, &Jd));
  for (PetscInt i = 0; i < NC; i++)
    for (PetscInt j = 0; j < NC; j++) Jr[i + j * NC] = i % 2 ? c * h * d->S0[i + j * NC] : -h * (sy->gamma * d->S0[i + j * NC] + (i == j));
  Check(comm, RelDiff(NC * NC, Jd, Jr) < 1e-10, "%s: Jacobian rows c h S0 (active), -h (I + g S0) (inactive) (%.1e)", label, (double)RelDiff(NC * NC, Jd, Jr));
  PetscCall(VecDuplicate(act, &b));
  PetscCall(VecDuplicate(act, &x));
  PetscCall(VecDuplicate(act, &r));
  for (PetscInt k = lo; k < hi; k++) PetscCall(VecSetValue(b, k, k + 1.0, INSERT_VALUES));
  PetscCall(VecAssemblyBegin(b));
  PetscCall(VecAssemblyEnd(b));
  PetscCall(CondensedJacobianFactor(cs, J, NULL, NULL, NULL, 0, 0));
  PetscCall(CondensedJacobianSolve(cs, b, x));
  PetscCall(MatMult(J, x, r));
  PetscCall(VecAXPY(r, -1.0, b));
  PetscCall(VecNorm(r, NORM_2, &nr));
  PetscCall(VecNorm(b, NORM_2, &nb));
  Check(comm, nr < 1e-12 * nb, "%s: J x = b after the dense LU (|J x - b| / |b| = %.1e)", label, (double)(nr / nb));
  PetscCall(PetscFree(Jd));
  PetscCall(MatDestroy(&J));
  PetscCall(VecDestroy(&act));
  PetscCall(VecDestroy(&b));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&r));
  PetscFunctionReturn(0);
}

static void DefaultOptions(M2dCondensedOptions *o)
{
  PetscMemzero(o, sizeof(*o));
  o->ldlt            = PETSC_TRUE;
  o->ordering        = M2D_ORDERING_METIS;
  o->mumps.ordering  = 7;
  o->mumps.workspace = 20;
  o->mumps.symbolic  = 2;
}

static PetscErrorCode CheckPath(MPI_Comm comm, System *sy, const Dense *d, const M2dCondensedOptions *o, const char *label)
{
  M2dCondensed    *cs;
  M2dCondensedInfo info;
  PetscMPIInt      size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(CondensedCreate(sy->Kg, sy->C, sy->Ct, sy->f, sy->gamma, o, &cs));
  PetscCall(CondensedGetInfo(cs, &info));
  Check(comm, info.multipliers == NC && info.interface_unknowns == info.separator_rows + NC && (size == 1 ? info.separator_rows == 0 : info.separator_rows > 0) && info.flops_sum > 0 && info.flops_max <= info.flops_sum,
        "%s: info: %d multipliers, %d separator rows, flops max/sum %.2f", label, (int)info.multipliers, (int)info.separator_rows, (double)(info.flops_max / info.flops_sum));
  PetscCall(CheckGaps(comm, cs, sy, d, label));
  PetscCall(CheckRecover(comm, cs, sy, d, label));
  PetscCall(CheckJacobian(comm, cs, sy, d, label));
  PetscCall(CondensedDestroy(&cs));
  Check(comm, cs == NULL, "%s: CondensedDestroy clears the pointer", label);
  PetscFunctionReturn(0);
}

/* a K_g whose rows and columns of node n are zero (a node held by nothing),
 * n in the separator (several ranks): the Cholesky factorization of the
 * separator fails on every rank alike. (In a rank's interior MUMPS 5.5
 * reports no null pivot when a Schur complement is requested, so that case
 * is left to the program's rigid-mode check before the solve.) */
static PetscErrorCode CheckSingular(MPI_Comm comm, System *sy, const M2dCondensedOptions *o, PetscInt n)
{
  System         s2 = *sy;
  M2dCondensed  *cs = NULL;
  PetscInt       rows[2], nr = 0, lo, hi;
  PetscErrorCode ierr;
  const char    *msg;

  PetscFunctionBeginUser;
  PetscCall(MatDuplicate(sy->Kg, MAT_COPY_VALUES, &s2.Kg));
  PetscCall(MatGetOwnershipRange(s2.Kg, &lo, &hi));
  for (PetscInt c = 0; c < 2; c++)
    if (2 * n + c >= lo && 2 * n + c < hi) rows[nr++] = 2 * n + c;
  PetscCall(MatZeroRowsColumns(s2.Kg, nr, rows, 0.0, NULL, NULL));
  PetscCall(M2dInstallErrorHandler());
  ierr = CondensedCreate(s2.Kg, s2.C, s2.Ct, s2.f, s2.gamma, o, &cs);
  PetscCall(M2dRemoveErrorHandler());
  msg = M2dFirstError();
  Check(comm, ierr != 0 && strstr(msg, "singular") && strstr(msg, "held by nothing"), "a separator node held by nothing: every rank raises \"%s\"", ierr ? msg : "(no error)");
  M2dClearError();
  PetscCall(CondensedDestroy(&cs));
  PetscCall(MatDestroy(&s2.Kg));
  PetscFunctionReturn(0);
}

/* create, use and destroy leave no PETSc memory behind (needs -malloc_debug) */
static PetscErrorCode CheckNoLeak(MPI_Comm comm, System *sy, const M2dCondensedOptions *o)
{
  M2dCondensed  *cs;
  PetscLogDouble m0, m1;
  PetscBool      tracked;
  Vec            nu, u;

  PetscFunctionBeginUser;
  PetscCall(PetscMallocGetDebug(&tracked, NULL, NULL));
  PetscCall(MatCreateVecs(sy->Ct, &nu, &u));
  PetscCall(VecSet(nu, 0.5));
  PetscCall(PetscMallocGetCurrentUsage(&m0));
  PetscCall(CondensedCreate(sy->Kg, sy->C, sy->Ct, sy->f, sy->gamma, o, &cs));
  PetscCall(CondensedRecover(cs, PETSC_TRUE, nu, u));
  PetscCall(CondensedDestroy(&cs));
  PetscCall(PetscMallocGetCurrentUsage(&m1));
  Check(comm, tracked && m1 == m0, "create, recover, destroy: %g bytes of PETSc memory left (tracked: %s)", (double)(m1 - m0), tracked ? "yes" : "no, run with -malloc_debug");
  PetscCall(VecDestroy(&nu));
  PetscCall(VecDestroy(&u));
  PetscFunctionReturn(0);
}

/* mumps.c alone: every rank its own 5 x 5 matrix A = tridiag(-1, 4 + rank, -1)
 * plus a(0,4) = a(4,0) = 1/2, the last 2 rows Schur variables. The Schur
 * complement, and condensation + expansion = A^-1 b, against LAPACK */
static PetscErrorCode CheckMumpsWrapper(MPI_Comm comm, PetscBool symmetric)
{
  const PetscInt  n = 5, ns = 2, ni = 3;
  PetscMPIInt     rank;
  PetscScalar     A[25] = {0}, b[5], x[5], rhs[5], red[2], Sref[4], *S, Aii[9], Z[3 * 3];
  M2dMumpsInt     irn[25], jcn[25];
  PetscScalar     a[25];
  PetscInt64      nnz = 0;
  M2dMumpsOptions opt = {0, 7, 0, 20, 2};
  M2dMumps       *mu;
  PetscBool       singular;
  PetscLogDouble  flops;
  PetscBLASInt    bn = 5, bi = 3, one = 1, three = 3, piv[5], info;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  for (PetscInt i = 0; i < n; i++) {
    A[i + i * n] = 4.0 + rank;
    if (i + 1 < n) A[i + (i + 1) * n] = A[i + 1 + i * n] = -1.0;
    b[i] = i + 1.0;
  }
  A[0 + 4 * n] = A[4 + 0 * n] = 0.5;
  for (PetscInt j = 0; j < n; j++)
    for (PetscInt i = 0; i < n; i++)
      if (A[i + j * n] != 0 && (!symmetric || i <= j)) {
        irn[nnz] = (M2dMumpsInt)(i + 1);
        jcn[nnz] = (M2dMumpsInt)(j + 1);
        a[nnz++] = A[i + j * n];
      }
  /* dense: S = A_ss - A_si A_ii^-1 A_is; x = A^-1 b */
  for (PetscInt j = 0; j < ni; j++)
    for (PetscInt i = 0; i < ni; i++) Aii[i + j * ni] = A[i + j * n];
  for (PetscInt j = 0; j < ns; j++)
    for (PetscInt i = 0; i < ni; i++) Z[i + j * ni] = A[i + (ni + j) * n];
  PetscCallBLAS("LAPACKgetrf", LAPACKgetrf_(&bi, &bi, Aii, &bi, piv, &info));
  PetscCallBLAS("LAPACKgetrs", LAPACKgetrs_("N", &bi, &three, Aii, &bi, piv, Z, &bi, &info));
  for (PetscInt q = 0; q < ns; q++)
    for (PetscInt p = 0; p < ns; p++) {
      Sref[p + q * ns] = A[ni + p + (ni + q) * n];
      for (PetscInt k = 0; k < ni; k++) Sref[p + q * ns] -= A[ni + p + k * n] * Z[k + q * ni];
    }
  PetscCall(PetscArraycpy(x, b, n));
  {
    PetscScalar Ac[25];
    PetscCall(PetscArraycpy(Ac, A, 25));
    PetscCallBLAS("LAPACKgetrf", LAPACKgetrf_(&bn, &bn, Ac, &bn, piv, &info));
    PetscCallBLAS("LAPACKgetrs", LAPACKgetrs_("N", &bn, &one, Ac, &bn, piv, x, &bn, &info));
  }

  PetscCall(M2dMumpsCreate(comm, n, symmetric, &opt, &mu));
  PetscCall(M2dMumpsAnalyse(mu, nnz, irn, jcn, a, NULL, ns));
  PetscCall(M2dMumpsFactor(mu, &singular, &flops));
  PetscCall(M2dMumpsGetSchur(mu, &S));
  Check(comm, !singular && RelDiff(ns * ns, S, Sref) < 1e-14, "M2dMumps (%s): Schur complement of the last 2 rows (%.1e)", symmetric ? "LDL^T" : "LU", (double)RelDiff(ns * ns, S, Sref));
  /* condensation gives the reduced right-hand side; the Schur solve and the expansion give A^-1 b */
  PetscCall(PetscArraycpy(rhs, b, n));
  PetscCall(M2dMumpsSolve(mu, M2D_MUMPS_CONDENSE, rhs, red));
  {
    PetscScalar det = S[0] * S[3] - S[1] * S[2], r0 = red[0], r1 = red[1];
    red[0] = (S[3] * r0 - S[2] * r1) / det;
    red[1] = (S[0] * r1 - S[1] * r0) / det;
  }
  PetscCall(M2dMumpsSolve(mu, M2D_MUMPS_EXPAND, rhs, red));
  rhs[3] = red[0];
  rhs[4] = red[1];
  Check(comm, RelDiff(n, rhs, x) < 1e-14, "M2dMumps (%s): condensation, Schur solve, expansion = A^-1 b (%.1e)", symmetric ? "LDL^T" : "LU", (double)RelDiff(n, rhs, x));
  PetscCall(PetscFree(S));
  PetscCall(M2dMumpsDestroy(&mu));
  Check(comm, mu == NULL, "M2dMumps (%s): destroy clears the pointer", symmetric ? "LDL^T" : "LU");
  PetscFunctionReturn(0);
}

/* a bad pivot order on the last rank only (rank 0 without rows, on several
 * ranks): the analysis fails there and every rank raises the same error */
static PetscErrorCode CheckMumpsAgreement(MPI_Comm comm)
{
  PetscMPIInt     rank, size;
  M2dMumpsInt     irn[3] = {1, 2, 3}, jcn[3] = {1, 2, 3}, perm[3] = {1, 2, 3};
  PetscScalar     a[3] = {1, 2, 3};
  M2dMumpsOptions opt = {0, 7, 0, 20, 2};
  M2dMumps       *mu;
  PetscErrorCode  ierr;
  const char     *msg;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (rank == size - 1) perm[2] = 1; /* not a permutation */
  PetscCall(M2dMumpsCreate(comm, size > 1 && rank == 0 ? 0 : 3, PETSC_TRUE, &opt, &mu));
  PetscCall(M2dInstallErrorHandler());
  ierr = M2dMumpsAnalyse(mu, 3, irn, jcn, a, perm, 0);
  PetscCall(M2dRemoveErrorHandler());
  msg = M2dFirstError();
  Check(comm, ierr != 0 && strstr(msg, "MUMPS analysis failed: INFOG(1) = -4"), "M2dMumps: a bad pivot order on the last rank: every rank raises \"%s\"", ierr ? msg : "(no error)");
  M2dClearError();
  PetscCall(M2dMumpsDestroy(&mu));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  MPI_Comm            comm;
  System              sy;
  Dense               d;
  M2dCondensedOptions o;
  PetscMPIInt         size;
  int                 any;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  comm = PETSC_COMM_WORLD;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(SystemCreate(comm, &sy));
  PetscCall(DenseCreate(&sy, &d));
  DefaultOptions(&o);
  PetscCall(CheckPath(comm, &sy, &d, &o, "LDL^T, METIS"));
  o.ordering = M2D_ORDERING_MUMPS;
  PetscCall(CheckPath(comm, &sy, &d, &o, "LDL^T, MUMPS' ordering"));
  o.ordering = M2D_ORDERING_METIS;
  o.ldlt     = PETSC_FALSE;
  PetscCall(CheckPath(comm, &sy, &d, &o, "LU, METIS"));
  DefaultOptions(&o);
  if (size > 1) { /* a node of rank 0 coupled to rank 1, away from C's columns */
    const PetscInt *ranges;
    PetscCall(MatGetOwnershipRanges(sy.Kg, &ranges));
    PetscCall(CheckSingular(comm, &sy, &o, ranges[1] / 2 - NX / 2));
  }
  PetscCall(CheckNoLeak(comm, &sy, &o));
  PetscCall(CheckMumpsWrapper(comm, PETSC_TRUE));
  PetscCall(CheckMumpsWrapper(comm, PETSC_FALSE));
  PetscCall(CheckMumpsAgreement(comm));
  PetscCall(DenseDestroy(&d));
  PetscCall(SystemDestroy(&sy));
  PetscCallMPI(MPI_Allreduce(&failures, &any, 1, MPI_INT, MPI_MAX, comm));
  PetscCall(PetscFinalize());
  return any ? 1 : 0;
}
