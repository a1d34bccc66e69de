/* contact.c - the contact pairs: set-up, results, fields, state (see contact.h). */
#include "contact.h"
#include "method.h"

/* no row within reach: say whether the non-mortar surface lies inside the
 * mortar body deeper than the reach (the meshes overlap), or beyond it (a
 * gap), from each node's signed distance to the nearest mortar edge it faces */
static PetscErrorCode NoRows(MPI_Comm comm, const M2dContactPair *c, const M2dScene *s, PetscReal L)
{
  PetscReal      deep = 0, near = PETSC_MAX_REAL, ext = PetscSqrtReal(PetscSqr(c->m.hi[0] - c->m.lo[0]) + PetscSqr(c->m.hi[1] - c->m.lo[1]));
  const char    *nmg = c->def->nm, *mg = c->def->m;
  M2dSurfaceTree tree;

  PetscFunctionBeginUser;
  PetscCall(SurfaceTreeCreate(&c->m, &tree));
  for (PetscInt i = 0; i < c->nm.nnode; i++) { /* each node against the nearest mortar edge it faces */
    PetscReal nn[2], d, t;
    SurfaceNodeNormal(&c->nm, i, nn);
    if (SurfaceTreeFacing(&tree, &c->nm.x[2 * i], nn, PETSC_MIN_REAL, PETSC_MAX_REAL, &d, &t) < 0) continue;
    deep = PetscMin(deep, d); /* < 0: inside the mortar body */
    near = PetscMin(near, PetscAbsReal(d));
  }
  PetscCall(SurfaceTreeDestroy(&tree));
  PetscCheck(!(deep < -c->reach), comm, PETSC_ERR_USER_INPUT, "%s: '%s' lies up to %g inside body '%s', behind '%s' (the meshes overlap by %.0f%% of that surface's extent %g), deeper than -contact_reach %g: move the bodies apart in the mesh (or raise -contact_reach past the overlap)",
             c->def->what, nmg, (double)(-deep * L), c->m.body >= 0 ? s->body[c->m.body].name : "?", mg, (double)(-100 * deep / ext), (double)(ext * L), (double)(L * c->reach));
  PetscCheck(near == PETSC_MAX_REAL, comm, PETSC_ERR_USER_INPUT, "%s: the two surfaces are %g apart where they face each other, more than -contact_reach %g: raise -contact_reach or close the gap", c->def->what, (double)(near * L), (double)(L * c->reach));
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "%s: the two surfaces never face each other within %g (-contact_reach)", c->def->what, (double)(L * c->reach));
}

