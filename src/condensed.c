/* condensed.c - factor once: every rank factors its own rows with its own
 * sequential MUMPS (dmumps_c) and a Schur complement on its interface, the
 * interface is dense and shared; the reduced iteration's algebra (see
 * condensed.h). */
#include "condensed.h"
#include <dmumps_c.h>
#include <petscblaslapack.h>

#define ICNTL(I) icntl[(I) - 1]
#define INFO(I)  info[(I) - 1]
#define INFOG(I) infog[(I) - 1]
#define RINFO(I) rinfo[(I) - 1]

struct M2dMumps {
  DMUMPS_STRUC_C id;
  MPI_Comm       comm;
};

static PetscLogEvent ev_order, ev_analysis, ev_factor, ev_iface, ev_solve;

static PetscErrorCode RegisterEvents(void)
{
  static PetscBool done = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (done) PetscFunctionReturn(0);
  PetscCall(PetscLogEventRegister("M2dCondOrder", MAT_CLASSID, &ev_order));
  PetscCall(PetscLogEventRegister("M2dMumpsAnalysis", MAT_CLASSID, &ev_analysis));
  PetscCall(PetscLogEventRegister("M2dMumpsFactor", MAT_CLASSID, &ev_factor));
  PetscCall(PetscLogEventRegister("M2dInterface", MAT_CLASSID, &ev_iface));
  PetscCall(PetscLogEventRegister("M2dMumpsSolve", MAT_CLASSID, &ev_solve));
  done = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* One MUMPS phase of every rank's own instance (mu = NULL: this rank has no
 * part in it). Collective on comm: the ranks agree on the outcome, so that a
 * failure on one rank stops them all with the same message. */
static PetscErrorCode MumpsCall(MPI_Comm comm, M2dMumps *mu, int job, const char *what)
{
  int st = 0, worst, st2 = PETSC_MIN_INT, worst2;

  PetscFunctionBeginUser;
  if (mu) {
    mu->id.job = job;
    dmumps_c(&mu->id);
    st = (int)mu->id.INFOG(1);
  }
  PetscCallMPI(MPI_Allreduce(&st, &worst, 1, MPI_INT, MPI_MIN, comm));
  if (worst >= 0) PetscFunctionReturn(0);
  if (st == worst) st2 = (int)mu->id.INFOG(2);
  PetscCallMPI(MPI_Allreduce(&st2, &worst2, 1, MPI_INT, MPI_MAX, comm));
  if (worst == -10 && job == 2) SETERRQ(comm, PETSC_ERR_USER_INPUT, "the stiffness with every candidate contact node tied is singular: a body is held by nothing (check -dirichlet and the contact pair)");
  SETERRQ(comm, PETSC_ERR_LIB, "MUMPS %s failed: INFOG(1) = %d, INFOG(2) = %d%s", what, worst, worst2, worst == -9 ? " (raise -mat_mumps_icntl_14)" : "");
}

/* The rows of [K_g C^T; C Z], read from the nest's blocks (no assembled copy
 * on this path). This rank's rows: its u rows (local 0..nu-1), then its
 * multiplier rows. A column comes back as its class: the interior index of
 * an own row (>= 0), -1 - its interface index, or M2D_OTHER_INTERIOR (an
 * interior row of another rank). */
#define M2D_OTHER_INTERIOR PETSC_MIN_INT
typedef struct {
  Mat             blk[4]; /* (u,u) (u,l) (l,u) (l,l) */
  PetscInt        u0, u1, l0, nu, nl;
  PetscInt        ns;     /* separator rows (all ranks) ... */
  const PetscInt *sepall; /* ... their u rows, sorted */
  const PetscInt *lidx;   /* own rows: interior index, or -1 - interface index */
  PetscInt        cap, *cols;
  PetscScalar    *vals;
} KKTRows;

static PetscErrorCode KKTRowsGet(KKTRows *kr, PetscInt i, PetscInt *nc)
{
  PetscInt lam = i >= kr->nu, row = lam ? kr->l0 + i - kr->nu : kr->u0 + i, n = 0;

  PetscFunctionBeginUser;
  for (int b = 0; b < 2; b++) {
    Mat                M = kr->blk[2 * lam + b];
    PetscInt           m;
    const PetscInt    *c;
    const PetscScalar *v;
    PetscCall(MatGetRow(M, row, &m, &c, &v));
    if (n + m > kr->cap) { /* grow, then read this block again (MatRestoreRow zeroes m) */
      kr->cap = 2 * (n + m);
      PetscCall(MatRestoreRow(M, row, &m, &c, &v));
      PetscCall(PetscRealloc(kr->cap * sizeof(PetscInt), &kr->cols));
      PetscCall(PetscRealloc(kr->cap * sizeof(PetscScalar), &kr->vals));
      b--;
      continue;
    }
    for (PetscInt k = 0; k < m; k++, n++) {
      PetscInt j = c[k], s;
      if (b == 1) kr->cols[n] = -1 - (kr->ns + j); /* a multiplier */
      else if (j >= kr->u0 && j < kr->u1) kr->cols[n] = kr->lidx[j - kr->u0];
      else {
        PetscCall(PetscFindInt(j, kr->ns, kr->sepall, &s));
        kr->cols[n] = s >= 0 ? -1 - s : M2D_OTHER_INTERIOR;
      }
      kr->vals[n] = v[k];
    }
    PetscCall(MatRestoreRow(M, row, &m, &c, &v));
  }
  *nc = n;
  PetscFunctionReturn(0);
}

