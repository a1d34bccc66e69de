/* optfiles.c - see optfiles.h. It runs after MPI_Init, before PetscInitialize.
 *
 * Mirrors PETSc 3.18 (src/sys/objects/options.c): PetscOptionsInsert reads
 * ~/.petscrc, ./.petscrc, ./petscrc (unless -skip_petscrc; missing is fine),
 * then PETSC_OPTIONS, then the command line. A file is read line by line:
 * everything from '#' is a comment, tabs and CR are blanks, the first token is
 * an option (-name, optionally followed by one value) or `alias -a -b`; a
 * token that starts with '"' runs to the next '"'. `-options_file F` inside a
 * file or PETSC_OPTIONS reads F (relative to the current directory, like the
 * command line) when it is met. Names holding ${...} and YAML files are only
 * checked as far as PETSc's expansion and parser need not be repeated: left
 * to PETSc. */
#define _POSIX_C_SOURCE 200809L
#include "optfiles.h"
#include <mpi.h>
#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

/* deeper nesting than this is refused: PETSc 3.18 has no limit, and a file
 * that includes itself ends any PETSc program in a segmentation fault
 * (measured: a.opts holding "-options_file a.opts", signal 11, no message) */
#define MAX_DEPTH 64
#define NAME_LEN  4096
#define M2D_MAX_USER_OPTIONS 500 /* PETSc 3.18: 512 (MAXOPTIONS in options.c) */

#define MAX_FILES 64 /* files remembered for M2dOptionsFilesRead */

static char        read_name[MAX_FILES][NAME_LEN];
static const char *read_list[MAX_FILES];
static int         nread;

typedef struct {
  int   depth;                  /* files being read, outermost first */
  char  name[MAX_DEPTH][NAME_LEN];
  dev_t dev[MAX_DEPTH];
  ino_t ino[MAX_DEPTH];
} Scan;

static int Fail(const char *fmt, ...);

/* every option name met (without the '-'), case-insensitively once: where it
 * was given (file: its name, NULL for the command line and PETSC_OPTIONS) */
typedef struct {
  char *name, *file;
} Given;
static Given *given;
static int    ngiven, capgiven;

static int Record(const char *key, const char *file)
{
  const char *name = key + (key[1] == '-' ? 2 : 1);

  for (int i = 0; i < ngiven; i++)
    if (!strcasecmp(given[i].name, name)) {
      if (!file) { /* typed by the user as well */
        free(given[i].file);
        given[i].file = NULL;
      }
      return 0;
    }
  if (ngiven == capgiven) {
    Given *g = realloc(given, (size_t)(capgiven = 2 * capgiven + 64) * sizeof(Given));
    if (!g) return Fail("out of memory reading the options");
    given = g;
  }
  given[ngiven].name = strdup(name);
  given[ngiven].file = file ? strdup(file) : NULL;
  if (!given[ngiven].name || (file && !given[ngiven].file)) return Fail("out of memory reading the options");
  ngiven++;
  return 0;
}

int M2dOptionsGivenCount(void)
{
  return ngiven;
}

const char *M2dOptionsGiven(int i, const char **file)
{
  if (file) *file = given[i].file;
  return given[i].name;
}

static int Fail(const char *fmt, ...)
{
  int     rank = 0;
  va_list ap;

  if (MPI_Comm_rank(MPI_COMM_WORLD, &rank) || rank) return 1; /* each rank finds the same error */
  fprintf(stderr, "mortar2d: error: ");
  va_start(ap, fmt);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fprintf(stderr, "\n");
  fflush(stderr);
  return 1;
}

/* PetscOptionsValidKey: "-" or "--", then a letter, and not a number such as -1e5 or -inf */
static int ValidKey(const char *key)
{
  char *end;

  if (!key || key[0] != '-') return 0;
  if (key[1] == '-') key++;
  if (!isalpha((unsigned char)key[1])) return 0;
  (void)strtod(key, &end);
  if (end != key && !(*end == '_' || isalnum((unsigned char)*end))) return 0;
  return 1;
}

