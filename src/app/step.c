/* step.c - one pass of the data path on one mesh (see step.h). */
#include "step.h"
#include "logging.h"
#include "util.h"

PetscErrorCode M2dStepSolve(MPI_Comm comm, M2dScene *s, const M2dMeshSource *src, const M2dContactState *warm, const M2dEstimatorOptions *eo, M2dStep *st)
{
  M2dSolverChoice choice;
  double          t0 = M2dWallTime(), *t = st->t;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(st, sizeof(*st)));
  PetscCall(PetscLogStagePush(M2dStage[M2D_STAGE_MESH]));
  t[M2D_STAGE_MESH] = M2dWallTime();
  PetscCall(ProblemCreate(comm, s, src ? src->msh : NULL, src ? src->what : NULL, &st->pb));
  t[M2D_STAGE_MESH] = M2dWallTime() - t[M2D_STAGE_MESH];
  PetscCall(PetscLogStagePop());

  PetscCall(M2dSolverChoosePath(comm, &st->pb.s, &st->pb.mesh, &choice));
  PetscCall(ProblemSetUp(&st->pb, &choice, M2dStage[M2D_STAGE_CONTACT], M2dStage[M2D_STAGE_ASSEMBLY], &t[M2D_STAGE_CONTACT], &t[M2D_STAGE_ASSEMBLY]));
  if (warm && st->pb.has_contact) {
    PetscCall(PetscMalloc1(st->pb.contact.R.n + 1, &st->pb.warm));
    PetscCall(ContactStateMask(warm, &st->pb.contact, &st->pb.units, st->pb.s.contact_c_set ? st->pb.s.contact_c : ActiveSetDefaultC(&st->pb.s, &st->pb.contact), st->pb.warm));
  }

  st->pb.keep_factor = (PetscBool)(eo && eo->enabled && eo->goal_contact); /* the dual problem reuses it (dual.h) */
  PetscCall(PetscLogStagePush(M2dStage[M2D_STAGE_SOLVE]));
  t[M2D_STAGE_SOLVE] = M2dWallTime();
  PetscCall(M2dSolverSolve(&st->pb, &choice, &st->sol));
  PetscCall(M2dVerifyTestPerturb(st->sol.u));
  PetscCall(M2dVerifyAnswer(&st->pb, &st->sol, &st->v));
  if (st->pb.has_contact) PetscCall(ContactResults(&st->pb.contact, st->pb.kkt.C, st->pb.kkt.r, st->sol.u, st->sol.lam, st->sol.active, st->sol.slip));
  PetscCall(M2dFramesRotateGlobal(&st->pb.frames, &st->pb.mesh, st->sol.u, PETSC_TRUE)); /* u = T u~ from here on */
  /* a node beyond the automatic reach (a tenth of the mortar surface) that
   * ends inside the other body moved that far: the strain says why (a soft
   * punch was told to raise -contact_reach); a reach the user set is the
   * likelier cause when it is short */
  if (st->pb.s.reach_set) PetscCall(M2dVerifyReach(&st->pb, st->sol.u));
  PetscCall(M2dVerifyStrain(&st->pb, st->sol.u, &st->v));
  if (!st->pb.s.reach_set) PetscCall(M2dVerifyReach(&st->pb, st->sol.u));
  t[M2D_STAGE_SOLVE] = M2dWallTime() - t[M2D_STAGE_SOLVE];
  PetscCall(PetscLogStagePop());

  PetscCall(PetscLogStagePush(M2dStage[M2D_STAGE_OUTPUT]));
  t[M2D_STAGE_OUTPUT] = M2dWallTime();
  PetscCall(PetscCalloc1(1, &st->sum));
  PetscCall(ReportCompute(&st->pb, &st->sol, &st->v, eo, &st->fig, st->sum));
  t[M2D_STAGE_OUTPUT]  = M2dWallTime() - t[M2D_STAGE_OUTPUT];
  t[M2D_STAGE_COUNT] = M2dWallTime() - t0;
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

/* the run's files, the final mesh of -adapt (-mesh_save: MeshSave puts it in
 * place at once), the summary last; then the files in place, in that order */
static PetscErrorCode WriteAll(M2dStep *st, const char *mesh_save, M2dOutput *o, char *list, size_t len)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)st->pb.mesh.dm);
  double   t0   = M2dWallTime();

  PetscFunctionBeginUser;
  PetscCall(ReportWriteFields(&st->pb, &st->sol, o));
  if (mesh_save && mesh_save[0]) PetscCall(MeshSave(&st->pb.mesh, st->pb.user, st->pb.units.L, mesh_save));
  st->t[M2D_STAGE_OUTPUT] += M2dWallTime() - t0;
  st->t[M2D_STAGE_COUNT] += M2dWallTime() - t0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, st->t, M2D_STAGE_COUNT + 1, MPI_DOUBLE, MPI_MAX, comm));
  PetscCall(ReportWriteSummary(&st->pb, st->sum, st->t, o));
  for (PetscInt k = 0; k < o->n; k++) {
    PetscCall(PetscStrlcat(list, k ? ", " : "", len));
    PetscCall(PetscStrlcat(list, o->file[k].final, len));
  }
  PetscCall(OutputCommit(o));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dStepWrite(M2dStep *st, const char *mesh_save)
{
  MPI_Comm       comm = PetscObjectComm((PetscObject)st->pb.mesh.dm);
  M2dOutput      o;
  char           list[4 * PETSC_MAX_PATH_LEN] = "";
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(M2dStage[M2D_STAGE_OUTPUT]));
  PetscCall(OutputBegin(comm, &st->pb.user->out, &o));
  ierr = WriteAll(st, mesh_save, &o, list, sizeof(list));
  if (ierr) OutputAbort(&o); /* the temporaries not yet in place */
  PetscCall(ierr);
  if (list[0]) PetscCall(PetscPrintf(comm, "output written: %s\n", list)); /* rank 0's list */
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode M2dStepDestroy(M2dStep *st)
{
  PetscFunctionBeginUser;
  if (st->sum) PetscCall(M2dSummaryDestroy(st->sum));
  PetscCall(PetscFree(st->sum));
  PetscCall(M2dSolutionDestroy(&st->sol));
  PetscCall(ProblemDestroy(&st->pb));
  PetscFunctionReturn(0);
}
