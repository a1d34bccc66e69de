/* units.h - the program computes in reference units, so that its answers do
 * not depend on the units of the input (E in Pa or GPa, lengths in m or um).
 *
 * Three references, each rounded to a power of two so that scaling is exact
 * in floating point: a length L (the mesh's bounding-box diagonal), a modulus
 * E (the largest Young's modulus) and a stress S (the load: the largest
 * applied pressure or traction; without loads E times the largest prescribed
 * displacement over L; at worst E). Displacements are measured in U = S L / E,
 * so that u, gaps and strains are O(1) numbers whatever the scene: with
 * x' = x/L, E' = E_body/E, p' = p/S and u' = u/U the discrete equations
 * K' u' = f', B' u' + g0' >= 0 hold exactly when K u = f, B u + g0 >= 0 do,
 * with K' = K/E, f' = f/(S L), B' = B/L, g0' = g0/(L U), lambda' = lambda/S.
 * Every tolerance inside the program is relative to these O(1) numbers; the
 * report turns results back into the user's units. */
#ifndef M2D_UNITS_H
#define M2D_UNITS_H
#include "mesh.h"

typedef struct {
  PetscReal L; /* length */
  PetscReal E; /* modulus */
  PetscReal S; /* stress (load) */
  PetscReal U; /* displacement, S L / E */
} M2dUnits;

/* The references of scene s (physical values) on mesh m (physical
 * coordinates). Collective on the mesh's communicator. */
PetscErrorCode M2dUnitsCreate(const M2dMesh *m, const M2dScene *s, M2dUnits *u);
/* The reference energy norm sqrt(S U L) (per unit thickness; computed without
 * overflow). Not collective. */
PetscReal      M2dUnitsEnergyNorm(const M2dUnits *u);
/* Scale a scene's numbers (moduli, loads, prescribed displacements, contact
 * reach and c, Hertz data, exact pressure) into reference units, in place.
 * Not collective. */
void M2dUnitsScaleScene(const M2dUnits *u, M2dScene *s);
/* Multiply the mesh coordinates by `factor` (1/L: into reference units, for
 * good; the writers take L). Collective on the mesh's communicator. */
PetscErrorCode M2dUnitsScaleMesh(M2dMesh *m, PetscReal factor);
#endif
