/* logging.c - the one table of -log_view stages and events (see logging.h). */
#include "logging.h"

PetscLogStage M2dStage[M2D_STAGE_COUNT];
PetscLogEvent M2dEvent[M2D_EV_COUNT];
const char   *M2dStageName[M2D_STAGE_COUNT] = {"mesh", "contact", "assembly", "solve", "output"};

static const char *stage_label[M2D_STAGE_COUNT] = {"Mesh", "Contact", "Assembly", "Solve", "Output"};
static const char *event_name[M2D_EV_COUNT]     = {"M2dMeshCreate", "M2dMeshRead", "M2dMeshEdges", "M2dMeshPartition", "M2dMeshPlex", "M2dPrealloc", "M2dElements", "M2dDirichlet", "M2dKKT", "M2dCondOrder", "M2dMumpsAnalysis", "M2dMumpsFactor", "M2dInterface", "M2dMumpsSolve", "M2dVerify", "M2dMetisOrder", "M2dIterSetUp", "M2dIterSolve", "M2dEstimate"};

PetscErrorCode M2dLogRegister(void)
{
  static PetscBool done = PETSC_FALSE;
  PetscClassId     cls;

  PetscFunctionBeginUser;
  if (done) PetscFunctionReturn(0);
  PetscCall(PetscClassIdRegister("mortar2d", &cls));
  for (int k = 0; k < M2D_STAGE_COUNT; k++) PetscCall(PetscLogStageRegister(stage_label[k], &M2dStage[k]));
  for (int k = 0; k < M2D_EV_COUNT; k++) PetscCall(PetscLogEventRegister(event_name[k], cls, &M2dEvent[k]));
  done = PETSC_TRUE;
  PetscFunctionReturn(0);
}
