/* Unit tests of the remeshing engine (remesh.h): the .geo's own mesh equals gmsh's
 * command-line .msh; parameters act as gmsh's -setnumber and do not leak from one
 * call to the next; a size field refines where it is small, every cell a
 * counter-clockwise convex quad, the bodies separate, physical groups kept, the
 * curved contact surface on its circle; errors name the .geo; gmsh's crash is
 * one line and its memory is bounded; the run's directory in TMPDIR is empty
 * between calls, and the sweep removes a dead run's, not a live one's; the
 * size field alone interpolates, extrapolates and filters by body as documented.
 * Meshes from the build: ../meshes/<name>.msh (ctest runs in build/tests). */
#include "msh.h"
#include "remesh.h"
#include "temprecord.h"
#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"

static char src[4096]; /* the source tree, from this file's path */

static const char *Path(const char *rel)
{
  static char buf[4][4096];
  static int  k;
  k = (k + 1) % 4;
  snprintf(buf[k], sizeof(buf[k]), "%s/%s", src, rel);
  return buf[k];
}

/* smallest corner Jacobian over all quads (> 0: all convex and counter-clockwise) */
static double MinJacobian(const MshMesh *m)
{
  double jmin = 1e300;
  for (long q = 0; q < m->nquad; q++)
    for (int k = 0; k < 4; k++) {
      const double *p = &m->xy[2 * m->quad[4 * q + k]], *a = &m->xy[2 * m->quad[4 * q + (k + 1) % 4]], *b = &m->xy[2 * m->quad[4 * q + (k + 3) % 4]];
      double        j = (a[0] - p[0]) * (b[1] - p[1]) - (a[1] - p[1]) * (b[0] - p[0]);
      if (j < jmin) jmin = j;
    }
  return jmin;
}

static int PhysTag(const MshMesh *m, int dim, const char *name)
{
  for (int i = 0; i < m->nphys; i++)
    if (m->phys[i].dim == dim && !strcmp(m->phys[i].name, name)) return m->phys[i].tag;
  return -1;
}

/* the same mesh, index for index (coordinates to the 16 digits of the .msh text) */
static int SameMesh(const MshMesh *a, const MshMesh *b)
{
  if (a->nnode != b->nnode || a->nquad != b->nquad || a->nline != b->nline || a->npoint != b->npoint || a->nphys != b->nphys) return 0;
  for (long i = 0; i < 2 * a->nnode; i++)
    if (fabs(a->xy[i] - b->xy[i]) > 1e-15 * fmax(1, fabs(b->xy[i]))) return 0;
  if (memcmp(a->quad, b->quad, 4 * (size_t)a->nquad * sizeof(long))) return 0;
  if (memcmp(a->quadphys, b->quadphys, (size_t)a->nquad * sizeof(int)) || memcmp(a->line, b->line, 2 * (size_t)a->nline * sizeof(long))) return 0;
  if (memcmp(a->linephys, b->linephys, (size_t)a->nline * sizeof(int)) || memcmp(a->point, b->point, (size_t)a->npoint * sizeof(long))) return 0;
  for (int i = 0; i < a->nphys; i++)
    if (a->phys[i].dim != b->phys[i].dim || a->phys[i].tag != b->phys[i].tag || strcmp(a->phys[i].name, b->phys[i].name)) return 0;
  return 1;
}

/* no node used by quads of two different physical surfaces */
static int BodiesSeparate(const MshMesh *m)
{
  int *owner = (int *)malloc((size_t)m->nnode * sizeof(int)), ok = 1;
  for (long n = 0; n < m->nnode; n++) owner[n] = -1;
  for (long q = 0; q < 4 * m->nquad; q++) {
    int *o = &owner[m->quad[q]], p = m->quadphys[q / 4];
    if (*o >= 0 && *o != p) ok = 0;
    *o = p;
  }
  free(owner);
  return ok;
}

static int Remesh(M2dRemeshInput *in, MshMesh *m, char *err)
{
  M2dRemeshStats st;
  int            rc = M2dRemesh(in, m, &st, err, 1024);
  if (rc) printf("     (%s)\n", err);
  return rc;
}

