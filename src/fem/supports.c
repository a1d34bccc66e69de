/* supports.c - rigid-mode check (see supports.h). */
#include "supports.h"
#include <petscblaslapack.h>

/* the three rigid modes of body b at point x, component d */
static void Modes(const M2dSupports *f, PetscInt b, const PetscReal x[2], PetscInt d, PetscReal r[3])
{
  r[0] = d == 0 ? 1 : 0;
  r[1] = d == 1 ? 1 : 0;
  r[2] = d == 0 ? -(x[1] - f->centroid[b][1]) / f->size[b] : (x[0] - f->centroid[b][0]) / f->size[b];
}

/* G += g g^T / |g|^2 for a row g of at most two bodies' modes: idx[0..k) its
 * entries (k <= 6) */
static void AddRow(PetscReal *G, PetscInt n, PetscInt k, const PetscInt idx[], const PetscReal g[])
{
  PetscReal nrm = 0;
  for (PetscInt i = 0; i < k; i++) nrm += g[i] * g[i];
  if (nrm == 0) return;
  for (PetscInt i = 0; i < k; i++)
    for (PetscInt j = 0; j < k; j++) G[idx[i] * n + idx[j]] += g[i] * g[j] / nrm;
}

/* body of each local vertex; centroids and extents of the bodies */
static PetscErrorCode BodyFrames(const M2dMesh *m, PetscInt nb, PetscInt *vbody, M2dSupports *sup)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)m->dm);
  PetscReal          sums[3 * M2D_MAX_BODIES], lo[2 * M2D_MAX_BODIES], hi[2 * M2D_MAX_BODIES];
  PetscSection       cs;
  Vec                cl;
  const PetscScalar *ca;

  PetscFunctionBeginUser;
  PetscCall(PetscArrayzero(sums, 3 * M2D_MAX_BODIES));
  for (PetscInt b = 0; b < nb; b++) {
    lo[2 * b] = lo[2 * b + 1] = PETSC_MAX_REAL;
    hi[2 * b] = hi[2 * b + 1] = PETSC_MIN_REAL;
  }
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(VecGetArrayRead(cl, &ca));
  for (PetscInt c = m->cStart; c < m->cEnd; c++)
    for (int k = 0; k < 4; k++) vbody[m->cellverts[4 * (c - m->cStart) + k] - m->vStart] = m->cellbody[c - m->cStart];
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt off, b = vbody[v - m->vStart];
    PetscCall(PetscSectionGetOffset(cs, v, &off));
    for (int d = 0; d < 2; d++) {
      sums[3 * b + d] += PetscRealPart(ca[off + d]);
      lo[2 * b + d] = PetscMin(lo[2 * b + d], PetscRealPart(ca[off + d]));
      hi[2 * b + d] = PetscMax(hi[2 * b + d], PetscRealPart(ca[off + d]));
    }
    sums[3 * b + 2] += 1;
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 3 * nb, MPIU_REAL, MPIU_SUM, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, lo, 2 * nb, MPIU_REAL, MPIU_MIN, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, hi, 2 * nb, MPIU_REAL, MPIU_MAX, comm));
  for (PetscInt b = 0; b < nb; b++) {
    sup->centroid[b][0] = sums[3 * b] / PetscMax(1, sums[3 * b + 2]);
    sup->centroid[b][1] = sums[3 * b + 1] / PetscMax(1, sums[3 * b + 2]);
    sup->size[b]        = PetscMax(PetscSqrtReal(PetscSqr(hi[2 * b] - lo[2 * b]) + PetscSqr(hi[2 * b + 1] - lo[2 * b + 1])), PETSC_SMALL);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSupportsCreate(const M2dMesh *m, const M2dScene *s, const M2dFrames *fr, PetscInt ndir, const PetscInt drows[], M2dSupports *sup)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)m->dm);
  PetscInt           nb = s->nbody, n = 3 * nb, *vbody, *sorted;
  PetscSection       gsec, cs;
  Vec                cl;
  const PetscScalar *ca;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(sup, sizeof(*sup)));
  sup->nbody = nb;
  PetscCall(PetscCalloc1(n * n + 1, &sup->gram));
  PetscCall(PetscMalloc1(m->vEnd - m->vStart + 1, &vbody));
  PetscCall(BodyFrames(m, nb, vbody, sup));
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(PetscMalloc1(ndir + 1, &sorted));
  PetscCall(PetscArraycpy(sorted, drows, ndir));
  PetscCall(PetscSortInt(ndir, sorted));
  PetscCall(VecGetArrayRead(cl, &ca));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) { /* owned Dirichlet rows */
    PetscInt  goff, off, loc, b = vbody[v - m->vStart];
    PetscReal x[2];
    PetscCall(PetscSectionGetOffset(gsec, v, &goff));
    if (goff < 0) continue;
    PetscCall(PetscSectionGetOffset(cs, v, &off));
    x[0] = PetscRealPart(ca[off]);
    x[1] = PetscRealPart(ca[off + 1]);
    for (PetscInt d = 0; d < 2; d++) {
      PetscCall(PetscFindInt(goff + d, ndir, sorted, &loc));
      if (loc >= 0) { /* the row holds u.dir: dir = e_d, or the frame's n (d = 0) or t (d = 1) */
        PetscReal g[3], rx[3], ry[3], nrm[2], dir[2] = {(PetscReal)(d == 0), (PetscReal)(d == 1)};
        PetscInt  idx[3] = {3 * b, 3 * b + 1, 3 * b + 2};
        if (M2dFramesAt(fr, m, v, nrm)) {
          dir[0] = d == 0 ? nrm[0] : -nrm[1];
          dir[1] = d == 0 ? nrm[1] : nrm[0];
        }
        Modes(sup, b, x, 0, rx);
        Modes(sup, b, x, 1, ry);
        for (int k = 0; k < 3; k++) g[k] = dir[0] * rx[k] + dir[1] * ry[k];
        AddRow(sup->gram, n, 3, idx, g);
      }
    }
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCall(PetscFree(sorted));
  PetscCall(PetscFree(vbody));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sup->gram, n * n, MPIU_REAL, MPIU_SUM, comm));
  PetscFunctionReturn(0);
}

