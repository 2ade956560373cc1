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

/* The magnitude of the computation that produced o + t d. */
CSG_FN real offset_magnitude(vec3 o, vec3 d, real t)
{
    real om = r_fmax(r_fabs(o.x), r_fmax(r_fabs(o.y), r_fabs(o.z)));
    real dm = r_fmax(r_fabs(d.x), r_fmax(r_fabs(d.y), r_fabs(d.z)));
    real m = r_fmax(om, t * dm);
    return m == m ? m : R(0.0); /* a NaN magnitude adds nothing */
}

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

/* Wächter and Binder's offset of one component, near-zero band scaled. */
CSG_FN real offset_wb(real p, real n, real scale)
{
    if (r_fabs(p) < OFFSET_ORIGIN * scale)
        return p + OFFSET_FLOAT_SCALE * scale * n;
    offset_bits step = (offset_bits)(OFFSET_INT_SCALE * n);
#ifdef __OPENCL_VERSION__
    offset_bits bits = OFFSET_AS_BITS(p);
    bits += p < R(0.0) ? -step : step;
    return OFFSET_AS_REAL(bits);
#else
    offset_bits bits;
    memcpy(&bits, &p, sizeof p);
    bits += p < R(0.0) ? -step : step;
    real q;
    memcpy(&q, &bits, sizeof q);
    return q;
#endif
}

CSG_FN real offset_component(real p, real n, real m)
{
    real wb = offset_wb(p, n, r_fmin(R(1.0), m));
    real ab = p + OFFSET_ERR_ULPS * OFFSET_UNIT_ROUNDOFF * m * n;
    return n >= R(0.0) ? r_fmax(wb, ab) : r_fmin(wb, ab);
}

/* p moved off the surface along n (unit, pointing to the side the new ray
 * leaves to); m from offset_magnitude of the ray that found p. */
CSG_FN vec3 offset_point(vec3 p, vec3 n, real m)
{
    return v3(offset_component(p.x, n.x, m), offset_component(p.y, n.y, m),
              offset_component(p.z, n.z, m));
}

#endif
