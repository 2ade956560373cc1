/*
 * test_tile_shortcuts.c — what the C engine remembers across the rays of a
 * tile changes no bit of the result:
 *   - the primary culling (workers/frustum.h): the hit records of
 *     engine->trace_primary equal csg_trace_nearest's, ray by ray, and a
 *     rectangle engine->rect_misses calls empty has no ray that hits; the
 *     candidate lists of engine->rect_candidates (the OpenCL packet
 *     pass's cells), found by a walk or among an enclosing rectangle's,
 *     keep every root a ray hits;
 *   - the shadow cache (workers/shade.c): a tile shaded as one rectangle,
 *     the cache carried from pixel to pixel, equals the same pixels shaded
 *     one by one, each with a fresh cache.
 * Compiled twice (test_tile_shortcuts_double.c: real = double, the double
 * engine).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>

#include "../csg/device/camera.h"
#include "../csg/flatten.h"
#include "../csg/lang/parser.h"
#include "../workers/engine.h"
#include "../workers/frustum.h"

#ifdef CSG_DOUBLE
#define ENGINE (&engine_double)
#else
#define ENGINE (&engine_float)
#endif

static double unit_rand(uint64_t *seed)
{
    *seed = *seed * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*seed >> 11) * 0x1.0p-53;
}

/* A scene of `count` random spheres in [-4, 4] x [-3, 3] x [-7, 5] (some
 * behind the camera, some around it), a third of them tiny, under the
 * given camera statement and extra objects. */
static char *random_scene(int count, uint64_t seed, const char *camera, const char *extra)
{
    size_t cap = 4096 + (size_t)count * 128, len = 0;
    char *text = malloc(cap);
    assert_non_null(text);
    len += (size_t)snprintf(text + len, cap - len, "%s\nlight_source { <-5, 8, -9> rgb 1 }\n%s\n",
                            camera, extra);
    for (int i = 0; i < count; i++) {
        double x = 8 * unit_rand(&seed) - 4, y = 6 * unit_rand(&seed) - 3;
        double z = 12 * unit_rand(&seed) - 7;
        double r = i % 3 == 0 ? 0.004 : 0.02 + 0.2 * unit_rand(&seed);
        len += (size_t)snprintf(text + len, cap - len,
                                "sphere { <%.6f, %.6f, %.6f>, %.6f pigment { rgb 1 } }\n", x, y,
                                z, r);
        assert_true(len < cap);
    }
    return text;
}

static void flatten_text(const char *text, int w, int h, int spp, csg_blob *b)
{
    csg_scene s;
    csg_diag d = {0};
    if (!csg_parse_string("primary.pov", text, strlen(text), &s, &d))
        fail_msg("parse: %s", d.message);
    csg_flatten_opts o = {w, h, 0, -1, spp, 0};
    if (!ENGINE->flatten(&s, &o, b, &d))
        fail_msg("flatten: %s", d.message);
    csg_scene_free(&s);
}

/* The object engine->rect_misses said a rectangle met: none when it
 * misses or an unbounded object may meet every ray, else one of the
 * candidates its culling gathers (fr), when it gathered them all. */
static void assert_rect_met(csg_view v, const frustum_roots *fr, bool misses, int32_t met)
{
    if (misses || v.root_count > 0) {
        assert_int_equal(met, -1);
        return;
    }
    if (!fr->culled)
        return;
    bool found = false;
    for (int k = 0; k < fr->n; k++)
        found = found || fr->roots[k] == met;
    assert_true(found);
}

/* The OpenCL packet pass's cells (host/pass/ocl.c): engine->rect_candidates
 * of r by a walk is frustum_roots_of's list when that one has it; each
 * quadrant's list taken among r's keeps every root a ray of the quadrant
 * hits (the unbounded roots and those candidates, each behind its box, give
 * csg_trace_nearest's record).  Returns how many quadrants' lists are
 * shorter than r's (0: the filter culled nothing here). */
