/* ordering.c - METIS nested dissection for MUMPS (see ordering.h). */
#include "ordering.h"
#include "logging.h"
#include <metis.h>
#include "tempfile.h"

/* sorted closed neighbourhood of every row (the row itself included) */
static PetscErrorCode ClosedRows(PetscInt n, const PetscInt ia[], const PetscInt ja[], PetscInt **xr, PetscInt **adj)
{
  PetscInt *x, *a;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(n + 1, &x));
  PetscCall(PetscMalloc1(ia[n] + n, &a));
  x[0] = 0;
  for (PetscInt i = 0; i < n; i++) {
    PetscInt k = x[i], m;
    a[k++] = i;
    for (PetscInt j = ia[i]; j < ia[i + 1]; j++)
      if (ja[j] != i) a[k++] = ja[j];
    m = k - x[i];
    PetscCall(PetscSortRemoveDupsInt(&m, a + x[i]));
    x[i + 1] = x[i] + m;
  }
  *xr  = x;
  *adj = a;
  PetscFunctionReturn(0);
}

/* Group consecutive rows with the same closed neighbourhood (the two dofs of
 * a node); rows in `last` stay out (grp -1). Group g is rows gstart[g] ..
 * gstart[g + 1] - 1 (those with grp == g) */
static PetscErrorCode GroupRows(PetscInt n, const PetscInt xr[], const PetscInt adj[], IS last, PetscInt grp[], PetscInt gstart[], PetscInt *ngroups)
{
  PetscInt ng = 0;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n; i++) grp[i] = 0;
  if (last) {
    const PetscInt *il;
    PetscInt        nl;
    PetscCall(ISGetLocalSize(last, &nl));
    PetscCall(ISGetIndices(last, &il));
    for (PetscInt j = 0; j < nl; j++) grp[il[j]] = -1;
    PetscCall(ISRestoreIndices(last, &il));
  }
  for (PetscInt i = 0; i < n; i++) {
    PetscBool same = PETSC_FALSE;
    if (grp[i] < 0) continue;
    if (ng > 0 && i > 0 && grp[i - 1] == ng - 1) { /* the previous row is in the open group */
      PetscInt lead = gstart[ng - 1], len = xr[lead + 1] - xr[lead];
      if (len == xr[i + 1] - xr[i]) {
        same = PETSC_TRUE;
        for (PetscInt k = 0; k < len && same; k++) same = (PetscBool)(adj[xr[lead] + k] == adj[xr[i] + k]);
      }
    }
    if (!same) gstart[ng++] = i;
    grp[i] = ng - 1;
  }
  gstart[ng] = n;
  *ngroups   = ng;
  PetscFunctionReturn(0);
}

/* the graph of the groups for METIS; vertex weight = rows in the group */
static PetscErrorCode QuotientGraph(PetscInt n, const PetscInt xr[], const PetscInt adj[], const PetscInt grp[], const PetscInt gstart[], PetscInt ng, idx_t **xadj, idx_t **gadj, idx_t **vwgt)
{
  PetscInt *stamp, nadj = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc3(ng + 1, xadj, ng + 1, vwgt, xr[n] + 1, gadj));
  PetscCall(PetscMalloc1(ng + 1, &stamp));
  for (PetscInt g = 0; g < ng; g++) stamp[g] = -1;
  (*xadj)[0] = 0;
  for (PetscInt g = 0; g < ng; g++) {
    PetscInt r = gstart[g], sz = 0;
    for (PetscInt i = r; i < n && grp[i] == g; i++) sz++;
    (*vwgt)[g] = (idx_t)sz;
    stamp[g]   = g;
    for (PetscInt k = xr[r]; k < xr[r + 1]; k++) {
      PetscInt h = grp[adj[k]];
      if (h < 0 || stamp[h] == g) continue;
      stamp[h]        = g;
      (*gadj)[nadj++] = (idx_t)h;
    }
    (*xadj)[g + 1] = (idx_t)nadj;
  }
  PetscCall(PetscFree(stamp));
  PetscFunctionReturn(0);
}

/* position of every row: the groups in METIS' order (the rows of a group
 * keep theirs), then the `last` rows in their given order */