static void WriteGeo(const char *path, const char *text)
{
  FILE *fp = fopen(path, "w");
  fputs(text, fp);
  fclose(fp);
}

/* a new temporary .geo holding text: geo is a mkstemps template ending in
 * XXXXXX.geo, filled in with the name; the caller unlinks the file */
static void NewGeo(char geo[], const char *text)
{
  close(mkstemps(geo, 4));
  WriteGeo(geo, text);
}

static void TestOwnMesh(void)
{
  M2dRemeshInput in = {0};
  MshMesh        m, ref;
  char           err[1024];
  const char    *names[] = {"level"};
  double         values[] = {0};
  in.geo = Path("meshes/patch_uniform.geo");
  CHECK(!Remesh(&in, &m, err) && !MshRead("../meshes/patch_uniform.msh", &ref, err, sizeof(err)) && SameMesh(&m, &ref), "patch_uniform.geo without a field: the mesh of gmsh's command line (nodes, quads, groups, names)");
  MshFree(&m), MshFree(&ref);
  in.geo = Path("meshes/hertz.geo"), in.nnumber = 1, in.names = names, in.values = values;
  CHECK(!Remesh(&in, &m, err) && !MshRead("../meshes/hertz_0.msh", &ref, err, sizeof(err)) && SameMesh(&m, &ref), "hertz.geo level 0 set as a parameter: the mesh of gmsh -setnumber level 0");
  MshFree(&m), MshFree(&ref);
}

/* DefineConstant and If (!Exists(...)) see the parameters; the next call starts clean */
static void TestParameters(void)
{
  char           geo[] = "/tmp/m2d_test_remesh_XXXXXX.geo", err[1024];
  const char    *names[] = {"nx", "ny"};
  double         values[] = {5, 3};
  M2dRemeshInput in = {0};
  MshMesh        m;
  NewGeo(geo, "DefineConstant[ nx = {2, Name \"Parameters/nx\"} ];\nIf (!Exists(ny))\n  ny = 4;\nEndIf\n"
              "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};\n"
              "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
              "Transfinite Curve{1, 3} = nx + 1; Transfinite Curve{2, 4} = ny + 1; Transfinite Surface{1}; Recombine Surface{1};\n"
              "Physical Surface(\"square\", 7) = {1};\n");
  in.geo = geo, in.nnumber = 2, in.names = names, in.values = values;
  CHECK(!Remesh(&in, &m, err) && m.nquad == 15, "parameters nx = 5 (DefineConstant) and ny = 3 (If !Exists): %ld quads, expected 15", m.nquad);
  MshFree(&m);
  in.nnumber = 0;
  CHECK(!Remesh(&in, &m, err) && m.nquad == 8, "next call without parameters: the .geo's defaults, %ld quads, expected 8", m.nquad);
  MshFree(&m);
  names[0] = "2x";
  in.nnumber = 1;
  CHECK(M2dRemesh(&in, &m, NULL, err, sizeof(err)) && strstr(err, geo) && strstr(err, "2x"), "a parameter name that is no identifier: '%s'", err);
  unlink(geo);
}

static void TestErrors(void)
{
  char           geo[] = "/tmp/m2d_test_remesh_XXXXXX.geo", err[1024];
  M2dRemeshInput in = {0};
  MshMesh        m;
  NewGeo(geo, "Point(1) = {0, 0, 0};\nLine(1) = {1, 2 3};\n");
  in.geo = "/nonexistent/scene.geo";
  CHECK(M2dRemesh(&in, &m, NULL, err, sizeof(err)) && strstr(err, in.geo) && !strchr(err, '\n') && m.nquad == 0, "missing .geo: '%s'", err);
  in.geo = geo;
  CHECK(M2dRemesh(&in, &m, NULL, err, sizeof(err)) && strstr(err, geo) && strstr(err, "syntax error") && !strchr(err, '\n'), "syntax error: '%s'", err);
  WriteGeo(geo, "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {0, 1, 0};\nLine(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};\n"
              "Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};\nPhysical Surface(\"tri\", 1) = {1};\n");
  CHECK(M2dRemesh(&in, &m, NULL, err, sizeof(err)) && strstr(err, geo) && strstr(err, "triangle"), "a .geo that makes triangles: '%s'", err);
  unlink(geo);
  in.geo = Path("meshes/patch_uniform.geo");
  CHECK(!Remesh(&in, &m, err) && m.nquad == 85, "after those errors gmsh still meshes: %ld quads, expected 85", m.nquad);
  MshFree(&m);
}

