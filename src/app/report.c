/* report.c - results, comparisons with exact answers, files (see report.h). */
#include "report.h"
#include "about.h"
#include "contact_report.h"
#include "optcheck.h"
#include "dual.h"
#include "elasticity.h"
#include "method.h"
#include "logging.h"
#include "options.h"
#include "util.h"
#include <string.h>
#include <sys/resource.h>

/* stress, per local cell: sigma_x, sigma_y, sigma_z, sigma_xy, von Mises, body (user units) */
#define M2D_CELL_FIELDS 6
/* the log's lines per pair and per body: the first this many (the summary has every one) */
#define M2D_LINES_MAX 16

static PetscErrorCode SummarizeProblem(const M2dProblem *pb, const M2dSolution *sol, const M2dVerification *v, M2dSummary *sum)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)pb->mesh.dm), &size));
  SummaryString(sum, "", "program", "mortar2d");
  M2dSummaryVersions(sum); /* version, git_commit, petsc_version (about.h) */
  SummaryString(sum, "", "run_id", pb->user->out.run_id);
  SummaryString(sum, "", "status", "ok"); /* written only by a run that got this far (else OutputWriteFailure's) */
  SummaryInt(sum, "", "dofs", 2 * pb->mesh.nvert_global);
  SummaryInt(sum, "", "cells", pb->mesh.ncell_global);
  SummaryInt(sum, "", "ranks", size);
  SummaryInt(sum, "", "bodies", pb->s.nbody);
  SummaryString(sum, "", "plane", pb->s.plane == M2D_PLANE_STRAIN ? "strain" : "stress");
  SummaryString(sum, "", "q4_integration", pb->s.sri ? "sri" : "full"); /* sri by default past M2D_LOCKING_NU in plane strain */
  SummaryString(sum, "", "kkt_path", M2dSolverPathName(sol->path));
  if (sol->path == M2D_PATH_CONDENSED) SummaryString(sum, "", "kkt_ordering", pb->s.kkt_ordering == M2D_ORDERING_METIS ? "metis" : "mumps"); /* auto resolved (ProblemCreate) */
  /* the iteration counts of this path: one linear solve, or the active set's steps (SummarizeContact) and their solves */
  if (sol->path == M2D_PATH_LINEAR || sol->path == M2D_PATH_TIED) SummaryInt(sum, "", "ksp_iterations", sol->ksp_its);
  SummaryInt(sum, "", "ksp_iterations_max", sol->ksp_its_max);
  if (sol->path == M2D_PATH_ITERATIVE) {
    SummaryInt(sum, "", "ksp_iterations_total", sol->as.ksp_its_total);
    SummaryInt(sum, "", "pc_setups", sol->as.pc_setups);
  }
  SummaryReal(sum, "", "residual_rel", v->residual_rel);
  SummaryReal(sum, "", "complementarity", v->complementarity);
  SummaryReal(sum, "", "strain_max", v->strain_max);
  SummaryReal(sum, "", "rotation_max", v->rotation_max);
  SummaryReal(sum, "", "residual_tol", M2D_VERIFY_TOL);
  SummaryReal(sum, "", "backward_error", v->backward_error);
  if (sol->factored) SummaryReal(sum, "", "backward_error_tol", M2D_VERIFY_BACKWARD_TOL); /* a Krylov answer is held to residual_tol alone */
  SummaryReal(sum, "", "complementarity_tol", M2D_VERIFY_TOL);
  if (sol->slip) {
    SummaryReal(sum, "", "coulomb", v->coulomb);
    SummaryReal(sum, "", "coulomb_tol", M2D_VERIFY_TOL);
  }
  /* every figure is in the units of the input (the internal scaling, units.h, never shows) */
  SummaryString(sum, "units", "length", "the mesh's coordinates x -mesh_scale");
  SummaryString(sum, "units", "stress", "the moduli's and the loads'");
  SummaryString(sum, "units", "force", "stress x length (per unit thickness)");
  PetscFunctionReturn(0);
}

/* pair k's comparison with Hertz (and Cattaneo-Mindlin), computed in the
 * reference units before the interface goes to the user's */
typedef struct {
  M2dHertzResult    h;
  M2dCattaneoResult cm;
} PairExact;

static PetscErrorCode PairExactCompute(M2dProblem *pb, PetscInt k, PairExact *e)
{
  PetscFunctionBeginUser;
  PetscCall(ContactHertz(&pb->contact.pair[k], &pb->s, &e->h));
  if (pb->s.cattaneo && pb->contact.pair[k].mu > 0) PetscCall(ContactCattaneo(&pb->contact.pair[k], &pb->s, &e->h, &e->cm));
  PetscFunctionReturn(0);
}

/* pair k's Hertz comparison: in "pairs", and the first compared pair's at
 * the top level (first); fig->pressure_l2_rel the largest of them */
static PetscErrorCode SummarizeHertz(M2dProblem *pb, PetscInt k, PetscBool first, const PairExact *e, M2dFigures *fig, M2dSummary *sum)
{
  const M2dHertzResult *h  = &e->h;
  const M2dUnits       *un = &pb->units;
  const char           *pk = pb->s.npair > 1 ? " " : "", *pn = pb->s.npair > 1 ? pb->s.pair[k].nm : "";
  const char           *keys[11] = {"pressure_l2_rel", "half_width", "hertz_a", "hertz_p0", "hertz_radius", "stick_half_width", "stick_half_width_exact", "shear_l2_rel", "shear_odd_rel", "pressure_even_l2_rel", "pressure_odd_rel"};
  PetscReal             vals[11] = {h->pressure_l2_rel, h->half_width * un->L, h->a * un->L, h->p0 * un->S, pb->user->pair[k].hertz_radius, e->cm.c * un->L, e->cm.c_exact * un->L, e->cm.shear_l2_rel, e->cm.shear_odd_rel, h->pressure_even_l2_rel, h->pressure_odd_rel};
  PetscBool             cm = (PetscBool)(pb->s.cattaneo && pb->contact.pair[k].mu > 0);

  PetscFunctionBeginUser;
  fig->pressure_l2_rel = PetscMax(fig->pressure_l2_rel, h->pressure_l2_rel);
  fig->hertz_pairs++;
  for (int q = 0; q < (cm ? 11 : 5); q++) PetscCall(M2dSummaryListReal(sum, "pairs", k, keys[q], vals[q]));
  if (first) {
    SummaryReal(sum, "", "pressure_l2_rel", h->pressure_l2_rel);
    SummaryReal(sum, "", "peak_pressure", h->peak_pressure * un->S);
    SummaryReal(sum, "", "half_width", h->half_width * un->L);
    SummaryReal(sum, "", "half_width_spacing", h->h_edge * un->L);
    SummaryReal(sum, "", "hertz_a", h->a * un->L);
    SummaryReal(sum, "", "hertz_p0", h->p0 * un->S);
    SummaryReal(sum, "", "hertz_radius", pb->user->pair[k].hertz_radius);
    for (int q = 5; cm && q < 11; q++) SummaryReal(sum, "", keys[q], vals[q]);
  }
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "Hertz%s%s: a = %.6g (computed %.6g, node spacing %.3g), p0 = %.6g (computed peak %.6g), L2 error of the pressure on [0, 1.5a]: %.4e\n", pk, pn, (double)(h->a * un->L), (double)(h->half_width * un->L), (double)(h->h_edge * un->L), (double)(h->p0 * un->S), (double)(h->peak_pressure * un->S), (double)h->pressure_l2_rel));
  if (cm) PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "Cattaneo-Mindlin%s%s: stick zone c = %.6g (computed %.6g), L2 error of the shear traction on [-1.5a, 1.5a]: %.4e (its even part; the odd part %.4e of it), of the pressure's even part %.4e (the odd part %.4e of Hertz's)\n", pk, pn, (double)vals[6], (double)vals[5], (double)vals[7], (double)vals[8], (double)vals[9], (double)vals[10]));
  PetscFunctionReturn(0);
}

