/*
 * flatten.c — scene tree (double, pointers) -> flat blob (real, indices).
 * Compiled twice: as csg_flatten_float and, with -DCSG_DOUBLE, as
 * csg_flatten_double.
 *
 * Steps:
 *  1. Top-level unions that are not inverted dissolve: their children
 *     become roots of their own (POV-Ray shows every surface of a union, and
 *     separate roots keep interval lists short and get their own bounding
 *     boxes).  Textures, interiors and no_shadow are inherited on the way.
 *  2. Every other top-level object becomes a root whose CSG tree is compiled
 *     into an RPN program of union / intersection over primitive leaves:
 *     complements (inverse, the subtracted operands of difference) are
 *     pushed to the leaves with De Morgan's laws.  Operands are ordered by
 *     the number of interval lists they need (Ershov number), largest first,
 *     so a program needs as few lists at once as possible; a program that
 *     still needs more than CSG_STACK_MAX is an error.
 *     A run of at least CSG_WIDE_MIN leaves folded by one operator, each
 *     the operator's identity where the ray misses it (a wide CSG node),
 *     gets a CSG_OP_WIDE mark and a BVH of its own (flat.h, csg_wide).
 *     Surfaces made of several triangles (polygon, mesh) are a union of
 *     their pieces: at the top level each piece is a root of its own (the
 *     BVH then sees every triangle), inside CSG a union in the program.
 *  3. Primitives get canonical parameters: spheres and boxes under a pure
 *     translate + scale keep world-space parameters (exact, no matrix);
 *     everything else stores its world -> local matrix.  A box whose
 *     corners share a coordinate (in `real`) is a flat_box, a sheet
 *     (device/flat.h).  Cylinders and cones live in a frame with their
 *     axis on +z from 0 to their height.
 *     Triangles are stored in world space (vertices and vertex normals
 *     transformed here, never a matrix); polygons are split into
 *     triangles (csg/polygon.c: fan when convex, ear clipping otherwise),
 *     once per polygon (the split of the last polygon is kept).
 *  4. Every root gets a world bounding box, padded outwards so rounding to
 *     `real` never clips a silhouette.
 *  5. Every root records what a shadow ray may skip in it (flat.h,
 *     csg_root_flags): all of it (every primitive no_shadow), or all but
 *     the first visible boundary (every primitive casts shadows and is
 *     opaque).
 *  6. Unbounded roots (planes, complements) go first and are tested one by
 *     one; the bounded ones are reordered into the leaves of a BVH built by
 *     binned SAH, siblings side by side (csg/bvh_build.c; the depth
 *     stays below CSG_BVH_STACK whatever the scene); the nodes and the
 *     primitives are then laid out in the roots' new order.
 */
#include "flatten.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bvh_build.h"
#include "camera_setup.h"
#include "extrude.h"
#include "polygon.h"

#ifdef CSG_DOUBLE
#define FLATTEN_FN csg_flatten_double
#define FLATTEN_SCAN csg_blob_scan_features_double
#else
#define FLATTEN_FN csg_flatten_float
#define FLATTEN_SCAN csg_blob_scan_features_float
#endif

#define CSG_MAX_MAP_PIGMENTS (1 << 20) /* materials of pigment map entries */

/* A material whose pigment map's entries, or whose pigment_pattern's
 * pigment, wait for their materials. */
typedef struct {
    int parent;                        /* the material holding the map   */
    const csg_pigment_entry *entries;  /* its entries (the scene's arena:
                                          the pigment may be a copy)     */
    int count;
    const csg_pigment *pattern;        /* not NULL: the pigment of the
                                          parent's pigment_pattern (count 1,
                                          no entries)                    */
} pending_map;

/* A texture whose layers, normals or texture_map entries wait for their
 * materials (add_texture_parts). */
typedef struct {
    int parent;             /* the material of its top layer              */
    const csg_texture *t;   /* the texture (the scene's arena: stable)    */
    csg_interior in;        /* the object's interior                      */
} pending_texture;

/* Growable arrays of the output, and what the walk inherits. */
#define FLAT_CARRIED_MAX 8 /* clipped unions nested in one another that are
                              split (deeper ones stay whole) */

typedef struct {
    csg_prim *prims;
    int prim_count, prim_cap;
    csg_node *nodes;
    int node_count, node_cap;
    csg_root *roots;
    dbox *root_boxes;       /* the world box of each root, in double       */
    int root_count, root_cap, root_box_cap;
    csg_bvh_node *bvh;
    int bvh_count, bvh_cap;
    dbox *prim_boxes;       /* each primitive's world box, uncomplemented
                               (the wide runs' hierarchies)             */
    int prim_box_cap;
    csg_wide *wide;         /* wide runs (flat.h, CSG_OP_WIDE)            */
    int wide_count, wide_cap;
    csg_bvh_node *wide_bvh;
    int wide_bvh_count, wide_bvh_cap;
    csg_i32 *wide_items;
    int wide_item_count, wide_item_cap;
    real *coefs;            /* the polys' coefficient table (flat.h)       */
    int coef_count, coef_cap;
    const csg_object *coefs_of; /* the poly whose coefficients start at   */
    int coefs_at;               /* coefs[coefs_at] (its pieces share them) */
    csg_curve *curves;      /* the curved sides of prisms' pieces (flat.h) */
    int curve_count, curve_cap;
    int linear_roots;       /* unbounded roots, tested one by one (first)  */
    csg_material *mats;
    uint64_t *mat_keys;     /* each material's (texture, interior) key   */
    int mat_count, mat_cap, mat_key_cap;
    int *mat_slots;         /* hash table over mat_keys: material + 1, 0
                               empty; mat_slot_cap a power of two, at
                               most half full                            */
    size_t mat_slot_cap;
    const csg_texture *last_texture; /* the texture and interior of the last */
    csg_interior last_interior;      /* material built from a texture entry  */
    int last_material;               /* (last_texture NULL: none yet)        */
    csg_map_color *maps;    /* the colour maps of patterned materials   */
    int map_count, map_cap;
    pending_map *pending;   /* pigment maps whose entries' materials are
                               still to be added (add_pigment_maps)      */
    int pending_count, pending_cap;
    pending_texture *tparts; /* textures whose parts are still to be added */
    int tpart_count, tpart_cap;
    int sky_first;          /* the sky_sphere's pigments: materials from here */
    const csg_scene *scene;
    csg_diag *diag;
    bool oom;
    const csg_object *split_of; /* the polygon whose split is in split[]  */
    int *split;                 /* its triangles, 3 vertex indices each    */
    int split_count, split_cap;
    const csg_object *traps_of; /* the prism whose pieces are in traps[]   */
    csg_trapezoid *traps;
    int trap_count;
    const csg_object *bound_removed; /* the top-level object whose bounded_by
                                        POV-Ray removes (add_top)          */
    bool bound_box_kept;             /* and whose box it keeps (emit_box_gate) */
    const csg_object *carried[FLAT_CARRIED_MAX]; /* the clipped unions above the
                                        root being added, whose clips cut it
                                        too (add_clipped_union)            */
    int carried_count;
} flat_builder;

typedef struct {
    int texture;  /* -1: none yet (the default texture) */
    int interior; /* -1: none yet (ior 1)               */
    bool no_shadow;
    int hollow;   /* 0 not said, 1 hollow, 2 not (csg_object.hollow) */
    bool clip;    /* inside a clipped_by: its primitives get CSG_PF_CLIP */
    bool bound;   /* inside a kept bounded_by: CSG_PF_BOUND                */
    int inside;   /* 1 + the interior_texture's index; 0: none          */
} inherited;

static bool grow(void **arr, int *cap, int need, size_t elem)
{
    if (need <= *cap)
        return true;
    int ncap = *cap ? *cap * 2 : 64;
    while (ncap < need)
        ncap *= 2;
    void *p = realloc(*arr, (size_t)ncap * elem);
    if (!p)
        return false;
    *arr = p;
    *cap = ncap;
    return true;
}

static void free_array(void **arr)
{
    free(*arr);
    *arr = NULL;
}

/* ---- boxes ------------------------------------------------------------------ */

static dbox box_infinite(void)
{
    dbox b;
    for (int i = 0; i < 3; i++) {
        b.lo[i] = -INFINITY;
        b.hi[i] = INFINITY;
    }
    return b;
}

static dbox box_of_corners(const csg_xform *x, const double lo[3], const double hi[3])
{
    dbox b = box_empty();
    for (int c = 0; c < 8; c++) {
        double p[3] = {(c & 1) ? hi[0] : lo[0], (c & 2) ? hi[1] : lo[1], (c & 4) ? hi[2] : lo[2]};
        for (int i = 0; i < 3; i++) {
            double w = x->m[i][0] * p[0] + x->m[i][1] * p[1] + x->m[i][2] * p[2] + x->m[i][3];
            b.lo[i] = box_min(b.lo[i], w);
            b.hi[i] = box_max(b.hi[i], w);
        }
    }
    return b;
}

static dbox box_intersect(dbox a, dbox b)
{
    for (int i = 0; i < 3; i++) {
        a.lo[i] = box_max(a.lo[i], b.lo[i]);
        a.hi[i] = box_min(a.hi[i], b.hi[i]);
    }
    return a;
}

/* Round outwards to `real` after a relative pad: the box test runs in
 * `real` and must never reject a ray that meets the solid. */
static void box_store(dbox b, real lo[3], real hi[3])
{
    for (int i = 0; i < 3; i++) {
        double pad = 1e-5 * (fabs(b.lo[i]) + fabs(b.hi[i])) + 1e-30;
        if (!isfinite(pad))
            pad = 0;
        double l = b.lo[i] - pad, h = b.hi[i] + pad;
        real rl = (real)l, rh = (real)h;
        if ((double)rl > l)
            rl = (real)nextafter(rl, -CSG_R_INF);
        if ((double)rh < h)
            rh = (real)nextafter(rh, CSG_R_INF);
        lo[i] = rl;
        hi[i] = rh;
    }
}

/* ---- primitives --------------------------------------------------------------- */

static void store3(real dst[3], dvec3 v);

static bool is_translate_scale(const csg_xform *x, bool uniform)
{
    const double(*m)[4] = x->m;
    if (m[0][1] != 0 || m[0][2] != 0 || m[1][0] != 0 || m[1][2] != 0 || m[2][0] != 0 || m[2][1] != 0)
        return false;
    return !uniform || (fabs(m[0][0]) == fabs(m[1][1]) && fabs(m[1][1]) == fabs(m[2][2]));
}

static dvec3 xf_point(const csg_xform *x, dvec3 p)
{
    const double(*m)[4] = x->m;
    return (dvec3){m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                   m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                   m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
}

static void store_inverse(csg_prim *p, const csg_xform *world_to_local)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            p->inv[i * 4 + j] = (real)world_to_local->m[i][j];
    p->flags |= CSG_PF_XFORM;
}

/* The frame of a cylinder/cone: object -> local with the axis from a to b
 * mapped onto +z from 0 to |b - a|. */
static void cone_frame(dvec3 a, dvec3 b, csg_xform *obj_to_local, double *height)
{
    double ax = b.x - a.x, ay = b.y - a.y, az = b.z - a.z;
    double h = sqrt(ax * ax + ay * ay + az * az);
    double w[3] = {ax / h, ay / h, az / h};
    /* u: any unit vector orthogonal to w; v = w x u */
    double t[3] = {0, 0, 0};
    int k = fabs(w[0]) <= fabs(w[1]) ? (fabs(w[0]) <= fabs(w[2]) ? 0 : 2)
                                     : (fabs(w[1]) <= fabs(w[2]) ? 1 : 2);
    t[k] = 1;
    double u[3] = {w[1] * t[2] - w[2] * t[1], w[2] * t[0] - w[0] * t[2], w[0] * t[1] - w[1] * t[0]};
    double ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int i = 0; i < 3; i++)
        u[i] /= ul;
    double v[3] = {w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2], w[0] * u[1] - w[1] * u[0]};
    const double *rows[3] = {u, v, w};
    double o[3] = {a.x, a.y, a.z};
    for (int i = 0; i < 3; i++) {
        obj_to_local->m[i][3] = 0;
        for (int j = 0; j < 3; j++) {
            obj_to_local->m[i][j] = rows[i][j];
            obj_to_local->m[i][3] -= rows[i][j] * o[j];
        }
    }
    *height = h;
}

/* ---- materials: one per (texture, interior) pair in use ------------------------
 * Interned in a hash table (linear probing): a million objects with their
 * own pigments flatten in linear time, and the key is 64 bits wide, so no
 * count of textures or interiors can make two pairs collide. */

static uint64_t material_key(inherited inh)
{
    return ((uint64_t)(uint32_t)(inh.texture + 1) << 32) | (uint32_t)(inh.interior + 1);
}

static size_t material_slot_of(uint64_t key, size_t cap)
{
    key ^= key >> 29; /* mix the texture half into the low bits */
    key *= 0xbf58476d1ce4e5b9u;
    key ^= key >> 32;
    return (size_t)key & (cap - 1);
}

/* The slot holding `key`, or the empty slot where it goes. */
static size_t material_find(const flat_builder *fb, uint64_t key)
{
    size_t i = material_slot_of(key, fb->mat_slot_cap);
    while (fb->mat_slots[i] && fb->mat_keys[fb->mat_slots[i] - 1] != key)
        i = (i + 1) & (fb->mat_slot_cap - 1);
    return i;
}

/* Room for one more material in the table (kept at most half full). */
static bool material_reserve(flat_builder *fb)
{
    if ((size_t)(fb->mat_count + 1) * 2 <= fb->mat_slot_cap)
        return true;
    size_t cap = fb->mat_slot_cap ? fb->mat_slot_cap * 2 : 64;
    int *old = fb->mat_slots;
    size_t old_cap = fb->mat_slot_cap;
    fb->mat_slots = calloc(cap, sizeof *fb->mat_slots);
    if (!fb->mat_slots) {
        fb->mat_slots = old;
        return false;
    }
    fb->mat_slot_cap = cap;
    for (size_t i = 0; i < old_cap; i++)
        if (old[i])
            fb->mat_slots[material_find(fb, fb->mat_keys[old[i] - 1])] = old[i];
    free(old);
    return true;
}

