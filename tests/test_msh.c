/* Unit tests of the gmsh reader: formats 2.2, 4.1 and binary 4.1 give the same mesh,
 * non-contiguous node tags, physical groups of every dimension, and clean
 * errors (never a crash) for corrupted input. */
#define _GNU_SOURCE /* memmem */
#include "msh.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"

/* two quads side by side, node tags 10,20,...; a physical curve and a point */
static const char *m41 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n0 3 \"pin\"\n1 2 \"bottom\"\n2 1 \"body\"\n$EndPhysicalNames\n"
                         "$Entities\n1 1 1 0\n7 0 0 0 1 3\n5 0 0 0 2 0 0 1 2 0\n1 0 0 0 2 1 0 1 1 0\n$EndEntities\n"
                         "$Nodes\n1 6 10 60\n2 1 0 6\n10\n20\n30\n40\n50\n60\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n$EndNodes\n"
                         "$Elements\n3 5 1 5\n0 7 15 1\n1 10\n1 5 1 2\n2 10 20\n3 20 30\n2 1 3 2\n4 10 20 50 40\n5 20 30 60 50\n$EndElements\n";
static const char *m22 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n0 3 \"pin\"\n1 2 \"bottom\"\n2 1 \"body\"\n$EndPhysicalNames\n"
                         "$Nodes\n6\n10 0 0 0\n20 1 0 0\n30 2 0 0\n40 0 1 0\n50 1 1 0\n60 2 1 0\n$EndNodes\n"
                         "$Elements\n5\n1 15 2 3 7 10\n2 1 2 2 5 10 20\n3 1 2 2 5 20 30\n4 3 2 1 1 10 20 50 40\n5 3 2 1 1 20 30 60 50\n$EndElements\n";

static int ReadText(const char *text, size_t len, MshMesh *m, char *err, size_t errlen)
{
  char  path[] = "/tmp/m2d_test_msh_XXXXXX";
  int   fd     = mkstemp(path), rc;
  FILE *fp     = fdopen(fd, "w");
  fwrite(text, 1, len, fp);
  fclose(fp);
  rc = MshRead(path, m, err, errlen);
  unlink(path);
  return rc;
}

/* m41 in gmsh's binary 4.1 layout (ints 4 bytes, sizes 8, doubles 8) */
typedef struct {
  char   b[4096];
  size_t n;
} Buf;
static void Put(Buf *o, const void *v, size_t n)
{
  memcpy(o->b + o->n, v, n);
  o->n += n;
}
static void Txt(Buf *o, const char *t) { Put(o, t, strlen(t)); }
static void I(Buf *o, int v) { Put(o, &v, sizeof(v)); }
static void Z(Buf *o, size_t v) { Put(o, &v, sizeof(v)); }
static void D(Buf *o, double v) { Put(o, &v, sizeof(v)); }
static void Binary41(Buf *o, int one)
{
  const double xy[6][2] = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}};
  o->n = 0;
  Txt(o, "$MeshFormat\n4.1 1 8\n");
  I(o, one);
  Txt(o, "\n$EndMeshFormat\n$PhysicalNames\n3\n0 3 \"pin\"\n1 2 \"bottom\"\n2 1 \"body\"\n$EndPhysicalNames\n$Entities\n");
  Z(o, 1), Z(o, 1), Z(o, 1), Z(o, 0);
  I(o, 7), D(o, 0), D(o, 0), D(o, 0), Z(o, 1), I(o, 3);                                    /* point 7 */
  I(o, 5), D(o, 0), D(o, 0), D(o, 0), D(o, 2), D(o, 0), D(o, 0), Z(o, 1), I(o, 2), Z(o, 0); /* curve 5 */
  I(o, 1), D(o, 0), D(o, 0), D(o, 0), D(o, 2), D(o, 1), D(o, 0), Z(o, 1), I(o, 1), Z(o, 0); /* surface 1 */
  Txt(o, "\n$EndEntities\n$Nodes\n");
  Z(o, 1), Z(o, 6), Z(o, 10), Z(o, 60);
  I(o, 2), I(o, 1), I(o, 0), Z(o, 6);
  for (int k = 0; k < 6; k++) Z(o, (size_t)(10 * (k + 1)));
  for (int k = 0; k < 6; k++) D(o, xy[k][0]), D(o, xy[k][1]), D(o, 0);
  Txt(o, "\n$EndNodes\n$Elements\n");
  Z(o, 3), Z(o, 5), Z(o, 1), Z(o, 5);
  I(o, 0), I(o, 7), I(o, 15), Z(o, 1), Z(o, 1), Z(o, 10);
  I(o, 1), I(o, 5), I(o, 1), Z(o, 2), Z(o, 2), Z(o, 10), Z(o, 20), Z(o, 3), Z(o, 20), Z(o, 30);
  I(o, 2), I(o, 1), I(o, 3), Z(o, 2), Z(o, 4), Z(o, 10), Z(o, 20), Z(o, 50), Z(o, 40), Z(o, 5), Z(o, 20), Z(o, 30), Z(o, 60), Z(o, 50);
  Txt(o, "\n$EndElements\n");
}

