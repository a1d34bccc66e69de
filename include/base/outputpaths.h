/* outputpaths.h - what a run writes and where, checked before any work.
 *
 * The files of a run are plain files: DIR/N.vtu, DIR/N.h5 + DIR/N.xmf,
 * DIR/N_contact.csv (DIR = -output_dir, N = -output_name, -output picks them)
 * and the JSON summary (-summary, default DIR/N_summary.json). Each carries
 * the run's id (run_id), so that files of different runs are told apart.
 * Everything that can be known about them is checked before the mesh is
 * read, with one line naming the option: the name, the lengths, the
 * directories (created, and a file really created and removed in each), no
 * output naming a directory, a device, a FIFO or a socket, and no output
 * naming an input (a mesh, the .geo, an options file) or another output,
 * compared as files (the directory's real path and the name, or the same
 * device and inode). Once that passed, a run that fails still writes its
 * summary, with status "error" and the error line (OutputWriteFailure). */
#ifndef M2D_OUTPUTPATHS_H
#define M2D_OUTPUTPATHS_H
#include <petscsys.h>

#define M2D_OUTPUT_NAME_MAX 200 /* -output_name: leaves room for .m2d.tmp.<tag>. within a file name */
#define M2D_RUN_ID_LEN      48

typedef struct {
  char      dir[PETSC_MAX_PATH_LEN];          /* -output_dir */
  char      name[M2D_OUTPUT_NAME_MAX + 1];    /* -output_name */
  PetscBool h5, vtu, csv, summary;            /* -output (and -output_hdf5, -output_vtu) */
  char      summary_path[PETSC_MAX_PATH_LEN]; /* -summary, else DIR/N_summary.json */
  char      run_id[M2D_RUN_ID_LEN];           /* set by OutputCheckPaths, the same on every rank */
} M2dOutputPaths;

/* a file the run reads, and the option that named it (for messages) */
typedef struct {
  const char *option;
  const char *path;
} M2dInputFile;

/* Check the output paths p (summary_path "" when p->summary: the default is
 * filled in) and mesh_save ("" none) against each other and the inputs, create
 * the directories, remove what killed runs left there, and give the run its
 * id. Collective on comm; one-line errors naming the options. */
PetscErrorCode OutputCheckPaths(MPI_Comm comm, M2dOutputPaths *p, const char *mesh_save, PetscInt ninput, const M2dInputFile inputs[]);
/* Once the options are read, before they and the paths are checked: a run
 * that then fails (a misspelt option) marks the summary an earlier run left
 * at p's summary path (OutputWriteFailure), creating nothing. Not collective
 * (rank 0 of comm keeps it). */
void OutputArmEarly(MPI_Comm comm, const M2dOutputPaths *p);
/* After an error (main's error path): write the summary {"status": "error",
 * "error": msg, ...} when the paths were checked and a summary is wanted, on
 * world rank 0; before the check (OutputArmEarly), only over a summary of
 * mortar2d already at that path. Not collective; its own failures are
 * ignored. */
void OutputWriteFailure(const char *msg);
#endif
