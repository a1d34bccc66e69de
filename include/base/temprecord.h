/* temprecord.h - the temporary-file table of tempfile.h for the plain-C
 * modules (no PETSc types), and the temporary directory: remesh.c records the
 * directory its files go in before it writes them, so that SIGINT, SIGTERM,
 * SIGHUP and every exit() remove them (tempfile.h). Not collective. */
#ifndef M2D_TEMPRECORD_H
#define M2D_TEMPRECORD_H
#include <stddef.h>
/* $TMPDIR, or /tmp when it is unset or empty. */
const char *M2dTempDir(void);
/* Before MPI_Init (Open MPI creates a missing TMPDIR and fails in an unusable
 * one with some 40 lines): M2dTempDir() must be an existing, writable
 * directory, else one line "mortar2d: error: TMPDIR ..." on stderr and 1 (on
 * every process: the rank is not known yet). Then the directories
 * <TMPDIR>/<sweep>* of runs that are gone are removed (M2dTempSweepDirs). */
int  M2dTempDirCheck(const char *sweep);
/* Remove, with everything in them, the directories parent/<prefix>* of this
 * user that no live process holds (M2dTempMakeDir's lock). */
void M2dTempSweepDirs(const char *parent, const char *prefix);
/* Make parent/<prefix>XXXXXX (mkdtemp), lock it for this process's life
 * (flock on *lockfd, kept open: a child process that must not hold the lock
 * closes its copy) and record it (removed with everything in it at exit or
 * interruption). 0, or -1 with errno (nothing made). */
int  M2dTempMakeDir(const char *parent, const char *prefix, char *path, size_t len, int *lockfd);
#endif
