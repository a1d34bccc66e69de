/* units.c - reference units (see units.h). */
#include "units.h"
#include <math.h>

#define M2D_UNITS_MIN 1e-300 /* results this small keep 8 decades above the subnormals */
#define M2D_UNITS_MAX 1e300

/* the power of two nearest to v > 0 (scaling by it is exact) */
static PetscReal Pow2(PetscReal v)
{
  return PetscPowReal(2.0, PetscFloorReal(PetscLog2Real(v) + 0.5));
}

/* bounding box of the local vertices, reduced over the ranks */
static PetscErrorCode BoundingBox(const M2dMesh *m, PetscReal lo[2], PetscReal hi[2])
{
  Vec                cl;
  const PetscScalar *ca;
  PetscInt           n;
  PetscReal          box[4] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL};

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(VecGetLocalSize(cl, &n));
  PetscCall(VecGetArrayRead(cl, &ca));
  for (PetscInt i = 0; i < n; i += 2)
    for (int d = 0; d < 2; d++) {
      box[d]     = PetscMin(box[d], PetscRealPart(ca[i + d]));
      box[2 + d] = PetscMin(box[2 + d], -PetscRealPart(ca[i + d]));
    }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, box, 4, MPIU_REAL, MPI_MIN, PetscObjectComm((PetscObject)m->dm)));
  for (int d = 0; d < 2; d++) {
    lo[d] = box[d];
    hi[d] = -box[2 + d];
  }
  PetscFunctionReturn(0);
}

/* the largest load stress over the box: |P + G.x| at its corners, |t| */
static PetscReal LoadStress(const M2dScene *s, const PetscReal lo[2], const PetscReal hi[2])
{
  PetscReal S = 0;
  for (PetscInt l = 0; l < s->nload; l++) {
    const M2dEdgeLoad *ld = &s->load[l];
    if (!ld->is_pressure) {
      S = PetscMax(S, hypot(ld->t[0], ld->t[1])); /* no overflow of t^2 (a traction of 1e308 gave S = inf, then NaN) */
      continue;
    }
    for (int k = 0; k < 4; k++) {
      PetscReal x = k % 2 ? hi[0] : lo[0], y = k / 2 ? hi[1] : lo[1];
      S           = PetscMax(S, PetscAbsReal(ld->p + ld->grad[0] * x + ld->grad[1] * y));
    }
  }
  return S;
}

/* sqrt(S U L) without the overflow of the product */
static PetscReal EnergyNorm(PetscReal S, PetscReal U, PetscReal L)
{
  return PetscSqrtReal(S) * PetscSqrtReal(U) * PetscSqrtReal(L);
}

PetscReal M2dUnitsEnergyNorm(const M2dUnits *u)
{
  return EnergyNorm(u->S, u->U, u->L);
}

