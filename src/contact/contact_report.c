/* contact_report.c - what the report reads off the interface (see contact_report.h). */
#include "contact_report.h"

static int CmpXY(const void *a, const void *b)
{
  const M2dXYIdx *p = (const M2dXYIdx *)a, *q = (const M2dXYIdx *)b;
  if (p->x != q->x) return p->x < q->x ? -1 : 1;
  return (p->y > q->y) - (p->y < q->y);
}

PetscErrorCode ContactWriteCSV(const M2dContact *c, PetscInt nstep, const PetscReal *const steps[], const char *run_id, FILE *fp)
{
  M2dXYIdx *o;
  PetscBool friction = (PetscBool)(c->R.n > c->nnormal);

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(c->nnormal + 1, &o));
  fprintf(fp, "%sx,y,gap,pressure,weight,active,pair,%srun_id\n", nstep ? "step," : "", friction ? "traction_t,slip,slip_increment,status," : "");
  for (PetscInt k = 0; k < PetscMax(nstep, 1); k++)
    for (PetscInt q = 0; q < c->npair; q++) {
      const M2dContactPair *p = &c->pair[q];
      for (PetscInt j = 0; j < p->R.n; j++) {
        o[j].x = p->nm.x[2 * p->R.node[j]];
        o[j].y = p->nm.x[2 * p->R.node[j] + 1];
        o[j].j = j;
      }
      qsort(o, (size_t)p->R.n, sizeof(M2dXYIdx), CmpXY);
      for (PetscInt i = 0; i < p->R.n; i++) {
        PetscInt   j = o[i].j;
        PetscReal  v[7];
        if (nstep) for (int f = 0; f < 7; f++) v[f] = steps[k][7 * (p->off + j) + f]; /* M2D_STEP_NODE_FIELDS (solver.h) */
        else v[0] = p->pressure[j], v[1] = p->gap[j], v[2] = p->active[j], v[3] = p->traction[j], v[4] = p->slip[j], v[5] = p->slip_inc[j], v[6] = p->status[j];
        if (nstep) fprintf(fp, "%d,", (int)k + 1);
        fprintf(fp, "%.17g,%.17g,%.17g,%.17g,%.17g,%d,%d,", (double)o[i].x, (double)o[i].y, (double)v[1], (double)v[0], (double)p->R.w[j], v[2] != 0, (int)q + 1);
        if (friction) fprintf(fp, "%.17g,%.17g,%.17g,%d,", (double)v[3], (double)v[4], (double)v[5], (int)v[6]);
        fprintf(fp, "%s\n", run_id);
      }
    }
  PetscCall(PetscFree(o));
  PetscFunctionReturn(0);
}

/* the neighbour of node i along the surface other than `from` (-1: none, or a
 * branch: more than two edges at i) */
static PetscInt NextNode(const M2dSurface *s, PetscInt i, PetscInt from)
{
  PetscInt nb = -1;
  if (s->n2e_ptr[i + 1] - s->n2e_ptr[i] > 2) return -1;
  for (PetscInt k = s->n2e_ptr[i]; k < s->n2e_ptr[i + 1]; k++) {
    PetscInt e = s->n2e[k], o = s->edge[2 * e] == i ? s->edge[2 * e + 1] : s->edge[2 * e];
    if (o != from) nb = o;
  }
  return nb;
}

