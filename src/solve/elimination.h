/* elimination.h - which unknown each contact row gives when it is active, for
 * the iterative path (iterative.h). Internal to iterative.c/elimination.c.
 *
 * Every candidate row j of C (multipliers x u; every rank holds all of them)
 * gets a slave s(j): among its unknowns within a tenth of its largest entry,
 * the one the fewest rows hold (with dual multipliers or NTS the non-mortar
 * node's own dof, which no other row holds). Rows that hold one another's
 * slaves are eliminated together (a group; dual multipliers: one row, two
 * where an edge is only partly covered). Per active set, group g's active
 * rows A with slaves S give X = C[A, S]^-1 and the rows of P and E
 * (iterative.c): du_S = X (t_A - C[A, rest] du_rest). */
#ifndef M2D_ELIMINATION_H
#define M2D_ELIMINATION_H
#include "mortar.h"

#define M2D_GROUP_MAX 8 /* rows eliminated together at the most */

typedef struct {
  MPI_Comm   comm;
  PetscInt   nrow;         /* candidate rows (every rank holds every row) */
  PetscInt  *rowptr;       /* row j's columns and their C values (Dirichlet columns 0) */
  PetscInt  *rowcol;
  PetscReal *rowval;
  PetscInt  *slave;        /* s(j) (global dof) */
  PetscInt   ngroup;
  PetscInt  *gptr, *grow;  /* rows of group g: grow[gptr[g] .. gptr[g + 1]) */
  PetscInt  *gcptr, *gcol; /* the columns of its rows: gcol[gcptr[g] .. gcptr[g + 1]), sorted */
} M2dElimination;

/* Slaves and groups of the rows R (C = -R with the Dirichlet columns zeroed;
 * drows: this rank's Dirichlet rows). One line on every rank when a row has
 * no free unknown or a group is larger than M2D_GROUP_MAX (standard mortar
 * multipliers). Collective (one reduction); free with M2dEliminationDestroy. */
PetscErrorCode M2dEliminationCreate(MPI_Comm comm, const M2dContactRows *R, PetscInt ndir, const PetscInt drows[], M2dElimination *el);
/* P's and E's rows (INSERT_VALUES, not assembled) of group g's slaves in
 * [lo, hi) for the set `on` (every row; NULL: none active): an active slave's
 * P row is -(X C[A, :]) off S and 0 on S, its E row X (columns A); an
 * inactive row's slave keeps the identity row (explicit zeros elsewhere: one
 * pattern for every set). *singular is set when C[A, S] cannot be inverted.
 * Not collective. */
PetscErrorCode M2dEliminationGroupRows(const M2dElimination *el, PetscInt g, const PetscScalar on[], PetscInt lo, PetscInt hi, Mat P, Mat E, PetscBool *singular);
PetscErrorCode M2dEliminationDestroy(M2dElimination *el);
#endif