static PetscErrorCode PairSetup(const M2dMesh *m, const M2dScene *s, PetscReal L, PetscInt k, M2dContactPair *c)
{
  MPI_Comm    comm  = PetscObjectComm((PetscObject)m->dm);

  PetscFunctionBeginUser;
  c->def    = &s->pair[k];
  c->method = c->def->method;
  c->basis  = (M2dMortarBasis)c->def->basis;
  PetscCall(SurfaceGather(m, c->def->nm, c->def->opt_nm, &c->nm));
  PetscCall(SurfaceGather(m, c->def->m, c->def->opt_m, &c->m));
  c->reach = s->reach;
  if (!s->reach_set) c->reach = 0.1 * PetscSqrtReal(PetscSqr(c->m.hi[0] - c->m.lo[0]) + PetscSqr(c->m.hi[1] - c->m.lo[1]));
  c->mu = c->def->mu;
  if (M2dMethodOf(c->method, c->basis)->segments) {
    PetscInt  corner;
    PetscReal turn;
    PetscCall(MortarBuildSegments(&c->nm, &c->m, c->reach, &c->seg));
    PetscCall(MortarReachedCorner(&c->nm, &c->m, &c->seg, &corner, &turn));
    PetscCheck(corner < 0, comm, PETSC_ERR_USER_INPUT, "%s: mortar surface '%s' has a corner at (%g, %g), turning by %.0f degrees, that '%s' reaches on both sides (within -contact_reach): the contact holds the non-mortar nodes, so the corner would pass between them; make '%s' the non-mortar side (its corner then holds), end the curve at the corner if nothing beyond it can touch, or round the corner", c->def->what, c->def->m,
               (double)(L * c->m.x[2 * corner]), (double)(L * c->m.x[2 * corner + 1]), (double)turn, c->def->nm, c->def->m);
    PetscCall(MortarRows(&c->nm, &c->m, &c->seg, c->basis, PETSC_FALSE, &c->R));
    if (c->mu > 0) PetscCall(MortarRows(&c->nm, &c->m, &c->seg, c->basis, PETSC_TRUE, &c->T));
  } else {
    PetscCall(NTSRows(&c->nm, &c->m, c->reach, PETSC_FALSE, &c->R));
    if (c->mu > 0) PetscCall(NTSRows(&c->nm, &c->m, c->reach, PETSC_TRUE, &c->T));
  }
  if (c->R.n == 0) PetscCall(NoRows(comm, c, s, L));
  PetscCall(PetscPrintf(comm, "contact%s: %s, non-mortar '%s' (%" PetscInt_FMT " edges), mortar '%s' (%" PetscInt_FMT " edges), %" PetscInt_FMT " segments, %" PetscInt_FMT " multipliers, reach %g\n", s->npair > 1 ? " pair" : "", M2dMethodOf(c->method, c->basis)->printed, c->def->nm, c->nm.nedge, c->def->m, c->m.nedge, c->seg.nseg, c->R.n, (double)(L * c->reach)));
  PetscFunctionReturn(0);
}

/* every pair's normal rows one after another, then the tangential ones (one
 * frictionless pair: a copy of its rows) */
static PetscErrorCode MergeRows(M2dContact *c)
{
  M2dContactRows *R = &c->R;
  PetscInt        nnz = 0, j = 0;

  PetscFunctionBeginUser;
  R->n = 0;
  for (int t = 0; t < 2; t++)
    for (PetscInt k = 0; k < c->npair; k++) {
      const M2dContactRows *P = t ? &c->pair[k].T : &c->pair[k].R;
      if (t) c->pair[k].toff = R->n;
      else c->pair[k].off = R->n;
      R->n += P->n;
      nnz += P->n ? P->ptr[P->n] : 0;
    }
  c->nnormal = c->npair ? c->pair[c->npair - 1].off + c->pair[c->npair - 1].R.n : 0;
  PetscCall(PetscMalloc4(R->n + 1, &R->node, R->n + 1, &R->ptr, R->n + 1, &R->g0, R->n + 1, &R->w));
  PetscCall(PetscMalloc2(nnz + 1, &R->col, nnz + 1, &R->val));
  PetscCall(PetscMalloc2(R->n + 1, &c->rowpair, R->n + 1, &c->partner));
  R->ptr[0] = 0;
  for (int t = 0; t < 2; t++)
    for (PetscInt k = 0; k < c->npair; k++) {
      const M2dContactRows *P = t ? &c->pair[k].T : &c->pair[k].R;
      if (!P->n) continue;
      PetscCall(PetscArraycpy(&R->col[R->ptr[j]], P->col, P->ptr[P->n]));
      PetscCall(PetscArraycpy(&R->val[R->ptr[j]], P->val, P->ptr[P->n]));
      for (PetscInt i = 0; i < P->n; i++, j++) {
        R->node[j]     = P->node[i];
        R->g0[j]       = P->g0[i];
        R->w[j]        = P->w[i];
        R->ptr[j + 1]  = R->ptr[j] + P->ptr[i + 1] - P->ptr[i];
        c->rowpair[j]  = k;
        c->partner[j]  = t ? c->pair[k].off + i : -1;
      }
    }
  PetscFunctionReturn(0);
}

