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
 * Surfaces (flat.h: CSG_SURFACE_KINDS, triangles, flat boxes) have no interval: a
 * crossing is a zero-length EVENT, kept in each list beside its intervals
 * (te/se, sorted, at most CSG_MAX_EVENTS).  A union keeps an operand's
 * event unless it lies strictly inside the other operand's intervals; an
 * intersection keeps it when it lies inside the other's closed intervals;
 * a complement keeps events as they are (flat.h states the meaning).  The
 * first boundary is then the nearer of the first visible interval end and
 * the first visible event (CSG_SURF_HIDDEN events block light only).
 *
 * Triangles: the watertight test of Woop, Benthin and Wald (JCGT 2(1),
 * 2013): vertices relative to the ray origin are sheared so the ray runs
 * along +z, and the three 2D edge functions decide the hit.  The edge
 * function of an edge depends only on its two vertices and the ray, and
 * the same vertices have the same bits in every triangle that shares
 * them, so a ray through a shared edge sees its two sides with opposite
 * signs of exactly one value: it meets one triangle or both, never
 * neither.  Boundary values (0) count as inside.  The paper's double
 * precision fallback for edge functions that round to 0 is left out: it
 * resolves which triangle an exact edge hit belongs to, not cracks.
 *
 * Nothing here recurses or uses function pointers (OpenCL forbids both).
 */
#ifndef CSG_INTERSECT_H
#define CSG_INTERSECT_H

#include "flat.h"
#include "poly_solve.h"
#include "vec.h"

/* csg_ray, csg_hit, the transforms, the primitive tests and the
 * single-primitive hit: the one-ray compilation of intersect_lanes.h. */
#include "intersect_lanes.h"

typedef struct {
    csg_i32 n;                  /* intervals in use                      */
    csg_i32 ne;                 /* surface events in use                 */
    real limit;                 /* nothing is known at or beyond this t  */
    real t0[CSG_MAX_SPANS];     /* entry parameter                       */
    real t1[CSG_MAX_SPANS];     /* exit parameter                        */
    csg_u32 s0[CSG_MAX_SPANS];  /* surface at entry (CSG_SURF_NONE: none) */
    csg_u32 s1[CSG_MAX_SPANS];  /* surface at exit                       */
    real te[CSG_MAX_EVENTS];    /* surface crossings (zero-length), sorted */
    csg_u32 se[CSG_MAX_EVENTS]; /* their surfaces (never CSG_SURF_NONE)  */
} csg_spans;

/* Pointers to the arrays of a flat scene, in either address space.  The
 * roots 0 .. root_count - 1 are tested one by one; the others are reached
 * through the BVH (bvh_count nodes; none when 0). */
typedef struct {
    CSG_GLOBAL const csg_prim *prims;
    CSG_GLOBAL const csg_node *nodes;
    CSG_GLOBAL const csg_root *roots;
    CSG_GLOBAL const csg_bvh_node *bvh;
    CSG_GLOBAL const csg_wide *wide;         /* wide runs (flat.h, CSG_OP_WIDE) */
    CSG_GLOBAL const csg_bvh_node *wide_bvh;
    CSG_GLOBAL const csg_i32 *wide_items;
    CSG_GLOBAL const csg_curve *curves;      /* curved trapezoid sides (flat.h) */
    csg_i32 root_count;
    csg_i32 bvh_count;
    csg_i32 curve_count;
#ifndef __OPENCL_VERSION__
    struct csg_pager *pager; /* a worker's scene below its memory budget
                                (workers/pager.h); NULL: the whole blob */
    const csg_u64 *page_tops; /* with a pager: a bit a BVH node, set where
                                 a page's top is (pager_page_tops) */
#endif
} csg_view;

/* Paging (C only: workers/pager.h).  A walk names each BVH node it enters
 * (its children or its roots are read next), and code that reaches a root
 * or a primitive by its index names it, so that the page holding them is
 * there before a byte of it is read.  Without a pager (the kernels, the
 * master, an in-memory worker) they do nothing. */
#ifdef __OPENCL_VERSION__
#define CSG_PAGE_ENTER(v, k) ((void)0)
#define CSG_PAGE_ROOT(v, i) ((void)0)
#define CSG_PAGE_PRIM(v, j) ((void)0)
#else
struct csg_pager;
void csg_page_enter(struct csg_pager *p, csg_i32 node);
void csg_page_root(struct csg_pager *p, csg_i32 root);
void csg_page_prim(struct csg_pager *p, csg_i32 prim);
/* (the bit tested here: a call only at a page's top, a few nodes in a walk) */
#define CSG_PAGE_ENTER(v, k)                                                           \
    ((v).pager && ((v).page_tops[(csg_u32)(k) >> 6] >> ((csg_u32)(k) & 63u) & 1u)     \
         ? csg_page_enter((v).pager, (k))                                              \
         : (void)0)
#define CSG_PAGE_ROOT(v, i) ((v).pager ? csg_page_root((v).pager, (i)) : (void)0)
#define CSG_PAGE_PRIM(v, j) ((v).pager ? csg_page_prim((v).pager, (j)) : (void)0)
#endif

