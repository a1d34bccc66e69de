/* condensed.c - the condensed path (condensed.h): every rank factors its
 * interior with its own MUMPS and a Schur complement on the interface; the
 * interface is dense on every rank, its separator eliminated by Cholesky;
 * then the substitutions and the dense algebra of the steps on nu. */
#include "condensed_impl.h"
#include "logging.h"

/* Order, analyse and factor this rank's matrix; *S gets its Schur complement
 * on the interface unknowns it couples to (nschur x nschur, column-major) */
static PetscErrorCode FactorLocal(M2dCondensed *cs, const M2dCondensedOptions *opt, PetscScalar **S)
{
  LocalFactor   *lf = &cs->local;
  PetscInt64     nnz;
  M2dMumpsInt   *irn, *jcn, *perm;
  PetscScalar   *a;
  PetscBool      singular;
  PetscLogDouble flops;

  PetscFunctionBeginUser;
  PetscCall(LocalMatrixCreate(cs->comm, cs->Kg, cs->C, cs->Ct, &cs->split, cs->ldlt, &lf->nschur, &lf->schur_iface, &nnz, &irn, &jcn, &a));
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_COND_ORDER], 0, 0, 0, 0));
  PetscCall(LocalOrdering(cs->comm, cs->Kg, &cs->split, lf->nschur, opt->ordering, &perm));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_COND_ORDER], 0, 0, 0, 0));
  PetscCall(M2dMumpsCreate(cs->comm, cs->split.ninterior > 0 ? cs->split.ninterior + lf->nschur : 0, opt->ldlt, &opt->mumps, &lf->mumps));
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MUMPS_ANALYSIS], 0, 0, 0, 0));
  PetscCall(M2dMumpsAnalyse(lf->mumps, nnz, irn, jcn, a, perm, lf->nschur));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MUMPS_ANALYSIS], 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MUMPS_FACTOR], 0, 0, 0, 0));
  PetscCall(M2dMumpsFactor(lf->mumps, &singular, &flops));
  PetscCall(PetscLogFlops(flops));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MUMPS_FACTOR], 0, 0, 0, 0));
  PetscCall(PetscFree3(irn, jcn, a));
  PetscCall(PetscFree(perm));
  PetscCheck(!singular, cs->comm, PETSC_ERR_USER_INPUT, "the stiffness with every candidate contact node tied is singular: a body is held by nothing (check -dirichlet and the contact pair)");
  PetscCall(PetscInfo(NULL, "MUMPS on this rank: %" PetscInt_FMT " interior rows, %" PetscInt_FMT " interface unknowns, %g flops (RINFO(3))\n", cs->split.ninterior, lf->nschur, (double)flops));
  PetscCallMPI(MPI_Allreduce(&flops, &cs->info.flops_sum, 1, MPI_DOUBLE, MPI_SUM, cs->comm));
  PetscCallMPI(MPI_Allreduce(&flops, &cs->info.flops_max, 1, MPI_DOUBLE, MPI_MAX, cs->comm));
  *S = NULL;
  if (lf->nschur > 0) PetscCall(M2dMumpsGetSchur(lf->mumps, S));
  PetscFunctionReturn(0);
}

/* The interface matrix S_G (G x G, column-major, every rank): the interface
 * rows' own entries plus every rank's Schur complement S (freed here) */
static PetscErrorCode InterfaceAssemble(M2dCondensed *cs, PetscScalar *S, PetscScalar **SG)
{
  const RowSplit *sp = &cs->split;
  const PetscInt *gi = cs->local.schur_iface, m = cs->local.nschur, G = sp->nsep + sp->nmult;
  PetscScalar    *A;
  RowReader       rr;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(G * G + 1, &A));
  for (PetscInt q = 0; q < m; q++)
    for (PetscInt p = 0; p < m; p++) A[gi[p] + gi[q] * G] += S[p + q * m];
  PetscCall(PetscFree(S));
  PetscCall(RowReaderCreate(cs->Kg, cs->C, cs->Ct, &cs->split, &rr));
  for (PetscInt i = 0; i < sp->u1 - sp->u0 + sp->nl; i++) {
    PetscInt r;
    if (sp->row[i].kind == UNKNOWN_INTERIOR) continue;
    r = InterfaceIndex(sp, sp->row[i]);
    PetscCall(RowReaderGet(&rr, i));
    for (PetscInt e = 0; e < rr.n; e++) { /* interior columns are in some rank's S */
      Unknown c = rr.ent[e].col;
      if (c.kind == UNKNOWN_SEPARATOR || c.kind == UNKNOWN_MULTIPLIER) A[r + InterfaceIndex(sp, c) * G] += rr.ent[e].val;
    }
  }
  PetscCall(RowReaderDestroy(&rr));
  for (PetscInt off = 0; off < G * G;) { /* MPI counts are int */
    PetscMPIInt cnt;
    PetscCall(PetscMPIIntCast(PetscMin(G * G - off, 1 << 30), &cnt));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, A + off, cnt, MPIU_SCALAR, MPIU_SUM, cs->comm));
    off += cnt;
  }
  *SG = A;
  PetscFunctionReturn(0);
}

