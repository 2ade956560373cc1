/*
 * frustum.h — the roots a rectangle of primary rays may hit, found once
 * for the rectangle (a tile) instead of once a ray.  Host C only
 * (workers/shade.c), in the `real` of the including file; the culling
 * itself is computed in double whatever the engine's precision.
 *
 * A perspective camera without a near plane sends every primary ray of a
 * pixel from `location` through a point of the image plane
 * direction + x0 right + y0 up, (x0, y0) inside the pixel (camera_lanes.h),
 * so the rays of a rectangle of pixels lie in the pyramid with its apex at
 * the location over the rectangle's part of the image plane.  A box
 * entirely outside one of the pyramid's four side planes meets none of
 * them.  The BVH (nodes, then each leaf's roots' own boxes) is walked once
 * with that test; what survives is the tile's candidate list, and each
 * primary ray tries the unbounded roots and those candidates instead of
 * walking the BVH.
 *
 * Exactness: the hit record of a ray does not depend on which roots are
 * tried beyond those it may hit, nor on their order (csg_hit_wins breaks
 * ties by surface id; every box test is a conservative cull), so the
 * records equal csg_trace_nearest's bit for bit as long as no root a ray
 * can hit is culled.  The pyramid is taken one whole pixel wider than the
 * rectangle on every side: a ray as computed in `real` (its direction
 * rounded by a few units of roundoff, at most ~1e-6 rad in float) stays
 * far inside it (one pixel is ~1e-3 rad at 1536 pixels; ~1e-5 rad would
 * still be ten times the rounding at a width of 100000), and a ray that
 * misses a padded root box by that angle misses its solid by far more
 * than the rounding of the primitive tests.  A near plane (NFF's hither)
 * moves a ray's origin along the ray's own direction (camera_lanes.h),
 * so the ray is a part of the one from the apex: inside the same pyramid
 * (its origin off that line by a rounding, far within the pixel's pad);
 * roots before the plane stay candidates that it no longer meets.
 * Anything unusual (another projection, a degenerate or non-finite
 * camera, a pyramid too wide) turns the culling off: the rays then walk
 * the BVH as before.
 */
#ifndef WORKERS_FRUSTUM_H
#define WORKERS_FRUSTUM_H

#include <math.h>
#include <string.h>

#include "../csg/device/intersect.h"
#include "engine.h"
#include "pager.h"

#define FRUSTUM_MAX_ROOTS 16 /* more candidates than this: walk the BVH  */

typedef struct {
    bool culled;             /* false: no list, every ray walks the BVH   */
    csg_i32 n;               /* candidate roots, nearest box first        */
    csg_i32 roots[FRUSTUM_MAX_ROOTS];
} frustum_roots;

typedef struct {
    double o[3];       /* the apex: the camera's location               */
    double n[4][3];    /* the side planes' normals, pointing inwards    */
    double axis[3];    /* the pyramid's central direction (for the order) */
} frustum;

static inline double frustum_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The pyramid of the rays of rect, one pixel wider on each side; false
 * when the camera is not one this culling knows to be safe for. */
static inline bool frustum_of(const csg_camera *cam, int width, int height, tile_rect rect,
                              frustum *f)
{
    if (cam->projection != CSG_CAMERA_PERSPECTIVE || !(cam->hither >= R(0.0))) /* (NaN) */
        return false;
    double x0[2] = {((double)rect.x - 1.0) / width - 0.5,
                    ((double)(rect.x + rect.width) + 1.0) / width - 0.5};
    double y0[2] = {0.5 - ((double)(rect.y + rect.height) + 1.0) / height,
                    0.5 - ((double)rect.y - 1.0) / height};
    static const int cx[4] = {0, 1, 1, 0}, cy[4] = {0, 0, 1, 1};
    double d[4][3];
    for (int k = 0; k < 4; k++)
        for (int a = 0; a < 3; a++)
            d[k][a] = (double)cam->direction[a] + x0[cx[k]] * (double)cam->right[a] +
                      y0[cy[k]] * (double)cam->up[a];
    for (int a = 0; a < 3; a++) {
        f->o[a] = (double)cam->location[a];
        f->axis[a] = (d[0][a] + d[1][a] + d[2][a] + d[3][a]) * 0.25;
        if (!isfinite(f->o[a]) || !isfinite(f->axis[a]))
            return false;
    }
    double axis_len = sqrt(frustum_dot(f->axis, f->axis));
    for (int k = 0; k < 4; k++) {
        const double *p = d[k], *q = d[(k + 1) % 4];
        double *n = f->n[k];
        n[0] = p[1] * q[2] - p[2] * q[1];
        n[1] = p[2] * q[0] - p[0] * q[2];
        n[2] = p[0] * q[1] - p[1] * q[0];
        double len = sqrt(frustum_dot(n, n)), side = frustum_dot(n, f->axis);
        /* the central direction well inside every side (a pyramid less
         * than a half-space wide), or no culling */
        if (!isfinite(len) || !(fabs(side) > 1e-6 * len * axis_len))
            return false;
        if (side < 0.0)
            for (int a = 0; a < 3; a++)
                n[a] = -n[a];
    }
    return true;
}

