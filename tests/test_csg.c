/*
 * test_csg.c — unit tests of the CSG half of csg/device/intersect.h: interval
 * lists (push, union, intersection, the CSG_MAX_SPANS limit), root
 * programs in reverse Polish notation over hand-built csg_prim / csg_node /
 * csg_root arrays, the nearest hit over several roots, and the root boxes.
 *
 * Compiled twice: as is (real = float) and through tests/test_csg_double.c
 * (real = double).  Most expected values are exact in both precisions
 * (boxes and spheres placed on small binary fractions).  The span algebra
 * is also checked against a pointwise evaluation on random lists.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <string.h>

#include "../csg/device/intersect.h"

#include "geom_assert.h"

/* A flat scene built by hand: primitives, then each root's program. */
typedef struct {
    csg_prim prims[64];
    csg_node nodes[128];
    csg_root roots[8];
    int np, nn, nr;
} scene;

static void scene_init(scene *s) { memset(s, 0, sizeof *s); }

static int add_prim(scene *s, int kind, int flags, const real *p, int n)
{
    csg_prim *q = &s->prims[s->np];
    memset(q, 0, sizeof *q);
    q->kind = kind;
    q->flags = flags;
    q->root = s->nr;
    for (int i = 0; i < n; i++)
        q->p[i] = p[i];
    return s->np++;
}

static int add_sphere(scene *s, int flags, real x, real y, real z, real r)
{
    real p[4] = {x, y, z, r};
    return add_prim(s, CSG_PRIM_SPHERE, flags, p, 4);
}

static int add_box(scene *s, int flags, real x0, real y0, real z0, real x1, real y1, real z1)
{
    real p[6] = {x0, y0, z0, x1, y1, z1};
    return add_prim(s, CSG_PRIM_BOX, flags, p, 6);
}

static int add_plane(scene *s, int flags, real nx, real ny, real nz, real d)
{
    real p[4] = {nx, ny, nz, d};
    return add_prim(s, CSG_PRIM_PLANE, flags, p, 4);
}

/* Program items: a primitive index >= 0, or one of these. */
#define U (-1)
#define I (-2)
#define B (-3) /* CSG_OP_BOUND */
#define END (-100)

/* Appends a root whose program is the list `prog` (ended by END), with an
 * unbounded box; returns the root index. */
static int add_root_prog(scene *s, const int *prog)
{
    csg_root *rt = &s->roots[s->nr];
    memset(rt, 0, sizeof *rt);
    rt->first_node = s->nn;
    int depth = 0, max_depth = 0;
    for (int k = 0; prog[k] != END; k++) {
        csg_node *n = &s->nodes[s->nn++];
        if (prog[k] >= 0) {
            n->op = CSG_OP_PRIM;
            n->prim = prog[k];
            s->prims[prog[k]].root = s->nr;
            depth++;
        } else {
            n->op = prog[k] == U ? CSG_OP_UNION : prog[k] == B ? CSG_OP_BOUND : CSG_OP_INTERSECT;
            n->prim = -1;
            depth--;
        }
        max_depth = depth > max_depth ? depth : max_depth;
        rt->node_count++;
    }
    assert_int_equal(depth, 1);
    rt->stack_depth = max_depth;
    for (int a = 0; a < 3; a++) {
        rt->lo[a] = -CSG_R_INF;
        rt->hi[a] = CSG_R_INF;
    }
    return s->nr++;
}

#define ROOT(s, ...) add_root_prog((s), (const int[]){__VA_ARGS__, END})

static csg_view view(const scene *s)
{
    csg_view v;
    v.prims = s->prims;
    v.nodes = s->nodes;
    v.roots = s->roots;
    v.bvh = NULL;
    v.root_count = s->nr;
    v.bvh_count = 0;
    return v;
}

static void root_spans(const scene *s, int root, csg_ray r, real tmin, real tmax, csg_spans *out)
{
    csg_root_spans(view(s), root, r, tmin, tmax, out);
}

static csg_hit nearest(const scene *s, csg_ray r)
{
    return csg_trace_nearest(view(s), r, 0, CSG_R_INF);
}

/* Asserts span k of l is [t0, t1] with those surfaces. */
#define SPAN(l, k, a, sa, b, sb) span_at(&(l), (k), (double)(a), (sa), (double)(b), (sb), __FILE__, __LINE__)

static void span_at(const csg_spans *l, int k, double t0, csg_u32 s0, double t1, csg_u32 s1,
                    const char *file, int line)
{
    if (k >= l->n || (double)l->t0[k] != t0 || (double)l->t1[k] != t1 || l->s0[k] != s0 ||
        l->s1[k] != s1) {
        if (k < l->n)
            print_error("span %d = [%.9g (%#x), %.9g (%#x)], expected [%.9g (%#x), %.9g (%#x)]\n",
                        k, (double)l->t0[k], l->s0[k], (double)l->t1[k], l->s1[k], t0, s0, t1,
                        s1);
        else
            print_error("span %d missing: the list has %d\n", k, l->n);
        _fail(file, line);
    }
}

#define S(prim, sub) CSG_SURF_PACK((prim), (sub), 0)
#define SF(prim, sub) CSG_SURF_PACK((prim), (sub), 1)

/* ---- set operations on two spheres ------------------------------------------- */

/* A at the origin, B at x = 1.5, both radius 1; rays along the x axis. */
static void two_spheres(scene *s, int flags_b)
{
    scene_init(s);
    add_sphere(s, 0, 0, 0, 0, 1);
    add_sphere(s, flags_b, R(1.5), 0, 0, 1);
}

static void test_union(void **state)
{
    (void)state;
    scene s;
    two_spheres(&s, 0);
    ROOT(&s, 0, 1, U);
    csg_spans l;
    csg_ray r = ray(-5, 0, 0, 1, 0, 0);
    root_spans(&s, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 4, S(0, 0), 7.5, S(1, 0));
    csg_hit h = nearest(&s, r);
    NEAR(h.t, 4, 0);
    assert_int_equal(h.surf, S(0, 0));
    /* from the other side, B is met first */
    r = ray(5, 0, 0, -1, 0, 0);
    h = nearest(&s, r);
    NEAR(h.t, 2.5, 0);
    assert_int_equal(h.surf, S(1, 0));
    /* operand order does not change the set */
    scene s2;
    two_spheres(&s2, 0);
    ROOT(&s2, 1, 0, U);
    root_spans(&s2, 0, ray(-5, 0, 0, 1, 0, 0), 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 4, S(0, 0), 7.5, S(1, 0));
    /* disjoint members stay two intervals */
    scene s3;
    scene_init(&s3);
    add_sphere(&s3, 0, 0, 0, 0, 1);
    add_sphere(&s3, 0, 4, 0, 0, 1);
    ROOT(&s3, 0, 1, U);
    root_spans(&s3, 0, ray(-5, 0, 0, 1, 0, 0), 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 2);
    SPAN(l, 0, 4, S(0, 0), 6, S(0, 0));
    SPAN(l, 1, 8, S(1, 0), 10, S(1, 0));
}

