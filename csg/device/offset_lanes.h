/*
 * offset_lanes.h — where a secondary ray starts (offset.h explains the two
 * bounds), lane-generic (lanes.h): included by offset.h for one ray
 * (offset_magnitude, offset_wb, offset_component, offset_point: the C
 * workers and the one-ray kernel) and by simd_kernels/packet.h for a
 * packet (..._pk: the packet program's csg_shadows, the hit frames of the
 * lanes that met one sphere at once).  No include guard: each inclusion
 * is one compilation of the template.
 */
#include "lanes.h"

/* A real's bits as the signed integer of its width, and back; a real
 * converted to that integer (toward zero). */
#ifdef CSG_LANES_PACKET
#define OFFSET_L_BITS intv
#define OFFSET_L_AS_BITS(x) CSG_PK_AS_INT(x)
#define OFFSET_L_AS_REAL(b) CSG_PK_AS_REAL(b)
#define OFFSET_L_TO_BITS(x) CSG_PK_TO_INT(x)
#else
#define OFFSET_L_BITS offset_bits
#define OFFSET_L_AS_BITS(x) offset_as_bits(x)
#define OFFSET_L_AS_REAL(b) offset_as_real(b)
#define OFFSET_L_TO_BITS(x) ((offset_bits)(x))
#endif

/* The magnitude of the computation that produced o + t d. */
CSG_FN L_REAL L_FN(offset_magnitude)(L_VEC3 o, L_VEC3 d, L_REAL t)
{
    L_REAL om = L_FN(r_fmax)(L_FABS(o.x), L_FN(r_fmax)(L_FABS(o.y), L_FABS(o.z)));
    L_REAL dm = L_FN(r_fmax)(L_FABS(d.x), L_FN(r_fmax)(L_FABS(d.y), L_FABS(d.z)));
    L_REAL m = L_FN(r_fmax)(om, t * dm);
    return L_SEL(m == m, m, L_RS(0.0)); /* a NaN magnitude adds nothing */
}

/* Wächter and Binder's offset of one component, near-zero band scaled. */
CSG_FN L_REAL L_FN(offset_wb)(L_REAL p, L_REAL n, L_REAL scale)
{
    L_INT near_zero = L_FABS(p) < OFFSET_ORIGIN * scale;
    L_REAL flat = p + OFFSET_FLOAT_SCALE * scale * n;
    if (!L_ANY(!near_zero)) /* (one ray: the band's offset alone) */
        return flat;
    OFFSET_L_BITS step = OFFSET_L_TO_BITS(OFFSET_INT_SCALE * n);
    OFFSET_L_BITS bits = OFFSET_L_AS_BITS(p);
    bits += L_SEL(p < R(0.0), -step, step);
    return L_SEL(near_zero, flat, OFFSET_L_AS_REAL(bits));
}

CSG_FN L_REAL L_FN(offset_component)(L_REAL p, L_REAL n, L_REAL m)
{
    L_REAL wb = L_FN(offset_wb)(p, n, L_FN(r_fmin)(L_RS(1.0), m));
    L_REAL ab = p + OFFSET_ERR_ULPS * OFFSET_UNIT_ROUNDOFF * m * n;
    return L_SEL(n >= R(0.0), L_FN(r_fmax)(wb, ab), L_FN(r_fmin)(wb, ab));
}

/* p moved off the surface along n (unit, pointing to the side the new ray
 * leaves to); m from offset_magnitude of the ray that found p. */
CSG_FN L_VEC3 L_FN(offset_point)(L_VEC3 p, L_VEC3 n, L_REAL m)
{
    return L_FN(v3)(L_FN(offset_component)(p.x, n.x, m), L_FN(offset_component)(p.y, n.y, m),
                    L_FN(offset_component)(p.z, n.z, m));
}

#undef OFFSET_L_BITS
#undef OFFSET_L_AS_BITS
#undef OFFSET_L_AS_REAL
#undef OFFSET_L_TO_BITS
#define CSG_LANES_END
#include "lanes.h"
