/* outputset.h - the results of a run replace the previous results as a whole.
 *
 * Layout of an output directory DIR for -output_name N:
 *   N.h5 N.xmf N.vtu N_contact.csv [summary]   symbolic links  -> .m2d.set.N/<file>
 *   .m2d.set.N                                 symbolic link   -> .m2d.gen.<host>.<pid>.<k>.N
 *   .m2d.gen.<host>.<pid>.<k>.N/               the files of the current set
 * A run writes its files into a new .m2d.gen... directory (the staging area);
 * commit makes sure every public name is a link through .m2d.set.N (a name
 * that is still a plain file is first hard-linked into the current set, so a
 * reader sees no change), then switches .m2d.set.N with one rename(2).
 * Guarantee: at every instant, and after any interruption (signal, SIGKILL,
 * crash; files and directory are fsync'ed before the switch), the names in
 * DIR resolve to the complete previous set or the complete new set (a reader
 * that opens N.h5, then N.xmf, may still straddle a switch).  Files
 * of other -output_name values and other files in DIR are never touched.  A
 * name the new set does not write (N.vtu after -output_vtu 0) disappears.
 * A -summary file inside DIR is part of the set; one elsewhere is written to a
 * temporary beside it and renamed right after the switch, with signals held
 * off between the two renames: only a SIGKILL or a crash in that window leaves
 * the new set with the previous summary.  Leftovers of killed runs are
 * removed by the next OutputCheckPaths on the same directory (tempfile.h). */
#ifndef M2D_OUTPUTSET_H
#define M2D_OUTPUTSET_H
#include <petscsys.h>

typedef struct _p_M2dOutputSet *M2dOutputSet;

/* Check, before any work, that the output can be written: -output_name is a
 * plain name (letters, digits, _ - . + , = @ ~; no leading - or .), no option
 * value was cut, DIR and the summary's directory exist or are created and a
 * file can be created in each, no output name is a directory.  Also removes
 * the leftovers of killed runs there.  Collective on comm; one-line errors
 * naming the option. write_files: HDF5/VTU/CSV are written (else DIR unused). */
PetscErrorCode OutputCheckPaths(MPI_Comm comm, const char *outdir, const char *outname, const char *summary, PetscBool write_files);

/* Create the staging area (after OutputCheckPaths).  summary: the -summary
 * path or NULL/"".  Collective on comm; *set is freed by Commit or Abort. */
PetscErrorCode M2dOutputSetBegin(MPI_Comm comm, const char *outdir, const char *outname, const char *summary, PetscBool write_files, M2dOutputSet *set);
/* Staging path of the file N<suffix> (e.g. ".h5", "_contact.csv"), owned by
 * the set; the same on every rank.  Not collective; errors without write_files. */
PetscErrorCode M2dOutputSetFile(M2dOutputSet set, const char *suffix, const char **path);
/* Path to write the summary to, owned by the set; NULL when there is none. */
PetscErrorCode M2dOutputSetSummary(M2dOutputSet set, const char **path);
/* The set's output name N (owned by the set). */
const char *M2dOutputSetName(M2dOutputSet set);
/* Put every file of the set in place at once (see above); on failure the
 * names keep showing the previous set and the staging area is removed.
 * Collective; frees *set. */
PetscErrorCode M2dOutputSetCommit(M2dOutputSet *set);
/* Remove the staging area and free *set (NULL: nothing).  Not collective: on
 * error paths any rank may call it (only rank 0 owns files). */
PetscErrorCode M2dOutputSetAbort(M2dOutputSet *set);
/* Abort every set of this process that is still open (main's error path,
 * where the handles are out of reach).  Not collective. */
PetscErrorCode M2dOutputSetAbortOpen(void);
#endif
