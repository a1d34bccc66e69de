/* options.c - see options.h. */
#include "options.h"
#include "optcheck.h"
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define VALUE_LEN 4096

/* the first problem found while reading, raised after PetscOptionsEnd */
static char deferred[2048];
static int  have_deferred;

PetscErrorCode M2dOptionsDefer(const char *fmt, ...)
{
  va_list ap;

  PetscFunctionBeginUser;
  if (have_deferred) PetscFunctionReturn(0);
  va_start(ap, fmt);
  vsnprintf(deferred, sizeof(deferred), fmt, ap);
  va_end(ap);
  have_deferred = 1;
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsRaise(MPI_Comm comm)
{
  PetscFunctionBeginUser;
  if (!have_deferred) PetscFunctionReturn(0);
  have_deferred = 0;
  SETERRQ(comm, PETSC_ERR_USER_INPUT, "%s", deferred);
}

/* the option's value as typed ("" for a bare flag); records the name as ours */
static PetscErrorCode Raw(PetscOptionItems *PetscOptionsObject, const char *name, char *full, char *value, PetscBool *set)
{
  const char *pre = PetscOptionsObject->prefix ? PetscOptionsObject->prefix : "";

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(full, 256, "-%s%s", pre, name + 1));
  PetscCall(M2dOptionsKnow(full));
  value[0] = 0;
  PetscCall(PetscOptionsGetString(PetscOptionsObject->options, PetscOptionsObject->prefix, name, value, VALUE_LEN, set));
  PetscFunctionReturn(0);
}

/* a finite number and nothing else (strtod also takes inf and nan: refused) */
static PetscBool ParseFinite(const char *text, PetscReal *v)
{
  char  *end;
  double d = strtod(text, &end);

  if (end == text || *end || PetscIsInfOrNanReal((PetscReal)d)) return PETSC_FALSE;
  *v = (PetscReal)d;
  return PETSC_TRUE;
}

PetscErrorCode M2dOptionsReal(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscReal def, PetscReal *value, PetscBool *set)
{
  char      full[256], buf[VALUE_LEN];
  PetscBool given;
  PetscReal v;

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  if (set) *set = PETSC_FALSE;
  *value = def;
  if (given && !ParseFinite(buf, &v)) PetscCall(M2dOptionsDefer("option %s: '%s' is not a finite number", full, buf));
  else PetscCall(PetscOptionsReal(name, help, "", def, value, set));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsRealAuto(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscReal *value, PetscBool *set)
{
  char      full[256], buf[VALUE_LEN], shown[64] = "auto";
  PetscBool given;
  PetscReal v;

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  *set = PETSC_FALSE;
  PetscCall(PetscOptionsString(name, help, "", shown, shown, sizeof(shown), NULL));
  if (!given || !strcasecmp(buf, "auto")) PetscFunctionReturn(0);
  if (!ParseFinite(buf, &v)) PetscCall(M2dOptionsDefer("option %s: '%s' is neither auto nor a finite number", full, buf));
  else {
    *value = v;
    *set   = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsRealList(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscInt max, PetscReal values[], PetscInt *n)
{
  char      full[256], buf[VALUE_LEN], *tok, *save = NULL;
  PetscBool given;
  PetscInt  k = 0;

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  if (given) { /* check every entry first: PETSc's own message names neither the option nor the entry */
    for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save), k++) {
      PetscReal v;
      if (k == max) {
        PetscCall(M2dOptionsDefer("option %s: at most %" PetscInt_FMT " values", full, max));
        PetscFunctionReturn(0);
      }
      if (!ParseFinite(tok, &v)) {
        PetscCall(M2dOptionsDefer("option %s: '%s' is not a finite number", full, tok));
        PetscFunctionReturn(0);
      }
    }
    if (k == 0) {
      PetscCall(M2dOptionsDefer("option %s: needs a value", full));
      PetscFunctionReturn(0);
    }
  }
  k = given ? max : *n;
  PetscCall(PetscOptionsRealArray(name, help, "", values, &k, &given));
  if (given) *n = k;
  PetscFunctionReturn(0);
}

/* base-10 integer that fits a PetscInt, nothing else */
static PetscBool ParseInt(const char *text, PetscInt *v)
{
  char     *end;
  long long l;

  if (!text[0]) return PETSC_FALSE;
  l = strtoll(text, &end, 10);
  if (*end || l > PETSC_MAX_INT || l < PETSC_MIN_INT) return PETSC_FALSE;
  *v = (PetscInt)l;
  return PETSC_TRUE;
}

PetscErrorCode M2dOptionsInt(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscInt def, PetscInt *value, PetscBool *set)
{
  char      full[256], buf[VALUE_LEN];
  PetscBool given;
  PetscInt  v;

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  if (set) *set = PETSC_FALSE;
  *value = def;
  if (given && !ParseInt(buf, &v)) PetscCall(M2dOptionsDefer("option %s: '%s' is not an integer", full, buf));
  else PetscCall(PetscOptionsInt(name, help, "", def, value, set));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsBool(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscBool def, PetscBool *value)
{
  const char *const yes[] = {"", "true", "yes", "on", "1"}, *const no[] = {"false", "no", "off", "0"};
  char              full[256], buf[VALUE_LEN];
  PetscBool         given, ok = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  *value = def;
  for (size_t i = 0; given && i < sizeof(yes) / sizeof(yes[0]); i++) ok = (PetscBool)(ok || !strcasecmp(buf, yes[i]));
  for (size_t i = 0; given && i < sizeof(no) / sizeof(no[0]); i++) ok = (PetscBool)(ok || !strcasecmp(buf, no[i]));
  if (given && !ok) PetscCall(M2dOptionsDefer("option %s: '%s' is not true or false", full, buf));
  else PetscCall(PetscOptionsBool(name, help, "", def, value, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsEList(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, const char *const list[], PetscInt n, PetscInt *index)
{
  char      full[256], buf[VALUE_LEN], choices[512] = "";
  PetscBool given, ok = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  for (PetscInt i = 0; i < n; i++) {
    ok = (PetscBool)(ok || !strcasecmp(buf, list[i]));
    PetscCall(PetscStrlcat(choices, i ? ", " : "", sizeof(choices)));
    PetscCall(PetscStrlcat(choices, list[i], sizeof(choices)));
  }
  /* PETSc's own message for a wrong value is one line naming the option, but it is
   * raised inside PetscOptionsBegin/End (leaking the block): checked here first */
  if (given && !ok) PetscCall(M2dOptionsDefer("option %s: unknown value '%s' (one of: %s)", full, buf, choices));
  else PetscCall(PetscOptionsEList(name, help, "", list, n, list[*index], index, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsString(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, char *value, size_t len, PetscBool *set)
{
  char      full[256], buf[VALUE_LEN];
  PetscBool given;

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  PetscCall(PetscOptionsString(name, help, "", value, value, len, set));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsStringArray(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscInt max, char *values[], PetscInt *n)
{
  char      full[256], buf[VALUE_LEN], **all;
  PetscBool given;
  PetscInt  k = max + 1; /* one more than allowed: PETSc drops the excess silently */

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  PetscCall(PetscCalloc1(max + 1, &all));
  PetscCall(PetscOptionsStringArray(name, help, "", all, &k, &given));
  if (!given) k = 0;
  if (k > max) {
    PetscCall(M2dOptionsDefer("option %s: at most %" PetscInt_FMT " entries", full, max));
    for (PetscInt i = 0; i < k; i++) PetscCall(PetscFree(all[i]));
    k = 0;
  }
  for (PetscInt i = 0; i < k; i++) values[i] = all[i];
  *n = k;
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}
