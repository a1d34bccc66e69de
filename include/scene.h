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
  M2D_PLANE_STRAIN,
  M2D_PLANE_STRESS
} M2dPlane;

typedef enum {
  M2D_EXACT_NONE,
  M2D_EXACT_UNIFORM, /* uniaxial compression: sigma_yy = -p, sigma_xx = sigma_xy = 0 */
  M2D_EXACT_MMS      /* manufactured solution with a body force (mms in elasticity.c) */
} M2dExact;

typedef enum {
  M2D_CONTACT_MORTAR,
  M2D_CONTACT_NTS
} M2dContactMethod;

typedef enum {
  M2D_KKT_AIJ,
  M2D_KKT_NEST
} M2dKKTMat;

typedef enum {
  M2D_PARTITIONER_METIS,
  M2D_PARTITIONER_PETSC
} M2dPartitioner;

typedef struct {
  char      name[M2D_NAME_LEN]; /* physical surface name */
  PetscReal E, nu;
} M2dBody;

typedef struct {
  char      group[M2D_NAME_LEN]; /* physical curve or point */
  PetscBool comp[2];             /* which of u_x, u_y are prescribed */
  PetscReal value[2];
} M2dDirichlet;

typedef struct {
  char      group[M2D_NAME_LEN]; /* physical curve */
  PetscBool is_pressure;
  PetscReal p;    /* pressure, positive pushing into the body: p + grad . (x, y) */
  PetscReal grad[2];
  PetscReal t[2]; /* traction vector */
} M2dEdgeLoad;

typedef struct {
  PetscInt    nmesh;
  PetscReal   mesh_scale; /* coordinates are multiplied by this (unit change) */
  PetscBool   mesh_check; /* run DMPlexCheck* on the plex as built */
  M2dPartitioner mesh_partitioner;
  char        mesh[2][PETSC_MAX_PATH_LEN];
  PetscInt    nbody; /* 0 = every physical surface is a body */
  M2dBody        body[M2D_MAX_BODIES];
  M2dPlane   plane;
  PetscBool   sri; /* selective reduced integration of the volumetric (lambda) part */
  PetscInt    ndir;
  M2dDirichlet dir[M2D_MAX_BC];
  PetscInt    nload;
  M2dEdgeLoad    load[M2D_MAX_BC];
  M2dExact   exact;
  PetscReal   mms_amplitude;
  PetscReal   mms_wavenumber; /* k of u = A (sin kx cos ky, cos kx sin ky): pi, times the reference length inside (units.h) */
  /* contact pair (empty: no contact) */
  char          contact_nm[M2D_NAME_LEN], contact_m[M2D_NAME_LEN];
  M2dContactMethod method;
  int           basis;       /* MortarBasis (mortar.h) */
  PetscReal     reach;       /* search distance; <= 0: automatic */
  PetscBool     unilateral;  /* FALSE: every candidate node is held closed (tied) */
  PetscReal     contact_c;   /* complementarity parameter; <= 0: automatic */
  PetscBool     contact_monitor;
  PetscInt      contact_initial; /* first active set: 0 closed gaps, 1 closest nodes, 2 every candidate */
  PetscBool     hertz;       /* compare the contact pressure with Hertz */
  PetscReal     hertz_radius, hertz_load;
  PetscReal     exact_p;     /* -exact uniform: the exact -sigma_yy */
  M2dKKTMat    kkt_mat;
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
} M2dScene;

PetscErrorCode SceneReadOptions(MPI_Comm comm, M2dScene *s);
/* Materials are read per body once the body names are known (after the mesh). */
PetscErrorCode SceneReadMaterials(MPI_Comm comm, M2dScene *s);
PetscErrorCode SceneView(MPI_Comm comm, const M2dScene *s);
#endif
