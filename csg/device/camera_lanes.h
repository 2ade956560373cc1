/*
 * camera_lanes.h — where a sample falls in its pixel and the camera ray
 * through it, lane-generic (lanes.h): included by camera.h for one ray
 * (csg_sample_offset, csg_camera_ray) and by simd_kernels/packet.h for a
 * packet (..._pk).  No include guard: each inclusion is one compilation of
 * the template.
 */
#include "lanes.h"

/* Where sample s of spp falls inside its pixel (0..1 each way), a fixed
 * stratified pattern: a k x k grid of cell centres when spp = k * k, else
 * the rank-1 lattice (s + 1/2, s * a + 1/2) / spp with a coprime to spp
 * near spp / golden ratio, so every row and column of the spp x spp grid
 * holds one sample.  spp = 1 is the pixel centre, (0 + 1/2) / 1 exactly.
 * k and a depend on spp alone; integer arithmetic and one division per
 * coordinate: the same bits in C and OpenCL. */
CSG_FN void L_FN(csg_sample_offset)(csg_i32 spp, L_INT s, L_REAL *ox, L_REAL *oy)
{
    if (spp == 1) {
        *ox = L_RS(R(0.5));
        *oy = L_RS(R(0.5));
        return;
    }
    csg_i32 k = 1;
    while ((k + 1) * (k + 1) <= spp)
        k++;
    if (k * k == spp) {
        *ox = (L_TO_REAL(s % k) + R(0.5)) / (real)k;
        *oy = (L_TO_REAL(s / k) + R(0.5)) / (real)k;
        return;
    }
    csg_i32 a = (spp * 618034 + 500000) / 1000000;
    for (;;) { /* the largest a' <= a coprime with spp (a' = 1 always is) */
        csg_i32 x = a, y = spp;
        while (y != 0) {
            csg_i32 r = x % y;
            x = y;
            y = r;
        }
        if (x == 1 || a <= 1)
            break;
        a--;
    }
    if (a < 1)
        a = 1;
    *ox = (L_TO_REAL(s) + R(0.5)) / (real)spp;
    *oy = (L_TO_REAL((s * a) % spp) + R(0.5)) / (real)spp;
}

/* sin and cos of a (radians) from + - * and floor alone, so the C workers
 * and the OpenCL kernels get the same bits (a libm's sin and OpenCL's need
 * not agree): a reduced to r = a - k pi/2 (|r| <= pi/4; pi/2 as a real
 * and the rest, so the error grows with k: meant for a camera's angles,
 * a few turns at most), the Taylor series of sin (to r^15) and cos (to
 * r^16), whose first omitted terms are below double's rounding there,
 * then swapped and negated by the quadrant k mod 4. */
CSG_FN void L_FN(csg_sincos)(L_REAL a, L_REAL *s, L_REAL *c)
{
#ifdef CSG_DOUBLE
    const real pi_2_lo = R(6.123233995736766e-17);
#else
    const real pi_2_lo = R(-4.37113883e-8);
#endif
    L_REAL k = L_FLOOR(a * R(0.63661977236758134) + R(0.5));
    L_REAL r = (a - k * R(1.5707963267948966)) - k * pi_2_lo;
    L_REAL r2 = r * r;
    L_REAL sr = R(-1.0) / R(1307674368000.0);
    sr = sr * r2 + R(1.0) / R(6227020800.0);
    sr = sr * r2 - R(1.0) / R(39916800.0);
    sr = sr * r2 + R(1.0) / R(362880.0);
    sr = sr * r2 - R(1.0) / R(5040.0);
    sr = sr * r2 + R(1.0) / R(120.0);
    sr = sr * r2 - R(1.0) / R(6.0);
    sr = r + r * (sr * r2);
    L_REAL cr = R(1.0) / R(20922789888000.0);
    cr = cr * r2 - R(1.0) / R(87178291200.0);
    cr = cr * r2 + R(1.0) / R(479001600.0);
    cr = cr * r2 - R(1.0) / R(3628800.0);
    cr = cr * r2 + R(1.0) / R(40320.0);
    cr = cr * r2 - R(1.0) / R(720.0);
    cr = cr * r2 + R(1.0) / R(24.0);
    cr = cr * r2 - R(0.5);
    cr = R(1.0) + cr * r2;
    L_REAL q = k - R(4.0) * L_FLOOR(k * R(0.25)); /* 0 .. 3 */
    L_INT swap = (q == R(1.0)) | (q == R(3.0));
    L_REAL sv = L_SEL(swap, cr, sr), cv = L_SEL(swap, sr, cr);
    *s = L_SEL((q == R(2.0)) | (q == R(3.0)), -sv, sv);
    *c = L_SEL((q == R(1.0)) | (q == R(2.0)), -cv, cv);
}

