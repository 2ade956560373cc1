/*
 * test_stability.c — numerical stability at the extremes, in process:
 * scenes written as text, parsed (csg_parse_string), flattened and
 * rendered by the CPU engine in float and in double, pixel buffers
 * compared.
 *
 * What is asserted (the bounds are the ones bench/ACCURACY.md states):
 *   - scale invariance: the same scene scaled by 1e-4 and 1e6 (objects,
 *     lights and camera together) renders like the unit scene: double
 *     within 1e-3 on every pixel and <= 0.1% pixels with another primary
 *     surface; float within 1/255 on all but 0.2% of the pixels, max 0.05;
 *   - extreme cameras (1e-3 from a surface, 1e5 away), grazing and
 *     tangent rays on every primitive, tiny and huge radii in one scene,
 *     coincident CSG surfaces, shadow acne at every scale: counted as
 *     isolated outlier pixels against the expected value;
 *   - the robust formulations against naive ones written here: the
 *     textbook quadratic loses a tiny far sphere that csg_sphere_span
 *     finds; a fixed-epsilon ray offset self-shadows where the ulp-scaled
 *     offset of csg/device/offset.h does not;
 *     (STABILITY_DUMP=dir writes the renders as PPM for a look)
 *   - NaN and infinity never reach a pixel (degenerate directions, rays
 *     parallel to faces, zero-thickness CSG, coordinates of 1e30, a camera
 *     on a surface, a light inside an object);
 *   - the --precision auto criterion (csg/precision.h) picks float exactly
 *     where float renders like double.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>

#include "../csg/flatten.h"
#include "../csg/device/intersect.h" /* real = float in this file */
#include "../csg/lang/parser.h"
#include "../csg/precision.h"
#include "../workers/engine.h"
#include "../csg/device/offset.h"

/* ---- rendering a scene string ------------------------------------------------ */

typedef struct {
    int w, h;
    float *rgb;     /* 3 floats a pixel, linear */
    uint32_t *surf; /* primary surface id, 0: background */
} image;

static void image_free(image *im)
{
    free(im->rgb);
    free(im->surf);
    im->rgb = NULL;
    im->surf = NULL;
}

/* The scenes are POV-Ray 3.7 scenes (linear output): the version is said
 * on their first line, which keeps every position. */
static void parse_ok(const char *text, csg_scene *s)
{
    csg_diag d = {0};
    static const char v37[] = "#version 3.7; ";
    size_t n = strlen(text);
    char *full = malloc(sizeof v37 + n);
    assert_non_null(full);
    memcpy(full, v37, sizeof v37 - 1);
    memcpy(full + sizeof v37 - 1, text, n + 1);
    if (!csg_parse_string("stability.pov", full, strlen(full), s, &d))
        fail_msg("parse failed: %s\n%s", d.message, text);
    free(full);
}

/* The whole image as one tile. */
static image render_text(const engine *e, const char *text, int w, int h)
{
    csg_scene s;
    parse_ok(text, &s);
    csg_flatten_opts o = {w, h, 0, -1, 1, 0};
    csg_diag d = {0};
    csg_blob b;
    if (!e->flatten(&s, &o, &b, &d))
        fail_msg("flatten failed: %s", d.message);
    image im = {w, h, calloc((size_t)w * h * 3, sizeof(float)), calloc((size_t)w * h, 4)};
    void *t = calloc((size_t)w * h, 8);
    assert_true(im.rgb && im.surf && t);
    ray_counts rays = {0};
    tile_rect r = {0, 0, w, h};
    e->trace_primary(b.bytes, r, t, im.surf, &rays);
    e->shade(b.bytes, r, t, im.surf, im.rgb, &rays);
    free(t);
    csg_blob_free(&b);
    csg_scene_free(&s);
    return im;
}

/* How two renders of one scene differ. */
typedef struct {
    int surf_mismatch; /* pixels whose primary surface differs */
    int off_1e3;       /* same surface, a channel off by > 1e-3 */
    int off_8bit;      /* same surface, a channel off by > 1/255 */
    double max_abs;    /* largest channel difference, same-surface pixels */
    int n;
} img_diff;

static img_diff compare(const image *a, const image *b)
{
    img_diff r = {0, 0, 0, 0.0, a->w * a->h};
    for (int i = 0; i < r.n; i++) {
        if (a->surf[i] != b->surf[i]) {
            r.surf_mismatch++;
            continue;
        }
        double m = 0.0;
        for (int c = 0; c < 3; c++)
            m = fmax(m, fabs((double)a->rgb[3 * i + c] - (double)b->rgb[3 * i + c]));
        r.max_abs = fmax(r.max_abs, m);
        r.off_1e3 += m > 1e-3;
        r.off_8bit += m > 1.0 / 255.0;
    }
    return r;
}

static void print_diff(const char *what, img_diff d)
{
    printf("  %-34s surf mismatch %5.2f%%  >1e-3 %5.2f%%  >1/255 %5.2f%%  max %.3g\n", what,
           100.0 * d.surf_mismatch / d.n, 100.0 * d.off_1e3 / d.n, 100.0 * d.off_8bit / d.n,
           d.max_abs);
}

/* STABILITY_DUMP=dir: the images of a comparison as PPM, for a look. */
static void dump_ppm(const image *im, const char *name)
{
    const char *dir = getenv("STABILITY_DUMP");
    if (!dir)
        return;
    char path[512];
    snprintf(path, sizeof path, "%s/%s.ppm", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f)
        return;
    fprintf(f, "P6 %d %d 255\n", im->w, im->h);
    for (int i = 0; i < 3 * im->w * im->h; i++) {
        double v = isfinite(im->rgb[i]) ? fmin(fmax((double)im->rgb[i], 0.0), 1.0) : 1.0;
        fputc((int)(255.0 * sqrt(v) + 0.5), f);
    }
    fclose(f);
}

static bool all_finite(const image *im)
{
    for (int i = 0; i < 3 * im->w * im->h; i++)
        if (!isfinite(im->rgb[i]))
            return false;
    return true;
}

static double luminance(const image *im, int i)
{
    return ((double)im->rgb[3 * i] + (double)im->rgb[3 * i + 1] + (double)im->rgb[3 * i + 2]) / 3.0;
}

/* Pixels darker than `frac` of all but the darkest of their 8 neighbours,
 * among pixels whose neighbours all share their primary surface: the
 * isolated dark speckles of acne and of coincident-surface fights (a
 * shadow's jagged edge has several dark neighbours and does not count). */
static int dark_speckles(const image *im, double frac)
{
    int count = 0;
    for (int y = 1; y < im->h - 1; y++) {
        for (int x = 1; x < im->w - 1; x++) {
            int i = y * im->w + x;
            if (im->surf[i] == 0)
                continue;
            double nb[8];
            int k = 0;
            bool same = true;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    if (!dx && !dy)
                        continue;
                    int j = (y + dy) * im->w + x + dx;
                    same = same && im->surf[j] == im->surf[i];
                    nb[k++] = luminance(im, j);
                }
            if (!same)
                continue;
            /* the median of 8: sort (tiny) */
            for (int p = 1; p < 8; p++)
                for (int q = p; q > 0 && nb[q] < nb[q - 1]; q--) {
                    double tmp = nb[q];
                    nb[q] = nb[q - 1];
                    nb[q - 1] = tmp;
                }
            count += luminance(im, i) < frac * nb[1];
        }
    }
    return count;
}

/* Pixels whose primary surface differs from all 8 neighbours' (which
 * agree with each other): single-pixel specks of the wrong surface. */
