/* contact.h - the contact pair of a scene: surfaces, mortar segments or NTS
 * rows, and the interface results (pressure, gap, force) after the solve. */
#ifndef M2D_CONTACT_H
#define M2D_CONTACT_H
#include "kkt.h"
#include "mesh.h"

typedef struct {
  Surface     nm, m;
  SegmentSet  seg;
  ContactRows R;
  PetscReal   reach;
  /* results, on every rank, one per multiplier */
  PetscReal  *pressure, *gap;
  PetscReal   force[2]; /* total contact force on the non-mortar body */
  PetscReal   force_n;  /* integral of the contact pressure */
} Contact;

PetscErrorCode ContactSetup(const Mesh *m, const Scene *s, Contact *c);
PetscErrorCode ContactResults(Contact *c, const KKT *kkt, Vec u, Vec lam);
/* a vector in the displacement layout: component 0 pressure, 1 gap (NaN off the interface) */
PetscErrorCode ContactFillField(const Contact *c, Vec field);
PetscErrorCode ContactWriteCSV(MPI_Comm comm, const Contact *c, const char *path);
PetscErrorCode ContactDestroy(Contact *c);
#endif
