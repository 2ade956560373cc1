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
 *     equal to the whole pass's;
 *   - on a device in host memory (PoCL's CPU device) with arrays from
 *     memory_pages_alloc and slices that start aligned, the kernels write
 *     the records in place (timing.records_in_place), the shadow answers
 *     too, ended early or limited as well: the same records, bit for bit,
 *     as copied out of device buffers (unaligned slices, or a context
 *     told to copy);
 *   - a device sliced as a GPU is (ocl_options.slice_records: at least so
 *     many records a slice, in whole tile rows) takes fewer, larger
 *     slices than the caller asks, with the same records.
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
#include "../host/memory.h"
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

/* A pass's records in arrays of memory_pages_alloc (NULL known: no shadow
 * answers). */
typedef struct {
    float *t;
    uint32_t *surf, *known, *lit, *hits;
} aligned_records;

static aligned_records aligned_alloc_records(bool shadows)
{
    size_t n = (size_t)W * H, tiles = sizeof ((records *)0)->hits / sizeof(uint32_t);
    aligned_records a = {memory_pages_alloc(n * sizeof(float), false),
                         memory_pages_alloc(n * sizeof(uint32_t), false),
                         shadows ? memory_pages_alloc(n * sizeof(uint32_t), false) : NULL,
                         shadows ? memory_pages_alloc(n * sizeof(uint32_t), false) : NULL,
                         calloc(tiles, sizeof(uint32_t))};
    assert_non_null(a.t);
    assert_non_null(a.surf);
    assert_non_null(a.hits);
    assert_true(!shadows || (a.known && a.lit));
    return a;
}

/* Every record made wrong, so that one a pass does not write shows. */
static void clear_records(aligned_records *a)
{
    size_t n = (size_t)W * H;
    memset(a->t, 0xff, n * sizeof *a->t);
    memset(a->surf, 0xff, n * sizeof *a->surf);
    if (a->known) {
        memset(a->known, 0xff, n * sizeof *a->known);
        memset(a->lit, 0xff, n * sizeof *a->lit);
    }
}

static void aligned_free_records(aligned_records *a)
{
    free(a->t);
    free(a->surf);
    free(a->known);
    free(a->lit);
    free(a->hits);
}

/* A background pass of `slice` rows over a, polled to its end (or to
 * `limit` rows when below H), its timing into *out (NULL: none); whether
 * it wrote in place. */
static bool run_pass_timed(ocl_ctx *ctx, const void *blob, int slice, int limit,
                           aligned_records *a, ocl_timing *out)
{
    csg_diag d = {{0}, 0};
    ocl_timing tm;
    memset(&tm, 0, sizeof tm);
    ocl_pass *p = NULL;
    clear_records(a);
    assert_true(ocl_pass_begin(ctx, blob, TILE, slice, a->t, a->surf, a->known, a->lit, a->hits,
                               NULL, NULL, &p, &d));
    if (limit < H)
        ocl_pass_limit(p, limit);
    int rows = 0;
    while (rows < limit)
        assert_true((rows = ocl_pass_rows(p, true, &d)) >= 0);
    assert_true(ocl_pass_end(p, &tm, &d));
    if (out)
        *out = tm;
    return tm.records_in_place;
}

static bool run_pass(ocl_ctx *ctx, const void *blob, int slice, int limit, aligned_records *a)
{
    return run_pass_timed(ctx, blob, slice, limit, a, NULL);
}

static void assert_records_equal(const aligned_records *a, const aligned_records *b, int rows)
{
    size_t n = (size_t)W * (size_t)rows;
    assert_memory_equal(a->t, b->t, n * sizeof *a->t);
    assert_memory_equal(a->surf, b->surf, n * sizeof *a->surf);
    if (a->known) {
        assert_memory_equal(a->known, b->known, n * sizeof *a->known);
        assert_memory_equal(a->lit, b->lit, n * sizeof *a->lit);
    }
    for (int i = 0; i < rows / TILE * ((W + TILE - 1) / TILE); i++)
        assert_int_equal(a->hits[i], b->hits[i]);
}

/* A context of the default device told to copy its records out of device
 * buffers (ocl_options.copy_buffers), as on a discrete GPU; *tm its
 * opening's timing. */
static ocl_ctx *open_copying(ocl_timing *tm)
{
    csg_diag d = {{0}, 0};
    memset(tm, 0, sizeof *tm);
    ocl_options copy_opt = {.copy_buffers = 1};
    ocl_ctx *copying = NULL;
    assert_true(ocl_open(&copy_opt, &copying, tm, &d));
    return copying;
}

static void test_in_place(void **state)
{
    fixture *fx = *state;
    ocl_timing tm;
    ocl_ctx *copying = open_copying(&tm);
    /* W = 90 floats a row: 16 rows start every slice on 128 bytes (PoCL's
     * CL_DEVICE_MEM_BASE_ADDR_ALIGN), 8 rows do not */
    enum { ALIGNED_ROWS = 16, UNALIGNED_ROWS = TILE };
    for (int shadows = 0; shadows < 2; shadows++) {
        aligned_records ref = aligned_alloc_records(shadows);
        aligned_records got = aligned_alloc_records(shadows);
        assert_false(run_pass(copying, fx->blob.bytes, ALIGNED_ROWS, H, &ref));
        assert_false(run_pass(fx->ctx, fx->blob.bytes, UNALIGNED_ROWS, H, &got));
        assert_records_equal(&got, &ref, H);
        bool in_place = run_pass(fx->ctx, fx->blob.bytes, ALIGNED_ROWS, H, &got);
        assert_true(in_place || !tm.cpu_device); /* (PoCL's CPU device works in host memory) */
        assert_records_equal(&got, &ref, H);
        for (int limit = 0; limit < H; limit += 2 * ALIGNED_ROWS + 3) { /* 0, 35 rows */
            assert_true(run_pass(fx->ctx, fx->blob.bytes, ALIGNED_ROWS, limit, &got) == in_place);
            assert_records_equal(&got, &ref, limit);
        }
        aligned_free_records(&ref);
        aligned_free_records(&got);
    }
    ocl_close(copying);
}

/* The pass on the device's clock (PoCL's queue times its commands): its
 * kernels, the copies after them (real ones on a context told to copy),
 * within the span from the first kernel to the last copy. */
static void test_device_times(void **state)
{
    fixture *fx = *state;
    ocl_timing tm;
    ocl_ctx *copying = open_copying(&tm);
    aligned_records a = aligned_alloc_records(true);
    for (int copy = 0; copy < 2; copy++) {
        ocl_ctx *ctx = copy ? copying : fx->ctx;
        run_pass_timed(ctx, fx->blob.bytes, 16, H, &a, &tm);
        assert_true(tm.device_kernel_s > 0.0);
        assert_true(tm.device_copy_s >= 0.0);
        if (copy)
            assert_true(tm.device_copy_s > 0.0);
        assert_true(tm.device_span_s + 1e-9 >= tm.device_kernel_s + tm.device_copy_s);
        assert_true(tm.device_span_s < 60.0);
    }
    aligned_free_records(&a);
    ocl_close(copying);
}

static void test_device_slices(void **state)
{
    fixture *fx = *state;
    csg_diag d = {{0}, 0};
    ocl_timing tm;
    memset(&tm, 0, sizeof tm);
    ocl_options opt = {.slice_records = 2000}; /* 22.2 rows of 90: 24 */
    ocl_ctx *gpu_like = NULL;
    assert_true(ocl_open(&opt, &gpu_like, &tm, &d));
    records *whole = calloc(1, sizeof *whole), *got = calloc(1, sizeof *got);
    assert_true(ocl_primary_pass(fx->ctx, fx->blob.bytes, TILE, whole->t, whole->surf,
                                 whole->hits, &tm, &d));
    ocl_pass *p = NULL;
    memset(got, 0xff, sizeof *got);
    assert_true(ocl_pass_begin(gpu_like, fx->blob.bytes, TILE, TILE, got->t, got->surf, NULL, NULL,
                               got->hits, NULL, NULL, &p, &d));
    int rows = 0, seen = 0;
    while (rows < H) {
        assert_true((rows = ocl_pass_rows(p, true, &d)) > seen);
        assert_true(rows % 24 == 0 || rows == H); /* slices of 24 rows */
        seen = rows;
    }
    assert_true(ocl_pass_end(p, &tm, &d));
    assert_int_equal(tm.slices, 3); /* 61 rows */
    assert_memory_equal(got->t, whole->t, sizeof got->t);
    assert_memory_equal(got->surf, whole->surf, sizeof got->surf);
    assert_memory_equal(got->hits, whole->hits, sizeof got->hits);
    free(whole);
    free(got);
    ocl_close(gpu_like);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_background_equals_whole),
        cmocka_unit_test(test_end_early),
        cmocka_unit_test(test_limit),
        cmocka_unit_test(test_in_place),
        cmocka_unit_test(test_device_slices),
        cmocka_unit_test(test_device_times),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
