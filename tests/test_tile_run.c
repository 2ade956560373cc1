/*
 * test_tile_run.c — the tile path in bands (workers/tile.h): with a
 * progress hook, tile_run_rect traces and shades a rectangle a band of
 * rows at a time and calls the hook between bands (a worker's large
 * answer moves on meanwhile: comm/mpi_link.h); the pixels, hits and ray
 * counts are those of the rectangle in one piece, for homo (tracing) and
 * hetero (shading the pass's records), several samples a pixel, and
 * rectangles as narrow as a band's row and as wide as a tile.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../csg/flatten.h"
#include "../csg/lang/parser.h"
#include "../workers/tile.h"

static const char scene[] =
    "camera { location <0, 1, -6> look_at <0, 0.5, 0> }\n"
    "light_source { <-5, 8, -9> rgb 1 }\n"
    "plane { y, -1 pigment { checker rgb 1 rgb 0.2 } finish { reflection 0.3 } }\n"
    "sphere { <0, 0.5, 0>, 1.2 pigment { rgbf <1, 1, 1, 0.8> } interior { ior 1.5 } }\n"
    "difference { box { -1, 1 } sphere { 0, 1.3 } translate <2.4, 0, 1> pigment { rgb <1, 0.3, 0> } }\n";

static void blob_of(int w, int h, int spp, csg_blob *b)
{
    csg_scene s;
    csg_diag d = {0};
    if (!csg_parse_string("bands.pov", scene, strlen(scene), &s, &d))
        fail_msg("parse: %s", d.message);
    csg_flatten_opts o = {w, h, 0, -1, spp, 0};
    if (!engine_float.flatten(&s, &o, b, &d))
        fail_msg("flatten: %s", d.message);
    csg_scene_free(&s);
}

static void count_call(void *arg)
{
    (*(int *)arg)++;
}

/* Rectangle r of the runner's image in one piece and in bands: the same
 * pixels and counts; the hook called once between each two bands. */
static void check_rect(tile_runner *tr, tile_rect r, const void *records)
{
    size_t n = (size_t)r.width * (size_t)r.height * 3;
    float *whole = calloc(n, sizeof *whole), *banded = calloc(n, sizeof *banded);
    assert_non_null(whole);
    assert_non_null(banded);
    tile_result a, b;
    int calls = 0;
    tr->progress = NULL;
    tile_run_rect(tr, r, records, whole, &a);
    tr->progress = count_call;
    tr->progress_arg = &calls;
    tile_run_rect(tr, r, records, banded, &b);
    tr->progress = NULL;
    assert_memory_equal(whole, banded, n * sizeof *whole);
    assert_int_equal(a.hits, b.hits);
    assert_memory_equal(&a.rays, &b.rays, sizeof a.rays);
    int rows = TILE_BAND_PIXELS / (r.width * tr->grid.spp);
    rows = rows < 1 ? 1 : rows;
    assert_int_equal(calls, (r.height + rows - 1) / rows - 1);
    free(whole);
    free(banded);
}

static void test_bands_are_the_rectangle(void **state)
{
    (void)state;
    for (int spp = 1; spp <= 3; spp += 2) {
        csg_blob blob;
        blob_of(96, 72, spp, &blob);
        tile_runner tr;
        assert_true(tile_runner_init(&tr, blob.bytes, 32));
        assert_null(tr.progress);
        const tile_rect rects[] = {{0, 0, 32, 32}, {64, 64, 32, 8}, {33, 5, 1, 27}, {10, 40, 17, 13}};
        for (size_t i = 0; i < sizeof rects / sizeof rects[0]; i++) {
            check_rect(&tr, rects[i], NULL); /* homo: traced, then shaded */
            /* hetero: shaded from records, here the engine's own */
            size_t recs = tile_records_bytes(&tr.grid, (size_t)rects[i].width * rects[i].height);
            void *records = malloc(recs);
            assert_non_null(records);
            size_t m = (size_t)rects[i].width * rects[i].height * (size_t)spp;
            engine_float.trace_primary(blob.bytes, rects[i], records,
                                       (uint32_t *)(void *)((char *)records + m * sizeof(float)),
                                       &(ray_counts){0, 0, 0, 0, 0, 0});
            check_rect(&tr, rects[i], records);
            free(records);
        }
        tile_runner_free(&tr);
        csg_blob_free(&blob);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bands_are_the_rectangle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
