/*
 * test_schedule.c — the work-item schedulers (host/schedule.c), the tile
 * cost estimate and Spearman's rank correlation (host/pass/estimate.c):
 *   - raster hands out tiles in the order they became ready, cost by
 *     decreasing estimate (ties: the lower tile), region each worker's
 *     band in order then the far end of the longest band, static the k-th tile to
 *     worker k mod W and nothing of another worker's;
 *   - tail splits the last tiles into quarters that partition each tile
 *     exactly, and tells when a tile's last piece is done;
 *   - pieces (sched_cut): every tile goes as 4 / 16 / 64 pieces that
 *     partition it exactly (odd edges, tiles narrower than the cuts), in
 *     cost order of the pieces' own estimates, batched, each tile complete
 *     once; static keeps whole tiles; the auto rule (sched_pieces_auto);
 *   - nothing is handed out twice, everything once, before `finished`;
 *   - a lost worker's items (sched_requeue) go out again before anything
 *     else, and `finished` waits for them; a lost worker's static share
 *     (sched_release) goes to the others, also tiles added later;
 *   - batches: the limit (--batch N, auto: 1 below SCHED_BATCH_WORKERS
 *     workers), the size of each message from the items ready (large
 *     first, never above the limit, 1 at the end and in tail's split
 *     phase, requeued items and tiles the pass has not reached counted),
 *     raster batches spread over the image, cost batches cut by their
 *     share of the estimates, every item exactly once; the
 *     protocol's batch sizes (parts 8-byte aligned, the RESULT cap);
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
#include "../host/pass/estimate.h"
#include "../comm/protocol.h"
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

/* Region: worker w owns tiles [w T / W, (w + 1) T / W) and takes them in
 * order; with its band empty it takes the last tile of the longest other
 * band; every tile once; batches are runs of neighbours; the fill is on. */
static void test_region(void **state)
{
    (void)state;
    sched s;
    int got[16];
    filled(&s, SCHED_REGION, 3, 10, NULL, NULL); /* bands 0-3, 4-6, 7-9 */
    assert_int_equal(drain(&s, 1, got, 2), 2);
    assert_int_equal(s.items[got[0]].tile, 4);
    assert_int_equal(s.items[got[1]].tile, 5);
    assert_int_equal(drain(&s, 1, got, 1), 1);
    assert_int_equal(s.items[got[0]].tile, 6);
    /* band 1 empty: the last of band 0 (4 left, band 2 has 3) */
    assert_int_equal(drain(&s, 1, got, 1), 1);
    assert_int_equal(s.items[got[0]].tile, 3);
    assert_int_equal(s.stolen, 1);
    /* bands 0 (0-2) and 2 (7-9) tie at 3: the first one's last */
    assert_int_equal(drain(&s, 1, got, 1), 1);
    assert_int_equal(s.items[got[0]].tile, 2);
    assert_int_equal(drain(&s, 0, got, 3), 3); /* 0, 1, then band 2's last: 9 */
    assert_int_equal(s.items[got[0]].tile, 0);
    assert_int_equal(s.items[got[1]].tile, 1);
    assert_int_equal(s.items[got[2]].tile, 9);
    assert_int_equal(drain(&s, 2, got, 16), 2); /* 7, 8 */
    assert_int_equal(s.items[got[0]].tile, 7);
    assert_int_equal(s.items[got[1]].tile, 8);
    assert_true(sched_finished(&s));
    sched_free(&s);
    /* a batch: a run of neighbours from the worker's own band */
    filled(&s, SCHED_REGION, 2, 40, NULL, NULL);
    int k = sched_next_batch(&s, 1, 0.0, 4, got);
    assert_true(k > 1);
    for (int i = 0; i < k; i++)
        assert_int_equal(s.items[got[i]].tile, 20 + i);
    sched_free(&s);
    /* with the fill: its items are never queued, and the end still comes */
    assert_true(sched_init(&s, SCHED_REGION, 2, 2, 8, NULL, NULL));
    sched_fill_enable(&s);
    assert_int_equal(sched_fill_claim(&s, 0), 7);
    assert_true(sched_next_fill(&s, 0.0, 7, rect_of(7)) >= 0);
    for (int i = 0; i < 7; i++)
        assert_true(sched_add(&s, i, rect_of(i)));
    sched_close(&s);
    assert_int_equal(drain(&s, 0, got, 16), 7);
    assert_true(sched_finished(&s));
    sched_free(&s);
}