PetscErrorCode ContactSetup(const M2dMesh *m, const M2dScene *s, PetscReal L, M2dContact *c)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(c, sizeof(*c)));
  PetscCall(PetscCalloc1(s->npair, &c->pair));
  c->npair = s->npair;
  for (PetscInt k = 0; k < s->npair; k++) PetscCall(PairSetup(m, s, L, k, &c->pair[k]));
  PetscCall(MergeRows(c));
  PetscFunctionReturn(0);
}

/* add lambda_j times row j of rows R to the force on the non-mortar body (its dofs: the node ids are u_x dofs) */
static void AddRowForces(M2dContactPair *c, const M2dContactRows *R, const PetscReal lam[])
{
  for (PetscInt j = 0; j < R->n; j++)
    for (PetscInt k = R->ptr[j]; k < R->ptr[j + 1]; k++) {
      PetscInt col = R->col[k], lo = 0, hi = c->nm.nnode - 1, d = col % 2 ? 1 : 0, base = col - d;
      while (lo <= hi) { /* c->nm.gdof is sorted */
        PetscInt mid = (lo + hi) / 2;
        if (c->nm.gdof[mid] == base) {
          c->force[d] += lam[j] * R->val[k];
          break;
        }
        if (c->nm.gdof[mid] < base) lo = mid + 1;
        else hi = mid - 1;
      }
    }
}

/* force on the non-mortar body: B^T lambda on its dofs; the integrals of the
 * pressure and of the tangential traction; the stick and slip counts */
static void PairForce(M2dContactPair *c)
{
  c->force[0] = c->force[1] = c->force_n = c->force_t = 0;
  c->nstick = c->nslip = 0;
  for (PetscInt j = 0; j < c->R.n; j++) {
    c->force_n += c->pressure[j] * c->R.w[j];
    c->force_t += c->traction[j] * c->R.w[j];
    c->nstick += c->status[j] == M2D_STATUS_STICK;
    c->nslip += c->status[j] == M2D_STATUS_SLIP;
  }
  AddRowForces(c, &c->R, c->pressure);
  if (c->T.n) AddRowForces(c, &c->T, c->traction);
}

void ContactPairViews(M2dContact *c)
{
  for (PetscInt k = 0; k < c->npair; k++) {
    M2dContactPair *p = &c->pair[k];
    p->pressure = c->pressure + p->off, p->gap = c->gap + p->off, p->active = c->active + p->off;
    p->traction = c->traction + p->off, p->slip = c->slip + p->off, p->slip_inc = c->slip_inc + p->off, p->status = c->status + p->off;
  }
}

