/*
 * shadow_pass.c — the device's shadow answers against the C worker's own
 * shadow rays on the same primary hits (#36 item 3), for the benchmarks
 * only (never linked into csgtrace).
 *
 *   build/bench/shadow_pass SCENE.pov [--width W] [--height H] [--repeat R]
 *                           [--precision float|double] [--kernel scalar|packet]
 *
 * Parses and flattens the scene as `csgtrace render` does, opens one
 * OpenCL context (the program built for the scene's features, as render
 * builds it), traces the primary records once (ocl_primary_pass, untimed),
 * then runs an untimed round and R timed rounds of:
 *   device  ocl_shadow_answers over the whole image (upload, csg_shadows,
 *           download), CPU time of the whole process (PoCL's threads);
 *   plain   engine->shade over the image in 32 x 32 tiles (as a worker
 *           shades them), the calling thread's CPU time;
 *   answered engine->shade_answered over the same tiles with the device's
 *           answers, the calling thread's CPU time.
 * The C worker's cost of the shadow rays the device takes over is
 * plain - answered (per round, paired); its rate is the rays taken over
 * (rays.shadow_answered) per CPU-second of that difference, and the
 * device's rate the same rays per CPU-second of the device's answers.
 * Their ratio is saved / device: how many CPU-seconds of worker time one
 * CPU-second of the device replaces.  That difference of two shading times
 * is noisy; so each round also times
 *   c_masks csg_shadow_masks, the kernel's own code, run in C over every
 *           record on the calling thread (float only: this file is
 *           compiled in float), the C cost of exactly the device's work;
 * "kernel_ratio" is c_masks / device (the same answers, per CPU-second).  The two images are compared bit for
 * bit (exit status 1 when they differ).
 *
 * Prints one JSON object: {"scene", "width", "height", "precision",
 * "kernel", "hits", "answers" (known bits), "taken" (shadow rays answered
 * from the records), "traced_plain", "traced_answered", "repeat",
 * "device_cpu_s", "device_wall_s", "plain_cpu_s", "answered_cpu_s",
 * "saved_cpu_s" (each: {"median", "min", "max"}), "device_mrays_per_cpu_s",
 * "c_mrays_per_cpu_s", "ratio", "identical"}.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/device/camera.h"
#include "../csg/device/shadow.h"
#include "../csg/features.h"
#include "../csg/lang/parser.h"
#include "../host/pass/ocl.h"
#include "../workers/engine.h"
#include "timing.h"

#define TILE 32

typedef struct {
    double median, min, max;
} spread;

static spread spread_of(double *v, int n)
{
    spread s = {0, 0, 0};
    if (n == 0)
        return s;
    s.median = bench_median(v, n); /* (sorts v) */
    s.min = v[0];
    s.max = v[n - 1];
    return s;
}

static void print_spread(const char *key, spread s)
{
    printf("  \"%s\": {\"median\": %.6f, \"min\": %.6f, \"max\": %.6f},\n", key, s.median, s.min,
           s.max);
}

/* csg_shadow_masks over every record in C (float blobs); its thread's CPU
 * seconds, the masks checked against the device's (*same). */
static double masks_c(const void *blob, const void *t, const uint32_t *surf,
                      const uint32_t *known, const uint32_t *lit, bool *same)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    const csg_flat_light *lights =
        (const csg_flat_light *)(const void *)((const char *)blob + h->off_lights);
    csg_view v = csg_blob_view(blob);
    const real *tr = t;
    double c0 = bench_clock_s(CLOCK_THREAD_CPUTIME_ID);
    for (int y = 0; y < h->height; y++)
        for (int x = 0; x < h->width; x++) {
            size_t i = (size_t)y * (size_t)h->width + (size_t)x;
            if (surf[i] == CSG_SURF_NONE)
                continue;
            csg_ray r = csg_sample_ray(csg_blob_camera(blob), h->width, h->height, x, y, 1, 0);
            csg_u32 k, l;
            csg_shadow_masks(v, lights, h->light_count, r, tr[i], surf[i], &k, &l);
            if (k != known[i] || l != lit[i]) {
                static int told;
                if (told++ < 5)
                    fprintf(stderr, "shadow_pass: record (%d, %d): C known %08x lit %08x, "
                                    "OpenCL %08x %08x\n",
                            x, y, (unsigned)k, (unsigned)l, (unsigned)known[i], (unsigned)lit[i]);
                *same = false;
            }
        }
    return bench_clock_s(CLOCK_THREAD_CPUTIME_ID) - c0;
}

