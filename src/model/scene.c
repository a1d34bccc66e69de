/* scene.c - read a scene from the options database (see scene.h).
 *
 * The options are read by job (mesh and bodies, boundary conditions, contact,
 * comparisons, linear algebra, output) inside one PetscOptionsBegin/End, so
 * that -help lists them together; their form is checked while reading
 * (options.h), their domains and the ways they combine after (CheckScene),
 * where an error leaks nothing.
 *
 * Boundary conditions name gmsh physical groups; several of each are given
 * comma separated:
 *   -dirichlet GROUP:x|y|xy|n|t[:VALUE]  prescribed displacement (default value 0):
 *                                        components x, y, or along the normal n / tangent t
 *   -pressure  GROUP:P[:GX:GY]           normal pressure P + GX x + GY y (positive pushes in)
 *   -traction  GROUP:TX:TY               traction vector */
#include "scene.h"
#include "about.h"
#include "optcheck.h"
#include "options.h"
#include "optfiles.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

/* split "a:b:c" in place into at most max fields; max + 1 when there are more */
static int Split(char *s, char **f, int max)
{
  int n = 0;
  f[n++] = s;
  for (char *c = s; *c; c++)
    if (*c == ':') {
      *c = 0;
      if (n == max) return max + 1;
      f[n++] = c + 1;
    }
  return n;
}

/* a finite number, else the option's error is kept (options.h) */
static PetscErrorCode ParseReal(const char *opt, const char *entry, const char *text, PetscReal *v)
{
  char  *end;
  double d = strtod(text, &end);

  PetscFunctionBeginUser;
  if (end == text || *end || PetscIsInfOrNanReal((PetscReal)d) || M2dUnderflows(text)) {
    char shown[2][128];
    PetscCall(M2dOptionsDefer("option %s: '%s' in '%s' is not a finite number%s", opt, M2dShown(text, shown[0], sizeof(shown[0])), M2dShown(entry, shown[1], sizeof(shown[1])), M2dUnderflows(text) ? " (nonzero but below double precision's range)" : ""));
  } else *v = (PetscReal)d;
  PetscFunctionReturn(0);
}

/* the form of one comma-separated entry of -dirichlet, -pressure or -traction:
 * GROUP, `words` words, then numbers; `counts` has bit n set when n fields are allowed */
typedef struct {
  const char *opt, *form, *help;
  int         words;
  unsigned    counts;
} EntryForm;

enum { ENTRY_DIRICHLET, ENTRY_PRESSURE, ENTRY_TRACTION, ENTRY_KINDS };

static const EntryForm entry_forms[ENTRY_KINDS] = {
  {"-dirichlet", "GROUP:x|y|xy|n|t[:VALUE]", "prescribed displacement GROUP:x|y|xy|n|t[:VALUE], up to " M2D_STR(M2D_MAX_BC) " comma separated; default: none", 1, 1u << 2 | 1u << 3},
  {"-pressure",  "GROUP:P or GROUP:P:GX:GY", "pressure GROUP:P[:GX:GY], p = P + GX x + GY y, > 0 pushes in (loads: up to " M2D_STR(M2D_MAX_BC) "); default: none", 0, 1u << 2 | 1u << 4},
  {"-traction",  "GROUP:TX:TY",              "traction vector GROUP:TX:TY on a physical curve, comma separated (loads: up to " M2D_STR(M2D_MAX_BC) "); default: none", 0, 1u << 3},
};

/* entry split by its form: GROUP into group, the word (if the form has one)
 * into word, the numbers into v[0..*nv); *nv = -1, and the error kept
 * (options.h), when the number of fields is wrong */
static PetscErrorCode ParseEntry(const EntryForm *ef, const char *opt, const char *entry, char group[M2D_NAME_LEN], char word[M2D_NAME_LEN], PetscReal v[], int *nv)
{
  char *f[5], *buf;
  int   nf;

  PetscFunctionBeginUser;
  PetscCall(PetscStrallocpy(entry, &buf));
  nf  = Split(buf, f, 4);
  *nv = -1;
  if (!(ef->counts >> nf & 1u)) {
    char shown[128];
    PetscCall(M2dOptionsDefer("option %s: '%s' is not %s", opt, M2dShown(entry, shown, sizeof(shown)), ef->form));
  } else if (strlen(f[0]) >= M2D_NAME_LEN) PetscCall(M2dOptionsDefer("option %s: the group name in '%.40s...' is longer than %d characters", opt, entry, M2D_NAME_LEN - 1));
  else {
    PetscCall(PetscStrncpy(group, f[0], M2D_NAME_LEN));
    if (ef->words) PetscCall(PetscStrncpy(word, f[1], M2D_NAME_LEN));
    *nv = nf - 1 - ef->words;
    for (int k = 0; k < *nv; k++) {
      v[k] = 0;
      PetscCall(ParseReal(opt, entry, f[1 + ef->words + k], &v[k]));
    }
  }
  PetscCall(PetscFree(buf));
  PetscFunctionReturn(0);
}

static PetscErrorCode ParseDirichlet(const char *opt, const char *entry, M2dDirichlet *bc)
{
  char      comp[M2D_NAME_LEN];
  PetscReal v[1];
  int       nv;

  PetscFunctionBeginUser;
  PetscCall(ParseEntry(&entry_forms[ENTRY_DIRICHLET], opt, entry, bc->group, comp, v, &nv));
  if (nv < 0) PetscFunctionReturn(0);
  bc->frame = M2D_BC_XY;
  if (!strcmp(comp, "x")) bc->comp[0] = PETSC_TRUE;
  else if (!strcmp(comp, "y")) bc->comp[1] = PETSC_TRUE;
  else if (!strcmp(comp, "xy")) bc->comp[0] = bc->comp[1] = PETSC_TRUE;
  else if (!strcmp(comp, "n")) bc->frame = M2D_BC_NORMAL;
  else if (!strcmp(comp, "t")) bc->frame = M2D_BC_TANGENT;
  else PetscCall(M2dOptionsDefer("option %s: unknown component '%s' in '%s' (x, y, xy, n or t)", opt, comp, entry));
  if (nv == 1) bc->value[0] = bc->value[1] = v[0];
  PetscFunctionReturn(0);
}

