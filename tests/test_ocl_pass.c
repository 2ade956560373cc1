/*
 * test_ocl_pass.c — the primary pass in the background (host/ocl.h:
 * ocl_pass_begin / ocl_pass_rows / ocl_pass_end), as the pipelined master
 * drives it: slices of one tile row, completion callbacks, polling.
 *   - the records and tile counts equal those of the pass waited for whole
 *     (ocl_primary_pass), whatever the slicing;
 *   - the rows reported never go back, end at the height, and the tile
 *     counts of every tile row already reported are final then;
 *   - the callback runs once a slice, and never after ocl_pass_end;
 *   - a pass can be ended before it is over (the master gave up).
 * The scene is parsed from SDL and flattened in float (the kernel's own
 * correctness is test_ocl's business).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/flatten.h"
#include "../csg/lang/parser.h"
#include "../host/ocl.h"

enum { W = 90, H = 61, TILE = 8 };

typedef struct {
    ocl_ctx *ctx;
    csg_blob blob;
} fixture;

static const char *scene_sdl =
    "camera { location <0, 1, -6> look_at <0, 0, 0> }\n"
    "light_source { <3, 5, -4> color rgb 1 }\n"
    "sphere { <-1, 0, 0>, 1 pigment { color rgb <1, 0.2, 0.2> } }\n"
    "difference { box { <0, -1, -1>, <2, 1, 1> } sphere { <1, 0, -1>, 0.8 }\n"
    "  pigment { color rgb 1 } finish { reflection 0.4 } }\n";

static int group_setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    csg_scene s;
    csg_diag d = {{0}, 0};
    csg_flatten_opts o = {W, H, 5, -1, 1, 0};
    ocl_options opt = {NULL, 0, 0, NULL};
    ocl_timing tm;
    memset(&tm, 0, sizeof tm);
    if (!fx || !csg_parse_string("pass.pov", scene_sdl, strlen(scene_sdl), &s, &d) ||
        !csg_flatten_float(&s, &o, &fx->blob, &d) || !ocl_open(&opt, &fx->ctx, &tm, &d)) {
        fprintf(stderr, "test_ocl_pass setup: %s\n", d.message);
        return -1;
    }
    csg_scene_free(&s);
    *state = fx;
    return 0;
}

static int group_teardown(void **state)
{
    fixture *fx = *state;
    ocl_close(fx->ctx);
    csg_blob_free(&fx->blob);
    free(fx);
    return 0;
}

typedef struct {
    float t[W * H];
    uint32_t surf[W * H];
    uint32_t hits[((W + TILE - 1) / TILE) * ((H + TILE - 1) / TILE)];
} records;

static void on_slice(void *arg)
{
    atomic_fetch_add((atomic_int *)arg, 1);
}

static void test_background_equals_whole(void **state)
{
    fixture *fx = *state;
    records *whole = calloc(1, sizeof *whole), *bg = calloc(1, sizeof *bg);
    csg_diag d = {{0}, 0};
    ocl_timing tm;
    memset(&tm, 0, sizeof tm);
    assert_true(ocl_primary_pass(fx->ctx, fx->blob.bytes, TILE, whole->t, whole->surf,
                                 whole->hits, &tm, &d));
    for (int slice = 1; slice <= 3 * TILE; slice += TILE - 1) { /* 1, 8, 15, 22 rows */
        atomic_int calls;
        atomic_init(&calls, 0);
        ocl_pass *p = NULL;
        memset(bg, 0xff, sizeof *bg);
        assert_true(ocl_pass_begin(fx->ctx, fx->blob.bytes, TILE, slice, bg->t, bg->surf,
                                   bg->hits, on_slice, &calls, &p, &d));
        int rows = 0, columns = (W + TILE - 1) / TILE;
        while (rows < H) {
            int now = ocl_pass_rows(p, slice % 2 == 0, &d); /* poll, or wait */
            assert_true(now >= rows && now <= H);
            rows = now;
            int final_tile_rows = rows == H ? (H + TILE - 1) / TILE : rows / TILE;
            for (int i = 0; i < final_tile_rows * columns; i++)
                assert_int_equal(bg->hits[i], whole->hits[i]);
        }
        assert_true(ocl_pass_end(p, &tm, &d));
        assert_int_equal(atomic_load(&calls), tm.slices);
        assert_int_equal(tm.slices, (H + (slice >= TILE ? slice / TILE * TILE : slice) - 1) /
                                        (slice >= TILE ? slice / TILE * TILE : slice));
        assert_memory_equal(bg->t, whole->t, sizeof bg->t);
        assert_memory_equal(bg->surf, whole->surf, sizeof bg->surf);
        assert_memory_equal(bg->hits, whole->hits, sizeof bg->hits);
    }
    free(whole);
    free(bg);
}

/* Ended at once, the pass still waits for what it enqueued and frees all. */
static void test_end_early(void **state)
{
    fixture *fx = *state;
    records *r = calloc(1, sizeof *r);
    csg_diag d = {{0}, 0};
    atomic_int calls;
    atomic_init(&calls, 0);
    ocl_pass *p = NULL;
    assert_true(ocl_pass_begin(fx->ctx, fx->blob.bytes, TILE, TILE, r->t, r->surf, r->hits,
                               on_slice, &calls, &p, &d));
    ocl_pass_end(p, NULL, &d); /* not asked how far it got */
    int after = atomic_load(&calls);
    assert_int_equal(after, (H + TILE - 1) / TILE); /* every callback ran, none later */
    free(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_background_equals_whole),
        cmocka_unit_test(test_end_early),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
