/*
 * frame_lanes.h — a primary hit's frame once its normals are known: the
 * point, whether the ray enters, the geometry's normal on the ray's side,
 * the offset scale and where shadow and reflected rays start (shadow.h's
 * csg_hit_frame_of), lane-generic (lanes.h): included by shadow.h for one
 * ray and by simd_kernels/packet.h for a packet (..._pk: csg_shadows'
 * frames, every lane that hit the same surface at once).  No include
 * guard: each inclusion is one compilation of the template.
 */
#include "lanes.h"

/* o + t d. */
CSG_FN L_VEC3 L_FN(csg_hit_point)(L_RAY r, L_REAL t)
{
    return L_FN(v3_add)(r.o, L_FN(v3_scale)(r.d, t));
}

/* Where secondary rays leave the hit at t along r, point p, whose
 * geometric normal is ng (unit, outward) and whose root's box has the
 * magnitude box_mag (offset_box_magnitude): *entering (the ray enters the
 * solid), *ngf (ng on the ray's side), *mag (the offset's scale). */
CSG_FN L_VEC3 L_FN(csg_frame_offset)(L_RAY r, L_REAL t, L_VEC3 p, L_VEC3 ng, L_REAL box_mag,
                                     L_INT *entering, L_VEC3 *ngf, L_REAL *mag)
{
    *entering = L_FN(v3_dot)(ng, r.d) < R(0.0);
    *ngf = L_FN(v3)(L_SEL(*entering, ng.x, -ng.x), L_SEL(*entering, ng.y, -ng.y),
                    L_SEL(*entering, ng.z, -ng.z));
    *mag = L_FN(r_fmax)(L_FN(offset_magnitude)(r.o, r.d, t), box_mag);
    return L_FN(offset_point)(p, *ngf, *mag);
}

/* csg_surface_normal (intersect.h) of surface s of an untransformed
 * sphere centred at c, at world point wp: its local normal, normalised,
 * reversed on a flipped surface; the same operations. */
CSG_FN L_VEC3 L_FN(csg_sphere_surface_normal)(CSG_GLOBAL const real *c, csg_u32 s, L_VEC3 wp)
{
    L_VEC3 n = L_FN(v3_normalize)(L_FN(v3_sub)(wp, L_FN(v3_load)(c)));
    return CSG_SURF_FLIP(s) ? L_FN(v3_neg)(n) : n;
}

#define CSG_LANES_END
#include "lanes.h"
