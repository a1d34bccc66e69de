/* contact.h - the contact pairs of a scene: surfaces, mortar segments or NTS
 * rows per pair, the interface results after the solve (contact_report.h: the report's). */
#ifndef M2D_CONTACT_H
#define M2D_CONTACT_H
#include "mortar.h"
#include "mesh.h"
#include "units.h"
#include "scene.h"

/* One pair: its two surfaces, segments and rows (R.node: nm's nodes; the
 * columns are global dofs, the same as in the interface's rows). */
typedef struct {
  M2dSurface       nm, m;
  M2dSegmentSet    seg;
  M2dContactRows   R;   /* normal rows: the weighted gaps */
  M2dContactRows   T;   /* with friction (mu > 0): tangential rows, node for node as R (T.n = 0 without) */
  PetscInt         off; /* its first normal row in the interface's rows */
  PetscInt         toff; /* its first tangential row there */
  PetscReal        reach;
  PetscReal        mu;  /* Coulomb friction coefficient */
  M2dContactMethod method;
  M2dMortarBasis   basis;
  const M2dPair   *def; /* the scene's entry (names, messages) */
  /* results: the interface's arrays from node off */
  PetscReal *pressure, *gap, *active;
  PetscReal *traction, *slip, *slip_inc, *status;
  PetscReal  force[2]; /* total contact force on the non-mortar body */
  PetscReal  force_n;  /* integral of the contact pressure */
  PetscReal  force_t;  /* integral of the tangential traction (along each node's tangent t = (-n_y, n_x)) */
  PetscInt   nstick, nslip; /* nodes in contact that stick, that slip (frictionless: every closed node slips) */
} M2dContactPair;

/* contact_status of a node (the point field and the CSV) */
#define M2D_STATUS_OPEN  0
#define M2D_STATUS_STICK 1
#define M2D_STATUS_SLIP  2

/* a node's position and index, for sorting (contact.c, contact_report.c) */
typedef struct {
  PetscReal x, y;
  PetscInt  j;
} M2dXYIdx;

/* The interface: every pair, and their rows: the normal rows one pair after
 * another (pair k's from pair[k].off), then the tangential rows of the pairs
 * with friction (pair k's from pair[k].toff), each row's normal row in
 * partner. Shared-node rule: a node on two non-mortar surfaces (a corner of a
 * body in two pairs) has one multiplier in each pair, with that pair's normal
 * and gap; the pairs' rows are never merged. */
typedef struct {
  PetscInt        npair;
  M2dContactPair *pair;
  M2dContactRows  R;       /* all rows; R.node is the node of its own pair's non-mortar surface */
  PetscInt        nnormal; /* the normal rows, R's first: one per contact node */
  PetscInt       *rowpair; /* the pair of each row */
  PetscInt       *partner; /* a tangential row's normal row, -1 for a normal row */
  /* results, on every rank, one per contact node (normal row) */
  PetscReal *pressure, *gap, *active;
  PetscReal *traction; /* tangential multiplier: the friction force per length on the non-mortar body along t (0 without friction) */
  PetscReal *slip;     /* accumulated slip along t of the non-mortar node relative to the mortar surface (length) */
  PetscReal *slip_inc; /* the last load step's */
  PetscReal *status;   /* M2D_STATUS_* */
} M2dContact;

/* Every pair of s (s->pair) in reference units; L: the length unit (reach
 * reported in the user's units). Errors name the pair's options: a missing
 * group, a group on two bodies, a pair whose sides lie on one body.
 * Collective (the surfaces are gathered on every rank). */
PetscErrorCode ContactSetup(const M2dMesh *m, const M2dScene *s, PetscReal L, M2dContact *c);
/* From the solve of one load step (reference units): the rows C (kkt.h) and
 * their right-hand side r of that step, its u, lam and active (1: a closed
 * normal row or a sticking tangential row, layout of r; NULL when every node
 * is held closed), and slip (the accumulated weighted slip of the tangential
 * rows, layout of r; NULL without friction). Collective. */
PetscErrorCode ContactResults(M2dContact *c, Mat C, Vec r, Vec u, Vec lam, Vec active, Vec slip);
/* Point each pair's results (pressure, ..., status) at its nodes in c's
 * arrays (after c's arrays were set or replaced). Not collective. */
void           ContactPairViews(M2dContact *c);
/* Whether either surface of c is curved: its normal turns at some node by
 * more than 1e-6 rad, less than 45 degrees (-hertz's choice of pairs). Not
 * collective. */
PetscBool ContactPairCurved(const M2dContactPair *c);
/* Point fields in the displacement layout (after ContactResults; every rank
 * calls, rank 0 sets): field component 0 the contact pressure, 1 the gap, on
 * the non-mortar nodes with a multiplier and, interpolated from those nodes
 * at each node's nearest point, on the mortar surface (so either body shows
 * them); elsewhere pressure 0 and gap NaN. active component 0: 1 or 0 on the
 * non-mortar surface (0 where it has no multiplier), NaN elsewhere. Collective. */
PetscErrorCode ContactFillField(const M2dContact *c, Vec field, Vec active);
/* The same for friction (user or reference units as c's results):
 * traction_slip gets the tangential traction (0 off the interface) and the
 * accumulated slip (NaN off it), increment_status the last load step's slip
 * and the contact status (M2D_STATUS_*; NaN off the interface; the mortar
 * side shows its nearest non-mortar node's). Collective. */
PetscErrorCode ContactFillFriction(const M2dContact *c, Vec traction_slip, Vec increment_status);
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
/* Turn the interface results and the surfaces' coordinates and weights from
 * reference units into the user's (for the files). Not collective. */
PetscErrorCode ContactToUserUnits(M2dContact *c, const M2dUnits *u);
PetscErrorCode ContactDestroy(M2dContact *c);
/* one pair's surfaces, segments and rows (not its results: the interface's) */
PetscErrorCode ContactPairDestroy(M2dContactPair *p);
#endif
