/* adapt.c - the adaptive loop (see adapt.h). */
#include "adapt.h"
#include "options.h"
#include "remesh.h"
#include "step.h"
#include "util.h"
#include <string.h>

PetscErrorCode AdaptReadOptions(MPI_Comm comm, const M2dScene *s, M2dAdaptOptions *ao)
{
  const char *quads[] = {"subdivide", "fullquad", "blossom", "simple"}; /* order of M2dRemeshQuads */
  const char *goals[] = {"energy", "contact"};
  char       *num[M2D_ADAPT_MAX_NUMBERS];
  PetscInt    nnum = M2D_ADAPT_MAX_NUMBERS;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(ao, sizeof(*ao)));
  ao->target    = 1e-2;
  ao->max_steps = 8;
  ao->max_dofs  = 1000000;
  ao->quads     = M2D_QUADS_SUBDIVIDE;
  ao->grading   = 1.2;
  PetscOptionsBegin(comm, NULL, "Adaptive meshes", "");
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-adapt", "adapt the mesh of the scene's .geo (-geo) to the error estimate", ao->enabled, &ao->enabled));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-adapt_target", "stop when the relative error estimate is below this", ao->target, &ao->target, NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-adapt_max_steps", "at most this many meshes", ao->max_steps, &ao->max_steps, NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-adapt_max_dofs", "stop before a mesh would have more dofs than this", ao->max_dofs, &ao->max_dofs, NULL));
  PetscCall(M2dOptionsEList(PetscOptionsObject, "-adapt_goal", "what the meshes are adapted to: energy (the energy-norm error) or contact (the contact pressure: dual-weighted)", goals, 2, &ao->goal));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-adapt_grading", "sizes grow by at most this factor per element (1: no limit)", ao->grading, &ao->grading, NULL));
  PetscCall(M2dOptionsEList(PetscOptionsObject, "-adapt_quads", "how gmsh makes quads from the size field: subdivide, fullquad, blossom, simple (faster, big meshes)", quads, 4, &ao->quads));
  PetscCall(M2dOptionsStringArray(PetscOptionsObject, "-geo_setnumber", "parameters of the .geo as NAME=VALUE, comma separated (gmsh's -setnumber); default: none", M2D_ADAPT_MAX_NUMBERS, num, &nnum));
  PetscOptionsEnd();
  PetscCall(M2dOptionsRaise(comm));
  for (PetscInt i = 0; i < nnum; i++) {
    char     *eq = strchr(num[i], '='), *end = NULL;
    PetscBool ok = (PetscBool)(eq != NULL && eq != num[i] && (size_t)(eq - num[i]) < sizeof(ao->number_name[0]));
    if (ok) {
      ao->number_value[i] = strtod(eq + 1, &end);
      ok                  = (PetscBool)(end != eq + 1 && *end == 0 && PetscIsNormalReal(PetscAbsReal(ao->number_value[i]) + 1));
      *eq                 = 0;
      PetscCall(PetscStrncpy(ao->number_name[i], num[i], sizeof(ao->number_name[i])));
      *eq = '=';
    }
    if (!ok) PetscCall(M2dOptionsDefer("option -geo_setnumber: '%s' is not NAME=VALUE", num[i]));
  }
  for (PetscInt i = 0; i < nnum; i++) PetscCall(PetscFree(num[i]));
  PetscCall(M2dOptionsRaise(comm));
  ao->nnumber = nnum;
  PetscCheck(ao->target > 0 && ao->target < 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_target: %g must be in (0, 1)", (double)ao->target);
  PetscCheck(ao->max_steps >= 1 && ao->max_steps <= M2D_ADAPT_MAX_STEPS, comm, PETSC_ERR_USER_INPUT, "option -adapt_max_steps: %" PetscInt_FMT " must be in [1, %d]", ao->max_steps, M2D_ADAPT_MAX_STEPS);
  PetscCheck(ao->grading >= 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_grading: %g must be >= 1", (double)ao->grading);
  PetscCheck(ao->max_dofs >= 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_max_dofs: %" PetscInt_FMT " must be >= 1", ao->max_dofs);
  PetscCheck(!ao->enabled || s->geo[0], comm, PETSC_ERR_USER_INPUT, "option -adapt: needs the scene's .geo (-geo FILE)");
  PetscFunctionReturn(0);
}

/* the previous mesh on rank 0, in the user's units, with the new size per
 * quad (the size field's h_new): what the remesher's size field is built on.
 * Quads carry the physical tag of their body's surface (bodytag). */
typedef struct {
  MshMesh  msh;
  double  *hcell;
} PrevMesh;

static void PrevMeshFree(PrevMesh *p)
{
  MshFree(&p->msh);
  free(p->hcell);
  p->hcell = NULL;
}

/* what each rank sends rank 0 about its cells and its owned vertices (all
 * doubles: one MPI datatype) */
typedef struct {
  double vert[4]; /* global vertex numbers */
  double body;
  double hnew;    /* the new size, user units */
} CellRecord;
typedef struct {
  double id, x, y; /* global vertex number, user coordinates */
} VertexRecord;
#define M2D_DOUBLES(T) ((int)(sizeof(T) / sizeof(double)))

static PetscErrorCode PackRecords(const M2dStep *st, CellRecord *cr, VertexRecord *vr, PetscInt *nown)
{
  const M2dMesh     *m = &st->pb.mesh;
  PetscInt           nlc = m->cEnd - m->cStart;
  PetscSection       gsec, cs;
  Vec                cl;
  const PetscScalar *ca;
  PetscReal         *h, L = st->pb.units.L;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(PetscMalloc1(nlc + 1, &h));
  PetscCall(M2dCellSizes(m, h));
  for (PetscInt c = 0; c < nlc; c++) {
    for (int j = 0; j < 4; j++) {
      PetscInt g;
      PetscCall(PetscSectionGetOffset(gsec, m->cellverts[4 * c + j], &g));
      cr[c].vert[j] = (double)((g < 0 ? -(g + 1) : g) / 2);
    }
    cr[c].body = (double)m->cellbody[c];
    cr[c].hnew = st->sol.eta[M2D_ETA_FIELDS * c + 2] * h[c] * L; /* h_new / h, times h */
  }
  PetscCall(PetscFree(h));
  PetscCall(VecGetArrayRead(cl, &ca));
  *nown = 0;
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt g, off;
    PetscCall(PetscSectionGetOffset(gsec, v, &g));
    if (g < 0) continue;
    PetscCall(PetscSectionGetOffset(cs, v, &off));
    vr[*nown].id = (double)(g / 2);
    vr[*nown].x  = PetscRealPart(ca[off]) * L;
    vr[*nown].y  = PetscRealPart(ca[off + 1]) * L;
    (*nown)++;
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscFunctionReturn(0);
}

/* gather n records of `width` doubles to rank 0 (*all there, *ntot their count) */
static PetscErrorCode GatherDoubles(MPI_Comm comm, const double *mine, PetscInt n, int width, double **all, PetscInt *ntot)
{
  PetscMPIInt rank, size, cnt, *counts = NULL, *displs = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMPIIntCast(width * n, &cnt));
  *all  = NULL;
  *ntot = 0;
  if (rank == 0) PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCallMPI(MPI_Gather(&cnt, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
  if (rank == 0) {
    displs[0] = 0;
    for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + counts[r];
    PetscCall(PetscMalloc1(displs[size] + 1, all));
    *ntot = displs[size] / width;
  }
  PetscCallMPI(MPI_Gatherv(mine, cnt, MPI_DOUBLE, *all, counts, displs, MPI_DOUBLE, 0, comm));
  if (rank == 0) PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(0);
}

/* the previous mesh on rank 0 (user units), with the new size per quad and the
 * physical tag of each quad's body (bodytag) */
static PetscErrorCode GatherPrevMesh(const M2dStep *st, const int bodytag[], PrevMesh *prev)
{
  const M2dMesh *m = &st->pb.mesh;
  MPI_Comm       comm = PetscObjectComm((PetscObject)m->dm);
  PetscInt       nlc = m->cEnd - m->cStart, nown = 0, nc = 0, nv = 0;
  CellRecord    *cr, *call;
  VertexRecord  *vr, *vall;
  MshMesh       *q = &prev->msh;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(nlc + 1, &cr, m->vEnd - m->vStart + 1, &vr));
  PetscCall(PackRecords(st, cr, vr, &nown));
  PetscCall(GatherDoubles(comm, (double *)cr, nlc, M2D_DOUBLES(CellRecord), (double **)&call, &nc));
  PetscCall(GatherDoubles(comm, (double *)vr, nown, M2D_DOUBLES(VertexRecord), (double **)&vall, &nv));
  PetscCall(PetscFree2(cr, vr));
  if (call) { /* rank 0 */
    PetscCall(PetscMemzero(q, sizeof(*q)));
    q->nnode    = m->nvert_global;
    q->nquad    = nc;
    q->xy       = (double *)malloc((size_t)(2 * q->nnode + 1) * sizeof(double));
    q->quad     = (long *)malloc((size_t)(4 * nc + 1) * sizeof(long));
    q->quadtag  = (long *)malloc((size_t)(nc + 1) * sizeof(long));
    q->quadphys = (int *)malloc((size_t)(nc + 1) * sizeof(int));
    prev->hcell = (double *)malloc((size_t)(nc + 1) * sizeof(double));
    PetscCheck(q->xy && q->quad && q->quadtag && q->quadphys && prev->hcell, PETSC_COMM_SELF, PETSC_ERR_MEM, "out of memory gathering the mesh for remeshing");
    for (PetscInt i = 0; i < nv; i++) q->xy[2 * (long)vall[i].id] = vall[i].x, q->xy[2 * (long)vall[i].id + 1] = vall[i].y;
    for (PetscInt c = 0; c < nc; c++) {
      for (int j = 0; j < 4; j++) q->quad[4 * c + j] = (long)call[c].vert[j];
      q->quadtag[c]  = c + 1;
      q->quadphys[c] = bodytag[(int)call[c].body];
      prev->hcell[c] = call[c].hnew;
    }
  }
  PetscCall(PetscFree(call));
  PetscCall(PetscFree(vall));
  PetscFunctionReturn(0);
}

/* a binary heap of (size, cell) for the gradation sweep */
typedef struct {
  PetscInt  n;
  PetscReal *key;
  PetscInt  *cell;
} Heap;

static void HeapPush(Heap *h, PetscReal key, PetscInt cell)
{
  PetscInt i = h->n++;
  while (i > 0 && h->key[(i - 1) / 2] > key) {
    h->key[i]  = h->key[(i - 1) / 2];
    h->cell[i] = h->cell[(i - 1) / 2];
    i          = (i - 1) / 2;
  }
  h->key[i]  = key;
  h->cell[i] = cell;
}

static void HeapPop(Heap *h, PetscReal *key, PetscInt *cell)
{
  PetscReal k = h->key[--h->n];
  PetscInt  c = h->cell[h->n], i = 0;
  *key        = h->key[0];
  *cell       = h->cell[0];
  for (;;) {
    PetscInt j = 2 * i + 1;
    if (j >= h->n) break;
    if (j + 1 < h->n && h->key[j + 1] < h->key[j]) j++;
    if (h->key[j] >= k) break;
    h->key[i]  = h->key[j];
    h->cell[i] = h->cell[j];
    i          = j;
  }
  h->key[i]  = k;
  h->cell[i] = c;
}

/* Gradation (rank 0): sizes may grow by at most a factor g per element, i.e.
 * h_K <= h_N + (g - 1) |c_K - c_N| over cells sharing a vertex, enforced by a
 * Dijkstra sweep from the smallest sizes. A steep jump from a fine zone to a
 * coarse one makes the far field stiffer than the body and moves the edge of
 * the contact zone; a gentle grading costs few cells. */
static PetscErrorCode Grade(PrevMesh *prev, PetscReal g)
{
  MshMesh   *q = &prev->msh;
  PetscInt   nc = (PetscInt)q->nquad, nv = (PetscInt)q->nnode, *vptr, *vadj;
  PetscReal *cen;
  Heap       hp;
  PetscBool *done;

  PetscFunctionBeginUser;
  if (!(g > 1) || nc == 0) PetscFunctionReturn(0);
  PetscCall(PetscCalloc2(nv + 1, &vptr, 4 * nc + 1, &vadj));
  PetscCall(PetscMalloc2(2 * nc + 1, &cen, nc + 1, &done));
  for (PetscInt c = 0; c < 4 * nc; c++) vptr[q->quad[c] + 1]++;
  for (PetscInt v = 0; v < nv; v++) vptr[v + 1] += vptr[v];
  for (PetscInt c = 0; c < 4 * nc; c++) vadj[vptr[q->quad[c]]++] = c / 4;
  for (PetscInt v = nv; v > 0; v--) vptr[v] = vptr[v - 1];
  vptr[0] = 0;
  for (PetscInt c = 0; c < nc; c++) {
    cen[2 * c] = cen[2 * c + 1] = 0;
    for (int k = 0; k < 4; k++) cen[2 * c] += 0.25 * q->xy[2 * q->quad[4 * c + k]], cen[2 * c + 1] += 0.25 * q->xy[2 * q->quad[4 * c + k] + 1];
    done[c] = PETSC_FALSE;
  }
  PetscCall(PetscMalloc2(4 * 8 * nc + nc + 1, &hp.key, 4 * 8 * nc + nc + 1, &hp.cell));
  hp.n = 0;
  for (PetscInt c = 0; c < nc; c++) HeapPush(&hp, prev->hcell[c], c);
  while (hp.n > 0) {
    PetscReal h;
    PetscInt  c;
    HeapPop(&hp, &h, &c);
    if (done[c] || h > prev->hcell[c]) continue;
    done[c] = PETSC_TRUE;
    for (int k = 0; k < 4; k++) {
      PetscInt v = q->quad[4 * c + k];
      for (PetscInt a = vptr[v]; a < vptr[v + 1]; a++) {
        PetscInt  o  = vadj[a];
        PetscReal hn = h + (g - 1) * PetscSqrtReal(PetscSqr(cen[2 * o] - cen[2 * c]) + PetscSqr(cen[2 * o + 1] - cen[2 * c + 1]));
        if (!done[o] && hn < prev->hcell[o] && q->quadphys[o] == q->quadphys[c]) {
          prev->hcell[o] = hn;
          if (hp.n < 4 * 8 * nc + nc) HeapPush(&hp, hn, o);
        }
      }
    }
  }
  PetscCall(PetscFree2(hp.key, hp.cell));
  PetscCall(PetscFree2(cen, done));
  PetscCall(PetscFree2(vptr, vadj));
  PetscFunctionReturn(0);
}

/* rank 0: the .geo meshed by gmsh, with the previous mesh's size field from step 1 on */
static PetscErrorCode Remesh(MPI_Comm comm, const M2dScene *s, const M2dAdaptOptions *ao, const PrevMesh *prev, PetscInt step, MshMesh *msh, double *seconds)
{
  PetscMPIInt    rank;
  char           err[1024] = "";
  M2dRemeshStats stats;
  const char    *names[M2D_ADAPT_MAX_NUMBERS];
  double         values[M2D_ADAPT_MAX_NUMBERS];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscMemzero(msh, sizeof(*msh)));
  *seconds = 0;
  if (rank == 0) {
    M2dRemeshInput in;
    PetscCall(PetscMemzero(&in, sizeof(in)));
    for (PetscInt i = 0; i < ao->nnumber; i++) {
      names[i]  = ao->number_name[i];
      values[i] = ao->number_value[i];
    }
    in.geo     = s->geo;
    in.nnumber = (int)ao->nnumber;
    in.names   = names;
    in.values  = values;
    in.quads   = (M2dRemeshQuads)ao->quads;
    if (step > 0) {
      in.prev  = &prev->msh;
      in.hcell = prev->hcell;
    }
    if (M2dRemesh(&in, msh, &stats, err, sizeof(err))) MshFree(msh);
    else *seconds = stats.seconds_total;
  }
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  PetscFunctionReturn(0);
}

/* the physical tag of every body's surface in the remeshed .geo (rank 0) */
static PetscErrorCode BodyTags(MPI_Comm comm, const M2dScene *s, const MshMesh *msh, int bodytag[])
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  for (PetscInt b = 0; b < s->nbody; b++) {
    bodytag[b] = -1;
    if (rank == 0)
      for (int i = 0; i < msh->nphys; i++)
        if (msh->phys[i].dim == 2 && !strcmp(msh->phys[i].name, s->body[b].name)) bodytag[b] = msh->phys[i].tag;
  }
  PetscFunctionReturn(0);
}