static PetscErrorCode PairRipple(const M2dContactPair *c, PetscReal *ripple, PetscInt *ninterior)
{
  const M2dSurface *s = &c->nm;
  PetscInt         *mult;
  PetscReal         peak = 0;

  PetscFunctionBeginUser;
  *ripple    = 0;
  *ninterior = 0;
  PetscCall(PetscMalloc1(s->nnode + 1, &mult));
  for (PetscInt i = 0; i < s->nnode; i++) mult[i] = -1;
  for (PetscInt j = 0; j < c->R.n; j++)
    if (c->active[j] != 0) {
      mult[c->R.node[j]] = j;
      peak               = PetscMax(peak, c->pressure[j]);
    }
  for (PetscInt j = 0; j < c->R.n && peak > 0; j++) {
    PetscInt  i = c->R.node[j], nb[2] = {-1, -1}, k = 0;
    PetscReal d[2], lin;
    if (mult[i] < 0 || s->n2e_ptr[i + 1] - s->n2e_ptr[i] != 2) continue;
    for (PetscInt q = s->n2e_ptr[i]; q < s->n2e_ptr[i + 1]; q++) {
      PetscInt e = s->n2e[q];
      nb[k]      = s->edge[2 * e] == i ? s->edge[2 * e + 1] : s->edge[2 * e];
      d[k++]     = s->len[e];
    }
    /* three active nodes on each side: the zone's own edge, where p ~ sqrt(a - x),
     * is not ripple (sampled at 20 nodes over the zone, Hertz's exact pressure
     * deviates from its neighbours' chord by 1.6% of the peak at the second
     * active node from the edge, 0.9% at the third, 0.6% at the fourth) */
    for (int side = 0, ok = 1; side < 2 && ok; side++) {
      PetscInt from = i, at = nb[side];
      for (int d = 0; d < 3 && ok; d++) {
        ok = at >= 0 && mult[at] >= 0;
        if (ok) {
          PetscInt nx = NextNode(s, at, from);
          from = at, at = nx;
        }
      }
      if (!ok) nb[0] = -1;
    }
    if (nb[0] < 0) continue;
    lin     = (d[1] * c->pressure[mult[nb[0]]] + d[0] * c->pressure[mult[nb[1]]]) / (d[0] + d[1]);
    *ripple = PetscMax(*ripple, PetscAbsReal(c->pressure[j] - lin) / peak);
    (*ninterior)++;
  }
  PetscCall(PetscFree(mult));
  PetscFunctionReturn(0);
}

/* the pressure of a node along a chain: its multiplier's, 0 without one */
typedef struct {
  PetscReal s, p;   /* arc length from the chain's start, pressure */
  PetscBool active;
} ChainNode;

/* int over [s0, s1] of (p*(t) - lambda_h(t))^2, p* = sqrt(max(0, c0 + c1 t)),
 * lambda_h linear between the chain's nodes: composite midpoint rule, 64
 * points per element (the square root's kink at its zero needs them) */
static PetscReal EdgeError(const ChainNode *n, PetscInt k0, PetscInt k1, PetscReal c0, PetscReal c1)
{
  PetscReal e = 0;
  for (PetscInt k = k0; k < k1; k++) {
    PetscReal h = n[k + 1].s - n[k].s;
    for (int q = 0; q < 64; q++) {
      PetscReal t = (q + 0.5) / 64, x = n[k].s + t * h, lin = (1 - t) * n[k].p + t * n[k + 1].p, ps = PetscSqrtReal(PetscMax(0, c0 + c1 * x));
      e += h / 64 * PetscSqr(ps - lin);
    }
  }
  return e;
}

/* one chain of nodes along the surface (see ContactPressureEstimate) */
static void ChainEstimate(const ChainNode *n, PetscInt len, PetscReal *e2, PetscReal *n2)
{
  for (PetscInt i = 0; i + 1 < len; i++) { /* ||lambda_h||^2, exact for the linear interpolant */
    PetscReal h = n[i + 1].s - n[i].s;
    *n2 += h / 3 * (n[i].p * n[i].p + n[i].p * n[i + 1].p + n[i + 1].p * n[i + 1].p);
  }
  for (PetscInt i = 1; i + 1 < len; i++) { /* interior: the interpolation error of the local parabola, h^5 p''^2 / 120 */
    PetscReal h0 = n[i].s - n[i - 1].s, h1 = n[i + 1].s - n[i].s, hh = 0.5 * (h0 + h1), d2;
    if (!n[i - 1].active || !n[i].active || !n[i + 1].active || !(h0 > 0 && h1 > 0)) continue;
    d2 = 2 * ((n[i + 1].p - n[i].p) / h1 - (n[i].p - n[i - 1].p) / h0) / (h0 + h1);
    *e2 += PetscSqr(d2 * hh * hh) * hh / 120;
  }
  for (PetscInt k = 0; k < len; k++) /* zone edges: an active node next to an inactive one, two more active behind it */
    for (int d = -1; d <= 1; d += 2) {
      PetscInt  a = k - d, b = k - 2 * d, o = k + d, lo, hi;
      PetscReal sx = 0, sy = 0, sxx = 0, sxy = 0, c0, c1, det;
      if (!n[k].active || o < 0 || o >= len || n[o].active || a < 0 || a >= len || b < 0 || b >= len || !n[a].active || !n[b].active) continue;
      for (int j = 0; j < 3; j++) { /* least squares p^2 = c0 + c1 s through the three */
        const ChainNode *m = &n[k - j * d];
        sx += m->s, sy += m->p * m->p, sxx += m->s * m->s, sxy += m->s * m->p * m->p;
      }
      det = 3 * sxx - sx * sx;
      if (!(det > 0)) continue;
      c1 = (3 * sxy - sx * sy) / det;
      c0 = (sy - c1 * sx) / 3;
      if (!(c1 * d < 0)) continue; /* p^2 must fall towards the edge */
      lo = PetscMax(0, PetscMin(b, k + 2 * d));
      hi = PetscMin(len - 1, PetscMax(b, k + 2 * d));
      *e2 += EdgeError(n, lo, hi, c0, c1);
    }
}