/* patch_uniform.geo's two bodies and groups, its Transfinite lines skipped under a
 * size field as remesh.h asks */
static const char *patch_geo =
  "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 0.5, 0}; Point(4) = {0, 0.5, 0};\n"
  "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
  "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
  "Point(11) = {0, 0.5, 0}; Point(12) = {1, 0.5, 0}; Point(13) = {1, 1, 0}; Point(14) = {0, 1, 0};\n"
  "Line(11) = {11, 12}; Line(12) = {12, 13}; Line(13) = {13, 14}; Line(14) = {14, 11};\n"
  "Curve Loop(2) = {11, 12, 13, 14}; Plane Surface(2) = {2};\n"
  "If (!Exists(m2d_size_field))\n"
  "  Transfinite Curve{1, 3} = 11; Transfinite Curve{2, 4} = 6; Transfinite Surface{1};\n"
  "  Transfinite Curve{11, 13} = 8; Transfinite Curve{12, 14} = 6; Transfinite Surface{2};\n"
  "EndIf\n"
  "Mesh.RecombineAll = 1;\n"
  "Physical Surface(\"lower\", 1) = {1};\nPhysical Curve(\"lower_bottom\", 11) = {1};\nPhysical Curve(\"lower_right\", 12) = {2};\n"
  "Physical Curve(\"lower_top\", 13) = {3};\nPhysical Curve(\"lower_left\", 14) = {4};\nPhysical Point(\"lower_origin\", 31) = {1};\n"
  "Physical Point(\"lower_corner2\", 33) = {2};\nPhysical Surface(\"upper\", 2) = {2};\nPhysical Curve(\"upper_bottom\", 21) = {11};\n"
  "Physical Curve(\"upper_right\", 22) = {12};\nPhysical Curve(\"upper_top\", 23) = {13};\nPhysical Curve(\"upper_left\", 24) = {14};\n"
  "Physical Point(\"upper_corner\", 32) = {11};\n";

/* same groups (dimension, tag, name) as the .msh of gmsh's command line */
static int SameGroups(const MshMesh *m, const MshMesh *ref)
{
  if (m->nphys != ref->nphys) return 0;
  for (int i = 0; i < ref->nphys; i++)
    if (PhysTag(m, ref->phys[i].dim, ref->phys[i].name) != ref->phys[i].tag) return 0;
  return 1;
}

/* cells a field asks for in a box: integral of 1 / h^2 (midpoint rule) */
static double Cells(const M2dRemeshField *f, double x0, double x1, double y0, double y1)
{
  double sum = 0, dx = (x1 - x0) / 100, dy = (y1 - y0) / 100;
  for (int j = 0; j < 100; j++)
    for (int i = 0; i < 100; i++) {
      double h = M2dRemeshFieldEval(f, -1, x0 + (i + 0.5) * dx, y0 + (j + 0.5) * dy);
      sum += dx * dy / (h * h);
    }
  return sum;
}

/* one mesh of the patch with the field: shapes, groups, refinement as the field
 * asks (ratio of the cells in two boxes), bodies */
