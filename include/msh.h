/* msh.h - a strict reader for gmsh .msh files (formats 2.2 and 4.1 ASCII, 4.1
 * binary: gmsh -bin, ten times faster to read for large meshes).
 *
 * Why our own reader and not DMPlexCreateGmshFromFile: PETSc 3.18's reader drops
 * physical points (we need them for point supports), stops on node tags repeated
 * across two files, and a corrupted file can take it past its buffers.  This one
 * checks every count and index against the file size and the node table and
 * reports the file, line (binary: byte) and section at fault.  The DMPlex is then built from
 * the cell list it returns (mesh.c). Plain C, no PETSc: unit-testable alone. */
#ifndef M2D_MSH_H
#define M2D_MSH_H
#include <stddef.h>

typedef struct {
  int  dim; /* 0 point, 1 curve, 2 surface */
  int  tag;
  char name[128];
} MshPhysical;

typedef struct {
  long    nnode;
  double *xy;      /* 2 per node; nodes numbered 0..nnode-1 in file order */
  long    nquad;
  long   *quad;    /* 4 node indices per quad, as in the file */
  long   *quadtag; /* element tag per quad (for messages) */
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

/* Returns 0 on success; otherwise fills err with one line naming the file,
 * line and what is wrong, and returns nonzero. Always leaves m freeable. */
int  MshRead(const char *path, MshMesh *m, char *err, size_t errlen);
void MshFree(MshMesh *m);
const char *MshPhysicalName(const MshMesh *m, int dim, int tag); /* NULL if unnamed */
#endif
