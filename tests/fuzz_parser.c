/*
 * fuzz_parser.c — libFuzzer entry point for the scene parser (optional; not
 * built by the Makefile, whose tests are tests/test_*.c).  Build and run:
 *
 *   clang -g -O1 -fsanitize=fuzzer,address,undefined -D_GNU_SOURCE \
 *     tests/fuzz_parser.c csg/lang/[a-z]*.c csg/scene.c csg/diag.c csg/camera_setup.c \
 *     -lm -o build/fuzz_parser
 *   build/fuzz_parser -max_total_time=60 [CORPUS_DIR]
 *
 * Each input is parsed from memory (the built-in colors.inc, a token budget
 * of 20000 so loops that never end stop fast); a failure must come with a
 * message "file:line:col: error: ..." and an empty scene, anything else
 * aborts.
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
    csg_parse_options o;
    csg_parse_options_default(&o);
    o.no_default_library = true;
    o.max_tokens = 20000;
    memset(&d, 0, sizeof d);
    if (csg_parse_string_opts("fuzz.pov", (const char *)data, size, &o, &s, &d)) {
        csg_scene_free(&s);
        return 0;
    }
    if (s.arena != NULL || !strstr(d.message, ": error: "))
        abort();
    return 0;
}
