/*
 * test_curved_sides.c — the normals of a prism's curved sides (flat.h,
 * csg_curve; intersect.h, csg_surface_shading_normal).  Rays meet the
 * chords the flattener cuts the splines into, but the shading normal
 * must be POV-Ray's Prism::Normal: the spline's, at the parameter where
 * the ray meets the spline.  The reference here is computed apart from
 * the code under test, in double, in POV-Ray's prism space (the outline in
 * xz, swept along y; the scenes have no transform): the spline segments
 * from the control points by Compute_Prism's formulas, the ray's meeting
 * with the true swept surface by sampling and bisection, and the normal by
 * Prism::Normal's formulas (the conic sweep's y from the hit point).  The
 * chord's own normal is measured too, so the test fails where the curve
 * is not used.  Compiled per precision (test_curved_sides_double.c).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/device/shadow.h"
#include "../csg/flatten.h"
#include "../csg/load.h"
#include "../workers/engine.h"
#include "flat_scene.h"


/* A closed Catmull-Rom loop through (1, 0), (0, 1), (-1, 0), (0, -1)
 * (POV-Ray's cubic_spline: the first and the last two points are the
 * tangents'), and a quadratic one through the same points. */
static const double loop_cubic[7][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 0}, {0, 1}};
static const double loop_quadratic[6][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 0}};

#define CUBIC_PRISM                                                                                \
    "prism { cubic_spline linear_sweep 0, 1, 7, <0, -1>, <1, 0>, <0, 1>, <-1, 0>, <0, -1>, "      \
    "<1, 0>, <0, 1> }\n"
#define CONIC_PRISM                                                                                \
    "prism { quadratic_spline conic_sweep 0.5, 1, 6, <0, -1>, <1, 0>, <0, 1>, <-1, 0>, <0, -1>, " \
    "<1, 0> }\n"

/* Segment i of a spline over points P as Compute_Prism's power basis:
 * coefficient k of x (0) and z (1) in c[axis][k], ((c0 u + c1) u + c2) u + c3. */
static void segment(int cubic, const double (*P)[2], int i, double c[2][4])
{
    for (int a = 0; a < 2; a++) {
        double p0 = P[i][a], p1 = P[i + 1][a], p2 = P[i + 2][a];
        if (cubic) {
            double p3 = P[i + 3][a];
            c[a][0] = -0.5 * p0 + 1.5 * p1 - 1.5 * p2 + 0.5 * p3;
            c[a][1] = p0 - 2.5 * p1 + 2.0 * p2 - 0.5 * p3;
            c[a][2] = -0.5 * p0 + 0.5 * p2;
        } else {
            c[a][0] = 0;
            c[a][1] = 0.5 * p0 - p1 + 0.5 * p2;
            c[a][2] = -0.5 * p0 + 0.5 * p2;
        }
        c[a][3] = p1;
    }
}

static double poly_at(const double c[4], double u)
{
    return ((c[0] * u + c[1]) * u + c[2]) * u + c[3];
}
static double slope_at(const double c[4], double u) { return (3 * c[0] * u + 2 * c[1]) * u + c[2]; }

typedef struct {
    double t;    /* along the ray; HUGE_VAL: none */
    double n[3]; /* POV-Ray's normal there, unit */
} curve_hit;

/* The ray o + t d (t > 0) against the side swept from segment c between
 * heights h0 and h1 (conic: the outline scaled by the height): the
 * plane through the ray holding the sweep's lines, m . (x(u), [1,] z(u)),
 * sampled and bisected for its roots. */
