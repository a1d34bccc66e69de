/* Unit tests of ordering.c (1 and 2 ranks):
 *  - M2dOrderingMetis on the vector Laplacian of an NG x NG grid (two dofs
 *    per node, one sequential matrix per rank): the positions form a
 *    permutation, the two dofs of a node pivot one after the other, the
 *    `last` rows come last in the given order, and the Cholesky factor has
 *    far fewer nonzeros than in the natural order (counted by symbolic
 *    elimination in the test: eliminating a row joins its remaining
 *    neighbours into a clique);
 *  - M2dOrderingSetupKSP with PCCHOLESKY + MUMPS: MUMPS orders with AMF on 1
 *    and 2 ranks (ICNTL(7) = 2 as MUMPS ran, and INFOG(7) = 2, the ordering
 *    it reports it used: on a small matrix its automatic choice is AMF too),
 *    and with the user's -mat_mumps_icntl_7 when given; PCLU on one rank
 *    gets the METIS ordering (ICNTL(7) = INFOG(7) = 1, a given pivot order). */
#include "ordering.h"
#include "unit_grid.h"

#define NG 20

/* the vector Laplacian L (x) [2 1/2; 1/2 1] of the grid: 2 NG^2 rows (node-major) */
static PetscErrorCode GridMatrix(MPI_Comm comm, PetscInt nlocal, Mat *A)
{
  PetscInt lo, hi, N = 2 * NG * NG;

  PetscFunctionBeginUser;
  PetscCall(MatCreateAIJ(comm, nlocal, nlocal, N, N, 10, NULL, 10, NULL, A));
  PetscCall(MatGetOwnershipRange(*A, &lo, &hi));
  for (PetscInt r = lo; r < hi; r++) {
    PetscInt n = r / 2, c = r % 2, i = n % NG, j = n / NG;
    PetscInt nb[5][2] = {{i, j}, {i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
    for (int k = 0; k < 5; k++) {
      if (nb[k][0] < 0 || nb[k][0] >= NG || nb[k][1] < 0 || nb[k][1] >= NG) continue;
      for (PetscInt d = 0; d < 2; d++) {
        PetscScalar b = c == d ? (c ? 1.0 : 2.0) : 0.5;
        PetscCall(MatSetValue(*A, r, 2 * (nb[k][1] * NG + nb[k][0]) + d, (k ? -1.0 : 4.1) * b, INSERT_VALUES));
      }
    }
  }
  PetscCall(MatAssemblyBegin(*A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*A, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* nonzeros below the diagonal of the Cholesky factor of the sequential A in
 * the pivot order pos (pos[i] = position of row i), by graph elimination */
static PetscErrorCode FactorNonzeros(Mat A, const PetscInt pos[], PetscInt64 *nnz)
{
  PetscInt        n, m, *order;
  unsigned char  *adj, *gone;
  const PetscInt *ia, *ja;
  PetscBool       done;

  PetscFunctionBeginUser;
  PetscCall(MatGetRowIJ(A, 0, PETSC_TRUE, PETSC_FALSE, &n, &ia, &ja, &done));
  PetscCall(PetscCalloc2(n * n, &adj, n, &gone));
  PetscCall(PetscMalloc1(n, &order));
  for (PetscInt i = 0; i < n; i++)
    for (PetscInt k = ia[i]; k < ia[i + 1]; k++)
      if (ja[k] != i) adj[i * n + ja[k]] = adj[ja[k] * n + i] = 1;
  PetscCall(MatRestoreRowIJ(A, 0, PETSC_TRUE, PETSC_FALSE, &m, &ia, &ja, &done)); /* sets m to 0 */
  for (PetscInt i = 0; i < n; i++) order[pos[i]] = i;
  *nnz = 0;
  for (PetscInt p = 0; p < n; p++) {
    PetscInt v = order[p];
    gone[v]    = 1;
    for (PetscInt a = 0; a < n; a++) {
      if (gone[a] || !adj[v * n + a]) continue;
      (*nnz)++;
      for (PetscInt b = 0; b < n; b++)
        if (!gone[b] && b != a && adj[v * n + b]) adj[a * n + b] = 1;
    }
  }
  PetscCall(PetscFree2(adj, gone));
  PetscCall(PetscFree(order));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckMetis(MPI_Comm comm)
{
  Mat             A;
  IS              pos, last;
  const PetscInt *p;
  PetscInt        n = 2 * NG * NG, lastrows[3] = {17, 5, 2 * NG * NG - 1}, *natural, *seen;
  PetscInt64      fill_metis, fill_natural;
  PetscBool       perm = PETSC_TRUE, pairs = PETSC_TRUE, inlast;

  PetscFunctionBeginUser;
  PetscCall(GridMatrix(PETSC_COMM_SELF, PETSC_DECIDE, &A));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, 3, lastrows, PETSC_COPY_VALUES, &last));
  PetscCall(M2dOrderingMetis(A, last, &pos));
  PetscCall(ISGetIndices(pos, &p));
  PetscCall(PetscCalloc2(n, &seen, n, &natural));
  for (PetscInt i = 0; i < n; i++) {
    if (p[i] < 0 || p[i] >= n || seen[p[i]]) perm = PETSC_FALSE;
    else seen[p[i]] = 1;
    natural[i] = i;
  }
  Check(comm, perm, "METIS positions of %d rows form a permutation", (int)n);
  Check(comm, p[17] == n - 3 && p[5] == n - 2 && p[n - 1] == n - 1, "the `last` rows 17, 5, %d come last, in that order (positions %d, %d, %d)", (int)(n - 1), (int)p[17], (int)p[5], (int)p[n - 1]);
  for (PetscInt k = 0; k < n / 2; k++) {
    inlast = (PetscBool)(2 * k == 17 || 2 * k + 1 == 17 || 2 * k == 5 || 2 * k + 1 == 5 || 2 * k + 1 == n - 1);
    if (!inlast && p[2 * k + 1] != p[2 * k] + 1) pairs = PETSC_FALSE;
  }
  Check(comm, pairs, "the two dofs of a node pivot one after the other (one METIS vertex)");
  PetscCall(FactorNonzeros(A, p, &fill_metis));
  PetscCall(FactorNonzeros(A, natural, &fill_natural));
  Check(comm, fill_metis < 0.8 * fill_natural, "Cholesky factor: %lld nonzeros with METIS, %lld in the natural order (ratio %.2f)", (long long)fill_metis, (long long)fill_natural, (double)fill_metis / (double)fill_natural);
  PetscCall(ISRestoreIndices(pos, &p));
  PetscCall(PetscFree2(seen, natural));
  PetscCall(ISDestroy(&pos));
  PetscCall(ISDestroy(&last));
  PetscCall(MatDestroy(&A));
  PetscFunctionReturn(0);
}

/* MUMPS' ICNTL(7) and the ordering it used (INFOG(7)) after a solve set up by M2dOrderingSetupKSP */
static PetscErrorCode SolveOrdering(MPI_Comm comm, PCType pctype, PetscInt *icntl7, PetscInt *infog7, PetscBool *metis)
{
  Mat A, F;
  Vec b, x;
  KSP ksp;
  PC  pc;

  PetscFunctionBeginUser;
  PetscCall(GridMatrix(comm, PETSC_DECIDE, &A));
  PetscCall(MatCreateVecs(A, &x, &b));
  PetscCall(VecSet(b, 1.0));
  PetscCall(KSPCreate(comm, &ksp));
  PetscCall(KSPSetOperators(ksp, A, A));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, pctype));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(KSPSetFromOptions(ksp));
  PetscCall(M2dOrderingSetupKSP(ksp, M2D_ORDERING_METIS, metis));
  PetscCall(KSPSolve(ksp, b, x));
  PetscCall(PCFactorGetMatrix(pc, &F));
  PetscCall(MatMumpsGetIcntl(F, 7, icntl7));
  PetscCall(MatMumpsGetInfog(F, 7, infog7));
  PetscCall(KSPDestroy(&ksp));
  PetscCall(MatDestroy(&A));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&b));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckSetupKSP(MPI_Comm comm)
{
  PetscInt    asked, used;
  PetscBool   metis;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscOptionsSetValue(NULL, "-mat_mumps_icntl_7", "0"));
  PetscCall(SolveOrdering(comm, PCCHOLESKY, &asked, &used, &metis));
  Check(comm, asked == 0 && used == 0 && !metis, "PCCHOLESKY + MUMPS, -mat_mumps_icntl_7 0 given: MUMPS used AMD (ICNTL(7) = %d, INFOG(7) = %d)", (int)asked, (int)used);
  PetscCall(PetscOptionsClearValue(NULL, "-mat_mumps_icntl_7"));
  PetscCall(SolveOrdering(comm, PCCHOLESKY, &asked, &used, &metis));
  Check(comm, asked == 2 && used == 2 && !metis, "PCCHOLESKY + MUMPS on %d rank(s): MUMPS used AMF (ICNTL(7) = %d, INFOG(7) = %d)", (int)size, (int)asked, (int)used);
  PetscCall(PetscOptionsClearValue(NULL, "-mat_mumps_icntl_7"));
  PetscCall(SolveOrdering(comm, PCLU, &asked, &used, &metis));
  if (size == 1) Check(comm, asked == 1 && used == 1 && metis, "PCLU + MUMPS on 1 rank: the METIS pivot order was given (ICNTL(7) = %d, INFOG(7) = %d)", (int)asked, (int)used);
  else Check(comm, asked == 2 && used == 2 && !metis, "PCLU + MUMPS on %d ranks: MUMPS used AMF (ICNTL(7) = %d, INFOG(7) = %d)", (int)size, (int)asked, (int)used);
  PetscCall(PetscOptionsClearValue(NULL, "-mat_mumps_icntl_7"));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  int any;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(CheckMetis(PETSC_COMM_WORLD));
  PetscCall(CheckSetupKSP(PETSC_COMM_WORLD));
  PetscCallMPI(MPI_Allreduce(&failures, &any, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD));
  PetscCall(PetscFinalize());
  return any ? 1 : 0;
}
