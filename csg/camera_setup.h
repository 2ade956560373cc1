/*
 * camera_setup.h — POV-Ray 3.7's camera statement, in double.
 *
 * Since #version 3.5 POV-Ray applies the items of a camera statement in a
 * fixed order, whatever the order they are written in: location,
 * direction, up, right and sky are plain values (the last one written
 * counts), then angle (sets the length of direction from right), then
 * look_at (turns the camera), then the orthographic sizing, then the
 * transforms.  csg_camera_mods collects what needs that order and
 * csg_camera_apply applies it.  Scenes that say #version 3.1 or older get
 * POV-Ray's old behaviour: every item applied where it is written
 * (csg_camera_look_at, csg_camera_angle, ... one by one).
 */
#ifndef CSG_CAMERA_SETUP_H
#define CSG_CAMERA_SETUP_H

#include <stdbool.h>

#include "scene.h"

/* The items of one camera statement that POV-Ray applies at its end. */
typedef struct {
    bool has_look_at, has_up, has_right, has_angle, has_xform;
    dvec3 look_at;
    csg_loc look_at_loc;
    double angle;         /* has_angle; 0 for an orthographic `angle` alone */
    csg_loc angle_loc;
    csg_xform xform;      /* translate / rotate / scale / matrix, in order    */
} csg_camera_mods;

/* location 0, direction z, up y, right 1.33 x, sky y, look_at z,
 * perspective (POV-Ray's defaults). */
void csg_camera_default(csg_camera_src *c);
void csg_camera_mods_init(csg_camera_mods *m);
/* Perspective or orthographic: a camera whose rays come from a plane of
 * the image (the others, POV-Ray's cylinder, ultra_wide_angle, panoramic
 * and spherical cameras, bend them through angles). */
bool csg_camera_planar(const csg_camera_src *c);
/* POV-Ray 3.5+: angle, look_at, the orthographic sizing and the transforms
 * of m, in that order; false (and d filled) as the functions below. */
bool csg_camera_apply(csg_camera_src *c, const csg_camera_mods *m, csg_diag *d);
/* Points the camera at `target`, keeping the lengths of direction, right
 * and up and the handedness of right; false (and d filled) when target is
 * the location or sky is parallel to the view direction. */
bool csg_camera_look_at(csg_camera_src *c, dvec3 target, csg_loc loc, csg_diag *d);
/* Horizontal field of view in degrees, 0 < angle < 180: sets the length of
 * direction to |right| / 2 / tan(angle / 2). */
bool csg_camera_angle(csg_camera_src *c, double degrees, csg_loc loc, csg_diag *d);
/* Orthographic: right and up scaled by |look_at - location| / |direction|,
 * so the view covers what the perspective camera shows at the look_at
 * distance (POV-Ray's rule). */
void csg_camera_orthographic_size(csg_camera_src *c);
/* The camera moved by x: location as a point, direction, up and right as
 * directions (sky and look_at stay, as in POV-Ray). */
void csg_camera_transform(csg_camera_src *c, const csg_xform *x);

#endif
