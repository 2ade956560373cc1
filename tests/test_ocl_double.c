/* test_ocl.c in the double build (real = double). */
#define CSG_DOUBLE 1
#include "test_ocl.c"
