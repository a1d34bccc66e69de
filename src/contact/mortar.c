/* mortar.c - mortar segments, D and M, and the node-to-segment rows (see mortar.h). */
#include "mortar.h"

static const PetscReal gp[2] = {-0.57735026918962576451, 0.57735026918962576451};

/* parameter in [-1, 1] of the projection of point p along the normal of mortar edge me */
static PetscReal MortarParam(const M2dSurface *m, PetscInt me, const PetscReal p[2])
{
  const PetscReal *a = &m->x[2 * m->edge[2 * me]], *b = &m->x[2 * m->edge[2 * me + 1]];
  PetscReal        t[2] = {b[0] - a[0], b[1] - a[1]};
  return 2 * ((p[0] - a[0]) * t[0] + (p[1] - a[1]) * t[1]) / (t[0] * t[0] + t[1] * t[1]) - 1;
}

static void EdgePoint(const M2dSurface *s, PetscInt e, PetscReal z, PetscReal p[2])
{
  const PetscReal *a = &s->x[2 * s->edge[2 * e]], *b = &s->x[2 * s->edge[2 * e + 1]];
  p[0]               = 0.5 * (1 - z) * a[0] + 0.5 * (1 + z) * b[0];
  p[1]               = 0.5 * (1 - z) * a[1] + 0.5 * (1 + z) * b[1];
}

/* signed gap along the mortar normal between the non-mortar point at zeta and its projection */
static PetscReal SegmentGap(const M2dSurface *nm, const M2dSurface *m, PetscInt ne, PetscInt me, PetscReal zeta)
{
  PetscReal p[2], q[2];
  EdgePoint(nm, ne, zeta, p);
  EdgePoint(m, me, MortarParam(m, me, p), q);
  return (p[0] - q[0]) * m->normal[2 * me] + (p[1] - q[1]) * m->normal[2 * me + 1];
}

PetscErrorCode MortarBuildSegments(const M2dSurface *nm, const M2dSurface *m, PetscReal reach, M2dSegmentSet *S)
{
  PetscInt       cap = 4 * (nm->nedge + m->nedge) + 16, ncand = 0, ccap = 0, *cand = NULL;
  M2dSurfaceTree tree;

  PetscFunctionBeginUser;
  S->nseg = 0;
  PetscCall(PetscMalloc1(cap, &S->seg));
  PetscCall(SurfaceTreeCreate(m, &tree));
  for (PetscInt e = 0; e < nm->nedge; e++) {
    const PetscReal *a = &nm->x[2 * nm->edge[2 * e]], *b = &nm->x[2 * nm->edge[2 * e + 1]];
    PetscReal        elo[2], ehi[2];
    for (int d = 0; d < 2; d++) {
      elo[d] = PetscMin(a[d], b[d]) - reach;
      ehi[d] = PetscMax(a[d], b[d]) + reach;
    }
    /* the mortar edges within reach of e along their normals (a superset of
     * those the tests below keep, in ascending order: the segments come in
     * the order of a loop over every mortar edge) */
    PetscCall(SurfaceTreeNear(&tree, a, b, reach, &ncand, &ccap, &cand));
    for (PetscInt ci = 0; ci < ncand; ci++) {
      const PetscInt   f = cand[ci];
      const PetscReal *c = &m->x[2 * m->edge[2 * f]], *d = &m->x[2 * m->edge[2 * f + 1]];
      PetscReal        xa, xb, lo, hi, za, zb, g0, g1;
      M2dSegment         *s;
      /* bounding boxes, then facing normals */
      if (PetscMax(c[0], d[0]) < elo[0] || PetscMin(c[0], d[0]) > ehi[0] || PetscMax(c[1], d[1]) < elo[1] || PetscMin(c[1], d[1]) > ehi[1]) continue;
      if (nm->normal[2 * e] * m->normal[2 * f] + nm->normal[2 * e + 1] * m->normal[2 * f + 1] >= 0) continue;
      xa = MortarParam(m, f, a);
      xb = MortarParam(m, f, b);
      if (PetscAbsReal(xb - xa) < 1e-12) continue; /* edges perpendicular */
      lo = PetscMax(-1.0, PetscMin(xa, xb));
      hi = PetscMin(1.0, PetscMax(xa, xb));
      if (!(hi > lo)) continue; /* no overlap (a shared end point is a zero-length segment: dropped) */
      /* the overlap in the non-mortar parameter */
      za = -1 + 2 * (lo - xa) / (xb - xa);
      zb = -1 + 2 * (hi - xa) / (xb - xa);
      if (za > zb) {
        PetscReal t = za;
        za          = zb;
        zb          = t;
      }
      za = PetscMax(-1.0, za);
      zb = PetscMin(1.0, zb);
      if (!(zb > za)) continue;
      g0 = SegmentGap(nm, m, e, f, za);
      g1 = SegmentGap(nm, m, e, f, zb);
      if (PetscMin(g0, g1) > reach || PetscMax(g0, g1) < -reach) continue;
      if (S->nseg == cap) {
        M2dSegment *t;
        cap *= 2;
        PetscCall(PetscMalloc1(cap, &t));
        PetscCall(PetscArraycpy(t, S->seg, S->nseg));
        PetscCall(PetscFree(S->seg));
        S->seg = t;
      }
      s          = &S->seg[S->nseg++];
      s->nm_edge = e;
      s->m_edge  = f;
      s->zeta[0] = za;
      s->zeta[1] = zb;
      {
        PetscReal p[2];
        EdgePoint(nm, e, za, p);
        s->xi[0] = MortarParam(m, f, p);
        EdgePoint(nm, e, zb, p);
        s->xi[1] = MortarParam(m, f, p);
      }
    }
  }
  PetscCall(PetscFree(cand));
  PetscCall(SurfaceTreeDestroy(&tree));
  PetscFunctionReturn(0);
}