/* the estimate the loop stops on: the goal's when there is one */
static PetscReal AdaptEstimate(const M2dStep *st)
{
  return st->fig.goal_estimate >= 0 ? st->fig.goal_estimate : st->fig.est.estimate_rel;
}

static void StepLine(MPI_Comm comm, PetscInt k, const M2dStep *st, double seconds)
{
  char known[128] = "";
  if (st->fig.pressure_l2_rel >= 0) PetscSNPrintf(known, sizeof(known), ", pressure error %.3e", (double)st->fig.pressure_l2_rel);
  else if (st->fig.true_error_rel >= 0) PetscSNPrintf(known, sizeof(known), ", error %.3e (effectivity %.3f)", (double)st->fig.true_error_rel, (double)st->fig.effectivity);
  PetscPrintf(comm, "adapt step %" PetscInt_FMT ": %" PetscInt_FMT " dofs, estimate %.3e%s, %" PetscInt_FMT " active-set steps, %.3f s\n", k, 2 * st->pb.mesh.nvert_global, (double)AdaptEstimate(st), known, st->pb.has_contact ? st->sol.as.iterations : 0, seconds);
}

/* what the summary's "adapt" list keeps of each step */
typedef struct {
  PetscInt  dofs, iterations;
  PetscReal estimate, pressure_l2_rel, error_rel, effectivity, seconds, gmsh;
} StepRecord;