static void test_intersection(void **state)
{
    (void)state;
    scene s;
    two_spheres(&s, 0);
    ROOT(&s, 0, 1, I);
    csg_spans l;
    csg_ray r = ray(-5, 0, 0, 1, 0, 0);
    root_spans(&s, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 5.5, S(1, 0), 6, S(0, 0));
    csg_hit h = nearest(&s, r);
    NEAR(h.t, 5.5, 0);
    NEAR_V(csg_surface_normal(s.prims, h.surf, v3_madd(r.o, r.d, h.t)), -1, 0, 0, 0);
    /* a ray through A only: nothing */
    r = ray(-5, 0, R(0.9), 1, 0, 0);
    assert_int_equal(nearest(&s, r).surf, CSG_SURF_NONE);
    assert_true(isinf(nearest(&s, r).t));
}

/* clipped_by: a sphere ∩ a clip half-space z < 0 (CSG_PF_CLIP): from the
 * front, the sphere's front; from behind, the ray passes the clip's plane
 * (no surface) and meets the sphere's back, inside the open hemisphere.
 * bounded_by: a sphere gated by a small box (CSG_OP_BOUND over a
 * CSG_PF_BOUND leaf): seen whole through the box, not at all beside it,
 * and the box counts beyond the query's tmax. */
static void test_clip_and_bound(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    add_sphere(&s, 0, 0, 0, 0, 1);
    add_plane(&s, CSG_PF_CLIP, 0, 0, 1, 0);
    ROOT(&s, 0, 1, I);
    csg_hit h = nearest(&s, ray(0, 0, -5, 0, 0, 1));
    NEAR(h.t, 4, 0);
    assert_int_equal(h.surf, S(0, 0));
    h = nearest(&s, ray(0, 0, 5, 0, 0, -1));
    NEAR(h.t, 6, 0);
    assert_int_equal(h.surf, S(0, 0));
    assert_int_equal(nearest(&s, ray(0, 0, 5, 1, 0, 0)).surf, CSG_SURF_NONE); /* (the plane: no hit) */
    add_sphere(&s, 0, 10, 0, 0, 1);
    add_box(&s, CSG_PF_BOUND, R(9.9), R(-0.1), R(-0.1), R(10.1), R(0.1), R(0.1));
    ROOT(&s, 2, 3, B);
    h = nearest(&s, ray(10, 0, -5, 0, 0, 1));
    NEAR(h.t, 4, 0);
    assert_int_equal(h.surf, S(2, 0));
    assert_int_equal(nearest(&s, ray(R(10.5), 0, -5, 0, 0, 1)).surf, CSG_SURF_NONE);
    h = csg_trace_nearest(view(&s), ray(10, 0, -5, 0, 0, 1), 0, R(4.5));
    NEAR(h.t, 4, 0);
}

/* A - B = A ∩ ¬B: the subtracted surface is B's, with its normal reversed
 * (the outward normal of the solid A - B). */
static void test_difference(void **state)
{
    (void)state;
    scene s;
    two_spheres(&s, CSG_PF_INVERT);
    ROOT(&s, 0, 1, I);
    csg_spans l;
    csg_ray r = ray(-5, 0, 0, 1, 0, 0);
    root_spans(&s, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 4, S(0, 0), 5.5, SF(1, 0));
    /* from +x: the ray first meets the bite taken by B, at x = 0.5 */
    r = ray(5, 0, 0, -1, 0, 0);
    root_spans(&s, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 4.5, SF(1, 0), 6, S(0, 0));
    csg_hit h = nearest(&s, r);
    NEAR(h.t, 4.5, 0);
    assert_int_equal(CSG_SURF_PRIM(h.surf), 1);
    assert_int_equal(CSG_SURF_FLIP(h.surf), 1);
    /* B's own normal there is -x; the solid's outward normal is +x */
    NEAR_V(csg_surface_normal(s.prims, h.surf, v3_madd(r.o, r.d, h.t)), 1, 0, 0, 0);
    /* B - A: the same pair, the other way */
    scene s2;
    scene_init(&s2);
    add_sphere(&s2, CSG_PF_INVERT, 0, 0, 0, 1);
    add_sphere(&s2, 0, R(1.5), 0, 0, 1);
    ROOT(&s2, 1, 0, I);
    root_spans(&s2, 0, ray(-5, 0, 0, 1, 0, 0), 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 6, SF(0, 0), 7.5, S(1, 0));
    /* a hole drilled through the middle: a box minus a thinner box gives
     * two pieces on a ray along the hole's cross direction */
    scene s3;
    scene_init(&s3);
    add_box(&s3, 0, 0, 0, 0, 4, 1, 1);
    add_box(&s3, CSG_PF_INVERT, R(1.5), -1, -1, R(2.5), 2, 2);
    ROOT(&s3, 0, 1, I);
    root_spans(&s3, 0, ray(-1, R(0.5), R(0.5), 1, 0, 0), 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 2);
    SPAN(l, 0, 1, S(0, 0), 2.5, SF(1, 0));
    SPAN(l, 1, 3.5, SF(1, 1), 5, S(0, 1));
    /* the normals of the two inner walls face into the hole */
    csg_ray rr = ray(-1, R(0.5), R(0.5), 1, 0, 0);
    NEAR_V(csg_surface_normal(s3.prims, l.s1[0], v3_madd(rr.o, rr.d, l.t1[0])), 1, 0, 0, 0);
    NEAR_V(csg_surface_normal(s3.prims, l.s0[1], v3_madd(rr.o, rr.d, l.t0[1])), -1, 0, 0, 0);
}

/* ---- nesting, inverted leaves, touching intervals ---------------------------------- */

/* Boxes that are slabs along x (y, z in [0, 1]) so that every interval on
 * the ray y = z = 0.5 along +x from x = -1 is t = x + 1. */
static int xslab(scene *s, int flags, real x0, real x1)
{
    return add_box(s, flags, x0, 0, 0, x1, 1, 1);
}

static void test_nested(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    int a = xslab(&s, 0, 0, 4), b = xslab(&s, 0, 2, 6);
    int c = xslab(&s, 0, 5, 9), d = xslab(&s, 0, 7, 10);
    int e = xslab(&s, CSG_PF_INVERT, 3, R(7.5));
    /* (A ∩ B) ∪ (C ∩ D) = [2, 4] ∪ [7, 9] */
    int r0 = ROOT(&s, a, b, I, c, d, I, U);
    assert_int_equal(s.roots[r0].stack_depth, 3);
    /* ((A ∩ B) ∪ (C ∩ D)) ∩ ¬E = [2, 3] ∪ [7.5, 9] */
    int r1 = ROOT(&s, a, b, I, c, d, I, U, e, I);
    /* A ∪ (B ∩ (C ∪ ¬E)) : C ∪ ¬E = (-inf,3] ∪ [5, inf); ∩ B = [2,3] ∪ [5,6];
     * ∪ A = [0, 4] ∪ [5, 6] */
    int r2 = ROOT(&s, a, b, c, e, U, I, U);
    csg_ray r = ray(-1, R(0.5), R(0.5), 1, 0, 0);
    csg_spans l;
    root_spans(&s, r0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 2);
    SPAN(l, 0, 3, S(b, 0), 5, S(a, 1));
    SPAN(l, 1, 8, S(d, 0), 10, S(c, 1));
    root_spans(&s, r1, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 2);
    SPAN(l, 0, 3, S(b, 0), 4, SF(e, 0));
    SPAN(l, 1, 8.5, SF(e, 1), 10, S(c, 1));
    root_spans(&s, r2, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 2);
    SPAN(l, 0, 1, S(a, 0), 5, S(a, 1));
    SPAN(l, 1, 6, S(c, 0), 7, S(b, 1));
}