/* The view of a blob (flat.h), its arrays found through its header. */
CSG_FN csg_view csg_blob_view(CSG_GLOBAL const csg_u8 *blob)
{
    CSG_GLOBAL const csg_blob_header *h = (CSG_GLOBAL const csg_blob_header *)blob;
    csg_view v;
    v.prims = (CSG_GLOBAL const csg_prim *)(blob + h->off_prims);
    v.nodes = (CSG_GLOBAL const csg_node *)(blob + h->off_nodes);
    v.roots = (CSG_GLOBAL const csg_root *)(blob + h->off_roots);
    v.bvh = (CSG_GLOBAL const csg_bvh_node *)(blob + h->off_bvh);
    v.wide = (CSG_GLOBAL const csg_wide *)(blob + h->off_wide);
    v.wide_bvh = (CSG_GLOBAL const csg_bvh_node *)(blob + h->off_wide_bvh);
    v.wide_items = (CSG_GLOBAL const csg_i32 *)(blob + h->off_wide_items);
    v.curves = (CSG_GLOBAL const csg_curve *)(blob + h->off_curves);
    v.root_count = h->linear_roots;
    v.bvh_count = h->bvh_count;
    v.curve_count = h->curve_count;
#ifndef __OPENCL_VERSION__
    v.pager = 0;
    v.page_tops = 0;
#endif
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
    l->ne = 0;
    l->limit = limit;
}

/* Nothing is known from t on: the limit moves in to t, intervals are cut
 * there and later events dropped (a list that is full). */
CSG_FN void csg_spans_truncate(csg_spans *l, real t)
{
    if (!(t < l->limit))
        return;
    l->limit = t;
    while (l->n > 0 && !(l->t0[l->n - 1] < t))
        l->n--;
    if (l->n > 0 && l->t1[l->n - 1] > t) {
        l->t1[l->n - 1] = t;
        l->s1[l->n - 1] = CSG_SURF_NONE;
    }
    while (l->ne > 0 && !(l->te[l->ne - 1] < t))
        l->ne--;
}

/* Append the event (t, s), t at or after the last one; beyond the limit
 * it is dropped, and a full list moves the limit in to t. */
CSG_FN void csg_events_push(csg_spans *l, real t, csg_u32 s)
{
    if (t > l->limit)
        return;
    if (l->ne == CSG_MAX_EVENTS) {
        csg_spans_truncate(l, t);
        return;
    }
    l->te[l->ne] = t;
    l->se[l->ne] = s;
    l->ne++;
}

/* Is t strictly inside (open) or inside (closed) one of l's intervals? */
CSG_FN int csg_spans_contain(const csg_spans *l, real t, int closed)
{
    for (csg_i32 k = 0; k < l->n; k++) {
        if (closed ? (l->t0[k] <= t && t <= l->t1[k]) : (l->t0[k] < t && t < l->t1[k]))
            return 1;
    }
    return 0;
}

/* The events of a and b into out, in order: for a union (inside == 0) those
 * not strictly inside the other operand, for an intersection (inside == 1)
 * those inside its closed intervals. */
