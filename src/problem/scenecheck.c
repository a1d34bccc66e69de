/* scenecheck.c - the scene checked against its mesh (see scenecheck.h). */
#include "scenecheck.h"
#include "surface.h"
#include <string.h>

/* a physical curve `name` with an edge inside the mesh (of two cells, found
 * when the mesh was read: M2dMesh.inner) is refused: one line naming
 * `option`, the curve, the body (or the two bodies) and the edge, then `why`
 * (the boundary's role). Not collective (the same on every rank). */
static PetscErrorCode CheckOnBoundary(const M2dMesh *m, const M2dScene *s, const char *name, const char *option, const char *why)
{
  PetscFunctionBeginUser;
  for (PetscInt g = 0; g < m->ngroup; g++) {
    const M2dGroupInner *in = &m->inner[g];
    const char          *b[2];
    char                 where[2 * M2D_NAME_LEN + 64];
    if (strcmp(m->group[g], name) || !in->n) continue;
    for (int k = 0; k < 2; k++) b[k] = in->body[k] >= 0 && in->body[k] < s->nbody ? s->body[in->body[k]].name : "?";
    if (in->body[0] == in->body[1]) PetscCall(PetscSNPrintf(where, sizeof(where), "inside body '%s'", b[0]));
    else PetscCall(PetscSNPrintf(where, sizeof(where), "between bodies '%s' and '%s', which share its nodes", b[0], b[1]));
    SETERRQ(PetscObjectComm((PetscObject)m->dm), PETSC_ERR_USER_INPUT, "option %s: physical curve '%s' has %" PetscInt_FMT " edge%s %s (the first from (%g, %g) to (%g, %g), between two cells): %s", option, name, in->n, in->n > 1 ? "s" : "", where, (double)in->xy[0], (double)in->xy[1], (double)in->xy[2], (double)in->xy[3], why);
  }
  PetscFunctionReturn(0);
}

/* a group the option names: it exists, has dimension `dim` (1: a curve; 2:
 * up to a curve: a point or a curve) and holds elements */
static PetscErrorCode CheckGroup(MPI_Comm comm, const M2dMesh *m, const char *group, const char *opt, PetscInt dim)
{
  PetscInt d = MeshGroupDim(m, group), n;

  PetscFunctionBeginUser;
  PetscCheck(d >= 0, comm, PETSC_ERR_USER_INPUT, "option %s: mesh file(s) %s have no physical group '%s'", opt, m->files, group);
  PetscCheck(dim != 1 || d == 1, comm, PETSC_ERR_USER_INPUT, "option %s: physical group '%s' is not a curve", opt, group);
  PetscCheck(d <= 1, comm, PETSC_ERR_USER_INPUT, "option %s: physical group '%s' is a surface; name a curve or a point", opt, group);
  PetscCall(MeshGroupSize(m, group, opt, &n)); /* a group that holds nothing would silently do nothing */
  PetscCheck(n > 0, comm, PETSC_ERR_USER_INPUT, "option %s: physical group '%s' of mesh file(s) %s has no elements", opt, group, m->files);
  PetscFunctionReturn(0);
}

/* one side of a contact pair: a boundary curve on one body; its body in
 * *body. Corners are fine: the mortar rows take each edge's own normal there
 * (mortar.h) */
static PetscErrorCode CheckContactSide(MPI_Comm comm, const M2dScene *s, const M2dMesh *m, const char *group, const char *opt, PetscInt *body)
{
  M2dSurface sf;

  PetscFunctionBeginUser;
  PetscCall(CheckGroup(comm, m, group, opt, 1));
  PetscCall(CheckOnBoundary(m, s, group, opt, "a contact surface is part of the boundary"));
  PetscCall(SurfaceGather(m, group, opt, &sf));
  *body = sf.body;
  PetscCall(SurfaceDestroy(&sf));
  PetscCheck(*body >= 0, comm, PETSC_ERR_USER_INPUT, "option %s: physical curve '%s' lies on more than one body", opt, group);
  PetscFunctionReturn(0);
}

/* a non-mortar edge: its two nodes (u_x dofs, the smaller first) and midpoint */
typedef struct {
  PetscInt  a, b;
  PetscReal x, y;
} EdgeKey;

static int CmpEdgeKey(const void *p, const void *q)
{
  const EdgeKey *e = (const EdgeKey *)p, *f = (const EdgeKey *)q;
  if (e->a != f->a) return e->a < f->a ? -1 : 1;
  return (e->b > f->b) - (e->b < f->b);
}

