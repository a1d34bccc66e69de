/* scene.h - everything a run is asked to do, read from the PETSc options
 * database (an options file per scene in options/). */
#ifndef M2D_SCENE_H
#define M2D_SCENE_H
#include <petscsys.h>
#include "outputpaths.h"

/* The scene's fixed caps (README, -help): bodies, contact pairs, entries of
 * -dirichlet and of -pressure with -traction, -mesh files. M2dScene holds them
 * by value (about 0.6 MB; a copy never aliases what units.c rescales); what
 * grows with the bodies squared (the supports' Gram matrix) is on the heap. */
#define M2D_MAX_BODIES 256
#define M2D_MAX_BC     512
#define M2D_NAME_LEN   128
#define M2D_MAX_MESH   16
#define M2D_MAX_PAIRS  512
#define M2D_MAX_STAGES 16 /* load stages: the scene's loads, then -stage2_... to -stageK_... */
/* plane strain past this Poisson ratio (lambda/mu = 9): full 2x2 integration
 * locks, -q4_integration defaults to sri (problem.c) */
#define M2D_LOCKING_NU 0.45
#define M2D_STR_(x)    #x
#define M2D_STR(x)     M2D_STR_(x) /* a constant in a help string */

typedef enum {
  M2D_PLANE_STRAIN,
  M2D_PLANE_STRESS
} M2dPlane;

typedef enum {
  M2D_EXACT_NONE,
  M2D_EXACT_UNIFORM, /* uniform stress: sigma_yy = -p, sigma_xy = tau, sigma_xx = 0 (in the frame of -exact_angle) */
  M2D_EXACT_MMS      /* manufactured solution with a body force (mms in elasticity.c) */
} M2dExact;

typedef enum {
  M2D_CONTACT_MORTAR,
  M2D_CONTACT_NTS
} M2dContactMethod;

/* one contact pair: non-mortar group : mortar group, its discretisation */
typedef struct {
  char             nm[M2D_NAME_LEN], m[M2D_NAME_LEN];
  M2dContactMethod method;
  int              basis;        /* MortarBasis (mortar.h) */
  PetscBool        own_method;   /* given in -contact_pairs (NM:M:standard|dual|nts) */
  PetscReal        hertz_radius; /* -hertz: this pair's effective radius */
  PetscBool        hertz;        /* -hertz compares it: named in -hertz_pairs, or (none named) a curved pair (ProblemCreate) */
  PetscReal        mu;           /* Coulomb friction coefficient (0: frictionless) */
  PetscBool        own_mu;       /* given in -contact_pairs (NM:M[:method]:MU) */
  char             what[2 * M2D_NAME_LEN + 64]; /* the options that name it, for messages */
  const char      *opt_nm, *opt_m;              /* the option that names each side: -contact_pairs, or -contact_nonmortar and -contact_mortar */
} M2dPair;

typedef enum {
  M2D_KKT_AIJ,
  M2D_KKT_NEST
} M2dKKTMat;

typedef enum {
  M2D_KKT_PATH_FULL,
  M2D_KKT_PATH_CONDENSED,
  M2D_KKT_PATH_ITERATIVE
} M2dKKTPath;

/* -kkt_ordering: the fill-reducing ordering of the MUMPS factorizations (ordering.h) */
typedef enum { M2D_ORDERING_MUMPS, M2D_ORDERING_METIS, M2D_ORDERING_AUTO } M2dOrdering;

typedef enum {
  M2D_PARTITIONER_METIS,
  M2D_PARTITIONER_PETSC
} M2dPartitioner;

typedef struct {
  char      name[M2D_NAME_LEN]; /* physical surface name */
  PetscReal E, nu;
} M2dBody;

/* the frame a prescribed displacement is written in (-dirichlet G:x|y|xy|n|t[:V]) */
typedef enum {
  M2D_BC_XY,      /* u_x = value[0] where comp[0], u_y = value[1] where comp[1] */
  M2D_BC_NORMAL,  /* u . n = value[0]: n the outward unit normal of the group's curve; comp[] unused (FALSE) */
  M2D_BC_TANGENT  /* u . t = value[0]: t = (-n_y, n_x), along the boundary counter-clockwise; comp[] unused (FALSE) */
} M2dBCFrame;

