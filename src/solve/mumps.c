/* mumps.c - one sequential MUMPS per rank, its status agreed over a
 * communicator (see m2dmumps.h). */
#include "m2dmumps.h"
#include <dmumps_c.h>

#define ICNTL(I) icntl[(I) - 1]
#define INFOG(I) infog[(I) - 1]
#define RINFO(I) rinfo[(I) - 1]

/* the triples are handed to MUMPS without a copy: its index type must be ours */
typedef char M2dMumpsIntIsMumpsInt[sizeof(MUMPS_INT) == sizeof(M2dMumpsInt) ? 1 : -1];

enum { JOB_INIT = -1, JOB_END = -2, JOB_ANALYSE = 1, JOB_FACTOR = 2, JOB_SOLVE = 3 };

struct M2dMumps {
  MPI_Comm       comm;     /* the ranks that agree on every call */
  MPI_Comm       self;     /* this rank's MUMPS communicator (a copy of MPI_COMM_SELF) */
  PetscBool      active;   /* this rank has rows (else it only joins the agreement) */
  PetscInt       n;        /* rows */
  PetscInt       nschur;   /* Schur variables: the last nschur rows */
  M2dMumpsInt   *schur_rows; /* their 1-based numbers (MUMPS' LISTVAR_SCHUR) */
  PetscScalar   *schur;    /* the Schur complement as MUMPS writes it (by rows; symmetric: lower triangle) */
  DMUMPS_STRUC_C id;
};

/* One MUMPS job on the ranks with call set, then all ranks agree: the most
 * negative INFOG(1) wins, with the INFOG(2) of a rank that reported it.
 * *status gets the agreed INFOG(1) (>= 0: success, warnings included). */
static PetscErrorCode Run(M2dMumps *mu, int job, PetscBool call, int *status, int *detail)
{
  int st = 0, worst, st2 = PETSC_MIN_INT;

  PetscFunctionBeginUser;
  if (call) {
    mu->id.job = job;
    dmumps_c(&mu->id);
    st = (int)mu->id.INFOG(1);
  }
  PetscCallMPI(MPI_Allreduce(&st, &worst, 1, MPI_INT, MPI_MIN, mu->comm));
  *status = worst;
  *detail = 0;
  if (worst >= 0) PetscFunctionReturn(0);
  if (st == worst) st2 = (int)mu->id.INFOG(2);
  PetscCallMPI(MPI_Allreduce(&st2, detail, 1, MPI_INT, MPI_MAX, mu->comm));
  PetscFunctionReturn(0);
}

/* Run, and a failure is an error naming the phase */
static PetscErrorCode RunChecked(M2dMumps *mu, int job, const char *what)
{
  int st, detail;

  PetscFunctionBeginUser;
  PetscCall(Run(mu, job, mu->active, &st, &detail));
  PetscCheck(st >= 0, mu->comm, PETSC_ERR_LIB, "MUMPS %s failed: INFOG(1) = %d, INFOG(2) = %d%s", what, st, detail, st == -9 ? " (raise -mat_mumps_icntl_14)" : "");
  PetscFunctionReturn(0);
}

PetscErrorCode M2dMumpsCreate(MPI_Comm comm, PetscInt n, PetscBool symmetric, const M2dMumpsOptions *opt, M2dMumps **mu)
{
  M2dMumps   *m;
  PetscMPIInt rank;
  PetscBool   print;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&m));
  m->comm   = comm;
  m->self   = MPI_COMM_NULL;
  m->n      = n;
  m->active = (PetscBool)(n > 0);
  if (m->active) {
    PetscCallMPI(MPI_Comm_dup(PETSC_COMM_SELF, &m->self));
    m->id.comm_fortran = (MUMPS_INT)MPI_Comm_c2f(m->self);
    m->id.par          = 1; /* this rank is MUMPS' host and works */
    m->id.sym          = symmetric ? 2 : 0;
  }
  *mu = m;
  PetscCall(RunChecked(m, JOB_INIT, "initialisation"));
  if (!m->active) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  print              = (PetscBool)(opt->output > 0 && rank == 0);
  m->id.ICNTL(1)     = print ? 6 : -1; /* errors */
  m->id.ICNTL(2)     = -1;             /* diagnostics */
  m->id.ICNTL(3)     = print ? 6 : -1; /* global information */
  m->id.ICNTL(4)     = (MUMPS_INT)opt->output;
  m->id.ICNTL(7)     = (MUMPS_INT)opt->ordering;
  m->id.ICNTL(8)     = (MUMPS_INT)opt->scaling;
  m->id.ICNTL(14)    = (MUMPS_INT)opt->workspace;
  m->id.ICNTL(18)    = 0; /* the matrix is on the host, this rank */
  m->id.ICNTL(58)    = (MUMPS_INT)opt->symbolic;
  m->id.n            = (MUMPS_INT)n;
  PetscFunctionReturn(0);
}