/* Is the box lo..hi entirely outside one side of the pyramid?  Its corner
 * farthest inwards along each normal decides; a NaN (an infinite bound)
 * never culls. */
static inline bool frustum_culls(const frustum *f, const real lo[3], const real hi[3])
{
    for (int k = 0; k < 4; k++) {
        const double *n = f->n[k];
        double c[3];
        for (int a = 0; a < 3; a++)
            c[a] = (n[a] > 0.0 ? (double)hi[a] : (double)lo[a]) - f->o[a];
        if (frustum_dot(n, c) < 0.0)
            return true;
    }
    return false;
}

/* A root that is one untransformed triangle (NFF's polygons, meshes):
 * outside the pyramid when its three corners are outside one side, the
 * triangle being their convex hull; its box, a tenfold larger area for a
 * slanted one, may not be (tetra's gasket: most of its empty tiles). */
static inline bool frustum_culls_triangle(const frustum *f, csg_view v, const csg_root *rt)
{
    if (rt->node_count != 1 || v.nodes[rt->first_node].op != CSG_OP_PRIM)
        return false;
    const csg_prim *p = &v.prims[v.nodes[rt->first_node].prim];
    if ((p->kind != CSG_PRIM_TRIANGLE && p->kind != CSG_PRIM_SMOOTH_TRIANGLE) ||
        (p->flags & (CSG_PF_XFORM | CSG_PF_INVERT)))
        return false;
    for (int k = 0; k < 4; k++) {
        bool outside = true;
        for (int j = 0; j < 3 && outside; j++) {
            double c[3];
            for (int a = 0; a < 3; a++)
                c[a] = (double)p->p[3 * j + a] - f->o[a];
            outside = frustum_dot(f->n[k], c) < 0.0;
        }
        if (outside)
            return true;
    }
    return false;
}

/* How far along the axis the box's centre lies: the candidates are tried
 * nearest first, so that the best hit's limit shrinks early. */
static inline double frustum_depth(const frustum *f, const real lo[3], const real hi[3])
{
    double c[3];
    for (int a = 0; a < 3; a++)
        c[a] = ((double)lo[a] + (double)hi[a]) * 0.5 - f->o[a];
    return frustum_dot(f->axis, c);
}

/* Adds root i at its place in the depth order of roots[0 .. *n - 1]
 * (depth[k]: root k's); false when the list already holds cap. */
static inline bool frustum_add(csg_i32 *roots, double *depth, csg_i32 *n, csg_i32 cap,
                               csg_i32 i, double di)
{
    if (*n >= cap)
        return false;
    csg_i32 k = (*n)++;
    while (k > 0 && depth[k - 1] > di) {
        roots[k] = roots[k - 1];
        depth[k] = depth[k - 1];
        k--;
    }
    roots[k] = i;
    depth[k] = di;
    return true;
}

/* May the pyramid meet bounded root i?  Neither its box nor, for a root
 * that is one triangle, the triangle lies outside a side.  Monotone: a box that
 * holds another culls no less, so every BVH node above a root the pyramid
 * may meet passes too (rounding is monotone in each operand). */
static inline bool frustum_may_meet(const frustum *f, csg_view v, csg_i32 i)
{
    CSG_PAGE_ROOT(v, i); /* (a list's root: from a walk of this item, or the pass's) */
    const csg_root *rt = &v.roots[i];
    return !frustum_culls(f, rt->lo, rt->hi) && !frustum_culls_triangle(f, v, rt);
}

/* Walks the BVH with the pyramid f: each root whose box (and triangle)
 * it may meet goes to take(arg, root), which returns false to stop the
 * walk.  True when the walk went through (no stop, no overflow). */
static inline bool frustum_walk(csg_view v, const frustum *f,
                                bool (*take)(void *arg, csg_i32 root), void *arg)
{
    csg_i32 stack[CSG_BVH_STACK + 2], top = 0;
    if (v.bvh_count > 0) {
        stack[top++] = 0;
        stack[top++] = 1;
    }
    while (top > 0) {
        const csg_bvh_node *node = &v.bvh[stack[--top]];
        if (frustum_culls(f, node->box, node->box + 3))
            continue;
        CSG_PAGE_ENTER(v, stack[top]); /* (its children or its roots are read next) */
        if (node->count < 0) {
            if (top + 2 > CSG_BVH_STACK + 2) /* the flattener prevents this */
                return false;
            stack[top++] = node->first;
            stack[top++] = node->first + 1;
            continue;
        }
        for (csg_i32 i = node->first; i < node->first + node->count; i++)
            if (frustum_may_meet(f, v, i) && !take(arg, i))
                return false;
    }
    return true;
}