/* a -pressure (P[:GX:GY]) or -traction (TX:TY) entry */
static PetscErrorCode ParseEdgeLoad(int kind, const char *opt, const char *entry, M2dEdgeLoad *l)
{
  PetscReal v[3];
  int       nv;

  PetscFunctionBeginUser;
  PetscCall(ParseEntry(&entry_forms[kind], opt, entry, l->group, NULL, v, &nv));
  if (nv < 0) PetscFunctionReturn(0);
  if (kind == ENTRY_TRACTION) {
    l->t[0] = v[0];
    l->t[1] = v[1];
    PetscFunctionReturn(0);
  }
  l->is_pressure = PETSC_TRUE;
  l->p           = v[0];
  if (nv == 3) {
    l->grad[0] = v[1];
    l->grad[1] = v[2];
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadMeshAndBodies(PetscOptionItems *PetscOptionsObject, M2dScene *s)
{
  const char *const parts[] = {"metis", "petsc"}; /* order of M2dPartitioner */
  char             *mesh[M2D_MAX_MESH], *bodies[M2D_MAX_BODIES];
  PetscInt          nbodies;

  PetscFunctionBeginUser;
  PetscCall(M2dOptionsStringArray(PetscOptionsObject, "-mesh", "gmsh .msh file(s), comma-separated (up to " M2D_STR(M2D_MAX_MESH) "); default: none, required", M2D_MAX_MESH, sizeof(s->mesh[0]), mesh, &s->nmesh));
  for (PetscInt i = 0; i < s->nmesh; i++) {
    PetscCall(PetscStrncpy(s->mesh[i], mesh[i], sizeof(s->mesh[i])));
    PetscCall(PetscFree(mesh[i]));
  }
  PetscCall(M2dOptionsString(PetscOptionsObject, "-mesh_dir", "directory of the -mesh files not found from the current directory", s->mesh_dir, sizeof(s->mesh_dir), NULL));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-mesh_scale", "multiply the mesh coordinates by this factor (a change of length unit), > 0", s->mesh_scale, &s->mesh_scale, NULL));
  PetscCall(M2dOptionsEnum(PetscOptionsObject, "-mesh_partitioner", "cells over the ranks: metis (libmetis on rank 0) or petsc (-petscpartitioner_type)", parts, 2, (PetscEnum *)&s->mesh_partitioner));
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-mesh_check", "run PETSc's plex checks on the mesh as built", s->mesh_check, &s->mesh_check));
  PetscCall(M2dOptionsString(PetscOptionsObject, "-geo", "gmsh .geo source of the scene's geometry for adaptive remeshing; default: none", s->geo, sizeof(s->geo), NULL));
  PetscCall(M2dOptionsString(PetscOptionsObject, "-geo_dir", "directory of the -geo file when not found from the current directory", s->geo_dir, sizeof(s->geo_dir), NULL));
  PetscCall(M2dOptionsStringArray(PetscOptionsObject, "-bodies", "physical surface names of the bodies (up to " M2D_STR(M2D_MAX_BODIES) "), comma separated; default: every physical surface", M2D_MAX_BODIES, M2D_NAME_LEN, bodies, &nbodies));
  s->nbody = nbodies;
  for (PetscInt i = 0; i < nbodies; i++) {
    char name[M2D_NAME_LEN + 8];
    PetscCall(PetscStrncpy(s->body[i].name, bodies[i], sizeof(s->body[i].name)));
    PetscCall(PetscFree(bodies[i]));
    for (PetscInt j = 0; j < i; j++)
      if (!strcmp(s->body[i].name, s->body[j].name)) PetscCall(M2dOptionsDefer("option -bodies: '%s' is listed twice", s->body[i].name));
    /* the materials are read later (SceneReadMaterials): known names already */
    PetscCall(PetscSNPrintf(name, sizeof(name), "-%s_E", s->body[i].name));
    PetscCall(M2dOptionsKnow(name));
    PetscCall(PetscSNPrintf(name, sizeof(name), "-%s_nu", s->body[i].name));
    PetscCall(M2dOptionsKnow(name));
  }
  PetscFunctionReturn(0);
}

/* the plane model and the element, for every body */
static PetscErrorCode ReadModel(PetscOptionItems *PetscOptionsObject, M2dScene *s)
{
  const char *const planes[] = {"strain", "stress"}; /* order of M2dPlane */
  const char *const integ[]  = {"full", "sri"};
  PetscInt          k;

  PetscFunctionBeginUser;
  PetscCall(M2dOptionsEnum(PetscOptionsObject, "-plane", "plane strain or plane stress", planes, 2, (PetscEnum *)&s->plane));
  k = s->sri ? 1 : 0;
  PetscCall(M2dOptionsEList(PetscOptionsObject, "-q4_integration", "Q4 stiffness: full (2x2 Gauss) or sri (selective reduced); default sri past plane-strain nu " M2D_STR(M2D_LOCKING_NU), integ, 2, &k));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-q4_integration", &s->integration_set));
  s->sri = (PetscBool)(k == 1);
  PetscFunctionReturn(0);
}

/* the loads and supports of stage `stage` (0: the scene's -dirichlet,
 * -pressure, -traction; k: -stage<k+1>_..., the block's prefix `pre`) */
static PetscErrorCode ReadBoundaryConditions(PetscOptionItems *PetscOptionsObject, const char *pre, PetscInt stage, M2dScene *s)
{
  char    *list[ENTRY_KINDS][M2D_MAX_BC], opt[ENTRY_KINDS][64];
  PetscInt n[ENTRY_KINDS];

  PetscFunctionBeginUser;
  const char *stage_help[ENTRY_KINDS] = {"a support's value changed by VALUE, GROUP:x|y|xy|n|t:VALUE (held by -dirichlet); default: none", "pressure added, GROUP:P[:GX:GY]; default: none", "traction added, GROUP:TX:TY; default: none"};

  for (int k = 0; k < ENTRY_KINDS; k++) {
    PetscCall(PetscSNPrintf(opt[k], sizeof(opt[k]), "-%s%s", pre ? pre : "", entry_forms[k].opt + 1));
    PetscCall(M2dOptionsStringArray(PetscOptionsObject, entry_forms[k].opt, stage ? stage_help[k] : entry_forms[k].help, M2D_MAX_BC, 0, list[k], &n[k]));
  }
  if (s->ndir + n[ENTRY_DIRICHLET] > M2D_MAX_BC) PetscCall(M2dOptionsDefer("option %s: at most %d supports and changes of supports in all stages", opt[ENTRY_DIRICHLET], M2D_MAX_BC));
  for (PetscInt i = 0; i < n[ENTRY_DIRICHLET] && s->ndir < M2D_MAX_BC; i++) {
    s->dir[s->ndir].stage = stage;
    PetscCall(ParseDirichlet(opt[ENTRY_DIRICHLET], list[ENTRY_DIRICHLET][i], &s->dir[s->ndir++]));
  }
  if (s->nload + n[ENTRY_PRESSURE] + n[ENTRY_TRACTION] > M2D_MAX_BC) PetscCall(M2dOptionsDefer("options %s and %s: at most %d loads in all stages", opt[ENTRY_PRESSURE], opt[ENTRY_TRACTION], M2D_MAX_BC));
  for (int k = ENTRY_PRESSURE; k <= ENTRY_TRACTION; k++)
    for (PetscInt i = 0; i < n[k] && s->nload < M2D_MAX_BC; i++) {
      s->load[s->nload].stage = stage;
      PetscCall(ParseEdgeLoad(k, opt[k], list[k][i], &s->load[s->nload++]));
    }
  for (int k = 0; k < ENTRY_KINDS; k++)
    for (PetscInt i = 0; i < n[k]; i++) PetscCall(PetscFree(list[k][i]));
  PetscFunctionReturn(0);
}

/* the load history: -load_steps, -load_stages, and each later stage's loads,
 * support values and steps under the prefix stage<k>_ (PETSc's manner) */
static PetscErrorCode ReadLoadHistory(MPI_Comm comm, M2dScene *s)
{
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, NULL, "mortar2d: load history", "");
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-load_steps", "quasi-static steps to the scene's loads and support values (friction depends on the path), >= 1", s->stage_steps[0], &s->stage_steps[0], NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-load_stages", "load stages: the scene's loads, then each -stageK_ stage's added to what is held, 1 to 16", s->nstage, &s->nstage, NULL));
  PetscOptionsEnd();
  PetscCall(M2dOptionsRaise(comm));
  PetscCheck(s->nstage >= 1 && s->nstage <= M2D_MAX_STAGES, comm, PETSC_ERR_USER_INPUT, "option -load_stages: %" PetscInt_FMT " must be in [1, %d]", s->nstage, M2D_MAX_STAGES);
  /* -help documents stage 2's options even when there is one stage */
  for (PetscInt k = 1; k < PetscMax(s->nstage, s->help ? 2 : 1); k++) {
    char pre[32], title[96];
    PetscCall(PetscSNPrintf(pre, sizeof(pre), "stage%d_", (int)k + 1));
    PetscCall(PetscSNPrintf(title, sizeof(title), "mortar2d: load stage %d", (int)k + 1));
    s->stage_steps[k] = 1;
    PetscOptionsBegin(comm, pre, title, "");
    PetscCall(ReadBoundaryConditions(PetscOptionsObject, pre, k, s));
    PetscCall(M2dOptionsInt(PetscOptionsObject, "-steps", "quasi-static steps of this stage, >= 1", s->stage_steps[k], &s->stage_steps[k], NULL));
    PetscOptionsEnd();
    PetscCall(M2dOptionsRaise(comm));
  }
  for (PetscInt k = s->nstage; k < M2D_MAX_STAGES; k++) { /* the program's names: beyond -load_stages they have no effect (CheckEffect) */
    const char *what[] = {"pressure", "traction", "dirichlet", "steps"};
    for (int w = 0; w < 4; w++) {
      char name[64];
      PetscCall(PetscSNPrintf(name, sizeof(name), "-stage%d_%s", (int)k + 1, what[w]));
      PetscCall(M2dOptionsKnow(name));
    }
  }
  for (PetscInt k = 0; k < s->nstage; k++) {
    char name[32] = "-load_steps";
    if (k) PetscCall(PetscSNPrintf(name, sizeof(name), "-stage%d_steps", (int)k + 1));
    PetscCheck(s->stage_steps[k] >= 1, comm, PETSC_ERR_USER_INPUT, "option %s: %" PetscInt_FMT " must be >= 1", name, s->stage_steps[k]);
  }
  if (s->help) { /* stage 2 may have been read only to be documented */
    while (s->nload > 0 && s->load[s->nload - 1].stage >= s->nstage) s->nload--;
    while (s->ndir > 0 && s->dir[s->ndir - 1].stage >= s->nstage) s->ndir--;
  }
  PetscFunctionReturn(0);
}

/* the friction coefficient in text: a finite number >= 0 (form errors deferred: options.h) */
static PetscErrorCode ParseMu(const char *opt, const char *entry, const char *text, PetscReal *mu)
{
  PetscFunctionBeginUser;
  PetscCall(ParseReal(opt, entry, text, mu));
  if (!(*mu >= 0)) PetscCall(M2dOptionsDefer("option %s: friction coefficient %s in '%s' must be >= 0", opt, text, entry));
  PetscFunctionReturn(0);
}

/* one -contact_pairs entry NM:M[:standard|dual|nts][:MU] into s->pair[k]
 * (form errors deferred: options.h) */
static PetscErrorCode ParsePair(const char *entry, PetscInt k, M2dScene *s)
{
  const char *const kinds[] = {"standard", "dual", "nts"};
  const char *const form    = "NM:M, NM:M:standard|dual|nts, NM:M:MU or NM:M:standard|dual|nts:MU (non-mortar curve:mortar curve[:method][:friction coefficient])";
  M2dPair          *p       = &s->pair[k];
  char             *buf, *f[5];
  int               nf;

  PetscFunctionBeginUser;
  s->npair = k + 1;
  PetscCall(PetscStrallocpy(entry, &buf));
  nf = Split(buf, f, 4);
  if (nf < 2 || nf > 4 || !f[0][0] || !f[1][0] || strlen(f[0]) >= sizeof(p->nm) || strlen(f[1]) >= sizeof(p->m)) {
    PetscCall(M2dOptionsDefer("option -contact_pairs: '%s' is not %s", entry, form));
    PetscCall(PetscFree(buf));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscStrncpy(p->nm, f[0], sizeof(p->nm)));
  PetscCall(PetscStrncpy(p->m, f[1], sizeof(p->m)));
  for (int q = 2; q < nf; q++) {
    int i = 0;
    while (i < 3 && strcasecmp(f[q], kinds[i])) i++;
    if (i < 3 && q == 2) {
      p->own_method = PETSC_TRUE;
      p->method     = i == 2 ? M2D_CONTACT_NTS : M2D_CONTACT_MORTAR;
      p->basis      = i == 1 ? 1 : 0; /* MortarBasis: standard, dual */
    } else if (q == nf - 1 && (q == 3 || i == 3)) {
      p->own_mu = PETSC_TRUE;
      PetscCall(ParseMu("-contact_pairs", entry, f[q], &p->mu));
    } else PetscCall(M2dOptionsDefer("option -contact_pairs: '%s' in '%s' is not standard, dual or nts (the form: %s)", f[q], entry, form));
  }
  PetscCall(PetscSNPrintf(p->what, sizeof(p->what), "option -contact_pairs, pair %d '%s:%s'", (int)k + 1, p->nm, p->m));
  p->opt_nm = p->opt_m = "-contact_pairs";
  PetscCall(PetscFree(buf));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadContact(PetscOptionItems *PetscOptionsObject, M2dScene *s)
{
  const char *const methods[] = {"mortar", "nts"}; /* order of M2dContactMethod */
  const char *const basis[]   = {"standard", "dual"}; /* order of MortarBasis */
  const char *const init[]    = {"gap", "closest", "all"};

  PetscFunctionBeginUser;
  char    *list[M2D_MAX_PAIRS];
  PetscInt n = 0;

  PetscCall(M2dOptionsStringArray(PetscOptionsObject, "-contact_pairs", "NM:M[:standard|dual|nts][:MU],... (non-mortar:mortar:method:friction), at most " M2D_STR(M2D_MAX_PAIRS) "; default: none", M2D_MAX_PAIRS, 0, list, &n));
  for (PetscInt i = 0; i < n; i++) {
    PetscCall(ParsePair(list[i], i, s));
    PetscCall(PetscFree(list[i]));
  }
  PetscCall(M2dOptionsString(PetscOptionsObject, "-contact_nonmortar", "non-mortar curve of one pair (several: -contact_pairs); default: none (no contact)", s->contact_nm, sizeof(s->contact_nm), NULL));
  PetscCall(M2dOptionsString(PetscOptionsObject, "-contact_mortar", "mortar curve of one pair (several: -contact_pairs); default: none (no contact)", s->contact_m, sizeof(s->contact_m), NULL));
  PetscCall(M2dOptionsEnum(PetscOptionsObject, "-contact_method", "contact discretisation: mortar or nts (node-to-segment)", methods, 2, (PetscEnum *)&s->method));
  PetscCall(M2dOptionsEnum(PetscOptionsObject, "-mortar_basis", "multipliers: standard (the seed report) or dual (biorthogonal: diagonal D)", basis, 2, (PetscEnum *)&s->basis));
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-contact_unilateral", "unilateral contact (active set); false: every candidate node held closed (tied)", s->unilateral, &s->unilateral));
  PetscCall(M2dOptionsRealAuto(PetscOptionsObject, "-contact_c", "complementarity parameter c of the active-set test, > 0; auto: E*/h^2", &s->contact_c, &s->contact_c_set));
  PetscCall(M2dOptionsEList(PetscOptionsObject, "-contact_initial", "first active set: gap (closed gaps), closest (smallest gaps) or all (every candidate)", init, 3, &s->contact_initial));
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-contact_monitor", "print one line per active-set step", s->contact_monitor, &s->contact_monitor));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-contact_friction", "Coulomb friction coefficient MU of the pairs without their own, >= 0; 0: frictionless", s->friction, &s->friction, NULL));
  PetscCall(M2dOptionsRealAuto(PetscOptionsObject, "-contact_reach", "search distance of the contact pair, > 0; auto: 0.1 x the mortar surface's extent", &s->reach, &s->reach_set));
  PetscFunctionReturn(0);
}

