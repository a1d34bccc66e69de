/* optfiles.h - check the options files a run names, before PETSc reads them.
 *
 * PETSc 3.18 follows `-options_file F` (on the command line, in PETSC_OPTIONS,
 * in ~/.petscrc, ./.petscrc, ./petscrc and inside options files) recursively:
 * a file that includes itself, directly or through others, recurses until the
 * stack overflows (signal 11), and a missing file stops PetscInitialize with a
 * multi-line traceback. This pre-scan follows the same files with the same
 * syntax (comments from '#', one option and its value per line, "quoted"
 * values, `alias` lines, names case-insensitive) and reports either in one line. */
#ifndef M2D_OPTFILES_H
#define M2D_OPTFILES_H

/* Follow every options file argv (argv[0] is the program), PETSC_OPTIONS and
 * the petscrc files name, the way PetscInitialize will. Returns 0 when every
 * required file can be read and no file includes itself; otherwise prints one
 * line "mortar2d: error: ..." on stderr (on world rank 0: call it after
 * MPI_Init) and returns 1. Not collective: every rank runs it on the same
 * files and gets the same answer. */
int M2dOptionsFilesCheck(int argc, char **argv);
/* After M2dOptionsFilesCheck: the option names it met (without the '-', each
 * once, case-insensitively; YAML files are not read), M2dOptionsGiven(i, &file)
 * for i < M2dOptionsGivenCount(), *file the options file that set it or NULL
 * when it was typed (command line, PETSC_OPTIONS). More than 500 names is an
 * error of M2dOptionsFilesCheck (PETSc 3.18 holds 512). A line with a NUL byte
 * is one too (PETSc would read it only up to that byte). Not collective. */
int         M2dOptionsGivenCount(void);
const char *M2dOptionsGiven(int i, const char **file);
/* The options files the check above found (at most 64, as given), for the
 * outputs to be checked against (outputpaths.h). Not collective. */
int M2dOptionsFilesRead(const char *const **names);
#endif
