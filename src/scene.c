/* scene.c - read a scene from the options database.
 *
 * Boundary conditions name gmsh physical groups:
 *   -dirichlet GROUP:x|y|xy[:VALUE]   prescribed displacement component(s) (default value 0)
 *   -pressure  GROUP:P[:GX:GY]        normal pressure P + GX x + GY y (positive pushes into the body)
 *   -traction  GROUP:TX:TY            traction vector
 * Several of each are given comma separated. */
#include "scene.h"
#include <stdlib.h>
#include <string.h>

/* PetscOptionsReal with a check first, so that a bad value is reported with the
 * option's name (PETSc's own message does not name it) and inf is refused */
static PetscErrorCode OptionsReal(PetscOptionItems *PetscOptionsObject, const char *prefix, const char *name, const char *help, PetscReal def, PetscReal *value)
{
  char      buf[256], *end;
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, prefix, name, buf, sizeof(buf), &set));
  if (set) {
    double v = strtod(buf, &end);
    PetscCheck(end != buf && *end == 0 && !PetscIsInfOrNanReal((PetscReal)v), PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -%s%s: '%s' is not a finite number", prefix ? prefix : "", name + 1, buf);
  }
  PetscCall(PetscOptionsReal(name, help, "", def, value, NULL));
  PetscFunctionReturn(0);
}

/* a string option with a fixed set of values: *index is the default on entry,
 * the chosen value on return; anything else is an error naming the option */
static PetscErrorCode OptionsChoice(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, const char *const choices[], PetscInt n, PetscInt *index)
{
  char buf[64], list[256] = "";

  PetscFunctionBeginUser;
  PetscCall(PetscStrncpy(buf, choices[*index], sizeof(buf)));
  PetscCall(PetscOptionsString(name, help, "", buf, buf, sizeof(buf), NULL));
  for (PetscInt i = 0; i < n; i++) {
    if (!strcmp(buf, choices[i])) {
      *index = i;
      PetscFunctionReturn(0);
    }
    PetscCall(PetscStrlcat(list, i ? "|" : "", sizeof(list)));
    PetscCall(PetscStrlcat(list, choices[i], sizeof(list)));
  }
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: unknown value '%s' (expected %s)", name, buf, list);
}

static PetscErrorCode ParseReal(const char *opt, const char *entry, const char *text, PetscReal *v)
{
  char *end;
  PetscFunctionBeginUser;
  *v = strtod(text, &end);
  PetscCheck(end != text && *end == 0 && *v == *v, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: '%s' in '%s' is not a number", opt, text, entry);
  PetscFunctionReturn(0);
}

/* split "a:b:c" in place into at most max fields */
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

static PetscErrorCode ReadGroupList(PetscOptionItems *PetscOptionsObject, const char *opt, const char *help, char ***entries, PetscInt *n)
{
  PetscBool set;
  PetscInt  nmax = M2D_MAX_BC;
  char    **e;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(nmax, &e));
  PetscCall(PetscOptionsStringArray(opt, help, "", e, &nmax, &set));
  if (!set) nmax = 0;
  *entries = e;
  *n       = nmax;
  PetscFunctionReturn(0);
}

