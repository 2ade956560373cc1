/*
 * intersect_lanes.h — the ray/primitive tests and the single-primitive hit,
 * lane-generic (lanes.h): included by intersect.h for one ray
 * (csg_sphere_span, csg_leaf_first_hit, ...) and by simd_kernels/packet.h
 * for a packet (csg_sphere_span_pk, ...).  No include guard: each
 * inclusion is one compilation of the template.
 *
 * Each test is the one-ray algorithm with its branches turned into masks
 * (lanes.h): a lane gets exactly the bits the one ray gets, and the
 * one-ray compilation keeps its early returns through L_ANY.  What a lane
 * returns beyond its mask (t0, t1, s0, s1 where the test says "no hit") is
 * unspecified, as it always was.
 */
#include "lanes.h"

typedef struct {
    L_VEC3 o; /* origin    */
    L_VEC3 d; /* direction (unit length for camera and secondary rays) */
} L_RAY;

typedef struct {
    L_REAL t;    /* ray parameter of the hit                  */
    L_UINT surf; /* packed surface id, CSG_SURF_NONE: no hit */
} L_HIT;

/* ---- affine transforms ------------------------------------------------ */

CSG_FN L_VEC3 L_FN(csg_xform_point)(CSG_GLOBAL const real *m, L_VEC3 p)
{
    return L_FN(v3)(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
                    m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                    m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}

CSG_FN L_VEC3 L_FN(csg_xform_vector)(CSG_GLOBAL const real *m, L_VEC3 v)
{
    return L_FN(v3)(m[0] * v.x + m[1] * v.y + m[2] * v.z,
                    m[4] * v.x + m[5] * v.y + m[6] * v.z,
                    m[8] * v.x + m[9] * v.y + m[10] * v.z);
}

CSG_FN L_RAY L_FN(csg_ray_to_local)(CSG_GLOBAL const csg_prim *p, L_RAY r)
{
    if (p->flags & CSG_PF_XFORM) {
        L_RAY l;
        l.o = L_FN(csg_xform_point)(p->inv, r.o);
        l.d = L_FN(csg_xform_vector)(p->inv, r.d);
        return l;
    }
    return r;
}

/* ---- one primitive: the interval of the whole ray line ------------------
 * Each returns its mask (the line meets the solid) and sets [*t0, *t1]
 * with the sub-surfaces of both ends there; ends may be -inf / +inf
 * (sub = -1 there). */

/* Ray/sphere after Haines et al., "Precision Improvements for Ray/Sphere
 * Intersection" (Ray Tracing Gems, ch. 7): the discriminant comes from the
 * distance of the centre to the line, and the far root from c / q, so
 * neither cancels catastrophically for small spheres far away. */
CSG_FN L_INT L_FN(csg_sphere_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                   L_INT *s0, L_INT *s1)
{
    L_VEC3 f = L_FN(v3_sub)(r.o, L_FN(v3_load)(p));
    real radius = p[3];
    L_REAL a = L_FN(v3_dot)(r.d, r.d);
    L_REAL b = L_FN(v3_dot)(f, r.d);
    L_INT ok = a > R(0.0);
    if (!L_ANY(ok))
        return ok;
    L_VEC3 l = L_FN(v3_sub)(f, L_FN(v3_scale)(r.d, b / a));
    L_REAL h = radius * radius - L_FN(v3_dot)(l, l);
    ok = ok & !(h < R(0.0));
    if (!L_ANY(ok))
        return ok;
    L_REAL root = L_SQRT(a * h);
    L_REAL q = L_SEL(b >= R(0.0), -(b + root), -(b - root));
    L_REAL c = L_FN(v3_dot)(f, f) - radius * radius;
    L_REAL ta = q / a;
    L_REAL tb = L_SEL(q != R(0.0), c / q, ta);
    *t0 = L_FN(r_fmin)(ta, tb);
    *t1 = L_FN(r_fmax)(ta, tb);
    *s0 = L_IS(CSG_SURF_SPHERE);
    *s1 = L_IS(CSG_SURF_SPHERE);
    return ok;
}

/* Narrow [*lo, *hi] by the slab lo_b <= o + t d <= hi_b of one axis: a
 * line parallel to the slab (d == 0) leaves the range as it is and is in
 * or out as a whole. */
CSG_FN L_INT L_FN(csg_slab)(L_REAL o, L_REAL d, real lo_b, real hi_b, csg_i32 axis, L_REAL *lo,
                            L_REAL *hi, L_INT *s_lo, L_INT *s_hi)
{
    L_INT flat = d == R(0.0);
    L_REAL ta = (lo_b - o) / d;
    L_REAL tb = (hi_b - o) / d;
    L_INT swap = ta > tb;
    L_REAL near = L_SEL(swap, tb, ta), far = L_SEL(swap, ta, tb);
    L_INT f_near = L_SEL(swap, L_IS(2 * axis + 1), L_IS(2 * axis));
    L_INT f_far = L_SEL(swap, L_IS(2 * axis), L_IS(2 * axis + 1));
    L_INT up_lo = (!flat) & (near > *lo);
    L_INT up_hi = (!flat) & (far < *hi);
    *lo = L_SEL(up_lo, near, *lo);
    *s_lo = L_SEL(up_lo, f_near, *s_lo);
    *hi = L_SEL(up_hi, far, *hi);
    *s_hi = L_SEL(up_hi, f_far, *s_hi);
    return L_SEL(flat, (o >= lo_b) & (o <= hi_b), *lo <= *hi);
}

/* The three slabs of box p narrowing the whole line: the mask before the
 * ends are compared (csg_box_span, csg_flat_box_span). */
CSG_FN L_INT L_FN(csg_box_slabs)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                 L_INT *s0, L_INT *s1)
{
    *t0 = L_RS(-CSG_R_INF);
    *t1 = L_RS(CSG_R_INF);
    *s0 = L_IS(-1);
    *s1 = L_IS(-1);
    L_INT ok = L_FN(csg_slab)(r.o.x, r.d.x, p[0], p[3], 0, t0, t1, s0, s1);
    if (!L_ANY(ok))
        return ok;
    ok = ok & L_FN(csg_slab)(r.o.y, r.d.y, p[1], p[4], 1, t0, t1, s0, s1);
    if (!L_ANY(ok))
        return ok;
    return ok & L_FN(csg_slab)(r.o.z, r.d.z, p[2], p[5], 2, t0, t1, s0, s1);
}

