/* m2d_remesh - the remeshing engine (remesh.h) from the command line, to measure it
 * and to make meshes from a size field without the solver:
 *   m2d_remesh GEO [-setnumber NAME VALUE]... [-o OUT.msh] [-quads subdivide|fullquad|blossom|simple]
 *              [-from PREV.msh -radial HFINE R0 RATIO [CX CY]] [-repeat N] [-v]
 * -radial gives the size at the nodes of PREV: HFINE within R0 of (CX, CY) (default
 * the origin), growing by RATIO per element beyond: h = HFINE + (RATIO - 1)(r - R0);
 * several -radial: the smallest of their sizes.
 * Prints one line: nodes, dofs (2 per node), quads, seconds, quad shapes. */
#include "msh.h"
#include "remesh.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAXNUM 32
#define MAXRAD 8

static int Usage(void)
{
  fprintf(stderr, "usage: m2d_remesh GEO [-setnumber NAME VALUE]... [-o OUT.msh] [-quads subdivide|fullquad|blossom|simple] [-from PREV.msh -radial HFINE R0 RATIO [CX CY]] [-repeat N] [-v]\n");
  return 2;
}

int main(int argc, char **argv)
{
  M2dRemeshInput in;
  M2dRemeshStats st;
  MshMesh        prev, out;
  const char    *names[MAXNUM], *from = NULL;
  double         values[MAXNUM], radial[MAXRAD][5], *h = NULL;
  int            nrad = 0, repeat = 1, rc = 0;
  char           err[2048];

  if (argc < 2) return Usage();
  memset(&in, 0, sizeof(in));
  memset(&prev, 0, sizeof(prev));
  in.geo    = argv[1];
  in.names  = names;
  in.values = values;
  for (int i = 2; i < argc; i++) {
    if (!strcmp(argv[i], "-setnumber") && i + 2 < argc && in.nnumber < MAXNUM) {
      names[in.nnumber]    = argv[i + 1];
      values[in.nnumber++] = atof(argv[i + 2]);
      i += 2;
    } else if (!strcmp(argv[i], "-o") && i + 1 < argc) in.write_msh = argv[++i];
    else if (!strcmp(argv[i], "-quads") && i + 1 < argc) {
      i++;
      if (!strcmp(argv[i], "subdivide")) in.quads = M2D_QUADS_SUBDIVIDE;
      else if (!strcmp(argv[i], "fullquad")) in.quads = M2D_QUADS_FULLQUAD;
      else if (!strcmp(argv[i], "blossom")) in.quads = M2D_QUADS_BLOSSOM;
      else if (!strcmp(argv[i], "simple")) in.quads = M2D_QUADS_SIMPLE;
      else return Usage();
    } else if (!strcmp(argv[i], "-from") && i + 1 < argc) from = argv[++i];
    else if (!strcmp(argv[i], "-radial") && i + 3 < argc && nrad < MAXRAD) {
      int k;
      memset(radial[nrad], 0, sizeof(radial[nrad]));
      for (k = 0; k < 5 && i + 1 < argc && (argv[i + 1][0] != '-' || (argv[i + 1][1] >= '0' && argv[i + 1][1] <= '9')); k++) radial[nrad][k] = atof(argv[++i]);
      if (k < 3) return Usage();
      nrad++;
    } else if (!strcmp(argv[i], "-repeat") && i + 1 < argc) repeat = atoi(argv[++i]);
    else if (!strcmp(argv[i], "-v")) in.verbose = 1;
    else return Usage();
  }
  if (!!from != (nrad > 0)) return Usage();
  if (from) {
    if (MshRead(from, &prev, err, sizeof(err))) {
      fprintf(stderr, "m2d_remesh: error: %s\n", err);
      return 1;
    }
    h = (double *)malloc((size_t)prev.nnode * sizeof(double));
    for (long n = 0; n < prev.nnode; n++) {
      h[n] = 1e300;
      for (int k = 0; k < nrad; k++) {
        double r = hypot(prev.xy[2 * n] - radial[k][3], prev.xy[2 * n + 1] - radial[k][4]);
        h[n]     = fmin(h[n], radial[k][0] + (radial[k][2] - 1) * (r > radial[k][1] ? r - radial[k][1] : 0));
      }
    }
    in.prev  = &prev;
    in.hnode = h;
  }
  for (int k = 0; k < repeat && !rc; k++) {
    if ((rc = M2dRemesh(&in, &out, &st, err, sizeof(err)))) fprintf(stderr, "m2d_remesh: error: %s\n", err);
    else {
      printf("nodes %ld dofs %ld quads %ld open %.3f s generate %.3f s total %.3f s angle [%.1f, %.1f] jratio_min %.3f bad(<30,>150) %ld\n", out.nnode, 2 * out.nnode, out.nquad, st.seconds_open, st.seconds_generate, st.seconds_total, st.quality.min_angle, st.quality.max_angle, st.quality.min_jratio, st.quality.nbad);
      MshFree(&out);
    }
  }
  free(h);
  MshFree(&prev);
  return rc ? 1 : 0;
}
