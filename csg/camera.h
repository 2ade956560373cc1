/*
 * camera.h — the primary ray of a pixel, shared by the OpenCL primary pass
 * and the C workers so that both trace exactly the same ray.
 *
 * POV-Ray's perspective camera: with x0 = (x + 0.5) / W - 0.5 and
 * y0 = 0.5 - (y + 0.5) / H (pixel centres, y down the image), the ray leaves
 * `location` along normalize(direction + x0 * right + y0 * up).  The
 * camera vectors already hold POV-Ray's look_at / angle / sky handling,
 * done once on the host in double (csg/camera.c).
 */
#ifndef CSG_CAMERA_H
#define CSG_CAMERA_H

#include "intersect.h"

CSG_FN csg_ray csg_primary_ray(CSG_GLOBAL const csg_camera *cam, csg_i32 width, csg_i32 height,
                               csg_i32 px, csg_i32 py)
{
    real x0 = ((real)px + R(0.5)) / (real)width - R(0.5);
    real y0 = R(0.5) - ((real)py + R(0.5)) / (real)height;
    vec3 d = v3_load(cam->direction);
    d = v3_add(d, v3_scale(v3_load(cam->right), x0));
    d = v3_add(d, v3_scale(v3_load(cam->up), y0));
    csg_ray r;
    r.o = v3_load(cam->location);
    r.d = v3_normalize(d);
    return r;
}

#endif
