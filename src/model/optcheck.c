/* optcheck.c - see optcheck.h. */
#include "optcheck.h"
#include "optfiles.h"
#include "scene.h"
#include <ctype.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_KNOWN (2 * M2D_MAX_BODIES + 256) /* the program's own, and -A_E, -A_nu of every body */
#define NAME_LEN  192

/* the program's options, recorded as they are read (options.c) */
static char known[MAX_KNOWN][NAME_LEN];
static int  nknown;

/* prefixes of the options PETSc's objects read when they are configured (the
 * first check leaves them to the second) */
static const char *const petsc_prefix[] = {"ksp_", "pc_", "snes_", "mat_", "matproduct_", "fieldsplit_", "redundant_", "iterative_", "dual_", "sub_", "mg_", "dm_", "petscpartitioner_", "petscsection_", "vec_", "is_", "sf_", "viewer_", "draw_", "log_", "malloc", "memory_", "info", "help", "version", "options_", "on_error_", "objects_", "fp_trap", "debugger", "start_in_debugger", "stop_for_debugger", "no_signal_handler", "error_output_", "check_pointer_intensity", "history", "nox", "display", "petsc_", "skip_petscrc", "use_gpu_aware_mpi", "mpi_", "device_", "default_device_type", "root_device_context_", "saws_", "citations", "tmp", "shared_tmp", "not_shared_tmp", "get_total_flops", "vecscatter_", "hdf5_"};

/* PETSc options users type most, for "did you mean" and as names known to
 * PETSc (unread when the solvers are configured: no effect on that path) */
static const char *const petsc_common[] = {
  "ksp_type", "ksp_rtol", "ksp_atol", "ksp_divtol", "ksp_max_it", "ksp_monitor", "ksp_monitor_true_residual", "ksp_monitor_short", "ksp_converged_reason", "ksp_view", "ksp_gmres_restart", "ksp_norm_type", "ksp_pc_side", "ksp_error_if_not_converged", "ksp_initial_guess_nonzero", "ksp_converged_rate",
  "pc_type", "pc_factor_mat_solver_type", "pc_factor_mat_ordering_type", "pc_factor_shift_type", "pc_factor_shift_amount", "pc_factor_levels", "pc_factor_fill", "pc_fieldsplit_type", "pc_fieldsplit_schur_fact_type", "pc_fieldsplit_schur_precondition", "pc_fieldsplit_detect_saddle_point", "pc_fieldsplit_block_size", "pc_hypre_type", "pc_gamg_threshold", "pc_gamg_agg_nsmooths", "pc_mg_levels", "pc_asm_overlap", "pc_bjacobi_blocks", "pc_use_amat",
  "snes_type", "snes_rtol", "snes_atol", "snes_stol", "snes_max_it", "snes_max_funcs", "snes_monitor", "snes_converged_reason", "snes_view", "snes_linesearch_type", "snes_linesearch_monitor", "snes_linesearch_max_it", "snes_error_if_not_converged", "snes_lag_jacobian", "snes_lag_preconditioner", "snes_ksp_ew", "snes_vi_monitor", "snes_test_jacobian",
  "mat_type", "mat_view", "mat_mumps_icntl_4", "mat_mumps_icntl_7", "mat_mumps_icntl_8", "mat_mumps_icntl_13", "mat_mumps_icntl_14", "mat_mumps_icntl_24", "mat_mumps_icntl_28", "mat_mumps_icntl_29", "mat_mumps_cntl_1", "mat_mumps_cntl_3", "mat_mumps_use_omp_threads",
  "vec_type", "vec_view", "dm_view", "dm_plex_check_all", "petscpartitioner_type", "petscpartitioner_view",
  "log_view", "log_view_memory", "log_trace", "log_all", "malloc_dump", "malloc_debug", "malloc_view", "malloc_test", "memory_view", "info", "help", "version", "options_left", "options_view", "options_monitor", "options_file", "options_file_yaml", "skip_petscrc", "on_error_abort", "on_error_attach_debugger", "start_in_debugger", "fp_trap", "no_signal_handler", "objects_dump", "viewer_binary_skip_info"};