PetscErrorCode M2dUnitsCreate(const M2dMesh *m, const M2dScene *s, M2dUnits *u)
{
  PetscReal lo[2], hi[2], L, E = 0, S, V = 0;

  PetscFunctionBeginUser;
  PetscCall(BoundingBox(m, lo, hi));
  L = PetscSqrtReal(PetscSqr(hi[0] - lo[0]) + PetscSqr(hi[1] - lo[1]));
  PetscCheck(L > 0 && PetscIsNormalReal(L), PetscObjectComm((PetscObject)m->dm), PETSC_ERR_USER_INPUT, "mesh file(s) %s: the bodies have no extent (bounding-box diagonal %g)", m->files, (double)L);
  for (PetscInt b = 0; b < s->nbody; b++) E = PetscMax(E, s->body[b].E);
  for (PetscInt k = 0; k < s->ndir; k++) V = PetscMax(V, PetscMax(PetscAbsReal(s->dir[k].value[0]), PetscAbsReal(s->dir[k].value[1])));
  S = LoadStress(s, lo, hi);
  if (!(S > 0) && s->exact == M2D_EXACT_MMS) S = E * PetscAbsReal(s->mms_amplitude) / L;
  /* the stress of the prescribed displacements counts too: a value of 1e300
   * with E = 1e9 scaled to 1e303 and overflowed to NaN in the solve */
  if (V > 0) S = PetscMax(S, E * (V / L));
  if (!(S > 0)) S = E;
  /* stresses and displacements in the user's units must stay normal doubles
   * with room to spare: a pressure of 1e-308 on E = 1e9 (displacements of
   * 1e-317, subnormal) exited 0 with stresses wrong by 3e-4 */
  PetscCheck(S >= M2D_UNITS_MIN && S <= M2D_UNITS_MAX && S * (L / E) >= M2D_UNITS_MIN && S * (L / E) <= M2D_UNITS_MAX, PetscObjectComm((PetscObject)m->dm), PETSC_ERR_USER_INPUT,
             "the loads and prescribed displacements give stresses of about %g and displacements of about %g (largest E %g, size %g): double precision keeps results only within [%g, %g]; state the loads, moduli and lengths in other units", (double)S, (double)(S * (L / E)), (double)E, (double)L, M2D_UNITS_MIN, M2D_UNITS_MAX);
  /* and the report's forces S L, energy norms sqrt(S U L) (per unit
   * thickness) and contact stiffness c ~ E/L^2 (-mesh_scale 1e200 on S2: an
   * energy norm of inf, null in the summary) */
  {
    PetscReal F = S * L, W = EnergyNorm(S, S * (L / E), L), C = E / L / L;
    PetscCheck(F >= M2D_UNITS_MIN && F <= M2D_UNITS_MAX && W >= M2D_UNITS_MIN && W <= M2D_UNITS_MAX && C >= M2D_UNITS_MIN && C <= M2D_UNITS_MAX, PetscObjectComm((PetscObject)m->dm), PETSC_ERR_USER_INPUT,
               "the scene gives forces of about %g, energy norms of about %g and contact stiffnesses of about %g (stresses %g, largest E %g, size %g): double precision keeps results only within [%g, %g]; state the loads, moduli and lengths in other units", (double)F, (double)W, (double)C, (double)S, (double)E, (double)L, M2D_UNITS_MIN, M2D_UNITS_MAX);
  }
  u->L = Pow2(L);
  u->E = Pow2(E);
  u->S = Pow2(S);
  u->U = u->S * u->L / u->E; /* powers of two: exact */
  PetscCall(PetscInfo(NULL, "reference units: length %g, modulus %g, stress %g, displacement %g\n", (double)u->L, (double)u->E, (double)u->S, (double)u->U));
  PetscFunctionReturn(0);
}

void M2dUnitsScaleScene(const M2dUnits *u, M2dScene *s)
{
  for (PetscInt b = 0; b < s->nbody; b++) s->body[b].E /= u->E;
  for (PetscInt l = 0; l < s->nload; l++) { /* p + G.x with x = L x': G' = G L / S */
    M2dEdgeLoad *ld = &s->load[l];
    ld->p /= u->S;
    for (int d = 0; d < 2; d++) {
      ld->grad[d] *= u->L / u->S;
      ld->t[d] /= u->S;
    }
  }
  for (PetscInt k = 0; k < s->ndir; k++)
    for (int d = 0; d < 2; d++) s->dir[k].value[d] /= u->U;
  s->reach /= u->L;
  s->contact_c *= u->L * u->U / u->S; /* lambda / c is a weighted gap (length x displacement) */
  for (PetscInt k = 0; k < s->npair; k++) s->pair[k].hertz_radius *= u->U / (u->L * u->L); /* the radius enters Hertz as the gap x^2/2R: a displacement over a length^2 */
  s->hertz_load /= u->S * u->L;
  s->exact_p /= u->S;
  s->exact_tau /= u->S;
  s->mms_amplitude /= u->U;
  s->mms_wavenumber *= u->L;
}

PetscErrorCode M2dUnitsScaleMesh(M2dMesh *m, PetscReal factor)
{
  Vec cg, cl;

  PetscFunctionBeginUser;
  if (factor == 1.0) PetscFunctionReturn(0);
  /* both exist before either is scaled: one may be created from the other on demand */
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinates(m->dm, &cg));
  PetscCall(VecScale(cl, factor));
  PetscCall(VecScale(cg, factor));
  PetscFunctionReturn(0);
}
