/*
 * primary_pass.c — the primary pass's throughput, for the benchmarks only
 * (never linked into csgtrace): the OpenCL pass in each kernel variant
 * against the C worker's own primary rays, on the same flattened scene, in
 * one process.
 *
 *   build/bench/primary_pass SCENE.pov [--width W] [--height H] [--spp N]
 *                            [--repeat R] [--precision float|double]
 *                            [--variants c,scalar,packet]
 *
 * A kernel variant may carry a suffix: packet+spec is the program built
 * for the scene's feature set (csg/features.h, what `csgtrace render`
 * builds), packet+kinds, +csg specialised on that part of it alone (the
 * gain of each specialisation), or on several (packet+kinds+csg);
 * the plain name is the general program.  +copy: the records go through
 * device buffers and are copied out, as on a discrete GPU, where the
 * plain variant writes them in place on a device in host memory (the
 * records' arrays are memory_pages_alloc's).
 *
 * Parses and flattens the scene as `csgtrace render` does, opens one
 * OpenCL context per kernel variant (ocl_open_kernel; the build and
 * PoCL's first launch stay in compile_s, outside every timing), runs every
 * variant once untimed, then R rounds that each run every variant once, the
 * order rotated from round to round (interleaved: a slow spell of the
 * shared machine hits every variant alike).  Timed figures:
 *   c       engine->trace_primary over the image in 32 x 32 tiles, the
 *           calling thread alone (one core);
 *   scalar, packet
 *           ocl_primary_pass (upload, kernels, download: its primary_s) on
 *           every compute unit of the device.
 * Every variant's records are compared with the C records bit for bit;
 * a difference is reported and makes the exit status 1.
 *
 * Prints one JSON object on stdout:
 *   {"scene", "width", "height", "spp", "precision", "rays", "hits",
 *    "roots", "bvh_nodes", "repeat", "device",
 *    "variants": {NAME: {"rounds_s", "cpu_rounds_s" (each round's time, in
 *                        round order: for paired ratios), "cores", "median_s",
 *                        "min_s", "max_s",
 *                        "mrays_per_s", "mrays_per_core", "cpu_median_s",
 *                        "cpu_min_s", "cpu_max_s", "mrays_per_cpu_s",
 *                        "compile_s", "kernel", "records_in_place",
 *                        "identical"}}}
 * with mrays_per_s = rays / median_s / 1e6 (wall clock), mrays_per_core
 * that over cores (1 for c, the device's compute units for OpenCL), and
 * mrays_per_cpu_s = rays / cpu_median_s / 1e6, where cpu_s is the CPU time
 * the whole process (PoCL's threads included) spent on the pass: rays per
 * core-second actually obtained, the fairer per-core figure on a machine
 * shared with other work (a busy machine lengthens wall time, not CPU
 * time).
 * Exit status: 0, 2 bad arguments or scene, 1 other failures.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/features.h"
#include "../csg/lang/parser.h"
#include "../host/memory.h"
#include "../host/pass/ocl.h"
#include "../workers/engine.h"
#include "timing.h"

#define TILE 32
#define MAX_VARIANTS 16
#define VARIANT_NAME 32

typedef struct {
    char name[VARIANT_NAME]; /* "c", "scalar", "packet+spec", ...  */
    ocl_ctx *ctx;      /* NULL for c                           */
    ocl_timing open;   /* compile_s, device, kernel, cores     */
    double *times;     /* repeat entries: wall seconds          */
    double *cpu;       /* repeat entries: CPU seconds of the process */
    void *t;           /* the records of the last pass         */
    uint32_t *surf;
    bool identical;    /* every pass equalled the C records     */
    bool in_place;     /* its passes wrote the records in place  */
} variant;

/* The C worker's records of the whole image, tile by tile (as a worker
 * traces them: engine->trace_primary writes a tile's records packed). */
