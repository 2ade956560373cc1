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

/* csg_sample_offset and csg_camera_ray: the one-ray compilation of
 * camera_lanes.h. */
#include "camera_lanes.h"

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
