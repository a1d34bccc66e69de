/* estimator.h - a posteriori error estimate per cell (src/estimator.c), and
 * the mesh-size field an adaptive loop derives from it (src/estimator_size.c).
 *
 * Volume part (Zienkiewicz-Zhu): the stresses are recovered per body - a
 * vertex only sees the cells of the body being recovered - either by the
 * superconvergent patch recovery (SPR: a least-squares plane a0 + a1 dx + a2 dy
 * through the 2x2 Gauss-point stresses of the cells around the vertex, a0 is
 * the vertex value) or by area-weighted nodal averaging of those stresses. The
 * recovered field sig* = sum_a N_a sig*_a is compared with the FE stress sig_h
 * in the energy norm, eta_K^2 = int_K (sig* - sig_h) : C^-1 (sig* - sig_h)
 * (3x3 Gauss). The patch sums are accumulated through the DM's local-to-global
 * map, so 1 and 2 ranks give the same indicators.
 *
 * Contact part, on the mortar segments of every non-mortar edge e (residual
 * estimator scaling, the units of eta_K^2):
 *   non-mortar cell  += h_e/E'_nm int_e (p*_nm - lambda)^2 + tau*_nm^2
 *   mortar cell      += h_f/E'_m  int_e (p*_m(proj) - lambda)^2 + tau*_m^2
 * with p* = -n.sig*.n, tau* the tangential traction (zero without friction),
 * lambda the nodal multipliers interpolated linearly, E' = E/(1 - nu^2) (plane
 * strain); and with unilateral contact the complementarity residual
 *   non-mortar cell  += h_e/Es int_e min(lambda, Es g / h_e)^2
 * (g the nodal gaps interpolated linearly, 1/Es = 1/E'_nm + 1/E'_m): the NCP
 * function is zero iff lambda >= 0, g >= 0 and lambda g = 0, so this counts a
 * negative pressure, a penetration, and pressure on an open gap. */
#ifndef M2D_ESTIMATOR_H
#define M2D_ESTIMATOR_H
#include "contact.h"
#include "mesh.h"
#include "scene.h"

typedef enum {
  M2D_RECOVERY_SPR,    /* superconvergent patch recovery (linear fit) */
  M2D_RECOVERY_AVERAGE /* area-weighted nodal average of the Gauss-point stresses */
} M2dRecovery;

typedef struct {
  PetscReal estimate;     /* sqrt(sum_K eta_K^2), global */
  PetscReal estimate_rel; /* estimate / energy_norm */
  PetscReal volume;       /* the Zienkiewicz-Zhu part alone, sqrt of its sum */
  PetscReal contact;      /* the contact part alone, sqrt of its sum (0 without contact) */
  PetscReal energy_norm;  /* sqrt(int sig_h : C^-1 sig_h) over every body */
  PetscReal eta_max;      /* largest eta_K */
} M2dErrorEstimate;

/* Indicators eta[] (one per local cell, caller allocates) and their global
 * sums in *e for the displacement u (global vector). ct: the contact pair after
 * ContactResults, or NULL (volume part only). eta_volume (may be NULL): the
 * same cells' volume part alone, from the same recovery; nodal (may be NULL):
 * the recovered stresses sigma_x, sigma_y, sigma_xy at every local vertex (3
 * each, from its body's cells). Collective on the mesh's comm. */
PetscErrorCode M2dEstimateError(const M2dMesh *m, const M2dScene *s, Vec u, const M2dContact *ct, M2dRecovery rec, PetscReal eta[], PetscReal eta_volume[], PetscReal nodal[], M2dErrorEstimate *e);

/* True energy-norm error ||sig - sig_h||_{C^-1} and ||sig||_{C^-1} (3x3 Gauss)
 * where the scene knows the answer (-exact mms: sig from finite differences of
 * M2dMMSDisplacement; -exact uniform: sig_yy = -exact_p); error otherwise.
 * Collective on the mesh's comm. */
PetscErrorCode M2dExactEnergyError(const M2dMesh *m, const M2dScene *s, Vec u, PetscReal *err, PetscReal *norm);

/* Cell size h_K = sqrt(area of K) per local cell (caller allocates). Not collective. */
PetscErrorCode M2dCellSizes(const M2dMesh *m, PetscReal h[]);

/* Parameters of the size-field rule (M2dSizeField). */
typedef struct {
  PetscReal target_rel;  /* wanted relative error: eta_T = target_rel * energy_norm */
  PetscReal order;       /* eta_K ~ h^order where the solution is smooth: p + d/2 = 2 for Q4 */
  PetscReal order_sing;  /* the same for the cells marked singular (corner: 0.5) */
  PetscReal sing_share;  /* cells with eta_K^2 >= sing_share x mean eta_K^2 are singular */
  PetscReal min_factor;  /* h_new/h_old is clamped to [min_factor, max_factor] */
  PetscReal max_factor;
  PetscReal max_cells;   /* > 0: the expected cells are capped here, the target relaxed to fit */
} M2dSizeFieldParams;

/* order 2, order_sing 0.5, sing_share 10, factors [1/8, 2], target_rel 0.05, no cap */
void M2dSizeFieldDefaults(M2dSizeFieldParams *p);

/* New target size per local cell from the current sizes h[] and indicators
 * eta[] (n local cells), by equidistributing eta_T^2 over the expected number
 * of cells N (rule in estimator.c, above the function): hnew[] (caller
 * allocates), *nexpect = N. Collective on comm. */
PetscErrorCode M2dSizeField(MPI_Comm comm, PetscInt n, const PetscReal h[], const PetscReal eta[], const M2dErrorEstimate *e, const M2dSizeFieldParams *p, PetscReal hnew[], PetscReal *nexpect);
#endif
