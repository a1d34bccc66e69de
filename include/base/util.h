/* util.h - error reporting, collective checks, paths and timing.
 *
 * mortar2d reports bad input as ONE line on stderr and a nonzero exit. PETSc's
 * default handler prints a traceback per frame; M2dInstallErrorHandler() replaces
 * it with one that remembers only the first (innermost) message, which main()
 * prints once.  Checks that depend on data only some ranks hold go through
 * M2dCheckCollective() so that every rank raises the same error (no hang).
 * Temporary files and M2dFile (write, then rename) live in tempfile.h. */
#ifndef M2D_UTIL_H
#define M2D_UTIL_H
#include <petscsys.h>
#include "tempfile.h"

/* Push (pop) the one-line error handler.  Not collective. */
PetscErrorCode M2dInstallErrorHandler(void);
PetscErrorCode M2dRemoveErrorHandler(void);
/* The first error message raised since the last M2dClearError (static storage,
 * one printable line), or "unknown error". */
const char *M2dFirstError(void);
/* TRUE once an error was raised (main reports it; async-signal-safe). */
PetscBool M2dHaveError(void);
void        M2dClearError(void);

/* Raise the same error on every rank of comm if `bad` is true on any rank; the
 * message of the lowest such rank is used.  Collective on comm. */
PetscErrorCode M2dCheckCollective(MPI_Comm comm, PetscBool bad, const char *msg);

/* mkdir -p path.  Not collective.  Returns 0, or nonzero with the reason in msg. */
int M2dMakeDirs(const char *path, char *msg, size_t len);

/* Where an output named path really goes (tempfile.h writes it beside its
 * target and renames it onto the target): path when absent or a regular file;
 * through symbolic links, the file they lead to when that is absent or
 * regular (written through: no link is ever replaced). Anything else is
 * refused: a directory, a device, a FIFO or a socket (renaming over it would
 * replace that node, and as root even a device of /dev), a process's file
 * descriptor (/dev/stdout leads into /proc), a loop of links. Links of earlier
 * versions into mortar2d's own hidden entries (".m2d.*") are replaced by the
 * file. Returns 0 with the target, or nonzero with the reason in msg. Not
 * collective. */
int M2dOutputTarget(const char *path, char *target, size_t tlen, char *msg, size_t len);

/* snprintf into buf that fails, naming option `opt`, when the result does not
 * fit (a path is never silently cut).  Not collective. */
PetscErrorCode M2dPathPrintf(char *buf, size_t len, const char *opt, const char *fmt, ...) PETSC_ATTRIBUTE_FORMAT(4, 5);

/* Test hook (built only with -DM2D_TEST_HOOKS=ON, tools/test.sh): sleeps
 * M2D_TEST_OUTPUT_DELAY seconds (environment) when that is set, nothing
 * otherwise; called between the steps of writing the output so
 * that tests can interrupt a run at a chosen step.  Not collective. */
void M2dTestDelay(void);

/* Wall-clock seconds (MPI_Wtime).  Not collective. */
double M2dWallTime(void);
#endif
