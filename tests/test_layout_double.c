/* test_layout.c in the double build (real = double). */
#define CSG_DOUBLE 1
#include "test_layout.c"
