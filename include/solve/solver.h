/* solver.h - solve a problem (problem.h) on the path chosen for it.
 *
 * The path is chosen in one place, M2dSolverChoosePath, from the scene and the
 * options database: no contact pair -> linear; -contact_unilateral 0 -> tied;
 * unilateral -> condensed (default) or full (-kkt_path full, or what the
 * condensed path cannot serve: -kkt_mat nest, -snes_type vinewtonrsls, or
 * does poorly: a contact surface past -kkt_condensed_max edges). */
#ifndef M2D_SOLVER_H
#define M2D_SOLVER_H
#include "activeset.h"
#include "problem.h"

/* one load step of a history (scene.h: stages and steps), kept for the
 * report: its answer's vectors (frames' coordinates, reference units) */
typedef struct {
  PetscInt  stage, step; /* stage 0 .., step 1 .. of that stage */
  PetscReal time;        /* the load's pseudo-time: stage + step / the stage's steps */
  PetscInt  iterations;  /* active-set steps of this load step */
  Vec       u, lam, active, slip, r; /* the answer; the rows' right-hand side of the step (kkt.h) */
  PetscReal *nodes;      /* the report's: the interface at the step's end, user units, M2D_STEP_NODE_FIELDS per contact node */
} M2dLoadStep;

/* M2dLoadStep.nodes: pressure, gap, active, traction, slip, slip increment, status */
#define M2D_STEP_NODE_FIELDS 7

typedef struct {
  M2dSolverPath    path;
  Vec              u;       /* displacement (reference units) */
  Vec              lam;     /* contact pressure per multiplier (layout of kkt.r), or NULL */
  Vec              active;  /* final active set (1/0, layout of lam), or NULL */
  PetscInt         ksp_its;     /* iterations of the linear solve (linear and tied paths) */
  PetscInt         ksp_its_max; /* the most iterations of any linear solve (1 for a direct one) */
  PetscBool        factored;    /* the answer is a factorization's, no Krylov iteration (verify.h) */
  M2dActiveSetInfo as;      /* active-set paths */
  PetscReal       *eta;     /* per local cell, M2D_ETA_FIELDS values (report.h), or NULL */
  PetscReal       *sv;      /* the estimator's recovered stresses per local vertex (sigma_x, sigma_y, sigma_xy), or NULL */
  Vec              slip;    /* friction: each tangential row's accumulated weighted slip (layout of lam), or NULL */
  PetscInt         nstep;   /* load steps taken */
  M2dLoadStep     *steps;   /* with more than one: each one's answer, or NULL */
} M2dSolution;

/* The path for scene s on mesh m (NULL: not read yet) and the KKT matrix it
 * needs, into *c (s is not changed); says so when it overrides -kkt_path: without
 * -kkt_path the condensed path gives way to the full one past
 * -kkt_condensed_max non-mortar edges (its dense interface costs O(N^3) per
 * step; the default 8,000 is the crossing the N^3 scaling of README S5's
 * measurements puts it at). Collective on comm (prints on rank 0). */
PetscErrorCode M2dSolverChoosePath(MPI_Comm comm, const M2dScene *s, const M2dMesh *m, M2dSolverChoice *c);
/* The one-line name of a path (summary key kkt_path). Not collective. */
const char    *M2dSolverPathName(M2dSolverPath path);
/* Solve pb as chosen (c); sol's vectors are created here and freed by
 * M2dSolutionDestroy. Collective on the problem's communicator. */
PetscErrorCode M2dSolverSolve(M2dProblem *pb, const M2dSolverChoice *c, M2dSolution *sol);
PetscErrorCode M2dSolutionDestroy(M2dSolution *sol);
/* -help: read the linear solvers' options so that they are listed. Collective. */
PetscErrorCode M2dSolverDocumentOptions(MPI_Comm comm, const M2dScene *s);
#endif
