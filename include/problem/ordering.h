/* ordering.h - a METIS nested-dissection ordering handed to MUMPS
 * (-kkt_ordering metis).
 *
 * Debian's MUMPS 5.5 has neither METIS nor SCOTCH inside (ICNTL(7) = 3 or 5
 * falls back to PORD), and when a Schur complement is requested it analyses
 * with AMD whatever ICNTL(7) says. Here libmetis orders the graph of the matrix
 * (consecutive rows with the same closed neighbourhood, the two dofs of a node,
 * become one weighted vertex) and MUMPS gets the result as its PERM_IN
 * (ICNTL(7) = 1), with the Schur variables, if any, last.
 *
 * The IS holds, for each row i, its position in the pivot order: MUMPS'
 * PERM_IN(i) - 1, which is what PETSc 3.18 forwards (perm_in[i] = idx[i] + 1).
 * Through PETSc's MUMPS interface (full path, reference) LU on one rank only:
 * in parallel PETSc 3.18 hands MUMPS a distributed matrix and no permutation,
 * and for a Cholesky factor none at all; those get MUMPS' AMF.
 * The condensed path calls MUMPS itself and orders on any number of ranks
 * (condensed.h), each rank its own rows with M2dOrderingMetis. */
#ifndef M2D_ORDERING_H
#define M2D_ORDERING_H
#include <petscksp.h>
#include "scene.h" /* M2dOrdering */

/* -kkt_ordering auto: MUMPS' own below this many dofs on one rank, METIS from
 * there and on several ranks (M2dOrderingFor). On
 * Hertz and S1 meshes of 1.6e4-2.6e5 dofs (docs/speed.md) MUMPS' AMD ordered,
 * analysed and factored in 0.66-0.93 of METIS' time (libmetis' nested
 * dissection costs about what it saves in the factorization), level 5 (9.9e5)
 * about the same; METIS' factors are the smaller (half the flops at 2.5e5). */
#define M2D_ORDERING_AUTO_DOFS 200000
#define MATORDERINGM2DMETIS "m2d_metis"

/* Pivot positions of the rows of the sequential AIJ matrix A (a permutation,
 * as an IS the caller destroys); the rows in `last` (may be NULL) come last,
 * in the order of `last`. Not collective. */
PetscErrorCode M2dOrderingMetis(Mat A, IS last, IS *pos);
/* The ordering of a KSP's MUMPS factorization (PCLU or PCCHOLESKY with
 * MATSOLVERMUMPS; call after KSPSetFromOptions): LU on one rank with
 * ord == METIS gets the METIS ordering (the MatOrdering "m2d_metis"; *metis
 * set, may be NULL); otherwise, once the operators are set, MUMPS orders with
 * AMF (ICNTL(7) = 2) unless -mat_mumps_icntl_7 is given. Other PCs: nothing.
 * Collective on the KSP's communicator. */
PetscErrorCode M2dOrderingSetupKSP(KSP ksp, M2dOrdering ord, PetscBool *metis);
/* The ordering ord means for a problem of dofs unknowns (the whole problem's,
 * so every rank decides alike) on `ranks` ranks: auto resolved, the others as
 * they are. Auto is METIS on several ranks: there MUMPS' own order of each
 * rank's rows, the separators as a Schur complement, lost the S2 patch test
 * with moduli 1e15 apart to round-off (residual 2.8e-2 on 2 ranks, 2e-15 with
 * METIS), and METIS was the faster on 2 ranks too (docs/speed.md). */
M2dOrdering M2dOrderingFor(M2dOrdering ord, PetscInt dofs, PetscMPIInt ranks);
#endif
