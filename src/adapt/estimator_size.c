/* estimator_size.c - the mesh-size field an adaptive loop derives from the
 * error indicators (estimator.h; the rule is written above M2dSizeField). */
#include "estimator.h"
#include "elasticity.h"

static const PetscReal gp[2] = {-0.57735026918962576451, 0.57735026918962576451};

PetscErrorCode M2dCellSizes(const M2dMesh *m, PetscReal h[])
{
  Vec                cl;
  PetscSection       cs;
  const PetscScalar *ca;

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(VecGetArrayRead(cl, &ca));
  for (PetscInt c = m->cStart; c < m->cEnd; c++) {
    PetscReal xy[8], N[4], dN[8], area = 0;
    MeshCellCoordinates(m, ca, cs, c, xy);
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2; j++) area += Q4Shape(xy, gp[i], gp[j], N, dN); /* exact for a bilinear map */
    h[c - m->cStart] = PetscSqrtReal(area);
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscFunctionReturn(0);
}

void M2dSizeFieldDefaults(M2dSizeFieldParams *p)
{
  p->target_rel = 0.05;
  p->order      = 2;
  p->order_sing = 0.5;
  p->sing_share = 10;
  p->min_factor = 0.125;
  p->max_factor = 2;
  p->max_cells  = 0;
}

/* per cell, what the factor h_new/h_K needs apart from N and the target's
 * scale t (1: eta_T as asked): with a = eta_T/eta_K, f = (t a)^(1/q)
 * N^(-1/(2q)) (ratio t a/sqrt(N) < 1: the cell is above its share) */
typedef struct {
  PetscReal *a, *f1, *fs; /* a, a^(1/order), a^(1/order_sing); a = 0: eta_K = 0 */
  PetscBool *sing;        /* holds at least sing_share x the mean eta_K^2 */
} SizeCells;

/* the factors of a target scaled by t and a cell count N */
typedef struct {
  PetscReal ta, s1, ss; /* t sqrt(N)^-1 for the singular test, (t^2/N)^(1/(2q)), the same with q_sing */
} SizeScale;

static SizeScale Scale(PetscReal t, PetscReal N, const M2dSizeFieldParams *p)
{
  SizeScale k = {PetscSqrtReal(N) / t, PetscPowReal(t * t / N, 0.5 / p->order), PetscPowReal(t * t / N, 0.5 / p->order_sing)};
  return k;
}

static PetscReal SizeFactor(const SizeCells *sc, PetscInt k, SizeScale z, const M2dSizeFieldParams *p)
{
  PetscReal f;
  if (!(sc->a[k] > 0)) return p->max_factor;
  f = sc->sing[k] && sc->a[k] < z.ta ? sc->fs[k] * z.ss : sc->f1[k] * z.s1;
  return PetscMin(PetscMax(f, p->min_factor), p->max_factor);
}

/* expected number of cells sum_K (h_K/h_new)^2 for the target scale t and N, minus N (global) */
static PetscErrorCode CountExcess(MPI_Comm comm, PetscInt n, const SizeCells *sc, PetscReal t, PetscReal N, const M2dSizeFieldParams *p, PetscReal *G)
{
  PetscReal cnt = 0;
  SizeScale z   = Scale(t, N, p);

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < n; k++) cnt += 1 / PetscSqr(SizeFactor(sc, k, z, p));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &cnt, 1, MPIU_REAL, MPI_SUM, comm));
  *G = cnt - N;
  PetscFunctionReturn(0);
}

/* The rule. Where the solution is smooth a cell's indicator falls as
 * eta_K ~ h^q, q = p + d/2 (p = 1 the energy-norm rate of Q4, d/2 = 1 because
 * eta_K^2 is an integral over the cell), so the cells that replace K carry
 * eta_K^2 (h_new/h_K)^(2q) each. A mesh of N cells that equidistributes the
 * target eta_T^2 (eta_T = target_rel x energy norm) gives each eta_T^2 / N:
 *     h_new = h_K (eta_T / (sqrt(N) eta_K))^(1/q),  clamped to [min, max] x h_K,
 * and N = sum_K (h_K / h_new)^2 is the expected number of cells: the smallest
 * root, bracketed by a geometric scan up from N_now/max^2 and bisected in log N
 * (the sum is increasing in N and bounded by the clamps). With equal eta_K this
 * is h_new/h = (eta_T/estimate)^(1/p), uniform refinement.
 * Singular cells. Near a singularity (S1's corners: u ~ r^alpha, alpha ~ 1/2;
 * Hertz zone edge: alpha = 3/2) the indicator of the cell at the singular point
 * falls only as h^alpha, so with q it would be refined too little and the loop
 * would take many steps to grade there. A cell holding at least sing_share
 * times the mean eta_K^2 (on a smooth solution no cell does; at a singular point
 * a few do, and fewer as the mesh grades) and above its share uses order_sing:
 * a larger refinement factor exactly where the indicator concentrates
 * (continuous at eta_K = share, where every order gives 1).
 * A cap. When N exceeds p->max_cells (> 0), the target is relaxed instead:
 * N = max_cells and eta_T scaled by the t > 1 that makes the expected count
 * N (bisected in log t; the count falls as t grows): the same distribution of
 * the error, on the cells the cap allows. */
