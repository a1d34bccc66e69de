/* contact.h - the contact pairs of a scene: surfaces, mortar segments or NTS
 * rows per pair, and the interface results (pressure, gap, force) after the solve. */
#ifndef M2D_CONTACT_H
#define M2D_CONTACT_H
#include "kkt.h"
#include "mesh.h"
#include "units.h"
#include "scene.h"

/* One pair: its two surfaces, segments and rows (R.node: nm's nodes; the
 * columns are global dofs, the same as in the interface's rows). */
typedef struct {
  M2dSurface       nm, m;
  M2dSegmentSet    seg;
  M2dContactRows   R;
  PetscInt         off; /* its first row in the interface's rows */
  PetscReal        reach;
  M2dContactMethod method;
  M2dMortarBasis   basis;
  const M2dPair   *def; /* the scene's entry (names, messages) */
  /* results: the interface's arrays from row off */
  PetscReal *pressure, *gap, *active;
  PetscReal  force[2]; /* total contact force on the non-mortar body */
  PetscReal  force_n;  /* integral of the contact pressure */
} M2dContactPair;

/* The interface: every pair, and their rows one pair after another (pair k's
 * from pair[k].off). Shared-node rule: a node on two non-mortar surfaces
 * (a corner of a body in two pairs) has one multiplier in each pair, with
 * that pair's normal and gap; the pairs' rows are never merged. */
typedef struct {
  PetscInt        npair;
  M2dContactPair *pair;
  M2dContactRows  R;       /* all rows; R.node is the node of its own pair's non-mortar surface */
  PetscInt       *rowpair; /* the pair of each row */
  /* results, on every rank, one per multiplier */
  PetscReal *pressure, *gap, *active;
} M2dContact;

/* Every pair of s (s->pair) in reference units; L: the length unit (reach
 * reported in the user's units). Errors name the pair's options: a missing
 * group, a group on two bodies, a pair whose sides lie on one body.
 * Collective (the surfaces are gathered on every rank). */
PetscErrorCode ContactSetup(const M2dMesh *m, const M2dScene *s, PetscReal L, M2dContact *c);
/* active: final active set (layout of lam), NULL when every node is held closed */
PetscErrorCode ContactResults(M2dContact *c, const M2dKKT *kkt, Vec u, Vec lam, Vec active);
typedef struct {
  PetscReal a, p0;           /* Hertz half-width and peak pressure */
  PetscReal half_width;      /* computed: midway between the last active and first inactive node */
  PetscReal h_edge;          /* spacing of the non-mortar nodes there */
  PetscReal peak_pressure;   /* largest nodal contact pressure */
  PetscReal pressure_l2_rel; /* ||p_h - p||_L2(0, 1.5a) / ||p||_L2(0, 1.5a), p_h piecewise linear */
} M2dHertzResult;
/* plane strain Hertz for a cylinder (radius R, load P per unit thickness) on a
 * half-space; the symmetry axis is x = 0 and contact is in the y direction */
PetscErrorCode ContactHertz(const M2dContactPair *c, const M2dScene *s, M2dHertzResult *h);
/* Point fields in the displacement layout (after ContactResults; every rank
 * calls, rank 0 sets): field component 0 the contact pressure, 1 the gap, on
 * the non-mortar nodes with a multiplier and, interpolated from those nodes
 * at each node's nearest point, on the mortar surface (so either body shows
 * them); elsewhere pressure 0 and gap NaN. active component 0: 1 or 0 on the
 * non-mortar surface (0 where it has no multiplier), NaN elsewhere. Collective. */
PetscErrorCode ContactFillField(const M2dContact *c, Vec field, Vec active);
/* The interface as CSV, one row per multiplier, pair by pair, sorted by x in
 * each: x, y, gap, pressure, weight, active, pair (1, 2, ...), run_id. Not collective (every rank has the rows). */
PetscErrorCode ContactWriteCSV(const M2dContact *c, const char *run_id, FILE *fp);
/* The contact state of a solved problem, kept to start the next one (an
 * adapted mesh of the same scene): the non-mortar nodes that carried a
 * multiplier, their positions (user units) and whether they were active. */
typedef struct {
  PetscInt   n;
  PetscInt   npair, *off; /* pair k's nodes from off[k] to off[k + 1] */
  PetscReal *xy;       /* 2 per node */
  PetscBool *active;
  PetscReal *pressure; /* user units */
  PetscReal *gap;
} M2dContactState;

/* Keep c's state (after ContactToUserUnits: positions in user units). Not
 * collective; free with ContactStateDestroy. */
PetscErrorCode ContactStateCreate(const M2dContact *c, M2dContactState *st);
PetscErrorCode ContactStateDestroy(M2dContactState *st);
/* The first active set of c from a previous state, by the active-set test
 * itself, phi = lambda - cw g > 0 (cw: c times the new node's weight, reference
 * units), with phi of the previous nodes interpolated between the two nearest
 * (positions compared in user units: c's surfaces are in reference units,
 * unscaled by u->L). mask: one per multiplier, every rank. Not collective. */
PetscErrorCode ContactStateMask(const M2dContactState *st, const M2dContact *c, const M2dUnits *u, PetscReal cparam, PetscBool mask[]);
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
/* Turn the interface results and the surfaces' coordinates and weights from
 * reference units into the user's (for the files). Not collective. */
PetscErrorCode ContactToUserUnits(M2dContact *c, const M2dUnits *u);
PetscErrorCode ContactDestroy(M2dContact *c);
/* one pair's surfaces, segments and rows (not its results: the interface's) */
PetscErrorCode ContactPairDestroy(M2dContactPair *p);
#endif
