/* condensed_rows.c - how the rows of M = [K_g C^T; C 0] are split among the
 * ranks (interior rows, separator, multipliers: condensed.h) and this rank's
 * sparse matrix for MUMPS (condensed_rows.h). */
#include "condensed_rows.h"
#include "util.h"

/* this rank's u rows coupled to a u row of a higher rank (none on one rank) */
static PetscErrorCode OwnSeparator(Mat Kg, PetscInt u0, PetscInt u1, PetscInt *nsep, PetscInt sep[])
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  *nsep = 0;
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)Kg), &size));
  if (size == 1) PetscFunctionReturn(0);
  for (PetscInt r = u0; r < u1; r++) {
    PetscInt        nc;
    const PetscInt *cols;
    PetscBool       coupled = PETSC_FALSE;
    PetscCall(MatGetRow(Kg, r, &nc, &cols, NULL));
    for (PetscInt k = nc - 1; k >= 0 && !coupled; k--) coupled = (PetscBool)(cols[k] >= u1);
    PetscCall(MatRestoreRow(Kg, r, &nc, &cols, NULL));
    if (coupled) sep[(*nsep)++] = r;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode RowSplitCreate(Mat Kg, Mat C, RowSplit *sp)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)Kg);
  PetscMPIInt size, rank, nown, *counts, *displ;
  PetscInt    nsep_own, *sep, nu, next_sep = 0, sep0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sp, sizeof(*sp)));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(MatGetOwnershipRange(Kg, &sp->u0, &sp->u1));
  PetscCall(MatGetOwnershipRange(C, &sp->l0, NULL));
  PetscCall(MatGetLocalSize(C, &sp->nl, NULL));
  PetscCall(MatGetSize(C, &sp->nmult, NULL));
  nu = sp->u1 - sp->u0;

  /* the separator: every rank's own part, then all of it on every rank */
  PetscCall(PetscMalloc1(nu + 1, &sep));
  PetscCall(OwnSeparator(Kg, sp->u0, sp->u1, &nsep_own, sep));
  PetscCall(PetscMPIIntCast(nsep_own, &nown));
  PetscCall(PetscMalloc2(size, &counts, size, &displ));
  PetscCallMPI(MPI_Allgather(&nown, 1, MPI_INT, counts, 1, MPI_INT, comm));
  displ[0] = 0;
  for (PetscMPIInt p = 1; p < size; p++) displ[p] = displ[p - 1] + counts[p - 1];
  sep0     = displ[rank];
  sp->nsep = displ[size - 1] + counts[size - 1];
  PetscCall(PetscMalloc1(sp->nsep + 1, &sp->sep_rows));
  PetscCallMPI(MPI_Allgatherv(sep, nown, MPIU_INT, sp->sep_rows, counts, displ, MPIU_INT, comm));
  PetscCall(PetscFree2(counts, displ));

  /* this rank's rows: interior or separator (u rows), then its multipliers */
  PetscCall(PetscMalloc1(nu + sp->nl + 1, &sp->row));
  for (PetscInt i = 0; i < nu; i++) {
    if (next_sep < nsep_own && sep[next_sep] == sp->u0 + i) {
      sp->row[i].kind  = UNKNOWN_SEPARATOR;
      sp->row[i].index = sep0 + next_sep++;
    } else {
      sp->row[i].kind  = UNKNOWN_INTERIOR;
      sp->row[i].index = sp->ninterior++;
    }
  }
  for (PetscInt k = 0; k < sp->nl; k++) {
    sp->row[nu + k].kind  = UNKNOWN_MULTIPLIER;
    sp->row[nu + k].index = sp->l0 + k;
  }
  PetscCall(PetscFree(sep));
  PetscFunctionReturn(0);
}

PetscErrorCode RowSplitDestroy(RowSplit *sp)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(sp->row));
  PetscCall(PetscFree(sp->sep_rows));
  PetscFunctionReturn(0);
}

PetscErrorCode RowReaderCreate(Mat Kg, Mat C, Mat Ct, const RowSplit *sp, RowReader *rr)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(rr, sizeof(*rr)));
  rr->Kg    = Kg;
  rr->C     = C;
  rr->Ct    = Ct;
  rr->split = sp;
  rr->cap   = 64;
  PetscCall(PetscMalloc1(rr->cap, &rr->ent));
  PetscFunctionReturn(0);
}

