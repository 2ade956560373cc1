/*
 * flat_scene.h — a test's scene text parsed and flattened (for a 4 x 4
 * image) by the engine of the test's precision (`real`: float, double
 * under -DCSG_DOUBLE); a failure fails the test with its message.
 * Include after cmocka.h.
 */
#ifndef TESTS_FLAT_SCENE_H
#define TESTS_FLAT_SCENE_H

#include <string.h>

#include "../csg/flatten.h"
#include "../csg/load.h"
#include "../workers/engine.h"

static inline const engine *flat_engine(void)
{
    return sizeof(real) == 8 ? &engine_double : &engine_float;
}

/* The flat scene of `text` (`name`'s extension picks the format). */
static inline csg_blob flat_scene(const char *name, const char *text)
{
    csg_scene s;
    csg_diag d = {0};
    if (!csg_load_string(name, text, strlen(text), NULL, &s, &d))
        fail_msg("parse: %s", d.message);
    csg_flatten_opts o = {4, 4, 0, -1, 1, 0};
    csg_blob b;
    if (!flat_engine()->flatten(&s, &o, &b, &d))
        fail_msg("flatten: %s", d.message);
    csg_scene_free(&s);
    return b;
}

#endif
