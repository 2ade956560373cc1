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
#include "same_file.h"

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

/* The byte of the float of bits u through pixels_to_rgb8 (its table)
 * against pixels_srgb_byte; false on a difference, printed. */
static bool table_agrees(uint32_t u)
{
    float v;
    memcpy(&v, &u, sizeof v);
    uint8_t want = 0, got = 0;
    bool has = pixels_srgb_byte(v, &want);
    bool conv = pixels_to_rgb8(&v, 1, &got);
    if (has == conv && (!has || got == want))
        return true;
    fprintf(stderr, "bits 0x%08x (%a): byte %d/%d, table %d/%d\n", (unsigned)u, (double)v, has,
            want, conv, got);
    return false;
}

/* The byte of the float of bits u; 256 when it has none. */
static int byte_of_bits(uint32_t u)
{
    float v;
    memcpy(&v, &u, sizeof v);
    uint8_t b;
    return pixels_srgb_byte(v, &b) ? b : 256;
}

/* pixels_to_rgb8's table equals pixels_srgb_byte for every float of the
 * curve's powf part (~70 million: this also checks that powf keeps the
 * bytes monotone there, which the table assumes), and in the linear part
 * (monotone by IEEE rounding) around every bucket's step and edges and at
 * a stride of 509 floats; the specials and out-of-range values too. */
static void test_table_is_the_function(void **state)
{
    (void)state;
    float knee = 0.0031308f;
    uint32_t pow_from, one = 0x3f800000u;
    memcpy(&pow_from, &knee, sizeof pow_from);
    long bad = 0;
    for (uint32_t u = pow_from; u <= one + 4096; u++)
        bad += !table_agrees(u);
    for (uint32_t u = 0; u < pow_from; u += 509)
        bad += !table_agrees(u);
    for (uint32_t k = 0; k <= pow_from >> 16; k++) {
        uint32_t first = k << 16;
        for (uint32_t u = first > 300 ? first - 300 : 0; u <= first + 300; u++)
            bad += !table_agrees(u); /* a bucket's edge */
        for (uint32_t base = first; base < first + 65536; base += 4096)
            if (byte_of_bits(base) != byte_of_bits(base + 4096))
                for (uint32_t u = base; u <= base + 4096; u++)
                    bad += !table_agrees(u); /* around a step */
    }
    const float specials[] = {0.0f, -0.0f, -1.0f, 1.0f, 2.0f, NAN, -NAN, INFINITY, -INFINITY,
                              0x1p-149f, -0x1p-149f, 0x1.fffffep-1f};
    for (size_t i = 0; i < sizeof specials / sizeof specials[0]; i++) {
        uint32_t u;
        memcpy(&u, &specials[i], sizeof u);
        bad += !table_agrees(u);
    }
    assert_int_equal(bad, 0);
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

/* A PNG written from the bytes' stand-ins is the PNG of the floats. */
/* A rectangle of bytes stored into a larger float image: each value is
 * pixels_linear_of of its byte, nothing outside the rectangle moves; at
 * every start alignment (the non-temporal stores' aligned and unaligned
 * paths) and rectangle width, odd ones included. */
static void test_store_bytes_rect(void **state)
{
    (void)state;
    enum { W = 23, H = 9 };
    static float image[W * H * 3];
    static uint8_t src[W * H * 3];
    for (size_t i = 0; i < sizeof src; i++)
        src[i] = (uint8_t)(i * 37u + 11u);
    for (int x = 0; x < 5; x++)
        for (int w = 1; x + w <= W; w += 3) {
            for (size_t i = 0; i < W * H * 3; i++)
                image[i] = -7.0f;
            int y = 2, h = 5;
            pixels_store_bytes_rect(image, W, x, y, w, h, src);
            for (int row = 0; row < H; row++)
                for (int col = 0; col < W * 3; col++) {
                    bool inside = row >= y && row < y + h && col >= x * 3 && col < (x + w) * 3;
                    float want = inside ? pixels_linear_of(src[(size_t)(row - y) * (size_t)w * 3 +
                                                               (size_t)(col - x * 3)])
                                        : -7.0f;
                    assert_true(image[(size_t)row * W * 3 + (size_t)col] == want);
                }
        }
}

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
        cmocka_unit_test(test_table_is_the_function),
        cmocka_unit_test(test_format_for_path),
        cmocka_unit_test(test_png_from_bytes_is_png_of_floats),
        cmocka_unit_test(test_store_bytes_rect),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
