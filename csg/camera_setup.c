/*
 * camera_setup.c — POV-Ray 3.7's camera semantics, in double (the order
 * of the items: camera_setup.h).
 *
 * look_at keeps |direction|, |right| and |up| and rebuilds the frame:
 * direction along target - location, right = sky x direction, up =
 * direction x right (left-handed, as in POV-Ray).  A `right` given with the
 * other handedness (e.g. right -x for a right-handed scene) keeps it.
 * A sky parallel to the view (sky x direction below POV-Ray's EPSILON,
 * 1e-10, in every component) keeps the right vector's direction, as
 * POV-Ray does; only a right vector parallel to the view too is an error.
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
    c->look_at = d3(0, 0, 1);
    c->projection = CSG_PROJ_PERSPECTIVE;
    c->angle = 90;
    c->h_angle = 360;
    c->v_angle = 180;
}

bool csg_camera_planar(const csg_camera_src *c)
{
    return c->projection == CSG_PROJ_PERSPECTIVE || c->projection == CSG_PROJ_ORTHOGRAPHIC;
}

void csg_camera_mods_init(csg_camera_mods *m)
{
    *m = (csg_camera_mods){0};
    csg_xform_identity(&m->xform);
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
    if (fabs(right.x) < 1e-10 && fabs(right.y) < 1e-10 && fabs(right.z) < 1e-10)
        right = c->right;
    right = d3_scale(right, 1.0 / d3_len(right));
    dvec3 up = d3_cross(dir, right);
    double ulen = d3_len(up);
    if (!(ulen > 1e-12)) {
        csg_error(d, loc, "camera sky and right are both parallel to the view direction");
        return false;
    }
    up = d3_scale(up, 1.0 / ulen);
    c->direction = d3_scale(dir, dir_len);
    /* (POV-Ray: "> 0" keeps the right vector, anything else, 0 included when
     * up is parallel to direction, e.g. `up z` with the default direction,
     * turns it round) */
    c->right = d3_scale(right, handedness > 0 ? right_len : -right_len);
    c->up = d3_scale(up, up_len);
    c->look_at = target;
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

void csg_camera_orthographic_size(csg_camera_src *c)
{
    double k1 = d3_len(d3_sub(c->look_at, c->location)), k2 = d3_len(c->direction);
    if (k1 > 1e-10 && k2 > 1e-10) { /* POV-Ray's EPSILON */
        c->right = d3_scale(c->right, k1 / k2);
        c->up = d3_scale(c->up, k1 / k2);
    }
}

static dvec3 d3_linear(const csg_xform *x, dvec3 v)
{
    return d3(x->m[0][0] * v.x + x->m[0][1] * v.y + x->m[0][2] * v.z,
              x->m[1][0] * v.x + x->m[1][1] * v.y + x->m[1][2] * v.z,
              x->m[2][0] * v.x + x->m[2][1] * v.y + x->m[2][2] * v.z);
}

void csg_camera_transform(csg_camera_src *c, const csg_xform *x)
{
    dvec3 l = d3_linear(x, c->location);
    c->location = d3(l.x + x->m[0][3], l.y + x->m[1][3], l.z + x->m[2][3]);
    c->direction = d3_linear(x, c->direction);
    c->up = d3_linear(x, c->up);
    c->right = d3_linear(x, c->right);
}

bool csg_camera_apply(csg_camera_src *c, const csg_camera_mods *m, csg_diag *d)
{
    bool ortho = c->projection == CSG_PROJ_ORTHOGRAPHIC;
    if (m->has_angle && !csg_camera_planar(c)) /* (kept: the ray's angles) */
        c->angle = m->angle;
    else if (m->has_angle && !(ortho && m->angle == 0) &&
             !csg_camera_angle(c, m->angle, m->angle_loc, d))
        return false;
    if (m->has_look_at && !csg_camera_look_at(c, m->look_at, m->look_at_loc, d))
        return false;
    if (ortho && ((!m->has_up && !m->has_right) || m->has_angle))
        csg_camera_orthographic_size(c);
    if (m->has_xform)
        csg_camera_transform(c, &m->xform);
    return true;
}
