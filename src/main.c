/* main.c - mortar2d: read a scene from the options database, run it, write results.
 *
 *   mortar2d -options_file options/block.opts [-output_dir out] [-summary out/summary.json]
 *
 * Phases (each a -log_view stage): Mesh (read, validate, distribute), Contact
 * (surfaces, search, mortar segments or NTS rows), Assembly (Q4 stiffness,
 * loads, Dirichlet rows, KKT system), Solve (KSP from the options database,
 * MUMPS LDL^T by default), Output (stresses, HDF5/XDMF, VTU, CSV, summary). */
#include "activeset.h"
#include "supports.h"
#include "contact.h"
#include "elasticity.h"
#include "mesh.h"
#include "optcheck.h"
#include "optfiles.h"
#include "output.h"
#include "scene.h"
#include "util.h"
#include <petscksp.h>
#include <petscsnes.h>
#include <string.h>
#include <sys/stat.h>

static const char help[] = "mortar2d: 2D frictionless contact of elastic bodies with Q4 elements and the mortar method.\n"
                           "Scenes are options files in options/; see README.md for every option.\n\n";

typedef enum {
  ST_MESH,
  ST_CONTACT,
  ST_ASSEMBLY,
  ST_SOLVE,
  ST_OUTPUT,
  ST_COUNT
} StageId;
static const char *stage_name[ST_COUNT] = {"mesh", "contact", "assembly", "solve", "output"};

static PetscErrorCode CheckOutputDir(MPI_Comm comm, const M2dScene *s)
{
  PetscMPIInt rank;
  char        msg[1024] = "";
  int         bad       = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0 && (s->write_vtu || s->write_hdf5)) {
    char why[900];
    if (M2dMakeDirs(s->outdir, why, sizeof(why))) {
      snprintf(msg, sizeof(msg), "option -output_dir: %s", why);
      bad = 1;
    }
  }
  if (rank == 0 && !bad && s->summary[0]) { /* the summary's directory must exist or be creatable */
    char        dir[PETSC_MAX_PATH_LEN], why[900];
    struct stat st;
    char       *slash;
    PetscCall(PetscStrncpy(dir, s->summary, sizeof(dir)));
    slash = strrchr(dir, '/');
    if (stat(s->summary, &st) == 0 && S_ISDIR(st.st_mode)) {
      snprintf(msg, sizeof(msg), "option -summary: '%s' is a directory", s->summary);
      bad = 1;
    } else if (slash && slash != dir) {
      *slash = 0;
      if (M2dMakeDirs(dir, why, sizeof(why))) {
        snprintf(msg, sizeof(msg), "option -summary: %s", why);
        bad = 1;
      }
    }
  }
  PetscCall(M2dCheckCollective(comm, bad ? PETSC_TRUE : PETSC_FALSE, msg));
  PetscFunctionReturn(0);
}

/* a physical group that exists but holds nothing would silently do nothing */
static PetscErrorCode CheckNotEmpty(MPI_Comm comm, const M2dMesh *m, const char *group, const char *opt)
{
  IS       is;
  PetscInt n;

  PetscFunctionBeginUser;
  PetscCall(MeshGetGroupIS(m, group, opt, &is));
  PetscCall(ISGetLocalSize(is, &n));
  PetscCall(ISDestroy(&is));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPIU_INT, MPI_SUM, comm));
  PetscCheck(n > 0, comm, PETSC_ERR_USER_INPUT, "option %s: physical group '%s' of mesh file(s) %s has no elements", opt, group, m->files);
  PetscFunctionReturn(0);
}

