/* tempfile.c - see tempfile.h. The signal handler only reads the table below
 * (paths written before their `used` flag is raised), calls unlink, write,
 * nanosleep, clock_gettime and _exit: all async-signal-safe. The publish
 * section is a three-state atomic (idle, publish, dying) so that a signal
 * taken on any thread either finds no rename in progress or is deferred until
 * the renames are done. */
#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE /* syscall */
#include "tempfile.h"
#include "temprecord.h"
#include "util.h"
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#define M2D_TEMP_MAX 64

typedef struct {
  volatile sig_atomic_t used;
  volatile sig_atomic_t dir; /* a directory: removed with everything in it */
  char                  path[PETSC_MAX_PATH_LEN];
} TempEntry;

enum { ST_IDLE, ST_PUBLISH, ST_DYING };

static TempEntry temps[M2D_TEMP_MAX];
static int       state          = ST_IDLE; /* atomics: handler and main thread */
static int       pending_signal = 0;       /* a signal deferred by the publish section */
static int       output_written = 0;       /* set at the end of a publish */
static long long cont_ns        = 0;       /* CLOCK_MONOTONIC of the last SIGCONT, 0 none */
static long long launched_ns    = 0;       /* CLOCK_MONOTONIC of the early handlers under a launcher, 0 none */
static int       world_rank     = -1;      /* only world rank 0 prints */
static int       world_size     = 1;
static pid_t     owner          = 0; /* the process that recorded the table */
static char      tag[64];
static int       atexit_done = 0;

/* Everything in the open directory dfd, removed with system calls only
 * (getdents64, unlinkat, openat: async-signal-safe, no opendir's malloc); a
 * pass that removed something is followed by another from the start, as the
 * listing of a directory being emptied may skip entries. Depth at most 16. */