/* pair p's non-mortar edges, sorted */
static PetscErrorCode EdgeKeys(const M2dMesh *m, const M2dPair *p, PetscInt *n, EdgeKey **key)
{
  M2dSurface sf;

  PetscFunctionBeginUser;
  PetscCall(SurfaceGather(m, p->nm, p->opt_nm, &sf));
  *n = sf.nedge;
  PetscCall(PetscMalloc1(sf.nedge + 1, key));
  for (PetscInt e = 0; e < sf.nedge; e++) {
    PetscInt i = sf.edge[2 * e], j = sf.edge[2 * e + 1];
    (*key)[e]  = (EdgeKey){PetscMin(sf.gdof[i], sf.gdof[j]), PetscMax(sf.gdof[i], sf.gdof[j]), 0.5 * (sf.x[2 * i] + sf.x[2 * j]), 0.5 * (sf.x[2 * i + 1] + sf.x[2 * j + 1])};
  }
  qsort(*key, (size_t)sf.nedge, sizeof(EdgeKey), CmpEdgeKey);
  PetscCall(SurfaceDestroy(&sf));
  PetscFunctionReturn(0);
}

/* an edge is the non-mortar side of at most one pair: in two, its nodes carry
 * two multipliers each for one condition (singular; a pair's curve and a part
 * of it named as another pair's gave four different wrong causes) */
static PetscErrorCode CheckSharedNonMortar(MPI_Comm comm, const M2dScene *s, const M2dMesh *m)
{
  PetscInt *n, shared = 0, first[2] = {-1, -1};
  EdgeKey **key;
  EdgeKey   at = {0, 0, 0, 0};

  PetscFunctionBeginUser;
  if (s->npair < 2) PetscFunctionReturn(0);
  PetscCall(PetscCalloc2(s->npair, &n, s->npair, &key));
  for (PetscInt k = 0; k < s->npair; k++) PetscCall(EdgeKeys(m, &s->pair[k], &n[k], &key[k]));
  for (PetscInt k = 0; k < s->npair && !shared; k++)
    for (PetscInt l = k + 1; l < s->npair && !shared; l++)
      for (PetscInt i = 0, j = 0; i < n[k] && j < n[l];) {
        int c = CmpEdgeKey(&key[k][i], &key[l][j]);
        if (c < 0) i++;
        else if (c > 0) j++;
        else {
          if (!shared) at = key[k][i], first[0] = k, first[1] = l;
          shared++, i++, j++;
        }
      }
  for (PetscInt q = 0; q < s->npair; q++) PetscCall(PetscFree(key[q]));
  PetscCall(PetscFree2(n, key));
  PetscCheck(!shared, comm, PETSC_ERR_USER_INPUT, "%s and %s share %" PetscInt_FMT " non-mortar edge%s (one at (%g, %g)): its nodes would carry two multipliers for one contact; give each edge to one pair (a non-mortar curve in one pair only)", s->pair[first[0]].what, s->pair[first[1]].what, shared, shared > 1 ? "s" : "", (double)at.x, (double)at.y);
  PetscFunctionReturn(0);
}

PetscErrorCode SceneCheckMesh(MPI_Comm comm, const M2dScene *s, const M2dMesh *m)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < s->ndir; i++) {
    const M2dDirichlet *bc = &s->dir[i];
    PetscCall(CheckGroup(comm, m, bc->group, "-dirichlet", 2));
    /* a point has no normal: G:n and G:t would hold nothing */
    PetscCheck(MeshGroupDim(m, bc->group) == 1 || bc->frame == M2D_BC_XY, comm, PETSC_ERR_USER_INPUT, "option -dirichlet: '%s:%s' needs a curve (its normal), and physical group '%s' is a point; give x, y or xy", bc->group, bc->frame == M2D_BC_NORMAL ? "n" : "t", bc->group);
    if (bc->frame != M2D_BC_XY) PetscCall(CheckOnBoundary(m, s, bc->group, "-dirichlet", "u.n and u.t are taken along the boundary's outward normal"));
  }
  for (PetscInt i = 0; i < s->nload; i++) {
    const char *opt = s->load[i].is_pressure ? "-pressure" : "-traction";
    PetscCall(CheckGroup(comm, m, s->load[i].group, opt, 1));
    PetscCall(CheckOnBoundary(m, s, s->load[i].group, opt, "a load acts on the boundary"));
  }
  for (PetscInt k = 0; k < s->npair; k++) {
    const M2dPair *p = &s->pair[k];
    PetscInt             bnm, bm;
    PetscCall(CheckContactSide(comm, s, m, p->nm, p->opt_nm, &bnm));
    PetscCall(CheckContactSide(comm, s, m, p->m, p->opt_m, &bm));
    PetscCheck(bnm != bm, comm, PETSC_ERR_USER_INPUT, "%s: both sides lie on body '%s' (a pair joins two bodies)", p->what, s->body[bnm].name);
  }
  PetscCall(CheckSharedNonMortar(comm, s, m));
  PetscFunctionReturn(0);
}
