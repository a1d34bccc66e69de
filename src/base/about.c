/* about.c - the program's version and where its files are (see about.h). */
#define _POSIX_C_SOURCE 200809L /* readlink */
#include "about.h"
#include "version_git.h" /* M2D_GIT_COMMIT, written by cmake/version.cmake at each build */
#include <petscsys.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef M2D_VERSION
  #define M2D_VERSION "unknown"
#endif

const char *M2dVersion(void)
{
  return M2D_VERSION;
}

const char *M2dGitCommit(void)
{
  return M2D_GIT_COMMIT;
}

void M2dPetscVersion(char *buf, size_t len)
{
  int major = 0, minor = 0, sub = 0, release = 0;
  (void)PetscGetVersionNumber(&major, &minor, &sub, &release);
  snprintf(buf, len, "%d.%d.%d%s", major, minor, sub, release ? "" : " (development)");
}

void M2dSummaryVersions(M2dSummary *sum)
{
  char petsc[64];
  M2dPetscVersion(petsc, sizeof(petsc));
  SummaryString(sum, "", "version", M2dVersion());
  if (M2dGitCommit()[0]) SummaryString(sum, "", "git_commit", M2dGitCommit());
  SummaryString(sum, "", "petsc_version", petsc);
}

int M2dVersionRequested(int argc, char **argv)
{
  char petsc[64];
  for (int i = 1; i < argc; i++)
    if (!strcmp(argv[i], "-version") || !strcmp(argv[i], "--version")) {
      M2dPetscVersion(petsc, sizeof(petsc));
      printf("mortar2d %s%s%s%s\nPETSc %s\n", M2dVersion(), M2dGitCommit()[0] ? " (git " : "", M2dGitCommit(), M2dGitCommit()[0] ? ")" : "", petsc);
      return 1;
    }
  return 0;
}

void M2dMeshDir(char *dir, size_t len)
{
  char        exe[4096];
  const char *under[] = {"meshes", "../share/mortar2d/meshes"};
  ssize_t     n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
  char       *slash;
  struct stat st;

  snprintf(dir, len, "meshes");
  if (n <= 0) return;
  exe[n] = 0;
  if (!(slash = strrchr(exe, '/'))) return;
  *slash = 0;
  for (int k = 0; k < 2; k++) {
    char path[4096 + 64];
    snprintf(path, sizeof(path), "%s/%s", exe, under[k]);
    if (!stat(path, &st) && S_ISDIR(st.st_mode)) {
      if (k == 1 && realpath(path, exe)) snprintf(dir, len, "%s", exe); /* without the .. */
      else snprintf(dir, len, "%s", path);
      return;
    }
  }
}
