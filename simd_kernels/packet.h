/*
 * packet.h — the packet variant of the primary pass (OpenCL C only): a
 * work-item traces a packet of CSG_PACKET rays held in OpenCL vectors
 * (float16 on AVX-512 and on AVX2, double8 on AVX2 ... in the double
 * build), which PoCL compiles to whole-register SIMD instructions (two
 * registers a value where the vector is twice the register, as on AVX2).
 * PoCL 3.1 does not vectorise the one-ray kernel across work-items (its
 * walk is a data-dependent loop with a private stack); explicit vectors
 * are what it turns into 512-bit code.
 *
 * Built by host/pass/ocl.c with -DCSG_PACKET=W (twice the device's preferred
 * vector width of `real`, at most 16) and -DCSG_PACKET_COLS=C: a packet
 * is a block of C records of a row (pixels, or samples side by side) by
 * W / C rows, lane k at (k % C, k / C), so its rays are coherent.
 *
 * Algorithm (pk_trace_nearest), for every lane at once:
 *   - the linear roots, then the candidate roots of the packet's cell when
 *     it has a list (host/pass/ocl.c: the roots whose boxes the cell's
 *     pyramid of rays may meet, found on the host as workers/frustum.h
 *     finds a C worker's tile's), each behind its own box; else
 *   - the BVH with an explicit stack of nodes: a
 *     node is entered when its box meets any live lane's range
 *     [0, hit limit of that lane]; its roots are tried for the lanes that
 *     met the box (a leaf of one root: the root's box is the leaf's, not
 *     tested again, as csg_trace_nearest does); the nearer child (lane
 *     0's direction) goes first.  Tried and measured slower on AVX2
 *     (0.86-0.94x at N = 10 .. 10^4): csg_bvh_open_pair's scheme, both
 *     children tested at once, the nearer by the least entry over the
 *     lanes entered, the other pushed with its entries per lane and
 *     dropped on pop when beyond every limit: it tests as many boxes
 *     (every child of every node entered, here at the pop) and adds the
 *     vector stack and two reductions a node;
 *   - a root that is one uncomplemented primitive (most of them) is
 *     evaluated for all lanes by the packet compilation of the very
 *     code the C workers run (intersect_lanes.h: csg_leaf_first_hit_pk),
 *     and the best hit updated lane by lane with the same rule
 *     (csg_hit_wins_pk: nearer, or as near with a lower surface id;
 *     csg_hit_limit_pk: evaluated up to and including the best t);
 *   - any other root (a CSG program, a complemented leaf) falls back to
 *     the one-ray code, csg_try_root, for each lane concerned.
 * So every lane gets the record csg_trace_nearest gives its ray, bit for
 * bit (tests/test_ocl.c checks it).
 *
 * Box tests.  The one-ray walk tests a box with a reciprocal direction
 * computed once per ray, scaled so that the range it accepts only widens
 * (csg_box_hit, after Ize, "Robust BVH Ray Traversal", JCGT 2013); the
 * packet does the same operations lane by lane on the same reciprocals
 * (pk_box_cull), so a lane passes a box exactly when its one-ray walk
 * would at the same limit.  The walks' orders differ, so their limits at a
 * given box may differ: a box is only ever rejected when the ray meets no
 * part of it before the best hit so far, and the nearest-hit rule is
 * independent of the order, so the records agree.
 *
 * What PoCL 3.1 (LLVM 15) makes of it on the AVX-512 CPU (checked with
 * objdump -d on csg_primary.so in POCL_CACHE_DIR, float build, W = 16):
 * the whole walk is one function (_pocl_kernel_csg_primary_workgroup_fast,
 * 1187 instructions on zmm registers; the one-ray kernel has none), and its
 * hot loops are 16-lane code: a root's sphere test is
 *     vsubps 0x10(%rax,%rdi,1){1to16},%zmm13,%zmm7   f = o - centre
 *     vmulps/vaddps ... vcmpltps %zmm11,%zmm21,%k0   a > 0
 *     kortestw %k0,%k0 ; je ...                      no lane left: out
 *     vdivps %zmm11,%zmm12,%zmm13                    b / a
 *     ... vsqrtps %zmm6,%zmm6 ... vdivps             root, q / a, c / q
 * and a box test is vsubps/vmulps with {1to16} broadcasts of the node's
 * bounds, vcmpltps into mask registers, vblendmps, one kortestw.  Only the
 * one-ray fallback (pk_try_root_lanes) and the record stores of a ragged
 * packet are scalar.  POCL_VECTORIZER_REMARKS=1 reports the work-item
 * loops as not vectorised ("loop control flow is not understood by
 * vectorizer"): nothing is left to vectorise across work-items, the lanes
 * are already explicit.
 */
