/* contact_report.h - what the report reads off the interface after ContactResults
 * (contact.h): the CSV, the pressure's ripple and error, Hertz, Cattaneo-Mindlin, figures. */
#ifndef M2D_CONTACT_REPORT_H
#define M2D_CONTACT_REPORT_H
#include "contact.h"

typedef struct {
  PetscReal a, p0;           /* Hertz half-width and peak pressure */
  PetscReal half_width;      /* computed: midway between the last active and first inactive node */
  PetscReal h_edge;          /* spacing of the non-mortar nodes there */
  PetscReal peak_pressure;   /* largest nodal contact pressure */
  PetscReal pressure_l2_rel; /* ||p_h - p||_L2(0, 1.5a) / ||p||_L2(0, 1.5a), p_h piecewise linear */
  PetscReal pressure_even_l2_rel; /* a whole model: the same of p_h's even part (p_h(x) + p_h(-x))/2 on [-1.5a, 1.5a], */
  PetscReal pressure_odd_rel;     /* and the norm of its odd part over p's (their squares sum to pressure_l2_rel's) */
} M2dHertzResult;
/* plane strain Hertz for a cylinder (radius R, load P per unit thickness) on a
 * half-space, centred at x = 0 and pressing in y; a half model (the pair on
 * one side of x = 0) is measured on [0, 1.5a], a whole one on [-1.5a, 1.5a].
 * Not collective. */
PetscErrorCode ContactHertz(const M2dContactPair *c, const M2dScene *s, M2dHertzResult *h);
typedef struct {
  PetscReal c;            /* the stick zone's half-width: midway between its outermost sticking nodes and their neighbours */
  PetscReal c_exact;      /* Cattaneo-Mindlin: a sqrt(1 - Q/(mu P)), Q the pair's tangential force */
  PetscReal shear_l2_rel; /* relative L2 error of the shear traction's even part against Cattaneo-Mindlin's q(x) on [-1.5a, 1.5a] */
  PetscReal shear_odd_rel; /* the odd part's norm over q's (zero for half-spaces: the finite bodies' own shear) */
} M2dCattaneoResult;
/* Cattaneo-Mindlin for pair c (a whole cylinder, -cattaneo) after Hertz h:
 * the stick zone and the shear traction q(x) = mu p0 (sqrt(1 - x^2/a^2) -
 * (c/a) sqrt(1 - x^2/c^2)) for |x| < c, mu p(x) for c <= |x| <= a. Not
 * collective. */
PetscErrorCode ContactCattaneo(const M2dContactPair *c, const M2dScene *s, const M2dHertzResult *h, M2dCattaneoResult *r);
/* What an engineer reads off a pair, in c's units (after
 * ContactToUserUnits: the user's), positions on the non-mortar surface as
 * meshed: the active nodes along the surface (its edges' direction, body on
 * the left; chains in the order of their first nodes' (x, y), a closed loop
 * from an open node) form `zones`; from and to are the first and last active
 * nodes, length the zones' lengths summed (each zone's ends midway to the
 * next node, or at the surface's end), half_width one zone's half length,
 * or its whole length when one end is the surface's end on x = 0 of a half
 * model (the symmetry plane); -1 with no or several zones, or a zone cut by
 * the surface's end elsewhere; the largest pressure and its node
 * (ties within 1e-9 of it: the first along the surface). Not collective. */
typedef struct {
  PetscInt  zones;
  PetscReal from[2], to[2], length, half_width;
  PetscReal peak, peak_at[2];
} M2dPairFigures;
PetscErrorCode ContactPairFigures(const M2dContactPair *c, M2dPairFigures *f);
/* The interface as CSV, one row per contact node, pair by pair, sorted by x
 * in each: x, y, gap, pressure, weight, active, pair (1, 2, ...), with
 * friction traction_t, slip, slip_increment, status, then run_id; a load
 * history (nstep > 1) has a first column step and every step's rows, from
 * steps[k] (M2D_STEP_NODE_FIELDS values per node, solver.h), else c's
 * results. Not collective (every rank has the rows). */
PetscErrorCode ContactWriteCSV(const M2dContact *c, PetscInt nstep, const PetscReal *const steps[], const char *run_id, FILE *fp);
/* Pressure ripple after ContactResults: the largest deviation of an interior
 * active node's pressure from the linear interpolation (along the surface) of
 * its two neighbours' pressures, over the peak pressure; interior: three active
 * nodes on each side along the non-mortar surface (the zone's own edge, where
 * p ~ sqrt(a - x), is left out). *ninterior: how many nodes were measured
 * (0: *ripple = 0). Not collective (every rank has the results). */
PetscErrorCode ContactRipple(const M2dContact *c, PetscReal *ripple, PetscInt *ninterior);
/* The relative L2 error of the contact pressure along the non-mortar surface,
 * estimated after ContactResults: where the pressure is smooth, the
 * interpolation error of the parabola through each active node and its two
 * neighbours (h^2 |p''| / 8); at each end of a contact zone, where p falls
 * as sqrt(distance) to zero (non-conforming contact), the difference between
 * the piecewise linear pressure and the square root fitted through the last
 * three active nodes (p^2 linear in the arc length). Over the norm of the
 * pressure. Effectivity against the scene's own fine solution on Hertz
 * meshes 1.0-1.2 (docs/). Not collective. */
PetscErrorCode ContactPressureEstimate(const M2dContact *c, PetscReal *est);
#endif
