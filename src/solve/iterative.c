/* iterative.c - the multipliers eliminated row by row, a sparse SPD system in
 * u solved by CG + algebraic multigrid (see iterative.h). */
#include "iterative.h"
#include "elimination.h"
#include "logging.h"
#include "options.h"
#include "util.h"
#include <petscksp.h>
#include <string.h>

struct M2dIterative {
  MPI_Comm   comm;
  Mat        K, C; /* referenced from the KKT */
  IS         isu, isl;
  M2dElimination el;       /* slaves and groups of the rows (elimination.h) */
  PetscInt  *own, nown;    /* groups with a slave dof this rank owns */
  Mat        P, E, Ar;     /* du = P v + E t; Ar = P^T K P + D_S */
  IS         upd, upd2;    /* the rows of Ar a set changes (the contact rows' unknowns and one ring), one ring more */
  Mat       *Ku, *Pu, Bu;  /* K[upd2, upd2] (once), P[upd2, upd2], Pu^T Ku Pu: every rank */
  Vec        dK;           /* diag K */
  Vec        mask;         /* the step's active set (layout of C's rows) */
  Vec        all;          /* the same on every rank */
  VecScatter toall;
  Vec        bu, q, w, e, v, du; /* u layout */
  Vec        bl, dl, t;          /* multiplier layout */
  PetscReal  c, scale;
  KSP        ksp;          /* CG, its PC the zone's and the AMG's (ZoneApply) */
  PC         amg;          /* the AMG (-iterative_pc_*), kept across steps */
  IS         zone, halo;   /* the contact zone's dofs and one ring more (all of them on every rank) */
  Mat       *Z, *G;        /* Ar[zone, zone] and Ar[zone, halo] (every rank), or NULL */
  KSP        zksp;         /* Z's LU */
  VecScatter toh, hz;      /* u layout -> the halo -> the zone */
  Vec        bz, xz, x2z, bh, yh, r;
  PetscReal  rtol;       /* a complete solve's tolerance (-iterative_ksp_rtol) */
  M2dIterativeOptions opt;
  PetscReal  pace_built; /* iterations per decade of the first solve after the set-up */
  PetscReal  pace_last;  /* ... of the last solve (its refinements included) */
  PetscInt   built_at;   /* solves before the last set-up */
  PetscReal  r0;         /* the last solve's right-hand side norm */
  PetscReal  rlast;      /* its residual norm now */
  PetscReal  rpace;      /* the residual its pace counts from (r0, or where the AMG was rebuilt) */
  PetscInt   maxit;      /* -iterative_ksp_max_it */
  PetscInt   its_step;   /* its iterations, refinements included */
  M2dIterativeInfo info;
};