/* S0 = S_ll - S_ls S_ss^-1 S_sl = S_ll - X^T X with L L^T = S_ss, X = L^-1 S_sl:
 * this rank's rows of S0; L and X (every rank) for the substitutions.
 * *pivot > 0: S_ss is not positive definite (LAPACK potrf's info) */
static PetscErrorCode InterfaceEliminateSeparator(M2dCondensed *cs, const PetscScalar *SG, PetscBLASInt *pivot)
{
  const RowSplit *sp = &cs->split;
  DenseInterface *di = &cs->iface;
  PetscInt        ns = sp->nsep, N = sp->nmult, nl = sp->nl, l0 = sp->l0, G = ns + N;
  PetscMPIInt     size, *counts, *displ;
  PetscBLASInt    bs, bn, bN;
  PetscScalar     one = 1.0, mone = -1.0;
  const PetscInt *lr;

  PetscFunctionBeginUser;
  *pivot = 0;
  PetscCall(PetscMalloc1(nl * N + 1, &di->S0));
  for (PetscInt j = 0; j < N; j++)
    for (PetscInt i = 0; i < nl; i++) di->S0[i + j * nl] = SG[(ns + l0 + i) + (ns + j) * G];
  if (ns == 0) PetscFunctionReturn(0);
  PetscCall(PetscBLASIntCast(ns, &bs));
  PetscCall(PetscBLASIntCast(nl, &bn));
  PetscCall(PetscBLASIntCast(N, &bN));
  PetscCall(PetscMalloc3(ns * ns, &di->L, ns * N + 1, &di->X, ns, &di->z));
  for (PetscInt j = 0; j < ns; j++)
    for (PetscInt i = 0; i < ns; i++) di->L[i + j * ns] = i >= j ? SG[i + j * G] : 0.0;
  PetscCallBLAS("LAPACKpotrf", LAPACKpotrf_("L", &bs, di->L, &bs, pivot));
  if (*pivot != 0) PetscFunctionReturn(0); /* the same on every rank: SG is */
  /* this rank's columns of X, then all of them */
  for (PetscInt j = 0; j < nl; j++)
    for (PetscInt i = 0; i < ns; i++) di->X[i + (l0 + j) * ns] = SG[i + (ns + l0 + j) * G];
  if (nl > 0) PetscCallBLAS("BLAStrsm", BLAStrsm_("L", "L", "N", "N", &bs, &bn, &one, di->L, &bs, di->X + l0 * ns, &bs));
  PetscCallMPI(MPI_Comm_size(cs->comm, &size));
  PetscCall(MatGetOwnershipRanges(cs->C, &lr));
  PetscCall(PetscMalloc2(size, &counts, size, &displ));
  for (PetscMPIInt p = 0; p < size; p++) {
    PetscCall(PetscMPIIntCast((lr[p + 1] - lr[p]) * ns, &counts[p]));
    PetscCall(PetscMPIIntCast(lr[p] * ns, &displ[p]));
  }
  PetscCallMPI(MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, di->X, counts, displ, MPIU_SCALAR, cs->comm));
  PetscCall(PetscFree2(counts, displ));
  if (nl > 0 && N > 0) PetscCallBLAS("BLASgemm", BLASgemm_("T", "N", &bn, &bN, &bs, &mone, di->X + l0 * ns, &bs, di->X, &bs, &one, di->S0, &bn));
  PetscCall(PetscLogFlops(ns * (PetscLogDouble)ns * ns / 3.0 + ns * (PetscLogDouble)ns * nl + 2.0 * nl * N * ns));
  PetscFunctionReturn(0);
}

