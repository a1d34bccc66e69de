/* elimination.c - slaves and groups of the contact rows, and the rows of P
 * and E for an active set (see elimination.h). */
#include "elimination.h"

/* the sorted distinct columns of R and, per column, how many rows hold it (a
 * row holds a column whose entry is above 1e-10 of the row's largest: the
 * dual basis leaves round-off where D is zero) and whether it is a Dirichlet
 * dof (of any rank) */
static PetscErrorCode ColumnCensus(MPI_Comm comm, const M2dContactRows *R, PetscInt ndir, const PetscInt drows[], PetscInt *ncol, PetscInt **cols, PetscInt **rows_with, PetscInt **dirichlet)
{
  PetscInt nnz = R->ptr[R->n], n = nnz, *last;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nnz + 1, cols));
  PetscCall(PetscArraycpy(*cols, R->col, nnz));
  PetscCall(PetscSortRemoveDupsInt(&n, *cols));
  PetscCall(PetscCalloc2(n + 1, rows_with, n + 1, dirichlet));
  PetscCall(PetscMalloc1(n + 1, &last));
  for (PetscInt k = 0; k < n; k++) last[k] = -1;
  for (PetscInt j = 0; j < R->n; j++) {
    PetscReal rowmax = 0;
    for (PetscInt k = R->ptr[j]; k < R->ptr[j + 1]; k++) rowmax = PetscMax(rowmax, PetscAbsReal(R->val[k]));
    for (PetscInt k = R->ptr[j]; k < R->ptr[j + 1]; k++) {
      PetscInt i;
      if (!(PetscAbsReal(R->val[k]) > 1e-10 * rowmax)) continue;
      PetscCall(PetscFindInt(R->col[k], n, *cols, &i));
      if (last[i] != j) (*rows_with)[i]++, last[i] = j;
    }
  }
  for (PetscInt d = 0; d < ndir; d++) {
    PetscInt i;
    PetscCall(PetscFindInt(drows[d], n, *cols, &i));
    if (i >= 0) (*dirichlet)[i] = 1;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, *dirichlet, (PetscMPIInt)n, MPIU_INT, MPI_MAX, comm));
  PetscCall(PetscFree(last));
  *ncol = n;
  PetscFunctionReturn(0);
}

/* C's rows (C = -B, Dirichlet columns zeroed: kkt.h) and each row's slave:
 * among its unknowns within a tenth of its largest, the one the fewest rows
 * hold (the non-mortar node's own dof: with dual multipliers no other row
 * holds it), the largest of those, not taken by an earlier row. The same on
 * every rank (R is). */
static PetscErrorCode ChooseSlaves(M2dElimination *el, const M2dContactRows *R, PetscInt ndir, const PetscInt drows[])
{
  PetscInt *cols, *rows_with, *dir, *taken, ncol;

  PetscFunctionBeginUser;
  PetscCall(ColumnCensus(el->comm, R, ndir, drows, &ncol, &cols, &rows_with, &dir));
  el->nrow = R->n;
  PetscCall(PetscMalloc4(R->n + 1, &el->slave, R->n + 1, &el->rowptr, R->ptr[R->n] + 1, &el->rowcol, R->ptr[R->n] + 1, &el->rowval));
  PetscCall(PetscCalloc1(ncol + 1, &taken));
  el->rowptr[0] = 0;
  for (PetscInt j = 0; j < R->n; j++) {
    PetscReal rowmax = 0, best = 0;
    PetscInt  ibest = -1;
    for (PetscInt k = R->ptr[j]; k < R->ptr[j + 1]; k++) {
      PetscInt i;
      PetscCall(PetscFindInt(R->col[k], ncol, cols, &i));
      el->rowcol[k] = R->col[k];
      el->rowval[k] = dir[i] ? 0.0 : -R->val[k];
      rowmax        = PetscMax(rowmax, PetscAbsReal(el->rowval[k]));
    }
    for (PetscInt k = R->ptr[j]; k < R->ptr[j + 1]; k++) {
      PetscInt  i;
      PetscReal a = PetscAbsReal(el->rowval[k]);
      PetscCall(PetscFindInt(R->col[k], ncol, cols, &i));
      if (taken[i] || !(a >= 0.1 * rowmax) || a == 0) continue;
      if (ibest < 0 || rows_with[i] < rows_with[ibest] || (rows_with[i] == rows_with[ibest] && a > best)) ibest = i, best = a;
    }
    PetscCheck(ibest >= 0, el->comm, PETSC_ERR_USER_INPUT, "option -kkt_path iterative: the contact row of non-mortar node %" PetscInt_FMT " has no free unknown to eliminate (its dofs are held by supports); use -kkt_path condensed", R->node[j]);
    taken[ibest]      = 1;
    el->slave[j]      = cols[ibest];
    el->rowptr[j + 1] = R->ptr[j + 1];
  }
  PetscCall(PetscFree(taken));
  PetscCall(PetscFree(cols));
  PetscCall(PetscFree2(rows_with, dir));
  PetscFunctionReturn(0);
}

