/* tempfile.h - temporary files, interruption and stale temporaries.
 *
 * Every temporary the program creates is recorded (path and kind) before it
 * exists, in a fixed table that a signal handler can read: SIGINT, SIGTERM and
 * SIGHUP remove the recorded temporaries (unlink, rmdir), print one line
 * "mortar2d: error: interrupted by SIGINT; ..." on world rank 0 and _exit(1).
 * The same table is emptied at exit() (an error return from main), so an
 * error never leaves a temporary behind.  What a SIGKILL leaves is recognised
 * by the next run by its name, .m2d.<kind>.<host>.<pid>.*: <host> is a hash of
 * the host name, and an entry whose process is gone (kill(pid, 0) gives ESRCH,
 * or a zombie) on this host is removed (M2dTempRemoveStale); a live run's
 * entry is kept. */
#ifndef M2D_TEMPFILE_H
#define M2D_TEMPFILE_H
#include <petscsys.h>
#include <stdio.h>

#define M2D_TEMP_PREFIX ".m2d."
#define M2D_NAME_MAX    255 /* longest directory entry (Linux NAME_MAX) */

/* Install the SIGINT/SIGTERM/SIGHUP handlers, after PetscInitialize (whose
 * crash handler takes SIGHUP).  Not collective; once per rank. */
PetscErrorCode M2dInstallSignalHandlers(void);
/* The same handlers before PetscInitialize (MPI start-up takes ~0.3 s: a
 * SIGTERM then killed the run with status 143 and no line); the rank comes
 * from the launcher's environment. Plain C: returns 0 or the failing signal. */
int M2dInstallEarlySignalHandlers(void);
/* Call right before PetscFinalize: PETSc 3.18's PetscFinalize resets SIGTERM
 * and SIGHUP to the default action (PetscPopSignalHandler); this keeps ours. */
PetscErrorCode M2dSignalsBeforeFinalize(void);
/* METIS (GKlib) traps SIGTERM while it runs and returns METIS_ERROR (-4) for
 * it (and only for it: out of memory is -3): an interrupt then read "METIS_NodeND
 * failed (-4)". Call with METIS's return code: on METIS_ERROR the SIGTERM is
 * raised again, now to the program's handler (one line, exit 1); holding the
 * signal over the call instead delayed the line past mpiexec's teardown.
 * Not collective. */
void M2dMetisSignal(int rc, int metis_error);

/* Record a temporary (file, or directory when isdir) before creating it; *slot
 * identifies it for M2dTempForget.  Not collective; errors when the table is
 * full or the path does not fit. */
PetscErrorCode M2dTempRecord(const char *path, PetscBool isdir, int *slot);
/* The same without raising: the slot, or -1 (not recorded). */
int M2dTempTryRecord(const char *path, PetscBool isdir);
/* Stop tracking a temporary (renamed into place, or removed); slot < 0: no-op. */
void M2dTempForget(int *slot);
/* Remove every recorded temporary now (files, then directories) and forget them. */
void M2dTempRemoveAll(void);

/* Commit section: signals that arrive inside are acted on at M2dTempCommitEnd,
 * so a handler never sees a half-done switch.  `written` (at End) changes the
 * interruption message from "no output written" to "output already complete". */
void M2dTempCommitBegin(void);
void M2dTempCommitEnd(PetscBool written);

/* This process's tag "<host hash>.<pid>" (the part that names its temporaries). */
const char *M2dTempTag(void);
/* TRUE if `name` (a directory entry) is of the form PREFIX<tag>.rest with tag of
 * this host and a process that no longer exists; *rest points into name. */
PetscBool M2dTempIsStale(const char *name, const char *prefix, const char **rest);
/* Remove, in directory dir, the files .m2d.{tmp,tmp-probe,tmp-link}.<stale tag>* and
 * the temporaries of earlier versions, <base>.tmp<dead pid>, for each base of
 * `bases` (NULL-terminated or NULL).  Not collective; errors ignored. */
void M2dTempRemoveStale(const char *dir, const char *const *bases);

/* The name a user knows for path: DIR/f for a staged DIR/.m2d.gen.../f (for
 * messages); buf holds it when it differs.  Not collective. */
const char *M2dPublicName(const char *path, char *buf, size_t len);

/* Temporary name of path: DIR/.m2d.tmp.<tag>.BASE; errors when it does not fit. */
PetscErrorCode M2dTmpName(const char *path, char *tmp, size_t len);

/* One file written under its temporary name and renamed when complete (a
 * failed or interrupted run never leaves a half-written file under the final
 * name).  Not collective; the caller writes through fp. */
typedef struct {
  FILE *fp;
  int   slot;
  char  final[PETSC_MAX_PATH_LEN];
  char  tmp[PETSC_MAX_PATH_LEN];
} M2dFile;
/* Open path's temporary for writing (recorded, see above). */
PetscErrorCode M2dFileOpen(const char *path, M2dFile *f);
/* fclose + fsync + rename; on any write error the temporary is removed and an
 * error naming the final file is raised. */
PetscErrorCode M2dFileCommit(M2dFile *f);
/* fclose + remove the temporary; safe after a failed open or commit. */
void M2dFileAbort(M2dFile *f);
#endif
