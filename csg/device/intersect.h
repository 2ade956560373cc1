/*
 * intersect.h — ray/primitive intervals, CSG interval combination and the
 * nearest hit over a flat scene.  Shared by C (workers, tests) and OpenCL C
 * (the primary pass): one source, the same arithmetic in the same order.
 *
 * Algorithm.  Every primitive is a convex solid (a plane is a half-space),
 * so a ray line meets it in at most one interval [t0, t1]; a complemented
 * primitive gives at most two.  The leaf interval is clipped to the query
 * range [tmin, tmax]; a clipped end gets the surface id CSG_SURF_NONE and is
 * never reported as a hit.  A root's program (flat.h) then combines the
 * leaf lists with union and intersection, pointwise set operations on
 * sorted disjoint interval lists.  The hit is the first visible boundary
 * strictly after tmin.  Restricting every leaf to [tmin, tmax] first is
 * exact: set operations are pointwise, so the combined set on that range
 * depends only on the leaves on that range.
 *
 * Invariants.  Lists are sorted, disjoint and hold no empty interval
 * (t0 < t1 strictly), so the difference of two identical solids leaves
 * nothing behind (no speckles on coincident surfaces): the two computations
 * give the same bits.  Touching intervals merge in a union: merge's inner
 * surfaces vanish.  A list that would exceed CSG_MAX_SPANS keeps its nearest
 * intervals and records in `limit` where knowledge ends; hits beyond the
 * limit are not reported (the flattener warns when a scene can reach it).
 *
 * Nothing here recurses or uses function pointers (OpenCL forbids both).
 */
#ifndef CSG_INTERSECT_H
#define CSG_INTERSECT_H

#include "flat.h"
#include "vec.h"

/* csg_ray, csg_hit, the transforms, the primitive tests and the
 * single-primitive hit: the one-ray compilation of intersect_lanes.h. */
#include "intersect_lanes.h"

typedef struct {
    csg_i32 n;                  /* intervals in use                      */
    real limit;                 /* nothing is known at or beyond this t  */
    real t0[CSG_MAX_SPANS];     /* entry parameter                       */
    real t1[CSG_MAX_SPANS];     /* exit parameter                        */
    csg_u32 s0[CSG_MAX_SPANS];  /* surface at entry (CSG_SURF_NONE: none) */
    csg_u32 s1[CSG_MAX_SPANS];  /* surface at exit                       */
} csg_spans;

/* Pointers to the arrays of a flat scene, in either address space.  The
 * roots 0 .. root_count - 1 are tested one by one; the others are reached
 * through the BVH (bvh_count nodes; none when 0). */
typedef struct {
    CSG_GLOBAL const csg_prim *prims;
    CSG_GLOBAL const csg_node *nodes;
    CSG_GLOBAL const csg_root *roots;
    CSG_GLOBAL const csg_bvh_node *bvh;
    csg_i32 root_count;
    csg_i32 bvh_count;
} csg_view;

/* The view of a blob (flat.h), its arrays found through its header. */
CSG_FN csg_view csg_blob_view(CSG_GLOBAL const csg_u8 *blob)
{
    CSG_GLOBAL const csg_blob_header *h = (CSG_GLOBAL const csg_blob_header *)blob;
    csg_view v;
    v.prims = (CSG_GLOBAL const csg_prim *)(blob + h->off_prims);
    v.nodes = (CSG_GLOBAL const csg_node *)(blob + h->off_nodes);
    v.roots = (CSG_GLOBAL const csg_root *)(blob + h->off_roots);
    v.bvh = (CSG_GLOBAL const csg_bvh_node *)(blob + h->off_bvh);
    v.root_count = h->linear_roots;
    v.bvh_count = h->bvh_count;
    return v;
}

/* ---- affine transforms: points and vectors in intersect_lanes.h ------ */

/* Normals transform with the transpose of the world->local matrix. */
CSG_FN vec3 csg_xform_normal(CSG_GLOBAL const real *m, vec3 n)
{
    return v3(m[0] * n.x + m[4] * n.y + m[8] * n.z,
              m[1] * n.x + m[5] * n.y + m[9] * n.z,
              m[2] * n.x + m[6] * n.y + m[10] * n.z);
}

/* ---- interval lists ------------------------------------------------------ */

CSG_FN void csg_spans_clear(csg_spans *l, real limit)
{
    l->n = 0;
    l->limit = limit;
}