/* friction: each pair's coefficient, tangential force and stick and slip
 * counts (user units), the first pair's force and every pair's counts at the
 * top level */
static PetscErrorCode SummarizeFriction(const M2dProblem *pb, M2dSummary *sum)
{
  const M2dContact *c = &pb->contact;
  PetscInt          nst = 0, nsl = 0;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < c->npair; k++) {
    const M2dContactPair *p = &c->pair[k];
    nst += p->nstick, nsl += p->nslip;
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "mu", p->mu));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "tangential_force", p->force_t));
    PetscCall(M2dSummaryListInt(sum, "pairs", k, "stick_nodes", p->nstick));
    PetscCall(M2dSummaryListInt(sum, "pairs", k, "slip_nodes", p->nslip));
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "friction%s%s: MU = %g, %" PetscInt_FMT " nodes stick, %" PetscInt_FMT " slip; tangential force %.12e, MU x normal force %.12e\n", c->npair > 1 ? " " : "", c->npair > 1 ? p->def->nm : "", (double)p->mu, p->nstick, p->nslip, (double)p->force_t, (double)(p->mu * p->force_n)));
  }
  SummaryReal(sum, "", "mu", c->pair[0].mu);
  SummaryReal(sum, "", "tangential_force", c->pair[0].force_t);
  SummaryInt(sum, "", "stick_nodes", nst);
  SummaryInt(sum, "", "slip_nodes", nsl);
  PetscFunctionReturn(0);
}

/* a load history: each step's load, active-set steps, and per pair the
 * normal and tangential forces and the nodes that stick, slip, are open
 * (user units); leaves the interface results of the last step in pb->contact */
static PetscErrorCode SummarizeSteps(M2dProblem *pb, const M2dSolution *sol, M2dSummary *sum)
{
  M2dContact *c  = &pb->contact;
  PetscInt    np = c->npair;
  PetscReal  *v, F = pb->units.S * pb->units.L;
  MPI_Comm    comm = PetscObjectComm((PetscObject)pb->mesh.dm);

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(np + 1, &v));
  PetscCall(PetscPrintf(comm, "load steps: step, stage, time, active-set steps, then per pair: normal force, tangential force, stick, slip, open nodes\n"));
  for (PetscInt k = 0; k < sol->nstep; k++) {
    M2dLoadStep *ls = &sol->steps[k];
    PetscCall(ContactResults(c, pb->kkt.C, ls->r, ls->u, ls->lam, ls->active, ls->slip));
    PetscCall(PetscFree(ls->nodes));
    PetscCall(PetscMalloc1(M2D_STEP_NODE_FIELDS * c->nnormal + 1, &ls->nodes));
    for (PetscInt j = 0; j < c->nnormal; j++) { /* for the fields' series (ReportWriteFields), in the user's units */
      PetscReal *o = &ls->nodes[M2D_STEP_NODE_FIELDS * j];
      o[0] = c->pressure[j] * pb->units.S, o[1] = c->gap[j] * pb->units.U, o[2] = c->active[j];
      o[3] = c->traction[j] * pb->units.S, o[4] = c->slip[j] * pb->units.U, o[5] = c->slip_inc[j] * pb->units.U, o[6] = c->status[j];
    }
    PetscCall(M2dSummaryListInt(sum, "load_steps", k, "step", k + 1));
    PetscCall(M2dSummaryListInt(sum, "load_steps", k, "stage", ls->stage + 1));
    PetscCall(M2dSummaryListReal(sum, "load_steps", k, "time", ls->time));
    PetscCall(M2dSummaryListInt(sum, "load_steps", k, "iterations", ls->iterations));
    PetscCall(PetscPrintf(comm, "  %3" PetscInt_FMT " %2" PetscInt_FMT " %8.4f %3" PetscInt_FMT, k + 1, ls->stage + 1, (double)ls->time, ls->iterations));
    for (PetscInt q = 0; q < np; q++) {
      const M2dContactPair *p = &c->pair[q];
      PetscCall(PetscPrintf(comm, "  | %.6e %.6e %" PetscInt_FMT " %" PetscInt_FMT " %" PetscInt_FMT, (double)(p->force_n * F), (double)(p->force_t * F), p->nstick, p->nslip, p->R.n - p->nstick - p->nslip));
    }
    PetscCall(PetscPrintf(comm, "\n"));
    for (PetscInt q = 0; q < np; q++) v[q] = c->pair[q].force_n * F;
    PetscCall(M2dSummaryListArray(sum, "load_steps", k, "normal_force", np, v));
    for (PetscInt q = 0; q < np; q++) v[q] = c->pair[q].force_t * F;
    PetscCall(M2dSummaryListArray(sum, "load_steps", k, "tangential_force", np, v));
    for (PetscInt q = 0; q < np; q++) v[q] = (PetscReal)c->pair[q].nstick;
    PetscCall(M2dSummaryListArray(sum, "load_steps", k, "stick_nodes", np, v));
    for (PetscInt q = 0; q < np; q++) v[q] = (PetscReal)c->pair[q].nslip;
    PetscCall(M2dSummaryListArray(sum, "load_steps", k, "slip_nodes", np, v));
    for (PetscInt q = 0; q < np; q++) v[q] = (PetscReal)(c->pair[q].R.n - c->pair[q].nstick - c->pair[q].nslip);
    PetscCall(M2dSummaryListArray(sum, "load_steps", k, "open_nodes", np, v));
  }
  PetscCall(PetscFree(v));
  PetscFunctionReturn(0);
}

/* every pair in the list "pairs" (user units), and a line each: where it
 * touches, its peak pressure, its forces; then the comparisons with exact
 * answers and friction's figures */