PetscErrorCode ContactRipple(const M2dContact *c, PetscReal *ripple, PetscInt *ninterior)
{
  PetscFunctionBeginUser;
  *ripple    = 0;
  *ninterior = 0;
  for (PetscInt q = 0; q < c->npair; q++) {
    PetscReal r;
    PetscInt  n;
    PetscCall(PairRipple(&c->pair[q], &r, &n));
    *ripple = PetscMax(*ripple, r);
    *ninterior += n;
  }
  PetscFunctionReturn(0);
}

/* one pair's squared error and norm, added to e2 and n2 */
static PetscErrorCode PairPressureEstimate(const M2dContactPair *c, PetscReal *e2p, PetscReal *n2p)
{
  const M2dSurface *s = &c->nm;
  PetscInt         *mult, *deg, *chain;
  PetscBool        *seen;
  ChainNode        *cn;
  PetscReal         e2 = *e2p, n2 = *n2p;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc5(s->nnode + 1, &mult, s->nnode + 1, &deg, s->nnode + 1, &chain, s->nnode + 1, &seen, s->nnode + 1, &cn));
  for (PetscInt i = 0; i < s->nnode; i++) mult[i] = -1, deg[i] = s->n2e_ptr[i + 1] - s->n2e_ptr[i], seen[i] = PETSC_FALSE;
  for (PetscInt j = 0; j < c->R.n; j++) mult[c->R.node[j]] = j;
  for (int pass = 0; pass < 2; pass++) /* chains from their ends first, then closed loops */
    for (PetscInt i0 = 0; i0 < s->nnode; i0++) {
      PetscInt len = 0, i = i0, from = -1;
      if (seen[i0] || (pass == 0 && deg[i0] != 1) || deg[i0] > 2) continue;
      while (i >= 0 && !seen[i] && deg[i] <= 2) {
        PetscInt nx = NextNode(s, i, from);
        seen[i]         = PETSC_TRUE;
        chain[len]      = i;
        cn[len].p       = mult[i] >= 0 ? c->pressure[mult[i]] : 0;
        cn[len].active  = (PetscBool)(mult[i] >= 0 && c->active[mult[i]] != 0);
        cn[len].s       = len ? cn[len - 1].s + PetscSqrtReal(PetscSqr(s->x[2 * i] - s->x[2 * chain[len - 1]]) + PetscSqr(s->x[2 * i + 1] - s->x[2 * chain[len - 1] + 1])) : 0;
        len++;
        from = i, i = nx;
      }
      ChainEstimate(cn, len, &e2, &n2);
    }
  *e2p = e2, *n2p = n2;
  PetscCall(PetscFree5(mult, deg, chain, seen, cn));
  PetscFunctionReturn(0);
}