static void test_inverted_leaf(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    add_sphere(&s, CSG_PF_INVERT, 0, 0, 0, 1);
    ROOT(&s, 0);
    csg_spans l;
    /* the complement of a sphere, from outside: the ray starts inside the
     * solid; its first boundary is the sphere's near side, normal reversed */
    csg_ray r = ray(-5, 0, 0, 1, 0, 0);
    root_spans(&s, 0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 2);
    SPAN(l, 0, 0, CSG_SURF_NONE, 4, SF(0, 0));
    assert_int_equal(l.s0[1], SF(0, 0));
    NEAR(l.t0[1], 6, 0);
    assert_true(isinf(l.t1[1]));
    assert_int_equal(l.s1[1], CSG_SURF_NONE);
    csg_hit h = nearest(&s, r);
    NEAR(h.t, 4, 0);
    NEAR_V(csg_surface_normal(s.prims, h.surf, v3_madd(r.o, r.d, h.t)), 1, 0, 0, 0);
    /* from inside the sphere: the complement starts at its far side */
    r = ray(0, 0, 0, 0, 1, 0);
    root_spans(&s, 0, r, 0, 100, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 1, SF(0, 0), 100, CSG_SURF_NONE);
    h = nearest(&s, r);
    NEAR(h.t, 1, 0);
    NEAR_V(csg_surface_normal(s.prims, h.surf, v3_madd(r.o, r.d, h.t)), 0, -1, 0, 0);
    /* a miss: the complement is the whole range, with no surface */
    root_spans(&s, 0, ray(-5, 3, 0, 1, 0, 0), 0, 100, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 0, CSG_SURF_NONE, 100, CSG_SURF_NONE);
    /* tangent: the zero-length gap closes, again no surface */
    root_spans(&s, 0, ray(-5, 1, 0, 1, 0, 0), 0, 100, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 0, CSG_SURF_NONE, 100, CSG_SURF_NONE);
    /* behind the origin */
    root_spans(&s, 0, ray(5, 0, 0, 1, 0, 0), 0, 100, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 0, CSG_SURF_NONE, 100, CSG_SURF_NONE);
    /* inverted half-space: the other side of the plane, normal reversed */
    scene p;
    scene_init(&p);
    add_plane(&p, CSG_PF_INVERT, 0, 1, 0, 0); /* y >= 0 */
    ROOT(&p, 0);
    r = ray(0, -2, 0, 0, 1, 0);
    h = nearest(&p, r);
    NEAR(h.t, 2, 0);
    NEAR_V(csg_surface_normal(p.prims, h.surf, v3_madd(r.o, r.d, h.t)), 0, -1, 0, 0);
    assert_int_equal(nearest(&p, ray(0, 2, 0, 0, 1, 0)).surf, CSG_SURF_NONE);
    /* De Morgan: ¬(A ∩ B) = ¬A ∪ ¬B on two slabs */
    scene m;
    scene_init(&m);
    int a = xslab(&m, CSG_PF_INVERT, 0, 4), b = xslab(&m, CSG_PF_INVERT, 2, 6);
    ROOT(&m, a, b, U);
    root_spans(&m, 0, ray(-1, R(0.5), R(0.5), 1, 0, 0), 0, 20, &l);
    assert_int_equal(l.n, 2);
    SPAN(l, 0, 0, CSG_SURF_NONE, 3, SF(b, 0));
    SPAN(l, 1, 5, SF(a, 1), 20, CSG_SURF_NONE);
}

/* Touching intervals merge in a union (merge's inner faces vanish), and
 * their intersection is empty. */
static void test_touching(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    int a = xslab(&s, 0, 0, 2), b = xslab(&s, 0, 2, 4), c = xslab(&s, 0, 4, 6);
    int r0 = ROOT(&s, a, b, U);
    int r1 = ROOT(&s, c, a, U, b, U); /* out of order: the middle one last */
    int r2 = ROOT(&s, a, b, I);
    int r3 = ROOT(&s, b, a, U);
    csg_ray r = ray(-1, R(0.5), R(0.5), 1, 0, 0);
    csg_spans l;
    root_spans(&s, r0, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 1, S(a, 0), 5, S(b, 1));
    root_spans(&s, r1, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 1, S(a, 0), 7, S(c, 1));
    root_spans(&s, r2, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 0);
    root_spans(&s, r3, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 1, S(a, 0), 5, S(b, 1));
    /* coming back, the far face of the union is the first hit */
    csg_hit h = csg_trace_nearest(view(&s), ray(10, R(0.5), R(0.5), -1, 0, 0), 0, CSG_R_INF);
    NEAR(h.t, 4, 0);
    assert_int_equal(h.surf, S(c, 1));
}

/* The exact difference of two identical solids leaves nothing behind, on
 * every ray (the two computations give the same bits). */
static void test_identical_difference(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    add_sphere(&s, 0, R(0.3), R(-0.7), R(1.1), R(1.3));
    add_sphere(&s, CSG_PF_INVERT, R(0.3), R(-0.7), R(1.1), R(1.3));
    add_box(&s, 0, R(-0.3), R(-1.1), R(0.2), R(0.9), R(0.4), R(1.7));
    add_box(&s, CSG_PF_INVERT, R(-0.3), R(-1.1), R(0.2), R(0.9), R(0.4), R(1.7));
    real cp[3] = {R(0.7), R(0.4), R(1.9)};
    add_prim(&s, CSG_PRIM_CONE, 0, cp, 3);
    add_prim(&s, CSG_PRIM_CONE, CSG_PF_INVERT, cp, 3);
    /* the same transform on both copies of the last pair */
    for (int k = 4; k < 6; k++) {
        real m[12] = {R(0.8), R(0.6), 0, R(0.1), R(-0.6), R(0.8), 0, R(-0.2), 0, 0, R(1.5), R(0.3)};
        memcpy(s.prims[k].inv, m, sizeof m);
        s.prims[k].flags |= CSG_PF_XFORM;
    }
    ROOT(&s, 0, 1, I);
    ROOT(&s, 2, 3, I);
    ROOT(&s, 4, 5, I);
    ROOT(&s, 1, 0, I);
    uint32_t seed = 7;
    for (int n = 0; n < 2000; n++) {
        real v[6];
        for (int i = 0; i < 6; i++) {
            seed = seed * 1664525u + 1013904223u;
            v[i] = (real)((double)(seed >> 8) / 8388608.0 - 1.0);
        }
        csg_ray r = ray(3 * v[0], 3 * v[1], 3 * v[2] + 1, v[3], v[4], v[5]);
        /* aim half the rays at the solids */
        if (n & 1)
            r.d = v3_sub(v3(R(0.3), R(-0.5), R(1.0)), r.o);
        for (int root = 0; root < 4; root++) {
            csg_spans l;
            root_spans(&s, root, r, 0, CSG_R_INF, &l);
            if (l.n != 0) {
                print_error("ray %d root %d: %d spans, first [%g, %g]\n", n, root, l.n,
                            (double)l.t0[0], (double)l.t1[0]);
                fail();
            }
        }
        assert_int_equal(nearest(&s, r).surf, CSG_SURF_NONE);
    }
}

