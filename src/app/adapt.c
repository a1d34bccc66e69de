/* adapt.c - the adaptive loop (see adapt.h). */
#include "adapt.h"
#include "optcheck.h"
#include "options.h"
#include "remesh.h"
#include "step.h"
#include "util.h"
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#define M2D_ADAPT_MIN_GROWTH 1.189207115002721 /* 2^(1/4): the loop's smallest step */

/* whether the .geo text at path, or a file it Includes, has the identifier
 * name outside comments (gmsh ignores a -setnumber of a name the .geo never
 * uses); -1 when a file cannot be read */
static int GeoHasName(const char *path, const char *name, int depth)
{
  FILE  *f = depth < 8 ? fopen(path, "r") : NULL;
  char  *t, *p, *q, inc[PETSC_MAX_PATH_LEN];
  long   n;
  int    found = 0, prev_include = 0;
  size_t len = strlen(name);

  if (!f) return -1;
  if (fseek(f, 0, SEEK_END) || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) || !(t = calloc((size_t)n + 1, 1))) {
    fclose(f);
    return -1;
  }
  n = (long)fread(t, 1, (size_t)n, f);
  fclose(f);
  for (p = t; !found && p < t + n && *p;) {
    if (p[0] == '/' && p[1] == '/') p += strcspn(p, "\n");
    else if (p[0] == '/' && p[1] == '*') p = (q = strstr(p + 2, "*/")) ? q + 2 : t + n;
    else if (*p == '"') { /* a string: the file name of an Include */
      q = strchr(p + 1, '"');
      if (!q) break;
      if (prev_include && (size_t)(q - p - 1) < sizeof(inc)) {
        const char *slash = strrchr(path, '/');
        int         dir   = p[1] == '/' || !slash ? 0 : (int)(slash - path + 1);
        snprintf(inc, sizeof(inc), "%.*s%.*s", dir, path, (int)(q - p - 1), p + 1);
        found = GeoHasName(inc, name, depth + 1) == 1;
      }
      prev_include = 0;
      p            = q + 1;
    } else if (isalpha((unsigned char)*p) || *p == '_') {
      for (q = p; isalnum((unsigned char)*q) || *q == '_'; q++) { }
      found        = (size_t)(q - p) == len && !strncmp(p, name, len);
      prev_include = q - p == 7 && !strncmp(p, "Include", 7);
      p            = q;
    } else {
      if (!isspace((unsigned char)*p)) prev_include = 0;
      p++;
    }
  }
  free(t);
  return found;
}

/* options that need -adapt, and -geo_setnumber names the .geo must use
 * (optcheck.h); in an adaptive run the solver path may change from mesh to
 * mesh (-kkt_condensed_max): the paths' own options are not judged per mesh */
