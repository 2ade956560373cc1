/* test_primary_double.c — tests/test_primary.c with real = double. */
#define CSG_DOUBLE 1
#include "test_primary.c"