static PetscErrorCode SummarizePairs(M2dProblem *pb, const PairExact *ex, const M2dSolution *sol, M2dFigures *fig, M2dSummary *sum)
{
  const M2dContact *c = &pb->contact;
  MPI_Comm          comm = PetscObjectComm((PetscObject)pb->mesh.dm);

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < c->npair; k++) {
    const M2dContactPair *p  = &c->pair[k];
    PetscInt              na = 0;
    M2dPairFigures        f;
    char                  where[256] = "";
    for (PetscInt j = 0; j < p->R.n; j++) na += p->active[j] != 0;
    PetscCall(ContactPairFigures(p, &f));
    PetscCall(M2dSummaryListString(sum, "pairs", k, "nonmortar", p->def->nm));
    PetscCall(M2dSummaryListString(sum, "pairs", k, "mortar", p->def->m));
    PetscCall(M2dSummaryListString(sum, "pairs", k, "method", M2dMethodOf(p->method, p->basis)->name));
    PetscCall(M2dSummaryListInt(sum, "pairs", k, "contact_nodes", p->R.n));
    PetscCall(M2dSummaryListInt(sum, "pairs", k, "active_nodes", na));
    PetscCall(M2dSummaryListInt(sum, "pairs", k, "contact_zones", f.zones));
    if (f.zones) {
      PetscCall(M2dSummaryListArray(sum, "pairs", k, "contact_extent_from", 2, f.from));
      PetscCall(M2dSummaryListArray(sum, "pairs", k, "contact_extent_to", 2, f.to));
      PetscCall(M2dSummaryListReal(sum, "pairs", k, "contact_length", f.length));
      if (f.half_width >= 0) PetscCall(M2dSummaryListReal(sum, "pairs", k, "contact_half_width", f.half_width));
      PetscCall(M2dSummaryListReal(sum, "pairs", k, "peak_pressure", f.peak));
      PetscCall(M2dSummaryListArray(sum, "pairs", k, "peak_pressure_at", 2, f.peak_at));
      char hw[64] = "";
      if (f.half_width >= 0) PetscCall(PetscSNPrintf(hw, sizeof(hw), ", half-width %.6g", (double)f.half_width));
      PetscCall(PetscSNPrintf(where, sizeof(where), " in %" PetscInt_FMT " zone%s from (%.6g, %.6g) to (%.6g, %.6g), length %.6g%s%s, peak pressure %.6g at (%.6g, %.6g)", f.zones, f.zones > 1 ? "s" : "", (double)f.from[0], (double)f.from[1], (double)f.to[0], (double)f.to[1], (double)f.length, f.zones > 1 ? " (summed)" : "", hw, (double)f.peak, (double)f.peak_at[0], (double)f.peak_at[1]));
    }
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "contact_force", p->force_n));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "contact_force_x", p->force[0]));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "contact_force_y", p->force[1]));
    if (k < M2D_LINES_MAX) PetscCall(PetscPrintf(comm, "pair %d '%s:%s': %" PetscInt_FMT " of %" PetscInt_FMT " nodes active%s; integral of pressure %.12e, force on the non-mortar body (%.12e, %.12e)\n", (int)k + 1, p->def->nm, p->def->m, na, p->R.n, where, (double)p->force_n, (double)p->force[0], (double)p->force[1]));
  }
  if (c->npair > M2D_LINES_MAX) PetscCall(PetscPrintf(comm, "(%" PetscInt_FMT " more pairs: every pair's figures are in the summary's pairs)\n", c->npair - M2D_LINES_MAX));
  for (PetscInt k = 0, n = 0; k < c->npair && pb->s.hertz; k++)
    if (pb->s.pair[k].hertz) PetscCall(SummarizeHertz(pb, k, (PetscBool)(n++ == 0), &ex[k], fig, sum));
  if (sol->slip) PetscCall(SummarizeFriction(pb, sum));
  PetscFunctionReturn(0);
}

/* the interface results (ContactResults already called, reference units);
 * the top-level figures are the first pair's (every pair's in "pairs"),
 * contact_nodes and active_nodes count every pair */
static PetscErrorCode SummarizeContact(M2dProblem *pb, const M2dSolution *sol, M2dFigures *fig, M2dSummary *sum)
{
  M2dContact     *c = &pb->contact;
  M2dContactPair *c0 = &c->pair[0];
  PetscReal       na;
  PairExact      *ex;

  PetscFunctionBeginUser;
  if (sol->nstep > 1) PetscCall(SummarizeSteps(pb, sol, sum));
  PetscCall(PetscCalloc1(c->npair, &ex));
  for (PetscInt k = 0; k < c->npair && pb->s.hertz; k++)
    if (pb->s.pair[k].hertz) PetscCall(PairExactCompute(pb, k, &ex[k]));
  PetscCall(ContactToUserUnits(c, &pb->units));
  SummaryString(sum, "", "method", M2dMethodOf(c0->method, c0->basis)->family);
  SummaryInt(sum, "", "contact_nodes", c->nnormal);
  SummaryReal(sum, "", "contact_force", c0->force_n);
  SummaryReal(sum, "", "contact_force_x", c0->force[0]);
  SummaryReal(sum, "", "contact_force_y", c0->force[1]);
  if (c0->nm.body >= 0 && c0->m.body >= 0) {
    char signs[3 * M2D_NAME_LEN + 256];
    PetscCall(PetscSNPrintf(signs, sizeof(signs), "contact_force: the integral of the contact pressure, positive in compression; contact_force_x, contact_force_y: the force of the mortar body '%s' on the non-mortar body '%s'%s", pb->s.body[c0->m.body].name, pb->s.body[c0->nm.body].name, c->npair > 1 ? " (the first pair; every pair's in pairs)" : ""));
    SummaryString(sum, "", "contact_force_signs", signs);
  }
  PetscCall(SummarizePairs(pb, ex, sol, fig, sum));
  PetscCall(PetscFree(ex));
  SummaryString(sum, "", "contact_solver", sol->path == M2D_PATH_TIED ? "tied" : sol->as.vi ? "vinewtonrsls" : "pdas");
  if (sol->path != M2D_PATH_TIED) SummaryInt(sum, "", "iterations", sol->as.iterations);
  na = 0;
  for (PetscInt j = 0; j < c->nnormal; j++) na += c->active[j] != 0;
  fig->active_nodes = (PetscInt)(na + 0.5);
  SummaryInt(sum, "", "active_nodes", fig->active_nodes);
  PetscCall(ContactRipple(c, &fig->pressure_ripple, &fig->ripple_nodes));
  SummaryReal(sum, "", "pressure_ripple", fig->pressure_ripple);
  SummaryReal(sum, "", "pressure_estimate", fig->pressure_estimate);
  if (sol->path != M2D_PATH_TIED) SummaryReal(sum, "", "contact_c", sol->as.c * (pb->units.S / pb->units.L) / pb->units.U);
  if (sol->path == M2D_PATH_CONDENSED) {
    SummaryReal(sum, "", "factor_flops", sol->as.factor_flops);
    SummaryReal(sum, "", "factor_flops_max_rank", sol->as.factor_flops_max);
    SummaryInt(sum, "", "interface_unknowns", sol->as.interface_unknowns);
  }
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "contact pressure: %" PetscInt_FMT " active nodes, estimated error %.3e (relative L2), ripple %.2f%% of the peak over %" PetscInt_FMT " interior ones\n", (PetscInt)(na + 0.5), (double)fig->pressure_estimate, (double)(100 * fig->pressure_ripple), fig->ripple_nodes));
  PetscFunctionReturn(0);
}

