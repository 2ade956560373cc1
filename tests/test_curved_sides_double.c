/* test_curved_sides_double.c — tests/test_curved_sides.c with real = double. */
#define CSG_DOUBLE 1
#include "test_curved_sides.c"
