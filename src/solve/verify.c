/* verify.c - the answer's own checks (see verify.h). */
#include "verify.h"
#include "elasticity.h"
#include "logging.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The recovered residual r = K u + C^T lambda - f, as |r| / max(|f|, |K u|)
 * (rel) and as the normwise backward error |r| / (|K| |u| + |C^T| |lambda| +
 * |f|) (backward), infinity norms: the smallest relative change of K, C^T and
 * f of which (u, lambda) is the exact answer (Rigal and Gaches). A backward-
 * stable factorization delivers a backward error of a few rounding units
 * whatever the conditioning, while |r| / |f| grows with it (a cantilever 1000
 * times longer than thick: 2e-4). */
static PetscErrorCode Equilibrium(const M2dProblem *pb, const M2dSolution *sol, PetscReal *rel, PetscReal *backward)
{
  Vec       r, ku;
  PetscReal nr, nf, nku, nK, nu, scale;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(sol->u, &r));
  PetscCall(VecDuplicate(sol->u, &ku));
  PetscCall(MatMult(pb->K, sol->u, ku));
  PetscCall(VecWAXPY(r, -1.0, pb->f, ku));
  if (pb->has_contact) PetscCall(MatMultAdd(pb->kkt.Ct, sol->lam, r, r));
  PetscCall(VecNorm(r, NORM_2, &nr));
  PetscCall(VecNorm(pb->f, NORM_2, &nf));
  PetscCall(VecNorm(ku, NORM_2, &nku));
  *rel = nr / PetscMax(PetscMax(nf, nku), PETSC_SMALL);
  PetscCall(VecNorm(r, NORM_INFINITY, &nr));
  PetscCall(VecNorm(pb->f, NORM_INFINITY, &nf));
  PetscCall(MatNorm(pb->K, NORM_INFINITY, &nK));
  PetscCall(VecNorm(sol->u, NORM_INFINITY, &nu));
  scale = nK * nu + nf;
  if (pb->has_contact) {
    PetscReal nC, nl;
    PetscCall(MatNorm(pb->kkt.Ct, NORM_INFINITY, &nC));
    PetscCall(VecNorm(sol->lam, NORM_INFINITY, &nl));
    scale += nC * nl;
  }
  *backward = nr / PetscMax(scale, PETSC_SMALL);
  if (PetscIsInfOrNanReal(nr) || PetscIsInfOrNanReal(scale)) *rel = *backward = PETSC_INFINITY;
  PetscCall(VecDestroy(&r));
  PetscCall(VecDestroy(&ku));
  PetscFunctionReturn(0);
}

/* the rows' lambda, r - C u (weighted gaps, weighted slips) and rules, whole, on every rank */
static PetscErrorCode GatherRows(const M2dProblem *pb, const M2dSolution *sol, Vec all[3])
{
  const M2dKKT *kkt = &pb->kkt;
  Vec           gw, from[3];
  VecScatter    sc;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(kkt->r, &gw));
  PetscCall(MatMult(kkt->C, sol->u, gw));
  PetscCall(VecAYPX(gw, -1.0, kkt->r));
  from[0] = sol->lam, from[1] = gw, from[2] = sol->active;
  PetscCall(VecScatterCreateToAll(sol->lam, &sc, &all[0]));
  for (int k = 0; k < 3; k++) {
    if (k) PetscCall(VecDuplicate(all[0], &all[k]));
    PetscCall(VecScatterBegin(sc, from[k], all[k], INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(sc, from[k], all[k], INSERT_VALUES, SCATTER_FORWARD));
  }
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(VecDestroy(&gw));
  PetscFunctionReturn(0);
}

/* The contact conditions at every node (every rank the same, reference
 * units): the normal rows' max of -lambda, -gap and |lambda gap|; the
 * tangential rows' largest violation of Coulomb's law (verify.h) */
