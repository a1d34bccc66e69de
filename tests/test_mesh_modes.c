/* Unit tests of MeshCreateFromMsh and MeshRigidBodyModes (mesh.h).
 * MeshCreateFromMsh: the S2 mesh read with MshRead and handed over in memory
 * (element tags dropped) gives the mesh MeshCreate gives; a node index out of
 * range is refused with a message naming the source (`what`).
 * MeshRigidBodyModes: on the S2 patch mesh (two bodies)
 * and on Hertz level 0, K assembled by ElasticityAssemble (before any Dirichlet
 * row) maps each of the 3 modes per body to zero to round-off; the modes are
 * orthonormal; a strained field (u = (x^2, x y)) is not mapped to zero, so the
 * check can fail. Run on 1 and 2 ranks (tests/CMakeLists.txt). Meshes and
 * options come from M2D_MESHES and M2D_SOURCE. */
#include "elasticity.h"
#include "mesh.h"
#include "scene.h"
#include "util.h"
#include <stdlib.h>
#include <string.h>

#include "check.h"

static PetscErrorCode CheckModes(const char *opts, const char *mesh, PetscInt nbody)
{
  MPI_Comm           comm = PETSC_COMM_WORLD;
  char               buf[4 * PETSC_MAX_PATH_LEN];
  M2dScene           s;
  M2dMesh            m;
  Mat                K;
  Vec                f, r, v;
  MatNullSpace       sp;
  PetscBool          cnst;
  PetscInt           n;
  const Vec         *z;
  PetscReal          knorm, worst = 0, worst_dot = 0, strained, vn;
  PetscSection       cs, gs;
  Vec                cl;
  const PetscScalar *ca;
  PetscScalar       *va;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscSNPrintf(buf, sizeof(buf), "-options_file %s/options/%s.opts -mesh %s/%s.msh", getenv("M2D_SOURCE"), opts, getenv("M2D_MESHES"), mesh));
  PetscCall(PetscOptionsInsertString(NULL, buf));
  PetscCall(PetscMemzero(&s, sizeof(s)));
  PetscCall(SceneReadOptions(comm, &s));
  PetscCall(MeshCreate(comm, &s, &m));
  PetscCall(SceneReadMaterials(comm, &s));
  PetscCall(MeshCreateMatrix(&m, 0, NULL, NULL, &K));
  PetscCall(DMCreateGlobalVector(m.dm, &f));
  PetscCall(VecDuplicate(f, &r));
  PetscCall(VecDuplicate(f, &v));
  {
    M2dFrames none = {0}; /* no supports: the plain frame everywhere */
    PetscCall(ElasticityAssemble(&m, &s, &none, K, f));
  }
  PetscCall(MatNorm(K, NORM_INFINITY, &knorm));
  PetscCall(MeshRigidBodyModes(&m, PETSC_TRUE, &sp));
  PetscCall(MatNullSpaceGetVecs(sp, &cnst, &n, &z));
  CHECK(n == 3 * nbody && !cnst, "%s: %" PetscInt_FMT " modes for %" PetscInt_FMT " bodies, no constant", mesh, n, nbody);
  for (PetscInt i = 0; i < n; i++) {
    PetscReal rn, zn;
    PetscCall(MatMult(K, z[i], r));
    PetscCall(VecNorm(r, NORM_INFINITY, &rn));
    PetscCall(VecNorm(z[i], NORM_INFINITY, &zn));
    worst = PetscMax(worst, rn / (knorm * zn));
    for (PetscInt j = 0; j < n; j++) {
      PetscScalar d;
      PetscCall(VecDot(z[i], z[j], &d));
      worst_dot = PetscMax(worst_dot, PetscAbsScalar(d - (i == j ? 1.0 : 0.0)));
    }
  }
  CHECK(worst < 1e-13, "%s: |K z|_inf / (|K|_inf |z|_inf) = %.1e for every mode (K before Dirichlet rows)", mesh, (double)worst);
  CHECK(worst_dot < 1e-13, "%s: modes orthonormal to %.1e", mesh, (double)worst_dot);
  /* a strained field: u = (x^2, x y) on every vertex */
  PetscCall(DMGetCoordinatesLocal(m.dm, &cl));
  PetscCall(DMGetCoordinateSection(m.dm, &cs));
  PetscCall(DMGetGlobalSection(m.dm, &gs));
  PetscCall(VecGetArrayRead(cl, &ca));
  PetscCall(VecGetArray(v, &va));
  {
    PetscInt lo;
    PetscCall(VecGetOwnershipRange(v, &lo, NULL));
    for (PetscInt p = m.vStart; p < m.vEnd; p++) {
      PetscInt g, off;
      PetscCall(PetscSectionGetOffset(gs, p, &g));
      if (g < 0) continue;
      PetscCall(PetscSectionGetOffset(cs, p, &off));
      va[g - lo]     = ca[off] * ca[off];
      va[g - lo + 1] = ca[off] * ca[off + 1];
    }
  }
  PetscCall(VecRestoreArray(v, &va));
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCall(MatMult(K, v, r));
  PetscCall(VecNorm(r, NORM_INFINITY, &strained));
  PetscCall(VecNorm(v, NORM_INFINITY, &vn));
  CHECK(strained / (knorm * vn) > 1e-6, "%s: a strained field is not mapped to zero (%.1e)", mesh, (double)(strained / (knorm * vn)));
  PetscCall(MatNullSpaceDestroy(&sp));
  PetscCall(VecDestroy(&f));
  PetscCall(VecDestroy(&r));
  PetscCall(VecDestroy(&v));
  PetscCall(MatDestroy(&K));
  PetscCall(MeshDestroy(&m));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckFromMsh(void)
{
  MPI_Comm    comm = PETSC_COMM_WORLD;
  char        buf[4 * PETSC_MAX_PATH_LEN], err[1024] = "";
  M2dScene    s;
  M2dMesh     a, b;
  MshMesh     msh;
  PetscMPIInt rank;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscOptionsClear(NULL));
  PetscCall(PetscSNPrintf(buf, sizeof(buf), "-options_file %s/options/patch_uniform.opts -mesh %s/patch_uniform.msh", getenv("M2D_SOURCE"), getenv("M2D_MESHES")));
  PetscCall(PetscOptionsInsertString(NULL, buf));
  PetscCall(PetscMemzero(&s, sizeof(s)));
  PetscCall(SceneReadOptions(comm, &s));
  PetscCall(MeshCreate(comm, &s, &a));
  PetscCall(PetscMemzero(&msh, sizeof(msh)));
  if (rank == 0) {
    CHECK(MshRead(s.mesh[0], &msh, err, sizeof(err)) == 0, "MshRead %s", err);
    free(msh.quadtag); /* optional: messages then count quads from 1 */
    msh.quadtag = NULL;
  }
  PetscCall(MeshCreateFromMsh(comm, &s, &msh, 1, "in-memory S2", &b));
  CHECK(a.ncell_global == b.ncell_global && a.nvert_global == b.nvert_global && a.ngroup == b.ngroup && !strcmp(b.files, "in-memory S2"),
        "MeshCreateFromMsh: %" PetscInt_FMT " cells, %" PetscInt_FMT " vertices, %" PetscInt_FMT " groups, as MeshCreate", b.ncell_global, b.nvert_global, b.ngroup);
  PetscCall(MeshDestroy(&b));
  if (rank == 0) msh.quad[4 * 3 + 2] = msh.nnode + 5;
  M2dClearError();
  PetscCall(M2dInstallErrorHandler());
  ierr = MeshCreateFromMsh(comm, &s, &msh, 1, "in-memory S2", &b);
  PetscCall(M2dRemoveErrorHandler());
  CHECK(ierr == PETSC_ERR_USER_INPUT && strstr(M2dFirstError(), "mesh 'in-memory S2': quadrilateral 4 uses node index"), "MeshCreateFromMsh: a node index out of range refused on every rank: %s", M2dFirstError());
  if (rank == 0) MshFree(&msh);
  PetscCall(MeshDestroy(&a));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  PetscMPIInt rank;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  if (!getenv("M2D_SOURCE") || !getenv("M2D_MESHES")) {
    printf("FAIL M2D_SOURCE and M2D_MESHES must be set\n");
    return 1;
  }
  PetscCall(CheckFromMsh());
  PetscCall(CheckModes("patch_uniform", "patch_uniform", 2));
  PetscCall(CheckModes("hertz", "hertz_0", 2));
  PetscCall(CheckModes("block", "block_8", 1));
  if (rank == 0) printf("%d failed\n", failures);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &failures, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD));
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
