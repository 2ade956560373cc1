/*
 * camera_setup.h — POV-Ray's camera statement, applied item by item as the
 * parser meets it (POV-Ray applies look_at and angle where they are
 * written, using the vectors set so far).
 */
#ifndef CSG_CAMERA_SETUP_H
#define CSG_CAMERA_SETUP_H

#include <stdbool.h>

#include "scene.h"

/* location 0, direction z, up y, right 1.33 x, sky y (POV-Ray's defaults). */
void csg_camera_default(csg_camera_src *c);
/* Points the camera at `target`, keeping the lengths of direction, right
 * and up and the handedness of right; false (and d filled) when target is
 * the location or sky is parallel to the view direction. */
bool csg_camera_look_at(csg_camera_src *c, dvec3 target, csg_loc loc, csg_diag *d);
/* Horizontal field of view in degrees, 0 < angle < 180: sets the length of
 * direction to |right| / 2 / tan(angle / 2). */
bool csg_camera_angle(csg_camera_src *c, double degrees, csg_loc loc, csg_diag *d);

#endif