/* -exact uniform: max over cells of the stress error / p (reference units:
 * relative), in the frame x' = R(-exact_angle) x where sigma_y'y' = -p and
 * sigma_x'y' = tau (-exact_tau) */
static PetscErrorCode SummarizeUniform(const M2dProblem *pb, const PetscReal *stress, M2dSummary *sum)
{
  PetscReal p = pb->s.exact_p, tau = pb->s.exact_tau, e[3] = {0, 0, 0}, th = pb->s.exact_angle * PETSC_PI / 180, c = PetscCosReal(th), sn = PetscSinReal(th);
  PetscInt  nlc = pb->mesh.cEnd - pb->mesh.cStart;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < nlc; k++) {
    const PetscReal *sg = &stress[M2D_CELL_FIELDS * k], sx = sg[0], sy = sg[1], sxy = sg[3];
    PetscReal        rx = c * c * sx + sn * sn * sy + 2 * sn * c * sxy, ry = sn * sn * sx + c * c * sy - 2 * sn * c * sxy, rxy = sn * c * (sy - sx) + (c * c - sn * sn) * sxy;
    e[0] = PetscMax(e[0], PetscAbsReal(ry + p) / PetscAbsReal(p));
    e[1] = PetscMax(e[1], PetscAbsReal(rx) / PetscAbsReal(p));
    e[2] = PetscMax(e[2], PetscAbsReal(rxy - tau) / PetscAbsReal(p));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, e, 3, MPIU_REAL, MPIU_MAX, PetscObjectComm((PetscObject)pb->mesh.dm)));
  SummaryReal(sum, "error", "sigma_yy_max_rel", e[0]);
  SummaryReal(sum, "error", "sigma_xx_max_rel", e[1]);
  SummaryReal(sum, "error", "sigma_xy_max_rel", e[2]);
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "uniform stress check: max |sigma_yy + p|/p = %.3e, max |sigma_xx|/p = %.3e, max |sigma_xy - tau|/p = %.3e\n", (double)e[0], (double)e[1], (double)e[2]));
  PetscFunctionReturn(0);
}

static PetscErrorCode SummarizeMMS(const M2dProblem *pb, Vec u, M2dSummary *sum)
{
  PetscReal err, nrm, h, area = pb->units.U * pb->units.L; /* L2 norm over the area: U x L */

  PetscFunctionBeginUser;
  PetscCall(ElasticityMMSError(&pb->mesh, &pb->s, u, &err, &nrm, &h));
  SummaryReal(sum, "error", "u_l2", err * area);
  SummaryReal(sum, "error", "u_l2_rel", err / nrm);
  SummaryReal(sum, "error", "h", h * pb->units.L);
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "manufactured solution: h = %.4e, L2 displacement error = %.6e (relative %.6e)\n", (double)(h * pb->units.L), (double)(err * area), (double)(err / nrm)));
  PetscFunctionReturn(0);
}

/* cell stresses (times `scale`) and the body index, M2D_CELL_FIELDS per local cell */
static PetscErrorCode CellFields(const M2dProblem *pb, Vec u, PetscReal scale, PetscReal **fields)
{
  PetscInt   nlc = pb->mesh.cEnd - pb->mesh.cStart;
  PetscReal *f;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(M2D_CELL_FIELDS * nlc + 1, &f));
  PetscCall(ElasticityCellStress(&pb->mesh, &pb->s, u, f)); /* 5 per cell, packed */
  for (PetscInt c = nlc - 1; c >= 0; c--) {
    for (int k = 4; k >= 0; k--) f[M2D_CELL_FIELDS * c + k] = f[5 * c + k] * scale;
    f[M2D_CELL_FIELDS * c + 5] = (PetscReal)pb->mesh.cellbody[c];
  }
  *fields = f;
  PetscFunctionReturn(0);
}

/* the recovered stresses per local vertex in the user's units: sigma_x,
 * sigma_y, sigma_z (plane strain: nu (sigma_x + sigma_y) of the vertex's body),
 * sigma_xy, von Mises; M2D_NODAL_FIELDS each */
#define M2D_NODAL_FIELDS 5
static PetscErrorCode NodalFields(const M2dProblem *pb, const PetscReal sv[], PetscReal **fields)
{
  const M2dMesh *m  = &pb->mesh;
  PetscInt       nv = m->vEnd - m->vStart;
  PetscReal     *f, S = pb->units.S;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(M2D_NODAL_FIELDS * nv + 1, &f));
  for (PetscInt c = 0; c < m->cEnd - m->cStart; c++) /* sigma_z's factor, by the body of a cell around the vertex */
    for (int k = 0; k < 4; k++) f[M2D_NODAL_FIELDS * (m->cellverts[4 * c + k] - m->vStart) + 2] = pb->s.plane == M2D_PLANE_STRAIN ? pb->s.body[m->cellbody[c]].nu : 0;
  for (PetscInt v = 0; v < nv; v++) {
    /* von Mises from the internal units, then scaled (its squares could overflow in the user's) */
    PetscReal *o = &f[M2D_NODAL_FIELDS * v], sx = sv[3 * v], sy = sv[3 * v + 1], sxy = sv[3 * v + 2], sz = o[2] * (sx + sy);
    o[0] = sx * S;
    o[1] = sy * S;
    o[2] = sz * S;
    o[3] = sxy * S;
    o[4] = PetscSqrtReal(0.5 * ((sx - sy) * (sx - sy) + (sy - sz) * (sy - sz) + (sz - sx) * (sz - sx)) + 3 * sxy * sxy) * S;
  }
  *fields = f;
  PetscFunctionReturn(0);
}

/* the largest value of each slot over the ranks, and where: ties within
 * 1e-9 of it go to the least (x, y), so that 1 and 2 ranks name the same
 * point. cand[3 i + {0, 1, 2}]: candidate i's value (>= 0), x, y, for slot
 * slot[i]; best[3 k + {0, 1, 2}] slot k's (value -1: no candidate).
 * Collective. */
static PetscErrorCode SlotMaxima(MPI_Comm comm, PetscInt n, PetscInt ncand, const PetscReal cand[], const PetscInt slot[], PetscReal best[])
{
  PetscReal *col;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(n + 1, &col));
  for (int c = 0; c < 3; c++) { /* the value, then x among the ties, then y among those at that x */
    for (PetscInt k = 0; k < n; k++) col[k] = c ? PETSC_MAX_REAL : -1;
    for (PetscInt i = 0; i < ncand; i++) {
      const PetscReal *q = &cand[3 * i], *bk = &best[3 * slot[i]];
      if (c == 0) col[slot[i]] = PetscMax(col[slot[i]], q[0]);
      else if (q[0] >= (1 - 1e-9) * bk[0] && (c == 1 || q[1] == bk[1])) col[slot[i]] = PetscMin(col[slot[i]], q[c]);
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, col, (PetscMPIInt)n, MPIU_REAL, c ? MPIU_MIN : MPIU_MAX, comm));
    for (PetscInt k = 0; k < n; k++) best[3 * k + c] = col[k];
  }
  PetscCall(PetscFree(col));
  PetscFunctionReturn(0);
}

