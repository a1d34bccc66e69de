/* msh.h - a strict reader for gmsh .msh files (formats 2.2 and 4.1 ASCII, 4.1
 * binary: gmsh -bin, ten times faster to read for large meshes).
 *
 * Why our own reader and not DMPlexCreateGmshFromFile: PETSc 3.18's reader drops
 * physical points (we need them for point supports), stops on node tags repeated
 * across two files, and a corrupted file can take it past its buffers.  This one
 * checks every count and index against the file size and the node table and
 * reports the file, line (binary: byte) and section at fault.  The DMPlex is then
 * built from the lists it returns (mesh.h: MeshCreate, or MeshCreateFromMsh for
 * an MshMesh filled in memory). Plain C, no PETSc: unit-testable alone. */
#ifndef M2D_MSH_H
#define M2D_MSH_H
#include <stdarg.h>
#include <stddef.h>

typedef struct {
  int  dim; /* 0 point, 1 curve, 2 surface */
  int  tag;
  char name[128];
} MshPhysical;

/* One mesh file's content; every array is malloc'ed (MshFree frees them all).
 * Node indices (quad, line, point) are 0-based positions in xy. Fields added
 * later must mean "absent" when zero. */
typedef struct {
  long    nnode;
  double *xy;      /* 2 per node; nodes numbered 0..nnode-1 in file order (z dropped: checked constant) */
  long    nquad;
  long   *quad;    /* 4 node indices per quad, as in the file (either orientation) */
  long   *quadtag; /* element tag per quad (for messages; NULL: the quad's position + 1) */
  int    *quadphys;/* physical surface tag of each quad, -1 if none */
  long    nline;   /* (line, physical tag) pairs: a line in two groups appears twice */
  long   *line;    /* 2 node indices per pair */
  int    *linephys;
  long    npoint;  /* (node, physical tag) pairs */
  long   *point;
  int    *pointphys;
  int     nphys;
  MshPhysical *phys;
} MshMesh;

/* Read the file at path into m (not collective: plain C). Returns 0 on success;
 * otherwise writes ONE line into err naming the file, line (binary: byte),
 * section and fault, and returns nonzero. Refuses: counts the file cannot hold,
 * unknown or repeated node tags, tags <= 0, z not constant, elements other than
 * 4-node quads, 2-node lines and points. Either way m is left for MshFree. */
int  MshRead(const char *path, MshMesh *m, char *err, size_t errlen);
/* Free every array of m and zero it (m itself is the caller's). */
void MshFree(MshMesh *m);

/* The first error of a run kept as one line "WHERE: WHAT" in err[0..len), WHAT
 * formatted from fmt; once *failed is set later errors are dropped. Sets
 * *failed, returns 1. The reader's and the remesher's (remesh.h) errors. */
int MshKeepError(char *err, size_t len, int *failed, const char *where, const char *fmt, va_list ap);
/* Name of the physical group (dim, tag) of m, NULL if unnamed; points into m. */
const char *MshPhysicalName(const MshMesh *m, int dim, int tag);
#endif
