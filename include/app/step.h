/* step.h - one pass of the data path on one mesh: mesh, contact, assembly,
 * solve and checks, report (each a -log_view stage, logging.h). main runs one
 * step; the adaptive loop (adapt.h) runs one per mesh. */
#ifndef M2D_STEP_H
#define M2D_STEP_H
#include "logging.h"
#include "msh.h"
#include "report.h"

typedef struct {
  M2dProblem      pb;
  M2dSolution     sol;
  M2dVerification v;
  M2dFigures      fig;
  M2dSummary     *sum;
  double          t[M2D_STAGE_COUNT + 1]; /* seconds per stage (logging.h order) and in all, max over ranks */
} M2dStep;

/* Where a step's mesh comes from: the -mesh files (msh NULL), or an MshMesh
 * on rank 0 (remesh.h; ignored on the other ranks) named `what` in messages. */
typedef struct {
  MshMesh    *msh;
  const char *what;
} M2dMeshSource;

/* Solve scene s on the mesh of src, starting the active set from warm (may be
 * NULL), check the answer and compute the report (not yet written). Collective. */
PetscErrorCode M2dStepSolve(MPI_Comm comm, M2dScene *s, const M2dMeshSource *src, const M2dContactState *warm, const M2dEstimatorOptions *eo, M2dStep *st);
/* Write the step's files (fields, CSV, summary: output.h) and, when
 * mesh_save is not NULL or "", its mesh there (MeshSave: the adaptive loop's
 * final mesh). Output stage. Collective. */
PetscErrorCode M2dStepWrite(M2dStep *st, const char *mesh_save);
/* Free the step. Collective. */
PetscErrorCode M2dStepDestroy(M2dStep *st);
#endif