/* per body ("body_results", user units, positions as meshed): the largest
 * von Mises stress of the cells (each cell's mean stress, at its centroid)
 * and of the recovered nodal stresses (with the error estimate), the largest
 * displacement, each with where; and a line each. Collective. */
static PetscErrorCode SummarizeBodies(const M2dProblem *pb, const M2dSolution *sol, M2dSummary *sum)
{
  const M2dMesh *m   = &pb->mesh;
  PetscInt       nb  = pb->s.nbody, nlc = m->cEnd - m->cStart, nv = m->vEnd - m->vStart, nc = 0, *slot, *vbody;
  PetscReal      L   = pb->units.L, *cells, *nodal = NULL, *cand, *best;
  M2dMeshArrays  ar;
  MPI_Comm       comm = PetscObjectComm((PetscObject)m->dm);
  const char    *kind[3] = {"von_mises_max", "von_mises_nodal_max", "displacement_max"};

  PetscFunctionBeginUser;
  PetscCall(CellFields(pb, sol->u, pb->units.S, &cells));
  if (sol->sv) PetscCall(NodalFields(pb, sol->sv, &nodal));
  PetscCall(PetscMalloc4(3 * (nlc + 2 * nv) + 1, &cand, nlc + 2 * nv + 1, &slot, nv + 1, &vbody, 9 * nb + 1, &best));
  PetscCall(MeshArraysOpen(m, sol->u, &ar));
  for (PetscInt c = 0; c < nlc; c++) {
    PetscReal xy[8];
    MeshCellCoordinates(m, ar.ca, ar.cs, c + m->cStart, xy);
    cand[3 * nc] = cells[M2D_CELL_FIELDS * c + 4], cand[3 * nc + 1] = 0.25 * (xy[0] + xy[2] + xy[4] + xy[6]) * L, cand[3 * nc + 2] = 0.25 * (xy[1] + xy[3] + xy[5] + xy[7]) * L;
    slot[nc++] = 3 * m->cellbody[c];
    for (int k = 0; k < 4; k++) vbody[m->cellverts[4 * c + k] - m->vStart] = m->cellbody[c];
  }
  for (PetscInt v = 0; v < nv; v++) {
    PetscInt  oc, ou;
    PetscReal x, y;
    PetscCall(PetscSectionGetOffset(ar.cs, v + m->vStart, &oc));
    PetscCall(PetscSectionGetOffset(ar.lsec, v + m->vStart, &ou));
    x = PetscRealPart(ar.ca[oc]) * L, y = PetscRealPart(ar.ca[oc + 1]) * L;
    if (nodal) cand[3 * nc] = nodal[M2D_NODAL_FIELDS * v + 4], cand[3 * nc + 1] = x, cand[3 * nc + 2] = y, slot[nc++] = 3 * vbody[v] + 1;
    cand[3 * nc] = PetscSqrtReal(PetscSqr(PetscRealPart(ar.ua[ou])) + PetscSqr(PetscRealPart(ar.ua[ou + 1]))) * pb->units.U, cand[3 * nc + 1] = x, cand[3 * nc + 2] = y;
    slot[nc++] = 3 * vbody[v] + 2;
  }
  PetscCall(MeshArraysClose(&ar));
  PetscCall(SlotMaxima(comm, 3 * nb, nc, cand, slot, best));
  for (PetscInt b = 0; b < nb; b++) {
    char line[512];
    int  len = snprintf(line, sizeof(line), "body '%s':", pb->s.body[b].name);
    PetscCall(M2dSummaryListString(sum, "body_results", b, "name", pb->s.body[b].name));
    for (int k = 0; k < 3; k++) {
      const PetscReal *q = &best[3 * (3 * b + k)];
      char             at[64];
      if (q[0] < 0) continue; /* no nodal stresses (-error_estimate false), or no cells */
      PetscCall(M2dSummaryListReal(sum, "body_results", b, kind[k], q[0]));
      PetscCall(PetscSNPrintf(at, sizeof(at), "%s_at", kind[k]));
      PetscCall(M2dSummaryListArray(sum, "body_results", b, at, 2, &q[1]));
      if (len < (int)sizeof(line)) len += snprintf(line + len, sizeof(line) - (size_t)len, "%s %s %.6g at (%.6g, %.6g)", k ? "," : "", k == 0 ? "von Mises max (cells)" : k == 1 ? "nodal" : "displacement max", (double)q[0], (double)q[1], (double)q[2]);
    }
    if (b < M2D_LINES_MAX) PetscCall(PetscPrintf(comm, "%s\n", line));
  }
  if (nb > M2D_LINES_MAX) PetscCall(PetscPrintf(comm, "(%" PetscInt_FMT " more bodies: every body's figures are in the summary's body_results)\n", nb - M2D_LINES_MAX));
  PetscCall(PetscFree4(cand, slot, vbody, best));
  PetscCall(PetscFree(nodal));
  PetscCall(PetscFree(cells));
  PetscFunctionReturn(0);
}

PetscErrorCode ReportEstimatorOptions(MPI_Comm comm, M2dEstimatorOptions *o)
{
  const char *recs[] = {"spr", "average"}; /* order of M2dRecovery */
  PetscInt    rec    = M2D_RECOVERY_SPR;
  PetscBool   help;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(o, sizeof(*o)));
  o->enabled = PETSC_TRUE;
  M2dSizeFieldDefaults(&o->size);
  PetscOptionsBegin(comm, NULL, "mortar2d: error estimate", "");
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-error_estimate", "estimate the error per cell (cell field error_indicator, summary error_estimate)", o->enabled, &o->enabled));
  PetscCall(M2dOptionsEList(PetscOptionsObject, "-estimator_recovery", "stress recovery: spr (superconvergent patch) or average (nodal averaging)", recs, 2, &rec));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-estimator_target", "target relative energy-norm error of the size field (-adapt: -adapt_target)", o->size.target_rel, &o->size.target_rel, &o->target_set));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-estimator_order_sing", "order in h of the indicator at singular cells (size field)", o->size.order_sing, &o->size.order_sing, NULL));
  PetscOptionsEnd();
  PetscCall(M2dOptionsRaise(comm));
  o->recovery = (M2dRecovery)rec;
  PetscCheck(o->size.target_rel > 0 && o->size.target_rel < 1, comm, PETSC_ERR_USER_INPUT, "option -estimator_target: %g must be in (0, 1)", (double)o->size.target_rel);
  PetscCheck(o->size.order_sing > 0 && o->size.order_sing <= o->size.order, comm, PETSC_ERR_USER_INPUT, "option -estimator_order_sing: %g must be in (0, %g]", (double)o->size.order_sing, (double)o->size.order);
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  if (!o->enabled && !help) PetscCall(M2dOptionsNoEffect(comm, "-estimator_recovery -estimator_target -estimator_order_sing", "with -error_estimate false"));
  PetscFunctionReturn(0);
}

