/* adapt.h - model only what the scene needs: the adaptive loop.
 *
 * Solve, estimate the error per cell (estimator.h), turn the indicators into
 * a new element size per cell (M2dSizeField: the error equidistributed over
 * the cells the target needs), remesh the scene's .geo with gmsh through its
 * C API driven by that size field (remesh.h: all quads, physical names kept,
 * no file in between), and solve again - starting from the previous contact
 * state carried over by position (the first active set of an adapted mesh is
 * the previous one's), so that after the first mesh the active set settles in
 * a few steps. Each next mesh is sized to the target: the dofs that bring
 * the estimate to 0.9 of it at the convergence rate seen so far (adapt.c,
 * above NextDofs), at most -adapt_growth times the last mesh's and within
 * -adapt_max_dofs, -adapt_max_seconds and -adapt_max_memory. Stops at
 * -adapt_target (relative estimate; or within -adapt_tolerance, 5%, above it),
 * -adapt_max_steps or a limit. Each step prints one line; the summary's
 * "adapt" list has one object per step and its top-level keys are the final
 * mesh's. */
#ifndef M2D_ADAPT_H
#define M2D_ADAPT_H
#include "report.h"

#define M2D_ADAPT_MAX_STEPS   32
#define M2D_ADAPT_MAX_NUMBERS 16

typedef struct {
  PetscBool enabled;   /* -adapt */
  PetscReal target;    /* -adapt_target: stop when the relative estimate is below */
  PetscInt  max_steps; /* -adapt_max_steps */
  PetscInt  max_dofs;  /* -adapt_max_dofs: stop before a mesh would exceed it */
  PetscInt  quads;     /* -adapt_quads (M2dRemeshQuads) */
  PetscInt  goal;      /* -adapt_goal: 0 energy, 1 contact */
  PetscReal grading;   /* -adapt_grading: largest growth of the size per element */
  PetscReal growth;    /* -adapt_growth: the largest ratio of the next mesh's dofs to this one's */
  PetscReal tolerance;   /* -adapt_tolerance: stop within this fraction above the target */
  PetscReal max_seconds; /* -adapt_max_seconds: the loop's time (0: none) */
  PetscReal max_memory;  /* -adapt_max_memory: peak resident MB per rank (0: none) */
  PetscInt  keep_last; /* -adapt_keep: 0 best (the last mesh within 10% of the smallest estimate), 1 last */
  PetscInt  nnumber;   /* -geo_setnumber NAME=VALUE,...: parameters of the .geo */
  char      number_name[M2D_ADAPT_MAX_NUMBERS][64];
  PetscReal number_value[M2D_ADAPT_MAX_NUMBERS];
} M2dAdaptOptions;

/* Read the -adapt* and -geo_setnumber options. Collective. */
PetscErrorCode AdaptReadOptions(MPI_Comm comm, const M2dScene *s, M2dAdaptOptions *ao);
/* Run the scene s adaptively from its .geo (-geo), write the final mesh's
 * results. Collective. */
PetscErrorCode AdaptRun(MPI_Comm comm, M2dScene *s, const M2dAdaptOptions *ao, const M2dEstimatorOptions *eo);
#endif
