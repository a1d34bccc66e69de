/* outputset.c - stage, commit or abort the files of one run (see outputset.h).
 * Rank 0 does every file operation; the other ranks hold the same paths. */
#include "outputset.h"
#include "outputset_impl.h"
#include "util.h"
#include <errno.h>
#include <dirent.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define M2D_SET_MAX 16

struct _p_M2dOutputSet {
  MPI_Comm    comm;
  PetscMPIInt rank;
  PetscBool   files;                      /* DIR is used (HDF5/VTU/CSV) */
  char        dir[PETSC_MAX_PATH_LEN];
  char        name[M2D_NAME_MAX + 1];
  char        stage[M2D_NAME_MAX + 1];    /* .m2d.gen... (in DIR) */
  char        stagepath[PETSC_MAX_PATH_LEN];
  int         stageslot;
  PetscInt    n;                          /* files in the set */
  char        base[M2D_SET_MAX][M2D_NAME_MAX + 1];
  char        path[M2D_SET_MAX][PETSC_MAX_PATH_LEN];
  int         slot[M2D_SET_MAX];
  char        summary[PETSC_MAX_PATH_LEN]; /* final summary path, "" none */
  char        sumpath[PETSC_MAX_PATH_LEN]; /* where it is written */
  PetscBool   suminside;                   /* part of the set */
  int         sumslot;
};

/* the sets begun and not yet committed or aborted: an error return leaves them
 * here (reachable) for M2dOutputSetAbortOpen */
#define M2D_OPEN_MAX 8
static M2dOutputSet open_sets[M2D_OPEN_MAX];

static void Track(M2dOutputSet s, PetscBool add)
{
  for (int i = 0; i < M2D_OPEN_MAX; i++)
    if (open_sets[i] == (add ? NULL : s)) {
      open_sets[i] = add ? s : NULL;
      return;
    }
}

/* ---------- helpers shared with outputcheck.c ---------- */
PetscErrorCode M2dSetPointerName(const char *name, char *buf, size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(M2dPathPrintf(buf, len, "-output_name", M2D_TEMP_PREFIX "set.%s", name));
  PetscFunctionReturn(0);
}

void M2dSetRemoveGen(const char *dir, const char *gen)
{
  char           path[PETSC_MAX_PATH_LEN], f[PETSC_MAX_PATH_LEN];
  DIR           *d;
  struct dirent *e;

  if (strncmp(gen, M2D_TEMP_PREFIX "gen.", sizeof(M2D_TEMP_PREFIX "gen.") - 1) || strchr(gen, '/')) return; /* only ours */
  if ((size_t)snprintf(path, sizeof(path), "%s/%s", dir, gen) >= sizeof(path)) return;
  if (!(d = opendir(path))) return;
  while ((e = readdir(d)))
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && (size_t)snprintf(f, sizeof(f), "%s/%s", path, e->d_name) < sizeof(f)) unlink(f);
  closedir(d);
  rmdir(path);
}

static int FsyncPath(const char *path, PetscBool isdir)
{
  int fd = open(path, isdir ? O_RDONLY | O_DIRECTORY : O_RDONLY), r;
  if (fd < 0) return -1;
  r = fsync(fd);
  if (r && (errno == EINVAL || errno == EROFS)) r = 0; /* file systems without fsync */
  close(fd);
  return r;
}

/* make `target` a symbolic link holding `text`, atomically (temporary + rename) */
static PetscErrorCode SwapLink(const char *dir, const char *text, const char *target)
{
  char tmp[PETSC_MAX_PATH_LEN];
  int  slot;

  PetscFunctionBeginUser;
  PetscCall(M2dPathPrintf(tmp, sizeof(tmp), "-output_dir", "%s/" M2D_TEMP_PREFIX "tmp-link.%s", dir, M2dTempTag()));
  PetscCall(M2dTempRecord(tmp, PETSC_FALSE, &slot));
  unlink(tmp);
  if (symlink(text, tmp) || rename(tmp, target)) {
    int e = errno;
    unlink(tmp);
    M2dTempForget(&slot);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot create the link '%s': %s", target, strerror(e));
  }
  M2dTempForget(&slot);
  PetscFunctionReturn(0);
}

/* ---------- begin ---------- */
/* create DIR/.m2d.gen.<tag>.<kind><k>.NAME with the first free k: a directory
 * of the same name can only be left by an earlier process with our pid */