PetscErrorCode SegmentSetDestroy(M2dSegmentSet *S)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(S->seg));
  S->nseg = 0;
  PetscFunctionReturn(0);
}

void MortarSegmentDM(const M2dSurface *nm, const M2dSegment *s, M2dMortarBasis basis, PetscReal D[4], PetscReal M[4])
{
  const PetscReal L = nm->len[s->nm_edge], h = 0.5 * (s->zeta[1] - s->zeta[0]);
  for (int k = 0; k < 4; k++) D[k] = M[k] = 0;
  for (int g = 0; g < 2; g++) {
    PetscReal z  = 0.5 * (s->zeta[0] + s->zeta[1]) + h * gp[g];
    PetscReal xi = s->xi[0] + (s->xi[1] - s->xi[0]) * (z - s->zeta[0]) / (s->zeta[1] - s->zeta[0]);
    PetscReal w  = h * 0.5 * L; /* Gauss weight 1, d zeta -> da = L/2 d zeta */
    PetscReal N[2] = {0.5 * (1 - z), 0.5 * (1 + z)}, Nm[2] = {0.5 * (1 - xi), 0.5 * (1 + xi)}, Phi[2];
    Phi[0] = basis == M2D_MORTAR_DUAL ? 2 * N[0] - N[1] : N[0];
    Phi[1] = basis == M2D_MORTAR_DUAL ? 2 * N[1] - N[0] : N[1];
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2; j++) {
        D[2 * i + j] += w * Phi[i] * N[j];
        M[2 * i + j] += w * Phi[i] * Nm[j];
      }
  }
}

/* ---- row building: a small accumulator per row ---- */
typedef struct {
  PetscInt   n, cap;
  PetscInt  *col;
  PetscReal *val;
} RowAcc;

/* the rows of one surface pair while they are built, one per non-mortar node:
 * its accumulator, gap constant and weight, and whether it gets a multiplier */
typedef struct {
  PetscInt   nnode;
  RowAcc    *acc;
  PetscReal *g0, *w;
  PetscBool *keep;
} RowSet;

static PetscErrorCode RowsStart(PetscInt nnode, RowSet *rs)
{
  PetscFunctionBeginUser;
  rs->nnode = nnode;
  PetscCall(PetscCalloc1(nnode + 1, &rs->acc));
  PetscCall(PetscCalloc3(nnode + 1, &rs->g0, nnode + 1, &rs->w, nnode + 1, &rs->keep));
  PetscFunctionReturn(0);
}