static PetscErrorCode ContactChecks(const M2dProblem *pb, const M2dSolution *sol, PetscReal *worst, PetscReal *coulomb)
{
  const M2dContact  *ct = &pb->contact;
  const PetscScalar *l, *g, *a;
  Vec                all[3];
  PetscReal          w = 0, cw = 0;

  PetscFunctionBeginUser;
  PetscCall(GatherRows(pb, sol, all));
  PetscCall(VecGetArrayRead(all[0], &l));
  PetscCall(VecGetArrayRead(all[1], &g));
  PetscCall(VecGetArrayRead(all[2], &a));
  for (PetscInt j = 0; j < ct->R.n; j++) {
    PetscInt  p   = ct->partner[j];
    PetscReal lam = PetscRealPart(l[j]), gap = PetscRealPart(g[j]) / ct->R.w[j], c;
    if (p < 0) c = PetscMax(PetscMax(-lam, -gap), PetscAbsReal(lam * gap));
    else {
      PetscReal bound = ct->pair[ct->rowpair[j]].mu * PetscRealPart(l[p]);
      if (PetscRealPart(a[p]) == 0) c = PetscAbsReal(lam);                                           /* open */
      else if (PetscRealPart(a[j]) != 0) c = PetscMax(PetscAbsReal(lam) - bound, PetscAbsReal(gap)); /* stick: within the cone, no slip */
      else c = PetscMax(PetscAbsReal(PetscAbsReal(lam) - bound), lam * gap);                          /* slip: on the cone, against the slip */
    }
    if (PetscIsInfOrNanReal(c)) c = PETSC_INFINITY;
    if (p < 0) w = PetscMax(w, c);
    else cw = PetscMax(cw, c);
  }
  PetscCall(VecRestoreArrayRead(all[2], &a));
  PetscCall(VecRestoreArrayRead(all[1], &g));
  PetscCall(VecRestoreArrayRead(all[0], &l));
  for (int k = 0; k < 3; k++) PetscCall(VecDestroy(&all[k]));
  *worst   = w;
  *coulomb = cw;
  PetscFunctionReturn(0);
}

/* bodies of very different moduli: the soft body's displacements swamp the
 * stiff one's strains in round-off (S2, stiff body on contact over a soft
 * supported one: ratio 1e12 fails the contact check); no solver option helps */
static void ModuliCause(const M2dScene *s, char *why, size_t len)
{
  PetscInt soft, stiff;

  why[0] = 0;
  (void)SceneModuliRatio(s, &soft, &stiff);
  if (s->body[stiff].E > 1e6 * s->body[soft].E)
    (void)PetscSNPrintf(why, len, "the moduli of '%s' and '%s' differ by a factor %.1e and round-off swamps the stiffer body's strains: bring -%s_E within 1e6 of -%s_E (a body a million times stiffer is rigid for the other)", s->body[soft].name, s->body[stiff].name, (double)(s->body[stiff].E / s->body[soft].E), s->body[soft].name, s->body[stiff].name);
}

/* A factorization's answer is judged by its backward error (a few rounding
 * units whatever the conditioning: a cantilever 1000 times longer than thick
 * has |r| / |f| = 2e-4 and a backward error of 3e-16); a Krylov solve's by
 * |r| / |f|, what it iterates on (its backward error can be as small on an
 * ill-conditioned scene while its answer is far off). */