/* unread when the solvers are configured, and read later: by PetscFinalize
 * (PETSc 3.18's pinit.c; the other -log_*, -malloc*, -info, -options_* names
 * are read by PetscInitialize: unread, they are typos such as -log_vie) */
static const char *const finalize_names[] = {"options_left", "options_view", "citations", "mpidump", "get_total_flops", "log_summary", "log_all", "log", "log_mpe", "nox", "nox_warning", "x_virtual", "saw_options", "malloc_info", "malloc_view", "malloc_view_threshold", "malloc_test", "malloc_debug", "malloc_dump", "objects_dump", "memory_view", "no_signal_handler", "mpi_linear_solver_server", "textbelt", "tellmycell"};

/* read later (at a factorization) or only on some rank counts (the
 * partitioner: not on one rank): unread is not an error */
static const char *const read_later_prefix[] = {"mat_superlu", "mat_umfpack", "mat_cholmod", "mat_klu", "mat_strumpack", "mat_pastix", "mat_mkl_", "petscpartitioner_"};

/* prefixes the run reads after the solvers are configured (M2dOptionsReadLater) */
#define MAX_LATER 16
static char later[MAX_LATER][NAME_LEN];
static int  nlater;

/* names of options with no effect already noted on stdout (set by an options file) */
#define MAX_NOTED 64
static char noted[MAX_NOTED][NAME_LEN];
static int  nnoted;

PetscErrorCode M2dOptionsKnow(const char *name)
{
  PetscFunctionBeginUser;
  if (name[0] == '-') name++;
  for (int i = 0; i < nknown; i++)
    if (!strcasecmp(known[i], name)) PetscFunctionReturn(0);
  PetscCheck(nknown < MAX_KNOWN, PETSC_COMM_SELF, PETSC_ERR_PLIB, "more than %d options: raise MAX_KNOWN in optcheck.c", MAX_KNOWN);
  PetscCall(PetscStrncpy(known[nknown++], name, NAME_LEN));
  PetscFunctionReturn(0);
}

static PetscBool Known(const char *name)
{
  for (int i = 0; i < nknown; i++)
    if (!strcasecmp(known[i], name)) return PETSC_TRUE;
  return PETSC_FALSE;
}

static PetscBool InList(const char *name, const char *const list[], size_t n, PetscBool prefix)
{
  for (size_t i = 0; i < n; i++)
    if (prefix ? !strncasecmp(name, list[i], strlen(list[i])) : !strcasecmp(name, list[i])) return PETSC_TRUE;
  return PETSC_FALSE;
}
#define IN_LIST(name, list, prefix) InList(name, list, sizeof(list) / sizeof(list[0]), prefix)

/* PETSc's MUMPS interface reads -mat_mumps_icntl_N (N = 1..60, MUMPS 5.5), -mat_mumps_cntl_N
 * (N = 1..15) and -mat_mumps_use_omp_threads at the symbolic factorization */
static PetscBool MumpsName(const char *name)
{
  const char *n = NULL;
  char       *end;
  long        k, max = 0;

  if (!strncasecmp(name, "mat_mumps_icntl_", 16)) n = name + 16, max = 60;
  else if (!strncasecmp(name, "mat_mumps_cntl_", 15)) n = name + 15, max = 15;
  else return (PetscBool)!strcasecmp(name, "mat_mumps_use_omp_threads");
  k = strtol(n, &end, 10);
  return (PetscBool)(end != n && !*end && k >= 1 && k <= max);
}

/* the prefix of a solver's options: a PCFIELDSPLIT split's, -fieldsplit_NAME_rest,
 * or the program's own solvers' (-iterative_rest: iterative.h, -dual_rest:
 * dual.h): its length (0: none) */
