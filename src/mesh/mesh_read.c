/* mesh_read.c - rank 0 merges the sources (one MshMesh per .msh file, or filled
 * in memory) into one cell list (see mesh_impl.h): physical names become groups,
 * physical surfaces bodies; clockwise quads are reoriented (gmsh writes them
 * whenever a curve loop runs clockwise) and every quad must then be convex with
 * a positive area. Plain C returns: 0, or 1 with one line in ri->err. */
#include "mesh_impl.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int FindGroup(const MeshReadInfo *ri, const char *name)
{
  for (int i = 0; i < ri->ngroup; i++)
    if (!strcmp(ri->group[i], name)) return i;
  return -1;
}

/* every physical name of every source becomes a group; a name used twice is refused */
static int CollectGroups(const MeshSources *src, MeshReadInfo *ri)
{
  int gsrc[M2D_MAX_GROUPS];
  for (int f = 0; f < src->nmsh; f++) {
    const MshMesh *msh = &src->msh[f];
    for (int i = 0; i < msh->nphys; i++) {
      int g = FindGroup(ri, msh->phys[i].name);
      if (g >= 0) {
        if (gsrc[g] != f) snprintf(ri->err, sizeof(ri->err), "physical group '%s' is defined in both %s and %s: give the groups of the two bodies different names", msh->phys[i].name, src->label[gsrc[g]], src->label[f]);
        else snprintf(ri->err, sizeof(ri->err), "%s: physical name '%s' is used for two groups", src->label[f], msh->phys[i].name);
        return 1;
      }
      if (ri->ngroup >= M2D_MAX_GROUPS) {
        snprintf(ri->err, sizeof(ri->err), "%s: more than %d physical groups", src->label[f], M2D_MAX_GROUPS);
        return 1;
      }
      snprintf(ri->group[ri->ngroup], M2D_NAME_LEN, "%s", msh->phys[i].name);
      gsrc[ri->ngroup]           = f;
      ri->groupdim[ri->ngroup++] = msh->phys[i].dim;
    }
  }
  return 0;
}

/* the bodies: those -bodies names (each a physical surface), or every physical surface */
static int CollectBodies(const M2dScene *s, const MeshSources *src, MeshReadInfo *ri)
{
  if (s->nbody > 0) {
    ri->nbody = s->nbody;
    for (int b = 0; b < s->nbody; b++) {
      int g = FindGroup(ri, s->body[b].name);
      if (g < 0 || ri->groupdim[g] != 2) {
        snprintf(ri->err, sizeof(ri->err), "option -bodies: mesh file(s) %s have no physical surface '%s'", src->all, s->body[b].name);
        return 1;
      }
      snprintf(ri->body[b], M2D_NAME_LEN, "%s", s->body[b].name);
    }
    return 0;
  }
  for (int f = 0; f < src->nmsh; f++)
    for (int i = 0; i < src->msh[f].nphys; i++)
      if (src->msh[f].phys[i].dim == 2) {
        if (ri->nbody >= M2D_MAX_BODIES) {
          snprintf(ri->err, sizeof(ri->err), "%s: more than %d physical surfaces (bodies)", src->label[f], M2D_MAX_BODIES);
          return 1;
        }
        snprintf(ri->body[ri->nbody++], M2D_NAME_LEN, "%s", src->msh[f].phys[i].name);
      }
  if (ri->nbody == 0) {
    snprintf(ri->err, sizeof(ri->err), "%s: no physical surface names a body (add Physical Surface(\"name\") in the .geo)", src->label[0]);
    return 1;
  }
  return 0;
}

/* Jacobian determinant of the bilinear map at the four corners: all must be > 0
 * for a valid (convex, counter-clockwise, non-degenerate) Q4. */
static double MinCornerJacobian(const double xy[8])
{
  double jmin = 1e300;
  for (int k = 0; k < 4; k++) {
    const double *p = &xy[2 * k], *n = &xy[2 * ((k + 1) % 4)], *q = &xy[2 * ((k + 3) % 4)];
    double        j = (n[0] - p[0]) * (q[1] - p[1]) - (n[1] - p[1]) * (q[0] - p[0]);
    if (j < jmin) jmin = j;
  }
  return jmin;
}

