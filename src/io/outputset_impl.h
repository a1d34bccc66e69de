/* outputset_impl.h - helpers shared by outputset.c and outputcheck.c (private). */
#ifndef M2D_OUTPUTSET_IMPL_H
#define M2D_OUTPUTSET_IMPL_H
#include <petscsys.h>

/* ".m2d.set.NAME": the link that names the current set of NAME */
PetscErrorCode M2dSetPointerName(const char *name, char *buf, size_t len);
/* remove DIR/GEN (a .m2d.gen.* directory of flat files); errors ignored */
void M2dSetRemoveGen(const char *dir, const char *gen);
/* directory part ("." when none) and file name of path; NULL outputs skipped;
 * errors when the file name is empty or a part does not fit */
PetscErrorCode M2dSetSplitPath(const char *path, char *dir, size_t dlen, char *base);
#endif
