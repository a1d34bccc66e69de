/* verify.c - the answer's own checks (see verify.h). */
#include "verify.h"
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

/* max over the multipliers of -lambda, -gap and |lambda gap| (reference units) */
static PetscErrorCode Complementarity(const M2dProblem *pb, const M2dSolution *sol, PetscReal *worst)
{
  const M2dKKT      *kkt = &pb->kkt;
  Vec                gm;
  const PetscScalar *l, *g;
  PetscInt           lo, hi;
  PetscReal          w = 0;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(kkt->r, &gm));
  PetscCall(MatMult(kkt->C, sol->u, gm)); /* C u - r = -g~ */
  PetscCall(VecAXPY(gm, -1.0, kkt->r));
  PetscCall(VecGetOwnershipRange(gm, &lo, &hi));
  PetscCall(VecGetArrayRead(sol->lam, &l));
  PetscCall(VecGetArrayRead(gm, &g));
  for (PetscInt j = lo; j < hi; j++) {
    PetscReal lam = PetscRealPart(l[j - lo]), gap = -PetscRealPart(g[j - lo]) / pb->contact.R.w[j];
    PetscReal c = PetscMax(PetscMax(-lam, -gap), PetscAbsReal(lam * gap));
    if (PetscIsInfOrNanReal(c)) c = PETSC_INFINITY;
    w = PetscMax(w, c);
  }
  PetscCall(VecRestoreArrayRead(gm, &g));
  PetscCall(VecRestoreArrayRead(sol->lam, &l));
  PetscCall(VecDestroy(&gm));
  PetscCallMPI(MPI_Allreduce(&w, worst, 1, MPIU_REAL, MPIU_MAX, PetscObjectComm((PetscObject)sol->u)));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dVerifyAnswer(const M2dProblem *pb, const M2dSolution *sol, M2dVerification *v)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)sol->u);

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_VERIFY], 0, 0, 0, 0));
  PetscCall(PetscMemzero(v, sizeof(*v)));
  PetscCall(Equilibrium(pb, sol, &v->residual_rel));
  if (sol->path == M2D_PATH_CONDENSED || sol->path == M2D_PATH_FULL) PetscCall(Complementarity(pb, sol, &v->complementarity));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_VERIFY], 0, 0, 0, 0));
  PetscCall(PetscPrintf(comm, "checks: equilibrium |K u + C^T lambda - f| / |f| = %.3e, complementarity %.3e (tolerance %.0e)\n", (double)v->residual_rel, (double)v->complementarity, M2D_VERIFY_TOL));
  if (v->residual_rel > M2D_VERIFY_TOL) {
    const M2dScene *s    = &pb->s;
    PetscInt        soft = 0, stiff = 0;
    for (PetscInt b = 1; b < s->nbody; b++) {
      if (s->body[b].E < s->body[soft].E) soft = b;
      if (s->body[b].E > s->body[stiff].E) stiff = b;
    }
    /* bodies of very different moduli: the soft body's displacements swamp the
     * stiff one's strains in round-off (S2, stiff body on contact over a soft
     * supported one: ratio 1e9 gives 1.9e-6); no solver option helps */
    PetscCheck(s->body[stiff].E <= 1e6 * s->body[soft].E, comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its equilibrium check: |K u + C^T lambda - f| = %.3e of |f| (tolerance %.0e); the moduli of '%s' and '%s' differ by a factor %.1e and round-off swamps the stiffer body's strains: bring -%s_E within 1e6 of -%s_E (a body a million times stiffer is rigid for the other)", (double)v->residual_rel, M2D_VERIFY_TOL, s->body[soft].name, s->body[stiff].name, (double)(s->body[stiff].E / s->body[soft].E), s->body[soft].name, s->body[stiff].name);
    SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its equilibrium check: |K u + C^T lambda - f| = %.3e of |f| (tolerance %.0e); the linear solves lost accuracy (try -kkt_path full or a better-conditioned scene: check E, nu and the supports)", (double)v->residual_rel, M2D_VERIFY_TOL);
  }
  PetscCheck(v->complementarity <= M2D_VERIFY_TOL, comm, PETSC_ERR_NOT_CONVERGED, "the answer fails its contact check: complementarity %.3e of the load (tolerance %.0e: a negative pressure, a penetration or both at one node); the active set did not settle (raise -snes_max_it or check -contact_c)", (double)v->complementarity, M2D_VERIFY_TOL);
  PetscFunctionReturn(0);
}
