/* summary.h - the JSON summary of a run (-summary FILE).
 *
 * A summary is a list of entries written as one JSON object:
 *   top-level keys (section "")          "dofs": 1234,
 *   objects (section "time", "error")    "time": {"mesh": 0.1, ...},
 *   lists of objects (M2dSummaryList*)   "adapt": [{"dofs": 10, ...}, {...}]
 * Top-level keys come first in the order they were first set, then objects and
 * lists in the order of their first entry; list elements in index order (an
 * index with no entry is written as {}).  Setting a key again replaces its
 * value.  Storage grows as needed; a failed allocation or a name used both as
 * a key and as an object/list is remembered (err, errmsg: the writer raises it), so
 * no entry is ever dropped silently.  README.md documents the keys. */
#ifndef M2D_SUMMARY_H
#define M2D_SUMMARY_H
#include <petscsys.h>
#include <stdio.h>

typedef struct {
  char    *section; /* "" top level, else object or list name */
  char    *key;
  char    *value;   /* JSON text */
  PetscInt index;   /* list element, -1 outside lists */
} M2dSummaryEntry;

/* Zero-initialise (PetscCalloc1 or = {0}); free with M2dSummaryDestroy. */
typedef struct {
  PetscInt         n, cap;
  M2dSummaryEntry *e;
  PetscErrorCode   err;        /* first failure, raised by the writer */
  char             errmsg[256];
} M2dSummary;

/* Set key in section ("" or NULL: top level) to a number (NaN/Inf: null), an
 * integer or a string (escaped).  Not collective; the strings are copied. */
PetscErrorCode M2dSummaryReal(M2dSummary *s, const char *section, const char *key, PetscReal v);
PetscErrorCode M2dSummaryInt(M2dSummary *s, const char *section, const char *key, PetscInt v);
PetscErrorCode M2dSummaryString(M2dSummary *s, const char *section, const char *key, const char *v);
/* Set key of element `index` (>= 0) of the list `list`, e.g. ("adapt", 2, "dofs"). */
PetscErrorCode M2dSummaryListReal(M2dSummary *s, const char *list, PetscInt index, const char *key, PetscReal v);
PetscErrorCode M2dSummaryListInt(M2dSummary *s, const char *list, PetscInt index, const char *key, PetscInt v);
PetscErrorCode M2dSummaryListString(M2dSummary *s, const char *list, PetscInt index, const char *key, const char *v);

/* Set key of list element `index` to the array [v[0], ..., v[n-1]] (numbers; NaN/Inf: null). */
PetscErrorCode M2dSummaryListArray(M2dSummary *s, const char *list, PetscInt index, const char *key, PetscInt n, const PetscReal v[]);

/* Print the summary as one JSON object (a failure recorded by the setters is
 * not checked here: the caller raises s->err first). Not collective. */
void M2dSummaryPrint(FILE *fp, const M2dSummary *s);
/* Free the entries (the struct itself is the caller's); s is empty afterwards. */
PetscErrorCode M2dSummaryDestroy(M2dSummary *s);

/* Earlier names, kept for existing callers: they record a failure in s (raised
 * by the writer) instead of returning it. */
void           SummaryReal(M2dSummary *s, const char *section, const char *key, PetscReal v);
void           SummaryInt(M2dSummary *s, const char *section, const char *key, PetscInt v);
void           SummaryString(M2dSummary *s, const char *section, const char *key, const char *v);
#endif