static void Record(StepRecord *r, const M2dStep *st, double seconds, double gmsh)
{
  r->dofs            = 2 * st->pb.mesh.nvert_global;
  r->iterations      = st->pb.has_contact ? st->sol.as.iterations : 0;
  r->estimate        = AdaptEstimate(st);
  r->pressure_l2_rel = st->fig.pressure_l2_rel;
  r->error_rel       = st->fig.true_error_rel;
  r->effectivity     = st->fig.effectivity;
  r->seconds         = seconds;
  r->gmsh            = gmsh;
}

static PetscErrorCode WriteRecords(M2dSummary *sum, PetscInt n, const StepRecord *r)
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < n; k++) {
    PetscCall(M2dSummaryListInt(sum, "adapt", k, "dofs", r[k].dofs));
    PetscCall(M2dSummaryListReal(sum, "adapt", k, "error_estimate", r[k].estimate));
    if (r[k].pressure_l2_rel >= 0) PetscCall(M2dSummaryListReal(sum, "adapt", k, "pressure_l2_rel", r[k].pressure_l2_rel));
    if (r[k].error_rel >= 0) PetscCall(M2dSummaryListReal(sum, "adapt", k, "error_rel", r[k].error_rel));
    if (r[k].effectivity >= 0) PetscCall(M2dSummaryListReal(sum, "adapt", k, "effectivity", r[k].effectivity));
    PetscCall(M2dSummaryListInt(sum, "adapt", k, "iterations", r[k].iterations));
    PetscCall(M2dSummaryListReal(sum, "adapt", k, "seconds", r[k].seconds));
    PetscCall(M2dSummaryListReal(sum, "adapt", k, "seconds_gmsh", r[k].gmsh));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode AdaptRun(MPI_Comm comm, M2dScene *s, const M2dAdaptOptions *ao, const M2dEstimatorOptions *eo)
{
  PrevMesh        prev;
  M2dContactState state, *warm = NULL;
  M2dStep         st;
  StepRecord      rec[M2D_ADAPT_MAX_STEPS];
  PetscInt        nrec = 0;
  int             bodytag[M2D_MAX_BODIES];
  char            what[PETSC_MAX_PATH_LEN + 64];
  double          t_start = M2dWallTime();
  PetscErrorCode  ierr;

  PetscFunctionBeginUser;
  PetscCheck(eo->enabled, comm, PETSC_ERR_USER_INPUT, "option -adapt: needs the error estimate (-error_estimate 1)");
  PetscCall(PetscMemzero(&prev, sizeof(prev)));
  PetscCall(PetscMemzero(&state, sizeof(state)));
  for (PetscInt k = 0;; k++) {
    MshMesh  msh;
    double   t0 = M2dWallTime(), tgmsh = 0, seconds;
    PetscBool last;
    PetscCall(Remesh(comm, s, ao, &prev, k, &msh, &tgmsh));
    PrevMeshFree(&prev);
    PetscCall(PetscSNPrintf(what, sizeof(what), "%s (adapt step %" PetscInt_FMT ")", s->geo, k));
    ierr = M2dStepSolve(comm, s, &(M2dMeshSource){&msh, what}, warm, eo, &st);
    if (!ierr && k == 0) ierr = BodyTags(comm, s, &msh, bodytag);
    MshFree(&msh);
    if (ierr) { /* free what the loop holds, then raise */
      PetscCall(M2dStepDestroy(&st));
      PetscCall(ContactStateDestroy(&state));
      PetscCall(ierr);
    }
    seconds = M2dWallTime() - t0;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, comm));
    StepLine(comm, k, &st, seconds);
    Record(&rec[nrec++], &st, seconds, tgmsh);
    last = (PetscBool)(AdaptEstimate(&st) <= ao->target || k + 1 >= ao->max_steps);
    /* the next mesh must fit -adapt_max_dofs: the size field's expected cells, about one vertex (2 dofs) each */
    if (!last) last = (PetscBool)(2 * st.fig.expected_cells > ao->max_dofs);
    if (last) break;
    PetscCall(GatherPrevMesh(&st, bodytag, &prev));
    if (prev.hcell) PetscCall(Grade(&prev, ao->grading));
    PetscCall(ContactStateDestroy(&state));
    if (st.pb.has_contact) {
      PetscCall(ContactStateCreate(&st.pb.contact, &state));
      warm = &state;
    }
    PetscCall(M2dStepDestroy(&st));
  }
  PetscCall(WriteRecords(st.sum, nrec, rec));
  PetscCall(M2dSummaryReal(st.sum, "", "adapt_seconds", M2dWallTime() - t_start));
  PetscCall(M2dStepWrite(&st));
  PetscCall(M2dStepDestroy(&st));
  PetscCall(ContactStateDestroy(&state));
  PetscFunctionReturn(0);
}