/* P and E for the set `on` (NULL: none active) */
static PetscErrorCode SlaveRows(M2dIterative *it, const PetscScalar on[])
{
  PetscInt  lo, hi;
  PetscBool singular = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(it->P, &lo, &hi));
  for (PetscInt k = 0; k < it->nown; k++) PetscCall(M2dEliminationGroupRows(&it->el, it->own[k], on, lo, hi, it->P, it->E, &singular));
  PetscCall(M2dCheckCollective(it->comm, singular, "-kkt_path iterative: active contact rows that share their unknowns form a singular block and cannot be eliminated; use -kkt_path condensed"));
  PetscCall(MatAssemblyBegin(it->P, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(it->P, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyBegin(it->E, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(it->E, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* nonzeros of an owned row with columns cols[0..n) in [clo, chi) (diagonal block) and outside */
static void CountRow(PetscInt n, const PetscInt cols[], PetscInt clo, PetscInt chi, PetscInt *d, PetscInt *o)
{
  *d = *o = 0;
  for (PetscInt i = 0; i < n; i++) {
    if (cols[i] >= clo && cols[i] < chi) (*d)++;
    else (*o)++;
  }
}

/* P: the identity, the slave rows with their group's columns; E: the slave
 * rows with their group's rows (multiplier layout); both of fixed pattern */
static PetscErrorCode CreateMaps(M2dIterative *it)
{
  PetscInt lo, hi, llo, lhi, n, N, nl, Nl, *pd, *po, *ed, *eo;

  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(it->K, &lo, &hi));
  PetscCall(MatGetSize(it->K, &N, NULL));
  PetscCall(MatGetLocalSize(it->C, &nl, NULL));
  PetscCall(MatGetSize(it->C, &Nl, NULL));
  PetscCall(MatGetOwnershipRange(it->C, &llo, &lhi));
  n = hi - lo;
  PetscCall(PetscMalloc4(n + 1, &pd, n + 1, &po, n + 1, &ed, n + 1, &eo));
  PetscCall(PetscMalloc1(it->el.ngroup + 1, &it->own));
  for (PetscInt i = 0; i < n; i++) pd[i] = 1, po[i] = 0, ed[i] = eo[i] = 0;
  it->nown = 0;
  for (PetscInt g = 0; g < it->el.ngroup; g++) {
    PetscBool mine = PETSC_FALSE;
    for (PetscInt q = it->el.gptr[g]; q < it->el.gptr[g + 1]; q++) {
      PetscInt s = it->el.slave[it->el.grow[q]];
      if (s < lo || s >= hi) continue;
      mine = PETSC_TRUE;
      CountRow(it->el.gcptr[g + 1] - it->el.gcptr[g], it->el.gcol + it->el.gcptr[g], lo, hi, &pd[s - lo], &po[s - lo]);
      CountRow(it->el.gptr[g + 1] - it->el.gptr[g], it->el.grow + it->el.gptr[g], llo, lhi, &ed[s - lo], &eo[s - lo]);
    }
    if (mine) it->own[it->nown++] = g;
  }
  PetscCall(MatCreate(it->comm, &it->P));
  PetscCall(MatSetSizes(it->P, n, n, N, N));
  PetscCall(MatSetBlockSizes(it->P, 2, 2)); /* P^T K P keeps K's nodes */
  PetscCall(MatSetType(it->P, MATAIJ));
  PetscCall(MatSeqAIJSetPreallocation(it->P, 0, pd));
  PetscCall(MatMPIAIJSetPreallocation(it->P, 0, pd, 0, po));
  PetscCall(MatCreateAIJ(it->comm, n, nl, N, Nl, 0, ed, 0, eo, &it->E));
  for (PetscInt i = lo; i < hi; i++) /* not a slave (no E row): the identity */
    if (ed[i - lo] + eo[i - lo] == 0) PetscCall(MatSetValue(it->P, i, i, 1.0, INSERT_VALUES));
  PetscCall(PetscFree4(pd, po, ed, eo));
  PetscCall(SlaveRows(it, NULL)); /* every row inactive: the patterns, assembled */
  PetscFunctionReturn(0);
}

/* The preconditioners' defaults, put in the options database under our own
 * prefix where the user gave none (PETSc 3.18 has no API for BoomerAMG's
 * parameters), for the preconditioner the options choose: BoomerAMG with
 * HMIS coarsening, extended+i interpolation of at most 4 entries and strong
 * threshold 0.5 (iterations stay flat over the Hertz levels: README); GAMG
 * with weak couplings (below 0.02) dropped and its smoothers' eigenvalues
 * estimated for each step's operator (the prolongator smoothing's estimate of
 * an earlier operator no longer bounds the spectrum: Chebyshev diverges). */
static PetscErrorCode DefaultOptions(void)
{
  static const char *const hypre[][2] = {
    {"-iterative_pc_hypre_boomeramg_coarsen_type", "HMIS"},
    {"-iterative_pc_hypre_boomeramg_interp_type", "ext+i"},
    {"-iterative_pc_hypre_boomeramg_P_max", "4"},
    {"-iterative_pc_hypre_boomeramg_strong_threshold", "0.5"},
    {"-iterative_pc_hypre_boomeramg_agg_nl", "1"},
    {"-iterative_pc_hypre_boomeramg_relax_type_down", "SOR/Jacobi"},
    {"-iterative_pc_hypre_boomeramg_relax_type_up", "backward-SOR/Jacobi"},
  };
  static const char *const gamg[][2] = {
    {"-iterative_pc_gamg_threshold", "0.02"},
    {"-iterative_pc_gamg_use_sa_esteig", "false"},
  };
  char        type[64] = PCHYPRE, htype[64] = "boomeramg";
  const char *const(*list)[2] = NULL;
  size_t      n = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, "-iterative_pc_type", type, sizeof(type), NULL));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-iterative_pc_hypre_type", htype, sizeof(htype), NULL));
  if (!strcmp(type, PCHYPRE) && !strcmp(htype, "boomeramg")) list = hypre, n = sizeof(hypre) / sizeof(hypre[0]);
  else if (!strcmp(type, PCGAMG)) list = gamg, n = sizeof(gamg) / sizeof(gamg[0]);
  for (size_t i = 0; i < n; i++) {
    PetscBool given;
    PetscCall(PetscOptionsHasName(NULL, NULL, list[i][0], &given));
    if (!given) PetscCall(PetscOptionsSetValue(NULL, list[i][0], list[i][1]));
  }
  PetscFunctionReturn(0);
}

/* CG on the unpreconditioned residual (the KKT residual of the step) to
 * 1e-12, BoomerAMG; all of it from the options database (-iterative_) */
PetscErrorCode M2dIterativeCreateKSP(MPI_Comm comm, KSP *ksp)
{
  PC pc;

  PetscFunctionBeginUser;
  PetscCall(DefaultOptions());
  PetscCall(KSPCreate(comm, ksp));
  PetscCall(KSPSetOptionsPrefix(*ksp, "iterative_"));
  PetscCall(KSPSetType(*ksp, KSPCG));
  PetscCall(KSPSetNormType(*ksp, KSP_NORM_UNPRECONDITIONED));
  PetscCall(KSPSetTolerances(*ksp, 1e-12, PETSC_DEFAULT, PETSC_DEFAULT, 1000));
  PetscCall(KSPGetPC(*ksp, &pc));
  PetscCall(PCSetType(pc, PCHYPRE));
  PetscCall(KSPSetFromOptions(*ksp));
  PetscFunctionReturn(0);
}

/* the sorted list z[0..n) (the same on every rank) with K's neighbours of
 * its unknowns added (one ring) */
static PetscErrorCode Ring(M2dIterative *it, PetscInt *n, PetscInt **z)
{
  PetscInt     lo, hi, *mine = NULL, nm = 0, cap = 0, *all, total;
  PetscMPIInt  size, *cnt, *off, nmi;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(it->comm, &size));
  PetscCall(MatGetOwnershipRange(it->K, &lo, &hi));
  for (PetscInt i = 0; i < *n; i++) {
    PetscInt        ncols;
    const PetscInt *cols;
    if ((*z)[i] < lo || (*z)[i] >= hi) continue;
    PetscCall(MatGetRow(it->K, (*z)[i], &ncols, &cols, NULL));
    if (nm + ncols > cap) {
      PetscInt *t;
      cap = 2 * (nm + ncols);
      PetscCall(PetscMalloc1(cap, &t));
      if (mine) PetscCall(PetscArraycpy(t, mine, nm));
      PetscCall(PetscFree(mine));
      mine = t;
    }
    PetscCall(PetscArraycpy(mine + nm, cols, ncols));
    nm += ncols;
    PetscCall(MatRestoreRow(it->K, (*z)[i], &ncols, &cols, NULL));
  }
  PetscCall(PetscSortRemoveDupsInt(&nm, mine));
  PetscCall(PetscMalloc2(size, &cnt, size + 1, &off));
  PetscCall(PetscMPIIntCast(nm, &nmi));
  PetscCallMPI(MPI_Allgather(&nmi, 1, MPI_INT, cnt, 1, MPI_INT, it->comm));
  off[0] = 0;
  for (PetscMPIInt r = 0; r < size; r++) off[r + 1] = off[r] + cnt[r];
  total = off[size] + *n;
  PetscCall(PetscMalloc1(total + 1, &all));
  PetscCallMPI(MPI_Allgatherv(mine, nmi, MPIU_INT, all, cnt, off, MPIU_INT, it->comm));
  PetscCall(PetscArraycpy(all + off[size], *z, *n));
  PetscCall(PetscSortRemoveDupsInt(&total, all));
  PetscCall(PetscFree(*z));
  PetscCall(PetscFree(mine));
  PetscCall(PetscFree2(cnt, off));
  *z = all;
  *n = total;
  PetscFunctionReturn(0);
}

/* the contact rows' unknowns with `layers` rings of neighbours (z, n) and
 * one ring more (h, nh): sorted, the same on every rank */
static PetscErrorCode RowsAndRings(M2dIterative *it, PetscInt layers, PetscInt *n, PetscInt **z, PetscInt *nh, PetscInt **h)
{
  PetscFunctionBeginUser;
  *n = it->el.rowptr[it->el.nrow];
  PetscCall(PetscMalloc1(*n + 1, z));
  PetscCall(PetscArraycpy(*z, it->el.rowcol, *n));
  PetscCall(PetscSortRemoveDupsInt(n, *z));
  for (PetscInt l = 0; l < layers; l++) PetscCall(Ring(it, n, z));
  *nh = *n;
  PetscCall(PetscMalloc1(*n + 1, h));
  PetscCall(PetscArraycpy(*h, *z, *n));
  PetscCall(Ring(it, nh, h));
  PetscFunctionReturn(0);
}

/* The rows of Ar = P^T K P that a set can change: those of the contact rows'
 * unknowns (slaves and masters) and of their neighbours (a slave's column of
 * K reaches them), one ring; outside them Ar is K. Their columns lie in one
 * ring more (upd2), and every product in their entries stays in upd2, so
 * those rows of Ar are the same rows of Pu^T Ku Pu, P and K cut to upd2. */
static PetscErrorCode UpdateCreate(M2dIterative *it)
{
  PetscInt n, n2, *z, *z2;

  PetscFunctionBeginUser;
  PetscCall(RowsAndRings(it, 1, &n, &z, &n2, &z2));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, z, PETSC_OWN_POINTER, &it->upd));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n2, z2, PETSC_OWN_POINTER, &it->upd2));
  PetscCall(MatCreateSubMatrices(it->K, 1, &it->upd2, &it->upd2, MAT_INITIAL_MATRIX, &it->Ku));
  PetscFunctionReturn(0);
}