PetscErrorCode ContactResults(M2dContact *c, Mat C, Vec r, Vec u, Vec lam, Vec active, Vec slip)
{
  Vec                gw, from[4], all[4]; /* multipliers, weighted gaps and slips, active flags (NULL: all), accumulated slips */
  VecScatter         sc;
  const PetscScalar *a[4];
  PetscInt           nn = c->nnormal;

  PetscFunctionBeginUser;
  /* weighted gap g~ = r - C u (r carries g~0 and the Dirichlet part); on a
   * tangential row the step's weighted slip (kkt.h) */
  PetscCall(VecDuplicate(r, &gw));
  PetscCall(MatMult(C, u, gw));
  PetscCall(VecAYPX(gw, -1.0, r));
  from[0] = lam, from[1] = gw, from[2] = active, from[3] = slip;
  PetscCall(VecScatterCreateToAll(lam, &sc, &all[0]));
  for (int k = 0; k < 4; k++) { /* every rank gets every row */
    if (k) PetscCall(VecDuplicate(all[0], &all[k]));
    if (from[k]) {
      PetscCall(VecScatterBegin(sc, from[k], all[k], INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecScatterEnd(sc, from[k], all[k], INSERT_VALUES, SCATTER_FORWARD));
    } else PetscCall(VecSet(all[k], k == 2 ? 1.0 : 0.0));
    PetscCall(VecGetArrayRead(all[k], &a[k]));
  }
  PetscCall(PetscFree3(c->pressure, c->gap, c->active));
  PetscCall(PetscFree4(c->traction, c->slip, c->slip_inc, c->status));
  PetscCall(PetscMalloc3(nn + 1, &c->pressure, nn + 1, &c->gap, nn + 1, &c->active));
  PetscCall(PetscCalloc4(nn + 1, &c->traction, nn + 1, &c->slip, nn + 1, &c->slip_inc, nn + 1, &c->status));
  for (PetscInt j = 0; j < nn; j++) {
    c->pressure[j] = PetscRealPart(a[0][j]);
    c->gap[j]      = PetscRealPart(a[1][j]) / c->R.w[j];
    c->active[j]   = PetscRealPart(a[2][j]);
    c->status[j]   = c->active[j] != 0 ? M2D_STATUS_SLIP : M2D_STATUS_OPEN; /* frictionless: a closed node slides */
  }
  for (PetscInt j = nn; j < c->R.n; j++) { /* tangential rows: r - C u is the step's weighted slip (kkt.h) */
    PetscInt i = c->partner[j];
    c->traction[i] = PetscRealPart(a[0][j]);
    c->slip_inc[i] = c->active[i] != 0 ? PetscRealPart(a[1][j]) / c->R.w[j] : 0; /* an open node does not slip */
    c->slip[i]     = PetscRealPart(a[3][j]) / c->R.w[j];
    if (c->active[i] != 0 && PetscRealPart(a[2][j]) != 0) c->status[i] = M2D_STATUS_STICK;
  }
  ContactPairViews(c);
  for (PetscInt k = 0; k < c->npair; k++) PairForce(&c->pair[k]);
  for (int k = 0; k < 4; k++) {
    PetscCall(VecRestoreArrayRead(all[k], &a[k]));
    PetscCall(VecDestroy(&all[k]));
  }
  PetscCall(VecScatterDestroy(&sc));
  PetscCall(VecDestroy(&gw));
  PetscFunctionReturn(0);
}

PetscErrorCode ContactStateCreate(const M2dContact *c, M2dContactState *st)
{
  PetscFunctionBeginUser;
  st->n     = c->nnormal;
  st->npair = c->npair;
  PetscCall(PetscMalloc1(c->npair + 1, &st->off));
  for (PetscInt k = 0; k < c->npair; k++) st->off[k] = c->pair[k].off;
  st->off[c->npair] = c->nnormal;
  PetscCall(PetscMalloc4(2 * st->n + 1, &st->xy, st->n + 1, &st->active, st->n + 1, &st->pressure, st->n + 1, &st->gap));
  for (PetscInt j = 0; j < st->n; j++) {
    const M2dSurface *nm = &c->pair[c->rowpair[j]].nm;
    st->xy[2 * j]     = nm->x[2 * c->R.node[j]];
    st->xy[2 * j + 1] = nm->x[2 * c->R.node[j] + 1];
    st->active[j]     = (PetscBool)(c->active[j] != 0);
    st->pressure[j]   = c->pressure[j];
    st->gap[j]        = c->gap[j];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ContactStateDestroy(M2dContactState *st)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree4(st->xy, st->active, st->pressure, st->gap));
  PetscCall(PetscFree(st->off));
  st->n = st->npair = 0;
  PetscFunctionReturn(0);
}

static int CmpX(const void *a, const void *b)
{
  const M2dXYIdx *p = (const M2dXYIdx *)a, *q = (const M2dXYIdx *)b;
  return (p->x > q->x) - (p->x < q->x);
}

/* the points xy[0 .. n) sorted along the axis of their larger extent (o[k].x
 * that coordinate, o[k].y the other): the sweeps below then visit the points
 * near a query and few others, unless the points crowd both axes */
static int SweepSort(M2dXYIdx *o, PetscInt n, const PetscReal *xy)
{
  PetscReal lo[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[2] = {PETSC_MIN_REAL, PETSC_MIN_REAL};
  int       axis;
  for (PetscInt k = 0; k < n; k++)
    for (int d = 0; d < 2; d++) lo[d] = PetscMin(lo[d], xy[2 * k + d]), hi[d] = PetscMax(hi[d], xy[2 * k + d]);
  axis = hi[1] - lo[1] > hi[0] - lo[0];
  for (PetscInt k = 0; k < n; k++) {
    o[k].x = xy[2 * k + axis];
    o[k].y = xy[2 * k + 1 - axis];
    o[k].j = k;
  }
  qsort(o, (size_t)n, sizeof(M2dXYIdx), CmpX);
  return axis;
}

/* the nearest previous node k[0], and k[1] the nearest beyond p as seen from
 * k[0] ((x_k1 - x_k0) . (p - x_k0) > 0; -1 if none), by sweeps outwards
 * along o's axis (SweepSort) from the binary-search position */
static void Nearest2(const M2dXYIdx *o, PetscInt n, const PetscReal *xyp, int axis, const PetscReal p[2], PetscInt k[2])
{
  const PetscReal x = p[axis], y = p[1 - axis];
  PetscInt        lo = 0, hi = n;
  PetscReal d2[2] = {PETSC_MAX_REAL, PETSC_MAX_REAL};
  k[0] = k[1] = -1;
  while (lo < hi) {
    PetscInt mid = (lo + hi) / 2;
    if (o[mid].x < x) lo = mid + 1;
    else hi = mid;
  }
  for (int pass = 0; pass < 2; pass++)
    for (int dir = 0; dir < 2; dir++)
      for (PetscInt i = dir ? lo - 1 : lo; i >= 0 && i < n && PetscSqr(o[i].x - x) < d2[pass]; i += dir ? -1 : 1) {
        PetscReal d = PetscSqr(o[i].x - x) + PetscSqr(o[i].y - y);
        if (pass == 1 && (o[i].j == k[0] || (o[i].x - xyp[2 * k[0] + axis]) * (x - xyp[2 * k[0] + axis]) + (o[i].y - xyp[2 * k[0] + 1 - axis]) * (y - xyp[2 * k[0] + 1 - axis]) <= 0)) continue;
        if (d < d2[pass]) d2[pass] = d, k[pass] = o[i].j;
        if (pass == 1 && k[0] < 0) return;
      }
}

/* the mortar surface of one pair: the non-mortar values v0, v1 (per node of
 * its rows) where its node's nearest point on the chain of multiplier nodes
 * lies, linear between two of them (v1 categorical: the nearer one's), none
 * (field untouched) beyond its ends; into components 0 and 1 of field */
static PetscErrorCode PairFillMortar(const M2dContactPair *c, const PetscReal v0[], const PetscReal v1[], PetscBool categorical, Vec field)
{
  M2dXYIdx  *o;
  PetscReal *xy;
  int        axis;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(c->R.n + 1, &o, 2 * c->R.n + 1, &xy));
  for (PetscInt j = 0; j < c->R.n; j++) {
    xy[2 * j]     = c->nm.x[2 * c->R.node[j]];
    xy[2 * j + 1] = c->nm.x[2 * c->R.node[j] + 1];
  }
  axis = SweepSort(o, c->R.n, xy);
  for (PetscInt i = 0; i < c->m.nnode && c->R.n > 0; i++) {
    const PetscReal *p = &c->m.x[2 * i], *a;
    PetscInt         k[2];
    PetscReal        t = 0, d2;
    Nearest2(o, c->R.n, xy, axis, p, k);
    a  = &xy[2 * k[0]];
    d2 = PetscSqr(p[0] - a[0]) + PetscSqr(p[1] - a[1]);
    if (k[1] >= 0) {
      const PetscReal *b  = &xy[2 * k[1]];
      PetscReal        l2 = PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]);
      t = l2 > 0 ? PetscMin(1, ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / l2) : 0;
    } else if (d2 > PetscSqr(1e-9 * (c->m.hi[0] - c->m.lo[0] + c->m.hi[1] - c->m.lo[1]))) continue; /* beyond the chain */
    PetscCall(VecSetValue(field, c->m.gdof[i], (1 - t) * v0[k[0]] + (k[1] >= 0 ? t * v0[k[1]] : 0), INSERT_VALUES));
    if (categorical) PetscCall(VecSetValue(field, c->m.gdof[i] + 1, v1[k[1] >= 0 && t > 0.5 ? k[1] : k[0]], INSERT_VALUES));
    else PetscCall(VecSetValue(field, c->m.gdof[i] + 1, (1 - t) * v1[k[0]] + (k[1] >= 0 ? t * v1[k[1]] : 0), INSERT_VALUES));
  }
  PetscCall(PetscFree2(o, xy));
  PetscFunctionReturn(0);
}