PetscErrorCode M2dMumpsAnalyse(M2dMumps *mu, PetscInt64 nnz, M2dMumpsInt irn[], M2dMumpsInt jcn[], PetscScalar a[], M2dMumpsInt perm[], PetscInt nschur)
{
  PetscFunctionBeginUser;
  mu->nschur = nschur;
  if (mu->active) {
    mu->id.nnz     = (MUMPS_INT8)nnz;
    mu->id.irn     = irn;
    mu->id.jcn     = jcn;
    mu->id.a       = a;
    mu->id.perm_in = perm;
    if (perm) mu->id.ICNTL(7) = 1; /* the given pivot order */
    mu->id.ICNTL(19) = nschur > 0 ? 1 : 0; /* the Schur complement, by rows */
    if (nschur > 0) {
      PetscCall(PetscMalloc1(nschur, &mu->schur_rows));
      PetscCall(PetscMalloc1(nschur * nschur, &mu->schur));
      for (PetscInt k = 0; k < nschur; k++) mu->schur_rows[k] = (M2dMumpsInt)(mu->n - nschur + k + 1);
      mu->id.size_schur    = (MUMPS_INT)nschur;
      mu->id.listvar_schur = mu->schur_rows;
      mu->id.schur         = mu->schur;
      mu->id.schur_lld     = (MUMPS_INT)nschur;
    }
  }
  PetscCall(RunChecked(mu, JOB_ANALYSE, "analysis"));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dMumpsFactor(M2dMumps *mu, PetscBool *singular, PetscLogDouble *flops)
{
  int st, detail;

  PetscFunctionBeginUser;
  PetscCall(Run(mu, JOB_FACTOR, mu->active, &st, &detail));
  if (mu->active) PetscCall(PetscInfo(NULL, "MUMPS factorization on this rank: INFOG(1) = %d, null pivots INFOG(28) = %d\n", (int)mu->id.INFOG(1), (int)mu->id.INFOG(28)));
  *singular = (PetscBool)(st == -10);
  *flops    = mu->active ? (PetscLogDouble)mu->id.RINFO(3) : 0.0;
  if (mu->active) { /* the solves need neither the matrix nor the ordering */
    mu->id.irn = mu->id.jcn = NULL;
    mu->id.a                = NULL;
    mu->id.perm_in          = NULL;
  }
  PetscCheck(st >= 0 || st == -10, mu->comm, PETSC_ERR_LIB, "MUMPS factorization failed: INFOG(1) = %d, INFOG(2) = %d%s", st, detail, st == -9 ? " (raise -mat_mumps_icntl_14)" : "");
  PetscFunctionReturn(0);
}

PetscErrorCode M2dMumpsGetSchur(M2dMumps *mu, PetscScalar **S)
{
  PetscInt     m = mu->nschur;
  PetscScalar *s = mu->schur;

  PetscFunctionBeginUser;
  PetscCheck(s || m == 0, PETSC_COMM_SELF, PETSC_ERR_ORDER, "M2dMumpsGetSchur: once, after the factorization");
  /* by rows -> by columns: S(p,q) sits at s[p m + q]. Symmetric: only p >= q
   * is there, which read by columns is the upper triangle of S^T = S */
  for (PetscInt q = 0; q < m; q++)
    for (PetscInt p = q + 1; p < m; p++) {
      PetscScalar t = s[p * m + q]; /* S(p,q), lower */
      if (mu->id.sym) s[p + q * m] = t;
      else {
        s[p * m + q] = s[q * m + p];
        s[q * m + p] = t;
      }
    }
  *S = s;
  mu->schur = NULL;
  PetscCall(PetscFree(mu->schur_rows));
  if (mu->active) {
    mu->id.listvar_schur = NULL;
    mu->id.schur         = NULL;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dMumpsSolve(M2dMumps *mu, M2dMumpsPhase phase, PetscScalar rhs[], PetscScalar red[])
{
  PetscBool split = (PetscBool)(mu->nschur > 0), run = (PetscBool)(split || phase == M2D_MUMPS_CONDENSE);
  int       st, detail;

  PetscFunctionBeginUser;
  if (mu->active && run) {
    mu->id.rhs       = rhs;
    mu->id.lrhs      = (MUMPS_INT)mu->n;
    mu->id.nrhs      = 1;
    mu->id.redrhs    = red;
    mu->id.lredrhs   = (MUMPS_INT)PetscMax(mu->nschur, 1);
    mu->id.ICNTL(20) = 0; /* dense right-hand side */
    mu->id.ICNTL(21) = 0; /* solution in place */
    mu->id.ICNTL(26) = !split ? 0 : phase == M2D_MUMPS_CONDENSE ? 1 : 2;
  }
  PetscCall(Run(mu, JOB_SOLVE, (PetscBool)(mu->active && run), &st, &detail)); /* a rank with nothing to expand joins the agreement */
  PetscCheck(st >= 0, mu->comm, PETSC_ERR_LIB, "MUMPS solve (%s) failed: INFOG(1) = %d, INFOG(2) = %d", phase == M2D_MUMPS_CONDENSE ? "condensation" : "expansion", st, detail);
  PetscFunctionReturn(0);
}

PetscErrorCode M2dMumpsDestroy(M2dMumps **mu)
{
  M2dMumps *m = *mu;

  PetscFunctionBeginUser;
  if (!m) PetscFunctionReturn(0);
  if (m->active) {
    m->id.job = JOB_END;
    dmumps_c(&m->id);
    PetscCallMPI(MPI_Comm_free(&m->self));
  }
  PetscCall(PetscFree(m->schur_rows));
  PetscCall(PetscFree(m->schur));
  PetscCall(PetscFree(*mu));
  PetscFunctionReturn(0);
}
