/* mesh_modes.c - the rigid-body modes of the bodies (see mesh.h): the
 * near-null space of K that an algebraic multigrid or a deflated iterative
 * solver needs. A body free of Dirichlet conditions moves rigidly without
 * strain: u = (1, 0), (0, 1) and (-(y - yc), x - xc) on its vertices, zero
 * elsewhere. Bodies that share a vertex move together and count as one. */
#include "mesh_impl.h"

/* comp[b]: the smallest body connected to body b through shared vertices
 * (every rank: vertex body masks summed over the point SF, then closed) */
static PetscErrorCode BodyComponents(const M2dMesh *m, PetscInt nbody, PetscInt *vmask, PetscInt comp[])
{
  MPI_Comm  comm = PetscObjectComm((PetscObject)m->dm);
  PetscSF   sf;
  PetscInt  reach[M2D_MAX_BODIES] = {0};
  PetscBool changed = PETSC_TRUE;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < m->cEnd - m->cStart; c++)
    for (int k = 0; k < 4; k++) vmask[m->cellverts[4 * c + k]] |= (PetscInt)1 << m->cellbody[c];
  PetscCall(DMGetPointSF(m->dm, &sf));
  PetscCall(PetscSFReduceBegin(sf, MPIU_INT, vmask, vmask, MPI_BOR));
  PetscCall(PetscSFReduceEnd(sf, MPIU_INT, vmask, vmask, MPI_BOR));
  PetscCall(PetscSFBcastBegin(sf, MPIU_INT, vmask, vmask, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, MPIU_INT, vmask, vmask, MPI_REPLACE));
  for (PetscInt v = m->vStart; v < m->vEnd; v++)
    for (PetscInt b = 0; b < nbody; b++)
      if (vmask[v] >> b & 1) reach[b] |= vmask[v];
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, reach, (PetscMPIInt)nbody, MPIU_INT, MPI_BOR, comm));
  for (PetscInt b = 0; b < nbody; b++) comp[b] = b;
  while (changed) { /* at most nbody passes over a graph of nbody nodes */
    changed = PETSC_FALSE;
    for (PetscInt b = 0; b < nbody; b++)
      for (PetscInt d = 0; d < nbody; d++)
        if ((reach[b] >> d & 1) && comp[d] < comp[b]) comp[b] = comp[d], changed = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

/* body of each owned vertex (-1: not owned or in no cell), centroid of each
 * component's vertices (xc[2 comp], xc[2 comp + 1]) */
static PetscErrorCode Centroids(const M2dMesh *m, PetscInt nbody, const PetscInt vmask[], const PetscInt comp[], const PetscScalar ca[], PetscSection cs, PetscSection gs, PetscInt vbody[], PetscReal xc[])
{
  PetscReal sum[3 * M2D_MAX_BODIES] = {0};

  PetscFunctionBeginUser;
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt g, off, b = -1;
    PetscCall(PetscSectionGetOffset(gs, v, &g));
    for (PetscInt k = 0; k < nbody && b < 0; k++)
      if (vmask[v] >> k & 1) b = comp[k];
    vbody[v - m->vStart] = g >= 0 ? b : -1;
    if (g < 0 || b < 0) continue;
    PetscCall(PetscSectionGetOffset(cs, v, &off));
    sum[3 * b] += PetscRealPart(ca[off]);
    sum[3 * b + 1] += PetscRealPart(ca[off + 1]);
    sum[3 * b + 2] += 1;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sum, (PetscMPIInt)(3 * nbody), MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)m->dm)));
  for (PetscInt b = 0; b < nbody; b++) {
    xc[2 * b]     = sum[3 * b + 2] > 0 ? sum[3 * b] / sum[3 * b + 2] : 0;
    xc[2 * b + 1] = sum[3 * b + 2] > 0 ? sum[3 * b + 1] / sum[3 * b + 2] : 0;
  }
  PetscFunctionReturn(0);
}

