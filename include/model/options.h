/* options.h - the program's own options, read inside PetscOptionsBegin/End.
 *
 * Each reader shows the option in -help (help string, default), records its
 * name as one of the program's (optcheck.h) and checks the value's form: a
 * value that is not a finite number, an integer, a boolean or one of a list,
 * or too long for the program (never cut), is
 * not raised at once (an error inside PetscOptionsBegin/End leaks the block's
 * strings) but kept, the default used, and raised by M2dOptionsRaise after
 * PetscOptionsEnd as one line naming the option. Only the first one is kept.
 * Names are given with the '-' and without the block's prefix (PETSc's style);
 * messages name the option with its prefix. Not collective: every rank reads
 * the same database and keeps the same error. */
#ifndef M2D_OPTIONS_H
#define M2D_OPTIONS_H
#include <petscsys.h>

/* real option: a finite number; *set (may be NULL) says whether it was given */
PetscErrorCode M2dOptionsReal(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscReal def, PetscReal *value, PetscBool *set);
/* real option whose default is "auto" (-help shows it): *set is PETSC_FALSE
 * (and *value untouched) when it is absent or "auto", else *value is the number */
PetscErrorCode M2dOptionsRealAuto(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscReal *value, PetscBool *set);
/* integer option (base 10, nothing else in the value) */
/* text itself when at most 80 characters, else its start, its end and its
 * length in buf: a value quoted in a message never pushes the reason out of
 * the line. Not collective. */
const char    *M2dShown(const char *text, char *buf, size_t len);
/* text is a nonzero number that strtod reads as 0. Not collective. */
PetscBool      M2dUnderflows(const char *text);
/* text is an integer, in digits or in e-notation of an exact integer (1e6):
 * TRUE with *value (saturated at LLONG_MIN/MAX). Not collective. */
PetscBool      M2dOptionsParseInteger(const char *text, long long *value);
PetscErrorCode M2dOptionsInt(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscInt def, PetscInt *value, PetscBool *set);
/* boolean option: true/false, yes/no, on/off, 1/0, or no value (true) */
PetscErrorCode M2dOptionsBool(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscBool def, PetscBool *value);
/* one of list[0..n-1] (case-insensitive, as PETSc): *index is the default on
 * entry, the choice on return; -help lists the choices */
PetscErrorCode M2dOptionsEList(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, const char *const list[], PetscInt n, PetscInt *index);
/* The same for an enum variable (PETSc's cast: (PetscEnum *)&s->field), list in
 * the enum's order. */
PetscErrorCode M2dOptionsEnum(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, const char *const list[], PetscInt n, PetscEnum *value);
/* string option: value holds the default on entry (len bytes; a longer value is an error) */
PetscErrorCode M2dOptionsString(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, char *value, size_t len, PetscBool *set);
/* comma-separated strings, at most max (more is an error), each shorter than
 * len bytes (longer is an error; 0: no limit): values[0..*n-1] are allocated
 * with PetscMalloc, the caller frees them with PetscFree */
PetscErrorCode M2dOptionsStringArray(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscInt max, size_t len, char *values[], PetscInt *n);

/* keep the first problem found while reading (printf-style, one line) */
PetscErrorCode M2dOptionsDefer(const char *fmt, ...) PETSC_ATTRIBUTE_FORMAT(1, 2);
/* raise the kept problem, if any (and forget it), on comm; call after PetscOptionsEnd */
PetscErrorCode M2dOptionsRaise(MPI_Comm comm);
#endif