/* Boxes with flush faces: a box minus a box that shares three of its faces
 * leaves no film on the shared faces. */
static void test_flush_faces(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    int a = add_box(&s, 0, 0, 0, 0, 2, 1, 1);
    int b = add_box(&s, CSG_PF_INVERT, 1, 0, 0, 2, 1, 1);     /* flush on 5 faces */
    int c = add_box(&s, CSG_PF_INVERT, 1, -1, 0, 3, 1, 2);    /* flush on y = 1, z = 0 */
    ROOT(&s, a, b, I);
    ROOT(&s, a, c, I);
    csg_spans l;
    for (int root = 0; root < 2; root++) {
        /* along y and z through the removed part: nothing */
        root_spans(&s, root, ray(R(1.5), -1, R(0.5), 0, 1, 0), 0, CSG_R_INF, &l);
        assert_int_equal(l.n, 0);
        root_spans(&s, root, ray(R(1.5), R(0.5), -1, 0, 0, 1), 0, CSG_R_INF, &l);
        assert_int_equal(l.n, 0);
        /* in the kept part: the original box's faces */
        root_spans(&s, root, ray(R(0.5), -1, R(0.5), 0, 1, 0), 0, CSG_R_INF, &l);
        assert_int_equal(l.n, 1);
        SPAN(l, 0, 1, S(a, 2), 2, S(a, 3));
        /* from +x: the cut face, normal +x */
        csg_ray r = ray(5, R(0.5), R(0.5), -1, 0, 0);
        root_spans(&s, root, r, 0, CSG_R_INF, &l);
        assert_int_equal(l.n, 1);
        SPAN(l, 0, 4, SF(root == 0 ? b : c, 0), 5, S(a, 0));
        NEAR_V(csg_surface_normal(s.prims, l.s0[0], v3_madd(r.o, r.d, l.t0[0])), 1, 0, 0, 0);
        /* grazing along the flush face y = 1 */
        root_spans(&s, root, ray(R(1.5), 1, -1, 0, 0, 1), 0, CSG_R_INF, &l);
        assert_int_equal(l.n, 0);
    }
}

/* ---- several roots, tmin / tmax -------------------------------------------------- */

static void test_nearest_roots(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    int sp = add_sphere(&s, 0, 5, 0, 0, 1); /* entry t = 4 */
    int bx = add_box(&s, 0, 4, -1, -1, 6, 1, 1); /* entry t = 4 too */
    int near = add_sphere(&s, 0, 3, 0, 0, R(0.5)); /* entry t = 2.5 */
    ROOT(&s, sp);
    ROOT(&s, bx);
    csg_ray r = ray(0, 0, 0, 1, 0, 0);
    /* a tie goes to the lower surface id, whatever the root order */
    csg_hit h = nearest(&s, r);
    NEAR(h.t, 4, 0);
    assert_int_equal(h.surf, S(sp, 0));
    scene s2;
    scene_init(&s2);
    bx = add_box(&s2, 0, 4, -1, -1, 6, 1, 1);
    sp = add_sphere(&s2, 0, 5, 0, 0, 1);
    ROOT(&s2, bx);
    ROOT(&s2, sp);
    h = nearest(&s2, r);
    NEAR(h.t, 4, 0);
    assert_int_equal(h.surf, S(bx, 0));
    scene s3; /* the box's surface id is the lower one, its root comes last */
    scene_init(&s3);
    bx = add_box(&s3, 0, 4, -1, -1, 6, 1, 1);
    sp = add_sphere(&s3, 0, 5, 0, 0, 1);
    ROOT(&s3, sp);
    ROOT(&s3, bx);
    h = nearest(&s3, r);
    NEAR(h.t, 4, 0);
    assert_int_equal(h.surf, S(bx, 0));
    /* a strictly nearer later root wins */
    ROOT(&s, near);
    h = nearest(&s, r);
    NEAR(h.t, 2.5, 0);
    assert_int_equal(h.surf, S(near, 0));
    /* roots that the ray misses do not matter */
    h = nearest(&s, ray(0, 0, 0, -1, 0, 0));
    assert_int_equal(h.surf, CSG_SURF_NONE);
    assert_true(isinf(h.t) && h.t > 0);
    /* no roots at all */
    scene e;
    scene_init(&e);
    assert_int_equal(nearest(&e, r).surf, CSG_SURF_NONE);
}

static void test_tmin_tmax(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    add_sphere(&s, 0, 5, 0, 0, 1); /* [4, 6] */
    ROOT(&s, 0);
    csg_view v = view(&s);
    csg_ray r = ray(0, 0, 0, 1, 0, 0);
    csg_hit h;
    /* tmin inside: the exit */
    h = csg_trace_nearest(v, r, R(4.5), CSG_R_INF);
    NEAR(h.t, 6, 0);
    /* hits must be strictly after tmin */
    h = csg_trace_nearest(v, r, 4, CSG_R_INF);
    NEAR(h.t, 6, 0);
    h = csg_trace_nearest(v, r, 6, CSG_R_INF);
    assert_int_equal(h.surf, CSG_SURF_NONE);
    /* and strictly before tmax */
    h = csg_trace_nearest(v, r, 0, 5);
    NEAR(h.t, 4, 0);
    h = csg_trace_nearest(v, r, 0, 4);
    assert_int_equal(h.surf, CSG_SURF_NONE);
    h = csg_trace_nearest(v, r, 0, R(3.9));
    assert_int_equal(h.surf, CSG_SURF_NONE);
    assert_true(isinf(h.t));
    /* a shadow-ray style query: between 4.5 and 5.5 there is no surface */
    h = csg_trace_nearest(v, r, R(4.5), R(5.5));
    assert_int_equal(h.surf, CSG_SURF_NONE);
    /* the leaf list on [4.5, 5.5]: one surface-less interval */
    csg_spans l;
    csg_root_spans(v, 0, r, R(4.5), R(5.5), &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 4.5, CSG_SURF_NONE, 5.5, CSG_SURF_NONE);
    /* clipping inside a CSG program is exact: (sphere ∩ ¬slab) on [3, 5] */
    scene d;
    scene_init(&d);
    add_sphere(&d, 0, 5, 0, 0, 1);
    add_box(&d, CSG_PF_INVERT, R(4.5), -2, -2, R(5.5), 2, 2);
    ROOT(&d, 0, 1, I);
    csg_root_spans(view(&d), 0, r, 3, 5, &l);
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 4, S(0, 0), 4.5, SF(1, 0));
    h = csg_trace_nearest(view(&d), r, R(4.25), CSG_R_INF);
    NEAR(h.t, 4.5, 0);
    h = csg_trace_nearest(view(&d), r, R(4.75), CSG_R_INF);
    NEAR(h.t, 5.5, 0);
    assert_int_equal(h.surf, SF(1, 1));
}

/* ---- the CSG_MAX_SPANS limit ------------------------------------------------------------- */

