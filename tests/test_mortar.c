/* Unit tests of the mortar geometry and integrals (mortar.c):
 *  - D and M of a two-edge configuration against values worked out by hand;
 *  - sum_j D_ij = sum_k M_ik for fully covered non-mortar nodes;
 *  - invariance of the rows under a translation and a rotation of both surfaces;
 *  - non-mortar nodes projecting exactly onto mortar nodes and onto the end of
 *    the mortar surface: no NaN, no lost length (zero-length segments dropped);
 *  - the NTS row of a node. */
#include "mortar.h"

#include "check.h"

/* value of row j at global dof col (0 if absent) */
static PetscReal RowVal(const M2dContactRows *R, PetscInt j, PetscInt col)
{
  for (PetscInt k = R->ptr[j]; k < R->ptr[j + 1]; k++)
    if (R->col[k] == col) return R->val[k];
  return 0;
}

static PetscInt RowOfNode(const M2dContactRows *R, PetscInt node)
{
  for (PetscInt j = 0; j < R->n; j++)
    if (R->node[j] == node) return j;
  return -1;
}

/* Edges are oriented body-on-the-left (outward normal (t_y, -t_x)).
 * Non-mortar: upper body's bottom edge from (0,0) to (1,0), normal -y. Node a = (1,0) gdof 100, b = (0,0) gdof 102.
 * Mortar: lower body's top edges (1.5,0)-(0.5,0)-(-0.5,0), normal +y, gdofs 4, 2, 0.
 * Worked out by hand with N_a = x, N_b = 1 - x on [0,1]:
 *   D = [1/3 1/6; 1/6 1/3],  M_a = [1/48, 18/48, 5/48],  M_b = [5/48, 18/48, 1/48]. */
static void TwoEdge(PetscReal theta, PetscReal tx, PetscReal ty, M2dSurface *nm, M2dSurface *m)
{
  PetscReal      xn[4] = {1, 0, 0, 0}, xm[6] = {-0.5, 0, 0.5, 0, 1.5, 0};
  const PetscInt gn[2] = {100, 102}, gm[3] = {0, 2, 4}, en[2] = {1, 0}, em[4] = {1, 0, 2, 1};
  PetscReal      c = PetscCosReal(theta), s = PetscSinReal(theta);
  for (int i = 0; i < 2; i++) {
    PetscReal x = xn[2 * i], y = xn[2 * i + 1];
    xn[2 * i]     = c * x - s * y + tx;
    xn[2 * i + 1] = s * x + c * y + ty;
  }
  for (int i = 0; i < 3; i++) {
    PetscReal x = xm[2 * i], y = xm[2 * i + 1];
    xm[2 * i]     = c * x - s * y + tx;
    xm[2 * i + 1] = s * x + c * y + ty;
  }
  SurfaceCreate(2, xn, gn, 1, en, nm);
  SurfaceCreate(3, xm, gm, 2, em, m);
}