static PetscErrorCode RowAdd(RowAcc *r, PetscInt col, PetscReal v)
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < r->n; k++)
    if (r->col[k] == col) {
      r->val[k] += v;
      PetscFunctionReturn(0);
    }
  if (r->n == r->cap) {
    r->cap = r->cap ? 2 * r->cap : 8;
    PetscCall(PetscRealloc(r->cap * sizeof(*r->col), &r->col));
    PetscCall(PetscRealloc(r->cap * sizeof(*r->val), &r->val));
  }
  r->col[r->n]   = col;
  r->val[r->n++] = v;
  PetscFunctionReturn(0);
}

/* add to row `row` coefficient c times the normal n at node i of surface s.
 * The row's coefficients sum to zero (sum_k D_jk = sum_l M_jl, both the
 * integral of the multiplier's basis function over the segments; NTS: a_s (1 - N_1 - N_2)),
 * so the gap may be taken relative to any point: relative to the row's own
 * node `ref` it is computed from differences of nearby coordinates, exact for
 * coincident surfaces instead of a difference of large sums. */
static PetscErrorCode RowAddNode(RowSet *rs, PetscInt row, const M2dSurface *s, PetscInt i, PetscReal c, const PetscReal n[2], const PetscReal ref[2])
{
  PetscFunctionBeginUser;
  PetscCall(RowAdd(&rs->acc[row], s->gdof[i], c * n[0]));
  PetscCall(RowAdd(&rs->acc[row], s->gdof[i] + 1, c * n[1]));
  rs->g0[row] += c * (n[0] * (s->x[2 * i] - ref[0]) + n[1] * (s->x[2 * i + 1] - ref[1]));
  PetscFunctionReturn(0);
}

/* compress the accumulators of the kept nodes into R; frees rs */
static PetscErrorCode RowsFinish(RowSet *rs, M2dContactRows *R)
{
  RowAcc  *acc = rs->acc;
  PetscInt nnz = 0, k = 0;

  PetscFunctionBeginUser;
  R->n = 0;
  for (PetscInt i = 0; i < rs->nnode; i++)
    if (rs->keep[i]) {
      R->n++;
      nnz += acc[i].n;
    }
  PetscCall(PetscMalloc4(R->n + 1, &R->node, R->n + 1, &R->ptr, R->n + 1, &R->g0, R->n + 1, &R->w));
  PetscCall(PetscMalloc2(nnz + 1, &R->col, nnz + 1, &R->val));
  R->ptr[0] = 0;
  for (PetscInt i = 0; i < rs->nnode; i++) {
    if (rs->keep[i]) {
      R->node[k] = i;
      R->g0[k]   = rs->g0[i];
      R->w[k]    = rs->w[i];
      for (PetscInt j = 0; j < acc[i].n; j++) {
        R->col[R->ptr[k] + j] = acc[i].col[j];
        R->val[R->ptr[k] + j] = acc[i].val[j];
      }
      R->ptr[k + 1] = R->ptr[k] + acc[i].n;
      k++;
    }
    PetscCall(PetscFree(acc[i].col));
    PetscCall(PetscFree(acc[i].val));
  }
  PetscCall(PetscFree(rs->acc));
  PetscCall(PetscFree3(rs->g0, rs->w, rs->keep));
  PetscFunctionReturn(0);
}

/* the nodes of surface a that coincide with a node of surface b (within 1e-6
 * of the shorter edge) whose edges lie on b's edges at that node (their
 * normals opposite within 1e-6): a vertex of the one polygon both surfaces
 * are there. From the segments' edges (the only ones that can meet). */
static void CommonVertices(const M2dSurface *nm, const M2dSurface *m, const M2dSegmentSet *S, PetscBool cnm[], PetscBool cm[])
{
  for (PetscInt k = 0; k < S->nseg; k++) {
    const M2dSegment *sg  = &S->seg[k];
    PetscReal         tol = 1e-6 * PetscMin(nm->len[sg->nm_edge], m->len[sg->m_edge]);
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2; j++) {
        PetscInt a = nm->edge[2 * sg->nm_edge + i], b = m->edge[2 * sg->m_edge + j], na = nm->n2e_ptr[a + 1] - nm->n2e_ptr[a], match = 0, used = 0;
        if ((cnm[a] && cm[b]) || na != m->n2e_ptr[b + 1] - m->n2e_ptr[b] || PetscSqr(nm->x[2 * a] - m->x[2 * b]) + PetscSqr(nm->x[2 * a + 1] - m->x[2 * b + 1]) > tol * tol) continue;
        if (na > 8) continue; /* a branch: no polygon */
        for (PetscInt p = nm->n2e_ptr[a]; p < nm->n2e_ptr[a + 1]; p++) { /* each edge on its own edge of the other side */
          const PetscReal *ne = &nm->normal[2 * nm->n2e[p]];
          for (PetscInt q = m->n2e_ptr[b]; q < m->n2e_ptr[b + 1]; q++) {
            const PetscReal *nf = &m->normal[2 * m->n2e[q]];
            if (!(used & (1 << (q - m->n2e_ptr[b]))) && PetscAbsReal(ne[0] + nf[0]) + PetscAbsReal(ne[1] + nf[1]) <= 1e-6) {
              used |= 1 << (q - m->n2e_ptr[b]);
              match++;
              break;
            }
          }
        }
        if (match == na) cnm[a] = cm[b] = PETSC_TRUE;
      }
  }
}