static void CheckPatch(const MshMesh *m, const MshMesh *ref, const M2dRemeshStats *st, int quads, double want)
{
  long ncorner = 0, nfar = 0, nbad = 0;
  int  lower = PhysTag(m, 2, "lower"), upper = PhysTag(m, 2, "upper"), lines_ok = 1;
  for (long q = 0; q < m->nquad; q++) {
    double cx = 0, cy = 0;
    for (int k = 0; k < 4; k++) cx += m->xy[2 * m->quad[4 * q + k]] / 4, cy += m->xy[2 * m->quad[4 * q + k] + 1] / 4;
    if (cx < 0.25 && cy < 0.25) ncorner++;
    if (cx > 0.5 && cy > 0.25 && cy < 0.5) nfar++;
    for (int k = 0; k < 4; k++) {
      double x = m->xy[2 * m->quad[4 * q + k]], y = m->xy[2 * m->quad[4 * q + k] + 1];
      if (x < -1e-12 || x > 1 + 1e-12 || y < (m->quadphys[q] == upper ? 0.5 : 0) - 1e-12 || y > (m->quadphys[q] == lower ? 0.5 : 1) + 1e-12) nbad++;
    }
  }
  for (long l = 0; l < m->nline; l++) /* both contact surfaces on y = 0.5 */
    if ((m->linephys[l] == PhysTag(m, 1, "lower_top") || m->linephys[l] == PhysTag(m, 1, "upper_bottom")) && (fabs(m->xy[2 * m->line[2 * l] + 1] - 0.5) > 1e-12 || fabs(m->xy[2 * m->line[2 * l + 1] + 1] - 0.5) > 1e-12)) lines_ok = 0;
  printf("     quads %d: %ld cells, %ld in [0,0.25]^2, %ld in [0.5,1]x[0.25,0.5] (ratio %.1f, the field's %.1f); angles [%.1f, %.1f], Jacobian ratio >= %.3f\n", quads, m->nquad, ncorner, nfar, (double)ncorner / (double)(nfar ? nfar : 1), want, st->quality.min_angle, st->quality.max_angle, st->quality.min_jratio);
  CHECK(MinJacobian(m) > 0 && st->quality.min_jratio > 0.05, "field, quads %d: every cell a convex counter-clockwise quad", quads);
  CHECK(SameGroups(m, ref) && m->npoint == ref->npoint, "field, quads %d: the physical groups of patch_uniform.msh (%d)", quads, m->nphys);
  CHECK(nfar > 0 && (double)ncorner / (double)nfar > want / 2 && (double)ncorner / (double)nfar < 2 * want && want > 2.5, "field, quads %d: refined in the corner as the field asks (a uniform mesh: ratio 0.5)", quads);
  CHECK(!nbad && lines_ok && BodiesSeparate(m), "field, quads %d: nodes inside their body, contact lines on y = 0.5, no node shared by the bodies", quads);
}

/* in's .geo remeshed with sizes per cell, h[0] in the cells of body `body`
 * and h[1] in the others: the edges of curve[k] (of the first body, then the
 * other; those within `reach` of the origin) must have size h[k] to 30% */
static void CheckSizesPerBody(M2dRemeshInput *in, const char *body, const double h[2], const char *const curve[2], double reach, const char *where, const char *what)
{
  double  *hc, range[2][2] = {{1e300, 0}, {1e300, 0}};
  MshMesh  prev, m;
  char     err[1024];
  int      tag;
  if (Remesh(in, &prev, err)) return;
  tag = PhysTag(&prev, 2, body);
  hc  = (double *)malloc((size_t)prev.nquad * sizeof(double));
  for (long q = 0; q < prev.nquad; q++) hc[q] = h[prev.quadphys[q] == tag ? 0 : 1];
  in->prev = &prev, in->hcell = hc;
  if (!Remesh(in, &m, err)) {
    for (long l = 0; l < m.nline; l++) {
      const double *a = &m.xy[2 * m.line[2 * l]], *b = &m.xy[2 * m.line[2 * l + 1]];
      double        len = hypot(b[0] - a[0], b[1] - a[1]), *r = m.linephys[l] == PhysTag(&m, 1, curve[0]) ? range[0] : m.linephys[l] == PhysTag(&m, 1, curve[1]) ? range[1] : NULL;
      if (r && hypot(a[0], a[1]) < reach) r[0] = fmin(r[0], len), r[1] = fmax(r[1], len);
    }
    printf("     edges %s: %s %.4f to %.4f, %s %.4f to %.4f\n", where, curve[0], range[0][0], range[0][1], curve[1], range[1][0], range[1][1]);
    CHECK(range[0][0] > 0.7 * h[0] && range[0][1] < 1.3 * h[0] && range[1][0] > 0.7 * h[1] && range[1][1] < 1.3 * h[1], "sizes per cell and per body: %s", what);
    MshFree(&m);
  }
  free(hc);
  MshFree(&prev);
}

