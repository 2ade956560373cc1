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