static void trace_c(const engine *e, const void *blob, void *t, uint32_t *surf, void *tile_t,
                    uint32_t *tile_surf)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    size_t rs = e->real_size, spp = (size_t)h->spp, row = (size_t)h->width * spp;
    ray_counts rays = {0};
    for (int y = 0; y < h->height; y += TILE) {
        for (int x = 0; x < h->width; x += TILE) {
            tile_rect r = {x, y, x + TILE <= h->width ? TILE : h->width - x,
                           y + TILE <= h->height ? TILE : h->height - y};
            e->trace_primary(blob, r, tile_t, tile_surf, &rays);
            size_t w = (size_t)r.width * spp;
            for (int k = 0; k < r.height; k++) {
                size_t dst = (size_t)(y + k) * row + (size_t)x * spp;
                memcpy((char *)t + dst * rs, (char *)tile_t + (size_t)k * w * rs, w * rs);
                memcpy(surf + dst, tile_surf + (size_t)k * w, w * sizeof *surf);
            }
        }
    }
}

/* CPU seconds of the whole process: every thread, PoCL's included. */
static double cpu_now_s(void)
{
    return bench_clock_s(CLOCK_PROCESS_CPUTIME_ID);
}

static bool run_once(variant *v, const engine *e, const void *blob, void *tile_t,
                     uint32_t *tile_surf, double *seconds)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    if (!v->ctx) {
        double t0 = bench_now_s();
        trace_c(e, blob, v->t, v->surf, tile_t, tile_surf);
        *seconds = bench_now_s() - t0;
        return true;
    }
    size_t tiles = (size_t)((h->width + TILE - 1) / TILE) * (size_t)((h->height + TILE - 1) / TILE);
    uint32_t *hits = malloc(tiles * sizeof *hits);
    ocl_timing tm;
    csg_diag d;
    memset(&tm, 0, sizeof tm);
    memset(&d, 0, sizeof d);
    bool ok = hits && ocl_primary_pass(v->ctx, blob, TILE, v->t, v->surf, hits, &tm, &d);
    free(hits);
    if (!ok)
        fprintf(stderr, "primary_pass: %s: %s\n", v->name, d.message[0] ? d.message : "failed");
    *seconds = tm.primary_s;
    v->in_place = tm.records_in_place;
    return ok;
}

/* "name": [x, ...] of n values, in round order. */
static void print_rounds(const char *name, const double *x, int n)
{
    printf("\"%s\": [", name);
    for (int i = 0; i < n; i++)
        printf("%s%.6f", i ? ", " : "", x[i]);
    printf("], ");
}

static void print_variant(const variant *v, int repeat, uint64_t rays, bool last)
{
    printf("    \"%s\": {", v->name);
    print_rounds("rounds_s", v->times, repeat); /* before the medians sort them */
    print_rounds("cpu_rounds_s", v->cpu, repeat);
    double median = bench_median(v->times, repeat);
    double cpu = bench_median(v->cpu, repeat);
    int cores = v->ctx ? v->open.compute_units : 1;
    printf("\"cores\": %d, \"median_s\": %.6f, \"min_s\": %.6f, \"max_s\": %.6f, "
           "\"mrays_per_s\": %.4f, \"mrays_per_core\": %.4f, \"cpu_median_s\": %.6f, "
           "\"cpu_min_s\": %.6f, \"cpu_max_s\": %.6f, \"mrays_per_cpu_s\": %.4f, "
           "\"compile_s\": %.3f, \"kernel\": \"%s\", \"records_in_place\": %s, "
           "\"identical\": %s}%s\n",
           cores, median, v->times[0], v->times[repeat - 1], (double)rays / median / 1e6,
           (double)rays / median / 1e6 / cores, cpu, v->cpu[0], v->cpu[repeat - 1],
           (double)rays / cpu / 1e6, v->open.compile_s, v->ctx ? v->open.kernel : "c",
           v->in_place ? "true" : "false", v->identical ? "true" : "false", last ? "" : ",");
}

