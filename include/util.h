/* util.h - error reporting, collective checks and safe file output.
 *
 * mortar2d reports bad input as ONE line on stderr and a nonzero exit. PETSc's
 * default handler prints a traceback per frame; M2dInstallErrorHandler() replaces
 * it with one that remembers only the first (innermost) message, which main()
 * prints once.  Checks that depend on data only some ranks hold go through
 * M2dCheckCollective() so that every rank raises the same error (no hang). */
#ifndef M2D_UTIL_H
#define M2D_UTIL_H
#include <petscsys.h>

PetscErrorCode M2dInstallErrorHandler(void);
PetscErrorCode M2dRemoveErrorHandler(void);
const char    *M2dFirstError(void);
void           M2dClearError(void);

/* Raise the same error on every rank of comm if `bad` is true on any rank; the
 * message of the lowest such rank is used. */
PetscErrorCode M2dCheckCollective(MPI_Comm comm, PetscBool bad, const char *msg);

/* mkdir -p; returns nonzero errno-like code, fills msg */
int M2dMakeDirs(const char *path, char *msg, size_t len);

/* Files are written under a temporary name and renamed when complete, so a
 * failed or interrupted run never leaves a half-written file under the final
 * name (and never destroys a previous result). */
typedef struct {
  FILE *fp;
  char  final[PETSC_MAX_PATH_LEN];
  char  tmp[PETSC_MAX_PATH_LEN + 32];
} M2dFile;
PetscErrorCode M2dFileOpen(const char *path, M2dFile *f);
PetscErrorCode M2dFileCommit(M2dFile *f); /* fclose + rename, errors if any write failed */
void           M2dFileAbort(M2dFile *f);  /* fclose + unlink temporary */
void           M2dTmpName(const char *path, char *tmp, size_t len);

double M2dWallTime(void);
#endif