/* Append [t0, t1] (already sorted after the last one); empty intervals are
 * dropped, a touching one is merged, and a full list moves `limit` in. */
CSG_FN void csg_spans_push(csg_spans *l, real t0, csg_u32 s0, real t1, csg_u32 s1)
{
    if (t1 > l->limit) {
        t1 = l->limit;
        s1 = CSG_SURF_NONE;
    }
    if (!(t0 < t1))
        return;
    if (l->n > 0 && t0 <= l->t1[l->n - 1]) {
        if (t1 > l->t1[l->n - 1]) {
            l->t1[l->n - 1] = t1;
            l->s1[l->n - 1] = s1;
        }
        return;
    }
    if (l->n == CSG_MAX_SPANS) {
        l->limit = t0;
        return;
    }
    l->t0[l->n] = t0;
    l->t1[l->n] = t1;
    l->s0[l->n] = s0;
    l->s1[l->n] = s1;
    l->n++;
}

/* The interval list of one primitive on [tmin, tmax]. */
CSG_FN void csg_leaf_spans(CSG_GLOBAL const csg_prim *prims, csg_i32 i, csg_ray r,
                           real tmin, real tmax, csg_spans *out)
{
    CSG_GLOBAL const csg_prim *p = &prims[i];
    real t0, t1;
    csg_i32 s0, s1;
    csg_spans_clear(out, tmax);
    int hit = csg_prim_span(p, r, &t0, &t1, &s0, &s1);
    if (!(p->flags & CSG_PF_INVERT)) {
        if (!hit)
            return;
        csg_u32 e0 = t0 < tmin ? CSG_SURF_NONE : csg_surf_of(i, s0, 0u, p->flags);
        csg_u32 e1 = csg_surf_of(i, s1, 0u, p->flags);
        csg_spans_push(out, r_fmax(t0, tmin), e0, t1, e1);
        return;
    }
    /* complement: the line minus [t0, t1], normals reversed */
    if (!hit) {
        csg_spans_push(out, tmin, CSG_SURF_NONE, tmax, CSG_SURF_NONE);
        return;
    }
    csg_spans_push(out, tmin, CSG_SURF_NONE, t0, csg_surf_of(i, s0, 1u, p->flags));
    csg_u32 e1 = t1 < tmin ? CSG_SURF_NONE : csg_surf_of(i, s1, 1u, p->flags);
    csg_spans_push(out, r_fmax(t1, tmin), e1, tmax, CSG_SURF_NONE);
}

/* out = a ∪ b (out may not alias a or b). */
CSG_FN void csg_spans_union(const csg_spans *a, const csg_spans *b, csg_spans *out)
{
    csg_i32 i = 0, j = 0;
    csg_spans_clear(out, r_fmin(a->limit, b->limit));
    while (i < a->n || j < b->n) {
        int take_a = j >= b->n || (i < a->n && a->t0[i] <= b->t0[j]);
        if (take_a) {
            csg_spans_push(out, a->t0[i], a->s0[i], a->t1[i], a->s1[i]);
            i++;
        } else {
            csg_spans_push(out, b->t0[j], b->s0[j], b->t1[j], b->s1[j]);
            j++;
        }
    }
}

/* out = a ∩ b (out may not alias a or b). */
CSG_FN void csg_spans_intersect(const csg_spans *a, const csg_spans *b, csg_spans *out)
{
    csg_i32 i = 0, j = 0;
    csg_spans_clear(out, r_fmin(a->limit, b->limit));
    while (i < a->n && j < b->n) {
        real t0 = a->t0[i];
        csg_u32 s0 = a->s0[i];
        if (b->t0[j] > t0) {
            t0 = b->t0[j];
            s0 = b->s0[j];
        }
        real t1 = a->t1[i];
        csg_u32 s1 = a->s1[i];
        if (b->t1[j] < t1) {
            t1 = b->t1[j];
            s1 = b->s1[j];
        }
        csg_spans_push(out, t0, s0, t1, s1);
        if (a->t1[i] < b->t1[j])
            i++;
        else
            j++;
    }
}

CSG_FN void csg_spans_copy(const csg_spans *src, csg_spans *dst)
{
    dst->n = src->n;
    dst->limit = src->limit;
    for (csg_i32 k = 0; k < src->n; k++) {
        dst->t0[k] = src->t0[k];
        dst->t1[k] = src->t1[k];
        dst->s0[k] = src->s0[k];
        dst->s1[k] = src->s1[k];
    }
}