/* a field of two point values per node: (f0, f1) off the interface, then the
 * pairs' values v0, v1 (offsets of the pairs' nodes in the interface's
 * arrays) on the mortar surfaces and, after them all, on the non-mortar ones */
static PetscErrorCode FillPair(const M2dContact *c, const PetscReal *v0, const PetscReal *v1, PetscReal f0, PetscReal f1, PetscBool categorical, Vec field)
{
  PetscMPIInt  rank;
  PetscScalar *a;
  PetscInt     n;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(field, &n));
  PetscCall(VecGetArray(field, &a));
  for (PetscInt i = 0; i < n; i += 2) {
    a[i]     = f0;
    a[i + 1] = f1;
  }
  PetscCall(VecRestoreArray(field, &a));
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)field), &rank));
  for (PetscInt q = 0; q < c->npair && rank == 0; q++) PetscCall(PairFillMortar(&c->pair[q], v0 + c->pair[q].off, v1 + c->pair[q].off, categorical, field));
  for (PetscInt q = 0; q < c->npair && rank == 0; q++) { /* after every mortar surface: a node on both sides shows its multiplier */
    const M2dContactPair *p = &c->pair[q];
    for (PetscInt j = 0; j < p->R.n; j++) {
      PetscInt g = p->nm.gdof[p->R.node[j]];
      PetscCall(VecSetValue(field, g, v0[p->off + j], INSERT_VALUES));
      PetscCall(VecSetValue(field, g + 1, v1[p->off + j], INSERT_VALUES));
    }
  }
  PetscCall(VecAssemblyBegin(field));
  PetscCall(VecAssemblyEnd(field));
  PetscFunctionReturn(0);
}