static PetscErrorCode CheckEffect(MPI_Comm comm, const M2dScene *s, const M2dAdaptOptions *ao)
{
  PetscMPIInt rank;
  PetscBool   path_given;

  PetscFunctionBeginUser;
  if (s->help) PetscFunctionReturn(0);
  if (!ao->enabled) PetscCall(M2dOptionsNoEffect(comm, "-adapt_target -adapt_tolerance -adapt_max_steps -adapt_max_dofs -adapt_max_seconds -adapt_max_memory -adapt_goal -adapt_grading -adapt_growth -adapt_keep -adapt_quads -geo -geo_setnumber", "without -adapt"));
  if (ao->enabled && ao->goal == 1) PetscCall(M2dOptionsReadLater("dual_")); /* the dual problem's solver, after the primal's */
  PetscCall(PetscOptionsHasName(NULL, NULL, "-kkt_path", &path_given));
  if (ao->enabled && !path_given) {
    const char *later[] = {"kkt_ldlt", "ksp_", "pc_", "fieldsplit_", "mat_mumps_"};
    for (size_t i = 0; i < sizeof(later) / sizeof(later[0]); i++) PetscCall(M2dOptionsReadLater(later[i]));
  }
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  for (PetscInt i = 0; ao->enabled && i < ao->nnumber; i++) {
    int has = 1;
    if (!strchr(ao->number_name[i], '.') && rank == 0) has = GeoHasName(s->geo, ao->number_name[i], 0); /* Mesh.X: an option of gmsh's */
    PetscCallMPI(MPI_Bcast(&has, 1, MPI_INT, 0, comm));
    PetscCheck(has != 0, comm, PETSC_ERR_USER_INPUT, "option -geo_setnumber: '%s' is no name in %s (gmsh would ignore it)", ao->number_name[i], s->geo);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode AdaptReadOptions(MPI_Comm comm, const M2dScene *s, M2dAdaptOptions *ao)
{
  const char *quads[] = {"subdivide", "fullquad", "blossom", "simple"}; /* order of M2dRemeshQuads */
  const char *goals[] = {"energy", "contact"};
  const char *keeps[] = {"best", "last"};
  char       *num[M2D_ADAPT_MAX_NUMBERS];
  PetscInt    nnum = M2D_ADAPT_MAX_NUMBERS;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(ao, sizeof(*ao)));
  ao->target    = 1e-2;
  ao->max_steps = 8;
  ao->max_dofs  = 1000000;
  ao->quads     = M2D_QUADS_SUBDIVIDE;
  ao->grading   = 1.2;
  ao->growth    = 4;
  ao->tolerance = 0.05;
  PetscOptionsBegin(comm, NULL, "mortar2d: adaptive meshes", "");
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-adapt", "adapt the mesh of the scene's .geo (-geo) to the error estimate", ao->enabled, &ao->enabled));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-adapt_target", "stop when the relative estimate is below this; each mesh is sized to reach 0.9 of it (adaptivity.md)", ao->target, &ao->target, NULL));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-adapt_tolerance", "stop also when the estimate is at most this fraction above the target (0: only below it)", ao->tolerance, &ao->tolerance, NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-adapt_max_steps", "at most this many meshes", ao->max_steps, &ao->max_steps, NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-adapt_max_dofs", "no mesh has more dofs than this (the next one is made smaller to fit)", ao->max_dofs, &ao->max_dofs, NULL));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-adapt_max_seconds", "the next mesh is made smaller to end within this many seconds of the loop's start (0: no limit)", ao->max_seconds, &ao->max_seconds, NULL));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-adapt_max_memory", "the next mesh is made smaller to keep each rank's peak memory below this many MB (0: no limit)", ao->max_memory, &ao->max_memory, NULL));
  PetscCall(M2dOptionsEList(PetscOptionsObject, "-adapt_goal", "what the meshes aim at: energy (energy-norm error) or contact (contact pressure, dual-weighted)", goals, 2, &ao->goal));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-adapt_grading", "sizes grow by at most this factor per element (1: no limit)", ao->grading, &ao->grading, NULL));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-adapt_growth", "each mesh has at most this many times the dofs of the one before (at least 1.19)", ao->growth, &ao->growth, NULL));
  PetscCall(M2dOptionsEList(PetscOptionsObject, "-adapt_keep", "the results of: best (the last mesh within 10% of the smallest estimate) or last (the last made)", keeps, 2, &ao->keep_last));
  PetscCall(M2dOptionsEList(PetscOptionsObject, "-adapt_quads", "how gmsh makes quads from the size field: subdivide, fullquad, blossom, simple (faster, big meshes)", quads, 4, &ao->quads));
  PetscCall(M2dOptionsStringArray(PetscOptionsObject, "-geo_setnumber", "parameters of the .geo as NAME=VALUE, comma separated (gmsh's -setnumber); default: none", M2D_ADAPT_MAX_NUMBERS, 0, num, &nnum));
  PetscOptionsEnd();
  PetscCall(M2dOptionsRaise(comm));
  for (PetscInt i = 0; i < nnum; i++) {
    char     *eq = strchr(num[i], '='), *end = NULL;
    PetscBool ok = (PetscBool)(eq != NULL && eq != num[i] && (size_t)(eq - num[i]) < sizeof(ao->number_name[0]));
    if (ok) {
      ao->number_value[i] = strtod(eq + 1, &end);
      ok                  = (PetscBool)(end != eq + 1 && *end == 0 && PetscIsNormalReal(PetscAbsReal(ao->number_value[i]) + 1));
      *eq                 = 0;
      PetscCall(PetscStrncpy(ao->number_name[i], num[i], sizeof(ao->number_name[i])));
      *eq = '=';
    }
    if (!ok) PetscCall(M2dOptionsDefer("option -geo_setnumber: '%s' is not NAME=VALUE", num[i]));
  }
  for (PetscInt i = 0; i < nnum; i++) PetscCall(PetscFree(num[i]));
  PetscCall(M2dOptionsRaise(comm));
  ao->nnumber = nnum;
  PetscCheck(ao->target > 0 && ao->target < 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_target: %g must be in (0, 1)", (double)ao->target);
  PetscCheck(ao->max_steps >= 1 && ao->max_steps <= M2D_ADAPT_MAX_STEPS, comm, PETSC_ERR_USER_INPUT, "option -adapt_max_steps: %" PetscInt_FMT " must be in [1, %d]", ao->max_steps, M2D_ADAPT_MAX_STEPS);
  PetscCheck(ao->grading >= 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_grading: %g must be >= 1", (double)ao->grading);
  PetscCheck(ao->growth >= M2D_ADAPT_MIN_GROWTH && ao->growth <= 64, comm, PETSC_ERR_USER_INPUT, "option -adapt_growth: %g must be in [%.4g, 64] (the loop's smallest step; the size field refines a cell at most 8 times per mesh)", (double)ao->growth, M2D_ADAPT_MIN_GROWTH);
  PetscCheck(ao->max_dofs >= 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_max_dofs: %" PetscInt_FMT " must be >= 1", ao->max_dofs);
  PetscCheck(ao->tolerance >= 0 && ao->tolerance < 1, comm, PETSC_ERR_USER_INPUT, "option -adapt_tolerance: %g must be in [0, 1)", (double)ao->tolerance);
  PetscCheck(ao->max_seconds >= 0 && ao->max_memory >= 0, comm, PETSC_ERR_USER_INPUT, "option -adapt_max_%s: %g must be >= 0 (0: no limit)", ao->max_seconds < 0 ? "seconds" : "memory", (double)(ao->max_seconds < 0 ? ao->max_seconds : ao->max_memory));
  PetscCheck(!ao->enabled || s->geo[0], comm, PETSC_ERR_USER_INPUT, "option -adapt: needs the scene's .geo (-geo FILE)");
  PetscCall(CheckEffect(comm, s, ao));
  PetscFunctionReturn(0);
}

/* The previous mesh on rank 0, with the new size per quad (the size field's
 * h_new): what the remesher's size field is built on. Canonical: the same
 * for the same mesh and sizes whatever the partition (1 or 2 ranks give the
 * same meshes), because cells and vertices are numbered by their coordinates,
 * not by the ranks' dof numbers. Coordinates and sizes in the user's units
 * until GeoUnits turns them into the .geo's (-mesh_scale). Quads carry the
 * physical tag of their body's surface (bodytag). */
typedef struct {
  MshMesh  msh;
  double  *hcell;
  PetscInt *cellbody;  /* body index per quad */
  double   *vkey;      /* per vertex in id order: body, x, y (the sort key, for lookups) */
} PrevMesh;

static void PrevMeshFree(PrevMesh *p)
{
  MshFree(&p->msh);
  free(p->hcell);
  free(p->cellbody);
  free(p->vkey);
  p->hcell    = NULL;
  p->cellbody = NULL;
  p->vkey     = NULL;
}

/* what each rank sends rank 0 about a cell (all doubles: one MPI datatype) */
typedef struct {
  double x[8]; /* corners, counter-clockwise, user units */
  double body;
  double hnew; /* the new size, user units */
} CellRecord;
#define M2D_DOUBLES(T) ((int)(sizeof(T) / sizeof(double)))

static PetscErrorCode PackRecords(const M2dStep *st, CellRecord *cr)
{
  const M2dMesh     *m = &st->pb.mesh;
  PetscInt           nlc = m->cEnd - m->cStart;
  PetscSection       cs;
  Vec                cl;
  const PetscScalar *ca;
  PetscReal         *h, L = st->pb.units.L;

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinatesLocal(m->dm, &cl));
  PetscCall(DMGetCoordinateSection(m->dm, &cs));
  PetscCall(PetscMalloc1(nlc + 1, &h));
  PetscCall(M2dCellSizes(m, h));
  PetscCall(VecGetArrayRead(cl, &ca));
  for (PetscInt c = 0; c < nlc; c++) {
    PetscReal xy[8];
    MeshCellCoordinates(m, ca, cs, c + m->cStart, xy);
    for (int k = 0; k < 8; k++) cr[c].x[k] = xy[k] * L; /* the same product as ContactToUserUnits' */
    cr[c].body = (double)m->cellbody[c];
    cr[c].hnew = st->sol.eta[M2D_ETA_FIELDS * c + 2] * h[c] * L; /* h_new / h, times h */
  }
  PetscCall(VecRestoreArrayRead(cl, &ca));
  PetscCall(PetscFree(h));
  PetscFunctionReturn(0);
}

/* gather n records of `width` doubles to rank 0 (*all there, *ntot their count) */
static PetscErrorCode GatherDoubles(MPI_Comm comm, const double *mine, PetscInt n, int width, double **all, PetscInt *ntot)
{
  PetscMPIInt rank, size, cnt, *counts = NULL, *displs = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMPIIntCast(width * n, &cnt));
  *all  = NULL;
  *ntot = 0;
  if (rank == 0) PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  PetscCallMPI(MPI_Gather(&cnt, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
  if (rank == 0) {
    displs[0] = 0;
    for (PetscMPIInt r = 0; r < size; r++) displs[r + 1] = displs[r] + counts[r];
    PetscCall(PetscMalloc1(displs[size] + 1, all));
    *ntot = displs[size] / width;
  }
  PetscCallMPI(MPI_Gatherv(mine, cnt, MPI_DOUBLE, *all, counts, displs, MPI_DOUBLE, 0, comm));
  if (rank == 0) PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(0);
}

/* lexicographic order of n doubles */
static int CmpKey(const double *a, const double *b, int n)
{
  for (int k = 0; k < n; k++)
    if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
  return 0;
}

/* cells by (body, centroid y, centroid x, corners); vertices by (body, x, y) */
typedef struct {
  double key[11];
  long   i;
} Keyed;
static int CmpCellKey(const void *a, const void *b)
{
  return CmpKey(((const Keyed *)a)->key, ((const Keyed *)b)->key, 11);
}
static int CmpVertKey(const void *a, const void *b)
{
  return CmpKey(((const Keyed *)a)->key, ((const Keyed *)b)->key, 3);
}

/* rank 0: the canonical mesh from the gathered cells (see PrevMesh); its
 * physical surfaces are the bodies (tag b + 1, named as the scene names them),
 * which the remesher matches to the .geo's by name */
static PetscErrorCode BuildPrevMesh(const CellRecord *cr, PetscInt nc, const M2dScene *s, PrevMesh *prev)
{
  MshMesh *q = &prev->msh;
  Keyed   *ck, *vk;
  long     nv = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(q, sizeof(*q)));
  PetscCall(PetscMalloc2(nc + 1, &ck, 4 * nc + 1, &vk));
  for (PetscInt c = 0; c < nc; c++) {
    ck[c].key[0] = cr[c].body;
    ck[c].key[1] = ck[c].key[2] = 0;
    for (int k = 0; k < 4; k++) ck[c].key[1] += 0.25 * cr[c].x[2 * k + 1], ck[c].key[2] += 0.25 * cr[c].x[2 * k];
    for (int k = 0; k < 8; k++) ck[c].key[3 + k] = cr[c].x[k];
    ck[c].i = c;
  }
  qsort(ck, (size_t)nc, sizeof(Keyed), CmpCellKey);
  for (PetscInt c = 0; c < nc; c++)
    for (int k = 0; k < 4; k++) {
      Keyed *v  = &vk[4 * c + k];
      v->key[0] = cr[ck[c].i].body;
      v->key[1] = cr[ck[c].i].x[2 * k];
      v->key[2] = cr[ck[c].i].x[2 * k + 1];
      v->i      = 4 * c + k; /* corner k of canonical cell c */
    }
  qsort(vk, (size_t)(4 * nc), sizeof(Keyed), CmpVertKey);
  q->nquad       = nc;
  q->xy          = (double *)malloc((size_t)(8 * nc + 1) * sizeof(double));
  q->quad        = (long *)malloc((size_t)(4 * nc + 1) * sizeof(long));
  q->quadtag     = (long *)malloc((size_t)(nc + 1) * sizeof(long));
  q->quadphys    = (int *)malloc((size_t)(nc + 1) * sizeof(int));
  prev->hcell    = (double *)malloc((size_t)(nc + 1) * sizeof(double));
  prev->cellbody = (PetscInt *)malloc((size_t)(nc + 1) * sizeof(PetscInt));
  prev->vkey     = (double *)malloc((size_t)(12 * nc + 1) * sizeof(double));
  q->phys        = (MshPhysical *)calloc((size_t)s->nbody + 1, sizeof(MshPhysical));
  if (!(q->xy && q->quad && q->quadtag && q->quadphys && prev->hcell && prev->cellbody && prev->vkey && q->phys)) {
    PetscCall(PetscFree2(ck, vk));
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_MEM, "out of memory gathering the mesh for remeshing");
  }
  for (PetscInt k = 0; k < 4 * nc; k++) {
    if (k == 0 || CmpVertKey(&vk[k], &vk[k - 1])) {
      for (int d = 0; d < 3; d++) prev->vkey[3 * nv + d] = vk[k].key[d];
      q->xy[2 * nv]     = vk[k].key[1];
      q->xy[2 * nv + 1] = vk[k].key[2];
      nv++;
    }
    q->quad[vk[k].i] = nv - 1;
  }
  q->nnode = nv;
  for (PetscInt c = 0; c < nc; c++) {
    q->quadtag[c]     = c + 1;
    prev->cellbody[c] = (PetscInt)cr[ck[c].i].body;
    q->quadphys[c]    = (int)prev->cellbody[c] + 1;
    prev->hcell[c]    = cr[ck[c].i].hnew;
  }
  for (PetscInt b = 0; b < s->nbody; b++) {
    q->phys[b].dim = 2;
    q->phys[b].tag = (int)b + 1;
    PetscCall(PetscStrncpy(q->phys[b].name, s->body[b].name, sizeof(q->phys[b].name)));
  }
  q->nphys = (int)s->nbody;
  PetscCall(PetscFree2(ck, vk));
  PetscFunctionReturn(0);
}