static int surface_specks(const image *im)
{
    int count = 0;
    for (int y = 1; y < im->h - 1; y++) {
        for (int x = 1; x < im->w - 1; x++) {
            int i = y * im->w + x;
            uint32_t n0 = im->surf[i - 1];
            bool odd = n0 != im->surf[i];
            for (int dy = -1; dy <= 1 && odd; dy++)
                for (int dx = -1; dx <= 1; dx++)
                    if ((dx || dy) && im->surf[(y + dy) * im->w + x + dx] != n0)
                        odd = false;
            count += odd;
        }
    }
    return count;
}

/* ---- the test scene, at any scale and offset --------------------------------- */

/* A lit scene with every primitive, CSG, a mirror and glass; every
 * position is p * scale + shift (objects, light and camera). */
static char *scene_scaled(double scale, double shift)
{
    static const char body[] =
        "  plane { y, 0 pigment { color rgb <0.6, 0.55, 0.5> } finish { reflection 0.1 } }\n"
        "  sphere { <-1.6, 0.8, 0.5>, 0.8 pigment { color rgb <0.9, 0.2, 0.2> }\n"
        "           finish { phong 0.6 } }\n"
        "  box { <-0.3, 0, -0.3>, <0.5, 0.8, 0.5> rotate 25*y pigment { color rgb <0.2, 0.8, 0.3> } }\n"
        "  cylinder { <1.3, 0, 0>, <1.3, 1.2, 0>, 0.35 pigment { color rgb <0.3, 0.3, 0.9> } }\n"
        "  cone { <2.3, 0, 0.8>, 0.5, <2.3, 1.1, 0.8>, 0 pigment { color rgb <0.9, 0.8, 0.2> } }\n"
        "  difference { box { <-0.8, 0, -1.6>, <0.2, 0.6, -1.0> }\n"
        "               sphere { <-0.3, 0.6, -1.3>, 0.35 } pigment { color rgb <0.8, 0.5, 0.9> } }\n"
        "  sphere { <0.9, 0.45, -1.4>, 0.45 pigment { color rgbf <1, 1, 1, 0.9> }\n"
        "           finish { reflection 0.05 } interior { ior 1.5 } }\n"
        "  box { <-3, 0, 2>, <3, 2, 2.05> finish { reflection 0.6 } pigment { color rgb 0.2 } }\n";
    char *text = malloc(4096);
    assert_non_null(text);
    double cam[3] = {0.4, 2.2, -6.0}, at[3] = {0.2, 0.6, 0.0}, lt[3] = {-5.0, 8.0, -6.0};
#define P3(v) (v)[0] * scale + shift, (v)[1] * scale + shift, (v)[2] * scale + shift
    int n = snprintf(text, 4096,
                     "global_settings { max_trace_level 5 }\n"
                     "camera { location <%.17g, %.17g, %.17g> look_at <%.17g, %.17g, %.17g> "
                     "angle 50 }\n"
                     "light_source { <%.17g, %.17g, %.17g> color rgb 1 }\n"
                     "background { color rgb <0.5, 0.7, 0.9> }\n"
                     "union {\n%s  scale %.17g translate %.17g\n}\n",
                     P3(cam), P3(at), P3(lt), body, scale, shift);
#undef P3
    assert_true(n > 0 && n < 4096);
    return text;
}

#define W 96
#define H 72

static const engine *const engines[2] = {&engine_double, &engine_float};

/* Every pixel finite, no isolated wrong-surface speck, no isolated dark
 * speckle; prints the counts under `what`. */
static void assert_clean(const image *im, const char *what, int max_specks, int max_dark)
{
    int specks = surface_specks(im), dark = dark_speckles(im, 0.5);
    printf("  %-34s specks %d  dark speckles %d\n", what, specks, dark);
    assert_true(all_finite(im));
    assert_true(specks <= max_specks);
    assert_true(dark <= max_dark);
}

static int count_surf(const image *im, bool (*pred)(uint32_t))
{
    int n = 0;
    for (int i = 0; i < im->w * im->h; i++)
        n += pred(im->surf[i]);
    return n;
}

static bool is_hit(uint32_t s) { return s != 0; }

/* A matte scene (no mirror, no glass: every dark pixel is a shadow) of
 * every primitive on a floor, scaled by S about the origin then moved by
 * `shift` along every axis, camera and light with it; the camera sits at
 * `cam` (scene units before scaling) with the given field of view. */
static void lit_scene(char *text, size_t size, double S, double shift, const double cam[3],
                      double angle)
{
    int n = snprintf(
        text, size,
        "camera { location <%.17g, %.17g, %.17g> look_at <%.17g, %.17g, %.17g> angle %.17g }\n"
        "light_source { <%.17g, %.17g, %.17g> color rgb 1 }\n"
        "union {\n"
        "  plane { y, 0 pigment { color rgb 0.8 } finish { ambient 0 } }\n"
        "  sphere { <0, 1, 0>, 1 pigment { color rgb <0.9, 0.4, 0.3> } finish { ambient 0 } }\n"
        "  box { <1.5, 0, -1>, <2.5, 1.2, 0> pigment { color rgb 0.6 } finish { ambient 0 } }\n"
        "  cylinder { <-2.5, 0, -0.5>, <-2.5, 1.5, -0.5>, 0.4 pigment { color rgb 0.6 }\n"
        "             finish { ambient 0 } }\n"
        "  cone { <-1.2, 0, -2>, 0.5, <-1.2, 1, -2>, 0.1 pigment { color rgb 0.6 }\n"
        "         finish { ambient 0 } }\n"
        "  scale %.17g translate %.17g }\n",
        cam[0] * S + shift, cam[1] * S + shift, cam[2] * S + shift, shift, 0.6 * S + shift, shift,
        angle, -4.0 * S + shift, 7.0 * S + shift, -3.0 * S + shift, S, shift);
    assert_true(n > 0 && (size_t)n < size);
}

/* Scale invariance: double within 1e-3 everywhere, <= 0.1% pixels on
 * another surface; float within 1/255 on all but 0.2% of the pixels. */
static void test_scale_invariance(void **state)
{
    (void)state;
    const double scales[2] = {1e-4, 1e6};
    char *unit_text = scene_scaled(1.0, 0.0);
    for (int k = 0; k < 2; k++) {
        image unit = render_text(engines[k], unit_text, W, H);
        dump_ppm(&unit, engines[k]->name);
        assert_clean(&unit, engines[k]->name, 0, 0);
        for (int j = 0; j < 2; j++) {
            char *text = scene_scaled(scales[j], 0.0);
            image im = render_text(engines[k], text, W, H);
            img_diff d = compare(&unit, &im);
            char what[64];
            snprintf(what, sizeof what, "%s scale %g", engines[k]->name, scales[j]);
            print_diff(what, d);
            dump_ppm(&im, what);
            assert_clean(&im, what, 0, 0);
            assert_true(d.surf_mismatch * 1000 <= d.n);
            if (k == 0) {
                assert_true(d.max_abs < 1e-3);
            } else {
                assert_true(d.off_8bit * 500 <= d.n);
                assert_true(d.max_abs < 0.05);
            }
            image_free(&im);
            free(text);
        }
        image_free(&unit);
    }
    free(unit_text);
}

