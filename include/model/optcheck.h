/* optcheck.h - options that do nothing: typos stop the run with the closest
 * name, options with no effect in the run's set-up are named.
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
 *     is an error unless it is read later (PetscFinalize's few, viewers,
 *     factorization packages' options, M2dOptionsReadLater's prefixes); a known
 *     name (the program's, PETSc's common ones) nobody read has no effect on
 *     this path: see M2dOptionsNoEffect.
 * An option given with no effect in the set-up (M2dOptionsNoEffect, and the
 * known names above) is an error "option -X has no effect WHY" when typed
 * (command line, PETSC_OPTIONS), a note on stdout when an options file set it
 * (the command line may have changed what the file's scene needs).
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
 * exceptions (read later); a known name unread has no effect `why` ("on the
 * condensed path (...)"); collective on comm */
PetscErrorCode M2dOptionsCheckUnused(MPI_Comm comm, const char *why);
/* names (space separated, with or without '-') the user gave have no effect
 * why (printf-style, e.g. "without -hertz"); a name ending in '*' is a family
 * of PETSc's options (the program's own, viewers and monitors left out);
 * collective on comm */
PetscErrorCode M2dOptionsNoEffect(MPI_Comm comm, const char *names, const char *why, ...) PETSC_ATTRIBUTE_FORMAT(3, 4);
/* options under prefix (with or without '-') are read after the solvers are
 * configured in this run (e.g. the dual problem's -dual_); not collective */
PetscErrorCode M2dOptionsReadLater(const char *prefix);
#endif