static void meet_segment(const double c[2][4], int conic, double h0, double h1, const double o[3],
                         const double d[3], curve_hit *best)
{
    double m[3];
    if (conic) { /* o x d, the plane through the apex */
        m[0] = o[1] * d[2] - o[2] * d[1];
        m[1] = o[2] * d[0] - o[0] * d[2];
        m[2] = o[0] * d[1] - o[1] * d[0];
    }
    enum { STEPS = 512 };
    double prev = 0;
    for (int k = 0; k <= STEPS; k++) {
        double u = (double)k / STEPS;
        double f = conic ? m[0] * poly_at(c[0], u) + m[1] + m[2] * poly_at(c[1], u)
                         : d[2] * (poly_at(c[0], u) - o[0]) - d[0] * (poly_at(c[1], u) - o[2]);
        if (k > 0 && (f == 0 || (prev < 0) != (f < 0))) {
            double lo = (double)(k - 1) / STEPS, hi = u, flo = prev;
            for (int it = 0; it < 80; it++) {
                double mid = 0.5 * (lo + hi);
                double fm = conic ? m[0] * poly_at(c[0], mid) + m[1] + m[2] * poly_at(c[1], mid)
                                  : d[2] * (poly_at(c[0], mid) - o[0]) -
                                        d[0] * (poly_at(c[1], mid) - o[2]);
                if ((fm < 0) == (flo < 0))
                    lo = mid, flo = fm;
                else
                    hi = mid;
            }
            double w = 0.5 * (lo + hi), x = poly_at(c[0], w), z = poly_at(c[1], w);
            double t;
            if (conic) /* o + t d = s (x, 1, z) */
                t = fabs(d[0] - x * d[1]) > fabs(d[2] - z * d[1])
                        ? (x * o[1] - o[0]) / (d[0] - x * d[1])
                        : (z * o[1] - o[2]) / (d[2] - z * d[1]);
            else
                t = fabs(d[0]) > fabs(d[2]) ? (x - o[0]) / d[0] : (z - o[2]) / d[2];
            double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
            if (t > 1e-9 && t < best->t && p[1] >= h0 && p[1] <= h1) {
                double n[3] = {slope_at(c[1], w), 0, -slope_at(c[0], w)}; /* Prism::Normal */
                if (conic)
                    n[1] = -(p[0] * n[0] + p[2] * n[2]) / p[1];
                double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                best->t = t;
                for (int a = 0; a < 3; a++)
                    best->n[a] = n[a] / len;
            }
        }
        prev = f;
    }
}

/* The angle between two normals, either way round (POV-Ray turns a
 * normal to the ray): from their cross product, which keeps small angles
 * (an arc cosine of float-rounded unit vectors would not). */
static double angle_between(const double a[3], vec3 b)
{
    double bx = (double)b.x, by = (double)b.y, bz = (double)b.z;
    double cx = a[1] * bz - a[2] * by, cy = a[2] * bx - a[0] * bz, cz = a[0] * by - a[1] * bx;
    double dot = fabs(a[0] * bx + a[1] * by + a[2] * bz);
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), dot);
}

typedef struct {
    int tested, chord_off; /* rays compared; of those, where the chord's normal is off */
    double worst;          /* the largest angle of ours to POV-Ray's */
} tally;

/* Rays from around the prism at points of its sides: where ours and the
 * reference meet the same side at about the same t, our shading normal
 * against POV-Ray's. */
