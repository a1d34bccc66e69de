/* report.c - results, comparisons with exact answers, files (see report.h). */
#include "report.h"
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

static PetscErrorCode SummarizeProblem(const M2dProblem *pb, const M2dSolution *sol, const M2dVerification *v, M2dSummary *sum)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)pb->mesh.dm), &size));
  SummaryString(sum, "", "program", "mortar2d");
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
  /* every figure is in the units of the input (the internal scaling, units.h, never shows) */
  SummaryString(sum, "units", "length", "the mesh's coordinates x -mesh_scale");
  SummaryString(sum, "units", "stress", "the moduli's and the loads'");
  SummaryString(sum, "units", "force", "stress x length (per unit thickness)");
  PetscFunctionReturn(0);
}

/* pair k's Hertz comparison: the first pair's at the top level, every pair's in "pairs" */
static PetscErrorCode SummarizeHertz(M2dProblem *pb, PetscInt k, M2dFigures *fig, M2dSummary *sum)
{
  M2dHertzResult h;
  const M2dUnits *un = &pb->units;

  PetscFunctionBeginUser;
  PetscCall(ContactHertz(&pb->contact.pair[k], &pb->s, &h)); /* reference units */
  fig->pressure_l2_rel = k ? PetscMax(fig->pressure_l2_rel, h.pressure_l2_rel) : h.pressure_l2_rel;
  if (k == 0) {
    SummaryReal(sum, "", "pressure_l2_rel", h.pressure_l2_rel);
    SummaryReal(sum, "", "peak_pressure", h.peak_pressure * un->S);
    SummaryReal(sum, "", "half_width", h.half_width * un->L);
    SummaryReal(sum, "", "half_width_spacing", h.h_edge * un->L);
    SummaryReal(sum, "", "hertz_a", h.a * un->L);
    SummaryReal(sum, "", "hertz_p0", h.p0 * un->S);
    SummaryReal(sum, "", "hertz_radius", pb->user->hertz_radius);
  }
  if (pb->s.npair > 1) {
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "pressure_l2_rel", h.pressure_l2_rel));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "peak_pressure", h.peak_pressure * un->S));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "half_width", h.half_width * un->L));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "hertz_a", h.a * un->L));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "hertz_p0", h.p0 * un->S));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "hertz_radius", pb->user->pair[k].hertz_radius));
  }
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "Hertz%s%s: a = %.6g (computed %.6g, node spacing %.3g), p0 = %.6g (computed peak %.6g), L2 error of the pressure on [0, 1.5a]: %.4e\n", pb->s.npair > 1 ? " " : "", pb->s.npair > 1 ? pb->s.pair[k].nm : "", (double)(h.a * un->L), (double)(h.half_width * un->L), (double)(h.h_edge * un->L), (double)(h.p0 * un->S),
                        (double)(h.peak_pressure * un->S), (double)h.pressure_l2_rel));
  PetscFunctionReturn(0);
}