/* PetscTokenFind with blank separators: the next token of *cur (modified in
 * place), NULL at the end; a token that starts with '"' ends at the next '"' */
static char *NextToken(char **cur)
{
  char *p = *cur, *tok, sep = ' ';

  if (!p || !*p) return NULL;
  tok = p;
  if (*p == '"') {
    sep = '"';
    tok++;
    p++;
  }
  for (;; p++) {
    if (*p == sep) {
      *p++ = 0;
      while (*p == ' ') p++;
      *cur = p;
      break;
    }
    if (!*p) {
      *cur = NULL;
      break;
    }
  }
  return tok;
}

static int EndsWith(const char *s, const char *suffix)
{
  size_t n = strlen(s), m = strlen(suffix);
  return n >= m && !strcmp(s + n - m, suffix);
}

static int ScanFile(Scan *sc, const char *given, int require, const char *where);

/* the -options_file / -options_file_yaml entries of a string (PETSC_OPTIONS);
 * PetscOptionsInsertString takes the token after them as the file name */
static int ScanString(Scan *sc, const char *text, const char *where)
{
  char *buf = strdup(text), *cur = buf, *tok;
  int   bad = 0;

  if (!buf) return Fail("out of memory reading the options %s", where);
  while (!bad && (tok = NextToken(&cur))) {
    int file = !strcasecmp(tok, "-options_file"), yaml = !strcasecmp(tok, "-options_file_yaml");
    if (ValidKey(tok) && (bad = Record(tok, NULL))) break;
    if (!file && !yaml) continue;
    tok = NextToken(&cur);
    if (!tok) bad = Fail("option %s %s: missing file name", file ? "-options_file" : "-options_file_yaml", where);
    else bad = ScanFile(sc, tok, file ? 1 : 2, where);
  }
  free(buf);
  return bad;
}

/* one line of an options file, checked as PetscOptionsInsertFilePetsc does;
 * an -options_file(_yaml) line gives its value in *include (*yaml: which) */
static int ScanLine(const char *file, int line, char *text, char **include, int *yaml)
{
  char *cur = text, *t[4], *c;
  int   alias = 0;

  *include = NULL;
  *yaml    = 0;
  if ((c = strchr(text, '#'))) *c = 0;
  for (c = text; *c; c++)
    if (*c == '\t' || *c == '\r' || *c == '\n') *c = ' ';
  t[0] = NextToken(&cur);
  if (t[0] && !t[0][0]) t[0] = NextToken(&cur); /* the line began with blanks */
  if (!t[0]) return 0;
  for (int i = 1; i < 4; i++) t[i] = NextToken(&cur);
  if (t[0][0] == '-') {
    if (!ValidKey(t[0])) return Fail("options file '%s' line %d: invalid option '%s'", file, line, t[0]);
    if (t[1] && ValidKey(t[1])) return Fail("options file '%s' line %d: two options on one line (%s %s)", file, line, t[0], t[1]);
    if (Record(t[0], file)) return 1;
    if (!strcasecmp(t[0], "-options_file") || !strcasecmp(t[0], "-options_file_yaml")) {
      if (!t[1]) return Fail("options file '%s' line %d: %s without a file name", file, line, t[0]);
      *include = t[1];
      *yaml    = t[0][13] != 0; /* -options_file_yaml */
    }
  } else if (!strcasecmp(t[0], "alias")) {
    alias = 1;
    if (!ValidKey(t[1]) || !ValidKey(t[2])) return Fail("options file '%s' line %d: alias needs two options (alias -new -old)", file, line);
  } else {
    for (c = t[0]; *c; c++) /* a binary file: no control bytes on the one error line */
      if ((unsigned char)*c < 32 || (unsigned char)*c >= 127) *c = '?';
    if (strlen(t[0]) > 60) strcpy(t[0] + 57, "...");
    return Fail("options file '%s' line %d: '%s' is not an option (options start with '-')", file, line, t[0]);
  }
  if (alias ? t[3] : t[2]) return Fail("options file '%s' line %d: extra token '%s'", file, line, alias ? t[3] : t[2]);
  return 0;
}