/* the patch with sizes per cell, 0.1 in the lower body and 0.025 in the upper:
 * on y = 0.5, which both bodies' cells touch, each contact surface takes its own
 * body's size */
static void TestPatchPerBody(const char *geo)
{
  const char *const curve[] = {"lower_top", "upper_bottom"};
  const double      h[]     = {0.1, 0.025};
  M2dRemeshInput    in      = {0};
  in.geo = geo;
  CheckSizesPerBody(&in, "lower", h, curve, INFINITY, "on y = 0.5", "each side of the shared line y = 0.5 its body's size");
}

/* the patch, sizes 0.01 at the corner (0,0) growing to 0.1 */
static void TestPatchField(void)
{
  char           geo[] = "/tmp/m2d_test_remesh_XXXXXX.geo", err[1024];
  M2dRemeshInput in    = {0};
  M2dRemeshStats st;
  MshMesh        prev, m, ref;
  M2dRemeshField  *f;
  double        *h, want;
  NewGeo(geo, patch_geo);
  in.geo = geo;
  if (Remesh(&in, &prev, err) || MshRead("../meshes/patch_uniform.msh", &ref, err, sizeof(err))) {
    CHECK(0, "patch without a field: %s", err);
    unlink(geo);
    return;
  }
  CHECK(prev.nquad == 85 && SameGroups(&prev, &ref), "patch without a field: its transfinite 10 x 5 and 7 x 5 quads, the groups of patch_uniform.msh");
  h = (double *)malloc((size_t)prev.nnode * sizeof(double));
  for (long n = 0; n < prev.nnode; n++) h[n] = fmin(0.1, 0.01 + 0.2 * hypot(prev.xy[2 * n], prev.xy[2 * n + 1]));
  in.prev = &prev, in.hnode = h;
  if (M2dRemeshFieldCreate(&prev, h, NULL, 0, 0, &f)) return;
  want = Cells(f, 0, 0.25, 0, 0.25) / Cells(f, 0.5, 1, 0.25, 0.5);
  M2dRemeshFieldDestroy(&f);
  for (int quads = M2D_QUADS_SUBDIVIDE; quads <= M2D_QUADS_SIMPLE; quads++) {
    in.quads = (M2dRemeshQuads)quads;
    if (M2dRemesh(&in, &m, &st, err, sizeof(err))) {
      CHECK(0, "patch with a field, quads %d: %s", quads, err);
      continue;
    }
    CheckPatch(&m, &ref, &st, quads, want);
    MshFree(&m);
  }
  in.geo = Path("meshes/patch_uniform.geo"); /* Transfinite, not guarded */
  CHECK(M2dRemesh(&in, &m, &st, err, sizeof(err)) && strstr(err, "patch_uniform.geo") && strstr(err, "m2d_size_field"), "a field on a .geo whose Transfinite is not guarded: '%s'", err);
  free(h);
  MshFree(&prev), MshFree(&ref);
  TestPatchPerBody(geo);
  unlink(geo);
}

/* Hertz from its coarse level -1 with a field 0.01 near the contact: the arc stays
 * on the circle, edges follow the field, each body sized by its own cells */