/* A lost worker's items go out again, first, to whoever asks. */
/* The fill: tiles claimed from the last one up, each handed out at once
 * without an estimate, never below the feed's front; the feed's tiles
 * stop at the fill's; a fill item lost goes out again, still a fill;
 * static has no fill. */
static void test_fill(void **state)
{
    (void)state;
    double cost[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    sched s;
    assert_true(sched_init(&s, SCHED_COST, 2, 2, 8, table_estimate, cost));
    assert_int_equal(sched_fill_claim(&s, 0), -1); /* off */
    sched_fill_enable(&s);
    assert_int_equal(sched_fill_front(&s), 8);
    int a = sched_fill_claim(&s, 0), b = sched_fill_claim(&s, 0);
    assert_int_equal(a, 7);
    assert_int_equal(b, 6);
    int ia = sched_next_fill(&s, 1.0, a, rect_of(a)), ib = sched_next_fill(&s, 2.0, b, rect_of(b));
    assert_true(ia >= 0 && ib >= 0);
    assert_true(s.items[ia].fill && s.items[ia].estimate < 0 && s.items[ia].order == 0);
    assert_true(s.items[ib].order == 1 && s.items[ib].sent_s == 2.0);
    assert_int_equal(sched_next(&s, 0, 3.0), -1); /* a fill item is never queued */
    for (int i = 0; i < 4; i++) /* the pass's tiles 0 .. 3, a front of 4 */
        assert_true(sched_add(&s, i, rect_of(i)));
    assert_int_equal(sched_fill_claim(&s, 4), 5);
    assert_true(sched_next_fill(&s, 4.0, 5, rect_of(5)) >= 0);
    assert_int_equal(sched_fill_claim(&s, 4), 4);
    assert_int_equal(sched_fill_front(&s), 4);
    assert_int_equal(sched_fill_claim(&s, 4), -1); /* the feed has every tile left */
    assert_true(sched_resume(&s, 4, rect_of(4))); /* (the caller's: tile 4 came resumed) */
    sched_close(&s);
    assert_int_equal(s.filled, 4);
    assert_true(sched_requeue(&s, ia));
    int order[5];
    assert_int_equal(drain(&s, 0, order, 5), 5);
    assert_int_equal(order[0], ia); /* again first, still a fill item */
    assert_true(s.items[order[0]].fill);
    for (int i = 1; i < 5; i++) /* then the pass's tiles by cost */
        assert_int_equal(s.items[order[i]].tile, 4 - i);
    assert_true(sched_finished(&s));
    assert_int_equal(s.added, 7);
    sched_free(&s);
    assert_true(sched_init(&s, SCHED_STATIC, 2, 2, 8, NULL, NULL));
    sched_fill_enable(&s);
    assert_int_equal(sched_fill_claim(&s, 0), -1);
    sched_free(&s);
    /* fill batches: what neither has yet over a round of every worker's
     * messages (2 x 2 x SCHED_BATCH_SPREAD), within the limit, 1 at least */
    assert_true(sched_init(&s, SCHED_RASTER, 2, 2, 100, NULL, NULL));
    sched_fill_enable(&s);
    assert_int_equal(sched_fill_batch(&s, 4), 4); /* ceil(100 / 16) = 7 */
    assert_int_equal(sched_fill_batch(&s, 1), 1);
    for (int i = 0; i < 60; i++)
        assert_true(sched_add(&s, i, rect_of(i)));
    while (sched_fill_claim(&s, 60) > 80)
        ;
    assert_int_equal(sched_fill_batch(&s, 8), 2); /* tiles 60 .. 79 left: ceil(20 / 16) */
    while (sched_fill_claim(&s, 60) >= 0)
        ;
    assert_int_equal(sched_fill_batch(&s, 8), 1);
    sched_free(&s);
}

/* The fill's tiles cut too: the first piece at once, the others next
 * (sched_next_fill_piece, or sched_next once the fill stops claiming),
 * the tile complete with its last piece, finished only with none left. */
static void test_fill_pieces(void **state)
{
    (void)state;
    double cost[4] = {1, 2, 3, 4};
    sched s;
    assert_true(sched_init(&s, SCHED_COST, 2, 2, 4, table_estimate, cost));
    assert_true(sched_cut(&s, 4));
    sched_fill_enable(&s);
    int tile = sched_fill_claim(&s, 0);
    assert_int_equal(tile, 3);
    int got[4];
    got[0] = sched_next_fill(&s, 1.0, tile, rect_of(tile));
    got[1] = sched_next_fill_piece(&s, 1.0);
    for (int i = 0; i < 3; i++) /* the pass's tiles 0 .. 2 */
        assert_true(sched_add(&s, i, rect_of(i)));
    sched_close(&s);
    assert_false(sched_finished(&s)); /* two pieces of the fill's tile left */
    got[2] = sched_next(&s, 0, 2.0);  /* they go before the pass's tiles */
    got[3] = sched_next(&s, 1, 2.0);
    int area = 0;
    for (int k = 0; k < 4; k++) {
        const sched_item *it = &s.items[got[k]];
        assert_true(it->fill && it->tile == 3 && it->piece == k + 1 && it->estimate < 0);
        area += it->rect.width * it->rect.height;
        assert_int_equal(sched_done(&s, got[k]), k == 3); /* complete with the last */
    }
    assert_int_equal(area, 256);
    assert_int_equal(sched_next_fill_piece(&s, 3.0), -1);
    int rest[12];
    assert_int_equal(drain(&s, 0, rest, 12), 12); /* the pass's tiles, 4 pieces each */
    for (int k = 0; k < 12; k++)
        assert_false(s.items[rest[k]].fill);
    assert_true(sched_finished(&s));
    assert_int_equal(s.filled, 1);
    sched_free(&s);
}

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
/* Hands out everything in batches of at most `limit` for worker 0 and
 * marks it done: pieces' areas per tile into area[], the tiles completed. */
static int drain_done(sched *s, int limit, int *area, int *items)
{
    int got[PROTO_BATCH_MAX], k, complete = 0;
    *items = 0;
    while ((k = sched_next_batch(s, 0, 0.0, limit, got)) > 0)
        for (int i = 0; i < k; i++) {
            const sched_item *it = &s->items[got[i]];
            assert_false(it->split);
            area[it->tile] += it->rect.width * it->rect.height;
            complete += sched_done(s, got[i]);
            (*items)++;
        }
    return complete;
}

/* Each tile as 4, 16, 64 pieces: they partition it (an odd edge tile of
 * 15x16, a 3x16 one narrower than 8 cuts), each tile is complete once,
 * and cost order follows the pieces' estimates. */
static void test_pieces(void **state)
{
    (void)state;
    enum { TILES = 6 };
    double cost[TILES] = {1, 5, 2, 4, 3, 6};
    const int pieces[] = {4, 16, 64};
    for (size_t c = 0; c < sizeof pieces / sizeof *pieces; c++) {
        sched s;
        assert_true(sched_init(&s, SCHED_COST, 2, 2, TILES, table_estimate, cost));
        assert_true(sched_cut(&s, pieces[c]));
        for (int i = 0; i < TILES; i++) {
            tile_rect r = rect_of(i);
            r.width = i == TILES - 1 ? 15 : i == TILES - 2 ? 3 : 16;
            assert_true(sched_add(&s, i, r));
        }
        sched_close(&s);
        int cuts = pieces[c] == 4 ? 2 : pieces[c] == 16 ? 4 : 8;
        /* 4 full tiles and the 15-wide one cut whole; the 3-wide one has
         * 3 non-empty columns of cuts once cuts > 3 */
        int expect = 5 * pieces[c] + (cuts > 3 ? 3 * cuts : pieces[c]);
        int area[TILES] = {0}, items = 0, complete = 0;
        double last = 1e30;
        for (int item; (item = sched_next(&s, 0, 0.0)) >= 0;) {
            const sched_item *it = &s.items[item];
            assert_true(it->piece >= 1 && it->piece <= pieces[c]);
            assert_true(it->estimate <= last); /* largest first, piece by piece */
            last = it->estimate;
            area[it->tile] += it->rect.width * it->rect.height;
            items++;
            complete += sched_done(&s, item);
        }
        assert_int_equal(complete, TILES);
        assert_int_equal(items, expect);
        for (int i = 0; i < TILES; i++)
            assert_int_equal(area[i], (i == TILES - 1 ? 15 : i == TILES - 2 ? 3 : 16) * 16);
        assert_true(sched_finished(&s));
        sched_free(&s);
    }
}

/* Batches of pieces: every piece once, each tile complete exactly once
 * (its last piece), raster and cost; static keeps whole tiles. */
static void test_pieces_batches(void **state)
{
    (void)state;
    enum { TILES = 40 };
    double cost[TILES];
    for (int i = 0; i < TILES; i++)
        cost[i] = 1 + (i * 7) % 5;
    const enum sched_policy policies[] = {SCHED_RASTER, SCHED_COST, SCHED_TAIL};
    for (size_t p = 0; p < sizeof policies / sizeof *policies; p++) {
        sched s;
        assert_true(sched_init(&s, policies[p], 4, 2, TILES, table_estimate, cost));
        assert_true(sched_cut(&s, 16));
        for (int i = 0; i < TILES; i++)
            assert_true(sched_add(&s, i, rect_of(i)));
        sched_close(&s);
        int area[TILES] = {0}, items = 0;
        assert_int_equal(drain_done(&s, 8, area, &items), TILES);
        assert_int_equal(items, 16 * TILES);
        for (int i = 0; i < TILES; i++)
            assert_int_equal(area[i], 256);
        assert_true(sched_finished(&s));
        sched_free(&s);
    }
    sched s;
    assert_true(sched_init(&s, SCHED_STATIC, 4, 2, TILES, NULL, NULL));
    assert_true(sched_cut(&s, 16));
    for (int i = 0; i < TILES; i++)
        assert_true(sched_add(&s, i, rect_of(i)));
    sched_close(&s);
    int area[TILES] = {0}, items = 0, complete = 0;
    for (int w = 0; w < 4; w++)
        for (int item; (item = sched_next(&s, w, 0.0)) >= 0; items++) {
            assert_int_equal(s.items[item].piece, 0);
            area[s.items[item].tile] += 256;
            complete += sched_done(&s, item);
        }
    assert_int_equal(items, TILES);
    assert_int_equal(complete, TILES);
    sched_free(&s);
}

/* auto: whole tiles below SCHED_PIECES_WORKERS workers; from there
 * quarters where a worker would have fewer than SCHED_PIECES_ITEMS tiles,
 * a quarter's edge at least SCHED_PIECE_MIN; a request is taken as it is
 * (no finer than a pixel). */
static void test_pieces_auto(void **state)
{
    (void)state;
    int tiles4096 = 128 * 128; /* 4096x4096 in tiles of 32 */
    assert_int_equal(sched_pieces_auto(0, 15, 64 * 64, 32, false), 1);
    assert_int_equal(sched_pieces_auto(0, SCHED_PIECES_WORKERS - 1, 16, 32, false), 1);
    assert_int_equal(sched_pieces_auto(0, 64, tiles4096, 32, false), 1);
    assert_int_equal(sched_pieces_auto(0, 128, tiles4096, 32, false), 1);  /* 128 a worker */
    assert_int_equal(sched_pieces_auto(0, 256, tiles4096, 32, false), 4);  /* 64 -> 256 */
    assert_int_equal(sched_pieces_auto(0, 512, tiles4096, 32, false), 4);  /* 32 -> 128 */
    /* 16 tiles a worker: rank 0's work on the parts outweighs the tail */
    assert_int_equal(sched_pieces_auto(0, 1024, tiles4096, 32, false), 1);
    assert_int_equal(sched_pieces_auto(0, 4096, tiles4096, 32, false), 1);
    assert_int_equal(sched_pieces_auto(0, 1024, 4 * tiles4096, 32, false), 4); /* 8192x8192 */
    assert_int_equal(sched_pieces_auto(0, 1024, 4 * tiles4096, 16, false), 4); /* one cut at most */
    assert_int_equal(sched_pieces_auto(0, 128, tiles4096 / 4, 64, false), 4); /* tile 64 */
    assert_int_equal(sched_pieces_auto(0, 256, tiles4096 / 4, 64, false), 1);
    assert_int_equal(sched_pieces_auto(0, 256, tiles4096, 15, false), 1); /* quarters under 8 */
    assert_int_equal(sched_pieces_auto(4, 2, 10, 32, false), 4);
    assert_int_equal(sched_pieces_auto(64, 2, 10, 7, false), 16); /* cuts of 8 > 7 pixels */
    assert_int_equal(sched_pieces_auto(16, 2, 10, 1, false), 1);
    /* compressed results (a slow link): whole tiles, unless asked */
    assert_int_equal(sched_pieces_auto(0, 1024, tiles4096, 32, true), 1);
    assert_int_equal(sched_pieces_auto(16, 1024, tiles4096, 32, true), 16);
}

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

static void test_batch_limit(void **state)
{
    (void)state;
    assert_int_equal(sched_batch_limit(4, 2, 32), 4);   /* asked: whatever the workers */
    assert_int_equal(sched_batch_limit(40, 2, 32), 32); /* within the protocol's */
    assert_int_equal(sched_batch_limit(0, SCHED_BATCH_WORKERS - 1, 32), 1);
    assert_int_equal(sched_batch_limit(0, SCHED_BATCH_WORKERS, 32), SCHED_BATCH_AUTO);
    assert_int_equal(sched_batch_limit(0, 1024, 4), 4);
    assert_int_equal(sched_batch_limit(-3, 1024, 32), SCHED_BATCH_AUTO);
}

/* Hands everything out in messages the way master.c does
 * (sched_next_batch); the sizes into sizes[], their count. */
static int drain_batches(sched *s, int limit, int *sizes, int cap, bool *seen)
{
    int n = 0, got[PROTO_BATCH_MAX];
    while (n < cap) {
        int k = sched_next_batch(s, n % s->workers, 0.0, limit, got);
        assert_true(k >= 0 && k <= limit);
        if (k == 0)
            break;
        for (int i = 0; i < k; i++) {
            assert_false(seen[got[i]]);
            seen[got[i]] = true;
        }
        sizes[n++] = k;
    }
    return n;
}

/* Large messages while much is ready, shrinking to 1; every item once. */
static void test_batch_sizes(void **state)
{
    (void)state;
    sched s;
    int sizes[256];
    bool seen[160] = {false};
    filled(&s, SCHED_RASTER, 4, 160, NULL, NULL); /* 4 workers x 2 in flight */
    assert_int_equal(sched_batch(&s, 1), 1);        /* limit 1: one item a message */
    assert_int_equal(sched_batch(&s, 4), 4);        /* 160 / 32, capped */
    assert_int_equal(sched_batch(&s, 32), 5);       /* 160 / (4 x 2 x SCHED_BATCH_SPREAD) */
    int n = drain_batches(&s, 8, sizes, 256, seen), total = 0;
    for (int i = 0; i < n; i++) {
        total += sizes[i];
        if (i > 0)
            assert_true(sizes[i] <= sizes[i - 1]); /* never grows: nothing was added */
    }
    assert_int_equal(total, 160);
    assert_int_equal(sizes[0], 5);
    assert_int_equal(sizes[n - 1], 1);
    assert_true(n < 160 / 2); /* far fewer messages than items */
    assert_true(sched_finished(&s));
    sched_free(&s);
}

/* Raster: a batch takes every (ready / size)-th tile, not neighbours. */
static void test_batch_spread(void **state)
{
    (void)state;
    sched s;
    int got[PROTO_BATCH_MAX];
    filled(&s, SCHED_RASTER, 4, 160, NULL, NULL);
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 5); /* 160 / 32: stride 32 */
    for (int i = 0; i < 5; i++)
        assert_int_equal(s.items[got[i]].tile, 32 * i);
    bool seen[160] = {false};
    for (int i = 0; i < 5; i++)
        seen[s.items[got[i]].tile] = true;
    assert_int_equal(sched_next_batch(&s, 1, 0.0, 8, got), 5); /* 155 ready: stride 31 */
    assert_int_equal(s.items[got[0]].tile, 5); /* (tiles 1 .. 4 went where 32 .. 128 were) */
    assert_int_equal(s.items[got[1]].tile, 36);
    for (int i = 0; i < 5; i++) {
        assert_false(seen[s.items[got[i]].tile]); /* none handed out twice */
        seen[s.items[got[i]].tile] = true;
    }
    assert_int_equal(s.items[got[0]].order, 5);
    sched_free(&s);
}