/* every pair in the list "pairs" (user units), and a line each */
static PetscErrorCode SummarizePairs(const M2dProblem *pb, M2dSummary *sum)
{
  const M2dContact *c = &pb->contact;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < c->npair; k++) {
    const M2dContactPair *p  = &c->pair[k];
    PetscInt              na = 0;
    for (PetscInt j = 0; j < p->R.n; j++) na += p->active[j] != 0;
    PetscCall(M2dSummaryListString(sum, "pairs", k, "nonmortar", p->def->nm));
    PetscCall(M2dSummaryListString(sum, "pairs", k, "mortar", p->def->m));
    PetscCall(M2dSummaryListString(sum, "pairs", k, "method", M2dMethodOf(p->method, p->basis)->name));
    PetscCall(M2dSummaryListInt(sum, "pairs", k, "contact_nodes", p->R.n));
    PetscCall(M2dSummaryListInt(sum, "pairs", k, "active_nodes", na));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "contact_force", p->force_n));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "contact_force_x", p->force[0]));
    PetscCall(M2dSummaryListReal(sum, "pairs", k, "contact_force_y", p->force[1]));
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "pair %d '%s:%s': %" PetscInt_FMT " of %" PetscInt_FMT " nodes active, integral of pressure %.12e, on the non-mortar body (%.12e, %.12e)\n", (int)k + 1, p->def->nm, p->def->m, na, p->R.n, (double)p->force_n, (double)p->force[0], (double)p->force[1]));
  }
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

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < c->npair && pb->s.hertz; k++) PetscCall(SummarizeHertz(pb, k, fig, sum));
  PetscCall(ContactToUserUnits(c, &pb->units));
  SummaryString(sum, "", "method", M2dMethodOf(c0->method, c0->basis)->family);
  SummaryInt(sum, "", "contact_nodes", c->R.n);
  SummaryReal(sum, "", "contact_force", c0->force_n);
  SummaryReal(sum, "", "contact_force_x", c0->force[0]);
  SummaryReal(sum, "", "contact_force_y", c0->force[1]);
  if (c0->nm.body >= 0 && c0->m.body >= 0) {
    char signs[3 * M2D_NAME_LEN + 256];
    PetscCall(PetscSNPrintf(signs, sizeof(signs), "contact_force: the integral of the contact pressure, positive in compression; contact_force_x, contact_force_y: the force of the mortar body '%s' on the non-mortar body '%s'%s", pb->s.body[c0->m.body].name, pb->s.body[c0->nm.body].name, c->npair > 1 ? " (the first pair; every pair's in pairs)" : ""));
    SummaryString(sum, "", "contact_force_signs", signs);
  }
  if (c->npair > 1) PetscCall(SummarizePairs(pb, sum));
  SummaryString(sum, "", "contact_solver", sol->path == M2D_PATH_TIED ? "tied" : sol->as.vi ? "vinewtonrsls" : "pdas");
  if (sol->path != M2D_PATH_TIED) SummaryInt(sum, "", "iterations", sol->as.iterations);
  PetscCall(VecSum(sol->active, &na));
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
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "contact force: integral of pressure %.12e, on the non-mortar body (%.12e, %.12e)%s\n", (double)c0->force_n, (double)c0->force[0], (double)c0->force[1], c->npair > 1 ? " (the first pair)" : ""));
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "contact pressure: %" PetscInt_FMT " active nodes, estimated error %.3e (relative L2), ripple %.2f%% of the peak over %" PetscInt_FMT " interior ones\n", (PetscInt)(na + 0.5), (double)fig->pressure_estimate, (double)(100 * fig->pressure_ripple), fig->ripple_nodes));
  PetscFunctionReturn(0);
}

/* -exact uniform: max over cells of the stress error / p (reference units:
 * relative), in the frame x' = R(-exact_angle) x where sigma_y'y' = -p */
static PetscErrorCode SummarizeUniform(const M2dProblem *pb, const PetscReal *stress, M2dSummary *sum)
{
  PetscReal p = pb->s.exact_p, e[3] = {0, 0, 0}, th = pb->s.exact_angle * PETSC_PI / 180, c = PetscCosReal(th), sn = PetscSinReal(th);
  PetscInt  nlc = pb->mesh.cEnd - pb->mesh.cStart;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < nlc; k++) {
    const PetscReal *sg = &stress[M2D_CELL_FIELDS * k], sx = sg[0], sy = sg[1], sxy = sg[3];
    PetscReal        rx = c * c * sx + sn * sn * sy + 2 * sn * c * sxy, ry = sn * sn * sx + c * c * sy - 2 * sn * c * sxy, rxy = sn * c * (sy - sx) + (c * c - sn * sn) * sxy;
    e[0] = PetscMax(e[0], PetscAbsReal(ry + p) / PetscAbsReal(p));
    e[1] = PetscMax(e[1], PetscAbsReal(rx) / PetscAbsReal(p));
    e[2] = PetscMax(e[2], PetscAbsReal(rxy) / PetscAbsReal(p));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, e, 3, MPIU_REAL, MPIU_MAX, PetscObjectComm((PetscObject)pb->mesh.dm)));
  SummaryReal(sum, "error", "sigma_yy_max_rel", e[0]);
  SummaryReal(sum, "error", "sigma_xx_max_rel", e[1]);
  SummaryReal(sum, "error", "sigma_xy_max_rel", e[2]);
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)pb->mesh.dm), "uniform stress check: max |sigma_yy + p|/p = %.3e, max |sigma_xx|/p = %.3e, max |sigma_xy|/p = %.3e\n", (double)e[0], (double)e[1], (double)e[2]));
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
  else PetscCall(M2dSizeField(comm, nlc, h, a, est, &eo->size, hn, &nexp));
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

