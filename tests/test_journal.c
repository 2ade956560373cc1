/*
 * test_journal.c — the journal's writer thread (host/output/journal.c): the tiles
 * the master queues are all in the file once the journal is closed, and
 * --resume reads them back (bit for bit for a float output; for an 8-bit
 * one as the same bytes, from records of bytes); nothing is appended before
 * the journal's after_s (JOURNAL_AFTER_S in a render), and a render that
 * finishes first writes no record; damaged records are skipped, the valid
 * ones after them kept; a writer with nothing to write
 * sleeps (it once spun on a core from the first second without a new tile
 * until the next one).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include <cmocka.h>

#include "../csg/lang/parser.h"
#include "../host/output/journal.h"
#include "../comm/pixels.h"
#include "../workers/engine.h"

typedef struct {
    csg_scene scene;
    csg_blob blob;
    tile_grid grid;
    char dir[64], out[96];
} fixture;

static int setup(void **state)
{
    static const char sdl[] =
        "camera { location <0, 0, -5> look_at <0, 0, 0> }\n"
        "light_source { <0, 5, -5> color rgb 1 }\n"
        "sphere { <0, 0, 0>, 1 pigment { color rgb 1 } }\n";
    fixture *f = calloc(1, sizeof *f);
    csg_diag d = {{0}, 0};
    csg_flatten_opts o = {24, 16, 5, -1, 1, 0}; /* 24x16 */
    if (!f || !csg_parse_string("j.pov", sdl, strlen(sdl), &f->scene, &d) ||
        !engine_float.flatten(&f->scene, &o, &f->blob, &d))
        return -1;
    f->grid = tile_grid_of(f->blob.bytes, 4); /* 6 x 4 tiles */
    snprintf(f->dir, sizeof f->dir, "/tmp/csgtrace-journal-XXXXXX");
    if (!mkdtemp(f->dir))
        return -1;
    snprintf(f->out, sizeof f->out, "%s/out.png", f->dir);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    char path[128];
    snprintf(path, sizeof path, "%s%s", f->out, JOURNAL_SUFFIX);
    unlink(path);
    rmdir(f->dir);
    csg_blob_free(&f->blob);
    csg_scene_free(&f->scene);
    free(f);
    return 0;
}

static double cpu_seconds(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return (double)u.ru_utime.tv_sec + (double)u.ru_utime.tv_usec * 1e-6 +
           (double)u.ru_stime.tv_sec + (double)u.ru_stime.tv_usec * 1e-6;
}

