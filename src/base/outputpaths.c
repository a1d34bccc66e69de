/* outputpaths.c - what can be known about the output before the mesh is
 * read, the run's id, and the summary of a failed run (see outputpaths.h). */
#define _POSIX_C_SOURCE 200809L
#include "outputpaths.h"
#include "summary.h"
#include "tempfile.h"
#include "util.h"
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define M2D_WORST_TAG ".m2d.tmp.ffffffff.2147483647."
#define M2D_OUTPUTS   6 /* .vtu .h5 .xmf _contact.csv, the summary, -mesh_save */

/* after OutputCheckPaths: where the summary of a failed run goes */
static M2dOutputPaths armed;
static PetscBool      is_armed = PETSC_FALSE, early_armed = PETSC_FALSE; /* early: the paths known, not yet checked */

/* directory part ("." when none) and file name of path; errors naming opt when the name is empty */
static PetscErrorCode SplitPath(const char *opt, const char *path, char *dir, size_t dlen, char *base, size_t blen)
{
  const char *slash = strrchr(path, '/');
  const char *b     = slash ? slash + 1 : path;

  PetscFunctionBeginUser;
  PetscCheck(b[0] && strcmp(b, ".") && strcmp(b, ".."), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: '%s' names a directory, not a file", opt, path);
  PetscCall(M2dPathPrintf(base, blen, opt, "%s", b));
  if (!slash) PetscCall(M2dPathPrintf(dir, dlen, opt, "."));
  else if (slash == path) PetscCall(M2dPathPrintf(dir, dlen, opt, "/"));
  else PetscCall(M2dPathPrintf(dir, dlen, opt, "%.*s", (int)(slash - path), path));
  PetscFunctionReturn(0);
}

/* a plain file name that needs no quoting in XML, XDMF ("file:/path"), URLs or shells */
static PetscErrorCode CheckName(MPI_Comm comm, const char *name)
{
  size_t n = strlen(name);

  PetscFunctionBeginUser;
  PetscCheck(n > 0, comm, PETSC_ERR_USER_INPUT, "option -output_name: the name is empty");
  PetscCheck(n <= M2D_OUTPUT_NAME_MAX, comm, PETSC_ERR_USER_INPUT, "option -output_name: '%.40s...' is longer than %d characters", name, M2D_OUTPUT_NAME_MAX);
  PetscCheck(isalnum((unsigned char)name[0]) || name[0] == '_', comm, PETSC_ERR_USER_INPUT, "option -output_name: '%s' must start with a letter, a digit or '_'", name);
  for (const unsigned char *c = (const unsigned char *)name; *c; c++) {
    PetscBool ok = (PetscBool)(*c < 128 && (isalnum(*c) || strchr("_-.+,=@~", *c)));
    if (*c >= 33 && *c < 127) PetscCheck(ok, comm, PETSC_ERR_USER_INPUT, "option -output_name: '%s' holds the character '%c' (allowed: letters, digits and _ - . + , = @ ~)", name, *c);
    else PetscCheck(ok, comm, PETSC_ERR_USER_INPUT, "option -output_name: '%s' holds the byte 0x%02x (allowed: letters, digits and _ - . + , = @ ~)", name, *c);
  }
  PetscFunctionReturn(0);
}

/* PetscOptionsString cuts a value to its buffer without a word: compare with the database */
static PetscErrorCode CheckNotCut(MPI_Comm comm, const char *opt, const char *value)
{
  const char *raw = NULL;
  PetscBool   set = PETSC_FALSE;
  size_t      n   = strlen(value);

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsFindPair(NULL, NULL, opt, &raw, &set));
  PetscCheck(!(set && raw && strlen(raw) > n && !strncmp(raw, value, n)), comm, PETSC_ERR_USER_INPUT, "option %s: the value '%.40s...' is longer than %d characters", opt, raw, (int)n);
  PetscFunctionReturn(0);
}

/* an output's path, the option that names it, and its directory and name */
typedef struct {
  const char *option;
  char        path[PETSC_MAX_PATH_LEN], dir[PETSC_MAX_PATH_LEN], base[M2D_NAME_MAX + 1];
} Output;