/* The interface: the multipliers, and on several ranks the separator, the
 * u rows of each rank coupled to a u row of a higher rank (the rows of the
 * other ranks' interiors then couple only to their own interior and to the
 * interface). Numbering: the separator rank by rank, then the multipliers in
 * the order of kkt->r. Sets kr (rows and classes) and cs->ns, nI, lidx. */
static PetscErrorCode Classify(M2dCondensed *cs, KKTRows *kr, PetscInt **sepall)
{
  M2dKKT            *kkt  = cs->kkt;
  MPI_Comm        comm = PetscObjectComm((PetscObject)kkt->Kblk);
  PetscMPIInt     size, rank, nn, *rc, *displ;
  const PetscInt *ur;
  PetscInt        nsep = 0, *sep, *lidx, ks = 0, sepoff, n;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(kr, sizeof(*kr)));
  kr->blk[0] = kkt->Kblk;
  kr->blk[1] = kkt->Ct;
  kr->blk[2] = kkt->CA;
  kr->blk[3] = kkt->Z;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(MatGetOwnershipRanges(kkt->Kblk, &ur));
  kr->u0 = ur[rank];
  kr->u1 = ur[rank + 1];
  kr->nu = kr->u1 - kr->u0;
  kr->l0 = cs->lo;
  kr->nl = cs->n;
  n      = kr->nu + kr->nl;
  PetscCall(PetscMalloc1(kr->nu + 1, &sep));
  PetscCall(PetscMalloc2(size, &rc, size, &displ));
  for (PetscInt i = 0; i < kr->nu && size > 1; i++) {
    PetscInt        nc;
    const PetscInt *cols;
    PetscBool       s = PETSC_FALSE;
    PetscCall(MatGetRow(kkt->Kblk, kr->u0 + i, &nc, &cols, NULL));
    for (PetscInt k = nc - 1; k >= 0 && !s; k--) s = (PetscBool)(cols[k] >= kr->u1); /* a u row of a higher rank */
    PetscCall(MatRestoreRow(kkt->Kblk, kr->u0 + i, &nc, &cols, NULL));
    if (s) sep[nsep++] = kr->u0 + i;
  }
  PetscCall(PetscMPIIntCast(nsep, &nn));
  PetscCallMPI(MPI_Allgather(&nn, 1, MPI_INT, rc, 1, MPI_INT, comm));
  displ[0] = 0;
  for (PetscMPIInt p = 1; p < size; p++) displ[p] = displ[p - 1] + rc[p - 1];
  sepoff = displ[rank];
  cs->ns = displ[size - 1] + rc[size - 1];
  PetscCall(PetscMalloc1(n + 1, &lidx));
  cs->nI = 0;
  for (PetscInt i = 0; i < n; i++) {
    if (i >= kr->nu) lidx[i] = -1 - (cs->ns + kr->l0 + i - kr->nu);
    else if (ks < nsep && sep[ks] == kr->u0 + i) lidx[i] = -1 - (sepoff + ks++);
    else lidx[i] = cs->nI++;
  }
  cs->lidx = lidx;
  PetscCall(PetscMalloc1(cs->ns + 1, sepall)); /* the separator's u rows, on every rank */
  PetscCallMPI(MPI_Allgatherv(sep, nn, MPIU_INT, *sepall, rc, displ, MPIU_INT, comm));
  PetscCall(PetscFree(sep));
  PetscCall(PetscFree2(rc, displ));
  kr->ns     = cs->ns;
  kr->sepall = *sepall;
  kr->lidx   = lidx;
  kr->cap    = 64;
  PetscCall(PetscMalloc1(kr->cap, &kr->cols));
  PetscCall(PetscMalloc1(kr->cap, &kr->vals));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedCreate(M2dKKT *kkt, const M2dScene *s, M2dCondensed *cs)
{
  Mat             A    = kkt->Kblk; /* for the communicator and the log */
  MPI_Comm        comm = PetscObjectComm((PetscObject)A);
  PetscMPIInt     size, rank;
  M2dMumps       *mu = NULL;
  PetscInt        n, G, nI, ng = 0, *sepall = NULL, *gloc, nnz = 0, k = 0;
  const PetscInt *lr;
  MUMPS_INT      *irn = NULL, *jcn = NULL, *perm = NULL, *listvar = NULL;
  PetscScalar    *a = NULL, *Sp = NULL, *SG;
  PetscLogDouble  t0;
  KKTRows         kr;
  M2dOrdering     ord = s->kkt_ordering;
  int             sym = s->kkt_ldlt ? 2 : 0; /* LDL^T of the symmetric matrix, or LU */

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(cs, sizeof(*cs)));
  PetscCheck(kkt->gamma > 0 && kkt->Kblk && kkt->Ct && kkt->CA && kkt->Z, comm, PETSC_ERR_PLIB, "condensed path needs the augmented monolithic KKT matrix");
  PetscCall(RegisterEvents());
  cs->kkt = kkt;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));

  t0 = MPI_Wtime();
  /* the multipliers, in the order of kkt->r (rank by rank) */
  PetscCall(VecGetLocalSize(kkt->r, &cs->n));
  PetscCall(VecGetSize(kkt->r, &cs->N));
  PetscCall(VecGetOwnershipRange(kkt->r, &cs->lo, NULL));
  PetscCall(VecGetOwnershipRanges(kkt->r, &lr));

  /* interior rows and the interface; METIS orders the interior */
  PetscCall(PetscLogEventBegin(ev_order, A, 0, 0, 0));
  PetscCall(Classify(cs, &kr, &sepall));
  n  = kr.nu + kr.nl;
  nI = cs->nI;
  G  = cs->ns + cs->N;
  if (ord == M2D_ORDERING_METIS && nI > 0) {
    Mat             Ad = A;
    IS              last, posis;
    PetscInt       *lastidx, nlast = 0;
    const PetscInt *pos;
    if (size > 1) PetscCall(MatMPIAIJGetSeqAIJ(A, &Ad, NULL, NULL));
    PetscCall(PetscMalloc1(kr.nu - nI + 1, &lastidx));
    for (PetscInt i = 0; i < kr.nu; i++) /* the u rows: the separator stays out */
      if (cs->lidx[i] < 0) lastidx[nlast++] = i;
    PetscCall(ISCreateGeneral(PETSC_COMM_SELF, nlast, lastidx, PETSC_OWN_POINTER, &last));
    PetscCall(M2dOrderingMetis(Ad, last, &posis));
    PetscCall(ISDestroy(&last));
    PetscCall(PetscMalloc1(n + 1, &perm)); /* interior part; the interface is appended below */
    PetscCall(ISGetIndices(posis, &pos));
    for (PetscInt i = 0; i < kr.nu; i++)
      if (cs->lidx[i] >= 0) perm[cs->lidx[i]] = (MUMPS_INT)(pos[i] + 1);
    PetscCall(ISRestoreIndices(posis, &pos));
    PetscCall(ISDestroy(&posis));
  }
  PetscCall(PetscLogEventEnd(ev_order, A, 0, 0, 0));
  PetscCall(PetscInfo(NULL, "interface: %" PetscInt_FMT " separator rows, %" PetscInt_FMT " multipliers; this rank: %" PetscInt_FMT " interior rows\n", cs->ns, cs->N, nI));

  /* this rank's matrix: the interior rows, then the interface unknowns they
   * couple to (numbered as met: gloc, cs->glist), as 1-based triples */
  PetscCall(PetscMalloc1(G + 1, &gloc));
  PetscCall(PetscMalloc1(G + 1, &cs->glist));
  for (PetscInt g = 0; g < G; g++) gloc[g] = -1;
  for (int pass = 0; pass < 2; pass++) {
    if (pass == 1) PetscCall(PetscMalloc3(nnz + 1, &irn, nnz + 1, &jcn, nnz + 1, &a));
    for (PetscInt i = 0; i < n; i++) {
      PetscInt           nc, li = cs->lidx[i];
      const PetscInt    *cols;
      const PetscScalar *v;
      if (li < 0) continue;
      PetscCall(KKTRowsGet(&kr, i, &nc));
      cols = kr.cols;
      v    = kr.vals;
      for (PetscInt j = 0; j < nc; j++) {
        PetscInt cl = cols[j];
        PetscCheck(cl != M2D_OTHER_INTERIOR, PETSC_COMM_SELF, PETSC_ERR_PLIB, "local row %" PetscInt_FMT " couples to another rank's interior row", i);
        if (cl >= 0) {
          if (sym && cl < li) continue; /* symmetric: the upper triangle */
          if (pass == 1) {
            irn[k] = (MUMPS_INT)(li + 1);
            jcn[k] = (MUMPS_INT)(cl + 1);
            a[k++] = v[j];
          } else nnz++;
        } else {
          PetscInt g = -1 - cl;
          if (pass == 0) {
            if (gloc[g] < 0) {
              gloc[g]        = ng;
              cs->glist[ng++] = g;
            }
            nnz += sym ? 1 : 2;
          } else {
            irn[k] = (MUMPS_INT)(li + 1);
            jcn[k] = (MUMPS_INT)(nI + gloc[g] + 1);
            a[k++] = v[j];
            if (!sym) {
              irn[k] = jcn[k - 1];
              jcn[k] = irn[k - 1];
              a[k++] = v[j];
            }
          }
        }
      }
    }
  }
  cs->ng = ng;
  if (perm) { /* the interface unknowns last */
    MUMPS_INT *p2;
    PetscCall(PetscMalloc1(nI + ng, &p2));
    PetscCall(PetscArraycpy(p2, perm, nI));
    for (PetscInt g = 0; g < ng; g++) p2[nI + g] = (MUMPS_INT)(nI + g + 1);
    PetscCall(PetscFree(perm));
    perm = p2;
  }

  /* every rank with interior rows: its own sequential MUMPS, the Schur
   * complement on its interface unknowns (-B A_II^-1 B^T, dense, ng x ng) */
  if (nI > 0) {
    PetscCall(PetscNew(&mu));
    PetscCallMPI(MPI_Comm_dup(PETSC_COMM_SELF, &mu->comm));
    mu->id.comm_fortran = (MUMPS_INT)MPI_Comm_c2f(mu->comm);
    mu->id.par          = 1;
    mu->id.sym          = (MUMPS_INT)sym;
  }
  cs->mumps = mu;
  PetscCall(MumpsCall(comm, mu, -1, "initialisation"));
  if (mu) {
    PetscBool out = (PetscBool)(s->icntl4 > 0 && rank == 0);
    mu->id.ICNTL(1)  = out ? 6 : -1;
    mu->id.ICNTL(2)  = -1;
    mu->id.ICNTL(3)  = out ? 6 : -1;
    mu->id.ICNTL(4)  = (MUMPS_INT)s->icntl4;
    mu->id.ICNTL(7)  = perm ? 1 : (MUMPS_INT)s->icntl7;
    mu->id.ICNTL(8)  = (MUMPS_INT)s->icntl8;
    mu->id.ICNTL(14) = (MUMPS_INT)s->icntl14;
    mu->id.ICNTL(18) = 0; /* the matrix on this rank, which is MUMPS' host */
    mu->id.ICNTL(19) = ng > 0 ? 1 : 0;
    mu->id.ICNTL(58) = (MUMPS_INT)s->icntl58;
    mu->id.n         = (MUMPS_INT)(nI + ng);
    mu->id.nnz       = (MUMPS_INT8)nnz;
    mu->id.irn       = irn;
    mu->id.jcn       = jcn;
    mu->id.a         = a;
    mu->id.perm_in   = perm;
    if (ng > 0) {
      PetscCall(PetscMalloc2(ng, &listvar, ng * ng, &Sp));
      for (PetscInt g = 0; g < ng; g++) listvar[g] = (MUMPS_INT)(nI + g + 1);
      mu->id.size_schur    = (MUMPS_INT)ng;
      mu->id.listvar_schur = listvar;
      mu->id.schur         = Sp;
      mu->id.schur_lld     = (MUMPS_INT)ng;
    }
  }
  PetscCall(PetscLogEventBegin(ev_analysis, A, 0, 0, 0));
  PetscCall(MumpsCall(comm, mu, 1, "analysis"));
  PetscCall(PetscLogEventEnd(ev_analysis, A, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_factor, A, 0, 0, 0));
  PetscCall(MumpsCall(comm, mu, 2, "factorization"));
  if (mu) {
    PetscCall(PetscLogFlops(mu->id.RINFO(3)));
    PetscCall(PetscInfo(NULL, "MUMPS on this rank: %" PetscInt_FMT " interior rows, %" PetscInt_FMT " interface unknowns, %g flops (RINFO(3))\n", nI, ng, (double)mu->id.RINFO(3)));
    mu->id.irn = mu->id.jcn = NULL;
    mu->id.a                = NULL;
    mu->id.perm_in          = NULL;
  }
  PetscCall(PetscFree3(irn, jcn, a)); /* the solves need neither the matrix nor the ordering */
  PetscCall(PetscFree(perm));
  PetscCall(PetscLogEventEnd(ev_factor, A, 0, 0, 0));

  /* the interface matrix S_G = A_GG + sum over ranks of their Schur
   * complements, dense (G x G), on every rank; then the separator is
   * eliminated: S0 = S_ll - X^T X, X = L^-1 S_sl, L L^T = S_ss */
  PetscCall(PetscLogEventBegin(ev_iface, A, 0, 0, 0));
  PetscCall(PetscCalloc1(G * G + 1, &SG));
  for (PetscInt p = 0; p < ng; p++) /* sym: MUMPS gives the lower triangle by rows */
    for (PetscInt q = 0; q < ng; q++) SG[cs->glist[p] + cs->glist[q] * G] += sym && q > p ? Sp[q * ng + p] : Sp[p * ng + q];
  for (PetscInt i = 0; i < n; i++) {
    PetscInt nc, li = cs->lidx[i];
    if (li >= 0) continue;
    PetscCall(KKTRowsGet(&kr, i, &nc));
    for (PetscInt j = 0; j < nc; j++) {
      PetscInt cl = kr.cols[j];
      if (cl < 0 && cl != M2D_OTHER_INTERIOR) SG[(-1 - li) + (-1 - cl) * G] += kr.vals[j];
    }
  }
  PetscCall(PetscFree2(listvar, Sp));
  if (mu) {
    mu->id.listvar_schur = NULL;
    mu->id.schur         = NULL;
  }
  for (PetscInt off = 0; off < G * G;) { /* MPI counts are int */
    PetscMPIInt cnt;
    PetscCall(PetscMPIIntCast(PetscMin(G * G - off, 1 << 30), &cnt));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, SG + off, cnt, MPIU_SCALAR, MPIU_SUM, comm));
    off += cnt;
  }
  PetscCall(PetscMalloc1(cs->n * cs->N + 1, &cs->S));
  for (PetscInt j = 0; j < cs->N; j++)
    for (PetscInt i = 0; i < cs->n; i++) cs->S[i + j * cs->n] = SG[(cs->ns + cs->lo + i) + (cs->ns + j) * G];
  if (cs->ns > 0) {
    PetscBLASInt bs, bG, bn, bN, info;
    PetscScalar  one = 1.0, mone = -1.0;
    PetscMPIInt *rcx, *dx;
    PetscCall(PetscBLASIntCast(cs->ns, &bs));
    PetscCall(PetscBLASIntCast(G, &bG));
    PetscCall(PetscBLASIntCast(cs->n, &bn));
    PetscCall(PetscBLASIntCast(cs->N, &bN));
    PetscCallBLAS("LAPACKpotrf", LAPACKpotrf_("L", &bs, SG, &bG, &info));
    PetscCheck(info == 0, comm, PETSC_ERR_USER_INPUT, "the stiffness with every candidate contact node tied is singular: a body is held by nothing (check -dirichlet and the contact pair; separator pivot %d)", (int)info);
    PetscCall(PetscMalloc2(cs->ns * cs->ns, &cs->L, cs->ns * cs->N + 1, &cs->X));
    for (PetscInt j = 0; j < cs->ns; j++)
      for (PetscInt i = 0; i < cs->ns; i++) cs->L[i + j * cs->ns] = i >= j ? SG[i + j * G] : 0.0;
    /* this rank's columns of X, then all of them */
    for (PetscInt j = 0; j < cs->n; j++)
      for (PetscInt i = 0; i < cs->ns; i++) cs->X[i + (cs->lo + j) * cs->ns] = SG[i + (cs->ns + cs->lo + j) * G];
    if (cs->n > 0) PetscCallBLAS("BLAStrsm", BLAStrsm_("L", "L", "N", "N", &bs, &bn, &one, cs->L, &bs, cs->X + cs->lo * cs->ns, &bs));
    PetscCall(PetscMalloc2(size, &rcx, size, &dx));
    for (PetscMPIInt p = 0; p < size; p++) {
      PetscCall(PetscMPIIntCast((lr[p + 1] - lr[p]) * cs->ns, &rcx[p]));
      PetscCall(PetscMPIIntCast(lr[p] * cs->ns, &dx[p]));
    }
    PetscCallMPI(MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, cs->X, rcx, dx, MPIU_SCALAR, comm));
    PetscCall(PetscFree2(rcx, dx));
    if (cs->n > 0 && cs->N > 0) PetscCallBLAS("BLASgemm", BLASgemm_("T", "N", &bn, &bN, &bs, &mone, cs->X + cs->lo * cs->ns, &bs, cs->X, &bs, &one, cs->S, &bn));
    PetscCall(PetscLogFlops(cs->ns * (PetscLogDouble)cs->ns * cs->ns / 3.0 + cs->ns * (PetscLogDouble)cs->ns * cs->n + 2.0 * cs->n * cs->N * cs->ns));
  }
  PetscCall(PetscFree(SG));
  PetscCall(PetscLogEventEnd(ev_iface, A, 0, 0, 0));
  PetscCall(PetscFree(gloc));
  PetscCall(PetscFree(sepall));
  PetscCall(PetscFree(kr.cols));
  PetscCall(PetscFree(kr.vals));
  cs->factor_time = MPI_Wtime() - t0;
  {
    double fl = mu ? (double)mu->id.RINFO(3) : 0.0;
    PetscCallMPI(MPI_Allreduce(&fl, &cs->flops_sum, 1, MPI_DOUBLE, MPI_SUM, comm));
    PetscCallMPI(MPI_Allreduce(&fl, &cs->flops_max, 1, MPI_DOUBLE, MPI_MAX, comm));
  }

  PetscCall(PetscMalloc3(nI + ng + 1, &cs->b, ng + 1, &cs->red, G + 1, &cs->g));
  PetscCall(VecScatterCreateToAll(kkt->r, &cs->toall, &cs->all));
  PetscCall(PetscMalloc2(cs->N * cs->N + 1, &cs->lu, cs->N + 1, &cs->piv));
  PetscFunctionReturn(0);
}

