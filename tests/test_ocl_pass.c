/*
 * test_ocl_pass.c — the primary pass in the background (host/pass/ocl.h:
 * ocl_pass_begin / ocl_pass_rows / ocl_pass_end), as the pipelined master
 * drives it: slices of one tile row, completion callbacks, polling.
 *   - the records and tile counts equal those of the pass waited for whole
 *     (ocl_primary_pass), whatever the slicing;
 *   - the rows reported never go back, end at the height, and the tile
 *     counts of every tile row already reported are final then;
 *   - the callback runs once a slice, and never after ocl_pass_end;
 *   - a pass can be ended before it is over (the master gave up): it
 *     waits only for the few slices on the queue (OCL_PASS_WINDOW);
 *   - a pass limited to the top rows (ocl_pass_limit: the fill took the
 *     rest) stops there, whole, with those rows' records and counts
 *     equal to the whole pass's.
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
#include "../host/pass/ocl.h"

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
    ocl_options opt = {0};
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
        assert_true(ocl_pass_begin(fx->ctx, fx->blob.bytes, TILE, slice, bg->t, bg->surf, NULL, NULL,
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

/* Ended at once, the pass still waits for what it enqueued (the first
 * slices only: the queue is topped up by ocl_pass_rows) and frees all. */
static void test_end_early(void **state)
{
    fixture *fx = *state;
    records *r = calloc(1, sizeof *r);
    csg_diag d = {{0}, 0};
    atomic_int calls;
    atomic_init(&calls, 0);
    ocl_pass *p = NULL;
    assert_true(ocl_pass_begin(fx->ctx, fx->blob.bytes, TILE, TILE, r->t, r->surf, NULL, NULL, r->hits,
                               on_slice, &calls, &p, &d));
    ocl_pass_end(p, NULL, &d); /* not asked how far it got */
    int after = atomic_load(&calls);
    assert_true(after >= 1 && after < (H + TILE - 1) / TILE); /* not every slice */
    free(r);
}

/* Limited to the top rows, at once or half-way: it stops after them
 * (only the slices already on the queue run beyond), is whole, and those
 * rows equal the whole pass's. */
static void test_limit(void **state)
{
    fixture *fx = *state;
    records *whole = calloc(1, sizeof *whole), *part = calloc(1, sizeof *part);
    csg_diag d = {{0}, 0};
    ocl_timing tm;
    memset(&tm, 0, sizeof tm);
    assert_true(ocl_primary_pass(fx->ctx, fx->blob.bytes, TILE, whole->t, whole->surf,
                                 whole->hits, &tm, &d));
    int slices = (H + TILE - 1) / TILE, columns = (W + TILE - 1) / TILE;
    for (int limit = 0; limit <= H; limit += 3 * TILE - 5) { /* 0, 19, 38, 57 rows */
        for (int late = 0; late < 2; late++) {
            ocl_pass *p = NULL;
            memset(part, 0xff, sizeof *part);
            assert_true(ocl_pass_begin(fx->ctx, fx->blob.bytes, TILE, TILE, part->t, part->surf, NULL, NULL,
                                       part->hits, NULL, NULL, &p, &d));
            int rows = late ? ocl_pass_rows(p, true, &d) : 0; /* a slice or more in first */
            int done = rows / TILE; /* (slices of TILE rows) */
            ocl_pass_limit(p, limit);
            while (rows < limit)
                assert_true((rows = ocl_pass_rows(p, true, &d)) >= 0);
            assert_true(ocl_pass_end(p, &tm, &d));
            int need = (limit + TILE - 1) / TILE;
            assert_true(tm.slices >= need && tm.slices <= slices);
            assert_true(tm.slices <= (need > done ? need : done) + 3); /* the window */
            size_t n = (size_t)W * (size_t)(limit < H ? limit : H);
            assert_memory_equal(part->t, whole->t, n * sizeof *part->t);
            assert_memory_equal(part->surf, whole->surf, n * sizeof *part->surf);
            for (int i = 0; i < limit / TILE * columns; i++)
                assert_int_equal(part->hits[i], whole->hits[i]);
        }
    }
    free(whole);
    free(part);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_background_equals_whole),
        cmocka_unit_test(test_end_early),
        cmocka_unit_test(test_limit),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
