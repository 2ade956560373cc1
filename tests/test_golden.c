/*
 * test_golden.c — every example scene (scenes/NAME.pov) rendered in-process
 * at 160 x 120 and compared with its golden image (tests/golden/NAME.png)
 * through OpenImageIO's ImageBufAlgo::compare: same size, RMSE <= 0.01 and
 * PSNR >= 40 dB.  Thresholds, not byte equality: another compiler or libm
 * may move a highlight by a bit.  `make golden` writes new golden images
 * (look at them before committing them).
 */
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "../csg/flatten.h"
#include "../csg/lang/parser.h"
#include "../host/output/image.h"
#include "../workers/engine.h"

#define GOLDEN_W 160
#define GOLDEN_H 120

static float *render_scene(const char *path)
{
    csg_scene s;
    csg_diag d = {0};
    if (!csg_parse_file(path, &s, &d))
        fail_msg("%s", d.message);
    csg_flatten_opts o = {GOLDEN_W, GOLDEN_H, 0, -1, 1, 0};
    csg_blob b;
    if (!engine_float.flatten(&s, &o, &b, &d))
        fail_msg("%s", d.message);
    csg_scene_free(&s);
    size_t n = (size_t)GOLDEN_W * GOLDEN_H;
    float *rgb = malloc(n * 3 * sizeof(float));
    float *t = malloc(n * sizeof(float));
    uint32_t *surf = malloc(n * sizeof(uint32_t));
    assert_true(rgb && t && surf);
    ray_counts rays = {0};
    tile_rect all = {0, 0, GOLDEN_W, GOLDEN_H};
    engine_float.trace_primary(b.bytes, all, t, surf, &rays);
    engine_float.shade(b.bytes, all, t, surf, rgb, &rays);
    free(t);
    free(surf);
    csg_blob_free(&b);
    return rgb;
}

/* This binary's output folder: <build>/test-out beside its tests/ folder
 * (build/test-out, build/asan/test-out), so the plain and the ASan binaries
 * never write the same files. */
static void test_out_dir(char *out, size_t size)
{
    char exe[4096];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    assert_true(n > 0);
    exe[n] = '\0';
    for (int up = 0; up < 2; up++) { /* .../build[/asan]/tests/test_golden */
        char *slash = strrchr(exe, '/');
        assert_non_null(slash);
        *slash = '\0';
    }
    if ((size_t)snprintf(out, size, "%s/test-out", exe) >= size)
        fail_msg("output folder path too long: %s/test-out", exe);
    mkdir(out, 0755);
}

/* A file of that folder. */
static void test_out_path(char *out, size_t size, const char *name)
{
    char dir[4096];
    test_out_dir(dir, sizeof dir);
    if ((size_t)snprintf(out, size, "%s/%s", dir, name) >= size)
        fail_msg("output path too long: %s/%s", dir, name);
}

static void test_golden_images(void **state)
{
    (void)state;
    const char *root = "."; /* (the tests run in the source tree: tests/run.sh) */
    char dir[4096], out_dir[4096];
    snprintf(dir, sizeof dir, "%s/scenes", root);
    test_out_dir(out_dir, sizeof out_dir);
    DIR *dp = opendir(dir);
    assert_non_null(dp);
    int scenes = 0;
    for (struct dirent *e; (e = readdir(dp));) {
        size_t len = strlen(e->d_name);
        if (len < 5 || strcmp(e->d_name + len - 4, ".pov") != 0)
            continue;
        char scene[4096 + 256], golden[4096 + 256], fresh[4096 + 256], err[512];
        snprintf(scene, sizeof scene, "%s/%s", dir, e->d_name);
        snprintf(golden, sizeof golden, "%s/tests/golden/%.*s.png", root, (int)(len - 4), e->d_name);
        snprintf(fresh, sizeof fresh, "%s/%.*s.png", out_dir, (int)(len - 4), e->d_name);
        float *rgb = render_scene(scene);
        if (!img_write_rgb(fresh, rgb, GOLDEN_W, GOLDEN_H, err, sizeof err))
            fail_msg("%s", err);
        free(rgb);
        img_compare_result r;
        if (!img_compare_files(fresh, golden, 1.0 / 255.0, &r, err, sizeof err))
            fail_msg("%s: %s (run `make golden` to create it)", golden, err);
        printf("  %-20s RMSE %.5f  PSNR %6.2f dB  max %.4f  pixels over 1/255: %ld\n", e->d_name,
               r.rmse, r.psnr, r.max_error, r.pixels_over);
        if (!r.same_size || r.rmse > 0.01 || r.psnr < 40.0)
            fail_msg("%s differs from %s: size %s, RMSE %g, PSNR %g", fresh, golden,
                     r.same_size ? "same" : "DIFFERENT", r.rmse, r.psnr);
        scenes++;
    }
    closedir(dp);
    assert_true(scenes >= 6);
}

