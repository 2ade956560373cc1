/*
 * shadow.h — the shadow rays of a hit, shared by the C workers
 * (workers/shade.c) and the OpenCL shadow kernel (simd_kernels/primary.cl:
 * csg_shadows): where secondary rays start (the hit point moved off the
 * surface, offset.h), the line to a light, the tolerance at the light,
 * and the yes/no answer the device gives for a light whose shadow ray
 * meets only opaque objects (#36 item 3).
 *
 * The device's answer is exact: it is what the worker's own walk
 * (light_transmittance in shade.c) finds, whatever the worker's shadow
 * cache holds:
 *   - BLOCKED: an opaque root has a visible boundary on the segment.  The
 *     worker's walk visits that root too (the same BVH walk over the same
 *     segment, the same box test, csg_shadow_opaque_blocks), unless another
 *     root blocks first: either way the light is black.
 *   - LIT: no root but opaque or no_shadow ones is met and none blocks,
 *     so the worker's transmittance stays exactly (1, 1, 1).
 *   - UNKNOWN: a root that may filter the light is met (its pigment, its
 *     interior: the worker's business), or the light is not one the device
 *     answers (csg_shadow_answerable), or is beyond CSG_SHADOW_LIGHTS.
 */
#ifndef CSG_SHADOW_H
#define CSG_SHADOW_H

#include "intersect.h"
#include "offset.h"
#include "patterns.h"

#define CSG_SHADOW_LIGHTS 32 /* lights a record answers (bits of a mask) */

enum csg_shadow_answer { CSG_SHADOW_UNKNOWN = 0, CSG_SHADOW_LIT = 1, CSG_SHADOW_BLOCKED = 2 };

/* Where a hit is and how secondary rays leave it. */
typedef struct {
    vec3 p;     /* o + t d                                                   */
    vec3 n;     /* the unit outward normal of the solid there                */
    vec3 ng;    /* the geometry's own normal (a smooth triangle's flat one)  */
    vec3 ngf;   /* ng on the ray's side                                      */
    int entering;
    real mag;   /* the offset scale of secondary rays                        */
    vec3 above; /* where reflected and shadow rays start                     */
} csg_hit_frame;

/* csg_hit_point, csg_frame_offset, csg_sphere_surface_normal: the one-ray
 * compilation of frame_lanes.h. */
#include "frame_lanes.h"

CSG_FN csg_hit_frame csg_hit_frame_of(csg_view v, csg_ray r, real t, csg_u32 surf)
{
    csg_hit_frame f;
    f.p = csg_hit_point(r, t);
    f.n = csg_surface_normal(v.prims, surf, f.p);
    /* the side of the geometry decides where secondary rays start and
     * whether the ray enters (a smooth triangle's normals may point
     * against its winding) */
    f.ng = csg_surface_geometric_normal(v.prims, surf, f.p, f.n);
    /* (a curved side's shading normal is its spline's; the ray met the
     * chord, whose normal ng stays) */
    f.n = csg_surface_shading_normal(v, surf, f.p, r.d, f.n);
    CSG_GLOBAL const csg_root *root = &v.roots[v.prims[CSG_SURF_PRIM(surf)].root];
    csg_i32 entering;
    f.above = csg_frame_offset(r, t, f.p, f.ng, offset_box_magnitude(root->lo, root->hi),
                               &entering, &f.ngf, &f.mag);
    f.entering = entering;
    return f;
}

/* csg_light_ray, csg_light_line and csg_shadow_reach: the one-ray
 * compilation of light_lanes.h. */
#include "light_lanes.h"

/* Whether opaque root i has a visible boundary on (0, dist) of r. */
CSG_FN int csg_shadow_opaque_blocks(csg_view v, csg_i32 i, csg_ray r, real dist)
{
    csg_hit h = csg_root_first_hit(v, i, r, R(0.0), dist);
    return h.surf != CSG_SURF_NONE && h.t < dist;
}

/* A light whose shadow is a plain yes/no: not shadowless, not an area
 * light (a grid of rays), not dimmed by fog on the way. */