CSG_FN void csg_events_combine(const csg_spans *a, const csg_spans *b, int inside, csg_spans *out)
{
    csg_i32 i = 0, j = 0;
    while (i < a->ne || j < b->ne) {
        int take_a = j >= b->ne || (i < a->ne && a->te[i] <= b->te[j]);
        real t = take_a ? a->te[i] : b->te[j];
        csg_u32 s = take_a ? a->se[i] : b->se[j];
        int in = csg_spans_contain(take_a ? b : a, t, inside);
        if (take_a)
            i++;
        else
            j++;
        if (in == inside)
            csg_events_push(out, t, s);
    }
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

/* A surface primitive's list on [tmin, tmax]: its crossing as an event
 * when strictly after tmin, and the whole range when complemented. */
CSG_FN void csg_surface_leaf_spans(CSG_GLOBAL const csg_prim *p, csg_i32 i, csg_ray r,
                                   real tmin, real tmax, csg_spans *out)
{
    real t0, t1;
    csg_i32 s0, s1;
    int hit = csg_prim_span(p, r, &t0, &t1, &s0, &s1);
    if (p->flags & CSG_PF_INVERT)
        csg_spans_push(out, tmin, CSG_SURF_NONE, tmax, CSG_SURF_NONE);
    if (hit && t0 > tmin && t0 <= tmax && !(p->flags & CSG_PF_CLIP)) /* (a clip's: none) */
        csg_events_push(out, t0, csg_surf_of(i, s0, 0u, p->flags));
}

/* The interval list of one primitive on [tmin, tmax]. */
CSG_FN void csg_leaf_spans(CSG_GLOBAL const csg_prim *prims, csg_i32 i, csg_ray r,
                           real tmin, real tmax, csg_spans *out)
{
    CSG_GLOBAL const csg_prim *p = &prims[i];
    real t0, t1;
    csg_i32 s0, s1;
    if (p->flags & CSG_PF_BOUND) /* a bound is met anywhere along the ray (CSG_OP_BOUND) */
        tmax = CSG_R_INF;
    csg_spans_clear(out, tmax);
    if (CSG_USE_SURFACES && CSG_PRIM_IS_SURFACE(p->kind)) {
        csg_surface_leaf_spans(p, i, r, tmin, tmax, out);
        return;
    }
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
    if (a->ne > 0 || b->ne > 0)
        csg_events_combine(a, b, 0, out);
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
    if (a->ne > 0 || b->ne > 0)
        csg_events_combine(a, b, 1, out);
}

/* Does the ray meet the bound whose list (on [tmin, inf)) is b, or start
 * inside it?  POV-Ray's Ray_In_Bound: an intersection of the bound (a
 * surface, not the cut of its own clip) or the origin inside it (a list
 * that starts at tmin). */
CSG_FN int csg_spans_met(const csg_spans *b, real tmin)
{
    if (b->ne > 0)
        return 1;
    for (csg_i32 k = 0; k < b->n; k++)
        if (!(b->t0[k] > tmin) || b->s0[k] != CSG_SURF_NONE || b->s1[k] != CSG_SURF_NONE)
            return 1;
    return 0;
}

/* POV-Ray's Ray_In_Bound (flat.h, CSG_OP_BOUND): a keeps its surfaces
 * only when the ray meets the bound (csg_spans_met); its solid stays as
 * it is. */
CSG_FN void csg_spans_gate(csg_spans *a, const csg_spans *bound, real tmin)
{
    if (csg_spans_met(bound, tmin))
        return;
    for (csg_i32 k = 0; k < a->n; k++) {
        a->s0[k] = CSG_SURF_NONE;
        a->s1[k] = CSG_SURF_NONE;
    }
    a->ne = 0;
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
    dst->ne = src->ne;
    for (csg_i32 k = 0; k < src->ne; k++) {
        dst->te[k] = src->te[k];
        dst->se[k] = src->se[k];
    }
}

/* ---- boxes ----------------------------------------------------------------------
 * Root and BVH boxes are conservative culls: a box test may pass a ray
 * that misses the solid, never the reverse.  Every box is padded outwards
 * by the flattener (csg/flatten.c, box_store), and the test below is
 * written so that its own rounding and the IEEE special cases only ever
 * widen the range it accepts.
 *
 * The slab test divides by the direction once per ray, not six times per
 * box (Williams et al., "An Efficient and Robust Ray-Box Intersection
 * Algorithm", JGT 2005; Ize, "Robust BVH Ray Traversal", JCGT 2013):
 *   - inv = 1 / d; with d == +0 or -0 it is +inf or -inf, and `neg` is
 *     taken from inv's sign, so -0 counts as negative;
 *   - the near plane of each axis is lo (hi when neg), the far plane hi
 *     (lo when neg), so t_near <= t_far without a min/max per axis;
 *   - t = (plane - o) * inv rounds four times (the difference, the
 *     reciprocal, its scaling, the product), a relative error below 4
 *     units of roundoff; the reciprocals are scaled by 1 -/+ 2^-21 in
 *     float (2^-50 in double), 8 units, so that the near t only moves
 *     towards 0 and the far t away from it (rounding never changes the
 *     sign of a difference or a product);
 *   - d == 0 with the origin strictly inside the slab gives -inf / +inf,
 *     strictly outside gives +inf / +inf or -inf / -inf (the ray misses
 *     the slab, the test fails unless every other bound is infinite too,
 *     which only makes it conservative); the origin exactly on the
 *     slab's plane gives 0 * inf = NaN, and the comparisons below are
 *     written so that a NaN never replaces a bound: the slab then
 *     constrains nothing, which is right (the line lies in the closed
 *     slab);
 *   - infinite box bounds (unbounded roots) give +-inf, never NaN, for a
 *     finite origin. */
#ifdef CSG_DOUBLE
#define CSG_INV_NEAR_SCALE (R(1.0) - R(8.8817841970012523e-16)) /* 1 - 2^-50 */
#define CSG_INV_FAR_SCALE (R(1.0) + R(8.8817841970012523e-16))
#else
#define CSG_INV_NEAR_SCALE (R(1.0) - R(4.76837158203125e-07)) /* 1 - 2^-21 */
#define CSG_INV_FAR_SCALE (R(1.0) + R(4.76837158203125e-07))
#endif

/* A ray prepared once for every box test along it. */
typedef struct {
    real o[3];         /* origin                                        */
    real inv_near[3];  /* 1 / d, its magnitude rounded down: near planes */
    real inv_far[3];   /* 1 / d, its magnitude rounded up: far planes    */
    csg_i32 neg[3];    /* 1 where 1 / d < 0 (d < 0 or d == -0)           */
    csg_i32 near_i[3]; /* the near plane of each axis in a BVH node's box[6] */
    csg_i32 far_i[3];  /* and its far plane                              */
} csg_box_ray;

CSG_FN csg_box_ray csg_box_ray_of(csg_ray r)
{
    csg_box_ray b;
    real d[3];
    b.o[0] = r.o.x;
    b.o[1] = r.o.y;
    b.o[2] = r.o.z;
    d[0] = r.d.x;
    d[1] = r.d.y;
    d[2] = r.d.z;
    for (int a = 0; a < 3; a++) {
        real inv = R(1.0) / d[a];
        b.inv_near[a] = inv * CSG_INV_NEAR_SCALE;
        b.inv_far[a] = inv * CSG_INV_FAR_SCALE;
        b.neg[a] = inv < R(0.0) ? 1 : 0;
        b.near_i[a] = a + 3 * b.neg[a];
        b.far_i[a] = a + 3 - 3 * b.neg[a];
    }
    return b;
}

/* The slab test on the planes already picked: n* the near and f* the far
 * plane of each axis.  *t_enter gets where the ray enters (at least
 * tmin) when it meets the box on [tmin, tmax]. */
CSG_FN int csg_slabs_hit(real nx, real fx, real ny, real fy, real nz, real fz,
                         const csg_box_ray *b, real tmin, real tmax, real *t_enter)
{
    real tnx = (nx - b->o[0]) * b->inv_near[0], tfx = (fx - b->o[0]) * b->inv_far[0];
    real tny = (ny - b->o[1]) * b->inv_near[1], tfy = (fy - b->o[1]) * b->inv_far[1];
    real tnz = (nz - b->o[2]) * b->inv_near[2], tfz = (fz - b->o[2]) * b->inv_far[2];
    /* a > b ? a : b is false for a NaN: the bound stays */
    real lo = tnx > tmin ? tnx : tmin, hi = tfx < tmax ? tfx : tmax;
    lo = tny > lo ? tny : lo;
    hi = tfy < hi ? tfy : hi;
    lo = tnz > lo ? tnz : lo;
    hi = tfz < hi ? tfz : hi;
    *t_enter = lo;
    return lo <= hi;
}

/* Does the ray meet the box lo..hi on [tmin, tmax]?  The planes picked by
 * pointer, no branch on the signs. */
CSG_FN int csg_box_hit(CSG_GLOBAL const real *lo_b, CSG_GLOBAL const real *hi_b,
                       const csg_box_ray *b, real tmin, real tmax, real *t_enter)
{
    CSG_GLOBAL const real *nx = b->neg[0] ? hi_b : lo_b, *fx = b->neg[0] ? lo_b : hi_b;
    CSG_GLOBAL const real *ny = b->neg[1] ? hi_b : lo_b, *fy = b->neg[1] ? lo_b : hi_b;
    CSG_GLOBAL const real *nz = b->neg[2] ? hi_b : lo_b, *fz = b->neg[2] ? lo_b : hi_b;
    return csg_slabs_hit(nx[0], fx[0], ny[1], fy[1], nz[2], fz[2], b, tmin, tmax, t_enter);
}

/* The same for a BVH node, its planes picked by index (the walk's
 * commonest test: no select at all). */
CSG_FN int csg_node_hit(CSG_GLOBAL const csg_bvh_node *n, const csg_box_ray *b, real tmin,
                        real tmax, real *t_enter)
{
    CSG_GLOBAL const real *x = n->box;
    return csg_slabs_hit(x[b->near_i[0]], x[b->far_i[0]], x[b->near_i[1]], x[b->far_i[1]],
                         x[b->near_i[2]], x[b->far_i[2]], b, tmin, tmax, t_enter);
}

/* The same test for one ray, when no csg_box_ray is at hand. */
CSG_FN int csg_aabb_overlaps(CSG_GLOBAL const real *lo_b, CSG_GLOBAL const real *hi_b, csg_ray r,
                             real tmin, real tmax)
{
    csg_box_ray b = csg_box_ray_of(r);
    real t;
    return csg_box_hit(lo_b, hi_b, &b, tmin, tmax, &t);
}

CSG_FN int csg_box_overlaps(CSG_GLOBAL const csg_root *root, csg_ray r, real tmin, real tmax)
{
    return csg_aabb_overlaps(root->lo, root->hi, r, tmin, tmax);
}

/* ---- wide runs (flat.h, CSG_OP_WIDE) -------------------------------------------- */

/* The pairs of wide run w whose leaf boxes the ray meets on [tmin, tmax],
 * into hit[] in the run's order; -1 when more than CSG_WIDE_HITS (the
 * caller then folds every pair).  A depth-first walk: the order of the
 * visits does not matter, the indices are sorted after. */
CSG_FN csg_i32 csg_wide_hits(csg_view v, CSG_GLOBAL const csg_wide *w, csg_ray r, real tmin,
                             real tmax, csg_i32 *hit)
{
    csg_box_ray br = csg_box_ray_of(r);
    csg_i32 stack[CSG_BVH_STACK + 1];
    csg_i32 top = 0, n = 0;
    stack[top++] = w->bvh_first;
    stack[top++] = w->bvh_first + 1;
    while (top > 0) {
        CSG_GLOBAL const csg_bvh_node *node = &v.wide_bvh[stack[--top]];
        real t_enter;
        if (!csg_node_hit(node, &br, tmin, tmax, &t_enter))
            continue;
        if (node->count < 0) {
            if (top + 2 > CSG_BVH_STACK + 1) /* the flattener keeps the tree shallower */
                return -1;
            stack[top++] = node->first;
            stack[top++] = node->first + 1;
            continue;
        }
        if (n + node->count > CSG_WIDE_HITS)
            return -1;
        for (csg_i32 k = 0; k < node->count; k++)
            hit[n++] = v.wide_items[node->first + k];
    }
    for (csg_i32 i = 1; i < n; i++) { /* insertion sort: n is small */
        csg_i32 x = hit[i], j = i - 1;
        while (j >= 0 && hit[j] > x) {
            hit[j + 1] = hit[j];
            j--;
        }
        hit[j + 1] = x;
    }
    return n;
}

/* The run marked by the CSG_OP_WIDE node at nodes[at], folded into *acc
 * through its hierarchy; returns the nodes it stands for (0: none done,
 * the caller folds the pairs one by one). */
CSG_FN csg_i32 csg_wide_fold(csg_view v, csg_i32 at, csg_ray r, real tmin, real tmax,
                             csg_spans *acc)
{
    CSG_GLOBAL const csg_wide *w = &v.wide[v.nodes[at].prim];
    csg_i32 hit[CSG_WIDE_HITS];
    if (!(tmin < tmax)) /* a complemented leaf's line is then empty, no identity */
        return 0;
    csg_i32 n = csg_wide_hits(v, w, r, tmin, tmax, hit);
    if (n < 0)
        return 0;
    csg_spans leaf, tmp;
    for (csg_i32 k = 0; k < n; k++) {
        csg_i32 pair = at + 1 + 2 * hit[k];
        csg_leaf_spans(v.prims, v.nodes[pair].prim, r, tmin, tmax, &leaf);
        if (v.nodes[pair + 1].op == CSG_OP_UNION)
            csg_spans_union(acc, &leaf, &tmp);
        else
            csg_spans_intersect(acc, &leaf, &tmp);
        csg_spans_copy(&tmp, acc);
    }
    return 2 * w->pair_count;
}

/* ---- a root ---------------------------------------------------------------- */

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
        if (n.op == CSG_OP_WIDE) {
            if (top > 0) /* (the blob validator checks it) */
                k += csg_wide_fold(v, rt->first_node + k, r, tmin, tmax, &stack[top - 1]);
            continue;
        }
        if (n.op == CSG_OP_PRIM) {
            if (top == CSG_STACK_MAX) /* the flattener prevents this */
                break;
            csg_leaf_spans(v.prims, n.prim, r, tmin, tmax, &stack[top]);
            top++;
            continue;
        }
        if (top < 2)
            break;
        if (n.op == CSG_OP_BOUND) {
            csg_spans_gate(&stack[top - 2], &stack[top - 1], tmin);
            top--;
            continue;
        }
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

/* The first visible boundary strictly after tmin: an interval's end or
 * an event, the nearer (as near: the lower surface id). */
CSG_FN csg_hit csg_first_boundary(const csg_spans *l, real tmin)
{
    csg_hit h;
    h.t = CSG_R_INF;
    h.surf = CSG_SURF_NONE;
    for (csg_i32 k = 0; k < l->n; k++) {
        if (l->s0[k] != CSG_SURF_NONE && l->t0[k] > tmin) {
            h.t = l->t0[k];
            h.surf = l->s0[k];
            break;
        }
        if (l->s1[k] != CSG_SURF_NONE && l->t1[k] > tmin) {
            h.t = l->t1[k];
            h.surf = l->s1[k];
            break;
        }
    }
    for (csg_i32 k = 0; k < l->ne; k++) {
        if (!csg_surf_visible(l->se[k]) || !(l->te[k] > tmin))
            continue;
        if (l->te[k] < h.t || (l->te[k] == h.t && l->se[k] < h.surf) ||
            h.surf == CSG_SURF_NONE) {
            h.t = l->te[k];
            h.surf = l->se[k];
        }
        break;
    }
    return h;
}

/* Root i's first visible boundary on (tmin, tmax): the single-primitive
 * fast path or the root's interval list. */
CSG_FN csg_hit csg_root_first_hit(csg_view v, csg_i32 i, csg_ray r, real tmin, real tmax)
{
    CSG_GLOBAL const csg_root *rt = &v.roots[i];
    if (!CSG_USE_CSG) /* every root is one uncomplemented primitive (spec.h) */
        return csg_leaf_first_hit(v.prims, v.nodes[rt->first_node].prim, r, tmin, tmax);
    csg_i32 leaf = rt->node_count == 1 ? v.nodes[rt->first_node].prim : -1;
    if (leaf >= 0 && !(v.prims[leaf].flags & CSG_PF_INVERT))
        return csg_leaf_first_hit(v.prims, leaf, r, tmin, tmax);
    csg_spans spans;
    csg_root_spans(v, i, r, tmin, tmax, &spans);
    return csg_first_boundary(&spans, tmin);
}

/* Root i's first visible boundary, if it wins against *best; its box is
 * tested first when test_box (a BVH leaf of one root has just tested the
 * very same box). */
CSG_FN void csg_try_root(csg_view v, csg_i32 i, csg_ray r, const csg_box_ray *br, int test_box,
                         real tmin, csg_hit *best)
{
    CSG_GLOBAL const csg_root *rt = &v.roots[i];
    real tmax = csg_hit_limit(best);
    real t_enter;
    if (test_box && !csg_box_hit(rt->lo, rt->hi, br, tmin, tmax, &t_enter))
        return;
    csg_hit h = csg_root_first_hit(v, i, r, tmin, tmax);
    if (csg_hit_wins(h, best))
        *best = h;
}

/* ---- the BVH walk ----------------------------------------------------------------
 * The two children of a node are tested together (they are adjacent in
 * the array, flat.h), the nearer one entered at once and the other pushed
 * with its entry t; a popped node whose entry lies beyond tmax (which
 * only shrinks during a walk) is dropped, exactly what testing its box
 * again would do.  The stack holds at most one node a level, and the
 * flattener keeps the depth below CSG_BVH_STACK. */
typedef struct {
    csg_i32 pair; /* the pair to open next, -1: pop instead */
    csg_i32 top;
    csg_i32 node[CSG_BVH_STACK];
    real t[CSG_BVH_STACK];
} csg_bvh_walk;

CSG_FN void csg_bvh_walk_start(csg_bvh_walk *w, csg_view v)
{
    w->pair = v.bvh_count > 0 ? 0 : -1; /* nodes 0 and 1: the top pair */
    w->top = 0;
}

/* Tests the pair (c, c + 1) on [tmin, tmax]; returns the node to enter
 * next (-1: neither) and pushes the farther one when both are met. */
CSG_FN csg_i32 csg_bvh_open_pair(CSG_GLOBAL const csg_bvh_node *bvh, csg_i32 c,
                                 const csg_box_ray *br, real tmin, real tmax, csg_bvh_walk *w)
{
    real ta, tb;
    int ha = csg_node_hit(&bvh[c], br, tmin, tmax, &ta);
    int hb = csg_node_hit(&bvh[c + 1], br, tmin, tmax, &tb);
    if (ha && hb) {
        if (w->top == CSG_BVH_STACK) /* the flattener prevents this */
            return -1;
        int b_first = tb < ta;
        w->node[w->top] = b_first ? c : c + 1;
        w->t[w->top] = b_first ? ta : tb;
        w->top++;
        return b_first ? c + 1 : c;
    }
    return ha ? c : (hb ? c + 1 : -1);
}

/* The next leaf whose box the ray meets on [tmin, tmax], nearest first as
 * far as the boxes tell; -1 when the walk is over. */
CSG_FN csg_i32 csg_bvh_next_leaf(csg_view v, const csg_box_ray *br, real tmin, real tmax,
                                 csg_bvh_walk *w)
{
    CSG_GLOBAL const csg_bvh_node *bvh = v.bvh;
    for (;;) {
        csg_i32 k = w->pair >= 0 ? csg_bvh_open_pair(bvh, w->pair, br, tmin, tmax, w) : -1;
        w->pair = -1;
        while (k < 0 && w->top > 0) {
            w->top--;
            if (w->t[w->top] <= tmax)
                k = w->node[w->top];
        }
        if (k < 0)
            return -1;
        CSG_PAGE_ENTER(v, k); /* (its children or its roots are read next) */
        if (bvh[k].count >= 0)
            return k;
        w->pair = bvh[k].first;
    }
}

/* The nearest visible surface on (tmin, tmax) over every root: first the
 * roots tested one by one, then the BVH's leaves, nearer first.  Ties go
 * to the lower surface id (csg_hit_wins), so the answer depends neither
 * on the visiting order nor on where this runs. */
CSG_FN csg_hit csg_trace_nearest(csg_view v, csg_ray r, real tmin, real tmax)
{
    csg_hit best;
    best.t = tmax;
    best.surf = CSG_SURF_NONE;
    csg_box_ray br = csg_box_ray_of(r);
    for (csg_i32 i = 0; i < v.root_count; i++)
        csg_try_root(v, i, r, &br, 1, tmin, &best);
    csg_bvh_walk w;
    csg_bvh_walk_start(&w, v);
    csg_i32 k;
    while ((k = csg_bvh_next_leaf(v, &br, tmin, csg_hit_limit(&best), &w)) >= 0) {
        CSG_GLOBAL const csg_bvh_node *n = &v.bvh[k];
        for (csg_i32 i = n->first; i < n->first + n->count; i++)
            csg_try_root(v, i, r, &br, n->count > 1, tmin, &best);
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

/* A trapezoid's sides point out against their inward normals; its slab
 * faces are a box's (sub 2 .. 5). */
CSG_FN vec3 csg_trapezoid_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    if (sub == CSG_SURF_TRAP_SIDE_A || sub == CSG_SURF_TRAP_SIDE_B)
        return v3(-p[3 * sub], -p[3 * sub + 1], R(0.0));
    return csg_box_normal(p, sub, lp);
}

/* A conic piece's walls point out against the gradients of its bounds. */
CSG_FN vec3 csg_conic_trapezoid_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    if (sub == CSG_SURF_TRAP_SIDE_A)
        return v3(R(-1.0), p[0], p[1]);
    if (sub == CSG_SURF_TRAP_SIDE_B)
        return v3(R(1.0), -p[2], -p[3]);
    if (sub == 2)
        return v3(R(0.0), R(-1.0), p[4]);
    if (sub == 3)
        return v3(R(0.0), R(1.0), -p[5]);
    return csg_box_normal(p, sub, lp);
}

/* A sheet's face (csg_flat_box_span picks the one facing the ray). */
CSG_FN vec3 csg_flat_box_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    return csg_box_normal(p, sub, lp);
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

/* The torus's: from the point towards it off the ring's circle of radius
 * R (POV-Ray's Torus::Normal; on the axis itself, the point's own). */
CSG_FN vec3 csg_torus_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    (void)sub;
    real dist = r_sqrt(lp.x * lp.x + lp.z * lp.z);
    if (!(dist > R(0.0)))
        return lp;
    real k = p[0] / dist;
    return v3(lp.x - k * lp.x, lp.y, lp.z - k * lp.z);
}

