/* verify.c - the answer's own checks (see verify.h). */
#include "verify.h"
#include "elasticity.h"
#include "logging.h"

static PetscErrorCode Equilibrium(const M2dProblem *pb, const M2dSolution *sol, PetscReal *rel)
{
  Vec       r, ku;
  PetscReal nr, nf, nku;

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
  if (PetscIsInfOrNanReal(nr)) *rel = PETSC_INFINITY;
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

PetscErrorCode M2dVerifyAnswer(const M2dProblem *pb, const M2dSolution *sol, M2dVerification *v)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)sol->u);

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_VERIFY], 0, 0, 0, 0));
  PetscCall(PetscMemzero(v, sizeof(*v)));
  PetscCall(Equilibrium(pb, sol, &v->residual_rel));
  if (sol->path == M2D_PATH_CONDENSED || sol->path == M2D_PATH_FULL) PetscCall(ContactChecks(pb, sol, &v->complementarity, &v->coulomb));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_VERIFY], 0, 0, 0, 0));
  if (sol->slip) PetscCall(PetscPrintf(comm, "checks: equilibrium |K u + C^T lambda - f| / |f| = %.3e, complementarity %.3e, Coulomb %.3e (tolerance %.0e)\n", (double)v->residual_rel, (double)v->complementarity, (double)v->coulomb, M2D_VERIFY_TOL));
  else PetscCall(PetscPrintf(comm, "checks: equilibrium |K u + C^T lambda - f| / |f| = %.3e, complementarity %.3e (tolerance %.0e)\n", (double)v->residual_rel, (double)v->complementarity, M2D_VERIFY_TOL));
  if (v->residual_rel > M2D_VERIFY_TOL) {
    const M2dScene *s = &pb->s;
    PetscInt        soft, stiff;
    (void)SceneModuliRatio(s, &soft, &stiff);
    /* bodies of very different moduli: the soft body's displacements swamp the
     * stiff one's strains in round-off (S2, stiff body on contact over a soft
     * supported one: ratio 1e9 gives 1.9e-6); no solver option helps */
    PetscCheck(s->body[stiff].E <= 1e6 * s->body[soft].E, comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its equilibrium check: |K u + C^T lambda - f| = %.3e of |f| (tolerance %.0e); the moduli of '%s' and '%s' differ by a factor %.1e and round-off swamps the stiffer body's strains: bring -%s_E within 1e6 of -%s_E (a body a million times stiffer is rigid for the other)", (double)v->residual_rel, M2D_VERIFY_TOL, s->body[soft].name, s->body[stiff].name, (double)(s->body[stiff].E / s->body[soft].E), s->body[soft].name, s->body[stiff].name);
    SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its equilibrium check: |K u + C^T lambda - f| = %.3e of |f| (tolerance %.0e); the linear solves lost accuracy (try -kkt_path full or a better-conditioned scene: check E, nu and the supports)", (double)v->residual_rel, M2D_VERIFY_TOL);
  }
  PetscCheck(v->coulomb <= M2D_VERIFY_TOL, comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its friction check: Coulomb's law is violated by %.3e of the load at a contact node (tolerance %.0e: a friction force beyond MU x the pressure, a sticking node that slipped, or a slip along its friction force); the active set did not settle (raise -snes_max_it or check -contact_c)", (double)v->coulomb, M2D_VERIFY_TOL);
  PetscCheck(v->complementarity <= M2D_VERIFY_TOL, comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its contact check: complementarity %.3e of the load (tolerance %.0e: a negative pressure, a penetration or both at one node); the active set did not settle (raise -snes_max_it or check -contact_c)", (double)v->complementarity, M2D_VERIFY_TOL);
  PetscFunctionReturn(0);
}

PetscErrorCode M2dVerifyStrain(const M2dProblem *pb, Vec u, M2dVerification *v)
{
  const M2dMesh *m    = &pb->mesh;
  MPI_Comm       comm = PetscObjectComm((PetscObject)u);
  PetscInt       nc = m->cEnd - m->cStart, cw = -1;
  PetscReal     *e, scale = pb->units.U / pb->units.L; /* a reference strain in the user's */
  M2dMeshArrays  ar;
  struct {
    double      value;
    PetscMPIInt rank;
  } worst = {0, 0};
  double      where[4] = {0, 0, 0, 0}; /* centre x, y of the cell, body, rotation (1) or strain (0) */
  const char *body;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &worst.rank));
  PetscCall(PetscMalloc1(2 * nc + 1, &e));
  PetscCall(ElasticityCellStrain(m, &pb->s, u, e));
  for (PetscInt k = 0; k < 2 * nc; k++)
    if (!(e[k] * scale <= worst.value)) { /* NaN counts as the worst */
      worst.value = PetscIsInfOrNanReal(e[k] * scale) ? PETSC_INFINITY : e[k] * scale;
      cw          = k;
    }
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  if (cw >= 0) {
    PetscReal xy[8];
    MeshCellCoordinates(m, ar.ca, ar.cs, m->cStart + cw / 2, xy);
    where[0] = 0.25 * (xy[0] + xy[2] + xy[4] + xy[6]) * pb->units.L;
    where[1] = 0.25 * (xy[1] + xy[3] + xy[5] + xy[7]) * pb->units.L;
    where[2] = (double)m->cellbody[cw / 2];
    where[3] = cw % 2;
  }
  PetscCall(MeshArraysClose(&ar));
  PetscCall(PetscFree(e));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm));
  PetscCallMPI(MPI_Bcast(where, 4, MPI_DOUBLE, worst.rank, comm));
  v->strain_max = worst.value;
  if (worst.value <= M2D_STRAIN_WARN) PetscFunctionReturn(0);
  body = pb->s.body[(PetscInt)where[2]].name;
  PetscCheck(worst.value <= pb->s.strain_limit, comm, PETSC_ERR_USER_INPUT, "body '%s' %s %.3g%s at (%g, %g), more than -strain_limit %g: small-strain theory does not hold there (the answer would be off by about as much); lower the loads, the prescribed displacements or the initial overlap, or make the body stiffer (-%s_E)", body,
             where[3] ? "rotates by" : "strains by", where[3] ? worst.value : 100 * worst.value, where[3] ? " rad" : "%", where[0], where[1], (double)pb->s.strain_limit, body);
  PetscCall(PetscPrintf(comm, "warning: body '%s' %s %.3g%s at (%g, %g): small-strain theory is off by about as much (refused above -strain_limit %g)\n", body, where[3] ? "rotates by" : "strains by", where[3] ? worst.value : 100 * worst.value, where[3] ? " rad" : "%", where[0], where[1], (double)pb->s.strain_limit));
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
