/*
 * engine.h — the renderer's inner loop behind one small table per
 * precision, so that main, the MPI master and the workers stay
 * precision-agnostic and deal only in blobs, tiles and pixel buffers.
 *
 * Every pixel is rendered in two steps, whatever the mode:
 *   1. trace_primary: the primary ray's hit record (t, surface id);
 *   2. shade: Whitted shading from that record (shadow, reflected and
 *      refracted rays, recursively up to max_depth).
 * serial/homo do both on the CPU; hetero does step 1 in one OpenCL pass
 * over the whole image (simd_kernels/primary.cl, the same shared code of
 * csg/) and ships the records to the workers, who do step 2.  Because
 * step 2 only sees the record, the images agree bit for bit exactly when
 * the records do.
 *
 * Hit records are two arrays per tile, row-major: t[] of the blob's `real`
 * (4 or 8 bytes) and surf[] of uint32 (0: the primary ray hit nothing),
 * one record per primary sample (spp of them side by side for a pixel).
 * That is 8 bytes a sample in float, 12 in double, and it is the minimum a
 * worker needs to go on without intersecting the primary ray again:
 *   - surf packs the primitive index, which of its surfaces (box face, cone
 *     side or cap) and whether the solid's normal is the primitive's
 *     reversed (a subtracted surface): the material, the normal and the
 *     inside/outside side all follow from it (flat.h, CSG_SURF_PACK);
 *   - t gives the hit point o + t d, where the worker rebuilds o and d of
 *     the primary ray from the pixel and sample indices with the same
 *     camera code, so the point has exactly the bits the kernel's had.
 * The point itself (3 reals) or the normal would cost more bytes and are
 * recomputed bit-identically from these two fields.
 */
#ifndef WORKERS_ENGINE_H
#define WORKERS_ENGINE_H

#include <stddef.h>
#include <stdint.h>

#include "../comm/tiles.h"
#include "../csg/flatten.h"

typedef struct {
    uint64_t primary, shadow, reflected, refracted;
    uint64_t over_budget; /* pixels that met their ray budget (shade.c) */
    uint64_t shadow_answered; /* shadow rays not traced: their answer came in
                                 the records (shade_answered)              */
} ray_counts;

/* Rays of every kind. */
static inline uint64_t ray_counts_total(const ray_counts *r)
{
    return r->primary + r->shadow + r->reflected + r->refracted;
}

/* The longest list engine->rect_candidates gives. */
#define ENGINE_CANDIDATES_MAX 256

typedef struct {
    const char *name;  /* "float" or "double" */
    size_t real_size;  /* sizeof(real) of this build */
    bool (*flatten)(const csg_scene *s, const csg_flatten_opts *o, csg_blob *out, csg_diag *d);
    /* Hit records of the primary rays of `rect` (t_out: real[w*h]). */
    void (*trace_primary)(const void *blob, tile_rect rect, void *t_out, uint32_t *surf_out,
                          ray_counts *rays);
    /* RGB (3 floats a pixel, linear, not clamped) of `rect` from its
     * records; adds the secondary rays it traced to *rays. */
    void (*shade)(const void *blob, tile_rect rect, const void *t, const uint32_t *surf,
                  float *rgb_out, ray_counts *rays);
    /* shade, with the device's shadow answers of every record (known[],
     * lit[]: csg/device/shadow.h, csg_shadow_masks; NULL: none): a known
     * answer replaces the primary hit's shadow ray, which it equals, so
     * the pixels are shade's bit for bit (counted in shadow_answered). */
    void (*shade_answered)(const void *blob, tile_rect rect, const void *t, const uint32_t *surf,
                           const uint32_t *known, const uint32_t *lit, float *rgb_out,
                           ray_counts *rays);
    /* The pixel shade gives when no primary sample hit (the background):
     * what the hetero master fills degenerate tiles with. */
    void (*miss_rgb)(const void *blob, float rgb[3]);
    /* Every primary ray of `rect` provably misses every object (the
     * frustum culling of trace_primary found no root it may meet; false
     * when that culling does not apply): with no sky_sphere, the
     * rectangle is miss_rgb throughout, traced or not.  *met: -1, or what
     * the previous call left there, an object tried first (a neighbouring
     * rectangle's; the answer is the same, found sooner); on return the
     * object this rectangle may meet (-1: none). */
    bool (*rect_misses)(const void *blob, tile_rect rect, int32_t *met);
    /* The bounded roots the primary rays of `rect` may hit (the frustum
     * culling of trace_primary, workers/frustum.h) into roots[0 .. cap - 1]
     * (cap <= ENGINE_CANDIDATES_MAX): found by a walk of the BVH, nearest
     * box first (from NULL), or among from[0 .. from_n - 1] in its order,
     * a list that holds them all (an enclosing rectangle's).  Returns their
     * number, or -1 when no list applies (another camera, more than cap).
     * The unbounded roots (the blob's first root_count) are never listed:
     * every ray tries them.  The OpenCL packet pass's cells. */
    int32_t (*rect_candidates)(const void *blob, tile_rect rect, const int32_t *from,
                               int32_t from_n, int32_t *roots, int32_t cap);
    /* For the cost estimate of a tile (host/pass/estimate.h): the ENGINE_CLASS_*
     * bits of every primitive's material into class_out[prim_count]; returns
     * the number of lights that cast shadows (a shadow ray each a hit). */
    int (*surface_classes)(const void *blob, uint8_t *class_out);
} engine;

enum { ENGINE_CLASS_REFLECTIVE = 1, ENGINE_CLASS_TRANSPARENT = 2 };

extern const engine engine_float;
extern const engine engine_double;

/* The engine whose real_size matches the blob's. */
const engine *engine_for_blob(const void *blob);

#endif