static PetscInt Root(PetscInt *parent, PetscInt j)
{
  while (parent[j] != j) j = parent[j] = parent[parent[j]];
  return j;
}

/* Groups: rows j and i are eliminated together when row j holds row i's
 * slave (above 1e-10 of its largest entry); each group's columns. */
static PetscErrorCode FormGroups(M2dElimination *el, const M2dContactRows *R)
{
  PetscInt *parent, *sorted, *srow, *cnt, n = el->nrow, big = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc4(n + 1, &parent, n + 1, &sorted, n + 1, &srow, n + 1, &cnt));
  for (PetscInt j = 0; j < n; j++) parent[j] = j, sorted[j] = el->slave[j], srow[j] = j;
  PetscCall(PetscSortIntWithArray(n, sorted, srow));
  for (PetscInt j = 0; j < n; j++) {
    PetscReal rowmax = 0;
    for (PetscInt k = el->rowptr[j]; k < el->rowptr[j + 1]; k++) rowmax = PetscMax(rowmax, PetscAbsReal(el->rowval[k]));
    for (PetscInt k = el->rowptr[j]; k < el->rowptr[j + 1]; k++) {
      PetscInt i;
      if (!(PetscAbsReal(el->rowval[k]) > 1e-10 * rowmax)) continue;
      PetscCall(PetscFindInt(el->rowcol[k], n, sorted, &i));
      if (i >= 0) parent[Root(parent, srow[i])] = Root(parent, j);
    }
  }
  /* number the groups by their first row; rows grouped in order */
  for (PetscInt j = 0; j < n; j++) cnt[j] = 0, sorted[j] = -1;
  el->ngroup = 0;
  for (PetscInt j = 0; j < n; j++) {
    PetscInt r = Root(parent, j);
    if (sorted[r] < 0) sorted[r] = el->ngroup++;
    cnt[sorted[r]]++;
  }
  PetscCall(PetscMalloc2(el->ngroup + 1, &el->gptr, n + 1, &el->grow));
  el->gptr[0] = 0;
  for (PetscInt g = 0; g < el->ngroup; g++) el->gptr[g + 1] = el->gptr[g] + cnt[g], big = PetscMax(big, cnt[g]);
  for (PetscInt g = 0; g < el->ngroup; g++) cnt[g] = el->gptr[g];
  for (PetscInt j = 0; j < n; j++) el->grow[cnt[sorted[Root(parent, j)]]++] = j;
  PetscCheck(big <= M2D_GROUP_MAX, el->comm, PETSC_ERR_USER_INPUT, "option -kkt_path iterative: %" PetscInt_FMT " contact rows are coupled through the unknowns they give (standard mortar multipliers couple neighbouring nodes); use -mortar_basis dual or -contact_method nts, or -kkt_path condensed", big);
  PetscCall(PetscFree4(parent, sorted, srow, cnt));
  /* each group's columns */
  PetscCall(PetscMalloc2(el->ngroup + 1, &el->gcptr, R->ptr[n] + 1, &el->gcol));
  el->gcptr[0] = 0;
  for (PetscInt g = 0; g < el->ngroup; g++) {
    PetscInt m = 0, *gc = el->gcol + el->gcptr[g];
    for (PetscInt q = el->gptr[g]; q < el->gptr[g + 1]; q++)
      for (PetscInt k = el->rowptr[el->grow[q]]; k < el->rowptr[el->grow[q] + 1]; k++) gc[m++] = el->rowcol[k];
    PetscCall(PetscSortRemoveDupsInt(&m, gc));
    el->gcptr[g + 1] = el->gcptr[g] + m;
  }
  PetscFunctionReturn(0);
}

/* X = A^-1 for a k x k row-major A (k <= M2D_GROUP_MAX), Gauss-Jordan with
 * partial pivoting; FALSE when a pivot falls below 1e-12 of the largest entry */
