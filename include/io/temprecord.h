/* temprecord.h - the temporary-file table of tempfile.h for the plain-C
 * modules (no PETSc types): remesh.c records the .geo wrapper it writes
 * before creating it, so that SIGINT, SIGTERM, SIGHUP and every exit() remove
 * it (tempfile.h). Not collective. */
#ifndef M2D_TEMPRECORD_H
#define M2D_TEMPRECORD_H
/* Record the file path (before it exists): its slot, or -1 when the path is
 * too long or the table is full (then nothing is recorded). */
int  M2dTempRecordFile(const char *path);
/* Make and record (removed with everything in it) the directory parent/<prefix><host hash>.<pid>.XXXXXX
 * (mkdtemp), its path in path; first remove those of this host's processes
 * that are gone (killed or crashed before they could). 0, or -1 (nothing made). */
int  M2dTempMakeDir(const char *parent, const char *prefix, char *path, size_t len);
/* Stop tracking it (removed, or kept on purpose); slot < 0: no-op. */
void M2dTempForgetFile(int slot);
#endif
