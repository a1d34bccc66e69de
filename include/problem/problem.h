/* problem.h - one discrete problem: the mesh, the contact pair, the stiffness,
 * the loads and supports, and (with contact) the KKT blocks, all in the
 * reference units of units.h.
 *
 * Built in two stages that are also -log_view stages: ProblemCreate (Mesh:
 * read and check the mesh, materials, units) and ProblemSetUp (Contact:
 * surfaces, segments, rows; Assembly: K, f, supports, KKT). */
#ifndef M2D_PROBLEM_H
#define M2D_PROBLEM_H
#include "frames.h"
#include "kkt.h"
#include "msh.h"
#include "supports.h"
#include "units.h"

/* how the discrete problem is solved; chosen once (solver.h) */
typedef enum {
  M2D_PATH_LINEAR,    /* no contact pair: K u = f */
  M2D_PATH_TIED,      /* every candidate node held closed: one KKT solve */
  M2D_PATH_CONDENSED, /* active set on the multipliers, K + g C^T C factored once (condensed.h) */
  M2D_PATH_FULL,      /* active set, the KKT matrix refactored at each step */
  M2D_PATH_ITERATIVE  /* active set, multipliers eliminated, CG + AMG in u (iterative.h) */
} M2dSolverPath;

/* the solver's choice (solver.h): the path and the KKT matrix it builds (the scene keeps the user's options) */
typedef struct {
  M2dSolverPath path;
  M2dKKTMat     kkt_mat;     /* -kkt_mat; nest on -kkt_path iterative (the blocks suffice) */
  PetscReal     kkt_augment; /* -kkt_augment; 1 for 0 on the condensed path (it factors K + g C^T C) */
} M2dSolverChoice;

typedef struct {
  const M2dScene *user;  /* the scene in the user's units (borrowed) */
  M2dScene        s;     /* the same in reference units */
  M2dUnits        units;
  M2dMesh         mesh;  /* coordinates in reference units */
  PetscBool       has_contact;
  M2dContact      contact;
  Mat             K;     /* stiffness, Dirichlet rows and columns eliminated */
  Vec             f;     /* load, Dirichlet-lifted */
  Vec             ubc;   /* prescribed values on the Dirichlet rows, 0 elsewhere */
  PetscInt        ndir;  /* Dirichlet rows owned by this rank */
  PetscInt       *drows;
  M2dSupports     supports; /* is every body held (with a given contact set)? */
  M2dFrames       frames;   /* supports per vertex; inclined ones rotate the vertex's dofs (frames.h) */
  M2dContactRows  Rkkt;     /* with frames: the contact rows in the frames' coordinates (the KKT's) */
  M2dKKT          kkt;   /* with contact */
  PetscBool      *warm;  /* with contact: the first active set (one per multiplier, every rank), or NULL */
  PetscInt        ncase;   /* a load history (scene.h: stages, steps): its load cases, one per stage; 0 for one step */
  Vec            *fcase;   /* each stage's load, Dirichlet-lifted (the first: the scene's) */
  Vec            *ubccase; /* each stage's support values */
  PetscBool       keep_factor; /* condensed path: keep the factorization for later solves (M2dActiveSetInfo.factor) */
} M2dProblem;

/* Mesh stage: the mesh of scene `user` (its -mesh files, or msh on rank 0
 * when msh is not NULL: an MshMesh named `what` in messages), the materials,
 * the groups the options name checked, the reference units picked and
 * applied. `user` is borrowed and must outlive pb; its body list is completed
 * from the mesh. Collective on comm. */
PetscErrorCode ProblemCreate(MPI_Comm comm, M2dScene *user, MshMesh *msh, const char *what, M2dProblem *pb);
/* Contact and assembly stages for the solver's choice (which decides how the
 * KKT blocks are built). Collective. */
PetscErrorCode ProblemSetUp(M2dProblem *pb, const M2dSolverChoice *choice, PetscLogStage contact_stage, PetscLogStage assembly_stage, double *t_contact, double *t_assembly);
/* What path means for the options, as "on the condensed path (...)": the
 * reason an option has no effect (optcheck.h). Not collective. */
const char    *ProblemPathSays(const M2dScene *s, M2dSolverPath path);
/* The load of step `step` (1 ..) of stage `stage` (0 ..) of the history into
 * pb->f and pb->ubc: the stages before held whole, this one's by the
 * fraction step / its steps. Collective. */
PetscErrorCode ProblemSetLoad(M2dProblem *pb, PetscInt stage, PetscInt step);
/* Frees everything pb owns. Collective. */
PetscErrorCode ProblemDestroy(M2dProblem *pb);
#endif
