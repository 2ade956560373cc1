/*
 * dbox.h — axis-aligned boxes in double, as the flattener computes world
 * boxes and the BVH builder splits them (csg/flatten.c, csg/bvh_build.c).
 */
#ifndef CSG_DBOX_H
#define CSG_DBOX_H

#include <math.h>

typedef struct {
    double lo[3], hi[3];
} dbox;

/* fmin and fmax, to the bit (a tie, -0 against +0 included, gives b; a NaN
 * gives the other operand), inline: without -ffinite-math-only GCC calls
 * libm's, and those calls were 9 % of a tetra7 render (the BVH's boxes). */
static inline double box_min(double a, double b)
{
    return a < b ? a : isnan(b) ? a : b;
}

static inline double box_max(double a, double b)
{
    return a > b ? a : isnan(b) ? a : b;
}

/* The box of nothing: the union's identity. */
static inline dbox box_empty(void)
{
    dbox b;
    for (int i = 0; i < 3; i++) {
        b.lo[i] = INFINITY;
        b.hi[i] = -INFINITY;
    }
    return b;
}

static inline dbox box_union(dbox a, dbox b)
{
    for (int i = 0; i < 3; i++) {
        a.lo[i] = box_min(a.lo[i], b.lo[i]);
        a.hi[i] = box_max(a.hi[i], b.hi[i]);
    }
    return a;
}

#endif