CSG_FN L_INT L_FN(csg_box_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                L_INT *s0, L_INT *s1)
{
    L_INT ok = L_FN(csg_box_slabs)(p, r, t0, t1, s0, s1);
    return ok & (*t0 < *t1);
}

/* A flat box (flat.h: a box with lo == hi on some axis, a surface kind):
 * POV-Ray's Intersect_Box accepts tmin == tmax, so the sheet is met where
 * the ray crosses its plane inside the closed rectangle.  The crossing is
 * t0 == t1 on the face of the flat axis that looks at the ray (the + face
 * when the ray runs towards -axis: POV-Ray's smin), on both sides.  A line
 * lying in the sheet's plane meets it where it enters the rectangle. */
CSG_FN L_INT L_FN(csg_flat_box_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                     L_INT *s0, L_INT *s1)
{
    L_INT ok = L_FN(csg_box_slabs)(p, r, t0, t1, s0, s1);
    ok = ok & (*t0 <= *t1);
    csg_i32 axis = 2;
    L_REAL d = r.d.z;
    if (p[0] == p[3]) {
        axis = 0;
        d = r.d.x;
    } else if (p[1] == p[4]) {
        axis = 1;
        d = r.d.y;
    }
    *t1 = *t0;
    *s0 = L_SEL(d < R(0.0), L_IS(2 * axis + 1), L_IS(2 * axis));
    *s1 = *s0;
    return ok;
}

/* Truncated cone (or cylinder) along local z in [0, h], radius
 * r(z) = r0 + k z.  The solid is the slab 0 <= z <= h intersected with
 * x^2 + y^2 <= r(z)^2, which inside the slab is the one nappe we want.
 * The quadratic's set on the line is one interval (A > 0), the line minus
 * one interval (A < 0) or a half-line (A == 0); clipped by the slab the
 * result is a single interval because the frustum is convex.  The cases
 * below are the one-ray code's if/else chain, each a mask. */
CSG_FN L_INT L_FN(csg_cone_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                 L_INT *s0, L_INT *s1)
{
    real r0 = p[0], h = p[2];
    real k = (p[1] - p[0]) / h;
    /* the slab 0 <= z <= h */
    L_INT flat = r.d.z == R(0.0);
    L_INT ok = (!flat) | ((r.o.z >= R(0.0)) & (r.o.z <= h));
    if (!L_ANY(ok))
        return ok;
    L_REAL ta = (R(0.0) - r.o.z) / r.d.z;
    L_REAL tb = (h - r.o.z) / r.d.z;
    L_INT up = ta < tb;
    L_REAL lo = L_SEL(flat, L_RS(-CSG_R_INF), L_FN(r_fmin)(ta, tb));
    L_REAL hi = L_SEL(flat, L_RS(CSG_R_INF), L_FN(r_fmax)(ta, tb));
    L_INT slo = L_SEL(flat, L_IS(-1),
                      L_SEL(up, L_IS(CSG_SURF_CONE_BASE), L_IS(CSG_SURF_CONE_TOP)));
    L_INT shi = L_SEL(flat, L_IS(-1),
                      L_SEL(up, L_IS(CSG_SURF_CONE_TOP), L_IS(CSG_SURF_CONE_BASE)));
    /* Solve in u = t - tc from o = o + tc d, the closest approach to the
     * axis kept within the slab's range: there the terms have the size of
     * the solid, so b*b - a*c does not cancel catastrophically as it does
     * from a far origin (as for the sphere above). */
    L_REAL dxy = r.d.x * r.d.x + r.d.y * r.d.y;
    L_REAL tc = L_SEL(dxy > R(0.0), -(r.o.x * r.d.x + r.o.y * r.d.y) / dxy, L_RS(R(0.0)));
    tc = L_FN(r_fmin)(L_FN(r_fmax)(tc, lo), hi);
    L_VEC3 o = L_FN(v3_madd)(r.o, r.d, tc);
    L_REAL rz = r0 + k * o.z; /* radius at that height */
    L_REAL a = dxy - k * k * r.d.z * r.d.z;
    L_REAL b = o.x * r.d.x + o.y * r.d.y - k * rz * r.d.z;
    L_REAL c = o.x * o.x + o.y * o.y - rz * rz;
    /* inside the quadratic: a t^2 + 2 b t + c <= 0 */
    L_INT linear = a == R(0.0);
    L_INT b_zero = b == R(0.0), b_pos = b > R(0.0);
    L_REAL disc = b * b - a * c;
    L_INT no_root = (!linear) & (disc < R(0.0));
    L_INT a_pos = a > R(0.0);
    ok = ok & !(linear & b_zero & (c > R(0.0))) & !(no_root & a_pos);
    if (!L_ANY(ok))
        return ok;
    /* linear, b != 0: a half-line ending at -c / 2b */
    L_REAL t_lin = L_RS(R(0.0));
    if (L_ANY(linear))
        t_lin = tc + -c / (R(2.0) * b);
    L_INT lin_hi = linear & (!b_zero) & b_pos;  /* (-inf, t_lin] */
    L_INT lin_lo = linear & (!b_zero) & (!b_pos); /* [t_lin, inf)  */
    /* two roots u0 <= u1 */
    L_INT roots = (!linear) & (!no_root);
    L_REAL u0 = L_RS(R(0.0)), u1 = L_RS(R(0.0));
    L_INT keep0 = L_IS(0);
    if (L_ANY(roots)) {
        L_REAL root = L_SQRT(disc);
        L_REAL q = L_SEL(b >= R(0.0), -(b + root), -(b - root));
        L_REAL ra = q / a;
        L_REAL rb = L_SEL(q != R(0.0), c / q, ra);
        u0 = tc + L_FN(r_fmin)(ra, rb);
        u1 = tc + L_FN(r_fmax)(ra, rb);
        /* a < 0: (-inf, u0] or [u1, inf), the piece inside the slab */
        L_REAL len0 = L_FN(r_fmin)(u0, hi) - lo;
        L_REAL len1 = hi - L_FN(r_fmax)(u1, lo);
        keep0 = len0 >= len1;
    }
    L_INT in = roots & a_pos;              /* [u0, u1]      */
    L_INT out0 = roots & (!a_pos) & keep0;   /* (-inf, u0]    */
    L_INT out1 = roots & (!a_pos) & (!keep0);  /* [u1, inf)     */
    L_REAL qa = L_SEL(lin_lo, t_lin, L_SEL(in, u0, L_SEL(out1, u1, L_RS(-CSG_R_INF))));
    L_REAL qb = L_SEL(lin_hi, t_lin, L_SEL(in, u1, L_SEL(out0, u0, L_RS(CSG_R_INF))));
    L_INT sa = L_SEL(lin_lo | in | out1, L_IS(CSG_SURF_CONE_SIDE), L_IS(-1));
    L_INT sb = L_SEL(lin_hi | in | out0, L_IS(CSG_SURF_CONE_SIDE), L_IS(-1));
    L_INT up_lo = qa > lo, up_hi = qb < hi;
    *t0 = L_SEL(up_lo, qa, lo);
    *s0 = L_SEL(up_lo, sa, slo);
    *t1 = L_SEL(up_hi, qb, hi);
    *s1 = L_SEL(up_hi, sb, shi);
    return ok & (*t0 < *t1);
}