/* mark the corners of surface s: nodes where it turns by more than
 * M2D_SURFACE_CORNER degrees, where the average of the edges' normals is
 * the normal of neither */
static void Corners(const M2dSurface *s, PetscBool sharp[])
{
  const PetscReal cmin = PetscCosReal(M2D_SURFACE_CORNER * PETSC_PI / 180);
  for (PetscInt i = 0; i < s->nnode; i++) {
    const PetscInt *e = &s->n2e[s->n2e_ptr[i]];
    if (s->n2e_ptr[i + 1] - s->n2e_ptr[i] == 2 && s->normal[2 * e[0]] * s->normal[2 * e[1]] + s->normal[2 * e[0] + 1] * s->normal[2 * e[1] + 1] < cmin) sharp[i] = PETSC_TRUE;
  }
}

/* the end normals of surface s's edges: the edge's own normal at a sharp
 * node (a common vertex or a corner), the node's normal elsewhere */
static void EndNormals(const M2dSurface *s, const PetscBool common[], PetscReal *en)
{
  for (PetscInt e = 0; e < s->nedge; e++)
    for (int end = 0; end < 2; end++) {
      PetscInt i = s->edge[2 * e + end];
      if (common[i]) {
        en[4 * e + 2 * end]     = s->normal[2 * e];
        en[4 * e + 2 * end + 1] = s->normal[2 * e + 1];
      } else SurfaceNodeNormal(s, i, &en[4 * e + 2 * end]);
    }
}

/* the unit vector along a - b (the two normals face each other: |a - b| >= sqrt(2)) */
static void Bisector(const PetscReal a[2], const PetscReal b[2], PetscReal n[2])
{
  PetscReal l;
  n[0] = a[0] - b[0];
  n[1] = a[1] - b[1];
  l    = PetscSqrtReal(n[0] * n[0] + n[1] * n[1]);
  if (l > 0) n[0] /= l, n[1] /= l;
}