/* the previous mesh on rank 0 (PrevMesh), with the new size per quad */
static PetscErrorCode GatherPrevMesh(const M2dStep *st, PrevMesh *prev)
{
  const M2dMesh *m    = &st->pb.mesh;
  MPI_Comm       comm = PetscObjectComm((PetscObject)m->dm);
  PetscInt       nlc = m->cEnd - m->cStart, nc = 0;
  CellRecord    *cr, *call;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nlc + 1, &cr));
  PetscCall(PackRecords(st, cr));
  PetscCall(GatherDoubles(comm, (double *)cr, nlc, M2D_DOUBLES(CellRecord), (double **)&call, &nc));
  PetscCall(PetscFree(cr));
  if (call) PetscCall(BuildPrevMesh(call, nc, st->pb.user, prev)); /* rank 0 */
  PetscCall(PetscFree(call));
  PetscFunctionReturn(0);
}

/* rank 0: vertex id of (body, x, y) in prev (exact coordinates), -1 if none */
static long FindVertex(const PrevMesh *prev, PetscInt body, const PetscReal x[2])
{
  const double key[3] = {(double)body, x[0], x[1]};
  long         lo = 0, hi = prev->msh.nnode - 1;
  while (lo <= hi) {
    long mid = (lo + hi) / 2;
    int  c   = CmpKey(&prev->vkey[3 * mid], key, 3);
    if (!c) return mid;
    if (c < 0) lo = mid + 1;
    else hi = mid - 1;
  }
  return -1;
}

/* vertex -> cells (CSR) of a mesh: vptr[nv + 1], vadj[4 nc] (caller frees both) */
static PetscErrorCode VertexCells(const MshMesh *q, PetscInt **vptr, PetscInt **vadj)
{
  PetscInt nc = (PetscInt)q->nquad, nv = (PetscInt)q->nnode, *p, *a;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(nv + 1, &p));
  PetscCall(PetscMalloc1(4 * nc + 1, &a));
  for (PetscInt c = 0; c < 4 * nc; c++) p[q->quad[c] + 1]++;
  for (PetscInt v = 0; v < nv; v++) p[v + 1] += p[v];
  for (PetscInt c = 0; c < 4 * nc; c++) a[p[q->quad[c]]++] = c / 4;
  for (PetscInt v = nv; v > 0; v--) p[v] = p[v - 1];
  p[0]  = 0;
  *vptr = p;
  *vadj = a;
  PetscFunctionReturn(0);
}

/* rank 0: the cell of prev that has surface edge e (user units) as a side, -1 if none */
static PetscInt EdgeCell(const PrevMesh *prev, const PetscInt *vptr, const PetscInt *vadj, const M2dSurface *s, PetscInt e)
{
  long va = FindVertex(prev, s->body, &s->x[2 * s->edge[2 * e]]), vb = FindVertex(prev, s->body, &s->x[2 * s->edge[2 * e + 1]]);
  if (va < 0 || vb < 0) return -1;
  for (PetscInt k = vptr[va]; k < vptr[va + 1]; k++)
    for (int j = 0; j < 4; j++)
      if (prev->msh.quad[4 * vadj[k] + j] == vb) return vadj[k];
  return -1;
}

/* Rank 0: sizes balanced across the contact interface. Where the two surfaces
 * touch (a segment whose non-mortar nodes' gap is within the larger of the two
 * cells' new sizes), the non-mortar cell takes the smaller of the two sizes
 * and the mortar cell that divided by 1.3: a non-mortar side finer than the
 * mortar side sees the mortar edges' facets as waviness of the surface it is
 * pressed on, and its multipliers are then less tied down by the mortar side's
 * displacements (a stiff non-mortar body on a soft mortar one, such as a punch
 * on its foundation, showed spikes of 20% of the peak where the non-mortar
 * side was locally 1.5 times finer; docs/); indicators that feed on such
 * ripple would refine one side further. The gradation then carries the sizes
 * into each body. nm_too false: only the mortar cells, to 1.3 times finer than
 * the non-mortar cells they face (after the gradation, which lowers each side's
 * sizes on its own). c: the contact pair in the user's units (after
 * ReportCompute; its reach still in reference units, L the length unit). */