CSG_FN L_INT L_FN(csg_plane_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                  L_INT *s0, L_INT *s1)
{
    L_VEC3 n = L_FN(v3_load)(p);
    L_REAL dn = L_FN(v3_dot)(n, r.d);
    L_REAL side = p[3] - L_FN(v3_dot)(n, r.o); /* > 0: origin inside */
    L_INT flat = dn == R(0.0);
    L_INT exits = (!flat) & (dn > R(0.0));  /* [-inf, t]  */
    L_INT enters = (!flat) & !(dn > R(0.0)); /* [t, inf]  */
    L_REAL t = side / dn;
    *t0 = L_SEL(enters, t, L_RS(-CSG_R_INF));
    *t1 = L_SEL(exits, t, L_RS(CSG_R_INF));
    *s0 = L_SEL(enters, L_IS(CSG_SURF_PLANE), L_IS(-1));
    *s1 = L_SEL(exits, L_IS(CSG_SURF_PLANE), L_IS(-1));
    return (!flat) | (side > R(0.0));
}

/* Narrow [*lo, *hi] by the half-line where f0 + t fd >= 0 (sub-surface
 * `sub` at its end): a line parallel to it (fd == 0) is in or out as a
 * whole.  Two pieces that share the line compute the same f0 and fd with
 * opposite signs, hence the same t. */
CSG_FN L_INT L_FN(csg_half)(L_REAL f0, L_REAL fd, csg_i32 sub, L_REAL *lo, L_REAL *hi,
                            L_INT *s_lo, L_INT *s_hi)
{
    L_INT flat = fd == R(0.0);
    L_REAL t = -f0 / fd;
    L_INT up_lo = (!flat) & (fd > R(0.0)) & (t > *lo);
    L_INT up_hi = (!flat) & (fd < R(0.0)) & (t < *hi);
    *lo = L_SEL(up_lo, t, *lo);
    *s_lo = L_SEL(up_lo, L_IS(sub), *s_lo);
    *hi = L_SEL(up_hi, t, *hi);
    *s_hi = L_SEL(up_hi, L_IS(sub), *s_hi);
    return L_SEL(flat, f0 >= R(0.0), *lo <= *hi);
}

/* A trapezoid piece of an extruded outline (flat.h): the z slab [0, 1],
 * the y slab [p[6], p[7]] and its two sides, each side the half-plane
 * n . (x, y) >= c. */
CSG_FN L_INT L_FN(csg_trapezoid_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                      L_INT *s0, L_INT *s1)
{
    *t0 = L_RS(-CSG_R_INF);
    *t1 = L_RS(CSG_R_INF);
    *s0 = L_IS(-1);
    *s1 = L_IS(-1);
    L_INT ok = L_FN(csg_slab)(r.o.z, r.d.z, R(0.0), R(1.0), 2, t0, t1, s0, s1);
    if (!L_ANY(ok))
        return ok;
    ok = ok & L_FN(csg_slab)(r.o.y, r.d.y, p[6], p[7], 1, t0, t1, s0, s1);
    if (!L_ANY(ok))
        return ok;
    for (csg_i32 k = 0; k < 2; k++) {
        real nx = p[3 * k], ny = p[3 * k + 1], c = p[3 * k + 2];
        L_REAL f0 = nx * r.o.x + ny * r.o.y - c;
        L_REAL fd = nx * r.d.x + ny * r.d.y;
        ok = ok & L_FN(csg_half)(f0, fd, CSG_SURF_TRAP_SIDE_A + k, t0, t1, s0, s1);
    }
    return ok & (*t0 < *t1);
}

