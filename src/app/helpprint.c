/* helpprint.c - -help: the program's options first, by job (helpprint.h) */
#define _POSIX_C_SOURCE 200809L /* strdup */
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "helpprint.h"

#define RULE "----------------------------------------\n"

typedef struct {
  char  *title; /* NULL: text before the first section (PETSc's banner) */
  char  *text;
  size_t len, cap;
} HelpChunk;

static HelpChunk *chunks;
static int        nchunk, capchunk, printed;
/* PETSc prints the type lists of -ksp_type, -pc_type, ... not through
 * PetscHelpPrintf but with PetscFPrintf to stdout (PetscOptionsFList in 3.18):
 * PetscVFPrintf is taken too, and its text on stdout belongs to the section
 * being printed */
static PetscErrorCode (*petsc_vfprintf)(FILE *, const char[], va_list);

/* the program's sections, in the order they are printed (a title prefix each) */
static const char *const job_order[] = {
  "mortar2d: scene and mesh",   "mortar2d: materials",  "Material of body '",        "mortar2d: loads and supports", "mortar2d: load history", "mortar2d: load stage", "mortar2d: contact",
  "mortar2d: solver paths",     "mortar2d: checks",     "mortar2d: error estimate", "mortar2d: adaptive meshes",    "mortar2d: output",
  "mortar2d", /* any other section of the program */
};

static int IsOurs(const char *title)
{
  return title && (!strncmp(title, "mortar2d", 8) || !strncmp(title, "Material of body '", 18));
}

static int NewChunk(const char *title)
{
  HelpChunk *c;

  if (nchunk == capchunk) {
    int        cap  = capchunk ? 2 * capchunk : 64;
    HelpChunk *more = (HelpChunk *)realloc(chunks, (size_t)cap * sizeof(*chunks));
    if (!more) return 1;
    chunks   = more;
    capchunk = cap;
  }
  c = &chunks[nchunk++];
  *c = (HelpChunk){NULL, NULL, 0, 0};
  if (title) c->title = strdup(title);
  return 0;
}

static int Append(const char *s, size_t n)
{
  HelpChunk *c;

  if (!nchunk && NewChunk(NULL)) return 1;
  c = &chunks[nchunk - 1];
  if (c->len + n + 1 > c->cap) {
    size_t cap  = 2 * (c->len + n + 1);
    char  *more = (char *)realloc(c->text, cap);
    if (!more) return 1;
    c->text = more;
    c->cap  = cap;
  }
  memcpy(c->text + c->len, s, n);
  c->len += n;
  c->text[c->len] = 0;
  return 0;
}

/* format (PETSc's formatting: a real 1 prints as "1.") into a new buffer, or NULL */
static char *Format(const char format[], va_list ap)
{
  for (size_t size = 4096, full = 0;; size = full + 1) {
    char   *buf = (char *)malloc(size);
    va_list aq;
    if (!buf) return NULL;
    full = 0;
    va_copy(aq, ap);
    if (PetscVSNPrintf(buf, size, format, &full, aq)) full = 0;
    va_end(aq);
    if (full < size) return buf;
    free(buf);
  }
}

/* PETSc calls it for every piece of help text; a section starts with RULE and "TITLE:" */
static PetscErrorCode Collect(MPI_Comm comm, const char format[], ...)
{
  va_list ap;
  int     init = 0, rank = 0;
  char   *buf;

  MPI_Initialized(&init);
  if (init) MPI_Comm_rank(comm, &rank);
  if (rank) return 0;
  va_start(ap, format);
  buf = Format(format, ap);
  va_end(ap);
  if (!buf) return 0;
  if (!strncmp(buf, RULE, strlen(RULE))) {
    const char *t = buf + strlen(RULE);
    size_t      k = strcspn(t, "\n");
    char        title[256];
    if (k >= sizeof(title)) k = sizeof(title) - 1;
    memcpy(title, t, k);
    title[k] = 0;
    if (k > 0 && title[k - 1] == ':') title[k - 1] = 0;
    if (NewChunk(title)) {
      free(buf);
      return 0;
    }
  }
  (void)Append(buf, strlen(buf));
  free(buf);
  return 0;
}

/* PETSc's text on stdout, into the current section (PetscFPrintf prints on rank 0 only) */
static PetscErrorCode CollectStdout(FILE *fd, const char format[], va_list ap)
{
  char *buf;

  if (fd != stdout && fd != PETSC_STDOUT) return petsc_vfprintf(fd, format, ap);
  if ((buf = Format(format, ap))) (void)Append(buf, strlen(buf));
  free(buf);
  return 0;
}