/* Ar = P^T K P for a new P: only the rows in upd are computed again (from
 * Pu^T Ku Pu), each of them zeroed first so that no value of the last set
 * stays; a new nonzero would be an error (Ar's pattern is that of P's full
 * pattern). Collective. */
static PetscErrorCode UpdateRows(M2dIterative *it)
{
  const PetscInt *g, *u;
  PetscInt        n2, n, lo, hi, cap = 0, *cols = NULL, *rows, nr = 0;

  PetscFunctionBeginUser;
  PetscCall(MatCreateSubMatrices(it->P, 1, &it->upd2, &it->upd2, it->Pu ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, &it->Pu));
  PetscCall(MatPtAP(it->Ku[0], it->Pu[0], it->Bu ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, 2.0, &it->Bu));
  PetscCall(MatGetOwnershipRange(it->Ar, &lo, &hi));
  PetscCall(ISGetLocalSize(it->upd2, &n2));
  PetscCall(ISGetLocalSize(it->upd, &n));
  PetscCall(ISGetIndices(it->upd2, &g));
  PetscCall(ISGetIndices(it->upd, &u));
  PetscCall(PetscMalloc1(n + 1, &rows));
  for (PetscInt k = 0; k < n; k++)
    if (u[k] >= lo && u[k] < hi) rows[nr++] = u[k];
  PetscCall(MatZeroRows(it->Ar, nr, rows, 0.0, NULL, NULL)); /* pattern kept (MAT_KEEP_NONZERO_PATTERN) */
  for (PetscInt i = 0, k = 0; i < n2; i++) {
    const PetscInt    *c;
    const PetscScalar *v;
    PetscInt           nc, r = g[i];
    while (k < n && u[k] < r) k++;
    if (r < lo || r >= hi || k == n || u[k] != r) continue; /* not this rank's, or not a row a set changes */
    PetscCall(MatGetRow(it->Bu, i, &nc, &c, &v));
    if (nc > cap) {
      PetscCall(PetscFree(cols));
      cap = 2 * nc;
      PetscCall(PetscMalloc1(cap, &cols));
    }
    for (PetscInt j = 0; j < nc; j++) cols[j] = g[c[j]];
    PetscCall(MatSetValues(it->Ar, 1, &r, nc, cols, v, INSERT_VALUES));
    PetscCall(MatRestoreRow(it->Bu, i, &nc, &c, &v));
  }
  PetscCall(ISRestoreIndices(it->upd, &u));
  PetscCall(ISRestoreIndices(it->upd2, &g));
  PetscCall(PetscFree(cols));
  PetscCall(PetscFree(rows));
  PetscCall(MatAssemblyBegin(it->Ar, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(it->Ar, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* The contact zone: every unknown of a contact row and `layers` rings of
 * K's neighbours around them, and its halo (one ring more), the same sorted
 * lists on every rank. Between two active sets P^T K P + D_S differs only in
 * the zone (rows and columns of the rows' unknowns and the slaves'
 * neighbours); the zone's rows couple only to the halo. */
static PetscErrorCode ZoneCreate(M2dIterative *it, PetscInt layers)
{
  PetscInt n, nh, *z, *h, *pos;
  IS       isz;

  PetscFunctionBeginUser;
  PetscCall(RowsAndRings(it, layers, &n, &z, &nh, &h));
  PetscCall(PetscMalloc1(n + 1, &pos)); /* the zone's places in the halo */
  for (PetscInt i = 0; i < n; i++) PetscCall(PetscFindInt(z[i], nh, h, &pos[i]));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, z, PETSC_OWN_POINTER, &it->zone));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, nh, h, PETSC_OWN_POINTER, &it->halo));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, n, &it->bz));
  PetscCall(VecDuplicate(it->bz, &it->xz));
  PetscCall(VecDuplicate(it->bz, &it->x2z));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, nh, &it->bh));
  PetscCall(VecDuplicate(it->bh, &it->yh));
  PetscCall(VecScatterCreate(it->bu, it->halo, it->bh, NULL, &it->toh));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, pos, PETSC_OWN_POINTER, &isz));
  PetscCall(VecScatterCreate(it->bh, isz, it->bz, NULL, &it->hz)); /* halo -> zone (sequential) */
  PetscCall(ISDestroy(&isz));
  PetscCall(KSPCreate(PETSC_COMM_SELF, &it->zksp));
  PetscCall(KSPSetType(it->zksp, KSPPREONLY));
  {
    PC pc;
    PetscCall(KSPGetPC(it->zksp, &pc));
    PetscCall(PCSetType(pc, PCLU));
    PetscCall(PCFactorSetMatOrderingType(pc, MATORDERINGND));
  }
  it->info.zone_dofs = n;
  PetscFunctionReturn(0);
}

