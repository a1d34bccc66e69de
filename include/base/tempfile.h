/* tempfile.h - files written under a temporary name and renamed into place,
 * and interruption.
 *
 * Every temporary the program creates is recorded (path) before it exists, in
 * a fixed table that a signal handler can read: SIGINT, SIGTERM and SIGHUP
 * remove the recorded temporaries, print one line "mortar2d: error:
 * interrupted by SIGINT; ..." on world rank 0 and _exit(1). The same table is
 * emptied at exit() (an error return from main), so an error never leaves a
 * temporary behind. A temporary is named DIR/.m2d.tmp.<host>.<pid>.BASE beside
 * its final name DIR/BASE; what a SIGKILL leaves is recognised by the next run
 * by that name (<host> a hash of the host name, a process that is gone) and
 * removed (M2dTempRemoveStale).
 *
 * A launcher that ends a job (Open MPI's mpiexec after a Ctrl-C or SIGTERM)
 * first sends SIGCONT to every rank and SIGTERM only about a second later
 * (odls_base_sigkill_timeout): a short run would finish and replace its
 * results in between. M2dSignalsAwaitLauncher waits, before results are put
 * in place, until that SIGTERM would have come. */
#ifndef M2D_TEMPFILE_H
#define M2D_TEMPFILE_H
#include <petscsys.h>
#include <stdio.h>

#define M2D_TEMP_PREFIX ".m2d."
#define M2D_NAME_MAX    255 /* longest directory entry (Linux NAME_MAX) */

/* Install the SIGINT/SIGTERM/SIGHUP (and SIGCONT, SIGPIPE) handlers, after
 * PetscInitialize (whose crash handler takes SIGTERM and SIGHUP), and let the
 * held signals through. Not collective; once per rank. */
PetscErrorCode M2dInstallSignalHandlers(void);
/* The same handlers before MPI_Init, and SIGINT, SIGTERM, SIGHUP held until
 * M2dInstallSignalHandlers: MPI's start-up (a singleton of Open MPI forks its
 * orted, which printed "ORTE_ERROR_LOG: Broken pipe" when the run ended under
 * it; threads started there inherit the mask) and PETSc's own handler
 * (PetscInitialize) never see them, and the one line comes once the rank is
 * known. Plain C: returns 0 or a failing signal. */
int M2dInstallEarlySignalHandlers(void);
/* Call right before PetscFinalize: PETSc 3.18's PetscFinalize resets SIGTERM
 * and SIGHUP to the default action (PetscPopSignalHandler); this keeps ours. */
PetscErrorCode M2dSignalsBeforeFinalize(void);
/* On more than one rank (a launcher started them), wait until 1.3 s (Open
 * MPI's odls_base_sigkill_timeout + 0.3 s) after the last SIGCONT and after
 * the early handlers were installed: a Ctrl-C to mpiexec at any moment before
 * (even before this process could catch the SIGCONT) has by then ended the
 * run. A run of that length, or a singleton, does not wait. Not collective. */
void M2dSignalsAwaitLauncher(void);
/* METIS (GKlib) traps SIGTERM while it runs and returns METIS_ERROR (-4) for
 * it (and only for it: out of memory is -3): an interrupt then read "METIS_NodeND
 * failed (-4)". Call with METIS's return code: on METIS_ERROR the SIGTERM is
 * raised again, now to the program's handler (one line, exit 1). Not collective. */
void M2dMetisSignal(int rc, int metis_error);

/* This process's tag "<host hash>.<pid>" (the part that names its temporaries). */
const char *M2dTempTag(void);
/* Remove, in directory dir, the temporaries .m2d.tmp.<tag>.* whose process is
 * gone (same host). Not collective; errors ignored. */
void M2dTempRemoveStale(const char *dir);
/* Temporary name of path: DIR/.m2d.tmp.<tag>.BASE; errors when it does not fit. */
PetscErrorCode M2dTmpName(const char *path, char *tmp, size_t len);

/* One file written under its temporary name (recorded, see above) and renamed
 * into place when complete: a failed or interrupted run never leaves a
 * half-written file under the final name. Not collective. */
typedef struct {
  FILE *fp;   /* open for writing (M2dFileOpen with stdio), else NULL */
  int   slot; /* in the table of temporaries, -1: none */
  char  final[PETSC_MAX_PATH_LEN];
  char  tmp[PETSC_MAX_PATH_LEN];
} M2dFile;
/* Record path's temporary and, with stdio, open it for writing through f->fp
 * (without: the caller creates f->tmp itself, e.g. with HDF5). */
PetscErrorCode M2dFileOpen(const char *path, PetscBool stdio, M2dFile *f);
/* Complete on disk under the temporary name: fflush + fsync + fclose (or fsync
 * of f->tmp); on any write error the temporary is removed and an error naming
 * the final file is raised. */
PetscErrorCode M2dFileClose(M2dFile *f);
/* Rename closed files into place, in the order given (so the last one, the
 * summary, is the sign that the others are there), with signals held off
 * between the first and the last rename: an interruption ends the run either
 * before any of them ("no output written, previous results kept") or after all
 * ("the output was already complete"). On failure the remaining temporaries
 * are removed and an error names the file. */
PetscErrorCode M2dFilePublish(PetscInt n, M2dFile f[]);
/* Close and publish one file. */
PetscErrorCode M2dFileCommit(M2dFile *f);
/* Remove the temporary (closing it first); safe after a failed open or commit. */
void M2dFileAbort(M2dFile *f);
#endif