PetscErrorCode M2dSizeField(MPI_Comm comm, PetscInt n, const PetscReal h[], const PetscReal eta[], const M2dErrorEstimate *e, const M2dSizeFieldParams *p, PetscReal hnew[], PetscReal *nexpect)
{
  PetscReal       etaT = p->target_rel * e->energy_norm, ncur = n, sing2, lo, hi, G, t = 1;
  const PetscReal step = 1.189207115002721; /* 2^(1/4) */
  SizeCells       sc;
  SizeScale       z;

  PetscFunctionBeginUser;
  PetscCheck(p->target_rel > 0 && p->order > 0 && p->order_sing > 0 && p->sing_share > 0 && p->min_factor > 0 && p->min_factor <= 1 && p->max_factor >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE, "size field: target %g, orders %g %g, share %g, factors [%g, %g] out of range", (double)p->target_rel, (double)p->order, (double)p->order_sing, (double)p->sing_share, (double)p->min_factor, (double)p->max_factor);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &ncur, 1, MPIU_REAL, MPI_SUM, comm));
  sing2 = ncur > 0 ? p->sing_share * e->estimate * e->estimate / ncur : 0;
  PetscCall(PetscMalloc4(n + 1, &sc.a, n + 1, &sc.f1, n + 1, &sc.fs, n + 1, &sc.sing));
  for (PetscInt k = 0; k < n; k++) {
    sc.a[k]    = eta[k] > 0 ? etaT / eta[k] : 0;
    sc.f1[k]   = eta[k] > 0 ? PetscPowReal(sc.a[k], 1 / p->order) : 0;
    sc.fs[k]   = eta[k] > 0 ? PetscPowReal(sc.a[k], 1 / p->order_sing) : 0;
    sc.sing[k] = (PetscBool)(eta[k] * eta[k] >= sing2);
  }
  lo = ncur / PetscSqr(p->max_factor); /* G(lo) >= 0: every factor is <= max */
  for (hi = lo * step;; hi *= step) {  /* G(ncur / min^2) <= 0: the scan stops there at the latest */
    PetscCall(CountExcess(comm, n, &sc, 1, hi, p, &G));
    if (G <= 0 || hi >= ncur / PetscSqr(p->min_factor)) break;
    lo = hi;
  }
  for (int it = 0; it < 30 && hi > lo * (1 + 1e-9); it++) {
    PetscReal N = PetscSqrtReal(lo * hi);
    PetscCall(CountExcess(comm, n, &sc, 1, N, p, &G));
    if (G > 0) lo = N;
    else hi = N;
  }
  if (p->max_cells > 0 && hi > p->max_cells) { /* relax the target to fit the cap */
    PetscReal tlo = 1, thi = 2;
    hi = p->max_cells;
    for (;; thi *= 2) {
      PetscCall(CountExcess(comm, n, &sc, thi, hi, p, &G));
      if (G <= 0 || thi > 1e12) break;
      tlo = thi;
    }
    for (int it = 0; it < 40 && thi > tlo * (1 + 1e-9); it++) {
      t = PetscSqrtReal(tlo * thi);
      PetscCall(CountExcess(comm, n, &sc, t, hi, p, &G));
      if (G > 0) tlo = t;
      else thi = t;
    }
    t = thi;
  }
  *nexpect = hi;
  z        = Scale(t, hi, p);
  for (PetscInt k = 0; k < n; k++) hnew[k] = h[k] * SizeFactor(&sc, k, z, p);
  PetscCall(PetscFree4(sc.a, sc.f1, sc.fs, sc.sing));
  PetscFunctionReturn(0);
}