static PetscErrorCode Balance(PrevMesh *prev, const M2dContactPair *c, PetscReal L, PetscBool nm_too)
{
  M2dSegmentSet        own;
  const M2dSegmentSet *S = &c->seg;
  PetscInt            *vptr, *vadj, *cnm, *cm;
  PetscReal           *gap, *h0;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&own, sizeof(own)));
  if (S->nseg == 0) { /* node-to-segment: the mortar segments tell where the surfaces face each other */
    PetscCall(MortarBuildSegments(&c->nm, &c->m, c->reach * L, &own));
    S = &own;
  }
  PetscCall(VertexCells(&prev->msh, &vptr, &vadj));
  PetscCall(PetscMalloc3(c->nm.nedge + 1, &cnm, c->m.nedge + 1, &cm, c->nm.nnode + 1, &gap));
  for (PetscInt e = 0; e < c->nm.nedge; e++) cnm[e] = EdgeCell(prev, vptr, vadj, &c->nm, e);
  for (PetscInt e = 0; e < c->m.nedge; e++) cm[e] = EdgeCell(prev, vptr, vadj, &c->m, e);
  for (PetscInt i = 0; i < c->nm.nnode; i++) gap[i] = PETSC_MAX_REAL;
  for (PetscInt j = 0; j < c->R.n; j++) gap[c->R.node[j]] = PetscAbsReal(c->gap[j]); /* c: one pair (its normal rows) */
  PetscCall(PetscMalloc1(prev->msh.nquad + 1, &h0)); /* every pair from the sizes as they came: the order of the segments cannot matter */
  PetscCall(PetscArraycpy(h0, prev->hcell, prev->msh.nquad));
  for (PetscInt k = 0; k < S->nseg; k++) {
    const M2dSegment *sg = &S->seg[k];
    PetscInt          a = cnm[sg->nm_edge], b = cm[sg->m_edge];
    PetscReal         g = PetscMin(gap[c->nm.edge[2 * sg->nm_edge]], gap[c->nm.edge[2 * sg->nm_edge + 1]]), h;
    if (a < 0 || b < 0 || !(g <= PetscMax(h0[a], h0[b]))) continue;
    h = nm_too ? PetscMin(h0[a], h0[b]) : h0[a];
    if (nm_too) prev->hcell[a] = PetscMin(prev->hcell[a], h);
    prev->hcell[b] = PetscMin(prev->hcell[b], h / 1.3);
  }
  PetscCall(PetscFree(h0));
  PetscCall(PetscFree3(cnm, cm, gap));
  PetscCall(PetscFree(vptr));
  PetscCall(PetscFree(vadj));
  PetscCall(SegmentSetDestroy(&own));
  PetscFunctionReturn(0);
}

/* Rank 0: every size rounded to 16 steps per octave (a factor 2^(1/16) =
 * 1.044): the round-off by which 1 and 2 ranks, or two BLAS, differ cannot
 * move a size, so gmsh gets the same field and makes the same mesh. */
static void Quantize(PrevMesh *prev)
{
  for (long c = 0; c < prev->msh.nquad; c++) prev->hcell[c] = PetscPowReal(2.0, round(16 * PetscLog2Real(prev->hcell[c])) / 16);
}

/* Rank 0: coordinates and sizes from the user's units into the .geo's */
static void GeoUnits(PrevMesh *prev, PetscReal scale)
{
  for (long i = 0; i < 2 * prev->msh.nnode; i++) prev->msh.xy[i] /= scale;
  for (long c = 0; c < prev->msh.nquad; c++) prev->hcell[c] /= scale;
}

/* a binary heap of (size, cell) for the gradation sweep */
typedef struct {
  PetscInt  n;
  PetscReal *key;
  PetscInt  *cell;
} Heap;

static void HeapPush(Heap *h, PetscReal key, PetscInt cell)
{
  PetscInt i = h->n++;
  while (i > 0 && h->key[(i - 1) / 2] > key) {
    h->key[i]  = h->key[(i - 1) / 2];
    h->cell[i] = h->cell[(i - 1) / 2];
    i          = (i - 1) / 2;
  }
  h->key[i]  = key;
  h->cell[i] = cell;
}

static void HeapPop(Heap *h, PetscReal *key, PetscInt *cell)
{
  PetscReal k = h->key[--h->n];
  PetscInt  c = h->cell[h->n], i = 0;
  *key        = h->key[0];
  *cell       = h->cell[0];
  for (;;) {
    PetscInt j = 2 * i + 1;
    if (j >= h->n) break;
    if (j + 1 < h->n && h->key[j + 1] < h->key[j]) j++;
    if (h->key[j] >= k) break;
    h->key[i]  = h->key[j];
    h->cell[i] = h->cell[j];
    i          = j;
  }
  h->key[i]  = k;
  h->cell[i] = c;
}

/* Gradation (rank 0): sizes may grow by at most a factor g per element, i.e.
 * h_K <= h_N + (g - 1) |c_K - c_N| over cells sharing a vertex, enforced by a
 * Dijkstra sweep from the smallest sizes. A steep jump from a fine zone to a
 * coarse one makes the far field stiffer than the body and moves the edge of
 * the contact zone; a gentle grading costs few cells. */
static PetscErrorCode Grade(PrevMesh *prev, PetscReal g)
{
  MshMesh   *q = &prev->msh;
  PetscInt   nc = (PetscInt)q->nquad, *vptr, *vadj;
  PetscReal *cen;
  Heap       hp;
  PetscBool *done;

  PetscFunctionBeginUser;
  if (!(g > 1) || nc == 0) PetscFunctionReturn(0);
  PetscCall(VertexCells(q, &vptr, &vadj));
  PetscCall(PetscMalloc2(2 * nc + 1, &cen, nc + 1, &done));
  for (PetscInt c = 0; c < nc; c++) {
    cen[2 * c] = cen[2 * c + 1] = 0;
    for (int k = 0; k < 4; k++) cen[2 * c] += 0.25 * q->xy[2 * q->quad[4 * c + k]], cen[2 * c + 1] += 0.25 * q->xy[2 * q->quad[4 * c + k] + 1];
    done[c] = PETSC_FALSE;
  }
  PetscCall(PetscMalloc2(4 * 8 * nc + nc + 1, &hp.key, 4 * 8 * nc + nc + 1, &hp.cell));
  hp.n = 0;
  for (PetscInt c = 0; c < nc; c++) HeapPush(&hp, prev->hcell[c], c);
  while (hp.n > 0) {
    PetscReal h;
    PetscInt  c;
    HeapPop(&hp, &h, &c);
    if (done[c] || h > prev->hcell[c]) continue;
    done[c] = PETSC_TRUE;
    for (int k = 0; k < 4; k++) {
      PetscInt v = q->quad[4 * c + k];
      for (PetscInt a = vptr[v]; a < vptr[v + 1]; a++) {
        PetscInt  o  = vadj[a];
        PetscReal hn = h + (g - 1) * PetscSqrtReal(PetscSqr(cen[2 * o] - cen[2 * c]) + PetscSqr(cen[2 * o + 1] - cen[2 * c + 1]));
        if (!done[o] && hn < prev->hcell[o] && q->quadphys[o] == q->quadphys[c]) {
          prev->hcell[o] = hn;
          if (hp.n < 4 * 8 * nc + nc) HeapPush(&hp, hn, o);
        }
      }
    }
  }
  PetscCall(PetscFree2(hp.key, hp.cell));
  PetscCall(PetscFree2(cen, done));
  PetscCall(PetscFree(vptr));
  PetscCall(PetscFree(vadj));
  PetscFunctionReturn(0);
}

/* rank 0: the .geo meshed by gmsh, with the previous mesh's size field from
 * step 1 on; *dofs (every rank): 2 x the mesh's nodes */
static PetscErrorCode Remesh(MPI_Comm comm, const M2dScene *s, const M2dAdaptOptions *ao, const PrevMesh *prev, PetscInt step, MshMesh *msh, double *seconds, PetscInt *dofs)
{
  PetscMPIInt    rank;
  char           err[1024] = "";
  M2dRemeshStats stats;
  const char    *names[M2D_ADAPT_MAX_NUMBERS];
  double         values[M2D_ADAPT_MAX_NUMBERS], n = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscMemzero(msh, sizeof(*msh)));
  *seconds = 0;
  if (rank == 0) {
    M2dRemeshInput in;
    PetscCall(PetscMemzero(&in, sizeof(in)));
    for (PetscInt i = 0; i < ao->nnumber; i++) {
      names[i]  = ao->number_name[i];
      values[i] = ao->number_value[i];
    }
    in.geo     = s->geo;
    in.nnumber = (int)ao->nnumber;
    in.names   = names;
    in.values  = values;
    in.quads   = (M2dRemeshQuads)ao->quads;
    in.max_nodes = 0.5 * (double)ao->max_dofs; /* gmsh's memory bounded by the cap's mesh */
    if (step > 0) {
      in.prev  = &prev->msh;
      in.hcell = prev->hcell;
    }
    if (M2dRemesh(&in, msh, &stats, err, sizeof(err))) MshFree(msh);
    else {
      *seconds = stats.seconds_total;
      n        = 2.0 * (double)msh->nnode;
    }
  }
  PetscCall(M2dCheckCollective(comm, err[0] ? PETSC_TRUE : PETSC_FALSE, err));
  PetscCallMPI(MPI_Bcast(&n, 1, MPI_DOUBLE, 0, comm));
  *dofs = (PetscInt)n;
  PetscFunctionReturn(0);
}

