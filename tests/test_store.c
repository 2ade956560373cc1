/*
 * test_store.c — the store thread (host/store.h): every queued part ends
 * in the image as the loop would have stored it, across many turns of the
 * ring; a complete tile is given back for the journal only once all that
 * was queued before it is stored, in order; a part larger than the ring
 * is refused (the caller stores it); stopping drains the ring.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../host/pixels.h"
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

/* 80 rounds over the 150 tiles: 15 MB through the 8 MiB ring (its end
 * passed once at least). */
static void test_every_part_stored(void **state)
{
    (void)state;
    store *s = store_start(image, W, W / T * (H / T));
    assert_non_null(s);
    for (int round = 0; round < 80; round++) {
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
    /* (the records' bytes: what went through the ring) */
    assert_true(80.0 * (W / T) * (H / T) * (STORE_ALIGN + T * T * 3) > 1.5 * STORE_RING_BYTES);
    store_stop(s);
}

/* store_after: at once when nothing is queued; else later, in order, and
 * only once everything queued before the tile is in the image. */
static void test_tiles_given_back_once_stored(void **state)
{
    (void)state;
    memset(image, 0, sizeof image);
    store *s = store_start(image, W, W / T * (H / T));
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
    (void)state;
    enum { BW = 2000, BH = 1500 }; /* 9 MB of bytes */
    float *big = calloc((size_t)BW * BH * 3, sizeof *big);
    uint8_t *src = calloc((size_t)BW * BH * 3, 1);
    assert_non_null(big);
    assert_non_null(src);
    store *s = store_start(big, BW, 1);
    assert_non_null(s);
    tile_rect all = {0, 0, BW, BH};
    assert_false(store_queue(s, all, src));
    for (size_t i = 0; i < 300 * 3; i++)
        src[i] = 255;
    tile_rect row = {0, 7, 300, 1};
    assert_true(store_queue(s, row, src));
    store_stop(s);
    for (size_t i = 0; i < 300 * 3; i++)
        assert_true(big[(size_t)7 * BW * 3 + i] == 1.0f);
    assert_true(big[0] == 0.0f);
    free(big);
    free(src);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_part_stored),
        cmocka_unit_test(test_tiles_given_back_once_stored),
        cmocka_unit_test(test_too_large_refused_and_stop_drains),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
