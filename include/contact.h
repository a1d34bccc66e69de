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
  PetscReal  *pressure, *gap, *active;
  PetscReal   force[2]; /* total contact force on the non-mortar body */
  PetscReal   force_n;  /* integral of the contact pressure */
} Contact;

PetscErrorCode ContactSetup(const Mesh *m, const Scene *s, Contact *c);
/* active: final active set (layout of lam), NULL when every node is held closed */
PetscErrorCode ContactResults(Contact *c, const KKT *kkt, Vec u, Vec lam, Vec active);

typedef struct {
  PetscReal a, p0;           /* Hertz half-width and peak pressure */
  PetscReal half_width;      /* computed: midway between the last active and first inactive node */
  PetscReal h_edge;          /* spacing of the non-mortar nodes there */
  PetscReal peak_pressure;   /* largest nodal contact pressure */
  PetscReal pressure_l2_rel; /* ||p_h - p||_L2(0, 1.5a) / ||p||_L2(0, 1.5a), p_h piecewise linear */
} HertzResult;
/* plane strain Hertz for a cylinder (radius R, load P per unit thickness) on a
 * half-space; the symmetry axis is x = 0 and contact is in the y direction */
PetscErrorCode ContactHertz(const Contact *c, const Scene *s, HertzResult *h);
/* a vector in the displacement layout: component 0 pressure, 1 gap (NaN off the interface) */
PetscErrorCode ContactFillField(const Contact *c, Vec field);
PetscErrorCode ContactWriteCSV(MPI_Comm comm, const Contact *c, const char *path);
PetscErrorCode ContactDestroy(Contact *c);
#endif
