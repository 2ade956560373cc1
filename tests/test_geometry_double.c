/* test_geometry_double.c — tests/test_geometry.c with real = double. */
#define CSG_DOUBLE 1
#include "test_geometry.c"