static int usage(void)
{
    fprintf(stderr, "usage: primary_pass SCENE.pov [--width W] [--height H] [--spp N] "
                    "[--repeat R] [--precision float|double] [--variants c,scalar,packet]\n"
                    "  a kernel variant may end in +spec (the program specialised on the "
                    "scene), +kinds or +csg (on that part of it only), +copy (records "
                    "copied out of device buffers)\n");
    return 2;
}

/* The feature set of a kernel variant "KERNEL[+PART...]" for a scene
 * that uses `scene`: everything (the general program) with the scene's
 * own set in each part named (spec: all of it; kinds: its primitive
 * kinds; csg: no interval lists when it has none).  `parts` is what follows the first '+' ("kinds+csg"),
 * NULL for none.  False for an unknown part. */
static bool variant_features(const char *parts, csg_features scene, csg_features *out)
{
    csg_features f = csg_features_all();
    while (parts && *parts) {
        size_t len = strcspn(parts, "+");
        uint32_t bit = 0;
        if (len == 4 && !strncmp(parts, "spec", len))
            f = scene;
        else if (len == 5 && !strncmp(parts, "kinds", len))
            f.kinds = scene.kinds;
        else if (len == 3 && !strncmp(parts, "csg", len))
            bit = CSG_FEAT_CSG;
        else if (len == 4 && !strncmp(parts, "copy", len))
            ; /* (not a feature: variant_open) */
        else
            return false;
        f.uses = (f.uses & ~bit) | (scene.uses & bit);
        parts += len + (parts[len] == '+');
    }
    *out = f;
    return true;
}

/* Opens the OpenCL context of variant "scalar[+PART]" or "packet[+PART]";
 * 2 for a name it does not know, 1 when OpenCL fails. */
