/* report.h - what a run tells: the interface results, the comparisons with
 * exact answers (uniform stress, manufactured solution, Hertz), the fields
 * for ParaView, the CSV of the interface and the JSON summary, all in the
 * user's units. */
#ifndef M2D_REPORT_H
#define M2D_REPORT_H
#include "output.h"
#include "summary.h"
#include "estimator.h"
#include "verify.h"

/* per local cell, in sol->eta: the error indicator with the contact terms, the
 * volume part alone (user units, sqrt of an energy per unit thickness), the
 * size field's h_new / h (the first M2D_ETA_WRITTEN: cell fields of the
 * files), and the indicator the size field was made from (with
 * fig->size_est: the adaptive loop sizes its next mesh again from them) */
#define M2D_ETA_FIELDS  4
#define M2D_ETA_WRITTEN 3

typedef struct {
  PetscBool          enabled;  /* -error_estimate */
  M2dRecovery        recovery; /* -estimator_recovery */
  M2dSizeFieldParams size;     /* -estimator_target, -estimator_order_sing */
  PetscBool          target_set; /* -estimator_target given */
  PetscBool          goal_contact; /* -adapt_goal contact: sizes from the pressure's dual-weighted indicators (dual.h) */
  PetscReal          max_dofs;     /* > 0 (the adaptive loop's cap): the size field's expected dofs at most this */
  PetscReal          growth;       /* > 0 (the adaptive loop): and at most this times the mesh's */
} M2dEstimatorOptions;

/* the figures a run is judged by (-1 where not known) */
typedef struct {
  M2dErrorEstimate est;             /* the error estimate (reference units; estimate_rel is unit-free) */
  PetscReal        pressure_l2_rel; /* -hertz: the pressure error against Hertz, the largest over the compared pairs */
  PetscInt         hertz_pairs;     /* -hertz: how many pairs it compared */
  PetscReal        true_error_rel;  /* -exact: the energy-norm error, relative */
  PetscReal        effectivity;     /* -exact: estimate / true error */
  PetscReal        expected_cells;  /* the size field's cell count for the target (estimator.h) */
  M2dErrorEstimate size_est;        /* the sums the size field was made from (est, or the goal's) */
  PetscReal        pressure_ripple; /* contact: ContactRipple (contact_report.h), else -1 */
  PetscInt         ripple_nodes;    /* the interior active nodes it was measured on */
  PetscInt         active_nodes;    /* contact: the active non-mortar nodes */
  PetscReal        pressure_local;    /* contact: ContactPressureEstimate, the pressure's own error */
  PetscReal        pressure_estimate; /* contact: that and the global part (report.c), else -1 */
} M2dFigures;

/* -error_estimate, -estimator_recovery, -estimator_target, -estimator_order_sing.
 * Collective. */
PetscErrorCode ReportEstimatorOptions(MPI_Comm comm, M2dEstimatorOptions *o);

/* Fill sum with the run's figures (problem, path, contact results, the error
 * estimate (into fig->est and sol->eta, when eo->enabled), exact comparisons,
 * checks v) and print them. Leaves the interface results in pb->contact in
 * the user's units. Collective. */
PetscErrorCode ReportCompute(M2dProblem *pb, M2dSolution *sol, const M2dVerification *v, const M2dEstimatorOptions *eo, M2dFigures *fig, M2dSummary *sum);
/* Write the interface CSV and the fields (N.vtu, N.h5 + N.xmf, as the output
 * paths ask; coordinates in the user's units) into the run's files o
 * (output.h), not yet in place. Collective. */
PetscErrorCode ReportWriteFields(M2dProblem *pb, const M2dSolution *sol, M2dOutput *o);
/* Add the stage times (logging.h order, then the total) and the names of the
 * run's files, and write the JSON summary as the last of o's files. Collective. */
PetscErrorCode ReportWriteSummary(const M2dProblem *pb, M2dSummary *sum, const double times[], M2dOutput *o);
#endif