/* A camera 1e-3 from a surface and one 1e5 away. */
static void test_extreme_cameras(void **state)
{
    (void)state;
    /* 1e-3 above a lit floor and in front of a sphere's surface */
    static const char near_text[] =
        "camera { location <0, 1.001, -0.4> look_at <0, 1.001, 1> angle 60 }\n"
        "light_source { <-3, 6, -4> color rgb 1 }\n"
        "plane { y, 1 pigment { color rgb <0.8, 0.7, 0.6> } }\n"
        "sphere { <0, 2, 0.601>, 1 pigment { color rgb <0.9, 0.3, 0.3> } }\n"
        "box { <-5, 1, 3>, <5, 4, 3.5> pigment { color rgb <0.3, 0.4, 0.9> } }\n";
    /* the matte scene seen from 1e5 away with a narrow lens */
    char far_text[2048];
    const double far_cam[3] = {0.0, 5e4, -8.66e4};
    lit_scene(far_text, sizeof far_text, 1.0, 0.0, far_cam, 0.0033);
    image ims[2][2];
    for (int k = 0; k < 2; k++) {
        char what[64];
        ims[k][0] = render_text(engines[k], near_text, W, H);
        snprintf(what, sizeof what, "%s camera 1e-3 away", engines[k]->name);
        dump_ppm(&ims[k][0], what);
        assert_clean(&ims[k][0], what, 0, 0);
        assert_int_equal(count_surf(&ims[k][0], is_hit), W * H);
        ims[k][1] = render_text(engines[k], far_text, W, H);
        snprintf(what, sizeof what, "%s camera 1e5 away", engines[k]->name);
        dump_ppm(&ims[k][1], what);
        assert_clean(&ims[k][1], what, 0, 0);
    }
    img_diff dn = compare(&ims[0][0], &ims[1][0]);
    img_diff df = compare(&ims[0][1], &ims[1][1]);
    print_diff("near: float vs double", dn);
    print_diff("far: float vs double", df);
    assert_true(dn.surf_mismatch * 1000 <= dn.n && dn.off_8bit * 1000 <= dn.n);
    /* far in float: hit points are off by ulps of 1e5 (~0.01): silhouettes
     * may move by a pixel, shading stays within bounds (no acne: above) */
    assert_true(df.surf_mismatch * 50 <= df.n);
    for (int k = 0; k < 2; k++) {
        image_free(&ims[k][0]);
        image_free(&ims[k][1]);
    }
}

/* Rays exactly tangent to every primitive: an odd image height puts the
 * middle row's rays exactly horizontal at the camera's height, y = 1,
 * the top of a unit sphere, of a box, of a cylinder (side, along the
 * row), the cap of a cylinder, a cone's apex, and a plane. */
static void test_tangent_rays(void **state)
{
    (void)state;
    static const char text[] =
        "camera { location <0, 1, -8> direction z up y right 1.3333*x }\n"
        "light_source { <2, 9, -6> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "sphere { <-3, 0, 0>, 1 pigment { color rgb <0.9, 0.3, 0.3> } }\n"
        "box { <-1.6, -1, -0.5>, <-0.6, 1, 0.5> pigment { color rgb <0.3, 0.9, 0.3> } }\n"
        "cylinder { <0, -1, 0>, <0, 1, 0>, 0.4 pigment { color rgb <0.3, 0.3, 0.9> } }\n"
        "cylinder { <0.8, 0, -1>, <0.8, 0, 1>, 1 pigment { color rgb <0.9, 0.9, 0.3> } }\n"
        "cone { <2.5, -1, 0>, 0.8, <2.5, 1, 0>, 0 pigment { color rgb <0.9, 0.5, 0.2> } }\n"
        "plane { y, -1 pigment { color rgb 0.6 } }\n"
        "difference { plane { y, 1 } sphere { <0, 1, 20>, 30 } pigment { color rgb 0.5 } }\n";
    const int h = 73; /* odd: row 36 is exactly horizontal */
    image ims[2];
    for (int k = 0; k < 2; k++) {
        char what[64];
        ims[k] = render_text(engines[k], text, W, h);
        snprintf(what, sizeof what, "%s tangent rays", engines[k]->name);
        dump_ppm(&ims[k], what);
        assert_clean(&ims[k], what, 0, 0);
    }
    img_diff d = compare(&ims[0], &ims[1]);
    print_diff("tangent: float vs double", d);
    /* only the tangent row itself may decide differently */
    assert_true(d.surf_mismatch <= W);
    assert_true(d.off_8bit <= W);
    image_free(&ims[0]);
    image_free(&ims[1]);
}

/* Grazing rays: a camera just above a box top, a plane and a cylinder
 * side, looking along them; the surfaces are lit, no acne. */
static void test_grazing_rays(void **state)
{
    (void)state;
    static const char text[] =
        "camera { location <0, 0.02, -10> look_at <0, 0, 0> angle 40 }\n"
        "light_source { <-3, 10, -2> color rgb 1 }\n"
        "plane { y, 0 pigment { color rgb <0.7, 0.7, 0.6> } }\n"
        "box { <-3, 0, -2>, <-0.5, 0.01, 4> pigment { color rgb <0.3, 0.8, 0.3> } }\n"
        "cylinder { <1, 0.4, -4>, <1, 0.4, 6>, 0.4 pigment { color rgb <0.3, 0.3, 0.9> } }\n"
        "cone { <2.5, 0.3, -3>, 0.3, <2.5, 0.3, 5>, 0.1 pigment { color rgb <0.9, 0.5, 0.2> } }\n"
        "sphere { <-1.5, 3, 20>, 3 pigment { color rgb <0.9, 0.3, 0.3> } }\n";
    for (int k = 0; k < 2; k++) {
        char what[64];
        image im = render_text(engines[k], text, W, H);
        snprintf(what, sizeof what, "%s grazing rays", engines[k]->name);
        dump_ppm(&im, what);
        assert_clean(&im, what, 0, 0);
        image_free(&im);
    }
}

/* A sphere of radius 1e-3 next to one of radius 1e4 (the ground). */
static void test_tiny_and_huge_radii(void **state)
{
    (void)state;
    static const char text[] =
        "camera { location <0, 0.0016, -0.006> look_at <0, 0.0008, 0> angle 40 }\n"
        "light_source { <-3000, 6000, -4000> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "sphere { <0, -10000, 0>, 10000 pigment { color rgb <0.6, 0.7, 0.5> } }\n"
        "sphere { <0, 0.001, 0>, 0.001 pigment { color rgb <0.9, 0.3, 0.3> } }\n"
        "sphere { <0.0025, 0.0005, 0.002>, 0.0005 pigment { color rgb <0.3, 0.3, 0.9> } }\n";
    image ims[2];
    for (int k = 0; k < 2; k++) {
        char what[64];
        ims[k] = render_text(engines[k], text, W, H);
        snprintf(what, sizeof what, "%s radii 1e-3 and 1e4", engines[k]->name);
        dump_ppm(&ims[k], what);
        assert_clean(&ims[k], what, 0, 0);
    }
    img_diff d = compare(&ims[0], &ims[1]);
    print_diff("radii: float vs double", d);
    assert_true(d.surf_mismatch * 200 <= d.n);
    image_free(&ims[0]);
    image_free(&ims[1]);
}

static bool is_background(uint32_t s) { return s == 0; }

/* Coincident CSG surfaces: identical spheres cancel, flush faces leave no
 * speckles. */
