/*
 * png_write.c — the PNG writer measured: reads a float image (an EXR
 * render), then writes it as PNG in each way in turn, ROUNDS times
 * interleaved (way 1, 2, ..., then again), and prints per way the median
 * write time with its range and the file's size.  "oiio" is the image
 * module's writer ($CSGTRACE_IMAGE_WRITER=oiio); the others are csgtrace's
 * own (host/output/stream.c: bands of 64 rows, each compressed apart) on
 * so many threads, at csgtrace's settings (Up and Sub, run-length) or at a
 * zlib level with every filter ($CSGTRACE_PNG_LEVEL).
 *
 *   build/bench/png_write IMAGE.exr ROUNDS OUTDIR [REPEAT [WAYS]]
 *
 * REPEAT (default 1) tiles the image REPEAT x REPEAT times (a 16384² image
 * from a 4096² render); WAYS (default all) measures only the first ones.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../host/output/image.h"
#include "../host/output/stream.h"
#include "timing.h"

typedef struct {
    const char *name;
    bool module;  /* the image module's writer            */
    int threads;  /* csgtrace's: encoder threads (0: every CPU) */
    int level;    /* -1: csgtrace's settings; else the zlib level */
} setting;

static const setting settings[] = {
    {"oiio (module, Up + RLE)", true, 0, -1},
    {"csgtrace, 1 thread (default settings)", false, 1, -1},
    {"csgtrace, every CPU (default settings)", false, 0, -1},
    {"csgtrace, 1 thread, level 6 every filter", false, 1, 6},
    {"csgtrace, every CPU, level 9 every filter", false, 0, 9},
};
enum { SETTINGS = sizeof settings / sizeof settings[0], MAX_ROUNDS = 64 };

static bool write_one(const setting *s, const char *path, const float *rgb, int w, int h,
                      char *err, size_t err_size)
{
    img_configure(&(img_settings){NULL, s->module, s->level});
    tile_grid g = {w, h, IMG_STREAM_ROWS, 1, sizeof(float), 0};
    img_stream *st = s->module ? NULL : img_stream_open(path, rgb, &g, err, err_size);
    bool ok;
    if (s->module) {
        ok = img_write_rgb(path, rgb, w, h, err, err_size);
    } else if (st) {
        for (int t = 0; t < tile_count(&g); t++)
            img_stream_tile(st, t);
        img_stream_report r;
        ok = img_stream_finish(st, s->threads, &r, err, err_size);
    } else {
        ok = false;
    }
    img_configure(&(img_settings){NULL, false, -1});
    return ok;
}

/* rgb (w x h, freed) tiled n x n times into a new image. */
static float *tiled(float *rgb, int *w, int *h, int n)
{
    size_t row = (size_t)*w * 3, out_row = row * (size_t)n;
    float *out = malloc(out_row * (size_t)*h * (size_t)n * sizeof *out);
    for (size_t y = 0; out && y < (size_t)*h * (size_t)n; y++)
        for (int x = 0; x < n; x++)
            memcpy(out + y * out_row + row * (size_t)x, rgb + (y % (size_t)*h) * row,
                   row * sizeof *out);
    free(rgb);
    *w *= n;
    *h *= n;
    return out;
}

int main(int argc, char **argv)
{
    int rounds = 0, w = 0, h = 0;
    float *rgb = NULL;
    char err[1024];
    int repeat = 1, count = SETTINGS;
    if (argc < 4 || argc > 6 || !bench_parse_int(argv[2], 1, MAX_ROUNDS, &rounds) ||
        (argc > 4 && !bench_parse_int(argv[4], 1, 16, &repeat)) ||
        (argc > 5 && !bench_parse_int(argv[5], 1, SETTINGS, &count))) {
        fprintf(stderr,
                "usage: %s IMAGE.exr ROUNDS(1..%d) OUTDIR [REPEAT(1..16) [SETTINGS(1..%d)]]\n",
                argv[0], MAX_ROUNDS, SETTINGS);
        return 2;
    }
    if (!img_read_rgb(argv[1], &rgb, &w, &h, err, sizeof err)) {
        fprintf(stderr, "%s\n", err);
        return 1;
    }
    if (repeat > 1 && !(rgb = tiled(rgb, &w, &h, repeat))) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    static double t[SETTINGS][MAX_ROUNDS];
    long long size[SETTINGS] = {0};
    char path[4096];
    for (int r = 0; r < rounds; r++)
        for (int i = 0; i < count; i++) {
            snprintf(path, sizeof path, "%s/png_write-%d.png", argv[3], i);
            double t0 = bench_now_s();
            if (!write_one(&settings[i], path, rgb, w, h, err, sizeof err)) {
                fprintf(stderr, "%s: %s\n", settings[i].name, err);
                return 1;
            }
            t[i][r] = bench_now_s() - t0;
            struct stat st;
            size[i] = stat(path, &st) == 0 ? (long long)st.st_size : -1;
            remove(path);
        }
    printf("%dx%d, %d rounds interleaved\n", w, h, rounds);
    printf("| way | write s, median (min-max) | size bytes | size / csgtrace's |\n"
           "|---|---|---|---|\n");
    for (int i = 0; i < count; i++) {
        double med = bench_median(t[i], rounds);
        printf("| %s | %.3f (%.3f-%.3f) | %lld | %.3f |\n", settings[i].name, med, t[i][0],
               t[i][rounds - 1], size[i], (double)size[i] / (double)size[1]);
    }
    free(rgb);
    return 0;
}