static int assert_candidates_in(const void *blob, int w, int h, int spp, tile_rect r)
{
    const unsigned char *bytes = blob;
    csg_view v = csg_blob_view(bytes);
    const csg_camera *cam = csg_blob_camera(bytes);
    int32_t all[ENGINE_CANDIDATES_MAX], sub[ENGINE_CANDIDATES_MAX];
    int32_t n = ENGINE->rect_candidates(blob, r, NULL, 0, all, ENGINE_CANDIDATES_MAX);
    frustum_roots fr;
    frustum_roots_of(v, cam, w, h, r, &fr);
    if (fr.culled) {
        assert_int_equal(n, fr.n);
        assert_memory_equal(all, fr.roots, (size_t)n * sizeof *all);
    }
    if (n < 0)
        return 0;
    int shorter = 0, hw = (r.width + 1) / 2, hh = (r.height + 1) / 2;
    tile_rect quads[4] = {{r.x, r.y, hw, hh},
                          {r.x + hw, r.y, r.width - hw, hh},
                          {r.x, r.y + hh, hw, r.height - hh},
                          {r.x + hw, r.y + hh, r.width - hw, r.height - hh}};
    for (int q = 0; q < 4; q++) {
        tile_rect c = quads[q];
        if (c.width <= 0 || c.height <= 0)
            continue;
        int32_t m = ENGINE->rect_candidates(blob, c, all, n, sub, ENGINE_CANDIDATES_MAX);
        assert_true(m >= 0 && m <= n);
        shorter += m < n;
        for (int y = c.y; y < c.y + c.height; y++)
            for (int x = c.x; x < c.x + c.width; x++)
                for (int k = 0; k < spp; k++) {
                    csg_ray ray = csg_sample_ray(cam, w, h, x, y, spp, k);
                    csg_box_ray br = csg_box_ray_of(ray);
                    csg_hit best;
                    best.t = CSG_R_INF;
                    best.surf = CSG_SURF_NONE;
                    for (csg_i32 i = 0; i < v.root_count; i++)
                        csg_try_root(v, i, ray, &br, 1, R(0.0), &best);
                    for (int32_t j = 0; j < m; j++)
                        csg_try_root(v, sub[j], ray, &br, 1, R(0.0), &best);
                    if (best.surf == CSG_SURF_NONE)
                        best.t = CSG_R_INF;
                    csg_hit hit = csg_trace_nearest(v, ray, R(0.0), CSG_R_INF);
                    assert_int_equal(best.surf, hit.surf);
                    assert_memory_equal(&best.t, &hit.t, sizeof hit.t);
                }
    }
    return shorter;
}

/* Every rectangle of a tiling of `tile` pixels: the engine's records equal
 * csg_trace_nearest of each sample's ray.  Returns how many rectangles
 * rect_misses answered from the previous one's object alone (it kept that
 * object where a walk of its own finds another). */
static int assert_primary_records(const void *blob, int w, int h, int spp, int tile)
{
    int kept = 0;
    const unsigned char *bytes = blob;
    csg_view v = csg_blob_view(bytes);
    const csg_camera *cam = csg_blob_camera(bytes);
    int32_t met_before = -1; /* (carried from tile to tile, as the master does) */
    real *t = malloc((size_t)tile * tile * spp * sizeof *t);
    uint32_t *surf = malloc((size_t)tile * tile * spp * sizeof *surf);
    assert_true(t && surf);
    for (int ty = 0; ty < h; ty += tile) {
        for (int tx = 0; tx < w; tx += tile) {
            tile_rect r = {tx, ty, tile < w - tx ? tile : w - tx, tile < h - ty ? tile : h - ty};
            ray_counts rays = {0};
            ENGINE->trace_primary(blob, r, t, surf, &rays);
            assert_int_equal(rays.primary, (uint64_t)r.width * r.height * spp);
            /* the hetero master's proof of a degenerate tile (rect_misses)
             * is the trace's own shortcut, and every ray below misses; the
             * same with the previous tile's object tried first, or with
             * one that does not exist */
            frustum_roots fr;
            frustum_roots_of(v, cam, w, h, r, &fr);
            int32_t carried = met_before;
            bool misses = ENGINE->rect_misses(blob, r, &met_before);
            assert_int_equal(misses, frustum_all_miss(v, &fr));
            assert_rect_met(v, &fr, misses, met_before);
            int32_t fresh = -1, bogus = INT32_MAX;
            assert_int_equal(ENGINE->rect_misses(blob, r, &fresh), misses);
            assert_rect_met(v, &fr, misses, fresh);
            kept += carried >= 0 && met_before == carried && fresh != carried;
            assert_int_equal(ENGINE->rect_misses(blob, r, &bogus), misses);
            for (int y = 0; y < r.height; y++)
                for (int x = 0; x < r.width; x++)
                    for (int k = 0; k < spp; k++) {
                        size_t i = ((size_t)y * r.width + x) * spp + k;
                        csg_ray ray = csg_sample_ray(cam, w, h, tx + x, ty + y, spp, k);
                        csg_hit hit = csg_trace_nearest(v, ray, R(0.0), CSG_R_INF);
                        assert_int_equal(surf[i], hit.surf);
                        if (misses)
                            assert_int_equal(hit.surf, CSG_SURF_NONE);
                        assert_memory_equal(&t[i], &hit.t, sizeof hit.t);
                    }
        }
    }
    free(t);
    free(surf);
    return kept;
}

