/* logging.h - the program's -log_view stages and events, registered in one
 * table (logging.c). A module times a phase with
 *   PetscLogEventBegin(M2dEvent[M2D_EV_ELEMENTS], 0, 0, 0, 0); ... End(...)
 * and the stages are pushed by main. */
#ifndef M2D_LOGGING_H
#define M2D_LOGGING_H
#include <petscsys.h>

typedef enum {
  M2D_STAGE_MESH,
  M2D_STAGE_CONTACT,
  M2D_STAGE_ASSEMBLY,
  M2D_STAGE_SOLVE,
  M2D_STAGE_OUTPUT,
  M2D_STAGE_COUNT
} M2dStageId;

typedef enum {
  M2D_EV_MESH_CREATE,    /* the whole mesh stage of MeshCreate */
  M2D_EV_MESH_READ,      /* read and merge the .msh files (rank 0), or load the .h5 */
  M2D_EV_MESH_EDGES,     /* the skeleton: every edge once, group entries */
  M2D_EV_MESH_PARTITION, /* METIS partition of the cells */
  M2D_EV_MESH_PLEX,      /* the DMPlex from the lists */
  M2D_EV_PREALLOC,       /* stiffness preallocation */
  M2D_EV_ELEMENTS,       /* element stiffness and loads */
  M2D_EV_DIRICHLET,      /* supports: rows, rigid-mode check, elimination */
  M2D_EV_KKT,            /* the KKT blocks */
  M2D_EV_COND_ORDER,     /* condensed path: METIS ordering of each rank's interior */
  M2D_EV_MUMPS_ANALYSIS, /* condensed path: MUMPS analysis */
  M2D_EV_MUMPS_FACTOR,   /* condensed path: MUMPS factorization */
  M2D_EV_INTERFACE,      /* condensed path: the dense interface (separator + multipliers) */
  M2D_EV_MUMPS_SOLVE,    /* condensed path: MUMPS condensation and expansion */
  M2D_EV_VERIFY,         /* the answer's own checks: equilibrium, complementarity, refinement */
  M2D_EV_METIS_ORDER,    /* METIS nested dissection of one matrix (ordering.c) */
  M2D_EV_ITER_SETUP,     /* iterative path: P, P^T K P and the preconditioner's set-up for a step */
  M2D_EV_ITER_SOLVE,     /* iterative path: one step's elimination and Krylov solve */
  M2D_EV_ESTIMATE,       /* the error estimate */
  M2D_EV_COUNT
} M2dEventId;

extern PetscLogStage M2dStage[M2D_STAGE_COUNT];
extern PetscLogEvent M2dEvent[M2D_EV_COUNT];
extern const char   *M2dStageName[M2D_STAGE_COUNT]; /* "mesh", "contact", ... (summary keys) */

/* Register every stage and event once (later calls do nothing; modules that
 * can be used alone call it too). Not collective. */
PetscErrorCode M2dLogRegister(void);
#endif