/* o's directory and name: those of path, where its temporary must fit too (tempfile.h), for any process id */
static PetscErrorCode SetWhere(Output *o, const char *path)
{
  char tmp[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(SplitPath(o->option, path, o->dir, sizeof(o->dir), o->base, sizeof(o->base)));
  PetscCall(M2dPathPrintf(tmp, sizeof(tmp), o->option, "%s/" M2D_WORST_TAG "%s", o->dir, o->base));
  PetscCall(M2dPathPrintf(tmp, M2D_NAME_MAX + 1, o->option, M2D_WORST_TAG "%s", o->base));
  PetscFunctionReturn(0);
}

static PetscErrorCode AddOutput(Output out[], PetscInt *n, const char *option, const char *path)
{
  Output *o = &out[(*n)++];

  PetscFunctionBeginUser;
  o->option = option;
  PetscCall(M2dPathPrintf(o->path, sizeof(o->path), option, "%s", path));
  PetscCall(SetWhere(o, path));
  PetscFunctionReturn(0);
}

/* a file can really be created in dir (a read-only or pseudo file system says so only then) */
static PetscErrorCode Probe(const char *opt, const char *dir)
{
  char    path[PETSC_MAX_PATH_LEN];
  M2dFile f;
  int     e = 0;

  PetscFunctionBeginUser;
  PetscCall(M2dPathPrintf(path, sizeof(path), opt, "%s/probe", dir));
  PetscCall(M2dFileOpen(path, PETSC_FALSE, &f));
  {
    int fd = open(f.tmp, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fd < 0 || write(fd, "", 1) != 1) e = errno;
    if (fd >= 0 && close(fd) && !e) e = errno;
  }
  M2dFileAbort(&f);
  PetscCheck(!e, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "option %s: cannot create files in '%s': %s", opt, dir, strerror(e));
  PetscFunctionReturn(0);
}

/* path resolved: the real path of its directory, then its name (when the directory exists) */
static void Resolve(const char *path, char *buf, size_t len)
{
  char        dir[PETSC_MAX_PATH_LEN], real[PATH_MAX];
  const char *slash = strrchr(path, '/');

  snprintf(dir, sizeof(dir), "%.*s", slash ? (slash == path ? 1 : (int)(slash - path)) : 1, slash ? path : ".");
  if (realpath(dir, real)) snprintf(buf, len, "%s/%s", strcmp(real, "/") ? real : "", slash ? slash + 1 : path);
  else snprintf(buf, len, "%s", path);
}

/* one file: the same resolved path, or the same device and inode (hard links) */
static PetscBool SameFile(const char *a, const char *b)
{
  char        ra[PETSC_MAX_PATH_LEN + PATH_MAX], rb[PETSC_MAX_PATH_LEN + PATH_MAX];
  struct stat sa, sb;

  if (!stat(a, &sa) && !stat(b, &sb) && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino) return PETSC_TRUE;
  Resolve(a, ra, sizeof(ra));
  Resolve(b, rb, sizeof(rb));
  return strcmp(ra, rb) ? PETSC_FALSE : PETSC_TRUE;
}

/* rank 0: the kind of each output and no input among them (an input exists:
 * an output in a directory yet to be made is none), then the directories
 * (made, a file created in each, leftovers removed), then no two outputs the same */
static PetscErrorCode CheckLocal(Output out[], PetscInt nout, PetscInt nfield, PetscInt ninput, const M2dInputFile in[])
{
  char why[2 * PETSC_MAX_PATH_LEN + 200], target[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < nout; k++) {
    Output *o = &out[k];
    PetscCheck(strncmp(o->base, M2D_TEMP_PREFIX, strlen(M2D_TEMP_PREFIX)), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: names starting with '" M2D_TEMP_PREFIX "' are mortar2d's own (%s)", o->option, o->path);
    PetscCheck(!M2dOutputTarget(o->path, target, sizeof(target), why, sizeof(why)), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: %s", o->option, why);
    if (strcmp(target, o->path)) PetscCall(SetWhere(o, target)); /* a link, written through: its target's directory is probed */
    for (PetscInt i = 0; i < ninput; i++)
      PetscCheck(!SameFile(o->path, in[i].path), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "options %s and %s name the same file '%s': the output would replace an input", o->option, in[i].option, o->path);
  }
  for (PetscInt k = 0; k < nout; k++) {
    const char *opt = k < nfield ? "-output_dir" : out[k].option;
    if (k && k < nfield) continue; /* the field files share one directory */
    if (strcmp(opt, "-mesh_save")) PetscCheck(!M2dMakeDirs(out[k].dir, why, sizeof(why)), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "option %s: %s", opt, why);
    PetscCall(Probe(opt, out[k].dir));
    M2dTempRemoveStale(out[k].dir);
  }
  for (PetscInt k = 0; k < nout; k++)
    for (PetscInt j = 0; j < k; j++)
      PetscCheck(!SameFile(out[k].path, out[j].path), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "options %s and %s name the same file '%s': two outputs of one run", out[j].option, out[k].option, out[k].path);
  PetscFunctionReturn(0);
}

/* the run's id: UTC time of the check, then 8 hex digits of the host, the
 * process and the nanoseconds (two runs started in one second differ) */
static void MakeRunId(char *id, size_t len)
{
  struct timespec ts;
  struct tm       tm;
  char            when[32];
  uint32_t        h = 2166136261u; /* FNV-1a */
  const char     *tag = M2dTempTag();

  clock_gettime(CLOCK_REALTIME, &ts);
  gmtime_r(&ts.tv_sec, &tm);
  strftime(when, sizeof(when), "%Y%m%dT%H%M%SZ", &tm);
  for (const char *c = tag; *c; c++) h = (h ^ (unsigned char)*c) * 16777619u;
  for (int k = 0; k < 4; k++) h = (h ^ (unsigned)((ts.tv_nsec >> (8 * k)) & 0xff)) * 16777619u;
  snprintf(id, len, "%s-%08x", when, (unsigned)h);
}

PetscErrorCode OutputCheckPaths(MPI_Comm comm, M2dOutputPaths *p, const char *mesh_save, PetscInt ninput, const M2dInputFile inputs[])
{
  static const char *const suffix[] = {".vtu", ".h5", ".xmf", "_contact.csv"};
  PetscBool                want[4]  = {p->vtu, p->h5, p->h5, p->csv};
  Output                  *out;
  PetscInt                 nout = 0, nfield;
  PetscMPIInt              rank;
  PetscErrorCode           ierr = 0;
  char                     err[1024] = "";

  PetscFunctionBeginUser;
  early_armed = PETSC_FALSE; /* a run refused for its output paths touches none of them */
  PetscCall(CheckName(comm, p->name));
  PetscCall(CheckNotCut(comm, "-output_name", p->name));
  PetscCall(CheckNotCut(comm, "-output_dir", p->dir));
  PetscCall(CheckNotCut(comm, "-summary", p->summary_path));
  PetscCall(CheckNotCut(comm, "-mesh_save", mesh_save));
  PetscCheck(p->summary || !p->summary_path[0], comm, PETSC_ERR_USER_INPUT, "option -summary: '%s' has no effect: -output leaves the summary out", p->summary_path);
  PetscCheck(!(p->vtu || p->h5 || p->csv || (p->summary && !p->summary_path[0])) || p->dir[0], comm, PETSC_ERR_USER_INPUT, "option -output_dir: the directory name is empty");
  if (p->summary && !p->summary_path[0]) PetscCall(M2dPathPrintf(p->summary_path, sizeof(p->summary_path), "-output_dir", "%s/%s_summary.json", p->dir, p->name));
  /* the same on every rank: names and lengths */
  PetscCall(PetscMalloc1(M2D_OUTPUTS, &out));
  for (int k = 0; k < 4; k++) {
    char path[PETSC_MAX_PATH_LEN];
    if (!want[k]) continue;
    PetscCall(M2dPathPrintf(path, sizeof(path), "-output_dir", "%s/%s%s", p->dir, p->name, suffix[k]));
    ierr = AddOutput(out, &nout, "-output_dir/-output_name", path);
    if (ierr) break;
  }
  nfield = nout;
  if (!ierr && p->summary) ierr = AddOutput(out, &nout, "-summary", p->summary_path);
  if (!ierr && mesh_save[0]) ierr = AddOutput(out, &nout, "-mesh_save", mesh_save);
  if (ierr) PetscCall(PetscFree(out));
  PetscCall(ierr);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    ierr = CheckLocal(out, nout, nfield, ninput, inputs);
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
    MakeRunId(p->run_id, sizeof(p->run_id));
  }
  PetscCall(PetscFree(out));
  PetscCall(M2dCheckCollective(comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscCallMPI(MPI_Bcast(p->run_id, (PetscMPIInt)sizeof(p->run_id), MPI_CHAR, 0, comm));
  armed       = *p;
  is_armed    = (PetscBool)(rank == 0 && p->summary);
  early_armed = PETSC_FALSE;
  PetscFunctionReturn(0);
}

void OutputArmEarly(MPI_Comm comm, const M2dOutputPaths *p)
{
  PetscMPIInt rank = 1;

  if (is_armed || !p->summary) return;
  (void)MPI_Comm_rank(comm, &rank);
  if (rank) return;
  armed = *p;
  if (!armed.summary_path[0] && (size_t)snprintf(armed.summary_path, sizeof(armed.summary_path), "%s/%s_summary.json", p->dir, p->name) >= sizeof(armed.summary_path)) return;
  MakeRunId(armed.run_id, sizeof(armed.run_id));
  early_armed = PETSC_TRUE;
}

/* an earlier run's summary at path (through links), which a failed run may mark */
static PetscBool EarlierSummary(const char *path)
{
  char        head[512] = "";
  FILE       *fp;
  size_t      n;
  struct stat st;

  if (stat(path, &st) || !S_ISREG(st.st_mode) || !(fp = fopen(path, "rb"))) return PETSC_FALSE; /* never a FIFO or a terminal: reading would wait */
  n       = fread(head, 1, sizeof(head) - 1, fp);
  head[n] = 0;
  fclose(fp);
  return (PetscBool)(strstr(head, "\"program\": \"mortar2d\"") != NULL);
}

void OutputWriteFailure(const char *msg)
{
  M2dSummary s = {0};
  M2dFile    f;

  if (!is_armed && !(early_armed && EarlierSummary(armed.summary_path))) return; /* before the checks: only an earlier summary is marked, nothing created */
  is_armed = early_armed = PETSC_FALSE; /* once */
  if (M2dSummaryString(&s, "", "program", "mortar2d") || M2dSummaryString(&s, "", "run_id", armed.run_id) || M2dSummaryString(&s, "", "status", "error") || M2dSummaryString(&s, "", "error", msg)) {
    (void)M2dSummaryDestroy(&s);
    return;
  }
  if (!M2dFileOpen(armed.summary_path, PETSC_TRUE, &f)) {
    M2dSummaryPrint(f.fp, &s);
    if (M2dFileCommit(&f)) M2dFileAbort(&f);
  }
  (void)M2dSummaryDestroy(&s);
}
