/* supports.h - is every body held? Checked before any factorization.
 *
 * Each body has three rigid modes (two translations, one rotation). The
 * Dirichlet rows and the contact rows (every candidate, as if all were
 * closed) act on them through the 3 nb x 3 nb Gram matrix G = sum_rows g g^T,
 * g = the row applied to the rigid modes. A zero eigenvalue of G is a rigid
 * motion that nothing resists: a body held by nothing (frictionless contact
 * resists only normal motion). */
#ifndef M2D_SUPPORTS_H
#define M2D_SUPPORTS_H
#include "contact.h"

PetscErrorCode CheckRigidModes(const M2dMesh *m, const M2dScene *s, const M2dContact *ct, PetscInt ndir, const PetscInt drows[]);
#endif