#ifndef CSG_PACKET_H
#define CSG_PACKET_H

#include "camera.h"

#define CSG_CAT_(a, b) a##b
#define CSG_CAT(a, b) CSG_CAT_(a, b)

#define CSG_PACKET_ROWS (CSG_PACKET / CSG_PACKET_COLS)

/* The lane types: realv of W reals, intv / uintv of W integers of the
 * same width (what a comparison of realv gives), lane_int / lane_uint
 * their elements. */
#ifdef CSG_DOUBLE
#define CSG_PK_R double
#define CSG_PK_I long
#define CSG_PK_U ulong
#else
#define CSG_PK_R float
#define CSG_PK_I int
#define CSG_PK_U uint
#endif
#define CSG_PK_V(t) CSG_CAT(t, CSG_PACKET)
typedef CSG_PK_V(CSG_PK_R) realv;
typedef CSG_PK_V(CSG_PK_I) intv;
typedef CSG_PK_V(CSG_PK_U) uintv;
typedef CSG_PK_I lane_int;
typedef CSG_PK_U lane_uint;
#define CSG_PK_TO_REAL(i) CSG_CAT(convert_, CSG_PK_V(CSG_PK_R))(i)
#define CSG_PK_AS_UINT(x) CSG_CAT(as_, CSG_PK_V(CSG_PK_U))(x)
#define CSG_PK_AS_REAL(x) CSG_CAT(as_, CSG_PK_V(CSG_PK_R))(x)
#define CSG_PK_I_AS_U(x) CSG_CAT(as_, CSG_PK_V(CSG_PK_U))(x)
#define CSG_PK_AS_INT(x) CSG_CAT(as_, CSG_PK_V(CSG_PK_I))(x)      /* realv -> intv, bits */
#define CSG_PK_TO_INT(x) CSG_CAT(convert_, CSG_PK_V(CSG_PK_I))(x) /* toward zero, as C */
#define CSG_PK_LOAD(p) CSG_CAT(vload, CSG_PACKET)(0, p)
#define CSG_PK_STORE(v, p) CSG_CAT(vstore, CSG_PACKET)(v, 0, p)

/* Any lane of mask m (-1 / 0 lanes) set.  OpenCL's any() tests the sign
 * bits, which PoCL's LLVM lowers to a chain of extracts; a reduction of
 * a comparison to "not 0" becomes one kortest. */
#ifndef __has_builtin
#define __has_builtin(x) 0 /* not clang: OpenCL's any() and all() */
#endif
#if __has_builtin(__builtin_reduce_or)
#define CSG_PK_ANY(m) (__builtin_reduce_or(m) != 0)
#else
#define CSG_PK_ANY(m) any(m)
#endif

/* Every lane of mask m set. */
#if __has_builtin(__builtin_reduce_and)
#define CSG_PK_ALL(m) (__builtin_reduce_and(m) != 0)
#else
#define CSG_PK_ALL(m) all(m)
#endif

/* A row of a packet (CSG_PACKET_COLS lanes) from or to memory; surface
 * ids narrowed to the records' uint. */
#define CSG_PK_ROW_LOAD(p) CSG_CAT(vload, CSG_PACKET_COLS)(0, p)
#define CSG_PK_ROW_STORE(v, p) CSG_CAT(vstore, CSG_PACKET_COLS)(v, 0, p)
#define CSG_PK_ROW_UINT(v) CSG_CAT(convert_uint, CSG_PACKET_COLS)(v)
/* A whole packet's values from memory (its rows, `stride` apart) as a
 * vector of type T (realv, CSG_PK_V(uint)), composed in registers: a
 * vector read of a private array just written lane by lane waits until
 * those narrow stores reach the cache (the store buffer does not forward
 * them into one wide load). */
