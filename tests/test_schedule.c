/*
 * test_schedule.c — the work-item schedulers (host/schedule.c), the tile
 * cost estimate and Spearman's rank correlation (host/estimate.c):
 *   - raster hands out tiles in the order they became ready, cost by
 *     decreasing estimate (ties: the lower tile), static the k-th tile to
 *     worker k mod W and nothing of another worker's;
 *   - tail splits the last tiles into quarters that partition each tile
 *     exactly, and tells when a tile's last piece is done;
 *   - nothing is handed out twice, everything once, before `finished`;
 *   - a lost worker's items (sched_requeue) go out again before anything
 *     else, and `finished` waits for them; a lost worker's static share
 *     (sched_release) goes to the others, also tiles added later;
 *   - the estimate ranks a mirror sphere over a matte one over the
 *     background, from a real flattened scene and hand-made records;
 *   - Spearman: +1, -1, ties, and NaN where it is undefined.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/lang/parser.h"
#include "../host/estimate.h"
#include "../host/schedule.h"

/* Estimates from a table: the tile at x / 16 costs cost[x / 16] per pixel
 * row of 16 (enough for the quarters of a 16-pixel tile to differ). */
static double table_estimate(void *arg, tile_rect r)
{
    const double *cost = arg;
    return cost[r.x / 16] * (double)(r.width * r.height) / 256.0;
}

static tile_rect rect_of(int i)
{
    tile_rect r = { i * 16, 0, 16, 16 };
    return r;
}

/* A scheduler given tiles 0 .. tiles-1 (rect_of) and closed. */
static void filled(sched *s, enum sched_policy p, int workers, int tiles,
                   sched_estimate_fn estimate, void *arg)
{
    assert_true(sched_init(s, p, workers, 2, tiles, estimate, arg));
    for (int i = 0; i < tiles; i++)
        assert_true(sched_add(s, i, rect_of(i)));
    sched_close(s);
}

/* Hands out everything for worker w, in order, into out; the count. */
static int drain(sched *s, int w, int *out, int cap)
{
    int n = 0, item;
    while (n < cap && (item = sched_next(s, w, 0.0)) >= 0)
        out[n++] = item;
    return n;
}

static void test_raster_order(void **state)
{
    (void)state;
    sched s;
    int got[8];
    assert_true(sched_init(&s, SCHED_RASTER, 2, 2, 4, NULL, NULL));
    assert_true(sched_add(&s, 0, rect_of(0)));
    assert_true(sched_skip(&s, 1, rect_of(1)));
    assert_true(sched_add(&s, 2, rect_of(2)));
    assert_int_equal(sched_next(&s, 1, 0.0), 0);
    assert_false(sched_finished(&s)); /* not closed: more may come */
    assert_true(sched_add(&s, 3, rect_of(3)));
    sched_close(&s);
    assert_int_equal(drain(&s, 0, got, 8), 2);
    assert_int_equal(s.items[got[0]].tile, 2);
    assert_int_equal(s.items[got[1]].tile, 3);
    assert_true(sched_finished(&s));
    assert_int_equal(s.items[got[1]].order, 2);
    assert_true(s.items[1].skipped && s.items[1].order == -1);
    assert_true(s.items[0].estimate < 0); /* no estimator: unknown */
    sched_free(&s);
}

static void test_cost_order(void **state)
{
    (void)state;
    double cost[5] = { 1, 5, 3, 5, 2 };
    sched s;
    int got[8];
    filled(&s, SCHED_COST, 2, 5, table_estimate, cost);
    assert_int_equal(drain(&s, 0, got, 8), 5);
    int want[5] = { 1, 3, 2, 4, 0 }; /* 5, 5 (lower tile first), 3, 2, 1 */
    for (int i = 0; i < 5; i++)
        assert_int_equal(s.items[got[i]].tile, want[i]);
    assert_true(s.items[got[0]].estimate == 5.0);
    sched_free(&s);
}

/* Without estimates (homo), cost is raster. */
static void test_cost_without_estimates(void **state)
{
    (void)state;
    sched s;
    int got[4];
    filled(&s, SCHED_COST, 1, 3, NULL, NULL);
    assert_int_equal(drain(&s, 0, got, 4), 3);
    for (int i = 0; i < 3; i++)
        assert_int_equal(s.items[got[i]].tile, i);
    sched_free(&s);
}

