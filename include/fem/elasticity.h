/* elasticity.h - bilinear quadrilateral (Q4) plane elasticity, small strain.
 *
 * Hand-written Q4 kernels rather than PetscFE: the contact module needs the
 * element-to-vertex map and cell stresses anyway, the kernels are 100 lines,
 * and they are unit-tested on their own (tests/test_q4.c).  Voigt order
 * [xx, yy, xy] with engineering shear strain. */
#ifndef M2D_ELASTICITY_H
#define M2D_ELASTICITY_H
#include "frames.h"
#include "scene.h"

/* material matrix (3x3, row major) */
void M2dMaterialMatrix(PetscReal E, PetscReal nu, M2dPlane plane, PetscReal D[9]);
/* shape function values and x,y-derivatives at (xi, eta); returns det J */
PetscReal Q4Shape(const PetscReal xy[8], PetscReal xi, PetscReal eta, PetscReal N[4], PetscReal dN[8]);
/* strain [exx, eyy, gxy] from the x,y-derivatives dN (Q4Shape) and the nodal
 * displacements ue [u0x u0y u1x ...] */
void Q4Strain(const PetscReal dN[8], const PetscReal ue[8], PetscReal eps[3]);
/* element stiffness (8x8 row major, dofs [u0x u0y u1x ...]), 2x2 Gauss; with
 * sri the part lam m m^T of D (m = [1 1 0]) is integrated at the centre only */
void Q4Stiffness(const PetscReal xy[8], const PetscReal D[9], PetscBool sri, PetscReal lam, PetscReal Ke[64]);
/* area-averaged stress [sxx, syy, sxy] of the element (same split with sri) */
void Q4AverageStress(const PetscReal xy[8], const PetscReal D[9], PetscBool sri, PetscReal lam, const PetscReal ue[8], PetscReal sig[3]);
/* the lambda of D's split D = lam m m^T + rest (plane stress: 2 lam mu / (lam + 2 mu)) */
PetscReal M2dLambda(PetscReal E, PetscReal nu, M2dPlane plane);

/* assemble K and the load vector f (edge loads, body force of the MMS) */
/* K and f in the frames' coordinates (frames.h: identity where no frame). Collective. */
PetscErrorCode ElasticityAssemble(const M2dMesh *m, const M2dScene *s, const M2dFrames *fr, Mat K, Vec f);
/* Dirichlet rows (global, locally owned, in the frames' coordinates) and
 * their values; the caller PetscFree()s each array. Not collective. */
PetscErrorCode ElasticityDirichletRows(const M2dMesh *m, const M2dScene *s, const M2dFrames *fr, PetscInt *n, PetscInt **rows, PetscScalar **vals);
/* Apply Dirichlet rows to K, f (symmetric elimination, u set on those rows) */
PetscErrorCode ElasticityApplyDirichlet(Mat K, Vec f, Vec u, PetscInt n, const PetscInt rows[], const PetscScalar vals[]);
/* The same elimination's effect on another load case, K left as it is
 * (before ElasticityApplyDirichlet): u = the values on the rows, f <- f - K u
 * on the free rows and diag u on the held ones. Collective. */
PetscErrorCode ElasticityLiftDirichlet(Mat K, Vec f, Vec u, PetscInt n, const PetscInt rows[], const PetscScalar vals[]);
/* The edge loads of load stage `stage` > 0 alone (scene.h), in the frames'
 * coordinates. Collective. */
PetscErrorCode ElasticityStageLoad(const M2dMesh *m, const M2dScene *s, const M2dFrames *fr, PetscInt stage, Vec f);
/* per local cell: sigma_x, sigma_y, sigma_z, sigma_xy, von Mises (5 per cell) */
PetscErrorCode ElasticityCellStress(const M2dMesh *m, const M2dScene *s, Vec u, PetscReal *stress);

/* per local cell, over its 2x2 Gauss points (2 per cell): the largest
 * principal strain in magnitude (plane stress: and |eps_zz|) and the largest
 * rotation |u_y,x - u_x,y| / 2. Not collective (u's ghosts: collective). */
PetscErrorCode ElasticityCellStrain(const M2dMesh *m, const M2dScene *s, Vec u, PetscReal *strain);

/* integral of the pressure of load l over its curve (global); *both: the
 * curve reaches both sides of x = 0 (a whole body, not a half one with its
 * symmetry plane at x = 0). Collective. */
PetscErrorCode ElasticityPressureResultant(const M2dMesh *m, const M2dEdgeLoad *l, PetscReal *R, PetscBool *both);

/* manufactured solution (-exact mms) on body b */
void M2dMMSDisplacement(const M2dScene *s, PetscReal x, PetscReal y, PetscReal u[2]);
/* L2 norm of u_h - u_exact and of u_exact (global) */
PetscErrorCode ElasticityMMSError(const M2dMesh *m, const M2dScene *s, Vec u, PetscReal *err, PetscReal *norm, PetscReal *hmax);
#endif