PetscErrorCode MortarRowNormals(const M2dSurface *nm, const M2dSurface *m, const M2dSegmentSet *S, PetscReal n[])
{
  PetscReal *dist, *enn, *enm, *nn;
  PetscBool *cnm, *cm;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc4(2 * nm->nedge + nm->nnode + 1, &dist, 4 * nm->nedge + 1, &enn, 4 * m->nedge + 1, &enm, 2 * nm->nnode + 1, &nn));
  PetscCall(PetscCalloc2(nm->nnode + 1, &cnm, m->nnode + 1, &cm));
  CommonVertices(nm, m, S, cnm, cm);
  Corners(nm, cnm);
  Corners(m, cm);
  EndNormals(nm, cnm, enn);
  EndNormals(m, cm, enm);
  for (PetscInt k = 0; k < 2 * nm->nedge + nm->nnode; k++) dist[k] = PETSC_MAX_REAL;
  for (PetscInt k = 0; k < 2 * nm->nedge; k++) n[2 * k] = n[2 * k + 1] = 0;
  /* the segment nearest (in zeta) to the node on each of its edges gives, at a
   * sharp node, that edge's direction; elsewhere the nearest on either edge
   * gives the node's one direction */
  for (PetscInt k = 0; k < S->nseg; k++) {
    const M2dSegment *sg = &S->seg[k];
    const PetscReal  *me = &enm[4 * sg->m_edge];
    for (int end = 0; end < 2; end++) { /* node `end` of the non-mortar edge sits at zeta = -1 or +1 */
      PetscInt  q = 2 * sg->nm_edge + end, i = nm->edge[q], at = cnm[i] ? q : 2 * nm->nedge + i;
      PetscReal z = end ? 1.0 : -1.0, d = z < sg->zeta[0] ? sg->zeta[0] - z : z > sg->zeta[1] ? z - sg->zeta[1] : 0, xi, mn[2], l;
      if (!(d < dist[at])) continue;
      dist[at] = d;
      xi       = sg->xi[0] + (sg->xi[1] - sg->xi[0]) * (z - sg->zeta[0]) / (sg->zeta[1] - sg->zeta[0]);
      xi       = PetscMax(-1.0, PetscMin(1.0, xi));
      for (int c = 0; c < 2; c++) mn[c] = 0.5 * (1 - xi) * me[c] + 0.5 * (1 + xi) * me[2 + c];
      l = PetscSqrtReal(mn[0] * mn[0] + mn[1] * mn[1]);
      if (l > 0) mn[0] /= l, mn[1] /= l;
      Bisector(mn, &enn[2 * q], cnm[i] ? &n[2 * q] : &nn[2 * i]);
    }
  }
  for (PetscInt q = 0; q < 2 * nm->nedge; q++) {
    PetscInt i = nm->edge[q];
    if (!cnm[i] && dist[2 * nm->nedge + i] < PETSC_MAX_REAL) n[2 * q] = nn[2 * i], n[2 * q + 1] = nn[2 * i + 1];
  }
  PetscCall(PetscFree4(dist, enn, enm, nn));
  PetscCall(PetscFree2(cnm, cm));
  PetscFunctionReturn(0);
}

/* the mortar surface walked as chains (open ends first, then closed loops):
 * epos[e] the edge's place in its chain, npos[i] the place of the edge that
 * leaves node i (the one that arrives: npos[i] - 1), chain[] and loop[]
 * per node, len[] per chain. PETSC_FALSE if a node has more than two edges. */
static PetscBool ChainWalk(const M2dSurface *m, PetscInt epos[], PetscInt npos[], PetscInt chain[], PetscBool loop[], PetscInt len[])
{
  PetscInt nch = 0;
  for (PetscInt i = 0; i < m->nnode; i++) {
    if (m->n2e_ptr[i + 1] - m->n2e_ptr[i] > 2) return PETSC_FALSE;
    chain[i] = -1;
  }
  for (int pass = 0; pass < 2; pass++)
    for (PetscInt i0 = 0; i0 < m->nnode; i0++) {
      PetscInt i = i0, k = 0;
      if (chain[i0] >= 0 || (pass == 0 && m->n2e_ptr[i0 + 1] - m->n2e_ptr[i0] != 1)) continue;
      while (i >= 0 && chain[i] < 0) { /* follow the edges that leave i (body on the left: edge[2 e] == i) */
        PetscInt next = -1;
        chain[i] = nch, loop[i] = (PetscBool)pass, npos[i] = k;
        for (PetscInt q = m->n2e_ptr[i]; q < m->n2e_ptr[i + 1]; q++)
          if (m->edge[2 * m->n2e[q]] == i) epos[m->n2e[q]] = k, next = m->edge[2 * m->n2e[q] + 1];
        k++;
        i = next;
      }
      len[nch++] = k;
    }
  return PETSC_TRUE;
}