/* rank 0: the contact CSV into the run's files */
static PetscErrorCode WriteCSV(const M2dProblem *pb, M2dOutput *o)
{
  PetscErrorCode ierr = 0;
  char           err[1024] = "";
  FILE          *fp;

  PetscFunctionBeginUser;
  if (o->rank == 0) {
    ierr = OutputFile(o, "_contact.csv", &fp);
    if (!ierr) ierr = ContactWriteCSV(&pb->contact, o->paths->run_id, fp);
    if (ierr) PetscCall(PetscStrncpy(err, M2dFirstError(), sizeof(err)));
  }
  PetscCall(M2dCheckCollective(o->comm, ierr ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

PetscErrorCode ReportWriteFields(M2dProblem *pb, const M2dSolution *sol, M2dOutput *o)
{
  PetscReal  *cells, *nodal = NULL;
  Vec         u, cfield = NULL, afield = NULL;
  M2dFieldSet fs;
  const char *cname[M2D_CELL_FIELDS]  = {"sigma_x", "sigma_y", "sigma_z", "sigma_xy", "von_mises", "body"};
  const char *nname[M2D_NODAL_FIELDS] = {"sigma_x_nodal", "sigma_y_nodal", "sigma_z_nodal", "sigma_xy_nodal", "von_mises_nodal"};

  PetscFunctionBeginUser;
  if (pb->has_contact && o->paths->csv) PetscCall(WriteCSV(pb, o));
  if (!o->paths->vtu && !o->paths->h5) PetscFunctionReturn(0);
  PetscCall(CellFields(pb, sol->u, pb->units.S, &cells));
  if (sol->sv) PetscCall(NodalFields(pb, sol->sv, &nodal));
  PetscCall(VecDuplicate(sol->u, &u));
  PetscCall(VecAXPY(u, pb->units.U, sol->u));
  PetscCall(M2dUnitsScaleMesh(&pb->mesh, pb->units.L)); /* the files hold the user's coordinates */
  PetscCall(PetscMemzero(&fs, sizeof(fs)));
  fs.point[fs.npoint++] = (M2dPointField){"displacement", u, PETSC_TRUE, 0, NULL, 0};
  if (pb->has_contact) {
    PetscCall(VecDuplicate(u, &cfield));
    PetscCall(VecDuplicate(u, &afield));
    PetscCall(ContactFillField(&pb->contact, cfield, afield));
    fs.point[fs.npoint++] = (M2dPointField){"contact_pressure", cfield, PETSC_FALSE, 0, NULL, 0};
    fs.point[fs.npoint++] = (M2dPointField){"gap", cfield, PETSC_FALSE, 1, NULL, 0};
    fs.point[fs.npoint++] = (M2dPointField){"active", afield, PETSC_FALSE, 0, NULL, 0};
  }
  for (int k = 0; nodal && k < M2D_NODAL_FIELDS; k++) fs.point[fs.npoint++] = (M2dPointField){nname[k], NULL, PETSC_FALSE, k, nodal, M2D_NODAL_FIELDS};
  for (int k = 0; k < M2D_CELL_FIELDS; k++) fs.cell[fs.ncell++] = (M2dCellField){cname[k], cells, M2D_CELL_FIELDS, k};
  if (sol->eta) {
    const char *ename[M2D_ETA_FIELDS] = {"error_indicator", "error_indicator_volume", "size_factor"};
    for (int k = 0; k < M2D_ETA_FIELDS; k++) fs.cell[fs.ncell++] = (M2dCellField){ename[k], sol->eta, M2D_ETA_FIELDS, k};
  }
  PetscCall(OutputWriteFields(&pb->mesh, o, &fs));
  PetscCall(VecDestroy(&afield));
  PetscCall(VecDestroy(&cfield));
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