/* Cost: a batch costs at most the larger of its share of the estimate
 * left (over one round: SCHED_BATCH_SPREAD_COST) and the largest tile:
 * the costliest tiles go alone, cheap ones together, as many as the
 * count allows. */
static void test_batch_cost(void **state)
{
    (void)state;
    double cost[64];
    for (int i = 0; i < 64; i++)
        cost[i] = i < 2 ? 100.0 : 1.0; /* two expensive tiles, 62 cheap */
    sched s;
    int got[PROTO_BATCH_MAX];
    filled(&s, SCHED_COST, 1, 64, table_estimate, cost); /* 1 x 2 x 2 a round */
    assert_int_equal(SCHED_BATCH_SPREAD_COST, 2);
    assert_true(fabs(s.ready_estimate - 262.0) < 1e-9);
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 1); /* 100 + 100 > max(262 / 4, 100) */
    assert_int_equal(s.items[got[0]].tile, 0);
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 1); /* 100 + 1 > 100 */
    assert_int_equal(s.items[got[0]].tile, 1);
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 16, got), 16); /* the limit: 16 <= 100 */
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 4, got), 4);   /* the limit 4 */
    assert_true(fabs(s.ready_estimate - 42.0) < 1e-9);
    sched_free(&s);
    for (int i = 0; i < 64; i++)
        cost[i] = i < 8 ? 30.0 : 1.0; /* the largest tile: 30 */
    filled(&s, SCHED_COST, 1, 64, table_estimate, cost); /* 296 in all */
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 2); /* 296 / 4 = 74: 2 x 30 */
    for (int left = 236; left > 86; left -= 30) /* 59, 51.5, 44, 36.5, 29 (or the */
        assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 1); /* largest, 30) */
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 1); /* 86 / 4: 30 + 1 > 30 */
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 8); /* 56 / 4 < 30: 8 x 1 */
    sched_free(&s);
}