static void test_coincident_surfaces(void **state)
{
    (void)state;
    static const char gone[] =
        "camera { location <0, 1, -5> look_at 0 }\n"
        "light_source { <-3, 6, -4> color rgb 1 }\n"
        "difference { sphere { 0, 1 } sphere { 0, 1 } pigment { color rgb 1 } }\n"
        "difference { box { <1, -1, -1>, <2, 1, 1> } box { <1, -1, -1>, <2, 1, 1> } }\n"
        "intersection { box { <-2, -1, -1>, <-1, 1, 1> } box { <-1, -1, -1>, <0, 1, 1> } }\n";
    static const char flush[] =
        "camera { location <1.5, 2.5, -4> look_at <0, 0.5, 0> angle 60 }\n"
        "light_source { <-3, 6, -4> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "plane { y, 0 pigment { color rgb 0.7 } }\n"
        /* a union of two boxes sharing a face, a merge likewise */
        "union { box { <-2, 0, -1>, <-1, 1, 1> } box { <-1, 0, -1>, <0, 1, 1> }\n"
        "        pigment { color rgb <0.9, 0.3, 0.3> } }\n"
        "merge { box { <0.2, 0, -1>, <1.2, 1, 1> } box { <1.2, 0, -1>, <2.2, 1, 1> }\n"
        "        pigment { color rgb <0.3, 0.9, 0.3> } }\n"
        /* a difference whose cut shares the top and front faces */
        "difference { box { <-1.5, 0, -2.5>, <1.5, 0.6, -1.5> }\n"
        "             box { <0, 0, -2.5>, <1.5, 0.6, -2> } pigment { color rgb <0.3, 0.3, 0.9> } }\n"
        /* a sphere sharing the box's top face */
        "intersection { box { <2.5, 0, -2>, <3.5, 1, -1> } sphere { <3, 1, -1.5>, 0.5 }\n"
        "               pigment { color rgb <0.9, 0.9, 0.3> } }\n";
    for (int k = 0; k < 2; k++) {
        char what[64];
        image im = render_text(engines[k], gone, W, H);
        snprintf(what, sizeof what, "%s identical operands", engines[k]->name);
        assert_clean(&im, what, 0, 0);
        assert_int_equal(count_surf(&im, is_background), W * H);
        image_free(&im);
        im = render_text(engines[k], flush, W, H);
        snprintf(what, sizeof what, "%s flush faces", engines[k]->name);
        dump_ppm(&im, what);
        assert_clean(&im, what, 0, 0);
        image_free(&im);
    }
}

/* The matte scene at scales 1e-4, 1 and 1e6: no dark speckle anywhere
 * (acne), and the lit side of the floor is lit. */
static void test_shadow_acne(void **state)
{
    (void)state;
    const double scales[3] = {1e-4, 1.0, 1e6};
    const double cam[3] = {0.0, 3.0, -6.0};
    for (int j = 0; j < 3; j++) {
        char text[2048];
        lit_scene(text, sizeof text, scales[j], 0.0, cam, 55.0);
        for (int k = 0; k < 2; k++) {
            char what[64];
            image im = render_text(engines[k], text, W, H);
            snprintf(what, sizeof what, "%s acne scale %g", engines[k]->name, scales[j]);
            dump_ppm(&im, what);
            assert_clean(&im, what, 0, 0);
            /* the top-left of the floor (row 62, columns 2..12) is lit */
            for (int x = 2; x < 12; x++)
                assert_true(luminance(&im, 62 * W + x) > 0.2);
            image_free(&im);
        }
    }
}

/* ---- robust formulations against naive ones (float) ------------------------- */

/* The textbook quadratic: |o + t d - c|^2 = r^2 with b = 2 f.d, c = f.f - r^2. */
static int naive_sphere(const real *sp, csg_ray r, real *t0, real *t1)
{
    vec3 f = v3_sub(r.o, v3_load(sp));
    real a = v3_dot(r.d, r.d), b = R(2.0) * v3_dot(f, r.d);
    real c = v3_dot(f, f) - sp[3] * sp[3];
    real disc = b * b - R(4.0) * a * c;
    if (disc < R(0.0))
        return 0;
    real root = r_sqrt(disc);
    *t0 = (-b - root) / (R(2.0) * a);
    *t1 = (-b + root) / (R(2.0) * a);
    return 1;
}

/* A sphere of radius 0.1 at 1e4, rays passing 0 .. 0.2 from its centre:
 * float's textbook quadratic cancels (c = 1e8 - 0.01 keeps no trace of
 * the radius) and answers at random; csg_sphere_span is right on every
 * ray that passes more than 5% of the radius from the rim. */
static void test_sphere_naive_vs_haines(void **state)
{
    (void)state;
    const real sp[4] = {R(0.0), R(0.0), R(1e4), R(0.1)};
    const int n = 400;
    int wrong_naive = 0, wrong_robust = 0, judged = 0;
    double worst_t = 0.0;
    for (int i = 0; i < n; i++) {
        double x = 0.2 * (i + 0.5) / n;
        double len = sqrt(x * x + 1e8);
        csg_ray r;
        r.o = v3(R(0.0), R(0.0), R(0.0));
        r.d = v3((real)(x / len), R(0.0), (real)(1e4 / len));
        /* the truth, in double, for the float ray as stored */
        double dx = (double)r.d.x, dz = (double)r.d.z, dl = sqrt(dx * dx + dz * dz);
        double along = 1e4 * dz / dl;
        double perp = fabs(1e4 * dx / dl);
        if (fabs(perp - 0.1) < 0.005)
            continue;
        judged++;
        bool truth = perp < 0.1;
        real t0, t1;
        csg_i32 s0, s1;
        bool robust = csg_sphere_span(sp, r, &t0, &t1, &s0, &s1) != 0;
        if (robust && truth)
            worst_t = fmax(worst_t, fabs((double)t0 * dl - (along - sqrt(0.01 - perp * perp))));
        wrong_robust += robust != truth;
        wrong_naive += (naive_sphere(sp, r, &t0, &t1) != 0) != truth;
    }
    printf("  sphere at 1e4, r 0.1, float: naive wrong %d/%d, Haines wrong %d/%d, "
           "max |t - t_exact| %.3g\n",
           wrong_naive, judged, wrong_robust, judged, worst_t);
    assert_int_equal(wrong_robust, 0);
    assert_true(wrong_naive * 5 > judged); /* > 20% */
    assert_true(worst_t < 0.01);           /* an ulp of 1e4 in float is 0.001 */
}

/* Shadow rays leaving a lit sphere of radius S at distance 5 S, float:
 * a fixed epsilon (1e-4) vanishes in the rounding at S = 1e6 (the shadow
 * ray starts inside and the sphere shadows itself) and swallows the whole
 * sphere at S = 1e-4; offset_point self-intersects nowhere and moves the
 * origin by less than 1e-3 of the radius at every scale. */
static void test_offset_naive_vs_robust(void **state)
{
    (void)state;
    const double scales[3] = {1e-4, 1.0, 1e6};
    for (int j = 0; j < 3; j++) {
        double S = scales[j];
        const real sp[4] = {(real)(0.3 * S), (real)(0.2 * S), (real)(5.0 * S), (real)S};
        const real lo[3] = {sp[0] - sp[3], sp[1] - sp[3], sp[2] - sp[3]};
        const real hi[3] = {sp[0] + sp[3], sp[1] + sp[3], sp[2] + sp[3]};
        int self_naive = 0, self_robust = 0, rays = 0;
        double move_naive = 0.0, move_robust = 0.0;
        for (int iy = 0; iy < 20; iy++) {
            for (int ix = 0; ix < 20; ix++) {
                csg_ray r;
                r.o = v3(R(0.0), R(0.0), R(0.0));
                r.d = v3_normalize(v3((real)(0.3 + 0.09 * (ix - 9.5) / 10.0),
                                      (real)(0.2 + 0.09 * (iy - 9.5) / 10.0), R(5.0)));
                real t0, t1;
                csg_i32 s0, s1;
                if (!csg_sphere_span(sp, r, &t0, &t1, &s0, &s1))
                    continue;
                vec3 p = v3_add(r.o, v3_scale(r.d, t0));
                vec3 nrm = v3_normalize(v3_sub(p, v3_load(sp)));
                vec3 l = v3_normalize(v3_add(nrm, v3(R(0.2), R(0.6), R(-0.3))));
                if (v3_dot(l, nrm) < R(0.2))
                    continue;
                rays++;
                real m = r_fmax(offset_magnitude(r.o, r.d, t0), offset_box_magnitude(lo, hi));
                vec3 q[2] = {v3_add(p, v3_scale(nrm, R(1e-4))), offset_point(p, nrm, m)};
                for (int k = 0; k < 2; k++) {
                    csg_ray sh;
                    sh.o = q[k];
                    sh.d = l;
                    bool self = csg_sphere_span(sp, sh, &t0, &t1, &s0, &s1) && t1 > R(0.0);
                    double move = (double)v3_length(v3_sub(q[k], p)) / S;
                    if (k == 0) {
                        self_naive += self;
                        move_naive = fmax(move_naive, move);
                    } else {
                        self_robust += self;
                        move_robust = fmax(move_robust, move);
                    }
                }
            }
        }
        printf("  offsets at scale %-6g float: fixed 1e-4: %3d/%d self-hits, moved %.3g R; "
               "offset_point: %d self-hits, moved %.3g R\n",
               S, self_naive, rays, move_naive, self_robust, move_robust);
        assert_true(rays > 200);
        assert_int_equal(self_robust, 0);
        assert_true(move_robust < 1e-3);
        if (S > 1e5)
            assert_true(self_naive * 10 > rays); /* > 10% acne */
        if (S < 1e-3)
            assert_true(move_naive > 0.5);       /* half the radius: light leaks */
    }
}