/* -adapt_goal contact: the dual solution z of the pressure (dual.h), its own
 * indicators eta_K(z), and the goal-oriented indicator eta_K^g =
 * sqrt(eta_K(u) eta_K(z) |u|/|z|) - an energy-norm quantity that falls as h^2
 * where both fields are smooth, so the size rule of estimator.h applies to it
 * unchanged. New sizes into hn. It only says where the cells go: its sum is
 * no estimate of the pressure error (on Hertz its ratio to the true error grew
 * from 2.5 to 17 over three meshes), so the loop stops on the energy-norm
 * estimate, whose effectivity stays near 1. */
static PetscErrorCode GoalIndicators(M2dProblem *pb, M2dSolution *sol, const M2dEstimatorOptions *eo, const PetscReal eta[], M2dFigures *fig, PetscReal hn[])
{
  MPI_Comm         comm = PetscObjectComm((PetscObject)pb->mesh.dm);
  PetscInt         nlc  = pb->mesh.cEnd - pb->mesh.cStart;
  PetscReal       *az, *g, *h, s2 = 0;
  Vec              z;
  M2dErrorEstimate ez, eg;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(sol->u, &z));
  PetscCall(M2dDualSolve(pb, sol, z));
  PetscCall(PetscMalloc3(nlc + 1, &az, nlc + 1, &g, nlc + 1, &h));
  PetscCall(M2dEstimateError(&pb->mesh, &pb->s, z, NULL, eo->recovery, az, NULL, NULL, &ez));
  for (PetscInt c = 0; c < nlc; c++) {
    g[c] = PetscSqrtReal(eta[c] * az[c] * fig->est.energy_norm / PetscMax(ez.energy_norm, PETSC_SMALL));
    s2 += g[c] * g[c];
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &s2, 1, MPIU_REAL, MPIU_SUM, comm));
  eg          = fig->est;
  eg.estimate = PetscSqrtReal(s2);
  { /* the cells' shares of the pressure error estimate: the local part goes as
     * the dual-weighted indicators, the global part as the energy-norm ones */
    PetscReal gl = 0.5 * PetscSqr(fig->est.estimate_rel), loc2 = PetscSqr(fig->pressure_local), wg = loc2 / PetscMax(loc2 + gl * gl, PETSC_SMALL);
    PetscReal e2 = PetscSqr(fig->est.estimate);
    for (PetscInt c = 0; c < nlc; c++) g[c] = PetscSqrtReal(wg * PetscSqr(g[c]) / PetscMax(s2, PETSC_SMALL) + (1 - wg) * PetscSqr(eta[c]) / PetscMax(e2, PETSC_SMALL));
    eg.estimate = 1;
  }
  for (PetscInt c = 0; c < nlc; c++) sol->eta[M2D_ETA_FIELDS * c + 3] = g[c];
  fig->size_est = eg;
  PetscCall(M2dCellSizes(&pb->mesh, h));
  PetscCall(M2dSizeField(comm, nlc, h, g, &eg, &eo->size, hn, &fig->expected_cells));
  PetscCall(PetscFree3(az, g, h));
  PetscCall(VecDestroy(&z));
  PetscFunctionReturn(0);
}

/* the indicators (reference units inside; the absolute figures in the user's:
 * an energy per unit thickness scales with S U L), the size field, and the
 * effectivity where the answer is known */
static PetscErrorCode Estimate(M2dProblem *pb, M2dSolution *sol, const M2dEstimatorOptions *eo, M2dFigures *fig, M2dSummary *sum)
{
  MPI_Comm          comm = PetscObjectComm((PetscObject)pb->mesh.dm);
  const M2dContact *ct   = pb->has_contact ? &pb->contact : NULL;
  PetscInt          nlc  = pb->mesh.cEnd - pb->mesh.cStart;
  PetscReal        *a, *av, *h, *hn, nexp, scale = M2dUnitsEnergyNorm(&pb->units);
  M2dErrorEstimate *est = &fig->est;
  M2dEstimatorOptions eoc = *eo; /* the cap in cells: dofs per cell as on this mesh */

  PetscFunctionBeginUser;
  if (eo->max_dofs > 0) eoc.size.max_cells = eo->max_dofs * (PetscReal)pb->mesh.ncell_global / (2.0 * (PetscReal)pb->mesh.nvert_global);
  if (eo->growth > 0) eoc.size.max_cells = PetscMin(eoc.size.max_cells > 0 ? eoc.size.max_cells : PETSC_MAX_REAL, eo->growth * (PetscReal)pb->mesh.ncell_global);
  eo = &eoc;
  PetscCall(PetscMalloc1(M2D_ETA_FIELDS * nlc + 1, &sol->eta));
  PetscCall(PetscMalloc4(nlc + 1, &a, nlc + 1, &av, nlc + 1, &h, nlc + 1, &hn));
  PetscCall(PetscMalloc1(3 * (pb->mesh.vEnd - pb->mesh.vStart) + 1, &sol->sv));
  PetscCall(M2dEstimateError(&pb->mesh, &pb->s, sol->u, ct, eo->recovery, a, av, sol->sv, est)); /* one recovery: the indicators, their volume part, the nodal stresses */
  for (PetscInt c = 0; c < nlc; c++) sol->eta[M2D_ETA_FIELDS * c + 1] = av[c] * scale;
  PetscCall(M2dCellSizes(&pb->mesh, h));
  if (eo->goal_contact && ct && sol->path != M2D_PATH_LINEAR) PetscCall(GoalIndicators(pb, sol, eo, a, fig, hn));
  else {
    for (PetscInt c = 0; c < nlc; c++) sol->eta[M2D_ETA_FIELDS * c + 3] = a[c];
    fig->size_est = *est;
    PetscCall(M2dSizeField(comm, nlc, h, a, est, &eo->size, hn, &nexp));
  }
  if (eo->goal_contact && ct && sol->path != M2D_PATH_LINEAR) nexp = fig->expected_cells;
  for (PetscInt c = 0; c < nlc; c++) {
    sol->eta[M2D_ETA_FIELDS * c]     = a[c] * scale;
    sol->eta[M2D_ETA_FIELDS * c + 2] = hn[c] / h[c];
  }
  SummaryReal(sum, "", "error_estimate", est->estimate_rel);
  SummaryReal(sum, "estimator", "absolute", est->estimate * scale);
  SummaryReal(sum, "estimator", "volume", est->volume * scale);
  SummaryReal(sum, "estimator", "contact", est->contact * scale);
  SummaryReal(sum, "estimator", "energy_norm", est->energy_norm * scale);
  SummaryReal(sum, "estimator", "eta_max", est->eta_max * scale);
  SummaryReal(sum, "estimator", "expected_cells", nexp);
  fig->expected_cells = nexp;
  PetscCall(PetscPrintf(comm, "error estimate: %.4e relative (%.4e absolute: volume %.4e, contact %.4e; energy norm %.4e)\n", (double)est->estimate_rel, (double)(est->estimate * scale), (double)(est->volume * scale), (double)(est->contact * scale), (double)(est->energy_norm * scale)));
  if (pb->s.exact == M2D_EXACT_MMS || pb->s.exact == M2D_EXACT_UNIFORM) {
    PetscReal err, nrm;
    PetscCall(M2dExactEnergyError(&pb->mesh, &pb->s, sol->u, &err, &nrm));
    SummaryReal(sum, "estimator", "true_error", err * scale);
    SummaryReal(sum, "estimator", "true_error_rel", nrm > 0 ? err / nrm : 0);
    SummaryReal(sum, "estimator", "effectivity", err > 0 ? est->estimate / err : 0);
    fig->true_error_rel = nrm > 0 ? err / nrm : 0;
    fig->effectivity    = err > 0 ? est->estimate / err : 0;
    PetscCall(PetscPrintf(comm, "true energy-norm error %.4e, effectivity %.4f\n", (double)(err * scale), (double)(err > 0 ? est->estimate / err : 0)));
  }
  PetscCall(PetscFree4(a, av, h, hn));
  PetscFunctionReturn(0);
}

