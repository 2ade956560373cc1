/*
 * fuzz_parser.c — libFuzzer entry point for the scene parser (optional; not
 * built by the Makefile, whose tests are tests/test_*.c).  Build and run:
 *
 *   clang -g -O1 -fsanitize=fuzzer,address,undefined -D_GNU_SOURCE \
 *     tests/fuzz_parser.c csg/lang/parser.c csg/lang/expr.c csg/lang/symbols.c \
 *     csg/lang/source.c csg/lang/lexer.c csg/lang/colors.c csg/scene.c \
 *     csg/diag.c csg/camera_setup.c -lm -o build/fuzz_parser
 *   build/fuzz_parser -max_total_time=60 [CORPUS_DIR]
 *
 * Each input is parsed from memory; a failure must come with a message
 * "file:line:col: error: ..." and an empty scene, anything else aborts.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/lang/parser.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    csg_scene s;
    csg_diag d;
    memset(&d, 0, sizeof d);
    if (csg_parse_string("fuzz.pov", (const char *)data, size, &s, &d)) {
        csg_scene_free(&s);
        return 0;
    }
    if (s.arena != NULL || !strstr(d.message, ": error: "))
        abort();
    return 0;
}
