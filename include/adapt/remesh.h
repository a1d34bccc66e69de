/* remesh.h - mesh a scene's .geo with gmsh's C API (libgmsh), optionally driven
 * by a mesh-size field given on a previous mesh, and return the all-quad mesh in
 * memory as the MshMesh that MshRead would fill from the same mesh saved as a .msh.
 *
 * Why through the library and not the gmsh program: no .msh file in between, and
 * the size field goes in as numbers rather than as a .pos file. The .geo stays the
 * scene's geometry source: its physical names, its parameters (set like gmsh's
 * -setnumber) and, without a size field, its own sizes and meshing options.
 *
 * With a size field, the .geo's own size sources are switched off, and the number
 * m2d_size_field = 1 is defined before it is parsed: gmsh 4.8 cannot undo a .geo's
 * Transfinite constraints (they would override the field), so a .geo meant to
 * be remeshed skips them then: If (!Exists(m2d_size_field)) Transfinite ... EndIf
 * (M2dRemesh refuses a .geo that names Transfinite but not m2d_size_field).
 *
 * gmsh keeps global state (options, parser, models), so every call meshes with
 * a gmsh just initialised (a process forked per call from a server process that
 * initialised it once, remesh.c): calls are independent of each other and of
 * what the .geo of an earlier call set, and a crash of gmsh is an error line.
 * With a size field, the surfaces are meshed in two shares at once, each by a
 * process of its own (connected surfaces stay together; remesh.c, Share), and
 * joined: the first share's nodes and cells first.
 * Call from one thread at a time (mortar2d: rank 0 only). Plain C, no PETSc,
 * no MPI. */
#ifndef M2D_REMESH_H
#define M2D_REMESH_H
#include <stddef.h>
#include "msh.h"

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
  const char    *write_msh;   /* if not NULL: also save the mesh there (gmsh .msh 4.1; not shared then) */
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
  double         seconds_open;     /* load gmsh (first call), parse the .geo, set up the field */
  double         seconds_generate; /* gmsh's 2D meshing (the longer share's, when shared) */
  double         seconds_total;    /* the whole call */
  M2dQuadQuality quality;
} M2dRemeshStats;

/* Mesh in->geo (rank-0 work, not collective). Returns 0 and fills out (free it
 * with MshFree) with nodes 0-based, every quad counter-clockwise with positive
 * corner Jacobians, and physical surfaces, curves and points with their names;
 * stats (may be NULL) gets timings and quad shapes. On error returns nonzero,
 * fills err with one line naming the .geo, and leaves out empty (freeable). */
int M2dRemesh(const M2dRemeshInput *in, MshMesh *out, M2dRemeshStats *stats, char *err, size_t errlen);
/* gmsh runs in a server process (remesh.c) that the first M2dRemesh starts, or
 * this earlier (not collective, no MPI or PETSc call; best called before
 * MPI_Init, while the process is small): the server then loads and
 * initialises gmsh while the caller goes on. Returns 0, or 1 when the process
 * could not be started (M2dRemesh will try again). The server ends when the
 * caller exits. */
int M2dRemeshStart(void);

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