/* What double precision can vouch for (the answer is checked to 1e-6, verify.h),
 * measured on a 4 x 4 block under uniform compression:
 *  - a cell of aspect ratio A (longest side^2 / area) makes the stiffness lose
 *    about eps A^2 / 2 of the stresses (A = 1e5: 1.1e-6, 1e7: 2.4e-2, 1e8: 0.46),
 *    while the residual stays small (a backward-stable solve of an
 *    ill-conditioned matrix): refused above eps A^2 = 1e-6 (A = 6.7e4);
 *  - a cell of width h at a distance X from the origin keeps its shape only to
 *    eps X / h (X/h = 4e10: stress errors 3.9e-6): refused above 1e-6. */
#define M2D_GEOMETRY_ROUNDOFF 1e-6

static int Conditioning(const MeshSources *src, MeshReadInfo *ri, int f, long tag, const double xy[8], double a)
{
  double lmax = 0, xmax = 0, aspect, width, eps = PETSC_MACHINE_EPSILON;
  for (int k = 0; k < 4; k++) {
    const double *p = &xy[2 * k], *n = &xy[2 * ((k + 1) % 4)];
    lmax = fmax(lmax, hypot(n[0] - p[0], n[1] - p[1]));
    xmax = fmax(xmax, fmax(fabs(p[0]), fabs(p[1])));
  }
  aspect = lmax * lmax / a;
  width  = a / lmax;
  if (eps * aspect * aspect > M2D_GEOMETRY_ROUNDOFF) {
    snprintf(ri->err, sizeof(ri->err), "%s: quadrilateral %ld is too thin (aspect ratio %.2g: side %g, width %g): round-off in its stiffness alone puts stress errors of about %.1e of the load, beyond the 1e-06 the answer is checked to; remesh with aspect ratios below %.0e", src->label[f], tag, aspect, lmax, width, 0.5 * eps * aspect * aspect, sqrt(M2D_GEOMETRY_ROUNDOFF / eps));
    return 1;
  }
  if (eps * xmax / width > M2D_GEOMETRY_ROUNDOFF) {
    snprintf(ri->err, sizeof(ri->err), "%s: quadrilateral %ld lies %g from the origin but is only %g wide: double precision keeps its shape to %.0e of its width, beyond the 1e-06 the answer is checked to; move the mesh near the origin (gmsh: Translate)", src->label[f], tag, xmax, width, eps * xmax / width);
    return 1;
  }
  return 0;
}

/* Quad q of source f: its body, its nodes counter-clockwise in nodes[4] (the
 * file's order reversed if the area is negative: *flipped), checked. */
static int OneQuad(const M2dScene *s, const MeshSources *src, MeshReadInfo *ri, int f, long q, int *body, long nodes[4], int *flipped)
{
  const MshMesh *msh   = &src->msh[f];
  const char    *pname = MshPhysicalName(msh, 2, msh->quadphys[q]);
  long           tag   = msh->quadtag ? msh->quadtag[q] : q + 1;
  double         xy[8], a, jmin;

  *body = -1;
  for (int k = 0; pname && k < ri->nbody; k++)
    if (!strcmp(ri->body[k], pname)) *body = k;
  if (*body < 0) {
    snprintf(ri->err, sizeof(ri->err), "%s: quadrilateral %ld lies in %s%s%s, which is not a body (see -bodies)", src->label[f], tag, pname ? "physical surface '" : "no physical surface", pname ? pname : "", pname ? "'" : "");
    return 1;
  }
  for (int k = 0; k < 4; k++) {
    nodes[k] = msh->quad[4 * q + k];
    if (nodes[k] < 0 || nodes[k] >= msh->nnode) {
      snprintf(ri->err, sizeof(ri->err), "%s: quadrilateral %ld uses node index %ld, outside 0..%ld", src->label[f], tag, nodes[k], msh->nnode - 1);
      return 1;
    }
    for (int l = 0; l < k; l++)
      if (nodes[l] == nodes[k]) {
        snprintf(ri->err, sizeof(ri->err), "%s: quadrilateral %ld repeats node %ld", src->label[f], tag, nodes[k]);
        return 1;
      }
  }
  /* area from the diagonals; negative: listed clockwise */
  a        = 0.5 * ((msh->xy[2 * nodes[0]] - msh->xy[2 * nodes[2]]) * (msh->xy[2 * nodes[1] + 1] - msh->xy[2 * nodes[3] + 1]) - (msh->xy[2 * nodes[1]] - msh->xy[2 * nodes[3]]) * (msh->xy[2 * nodes[0] + 1] - msh->xy[2 * nodes[2] + 1]));
  if (a == 0) a = 0; /* no "-0" in messages */
  *flipped = a < 0;
  if (*flipped) {
    long t   = nodes[1];
    nodes[1] = nodes[3];
    nodes[3] = t;
    a        = -a;
  }
  for (int k = 0; k < 4; k++) xy[2 * k] = s->mesh_scale * msh->xy[2 * nodes[k]], xy[2 * k + 1] = s->mesh_scale * msh->xy[2 * nodes[k] + 1];
  a *= s->mesh_scale * s->mesh_scale;
  jmin = MinCornerJacobian(xy);
  if (!(jmin > 1e-12 * a) || !(a > 0)) {
    snprintf(ri->err, sizeof(ri->err), "%s: quadrilateral %ld is %s (area %g, smallest corner Jacobian %g)", src->label[f], tag, a == 0 ? "of zero area" : "degenerate or non-convex", a, jmin);
    return 1;
  }
  return Conditioning(src, ri, f, tag, xy, a);
}

