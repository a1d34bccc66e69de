/* tempfile.c - see tempfile.h.  The signal handler only reads the table below
 * (paths written before their `used` flag is raised), calls unlink, rmdir,
 * write and _exit: all async-signal-safe.  The commit section is a three-state
 * atomic (idle, commit, dying) so that a signal taken on any thread either
 * finds no switch in progress or is deferred until the switch is done. */
#include "tempfile.h"
#include "temprecord.h"
#include "util.h"
#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define M2D_TEMP_MAX 64

typedef struct {
  volatile sig_atomic_t used;
  int                   isdir;
  char                  path[PETSC_MAX_PATH_LEN];
} TempEntry;

enum { ST_IDLE, ST_COMMIT, ST_DYING };

static TempEntry    temps[M2D_TEMP_MAX];
static int          state = ST_IDLE;     /* atomics: handler and main thread */
static int          pending_signal = 0;  /* a signal deferred by the commit section */
static int          output_written = 0;  /* set at the end of a successful commit */
static int          world_rank     = -1; /* only world rank 0 prints */
static int          world_size     = 1;
static pid_t        owner          = 0;  /* the process that recorded the table */
static char         tag[64];
static int          atexit_done = 0;

static void RemoveRecorded(void)
{
  if (getpid() != owner) return; /* a forked child owns nothing */
  for (int pass = 0; pass < 2; pass++)
    for (int i = M2D_TEMP_MAX - 1; i >= 0; i--) {
      if (!temps[i].used || temps[i].isdir != pass) continue;
      if (pass) rmdir(temps[i].path);
      else unlink(temps[i].path);
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
   * mpiexec to end them */
  /* after an error main prints that error: mpiexec's SIGTERM to the ranks
   * still finishing must not add a second line */
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

static void Handler(int sig)
{
  int idle = ST_IDLE;
  if (__atomic_compare_exchange_n(&state, &idle, ST_DYING, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST)) Die(sig);
  if (idle == ST_COMMIT) __atomic_store_n(&pending_signal, sig, __ATOMIC_SEQ_CST); /* acted on at CommitEnd */
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

static int SetHandlers(void)
{
  struct sigaction sa;
  int              sigs[3] = {SIGINT, SIGTERM, SIGHUP};

  memset(&sa, 0, sizeof(sa));
  sa.sa_handler = Handler;
  sigemptyset(&sa.sa_mask);
  for (int k = 0; k < 3; k++) sigaddset(&sa.sa_mask, sigs[k]);
  for (int k = 0; k < 3; k++)
    if (sigaction(sigs[k], &sa, NULL)) return sigs[k];
  /* stdout only reports progress: a reader that goes away (`mortar2d ... |
   * head -1`) must not kill the run (PETSc's handler made that a 6-line
   * "Caught signal 13 Broken Pipe" and exit 59); the writes fail quietly */
  sa.sa_handler = SIG_IGN;
  if (sigaction(SIGPIPE, &sa, NULL)) return SIGPIPE;
  return 0;
}

static int EnvInt(const char *const names[], int def)
{
  for (int k = 0; names[k]; k++) {
    const char *v = getenv(names[k]);
    if (v && *v) return atoi(v);
  }
  return def;
}

int M2dInstallEarlySignalHandlers(void)
{
  const char *const rank_vars[] = {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK", NULL};
  const char *const size_vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", NULL};
  world_rank = EnvInt(rank_vars, 0);
  world_size = EnvInt(size_vars, 1);
  owner      = getpid();
  return SetHandlers();
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
  (void)M2dTempTag();
  bad = SetHandlers();
  PetscCheck(!bad, PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot install the handler of signal %d: %s", bad, strerror(errno));
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

int M2dTempTryRecord(const char *path, PetscBool isdir)
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
    temps[i].isdir = isdir ? 1 : 0;
    __atomic_thread_fence(__ATOMIC_SEQ_CST); /* the path is complete before the handler may read it */
    temps[i].used = 1;
    return i;
  }
  return -1;
}

int M2dTempRecordFile(const char *path)
{
  return M2dTempTryRecord(path, PETSC_FALSE);
}

void M2dTempForgetFile(int slot)
{
  M2dTempForget(&slot);
}

PetscErrorCode M2dTempRecord(const char *path, PetscBool isdir, int *slot)
{
  PetscFunctionBeginUser;
  *slot = M2dTempTryRecord(path, isdir);
  PetscCheck(*slot >= 0, PETSC_COMM_SELF, PETSC_ERR_MEM, "cannot record the temporary '%.200s': path too long or more than %d temporaries", path, M2D_TEMP_MAX);
  PetscFunctionReturn(0);
}

void M2dTempForget(int *slot)
{
  if (*slot >= 0 && *slot < M2D_TEMP_MAX) temps[*slot].used = 0;
  *slot = -1;
}

void M2dTempRemoveAll(void)
{
  if (!owner) return;
  RemoveRecorded();
}

void M2dTempCommitBegin(void)
{
  int idle = ST_IDLE;
  /* if a handler is already dying on another thread, wait for its _exit */
  while (!__atomic_compare_exchange_n(&state, &idle, ST_COMMIT, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST)) {
    idle = ST_IDLE;
    pause();
  }
}

void M2dTempCommitEnd(PetscBool written)
{
  int sig;
  if (written) __atomic_store_n(&output_written, 1, __ATOMIC_SEQ_CST);
  __atomic_store_n(&state, ST_IDLE, __ATOMIC_SEQ_CST);
  sig = __atomic_exchange_n(&pending_signal, 0, __ATOMIC_SEQ_CST);
  if (sig) Handler(sig);
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

/* "<8 hex>.<pid>." after prefix: this host's tag of a process that is gone */
PetscBool M2dTempIsStale(const char *name, const char *prefix, const char **rest)
{
  size_t      lp = strlen(prefix);
  const char *t  = M2dTempTag(), *p;
  char       *end;
  long        pid;

  if (strncmp(name, prefix, lp) || strncmp(name + lp, t, 9)) return PETSC_FALSE; /* other kind or host */
  p   = name + lp + 9;
  pid = strtol(p, &end, 10);
  if (end == p || (*end != '.' && *end != 0) || pid <= 0) return PETSC_FALSE;
  if (rest) *rest = *end ? end + 1 : end;
  if (pid == (long)getpid()) return PETSC_FALSE;
  return Gone(pid);
}

/* the temporaries of earlier versions: BASE.tmp<pid> */
static PetscBool LegacyStale(const char *name, const char *base)
{
  size_t lb = strlen(base);
  char  *end;
  long   pid;

  if (strncmp(name, base, lb) || strncmp(name + lb, ".tmp", 4)) return PETSC_FALSE;
  pid = strtol(name + lb + 4, &end, 10);
  if (end == name + lb + 4 || *end || pid <= 0 || pid == (long)getpid()) return PETSC_FALSE;
  return Gone(pid);
}

void M2dTempRemoveStale(const char *dir, const char *const *bases)
{
  static const char *const kinds[] = {M2D_TEMP_PREFIX "tmp.", M2D_TEMP_PREFIX "tmp-probe.", M2D_TEMP_PREFIX "tmp-link.", NULL};
  DIR                     *d       = opendir(dir);
  struct dirent           *e;
  char                     path[PETSC_MAX_PATH_LEN];

  if (!d) return;
  while ((e = readdir(d))) {
    const char *rest = NULL;
    PetscBool   bad  = PETSC_FALSE;
    for (int k = 0; !bad && kinds[k]; k++) bad = M2dTempIsStale(e->d_name, kinds[k], &rest);
    for (int k = 0; !bad && bases && bases[k]; k++) bad = LegacyStale(e->d_name, bases[k]);
    if (!bad) continue;
    if ((size_t)snprintf(path, sizeof(path), "%s/%s", dir, e->d_name) >= sizeof(path)) continue;
    unlink(path);
  }
  closedir(d);
}

const char *M2dPublicName(const char *path, char *buf, size_t len)
{
  const char *g = strstr(path, "/" M2D_TEMP_PREFIX "gen."), *e = g ? strchr(g + 1, '/') : NULL;
  if (!e || strchr(e + 1, '/') || (size_t)snprintf(buf, len, "%.*s%s", (int)(g - path), path, e) >= len) return path;
  return buf;
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

PetscErrorCode M2dFileOpen(const char *path, M2dFile *f)
{
  PetscFunctionBeginUser;
  f->fp   = NULL;
  f->slot = -1;
  f->tmp[0] = 0;
  PetscCall(PetscStrncpy(f->final, path, sizeof(f->final)));
  PetscCall(M2dTmpName(path, f->tmp, sizeof(f->tmp)));
  PetscCall(M2dTempRecord(f->tmp, PETSC_FALSE, &f->slot));
  f->fp = fopen(f->tmp, "wb");
  if (!f->fp) {
    int  e = errno;
    char pub[PETSC_MAX_PATH_LEN];
    M2dTempForget(&f->slot);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write output file '%s': %s", M2dPublicName(f->final, pub, sizeof(pub)), strerror(e));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dFileCommit(M2dFile *f)
{
  int bad, e = 0;

  PetscFunctionBeginUser;
  bad = ferror(f->fp) || fflush(f->fp);
  if (bad) e = errno;
  if (!bad && fsync(fileno(f->fp))) {
    bad = 1;
    e   = errno;
  }
  if (fclose(f->fp) && !bad) {
    bad = 1;
    e   = errno;
  }
  f->fp = NULL;
  if (!bad && rename(f->tmp, f->final)) {
    bad = 2;
    e   = errno;
  }
  if (bad) {
    char pub[PETSC_MAX_PATH_LEN];
    unlink(f->tmp);
    M2dTempForget(&f->slot);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "%s output file '%s' failed: %s", bad == 2 ? "renaming" : "writing", M2dPublicName(f->final, pub, sizeof(pub)), e ? strerror(e) : "write error");
  }
  M2dTempForget(&f->slot);
  PetscFunctionReturn(0);
}

void M2dFileAbort(M2dFile *f)
{
  if (f->fp) fclose(f->fp);
  f->fp = NULL;
  if (f->slot >= 0) unlink(f->tmp);
  M2dTempForget(&f->slot);
}