CSG_FN int csg_shadow_answerable(CSG_GLOBAL const csg_flat_light *lt)
{
    return !lt->shadowless && !lt->area && !lt->media_attenuation;
}

/* Root i on the shadow segment (the box already tested when !test_box, as
 * the worker's walk does): BLOCKED, LIT (passes untouched) or UNKNOWN (it
 * may filter the light). */
CSG_FN int csg_shadow_root(csg_view v, csg_i32 i, csg_ray r, const csg_box_ray *br, int test_box,
                           real dist)
{
    CSG_GLOBAL const csg_root *rt = &v.roots[i];
    real t_enter;
    if (rt->flags & CSG_ROOT_NO_SHADOW)
        return CSG_SHADOW_LIT;
    if (test_box && !csg_box_hit(rt->lo, rt->hi, br, R(0.0), dist, &t_enter))
        return CSG_SHADOW_LIT;
    if (!(rt->flags & CSG_ROOT_OPAQUE))
        return CSG_SHADOW_UNKNOWN;
    return csg_shadow_opaque_blocks(v, i, r, dist) ? CSG_SHADOW_BLOCKED : CSG_SHADOW_LIT;
}

/* The answer for the shadow ray from p (already offset) along unit l to a
 * light `dist` away: the worker's walk (unbounded roots, then the BVH's
 * leaves in its order), stopped at the first blocker. */
CSG_FN int csg_shadow_answer(csg_view v, vec3 p, vec3 l, real dist)
{
    dist = csg_shadow_reach(dist);
    csg_ray r;
    r.o = p;
    r.d = l;
    csg_box_ray br = csg_box_ray_of(r);
    int answer = CSG_SHADOW_LIT;
    for (csg_i32 i = 0; i < v.root_count; i++) {
        int a = csg_shadow_root(v, i, r, &br, 1, dist);
        if (a == CSG_SHADOW_BLOCKED)
            return a;
        if (a == CSG_SHADOW_UNKNOWN)
            answer = a;
    }
    csg_bvh_walk w;
    csg_bvh_walk_start(&w, v);
    csg_i32 k;
    while ((k = csg_bvh_next_leaf(v, &br, R(0.0), dist, &w)) >= 0) {
        CSG_GLOBAL const csg_bvh_node *n = &v.bvh[k];
        for (csg_i32 i = n->first; i < n->first + n->count; i++) {
            int a = csg_shadow_root(v, i, r, &br, n->count > 1, dist);
            if (a == CSG_SHADOW_BLOCKED)
                return a;
            if (a == CSG_SHADOW_UNKNOWN)
                answer = a;
        }
    }
    return answer;
}

/* The answers for the lights of a primary hit (t, surf) of ray r: bit i
 * of *known says light i is answered, bit i of *lit that its light
 * arrives (else it is blocked).  A light the hit faces away from (by the
 * unperturbed normal) is left unknown: shading most likely skips it. */
CSG_FN void csg_shadow_masks(csg_view v, CSG_GLOBAL const csg_flat_light *lights,
                             csg_i32 light_count, csg_ray r, real t, csg_u32 surf,
                             csg_u32 *known, csg_u32 *lit)
{
    *known = 0u;
    *lit = 0u;
    if (surf == CSG_SURF_NONE)
        return;
    csg_hit_frame f = csg_hit_frame_of(v, r, t, surf);
    vec3 nf = v3_dot(f.n, r.d) > R(0.0) ? v3_neg(f.n) : f.n;
    csg_i32 n = light_count < CSG_SHADOW_LIGHTS ? light_count : CSG_SHADOW_LIGHTS;
    for (csg_i32 i = 0; i < n; i++) {
        CSG_GLOBAL const csg_flat_light *lt = &lights[i];
        vec3 l;
        real dist;
        if (!csg_shadow_answerable(lt) || !csg_light_line(lt, f.above, &l, &dist) ||
            !(v3_dot(nf, l) > R(0.0)))
            continue;
        int a = csg_shadow_answer(v, f.above, l, dist);
        if (a == CSG_SHADOW_UNKNOWN)
            continue;
        *known |= 1u << i;
        if (a == CSG_SHADOW_LIT)
            *lit |= 1u << i;
    }
}

#endif