static PetscErrorCode FreeList(char **e, PetscInt n)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n; i++) PetscCall(PetscFree(e[i]));
  PetscCall(PetscFree(e));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneReadOptions(MPI_Comm comm, M2dScene *s)
{
  char     *mesh[3]   = {NULL, NULL, NULL};
  char     *bodies[M2D_MAX_BODIES + 1];
  char    **dir, **pres, **trac;
  PetscInt  nmesh = 3, nbodies = M2D_MAX_BODIES + 1, ndir, npres, ntrac;
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof(*s)));
  s->mms_amplitude = 1e-3;
  s->mms_wavenumber = PETSC_PI;
  s->write_vtu     = PETSC_TRUE;
  s->write_hdf5    = PETSC_TRUE;
  PetscCall(PetscStrncpy(s->outdir, "output", sizeof(s->outdir)));
  PetscCall(PetscStrncpy(s->outname, "solution", sizeof(s->outname)));
  PetscCall(PetscOptionsHasHelp(NULL, &s->help));

  PetscOptionsBegin(comm, NULL, "mortar2d: 2D frictionless contact of elastic bodies (Q4, mortar)", "");
  PetscCall(PetscOptionsStringArray("-mesh", "gmsh .msh file: one holding every body, or two comma-separated files (one per body); default: none, required", "", mesh, &nmesh, &set));
  s->nmesh = set ? nmesh : 0;
  PetscCheck(nmesh <= 2, comm, PETSC_ERR_USER_INPUT, "option -mesh: at most two files, got %" PetscInt_FMT, nmesh);
  for (PetscInt i = 0; i < s->nmesh; i++) {
    PetscCall(PetscStrncpy(s->mesh[i], mesh[i], sizeof(s->mesh[i])));
    PetscCall(PetscFree(mesh[i]));
  }
  s->mesh_scale = 1.0;
  PetscCall(OptionsReal(PetscOptionsObject, NULL, "-mesh_scale", "multiply the mesh coordinates by this factor (a change of length unit)", s->mesh_scale, &s->mesh_scale));
  PetscCheck(s->mesh_scale > 0, comm, PETSC_ERR_USER_INPUT, "option -mesh_scale: %g must be > 0", (double)s->mesh_scale);
  {
    const char *parts[] = {"metis", "petsc", "M2dPartitioner", "M2D_PARTITIONER_", NULL};
    s->mesh_partitioner = M2D_PARTITIONER_METIS;
    PetscCall(PetscOptionsEnum("-mesh_partitioner", "how the cells are split over the ranks: metis (libmetis on rank 0, METIS_PartGraphRecursive on the cells sharing an edge; every rank then builds its own part of the plex) or petsc (PETSc's partitioner, -petscpartitioner_type, PTScotch by default, and DMPlexDistribute)", "", parts, (PetscEnum)s->mesh_partitioner, (PetscEnum *)&s->mesh_partitioner, NULL));
  }
  s->mesh_check = PETSC_FALSE;
  PetscCall(PetscOptionsBool("-mesh_check", "run PETSc's plex checks (symmetry, skeleton, faces and their orientation, geometry; point SF on several ranks) on the mesh as built", "", s->mesh_check, &s->mesh_check, NULL));
  PetscCall(PetscOptionsStringArray("-bodies", "physical surface names of the bodies, comma separated (default: every physical surface is a body)", "", bodies, &nbodies, &set));
  if (!set) nbodies = 0;
  PetscCheck(nbodies <= M2D_MAX_BODIES, comm, PETSC_ERR_USER_INPUT, "option -bodies: at most %d bodies", M2D_MAX_BODIES);
  s->nbody = nbodies;
  for (PetscInt i = 0; i < nbodies; i++) {
    PetscCall(PetscStrncpy(s->body[i].name, bodies[i], sizeof(s->body[i].name)));
    PetscCall(PetscFree(bodies[i]));
    for (PetscInt j = 0; j < i; j++) PetscCheck(strcmp(s->body[i].name, s->body[j].name), comm, PETSC_ERR_USER_INPUT, "option -bodies: '%s' is listed twice", s->body[i].name);
  }
  {
    const char *const planes[] = {"strain", "stress"}; /* order of PlaneMode */
    PetscInt          k        = M2D_PLANE_STRAIN;
    PetscCall(OptionsChoice(PetscOptionsObject, "-plane", "plane strain or plane stress: strain|stress", planes, 2, &k));
    s->plane = (M2dPlane)k;
  }

  {
    const char *const integ[] = {"full", "sri"};
    PetscInt          k       = 0;
    PetscCall(OptionsChoice(PetscOptionsObject, "-q4_integration", "Q4 stiffness integration: full (2x2 Gauss; locks as nu -> 0.5 in plane strain) or sri (selective reduced: the lambda part at 1 point, cures volumetric locking)", integ, 2, &k));
    s->sri = (PetscBool)(k == 1);
  }
  PetscCall(ReadGroupList(PetscOptionsObject, "-dirichlet", "prescribed displacement GROUP:x|y|xy[:VALUE] on a physical curve or point, comma separated; default: none", &dir, &ndir));
  PetscCall(ReadGroupList(PetscOptionsObject, "-pressure", "normal pressure GROUP:P[:GX:GY] on a physical curve, p = P + GX x + GY y (p > 0 pushes into the body), comma separated; default: none", &pres, &npres));
  PetscCall(ReadGroupList(PetscOptionsObject, "-traction", "traction GROUP:TX:TY on a physical curve, comma separated; default: none", &trac, &ntrac));
  for (PetscInt i = 0; i < ndir; i++) {
    char        *f[4], buf[256];
    int          nf;
    M2dDirichlet *bc = &s->dir[s->ndir++];
    PetscCall(PetscStrncpy(buf, dir[i], sizeof(buf)));
    nf = Split(buf, f, 3);
    PetscCheck(nf == 2 || nf == 3, comm, PETSC_ERR_USER_INPUT, "option -dirichlet: '%s' is not GROUP:x|y|xy[:VALUE]", dir[i]);
    PetscCall(PetscStrncpy(bc->group, f[0], sizeof(bc->group)));
    if (!strcmp(f[1], "x")) bc->comp[0] = PETSC_TRUE;
    else if (!strcmp(f[1], "y")) bc->comp[1] = PETSC_TRUE;
    else if (!strcmp(f[1], "xy")) bc->comp[0] = bc->comp[1] = PETSC_TRUE;
    else SETERRQ(comm, PETSC_ERR_USER_INPUT, "option -dirichlet: unknown component '%s' in '%s' (expected x, y or xy)", f[1], dir[i]);
    if (nf == 3) {
      PetscReal v;
      PetscCall(ParseReal("-dirichlet", dir[i], f[2], &v));
      bc->value[0] = bc->value[1] = v;
    }
  }
  for (PetscInt i = 0; i < npres; i++) {
    char     *f[5], buf[256];
    M2dEdgeLoad *l = &s->load[s->nload++];
    PetscCall(PetscStrncpy(buf, pres[i], sizeof(buf)));
    int   nf;
    nf = Split(buf, f, 4);
    PetscCheck(nf == 2 || nf == 4, comm, PETSC_ERR_USER_INPUT, "option -pressure: '%s' is not GROUP:P or GROUP:P:GX:GY", pres[i]);
    PetscCall(PetscStrncpy(l->group, f[0], sizeof(l->group)));
    l->is_pressure = PETSC_TRUE;
    PetscCall(ParseReal("-pressure", pres[i], f[1], &l->p));
    if (nf == 4) {
      PetscCall(ParseReal("-pressure", pres[i], f[2], &l->grad[0]));
      PetscCall(ParseReal("-pressure", pres[i], f[3], &l->grad[1]));
    }
  }
  for (PetscInt i = 0; i < ntrac; i++) {
    char     *f[4], buf[256];
    M2dEdgeLoad *l;
    PetscCheck(s->nload < M2D_MAX_BC, comm, PETSC_ERR_USER_INPUT, "options -pressure and -traction: at most %d loads", M2D_MAX_BC);
    l = &s->load[s->nload++];
    PetscCall(PetscStrncpy(buf, trac[i], sizeof(buf)));
    PetscCheck(Split(buf, f, 3) == 3, comm, PETSC_ERR_USER_INPUT, "option -traction: '%s' is not GROUP:TX:TY", trac[i]);
    PetscCall(PetscStrncpy(l->group, f[0], sizeof(l->group)));
    PetscCall(ParseReal("-traction", trac[i], f[1], &l->t[0]));
    PetscCall(ParseReal("-traction", trac[i], f[2], &l->t[1]));
  }
  PetscCall(FreeList(dir, ndir));
  PetscCall(FreeList(pres, npres));
  PetscCall(FreeList(trac, ntrac));

  {
    const char *const exact[] = {"none", "uniform", "mms"}; /* order of ExactKind */
    PetscInt          k       = M2D_EXACT_NONE;
    PetscCall(OptionsChoice(PetscOptionsObject, "-exact", "exact solution to compare with: none|uniform|mms (uniform: sigma_yy = -p of the first -pressure, sigma_xx = sigma_xy = 0)", exact, 3, &k));
    s->exact = (M2dExact)k;
  }
  PetscCall(OptionsReal(PetscOptionsObject, NULL, "-exact_p", "exact -sigma_yy for -exact uniform (<= 0: the first -pressure)", s->exact_p, &s->exact_p));
  PetscCall(OptionsReal(PetscOptionsObject, NULL, "-mms_amplitude", "amplitude of the manufactured displacement (-exact mms)", s->mms_amplitude, &s->mms_amplitude));
  PetscCall(PetscOptionsString("-contact_nonmortar", "physical curve of the non-mortar contact surface (carries the multipliers); empty: no contact", "", s->contact_nm, s->contact_nm, sizeof(s->contact_nm), NULL));
  PetscCall(PetscOptionsString("-contact_mortar", "physical curve of the mortar contact surface", "", s->contact_m, s->contact_m, sizeof(s->contact_m), NULL));
  PetscCheck(!s->contact_nm[0] == !s->contact_m[0], comm, PETSC_ERR_USER_INPUT, "option %s: a contact pair needs both -contact_nonmortar and -contact_mortar", s->contact_nm[0] ? "-contact_mortar" : "-contact_nonmortar");
  {
    const char *const methods[] = {"mortar", "nts"}; /* order of ContactMethod */
    PetscInt          k         = M2D_CONTACT_MORTAR;
    PetscCall(OptionsChoice(PetscOptionsObject, "-contact_method", "contact discretisation: mortar|nts", methods, 2, &k));
    s->method = (M2dContactMethod)k;
  }
  s->unilateral      = PETSC_TRUE;
  s->contact_monitor = PETSC_TRUE;
  s->hertz_radius    = 1.0;
  s->hertz_load      = -1;
  PetscCall(PetscOptionsBool("-contact_unilateral", "unilateral contact (active set through SNES); false: every candidate node stays closed (tied, one linear solve)", "", s->unilateral, &s->unilateral, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, NULL, "-contact_c", "complementarity parameter c of the active-set test lambda/c >= gap (<= 0: E*/h^2 from the materials and the non-mortar edge length)", s->contact_c, &s->contact_c));
  {
    const char *const init[] = {"gap", "closest", "all"};
    s->contact_initial       = 1;
    PetscCall(OptionsChoice(PetscOptionsObject, "-contact_initial", "first active set: gap (nodes whose initial gap is closed), closest (the nodes with the smallest initial gap: a body held only by contact is held from the start), all (every candidate)", init, 3, &s->contact_initial));
  }
  PetscCall(PetscOptionsBool("-contact_monitor", "print one line per active-set step", "", s->contact_monitor, &s->contact_monitor, NULL));
  PetscCall(PetscOptionsBool("-hertz", "compare the contact pressure with Hertz (cylinder on a half-space, plane strain) and report it", "", s->hertz, &s->hertz, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, NULL, "-hertz_radius", "cylinder radius R for -hertz", s->hertz_radius, &s->hertz_radius));
  PetscCall(OptionsReal(PetscOptionsObject, NULL, "-hertz_load", "load P per unit thickness on the full cylinder for -hertz (<= 0: twice the resultant of the first -pressure, as for the quarter model)", s->hertz_load, &s->hertz_load));
  {
    const char *const basis[] = {"standard", "dual"}; /* order of MortarBasis */
    PetscInt          k       = 0;
    PetscCall(OptionsChoice(PetscOptionsObject, "-mortar_basis", "multiplier basis of the mortar method: standard (the seed report) or dual (biorthogonal: diagonal D, decoupled nodal contact conditions)", basis, 2, &k));
    s->basis = (int)k;
  }
  PetscCall(OptionsReal(PetscOptionsObject, NULL, "-contact_reach", "search distance: non-mortar points farther than this from the mortar surface get no multiplier (<= 0: 0.1 x the mortar surface's extent)", s->reach, &s->reach));
  {
    const char *const mats[] = {"aij", "nest"}; /* order of KKTMatType */
    PetscInt          k      = M2D_KKT_AIJ;
    PetscCall(OptionsChoice(PetscOptionsObject, "-kkt_mat", "matrix of the KKT system: aij (monolithic, for MUMPS) or nest (MatNest, for PCFIELDSPLIT)", mats, 2, &k));
    s->kkt_mat = (M2dKKTMat)k;
  }
  {
    const char *const paths[] = {"full", "condensed"};
    PetscInt          k       = 1;
    PetscCall(OptionsChoice(PetscOptionsObject, "-kkt_path", "linear solves of the active set: condensed (K + g C^T C factored once: every rank factors its own rows with its own MUMPS, called directly, with a Schur complement on the interface, the multipliers and the rows coupled to another rank; the steps run on the multipliers with dense n_lambda algebra; 1 or more ranks) or full (the KKT matrix refactored at every step through PETSc's PCLU; needed for PCFIELDSPLIT, nest and vinewtonrsls)", paths, 2, &k));
    s->condensed = (PetscBool)(k == 1);
  }
  {
    const char *const ords[] = {"mumps", "metis"}; /* order of M2dOrdering */
    PetscInt          k      = M2D_ORDERING_METIS;
    PetscCall(OptionsChoice(PetscOptionsObject, "-kkt_ordering", "fill-reducing ordering handed to MUMPS: metis (libmetis nested dissection, multipliers last; condensed path on any number of ranks - each rank orders its own interior, the interface (its rows coupled to a higher rank, the multipliers) last -, full path on one rank) or mumps (MUMPS' own choice, -mat_mumps_icntl_7; AMD whenever a Schur complement is asked)", ords, 2, &k));
    s->kkt_ordering = (M2dOrdering)k;
  }
  s->kkt_ldlt = PETSC_TRUE;
  PetscCall(PetscOptionsBool("-kkt_ldlt", "condensed path: LDL^T of the symmetric KKT matrix (MUMPS SYM = 2, half the flops of LU); false: LU", "", s->kkt_ldlt, &s->kkt_ldlt, NULL));
  s->icntl4  = 0;
  s->icntl7  = 7;
  s->icntl8  = 0;
  s->icntl14 = 20;
  s->icntl58 = 2;
  PetscCall(PetscOptionsInt("-mat_mumps_icntl_4", "condensed path's MUMPS: output level (0 none, 2 statistics)", "", s->icntl4, &s->icntl4, NULL));
  PetscCall(PetscOptionsInt("-mat_mumps_icntl_7", "condensed path's MUMPS with -kkt_ordering mumps: its ordering (AMD is used whenever a Schur complement is asked)", "", s->icntl7, &s->icntl7, NULL));
  PetscCall(PetscOptionsInt("-mat_mumps_icntl_8", "condensed path's MUMPS: scaling (0: none - the factored block K + g C^T C is symmetric positive definite, and scaling cost 0.4 s of 4.6 s at level 5 -, 77: MUMPS' automatic choice)", "", s->icntl8, &s->icntl8, NULL));
  PetscCall(PetscOptionsInt("-mat_mumps_icntl_14", "condensed path's MUMPS: working-space increase in percent (raise it when MUMPS reports INFOG(1) = -9)", "", s->icntl14, &s->icntl14, NULL));
  PetscCall(PetscOptionsInt("-mat_mumps_icntl_58", "condensed path's MUMPS: symbolic factorization (2: column counts, 0.25 s faster analysis than 1 at level 5; PETSc 3.18 does not forward this option to its own MUMPS interface)", "", s->icntl58, &s->icntl58, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, NULL, "-kkt_augment", "augmented-Lagrangian weight: K + w*scale*C^T C in the (u,u) block, exact at the solution; makes K invertible when bodies are held only by contact (fieldsplit needs it then); 0: off", s->kkt_augment, &s->kkt_augment));
  PetscCheck(s->kkt_augment >= 0, comm, PETSC_ERR_USER_INPUT, "option -kkt_augment: %g must be >= 0", (double)s->kkt_augment);
  PetscCall(PetscOptionsString("-output_dir", "directory for the HDF5/XDMF, VTU and CSV output (created if missing)", "", s->outdir, s->outdir, sizeof(s->outdir), NULL));
  PetscCall(PetscOptionsString("-output_name", "base name of the output files", "", s->outname, s->outname, sizeof(s->outname), NULL));
  PetscCall(PetscOptionsBool("-output_vtu", "write NAME.vtu", "", s->write_vtu, &s->write_vtu, NULL));
  PetscCall(PetscOptionsBool("-output_hdf5", "write NAME.h5 and NAME.xmf", "", s->write_hdf5, &s->write_hdf5, NULL));
  PetscCall(PetscOptionsString("-summary", "write a JSON summary of the run to this file (empty: none)", "", s->summary, s->summary, sizeof(s->summary), NULL));
  PetscOptionsEnd();
  if (s->exact == M2D_EXACT_UNIFORM && s->exact_p <= 0) {
    PetscCheck(s->nload > 0 && s->load[0].is_pressure, comm, PETSC_ERR_USER_INPUT, "option -exact uniform: needs -exact_p or a -pressure load (its value is the exact -sigma_yy)");
    s->exact_p = s->load[0].p;
  }
  PetscCheck(!s->hertz || s->hertz_load > 0 || (s->nload > 0 && s->load[0].is_pressure), comm, PETSC_ERR_USER_INPUT, "option -hertz: needs -hertz_load or a -pressure load");
  PetscCheck(!s->hertz || s->contact_nm[0], comm, PETSC_ERR_USER_INPUT, "option -hertz: the scene has no contact pair (-contact_nonmortar, -contact_mortar)");
  PetscCheck(s->outname[0] && !strchr(s->outname, '/'), comm, PETSC_ERR_USER_INPUT, "option -output_name: '%s' must be a plain file name", s->outname);
  PetscFunctionReturn(0);
}

