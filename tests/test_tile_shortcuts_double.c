/* test_tile_shortcuts_double.c — tests/test_tile_shortcuts.c with real = double. */
#define CSG_DOUBLE 1
#include "test_tile_shortcuts.c"
