/*
 * pixels.c — the result pixel formats and the 8-bit conversion (pixels.h).
 *
 * The master keeps a float image whatever the format (the journal, the
 * writer and the background fill of empty tiles all work on it); a byte
 * received becomes the linear value of pixels_linear_of, chosen so that
 * the writer's conversion gives that very byte back: the file is the one
 * the worker's floats would have given.
 */
#include "pixels.h"

#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <string.h>
#include <strings.h>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

/* pixels_to_rgb8 without a powf a value: the bytes of the floats of (0, 1)
 * by their bit patterns, in buckets of 2^PIXELS_BUCKET_SHIFT consecutive
 * floats.  The byte never falls as the float grows (the curve's linear part
 * is monotone by IEEE rounding; its powf part was checked float by float,
 * tests/test_pixels.c, which also compares this table with
 * pixels_srgb_byte for every float of that part), so a bucket whose first
 * and last bytes differ by one has its byte `lo`, plus one from the float
 * `step` on (found by bisection).  A bucket the table cannot settle so (more
 * than one step) is `slow`: its values go through pixels_srgb_byte.  ~0.5 ms to
 * build, once a process, on the first conversion. */
#define PIXELS_BUCKET_SHIFT 16
#define PIXELS_ONE_BITS 0x3f800000u /* 1.0f */
enum { PIXELS_BUCKETS = PIXELS_ONE_BITS >> PIXELS_BUCKET_SHIFT };

typedef struct {
    uint32_t step; /* first float bits of the bucket at lo + 1; UINT32_MAX: none */
    uint8_t lo;
    uint8_t slow;
} pixels_bucket;

typedef struct {
    pthread_once_t once;
    pixels_bucket bucket[PIXELS_BUCKETS];
} pixels_table;

static pixels_table table = {PTHREAD_ONCE_INIT, {{0, 0, 0}}};

