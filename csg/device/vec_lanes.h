/*
 * vec_lanes.h — three-component vectors and fmin/fmax, lane-generic
 * (lanes.h): included by vec.h for one ray (vec3, v3_add, r_fmin, ...) and
 * by simd_kernels/packet.h for a packet (vec3_pk, v3_add_pk, r_fmin_pk, ...).
 * No include guard: each inclusion is one compilation of the template.
 *
 * A vector is a plain struct of three lanes, never OpenCL's float3 (16
 * bytes there, 12 as three C floats).  Every operation is written out
 * component by component in a fixed order so both compilers evaluate the
 * same expression tree.
 *
 * r_fmin / r_fmax are written out rather than mapped to fmin/fmax: with
 * IEEE semantics kept (no -ffast-math) C compilers call libm for those,
 * which cost 15% of a render.  They return the other argument when one is
 * a NaN, like fmin/fmax; between +0 and -0 they return the first.
 */
#include "lanes.h"

typedef struct {
    L_REAL x, y, z;
} L_VEC3;

CSG_FN L_REAL L_FN(r_fmin)(L_REAL a, L_REAL b) { return L_SEL(a != a, b, L_SEL(b < a, b, a)); }
CSG_FN L_REAL L_FN(r_fmax)(L_REAL a, L_REAL b) { return L_SEL(a != a, b, L_SEL(b > a, b, a)); }

CSG_FN L_VEC3 L_FN(v3)(L_REAL x, L_REAL y, L_REAL z)
{
    L_VEC3 r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}

CSG_FN L_VEC3 L_FN(v3_add)(L_VEC3 a, L_VEC3 b) { return L_FN(v3)(a.x + b.x, a.y + b.y, a.z + b.z); }
CSG_FN L_VEC3 L_FN(v3_sub)(L_VEC3 a, L_VEC3 b) { return L_FN(v3)(a.x - b.x, a.y - b.y, a.z - b.z); }
CSG_FN L_VEC3 L_FN(v3_mul)(L_VEC3 a, L_VEC3 b) { return L_FN(v3)(a.x * b.x, a.y * b.y, a.z * b.z); }
CSG_FN L_VEC3 L_FN(v3_scale)(L_VEC3 a, L_REAL s) { return L_FN(v3)(a.x * s, a.y * s, a.z * s); }
CSG_FN L_VEC3 L_FN(v3_neg)(L_VEC3 a) { return L_FN(v3)(-a.x, -a.y, -a.z); }
CSG_FN L_REAL L_FN(v3_dot)(L_VEC3 a, L_VEC3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
CSG_FN L_VEC3 L_FN(v3_cross)(L_VEC3 a, L_VEC3 b)
{
    return L_FN(v3)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
CSG_FN L_REAL L_FN(v3_length)(L_VEC3 a) { return L_SQRT(L_FN(v3_dot)(a, a)); }
/* a / |a|, as a * (1 / |a|); a itself when |a| is 0 (or NaN). */
CSG_FN L_VEC3 L_FN(v3_normalize)(L_VEC3 a)
{
    L_REAL len = L_FN(v3_length)(a);
    L_INT pos = len > R(0.0);
    L_VEC3 s = L_FN(v3_scale)(a, R(1.0) / len);
    return L_FN(v3)(L_SEL(pos, s.x, a.x), L_SEL(pos, s.y, a.y), L_SEL(pos, s.z, a.z));
}
/* a + b * s, without contraction: a multiply, then an add. */
CSG_FN L_VEC3 L_FN(v3_madd)(L_VEC3 a, L_VEC3 b, L_REAL s)
{
    return L_FN(v3_add)(a, L_FN(v3_scale)(b, s));
}
/* Three reals of the scene, the same in every lane. */
CSG_FN L_VEC3 L_FN(v3_load)(CSG_GLOBAL const real *p)
{
    return L_FN(v3)(L_RS(p[0]), L_RS(p[1]), L_RS(p[2]));
}

#define CSG_LANES_END
#include "lanes.h"