/* bytes this node has for new allocations (MemAvailable; M2D_TEST_MEMORY_MB
 * overrides it for the tests in a build with -DM2D_TEST_HOOKS=ON), or -1 when unknown */
static double AvailableBytes(void)
{
  FILE  *f;
  char   line[256];
  double kb = -1;

#if defined(M2D_TEST_HOOKS)
  if (getenv("M2D_TEST_MEMORY_MB")) return 1048576.0 * atof(getenv("M2D_TEST_MEMORY_MB"));
#endif
  if (!(f = fopen("/proc/meminfo", "r"))) return -1;
  while (fgets(line, sizeof(line), f))
    if (sscanf(line, "MemAvailable: %lf kB", &kb) == 1) break;
  fclose(f);
  return kb < 0 ? -1 : 1024 * kb;
}

/* bytes as a number of MB below 1 GB, else of GB (*unit) */
static double InUnits(double bytes, const char **unit)
{
  *unit = bytes < 1073741824.0 ? "MB" : "GB";
  return bytes / (bytes < 1073741824.0 ? 1048576.0 : 1073741824.0);
}

/* The dense interface (G = separator rows + multipliers unknowns, on every
 * rank) peaks at about six G x G arrays per rank (measured: 20,510
 * multipliers on one rank, 19.9 GB = 5.9 x 8 G^2; MUMPS' Schur front and its
 * copy, S_G, the multiplier block, the Jacobian's rows and LU). Refused in one
 * line before it is allocated when the ranks of this node would need more
 * than it has: the kernel would kill the run without a word. */
static PetscErrorCode CheckDenseMemory(const M2dCondensed *cs)
{
  PetscInt    G = cs->split.nsep + cs->split.nmult;
  double      need = 6.0 * sizeof(PetscScalar) * (double)G * (double)G, have = AvailableBytes();
  MPI_Comm    node;
  PetscMPIInt pernode;
  const char *uneed, *uhave;
  double      vneed, vhave;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_split_type(cs->comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node));
  PetscCallMPI(MPI_Comm_size(node, &pernode));
  PetscCallMPI(MPI_Comm_free(&node));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &have, 1, MPI_DOUBLE, MPI_MIN, cs->comm));
  vneed = InUnits(need, &uneed);
  vhave = InUnits(have, &uhave);
  PetscCheck(have < 0 || need * pernode <= have, cs->comm, PETSC_ERR_MEM, "-kkt_path condensed: the dense interface of %" PetscInt_FMT " unknowns (%" PetscInt_FMT " separator rows, %" PetscInt_FMT " contact multipliers) needs about %.3g %s on each of the %d ranks of this node, more than the %.3g %s it has free; use -kkt_path full (MUMPS on the sparse KKT matrix) or -kkt_path iterative", G, cs->split.nsep, cs->split.nmult, vneed, uneed, (int)pernode, vhave, uhave);
  PetscFunctionReturn(0);
}

/* MUMPS' condensation of [f; 0]: every rank eliminates its interior, the
 * interface right-hand side g is summed over the ranks, the separator is
 * eliminated, z = L^-1 g_s (kept for the expansions), and what is left on
 * the multipliers is g_l - X^T z = -C K_g^-1 f = -w */
