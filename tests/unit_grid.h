/* unit_grid.h - what the C unit tests of the condensed path, kkt.c and
 * ordering.c share: a check that agrees over the ranks, and a small system on
 * a grid (two dofs per node) with contact-like rows, gathered on every rank
 * for dense reference answers. Header-only (static inline). */
#ifndef M2D_UNIT_GRID_H
#define M2D_UNIT_GRID_H
#include <petscmat.h>
#include <stdarg.h>
#include <stdio.h>

/* the grid: NX x NY nodes; NC contact-like rows */
#define NX 12
#define NY 14
#define NC 6

static int failures; /* checks failed on any rank */

/* one line on rank 0; fails if cond is false on any rank */
static inline void Check(MPI_Comm comm, int cond, const char *fmt, ...)
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

static inline PetscInt Dof(PetscInt i, PetscInt j, PetscInt c)
{
  return 2 * (j * NX + i) + c;
}

/* K = L (x) B, preallocated with room for extra entries (the pattern of C^T C) */
static inline PetscErrorCode BuildK(MPI_Comm comm, Mat *K)
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
static inline void RowsB(PetscInt ptr[], PetscInt col[], PetscReal val[], PetscReal g0[])
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

static inline PetscErrorCode BuildC(MPI_Comm comm, Mat K, Mat *C)
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
static inline PetscErrorCode GatherDense(Mat A, PetscScalar **D)
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
static inline PetscErrorCode GatherVec(Vec v, PetscScalar out[])
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

static inline PetscReal RelDiff(PetscInt n, const PetscScalar a[], const PetscScalar b[])
{
  PetscReal d = 0, m = 0;
  for (PetscInt i = 0; i < n; i++) {
    d = PetscMax(d, PetscAbsScalar(a[i] - b[i]));
    m = PetscMax(m, PetscAbsScalar(b[i]));
  }
  return m > 0 ? d / m : d;
}
#endif
