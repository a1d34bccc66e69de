/* method.c - see method.h */
#include "method.h"

static const M2dMethodInfo methods[] = {
  {"mortar", "mortar standard", "mortar (standard multipliers)", PETSC_TRUE, PETSC_FALSE},
  {"mortar", "mortar dual", "mortar (dual multipliers)", PETSC_TRUE, PETSC_TRUE},
  {"nts", "nts", "node-to-segment", PETSC_FALSE, PETSC_TRUE},
};

const M2dMethodInfo *M2dMethodOf(M2dContactMethod method, M2dMortarBasis basis)
{
  if (method == M2D_CONTACT_NTS) return &methods[2];
  return &methods[basis == M2D_MORTAR_DUAL ? 1 : 0];
}