/* The journal's file size, the file kept. */
static long journal_size(const char *out)
{
    char path[160];
    snprintf(path, sizeof path, "%s%s", out, JOURNAL_SUFFIX);
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

/* The time now, in seconds (CLOCK_MONOTONIC, the journal's). */
static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Every tile queued is appended by the time the journal is closed (by
 * the writer thread, or by journal_tile_done itself before the writer is
 * started), `after_s` or not: with a long one, nothing is in the file
 * until the close, which does not wait for it; a resume gives back the
 * hits, and the pixels: the very floats for a float output, for an 8-bit
 * one the floats of the same bytes (pixels_linear_of: the file is the
 * same).  `image` is the render's (its values in [0, 1)); the journal's
 * size is returned (the file kept, removed by the next open without
 * --resume or by teardown). */
static long tiles_are_kept_after(fixture *f, const char *out, bool writer, const float *image,
                                 double after_s)
{
    size_t floats = (size_t)f->grid.width * (size_t)f->grid.height * 3;
    float *back = calloc(floats, sizeof *back);
    assert_non_null(back);
    journal *j = NULL;
    csg_diag d = {{0}, 0};
    assert_int_equal(
        journal_open(out, f->blob.bytes, &f->grid, false, (float *)image, after_s, &j, &d), 0);
    long header = journal_size(out);
    if (writer)
        journal_start_writer(j);
    int tiles = tile_count(&f->grid);
    for (int t = 0; t < tiles; t++) {
        journal_add_hits(j, t, (uint32_t)t + 1);
        journal_tile_done(j, t, image);
    }
    if (after_s >= 60) /* (queued only: the first record waits a minute) */
        assert_int_equal(journal_size(out), header);
    double t0 = now_s();
    journal_close(j, false); /* kept: the render did not finish */
    assert_true(now_s() - t0 < 30); /* (the writer's wait cut short) */
    long size = journal_size(out);
    assert_int_equal(journal_open(out, f->blob.bytes, &f->grid, true, back, 0, &j, &d), 0);
    assert_int_equal(journal_tiles_resumed(j), tiles);
    for (int t = 0; t < tiles; t++)
        assert_int_equal(journal_resumed_hits(j, t), (uint32_t)t + 1);
    if (pixels_format_for(out) == PIXELS_FLOAT) {
        assert_memory_equal(image, back, floats * sizeof *image);
    } else {
        for (size_t i = 0; i < floats; i++)
            assert_int_equal(pixels_srgb_byte(back[i]), pixels_srgb_byte(image[i]));
    }
    journal_close(j, false);
    free(back);
    return size;
}

static long tiles_are_all_kept(fixture *f, const char *out, bool writer, const float *image)
{
    return tiles_are_kept_after(f, out, writer, image, 0);
}

/* The render's image: values over [0, 1), both of the curve's parts. */
static float *test_image(const fixture *f)
{
    size_t floats = (size_t)f->grid.width * (size_t)f->grid.height * 3;
    float *image = malloc(floats * sizeof *image);
    assert_non_null(image);
    for (size_t i = 0; i < floats; i++)
        image[i] = (float)(i % 97) / 97.0f * (i % 5 == 0 ? 0.003f : 1.0f);
    return image;
}

static void test_queued_tiles_are_all_kept(void **state)
{
    fixture *f = *state;
    float *image = test_image(f);
    tiles_are_all_kept(f, f->out, true, image);
    free(image);
}

static void test_tiles_without_the_writer(void **state)
{
    fixture *f = *state;
    float *image = test_image(f);
    tiles_are_all_kept(f, f->out, false, image);
    free(image);
}

/* A render stopped before the journal's first record keeps what it had
 * queued: the close appends it (with the writer, or without). */
static void test_stopped_before_after_keeps_the_tiles(void **state)
{
    fixture *f = *state;
    float *image = test_image(f);
    long now = tiles_are_kept_after(f, f->out, true, image, 0);
    assert_int_equal(tiles_are_kept_after(f, f->out, true, image, 60), now);
    assert_int_equal(tiles_are_kept_after(f, f->out, false, image, 60), now);
    free(image);
}

/* A render finished before the first record writes none: the journal is
 * removed at once, the writer's wait cut short. */
static void test_finished_before_after_writes_none(void **state)
{
    fixture *f = *state;
    float *image = test_image(f);
    for (int writer = 0; writer < 2; writer++) {
        journal *j = NULL;
        csg_diag d = {{0}, 0};
        assert_int_equal(journal_open(f->out, f->blob.bytes, &f->grid, false, image, 60, &j, &d),
                         0);
        long header = journal_size(f->out);
        if (writer)
            journal_start_writer(j);
        for (int t = 0; t < tile_count(&f->grid); t++)
            journal_tile_done(j, t, image);
        assert_int_equal(journal_size(f->out), header);
        double t0 = now_s();
        journal_close(j, true);
        assert_true(now_s() - t0 < 30);
        assert_int_equal(journal_size(f->out), -1);
    }
    free(image);
}

/* Once after_s has passed, the writer appends what was queued before
 * (never sooner), and the tiles after it as they come. */
static void test_records_once_after_has_passed(void **state)
{
    fixture *f = *state;
    float *image = test_image(f);
    long full = tiles_are_all_kept(f, f->out, true, image);
    const double after_s = 0.3;
    journal *j = NULL;
    csg_diag d = {{0}, 0};
    double opened = now_s();
    assert_int_equal(journal_open(f->out, f->blob.bytes, &f->grid, false, image, after_s, &j, &d),
                     0);
    long header = journal_size(f->out);
    journal_start_writer(j);
    int tiles = tile_count(&f->grid);
    for (int t = 0; t < tiles / 2; t++)
        journal_tile_done(j, t, image);
    double first = 0;
    long size = header;
    for (double until = now_s() + 20; size == header && now_s() < until;) {
        nanosleep(&(struct timespec){0, 2000000L}, NULL);
        size = journal_size(f->out);
        first = now_s();
    }
    assert_true(size > header);
    assert_true(first - opened >= after_s);
    for (int t = tiles / 2; t < tiles; t++)
        journal_tile_done(j, t, image);
    for (double until = now_s() + 20; size != full && now_s() < until;) {
        nanosleep(&(struct timespec){0, 2000000L}, NULL);
        size = journal_size(f->out);
    }
    assert_int_equal(size, full); /* (before the close: the writer's own) */
    journal_close(j, false);
    free(image);
}

/* An 8-bit output's records hold its bytes: 3 bytes a pixel against a
 * float output's 12 (24 tiles of 4x4: 3456 bytes fewer; the headers differ
 * by the pixel format's name, "rgb8" against "float"). */
static void test_8bit_records_are_bytes(void **state)
{
    fixture *f = *state;
    float *image = test_image(f);
    char exr[112];
    snprintf(exr, sizeof exr, "%s/out.exr", f->dir);
    long png = tiles_are_all_kept(f, f->out, true, image);
    long flt = tiles_are_all_kept(f, exr, true, image);
    assert_int_equal(flt - png, 24 * 4 * 4 * 3 * 3 + 1);
    char path[160];
    snprintf(path, sizeof path, "%s%s", exr, JOURNAL_SUFFIX);
    unlink(path);
    free(image);
}

/* Damaged records are skipped, the valid ones after them kept: a flipped
 * byte in the first record's pixels (its size known from its header), one
 * in the third's rectangle (its header unsound: the reader looks for the
 * next valid record), and a torn last record; the other tiles resumed with
 * their bytes, the torn end cut off.  (A damaged record once ended the
 * journal: every tile after it was rendered again.) */
static void test_damaged_records_are_skipped(void **state)
{
    fixture *f = *state;
    float *image = test_image(f);
    size_t floats = (size_t)f->grid.width * (size_t)f->grid.height * 3;
    float *back = calloc(floats, sizeof *back);
    assert_non_null(back);
    journal *j = NULL;
    csg_diag d = {{0}, 0};
    int tiles = tile_count(&f->grid);
    assert_int_equal(journal_open(f->out, f->blob.bytes, &f->grid, false, image, 0, &j, &d), 0);
    for (int t = 0; t < tiles; t++)
        journal_tile_done(j, t, image); /* (records in tile order: after_s 0, no writer) */
    journal_close(j, false);
    char path[160];
    snprintf(path, sizeof path, "%s%s", f->out, JOURNAL_SUFFIX);
    FILE *file = fopen(path, "r+b");
    assert_non_null(file);
    char data[8192];
    size_t n = fread(data, 1, sizeof data, file);
    const size_t rec = 32 + 4 * 4 * 3 + 8; /* the fixed part, 4x4 bytes x 3, the checksum */
    size_t header = (size_t)(strstr(data, "\n.\n") - data) + 3;
    assert_int_equal(n, header + (size_t)tiles * rec);
    data[header + 40] ^= 0x40;          /* record 0: a byte of its pixels */
    data[header + 2 * rec + 8] ^= 0x01; /* record 2: its x */
    rewind(file);
    assert_int_equal(fwrite(data, 1, n - 10, file), n - 10);
    fclose(file);
    assert_int_equal(truncate(path, (off_t)(n - 10)), 0); /* record 23: torn */
    assert_int_equal(journal_open(f->out, f->blob.bytes, &f->grid, true, back, 0, &j, &d), 0);
    assert_int_equal(journal_tiles_resumed(j), tiles - 3);
    for (int t = 0; t < tiles; t++)
        assert_int_equal(journal_resumed(j, t), t != 0 && t != 2 && t != tiles - 1);
    for (size_t i = 0; i < floats; i++) { /* (tile 1's pixels and the others' are back) */
        size_t x = i / 3 % (size_t)f->grid.width, y = i / 3 / (size_t)f->grid.width;
        int t = (int)(y / 4) * 6 + (int)(x / 4);
        if (journal_resumed(j, t))
            assert_int_equal(pixels_srgb_byte(back[i]), pixels_srgb_byte(image[i]));
    }
    journal_close(j, false);
    assert_int_equal(journal_size(f->out), (long)(header + (size_t)(tiles - 1) * rec));
    free(back);
    free(image);
}

/* 2.5 s without a tile: the writer looks every millisecond and sleeps in
 * between (measured: ~0.03 s of CPU); spinning, it took a core from the
 * first second on (a second with no new tile left it no time to wait:
 * 1.5 s of CPU here).
 * CPU time, not speed: other load cannot raise it, only make a spinning
 * writer take less. */
static void test_idle_writer_sleeps(void **state)
{
    fixture *f = *state;
    size_t floats = (size_t)f->grid.width * (size_t)f->grid.height * 3;
    float *image = calloc(floats, sizeof *image);
    assert_non_null(image);
    journal *j = NULL;
    csg_diag d = {{0}, 0};
    prctl(PR_SET_TIMERSLACK, 1000UL); /* (as every rank has it: comm/mpi_link.c; the writer inherits it) */
    assert_int_equal(journal_open(f->out, f->blob.bytes, &f->grid, false, image, 0, &j, &d), 0);
    journal_start_writer(j);
    double cpu0 = cpu_seconds();
    nanosleep(&(struct timespec){2, 500000000L}, NULL);
    double used = cpu_seconds() - cpu0;
    journal_close(j, true);
    if (used > 0.1)
        fail_msg("the idle journal writer used %.2f s of CPU in 2.5 s", used);
    free(image);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_queued_tiles_are_all_kept, setup, teardown),
        cmocka_unit_test_setup_teardown(test_tiles_without_the_writer, setup, teardown),
        cmocka_unit_test_setup_teardown(test_stopped_before_after_keeps_the_tiles, setup, teardown),
        cmocka_unit_test_setup_teardown(test_finished_before_after_writes_none, setup, teardown),
        cmocka_unit_test_setup_teardown(test_records_once_after_has_passed, setup, teardown),
        cmocka_unit_test_setup_teardown(test_8bit_records_are_bytes, setup, teardown),
        cmocka_unit_test_setup_teardown(test_damaged_records_are_skipped, setup, teardown),
        cmocka_unit_test_setup_teardown(test_idle_writer_sleeps, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