static void CompareLen(const char *name, const char *text, size_t len)
{
  MshMesh m;
  char    err[1024];
  int     rc = ReadText(text, len, &m, err, sizeof(err));
  CHECK(rc == 0, "%s reads (%s)", name, rc ? err : "");
  if (rc) return;
  CHECK(m.nnode == 6 && m.nquad == 2 && m.nline == 2 && m.npoint == 1, "%s: 6 nodes, 2 quads, 2 lines, 1 point", name);
  CHECK(m.quad[4] == 1 && m.quad[5] == 2 && m.quad[6] == 5 && m.quad[7] == 4, "%s: second quad's nodes mapped from tags", name);
  CHECK(m.xy[2 * 5] == 2.0 && m.xy[2 * 5 + 1] == 1.0, "%s: coordinates", name);
  CHECK(!strcmp(MshPhysicalName(&m, 2, m.quadphys[0]), "body") && !strcmp(MshPhysicalName(&m, 1, m.linephys[1]), "bottom") && !strcmp(MshPhysicalName(&m, 0, m.pointphys[0]), "pin"), "%s: physical names", name);
  MshFree(&m);
}

static void Compare(const char *name, const char *text) { CompareLen(name, text, strlen(text)); }

int main(void)
{
  Compare("msh 4.1", m41);
  Compare("msh 2.2", m22);
  { /* binary 4.1: the same mesh; every truncation, the other byte order and a huge count rejected */
    Buf b, t;
    int bad = 0, rejected = 0;
    Binary41(&b, 1);
    CompareLen("msh 4.1 binary", b.b, b.n);
    for (size_t k = 0; k + 14 < b.n; k++) {
      MshMesh m;
      char    err[1024] = "";
      int     rc        = ReadText(b.b, k, &m, err, sizeof(err));
      if (!rc || !strstr(err, "mesh file")) bad++;
      else rejected++;
      MshFree(&m);
    }
    CHECK(bad == 0 && rejected > 0, "truncated binary files: %d rejected with a message naming the file, %d not", rejected, bad);
    {
      MshMesh m;
      char    err[1024] = "";
      int     rc;
      Binary41(&t, 1 << 24);
      rc = ReadText(t.b, t.n, &m, err, sizeof(err));
      CHECK(rc && strstr(err, "byte order"), "binary file of the other byte order rejected: %s", err);
      MshFree(&m);
    }
    {
      MshMesh     m;
      char        err[1024] = "";
      const char *key = "$Nodes\n";
      char       *q;
      size_t      huge = (size_t)1 << 40;
      int         rc;
      t = b;
      q = (char *)memmem(t.b, t.n, key, strlen(key));
      memcpy(q + strlen(key) + 8, &huge, sizeof(huge)); /* the number of nodes */
      rc = ReadText(t.b, t.n, &m, err, sizeof(err));
      CHECK(rc && strstr(err, "larger than the rest") && strstr(err, "(binary), byte"), "binary file with a huge node count rejected: %s", err);
      MshFree(&m);
    }
  }
  { /* every truncation of both files is rejected with a message, or (at the very end) accepted */
    int         bad = 0, rejected = 0;
    const char *texts[2] = {m41, m22};
    for (int t = 0; t < 2; t++) {
      size_t n = strlen(texts[t]);
      for (size_t k = 0; k < n - 13; k++) {
        MshMesh m;
        char    err[1024] = "";
        int     rc        = ReadText(texts[t], k, &m, err, sizeof(err));
        if (rc && !strstr(err, "mesh file")) bad++;
        if (rc) rejected++;
        MshFree(&m);
      }
    }
    CHECK(bad == 0 && rejected > 0, "truncated files: %d rejected with a message naming the file, %d without", rejected, bad);
  }
  { /* corruptions: huge counts, unknown node, triangle, binary */
    struct {
      const char *from, *to, *expect;
    } cases[] = {
      {"$Nodes\n6\n", "$Nodes\n600000000\n", "larger than the rest"},
      {"4 3 2 1 1 10 20 50 40", "4 3 2 1 1 10 20 55 40", "node 55"},
      {"5 3 2 1 1 20 30 60 50", "5 2 2 1 1 20 30 60", "triangle"},
      {"2.2 0 8", "2.2 1 8", "binary"},
      {"30 2 0 0", "30 2 zz 0", "real number"},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
      char        text[4096], err[1024] = "";
      MshMesh     m;
      const char *p = strstr(m22, cases[i].from);
      size_t      pre = (size_t)(p - m22);
      snprintf(text, sizeof(text), "%.*s%s%s", (int)pre, m22, cases[i].to, p + strlen(cases[i].from));
      int rc = ReadText(text, strlen(text), &m, err, sizeof(err));
      CHECK(rc != 0 && strstr(err, cases[i].expect), "corruption '%s' rejected: %s", cases[i].to, err);
      MshFree(&m);
    }
  }
  {
    MshMesh m;
    char    err[1024];
    int     rc = MshRead("/nonexistent/x.msh", &m, err, sizeof(err));
    CHECK(rc && strstr(err, "/nonexistent/x.msh"), "missing file: %s", err);
    MshFree(&m);
  }
  printf("%d failed\n", failures);
  return failures ? 1 : 0;
}
