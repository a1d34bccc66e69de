/* activeset_paths.h - what each solver path adds to the active-set iteration
 * (activeset_paths.c): the condensed path's iteration on the multipliers, the
 * iterative path's solves, the VI solver's bounds. Not public. */
#ifndef M2D_ACTIVESET_PATHS_H
#define M2D_ACTIVESET_PATHS_H
#include "activeset_step.h"

PetscErrorCode ActiveSetSetupCondensed(SNES snes, M2dActiveSet *as, M2dActiveSetInfo *info);
PetscErrorCode ActiveSetCondensedStart(SNES snes, M2dActiveSet *as, Vec z0, Vec *nu, Mat *J);
PetscErrorCode ActiveSetSetupIterative(SNES snes, M2dActiveSet *as);
PetscErrorCode ActiveSetSetupVI(SNES snes, M2dActiveSet *as, Vec z);
#endif