/* ---- NaN and infinity ------------------------------------------------------------ */

/* Every object has ambient light on a non-black pigment and the
 * background is not black, so a pixel exactly black is a NaN or an
 * infinity the engine zeroed. */
static int black_pixels(const image *im)
{
    int n = 0;
    for (int i = 0; i < im->w * im->h; i++)
        n += im->rgb[3 * i] == 0.0f && im->rgb[3 * i + 1] == 0.0f && im->rgb[3 * i + 2] == 0.0f;
    return n;
}

static void test_no_nan_or_inf(void **state)
{
    (void)state;
    static const char *const scenes[] = {
        /* a pixel whose direction is exactly zero: direction cancels right
         * at x0 = -0.4921875 (column 0 of 64), up at row 24 of 49 is 0 */
        "camera { location <0, 1, -5> direction <0.4921875, 0, 0> right x up y }\n"
        "light_source { <3, 6, -4> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "sphere { <3, 1, 0>, 1 pigment { color rgb <0.9, 0.3, 0.3> } }\n"
        "plane { y, 0 pigment { color rgb 0.6 } }\n",
        /* rays exactly along box faces and edges, cylinder and cone axes */
        "camera { location <0.5, 0.5, -5> direction z up y right 1.3333*x }\n"
        "light_source { <0.5, 0.5, -10> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "box { <0.5, 0.5, 0>, <1.5, 1.5, 1> pigment { color rgb <0.3, 0.9, 0.3> } }\n"
        "cylinder { <0.5, 0.5, 2>, <0.5, 0.5, 3>, 0.2 pigment { color rgb <0.3, 0.3, 0.9> } }\n"
        "cone { <0.5, 0.5, 4>, 0, <0.5, 0.5, 5>, 0.3 pigment { color rgb <0.9, 0.9, 0.3> } }\n"
        "cone { <0.5, 0.5, 6>, 1, <0.5, 0.5, 7>, 1 open pigment { color rgb <0.9, 0.3, 0.9> } }\n"
        "plane { x, 0.5 pigment { color rgb 0.6 } }\n",
        /* zero-thickness CSG */
        "camera { location <0.5, 2, -4> look_at <0.5, 0.5, 0> }\n"
        "light_source { <3, 6, -4> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "intersection { box { <-1, 0, 0>, <0, 1, 1> } box { <0, 0, 0>, <1, 1, 1> } }\n"
        "difference { box { <0, 0, 0>, <1, 1, 1> } box { <0, 0, 0>, <1, 1, 1> } }\n"
        "merge { sphere { <2, 1, 0>, 1 } sphere { <2, 1, 0>, 1 inverse } pigment { color rgb 1 } }\n"
        "intersection { sphere { <-2, 1, 0>, 1 } plane { x, -3 } pigment { color rgb 1 } }\n"
        "plane { y, 0 pigment { color rgb 0.6 } }\n",
        /* coordinates of 1e30 */
        "camera { location <0, 0, 0> look_at <0, 0, 1e30> }\n"
        "light_source { <0, 1e30, 0> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "sphere { <0, 0, 1e30>, 4e29 pigment { color rgb <0.9, 0.3, 0.3> } }\n"
        "box { <-1e30, -1e30, 2e30>, <1e30, -3e29, 3e30> pigment { color rgb 0.5 } }\n",
        /* the camera on a sphere and on a plane */
        "camera { location <0, 0, -1> look_at <0, 0, 0> }\n"
        "light_source { <0, 0, 0> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "sphere { <0, 0, 0>, 1 pigment { color rgb <0.9, 0.3, 0.3> } }\n",
        "camera { location <0, 0, -3> look_at <0, 0, 0> }\n"
        "light_source { <2, 5, -3> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "plane { y, 0 pigment { color rgb 0.6 } }\n"
        "sphere { <0, 0, 0>, 1 pigment { color rgb <0.9, 0.3, 0.3> } }\n",
        /* a light inside an opaque sphere and one inside glass */
        "camera { location <0, 2, -6> look_at <0, 1, 0> }\n"
        "light_source { <-2, 1, 0> color rgb 1 }\n"
        "light_source { <2, 1, 0> color rgb 1 }\n"
        "background { color rgb <0.4, 0.6, 0.8> }\n"
        "plane { y, 0 pigment { color rgb 0.6 } }\n"
        "sphere { <-2, 1, 0>, 0.8 pigment { color rgb <0.9, 0.3, 0.3> } }\n"
        "sphere { <2, 1, 0>, 0.8 pigment { color rgbf <1, 1, 1, 0.9> } interior { ior 1.5 } }\n",
    };
    const int n = (int)(sizeof scenes / sizeof scenes[0]);
    for (int j = 0; j < n; j++) {
        for (int k = 0; k < 2; k++) {
            image im = render_text(engines[k], scenes[j], 64, 49);
            int black = black_pixels(&im);
            printf("  %s scene %d: %d hit, %d black\n", engines[k]->name, j,
                   count_surf(&im, is_hit), black);
            assert_true(all_finite(&im));
            assert_int_equal(black, 0);
            if (j == 3 && k == 0) /* double sees the sphere at 1e30, lit */
                assert_true(count_surf(&im, is_hit) > 64 * 49 / 10);
            image_free(&im);
        }
    }
}

/* ---- the --precision auto criterion ------------------------------------------------ */

static bool auto_pick(const char *text, int w, int h)
{
    csg_scene s;
    parse_ok(text, &s);
    char why[512];
    bool need = csg_needs_double(&s, w, h, why, sizeof why);
    printf("  auto: %s\n", why);
    assert_true(strncmp(why, need ? "double: " : "float: ", need ? 8 : 7) == 0);
    csg_scene_free(&s);
    return need;
}

/* Float where float renders like double (<= 0.1% of the pixels off by
 * more than 1/255, <= 0.1% on another surface), double where it does not
 * (> 1% off): the unit scene, scaled by 1e-4 or 1e6, a camera 1e-3 from a
 * surface -> float; the unit scene moved 1e6 from the origin, a camera
 * 1e5 away with a narrow lens, radii 1e-3 beside 1e4, 1e30 -> double. */