/* ---- a root ---------------------------------------------------------------- */

/* Does the ray meet the box lo..hi on [tmin, tmax]?  Unbounded boxes hold
 * infinities; fmin/fmax drop the NaN of 0 * inf so those always pass. */
CSG_FN int csg_aabb_overlaps(CSG_GLOBAL const real *lo_b, CSG_GLOBAL const real *hi_b, csg_ray r,
                             real tmin, real tmax)
{
    real lo = tmin, hi = tmax;
    real o[3], d[3];
    o[0] = r.o.x; o[1] = r.o.y; o[2] = r.o.z;
    d[0] = r.d.x; d[1] = r.d.y; d[2] = r.d.z;
    for (int a = 0; a < 3; a++) {
        if (d[a] == R(0.0)) {
            if (o[a] < lo_b[a] || o[a] > hi_b[a])
                return 0;
            continue;
        }
        real ta = (lo_b[a] - o[a]) / d[a];
        real tb = (hi_b[a] - o[a]) / d[a];
        lo = r_fmax(lo, r_fmin(ta, tb));
        hi = r_fmin(hi, r_fmax(ta, tb));
    }
    return lo <= hi;
}

CSG_FN int csg_box_overlaps(CSG_GLOBAL const csg_root *root, csg_ray r, real tmin, real tmax)
{
    return csg_aabb_overlaps(root->lo, root->hi, r, tmin, tmax);
}

/* The interval list of a whole root on [tmin, tmax], through its program. */
CSG_FN void csg_root_spans(csg_view v, csg_i32 root, csg_ray r, real tmin, real tmax,
                           csg_spans *out)
{
    CSG_GLOBAL const csg_root *rt = &v.roots[root];
    if (rt->node_count == 1) {
        csg_leaf_spans(v.prims, v.nodes[rt->first_node].prim, r, tmin, tmax, out);
        return;
    }
    csg_spans stack[CSG_STACK_MAX];
    csg_spans tmp;
    csg_i32 top = 0;
    for (csg_i32 k = 0; k < rt->node_count; k++) {
        csg_node n = v.nodes[rt->first_node + k];
        if (n.op == CSG_OP_PRIM) {
            if (top == CSG_STACK_MAX) /* the flattener prevents this */
                break;
            csg_leaf_spans(v.prims, n.prim, r, tmin, tmax, &stack[top]);
            top++;
            continue;
        }
        if (top < 2)
            break;
        if (n.op == CSG_OP_UNION)
            csg_spans_union(&stack[top - 2], &stack[top - 1], &tmp);
        else
            csg_spans_intersect(&stack[top - 2], &stack[top - 1], &tmp);
        csg_spans_copy(&tmp, &stack[top - 2]);
        top--;
    }
    if (top == 1)
        csg_spans_copy(&stack[0], out);
    else
        csg_spans_clear(out, tmax);
}

/* The first visible boundary strictly after tmin. */
CSG_FN csg_hit csg_first_boundary(const csg_spans *l, real tmin)
{
    csg_hit h;
    h.t = CSG_R_INF;
    h.surf = CSG_SURF_NONE;
    for (csg_i32 k = 0; k < l->n; k++) {
        if (l->s0[k] != CSG_SURF_NONE && l->t0[k] > tmin) {
            h.t = l->t0[k];
            h.surf = l->s0[k];
            return h;
        }
        if (l->s1[k] != CSG_SURF_NONE && l->t1[k] > tmin) {
            h.t = l->t1[k];
            h.surf = l->s1[k];
            return h;
        }
    }
    return h;
}

/* Root i's first visible boundary, if it wins against *best. */
CSG_FN void csg_try_root(csg_view v, csg_i32 i, csg_ray r, real tmin, csg_hit *best)
{
    CSG_GLOBAL const csg_root *rt = &v.roots[i];
    real tmax = csg_hit_limit(best);
    if (!csg_box_overlaps(rt, r, tmin, tmax))
        return;
    csg_hit h;
    csg_i32 leaf = rt->node_count == 1 ? v.nodes[rt->first_node].prim : -1;
    if (leaf >= 0 && !(v.prims[leaf].flags & CSG_PF_INVERT)) {
        h = csg_leaf_first_hit(v.prims, leaf, r, tmin, tmax);
    } else {
        csg_spans spans;
        csg_root_spans(v, i, r, tmin, tmax, &spans);
        h = csg_first_boundary(&spans, tmin);
    }
    if (csg_hit_wins(h, best))
        *best = h;
}