int main(int argc, char **argv)
{
  M2dSurface     nm, m;
  M2dSegmentSet  S;
  M2dContactRows R, Rt;

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  TwoEdge(0, 0, 0, &nm, &m);
  PetscCall(MortarBuildSegments(&nm, &m, 0.1, &S));
  CHECK(S.nseg == 2, "two segments (%d)", (int)S.nseg);
  PetscCall(MortarRows(&nm, &m, &S, M2D_MORTAR_STANDARD, &R));
  {
    PetscInt  ja = RowOfNode(&R, 0), jb = RowOfNode(&R, 1);
    /* rows hold D n and -M n with n = (0, 1): the y-dofs carry the numbers */
    PetscReal D[4]  = {RowVal(&R, ja, 101), RowVal(&R, ja, 103), RowVal(&R, jb, 101), RowVal(&R, jb, 103)};
    PetscReal Ma[3] = {-RowVal(&R, ja, 1), -RowVal(&R, ja, 3), -RowVal(&R, ja, 5)};
    PetscReal Mb[3] = {-RowVal(&R, jb, 1), -RowVal(&R, jb, 3), -RowVal(&R, jb, 5)};
    PetscReal eD = PetscAbsReal(D[0] - 1. / 3) + PetscAbsReal(D[1] - 1. / 6) + PetscAbsReal(D[2] - 1. / 6) + PetscAbsReal(D[3] - 1. / 3);
    PetscReal eM = PetscAbsReal(Ma[0] - 1. / 48) + PetscAbsReal(Ma[1] - 18. / 48) + PetscAbsReal(Ma[2] - 5. / 48) + PetscAbsReal(Mb[0] - 5. / 48) + PetscAbsReal(Mb[1] - 18. / 48) + PetscAbsReal(Mb[2] - 1. / 48);
    CHECK(R.n == 2 && ja >= 0 && jb >= 0, "both non-mortar nodes carry a multiplier");
    CHECK(eD < 1e-15, "D against hand values (error %.1e)", (double)eD);
    CHECK(eM < 1e-15, "M against hand values (error %.1e)", (double)eM);
    CHECK(RowVal(&R, ja, 100) == 0 && RowVal(&R, ja, 0) == 0, "no tangential entries for a horizontal interface");
    for (PetscInt j = 0; j < R.n; j++) {
      PetscReal sd = 0, sm = 0;
      for (PetscInt k = R.ptr[j]; k < R.ptr[j + 1]; k++) {
        if (R.col[k] >= 100) sd += R.val[k];
        else sm -= R.val[k];
      }
      CHECK(PetscAbsReal(sd - sm) < 1e-14, "row %d: sum_j D = sum_k M (%.1e)", (int)j, (double)(sd - sm));
      CHECK(PetscAbsReal(R.w[j] - 0.5) < 1e-15 && PetscAbsReal(R.g0[j]) < 1e-15, "row %d: weight 1/2 and zero initial gap", (int)j);
    }
  }
  { /* translation + rotation: rows rotate with the normal, weights and gaps stay */
    M2dSurface    nm2, m2;
    M2dSegmentSet S2;
    PetscReal  th = 0.7, err = 0;
    TwoEdge(th, 3.3, -1.7, &nm2, &m2);
    PetscCall(MortarBuildSegments(&nm2, &m2, 0.1, &S2));
    PetscCall(MortarRows(&nm2, &m2, &S2, M2D_MORTAR_STANDARD, &Rt));
    CHECK(Rt.n == R.n && S2.nseg == S.nseg, "same segments and multipliers after a rigid motion");
    for (PetscInt j = 0; j < R.n && Rt.n == R.n; j++) {
      err = PetscMax(err, PetscAbsReal(R.w[j] - Rt.w[j]) + PetscAbsReal(Rt.g0[j]));
      for (PetscInt k = R.ptr[j]; k < R.ptr[j + 1]; k++) {
        PetscInt col = R.col[k];
        if (col % 2 == 0) continue;
        /* entry on the y-dof times the rotated normal (-sin, cos) */
        err = PetscMax(err, PetscAbsReal(RowVal(&Rt, j, col - 1) - R.val[k] * -PetscSinReal(th)) + PetscAbsReal(RowVal(&Rt, j, col) - R.val[k] * PetscCosReal(th)));
      }
    }
    CHECK(err < 1e-14, "rows invariant under translation and rotation (%.1e)", (double)err);
    PetscCall(ContactRowsDestroy(&Rt));
    PetscCall(SegmentSetDestroy(&S2));
    PetscCall(SurfaceDestroy(&nm2));
    PetscCall(SurfaceDestroy(&m2));
  }
  PetscCall(ContactRowsDestroy(&R));
  PetscCall(SegmentSetDestroy(&S));
  PetscCall(SurfaceDestroy(&nm));
  PetscCall(SurfaceDestroy(&m));

  { /* coincident nodes and the end of the mortar surface: non-mortar edges
     * (0,0)-(0.5,0)-(1,0)-(1.5,0) (upper body), mortar (0,0)-(0.5,0)-(1,0):
     * nodes project exactly onto mortar nodes, the last one beyond the end */
    const PetscReal xn[8] = {1.5, 0, 1, 0, 0.5, 0, 0, 0}, xm[6] = {0, 0, 0.5, 0, 1, 0};
    const PetscInt  gn[4] = {100, 102, 104, 106}, en[6] = {1, 0, 2, 1, 3, 2}, gm[3] = {0, 2, 4}, em[4] = {1, 0, 2, 1};
    PetscReal       len = 0, sumw = 0;
    PetscBool       finite = PETSC_TRUE;
    PetscCall(SurfaceCreate(4, xn, gn, 3, en, &nm));
    PetscCall(SurfaceCreate(3, xm, gm, 2, em, &m));
    PetscCall(MortarBuildSegments(&nm, &m, 0.1, &S));
    PetscCall(MortarRows(&nm, &m, &S, M2D_MORTAR_STANDARD, &R));
    for (PetscInt k = 0; k < S.nseg; k++) {
      len += 0.5 * (S.seg[k].zeta[1] - S.seg[k].zeta[0]) * nm.len[S.seg[k].nm_edge];
      finite = (PetscBool)(finite && !PetscIsInfOrNanReal(S.seg[k].zeta[0] + S.seg[k].zeta[1] + S.seg[k].xi[0] + S.seg[k].xi[1]));
    }
    for (PetscInt j = 0; j < R.n; j++) {
      sumw += R.w[j];
      for (PetscInt k = R.ptr[j]; k < R.ptr[j + 1]; k++) finite = (PetscBool)(finite && !PetscIsInfOrNanReal(R.val[k]));
    }
    CHECK(S.nseg == 2, "coincident nodes: 2 segments, zero-length ones dropped (%d)", (int)S.nseg);
    CHECK(PetscAbsReal(len - 1.0) < 1e-15 && PetscAbsReal(sumw - 1.0) < 1e-15, "covered length 1 kept (segments %.16g, weights %.16g)", (double)len, (double)sumw);
    CHECK(finite, "no NaN or Inf in segments and rows");
    CHECK(R.n == 3 && RowOfNode(&R, 0) < 0, "the node beyond the mortar surface gets no multiplier (%d multipliers)", (int)R.n);
    PetscCall(ContactRowsDestroy(&R));
    { /* NTS: node (0.5, 0.02) above mortar node (0.5, 0): xi = 1 on edge 0 or -1 on edge 1 */
      M2dContactRows N;
      PetscInt    j;
      PetscCall(NTSRows(&nm, &m, 0.1, &N));
      j = RowOfNode(&N, 2);
      CHECK(N.n == 3 && j >= 0, "NTS: 3 multipliers (nodes over the mortar surface)");
      if (j >= 0) CHECK(PetscAbsReal(N.w[j] - 0.5) < 1e-15 && PetscAbsReal(RowVal(&N, j, 105) - 0.5) < 1e-15 && PetscAbsReal(RowVal(&N, j, 3) + 0.5) < 1e-15, "NTS row: a_s n at the node, -a_s n at the coincident mortar node");
      PetscCall(ContactRowsDestroy(&N));
    }
    PetscCall(SegmentSetDestroy(&S));
    PetscCall(SurfaceDestroy(&nm));
    PetscCall(SurfaceDestroy(&m));
  }
  PetscCall(PetscFinalize());
  printf("%d failed\n", failures);
  return failures ? 1 : 0;
}
