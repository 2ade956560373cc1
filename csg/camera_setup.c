/*
 * camera_setup.c — POV-Ray's perspective camera semantics, in double.
 *
 * look_at keeps |direction|, |right| and |up| and rebuilds the frame:
 * direction along target - location, right = sky x direction, up =
 * direction x right (left-handed, as in POV-Ray).  A `right` given with the
 * other handedness (e.g. right -x for a right-handed scene) keeps it.
 */
#include "camera_setup.h"

#include <math.h>

static dvec3 d3(double x, double y, double z) { return (dvec3){x, y, z}; }
static dvec3 d3_sub(dvec3 a, dvec3 b) { return d3(a.x - b.x, a.y - b.y, a.z - b.z); }
static dvec3 d3_scale(dvec3 a, double s) { return d3(a.x * s, a.y * s, a.z * s); }
static double d3_dot(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double d3_len(dvec3 a) { return sqrt(d3_dot(a, a)); }
static dvec3 d3_cross(dvec3 a, dvec3 b)
{
    return d3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

void csg_camera_default(csg_camera_src *c)
{
    c->location = d3(0, 0, 0);
    c->direction = d3(0, 0, 1);
    c->up = d3(0, 1, 0);
    c->right = d3(1.33, 0, 0);
    c->sky = d3(0, 1, 0);
}

bool csg_camera_look_at(csg_camera_src *c, dvec3 target, csg_loc loc, csg_diag *d)
{
    double dir_len = d3_len(c->direction);
    double up_len = d3_len(c->up);
    double right_len = d3_len(c->right);
    double handedness = d3_dot(d3_cross(c->up, c->direction), c->right);
    dvec3 view = d3_sub(target, c->location);
    double view_len = d3_len(view);
    if (!(view_len > 0)) {
        csg_error(d, loc, "camera look_at equals its location: no view direction");
        return false;
    }
    dvec3 dir = d3_scale(view, 1.0 / view_len);
    dvec3 right = d3_cross(c->sky, dir);
    double rlen = d3_len(right);
    if (!(rlen > 1e-12 * d3_len(c->sky))) {
        csg_error(d, loc, "camera sky is parallel to the view direction");
        return false;
    }
    right = d3_scale(right, 1.0 / rlen);
    dvec3 up = d3_cross(dir, right);
    up = d3_scale(up, 1.0 / d3_len(up));
    c->direction = d3_scale(dir, dir_len);
    c->right = d3_scale(right, handedness < 0 ? -right_len : right_len);
    c->up = d3_scale(up, up_len);
    return true;
}

bool csg_camera_angle(csg_camera_src *c, double degrees, csg_loc loc, csg_diag *d)
{
    if (!(degrees > 0 && degrees < 180)) {
        csg_error(d, loc, "camera angle must be between 0 and 180 degrees, got %g", degrees);
        return false;
    }
    double dir_len = d3_len(c->direction);
    double want = 0.5 * d3_len(c->right) / tan(degrees * M_PI / 360.0);
    if (!(dir_len > 0)) {
        csg_error(d, loc, "camera direction has zero length");
        return false;
    }
    c->direction = d3_scale(c->direction, want / dir_len);
    return true;
}
