/*
 * test_geometry.c — unit tests of the shared ray/primitive geometry:
 * csg/device/vec.h, the primitive intervals and normals of csg/device/intersect.h, the
 * CSG_PF_XFORM path, and the primary ray of csg/device/camera.h.
 *
 * The same file is compiled twice: as is (real = float) and through
 * tests/test_geometry_double.c (real = double, CSG_DOUBLE).  Expected values
 * are analytic (exactly representable where the test says "exact"), or come
 * from a reference computed in a wider type from the very same inputs.
 * Tolerances scale with the precision's epsilon (EPS below).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <string.h>

#include "../csg/device/camera.h"
#include "../csg/device/intersect.h"
#include "../csg/scene.h"

#include "geom_assert.h"

static csg_prim prim_new(int kind, int flags)
{
    csg_prim p;
    memset(&p, 0, sizeof p);
    p.kind = kind;
    p.flags = flags;
    return p;
}

static csg_prim sphere(real cx, real cy, real cz, real radius)
{
    csg_prim p = prim_new(CSG_PRIM_SPHERE, 0);
    p.p[0] = cx;
    p.p[1] = cy;
    p.p[2] = cz;
    p.p[3] = radius;
    return p;
}

static csg_prim box(real x0, real y0, real z0, real x1, real y1, real z1)
{
    csg_prim p = prim_new(CSG_PRIM_BOX, 0);
    p.p[0] = x0;
    p.p[1] = y0;
    p.p[2] = z0;
    p.p[3] = x1;
    p.p[4] = y1;
    p.p[5] = z1;
    return p;
}

static csg_prim cone(real r0, real r1, real h, int flags)
{
    csg_prim p = prim_new(CSG_PRIM_CONE, flags);
    p.p[0] = r0;
    p.p[1] = r1;
    p.p[2] = h;
    return p;
}

static csg_prim plane(real nx, real ny, real nz, real d)
{
    csg_prim p = prim_new(CSG_PRIM_PLANE, 0);
    p.p[0] = nx;
    p.p[1] = ny;
    p.p[2] = nz;
    p.p[3] = d;
    return p;
}

/* The whole-line interval of one primitive; returns the hit flag. */
static int span(const csg_prim *p, csg_ray r, real *t0, real *t1, csg_i32 *s0, csg_i32 *s1)
{
    return csg_prim_span(p, r, t0, t1, s0, s1);
}

/* Unit outward normal at the point of ray r at parameter t. */
static vec3 normal_at(const csg_prim *p, csg_u32 surf, csg_ray r, real t)
{
    return csg_surface_normal(p, surf, v3_madd(r.o, r.d, t));
}

/* ---- vec.h ------------------------------------------------------------------- */

static void test_vec_ops(void **state)
{
    (void)state;
    vec3 a = v3(1, 2, 3), b = v3(-4, 5, 0.5);
    NEAR_V(v3_add(a, b), -3, 7, 3.5, 0);
    NEAR_V(v3_sub(a, b), 5, -3, 2.5, 0);
    NEAR_V(v3_mul(a, b), -4, 10, 1.5, 0);
    NEAR_V(v3_scale(a, R(-2.0)), -2, -4, -6, 0);
    NEAR_V(v3_neg(a), -1, -2, -3, 0);
    NEAR(v3_dot(a, b), 7.5, 0);
    /* x cross y = z: the algebraic cross product, whatever the handedness */
    NEAR_V(v3_cross(v3(1, 0, 0), v3(0, 1, 0)), 0, 0, 1, 0);
    NEAR_V(v3_cross(a, b), 2 * 0.5 - 3 * 5, 3 * -4 - 1 * 0.5, 1 * 5 - 2 * -4, 0);
    NEAR(v3_length(v3(3, 4, 12)), 13, 0);
    NEAR_V(v3_normalize(v3(0, -3, 4)), 0, -0.6, 0.8, 2 * EPS);
    /* the zero vector stays zero instead of becoming NaN */
    NEAR_V(v3_normalize(v3(0, 0, 0)), 0, 0, 0, 0);
    NEAR_V(v3_madd(a, b, R(2.0)), -7, 12, 4, 0);
    real arr[3] = {7, 8, 9};
    NEAR_V(v3_load(arr), 7, 8, 9, 0);
}

/* ---- sphere ---------------------------------------------------------------------- */

