/*
 * test_pixels.c — the 8-bit results (host/pixels.h): the byte of every
 * value, the value the master keeps for a byte, the one value without a
 * byte of its own, and the file a PNG gets from the workers' bytes: the
 * one their floats would have given, byte for byte.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "../host/image.h"
#include "../host/pixels.h"

/* Every byte's stand-in converts back to that byte. */
static void test_linear_of_every_byte(void **state)
{
    (void)state;
    for (int b = 0; b < 256; b++) {
        uint8_t got = 0;
        assert_true(pixels_srgb_byte(pixels_linear_of((uint8_t)b), &got));
        assert_int_equal(got, b);
    }
    assert_true(pixels_linear_of(0) == 0.0f && pixels_linear_of(255) == 1.0f);
}

/* Bytes never fall as the value grows; out of [0, 1] and NaN clamp. */
static void test_bytes_monotone_and_clamped(void **state)
{
    (void)state;
    uint8_t prev = 0, b = 0;
    for (float v = 0.0f; v <= 1.0f; v = nextafterf(v, 2.0f) + v * 1e-5f) {
        if (!pixels_srgb_byte(v, &b))
            continue;
        assert_true(b >= prev);
        prev = b;
    }
    assert_int_equal(prev, 255);
    assert_true(pixels_srgb_byte(-1.0f, &b) && b == 0);
    assert_true(pixels_srgb_byte(7.5f, &b) && b == 255);
    assert_true(pixels_srgb_byte(NAN, &b) && b == 0);
    assert_true(pixels_srgb_byte(INFINITY, &b) && b == 255);
}

/* The linear values that encode to the ambiguous value have no byte: a
 * row holding one does not convert (the worker sends its floats). */
static void test_ambiguous_has_no_byte(void **state)
{
    (void)state;
    float v = PIXELS_AMBIGUOUS_ENCODED / 12.92f;
    int found = 0;
    for (int k = -8; k <= 8; k++) {
        float x = v;
        for (int i = 0; i < (k < 0 ? -k : k); i++)
            x = nextafterf(x, k < 0 ? 0.0f : 1.0f);
        uint8_t b;
        if (pixels_srgb_encode(x) != PIXELS_AMBIGUOUS_ENCODED)
            continue;
        found++;
        assert_false(pixels_srgb_byte(x, &b));
        float row[4] = {0.5f, 0.25f, x, 1.0f};
        uint8_t out[4];
        assert_false(pixels_to_rgb8(row, 4, out));
    }
    assert_true(found > 0);
    float row[3] = {0.5f, 0.25f, 1.0f};
    uint8_t out[3];
    assert_true(pixels_to_rgb8(row, 3, out));
    assert_int_equal(out[2], 255);
}

static void test_format_for_path(void **state)
{
    (void)state;
    assert_int_equal(pixels_format_for(NULL), PIXELS_FLOAT);
    assert_int_equal(pixels_format_for("a.exr"), PIXELS_FLOAT);
    assert_int_equal(pixels_format_for("dir/A.EXR"), PIXELS_FLOAT);
    assert_int_equal(pixels_format_for("a.hdr"), PIXELS_FLOAT);
    assert_int_equal(pixels_format_for("a.pfm"), PIXELS_FLOAT);
    assert_int_equal(pixels_format_for("a.png"), PIXELS_RGB8);
    assert_int_equal(pixels_format_for("a.tif"), PIXELS_RGB8);
    assert_int_equal(pixels_format_for("a.ppm"), PIXELS_RGB8);
    assert_int_equal(pixels_format_for("out.exr/a.png"), PIXELS_RGB8);
    assert_int_equal(pixels_format_for("exr"), PIXELS_RGB8);
    assert_int_equal(pixels_bytes(PIXELS_RGB8), 3);
    assert_int_equal(pixels_bytes(PIXELS_FLOAT), 12);
}

static bool same_file(const char *a, const char *b)
{
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    bool same = fa && fb;
    while (same) {
        int ca = fgetc(fa), cb = fgetc(fb);
        same = ca == cb;
        if (ca == EOF)
            break;
    }
    if (fa)
        fclose(fa);
    if (fb)
        fclose(fb);
    return same;
}

/* A PNG written from the bytes' stand-ins is the PNG of the floats. */
static void test_png_from_bytes_is_png_of_floats(void **state)
{
    (void)state;
    enum { W = 61, H = 37 };
    static float exact[W * H * 3], kept[W * H * 3];
    static uint8_t bytes[W * H * 3];
    uint32_t x = 12345;
    for (size_t i = 0; i < sizeof exact / sizeof exact[0]; i++) {
        x = x * 1664525u + 1013904223u; /* values over [-0.1, 1.2) */
        exact[i] = (float)(x >> 8) / (float)(1u << 24) * 1.3f - 0.1f;
        if (i % 7 == 0)
            exact[i] *= 0.004f; /* the curve's linear part */
    }
    assert_true(pixels_to_rgb8(exact, W * H * 3, bytes));
    for (size_t i = 0; i < sizeof kept / sizeof kept[0]; i++)
        kept[i] = pixels_linear_of(bytes[i]);
    char err[512], dir[] = "/tmp/csgtrace-pixels-XXXXXX", a[64], b[64];
    assert_non_null(mkdtemp(dir));
    snprintf(a, sizeof a, "%s/a.png", dir);
    snprintf(b, sizeof b, "%s/b.png", dir);
    bool ok = img_write_rgb(a, exact, W, H, err, sizeof err) &&
              img_write_rgb(b, kept, W, H, err, sizeof err);
    if (!ok)
        fprintf(stderr, "%s\n", err);
    assert_true(ok);
    assert_true(same_file(a, b));
    unlink(a);
    unlink(b);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear_of_every_byte),
        cmocka_unit_test(test_bytes_monotone_and_clamped),
        cmocka_unit_test(test_ambiguous_has_no_byte),
        cmocka_unit_test(test_format_for_path),
        cmocka_unit_test(test_png_from_bytes_is_png_of_floats),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