static void TestHertzField(void)
{
  const char    *names[] = {"level"};
  double         values[] = {-1}, *h, worst = 0, lmin = 1e300, lmax = 0, rmax = 0;
  M2dRemeshInput in = {0};
  MshMesh        prev, m;
  char           err[1024];
  int            arc, top;
  in.geo = Path("meshes/hertz.geo"), in.nnumber = 1, in.names = names, in.values = values;
  if (Remesh(&in, &prev, err)) return;
  h = (double *)malloc((size_t)prev.nnode * sizeof(double));
  for (long n = 0; n < prev.nnode; n++) h[n] = 0.01 + 0.3 * fmax(0, hypot(prev.xy[2 * n], prev.xy[2 * n + 1]) - 0.1);
  in.prev = &prev, in.hnode = h;
  if (Remesh(&in, &m, err)) goto done;
  arc = PhysTag(&m, 1, "cylinder_arc"), top = PhysTag(&m, 1, "block_top");
  for (long l = 0; l < m.nline; l++) {
    const double *a = &m.xy[2 * m.line[2 * l]], *b = &m.xy[2 * m.line[2 * l + 1]];
    double        len = hypot(b[0] - a[0], b[1] - a[1]), r = hypot(a[0] + b[0], a[1] + b[1]) / 2;
    if (m.linephys[l] == arc) worst = fmax(worst, fmax(fabs(hypot(a[0], a[1] - 1) - 1), fabs(hypot(b[0], b[1] - 1) - 1)));
    if (m.linephys[l] == top) worst = fmax(worst, fmax(fabs(a[1]), fabs(b[1])));
    if ((m.linephys[l] == arc || m.linephys[l] == top) && r < 0.1) lmin = fmin(lmin, len), lmax = fmax(lmax, len), rmax = fmax(rmax, len / (0.01 + 0.3 * fmax(0, r - 0.1)));
  }
  printf("     Hertz: %ld -> %ld nodes; contact edges within 0.1 of the origin: %.4f to %.4f\n", prev.nnode, m.nnode, lmin, lmax);
  CHECK(worst < 1e-10, "cylinder_arc nodes on the circle of radius 1 around (0,1), block_top on y = 0 (worst %.1e)", worst);
  CHECK(lmin > 0.5 * 0.01 && lmax < 1.5 * 0.01, "contact edges near the origin follow the field's 0.01");
  CHECK(MinJacobian(&m) > 0 && BodiesSeparate(&m) && PhysTag(&m, 2, "cylinder") > 0 && PhysTag(&m, 1, "block_bottom") > 0 && PhysTag(&m, 1, "cylinder_top") > 0, "convex counter-clockwise quads, the bodies separate, groups kept");
  MshFree(&m);
done:
  free(h);
  MshFree(&prev);
}

/* Hertz with sizes per cell, 0.02 in the cylinder and 0.08 in the block: where
 * the bodies touch each contact surface takes its own body's size */
static void TestHertzPerBody(void)
{
  const char       *names[] = {"level"};
  const char *const curve[] = {"cylinder_arc", "block_top"};
  const double      h[]     = {0.02, 0.08};
  double            values[] = {-1};
  M2dRemeshInput    in       = {0};
  in.geo = Path("meshes/hertz.geo"), in.nnumber = 1, in.names = names, in.values = values;
  CheckSizesPerBody(&in, "cylinder", h, curve, 0.3, "within 0.3 of the contact point", "each contact surface its body's size up to the contact point");
}

