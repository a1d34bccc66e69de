/* adapt.c - the adaptive loop (see adapt.h). */
#include "adapt.h"
#include "remesh.h"
#include "step.h"
#include "util.h"
#include <string.h>

PetscErrorCode AdaptReadOptions(MPI_Comm comm, const M2dScene *s, M2dAdaptOptions *ao)
{
  const char *quads[] = {"subdivide", "fullquad", "blossom", "M2dRemeshQuads", "M2D_QUADS_", NULL};
  char       *num[16];
  PetscInt    nnum = 16;
  PetscBool   set;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(ao, sizeof(*ao)));
  ao->target    = 1e-2;
  ao->max_steps = 8;
  ao->max_dofs  = 1000000;
  ao->quads     = M2D_QUADS_SUBDIVIDE;
  PetscOptionsBegin(comm, NULL, "Adaptive meshes", "");
  PetscCall(PetscOptionsBool("-adapt", "adapt the mesh of the scene's .geo (-geo) to the error estimate", "", ao->enabled, &ao->enabled, NULL));
  PetscCall(PetscOptionsReal("-adapt_target", "stop when the relative error estimate is below this", "", ao->target, &ao->target, NULL));
  PetscCall(PetscOptionsInt("-adapt_max_steps", "at most this many meshes", "", ao->max_steps, &ao->max_steps, NULL));
  PetscCall(PetscOptionsInt("-adapt_max_dofs", "stop before a mesh would have more dofs than this", "", ao->max_dofs, &ao->max_dofs, NULL));
  PetscCall(PetscOptionsEnum("-adapt_quads", "how gmsh makes quads from the size field: subdivide (always all quads), fullquad, blossom", "", quads, (PetscEnum)ao->quads, (PetscEnum *)&ao->quads, NULL));
  PetscCall(PetscOptionsStringArray("-geo_setnumber", "parameters of the .geo as NAME=VALUE, comma separated (gmsh's -setnumber); default: none", "", num, &nnum, &set));
  PetscOptionsEnd();
  if (!set) nnum = 0;
  for (PetscInt i = 0; i < nnum; i++) {
    char *eq = strchr(num[i], '='), *end;
    PetscBool ok = (PetscBool)(eq != NULL && eq != num[i] && (size_t)(eq - num[i]) < sizeof(ao->number_name[0]));
    if (ok) {
      *eq                   = 0;
      ao->number_value[i]   = strtod(eq + 1, &end);
      ok                    = (PetscBool)(end != eq + 1 && *end == 0 && PetscIsNormalReal(PetscAbsReal(ao->number_value[i]) + 1));
      PetscCall(PetscStrncpy(ao->number_name[i], num[i], sizeof(ao->number_name[i])));
      *eq = '=';
    }
    if (!ok) {
      char bad[256];
      PetscCall(PetscStrncpy(bad, num[i], sizeof(bad)));
      for (PetscInt k = i; k < nnum; k++) PetscCall(PetscFree(num[k]));
      SETERRQ(comm, PETSC_ERR_USER_INPUT, "option -geo_setnumber: '%s' is not NAME=VALUE", bad);
    }
    PetscCall(PetscFree(num[i]));
  }
  ao->nnumber = nnum;
  if (!ao->enabled) PetscFunctionReturn(0);
  PetscCheck(s->geo[0], comm, PETSC_ERR_USER_INPUT, "option -adapt: needs the scene's .geo (-geo FILE)");
  PetscCheck(ao->target > 0 && ao->target < 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_target: %g must be in (0, 1)", (double)ao->target);
  PetscCheck(ao->max_steps >= 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_max_steps: %" PetscInt_FMT " must be >= 1", ao->max_steps);
  PetscCheck(ao->max_dofs >= 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_max_dofs: %" PetscInt_FMT " must be >= 1", ao->max_dofs);
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

/* per local cell: 4 global vertex numbers, the body, h_new; per owned vertex: its number and coordinates */
static PetscErrorCode GatherPrevMesh(const M2dStep *st, const int bodytag[], PrevMesh *prev)
{
  const M2dMesh     *m    = &st->pb.mesh;
  MPI_Comm           comm = PetscObjectComm((PetscObject)m->dm);
  PetscMPIInt        rank, size, nc, nv, *cc, *cd, *vc, *vd;
  PetscInt           nlc = m->cEnd - m->cStart, nown = 0, k = 0;
  PetscSection       gsec, cs;
  Vec                cl;
  const PetscScalar *ca;
  double            *cbuf, *vbuf, *call = NULL, *vall = NULL, L = st->pb.units.L;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(VecGetArrayRead(cl, &ca));
  PetscCall(PetscMalloc2(6 * nlc + 1, &cbuf, 3 * (m->vEnd - m->vStart) + 1, &vbuf));
  for (PetscInt c = 0; c < nlc; c++) {
    for (int j = 0; j < 4; j++) {
      PetscInt g;
      PetscCall(PetscSectionGetOffset(gsec, m->cellverts[4 * c + j], &g));
      cbuf[6 * c + j] = (double)((g < 0 ? -(g + 1) : g) / 2);
    }
    cbuf[6 * c + 4] = (double)m->cellbody[c];
    cbuf[6 * c + 5] = st->sol.eta[M2D_ETA_FIELDS * c + 2]; /* h_new / h, times h below */
  }
  {
    PetscReal *h;
    PetscCall(PetscMalloc1(nlc + 1, &h));
    PetscCall(M2dCellSizes(m, h));
    for (PetscInt c = 0; c < nlc; c++) cbuf[6 * c + 5] *= h[c] * L;
    PetscCall(PetscFree(h));
  }
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt g, off;
    PetscCall(PetscSectionGetOffset(gsec, v, &g));
    if (g < 0) continue;
    PetscCall(PetscSectionGetOffset(cs, v, &off));
    vbuf[3 * nown]     = (double)(g / 2);
    vbuf[3 * nown + 1] = PetscRealPart(ca[off]) * L;
    vbuf[3 * nown + 2] = PetscRealPart(ca[off + 1]) * L;
    nown++;
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCall(PetscMalloc4(size, &cc, size + 1, &cd, size, &vc, size + 1, &vd));
  PetscCall(PetscMPIIntCast(6 * nlc, &nc));
  PetscCall(PetscMPIIntCast(3 * nown, &nv));
  PetscCallMPI(MPI_Gather(&nc, 1, MPI_INT, cc, 1, MPI_INT, 0, comm));
  PetscCallMPI(MPI_Gather(&nv, 1, MPI_INT, vc, 1, MPI_INT, 0, comm));
  if (rank == 0) {
    cd[0] = vd[0] = 0;
    for (PetscMPIInt r = 0; r < size; r++) cd[r + 1] = cd[r] + cc[r], vd[r + 1] = vd[r] + vc[r];
    PetscCall(PetscMalloc2(cd[size] + 1, &call, vd[size] + 1, &vall));
  }
  PetscCallMPI(MPI_Gatherv(cbuf, nc, MPI_DOUBLE, call, cc, cd, MPI_DOUBLE, 0, comm));
  PetscCallMPI(MPI_Gatherv(vbuf, nv, MPI_DOUBLE, vall, vc, vd, MPI_DOUBLE, 0, comm));
  if (rank == 0) {
    MshMesh *q = &prev->msh;
    PetscCall(PetscMemzero(q, sizeof(*q)));
    q->nnode    = m->nvert_global;
    q->nquad    = m->ncell_global;
    q->xy       = (double *)malloc((size_t)(2 * q->nnode + 1) * sizeof(double));
    q->quad     = (long *)malloc((size_t)(4 * q->nquad + 1) * sizeof(long));
    q->quadtag  = (long *)malloc((size_t)(q->nquad + 1) * sizeof(long));
    q->quadphys = (int *)malloc((size_t)(q->nquad + 1) * sizeof(int));
    prev->hcell = (double *)malloc((size_t)(q->nquad + 1) * sizeof(double));
    PetscCheck(q->xy && q->quad && q->quadtag && q->quadphys && prev->hcell, PETSC_COMM_SELF, PETSC_ERR_MEM, "out of memory gathering the mesh for remeshing");
    for (PetscInt i = 0; i < vd[size] / 3; i++) {
      long g            = (long)vall[3 * i];
      q->xy[2 * g]     = vall[3 * i + 1];
      q->xy[2 * g + 1] = vall[3 * i + 2];
    }
    for (PetscInt c = 0; c < cd[size] / 6; c++, k++) {
      for (int j = 0; j < 4; j++) q->quad[4 * c + j] = (long)call[6 * c + j];
      q->quadtag[c]  = c + 1;
      q->quadphys[c] = bodytag[(int)call[6 * c + 4]];
      prev->hcell[c] = call[6 * c + 5];
    }
    PetscCall(PetscFree2(call, vall));
  }
  (void)k;
  PetscCall(PetscFree4(cc, cd, vc, vd));
  PetscCall(PetscFree2(cbuf, vbuf));
  PetscFunctionReturn(0);
}

/* rank 0: the .geo meshed by gmsh, with the previous mesh's size field from step 1 on */
static PetscErrorCode Remesh(MPI_Comm comm, const M2dScene *s, const M2dAdaptOptions *ao, const PrevMesh *prev, PetscInt step, MshMesh *msh, double *seconds)
{
  PetscMPIInt    rank;
  char           err[1024] = "";
  M2dRemeshStats stats;
  const char    *names[16];
  double         values[16];

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

static void StepLine(MPI_Comm comm, PetscInt k, const M2dStep *st, double seconds)
{
  char known[128] = "";
  if (st->fig.pressure_l2_rel >= 0) PetscSNPrintf(known, sizeof(known), ", pressure error %.3e", (double)st->fig.pressure_l2_rel);
  else if (st->fig.true_error_rel >= 0) PetscSNPrintf(known, sizeof(known), ", error %.3e (effectivity %.3f)", (double)st->fig.true_error_rel, (double)st->fig.effectivity);
  PetscPrintf(comm, "adapt step %" PetscInt_FMT ": %" PetscInt_FMT " dofs, estimate %.3e%s, %" PetscInt_FMT " active-set steps, %.3f s\n", k, 2 * st->pb.mesh.nvert_global, (double)st->fig.est.estimate_rel, known, st->pb.has_contact ? st->sol.as.iterations : 0, seconds);
}

static void Record(M2dSummary *list, PetscInt k, const M2dStep *st, double seconds)
{
  SummaryListInt(list, "adapt", k, "dofs", 2 * st->pb.mesh.nvert_global);
  SummaryListReal(list, "adapt", k, "error_estimate", st->fig.est.estimate_rel);
  if (st->fig.pressure_l2_rel >= 0) SummaryListReal(list, "adapt", k, "pressure_l2_rel", st->fig.pressure_l2_rel);
  if (st->fig.true_error_rel >= 0) SummaryListReal(list, "adapt", k, "error_rel", st->fig.true_error_rel);
  if (st->fig.effectivity >= 0) SummaryListReal(list, "adapt", k, "effectivity", st->fig.effectivity);
  SummaryListInt(list, "adapt", k, "iterations", st->pb.has_contact ? st->sol.as.iterations : 0);
  SummaryListReal(list, "adapt", k, "seconds", seconds);
}

PetscErrorCode AdaptRun(MPI_Comm comm, M2dScene *s, const M2dAdaptOptions *ao, const M2dEstimatorOptions *eo)
{
  PrevMesh        prev;
  M2dContactState state, *warm = NULL;
  M2dStep         st;
  M2dSummary     *list;
  int             bodytag[M2D_MAX_BODIES];
  char            what[PETSC_MAX_PATH_LEN + 64];

  PetscFunctionBeginUser;
  PetscCheck(eo->enabled, comm, PETSC_ERR_USER_INPUT, "option -adapt: needs the error estimate (-error_estimate 1)");
  PetscCall(PetscMemzero(&prev, sizeof(prev)));
  PetscCall(PetscMemzero(&state, sizeof(state)));
  PetscCall(PetscCalloc1(1, &list));
  for (PetscInt k = 0;; k++) {
    MshMesh  msh;
    double   t0 = M2dWallTime(), tgmsh, seconds;
    PetscBool last;
    PetscCall(Remesh(comm, s, ao, &prev, k, &msh, &tgmsh));
    PrevMeshFree(&prev);
    PetscCall(PetscSNPrintf(what, sizeof(what), "%s (adapt step %" PetscInt_FMT ")", s->geo, k));
    PetscCall(M2dStepSolve(comm, s, &(M2dMeshSource){&msh, what}, warm, eo, &st));
    if (k == 0) PetscCall(BodyTags(comm, s, &msh, bodytag));
    MshFree(&msh);
    seconds = M2dWallTime() - t0;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, comm));
    StepLine(comm, k, &st, seconds);
    Record(list, k, &st, seconds);
    last = (PetscBool)(st.fig.est.estimate_rel <= ao->target || k + 1 >= ao->max_steps);
    /* the next mesh must fit -adapt_max_dofs: the size field's expected cells, about one vertex (2 dofs) each */
    if (!last) last = (PetscBool)(2 * st.fig.expected_cells > ao->max_dofs);
    if (last) break;
    PetscCall(GatherPrevMesh(&st, bodytag, &prev));
    PetscCall(ContactStateDestroy(&state));
    if (st.pb.has_contact) {
      PetscCall(ContactStateCreate(&st.pb.contact, &state));
      warm = &state;
    }
    PetscCall(M2dStepDestroy(&st));
  }
  PetscCall(SummaryMergeLists(st.sum, list));
  PetscCall(M2dStepWrite(&st));
  PetscCall(M2dStepDestroy(&st));
  PetscCall(ContactStateDestroy(&state));
  PetscCall(PetscFree(list));
  PetscFunctionReturn(0);
}