PetscErrorCode RowReaderDestroy(RowReader *rr)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(rr->ent));
  PetscFunctionReturn(0);
}

/* a column of K_g that is another rank's u row: its separator row, or foreign */
static PetscErrorCode ClassifyOther(const RowSplit *sp, PetscInt j, Unknown *x)
{
  PetscInt s;

  PetscFunctionBeginUser;
  PetscCall(PetscFindInt(j, sp->nsep, sp->sep_rows, &s));
  x->kind  = s >= 0 ? UNKNOWN_SEPARATOR : UNKNOWN_FOREIGN;
  x->index = s >= 0 ? s : j;
  PetscFunctionReturn(0);
}

/* append one row of block A (its columns are u rows, or multipliers) */
static PetscErrorCode AppendRow(RowReader *rr, Mat A, PetscInt row, PetscBool multiplier_cols)
{
  const RowSplit    *sp = rr->split;
  PetscInt           m;
  const PetscInt    *c;
  const PetscScalar *v;

  PetscFunctionBeginUser;
  PetscCall(MatGetRow(A, row, &m, &c, &v));
  if (rr->n + m > rr->cap) {
    rr->cap = 2 * (rr->n + m);
    PetscCall(PetscRealloc(rr->cap * sizeof(*rr->ent), &rr->ent));
  }
  for (PetscInt k = 0; k < m; k++, rr->n++) {
    Unknown *x = &rr->ent[rr->n].col;
    if (multiplier_cols) {
      x->kind  = UNKNOWN_MULTIPLIER;
      x->index = c[k];
    } else if (c[k] >= sp->u0 && c[k] < sp->u1) *x = sp->row[c[k] - sp->u0];
    else PetscCall(ClassifyOther(sp, c[k], x));
    rr->ent[rr->n].val = v[k];
  }
  PetscCall(MatRestoreRow(A, row, &m, &c, &v));
  PetscFunctionReturn(0);
}

PetscErrorCode RowReaderGet(RowReader *rr, PetscInt i)
{
  const RowSplit *sp = rr->split;
  PetscInt        nu = sp->u1 - sp->u0;

  PetscFunctionBeginUser;
  rr->n = 0;
  if (i < nu) { /* [K_g C^T] */
    PetscCall(AppendRow(rr, rr->Kg, sp->u0 + i, PETSC_FALSE));
    PetscCall(AppendRow(rr, rr->Ct, sp->u0 + i, PETSC_TRUE));
  } else PetscCall(AppendRow(rr, rr->C, sp->l0 + i - nu, PETSC_FALSE)); /* [C 0] */
  PetscFunctionReturn(0);
}

/* One pass over the interior rows: count the triples (irn == NULL), or write
 * them. The interface unknowns get their local Schur numbers as met (first
 * pass). Symmetric storage keeps the upper triangle; else an entry between an
 * interior row and the interface is written twice (M is symmetric). */
static PetscErrorCode LocalTriples(RowReader *rr, PetscBool ldlt, PetscInt schur_of[], PetscInt *nschur, PetscInt schur_iface[], PetscInt64 *nnz, M2dMumpsInt irn[], M2dMumpsInt jcn[], PetscScalar a[], PetscBool *foreign)
{
  const RowSplit *sp = rr->split;
  PetscInt64      k  = 0;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < sp->u1 - sp->u0; i++) {
    Unknown r = sp->row[i];
    if (r.kind != UNKNOWN_INTERIOR) continue;
    PetscCall(RowReaderGet(rr, i));
    for (PetscInt e = 0; e < rr->n; e++) {
      Unknown     c = rr->ent[e].col;
      PetscInt    row = r.index + 1, col, g;
      PetscBool   both;
      if (c.kind == UNKNOWN_FOREIGN) {
        *foreign = PETSC_TRUE;
        continue;
      }
      if (c.kind == UNKNOWN_INTERIOR) {
        if (ldlt && c.index < r.index) continue;
        col  = c.index + 1;
        both = PETSC_FALSE;
      } else {
        g = InterfaceIndex(sp, c);
        if (schur_of[g] < 0) {
          schur_of[g]               = *nschur;
          schur_iface[(*nschur)++] = g;
        }
        col  = sp->ninterior + schur_of[g] + 1;
        both = (PetscBool)!ldlt;
      }
      if (irn) {
        irn[k] = (M2dMumpsInt)row;
        jcn[k] = (M2dMumpsInt)col;
        a[k]   = rr->ent[e].val;
      }
      k++;
      if (both) {
        if (irn) {
          irn[k] = (M2dMumpsInt)col;
          jcn[k] = (M2dMumpsInt)row;
          a[k]   = rr->ent[e].val;
        }
        k++;
      }
    }
  }
  *nnz = k;
  PetscFunctionReturn(0);
}

