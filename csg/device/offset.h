/*
 * offset.h — where a secondary ray starts: the hit point moved off the
 * surface, far enough that the new ray cannot find the surface it leaves
 * again (self-intersection: shadow acne, speckled reflections), near
 * enough that contact shadows and thin objects survive.  Shared by the
 * C workers (workers/shade.c), the stability tests and the OpenCL shadow
 * kernel (simd_kernels/primary.cl, through shadow.h), so a shadow ray
 * starts at the same bits on both sides; in the `real` of the including
 * file (-DCSG_DOUBLE: double).
 *
 * Two bounds, the farther one wins, per component:
 *   1. Wächter and Binder, "A Fast and Robust Method for Avoiding
 *      Self-Intersection" (Ray Tracing Gems, ch. 6): a component moves by
 *      a fixed number of units in the last place of itself (the rounding
 *      of a coordinate is relative to its size); a component near zero,
 *      whose ulps are denormal-small, moves by a fixed small amount
 *      instead.  That "near zero" (|p| < 1/32) and that amount (2^-16 in
 *      float, 2^-40 in double) assume a scene of size about 1: they are
 *      scaled by min(1, m) below, m the ray's magnitude, so a scene of
 *      size 1e-4 keeps the same relative offsets as the unit scene.
 *   2. The hit point o + t d inherits the rounding of the ray, not only
 *      its own: a point near a zero coordinate reached from a camera 1e6
 *      away is off by ulps of 1e6, and so is a point found on a sphere of
 *      radius 1e6 however near the origin.  So the point also moves by
 *      OFFSET_ERR_ULPS * unit roundoff * m along the normal, where
 *      m = max(|o|max, t |d|max, the object's bounding-box magnitude) is
 *      the magnitude of the computation.
 * For the usual scene (size about 1, camera a few units away) bound 1
 * dominates and the offsets are exactly Wächter and Binder's.
 */
#ifndef CSG_OFFSET_H
#define CSG_OFFSET_H

#include "vec.h"
#ifndef __OPENCL_VERSION__
#include <string.h>
#endif

#ifdef CSG_DOUBLE
#ifdef __OPENCL_VERSION__
typedef long offset_bits;
#define OFFSET_AS_BITS(p) as_long(p)
#define OFFSET_AS_REAL(b) as_double(b)
#endif
#ifndef __OPENCL_VERSION__
typedef int64_t offset_bits;
#endif
#define OFFSET_FLOAT_SCALE (R(1.0) / R(1099511627776.0)) /* 2^-40 */
#define OFFSET_INT_SCALE (R(256.0) * R(2097152.0))       /* 2^29 ulps */
#define OFFSET_UNIT_ROUNDOFF (R(1.0) / R(9007199254740992.0)) /* 2^-53 */
#else
#ifdef __OPENCL_VERSION__
typedef int offset_bits;
#define OFFSET_AS_BITS(p) as_int(p)
#define OFFSET_AS_REAL(b) as_float(b)
#else
typedef int32_t offset_bits;
#endif
#define OFFSET_FLOAT_SCALE (R(1.0) / R(65536.0)) /* 2^-16 */
#define OFFSET_INT_SCALE R(256.0)                /* 256 ulps */
#define OFFSET_UNIT_ROUNDOFF (R(1.0) / R(16777216.0)) /* 2^-24 */
#endif
#define OFFSET_ORIGIN (R(1.0) / R(32.0))
#define OFFSET_ERR_ULPS R(16.0)

/* The magnitude of the object's coordinates, from its world bounding box
 * (infinite bounds skipped): a point on a sphere of radius 1e4 is found
 * with errors of ulps of 1e4, however near the ray's origin it lies. */
CSG_FN real offset_box_magnitude(CSG_GLOBAL const real *lo, CSG_GLOBAL const real *hi)
{
    real m = R(0.0);
    for (int i = 0; i < 3; i++) {
        if (r_fabs(lo[i]) < CSG_R_INF)
            m = r_fmax(m, r_fabs(lo[i]));
        if (r_fabs(hi[i]) < CSG_R_INF)
            m = r_fmax(m, r_fabs(hi[i]));
    }
    return m;
}

#ifdef __OPENCL_VERSION__
CSG_FN offset_bits offset_as_bits(real p) { return OFFSET_AS_BITS(p); }
CSG_FN real offset_as_real(offset_bits b) { return OFFSET_AS_REAL(b); }
#else
CSG_FN offset_bits offset_as_bits(real p)
{
    offset_bits b;
    memcpy(&b, &p, sizeof p);
    return b;
}
CSG_FN real offset_as_real(offset_bits b)
{
    real p;
    memcpy(&p, &b, sizeof p);
    return p;
}
#endif

/* offset_magnitude, offset_wb, offset_component, offset_point: the one-ray
 * compilation of offset_lanes.h (simd_kernels/packet.h compiles them for a
 * packet: ..._pk). */
#include "offset_lanes.h"

#endif
