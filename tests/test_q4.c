/* Unit tests of the Q4 kernels: symmetry, the three rigid-body modes in the
 * null space, exact stress for a linear displacement on a distorted element,
 * and the material matrices. */
#include "elasticity.h"

#include "check.h"

int main(int argc, char **argv)
{
  const PetscReal xy[8] = {0.1, -0.2, 1.3, 0.1, 1.0, 1.4, -0.1, 0.9}; /* distorted, convex */
  PetscReal       D[9], Ke[64], sym = 0, scale = 0;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  M2dMaterialMatrix(200.0, 0.3, M2D_PLANE_STRAIN, D);
  CHECK(PetscAbsReal(D[0] - 200.0 * 0.7 / (1.3 * 0.4)) < 1e-12 && PetscAbsReal(D[8] - 200.0 / 2.6) < 1e-12, "plane strain D");
  M2dMaterialMatrix(200.0, 0.3, M2D_PLANE_STRESS, D);
  CHECK(PetscAbsReal(D[0] - 200.0 / 0.91) < 1e-12 && PetscAbsReal(D[1] - 60.0 / 0.91) < 1e-12, "plane stress D");
  M2dMaterialMatrix(200.0, 0.3, M2D_PLANE_STRAIN, D);
  Q4Stiffness(xy, D, PETSC_FALSE, 0, Ke);
  for (int i = 0; i < 64; i++) scale = PetscMax(scale, PetscAbsReal(Ke[i]));
  for (int i = 0; i < 8; i++)
    for (int j = 0; j < 8; j++) sym = PetscMax(sym, PetscAbsReal(Ke[8 * i + j] - Ke[8 * j + i]));
  CHECK(sym < 1e-14 * scale, "stiffness symmetric (%.1e)", (double)(sym / scale));
  { /* rigid modes: translations and an infinitesimal rotation give zero force */
    PetscReal modes[3][8], worst = 0;
    for (int a = 0; a < 4; a++) {
      modes[0][2 * a] = 1, modes[0][2 * a + 1] = 0;
      modes[1][2 * a] = 0, modes[1][2 * a + 1] = 1;
      modes[2][2 * a] = -xy[2 * a + 1], modes[2][2 * a + 1] = xy[2 * a];
    }
    for (int k = 0; k < 3; k++)
      for (int i = 0; i < 8; i++) {
        PetscReal r = 0;
        for (int j = 0; j < 8; j++) r += Ke[8 * i + j] * modes[k][j];
        worst = PetscMax(worst, PetscAbsReal(r));
      }
    CHECK(worst < 1e-13 * scale, "rigid-body modes in the null space (%.1e)", (double)(worst / scale));
  }
  { /* a linear field u = (a x + b y, c x + d y) gives constant exact stress */
    const PetscReal a = 1e-3, b = 2e-3, c = -5e-4, d = 7e-4;
    PetscReal       ue[8], sig[3], ex[3], eps[3] = {a, d, b + c}, err = 0;
    for (int k = 0; k < 4; k++) {
      ue[2 * k]     = a * xy[2 * k] + b * xy[2 * k + 1];
      ue[2 * k + 1] = c * xy[2 * k] + d * xy[2 * k + 1];
    }
    Q4AverageStress(xy, D, PETSC_FALSE, 0, ue, sig);
    for (int r = 0; r < 3; r++) {
      ex[r] = D[3 * r] * eps[0] + D[3 * r + 1] * eps[1] + D[3 * r + 2] * eps[2];
      err   = PetscMax(err, PetscAbsReal(sig[r] - ex[r]) / PetscAbsReal(ex[0]));
    }
    CHECK(err < 1e-13, "linear field: exact stress on a distorted element (%.1e)", (double)err);
  }
  { /* shape functions: partition of unity and the Jacobian of an affine map */
    const PetscReal sq[8] = {0, 0, 2, 0, 2, 1, 0, 1};
    PetscReal       N[4], dN[8], det = Q4Shape(sq, 0.3, -0.4, N, dN);
    CHECK(PetscAbsReal(N[0] + N[1] + N[2] + N[3] - 1) < 1e-15 && PetscAbsReal(det - 0.5) < 1e-15, "partition of unity, det J = area/4");
  }
  PetscCall(PetscFinalize());
  printf("%d failed\n", failures);
  return failures ? 1 : 0;
}