/* PETSc's printers back */
static void Restore(void)
{
  if (PetscHelpPrintf == Collect) PetscHelpPrintf = PetscHelpPrintfDefault;
  if (PetscVFPrintf == CollectStdout) PetscVFPrintf = petsc_vfprintf;
}

static void Free(void)
{
  for (int i = 0; i < nchunk; i++) {
    free(chunks[i].title);
    free(chunks[i].text);
  }
  free(chunks);
  chunks   = NULL;
  nchunk   = capchunk = 0;
}

/* at exit, what no one printed (PETSc exits inside PetscInitialize on -help intro) */
static void AtExit(void)
{
  (void)signal(SIGPIPE, SIG_IGN); /* stdout closed by its reader (mortar2d -help intro | head) */
  Restore();
  for (int i = 0; i < nchunk && !printed; i++)
    if (chunks[i].text) fputs(chunks[i].text, stdout);
  fflush(stdout);
  Free();
}

int M2dHelpCapture(void)
{
  PetscHelpPrintf = Collect;
  petsc_vfprintf  = PetscVFPrintf;
  PetscVFPrintf   = CollectStdout;
  (void)atexit(AtExit);
  return 0;
}

int M2dHelpArgs(int *argc, char ***argv)
{
  static char *args[1024];
  int          n = *argc, petsc = 0, help = 0;

  for (int i = 1; i < n; i++) {
    petsc = petsc || !strcmp((*argv)[i], "-help_petsc");
    help  = help || !strcmp((*argv)[i], "-help");
  }
  if (!petsc || help || n + 2 > (int)(sizeof(args) / sizeof(args[0]))) return 0;
  for (int i = 0; i < n; i++) args[i] = (*argv)[i];
  args[n]     = (char *)"-help";
  args[n + 1] = NULL;
  *argc       = n + 1;
  *argv       = args;
  return 0;
}

void M2dHelpDiscard(void)
{
  Restore();
  printed = 1;
  Free();
}

PetscErrorCode M2dHelpRelease(void)
{
  PetscFunctionBeginUser;
  Restore();
  for (int i = 0; i < nchunk; i++)
    if (chunks[i].text) PetscCall(PetscFPrintf(PETSC_COMM_SELF, PETSC_STDOUT, "%s", chunks[i].text));
  printed = 1;
  Free();
  PetscFunctionReturn(0);
}

PetscErrorCode M2dHelpPrint(MPI_Comm comm, const char *intro)
{
  PetscBool   petsc = PETSC_FALSE;
  PetscMPIInt rank;
  const int   njob = (int)(sizeof(job_order) / sizeof(job_order[0]));
  char       *done;

  PetscFunctionBeginUser;
  Restore();
  PetscCall(PetscOptionsHasName(NULL, NULL, "-help_petsc", &petsc));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  printed = 1;
  if (rank) PetscFunctionReturn(0);
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, PETSC_STDOUT, "%s", intro));
  PetscCall(PetscCalloc1(nchunk + 1, &done));
  for (int j = 0; j < njob; j++)
    for (int i = 0; i < nchunk; i++)
      if (!done[i] && IsOurs(chunks[i].title) && !strncmp(chunks[i].title, job_order[j], strlen(job_order[j]))) {
        PetscCall(PetscFPrintf(PETSC_COMM_SELF, PETSC_STDOUT, "%s", chunks[i].text));
        done[i] = 1;
      }
  if (petsc) {
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, PETSC_STDOUT, RULE "PETSc's own options (the solvers as this scene configures them; -snes_* act on the active set):\n"));
    for (int i = 0; i < nchunk; i++) {
      const char *text = chunks[i].text;
      if (text && !chunks[i].title) text = strstr(text, RULE); /* the banner without the intro printed above */
      if (!done[i] && text) PetscCall(PetscFPrintf(PETSC_COMM_SELF, PETSC_STDOUT, "%s", text));
    }
  } else {
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, PETSC_STDOUT, RULE "PETSc's own options (-ksp_*, -pc_*, -snes_*, -log_view, ...): mortar2d -help_petsc [scene options]\n"));
  }
  PetscCall(PetscFree(done));
  Free();
  PetscFunctionReturn(0);
}
