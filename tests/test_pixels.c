/*
 * test_pixels.c — the 8-bit results (comm/pixels.h): the byte of every
 * value, the value the master keeps for a byte, the value OpenImageIO's own
 * conversion rounds two ways (one byte here, everywhere), and the file a
 * PNG gets from the workers' bytes: the one their floats would have given,
 * byte for byte.
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

#include "../host/output/image.h"
#include "../comm/pixels.h"
#include "../comm/pixels_z.h"
#include "same_file.h"

/* Every byte's stand-in converts back to that byte. */
static void test_linear_of_every_byte(void **state)
{
    (void)state;
    for (int b = 0; b < 256; b++) {
        assert_int_equal(pixels_srgb_byte(pixels_linear_of((uint8_t)b)), b);
    }
    assert_true(pixels_linear_of(0) == 0.0f && pixels_linear_of(255) == 1.0f);
}

/* Bytes never fall as the value grows; out of [0, 1] and NaN clamp. */
static void test_bytes_monotone_and_clamped(void **state)
{
    (void)state;
    uint8_t prev = 0;
    for (float v = 0.0f; v <= 1.0f; v = nextafterf(v, 2.0f) + v * 1e-5f) {
        uint8_t b = pixels_srgb_byte(v);
        assert_true(b >= prev);
        prev = b;
    }
    assert_int_equal(prev, 255);
    assert_int_equal(pixels_srgb_byte(-1.0f), 0);
    assert_int_equal(pixels_srgb_byte(7.5f), 255);
    assert_int_equal(pixels_srgb_byte(NAN), 0);
    assert_int_equal(pixels_srgb_byte(INFINITY), 255);
}

/* The values that encode to x * 255 = 0.49999997 (the float just below
 * 0.5), which OpenImageIO's own conversion rounds to 0 in its SIMD lanes
 * and to 1 in its scalar tail: one byte here, 1 (0.49999997f + 0.5f is a
 * tie between 1 - 2^-24 and 1, rounded to even), at every position of a
 * row, and the same byte in every format's file, whoever writes it. */
static void test_the_value_oiio_rounds_two_ways(void **state)
{
    (void)state;
    const float encoded = 0x1.0101p-9f; /* (0.49999997 / 255) */
    float v = encoded / 12.92f;
    int found = 0;
    enum { W = 37, H = 3 };
    static float image[W * H * 3];
    for (int k = -8; k <= 8; k++) {
        float x = v;
        for (int i = 0; i < (k < 0 ? -k : k); i++)
            x = nextafterf(x, k < 0 ? 0.0f : 1.0f);
        if (pixels_srgb_encode(x) != encoded)
            continue;
        found++;
        assert_int_equal(pixels_srgb_byte(x), 1);
        for (size_t i = 0; i < sizeof image / sizeof image[0]; i++)
            image[i] = x;
        uint8_t row[W * H * 3];
        pixels_to_rgb8(image, sizeof row, row);
        for (size_t i = 0; i < sizeof row; i++)
            assert_int_equal(row[i], 1);
    }
    assert_true(found > 0);
    char err[512], dir[] = "/tmp/csgtrace-pixels-XXXXXX", a[64], b[64];
    assert_non_null(mkdtemp(dir));
    snprintf(a, sizeof a, "%s/a.png", dir);
    snprintf(b, sizeof b, "%s/b.tif", dir);
    float *back = NULL;
    int w = 0, h = 0;
    bool ok = img_write_rgb(a, image, W, H, err, sizeof err) &&
              img_write_rgb(b, image, W, H, err, sizeof err);
    for (int f = 0; ok && f < 2; f++) {
        ok = img_read_rgb(f ? b : a, &back, &w, &h, err, sizeof err) && w == W && h == H;
        for (size_t i = 0; ok && i < sizeof image / sizeof image[0]; i++)
            ok = lrintf(back[i] * 255.0f) == 1; /* (read back as byte / 255) */
        free(back);
        back = NULL;
    }
    if (!ok)
        fprintf(stderr, "%s\n", err);
    assert_true(ok);
    unlink(a);
    unlink(b);
    rmdir(dir);
}