/* every physical group the options name must exist, before any work is done */
static PetscErrorCode CheckGroups(MPI_Comm comm, const M2dScene *s, const M2dMesh *m)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < s->ndir; i++) {
    PetscInt d = MeshGroupDim(m, s->dir[i].group);
    PetscCheck(d >= 0, comm, PETSC_ERR_USER_INPUT, "option -dirichlet: mesh file(s) %s have no physical group '%s'", m->files, s->dir[i].group);
    PetscCheck(d <= 1, comm, PETSC_ERR_USER_INPUT, "option -dirichlet: physical group '%s' is a surface; name a curve or a point", s->dir[i].group);
    PetscCall(CheckNotEmpty(comm, m, s->dir[i].group, "-dirichlet"));
  }
  for (PetscInt i = 0; i < s->nload; i++) {
    const char *opt = s->load[i].is_pressure ? "-pressure" : "-traction";
    PetscInt    d   = MeshGroupDim(m, s->load[i].group);
    PetscCheck(d >= 0, comm, PETSC_ERR_USER_INPUT, "option %s: mesh file(s) %s have no physical group '%s'", opt, m->files, s->load[i].group);
    PetscCheck(d == 1, comm, PETSC_ERR_USER_INPUT, "option %s: physical group '%s' is not a curve", opt, s->load[i].group);
    PetscCall(CheckNotEmpty(comm, m, s->load[i].group, opt));
  }
  PetscFunctionReturn(0);
}

/* defaults for the linear solves (no contact, or tied): the matrix is
 * symmetric, MUMPS LDL^T (PCCHOLESKY, SYM = 2), as the condensed path. PETSc
 * 3.18 hands MUMPS no ordering for a Cholesky factor: MUMPS orders with AMF
 * (its automatic choice, PORD, is slower here); the METIS ordering applies to
 * -pc_type lu on one rank; -ksp_type/-pc_type/-mat_mumps_* override */
