/* problem.c - the mesh, contact and assembly stages (see problem.h). */
#include "problem.h"
#include "scenecheck.h"
#include "elasticity.h"
#include "logging.h"
#include "util.h"
#include "ordering.h"

#define M2D_ROUNDOFF_LIMIT 1e-6 /* largest stress round-off (of the load) accepted a priori */

/* Volumetric locking: in plane strain past nu = M2D_LOCKING_NU (lambda/mu = 9)
 * Q4 with full 2x2 integration is stiffer than it should be, the more so as
 * nu -> 0.5 (Hertz level 2, pressure error against sri's: 0.97x at nu 0.45,
 * 1.5x at 0.47, 2.2x at 0.48, 2.4x at 0.485, 3.1x at 0.49, 44x at 0.4999).
 * There the default integration is sri (selective reduced: the lambda part at
 * the centre); -q4_integration full given by the user runs, with a warning. */
static PetscErrorCode CheckLocking(MPI_Comm comm, M2dScene *s)
{
  PetscInt b, worst = 0;

  PetscFunctionBeginUser;
  if (s->plane != M2D_PLANE_STRAIN || s->sri) PetscFunctionReturn(0);
  for (b = 1; b < s->nbody; b++)
    if (s->body[b].nu > s->body[worst].nu) worst = b;
  if (!(s->body[worst].nu > M2D_LOCKING_NU)) PetscFunctionReturn(0);
  if (!s->integration_set) {
    s->sri = PETSC_TRUE; /* for every later mesh too */
    PetscCall(PetscPrintf(comm, "note: nu = %g (-%s_nu) > %g in plane strain: Q4 with selective reduced integration (-q4_integration sri; full 2x2 integration locks)\n", (double)s->body[worst].nu, s->body[worst].name, M2D_LOCKING_NU));
  } else if (!s->locking_warned) {
    s->locking_warned = PETSC_TRUE;
    PetscCall(PetscPrintf(comm, "warning: -q4_integration full with nu = %g (-%s_nu) > %g in plane strain: full 2x2 integration locks (volumetric locking: too stiff, by 2x in the contact pressure's error at nu = 0.48); -q4_integration sri cures it\n", (double)s->body[worst].nu, s->body[worst].name, M2D_LOCKING_NU));
  }
  PetscFunctionReturn(0);
}

/* Whatever the integration, near-incompressible stresses carry round-off of
 * order lambda/mu x machine epsilon (the volumetric part is lambda div u):
 * beyond 1e-6 of the load the answer cannot be vouched for. */
static PetscErrorCode CheckMaterials(MPI_Comm comm, M2dScene *s)
{
  PetscInt soft, stiff;

  PetscFunctionBeginUser;
  /* one stiffness matrix holds both bodies: a body softer than the other by
   * more than 1/eps has a stiffness below the other's round-off (E ratio 1e19
   * on S2: "cycling" on 1 rank, "singular" on 2; 1e309: MUMPS INFOG(1) = -9) */
  (void)SceneModuliRatio(s, &soft, &stiff);
  PetscCheck(s->body[stiff].E <= s->body[soft].E / PETSC_MACHINE_EPSILON, comm, PETSC_ERR_USER_INPUT, "options -%s_E %g and -%s_E %g: the moduli differ by a factor 1e%+.0f, more than double precision resolves in one stiffness matrix (%.1e = 1/eps); bring them within 1e6 of each other (a body a million times stiffer is rigid for the other)", s->body[soft].name, (double)s->body[soft].E, s->body[stiff].name, (double)s->body[stiff].E, (double)(PetscLog10Real(s->body[stiff].E) - PetscLog10Real(s->body[soft].E)), (double)(1 / PETSC_MACHINE_EPSILON));
  if (s->plane != M2D_PLANE_STRAIN) PetscFunctionReturn(0);
  for (PetscInt b = 0; b < s->nbody; b++) {
    PetscReal nu = s->body[b].nu, ratio = 2 * nu / (1 - 2 * nu); /* lambda / mu */
    PetscReal roundoff = 10 * ratio * PETSC_MACHINE_EPSILON; /* measured on S2: 2-10 x ratio x eps */
    PetscCheck(roundoff < M2D_ROUNDOFF_LIMIT, comm, PETSC_ERR_USER_INPUT, "option -%s_nu: nu = %.17g in plane strain makes lambda/mu = %.3g: round-off alone puts stress errors of about %.1e of the load in a displacement formulation; use nu <= 0.4999999", s->body[b].name, (double)nu, (double)ratio, (double)roundoff);
  }
  PetscCall(CheckLocking(comm, s));
  PetscFunctionReturn(0);
}

