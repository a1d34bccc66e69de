/* condensed_rows.h - the rows of M = [K_g C^T; C 0] for the condensed path
 * (condensed.h): how they are split among the ranks (interior rows,
 * separator, multipliers), a reader of one row at a time, and this rank's
 * sparse matrix and ordering for MUMPS. The lower layer of condensed.c:
 * condensed_rows.c knows nothing of the factorization. Private. */
#ifndef M2D_CONDENSED_ROWS_H
#define M2D_CONDENSED_ROWS_H
#include "m2dmumps.h"
#include "ordering.h"

/* What one of this rank's rows of M, or a column met in them, is */
typedef enum {
  UNKNOWN_INTERIOR,   /* index: its row in this rank's MUMPS matrix (0 .. ninterior-1) */
  UNKNOWN_SEPARATOR,  /* index: its separator number (0 .. nsep-1, rank by rank) */
  UNKNOWN_MULTIPLIER, /* index: the multiplier (row of C, 0 .. nmult-1) */
  UNKNOWN_FOREIGN     /* an interior row of another rank (only ever a column) */
} UnknownKind;

typedef struct {
  UnknownKind kind;
  PetscInt    index;
} Unknown;

/* The split of the rows: the interface is the separator (numbered first) and
 * the multipliers (then, in the order of C's rows) */
typedef struct {
  PetscInt  u0, u1;    /* this rank's u rows: [u0, u1) of K_g */
  PetscInt  l0, nl;    /* this rank's multipliers: [l0, l0 + nl) of C's rows */
  PetscInt  nmult;     /* multipliers, all ranks */
  PetscInt  nsep;      /* separator rows, all ranks */
  PetscInt  ninterior; /* this rank's interior rows */
  Unknown  *row;       /* this rank's u rows (u1 - u0 of them), then its multipliers (nl) */
  PetscInt *sep_rows;  /* the K_g row of every separator row, ascending, on every rank */
} RowSplit;

/* interface index (separator, then multipliers) of a separator row or multiplier */
static inline PetscInt InterfaceIndex(const RowSplit *sp, Unknown x)
{
  return x.kind == UNKNOWN_SEPARATOR ? x.index : sp->nsep + x.index;
}

/* One of this rank's rows of M at a time, its columns classified (no
 * assembled copy of M: K_g and C^T give the u rows, C the multiplier rows;
 * the (multiplier, multiplier) block of M is zero) */
typedef struct {
  Mat             Kg, C, Ct;
  const RowSplit *split;
  PetscInt        n, cap; /* entries of the current row; room */
  struct {
    Unknown     col;
    PetscScalar val;
  } *ent;
} RowReader;

PetscErrorCode RowSplitCreate(Mat Kg, Mat C, RowSplit *sp);
PetscErrorCode RowSplitDestroy(RowSplit *sp);
/* a reader of the rows of M = [K_g, C^T; C, 0] as split by sp (borrowed) */
PetscErrorCode RowReaderCreate(Mat Kg, Mat C, Mat Ct, const RowSplit *sp, RowReader *rr);
/* this rank's row i of M (its u rows first, then its multipliers) */
PetscErrorCode RowReaderGet(RowReader *rr, PetscInt i);
PetscErrorCode RowReaderDestroy(RowReader *rr);
/* this rank's MUMPS matrix (its interior rows, then the interface unknowns
 * they couple to) as 1-based triples, one triangle when ldlt; *nschur and
 * *schur_iface (allocated here): those interface unknowns. Collective. */
PetscErrorCode LocalMatrixCreate(MPI_Comm comm, Mat Kg, Mat C, Mat Ct, const RowSplit *sp, PetscBool ldlt, PetscInt *nschur, PetscInt **schur_iface, PetscInt64 *nnz, M2dMumpsInt **irn, M2dMumpsInt **jcn, PetscScalar **a);
/* METIS pivot order of this rank's interior (NULL without METIS or interior),
 * the nschur Schur variables last; after LocalMatrixCreate */
PetscErrorCode LocalOrdering(MPI_Comm comm, Mat Kg, const RowSplit *sp, PetscInt nschur, M2dOrdering ord, M2dMumpsInt **perm);
#endif