static PetscErrorCode CondenseLoad(M2dCondensed *cs, Vec f)
{
  const RowSplit    *sp = &cs->split;
  LocalFactor       *lf = &cs->local;
  DenseInterface    *di = &cs->iface;
  PetscInt           ns = sp->nsep, G = ns + sp->nmult, nI = sp->ninterior;
  PetscScalar       *g  = di->g, *w, one = 1.0;
  const PetscScalar *fa;
  PetscBLASInt       bs, ione = 1;
  PetscMPIInt        cnt;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(f, &fa));
  for (PetscInt i = 0; i < sp->u1 - sp->u0; i++)
    if (sp->row[i].kind == UNKNOWN_INTERIOR) lf->f_local[sp->row[i].index] = fa[i];
  for (PetscInt k = 0; k < lf->nschur; k++) lf->f_local[nI + k] = 0.0;
  PetscCall(PetscArraycpy(lf->rhs, lf->f_local, nI + lf->nschur));
  PetscCall(M2dMumpsSolve(lf->mumps, M2D_MUMPS_CONDENSE, lf->rhs, lf->red));
  lf->condensed = PETSC_TRUE;
  for (PetscInt k = 0; k < G; k++) g[k] = 0.0;
  for (PetscInt k = 0; k < lf->nschur; k++) g[lf->schur_iface[k]] += lf->red[k];
  for (PetscInt i = 0; i < sp->u1 - sp->u0; i++) /* f of the own separator rows (the multipliers' right-hand side is 0) */
    if (sp->row[i].kind == UNKNOWN_SEPARATOR) g[sp->row[i].index] += fa[i];
  PetscCall(VecRestoreArrayRead(f, &fa));
  PetscCall(PetscMPIIntCast(G, &cnt));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, g, cnt, MPIU_SCALAR, MPIU_SUM, cs->comm));
  if (ns > 0) {
    PetscCall(PetscBLASIntCast(ns, &bs));
    PetscCallBLAS("BLAStrsm", BLAStrsm_("L", "L", "N", "N", &bs, &ione, &one, di->L, &bs, g, &bs));
    PetscCall(PetscArraycpy(di->z, g, ns));
  }
  if (!cs->w) PetscCall(MatCreateVecs(cs->C, NULL, &cs->w));
  PetscCall(VecGetArrayWrite(cs->w, &w));
  for (PetscInt i = 0; i < sp->nl; i++) {
    const PetscScalar *x = di->X ? di->X + (sp->l0 + i) * ns : NULL; /* column l0 + i of X */
    PetscScalar        t = g[ns + sp->l0 + i];
    for (PetscInt k = 0; k < ns; k++) t -= x[k] * g[k];
    w[i] = -t;
  }
  PetscCall(VecRestoreArrayWrite(cs->w, &w));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedCreate(Mat Kg, Mat C, Mat Ct, Vec f, PetscReal gamma, const M2dCondensedOptions *opt, M2dCondensed **csp)
{
  M2dCondensed  *cs;
  PetscScalar   *S, *SG;
  PetscBLASInt   pivot;
  PetscInt       N;
  PetscLogDouble t0 = MPI_Wtime();

  PetscFunctionBeginUser;
  PetscCall(M2dLogRegister()); /* once; the events are logging.c's */
  PetscCall(PetscNew(&cs));
  *csp     = cs;
  cs->comm = PetscObjectComm((PetscObject)Kg);
  cs->Kg   = Kg;
  cs->C    = C;
  cs->Ct   = Ct;
  PetscCall(PetscObjectReference((PetscObject)Kg));
  PetscCall(PetscObjectReference((PetscObject)C));
  PetscCall(PetscObjectReference((PetscObject)Ct));
  cs->gamma = gamma;
  cs->ldlt  = opt->ldlt;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_COND_ORDER], 0, 0, 0, 0));
  PetscCall(RowSplitCreate(Kg, C, &cs->split));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_COND_ORDER], 0, 0, 0, 0));
  N = cs->split.nmult;
  PetscCall(PetscInfo(NULL, "interface: %" PetscInt_FMT " separator rows, %" PetscInt_FMT " multipliers; this rank: %" PetscInt_FMT " interior rows\n", cs->split.nsep, N, cs->split.ninterior));
  PetscCall(CheckDenseMemory(cs));
  PetscCall(FactorLocal(cs, opt, &S));
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_INTERFACE], 0, 0, 0, 0));
  PetscCall(InterfaceAssemble(cs, S, &SG));
  PetscCall(InterfaceEliminateSeparator(cs, SG, &pivot));
  PetscCall(PetscFree(SG));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_INTERFACE], 0, 0, 0, 0));
  PetscCheck(pivot == 0, cs->comm, PETSC_ERR_USER_INPUT, "the stiffness with every candidate contact node tied is singular: a body is held by nothing (check -dirichlet and the contact pair; separator pivot %d)", (int)pivot);
  cs->info.factor_time        = MPI_Wtime() - t0;
  cs->info.separator_rows     = cs->split.nsep;
  cs->info.multipliers        = N;
  cs->info.interface_unknowns = cs->split.nsep + N;

  PetscCall(PetscMalloc3(cs->split.ninterior + cs->local.nschur + 1, &cs->local.f_local, cs->split.ninterior + cs->local.nschur + 1, &cs->local.rhs, cs->local.nschur + 1, &cs->local.red));
  PetscCall(PetscMalloc1(cs->split.nsep + N + 1, &cs->iface.g));
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MUMPS_SOLVE], 0, 0, 0, 0));
  PetscCall(CondenseLoad(cs, f));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MUMPS_SOLVE], 0, 0, 0, 0));
  PetscCall(VecScatterCreateToAll(cs->w, &cs->to_all, &cs->all));
  PetscCall(PetscMalloc2(N * N + 1, &cs->jac.lu, N + 1, &cs->jac.piv));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedCreateFromKKT(const M2dKKT *kkt, const M2dScene *s, M2dCondensed **cs)
{
  M2dCondensedOptions opt;

  PetscFunctionBeginUser;
  PetscCheck(kkt->gamma > 0 && kkt->Kblk && kkt->C && kkt->Ct, PetscObjectComm((PetscObject)kkt->K), PETSC_ERR_PLIB, "condensed path needs the augmented KKT blocks");
  opt.ldlt            = s->kkt_ldlt;
  opt.ordering        = s->kkt_ordering; /* auto resolved by ProblemCreate */
  opt.mumps.output    = s->icntl4;
  opt.mumps.ordering  = s->icntl7;
  opt.mumps.scaling   = s->icntl8;
  opt.mumps.workspace = s->icntl14;
  opt.mumps.symbolic  = s->icntl58;
  PetscCall(CondensedCreate(kkt->Kblk, kkt->C, kkt->Ct, kkt->f, kkt->gamma, &opt, cs));
  PetscFunctionReturn(0);
}