static void compare_normals(const char *text, int cubic, int conic, double h0, double h1,
                            tally *out)
{
    csg_blob b = flat_scene("t.pov", text);
    csg_view v = csg_blob_view(b.bytes);
    const double(*P)[2] = cubic ? loop_cubic : loop_quadratic;
    memset(out, 0, sizeof *out);
    for (int seg = 0; seg < 4; seg++) {
        double c[2][4];
        segment(cubic, P, seg, c);
        for (int k = 0; k < 23; k++) {
            double u = (k + 0.5) / 23, y = h0 + (h1 - h0) * (0.2 + 0.6 * ((k * 7) % 23) / 23.0);
            double s = conic ? y : 1;
            double target[3] = {s * poly_at(c[0], u), y, s * poly_at(c[1], u)};
            /* from outside, off the normal by up to about 40 degrees */
            double nx = slope_at(c[1], u), nz = -slope_at(c[0], u), len = hypot(nx, nz);
            double side = (nx * target[0] + nz * target[2]) > 0 ? 1 : -1;
            double o[3] = {target[0] + side * 4 * nx / len + 1.5 * ((k % 5) - 2) * nz / len,
                           y + 0.6 * ((k % 3) - 1),
                           target[2] + side * 4 * nz / len - 1.5 * ((k % 5) - 2) * nx / len};
            double d[3] = {target[0] - o[0], target[1] - o[1], target[2] - o[2]};
            double dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int a = 0; a < 3; a++)
                d[a] /= dl;
            curve_hit ref = {HUGE_VAL, {0, 0, 0}};
            for (int j = 0; j < 4; j++) {
                double cj[2][4];
                segment(cubic, P, j, cj);
                meet_segment(cj, conic, h0, h1, o, d, &ref);
            }
            csg_ray r;
            r.o = v3((real)o[0], (real)o[1], (real)o[2]);
            r.d = v3((real)d[0], (real)d[1], (real)d[2]);
            csg_hit h = csg_trace_nearest(v, r, R(0.0), CSG_R_INF);
            if (ref.t == HUGE_VAL || h.surf == CSG_SURF_NONE ||
                fabs((double)h.t - ref.t) > 1e-3 || CSG_SURF_SUB(h.surf) > CSG_SURF_TRAP_SIDE_B)
                continue;
            csg_hit_frame f = csg_hit_frame_of(v, r, h.t, h.surf);
            double off = angle_between(ref.n, f.n), chord = angle_between(ref.n, f.ng);
            out->tested++;
            out->chord_off += chord > 1e-3;
            out->worst = off > out->worst ? off : out->worst;
        }
    }
    csg_blob_free(&b);
}

/* linear_sweep, cubic spline: ours within 10^-5 of POV-Ray's normal
 * (measured: 6e-7 in float, 1e-15 in double), where the chord's is off by
 * more than 10^-3 on most rays. */
static void test_linear_sweep_normals(void **state)
{
    (void)state;
    tally t;
    compare_normals(CUBIC_PRISM, 1, 0, 0, 1, &t);
    print_message("# linear sweep: %d rays, worst %.3g rad, chord off on %d\n", t.tested,
                  t.worst, t.chord_off);
    assert_true(t.tested >= 80);
    assert_true(t.chord_off >= t.tested / 2);
    assert_true(t.worst < 1e-5);
}

/* conic_sweep, quadratic spline: the same, with the height's component
 * from the hit point. */
static void test_conic_sweep_normals(void **state)
{
    (void)state;
    tally t;
    compare_normals(CONIC_PRISM, 0, 1, 0.5, 1, &t);
    print_message("# conic sweep: %d rays, worst %.3g rad, chord off on %d\n", t.tested, t.worst,
                  t.chord_off);
    assert_true(t.tested >= 80);
    assert_true(t.chord_off >= t.tested / 2);
    assert_true(t.worst < 1e-5);
}

static int curve_count(const char *text)
{
    csg_blob b = flat_scene("t.pov", text);
    int n = csg_blob_hdr(b.bytes)->curve_count;
    csg_blob_free(&b);
    return n;
}

/* Only the pieces on a curve carry one: a linear spline's prism has
 * none, so it renders as before; a curved prism's pieces and a text's
 * (its glyphs' quadratic curves: POV-Ray's TrueType normal is the curve's
 * too) do. */
static void test_which_pieces(void **state)
{
    (void)state;
    assert_int_equal(curve_count("prism { linear_spline 0, 1, 4, <0, 0>, <1, 0>, <0, 1>, <0, 0> }"),
                     0);
    assert_true(curve_count("text { ttf \"timrom.ttf\" \"So\" 0.2, 0 }") > 10);
    csg_blob b = flat_scene("t.pov", CUBIC_PRISM);
    const csg_blob_header *h = csg_blob_hdr(b.bytes);
    csg_view v = csg_blob_view(b.bytes);
    assert_true(h->curve_count > 10);
    for (int i = 0; i < h->prim_count; i++)
        assert_true(CSG_PRIM_CURVE(&v.prims[i]) >= 0);
    csg_blob_free(&b);
}

/* Each curved edge of an outline is the chord of its curve: the curve at
 * u0 and u1 is the edge's two ends (a glyph's in the text's units, with
 * its place; a prism's), so the normal belongs to that chord. */
