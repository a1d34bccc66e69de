/* mesh_matrix.c - the stiffness matrix of the mesh (see mesh.h): AIJ with an
 * exact preallocation from the cell -> vertex lists (2 dofs per vertex). Rows of
 * vertices shared with another rank also receive that rank's cells: their counts
 * add the other rank's (over-estimates, never under). */
#include "mesh_impl.h"

/* vertex -> cells (cptr, cadj, by local vertex index), counting sort */
static void VertexCells(const M2dMesh *m, PetscInt cptr[], PetscInt cadj[])
{
  PetscInt nv = m->vEnd - m->vStart, nc = m->cEnd - m->cStart;
  for (PetscInt v = 0; v <= nv; v++) cptr[v] = 0;
  for (PetscInt i = 0; i < 4 * nc; i++) cptr[m->cellverts[i] - m->vStart + 1]++;
  for (PetscInt v = 0; v < nv; v++) cptr[v + 1] += cptr[v];
  for (PetscInt i = 0; i < 4 * nc; i++) cadj[cptr[m->cellverts[i] - m->vStart]++] = i / 4;
  for (PetscInt v = nv; v > 0; v--) cptr[v] = cptr[v - 1];
  cptr[0] = 0;
}

/* per local vertex v: neighbour vertices (itself included) whose dofs are in my
 * row range [lo, hi) (cnt[2v]) and outside it (cnt[2v+1]); any number of them */
static PetscErrorCode NeighbourCounts(const M2dMesh *m, const PetscInt cptr[], const PetscInt cadj[], const PetscInt gdof[], PetscInt lo, PetscInt hi, PetscInt cnt[])
{
  PetscInt nv = m->vEnd - m->vStart, *seen;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nv + 1, &seen));
  for (PetscInt w = 0; w < nv; w++) seen[w] = -1;
  for (PetscInt v = 0; v < nv; v++) {
    cnt[2 * v] = cnt[2 * v + 1] = 0;
    for (PetscInt k = cptr[v]; k < cptr[v + 1]; k++)
      for (int a = 0; a < 4; a++) {
        PetscInt w = m->cellverts[4 * cadj[k] + a] - m->vStart, g;
        if (seen[w] == v) continue;
        seen[w] = v;
        g       = gdof[w] >= 0 ? gdof[w] : -(gdof[w] + 1);
        cnt[2 * v + (g >= lo && g < hi ? 0 : 1)]++;
      }
  }
  PetscCall(PetscFree(seen));
  PetscFunctionReturn(0);
}

/* shared vertices: the owner adds what the other ranks see (to both counts, an upper bound) */
static PetscErrorCode AddSharedCounts(const M2dMesh *m, const PetscInt gdof[], PetscInt cnt[])
{
  PetscSF   sf;
  PetscInt *sum, *leafv, nroots, pStart, pEnd;

  PetscFunctionBeginUser;
  PetscCall(DMGetPointSF(m->dm, &sf));
  PetscCall(PetscSFGetGraph(sf, &nroots, NULL, NULL, NULL));
  if (nroots < 0) PetscFunctionReturn(0);
  PetscCall(DMPlexGetChart(m->dm, &pStart, &pEnd));
  PetscCall(PetscCalloc2(pEnd + 1, &sum, pEnd + 1, &leafv));
  for (PetscInt v = m->vStart; v < m->vEnd; v++) leafv[v] = cnt[2 * (v - m->vStart)] + cnt[2 * (v - m->vStart) + 1];
  PetscCall(PetscSFReduceBegin(sf, MPIU_INT, leafv, sum, MPI_SUM));
  PetscCall(PetscSFReduceEnd(sf, MPIU_INT, leafv, sum, MPI_SUM));
  for (PetscInt v = m->vStart; v < m->vEnd; v++)
    if (gdof[v - m->vStart] >= 0 && sum[v]) {
      cnt[2 * (v - m->vStart)] += sum[v];
      cnt[2 * (v - m->vStart) + 1] += sum[v];
    }
  PetscCall(PetscFree2(sum, leafv));
  PetscFunctionReturn(0);
}

/* the couplings of every dof group (a contact row): room for all of them in
 * both blocks (an upper bound), then explicit zeros there, in the rows this rank
 * owns, so that K + g C^T C keeps K's pattern */