PetscErrorCode ProblemCreate(MPI_Comm comm, M2dScene *user, MshMesh *msh, const char *what, M2dProblem *pb)
{
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(pb, sizeof(*pb)));
  pb->user = user;
  if (what) PetscCall(MeshCreateFromMsh(comm, user, msh, 1, what, &pb->mesh));
  else PetscCall(MeshCreate(comm, user, &pb->mesh));
  PetscCall(SceneReadMaterials(comm, user));
  PetscCall(SceneCheckOptions(comm, user)); /* typos of the per-body options */
  PetscCall(CheckMaterials(comm, user));
  PetscCall(SceneCheckMesh(comm, user, &pb->mesh));
  PetscCall(M2dUnitsCreate(&pb->mesh, user, &pb->units));
  PetscCall(M2dUnitsScaleMesh(&pb->mesh, 1.0 / pb->units.L));
  pb->s = *user;
  M2dUnitsScaleScene(&pb->units, &pb->s);
  PetscCallMPI(MPI_Comm_size(comm, &size));
  pb->s.kkt_ordering = M2dOrderingFor(pb->s.kkt_ordering, 2 * pb->mesh.nvert_global, size); /* auto resolved for this mesh */
  if (pb->s.hertz && !pb->s.hertz_load_set && pb->s.nload > 0 && pb->s.load[0].is_pressure) { /* a half model (its load on one side of x = 0): the full cylinder carries twice the load */
    PetscBool both;
    PetscCall(ElasticityPressureResultant(&pb->mesh, &pb->s.load[0], &pb->s.hertz_load, &both));
    if (!both) pb->s.hertz_load *= 2;
    PetscCheck(pb->s.hertz_load > 0, comm, PETSC_ERR_USER_INPUT, "option -hertz: the load on '%s' is not a compressive force (resultant %g)", user->load[0].group, (double)(pb->s.hertz_load / (both ? 1 : 2) * pb->units.S * pb->units.L));
  }
  PetscCall(SceneView(comm, user));
  PetscFunctionReturn(0);
}

/* -hertz: the pairs compared, once their surfaces are known: those of
 * -hertz_pairs (each must be curved), else every curved pair */
static PetscErrorCode HertzPairs(M2dProblem *pb)
{
  MPI_Comm comm = PetscObjectComm((PetscObject)pb->mesh.dm);
  PetscInt first = -1;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < pb->s.npair; k++) {
    M2dPair  *p = &pb->s.pair[k];
    PetscBool curved = ContactPairCurved(&pb->contact.pair[k]);
    PetscCheck(!p->hertz || curved, comm, PETSC_ERR_USER_INPUT, "option -hertz_pairs: pair %d '%s:%s' is flat on flat: Hertz compares a curved surface with another", (int)k + 1, p->nm, p->m);
    if (!pb->s.hertz_npairs) p->hertz = curved;
    if (p->hertz && first < 0) first = k;
  }
  PetscCheck(first >= 0, comm, PETSC_ERR_USER_INPUT, "option -hertz: no pair has a curved surface (Hertz compares a cylinder with a surface; name the pairs with -hertz_pairs)");
  PetscFunctionReturn(0);
}