static void test_sphere_outside(void **state)
{
    (void)state;
    csg_prim s = sphere(0, 0, 5, 1);
    real t0, t1;
    csg_i32 s0, s1;
    /* through the centre: exact */
    assert_true(span(&s, ray(0, 0, 0, 0, 0, 1), &t0, &t1, &s0, &s1));
    NEAR(t0, 4, 0);
    NEAR(t1, 6, 0);
    assert_int_equal(s0, CSG_SURF_SPHERE);
    assert_int_equal(s1, CSG_SURF_SPHERE);
    /* off axis, chord half-length 0.8 */
    csg_ray r = ray(R(0.6), 0, 0, 0, 0, 1);
    assert_true(span(&s, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 4.2, 8 * EPS);
    NEAR(t1, 5.8, 8 * EPS);
    /* a direction of length 2 halves t: t is the parameter of o + t d */
    r.d = v3(0, 0, 2);
    assert_true(span(&s, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 2.1, 8 * EPS);
    NEAR(t1, 2.9, 8 * EPS);
    /* leaf list on [0, inf): one visible interval, normal outward */
    csg_spans l;
    csg_leaf_spans(&s, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    assert_int_equal(l.s0[0], CSG_SURF_PACK(0, CSG_SURF_SPHERE, 0));
    assert_int_equal(l.s1[0], CSG_SURF_PACK(0, CSG_SURF_SPHERE, 0));
    vec3 n = normal_at(&s, l.s0[0], r, l.t0[0]);
    NEAR_V(n, 0.6, 0, -0.8, 8 * EPS);
    n = normal_at(&s, l.s1[0], r, l.t1[0]);
    NEAR_V(n, 0.6, 0, 0.8, 8 * EPS);
}

static void test_sphere_inside(void **state)
{
    (void)state;
    csg_prim s = sphere(0, 0, 5, 2);
    csg_ray r = ray(0, 0, 5, 1, 0, 0);
    real t0, t1;
    csg_i32 s0, s1;
    assert_true(span(&s, r, &t0, &t1, &s0, &s1));
    NEAR(t0, -2, 0);
    NEAR(t1, 2, 0);
    /* clipped at tmin = 0: the start is no surface, the exit is */
    csg_spans l;
    csg_leaf_spans(&s, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    NEAR(l.t0[0], 0, 0);
    assert_int_equal(l.s0[0], CSG_SURF_NONE);
    NEAR(l.t1[0], 2, 0);
    csg_hit h = csg_first_boundary(&l, 0);
    NEAR(h.t, 2, 0);
    assert_int_equal(h.surf, CSG_SURF_PACK(0, 0, 0));
    NEAR_V(normal_at(&s, h.surf, r, h.t), 1, 0, 0, 0);
    /* origin not at the centre */
    r = ray(0, R(0.5), 5, 0, 1, 0);
    csg_leaf_spans(&s, 0, r, 0, CSG_R_INF, &l);
    h = csg_first_boundary(&l, 0);
    NEAR(h.t, 1.5, 0);
}

static void test_sphere_tangent_miss_behind(void **state)
{
    (void)state;
    csg_prim s = sphere(0, 0, 5, 1);
    real t0, t1;
    csg_i32 s0, s1;
    csg_spans l;
    /* tangent: a zero-length interval, which the leaf list drops */
    csg_ray r = ray(1, 0, 0, 0, 0, 1);
    if (span(&s, r, &t0, &t1, &s0, &s1)) {
        NEAR(t0, 5, 8 * EPS);
        NEAR(t1, 5, 8 * EPS);
    }
    csg_leaf_spans(&s, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 0);
    /* miss */
    assert_false(span(&s, ray(R(1.001), 0, 0, 0, 0, 1), &t0, &t1, &s0, &s1));
    assert_false(span(&s, ray(0, 0, 0, 1, 0, 0), &t0, &t1, &s0, &s1));
    /* behind the origin: the line meets it, the ray (t >= 0) does not */
    r = ray(0, 0, 10, 0, 0, 1);
    assert_true(span(&s, r, &t0, &t1, &s0, &s1));
    NEAR(t0, -6, 0);
    NEAR(t1, -4, 0);
    csg_leaf_spans(&s, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 0);
    /* a zero direction meets nothing (no NaN) */
    assert_false(span(&s, ray(0, 0, 5, 0, 0, 0), &t0, &t1, &s0, &s1));
}

/* Reference roots in long double from the same (rounded) inputs. */
static void sphere_reference(const csg_prim *s, csg_ray r, long double *t0, long double *t1)
{
    long double f[3] = {(long double)r.o.x - s->p[0], (long double)r.o.y - s->p[1],
                        (long double)r.o.z - s->p[2]};
    long double d[3] = {r.d.x, r.d.y, r.d.z};
    long double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    long double b = (f[0] * d[0] + f[1] * d[1] + f[2] * d[2]) / a;
    long double l2 = 0;
    for (int i = 0; i < 3; i++) {
        long double li = f[i] - d[i] * b;
        l2 += li * li;
    }
    long double h = sqrtl(((long double)s->p[3] * s->p[3] - l2) / a);
    *t0 = -b - h;
    *t1 = -b + h;
}

/* A small sphere far away: the textbook b^2 - ac cancels catastrophically
 * there; the Haines formulation keeps t within a few ulp. */
static void test_sphere_tiny_far(void **state)
{
    (void)state;
#ifdef CSG_DOUBLE
    const double dist = 1e6, rad = 1e-3;
#else
    const double dist = 1e3, rad = 1e-2;
#endif
    double dirs[4][3] = {{0.3, -0.5, 0.8}, {1, 0, 0}, {-0.1, 0.9, 0.2}, {0.577, 0.577, -0.577}};
    for (int k = 0; k < 4; k++) {
        double len = sqrt(dirs[k][0] * dirs[k][0] + dirs[k][1] * dirs[k][1] +
                          dirs[k][2] * dirs[k][2]);
        double c[3];
        for (int i = 0; i < 3; i++)
            c[i] = dirs[k][i] / len * dist;
        csg_prim s = sphere((real)c[0], (real)c[1], (real)c[2], (real)rad);
        /* aim at a point half a radius off the centre, sideways */
        vec3 aim = v3((real)c[0], (real)(c[1] + 0.5 * rad), (real)(c[2] - 0.3 * rad));
        csg_ray r;
        r.o = v3(R(0.25), R(-0.5), R(0.125));
        r.d = v3_normalize(v3_sub(aim, r.o));
        real t0, t1;
        csg_i32 s0, s1;
        assert_true(span(&s, r, &t0, &t1, &s0, &s1));
        long double w0, w1;
        sphere_reference(&s, r, &w0, &w1);
        assert_true(w1 > w0);
        NEAR(t0, (double)w0, 4 * EPS * dist);
        NEAR(t1, (double)w1, 4 * EPS * dist);
        /* the chord itself, a difference of two large t, to 2 % */
        NEAR(t1 - t0, (double)(w1 - w0), 0.02 * (double)(w1 - w0));
    }
}

/* A huge sphere seen from close by (a floor made of a sphere): t of the
 * near side must stay good to a few ulp of the radius, the conditioning of
 * the problem itself. */
static void test_sphere_huge(void **state)
{
    (void)state;
    const double rad = 1e6;
    csg_prim s = sphere(0, 0, (real)(rad + 10), (real)rad);
    csg_ray r = ray(3, 4, 0, 0, 0, 1);
    real t0, t1;
    csg_i32 s0, s1;
    assert_true(span(&s, r, &t0, &t1, &s0, &s1));
    long double w0, w1;
    sphere_reference(&s, r, &w0, &w1);
    NEAR(t0, (double)w0, 4 * EPS * rad);
    NEAR(t1, (double)w1, 4 * EPS * rad);
    NEAR(t0, 10 + 25 / (2 * rad), 4 * EPS * rad); /* 10 + r - sqrt(r^2 - 25) */
    csg_spans l;
    csg_leaf_spans(&s, 0, r, 0, CSG_R_INF, &l);
    csg_hit h = csg_first_boundary(&l, 0);
    vec3 n = normal_at(&s, h.surf, r, h.t);
    NEAR_V(n, 3 / rad, 4 / rad, -sqrt(rad * rad - 25) / rad, 4 * EPS);
}

/* ---- box ------------------------------------------------------------------------- */

static void test_box_faces(void **state)
{
    (void)state;
    const real ext[3] = {1, 2, 3};
    csg_prim b = box(-1, -2, -3, 1, 2, 3);
    for (int axis = 0; axis < 3; axis++) {
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            real o[3] = {R(0.25), R(-0.5), R(0.75)};
            real d[3] = {0, 0, 0};
            o[axis] = (real)(-10 * sgn);
            d[axis] = (real)sgn;
            csg_ray r = ray(o[0], o[1], o[2], d[0], d[1], d[2]);
            real t0, t1;
            csg_i32 s0, s1;
            assert_true(span(&b, r, &t0, &t1, &s0, &s1));
            NEAR(t0, 10 - ext[axis], 0);
            NEAR(t1, 10 + ext[axis], 0);
            /* moving +: enter by the - face (2 axis), leave by the + face */
            int neg = 2 * axis, pos = 2 * axis + 1;
            assert_int_equal(s0, sgn > 0 ? neg : pos);
            assert_int_equal(s1, sgn > 0 ? pos : neg);
            csg_spans l;
            csg_leaf_spans(&b, 0, r, 0, CSG_R_INF, &l);
            assert_int_equal(l.n, 1);
            vec3 n0 = normal_at(&b, l.s0[0], r, l.t0[0]);
            vec3 n1 = normal_at(&b, l.s1[0], r, l.t1[0]);
            /* the entry normal faces the ray, the exit normal goes along it */
            NEAR_V(n0, -r.d.x, -r.d.y, -r.d.z, 0);
            NEAR_V(n1, r.d.x, r.d.y, r.d.z, 0);
        }
    }
}

static void test_box_parallel_and_edges(void **state)
{
    (void)state;
    csg_prim b = box(-1, -2, -3, 1, 2, 3);
    real t0, t1;
    csg_i32 s0, s1;
    /* parallel to the y slabs: inside, on the boundary (closed), outside */
    assert_true(span(&b, ray(-5, 0, 0, 1, 0, 0), &t0, &t1, &s0, &s1));
    assert_true(span(&b, ray(-5, 2, 0, 1, 0, 0), &t0, &t1, &s0, &s1));
    NEAR(t0, 4, 0);
    NEAR(t1, 6, 0);
    assert_false(span(&b, ray(-5, R(2.5), 0, 1, 0, 0), &t0, &t1, &s0, &s1));
    assert_false(span(&b, ray(-5, R(-2.001), 0, 1, 0, 0), &t0, &t1, &s0, &s1));
    /* a negative zero direction component is still parallel */
    assert_true(span(&b, ray(-5, 0, 0, 1, R(-0.0), 0), &t0, &t1, &s0, &s1));
    assert_false(span(&b, ray(-5, 3, 0, 1, R(-0.0), 0), &t0, &t1, &s0, &s1));
    /* origin inside: entry behind, leaf clipped to a surface-less start */
    csg_ray r = ray(0, 0, 0, 0, 1, 0);
    assert_true(span(&b, r, &t0, &t1, &s0, &s1));
    NEAR(t0, -2, 0);
    NEAR(t1, 2, 0);
    assert_int_equal(s0, 2);
    assert_int_equal(s1, 3);
    csg_spans l;
    csg_leaf_spans(&b, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.s0[0], CSG_SURF_NONE);
    assert_int_equal(l.s1[0], CSG_SURF_PACK(0, 3, 0));
    /* through an edge (x = -1, y = -2) diagonally: enters at t = 1 by one
     * of the two faces of that edge */
    assert_true(span(&b, ray(-2, -3, 0, 1, 1, 0), &t0, &t1, &s0, &s1));
    NEAR(t0, 1, 0);
    assert_true(s0 == 0 || s0 == 2);
    NEAR(t1, 3, 0);
    assert_int_equal(s1, 1);
    /* grazing the same edge from outside: one point, no interval */
    assert_false(span(&b, ray(-3, 0, 0, 1, 1, 0), &t0, &t1, &s0, &s1));
    /* through a corner */
    assert_true(span(&b, ray(-2, -3, -4, 1, 1, 1), &t0, &t1, &s0, &s1));
    NEAR(t0, 1, 0);
    NEAR(t1, 3, 0);
    /* missing the box diagonally */
    assert_false(span(&b, ray(-3, 3, 0, 1, 1, 0), &t0, &t1, &s0, &s1));
}

/* ---- cone / cylinder --------------------------------------------------------------- */

static void test_cylinder(void **state)
{
    (void)state;
    csg_prim c = cone(1, 1, 2, 0);
    real t0, t1;
    csg_i32 s0, s1;
    /* side in, side out */
    csg_ray r = ray(-5, R(0.6), 1, 1, 0, 0);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 4.2, 8 * EPS);
    NEAR(t1, 5.8, 8 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_SIDE);
    assert_int_equal(s1, CSG_SURF_CONE_SIDE);
    NEAR_V(normal_at(&c, CSG_SURF_PACK(0, s0, 0), r, t0), -0.8, 0.6, 0, 8 * EPS);
    NEAR_V(normal_at(&c, CSG_SURF_PACK(0, s1, 0), r, t1), 0.8, 0.6, 0, 8 * EPS);
    /* along the axis: base cap in, top cap out, whatever the radius test */
    r = ray(R(0.5), 0, -3, 0, 0, 1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 3, 0);
    NEAR(t1, 5, 0);
    assert_int_equal(s0, CSG_SURF_CONE_BASE);
    assert_int_equal(s1, CSG_SURF_CONE_TOP);
    NEAR_V(normal_at(&c, CSG_SURF_PACK(0, s0, 0), r, t0), 0, 0, -1, 0);
    NEAR_V(normal_at(&c, CSG_SURF_PACK(0, s1, 0), r, t1), 0, 0, 1, 0);
    /* downwards: top cap in */
    r = ray(0, 0, 7, 0, 0, -1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 5, 0);
    NEAR(t1, 7, 0);
    assert_int_equal(s0, CSG_SURF_CONE_TOP);
    assert_int_equal(s1, CSG_SURF_CONE_BASE);
    /* parallel to the axis, outside the radius: miss */
    assert_false(span(&c, ray(R(1.5), 0, -3, 0, 0, 1), &t0, &t1, &s0, &s1));
    /* horizontal above / below the slab: miss */
    assert_false(span(&c, ray(-5, 0, R(2.5), 1, 0, 0), &t0, &t1, &s0, &s1));
    assert_false(span(&c, ray(-5, 0, R(-0.5), 1, 0, 0), &t0, &t1, &s0, &s1));
    /* oblique: in by the base, out by the side */
    r = ray(0, 0, -1, R(0.5), 0, 1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 1, 0);
    NEAR(t1, 2, 4 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_BASE);
    assert_int_equal(s1, CSG_SURF_CONE_SIDE);
}

static void test_cylinder_open(void **state)
{
    (void)state;
    csg_prim c = cone(1, 1, 2, CSG_PF_OPEN);
    csg_spans l;
    /* along the axis: the interval is there (it is still a solid for CSG)
     * but neither cap is a visible surface */
    csg_ray r = ray(R(0.5), 0, -3, 0, 0, 1);
    csg_leaf_spans(&c, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    NEAR(l.t0[0], 3, 0);
    NEAR(l.t1[0], 5, 0);
    assert_int_equal(l.s0[0], CSG_SURF_NONE);
    assert_int_equal(l.s1[0], CSG_SURF_NONE);
    assert_int_equal(csg_first_boundary(&l, 0).surf, CSG_SURF_NONE);
    /* in through the open base, out through the side: the inner wall */
    r = ray(0, 0, -1, R(0.5), 0, 1);
    csg_leaf_spans(&c, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    assert_int_equal(l.s0[0], CSG_SURF_NONE);
    assert_int_equal(l.s1[0], CSG_SURF_PACK(0, CSG_SURF_CONE_SIDE, 0));
    csg_hit h = csg_first_boundary(&l, 0);
    NEAR(h.t, 2, 4 * EPS);
    NEAR_V(normal_at(&c, h.surf, r, h.t), 1, 0, 0, 4 * EPS);
    /* the side is visible from outside too */
    r = ray(-5, 0, 1, 1, 0, 0);
    csg_leaf_spans(&c, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.s0[0], CSG_SURF_PACK(0, CSG_SURF_CONE_SIDE, 0));
    /* inverted open cylinder: the cap ends stay invisible */
    c.flags |= CSG_PF_INVERT;
    r = ray(R(0.5), 0, -3, 0, 0, 1);
    csg_leaf_spans(&c, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 2);
    assert_int_equal(l.s1[0], CSG_SURF_NONE);
    assert_int_equal(l.s0[1], CSG_SURF_NONE);
}

static void test_cone_frustum(void **state)
{
    (void)state;
    csg_prim c = cone(2, 1, 2, 0); /* r(z) = 2 - z/2 */
    real t0, t1;
    csg_i32 s0, s1;
    /* horizontal at z = 1: radius 1.5 */
    csg_ray r = ray(-5, 0, 1, 1, 0, 0);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 3.5, 8 * EPS);
    NEAR(t1, 6.5, 8 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_SIDE);
    /* the side leans in going up: the outward normal leans up, (-2, 0, 1)/sqrt 5 */
    vec3 n = normal_at(&c, CSG_SURF_PACK(0, s0, 0), r, t0);
    NEAR_V(n, -2 / sqrt(5.0), 0, 1 / sqrt(5.0), 8 * EPS);
    n = normal_at(&c, CSG_SURF_PACK(0, s1, 0), r, t1);
    NEAR_V(n, 2 / sqrt(5.0), 0, 1 / sqrt(5.0), 8 * EPS);
    /* along the axis: caps, both ways (here a < 0, the quadratic has no
     * root or a double one at the apex z = 4, outside the slab) */
    r = ray(0, 0, -1, 0, 0, 1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 1, 0);
    NEAR(t1, 3, 0);
    assert_int_equal(s0, CSG_SURF_CONE_BASE);
    assert_int_equal(s1, CSG_SURF_CONE_TOP);
    r = ray(R(0.25), R(0.5), 10, 0, 0, -1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 8, 0);
    NEAR(t1, 10, 0);
    assert_int_equal(s0, CSG_SURF_CONE_TOP);
    assert_int_equal(s1, CSG_SURF_CONE_BASE);
    /* vertical, between the top radius and the base radius: in by the
     * base, out by the side at r(z) = 1.5, z = 1 */
    r = ray(R(1.5), 0, -1, 0, 0, 1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 1, 0);
    NEAR(t1, 2, 8 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_BASE);
    assert_int_equal(s1, CSG_SURF_CONE_SIDE);
    /* vertical, outside the base radius but inside the mirrored nappe
     * (z > 4): miss */
    assert_false(span(&c, ray(R(2.5), 0, -1, 0, 0, 1), &t0, &t1, &s0, &s1));
    /* steep rays (a < 0) crossing both nappes of the double cone: only the
     * frustum's piece counts.  Through the apex (0, 0, 4): */
    r = ray(R(-0.5), 0, 2, R(0.25), 0, 1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, -2, 8 * EPS);
    NEAR(t1, 0, 8 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_BASE);
    assert_int_equal(s1, CSG_SURF_CONE_TOP);
    /* beside the apex: the quadratic's set is (-inf, 5/3] u [3, inf) */
    r = ray(R(-0.25), 0, 2, R(0.25), 0, 1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, -2, 8 * EPS);
    NEAR(t1, 0, 8 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_BASE);
    assert_int_equal(s1, CSG_SURF_CONE_TOP);
    /* the same line run backwards: the frustum is the later piece */
    r = ray(R(0.75), 0, 6, R(-0.25), 0, -1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 4, 8 * EPS);
    NEAR(t1, 6, 8 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_TOP);
    assert_int_equal(s1, CSG_SURF_CONE_BASE);
    /* along a generator of the side (a == 0) from rim to rim */
    r = ray(-1, 0, 2, R(0.5), 0, 1);
    if (span(&c, r, &t0, &t1, &s0, &s1) && t0 < t1) {
        NEAR(t0, -2, 8 * EPS);
        NEAR(t1, 0, 8 * EPS);
    }
}

static void test_cone_apex(void **state)
{
    (void)state;
    csg_prim c = cone(1, 0, 1, 0); /* apex at (0, 0, 1): |x| <= 1 - z */
    real t0, t1;
    csg_i32 s0, s1;
    /* parallel to the side (a == 0, b < 0): side in at t = 0.25 */
    csg_ray r = ray(R(-0.5), 0, 1, 1, 0, -1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 0.25, 4 * EPS);
    NEAR(t1, 1, 0);
    assert_int_equal(s0, CSG_SURF_CONE_SIDE);
    assert_int_equal(s1, CSG_SURF_CONE_BASE);
    NEAR_V(normal_at(&c, CSG_SURF_PACK(0, s0, 0), r, t0), -1 / sqrt(2.0), 0, 1 / sqrt(2.0),
           8 * EPS);
    /* parallel to the side the other way (a == 0, b > 0) */
    r = ray(R(0.5), 0, 0, -1, 0, 1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 0, 0);
    NEAR(t1, 0.75, 4 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_BASE);
    assert_int_equal(s1, CSG_SURF_CONE_SIDE);
    /* parallel to the side, outside the cone: miss */
    assert_false(span(&c, ray(R(1.5), 0, 0, -1, 0, 1), &t0, &t1, &s0, &s1));
    /* along the axis to the apex */
    r = ray(0, 0, -1, 0, 0, 1);
    assert_true(span(&c, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 1, 0);
    NEAR(t1, 2, 0);
    assert_int_equal(s0, CSG_SURF_CONE_BASE);
    /* the apex at the base: r0 = 0, r1 = 2, h = 2 (|x| <= z) */
    csg_prim v = cone(0, 2, 2, 0);
    r = ray(-5, 0, 1, 1, 0, 0);
    assert_true(span(&v, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 4, 4 * EPS);
    NEAR(t1, 6, 4 * EPS);
    NEAR_V(normal_at(&v, CSG_SURF_PACK(0, s0, 0), r, t0), -1 / sqrt(2.0), 0, -1 / sqrt(2.0),
           8 * EPS);
    /* from above, down the axis: top cap in, exit at the apex */
    r = ray(0, 0, 3, 0, 0, -1);
    assert_true(span(&v, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 1, 0);
    NEAR(t1, 3, 4 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_TOP);
}

/* Side roots of a cone in long double, solved from the ray's closest
 * approach to the axis (so the reference itself does not cancel). */
static void cone_reference(const csg_prim *c, csg_ray r, long double *t0, long double *t1)
{
    long double d[3] = {r.d.x, r.d.y, r.d.z};
    long double dxy = d[0] * d[0] + d[1] * d[1];
    long double tc = -((long double)r.o.x * d[0] + (long double)r.o.y * d[1]) / dxy;
    long double o[3] = {r.o.x + tc * d[0], r.o.y + tc * d[1], r.o.z + tc * d[2]};
    long double k = ((long double)c->p[1] - c->p[0]) / c->p[2];
    long double rz = c->p[0] + k * o[2];
    long double a = dxy - k * k * d[2] * d[2];
    long double b = o[0] * d[0] + o[1] * d[1] - k * rz * d[2];
    long double cc = o[0] * o[0] + o[1] * o[1] - rz * rz;
    long double root = sqrtl(b * b - a * cc);
    *t0 = tc + (-b - root) / a;
    *t1 = tc + (-b + root) / a;
}

/* A thin cylinder (and cone) far away: the side's quadratic solved from
 * the far origin lost everything to cancellation in float (radius 0.01 at
 * distance 100 was missed, radius 0.1 had a 40 % chord error); solved
 * from the closest approach it is good to an ulp or so of t. */
static void test_cone_thin_far(void **state)
{
    (void)state;
#ifdef CSG_DOUBLE
    const double dist = 1e6, rad = 1e-3;
#else
    const double dist = 1e3, rad = 1e-2;
#endif
    csg_prim shapes[2] = {cone((real)rad, (real)rad, 2, 0), cone((real)rad, (real)(rad / 2), 2, 0)};
    for (int i = 0; i < 2; i++) {
        for (int k = 0; k < 21; k++) {
            double off = rad * (-0.7 + 1.4 * k / 20.0); /* r(0.75) >= 0.8 rad */
            csg_ray r;
            r.o = v3((real)-dist, (real)(0.3 * off), R(0.75));
            r.d = v3_normalize(v3((real)dist, (real)(0.7 * off), (real)(1e-4 * dist * EPS)));
            real t0, t1;
            csg_i32 s0, s1;
            assert_true(span(&shapes[i], r, &t0, &t1, &s0, &s1));
            assert_int_equal(s0, CSG_SURF_CONE_SIDE);
            assert_int_equal(s1, CSG_SURF_CONE_SIDE);
            long double w0, w1;
            cone_reference(&shapes[i], r, &w0, &w1);
            NEAR(t0, (double)w0, 4 * EPS * dist);
            NEAR(t1, (double)w1, 4 * EPS * dist);
            NEAR(t1 - t0, (double)(w1 - w0), 0.02 * (double)(w1 - w0));
        }
    }
    /* from far away along a steep line (down the axis, slightly tilted):
     * the caps, at their exact heights */
    csg_ray r;
    r.o = v3(R(0.25) * (real)rad, 0, (real)dist);
    r.d = v3_normalize(v3((real)(-0.1 * rad / dist), 0, -1));
    real t0, t1;
    csg_i32 s0, s1;
    assert_true(span(&shapes[0], r, &t0, &t1, &s0, &s1));
    assert_int_equal(s0, CSG_SURF_CONE_TOP);
    assert_int_equal(s1, CSG_SURF_CONE_BASE);
    NEAR(t0, dist - 2, 4 * EPS * dist);
    NEAR(t1, dist, 4 * EPS * dist);
}

/* ---- a sampled cross-check of every primitive ------------------------------------
 * Many deterministic pseudo-random rays; points just inside the reported
 * interval must be inside the solid and points just outside it outside
 * (tested in long double), and a reported miss must have no inside sample. */

static uint32_t lcg_next(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static double lcg_unit(uint32_t *s) /* [-1, 1) */
{
    return (double)lcg_next(s) / 8388608.0 - 1.0;
}

static int inside_ld(const csg_prim *p, long double x, long double y, long double z)
{
    const long double e = 1e-9L;
    switch (p->kind) {
    case CSG_PRIM_SPHERE: {
        long double dx = x - p->p[0], dy = y - p->p[1], dz = z - p->p[2];
        return dx * dx + dy * dy + dz * dz < (long double)p->p[3] * p->p[3];
    }
    case CSG_PRIM_BOX:
        return x > p->p[0] && x < p->p[3] && y > p->p[1] && y < p->p[4] && z > p->p[2] &&
               z < p->p[5];
    case CSG_PRIM_CONE: {
        long double h = p->p[2];
        long double rz = p->p[0] + ((long double)p->p[1] - p->p[0]) * z / h;
        return z > e && z < h - e && rz > 0 && sqrtl(x * x + y * y) < rz - e;
    }
    default:
        return x * p->p[0] + y * p->p[1] + z * p->p[2] < p->p[3];
    }
}

static void check_sampled(const csg_prim *p, csg_ray r)
{
    real t0, t1;
    csg_i32 s0, s1;
    int hit = span(p, r, &t0, &t1, &s0, &s1) && t0 < t1;
    long double o[3] = {r.o.x, r.o.y, r.o.z}, d[3] = {r.d.x, r.d.y, r.d.z};
    /* samples on [-20, 20] with a margin around the reported ends */
    const double margin = 1e-3;
    for (int k = 0; k <= 400; k++) {
        double t = -20 + 0.1 * k;
        long double x = o[0] + d[0] * t, y = o[1] + d[1] * t, z = o[2] + d[2] * t;
        int in = inside_ld(p, x, y, z);
        if (hit && t > (double)t0 + margin && t < (double)t1 - margin && !in) {
            print_error("kind %d: t = %g in [%g, %g] but outside\n", p->kind, t, (double)t0,
                        (double)t1);
            fail();
        }
        if (in && !(hit && t >= (double)t0 - margin && t <= (double)t1 + margin)) {
            print_error("kind %d: t = %g inside but not in [%g, %g] (hit %d)\n", p->kind, t,
                        (double)t0, (double)t1, hit);
            fail();
        }
    }
}

static void test_prims_sampled(void **state)
{
    (void)state;
    csg_prim prims[6] = {sphere(R(0.5), R(-0.25), 1, 2), box(-1, -2, R(-0.5), 2, 1, 3),
                         cone(2, 1, 3, 0), cone(R(0.5), R(2.5), 2, 0), cone(1, 0, 2, 0),
                         plane(R(0.6), 0, R(0.8), R(0.5))};
    uint32_t seed = 12345;
    for (int n = 0; n < 400; n++) {
        csg_ray r;
        r.o = v3((real)(4 * lcg_unit(&seed)), (real)(4 * lcg_unit(&seed)),
                 (real)(4 * lcg_unit(&seed)));
        r.d = v3_normalize(v3((real)lcg_unit(&seed), (real)lcg_unit(&seed),
                              (real)lcg_unit(&seed)));
        if (n % 4 == 0) /* steep rays through the cones' nappes */
            r.d = v3_normalize(v3(r.d.x * R(0.2), r.d.y * R(0.2), R(1.0)));
        for (int i = 0; i < 6; i++)
            check_sampled(&prims[i], r);
    }
}

/* ---- plane ------------------------------------------------------------------------ */

static void test_plane(void **state)
{
    (void)state;
    csg_prim p = plane(0, 1, 0, 1); /* inside: y < 1 */
    real t0, t1;
    csg_i32 s0, s1;
    csg_spans l;
    /* from inside, upwards: leave at t = 1 */
    csg_ray r = ray(0, 0, 0, 0, 1, 0);
    assert_true(span(&p, r, &t0, &t1, &s0, &s1));
    assert_true(isinf(t0) && t0 < 0);
    NEAR(t1, 1, 0);
    assert_int_equal(s0, -1);
    assert_int_equal(s1, CSG_SURF_PLANE);
    csg_leaf_spans(&p, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    assert_int_equal(l.s0[0], CSG_SURF_NONE);
    NEAR(csg_first_boundary(&l, 0).t, 1, 0);
    /* from outside, downwards: enter at t = 2, normal +y */
    r = ray(0, 3, 0, 0, -1, 0);
    assert_true(span(&p, r, &t0, &t1, &s0, &s1));
    NEAR(t0, 2, 0);
    assert_true(isinf(t1) && t1 > 0);
    csg_leaf_spans(&p, 0, r, 0, CSG_R_INF, &l);
    csg_hit h = csg_first_boundary(&l, 0);
    NEAR(h.t, 2, 0);
    NEAR_V(normal_at(&p, h.surf, r, h.t), 0, 1, 0, 0);
    /* from outside, upwards: the half-space is behind */
    csg_leaf_spans(&p, 0, ray(0, 3, 0, 0, 1, 0), 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 0);
    /* parallel, inside and outside; the plane itself is outside (strict) */
    assert_true(span(&p, ray(0, 0, 0, 1, 0, 0), &t0, &t1, &s0, &s1));
    assert_true(isinf(t0) && isinf(t1));
    assert_false(span(&p, ray(0, 2, 0, 1, 0, 0), &t0, &t1, &s0, &s1));
    assert_false(span(&p, ray(0, 1, 0, 1, 0, 0), &t0, &t1, &s0, &s1));
    /* oblique normal, distance 2: n = (0.6, 0.8, 0) */
    p = plane(R(0.6), R(0.8), 0, 2);
    r = ray(0, 0, 0, 1, 0, 0);
    assert_true(span(&p, r, &t0, &t1, &s0, &s1));
    NEAR(t1, 2 / 0.6, 4 * EPS * 4);
}

/* ---- CSG_PF_XFORM ---------------------------------------------------------------------- */

/* Builds object -> world with scene.c and stores its inverse in p->inv. */
static void set_xform(csg_prim *p, const csg_xform *fwd)
{
    csg_xform inv;
    assert_true(csg_xform_invert(fwd, &inv));
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            p->inv[4 * i + j] = (real)inv.m[i][j];
    p->flags |= CSG_PF_XFORM;
}

static vec3 fwd_point(const csg_xform *x, double px, double py, double pz)
{
    double q[3];
    for (int i = 0; i < 3; i++)
        q[i] = x->m[i][0] * px + x->m[i][1] * py + x->m[i][2] * pz + x->m[i][3];
    return v3((real)q[0], (real)q[1], (real)q[2]);
}

static vec3 fwd_vector(const csg_xform *x, double px, double py, double pz)
{
    double q[3];
    for (int i = 0; i < 3; i++)
        q[i] = x->m[i][0] * px + x->m[i][1] * py + x->m[i][2] * pz;
    return v3((real)q[0], (real)q[1], (real)q[2]);
}

/* A unit sphere scaled <2, 1, 0.5>, rotated 90 about z, moved <1, 2, 3>:
 * the world ray that is the image of a local ray has the same t, and the
 * normal is the inverse transpose one (not the forward-transformed one). */
static void test_xform_sphere(void **state)
{
    (void)state;
    csg_xform m;
    csg_xform_identity(&m);
    csg_xform_scale(&m, (dvec3){2, 1, 0.5});
    csg_xform_rotate(&m, (dvec3){0, 0, 90});
    csg_xform_translate(&m, (dvec3){1, 2, 3});
    csg_prim s = sphere(0, 0, 0, 1);
    set_xform(&s, &m);
    /* local ray (0.6, 0, -5) + t (0, 0, 1): t = 4.2 and 5.8 */
    csg_ray w;
    w.o = fwd_point(&m, 0.6, 0, -5);
    w.d = fwd_vector(&m, 0, 0, 1);
    real t0, t1;
    csg_i32 s0, s1;
    assert_true(span(&s, w, &t0, &t1, &s0, &s1));
    NEAR(t0, 4.2, 32 * EPS);
    NEAR(t1, 5.8, 32 * EPS);
    /* local hit (0.6, 0, -0.8): local normal (0.6, 0, -0.8); world normal
     * = R S^-1 n = R (0.3, 0, -1.6) = (0, 0.3, -1.6) (rotate z 90: x -> y) */
    csg_spans l;
    csg_leaf_spans(&s, 0, w, 0, CSG_R_INF, &l);
    csg_hit h = csg_first_boundary(&l, 0);
    NEAR(h.t, 4.2, 32 * EPS);
    vec3 n = normal_at(&s, h.surf, w, h.t);
    double len = sqrt(0.3 * 0.3 + 1.6 * 1.6);
    NEAR_V(n, 0, 0.3 / len, -1.6 / len, 32 * EPS);
    /* the world hit point is the image of the local one */
    vec3 wp = v3_madd(w.o, w.d, h.t);
    vec3 want = fwd_point(&m, 0.6, 0, -0.8);
    NEAR_V(wp, want.x, want.y, want.z, 64 * EPS);
    /* a world-space ray written directly: along -y from far: the ellipsoid
     * spans world y in [2 - 2, 2 + 2] at x = 1, z = 3 */
    w = ray(1, 10, 3, 0, -1, 0);
    assert_true(span(&s, w, &t0, &t1, &s0, &s1));
    NEAR(t0, 6, 32 * EPS);
    NEAR(t1, 10, 32 * EPS);
    /* and along z: half-axis 0.5 */
    w = ray(1, 2, -10, 0, 0, 1);
    assert_true(span(&s, w, &t0, &t1, &s0, &s1));
    NEAR(t0, 12.5, 64 * EPS);
    NEAR(t1, 13.5, 64 * EPS);
}

static void test_xform_box_cone(void **state)
{
    (void)state;
    /* box [0,1]^3 scaled 3 along x, rotated -90 about y (POV-Ray: x -> +z),
     * moved up 1: occupies x in [-1, 0], y in [1, 2], z in [0, 3] */
    csg_xform m;
    csg_xform_identity(&m);
    csg_xform_scale(&m, (dvec3){3, 1, 1});
    csg_xform_rotate(&m, (dvec3){0, -90, 0});
    csg_xform_translate(&m, (dvec3){0, 1, 0});
    csg_prim b = box(0, 0, 0, 1, 1, 1);
    set_xform(&b, &m);
    real t0, t1;
    csg_i32 s0, s1;
    csg_ray w = ray(R(-0.5), R(1.5), -5, 0, 0, 1);
    assert_true(span(&b, w, &t0, &t1, &s0, &s1));
    NEAR(t0, 5, 16 * EPS);
    NEAR(t1, 8, 16 * EPS);
    /* world -z face is the local -x face (sub 0) */
    assert_int_equal(s0, 0);
    assert_int_equal(s1, 1);
    NEAR_V(normal_at(&b, CSG_SURF_PACK(0, s0, 0), w, t0), 0, 0, -1, 16 * EPS);
    w = ray(-5, R(1.5), 1, 1, 0, 0);
    assert_true(span(&b, w, &t0, &t1, &s0, &s1));
    NEAR(t0, 4, 16 * EPS);
    NEAR(t1, 5, 16 * EPS);
    /* at x = +0.5 it misses: a sign error in the rotation would hit */
    assert_false(span(&b, ray(R(0.5), R(1.5), -5, 0, 0, 1), &t0, &t1, &s0, &s1));
    /* a cylinder from (0,0,0) to (0,4,0), radius 1, as the flattener would
     * put it: local z mapped to world y by rotate <-90, 0, 0>, then
     * scaled non-uniformly in x (an elliptic cylinder) */
    csg_prim c = cone(1, 1, 4, 0);
    csg_xform_identity(&m);
    csg_xform_rotate(&m, (dvec3){-90, 0, 0});
    csg_xform_scale(&m, (dvec3){2, 1, 1});
    set_xform(&c, &m);
    w = ray(-10, 1, 0, 1, 0, 0);
    assert_true(span(&c, w, &t0, &t1, &s0, &s1));
    NEAR(t0, 8, 16 * EPS);
    NEAR(t1, 12, 16 * EPS);
    /* oblique point on the elliptic side: local (cos a, sin a) at height 1;
     * world (2 cos a, 1, -sin a); the normal is (cos a / 2, 0, -sin a) */
    double a = 0.7;
    vec3 lp = fwd_point(&m, cos(a), sin(a), 1);
    NEAR(lp.y, 1, 4 * EPS);
    vec3 n = csg_surface_normal(&c, CSG_SURF_PACK(0, CSG_SURF_CONE_SIDE, 0), lp);
    double nx = cos(a) / 2, nz = -sin(a), nl = sqrt(nx * nx + nz * nz);
    NEAR_V(n, nx / nl, 0, nz / nl, 16 * EPS);
    /* the caps: base at world y = 0 faces -y, top at y = 4 faces +y */
    w = ray(R(0.5), -3, 0, 0, 1, 0);
    assert_true(span(&c, w, &t0, &t1, &s0, &s1));
    NEAR(t0, 3, 16 * EPS);
    NEAR(t1, 7, 16 * EPS);
    assert_int_equal(s0, CSG_SURF_CONE_BASE);
    NEAR_V(normal_at(&c, CSG_SURF_PACK(0, s0, 0), w, t0), 0, -1, 0, 16 * EPS);
    NEAR_V(normal_at(&c, CSG_SURF_PACK(0, s1, 0), w, t1), 0, 1, 0, 16 * EPS);
}

/* Flipped surfaces reverse the normal. */
static void test_normal_flip(void **state)
{
    (void)state;
    csg_prim s = sphere(0, 0, 0, 2);
    vec3 n = csg_surface_normal(&s, CSG_SURF_PACK(0, 0, 1), v3(0, 2, 0));
    NEAR_V(n, 0, -1, 0, 0);
    n = csg_surface_normal(&s, CSG_SURF_PACK(0, 0, 0), v3(0, 2, 0));
    NEAR_V(n, 0, 1, 0, 0);
}

/* ---- surface ids ---------------------------------------------------------------------- */

static void test_surface_pack(void **state)
{
    (void)state;
    csg_u32 s = CSG_SURF_PACK(12345, 5, 1);
    assert_int_not_equal(s, CSG_SURF_NONE);
    assert_int_equal(CSG_SURF_PRIM(s), 12345);
    assert_int_equal(CSG_SURF_SUB(s), 5);
    assert_int_equal(CSG_SURF_FLIP(s), 1);
    s = CSG_SURF_PACK(0, 0, 0);
    assert_int_not_equal(s, CSG_SURF_NONE);
    assert_int_equal(CSG_SURF_PRIM(s), 0);
    s = CSG_SURF_PACK(CSG_MAX_PRIMS - 1, 2, 0);
    assert_int_equal(CSG_SURF_PRIM(s), CSG_MAX_PRIMS - 1);
    assert_int_equal(CSG_SURF_SUB(s), 2);
    assert_int_equal(CSG_SURF_FLIP(s), 0);
}

/* ---- camera ------------------------------------------------------------------------------ */

static csg_camera camera(void)
{
    csg_camera c = {0}; /* no hither; every field set */
    c.projection = CSG_CAMERA_PERSPECTIVE;
    real loc[3] = {1, 2, 3}, dir[3] = {0, 0, 1}, right[3] = {R(1.33), 0, 0}, up[3] = {0, 1, 0};
    for (int i = 0; i < 3; i++) {
        c.location[i] = loc[i];
        c.direction[i] = dir[i];
        c.right[i] = right[i];
        c.up[i] = up[i];
    }
    c.hither = 0; /* rays start at location (was left unset: ASan runs read garbage) */
    return c;
}

static void expect_primary(const csg_camera *c, int w, int h, int x, int y)
{
    double x0 = (x + 0.5) / w - 0.5, y0 = 0.5 - (y + 0.5) / h;
    double d[3], len = 0;
    for (int i = 0; i < 3; i++) {
        d[i] = (double)c->direction[i] + x0 * (double)c->right[i] + y0 * (double)c->up[i];
        len += d[i] * d[i];
    }
    len = sqrt(len);
    csg_ray r = csg_primary_ray(c, w, h, x, y);
    NEAR_V(r.o, (double)c->location[0], (double)c->location[1], (double)c->location[2], 0);
    NEAR_V(r.d, d[0] / len, d[1] / len, d[2] / len, 8 * EPS);
    NEAR(v3_length(r.d), 1, 4 * EPS);
}

static void test_camera_primary(void **state)
{
    (void)state;
    csg_camera c = camera();
    /* odd image: the centre pixel looks straight down `direction` */
    csg_ray r = csg_primary_ray(&c, 5, 3, 2, 1);
    NEAR_V(r.d, 0, 0, 1, 0);
    NEAR_V(r.o, 1, 2, 3, 0);
    /* the top-left pixel looks left (-x) and up (+y): y runs down the image */
    r = csg_primary_ray(&c, 5, 3, 0, 0);
    assert_true(r.d.x < 0);
    assert_true(r.d.y > 0);
    r = csg_primary_ray(&c, 5, 3, 4, 2);
    assert_true(r.d.x > 0);
    assert_true(r.d.y < 0);
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 5; x++)
            expect_primary(&c, 5, 3, x, y);
    /* symmetric pixels of an even image mirror each other exactly */
    csg_ray a = csg_primary_ray(&c, 64, 32, 0, 0), b = csg_primary_ray(&c, 64, 32, 63, 31);
    NEAR(a.d.x, -(double)b.d.x, 0);
    NEAR(a.d.y, -(double)b.d.y, 0);
    NEAR(a.d.z, (double)b.d.z, 0);
    /* a right-handed camera (right -x), long direction, tilted up vector */
    c.right[0] = R(-1.33);
    c.direction[2] = 2;
    c.up[1] = R(0.8);
    c.up[2] = R(0.6);
    r = csg_primary_ray(&c, 5, 3, 0, 0);
    assert_true(r.d.x > 0);
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 5; x++)
            expect_primary(&c, 5, 3, x, y);
    expect_primary(&c, 640, 480, 17, 401);
}

#ifdef CSG_DOUBLE
#define TRIG_TOL 4e-16 /* per unit of max(1, |a|): the reduction's error grows with a */
#define RAY_TOL 1e-12
#else
#define TRIG_TOL 2.5e-7
#define RAY_TOL 4e-6
#endif

/* csg_sincos (+ - * floor only, the same bits in OpenCL) against libm,
 * over several turns both ways, and exact at 0. */
static void test_sincos(void **state)
{
    (void)state;
    double worst = 0;
    for (int i = -20000; i <= 20000; i++) {
        real a = (real)(i * 0.001);
        real s, c;
        csg_sincos(a, &s, &c);
        double tol = TRIG_TOL * fmax(1.0, fabs((double)a));
        NEAR(s, sin((double)a), tol);
        NEAR(c, cos((double)a), tol);
        worst = fmax(worst, fabs((double)s - sin((double)a)) / fmax(1.0, fabs((double)a)));
    }
    real s, c;
    csg_sincos(0, &s, &c);
    assert_true(s == 0 && c == 1);
    print_message("csg_sincos: worst error %.3g (per unit of |a| beyond 1)\n", worst);
}

/* One ray of POV-Ray's CreateCameraRay for the bent cameras, in double with
 * libm, from the blob's camera (unit vectors, kx and ky as flatten.c sets
 * them): the reference the shared code is held to. */
static void pov_bent_ray(const csg_camera *c, double x0, double y0, double o[3], double d[3])
{
    double R3[3], U[3], D[3], ax = x0 * (double)c->kx, ay = y0 * (double)c->ky, v1[3];
    for (int i = 0; i < 3; i++) {
        R3[i] = c->right[i];
        U[i] = c->up[i];
        D[i] = c->direction[i];
        o[i] = c->location[i];
    }
    for (int i = 0; i < 3; i++) {
        switch (c->projection) {
        case CSG_CAMERA_CYLINDER_1: d[i] = sin(ax) * R3[i] + ay * U[i] + cos(ax) * D[i]; break;
        case CSG_CAMERA_CYLINDER_2: d[i] = ax * R3[i] + sin(ay) * U[i] + cos(ay) * D[i]; break;
        case CSG_CAMERA_CYLINDER_3:
            d[i] = sin(ax) * R3[i] + cos(ax) * D[i];
            o[i] += ay * U[i];
            break;
        case CSG_CAMERA_CYLINDER_4:
            d[i] = sin(ay) * U[i] + cos(ay) * D[i];
            o[i] += ax * R3[i];
            break;
        case CSG_CAMERA_ULTRA_WIDE_ANGLE:
            d[i] = sin(ax) * R3[i] + sin(ay) * U[i] + cos(ax) * cos(ay) * D[i];
            break;
        case CSG_CAMERA_PANORAMIC: {
            double px = (1.0 - (x0 + 0.5)) * M_PI;
            d[i] = cos(px) * R3[i] + tan(ay) * U[i] + sin(px) * D[i];
            break;
        }
        default: break;
        }
    }
    if (c->projection == CSG_CAMERA_SPHERICAL) { /* Rodrigues' formula, about right then up */
        double a1 = -ay, a2 = ax, k1[3] = {R3[0], R3[1], R3[2]}, k2[3] = {U[0], U[1], U[2]};
        double kd = k1[0] * D[0] + k1[1] * D[1] + k1[2] * D[2];
        double kx[3] = {k1[1] * D[2] - k1[2] * D[1], k1[2] * D[0] - k1[0] * D[2],
                        k1[0] * D[1] - k1[1] * D[0]};
        for (int i = 0; i < 3; i++) /* (POV-Ray's row-vector matrix: a turn by +angle) */
            v1[i] = D[i] * cos(a1) + kx[i] * sin(a1) + k1[i] * kd * (1 - cos(a1));
        kd = k2[0] * v1[0] + k2[1] * v1[1] + k2[2] * v1[2];
        double kv[3] = {k2[1] * v1[2] - k2[2] * v1[1], k2[2] * v1[0] - k2[0] * v1[2],
                        k2[0] * v1[1] - k2[1] * v1[0]};
        for (int i = 0; i < 3; i++)
            d[i] = v1[i] * cos(a2) + kv[i] * sin(a2) + k2[i] * kd * (1 - cos(a2));
    }
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int i = 0; i < 3; i++)
        d[i] /= len;
}

/* Every bent camera's rays, at the corners, centre and a sweep of an odd
 * image, against pov_bent_ray; an oblique frame (unit vectors). */
static void test_bent_cameras(void **state)
{
    (void)state;
    static const int types[] = {CSG_CAMERA_CYLINDER_1,       CSG_CAMERA_CYLINDER_2,
                                CSG_CAMERA_CYLINDER_3,       CSG_CAMERA_CYLINDER_4,
                                CSG_CAMERA_ULTRA_WIDE_ANGLE, CSG_CAMERA_PANORAMIC,
                                CSG_CAMERA_SPHERICAL};
    double s = sqrt(0.5);
    real dir[3] = {(real)s, 0, (real)s}, right[3] = {(real)s, 0, (real)-s}, up[3] = {0, 1, 0};
    for (size_t t = 0; t < sizeof types / sizeof types[0]; t++) {
        csg_camera c = camera();
        c.projection = types[t];
        for (int i = 0; i < 3; i++) {
            c.direction[i] = dir[i];
            c.right[i] = right[i];
            c.up[i] = up[i];
        }
        c.kx = types[t] == CSG_CAMERA_CYLINDER_2 || types[t] == CSG_CAMERA_CYLINDER_4 ? R(1.5) : R(2.9);
        c.ky = types[t] == CSG_CAMERA_CYLINDER_1 || types[t] == CSG_CAMERA_CYLINDER_3 ? R(0.75) : R(2.1);
        if (types[t] == CSG_CAMERA_PANORAMIC)
            c.kx = c.ky = (real)M_PI;
        for (int y = 0; y < 31; y += 3)
            for (int x = 0; x < 41; x += 4) {
                csg_ray r = csg_primary_ray(&c, 41, 31, x, y);
                double o[3], d[3];
                pov_bent_ray(&c, (x + 0.5) / 41 - 0.5, 0.5 - (y + 0.5) / 31, o, d);
                NEAR_V(r.d, d[0], d[1], d[2], RAY_TOL);
                NEAR_V(r.o, o[0], o[1], o[2], RAY_TOL * 4);
            }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vec_ops),
        cmocka_unit_test(test_sphere_outside),
        cmocka_unit_test(test_sphere_inside),
        cmocka_unit_test(test_sphere_tangent_miss_behind),
        cmocka_unit_test(test_sphere_tiny_far),
        cmocka_unit_test(test_sphere_huge),
        cmocka_unit_test(test_box_faces),
        cmocka_unit_test(test_box_parallel_and_edges),
        cmocka_unit_test(test_cylinder),
        cmocka_unit_test(test_cylinder_open),
        cmocka_unit_test(test_cone_frustum),
        cmocka_unit_test(test_cone_apex),
        cmocka_unit_test(test_cone_thin_far),
        cmocka_unit_test(test_prims_sampled),
        cmocka_unit_test(test_plane),
        cmocka_unit_test(test_xform_sphere),
        cmocka_unit_test(test_xform_box_cone),
        cmocka_unit_test(test_normal_flip),
        cmocka_unit_test(test_surface_pack),
        cmocka_unit_test(test_camera_primary),
        cmocka_unit_test(test_sincos),
        cmocka_unit_test(test_bent_cameras),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