/* the whole of a multiplier vector on every rank, in cs->all */
static PetscErrorCode GatherAll(M2dCondensed *cs, Vec v)
{
  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(cs->to_all, v, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(cs->to_all, v, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedGaps(M2dCondensed *cs, Vec nu, Vec cu)
{
  const PetscScalar *v, *w, *S0 = cs->iface.S0;
  PetscScalar       *y;
  PetscInt           n = cs->split.nl, N = cs->split.nmult;

  PetscFunctionBeginUser;
  PetscCall(GatherAll(cs, nu));
  PetscCall(VecGetArrayRead(cs->all, &v));
  PetscCall(VecGetArrayRead(cs->w, &w));
  PetscCall(VecGetArrayWrite(cu, &y));
  for (PetscInt i = 0; i < n; i++) y[i] = w[i];
  for (PetscInt j = 0; j < N; j++) /* column-major: y += S0(:, j) nu_j */
    for (PetscInt i = 0; i < n; i++) y[i] += S0[i + j * n] * v[j];
  PetscCall(VecRestoreArrayWrite(cu, &y));
  PetscCall(VecRestoreArrayRead(cs->w, &w));
  PetscCall(VecRestoreArrayRead(cs->all, &v));
  PetscCall(PetscLogFlops(2.0 * n * N));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedJacobian(M2dCondensed *cs, Vec active, PetscReal c, PetscReal h, Mat J)
{
  const PetscScalar *a, *S0 = cs->iface.S0;
  PetscScalar       *Jv;
  PetscInt           n = cs->split.nl, N = cs->split.nmult, l0 = cs->split.l0, ldj;
  PetscReal          g = cs->gamma;

  PetscFunctionBeginUser;
  PetscCall(MatDenseGetLDA(J, &ldj));
  PetscCall(VecGetArrayRead(active, &a));
  PetscCall(MatDenseGetArrayWrite(J, &Jv));
  for (PetscInt j = 0; j < N; j++)
    for (PetscInt i = 0; i < n; i++) {
      PetscScalar s = S0[i + j * n];
      Jv[i + j * ldj] = PetscRealPart(a[i]) != 0 ? c * h * s : -h * (g * s + (l0 + i == j ? 1.0 : 0.0));
    }
  PetscCall(MatDenseRestoreArrayWrite(J, &Jv));
  PetscCall(VecRestoreArrayRead(active, &a));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedSetLoad(M2dCondensed *cs, Vec f)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MUMPS_SOLVE], 0, 0, 0, 0));
  PetscCall(CondenseLoad(cs, f));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MUMPS_SOLVE], 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* every rank: the whole J, gathered by rows (row-major = J^T column-major), LU of J^T */
PetscErrorCode CondensedJacobianFactor(M2dCondensed *cs, Mat J, const PetscInt partner[], const PetscReal rule[], const PetscReal coef[], PetscReal c, PetscReal h)
{
  PetscMPIInt        size, nr, *counts, *displ;
  const PetscScalar *Jv;
  PetscScalar       *rows;
  PetscInt           n = cs->split.nl, N = cs->split.nmult, ldj;
  PetscBLASInt       bN, info;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(cs->comm, &size));
  PetscCall(PetscMalloc3(n * N + 1, &rows, size, &counts, size, &displ));
  PetscCall(MatDenseGetLDA(J, &ldj));
  PetscCall(MatDenseGetArrayRead(J, &Jv));
  for (PetscInt i = 0; i < n; i++)
    for (PetscInt j = 0; j < N; j++) rows[i * N + j] = Jv[i + j * ldj];
  PetscCall(MatDenseRestoreArrayRead(J, &Jv));
  PetscCall(PetscMPIIntCast(n * N, &nr));
  PetscCallMPI(MPI_Allgather(&nr, 1, MPI_INT, counts, 1, MPI_INT, cs->comm));
  displ[0] = 0;
  for (PetscMPIInt p = 1; p < size; p++) displ[p] = displ[p - 1] + counts[p - 1];
  PetscCallMPI(MPI_Allgatherv(rows, nr, MPIU_SCALAR, cs->jac.lu, counts, displ, MPIU_SCALAR, cs->comm));
  PetscCall(PetscFree3(rows, counts, displ));
  for (PetscInt j = 0; partner && j < N; j++) { /* the slipping rows' coupling to their normal rows */
    PetscInt     p = partner[j];
    PetscScalar *Jj = cs->jac.lu + j * N, *Jp;
    if (p < 0 || rule[j] != 0 || coef[j] == 0) continue;
    Jp = cs->jac.lu + p * N;
    for (PetscInt k = 0; k < N; k++) Jj[k] += coef[j] * (cs->gamma + c) / c * Jp[k];
    Jj[p] += h * coef[j];
  }
  PetscCall(PetscBLASIntCast(N, &bN));
  if (N > 0) {
    PetscCallBLAS("LAPACKgetrf", LAPACKgetrf_(&bN, &bN, cs->jac.lu, &bN, cs->jac.piv, &info));
    PetscCheck(info == 0, cs->comm, PETSC_ERR_NOT_CONVERGED, "the active-set Jacobian on the multipliers is singular (LAPACK getrf info %d)", (int)info);
  }
  PetscCall(PetscLogFlops(2.0 * N * N * N / 3.0));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedJacobianSolve(M2dCondensed *cs, Vec b, Vec x)
{
  PetscScalar  *v, *xv;
  PetscBLASInt  bN, one = 1, info;
  PetscInt      N = cs->split.nmult;

  PetscFunctionBeginUser;
  PetscCall(GatherAll(cs, b));
  PetscCall(PetscBLASIntCast(N, &bN));
  PetscCall(VecGetArray(cs->all, &v));
  if (N > 0) PetscCallBLAS("LAPACKgetrs", LAPACKgetrs_("T", &bN, &one, cs->jac.lu, &bN, cs->jac.piv, v, &bN, &info));
  PetscCall(VecGetArrayWrite(x, &xv));
  for (PetscInt i = 0; i < cs->split.nl; i++) xv[i] = v[cs->split.l0 + i];
  PetscCall(VecRestoreArrayWrite(x, &xv));
  PetscCall(VecRestoreArray(cs->all, &v));
  PetscCall(PetscLogFlops(2.0 * N * N));
  PetscFunctionReturn(0);
}

/* u(nu): the separator from the interface, x_s = L^-T (z - X nu), then every
 * rank's interior by MUMPS' expansion phase from x_s, nu and the condensed
 * right-hand side: f (condensed again first when an earlier recovery has
 * consumed it), or zero without the load (z = 0 then) */
PetscErrorCode CondensedRecover(M2dCondensed *cs, PetscBool load, Vec nu, Vec u)
{
  const RowSplit    *sp = &cs->split;
  LocalFactor       *lf = &cs->local;
  DenseInterface    *di = &cs->iface;
  PetscInt           ns = sp->nsep, N = sp->nmult, nI = sp->ninterior;
  PetscScalar       *g  = di->g, *ua, one = 1.0, mone = -1.0;
  const PetscScalar *v;
  PetscBLASInt       bs, bN, ione = 1;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_MUMPS_SOLVE], 0, 0, 0, 0));
  if (!load) {
    PetscCall(PetscArrayzero(lf->rhs, nI + lf->nschur));
    PetscCall(M2dMumpsSolve(lf->mumps, M2D_MUMPS_CONDENSE, lf->rhs, lf->red));
  } else if (!lf->condensed) {
    PetscCall(PetscArraycpy(lf->rhs, lf->f_local, nI + lf->nschur));
    PetscCall(M2dMumpsSolve(lf->mumps, M2D_MUMPS_CONDENSE, lf->rhs, lf->red));
  }
  PetscCall(GatherAll(cs, nu));
  PetscCall(VecGetArrayRead(cs->all, &v));
  if (ns > 0) {
    PetscCall(PetscBLASIntCast(ns, &bs));
    PetscCall(PetscBLASIntCast(N, &bN));
    if (load) PetscCall(PetscArraycpy(g, di->z, ns));
    else PetscCall(PetscArrayzero(g, ns));
    if (N > 0) PetscCallBLAS("BLASgemv", BLASgemv_("N", &bs, &bN, &mone, di->X, &bs, v, &ione, &one, g, &ione));
    PetscCallBLAS("BLAStrsm", BLAStrsm_("L", "L", "T", "N", &bs, &ione, &one, di->L, &bs, g, &bs));
  }
  for (PetscInt j = 0; j < N; j++) g[ns + j] = v[j];
  PetscCall(VecRestoreArrayRead(cs->all, &v));
  for (PetscInt k = 0; k < lf->nschur; k++) lf->red[k] = g[lf->schur_iface[k]];
  PetscCall(M2dMumpsSolve(lf->mumps, M2D_MUMPS_EXPAND, lf->rhs, lf->red));
  lf->condensed = PETSC_FALSE;
  PetscCall(VecGetArrayWrite(u, &ua));
  for (PetscInt i = 0; i < sp->u1 - sp->u0; i++) ua[i] = sp->row[i].kind == UNKNOWN_INTERIOR ? lf->rhs[sp->row[i].index] : g[sp->row[i].index];
  PetscCall(VecRestoreArrayWrite(u, &ua));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_MUMPS_SOLVE], 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedGetInfo(const M2dCondensed *cs, M2dCondensedInfo *info)
{
  PetscFunctionBeginUser;
  *info = cs->info;
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedDestroy(M2dCondensed **csp)
{
  M2dCondensed *cs = *csp;

  PetscFunctionBeginUser;
  if (!cs) PetscFunctionReturn(0);
  PetscCall(M2dMumpsDestroy(&cs->local.mumps));
  PetscCall(PetscFree(cs->local.schur_iface));
  PetscCall(PetscFree3(cs->local.f_local, cs->local.rhs, cs->local.red));
  PetscCall(PetscFree3(cs->iface.L, cs->iface.X, cs->iface.z));
  PetscCall(PetscFree(cs->iface.S0));
  PetscCall(PetscFree(cs->iface.g));
  PetscCall(PetscFree2(cs->jac.lu, cs->jac.piv));
  PetscCall(RowSplitDestroy(&cs->split));
  PetscCall(VecDestroy(&cs->w));
  PetscCall(VecDestroy(&cs->all));
  PetscCall(VecScatterDestroy(&cs->to_all));
  PetscCall(MatDestroy(&cs->Kg));
  PetscCall(MatDestroy(&cs->C));
  PetscCall(MatDestroy(&cs->Ct));
  PetscCall(PetscFree(*csp));
  PetscFunctionReturn(0);
}