/* what holds the next mesh's size (Plan) */
typedef enum {
  LIMIT_NONE,
  LIMIT_GROWTH, /* -adapt_growth: far from the target */
  LIMIT_DOFS,   /* the limits: -adapt_max_dofs, -adapt_max_seconds, -adapt_max_memory */
  LIMIT_SECONDS,
  LIMIT_MEMORY
} Limit;
static const char *const LimitOption[] = {"", "-adapt_growth", "-adapt_max_dofs", "-adapt_max_seconds", "-adapt_max_memory"};

/* why the loop stopped (the summary's adapt_stop): the target, near it, the
 * step count, or a limit (limit: which) that holds the mesh while the estimate
 * no longer falls by 10% (held) or that leaves no room for the next mesh (fit) */
typedef enum {
  STOP_NONE,
  STOP_TARGET,
  STOP_NEAR,
  STOP_STEPS,
  STOP_HELD,
  STOP_FIT
} StopReason;
static const char *const LimitKey[] = {"", "", "max_dofs", "max_seconds", "max_memory"};

/* The estimate of the goal: the relative energy-norm error, or with
 * -adapt_goal contact the relative L2 error of the contact pressure
 * (ContactPressureEstimate): what the target, the best mesh and the progress
 * are judged by */
static PetscReal GoalEstimate(const M2dAdaptOptions *ao, const M2dStep *st)
{
  return ao->goal == 1 && st->fig.pressure_estimate >= 0 ? st->fig.pressure_estimate : st->fig.est.estimate_rel;
}

/* what the summary's "adapt" list keeps of each step */
typedef struct {
  PetscInt  dofs, iterations, ripple_nodes, active_nodes, hertz_pairs;
  PetscReal estimate, goal, pressure_estimate, pressure_l2_rel, error_rel, effectivity, ripple, seconds, gmsh;
  PetscReal memory;          /* MB: the largest rank's peak resident memory so far */
  PetscReal rate, next_dofs; /* the plan made from this step (0: none) */
} StepRecord;

/* MB: the largest rank's peak resident memory so far (Linux: ru_maxrss in kB) */
static PetscErrorCode PeakMemory(MPI_Comm comm, PetscReal *mb)
{
  struct rusage ru;

  PetscFunctionBeginUser;
  getrusage(RUSAGE_SELF, &ru);
  *mb = (PetscReal)ru.ru_maxrss / 1024.0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, mb, 1, MPIU_REAL, MPIU_MAX, comm));
  PetscFunctionReturn(0);
}

static void Record(StepRecord *r, const M2dAdaptOptions *ao, const M2dStep *st, double seconds, double gmsh)
{
  memset(r, 0, sizeof(*r));
  r->dofs            = 2 * st->pb.mesh.nvert_global;
  r->iterations      = st->pb.has_contact ? st->sol.as.iterations : 0;
  r->estimate        = st->fig.est.estimate_rel;
  r->goal            = GoalEstimate(ao, st);
  r->pressure_estimate = st->fig.pressure_estimate;
  r->pressure_l2_rel = st->fig.pressure_l2_rel;
  r->hertz_pairs     = st->fig.hertz_pairs;
  r->error_rel       = st->fig.true_error_rel;
  r->effectivity     = st->fig.effectivity;
  r->ripple          = st->fig.pressure_ripple;
  r->ripple_nodes    = st->fig.ripple_nodes;
  r->active_nodes    = st->fig.active_nodes;
  r->seconds         = seconds;
  r->gmsh            = gmsh;
}

static void StepLine(MPI_Comm comm, PetscInt k, const StepRecord *r)
{
  char known[128] = "", contact[160] = "", hertz[64] = "";
  if (r->error_rel >= 0) PetscSNPrintf(known, sizeof(known), " (true %.3e)", (double)r->error_rel);
  if (r->pressure_l2_rel >= 0) PetscSNPrintf(hertz, sizeof(hertz), " (Hertz %.3e%s)", (double)r->pressure_l2_rel, r->hertz_pairs > 1 ? ", the worst pair" : "");
  if (r->pressure_estimate >= 0) PetscSNPrintf(contact, sizeof(contact), ", pressure %.3e%s, ripple %.2f%%", (double)r->pressure_estimate, hertz, (double)(100 * r->ripple));
  PetscPrintf(comm, "adapt step %" PetscInt_FMT ": %" PetscInt_FMT " dofs, estimated errors: energy %.3e%s%s, %" PetscInt_FMT " active-set steps, %.3f s\n", k, r->dofs, (double)r->estimate, known, contact, r->iterations, r->seconds);
}

static const char *StopKeyOf(StopReason why, Limit limit)
{
  const char *key[] = {"", "target", "near_target", "max_steps"};
  return why >= STOP_HELD ? LimitKey[limit] : key[why];
}

static PetscErrorCode WriteRecords(M2dSummary *sum, PetscInt n, const StepRecord *r, StopReason why, Limit limit, PetscInt best)
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < n; k++) {
    PetscCall(M2dSummaryListInt(sum, "adapt", k, "dofs", r[k].dofs));
    PetscCall(M2dSummaryListReal(sum, "adapt", k, "error_estimate", r[k].estimate));
    PetscCall(M2dSummaryListReal(sum, "adapt", k, "goal_estimate", r[k].goal));
    if (r[k].pressure_estimate >= 0) PetscCall(M2dSummaryListReal(sum, "adapt", k, "pressure_estimate", r[k].pressure_estimate));
    if (r[k].pressure_l2_rel >= 0) PetscCall(M2dSummaryListReal(sum, "adapt", k, "pressure_l2_rel", r[k].pressure_l2_rel));
    if (r[k].error_rel >= 0) PetscCall(M2dSummaryListReal(sum, "adapt", k, "error_rel", r[k].error_rel));
    if (r[k].effectivity >= 0) PetscCall(M2dSummaryListReal(sum, "adapt", k, "effectivity", r[k].effectivity));
    if (r[k].ripple >= 0) PetscCall(M2dSummaryListReal(sum, "adapt", k, "pressure_ripple", r[k].ripple));
    if (r[k].ripple >= 0) PetscCall(M2dSummaryListInt(sum, "adapt", k, "active_nodes", r[k].active_nodes));
    PetscCall(M2dSummaryListInt(sum, "adapt", k, "iterations", r[k].iterations));
    PetscCall(M2dSummaryListReal(sum, "adapt", k, "seconds", r[k].seconds));
    PetscCall(M2dSummaryListReal(sum, "adapt", k, "seconds_gmsh", r[k].gmsh));
    PetscCall(M2dSummaryListReal(sum, "adapt", k, "memory_max_rank_mb", r[k].memory));
    if (r[k].next_dofs > 0) PetscCall(M2dSummaryListReal(sum, "adapt", k, "rate", r[k].rate));
    if (r[k].next_dofs > 0) PetscCall(M2dSummaryListInt(sum, "adapt", k, "next_dofs", (PetscInt)r[k].next_dofs));
  }
  PetscCall(M2dSummaryString(sum, "", "adapt_stop", StopKeyOf(why, limit)));
  PetscCall(M2dSummaryInt(sum, "", "adapt_best_step", best));
  PetscFunctionReturn(0);
}

