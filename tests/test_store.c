/*
 * test_store.c — the store threads (host/store.h), one and several: every
 * queued part ends in the image as the loop would have stored it, across
 * many turns of the rings; a complete tile is given back for the journal
 * only once all that was queued before it is stored, in order; a part
 * larger than a ring is refused (the caller stores it); stopping drains
 * the rings.  Each test runs with 1 and with 3 threads (the state).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../comm/pixels.h"
#include "../comm/pixels_z.h"
#include "../host/store.h"

enum { W = 300, H = 200, T = 20 }; /* tiles of 20x20: 15 x 10 */

static float image[W * H * 3], want[W * H * 3];
static uint8_t bytes[T * T * 3];

/* Tile `index`'s rectangle, and bytes of its own (a function of `round`). */
static tile_rect tile_of(int index)
{
    tile_rect r = {index % (W / T) * T, index / (W / T) * T, T, T};
    return r;
}

static void fill_bytes(int index, int round)
{
    for (size_t i = 0; i < sizeof bytes; i++)
        bytes[i] = (uint8_t)(i * 31u + (unsigned)index * 7u + (unsigned)round * 13u);
}

/* What the master's loop stores for those bytes. */
static void expect(tile_rect r)
{
    pixels_store_bytes_rect(want, W, r.x, r.y, r.width, r.height, bytes);
}

static int threads_of(void **state)
{
    return *(const int *)*state;
}

/* 80 rounds a thread over the 150 tiles: 15 MB a thread through the 8 MiB
 * rings (each ring's end passed once at least). */
static void test_every_part_stored(void **state)
{
    memset(image, 0, sizeof image);
    store *s = store_start(image, W, W / T * (H / T), threads_of(state));
    assert_non_null(s);
    assert_int_equal(store_threads(s), threads_of(state));
    int rounds = 80 * threads_of(state);
    for (int round = 0; round < rounds; round++) {
        for (int i = 0; i < W / T * (H / T); i++) {
            fill_bytes(i, round);
            tile_rect r = tile_of(i);
            expect(r);
            while (!store_queue(s, r, bytes)) /* (full: the thread catches up) */
                store_drain(s);
        }
        store_drain(s);
        assert_memory_equal(image, want, sizeof image);
    }
    /* (the records' bytes: what went through the rings, each about its
     * share: the ties rotate) */
    assert_true((double)rounds * (W / T) * (H / T) * (STORE_ALIGN + T * T * 3) >
                1.5 * STORE_RING_BYTES * threads_of(state));
    store_stop(s);
}

/* store_after: at once when nothing is queued; else later, in order, and
 * only once everything queued before the tile is in the image. */
static void test_tiles_given_back_once_stored(void **state)
{
    memset(image, 0, sizeof image);
    store *s = store_start(image, W, W / T * (H / T), threads_of(state));
    assert_non_null(s);
    assert_true(store_after(s, 3)); /* nothing queued */
    int tile;
    assert_false(store_finished(s, &tile, false));
    int deferred[20], n = 0;
    for (int i = 0; i < 20; i++) {
        fill_bytes(i, 0);
        expect(tile_of(i));
        assert_true(store_queue(s, tile_of(i), bytes));
        if (!store_after(s, i))
            deferred[n++] = i;
    }
    int next = 0;
    while (store_finished(s, &tile, true)) {
        assert_true(next < n);
        assert_int_equal(tile, deferred[next]);
        tile_rect r = tile_of(tile); /* its pixels are there when it comes back */
        for (int row = 0; row < r.height; row++) {
            size_t at = ((size_t)(r.y + row) * W + (size_t)r.x) * 3;
            assert_memory_equal(image + at, want + at, (size_t)r.width * 3 * sizeof(float));
        }
        next++;
    }
    assert_int_equal(next, n);
    store_stop(s);
}

/* A part larger than the whole ring is refused, nothing queued; stopping
 * with parts queued stores them first. */