PetscErrorCode ReportCompute(M2dProblem *pb, M2dSolution *sol, const M2dVerification *v, const M2dEstimatorOptions *eo, M2dFigures *fig, M2dSummary *sum)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(fig, sizeof(*fig)));
  fig->pressure_l2_rel = fig->true_error_rel = fig->effectivity = fig->pressure_ripple = fig->pressure_estimate = -1;
  PetscCall(SummarizeProblem(pb, sol, v, sum));
  if (pb->has_contact) PetscCall(ContactPressureEstimate(&pb->contact, &fig->pressure_local));
  if (eo->enabled) PetscCall(Estimate(pb, sol, eo, fig, sum));
  /* the pressure's own (local) error, and the global one: the discrete model is
   * too stiff by its energy error squared (relative compliance), and a zone
   * whose width goes as the square root of the compliance moves its edge by half
   * that */
  if (pb->has_contact) fig->pressure_estimate = eo->enabled ? PetscSqrtReal(PetscSqr(fig->pressure_local) + PetscSqr(0.5 * PetscSqr(fig->est.estimate_rel))) : fig->pressure_local;
  if (pb->has_contact) PetscCall(SummarizeContact(pb, sol, fig, sum));
  if (pb->s.exact == M2D_EXACT_UNIFORM) {
    PetscReal *f;
    PetscCall(CellFields(pb, sol->u, 1.0, &f));
    PetscCall(SummarizeUniform(pb, f, sum));
    PetscCall(PetscFree(f));
  } else if (pb->s.exact == M2D_EXACT_MMS) PetscCall(SummarizeMMS(pb, sol->u, sum));
  PetscCall(SummarizeBodies(pb, sol, sum));
  PetscFunctionReturn(0);
}

/* rank 0: the contact CSV into the run's files */
static PetscErrorCode WriteCSV(const M2dProblem *pb, const M2dSolution *sol, M2dOutput *o)
{
  PetscErrorCode   ierr = 0;
  char             err[1024] = "";
  FILE            *fp;
  const PetscReal *nodes[1] = {NULL}, **steps = nodes;

  PetscFunctionBeginUser;
  if (o->rank == 0) {
    if (sol->nstep > 1) { /* every step's rows, a step column first */
      PetscCall(PetscMalloc1(sol->nstep, &steps));
      for (PetscInt k = 0; k < sol->nstep; k++) steps[k] = sol->steps[k].nodes;
    }
    ierr = OutputFile(o, "_contact.csv", &fp);
    if (!ierr) ierr = ContactWriteCSV(&pb->contact, sol->nstep > 1 ? sol->nstep : 0, steps, o->paths->run_id, fp);
    if (sol->nstep > 1) PetscCall(PetscFree(steps));
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  PetscCall(M2dCheckCollective(o->comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

/* the point fields of the interface (contact.h) on vectors like u: pressure
 * and gap, active, and with friction the traction and slip, the slip
 * increment and status; v[0..3] created here */
static PetscErrorCode InterfaceFields(const M2dContact *c, Vec u, PetscBool friction, Vec v[4], M2dFieldSet *fs)
{
  PetscFunctionBeginUser;
  for (int k = 0; k < (friction ? 4 : 2); k++) PetscCall(VecDuplicate(u, &v[k]));
  PetscCall(ContactFillField(c, v[0], v[1]));
  fs->point[fs->npoint++] = (M2dPointField){"contact_pressure", v[0], PETSC_FALSE, 0, NULL, 0};
  fs->point[fs->npoint++] = (M2dPointField){"gap", v[0], PETSC_FALSE, 1, NULL, 0};
  fs->point[fs->npoint++] = (M2dPointField){"active", v[1], PETSC_FALSE, 0, NULL, 0};
  if (!friction) PetscFunctionReturn(0);
  PetscCall(ContactFillFriction(c, v[2], v[3]));
  fs->point[fs->npoint++] = (M2dPointField){"traction_t", v[2], PETSC_FALSE, 0, NULL, 0};
  fs->point[fs->npoint++] = (M2dPointField){"slip", v[2], PETSC_FALSE, 1, NULL, 0};
  fs->point[fs->npoint++] = (M2dPointField){"slip_increment", v[3], PETSC_FALSE, 0, NULL, 0};
  fs->point[fs->npoint++] = (M2dPointField){"contact_status", v[3], PETSC_FALSE, 1, NULL, 0};
  PetscFunctionReturn(0);
}

static const char *cname[M2D_CELL_FIELDS] = {"sigma_x", "sigma_y", "sigma_z", "sigma_xy", "von_mises", "body"};

/* What one earlier load step shows (its displacement, interface and cell
 * stresses), for the series: made into st (its own vectors and arrays; the
 * interface's results are borrowed while it is written) */
typedef struct {
  M2dFieldSet fs;
  Vec         u, v[4];
  PetscReal  *cells;
} StepFields;

static PetscErrorCode StepFieldsCreate(M2dProblem *pb, const M2dLoadStep *ls, PetscBool friction, StepFields *sf)
{
  M2dContact *c = &pb->contact;
  PetscReal  *keep[7] = {c->pressure, c->gap, c->active, c->traction, c->slip, c->slip_inc, c->status}, *arr;
  PetscInt    nn = c->nnormal;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sf, sizeof(*sf)));
  PetscCall(VecDuplicate(ls->u, &sf->u));
  PetscCall(VecCopy(ls->u, sf->u));
  PetscCall(M2dFramesRotateGlobal(&pb->frames, &pb->mesh, sf->u, PETSC_TRUE));
  PetscCall(CellFields(pb, sf->u, pb->units.S, &sf->cells));
  PetscCall(VecScale(sf->u, pb->units.U));
  sf->fs.point[sf->fs.npoint++] = (M2dPointField){"displacement", sf->u, PETSC_TRUE, 0, NULL, 0};
  if (pb->has_contact) { /* the step's interface in place of the final one's while the fields are made */
    PetscCall(PetscMalloc1(7 * nn + 1, &arr));
    for (int f = 0; f < 7; f++) {
      PetscReal *a = arr + f * nn;
      for (PetscInt j = 0; j < nn; j++) a[j] = ls->nodes[M2D_STEP_NODE_FIELDS * j + f];
      if (f == 0) c->pressure = a;
      else if (f == 1) c->gap = a;
      else if (f == 2) c->active = a;
      else if (f == 3) c->traction = a;
      else if (f == 4) c->slip = a;
      else if (f == 5) c->slip_inc = a;
      else c->status = a;
    }
    ContactPairViews(c);
    PetscCall(InterfaceFields(c, sf->u, friction, sf->v, &sf->fs));
    c->pressure = keep[0], c->gap = keep[1], c->active = keep[2], c->traction = keep[3], c->slip = keep[4], c->slip_inc = keep[5], c->status = keep[6];
    ContactPairViews(c);
    PetscCall(PetscFree(arr));
  }
  for (int k = 0; k < M2D_CELL_FIELDS; k++) sf->fs.cell[sf->fs.ncell++] = (M2dCellField){cname[k], sf->cells, M2D_CELL_FIELDS, k};
  PetscFunctionReturn(0);
}

static PetscErrorCode StepFieldsDestroy(StepFields *sf)
{
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&sf->u));
  for (int k = 0; k < 4; k++) PetscCall(VecDestroy(&sf->v[k]));
  PetscCall(PetscFree(sf->cells));
  PetscFunctionReturn(0);
}