static void check_chords(const csg_object *o, int *curved)
{
    for (int k = 0; k < o->child_count; k++)
        check_chords(o->children[k], curved);
    if (o->kind != CSG_OBJ_PRISM || !o->edge_curves)
        return;
    for (int c = 0, start = 0; c < o->contour_count; start = o->contour_ends[c], c++)
        for (int i = start; i < o->contour_ends[c]; i++) {
            const csg_outline_curve *e = &o->edge_curves[i];
            if (!(e->u0 < e->u1))
                continue;
            int next = i + 1 < o->contour_ends[c] ? i + 1 : start;
            const dvec3 ends[2] = {o->verts[i], o->verts[next]};
            const double us[2] = {e->u0, e->u1};
            for (int j = 0; j < 2; j++) {
                double x = ((e->a[0] * us[j] + e->b[0]) * us[j] + e->c[0]) * us[j] + e->d[0];
                double y = ((e->a[1] * us[j] + e->b[1]) * us[j] + e->c[1]) * us[j] + e->d[1];
                if (fabs(x - ends[j].x) > 1e-9 || fabs(y - ends[j].y) > 1e-9)
                    fail_msg("edge %d: the curve at %g is (%.12g, %.12g), the edge's end "
                             "(%.12g, %.12g)", i, us[j], x, y, ends[j].x, ends[j].y);
            }
            (*curved)++;
        }
}

static void test_chords(void **state)
{
    (void)state;
    static const char *const texts[] = {
        "text { ttf \"timrom.ttf\" \"Sog&\" 0.2, <0.1, 0.05, 0> }",
        "text { ttf \"cyrvetic.ttf\" \"@Q\" 1, 0 }",
        CUBIC_PRISM, CONIC_PRISM,
        "prism { bezier_spline 0, 1, 8, <0, 0>, <1, 0>, <1, 1>, <0, 1>, <0, 1>, <-1, 1>, "
        "<-1, 0>, <0, 0> }",
    };
    for (size_t t = 0; t < sizeof texts / sizeof texts[0]; t++) {
        csg_scene s;
        csg_diag d = {0};
        if (!csg_load_string("t.pov", texts[t], strlen(texts[t]), NULL, &s, &d))
            fail_msg("parse: %s", d.message);
        int curved = 0;
        for (int k = 0; k < s.object_count; k++)
            check_chords(s.objects[k], &curved);
        assert_true(curved > 10);
        csg_scene_free(&s);
    }
}

/* The validator refuses a curve index beyond the table, and one on a
 * primitive that is not a trapezoid piece. */
static void test_validation(void **state)
{
    (void)state;
    csg_blob b = flat_scene("t.pov", CUBIC_PRISM "sphere { <0, 3, 0>, 1 }");
    assert_true(csg_blob_valid(b.bytes, b.size));
    const csg_blob_header *h = csg_blob_hdr(b.bytes);
    csg_prim *prims = (csg_prim *)(void *)((unsigned char *)b.bytes + h->off_prims);
    int sphere = -1, piece = -1;
    for (int i = 0; i < h->prim_count; i++) {
        if (prims[i].kind == CSG_PRIM_SPHERE)
            sphere = i;
        else
            piece = i;
    }
    assert_true(sphere >= 0 && piece >= 0);
    csg_i32 kept = prims[piece].flags;
    prims[piece].flags = (kept & ((1 << CSG_PF_CURVE_SHIFT) - 1)) |
                         ((h->curve_count + 1) << CSG_PF_CURVE_SHIFT);
    assert_false(csg_blob_valid(b.bytes, b.size));
    prims[piece].flags = kept;
    prims[sphere].flags |= 1 << CSG_PF_CURVE_SHIFT;
    assert_false(csg_blob_valid(b.bytes, b.size));
    csg_blob_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear_sweep_normals),
        cmocka_unit_test(test_conic_sweep_normals),
        cmocka_unit_test(test_which_pieces),
        cmocka_unit_test(test_chords),
        cmocka_unit_test(test_validation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