/* the cells of every source, counter-clockwise, with the vertices they use */
static int MergeCells(const M2dScene *s, const MeshSources *src, MeshReadInfo *ri, MeshLists *L)
{
  long c = 0;
  for (int f = 0; f < src->nmsh; f++)
    for (long q = 0; q < src->msh[f].nquad; q++, c++) {
      long nodes[4];
      int  b, flipped;
      if (OneQuad(s, src, ri, f, q, &b, nodes, &flipped)) return 1;
      ri->nflip[b] += flipped;
      L->cellbody[c] = b;
      L->celltag[c]  = src->msh[f].quadtag ? src->msh[f].quadtag[q] : q + 1;
      L->cellsrc[c]  = f;
      for (int k = 0; k < 4; k++) {
        long g = L->nodeoff[f] + nodes[k];
        if (L->nodemap[g] < 0) L->nodemap[g] = L->nv++;
        L->cells[4 * c + k] = (PetscInt)L->nodemap[g];
      }
    }
  return 0;
}

int MeshMerge(const M2dScene *s, const MeshSources *src, MeshReadInfo *ri, MeshLists *L)
{
  long nquad = 0;

  memset(L, 0, sizeof(*L));
  if (CollectGroups(src, ri) || CollectBodies(s, src, ri)) return 1;
  L->nodeoff = (long *)malloc((size_t)(src->nmsh + 1) * sizeof(long));
  if (!L->nodeoff) goto oom;
  L->nodeoff[0] = 0;
  for (int f = 0; f < src->nmsh; f++) {
    L->nodeoff[f + 1] = L->nodeoff[f] + src->msh[f].nnode;
    nquad += src->msh[f].nquad;
  }
  L->nc       = (PetscInt)nquad;
  L->nodemap  = (long *)malloc((size_t)(L->nodeoff[src->nmsh] + 1) * sizeof(long));
  L->cells    = (PetscInt *)malloc((size_t)(4 * nquad + 1) * sizeof(PetscInt));
  L->cellbody = (PetscInt *)malloc((size_t)(nquad + 1) * sizeof(PetscInt));
  L->celltag  = (long *)malloc((size_t)(nquad + 1) * sizeof(long));
  L->cellsrc  = (int *)malloc((size_t)(nquad + 1) * sizeof(int));
  if (!L->nodemap || !L->cells || !L->cellbody || !L->celltag || !L->cellsrc) goto oom;
  for (long i = 0; i < L->nodeoff[src->nmsh]; i++) L->nodemap[i] = -1;
  if (MergeCells(s, src, ri, L)) return 1;
  L->coords = (PetscReal *)malloc((size_t)(2 * L->nv + 1) * sizeof(PetscReal));
  if (!L->coords) goto oom;
  for (int f = 0; f < src->nmsh; f++)
    for (long n = 0; n < src->msh[f].nnode; n++) {
      long g = L->nodemap[L->nodeoff[f] + n];
      if (g < 0) continue;
      L->coords[2 * g]     = s->mesh_scale * src->msh[f].xy[2 * n];
      L->coords[2 * g + 1] = s->mesh_scale * src->msh[f].xy[2 * n + 1];
    }
  return 0;
oom:
  snprintf(ri->err, sizeof(ri->err), "out of memory merging the meshes %s", src->all);
  return 1;
}

void MeshListsFree(MeshLists *L)
{
  free(L->cells);
  free(L->coords);
  free(L->cellbody);
  free(L->celltag);
  free(L->cellsrc);
  free(L->nodemap);
  free(L->nodeoff);
  free(L->ent);
  memset(L, 0, sizeof(*L));
}