static PetscErrorCode CheckEquilibrium(const M2dProblem *pb, const M2dSolution *sol, const M2dVerification *v)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)sol->u);
  char     why[512];

  PetscFunctionBeginUser;
  if (v->residual_rel <= M2D_VERIFY_TOL || (sol->factored && v->backward_error <= M2D_VERIFY_BACKWARD_TOL)) PetscFunctionReturn(0);
  ModuliCause(&pb->s, why, sizeof(why));
  PetscCheck(!why[0], comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its equilibrium check: |K u + C^T lambda - f| = %.3e of |f|, backward error %.3e; %s", (double)v->residual_rel, (double)v->backward_error, why);
  PetscCheck(sol->factored, comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its equilibrium check: |K u + C^T lambda - f| = %.3e of |f|, more than %.0e (an iterative solve's answer is held to that): solve more exactly (%s) or directly (the default)", (double)v->residual_rel, M2D_VERIFY_TOL,
             sol->path == M2D_PATH_ITERATIVE || pb->s.kkt_path == M2D_KKT_PATH_ITERATIVE ? "-iterative_ksp_rtol, -iterative_ksp_atol" : "-ksp_rtol, -ksp_atol");
  SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its equilibrium check: backward error %.3e (|K u + C^T lambda - f| = %.3e of |f|), more than the %.0e a factorization delivers: it lost accuracy (check E, nu and the supports%s)", (double)v->backward_error, (double)v->residual_rel, M2D_VERIFY_BACKWARD_TOL, sol->path == M2D_PATH_CONDENSED ? ", or try -kkt_path full" : "");
}

PetscErrorCode M2dVerifyTestPerturb(Vec u)
{
#if defined(M2D_TEST_HOOKS)
  const char *e = getenv("M2D_TEST_PERTURB");
#else
  const char *e = NULL; /* a build without the tests' hooks */
#endif
  char        kind[16] = "";
  double      eps      = 0;
  PetscReal   umax;
  PetscInt    lo, hi;
  PetscScalar *a;

  PetscFunctionBeginUser;
  if (!e || sscanf(e, "%15s %lf", kind, &eps) != 2) PetscFunctionReturn(0);
  PetscCall(VecNorm(u, NORM_INFINITY, &umax));
  PetscCall(VecGetOwnershipRange(u, &lo, &hi));
  PetscCall(VecGetArray(u, &a));
  for (PetscInt i = lo; i < hi; i++) {
    double x = sin(12.9898 * (double)i) * 43758.5453; /* the same by global index on any number of ranks */
    a[i - lo] += strcmp(kind, "noise") ? eps * a[i - lo] : eps * umax * (2 * (x - floor(x)) - 1);
  }
  PetscCall(VecRestoreArray(u, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dVerifyAnswer(const M2dProblem *pb, const M2dSolution *sol, M2dVerification *v)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)sol->u);
  char     why[512];

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_VERIFY], 0, 0, 0, 0));
  PetscCall(PetscMemzero(v, sizeof(*v)));
  PetscCall(Equilibrium(pb, sol, &v->residual_rel, &v->backward_error));
  if (sol->path == M2D_PATH_CONDENSED || sol->path == M2D_PATH_FULL) PetscCall(ContactChecks(pb, sol, &v->complementarity, &v->coulomb));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_VERIFY], 0, 0, 0, 0));
  if (sol->slip) PetscCall(PetscSNPrintf(why, sizeof(why), ", Coulomb %.3e (%.0e)", (double)v->coulomb, M2D_VERIFY_TOL));
  else why[0] = 0;
  if (sol->factored) PetscCall(PetscPrintf(comm, "checks: equilibrium |K u + C^T lambda - f| / |f| = %.3e (tolerance %.0e) or backward error %.3e (%.0e), complementarity %.3e (%.0e)%s\n", (double)v->residual_rel, M2D_VERIFY_TOL, (double)v->backward_error, M2D_VERIFY_BACKWARD_TOL, (double)v->complementarity, M2D_VERIFY_TOL, why));
  else PetscCall(PetscPrintf(comm, "checks: equilibrium |K u + C^T lambda - f| / |f| = %.3e (tolerance %.0e), complementarity %.3e (%.0e)%s\n", (double)v->residual_rel, M2D_VERIFY_TOL, (double)v->complementarity, M2D_VERIFY_TOL, why));
  PetscCall(CheckEquilibrium(pb, sol, v));
  PetscCheck(v->coulomb <= M2D_VERIFY_TOL, comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its friction check: Coulomb's law is violated by %.3e of the load at a contact node (tolerance %.0e: a friction force beyond MU x the pressure, a sticking node that slipped, or a slip along its friction force); the active set did not settle (raise -snes_max_it or check -contact_c)", (double)v->coulomb, M2D_VERIFY_TOL);
  if (v->complementarity > M2D_VERIFY_TOL) ModuliCause(&pb->s, why, sizeof(why));
  PetscCheck(v->complementarity <= M2D_VERIFY_TOL, comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its contact check: complementarity %.3e of the load (tolerance %.0e: a negative pressure, a penetration or both at one node); %s", (double)v->complementarity, M2D_VERIFY_TOL, why[0] ? why : "the active set did not settle (raise -snes_max_it or check -contact_c)");
  PetscFunctionReturn(0);
}

/* The check's measure of a cell: its strain, or theta^2/2 for a rotation theta -
 * a rigid rotation changes small-strain results by 1 - cos(theta) ~ theta^2/2,
 * not by theta (the linear strain of u = (R - I) x is (cos(theta) - 1) I).
 * Beyond 2 rad (theta^2/2 = theta) the rotation counts as theta: nothing there
 * is small, and a huge load's round-off rotation does not outgrow its strain. */
static PetscReal StrainMeasure(PetscReal strain, PetscReal rotation, PetscBool *by_rotation)
{
  PetscReal r = rotation < 2 ? 0.5 * rotation * rotation : rotation;
  *by_rotation = (PetscBool)(r > strain);
  return *by_rotation ? r : strain;
}

PetscErrorCode M2dVerifyStrain(const M2dProblem *pb, Vec u, M2dVerification *v)
{
  const M2dMesh *m    = &pb->mesh;
  MPI_Comm       comm = PetscObjectComm((PetscObject)u);
  PetscInt       nc = m->cEnd - m->cStart, cw = -1;
  PetscReal     *e, scale = pb->units.U / pb->units.L, most[2] = {0, 0}; /* a reference strain in the user's; largest strain, rotation */
  PetscBool      rot = PETSC_FALSE;
  M2dMeshArrays  ar;
  struct {
    double      value;
    PetscMPIInt rank;
  } worst = {0, 0};
  double      where[5] = {0, 0, 0, 0, 0}; /* centre x, y of the cell, body, strain, rotation */
  const char *body;
  char        what[128];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &worst.rank));
  PetscCall(PetscMalloc1(2 * nc + 1, &e));
  PetscCall(ElasticityCellStrain(m, &pb->s, u, e));
  for (PetscInt c = 0; c < nc; c++) {
    PetscBool r;
    PetscReal x = StrainMeasure(e[2 * c] * scale, e[2 * c + 1] * scale, &r);
    for (int k = 0; k < 2; k++) most[k] = PetscIsInfOrNanReal(e[2 * c + k]) ? PETSC_INFINITY : PetscMax(most[k], e[2 * c + k] * scale);
    if (!(x <= worst.value)) { /* NaN counts as the worst */
      worst.value = PetscIsInfOrNanReal(x) ? PETSC_INFINITY : x;
      cw          = c;
    }
  }
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  if (cw >= 0) {
    PetscReal xy[8];
    MeshCellCoordinates(m, ar.ca, ar.cs, m->cStart + cw, xy);
    where[0] = 0.25 * (xy[0] + xy[2] + xy[4] + xy[6]) * pb->units.L;
    where[1] = 0.25 * (xy[1] + xy[3] + xy[5] + xy[7]) * pb->units.L;
    where[2] = (double)m->cellbody[cw];
    where[3] = e[2 * cw] * scale;
    where[4] = e[2 * cw + 1] * scale;
  }
  PetscCall(MeshArraysClose(&ar));
  PetscCall(PetscFree(e));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, most, 2, MPIU_REAL, MPIU_MAX, comm));
  PetscCallMPI(MPI_Bcast(where, 5, MPI_DOUBLE, worst.rank, comm));
  v->strain_max   = most[0];
  v->rotation_max = most[1];
  if (worst.value <= M2D_STRAIN_WARN) PetscFunctionReturn(0);
  body = pb->s.body[(PetscInt)where[2]].name;
  (void)StrainMeasure(where[3], where[4], &rot);
  if (rot && where[4] >= 2) PetscCall(PetscSNPrintf(what, sizeof(what), "rotates by %.3g rad", where[4]));
  else if (rot) PetscCall(PetscSNPrintf(what, sizeof(what), "rotates by %.3g rad (a strain error of theta^2/2 = %.3g%%)", where[4], 100 * worst.value));
  else PetscCall(PetscSNPrintf(what, sizeof(what), "strains by %.3g%%", 100 * worst.value));
  PetscCheck(worst.value <= pb->s.strain_limit, comm, PETSC_ERR_USER_INPUT, "body '%s' %s at (%g, %g), more than -strain_limit %g: small-strain theory does not hold there (the answer would be off by about as much); lower the loads, the prescribed displacements or the initial overlap, or make the body stiffer (-%s_E)", body, what, where[0], where[1], (double)pb->s.strain_limit, body);
  PetscCall(PetscPrintf(comm, "warning: body '%s' %s at (%g, %g): small-strain theory is off by about as much (refused above -strain_limit %g)\n", body, what, where[0], where[1], (double)pb->s.strain_limit));
  PetscFunctionReturn(0);
}