static void test_auto_precision(void **state)
{
    (void)state;
    const double cam[3] = {0.0, 3.0, -6.0}, far_cam[3] = {0.0, 5e4, -8.66e4};
    char texts[6][2048];
    lit_scene(texts[0], sizeof texts[0], 1.0, 0.0, cam, 55.0);
    lit_scene(texts[1], sizeof texts[1], 1e-4, 0.0, cam, 55.0);
    lit_scene(texts[2], sizeof texts[2], 1e6, 0.0, cam, 55.0);
    lit_scene(texts[3], sizeof texts[3], 1.0, 1e6, cam, 55.0);
    lit_scene(texts[4], sizeof texts[4], 1.0, 0.0, far_cam, 0.0033);
    lit_scene(texts[5], sizeof texts[5], 1.0, 3e4, cam, 55.0);
    const bool want[6] = {false, false, false, true, true, true};
    for (int j = 0; j < 6; j++) {
        bool need = auto_pick(texts[j], W, H);
        image a = render_text(&engine_double, texts[j], W, H);
        image b = render_text(&engine_float, texts[j], W, H);
        img_diff d = compare(&a, &b);
        char what[64];
        snprintf(what, sizeof what, "float vs double, scene %d", j);
        print_diff(what, d);
        assert_true(need == want[j]);
        if (need)
            assert_true(d.off_8bit + d.surf_mismatch > d.n / 100);
        else
            assert_true(d.off_8bit * 1000 <= d.n && d.surf_mismatch * 1000 <= d.n);
        image_free(&a);
        image_free(&b);
    }
}


/* ---- the torus: its root solver and its span at the extremes ---------------- */

/* csg_poly_roots (csg/device/poly_solve.h) on quartics whose roots are
 * known: close simple roots, a double root (a grazing ray), none. */
static void test_poly_roots(void **state)
{
    (void)state;
    /* (x - 0.1)(x - 0.1001)(x + 0.5)(x - 0.7), expanded in double:
       q[i] the coefficient of x^i */
    double r4[4] = {0.1, 0.1001, -0.5, 0.7}, q[5] = {1, 0, 0, 0, 0};
    for (int k = 0; k < 4; k++) { /* q *= (x - r4[k]) */
        for (int i = k + 1; i >= 1; i--)
            q[i] = q[i - 1] - r4[k] * q[i];
        q[0] = -r4[k] * q[0];
    }
    double got[4];
    int n = csg_poly_roots(q, 4, -1.0, 1.0, got);
    assert_int_equal(n, 4);
    double want[4] = {-0.5, 0.1, 0.1001, 0.7};
    for (int k = 0; k < 4; k++)
        assert_true(fabs(got[k] - want[k]) < 1e-8);
    /* (x - 0.3)^2 (x + 0.2)(x - 0.9) = x^4 - 1.3x^3 + 0.33x^2 + 0.045x - 0.0162 */
    double d2[5] = {-0.0162, 0.045, 0.33, -1.3, 1};
    /* the double root is found once, or lost in the rounding of the
       sequence (a grazing ray: no interval either way); the others stay */
    n = csg_poly_roots(d2, 4, -1.0, 1.0, got);
    assert_true(n == 2 || n == 3);
    assert_true(fabs(got[0] + 0.2) < 1e-9 && fabs(got[n - 1] - 0.9) < 1e-9);
    if (n == 3)
        assert_true(fabs(got[1] - 0.3) < 1e-6);
    double none[5] = {1, 0, 0, 0, 1}; /* x^4 + 1 */
    assert_int_equal(csg_poly_roots(none, 4, -10.0, 10.0, got), 0);
    double lin[5] = {-0.25, 1, 0, 0, 0}; /* x - 0.25: the leading zeros drop */
    n = csg_poly_roots(lin, 4, -1.0, 1.0, got);
    assert_int_equal(n, 1);
    assert_true(fabs(got[0] - 0.25) < 1e-12);
}

/* The ends of n spans [t0, t1) within [-1e3, 1e3], between the two ends
 * of that window: the points that cut the line into runs of one sign. */
static int span_cuts(const float *t0, const float *t1, int n, double *cuts)
{
    int m = 0;
    cuts[m++] = -1e3;
    for (int i = 0; i < n; i++) {
        cuts[m++] = fmax((double)t0[i], -1e3);
        cuts[m++] = fmin((double)t1[i], 1e3);
    }
    cuts[m++] = 1e3;
    return m;
}

/* The two pieces of torus (big, small) on the ray (o, d): their
 * intervals, n of them (0 to 2). */
static int torus_spans(double big, double small, const float o[3], const float d[3], float t0[2],
                       float t1[2])
{
    int n = 0;
    for (int piece = 0; piece < 2; piece++) {
        csg_prim pr;
        memset(&pr, 0, sizeof pr);
        pr.kind = CSG_PRIM_TORUS;
        pr.p[0] = (float)big;
        pr.p[1] = (float)small;
        pr.p[2] = (float)piece;
        csg_ray r = {v3(o[0], o[1], o[2]), v3(d[0], d[1], d[2])};
        float a = 0, b = 0;
        csg_i32 s0, s1;
        if (csg_prim_span(&pr, r, &a, &b, &s0, &s1)) {
            assert_true(isfinite(a) && isfinite(b) && a < b);
            assert_int_equal(n, piece); /* piece 1 only after piece 0 */
            if (n > 0)
                assert_true(t1[n - 1] < a);
            t0[n] = a;
            t1[n] = b;
            n++;
        }
    }
    return n;
}

/* A thin torus (r = 1e-3 R) seen from 1e4 away, along z at distance x0
 * from its axis and height y0 (a line parallel to the axis plane meets the
 * tube where its circle of radius w = sqrt(r^2 - y0^2) is: |rho - R| <=
 * w, rho = sqrt(x0^2 + z^2)): the float parameters are within one unit in
 * the last place of the exact ones (an interval shorter than that unit
 * is lost: float's limit at that distance, not the solver's).  Then a ray grazing the top of a
 * thin tube (y0 just below r: a tiny interval on each side; exactly r:
 * a double root, nothing of any length; just above: nothing). */
static void test_torus_extremes(void **state)
{
    (void)state;
    const double big = 1, small = 1e-3, far = 1e4;
    static const double cases[][3] = {/* x0, y0 / small, intervals */
                                      {0.5, 0, 2}, {0.5, 0.7, 2}, {1.0, 0, 1}, {0.9995, 0.3, 1},
                                      {0.2, 0.6, 2}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        double x0 = cases[c][0], y0 = cases[c][1] * small;
        float o[3] = {(float)x0, (float)y0, (float)-far}, d[3] = {0, 0, 1}, t0[2], t1[2];
        int n = torus_spans(big, small, o, d, t0, t1);
        assert_int_equal(n, (int)cases[c][2]);
        double w = sqrt(small * small - (double)o[1] * (double)o[1]);
        double zo = sqrt((big + w) * (big + w) - (double)o[0] * (double)o[0]);
        double ri = big - w, inner = ri > (double)o[0] ? sqrt(ri * ri - (double)o[0] * (double)o[0]) : 0;
        double want0[2] = {far - zo, far + inner}, want1[2] = {far - inner, far + zo};
        if (n == 1) /* the line stays in the tube across the axis plane */
            want1[0] = far + zo;
        double ulp = 1e4 * 1.2e-7;
        for (int k = 0; k < n; k++) {
            assert_true(fabs((double)t0[k] - want0[k]) <= ulp);
            assert_true(fabs((double)t1[k] - want1[k]) <= ulp);
        }
    }
    /* a spindle torus (R 0.3 < r 0.6), along y at x = 0.05: inside the
       tube for |y| < sqrt(0.36 - 0.0625), its spindle (|y| < sqrt(0.36 -
       0.1225)) included, as POV-Ray's default union mode: one interval */
    {
        float o[3] = {0.05f, -5, 0}, d[3] = {0, 1, 0}, t0[2], t1[2];
        int n = torus_spans(0.3, 0.6, o, d, t0, t1);
        assert_int_equal(n, 1);
        double half = sqrt(0.36 - (0.3 - (double)o[0]) * (0.3 - (double)o[0]));
        assert_true(fabs((double)t0[0] - (5 - half)) < 1e-5 && fabs((double)t1[0] - (5 + half)) < 1e-5);
    }
    /* grazing the top of the tube from 10 away, along x */
    const double heights[] = {1 - 1e-4, 1.0, 1 + 1e-4};
    for (int k = 0; k < 3; k++) {
        float o[3] = {-10, (float)(heights[k] * small), 0}, d[3] = {1, 0, 0}, t0[2], t1[2];
        int n = torus_spans(big, small, o, d, t0, t1);
        if (k == 0) {
            assert_int_equal(n, 2);
            assert_true(fabs((double)t0[0] - 9) < 1e-4 && fabs((double)t1[1] - 11) < 1e-4);
        } else {
            for (int i = 0; i < n; i++) /* a double root may leave a sliver */
                assert_true((double)(t1[i] - t0[i]) < 1e-5);
            if (k == 2)
                assert_int_equal(n, 0);
        }
    }
}