#if CSG_PACKET_ROWS == 1
#define CSG_PK_ROWS_LOAD(T, p, stride) CSG_PK_ROW_LOAD(p)
#elif CSG_PACKET_ROWS == 2
#define CSG_PK_ROWS_LOAD(T, p, stride) ((T)(CSG_PK_ROW_LOAD(p), CSG_PK_ROW_LOAD((p) + (stride))))
#elif CSG_PACKET_ROWS == 4
#define CSG_PK_ROWS_LOAD(T, p, stride)                                                     \
    ((T)(CSG_PK_ROW_LOAD(p), CSG_PK_ROW_LOAD((p) + (stride)),                              \
         CSG_PK_ROW_LOAD((p) + 2 * (stride)), CSG_PK_ROW_LOAD((p) + 3 * (stride))))
#else
#error "CSG_PACKET / CSG_PACKET_COLS: 1, 2 or 4 rows (host/pass/ocl.c picks them)"
#endif

/* The walk is one function once inlined (its vectors stay in registers);
 * the one-ray fallback is kept out of it. */
#define CSG_PK_FN static inline __attribute__((always_inline))
#define CSG_PK_COLD static __attribute__((noinline))

/* The packet compilation of the shared geometry: v3_add_pk, ...,
 * csg_leaf_first_hit_pk, csg_hit_wins_pk, csg_camera_ray_pk,
 * csg_light_line_pk, offset_point_pk, csg_frame_offset_pk (lanes.h). */
#define CSG_LANES_PACKET
#include "vec_lanes.h"
#include "intersect_lanes.h"
#include "camera_lanes.h"
#include "light_lanes.h"
#include "offset_lanes.h"
#include "frame_lanes.h"
#undef CSG_LANES_PACKET

__constant lane_int csg_pk_lane_ids[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};

/* Scale factors of the reciprocal direction: 8 units of roundoff, more
 * than the 3.5 the culling test's own roundings can lose (Ize 2013). */
#ifdef CSG_DOUBLE
#define CSG_PK_INV_NEAR (R(1.0) - R(8.8817841970012523e-16)) /* 1 - 2^-50 */
#define CSG_PK_INV_FAR (R(1.0) + R(8.8817841970012523e-16))
#else
#define CSG_PK_INV_NEAR (R(1.0) - R(4.76837158203125e-07)) /* 1 - 2^-21 */
#define CSG_PK_INV_FAR (R(1.0) + R(4.76837158203125e-07))
#endif

typedef struct {
    csg_ray_pk ray;
    real tmin;            /* where every ray starts (the pass uses 0)        */
    intv live;            /* lanes that are records of the image             */
    realv o[3], d[3];     /* ray.o, ray.d by axis                            */
    realv inv_near[3];    /* 1 / d, its magnitude rounded down               */
    realv inv_far[3];     /* 1 / d, its magnitude rounded up                 */
    intv neg[3];          /* 1 / d < 0: the near plane is the box's hi       */
    csg_i32 back[3];      /* lane 0's d < 0 on that axis: the walk's order   */
} pk_packet;

CSG_PK_FN void pk_packet_init(pk_packet *pk, csg_ray_pk r, intv live)
{
    pk->ray = r;
    pk->tmin = R(0.0);
    pk->live = live;
    pk->o[0] = r.o.x;
    pk->o[1] = r.o.y;
    pk->o[2] = r.o.z;
    pk->d[0] = r.d.x;
    pk->d[1] = r.d.y;
    pk->d[2] = r.d.z;
    for (int a = 0; a < 3; a++) {
        realv inv = R(1.0) / pk->d[a];
        pk->inv_near[a] = inv * CSG_PK_INV_NEAR;
        pk->inv_far[a] = inv * CSG_PK_INV_FAR;
        pk->neg[a] = inv < R(0.0);
        pk->back[a] = pk->d[a].s0 < R(0.0);
    }
}

/* ---- box tests ---------------------------------------------------------------- */