static PetscErrorCode GroupCounts(PetscInt ngrp, const PetscInt gptr[], const PetscInt gdofs[], PetscInt lo, PetscInt hi, PetscInt dnz[], PetscInt onz[])
{
  PetscFunctionBeginUser;
  for (PetscInt j = 0; j < ngrp; j++)
    for (PetscInt k = gptr[j]; k < gptr[j + 1]; k++)
      if (gdofs[k] >= lo && gdofs[k] < hi) {
        dnz[gdofs[k] - lo] = PetscMin(dnz[gdofs[k] - lo] + gptr[j + 1] - gptr[j], hi - lo);
        onz[gdofs[k] - lo] += gptr[j + 1] - gptr[j];
      }
  PetscFunctionReturn(0);
}

static PetscErrorCode GroupZeros(Mat K, PetscInt ngrp, const PetscInt gptr[], const PetscInt gdofs[], PetscInt lo, PetscInt hi)
{
  PetscFunctionBeginUser;
  for (PetscInt j = 0; j < ngrp; j++) {
    PetscInt     n = gptr[j + 1] - gptr[j];
    PetscScalar *zero;
    PetscCall(PetscCalloc1(n + 1, &zero));
    for (PetscInt k = gptr[j]; k < gptr[j + 1]; k++)
      if (gdofs[k] >= lo && gdofs[k] < hi) PetscCall(MatSetValues(K, 1, &gdofs[k], n, &gdofs[gptr[j]], zero, ADD_VALUES));
    PetscCall(PetscFree(zero));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MeshCreateMatrix(const M2dMesh *m, PetscInt ngrp, const PetscInt gptr[], const PetscInt gdofs[], Mat *K)
{
  MPI_Comm               comm = PetscObjectComm((PetscObject)m->dm);
  PetscSection           gsec;
  ISLocalToGlobalMapping ltog;
  PetscInt               nv = m->vEnd - m->vStart, nc = m->cEnd - m->cStart, nloc, *cptr, *cadj, *gdof, *cnt, *dnz, *onz, lo, hi, nrow = 0;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalSection(m->dm, &gsec));
  PetscCall(PetscSectionGetStorageSize(gsec, &nloc));
  PetscCall(PetscMalloc4(nv + 1, &cptr, 4 * nc + 1, &cadj, nv + 1, &gdof, 2 * nv + 2, &cnt));
  VertexCells(m, cptr, cadj);
  /* global first dof of each vertex; negative: owned by another rank */
  for (PetscInt v = 0; v < nv; v++) PetscCall(PetscSectionGetOffset(gsec, m->vStart + v, &gdof[v]));
  PetscCallMPI(MPI_Scan(&nloc, &hi, 1, MPIU_INT, MPI_SUM, comm));
  lo = hi - nloc;
  PetscCall(NeighbourCounts(m, cptr, cadj, gdof, lo, hi, cnt));
  PetscCall(AddSharedCounts(m, gdof, cnt));
  PetscCall(PetscMalloc2(nloc + 1, &dnz, nloc + 1, &onz));
  for (PetscInt v = 0; v < nv; v++)
    if (gdof[v] >= 0) {
      PetscInt r = gdof[v] - lo;
      dnz[r] = dnz[r + 1] = 2 * PetscMin(cnt[2 * v], nloc / 2);
      onz[r] = onz[r + 1] = 2 * cnt[2 * v + 1];
      nrow++;
    }
  PetscCheck(2 * nrow == nloc, PETSC_COMM_SELF, PETSC_ERR_PLIB, "preallocation: %" PetscInt_FMT " owned vertices for %" PetscInt_FMT " dofs", nrow, nloc);
  PetscCall(GroupCounts(ngrp, gptr, gdofs, lo, hi, dnz, onz));
  PetscCall(MatCreate(comm, K));
  PetscCall(MatSetSizes(*K, nloc, nloc, PETSC_DETERMINE, PETSC_DETERMINE));
  PetscCall(MatSetBlockSize(*K, 2)); /* a vertex's two dofs: AMG aggregates nodes */
  PetscCall(MatSetType(*K, MATAIJ));
  PetscCall(MatSeqAIJSetPreallocation(*K, 0, dnz));
  PetscCall(MatMPIAIJSetPreallocation(*K, 0, dnz, 0, onz));
  PetscCall(DMGetLocalToGlobalMapping(m->dm, &ltog));
  PetscCall(MatSetLocalToGlobalMapping(*K, ltog, ltog));
  PetscCall(MatSetOption(*K, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscCall(GroupZeros(*K, ngrp, gptr, gdofs, lo, hi));
  PetscCall(PetscFree2(dnz, onz));
  PetscCall(PetscFree4(cptr, cadj, gdof, cnt));
  PetscFunctionReturn(0);
}
