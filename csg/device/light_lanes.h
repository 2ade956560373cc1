/*
 * light_lanes.h — the line from a point to a light and the shadow ray's
 * reach, lane-generic (lanes.h): included by shadow.h for one ray
 * (csg_light_ray, csg_light_line, csg_shadow_reach: the C workers and the
 * one-ray kernel) and by simd_kernels/packet.h for a packet (..._pk: the
 * packet program's csg_shadows, every lane's line to a light at once).
 * No include guard: each inclusion is one compilation of the template.
 * The light is the same in every lane, so its branches are uniform.
 */
#include "lanes.h"

/* POV-Ray's ComputeOneWhiteLightRay: the unit direction *l from point o to
 * light lt whose centre is `center` (its position, or a point of an area
 * light's grid) and how far the shadow ray goes. */
CSG_FN void L_FN(csg_light_ray)(CSG_GLOBAL const csg_flat_light *lt, L_VEC3 o, L_VEC3 center,
                                L_VEC3 *l, L_REAL *dist)
{
    if (lt->kind == CSG_LIGHT_CYLINDER) {
        L_VEC3 dir = L_FN(v3_sub)(center, L_FN(v3_load)(lt->point_at));
        L_REAL len = L_FN(v3_length)(dir);
        *dist = L_FN(v3_dot)(L_FN(v3_sub)(center, o), dir) / len;
        *l = L_FN(v3_scale)(dir, R(1.0) / len);
    } else {
        L_VEC3 to_light = L_FN(v3_sub)(center, o);
        *dist = L_FN(v3_length)(to_light);
        *l = L_FN(v3_scale)(to_light, R(1.0) / *dist);
    }
    if (lt->parallel) {
        if (lt->area) {
            L_VEC3 v1 = L_FN(v3_normalize)(L_FN(v3_sub)(center, L_FN(v3_load)(lt->point_at)));
            *dist *= L_FN(v3_dot)(v1, *l);
            *l = v1;
        } else {
            L_VEC3 d = L_FN(v3_load)(lt->direction);
            *dist *= -L_FN(v3_dot)(d, *l);
            *l = L_FN(v3_neg)(d);
        }
    }
}

/* The line from o to light lt's position that shading and its shadow ray
 * follow; false (a 0 lane) where the light is skipped (o at the light). */
CSG_FN L_INT L_FN(csg_light_line)(CSG_GLOBAL const csg_flat_light *lt, L_VEC3 o, L_VEC3 *l,
                                  L_REAL *dist)
{
    L_FN(csg_light_ray)(lt, o, L_FN(v3_load)(lt->position), l, dist);
    return (*dist > R(0.0)) | (L_IS(lt->parallel) != L_IS(0));
}

/* POV-Ray's SHADOW_TOLERANCE (trace.cpp, TracePointLightShadowRay): a
 * surface closer than 1e-3 to the light casts no shadow, so a light on
 * a surface (lights/laser.pov: a spotlight on a cylinder's cap) is not
 * hidden by it where rounding puts the cap before the light.  Below a
 * distance of 1 it shrinks with the distance (1e-3 of it), so a scene
 * drawn at 10^-4 of its size keeps its shadows (POV-Ray's absolute
 * tolerance would remove them all; tests/test_stability's scale
 * invariance); from 1 on it is POV-Ray's.  The segment's end. */
CSG_FN L_REAL L_FN(csg_shadow_reach)(L_REAL dist)
{
    return dist - L_FN(r_fmin)(L_RS(1.0e-3), R(1.0e-3) * dist);
}

#define CSG_LANES_END
#include "lanes.h"