/* The lanes whose range [tmin, tmax] meets the box lo..hi: csg_box_hit
 * (intersect.h) lane by lane, the same operations in the same order on the
 * same reciprocals, so the same lanes pass.  A NaN (0 * inf: the origin on
 * a plane of a slab the ray runs along) never replaces a bound. */
CSG_PK_FN intv pk_box_cull(CSG_GLOBAL const real *lo, CSG_GLOBAL const real *hi,
                           const pk_packet *pk, realv tmax)
{
    realv l = (realv)(pk->tmin), h = tmax;
    for (int a = 0; a < 3; a++) {
        realv near = select((realv)(lo[a]), (realv)(hi[a]), pk->neg[a]);
        realv far = select((realv)(hi[a]), (realv)(lo[a]), pk->neg[a]);
        realv tn = (near - pk->o[a]) * pk->inv_near[a];
        realv tf = (far - pk->o[a]) * pk->inv_far[a];
        l = select(l, tn, tn > l);
        h = select(h, tf, tf < h);
    }
    return l <= h;
}

/* ---- one root ------------------------------------------------------------------- */

/* The packet's rays into one-ray arrays, lane by lane (the cold paths'
 * fallback to the one-ray code). */
CSG_PK_FN void pk_ray_store(csg_ray_pk ray, real ro[3][CSG_PACKET], real rd[3][CSG_PACKET])
{
    CSG_PK_STORE(ray.o.x, ro[0]);
    CSG_PK_STORE(ray.o.y, ro[1]);
    CSG_PK_STORE(ray.o.z, ro[2]);
    CSG_PK_STORE(ray.d.x, rd[0]);
    CSG_PK_STORE(ray.d.y, rd[1]);
    CSG_PK_STORE(ray.d.z, rd[2]);
}

/* Root i for the lanes of m by the one-ray code (csg_try_root), lane by
 * lane: CSG programs and complemented leaves.  Returns the new best. */
CSG_PK_COLD csg_hit_pk pk_try_root_lanes(csg_view v, csg_i32 i, csg_ray_pk ray, real tmin,
                                         intv m, csg_hit_pk best)
{
    lane_int mk[CSG_PACKET];
    real bt[CSG_PACKET], ro[3][CSG_PACKET], rd[3][CSG_PACKET];
    lane_uint bs[CSG_PACKET];
    CSG_PK_STORE(m, mk);
    CSG_PK_STORE(best.t, bt);
    CSG_PK_STORE(best.surf, bs);
    pk_ray_store(ray, ro, rd);
    for (int k = 0; k < CSG_PACKET; k++) {
        if (!mk[k])
            continue;
        csg_ray r;
        r.o = v3(ro[0][k], ro[1][k], ro[2][k]);
        r.d = v3(rd[0][k], rd[1][k], rd[2][k]);
        csg_hit b;
        b.t = bt[k];
        b.surf = (csg_u32)bs[k];
        csg_box_ray br = csg_box_ray_of(r);
        csg_try_root(v, i, r, &br, 0, tmin, &b); /* the box: tested by the caller */
        bt[k] = b.t;
        bs[k] = b.surf;
    }
    best.t = CSG_PK_LOAD(bt);
    best.surf = CSG_PK_LOAD(bs);
    return best;
}

/* Root i for the lanes of m: what csg_try_root does for each of them (its
 * box tested first when test_box: a BVH leaf of one root has just tested
 * the very same box). */
CSG_PK_FN void pk_try_root(csg_view v, csg_i32 i, const pk_packet *pk, intv m, int test_box,
                           csg_hit_pk *best)
{
    CSG_GLOBAL const csg_root *rt = &v.roots[i];
    realv limit = csg_hit_limit_pk(best);
    if (test_box) {
        m = m & pk_box_cull(rt->lo, rt->hi, pk, limit);
        if (!CSG_PK_ANY(m))
            return;
    }
    csg_i32 leaf = v.nodes[rt->first_node].prim;
    /* without CSG (spec.h) every root is one uncomplemented primitive */
    if (CSG_USE_CSG && (rt->node_count != 1 || (v.prims[leaf].flags & CSG_PF_INVERT))) {
        *best = pk_try_root_lanes(v, i, pk->ray, pk->tmin, m, *best);
        return;
    }
    csg_hit_pk h = csg_leaf_first_hit_pk(v.prims, leaf, pk->ray, (realv)(pk->tmin), limit);
    intv win = m & csg_hit_wins_pk(h, best);
    best->t = select(best->t, h.t, win);
    best->surf = select(best->surf, h.surf, win);
}