static void store3(real dst[3], dvec3 v)
{
    dst[0] = (real)v.x;
    dst[1] = (real)v.y;
    dst[2] = (real)v.z;
}

static bool pigment_map_values(flat_builder *fb, const csg_pigment *pig, csg_material *m);
static bool pattern_pigment_queue(flat_builder *fb, const csg_pigment *pig, csg_material *m);

/* A patterned pigment: its kind, world -> pattern matrix (pig's own
 * transform, then `then` when not NULL), wave and colour map (appended to
 * fb->maps); a plain one: its colour (CSG_PATTERN_PLAIN). */
static bool material_pattern(flat_builder *fb, const csg_pigment *pig, const csg_xform *then,
                             csg_material *m)
{
    for (int i = 0; i < 3; i++)
        m->color[i] = (real)pig->rgbft[i];
    m->filter = (real)pig->rgbft[3];
    m->transmit = (real)pig->rgbft[4];
    m->pattern = pig->pattern; /* one id in the scene and the blob (device/patterns.h) */
    m->map_first = m->map_count = m->pad = 0;
    if (m->pattern == CSG_PATTERN_PLAIN)
        return true;
    /* (a map's pigment or the sky's has no texture to set it: the wave
     * sources of its ripples or waves, which every other blob leaves as
     * it was) */
    if (m->pattern == CSG_PATTERN_RIPPLES || m->pattern == CSG_PATTERN_WAVES)
        m->number_of_waves = fb->scene->globals.number_of_waves;
    m->wave = pig->wave;
    m->exponent = (real)pig->exponent;
    m->noise_gen = csg_noise_of(fb->scene, pig);
    m->turb_on = pig->turb.on;
    m->octaves = pig->turb.octaves;
    store3(m->turbulence, pig->turb.amount);
    m->omega = (real)pig->turb.omega;
    m->lambda = (real)pig->turb.lambda;
    m->agate_turb = (real)pig->agate_turb;
    store3(m->crackle_form, pig->crackle.form);
    m->crackle_metric = (real)pig->crackle.metric;
    m->crackle_offset = (real)pig->crackle.offset;
    m->crackle_solid = pig->crackle.solid;
    m->quilt_control[0] = (real)pig->control0; /* a quilted pigment's, as a normal's */
    m->quilt_control[1] = (real)pig->control1;
    m->spiral_arms = pig->arms;
    store3(m->brick_size, pig->brick_size);
    m->mortar = (real)pig->mortar;
    csg_xform inv, full = pig->xform;
    if (then)
        csg_xform_then(&full, then, &full);
    if (!csg_xform_invert(&full, &inv))
        csg_xform_identity(&inv); /* the parser refuses singular transforms */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            m->to_pattern[4 * i + j] = (real)inv.m[i][j];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            m->from_pattern[3 * i + j] = (real)full.m[i][j];
    store3(m->gradient, pig->gradient);
    m->frequency = (real)pig->frequency;
    m->phase = (real)pig->phase;
    if (pig->pattern == CSG_PATTERN_PIGMENT_PATTERN && !pattern_pigment_queue(fb, pig, m))
        return false;
    if (pig->pmap_count > 0)
        return pigment_map_values(fb, pig, m);
    if (!grow((void **)&fb->maps, &fb->map_cap, fb->map_count + pig->map_count,
              sizeof(csg_map_color))) {
        fb->oom = true;
        return false;
    }
    m->map_first = fb->map_count;
    m->map_count = pig->map_count;
    for (int i = 0; i < pig->map_count; i++) {
        csg_map_color *c = &fb->maps[fb->map_count++];
        c->value = (real)pig->map[i].value;
        for (int k = 0; k < 5; k++)
            c->rgbft[k] = (real)pig->map[i].rgbft[k];
    }
    return true;
}

/* Pigments a pigment_clear call may visit: a map of maps declared from
 * the same identifiers grows exponentially; past this it answers "clear",
 * which is only slower (a shadow ray then looks at the surface). */
#define CLEAR_VISIT_BUDGET 4096

/* Some point of the pigment lets light through (filter or transmit), or
 * the budget *left ran out. */
static bool pigment_clear(const csg_pigment *pig, int *left)
{
    if (--*left < 0)
        return true;
    if (pig->pattern == CSG_PATTERN_PLAIN)
        return pig->rgbft[3] > 0 || pig->rgbft[4] > 0;
    if (pig->pmap_count > 0) {
        for (int i = 0; i < pig->pmap_count; i++)
            if (pigment_clear(&pig->pmap[i].pigment, left))
                return true;
        return false;
    }
    for (int i = 0; i < pig->map_count; i++)
        if (pig->map[i].rgbft[3] > 0 || pig->map[i].rgbft[4] > 0)
            return true;
    return false;
}

/* A pigment map: its values in fb->maps, each with filter 1 when its
 * pigment lets light through somewhere (what material_opaque reads), and
 * its entries' materials queued for add_pigment_maps. */
static bool pigment_map_values(flat_builder *fb, const csg_pigment *pig, csg_material *m)
{
    if (!grow((void **)&fb->maps, &fb->map_cap, fb->map_count + pig->pmap_count,
              sizeof(csg_map_color)) ||
        !grow((void **)&fb->pending, &fb->pending_cap, fb->pending_count + 1,
              sizeof(pending_map))) {
        fb->oom = true;
        return false;
    }
    m->map_first = fb->map_count;
    m->map_count = pig->pmap_count;
    for (int i = 0; i < pig->pmap_count; i++) {
        csg_map_color *c = &fb->maps[fb->map_count++];
        memset(c, 0, sizeof *c);
        c->value = (real)pig->pmap[i].value;
        int left = CLEAR_VISIT_BUDGET;
        c->rgbft[3] = pigment_clear(&pig->pmap[i].pigment, &left) ? R(1.0) : R(0.0);
    }
    pending_map *pm = &fb->pending[fb->pending_count++];
    pm->parent = (int)(m - fb->mats);
    pm->entries = pig->pmap;
    pm->count = pig->pmap_count;
    pm->pattern = NULL;
    return true;
}

/* A pigment_pattern: its pigment queued for add_pigment_maps, which puts
 * its material after every other one (m->pattern_pigment). */
static bool pattern_pigment_queue(flat_builder *fb, const csg_pigment *pig, csg_material *m)
{
    if (!grow((void **)&fb->pending, &fb->pending_cap, fb->pending_count + 1,
              sizeof(pending_map))) {
        fb->oom = true;
        return false;
    }
    pending_map *pm = &fb->pending[fb->pending_count++];
    pm->parent = (int)(m - fb->mats);
    pm->entries = NULL;
    pm->count = 1;
    pm->pattern = pig->pattern_pigment;
    return true;
}

/* The materials of the pigment maps' entries, after every other one (so
 * an entry's material comes after its map's: blob.c checks it), each
 * pattern relative to the point of the pattern holding the map.  Entries
 * with maps of their own queue more as they go; maps of maps declared
 * from the same pigments multiply, so their materials are limited.
 * False (d filled) past the limit. */
static bool add_pigment_maps(flat_builder *fb)
{
    int added = 0;
    for (int i = 0; i < fb->pending_count && !fb->oom; i++) {
        pending_map pm = fb->pending[i];
        int n = pm.count;
        if ((added += n) > CSG_MAX_MAP_PIGMENTS) {
            csg_error_plain(fb->diag, "pigment maps hold more than %d pigments in all",
                            CSG_MAX_MAP_PIGMENTS);
            return false;
        }
        if (!grow((void **)&fb->mats, &fb->mat_cap, fb->mat_count + n, sizeof(csg_material)) ||
            !grow((void **)&fb->mat_keys, &fb->mat_key_cap, fb->mat_count + n, sizeof(uint64_t))) {
            fb->oom = true;
            return true; /* reported as out of memory */
        }
        if (pm.pattern)
            fb->mats[pm.parent].pattern_pigment = fb->mat_count;
        else
            fb->mats[pm.parent].sub_first = fb->mat_count;
        for (int k = 0; k < n; k++) {
            csg_material *m = &fb->mats[fb->mat_count];
            memset(m, 0, sizeof *m);
            if (!material_pattern(fb, pm.pattern ? pm.pattern : &pm.entries[k].pigment, NULL, m))
                return true; /* out of memory: fb->oom, reported so */
            fb->mat_keys[fb->mat_count++] = UINT64_MAX; /* never a texture's */
        }
    }
    return true;
}

/* The sky_sphere's pigments, as materials after the objects' (only their
 * pigment fields count), each through the sky's transform. */
static void add_sky(flat_builder *fb)
{
    const csg_sky *sky = &fb->scene->sky;
    fb->sky_first = fb->mat_count;
    if (!grow((void **)&fb->mats, &fb->mat_cap, fb->mat_count + sky->count, sizeof(csg_material)) ||
        !grow((void **)&fb->mat_keys, &fb->mat_key_cap, fb->mat_count + sky->count,
              sizeof(uint64_t))) {
        fb->oom = true;
        return;
    }
    for (int i = 0; i < sky->count; i++) {
        csg_material *m = &fb->mats[fb->mat_count];
        memset(m, 0, sizeof *m);
        if (!material_pattern(fb, &sky->pigments[i], &sky->xform, m))
            return;
        fb->mat_keys[fb->mat_count++] = UINT64_MAX; /* never a texture's (not in the hash) */
    }
}

/* One layer of a texture into m: its finish, its pigment (or a
 * texture_map's pattern, whose map values are its entries'), the ior; its
 * normal, the layers under it and the map's entries are queued
 * (add_texture_parts) when it has any. */
static bool material_layer(flat_builder *fb, const csg_texture *tex, const csg_interior *in,
                           csg_material *m)
{
    double ior = in->ior;
    m->fade_distance = (real)in->fade_distance;
    m->fade_power = (real)in->fade_power;
    for (int i = 0; i < 3; i++)
        m->fade_color[i] = (real)in->fade_color[i];
    for (int i = 0; i < 3; i++) {
        m->ambient[i] = (real)tex->finish.ambient[i];
        m->reflection[i] = (real)tex->finish.reflection[i];
    }
    m->diffuse = (real)tex->finish.diffuse;
    m->brilliance = (real)tex->finish.brilliance;
    m->specular = (real)tex->finish.specular;
    m->roughness = (real)tex->finish.roughness;
    m->phong = (real)tex->finish.phong;
    m->phong_size = (real)tex->finish.phong_size;
    m->metallic = (real)tex->finish.metallic;
    m->crand = (real)tex->finish.crand;
    m->irid = (real)tex->finish.irid;
    m->irid_thickness = (real)tex->finish.irid_thickness;
    m->irid_turbulence = (real)tex->finish.irid_turbulence;
    const csg_finish *fin = &tex->finish;
    if (fin->reflection_variable) {
        m->reflection_variable = 1;
        m->reflection_fresnel = fin->reflection_fresnel;
        m->conserve_energy = fin->conserve_energy;
        for (int i = 0; i < 3; i++)
            m->reflection_min[i] = (real)fin->reflection_min[i];
        m->reflection_falloff = (real)fin->reflection_falloff;
        m->reflection_exponent = (real)fin->reflection_exponent;
        m->reflection_metallic = (real)fin->reflection_metallic;
    }
    m->ior = (real)ior;
    m->number_of_waves = fb->scene->globals.number_of_waves;
    if (tex->tmap_count > 0) {
        csg_pigment pattern = tex->pigment; /* the map's pattern: no colour map */
        pattern.map_count = 0;
        pattern.pmap_count = 0;
        if (!material_pattern(fb, &pattern, NULL, m))
            return false;
        if (!grow((void **)&fb->maps, &fb->map_cap, fb->map_count + tex->tmap_count,
                  sizeof(csg_map_color))) {
            fb->oom = true;
            return false;
        }
        m->tmap = 1;
        m->map_first = fb->map_count;
        m->map_count = tex->tmap_count;
        for (int i = 0; i < tex->tmap_count; i++) {
            csg_map_color *c = &fb->maps[fb->map_count++];
            memset(c, 0, sizeof *c);
            c->value = (real)tex->tmap[i].value;
        }
    } else if (!material_pattern(fb, &tex->pigment, NULL, m)) {
        return false;
    }
    if (tex->tmap_count > 0 || tex->under || tex->normal.on) {
        if (!grow((void **)&fb->tparts, &fb->tpart_cap, fb->tpart_count + 1,
                  sizeof(pending_texture))) {
            fb->oom = true;
            return false;
        }
        pending_texture *pt = &fb->tparts[fb->tpart_count++];
        pt->parent = (int)(m - fb->mats);
        pt->t = tex;
        pt->in = *in;
    }
    return true;
}

/* Whether the texture entry and interior of inh hold, byte for byte, those
 * of the last material built from a texture entry, which then serves
 * (the material is a function of the two: material_layer).  Sibling
 * objects written with the same pigment each have a texture entry of
 * their own (the parser's copy-on-write): a box minus 10^5 such spheres
 * made 10^5 equal materials, 59 MB of the blob (issue #39).  Equal bytes
 * are equal values; unequal ones (a -0, padding) only cost a material. */
static bool same_as_last_material(const flat_builder *fb, inherited inh, const csg_texture *tex,
                                  const csg_interior *in)
{
    return inh.texture >= 0 && fb->last_texture &&
           (tex == fb->last_texture || memcmp(tex, fb->last_texture, sizeof *tex) == 0) &&
           memcmp(in, &fb->last_interior, sizeof *in) == 0;
}

/* The material of inh's (texture, interior), interned (one per pair), or
 * when !intern a new one of its own (its key kept, for material_opaque,
 * but not in the hash table: never found for another primitive). */