/* The nearest visible surface on (tmin, tmax) over every root: first the
 * roots tested one by one, then the BVH, nearer child first.  Ties go to
 * the lower surface id (csg_hit_wins), so the answer depends neither on
 * the visiting order nor on where this runs. */
CSG_FN csg_hit csg_trace_nearest(csg_view v, csg_ray r, real tmin, real tmax)
{
    csg_hit best;
    best.t = tmax;
    best.surf = CSG_SURF_NONE;
    for (csg_i32 i = 0; i < v.root_count; i++)
        csg_try_root(v, i, r, tmin, &best);
    csg_i32 stack[CSG_BVH_STACK];
    csg_i32 top = 0;
    if (v.bvh_count > 0)
        stack[top++] = 0;
    while (top > 0) {
        csg_i32 k = stack[--top];
        CSG_GLOBAL const csg_bvh_node *n = &v.bvh[k];
        if (!csg_aabb_overlaps(n->lo, n->hi, r, tmin, csg_hit_limit(&best)))
            continue;
        if (n->count > 0) {
            for (csg_i32 i = n->first; i < n->first + n->count; i++)
                csg_try_root(v, i, r, tmin, &best);
            continue;
        }
        if (top + 2 > CSG_BVH_STACK) /* the flattener prevents this */
            break;
        csg_i32 axis = -1 - n->count;
        real dir = axis == 0 ? r.d.x : (axis == 1 ? r.d.y : r.d.z);
        /* push the far child first so the near one is visited first */
        if (dir < R(0.0)) {
            stack[top++] = k + 1;
            stack[top++] = n->first;
        } else {
            stack[top++] = n->first;
            stack[top++] = k + 1;
        }
    }
    if (best.surf == CSG_SURF_NONE)
        best.t = CSG_R_INF;
    return best;
}

/* ---- normals ---------------------------------------------------------------- */

/* The outward normal (not normalised) of each kind at local point lp of
 * its sub-surface `sub`. */
CSG_FN vec3 csg_sphere_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    (void)sub;
    return v3_sub(lp, v3_load(p));
}

CSG_FN vec3 csg_box_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    (void)p;
    (void)lp;
    real s = (sub & 1) ? R(1.0) : R(-1.0);
    int axis = sub >> 1;
    return v3(axis == 0 ? s : R(0.0), axis == 1 ? s : R(0.0), axis == 2 ? s : R(0.0));
}

CSG_FN vec3 csg_cone_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    if (sub == CSG_SURF_CONE_BASE)
        return v3(R(0.0), R(0.0), R(-1.0));
    if (sub == CSG_SURF_CONE_TOP)
        return v3(R(0.0), R(0.0), R(1.0));
    real k = (p[1] - p[0]) / p[2];
    real rz = p[0] + k * lp.z;
    return v3(lp.x, lp.y, -k * rz);
}

CSG_FN vec3 csg_plane_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    (void)sub;
    (void)lp;
    return v3_load(p);
}

CSG_FN vec3 csg_local_normal(CSG_GLOBAL const csg_prim *p, csg_i32 sub, vec3 lp)
{
    switch (p->kind) {
#define CSG_NORMAL_CASE(ID, name)                                                                  \
    case CSG_PRIM_##ID:                                                                            \
        return csg_##name##_normal(p->p, sub, lp);
        CSG_PRIM_KINDS(CSG_NORMAL_CASE)
#undef CSG_NORMAL_CASE
    default:
        return v3(R(0.0), R(0.0), R(0.0));
    }
}

/* The unit outward normal of the solid at world point wp on surface s. */
CSG_FN vec3 csg_surface_normal(CSG_GLOBAL const csg_prim *prims, csg_u32 s, vec3 wp)
{
    CSG_GLOBAL const csg_prim *p = &prims[CSG_SURF_PRIM(s)];
    vec3 lp = (p->flags & CSG_PF_XFORM) ? csg_xform_point(p->inv, wp) : wp;
    vec3 n = csg_local_normal(p, CSG_SURF_SUB(s), lp);
    if (p->flags & CSG_PF_XFORM)
        n = csg_xform_normal(p->inv, n);
    n = v3_normalize(n);
    return CSG_SURF_FLIP(s) ? v3_neg(n) : n;
}

#endif