static void EmptyDir(int dfd, int depth)
{
  struct Dirent64 {
    uint64_t       ino;
    int64_t        off;
    unsigned short reclen;
    unsigned char  type;
    char           name[];
  };
  char buf[2048] __attribute__((aligned(8)));
  for (int pass = 0, removed = 1; removed && pass < 64; pass++) {
    long n;
    removed = 0;
    if (lseek(dfd, 0, SEEK_SET) < 0) return;
    while ((n = syscall(SYS_getdents64, dfd, buf, sizeof(buf))) > 0)
      for (long off = 0; off < n;) {
        const struct Dirent64 *e = (const struct Dirent64 *)(buf + off);
        off += e->reclen;
        if (e->name[0] == '.' && (!e->name[1] || (e->name[1] == '.' && !e->name[2]))) continue;
        if (!unlinkat(dfd, e->name, 0)) removed = 1;
        else if (errno == EISDIR && depth < 16) {
          int sub = openat(dfd, e->name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
          if (sub >= 0) EmptyDir(sub, depth + 1), close(sub);
          if (!unlinkat(dfd, e->name, AT_REMOVEDIR)) removed = 1;
        }
      }
  }
}

static void RemoveRecorded(void)
{
  if (getpid() != owner) return; /* a forked child owns nothing */
  for (int i = M2D_TEMP_MAX - 1; i >= 0; i--) {
    if (!temps[i].used) continue;
    if (temps[i].dir) {
      int dfd = open(temps[i].path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
      if (dfd >= 0) EmptyDir(dfd, 0), close(dfd);
      rmdir(temps[i].path);
    } else unlink(temps[i].path);
    temps[i].used = 0;
  }
}

static void Die(int sig)
{
  char        line[160];
  const char *name = sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "a signal";
  const char *what = __atomic_load_n(&output_written, __ATOMIC_SEQ_CST) ? "; the output was already complete" : "; no output written, previous results kept";
  size_t      n    = 0;

  RemoveRecorded();
  /* no snprintf in a handler: concatenate by hand */
  for (const char *p = "mortar2d: error: interrupted by "; *p; p++) line[n++] = *p;
  for (const char *p = name; *p; p++) line[n++] = *p;
  for (const char *p = what; *p && n < sizeof(line) - 1; p++) line[n++] = *p;
  line[n++] = '\n';
  /* under mpiexec the job ends as soon as one rank exits (the others are
   * killed, later output is lost): rank 0, which owns the files, must be the
   * first to exit, after its line has been read; the other ranks wait for
   * mpiexec to end them. After an error main prints that error: mpiexec's
   * SIGTERM to the ranks still finishing must not add a second line */
  if (world_rank == 0 && !M2dHaveError()) {
    ssize_t w = write(STDERR_FILENO, line, n);
    (void)w;
  }
  if (world_size > 1) {
    struct timespec ts = {world_rank == 0 ? 0 : 5, world_rank == 0 ? 100000000 : 0};
    nanosleep(&ts, NULL);
  }
  _exit(1);
}

static long long MonotonicNs(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void Handler(int sig)
{
  int idle = ST_IDLE;
  if (sig == SIGCONT) { /* perhaps a launcher ending the job: see M2dFilePublish */
    __atomic_store_n(&cont_ns, MonotonicNs(), __ATOMIC_SEQ_CST);
    return;
  }
  if (__atomic_compare_exchange_n(&state, &idle, ST_DYING, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST)) Die(sig);
  if (idle == ST_PUBLISH) __atomic_store_n(&pending_signal, sig, __ATOMIC_SEQ_CST); /* acted on after the renames */
  /* ST_DYING: another thread is already removing the temporaries and exiting */
}

static void AtExit(void)
{
  RemoveRecorded();
}

const char *M2dTempTag(void)
{
  if (!tag[0]) {
    char     host[256] = "";
    uint32_t h         = 2166136261u; /* FNV-1a */
    if (gethostname(host, sizeof(host) - 1)) host[0] = 0;
    for (const char *c = host; *c; c++) h = (h ^ (unsigned char)*c) * 16777619u;
    snprintf(tag, sizeof(tag), "%08x.%ld", (unsigned)h, (long)getpid());
  }
  return tag;
}

/* SIGINT, SIGTERM, SIGHUP held (pending) or let through */
static int Hold(int how)
{
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return sigprocmask(how, &set, NULL);
}

static int SetHandlers(void)
{
  struct sigaction sa;
  int              sigs[4] = {SIGINT, SIGTERM, SIGHUP, SIGCONT};

  memset(&sa, 0, sizeof(sa));
  sa.sa_handler = Handler;
  sigemptyset(&sa.sa_mask);
  for (int k = 0; k < 3; k++) sigaddset(&sa.sa_mask, sigs[k]);
  for (int k = 0; k < 4; k++)
    if (sigaction(sigs[k], &sa, NULL)) return sigs[k];
  /* stdout only reports progress: a reader that goes away (`mortar2d ... |
   * head -1`) must not kill the run (PETSc's handler made that a 6-line
   * "Caught signal 13 Broken Pipe" and exit 59); the writes fail quietly */
  sa.sa_handler = SIG_IGN;
  if (sigaction(SIGPIPE, &sa, NULL)) return SIGPIPE;
  return 0;
}

int M2dInstallEarlySignalHandlers(void)
{
  owner       = getpid();
  launched_ns = MonotonicNs(); /* kept under a launcher only (M2dInstallSignalHandlers) */
  return SetHandlers() || Hold(SIG_BLOCK) ? SIGINT : 0;
}

PetscErrorCode M2dInstallSignalHandlers(void)
{
  PetscMPIInt rank, size;
  int         bad;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  world_rank = rank;
  world_size = size;
  owner      = getpid();
  if (size == 1) launched_ns = 0; /* see M2dSignalsAwaitLauncher */
  (void)M2dTempTag();
  bad = SetHandlers();
  PetscCheck(!bad, PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot install the handler of signal %d: %s", bad, strerror(errno));
  PetscCheck(!Hold(SIG_UNBLOCK), PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot unblock SIGINT, SIGTERM and SIGHUP: %s", strerror(errno)); /* one that came meanwhile ends the run here */
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSignalsBeforeFinalize(void)
{
  int bad;

  PetscFunctionBeginUser;
  if (world_rank < 0) PetscFunctionReturn(0); /* handlers never installed */
  /* PetscFinalize pops PETSc's crash handler, and when its stack is then empty
   * it resets SIGTERM and SIGHUP to the default action: pop it now, and put
   * ours back, so that PetscFinalize finds an empty stack and resets nothing */
  PetscCall(PetscPopSignalHandler());
  bad = SetHandlers();
  PetscCheck(!bad, PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot install the handler of signal %d: %s", bad, strerror(errno));
  PetscFunctionReturn(0);
}

void M2dMetisSignal(int rc, int metis_error)
{
  if (rc == metis_error) raise(SIGTERM); /* GKlib restored our handler on return */
}

static int Record(const char *path, int dir)
{
  size_t n = strlen(path);

  if (n >= PETSC_MAX_PATH_LEN) return -1;
  if (!owner) owner = getpid();
  if (!atexit_done) {
    atexit(AtExit);
    atexit_done = 1;
  }
  for (int i = 0; i < M2D_TEMP_MAX; i++) {
    if (temps[i].used) continue;
    memcpy(temps[i].path, path, n + 1);
    temps[i].dir = dir;
    __atomic_thread_fence(__ATOMIC_SEQ_CST); /* the path is complete before the handler may read it */
    temps[i].used = 1;
    return i;
  }
  return -1;
}

static void Forget(int *slot)
{
  if (*slot >= 0 && *slot < M2D_TEMP_MAX) temps[*slot].used = 0;
  *slot = -1;
}

/* a process that exited but was not reaped yet (a zombie, e.g. a rank whose
 * mpiexec is gone) still answers kill(pid, 0): look at its state too */
static PetscBool Gone(long pid)
{
  char  path[64], buf[256], *p;
  FILE *fp;
  int   zombie = 0;

  if (kill((pid_t)pid, 0)) return errno == ESRCH ? PETSC_TRUE : PETSC_FALSE;
  snprintf(path, sizeof(path), "/proc/%ld/stat", pid);
  if (!(fp = fopen(path, "r"))) return PETSC_FALSE;
  if (fgets(buf, sizeof(buf), fp) && (p = strrchr(buf, ')')) && p[1] == ' ') zombie = p[2] == 'Z' || p[2] == 'X';
  fclose(fp);
  return zombie ? PETSC_TRUE : PETSC_FALSE;
}

/* "<prefix><8 hex>.<pid>.<anything>" of this host and a process that is gone */
static PetscBool Stale(const char *name, const char *prefix)
{
  const char *t = M2dTempTag(), *p;
  size_t      lp = strlen(prefix);
  char       *end;
  long        pid;

  if (strncmp(name, prefix, lp) || strncmp(name + lp, t, 9)) return PETSC_FALSE; /* not ours, or another host */
  p   = name + lp + 9;
  pid = strtol(p, &end, 10);
  if (end == p || *end != '.' || pid <= 0 || pid == (long)getpid()) return PETSC_FALSE;
  return Gone(pid);
}

void M2dTempRemoveStale(const char *dir)
{
  DIR           *d = opendir(dir);
  struct dirent *e;
  char           path[PETSC_MAX_PATH_LEN];

  if (!d) return;
  while ((e = readdir(d)))
    if (Stale(e->d_name, M2D_TEMP_PREFIX "tmp.") && (size_t)snprintf(path, sizeof(path), "%s/%s", dir, e->d_name) < sizeof(path)) unlink(path);
  closedir(d);
}

const char *M2dTempDir(void)
{
  const char *t = getenv("TMPDIR");
  return t && *t ? t : "/tmp";
}

int M2dTempDirCheck(const char *sweep)
{
  const char    *dir = M2dTempDir(), *why = NULL;
  struct stat    st;
  struct statvfs fs;
  if (stat(dir, &st)) why = strerror(errno);
  else if (!S_ISDIR(st.st_mode)) why = "not a directory";
  else if (access(dir, W_OK | X_OK)) why = strerror(errno);
  else if (!statvfs(dir, &fs) && ((fs.f_blocks && !(geteuid() ? fs.f_bavail : fs.f_bfree)) || (fs.f_files && !(geteuid() ? fs.f_favail : fs.f_ffree)))) why = strerror(ENOSPC); /* full (nearly full: Open MPI fails in MPI_Init, in its own words) */
  if (why) {
    fprintf(stderr, "mortar2d: error: %s '%s': %s (MPI and the remeshing write their temporary files there)\n", getenv("TMPDIR") && *getenv("TMPDIR") ? "TMPDIR" : "the temporary directory (TMPDIR unset)", dir, why);
    return 1;
  }
  M2dTempSweepDirs(dir, sweep);
  return 0;
}

/* A directory is in use while its owner holds flock() on it (the kernel drops
 * the lock when the process ends, however it ends, in any PID namespace): the
 * unlocked ones are a dead run's. One of another user is left alone. */
void M2dTempSweepDirs(const char *parent, const char *prefix)
{
  DIR           *d = opendir(parent);
  struct dirent *e;
  struct stat    st;

  if (!d) return;
  while ((e = readdir(d))) {
    int dfd;
    if (strncmp(e->d_name, prefix, strlen(prefix)) || (dfd = openat(dirfd(d), e->d_name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)) < 0) continue;
    if (!fstat(dfd, &st) && st.st_uid == geteuid() && !flock(dfd, LOCK_EX | LOCK_NB)) {
      EmptyDir(dfd, 0);
      (void)unlinkat(dirfd(d), e->d_name, AT_REMOVEDIR);
    }
    close(dfd); /* the lock with it */
  }
  closedir(d);
}

int M2dTempMakeDir(const char *parent, const char *prefix, char *path, size_t len, int *lockfd)
{
  for (int attempt = 0; attempt < 16; attempt++) {
    struct stat a, b;
    int         dfd, n = snprintf(path, len, "%s/%sXXXXXX", parent, prefix);
    if (n < 0 || (size_t)n >= len) return errno = ENAMETOOLONG, -1;
    if (!mkdtemp(path)) return -1;
    /* a sweep may take the new directory before it is locked: it removes it, and this tries another */
    if ((dfd = open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)) < 0) continue;
    if ((flock(dfd, LOCK_EX | LOCK_NB) && errno == EWOULDBLOCK) || fstat(dfd, &a) || stat(path, &b) || a.st_ino != b.st_ino || a.st_dev != b.st_dev) {
      close(dfd);
      continue;
    } /* (a file system without flock: the directory is used unlocked, and only its own run removes it) */
    if (Record(path, 1) < 0) {
      close(dfd);
      rmdir(path);
      return errno = ENAMETOOLONG, -1;
    }
    *lockfd = dfd;
    return 0;
  }
  return errno = EBUSY, -1;
}

PetscErrorCode M2dTmpName(const char *path, char *tmp, size_t len)
{
  const char *slash = strrchr(path, '/');
  int         n;

  PetscFunctionBeginUser;
  if (slash) n = snprintf(tmp, len, "%.*s/" M2D_TEMP_PREFIX "tmp.%s.%s", (int)(slash - path), path, M2dTempTag(), slash + 1);
  else n = snprintf(tmp, len, M2D_TEMP_PREFIX "tmp.%s.%s", M2dTempTag(), path);
  PetscCheck(n >= 0 && (size_t)n < len, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "output path '%s' is too long", path);
  PetscCheck(strlen(strrchr(tmp, '/') ? strrchr(tmp, '/') + 1 : tmp) <= M2D_NAME_MAX, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "output file name '%s' is too long", slash ? slash + 1 : path);
  PetscFunctionReturn(0);
}

PetscErrorCode M2dFileOpen(const char *path, PetscBool stdio, M2dFile *f)
{
  char why[2 * PETSC_MAX_PATH_LEN + 200];

  PetscFunctionBeginUser;
  f->fp     = NULL;
  f->slot   = -1;
  f->tmp[0] = 0;
  PetscCheck(!M2dOutputTarget(path, f->final, sizeof(f->final), why, sizeof(why)), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write output file: %s", why); /* through a link: onto its target */
  PetscCall(M2dTmpName(f->final, f->tmp, sizeof(f->tmp)));
  f->slot = Record(f->tmp, 0);
  PetscCheck(f->slot >= 0, PETSC_COMM_SELF, PETSC_ERR_MEM, "cannot record the temporary '%.200s': more than %d temporaries", f->tmp, M2D_TEMP_MAX);
  if (!stdio) PetscFunctionReturn(0);
  f->fp = fopen(f->tmp, "wb");
  if (!f->fp) {
    int e = errno;
    Forget(&f->slot);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write output file '%s': %s", f->final, strerror(e));
  }
  PetscFunctionReturn(0);
}

static int FsyncPath(const char *path, int flags)
{
  int fd = open(path, O_RDONLY | flags), r;
  if (fd < 0) return -1;
  r = fsync(fd);
  if (r && (errno == EINVAL || errno == EROFS)) r = 0; /* file systems without fsync */
  close(fd);
  return r;
}

PetscErrorCode M2dFileClose(M2dFile *f)
{
  int bad = 0, e = 0;

  PetscFunctionBeginUser;
  if (f->fp) {
    bad = ferror(f->fp) || fflush(f->fp) || fsync(fileno(f->fp));
    if (bad) e = errno;
    if (fclose(f->fp) && !bad) {
      bad = 1;
      e   = errno;
    }
    f->fp = NULL;
  } else if (FsyncPath(f->tmp, 0)) {
    bad = 1;
    e   = errno;
  }
  if (bad) {
    M2dFileAbort(f);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "writing output file '%s' failed: %s", f->final, e ? strerror(e) : "write error");
  }
  PetscFunctionReturn(0);
}

/* tempfile.h; measured: the SIGTERM 1.0007 s after the SIGCONT, so 0.3 s of margin */
void M2dSignalsAwaitLauncher(void)
{
  const long long wait = 1300000000LL; /* a launcher's SIGTERM comes 1 s after its SIGCONT (mpiexec's default), plus a margin */

  for (;;) { /* again after each wake-up: a SIGCONT may come while waiting */
    long long t[2] = {__atomic_load_n(&cont_ns, __ATOMIC_SEQ_CST), launched_ns}, until = 0, now = MonotonicNs();
    for (int k = 0; k < 2; k++)
      if (t[k] && t[k] + wait > until) until = t[k] + wait;
    if (now >= until) return;
    struct timespec ts = {(time_t)((until - now) / 1000000000LL), (long)((until - now) % 1000000000LL)};
    nanosleep(&ts, NULL);
  }
}

/* fsync the directory of path, unless it is prev (the last one synced) */
static void SyncDirOf(const char *path, char prev[], size_t len)
{
  const char *s = strrchr(path, '/');
  char        dir[PETSC_MAX_PATH_LEN];

  if (!s) snprintf(dir, sizeof(dir), ".");
  else snprintf(dir, sizeof(dir), "%.*s", s == path ? 1 : (int)(s - path), path);
  if (!strcmp(dir, prev)) return;
  (void)FsyncPath(dir, O_DIRECTORY);
  snprintf(prev, len, "%s", dir);
}

PetscErrorCode M2dFilePublish(PetscInt n, M2dFile f[])
{
  PetscInt k = 0;
  int      e = 0, idle = ST_IDLE, sig;
  char     prev[PETSC_MAX_PATH_LEN] = "";

  PetscFunctionBeginUser;
  /* if a handler is already dying on another thread, wait for its _exit */
  while (!__atomic_compare_exchange_n(&state, &idle, ST_PUBLISH, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST)) {
    idle = ST_IDLE;
    pause();
  }
  for (; k < n; k++) {
    if (k) M2dTestDelay(); /* tests: a SIGKILL between two renames */
    if (rename(f[k].tmp, f[k].final)) {
      e = errno;
      break;
    }
    Forget(&f[k].slot);
  }
  for (PetscInt j = 0; j < k; j++) SyncDirOf(f[j].final, prev, sizeof(prev)); /* the renames on disk */
  if (k == n && n > 0) __atomic_store_n(&output_written, 1, __ATOMIC_SEQ_CST);
  __atomic_store_n(&state, ST_IDLE, __ATOMIC_SEQ_CST);
  sig = __atomic_exchange_n(&pending_signal, 0, __ATOMIC_SEQ_CST);
  if (sig) Handler(sig);
  if (k < n) {
    PetscInt    bad = k;
    struct stat st;
    int         gone = e == ENOENT && lstat(f[bad].tmp, &st); /* which one: the temporary, or the directory */
    for (; k < n; k++) M2dFileAbort(&f[k]);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot put output file '%s' in place: %s%s%s%s", f[bad].final, strerror(e), gone ? " (its temporary is gone: " : "", gone ? f[bad].tmp : "", gone ? ")" : "");
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dFileCommit(M2dFile *f)
{
  PetscFunctionBeginUser;
  PetscCall(M2dFileClose(f));
  PetscCall(M2dFilePublish(1, f));
  PetscFunctionReturn(0);
}

void M2dFileAbort(M2dFile *f)
{
  if (f->fp) fclose(f->fp);
  f->fp = NULL;
  if (f->slot >= 0) unlink(f->tmp);
  Forget(&f->slot);
}