/* ---- the BVH as this walk knows it (flat.h, csg_bvh_node): only here ------------
 * Nodes come in sibling pairs; an interior node's children are first and
 * first + 1.  A node is tested with the limit of the moment for every lane
 * still live; the nearer child by lane 0's direction is entered first. */

CSG_PK_FN int pk_bvh_is_leaf(CSG_GLOBAL const csg_bvh_node *n) { return n->count >= 0; }

CSG_PK_FN void pk_walk_bvh(csg_view v, const pk_packet *pk, csg_hit_pk *best)
{
    csg_i32 stack[2 * CSG_BVH_STACK];
    csg_i32 top = 0;
    if (v.bvh_count > 0) { /* the top pair, nodes 0 and 1 */
        stack[top++] = 1;
        stack[top++] = 0;
    }
    while (top > 0) {
        csg_i32 k = stack[--top];
        CSG_GLOBAL const csg_bvh_node *n = &v.bvh[k];
        intv m = pk->live & pk_box_cull(n->box, n->box + 3, pk, csg_hit_limit_pk(best));
        if (!CSG_PK_ANY(m))
            continue;
        if (pk_bvh_is_leaf(n)) {
            for (csg_i32 i = n->first; i < n->first + n->count; i++)
                pk_try_root(v, i, pk, m, n->count > 1, best);
            continue;
        }
        if (top + 2 > 2 * CSG_BVH_STACK) /* the flattener prevents this */
            break;
        int back = pk->back[-1 - n->count]; /* count = -1 - split axis */
        stack[top++] = back ? n->first : n->first + 1;
        stack[top++] = back ? n->first + 1 : n->first;
    }
}

/* ---- shadow rays: the any-hit walk of shadow.h, a packet at a time ------------------
 * Lane by lane the same decisions as csg_shadow_answer: a root is met when
 * the walk reaches its leaf and (in a leaf of several roots, or unbounded)
 * its own box passes on [0, tmax]; a met opaque root blocks when its first
 * visible boundary lies before tmax (csg_shadow_opaque_blocks); a met root
 * that may filter the light makes the lane unknown.  The answer of a lane
 * does not depend on the order the roots are met in (blocked if any met
 * opaque root blocks, else unknown if any filtering root is met, else lit),
 * so the packet's walk may visit them in its own order. */

/* Root i blocks the lanes of m: csg_shadow_opaque_blocks by the one-ray
 * code, lane by lane (CSG programs and complemented leaves). */
CSG_PK_COLD intv pk_shadow_lanes(csg_view v, csg_i32 i, csg_ray_pk ray, realv tmax, intv m)
{
    lane_int mk[CSG_PACKET], out[CSG_PACKET];
    real tm[CSG_PACKET], ro[3][CSG_PACKET], rd[3][CSG_PACKET];
    CSG_PK_STORE(m, mk);
    CSG_PK_STORE(tmax, tm);
    pk_ray_store(ray, ro, rd);
    for (int k = 0; k < CSG_PACKET; k++) {
        out[k] = 0;
        if (!mk[k])
            continue;
        csg_ray r;
        r.o = v3(ro[0][k], ro[1][k], ro[2][k]);
        r.d = v3(rd[0][k], rd[1][k], rd[2][k]);
        out[k] = csg_shadow_opaque_blocks(v, i, r, tm[k]) ? -1 : 0;
    }
    return CSG_PK_LOAD(out);
}