/* Rank 0: the cells the field asks for on prev, sum over quads of area / h^2 */
static double FieldCells(const PrevMesh *prev)
{
  const MshMesh *q = &prev->msh;
  double         n = 0;
  for (long c = 0; c < q->nquad; c++) {
    const long *v = &q->quad[4 * c];
    double      a = 0;
    for (int j = 0; j < 4; j++) a += 0.5 * (q->xy[2 * v[j]] * q->xy[2 * v[(j + 1) % 4] + 1] - q->xy[2 * v[(j + 1) % 4]] * q->xy[2 * v[j] + 1]);
    n += a / (prev->hcell[c] * prev->hcell[c]);
  }
  return n;
}

/* Rank 0: every size times f */
static void Scale(PrevMesh *prev, double f)
{
  for (long c = 0; c < prev->msh.nquad; c++) prev->hcell[c] *= f;
}

/* Rank 0: a floor for the refinement at a contact zone's edges: sizes at least
 * 2e-3 of the zone's length along the non-mortar surface (edges with both
 * nodes active; user units), so that no cell (the square root of its area:
 * gmsh's quads of size h measure 0.6-0.8 h so) is below 1e-3 of it */
static PetscErrorCode Floor(PrevMesh *prev, const M2dContact *ct, PetscReal L)
{
  PetscReal floor = 0; /* several pairs: the shortest zone's */

  PetscFunctionBeginUser;
  for (PetscInt p = 0; p < ct->npair; p++) {
    const M2dContactPair *c = &ct->pair[p];
    PetscBool            *act;
    PetscReal             len = 0;
    PetscCall(PetscMalloc1(c->nm.nnode + 1, &act));
    for (PetscInt i = 0; i < c->nm.nnode; i++) act[i] = PETSC_FALSE;
    for (PetscInt j = 0; j < c->R.n; j++) act[c->R.node[j]] = (PetscBool)(c->active[j] != 0);
    for (PetscInt e = 0; e < c->nm.nedge; e++)
      if (act[c->nm.edge[2 * e]] && act[c->nm.edge[2 * e + 1]]) len += c->nm.len[e] * L; /* len: reference units */
    PetscCall(PetscFree(act));
    if (len > 0) floor = floor > 0 ? PetscMin(floor, 2e-3 * len) : 2e-3 * len;
  }
  for (long q = 0; q < prev->msh.nquad; q++) prev->hcell[q] = PetscMax(prev->hcell[q], floor);
  PetscFunctionReturn(0);
}

/* The sizing rule. The estimate falls as dofs^-r. r: 0.6 of the slowest rate
 * seen between two adapted meshes, or before two adapted meshes the rate of
 * adapted Q4 meshes, 1/2 for the energy norm and 1 for the contact pressure;
 * clamped to [1/4, 2]. (The first mesh, the .geo's own or -mesh, is not an
 * adapted one: the step from it measures what adapting gains, not how the
 * error converges. The rates fall as the meshes refine, to 0.35-0.9 of the
 * pair's before on the shipped scenes: the slowest, and 0.6 of it, because a
 * mesh short of the target costs one more mesh, while one past it by a factor
 * f costs f^1.2 - 1 of its time; 0.75 ended Hertz on 20,708 dofs at 1.7e-3
 * against Hertz, 0.6 on 26,496 at 1.4e-3, 0.5 as the fixed growth did.) The
 * next mesh has the dofs that bring the estimate to M2D_ADAPT_AIM x the
 * target at that rate (a mesh that misses the target by 5-20% gets a small
 * step: 1.2-1.7 times its dofs at the pressure's rates, 1.5-2.2 at the energy
 * norm's, which are slower), at least M2D_ADAPT_MIN_GROWTH times the
 * last mesh's, rounded up to steps of 2^(1/8) (the round-off by which 1 and 2
 * ranks differ cannot move it), at most -adapt_growth times, and at most 0.9
 * x the tightest limit: -adapt_max_dofs, the dofs whose time fits what is
 * left of -adapt_max_seconds and those whose memory fits -adapt_max_memory,
 * both scaled from the last mesh's as dofs^1.2 (a sparse direct solver's fill
 * in 2D grows as N log N: 1.2 is above it for the steps the loop takes). */
#define M2D_ADAPT_AIM         0.9
#define M2D_ADAPT_RATE_SAFETY 0.6
#define M2D_ADAPT_COST_POWER  1.2

typedef struct {
  PetscReal dofs;  /* the next mesh's dofs, asked of the size field */
  PetscReal cap;   /* no mesh above this (the tightest limit) */
  PetscReal rate;  /* the rate the size was set with */
  Limit     limit; /* what holds dofs below the rule's (LIMIT_NONE: nothing) */
  Limit     capby; /* the limit cap comes from */
} Plan;

typedef struct {
  double    t_start; /* the loop's start (M2dWallTime) */
  PetscReal mem0;    /* MB: the largest rank's peak resident memory then */
} Budget;

static PetscReal ObservedRate(const M2dAdaptOptions *ao, const StepRecord *r, PetscInt n)
{
  PetscReal rate = PETSC_MAX_REAL;
  for (PetscInt k = 2; k < n; k++)
    if (r[k].dofs >= 1.1 * r[k - 1].dofs && r[k].goal > 0 && r[k - 1].goal > 0) rate = PetscMin(rate, PetscLogReal(r[k - 1].goal / r[k].goal) / PetscLogReal((PetscReal)r[k].dofs / (PetscReal)r[k - 1].dofs));
  rate = rate == PETSC_MAX_REAL ? (ao->goal == 1 ? 1.0 : 0.5) : M2D_ADAPT_RATE_SAFETY * rate;
  return PetscMin(PetscMax(rate, 0.25), 2.0);
}

/* the dofs whose cost fits `room` where the last mesh, of `dofs`, cost `used`
 * (seconds, or MB with the `held` dofs of the mesh kept beside it; the next
 * one will have the last beside it, the mesh kept but for a worse last) */
static PetscReal FitDofs(PetscReal dofs, PetscBool memory, PetscReal held, PetscReal room, PetscReal used)
{
  const PetscReal p = M2D_ADAPT_COST_POWER;
  PetscReal       c = PetscMax(used, PETSC_SMALL) / (PetscPowReal(dofs, p) + (memory ? PetscPowReal(held, p) : 0));
  PetscReal       free = room / c - (memory ? PetscPowReal(dofs, p) : 0);
  return room > 0 && free > 0 ? PetscPowReal(free, 1 / p) : 0;
}

/* The next mesh's size after the n steps r (the rule above). Collective. */
static PetscErrorCode NextDofs(MPI_Comm comm, const M2dAdaptOptions *ao, const StepRecord *r, PetscInt n, const Budget *b, Plan *p)
{
  const StepRecord *last = &r[n - 1];
  PetscReal         N    = (PetscReal)last->dofs, g;

  PetscFunctionBeginUser;
  p->rate  = ObservedRate(ao, r, n);
  g        = PetscMax(PetscPowReal(last->goal / (M2D_ADAPT_AIM * ao->target), 1 / p->rate), M2D_ADAPT_MIN_GROWTH);
  g        = PetscPowReal(2.0, PetscCeilReal(8 * PetscLog2Real(g) - 1e-6) / 8);
  p->limit = LIMIT_NONE;
  if (g >= ao->growth) {
    g        = ao->growth;
    p->limit = LIMIT_GROWTH;
  }
  p->cap   = (PetscReal)ao->max_dofs;
  p->capby = LIMIT_DOFS;
  if (ao->max_seconds > 0) {
    double    elapsed = M2dWallTime() - b->t_start;
    PetscReal fit;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &elapsed, 1, MPI_DOUBLE, MPI_MAX, comm));
    fit = FitDofs(N, PETSC_FALSE, 0, ao->max_seconds - (PetscReal)elapsed, last->seconds);
    if (fit < p->cap) p->cap = fit, p->capby = LIMIT_SECONDS;
  }
  if (ao->max_memory > 0) {
    PetscReal fit = FitDofs(N, PETSC_TRUE, n > 1 ? (PetscReal)r[n - 2].dofs : 0, ao->max_memory - b->mem0, last->memory - b->mem0);
    if (fit < p->cap) p->cap = fit, p->capby = LIMIT_MEMORY;
  }
  if (g * N > 0.9 * p->cap) {
    g        = 0.9 * p->cap / N;
    p->limit = p->capby;
  }
  p->dofs = g * N;
  PetscFunctionReturn(0);
}