/* the contact rows selected by active, applied to the rigid modes */
static PetscErrorCode AddContactRows(const M2dSupports *sup, const M2dContact *ct, const PetscScalar *active, PetscReal *G)
{
  PetscInt n = 3 * sup->nbody;

  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < ct->npair; p++) { /* every pair: a body held only by contacts is held by all of them together */
    const M2dContactPair *cp    = &ct->pair[p];
    const M2dSurface     *sf[2] = {&cp->nm, &cp->m};
    for (PetscInt j = 0; j < cp->R.n + cp->T.n; j++) { /* the normal rows, then a sticking node's tangential ones */
      const M2dContactRows *R = j < cp->R.n ? &cp->R : &cp->T;
      PetscInt              ir = j < cp->R.n ? j : j - cp->R.n, row = j < cp->R.n ? cp->off + j : cp->toff + ir;
      PetscReal             g[6] = {0}; /* the modes of the pair's two bodies (non-mortar's, mortar's) */
      PetscInt              idx[6];
      if (active && PetscRealPart(active[row]) == 0) continue;
      for (int q = 0; q < 2; q++)
        for (int t = 0; t < 3; t++) idx[3 * q + t] = 3 * sf[q]->body + t;
      for (PetscInt k = R->ptr[ir]; k < R->ptr[ir + 1]; k++) {
        PetscInt col = R->col[k], d = col % 2, base = col - d;
        for (int q = 0; q < 2; q++) {
          PetscInt i;
          PetscCall(PetscFindInt(base, sf[q]->nnode, sf[q]->gdof, &i));
          if (i >= 0) {
            PetscReal r[3];
            Modes(sup, sf[q]->body, &sf[q]->x[2 * i], d, r);
            for (int t = 0; t < 3; t++) g[3 * q + t] += R->val[k] * r[t];
            break;
          }
        }
      }
      AddRow(G, n, 6, idx, g);
    }
  }
  PetscFunctionReturn(0);
}

/* the eigen-decomposition of G with the contact rows selected by active:
 * eigenvalues w ascending, vectors in G; *gmax the scale of a zero one */