/* A piece of a conic prism (flat.h): every bound a half-space
 * f0 + t fd >= 0 through the apex but the z slab.  Two pieces on the same
 * edge or height compute the same f0 and fd, or their exact negations. */
CSG_FN L_INT L_FN(csg_conic_trapezoid_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0,
                                            L_REAL *t1, L_INT *s0, L_INT *s1)
{
    *t0 = L_RS(-CSG_R_INF);
    *t1 = L_RS(CSG_R_INF);
    *s0 = L_IS(-1);
    *s1 = L_IS(-1);
    L_INT ok = L_FN(csg_slab)(r.o.z, r.d.z, p[6], R(1.0), 2, t0, t1, s0, s1);
    if (!L_ANY(ok))
        return ok;
    ok = ok & L_FN(csg_half)(r.o.y - p[4] * r.o.z, r.d.y - p[4] * r.d.z, 2, t0, t1, s0, s1);
    ok = ok & L_FN(csg_half)(p[5] * r.o.z - r.o.y, p[5] * r.d.z - r.d.y, 3, t0, t1, s0, s1);
    L_REAL la = p[0] * r.o.y + p[1] * r.o.z, lb = p[0] * r.d.y + p[1] * r.d.z;
    ok = ok & L_FN(csg_half)(r.o.x - la, r.d.x - lb, CSG_SURF_TRAP_SIDE_A, t0, t1, s0, s1);
    L_REAL ra = p[2] * r.o.y + p[3] * r.o.z, rb = p[2] * r.d.y + p[3] * r.d.z;
    ok = ok & L_FN(csg_half)(ra - r.o.x, rb - r.d.x, CSG_SURF_TRAP_SIDE_B, t0, t1, s0, s1);
    return ok & (*t0 < *t1);
}

#ifdef CSG_LANES_PACKET
/* A torus is never a root alone (flat.h: the flattener joins its two
 * pieces by union) and the packet kernel evaluates CSG programs through
 * the one-ray code (packet.h, pk_try_root): never called. */
CSG_FN L_INT L_FN(csg_torus_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                  L_INT *s0, L_INT *s1)
{
    (void)p;
    (void)r;
    (void)t0;
    (void)t1;
    (void)s0;
    (void)s1;
    return L_IS(0);
}

/* The same holds for a quadric (flat.h). */
CSG_FN L_INT L_FN(csg_quadric_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                    L_INT *s0, L_INT *s1)
{
    return L_FN(csg_torus_span)(p, r, t0, t1, s0, s1);
}

/* And for a poly (flat.h). */
CSG_FN L_INT L_FN(csg_poly_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                 L_INT *s0, L_INT *s1)
{
    return L_FN(csg_torus_span)(p, r, t0, t1, s0, s1);
}
#else
#if CSG_USE_TORUS
/* The quartic of the torus (flat.h) along the line, in double precision:
 * x is the distance from the line's point nearest the centre, in units of
 * the bounding sphere's radius S = R + r, so every root lies in [-1, 1]
 * and the coefficients have the size of the torus however far the
 * origin is (POV-Ray moves the origin towards the torus for the same
 * reason).  q[i] is the coefficient of x^i; *tc the nearest point's
 * parameter along the unit direction, c[] that point, *xr the chord's
 * half length (0: the line misses the sphere). */
CSG_FN void csg_torus_quartic(CSG_GLOBAL const real *p, const double *o, const double *u,
                              double *q, double *tc, double *c, double *xr)
{
    double big = (double)p[0], small = (double)p[1], s = big + small;
    *tc = -(o[0] * u[0] + o[1] * u[1] + o[2] * u[2]);
    c[0] = o[0] + *tc * u[0];
    c[1] = o[1] + *tc * u[1];
    c[2] = o[2] + *tc * u[2];
    double cc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    double h2 = s * s - cc;
    *xr = h2 > 0.0 ? sqrt(h2) / s : 0.0;
    /* |X|^2 - R^2 - r^2 and X.u along X = c + w u, w = s x (POV-Ray's
     * Torus::Intersect with the origin at c) */
    double rr = big * big, k1 = cc - rr - small * small, k2 = c[0] * u[0] + c[1] * u[1] + c[2] * u[2];
    double w[5];
    w[4] = 1.0;
    w[3] = 4.0 * k2;
    w[2] = 2.0 * (k1 + 2.0 * (k2 * k2 + rr * u[1] * u[1]));
    w[1] = 4.0 * (k2 * k1 + 2.0 * rr * c[1] * u[1]);
    w[0] = k1 * k1 + 4.0 * rr * (c[1] * c[1] - small * small);
    double scale = 1.0;
    for (csg_i32 i = 4; i >= 0; i--) {
        q[i] = w[i] * scale; /* w[i] s^i / s^4 */
        scale = scale / s;
    }
}

/* Is the point c + w u inside the tube, (rho - R)^2 + y^2 < r^2?  (The
 * quartic is that times (rho + R)^2 + y^2 - r^2, which is negative only
 * in a spindle torus's spindle: POV-Ray's default spindle mode, union,
 * counts the spindle inside, as this does.) */
CSG_FN int csg_torus_inside(CSG_GLOBAL const real *p, const double *c, const double *u, double w)
{
    double x = c[0] + w * u[0], y = c[1] + w * u[1], z = c[2] + w * u[2];
    double ring = sqrt(x * x + z * z) - (double)p[0], small = (double)p[1];
    return ring * ring + y * y < small * small;
}