/* the size field of st again for about `dofs` dofs (cells as on st's mesh):
 * into st's h_new / h (sol.eta), from the indicators and sums it was made from */
static PetscErrorCode SizeFor(const M2dEstimatorOptions *eo, M2dStep *st, PetscReal dofs)
{
  const M2dMesh     *m    = &st->pb.mesh;
  MPI_Comm           comm = PetscObjectComm((PetscObject)m->dm);
  PetscInt           nlc  = m->cEnd - m->cStart;
  PetscReal         *h, *hn, *ind;
  M2dSizeFieldParams p = eo->size;

  PetscFunctionBeginUser;
  p.max_cells = dofs * (PetscReal)m->ncell_global / (2.0 * (PetscReal)m->nvert_global);
  PetscCall(PetscMalloc3(nlc + 1, &h, nlc + 1, &hn, nlc + 1, &ind));
  for (PetscInt c = 0; c < nlc; c++) ind[c] = st->sol.eta[M2D_ETA_FIELDS * c + 3];
  PetscCall(M2dCellSizes(m, h));
  PetscCall(M2dSizeField(comm, nlc, h, ind, &st->fig.size_est, &p, hn, &st->fig.expected_cells));
  for (PetscInt c = 0; c < nlc; c++) st->sol.eta[M2D_ETA_FIELDS * c + 2] = hn[c] / h[c];
  PetscCall(PetscFree3(h, hn, ind));
  PetscFunctionReturn(0);
}

/* The mesh of step k > 0 from the size field of step st, made again for the
 * plan's dofs (SizeFor): gathered on rank 0,
 * floored, balanced across the contact, graded, the mortar side made the finer
 * again where the gradation undid it and graded once more; then every size grown by one
 * factor so that the cells gmsh will make (the field's count times *ratio,
 * gmsh's cells per asked cell at the last remeshing) are those the size field
 * chose (balance and gradation add some); rounded (Quantize), in the .geo's
 * units, remeshed. A mesh past the plan's cap is made again with every size
 * grown to fit, at most three times; *fits false if it still does not. */
static PetscErrorCode NextMesh(MPI_Comm comm, const M2dScene *s, const M2dAdaptOptions *ao, const M2dEstimatorOptions *eo, M2dStep *st, const Plan *plan, PetscInt k, double *ratio, MshMesh *msh, double *tgmsh, PetscInt *dofs, PetscBool *fits)
{
  PrevMesh prev;

  PetscFunctionBeginUser;
  PetscCall(SizeFor(eo, st, plan->dofs));
  PetscCall(PetscMemzero(&prev, sizeof(prev)));
  PetscCall(GatherPrevMesh(st, &prev));
  if (prev.hcell) { /* rank 0 */
    if (st->pb.has_contact) {
      PetscCall(Floor(&prev, &st->pb.contact, st->pb.units.L));
      for (PetscInt p = 0; p < st->pb.contact.npair; p++) PetscCall(Balance(&prev, &st->pb.contact.pair[p], st->pb.units.L, PETSC_TRUE)); /* every interface */
    }
    PetscCall(Grade(&prev, ao->grading));
    if (st->pb.has_contact) { /* the gradation lowers each side's sizes on its own: the mortar side made the finer again where it no longer is, and graded */
      for (PetscInt p = 0; p < st->pb.contact.npair; p++) PetscCall(Balance(&prev, &st->pb.contact.pair[p], st->pb.units.L, PETSC_FALSE));
      PetscCall(Grade(&prev, ao->grading));
    }
    {
      double f = PetscSqrtReal(*ratio * FieldCells(&prev) / PetscMax(st->fig.expected_cells, 1));
      if (f > 1) Scale(&prev, f);
    }
    Quantize(&prev);
    GeoUnits(&prev, s->mesh_scale);
  }
  *fits = PETSC_FALSE;
  for (int attempt = 0; attempt < 4; attempt++) {
    double t;
    PetscCall(Remesh(comm, s, ao, &prev, k, msh, &t, dofs));
    *tgmsh += t;
    if (prev.hcell && msh->nquad) *ratio = (double)msh->nquad / FieldCells(&prev);
    if (*dofs <= plan->cap) {
      *fits = PETSC_TRUE;
      break;
    }
    MshFree(msh);
    if (prev.hcell) { /* the area ratio and 4% more, at least one rounding step */
      Scale(&prev, PetscMax(PetscSqrtReal(1.04 * (PetscReal)*dofs / plan->cap), 1.0444));
      Quantize(&prev);
    }
  }
  PrevMeshFree(&prev);
  PetscFunctionReturn(0);
}

/* the step's line about the next mesh */
static void PlanLine(MPI_Comm comm, const M2dAdaptOptions *ao, const StepRecord *last, const Plan *p)
{
  const char *what = ao->goal == 1 ? "pressure" : "energy";
  if (p->limit == LIMIT_NONE) PetscPrintf(comm, "adapt: next mesh about %.0f dofs (%.2f times): the %s estimate %.3e falls to 0.9 x the target there at rate %.2f (estimate ~ dofs^-rate)\n", (double)p->dofs, (double)(p->dofs / last->dofs), what, (double)last->goal, (double)p->rate);
  else PetscPrintf(comm, "adapt: next mesh about %.0f dofs (%.2f times), held by %s (the %s estimate %.3e, rate %.2f)\n", (double)p->dofs, (double)(p->dofs / last->dofs), LimitOption[p->limit], what, (double)last->goal, (double)p->rate);
}

static void StopText(const M2dAdaptOptions *ao, StopReason why, Limit limit, PetscReal est, char *text, size_t len)
{
  if (why == STOP_TARGET) PetscSNPrintf(text, len, "the estimate reached -adapt_target");
  else if (why == STOP_NEAR) PetscSNPrintf(text, len, "the estimate is within %.1f%% of the target (-adapt_tolerance %g)", (double)(100 * (est / ao->target - 1)), (double)ao->tolerance);
  else if (why == STOP_STEPS) PetscSNPrintf(text, len, "-adapt_max_steps meshes");
  else if (why == STOP_HELD) PetscSNPrintf(text, len, "%s holds the mesh and the estimate no longer falls by 10%%", LimitOption[limit]);
  else PetscSNPrintf(text, len, "the next mesh does not fit under %s", LimitOption[limit]);
}

/* After step k (its record r[n - 1]): why the loop stops, or the plan of the
 * next mesh. A limit holds the loop when it holds the next mesh and this one
 * lowered the best estimate by less than 10% (nothing more is gained), or
 * when not even a mesh of this one's size fits in the time or memory left. */
static PetscErrorCode Decide(MPI_Comm comm, const M2dAdaptOptions *ao, StepRecord *r, PetscInt n, PetscInt k, const Budget *b, PetscBool have_best, PetscReal est_min, Plan *plan, StopReason *why)
{
  PetscReal est = r[n - 1].goal;

  PetscFunctionBeginUser;
  *why = STOP_NONE;
  if (est <= ao->target) *why = STOP_TARGET;
  else if (est <= (1 + ao->tolerance) * ao->target) *why = STOP_NEAR;
  else if (k + 1 >= ao->max_steps) *why = STOP_STEPS;
  if (*why != STOP_NONE) PetscFunctionReturn(0);
  PetscCall(NextDofs(comm, ao, r, n, b, plan));
  if (plan->cap < r[n - 1].dofs && plan->capby != LIMIT_DOFS) *why = STOP_FIT;
  else if (plan->limit >= LIMIT_DOFS && have_best && est > 0.9 * est_min) *why = STOP_HELD;
  if (*why != STOP_NONE) PetscFunctionReturn(0);
  r[n - 1].rate      = plan->rate;
  r[n - 1].next_dofs = plan->dofs;
  PlanLine(comm, ao, &r[n - 1], plan);
  PetscFunctionReturn(0);
}

