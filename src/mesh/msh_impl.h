/* msh_impl.h - the gmsh reader's internals, shared by its files (not public):
 *   msh_token.c     the token layer: text (strtol/strtod) and binary (raw bytes) reads,
 *                   every count checked against the bytes left; the only file where
 *                   text and binary differ
 *   msh_store.c     node-tag lookup, the plane check of z, element tables and storage,
 *                   MshPhysicalName, MshFree
 *   msh_sections.c  the sections of formats 4.1 and 2.2
 *   msh.c           MshRead (file, header, section loop)
 * Each file calls only the files listed above it (no circle). */
#ifndef M2D_MSH_IMPL_H
#define M2D_MSH_IMPL_H
#include "msh.h"
#include <stddef.h>

typedef struct {
  const char *path;
  char       *buf;
  size_t      len, pos;
  char       *err;
  size_t      errlen;
  const char *section;
  int         failed;
  int         binary; /* format 4.1 binary (Mesh.Binary = 1): ints 4 bytes, sizes 8 */
} Parser;

/* token layer (msh_token.c): each returns 0, or 1 after MshFail() wrote the message */
int    MshFail(Parser *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void   MshSkipSpace(Parser *p);
size_t MshRemaining(const Parser *p);
int    MshReadLong(Parser *p, long *v);   /* a text integer */
int    MshReadInt(Parser *p, long *v);    /* an int field (4 bytes in binary) */
int    MshReadSize(Parser *p, long *v);   /* a size_t field (8 bytes in binary) */
int    MshReadTag(Parser *p, long *v, const char *what); /* a size_t field that is a tag: > 0 */
int    MshReadDouble(Parser *p, double *v);
int    MshReadCount(Parser *p, long *v, long bytes_per_item, const char *what);
int    MshReadWord(Parser *p, char *w, size_t n);
int    MshExpect(Parser *p, const char *word);
int    MshBinaryStart(Parser *p);

/* node tags -> node indices (msh_store.c) */
typedef struct {
  long tag, idx;
} TagIdx;
typedef struct {
  TagIdx *t;
  long    n;
  long   *direct; /* dense tags (gmsh numbers 1..N): index by tag - lo, -1 if none */
  long    lo, hi;
} NodeMap;
long MshNodeLookup(const NodeMap *map, long tag);
int  MshBuildNodeMap(Parser *p, NodeMap *map);

/* z of every node must be one constant (msh_store.c): MshPlaneAdd gathers, MshPlaneCheck judges */
typedef struct {
  long   n, tag0, tagfar;
  double z0, zfar, far, xmin, xmax, ymin, ymax;
  size_t posfar;
} Plane;
void MshPlaneAdd(Plane *pl, const Parser *p, long tag, double x, double y, double z);
int  MshPlaneCheck(Parser *p, const Plane *pl);

/* storage of the elements read (msh_store.c) */
typedef struct {
  long qcap, lcap, pcap;
} Caps;
int MshNodesPerElement(long type);
int MshElementDim(long type);
const char *MshElementName(long type);
int MshStoreElement(Parser *p, MshMesh *m, Caps *c, long etag, long type, const long *nodes, int phys);

/* sections (msh_sections.c) */
typedef struct {
  int  dim;
  long tag;
  int  phys; /* first physical tag of the entity, -1 if none */
  long nphys;
  int *physall;
} Entity;
typedef struct {
  Entity *e;
  long    n;
} EntityTable;
int MshReadPhysicalNames(Parser *p, MshMesh *m);
int MshReadEntities41(Parser *p, EntityTable *t);
int MshReadNodes41(Parser *p, MshMesh *m, NodeMap *map);
int MshReadElements41(Parser *p, MshMesh *m, const NodeMap *map, const EntityTable *ents, Caps *c);
int MshReadNodes22(Parser *p, MshMesh *m, NodeMap *map);
int MshReadElements22(Parser *p, MshMesh *m, const NodeMap *map, Caps *c);
#endif