static float float_of_bits(uint32_t u)
{
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

/* The byte of the float of bits u. */
static int raw_byte(uint32_t u)
{
    return pixels_srgb_byte(float_of_bits(u));
}

static void build_table(void)
{
    for (uint32_t k = 0; k < PIXELS_BUCKETS; k++) {
        pixels_bucket *bk = &table.bucket[k];
        uint32_t first = k << PIXELS_BUCKET_SHIFT, last = first + (1u << PIXELS_BUCKET_SHIFT) - 1;
        int lo = raw_byte(first), hi = raw_byte(last);
        bk->lo = (uint8_t)lo;
        bk->step = UINT32_MAX;
        bk->slow = hi - lo > 1 || hi < lo;
        if (bk->slow || hi == lo)
            continue;
        uint32_t a = first, b = last; /* first u of byte hi */
        while (a < b) {
            uint32_t m = a + (b - a) / 2;
            if (raw_byte(m) >= hi)
                b = m;
            else
                a = m + 1;
        }
        bk->step = a;
    }
}

void pixels_to_rgb8(const float *rgb, size_t n, uint8_t *out)
{
    pthread_once(&table.once, build_table);
    for (size_t i = 0; i < n; i++) {
        uint32_t u;
        memcpy(&u, &rgb[i], sizeof u);
        /* past the table (u - 1 wraps for 0): 0, negatives, 1 and more, NaN,
         * which pixels_srgb_byte clamps without a powf */
        const pixels_bucket *bk =
            u - 1u < PIXELS_ONE_BITS - 1u ? &table.bucket[u >> PIXELS_BUCKET_SHIFT] : NULL;
        out[i] = bk && !bk->slow ? (uint8_t)(bk->lo + (u >= bk->step)) : pixels_srgb_byte(rgb[i]);
    }
}

/* For each byte b: the sRGB curve's inverse at b / 255 (the middle of the
 * byte's interval of encoded values), as a float; tests/test_pixels.c
 * checks that every entry converts back to its byte. */
static const float linear_of_byte[256] = {
    0x0p+0, 0x1.3e4568p-12, 0x1.3e4568p-11, 0x1.dd681cp-11,
    0x1.3e4568p-10, 0x1.8dd6c2p-10, 0x1.dd681cp-10, 0x1.167cbap-9,
    0x1.3e4568p-9, 0x1.660e14p-9, 0x1.8dd6c2p-9, 0x1.b6a31cp-9,
    0x1.e1e31ep-9, 0x1.07c38cp-8, 0x1.1fcc2cp-8, 0x1.390ffap-8,
    0x1.53936cp-8, 0x1.6f5adep-8, 0x1.8c6a94p-8, 0x1.aac6cp-8,
    0x1.ca7382p-8, 0x1.eb74e2p-8, 0x1.06e76cp-7, 0x1.18c2a6p-7,
    0x1.2b4e0ap-7, 0x1.3e8b7cp-7, 0x1.527cd6p-7, 0x1.6723eep-7,
    0x1.7c8292p-7, 0x1.929a88p-7, 0x1.a96d92p-7, 0x1.c0fd68p-7,
    0x1.d94bbep-7, 0x1.f25a44p-7, 0x1.061552p-6, 0x1.135f3ep-6,
    0x1.210bb8p-6, 0x1.2f1b8cp-6, 0x1.3d8f84p-6, 0x1.4c6866p-6,
    0x1.5ba6fap-6, 0x1.6b4c04p-6, 0x1.7b5842p-6, 0x1.8bcc74p-6,
    0x1.9ca958p-6, 0x1.adefaap-6, 0x1.bfa02p-6, 0x1.d1bb74p-6,
    0x1.e4425ap-6, 0x1.f73586p-6, 0x1.054ad4p-5, 0x1.0f31bap-5,
    0x1.194fccp-5, 0x1.23a55ep-5, 0x1.2e32c8p-5, 0x1.38f86p-5,
    0x1.43f678p-5, 0x1.4f2d64p-5, 0x1.5a9d76p-5, 0x1.664702p-5,
    0x1.722a56p-5, 0x1.7e47c8p-5, 0x1.8a9fa4p-5, 0x1.97323ap-5,
    0x1.a3ffd8p-5, 0x1.b108dp-5, 0x1.be4d6cp-5, 0x1.cbcdfap-5,
    0x1.d98ac6p-5, 0x1.e7841cp-5, 0x1.f5ba48p-5, 0x1.0216cap-4,
    0x1.096f26p-4, 0x1.10e65cp-4, 0x1.187c9p-4, 0x1.2031e8p-4,
    0x1.280688p-4, 0x1.2ffa92p-4, 0x1.380e2ap-4, 0x1.404174p-4,
    0x1.489494p-4, 0x1.5107acp-4, 0x1.599adep-4, 0x1.624e4ep-4,
    0x1.6b221ep-4, 0x1.74167p-4, 0x1.7d2b66p-4, 0x1.86612p-4,
    0x1.8fb7cp-4, 0x1.992f68p-4, 0x1.a2c83ap-4, 0x1.ac8256p-4,
    0x1.b65ddcp-4, 0x1.c05aecp-4, 0x1.ca79a8p-4, 0x1.d4ba3p-4,
    0x1.df1ca2p-4, 0x1.e9a12p-4, 0x1.f447cap-4, 0x1.ff10bcp-4,
    0x1.04fe0cp-3, 0x1.0a84fep-3, 0x1.101d44p-3, 0x1.15c6eep-3,
    0x1.1b8208p-3, 0x1.214ea6p-3, 0x1.272cd4p-3, 0x1.2d1ca2p-3,
    0x1.331e1ep-3, 0x1.393158p-3, 0x1.3f566p-3, 0x1.458d42p-3,
    0x1.4bd60ep-3, 0x1.5230d4p-3, 0x1.589dap-3, 0x1.5f1c84p-3,
    0x1.65ad8ap-3, 0x1.6c50c4p-3, 0x1.73063ep-3, 0x1.79ce06p-3,
    0x1.80a82ep-3, 0x1.8794cp-3, 0x1.8e93ccp-3, 0x1.95a55ep-3,
    0x1.9cc986p-3, 0x1.a40052p-3, 0x1.ab49cep-3, 0x1.b2a60ap-3,
    0x1.ba1512p-3, 0x1.c196f4p-3, 0x1.c92bbep-3, 0x1.d0d37cp-3,
    0x1.d88e3ep-3, 0x1.e05c0ep-3, 0x1.e83cfcp-3, 0x1.f03116p-3,
    0x1.f83866p-3, 0x1.00297ep-2, 0x1.044072p-2, 0x1.086116p-2,
    0x1.0c8b7p-2, 0x1.10bf86p-2, 0x1.14fd6p-2, 0x1.194502p-2,
    0x1.1d9676p-2, 0x1.21f1bep-2, 0x1.2656e4p-2, 0x1.2ac5ecp-2,
    0x1.2f3edep-2, 0x1.33c1cp-2, 0x1.384e98p-2, 0x1.3ce56cp-2,
    0x1.418642p-2, 0x1.46312p-2, 0x1.4ae60ep-2, 0x1.4fa51p-2,
    0x1.546e2cp-2, 0x1.59416cp-2, 0x1.5e1edp-2, 0x1.630664p-2,
    0x1.67f82ap-2, 0x1.6cf428p-2, 0x1.71fa68p-2, 0x1.770aecp-2,
    0x1.7c25bcp-2, 0x1.814adcp-2, 0x1.867a54p-2, 0x1.8bb428p-2,
    0x1.90f86p-2, 0x1.9647p-2, 0x1.9ba01p-2, 0x1.a10394p-2,
    0x1.a67192p-2, 0x1.abea1p-2, 0x1.b16d14p-2, 0x1.b6faa4p-2,
    0x1.bc92c6p-2, 0x1.c2357ep-2, 0x1.c7e2d2p-2, 0x1.cd9acap-2,
    0x1.d35d6ap-2, 0x1.d92ab6p-2, 0x1.df02b8p-2, 0x1.e4e57p-2,
    0x1.ead2e8p-2, 0x1.f0cb26p-2, 0x1.f6ce2cp-2, 0x1.fcdcp-2,
    0x1.017a56p-1, 0x1.048c18p-1, 0x1.07a34ap-1, 0x1.0abfeep-1,
    0x1.0de208p-1, 0x1.11099ap-1, 0x1.1436a8p-1, 0x1.176932p-1,
    0x1.1aa13ep-1, 0x1.1ddecap-1, 0x1.2121dep-1, 0x1.246a7ap-1,
    0x1.27b8ap-1, 0x1.2b0c54p-1, 0x1.2e6598p-1, 0x1.31c46ep-1,
    0x1.3528dcp-1, 0x1.3892ep-1, 0x1.3c028p-1, 0x1.3f77bcp-1,
    0x1.42f29ap-1, 0x1.467318p-1, 0x1.49f93ep-1, 0x1.4d850ap-1,
    0x1.511682p-1, 0x1.54ada4p-1, 0x1.584a78p-1, 0x1.5becfep-1,
    0x1.5f9538p-1, 0x1.634328p-1, 0x1.66f6d4p-1, 0x1.6ab03ap-1,
    0x1.6e6f6p-1, 0x1.723448p-1, 0x1.75fef4p-1, 0x1.79cf64p-1,
    0x1.7da59ep-1, 0x1.8181a4p-1, 0x1.856378p-1, 0x1.894b1cp-1,
    0x1.8d3892p-1, 0x1.912bdep-1, 0x1.9525p-1, 0x1.9923fep-1,
    0x1.9d28d8p-1, 0x1.a13392p-1, 0x1.a5442cp-1, 0x1.a95aacp-1,
    0x1.ad771p-1, 0x1.b1995ep-1, 0x1.b5c198p-1, 0x1.b9efbep-1,
    0x1.be23d4p-1, 0x1.c25ddep-1, 0x1.c69ddcp-1, 0x1.cae3d2p-1,
    0x1.cf2fcp-1, 0x1.d381aap-1, 0x1.d7d994p-1, 0x1.dc377ep-1,
    0x1.e09b6ap-1, 0x1.e5055cp-1, 0x1.e97556p-1, 0x1.edeb5cp-1,
    0x1.f2676cp-1, 0x1.f6e98cp-1, 0x1.fb71bcp-1, 0x1p+0
};

float pixels_linear_of(uint8_t b)
{
    return linear_of_byte[b];
}

/* The sRGB curve's inverse (POV-Ray's SRGBGammaCurve::Decode), in double. */
static double srgb_decode(double c)
{
    return c < 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

float pixels_scene_linear(float v, int gamma_mode, float gamma)
{
    double lin;
    if (gamma_mode == PIXELS_GAMMA_POWER) {
        float enc = 1.0f / gamma;
        lin = powf(v > 0.0f ? v : 0.0f, 1.0f / enc);
    } else if (gamma_mode == PIXELS_GAMMA_DIRECT) {
        float c = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
        int byte = (int)floorf(c * 255.0f + 0.5f);
        if (v < 0.0f || v > 1.0f)
            lin = srgb_decode((double)v); /* the file's byte is 0 or 255 either way */
        else {
            float f = (float)srgb_decode((double)c);
            return pixels_srgb_byte(f) == byte ? f : pixels_linear_of((uint8_t)byte);
        }
    } else {
        return v;
    }
    return lin > (double)FLT_MAX ? FLT_MAX : (float)lin;
}

/* One row of pixels_store_bytes_rect.  The master's image is far larger
 * than the caches and a tile's rows are written once, long before anything
 * reads them (the journal's writer, the image writer): the values go out
 * with non-temporal stores, which skip reading each destination line from
 * memory first.  Rank 0's thread CPU on a 32x32 part (4096x4096, one
 * worker): 3.9 -> 2.7 us with a part a RESULT, 8.2 -> 4.6 us with 16
 * (bench/SCALE.md); the store thread (store.h) uses them too. */
static void pixels_linear_row(const uint8_t *src, size_t n, float *dst)
{
#if defined(__SSE2__)
    const int32_t *bits = (const int32_t *)(const void *)linear_of_byte;
    size_t i = 0;
    for (; i < n && ((uintptr_t)(dst + i) & 15) != 0; i++)
        _mm_stream_si32((int *)(void *)(dst + i), bits[src[i]]);
    for (; i + 4 <= n; i += 4)
        _mm_stream_ps(dst + i, _mm_setr_ps(linear_of_byte[src[i]], linear_of_byte[src[i + 1]],
                                           linear_of_byte[src[i + 2]],
                                           linear_of_byte[src[i + 3]]));
    for (; i < n; i++)
        _mm_stream_si32((int *)(void *)(dst + i), bits[src[i]]);
#else
    for (size_t i = 0; i < n; i++)
        dst[i] = linear_of_byte[src[i]];
#endif
}

void pixels_store_bytes_rect(float *image, int image_width, int x, int y, int width, int height,
                             const uint8_t *src)
{
    size_t values = (size_t)width * 3, stride = (size_t)image_width * 3;
    float *dst = image + (size_t)y * stride + (size_t)x * 3;
    for (size_t row = 0; row < (size_t)height; row++)
        pixels_linear_row(src + row * values, values, dst + row * stride);
#if defined(__SSE2__)
    _mm_sfence(); /* the stores seen by every thread before the tile is handed on */
#endif
}
