/* test_csg_double.c — tests/test_csg.c with real = double. */
#define CSG_DOUBLE 1
#include "test_csg.c"
