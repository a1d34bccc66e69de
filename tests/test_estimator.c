/* Unit tests of the error estimator (estimator.h) on meshes written here:
 * - a linear displacement on a randomly distorted mesh: eta = 0 to round-off
 *   (both recoveries);
 * - two bodies glued along y = 1/2 (shared vertices) with different constant
 *   strains: eta = 0 only if the recovery stays inside each body;
 * - a quadratic displacement on a smoothly distorted mesh: sum eta^2 falls as
 *   h^2 (the energy-norm error of Q4 is O(h));
 * - the interpolant of the manufactured solution: estimate / true error -> 1;
 * - the size field: uniform indicators give uniform refinement by
 *   (target/estimate)^(1/p), the clamps hold, a singular cell is refined more. */
#include "elasticity.h"
#include "estimator.h"

#include "check.h"

typedef enum {
  GRID_RANDOM,
  GRID_SMOOTH
} GridKind;

/* n x n quads on the unit square, interior nodes moved; two physical
 * surfaces "lower" (y < 1/2) and "upper" sharing the vertices at y = 1/2 */
static PetscErrorCode WriteGrid(const char *path, PetscInt n, GridKind kind)
{
  FILE *f = fopen(path, "w");

  PetscFunctionBeginUser;
  PetscCheck(f, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s", path);
  fprintf(f, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 1 \"lower\"\n2 2 \"upper\"\n$EndPhysicalNames\n");
  fprintf(f, "$Nodes\n%d\n", (int)((n + 1) * (n + 1)));
  for (PetscInt j = 0; j <= n; j++)
    for (PetscInt i = 0; i <= n; i++) {
      PetscReal x = (PetscReal)i / n, y = (PetscReal)j / n;
      if (kind == GRID_RANDOM && i > 0 && i < n && j > 0 && j < n && 2 * j != n) {
        unsigned h = (unsigned)(i * 7919 + j * 104729) * 2654435761u;
        x += 0.25 / n * (((h >> 8) & 1023) / 511.5 - 1);
        y += 0.25 / n * (((h >> 18) & 1023) / 511.5 - 1);
      } else if (kind == GRID_SMOOTH) {
        PetscReal dx = 0.08 * PetscSinReal(2 * PETSC_PI * x) * PetscSinReal(PETSC_PI * y);
        PetscReal dy = 0.06 * PetscSinReal(PETSC_PI * x) * PetscSinReal(2 * PETSC_PI * y);
        x += dx;
        y += dy;
      }
      fprintf(f, "%d %.17g %.17g 0\n", (int)(j * (n + 1) + i + 1), (double)x, (double)y);
    }
  fprintf(f, "$EndNodes\n$Elements\n%d\n", (int)(n * n));
  for (PetscInt j = 0; j < n; j++)
    for (PetscInt i = 0; i < n; i++) {
      int v0 = (int)(j * (n + 1) + i + 1);
      fprintf(f, "%d 3 2 %d %d %d %d %d %d\n", (int)(j * n + i + 1), 2 * j < n ? 1 : 2, 2 * j < n ? 1 : 2, v0, v0 + 1, v0 + (int)n + 2, v0 + (int)n + 1);
    }
  fprintf(f, "$EndElements\n");
  PetscCheck(!fclose(f), PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s", path);
  PetscFunctionReturn(0);
}

typedef void (*Field)(PetscReal x, PetscReal y, PetscInt body, const M2dScene *s, PetscReal u[2]);

static void Linear(PetscReal x, PetscReal y, PetscInt body, const M2dScene *s, PetscReal u[2])
{
  (void)body, (void)s;
  u[0] = 1e-3 * x + 2e-3 * y + 0.5;
  u[1] = -5e-4 * x + 7e-4 * y - 0.1;
}

/* continuous at y = 1/2, a different constant strain in each half */
static void Kinked(PetscReal x, PetscReal y, PetscInt body, const M2dScene *s, PetscReal u[2])
{
  (void)body, (void)s;
  u[0] = 1e-3 * x + (y < 0.5 ? 2e-3 * y : 1e-3 + 5e-3 * (y - 0.5));
  u[1] = 7e-4 * y;
}

static void Quadratic(PetscReal x, PetscReal y, PetscInt body, const M2dScene *s, PetscReal u[2])
{
  (void)body, (void)s;
  u[0] = 1e-3 * x * x;
  u[1] = 1e-3 * x * y;
}

static void Mms(PetscReal x, PetscReal y, PetscInt body, const M2dScene *s, PetscReal u[2])
{
  (void)body;
  M2dMMSDisplacement(s, x, y, u);
}

typedef struct {
  M2dScene  s;
  M2dMesh   m;
  Vec       u;
  PetscReal *eta;
} Case;

/* read the grid, interpolate the field at the vertices */
static PetscErrorCode CaseCreate(const char *path, Field fn, Case *k)
{
  PetscSection       gsec, cs;
  Vec                cl;
  const PetscScalar *ca;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsSetValue(NULL, "-mesh", path));
  PetscCall(PetscOptionsSetValue(NULL, "-bodies", "lower,upper"));
  PetscCall(PetscOptionsSetValue(NULL, "-exact", "mms"));
  PetscCall(SceneReadOptions(PETSC_COMM_WORLD, &k->s));
  PetscCall(MeshCreate(PETSC_COMM_WORLD, &k->s, &k->m));
  PetscCall(SceneReadMaterials(PETSC_COMM_WORLD, &k->s));
  PetscCall(DMCreateGlobalVector(k->m.dm, &k->u));
  PetscCall(DMGetGlobalSection(k->m.dm, &gsec));
  PetscCall(DMGetCoordinatesLocal(k->m.dm, &cl));
  PetscCall(DMGetCoordinateSection(k->m.dm, &cs));
  PetscCall(VecGetArrayRead(cl, &ca));
  for (PetscInt v = k->m.vStart; v < k->m.vEnd; v++) {
    PetscInt    goff, coff;
    PetscReal   uv[2];
    PetscScalar val[2];
    PetscCall(PetscSectionGetOffset(gsec, v, &goff));
    if (goff < 0) continue;
    PetscCall(PetscSectionGetOffset(cs, v, &coff));
    fn(PetscRealPart(ca[coff]), PetscRealPart(ca[coff + 1]), 0, &k->s, uv);
    val[0] = uv[0];
    val[1] = uv[1];
    PetscCall(VecSetValue(k->u, goff, val[0], INSERT_VALUES));
    PetscCall(VecSetValue(k->u, goff + 1, val[1], INSERT_VALUES));
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCall(VecAssemblyBegin(k->u));
  PetscCall(VecAssemblyEnd(k->u));
  PetscCall(PetscMalloc1(k->m.cEnd - k->m.cStart + 1, &k->eta));
  PetscFunctionReturn(0);
}

static PetscErrorCode CaseDestroy(Case *k)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(k->eta));
  PetscCall(VecDestroy(&k->u));
  PetscCall(MeshDestroy(&k->m));
  PetscFunctionReturn(0);
}

