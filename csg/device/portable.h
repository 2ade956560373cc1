/*
 * portable.h — the one header that lets the geometry code of csg/ compile
 * both as C11 (host, workers, tests) and as OpenCL C 1.2 (simd_kernels/).
 *
 * It maps the few differences: address-space qualifiers, fixed-width
 * integer names, the scalar type `real` (float, or double with CSG_DOUBLE)
 * and the handful of math functions the shared code uses.  The shared code
 * uses only + - * / sqrt fabs fmin fmax on `real`: all correctly rounded in
 * IEEE 754, so C and OpenCL produce the same bits as long as contraction is
 * off on both sides (-ffp-contract=off, FP_CONTRACT OFF) and the kernel is
 * built with -cl-fp32-correctly-rounded-divide-sqrt.
 *
 * Literals go through R(): R(0.5) is 0.5f in the float build and 0.5 in
 * the double build, so no expression silently promotes to double.
 *
 * r_fmin / r_fmax live with the vectors (vec_lanes.h), written once for
 * one ray and for a packet (lanes.h).
 */
#ifndef CSG_PORTABLE_H
#define CSG_PORTABLE_H

#ifdef __OPENCL_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#ifdef CSG_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif
#define CSG_GLOBAL __global
#define CSG_FN static inline
typedef uchar csg_u8;
typedef uint csg_u32;
typedef int csg_i32;
typedef ulong csg_u64;
#define CSG_R_INF ((real)INFINITY)
#else
#include <math.h>
#include <stdint.h>
#define CSG_GLOBAL
#define CSG_FN static inline
typedef uint8_t csg_u8;
typedef uint32_t csg_u32;
typedef int32_t csg_i32;
typedef uint64_t csg_u64;
#define CSG_R_INF ((real)INFINITY)
#endif

#ifdef CSG_DOUBLE
typedef double real;
#define R(x) (x)
#ifdef __OPENCL_VERSION__
#define r_sqrt(a) sqrt(a)
#define r_fabs(a) fabs(a)
#define r_floor(a) floor(a)
#else
#define r_sqrt(a) sqrt(a)
#define r_fabs(a) fabs(a)
#define r_floor(a) floor(a)
#endif
#else
typedef float real;
#define R(x) (x##f)
#ifdef __OPENCL_VERSION__
#define r_sqrt(a) sqrt(a)
#define r_fabs(a) fabs(a)
#define r_floor(a) floor(a)
#else
#define r_sqrt(a) sqrtf(a)
#define r_fabs(a) fabsf(a)
#define r_floor(a) floorf(a)
#endif
#endif

/* The next real above t >= 0 (t itself when infinite or NaN): integer
 * steps on the bits, the same on every side, no libm call. */
#ifdef __OPENCL_VERSION__
#ifdef CSG_DOUBLE
CSG_FN real r_next_up(real t) { return t < (real)INFINITY ? as_double(as_ulong(t) + 1ul) : t; }
#else
CSG_FN real r_next_up(real t) { return t < (real)INFINITY ? as_float(as_uint(t) + 1u) : t; }
#endif
#else
CSG_FN real r_next_up(real t)
{
#ifdef CSG_DOUBLE
    union { double r; uint64_t u; } b;
#else
    union { float r; uint32_t u; } b;
#endif
    if (!(t < CSG_R_INF))
        return t;
    b.r = t;
    b.u++;
    return b.r;
}
#endif

#endif