static int material_make(flat_builder *fb, inherited inh, bool intern)
{
    uint64_t key = material_key(inh);
    if (!material_reserve(fb) ||
        !grow((void **)&fb->mats, &fb->mat_cap, fb->mat_count + 1, sizeof(csg_material)) ||
        !grow((void **)&fb->mat_keys, &fb->mat_key_cap, fb->mat_count + 1, sizeof(uint64_t))) {
        fb->oom = true;
        return 0;
    }
    size_t slot = intern ? material_find(fb, key) : 0;
    if (intern && fb->mat_slots[slot])
        return fb->mat_slots[slot] - 1;
    csg_texture plain; /* the default texture (no parts: never queued) */
    const csg_texture *tex;
    if (inh.texture >= 0) {
        tex = &fb->scene->textures[inh.texture];
    } else {
        csg_texture_default(&plain);
        tex = &plain;
    }
    csg_interior in = {1.0, 0, 0, {0, 0, 0}};
    if (inh.interior >= 0)
        in = fb->scene->interiors[inh.interior];
    if (intern && same_as_last_material(fb, inh, tex, &in))
        return fb->last_material;
    csg_material *m = &fb->mats[fb->mat_count];
    memset(m, 0, sizeof *m); /* pattern fields 0 for a plain pigment, and no stray
                                byte: the blob is hashed (host/output/journal.c) */
    if (!material_layer(fb, tex, &in, m))
        return 0;
    fb->mat_keys[fb->mat_count] = key;
    if (!intern)
        return fb->mat_count++;
    fb->mat_slots[slot] = fb->mat_count + 1;
    if (inh.texture >= 0) {
        fb->last_texture = tex;
        fb->last_interior = in;
        fb->last_material = fb->mat_count;
    }
    return fb->mat_count++;
}

/* The material of a primitive: its (texture, interior) pair's; with an
 * interior_texture, a material of its own (the pair's may serve primitives
 * without one) whose `inside` is the (interior texture, interior) pair's,
 * which shade.c uses where a ray meets the surface from inside. */
static int material_for(flat_builder *fb, inherited inh)
{
    if (inh.inside <= 0)
        return material_make(fb, inh, true);
    inherited in = inh;
    in.texture = inh.inside - 1;
    in.inside = 0;
    int inside = material_make(fb, in, true);
    if (fb->oom)
        return 0;
    int outer = material_make(fb, inh, false);
    if (fb->oom)
        return 0;
    fb->mats[outer].inside = inside + 1;
    return outer;
}

/* A new material at the end of the table (never a texture's key). */
static csg_material *material_append(flat_builder *fb)
{
    if (!grow((void **)&fb->mats, &fb->mat_cap, fb->mat_count + 1, sizeof(csg_material)) ||
        !grow((void **)&fb->mat_keys, &fb->mat_key_cap, fb->mat_count + 1, sizeof(uint64_t))) {
        fb->oom = true;
        return NULL;
    }
    csg_material *m = &fb->mats[fb->mat_count];
    memset(m, 0, sizeof *m);
    fb->mat_keys[fb->mat_count++] = UINT64_MAX;
    return m;
}

/* A normal { } as a material: its pattern's fields, and what perturbs. */
static bool material_normal(flat_builder *fb, const csg_normal *n, csg_material *m)
{
    csg_pigment pattern = n->pattern;
    pattern.pmap_count = 0;
    if (pattern.pattern == CSG_PATTERN_PLAIN) /* the normal-only kinds read no pattern */
        pattern.pattern = CSG_PATTERN_BOZO;
    if (pattern.map_count == 0) { /* the validator wants a map on a pattern */
        static const csg_map_entry gray[2] = {{0, {0, 0, 0, 0, 0}}, {1, {1, 1, 1, 0, 0}}};
        pattern.map = gray;
        pattern.map_count = 2;
    }
    if (!material_pattern(fb, &pattern, NULL, m))
        return false;
    m->normal_kind = n->kind;
    m->no_bump_scale = n->no_bump_scale;
    m->number_of_waves = fb->scene->globals.number_of_waves;
    m->bump_size = (real)n->amount;
    m->accuracy = (real)n->accuracy;
    return true;
}

#define CSG_MAX_TEXTURE_PARTS (1 << 20) /* materials of layers, normals and maps */

/* The parts of the textures queued by material_layer, after every
 * material that uses them (blob.c checks that each points forward): a
 * layer's normal, the layer under it, a texture_map's entries (each a
 * texture of its own, queued in turn).  False (d filled) past the limit. */
static bool add_texture_parts(flat_builder *fb)
{
    for (int i = 0; i < fb->tpart_count && !fb->oom; i++) {
        pending_texture pt = fb->tparts[i];
        if (fb->mat_count > CSG_MAX_TEXTURE_PARTS) {
            csg_error_plain(fb->diag, "textures hold more than %d layers, normals and "
                                      "texture_map entries in all", CSG_MAX_TEXTURE_PARTS);
            return false;
        }
        if (pt.t->normal.on && pt.t->tmap_count == 0) {
            csg_material *m = material_append(fb);
            if (!m || !material_normal(fb, &pt.t->normal, m))
                return true; /* out of memory: reported so */
            fb->mats[pt.parent].normal = fb->mat_count; /* index + 1 */
        }
        if (pt.t->under && pt.t->tmap_count == 0) {
            csg_material *m = material_append(fb);
            if (!m || !material_layer(fb, pt.t->under, &pt.in, m))
                return true;
            fb->mats[pt.parent].under = fb->mat_count;
        }
        if (pt.t->tmap_count > 0) {
            int first = fb->mat_count;
            for (int k = 0; k < pt.t->tmap_count; k++)
                if (!material_append(fb))
                    return true;
            fb->mats[pt.parent].sub_first = first;
            for (int k = 0; k < pt.t->tmap_count; k++)
                if (!material_layer(fb, &pt.t->tmap[k].texture, &pt.in, &fb->mats[first + k]))
                    return true;
        }
    }
    return true;
}

/* ---- one function a shape kind (CSG_OBJECT_KINDS) ----------------------------
 * Each checks its shape (false, with the error, when it is degenerate),
 * fills the primitive's kind and parameters (and its world -> local matrix
 * when the parameters cannot be kept in world space) and the shape's world
 * bounding box. */

static bool degenerate_piece(flat_builder *fb, const csg_object *o, int piece)
{
    csg_error(fb->diag, csg_piece_loc(o, piece),
              "degenerate shape: zero size, negative radius or zero normal");
    return false;
}

static bool degenerate(flat_builder *fb, const csg_object *o) { return degenerate_piece(fb, o, 0); }

static bool flatten_sphere(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                           int piece, csg_prim *p, dbox *box)
{
    (void)piece;
    double r = o->r0;
    if (!(r > 0))
        return degenerate(fb, o);
    double lo[3] = {o->a.x - r, o->a.y - r, o->a.z - r};
    double hi[3] = {o->a.x + r, o->a.y + r, o->a.z + r};
    p->kind = CSG_PRIM_SPHERE;
    if (is_translate_scale(&o->xform, true)) {
        dvec3 c = xf_point(&o->xform, o->a);
        double s = fabs(o->xform.m[0][0]);
        p->p[0] = (real)c.x;
        p->p[1] = (real)c.y;
        p->p[2] = (real)c.z;
        p->p[3] = (real)(r * s);
    } else {
        p->p[0] = (real)o->a.x;
        p->p[1] = (real)o->a.y;
        p->p[2] = (real)o->a.z;
        p->p[3] = (real)r;
        store_inverse(p, world_to_obj);
    }
    *box = box_of_corners(&o->xform, lo, hi);
    return true;
}

static bool flatten_box(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                        int piece, csg_prim *p, dbox *box)
{
    (void)piece;
    (void)fb;
    double lo[3] = {box_min(o->a.x, o->b.x), box_min(o->a.y, o->b.y), box_min(o->a.z, o->b.z)};
    double hi[3] = {box_max(o->a.x, o->b.x), box_max(o->a.y, o->b.y), box_max(o->a.z, o->b.z)};
    p->kind = CSG_PRIM_BOX;
    *box = box_of_corners(&o->xform, lo, hi);
    bool world = is_translate_scale(&o->xform, false);
    for (int i = 0; i < 3; i++) {
        p->p[i] = (real)(world ? box->lo[i] : lo[i]);
        p->p[3 + i] = (real)(world ? box->hi[i] : hi[i]);
        if (p->p[i] == p->p[3 + i]) /* zero thickness, in `real`: a sheet */
            p->kind = CSG_PRIM_FLAT_BOX;
    }
    if (!world)
        store_inverse(p, world_to_obj);
    return true;
}

/* A cone from base a (radius r0) to cap b (radius r1); a cylinder is one
 * with r0 == r1. */
static bool flatten_axial(flat_builder *fb, const csg_object *o, double r1,
                          const csg_xform *world_to_obj, csg_prim *p, dbox *box)
{
    double dx = o->b.x - o->a.x, dy = o->b.y - o->a.y, dz = o->b.z - o->a.z;
    if (!(dx * dx + dy * dy + dz * dz > 0) || o->r0 < 0 || r1 < 0 || !(o->r0 + r1 > 0))
        return degenerate(fb, o);
    csg_xform obj_to_local, world_to_local;
    double h;
    cone_frame(o->a, o->b, &obj_to_local, &h);
    csg_xform_then(world_to_obj, &obj_to_local, &world_to_local);
    p->kind = CSG_PRIM_CONE;
    p->p[0] = (real)o->r0;
    p->p[1] = (real)r1;
    p->p[2] = (real)h;
    store_inverse(p, &world_to_local);
    csg_xform local_to_world;
    csg_xform_invert(&world_to_local, &local_to_world);
    double rm = box_max(o->r0, r1);
    double lo[3] = {-rm, -rm, 0}, hi[3] = {rm, rm, h};
    *box = box_of_corners(&local_to_world, lo, hi);
    return true;
}

static bool flatten_cylinder(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                             int piece, csg_prim *p, dbox *box)
{
    (void)piece;
    return flatten_axial(fb, o, o->r0, world_to_obj, p, box);
}

static bool flatten_cone(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                         int piece, csg_prim *p, dbox *box)
{
    (void)piece;
    return flatten_axial(fb, o, o->r1, world_to_obj, p, box);
}

static bool flatten_plane(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                          int piece, csg_prim *p, dbox *box)
{
    (void)piece;
    double n = sqrt(o->a.x * o->a.x + o->a.y * o->a.y + o->a.z * o->a.z);
    if (!(n > 0))
        return degenerate(fb, o);
    p->kind = CSG_PRIM_PLANE;
    p->p[0] = (real)(o->a.x / n);
    p->p[1] = (real)(o->a.y / n);
    p->p[2] = (real)(o->a.z / n);
    p->p[3] = (real)o->r0;
    const double(*m)[4] = o->xform.m;
    bool identity = is_translate_scale(&o->xform, false) && m[0][0] == 1 && m[1][1] == 1 &&
                    m[2][2] == 1 && m[0][3] == 0 && m[1][3] == 0 && m[2][3] == 0;
    if (!identity)
        store_inverse(p, world_to_obj);
    *box = box_infinite();
    return true;
}

/* A torus: piece 0 and piece 1, the first and the second interval of a
 * line inside it (flat.h), in the object's own frame. */
static bool flatten_torus(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                          int piece, csg_prim *p, dbox *box)
{
    if (!(o->r0 > 0) || !(o->r1 > 0))
        return degenerate(fb, o);
    p->kind = CSG_PRIM_TORUS;
    p->p[0] = (real)o->r0;
    p->p[1] = (real)o->r1;
    p->p[2] = (real)piece;
    store_inverse(p, world_to_obj);
    double s = o->r0 + o->r1;
    double lo[3] = {-s, -o->r1, -s}, hi[3] = {s, o->r1, s};
    *box = box_of_corners(&o->xform, lo, hi);
    return true;
}

/* A quadric, transformed into world space: with W the world -> object map
 * in homogeneous form and Q the symmetric matrix of the quadric, the
 * world quadric is W^T Q W (POV-Ray's Transform_Quadric). */
static bool flatten_quadric(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                            int piece, csg_prim *p, dbox *box)
{
    (void)fb;
    const double *c = o->coef;
    double q[4][4] = {{c[0], c[3] / 2, c[4] / 2, c[6] / 2},
                      {c[3] / 2, c[1], c[5] / 2, c[7] / 2},
                      {c[4] / 2, c[5] / 2, c[2], c[8] / 2},
                      {c[6] / 2, c[7] / 2, c[8] / 2, c[9]}};
    double w[4][4] = {{0}}, qw[4][4], out[4][4];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            w[i][j] = world_to_obj->m[i][j];
    w[3][3] = 1;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            qw[i][j] = 0;
            for (int k = 0; k < 4; k++)
                qw[i][j] += q[i][k] * w[k][j];
        }
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            out[i][j] = 0;
            for (int k = 0; k < 4; k++)
                out[i][j] += w[k][i] * qw[k][j];
        }
    double world[10] = {out[0][0], out[1][1], out[2][2], 2 * out[0][1], 2 * out[0][2],
                        2 * out[1][2], 2 * out[0][3], 2 * out[1][3], 2 * out[2][3], out[3][3]};
    p->kind = CSG_PRIM_QUADRIC;
    for (int k = 0; k < 10; k++)
        p->p[k] = (real)world[k];
    p->p[10] = (real)piece;
    *box = box_infinite();
    return true;
}

/* A poly's coefficients in the table: once an object, its pieces sharing
 * them; the index, or -1 (out of memory, a table beyond int, or a
 * coefficient beyond the range of `real`: an error; --precision auto
 * takes double for such a poly, csg/precision.c). */