static void test_static_assignment(void **state)
{
    (void)state;
    sched s;
    int got[8];
    filled(&s, SCHED_STATIC, 3, 7, NULL, NULL);
    assert_int_equal(drain(&s, 1, got, 8), 2); /* tiles 1 and 4, nothing else */
    assert_int_equal(s.items[got[0]].tile, 1);
    assert_int_equal(s.items[got[1]].tile, 4);
    assert_false(sched_finished(&s));
    assert_int_equal(drain(&s, 0, got, 8), 3); /* 0, 3, 6 */
    assert_int_equal(s.items[got[2]].tile, 6);
    assert_int_equal(drain(&s, 2, got, 8), 2);
    assert_true(sched_finished(&s));
    sched_free(&s);
}

/* A lost worker's items go out again, first, to whoever asks. */
static void test_requeue(void **state)
{
    (void)state;
    sched s;
    int got[8] = {0};
    filled(&s, SCHED_RASTER, 2, 4, NULL, NULL);
    assert_int_equal(drain(&s, 0, got, 2), 2); /* tiles 0, 1 to the worker lost */
    assert_true(sched_requeue(&s, got[1]));
    assert_true(sched_requeue(&s, got[0]));
    assert_int_equal(drain(&s, 1, got, 8), 4);
    int want[4] = {1, 0, 2, 3};
    for (int i = 0; i < 4; i++)
        assert_int_equal(s.items[got[i]].tile, want[i]);
    assert_true(sched_finished(&s));
    assert_int_equal(s.requeued, 2);
    assert_int_equal(s.dispatched, 6);
    sched_free(&s);
}

/* Static: a lost worker's queue, and tiles added for it later, go to the
 * others once their own queue is empty. */
static void test_static_release(void **state)
{
    (void)state;
    sched s;
    int got[8];
    assert_true(sched_init(&s, SCHED_STATIC, 2, 2, 6, NULL, NULL));
    for (int i = 0; i < 4; i++)
        assert_true(sched_add(&s, i, rect_of(i)));
    sched_release(&s, 1);
    assert_int_equal(drain(&s, 0, got, 8), 4); /* 0, 2, then 1, 3 */
    assert_int_equal(s.items[got[2]].tile, 1);
    assert_true(sched_add(&s, 4, rect_of(4)));
    assert_true(sched_add(&s, 5, rect_of(5)));
    sched_close(&s);
    assert_false(sched_finished(&s));
    assert_int_equal(drain(&s, 0, got, 8), 2);
    assert_true(sched_finished(&s));
    sched_free(&s);
}

/* Tail: the last tiles go as quarters that cover each tile exactly once. */
static void test_tail_split(void **state)
{
    (void)state;
    enum { TILES = 12 };
    double cost[TILES];
    for (int i = 0; i < TILES; i++)
        cost[i] = 1 + i % 4;
    sched s;
    int got[64];
    assert_true(sched_init(&s, SCHED_TAIL, 1, 2, TILES, table_estimate, cost));
    for (int i = 0; i < TILES; i++) {
        tile_rect r = rect_of(i);
        r.width = i == TILES - 1 ? 15 : 16; /* an odd edge tile */
        assert_true(sched_add(&s, i, r));
    }
    int before = sched_next(&s, 0, 0.0); /* not closed: never split */
    assert_int_equal(s.items[before].piece, 0);
    sched_close(&s);
    int n = drain(&s, 0, got, 64);
    assert_true(sched_finished(&s));
    int whole = 0, pieces = 0, area[TILES] = { 0 }, done_tiles = 0;
    for (int k = 0; k < n; k++) {
        const sched_item *it = &s.items[got[k]];
        whole += it->piece == 0;
        pieces += it->piece > 0;
        area[it->tile] += it->rect.width * it->rect.height;
        assert_false(it->split);
        done_tiles += sched_done(&s, got[k]);
    }
    done_tiles += sched_done(&s, before);
    int split_tiles = SCHED_TAIL_TILES_PER_SLOT * 1 * 2; /* workers x in flight */
    assert_int_equal(pieces, 4 * split_tiles);
    assert_int_equal(whole + 1, TILES - split_tiles);
    assert_int_equal(done_tiles, TILES); /* each tile complete exactly once */
    area[s.items[before].tile] += 256;
    for (int i = 0; i < TILES; i++)
        assert_int_equal(area[i], i == TILES - 1 ? 15 * 16 : 256);
    sched_free(&s);
}