/* Paged (workers/pager.h): page tops gathered for one prefetch request,
 * each once (a small open-addressed set), sent when the list is full
 * (another request) and at the end (page_tops_send). */
enum { PAGE_TOPS_MAX = 1024, PAGE_TOPS_SET = 4096 };
typedef struct {
    csg_pager *pager;
    size_t n;
    csg_i32 tops[PAGE_TOPS_MAX];
    csg_i32 seen[PAGE_TOPS_SET]; /* node + 1; 0: free */
} page_tops;

static inline void page_tops_init(page_tops *t, csg_pager *pager)
{
    t->pager = pager;
    t->n = 0;
    memset(t->seen, 0, sizeof t->seen);
}

static inline void page_tops_send(page_tops *t)
{
    if (t->n > 0)
        pager_prefetch_nodes(t->pager, t->tops, t->n);
    t->n = 0;
    memset(t->seen, 0, sizeof t->seen);
}

static inline void page_tops_add(page_tops *t, csg_i32 k)
{
    uint32_t h = ((uint32_t)k * 2654435761u) >> 20; /* (12 bits: PAGE_TOPS_SET) */
    for (;; h = (h + 1) & (PAGE_TOPS_SET - 1)) {
        if (t->seen[h] == k + 1)
            return;
        if (t->seen[h] == 0)
            break;
    }
    t->seen[h] = k + 1;
    t->tops[t->n++] = k;
    if (t->n == PAGE_TOPS_MAX / 2) /* (the set stays at most half full) */
        page_tops_send(t);
}

/* The tops of the pages whose boxes a walk of the BVH with the test
 * meets(arg, node) could enter, onto t.  The BVH above the pages and the
 * pages' top boxes are resident, so which pages it meets is known without
 * them: the walk stops at each page's top.  (Inline with a constant test:
 * the compiler makes one walk of each.) */
static inline void page_tops_walk(csg_view v, bool (*meets)(const void *arg, const csg_bvh_node *n),
                                  const void *arg, page_tops *t)
{
    csg_i32 stack[CSG_BVH_STACK + 2], top = 0;
    stack[top++] = 0;
    stack[top++] = 1;
    while (top > 0) {
        csg_i32 k = stack[--top];
        const csg_bvh_node *node = &v.bvh[k];
        if (!meets(arg, node))
            continue;
        if (pager_is_page_top(v.pager, k))
            page_tops_add(t, k);
        else if (node->count < 0 && top + 2 <= CSG_BVH_STACK + 2) {
            stack[top++] = node->first;
            stack[top++] = node->first + 1;
        }
    }
}

static inline bool frustum_meets_node(const void *f, const csg_bvh_node *n)
{
    return !frustum_culls(f, n->box, n->box + 3);
}

/* The pages rect's primary rays' pyramid meets (page_tops_walk),
 * fetched in one request before its rays. */
static inline void frustum_prefetch_pages(csg_view v, const csg_camera *cam, int width,
                                          int height, tile_rect rect)
{
    frustum f;
    if (!v.pager || !v.pager->prefetch || v.bvh_count == 0 ||
        !frustum_of(cam, width, height, rect, &f))
        return;
    page_tops t;
    page_tops_init(&t, v.pager);
    page_tops_walk(v, frustum_meets_node, &f, &t);
    page_tops_send(&t);
}

/* The longest candidate list any caller asks for (the OpenCL packet
 * pass's cells and their blocks: host/pass/ocl.c). */
#define FRUSTUM_LIST_MAX ENGINE_CANDIDATES_MAX

typedef struct {
    const frustum *f;
    csg_view v;
    csg_i32 *roots, n, cap;
    double depth[FRUSTUM_LIST_MAX];
} frustum_gather;

static inline bool frustum_take_candidate(void *arg, csg_i32 i)
{
    frustum_gather *g = arg;
    const csg_root *rt = &g->v.roots[i];
    return frustum_add(g->roots, g->depth, &g->n, g->cap, i,
                       frustum_depth(g->f, rt->lo, rt->hi));
}

/* The candidate roots of rect's primary rays into roots[0 .. cap - 1]
 * (cap <= FRUSTUM_LIST_MAX), nearest box first: the BVH's roots whose
 * boxes the pyramid may meet.  Returns their number, or -1 when there is
 * no list to use (the camera is not a plain perspective one, or more than
 * cap candidates). */