/* Relays (sched_batch_floor): a batch takes at least the floor while
 * much is left, however cheap the guided share or the cost budget; once
 * what is left spread over the slots is less, that much, down to 1. */
static void test_batch_floor(void **state)
{
    (void)state;
    sched s;
    int got[PROTO_BATCH_MAX];
    filled(&s, SCHED_RASTER, 4, 160, NULL, NULL); /* 4 relays x 2 in flight */
    assert_int_equal(sched_batch(&s, 32), 5);       /* 160 / (4 x 2 x 4): guided */
    sched_batch_floor(&s, 8, 16);                   /* 4 relays x 4 TILEs */
    assert_int_equal(sched_batch(&s, 32), 8);       /* the floor */
    assert_int_equal(sched_batch(&s, 6), 6);        /* the limit still wins */
    int left = 160;
    while (left > 0) {
        int k = sched_next_batch(&s, 0, 0.0, 32, got);
        int floor = (left + 15) / 16 < 8 ? (left + 15) / 16 : 8;
        int guided = (left + 31) / 32;
        int want = guided > floor ? guided : floor;
        assert_int_equal(k, want < left ? want : left);
        left -= k;
    }
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 32, got), 0);
    assert_true(sched_finished(&s));
    sched_free(&s);

    filled(&s, SCHED_RASTER, 4, 160, NULL, NULL);
    sched_batch_floor(&s, 8, 0); /* no slots: no floor */
    assert_int_equal(sched_batch(&s, 32), 5);
    sched_free(&s);

    double cost[64]; /* cost cut: the floor goes past the budget */
    for (int i = 0; i < 64; i++)
        cost[i] = i < 2 ? 100.0 : 1.0;
    filled(&s, SCHED_COST, 1, 64, table_estimate, cost);
    sched_batch_floor(&s, 4, 8);
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 4); /* 100 + 100 + 1 + 1 */
    assert_int_equal(s.items[got[0]].tile, 0);
    assert_int_equal(s.items[got[1]].tile, 1);
    sched_free(&s);
}