/* -hertz_pairs N,... and -hertz_radius: entries R or R1:R2 (two cylinders) */
static PetscErrorCode ReadHertzPairs(PetscOptionItems *PetscOptionsObject, M2dScene *s)
{
  char    *list[M2D_MAX_PAIRS];
  PetscInt n = 0;

  PetscFunctionBeginUser;
  PetscCall(M2dOptionsStringArray(PetscOptionsObject, "-hertz_pairs", "the pairs -hertz compares, by number (1, 2, ...); default: the curved ones", M2D_MAX_PAIRS, 0, list, &n));
  s->hertz_npairs = n;
  for (PetscInt i = 0; i < n; i++) {
    char *end;
    long  v = strtol(list[i], &end, 10);
    if (end == list[i] || *end || v < 1 || v > M2D_MAX_PAIRS) PetscCall(M2dOptionsDefer("option -hertz_pairs: '%s' is not a pair number (1, 2, ...)", list[i]));
    else s->hertz_pairs[i] = (PetscInt)v;
    PetscCall(PetscFree(list[i]));
  }
  n = 0;
  PetscCall(M2dOptionsStringArray(PetscOptionsObject, "-hertz_radius", "Hertz radius R or R1:R2 (two cylinders), for all pairs or one per -hertz_pairs; default: 1", M2D_MAX_PAIRS, 0, list, &n));
  if (n) s->hertz_nradius = n;
  for (PetscInt i = 0; i < n; i++) {
    char *colon = strchr(list[i], ':'), entry[64];
    PetscCall(PetscStrncpy(entry, list[i], sizeof(entry)));
    if (colon) *colon = 0;
    s->hertz_radii[i][1] = 0;
    PetscCall(ParseReal("-hertz_radius", entry, list[i], &s->hertz_radii[i][0]));
    if (colon) PetscCall(ParseReal("-hertz_radius", entry, colon + 1, &s->hertz_radii[i][1]));
    if (colon && strchr(colon + 1, ':')) PetscCall(M2dOptionsDefer("option -hertz_radius: '%s' is not R or R1:R2", entry));
    else if (!(s->hertz_radii[i][0] > 0) || (colon && !(s->hertz_radii[i][1] > 0))) PetscCall(M2dOptionsDefer("option -hertz_radius: '%s': a radius must be > 0", entry));
    PetscCall(PetscFree(list[i]));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadComparisons(PetscOptionItems *PetscOptionsObject, M2dScene *s)
{
  const char *const exact[] = {"none", "uniform", "mms"}; /* order of M2dExact */

  PetscFunctionBeginUser;
  PetscCall(M2dOptionsEnum(PetscOptionsObject, "-exact", "compare with an exact solution: uniform (sigma_yy = -p, the rest 0) or mms", exact, 3, (PetscEnum *)&s->exact));
  PetscCall(M2dOptionsRealAuto(PetscOptionsObject, "-exact_p", "-exact uniform: the exact -sigma_yy, > 0; auto: the first -pressure", &s->exact_p, &s->exact_p_set));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-exact_tau", "-exact uniform: the exact sigma_xy (a sheared patch; frame of -exact_angle)", s->exact_tau, &s->exact_tau, NULL));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-exact_angle", "-exact uniform: its frame turned by this angle, in degrees", s->exact_angle, &s->exact_angle, NULL));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-mms_amplitude", "amplitude of the manufactured displacement (-exact mms), not 0", s->mms_amplitude, &s->mms_amplitude, NULL));
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-hertz", "compare the contact pressure with Hertz (cylinder on a half-space, plane strain)", s->hertz, &s->hertz));
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-cattaneo", "with -hertz and friction: compare the shear traction with Cattaneo-Mindlin", s->cattaneo, &s->cattaneo));
  PetscCall(ReadHertzPairs(PetscOptionsObject, s));
  PetscCall(M2dOptionsRealAuto(PetscOptionsObject, "-hertz_load", "Hertz load per unit thickness (> 0); auto: -pressure resultant (x2, half model) or contact force", &s->hertz_load, &s->hertz_load_set));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-strain_limit", "the largest strain an answer may reach (a rotation t counts as t^2/2), > 0; warned above 0.01", s->strain_limit, &s->strain_limit, NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadLinearAlgebra(PetscOptionItems *PetscOptionsObject, M2dScene *s)
{
  const char *const mats[]  = {"aij", "nest"}; /* order of M2dKKTMat */
  const char *const paths[] = {"full", "condensed", "iterative"}; /* order of M2dKKTPath */
  const char *const ords[]  = {"mumps", "metis", "auto"}; /* order of M2dOrdering */

  PetscFunctionBeginUser;
  PetscCall(M2dOptionsEnum(PetscOptionsObject, "-kkt_mat", "KKT matrix: aij (monolithic, for MUMPS) or nest (MatNest, for PCFIELDSPLIT)", mats, 2, (PetscEnum *)&s->kkt_mat));
  PetscCall(M2dOptionsEnum(PetscOptionsObject, "-kkt_path", "solves: condensed (factor once), full (KKT each step) or iterative (CG + AMG in u)", paths, 3, (PetscEnum *)&s->kkt_path));
  PetscCall(M2dOptionsEnum(PetscOptionsObject, "-kkt_ordering", "ordering for MUMPS: metis (nested dissection), mumps (its own), auto (mumps: 1 rank, < 2e5 dofs)", ords, 3, (PetscEnum *)&s->kkt_ordering));
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-kkt_ldlt", "condensed path: LDL^T of the symmetric KKT matrix (MUMPS SYM = 2); false: LU", s->kkt_ldlt, &s->kkt_ldlt));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-mat_mumps_icntl_4", "condensed path's MUMPS ICNTL(4): output level, 0 to 4", s->icntl4, &s->icntl4, NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-mat_mumps_icntl_7", "condensed path's MUMPS ICNTL(7) when MUMPS orders (-kkt_ordering): ordering, 0 or 2 to 7", s->icntl7, &s->icntl7, NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-mat_mumps_icntl_8", "condensed path's MUMPS ICNTL(8): scaling, -2, 0, 1, 3, 4, 7, 8 or 77", s->icntl8, &s->icntl8, NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-mat_mumps_icntl_14", "condensed path's MUMPS ICNTL(14): working-space increase in percent, >= 0", s->icntl14, &s->icntl14, NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-mat_mumps_icntl_58", "condensed path's MUMPS ICNTL(58): symbolic factorization, 1 or 2", s->icntl58, &s->icntl58, NULL));
  PetscCall(M2dOptionsInt(PetscOptionsObject, "-kkt_condensed_max", "without -kkt_path: the condensed path up to this many non-mortar edges, the full path past it", s->kkt_condensed_max, &s->kkt_condensed_max, NULL));
  PetscCall(M2dOptionsReal(PetscOptionsObject, "-kkt_augment", "weight w of K + w s C^T C, >= 0 (0: off; the condensed path takes 1)", s->kkt_augment, &s->kkt_augment, NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadOutput(PetscOptionItems *PetscOptionsObject, M2dScene *s)
{
  const char *const kinds[] = {"h5", "vtu", "csv", "summary", "none"};
  PetscBool        *flag[]  = {&s->out.h5, &s->out.vtu, &s->out.csv, &s->out.summary, NULL};
  char             *list[5];
  PetscInt          n = 0;
  PetscBool         listed, vtu, h5;

  PetscFunctionBeginUser;
  PetscCall(M2dOptionsString(PetscOptionsObject, "-output_dir", "directory of the output files (created if missing)", s->out.dir, sizeof(s->out.dir), NULL));
  PetscCall(M2dOptionsString(PetscOptionsObject, "-output_name", "base name N of the output files N.h5, N.xmf, N.vtu, N_contact.csv, N_summary.json", s->out.name, sizeof(s->out.name), NULL));
  PetscCall(M2dOptionsStringArray(PetscOptionsObject, "-output", "files to write: h5 (and .xmf), vtu, csv, summary, or none; default: h5,vtu,csv,summary", 5, 0, list, &n));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-output", &listed));
  if (listed && n == 0) PetscCall(M2dOptionsDefer("option -output: needs h5, vtu, csv, summary or none"));
  for (PetscInt k = 0; k < 4 && n > 0; k++) *flag[k] = PETSC_FALSE;
  for (PetscInt i = 0; i < n; i++) {
    PetscInt k = 0;
    while (k < 5 && strcasecmp(list[i], kinds[k])) k++;
    if (k == 5 || (k == 4 && n > 1)) PetscCall(M2dOptionsDefer("option -output: '%s' is not one of h5, vtu, csv, summary (or none alone)", list[i]));
    else if (flag[k]) *flag[k] = PETSC_TRUE;
    PetscCall(PetscFree(list[i]));
  }
  vtu = s->out.vtu, h5 = s->out.h5;
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-output_vtu", "write N.vtu (as vtu in -output)", s->out.vtu, &s->out.vtu));
  PetscCall(M2dOptionsBool(PetscOptionsObject, "-output_hdf5", "write N.h5 and N.xmf (as h5 in -output)", s->out.h5, &s->out.h5));
  /* the older switches may repeat -output's list, not contradict it (-output h5 -output_hdf5 0 wrote nothing, exit 0) */
  if (listed && n > 0 && (s->out.vtu != vtu || s->out.h5 != h5)) {
    char given[64] = "";
    PetscCall(PetscOptionsGetString(NULL, NULL, "-output", given, sizeof(given), NULL));
    PetscCall(M2dOptionsDefer("options -output %s and %s %d contradict each other (give one of them)", given, s->out.vtu != vtu ? "-output_vtu" : "-output_hdf5", (int)(s->out.vtu != vtu ? s->out.vtu : s->out.h5)));
  }
  PetscCall(M2dOptionsString(PetscOptionsObject, "-summary", "path of the JSON summary; default: OUTPUT_DIR/N_summary.json", s->out.summary_path, sizeof(s->out.summary_path), NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode Defaults(M2dScene *s)
{
  PetscFunctionBeginUser;
  /* by job, as the options are read; every other field 0 */
  *s = (M2dScene){
    .mesh_scale = 1.0, .mesh_partitioner = M2D_PARTITIONER_METIS, .plane = M2D_PLANE_STRAIN,
    .mms_amplitude = 1e-3, .mms_wavenumber = PETSC_PI, .hertz_nradius = 1, .hertz_radii = {{1.0, 0}}, .strain_limit = 0.1,
    .nstage = 1, .stage_steps = {1},
    .method = M2D_CONTACT_MORTAR, .unilateral = PETSC_TRUE, .contact_monitor = PETSC_TRUE, .contact_initial = 1,
    .kkt_mat = M2D_KKT_AIJ, .kkt_path = M2D_KKT_PATH_CONDENSED, .kkt_ordering = M2D_ORDERING_AUTO, .kkt_ldlt = PETSC_TRUE, .kkt_condensed_max = 8000,
    .icntl4 = 0, .icntl7 = 7, .icntl8 = 0, .icntl14 = 20, .icntl58 = 2,
    .out = {.dir = "output", .name = "solution", .h5 = PETSC_TRUE, .vtu = PETSC_TRUE, .csv = PETSC_TRUE, .summary = PETSC_TRUE},
  };
  M2dMeshDir(s->mesh_dir, sizeof(s->mesh_dir)); /* the shipped meshes, .geo and .msh together */
  PetscCall(PetscStrncpy(s->geo_dir, s->mesh_dir, sizeof(s->geo_dir)));
  PetscFunctionReturn(0);
}

/* MUMPS 5.5's documented values of the ICNTL entries the condensed path sets
 * (ICNTL(7) = 1 and ICNTL(8) = -1 need arrays the program does not give) */
static PetscErrorCode CheckMumps(MPI_Comm comm, const M2dScene *s)
{
  const PetscInt scal[] = {-2, 0, 1, 3, 4, 7, 8, 77};
  PetscBool      ok     = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCheck(s->icntl4 >= 0 && s->icntl4 <= 4, comm, PETSC_ERR_USER_INPUT, "option -mat_mumps_icntl_4: %" PetscInt_FMT " is not an output level 0 to 4", s->icntl4);
  PetscCheck(s->icntl7 >= 0 && s->icntl7 <= 7 && s->icntl7 != 1, comm, PETSC_ERR_USER_INPUT, "option -mat_mumps_icntl_7: %" PetscInt_FMT " is not an ordering 0 or 2 to 7 (1, a given ordering, is -kkt_ordering metis)", s->icntl7);
  for (size_t i = 0; i < sizeof(scal) / sizeof(scal[0]); i++) ok = (PetscBool)(ok || s->icntl8 == scal[i]);
  PetscCheck(ok, comm, PETSC_ERR_USER_INPUT, "option -mat_mumps_icntl_8: %" PetscInt_FMT " is not a scaling -2, 0, 1, 3, 4, 7, 8 or 77", s->icntl8);
  PetscCheck(s->icntl14 >= 0, comm, PETSC_ERR_USER_INPUT, "option -mat_mumps_icntl_14: %" PetscInt_FMT " must be >= 0 (a percentage)", s->icntl14);
  PetscCheck(s->icntl58 == 1 || s->icntl58 == 2, comm, PETSC_ERR_USER_INPUT, "option -mat_mumps_icntl_58: %" PetscInt_FMT " must be 1 or 2", s->icntl58);
  PetscFunctionReturn(0);
}

/* -snes_max_it is PETSc's, which takes 0 or a negative value silently: the program needs >= 1 */
static PetscErrorCode CheckSNESMaxIt(MPI_Comm comm)
{
  const char *buf = NULL;
  char        digits[32], shown[128];
  PetscBool   set;
  long long   v = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsFindPair(NULL, NULL, "-snes_max_it", &buf, &set)); /* the whole value */
  if (!set) PetscFunctionReturn(0);
  if (!buf) buf = "";
  PetscCheck(M2dOptionsParseInteger(buf, &v), comm, PETSC_ERR_USER_INPUT, "option -snes_max_it: '%s' is not an integer", M2dShown(buf, shown, sizeof(shown)));
  PetscCheck(v >= 1, comm, PETSC_ERR_USER_INPUT, "option -snes_max_it: %s must be >= 1", M2dShown(buf, shown, sizeof(shown)));
  PetscCheck(v <= PETSC_MAX_INT, comm, PETSC_ERR_USER_INPUT, "option -snes_max_it: '%s' is larger than %d", M2dShown(buf, shown, sizeof(shown)), (int)PETSC_MAX_INT);
  PetscCall(PetscSNPrintf(digits, sizeof(digits), "%lld", v));
  if (strcmp(digits, buf)) PetscCall(PetscOptionsSetValue(NULL, "-snes_max_it", digits)); /* 1e3: PETSc reads digits only */
  PetscFunctionReturn(0);
}

/* PETSc's SNES/KSP tolerances are read without a domain check (-ksp_rtol -1
 * and -snes_rtol -1 ran silently): finite, >= 0, relative ones below 1 */
static PetscErrorCode CheckTolerances(MPI_Comm comm)
{
  const char *const name[] = {"-ksp_rtol", "-ksp_atol", "-ksp_divtol", "-snes_rtol", "-snes_atol", "-snes_stol"};

  PetscFunctionBeginUser;
  for (size_t k = 0; k < sizeof(name) / sizeof(name[0]); k++) {
    const char *buf = NULL;
    char       *end, shown[128];
    PetscBool   set;
    double      v;
    PetscCall(PetscOptionsFindPair(NULL, NULL, name[k], &buf, &set)); /* the whole value */
    if (!set) continue;
    if (!buf) buf = "";
    v = strtod(buf, &end);
    PetscCheck(buf[0] && !*end && isfinite(v) && !M2dUnderflows(buf), comm, PETSC_ERR_USER_INPUT, "option %s: '%s' is not a finite number%s", name[k], M2dShown(buf, shown, sizeof(shown)), M2dUnderflows(buf) ? " (nonzero but below double precision's range)" : "");
    PetscCheck(v >= 0, comm, PETSC_ERR_USER_INPUT, "option %s: %s must be >= 0", name[k], M2dShown(buf, shown, sizeof(shown)));
    PetscCheck(v < 1 || !strstr(name[k], "rtol"), comm, PETSC_ERR_USER_INPUT, "option %s: %s must be < 1", name[k], M2dShown(buf, shown, sizeof(shown)));
  }
  PetscFunctionReturn(0);
}

/* the pairs: the short form as pair 1, each pair's method, no pair twice,
 * each pair's Hertz radius */
/* the pairs -hertz compares and their radii: -hertz_pairs' (one radius for
 * all, or one each), or (none named) every pair with one radius, the pairs
 * with a curved surface chosen once the mesh is read (ProblemCreate) */
static PetscErrorCode SceneHertzPairs(MPI_Comm comm, M2dScene *s)
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < PetscMax(1, s->npair); k++) s->pair[k].hertz = PETSC_FALSE, s->pair[k].hertz_radius = s->hertz_radii[0][1] > 0 ? s->hertz_radii[0][0] * s->hertz_radii[0][1] / (s->hertz_radii[0][0] + s->hertz_radii[0][1]) : s->hertz_radii[0][0];
  if (!s->hertz) PetscFunctionReturn(0);
  if (s->hertz_npairs) PetscCheck(s->hertz_nradius == 1 || s->hertz_nradius == s->hertz_npairs, comm, PETSC_ERR_USER_INPUT, "option -hertz_radius: %d radii for %d pair%s in -hertz_pairs: give one (every listed pair) or one per listed pair", (int)s->hertz_nradius, (int)s->hertz_npairs, s->hertz_npairs == 1 ? "" : "s");
  else if (s->hertz_nradius > 1 && s->npair <= 1) SETERRQ(comm, PETSC_ERR_USER_INPUT, "option -hertz_radius: %d radii for the scene's one pair: give R, or R1:R2 for two cylinders (e.g. %g:%g)", (int)s->hertz_nradius, (double)s->hertz_radii[0][0], (double)s->hertz_radii[1][0]);
  else PetscCheck(s->hertz_nradius == 1, comm, PETSC_ERR_USER_INPUT, "option -hertz_radius: %d radii: name the pairs they are for with -hertz_pairs (one radius each), or give one R (or R1:R2) for every compared pair", (int)s->hertz_nradius);
  for (PetscInt i = 0; i < s->hertz_npairs; i++) { /* the listed pairs, each its own radius (in the list's order) */
    PetscInt         k = s->hertz_pairs[i] - 1;
    const PetscReal *r = s->hertz_radii[s->hertz_nradius > 1 ? i : 0];
    PetscCheck(k < s->npair, comm, PETSC_ERR_USER_INPUT, "option -hertz_pairs: pair %d: the scene has %d pair%s", (int)k + 1, (int)s->npair, s->npair == 1 ? "" : "s");
    PetscCheck(!s->pair[k].hertz, comm, PETSC_ERR_USER_INPUT, "option -hertz_pairs: pair %d is named twice", (int)k + 1);
    s->pair[k].hertz        = PETSC_TRUE;
    s->pair[k].hertz_radius = r[1] > 0 ? r[0] * r[1] / (r[0] + r[1]) : r[0];
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckPairs(MPI_Comm comm, M2dScene *s)
{
  PetscFunctionBeginUser;
  PetscCheck(!s->contact_nm[0] == !s->contact_m[0], comm, PETSC_ERR_USER_INPUT, "option %s: a contact pair needs both -contact_nonmortar and -contact_mortar", s->contact_nm[0] ? "-contact_mortar" : "-contact_nonmortar");
  PetscCheck(!s->contact_nm[0] || !s->npair, comm, PETSC_ERR_USER_INPUT, "option -contact_pairs: give the pairs either there or as -contact_nonmortar and -contact_mortar (one pair), not both");
  for (int k = 0; k < 2 && s->contact_nm[0]; k++) {
    const char *g = k ? s->contact_m : s->contact_nm;
    PetscCheck(!strpbrk(g, ",:"), comm, PETSC_ERR_USER_INPUT, "option %s: '%s' names more than one curve: -contact_nonmortar and -contact_mortar give one pair, -contact_pairs NM1:M1,NM2:M2 several", k ? "-contact_mortar" : "-contact_nonmortar", g);
  }
  if (s->contact_nm[0]) {
    s->npair = 1;
    PetscCall(PetscStrncpy(s->pair[0].nm, s->contact_nm, sizeof(s->pair[0].nm)));
    PetscCall(PetscStrncpy(s->pair[0].m, s->contact_m, sizeof(s->pair[0].m)));
    PetscCall(PetscSNPrintf(s->pair[0].what, sizeof(s->pair[0].what), "options -contact_nonmortar %s and -contact_mortar %s", s->contact_nm, s->contact_m));
    s->pair[0].opt_nm = "-contact_nonmortar";
    s->pair[0].opt_m  = "-contact_mortar";
  }
  for (PetscInt k = 0; k < s->npair; k++) {
    M2dPair *p = &s->pair[k];
    if (!p->own_method) p->method = s->method, p->basis = s->basis;
    if (!p->own_mu) p->mu = s->friction;
    PetscCheck(p->mu == 0 || s->unilateral, comm, PETSC_ERR_USER_INPUT, "%s: friction coefficient %g on a tied pair (-contact_unilateral false holds its nodes in every direction: there is nothing to slide); drop the friction or the tie", p->own_mu ? p->what : "option -contact_friction", (double)p->mu);
    PetscCheck(strcmp(p->nm, p->m), comm, PETSC_ERR_USER_INPUT, "%s: the curve '%s' is on both sides", p->what, p->nm);
    for (PetscInt i = 0; i < k; i++) {
      const M2dPair *q = &s->pair[i];
      PetscCheck((strcmp(p->nm, q->nm) || strcmp(p->m, q->m)) && (strcmp(p->nm, q->m) || strcmp(p->m, q->nm)), comm, PETSC_ERR_USER_INPUT, "%s: the same pair as pair %d '%s:%s'", p->what, (int)i + 1, q->nm, q->m);
    }
  }
  PetscCall(SceneHertzPairs(comm, s));
  PetscFunctionReturn(0);
}

/* a later stage changes the value of a support of the scene, never adds one
 * (the stiffness is factored once for the whole history): each component of
 * a -stage<k>_dirichlet entry must be held by a -dirichlet entry of the same
 * group and kind */
static PetscErrorCode CheckStageSupports(MPI_Comm comm, const M2dScene *s)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < s->ndir; i++) {
    const M2dDirichlet *d = &s->dir[i];
    if (!d->stage) continue;
    for (int c = 0; c < (d->frame == M2D_BC_XY ? 2 : 1); c++) {
      PetscBool held = PETSC_FALSE;
      if (d->frame == M2D_BC_XY && !d->comp[c]) continue;
      for (PetscInt j = 0; j < s->ndir && !held; j++) {
        const M2dDirichlet *e = &s->dir[j];
        held = (PetscBool)(!e->stage && e->frame == d->frame && !strcmp(e->group, d->group) && (d->frame != M2D_BC_XY || e->comp[c]));
      }
      PetscCheck(held, comm, PETSC_ERR_USER_INPUT, "option -stage%d_dirichlet: '%s' %s is not held by -dirichlet; a stage changes the value of a support of the scene and cannot add one (hold it in -dirichlet with value 0)", (int)d->stage + 1, d->group, d->frame == M2D_BC_NORMAL ? "n" : d->frame == M2D_BC_TANGENT ? "t" : c ? "y" : "x");
    }
  }
  PetscFunctionReturn(0);
}

/* domains, and options that need one another */
static PetscErrorCode CheckScene(MPI_Comm comm, M2dScene *s)
{
  PetscFunctionBeginUser;
  PetscCheck(s->mesh_scale > 0, comm, PETSC_ERR_USER_INPUT, "option -mesh_scale: %g must be > 0", (double)s->mesh_scale);
  PetscCheck(!s->contact_c_set || s->contact_c > 0, comm, PETSC_ERR_USER_INPUT, "option -contact_c: %g must be > 0 (auto: the automatic value)", (double)s->contact_c);
  PetscCheck(s->friction >= 0, comm, PETSC_ERR_USER_INPUT, "option -contact_friction: %g must be >= 0", (double)s->friction);
  PetscCall(CheckStageSupports(comm, s));
  PetscCheck(!s->reach_set || s->reach > 0, comm, PETSC_ERR_USER_INPUT, "option -contact_reach: %g must be > 0 (auto: the automatic value)", (double)s->reach);
  PetscCheck(!s->hertz_load_set || s->hertz_load > 0, comm, PETSC_ERR_USER_INPUT, "option -hertz_load: %g must be > 0 (auto: from the first -pressure)", (double)s->hertz_load);
  PetscCheck(!s->exact_p_set || s->exact_p > 0, comm, PETSC_ERR_USER_INPUT, "option -exact_p: %g must be > 0 (auto: the first -pressure)", (double)s->exact_p);
  PetscCheck(s->mms_amplitude != 0, comm, PETSC_ERR_USER_INPUT, "option -mms_amplitude: must not be 0");
  PetscCheck(s->exact != M2D_EXACT_MMS || s->nstage == 1, comm, PETSC_ERR_USER_INPUT, "option -exact mms: the manufactured solution is one load; drop -load_stages");
  PetscCheck(s->strain_limit > 0, comm, PETSC_ERR_USER_INPUT, "option -strain_limit: %g must be > 0", (double)s->strain_limit);
  PetscCheck(s->kkt_augment >= 0, comm, PETSC_ERR_USER_INPUT, "option -kkt_augment: %g must be >= 0", (double)s->kkt_augment);
  PetscCheck(s->kkt_condensed_max >= 0, comm, PETSC_ERR_USER_INPUT, "option -kkt_condensed_max: %" PetscInt_FMT " must be >= 0", s->kkt_condensed_max);
  PetscCall(CheckMumps(comm, s));
  PetscCall(CheckSNESMaxIt(comm));
  PetscCall(CheckTolerances(comm));
  PetscCall(CheckPairs(comm, s));
  if (s->exact == M2D_EXACT_UNIFORM && !s->exact_p_set) {
    PetscCheck(s->nload > 0 && s->load[0].is_pressure && s->load[0].p != 0, comm, PETSC_ERR_USER_INPUT, "option -exact uniform: needs -exact_p or a first -pressure load P != 0 (its value is the exact -sigma_yy)");
    s->exact_p = s->load[0].p;
  }
  PetscCheck(!s->hertz || s->npair, comm, PETSC_ERR_USER_INPUT, "option -hertz: the scene has no contact pair (-contact_pairs, or -contact_nonmortar and -contact_mortar)");
  PetscCheck(!s->cattaneo || (s->hertz && SceneHasFriction(s)), comm, PETSC_ERR_USER_INPUT, "option -cattaneo: needs -hertz (a, p0) and friction (-contact_friction)");
  PetscCheck(s->out.name[0] && !strchr(s->out.name, '/'), comm, PETSC_ERR_USER_INPUT, "option -output_name: '%s' must be a plain file name", s->out.name);
  PetscFunctionReturn(0);
}

/* options that need another one: named (optcheck.h: an error when typed, a
 * note when an options file set them); the solver paths' own in solver.c */
static PetscErrorCode CheckEffect(MPI_Comm comm, const M2dScene *s)
{
  PetscBool own = PETSC_TRUE, mortar = PETSC_FALSE;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < s->npair; k++) {
    own    = (PetscBool)(own && s->pair[k].own_method);
    mortar = (PetscBool)(mortar || (!s->pair[k].own_method && s->pair[k].method == M2D_CONTACT_MORTAR));
  }
  if (!s->hertz) PetscCall(M2dOptionsNoEffect(comm, "-hertz_radius -hertz_load -hertz_pairs", "without -hertz"));
  if (s->exact != M2D_EXACT_UNIFORM) PetscCall(M2dOptionsNoEffect(comm, "-exact_p -exact_angle -exact_tau", "without -exact uniform"));
  if (s->exact != M2D_EXACT_MMS) PetscCall(M2dOptionsNoEffect(comm, "-mms_amplitude", "without -exact mms"));
  if (!s->npair) PetscCall(M2dOptionsNoEffect(comm, "-contact_method -mortar_basis -contact_unilateral -contact_c -contact_initial -contact_reach", "without a contact pair (-contact_pairs, or -contact_nonmortar and -contact_mortar)"));
  else if (own) PetscCall(M2dOptionsNoEffect(comm, "-contact_method -mortar_basis", "when every pair of -contact_pairs names its own method (NM:M:standard|dual|nts)"));
  else if (!mortar) PetscCall(M2dOptionsNoEffect(comm, "-mortar_basis", "with -contact_method nts (node-to-segment rows have no multiplier basis)"));
  if (s->npair && !s->unilateral) PetscCall(M2dOptionsNoEffect(comm, "-contact_c -contact_initial", "with -contact_unilateral false (every candidate node is held closed: no active set)"));
  if (!s->geo[0]) PetscCall(M2dOptionsNoEffect(comm, "-geo_dir", "without -geo"));
  if (!s->npair) PetscCall(M2dOptionsNoEffect(comm, "-contact_friction", "without a contact pair"));
  for (PetscInt k = s->nstage; k < M2D_MAX_STAGES; k++) {
    char names[256];
    PetscCall(PetscSNPrintf(names, sizeof(names), "-stage%d_pressure -stage%d_traction -stage%d_dirichlet -stage%d_steps", (int)k + 1, (int)k + 1, (int)k + 1, (int)k + 1));
    PetscCall(M2dOptionsNoEffect(comm, names, "beyond -load_stages %d", (int)s->nstage));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SceneResolvePath(MPI_Comm comm, const char *opt, const char *given, const char *dir, char *path, size_t len)
{
  PetscMPIInt rank;
  int         found = 0;
  struct stat st;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (rank == 0) {
    PetscCall(PetscStrncpy(path, given, len));
    if (given[0] == '/' || !stat(given, &st)) found = 1; /* an absolute path that is missing: its reader says so */
    else {
      PetscCall(PetscSNPrintf(path, len, "%s/%s", dir, given));
      found = !stat(path, &st);
    }
  }
  PetscCallMPI(MPI_Bcast(&found, 1, MPI_INT, 0, comm));
  PetscCheck(found, comm, PETSC_ERR_USER_INPUT, "option %s: no file '%s' in the current directory or in '%s'", opt, given, dir);
  PetscCallMPI(MPI_Bcast(path, (int)len, MPI_CHAR, 0, comm));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneReadOptions(MPI_Comm comm, M2dScene *s)
{
  PetscFunctionBeginUser;
  PetscCall(Defaults(s));
  PetscCall(PetscOptionsHasHelp(NULL, &s->help));
  /* one group per job: -help prints them in the README's order (helpprint.h) */
  PetscOptionsBegin(comm, NULL, "mortar2d: scene and mesh", "");
  PetscCall(ReadMeshAndBodies(PetscOptionsObject, s));
  PetscOptionsEnd();
  PetscOptionsBegin(comm, NULL, "mortar2d: materials (and -NAME_E, -NAME_nu per body)", "");
  PetscCall(ReadModel(PetscOptionsObject, s));
  PetscOptionsEnd();
  PetscOptionsBegin(comm, NULL, "mortar2d: loads and supports (GROUP: a gmsh physical name)", "");
  PetscCall(ReadBoundaryConditions(PetscOptionsObject, NULL, 0, s));
  PetscOptionsEnd();
  PetscCall(M2dOptionsRaise(comm));
  PetscCall(ReadLoadHistory(comm, s));
  PetscOptionsBegin(comm, NULL, "mortar2d: contact", "");
  PetscCall(ReadContact(PetscOptionsObject, s));
  PetscOptionsEnd();
  PetscOptionsBegin(comm, NULL, "mortar2d: checks against exact answers", "");
  PetscCall(ReadComparisons(PetscOptionsObject, s));
  PetscOptionsEnd();
  PetscOptionsBegin(comm, NULL, "mortar2d: solver paths", "");
  PetscCall(ReadLinearAlgebra(PetscOptionsObject, s));
  PetscOptionsEnd();
  PetscOptionsBegin(comm, NULL, "mortar2d: output", "");
  PetscCall(ReadOutput(PetscOptionsObject, s));
  PetscOptionsEnd();
  PetscOptionsBegin(comm, NULL, "mortar2d: output (mesh)", "");
  PetscCall(M2dOptionsString(PetscOptionsObject, "-mesh_save", "write the mesh as built to this .h5 file (PETSc's HDF5; read back by -mesh F.h5); default: none", s->mesh_save, sizeof(s->mesh_save), NULL));
  PetscOptionsEnd();
  PetscCall(M2dOptionsRaise(comm));
  OutputArmEarly(comm, &s->out); /* a run that fails from here (not at the output paths' own checks) marks the summary an earlier run left */
  PetscCall(CheckScene(comm, s));
  if (s->help) PetscFunctionReturn(0); /* -help documents the options; no files are needed */
  PetscCall(CheckEffect(comm, s));
  if (s->nmesh == 0 && !s->geo[0]) { /* a first try at the program: point to -help */
    for (int i = 0; i < M2dOptionsGivenCount(); i++) {
      const char *g = M2dOptionsGiven(i, NULL);
      PetscCheck(strcasecmp(g, "help"), comm, PETSC_ERR_USER_INPUT, "option --help is not mortar2d's: mortar2d -help lists the options (README.md the scenes)"); /* -help returned above: "--help" (recorded without its dashes) */
      PetscCheck(strcasecmp(g, "h"), comm, PETSC_ERR_USER_INPUT, "option -%s is not mortar2d's: mortar2d -help lists the options (README.md the scenes)", g);
    }
    SETERRQ(comm, PETSC_ERR_USER_INPUT, "option -mesh: no mesh file given (a scene names its mesh: mortar2d -options_file options/patch_uniform.opts; mortar2d -help lists the options)");
  }
  for (PetscInt i = 0; i < s->nmesh; i++) {
    char given[PETSC_MAX_PATH_LEN];
    PetscCall(PetscStrncpy(given, s->mesh[i], sizeof(given)));
    PetscCall(SceneResolvePath(comm, "-mesh", given, s->mesh_dir, s->mesh[i], sizeof(s->mesh[i])));
  }
  if (s->geo[0]) {
    char given[PETSC_MAX_PATH_LEN];
    PetscCall(PetscStrncpy(given, s->geo, sizeof(given)));
    PetscCall(SceneResolvePath(comm, "-geo", given, s->geo_dir, s->geo, sizeof(s->geo)));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SceneReadMaterials(MPI_Comm comm, M2dScene *s)
{
  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < s->nbody; b++) {
    char       prefix[M2D_NAME_LEN + 2], title[256], help[256];
    M2dBody   *body = &s->body[b];
    PetscReal  E;
    PetscCall(PetscSNPrintf(prefix, sizeof(prefix), "%s_", body->name));
    PetscCall(PetscSNPrintf(title, sizeof(title), "Material of body '%s'", body->name));
    body->E  = 1.0;
    body->nu = 0.3;
    PetscOptionsBegin(comm, prefix, title, "");
    PetscCall(PetscSNPrintf(help, sizeof(help), "Young's modulus of body %s, in [1e-300, 1e300]", body->name));
    PetscCall(M2dOptionsReal(PetscOptionsObject, "-E", help, body->E, &body->E, NULL));
    PetscCall(PetscSNPrintf(help, sizeof(help), "Poisson ratio of body %s, in (-1, 0.5)", body->name));
    PetscCall(M2dOptionsReal(PetscOptionsObject, "-nu", help, body->nu, &body->nu, NULL));
    PetscOptionsEnd();
    PetscCall(M2dOptionsRaise(comm));
    /* any finite E > 0 is scaled to order one by the assembly; outside this range the
     * product with a length or a strain is not representable in double precision */
    E = body->E;
    PetscCheck(E > 0, comm, PETSC_ERR_USER_INPUT, "option -%sE: Young's modulus %g must be > 0", prefix, (double)E);
    PetscCheck(E >= 1e-300 && E <= 1e300, comm, PETSC_ERR_USER_INPUT, "option -%sE: Young's modulus %g is outside [1e-300, 1e300]", prefix, (double)E);
    PetscCheck(body->nu > -1 && body->nu < 0.5, comm, PETSC_ERR_USER_INPUT, "option -%snu: Poisson ratio %g must be in (-1, 0.5)", prefix, (double)body->nu);
  }
  s->materials_read = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* before the materials are read, a -NAME_E or -NAME_nu may belong to a body the
 * mesh names (no -bodies), or be meant for a body -bodies misspells (the mesh
 * then says which): left for the check after SceneReadMaterials */
static PetscBool MaybeMaterial(const char *name, void *ctx)
{
  const M2dScene *s = (const M2dScene *)ctx;
  size_t          n = strlen(name);

  if (s->materials_read) return PETSC_FALSE;
  return (PetscBool)((n > 2 && !strcasecmp(name + n - 2, "_E")) || (n > 3 && !strcasecmp(name + n - 3, "_nu")));
}

PetscErrorCode SceneCheckOptions(MPI_Comm comm, const M2dScene *s)
{
  PetscFunctionBeginUser;
  if (s->help) PetscFunctionReturn(0);
  PetscCall(M2dOptionsCheckUnknown(comm, MaybeMaterial, (void *)s));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneView(MPI_Comm comm, const M2dScene *s)
{
  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(comm, "mortar2d: %s, %" PetscInt_FMT " bodies:", s->plane == M2D_PLANE_STRAIN ? "plane strain" : "plane stress", s->nbody));
  for (PetscInt b = 0; b < s->nbody; b++) PetscCall(PetscPrintf(comm, " %s (E = %g, nu = %g)", s->body[b].name, (double)s->body[b].E, (double)s->body[b].nu));
  PetscCall(PetscPrintf(comm, "\n"));
  for (PetscInt i = 0; s->hertz && i < s->hertz_nradius; i++) /* two cylinders: say what R is */
    if (s->hertz_radii[i][1] > 0) PetscCall(PetscPrintf(comm, "mortar2d: Hertz: radii %g and %g%s, effective radius R = R1 R2/(R1 + R2) = %g\n", (double)s->hertz_radii[i][0], (double)s->hertz_radii[i][1], s->hertz_npairs && s->hertz_nradius > 1 ? " of the pair" : "", (double)(s->hertz_radii[i][0] * s->hertz_radii[i][1] / (s->hertz_radii[i][0] + s->hertz_radii[i][1]))));
  PetscFunctionReturn(0);
}

PetscBool SceneHasFriction(const M2dScene *s)
{
  for (PetscInt k = 0; k < s->npair; k++)
    if (s->pair[k].mu > 0) return PETSC_TRUE;
  return PETSC_FALSE;
}

PetscInt SceneLoadSteps(const M2dScene *s)
{
  PetscInt n = 0;
  for (PetscInt k = 0; k < s->nstage; k++) n += s->stage_steps[k];
  return n;
}

PetscReal SceneModuliRatio(const M2dScene *s, PetscInt *soft, PetscInt *stiff)
{
  PetscInt lo = 0, hi = 0;
  for (PetscInt b = 1; b < s->nbody; b++) {
    if (s->body[b].E < s->body[lo].E) lo = b;
    if (s->body[b].E > s->body[hi].E) hi = b;
  }
  if (soft) *soft = lo;
  if (stiff) *stiff = hi;
  return s->body[hi].E / s->body[lo].E;
}
