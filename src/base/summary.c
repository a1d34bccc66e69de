/* summary.c - the JSON summary (see summary.h): entries in a growing array,
 * printed as one JSON object. */
#include "summary.h"
#include "util.h"
#include <string.h>

/* JSON string literal of v: quotes, backslash and control characters escaped */
static PetscErrorCode JsonString(const char *v, char **out)
{
  size_t n = strlen(v), k = 0;
  char  *t;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(6 * n + 3, &t));
  t[k++] = '"';
  for (const unsigned char *c = (const unsigned char *)v; *c; c++) {
    if (*c == '"' || *c == '\\') {
      t[k++] = '\\';
      t[k++] = (char)*c;
    } else if (*c < 32 || *c == 127) {
      snprintf(t + k, 7, "\\u%04x", *c);
      k += 6;
    } else t[k++] = (char)*c;
  }
  t[k++] = '"';
  t[k]   = 0;
  *out   = t;
  PetscFunctionReturn(0);
}

static PetscErrorCode Fail(M2dSummary *s, PetscErrorCode code, const char *msg, const char *name)
{
  if (!s->err) {
    s->err = code;
    snprintf(s->errmsg, sizeof(s->errmsg), msg, name);
  }
  return code;
}

/* is the name `section` (or a top-level key equal to it) already used in another role? */
static PetscBool Conflicts(const M2dSummary *s, const char *section, const char *key, PetscInt index)
{
  for (PetscInt i = 0; i < s->n; i++) {
    const M2dSummaryEntry *e = &s->e[i];
    if (section[0] && !e->section[0] && !strcmp(e->key, section)) return PETSC_TRUE;
    if (!section[0] && e->section[0] && !strcmp(e->section, key)) return PETSC_TRUE;
    if (section[0] && !strcmp(e->section, section) && ((e->index < 0) != (index < 0))) return PETSC_TRUE;
  }
  return PETSC_FALSE;
}

/* set (section, index, key) to the JSON text `text` (taken over by s) */
static PetscErrorCode Add(M2dSummary *s, const char *section, PetscInt index, const char *key, char *text)
{
  M2dSummaryEntry *e;

  PetscFunctionBeginUser;
  if (!section) section = "";
  for (PetscInt i = 0; i < s->n; i++) {
    e = &s->e[i];
    if (e->index == index && !strcmp(e->section, section) && !strcmp(e->key, key)) {
      PetscCall(PetscFree(e->value));
      e->value = text;
      PetscFunctionReturn(0);
    }
  }
  if (Conflicts(s, section, key, index)) {
    PetscCall(PetscFree(text));
    PetscFunctionReturn(Fail(s, PETSC_ERR_ARG_WRONG, "summary: the name '%s' is used both as a key and as an object or list", section[0] ? section : key));
  }
  if (s->n == s->cap) {
    PetscInt         cap = s->cap ? 2 * s->cap : 64;
    M2dSummaryEntry *ne;
    PetscCall(PetscMalloc1(cap, &ne));
    if (s->n) PetscCall(PetscArraycpy(ne, s->e, s->n));
    PetscCall(PetscFree(s->e));
    s->e   = ne;
    s->cap = cap;
  }
  e        = &s->e[s->n];
  e->index = index;
  e->value = text;
  PetscCall(PetscStrallocpy(section, &e->section));
  PetscCall(PetscStrallocpy(key, &e->key));
  s->n++;
  PetscFunctionReturn(0);
}

static PetscErrorCode FormatNumber(PetscBool isreal, PetscReal r, PetscInt i, char **out)
{
  char t[64];

  PetscFunctionBeginUser;
  if (!isreal) snprintf(t, sizeof(t), "%lld", (long long)i);
  else if (PetscIsInfOrNanReal(r)) snprintf(t, sizeof(t), "null");
  else snprintf(t, sizeof(t), "%.17g", (double)r);
  PetscCall(PetscStrallocpy(t, out));
  PetscFunctionReturn(0);
}

/* one entry point for the six setters; failures are also remembered in s */
static PetscErrorCode Set(M2dSummary *s, const char *section, PetscInt index, const char *key, int kind, PetscReal r, PetscInt i, const char *str)
{
  char          *text = NULL;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  if (s->err) PetscFunctionReturn(s->err);
  if (!key || !key[0] || (index < -1)) PetscFunctionReturn(Fail(s, PETSC_ERR_ARG_WRONG, "summary: an empty key or a negative list index in '%s'", section ? section : ""));
  ierr = kind == 2 ? JsonString(str ? str : "", &text) : FormatNumber(kind == 0 ? PETSC_TRUE : PETSC_FALSE, r, i, &text);
  if (!ierr) ierr = Add(s, section, index, key, text);
  if (ierr) PetscFunctionReturn(Fail(s, ierr, "summary: cannot store key '%s'", key));
  PetscFunctionReturn(0);
}