/* The loop's end: why it stopped, the records into the kept mesh's summary,
 * its files written (-mesh_save: its mesh), and the last line, the whole
 * loop's time (the files included) and every mesh's dofs. Collective. */
static PetscErrorCode Finish(MPI_Comm comm, const M2dAdaptOptions *ao, const StepRecord *rec, PetscInt nrec, StopReason why, Limit limit, PetscInt kbest, double t_start, M2dStep *best)
{
  char   text[256], list[M2D_ADAPT_MAX_STEPS * 12] = "";
  double seconds;

  PetscFunctionBeginUser;
  StopText(ao, why, limit, rec[nrec - 1].goal, text, sizeof(text));
  PetscCall(PetscPrintf(comm, "adapt: stopped after %" PetscInt_FMT " mesh%s: %s; the results are those of step %" PetscInt_FMT " (%" PetscInt_FMT " dofs, estimated %s error %.3e)\n", nrec, nrec > 1 ? "es" : "", text, kbest, rec[kbest].dofs, ao->goal == 1 ? "pressure" : "energy", (double)rec[kbest].goal));
  PetscCall(WriteRecords(best->sum, nrec, rec, why, limit, kbest));
  PetscCall(M2dSummaryReal(best->sum, "", "adapt_seconds", M2dWallTime() - t_start));
  PetscCall(M2dStepWrite(best, best->pb.s.mesh_save));
  seconds = M2dWallTime() - t_start;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, comm));
  for (PetscInt k = 0; k < nrec; k++) PetscCall(PetscSNPrintf(list + strlen(list), sizeof(list) - strlen(list), "%s%" PetscInt_FMT, k ? ", " : "", rec[k].dofs));
  PetscCall(PetscPrintf(comm, "adapt: %.3f s in all, %" PetscInt_FMT " mesh%s of %s dofs; the results written are step %" PetscInt_FMT "'s\n", seconds, nrec, nrec > 1 ? "es" : "", list, kbest));
  PetscFunctionReturn(0);
}

/* Run the loop (adapt.h). The meshes' sizes come from the latest mesh and
 * its plan (NextDofs), the results written are those of the mesh with the
 * smallest estimate (or the last: -adapt_keep); the loop says why it stopped
 * (Decide) and, last, its time and the meshes' dofs. */
PetscErrorCode AdaptRun(MPI_Comm comm, M2dScene *s, const M2dAdaptOptions *ao, const M2dEstimatorOptions *eo_in)
{
  M2dContactState     state, *warm = NULL;
  M2dStep             st, best; /* the latest mesh's step, the best one's (may be the same) */
  StepRecord          rec[M2D_ADAPT_MAX_STEPS];
  PetscInt            nrec = 0, kbest = -1;
  char                what[PETSC_MAX_PATH_LEN + 64];
  double              ratio = 1.3; /* gmsh's cells per asked cell (rank 0): learnt from each remeshing */
  M2dEstimatorOptions eo = *eo_in;
  StopReason          why = STOP_NONE;
  Plan                plan;
  Budget              budget;
  PetscReal           est, est_min = 0;
  PetscBool           have_best = PETSC_FALSE, st_is_best = PETSC_FALSE;
  PetscErrorCode      ierr = 0;

  PetscFunctionBeginUser;
  PetscCheck(eo.enabled, comm, PETSC_ERR_USER_INPUT, "option -adapt: needs the error estimate (-error_estimate 1)");
  budget.t_start = M2dWallTime();
  PetscCall(PeakMemory(comm, &budget.mem0));
  /* each mesh's own size field (written as size_factor) at the largest step,
   * -adapt_growth times its dofs, at most 0.9 x the cap (gmsh's count
   * varies), the error equidistributed over them (estimator.h); the loop
   * makes it again for its plan's dofs (SizeFor) */
  eo.size.target_rel = 1e-12;
  eo.max_dofs        = 0.9 * (PetscReal)ao->max_dofs;
  eo.growth          = ao->growth;
  PetscCall(PetscMemzero(&plan, sizeof(plan)));
  PetscCall(PetscMemzero(&state, sizeof(state)));
  PetscCall(PetscMemzero(&st, sizeof(st)));
  for (PetscInt k = 0; !ierr && why == STOP_NONE; k++) {
    MshMesh   msh;
    double    t0 = M2dWallTime(), tgmsh = 0, seconds;
    PetscInt  dofs = 0;
    PetscBool fits = PETSC_TRUE;

    if (k == 0 && s->nmesh == 0) {
      PetscCall(Remesh(comm, s, ao, NULL, 0, &msh, &tgmsh, &dofs));
      if (dofs > ao->max_dofs) MshFree(&msh);
      PetscCheck(dofs <= ao->max_dofs, comm, PETSC_ERR_USER_INPUT, "option -adapt_max_dofs: the first mesh, the .geo's own ('%s'), has %" PetscInt_FMT " dofs, more than the cap %" PetscInt_FMT ": coarsen it (its parameters: -geo_setnumber) or raise the cap", s->geo, dofs, ao->max_dofs);
    } else if (k > 0) {
      ierr = NextMesh(comm, s, ao, &eo, &st, &plan, k, &ratio, &msh, &tgmsh, &dofs, &fits);
      if (ierr || !fits) { /* keep the results so far */
        if (!ierr) why = STOP_FIT;
        break;
      }
      if (st.pb.has_contact) { /* the next mesh starts from this one's contact state */
        PetscCall(ContactStateDestroy(&state));
        PetscCall(ContactStateCreate(&st.pb.contact, &state));
        warm = &state;
      }
      if (!st_is_best) PetscCall(M2dStepDestroy(&st));
      st_is_best = PETSC_FALSE; /* best keeps what st shared with it */
    }
    PetscCall(PetscSNPrintf(what, sizeof(what), "%s (adapt step %" PetscInt_FMT ")", s->geo, k));
    if (k == 0 && s->nmesh > 0) { /* the first mesh: the -mesh files */
      ierr = M2dStepSolve(comm, s, NULL, NULL, &eo, &st);
      dofs = ierr ? 0 : 2 * st.pb.mesh.nvert_global;
      if (!ierr && dofs > ao->max_dofs) ierr = PetscError(comm, __LINE__, PETSC_FUNCTION_NAME, __FILE__, PETSC_ERR_USER_INPUT, PETSC_ERROR_INITIAL, "option -adapt_max_dofs: the first mesh, -mesh %s, has %" PetscInt_FMT " dofs, more than the cap %" PetscInt_FMT, s->mesh[0], dofs, ao->max_dofs);
    } else {
      ierr = M2dStepSolve(comm, s, &(M2dMeshSource){&msh, what}, warm, &eo, &st);
      MshFree(&msh);
    }
    if (ierr) break;
    seconds = M2dWallTime() - t0;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &seconds, 1, MPI_DOUBLE, MPI_MAX, comm));
    Record(&rec[nrec], ao, &st, seconds, tgmsh);
    PetscCall(PeakMemory(comm, &rec[nrec].memory));
    StepLine(comm, k, &rec[nrec++]);
    est = GoalEstimate(ao, &st);
    PetscCall(Decide(comm, ao, rec, nrec, k, &budget, have_best, est_min, &plan, &why));
    /* the mesh kept: the last one whose estimate is within 10% of the smallest
     * so far (the estimate cannot rank meshes closer than that; the later mesh
     * was made from more information) */
    est_min = have_best ? PetscMin(est_min, est) : est;
    if (est <= 1.1 * est_min || ao->keep_last) {
      if (have_best) PetscCall(M2dStepDestroy(&best));
      best       = st;
      kbest      = k;
      have_best  = PETSC_TRUE;
      st_is_best = PETSC_TRUE;
    }
  }
  if (!ierr) ierr = Finish(comm, ao, rec, nrec, why, why == STOP_FIT ? plan.capby : plan.limit, kbest, budget.t_start, &best);
  if (!st_is_best) PetscCall(M2dStepDestroy(&st));
  if (have_best) PetscCall(M2dStepDestroy(&best));
  PetscCall(ContactStateDestroy(&state));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}