PetscErrorCode ContactPressureEstimate(const M2dContact *c, PetscReal *est)
{
  PetscReal e2 = 0, n2 = 0;

  PetscFunctionBeginUser;
  for (PetscInt q = 0; q < c->npair; q++) PetscCall(PairPressureEstimate(&c->pair[q], &e2, &n2));
  *est = n2 > 0 ? PetscSqrtReal(e2 / n2) : 0;
  PetscFunctionReturn(0);
}

/* the nodal values v (per normal row of pair c) as functions of x, sorted by
 * x (the nodes' |x| when the pair lies on one side of x = 0, a half model),
 * per unit x: the multiplier is a force per unit length of the non-mortar
 * surface, so v_x = v ds/dx = v / |n_y| (n: the node's normal) */
static PetscErrorCode AlongX(const M2dContactPair *c, PetscBool half, const PetscReal v[], M2dXYIdx *o, PetscReal *px)
{
  PetscInt n = c->R.n;

  PetscFunctionBeginUser;
  for (PetscInt j = 0; j < n; j++) {
    PetscReal nn[2], x = c->nm.x[2 * c->R.node[j]];
    o[j].x = half ? PetscAbsReal(x) : x;
    o[j].y = c->nm.x[2 * c->R.node[j] + 1];
    o[j].j = j;
    SurfaceNodeNormal(&c->nm, c->R.node[j], nn);
    px[j] = v[j] / PetscMax(PetscAbsReal(nn[1]), PETSC_SMALL);
  }
  qsort(o, (size_t)n, sizeof(M2dXYIdx), CmpXY);
  PetscFunctionReturn(0);
}

/* the piecewise linear interpolant of the nodal values px (sorted by o) at x, constant beyond the first node */
static PetscReal Interpolate(const M2dXYIdx *o, const PetscReal *px, PetscInt n, PetscInt *k, PetscReal x)
{
  while (*k + 1 < n && o[*k + 1].x < x) (*k)++;
  if (n == 1 || x <= o[0].x) return px[o[0].j];
  if (*k + 1 < n) {
    PetscReal t = (x - o[*k].x) / (o[*k + 1].x - o[*k].x);
    return (1 - t) * px[o[*k].j] + t * px[o[*k + 1].j];
  }
  return 0;
}

/* does the pair lie on one side of x = 0 (a half model with its symmetry plane there)? */
static PetscBool HalfModel(const M2dContactPair *c)
{
  PetscReal lo = PETSC_MAX_REAL, hi = PETSC_MIN_REAL;
  for (PetscInt j = 0; j < c->R.n; j++) {
    lo = PetscMin(lo, c->nm.x[2 * c->R.node[j]]);
    hi = PetscMax(hi, c->nm.x[2 * c->R.node[j]]);
  }
  return (PetscBool)(lo >= -1e-9 * (hi - lo) || hi <= 1e-9 * (hi - lo));
}

/* the half-width of the nodes where `in` holds: midway between the first and
 * last such node and their outer neighbours (sorted by o; a half model: from 0) */
static void ZoneHalfWidth(const M2dXYIdx *o, PetscInt n, const PetscReal *in, PetscReal inval, PetscBool half, PetscReal *hw, PetscReal *hedge)
{
  PetscInt first = -1, last = -1;
  *hw = *hedge = 0;
  for (PetscInt k = 0; k < n; k++)
    if (in[o[k].j] == inval) {
      if (first < 0) first = k;
      last = k;
    }
  if (last < 0) return;
  {
    PetscReal xr = last + 1 < n ? o[last + 1].x : o[last].x, xl = first > 0 ? o[first - 1].x : o[first].x;
    PetscReal right = 0.5 * (o[last].x + xr), left = 0.5 * (o[first].x + xl);
    *hw    = half ? right : 0.5 * (right - left);
    *hedge = xr - o[last].x;
  }
}