/* Raster with estimates (hetero): the same cost cut, in raster order;
 * without (homo) the count alone, over SCHED_BATCH_SPREAD rounds. */
static void test_batch_raster_cost(void **state)
{
    (void)state;
    double cost[64];
    for (int i = 0; i < 64; i++)
        cost[i] = i == 0 ? 100.0 : 1.0;
    sched s;
    int got[PROTO_BATCH_MAX];
    filled(&s, SCHED_RASTER, 1, 64, table_estimate, cost);
    assert_true(fabs(s.ready_estimate - 163.0) < 1e-9);
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 1); /* tile 0 (100), then 8 (1): */
    assert_int_equal(s.items[got[0]].tile, 0);                 /* 101 > max(163 / 4, 100) */
    assert_true(fabs(s.ready_estimate - 63.0) < 1e-9);
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 8, got), 8); /* cheap: the limit */
    assert_true(fabs(s.ready_estimate - 55.0) < 1e-9);
    sched_free(&s);
    filled(&s, SCHED_RASTER, 1, 64, NULL, NULL);
    assert_int_equal(sched_next_batch(&s, 0, 0.0, 16, got), 8); /* 64 / (1 x 2 x 4) */
    sched_free(&s);
}

/* Tail: once tiles are split, one piece a message. */
static void test_batch_tail(void **state)
{
    (void)state;
    double cost[16] = {9, 8, 7, 6, 5, 4, 3, 2, 1, 1, 1, 1, 1, 1, 1, 1};
    sched s;
    filled(&s, SCHED_TAIL, 1, 16, table_estimate, cost); /* tail from 4 tiles left */
    int pieces = 0, got[PROTO_BATCH_MAX], k;
    while ((k = sched_next_batch(&s, 0, 0.0, 8, got)) > 0) {
        for (int i = 0; i < k; i++) {
            if (s.items[got[i]].piece > 0) {
                assert_int_equal(k, 1);
                pieces++;
            }
        }
    }
    assert_int_equal(pieces, 4 * 4);
    assert_true(sched_finished(&s));
    sched_free(&s);
}