static void test_span_limit(void **state)
{
    (void)state;
    const int count = CSG_MAX_SPANS + 2;
    scene s;
    scene_init(&s);
    int prog[2 * (CSG_MAX_SPANS + 2) + 4];
    int k = 0;
    /* spheres at x = 2, 4, ..., radius 0.5: [2i + 1.5, 2i + 2.5] from x = 0 */
    for (int i = 0; i < count; i++) {
        add_sphere(&s, 0, (real)(2 * i + 2), 0, 0, R(0.5));
        prog[k++] = i;
        if (i > 0)
            prog[k++] = U;
    }
    prog[k] = END;
    int r_union = add_root_prog(&s, prog);
    /* the same union, far to near */
    k = 0;
    for (int i = count - 1; i >= 0; i--) {
        prog[k++] = i;
        if (i < count - 1)
            prog[k++] = U;
    }
    prog[k] = END;
    int r_rev = add_root_prog(&s, prog);
    csg_ray r = ray(0, 0, 0, 1, 0, 0);
    csg_spans l;
    const double limit = 2 * CSG_MAX_SPANS + 1.5; /* entry of sphere CSG_MAX_SPANS */
    for (int root = r_union; root <= r_rev; root++) {
        root_spans(&s, root, r, 0, CSG_R_INF, &l);
        assert_int_equal(l.n, CSG_MAX_SPANS);
        NEAR(l.limit, limit, 0);
        for (int i = 0; i < CSG_MAX_SPANS; i++)
            SPAN(l, i, 2 * i + 1.5, S(i, 0), 2 * i + 2.5, S(i, 0));
    }
    csg_hit h = nearest(&s, r);
    NEAR(h.t, 1.5, 0);
    /* beyond the limit nothing is known: the union cut by the half-space
     * x > 2 * CSG_MAX_SPANS + 1 reports no hit (and never a wrong one) */
    int cut = add_plane(&s, 0, -1, 0, 0, (real)(-(2 * CSG_MAX_SPANS + 1)));
    k = 0;
    for (int i = 0; i < count; i++) {
        prog[k++] = i;
        if (i > 0)
            prog[k++] = U;
    }
    prog[k++] = cut;
    prog[k++] = I;
    prog[k] = END;
    scene t = s;
    t.nr = 0;
    int r_cut = add_root_prog(&t, prog);
    root_spans(&t, r_cut, r, 0, CSG_R_INF, &l);
    assert_int_equal(l.n, 0);
    NEAR(l.limit, limit, 0);
    assert_int_equal(csg_trace_nearest(view(&t), r, 0, CSG_R_INF).surf, CSG_SURF_NONE);
    /* the same scene with tmin past the first spheres sees them all */
    h = csg_trace_nearest(view(&t), r, 20, CSG_R_INF);
    NEAR(h.t, 2 * CSG_MAX_SPANS + 1.5, 0);
}

/* ---- the span algebra against a pointwise evaluation ----------------------------------- */

static void random_list(uint32_t *seed, csg_spans *l, csg_u32 tag)
{
    csg_spans_clear(l, 100);
    int x = 0;
    for (;;) {
        *seed = *seed * 1664525u + 1013904223u;
        x += 1 + (int)((*seed >> 16) % 9);
        *seed = *seed * 1664525u + 1013904223u;
        int len = 1 + (int)((*seed >> 16) % 7);
        if (x + len > 100 || l->n == 6)
            break;
        csg_spans_push(l, (real)x, tag + (csg_u32)(2 * l->n), (real)(x + len),
                       tag + (csg_u32)(2 * l->n + 1));
        x += len;
    }
}

static int member(const csg_spans *l, double t)
{
    for (int k = 0; k < l->n; k++)
        if (t > (double)l->t0[k] && t < (double)l->t1[k])
            return 1;
    return 0;
}

/* out's ends carry the label of an input interval with the same end. */
static int label_ok(const csg_spans *a, const csg_spans *b, real t, csg_u32 s, int end)
{
    const csg_spans *ls[2] = {a, b};
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < ls[i]->n; k++) {
            real tt = end ? ls[i]->t1[k] : ls[i]->t0[k];
            csg_u32 ss = end ? ls[i]->s1[k] : ls[i]->s0[k];
            if (tt == t && ss == s)
                return 1;
        }
    return 0;
}

static void test_span_algebra(void **state)
{
    (void)state;
    uint32_t seed = 99;
    for (int n = 0; n < 300; n++) {
        csg_spans a, b, u, x;
        random_list(&seed, &a, 0x100);
        random_list(&seed, &b, 0x200);
        csg_spans_union(&a, &b, &u);
        csg_spans_intersect(&a, &b, &x);
        const csg_spans *outs[2] = {&u, &x};
        for (int o = 0; o < 2; o++) {
            const csg_spans *l = outs[o];
            for (int k = 0; k < l->n; k++) {
                assert_true(l->t0[k] < l->t1[k]);
                if (k > 0)
                    assert_true(l->t1[k - 1] < l->t0[k]); /* disjoint, not touching */
                assert_true(label_ok(&a, &b, l->t0[k], l->s0[k], 0));
                assert_true(label_ok(&a, &b, l->t1[k], l->s1[k], 1));
            }
        }
        /* samples between the integer ends (the sets are regularised:
         * a point where two intervals touch belongs to neither test) */
        for (int i = 0; i < 100; i++) {
            double t = 0.5 + i;
            int ma = member(&a, t), mb = member(&b, t);
            if (member(&u, t) != (ma || mb) || member(&x, t) != (ma && mb)) {
                print_error("list %d, t = %g: a %d b %d union %d intersection %d\n", n, t, ma,
                            mb, member(&u, t), member(&x, t));
                fail();
            }
        }
    }
}

static void test_spans_push(void **state)
{
    (void)state;
    csg_spans l;
    csg_spans_clear(&l, 10);
    csg_spans_push(&l, 1, 11, 2, 12);
    csg_spans_push(&l, 3, 13, 3, 14); /* empty: dropped */
    assert_int_equal(l.n, 1);
    csg_spans_push(&l, 2, 15, 4, 16); /* touching: merged, far end taken */
    assert_int_equal(l.n, 1);
    SPAN(l, 0, 1, 11, 4, 16);
    csg_spans_push(&l, 3, 17, R(3.5), 18); /* contained: no change */
    SPAN(l, 0, 1, 11, 4, 16);
    csg_spans_push(&l, 8, 19, 12, 20); /* past the limit: clipped, no surface */
    assert_int_equal(l.n, 2);
    SPAN(l, 1, 8, 19, 10, CSG_SURF_NONE);
    csg_spans_push(&l, 10, 21, 12, 22); /* at the limit: nothing */
    assert_int_equal(l.n, 2);
    /* a full list moves the limit in to the start of what it drops */
    csg_spans_clear(&l, 100);
    for (int i = 0; i < CSG_MAX_SPANS; i++)
        csg_spans_push(&l, (real)(2 * i), 1, (real)(2 * i + 1), 2);
    assert_int_equal(l.n, CSG_MAX_SPANS);
    NEAR(l.limit, 100, 0);
    csg_spans_push(&l, 40, 1, 41, 2);
    assert_int_equal(l.n, CSG_MAX_SPANS);
    NEAR(l.limit, 40, 0);
    csg_spans_push(&l, 42, 1, 43, 2);
    assert_int_equal(l.n, CSG_MAX_SPANS);
    /* but an interval touching the last one still merges */
    csg_spans_push(&l, 2 * CSG_MAX_SPANS - 1, 1, 2 * CSG_MAX_SPANS + R(0.5), 3);
    assert_int_equal(l.n, CSG_MAX_SPANS);
    NEAR(l.t1[CSG_MAX_SPANS - 1], 2 * CSG_MAX_SPANS + 0.5, 0);
    /* the limit of a combination is the smaller one */
    csg_spans a, b, o;
    csg_spans_clear(&a, 5);
    csg_spans_clear(&b, 50);
    csg_spans_push(&b, 1, 1, 20, 2);
    csg_spans_union(&a, &b, &o);
    NEAR(o.limit, 5, 0);
    assert_int_equal(o.n, 1);
    SPAN(o, 0, 1, 1, 5, CSG_SURF_NONE);
    csg_spans_intersect(&b, &a, &o);
    NEAR(o.limit, 5, 0);
    assert_int_equal(o.n, 0);
}