static int ScanFileLines(Scan *sc, FILE *fp, const char *file)
{
  char  *text = NULL, where[NAME_LEN + 64];
  size_t cap  = 0;
  int    line = 0, bad = 0;
  ssize_t n;

  while (!bad && (n = getline(&text, &cap, fp)) >= 0) {
    char *include = NULL;
    int   yaml    = 0;
    line++;
    /* PETSc reads a line only up to a NUL byte: the rest would be dropped unseen */
    if (memchr(text, 0, (size_t)n)) bad = Fail("options file '%s' line %d: a NUL byte (PETSc would ignore the rest of the line): is it a text file?", file, line);
    else bad = ScanLine(file, line, text, &include, &yaml);
    if (!bad && include) {
      snprintf(where, sizeof(where), "in '%s' line %d", file, line);
      bad = ScanFile(sc, include, yaml ? 2 : 1, where);
    }
  }
  free(text);
  return bad;
}

/* require: 0 the file may be missing (petscrc), 1 required, 2 required YAML (existence only) */
static int ScanFile(Scan *sc, const char *given, int require, const char *where)
{
  char        name[NAME_LEN], chain[2 * NAME_LEN] = "";
  struct stat st;
  FILE       *fp;
  int         bad;

  if (strstr(given, "${")) return 0; /* PETSc expands ${PETSC_DIR} and the like: its business */
  if (strlen(given) >= sizeof(name)) return Fail("options file name %s is too long", where);
  for (size_t i = 0; i <= strlen(given); i++) name[i] = given[i] == '\\' ? '/' : given[i]; /* PetscFixFilename */
  if (EndsWith(name, ":yaml")) { /* PETSc's "read it as YAML" suffix */
    name[strlen(name) - 5] = 0;
    if (require) require = 2;
  }
  if (stat(name, &st)) {
    if (!require) return 0;
    return Fail("options file '%s' (named %s) cannot be read: %s", name, where, strerror(errno));
  }
  if (S_ISDIR(st.st_mode)) return require ? Fail("options file '%s' (named %s) is a directory", name, where) : 0;
  /* /dev/zero never ends and a FIFO blocks until a writer comes: both hung the run */
  if (!S_ISREG(st.st_mode)) return require ? Fail("options file '%s' (named %s) is not a regular file (%s)", name, where, S_ISCHR(st.st_mode) ? "a character device" : S_ISFIFO(st.st_mode) ? "a FIFO" : "a device or socket") : 0;
  for (int d = 0; d < sc->depth; d++) {
    if (sc->dev[d] != st.st_dev || sc->ino[d] != st.st_ino) continue;
    for (int k = d; k < sc->depth; k++) {
      strncat(chain, sc->name[k], sizeof(chain) - strlen(chain) - 1);
      strncat(chain, " -> ", sizeof(chain) - strlen(chain) - 1);
    }
    strncat(chain, name, sizeof(chain) - strlen(chain) - 1);
    return Fail("options file '%s' includes itself: %s", name, chain);
  }
  if (nread < MAX_FILES) { /* an input the outputs may not name (outputpaths.h) */
    snprintf(read_name[nread], NAME_LEN, "%s", name);
    read_list[nread] = read_name[nread];
    nread++;
  }
  if (sc->depth == MAX_DEPTH) return Fail("options file '%s': options files nested more than %d deep", name, MAX_DEPTH);
  if (require == 2 || EndsWith(name, ".yaml") || EndsWith(name, ".yml") || EndsWith(name, ".json")) {
    if (!(fp = fopen(name, "r"))) return Fail("options file '%s' (named %s) cannot be read: %s", name, where, strerror(errno));
    fclose(fp);
    return 0; /* YAML: PETSc's own parser */
  }
  if (!(fp = fopen(name, "r"))) return require ? Fail("options file '%s' (named %s) cannot be read: %s", name, where, strerror(errno)) : 0;
  {
    char head[7] = "";
    size_t n = fread(head, 1, 6, fp);
    head[n] = 0;
    if (!strncmp(head, "%YAML ", 6) || !strncmp(head, "---", 3)) { /* PETSc reads it as YAML */
      fclose(fp);
      return 0;
    }
    rewind(fp);
  }
  snprintf(sc->name[sc->depth], NAME_LEN, "%s", name);
  sc->dev[sc->depth] = st.st_dev;
  sc->ino[sc->depth] = st.st_ino;
  sc->depth++;
  bad = ScanFileLines(sc, fp, name);
  sc->depth--;
  fclose(fp);
  return bad;
}