/* u at both surfaces' nodes, on every rank: 2 per node, non-mortar then mortar */
static PetscErrorCode SurfaceDisplacements(const M2dContactPair *ct, Vec u, Vec *useq)
{
  PetscInt   n = ct->nm.nnode + ct->m.nnode, *idx;
  IS         is;
  VecScatter sc;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(2 * n + 1, &idx));
  for (PetscInt i = 0; i < ct->nm.nnode; i++) idx[2 * i] = ct->nm.gdof[i], idx[2 * i + 1] = ct->nm.gdof[i] + 1;
  for (PetscInt i = 0; i < ct->m.nnode; i++) idx[2 * (ct->nm.nnode + i)] = ct->m.gdof[i], idx[2 * (ct->nm.nnode + i) + 1] = ct->m.gdof[i] + 1;
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, 2 * n, idx, PETSC_OWN_POINTER, &is));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, 2 * n, useq));
  PetscCall(VecScatterCreate(u, is, *useq, NULL, &sc));
  PetscCall(VecScatterBegin(sc, u, *useq, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(sc, u, *useq, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(ISDestroy(&is));
  PetscFunctionReturn(0);
}

static PetscErrorCode PairVerifyReach(const M2dProblem *pb, const M2dContactPair *ct, Vec u)
{
  const M2dSurface  *nm = &ct->nm, *m = &ct->m;
  const PetscReal    L = pb->units.L, U = pb->units.U;
  PetscBool         *held;
  Vec                useq;
  const PetscScalar *us;
  PetscReal          umax = 0, worst = 0;
  PetscInt           iworst = -1;
  M2dSurfaceTree     tree;

  PetscFunctionBeginUser;
  PetscCall(SurfaceDisplacements(ct, u, &useq));
  PetscCall(VecGetArrayRead(useq, &us));
  for (PetscInt k = 0; k < 2 * (nm->nnode + m->nnode); k++) umax = PetscMax(umax, U * PetscAbsReal(PetscRealPart(us[k])));
  PetscCall(PetscCalloc1(nm->nnode + 1, &held));
  for (PetscInt j = 0; j < ct->R.n; j++) held[ct->R.node[j]] = PETSC_TRUE;
  PetscCall(SurfaceTreeCreate(m, &tree));
  for (PetscInt i = 0; i < nm->nnode; i++) { /* the same arithmetic on every rank: no reduction needed */
    PetscReal        nn[2], t, d, du[2], g;
    const PetscReal *n;
    PetscInt         e;
    if (held[i]) continue;
    SurfaceNodeNormal(nm, i, nn);
    /* the nearest mortar edge it faces, not behind it from the start (d > 0:
     * outside the mortar body); one farther than the surfaces moved apart
     * (L d > 2 umax) ends outside it whatever it is */
    e = SurfaceTreeFacing(&tree, &nm->x[2 * i], nn, -ct->reach, PetscMax(ct->reach, 2 * umax / L) * (1 + 1e-12), &d, &t);
    if (e < 0) continue;
    n = &m->normal[2 * e];
    for (int c = 0; c < 2; c++) {
      PetscReal um = (1 - t) * PetscRealPart(us[2 * (nm->nnode + m->edge[2 * e]) + c]) + t * PetscRealPart(us[2 * (nm->nnode + m->edge[2 * e + 1]) + c]);
      du[c]        = PetscRealPart(us[2 * i + c]) - um;
    }
    g = L * d + U * (du[0] * n[0] + du[1] * n[1]);
    if (g < worst) worst = g, iworst = i;
  }
  PetscCall(SurfaceTreeDestroy(&tree));
  PetscCall(VecRestoreArrayRead(useq, &us));
  PetscCall(VecDestroy(&useq));
  PetscCall(PetscFree(held));
  PetscCheck(iworst < 0 || worst >= -M2D_VERIFY_TOL * umax, PetscObjectComm((PetscObject)u), PETSC_ERR_NOT_CONVERGED,
             "the answer fails its contact check: non-mortar node (%g, %g) of '%s' ends %g inside '%s' but carries no multiplier (it lay beyond -contact_reach %g); raise -contact_reach (auto: 0.1 x the mortar surface's extent)",
             (double)(L * nm->x[2 * iworst]), (double)(L * nm->x[2 * iworst + 1]), ct->def->nm, (double)-worst, ct->def->m, (double)(L * ct->reach));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dVerifyReach(const M2dProblem *pb, Vec u)
{
  PetscFunctionBeginUser;
  if (!pb->has_contact) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < pb->contact.npair; k++) PetscCall(PairVerifyReach(pb, &pb->contact.pair[k], u));
  PetscFunctionReturn(0);
}