PetscErrorCode ContactFillField(const M2dContact *c, Vec field, Vec active)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(FillPair(c, c->pressure, c->gap, 0, NAN, PETSC_FALSE, field)); /* pressure 0 and gap NaN off the interface */
  PetscCall(VecSet(active, NAN));
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)field), &rank));
  for (PetscInt q = 0; q < c->npair && rank == 0; q++) {
    const M2dContactPair *p = &c->pair[q];
    for (PetscInt i = 0; i < p->nm.nnode; i++) PetscCall(VecSetValue(active, p->nm.gdof[i], 0.0, INSERT_VALUES));
    for (PetscInt j = 0; j < p->R.n; j++) PetscCall(VecSetValue(active, p->nm.gdof[p->R.node[j]], p->active[j] != 0 ? 1.0 : 0.0, INSERT_VALUES));
  }
  PetscCall(VecAssemblyBegin(active));
  PetscCall(VecAssemblyEnd(active));
  PetscFunctionReturn(0);
}

PetscErrorCode ContactFillFriction(const M2dContact *c, Vec traction_slip, Vec increment_status)
{
  PetscFunctionBeginUser;
  PetscCall(FillPair(c, c->traction, c->slip, 0, NAN, PETSC_FALSE, traction_slip));
  PetscCall(FillPair(c, c->slip_inc, c->status, NAN, NAN, PETSC_TRUE, increment_status));
  PetscFunctionReturn(0);
}