/* ---- root boxes --------------------------------------------------------------------------------- */

static csg_root box_root(real x0, real y0, real z0, real x1, real y1, real z1)
{
    csg_root r;
    memset(&r, 0, sizeof r);
    r.lo[0] = x0;
    r.lo[1] = y0;
    r.lo[2] = z0;
    r.hi[0] = x1;
    r.hi[1] = y1;
    r.hi[2] = z1;
    return r;
}

static void test_box_overlaps(void **state)
{
    (void)state;
    const real inf = CSG_R_INF;
    csg_root all = box_root(-inf, -inf, -inf, inf, inf, inf);
    csg_root floor = box_root(-inf, -inf, -inf, inf, 0, inf); /* y <= 0 */
    csg_root unit = box_root(0, 0, 0, 1, 1, 1);
    /* unbounded: every ray, even with zero components and infinite tmax */
    assert_true(csg_box_overlaps(&all, ray(1, 2, 3, 0, 0, 1), 0, inf));
    assert_true(csg_box_overlaps(&all, ray(1, 2, 3, R(0.6), R(-0.8), 0), 0, inf));
    assert_true(csg_box_overlaps(&all, ray(0, 0, 0, 1, 1, 1), 0, 1));
    /* half-bounded */
    assert_true(csg_box_overlaps(&floor, ray(0, 5, 0, 0, -1, 0), 0, inf));
    assert_false(csg_box_overlaps(&floor, ray(0, 5, 0, 0, 1, 0), 0, inf));
    assert_false(csg_box_overlaps(&floor, ray(0, 5, 0, 1, 0, 0), 0, inf));
    assert_true(csg_box_overlaps(&floor, ray(0, -1, 0, 1, 0, 0), 0, inf));
    assert_true(csg_box_overlaps(&floor, ray(0, 0, 0, 1, 0, 0), 0, inf));
    assert_false(csg_box_overlaps(&floor, ray(0, 5, 0, 0, -1, 0), 0, 4));
    assert_true(csg_box_overlaps(&floor, ray(0, 5, 0, R(0.6), R(-0.8), 0), 0, inf));
    /* finite */
    assert_true(csg_box_overlaps(&unit, ray(-1, R(0.5), R(0.5), 1, 0, 0), 0, inf));
    assert_false(csg_box_overlaps(&unit, ray(-1, R(1.5), R(0.5), 1, 0, 0), 0, inf));
    assert_false(csg_box_overlaps(&unit, ray(-1, R(0.5), R(0.5), -1, 0, 0), 0, inf));
    assert_false(csg_box_overlaps(&unit, ray(-1, R(0.5), R(0.5), 1, 0, 0), 0, R(0.5)));
    assert_true(csg_box_overlaps(&unit, ray(-1, R(0.5), R(0.5), 1, 0, 0), R(1.5), R(1.75)));
    assert_false(csg_box_overlaps(&unit, ray(-1, R(0.5), R(0.5), 1, 0, 0), R(2.5), 3));
    assert_false(csg_box_overlaps(&unit, ray(-1, -1, R(0.5), 1, R(-0.1), 0), 0, inf));
    /* a root whose box the ray misses is skipped by the nearest-hit search */
    scene s;
    scene_init(&s);
    add_sphere(&s, 0, 0, 0, 0, 1);
    ROOT(&s, 0);
    s.roots[0].lo[0] = 5; /* a (wrong) box that excludes the sphere */
    s.roots[0].lo[1] = 5;
    s.roots[0].lo[2] = 5;
    s.roots[0].hi[0] = 6;
    s.roots[0].hi[1] = 6;
    s.roots[0].hi[2] = 6;
    assert_int_equal(nearest(&s, ray(-5, 0, 0, 1, 0, 0)).surf, CSG_SURF_NONE);
    /* a plane root has an infinite box and is found */
    scene p;
    scene_init(&p);
    add_plane(&p, 0, 0, 1, 0, 0);
    ROOT(&p, 0);
    csg_hit h = nearest(&p, ray(0, 5, 0, 0, -1, 0));
    NEAR(h.t, 5, 0);
}

/* The reciprocal slab test at the IEEE edges: directions with +0 and -0
 * components, origins exactly on a slab's plane (0 * inf = NaN), infinite
 * and flat boxes, a denormal direction component. */
/* csg_box_hit on lo..hi, checked against csg_node_hit on the same box as
 * a BVH node (planes by index instead of by pointer): the same answer and
 * the same entry, bit for bit. */
static int box_hits(const real lo[3], const real hi[3], real ox, real oy, real oz, real dx, real dy,
                    real dz, real tmin, real tmax, real *t_enter)
{
    csg_box_ray b = csg_box_ray_of(ray(ox, oy, oz, dx, dy, dz));
    csg_bvh_node n;
    real t_node;
    memcpy(n.box, lo, 3 * sizeof *lo);
    memcpy(n.box + 3, hi, 3 * sizeof *hi);
    int hit = csg_box_hit(lo, hi, &b, tmin, tmax, t_enter);
    assert_int_equal(csg_node_hit(&n, &b, tmin, tmax, &t_node), hit);
    if (hit)
        assert_memory_equal(&t_node, t_enter, sizeof t_node);
    return hit;
}

