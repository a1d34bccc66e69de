/* method.h - what each contact method provides, in one table: the name the
 * summary and the run print, whether it builds mortar segments (D and M) or
 * node-to-segment rows, and whether each of its rows has a dof of its own
 * (the non-mortar node's normal component), so that the iterative path can
 * eliminate the multipliers row by row. Not collective. */
#ifndef M2D_METHOD_H
#define M2D_METHOD_H
#include "mortar.h"
#include "scene.h"

typedef struct {
  const char *family;  /* summary "method": mortar or nts */
  const char *name;    /* summary "pairs"[k].method: mortar standard, mortar dual, nts */
  const char *printed; /* the set-up line */
  PetscBool   segments;     /* mortar segments and D, M per non-mortar edge; else NTS rows */
  PetscBool   row_own_dof;  /* each row has a dof of its own (dual mortar, NTS) */
} M2dMethodInfo;

const M2dMethodInfo *M2dMethodOf(M2dContactMethod method, M2dMortarBasis basis);
#endif