/* Root i for the lanes of m (its box tested first when test_box). */
CSG_PK_FN void pk_shadow_root(csg_view v, csg_i32 i, const pk_packet *pk, realv tmax, intv m,
                              int test_box, intv *blocked, intv *touched)
{
    CSG_GLOBAL const csg_root *rt = &v.roots[i];
    if (rt->flags & CSG_ROOT_NO_SHADOW)
        return;
    if (test_box)
        m = m & pk_box_cull(rt->lo, rt->hi, pk, tmax);
    if (!CSG_PK_ANY(m))
        return;
    if (!(rt->flags & CSG_ROOT_OPAQUE)) {
        *touched = *touched | m;
        return;
    }
    csg_i32 leaf = v.nodes[rt->first_node].prim;
    if (CSG_USE_CSG && (rt->node_count != 1 || (v.prims[leaf].flags & CSG_PF_INVERT))) {
        *blocked = *blocked | pk_shadow_lanes(v, i, pk->ray, tmax, m);
        return;
    }
    csg_hit_pk h = csg_leaf_first_hit_pk(v.prims, leaf, pk->ray, (realv)(R(0.0)), tmax);
    *blocked = *blocked | (m & (h.surf != (uintv)(CSG_SURF_NONE)) & (h.t < tmax));
}

/* The shadow walk of the packet's live lanes to tmax (per lane): the
 * unbounded roots, then the BVH, a node tested for the lanes whose walk
 * reached its parent (the one-ray walk opens a node's children only after
 * its own box passed) and are not blocked yet. */
CSG_PK_FN void pk_shadow_walk(csg_view v, const pk_packet *pk, realv tmax, intv *blocked,
                              intv *touched)
{
    *blocked = (intv)(0);
    *touched = (intv)(0);
    for (csg_i32 i = 0; i < v.root_count; i++)
        pk_shadow_root(v, i, pk, tmax, pk->live & ~*blocked, 1, blocked, touched);
    csg_i32 stack[2 * CSG_BVH_STACK];
    intv reached[2 * CSG_BVH_STACK]; /* the lanes that passed the parent */
    csg_i32 top = 0;
    if (v.bvh_count > 0) { /* the top pair, nodes 0 and 1 */
        stack[top] = 1;
        reached[top++] = pk->live;
        stack[top] = 0;
        reached[top++] = pk->live;
    }
    while (top > 0) {
        top--;
        csg_i32 k = stack[top];
        CSG_GLOBAL const csg_bvh_node *n = &v.bvh[k];
        intv m = reached[top] & ~*blocked & pk_box_cull(n->box, n->box + 3, pk, tmax);
        if (!CSG_PK_ANY(m))
            continue;
        if (pk_bvh_is_leaf(n)) {
            for (csg_i32 i = n->first; i < n->first + n->count; i++)
                pk_shadow_root(v, i, pk, tmax, m & ~*blocked, n->count > 1, blocked, touched);
            continue;
        }
        if (top + 2 > 2 * CSG_BVH_STACK) /* the flattener prevents this */
            break;
        int back = pk->back[-1 - n->count]; /* count = -1 - split axis */
        stack[top] = back ? n->first : n->first + 1;
        reached[top++] = m;
        stack[top] = back ? n->first + 1 : n->first;
        reached[top++] = m;
    }
}

/* ---- the packet's nearest hits ---------------------------------------------------- */

/* Lane by lane, csg_trace_nearest(v, ray, 0, inf).  With a candidate list
 * (n >= 0: cands[0 .. n - 1], the bounded roots the packet's frustum may
 * meet, host/pass/ocl.c's cells) those are tried, each behind its own box,
 * instead of the BVH walk: workers/frustum.h's culling, exact for the same
 * reason (a root no ray of the packet can meet is all it leaves out, and
 * the nearest-hit rule does not depend on the order). */
CSG_PK_FN csg_hit_pk pk_trace_nearest(csg_view v, const pk_packet *pk,
                                      CSG_GLOBAL const csg_i32 *cands, csg_i32 n)
{
    csg_hit_pk best;
    best.t = (realv)(CSG_R_INF);
    best.surf = (uintv)(CSG_SURF_NONE);
    for (csg_i32 i = 0; i < v.root_count; i++)
        pk_try_root(v, i, pk, pk->live, 1, &best);
    if (n >= 0)
        for (csg_i32 k = 0; k < n; k++)
            pk_try_root(v, cands[k], pk, pk->live, 1, &best);
    else
        pk_walk_bvh(v, pk, &best);
    best.t = select(best.t, (realv)(CSG_R_INF), best.surf == CSG_SURF_NONE);
    return best;
}

#endif
