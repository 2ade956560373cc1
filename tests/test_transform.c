/*
 * test_transform.c — unit tests of the host-side transforms of csg/scene.c
 * (composition order, inverse, POV-Ray's rotate convention, exact quarter
 * turns) and of POV-Ray's camera rules in csg/camera_setup.c (look_at keeps
 * the vector lengths and the handedness, angle sets |direction|, errors
 * with file:line:col).  All in double: no `real` here.
 *
 * The rotate convention was cross-checked once against POV-Ray 3.7 itself:
 * spheres and boxes with `scale`/`rotate`/`translate` chains (including
 * rotate <30, 45, 60> and <60, -45, 30>), seen by `camera { location
 * <3,4,-6> right x*4/3 look_at 0 angle 60 }`, rendered at 64 x 48 with
 * `povray +W64 +H48 -D -A +FP`, give exactly the same hit masks as our
 * camera_setup + csg_xform_* + csg_primary_ray + csg_trace_nearest (0 of
 * 3072 pixels differ; negating any one angle makes 39 to 105 differ).  The
 * expected values below are the analytic form of that convention.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "../csg/camera_setup.h"
#include "../csg/scene.h"

/* ---- helpers ---------------------------------------------------------------- */

#define NEAR(a, b, tol) near_at((a), (b), (tol), #a, __FILE__, __LINE__)

static void near_at(double got, double want, double tol, const char *what, const char *file,
                    int line)
{
    if (!(fabs(got - want) <= tol)) {
        print_error("%s = %.17g, expected %.17g (tolerance %.3g)\n", what, got, want, tol);
        _fail(file, line);
    }
}

#define NEAR_D3(v, ex, ey, ez, tol) near_d3_at((v), (ex), (ey), (ez), (tol), #v, __FILE__, __LINE__)

static void near_d3_at(dvec3 v, double ex, double ey, double ez, double tol, const char *what,
                       const char *file, int line)
{
    if (!(fabs(v.x - ex) <= tol && fabs(v.y - ey) <= tol && fabs(v.z - ez) <= tol)) {
        print_error("%s = (%.17g, %.17g, %.17g), expected (%.17g, %.17g, %.17g)\n", what, v.x,
                    v.y, v.z, ex, ey, ez);
        _fail(file, line);
    }
}

static dvec3 apply(const csg_xform *x, dvec3 p)
{
    dvec3 q;
    q.x = x->m[0][0] * p.x + x->m[0][1] * p.y + x->m[0][2] * p.z + x->m[0][3];
    q.y = x->m[1][0] * p.x + x->m[1][1] * p.y + x->m[1][2] * p.z + x->m[1][3];
    q.z = x->m[2][0] * p.x + x->m[2][1] * p.y + x->m[2][2] * p.z + x->m[2][3];
    return q;
}