static int poly_coefs_index(flat_builder *fb, const csg_object *o)
{
    if (fb->coefs_of == o)
        return fb->coefs_at;
    int order = o->poly_order;
    int terms = (order + 1) * (order + 2) * (order + 3) / 6;
    for (int k = 0; k < terms; k++)
        if (!((real)fabs(o->poly_coef[k]) < CSG_R_INF)) {
            csg_error(fb->diag, o->loc,
                      "the poly's coefficient %d (%g) is beyond the range of single precision "
                      "(--precision double renders it)", k + 1, o->poly_coef[k]);
            return -1;
        }
    if (fb->coef_count > INT_MAX / 2 - terms ||
        !grow((void **)&fb->coefs, &fb->coef_cap, fb->coef_count + terms, sizeof(real))) {
        fb->oom = true;
        return -1;
    }
    for (int k = 0; k < terms; k++)
        fb->coefs[fb->coef_count + k] = (real)o->poly_coef[k];
    fb->coefs_of = o;
    fb->coefs_at = fb->coef_count;
    fb->coef_count += terms;
    return fb->coefs_at;
}

/* A poly (quartic, cubic): piece k of order / 2 + 1, the k-th interval of
 * the line where it is negative (flat.h), in its own frame; unbounded, as
 * in POV-Ray (its bounding box is infinite: Poly::Compute_BBox).  p[2]
 * and p[3] hold the coefficients' index in the table here; write_blob
 * turns it into the offset from the primitive (poly_offsets). */
static bool flatten_poly(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                         int piece, csg_prim *p, dbox *box)
{
    int at = poly_coefs_index(fb, o);
    if (at < 0)
        return false;
    p->kind = CSG_PRIM_POLY;
    p->p[0] = (real)o->poly_order;
    p->p[1] = (real)piece;
    p->p[2] = (real)(at / CSG_POLY_OFFSET_UNIT);
    p->p[3] = (real)(at % CSG_POLY_OFFSET_UNIT);
    store_inverse(p, world_to_obj);
    *box = box_infinite();
    return true;
}

/* ---- surfaces: triangles in world space ------------------------------------ */

static dvec3 xf_normal(const csg_xform *world_to_obj, dvec3 n)
{
    const double(*m)[4] = world_to_obj->m; /* the inverse transpose */
    dvec3 w = {m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z,
               m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
               m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
    double l = sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
    return l > 0 ? (dvec3){w.x / l, w.y / l, w.z / l} : w;
}

/* The triangle v[a], v[b], v[c] of o, with the normals n[a], n[b], n[c]
 * when n is given and they are not all zero (a smooth triangle). */
static bool triangle_prim(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                          const dvec3 *v, const dvec3 *n, const int idx[3], csg_prim *p,
                          dbox *box)
{
    dvec3 w[3];
    for (int k = 0; k < 3; k++)
        w[k] = xf_point(&o->xform, v[idx[k]]);
    dvec3 e1 = {w[1].x - w[0].x, w[1].y - w[0].y, w[1].z - w[0].z};
    dvec3 e2 = {w[2].x - w[0].x, w[2].y - w[0].y, w[2].z - w[0].z};
    dvec3 ng = {e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x};
    if (!(ng.x * ng.x + ng.y * ng.y + ng.z * ng.z > 0) && o->kind != CSG_OBJ_POLYGON)
        return degenerate_piece(fb, o, o->kind == CSG_OBJ_MESH ? idx[0] / 3 : 0);
    bool smooth = false;
    for (int k = 0; n && k < 3; k++)
        smooth = smooth || n[idx[k]].x != 0 || n[idx[k]].y != 0 || n[idx[k]].z != 0;
    p->kind = smooth ? CSG_PRIM_SMOOTH_TRIANGLE : CSG_PRIM_TRIANGLE;
    for (int i = 0; i < 3; i++) {
        box->lo[i] = INFINITY;
        box->hi[i] = -INFINITY;
    }
    for (int k = 0; k < 3; k++) {
        store3(p->p + 3 * k, w[k]);
        if (smooth)
            store3(p->p + 9 + 3 * k, xf_normal(world_to_obj, n[idx[k]]));
        double c[3] = {w[k].x, w[k].y, w[k].z};
        for (int i = 0; i < 3; i++) {
            box->lo[i] = box_min(box->lo[i], c[i]);
            box->hi[i] = box_max(box->hi[i], c[i]);
        }
    }
    if (o->one_sided)
        p->flags |= CSG_PF_ONE_SIDED;
    return true;
}

static bool flatten_triangle(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                             int piece, csg_prim *p, dbox *box)
{
    static const int idx[3] = {0, 1, 2};
    (void)piece;
    return triangle_prim(fb, o, world_to_obj, o->verts, NULL, idx, p, box);
}

static bool flatten_smooth_triangle(flat_builder *fb, const csg_object *o,
                                    const csg_xform *world_to_obj, int piece, csg_prim *p,
                                    dbox *box)
{
    static const int idx[3] = {0, 1, 2};
    (void)piece;
    return triangle_prim(fb, o, world_to_obj, o->verts, o->normals, idx, p, box);
}

/* The split of polygon o into split[] (kept for its next piece). */
static bool split_polygon(flat_builder *fb, const csg_object *o)
{
    if (fb->split_of == o)
        return true;
    fb->split_of = NULL;
    if (!grow((void **)&fb->split, &fb->split_cap, 3 * o->vert_count, sizeof(int))) {
        fb->oom = true;
        return false;
    }
    fb->split_count = csg_polygon_triangulate(o->verts, o->vert_count, fb->split);
    if (fb->split_count <= 0) {
        csg_error(fb->diag, o->loc, "degenerate polygon: its vertices enclose no area");
        return false;
    }
    fb->split_of = o;
    return true;
}

static bool flatten_polygon(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                            int piece, csg_prim *p, dbox *box)
{
    if (!split_polygon(fb, o))
        return false;
    return triangle_prim(fb, o, world_to_obj, o->verts, NULL, fb->split + 3 * piece, p, box);
}

static bool flatten_mesh(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                         int piece, csg_prim *p, dbox *box)
{
    int idx[3] = {3 * piece, 3 * piece + 1, 3 * piece + 2};
    return triangle_prim(fb, o, world_to_obj, o->verts, o->normals, idx, p, box);
}

/* The pieces of prism o into traps[] (kept for its next piece). */
static bool split_prism(flat_builder *fb, const csg_object *o)
{
    if (fb->traps_of == o)
        return true;
    fb->traps_of = NULL;
    free(fb->traps);
    fb->traps = NULL;
    if (o->vert_count > CSG_EXTRUDE_MAX_EDGES) {
        csg_error(fb->diag, o->loc, "prism outline too detailed: %d edges (limit %d)",
                  o->vert_count, CSG_EXTRUDE_MAX_EDGES);
        return false;
    }
    fb->trap_count = csg_extrude_split(o->verts, o->contour_ends, o->contour_count, &fb->traps);
    if (fb->trap_count < 0) {
        fb->oom = true;
        return false;
    }
    if (fb->trap_count == 0 || !(o->r0 < o->r1)) {
        csg_error(fb->diag, o->loc, "degenerate prism: its outline encloses no area or its "
                                    "heights are equal");
        return false;
    }
    fb->traps_of = o;
    return true;
}

/* The x where side s = {n.x, n.y, c} (n.x != 0: no side is horizontal)
 * is at height y. */
static double side_x(const double s[3], double y) { return (s[2] - s[1] * y) / s[0]; }

/* Widens a local box by a margin: the box is tested in world space, the
 * piece in `real` in its own frame, and the rounding of the one must not
 * cut the other. */
static void pad_box(double lo[3], double hi[3])
{
    for (int i = 0; i < 3; i++) {
        double pad = 1e-6 * (1 + box_max(fabs(lo[i]), fabs(hi[i])));
        lo[i] -= pad;
        hi[i] += pad;
    }
}

/* A piece of a conic prism (flat.h's conic_trapezoid): each side
 * n . (x, y) >= c of the outline at height 1 becomes x >= a y + b z (or <=),
 * a = -n.y / n.x, b = c / n.x, the same for every piece on that edge; the
 * frame scaled by 1 / r1 so the top is z = 1. */
static bool conic_piece(const csg_object *o, const csg_trapezoid *t,
                        const csg_xform *world_to_obj, csg_prim *p, dbox *box)
{
    p->kind = CSG_PRIM_CONIC_TRAPEZOID;
    for (int k = 0; k < 2; k++) {
        p->p[2 * k] = (real)(-t->side[k][1] / t->side[k][0]);
        p->p[2 * k + 1] = (real)(t->side[k][2] / t->side[k][0]);
    }
    p->p[4] = (real)t->y_lo;
    p->p[5] = (real)t->y_hi;
    p->p[6] = (real)(o->r0 / o->r1);
    csg_xform to_unit, world_to_local;
    csg_xform_identity(&to_unit);
    for (int i = 0; i < 3; i++)
        to_unit.m[i][i] = 1 / o->r1;
    csg_xform_then(world_to_obj, &to_unit, &world_to_local);
    store_inverse(p, &world_to_local);
    double ys[2] = {t->y_lo, t->y_hi}, hs[2] = {o->r0, o->r1};
    double lo[3] = {INFINITY, INFINITY, o->r0}, hi[3] = {-INFINITY, -INFINITY, o->r1};
    for (int k = 0; k < 2; k++)
        for (int j = 0; j < 2; j++)
            for (int m = 0; m < 2; m++) {
                double x = side_x(t->side[k], ys[j]) * hs[m], y = ys[j] * hs[m];
                lo[0] = box_min(lo[0], x);
                hi[0] = box_max(hi[0], x);
                lo[1] = box_min(lo[1], y);
                hi[1] = box_max(hi[1], y);
            }
    pad_box(lo, hi);
    *box = box_of_corners(&o->xform, lo, hi);
    return true;
}

/* The sides of piece t of prism (or glyph) o that are chords of its
 * curve, as the curve of prim p (flat.h, csg_curve); none when both are
 * straight, or when the table is full (the chords' normals then: a scene
 * of millions of curved pieces). */
static bool attach_curve(flat_builder *fb, const csg_object *o, const csg_trapezoid *t,
                         csg_prim *p)
{
    if (!o->edge_curves)
        return true;
    const csg_outline_curve *e[2] = {&o->edge_curves[t->edge[0]], &o->edge_curves[t->edge[1]]};
    if (!(e[0]->u0 < e[0]->u1) && !(e[1]->u0 < e[1]->u1))
        return true;
    if (fb->curve_count >= CSG_CURVE_MAX)
        return true;
    if (!grow((void **)&fb->curves, &fb->curve_cap, fb->curve_count + 1, sizeof(csg_curve))) {
        fb->oom = true;
        return false;
    }
    csg_curve *c = &fb->curves[fb->curve_count];
    for (int k = 0; k < 2; k++) {
        csg_curve_side *side = &c->side[k];
        for (int i = 0; i < 2; i++) {
            side->a[i] = (real)e[k]->a[i];
            side->b[i] = (real)e[k]->b[i];
            side->c[i] = (real)e[k]->c[i];
            side->d[i] = (real)e[k]->d[i];
        }
        side->u0 = (real)e[k]->u0;
        side->u1 = (real)e[k]->u1;
    }
    p->flags |= (fb->curve_count + 1) << CSG_PF_CURVE_SHIFT;
    fb->curve_count++;
    return true;
}

/* Piece `piece` of a prism: its trapezoid in the local frame where the
 * extrusion runs from z = 0 to 1 (flat.h), and its curve. */
static bool flatten_prism(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                          int piece, csg_prim *p, dbox *box)
{
    if (!split_prism(fb, o))
        return false;
    const csg_trapezoid *t = &fb->traps[piece];
    if (!attach_curve(fb, o, t, p))
        return false;
    if (o->conic)
        return conic_piece(o, t, world_to_obj, p, box);
    p->kind = CSG_PRIM_TRAPEZOID;
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 3; i++)
            p->p[3 * k + i] = (real)t->side[k][i];
    p->p[6] = (real)t->y_lo;
    p->p[7] = (real)t->y_hi;
    double h = o->r1 - o->r0;
    csg_xform to_unit, world_to_local;
    csg_xform_identity(&to_unit);
    to_unit.m[2][2] = 1 / h;
    to_unit.m[2][3] = -o->r0 / h;
    csg_xform_then(world_to_obj, &to_unit, &world_to_local);
    store_inverse(p, &world_to_local);
    double xs[4] = {side_x(t->side[0], t->y_lo), side_x(t->side[0], t->y_hi),
                    side_x(t->side[1], t->y_lo), side_x(t->side[1], t->y_hi)};
    double lo[3] = {xs[0], t->y_lo, o->r0}, hi[3] = {xs[0], t->y_hi, o->r1};
    for (int i = 1; i < 4; i++) {
        lo[0] = box_min(lo[0], xs[i]);
        hi[0] = box_max(hi[0], xs[i]);
    }
    pad_box(lo, hi);
    *box = box_of_corners(&o->xform, lo, hi);
    return true;
}

/* The primitives shape o becomes: several for a polygon (its triangles)
 * or a mesh, else 1; 0 with the error when it cannot be split. */
static int shape_pieces(flat_builder *fb, const csg_object *o)
{
    if (o->kind == CSG_OBJ_MESH)
        return o->vert_count / 3;
    if (o->kind == CSG_OBJ_POLYGON)
        return split_polygon(fb, o) ? fb->split_count : 0;
    if (o->kind == CSG_OBJ_PRISM)
        return split_prism(fb, o) ? fb->trap_count : 0;
    if (o->kind == CSG_OBJ_TORUS || o->kind == CSG_OBJ_QUADRIC)
        return 2;
    if (o->kind == CSG_OBJ_POLY)
        return o->poly_order / 2 + 1;
    return 1;
}

/* The shape's primitive (piece `piece` of it), through the function of
 * its kind. */