PetscErrorCode LocalMatrixCreate(MPI_Comm comm, Mat Kg, Mat C, Mat Ct, const RowSplit *sp, PetscBool ldlt, PetscInt *nschur, PetscInt **schur_iface, PetscInt64 *nnz, M2dMumpsInt **irn, M2dMumpsInt **jcn, PetscScalar **a)
{
  PetscInt        G  = sp->nsep + sp->nmult, *schur_of;
  PetscBool       foreign = PETSC_FALSE;
  RowReader       rr;

  PetscFunctionBeginUser;
  PetscCall(RowReaderCreate(Kg, C, Ct, sp, &rr));
  PetscCall(PetscMalloc1(G + 1, &schur_of));
  PetscCall(PetscMalloc1(G + 1, schur_iface));
  for (PetscInt g = 0; g < G; g++) schur_of[g] = -1;
  *nschur = 0;
  PetscCall(LocalTriples(&rr, ldlt, schur_of, nschur, *schur_iface, nnz, NULL, NULL, NULL, &foreign));
  PetscCall(M2dCheckCollective(comm, foreign, "condensed path: an interior row couples to another rank's interior"));
  PetscCall(PetscMalloc3(*nnz + 1, irn, *nnz + 1, jcn, *nnz + 1, a));
  for (PetscInt g = 0; g < G; g++) schur_of[g] = -1;
  *nschur = 0;
  PetscCall(LocalTriples(&rr, ldlt, schur_of, nschur, *schur_iface, nnz, *irn, *jcn, *a, &foreign));
  PetscCall(PetscFree(schur_of));
  PetscCall(RowReaderDestroy(&rr));
  PetscFunctionReturn(0);
}

PetscErrorCode LocalOrdering(MPI_Comm comm, Mat Kg, const RowSplit *sp, PetscInt nschur, M2dOrdering ord, M2dMumpsInt **perm)
{
  PetscInt        nu = sp->u1 - sp->u0, nI = sp->ninterior, nlast = 0, *last_rows;
  PetscMPIInt     size;
  Mat             Kd = Kg;
  IS              last, pos;
  const PetscInt *p;

  PetscFunctionBeginUser;
  *perm = NULL;
  if (ord != M2D_ORDERING_METIS || nI == 0) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size > 1) PetscCall(MatMPIAIJGetSeqAIJ(Kg, &Kd, NULL, NULL)); /* this rank's rows and columns */
  PetscCall(PetscMalloc1(nu - nI + 1, &last_rows));
  for (PetscInt i = 0; i < nu; i++) /* the separator rows stay out of the interior's order */
    if (sp->row[i].kind == UNKNOWN_SEPARATOR) last_rows[nlast++] = i;
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, nlast, last_rows, PETSC_OWN_POINTER, &last));
  PetscCall(M2dOrderingMetis(Kd, last, &pos));
  PetscCall(ISDestroy(&last));
  PetscCall(PetscMalloc1(nI + nschur + 1, perm));
  PetscCall(ISGetIndices(pos, &p));
  for (PetscInt i = 0; i < nu; i++) /* the interior comes first in METIS' order: positions 0 .. nI-1 */
    if (sp->row[i].kind == UNKNOWN_INTERIOR) (*perm)[sp->row[i].index] = (M2dMumpsInt)(p[i] + 1);
  PetscCall(ISRestoreIndices(pos, &p));
  PetscCall(ISDestroy(&pos));
  for (PetscInt k = 0; k < nschur; k++) (*perm)[nI + k] = (M2dMumpsInt)(nI + k + 1); /* the Schur variables last */
  PetscFunctionReturn(0);
}
