/* helpprint.h - -help prints the program's options first, grouped by job.
 *
 * PETSc prints its help through the function pointer PetscHelpPrintf: the
 * general options inside PetscInitialize, then one section per
 * PetscOptionsBegin group as objects read their options. M2dHelpCapture()
 * (before PetscInitialize) points it at a buffer that keeps each section
 * apart; M2dHelpPrint() then prints the program's sections in the order of
 * the README (scene and mesh, materials, loads and supports, contact, solver
 * paths, checks, error estimate and adaptive meshes, output) and, only with
 * -help_petsc, PETSc's own sections after them (PETSc 3.18 takes no value
 * after -help but intro). */
#ifndef M2D_HELPPRINT_H
#define M2D_HELPPRINT_H
#include <petscsys.h>

/* Before PetscInitialize: collect what PETSc's help printer prints (rank 0)
 * and what PETSc prints to stdout (PetscVFPrintf: the type lists).
 * What is never printed by M2dHelpPrint is printed as it came at exit (so
 * -version and -help intro print as before).  Returns 0. */
int M2dHelpCapture(void);
/* Before PetscInitialize: -help_petsc without -help adds -help to argv (a
 * static copy).  Returns 0. */
int M2dHelpArgs(int *argc, char ***argv);
/* After PetscInitialize without -help: print what was collected as it came,
 * and give PetscHelpPrintf and PetscVFPrintf back.  Not collective. */
PetscErrorCode M2dHelpRelease(void);
/* An error ended the run: its one line is the output, not the help collected
 * so far (-help -hertz without a pair). Not collective; idempotent. */
void           M2dHelpDiscard(void);
/* With -help: intro (the program's help text), the program's sections by job, then with -help_petsc PETSc's
 * banner and sections as PETSc printed them, else one line naming
 * -help_petsc; gives PetscHelpPrintf back to PETSc.  Collective on comm. */
PetscErrorCode M2dHelpPrint(MPI_Comm comm, const char *intro);
#endif