static bool flatten_shape(flat_builder *fb, const csg_object *o, const csg_xform *world_to_obj,
                          int piece, csg_prim *p, dbox *box)
{
    switch (o->kind) {
#define FLATTEN_SHAPE(ID, name)                                                                    \
    case CSG_OBJ_##ID:                                                                             \
        return flatten_##name(fb, o, world_to_obj, piece, p, box);
        CSG_OBJECT_KINDS(FLATTEN_SHAPE, CSG_KIND_NONE)
    default:
        csg_error(fb->diag, o->loc, "internal error: %s is not a shape",
                  csg_object_kind_name(o->kind) ? csg_object_kind_name(o->kind) : "?");
        return false;
    }
}

/* Appends the primitive of leaf `o`; returns its index (-1 on failure)
 * and its world bounding box (before complement). */
static int add_prim(flat_builder *fb, const csg_object *o, int piece, inherited inh, bool invert,
                    int root, dbox *box)
{
    if (fb->prim_count >= CSG_MAX_PRIMS) {
        csg_error(fb->diag, csg_piece_loc(o, piece), "too many primitives (limit %d)",
                  CSG_MAX_PRIMS);
        return -1;
    }
    if (!grow((void **)&fb->prims, &fb->prim_cap, fb->prim_count + 1, sizeof(csg_prim)) ||
        !grow((void **)&fb->prim_boxes, &fb->prim_box_cap, fb->prim_count + 1, sizeof(dbox))) {
        fb->oom = true;
        return -1;
    }
    csg_prim *p = &fb->prims[fb->prim_count];
    memset(p, 0, sizeof *p);
    csg_xform world_to_obj;
    csg_xform_identity(&world_to_obj); /* defined even when not invertible */
    bool invertible = csg_xform_invert(&o->xform, &world_to_obj);
    if (!flatten_shape(fb, o, &world_to_obj, piece, p, box))
        return -1;
    if (!csg_xform_finite(&o->xform)) {
        csg_error(fb->diag, o->loc,
                  "the object's transformation overflows: its combined scale or translation "
                  "is beyond the range of numbers");
        return -1;
    }
    if (!invertible) {
        csg_error(fb->diag, o->loc, "the object's transformation is singular (a zero scale?)");
        return -1;
    }
    p->material = material_for(fb, inh);
    p->root = root;
    p->flags |= (invert ? CSG_PF_INVERT : 0) | (inh.no_shadow ? CSG_PF_NO_SHADOW : 0) |
                (o->open ? CSG_PF_OPEN : 0) | (inh.hollow == 1 ? CSG_PF_HOLLOW : 0) |
                (inh.clip ? CSG_PF_CLIP : 0) | (inh.bound ? CSG_PF_BOUND : 0);
    fb->prim_boxes[fb->prim_count] = *box;
    if (invert)
        *box = box_infinite();
    return fb->prim_count++;
}

/* ---- CSG programs --------------------------------------------------------------- */

static bool is_leaf(const csg_object *o) { return csg_object_is_leaf(o->kind); }

static inherited inherit(inherited inh, const csg_object *o)
{
    if (o->texture >= 0)
        inh.texture = o->texture;
    if (o->interior >= 0)
        inh.interior = o->interior;
    if (o->interior_texture > 0)
        inh.inside = o->interior_texture;
    inh.no_shadow = inh.no_shadow || o->no_shadow;
    if (o->hollow)
        inh.hollow = o->hollow;
    return inh;
}

/* A surface that may become several primitives (a union of them). */
static bool is_multi_piece(const csg_object *o)
{
    return ((o->kind == CSG_OBJ_POLYGON || o->kind == CSG_OBJ_MESH) && o->vert_count > 3) ||
           o->kind == CSG_OBJ_TORUS || o->kind == CSG_OBJ_QUADRIC || o->kind == CSG_OBJ_POLY;
}

/* A solid made of pieces (each an interval of the line inside it,
 * flat.h): one root always, never a piece alone. */
static bool is_solid_of_pieces(const csg_object *o)
{
    return o->kind == CSG_OBJ_TORUS || o->kind == CSG_OBJ_QUADRIC || o->kind == CSG_OBJ_POLY;
}

/* A solid made of several pieces (a union of them, which must stay one
 * root: where two pieces touch, the union has no surface). */
static bool is_multi_solid(const csg_object *o) { return o->kind == CSG_OBJ_PRISM; }

static int lists_needed_body(const csg_object *o);

/* A bounded_by that gates o (CSG_OP_BOUND): one of its own, not the clips
 * (linked, the clip alone is exact: a visible point of o lies in the
 * clip, so the ray meets the clip), and not removed by POV-Ray. */
static bool has_gate(const flat_builder *fb, const csg_object *o)
{
    return o->bound_count > 0 && !o->bound_is_clip && o != fb->bound_removed;
}

/* Interval lists the subtree needs at once (its Ershov number): its body,
 * then each clip and each bound on top of the held result (emit_tree);
 * the bounds only when `gated`. */
static int lists_needed_mods(const csg_object *o, bool gated)
{
    int need = lists_needed_body(o);
    for (int i = 0; i < o->clip_count; i++) {
        int c = lists_needed_mods(o->clips[i], true) + 1;
        need = c > need ? c : need;
    }
    for (int i = 0; gated && !o->bound_is_clip && i < o->bound_count; i++) {
        int c = lists_needed_mods(o->bounds[i], true) + 1;
        need = c > need ? c : need;
    }
    return need;
}

static int lists_needed(const csg_object *o) { return lists_needed_mods(o, true); }

static int lists_needed_body(const csg_object *o)
{
    if (is_leaf(o) || o->child_count == 0)
        return is_multi_piece(o) || is_multi_solid(o) ? 2 : 1;
    int best = 0, second = 0;
    for (int i = 0; i < o->child_count; i++) {
        int n = lists_needed(o->children[i]);
        if (n > best) {
            second = best;
            best = n;
        } else if (n > second) {
            second = n;
        }
    }
    /* largest first, then every other operand on top of one held result */
    return o->child_count == 1 ? best : (best > second + 1 ? best : second + 1);
}

/* order[0..n) sorted by need[] decreasing, equal needs in their index
 * order: a stable sort, as qsort of (need, index) keys (a selection sort
 * was quadratic at 10^5 operands, issue #39).  False when out of memory. */
typedef struct {
    int need, index;
} need_key;

static int by_need(const void *a, const void *b)
{
    const need_key *x = a, *y = b;
    if (x->need != y->need)
        return x->need > y->need ? -1 : 1;
    return (x->index > y->index) - (x->index < y->index);
}

/* Whether need[0..n) is already in the order sort_by_need makes (then
 * the identity: the operands of a wide run, 10^5 leaves of need 1, skip
 * the sort). */
static bool needs_decreasing(const int *need, int n)
{
    for (int i = 1; i < n; i++)
        if (need[i] > need[i - 1])
            return false;
    return true;
}

static bool sort_by_need(int *order, const int *need, int n)
{
    if (n <= 0)
        return true;
    if (needs_decreasing(need, n)) {
        for (int i = 0; i < n; i++)
            order[i] = i;
        return true;
    }
    need_key *keys = malloc((size_t)n * sizeof *keys);
    if (!keys)
        return false;
    for (int i = 0; i < n; i++)
        keys[i] = (need_key){need[i], i};
    qsort(keys, (size_t)n, sizeof *keys, by_need);
    for (int i = 0; i < n; i++)
        order[i] = keys[i].index;
    free(keys);
    return true;
}

static bool emit(flat_builder *fb, int op, int prim)
{
    if (!grow((void **)&fb->nodes, &fb->node_cap, fb->node_count + 1, sizeof(csg_node))) {
        fb->oom = true;
        return false;
    }
    fb->nodes[fb->node_count].op = op;
    fb->nodes[fb->node_count].prim = prim;
    fb->node_count++;
    return true;
}

/* A shape's RPN: its primitive, or the union of its pieces (each one
 * complemented and intersected when `neg`, by De Morgan). */
static bool emit_leaf(flat_builder *fb, const csg_object *o, inherited inh, bool neg, int root,
                      dbox *box)
{
    int pieces = shape_pieces(fb, o);
    if (pieces <= 0)
        return false;
    for (int k = 0; k < pieces; k++) {
        dbox pb;
        int prim = add_prim(fb, o, k, inh, neg, root, &pb);
        if (prim < 0 || !emit(fb, CSG_OP_PRIM, prim))
            return false;
        *box = k == 0 ? pb : neg ? box_intersect(*box, pb) : box_union(*box, pb);
        if (k > 0 && !emit(fb, neg ? CSG_OP_INTERSECT : CSG_OP_UNION, -1))
            return false;
    }
    return true;
}

static bool emit_tree(flat_builder *fb, const csg_object *o, inherited inh, bool neg, int root,
                      dbox *box);

/* The RPN of o itself, its clips aside (complemented when `neg`); inh
 * already has o's own. */
static bool emit_body(flat_builder *fb, const csg_object *o, inherited inh, bool neg, int root,
                      dbox *box)
{
    neg = neg != o->inverse;
    if (is_leaf(o))
        return emit_leaf(fb, o, inh, neg, root, box);
    if (o->child_count == 0) {
        csg_error(fb->diag, o->loc, "a CSG object needs at least one operand");
        return false;
    }
    /* union/merge: U children; intersection: ∩; difference: c0 ∩ ¬c1 ∩ ...
     * A complement swaps the operator and complements every operand. */
    bool is_union = o->kind == CSG_OBJ_UNION || o->kind == CSG_OBJ_MERGE;
    int op = (is_union != neg) ? CSG_OP_UNION : CSG_OP_INTERSECT;
    /* operands, largest need first (a stable selection sort over indices) */
    int n = o->child_count;
    int *order = malloc((size_t)n * sizeof *order);
    int *need = malloc((size_t)n * sizeof *need);
    if (!order || !need) {
        free(order);
        free(need);
        fb->oom = true;
        return false;
    }
    for (int i = 0; i < n; i++) {
        order[i] = i;
        need[i] = lists_needed(o->children[i]);
    }
    if (!sort_by_need(order, need, n)) {
        free(order);
        free(need);
        fb->oom = true;
        return false;
    }
    bool ok = true;
    for (int k = 0; k < n && ok; k++) {
        int i = order[k];
        bool child_neg = neg != (o->kind == CSG_OBJ_DIFFERENCE && i > 0);
        dbox cb;
        ok = emit_tree(fb, o->children[i], inh, child_neg, root, &cb);
        if (!ok)
            break;
        if (k == 0)
            *box = cb;
        else if (op == CSG_OP_UNION)
            *box = box_union(*box, cb);
        else
            *box = box_intersect(*box, cb);
        if (k > 0)
            ok = emit(fb, op, -1);
    }
    free(order);
    free(need);
    return ok;
}

/* The n objects of a clip or bound list, each emitted with inh and folded
 * into the program by op; with narrow, the box narrowed to each one's (a
 * clip's: the object lies inside its clips). */
static bool emit_list(flat_builder *fb, csg_object *const *list, int n, inherited inh, int op,
                      int root, dbox *narrow)
{
    for (int i = 0; i < n; i++) {
        dbox b;
        if (!emit_tree(fb, list[i], inh, false, root, &b) || !emit(fb, op, -1))
            return false;
        if (narrow)
            *narrow = box_intersect(*narrow, b);
    }
    return true;
}

/* Emits the RPN of `o` (complemented when `neg`); returns false on error
 * and sets *box to the subtree's world bounding box.
 *
 * clipped_by, as POV-Ray 3.7 defines it: an intersection of the object
 * survives only where it is inside every clip (Point_In_Clip), and the
 * object's inside is its own inside and every clip's (Inside_Object,
 * which CSG parents use).  So the clipped object is the solid O ∩ C1 ∩
 * C2 ..., the clips' surfaces never being intersections: the ray passes
 * through them, and looks into an open object (a sphere clipped by a
 * plane shows its inside).  That is the interval intersection with the
 * clips' primitives flagged CSG_PF_CLIP: their boundaries carry no
 * surface (CSG_SURF_NONE, intersect.h), so no ray, looking or shadow,
 * ever stops on them, while the sets combine as any CSG.  A complement
 * (`inverse`, or being subtracted: POV-Ray's Invert, which flips the
 * object's INVERTED_FLAG and recursively its children's) complements the
 * object's own inside only, never a clip: Inside_Object tests the clips
 * as they are, so X = O' ∩ C1 ∩ C2 ... with O' = ¬O when `neg`, and the
 * clips are always intersected, uncomplemented. */
static bool emit_tree(flat_builder *fb, const csg_object *o, inherited inh, bool neg, int root,
                      dbox *box)
{
    inh = inherit(inh, o);
    if (!emit_body(fb, o, inh, neg, root, box))
        return false;
    inherited clip_inh = inh;
    clip_inh.clip = true;
    if (!emit_list(fb, o->clips, o->clip_count, clip_inh, CSG_OP_INTERSECT, root, box))
        return false;
    if (!has_gate(fb, o))
        return true;
    /* bounded_by: POV-Ray's Ray_In_Bound before the object's (or a CSG
     * child's) intersections, every bound to be met (CSG_OP_BOUND).  It
     * does not clip: a bound smaller than the object hides the object
     * from the rays that miss the bound, and only them.  The root's box
     * stays the object's (a bound's box could cull a visible hit). */
    inherited bound_inh = inh; /* (its surfaces tell csg_spans_met it is met) */
    bound_inh.bound = true;
    return emit_list(fb, o->bounds, o->bound_count, bound_inh, CSG_OP_BOUND, root, NULL);
}

/* A pigment no point of which lets light through. */
static bool pigment_opaque(const csg_pigment *pig)
{
    int left = CLEAR_VISIT_BUDGET;
    if (pig->pattern == CSG_PATTERN_PLAIN)
        return !(pig->rgbft[3] > 0 || pig->rgbft[4] > 0);
    return !pigment_clear(pig, &left);
}

