/*
 * primary_rays.c — a timing harness over the engine's primary pass, for the
 * benchmarks only (never linked into csgtrace).
 *
 *   build/bench/primary_rays SCENE.pov [--width W] [--height H] [--repeat R]
 *                            [--precision float|double] [--export-spheres FILE]
 *
 * Parses and flattens the scene as `csgtrace render` does, then traces every
 * primary ray of the image through engine->trace_primary, in the renderer's
 * 32 x 32 tiles, once untimed and then R times timed (one core, the calling
 * thread).  Prints one JSON object on stdout:
 *   {"width", "height", "roots", "bvh_nodes", "rays", "hits", "repeat",
 *    "best_s", "median_s", "max_s", "mrays_per_s"}
 * where mrays_per_s = rays / median_s / 1e6.  Parsing, flattening and the
 * BVH build are outside every timed pass.
 *
 * --export-spheres FILE writes the scene for bench/embree_primary.c: the
 * image size, the blob's camera and every sphere (centre, radius) exactly
 * as the blob holds them (%.9g round-trips a float), so the Embree helper
 * traces the very same rays (it builds them with csg/device/camera.h) at
 * the very same spheres.  Only scenes of untransformed spheres (what
 * `csgtrace gen spheres` writes) can be exported: anything else is an
 * error.  Exit status: 0, 2 bad arguments or scene, 1 other failures.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/device/flat.h"
#include "../csg/lang/parser.h"
#include "../workers/engine.h"
#include "timing.h"

#define TILE 32

/* One pass over the image; returns the number of records that hit. */
static uint64_t trace_image(const engine *e, const void *blob, int w, int h, void *t,
                            uint32_t *surf, ray_counts *rays)
{
    uint64_t hits = 0;
    for (int y = 0; y < h; y += TILE) {
        for (int x = 0; x < w; x += TILE) {
            tile_rect r = {x, y, x + TILE <= w ? TILE : w - x, y + TILE <= h ? TILE : h - y};
            e->trace_primary(blob, r, t, surf, rays);
            for (int i = 0; i < r.width * r.height; i++)
                hits += surf[i] != CSG_SURF_NONE;
        }
    }
    return hits;
}

/* The spheres and the camera of a float blob, for bench/embree_primary. */
static bool export_spheres(const void *blob, const char *path)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    const unsigned char *b = blob;
    const csg_prim *prims = (const csg_prim *)(b + h->off_prims);
    const csg_camera *c = (const csg_camera *)(b + h->off_camera);
    if (h->real_size != 4 || h->prim_count != h->root_count) {
        fprintf(stderr, "primary_rays: --export-spheres needs a float scene of plain spheres\n");
        return false;
    }
    for (int i = 0; i < h->prim_count; i++) {
        if (prims[i].kind != CSG_PRIM_SPHERE || prims[i].flags != 0) {
            fprintf(stderr, "primary_rays: primitive %d is not a plain sphere\n", i);
            return false;
        }
    }
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "primary_rays: cannot write %s: %s\n", path, strerror(errno));
        return false;
    }
    if (c->projection != CSG_CAMERA_PERSPECTIVE || c->hither != 0.0f) {
        fprintf(stderr, "primary_rays: %s: only a perspective camera without hither is "
                        "exported\n", path);
        fclose(f);
        return false;
    }
    fprintf(f, "csgtrace-spheres 1\nimage %d %d\ncamera", h->width, h->height);
    const float *vecs[4] = {c->location, c->direction, c->right, c->up};
    for (int v = 0; v < 4; v++)
        for (int k = 0; k < 3; k++)
            fprintf(f, " %.9g", (double)vecs[v][k]);
    fprintf(f, "\nspheres %d\n", h->prim_count);
    for (int i = 0; i < h->prim_count; i++)
        fprintf(f, "%.9g %.9g %.9g %.9g\n", (double)prims[i].p[0], (double)prims[i].p[1],
                (double)prims[i].p[2], (double)prims[i].p[3]);
    bool ok = !ferror(f);
    ok = fclose(f) == 0 && ok;
    if (!ok)
        fprintf(stderr, "primary_rays: cannot write %s\n", path);
    return ok;
}

int main(int argc, char **argv)
{
    const char *scene = NULL, *export_path = NULL;
    bench_options args = {384, 384, 5, false};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        bool has_value = i + 1 < argc;
        if (bench_common_option(argc, argv, &i, &args)) {
            continue;
        } else if (!strcmp(a, "--export-spheres") && has_value) {
            export_path = argv[++i];
        } else if (a[0] != '-' && !scene) {
            scene = a;
        } else {
            fprintf(stderr, "usage: primary_rays SCENE.pov [--width W] [--height H] [--repeat R] "
                            "[--precision float|double] [--export-spheres FILE]\n");
            return 2;
        }
    }
    int width = args.width, height = args.height, repeat = args.repeat;
    bool dbl = args.dbl;
    if (!scene) {
        fprintf(stderr, "primary_rays: no scene given\n");
        return 2;
    }
    const engine *e = dbl ? &engine_double : &engine_float;
    csg_scene s;
    csg_diag d;
    csg_blob blob = {NULL, 0};
    memset(&d, 0, sizeof d);
    csg_scene_init(&s);
    csg_flatten_opts o = {width, height, 0, -1, 1, 0};
    bool ok = csg_parse_file(scene, &s, &d) && e->flatten(&s, &o, &blob, &d);
    csg_scene_free(&s);
    if (!ok) {
        fprintf(stderr, "%s\n", d.message[0] ? d.message : "primary_rays: cannot load the scene");
        return 2;
    }
    if (export_path && !export_spheres(blob.bytes, export_path)) {
        csg_blob_free(&blob);
        return 1;
    }
    size_t n = (size_t)TILE * TILE;
    void *t = malloc(n * e->real_size);
    uint32_t *surf = malloc(n * sizeof *surf);
    double *times = malloc((size_t)repeat * sizeof *times);
    if (!t || !surf || !times) {
        fprintf(stderr, "primary_rays: out of memory\n");
        return 1;
    }
    ray_counts rays = {0};
    uint64_t hits = trace_image(e, blob.bytes, width, height, t, surf, &rays); /* warm-up */
    for (int r = 0; r < repeat; r++) {
        double t0 = bench_now_s();
        uint64_t again = trace_image(e, blob.bytes, width, height, t, surf, &rays);
        times[r] = bench_now_s() - t0;
        if (again != hits) {
            fprintf(stderr, "primary_rays: the passes disagree (%llu vs %llu hits)\n",
                    (unsigned long long)again, (unsigned long long)hits);
            return 1;
        }
    }
    double median = bench_median(times, repeat);
    uint64_t pixels = (uint64_t)width * (uint64_t)height;
    const csg_blob_header *h = csg_blob_hdr(blob.bytes);
    printf("{\"width\": %d, \"height\": %d, \"roots\": %d, \"bvh_nodes\": %d, \"rays\": %llu, "
           "\"hits\": %llu, \"repeat\": %d, \"best_s\": %.6f, \"median_s\": %.6f, "
           "\"max_s\": %.6f, \"mrays_per_s\": %.4f}\n",
           width, height, h->root_count, h->bvh_count, (unsigned long long)pixels,
           (unsigned long long)hits, repeat, times[0], median, times[repeat - 1],
           (double)pixels / median / 1e6);
    free(t);
    free(surf);
    free(times);
    csg_blob_free(&blob);
    return 0;
}
