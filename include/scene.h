/* scene.h - everything a run is asked to do, read from the PETSc options
 * database (an options file per scene in options/). */
#ifndef M2D_SCENE_H
#define M2D_SCENE_H
#include <petscsys.h>
#include "ordering.h"

#define M2D_MAX_BODIES 8
#define M2D_MAX_BC     32
#define M2D_NAME_LEN   128

typedef enum {
  PLANE_STRAIN,
  PLANE_STRESS
} PlaneMode;

typedef enum {
  EXACT_NONE,
  EXACT_UNIFORM, /* uniaxial compression: sigma_yy = -p, sigma_xx = sigma_xy = 0 */
  EXACT_MMS      /* manufactured solution with a body force (mms in elasticity.c) */
} ExactKind;

typedef enum {
  CONTACT_MORTAR,
  CONTACT_NTS
} ContactMethod;

typedef enum {
  KKT_AIJ,
  KKT_NEST
} KKTMatType;

typedef enum {
  M2D_PARTITIONER_METIS,
  M2D_PARTITIONER_PETSC
} M2dPartitioner;

typedef struct {
  char      name[M2D_NAME_LEN]; /* physical surface name */
  PetscReal E, nu;
} Body;

typedef struct {
  char      group[M2D_NAME_LEN]; /* physical curve or point */
  PetscBool comp[2];             /* which of u_x, u_y are prescribed */
  PetscReal value[2];
} DirichletBC;

typedef struct {
  char      group[M2D_NAME_LEN]; /* physical curve */
  PetscBool is_pressure;
  PetscReal p;    /* pressure, positive pushing into the body: p + grad . (x, y) */
  PetscReal grad[2];
  PetscReal t[2]; /* traction vector */
} EdgeLoad;

typedef struct {
  PetscInt    nmesh;
  PetscReal   mesh_scale; /* coordinates are multiplied by this (unit change) */
  PetscBool   mesh_check; /* run DMPlexCheck* on the plex as built */
  M2dPartitioner mesh_partitioner;
  char        mesh[2][PETSC_MAX_PATH_LEN];
  PetscInt    nbody; /* 0 = every physical surface is a body */
  Body        body[M2D_MAX_BODIES];
  PlaneMode   plane;
  PetscBool   sri; /* selective reduced integration of the volumetric (lambda) part */
  PetscInt    ndir;
  DirichletBC dir[M2D_MAX_BC];
  PetscInt    nload;
  EdgeLoad    load[M2D_MAX_BC];
  ExactKind   exact;
  PetscReal   mms_amplitude;
  /* contact pair (empty: no contact) */
  char          contact_nm[M2D_NAME_LEN], contact_m[M2D_NAME_LEN];
  ContactMethod method;
  int           basis;       /* MortarBasis (mortar.h) */
  PetscReal     reach;       /* search distance; <= 0: automatic */
  PetscBool     unilateral;  /* FALSE: every candidate node is held closed (tied) */
  PetscReal     contact_c;   /* complementarity parameter; <= 0: automatic */
  PetscBool     contact_monitor;
  PetscInt      contact_initial; /* first active set: 0 closed gaps, 1 closest nodes, 2 every candidate */
  PetscBool     hertz;       /* compare the contact pressure with Hertz */
  PetscReal     hertz_radius, hertz_load;
  PetscReal     exact_p;     /* -exact uniform: the exact -sigma_yy */
  KKTMatType    kkt_mat;
  PetscBool     condensed;   /* active set: factor once with a Schur complement (condensed.h) */
  PetscReal     kkt_augment; /* augmented-Lagrangian weight on the K block (0: off) */
  M2dOrdering   kkt_ordering; /* fill-reducing ordering of the MUMPS factorizations */
  PetscBool     kkt_ldlt;     /* condensed path: LDL^T (MUMPS SYM = 2) */
  PetscInt      icntl4, icntl7, icntl8, icntl14, icntl58; /* condensed path's MUMPS ICNTL(n) */
  char        outdir[PETSC_MAX_PATH_LEN];
  char        outname[M2D_NAME_LEN];
  char        summary[PETSC_MAX_PATH_LEN];
  PetscBool   write_vtu, write_hdf5;
  PetscBool   help;
} Scene;

PetscErrorCode SceneReadOptions(MPI_Comm comm, Scene *s);
/* Materials are read per body once the body names are known (after the mesh). */
PetscErrorCode SceneReadMaterials(MPI_Comm comm, Scene *s);
PetscErrorCode SceneView(MPI_Comm comm, const Scene *s);
#endif
