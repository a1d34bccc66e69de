/* Unit tests of the condensed path (condensed.c, condensed_rows.c, mumps.c)
 * and of kkt.c, on any number of ranks (ctest: 1, 2 and 3).
 *
 * The system: a grid of nx x ny nodes, two dofs per node, K = L (x) B with L
 * the 5-point Laplacian plus a small shift and B = [2 1/2; 1/2 1] (both SPD,
 * so K is), distributed by rows (grid lines: on several ranks the separator
 * is the grid line below the next rank's); C: NC rows like mortar rows, each
 * tying a node of the left side to nodes of the right side (far apart in the
 * numbering, as a contact pair is); K_g = K + g C^T C; f varies along the rows.
 * Against a dense computation (LAPACK Cholesky of the gathered K_g):
 *  - w = C K_g^-1 f (CondensedGaps at nu = 0) and every column of
 *    S0 = -C K_g^-1 C^T (CondensedGaps at nu = e_j, minus w), to 1e-10;
 *  - u(nu) = K_g^-1 (f - C^T nu) (CondensedRecover), to 1e-10, and a second
 *    recovery gives the same u (the condensed f is kept, not consumed);
 *  - the Jacobian rows c h S0 (active) and -h (I + g S0) (inactive), and
 *    J x = b after CondensedJacobianFactor/Solve;
 * for LDL^T and LU, the METIS ordering and MUMPS' own. Then
 *  - a K_g with a zero row (a node held by nothing), in a rank's interior and
 *    (on several ranks) in the separator: every rank raises the same
 *    "singular" error, no hang, and CondensedDestroy frees what was built;
 *  - create/destroy leaves no PETSc memory behind (-malloc_debug);
 *  - kkt.c: KKTCreate zeroes the Dirichlet columns of C and moves their part
 *    to r (r = g0 + B u_D); KKTSetActive makes an inactive row of A
 *    -(scale/c) e_j and an active one scale C_j. */
#include "condensed.h"
#include "util.h"
#include <petscblaslapack.h>
#include <stdarg.h>

#define NX 12
#define NY 14
#define NC 6

static int failures;

/* one line on rank 0; fails if cond is false on any rank */
static void Check(MPI_Comm comm, int cond, const char *fmt, ...)
{
  int         all;
  PetscMPIInt rank;
  va_list     ap;

  MPI_Allreduce(&cond, &all, 1, MPI_INT, MPI_MIN, comm);
  MPI_Comm_rank(comm, &rank);
  if (!all) failures++;
  if (rank) return;
  printf(all ? "ok   " : "FAIL ");
  va_start(ap, fmt);
  vprintf(fmt, ap);
  va_end(ap);
  printf("\n");
  fflush(stdout);
}

static PetscInt Dof(PetscInt i, PetscInt j, PetscInt c)
{
  return 2 * (j * NX + i) + c;
}