static inline csg_i32 frustum_candidates(csg_view v, const csg_camera *cam, int width,
                                         int height, tile_rect rect, csg_i32 *roots,
                                         csg_i32 cap)
{
    frustum f;
    if (cap > FRUSTUM_LIST_MAX || !frustum_of(cam, width, height, rect, &f))
        return -1;
    frustum_gather g = {&f, v, roots, 0, cap, {0}};
    return frustum_walk(v, &f, frustum_take_candidate, &g) ? g.n : -1;
}

/* The candidate roots of rect's primary rays among from[0 .. from_n - 1],
 * a list that holds every candidate of rect (an enclosing rectangle's: a
 * pyramid inside another culls no less), in that list's order, into
 * roots[0 .. cap - 1]: frustum_candidates for the price of from_n box
 * tests instead of a walk of the BVH.  -1 as frustum_candidates. */
static inline csg_i32 frustum_candidates_in(csg_view v, const csg_camera *cam, int width,
                                            int height, tile_rect rect, const csg_i32 *from,
                                            csg_i32 from_n, csg_i32 *roots, csg_i32 cap)
{
    frustum f;
    if (!frustum_of(cam, width, height, rect, &f))
        return -1;
    csg_i32 n = 0;
    for (csg_i32 k = 0; k < from_n; k++) {
        if (!frustum_may_meet(&f, v, from[k]))
            continue;
        if (n == cap)
            return -1;
        roots[n++] = from[k];
    }
    return n;
}

/* The candidate roots of rect's primary rays (frustum_candidates):
 * fr->culled is false when there is no list to use. */
static inline void frustum_roots_of(csg_view v, const csg_camera *cam, int width, int height,
                                    tile_rect rect, frustum_roots *fr)
{
    fr->n = frustum_candidates(v, cam, width, height, rect, fr->roots, FRUSTUM_MAX_ROOTS);
    fr->culled = fr->n >= 0;
    if (!fr->culled)
        fr->n = 0;
}

static inline bool frustum_take_first(void *arg, csg_i32 i)
{
    *(csg_i32 *)arg = i;
    return false; /* (one root the pyramid may meet: not a miss) */
}

/* Does every primary ray of the rectangle whose candidates are fr miss
 * everything?  No candidate survived, and no unbounded root is tried:
 * the rectangle's pixels are then the background (no sky_sphere) without
 * a ray (engine_trace_primary's shortcut). */
static inline bool frustum_all_miss(csg_view v, const frustum_roots *fr)
{
    return fr->culled && fr->n == 0 && v.root_count == 0;
}

/* frustum_all_miss of rect's candidates, found without gathering them
 * (the hetero master asks this of every fill tile: engine->rect_misses).
 * *met is a bounded root (below `roots`, the blob's root_count) that a
 * rectangle met before, or -1; it is tried first: neighbouring tiles of a
 * covered image mostly meet the same one, found at once instead of by a
 * walk of tens of boxes (1-3 us a tile on the SPD files).  The answer is
 * the walk's either way, a root the pyramid may meet being one the walk
 * reaches (frustum_may_meet).  On return *met is the root this rectangle
 * met (-1: none, or the camera allows no pyramid). */
static inline bool frustum_rect_misses(csg_view v, const csg_camera *cam, int width, int height,
                                       tile_rect rect, csg_i32 roots, csg_i32 *met)
{
    frustum f;
    if (v.root_count != 0 || !frustum_of(cam, width, height, rect, &f)) {
        *met = -1;
        return false;
    }
    if (*met >= v.root_count && *met < roots && frustum_may_meet(&f, v, *met))
        return false;
    *met = -1;
    return frustum_walk(v, &f, frustum_take_first, met);
}

/* csg_trace_nearest(v, r, 0, inf) for a ray of a rectangle whose
 * candidates are fr (fr->culled): the unbounded roots, then the
 * candidates, each behind its own box. */
static inline csg_hit frustum_trace(csg_view v, const frustum_roots *fr, csg_ray r)
{
    csg_hit best;
    best.t = CSG_R_INF;
    best.surf = CSG_SURF_NONE;
    csg_box_ray br = csg_box_ray_of(r);
    for (csg_i32 i = 0; i < v.root_count; i++)
        csg_try_root(v, i, r, &br, 1, R(0.0), &best);
    for (csg_i32 k = 0; k < fr->n; k++)
        csg_try_root(v, fr->roots[k], r, &br, 1, R(0.0), &best);
    if (best.surf == CSG_SURF_NONE)
        best.t = CSG_R_INF;
    return best;
}

#endif