PetscErrorCode ContactHertz(const M2dContactPair *c, const M2dScene *s, M2dHertzResult *h)
{
  M2dXYIdx  *o;
  PetscReal *px, inv = 0, Es, P = s->hertz_load > 0 ? s->hertz_load : c->force_n * (HalfModel(c) ? 2 : 1), R = c->def->hertz_radius, num = 0, den = 0, ne = 0, no = 0, x0;
  PetscInt  n = c->R.n, k = 0, b[2] = {c->nm.body, c->m.body};
  PetscBool half = HalfModel(c);
  const int ns = 3000;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(h, sizeof(*h)));
  PetscCheck(b[0] >= 0 && b[1] >= 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -hertz: %s: a surface without its body", c->def->what);
  for (PetscInt q = 0; q < 2; q++) inv += (s->plane == M2D_PLANE_STRAIN ? 1 - s->body[b[q]].nu * s->body[b[q]].nu : 1.0) / s->body[b[q]].E; /* the pair's two bodies */
  Es    = 1.0 / inv;
  h->a  = PetscSqrtReal(4 * P * R / (PETSC_PI * Es));
  h->p0 = 2 * P / (PETSC_PI * h->a);
  PetscCall(PetscMalloc2(n + 1, &o, n + 1, &px));
  PetscCall(AlongX(c, half, c->pressure, o, px));
  for (PetscInt q = 0; q < n; q++) h->peak_pressure = PetscMax(h->peak_pressure, px[o[q].j]);
  ZoneHalfWidth(o, n, c->active, 1.0, half, &h->half_width, &h->h_edge);
  /* L2 on [0, 1.5 a] (a whole body: [-1.5 a, 1.5 a], and there the even and
   * odd parts (p(x) +- p(-x)) / 2) of the piecewise linear nodal pressure (midpoint rule, fine) */
  x0 = half ? 0 : -1.5 * h->a;
  for (int i = 0; i < ns; i++) {
    PetscReal x = half ? (i + 0.5) * 1.5 * h->a / ns : x0 + (i + 0.5) * 3 * h->a / ns, pe = PetscAbsReal(x) < h->a ? h->p0 * PetscSqrtReal(1 - x * x / (h->a * h->a)) : 0, ph = Interpolate(o, px, n, &k, x);
    num += (ph - pe) * (ph - pe);
    den += pe * pe;
    if (!half) {
      PetscInt  km = 0; /* -x runs backwards: a cursor of its own */
      PetscReal pm = Interpolate(o, px, n, &km, -x);
      ne += PetscSqr(0.5 * (ph + pm) - pe);
      no += PetscSqr(0.5 * (ph - pm));
    }
  }
  h->pressure_l2_rel      = PetscSqrtReal(num / den);
  h->pressure_even_l2_rel = PetscSqrtReal(ne / den);
  h->pressure_odd_rel     = PetscSqrtReal(no / den);
  PetscCall(PetscFree2(o, px));
  PetscFunctionReturn(0);
}

PetscErrorCode ContactCattaneo(const M2dContactPair *c, const M2dScene *s, const M2dHertzResult *h, M2dCattaneoResult *r)
{
  M2dXYIdx  *o;
  PetscReal *qx, sg = c->force_t < 0 ? -1 : 1, ne = 0, no = 0, nq = 0, a = h->a, mu = c->mu, P = s->hertz_load > 0 ? s->hertz_load : c->force_n, Q = PetscAbsReal(c->force_t);
  PetscInt   n = c->R.n, kp = 0;
  const int  ns = 3000;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(r, sizeof(*r)));
  PetscCheck(mu > 0, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -cattaneo: %s has no friction (-contact_friction)", c->def->what);
  r->c_exact = a * PetscSqrtReal(PetscMax(0, 1 - Q / (mu * P)));
  PetscCall(PetscMalloc2(n + 1, &o, n + 1, &qx));
  PetscCall(AlongX(c, PETSC_FALSE, c->traction, o, qx));
  for (PetscInt j = 0; j < n; j++) qx[j] *= sg; /* the friction force's own sign: q > 0 */
  {
    PetscReal hedge;
    ZoneHalfWidth(o, n, c->status, M2D_STATUS_STICK, PETSC_FALSE, &r->c, &hedge);
  }
  /* the even part (q(x) + q(-x)) / 2 against the formula, the odd part (q(x) - q(-x)) / 2 against q, on [-1.5 a, 1.5 a] */
  for (int i = 0; i < ns; i++) {
    PetscInt  km = 0; /* -x runs backwards: a cursor of its own */
    PetscReal x = -1.5 * a + (i + 0.5) * 3 * a / ns, qp = Interpolate(o, qx, n, &kp, x), qm = Interpolate(o, qx, n, &km, -x), qe, cc = r->c_exact;
    qe = PetscAbsReal(x) < a ? mu * h->p0 * PetscSqrtReal(1 - x * x / (a * a)) : 0;
    if (PetscAbsReal(x) < cc) qe -= mu * h->p0 * (cc / a) * PetscSqrtReal(1 - x * x / (cc * cc));
    ne += PetscSqr(0.5 * (qp + qm) - qe);
    no += PetscSqr(0.5 * (qp - qm));
    nq += qe * qe;
  }
  r->shear_l2_rel = PetscSqrtReal(ne / nq);
  r->shear_odd_rel = PetscSqrtReal(no / nq);
  PetscCall(PetscFree2(o, qx));
  PetscFunctionReturn(0);
}

