/*
 * camera.h — the primary ray of a pixel, shared by the OpenCL primary pass
 * and the C workers so that both trace exactly the same ray.
 *
 * POV-Ray's perspective camera: with x0 = (x + 0.5) / W - 0.5 and
 * y0 = 0.5 - (y + 0.5) / H (pixel centres, y down the image), the ray leaves
 * `location` along normalize(direction + x0 * right + y0 * up); the
 * orthographic camera's ray leaves location + x0 * right + y0 * up along
 * normalize(direction).  The
 * camera vectors already hold POV-Ray's look_at / angle / sky handling,
 * done once on the host in double (csg/camera_setup.c).  A camera with a
 * near plane (hither > 0) starts each ray on that plane instead.
 */
#ifndef CSG_CAMERA_H
#define CSG_CAMERA_H

#include "intersect.h"

/* The camera of a blob (flat.h). */
CSG_FN CSG_GLOBAL const csg_camera *csg_blob_camera(CSG_GLOBAL const csg_u8 *blob)
{
    CSG_GLOBAL const csg_blob_header *h = (CSG_GLOBAL const csg_blob_header *)blob;
    return (CSG_GLOBAL const csg_camera *)(blob + h->off_camera);
}

/* Where sample s of spp falls inside its pixel (0..1 each way), a fixed
 * stratified pattern: a k x k grid of cell centres when spp = k * k, else
 * the rank-1 lattice (s + 1/2, s * a + 1/2) / spp with a coprime to spp
 * near spp / golden ratio, so every row and column of the spp x spp grid
 * holds one sample.  spp = 1 is the pixel centre.  Integer arithmetic and
 * one division each: the same bits in C and OpenCL. */
CSG_FN void csg_sample_offset(csg_i32 spp, csg_i32 s, real *ox, real *oy)
{
    csg_i32 k = 1;
    while ((k + 1) * (k + 1) <= spp)
        k++;
    if (k * k == spp) {
        *ox = ((real)(s % k) + R(0.5)) / (real)k;
        *oy = ((real)(s / k) + R(0.5)) / (real)k;
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
    *ox = ((real)s + R(0.5)) / (real)spp;
    *oy = ((real)((s * a) % spp) + R(0.5)) / (real)spp;
}

/* The ray through the point (px + ox, py + oy) of the image plane, pixel
 * units, y down. */
CSG_FN csg_ray csg_camera_ray(CSG_GLOBAL const csg_camera *cam, csg_i32 width, csg_i32 height,
                              csg_i32 px, csg_i32 py, real ox, real oy)
{
    real x0 = ((real)px + ox) / (real)width - R(0.5);
    real y0 = R(0.5) - ((real)py + oy) / (real)height;
    vec3 rx = v3_scale(v3_load(cam->right), x0), uy = v3_scale(v3_load(cam->up), y0);
    vec3 d = v3_load(cam->direction);
    csg_ray r;
    r.o = v3_load(cam->location);
    if (cam->projection == CSG_CAMERA_ORTHOGRAPHIC)
        r.o = v3_add(v3_add(r.o, rx), uy);
    else
        d = v3_add(v3_add(d, rx), uy);
    r.d = v3_normalize(d);
    if (cam->hither > R(0.0)) {
        vec3 view = v3_load(cam->direction);
        r.o = v3_madd(r.o, r.d, cam->hither * v3_length(view) / v3_dot(r.d, view));
    }
    return r;
}

/* The primary ray of pixel (px, py) through its centre. */
CSG_FN csg_ray csg_primary_ray(CSG_GLOBAL const csg_camera *cam, csg_i32 width, csg_i32 height,
                               csg_i32 px, csg_i32 py)
{
    return csg_camera_ray(cam, width, height, px, py, R(0.5), R(0.5));
}

/* Sample s of spp of pixel (px, py). */
CSG_FN csg_ray csg_sample_ray(CSG_GLOBAL const csg_camera *cam, csg_i32 width, csg_i32 height,
                              csg_i32 px, csg_i32 py, csg_i32 spp, csg_i32 s)
{
    real ox, oy;
    csg_sample_offset(spp, s, &ox, &oy);
    return csg_camera_ray(cam, width, height, px, py, ox, oy);
}

#endif