/* Piece p[2] of the torus: the p[2]-th interval of the line inside it
 * (the roots cut the chord into runs; a run is inside where its middle
 * is, csg_torus_inside; touching inside runs merge, so neither a grazing
 * ray's double root nor a spindle's surface splits anything). */
CSG_FN csg_i32 csg_torus_span(CSG_GLOBAL const real *p, csg_ray r, real *t0, real *t1,
                              csg_i32 *s0, csg_i32 *s1)
{
    double d[3] = {(double)r.d.x, (double)r.d.y, (double)r.d.z};
    double o[3] = {(double)r.o.x, (double)r.o.y, (double)r.o.z};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(len > 0.0) || !(p[0] > R(0.0)) || !(p[1] > R(0.0)))
        return 0;
    double u[3] = {d[0] / len, d[1] / len, d[2] / len};
    double q[5], tc, c[3], xr;
    csg_torus_quartic(p, o, u, q, &tc, c, &xr);
    if (!(xr > 0.0))
        return 0;
    xr = xr + 1e-6; /* the chord's ends strictly outside the torus */
    double cut[6];
    csg_i32 n = csg_poly_roots(q, 4, -xr, xr, cut + 1);
    cut[0] = -xr;
    cut[n + 1] = xr;
    csg_i32 want = p[2] == R(1.0) ? 1 : 0, runs = 0;
    double a = 0.0, b = 0.0, s = (double)p[0] + (double)p[1];
    int open = 0, found = 0;
    for (csg_i32 k = 0; k <= n && !found; k++) {
        int in = csg_torus_inside(p, c, u, s * 0.5 * (cut[k] + cut[k + 1]));
        if (in && !open) {
            a = cut[k];
            open = 1;
        }
        if (open && (!in || k == n)) { /* the run ended at cut[k] (or at the chord's end) */
            b = in ? cut[k + 1] : cut[k];
            open = 0;
            found = runs == want;
            runs++;
        }
    }
    if (!found)
        return 0;
    *t0 = (real)((tc + s * a) / len);
    *t1 = (real)((tc + s * b) / len);
    *s0 = CSG_SURF_TORUS;
    *s1 = CSG_SURF_TORUS;
    return *t0 < *t1;
}
#else /* (a program without tori: no double arithmetic, poly_solve.h) */
CSG_FN csg_i32 csg_torus_span(CSG_GLOBAL const real *p, csg_ray r, real *t0, real *t1,
                              csg_i32 *s0, csg_i32 *s1)
{
    (void)p;
    (void)r;
    (void)t0;
    (void)t1;
    (void)s0;
    (void)s1;
    return 0;
}
#endif

#if CSG_USE_QUADRIC
/* Piece p[10] of the quadric (flat.h): its set f <= 0 on the line, f(t) =
 * a t^2 + 2 b t + c in double (POV-Ray's Quadric::Intersect), is one
 * interval, the line minus one (two half-lines), a half-line, the whole
 * line or nothing; piece 0 is the first of those intervals, piece 1 the
 * second.  The roots by the stable form (q = -(b + sign(b) sqrt(disc)),
 * roots q / a and c / q).  An unbounded end is -inf / +inf, sub -1. */
CSG_FN csg_i32 csg_quadric_span(CSG_GLOBAL const real *p, csg_ray r, real *t0, real *t1,
                                csg_i32 *s0, csg_i32 *s1)
{
    double qa = (double)p[0], qb = (double)p[1], qc = (double)p[2], qd = (double)p[3];
    double qe = (double)p[4], qf = (double)p[5], qg = (double)p[6], qh = (double)p[7];
    double qi = (double)p[8], qj = (double)p[9];
    double ox = (double)r.o.x, oy = (double)r.o.y, oz = (double)r.o.z;
    double dx = (double)r.d.x, dy = (double)r.d.y, dz = (double)r.d.z;
    double a = dx * (qa * dx + qd * dy + qe * dz) + dy * (qb * dy + qf * dz) + dz * qc * dz;
    double b = dx * (qa * ox + 0.5 * (qd * oy + qe * oz + qg)) +
               dy * (qb * oy + 0.5 * (qd * ox + qf * oz + qh)) +
               dz * (qc * oz + 0.5 * (qe * ox + qf * oy + qi));
    double c = ox * (qa * ox + qd * oy + qe * oz + qg) + oy * (qb * oy + qf * oz + qh) +
               oz * (qc * oz + qi) + qj;
    double inf = (double)CSG_R_INF, lo[2] = {-inf, inf}, hi[2] = {inf, inf};
    csg_i32 n = 0;
    if (a == 0.0) { /* linear: 2 b t + c <= 0 */
        if (b != 0.0) {
            double t = -0.5 * c / b;
            lo[0] = b > 0.0 ? -inf : t;
            hi[0] = b > 0.0 ? t : inf;
            n = 1;
        } else {
            n = c <= 0.0 ? 1 : 0; /* the whole line, or nothing */
        }
    } else {
        double disc = b * b - a * c;
        if (disc > 0.0) {
            double root = sqrt(disc);
            double q = b >= 0.0 ? -(b + root) : -(b - root);
            double ra = q / a, rb = q != 0.0 ? c / q : ra;
            double u = ra < rb ? ra : rb, v = ra < rb ? rb : ra;
            if (a > 0.0) { /* [u, v] */
                lo[0] = u;
                hi[0] = v;
                n = 1;
            } else { /* (-inf, u] and [v, inf) */
                hi[0] = u;
                lo[1] = v;
                n = 2;
            }
        } else {
            n = a < 0.0 ? 1 : 0; /* f < 0 everywhere, or nowhere below 0 */
        }
    }
    csg_i32 want = p[10] == R(1.0) ? 1 : 0;
    if (want >= n)
        return 0;
    *t0 = (real)lo[want];
    *t1 = (real)hi[want];
    *s0 = lo[want] == -inf ? -1 : CSG_SURF_QUADRIC;
    *s1 = hi[want] == inf ? -1 : CSG_SURF_QUADRIC;
    return *t0 < *t1;
}
#else /* (a program without quadrics) */
CSG_FN csg_i32 csg_quadric_span(CSG_GLOBAL const real *p, csg_ray r, real *t0, real *t1,
                                csg_i32 *s0, csg_i32 *s1)
{
    return csg_torus_span(p, r, t0, t1, s0, s1);
}
#endif

