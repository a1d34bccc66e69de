/* about.h - what the program knows about itself: its version (CMakeLists.txt's
 * project version, and the git commit it was built from when built from a git
 * checkout), PETSc's, and where its shipped scenes' meshes are. */
#ifndef M2D_ABOUT_H
#define M2D_ABOUT_H
#include "summary.h"
#include <stddef.h>

/* The program's version ("1.0.0"), and its git commit ("3f2a9c1b0d4e",
 * "-dirty" appended when the checkout had changes) or "" when not built from
 * git. Static strings. Not collective. */
const char *M2dVersion(void);
const char *M2dGitCommit(void);
/* PETSc's version as the linked library gives it ("3.18.5"). Not collective. */
void M2dPetscVersion(char *buf, size_t len);
/* The summary's "version", "git_commit" (only when built from git) and
 * "petsc_version". Not collective. */
void M2dSummaryVersions(M2dSummary *sum);
/* -version on the command line: print the program's and PETSc's versions to
 * stdout and return 1 (main exits 0 before MPI starts); 0 otherwise. */
int M2dVersionRequested(int argc, char **argv);

/* The directory of the shipped meshes (.geo and the generated .msh), found
 * from the executable (/proc/self/exe): DIR/meshes beside it (a build tree),
 * else DIR/../share/mortar2d/meshes (an install, cmake --install), else
 * "meshes" (the current directory's). The defaults of -mesh_dir and -geo_dir.
 * Not collective. */
void M2dMeshDir(char *dir, size_t len);
#endif
