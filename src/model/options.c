/* options.c - see options.h. */
#include "options.h"
#include "optcheck.h"
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define VALUE_LEN 65536 /* a long list: -contact_pairs of the 512 pairs a scene may hold (about 20 characters each, up to 255) */

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

/* the option's value as typed ("" for a bare flag); records the name as ours.
 * A value longer than the buffer is refused, not cut (PETSc copies what fits:
 * "1" and 300 zeros in a 256-byte buffer read as 1e255) */
static PetscErrorCode Raw(PetscOptionItems *PetscOptionsObject, const char *name, char *full, char *value, PetscBool *set)
{
  const char *pre = PetscOptionsObject->prefix ? PetscOptionsObject->prefix : "", *v = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(full, 256, "-%s%s", pre, name + 1));
  PetscCall(M2dOptionsKnow(full));
  value[0] = 0;
  PetscCall(PetscOptionsFindPair(PetscOptionsObject->options, PetscOptionsObject->prefix, name, &v, set));
  if (*set && v && strlen(v) >= VALUE_LEN) { /* no reader's form: PETSc is not asked to parse it */
    PetscCall(M2dOptionsDefer("option %s: its value is %zu characters, longer than the %d allowed", full, strlen(v), VALUE_LEN - 1));
    PetscCall(PetscStrncpy(value, "(too long)", VALUE_LEN));
  } else if (*set && v) PetscCall(PetscStrncpy(value, v, VALUE_LEN));
  PetscFunctionReturn(0);
}

/* text (an option's value) fits len bytes, else the error is kept */
static PetscErrorCode CheckFits(const char *full, const char *text, size_t len)
{
  PetscFunctionBeginUser;
  if (len && strlen(text) >= len) PetscCall(M2dOptionsDefer("option %s: '%.40s...' is %zu characters, longer than the %zu allowed", full, text, strlen(text), len - 1));
  PetscFunctionReturn(0);
}

const char *M2dShown(const char *text, char *buf, size_t len)
{
  size_t n = strlen(text);

  if (n <= 80) return text;
  snprintf(buf, len, "%.32s...%s (%zu characters)", text, text + n - 16, n);
  return buf;
}

PetscBool M2dUnderflows(const char *text)
{
  char  *end;
  double d;

  errno = 0;
  d     = strtod(text, &end);
  return (PetscBool)(end != text && !*end && errno == ERANGE && d == 0); /* a subnormal (1e-308) is a number: its own checks judge it */
}

/* a finite number and nothing else (strtod also takes inf and nan: refused;
 * and a nonzero number below double precision's range, read as 0) */
static PetscBool ParseFinite(const char *text, PetscReal *v)
{
  char  *end;
  double d = strtod(text, &end);

  if (end == text || *end || PetscIsInfOrNanReal((PetscReal)d) || M2dUnderflows(text)) return PETSC_FALSE;
  *v = (PetscReal)d;
  return PETSC_TRUE;
}

static PetscBool IsFinite(const char *text)
{
  PetscReal v;
  return ParseFinite(text, &v);
}

PetscBool M2dOptionsParseInteger(const char *text, long long *value)
{
  char     *end;
  long long l;
  PetscReal d;

  if (!text[0]) return PETSC_FALSE;
  l = strtoll(text, &end, 10); /* saturates at LLONG_MIN/MAX */
  if (*end) { /* e-notation of an exact integer (docs give 1e6 for -adapt_max_dofs) */
    if (!ParseFinite(text, &d) || d != PetscFloorReal(d)) return PETSC_FALSE;
    l = d >= 9.2e18 ? LLONG_MAX : d <= -9.2e18 ? LLONG_MIN : (long long)d;
  }
  *value = l;
  return PETSC_TRUE;
}

/* base-10 integer, or e-notation of one, that fits a PetscInt, nothing else */
static PetscBool IsInteger(const char *text)
{
  long long l;
  return (PetscBool)(M2dOptionsParseInteger(text, &l) && l <= PETSC_MAX_INT && l >= PETSC_MIN_INT);
}

