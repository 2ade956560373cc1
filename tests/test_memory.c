/*
 * test_memory.c — the image's pages faulted in by a thread of their own
 * (host/memory.h, memory_prefault_*): the pages become resident, what the
 * master stores meanwhile is kept, small images go without a thread; and
 * the image's memory (memory_pages_alloc): a large one aligned to 2 MiB
 * and in huge pages where the kernel grants them on request; the peak's
 * estimate counts the tiles' bookkeeping (render_memory_need).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include <cmocka.h>

#include "../host/memory.h"

#define BIG ((size_t)24 << 20) /* over the 8 MiB below which no thread runs */

/* Pages of [p, p + n) resident now; -1 when mincore cannot say. */
static long resident_pages(const void *p, size_t n)
{
    long page = sysconf(_SC_PAGESIZE);
    uintptr_t first = ((uintptr_t)p + (uintptr_t)page - 1) / (uintptr_t)page * (uintptr_t)page;
    uintptr_t end = ((uintptr_t)p + n) / (uintptr_t)page * (uintptr_t)page;
    size_t count = (end - first) / (size_t)page;
    unsigned char *v = malloc(count);
    if (!v || mincore((void *)first, end - first, v) != 0) {
        free(v);
        return -1;
    }
    long in = 0;
    for (size_t i = 0; i < count; i++)
        in += v[i] & 1;
    free(v);
    return in;
}

/* Untouched, the image's pages are resident once the thread is done
 * (where the kernel has MADV_POPULATE_WRITE: 5.14 on). */
static void test_pages_become_resident(void **state)
{
    (void)state;
    char *image = malloc(BIG);
    assert_non_null(image);
    long before = resident_pages(image, BIG);
    memory_prefault p;
    memory_prefault_start(&p, image, BIG);
    assert_true(p.running);
    memory_prefault_join(&p);
    assert_false(p.running);
    long page = sysconf(_SC_PAGESIZE), all = (long)(BIG / (size_t)page) - 1;
    long after = resident_pages(image, BIG);
    if (before >= 0 && madvise(image + page, (size_t)page, MADV_POPULATE_WRITE) == 0) {
        assert_true(before < all / 2); /* (fresh memory: mostly not yet) */
        assert_true(after >= all - 1);
    }
    memory_prefault_join(&p); /* (again: nothing to wait for) */
    free(image);
}

/* Several arrays at once (the pass's hit records): every page of each
 * resident once the thread is done, what was written meanwhile kept, a
 * NULL array and one under a page skipped; arrays of under 8 MiB in all
 * go without a thread. */
static void test_arrays_become_resident(void **state)
{
    (void)state;
    size_t sizes[4] = {BIG / 2, BIG / 4 + 100, 0, 1000};
    char *a = memory_pages_alloc(sizes[0], false), *b = memory_pages_alloc(sizes[1], false);
    char *tiny = memory_pages_alloc(sizes[3], false);
    assert_non_null(a);
    assert_non_null(b);
    assert_non_null(tiny);
    void *const arrays[4] = {a, b, NULL, tiny};
    memory_prefault p;
    memory_prefault_start_arrays(&p, arrays, sizes, 4);
    assert_true(p.running);
    assert_int_equal(p.count, 2); /* (the NULL one and the one under a page: none) */
    b[7] = 42;
    memory_prefault_join(&p);
    long page = sysconf(_SC_PAGESIZE);
    if (madvise(a, (size_t)page, MADV_POPULATE_WRITE) == 0) {
        assert_int_equal(resident_pages(a, sizes[0]), (long)(sizes[0] / (size_t)page));
        assert_int_equal(resident_pages(b, sizes[1]), (long)(sizes[1] / (size_t)page));
    }
    assert_int_equal(b[7], 42);
    size_t small[2] = {(size_t)3 << 20, (size_t)4 << 20};
    void *const two[2] = {a, b};
    memory_prefault_start_arrays(&p, two, small, 2);
    assert_false(p.running);
    free(a);
    free(b);
    free(tiny);
}

/* Stores made while the thread runs are all there afterwards. */
static void test_stores_meanwhile_are_kept(void **state)
{
    (void)state;
    size_t n = BIG / sizeof(float);
    float *image = malloc(BIG);
    assert_non_null(image);
    memory_prefault p;
    memory_prefault_start(&p, image, BIG);
    for (size_t i = 0; i < n; i++)
        image[i] = (float)(i % 1000) * 0.5f;
    memory_prefault_join(&p);
    for (size_t i = 0; i < n; i++)
        if (image[i] != (float)(i % 1000) * 0.5f)
            fail_msg("float %zu changed", i);
    free(image);
}

