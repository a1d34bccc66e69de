/* util.c - see util.h. */
#include "util.h"
#include <errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <limits.h>
#include <linux/magic.h>
#include <sys/stat.h>
#include <sys/statfs.h>
#include <unistd.h>

static char first_error[4096];
static volatile sig_atomic_t have_error; /* read by the signal handler */

static PetscErrorCode M2dErrorHandler(MPI_Comm comm, int line, const char *func, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  (void)comm;
  (void)line;
  (void)func;
  (void)file;
  (void)ctx;
  if (p == PETSC_ERROR_INITIAL && !have_error) {
    const char *text = NULL;
    if (mess && mess[0]) text = mess;
    else PetscErrorMessage(n, &text, NULL);
    snprintf(first_error, sizeof(first_error), "%s", text ? text : "unknown error");
    /* keep it to one printable line: a corrupted file's bytes may be quoted in it */
    for (char *c = first_error; *c; c++)
      if ((unsigned char)*c < 32 || (unsigned char)*c > 126) *c = '?';
    have_error = 1;
  }
  return n;
}

PetscErrorCode M2dInstallErrorHandler(void)
{
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(M2dErrorHandler, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dRemoveErrorHandler(void)
{
  PetscFunctionBeginUser;
  PetscCall(PetscPopErrorHandler());
  PetscFunctionReturn(0);
}

PetscBool M2dHaveError(void)
{
  return have_error ? PETSC_TRUE : PETSC_FALSE;
}

const char *M2dFirstError(void)
{
  return have_error ? first_error : "unknown error";
}

void M2dClearError(void)
{
  have_error     = 0;
  first_error[0] = 0;
}

PetscErrorCode M2dCheckCollective(MPI_Comm comm, PetscBool bad, const char *msg)
{
  PetscMPIInt rank, size, mine, first;
  char        buf[2048];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  mine = bad ? rank : size;
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first == size) PetscFunctionReturn(0);
  buf[0] = 0;
  if (rank == first) snprintf(buf, sizeof(buf), "%s", msg ? msg : "error");
  PetscCallMPI(MPI_Bcast(buf, (int)sizeof(buf), MPI_CHAR, first, comm));
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "%s", buf);
}

int M2dMakeDirs(const char *path, char *msg, size_t len)
{
  char        tmp[PETSC_MAX_PATH_LEN];
  struct stat st;
  size_t      n = strlen(path);

  if (n == 0 || n >= sizeof(tmp)) {
    snprintf(msg, len, "invalid directory name '%s'", path);
    return 1;
  }
  memcpy(tmp, path, n + 1);
  for (char *p = tmp + 1; *p; p++) {
    if (*p != '/') continue;
    *p = 0;
    if (mkdir(tmp, 0777) && errno != EEXIST) {
      snprintf(msg, len, "cannot create directory '%s': %s", tmp, strerror(errno));
      return 1;
    }
    *p = '/';
  }
  if (mkdir(tmp, 0777) && errno != EEXIST) {
    snprintf(msg, len, "cannot create directory '%s': %s", tmp, strerror(errno));
    return 1;
  }
  if (stat(tmp, &st) || !S_ISDIR(st.st_mode)) {
    snprintf(msg, len, "'%s' is not a directory", tmp);
    return 1;
  }
  if (access(tmp, W_OK)) {
    snprintf(msg, len, "directory '%s' is not writable: %s", tmp, strerror(errno));
    return 1;
  }
  return 0;
}

static const char *NodeKind(mode_t m)
{
  return S_ISDIR(m) ? "a directory" : S_ISCHR(m) ? "a character device" : S_ISBLK(m) ? "a block device" : S_ISFIFO(m) ? "a FIFO" : S_ISSOCK(m) ? "a socket" : "not a regular file";
}

/* is path's directory on procfs (/proc/self/fd/1: a process's file descriptor)? */
static int OnProc(const char *path)
{
  char          dir[PATH_MAX];
  const char   *slash = strrchr(path, '/');
  struct statfs fs;

  snprintf(dir, sizeof(dir), "%.*s", slash ? (slash == path ? 1 : (int)(slash - path)) : 1, slash ? path : ".");
  return !statfs(dir, &fs) && fs.f_type == PROC_SUPER_MAGIC;
}

int M2dOutputTarget(const char *path, char *target, size_t tlen, char *msg, size_t len)
{
  char        cur[PATH_MAX], link[PATH_MAX];
  struct stat st;

  if (snprintf(cur, sizeof(cur), "%s", path) >= (int)sizeof(cur)) {
    snprintf(msg, len, "'%.60s...' is too long a path", path);
    return 1;
  }
  for (int hop = 0;; hop++) {
    ssize_t     n;
    const char *slash;
    if (lstat(cur, &st) || S_ISREG(st.st_mode)) break; /* absent (or unreachable: the write says why), or a file */
    if (!S_ISLNK(st.st_mode)) {
      if (hop) snprintf(msg, len, "'%s' is a symbolic link to '%s', %s, not to a regular file (name a file)", path, cur, NodeKind(st.st_mode));
      else snprintf(msg, len, "'%s' is %s, not a regular file (the output is written beside it and renamed onto it: name a file)", path, NodeKind(st.st_mode));
      return 1;
    }
    if (OnProc(cur)) {
      if (hop) snprintf(msg, len, "'%s' leads to '%s', a process's file descriptor, not a file (name a file)", path, cur);
      else snprintf(msg, len, "'%s' is a process's file descriptor (a link in /proc), not a file (name a file)", path);
      return 1;
    }
    if (hop == 40 || (n = readlink(cur, link, sizeof(link) - 1)) < 0) {
      snprintf(msg, len, "'%s': %s", path, hop == 40 ? "too many levels of symbolic links" : strerror(errno));
      return 1;
    }
    link[n] = 0;
    if (!hop && !strncmp(link, ".m2d.", 5)) break; /* earlier versions' links into their own hidden entries: replaced */
    slash = strrchr(cur, '/');
    if (link[0] == '/' || !slash) snprintf(cur, sizeof(cur), "%s", link);
    else if (snprintf(cur + (slash + 1 - cur), sizeof(cur) - (size_t)(slash + 1 - cur), "%s", link) >= (int)(sizeof(cur) - (size_t)(slash + 1 - cur))) {
      snprintf(msg, len, "'%s': its link leads to too long a path", path);
      return 1;
    }
  }
  if (snprintf(target, tlen, "%s", cur) >= (int)tlen) {
    snprintf(msg, len, "'%s' leads to too long a path", path);
    return 1;
  }
  return 0;
}

PetscErrorCode M2dPathPrintf(char *buf, size_t len, const char *opt, const char *fmt, ...)
{
  va_list ap;
  int     n;

  PetscFunctionBeginUser;
  va_start(ap, fmt);
  n = vsnprintf(buf, len, fmt, ap);
  va_end(ap);
  PetscCheck(n >= 0 && (size_t)n < len, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "option %s: the path '%.60s...' is longer than %d characters", opt, buf, (int)len - 1);
  PetscFunctionReturn(0);
}

void M2dTestDelay(void)
{
#if defined(M2D_TEST_HOOKS)
  const char *s = getenv("M2D_TEST_OUTPUT_DELAY");
  double      t = s ? atof(s) : 0;
  if (t > 0) usleep((useconds_t)(t * 1e6));
#endif
}

double M2dWallTime(void)
{
  return MPI_Wtime();
}