/* -skip_petscrc on the command line (PetscOptionsProcessPrecedentFlags): the last one wins */
static int SkipPetscrc(int argc, char **argv)
{
  int skip = 0;

  for (int a = 1; a < argc; a++) {
    const char *v;
    if (!ValidKey(argv[a]) || strcasecmp(argv[a], "-skip_petscrc")) continue;
    v    = (a + 1 < argc && argv[a + 1][0] && argv[a + 1][0] != '-') ? argv[a + 1] : NULL;
    skip = !v || !(!strcasecmp(v, "0") || !strcasecmp(v, "false") || !strcasecmp(v, "no") || !strcasecmp(v, "off"));
  }
  return skip;
}

int M2dOptionsFilesCheck(int argc, char **argv)
{
  static Scan sc; /* large: not on the stack */
  const char *env;
  int         bad = 0;

  sc.depth = 0;
  if (!SkipPetscrc(argc, argv)) {
    const char *home = getenv("HOME");
    if (home && home[0]) {
      char rc[NAME_LEN];
      snprintf(rc, sizeof(rc), "%s/.petscrc", home);
      bad = ScanFile(&sc, rc, 0, "as ~/.petscrc");
    }
    if (!bad) bad = ScanFile(&sc, ".petscrc", 0, "as ./.petscrc");
    if (!bad) bad = ScanFile(&sc, "petscrc", 0, "as ./petscrc");
  }
  env = getenv("PETSC_OPTIONS");
  if (!bad && env && env[0]) bad = ScanString(&sc, env, "in PETSC_OPTIONS");
  /* the command line, as PetscOptionsInsertArgs walks it: a key, then its value unless the next is a key */
  for (int a = 1; !bad && a < argc;) {
    int file = !strcasecmp(argv[a], "-options_file"), yaml = !strcasecmp(argv[a], "-options_file_yaml");
    if (!ValidKey(argv[a])) a++;
    else if ((bad = Record(argv[a], NULL))) break;
    else if (file || yaml) {
      if (a + 1 >= argc || argv[a + 1][0] == '-') bad = Fail("option %s: missing file name", argv[a]);
      else bad = ScanFile(&sc, argv[a + 1], file ? 1 : 2, "on the command line");
      a += 2;
    } else a += (a + 1 < argc && !ValidKey(argv[a + 1])) ? 2 : 1;
  }
  /* PETSc 3.18's table holds 512 names and stops PetscInitialize with a
   * 500-line trace past them; the program puts up to 12 of its own there */
  if (!bad && ngiven > M2D_MAX_USER_OPTIONS) bad = Fail("%d different options given (command line, options files, PETSC_OPTIONS, petscrc): PETSc holds at most %d of them for this program; give fewer", ngiven, M2D_MAX_USER_OPTIONS);
  return bad;
}

int M2dOptionsFilesRead(const char *const **names)
{
  *names = read_list;
  return nread;
}