/* The byte of the float of bits u through pixels_to_rgb8 (its table)
 * against pixels_srgb_byte; false on a difference, printed. */
static bool table_agrees(uint32_t u)
{
    float v;
    memcpy(&v, &u, sizeof v);
    uint8_t want = pixels_srgb_byte(v), got = 0;
    pixels_to_rgb8(&v, 1, &got);
    if (got == want)
        return true;
    fprintf(stderr, "bits 0x%08x (%a): byte %d, table %d\n", (unsigned)u, (double)v, want, got);
    return false;
}

/* The byte of the float of bits u. */
static int byte_of_bits(uint32_t u)
{
    float v;
    memcpy(&v, &u, sizeof v);
    return pixels_srgb_byte(v);
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
    pixels_to_rgb8(exact, W * H * 3, bytes);
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

/* A tile of rendered-like bytes (a flat background, a shaded disc) through
 * a worker's compressor and rank 0's decompressor: the same bytes, fewer
 * of them; and each way a part can be wrong refused without a byte
 * written past its tile: cut short, one byte too many, the tile one byte
 * smaller or larger, a flipped bit, nothing, the wrong kind of context. */
static void test_compress_round_trip_and_refusals(void **state)
{
    (void)state;
    enum { W = 32, H = 32, N = W * H * 3 };
    uint8_t tile[N], back[N + 16];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int d2 = (x - 16) * (x - 16) + (y - 16) * (y - 16);
            for (int c = 0; c < 3; c++)
                tile[(y * W + x) * 3 + c] = d2 < 144 ? (uint8_t)(200 - d2 + 17 * c) : 30;
        }
    pixels_zstream *comp = pixels_compressor_new(), *decomp = pixels_decompressor_new();
    assert_non_null(comp);
    assert_non_null(decomp);
    uint8_t z[pixels_compress_bound(N) + 1];
    size_t len = pixels_compress(comp, tile, N, z);
    assert_true(len > 0 && len < N / 3); /* (this disc: 775 bytes; rendered tiles: 11x) */
    for (int round = 0; round < 2; round++) { /* (the contexts are reused) */
        memset(back, 0x5a, sizeof back);
        assert_true(pixels_decompress(decomp, z, len, back, N));
        assert_memory_equal(back, tile, N);
        assert_int_equal(back[N], 0x5a);
        assert_int_equal(pixels_compress(comp, tile, N, z), len);
    }
    assert_false(pixels_decompress(decomp, z, len - 1, back, N)); /* cut short       */
    z[len] = 0;
    assert_false(pixels_decompress(decomp, z, len + 1, back, N)); /* a byte after    */
    memset(back, 0x5a, sizeof back);
    assert_false(pixels_decompress(decomp, z, len, back, N - 1)); /* tile smaller    */
    assert_int_equal(back[N - 1], 0x5a);                          /* (nothing past)  */
    assert_false(pixels_decompress(decomp, z, len, back, N + 1)); /* tile larger     */
    assert_false(pixels_decompress(decomp, z, 0, back, N));       /* nothing         */
    z[len / 2] ^= 0x40; /* (the frame's checksum catches it) */
    assert_false(pixels_decompress(decomp, z, len, back, N));
    assert_false(pixels_decompress(comp, z, len, back, N));       /* a compressor    */
    assert_int_equal(pixels_compress(decomp, tile, N, z), 0);     /* a decompressor  */
    pixels_zstream_free(comp);
    pixels_zstream_free(decomp);
    pixels_zstream_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear_of_every_byte),
        cmocka_unit_test(test_bytes_monotone_and_clamped),
        cmocka_unit_test(test_the_value_oiio_rounds_two_ways),
        cmocka_unit_test(test_table_is_the_function),
        cmocka_unit_test(test_format_for_path),
        cmocka_unit_test(test_png_from_bytes_is_png_of_floats),
        cmocka_unit_test(test_store_bytes_rect),
        cmocka_unit_test(test_compress_round_trip_and_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
