/* supports.h - is every body held? Checked before any factorization and
 * before each active-set step.
 *
 * Each body has three rigid modes (two translations, one rotation). The
 * Dirichlet rows and the contact rows act on them through the 3 nb x 3 nb Gram
 * matrix G = sum_rows g g^T / |g|^2, g = the row applied to the rigid modes. A
 * zero eigenvalue of G is a rigid motion that nothing resists: a body held by
 * nothing (frictionless contact resists only normal motion). The Dirichlet
 * part is summed once (M2dSupportsCreate); the contact part, replicated on
 * every rank, is added for each set checked, so every rank reaches the same
 * verdict without communication. A row touches the modes of at most two
 * bodies, so G is assembled from its nonzeros; the eigen-decomposition is
 * dense, (3 nbody)^3 per check (40 bodies: 1.7e6 flops; 256: 4.5e8). */
#ifndef M2D_SUPPORTS_H
#define M2D_SUPPORTS_H
#include "contact.h"
#include "frames.h"

typedef struct {
  PetscInt   nbody;
  PetscReal  centroid[M2D_MAX_BODIES][2];
  PetscReal  size[M2D_MAX_BODIES]; /* scales the rotation mode */
  PetscReal *gram;                 /* the Dirichlet rows' part of G, 3 nbody x 3 nbody (heap: 4.7 MB at 256 bodies) */
} M2dSupports;

/* The body frames and the Dirichlet part of G from this rank's Dirichlet rows
 * drows (global dofs, in the vertices' frames fr). Collective on the mesh's
 * communicator. */
PetscErrorCode M2dSupportsCreate(const M2dMesh *m, const M2dScene *s, const M2dFrames *fr, PetscInt ndir, const PetscInt drows[], M2dSupports *sup);
/* Free what M2dSupportsCreate allocated. Not collective. */
PetscErrorCode M2dSupportsDestroy(M2dSupports *sup);
/* Fail with one line naming the body and the free motion if G, with the
 * contact rows of ct selected by active (every multiplier, 1/0; NULL = every
 * candidate; ct NULL = no contact), is singular. `when` (may be NULL) is
 * added to the message. Collective (no communication; same verdict on every
 * rank). */
PetscErrorCode M2dSupportsCheck(const M2dSupports *sup, MPI_Comm comm, const M2dScene *s, const M2dContact *ct, const PetscScalar *active, const char *when);
/* The same question without failing: *held when every body is held. */
PetscErrorCode M2dSupportsHeld(const M2dSupports *sup, MPI_Comm comm, const M2dContact *ct, const PetscScalar *active, PetscBool *held);
#endif