/* engine->shade_answered over the image in TILE x TILE tiles (records
 * packed per tile as a worker receives them); its thread's CPU seconds. */
static double shade_tiles(const engine *e, const void *blob, const void *t,
                          const uint32_t *surf, const uint32_t *known, const uint32_t *lit,
                          float *rgb, ray_counts *rays)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    size_t rs = e->real_size, spp = (size_t)h->spp;
    static char tt[TILE * TILE * 8 * 4];
    static uint32_t ts[TILE * TILE * 4], tk[TILE * TILE * 4], tl[TILE * TILE * 4];
    static float trgb[TILE * TILE * 3];
    double c0 = bench_clock_s(CLOCK_THREAD_CPUTIME_ID);
    for (int y0 = 0; y0 < h->height; y0 += TILE)
        for (int x0 = 0; x0 < h->width; x0 += TILE) {
            tile_rect r = {x0, y0, h->width - x0 < TILE ? h->width - x0 : TILE,
                           h->height - y0 < TILE ? h->height - y0 : TILE};
            size_t line = (size_t)r.width * spp;
            for (int row = 0; row < r.height; row++) {
                size_t src = ((size_t)(y0 + row) * (size_t)h->width + (size_t)x0) * spp;
                memcpy(tt + (size_t)row * line * rs, (const char *)t + src * rs, line * rs);
                memcpy(ts + (size_t)row * line, surf + src, line * 4);
                if (known) {
                    memcpy(tk + (size_t)row * line, known + src, line * 4);
                    memcpy(tl + (size_t)row * line, lit + src, line * 4);
                }
            }
            e->shade_answered(blob, r, tt, ts, known ? tk : NULL, known ? tl : NULL, trgb, rays);
            for (int row = 0; row < r.height; row++)
                memcpy(rgb + ((size_t)(y0 + row) * (size_t)h->width + (size_t)x0) * 3,
                       trgb + (size_t)row * (size_t)r.width * 3, (size_t)r.width * 3 * 4);
        }
    return bench_clock_s(CLOCK_THREAD_CPUTIME_ID) - c0;
}

static int usage(void)
{
    fprintf(stderr, "usage: shadow_pass SCENE.pov [--width W] [--height H] [--repeat R] "
                    "[--precision float|double] [--kernel scalar|packet]\n");
    return 2;
}

