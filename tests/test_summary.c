/* test_summary.c - the JSON summary (summary.h) against hand-written text:
 * key order, objects, lists of objects in index order (a missing index as {}),
 * escaping of keys and strings, NaN as null, a replaced value, 300 keys (no
 * fixed limit), and the errors: a name used as a key and as an object, a
 * negative list index, a key set through the old void API after a failure (the
 * first failure kept for the writer). */
#include "summary.h"
#include <string.h>

static int failures = 0;

static void Check(int ok, const char *what)
{
  printf("%s %s\n", ok ? "ok  " : "FAIL", what);
  if (!ok) failures++;
}

static PetscErrorCode ReadAll(const char *path, char *buf, size_t len)
{
  FILE  *fp;
  size_t n;

  PetscFunctionBeginUser;
  fp = fopen(path, "rb");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot read %s", path);
  n      = fread(buf, 1, len - 1, fp);
  buf[n] = 0;
  fclose(fp);
  PetscFunctionReturn(0);
}

/* the summary as its writer prints it (output.c: M2dSummaryPrint into the file) */
static PetscErrorCode Written(const char *path, const M2dSummary *s)
{
  FILE *fp;

  PetscFunctionBeginUser;
  PetscCheck(!s->err, PETSC_COMM_SELF, s->err, "%s", s->errmsg);
  fp = fopen(path, "w");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s", path);
  M2dSummaryPrint(fp, s);
  fclose(fp);
  PetscFunctionReturn(0);
}

static PetscErrorCode Small(const char *path)
{
  M2dSummary  s = {0};
  char        got[4096];
  const char *want = "{\n"
                     "  \"program\": \"mortar2d\",\n"
                     "  \"dofs\": 12,\n"
                     "  \"odd \\\"key\\\"\\u000a\": \"a\\\\b\\u0001\\\"\",\n"
                     "  \"residual_rel\": null,\n"
                     "  \"adapt\": [\n"
                     "    {\"dofs\": 10, \"error_estimate\": 0.5},\n"
                     "    {},\n"
                     "    {\"dofs\": 40, \"mark\": \"max\"}\n"
                     "  ],\n"
                     "  \"time\": {\"mesh\": 0.25}\n"
                     "}\n";

  PetscFunctionBeginUser;
  PetscCall(M2dSummaryString(&s, "", "program", "mortar2d"));
  PetscCall(M2dSummaryInt(&s, NULL, "dofs", 11));
  PetscCall(M2dSummaryListInt(&s, "adapt", 2, "dofs", 40));
  PetscCall(M2dSummaryString(&s, "", "odd \"key\"\n", "a\\b\001\""));
  PetscCall(M2dSummaryListInt(&s, "adapt", 0, "dofs", 10));
  PetscCall(M2dSummaryReal(&s, "", "residual_rel", (PetscReal)NAN));
  PetscCall(M2dSummaryListReal(&s, "adapt", 0, "error_estimate", 0.5));
  PetscCall(M2dSummaryListString(&s, "adapt", 2, "mark", "max"));
  PetscCall(M2dSummaryReal(&s, "time", "mesh", 0.25));
  PetscCall(M2dSummaryInt(&s, "", "dofs", 12)); /* replaces 11, keeps the place */
  PetscCall(Written(path, &s));
  PetscCall(M2dSummaryDestroy(&s));
  PetscCall(ReadAll(path, got, sizeof(got)));
  Check(!strcmp(got, want), "keys, objects, lists, escapes, null, replaced value");
  if (strcmp(got, want)) printf("got:\n%s\nwant:\n%s\n", got, want);
  PetscFunctionReturn(0);
}

static PetscErrorCode Many(const char *path)
{
  M2dSummary s = {0};
  char       got[65536], key[32], *p;
  int        n = 0, last = 1;

  PetscFunctionBeginUser;
  for (int k = 0; k < 300; k++) {
    PetscCall(PetscSNPrintf(key, sizeof(key), "k%03d", k));
    PetscCall(M2dSummaryInt(&s, "", key, k));
  }
  for (int k = 0; k < 100; k++) PetscCall(M2dSummaryListInt(&s, "adapt", k, "level", k));
  PetscCall(Written(path, &s));
  PetscCall(M2dSummaryDestroy(&s));
  PetscCall(ReadAll(path, got, sizeof(got)));
  for (p = got; (p = strstr(p, "\"k")); p++) n++;
  Check(n == 300 && strstr(got, "\"k299\": 299"), "300 top-level keys all written");
  for (int k = 0; k < 100; k++) {
    PetscCall(PetscSNPrintf(key, sizeof(key), "{\"level\": %d}", k));
    last = last && strstr(got, key) != NULL;
  }
  Check(last && s.n == 0 && !s.e, "100 list elements written; Destroy empties the summary");
  PetscFunctionReturn(0);
}

static PetscErrorCode Errors(void)
{
  M2dSummary     s = {0};
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  PetscCall(M2dSummaryInt(&s, "", "time", 1));
  ierr = M2dSummaryReal(&s, "time", "mesh", 1.0);
  Check(ierr != 0 && strstr(s.errmsg, "'time'"), "a name used as a key and as an object is an error");
  SummaryInt(&s, "", "later", 2); /* the old API: the failure stays recorded */
  Check(s.err != 0 && strstr(s.errmsg, "'time'"), "the first failure stays recorded for the writer to raise");
  PetscCall(M2dSummaryDestroy(&s));
  ierr = M2dSummaryListInt(&s, "adapt", -1, "dofs", 1);
  Check(ierr != 0, "a negative list index is an error");
  PetscCall(M2dSummaryDestroy(&s));
  ierr = M2dSummaryListInt(&s, "adapt", 0, "dofs", 1);
  if (!ierr) ierr = M2dSummaryInt(&s, "adapt", "dofs", 1);
  Check(ierr != 0, "a name used as a list and as an object is an error");
  PetscCall(M2dSummaryDestroy(&s));
  PetscCall(PetscPopErrorHandler());
  PetscFunctionReturn(0);
}

int main(int argc, char **argv)
{
  const char *path = "test_summary.json";

  PetscCall(PetscInitialize(&argc, &argv, NULL, NULL));
  PetscCall(Small(path));
  PetscCall(Many(path));
  PetscCall(Errors());
  remove(path);
  printf("%s\n", failures ? "test_summary: FAILED" : "test_summary: all checks passed");
  PetscCall(PetscFinalize());
  return failures ? 1 : 0;
}