/* While the pass goes on, the tiles it has not reached count too, as
 * the known ones do (skipped ones as nothing). */
static void test_batch_unknown(void **state)
{
    (void)state;
    double cost[128];
    for (int i = 0; i < 128; i++)
        cost[i] = 1.0;
    sched s, c;
    int got[PROTO_BATCH_MAX];
    assert_true(sched_init(&s, SCHED_RASTER, 1, 2, 128, NULL, NULL));
    assert_true(sched_init(&c, SCHED_COST, 1, 2, 128, table_estimate, cost));
    for (int i = 0; i < 32; i++) { /* a quarter known: half of it skipped */
        assert_true(i % 2 ? sched_skip(&s, i, rect_of(i)) : sched_add(&s, i, rect_of(i)));
        assert_true(i % 2 ? sched_skip(&c, i, rect_of(i)) : sched_add(&c, i, rect_of(i)));
    }
    /* 16 ready + 96 unknown x 16 / 32 = 64 left: 64 / (1 x 2 x 4) = 8 */
    assert_int_equal(sched_batch(&s, 32), 8);
    /* the same in estimates, over SCHED_BATCH_SPREAD_COST rounds: 64 / 4 =
     * 16 tiles of 1 */
    assert_int_equal(sched_batch(&c, 32), 16);
    assert_int_equal(sched_next_batch(&c, 0, 0.0, 32, got), 16);
    sched_close(&s);
    assert_int_equal(sched_batch(&s, 32), 2); /* closed: the 16 ready only */
    sched_free(&s);
    sched_free(&c);
}

