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
#define _POSIX_C_SOURCE 200809L /* posix_memalign */
#include "about.h"
#include "logging.h"
#include "optcheck.h"
#include "optfiles.h"
#include "adapt.h"
#include "remesh.h"
#include "temprecord.h"
#include "helpprint.h"
#include "step.h"
#include "util.h"
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char help[] = "mortar2d: 2D contact of linear elastic bodies, frictionless or Coulomb (small strain, Q4, mortar or node-to-segment).\n"
                           "Usage: mortar2d -options_file SCENE.opts [options]; the scenes are in options/, README.md explains them.\n"
                           "-help: the program's options by job, each with its default; -help_petsc: PETSc's own after them; -version: the program's and PETSc's versions.\n"
                           "The materials -NAME_E, -NAME_nu are listed for the bodies of -bodies: mortar2d -help -bodies lower,upper\n\n";

/* -help: document the per-body and solver options too, print them by job
 * (helpprint.h), then stop */
static PetscErrorCode DocumentOptions(MPI_Comm comm, M2dScene *s)
{
  M2dSolverChoice     choice;
  M2dEstimatorOptions eo;
  M2dAdaptOptions     ao;

  PetscFunctionBeginUser;
  if (s->nbody == 0) {
    s->nbody = 1;
    PetscCall(PetscStrncpy(s->body[0].name, "BODY", sizeof(s->body[0].name)));
  }
  PetscCall(SceneReadMaterials(comm, s));
  PetscCall(M2dSolverChoosePath(comm, s, NULL, &choice));
  PetscCall(M2dSolverDocumentOptions(comm, s));
  PetscCall(ReportEstimatorOptions(comm, &eo));
  PetscCall(AdaptReadOptions(comm, s, &ao));
  PetscCall(M2dHelpPrint(comm, help));
  PetscFunctionReturn(0);
}

/* the output paths against each other and every file the run reads */
static PetscErrorCode CheckOutputPaths(MPI_Comm comm, M2dScene *s)
{
  M2dInputFile       in[M2D_MAX_MESH + 1 + 64];
  const char *const *optfiles;
  PetscInt           n = 0;
  int                nopt = M2dOptionsFilesRead(&optfiles);

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < s->nmesh; i++) in[n++] = (M2dInputFile){"-mesh", s->mesh[i]};
  if (s->geo[0]) in[n++] = (M2dInputFile){"-geo", s->geo};
  for (int i = 0; i < nopt && i < 64; i++) in[n++] = (M2dInputFile){"-options_file", optfiles[i]};
  PetscCall(OutputCheckPaths(comm, &s->out, s->mesh_save, n, in));
  PetscFunctionReturn(0);
}