PetscErrorCode MortarReachedCorner(const M2dSurface *nm, const M2dSurface *m, const M2dSegmentSet *S, PetscInt *corner, PetscReal *turn)
{
  PetscBool      *cnm, *cm, *loop;
  PetscInt       *epos, *npos, *chain, *len, *lo, *hi, *ch;
  const PetscReal cmin = PetscCosReal(M2D_SURFACE_CORNER * PETSC_PI / 180);

  PetscFunctionBeginUser;
  *corner = -1;
  *turn   = 0;
  PetscCall(PetscCalloc3(nm->nnode + 1, &cnm, m->nnode + 1, &cm, m->nnode + 1, &loop));
  PetscCall(PetscMalloc4(m->nedge + 1, &epos, m->nnode + 1, &npos, m->nnode + 1, &chain, m->nnode + 1, &len));
  PetscCall(PetscMalloc3(nm->nnode + 1, &lo, nm->nnode + 1, &hi, nm->nnode + 1, &ch));
  if (ChainWalk(m, epos, npos, chain, loop, len)) {
    CommonVertices(nm, m, S, cnm, cm);
    /* the mortar edges each non-mortar node's row reaches: their places in one chain */
    for (PetscInt i = 0; i < nm->nnode; i++) lo[i] = PETSC_MAX_INT, hi[i] = -1, ch[i] = -1;
    for (PetscInt k = 0; k < S->nseg; k++) {
      PetscInt f = S->seg[k].m_edge, c = chain[m->edge[2 * f]];
      for (int end = 0; end < 2; end++) {
        PetscInt i = nm->edge[2 * S->seg[k].nm_edge + end];
        if (ch[i] == -1) ch[i] = c;
        if (ch[i] != c) ch[i] = -2; /* two chains: no corner between them */
        lo[i] = PetscMin(lo[i], epos[f]), hi[i] = PetscMax(hi[i], epos[f]);
      }
    }
    for (PetscInt c = 0; c < m->nnode && *corner < 0; c++) { /* a convex corner, not shared, that a row reaches on both sides */
      const PetscInt *e = &m->n2e[m->n2e_ptr[c]];
      PetscInt        in, out;
      PetscReal       cs;
      if (m->n2e_ptr[c + 1] - m->n2e_ptr[c] != 2 || cm[c]) continue;
      cs = m->normal[2 * e[0]] * m->normal[2 * e[1]] + m->normal[2 * e[0] + 1] * m->normal[2 * e[1] + 1];
      in  = m->edge[2 * e[0] + 1] == c ? e[0] : e[1];
      out = in == e[0] ? e[1] : e[0];
      /* body on the left: the normals turning left is a convex corner */
      if (!(cs < cmin) || !(m->normal[2 * in] * m->normal[2 * out + 1] - m->normal[2 * in + 1] * m->normal[2 * out] > 0)) continue;
      for (PetscInt i = 0; i < nm->nnode && *corner < 0; i++) {
        PetscInt k = npos[c];
        if (ch[i] != chain[c]) continue;
        if (loop[c] && 2 * (hi[i] - lo[i]) > len[chain[c]] ? (k <= lo[i] || k > hi[i]) : (lo[i] < k && k <= hi[i])) *corner = c, *turn = PetscAcosReal(PetscMax(-1, cs)) * 180 / PETSC_PI;
      }
    }
  }
  PetscCall(PetscFree3(cnm, cm, loop));
  PetscCall(PetscFree4(epos, npos, chain, len));
  PetscCall(PetscFree3(lo, hi, ch));
  PetscFunctionReturn(0);
}

/* the direction of a row: the normal n, or the tangent (-n_y, n_x) */
static void RowDirection(const PetscReal n[2], PetscBool tangent, PetscReal d[2])
{
  PetscReal n0 = n[0], n1 = n[1]; /* d may be n */
  d[0] = tangent ? -n1 : n0;
  d[1] = tangent ? n0 : n1;
}

/* a tangential row's constant: the slip is measured from the state a load
 * step starts from (kkt.h), not from the geometry */
static void ZeroGapConstants(M2dContactRows *R)
{
  for (PetscInt j = 0; j < R->n; j++) R->g0[j] = 0;
}

PetscErrorCode MortarRows(const M2dSurface *nm, const M2dSurface *m, const M2dSegmentSet *S, M2dMortarBasis basis, PetscBool tangent, M2dContactRows *R)
{
  RowSet     rs;
  PetscReal *n;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(4 * nm->nedge + 1, &n));
  PetscCall(MortarRowNormals(nm, m, S, n));
  for (PetscInt q = 0; q < 2 * nm->nedge; q++) RowDirection(&n[2 * q], tangent, &n[2 * q]); /* a tangential row: t = (-n_y, n_x) on each edge */
  PetscCall(RowsStart(nm->nnode, &rs));
  for (PetscInt k = 0; k < S->nseg; k++) {
    const M2dSegment *s  = &S->seg[k];
    const PetscInt   *en = &nm->edge[2 * s->nm_edge], *em = &m->edge[2 * s->m_edge];
    PetscReal         D[4], M[4];
    MortarSegmentDM(nm, s, basis, D, M);
    for (int i = 0; i < 2; i++) {
      const PetscReal *ni = &n[4 * s->nm_edge + 2 * i];
      for (int j = 0; j < 2; j++) {
        PetscCall(RowAddNode(&rs, en[i], nm, en[j], D[2 * i + j], ni, &nm->x[2 * en[i]]));
        PetscCall(RowAddNode(&rs, en[i], m, em[j], -M[2 * i + j], ni, &nm->x[2 * en[i]]));
      }
      rs.w[en[i]] += D[2 * i] + D[2 * i + 1];
    }
  }
  /* a node gets a multiplier if the mortar surface covers a non-negligible part of its support */
  for (PetscInt i = 0; i < nm->nnode; i++) {
    PetscReal support = 0;
    for (PetscInt k = nm->n2e_ptr[i]; k < nm->n2e_ptr[i + 1]; k++) support += 0.5 * nm->len[nm->n2e[k]];
    rs.keep[i] = (PetscBool)(rs.w[i] > 1e-10 * support);
  }
  PetscCall(RowsFinish(&rs, R));
  PetscCall(PetscFree(n));
  if (tangent) ZeroGapConstants(R);
  PetscFunctionReturn(0);
}

