/*
 * vec.h — three-component vectors of `real`, shared by C and OpenCL C.
 *
 * A plain struct of three scalars, never OpenCL's float3 (16 bytes there,
 * 12 as three C floats): the layout is the same on both sides.  Every
 * operation is written out component by component in a fixed order so the
 * two compilers evaluate the same expression tree.
 */
#ifndef CSG_VEC_H
#define CSG_VEC_H

#include "portable.h"

typedef struct {
    real x, y, z;
} vec3;

CSG_FN vec3 v3(real x, real y, real z)
{
    vec3 r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}

CSG_FN vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
CSG_FN vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
CSG_FN vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
CSG_FN vec3 v3_scale(vec3 a, real s) { return v3(a.x * s, a.y * s, a.z * s); }
CSG_FN vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
CSG_FN real v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
CSG_FN vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
CSG_FN real v3_length(vec3 a) { return r_sqrt(v3_dot(a, a)); }
CSG_FN vec3 v3_normalize(vec3 a)
{
    real len = v3_length(a);
    return len > R(0.0) ? v3_scale(a, R(1.0) / len) : a;
}
/* a + b * s, without contraction: a multiply, then an add. */
CSG_FN vec3 v3_madd(vec3 a, vec3 b, real s) { return v3_add(a, v3_scale(b, s)); }
CSG_FN vec3 v3_load(CSG_GLOBAL const real *p) { return v3(p[0], p[1], p[2]); }

#endif