/* The coefficients of poly p (flat.h): the table's entries p[2] *
 * CSG_POLY_OFFSET_UNIT + p[3] reals on from p (the blob validator checks
 * that they lie in the table). */
CSG_FN CSG_GLOBAL const real *csg_poly_coefs(CSG_GLOBAL const real *p)
{
    return p + (csg_i32)p[2] * CSG_POLY_OFFSET_UNIT + (csg_i32)p[3];
}

#if CSG_USE_POLY
#define CSG_POLY_FAR 1e7 /* roots farther along the line (local units) are
                            not sought: POV-Ray's MAX_DISTANCE */

/* The poly of order n along the line X(w) = c + w u, in double: q[h] the
 * coefficient of w^h (POV-Ray's Poly::intersect, about c).  pw[a][e] is
 * (c_a + u_a w)^e; term x^i y^j z^k adds its coefficient times the
 * product of the three. */
CSG_FN void csg_poly_on_line(CSG_GLOBAL const real *p, csg_i32 n, const double *c,
                             const double *u, double *q)
{
    double pw[3][CSG_POLY_MAX_ORDER + 1][CSG_POLY_MAX_ORDER + 1];
    for (csg_i32 a = 0; a < 3; a++) {
        pw[a][0][0] = 1.0;
        for (csg_i32 e = 1; e <= n; e++)
            for (csg_i32 h = 0; h <= e; h++)
                pw[a][e][h] = (h < e ? pw[a][e - 1][h] * c[a] : 0.0) +
                              (h > 0 ? pw[a][e - 1][h - 1] * u[a] : 0.0);
    }
    for (csg_i32 h = 0; h <= n; h++)
        q[h] = 0.0;
    CSG_GLOBAL const real *coef = csg_poly_coefs(p);
    csg_i32 term = 0;
    for (csg_i32 i = n; i >= 0; i--)
        for (csg_i32 j = n - i; j >= 0; j--)
            for (csg_i32 k = n - i - j; k >= 0; k--) {
                double a = (double)coef[term++];
                if (a == 0.0)
                    continue;
                double xy[CSG_POLY_MAX_ORDER + 1];
                for (csg_i32 h = 0; h <= i + j; h++)
                    xy[h] = 0.0;
                for (csg_i32 h1 = 0; h1 <= i; h1++)
                    for (csg_i32 h2 = 0; h2 <= j; h2++)
                        xy[h1 + h2] = xy[h1 + h2] + pw[0][i][h1] * pw[1][j][h2];
                for (csg_i32 h1 = 0; h1 <= i + j; h1++)
                    for (csg_i32 h3 = 0; h3 <= k; h3++)
                        q[h1 + h3] = q[h1 + h3] + a * xy[h1] * pw[2][k][h3];
            }
}

/* Piece p[1] of the poly (flat.h): the p[1]-th interval of the line where
 * the poly is < 0.  The line is written from its point c nearest the
 * local origin, w the distance along it in local units (as POV-Ray's
 * Poly::intersect: a poly's own units are the ones its coefficients are
 * written for; scaling w by a root bound would crush the near roots of a
 * line whose leading coefficient almost vanishes); its roots lie within
 * Cauchy's bound B = 1 + max |q_i / q_n| of c, sought up to CSG_POLY_FAR.
 * The roots cut the line into runs; a run is inside where the poly is
 * negative at its middle; touching inside runs merge (a double root
 * splits nothing); a run that reaches past B is unbounded there (-inf /
 * +inf, sub -1). */
CSG_FN csg_i32 csg_poly_span(CSG_GLOBAL const real *p, csg_ray r, real *t0, real *t1,
                             csg_i32 *s0, csg_i32 *s1)
{
    csg_i32 n = (csg_i32)p[0];
    double d[3] = {(double)r.d.x, (double)r.d.y, (double)r.d.z};
    double o[3] = {(double)r.o.x, (double)r.o.y, (double)r.o.z};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(len > 0.0) || n < 1 || n > CSG_POLY_MAX_ORDER)
        return 0;
    double u[3] = {d[0] / len, d[1] / len, d[2] / len};
    double tc = -(o[0] * u[0] + o[1] * u[1] + o[2] * u[2]);
    double c[3] = {o[0] + tc * u[0], o[1] + tc * u[1], o[2] + tc * u[2]};
    double q[CSG_POLY_MAX_ORDER + 1];
    csg_poly_on_line(p, n, c, u, q);
    while (n > 0 && q[n] == 0.0)
        n--;
    double bound = 0.0;
    for (csg_i32 i = 0; i < n; i++) {
        double m = q[i] / q[n];
        m = m < 0.0 ? -m : m;
        bound = m > bound ? m : bound;
    }
    bound = bound + 1.0;
    if (!(bound < CSG_POLY_FAR))
        bound = CSG_POLY_FAR;
    double cut[CSG_POLY_MAX_ORDER + 2];
    csg_i32 m = n > 0 ? csg_poly_roots(q, n, -bound, bound, cut + 1) : 0;
    cut[0] = -bound;
    cut[m + 1] = bound;
    csg_i32 want = (csg_i32)p[1], runs = 0;
    csg_i32 ka = 0, kb = 0;
    int open = 0, found = 0;
    for (csg_i32 k = 0; k <= m && !found; k++) {
        int in = csg_poly_eval(q, n, 0.5 * (cut[k] + cut[k + 1])) < 0.0;
        if (in && !open) {
            ka = k;
            open = 1;
        }
        if (open && (!in || k == m)) { /* the run ended at cut[k] (or at the line's end) */
            kb = in ? k + 1 : k;
            open = 0;
            found = runs == want;
            runs++;
        }
    }
    if (!found)
        return 0;
    double inf = (double)CSG_R_INF;
    *t0 = ka == 0 ? (real)-inf : (real)((tc + cut[ka]) / len);
    *t1 = kb == m + 1 ? (real)inf : (real)((tc + cut[kb]) / len);
    *s0 = ka == 0 ? -1 : CSG_SURF_POLY;
    *s1 = kb == m + 1 ? -1 : CSG_SURF_POLY;
    return *t0 < *t1;
}
#else /* (a program without polys) */
CSG_FN csg_i32 csg_poly_span(CSG_GLOBAL const real *p, csg_ray r, real *t0, real *t1,
                             csg_i32 *s0, csg_i32 *s1)
{
    return csg_torus_span(p, r, t0, t1, s0, s1);
}
#endif
#endif