static dvec3 d3(double x, double y, double z) { return (dvec3){x, y, z}; }
static double dot(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double len(dvec3 a) { return sqrt(dot(a, a)); }
static dvec3 cross(dvec3 a, dvec3 b)
{
    return d3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

static csg_xform rotation(double x, double y, double z)
{
    csg_xform r;
    csg_xform_identity(&r);
    csg_xform_rotate(&r, d3(x, y, z));
    return r;
}

/* Exact equality: quarter turns must not leave 6e-17 behind. */
#define MAPS_EXACTLY(x, px, py, pz, qx, qy, qz) \
    NEAR_D3(apply(&(x), d3(px, py, pz)), qx, qy, qz, 0)

/* ---- composition ---------------------------------------------------------------- */

static void test_identity_translate_scale(void **state)
{
    (void)state;
    csg_xform x;
    csg_xform_identity(&x);
    MAPS_EXACTLY(x, 1, 2, 3, 1, 2, 3);
    /* POV-Ray applies transforms in source order: translate then scale
     * scales the translation too */
    csg_xform_translate(&x, d3(1, 0, 0));
    csg_xform_scale(&x, d3(2, 3, 4));
    MAPS_EXACTLY(x, 0, 0, 0, 2, 0, 0);
    MAPS_EXACTLY(x, 1, 1, 1, 4, 3, 4);
    /* scale then translate does not */
    csg_xform_identity(&x);
    csg_xform_scale(&x, d3(2, 3, 4));
    csg_xform_translate(&x, d3(1, 0, 0));
    MAPS_EXACTLY(x, 0, 0, 0, 1, 0, 0);
    MAPS_EXACTLY(x, 1, 1, 1, 3, 3, 4);
}

static void test_then_order(void **state)
{
    (void)state;
    csg_xform t, s, ts, st;
    csg_xform_identity(&t);
    csg_xform_translate(&t, d3(1, 2, 3));
    csg_xform_identity(&s);
    csg_xform_scale(&s, d3(2, 2, 2));
    csg_xform_then(&t, &s, &ts); /* t first, then s */
    csg_xform_then(&s, &t, &st);
    MAPS_EXACTLY(ts, 0, 0, 0, 2, 4, 6);
    MAPS_EXACTLY(st, 0, 0, 0, 1, 2, 3);
    MAPS_EXACTLY(ts, 1, 1, 1, 4, 6, 8);
    MAPS_EXACTLY(st, 1, 1, 1, 3, 4, 5);
    /* a rotation then a translation: rotate the point, then move it */
    csg_xform r = rotation(0, 0, 90), rt;
    csg_xform_then(&r, &t, &rt);
    MAPS_EXACTLY(rt, 1, 0, 0, 1, 3, 3);
    /* then(a, b) agrees with applying a, then b, on a generic point */
    csg_xform a = rotation(10, 20, 30), b = rotation(-40, 5, 70), ab;
    csg_xform_scale(&a, d3(1.5, 0.5, 2));
    csg_xform_translate(&b, d3(-1, 0.25, 4));
    csg_xform_then(&a, &b, &ab);
    dvec3 p = d3(0.3, -1.7, 2.9);
    dvec3 want = apply(&b, apply(&a, p));
    dvec3 got = apply(&ab, p);
    NEAR_D3(got, want.x, want.y, want.z, 1e-14);
    /* out may alias either operand */
    csg_xform a2 = a, b2 = b;
    csg_xform_then(&a2, &b, &a2);
    csg_xform_then(&a, &b2, &b2);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++) {
            NEAR(a2.m[i][j], ab.m[i][j], 0);
            NEAR(b2.m[i][j], ab.m[i][j], 0);
        }
}

static void test_invert(void **state)
{
    (void)state;
    csg_xform x = rotation(17, -33, 71), inv, back, id;
    csg_xform_scale(&x, d3(2, 0.5, -3));
    csg_xform_translate(&x, d3(4, -5, 6));
    assert_true(csg_xform_invert(&x, &inv));
    csg_xform_then(&x, &inv, &id);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            NEAR(id.m[i][j], i == j ? 1.0 : 0.0, 1e-14);
    csg_xform_then(&inv, &x, &id);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            NEAR(id.m[i][j], i == j ? 1.0 : 0.0, 1e-14);
    /* the inverse of the inverse is the original */
    assert_true(csg_xform_invert(&inv, &back));
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            NEAR(back.m[i][j], x.m[i][j], 1e-13);
    /* a point goes there and back */
    dvec3 p = d3(1.25, -2.5, 0.125);
    dvec3 q = apply(&inv, apply(&x, p));
    NEAR_D3(q, p.x, p.y, p.z, 1e-14);
    /* simple cases are exact */
    csg_xform t;
    csg_xform_identity(&t);
    csg_xform_scale(&t, d3(2, 4, 8));
    csg_xform_translate(&t, d3(1, 2, 3));
    assert_true(csg_xform_invert(&t, &inv));
    MAPS_EXACTLY(inv, 1, 2, 3, 0, 0, 0);
    MAPS_EXACTLY(inv, 3, 6, 11, 1, 1, 1);
    /* an asymmetric matrix, where a transposed cofactor would show */
    csg_xform g;
    memset(&g, 0, sizeof g);
    double m[3][4] = {{1, 2, 0, 1}, {0, 1, 3, 0}, {4, 0, 1, -2}};
    memcpy(g.m, m, sizeof m);
    assert_true(csg_xform_invert(&g, &inv));
    csg_xform_then(&g, &inv, &id);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            NEAR(id.m[i][j], i == j ? 1.0 : 0.0, 1e-15);
    /* singular and non-finite matrices are refused */
    csg_xform z;
    csg_xform_identity(&z);
    csg_xform_scale(&z, d3(1, 0, 1));
    assert_false(csg_xform_invert(&z, &inv));
    csg_xform_identity(&z);
    z.m[1][1] = INFINITY;
    assert_false(csg_xform_invert(&z, &inv));
    csg_xform_identity(&z);
    z.m[0][0] = NAN;
    assert_false(csg_xform_invert(&z, &inv));
}

/* ---- rotate ------------------------------------------------------------------------------ */

/* POV-Ray's left-handed rotations: rotate <0, 90, 0> takes +x to -z. */
static void test_rotate_axes(void **state)
{
    (void)state;
    csg_xform rx = rotation(90, 0, 0), ry = rotation(0, 90, 0), rz = rotation(0, 0, 90);
    MAPS_EXACTLY(rx, 1, 0, 0, 1, 0, 0);
    MAPS_EXACTLY(rx, 0, 1, 0, 0, 0, 1);
    MAPS_EXACTLY(rx, 0, 0, 1, 0, -1, 0);
    MAPS_EXACTLY(ry, 1, 0, 0, 0, 0, -1);
    MAPS_EXACTLY(ry, 0, 1, 0, 0, 1, 0);
    MAPS_EXACTLY(ry, 0, 0, 1, 1, 0, 0);
    MAPS_EXACTLY(rz, 1, 0, 0, 0, 1, 0);
    MAPS_EXACTLY(rz, 0, 1, 0, -1, 0, 0);
    MAPS_EXACTLY(rz, 0, 0, 1, 0, 0, 1);
    /* the same sense for a generic angle: rotate <0, 0, 30> */
    csg_xform r30 = rotation(0, 0, 30);
    NEAR_D3(apply(&r30, d3(1, 0, 0)), sqrt(3.0) / 2, 0.5, 0, 1e-15);
    csg_xform ry30 = rotation(0, 30, 0);
    NEAR_D3(apply(&ry30, d3(1, 0, 0)), sqrt(3.0) / 2, 0, -0.5, 1e-15);
    csg_xform rx30 = rotation(30, 0, 0);
    NEAR_D3(apply(&rx30, d3(0, 1, 0)), 0, sqrt(3.0) / 2, 0.5, 1e-15);
}

static void test_rotate_quarter_turns_exact(void **state)
{
    (void)state;
    /* every multiple of 90, negative and beyond 360, is exact */
    static const struct {
        double deg, c, s;
    } q[] = {{0, 1, 0},     {90, 0, 1},    {180, -1, 0},   {270, 0, -1},  {360, 1, 0},
             {-90, 0, -1},  {-180, -1, 0}, {-270, 0, 1},   {450, 0, 1},   {-450, 0, -1},
             {720, 1, 0},   {-360, 1, 0},  {1080 + 180, -1, 0}};
    for (size_t k = 0; k < sizeof q / sizeof q[0]; k++) {
        csg_xform r = rotation(0, 0, q[k].deg);
        /* rotate z: +x -> (c, s, 0) */
        MAPS_EXACTLY(r, 1, 0, 0, q[k].c, q[k].s, 0);
        MAPS_EXACTLY(r, 0, 1, 0, -q[k].s, q[k].c, 0);
        r = rotation(q[k].deg, 0, 0); /* rotate x: +y -> (0, c, s) */
        MAPS_EXACTLY(r, 0, 1, 0, 0, q[k].c, q[k].s);
        r = rotation(0, q[k].deg, 0); /* rotate y: +z -> (s, 0, c) */
        MAPS_EXACTLY(r, 0, 0, 1, q[k].s, 0, q[k].c);
    }
    /* composed quarter turns stay exact (and x, then y, then z) */
    csg_xform r = rotation(90, 90, 0);
    MAPS_EXACTLY(r, 0, 1, 0, 1, 0, 0); /* +y -x-> +z -y-> +x */
    r = rotation(90, 90, 90);
    MAPS_EXACTLY(r, 0, 1, 0, 0, 1, 0); /* ... -z-> +y */
    MAPS_EXACTLY(r, 1, 0, 0, 0, 0, -1);
}

static void test_rotate_order(void **state)
{
    (void)state;
    /* rotate <a, b, c> = rotate <a,0,0> rotate <0,b,0> rotate <0,0,c> */
    csg_xform all = rotation(30, 45, 60), seq;
    csg_xform_identity(&seq);
    csg_xform_rotate(&seq, d3(30, 0, 0));
    csg_xform_rotate(&seq, d3(0, 45, 0));
    csg_xform_rotate(&seq, d3(0, 0, 60));
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            NEAR(all.m[i][j], seq.m[i][j], 1e-15);
    /* and not z first */
    csg_xform rev;
    csg_xform_identity(&rev);
    csg_xform_rotate(&rev, d3(0, 0, 60));
    csg_xform_rotate(&rev, d3(0, 45, 0));
    csg_xform_rotate(&rev, d3(30, 0, 0));
    dvec3 a = apply(&all, d3(0, 1, 0)), b = apply(&rev, d3(0, 1, 0));
    assert_true(len(d3(a.x - b.x, a.y - b.y, a.z - b.z)) > 0.1);
    /* a rotation after a translation moves the translated point */
    csg_xform x;
    csg_xform_identity(&x);
    csg_xform_translate(&x, d3(2, 0, 0));
    csg_xform_rotate(&x, d3(0, 90, 0));
    MAPS_EXACTLY(x, 0, 0, 0, 0, 0, -2);
    /* any rotation is orthonormal with determinant +1 */
    csg_xform g = rotation(12.5, -77, 203);
    dvec3 c0 = d3(g.m[0][0], g.m[1][0], g.m[2][0]), c1 = d3(g.m[0][1], g.m[1][1], g.m[2][1]),
          c2 = d3(g.m[0][2], g.m[1][2], g.m[2][2]);
    NEAR(dot(c0, c0), 1, 1e-15);
    NEAR(dot(c1, c1), 1, 1e-15);
    NEAR(dot(c0, c1), 0, 1e-15);
    NEAR(dot(c1, c2), 0, 1e-15);
    NEAR(dot(cross(c0, c1), c2), 1, 1e-15);
    NEAR(g.m[0][3], 0, 0);
}

/* ---- camera ------------------------------------------------------------------------------ */

static csg_loc here(int line, int col)
{
    csg_loc l;
    l.file = "scene.pov";
    l.line = line;
    l.col = col;
    return l;
}

static void test_camera_default(void **state)
{
    (void)state;
    csg_camera_src c;
    memset(&c, 0xff, sizeof c);
    csg_camera_default(&c);
    NEAR_D3(c.location, 0, 0, 0, 0);
    NEAR_D3(c.direction, 0, 0, 1, 0);
    NEAR_D3(c.up, 0, 1, 0, 0);
    NEAR_D3(c.right, 1.33, 0, 0, 0);
    NEAR_D3(c.sky, 0, 1, 0, 0);
}

static void test_camera_look_at(void **state)
{
    (void)state;
    csg_camera_src c;
    csg_diag d;
    memset(&d, 0, sizeof d);
    /* straight ahead: nothing changes */
    csg_camera_default(&c);
    c.location = d3(0, 0, -5);
    assert_true(csg_camera_look_at(&c, d3(0, 0, 0), here(1, 1), &d));
    NEAR_D3(c.direction, 0, 0, 1, 1e-15);
    NEAR_D3(c.right, 1.33, 0, 0, 1e-15);
    NEAR_D3(c.up, 0, 1, 0, 1e-15);
    /* from +x: right = sky x direction = y x -x = +z (left-handed) */
    csg_camera_default(&c);
    c.location = d3(5, 0, 0);
    assert_true(csg_camera_look_at(&c, d3(0, 0, 0), here(1, 1), &d));
    NEAR_D3(c.direction, -1, 0, 0, 1e-15);
    NEAR_D3(c.right, 0, 0, 1.33, 1e-15);
    NEAR_D3(c.up, 0, 1, 0, 1e-15);
    /* a general view: the lengths of direction, right and up are kept */
    csg_camera_default(&c);
    c.location = d3(3, 4, -6);
    c.direction = d3(0, 0, 2.5);
    c.up = d3(0, 0.5, 0);
    c.right = d3(4.0 / 3.0, 0, 0);
    assert_true(csg_camera_look_at(&c, d3(1, 1, 1), here(1, 1), &d));
    NEAR(len(c.direction), 2.5, 1e-14);
    NEAR(len(c.right), 4.0 / 3.0, 1e-14);
    NEAR(len(c.up), 0.5, 1e-14);
    dvec3 v = d3(1 - 3, 1 - 4, 1 + 6);
    double vl = len(v);
    NEAR_D3(c.direction, 2.5 * v.x / vl, 2.5 * v.y / vl, 2.5 * v.z / vl, 1e-14);
    NEAR(dot(c.direction, c.right), 0, 1e-14);
    NEAR(dot(c.direction, c.up), 0, 1e-14);
    NEAR(dot(c.right, c.up), 0, 1e-14);
    NEAR(c.right.y, 0, 1e-15); /* horizontal: perpendicular to sky */
    assert_true(c.up.y > 0);
    /* still left-handed: (up x direction) . right > 0 */
    assert_true(dot(cross(c.up, c.direction), c.right) > 0);
    /* a right-handed camera (right -x) stays right-handed */
    csg_camera_default(&c);
    c.location = d3(3, 4, -6);
    c.right = d3(-1.33, 0, 0);
    assert_true(csg_camera_look_at(&c, d3(0, 0, 0), here(1, 1), &d));
    NEAR(len(c.right), 1.33, 1e-14);
    assert_true(dot(cross(c.up, c.direction), c.right) < 0);
    csg_camera_default(&c);
    c.location = d3(0, 0, -5);
    c.right = d3(-1.33, 0, 0);
    assert_true(csg_camera_look_at(&c, d3(0, 0, 0), here(1, 1), &d));
    NEAR_D3(c.right, -1.33, 0, 0, 1e-15);
    /* a tilted sky */
    csg_camera_default(&c);
    c.location = d3(0, 0, -5);
    c.sky = d3(1, 1, 0);
    assert_true(csg_camera_look_at(&c, d3(0, 0, 0), here(1, 1), &d));
    NEAR_D3(c.up, sqrt(0.5), sqrt(0.5), 0, 1e-15);
    NEAR_D3(c.right, 1.33 * sqrt(0.5), -1.33 * sqrt(0.5), 0, 1e-14);
    assert_false(d.failed);
}

static void test_camera_look_at_errors(void **state)
{
    (void)state;
    csg_camera_src c;
    csg_diag d;
    memset(&d, 0, sizeof d);
    csg_camera_default(&c);
    c.location = d3(1, 2, 3);
    assert_false(csg_camera_look_at(&c, d3(1, 2, 3), here(12, 5), &d));
    assert_true(d.failed);
    const char *want = "scene.pov:12:5: error: ";
    if (strncmp(d.message, want, strlen(want)) != 0) {
        print_error("message: %s\n", d.message);
        fail();
    }
    assert_non_null(strstr(d.message, "look_at"));
    assert_null(strchr(d.message, '\n'));
    /* the sky along the view direction keeps the right vector (POV-Ray) */
    memset(&d, 0, sizeof d);
    csg_camera_default(&c);
    c.location = d3(0, 5, 0);
    assert_true(csg_camera_look_at(&c, d3(0, 0, 0), here(3, 9), &d));
    assert_false(d.failed);
    assert_true(c.right.x == 1.33 && c.up.z == 1 && c.direction.y == -1);
    /* ... unless it is along the view too: no frame */
    csg_camera_default(&c);
    c.location = d3(0, 5, 0);
    c.right = d3(0, 2, 0);
    assert_false(csg_camera_look_at(&c, d3(0, 0, 0), here(3, 9), &d));
    assert_true(d.failed);
    assert_int_equal(strncmp(d.message, "scene.pov:3:9: error: ", 22), 0);
}

static void test_camera_angle(void **state)
{
    (void)state;
    csg_camera_src c;
    csg_diag d;
    memset(&d, 0, sizeof d);
    csg_camera_default(&c);
    assert_true(csg_camera_angle(&c, 90, here(1, 1), &d));
    /* |direction| = |right| / 2 / tan(angle / 2) */
    NEAR_D3(c.direction, 0, 0, 1.33 / 2, 1e-15);
    c.right = d3(4.0 / 3.0, 0, 0);
    c.direction = d3(0, 3, 4);
    assert_true(csg_camera_angle(&c, 60, here(1, 1), &d));
    double want = (2.0 / 3.0) / tan(M_PI / 6);
    NEAR(len(c.direction), want, 1e-14);
    NEAR_D3(c.direction, 0, 0.6 * want, 0.8 * want, 1e-14);
    /* the angle and then look_at (or the other way) give the same camera */
    csg_camera_src a, b;
    csg_camera_default(&a);
    a.location = d3(3, 4, -6);
    b = a;
    assert_true(csg_camera_angle(&a, 45, here(1, 1), &d));
    assert_true(csg_camera_look_at(&a, d3(0, 1, 0), here(1, 1), &d));
    assert_true(csg_camera_look_at(&b, d3(0, 1, 0), here(1, 1), &d));
    assert_true(csg_camera_angle(&b, 45, here(1, 1), &d));
    NEAR_D3(a.direction, b.direction.x, b.direction.y, b.direction.z, 1e-14);
    NEAR_D3(a.right, b.right.x, b.right.y, b.right.z, 1e-14);
    NEAR_D3(a.up, b.up.x, b.up.y, b.up.z, 1e-14);
    assert_false(d.failed);
    /* out of range */
    const double bad[] = {0, 180, -10, 200, NAN};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        memset(&d, 0, sizeof d);
        csg_camera_default(&c);
        assert_false(csg_camera_angle(&c, bad[k], here(7, 3), &d));
        assert_int_equal(strncmp(d.message, "scene.pov:7:3: error: ", 22), 0);
        NEAR_D3(c.direction, 0, 0, 1, 0); /* untouched */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_identity_translate_scale),
        cmocka_unit_test(test_then_order),
        cmocka_unit_test(test_invert),
        cmocka_unit_test(test_rotate_axes),
        cmocka_unit_test(test_rotate_quarter_turns_exact),
        cmocka_unit_test(test_rotate_order),
        cmocka_unit_test(test_camera_default),
        cmocka_unit_test(test_camera_look_at),
        cmocka_unit_test(test_camera_look_at_errors),
        cmocka_unit_test(test_camera_angle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