/* How many of the w x h image's tiles of `tile` pixels get a candidate
 * list, and how many of those an empty one (no ray traced at all). */
static void count_culled(const void *blob, int w, int h, int tile, int *culled, int *empty)
{
    const unsigned char *bytes = blob;
    *culled = *empty = 0;
    for (int ty = 0; ty < h; ty += tile)
        for (int tx = 0; tx < w; tx += tile) {
            tile_rect r = {tx, ty, tile < w - tx ? tile : w - tx, tile < h - ty ? tile : h - ty};
            frustum_roots fr;
            frustum_roots_of(csg_blob_view(bytes), csg_blob_camera(bytes), w, h, r, &fr);
            *culled += fr.culled;
            *empty += fr.culled && fr.n == 0;
        }
}

/* expect_culled: the camera is one the culling handles, and some 5-pixel
 * tiles must get a list, some an empty one (else nothing was tested).
 * hither > 0: the camera's near plane (NFF's hither; the POV language has
 * none), set in the flattened blob. */
static void check_scene_near(const char *camera, const char *extra, int w, int h,
                             bool expect_culled, double hither)
{
    char *text = random_scene(400, 777, camera, extra);
    for (int spp = 1; spp <= 4; spp += 3) {
        csg_blob b;
        flatten_text(text, w, h, spp, &b);
        if (hither > 0.0)
            ((csg_camera *)(void *)csg_blob_camera(b.bytes))->hither = (real)hither;
        int culled, empty;
        count_culled(b.bytes, w, h, 5, &culled, &empty);
        if (expect_culled) {
            assert_true(culled > 0);
            assert_true(empty > 0);
        } else {
            assert_int_equal(culled, 0);
        }
        int shorter = 0; /* the packet pass's cells: 16-pixel ones in 64-pixel blocks */
        for (int ty = 0; ty < h; ty += 64)
            for (int tx = 0; tx < w; tx += 64) {
                tile_rect r = {tx, ty, 64 < w - tx ? 64 : w - tx, 64 < h - ty ? 64 : h - ty};
                shorter += assert_candidates_in(b.bytes, w, h, spp, r);
            }
        if (expect_culled)
            assert_true(shorter > 0);
        int tiles[] = {1, 5, 16, 64}, kept = 0;
        for (size_t i = 0; i < sizeof tiles / sizeof tiles[0]; i++)
            kept += assert_primary_records(b.bytes, w, h, spp, tiles[i]);
        if (expect_culled && csg_blob_view(b.bytes).root_count == 0)
            assert_true(kept > 0); /* (the previous object's shortcut was taken) */
        csg_blob_free(&b);
    }
    free(text);
}

static void check_scene(const char *camera, const char *extra, int w, int h, bool expect_culled)
{
    check_scene_near(camera, extra, w, h, expect_culled, 0.0);
}