/* The component of v along axis k (0, 1, 2), k chosen per lane. */
CSG_FN L_REAL L_FN(csg_axis)(L_VEC3 v, L_INT k)
{
    return L_SEL(k == 0, v.x, L_SEL(k == 1, v.y, v.z));
}

/* A triangle (flat.h) crossed by the ray line: t0 == t1 = the crossing,
 * s0 == s1 = the side met (CSG_SURF_TRI_FRONT or _BACK).  Watertight
 * (Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT
 * 2013): the vertices are moved into the ray's frame (its dominant axis kz
 * as depth, kx and ky in the winding that keeps the sign), where the edge
 * functions are exact in sign for a shared edge.  The axes are picked per
 * lane; every operation is then the one-ray one. */
CSG_FN L_INT L_FN(csg_triangle_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0, L_REAL *t1,
                                     L_INT *s0, L_INT *s1)
{
    L_VEC3 a = L_FN(v3)(p[0] - r.o.x, p[1] - r.o.y, p[2] - r.o.z);
    L_VEC3 b = L_FN(v3)(p[3] - r.o.x, p[4] - r.o.y, p[5] - r.o.z);
    L_VEC3 c = L_FN(v3)(p[6] - r.o.x, p[7] - r.o.y, p[8] - r.o.z);
    L_REAL fx = L_FABS(r.d.x), fy = L_FABS(r.d.y), fz = L_FABS(r.d.z);
    L_INT kz = L_SEL(fx > fy, L_SEL(fx > fz, L_IS(0), L_IS(2)), L_SEL(fy > fz, L_IS(1), L_IS(2)));
    L_INT kx0 = L_SEL(kz == 2, L_IS(0), kz + 1);
    L_INT ky0 = L_SEL(kx0 == 2, L_IS(0), kx0 + 1);
    L_REAL dz = L_FN(csg_axis)(r.d, kz);
    L_INT swap = dz < R(0.0); /* keep the winding */
    L_INT kx = L_SEL(swap, ky0, kx0), ky = L_SEL(swap, kx0, ky0);
    L_REAL sx = L_FN(csg_axis)(r.d, kx) / dz, sy = L_FN(csg_axis)(r.d, ky) / dz;
    L_REAL sz = R(1.0) / dz;
    L_REAL az = L_FN(csg_axis)(a, kz), bz = L_FN(csg_axis)(b, kz), cz = L_FN(csg_axis)(c, kz);
    L_REAL ax = L_FN(csg_axis)(a, kx) - sx * az, ay = L_FN(csg_axis)(a, ky) - sy * az;
    L_REAL bx = L_FN(csg_axis)(b, kx) - sx * bz, by = L_FN(csg_axis)(b, ky) - sy * bz;
    L_REAL cx = L_FN(csg_axis)(c, kx) - sx * cz, cy = L_FN(csg_axis)(c, ky) - sy * cz;
    L_REAL u = cx * by - cy * bx;
    L_REAL v = ax * cy - ay * cx;
    L_REAL w = bx * ay - by * ax;
    L_INT outside = ((u < R(0.0)) | (v < R(0.0)) | (w < R(0.0))) &
                    ((u > R(0.0)) | (v > R(0.0)) | (w > R(0.0)));
    L_REAL det = u + v + w;
    L_REAL t = (u * (sz * az) + v * (sz * bz) + w * (sz * cz)) / det;
    L_INT hit = (dz != R(0.0)) & (!outside) & (det != R(0.0)) & (t == t);
    *t0 = t;
    *t1 = t;
    /* det > 0: the ray meets the side (v1 - v0) x (v2 - v0) points to */
    *s0 = L_SEL(det > R(0.0), L_IS(CSG_SURF_TRI_FRONT), L_IS(CSG_SURF_TRI_BACK));
    *s1 = *s0;
    return hit;
}

CSG_FN L_INT L_FN(csg_smooth_triangle_span)(CSG_GLOBAL const real *p, L_RAY r, L_REAL *t0,
                                            L_REAL *t1, L_INT *s0, L_INT *s1)
{
    return L_FN(csg_triangle_span)(p, r, t0, t1, s0, s1);
}

/* The interval of any primitive, dispatched by kind (flat.h's table); an
 * unknown kind has none (the blob validator lets none through), nor has a
 * kind this compilation leaves out (spec.h: the OpenCL host never gives
 * it a scene that has one). */