typedef struct {
  char       group[M2D_NAME_LEN]; /* physical curve or point (M2D_BC_NORMAL/TANGENT: a curve) */
  M2dBCFrame frame;
  PetscBool  comp[2];             /* M2D_BC_XY: which of u_x, u_y are prescribed */
  PetscReal  value[2];
  PetscInt   stage;               /* 0: a support of the scene (-dirichlet); k > 0: -stage<k+1>_dirichlet, a change of a support's value */
} M2dDirichlet;

typedef struct {
  char      group[M2D_NAME_LEN]; /* physical curve */
  PetscBool is_pressure;
  PetscReal p;    /* pressure, positive pushing into the body: p + grad . (x, y) */
  PetscReal grad[2];
  PetscReal t[2]; /* traction vector */
  PetscInt  stage; /* 0: the scene's (-pressure, -traction); k > 0: added by -stage<k+1>_pressure, -stage<k+1>_traction */
} M2dEdgeLoad;

typedef struct {
  PetscInt       nmesh;
  PetscReal      mesh_scale; /* coordinates are multiplied by this (unit change) */
  PetscBool      mesh_check; /* run DMPlexCheck* on the plex as built */
  M2dPartitioner mesh_partitioner;
  char           mesh[M2D_MAX_MESH][PETSC_MAX_PATH_LEN]; /* resolved (SceneResolvePath against mesh_dir) */
  char           mesh_dir[PETSC_MAX_PATH_LEN];
  char           geo[PETSC_MAX_PATH_LEN]; /* .geo source for remeshing, resolved against geo_dir; "" none */
  char           geo_dir[PETSC_MAX_PATH_LEN];
  char           mesh_save[PETSC_MAX_PATH_LEN]; /* -mesh_save: the mesh as built, written to this .h5; "" none */
  PetscInt       nbody; /* 0 = every physical surface is a body */
  M2dBody        body[M2D_MAX_BODIES];
  PetscBool      materials_read; /* SceneReadMaterials has run */
  M2dPlane       plane;
  PetscBool      sri; /* selective reduced integration of the volumetric (lambda) part */
  PetscBool      integration_set; /* -q4_integration given; else sri past M2D_LOCKING_NU in plane strain (problem.c) */
  PetscBool      locking_warned;  /* -q4_integration full past M2D_LOCKING_NU: said once */
  PetscInt       ndir;
  M2dDirichlet   dir[M2D_MAX_BC];
  PetscInt       nload;
  M2dEdgeLoad    load[M2D_MAX_BC];
  M2dExact       exact;
  PetscReal      exact_angle; /* degrees: -exact uniform's frame, x' = R(angle) x */
  PetscReal      mms_amplitude;
  PetscReal      mms_wavenumber; /* k of u = A (sin kx cos ky, cos kx sin ky): pi, times the reference length inside (units.h) */
  /* contact pairs (none: no contact): -contact_pairs, or the short form
   * -contact_nonmortar/-contact_mortar (contact_nm, contact_m) */
  char             contact_nm[M2D_NAME_LEN], contact_m[M2D_NAME_LEN];
  PetscInt         npair;
  M2dPair          pair[M2D_MAX_PAIRS];
  M2dContactMethod method;          /* -contact_method: every pair without its own */
  int              basis;           /* MortarBasis (mortar.h): -mortar_basis, the same */
  PetscBool        reach_set;       /* -contact_reach given; FALSE: automatic (reach is then 0) */
  PetscReal        reach;           /* search distance, > 0 when reach_set */
  PetscBool        unilateral;      /* FALSE: every candidate node is held closed (tied) */
  PetscBool        contact_c_set;   /* -contact_c given; FALSE: automatic (contact_c is then 0) */
  PetscReal        contact_c;       /* complementarity parameter, > 0 when contact_c_set */
  PetscBool        contact_monitor;
  PetscInt         contact_initial; /* first active set: 0 closed gaps, 1 closest nodes, 2 every candidate */
  PetscReal        friction;        /* -contact_friction: MU of every pair without its own */
  PetscInt         nstage;          /* load stages (-load_stages), >= 1 */
  PetscInt         stage_steps[M2D_MAX_STAGES]; /* each stage's load steps (-load_steps, -stage<k>_steps) */
  PetscBool        hertz;           /* compare the contact pressure with Hertz */
  PetscBool        cattaneo;        /* with -hertz and friction: compare the shear traction with Cattaneo-Mindlin */
  PetscInt         hertz_nradius;   /* entries of -hertz_radius: 1 (every compared pair) or one per -hertz_pairs entry */
  PetscReal        hertz_radii[M2D_MAX_PAIRS][2]; /* each entry's R1 and R2 (0: one radius) */
  PetscInt         hertz_npairs;    /* -hertz_pairs given: the pairs compared (1, 2, ...); 0: the curved ones */
  PetscInt         hertz_pairs[M2D_MAX_PAIRS];
  PetscBool        hertz_load_set;  /* -hertz_load given; FALSE: from the first -pressure (hertz_load is then 0) */
  PetscReal        hertz_load;
  PetscBool        exact_p_set;     /* -exact_p given; else exact_p is the first -pressure (-exact uniform) */
  PetscReal        exact_p;         /* -exact uniform: the exact -sigma_yy */
  PetscReal        exact_tau;       /* -exact uniform: the exact sigma_xy (a sheared patch) */
  PetscReal        strain_limit;    /* the largest strain or rotation an answer may reach (verify.h) */
  M2dKKTMat        kkt_mat;
  M2dKKTPath       kkt_path;     /* active-set solves: full, condensed (condensed.h) or iterative (iterative.h) */
  PetscReal        kkt_augment;  /* augmented-Lagrangian weight on the K block (0: off) */
  PetscInt         kkt_condensed_max; /* default path: condensed up to this many non-mortar edges, full past it (solver.h) */
  M2dOrdering      kkt_ordering; /* fill-reducing ordering of the MUMPS factorizations */
  PetscBool        kkt_ldlt;     /* condensed path: LDL^T (MUMPS SYM = 2) */
  PetscInt         icntl4, icntl7, icntl8, icntl14, icntl58; /* condensed path's MUMPS ICNTL(n) */
  M2dOutputPaths   out;          /* -output_dir, -output_name, -output, -summary */
  PetscBool        help;
} M2dScene;