/* Random lines through a torus and its surroundings: the middle of every
 * interval is inside (POV-Ray's test, in double) and the middle of every
 * gap outside, unless the line passes within 1e-5 of the surface there. */
static void test_torus_pieces_random(void **state)
{
    (void)state;
    const double big = 1, small = 0.35;
    uint64_t st = 12345;
    int checked = 0, inside = 0;
    for (int k = 0; k < 2000; k++) {
        float o[3], d[3], t0[2], t1[2];
        static const double aim[3] = {3, 1, 3}; /* towards the torus's box */
        for (int i = 0; i < 3; i++) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            o[i] = (float)(((double)(st >> 11) / 9007199254740992.0 - 0.5) * 8);
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            d[i] = (float)(((double)(st >> 11) / 9007199254740992.0 - 0.5) * aim[i]) - o[i];
        }
        int n = torus_spans(big, small, o, d, t0, t1);
        inside += n;
        double cuts[6] = {-20};
        int m = 1;
        for (int i = 0; i < n; i++) {
            cuts[m++] = t0[i];
            cuts[m++] = t1[i];
        }
        cuts[m++] = 20;
        for (int i = 0; i + 1 < m; i++) {
            double t = 0.5 * (cuts[i] + cuts[i + 1]);
            double p[3];
            for (int a = 0; a < 3; a++)
                p[a] = (double)o[a] + t * (double)d[a];
            double ring = sqrt(p[0] * p[0] + p[2] * p[2]) - big;
            double dist = sqrt(p[1] * p[1] + ring * ring) - small;
            if (fabs(dist) < 1e-5)
                continue;
            assert_true((dist < 0) == (i % 2 == 1));
            checked++;
        }
    }
    assert_true(checked > 4000 && inside > 1000);
}

/* Quadrics (world-space coefficients A..J, flat.h) on random lines: the
 * pieces' intervals are sorted and disjoint, their middles inside (f <=
 * 0, in double), the gaps' middles outside, unless the point is within
 * 1e-6 (relative) of the surface; every kind of set a line can meet is
 * reached (one interval, two half-lines, a half-line, the whole line). */
static void test_quadric_pieces_random(void **state)
{
    (void)state;
    static const double quads[][10] = {
        {1, 4, 2, 0, 0, 0, 0, 0, 0, -1},          /* ellipsoid            */
        {1, -1, 1, 0.4, 0, 0, 0, 0, 0, -0.3},     /* hyperboloid, 1 sheet */
        {-1, 1, -1, 0, 0.2, 0, 0, 0, 0, -0.3},    /* 2 sheets, inside out */
        {1, 0, 1, 0, 0, 0, 0, -1, 0, 0},          /* paraboloid           */
        {0, 0, 0, 0, 0, 0, 0.3, 1, -0.2, 0.5},    /* a plane: linear      */
    };
    uint64_t st = 777;
    int checked = 0, two = 0, unbounded = 0;
    for (size_t q = 0; q < sizeof quads / sizeof quads[0]; q++)
        for (int k = 0; k < 400; k++) {
            float o[3], d[3];
            for (int i = 0; i < 3; i++) {
                st = st * 6364136223846793005ull + 1442695040888963407ull;
                o[i] = (float)(((double)(st >> 11) / 9007199254740992.0 - 0.5) * 6);
                st = st * 6364136223846793005ull + 1442695040888963407ull;
                d[i] = (float)(((double)(st >> 11) / 9007199254740992.0 - 0.5) * 2);
            }
            float t0[2], t1[2];
            int n = 0;
            for (int piece = 0; piece < 2; piece++) {
                csg_prim pr;
                memset(&pr, 0, sizeof pr);
                pr.kind = CSG_PRIM_QUADRIC;
                for (int i = 0; i < 10; i++)
                    pr.p[i] = (float)quads[q][i];
                pr.p[10] = (float)piece;
                csg_ray r = {v3(o[0], o[1], o[2]), v3(d[0], d[1], d[2])};
                float a = 0, b = 0;
                csg_i32 s0, s1;
                if (csg_prim_span(&pr, r, &a, &b, &s0, &s1)) {
                    assert_true(a < b && !isnan(a) && !isnan(b));
                    assert_int_equal(n, piece);
                    assert_true(n == 0 || t1[0] < a);
                    unbounded += isinf(a) || isinf(b);
                    t0[n] = a;
                    t1[n] = b;
                    n++;
                }
            }
            two += n == 2;
            double cuts[6];
            int m = span_cuts(t0, t1, n, cuts);
            for (int i = 0; i + 1 < m; i++) {
                if (!(cuts[i] < cuts[i + 1]))
                    continue;
                double t = 0.5 * (cuts[i] + cuts[i + 1]), p[3];
                for (int a = 0; a < 3; a++)
                    p[a] = (double)o[a] + t * (double)d[a];
                const double *c = quads[q];
                double f = p[0] * (c[0] * p[0] + c[3] * p[1] + c[6]) +
                           p[1] * (c[1] * p[1] + c[5] * p[2] + c[7]) +
                           p[2] * (c[2] * p[2] + c[4] * p[0] + c[8]) + c[9];
                double scale = 1 + p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
                if (fabs(f) < 1e-6 * scale)
                    continue;
                assert_true((f <= 0) == (i % 2 == 1));
                checked++;
            }
        }
    assert_true(checked > 2000 && two > 50 && unbounded > 50);
}

/* A poly primitive with its coefficients right after it: p[2], p[3] the
 * offset from its payload to them (flat.h), as the flattener writes it. */
typedef struct {
    csg_prim prim;
    float coefs[120];
} poly_prim;

static void poly_prim_make(poly_prim *pp, int order, int piece, const double *coef)
{
    memset(pp, 0, sizeof *pp);
    pp->prim.kind = CSG_PRIM_POLY;
    pp->prim.p[0] = (float)order;
    pp->prim.p[1] = (float)piece;
    size_t rel = (offsetof(poly_prim, coefs) - offsetof(poly_prim, prim) - offsetof(csg_prim, p)) /
                 sizeof(float);
    pp->prim.p[2] = (float)(rel / CSG_POLY_OFFSET_UNIT);
    pp->prim.p[3] = (float)(rel % CSG_POLY_OFFSET_UNIT);
    int terms = (order + 1) * (order + 2) * (order + 3) / 6;
    for (int k = 0; k < terms; k++)
        pp->coefs[k] = (float)coef[k];
}

