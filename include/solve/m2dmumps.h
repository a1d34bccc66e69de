/* m2dmumps.h - one sequential MUMPS per rank (dmumps_c on a copy of
 * MPI_COMM_SELF), the condensed path's only door to MUMPS (condensed.h).
 *
 * Every rank of a communicator holds an M2dMumps; a rank with no rows takes
 * part only in the agreement on the outcome. Every call below is collective on
 * that communicator: the ranks agree on MUMPS' status, so a failure on one rank
 * raises the same error on all of them (no hang).
 *
 * The matrix comes as 1-based triples (MUMPS' centralized assembled format;
 * with symmetric storage, LDL^T, one triangle only). The Schur variables are
 * the last nschur rows: the factorization also gives their Schur complement
 * S = A_ss - A_si A_ii^-1 A_is (dense), and the solves can be split into
 * the condensation (forward elimination: the reduced right-hand side on the
 * Schur variables) and the expansion (backward substitution, given the values
 * of the Schur variables). */
#ifndef M2D_MUMPS_H
#define M2D_MUMPS_H
#include <petscsys.h>

typedef int M2dMumpsInt; /* MUMPS_INT of Debian's MUMPS 5.5 (32-bit), checked at compile time in mumps.c */

typedef struct {
  PetscInt output;    /* ICNTL(4): 0 silent, 2 statistics (printed by the communicator's rank 0) */
  PetscInt ordering;  /* ICNTL(7) when no pivot order is given */
  PetscInt scaling;   /* ICNTL(8) */
  PetscInt workspace; /* ICNTL(14): working-space increase in percent */
  PetscInt symbolic;  /* ICNTL(58): symbolic factorization variant */
} M2dMumpsOptions;

typedef enum {
  M2D_MUMPS_CONDENSE, /* forward elimination; the reduced right-hand side of the Schur variables comes back (ICNTL(26) = 1) */
  M2D_MUMPS_EXPAND    /* backward substitution from the Schur variables' values (ICNTL(26) = 2) */
} M2dMumpsPhase;

typedef struct M2dMumps M2dMumps;

/* A MUMPS instance on this rank for n rows (n = 0: this rank only joins the
 * agreement), LDL^T (symmetric) or LU. Collective on comm; *mu freed by M2dMumpsDestroy. */
PetscErrorCode M2dMumpsCreate(MPI_Comm comm, PetscInt n, PetscBool symmetric, const M2dMumpsOptions *opt, M2dMumps **mu);
/* Analysis of the nnz triples (irn, jcn, a: 1-based; kept by pointer, valid
 * until M2dMumpsFactor returns), with the pivot order perm (perm[i] = 1-based
 * position of row i; NULL: MUMPS orders, opt->ordering) and the last nschur
 * rows as Schur variables. Collective. */
PetscErrorCode M2dMumpsAnalyse(M2dMumps *mu, PetscInt64 nnz, M2dMumpsInt irn[], M2dMumpsInt jcn[], PetscScalar a[], M2dMumpsInt perm[], PetscInt nschur);
/* Numerical factorization. *singular (every rank the same): MUMPS found the
 * matrix numerically singular (INFOG(1) = -10; MUMPS 5.5 does not report it
 * when Schur variables are given); other failures raise an error. *flops:
 * this rank's factorization flops (RINFO(3)). Collective. */
PetscErrorCode M2dMumpsFactor(M2dMumps *mu, PetscBool *singular, PetscLogDouble *flops);
/* The Schur complement (nschur x nschur, column-major, both triangles), once,
 * after M2dMumpsFactor; the caller owns *S (PetscFree). Not collective. */
PetscErrorCode M2dMumpsGetSchur(M2dMumps *mu, PetscScalar **S);
/* One phase of a solve, in place. CONDENSE: rhs (n) holds the right-hand side
 * (its Schur rows ignored) and comes back forward-eliminated, red (nschur)
 * gets the reduced right-hand side. EXPAND: rhs holds what a CONDENSE left,
 * red the Schur variables' values; rhs gets the solution of the other rows.
 * Without Schur variables CONDENSE is the whole solve and EXPAND does nothing.
 * Collective. */
PetscErrorCode M2dMumpsSolve(M2dMumps *mu, M2dMumpsPhase phase, PetscScalar rhs[], PetscScalar red[]);
/* Frees MUMPS' factors and *mu; *mu = NULL. Not collective. */
PetscErrorCode M2dMumpsDestroy(M2dMumps **mu);
#endif