static PetscErrorCode ExpandOrder(PetscInt n, const PetscInt grp[], const PetscInt gstart[], PetscInt ng, const idx_t perm[], IS last, PetscInt out[])
{
  PetscInt cnt = 0;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < ng; k++) {
    PetscInt g = (PetscInt)perm[k];
    for (PetscInt i = gstart[g]; i < gstart[g + 1] && grp[i] == g; i++) out[i] = cnt++;
  }
  if (last) {
    const PetscInt *il;
    PetscInt        nl;
    PetscCall(ISGetLocalSize(last, &nl));
    PetscCall(ISGetIndices(last, &il));
    for (PetscInt j = 0; j < nl; j++) out[il[j]] = cnt++;
    PetscCall(ISRestoreIndices(last, &il));
  }
  PetscCheck(cnt == n, PETSC_COMM_SELF, PETSC_ERR_PLIB, "METIS ordering covers %" PetscInt_FMT " of %" PetscInt_FMT " rows", cnt, n);
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOrderingMetis(Mat A, IS last, IS *pos)
{
  const PetscInt *ia, *ja;
  PetscInt        n, *xr, *adj, *grp, *gstart, ng, *out;
  PetscBool       done, seq;
  idx_t           nv, *xadj, *gadj, *vwgt, *perm, *iperm, opts[METIS_NOPTIONS];
  int             rc;
  PetscLogEvent   ev;

  PetscFunctionBeginUser;
  PetscCall(M2dLogRegister());
  ev = M2dEvent[M2D_EV_METIS_ORDER];
  PetscCall(PetscObjectBaseTypeCompare((PetscObject)A, MATSEQAIJ, &seq));
  PetscCheck(seq, PetscObjectComm((PetscObject)A), PETSC_ERR_SUP, "option -kkt_ordering metis: needs a sequential AIJ matrix (one rank)");
  PetscCall(PetscLogEventBegin(ev, A, 0, 0, 0));
  PetscCall(MatGetRowIJ(A, 0, PETSC_TRUE, PETSC_FALSE, &n, &ia, &ja, &done));
  PetscCheck(done, PETSC_COMM_SELF, PETSC_ERR_SUP, "option -kkt_ordering metis: the matrix gives no row structure");
  PetscCall(ClosedRows(n, ia, ja, &xr, &adj));
  PetscCall(MatRestoreRowIJ(A, 0, PETSC_TRUE, PETSC_FALSE, &n, &ia, &ja, &done));
  PetscCall(MatGetSize(A, &n, NULL));
  PetscCall(PetscMalloc2(n + 1, &grp, n + 1, &gstart));
  PetscCall(PetscMalloc1(n + 1, &out)); /* owned by the IS */
  PetscCall(GroupRows(n, xr, adj, last, grp, gstart, &ng));
  PetscCall(QuotientGraph(n, xr, adj, grp, gstart, ng, &xadj, &gadj, &vwgt));
  PetscCall(PetscFree(xr));
  PetscCall(PetscFree(adj));

  PetscCall(PetscMalloc2(ng + 1, &perm, ng + 1, &iperm));
  nv = (idx_t)ng;
  METIS_SetDefaultOptions(opts);
  opts[METIS_OPTION_NUMBERING] = 0;
  rc = ng > 0 ? METIS_NodeND(&nv, xadj, gadj, vwgt, opts, perm, iperm) : METIS_OK;
  M2dMetisSignal((int)rc, METIS_ERROR); /* a SIGTERM that GKlib trapped */
  PetscCall(PetscInfo(A, "METIS_NodeND: %" PetscInt_FMT " vertices for %" PetscInt_FMT " rows\n", ng, n));
  PetscCall(PetscFree3(xadj, vwgt, gadj));
  if (rc == METIS_OK) PetscCall(ExpandOrder(n, grp, gstart, ng, perm, last, out));
  PetscCall(PetscFree2(perm, iperm));
  PetscCall(PetscFree2(grp, gstart));
  if (rc != METIS_OK) PetscCall(PetscFree(out));
  PetscCheck(rc == METIS_OK, PETSC_COMM_SELF, PETSC_ERR_LIB, "option -kkt_ordering metis: METIS_NodeND failed (%d)", rc);
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, out, PETSC_OWN_POINTER, pos));
  PetscCall(PetscLogEventEnd(ev, A, 0, 0, 0));
  PetscFunctionReturn(0);
}

