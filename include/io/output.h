/* output.h - the files of a run, for ParaView and for scripts.
 *
 * Rank 0 gathers the (small, 2D) mesh and fields and writes
 *   N.vtu          VTK unstructured grid (raw appended binary)
 *   N.h5 + N.xmf   HDF5 with an XDMF description (ParaView: XDMF Reader)
 * with vector fields as 3-vectors (z = 0) and every other field as its own
 * scalar; the caller adds its own files (the contact CSV, the summary)
 * through OutputFile. Each file is written under a temporary name, and
 * OutputCommit renames them all into place in the order they were added, the
 * summary last (tempfile.h). Each file names the run: the .h5 in the root
 * attribute run_id, the .xmf and .vtu in an XML comment "run_id ...". Equal
 * runs give equal files but for that id (no time stamps inside). Paths and
 * the id come from outputpaths.h; the JSON summary is in summary.h. */
#ifndef M2D_OUTPUT_H
#define M2D_OUTPUT_H
#include "mesh.h"
#include "outputpaths.h"
#include "tempfile.h"

#define M2D_MAX_FIELDS 20
#define M2D_OUTPUT_FILES 8

/* A point field: a global vector in the mesh's dof layout (2 per vertex), or
 * values per local vertex (v NULL: data[stride * i + comp], the same on every
 * rank that holds vertex i). */
typedef struct {
  const char      *name;
  Vec              v;
  PetscBool        vector; /* v: one 3-vector field (z = 0); FALSE: component comp only */
  PetscInt         comp;
  const PetscReal *data;
  PetscInt         stride;
} M2dPointField;

typedef struct {
  const char      *name;
  const PetscReal *data; /* per local cell, `stride` values, this one at `comp` */
  PetscInt         stride, comp;
} M2dCellField;

/* Fields to write; names, vectors and arrays are borrowed (the caller keeps
 * them). body_names (nbody of them, may be 0): the names of the values 0, 1,
 * ... of the cell field "body", written as the VTU's field data body_names
 * (a string array), the .h5's dataset /body_names and the .xmf's
 * Information body_names. */
typedef struct {
  PetscInt           npoint, ncell, nbody;
  M2dPointField      point[M2D_MAX_FIELDS];
  M2dCellField       cell[M2D_MAX_FIELDS];
  const char *const *body_names;
} M2dFieldSet;

/* The files of one run being written (rank 0 holds them). */
typedef struct {
  const M2dOutputPaths *paths;
  MPI_Comm              comm;
  PetscMPIInt           rank;
  PetscInt              n;
  M2dFile               file[M2D_OUTPUT_FILES];
} M2dOutput;

/* Start the run's output (paths checked by OutputCheckPaths). Not collective. */
PetscErrorCode OutputBegin(MPI_Comm comm, const M2dOutputPaths *paths, M2dOutput *o);
/* Rank 0 only: open the temporary of DIR/N<suffix>, or of the summary when
 * suffix is NULL, for writing through *fp (complete it by OutputCommit). */
PetscErrorCode OutputFile(M2dOutput *o, const char *suffix, FILE **fp);
/* A load history's earlier states, for ParaView's time series: step k's
 * fields (usually fewer than the final state's) at pseudo-time time[k]. */
typedef struct {
  PetscInt           n;
  const PetscReal   *time;
  const M2dFieldSet *step;
} M2dSeries;

/* Write N.vtu and N.h5 + N.xmf (as paths->vtu, paths->h5 say) under their
 * temporary names: m's coordinates times L (the user's length unit), the
 * fields fs of the final state; with a series (NULL: none) the .h5 also holds
 * each earlier state in /steps/K/ and the .xmf is a temporal collection, its
 * last time the final state (time_final). Collective; errors on every rank. */
PetscErrorCode OutputWriteFields(const M2dMesh *m, PetscReal L, M2dOutput *o, const M2dFieldSet *fs, const M2dSeries *series, PetscReal time_final);
/* Close the files and rename them into place, in the order they were added.
 * Collective; errors raised on every rank, the temporaries then removed. */
PetscErrorCode OutputCommit(M2dOutput *o);
/* Remove the temporaries not yet in place. Not collective. */
void OutputAbort(M2dOutput *o);
#endif