/* two unit quads side by side, bodies 1 and 2, sizes per node */
static void TestSizeField(void)
{
  double        xy[12] = {0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1}, hn[6] = {1, 2, 3, 4, 5, 6}, hc[2] = {0.5, 0.25};
  long          quad[8] = {0, 1, 4, 3, 1, 2, 5, 4};
  int           phys[2] = {1, 2};
  MshMesh       m = {0};
  M2dRemeshField *f;
  m.nnode = 6, m.xy = xy, m.nquad = 2, m.quad = quad, m.quadphys = phys;
  if (M2dRemeshFieldCreate(&m, hn, NULL, 0, 0, &f)) return;
  CHECK(M2dRemeshFieldEval(f, -1, 0, 0) == 1 && M2dRemeshFieldEval(f, -1, 2, 1) == 6 && fabs(M2dRemeshFieldEval(f, -1, 0.5, 0) - 1.5) < 1e-14, "node values, linear along an edge");
  /* in triangle (0,1,4): h = 1 + x + 3y */
  CHECK(fabs(M2dRemeshFieldEval(f, -1, 0.75, 0.25) - 2.5) < 1e-14 && fabs(M2dRemeshFieldEval(f, 1, 0.75, 0.25) - 2.5) < 1e-14, "linear inside a quad's triangle");
  CHECK(fabs(M2dRemeshFieldEval(f, -1, 0.5, -0.3) - 1.5) < 1e-14 && fabs(M2dRemeshFieldEval(f, -1, 3, 2) - 6) < 1e-14, "outside: the value at the closest boundary point");
  CHECK(fabs(M2dRemeshFieldEval(f, 1, 1.5, 0.5) - 3.5) < 1e-14 && M2dRemeshFieldEval(f, 3, 0.5, 0.5) == -1, "restricted to body 1: its cell's closest point; an unknown body: -1");
  M2dRemeshFieldDestroy(&f);
  if (M2dRemeshFieldCreate(&m, NULL, hc, 0.3, 0, &f)) return;
  CHECK(M2dRemeshFieldEval(f, -1, 0.5, 0.5) == 0.5 && M2dRemeshFieldEval(f, -1, 1.5, 0.5) == 0.3, "sizes per cell, clamped below");
  M2dRemeshFieldDestroy(&f);
}

/* the entries of directory d whose names start with prefix */
static int Entries(const char *d, const char *prefix, char *first, size_t len)
{
  DIR           *dir = opendir(d);
  struct dirent *e;
  int            n = 0;
  while (dir && (e = readdir(dir)))
    if (!strncmp(e->d_name, prefix, strlen(prefix)) && n++ == 0 && first) snprintf(first, len, "%s/%s", d, e->d_name);
  if (dir) closedir(dir);
  return n;
}

/* The run's directory in TMPDIR (made by the first call: TMPDIR is tried
 * first), a crash of gmsh, gmsh's memory bound, and the sweep of the
 * directories of runs that are gone. */