/* A lost worker's items count as ready. */
static void test_batch_requeued(void **state)
{
    (void)state;
    sched s;
    int got[40];
    filled(&s, SCHED_RASTER, 1, 20, NULL, NULL); /* one worker: 2 x 4 a round */
    assert_int_equal(drain(&s, 0, got, 20), 20);
    assert_int_equal(sched_batch(&s, 8), 1); /* nothing ready */
    for (int i = 0; i < 12; i++)
        assert_true(sched_requeue(&s, got[i]));
    assert_int_equal(sched_batch(&s, 8), 2); /* 12 / (1 x 2 x 4), rounded up */
    sched_free(&s);
}

/* Parts start 8-byte aligned; nothing follows the last; the cap. */
static void test_batch_bytes(void **state)
{
    (void)state;
    size_t odd = proto_result_part(49, PIXELS_FLOAT); /* 49 pixels: 4 bytes short of 8 */
    assert_int_equal(odd % 8, 4);
    assert_int_equal(proto_batch_bytes(odd, 1), odd);
    assert_int_equal(proto_batch_bytes(odd, 3), 2 * (odd + 4) + odd);
    assert_int_equal(proto_master_limit(49, 1), odd > sizeof(proto_fail) ? odd : sizeof(proto_fail));
    assert_int_equal(proto_batch_fit(8, 64 * 64), 8); /* 8 x 49 KB */
    size_t big = 512 * 512;                         /* 3 MB a tile */
    assert_int_equal(proto_batch_fit(8, big), 1);
    int fit = proto_batch_fit(PROTO_BATCH_MAX, 128 * 128);
    size_t part = proto_result_part(128 * 128, PIXELS_FLOAT);
    assert_true(fit > 1 && proto_batch_bytes(part, fit) <= PROTO_BATCH_BYTES);
    assert_true(proto_batch_bytes(part, fit + 1) > PROTO_BATCH_BYTES);
    /* 8-bit parts: 3 bytes a pixel (the limits stay those of floats: one
     * limit for every output) */
    assert_int_equal(proto_result_part(49, PIXELS_RGB8), sizeof(proto_result) + 49 * 3);
    assert_int_equal(proto_result_part(49, PIXELS_RGB8) + 49 * 9, odd);
    /* compressed parts: a part of one pixel may take more than its floats
     * (a frame's header and checksum), and the limits leave room for it */
    assert_true(proto_result_part_max(1) >= sizeof(proto_result) + pixels_compress_bound(3));
    assert_true(proto_result_part_max(1) > proto_result_part(1, PIXELS_FLOAT));
    assert_true(proto_master_limit(1, 1) >= proto_result_part_max(1));
    assert_int_equal(proto_result_part_max(49), odd);
}

/* A result's header goes without its paging counts unless a worker pages
 * (PROTO_RESULT_PAGING): 96 bytes or 216, both multiples of 8; read back,
 * absent counts are zero whatever the buffer held; a header cut short is
 * refused. */