/* NTS: the key of mortar edge f for node p (normal nn): |gap| along f's
 * normal from p's projection, clamped to f, for a facing edge that p projects
 * onto within reach; -1 otherwise */
typedef struct {
  const M2dSurface *m;
  const PetscReal  *p, *nn;
  PetscReal         reach;
} NTSKey;

static PetscReal NTSGap(void *ctx, PetscInt f)
{
  const NTSKey *k = (const NTSKey *)ctx;
  PetscReal     xi, q[2], g;
  if (k->nn[0] * k->m->normal[2 * f] + k->nn[1] * k->m->normal[2 * f + 1] >= 0) return -1;
  xi = MortarParam(k->m, f, k->p);
  if (xi < -1 - 1e-12 || xi > 1 + 1e-12) return -1;
  EdgePoint(k->m, f, PetscMax(-1.0, PetscMin(1.0, xi)), q);
  g = PetscAbsReal((k->p[0] - q[0]) * k->m->normal[2 * f] + (k->p[1] - q[1]) * k->m->normal[2 * f + 1]);
  return g <= k->reach ? g : -1;
}

PetscErrorCode NTSRows(const M2dSurface *nm, const M2dSurface *m, PetscReal reach, PetscBool tangent, M2dContactRows *R)
{
  RowSet         rs;
  M2dSurfaceTree tree;

  PetscFunctionBeginUser;
  PetscCall(RowsStart(nm->nnode, &rs));
  PetscCall(SurfaceTreeCreate(m, &tree));
  for (PetscInt i = 0; i < nm->nnode; i++) {
    const PetscReal *p = &nm->x[2 * i];
    PetscReal        nn[2], best, bxi, a = 0;
    NTSKey           key = {m, p, nn, reach};
    PetscInt         bf;
    SurfaceNodeNormal(nm, i, nn);
    bf = SurfaceTreeNearest(&tree, p, NTSGap, &key, reach, &best); /* the closest point (seed eq. 6) */
    if (bf < 0) continue;
    bxi = PetscMax(-1.0, PetscMin(1.0, MortarParam(m, bf, p)));
    for (PetscInt k = nm->n2e_ptr[i]; k < nm->n2e_ptr[i + 1]; k++) a += 0.5 * nm->len[nm->n2e[k]];
    {
      const PetscInt *em = &m->edge[2 * bf];
      PetscReal       n[2];
      RowDirection(&m->normal[2 * bf], tangent, n);
      PetscCall(RowAddNode(&rs, i, nm, i, a, n, p));
      PetscCall(RowAddNode(&rs, i, m, em[0], -a * 0.5 * (1 - bxi), n, p));
      PetscCall(RowAddNode(&rs, i, m, em[1], -a * 0.5 * (1 + bxi), n, p));
    }
    rs.w[i]    = a;
    rs.keep[i] = PETSC_TRUE;
  }
  PetscCall(SurfaceTreeDestroy(&tree));
  PetscCall(RowsFinish(&rs, R));
  if (tangent) ZeroGapConstants(R);
  PetscFunctionReturn(0);
}

PetscErrorCode ContactRowsDestroy(M2dContactRows *R)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree4(R->node, R->ptr, R->g0, R->w));
  PetscCall(PetscFree2(R->col, R->val));
  R->n = 0;
  PetscFunctionReturn(0);
}