/* one pair's chains oriented along the edges (body on the left) and a loop
 * started at its node of least (x, y) without an active multiplier, so that
 * the order is the geometry's, whatever the gathered numbering (1 or 2
 * ranks): walk chain from node i0 towards `to` */
static PetscInt WalkChain(const M2dSurface *s, PetscInt i0, PetscInt to, PetscBool seen[], PetscInt chain[])
{
  PetscInt len = 0, i = i0, from = -1;
  while (i >= 0 && !seen[i]) {
    PetscInt nx = len == 0 ? to : NextNode(s, i, from);
    seen[i] = PETSC_TRUE, chain[len++] = i;
    from = i, i = nx;
  }
  return len;
}

/* the node after i along its edges' direction (-1: none or a branch) */
static PetscInt Downstream(const M2dSurface *s, PetscInt i)
{
  if (s->n2e_ptr[i + 1] - s->n2e_ptr[i] > 2) return -1;
  for (PetscInt k = s->n2e_ptr[i]; k < s->n2e_ptr[i + 1]; k++)
    if (s->edge[2 * s->n2e[k]] == i) return s->edge[2 * s->n2e[k] + 1];
  return -1;
}

static PetscBool Before(const PetscReal *a, const PetscReal *b)
{
  return (PetscBool)(a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]));
}

