/* check.h - the one-line check of the C unit tests: "ok   ..." or "FAIL ...". */
#ifndef M2D_TEST_CHECK_H
#define M2D_TEST_CHECK_H
#include <stdio.h>

static int failures;
#define CHECK(c, ...) \
  do { \
    if (!(c)) { \
      failures++; \
      printf("FAIL "); \
    } else printf("ok   "); \
    printf(__VA_ARGS__); \
    printf("\n"); \
  } while (0)
#endif