static PetscBool IsBool(const char *text)
{
  const char *const words[] = {"", "true", "yes", "on", "1", "false", "no", "off", "0"};

  for (size_t i = 0; i < sizeof(words) / sizeof(words[0]); i++)
    if (!strcasecmp(text, words[i])) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* Raw, and the value, when given, checked by valid(): *ok FALSE, and the error
 * "option NAME: 'VALUE' is not <what>" kept, when it fails; PETSc is then not
 * asked (its own error would be raised inside PetscOptionsBegin/End) */
static PetscErrorCode RawChecked(PetscOptionItems *PetscOptionsObject, const char *name, PetscBool (*valid)(const char *), const char *what, PetscBool *ok)
{
  char      full[256], buf[VALUE_LEN];
  PetscBool given;

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  *ok = (PetscBool)(!given || valid(buf));
  if (!*ok) {
    char shown[128];
    if (M2dUnderflows(buf)) PetscCall(M2dOptionsDefer("option %s: '%s' is nonzero but below double precision's range (4.9e-324)", full, M2dShown(buf, shown, sizeof(shown))));
    else PetscCall(M2dOptionsDefer("option %s: '%s' is not %s", full, M2dShown(buf, shown, sizeof(shown)), what));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsReal(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscReal def, PetscReal *value, PetscBool *set)
{
  PetscBool ok;

  PetscFunctionBeginUser;
  if (set) *set = PETSC_FALSE;
  *value = def;
  PetscCall(RawChecked(PetscOptionsObject, name, IsFinite, "a finite number", &ok));
  if (ok) PetscCall(PetscOptionsReal(name, help, "", def, value, set));
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
  if (!ParseFinite(buf, &v)) {
    char shown[128];
    PetscCall(M2dOptionsDefer("option %s: '%s' is neither auto nor a finite number%s", full, M2dShown(buf, shown, sizeof(shown)), M2dUnderflows(buf) ? " (nonzero but below double precision's range)" : ""));
  }
  else {
    *value = v;
    *set   = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsInt(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscInt def, PetscInt *value, PetscBool *set)
{
  PetscBool ok;

  PetscFunctionBeginUser;
  if (set) *set = PETSC_FALSE;
  *value = def;
  PetscCall(RawChecked(PetscOptionsObject, name, IsInteger, "an integer", &ok));
  if (ok) {
    char      full[256], buf[VALUE_LEN];
    PetscBool given;
    long long l;
    PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
    if (given && strspn(buf, "+-0123456789") != strlen(buf) && M2dOptionsParseInteger(buf, &l)) { /* PETSc reads no e-notation: the same integer in digits */
      PetscCall(PetscSNPrintf(buf, sizeof(buf), "%lld", l));
      PetscCall(PetscOptionsSetValue(PetscOptionsObject->options, full, buf));
    }
    PetscCall(PetscOptionsInt(name, help, "", def, value, set));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsBool(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscBool def, PetscBool *value)
{
  PetscBool ok;

  PetscFunctionBeginUser;
  *value = def;
  PetscCall(RawChecked(PetscOptionsObject, name, IsBool, "true or false", &ok));
  if (ok) PetscCall(PetscOptionsBool(name, help, "", def, value, NULL));
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
  if (given && !ok) {
    char shown[128];
    PetscCall(M2dOptionsDefer("option %s: unknown value '%s' (one of: %s)", full, M2dShown(buf, shown, sizeof(shown)), choices));
  }
  else PetscCall(PetscOptionsEList(name, help, "", list, n, list[*index], index, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsEnum(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, const char *const list[], PetscInt n, PetscEnum *value)
{
  PetscInt k = (PetscInt)*value;

  PetscFunctionBeginUser;
  PetscCall(M2dOptionsEList(PetscOptionsObject, name, help, list, n, &k));
  *value = (PetscEnum)k;
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsString(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, char *value, size_t len, PetscBool *set)
{
  char      full[256], buf[VALUE_LEN];
  PetscBool given;

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  if (given) PetscCall(CheckFits(full, buf, len));
  PetscCall(PetscOptionsString(name, help, "", value, value, len, set));
  PetscFunctionReturn(0);
}

PetscErrorCode M2dOptionsStringArray(PetscOptionItems *PetscOptionsObject, const char *name, const char *help, PetscInt max, size_t len, char *values[], PetscInt *n)
{
  char      full[256], buf[VALUE_LEN], **all;
  PetscBool given;
  PetscInt  k = max + 1; /* one more than allowed: PETSc drops the excess silently */

  PetscFunctionBeginUser;
  PetscCall(Raw(PetscOptionsObject, name, full, buf, &given));
  if (given && buf[0] && (buf[0] == ',' || buf[strlen(buf) - 1] == ',' || strstr(buf, ",,"))) { /* PETSc drops all but a leading one */
    char shown[128];
    PetscCall(M2dOptionsDefer("option %s: '%s' has an empty entry (two commas together, or one at an end)", full, M2dShown(buf, shown, sizeof(shown))));
  }
  PetscCall(PetscCalloc1(max + 1, &all));
  PetscCall(PetscOptionsStringArray(name, help, "", all, &k, &given));
  if (!given) k = 0;
  if (k > max) {
    PetscCall(M2dOptionsDefer("option %s: at most %" PetscInt_FMT " entries", full, max));
    for (PetscInt i = 0; i < k; i++) PetscCall(PetscFree(all[i]));
    k = 0;
  }
  for (PetscInt i = 0; i < k; i++) {
    PetscCall(CheckFits(full, all[i], len));
    values[i] = all[i];
  }
  *n = k;
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}