static PetscErrorCode MatGetOrdering_M2dMetis(Mat A, MatOrderingType type, IS *row, IS *col)
{
  PetscFunctionBeginUser;
  (void)type;
  PetscCall(M2dOrderingMetis(A, NULL, row));
  PetscCall(ISDuplicate(*row, col));
  PetscFunctionReturn(0);
}

/* A PC that factors with MUMPS: its factor type, or MAT_FACTOR_NONE */
static PetscErrorCode MumpsFactorType(PC pc, MatFactorType *ft)
{
  PetscBool     lu, chol, mumps = PETSC_FALSE;
  MatSolverType st;

  PetscFunctionBeginUser;
  *ft = MAT_FACTOR_NONE;
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCLU, &lu));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCCHOLESKY, &chol));
  if (!lu && !chol) PetscFunctionReturn(0);
  PetscCall(PCFactorGetMatSolverType(pc, &st));
  if (st) PetscCall(PetscStrcmp(st, MATSOLVERMUMPS, &mumps));
  if (mumps) *ft = lu ? MAT_FACTOR_LU : MAT_FACTOR_CHOLESKY;
  PetscFunctionReturn(0);
}

/* MUMPS' AMF ordering (ICNTL(7) = 2) for a factorization PETSc hands no
 * ordering, unless -mat_mumps_icntl_7 is given. Set on the factor matrix
 * (MatMumpsSetIcntl), which PETSc 3.18 keeps on several ranks; on one rank
 * its sequential analysis first sets ICNTL(7) from the PC's ordering (7
 * without one) and only then reads the options database, so there the
 * database, under the PC's prefix, is the only way in (tests/test_ordering.c
 * checks the ordering MUMPS used, INFOG(7), on 1 and 2 ranks). */
static PetscErrorCode SetMumpsAMF(PC pc, MatFactorType ft)
{
  const char *prefix;
  char        name[256];
  PetscBool   given, set, avail;
  Mat         P, F;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCall(PCGetOptionsPrefix(pc, &prefix));
  PetscCall(PetscOptionsHasName(NULL, prefix, "-mat_mumps_icntl_7", &given));
  PetscCall(PCGetOperatorsSet(pc, NULL, &set));
  if (given || !set) PetscFunctionReturn(0);
  PetscCall(PCGetOperators(pc, NULL, &P));
  PetscCall(MatGetFactorAvailable(P, MATSOLVERMUMPS, ft, &avail));
  if (!avail) PetscFunctionReturn(0); /* e.g. a MatNest: KKTSetupKSP says what to do */
  PetscCall(PCFactorSetUpMatSolverType(pc));
  PetscCall(PCFactorGetMatrix(pc, &F));
  PetscCall(MatMumpsSetIcntl(F, 7, 2));
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)pc), &size));
  if (size == 1) {
    PetscCall(PetscSNPrintf(name, sizeof(name), "-%smat_mumps_icntl_7", prefix ? prefix : ""));
    PetscCall(PetscOptionsSetValue(NULL, name, "2"));
  }
  PetscFunctionReturn(0);
}

M2dOrdering M2dOrderingFor(M2dOrdering ord, PetscInt dofs, PetscMPIInt ranks)
{
  if (ord != M2D_ORDERING_AUTO) return ord;
  return ranks == 1 && dofs < M2D_ORDERING_AUTO_DOFS ? M2D_ORDERING_MUMPS : M2D_ORDERING_METIS;
}

PetscErrorCode M2dOrderingSetupKSP(KSP ksp, M2dOrdering ord, PetscBool *metis)
{
  PC            pc;
  MatFactorType ft;
  PetscMPIInt   size;

  PetscFunctionBeginUser;
  if (metis) *metis = PETSC_FALSE;
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(MumpsFactorType(pc, &ft));
  if (ft == MAT_FACTOR_NONE) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)ksp), &size));
  /* PETSc 3.18 hands MUMPS an ordering only for LU on one rank */
  if (ord == M2D_ORDERING_METIS && ft == MAT_FACTOR_LU && size == 1) {
    PetscCall(MatOrderingRegister(MATORDERINGM2DMETIS, MatGetOrdering_M2dMetis)); /* again: replaces */
    PetscCall(PCFactorSetMatOrderingType(pc, MATORDERINGM2DMETIS));
    if (metis) *metis = PETSC_TRUE;
  } else PetscCall(SetMumpsAMF(pc, ft));
  PetscFunctionReturn(0);
}