/* The preconditioner, x = B b: the zone's exact solve, the AMG on what is
 * left, the zone again (symmetric multiplicative Schwarz, so CG's
 * preconditioner stays symmetric). The zone takes what changes from step
 * to step, so the AMG of an earlier step still serves. Everything but the
 * AMG is on the zone and its halo, held by every rank: with Z = Ar[zone,
 * zone] and G = Ar[zone, halo],
 *   x1 = Z^-1 b_z;  r = b - G^T x1 (on the halo);  y = AMG r;
 *   x2 = Z^-1 (b_z - G (x1 + y)_halo);  x = y + x1 + x2 (on the zone). */
static PetscErrorCode ZoneApply(PC pc, Vec b, Vec x)
{
  M2dIterative *it;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &it));
  PetscCall(VecScatterBegin(it->toh, b, it->bh, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(it->toh, b, it->bh, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterBegin(it->hz, it->bh, it->bz, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(it->hz, it->bh, it->bz, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(KSPSolve(it->zksp, it->bz, it->xz));          /* x1 */
  PetscCall(MatMultTranspose(it->G[0], it->xz, it->yh));  /* r_h = b_h - G^T x1 */
  PetscCall(VecAYPX(it->yh, -1.0, it->bh));
  PetscCall(VecCopy(b, it->r));
  PetscCall(VecScatterBegin(it->toh, it->yh, it->r, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(it->toh, it->yh, it->r, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(PCApply(it->amg, it->r, x));                  /* y */
  PetscCall(VecScatterBegin(it->toh, x, it->yh, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(it->toh, x, it->yh, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterBegin(it->hz, it->xz, it->yh, ADD_VALUES, SCATTER_REVERSE)); /* (x1 + y)_h */
  PetscCall(VecScatterEnd(it->hz, it->xz, it->yh, ADD_VALUES, SCATTER_REVERSE));
  PetscCall(MatMult(it->G[0], it->yh, it->bz));           /* b_z - G (x1 + y)_h */
  PetscCall(VecScatterBegin(it->hz, it->bh, it->x2z, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(it->hz, it->bh, it->x2z, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecAYPX(it->bz, -1.0, it->x2z));
  PetscCall(KSPSolve(it->zksp, it->bz, it->x2z));         /* x2 */
  PetscCall(VecAXPY(it->xz, 1.0, it->x2z));               /* x = y + x1 + x2 on the zone */
  PetscCall(VecZeroEntries(it->yh));
  PetscCall(VecScatterBegin(it->hz, it->xz, it->yh, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(it->hz, it->xz, it->yh, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecZeroEntries(it->r));
  PetscCall(VecScatterBegin(it->toh, it->yh, it->r, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(it->toh, it->yh, it->r, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecAXPY(x, 1.0, it->r));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dIterativeReadOptions(MPI_Comm comm, M2dIterativeOptions *opt)
{
  PetscFunctionBeginUser;
  opt->inexact = 0.1;
  opt->reuse   = 2;
  opt->zone    = 4;
  opt->prove   = PETSC_FALSE;
  PetscOptionsBegin(comm, NULL, "mortar2d: solver paths (-kkt_path iterative)", "");
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-iterative_inexact", "CG tolerance of a step whose set may still change (of its rhs; 0: all complete)", opt->inexact, &opt->inexact, NULL));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-iterative_reuse", "keep the AMG while steps converge at most this much slower (0: new each step)", opt->reuse, &opt->reuse, NULL));
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-iterative_prove", "prove every inexact step's next set by tenfold refinements (default: the last step's only)", opt->prove, &opt->prove));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-iterative_zone", "rings of neighbours around the contact dofs solved exactly each step (-1: none)", opt->zone, &opt->zone, NULL));
  PetscOptionsEnd();
  PetscCall(M2dOptionsRaise(comm));
  PetscCheck(opt->inexact >= 0 && opt->inexact < 1, comm, PETSC_ERR_USER_INPUT, "option -iterative_inexact: %g must be in [0, 1)", (double)opt->inexact);
  PetscCheck(opt->reuse == 0 || opt->reuse >= 1, comm, PETSC_ERR_USER_INPUT, "option -iterative_reuse: %g must be 0 (a new AMG every step) or >= 1", (double)opt->reuse);
  PetscCheck(opt->zone >= -1, comm, PETSC_ERR_USER_INPUT, "option -iterative_zone: %" PetscInt_FMT " must be >= 0 (rings; -1: no zone)", opt->zone);
  PetscFunctionReturn(0);
}

PetscErrorCode M2dIterativeCreate(const M2dKKT *kkt, const M2dContactRows *R, PetscInt ndir, const PetscInt drows[], M2dIterative **itp)
{
  M2dIterative *it;

  PetscFunctionBeginUser;
  PetscCall(M2dLogRegister());
  PetscCall(PetscNew(&it));
  it->comm = PetscObjectComm((PetscObject)kkt->K);
  it->K    = kkt->K;
  it->C    = kkt->C;
  it->isu  = kkt->isu;
  it->isl  = kkt->isl;
  PetscCall(PetscObjectReference((PetscObject)it->K));
  PetscCall(PetscObjectReference((PetscObject)it->C));
  PetscCall(PetscObjectReference((PetscObject)it->isu));
  PetscCall(PetscObjectReference((PetscObject)it->isl));
  *itp = it; /* from here M2dIterativeDestroy frees what exists */
  PetscCall(M2dEliminationCreate(it->comm, R, ndir, drows, &it->el));
  PetscCall(CreateMaps(it));
  PetscCall(MatCreateVecs(it->K, &it->bu, &it->dK));
  PetscCall(MatGetDiagonal(it->K, it->dK));
  PetscCall(VecDuplicate(it->bu, &it->q));
  PetscCall(VecDuplicate(it->bu, &it->w));
  PetscCall(VecDuplicate(it->bu, &it->e));
  PetscCall(VecDuplicate(it->bu, &it->v));
  PetscCall(VecDuplicate(it->bu, &it->du));
  PetscCall(VecDuplicate(kkt->r, &it->bl));
  PetscCall(VecDuplicate(kkt->r, &it->dl));
  PetscCall(VecDuplicate(kkt->r, &it->t));
  PetscCall(VecDuplicate(kkt->r, &it->mask));
  PetscCall(VecScatterCreateToAll(it->mask, &it->toall, &it->all));
  PetscCall(M2dIterativeCreateKSP(it->comm, &it->ksp));
  PetscCall(KSPGetTolerances(it->ksp, &it->rtol, NULL, NULL, &it->maxit));
  PetscCall(M2dIterativeReadOptions(it->comm, &it->opt));
  if (it->opt.zone >= 0) { /* the KSP's PC (the AMG) goes behind the zone's (ZoneApply) */
    PC shell;
    PetscCall(KSPGetPC(it->ksp, &it->amg));
    PetscCall(PetscObjectReference((PetscObject)it->amg));
    PetscCall(PCCreate(it->comm, &shell));
    PetscCall(PCSetType(shell, PCSHELL));
    PetscCall(PCShellSetContext(shell, it));
    PetscCall(PCShellSetApply(shell, ZoneApply));
    PetscCall(PCShellSetName(shell, "the contact zone's LU, the AMG, the zone's LU (symmetric multiplicative)"));
    PetscCall(KSPSetPC(it->ksp, shell));
    PetscCall(PCDestroy(&shell));
    PetscCall(ZoneCreate(it, it->opt.zone));
    PetscCall(VecDuplicate(it->bu, &it->r));
  }
  it->info.slave_dofs = it->el.nrow;
  it->info.rtol       = it->rtol;
  it->info.inexact    = it->opt.inexact;
  it->info.prove      = it->opt.prove;
  PetscFunctionReturn(0);
}

/* the AMG's reuse flag: on its own PC with the zone, else on the KSP's */
static PetscErrorCode SetReuse(M2dIterative *it, PetscBool reuse)
{
  PetscFunctionBeginUser;
  if (it->amg) PetscCall(PCSetReusePreconditioner(it->amg, reuse));
  else PetscCall(KSPSetReusePreconditioner(it->ksp, reuse));
  PetscFunctionReturn(0);
}

static PetscErrorCode GetReuse(M2dIterative *it, PetscBool *reuse)
{
  PetscFunctionBeginUser;
  if (it->amg) PetscCall(PCGetReusePreconditioner(it->amg, reuse));
  else PetscCall(KSPGetReusePreconditioner(it->ksp, reuse));
  PetscFunctionReturn(0);
}

/* Keep the AMG of an earlier step, built for another set, while the last
 * step converged at most -iterative_reuse times as slowly (iterations per
 * decade of the residual) as the first step after the set-up; otherwise
 * build it anew. The operator differs from the one the AMG was built for
 * in the contact zone only, which the zone's exact solve takes (ZoneApply);
 * without the zone each changed row costs CG about an iteration. */
static PetscErrorCode ReusePreconditioner(M2dIterative *it)
{
  PetscBool reuse;

  PetscFunctionBeginUser;
  if (it->info.setups > 0 && it->info.solves == it->built_at + 1) it->pace_built = it->pace_last;
  reuse = (PetscBool)(it->info.setups > 0 && it->opt.reuse > 0 && it->pace_last <= it->opt.reuse * it->pace_built);
  PetscCall(SetReuse(it, reuse));
  if (!reuse) {
    it->built_at = it->info.solves;
    it->info.setups++;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dIterativeSetActive(M2dIterative *it, Vec active, PetscReal c, PetscReal scale)
{
  const PetscScalar *on, *dk;
  PetscScalar       *ds;
  Vec                dS;
  PetscInt           lo, hi;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_ITER_SETUP], 0, 0, 0, 0));
  it->c     = c;
  it->scale = scale;
  PetscCall(VecCopy(active, it->mask));
  PetscCall(VecScatterBegin(it->toall, it->mask, it->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(it->toall, it->mask, it->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(it->all, &on));
  PetscCall(SlaveRows(it, on));
  PetscCall(VecDuplicate(it->dK, &dS)); /* D_S: diag K on the active slave dofs */
  PetscCall(VecZeroEntries(dS));
  PetscCall(VecGetOwnershipRange(dS, &lo, &hi));
  PetscCall(VecGetArrayRead(it->dK, &dk));
  PetscCall(VecGetArray(dS, &ds));
  for (PetscInt k = 0; k < it->nown; k++)
    for (PetscInt q = it->el.gptr[it->own[k]]; q < it->el.gptr[it->own[k] + 1]; q++) {
      PetscInt j = it->el.grow[q], s = it->el.slave[j];
      if (PetscRealPart(on[j]) != 0 && s >= lo && s < hi) ds[s - lo] = dk[s - lo];
    }
  PetscCall(VecRestoreArray(dS, &ds));
  PetscCall(VecRestoreArrayRead(it->dK, &dk));
  if (!it->Ar) {
    MatNullSpace nsp;
    PetscCall(MatPtAP(it->K, it->P, MAT_INITIAL_MATRIX, 2.0, &it->Ar));
    PetscCall(MatGetNearNullSpace(it->K, &nsp));
    if (nsp) PetscCall(MatSetNearNullSpace(it->Ar, nsp));
    PetscCall(MatSetOption(it->Ar, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
    PetscCall(MatSetOption(it->Ar, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
    PetscCall(UpdateCreate(it));
  } else PetscCall(UpdateRows(it)); /* what the set changes: the rows of upd */
  PetscCall(MatDiagonalSet(it->Ar, dS, ADD_VALUES));
  PetscCall(VecDestroy(&dS));
  PetscCall(KSPSetOperators(it->ksp, it->Ar, it->Ar));
  PetscCall(ReusePreconditioner(it));
  if (it->amg) { /* the AMG's set-up unless reused, the zone's LU */
    PetscCall(PCSetOperators(it->amg, it->Ar, it->Ar));
    PetscCall(PCSetUp(it->amg));
    PetscCall(MatCreateSubMatrices(it->Ar, 1, &it->zone, &it->zone, it->Z ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, &it->Z));
    PetscCall(MatCreateSubMatrices(it->Ar, 1, &it->zone, &it->halo, it->G ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, &it->G));
    /* on several ranks, with the zone holding every unknown (a small scene),
     * PETSc 3.18's reuse refreshes the values of Z but not its state, and the
     * LU's set-up then kept the factors of the last set: a zone solve of the
     * wrong operator, an indefinite preconditioner (the stack with a set
     * changing each step: DIVERGED_INDEFINITE_PC on 2 and 3 ranks); the
     * assembly marks Z as changed */
    PetscCall(MatAssemblyBegin(it->Z[0], MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(it->Z[0], MAT_FINAL_ASSEMBLY));
    PetscCall(KSPSetOperators(it->zksp, it->Z[0], it->Z[0]));
    PetscCall(KSPSetUp(it->zksp));
  }
  PetscCall(KSPSetUp(it->ksp)); /* the preconditioner's set-up, unless reused */
  PetscCall(VecRestoreArrayRead(it->all, &on));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_ITER_SETUP], 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* the one line for a Krylov solve that did not converge */
static PetscErrorCode SolveFailed(M2dIterative *it)
{
  KSPConvergedReason reason;
  PetscInt           its;
  PetscReal          rnorm;

  PetscFunctionBeginUser;
  PetscCall(KSPGetConvergedReason(it->ksp, &reason));
  if (reason > 0) PetscFunctionReturn(0);
  PetscCall(KSPGetIterationNumber(it->ksp, &its));
  PetscCall(KSPGetResidualNorm(it->ksp, &rnorm));
  SETERRQ(it->comm, PETSC_ERR_NOT_CONVERGED, "-kkt_path iterative: the Krylov solve of active-set step %" PetscInt_FMT " did not converge (%s after %" PetscInt_FMT " iterations, residual %.3e); try -iterative_pc_type gamg, more -iterative_ksp_max_it, or -kkt_path condensed", it->info.solves, KSPConvergedReasons[reason], its, (double)rnorm);
}

/* A user's -iterative_ksp_atol above the residual the step asks for stops CG
 * short of it, at once when above the right-hand side: nothing is solved and
 * the active set cannot settle (it said "did not settle in 50 steps") */
static PetscErrorCode StoppedByAtol(M2dIterative *it, PetscReal rtol, PetscReal rnorm)
{
  KSPConvergedReason reason;
  PetscReal          atol;

  PetscFunctionBeginUser;
  PetscCall(KSPGetConvergedReason(it->ksp, &reason));
  PetscCall(KSPGetTolerances(it->ksp, NULL, &atol, NULL, NULL));
  PetscCheck(!(reason == KSP_CONVERGED_ATOL && rnorm > rtol * it->r0 && atol > 1e-40), it->comm, PETSC_ERR_USER_INPUT, "option -iterative_ksp_atol: %g stopped the Krylov solve of %s %" PetscInt_FMT " at a residual of %.3e of its right-hand side (%.3e), short of the %.0e it was asked for; lower -iterative_ksp_atol or leave it out (default: none)",
             (double)atol, it->c > 0 ? "active-set step" : "solve", it->info.solves, (double)(it->r0 > 0 ? rnorm / it->r0 : 0), (double)it->r0, (double)rtol);
  PetscFunctionReturn(0);
}

/* CG on the u system to rtol of its right-hand side, from v (cont) or from 0.
 * Under a preconditioner kept from an earlier set CG has -iterative_reuse times the
 * iterations per decade of the first step after the set-up; past those (a
 * rise in iterations) the preconditioner is built anew for this set and CG
 * goes on from where it stopped. */
static PetscErrorCode Krylov(M2dIterative *it, PetscReal rtol, PetscBool cont)
{
  KSPConvergedReason reason;
  PetscInt           its, budget = it->maxit;
  PetscReal          rnorm;
  PetscBool          reused;

  PetscFunctionBeginUser;
  PetscCall(GetReuse(it, &reused));
  if (reused) {
    PetscReal decades = PetscLog10Real((cont ? it->rlast : it->r0) / (rtol * it->r0));
    budget            = PetscMin(it->maxit, (PetscInt)PetscCeilReal(it->opt.reuse * it->pace_built * PetscMax(decades, 0)) + 1);
  }
  PetscCall(KSPSetTolerances(it->ksp, rtol, PETSC_DEFAULT, PETSC_DEFAULT, budget));
  PetscCall(KSPSetInitialGuessNonzero(it->ksp, cont));
  PetscCall(KSPSolve(it->ksp, it->bu, it->v));
  PetscCall(KSPGetConvergedReason(it->ksp, &reason));
  PetscCall(KSPGetIterationNumber(it->ksp, &its));
  it->its_step += its;
  it->info.its_total += its;
  if (reason < 0 && reused) {
    PetscCall(KSPGetResidualNorm(it->ksp, &it->rpace)); /* the step's pace counts from here */
    PetscCall(SetReuse(it, PETSC_FALSE));
    if (it->amg) PetscCall(PCSetUp(it->amg));
    it->built_at = it->info.solves - 1;
    it->info.setups++;
    PetscCall(KSPSetTolerances(it->ksp, rtol, PETSC_DEFAULT, PETSC_DEFAULT, it->maxit));
    PetscCall(KSPSetInitialGuessNonzero(it->ksp, PETSC_TRUE));
    PetscCall(KSPSolve(it->ksp, it->bu, it->v));
    PetscCall(KSPGetIterationNumber(it->ksp, &its));
    it->its_step = its;
    it->info.its_total += its;
  }
  PetscCall(SolveFailed(it));
  it->info.its_max = PetscMax(it->info.its_max, it->its_step);
  PetscCall(KSPGetResidualNorm(it->ksp, &rnorm));
  PetscCall(StoppedByAtol(it, rtol, rnorm));
  it->rlast     = rnorm;
  it->pace_last = rnorm > 0 && rnorm < it->rpace ? it->its_step / PetscLog10Real(it->rpace / rnorm) : 0;
  PetscFunctionReturn(0);
}

/* y from v: du = P v + e, dl_A = (q - K du)_s / C_js, dl_I kept in bl */
static PetscErrorCode Recover(M2dIterative *it, Vec y)
{
  PetscFunctionBeginUser;
  PetscCall(MatMultAdd(it->P, it->v, it->e, it->du)); /* du = P v + e */
  PetscCall(MatMult(it->K, it->du, it->w));           /* dl_A = (q - K du)_s / C_js */
  PetscCall(VecAYPX(it->w, -1.0, it->q));
  PetscCall(MatMultTranspose(it->E, it->w, it->t));
  PetscCall(VecPointwiseMult(it->t, it->t, it->mask));
  PetscCall(VecWAXPY(it->dl, 1.0, it->bl, it->t));
  PetscCall(VecISCopy(y, it->isu, SCATTER_FORWARD, it->du));
  PetscCall(VecISCopy(y, it->isl, SCATTER_FORWARD, it->dl));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dIterativeSolve(M2dIterative *it, Vec b, PetscReal rtol, Vec y)
{
  const PetscScalar *a;
  PetscScalar       *l, *tt;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_ITER_SOLVE], 0, 0, 0, 0));
  PetscCall(VecISCopy(b, it->isu, SCATTER_REVERSE, it->bu));
  PetscCall(VecISCopy(b, it->isl, SCATTER_REVERSE, it->bl));
  /* inactive rows: dl_j = -(c / scale) b_j; active rows: C_j du = t_j = b_j / scale */
  PetscCall(VecGetLocalSize(it->bl, &n));
  PetscCall(VecGetArrayRead(it->mask, &a));
  PetscCall(VecGetArray(it->bl, &l));
  PetscCall(VecGetArrayWrite(it->t, &tt));
  for (PetscInt j = 0; j < n; j++) {
    PetscBool act = (PetscBool)(PetscRealPart(a[j]) != 0);
    tt[j]         = act ? l[j] / it->scale : 0.0;
    l[j]          = act ? 0.0 : -(it->c / it->scale) * l[j];
  }
  PetscCall(VecRestoreArrayWrite(it->t, &tt));
  PetscCall(VecRestoreArray(it->bl, &l));
  PetscCall(VecRestoreArrayRead(it->mask, &a));
  PetscCall(MatMultTranspose(it->C, it->bl, it->q));    /* q = b_u - C^T dl_I */
  PetscCall(VecAYPX(it->q, -1.0, it->bu));
  PetscCall(MatMult(it->E, it->t, it->e));              /* e_s = t_j / C_js */
  PetscCall(MatMult(it->K, it->e, it->w));              /* rhs = P^T (q - K e) */
  PetscCall(VecAYPX(it->w, -1.0, it->q));
  PetscCall(MatMultTranspose(it->P, it->w, it->bu));
  PetscCall(VecNorm(it->bu, NORM_2, &it->r0));
  it->rpace = it->r0;
  it->its_step = 0;
  it->info.solves++;
  PetscCall(Krylov(it, rtol > 0 ? rtol : it->rtol, PETSC_FALSE));
  PetscCall(Recover(it, y));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_ITER_SOLVE], 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dIterativeRefine(M2dIterative *it, PetscReal rtol, Vec y)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_ITER_SOLVE], 0, 0, 0, 0));
  PetscCall(Krylov(it, rtol > 0 ? rtol : it->rtol, PETSC_TRUE));
  PetscCall(Recover(it, y));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_ITER_SOLVE], 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dIterativeGetInfo(const M2dIterative *it, M2dIterativeInfo *info)
{
  PetscFunctionBeginUser;
  *info = it->info;
  PetscFunctionReturn(0);
}

PetscErrorCode M2dIterativeDestroy(M2dIterative **itp)
{
  M2dIterative *it = *itp;

  PetscFunctionBeginUser;
  if (!it) PetscFunctionReturn(0);
  PetscCall(MatDestroy(&it->K));
  PetscCall(MatDestroy(&it->C));
  PetscCall(ISDestroy(&it->isu));
  PetscCall(ISDestroy(&it->isl));
  PetscCall(M2dEliminationDestroy(&it->el));
  PetscCall(PetscFree(it->own));
  PetscCall(MatDestroy(&it->P));
  PetscCall(MatDestroy(&it->E));
  PetscCall(MatDestroy(&it->Ar));
  PetscCall(VecDestroy(&it->dK));
  PetscCall(VecDestroy(&it->mask));
  PetscCall(VecDestroy(&it->all));
  PetscCall(VecScatterDestroy(&it->toall));
  PetscCall(VecDestroy(&it->bu));
  PetscCall(VecDestroy(&it->q));
  PetscCall(VecDestroy(&it->w));
  PetscCall(VecDestroy(&it->e));
  PetscCall(VecDestroy(&it->v));

  PetscCall(VecDestroy(&it->du));
  PetscCall(VecDestroy(&it->bl));
  PetscCall(VecDestroy(&it->dl));
  PetscCall(VecDestroy(&it->t));
  PetscCall(KSPDestroy(&it->ksp));
  PetscCall(PCDestroy(&it->amg));
  PetscCall(ISDestroy(&it->zone));
  PetscCall(ISDestroy(&it->upd));
  PetscCall(ISDestroy(&it->upd2));
  if (it->Ku) PetscCall(MatDestroySubMatrices(1, &it->Ku));
  if (it->Pu) PetscCall(MatDestroySubMatrices(1, &it->Pu));
  PetscCall(MatDestroy(&it->Bu));
  PetscCall(ISDestroy(&it->halo));
  if (it->Z) PetscCall(MatDestroySubMatrices(1, &it->Z));
  if (it->G) PetscCall(MatDestroySubMatrices(1, &it->G));
  PetscCall(KSPDestroy(&it->zksp));
  PetscCall(VecScatterDestroy(&it->toh));
  PetscCall(VecScatterDestroy(&it->hz));
  PetscCall(VecDestroy(&it->bz));
  PetscCall(VecDestroy(&it->xz));
  PetscCall(VecDestroy(&it->x2z));
  PetscCall(VecDestroy(&it->bh));
  PetscCall(VecDestroy(&it->yh));
  PetscCall(VecDestroy(&it->r));
  PetscCall(PetscFree(it));
  *itp = NULL;
  PetscFunctionReturn(0);
}