/* The quadric's gradient (POV-Ray's Quadric::Normal), in world space. */
CSG_FN vec3 csg_quadric_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    (void)sub;
    vec3 n = v3(R(2.0) * p[0] * lp.x + p[3] * lp.y + p[4] * lp.z + p[6],
                p[3] * lp.x + R(2.0) * p[1] * lp.y + p[5] * lp.z + p[7],
                p[4] * lp.x + p[5] * lp.y + R(2.0) * p[2] * lp.z + p[8]);
    /* (a singular point, a cone's apex: POV-Ray's arbitrary direction) */
    return v3_dot(n, n) > R(0.0) ? n : v3(R(1.0), R(0.0), R(0.0));
}

#if CSG_POLY_SOLVER
/* The poly's gradient (POV-Ray's Poly::Normal), in its local frame, in
 * double over the coefficients divided by the largest magnitude (the same
 * direction; no term overflows where a root was found, |lp| <= 10^7), then
 * divided by its largest component, so that it is finite in `real` too;
 * where it vanishes or is not finite, POV-Ray's arbitrary direction.
 * (The fuzzer found a float gradient of inf * 0: a NaN normal.)  Only
 * + - * / and comparisons on double, as poly_solve.h. */
CSG_FN vec3 csg_poly_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    (void)sub;
    const vec3 arbitrary = v3(R(1.0), R(0.0), R(0.0));
    csg_i32 n = (csg_i32)p[0];
    if (n < 1 || n > CSG_POLY_ORDER_MAX)
        return arbitrary;
    CSG_GLOBAL const real *coef = csg_poly_coefs(p);
    csg_i32 terms = (n + 1) * (n + 2) * (n + 3) / 6;
    double big = 0.0;
    for (csg_i32 t = 0; t < terms; t++) {
        double c = (double)coef[t];
        c = c < 0.0 ? -c : c;
        big = c > big ? c : big;
    }
    if (!(big > 0.0 && big - big == 0.0)) /* (x - x is 0 only when x is finite) */
        return arbitrary;
    double px[CSG_POLY_ORDER_MAX + 1], py[CSG_POLY_ORDER_MAX + 1], pz[CSG_POLY_ORDER_MAX + 1];
    px[0] = py[0] = pz[0] = 1.0;
    for (csg_i32 e = 1; e <= n; e++) {
        px[e] = px[e - 1] * (double)lp.x;
        py[e] = py[e - 1] * (double)lp.y;
        pz[e] = pz[e - 1] * (double)lp.z;
    }
    double gx = 0.0, gy = 0.0, gz = 0.0;
    csg_i32 term = 0;
    for (csg_i32 i = n; i >= 0; i--)
        for (csg_i32 j = n - i; j >= 0; j--)
            for (csg_i32 k = n - i - j; k >= 0; k--) {
                double a = (double)coef[term++] / big;
                if (i >= 1)
                    gx = gx + (double)i * a * px[i - 1] * py[j] * pz[k];
                if (j >= 1)
                    gy = gy + (double)j * a * px[i] * py[j - 1] * pz[k];
                if (k >= 1)
                    gz = gz + (double)k * a * px[i] * py[j] * pz[k - 1];
            }
    double ax = gx < 0.0 ? -gx : gx, ay = gy < 0.0 ? -gy : gy, az = gz < 0.0 ? -gz : gz;
    double m = ax > ay ? ax : ay;
    m = az > m ? az : m;
    if (!(m > 0.0 && m - m == 0.0))
        return arbitrary;
    return v3((real)(gx / m), (real)(gy / m), (real)(gz / m));
}
#else /* (a program without polys, nor the solver's double) */
CSG_FN vec3 csg_poly_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    (void)p;
    (void)sub;
    (void)lp;
    return v3(R(1.0), R(0.0), R(0.0));
}
#endif