/* v turned by angle (cosine c, sine s) about the unit axis a, as POV-Ray's
 * Compute_Axis_Rotation_Transform and MTransPoint do it. */
CSG_FN L_VEC3 L_FN(csg_turn_about)(L_VEC3 v, CSG_GLOBAL const real *a, L_REAL c, L_REAL s)
{
    real ax = a[0], ay = a[1], az = a[2];
    L_REAL t = R(1.0) - c;
    L_REAL m00 = ax * ax + c * (R(1.0) - ax * ax), m11 = ay * ay + c * (R(1.0) - ay * ay);
    L_REAL m22 = az * az + c * (R(1.0) - az * az);
    L_REAL m01 = ax * ay * t + az * s, m02 = ax * az * t - ay * s;
    L_REAL m10 = ax * ay * t - az * s, m12 = ay * az * t + ax * s;
    L_REAL m20 = ax * az * t + ay * s, m21 = ay * az * t - ax * s;
    return L_FN(v3)(v.x * m00 + v.y * m10 + v.z * m20, v.x * m01 + v.y * m11 + v.z * m21,
                    v.x * m02 + v.y * m12 + v.z * m22);
}

/* POV-Ray's cameras that bend their rays through angles (tracepixel.cpp,
 * CreateCameraRay), for x0, y0 in -0.5 .. 0.5 and the factors kx, ky of
 * flatten.c: the cylinder cameras (1: axis up; 2: axis right; 3 and 4 the
 * same with the origin moved along the axis instead of the ray turned),
 * ultra_wide_angle, panoramic (Graphic Gems III) and spherical (direction
 * turned about right by the latitude, then about up by the longitude). */