/* A poly's normal where its float gradient overflows: f = 1e38 (x^2 -
 * y^2 + z) at (10, 5, -75) has the gradient 1e38 (20, -10, 1), beyond
 * float (the fuzzer's NaN normal: inf * 0 after the normalisation); the
 * normal is computed over the coefficients divided by the largest, so it
 * is finite and points along (20, -10, 1). */
static void test_poly_normal_range(void **state)
{
    (void)state;
    /* order 2, POV-Ray's term order: x^2 xy xz x y^2 yz y z^2 z 1 */
    const double coef[10] = {1e38, 0, 0, 0, -1e38, 0, 0, 0, 1e38, 0};
    poly_prim pp;
    poly_prim_make(&pp, 2, 0, coef);
    vec3 n = csg_poly_normal(pp.prim.p, 0, v3(10.0f, 5.0f, -75.0f));
    assert_true(isfinite(n.x) && isfinite(n.y) && isfinite(n.z));
    double nx = (double)n.x, ny = (double)n.y, nz = (double)n.z;
    double len = sqrt(nx * nx + ny * ny + nz * nz);
    double want_len = sqrt(20.0 * 20 + 10 * 10 + 1);
    assert_true(fabs(nx / len - 20 / want_len) < 1e-6);
    assert_true(fabs(ny / len + 10 / want_len) < 1e-6);
    assert_true(fabs(nz / len - 1 / want_len) < 1e-6);
}

/* Polys of orders 2 to 7 (bounded, unbounded, odd) on random lines: the
 * pieces' intervals are sorted and disjoint, their middles inside (the
 * poly < 0, in double: csg_poly_value), the gaps' middles outside, unless
 * the point is within 1e-6 (relative) of the surface; the quartic torus
 * gives the torus primitive's intervals (within 1e-4). */
static void test_poly_pieces_random(void **state)
{
    (void)state;
    static const double torus4[35] = {1, 0, 0, 0, 2, 0, 0, 2, 0, -2.32, 0, 0, 0, 0, 0, 0, 0, 0,
                                      0, 0, 1, 0, 0, 2, 0, 1.68, 0, 0, 0, 0, 1, 0, -2.32, 0, 0.7056};
    static const double saddle3[20] = {1, 0, 0, 0, -3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -1, 0};
    static const double sphere2[10] = {1, 0, 0, 0, 1, 0, 0, 1, 0, -1};
    static const double bowl4[35] = {[0] = 1, [29] = -1, [30] = 1};  /* x^4 + z^4 - y */
    static const double cyl4[35] = {[0] = 1, [20] = 1, [34] = -0.1}; /* x^4 + y^4 - 0.1 */
    double p5[56] = {0}, p7[120] = {0};
    p5[0] = 1, p5[37] = 1, p5[51] = 1, p5[55] = -0.5; /* x^5 + y^4 + z^4 - 0.5 */
    p7[0] = 1, p7[85] = -1, p7[119] = -1; /* x^7 - y^6 z - 1 */
    struct {
        int order;
        const double *c;
    } polys[] = {{4, torus4}, {3, saddle3}, {2, sphere2}, {4, bowl4}, {4, cyl4}, {5, p5}, {7, p7}};
    uint64_t st = 4242;
    int checked = 0, several = 0, unbounded = 0, same_as_torus = 0;
    for (size_t q = 0; q < sizeof polys / sizeof polys[0]; q++)
        for (int k = 0; k < 300; k++) {
            float o[3], d[3];
            for (int i = 0; i < 3; i++) {
                st = st * 6364136223846793005ull + 1442695040888963407ull;
                o[i] = (float)(((double)(st >> 11) / 9007199254740992.0 - 0.5) * 4);
                st = st * 6364136223846793005ull + 1442695040888963407ull;
                d[i] = (float)(((double)(st >> 11) / 9007199254740992.0 - 0.5) * 2);
            }
            int order = polys[q].order, n = 0;
            float t0[4], t1[4];
            csg_ray r = {v3(o[0], o[1], o[2]), v3(d[0], d[1], d[2])};
            for (int piece = 0; piece <= order / 2; piece++) {
                poly_prim pp;
                poly_prim_make(&pp, order, piece, polys[q].c);
                float a = 0, b = 0;
                csg_i32 s0, s1;
                if (csg_prim_span(&pp.prim, r, &a, &b, &s0, &s1)) {
                    assert_true(a < b && !isnan(a) && !isnan(b));
                    assert_int_equal(n, piece);
                    assert_true(n == 0 || t1[n - 1] < a);
                    unbounded += isinf(a) || isinf(b);
                    t0[n] = a;
                    t1[n] = b;
                    n++;
                }
            }
            several += n >= 2;
            if (q == 0) { /* the torus primitive (R 1, r 0.4) agrees */
                for (int piece = 0; piece < 2; piece++) {
                    csg_prim pr;
                    memset(&pr, 0, sizeof pr);
                    pr.kind = CSG_PRIM_TORUS;
                    pr.p[0] = 1.0f;
                    pr.p[1] = 0.4f;
                    pr.p[2] = (float)piece;
                    float a = 0, b = 0;
                    csg_i32 s0, s1;
                    int hit = csg_prim_span(&pr, r, &a, &b, &s0, &s1);
                    assert_int_equal(hit, piece < n);
                    if (hit) {
                        assert_true(fabsf(a - t0[piece]) < 1e-4f && fabsf(b - t1[piece]) < 1e-4f);
                        same_as_torus++;
                    }
                }
                assert_true(n <= 2);
            }
            double cuts[10];
            int m = span_cuts(t0, t1, n, cuts);
            for (int i = 0; i + 1 < m; i++) {
                if (!(cuts[i] < cuts[i + 1]))
                    continue;
                double t = 0.5 * (cuts[i] + cuts[i + 1]);
                dvec3 p = {(double)o[0] + t * (double)d[0], (double)o[1] + t * (double)d[1],
                           (double)o[2] + t * (double)d[2]};
                double f = csg_poly_value(order, polys[q].c, p, NULL);
                double scale = pow(1 + p.x * p.x + p.y * p.y + p.z * p.z, 0.5 * order);
                if (fabs(f) < 1e-6 * scale)
                    continue;
                if ((f < 0) != (i % 2 == 1))
                    print_message("poly %d line %d: f %g at t %g, run %d of %d\n", (int)q, k, f, t, i, m);
                assert_true((f < 0) == (i % 2 == 1));
                checked++;
            }
        }
    assert_true(checked > 2500 && several > 100 && unbounded > 100 && same_as_torus > 50);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scale_invariance),
        cmocka_unit_test(test_extreme_cameras),
        cmocka_unit_test(test_tangent_rays),
        cmocka_unit_test(test_grazing_rays),
        cmocka_unit_test(test_tiny_and_huge_radii),
        cmocka_unit_test(test_coincident_surfaces),
        cmocka_unit_test(test_shadow_acne),
        cmocka_unit_test(test_sphere_naive_vs_haines),
        cmocka_unit_test(test_offset_naive_vs_robust),
        cmocka_unit_test(test_no_nan_or_inf),
        cmocka_unit_test(test_auto_precision),
        cmocka_unit_test(test_poly_roots),
        cmocka_unit_test(test_torus_extremes),
        cmocka_unit_test(test_torus_pieces_random),
        cmocka_unit_test(test_quadric_pieces_random),
        cmocka_unit_test(test_poly_pieces_random),
        cmocka_unit_test(test_poly_normal_range),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