/* Read the scene from the options database into *s (overwritten, owns no memory):
 * every option checked for form and domain (an error names it), the -mesh and
 * -geo files resolved (SceneResolvePath). Collective on comm. */
PetscErrorCode SceneReadOptions(MPI_Comm comm, M2dScene *s);
/* Read -NAME_E and -NAME_nu for every body in s->body (names known once the
 * mesh is read when -bodies is not given); E in [1e-300, 1e300], nu in
 * (-1, 0.5). Sets s->materials_read. Collective on comm. */
PetscErrorCode SceneReadMaterials(MPI_Comm comm, M2dScene *s);
/* Error "option -X is unknown (did you mean -Y?)" for an option that is
 * neither the program's nor a PETSc object's (optcheck.h). Call after
 * SceneReadOptions (before the mesh: -NAME_E/-NAME_nu are then left for
 * later) and again after SceneReadMaterials. Collective on comm. */
PetscErrorCode SceneCheckOptions(MPI_Comm comm, const M2dScene *s);
/* Resolve a file an option names: an absolute path, or a relative one that
 * exists from the current directory, as given; else dir/given if that exists;
 * else an error naming opt, given and dir. path gets len bytes. Collective on
 * comm (rank 0 looks, every rank gets its answer). */
PetscErrorCode SceneResolvePath(MPI_Comm comm, const char *opt, const char *given, const char *dir, char *path, size_t len);
/* Whether some pair has friction (mu > 0). Not collective. */
PetscBool      SceneHasFriction(const M2dScene *s);
/* The load steps of the whole history (every stage's). Not collective. */
PetscInt       SceneLoadSteps(const M2dScene *s);
/* Print the plane mode, the bodies and their materials (and Hertz's effective
 * radius when two radii are given). Collective on comm. */
PetscErrorCode SceneView(MPI_Comm comm, const M2dScene *s);
/* The largest modulus over the smallest (the bodies' E), and which bodies
 * they are. Not collective. */
PetscReal SceneModuliRatio(const M2dScene *s, PetscInt *soft, PetscInt *stiff);
#endif