/* G (n x n) and w (n), to free with PetscFree2 */
static PetscErrorCode Decompose(const M2dSupports *sup, MPI_Comm comm, const M2dContact *ct, const PetscScalar *active, PetscReal **G, PetscReal **w, PetscReal *gmax)
{
  PetscInt     n = 3 * sup->nbody;
  PetscReal   *work;
  PetscBLASInt bn, lwork = 10 * (PetscBLASInt)n, info;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc2(n * n, G, n, w));
  PetscCall(PetscMalloc1(lwork, &work));
  PetscCall(PetscArraycpy(*G, sup->gram, n * n));
  if (ct) PetscCall(AddContactRows(sup, ct, active, *G));
  PetscCall(PetscBLASIntCast(n, &bn));
  PetscCallBLAS("LAPACKsyev", LAPACKsyev_("V", "U", &bn, *G, &bn, *w, work, &lwork, &info));
  PetscCall(PetscFree(work));
  PetscCheck(info == 0, comm, PETSC_ERR_LIB, "rigid-mode check: LAPACK syev failed (%d)", (int)info);
  *gmax = PetscMax((*w)[n - 1], 1.0);
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSupportsHeld(const M2dSupports *sup, MPI_Comm comm, const M2dContact *ct, const PetscScalar *active, PetscBool *held)
{
  PetscReal *G, *w, gmax;

  PetscFunctionBeginUser;
  PetscCall(Decompose(sup, comm, ct, active, &G, &w, &gmax));
  *held = (PetscBool)(w[0] > 1e-12 * gmax);
  PetscCall(PetscFree2(G, w));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSupportsDestroy(M2dSupports *sup)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(sup->gram));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSupportsCheck(const M2dSupports *sup, MPI_Comm comm, const M2dScene *s, const M2dContact *ct, const PetscScalar *active, const char *when)
{
  PetscInt   n = 3 * sup->nbody, bad = -1;
  PetscReal *G, *w, gmax;
  char       what[96];

  PetscFunctionBeginUser;
  PetscCall(Decompose(sup, comm, ct, active, &G, &w, &gmax));
  for (PetscInt e = 0; e < n; e++) { /* a (near) zero eigenvalue: name the body and the motion that dominates it */
    const PetscReal *vec = &G[e * n];
    PetscInt         imax, b;
    if (w[e] > 1e-12 * gmax) continue;
    PetscReal        vmax = 0, tx, ty, tn;
    for (PetscInt i = 0; i < n; i++) vmax = PetscMax(vmax, PetscAbsReal(vec[i]));
    /* the first body among those (nearly) equally involved: bodies that move
     * together (a free body carrying another through contact) are named the
     * same way whatever round-off the rank count brings */
    for (imax = 0; imax < n && PetscAbsReal(vec[imax]) < (1 - 1e-6) * vmax; imax++) {}
    b  = imax / 3;
    tx = vec[3 * b], ty = vec[3 * b + 1], tn = PetscSqrtReal(tx * tx + ty * ty);
    if (imax % 3 == 2 || tn < 1e-6 * vmax) PetscCall(PetscSNPrintf(what, sizeof(what), "rotation"));
    else if (PetscAbsReal(ty) <= 1e-6 * tn) PetscCall(PetscSNPrintf(what, sizeof(what), "translation in x"));
    else if (PetscAbsReal(tx) <= 1e-6 * tn) PetscCall(PetscSNPrintf(what, sizeof(what), "translation in y"));
    else { /* a support along an inclined boundary: the free direction, sign fixed by its larger component */
      PetscReal sg = (PetscAbsReal(tx) >= PetscAbsReal(ty) ? tx : ty) < 0 ? -1 : 1;
      PetscCall(PetscSNPrintf(what, sizeof(what), "translation along (%.4f, %.4f)", (double)(sg * tx / tn), (double)(sg * ty / tn)));
    }
    bad = b;
    break;
  }
  PetscCall(PetscFree2(G, w));
  if (bad < 0) PetscFunctionReturn(0);
  if (when) SETERRQ(comm, PETSC_ERR_USER_INPUT, "body '%s' is held by nothing against %s %s: the load separates the bodies and no -dirichlet support holds it", s->body[bad].name, what, when);
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "body '%s' is held by nothing against %s: no -dirichlet support and no contact surface resists it (frictionless contact holds only the normal direction)", s->body[bad].name, what);
}