static void test_result_head(void **state)
{
    (void)state;
    char wire[sizeof(proto_result) + 16];
    proto_result h = {.index = 7, .hits = 3, .x = 48, .y = 16, .busy_s = 0.25,
                      .pixels = PIXELS_RGB8};
    h.paging.faults = 99; /* (not sent: no flag) */
    memset(wire, 0x5a, sizeof wire);
    size_t head = proto_result_write(wire, &h);
    assert_int_equal(head, PROTO_RESULT_HEAD_MIN);
    assert_int_equal(head, 96);
    assert_int_equal(head % 8, 0);
    assert_true(head + sizeof h.paging == sizeof h);
    proto_result back;
    memset(&back, 0xff, sizeof back);
    assert_int_equal(proto_result_read(wire, sizeof wire, &back), head);
    assert_int_equal(back.index, 7);
    assert_int_equal(back.hits, 3);
    assert_int_equal(back.x, 48); /* (the rectangle: which item it answers) */
    assert_int_equal(back.y, 16);
    assert_true(back.busy_s == 0.25);
    assert_int_equal(back.paging.faults, 0); /* (0x5a bytes after the header: ignored) */
    assert_int_equal(proto_result_part_of(&back, 49, PIXELS_RGB8), head + 49 * 3);
    assert_int_equal(proto_result_read(wire, head - 1, &back), 0);

    h.flags = PROTO_RESULT_PAGING;
    head = proto_result_write(wire, &h);
    assert_int_equal(head, sizeof(proto_result));
    assert_int_equal(proto_result_read(wire, sizeof wire, &back), head);
    assert_int_equal(back.paging.faults, 99);
    assert_int_equal(proto_result_part_of(&back, 49, PIXELS_FLOAT),
                     proto_result_part(49, PIXELS_FLOAT));
    assert_int_equal(proto_result_read(wire, head - 8, &back), 0); /* (its counts cut off) */
    /* compressed: the header's bytes and the payload */
    h = (proto_result){.pixels = PIXELS_RGB8Z, .payload = 40};
    assert_int_equal(proto_result_part_of(&h, 49, PIXELS_RGB8Z), PROTO_RESULT_HEAD_MIN + 40);
}

/* The batches rank 0 keeps at a relay: 16 (8 with costs) up to groups of
 * 16 workers, then one a worker (one for two), at most 32 (16): never
 * more than a relay holds. */
static void test_relay_depth(void **state)
{
    (void)state;
    for (int costs = 0; costs <= 1; costs++) {
        int least = costs ? PROTO_RELAY_DEPTH_COST : PROTO_RELAY_DEPTH;
        assert_int_equal(proto_relay_depth(1, costs), least);
        assert_int_equal(proto_relay_depth(16, costs), least);
        assert_int_equal(proto_relay_depth(24, costs), costs ? 12 : 24);
        assert_int_equal(proto_relay_depth(32, costs), 2 * least);
        assert_int_equal(proto_relay_depth(1000, costs), 2 * least);
        for (int g = 0; g < 200; g++)
            assert_true(proto_relay_depth(g, costs) <= PROTO_RELAY_IN_FLIGHT);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_raster_order),
        cmocka_unit_test(test_result_head),
        cmocka_unit_test(test_relay_depth),
        cmocka_unit_test(test_cost_order),
        cmocka_unit_test(test_cost_without_estimates),
        cmocka_unit_test(test_static_assignment),
        cmocka_unit_test(test_region),
        cmocka_unit_test(test_requeue),
        cmocka_unit_test(test_fill),
        cmocka_unit_test(test_fill_pieces),
        cmocka_unit_test(test_static_release),
        cmocka_unit_test(test_tail_split),
        cmocka_unit_test(test_tail_one_pixel),
        cmocka_unit_test(test_pieces),
        cmocka_unit_test(test_pieces_batches),
        cmocka_unit_test(test_pieces_auto),
        cmocka_unit_test(test_batch_limit),
        cmocka_unit_test(test_batch_sizes),
        cmocka_unit_test(test_batch_spread),
        cmocka_unit_test(test_batch_cost),
        cmocka_unit_test(test_batch_raster_cost),
        cmocka_unit_test(test_batch_floor),
        cmocka_unit_test(test_batch_tail),
        cmocka_unit_test(test_batch_unknown),
        cmocka_unit_test(test_batch_requeued),
        cmocka_unit_test(test_batch_bytes),
        cmocka_unit_test(test_spearman),
        cmocka_unit_test(test_estimate_ranks_materials),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