PetscErrorCode ReportWriteFields(M2dProblem *pb, const M2dSolution *sol, M2dOutput *o)
{
  PetscReal  *cells, *nodal = NULL, *times = NULL;
  Vec         u, v[4] = {NULL, NULL, NULL, NULL};
  M2dFieldSet fs, *steps = NULL;
  StepFields *sf    = NULL;
  M2dSeries   se    = {0, NULL, NULL};
  PetscBool   friction = (PetscBool)(sol->slip != NULL);
  PetscInt    ns = sol->nstep > 1 && o->paths->h5 ? sol->nstep - 1 : 0; /* the last one is the final state */
  const char *nname[M2D_NODAL_FIELDS] = {"sigma_x_nodal", "sigma_y_nodal", "sigma_z_nodal", "sigma_xy_nodal", "von_mises_nodal"}, *names[M2D_MAX_BODIES];

  PetscFunctionBeginUser;
  if (pb->has_contact && o->paths->csv) PetscCall(WriteCSV(pb, sol, o));
  if (!o->paths->vtu && !o->paths->h5) PetscFunctionReturn(0);
  PetscCall(CellFields(pb, sol->u, pb->units.S, &cells));
  if (sol->sv) PetscCall(NodalFields(pb, sol->sv, &nodal));
  PetscCall(VecDuplicate(sol->u, &u));
  PetscCall(VecAXPY(u, pb->units.U, sol->u));
  PetscCall(PetscCalloc3(ns + 1, &sf, ns + 1, &steps, ns + 1, &times));
  for (PetscInt k = 0; k < ns; k++) {
    PetscCall(StepFieldsCreate(pb, &sol->steps[k], friction, &sf[k]));
    steps[k] = sf[k].fs;
    times[k] = sol->steps[k].time;
  }
  se.n = ns, se.time = times, se.step = steps;
  PetscCall(PetscMemzero(&fs, sizeof(fs)));
  for (PetscInt b = 0; b < pb->s.nbody; b++) names[b] = pb->s.body[b].name;
  fs.nbody = pb->s.nbody, fs.body_names = names;
  fs.point[fs.npoint++] = (M2dPointField){"displacement", u, PETSC_TRUE, 0, NULL, 0};
  if (pb->has_contact) PetscCall(InterfaceFields(&pb->contact, u, friction, v, &fs));
  for (int k = 0; nodal && k < M2D_NODAL_FIELDS; k++) fs.point[fs.npoint++] = (M2dPointField){nname[k], NULL, PETSC_FALSE, k, nodal, M2D_NODAL_FIELDS};
  for (int k = 0; k < M2D_CELL_FIELDS; k++) fs.cell[fs.ncell++] = (M2dCellField){cname[k], cells, M2D_CELL_FIELDS, k};
  if (sol->eta) {
    const char *ename[M2D_ETA_WRITTEN] = {"error_indicator", "error_indicator_volume", "size_factor"};
    for (int k = 0; k < M2D_ETA_WRITTEN; k++) fs.cell[fs.ncell++] = (M2dCellField){ename[k], sol->eta, M2D_ETA_FIELDS, k};
  }
  PetscCall(OutputWriteFields(&pb->mesh, pb->units.L, o, &fs, ns ? &se : NULL, sol->nstep > 1 ? sol->steps[sol->nstep - 1].time : -1)); /* the user's coordinates */
  for (PetscInt k = 0; k < ns; k++) PetscCall(StepFieldsDestroy(&sf[k]));
  PetscCall(PetscFree3(sf, steps, times));
  for (int k = 0; k < 4; k++) PetscCall(VecDestroy(&v[k]));
  PetscCall(VecDestroy(&u));
  PetscCall(PetscFree(nodal));
  PetscCall(PetscFree(cells));
  PetscFunctionReturn(0);
}

PetscErrorCode ReportWriteSummary(const M2dProblem *pb, M2dSummary *sum, const double times[], M2dOutput *o)
{
  MPI_Comm      comm = PetscObjectComm((PetscObject)pb->mesh.dm);
  struct rusage  ru;
  PetscReal      mb;
  PetscErrorCode ierr      = 0;
  char           err[1024] = "";

  PetscFunctionBeginUser;
  getrusage(RUSAGE_SELF, &ru); /* peak resident memory of this rank (Linux: kB) */
  mb = (PetscReal)ru.ru_maxrss / 1024.0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &mb, 1, MPIU_REAL, MPIU_MAX, comm));
  SummaryReal(sum, "", "memory_max_rank_mb", mb);
  for (int k = 0; k < M2D_STAGE_COUNT; k++) SummaryReal(sum, "time", M2dStageName[k], times[k]);
  SummaryReal(sum, "time", "total", times[M2D_STAGE_COUNT]);
  PetscCall(PetscPrintf(comm, "dofs %" PetscInt_FMT ", time: mesh %.3f s, contact %.3f s, assembly %.3f s, solve %.3f s, output %.3f s, total %.3f s\n", 2 * pb->mesh.nvert_global, times[0], times[1], times[2], times[3], times[4], times[5]));
  if (!o->paths->summary) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < o->n; k++) { /* the files of this run, by their names in -output_dir */
    const char *base = strrchr(o->file[k].final, '/'), *dot = strrchr(o->file[k].final, '.');
    SummaryString(sum, "files", dot ? dot + 1 : "file", base ? base + 1 : o->file[k].final);
  }
  PetscCheck(!sum->err, comm, PETSC_ERR_ARG_WRONG, "%s", sum->errmsg);
  if (o->rank == 0) { /* a write error shows when OutputCommit closes the file */
    FILE *fp;
    ierr = OutputFile(o, NULL, &fp);
    if (!ierr) M2dSummaryPrint(fp, sum);
    else PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  PetscCall(M2dCheckCollective(comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}