static PetscErrorCode Estimate(const char *path, Field fn, M2dRecovery rec, M2dErrorEstimate *e, PetscReal *true_err)
{
  Case      k;
  PetscReal nrm;

  PetscFunctionBeginUser;
  PetscCall(CaseCreate(path, fn, &k));
  PetscCall(M2dEstimateError(&k.m, &k.s, k.u, NULL, rec, k.eta, NULL, NULL, e));
  if (true_err) PetscCall(M2dExactEnergyError(&k.m, &k.s, k.u, true_err, &nrm));
  PetscCall(CaseDestroy(&k));
  PetscFunctionReturn(0);
}

/* global sums of synthetic indicators, as M2dEstimateError gives them */
static void Sums(const PetscReal eta[], PetscInt n, M2dErrorEstimate *e)
{
  PetscReal s = 0;
  for (PetscInt k = 0; k < n; k++) s += eta[k] * eta[k];
  e->estimate    = PetscSqrtReal(s);
  e->energy_norm = 0.5;
}

static PetscErrorCode TestSizeField(void)
{
  M2dSizeFieldParams p;
  M2dErrorEstimate   e;
  PetscReal          h[100], eta[100], hn[100], N, worst = 0;

  PetscFunctionBeginUser;
  M2dSizeFieldDefaults(&p);
  p.target_rel = 0.01;
  PetscCall(PetscMemzero(&e, sizeof(e)));
  for (int k = 0; k < 100; k++) {
    h[k]   = 0.1;
    eta[k] = 1e-3;
  }
  Sums(eta, 100, &e); /* 2% now, 1% wanted: h/2 everywhere (p = 1) */
  PetscCall(M2dSizeField(PETSC_COMM_SELF, 100, h, eta, &e, &p, hn, &N));
  for (int k = 0; k < 100; k++) worst = PetscMax(worst, PetscAbsReal(hn[k] / h[k] - 0.5));
  CHECK(worst < 1e-8 && PetscAbsReal(N - 400) < 1e-5, "size field: uniform eta, half the error -> h/2 and 4x the cells (%.1e, N = %g)", (double)worst, (double)N);
  eta[0] = 1.0; /* one cell holding nearly all the error: singular */
  Sums(eta, 100, &e);
  PetscCall(M2dSizeField(PETSC_COMM_SELF, 100, h, eta, &e, &p, hn, &N));
  CHECK(PetscAbsReal(hn[0] / h[0] - p.min_factor) < 1e-12, "size field: the singular cell gets the largest refinement allowed (%g)", (double)(hn[0] / h[0]));
  eta[0] = 1.5e-3; /* above its share: as a singular cell it is refined more than by the smooth rule */
  Sums(eta, 100, &e);
  {
    PetscReal f_sing, f_smooth, N2, rule;
    p.sing_share = 2;
    PetscCall(M2dSizeField(PETSC_COMM_SELF, 100, h, eta, &e, &p, hn, &N));
    f_sing       = hn[0] / h[0];
    p.sing_share = 10;
    PetscCall(M2dSizeField(PETSC_COMM_SELF, 100, h, eta, &e, &p, hn, &N2));
    f_smooth = hn[0] / h[0];
    rule     = PetscSqrtReal(p.target_rel * e.energy_norm / (PetscSqrtReal(N2) * eta[0])); /* order 2 */
    CHECK(f_sing < f_smooth && PetscAbsReal(f_smooth - rule) < 1e-8 && f_smooth < 0.5 && f_sing >= p.min_factor, "size field: a singular cell is refined more (%.3f < %.3f = the rule's %.3f)", (double)f_sing, (double)f_smooth, (double)rule);
  }
  for (int k = 0; k < 100; k++) eta[k] = 1e-9; /* far below the target: coarsen, clamped */
  Sums(eta, 100, &e);
  PetscCall(M2dSizeField(PETSC_COMM_SELF, 100, h, eta, &e, &p, hn, &N));
  CHECK(PetscAbsReal(hn[5] / h[5] - p.max_factor) < 1e-12 && PetscAbsReal(N - 25) < 1e-6, "size field: coarsening clamped at max_factor (%g, N = %g)", (double)(hn[5] / h[5]), (double)N);
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  char             path[3][PETSC_MAX_PATH_LEN];
  M2dErrorEstimate e;
  const PetscInt   lev[3] = {8, 16, 32};
  PetscReal        s2[3], eff[3];

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(PetscSNPrintf(path[0], sizeof(path[0]), "test_estimator_random.msh"));
  PetscCall(WriteGrid(path[0], 8, GRID_RANDOM));
  for (int r = 0; r < 2; r++) {
    M2dRecovery rec = r ? M2D_RECOVERY_AVERAGE : M2D_RECOVERY_SPR;
    PetscCall(Estimate(path[0], Linear, rec, &e, NULL));
    /* u carries an offset 500x its gradient x the size: the strains themselves lose ~3 digits */
    CHECK(e.energy_norm > 0 && e.estimate_rel < 1e-11, "%s: linear field on a distorted mesh, estimate/energy = %.1e", r ? "average" : "spr", (double)e.estimate_rel);
    PetscCall(Estimate(path[0], Kinked, rec, &e, NULL));
    CHECK(e.estimate_rel < 1e-12, "%s: two glued bodies, a constant strain each: no smoothing across them (%.1e)", r ? "average" : "spr", (double)e.estimate_rel);
  }
  for (int l = 0; l < 3; l++) {
    PetscReal t;
    PetscCall(PetscSNPrintf(path[l], sizeof(path[l]), "test_estimator_smooth_%d.msh", (int)lev[l]));
    PetscCall(WriteGrid(path[l], lev[l], GRID_SMOOTH));
    PetscCall(Estimate(path[l], Quadratic, M2D_RECOVERY_SPR, &e, NULL));
    s2[l] = PetscSqr(e.estimate);
    PetscCall(Estimate(path[l], Mms, M2D_RECOVERY_SPR, &e, &t));
    eff[l] = e.estimate / t;
    printf("     n = %2d: quadratic sum eta^2 = %.4e; MMS interpolant: estimate %.4e, true %.4e, effectivity %.4f\n", (int)lev[l], (double)s2[l], (double)e.estimate, (double)t, (double)eff[l]);
  }
  for (int l = 1; l < 3; l++) {
    PetscReal rate = PetscLog2Real(s2[l - 1] / s2[l]);
    CHECK(s2[l] > 0 && rate > 1.9 && rate < 2.1, "quadratic field: sum eta^2 rate %.3f in h (expected 2)", (double)rate);
  }
  CHECK(eff[0] > 0.5 && eff[0] < 3 && PetscAbsReal(eff[2] - 1) < 0.1 && PetscAbsReal(eff[2] - 1) < PetscAbsReal(eff[0] - 1) + 1e-3, "MMS interpolant: effectivity %.3f, %.3f, %.3f -> 1", (double)eff[0], (double)eff[1], (double)eff[2]);
  PetscCall(TestSizeField());
  for (int l = 0; l < 3; l++) remove(path[l]);
  remove("test_estimator_random.msh");
  PetscCall(PetscFinalize());
  printf("%d failed\n", failures);
  return failures ? 1 : 0;
}