static void test_too_large_refused_and_stop_drains(void **state)
{
    enum { BW = 2000, BH = 1500 }; /* 9 MB of bytes */
    float *big = calloc((size_t)BW * BH * 3, sizeof *big);
    uint8_t *src = calloc((size_t)BW * BH * 3, 1);
    assert_non_null(big);
    assert_non_null(src);
    store *s = store_start(big, BW, 1, threads_of(state));
    assert_non_null(s);
    tile_rect all = {0, 0, BW, BH};
    assert_false(store_queue(s, all, src));
    for (size_t i = 0; i < 300 * 3; i++)
        src[i] = 255;
    for (int y = 7; y < 11; y++) { /* (with 3 threads: in more than one ring) */
        tile_rect row = {0, y, 300, 1};
        assert_true(store_queue(s, row, src));
    }
    store_stop(s);
    for (int y = 7; y < 11; y++)
        for (size_t i = 0; i < 300 * 3; i++)
            assert_true(big[(size_t)y * BW * 3 + i] == 1.0f);
    assert_true(big[0] == 0.0f);
    free(big);
    free(src);
}

/* The thread count is clamped to 1 .. STORE_THREADS_MAX; NULL has none;
 * auto's count for so many workers. */
static void test_thread_count(void **state)
{
    (void)state;
    assert_int_equal(store_threads(NULL), 0);
    int asked[] = {0, 1, 2, STORE_THREADS_MAX + 5}, got[] = {1, 1, 2, STORE_THREADS_MAX};
    for (int i = 0; i < 4; i++) {
        store *s = store_start(image, W, 4, asked[i]);
        assert_non_null(s);
        assert_int_equal(store_threads(s), got[i]);
        store_stop(s);
    }
    /* --store-threads auto: one a STORE_WORKERS_A_THREAD workers, 1 to the most */
    int workers[] = {0, 1, 15, 64, 65, 256, 512, 1024, 100000};
    int threads[] = {1, 1, 1, 1, 2, 4, 8, 8, STORE_THREADS_MAX};
    for (int i = 0; i < 9; i++)
        assert_int_equal(store_threads_auto(workers[i]), threads[i]);
}

/* Compressed parts (--compress): the threads decompress each into its
 * tile, the image as with plain bytes; then one part that is not a frame
 * (tag 7): store_corrupt names it, nothing of it is stored, and no tile is
 * ever given back as complete after it. */
static void test_compressed_parts_and_a_corrupt_one(void **state)
{
    memset(image, 0, sizeof image);
    memset(want, 0, sizeof want);
    store *s = store_start(image, W, W / T * (H / T), threads_of(state));
    pixels_zstream *z = pixels_compressor_new();
    assert_non_null(s);
    assert_non_null(z);
    uint8_t frame[pixels_compress_bound(sizeof bytes)];
    for (int i = 0; i < W / T * (H / T); i++) {
        fill_bytes(i, 1);
        expect(tile_of(i));
        size_t len = pixels_compress(z, bytes, sizeof bytes, frame);
        assert_true(len > 0);
        assert_true(store_queue_compressed(s, tile_of(i), frame, len, i));
    }
    store_drain(s);
    assert_int_equal(store_corrupt(s), -1);
    assert_memory_equal(image, want, sizeof image);
    assert_true(store_after(s, 1)); /* (all in: complete at once) */
    memset(frame, 0xab, 40);
    assert_true(store_queue_compressed(s, tile_of(0), frame, 40, 7));
    store_drain(s);
    assert_int_equal(store_corrupt(s), 7);
    assert_memory_equal(image, want, sizeof image); /* (nothing of it stored) */
    assert_false(store_after(s, 0));
    int tile;
    assert_false(store_finished(s, &tile, true));
    pixels_zstream_free(z);
    store_stop(s);
}

static int one = 1, three = 3;

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_prestate(test_every_part_stored, &one),
        cmocka_unit_test_prestate(test_tiles_given_back_once_stored, &one),
        cmocka_unit_test_prestate(test_too_large_refused_and_stop_drains, &one),
        cmocka_unit_test_prestate(test_every_part_stored, &three),
        cmocka_unit_test_prestate(test_tiles_given_back_once_stored, &three),
        cmocka_unit_test_prestate(test_too_large_refused_and_stop_drains, &three),
        cmocka_unit_test_prestate(test_compressed_parts_and_a_corrupt_one, &one),
        cmocka_unit_test_prestate(test_compressed_parts_and_a_corrupt_one, &three),
        cmocka_unit_test(test_thread_count),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