/* Between the last active previous node A0 and the first inactive one B the
 * zone ends where the pressure does: near the edge of a smooth contact p^2 is
 * linear in the distance to it (p ~ sqrt(a - x)), so with A1 the active node
 * before A0, the edge is at |A0 - A1| p0^2 / (p1^2 - p0^2) beyond A0. Is p
 * (projected on A0 -> B) before it? */
static PetscBool EdgeSide(const M2dContactState *st, PetscInt a0, PetscInt b, const PetscReal p[2])
{
  const PetscReal *x0 = &st->xy[2 * a0], *xb = &st->xy[2 * b];
  PetscReal        d[2] = {xb[0] - x0[0], xb[1] - x0[1]}, L = PetscSqrtReal(d[0] * d[0] + d[1] * d[1]), best = PETSC_MAX_REAL, s, p0, p1;
  PetscInt         a1 = -1;
  if (!(L > 0)) return PETSC_TRUE;
  for (PetscInt i = 0; i < st->n; i++) { /* the nearest active node behind A0 */
    PetscReal e[2] = {st->xy[2 * i] - x0[0], st->xy[2 * i + 1] - x0[1]}, dd = e[0] * e[0] + e[1] * e[1];
    if (i == a0 || !st->active[i] || e[0] * d[0] + e[1] * d[1] >= 0 || dd >= best) continue;
    best = dd, a1 = i;
  }
  s  = ((p[0] - x0[0]) * d[0] + (p[1] - x0[1]) * d[1]) / L; /* p's distance beyond A0 */
  p0 = st->pressure[a0];
  p1 = a1 >= 0 ? st->pressure[a1] : 0;
  if (a1 < 0 || !(p1 * p1 > p0 * p0)) return (PetscBool)(s < 0.5 * L);
  return (PetscBool)(s < PetscMin(L, PetscSqrtReal(best) * p0 * p0 / (p1 * p1 - p0 * p0)));
}

/* pair c's rows against the previous state of the same pair */
static PetscErrorCode PairStateMask(const M2dContactState *st, const M2dContactPair *c, const M2dUnits *u, PetscReal cparam, PetscBool mask[])
{
  M2dXYIdx *o;
  int       axis;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(st->n + 1, &o));
  axis = SweepSort(o, st->n, st->xy);
  for (PetscInt j = 0; j < c->R.n; j++) {
    PetscReal p[2] = {c->nm.x[2 * c->R.node[j]] * u->L, c->nm.x[2 * c->R.node[j] + 1] * u->L}, cw = cparam * c->R.w[j], phi[2], t = 0;
    PetscInt  k[2];
    Nearest2(o, st->n, st->xy, axis, p, k);
    mask[j] = PETSC_FALSE;
    if (k[0] < 0) continue;
    for (int i = 0; i < 2; i++) phi[i] = k[i] < 0 ? 0 : st->pressure[k[i]] / u->S - cw * st->gap[k[i]] / u->U;
    if (k[1] >= 0 && (phi[0] > 0) != (phi[1] > 0)) { /* the edge of the zone between them: interpolate */
      const PetscReal *a = &st->xy[2 * k[0]], *b = &st->xy[2 * k[1]];
      PetscReal        l2 = PetscSqr(b[0] - a[0]) + PetscSqr(b[1] - a[1]);
      t = l2 > 0 ? PetscMin(1, PetscMax(0, ((p[0] - a[0]) * (b[0] - a[0]) + (p[1] - a[1]) * (b[1] - a[1])) / l2)) : 0;
    }
    mask[j] = (PetscBool)((1 - t) * phi[0] + t * (k[1] >= 0 ? phi[1] : 0) > 0);
    if (k[1] >= 0 && st->active[k[0]] != st->active[k[1]]) mask[j] = EdgeSide(st, st->active[k[0]] ? k[0] : k[1], st->active[k[0]] ? k[1] : k[0], p);
  }
  PetscCall(PetscFree(o));
  PetscFunctionReturn(0);
}