PetscErrorCode ContactPairFigures(const M2dContactPair *c, M2dPairFigures *f)
{
  const M2dSurface *s = &c->nm;
  PetscInt         *mult, *chain, *start, nstart = 0;
  PetscBool        *seen, half = HalfModel(c);
  PetscReal         peak = 0, lo = PETSC_MAX_REAL, hi = PETSC_MIN_REAL, hw = -1;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(f, sizeof(*f)));
  f->half_width = -1;
  PetscCall(PetscMalloc4(s->nnode + 1, &mult, 2 * s->nnode + 2, &chain, s->nnode + 1, &start, s->nnode + 1, &seen));
  for (PetscInt i = 0; i < s->nnode; i++) mult[i] = -1, seen[i] = PETSC_FALSE;
  for (PetscInt j = 0; j < c->R.n; j++) {
    mult[c->R.node[j]] = j;
    if (c->active[j] != 0) peak = PetscMax(peak, c->pressure[j]);
    lo = PetscMin(lo, s->x[2 * c->R.node[j]]), hi = PetscMax(hi, s->x[2 * c->R.node[j]]);
  }
  /* the chains' first nodes: tails of open chains, then each loop's least node
   * (an inactive one if it has any), in the order of their (x, y) */
  for (PetscInt i = 0; i < s->nnode; i++) {
    PetscBool tail = PETSC_TRUE;
    for (PetscInt k = s->n2e_ptr[i]; k < s->n2e_ptr[i + 1]; k++) tail = (PetscBool)(tail && s->edge[2 * s->n2e[k] + 1] != i);
    if (tail) start[nstart++] = i, WalkChain(s, i, Downstream(s, i), seen, chain);
  }
  for (PetscInt i0 = 0; i0 < s->nnode; i0++) { /* loops: what the walks from tails left */
    PetscInt best = -1, len;
    if (seen[i0]) continue;
    len = WalkChain(s, i0, Downstream(s, i0), seen, chain);
    for (PetscInt k = 0; k < len; k++) {
      PetscInt  i = chain[k], act = mult[i] >= 0 && c->active[mult[i]] != 0, bact = best >= 0 && mult[best] >= 0 && c->active[mult[best]] != 0;
      if (best < 0 || (act == bact && Before(&s->x[2 * i], &s->x[2 * best])) || (!act && bact)) best = i;
    }
    start[nstart++] = best;
  }
  for (PetscInt a = 1; a < nstart; a++) /* insertion sort by (x, y): a few chains */
    for (PetscInt b = a; b > 0 && Before(&s->x[2 * start[b]], &s->x[2 * start[b - 1]]); b--) {
      PetscInt t = start[b];
      start[b] = start[b - 1], start[b - 1] = t;
    }
  for (PetscInt i = 0; i < s->nnode; i++) seen[i] = PETSC_FALSE;
  for (PetscInt q = 0; q < nstart; q++) {
    PetscInt  len = WalkChain(s, start[q], Downstream(s, start[q]), seen, chain), z0 = -1;
    PetscBool loop = (PetscBool)(len > 2 && Downstream(s, chain[len - 1]) == chain[0]);
    PetscReal *ds;
    if (loop) chain[len++] = chain[0]; /* the closing edge */
    PetscCall(PetscMalloc1(len + 1, &ds));
    for (PetscInt k = 0; k < len; k++) {
      PetscInt i = chain[k], act = mult[i] >= 0 && c->active[mult[i]] != 0;
      ds[k] = k ? PetscSqrtReal(PetscSqr(s->x[2 * i] - s->x[2 * chain[k - 1]]) + PetscSqr(s->x[2 * i + 1] - s->x[2 * chain[k - 1] + 1])) : 0;
      if (act && peak > 0 && c->pressure[mult[i]] >= (1 - 1e-9) * peak && !f->peak) { /* ties within 1e-9: the first along the surface */
        f->peak = c->pressure[mult[i]], f->peak_at[0] = s->x[2 * i], f->peak_at[1] = s->x[2 * i + 1];
      }
      if (act && z0 < 0) z0 = k;
      if (act && (k == len - 1 || !(mult[chain[k + 1]] >= 0 && c->active[mult[chain[k + 1]]] != 0))) { /* a zone z0..k */
        PetscInt  a = chain[z0], b = chain[k];
        PetscReal zl = 0;
        for (PetscInt t = z0 + 1; t <= k; t++) zl += ds[t];
        if (z0 > 0) zl += 0.5 * ds[z0]; /* its ends midway to the neighbours (or at the chain's ends) */
        if (k + 1 < len) zl += 0.5 * PetscSqrtReal(PetscSqr(s->x[2 * chain[k + 1]] - s->x[2 * b]) + PetscSqr(s->x[2 * chain[k + 1] + 1] - s->x[2 * b + 1]));
        if (!f->zones) f->from[0] = s->x[2 * a], f->from[1] = s->x[2 * a + 1];
        f->to[0] = s->x[2 * b], f->to[1] = s->x[2 * b + 1];
        f->length += zl;
        f->zones++;
        { /* its ends at the surface's ends: on x = 0 of a half model (the symmetry plane), or cut */
          PetscBool e0 = (PetscBool)(z0 == 0 && !loop), e1 = (PetscBool)(k == len - 1 && !loop);
          PetscBool ax0 = (PetscBool)(e0 && half && PetscAbsReal(s->x[2 * a]) <= 1e-9 * (hi - lo)), ax1 = (PetscBool)(e1 && half && PetscAbsReal(s->x[2 * b]) <= 1e-9 * (hi - lo));
          hw = !e0 && !e1 ? 0.5 * zl : (e0 != e1 && (ax0 || ax1)) ? zl : -1;
        }
        z0 = -1;
      }
    }
    PetscCall(PetscFree(ds));
  }
  if (f->zones == 1) f->half_width = hw;
  PetscCall(PetscFree4(mult, chain, start, seen));
  PetscFunctionReturn(0);
}
