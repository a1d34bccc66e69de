/* output.h - results for ParaView and for scripts.
 *
 * Rank 0 gathers the (small, 2D) mesh and fields and writes, into an output
 * set (outputset.h: all files of a run replace the previous ones at once),
 *   N.h5 + N.xmf   HDF5 with an XDMF description (ParaView: XDMF Reader)
 *   N.vtu          VTK unstructured grid (raw appended binary)
 * with displacement as a 3-vector and every stress component as its own scalar
 * cell field.  Equal runs give byte-identical files (no time stamps inside).
 * The JSON summary is in summary.h. */
#ifndef M2D_OUTPUT_H
#define M2D_OUTPUT_H
#include "mesh.h"
#include "outputset.h"
#include "summary.h"

#define M2D_MAX_FIELDS 16

typedef struct {
  const char *name;
  Vec         v;      /* global vector in the mesh's dof layout (2 per vertex) */
  PetscBool   vector; /* TRUE: one 3-vector field (z = 0); FALSE: component 0 only */
  PetscInt    comp;   /* component written when !vector */
} M2dPointField;

typedef struct {
  const char      *name;
  const PetscReal *data; /* per local cell, `stride` values, this one at `comp` */
  PetscInt         stride, comp;
} M2dCellField;

/* Fields to write; names and vectors are borrowed (the caller keeps them). */
typedef struct {
  PetscInt      npoint, ncell;
  M2dPointField point[M2D_MAX_FIELDS];
  M2dCellField  cell[M2D_MAX_FIELDS];
} M2dFieldSet;

/* Write N.vtu and/or N.h5 + N.xmf into the staging area of `set`.
 * Collective on the mesh's communicator; errors raised on every rank. */
PetscErrorCode OutputWriteSet(const M2dMesh *m, M2dOutputSet set, PetscBool vtu, PetscBool hdf5, const M2dFieldSet *fs);
/* Earlier form: the same files as a set of their own in dir (no CSV, no
 * summary in it), committed before returning.  Collective. */
PetscErrorCode OutputWrite(const M2dMesh *m, const char *dir, const char *name, PetscBool vtu, PetscBool hdf5, const M2dFieldSet *fs);
#endif
