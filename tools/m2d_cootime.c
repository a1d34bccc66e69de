/* m2d_cootime - PETSc's COO assembly against the program's own (issue 15:
 * "COO preallocation if it measures no slower"):
 *
 *   mpiexec -n P m2d_cootime -options_file options/hertz.opts -mesh hertz_5.msh [-repeat N]
 *
 * Own: MeshCreateMatrix (preallocation from the cell lists) + the element
 * loop with MatSetValuesLocal (what ElasticityAssemble does for K).
 * COO: MatSetPreallocationCOOLocal with the 64 (row, column) pairs of every
 * cell, then MatSetValuesCOO with the same element matrices (Q4Stiffness).
 * Both K compared entry by entry (max |difference| / max |K|), seconds max
 * over ranks, min of N repeats. Prints one line. (The frames of inclined
 * supports and the loads are not part of either timing.) */
#include "elasticity.h"
#include "mesh.h"

typedef struct {
  PetscReal D[M2D_MAX_BODIES][9], lam[M2D_MAX_BODIES];
} Materials;

/* the cell's corner coordinates and local dofs (8) */
static PetscErrorCode CellDofs(const M2dMesh *m, const M2dMeshArrays *ar, PetscInt c, PetscReal xy[8], PetscInt dofs[8])
{
  PetscFunctionBeginUser;
  MeshCellCoordinates(m, ar->ca, ar->cs, c, xy);
  for (int a = 0; a < 4; a++) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(ar->lsec, m->cellverts[4 * (c - m->cStart) + a], &off));
    dofs[2 * a] = off, dofs[2 * a + 1] = off + 1;
  }
  PetscFunctionReturn(0);
}

/* K by the element loop (coo == NULL: MatSetValuesLocal) or into coo[64 per cell] */
static PetscErrorCode Elements(const M2dMesh *m, const M2dScene *s, const Materials *mt, Mat K, PetscScalar coo[], PetscInt ci[], PetscInt cj[])
{
  M2dMeshArrays ar;

  PetscFunctionBeginUser;
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    PetscReal xy[8], Ke[64];
    PetscInt  dofs[8], b = m->cellbody[c - m->cStart], k = 64 * (c - m->cStart);
    PetscCall(CellDofs(m, &ar, c, xy, dofs));
    if (ci) {
      for (int i = 0; i < 64; i++) ci[k + i] = dofs[i / 8], cj[k + i] = dofs[i % 8];
      continue;
    }
    Q4Stiffness(xy, mt->D[b], s->sri, mt->lam[b], Ke);
    if (coo)
      for (int i = 0; i < 64; i++) coo[k + i] = Ke[i];
    else PetscCall(MatSetValuesLocal(K, 8, dofs, 8, dofs, Ke, ADD_VALUES));
  }
  PetscCall(MeshArraysClose(&ar));
  PetscFunctionReturn(0);
}

static double MaxTime(MPI_Comm comm, double t)
{
  MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPI_DOUBLE, MPI_MAX, comm);
  return t;
}

int main(int argc, char **argv)
{
  MPI_Comm               comm;
  M2dScene               s;
  M2dMesh                m;
  Materials              mt;
  PetscInt               repeat = 3, nc;
  double                 own = 1e300, coo = 1e300, t;
  PetscReal              diff = 0, kmax = 0;
  PetscMPIInt            size;
  ISLocalToGlobalMapping ltog;

  PetscCall(PetscInitialize(&argc, &argv, NULL, "m2d_cootime: COO assembly against our own preallocation and element loop\n"));
  comm = PETSC_COMM_WORLD;
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-repeat", &repeat, NULL));
  PetscCall(SceneReadOptions(comm, &s));
  PetscCall(MeshCreate(comm, &s, &m));
  PetscCall(SceneReadMaterials(comm, &s));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (PetscInt b = 0; b < s.nbody; b++) {
    M2dMaterialMatrix(s.body[b].E, s.body[b].nu, s.plane, mt.D[b]);
    mt.lam[b] = M2dLambda(s.body[b].E, s.body[b].nu, s.plane);
  }
  nc = m.cEnd - m.cStart;
  PetscCall(DMGetLocalToGlobalMapping(m.dm, &ltog));
  for (PetscInt r = 0; r < repeat; r++) {
    Mat          K1, K2;
    PetscInt    *ci, *cj, n;
    PetscScalar *cv;
    PetscCallMPI(MPI_Barrier(comm));
    t = MPI_Wtime();
    PetscCall(MeshCreateMatrix(&m, 0, NULL, NULL, &K1));
    PetscCall(Elements(&m, &s, &mt, K1, NULL, NULL, NULL));
    PetscCall(MatAssemblyBegin(K1, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(K1, MAT_FINAL_ASSEMBLY));
    own = PetscMin(own, MaxTime(comm, MPI_Wtime() - t));
    PetscCallMPI(MPI_Barrier(comm));
    t = MPI_Wtime();
    PetscCall(MatGetLocalSize(K1, &n, NULL));
    PetscCall(MatCreate(comm, &K2));
    PetscCall(MatSetSizes(K2, n, n, PETSC_DETERMINE, PETSC_DETERMINE));
    PetscCall(MatSetBlockSize(K2, 2));
    PetscCall(MatSetType(K2, MATAIJ));
    PetscCall(MatSetLocalToGlobalMapping(K2, ltog, ltog));
    PetscCall(PetscMalloc3(64 * nc + 1, &ci, 64 * nc + 1, &cj, 64 * nc + 1, &cv));
    PetscCall(Elements(&m, &s, &mt, K2, NULL, ci, cj));
    PetscCall(MatSetPreallocationCOOLocal(K2, 64 * nc, ci, cj));
    PetscCall(Elements(&m, &s, &mt, K2, cv, NULL, NULL));
    PetscCall(MatSetValuesCOO(K2, cv, ADD_VALUES));
    coo = PetscMin(coo, MaxTime(comm, MPI_Wtime() - t));
    PetscCall(PetscFree3(ci, cj, cv));
    PetscCall(MatNorm(K1, NORM_MAX, &kmax));
    PetscCall(MatAXPY(K2, -1.0, K1, DIFFERENT_NONZERO_PATTERN));
    PetscCall(MatNorm(K2, NORM_MAX, &diff));
    PetscCall(MatDestroy(&K1));
    PetscCall(MatDestroy(&K2));
  }
  PetscCall(PetscPrintf(comm, "ranks %d, cells %" PetscInt_FMT ": own preallocation + MatSetValuesLocal %.3f s, COO %.3f s, ratio %.2f (min of %" PetscInt_FMT "); K equal to %.1e\n", size, m.ncell_global, own, coo, coo / own, repeat, (double)(diff / kmax)));
  PetscCall(MeshDestroy(&m));
  PetscCall(PetscFinalize());
  return 0;
}
