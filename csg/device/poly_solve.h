/*
 * poly_solve.h — the real roots of a polynomial in a closed range, by a
 * Sturm sequence and bisection, in double precision whatever `real` is.
 * Shared by C and OpenCL C (one ray only: the packet kernel evaluates the
 * roots that need it through the one-ray code, packet.h).
 *
 * Algorithm.  The Sturm sequence of p (p0 = p, p1 = p', then each the
 * negated remainder of the two before it) gives, by its count of sign
 * changes V(x), the number of distinct real roots in (a, b]: V(a) - V(b).
 * The roots are found in increasing order: the bracket (a, b] is halved,
 * keeping the half that holds the first root after a, until it holds
 * exactly one distinct root (or is narrower than the tolerance); that
 * root is then refined by bisection on the sign of p where p changes sign
 * at the ends (a simple or odd root), on the Sturm count where it does
 * not (an even root, a ray grazing the surface); the next search starts
 * at the bracket's end.  Roots closer than the tolerance count once.
 * POV-Ray 3.7 (polysolve in polynomialsolver.cpp) does the same with a
 * recursive bisection and regula falsi; this one is iterative (OpenCL has
 * no recursion) and bounded (every loop has a fixed cap).
 *
 * Conditioning.  The caller scales the variable so that the roots it wants
 * lie in [-1, 1] or so (the torus: its bounding sphere's chord, in units
 * of the sphere's radius; a poly: its own units, its roots up to 1e7
 * away, a bracket then narrowed to the doubles' spacing), so the
 * tolerances below are absolute on an O(1) variable: CSG_POLY_TOL on a
 * root, CSG_POLY_ZERO on a remainder's coefficient relative to its
 * dividend's largest (POV-Ray's SMALL_ENOUGH,
 * 1e-10, on a monic sequence).
 *
 * Only + - * / and comparisons on double: the same bits in C and OpenCL C
 * (contraction off on both sides, portable.h).
 */
#ifndef CSG_POLY_SOLVE_H
#define CSG_POLY_SOLVE_H

#include "portable.h"
#include "spec.h"

/* double is needed on the device only by a program that has a torus, a
 * quadric or a poly (spec.h): a float program without them compiles on a device
 * without cl_khr_fp64, as before. */
#if !defined(__OPENCL_VERSION__) || defined(CSG_DOUBLE) || CSG_USE_TORUS || CSG_USE_QUADRIC ||     \
    CSG_USE_POLY
#define CSG_POLY_SOLVER 1
#if defined(__OPENCL_VERSION__) && !defined(CSG_DOUBLE)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif
#else
#define CSG_POLY_SOLVER 0
#endif

#if CSG_POLY_SOLVER

/* The highest degree solved: a poly's (flat.h's CSG_POLY_ORDER_MAX), or a
 * quartic in a program without polys (a torus's: its Sturm sequence
 * takes private memory by this square, on the device too). */
#if CSG_USE_POLY
#define CSG_POLY_MAX_ORDER CSG_POLY_ORDER_MAX /* (flat.h: intersect.h includes it first) */
#else
#define CSG_POLY_MAX_ORDER 4
#endif
#define CSG_POLY_TOL 1e-12     /* the width a root is bracketed to            */
#define CSG_POLY_ZERO 1e-15    /* a remainder coefficient below this, times its
                                  dividend's largest, is 0                    */
#define CSG_POLY_ITER 80       /* bisection steps at most, a root              */

/* A Sturm sequence: polynomial k is c[k][0 .. deg[k]], c[k][i] the
 * coefficient of x^i. */
typedef struct {
    csg_i32 count;
    csg_i32 deg[CSG_POLY_MAX_ORDER + 1];
    double c[CSG_POLY_MAX_ORDER + 1][CSG_POLY_MAX_ORDER + 1];
} csg_sturm;

/* p(x) for p = c[0 .. n], by Horner's rule. */
CSG_FN double csg_poly_eval(const double *c, csg_i32 n, double x)
{
    double v = c[n];
    for (csg_i32 i = n - 1; i >= 0; i--)
        v = v * x + c[i];
    return v;
}

/* Sequence polynomial k at x (a private copy: OpenCL's address spaces). */
CSG_FN double csg_sturm_eval(const csg_sturm *s, csg_i32 k, double x)
{
    double v = s->c[k][s->deg[k]];
    for (csg_i32 i = s->deg[k] - 1; i >= 0; i--)
        v = v * x + s->c[k][i];
    return v;
}

/* Scale polynomial k so that its leading coefficient is +1 or -1. */
CSG_FN void csg_sturm_unit_lead(csg_sturm *s, csg_i32 k)
{
    double lead = s->c[k][s->deg[k]];
    double m = lead < 0.0 ? -lead : lead;
    for (csg_i32 i = 0; i <= s->deg[k]; i++)
        s->c[k][i] = s->c[k][i] / m;
}

/* Polynomial k = -(remainder of k - 2 divided by k - 1); false when the
 * remainder is 0 (the sequence ends at k - 1). */