/* K = L (x) B, preallocated with room for extra entries (the pattern of C^T C) */
static PetscErrorCode BuildK(MPI_Comm comm, Mat *K)
{
  const PetscScalar B[2][2] = {{2.0, 0.5}, {0.5, 1.0}};
  PetscInt          lo, hi;

  PetscFunctionBeginUser;
  PetscCall(MatCreateAIJ(comm, PETSC_DECIDE, PETSC_DECIDE, 2 * NX * NY, 2 * NX * NY, 20, NULL, 20, NULL, K));
  PetscCall(MatSetOption(*K, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscCall(MatGetOwnershipRange(*K, &lo, &hi));
  for (PetscInt r = lo; r < hi; r++) {
    PetscInt n = r / 2, c = r % 2, i = n % NX, j = n / NX;
    PetscInt nb[5][3] = {{i, j, 1}, {i - 1, j, 0}, {i + 1, j, 0}, {i, j - 1, 0}, {i, j + 1, 0}};
    for (int k = 0; k < 5; k++) {
      PetscScalar l = nb[k][2] ? 4.1 : -1.0;
      if (nb[k][0] < 0 || nb[k][0] >= NX || nb[k][1] < 0 || nb[k][1] >= NY) continue;
      for (PetscInt d = 0; d < 2; d++) PetscCall(MatSetValue(*K, r, Dof(nb[k][0], nb[k][1], d), l * B[c][d], INSERT_VALUES));
    }
  }
  PetscCall(MatAssemblyBegin(*K, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*K, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* rows of B (C = -B in kkt.c): row k ties the y dof of left node (0, j_k)
 * (weights 2/3, 1/6 on it and the node above) to right nodes (NX-1, j_k),
 * (NX-1, j_k + 1) (weights -1/2, -1/3) */
static void RowsB(PetscInt ptr[], PetscInt col[], PetscReal val[], PetscReal g0[])
{
  for (PetscInt k = 0; k < NC; k++) {
    PetscInt  j      = 2 * k + 1;
    PetscInt  c[4]   = {Dof(0, j, 1), Dof(0, j + 1, 1), Dof(NX - 1, j, 1), Dof(NX - 1, j + 1, 1)};
    PetscReal v[4]   = {2.0 / 3, 1.0 / 6, -0.5, -1.0 / 3};
    ptr[k]           = 4 * k;
    for (int e = 0; e < 4; e++) {
      col[4 * k + e] = c[e];
      val[4 * k + e] = v[e];
    }
    g0[k] = 0.01 * (k + 1);
  }
  ptr[NC] = 4 * NC;
}

static PetscErrorCode BuildC(MPI_Comm comm, Mat K, Mat *C)
{
  PetscInt  ptr[NC + 1], col[4 * NC], lo, hi, nu;
  PetscReal val[4 * NC], g0[NC];

  PetscFunctionBeginUser;
  RowsB(ptr, col, val, g0);
  PetscCall(MatGetLocalSize(K, &nu, NULL));
  PetscCall(MatCreateAIJ(comm, PETSC_DECIDE, nu, NC, 2 * NX * NY, 4, NULL, 4, NULL, C));
  PetscCall(MatGetOwnershipRange(*C, &lo, &hi));
  for (PetscInt k = lo; k < hi; k++) {
    PetscScalar v[4];
    for (int e = 0; e < 4; e++) v[e] = -val[ptr[k] + e];
    PetscCall(MatSetValues(*C, 1, &k, 4, &col[ptr[k]], v, INSERT_VALUES));
  }
  PetscCall(MatAssemblyBegin(*C, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*C, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* the whole matrix on every rank, dense, column-major (m x n) */
static PetscErrorCode GatherDense(Mat A, PetscScalar **D)
{
  PetscInt m, n;
  IS       rows, cols;
  Mat     *sub;

  PetscFunctionBeginUser;
  PetscCall(MatGetSize(A, &m, &n));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, m, 0, 1, &rows));
  PetscCall(ISCreateStride(PETSC_COMM_SELF, n, 0, 1, &cols));
  PetscCall(MatCreateSubMatrices(A, 1, &rows, &cols, MAT_INITIAL_MATRIX, &sub));
  PetscCall(PetscCalloc1(m * n, D));
  for (PetscInt i = 0; i < m; i++) {
    PetscInt           nc;
    const PetscInt    *c;
    const PetscScalar *v;
    PetscCall(MatGetRow(sub[0], i, &nc, &c, &v));
    for (PetscInt k = 0; k < nc; k++) (*D)[i + c[k] * m] = v[k];
    PetscCall(MatRestoreRow(sub[0], i, &nc, &c, &v));
  }
  PetscCall(MatDestroySubMatrices(1, &sub));
  PetscCall(ISDestroy(&rows));
  PetscCall(ISDestroy(&cols));
  PetscFunctionReturn(0);
}

/* the whole vector on every rank */
static PetscErrorCode GatherVec(Vec v, PetscScalar out[])
{
  Vec                all;
  VecScatter         sc;
  const PetscScalar *a;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(VecScatterCreateToAll(v, &sc, &all));
  PetscCall(VecScatterBegin(sc, v, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, v, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetSize(all, &n));
  PetscCall(VecGetArrayRead(all, &a));
  PetscCall(PetscArraycpy(out, a, n));
  PetscCall(VecRestoreArrayRead(all, &a));
  PetscCall(VecDestroy(&all));
  PetscCall(VecScatterDestroy(&sc));
  PetscFunctionReturn(0);
}

static PetscReal RelDiff(PetscInt n, const PetscScalar a[], const PetscScalar b[])
{
  PetscReal d = 0, m = 0;
  for (PetscInt i = 0; i < n; i++) {
    d = PetscMax(d, PetscAbsScalar(a[i] - b[i]));
    m = PetscMax(m, PetscAbsScalar(b[i]));
  }
  return m > 0 ? d / m : d;
}

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
  PetscCall(CondensedRecover(cs, nu, u));
  PetscCall(GatherVec(u, u1));
  PetscCall(VecSet(u, -1.0));
  PetscCall(CondensedRecover(cs, nu, u));
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
  PetscCall(CondensedJacobianFactor(cs, J));
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
  PetscCall(CondensedRecover(cs, nu, u));
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

/* kkt.c: KKTCreate moves the Dirichlet columns of C to r; KKTSetActive sets
 * the multiplier rows of the monolithic A */
static PetscErrorCode CheckKKT(MPI_Comm comm)
{
  M2dScene       s;
  M2dContactRows R;
  M2dKKT         kkt;
  Mat            K;
  Vec            f, ubc, act;
  PetscInt       ptr[NC + 1], col[4 * NC], drows[3], dall[3] = {Dof(0, 2, 1), Dof(NX - 1, 2, 1), Dof(0, 2, 0)}, nd = 0, lo, hi, N = 2 * NX * NY, NA;
  PetscReal      val[4 * NC], g0[NC], uval[3] = {0.3, -0.2, 0.5}, c = 2.0, scale = 3.0;
  PetscScalar    r[NC], *Cd, *Ad, *ub;
  IS             isu, isl;
  const PetscInt *iu, *il;
  PetscBool      ok = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&s, sizeof(s)));
  s.kkt_mat    = M2D_KKT_AIJ;
  s.unilateral = PETSC_TRUE;
  RowsB(ptr, col, val, g0);
  R.n   = NC;
  R.ptr = ptr;
  R.col = col;
  R.val = val;
  R.g0  = g0;
  PetscCall(BuildK(comm, &K));
  PetscCall(MatCreateVecs(K, &ubc, &f));
  PetscCall(VecSet(f, 1.0));
  PetscCall(VecGetOwnershipRange(ubc, &lo, &hi));
  for (int k = 0; k < 3; k++)
    if (dall[k] >= lo && dall[k] < hi) {
      drows[nd++] = dall[k];
      PetscCall(VecSetValue(ubc, dall[k], uval[k], INSERT_VALUES));
    }
  PetscCall(VecAssemblyBegin(ubc));
  PetscCall(VecAssemblyEnd(ubc));
  PetscCall(KKTCreate(&s, &R, K, f, ubc, nd, drows, &kkt));

  /* C = -B without the Dirichlet columns; r = g0 - C_full u_D = g0 + B u_D */
  PetscCall(GatherDense(kkt.C, &Cd));
  PetscCall(PetscCalloc1(N, &ub));
  for (int k = 0; k < 3; k++) ub[dall[k]] = uval[k];
  for (PetscInt k = 0; k < NC; k++) {
    PetscScalar rk = g0[k];
    for (PetscInt e = ptr[k]; e < ptr[k + 1]; e++) {
      PetscBool dir = (PetscBool)(ub[col[e]] != 0);
      rk += val[e] * ub[col[e]];
      ok = (PetscBool)(ok && Cd[k + col[e] * NC] == (dir ? 0.0 : -val[e]));
    }
    r[k] = rk;
  }
  Check(comm, ok, "KKTCreate: C = -B, its Dirichlet columns zero");
  {
    PetscScalar rr[NC];
    PetscCall(GatherVec(kkt.r, rr));
    Check(comm, RelDiff(NC, rr, r) < 1e-14 && r[0] != g0[0], "KKTCreate: r = g0 + B u_D (%.1e)", (double)RelDiff(NC, rr, r));
  }

  /* inactive rows (even k): -(scale/c) e_k; active: scale C_k, zero diagonal */
  PetscCall(MatCreateVecs(kkt.Ct, &act, NULL));
  PetscCall(VecGetOwnershipRange(act, &lo, &hi));
  for (PetscInt k = lo; k < hi; k++) PetscCall(VecSetValue(act, k, (PetscScalar)(k % 2), INSERT_VALUES));
  PetscCall(VecAssemblyBegin(act));
  PetscCall(VecAssemblyEnd(act));
  PetscCall(KKTSetActive(&kkt, act, c, scale));
  PetscCall(MatGetSize(kkt.A, &NA, NULL));
  PetscCall(GatherDense(kkt.A, &Ad));
  PetscCall(ISAllGather(kkt.isu, &isu));
  PetscCall(ISAllGather(kkt.isl, &isl));
  PetscCall(ISGetIndices(isu, &iu));
  PetscCall(ISGetIndices(isl, &il));
  ok = PETSC_TRUE;
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
  PetscCall(PetscFree(ub));
  PetscCall(VecDestroy(&act));
  PetscCall(KKTDestroy(&kkt));
  PetscCall(MatDestroy(&K));
  PetscCall(VecDestroy(&f));
  PetscCall(VecDestroy(&ubc));
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
  PetscCall(CheckKKT(comm));
  PetscCall(DenseDestroy(&d));
  PetscCall(SystemDestroy(&sy));
  PetscCallMPI(MPI_Allreduce(&failures, &any, 1, MPI_INT, MPI_MAX, comm));
  PetscCall(PetscFinalize());
  return any ? 1 : 0;
}
