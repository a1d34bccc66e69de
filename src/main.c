/* main.c - mortar2d: read a scene from the options database, solve it, check
 * the answer, write the results.
 *
 *   mortar2d -options_file options/seed_patch.opts [-output_dir out] [-summary out/summary.json]
 *
 * The data path, one -log_view stage each (logging.h): Mesh (read and check
 * the mesh, materials, reference units: problem.h), Contact (surfaces,
 * mortar segments or node-to-segment rows) and Assembly (Q4 stiffness, loads,
 * supports, KKT blocks), Solve (the path chosen in solver.h; the answer's own
 * checks in verify.h), Output (report.h: interface results, comparisons with
 * exact answers, HDF5/XDMF, VTU, CSV, JSON summary). */
#include "logging.h"
#include "report.h"
#include "optfiles.h"
#include "util.h"

static const char help[] = "mortar2d: 2D frictionless contact of elastic bodies with Q4 elements and the mortar method.\n"
                           "Scenes are options files in options/; see README.md for every option.\n\n";

/* -help: document the per-body and solver options too, then stop */
static PetscErrorCode DocumentOptions(MPI_Comm comm, M2dScene *s)
{
  M2dSolverPath       path;
  M2dEstimatorOptions eo;

  PetscFunctionBeginUser;
  if (s->nbody == 0) {
    s->nbody = 1;
    PetscCall(PetscStrncpy(s->body[0].name, "BODY", sizeof(s->body[0].name)));
  }
  PetscCall(SceneReadMaterials(comm, s));
  PetscCall(M2dSolverChoosePath(comm, s, &path));
  PetscCall(M2dSolverDocumentOptions(comm, s));
  PetscCall(ReportEstimatorOptions(comm, &eo));
  PetscFunctionReturn(0);
}

static PetscErrorCode Run(MPI_Comm comm)
{
  M2dScene        s;
  M2dProblem      pb;
  M2dSolution     sol;
  M2dVerification v;
  M2dEstimatorOptions eo;
  M2dErrorEstimate    est;
  M2dSolverPath   path;
  M2dSummary     *sum;
  double          t[M2D_STAGE_COUNT + 1], t0 = M2dWallTime();

  PetscFunctionBeginUser;
  PetscCall(M2dLogRegister());
  PetscCall(SceneReadOptions(comm, &s));
  if (s.help) PetscFunctionReturn(DocumentOptions(comm, &s));
  PetscCall(ReportCheckPaths(comm, &s));
  PetscCall(ReportEstimatorOptions(comm, &eo));

  PetscCall(PetscLogStagePush(M2dStage[M2D_STAGE_MESH]));
  t[M2D_STAGE_MESH] = M2dWallTime();
  PetscCall(ProblemCreate(comm, &s, &pb));
  t[M2D_STAGE_MESH] = M2dWallTime() - t[M2D_STAGE_MESH];
  PetscCall(PetscLogStagePop());

  PetscCall(M2dSolverChoosePath(comm, &pb.s, &path));
  PetscCall(ProblemSetUp(&pb, path, M2dStage[M2D_STAGE_CONTACT], M2dStage[M2D_STAGE_ASSEMBLY], &t[M2D_STAGE_CONTACT], &t[M2D_STAGE_ASSEMBLY]));

  PetscCall(PetscLogStagePush(M2dStage[M2D_STAGE_SOLVE]));
  t[M2D_STAGE_SOLVE] = M2dWallTime();
  PetscCall(M2dSolverSolve(&pb, path, &sol));
  PetscCall(M2dVerifyAnswer(&pb, &sol, &v));
  t[M2D_STAGE_SOLVE] = M2dWallTime() - t[M2D_STAGE_SOLVE];
  PetscCall(PetscLogStagePop());

  PetscCall(PetscLogStagePush(M2dStage[M2D_STAGE_OUTPUT]));
  t[M2D_STAGE_OUTPUT] = M2dWallTime();
  PetscCall(PetscCalloc1(1, &sum));
  PetscCall(ReportCompute(&pb, &sol, &v, &eo, &est, sum));
  PetscCall(ReportWriteFields(&pb, &sol));
  t[M2D_STAGE_OUTPUT]  = M2dWallTime() - t[M2D_STAGE_OUTPUT];
  t[M2D_STAGE_COUNT] = M2dWallTime() - t0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, t, M2D_STAGE_COUNT + 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscCall(ReportWriteSummary(&pb, sum, t));
  PetscCall(PetscLogStagePop());

  PetscCall(PetscFree(sum));
  PetscCall(M2dSolutionDestroy(&sol));
  PetscCall(ProblemDestroy(&pb));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;
  PetscMPIInt    rank;

  if (M2dOptionsFilesCheck(argc, argv)) return 1; /* before PETSc follows a cycle of -options_file into a crash */
  ierr = PetscInitialize(&argc, &argv, NULL, help);
  if (ierr) return 1;
  ierr = M2dInstallErrorHandler();
  if (!ierr) ierr = Run(PETSC_COMM_WORLD);
  if (ierr) {
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    if (rank == 0) fprintf(stderr, "mortar2d: error: %s\n", M2dFirstError());
    fflush(stderr);
    /* objects of the failed run are not freed; skip PETSc's leak report */
    PetscOptionsClearValue(NULL, "-malloc_dump");
    PetscFinalize();
    return 1;
  }
  ierr = M2dRemoveErrorHandler();
  ierr = PetscFinalize() || ierr;
  return ierr ? 1 : 0;
}
