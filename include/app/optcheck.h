/* optcheck.h - options nobody reads: typos stop the run with the closest name.
 *
 * PETSc keeps, per option, whether anything has read it. The program's own
 * options are read (options.h) before the check and so are "used"; what is
 * left is a typo, an option of another program, or a PETSc option that only a
 * solver configured later will read. Two checks:
 *   M2dOptionsCheckUnknown - right after the program's options are read: an
 *     unread option that is neither the program's nor under a prefix PETSc's
 *     objects read (ksp_, pc_, snes_, mat_, fieldsplit_, dm_, log_, ...) is an
 *     error "option -X is unknown (did you mean -Y?)";
 *   M2dOptionsCheckUnused - once the solvers are configured: an unread option
 *     is an error unless it is a known name that is read later or only on some
 *     paths (the list in optcheck.c: viewers, -log_*, -malloc*, -options_*,
 *     MUMPS and other factorization packages' options, PETSc options the
 *     program's solvers take on another path, ...).
 * Names are compared without the '-' and case-insensitively, as PETSc does. */
#ifndef M2D_OPTCHECK_H
#define M2D_OPTCHECK_H
#include <petscsys.h>

/* record name ("-name", with any prefix) as one of the program's options; not collective */
PetscErrorCode M2dOptionsKnow(const char *name);
/* closest known name to name (no '-'), the program's or PETSc's common ones,
 * as "-Y" in best (len bytes), or "" when nothing is close; not collective */
PetscErrorCode M2dOptionsSuggest(const char *name, char *best, size_t len);
/* error for the first unread option that is not the program's, not under a
 * PETSc prefix and for which skip (may be NULL) says no; collective on comm */
PetscErrorCode M2dOptionsCheckUnknown(MPI_Comm comm, PetscBool (*skip)(const char *name, void *ctx), void *ctx);
/* error for the first option no rank has read, except the documented
 * exceptions (read later or only on some paths); collective on comm */
PetscErrorCode M2dOptionsCheckUnused(MPI_Comm comm);
#endif