/* modified Gram-Schmidt (collective); a vector that vanishes is an error */
static PetscErrorCode Orthonormalise(PetscInt n, Vec v[])
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n; i++) {
    PetscReal nrm;
    for (PetscInt j = 0; j < i; j++) {
      PetscScalar d;
      PetscCall(VecDot(v[i], v[j], &d));
      PetscCall(VecAXPY(v[i], -d, v[j]));
    }
    PetscCall(VecNormalize(v[i], &nrm));
    PetscCheck(nrm > 0, PetscObjectComm((PetscObject)v[i]), PETSC_ERR_PLIB, "rigid-body mode %" PetscInt_FMT " vanishes", i);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MeshRigidBodyModes(const M2dMesh *m, PetscBool per_body, MatNullSpace *sp)
{
  MPI_Comm           comm = PetscObjectComm((PetscObject)m->dm);
  PetscInt           nbody = 0, comp[M2D_MAX_BODIES], *vmask, *vbody, pStart, pEnd, lo, nvec = 0, idx[M2D_MAX_BODIES];
  PetscReal          xc[2 * M2D_MAX_BODIES];
  PetscSection       cs, gs;
  Vec                cl, g, *z;
  const PetscScalar *ca;
  PetscScalar      **za;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < m->cEnd - m->cStart; c++) nbody = PetscMax(nbody, m->cellbody[c] + 1);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &nbody, 1, MPIU_INT, MPI_MAX, comm));
  PetscCall(DMPlexGetChart(m->dm, &pStart, &pEnd));
  PetscCall(PetscCalloc2(pEnd + 1, &vmask, m->vEnd - m->vStart + 1, &vbody));
  PetscCall(BodyComponents(m, nbody, vmask, comp));
  if (!per_body)
    for (PetscInt b = 0; b < nbody; b++) comp[b] = 0;
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(DMGetGlobalSection(m->dm, &gs));
  PetscCall(VecGetArrayRead(cl, &ca));
  PetscCall(Centroids(m, nbody, vmask, comp, ca, cs, gs, vbody, xc));
  for (PetscInt b = 0; b < nbody; b++) idx[b] = comp[b] == b ? nvec++ : -1; /* one set of modes per component */
  PetscCall(DMGetGlobalVector(m->dm, &g));
  PetscCall(VecGetOwnershipRange(g, &lo, NULL));
  PetscCall(VecDuplicateVecs(g, 3 * nvec, &z));
  PetscCall(DMRestoreGlobalVector(m->dm, &g));
  PetscCall(PetscMalloc1(3 * nvec + 1, &za));
  for (PetscInt i = 0; i < 3 * nvec; i++) {
    PetscCall(VecZeroEntries(z[i]));
    PetscCall(VecGetArray(z[i], &za[i]));
  }
  for (PetscInt v = m->vStart; v < m->vEnd; v++) {
    PetscInt b = vbody[v - m->vStart], k, goff, off;
    if (b < 0) continue;
    k = idx[b];
    PetscCall(PetscSectionGetOffset(gs, v, &goff));
    PetscCall(PetscSectionGetOffset(cs, v, &off));
    goff -= lo;
    za[3 * k][goff]         = 1;
    za[3 * k + 1][goff + 1] = 1;
    za[3 * k + 2][goff]     = -(PetscRealPart(ca[off + 1]) - xc[2 * b + 1]);
    za[3 * k + 2][goff + 1] = PetscRealPart(ca[off]) - xc[2 * b];
  }
  for (PetscInt i = 0; i < 3 * nvec; i++) PetscCall(VecRestoreArray(z[i], &za[i]));
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCall(Orthonormalise(3 * nvec, z));
  PetscCall(MatNullSpaceCreate(comm, PETSC_FALSE, 3 * nvec, z, sp));
  PetscCall(VecDestroyVecs(3 * nvec, &z));
  PetscCall(PetscFree(za));
  PetscCall(PetscFree2(vmask, vbody));
  PetscFunctionReturn(0);
}
