/* condensed_impl.h - the condensed path's data (condensed.h) for condensed.c
 * (factor, dense interface, solves), built on the rows of condensed_rows.h.
 * Private. */
#ifndef M2D_CONDENSED_IMPL_H
#define M2D_CONDENSED_IMPL_H
#include "condensed.h"
#include "condensed_rows.h"
#include <petscblaslapack.h>

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

#endif