static int variant_open(variant *v, bool dbl, csg_features scene)
{
    char kname[VARIANT_NAME];
    memcpy(kname, v->name, sizeof kname); /* NUL-terminated: memset, < VARIANT_NAME */
    char *plus = strchr(kname, '+');
    if (plus)
        *plus++ = '\0';
    enum ocl_kernel kernel;
    csg_features f;
    if (!ocl_kernel_parse(kname, &kernel) || kernel == OCL_KERNEL_AUTO ||
        !variant_features(plus, scene, &f)) {
        fprintf(stderr, "primary_pass: unknown variant '%s'\n", v->name);
        return 2;
    }
    ocl_options opt = {.use_double = dbl, .features = &f,
                       .copy_buffers = plus && strstr(plus, "copy") != NULL};
    csg_diag d;
    memset(&d, 0, sizeof d);
    if (!ocl_open_kernel(&opt, kernel, &v->ctx, &v->open, &d)) {
        fprintf(stderr, "primary_pass: %s: %s\n", v->name, d.message);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *scene = NULL, *list = "c,scalar,packet";
    bench_options args = {1024, 1024, 5, false};
    int spp = 1;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        bool has_value = i + 1 < argc;
        if (bench_common_option(argc, argv, &i, &args)) {
            continue;
        } else if (!strcmp(a, "--spp") && has_value &&
                   bench_parse_int(argv[i + 1], 1, CSG_MAX_SPP, &spp)) {
            i++;
        } else if (!strcmp(a, "--variants") && has_value) {
            list = argv[++i];
        } else if (a[0] != '-' && !scene) {
            scene = a;
        } else {
            return usage();
        }
    }
    int width = args.width, height = args.height, repeat = args.repeat;
    bool dbl = args.dbl;
    if (!scene)
        return usage();

    const engine *e = dbl ? &engine_double : &engine_float;
    csg_scene s;
    csg_diag d;
    csg_blob blob = {NULL, 0};
    memset(&d, 0, sizeof d);
    csg_scene_init(&s);
    csg_flatten_opts o = {width, height, 0, -1, spp, 0};
    bool ok = csg_parse_file(scene, &s, &d) && e->flatten(&s, &o, &blob, &d);
    csg_scene_free(&s);
    if (!ok) {
        fprintf(stderr, "%s\n", d.message[0] ? d.message : "primary_pass: cannot load the scene");
        return 2;
    }
    const csg_blob_header *h = csg_blob_hdr(blob.bytes);
    uint64_t rays = (uint64_t)width * (uint64_t)height * (uint64_t)spp;
    size_t rs = e->real_size;

    /* The variants in the order given: c first (the reference), then the
     * OpenCL ones. */
    variant vs[MAX_VARIANTS];
    int nv = 0;
    memset(vs, 0, sizeof vs);
    for (const char *p = list; *p; p += *p == ',') {
        size_t len = strcspn(p, ",");
        if (nv == MAX_VARIANTS || len == 0 || len >= VARIANT_NAME)
            return usage();
        variant *v = &vs[nv++];
        memcpy(v->name, p, len);
        p += len;
        v->identical = true;
        v->times = malloc((size_t)repeat * sizeof *v->times);
        v->cpu = malloc((size_t)repeat * sizeof *v->cpu);
        v->t = memory_pages_alloc((size_t)rays * rs, false);
        v->surf = memory_pages_alloc((size_t)rays * sizeof *v->surf, false);
        if (!v->times || !v->cpu || !v->t || !v->surf) {
            fprintf(stderr, "primary_pass: out of memory\n");
            return 1;
        }
        if (strcmp(v->name, "c") == 0)
            continue;
        int failed = variant_open(v, dbl, csg_blob_features(blob.bytes));
        if (failed)
            return failed;
    }
    if (nv == 0 || strcmp(vs[0].name, "c") != 0) {
        fprintf(stderr, "primary_pass: --variants must include c (the reference)\n");
        return 2;
    }
    void *tile_t = malloc((size_t)TILE * TILE * (size_t)spp * rs);
    uint32_t *tile_surf = malloc((size_t)TILE * TILE * (size_t)spp * sizeof *tile_surf);
    if (!tile_t || !tile_surf) {
        fprintf(stderr, "primary_pass: out of memory\n");
        return 1;
    }

    int status = 0;
    double seconds;
    for (int r = -1; r < repeat; r++) { /* round -1: the untimed warm-up */
        for (int j = 0; j < nv; j++) {
            variant *v = &vs[r < 0 ? j : (j + r) % nv];
            double c0 = cpu_now_s();
            if (!run_once(v, e, blob.bytes, tile_t, tile_surf, &seconds))
                return 1;
            if (r >= 0) {
                v->times[r] = seconds;
                v->cpu[r] = cpu_now_s() - c0;
            }
        }
        for (int j = 1; j < nv; j++) {
            variant *v = &vs[j];
            if (memcmp(v->t, vs[0].t, (size_t)rays * rs) != 0 ||
                memcmp(v->surf, vs[0].surf, (size_t)rays * sizeof *v->surf) != 0) {
                if (v->identical)
                    fprintf(stderr, "primary_pass: %s records differ from the C records\n",
                            v->name);
                v->identical = false;
                status = 1;
            }
        }
    }

    uint64_t hits = 0;
    for (uint64_t i = 0; i < rays; i++)
        hits += vs[0].surf[i] != CSG_SURF_NONE;
    const char *device = nv > 1 ? vs[1].open.device_name : "";
    printf("{\"scene\": \"%s\", \"width\": %d, \"height\": %d, \"spp\": %d, \"precision\": \"%s\", "
           "\"rays\": %llu, \"hits\": %llu, \"roots\": %d, \"bvh_nodes\": %d, \"repeat\": %d, "
           "\"device\": \"%s\",\n  \"variants\": {\n",
           scene, width, height, spp, e->name, (unsigned long long)rays,
           (unsigned long long)hits, h->root_count, h->bvh_count, repeat, device);
    for (int j = 0; j < nv; j++)
        print_variant(&vs[j], repeat, rays, j == nv - 1);
    printf("  }\n}\n");
    for (int j = 0; j < nv; j++) {
        ocl_close(vs[j].ctx);
        free(vs[j].times);
        free(vs[j].cpu);
        free(vs[j].t);
        free(vs[j].surf);
    }
    free(tile_t);
    free(tile_surf);
    csg_blob_free(&blob);
    return status;
}