static void test_small_images_go_without(void **state)
{
    (void)state;
    char *image = malloc(1 << 20);
    assert_non_null(image);
    memory_prefault p;
    memory_prefault_start(&p, image, 1 << 20);
    assert_false(p.running);
    memory_prefault_join(&p);
    memory_prefault_start(&p, NULL, BIG);
    assert_false(p.running);
    free(image);
}

/* Does this kernel give transparent huge pages on request ("always" or
 * "madvise" chosen)? */
static bool huge_pages_on_request(void)
{
    char line[128] = "";
    FILE *f = fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r");
    if (!f)
        return false;
    bool on = fgets(line, sizeof line, f) && !strstr(line, "[never]");
    fclose(f);
    return on;
}

/* kB of huge pages in the mapping that holds p (/proc/self/smaps); -1 when
 * it cannot be read. */
static long huge_kb_at(const void *p)
{
    FILE *f = fopen("/proc/self/smaps", "r");
    if (!f)
        return -1;
    char line[512];
    bool inside = false;
    long kb = -1;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2 && strchr(line, '-') < strchr(line, ' '))
            inside = (uintptr_t)p >= lo && (uintptr_t)p < hi;
        else if (inside && sscanf(line, "AnonHugePages: %ld kB", &kb) == 1)
            break;
    }
    fclose(f);
    return kb;
}

static void test_image_memory(void **state)
{
    (void)state;
    float *small = memory_pages_alloc(1000, true);
    assert_non_null(small);
    assert_int_equal((uintptr_t)small % 4096, 0); /* (a device may write it in place) */
    small[249] = 1.0f;
    free(small);
    char *image = memory_pages_alloc(BIG + 12345, true);
    assert_non_null(image);
    assert_int_equal((uintptr_t)image % ((uintptr_t)2 << 20), 0);
    memset(image, 1, BIG + 12345);
    if (huge_pages_on_request())
        assert_true(huge_kb_at(image) > 0);
    free(image);
    char *records = memory_pages_alloc(BIG + 12345, false); /* (the hit records) */
    assert_non_null(records);
    assert_int_equal((uintptr_t)records % 4096, 0);
    free(records);
}

/* The estimate counts the master's bookkeeping of every tile: --tile 1 at
 * 2000x2000 (4 M tiles) peaked at 458 MB, ~101 bytes a tile beyond the
 * image, when the estimate was the image's 48 MB and the encoder's. */
static void test_estimate_counts_the_tiles(void **state)
{
    (void)state;
    render_memory one = render_memory_need(2000, 2000, 1, 1, 4, 0, "x.png");
    render_memory big = render_memory_need(2000, 2000, 32, 1, 4, 0, "x.png");
    assert_true(one.tiles >= 4000000ull * 101);
    assert_int_equal(one.total, one.image + one.writer + one.tiles);
    assert_int_equal(big.tiles, 63ull * 63 * memory_tile_bytes(false)); /* (2000 / 32: 63 a side) */
    assert_true(one.total - big.total >= 400ull << 20);
    render_memory hetero = render_memory_need(2000, 2000, 1, 1, 4, 128, "x.png");
    assert_true(memory_tile_bytes(true) > memory_tile_bytes(false));
    assert_int_equal(hetero.tiles, 4000000ull * memory_tile_bytes(true));
    /* the module's formats are written during the tile phase too: their
     * band counted beside the records (8-bit: a strip of bytes; EXR: a
     * band of floats and its compressed copy) */
    render_memory exr = render_memory_need(2000, 2000, 32, 1, 4, 128, "x.exr");
    render_memory tif = render_memory_need(2000, 2000, 32, 1, 4, 128, "x.tif");
    assert_int_equal(exr.writer, 2ull * 64 * 2000 * 12);
    assert_int_equal(tif.writer, 64ull * 2000 * 3);
    assert_int_equal(exr.total, exr.image + exr.tiles + exr.records + exr.device + exr.writer);
    assert_int_equal(tif.total, tif.image + tif.tiles + tif.records + tif.device + tif.writer);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pages_become_resident),
        cmocka_unit_test(test_stores_meanwhile_are_kept),
        cmocka_unit_test(test_arrays_become_resident),
        cmocka_unit_test(test_small_images_go_without),
        cmocka_unit_test(test_image_memory),
        cmocka_unit_test(test_estimate_counts_the_tiles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