/* A texture no point of which lets light through: a layer that does not,
 * or a texture_map whose every entry does not (too deep a nesting counts
 * as clear: only slower). */
static bool texture_opaque(const csg_texture *t, int depth)
{
    if (depth > 16)
        return false;
    if (t->tmap_count > 0) {
        for (int i = 0; i < t->tmap_count; i++)
            if (!texture_opaque(&t->tmap[i].texture, depth + 1))
                return false;
        return true;
    }
    for (; t; t = t->under)
        if (pigment_opaque(&t->pigment))
            return true;
    return false;
}

/* No point of the material lets light through: neither its pigment nor,
 * when patterned, any colour of its map (a texture's material: its
 * layers and texture_map entries, read from the scene's texture). */
static bool material_opaque(const flat_builder *fb, const csg_material *m)
{
    if (m->inside > 0 && !material_opaque(fb, &fb->mats[m->inside - 1])) /* (its inside has none) */
        return false;
    uint64_t key = fb->mat_keys[m - fb->mats];
    int texture = key == UINT64_MAX ? -1 : (int)(key >> 32) - 1;
    if (texture >= 0) {
        const csg_texture *t = &fb->scene->textures[texture];
        if (t->tmap_count > 0 || t->under)
            return texture_opaque(t, 0);
    }
    if (m->pattern == CSG_PATTERN_PLAIN)
        return m->filter <= 0 && m->transmit <= 0;
    for (int k = 0; k < m->map_count; k++) {
        const csg_map_color *c = &fb->maps[m->map_first + k];
        if (c->rgbft[3] > 0 || c->rgbft[4] > 0)
            return false;
    }
    return true;
}


/* ---- wide runs (flat.h, CSG_OP_WIDE) ------------------------------------------- */

static bool box_bounded(const dbox *b);
static void store_bvh_nodes(const bvh_build_node *built, int count, int first_node,
                            int first_item, csg_bvh_node *out);

/* Node k folds a primitive into the list below it that is OP's identity
 * when the ray misses the primitive's box: (PRIM p, OP) with p
 * complemented under INTERSECT, plain under UNION, and bounded. */
static int wide_pair_op(const flat_builder *fb, const csg_node *nodes, int k, int end)
{
    if (k + 1 >= end || nodes[k].op != CSG_OP_PRIM)
        return -1;
    int op = nodes[k + 1].op, prim = nodes[k].prim;
    bool inverted = (fb->prims[prim].flags & CSG_PF_INVERT) != 0;
    if (fb->prims[prim].flags & CSG_PF_BOUND) /* (met beyond tmax too: no box cull) */
        return -1;
    if (!(op == CSG_OP_INTERSECT && inverted) && !(op == CSG_OP_UNION && !inverted))
        return -1;
    return box_bounded(&fb->prim_boxes[prim]) ? op : -1;
}

/* The hierarchy of the run of `pairs` pairs from node `start`, appended to
 * fb->wide, fb->wide_bvh and fb->wide_items. */
static bool add_wide(flat_builder *fb, int start, int pairs)
{
    dbox *boxes = malloc((size_t)pairs * sizeof *boxes);
    int *all = malloc((size_t)pairs * sizeof *all);
    int *order = malloc((size_t)pairs * sizeof *order);
    bvh_build_node *built = NULL;
    int count = 0;
    bool ok = boxes && all && order;
    for (int j = 0; ok && j < pairs; j++) {
        boxes[j] = fb->prim_boxes[fb->nodes[start + 2 * j].prim];
        all[j] = j;
    }
    /* (threads only for a big run: one per run would cost more than it saves) */
    ok = ok && bvh_build(boxes, all, pairs, order, 0, pairs >= 4096 ? 0 : 1, &built, &count);
    ok = ok &&
         grow((void **)&fb->wide, &fb->wide_cap, fb->wide_count + 1, sizeof(csg_wide)) &&
         grow((void **)&fb->wide_bvh, &fb->wide_bvh_cap, fb->wide_bvh_count + count,
              sizeof(csg_bvh_node)) &&
         grow((void **)&fb->wide_items, &fb->wide_item_cap, fb->wide_item_count + pairs,
              sizeof(csg_i32));
    if (ok) {
        csg_wide *w = &fb->wide[fb->wide_count++];
        w->pair_count = pairs;
        w->bvh_first = fb->wide_bvh_count;
        w->bvh_count = count;
        w->item_first = fb->wide_item_count;
        store_bvh_nodes(built, count, w->bvh_first, w->item_first, fb->wide_bvh + w->bvh_first);
        for (int j = 0; j < pairs; j++)
            fb->wide_items[w->item_first + j] = order[j];
        fb->wide_bvh_count += count;
        fb->wide_item_count += pairs;
    }
    free(boxes);
    free(all);
    free(order);
    free(built);
    return ok;
}

/* The length in pairs of the run of like pairs from nodes[k] (0: none). */
static int wide_run_at(const flat_builder *fb, const csg_node *nodes, int k, int end)
{
    int op = wide_pair_op(fb, nodes, k, end), pairs = 0;
    while (op >= 0 && wide_pair_op(fb, nodes, k + 2 * pairs, end) == op)
        pairs++;
    return pairs;
}

/* Marks the wide runs of the program fb->nodes[first ..): a CSG_OP_WIDE
 * node before each run of at least CSG_WIDE_MIN pairs.  The hierarchies
 * are built first, from the program as it is, then the program is
 * rewritten with the marks. */
static bool mark_wide_runs(flat_builder *fb, int first)
{
    int end = fb->node_count, marks = 0, first_wide = fb->wide_count;
    for (int k = first; k < end;) {
        int pairs = wide_run_at(fb, fb->nodes, k, end);
        if (pairs >= CSG_WIDE_MIN) {
            if (!add_wide(fb, k, pairs))
                return false;
            marks++;
        }
        k += pairs > 0 ? 2 * pairs : 1;
    }
    if (marks == 0)
        return true;
    int n = end - first;
    csg_node *prog = malloc((size_t)n * sizeof *prog);
    if (!prog || !grow((void **)&fb->nodes, &fb->node_cap, end + marks, sizeof(csg_node))) {
        free(prog);
        return false;
    }
    memcpy(prog, fb->nodes + first, (size_t)n * sizeof *prog);
    int out = first, wide = first_wide;
    for (int k = 0; k < n;) {
        int pairs = 0;
        if (wide < fb->wide_count) /* (the first pass's runs, found again) */
            pairs = wide_run_at(fb, prog, k, n);
        if (pairs >= CSG_WIDE_MIN) {
            fb->nodes[out].op = CSG_OP_WIDE;
            fb->nodes[out++].prim = wide++;
        }
        int step = pairs > 0 ? 2 * pairs : 1;
        for (int i = 0; i < step; i++)
            fb->nodes[out++] = prog[k + i];
        k += step;
    }
    free(prog);
    fb->node_count = out;
    return true;
}

/* csg_root_flags of the root whose primitives are first_prim .. the last.
 * A one-sided surface is never opaque here: its hidden back still stops
 * light (a surface event, root_transmittance), which the first visible hit
 * does not see. */
static int root_shadow_flags(const flat_builder *fb, int first_prim)
{
    bool none = true, opaque = true;
    for (int i = first_prim; i < fb->prim_count; i++) {
        const csg_prim *p = &fb->prims[i];
        if (p->flags & (CSG_PF_CLIP | CSG_PF_BOUND)) /* (no surface: neither casts nor lets through) */
            continue;
        bool casts = !(p->flags & CSG_PF_NO_SHADOW);
        none = none && !casts;
        opaque = opaque && casts && !(p->flags & CSG_PF_ONE_SIDED) &&
                 material_opaque(fb, &fb->mats[p->material]);
    }
    return (none ? CSG_ROOT_NO_SHADOW : 0) | (opaque ? CSG_ROOT_OPAQUE : 0);
}

static double box_volume(dbox b)
{
    return (b.hi[0] - b.lo[0]) * (b.hi[1] - b.lo[1]) * (b.hi[2] - b.lo[2]);
}

/* POV-Ray gives an object the box of its bounds when that is smaller than
 * its own (the end of Parse_Object_Mods, "[DB 9/94]"), and keeps it when
 * Link_To_Frame then removes the bound itself (pov_removes_bound): a ray
 * meets such a top-level object only where it meets that box, at any
 * depth (Find_Intersection's Intersect_BBox).  So the removed bound still
 * gates, as its box: a world box primitive flagged CSG_PF_BOUND, under
 * CSG_OP_BOUND.  The bounds' box is that of their RPN, emitted and taken
 * back. */
static bool emit_box_gate(flat_builder *fb, const csg_object *o, inherited inh, int root,
                          dbox own)
{
    if (o != fb->bound_removed || !fb->bound_box_kept)
        return true;
    int nodes = fb->node_count, prims = fb->prim_count;
    inh.bound = true;
    dbox bounds = box_infinite();
    for (int i = 0; i < o->bound_count; i++) {
        dbox b;
        if (!emit_tree(fb, o->bounds[i], inh, false, root, &b))
            return false;
        bounds = box_intersect(bounds, b);
    }
    fb->node_count = nodes;
    fb->prim_count = prims;
    if (!(box_volume(bounds) < box_volume(own)) || !box_bounded(&bounds))
        return true;
    csg_object gate;
    memset(&gate, 0, sizeof gate);
    gate.kind = CSG_OBJ_BOX;
    gate.loc = o->bounds[0]->loc;
    gate.a = (dvec3){bounds.lo[0], bounds.lo[1], bounds.lo[2]};
    gate.b = (dvec3){bounds.hi[0], bounds.hi[1], bounds.hi[2]};
    csg_xform_identity(&gate.xform);
    gate.texture = -1;
    gate.interior = -1;
    dbox gb;
    int prim = add_prim(fb, &gate, 0, inh, false, root, &gb);
    return prim >= 0 && emit(fb, CSG_OP_PRIM, prim) && emit(fb, CSG_OP_BOUND, -1);
}

static bool add_root(flat_builder *fb, const csg_object *o, inherited inh)
{
    int depth = lists_needed_mods(o, has_gate(fb, o));
    if (o == fb->bound_removed && fb->bound_box_kept && depth < 2) /* (emit_box_gate's box) */
        depth = 2;
    for (int u = 0; u < fb->carried_count; u++)
        for (int i = 0; i < fb->carried[u]->clip_count; i++) {
            int c = lists_needed(fb->carried[u]->clips[i]) + 1;
            depth = c > depth ? c : depth;
        }
    if (depth > CSG_STACK_MAX) {
        csg_error(fb->diag, o->loc,
                  "CSG tree too complex: evaluating it needs %d interval lists at once (limit %d); "
                  "nest it less deeply or more evenly",
                  depth, CSG_STACK_MAX);
        return false;
    }
    if (!grow((void **)&fb->roots, &fb->root_cap, fb->root_count + 1, sizeof(csg_root)) ||
        !grow((void **)&fb->root_boxes, &fb->root_box_cap, fb->root_count + 1, sizeof(dbox))) {
        fb->oom = true;
        return false;
    }
    int root = fb->root_count;
    int first = fb->node_count, first_prim = fb->prim_count;
    dbox box;
    if (!emit_tree(fb, o, inh, false, root, &box))
        return false;
    inherited clip_inh = inh;
    clip_inh.clip = true;
    for (int u = 0; u < fb->carried_count; u++)
        if (!emit_list(fb, fb->carried[u]->clips, fb->carried[u]->clip_count, clip_inh,
                       CSG_OP_INTERSECT, root, &box))
            return false;
    if (!emit_box_gate(fb, o, inherit(inh, o), root, box))
        return false;
    if (!mark_wide_runs(fb, first)) {
        fb->oom = true;
        return false;
    }
    csg_root *r = &fb->roots[fb->root_count++];
    memset(r, 0, sizeof *r);
    r->first_node = first;
    r->node_count = fb->node_count - first;
    r->stack_depth = depth;
    r->flags = root_shadow_flags(fb, first_prim);
    box_store(box, r->lo, r->hi);
    fb->root_boxes[root] = box;
    return true;
}

/* A top-level polygon or mesh: one root a piece, like a union's children. */
static bool add_pieces(flat_builder *fb, const csg_object *o, inherited inh)
{
    int pieces = shape_pieces(fb, o);
    if (pieces <= 0)
        return false;
    inh = inherit(inh, o);
    for (int k = 0; k < pieces; k++) {
        if (!grow((void **)&fb->roots, &fb->root_cap, fb->root_count + 1, sizeof(csg_root)) ||
            !grow((void **)&fb->root_boxes, &fb->root_box_cap, fb->root_count + 1,
                  sizeof(dbox))) {
            fb->oom = true;
            return false;
        }
        int root = fb->root_count, first = fb->node_count;
        dbox box;
        int prim = add_prim(fb, o, k, inh, false, root, &box);
        if (prim < 0 || !emit(fb, CSG_OP_PRIM, prim))
            return false;
        csg_root *r = &fb->roots[fb->root_count++];
        memset(r, 0, sizeof *r);
        r->first_node = first;
        r->node_count = 1;
        r->stack_depth = 1;
        r->flags = root_shadow_flags(fb, prim); /* (as add_root's: a mesh's
                                                   opaque triangles stop shadow
                                                   rays at their first hit) */
        box_store(box, r->lo, r->hi);
        fb->root_boxes[root] = box;
    }
    return true;
}

/* POV-Ray's Link_To_Frame removes the bounded_by of a top-level object
 * (and of a split union's child) that is cheap to intersect ("Unnecessary
 * bounding object removed"): all but CSG, poly, text (here a union) and a
 * quadric whose box its clip did not shrink (Automatic_Bounds; here: a
 * clipped quadric loses its bound). */
