/* condensed_impl.h - the condensed path's data (condensed.h), shared by
 * condensed.c (factor, dense interface, solves) and condensed_rows.c (how
 * the rows of M = [K_g C^T; C 0] are split, this rank's sparse matrix).
 * Private to those two files. */
#ifndef M2D_CONDENSED_IMPL_H
#define M2D_CONDENSED_IMPL_H
#include "condensed.h"
#include <petscblaslapack.h>

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

/* This rank's sparse factorization: its interior rows, then the interface
 * unknowns they couple to, whose Schur complement MUMPS returns */
typedef struct {
  M2dMumps    *mumps;
  PetscInt     nschur;      /* interface unknowns this rank's interior couples to ... */
  PetscInt    *schur_iface; /* ... their interface indices, in MUMPS' order */
  PetscScalar *f_local;     /* f on the interior rows, 0 on the Schur variables (ninterior + nschur) */
  PetscScalar *rhs, *red;   /* a right-hand side (ninterior + nschur), a reduced one (nschur) */
  PetscBool    condensed;   /* rhs holds f condensed and MUMPS the data of that condensation, which
                               the next expansion consumes (MUMPS: INFOG(1) = -35 without them) */
} LocalFactor;

/* The dense interface on every rank, the separator eliminated */
typedef struct {
  PetscScalar *L;  /* nsep x nsep, column-major: L L^T = S_ss */
  PetscScalar *X;  /* nsep x nmult: L^-1 S_sl (all columns) */
  PetscScalar *S0; /* this rank's rows of S0 = S_ll - X^T X (nl x nmult, column-major) */
  PetscScalar *z;  /* nsep: L^-1 g_s of the condensed f, for the expansions */
  PetscScalar *g;  /* work: one interface vector (nsep + nmult) */
} DenseInterface;

/* The LU of the dense Jacobian of the steps on nu, on every rank */
typedef struct {
  PetscScalar  *lu;  /* nmult x nmult: LU of J^T (J gathered by rows) */
  PetscBLASInt *piv;
} DenseJacobian;

struct M2dCondensed {
  MPI_Comm         comm;
  Mat              Kg, C, Ct; /* references */
  PetscReal        gamma;     /* K_g = K + gamma C^T C */
  PetscBool        ldlt;      /* symmetric storage in MUMPS */
  RowSplit         split;
  LocalFactor      local;
  DenseInterface   iface;
  DenseJacobian    jac;
  Vec              w;      /* w = C K_g^-1 f (layout of C's rows) */
  Vec              all;    /* a multiplier vector, whole, on every rank ... */
  VecScatter       to_all; /* ... filled from the layout of C's rows */
  M2dCondensedInfo info;
};

PetscErrorCode RowSplitCreate(Mat Kg, Mat C, RowSplit *sp);
PetscErrorCode RowSplitDestroy(RowSplit *sp);
PetscErrorCode RowReaderCreate(M2dCondensed *cs, RowReader *rr);
/* this rank's row i of M (its u rows first, then its multipliers) */
PetscErrorCode RowReaderGet(RowReader *rr, PetscInt i);
PetscErrorCode RowReaderDestroy(RowReader *rr);
/* this rank's MUMPS matrix as 1-based triples (one triangle when symmetric);
 * sets cs->local.nschur and schur_iface */
PetscErrorCode LocalMatrixCreate(M2dCondensed *cs, PetscInt64 *nnz, M2dMumpsInt **irn, M2dMumpsInt **jcn, PetscScalar **a);
/* METIS pivot order of this rank's interior (NULL without METIS or interior),
 * the Schur variables last; after LocalMatrixCreate */
PetscErrorCode LocalOrdering(M2dCondensed *cs, M2dOrdering ord, M2dMumpsInt **perm);
#endif