int main(int argc, char **argv)
{
    const char *scene = NULL, *kname = "packet";
    bench_options args = {512, 512, 5, false};
    for (int i = 1; i < argc; i++) {
        if (bench_common_option(argc, argv, &i, &args))
            continue;
        if (!strcmp(argv[i], "--kernel") && i + 1 < argc)
            kname = argv[++i];
        else if (argv[i][0] != '-' && !scene)
            scene = argv[i];
        else
            return usage();
    }
    enum ocl_kernel kernel;
    if (!scene || !ocl_kernel_parse(kname, &kernel) || kernel == OCL_KERNEL_AUTO)
        return usage();
    const engine *e = args.dbl ? &engine_double : &engine_float;
    csg_scene s;
    csg_diag d;
    csg_blob blob = {NULL, 0};
    memset(&d, 0, sizeof d);
    csg_scene_init(&s);
    csg_flatten_opts o = {args.width, args.height, 0, -1, 1, 0};
    bool ok = csg_parse_file(scene, &s, &d) && e->flatten(&s, &o, &blob, &d);
    csg_scene_free(&s);
    if (!ok) {
        fprintf(stderr, "%s\n", d.message[0] ? d.message : "shadow_pass: cannot load the scene");
        return 2;
    }
    const csg_blob_header *h = csg_blob_hdr(blob.bytes);
    size_t n = (size_t)h->width * (size_t)h->height, rs = e->real_size;
    csg_features f = csg_blob_features(blob.bytes);
    ocl_options opt = {.use_double = args.dbl, .features = &f};
    ocl_ctx *ctx = NULL;
    ocl_timing tm;
    void *t = malloc(n * rs);
    uint32_t *surf = malloc(n * 4), *known = malloc(n * 4), *lit = malloc(n * 4);
    uint32_t *hits = malloc(n * 4);
    float *rgb_plain = malloc(n * 12), *rgb_answered = malloc(n * 12);
    int repeat = args.repeat;
    double *dev = malloc((size_t)repeat * sizeof *dev), *dev_wall = malloc((size_t)repeat * 8);
    double *plain = malloc((size_t)repeat * 8), *answered = malloc((size_t)repeat * 8);
    double *saved = malloc((size_t)repeat * 8), *cm = malloc((size_t)repeat * 8);
    if (!t || !surf || !known || !lit || !hits || !rgb_plain || !rgb_answered || !dev ||
        !dev_wall || !plain || !answered || !saved || !cm) {
        fprintf(stderr, "shadow_pass: out of memory\n");
        return 1;
    }
    if (!ocl_open_kernel(&opt, kernel, &ctx, &tm, &d) ||
        !ocl_primary_pass(ctx, blob.bytes, TILE, t, surf, hits, &tm, &d)) {
        fprintf(stderr, "shadow_pass: %s\n", d.message);
        return 1;
    }
    ray_counts rp = {0}, ra = {0};
    bool identical = true;
    for (int r = -1; r < repeat; r++) { /* round -1: untimed */
        double w0 = bench_now_s(), c0 = bench_clock_s(CLOCK_PROCESS_CPUTIME_ID);
        if (!ocl_shadow_answers(ctx, blob.bytes, t, surf, known, lit, NULL, &d)) {
            fprintf(stderr, "shadow_pass: %s\n", d.message);
            return 1;
        }
        double c1 = bench_clock_s(CLOCK_PROCESS_CPUTIME_ID), w1 = bench_now_s();
        memset(&rp, 0, sizeof rp);
        memset(&ra, 0, sizeof ra);
        double p = shade_tiles(e, blob.bytes, t, surf, NULL, NULL, rgb_plain, &rp);
        double a = shade_tiles(e, blob.bytes, t, surf, known, lit, rgb_answered, &ra);
        if (memcmp(rgb_plain, rgb_answered, n * 12) != 0) {
            if (identical)
                fprintf(stderr, "shadow_pass: the pixels with the answers differ\n");
            identical = false;
        }
        double m = args.dbl ? 0.0 : masks_c(blob.bytes, t, surf, known, lit, &identical);
        if (r < 0)
            continue;
        cm[r] = m;
        dev[r] = c1 - c0;
        dev_wall[r] = w1 - w0;
        plain[r] = p;
        answered[r] = a;
        saved[r] = p - a;
    }
    uint64_t answers = 0, nhits = 0;
    for (size_t i = 0; i < n; i++) {
        answers += (uint64_t)__builtin_popcount(known[i]);
        nhits += surf[i] != 0;
    }
    spread sd = spread_of(dev, repeat), sw = spread_of(dev_wall, repeat);
    spread sp = spread_of(plain, repeat), sa = spread_of(answered, repeat);
    spread ss = spread_of(saved, repeat), sm = spread_of(cm, repeat);
    double taken = (double)ra.shadow_answered;
    printf("{\n  \"scene\": \"%s\",\n  \"width\": %d,\n  \"height\": %d,\n  \"precision\": \"%s\",\n"
           "  \"kernel\": \"%s\",\n  \"hits\": %llu,\n  \"answers\": %llu,\n  \"taken\": %llu,\n"
           "  \"traced_plain\": %llu,\n  \"traced_answered\": %llu,\n  \"repeat\": %d,\n",
           scene, h->width, h->height, e->name, tm.kernel, (unsigned long long)nhits,
           (unsigned long long)answers, (unsigned long long)ra.shadow_answered,
           (unsigned long long)rp.shadow, (unsigned long long)ra.shadow, repeat);
    print_spread("device_cpu_s", sd);
    print_spread("device_wall_s", sw);
    print_spread("plain_cpu_s", sp);
    print_spread("answered_cpu_s", sa);
    print_spread("saved_cpu_s", ss);
    print_spread("c_masks_cpu_s", sm);
    printf("  \"device_mrays_per_cpu_s\": %.4f,\n  \"c_mrays_per_cpu_s\": %.4f,\n"
           "  \"ratio\": %.3f,\n  \"kernel_ratio\": %.3f,\n  \"identical\": %s\n}\n",
           taken / sd.median / 1e6, ss.median > 0 ? taken / ss.median / 1e6 : 0.0,
           sd.median > 0 ? ss.median / sd.median : 0.0,
           sd.median > 0 ? sm.median / sd.median : 0.0, identical ? "true" : "false");
    ocl_close(ctx);
    csg_blob_free(&blob);
    return identical ? 0 : 1;
}