static void TestProcess(const char *tmp)
{
  char           bad[4200], geo[] = "/tmp/m2d_test_remesh_XXXXXX.geo", err[1024], dir[8400], dead[4200], live[4200];
  M2dRemeshInput in = {0};
  MshMesh        m;
  int            fd;
  snprintf(bad, sizeof(bad), "%s/missing", tmp);
  setenv("TMPDIR", bad, 1);
  in.geo = Path("meshes/patch_uniform.geo");
  CHECK(M2dRemesh(&in, &m, NULL, err, sizeof(err)) && strstr(err, bad) && strstr(err, "TMPDIR") && strstr(err, "No such file"), "TMPDIR missing: '%s'", err);
  if (geteuid()) { /* (root writes in it anyway) */
    snprintf(bad, sizeof(bad), "%s/readonly", tmp);
    mkdir(bad, 0500);
    setenv("TMPDIR", bad, 1);
    CHECK(M2dRemesh(&in, &m, NULL, err, sizeof(err)) && strstr(err, bad) && strstr(err, "Permission denied"), "TMPDIR read-only: '%s'", err);
    rmdir(bad);
  } else printf("skip TMPDIR read-only: running as root\n");
  setenv("TMPDIR", tmp, 1);
  CHECK(!Remesh(&in, &m, err) && Entries(tmp, M2D_REMESH_DIR_PREFIX, dir, sizeof(dir)) == 1 && Entries(dir, "", NULL, 0) == 2, "meshed with this run's directory %s, empty between calls", dir);
  MshFree(&m);
  NewGeo(geo, "Mesh.Algorithm = 8; Mesh.RecombineAll = 1;\n" /* gmsh 4.8.4's quad algorithm: a segmentation fault */
              "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};\n"
              "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
              "Physical Surface(\"square\", 7) = {1};\n");
  in.geo = geo;
  CHECK(M2dRemesh(&in, &m, NULL, err, sizeof(err)) && strstr(err, geo) && strstr(err, "crashed") && strstr(err, "SIGSEGV") && !strchr(err, '\n'), "gmsh's crash: '%s'", err);
  WriteGeo(geo, "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};\n"
                "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
                "Transfinite Curve{1, 3} = 1e9; Transfinite Curve{2, 4} = 2; Transfinite Surface{1}; Recombine Surface{1};\nPhysical Surface(\"square\", 7) = {1};\n");
  in.max_nodes = 500;
  CHECK(M2dRemesh(&in, &m, NULL, err, sizeof(err)) && strstr(err, geo) && strstr(err, "MB allowed for a mesh of at most 500 nodes"), "1e9 cells asked, memory bounded by 500 nodes: '%s'", err);
  in.max_nodes = 0;
  unlink(geo);
  in.geo = Path("meshes/patch_uniform.geo");
  CHECK(!Remesh(&in, &m, err) && m.nquad == 85 && Entries(tmp, M2D_REMESH_DIR_PREFIX, NULL, 0) == 1 && Entries(dir, "", NULL, 0) == 2, "after those, gmsh still meshes: %ld quads; one directory, empty", m.nquad);
  MshFree(&m);
  /* a dead run's directory (nobody holds its lock) and a live one's (a lock held) */
  snprintf(dead, sizeof(dead), "%s/" M2D_REMESH_DIR_PREFIX "dead00", tmp);
  snprintf(live, sizeof(live), "%s/" M2D_REMESH_DIR_PREFIX "live00", tmp);
  mkdir(dead, 0700), mkdir(live, 0700);
  snprintf(bad, sizeof(bad), "%s/wrapper.geo", dead);
  WriteGeo(bad, "// left by a SIGKILL\n");
  fd = open(live, O_RDONLY | O_DIRECTORY);
  CHECK(fd >= 0 && !flock(fd, LOCK_EX | LOCK_NB), "a live run's lock held");
  M2dTempSweepDirs(tmp, M2D_REMESH_DIR_PREFIX);
  CHECK(access(dead, F_OK) && !access(live, F_OK) && !access(dir, F_OK), "the sweep removes the dead run's directory and keeps the live ones (another's and this run's)");
  close(fd);
  M2dTempSweepDirs(tmp, M2D_REMESH_DIR_PREFIX);
  CHECK(access(live, F_OK) && !access(dir, F_OK), "once its lock is gone, that one too");
}
static void TestQuality(void)
{
  double         xy[8] = {0, 0, 2, 0, 1, 1, 0, 1};
  long           quad[4] = {0, 1, 2, 3};
  int            phys[1] = {1};
  MshMesh        m = {0};
  M2dQuadQuality q;
  m.nnode = 4, m.xy = xy, m.nquad = 1, m.quad = quad, m.quadphys = phys;
  M2dQuadQualityCompute(&m, &q);
  /* corners: 90, 45, 135, 90; Jacobians 2, 2, 1, 1 */
  CHECK(fabs(q.min_angle - 45) < 1e-12 && fabs(q.max_angle - 135) < 1e-12 && fabs(q.min_jratio - 0.5) < 1e-12 && q.nbad == 0, "quality of a trapezoid: angles [%g, %g], Jacobian ratio %g", q.min_angle, q.max_angle, q.min_jratio);
}

static char tmp[] = "/tmp/m2d_test_tmpdir_XXXXXX"; /* this test's TMPDIR */

static void RemoveTmp(void) /* after the run's directory went (atexit: registered first, runs last) */
{
  rmdir(tmp);
}

int main(void)
{
  char *slash;
  snprintf(src, sizeof(src), "%s", __FILE__);
  if ((slash = strrchr(src, '/'))) *slash = 0; /* tests/ */
  if ((slash = strrchr(src, '/'))) *slash = 0;
  else snprintf(src, sizeof(src), "..");
  if (!mkdtemp(tmp) || atexit(RemoveTmp)) return 1;
  TestProcess(tmp); /* first: the run's directory is made by the first call */
  TestQuality();
  TestSizeField();
  TestOwnMesh();
  TestParameters();
  TestErrors();
  TestPatchField();
  TestHertzField();
  TestHertzPerBody();
  printf("%s\n", failures ? "FAILED" : "all passed");
  return failures ? 1 : 0;
}