/* A slanted perspective camera: the culling's own case. */
static void test_perspective(void **state)
{
    (void)state;
    check_scene("camera { location <0.3, 0.7, -5> look_at <0.6, 0.2, 0> sky <0.1, 1, 0> }", "",
                67, 41, true);
}

/* Wide angle, the camera inside the cloud; and an unbounded root (tried by
 * every ray beside the candidates). */
static void test_wide_and_plane(void **state)
{
    (void)state;
    check_scene("camera { location <0, 0, 0> look_at <0, 0, 1> angle 150 }",
                "plane { y, -2.5 pigment { rgb 1 } }", 53, 47, true);
}

/* A near plane (NFF's hither) starts each ray further along its own line,
 * inside the same pyramid: culled as without one.  The camera sits inside
 * the cloud, so the planes at 0.5 and 3 leave spheres (and parts of
 * spheres) behind them: those rays start past them and must not hit. */
static void test_near_plane(void **state)
{
    (void)state;
    const char *camera = "camera { location <0.2, -0.3, -1> look_at <0.5, 0.1, 3> }";
    check_scene_near(camera, "", 61, 43, true, 0.5);
    check_scene_near(camera, "plane { y, -2.5 pigment { rgb 1 } }", 37, 29, true, 3.0);
}

/* Tiles whose pyramid meets a triangle root's box but not the triangle
 * (frustum_culls_triangle), over a tiling of `tile` pixels. */
static int count_triangle_culls(const void *blob, int w, int h, int tile)
{
    const unsigned char *bytes = blob;
    csg_view v = csg_blob_view(bytes);
    const csg_blob_header *hdr = (const csg_blob_header *)blob;
    int n = 0;
    for (int ty = 0; ty < h; ty += tile)
        for (int tx = 0; tx < w; tx += tile) {
            tile_rect r = {tx, ty, tile < w - tx ? tile : w - tx, tile < h - ty ? tile : h - ty};
            frustum f;
            assert_true(frustum_of(csg_blob_camera(bytes), w, h, r, &f));
            for (csg_i32 i = 0; i < hdr->root_count; i++) {
                const csg_root *rt = &v.roots[i];
                n += !frustum_culls(&f, rt->lo, rt->hi) && frustum_culls_triangle(&f, v, rt);
            }
        }
    return n;
}

/* Large slanted triangles (each its own root), with and without a near
 * plane: some tiles lose a candidate to the triangle's own corners, and
 * every record still equals the BVH walk's. */
static void test_triangles(void **state)
{
    (void)state;
    uint64_t seed = 4242;
    size_t cap = 16384, len = 0;
    char *text = malloc(cap);
    assert_non_null(text);
    len += (size_t)snprintf(text + len, cap - len,
                            "camera { location <0.2, -0.3, -6> look_at <0.5, 0.1, 0> }\n"
                            "light_source { <-5, 8, -9> rgb 1 }\n");
    for (int i = 0; i < 12; i++) {
        double c[3]; /* (one draw a statement: the order is the program's) */
        c[0] = 6 * unit_rand(&seed) - 3;
        c[1] = 4 * unit_rand(&seed) - 2;
        c[2] = 6 * unit_rand(&seed) - 2;
        len += (size_t)snprintf(text + len, cap - len, "triangle {");
        for (int k = 0; k < 3; k++) {
            double x = c[0] + 3 * unit_rand(&seed) - 1.5;
            double y = c[1] + 3 * unit_rand(&seed) - 1.5;
            double z = c[2] + 3 * unit_rand(&seed) - 1.5;
            len += (size_t)snprintf(text + len, cap - len, " <%.5f, %.5f, %.5f>%s", x, y, z,
                                    k < 2 ? "," : "");
        }
        len += (size_t)snprintf(text + len, cap - len, " pigment { rgb 1 } }\n");
        assert_true(len < cap);
    }
    for (int near = 0; near < 2; near++) {
        csg_blob b;
        flatten_text(text, 47, 35, 1, &b);
        if (near)
            ((csg_camera *)(void *)csg_blob_camera(b.bytes))->hither = (real)1.5;
        assert_true(count_triangle_culls(b.bytes, 47, 35, 5) > 0);
        int tiles[] = {1, 5, 16, 64};
        for (size_t i = 0; i < sizeof tiles / sizeof tiles[0]; i++)
            (void)assert_primary_records(b.bytes, 47, 35, 1, tiles[i]);
        csg_blob_free(&b);
    }
    free(text);
}