/* K's near-null space: the rigid-body modes of the bodies together (an AMG's
 * aggregates lie in one body), in the frames' coordinates where supports
 * are inclined (frames.h) */
static PetscErrorCode NearNullSpace(M2dProblem *pb)
{
  MatNullSpace sp;

  PetscFunctionBeginUser;
  PetscCall(MeshRigidBodyModes(&pb->mesh, PETSC_FALSE, &sp));
  if (pb->frames.any) { /* T^T z, still orthonormal (T is orthogonal per vertex) */
    const Vec   *z;
    Vec         *zr;
    PetscInt     n;
    MatNullSpace spr;
    PetscCall(MatNullSpaceGetVecs(sp, NULL, &n, &z));
    PetscCall(VecDuplicateVecs(z[0], n, &zr));
    for (PetscInt i = 0; i < n; i++) {
      PetscCall(VecCopy(z[i], zr[i]));
      PetscCall(M2dFramesRotateGlobal(&pb->frames, &pb->mesh, zr[i], PETSC_FALSE));
    }
    PetscCall(MatNullSpaceCreate(PetscObjectComm((PetscObject)pb->K), PETSC_FALSE, n, zr, &spr));
    PetscCall(VecDestroyVecs(n, &zr));
    PetscCall(MatNullSpaceDestroy(&sp));
    sp = spr;
  }
  PetscCall(MatSetNearNullSpace(pb->K, sp));
  PetscCall(MatNullSpaceDestroy(&sp));
  PetscFunctionReturn(0);
}

/* a vertex whose supports contradict each other (frames.h: its values NaN;
 * before, the first -dirichlet entry won, silently): one line naming it */
static PetscErrorCode CheckSupports(const M2dProblem *pb)
{
  const M2dMesh *m    = &pb->mesh;
  MPI_Comm       comm = PetscObjectComm((PetscObject)m->dm);
  struct {
    double      bad;
    PetscMPIInt rank;
  } any = {0, 0};
  double        xy[2] = {0, 0};
  M2dMeshArrays ar;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &any.rank));
  PetscCall(MeshArraysOpen(m, NULL, &ar));
  for (PetscInt v = 0; v < m->vEnd - m->vStart && !any.bad; v++)
    if (PetscIsInfOrNanReal(pb->frames.value[2 * v]) || PetscIsInfOrNanReal(pb->frames.value[2 * v + 1])) {
      PetscInt off;
      PetscCall(PetscSectionGetOffset(ar.cs, m->vStart + v, &off));
      xy[0]   = PetscRealPart(ar.ca[off]) * pb->units.L;
      xy[1]   = PetscRealPart(ar.ca[off + 1]) * pb->units.L;
      any.bad = 1;
    }
  PetscCall(MeshArraysClose(&ar));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm));
  if (!any.bad) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Bcast(xy, 2, MPI_DOUBLE, any.rank, comm));
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "option -dirichlet: the vertex at (%g, %g) is given two different displacements along one direction by groups that meet there; give it one value", xy[0], xy[1]);
}

/* A load history: each later stage's loads and support values, lifted like
 * the scene's (whose case 0 is copied once eliminated) */