/* raise the failure Set remembered (its message is in s) */
static PetscErrorCode Raise(const M2dSummary *s, PetscErrorCode ierr)
{
  PetscFunctionBeginUser;
  PetscCheck(!ierr, PETSC_COMM_SELF, ierr, "%s", s->errmsg);
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSummaryReal(M2dSummary *s, const char *section, const char *key, PetscReal v)
{
  PetscFunctionBeginUser;
  PetscCall(Raise(s, Set(s, section, -1, key, 0, v, 0, NULL)));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSummaryInt(M2dSummary *s, const char *section, const char *key, PetscInt v)
{
  PetscFunctionBeginUser;
  PetscCall(Raise(s, Set(s, section, -1, key, 1, 0, v, NULL)));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSummaryString(M2dSummary *s, const char *section, const char *key, const char *v)
{
  PetscFunctionBeginUser;
  PetscCall(Raise(s, Set(s, section, -1, key, 2, 0, 0, v)));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSummaryListReal(M2dSummary *s, const char *list, PetscInt index, const char *key, PetscReal v)
{
  PetscFunctionBeginUser;
  PetscCall(Raise(s, Set(s, list, index < 0 ? -2 : index, key, 0, v, 0, NULL)));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSummaryListInt(M2dSummary *s, const char *list, PetscInt index, const char *key, PetscInt v)
{
  PetscFunctionBeginUser;
  PetscCall(Raise(s, Set(s, list, index < 0 ? -2 : index, key, 1, 0, v, NULL)));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSummaryListString(M2dSummary *s, const char *list, PetscInt index, const char *key, const char *v)
{
  PetscFunctionBeginUser;
  PetscCall(Raise(s, Set(s, list, index < 0 ? -2 : index, key, 2, 0, 0, v)));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dSummaryListArray(M2dSummary *s, const char *list, PetscInt index, const char *key, PetscInt n, const PetscReal v[])
{
  char          *text = NULL;
  size_t         len = 0;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  if (s->err) PetscFunctionReturn(Raise(s, s->err));
  ierr = PetscMalloc1(32 * (size_t)n + 3, &text);
  if (!ierr) {
    text[len++] = '[';
    for (PetscInt i = 0; i < n; i++) {
      if (PetscIsInfOrNanReal(v[i])) len += (size_t)snprintf(text + len, 32, "%snull", i ? ", " : "");
      else len += (size_t)snprintf(text + len, 32, "%s%.17g", i ? ", " : "", (double)v[i]);
    }
    text[len++] = ']';
    text[len]   = 0;
    ierr        = Add(s, list, index < 0 ? -2 : index, key, text);
  }
  if (ierr) ierr = Fail(s, ierr, "summary: cannot store key '%s'", key);
  PetscCall(Raise(s, ierr));
  PetscFunctionReturn(0);
}

void SummaryReal(M2dSummary *s, const char *section, const char *key, PetscReal v)
{
  (void)Set(s, section, -1, key, 0, v, 0, NULL);
}

void SummaryInt(M2dSummary *s, const char *section, const char *key, PetscInt v)
{
  (void)Set(s, section, -1, key, 1, 0, v, NULL);
}

void SummaryString(M2dSummary *s, const char *section, const char *key, const char *v)
{
  (void)Set(s, section, -1, key, 2, 0, 0, v);
}

PetscErrorCode M2dSummaryDestroy(M2dSummary *s)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < s->n; i++) {
    PetscCall(PetscFree(s->e[i].section));
    PetscCall(PetscFree(s->e[i].key));
    PetscCall(PetscFree(s->e[i].value));
  }
  PetscCall(PetscFree(s->e));
  s->n = s->cap = 0;
  PetscFunctionReturn(0);
}

/* a key as a JSON string literal */
static void PutKey(FILE *fp, const char *v)
{
  fputc('"', fp);
  for (const unsigned char *c = (const unsigned char *)v; *c; c++) {
    if (*c == '"' || *c == '\\') fprintf(fp, "\\%c", *c);
    else if (*c < 32 || *c == 127) fprintf(fp, "\\u%04x", *c);
    else fputc(*c, fp);
  }
  fputc('"', fp);
}

/* "key": value pairs of one object (section, index), comma separated */
static void WriteMembers(FILE *fp, const M2dSummary *s, const char *section, PetscInt index)
{
  int first = 1;
  for (PetscInt i = 0; i < s->n; i++) {
    const M2dSummaryEntry *e = &s->e[i];
    if (e->index != index || strcmp(e->section, section)) continue;
    fprintf(fp, "%s", first ? "" : ", ");
    PutKey(fp, e->key);
    fprintf(fp, ": %s", e->value);
    first = 0;
  }
}

/* the object or list named by entry k, unless an earlier entry named it already */
static void WriteGroup(FILE *fp, const M2dSummary *s, PetscInt k, const char *sep)
{
  const M2dSummaryEntry *g = &s->e[k];
  PetscInt               last = -1;

  for (PetscInt i = 0; i < k; i++)
    if (!strcmp(s->e[i].section, g->section)) return;
  fprintf(fp, "%s\n  ", sep);
  PutKey(fp, g->section);
  fprintf(fp, ": ");
  if (g->index < 0) {
    fprintf(fp, "{");
    WriteMembers(fp, s, g->section, -1);
    fprintf(fp, "}");
    return;
  }
  for (PetscInt i = 0; i < s->n; i++)
    if (!strcmp(s->e[i].section, g->section)) last = PetscMax(last, s->e[i].index);
  fprintf(fp, "[");
  for (PetscInt j = 0; j <= last; j++) {
    fprintf(fp, "%s\n    {", j ? "," : "");
    WriteMembers(fp, s, g->section, j);
    fprintf(fp, "}");
  }
  fprintf(fp, "\n  ]");
}

void M2dSummaryPrint(FILE *fp, const M2dSummary *s)
{
  int first = 1;

  fprintf(fp, "{");
  for (PetscInt i = 0; i < s->n; i++)
    if (!s->e[i].section[0]) {
      fprintf(fp, "%s\n  ", first ? "" : ",");
      PutKey(fp, s->e[i].key);
      fprintf(fp, ": %s", s->e[i].value);
      first = 0;
    }
  for (PetscInt i = 0; i < s->n; i++)
    if (s->e[i].section[0]) {
      WriteGroup(fp, s, i, first ? "" : ",");
      first = 0;
    }
  fprintf(fp, "\n}\n");
}
