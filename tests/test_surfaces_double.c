/* test_surfaces_double.c — tests/test_surfaces.c with real = double. */
#define CSG_DOUBLE 1
#include "test_surfaces.c"
