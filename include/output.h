/* output.h - results for ParaView and for scripts.
 *
 * Rank 0 gathers the (small, 2D) mesh and fields and writes
 *   DIR/NAME.h5 + DIR/NAME.xmf   HDF5 with an XDMF description (ParaView: XDMF Reader)
 *   DIR/NAME.vtu                 VTK unstructured grid (raw appended binary)
 * with displacement as a 3-vector and every stress component as its own scalar
 * cell field.  Every file is written under a temporary name and renamed when
 * complete.  The JSON summary (-summary FILE) is a flat list of keys plus the
 * objects "time" and "error"; README.md documents the schema. */
#ifndef M2D_OUTPUT_H
#define M2D_OUTPUT_H
#include "mesh.h"

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

typedef struct {
  PetscInt   npoint, ncell;
  M2dPointField point[M2D_MAX_FIELDS];
  M2dCellField  cell[M2D_MAX_FIELDS];
} M2dFieldSet;

PetscErrorCode OutputWrite(const M2dMesh *m, const char *dir, const char *name, PetscBool vtu, PetscBool hdf5, const M2dFieldSet *fs);

/* ---- summary JSON ---- */
#define M2D_MAX_SUMMARY 64
typedef struct {
  PetscInt n;
  char     section[M2D_MAX_SUMMARY][16]; /* "" top level, else object name */
  char     key[M2D_MAX_SUMMARY][48];
  char     value[M2D_MAX_SUMMARY][256];  /* JSON text */
} M2dSummary;
void           SummaryReal(M2dSummary *s, const char *section, const char *key, PetscReal v);
void           SummaryInt(M2dSummary *s, const char *section, const char *key, PetscInt v);
void           SummaryString(M2dSummary *s, const char *section, const char *key, const char *v);
PetscErrorCode SummaryWrite(MPI_Comm comm, const char *path, const M2dSummary *s);
#endif