CSG_FN int csg_sturm_next(csg_sturm *s, csg_i32 k)
{
    double r[CSG_POLY_MAX_ORDER + 1];
    csg_i32 du = s->deg[k - 2], dv = s->deg[k - 1];
    double big = 0.0;
    for (csg_i32 i = 0; i <= du; i++) {
        r[i] = s->c[k - 2][i];
        double m = r[i] < 0.0 ? -r[i] : r[i];
        big = m > big ? m : big;
    }
    double lead = s->c[k - 1][dv]; /* +1 or -1 */
    for (csg_i32 j = du - dv; j >= 0; j--) {
        double q = r[dv + j] / lead;
        for (csg_i32 i = 0; i <= dv; i++)
            r[i + j] = r[i + j] - q * s->c[k - 1][i];
    }
    csg_i32 d = dv - 1;
    while (d >= 0 && (r[d] < 0.0 ? -r[d] : r[d]) <= CSG_POLY_ZERO * big)
        d--;
    if (d < 0)
        return 0;
    s->deg[k] = d;
    for (csg_i32 i = 0; i <= d; i++)
        s->c[k][i] = -r[i];
    csg_sturm_unit_lead(s, k);
    return 1;
}

/* The Sturm sequence of c[0 .. n] (n >= 1, c[n] != 0). */
CSG_FN void csg_sturm_build(const double *c, csg_i32 n, csg_sturm *s)
{
    s->deg[0] = n;
    for (csg_i32 i = 0; i <= n; i++)
        s->c[0][i] = c[i];
    csg_sturm_unit_lead(s, 0);
    s->deg[1] = n - 1;
    for (csg_i32 i = 1; i <= n; i++)
        s->c[1][i - 1] = s->c[0][i] * (double)i;
    csg_sturm_unit_lead(s, 1);
    s->count = 2;
    while (s->count <= n && s->deg[s->count - 1] > 0 && csg_sturm_next(s, s->count))
        s->count++;
}

/* V(x): the sign changes along the sequence at x, zeros skipped. */
CSG_FN csg_i32 csg_sturm_changes(const csg_sturm *s, double x)
{
    csg_i32 changes = 0, last = 0;
    for (csg_i32 k = 0; k < s->count; k++) {
        double v = csg_sturm_eval(s, k, x);
        csg_i32 sign = v > 0.0 ? 1 : (v < 0.0 ? -1 : 0);
        if (sign != 0 && last != 0 && sign != last)
            changes++;
        if (sign != 0)
            last = sign;
    }
    return changes;
}

/* The bracket (a, b] (va, vb: V there) cut at m to the half that holds
 * the first root after a. */
CSG_FN void csg_sturm_halve(const csg_sturm *s, double m, double *a, double *b, csg_i32 *va,
                            csg_i32 *vb)
{
    csg_i32 vm = csg_sturm_changes(s, m);
    if (*va - vm >= 1) {
        *b = m;
        *vb = vm;
    } else {
        *a = m;
        *va = vm;
    }
}

/* The one distinct root in (a, b] (va, vb: V there), refined to the
 * tolerance: by the sign of p when it changes over the bracket, else by
 * the Sturm count. */
CSG_FN double csg_sturm_refine(const csg_sturm *s, double a, double b, csg_i32 va, csg_i32 vb)
{
    double pa = csg_sturm_eval(s, 0, a), pb = csg_sturm_eval(s, 0, b);
    if (pb == 0.0)
        return b;
    int by_sign = (pa < 0.0 && pb > 0.0) || (pa > 0.0 && pb < 0.0);
    for (csg_i32 it = 0; it < CSG_POLY_ITER && b - a > CSG_POLY_TOL; it++) {
        double m = 0.5 * (a + b);
        if (!(m > a && m < b)) /* no double between them */
            break;
        if (by_sign) {
            double pm = csg_sturm_eval(s, 0, m);
            if (pm == 0.0)
                return m;
            if ((pm < 0.0) == (pa < 0.0)) {
                a = m;
                pa = pm;
            } else {
                b = m;
            }
        } else {
            csg_sturm_halve(s, m, &a, &b, &va, &vb);
        }
    }
    (void)vb;
    return 0.5 * (a + b);
}

/* The distinct real roots of c[0 .. n] in (lo, hi], increasing, into
 * roots[] (at most n); returns their count.  Leading coefficients that
 * are 0 lower the degree; degree 0 has no root. */
CSG_FN csg_i32 csg_poly_roots(const double *c, csg_i32 n, double lo, double hi, double *roots)
{
    while (n > 0 && c[n] == 0.0)
        n--;
    if (n < 1 || n > CSG_POLY_MAX_ORDER || !(lo < hi))
        return 0;
    csg_sturm s;
    csg_sturm_build(c, n, &s);
    csg_i32 va = csg_sturm_changes(&s, lo), v_end = csg_sturm_changes(&s, hi);
    double a = lo;
    csg_i32 found = 0;
    while (va - v_end > 0 && found < n) {
        double b = hi;
        csg_i32 vb = v_end;
        /* halve (a, b] towards the first root after a until it holds one */
        for (csg_i32 it = 0; it < CSG_POLY_ITER && va - vb > 1 && b - a > CSG_POLY_TOL; it++) {
            double m = 0.5 * (a + b);
            if (!(m > a && m < b))
                break;
            csg_sturm_halve(&s, m, &a, &b, &va, &vb);
        }
        roots[found++] = va - vb == 1 ? csg_sturm_refine(&s, a, b, va, vb) : 0.5 * (a + b);
        a = b;
        va = vb;
    }
    return found;
}

#endif /* CSG_POLY_SOLVER */

#endif