/* A triangle's normal is its front's: (v1 - v0) x (v2 - v0), on either side. */
CSG_FN vec3 csg_triangle_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    (void)sub;
    (void)lp;
    vec3 v0 = v3_load(p);
    return v3_cross(v3_sub(v3_load(p + 3), v0), v3_sub(v3_load(p + 6), v0));
}

/* The vertex normals interpolated at the barycentric coordinates of lp
 * (the triangle's normal where they cancel). */
CSG_FN vec3 csg_smooth_triangle_normal(CSG_GLOBAL const real *p, csg_i32 sub, vec3 lp)
{
    vec3 v0 = v3_load(p);
    vec3 e1 = v3_sub(v3_load(p + 3), v0), e2 = v3_sub(v3_load(p + 6), v0);
    vec3 ng = v3_cross(e1, e2);
    real nn = v3_dot(ng, ng);
    if (!(nn > R(0.0)))
        return ng;
    vec3 q = v3_sub(lp, v0);
    real b1 = v3_dot(v3_cross(q, e2), ng) / nn;
    real b2 = v3_dot(v3_cross(e1, q), ng) / nn;
    real b0 = R(1.0) - b1 - b2;
    vec3 n = v3_add(v3_add(v3_scale(v3_load(p + 9), b0), v3_scale(v3_load(p + 12), b1)),
                    v3_scale(v3_load(p + 15), b2));
    (void)sub;
    return v3_dot(n, n) > R(0.0) ? n : ng;
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

/* The unit normal of the geometry itself, given n = csg_surface_normal:
 * n, except on a smooth triangle, whose flat normal decides which side a
 * ray is on. */
CSG_FN vec3 csg_surface_geometric_normal(CSG_GLOBAL const csg_prim *prims, csg_u32 s, vec3 wp,
                                         vec3 n)
{
    CSG_GLOBAL const csg_prim *p = &prims[CSG_SURF_PRIM(s)];
    if (p->kind != CSG_PRIM_SMOOTH_TRIANGLE)
        return n;
    vec3 g = v3_normalize(csg_triangle_normal(p->p, CSG_SURF_SUB(s), wp));
    return CSG_SURF_FLIP(s) ? v3_neg(g) : g;
}

/* ---- the curved sides of an extruded outline -------------------------------
 * A trapezoid piece's side is a chord of its outline's curve (flat.h,
 * csg_curve): rays meet the chord, but POV-Ray's Prism::Normal is the
 * spline's at the parameter u where the ray meets the spline, from its
 * tangent T = (3 A u + 2 B) u + C: N = (T.y, -T.x) in the outline's plane
 * (linear_sweep); under conic_sweep, where the side is the cone from the
 * apex over the spline, N with the height's component
 * -(P.x N.x + P.y N.y) / P.z at POV-Ray's hit P (the local frame: the
 * outline at height z scaled by z), which lies on the spline's cone:
 * P / P.z = (x(u), y(u)), so the component is -(x(u) N.x + y(u) N.y).
 * The ray meets the spline where f(u) = m.x x(u) + m.y y(u) + m.z
 * vanishes, m the plane through the ray that holds the sweep's lines:
 * m = (D.y, -D.x, D.x P.y - D.y P.x) for the vertical walls of a linear
 * sweep, m = P x D through the apex for a conic one (POV-Ray's equations,
 * whose roots it finds).  The root is found by Newton's method from the
 * hit's place along the chord: the chord is within 10^-4 of the outline's
 * size of the spline, so a few steps reach it (6e-7 rad of POV-Ray's
 * normal in float, 1e-15 in double: tests/test_curved_sides.c). */

#define CSG_CURVE_NEWTON_STEPS 4

/* The spline of side c at u: its point (x, y) and tangent (tx, ty). */
CSG_FN void csg_curve_eval(CSG_GLOBAL const csg_curve_side *c, real u, real *x, real *y, real *tx,
                           real *ty)
{
    *x = ((c->a[0] * u + c->b[0]) * u + c->c[0]) * u + c->d[0];
    *y = ((c->a[1] * u + c->b[1]) * u + c->c[1]) * u + c->d[1];
    *tx = (R(3.0) * c->a[0] * u + R(2.0) * c->b[0]) * u + c->c[0];
    *ty = (R(3.0) * c->a[1] * u + R(2.0) * c->b[1]) * u + c->c[1];
}

/* Where along the chord of side c (from u0 to u1) the outline's point
 * (qx, qy) lies, as a parameter of the spline between u0 and u1. */
CSG_FN real csg_curve_chord_param(CSG_GLOBAL const csg_curve_side *c, real qx, real qy)
{
    real x0, y0, x1, y1, tx, ty;
    csg_curve_eval(c, c->u0, &x0, &y0, &tx, &ty);
    csg_curve_eval(c, c->u1, &x1, &y1, &tx, &ty);
    real ex = x1 - x0, ey = y1 - y0, ee = ex * ex + ey * ey;
    real s = ee > R(0.0) ? ((qx - x0) * ex + (qy - y0) * ey) / ee : R(0.5);
    s = r_fmin(r_fmax(s, R(0.0)), R(1.0));
    return c->u0 + s * (c->u1 - c->u0);
}

/* The root of m.x x(u) + m.y y(u) + m.z near u, kept within a chord's
 * length of parameter around [u0, u1]: a ray that meets the chord near
 * its end may meet the spline just beyond it (a neighbouring chord's, or
 * across the segment's end, where the spline is smooth: its polynomial
 * carries on). */
CSG_FN real csg_curve_meet(CSG_GLOBAL const csg_curve_side *c, vec3 m, real u)
{
    real h = c->u1 - c->u0, lo = c->u0 - h, hi = c->u1 + h;
    for (int i = 0; i < CSG_CURVE_NEWTON_STEPS; i++) {
        real x, y, tx, ty;
        csg_curve_eval(c, u, &x, &y, &tx, &ty);
        real f = m.x * x + m.y * y + m.z, df = m.x * tx + m.y * ty;
        if (df != R(0.0))
            u = u - f / df;
        u = r_fmin(r_fmax(u, lo), hi); /* (a NaN step: hi) */
    }
    return u;
}

/* The spline's normal (not normalised, either way round) of side c of
 * trapezoid piece p where the ray along ld (local) meets it near the hit
 * lp (local, on the chord); a zero vector where it has none. */
CSG_FN vec3 csg_curve_local_normal(CSG_GLOBAL const csg_prim *p,
                                   CSG_GLOBAL const csg_curve_side *c, vec3 lp, vec3 ld)
{
    int conic = p->kind == CSG_PRIM_CONIC_TRAPEZOID;
    if (conic && !(lp.z > R(0.0)))
        return v3(R(0.0), R(0.0), R(0.0));
    vec3 m = conic ? v3_cross(lp, ld) : v3(ld.y, -ld.x, ld.x * lp.y - ld.y * lp.x);
    real qx = conic ? lp.x / lp.z : lp.x, qy = conic ? lp.y / lp.z : lp.y;
    real u = csg_curve_meet(c, m, csg_curve_chord_param(c, qx, qy));
    real x, y, tx, ty;
    csg_curve_eval(c, u, &x, &y, &tx, &ty);
    /* (POV-Ray's hit P is on the spline's cone: P / P.z = (x(u), y(u))) */
    real nz = conic ? -(x * ty - y * tx) : R(0.0);
    return v3(ty, -tx, nz);
}

/* The shading normal at world point wp of surface s, met by a ray along
 * d, given n = csg_surface_normal there: n, but on a curved side of a
 * trapezoid piece the spline's (POV-Ray's Prism::Normal), outward as n
 * is; where the spline has no normal there (a cusp), n. */
CSG_FN vec3 csg_surface_shading_normal(csg_view v, csg_u32 s, vec3 wp, vec3 d, vec3 n)
{
    CSG_GLOBAL const csg_prim *p = &v.prims[CSG_SURF_PRIM(s)];
    csg_i32 sub = CSG_SURF_SUB(s), k = CSG_PRIM_CURVE(p);
    if (k < 0 || k >= v.curve_count || sub > CSG_SURF_TRAP_SIDE_B ||
        (p->kind != CSG_PRIM_TRAPEZOID && p->kind != CSG_PRIM_CONIC_TRAPEZOID))
        return n;
    CSG_GLOBAL const csg_curve_side *c = &v.curves[k].side[sub];
    if (!(c->u0 < c->u1))
        return n;
    vec3 lp = csg_xform_point(p->inv, wp);
    vec3 ln = csg_curve_local_normal(p, c, lp, csg_xform_vector(p->inv, d));
    vec3 chord = csg_local_normal(p, sub, lp);
    real along = v3_dot(ln, chord);
    if (!(along > R(0.0) || along < R(0.0))) /* (zero, or not a number) */
        return n;
    vec3 w = v3_normalize(csg_xform_normal(p->inv, along < R(0.0) ? v3_neg(ln) : ln));
    if (!(v3_dot(w, w) > R(0.0)))
        return n;
    return CSG_SURF_FLIP(s) ? v3_neg(w) : w;
}

#endif