static size_t SplitPrefix(const char *name)
{
  static const char *const own[] = {"iterative_", "dual_", "redundant_", "sub_"}; /* the last two: PCREDUNDANT's and PCBJACOBI's/PCASM's inner solvers */
  const char              *u;
  for (size_t i = 0; i < sizeof(own) / sizeof(own[0]); i++)
    if (!strncasecmp(name, own[i], strlen(own[i]))) return strlen(own[i]);
  if (strncasecmp(name, "fieldsplit_", 11) || !(u = strchr(name + 11, '_'))) return 0;
  return (size_t)(u + 1 - name);
}

/* optimal string alignment distance (Levenshtein with transpositions), case-insensitive */
static int Distance(const char *a, const char *b)
{
  int la = (int)strlen(a), lb = (int)strlen(b), d[3][NAME_LEN + 1];

  if (la >= NAME_LEN || lb >= NAME_LEN) return 1 << 20;
  for (int j = 0; j <= lb; j++) d[0][j] = j;
  for (int i = 1; i <= la; i++) {
    int *cur = d[i % 3], *prev = d[(i + 2) % 3], *pprev = d[(i + 1) % 3];
    cur[0] = i;
    for (int j = 1; j <= lb; j++) {
      int cost = tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]);
      int v    = PetscMin(PetscMin(prev[j] + 1, cur[j - 1] + 1), prev[j - 1] + cost);
      if (i > 1 && j > 1 && tolower((unsigned char)a[i - 1]) == tolower((unsigned char)b[j - 2]) && tolower((unsigned char)a[i - 2]) == tolower((unsigned char)b[j - 1])) v = PetscMin(v, pprev[j - 2] + 1);
      cur[j] = v;
    }
  }
  return d[la % 3][lb];
}

static void Closest(const char *name, const char **best, int *dbest)
{
  for (int i = 0; i < nknown; i++) {
    int d = Distance(name, known[i]);
    if (d < *dbest) *dbest = d, *best = known[i];
  }
  for (size_t i = 0; i < sizeof(petsc_common) / sizeof(petsc_common[0]); i++) {
    int d = Distance(name, petsc_common[i]);
    if (d < *dbest) *dbest = d, *best = petsc_common[i];
  }
}

