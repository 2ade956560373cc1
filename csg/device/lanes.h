/*
 * lanes.h — the vocabulary of the lane-generic geometry: the code of
 * vec_lanes.h, intersect_lanes.h and camera_lanes.h is written once over a
 * "lane" type and compiled twice:
 *   - for one ray: a lane is a `real` (C workers, tests, the one-ray-per-
 *     work-item kernel); vec.h, intersect.h and camera.h include the
 *     templates this way, and the functions keep their plain names
 *     (csg_sphere_span, v3_add, ...);
 *   - for a packet of rays (simd_kernels/packet.h, OpenCL only, with
 *     CSG_LANES_PACKET defined): a lane is one component of an OpenCL
 *     vector (realv: float16, double8, ...) and every name gets _pk.
 *
 * The rules that make the two compilations give the same bits lane by lane:
 *   - every arithmetic operation on L_REAL is one IEEE operation applied
 *     per lane (+ - * / and L_SQRT, correctly rounded on both sides, and
 *     L_FLOOR, exact), in the
 *     same order in both compilations because it is the same source;
 *   - no branch on lane data: a branch of the one-ray code becomes a mask
 *     (a comparison: 1/0 for one ray, -1/0 per lane for a packet, both of
 *     type L_INT) and L_SEL picks per lane, so a lane computes exactly what
 *     the one ray would on its path; the other path's values are computed
 *     too and thrown away (a NaN there never reaches a result);
 *   - masks combine with & | ! only (never ~, never arithmetic);
 *   - an early exit tests L_ANY: "no lane is still going" (one ray: the
 *     ray is not), so the one-ray code keeps its early returns;
 *   - constants enter through L_RS / L_IS / L_US (a cast, which OpenCL
 *     turns into a splat), loads from the scene are uniform scalars.
 *
 * Each template opens with #include "lanes.h" and closes with
 * #define CSG_LANES_END then #include "lanes.h", which removes the
 * vocabulary again, so the two compilations can follow each other in one
 * translation unit.
 */
#ifndef CSG_LANES_END

#ifdef CSG_LANES_PACKET
/* simd_kernels/packet.h has defined realv, intv, uintv (W lanes; intv and
 * uintv have the width of real, so a comparison of realv is an intv) and
 * the conversions CSG_PK_TO_REAL (intv -> realv), CSG_PK_AS_UINT /
 * CSG_PK_AS_REAL (bit casts realv <-> the unsigned integer of its width)
 * CSG_PK_I_AS_U (intv -> uintv, bits kept) and CSG_PK_ANY (any lane set). */
#define L_REAL realv
#define L_INT intv
#define L_UINT uintv
#define L_FN(name) name##_pk
#define L_SEL(c, t, f) select((f), (t), (c))
#define L_ANY(m) CSG_PK_ANY(m)
#define L_SQRT(x) sqrt(x)
#define L_FABS(x) fabs(x)
#define L_FLOOR(x) floor(x)
#define L_TO_REAL(i) CSG_PK_TO_REAL(i)
#define L_TO_UINT(i) CSG_PK_I_AS_U(i)
/* r_next_up lane by lane: the same integer step on the bits */
#define L_NEXT_UP(t) select((t), CSG_PK_AS_REAL(CSG_PK_AS_UINT(t) + 1), (t) < CSG_R_INF)
#else
#define L_REAL real
#define L_INT csg_i32
#define L_UINT csg_u32
#define L_FN(name) name
#define L_SEL(c, t, f) ((c) ? (t) : (f))
#define L_ANY(m) (m)
#define L_SQRT(x) r_sqrt(x)
#define L_FABS(x) r_fabs(x)
#define L_FLOOR(x) r_floor(x)
#define L_TO_REAL(i) ((real)(i))
#define L_TO_UINT(i) ((csg_u32)(i))
#define L_NEXT_UP(t) r_next_up(t)
#endif

#define L_RS(x) ((L_REAL)(x)) /* a real in every lane     */
#define L_IS(x) ((L_INT)(x))  /* an integer in every lane */
#define L_US(x) ((L_UINT)(x))
#define L_VEC3 L_FN(vec3)
#define L_RAY L_FN(csg_ray)
#define L_HIT L_FN(csg_hit)

#else /* CSG_LANES_END: take the vocabulary back */

#undef L_REAL
#undef L_INT
#undef L_UINT
#undef L_FN
#undef L_SEL
#undef L_ANY
#undef L_SQRT
#undef L_FABS
#undef L_FLOOR
#undef L_TO_REAL
#undef L_TO_UINT
#undef L_NEXT_UP
#undef L_RS
#undef L_IS
#undef L_US
#undef L_VEC3
#undef L_RAY
#undef L_HIT
#undef CSG_LANES_END

#endif