static void test_box_ray_edges(void **state)
{
    (void)state;
    const real inf = CSG_R_INF, z = R(0.0);
    const real lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    real t;
    csg_box_ray b = csg_box_ray_of(ray(0, 0, 0, -z, z, R(-1.0)));
    assert_int_equal(b.neg[0], 1); /* -0 counts as negative */
    assert_int_equal(b.neg[1], 0);
    assert_int_equal(b.neg[2], 1);
    for (int sgn = 0; sgn < 2; sgn++) {
        real d0 = sgn ? -z : z; /* +0, then -0 */
        /* origin on the lo and on the hi plane of x, moving along z: the
         * line lies in the closed slab, so the box is met */
        assert_true(box_hits(lo, hi, 0, R(0.5), -1, d0, 0, 1, 0, inf, &t));
        assert_true(t <= 1 && t > R(0.99));
        assert_true(box_hits(lo, hi, 1, R(0.5), -1, d0, 0, 1, 0, inf, &t));
        assert_true(box_hits(lo, hi, 1, 1, -1, d0, d0, 1, 0, inf, &t)); /* on an edge */
        assert_true(box_hits(lo, hi, 0, 0, 2, d0, d0, -1, 0, inf, &t));
        /* just outside the slab: missed */
        assert_false(box_hits(lo, hi, R(-0.001), R(0.5), -1, d0, 0, 1, 0, inf, &t));
        assert_false(box_hits(lo, hi, R(1.001), R(0.5), -1, d0, 0, 1, 0, inf, &t));
        /* inside: entered at tmin */
        assert_true(box_hits(lo, hi, R(0.5), R(0.5), R(0.5), d0, d0, 1, R(0.25), inf, &t));
        assert_true(t == R(0.25));
        /* a flat box (lo == hi on x) with the origin in its plane */
        const real flo[3] = {R(0.5), 0, 0}, fhi[3] = {R(0.5), 1, 1};
        assert_true(box_hits(flo, fhi, R(0.5), R(0.5), -1, d0, 0, 1, 0, inf, &t));
        assert_false(box_hits(flo, fhi, R(0.75), R(0.5), -1, d0, 0, 1, 0, inf, &t));
    }
    /* infinite bounds with a zero component and the origin anywhere */
    const real ilo[3] = {-inf, -inf, 0}, ihi[3] = {inf, 0, 1};
    assert_true(box_hits(ilo, ihi, R(1e30), -5, -1, 0, 0, 1, 0, inf, &t));
    assert_true(box_hits(ilo, ihi, 0, 0, -1, -z, -z, 1, 0, inf, &t)); /* on y's plane */
    assert_false(box_hits(ilo, ihi, 0, R(0.5), -1, 0, 0, 1, 0, inf, &t));
    /* a component so small that its reciprocal overflows (a float
     * denormal) acts like a zero one */
    real tiny = R(1e-40);
    assert_true(box_hits(lo, hi, R(0.5), R(0.5), -1, tiny, 0, 1, 0, inf, &t));
    assert_true(box_hits(lo, hi, R(0.5), R(0.5), -1, -tiny, 0, 1, 0, inf, &t));
    /* the range: tmax before the entry, tmin after the exit */
    assert_false(box_hits(lo, hi, -1, R(0.5), R(0.5), 1, 0, 0, 0, R(0.999), &t));
    assert_true(box_hits(lo, hi, -1, R(0.5), R(0.5), 1, 0, 0, 0, 1, &t));
    assert_true(box_hits(lo, hi, -1, R(0.5), R(0.5), 1, 0, 0, 2, 3, &t));
    assert_false(box_hits(lo, hi, -1, R(0.5), R(0.5), 1, 0, 0, R(2.001), 3, &t));
}

/* The reciprocal slab test never rejects a ray that meets the box: random
 * boxes and rays, many with zero components and origins on a plane,
 * against the textbook division test evaluated in long double (exact
 * enough to decide every case these inputs produce). */
static uint32_t lcg(uint32_t *seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    return *seed >> 8;
}

static real pick(uint32_t *seed, real scale)
{
    return (real)((double)lcg(seed) / 16777216.0 * 2.0 * (double)scale - (double)scale);
}

static int box_reference(const real lo[3], const real hi[3], const real o[3], const real d[3],
                         real tmin, real tmax, long double *enter)
{
    long double a = tmin, b = tmax;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k])
                return 0;
            continue;
        }
        long double ta = ((long double)lo[k] - o[k]) / d[k];
        long double tb = ((long double)hi[k] - o[k]) / d[k];
        a = fmaxl(a, fminl(ta, tb));
        b = fminl(b, fmaxl(ta, tb));
    }
    *enter = a;
    return a <= b;
}

static void test_box_ray_conservative(void **state)
{
    (void)state;
    uint32_t seed = 777u;
    int met = 0;
    for (int k = 0; k < 200000; k++) {
        real lo[3], hi[3], o[3], d[3];
        for (int a = 0; a < 3; a++) {
            lo[a] = pick(&seed, 4);
            hi[a] = lo[a] + (lcg(&seed) % 16 == 0 ? 0 : pick(&seed, R(1.5)) + R(1.5));
        }
        for (int a = 0; a < 3; a++) {
            uint32_t u = lcg(&seed);
            o[a] = u % 8 == 0 ? lo[a] : (u % 8 == 1 ? hi[a] : pick(&seed, 8)); /* on a plane */
            u = lcg(&seed);
            real aim = lo[a] + (hi[a] - lo[a]) * (pick(&seed, R(0.6)) + R(0.5)); /* near the box */
            d[a] = u % 6 == 0 ? ((u & 64) ? -R(0.0) : R(0.0)) : aim - o[a];
        }
        real tmax = (k & 1) ? CSG_R_INF : pick(&seed, 3) + R(3.0);
        long double want_t;
        real got_t;
        int want = box_reference(lo, hi, o, d, 0, tmax, &want_t);
        int got = box_hits(lo, hi, o[0], o[1], o[2], d[0], d[1], d[2], 0, tmax, &got_t);
        if (want) {
            assert_true(got);
            assert_true((long double)got_t <= want_t);
            met++;
        }
    }
    assert_true(met > 40000);
}

/* The single-primitive fast path of csg_try_root gives exactly what the
 * interval list gives (csg_leaf_spans + csg_first_boundary): every kind,
 * open caps, rays from inside and outside, on the surface, tangent, and
 * query ranges that clip either end. */
static void test_leaf_fast_path(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    const real sp[4] = {R(0.2), R(-0.1), R(0.3), R(1.0)};
    const real bx[6] = {R(-1.0), R(-0.5), R(-0.7), R(0.8), R(1.0), R(0.6)};
    const real cn[3] = {R(1.0), R(0.25), R(2.0)};
    const real pl[4] = {R(0.0), R(1.0), R(0.0), R(0.25)};
    add_prim(&s, CSG_PRIM_SPHERE, 0, sp, 4);
    add_prim(&s, CSG_PRIM_BOX, 0, bx, 6);
    add_prim(&s, CSG_PRIM_CONE, 0, cn, 3);
    add_prim(&s, CSG_PRIM_CONE, CSG_PF_OPEN, cn, 3);
    add_prim(&s, CSG_PRIM_PLANE, 0, pl, 4);
    const real fb[6] = {R(-1.0), R(-0.5), R(0.25), R(0.8), R(1.0), R(0.25)};
    add_prim(&s, CSG_PRIM_FLAT_BOX, 0, fb, 6);
    const real ranges[4][2] = {{R(0.0), CSG_R_INF}, {R(0.5), CSG_R_INF}, {R(0.0), R(2.0)},
                               {R(1.5), R(2.5)}};
    uint32_t seed = 12345u;
    int hits = 0;
    for (int k = 0; k < 20000; k++) {
        real v[6];
        for (int j = 0; j < 6; j++) {
            seed = seed * 1664525u + 1013904223u;
            v[j] = (real)((double)(seed >> 8) / 16777216.0 * 6.0 - 3.0);
        }
        /* aimed at a point near the shapes (v[3..5] / 3 is in [-1, 1]) */
        real d[3] = {v[3] / R(3.0) - v[0], v[4] / R(3.0) - v[1], v[5] / R(3.0) - v[2]};
        if (k % 7 == 0) /* exactly axis-aligned directions now and then */
            d[k % 3] = R(0.0);
        csg_ray r = ray(v[0], v[1], v[2], d[0], d[1], d[2]);
        int prim = k % s.np;
        const real *rg = ranges[(k / s.np) % 4];
        csg_spans l;
        csg_leaf_spans(s.prims, prim, r, rg[0], rg[1], &l);
        csg_hit want = csg_first_boundary(&l, rg[0]);
        csg_hit got = csg_leaf_first_hit(s.prims, prim, r, rg[0], rg[1]);
        assert_int_equal(got.surf, want.surf);
        if (want.surf != CSG_SURF_NONE) {
            assert_memory_equal(&got.t, &want.t, sizeof got.t);
            hits++;
        }
    }
    assert_true(hits > 2000);
}