/* The solves with the factors (condensed.h). Phase 1, condensation of
 * [f; 0]: every rank eliminates its interior (MUMPS' forward phase,
 * ICNTL(26) = 1), the interface right-hand side g is summed over the ranks,
 * the separator is eliminated, and the reduced right-hand side of the
 * multipliers, -C K_g^-1 f = -w, is left in lam. Phase 2, expansion from the
 * multipliers nu (in lam): the separator x_s = S_ss^-1 (g_s - S_sl nu), then
 * every rank's interior (MUMPS' backward phase, ICNTL(26) = 2):
 * u = K_g^-1 (f - C^T nu). Phase 2 uses what phase 1 left (cs->b, cs->g). */
static PetscErrorCode SchurPhase(M2dCondensed *cs, int phase, Vec lam, Vec u)
{
  M2dMumps          *mu   = cs->mumps;
  MPI_Comm           comm = PetscObjectComm((PetscObject)cs->kkt->Kblk);
  PetscInt           n, nI = cs->nI, ng = cs->ng, ns = cs->ns, G = ns + cs->N;
  PetscScalar       *g = cs->g, one = 1.0, mone = -1.0;
  const PetscScalar *nu, *f = NULL;
  PetscBLASInt       bs, bN, ione = 1;
  PetscMPIInt        cnt;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(ev_solve, 0, 0, 0, 0));
  PetscCall(PetscBLASIntCast(ns, &bs));
  PetscCall(PetscBLASIntCast(cs->N, &bN));
  PetscCall(VecGetLocalSize(cs->kkt->f, &n)); /* the u rows: lidx[0..n) */
  if (phase == 1) {
    PetscCall(VecGetArrayRead(cs->kkt->f, &f));
    for (PetscInt i = 0; i < n; i++)
      if (cs->lidx[i] >= 0) cs->b[cs->lidx[i]] = f[i];
    for (PetscInt k = 0; k < ng; k++) cs->b[nI + k] = 0.0;
  } else {
    PetscCall(VecScatterBegin(cs->toall, lam, cs->all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(cs->toall, lam, cs->all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecGetArrayRead(cs->all, &nu));
    /* x_s = L^-T (z - X nu); phase 1 left z = L^-1 g_s in g */
    if (ns > 0) {
      if (cs->N > 0) PetscCallBLAS("BLASgemv", BLASgemv_("N", &bs, &bN, &mone, cs->X, &bs, nu, &ione, &one, g, &ione));
      PetscCallBLAS("BLAStrsm", BLAStrsm_("L", "L", "T", "N", &bs, &ione, &one, cs->L, &bs, g, &bs));
    }
    for (PetscInt j = 0; j < cs->N; j++) g[ns + j] = nu[j];
    PetscCall(VecRestoreArrayRead(cs->all, &nu));
    for (PetscInt k = 0; k < ng; k++) cs->red[k] = g[cs->glist[k]];
  }
  if (mu) {
    mu->id.rhs       = cs->b;
    mu->id.lrhs      = (MUMPS_INT)(nI + ng);
    mu->id.nrhs      = 1;
    mu->id.redrhs    = cs->red;
    mu->id.lredrhs   = (MUMPS_INT)PetscMax(ng, 1);
    mu->id.ICNTL(20) = 0; /* dense right-hand side */
    mu->id.ICNTL(21) = 0; /* solution in place */
    mu->id.ICNTL(26) = ng > 0 ? phase : 0;
  }
  /* a rank without interface unknowns solved all in phase 1 */
  PetscCall(MumpsCall(comm, mu && (ng > 0 || phase == 1) ? mu : NULL, 3, phase == 1 ? "solve (condensation)" : "solve (expansion)"));
  if (phase == 1) {
    const PetscScalar *lc;
    PetscScalar       *lv;
    for (PetscInt k = 0; k < G; k++) g[k] = 0.0;
    for (PetscInt k = 0; k < ng; k++) g[cs->glist[k]] += cs->red[k];
    for (PetscInt i = 0; i < n; i++) /* f on the own separator rows (0 on the multiplier rows) */
      if (cs->lidx[i] < 0) g[-1 - cs->lidx[i]] += f[i];
    PetscCall(VecRestoreArrayRead(cs->kkt->f, &f));
    PetscCall(PetscMPIIntCast(G, &cnt));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, g, cnt, MPIU_SCALAR, MPIU_SUM, comm));
    if (ns > 0) PetscCallBLAS("BLAStrsm", BLAStrsm_("L", "L", "N", "N", &bs, &ione, &one, cs->L, &bs, g, &bs)); /* z */
    /* -w = g_l - X^T z, this rank's rows */
    PetscCall(VecGetArray(lam, &lv));
    for (PetscInt i = 0; i < cs->n; i++) {
      PetscScalar t = g[ns + cs->lo + i];
      lc            = cs->X ? cs->X + (cs->lo + i) * ns : NULL;
      for (PetscInt k = 0; k < ns; k++) t -= lc[k] * g[k];
      lv[i] = t;
    }
    PetscCall(VecRestoreArray(lam, &lv));
  } else {
    PetscScalar *ua;
    PetscCall(VecGetArrayWrite(u, &ua));
    for (PetscInt i = 0; i < n; i++) ua[i] = cs->lidx[i] >= 0 ? cs->b[cs->lidx[i]] : g[-1 - cs->lidx[i]];
    PetscCall(VecRestoreArrayWrite(u, &ua));
  }
  PetscCall(PetscLogEventEnd(ev_solve, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedReducedSetup(M2dCondensed *cs)
{
  M2dKKT *kkt = cs->kkt;

  PetscFunctionBeginUser;
  PetscCheck(cs->S && !cs->w, PetscObjectComm((PetscObject)kkt->Kblk), PETSC_ERR_PLIB, "reduced iteration: one setup after the factorization");
  PetscCall(VecDuplicate(kkt->r, &cs->w));
  PetscCall(SchurPhase(cs, 1, cs->w, NULL)); /* -w */
  PetscCall(VecScale(cs->w, -1.0));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedReducedGaps(M2dCondensed *cs, Vec nu, Vec cu)
{
  const PetscScalar *v, *w;
  PetscScalar       *y;
  PetscInt           n = cs->n, N = cs->N;

  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(cs->toall, nu, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(cs->toall, nu, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecGetArrayRead(cs->all, &v));
  PetscCall(VecGetArrayRead(cs->w, &w));
  PetscCall(VecGetArray(cu, &y));
  for (PetscInt i = 0; i < n; i++) y[i] = w[i];
  for (PetscInt j = 0; j < N; j++) /* column-major: y += S(:, j) v_j */
    for (PetscInt i = 0; i < n; i++) y[i] += cs->S[i + j * n] * v[j];
  PetscCall(VecRestoreArray(cu, &y));
  PetscCall(VecRestoreArrayRead(cs->w, &w));
  PetscCall(VecRestoreArrayRead(cs->all, &v));
  PetscCall(PetscLogFlops(2.0 * n * N));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedReducedJacobian(M2dCondensed *cs, Vec active, PetscReal c, PetscReal h, Mat J)
{
  const PetscScalar *a;
  PetscScalar       *Jv;
  PetscInt           n = cs->n, N = cs->N, ldj;
  PetscReal          g = cs->kkt->gamma;

  PetscFunctionBeginUser;
  PetscCall(MatDenseGetLDA(J, &ldj));
  PetscCall(VecGetArrayRead(active, &a));
  PetscCall(MatDenseGetArrayWrite(J, &Jv));
  for (PetscInt j = 0; j < N; j++)
    for (PetscInt i = 0; i < n; i++) {
      PetscScalar s = cs->S[i + j * n];
      Jv[i + j * ldj] = PetscRealPart(a[i]) != 0 ? c * h * s : -h * (g * s + (cs->lo + i == j ? 1.0 : 0.0));
    }
  PetscCall(MatDenseRestoreArrayWrite(J, &Jv));
  PetscCall(VecRestoreArrayRead(active, &a));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* every rank: the whole J, gathered by rows (row-major = J^T column-major), LU of J^T */
PetscErrorCode CondensedDenseFactor(M2dCondensed *cs, Mat J)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)J);
  PetscMPIInt        size, nr, *rc, *displ;
  const PetscScalar *Jv;
  PetscScalar       *buf;
  PetscInt           n = cs->n, N = cs->N, ldj;
  PetscBLASInt       bn, info;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc3(n * N + 1, &buf, size, &rc, size, &displ));
  PetscCall(MatDenseGetLDA(J, &ldj));
  PetscCall(MatDenseGetArrayRead(J, &Jv));
  for (PetscInt i = 0; i < n; i++)
    for (PetscInt j = 0; j < N; j++) buf[i * N + j] = Jv[i + j * ldj];
  PetscCall(MatDenseRestoreArrayRead(J, &Jv));
  PetscCall(PetscMPIIntCast(n * N, &nr));
  PetscCallMPI(MPI_Allgather(&nr, 1, MPI_INT, rc, 1, MPI_INT, comm));
  displ[0] = 0;
  for (PetscMPIInt p = 1; p < size; p++) displ[p] = displ[p - 1] + rc[p - 1];
  PetscCallMPI(MPI_Allgatherv(buf, nr, MPIU_SCALAR, cs->lu, rc, displ, MPIU_SCALAR, comm));
  PetscCall(PetscFree3(buf, rc, displ));
  PetscCall(PetscBLASIntCast(N, &bn));
  if (N > 0) {
    PetscCallBLAS("LAPACKgetrf", LAPACKgetrf_(&bn, &bn, cs->lu, &bn, cs->piv, &info));
    PetscCheck(info == 0, comm, PETSC_ERR_NOT_CONVERGED, "reduced active-set Jacobian is singular (LAPACK getrf info %d)", (int)info);
  }
  PetscCall(PetscLogFlops(2.0 * N * N * N / 3.0));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedDenseSolve(M2dCondensed *cs, Vec b, Vec x)
{
  PetscScalar       *v;
  const PetscScalar *va;
  PetscBLASInt       bn, one = 1, info;

  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(cs->toall, b, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(cs->toall, b, cs->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(PetscBLASIntCast(cs->N, &bn));
  PetscCall(VecGetArray(cs->all, &v));
  if (cs->N > 0) PetscCallBLAS("LAPACKgetrs", LAPACKgetrs_("T", &bn, &one, cs->lu, &bn, cs->piv, v, &bn, &info));
  PetscCall(VecRestoreArray(cs->all, &v));
  PetscCall(VecGetArrayRead(cs->all, &va));
  {
    PetscScalar *xv;
    PetscCall(VecGetArray(x, &xv));
    for (PetscInt i = 0; i < cs->n; i++) xv[i] = va[cs->lo + i];
    PetscCall(VecRestoreArray(x, &xv));
  }
  PetscCall(VecRestoreArrayRead(cs->all, &va));
  PetscCall(PetscLogFlops(2.0 * cs->N * cs->N));
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedRecover(M2dCondensed *cs, Vec nu, Vec u)
{
  M2dKKT *kkt = cs->kkt;

  PetscFunctionBeginUser;
  PetscCheck(cs->w, PetscObjectComm((PetscObject)kkt->Kblk), PETSC_ERR_PLIB, "reduced iteration: recovery before the setup");
  PetscCall(SchurPhase(cs, 2, nu, u)); /* u = K_g^-1 (f - C^T nu) */
  PetscFunctionReturn(0);
}

PetscErrorCode CondensedDestroy(M2dCondensed *cs)
{
  PetscFunctionBeginUser;
  if (cs->mumps) {
    cs->mumps->id.job = -2;
    dmumps_c(&cs->mumps->id);
    PetscCallMPI(MPI_Comm_free(&cs->mumps->comm));
    PetscCall(PetscFree(cs->mumps));
  }
  PetscCall(VecDestroy(&cs->w));
  PetscCall(PetscFree(cs->S));
  PetscCall(PetscFree(cs->lidx));
  PetscCall(PetscFree(cs->glist));
  PetscCall(PetscFree2(cs->L, cs->X));
  PetscCall(PetscFree3(cs->b, cs->red, cs->g));
  PetscCall(PetscFree2(cs->lu, cs->piv));
  PetscCall(VecDestroy(&cs->all));
  PetscCall(VecScatterDestroy(&cs->toall));
  PetscFunctionReturn(0);
}