/* The comparison itself catches a different image and a different size. */
static void test_compare_detects_differences(void **state)
{
    (void)state;
    char a[4096], b[4096], c[4096], err[512];
    test_out_path(a, sizeof a, "cmp_a.png");
    test_out_path(b, sizeof b, "cmp_b.png");
    test_out_path(c, sizeof c, "cmp_c.png");
    float img[8 * 8 * 3] = {0};
    assert_true(img_write_rgb(a, img, 8, 8, err, sizeof err));
    img[3 * 27 + 1] = 1.0f;
    assert_true(img_write_rgb(b, img, 8, 8, err, sizeof err));
    assert_true(img_write_rgb(c, img, 8, 4, err, sizeof err));
    img_compare_result r;
    assert_true(img_compare_files(a, a, 1.0 / 255.0, &r, err, sizeof err));
    assert_true(r.same_size && r.rmse == 0 && r.pixels_over == 0);
    assert_true(img_compare_files(a, b, 1.0 / 255.0, &r, err, sizeof err));
    assert_true(r.same_size && r.rmse > 0 && r.pixels_over == 1 && r.max_error > 0.99);
    assert_true(img_compare_files(a, c, 1.0 / 255.0, &r, err, sizeof err));
    assert_false(r.same_size);
}

/* The 8-bit encoding, read back: each byte is the sRGB curve of the value,
 * times 255, rounded half away from zero and clamped — over a sweep of
 * every 1/65536 of [0, 1], values past both ends, NaN, and pseudo-random
 * values, at widths that put them in every position of a row. */
static float srgb(float v)
{
    if (!(v > 0.0f))
        return 0.0f;
    if (v >= 1.0f)
        return 1.0f;
    return v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
}

static void test_display_encoding(void **state)
{
    (void)state;
    enum { N = 65536 + 4096 };
    float *in = malloc(N * sizeof(float));
    assert_non_null(in);
    uint32_t x = 12345;
    for (int i = 0; i < N; i++) {
        x = x * 1664525u + 1013904223u;
        in[i] = i <= 65536 ? (float)i / 65536.0f : -0.5f + 2.0f * (float)(x >> 8) / 16777216.0f;
    }
    in[N - 1] = NAN;
    int widths[] = {1, 7, 333};
    for (int k = 0; k < 3; k++) {
        int w = widths[k], h = (N + 3 * w - 1) / (3 * w);
        float *rgb = calloc((size_t)w * h * 3, sizeof(float));
        assert_non_null(rgb);
        memcpy(rgb, in, N * sizeof(float));
        char path[4096], err[512], name[64];
        snprintf(name, sizeof name, "encoding_%d.png", w);
        test_out_path(path, sizeof path, name);
        if (!img_write_rgb(path, rgb, w, h, err, sizeof err))
            fail_msg("%s", err);
        float *back;
        int bw, bh;
        if (!img_read_rgb(path, &back, &bw, &bh, err, sizeof err))
            fail_msg("%s", err);
        assert_true(bw == w && bh == h);
        for (int i = 0; i < N; i++) {
            float e = srgb(rgb[i]) * 255.0f;
            int want = e >= 255.0f ? 255 : (int)roundf(e);
            if ((int)roundf(back[i] * 255.0f) != want)
                fail_msg("width %d: value %a (#%d) gave %g, want %d", w, (double)rgb[i], i,
                         (double)(back[i] * 255.0f), want);
        }
        free(back);
        free(rgb);
    }
    free(in);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compare_detects_differences),
        cmocka_unit_test(test_display_encoding),
        cmocka_unit_test(test_golden_images),
    };
    return cmocka_run_group_tests_name("golden", tests, NULL, NULL);
}