static PetscBool Invert(PetscInt k, PetscReal A[], PetscReal X[])
{
  PetscReal amax = 0;
  for (PetscInt i = 0; i < k * k; i++) amax = PetscMax(amax, PetscAbsReal(A[i]));
  for (PetscInt i = 0; i < k; i++)
    for (PetscInt m = 0; m < k; m++) X[i * k + m] = i == m;
  for (PetscInt c = 0; c < k; c++) {
    PetscInt  p = c;
    PetscReal piv;
    for (PetscInt i = c + 1; i < k; i++)
      if (PetscAbsReal(A[i * k + c]) > PetscAbsReal(A[p * k + c])) p = i;
    if (!(PetscAbsReal(A[p * k + c]) > 1e-12 * amax)) return PETSC_FALSE;
    for (PetscInt m = 0; m < k; m++) {
      PetscReal ta = A[c * k + m], tx = X[c * k + m];
      A[c * k + m] = A[p * k + m], X[c * k + m] = X[p * k + m];
      A[p * k + m] = ta, X[p * k + m] = tx;
    }
    piv = A[c * k + c];
    for (PetscInt m = 0; m < k; m++) A[c * k + m] /= piv, X[c * k + m] /= piv;
    for (PetscInt i = 0; i < k; i++) {
      PetscReal f = A[i * k + c];
      if (i == c || f == 0) continue;
      for (PetscInt m = 0; m < k; m++) A[i * k + m] -= f * A[c * k + m], X[i * k + m] -= f * X[c * k + m];
    }
  }
  return PETSC_TRUE;
}

PetscErrorCode M2dEliminationGroupRows(const M2dElimination *el, PetscInt g, const PetscScalar on[], PetscInt lo, PetscInt hi, Mat P, Mat E, PetscBool *singular)
{
  PetscInt   nr = el->gptr[g + 1] - el->gptr[g], nc = el->gcptr[g + 1] - el->gcptr[g], k = 0, act[M2D_GROUP_MAX];
  PetscInt  *gc = el->gcol + el->gcptr[g], *gr = el->grow + el->gptr[g];
  PetscReal  Cs[M2D_GROUP_MAX * M2D_GROUP_MAX], X[M2D_GROUP_MAX * M2D_GROUP_MAX], *Ca, *prow, erow[M2D_GROUP_MAX];

  PetscFunctionBeginUser;
  for (PetscInt q = 0; q < nr; q++)
    if (on && PetscRealPart(on[gr[q]]) != 0) act[k++] = q;
  PetscCall(PetscCalloc2(M2D_GROUP_MAX * nc, &Ca, nc, &prow));
  for (PetscInt a = 0; a < k; a++) { /* C[A, group columns] */
    PetscInt j = gr[act[a]];
    for (PetscInt q = el->rowptr[j]; q < el->rowptr[j + 1]; q++) {
      PetscInt i;
      PetscCall(PetscFindInt(el->rowcol[q], nc, gc, &i));
      Ca[a * nc + i] += el->rowval[q];
    }
  }
  for (PetscInt a = 0; a < k; a++)
    for (PetscInt b = 0; b < k; b++) {
      PetscInt i;
      PetscCall(PetscFindInt(el->slave[gr[act[b]]], nc, gc, &i));
      Cs[a * k + b] = Ca[a * nc + i];
    }
  if (k > 0 && !Invert(k, Cs, X)) {
    *singular = PETSC_TRUE;
    k         = 0;
  }
  for (PetscInt q = 0; q < nr; q++) {
    PetscInt s = el->slave[gr[q]], m = -1;
    if (s < lo || s >= hi) continue;
    for (PetscInt a = 0; a < k; a++)
      if (act[a] == q) m = a;
    for (PetscInt i = 0; i < nc; i++) {
      PetscBool in_s = PETSC_FALSE;
      prow[i]        = 0;
      if (m < 0) {
        prow[i] = gc[i] == s ? 1.0 : 0.0;
        continue;
      }
      for (PetscInt b = 0; b < k; b++) in_s = (PetscBool)(in_s || gc[i] == el->slave[gr[act[b]]]);
      if (!in_s)
        for (PetscInt a = 0; a < k; a++) prow[i] -= X[m * k + a] * Ca[a * nc + i];
    }
    for (PetscInt p = 0; p < nr; p++) erow[p] = 0;
    for (PetscInt a = 0; m >= 0 && a < k; a++) erow[act[a]] = X[m * k + a];
    PetscCall(MatSetValues(P, 1, &s, nc, gc, prow, INSERT_VALUES));
    PetscCall(MatSetValues(E, 1, &s, nr, gr, erow, INSERT_VALUES));
  }
  PetscCall(PetscFree2(Ca, prow));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dEliminationCreate(MPI_Comm comm, const M2dContactRows *R, PetscInt ndir, const PetscInt drows[], M2dElimination *el)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(el, sizeof(*el)));
  el->comm = comm;
  PetscCall(ChooseSlaves(el, R, ndir, drows));
  PetscCall(FormGroups(el, R));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dEliminationDestroy(M2dElimination *el)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree4(el->slave, el->rowptr, el->rowcol, el->rowval));
  PetscCall(PetscFree2(el->gptr, el->grow));
  PetscCall(PetscFree2(el->gcptr, el->gcol));
  PetscFunctionReturn(0);
}
