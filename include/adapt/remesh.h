/* remesh.h - mesh a scene's .geo with gmsh's C API (libgmsh), optionally driven
 * by a mesh-size field given on a previous mesh, and return the all-quad mesh
 * as MshRead reads it from the .msh gmsh saves.
 *
 * Why through the library and not the gmsh program: the size field goes in as
 * gmsh's mesh-size callback, evaluated on the previous mesh (remesh_field.c),
 * rather than as a .pos view (remesh.c says why). The .geo stays the scene's
 * geometry source: its physical names, its parameters (set like gmsh's
 * -setnumber) and, without a size field, its own sizes and meshing options.
 *
 * With a size field, the .geo's own size sources are switched off, and the number
 * m2d_size_field = 1 is defined before it is parsed: gmsh 4.8 cannot undo a .geo's
 * Transfinite constraints (they would override the field), so a .geo meant to
 * be remeshed skips them then: If (!Exists(m2d_size_field)) Transfinite ... EndIf
 * (M2dRemesh refuses a .geo that names Transfinite but not m2d_size_field).
 *
 * gmsh keeps global state (options, parser, models) and crashes on some inputs,
 * so every call meshes in a child process of its own, with a gmsh just
 * initialised (remesh.c): calls are independent of each other and of what the
 * .geo of an earlier call set, and a crash of gmsh is an error line. The
 * child's files (the .geo wrapper, the mesh it hands back) are in a directory
 * <TMPDIR>/m2d_remesh_XXXXXX of this run's own, locked while the run lives and
 * removed at its end; one a killed run left is removed by the next run
 * (temprecord.h). Call from one thread at a time (mortar2d: rank 0 only).
 * Plain C, no PETSc, no MPI. */
#ifndef M2D_REMESH_H
#define M2D_REMESH_H
#include <stddef.h>
#include "msh.h"

#define M2D_REMESH_DIR_PREFIX "m2d_remesh_"

/* How the quads are made when a size field drives the mesh (the .geo's own
 * options are used without a field). Triangles are made with gmsh's
 * Frontal-Delaunay (Mesh.Algorithm 6; its quad algorithm 8 crashes in gmsh 4.8.4). */
typedef enum {
  M2D_QUADS_SUBDIVIDE = 0, /* triangles at 2h, Blossom recombination, every cell split
                              into quads (Mesh.SubdivisionAlgorithm 1): all quads, always */
  M2D_QUADS_FULLQUAD  = 1, /* gmsh's Blossom full-quad recombination (RecombinationAlgorithm 3) */
  M2D_QUADS_BLOSSOM   = 2, /* Blossom recombination at h, no split: fewest cells, but a
                              triangle may be left (then M2dRemesh fails) */
  M2D_QUADS_SIMPLE    = 3  /* as subdivide with gmsh's simple recombination: Blossom's
                              time grows faster than the mesh (minutes past ~3e5
                              nodes), this one's does not; slightly worse shapes */
} M2dRemeshQuads;

typedef struct {
  const char    *geo;     /* the scene's .geo file */
  int            nnumber; /* parameters defined before the .geo is parsed, as gmsh's */
  const char   **names;   /* -setnumber does: DefineConstant keeps them, Exists() sees */
  const double  *values;  /* them. Names are identifiers ([A-Za-z_][A-Za-z0-9_]*). */
  /* Size field (all NULL: the .geo's own sizes): target quad edge length, in the
   * mesh's units, on a previous mesh of the same .geo (its quadphys tags tell the
   * bodies apart), either per node (linear on the two triangles of each quad) or
   * per quad (constant in it). The field can be no sharper than prev's cells.
   * When prev names its physical surfaces (prev->phys), its quads are matched
   * to the .geo's surfaces by those names; otherwise by tag. */
  const MshMesh *prev;
  const double  *hnode;   /* prev->nnode sizes, or NULL */
  const double  *hcell;   /* prev->nquad sizes, or NULL (exactly one of the two) */
  double         hmin, hmax;  /* clamp the field (0: no clamp) */
  M2dRemeshQuads quads;   /* with a field: how quads are made */
  const char    *write_msh;   /* if not NULL: also save the mesh there (gmsh .msh 4.1) */
  double         max_nodes;   /* > 0: gmsh's memory is bounded by what a mesh of this
                                 many nodes takes (with a wide margin): a .geo that asks
                                 for far more ends in one line, not in the machine's swap */
  int            verbose;     /* 1: gmsh's messages on the terminal */
} M2dRemeshInput;

/* Shape of the quads of a mesh: corner angles, and the ratio smallest / largest
 * corner Jacobian of each quad (1 for a parallelogram, <= 0 if inverted). */
typedef struct {
  long   nquad;
  double min_angle, max_angle; /* degrees, over all corners of all quads */
  double min_jratio;           /* smallest per-quad Jacobian ratio */
  long   nbad;                 /* quads with a corner angle < 30 or > 150 degrees */
} M2dQuadQuality;

typedef struct {
  double         seconds_open;     /* load gmsh (first call), start its process, parse the .geo, set up the field */
  double         seconds_generate; /* gmsh's 2D meshing */
  double         seconds_total;    /* the whole call */
  M2dQuadQuality quality;
} M2dRemeshStats;

/* Mesh in->geo (rank-0 work, not collective). Returns 0 and fills out (free it
 * with MshFree) with nodes 0-based, every quad counter-clockwise with positive
 * corner Jacobians, and physical surfaces, curves and points with their names;
 * stats (may be NULL) gets timings and quad shapes. On error returns nonzero,
 * fills err with one line naming the .geo, and leaves out empty (freeable). */
int M2dRemesh(const M2dRemeshInput *in, MshMesh *out, M2dRemeshStats *stats, char *err, size_t errlen);
/* Corner angles and Jacobian ratios of the quads of m (any MshMesh). */
void M2dQuadQualityCompute(const MshMesh *m, M2dQuadQuality *q);

/* The size field M2dRemesh gives gmsh, usable alone (tests, estimators): sizes
 * per node of prev (linear on the triangles (0,1,2), (0,2,3) of each quad) or per
 * quad (constant), clamped to [hmin, hmax] (0: no clamp). It borrows prev and the
 * sizes: keep them alive and unchanged until M2dRemeshFieldDestroy. Returns nonzero
 * if out of memory or prev has no quads. */
typedef struct M2dRemeshField M2dRemeshField;
/* Create (*f owned by the caller) and destroy such a field. Not collective. */
int  M2dRemeshFieldCreate(const MshMesh *prev, const double *hnode, const double *hcell, double hmin, double hmax, M2dRemeshField **f);
void M2dRemeshFieldDestroy(M2dRemeshField **f);
/* Size at (x, y) from the quads of physical surface phys (-1: any quad); a point
 * outside them takes the value at the closest point of a nearby such quad (the
 * closest one when that is within its own size of the point). Returns -1 if no
 * quad has that physical tag. */
double M2dRemeshFieldEval(const M2dRemeshField *f, int phys, double x, double y);
#endif