PetscErrorCode SceneReadMaterials(MPI_Comm comm, M2dScene *s)
{
  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < s->nbody; b++) {
    char prefix[M2D_NAME_LEN + 2], title[256], help[256];
    PetscCall(PetscSNPrintf(prefix, sizeof(prefix), "%s_", s->body[b].name));
    PetscCall(PetscSNPrintf(title, sizeof(title), "Material of body '%s'", s->body[b].name));
    s->body[b].E  = 1.0;
    s->body[b].nu = 0.3;
    PetscOptionsBegin(comm, prefix, title, "");
    PetscCall(PetscSNPrintf(help, sizeof(help), "Young's modulus of body %s (> 0)", s->body[b].name));
    PetscCall(OptionsReal(PetscOptionsObject, prefix, "-E", help, s->body[b].E, &s->body[b].E));
    PetscCall(PetscSNPrintf(help, sizeof(help), "Poisson ratio of body %s, in (-1, 0.5)", s->body[b].name));
    PetscCall(OptionsReal(PetscOptionsObject, prefix, "-nu", help, s->body[b].nu, &s->body[b].nu));
    PetscOptionsEnd();
    PetscCheck(s->body[b].E > 0, comm, PETSC_ERR_USER_INPUT, "option -%sE: Young's modulus %g must be > 0", prefix, (double)s->body[b].E);
    PetscCheck(s->body[b].nu > -1 && s->body[b].nu < 0.5, comm, PETSC_ERR_USER_INPUT, "option -%snu: Poisson ratio %g must be in (-1, 0.5)", prefix, (double)s->body[b].nu);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode SceneView(MPI_Comm comm, const M2dScene *s)
{
  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(comm, "mortar2d: %s, %" PetscInt_FMT " bodies:", s->plane == M2D_PLANE_STRAIN ? "plane strain" : "plane stress", s->nbody));
  for (PetscInt b = 0; b < s->nbody; b++) PetscCall(PetscPrintf(comm, " %s (E = %g, nu = %g)", s->body[b].name, (double)s->body[b].E, (double)s->body[b].nu));
  PetscCall(PetscPrintf(comm, "\n"));
  PetscFunctionReturn(0);
}