/* The camera the culling leaves alone: orthographic. */
static void test_orthographic(void **state)
{
    (void)state;
    check_scene("camera { orthographic location <0, 0, -9> look_at <0, 0, 0> }", "", 40, 30, false);
}

/* The pixels of the whole image shaded as one rectangle, or pixel by
 * pixel (each with a fresh shadow cache). */
static float *shade_image(const void *blob, int w, int h, bool by_pixel)
{
    real *t = malloc((size_t)w * h * sizeof *t);
    uint32_t *surf = malloc((size_t)w * h * sizeof *surf);
    float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
    assert_true(t && surf && rgb);
    tile_rect all = {0, 0, w, h};
    ray_counts rays = {0};
    ENGINE->trace_primary(blob, all, t, surf, &rays);
    if (!by_pixel) {
        ENGINE->shade(blob, all, t, surf, rgb, &rays);
    } else {
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                tile_rect one = {x, y, 1, 1};
                size_t i = (size_t)y * w + x;
                ENGINE->shade(blob, one, t + i, surf + i, rgb + 3 * i, &rays);
            }
    }
    free(t);
    free(surf);
    return rgb;
}

/* A floor under a row of occluders between it and two lights: opaque
 * spheres (the cache's case), a glass sphere (light through, tinted),
 * a sphere opaque in one checker cell and transparent in the other, and
 * gaps, so that along a row of pixels the cached blocker keeps changing
 * and often no longer blocks; mirrors send reflected rays (another trace
 * level) into the same shadows. */
static void test_shadow_cache(void **state)
{
    (void)state;
    const char *text =
        "camera { location <0, 6, -9> look_at <0, 0, 0> }\n"
        "light_source { <-3, 12, -2> rgb 1 }\n"
        "light_source { <5, 9, 3> rgb <0.5, 0.4, 0.3> }\n"
        "plane { y, 0 pigment { rgb 1 } finish { reflection 0.2 } }\n"
        "sphere { <-3, 1, 0>, 0.8 pigment { rgb <1, 0, 0> } }\n"
        "sphere { <-1, 1.2, 0.5>, 0.7 pigment { rgbf <0.6, 0.9, 0.6, 0.8> } }\n"
        "sphere { <1, 1, 0>, 0.8 pigment { checker rgbt <0, 0, 1, 0> rgbt <1, 1, 1, 0.9> "
        "scale 0.3 } }\n"
        "sphere { <3, 1.5, 0.2>, 0.6 pigment { rgb 0.5 } finish { reflection 0.6 } }\n"
        "sphere { <0, 3, 2>, 0.5 pigment { rgb <1, 1, 0> } }\n"
        "box { <-4, 2.5, 3>, <4, 2.7, 3.3> pigment { rgbt <1, 1, 1, 0.5> } }\n";
    csg_blob b;
    flatten_text(text, 96, 64, 1, &b);
    float *whole = shade_image(b.bytes, 96, 64, false);
    float *single = shade_image(b.bytes, 96, 64, true);
    assert_memory_equal(whole, single, (size_t)96 * 64 * 3 * sizeof *whole);
    int shadowed = 0; /* the floor has shadows: some pixels darker than others */
    for (int i = 0; i < 96 * 64; i++)
        shadowed += whole[3 * i] < 0.05f;
    assert_true(shadowed > 0);
    free(whole);
    free(single);
    csg_blob_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_perspective),
        cmocka_unit_test(test_wide_and_plane),
        cmocka_unit_test(test_near_plane),
        cmocka_unit_test(test_triangles),
        cmocka_unit_test(test_orthographic),
        cmocka_unit_test(test_shadow_cache),
    };
    return cmocka_run_group_tests_name(ENGINE == &engine_double ? "tile_shortcuts_double" : "tile_shortcuts",
                                       tests, NULL, NULL);
}