static PetscErrorCode LoadCases(M2dProblem *pb)
{
  const M2dScene *s = &pb->s;

  PetscFunctionBeginUser;
  if (s->nstage == 1 && s->stage_steps[0] == 1) PetscFunctionReturn(0);
  pb->ncase = s->nstage;
  PetscCall(VecDuplicateVecs(pb->f, pb->ncase, &pb->fcase));
  PetscCall(VecDuplicateVecs(pb->f, pb->ncase, &pb->ubccase));
  for (PetscInt k = 1; k < pb->ncase; k++) {
    M2dFrames    fr;
    PetscInt     n, *rows;
    PetscScalar *vals;
    PetscCall(M2dFramesStage(&pb->mesh, s, k, &pb->frames, &fr));
    PetscCall(ElasticityDirichletRows(&pb->mesh, s, &fr, &n, &rows, &vals));
    PetscCall(M2dFramesDestroy(&fr));
    PetscCall(ElasticityStageLoad(&pb->mesh, s, &pb->frames, k, pb->fcase[k]));
    PetscCall(ElasticityLiftDirichlet(pb->K, pb->fcase[k], pb->ubccase[k], n, rows, vals));
    PetscCall(PetscFree(rows));
    PetscCall(PetscFree(vals));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ProblemSetLoad(M2dProblem *pb, PetscInt stage, PetscInt step)
{
  PetscFunctionBeginUser;
  if (!pb->ncase) PetscFunctionReturn(0); /* one step: f and ubc are the scene's */
  PetscCall(VecZeroEntries(pb->f));
  PetscCall(VecZeroEntries(pb->ubc));
  for (PetscInt k = 0; k <= stage; k++) {
    PetscReal a = k < stage ? 1.0 : (PetscReal)step / (PetscReal)pb->s.stage_steps[stage];
    PetscCall(VecAXPY(pb->f, a, pb->fcase[k]));
    PetscCall(VecAXPY(pb->ubc, a, pb->ubccase[k]));
  }
  PetscFunctionReturn(0);
}

/* K (with room for C^T C, block size 2, rigid-body modes), f, the supports eliminated */
static PetscErrorCode Assemble(M2dProblem *pb)
{
  M2dMesh     *m = &pb->mesh;
  PetscScalar   *dvals;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_PREALLOC], 0, 0, 0, 0));
  if (pb->has_contact) PetscCall(MeshCreateMatrix(m, pb->contact.R.n, pb->contact.R.ptr, pb->contact.R.col, &pb->K));
  else PetscCall(MeshCreateMatrix(m, 0, NULL, NULL, &pb->K));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_PREALLOC], 0, 0, 0, 0));
  PetscCall(DMCreateGlobalVector(m->dm, &pb->f));
  PetscCall(VecDuplicate(pb->f, &pb->ubc));
  PetscCall(M2dFramesCreate(m, &pb->s, &pb->frames));
  PetscCall(CheckSupports(pb));
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_ELEMENTS], 0, 0, 0, 0));
  PetscCall(ElasticityAssemble(m, &pb->s, &pb->frames, pb->K, pb->f));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_ELEMENTS], 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_DIRICHLET], 0, 0, 0, 0));
  PetscCall(ElasticityDirichletRows(m, &pb->s, &pb->frames, &pb->ndir, &pb->drows, &dvals));
  /* dvals is freed whatever happens (a body held by nothing, the commonest bad
   * input, lost it: valgrind 48-192 bytes) */
  ierr = M2dSupportsCreate(m, &pb->s, &pb->frames, pb->ndir, pb->drows, &pb->supports);
  if (!ierr) ierr = LoadCases(pb); /* K as assembled: before the elimination */
  if (!ierr) ierr = ElasticityApplyDirichlet(pb->K, pb->f, pb->ubc, pb->ndir, pb->drows, dvals);
  PetscCall(PetscFree(dvals));
  PetscCall(ierr);
  if (pb->ncase) {
    PetscCall(VecCopy(pb->f, pb->fcase[0]));
    PetscCall(VecCopy(pb->ubc, pb->ubccase[0]));
  }
  PetscCall(M2dSupportsCheck(&pb->supports, PetscObjectComm((PetscObject)m->dm), &pb->s, pb->has_contact ? &pb->contact : NULL, NULL, NULL));
  PetscCall(NearNullSpace(pb));
  PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_DIRICHLET], 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode ProblemSetUp(M2dProblem *pb, const M2dSolverChoice *choice, PetscLogStage contact_stage, PetscLogStage assembly_stage, double *t_contact, double *t_assembly)
{
  PetscFunctionBeginUser;
  pb->has_contact = (PetscBool)(pb->s.npair > 0);
  PetscCall(PetscLogStagePush(contact_stage));
  *t_contact = M2dWallTime();
  if (pb->has_contact) {
    PetscCall(ContactSetup(&pb->mesh, &pb->s, pb->units.L, &pb->contact));
    /* the geometric gap from scaled coordinates is g0 / L^2; in reference units it is g0 / (L U) */
    for (PetscInt j = 0; j < pb->contact.R.n; j++) pb->contact.R.g0[j] *= pb->units.L / pb->units.U;
    if (pb->s.hertz) PetscCall(HertzPairs(pb));
  }
  *t_contact = M2dWallTime() - *t_contact;
  PetscCall(PetscLogStagePop());

  PetscCall(PetscLogStagePush(assembly_stage));
  *t_assembly = M2dWallTime();
  PetscCall(Assemble(pb));
  if (pb->has_contact) {
    PetscCall(PetscLogEventBegin(M2dEvent[M2D_EV_KKT], 0, 0, 0, 0));
    PetscCall(M2dFramesRotateRows(&pb->frames, &pb->mesh, &pb->contact.R, &pb->Rkkt));
    PetscCall(KKTCreate(choice->kkt_mat, choice->kkt_augment, choice->path == M2D_PATH_CONDENSED, &pb->Rkkt, pb->contact.nnormal < pb->contact.R.n ? pb->contact.partner : NULL, pb->K, pb->f, pb->ubc, pb->ndir, pb->drows, &pb->kkt));
    PetscCall(PetscLogEventEnd(M2dEvent[M2D_EV_KKT], 0, 0, 0, 0));
  }
  *t_assembly = M2dWallTime() - *t_assembly;
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode ProblemDestroy(M2dProblem *pb)
{
  PetscFunctionBeginUser;
  if (pb->has_contact) {
    PetscCall(ContactDestroy(&pb->contact));
    PetscCall(KKTDestroy(&pb->kkt));
    PetscCall(ContactRowsDestroy(&pb->Rkkt));
  }
  PetscCall(PetscFree(pb->drows));
  PetscCall(PetscFree(pb->warm));
  if (pb->ncase) {
    PetscCall(VecDestroyVecs(pb->ncase, &pb->fcase));
    PetscCall(VecDestroyVecs(pb->ncase, &pb->ubccase));
  }
  PetscCall(M2dFramesDestroy(&pb->frames));
  PetscCall(M2dSupportsDestroy(&pb->supports));
  PetscCall(VecDestroy(&pb->ubc));
  PetscCall(VecDestroy(&pb->f));
  PetscCall(MatDestroy(&pb->K));
  PetscCall(MeshDestroy(&pb->mesh));
  PetscFunctionReturn(0);
}

const char *ProblemPathSays(const M2dScene *s, M2dSolverPath path)
{
  if (s->kkt_path == M2D_KKT_PATH_ITERATIVE && path == M2D_PATH_LINEAR) return "on the linear path (no contact pair) with -kkt_path iterative (one CG + AMG solve, options under -iterative_)";
  if (s->kkt_path == M2D_KKT_PATH_ITERATIVE && path == M2D_PATH_TIED) return "on the tied path (-contact_unilateral false) with -kkt_path iterative (one CG + AMG solve, options under -iterative_)";
  switch (path) {
  case M2D_PATH_LINEAR:
    return "on the linear path (no contact pair: one linear solve, no active set)";
  case M2D_PATH_TIED:
    return "on the tied path (-contact_unilateral false: one KKT solve, no active set)";
  case M2D_PATH_CONDENSED:
    return "on the condensed path (MUMPS called by the program, each active-set step by a dense LU)";
  case M2D_PATH_FULL:
    return "on the full path (the KKT matrix by PETSc's KSP and PC, refactored each step)";
  default:
    return "on the iterative path (each step by CG + AMG, options under -iterative_)";
  }
}