PetscErrorCode M2dOptionsSuggest(const char *name, char *out, size_t len)
{
  const char *best = NULL, *rest = name;
  int         dbest = 1 << 20;
  size_t      split = SplitPrefix(name);

  PetscFunctionBeginUser;
  if (name[0] == '-') name++, rest = name;
  out[0] = 0;
  if (split) rest = name + split; /* -fieldsplit_u_pc_tpye: match pc_tpye, keep the split's prefix */
  Closest(rest, &best, &dbest);
  if (best && dbest > 0 && dbest <= (strlen(rest) <= 5 ? 1 : (int)strlen(rest) / 3)) PetscCall(PetscSNPrintf(out, len, "-%.*s%s", (int)(rest - name), name, best));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsReadLater(const char *prefix)
{
  PetscFunctionBeginUser;
  if (prefix[0] == '-') prefix++;
  PetscCheck(nlater < MAX_LATER, PETSC_COMM_SELF, PETSC_ERR_PLIB, "more than %d prefixes read later: raise MAX_LATER in optcheck.c", MAX_LATER);
  PetscCall(PetscStrncpy(later[nlater++], prefix, NAME_LEN));
  PetscFunctionReturn(0);
}

static PetscBool Later(const char *name)
{
  for (int i = 0; i < nlater; i++)
    if (!strncasecmp(name, later[i], strlen(later[i]))) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* a viewer (-X_view, -X_view_Y), a monitor or a converged-reason report:
 * asks to show what happens, never changes it */
static PetscBool Display(const char *name)
{
  const char *v = strstr(name, "_view");
  return (PetscBool)((v && (v[5] == 0 || v[5] == '_')) || strstr(name, "_converged_reason") || strstr(name, "_monitor"));
}

/* whether the user gave name (no '-'), and where: *file NULL when typed
 * (command line, PETSC_OPTIONS), else the options file */
static PetscBool Given(const char *name, const char **file)
{
  for (int i = 0; i < M2dOptionsGivenCount(); i++)
    if (!strcasecmp(M2dOptionsGiven(i, file), name)) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* an option given with no effect in this run: an error when typed, a note
 * on stdout (once) when an options file set it (the command line may have
 * changed what the file's scene needs); collective, the same on every rank */
static PetscErrorCode NoEffect(MPI_Comm comm, const char *name, const char *file, const char *why)
{
  PetscFunctionBeginUser;
  PetscCheck(file, comm, PETSC_ERR_USER_INPUT, "option -%s has no effect %s", name, why);
  for (int i = 0; i < nnoted; i++)
    if (!strcasecmp(noted[i], name)) PetscFunctionReturn(0);
  if (nnoted < MAX_NOTED) PetscCall(PetscStrncpy(noted[nnoted++], name, NAME_LEN));
  PetscCall(PetscPrintf(comm, "note: option -%s (set in %s) has no effect %s\n", name, file, why));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsNoEffect(MPI_Comm comm, const char *names, const char *why, ...)
{
  char    list[1024], text[512], *tok, *save = NULL;
  va_list ap;

  PetscFunctionBeginUser;
  va_start(ap, why);
  vsnprintf(text, sizeof(text), why, ap);
  va_end(ap);
  PetscCall(PetscStrncpy(list, names, sizeof(list)));
  for (tok = strtok_r(list, " ", &save); tok; tok = strtok_r(NULL, " ", &save)) {
    size_t n = strlen(tok);
    if (tok[0] == '-') tok++, n--;
    if (tok[n - 1] != '*') { /* one of the program's options */
      const char *file;
      if (Given(tok, &file)) PetscCall(NoEffect(comm, tok, file, text));
      continue;
    }
    for (int i = 0; i < M2dOptionsGivenCount(); i++) { /* a family of PETSc's */
      const char *file, *name = M2dOptionsGiven(i, &file);
      if (strncasecmp(name, tok, n - 1) || Display(name) || Known(name) || Later(name)) continue;
      PetscCall(NoEffect(comm, name, file, text));
    }
  }
  PetscFunctionReturn(0);
}

/* rank 0's unread options that bad() flags and no rank has read, in rank 0's
 * order, copied to (*out)[0..*nout-1] (PetscFree it); collective */
static PetscErrorCode AllUnread(MPI_Comm comm, PetscBool (*bad)(const char *, void *), void *ctx, PetscInt *nout, char (**out)[NAME_LEN])
{
  PetscInt    n = 0;
  char      **names = NULL, **values = NULL, name[NAME_LEN];
  PetscMPIInt rank;
  int         count = 0;

  PetscFunctionBeginUser;
  *nout = 0;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  if (rank == 0)
    for (PetscInt i = 0; i < n; i++) count += bad(names[i], ctx) ? 1 : 0;
  PetscCallMPI(MPI_Bcast(&count, 1, MPI_INT, 0, comm));
  PetscCall(PetscMalloc1(count + 1, out));
  for (PetscInt i = 0, k = 0; k < count; i++) {
    PetscBool used = PETSC_FALSE;
    int       any;
    if (rank == 0) {
      while (!bad(names[i], ctx)) i++;
      PetscCall(PetscStrncpy(name, names[i], sizeof(name)));
    }
    k++;
    PetscCallMPI(MPI_Bcast(name, (int)sizeof(name), MPI_CHAR, 0, comm));
    PetscCall(PetscOptionsUsed(NULL, name, &used));
    any = used ? 1 : 0;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, comm));
    if (!any) PetscCall(PetscStrncpy((*out)[(*nout)++], name, NAME_LEN));
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
  PetscFunctionReturn(0);
}

typedef struct {
  PetscBool (*skip)(const char *, void *);
  void *ctx;
} UnknownCtx;

static PetscBool IsUnknown(const char *name, void *ctx)
{
  UnknownCtx *u = (UnknownCtx *)ctx;
  if (Known(name) || IN_LIST(name, petsc_prefix, PETSC_TRUE)) return PETSC_FALSE;
  return (PetscBool)!(u->skip && u->skip(name, u->ctx));
}

static PetscErrorCode RaiseUnknown(MPI_Comm comm, const char *name, const char *what)
{
  char best[NAME_LEN + 1];

  PetscFunctionBeginUser;
  PetscCall(M2dOptionsSuggest(name, best, sizeof(best)));
  if (best[0]) SETERRQ(comm, PETSC_ERR_USER_INPUT, "option -%s is %s (did you mean %s?)", name, what, best);
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "option -%s is %s (-help lists the options)", name, what);
}

PetscErrorCode M2dOptionsCheckUnknown(MPI_Comm comm, PetscBool (*skip)(const char *name, void *ctx), void *ctx)
{
  UnknownCtx u = {skip, ctx};
  PetscInt   n;
  char (*unread)[NAME_LEN];
  PetscErrorCode ierr = 0;

  PetscFunctionBeginUser;
  PetscCall(AllUnread(comm, IsUnknown, &u, &n, &unread));
  if (n) ierr = RaiseUnknown(comm, unread[0], "unknown");
  PetscCall(PetscFree(unread));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

/* unread when the solvers are configured and not excused: viewers, monitors
 * and reports (read when a solve ends, or on paths with that solver), names
 * read later (at PetscFinalize, at a factorization, by a solver the run
 * builds later: M2dOptionsReadLater), MUMPS' options (its factorization:
 * M2dOptionsNoEffect names them on paths without PETSc's MUMPS) and a
 * multigrid's level options (its set-up) */
static PetscBool IsUnused(const char *name, void *ctx)
{
  const char *rest = name + SplitPrefix(name);

  (void)ctx;
  if (Display(name) || Later(name) || IN_LIST(name, finalize_names, PETSC_FALSE) || IN_LIST(name, read_later_prefix, PETSC_TRUE) || MumpsName(rest)) return PETSC_FALSE;
  return (PetscBool)(strncasecmp(rest, "mg_levels_", 10) && strncasecmp(rest, "mg_coarse_", 10));
}

PetscErrorCode M2dOptionsCheckUnused(MPI_Comm comm, const char *why)
{
  PetscInt       n;
  char (*unread)[NAME_LEN];
  PetscErrorCode ierr = 0;

  PetscFunctionBeginUser;
  PetscCall(AllUnread(comm, IsUnused, NULL, &n, &unread));
  for (PetscInt i = 0; i < n && !ierr; i++) {
    const char *rest = unread[i] + SplitPrefix(unread[i]), *file = NULL;
    /* a known name nobody read: it does nothing on this path, except under a
     * PCFIELDSPLIT split's prefix or an inner solver's (PCREDUNDANT's, a block
     * solver's: read when that solver is set up, in the solve); anything else
     * is a typo */
    if (Known(unread[i]) || Known(rest) || IN_LIST(rest, petsc_common, PETSC_FALSE)) {
      if (strncasecmp(unread[i], "fieldsplit_", 11) && strncasecmp(unread[i], "redundant_", 10) && strncasecmp(unread[i], "sub_", 4) && Given(unread[i], &file)) ierr = NoEffect(comm, unread[i], file, why);
    } else ierr = RaiseUnknown(comm, unread[i], "unknown or unused");
  }
  PetscCall(PetscFree(unread));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}