static PetscErrorCode SetupSolver(KSP ksp, M2dOrdering ord)
{
  PC            pc;
  PetscBool     factor, chosen, given, metis;
  MatSolverType st;

  PetscFunctionBeginUser;
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCCHOLESKY));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(KSPSetFromOptions(ksp));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, ""));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-pc_factor_mat_solver_type", &chosen));
  if (factor && !chosen) PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS)); /* -pc_type lu alone: still MUMPS */
  PetscCall(M2dOrderingSetupKSP(ksp, ord, &metis));
  /* MUMPS orders itself: AMF unless -mat_mumps_icntl_7 says otherwise (level 5 tied: AMF 7.4 s,
   * AMD 8.1 s, PORD - MUMPS' automatic choice - 8.9 s); through the options database, because
   * PETSc 3.18 re-initialises MUMPS at the symbolic factorization */
  PetscCall(PetscOptionsHasName(NULL, NULL, "-mat_mumps_icntl_7", &given));
  if (factor && !metis && !given) {
    PetscCall(PCFactorGetMatSolverType(pc, &st));
    if (st && !strcmp(st, MATSOLVERMUMPS)) PetscCall(PetscOptionsSetValue(NULL, "-mat_mumps_icntl_7", "2"));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Run(MPI_Comm comm)
{
  M2dScene         s;
  M2dMesh          m;
  Mat           K;
  Vec           f, u;
  KSP           ksp;
  PetscLogStage stage[ST_COUNT];
  PetscLogEvent ev_asm[4]; /* assembly: preallocation, elements, Dirichlet, KKT */
  double        t[ST_COUNT + 1], tstart;
  PetscInt      ndir, *drows, nlc, its;
  PetscScalar  *dvals;
  PetscReal    *stress;
  PetscMPIInt   size;
  M2dSummary      *sum;
  KSPConvergedReason reason;
  PetscBool     has_contact;
  M2dContact       contact;
  M2dKKT           kkt;
  Vec           lam = NULL, cfield = NULL, active = NULL;
  M2dActiveSetInfo asinfo;

  PetscFunctionBeginUser;
  tstart = M2dWallTime();
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (int k = 0; k < ST_COUNT; k++) {
    char name[32];
    PetscCall(PetscSNPrintf(name, sizeof(name), "%c%s", stage_name[k][0] - 32, stage_name[k] + 1));
    PetscCall(PetscLogStageRegister(name, &stage[k]));
    t[k] = 0;
  }
  PetscCall(PetscLogEventRegister("M2dPrealloc", MAT_CLASSID, &ev_asm[0]));
  PetscCall(PetscLogEventRegister("M2dElements", MAT_CLASSID, &ev_asm[1]));
  PetscCall(PetscLogEventRegister("M2dDirichlet", MAT_CLASSID, &ev_asm[2]));
  PetscCall(PetscLogEventRegister("M2dKKT", MAT_CLASSID, &ev_asm[3]));
  PetscCall(SceneReadOptions(comm, &s));
  PetscCall(SceneCheckOptions(comm, &s)); /* typos of the program's options, before the mesh is read */
  if (s.help) { /* document the per-body options too, then stop */
    if (s.nbody == 0) {
      s.nbody = 1;
      PetscCall(PetscStrncpy(s.body[0].name, "BODY", sizeof(s.body[0].name)));
    }
    PetscCall(SceneReadMaterials(comm, &s));
    PetscCall(KSPCreate(comm, &ksp));
    PetscCall(SetupSolver(ksp, s.kkt_ordering));
    PetscCall(KSPDestroy(&ksp));
    PetscFunctionReturn(0);
  }
  PetscCall(CheckOutputDir(comm, &s));

  PetscCall(PetscLogStagePush(stage[ST_MESH]));
  t[ST_MESH] = M2dWallTime();
  PetscCall(MeshCreate(comm, &s, &m));
  PetscCall(SceneReadMaterials(comm, &s));
  PetscCall(SceneCheckOptions(comm, &s)); /* and of the per-body ones */
  PetscCall(CheckGroups(comm, &s, &m));
  if (s.hertz && s.hertz_load <= 0) { /* quarter model: the full cylinder carries twice the load */
    PetscCall(ElasticityPressureResultant(&m, &s.load[0], &s.hertz_load));
    s.hertz_load *= 2;
    PetscCheck(s.hertz_load > 0, comm, PETSC_ERR_USER_INPUT, "option -hertz: the load on '%s' is not a compressive force (resultant %g)", s.load[0].group, (double)s.hertz_load / 2);
  }
  PetscCall(SceneView(comm, &s));
  t[ST_MESH] = M2dWallTime() - t[ST_MESH];
  PetscCall(PetscLogStagePop());

  has_contact = (PetscBool)(s.contact_nm[0] != 0);
  PetscCall(PetscLogStagePush(stage[ST_CONTACT]));
  t[ST_CONTACT] = M2dWallTime();
  if (has_contact) PetscCall(ContactSetup(&m, &s, &contact));
  t[ST_CONTACT] = M2dWallTime() - t[ST_CONTACT];
  PetscCall(PetscLogStagePop());

  PetscCall(PetscLogStagePush(stage[ST_ASSEMBLY]));
  t[ST_ASSEMBLY] = M2dWallTime();
  PetscCall(PetscLogEventBegin(ev_asm[0], 0, 0, 0, 0));
  if (has_contact) PetscCall(MeshCreateMatrix(&m, contact.R.n, contact.R.ptr, contact.R.col, &K));
  else PetscCall(MeshCreateMatrix(&m, 0, NULL, NULL, &K));
  PetscCall(PetscLogEventEnd(ev_asm[0], 0, 0, 0, 0));
  PetscCall(DMCreateGlobalVector(m.dm, &f));
  PetscCall(VecDuplicate(f, &u));
  PetscCall(PetscObjectSetName((PetscObject)u, "displacement"));
  PetscCall(PetscLogEventBegin(ev_asm[1], 0, 0, 0, 0));
  PetscCall(ElasticityAssemble(&m, &s, K, f));
  PetscCall(PetscLogEventEnd(ev_asm[1], 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_asm[2], 0, 0, 0, 0));
  PetscCall(ElasticityDirichletRows(&m, &s, &ndir, &drows, &dvals));
  PetscCall(CheckRigidModes(&m, &s, has_contact ? &contact : NULL, ndir, drows));
  PetscCall(ElasticityApplyDirichlet(K, f, u, ndir, drows, dvals));
  PetscCall(PetscLogEventEnd(ev_asm[2], 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_asm[3], 0, 0, 0, 0));
  if (has_contact) {
    if (s.unilateral && s.condensed) {
      /* the fast path factors K + g C^T C (monolithic) once; what it cannot serve goes the full way */
      PetscBool vi = PETSC_FALSE;
      char      st[64];
      PetscCall(PetscOptionsGetString(NULL, NULL, "-snes_type", st, sizeof(st), &vi));
      vi = (PetscBool)(vi && !strcmp(st, SNESVINEWTONRSLS));
      if (s.kkt_mat == M2D_KKT_NEST || vi) {
        s.condensed = PETSC_FALSE;
        PetscCall(PetscPrintf(comm, "active set: -kkt_path full (the condensed path needs -kkt_mat aij and newtonls)\n"));
      } else if (s.kkt_augment == 0) s.kkt_augment = 1.0;
    }
    PetscCall(KKTCreate(&s, &contact.R, K, f, u, ndir, drows, &kkt));
    PetscCall(VecDuplicate(kkt.r, &lam));
    PetscCall(VecDuplicate(kkt.r, &active));
  }
  PetscCall(PetscLogEventEnd(ev_asm[3], 0, 0, 0, 0));
  PetscCall(PetscFree2(drows, dvals));
  t[ST_ASSEMBLY] = M2dWallTime() - t[ST_ASSEMBLY];
  PetscCall(PetscLogStagePop());

  PetscCall(PetscLogStagePush(stage[ST_SOLVE]));
  t[ST_SOLVE] = M2dWallTime();
  PetscCall(KSPCreate(comm, &ksp));
  PetscCall(PetscMemzero(&asinfo, sizeof(asinfo)));
  if (has_contact && s.unilateral) {
    PetscCall(ActiveSetSolve(&s, &m, &contact, &kkt, u, lam, active, &asinfo));
    PetscCall(KSPSetOperators(ksp, K, K)); /* unused: the SNES has its own */
    reason = KSP_CONVERGED_ITS;
    its    = 0;
  } else {
    if (has_contact) PetscCall(KSPSetOperators(ksp, kkt.A, kkt.A));
    else PetscCall(KSPSetOperators(ksp, K, K));
    PetscCall(SetupSolver(ksp, s.kkt_ordering));
    if (has_contact) {
      PetscCall(KKTSetupKSP(&kkt, ksp));
      PetscCall(KKTSolve(&kkt, ksp, u, lam));
      PetscCall(VecSet(active, 1.0));
    } else PetscCall(KSPSolve(ksp, f, u));
  }
  if (!(has_contact && s.unilateral)) {
    PetscCall(KSPGetConvergedReason(ksp, &reason));
    PetscCall(KSPGetIterationNumber(ksp, &its));
  }
  if (reason <= 0) {
    PetscBool fs;
    PC        pc;
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &fs));
    PetscCheck(!(fs && has_contact && s.kkt_augment == 0), comm, PETSC_ERR_NOT_CONVERGED, "linear solve failed (%s): the fieldsplit K block cannot be factored when a body is held only by contact; add -kkt_augment 1 or use the monolithic solver (options/kkt_mumps.opts)", KSPConvergedReasons[reason]);
    SETERRQ(comm, PETSC_ERR_NOT_CONVERGED, "linear solve failed: %s (check the supports: is every body held?)", KSPConvergedReasons[reason]);
  }
  t[ST_SOLVE] = M2dWallTime() - t[ST_SOLVE];
  PetscCall(PetscLogStagePop());
  PetscCall(M2dOptionsCheckUnused(comm)); /* PETSc options no solver read (best before the solve: see README) */

  PetscCall(PetscLogStagePush(stage[ST_OUTPUT]));
  t[ST_OUTPUT] = M2dWallTime();
  PetscCall(PetscCalloc1(1, &sum));
  nlc = m.cEnd - m.cStart;
  PetscCall(PetscMalloc1(6 * nlc + 1, &stress));
  PetscCall(ElasticityCellStress(&m, &s, u, stress)); /* 5 per cell */
  {
    /* re-pack as 6 per cell: 5 stresses + body id */
    for (PetscInt c = nlc - 1; c >= 0; c--) {
      for (int k = 4; k >= 0; k--) stress[6 * c + k] = stress[5 * c + k];
      stress[6 * c + 5] = (PetscReal)m.cellbody[c];
    }
  }
  SummaryString(sum, "", "program", "mortar2d");
  SummaryInt(sum, "", "dofs", 2 * m.nvert_global);
  SummaryInt(sum, "", "cells", m.ncell_global);
  SummaryInt(sum, "", "ranks", size);
  SummaryInt(sum, "", "bodies", s.nbody);
  SummaryString(sum, "", "plane", s.plane == M2D_PLANE_STRAIN ? "strain" : "stress");
  SummaryInt(sum, "", "ksp_iterations", its);
  if (has_contact) {
    char csv[PETSC_MAX_PATH_LEN];
    PetscCall(ContactResults(&contact, &kkt, u, lam, active));
    SummaryString(sum, "", "method", s.method == M2D_CONTACT_MORTAR ? "mortar" : "nts");
    SummaryInt(sum, "", "contact_nodes", contact.R.n);
    SummaryReal(sum, "", "contact_force", contact.force_n);
    SummaryReal(sum, "", "contact_force_x", contact.force[0]);
    SummaryReal(sum, "", "contact_force_y", contact.force[1]);
    SummaryString(sum, "", "contact_solver", !s.unilateral ? "tied" : asinfo.vi ? "vinewtonrsls" : "pdas");
    SummaryInt(sum, "", "iterations", s.unilateral ? asinfo.iterations : 1);
    {
      PetscReal na;
      PetscCall(VecSum(active, &na));
      SummaryInt(sum, "", "active_nodes", (PetscInt)(na + 0.5));
    }
    if (s.unilateral) SummaryReal(sum, "", "contact_c", asinfo.c);
    if (s.unilateral) SummaryString(sum, "", "kkt_path", asinfo.condensed ? "condensed" : "full");
    if (s.unilateral && asinfo.condensed) {
      SummaryReal(sum, "", "factor_flops", asinfo.factor_flops);
      SummaryReal(sum, "", "factor_flops_max_rank", asinfo.factor_flops_max);
      SummaryInt(sum, "", "interface_unknowns", asinfo.interface_unknowns);
    }
    if (s.hertz) {
      M2dHertzResult h;
      PetscCall(ContactHertz(&contact, &s, &h));
      SummaryReal(sum, "", "pressure_l2_rel", h.pressure_l2_rel);
      SummaryReal(sum, "", "peak_pressure", h.peak_pressure);
      SummaryReal(sum, "", "half_width", h.half_width);
      SummaryReal(sum, "", "half_width_spacing", h.h_edge);
      SummaryReal(sum, "", "hertz_a", h.a);
      SummaryReal(sum, "", "hertz_p0", h.p0);
      PetscCall(PetscPrintf(comm, "Hertz: a = %.6g (computed %.6g, node spacing %.3g), p0 = %.6g (computed peak %.6g), L2 error of the pressure on [0, 1.5a]: %.4e\n", (double)h.a, (double)h.half_width, (double)h.h_edge, (double)h.p0, (double)h.peak_pressure, (double)h.pressure_l2_rel));
    }
    PetscCall(PetscPrintf(comm, "contact force: integral of pressure %.12e, on the non-mortar body (%.12e, %.12e)\n", (double)contact.force_n, (double)contact.force[0], (double)contact.force[1]));
    PetscCall(VecDuplicate(u, &cfield));
    PetscCall(ContactFillField(&contact, cfield));
    if (s.write_vtu || s.write_hdf5) {
      PetscCall(PetscSNPrintf(csv, sizeof(csv), "%s/%s_contact.csv", s.outdir, s.outname));
      PetscCall(ContactWriteCSV(comm, &contact, csv));
    }
  }
  if (s.exact == M2D_EXACT_UNIFORM) {
    PetscReal p = s.exact_p, e[3] = {0, 0, 0};
    for (PetscInt c = 0; c < nlc; c++) {
      e[0] = PetscMax(e[0], PetscAbsReal(stress[6 * c + 1] + p) / PetscAbsReal(p));
      e[1] = PetscMax(e[1], PetscAbsReal(stress[6 * c + 0]) / PetscAbsReal(p));
      e[2] = PetscMax(e[2], PetscAbsReal(stress[6 * c + 3]) / PetscAbsReal(p));
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, e, 3, MPIU_REAL, MPI_MAX, comm));
    SummaryReal(sum, "error", "sigma_yy_max_rel", e[0]);
    SummaryReal(sum, "error", "sigma_xx_max_rel", e[1]);
    SummaryReal(sum, "error", "sigma_xy_max_rel", e[2]);
    PetscCall(PetscPrintf(comm, "uniform stress check: max |sigma_yy + p|/p = %.3e, max |sigma_xx|/p = %.3e, max |sigma_xy|/p = %.3e\n", (double)e[0], (double)e[1], (double)e[2]));
  } else if (s.exact == M2D_EXACT_MMS) {
    PetscReal err, nrm, h;
    PetscCall(ElasticityMMSError(&m, &s, u, &err, &nrm, &h));
    SummaryReal(sum, "error", "u_l2", err);
    SummaryReal(sum, "error", "u_l2_rel", err / nrm);
    SummaryReal(sum, "error", "h", h);
    PetscCall(PetscPrintf(comm, "manufactured solution: h = %.4e, L2 displacement error = %.6e (relative %.6e)\n", (double)h, (double)err, (double)(err / nrm)));
  }
  {
    M2dFieldSet fs;
    PetscCall(PetscMemzero(&fs, sizeof(fs)));
    fs.point[fs.npoint++] = (M2dPointField){"displacement", u, PETSC_TRUE, 0};
    if (has_contact) {
      fs.point[fs.npoint++] = (M2dPointField){"contact_pressure", cfield, PETSC_FALSE, 0};
      fs.point[fs.npoint++] = (M2dPointField){"gap", cfield, PETSC_FALSE, 1};
    }
    const char *cname[6]  = {"sigma_x", "sigma_y", "sigma_z", "sigma_xy", "von_mises", "body"};
    for (int k = 0; k < 6; k++) fs.cell[fs.ncell++] = (M2dCellField){cname[k], stress, 6, k};
    PetscCall(OutputWrite(&m, s.outdir, s.outname, s.write_vtu, s.write_hdf5, &fs));
  }
  t[ST_OUTPUT] = M2dWallTime() - t[ST_OUTPUT];
  PetscCall(PetscLogStagePop());
  t[ST_COUNT] = M2dWallTime() - tstart;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, t, ST_COUNT + 1, MPI_DOUBLE, MPI_MAX, comm));
  for (int k = 0; k < ST_COUNT; k++) SummaryReal(sum, "time", stage_name[k], t[k]);
  SummaryReal(sum, "time", "total", t[ST_COUNT]);
  if (s.write_vtu || s.write_hdf5) PetscCall(PetscPrintf(comm, "output written to %s/%s.{%s%s%s}\n", s.outdir, s.outname, s.write_hdf5 ? "h5,xmf" : "", s.write_hdf5 && s.write_vtu ? "," : "", s.write_vtu ? "vtu" : ""));
  PetscCall(PetscPrintf(comm, "dofs %" PetscInt_FMT ", time: mesh %.3f s, contact %.3f s, assembly %.3f s, solve %.3f s, output %.3f s, total %.3f s\n", 2 * m.nvert_global, t[0], t[1], t[2], t[3], t[4], t[5]));
  PetscCall(SummaryWrite(comm, s.summary, sum));

  if (has_contact) {
    PetscCall(ContactDestroy(&contact));
    PetscCall(KKTDestroy(&kkt));
  }
  PetscCall(VecDestroy(&lam));
  PetscCall(VecDestroy(&active));
  PetscCall(VecDestroy(&cfield));
  PetscCall(PetscFree(sum));
  PetscCall(PetscFree(stress));
  PetscCall(KSPDestroy(&ksp));
  PetscCall(VecDestroy(&u));
  PetscCall(VecDestroy(&f));
  PetscCall(MatDestroy(&K));
  PetscCall(MeshDestroy(&m));
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;
  PetscMPIInt    rank;

  if (M2dOptionsFilesCheck(argc, argv)) return 1; /* before PETSc follows a cycle of -options_file into a crash */
  ierr = PetscInitialize(&argc, &argv, NULL, help);
  if (ierr) return 1;
  ierr = M2dInstallErrorHandler();
  if (!ierr) ierr = Run(PETSC_COMM_WORLD);
  if (ierr) {
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    if (rank == 0) fprintf(stderr, "mortar2d: error: %s\n", M2dFirstError());
    fflush(stderr);
    /* objects of the failed run are not freed; skip PETSc's leak report */
    PetscOptionsClearValue(NULL, "-malloc_dump");
    PetscFinalize();
    return 1;
  }
  ierr = M2dRemoveErrorHandler();
  ierr = PetscFinalize() || ierr;
  return ierr ? 1 : 0;
}