/* A 1x1 tile cannot be split: it goes whole. */
static void test_tail_one_pixel(void **state)
{
    (void)state;
    sched s;
    tile_rect one = { 0, 0, 1, 1 };
    assert_true(sched_init(&s, SCHED_TAIL, 2, 2, 1, NULL, NULL));
    assert_true(sched_add(&s, 0, one));
    sched_close(&s);
    int item = sched_next(&s, 0, 0.0);
    assert_int_equal(s.items[item].piece, 0);
    assert_true(sched_done(&s, item));
    assert_true(sched_finished(&s));
    sched_free(&s);
}

static void test_spearman(void **state)
{
    (void)state;
    double x[5] = { 1, 2, 3, 4, 5 }, up[5] = { 10, 20, 25, 40, 100 }, down[5] = { 5, 4, 3, 2, 1 };
    double tied[5] = { 1, 1, 2, 2, 3 }, same[5] = { 7, 7, 7, 7, 7 };
    assert_true(fabs(estimate_spearman(x, up, 5) - 1.0) < 1e-12);
    assert_true(fabs(estimate_spearman(x, down, 5) + 1.0) < 1e-12);
    double rho = estimate_spearman(x, tied, 5); /* ranks 1.5 1.5 3.5 3.5 5 */
    assert_true(rho > 0.9 && rho < 1.0);
    assert_true(isnan(estimate_spearman(x, same, 5)));
    assert_true(isnan(estimate_spearman(x, up, 2)));
}

/* A mirror, a matte sphere and the background, estimated from records. */
static void test_estimate_ranks_materials(void **state)
{
    (void)state;
    const char *sdl =
        "camera { location <0, 0, -5> look_at <0, 0, 0> }\n"
        "light_source { <0, 5, -5> color rgb 1 }\n"
        "light_source { <5, 5, -5> color rgb 1 shadowless }\n"
        "sphere { <-1, 0, 0>, 0.5 pigment { color rgb 1 } }\n"
        "sphere { <1, 0, 0>, 0.5 pigment { color rgb 1 } finish { reflection 0.5 } }\n";
    csg_scene sc;
    csg_diag d = { { 0 }, 0 };
    csg_blob blob;
    csg_flatten_opts o = { 8, 2, 5, -1, 1, 0};
    assert_true(csg_parse_string("est.pov", sdl, strlen(sdl), &sc, &d));
    assert_true(engine_float.flatten(&sc, &o, &blob, &d));
    const csg_blob_header *h = csg_blob_hdr(blob.bytes);
    assert_int_equal(h->prim_count, 2);
    uint8_t cls[2];
    assert_int_equal(engine_float.surface_classes(blob.bytes, cls), 1); /* one casts shadows */
    int mirror = cls[0] & ENGINE_CLASS_REFLECTIVE ? 0 : 1;
    assert_true(cls[mirror] == ENGINE_CLASS_REFLECTIVE && cls[1 - mirror] == 0);
    /* Records by hand: column 0-1 background, 2-3 matte, 4-5 mirror. */
    uint32_t surf[16];
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 8; x++)
            surf[y * 8 + x] = x < 2 ? CSG_SURF_NONE
                                    : CSG_SURF_PACK(x < 4 ? 1 - mirror : mirror, 0, 0);
    tile_grid g = tile_grid_of(blob.bytes, 2);
    estimator e;
    assert_true(estimator_init(&e, blob.bytes, &g, surf));
    tile_rect bg = { 0, 0, 2, 2 }, matte = { 2, 0, 2, 2 }, shiny = { 4, 0, 2, 2 };
    double cb = estimate_rect(&e, bg), cm = estimate_rect(&e, matte), cs = estimate_rect(&e, shiny);
    assert_true(cb < cm && cm < cs);
    assert_true(fabs(cm - 4 * 2.0) < 1e-12); /* a hit and one shadow ray, 4 pixels */
    estimator_free(&e);
    csg_blob_free(&blob);
    csg_scene_free(&sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_raster_order),
        cmocka_unit_test(test_cost_order),
        cmocka_unit_test(test_cost_without_estimates),
        cmocka_unit_test(test_static_assignment),
        cmocka_unit_test(test_requeue),
        cmocka_unit_test(test_static_release),
        cmocka_unit_test(test_tail_split),
        cmocka_unit_test(test_tail_one_pixel),
        cmocka_unit_test(test_spearman),
        cmocka_unit_test(test_estimate_ranks_materials),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