CSG_FN L_RAY L_FN(csg_camera_bent_ray)(CSG_GLOBAL const csg_camera *cam, L_REAL x0, L_REAL y0)
{
    L_VEC3 right = L_FN(v3_load)(cam->right), up = L_FN(v3_load)(cam->up);
    L_VEC3 dir = L_FN(v3_load)(cam->direction), d;
    L_REAL ax = x0 * cam->kx, ay = y0 * cam->ky, sx, cx, sy, cy;
    L_RAY r;
    r.o = L_FN(v3_load)(cam->location);
    switch (cam->projection) {
    case CSG_CAMERA_CYLINDER_1:
        L_FN(csg_sincos)(ax, &sx, &cx);
        d = L_FN(v3_add)(L_FN(v3_add)(L_FN(v3_scale)(right, sx), L_FN(v3_scale)(up, ay)),
                         L_FN(v3_scale)(dir, cx));
        break;
    case CSG_CAMERA_CYLINDER_2:
        L_FN(csg_sincos)(ay, &sy, &cy);
        d = L_FN(v3_add)(L_FN(v3_add)(L_FN(v3_scale)(right, ax), L_FN(v3_scale)(up, sy)),
                         L_FN(v3_scale)(dir, cy));
        break;
    case CSG_CAMERA_CYLINDER_3:
        L_FN(csg_sincos)(ax, &sx, &cx);
        d = L_FN(v3_add)(L_FN(v3_scale)(right, sx), L_FN(v3_scale)(dir, cx));
        r.o = L_FN(v3_add)(r.o, L_FN(v3_scale)(up, ay));
        break;
    case CSG_CAMERA_CYLINDER_4:
        L_FN(csg_sincos)(ay, &sy, &cy);
        d = L_FN(v3_add)(L_FN(v3_scale)(up, sy), L_FN(v3_scale)(dir, cy));
        r.o = L_FN(v3_add)(r.o, L_FN(v3_scale)(right, ax));
        break;
    case CSG_CAMERA_ULTRA_WIDE_ANGLE:
        L_FN(csg_sincos)(ax, &sx, &cx);
        L_FN(csg_sincos)(ay, &sy, &cy);
        d = L_FN(v3_add)(L_FN(v3_add)(L_FN(v3_scale)(right, sx), L_FN(v3_scale)(up, sy)),
                         L_FN(v3_scale)(dir, cx * cy));
        break;
    case CSG_CAMERA_PANORAMIC: /* (x from 0 at the left: (1 - x / width) pi) */
        L_FN(csg_sincos)((R(0.5) - x0) * cam->kx, &sx, &cx);
        L_FN(csg_sincos)(ay, &sy, &cy);
        d = L_FN(v3_add)(L_FN(v3_add)(L_FN(v3_scale)(right, cx), L_FN(v3_scale)(up, sy / cy)),
                         L_FN(v3_scale)(dir, sx));
        break;
    default: /* CSG_CAMERA_SPHERICAL */
        L_FN(csg_sincos)(-ay, &sy, &cy);
        L_FN(csg_sincos)(ax, &sx, &cx);
        d = L_FN(csg_turn_about)(L_FN(csg_turn_about)(dir, cam->right, cy, sy), cam->up, cx, sx);
        break;
    }
    r.d = L_FN(v3_normalize)(d);
    return r;
}

/* The ray through the point (px + ox, py + oy) of the image plane, pixel
 * units, y down: from location along direction + x0 right + y0 up
 * (perspective), or from location + x0 right + y0 up along direction
 * (orthographic); with a hither (NFF), from where it crosses the near
 * plane.  The projection and the hither are the camera's: one branch for
 * every lane. */
CSG_FN L_RAY L_FN(csg_camera_ray)(CSG_GLOBAL const csg_camera *cam, csg_i32 width,
                                  csg_i32 height, L_INT px, L_INT py, L_REAL ox, L_REAL oy)
{
    L_REAL x0 = (L_TO_REAL(px) + ox) / (real)width - R(0.5);
    L_REAL y0 = R(0.5) - (L_TO_REAL(py) + oy) / (real)height;
    if (cam->projection > CSG_CAMERA_ORTHOGRAPHIC)
        return L_FN(csg_camera_bent_ray)(cam, x0, y0);
    L_VEC3 rx = L_FN(v3_scale)(L_FN(v3_load)(cam->right), x0);
    L_VEC3 uy = L_FN(v3_scale)(L_FN(v3_load)(cam->up), y0);
    L_VEC3 d = L_FN(v3_load)(cam->direction);
    L_RAY r;
    r.o = L_FN(v3_load)(cam->location);
    if (cam->projection == CSG_CAMERA_ORTHOGRAPHIC)
        r.o = L_FN(v3_add)(L_FN(v3_add)(r.o, rx), uy);
    else
        d = L_FN(v3_add)(L_FN(v3_add)(d, rx), uy);
    r.d = L_FN(v3_normalize)(d);
    if (cam->hither > R(0.0)) {
        L_VEC3 view = L_FN(v3_load)(cam->direction);
        r.o = L_FN(v3_madd)(r.o, r.d,
                            cam->hither * L_FN(v3_length)(view) / L_FN(v3_dot)(r.d, view));
    }
    return r;
}

#define CSG_LANES_END
#include "lanes.h"