PetscErrorCode ContactStateMask(const M2dContactState *st, const M2dContact *c, const M2dUnits *u, PetscReal cparam, PetscBool mask[])
{
  PetscFunctionBeginUser;
  for (PetscInt q = 0; q < c->npair; q++) {
    M2dContactState view = {0};
    if (q < st->npair) { /* the same pair of the previous mesh */
      PetscInt o = st->off[q];
      view.n = st->off[q + 1] - o, view.xy = st->xy + 2 * o, view.active = st->active + o, view.pressure = st->pressure + o, view.gap = st->gap + o;
    }
    PetscCall(PairStateMask(&view, &c->pair[q], u, cparam, mask + c->pair[q].off));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ContactToUserUnits(M2dContact *c, const M2dUnits *u)
{
  PetscFunctionBeginUser;
  for (PetscInt j = 0; j < c->nnormal; j++) {
    c->pressure[j] *= u->S;
    c->gap[j] *= u->U;
    c->traction[j] *= u->S;
    c->slip[j] *= u->U;
    c->slip_inc[j] *= u->U;
  }
  for (PetscInt j = 0; j < c->R.n; j++) c->R.w[j] *= u->L;
  for (PetscInt q = 0; q < c->npair; q++) {
    M2dContactPair *p     = &c->pair[q];
    M2dSurface     *sf[2] = {&p->nm, &p->m};
    for (PetscInt j = 0; j < p->R.n; j++) p->R.w[j] *= u->L;
    for (PetscInt j = 0; j < p->T.n; j++) p->T.w[j] *= u->L;
    for (int d = 0; d < 2; d++) p->force[d] *= u->S * u->L;
    p->force_n *= u->S * u->L;
    p->force_t *= u->S * u->L;
    for (int k = 0; k < 2; k++)
      for (PetscInt i = 0; i < 2 * sf[k]->nnode; i++) sf[k]->x[i] *= u->L;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ContactPairDestroy(M2dContactPair *p)
{
  PetscFunctionBeginUser;
  PetscCall(SurfaceDestroy(&p->nm));
  PetscCall(SurfaceDestroy(&p->m));
  PetscCall(SegmentSetDestroy(&p->seg));
  PetscCall(ContactRowsDestroy(&p->R));
  PetscCall(ContactRowsDestroy(&p->T));
  PetscFunctionReturn(0);
}

PetscErrorCode ContactDestroy(M2dContact *c)
{
  PetscFunctionBeginUser;
  for (PetscInt q = 0; q < c->npair; q++) PetscCall(ContactPairDestroy(&c->pair[q]));
  PetscCall(PetscFree(c->pair));
  PetscCall(PetscFree2(c->rowpair, c->partner));
  PetscCall(ContactRowsDestroy(&c->R));
  PetscCall(PetscFree3(c->pressure, c->gap, c->active));
  PetscCall(PetscFree4(c->traction, c->slip, c->slip_inc, c->status));
  c->npair = 0;
  PetscFunctionReturn(0);
}

/* a surface's normal turns at some node by more than 1e-6 rad and less than
 * 45 degrees (a corner is no curvature) */
static PetscBool SurfaceCurved(const M2dSurface *s)
{
  for (PetscInt i = 0; i < s->nnode; i++) {
    const PetscReal *a, *b;
    PetscReal        sn, cs;
    if (s->n2e_ptr[i + 1] - s->n2e_ptr[i] != 2) continue;
    a  = &s->normal[2 * s->n2e[s->n2e_ptr[i]]], b = &s->normal[2 * s->n2e[s->n2e_ptr[i] + 1]];
    sn = PetscAbsReal(a[0] * b[1] - a[1] * b[0]), cs = a[0] * b[0] + a[1] * b[1];
    if (sn > 1e-6 && cs > 0 && sn < cs) return PETSC_TRUE;
  }
  return PETSC_FALSE;
}

PetscBool ContactPairCurved(const M2dContactPair *c)
{
  return (PetscBool)(SurfaceCurved(&c->nm) || SurfaceCurved(&c->m));
}
