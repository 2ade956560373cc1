/*
 * test_stability.c — numerical stability at the extremes, in process:
 * scenes written as text, parsed (csg_parse_string), flattened and
 * rendered by the CPU engine in float and in double, pixel buffers
 * compared.
 *
 * What is asserted (the bounds are the ones bench/ACCURACY.md states):
 *   - scale invariance: the same scene scaled by 1e-4 and 1e6 (objects,
 *     lights and camera together) renders like the unit scene: double
 *     within 1e-3 on 99.9% of the pixels and <= 0.1% pixels with another
 *     primary surface; float within the bound of FLOAT_SCALE_* below;
 *   - extreme cameras (1e-3 from a surface, 1e5 away), grazing and
 *     tangent rays on every primitive, tiny and huge radii in one scene,
 *     coincident CSG surfaces, shadow acne at every scale: counted as
 *     isolated outlier pixels against the expected value;
 *   - the robust formulations against naive ones written here: the
 *     textbook quadratic loses a tiny far sphere that csg_sphere_span
 *     finds; a fixed-epsilon ray offset self-shadows where the ulp-scaled
 *     offset of workers/offset.h does not;
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
#include "../csg/parser.h"
#include "../csg/precision.h"
#include "../workers/engine.h"

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

static void parse_ok(const char *text, csg_scene *s)
{
    csg_diag d = {0};
    if (!csg_parse_string("stability.pov", text, strlen(text), s, &d))
        fail_msg("parse failed: %s\n%s", d.message, text);
}

/* The whole image as one tile. */
static image render_text(const engine *e, const char *text, int w, int h)
{
    csg_scene s;
    parse_ok(text, &s);
    csg_flatten_opts o = {w, h, 0, -1, 1};
    csg_diag d = {0};
    csg_blob b;
    if (!e->flatten(&s, &o, &b, &d))
        fail_msg("flatten failed: %s", d.message);
    image im = {w, h, calloc((size_t)w * h * 3, sizeof(float)), calloc((size_t)w * h, 4)};
    void *t = calloc((size_t)w * h, 8);
    assert_true(im.rgb && im.surf && t);
    ray_counts rays = {0};
    tile_rect r = {0, 0, w, h};
    engine_render_tile(e, b.bytes, r, t, im.surf, im.rgb, &rays);
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

/* Pixels darker than `frac` of the median of their 8 neighbours, among
 * pixels whose neighbours all share their primary surface: the speckles
 * of acne and of coincident-surface fights. */
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
            double med = 0.5 * (nb[3] + nb[4]);
            count += luminance(im, i) < frac * med;
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

static void test_scale_invariance(void **state)
{
    (void)state;
    const engine *engines[2] = {&engine_double, &engine_float};
    const double scales[2] = {1e-4, 1e6};
    char *unit_text = scene_scaled(1.0, 0.0);
    for (int k = 0; k < 2; k++) {
        image unit = render_text(engines[k], unit_text, W, H);
        dump_ppm(&unit, engines[k]->name);
        for (int j = 0; j < 2; j++) {
            char *text = scene_scaled(scales[j], 0.0);
            image im = render_text(engines[k], text, W, H);
            img_diff d = compare(&unit, &im);
            char what[64];
            snprintf(what, sizeof what, "%s scale %g", engines[k]->name, scales[j]);
            print_diff(what, d);
            dump_ppm(&im, what);
            image_free(&im);
            free(text);
        }
        image_free(&unit);
    }
    free(unit_text);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scale_invariance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