/* ---- boxes of zero thickness (sheets) ------------------------------------------ */

static int add_flat_box(scene *s, int flags, real x0, real y0, real z0, real x1, real y1, real z1)
{
    real p[6] = {x0, y0, z0, x1, y1, z1};
    return add_prim(s, CSG_PRIM_FLAT_BOX, flags, p, 6);
}

/* The sheet z = 0, |x|, |y| <= 1 (prim 0) alone as root 0. */
static void one_sheet(scene *s)
{
    scene_init(s);
    add_flat_box(s, 0, -1, -1, 0, 1, 1, 0);
    ROOT(s, 0);
}

/* Met from both sides, each time on the face that looks at the ray (the
 * face POV-Ray's Intersect_Box reports first), its edges included; a line
 * in its plane meets it where it enters the rectangle. */
static void test_flat_box_sides(void **state)
{
    (void)state;
    scene s;
    one_sheet(&s);
    csg_hit h = nearest(&s, ray(R(0.25), R(0.5), -2, 0, 0, 1));
    assert_true(h.t == R(2.0) && h.surf == S(0, CSG_SURF_BOX_NEG_X + 4));
    NEAR_V(csg_surface_normal(s.prims, h.surf, v3(R(0.25), R(0.5), 0)), 0, 0, -1, 0);
    h = nearest(&s, ray(R(0.25), R(0.5), 3, 0, 0, -1));
    assert_true(h.t == R(3.0) && h.surf == S(0, CSG_SURF_BOX_NEG_X + 5));
    NEAR_V(csg_surface_normal(s.prims, h.surf, v3(R(0.25), R(0.5), 0)), 0, 0, 1, 0);
    /* slanted, through the corner, just past the edge */
    h = nearest(&s, ray(-3, 0, -2, R(1.0), R(0.5), R(1.0)));
    assert_true(h.t == R(2.0) && h.surf == S(0, 4));
    assert_true(nearest(&s, ray(1, 1, -2, 0, 0, 1)).surf == S(0, 4));
    assert_true(nearest(&s, ray(R(1.001), 0, -2, 0, 0, 1)).surf == CSG_SURF_NONE);
    /* parallel to the sheet: in its plane (met at x = -1), beside it (not) */
    h = nearest(&s, ray(-3, R(0.5), 0, 1, 0, 0));
    assert_true(h.t == R(2.0) && h.surf != CSG_SURF_NONE);
    assert_true(nearest(&s, ray(-3, R(0.5), R(0.001), 1, 0, 0)).surf == CSG_SURF_NONE);
    /* from the sheet itself (t = 0 is not after tmin) */
    assert_true(nearest(&s, ray(0, 0, 0, 0, 0, 1)).surf == CSG_SURF_NONE);
    /* a box flat in two axes: a segment no ray across it meets */
    scene_init(&s);
    add_flat_box(&s, 0, -1, 0, 0, 1, 0, 0);
    ROOT(&s, 0);
    assert_true(nearest(&s, ray(R(0.25), R(0.1), -2, 0, 0, 1)).surf == CSG_SURF_NONE);
}

/* As a CSG operand a sheet is a surface (POV-Ray's closed inside test
 * holds nothing but the sheet): intersection { sheet sphere } is the disc
 * inside the sphere, difference { sheet sphere } the sheet with a hole,
 * difference { sphere sheet } the sphere, with the sheet inside it. */
static void test_flat_box_csg(void **state)
{
    (void)state;
    scene s;
    scene_init(&s);
    add_flat_box(&s, 0, -1, -1, 0, 1, 1, 0);
    add_sphere(&s, 0, 0, 0, 0, R(0.5));
    ROOT(&s, 0, 1, I);
    csg_hit h = nearest(&s, ray(R(0.25), 0, -2, 0, 0, 1));
    assert_true(h.t == R(2.0) && h.surf == S(0, 4));
    assert_true(nearest(&s, ray(R(0.75), 0, -2, 0, 0, 1)).surf == CSG_SURF_NONE);

    scene_init(&s);
    add_flat_box(&s, 0, -1, -1, 0, 1, 1, 0);
    add_sphere(&s, CSG_PF_INVERT, 0, 0, 0, R(0.5));
    ROOT(&s, 0, 1, I);
    assert_true(nearest(&s, ray(R(0.25), 0, -2, 0, 0, 1)).surf == CSG_SURF_NONE);
    h = nearest(&s, ray(R(0.75), 0, -2, 0, 0, 1));
    assert_true(h.t == R(2.0) && h.surf == S(0, 4));

    scene_init(&s);
    add_sphere(&s, 0, 0, 0, 0, R(0.5));
    add_flat_box(&s, CSG_PF_INVERT, -1, -1, 0, 1, 1, 0);
    ROOT(&s, 0, 1, I);
    h = nearest(&s, ray(R(0.25), 0, -2, 0, 0, 1));
    assert_true(h.surf == S(0, CSG_SURF_SPHERE) && h.t < R(2.0));
    h = nearest(&s, ray(R(0.25), 0, R(-0.1), 0, 0, 1)); /* from inside the sphere */
    assert_true(h.surf == S(1, 4));
    NEAR(h.t, 0.1, 1e-6);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_union),
        cmocka_unit_test(test_intersection),
        cmocka_unit_test(test_difference),
        cmocka_unit_test(test_nested),
        cmocka_unit_test(test_inverted_leaf),
        cmocka_unit_test(test_touching),
        cmocka_unit_test(test_identical_difference),
        cmocka_unit_test(test_flush_faces),
        cmocka_unit_test(test_nearest_roots),
        cmocka_unit_test(test_tmin_tmax),
        cmocka_unit_test(test_span_limit),
        cmocka_unit_test(test_span_algebra),
        cmocka_unit_test(test_spans_push),
        cmocka_unit_test(test_box_overlaps),
        cmocka_unit_test(test_box_ray_edges),
        cmocka_unit_test(test_box_ray_conservative),
        cmocka_unit_test(test_leaf_fast_path),
        cmocka_unit_test(test_flat_box_sides),
        cmocka_unit_test(test_flat_box_csg),
        cmocka_unit_test(test_clip_and_bound),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
