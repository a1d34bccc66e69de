/* m2d_plextime - PETSc's DMPlexCreateFromCellListParallelPetsc against the
 * program's own per-rank plex build (mesh_distribute.c), on the same cells:
 *
 *   mpiexec -n P m2d_plextime -options_file options/hertz.opts -mesh hertz_5.msh [-repeat N]
 *
 * MeshCreate builds the mesh as mortar2d does (rank 0 reads and partitions
 * with METIS, every rank builds its own interpolated plex: the M2dMeshPlex
 * event, max over ranks); then, from the same per-rank cells (global vertex
 * numbers) and owned vertex coordinates, DMPlexCreateFromCellListParallelPetsc
 * with interpolate = TRUE builds the same plex again, timed (max over ranks,
 * min of N repeats). Prints one line: ranks, cells, both seconds, their ratio.
 * (Labels of the physical groups are not part of either timing.) */
#include "logging.h"
#include "mesh.h"
#include <petscsf.h>

static PetscErrorCode PetscBuild(const M2dMesh *m, double *sec)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)m->dm);
  IS                 vnum;
  const PetscInt    *vn;
  Vec                cl;
  const PetscScalar *ca;
  PetscSection       cs;
  PetscInt           nc = m->cEnd - m->cStart, nvo = 0, NV, *cells;
  PetscReal         *xy;
  PetscSF            sf;
  DM                 dm;
  double             t;

  PetscFunctionBeginUser;
  PetscCall(DMPlexGetVertexNumbering(m->dm, &vnum)); /* global vertex numbers, -(n+1) for ghosts */
  PetscCall(ISGetIndices(vnum, &vn));
  for (PetscInt v = 0; v < m->vEnd - m->vStart; v++) nvo += vn[v] >= 0;
  PetscCall(PetscMalloc2(4 * nc + 1, &cells, 2 * nvo + 2, &xy));
  for (PetscInt c = 0; c < nc; c++)
    for (int k = 0; k < 4; k++) {
      PetscInt g = vn[m->cellverts[4 * c + k] - m->vStart];
      cells[4 * c + k] = g >= 0 ? g : -(g + 1);
    }
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(VecGetArrayRead(cl, &ca));
  {
    /* owned vertices in the order of their global numbers (a contiguous range per rank) */
    PetscInt lo = PETSC_MAX_INT;
    for (PetscInt v = 0; v < m->vEnd - m->vStart; v++)
      if (vn[v] >= 0) lo = PetscMin(lo, vn[v]);
    for (PetscInt v = 0; v < m->vEnd - m->vStart; v++) {
      PetscInt off;
      if (vn[v] < 0) continue;
      PetscCall(PetscSectionGetOffset(cs, v + m->vStart, &off));
      xy[2 * (vn[v] - lo)]     = PetscRealPart(ca[off]);
      xy[2 * (vn[v] - lo) + 1] = PetscRealPart(ca[off + 1]);
    }
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCall(ISRestoreIndices(vnum, &vn));
  NV = m->nvert_global;
  PetscCallMPI(MPI_Barrier(comm));
  t = MPI_Wtime();
  PetscCall(DMPlexCreateFromCellListParallelPetsc(comm, 2, nc, nvo, NV, 4, PETSC_TRUE, cells, 2, xy, &sf, NULL, &dm));
  t = MPI_Wtime() - t;
  PetscCallMPI(MPI_Allreduce(&t, sec, 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscCall(PetscSFDestroy(&sf));
  PetscCall(DMDestroy(&dm));
  PetscCall(PetscFree2(cells, xy));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  M2dScene          s;
  M2dMesh           m;
  PetscInt          repeat = 3;
  double            own = 1e300, petsc = 1e300, t;
  PetscMPIInt       size;
  PetscEventPerfInfo info;

  PetscCall(PetscInitialize(&argc, &argv, NULL, "m2d_plextime: DMPlexCreateFromCellListParallelPetsc against the program's own plex build\n"));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-repeat", &repeat, NULL));
  PetscCall(PetscLogDefaultBegin());
  PetscCall(M2dLogRegister());
  PetscCall(SceneReadOptions(PETSC_COMM_WORLD, &s));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  for (PetscInt r = 0; r < repeat; r++) {
    PetscCall(PetscLogEventGetPerfInfo(PETSC_DETERMINE, M2dEvent[M2D_EV_MESH_PLEX], &info));
    t = info.time;
    PetscCall(MeshCreate(PETSC_COMM_WORLD, &s, &m));
    PetscCall(PetscLogEventGetPerfInfo(PETSC_DETERMINE, M2dEvent[M2D_EV_MESH_PLEX], &info));
    t = info.time - t;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD));
    own = PetscMin(own, t);
    PetscCall(PetscBuild(&m, &t));
    petsc = PetscMin(petsc, t);
    PetscCall(MeshDestroy(&m));
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "ranks %d, cells %" PetscInt_FMT ": own plex build %.3f s, DMPlexCreateFromCellListParallelPetsc (interpolated) %.3f s, ratio %.2f (min of %" PetscInt_FMT ")\n", size, m.ncell_global, own, petsc, petsc / own, repeat));
  PetscCall(PetscFinalize());
  return 0;
}
