/* supports.c - rigid-mode check (see supports.h). */
#include "supports.h"
#include <petscblaslapack.h>

#define MAXM (3 * M2D_MAX_BODIES)

typedef struct {
  PetscReal c[M2D_MAX_BODIES][2]; /* centroid */
  PetscReal L[M2D_MAX_BODIES];    /* size, to scale the rotation mode */
} BodyFrame;

/* the three rigid modes of body b at point x, component d */
static void Modes(const BodyFrame *f, PetscInt b, const PetscReal x[2], PetscInt d, PetscReal r[3])
{
  r[0] = d == 0 ? 1 : 0;
  r[1] = d == 1 ? 1 : 0;
  r[2] = d == 0 ? -(x[1] - f->c[b][1]) / f->L[b] : (x[0] - f->c[b][0]) / f->L[b];
}

static void AddRow(PetscReal *G, PetscInt n, const PetscReal *g)
{
  PetscReal nrm = 0;
  for (PetscInt i = 0; i < n; i++) nrm += g[i] * g[i];
  if (nrm == 0) return;
  for (PetscInt i = 0; i < n; i++)
    for (PetscInt j = 0; j < n; j++) G[i * n + j] += g[i] * g[j] / nrm;
}

PetscErrorCode CheckRigidModes(const M2dMesh *m, const M2dScene *s, const M2dContact *ct, PetscInt ndir, const PetscInt drows[])
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)m->dm);
  PetscMPIInt        rank;
  PetscInt           nb = s->nbody, n = 3 * nb, *vbody, *sorted;
  PetscReal          G[MAXM * MAXM], sums[4 * M2D_MAX_BODIES], lo[2 * M2D_MAX_BODIES], hi[2 * M2D_MAX_BODIES];
  BodyFrame          f;
  PetscSection       gsec, cs;
  Vec                cl;
  const PetscScalar *ca;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscArrayzero(G, MAXM * MAXM));
  PetscCall(PetscArrayzero(sums, 4 * M2D_MAX_BODIES));
  for (PetscInt b = 0; b < nb; b++) {
    lo[2 * b] = lo[2 * b + 1] = PETSC_MAX_REAL;
    hi[2 * b] = hi[2 * b + 1] = PETSC_MIN_REAL;
  }
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(VecGetArrayRead(cl, &ca));
  /* body of each local vertex; centroids and extents */
  PetscCall(PetscMalloc1(m->vEnd - m->vStart + 1, &vbody));
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
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 3 * nb, MPIU_REAL, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, lo, 2 * nb, MPIU_REAL, MPI_MIN, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, hi, 2 * nb, MPIU_REAL, MPI_MAX, comm));
  for (PetscInt b = 0; b < nb; b++) {
    f.c[b][0] = sums[3 * b] / PetscMax(1, sums[3 * b + 2]);
    f.c[b][1] = sums[3 * b + 1] / PetscMax(1, sums[3 * b + 2]);
    f.L[b]    = PetscMax(PetscSqrtReal(PetscSqr(hi[2 * b] - lo[2 * b]) + PetscSqr(hi[2 * b + 1] - lo[2 * b + 1])), PETSC_SMALL);
  }
  /* Dirichlet rows (owned) */
  PetscCall(PetscMalloc1(ndir + 1, &sorted));
  PetscCall(PetscArraycpy(sorted, drows, ndir));
  PetscCall(PetscSortInt(ndir, sorted));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt  goff, off, loc, b = vbody[v - m->vStart];
    PetscReal x[2];
    PetscCall(PetscSectionGetOffset(gsec, v, &goff));
    if (goff < 0) continue;
    PetscCall(PetscSectionGetOffset(cs, v, &off));
    x[0] = PetscRealPart(ca[off]);
    x[1] = PetscRealPart(ca[off + 1]);
    for (PetscInt d = 0; d < 2; d++) {
      PetscCall(PetscFindInt(goff + d, ndir, sorted, &loc));
      if (loc >= 0) {
        PetscReal g[MAXM] = {0}, r[3];
        Modes(&f, b, x, d, r);
        for (int k = 0; k < 3; k++) g[3 * b + k] = r[k];
        AddRow(G, n, g);
      }
    }
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCall(PetscFree(sorted));
  PetscCall(PetscFree(vbody));
  /* contact rows: every rank holds them all, rank 0 adds them */
  if (ct && rank == 0) {
    const M2dSurface *sf[2] = {&ct->nm, &ct->m};
    for (PetscInt j = 0; j < ct->R.n; j++) {
      PetscReal g[MAXM] = {0};
      for (PetscInt k = ct->R.ptr[j]; k < ct->R.ptr[j + 1]; k++) {
        PetscInt col = ct->R.col[k], d = col % 2, base = col - d;
        for (int q = 0; q < 2; q++) {
          PetscInt i;
          PetscCall(PetscFindInt(base, sf[q]->nnode, sf[q]->gdof, &i));
          if (i >= 0) {
            PetscReal r[3];
            PetscInt  b = sf[q]->body;
            Modes(&f, b, &sf[q]->x[2 * i], d, r);
            for (int t = 0; t < 3; t++) g[3 * b + t] += ct->R.val[k] * r[t];
            break;
          }
        }
      }
      AddRow(G, n, g);
    }
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, G, n * n, MPIU_REAL, MPI_SUM, comm));
  { /* eigenvalues of G: a (near) zero one is a free rigid motion */
    PetscBLASInt bn, lwork = 10 * MAXM, info;
    PetscReal    w[MAXM], work[10 * MAXM], gmax;
    PetscCall(PetscBLASIntCast(n, &bn));
    PetscCallBLAS("LAPACKsyev", LAPACKsyev_("V", "U", &bn, G, &bn, w, work, &lwork, &info));
    PetscCheck(info == 0, comm, PETSC_ERR_LIB, "rigid-mode check: LAPACK syev failed (%d)", (int)info);
    gmax = PetscMax(w[n - 1], 1.0);
    for (PetscInt e = 0; e < n; e++) {
      if (w[e] > 1e-9 * gmax) continue;
      { /* name the body and the motion that dominates the free mode */
        const PetscReal *vec = &G[e * n];
        PetscInt         imax = 0;
        const char      *what[3] = {"translation in x", "translation in y", "rotation"};
        for (PetscInt i = 1; i < n; i++)
          if (PetscAbsReal(vec[i]) > PetscAbsReal(vec[imax])) imax = i;
        SETERRQ(comm, PETSC_ERR_USER_INPUT, "body '%s' is held by nothing against %s: no -dirichlet support and no contact surface resists it (frictionless contact holds only the normal direction)", s->body[imax / 3].name, what[imax % 3]);
      }
    }
  }
  PetscFunctionReturn(0);
}
