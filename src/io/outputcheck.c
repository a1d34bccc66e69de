/* outputcheck.c - OutputCheckPaths (outputset.h): what can be known about the
 * output before the mesh is read, and the leftovers of killed runs. */
#include "outputset.h"
#include "outputset_impl.h"
#include "util.h"
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define M2D_OUTPUT_NAME_MAX 200 /* leaves room for .m2d.gen.<tag>.<k>. within NAME_MAX */
#define M2D_WORST_TAG       "ffffffff.2147483647.2147483647"

static const char *const suffix[] = {".h5", ".xmf", ".vtu", "_contact.csv"};
#define NSUFFIX 4

PetscErrorCode M2dSetSplitPath(const char *path, char *dir, size_t dlen, char *base)
{
  const char *slash = strrchr(path, '/');
  const char *b     = slash ? slash + 1 : path;

  PetscFunctionBeginUser;
  PetscCheck(b[0] && strcmp(b, ".") && strcmp(b, ".."), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -summary: '%s' names a directory, not a file", path);
  if (base) PetscCall(M2dPathPrintf(base, M2D_NAME_MAX + 1, "-summary", "%s", b));
  if (!dir) PetscFunctionReturn(0);
  if (!slash) PetscCall(M2dPathPrintf(dir, dlen, "-summary", "."));
  else if (slash == path) PetscCall(M2dPathPrintf(dir, dlen, "-summary", "/"));
  else PetscCall(M2dPathPrintf(dir, dlen, "-summary", "%.*s", (int)(slash - path), path));
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

/* the longest paths a run builds from these options must fit */
static PetscErrorCode CheckLengths(const char *outdir, const char *outname, const char *summary, PetscBool files)
{
  char buf[PETSC_MAX_PATH_LEN], sumdir[PETSC_MAX_PATH_LEN], base[M2D_NAME_MAX + 1];

  PetscFunctionBeginUser;
  if (files) PetscCall(M2dPathPrintf(buf, sizeof(buf), "-output_dir", "%s/.m2d.gen." M2D_WORST_TAG ".%s/.m2d.tmp." M2D_WORST_TAG ".%s_contact.csv", outdir, outname, outname));
  if (summary[0]) {
    PetscCall(M2dSetSplitPath(summary, sumdir, sizeof(sumdir), base));
    PetscCall(M2dPathPrintf(buf, sizeof(buf), "-summary", "%s/.m2d.tmp." M2D_WORST_TAG ".%s", sumdir, base));
    PetscCall(M2dPathPrintf(buf, M2D_NAME_MAX + 1, "-summary", ".m2d.tmp." M2D_WORST_TAG ".%s", base));
  }
  PetscFunctionReturn(0);
}

/* a file (and, for the set, a symbolic link) can really be created in dir */
static PetscErrorCode Probe(const char *dir, const char *opt, PetscBool links)
{
  char path[PETSC_MAX_PATH_LEN];
  int  slot, fd, e = 0;

  PetscFunctionBeginUser;
  PetscCall(M2dPathPrintf(path, sizeof(path), opt, "%s/" M2D_TEMP_PREFIX "tmp-probe.%s", dir, M2dTempTag()));
  PetscCall(M2dTempRecord(path, PETSC_FALSE, &slot));
  fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
  if (fd < 0 || write(fd, "", 1) != 1) e = errno;
  if (fd >= 0 && close(fd) && !e) e = errno;
  unlink(path);
  if (e) {
    M2dTempForget(&slot);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "option %s: cannot create files in '%s': %s", opt, dir, strerror(e));
  }
  if (links && symlink("probe", path)) e = errno;
  unlink(path);
  M2dTempForget(&slot);
  PetscCheck(!e, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "option %s: cannot create symbolic links in '%s' (the output set needs them): %s", opt, dir, strerror(e));
  PetscFunctionReturn(0);
}

/* no output name may be a directory; the set's link must be a link */
static PetscErrorCode CheckPublic(const char *outdir, const char *outname)
{
  char        path[PETSC_MAX_PATH_LEN], ptr[M2D_NAME_MAX + 1];
  struct stat st;

  PetscFunctionBeginUser;
  for (int k = 0; k < NSUFFIX; k++) {
    PetscCall(M2dPathPrintf(path, sizeof(path), "-output_dir", "%s/%s%s", outdir, outname, suffix[k]));
    PetscCheck(lstat(path, &st) || !S_ISDIR(st.st_mode), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -output_name: the output file '%s' is a directory", path);
    PetscCheck(lstat(path, &st) || S_ISREG(st.st_mode) || S_ISLNK(st.st_mode), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -output_name: the output file '%s' exists and is not a regular file or a link (a device, FIFO or socket is never replaced)", path);
  }
  PetscCall(M2dSetPointerName(outname, ptr, sizeof(ptr)));
  PetscCall(M2dPathPrintf(path, sizeof(path), "-output_dir", "%s/%s", outdir, ptr));
  PetscCheck(lstat(path, &st) || S_ISLNK(st.st_mode), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -output_dir: '%s' is not a symbolic link (mortar2d's own name: remove it)", path);
  PetscFunctionReturn(0);
}

/* .m2d.gen.<tag>.<k>.NAME of a dead process that no .m2d.set.NAME points to */
static void RemoveStaleGens(const char *dir)
{
  DIR           *d = opendir(dir);
  struct dirent *e;

  if (!d) return;
  while ((e = readdir(d))) {
    const char *rest, *name;
    char        ptr[PETSC_MAX_PATH_LEN], have[PETSC_MAX_PATH_LEN];
    ssize_t     n;
    if (!M2dTempIsStale(e->d_name, M2D_TEMP_PREFIX "gen.", &rest) || !(name = strchr(rest, '.'))) continue;
    if ((size_t)snprintf(ptr, sizeof(ptr), "%s/" M2D_TEMP_PREFIX "set.%s", dir, name + 1) >= sizeof(ptr)) continue;
    n = readlink(ptr, have, sizeof(have) - 1);
    if (n >= 0) have[n] = 0;
    if (n >= 0 && !strcmp(have, e->d_name)) continue; /* the current set */
    M2dSetRemoveGen(dir, e->d_name);
  }
  closedir(d);
}

static PetscErrorCode CheckSummary(const char *outdir, const char *outname, const char *summary, PetscBool files)
{
  char        why[900], sumdir[PETSC_MAX_PATH_LEN], base[M2D_NAME_MAX + 1];
  const char *bases[2] = {base, NULL};
  struct stat st, so;

  PetscFunctionBeginUser;
  PetscCheck(stat(summary, &st) || !S_ISDIR(st.st_mode), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -summary: '%s' is a directory", summary);
  PetscCheck(!M2dCheckReplaceable(summary, why, sizeof(why)), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -summary: %s", why);
  PetscCall(M2dSetSplitPath(summary, sumdir, sizeof(sumdir), base));
  PetscCheck(strncmp(base, M2D_TEMP_PREFIX, strlen(M2D_TEMP_PREFIX)), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -summary: names starting with '" M2D_TEMP_PREFIX "' are mortar2d's own");
  PetscCheck(!M2dMakeDirs(sumdir, why, sizeof(why)), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "option -summary: %s", why);
  PetscCall(Probe(sumdir, "-summary", PETSC_FALSE));
  if (files && !stat(sumdir, &st) && !stat(outdir, &so) && st.st_dev == so.st_dev && st.st_ino == so.st_ino)
    for (int k = 0; k < NSUFFIX; k++) {
      char f[M2D_NAME_MAX + 1];
      PetscCall(M2dPathPrintf(f, sizeof(f), "-output_name", "%s%s", outname, suffix[k]));
      PetscCheck(strcmp(f, base), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -summary: '%s' is also an output file of -output_name %s", summary, outname);
    }
  M2dTempRemoveStale(sumdir, bases);
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckLocal(const char *outdir, const char *outname, const char *summary, PetscBool files)
{
  char        why[900], b[NSUFFIX][M2D_NAME_MAX + 1];
  const char *bases[NSUFFIX + 1];

  PetscFunctionBeginUser;
  if (files) {
    PetscCheck(!M2dMakeDirs(outdir, why, sizeof(why)), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "option -output_dir: %s", why);
    PetscCall(Probe(outdir, "-output_dir", PETSC_TRUE));
    PetscCall(CheckPublic(outdir, outname));
    for (int k = 0; k < NSUFFIX; k++) {
      PetscCall(M2dPathPrintf(b[k], sizeof(b[k]), "-output_name", "%s%s", outname, suffix[k]));
      bases[k] = b[k];
    }
    bases[NSUFFIX] = NULL;
    M2dTempRemoveStale(outdir, bases);
    RemoveStaleGens(outdir);
  }
  if (summary[0]) PetscCall(CheckSummary(outdir, outname, summary, files));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputCheckPaths(MPI_Comm comm, const char *outdir, const char *outname, const char *summary, PetscBool write_files)
{
  PetscMPIInt    rank;
  PetscErrorCode ierr = 0;
  char           err[1024] = "";

  PetscFunctionBeginUser;
  if (!summary) summary = "";
  PetscCall(CheckName(comm, outname));
  PetscCall(CheckNotCut(comm, "-output_name", outname));
  PetscCall(CheckNotCut(comm, "-output_dir", outdir));
  PetscCall(CheckNotCut(comm, "-summary", summary));
  PetscCheck(!write_files || outdir[0], comm, PETSC_ERR_USER_INPUT, "option -output_dir: the directory name is empty");
  PetscCall(CheckLengths(outdir, outname, summary, write_files)); /* the same on every rank */
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    ierr = CheckLocal(outdir, outname, summary, write_files);
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  PetscCall(M2dCheckCollective(comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}