static PetscErrorCode Run(MPI_Comm comm)
{
  M2dScene            s;
  M2dEstimatorOptions eo;
  M2dAdaptOptions     ao;
  M2dStep             st;
  PetscErrorCode      ierr;

  PetscFunctionBeginUser;
  PetscCall(M2dLogRegister());
  PetscCall(SceneReadOptions(comm, &s));
  if (s.help) PetscFunctionReturn(DocumentOptions(comm, &s));
  PetscCall(ReportEstimatorOptions(comm, &eo));
  PetscCall(AdaptReadOptions(comm, &s, &ao));
  if (ao.enabled && !eo.target_set) eo.size.target_rel = ao.target; /* the size field aims at the loop's target */
  if (ao.enabled) eo.goal_contact = (PetscBool)(ao.goal == 1);
  PetscCall(SceneCheckOptions(comm, &s)); /* typos of the program's options, before any work */
  PetscCall(CheckOutputPaths(comm, &s));
  /* a history's states (friction's slip, the stick and slip sets) would have to pass from one mesh to the next */
  PetscCheck(!ao.enabled || !SceneHasFriction(&s), comm, PETSC_ERR_USER_INPUT, "option -adapt: friction depends on the load path, whose state (the slip so far) a new mesh cannot inherit here; solve it on a fixed mesh graded to the contact (as options/cattaneo.opts)");
  PetscCheck(!ao.enabled || SceneLoadSteps(&s) == 1, comm, PETSC_ERR_USER_INPUT, "option -adapt: the adaptive loop solves one load step per mesh; drop -load_steps and -load_stages (without friction the last step's answer is the one-step answer)");
  if (ao.enabled) PetscFunctionReturn(AdaptRun(comm, &s, &ao, &eo)); /* model only what the scene needs */
  ierr = M2dStepSolve(comm, &s, NULL, NULL, &eo, &st);
  if (!ierr) ierr = M2dStepWrite(&st, NULL); /* -mesh_save was written with the mesh */
  PetscCall(M2dStepDestroy(&st)); /* also after an error: no leak on the error exits */
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

/* PETSc's arrays on 64-byte boundaries. OpenBLAS's AVX-512 kernels round
 * the last bits by an array's alignment, and PETSc's own 16 bytes leave that
 * to the heap's history, which Open MPI's threads interleave with ours at
 * moments of their own: the same command gave two answers (hertz_adapt.opts
 * -adapt_target 0.01: 5 runs in 12; hertz_3 once in 4). Not with PETSc's
 * -malloc_* debugging, which brings its own allocator. */
static PetscErrorCode AlignedMalloc(size_t n, PetscBool clear, int line, const char fn[], const char file[], void **r)
{
  (void)line, (void)fn, (void)file;
  *r = NULL;
  if (n && posix_memalign(r, 64, n)) return PETSC_ERR_MEM;
  if (n && clear) memset(*r, 0, n);
  return 0;
}

static PetscErrorCode AlignedFree(void *p, int line, const char fn[], const char file[])
{
  (void)line, (void)fn, (void)file;
  free(p);
  return 0;
}

/* realloc keeps the contents; a block it returns off the 64-byte boundary is
 * copied to one on it (no malloc_usable_size: not every C library has it) */
static PetscErrorCode AlignedRealloc(size_t n, int line, const char fn[], const char file[], void **r)
{
  void *q = NULL;
  (void)line, (void)fn, (void)file;
  if (!n) {
    free(*r);
    *r = NULL;
    return 0;
  }
  if (!(q = realloc(*r, n))) return PETSC_ERR_MEM;
  *r = q;
  if ((uintptr_t)q % 64 == 0) return 0;
  if (posix_memalign(r, 64, n)) {
    *r = q;
    return PETSC_ERR_MEM;
  }
  memcpy(*r, q, n);
  free(q);
  return 0;
}

static PetscBool MallocDebugRequested(void)
{
  for (int i = 0; i < M2dOptionsGivenCount(); i++)
    if (!strncasecmp(M2dOptionsGiven(i, NULL), "malloc", 6)) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* after MPI_Init: PetscInitialize to PetscFinalize; 0 or 1 */
static int Program(int argc, char **argv)
{
  PetscErrorCode ierr;
  PetscMPIInt    rank;

  if (M2dOptionsFilesCheck(argc, argv)) return 1; /* before PETSc follows a cycle of -options_file into a crash (signal 11) */
  if (!MallocDebugRequested() && PetscMallocSet(AlignedMalloc, AlignedFree, AlignedRealloc)) return 1;
  (void)M2dHelpArgs(&argc, &argv); /* -help_petsc: -help with PETSc's own options after the program's */
  (void)M2dHelpCapture(); /* -help: the program's options before PETSc's */
  ierr = PetscInitialize(&argc, &argv, NULL, help);
  if (ierr) return 1;
  {
    PetscBool has_help = PETSC_FALSE;
    ierr = PetscOptionsHasHelp(NULL, &has_help);
    if (!ierr && !has_help) ierr = M2dHelpRelease();
    if (ierr) return 1;
  }
  ierr = M2dInstallErrorHandler();
  if (!ierr) ierr = M2dInstallSignalHandlers();
  if (!ierr) ierr = Run(PETSC_COMM_WORLD);
  if (ierr) {
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    if (rank == 0) fprintf(stderr, "mortar2d: error: %s\n", M2dFirstError());
    fflush(stderr);
    OutputWriteFailure(M2dFirstError()); /* the summary says so (once the output paths were checked) */
    M2dHelpDiscard();
    /* objects of the failed run are not freed; skip PETSc's leak report */
    PetscOptionsClearValue(NULL, "-malloc_dump");
    M2dSignalsBeforeFinalize();
    PetscFinalize();
    return 1;
  }
  ierr = M2dRemoveErrorHandler();
  ierr = M2dSignalsBeforeFinalize() || ierr;
  ierr = PetscFinalize() || ierr;
  return ierr ? 1 : 0;
}

int main(int argc, char **argv)
{
  int rc, provided;

  if (M2dVersionRequested(argc, argv)) return 0; /* the program's and PETSc's versions, before MPI starts */
  if (M2dInstallEarlySignalHandlers()) return 1; /* a Ctrl-C during MPI's start-up: one line too */
  if (M2dTempDirCheck(M2D_REMESH_DIR_PREFIX)) return 1; /* before MPI_Init uses it */
  if (MPI_Init_thread(&argc, &argv, PETSC_MPI_THREAD_REQUIRED, &provided)) return 1; /* as PetscInitialize would */
  rc = Program(argc, argv);
  return MPI_Finalize() || rc;
}