static bool pov_removes_bound(const csg_object *o)
{
    if (o->bound_count == 0 || o->bound_is_clip)
        return false;
    switch (o->kind) {
    case CSG_OBJ_UNION: case CSG_OBJ_INTERSECTION: case CSG_OBJ_DIFFERENCE: case CSG_OBJ_MERGE:
    case CSG_OBJ_POLY: /* (poly, cubic, quartic: POV-Ray's Poly) */
        return false;
    case CSG_OBJ_QUADRIC:
        return o->clip_count > 0;
    default:
        return true;
    }
}

static bool is_identity(const csg_xform *x)
{
    csg_xform id;
    csg_xform_identity(&id);
    return memcmp(x, &id, sizeof id) == 0;
}

/* A union split into one root a child inside a clipped union: not
 * inverted, no bound of its own gating it. */
static bool splits_in_clip(const flat_builder *fb, const csg_object *o)
{
    return o->kind == CSG_OBJ_UNION && !o->inverse && !has_gate(fb, o) &&
           fb->carried_count < FLAT_CARRIED_MAX;
}

/* A clipped union (or a union inside one): POV-Ray links it whole
 * (split_unions is off), and its intersections are every child's that
 * lies inside the clips (CSG union's Intersect, then Point_In_Clip): a
 * child's surface inside another child shows, as in any union.  One
 * solid root, (A u B) n C, would hide those surfaces; a root a child,
 * A n C and B n C, shows them all.  The children keep their bounds
 * (POV-Ray removes none inside a linked union). */
static bool add_clipped_union(flat_builder *fb, const csg_object *o, inherited inh)
{
    inh = inherit(inh, o);
    bool pushed = o->clip_count > 0;
    if (pushed)
        fb->carried[fb->carried_count++] = o;
    bool ok = true;
    for (int i = 0; i < o->child_count && ok; i++) {
        const csg_object *child = o->children[i];
        fb->bound_removed = NULL;
        ok = splits_in_clip(fb, child) ? add_clipped_union(fb, child, inh)
                                       : add_root(fb, child, inh);
    }
    if (pushed)
        fb->carried_count--;
    return ok;
}

/* A top-level object, or the child of a union split at the top (POV-Ray's
 * Link_To_Frame); `moved`: a split union above it was transformed, which
 * recomputed the child's box from its shape (the bounds' box is gone). */
static bool add_top(flat_builder *fb, const csg_object *o, inherited inh, bool moved)
{
    fb->bound_removed = pov_removes_bound(o) ? o : NULL;
    fb->bound_box_kept = !moved;
    if (o->clip_count > 0 && splits_in_clip(fb, o))
        return add_clipped_union(fb, o, inh);
    /* one root: the clips cut all of it, a bound gates all of it (POV-Ray
       links a clipped or bounded union whole: split_unions is off) */
    if (o->clip_count > 0 || has_gate(fb, o) || (fb->bound_removed && !moved))
        return add_root(fb, o, inh);
    if (is_multi_piece(o) && !o->inverse && !is_solid_of_pieces(o))
        return add_pieces(fb, o, inh);
    if (o->kind == CSG_OBJ_UNION && !o->inverse) {
        inh = inherit(inh, o);
        moved = moved || !is_identity(&o->xform);
        for (int i = 0; i < o->child_count; i++)
            if (!add_top(fb, o->children[i], inh, moved))
                return false;
        return true;
    }
    return add_root(fb, o, inh);
}

/* ---- the BVH over bounded roots -------------------------------------------------- */

static bool box_bounded(const dbox *b)
{
    for (int i = 0; i < 3; i++)
        if (!isfinite(b->lo[i]) || !isfinite(b->hi[i]))
            return false;
    return true;
}

/* Copies the root programs and their primitives in the roots' order, so
 * that the roots of a BVH leaf, their nodes and their primitives lie side
 * by side in memory (a walk through a big scene touches them in that
 * order: +4 % primary rays at 10^5 spheres).  A root's own primitives keep
 * their order, that of its program; each primitive is the leaf of exactly
 * one node. */
static bool lay_out_programs(flat_builder *fb)
{
    csg_node *nodes = malloc((size_t)fb->node_count * sizeof *nodes);
    csg_prim *prims = malloc((size_t)fb->prim_count * sizeof *prims);
    if ((fb->node_count && !nodes) || (fb->prim_count && !prims)) {
        free(nodes);
        free(prims);
        return false;
    }
    int nn = 0, np = 0;
    for (int r = 0; r < fb->root_count; r++) {
        csg_root *rt = &fb->roots[r];
        int first = nn;
        for (int k = 0; k < rt->node_count; k++) {
            csg_node node = fb->nodes[rt->first_node + k];
            if (node.op == CSG_OP_PRIM) {
                prims[np] = fb->prims[node.prim];
                node.prim = np++;
            }
            nodes[nn++] = node;
        }
        rt->first_node = first;
    }
    free(fb->nodes);
    free(fb->prims);
    fb->nodes = nodes;
    fb->prims = prims;
    fb->node_cap = fb->node_count = nn; /* (every node is a root's: the same counts) */
    fb->prim_cap = fb->prim_count = np;
    return true;
}

/* Reorders the roots: unbounded ones first (source order), then the
 * bounded ones in the BVH's leaf order; nodes and primitives follow their
 * roots (lay_out_programs). */
/* fb->bvh from bvh_build's nodes, their boxes stored in `real`. */
/* bvh_build's nodes into out[], their boxes in `real`; a child index is
 * moved by first_node, a leaf's first item by first_item (a wide run's
 * tree lies inside a shared array). */
static void store_bvh_nodes(const bvh_build_node *built, int count, int first_node,
                            int first_item, csg_bvh_node *out)
{
    for (int i = 0; i < count; i++) {
        csg_bvh_node *node = &out[i];
        box_store(built[i].box, node->box, node->box + 3);
        node->first = built[i].first + (built[i].count < 0 ? first_node : first_item);
        node->count = built[i].count;
    }
}

static bool store_bvh(flat_builder *fb, const bvh_build_node *built, int count)
{
    fb->bvh = malloc((size_t)count * sizeof *fb->bvh);
    if (!fb->bvh)
        return false;
    fb->bvh_count = fb->bvh_cap = count;
    store_bvh_nodes(built, count, 0, 0, fb->bvh);
    return true;
}

static bool build_bvh(flat_builder *fb)
{
    int n = fb->root_count;
    if (n == 0)
        return true;
    int *order = malloc((size_t)n * sizeof *order);
    int *bounded = malloc((size_t)n * sizeof *bounded);
    int *new_index = NULL;
    csg_root *roots = NULL; /* (both taken after the build: its peak is the flattener's) */
    bool ok = order && bounded;
    int placed = 0, count = 0;
    for (int i = 0; ok && i < n; i++) {
        if (box_bounded(&fb->root_boxes[i]))
            bounded[count++] = i;
        else
            order[placed++] = i;
    }
    fb->linear_roots = placed;
    if (ok && count > 0) {
        bvh_build_node *built = NULL;
        int built_count = 0;
        ok = bvh_build(fb->root_boxes, bounded, count, order, placed, 0, &built, &built_count) &&
             store_bvh(fb, built, built_count);
        free(built);
    }
    free(bounded);
    free_array((void **)&fb->root_boxes); /* (the boxes' last use: memory for the
                                             layout's copies) */
    if (ok) {
        new_index = malloc((size_t)n * sizeof *new_index);
        roots = malloc((size_t)n * sizeof *roots);
        ok = new_index && roots;
    }
    if (ok) {
        for (int i = 0; i < n; i++) {
            roots[i] = fb->roots[order[i]];
            new_index[order[i]] = i;
        }
        free(fb->roots);
        fb->roots = roots;
        fb->root_cap = n;
        roots = NULL;
        for (int i = 0; i < fb->prim_count; i++)
            fb->prims[i].root = new_index[fb->prims[i].root];
        ok = lay_out_programs(fb);
    }
    free(order);
    free(new_index);
    free(roots);
    return ok;
}

/* ---- the blob -------------------------------------------------------------------- */

static uint64_t align64(uint64_t n) { return (n + 63u) & ~(uint64_t)63u; }

/* The offset of an array of `count` elements at *off; *off moves past it,
 * to the next 64-byte boundary. */
static uint64_t place(uint64_t *off, int count, size_t elem)
{
    uint64_t at = *off;
    *off = align64(at + (uint64_t)count * elem);
    return at;
}


/* The header: counts, and every array placed after it, 64-byte aligned. */
static csg_blob_header blob_header(const flat_builder *fb, const csg_flatten_opts *o)
{
    const csg_scene *s = fb->scene;
    csg_blob_header h;
    memset(&h, 0, sizeof h);
    h.magic = CSG_BLOB_MAGIC;
    h.real_size = (uint32_t)sizeof(real);
    h.width = o->width;
    h.height = o->height;
    h.max_depth = o->max_depth > 0 ? o->max_depth : s->globals.max_trace_level;
    if (h.max_depth < 1)
        h.max_depth = 1;
    h.spp = o->spp > 0 ? o->spp : 1;
    h.prim_count = fb->prim_count;
    h.node_count = fb->node_count;
    h.root_count = fb->root_count;
    h.linear_roots = fb->linear_roots;
    h.bvh_count = fb->bvh_count;
    h.wide_count = fb->wide_count;
    h.wide_bvh_count = fb->wide_bvh_count;
    h.wide_item_count = fb->wide_item_count;
    h.coef_count = fb->coef_count;
    h.curve_count = fb->curve_count;
    h.material_count = fb->mat_count;
    h.light_count = s->light_count;
    h.map_count = fb->map_count;
    h.sky_count = s->sky.count;
    for (int i = 0; i < fb->root_count; i++)
        if (fb->roots[i].stack_depth > h.max_stack)
            h.max_stack = fb->roots[i].stack_depth;
    uint64_t off = align64(sizeof h);
    h.off_prims = place(&off, fb->prim_count, sizeof(csg_prim));
    h.off_coefs = place(&off, fb->coef_count, sizeof(real)); /* right after (flat.h) */
    h.off_curves = place(&off, fb->curve_count, sizeof(csg_curve));
    h.off_nodes = place(&off, fb->node_count, sizeof(csg_node));
    h.off_roots = place(&off, fb->root_count, sizeof(csg_root));
    h.off_bvh = place(&off, fb->bvh_count, sizeof(csg_bvh_node));
    h.off_wide = place(&off, fb->wide_count, sizeof(csg_wide));
    h.off_wide_bvh = place(&off, fb->wide_bvh_count, sizeof(csg_bvh_node));
    h.off_wide_items = place(&off, fb->wide_item_count, sizeof(csg_i32));
    h.off_materials = place(&off, fb->mat_count, sizeof(csg_material));
    h.off_lights = place(&off, s->light_count, sizeof(csg_flat_light));
    h.off_camera = place(&off, 1, sizeof(csg_camera));
    h.off_shading = place(&off, 1, sizeof(csg_shading));
    h.off_maps = place(&off, fb->map_count, sizeof(csg_map_color));
    h.total_size = off;
    return h;
}

static void copy_array(unsigned char *b, uint64_t off, const void *src, int count, size_t elem)
{
    if (count > 0)
        memcpy(b + off, src, (size_t)count * elem);
}

/* Whether world point w is inside object o (POV-Ray's Inside: surfaces
 * have no inside; depth bounds the walk, as the parser bounds the tree). */
_Static_assert(CSG_FOG_MAX == CSG_FLAT_FOGS, "the fogs of a scene and of a blob");
_Static_assert(offsetof(csg_shading, fog_count) == 4 * sizeof(csg_i32),
               "csg_blob_fog_count reads it there in both precisions");

static bool object_contains(const csg_object *o, dvec3 w, int depth)
{
    if (depth > 200)
        return false;
    bool in = false;
    if (csg_object_is_leaf(o->kind)) {
        csg_xform inv;
        if (!csg_xform_invert(&o->xform, &inv))
            return false;
        dvec3 p = xf_point(&inv, w);
        switch (o->kind) {
        case CSG_OBJ_SPHERE: {
            dvec3 d = {p.x - o->a.x, p.y - o->a.y, p.z - o->a.z};
            in = d.x * d.x + d.y * d.y + d.z * d.z < o->r0 * o->r0;
            break;
        }
        case CSG_OBJ_BOX:
            in = p.x > fmin(o->a.x, o->b.x) && p.x < fmax(o->a.x, o->b.x) &&
                 p.y > fmin(o->a.y, o->b.y) && p.y < fmax(o->a.y, o->b.y) &&
                 p.z > fmin(o->a.z, o->b.z) && p.z < fmax(o->a.z, o->b.z);
            break;
        case CSG_OBJ_CYLINDER: case CSG_OBJ_CONE: {
            dvec3 ax = {o->b.x - o->a.x, o->b.y - o->a.y, o->b.z - o->a.z};
            dvec3 d = {p.x - o->a.x, p.y - o->a.y, p.z - o->a.z};
            double ll = ax.x * ax.x + ax.y * ax.y + ax.z * ax.z;
            double t = ll > 0 ? (d.x * ax.x + d.y * ax.y + d.z * ax.z) / ll : -1;
            double r = o->kind == CSG_OBJ_CYLINDER ? o->r0 : o->r0 + t * (o->r1 - o->r0);
            dvec3 q = {d.x - t * ax.x, d.y - t * ax.y, d.z - t * ax.z};
            in = t > 0 && t < 1 && q.x * q.x + q.y * q.y + q.z * q.z < r * r;
            break;
        }
        case CSG_OBJ_PLANE:
            in = o->a.x * p.x + o->a.y * p.y + o->a.z * p.z < o->r0;
            break;
        case CSG_OBJ_POLY: /* POV-Ray's Poly::Inside (its INSIDE_TOLERANCE) */
            in = csg_poly_value(o->poly_order, o->poly_coef, p, NULL) < 1e-4;
            break;
        case CSG_OBJ_QUADRIC: { /* POV-Ray's Quadric::Inside */
            const double *c = o->coef;
            in = p.x * (c[0] * p.x + c[3] * p.y + c[6]) + p.y * (c[1] * p.y + c[5] * p.z + c[7]) +
                     p.z * (c[2] * p.z + c[4] * p.x + c[8]) + c[9] <=
                 0;
            break;
        }
        case CSG_OBJ_TORUS: { /* POV-Ray's Torus::Inside */
            double ring = sqrt(p.x * p.x + p.z * p.z) - o->r0;
            in = p.y * p.y + ring * ring <= o->r1 * o->r1;
            break;
        }
        default: /* surfaces */
            return false;
        }
    } else if (o->kind == CSG_OBJ_INTERSECTION) {
        in = o->child_count > 0;
        for (int i = 0; i < o->child_count && in; i++)
            in = object_contains(o->children[i], w, depth + 1);
    } else if (o->kind == CSG_OBJ_DIFFERENCE) {
        in = o->child_count > 0 && object_contains(o->children[0], w, depth + 1);
        for (int i = 1; i < o->child_count && in; i++)
            in = !object_contains(o->children[i], w, depth + 1);
    } else { /* union, merge */
        for (int i = 0; i < o->child_count && !in; i++)
            in = object_contains(o->children[i], w, depth + 1);
    }
    in = o->inverse ? !in : in;
    for (int i = 0; i < o->clip_count && in; i++) /* (POV-Ray's Inside_Object) */
        in = object_contains(o->clips[i], w, depth + 1);
    return in;
}