static PetscErrorCode MakeGen(M2dOutputSet s, const char *kind, int *k, char *gen, char *path, int *slot)
{
  PetscFunctionBeginUser;
  for (int tries = 0;; tries++) {
    PetscCall(M2dPathPrintf(gen, M2D_NAME_MAX + 1, "-output_name", M2D_TEMP_PREFIX "gen.%s.%s%d.%s", M2dTempTag(), kind, (*k)++, s->name));
    PetscCall(M2dPathPrintf(path, PETSC_MAX_PATH_LEN, "-output_dir", "%s/%s", s->dir, gen));
    PetscCall(M2dTempRecord(path, PETSC_TRUE, slot));
    if (!mkdir(path, 0777)) break;
    M2dTempForget(slot);
    PetscCheck(errno == EEXIST && tries < 1000, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "option -output_dir: cannot create '%s': %s", path, strerror(errno));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode BeginLocal(M2dOutputSet s, const char *summary)
{
  static int seq = 0;
  char       why[900], sumdir[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (s->files) {
    PetscCheck(!M2dMakeDirs(s->dir, why, sizeof(why)), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "option -output_dir: %s", why);
    PetscCall(MakeGen(s, "", &seq, s->stage, s->stagepath, &s->stageslot));
  }
  if (summary && summary[0]) {
    struct stat a, b;
    PetscCall(M2dPathPrintf(s->summary, sizeof(s->summary), "-summary", "%s", summary));
    PetscCall(M2dSetSplitPath(summary, sumdir, sizeof(sumdir), NULL));
    s->suminside = (PetscBool)(s->files && !stat(sumdir, &a) && !stat(s->dir, &b) && a.st_dev == b.st_dev && a.st_ino == b.st_ino);
    if (!s->suminside) {
      PetscCall(M2dTmpName(summary, s->sumpath, sizeof(s->sumpath)));
      PetscCall(M2dTempRecord(s->sumpath, PETSC_FALSE, &s->sumslot));
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOutputSetBegin(MPI_Comm comm, const char *outdir, const char *outname, const char *summary, PetscBool write_files, M2dOutputSet *set)
{
  M2dOutputSet   s;
  PetscErrorCode ierr = 0;
  char           err[1024] = "";
  int            inside;

  PetscFunctionBeginUser;
  *set = NULL;
  PetscCheck(strlen(outdir) < sizeof(s->dir) && strlen(outname) < sizeof(s->name), PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "option -output_dir or -output_name: the name is too long");
  PetscCall(PetscNew(&s));
  s->comm      = comm;
  s->files     = write_files;
  s->stageslot = s->sumslot = -1;
  for (int i = 0; i < M2D_SET_MAX; i++) s->slot[i] = -1;
  PetscCallMPI(MPI_Comm_rank(comm, &s->rank));
  PetscCall(PetscStrncpy(s->dir, outdir, sizeof(s->dir)));
  PetscCall(PetscStrncpy(s->name, outname, sizeof(s->name)));
  *set = s;
  Track(s, PETSC_TRUE);
  if (s->rank == 0) {
    ierr = BeginLocal(s, summary);
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  ierr = M2dCheckCollective(comm, ierr ? PETSC_TRUE : PETSC_FALSE, err);
  if (ierr) {
    PetscCall(M2dOutputSetAbort(set));
    PetscCall(ierr);
  }
  /* the other ranks learn rank 0's names (they carry its pid) */
  inside = s->suminside;
  PetscCallMPI(MPI_Bcast(s->stage, (int)sizeof(s->stage), MPI_CHAR, 0, comm));
  PetscCallMPI(MPI_Bcast(s->stagepath, (int)sizeof(s->stagepath), MPI_CHAR, 0, comm));
  PetscCallMPI(MPI_Bcast(s->summary, (int)sizeof(s->summary), MPI_CHAR, 0, comm));
  PetscCallMPI(MPI_Bcast(s->sumpath, (int)sizeof(s->sumpath), MPI_CHAR, 0, comm));
  PetscCallMPI(MPI_Bcast(&inside, 1, MPI_INT, 0, comm));
  s->suminside = inside ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* add base to the set; *k its index */
static PetscErrorCode AddFile(M2dOutputSet s, const char *base, PetscInt *k)
{
  PetscFunctionBeginUser;
  for (*k = 0; *k < s->n; (*k)++)
    if (!strcmp(s->base[*k], base)) PetscFunctionReturn(0);
  PetscCheck(s->n < M2D_SET_MAX, PETSC_COMM_SELF, PETSC_ERR_ARG_SIZ, "more than %d files in one output set", M2D_SET_MAX);
  PetscCall(M2dPathPrintf(s->base[*k], sizeof(s->base[*k]), "-output_name", "%s", base));
  PetscCall(M2dPathPrintf(s->path[*k], sizeof(s->path[*k]), "-output_dir", "%s/%s", s->stagepath, base));
  if (s->rank == 0) PetscCall(M2dTempRecord(s->path[*k], PETSC_FALSE, &s->slot[*k]));
  s->n++;
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOutputSetFile(M2dOutputSet s, const char *suffix, const char **path)
{
  char     base[M2D_NAME_MAX + 1];
  PetscInt k;

  PetscFunctionBeginUser;
  PetscCheck(s->files, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONGSTATE, "output set without an output directory: no file %s%s", s->name, suffix);
  PetscCall(M2dPathPrintf(base, sizeof(base), "-output_name", "%s%s", s->name, suffix));
  PetscCall(AddFile(s, base, &k));
  *path = s->path[k];
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOutputSetSummary(M2dOutputSet s, const char **path)
{
  PetscInt k;
  char     base[M2D_NAME_MAX + 1];

  PetscFunctionBeginUser;
  *path = NULL;
  if (!s->summary[0]) PetscFunctionReturn(0);
  if (!s->suminside) {
    *path = s->sumpath;
    PetscFunctionReturn(0);
  }
  PetscCall(M2dSetSplitPath(s->summary, NULL, 0, base));
  PetscCall(AddFile(s, base, &k));
  *path = s->path[k];
  PetscFunctionReturn(0);
}

const char *M2dOutputSetName(M2dOutputSet s)
{
  return s->name;
}

/* ---------- abort ---------- */
static void AbortLocal(M2dOutputSet s)
{
  for (PetscInt k = 0; k < s->n; k++) M2dTempForget(&s->slot[k]);
  if (s->sumslot >= 0) unlink(s->sumpath);
  M2dTempForget(&s->sumslot);
  if (s->stageslot >= 0) M2dSetRemoveGen(s->dir, s->stage); /* everything in it is ours */
  M2dTempForget(&s->stageslot);
}

PetscErrorCode M2dOutputSetAbort(M2dOutputSet *set)
{
  PetscFunctionBeginUser;
  if (!*set) PetscFunctionReturn(0);
  if ((*set)->rank == 0) AbortLocal(*set);
  Track(*set, PETSC_FALSE);
  PetscCall(PetscFree(*set));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOutputSetAbortOpen(void)
{
  PetscFunctionBeginUser;
  for (int i = 0; i < M2D_OPEN_MAX; i++) {
    M2dOutputSet s = open_sets[i];
    if (s) PetscCall(M2dOutputSetAbort(&s));
  }
  PetscFunctionReturn(0);
}

/* ---------- commit ---------- */
/* every staged file exists and is on disk */
static PetscErrorCode SyncStage(M2dOutputSet s)
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < s->n; k++) {
    struct stat st;
    PetscCheck(!stat(s->path[k], &st) && S_ISREG(st.st_mode), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "output file '%s/%s' was not written", s->dir, s->base[k]);
    PetscCheck(!FsyncPath(s->path[k], PETSC_FALSE), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "writing output file '%s/%s' failed: %s", s->dir, s->base[k], strerror(errno));
    M2dTestDelay();
  }
  PetscCheck(!FsyncPath(s->stagepath, PETSC_TRUE), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "option -output_dir: cannot sync '%s': %s", s->stagepath, strerror(errno));
  PetscFunctionReturn(0);
}

/* no current set yet but a plain file to keep visible: make an empty set current */
static PetscErrorCode EnsureCurrent(M2dOutputSet s, const char *ptrpath, char *old, size_t len)
{
  static int adopt = 0;
  char       gen[M2D_NAME_MAX + 1], path[PETSC_MAX_PATH_LEN];
  int        slot;

  PetscFunctionBeginUser;
  if (old[0]) PetscFunctionReturn(0);
  PetscCall(MakeGen(s, "a", &adopt, gen, path, &slot));
  M2dTempCommitBegin();
  if (SwapLink(s->dir, gen, ptrpath)) {
    M2dTempCommitEnd(PETSC_FALSE);
    rmdir(path);
    M2dTempForget(&slot);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "option -output_dir: cannot create the link '%s'", ptrpath);
  }
  M2dTempForget(&slot); /* current from now on */
  M2dTempCommitEnd(PETSC_FALSE);
  PetscCall(PetscStrncpy(old, gen, len));
  PetscFunctionReturn(0);
}

/* public name DIR/base becomes the link .m2d.set.N/base; what it showed before
 * is first placed in the current set, so that it keeps showing the same file */
static PetscErrorCode PublishName(M2dOutputSet s, const char *base, const char *ptr, const char *ptrpath, char *old, size_t len)
{
  char        pub[PETSC_MAX_PATH_LEN], want[PETSC_MAX_PATH_LEN], have[PETSC_MAX_PATH_LEN], keep[PETSC_MAX_PATH_LEN];
  struct stat st;
  ssize_t     n;

  PetscFunctionBeginUser;
  PetscCall(M2dPathPrintf(pub, sizeof(pub), "-output_dir", "%s/%s", s->dir, base));
  PetscCall(M2dPathPrintf(want, sizeof(want), "-output_name", "%s/%s", ptr, base));
  if (lstat(pub, &st)) {
    PetscCheck(errno == ENOENT, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write output file '%s': %s", pub, strerror(errno));
    PetscCall(SwapLink(s->dir, want, pub));
    PetscFunctionReturn(0);
  }
  PetscCheck(!S_ISDIR(st.st_mode), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write output file '%s': it is a directory", pub);
  n = S_ISLNK(st.st_mode) ? readlink(pub, have, sizeof(have) - 1) : -1;
  if (n >= 0) have[n] = 0;
  if (n >= 0 && !strcmp(have, want)) PetscFunctionReturn(0);
  PetscCall(EnsureCurrent(s, ptrpath, old, len));
  PetscCall(M2dPathPrintf(keep, sizeof(keep), "-output_dir", "%s/%s/%s", s->dir, old, base));
  unlink(keep); /* not visible: pub is not a link to it */
  if (n >= 0) { /* a foreign link: the same text, one level down */
    char text[PETSC_MAX_PATH_LEN];
    PetscCall(M2dPathPrintf(text, sizeof(text), "-output_dir", "%s%s", have[0] == '/' ? "" : "../", have));
    PetscCheck(!symlink(text, keep), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot create the link '%s': %s", keep, strerror(errno));
  } else if (link(pub, keep)) { /* no hard links here: move it (missing until the link below takes its place) */
    PetscCheck(!rename(pub, keep), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot keep the previous '%s' in '%s': %s", pub, old, strerror(errno));
  }
  PetscCall(SwapLink(s->dir, want, pub));
  PetscFunctionReturn(0);
}

/* links of this name that no longer resolve (a file the new set lacks) */
static void RemoveDangling(M2dOutputSet s, const char *ptr)
{
  DIR           *d = opendir(s->dir);
  struct dirent *e;
  size_t         lp = strlen(ptr);

  if (!d) return;
  while ((e = readdir(d))) {
    char        pub[PETSC_MAX_PATH_LEN], have[PETSC_MAX_PATH_LEN];
    struct stat st;
    ssize_t     n;
    if ((size_t)snprintf(pub, sizeof(pub), "%s/%s", s->dir, e->d_name) >= sizeof(pub)) continue;
    if (lstat(pub, &st) || !S_ISLNK(st.st_mode)) continue;
    n = readlink(pub, have, sizeof(have) - 1);
    if (n < 0) continue;
    have[n] = 0;
    if (!strncmp(have, ptr, lp) && have[lp] == '/' && stat(pub, &st) && errno == ENOENT) unlink(pub);
  }
  closedir(d);
}

/* the files of the set being replaced, to record at the switch */
typedef struct {
  PetscInt n;
  char     path[2 * M2D_SET_MAX + 1][PETSC_MAX_PATH_LEN];
  int      slot[2 * M2D_SET_MAX + 1];
} OldSet;

static PetscErrorCode ListOld(M2dOutputSet s, const char *old, OldSet *o)
{
  DIR           *d;
  struct dirent *e;

  PetscFunctionBeginUser;
  o->n = 0;
  if (!old[0] || !strcmp(old, s->stage) || strncmp(old, M2D_TEMP_PREFIX "gen.", sizeof(M2D_TEMP_PREFIX "gen.") - 1) || strchr(old, '/')) PetscFunctionReturn(0);
  PetscCall(M2dPathPrintf(o->path[0], sizeof(o->path[0]), "-output_dir", "%s/%s", s->dir, old));
  o->n = 1;
  if (!(d = opendir(o->path[0]))) PetscFunctionReturn(0);
  while ((e = readdir(d)) && o->n < 2 * M2D_SET_MAX + 1)
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && (size_t)snprintf(o->path[o->n], sizeof(o->path[0]), "%s/%s", o->path[0], e->d_name) < sizeof(o->path[0])) o->n++;
  closedir(d);
  PetscFunctionReturn(0);
}

/* the switch: one rename of the pointer (and the outside summary's); from
 * then on the staged files are current and the previous set is a temporary */
static PetscErrorCode Switch(M2dOutputSet s, const char *ptrpath, OldSet *o)
{
  PetscErrorCode ierr = 0;
  int            e    = 0;

  PetscFunctionBeginUser;
  M2dTempCommitBegin();
  if (s->files) ierr = SwapLink(s->dir, s->stage, ptrpath);
  if (!ierr && s->summary[0] && !s->suminside && rename(s->sumpath, s->summary)) e = errno;
  if (!ierr) {
    for (PetscInt k = 0; k < s->n; k++) M2dTempForget(&s->slot[k]);
    M2dTempForget(&s->stageslot);
    if (!e) M2dTempForget(&s->sumslot);
    for (PetscInt k = 0; o && k < o->n; k++) o->slot[k] = M2dTempTryRecord(o->path[k], (PetscBool)(k == 0));
  }
  M2dTempCommitEnd(ierr ? PETSC_FALSE : PETSC_TRUE);
  PetscCall(ierr);
  PetscCheck(!e, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "option -summary: cannot write '%s': %s", s->summary, strerror(e));
  PetscFunctionReturn(0);
}

static PetscErrorCode CommitLocal(M2dOutputSet s)
{
  char    ptr[M2D_NAME_MAX + 1], ptrpath[PETSC_MAX_PATH_LEN], old[PETSC_MAX_PATH_LEN] = "";
  ssize_t        n;
  OldSet        *o;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  if (!s->files) {
    PetscCall(Switch(s, NULL, NULL));
    PetscFunctionReturn(0);
  }
  PetscCall(SyncStage(s));
  PetscCall(M2dSetPointerName(s->name, ptr, sizeof(ptr)));
  PetscCall(M2dPathPrintf(ptrpath, sizeof(ptrpath), "-output_dir", "%s/%s", s->dir, ptr));
  n = readlink(ptrpath, old, sizeof(old) - 1);
  PetscCheck(n >= 0 || errno == ENOENT, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "option -output_dir: '%s' is not a symbolic link: %s", ptrpath, strerror(errno));
  old[n >= 0 ? n : 0] = 0;
  for (PetscInt k = 0; k < s->n; k++) {
    PetscCall(PublishName(s, s->base[k], ptr, ptrpath, old, sizeof(old)));
    M2dTestDelay();
  }
  PetscCheck(!FsyncPath(s->dir, PETSC_TRUE), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "option -output_dir: cannot sync '%s': %s", s->dir, strerror(errno));
  PetscCall(PetscNew(&o));
  ierr = ListOld(s, old, o);
  if (!ierr) ierr = Switch(s, ptrpath, o);
  if (ierr) {
    PetscCall(PetscFree(o));
    PetscCall(ierr);
  }
  FsyncPath(s->dir, PETSC_TRUE);
  M2dTestDelay();
  RemoveDangling(s, ptr);
  for (PetscInt k = o->n - 1; k >= 0; k--) {
    if (k) unlink(o->path[k]);
    else rmdir(o->path[0]);
    M2dTempForget(&o->slot[k]);
  }
  PetscCall(PetscFree(o));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOutputSetCommit(M2dOutputSet *set)
{
  M2dOutputSet   s    = *set;
  PetscErrorCode ierr = 0;
  char           err[1024] = "";

  PetscFunctionBeginUser;
  if (s->rank == 0) {
    ierr = CommitLocal(s);
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  ierr = M2dCheckCollective(s->comm, ierr ? PETSC_TRUE : PETSC_FALSE, err);
  PetscCall(M2dOutputSetAbort(set)); /* after a commit only the failed parts remain */
  PetscCall(ierr);
  PetscFunctionReturn(0);
}
