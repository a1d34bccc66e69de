/* ordering.c - METIS nested dissection for MUMPS (see ordering.h). */
#include "ordering.h"
#include <metis.h>

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

PetscErrorCode M2dOrderingMetis(Mat A, IS last, IS *pos)
{
  const PetscInt *ia, *ja;
  PetscInt        n, *xr = NULL, *adj = NULL, *grp, *gstart, ng = 0, *out, cnt = 0;
  PetscBool       done, seq;
  idx_t           nv, *xadj, *gadj, *vwgt, *perm, *iperm, opts[METIS_NOPTIONS];
  PetscInt        nadj = 0, *stamp;
  int             rc;
  static PetscLogEvent ev = 0;

  PetscFunctionBeginUser;
  if (!ev) PetscCall(PetscLogEventRegister("M2dMetisOrder", MAT_CLASSID, &ev));
  PetscCall(PetscObjectBaseTypeCompare((PetscObject)A, MATSEQAIJ, &seq));
  PetscCheck(seq, PetscObjectComm((PetscObject)A), PETSC_ERR_SUP, "option -kkt_ordering metis: needs a sequential AIJ matrix (one rank)");
  PetscCall(PetscLogEventBegin(ev, A, 0, 0, 0));
  PetscCall(MatGetRowIJ(A, 0, PETSC_TRUE, PETSC_FALSE, &n, &ia, &ja, &done));
  PetscCheck(done, PETSC_COMM_SELF, PETSC_ERR_SUP, "option -kkt_ordering metis: the matrix gives no row structure");
  PetscCall(ClosedRows(n, ia, ja, &xr, &adj));
  PetscCall(MatRestoreRowIJ(A, 0, PETSC_TRUE, PETSC_FALSE, &n, &ia, &ja, &done));
  PetscCall(MatGetSize(A, &n, NULL));

  /* group consecutive rows with the same closed neighbourhood; rows in `last` stay out (-1) */
  PetscCall(PetscMalloc3(n, &grp, n + 1, &gstart, n, &stamp));
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

  /* the quotient graph, vertex weight = rows in the group */
  PetscCall(PetscMalloc3(ng + 1, &xadj, ng, &vwgt, xr[n], &gadj));
  for (PetscInt g = 0; g < ng; g++) stamp[g] = -1;
  xadj[0] = 0;
  for (PetscInt g = 0; g < ng; g++) {
    PetscInt r = gstart[g], sz = 0;
    for (PetscInt i = r; i < n && grp[i] == g; i++) sz++;
    vwgt[g]  = (idx_t)sz;
    stamp[g] = g;
    for (PetscInt k = xr[r]; k < xr[r + 1]; k++) {
      PetscInt h = grp[adj[k]];
      if (h < 0 || stamp[h] == g) continue;
      stamp[h]       = g;
      gadj[nadj++] = (idx_t)h;
    }
    xadj[g + 1] = (idx_t)nadj;
  }
  PetscCall(PetscFree(xr));
  PetscCall(PetscFree(adj));

  PetscCall(PetscMalloc2(ng, &perm, ng, &iperm));
  nv = (idx_t)ng;
  METIS_SetDefaultOptions(opts);
  opts[METIS_OPTION_NUMBERING] = 0;
  {
    double t0 = MPI_Wtime();
    rc = ng > 0 ? METIS_NodeND(&nv, xadj, gadj, vwgt, opts, perm, iperm) : METIS_OK;
    PetscCall(PetscInfo(A, "METIS_NodeND: %" PetscInt_FMT " vertices for %" PetscInt_FMT " rows, %g s\n", ng, n, MPI_Wtime() - t0));
  }
  PetscCheck(rc == METIS_OK, PETSC_COMM_SELF, PETSC_ERR_LIB, "option -kkt_ordering metis: METIS_NodeND failed (%d)", rc);

  /* expand: the rows of a group keep their order; `last` rows at the end */
  PetscCall(PetscMalloc1(n, &out));
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
  PetscCall(PetscFree2(perm, iperm));
  PetscCall(PetscFree3(xadj, vwgt, gadj));
  PetscCall(PetscFree3(grp, gstart, stamp));
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

PetscErrorCode M2dOrderingSetupKSP(KSP ksp, M2dOrdering ord, PetscBool *applied)
{
  static PetscBool registered = PETSC_FALSE;
  PC               pc;
  PetscBool        lu, mumps = PETSC_FALSE;
  PetscMPIInt      size;
  MatSolverType    st;

  PetscFunctionBeginUser;
  if (applied) *applied = PETSC_FALSE;
  if (ord != M2D_ORDERING_METIS) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)ksp), &size));
  if (size > 1) PetscFunctionReturn(0);
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCLU, &lu));
  if (!lu) PetscFunctionReturn(0);
  PetscCall(PCFactorGetMatSolverType(pc, &st));
  if (st) PetscCall(PetscStrcmp(st, MATSOLVERMUMPS, &mumps));
  if (!mumps) PetscFunctionReturn(0);
  if (!registered) {
    PetscCall(MatOrderingRegister(MATORDERINGM2DMETIS, MatGetOrdering_M2dMetis));
    registered = PETSC_TRUE;
  }
  PetscCall(PCFactorSetMatOrderingType(pc, MATORDERINGM2DMETIS));
  if (applied) *applied = PETSC_TRUE;
  PetscFunctionReturn(0);
}