/* The objects around the camera that are not hollow (POV-Ray's camera
 * ray starts inside their interiors: no fog until it leaves them). */
static int camera_solid(const csg_scene *s)
{
    if (s->fog_count == 0)
        return 0;
    csg_camera_src cam = s->camera;
    if (!s->has_camera)
        csg_camera_default(&cam);
    int n = 0;
    for (int i = 0; i < s->object_count; i++)
        if (s->objects[i]->hollow != 1 && object_contains(s->objects[i], cam.location, 0))
            n++;
    return n;
}

static dvec3 unit3(dvec3 v)
{
    double len = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    return len > 0 ? (dvec3){v.x / len, v.y / len, v.z / len} : v;
}

static double length3(dvec3 v)
{
    return sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
}

/* The blob's camera: POV-Ray's SetupCamera in double.  The cylinder and
 * ultra_wide_angle cameras take unit vectors and an aspect ratio from the
 * lengths (kx, ky: what camera_lanes.h multiplies x0 and y0 by); the
 * panoramic camera keeps its vectors, the spherical one turns direction
 * about its right and up. */
static void flat_camera(csg_camera *c, const csg_camera_src *cam, double hither)
{
    _Static_assert((int)CSG_PROJ_SPHERICAL == (int)CSG_CAMERA_SPHERICAL &&
                       (int)CSG_PROJ_ORTHOGRAPHIC == (int)CSG_CAMERA_ORTHOGRAPHIC &&
                       (int)CSG_PROJ_CYLINDER_1 == (int)CSG_CAMERA_CYLINDER_1,
                   "one order of the camera types");
    double rad = cam->angle * M_PI / 180.0, right = length3(cam->right), up = length3(cam->up);
    dvec3 d = cam->direction, r = cam->right, u = cam->up;
    double kx = 0, ky = 0;
    switch (cam->projection) {
    case CSG_PROJ_CYLINDER_1: case CSG_PROJ_CYLINDER_3: kx = rad; ky = up; break;
    case CSG_PROJ_CYLINDER_2: case CSG_PROJ_CYLINDER_4: kx = right; ky = rad; break;
    case CSG_PROJ_ULTRA_WIDE_ANGLE: kx = rad; ky = rad * (up / right); break;
    case CSG_PROJ_PANORAMIC: kx = M_PI; ky = M_PI; break;
    case CSG_PROJ_SPHERICAL:
        kx = cam->h_angle / 360 * (2 * M_PI);
        ky = cam->v_angle / 360 * (2 * M_PI);
        r = unit3(r); /* (the rotations' axes) */
        u = unit3(u);
        break;
    default: break;
    }
    if (cam->projection >= CSG_PROJ_CYLINDER_1 && cam->projection <= CSG_PROJ_ULTRA_WIDE_ANGLE) {
        d = unit3(d);
        r = unit3(r);
        u = unit3(u);
    }
    c->projection = cam->projection;
    store3(c->location, cam->location);
    store3(c->direction, d);
    store3(c->right, r);
    store3(c->up, u);
    c->hither = (real)hither;
    c->kx = (real)kx;
    c->ky = (real)ky;
}

/* Lights, shading values and the camera, from the scene into the blob. */
static void write_scene_values(const flat_builder *fb, const csg_flatten_opts *o,
                               const csg_blob_header *h, unsigned char *b)
{
    const csg_scene *s = fb->scene;
    csg_flat_light *lights = (csg_flat_light *)(b + h->off_lights);
    for (int i = 0; i < s->light_count; i++) {
        const csg_light *l = &s->lights[i];
        csg_flat_light *f = &lights[i];
        store3(f->position, l->position);
        for (int c = 0; c < 3; c++)
            f->color[c] = (real)l->color[c];
        f->shadowless = l->shadowless;
        f->kind = l->kind;
        f->parallel = l->parallel;
        f->area = l->area;
        f->size1 = l->size1;
        f->size2 = l->size2;
        f->adaptive = l->adaptive;
        f->jitter = l->jitter;
        f->circular = l->circular;
        f->orient = l->orient;
        f->media_attenuation = l->media_attenuation;
        /* POV-Ray's Direction: point_at - position, normalised when longer
         * than EPSILON (else as it is) */
        dvec3 d = {l->point_at.x - l->position.x, l->point_at.y - l->position.y,
                   l->point_at.z - l->position.z};
        double len = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        if (len > 1e-10)
            d = (dvec3){d.x / len, d.y / len, d.z / len};
        store3(f->direction, d);
        store3(f->point_at, l->point_at);
        f->tightness = (real)l->tightness;
        f->radius = (real)l->radius;
        f->falloff = (real)l->falloff;
        f->fade_distance = (real)l->fade_distance;
        f->fade_power = (real)l->fade_power;
        store3(f->axis1, l->axis1);
        store3(f->axis2, l->axis2);
    }
    csg_shading *sh = (csg_shading *)(b + h->off_shading);
    bool v37 = csg_version_v37(s);
    /* POV-Ray 3.7 (no alpha channel) composes the background over black:
     * its rgb times 1 - transmit; before 3.7 its filter and transmit are
     * dropped (parse.cpp, BACKGROUND) */
    double keep = v37 ? 1.0 - s->background[4] : 1.0;
    for (int c = 0; c < 3; c++) {
        sh->background[c] = (real)(keep == 1.0 ? s->background[c] : s->background[c] * keep);
        sh->ambient_light[c] = (real)s->globals.ambient_light[c];
    }
    sh->adc_bailout = (real)(o->bailout >= 0 ? o->bailout : s->globals.adc_bailout);
    sh->sky_first = fb->sky_first;
    sh->sky_v37 = v37;
    double gamma;
    sh->output = csg_output_gamma(s, &gamma);
    sh->output_gamma = (real)gamma;
    sh->fog_count = s->fog_count;
    for (int i = 0; i < s->fog_count; i++) {
        const csg_fog *f = &s->fogs[i];
        csg_flat_fog *g = &sh->fogs[i];
        g->kind = f->kind;
        g->turb_on = f->turb.on;
        g->octaves = f->turb.octaves;
        csg_pigment none;
        csg_pigment_default(&none);
        g->noise_gen = csg_noise_of(s, &none);
        g->distance = (real)f->distance;
        for (int k = 0; k < 5; k++)
            g->rgbft[k] = (real)f->rgbft[k];
        double len = sqrt(f->up.x * f->up.x + f->up.y * f->up.y + f->up.z * f->up.z);
        store3(g->up, (dvec3){f->up.x / len, f->up.y / len, f->up.z / len}); /* (parser: > 0) */
        g->offset = (real)f->offset;
        g->alt = (real)f->alt;
        store3(g->turbulence, f->turb.amount);
        g->omega = (real)f->turb.omega;
        g->lambda = (real)f->turb.lambda;
        g->turb_depth = (real)f->turb_depth;
    }
    sh->camera_solid = camera_solid(s);
    csg_pigment scene_noise;
    csg_pigment_default(&scene_noise); /* (its generator 0: the scene's) */
    sh->noise_gen = csg_noise_of(s, &scene_noise);
    store3(sh->irid_wavelength, (dvec3){s->globals.irid_wavelength[0],
                                        s->globals.irid_wavelength[1],
                                        s->globals.irid_wavelength[2]});
    long spp = o->spp > 0 ? o->spp : 1;
    sh->max_rays = o->max_rays > 0 ? o->max_rays
                                   : (csg_i32)(spp * CSG_RAYS_PER_SAMPLE); /* spp <= 1024 */
    store3(sh->sky_emission, (dvec3){s->sky.emission[0], s->sky.emission[1], s->sky.emission[2]});
    csg_camera_src cam = s->camera;
    if (!s->has_camera)
        csg_camera_default(&cam);
    flat_camera((csg_camera *)(b + h->off_camera), &cam, s->hither);
}

/* Each poly's coefficient index (flatten_poly) becomes the offset, in
 * reals, from its payload to its coefficients in the blob (flat.h). */
static void poly_offsets(const csg_blob_header *h, csg_prim *prims)
{
    for (int i = 0; i < h->prim_count; i++) {
        if (prims[i].kind != CSG_PRIM_POLY)
            continue;
        int64_t index = (int64_t)prims[i].p[2] * CSG_POLY_OFFSET_UNIT + (int64_t)prims[i].p[3];
        uint64_t payload = h->off_prims + (uint64_t)i * sizeof(csg_prim) + offsetof(csg_prim, p);
        int64_t rel = (int64_t)((h->off_coefs - payload) / sizeof(real)) + index;
        prims[i].p[2] = (real)(rel / CSG_POLY_OFFSET_UNIT);
        prims[i].p[3] = (real)(rel % CSG_POLY_OFFSET_UNIT);
    }
}

static bool write_blob(flat_builder *fb, const csg_flatten_opts *o, csg_blob *out)
{
    csg_blob_header h = blob_header(fb, o);
    unsigned char *b = calloc(1, (size_t)h.total_size);
    if (!b)
        return false;
    memcpy(b, &h, sizeof h);
    /* each big array freed once in the blob, whose pages are touched (made
     * resident) only as they are written: the two are never whole at once */
    copy_array(b, h.off_prims, fb->prims, fb->prim_count, sizeof(csg_prim));
    copy_array(b, h.off_coefs, fb->coefs, fb->coef_count, sizeof(real));
    copy_array(b, h.off_curves, fb->curves, fb->curve_count, sizeof(csg_curve));
    poly_offsets(&h, (csg_prim *)(void *)(b + h.off_prims));
    free_array((void **)&fb->prims);
    copy_array(b, h.off_nodes, fb->nodes, fb->node_count, sizeof(csg_node));
    free_array((void **)&fb->nodes);
    copy_array(b, h.off_roots, fb->roots, fb->root_count, sizeof(csg_root));
    free_array((void **)&fb->roots);
    copy_array(b, h.off_bvh, fb->bvh, fb->bvh_count, sizeof(csg_bvh_node));
    free_array((void **)&fb->bvh);
    copy_array(b, h.off_wide, fb->wide, fb->wide_count, sizeof(csg_wide));
    copy_array(b, h.off_wide_bvh, fb->wide_bvh, fb->wide_bvh_count, sizeof(csg_bvh_node));
    copy_array(b, h.off_wide_items, fb->wide_items, fb->wide_item_count, sizeof(csg_i32));
    copy_array(b, h.off_materials, fb->mats, fb->mat_count, sizeof(csg_material));
    copy_array(b, h.off_maps, fb->maps, fb->map_count, sizeof(csg_map_color));
    write_scene_values(fb, o, &h, b);
    csg_blob_header *hb = (csg_blob_header *)b;
    FLATTEN_SCAN(b, &hb->kinds, &hb->features);
    out->bytes = b;
    out->size = (size_t)h.total_size;
    return true;
}

bool FLATTEN_FN(const csg_scene *s, const csg_flatten_opts *o, csg_blob *out, csg_diag *d)
{
    flat_builder fb;
    memset(&fb, 0, sizeof fb);
    fb.scene = s;
    fb.diag = d;
    out->bytes = NULL;
    out->size = 0;
    bool ok = true;
    if (o->width <= 0 || o->height <= 0) {
        csg_error_plain(d, "image size must be positive, got %dx%d", o->width, o->height);
        ok = false;
    }
    inherited none = {-1, -1, false, 0, false, false, 0};
    for (int i = 0; ok && i < s->object_count; i++)
        ok = add_top(&fb, s->objects[i], none, false);
    if (ok && !fb.oom)
        add_sky(&fb);
    if (ok && !fb.oom)
        ok = add_texture_parts(&fb);
    if (ok && !fb.oom)
        ok = add_pigment_maps(&fb);
    if (ok && !fb.oom && !build_bvh(&fb))
        fb.oom = true;
    if (ok && !fb.oom && !write_blob(&fb, o, out))
        fb.oom = true;
    if (fb.oom) {
        csg_error_plain(d, "out of memory while flattening the scene");
        ok = false;
    }
    free(fb.prims);
    free(fb.nodes);
    free(fb.roots);
    free(fb.root_boxes);
    free(fb.bvh);
    free(fb.prim_boxes);
    free(fb.wide);
    free(fb.wide_bvh);
    free(fb.wide_items);
    free(fb.coefs);
    free(fb.curves);
    free(fb.mats);
    free(fb.mat_keys);
    free(fb.mat_slots);
    free(fb.split);
    free(fb.traps);
    free(fb.maps);
    free(fb.pending);
    free(fb.tparts);
    if (!ok)
        csg_blob_free(out);
    return ok;
}