CSG_FN L_INT L_FN(csg_prim_span)(CSG_GLOBAL const csg_prim *p, L_RAY world, L_REAL *t0,
                                 L_REAL *t1, L_INT *s0, L_INT *s1)
{
    L_RAY r = L_FN(csg_ray_to_local)(p, world);
    switch (p->kind) {
#define CSG_SPAN_CASE(ID, name)                                                                    \
    case CSG_PRIM_##ID:                                                                            \
        if (CSG_USES_KIND(ID))                                                                     \
            return L_FN(csg_##name##_span)(p->p, r, t0, t1, s0, s1);                               \
        break;
        CSG_PRIM_KINDS(CSG_SPAN_CASE)
#undef CSG_SPAN_CASE
    default:
        break;
    }
    return L_IS(0);
}

/* ---- the hit of one primitive -------------------------------------------- */

/* The packed surface id of sub-surface `sub` of primitive `prim`;
 * CSG_SURF_NONE for no sub-surface (sub < 0), an open cone's caps and a
 * clip's surfaces (CSG_PF_CLIP); the
 * back of a one-sided surface is CSG_SURF_HIDDEN. */
CSG_FN L_UINT L_FN(csg_surf_of)(csg_i32 prim, L_INT sub, csg_u32 flip, csg_i32 flags)
{
    if (flags & CSG_PF_CLIP)
        return L_US(CSG_SURF_NONE);
    L_INT none = sub < 0;
    if (flags & CSG_PF_OPEN)
        none = none | (sub != CSG_SURF_CONE_SIDE);
    if (flags & CSG_PF_ONE_SIDED)
        sub = L_SEL(sub == CSG_SURF_TRI_BACK, L_IS(CSG_SURF_HIDDEN), sub);
    L_UINT packed = (((csg_u32)prim + 1u) << 4) | (L_TO_UINT(sub) << 1) | flip;
    return L_SEL(none, L_US(CSG_SURF_NONE), packed);
}

/* Can a ray that looks see surface s?  (Shadow rays see hidden ones.) */
CSG_FN L_INT L_FN(csg_surf_visible)(L_UINT s)
{
    return (s != CSG_SURF_NONE) & (((s >> 1) & 7u) != (csg_u32)CSG_SURF_HIDDEN);
}

/* The first visible boundary of one uncomplemented primitive on
 * (tmin, tmax): exactly csg_first_boundary(csg_leaf_spans(...)) of
 * intersect.h, without building the list (most roots are a single
 * primitive). */
CSG_FN L_HIT L_FN(csg_leaf_first_hit)(CSG_GLOBAL const csg_prim *prims, csg_i32 i, L_RAY r,
                                      L_REAL tmin, L_REAL tmax)
{
    CSG_GLOBAL const csg_prim *p = &prims[i];
    L_HIT h;
    h.t = L_RS(CSG_R_INF);
    h.surf = L_US(CSG_SURF_NONE);
    L_REAL t0, t1;
    L_INT s0, s1;
    L_INT ok = L_FN(csg_prim_span)(p, r, &t0, &t1, &s0, &s1);
    if (!L_ANY(ok))
        return h;
    if (CSG_USE_SURFACES && CSG_PRIM_IS_SURFACE(p->kind)) { /* an event, as
                                                                csg_surface_leaf_spans */
        L_UINT e = L_FN(csg_surf_of)(i, s0, 0u, p->flags);
        L_INT at = ok & (t0 > tmin) & (t0 <= tmax) & L_FN(csg_surf_visible)(e);
        h.t = L_SEL(at, t0, h.t);
        h.surf = L_SEL(at, e, h.surf);
        return h;
    }
    L_UINT e0 = L_SEL(t0 < tmin, L_US(CSG_SURF_NONE), L_FN(csg_surf_of)(i, s0, 0u, p->flags));
    L_UINT e1 = L_FN(csg_surf_of)(i, s1, 0u, p->flags);
    L_REAL start = L_FN(r_fmax)(t0, tmin), end = t1;
    L_INT clip = end > tmax; /* clipped by the list's limit, as csg_spans_push does */
    end = L_SEL(clip, tmax, end);
    e1 = L_SEL(clip, L_US(CSG_SURF_NONE), e1);
    ok = ok & (start < end);
    L_INT at0 = ok & (e0 != CSG_SURF_NONE) & (start > tmin);
    L_INT at1 = ok & (!at0) & (e1 != CSG_SURF_NONE) & (end > tmin);
    h.t = L_SEL(at0, start, L_SEL(at1, end, h.t));
    h.surf = L_SEL(at0, e0, L_SEL(at1, e1, h.surf));
    return h;
}

/* ---- the nearest hit: the rule every walk applies ------------------------- */

/* How far a root is worth evaluating against the best hit so far: up to
 * and including best->t once there is a hit, so that a surface exactly as
 * near is seen and the tie broken (csg_hit_wins). */
CSG_FN L_REAL L_FN(csg_hit_limit)(const L_HIT *best)
{
    return L_SEL(best->surf != CSG_SURF_NONE, L_NEXT_UP(best->t), best->t);
}

/* h replaces best: nearer, or as near with a lower surface id.  The winner
 * is then the same whatever order the roots are visited in (a packet of
 * rays and a single ray walk the BVH differently; so do two BVHs). */
CSG_FN L_INT L_FN(csg_hit_wins)(L_HIT h, const L_HIT *best)
{
    return (h.surf != CSG_SURF_NONE) &
           ((h.t < best->t) | ((h.t == best->t) & (h.surf < best->surf)));
}

#define CSG_LANES_END
#include "lanes.h"
