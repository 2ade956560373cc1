/*
 * blob.c — validation and release of a flat-scene blob (device/flat.h).
 * Compiled twice, like the flattener: csg_blob_valid_float and, with
 * -DCSG_DOUBLE, csg_blob_valid_double, so every array size below is the
 * sizeof of the very struct in that precision and no size is written down
 * anywhere else.  csg_blob_valid (float object only) reads the precision
 * from the header and calls the right one.
 *
 * A blob that arrives over MPI is checked here before a worker reads a
 * single array through it, and the OpenCL host checks the blob it uploads
 * the same way: magic, precision, counts, every array inside the bytes and
 * 64-byte aligned, every primitive kind known, every index in range (a
 * material's colour map included) and every root program well formed.
 */
#include "flatten.h"

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#ifdef CSG_DOUBLE
#define BLOB_VALID csg_blob_valid_double
#define BLOB_SCAN csg_blob_scan_features_double
#else
#define BLOB_VALID csg_blob_valid_float
#define BLOB_SCAN csg_blob_scan_features_float
#endif

bool BLOB_VALID(const void *bytes, size_t blob_size);

static const void *blob_at(const void *bytes, uint64_t off)
{
    return (const unsigned char *)bytes + off;
}

static bool array_fits(uint64_t off, int32_t count, uint64_t elem, uint64_t total)
{
    if (count < 0 || off > total || off % 64 != 0)
        return false;
    return (uint64_t)count <= (total - off) / elem;
}

/* A whole number in [0, hi] (real: refused before any conversion). */
static bool whole_in(real v, real hi)
{
    return v >= R(0.0) && v <= hi && v == (real)(int64_t)v;
}

/* A poly's order, piece and coefficients (flat.h): its offset, p[2] *
 * CSG_POLY_OFFSET_UNIT + p[3] reals on from its payload, lands on a real
 * of the coefficient table with all its terms inside. */
static bool poly_valid(const csg_blob_header *h, const csg_prim *p, int32_t i)
{
    if (!whole_in(p->p[0], (real)CSG_POLY_ORDER_MAX) || p->p[0] < R(2.0) ||
        !whole_in(p->p[1], (real)((int)p->p[0] / 2)) || !whole_in(p->p[2], R(16777215.0)) ||
        !whole_in(p->p[3], (real)(CSG_POLY_OFFSET_UNIT - 1)))
        return false;
    int64_t order = (int64_t)p->p[0];
    int64_t terms = (order + 1) * (order + 2) * (order + 3) / 6;
    uint64_t rel = (uint64_t)p->p[2] * CSG_POLY_OFFSET_UNIT + (uint64_t)p->p[3];
    uint64_t at = h->off_prims + (uint64_t)i * sizeof(csg_prim) + offsetof(csg_prim, p) +
                  rel * sizeof(real);
    if (at < h->off_coefs || (at - h->off_coefs) % sizeof(real) != 0)
        return false;
    uint64_t first = (at - h->off_coefs) / sizeof(real);
    return first <= (uint64_t)h->coef_count && (uint64_t)terms <= (uint64_t)h->coef_count - first;
}

/* A primitive's curve (flat.h: CSG_PRIM_CURVE): none, or one of the
 * table's, on a trapezoid piece. */
static bool curve_valid(const csg_blob_header *h, const csg_prim *p)
{
    if (p->flags < 0)
        return false;
    int32_t k = CSG_PRIM_CURVE(p);
    return k < 0 || (k < h->curve_count && (p->kind == CSG_PRIM_TRAPEZOID ||
                                            p->kind == CSG_PRIM_CONIC_TRAPEZOID));
}

static bool prims_valid(const csg_blob_header *h, const csg_prim *prims)
{
    for (int32_t i = 0; i < h->prim_count; i++)
        if (prims[i].kind < 0 || prims[i].kind >= CSG_PRIM_KIND_COUNT || prims[i].material < 0 ||
            prims[i].material >= h->material_count || prims[i].root < 0 ||
            prims[i].root >= h->root_count || !curve_valid(h, &prims[i]) ||
            (prims[i].kind == CSG_PRIM_POLY && !poly_valid(h, &prims[i], i)))
            return false;
    return true;
}

/* A pattern or a wave of the tables (device/patterns.h): workers/pigment.c
 * dispatches on them with no default case, so an id outside is refused
 * here, never evaluated as another one. */
static bool pattern_known(const csg_material *m)
{
    return m->pattern >= 0 && m->pattern < CSG_PATTERN_COUNT &&
           (m->pattern == CSG_PATTERN_PLAIN || (m->wave >= 0 && m->wave < CSG_WAVE_COUNT));
}

/* A patterned material's colour map lies inside the maps array, its
 * pigment map's materials inside the materials after it, its pattern and
 * wave known, its noise generator and octaves within their ranges. */
static bool materials_valid(const csg_blob_header *h, const csg_material *mats)
{
    for (int32_t i = 0; i < h->material_count; i++) {
        const csg_material *m = &mats[i];
        if (!pattern_known(m))
            return false;
        if (m->pattern != CSG_PATTERN_PLAIN &&
            (m->map_count < 1 || m->map_first < 0 || m->map_first > h->map_count - m->map_count))
            return false;
        if (m->sub_first < 0 || (m->sub_first > 0 && (m->sub_first <= i || /* acyclic */
                                 m->sub_first > h->material_count - m->map_count)))
            return false;
        /* layers, normals and texture maps: later materials (acyclic) */
        if (m->under < 0 || (m->under > 0 && (m->under - 1 <= i || m->under > h->material_count)) ||
            m->normal < 0 || (m->normal > 0 && (m->normal - 1 <= i || m->normal > h->material_count)))
            return false;
        if (m->tmap != 0 && (m->tmap != 1 || m->sub_first <= 0 || m->pattern == CSG_PATTERN_PLAIN))
            return false;
        if (m->inside < 0 || m->inside > h->material_count || /* one step: no chain */
            (m->inside > 0 && mats[m->inside - 1].inside != 0))
            return false;
        if (m->pattern == CSG_PATTERN_PIGMENT_PATTERN /* its pigment: a later material */
                ? m->pattern_pigment <= i || m->pattern_pigment >= h->material_count
                : m->pattern_pigment != 0)
            return false;
        if (m->normal_kind < 0 || m->normal_kind >= CSG_NORMAL_COUNT || m->number_of_waves < 0 ||
            ((m->pattern == CSG_PATTERN_RIPPLES || m->pattern == CSG_PATTERN_WAVES ||
              m->normal_kind == CSG_NORMAL_RIPPLES || m->normal_kind == CSG_NORMAL_WAVES) &&
             (m->number_of_waves < 1 || m->number_of_waves > CSG_MAX_WAVES)))
            return false;
        if (m->pattern != CSG_PATTERN_PLAIN && /* pigment.c's tables and loops */
            (m->noise_gen < 1 || m->noise_gen > 3 ||
             ((m->turb_on || m->pattern == CSG_PATTERN_AGATE) && (m->octaves < 1 || m->octaves > 10))))
            return false;
    }
    return true;
}

/* The run after the CSG_OP_WIDE node at nodes[k] (flat.h) lies inside its
 * program (end: one past it): pair_count like pairs whose leaves are
 * their operator's identity when missed. */
static bool wide_run_valid(const csg_blob_header *h, const csg_wide *wide, const csg_prim *prims,
                           const csg_node *nodes, int32_t k, int32_t end)
{
    if (nodes[k].prim < 0 || nodes[k].prim >= h->wide_count)
        return false;
    const csg_wide *w = &wide[nodes[k].prim];
    if (w->pair_count < 1 || w->pair_count > (end - k - 1) / 2)
        return false;
    int32_t op = nodes[k + 2].op;
    for (int32_t j = 0; j < w->pair_count; j++) {
        const csg_node *p = &nodes[k + 1 + 2 * j];
        if (p[0].op != CSG_OP_PRIM || p[1].op != op || p[0].prim < 0 || p[0].prim >= h->prim_count)
            return false;
        bool inverted = (prims[p[0].prim].flags & CSG_PF_INVERT) != 0;
        if (op == CSG_OP_INTERSECT ? !inverted : (op != CSG_OP_UNION || inverted))
            return false;
    }
    return true;
}

/* Every root program is RPN over known nodes within the stack limit, its
 * wide runs' marks before wide runs with something to fold into. */
static bool roots_valid(const csg_blob_header *h, const csg_root *roots, const csg_node *nodes,
                        const csg_wide *wide, const csg_prim *prims)
{
    for (int32_t r = 0; r < h->root_count; r++) {
        int32_t first = roots[r].first_node, count = roots[r].node_count, depth = 0;
        if (first < 0 || count < 1 || first > h->node_count - count)
            return false;
        for (int32_t k = first; k < first + count; k++) {
            if (nodes[k].op == CSG_OP_WIDE) {
                if (depth < 1 || !wide_run_valid(h, wide, prims, nodes, k, first + count))
                    return false;
            } else if (nodes[k].op == CSG_OP_PRIM) {
                if (nodes[k].prim < 0 || nodes[k].prim >= h->prim_count || ++depth > CSG_STACK_MAX)
                    return false;
            } else if ((nodes[k].op != CSG_OP_UNION && nodes[k].op != CSG_OP_INTERSECT &&
                        nodes[k].op != CSG_OP_BOUND) ||
                       --depth < 1) {
                return false;
            }
        }
        if (depth != 1)
            return false;
    }
    return true;
}

/* Leaves hold bounded roots only; the top pair exists, and children come
 * in pairs after their parent, so the tree has no cycle and a walk ends. */
static bool bvh_valid(const csg_blob_header *h, const csg_bvh_node *bvh)
{
    if (h->linear_roots < 0 || h->linear_roots > h->root_count || h->bvh_count < 0)
        return false;
    if (h->bvh_count == 0)
        return h->linear_roots == h->root_count;
    if (h->bvh_count < 2)
        return false;
    for (int32_t k = 0; k < h->bvh_count; k++) {
        if (bvh[k].count >= 0) {
            if (bvh[k].first < h->linear_roots || bvh[k].first > h->root_count - bvh[k].count)
                return false;
        } else if (bvh[k].count < -3 || bvh[k].first <= k || bvh[k].first >= h->bvh_count - 1) {
            return false;
        }
    }
    return true;
}

/* Each wide run's tree (flat.h, csg_wide): its nodes inside the shared
 * array, children after their parent within the run's nodes, leaves over
 * the run's items, the items pair indices of the run. */
static bool wide_valid(const csg_blob_header *h, const csg_wide *wide, const csg_bvh_node *bvh,
                       const int32_t *items)
{
    for (int32_t i = 0; i < h->wide_count; i++) {
        const csg_wide *w = &wide[i];
        int32_t b0 = w->bvh_first, b1 = w->bvh_first + w->bvh_count;
        int32_t i0 = w->item_first, i1 = w->item_first + w->pair_count;
        if (w->bvh_count < 2 || b0 < 0 || b0 > h->wide_bvh_count - w->bvh_count ||
            w->pair_count < 1 || i0 < 0 || i0 > h->wide_item_count - w->pair_count)
            return false;
        for (int32_t k = b0; k < b1; k++) {
            if (bvh[k].count >= 0) {
                if (bvh[k].first < i0 || bvh[k].first > i1 - bvh[k].count)
                    return false;
            } else if (bvh[k].count < -3 || bvh[k].first <= k || bvh[k].first >= b1 - 1) {
                return false;
            }
        }
        for (int32_t k = i0; k < i1; k++)
            if (items[k] < 0 || items[k] >= w->pair_count)
                return false;
    }
    return true;
}

/* ---- the feature set (flat.h, enum csg_feature) ---------------------------- */

/* Lets light through: its pigment or any colour of its map. */
static bool pigment_transparent(const csg_material *m, const csg_map_color *maps)
{
    if (m->pattern == CSG_PATTERN_PLAIN)
        return m->filter > 0 || m->transmit > 0;
    for (int32_t k = 0; k < m->map_count; k++)
        if (maps[m->map_first + k].rgbft[3] > 0 || maps[m->map_first + k].rgbft[4] > 0)
            return true;
    return false;
}

/* Material i (a texture's) lets light through somewhere and reflects
 * somewhere: its layers (every one must let light through), its
 * texture_map's entries (any); past a nesting of 16, both (only slower). */
static void material_bits(const csg_material *mats, int32_t i, const csg_map_color *maps,
                          int depth, bool *transparent, bool *reflect)
{
    *transparent = *reflect = false;
    if (depth > 16) {
        *transparent = *reflect = true;
        return;
    }
    const csg_material *m = &mats[i];
    if (m->tmap) {
        for (int32_t k = 0; k < m->map_count; k++) {
            bool t, r;
            material_bits(mats, m->sub_first + k, maps, depth + 1, &t, &r);
            *transparent = *transparent || t;
            *reflect = *reflect || r;
        }
        return;
    }
    bool all_clear = true;
    for (int32_t k = i, n = 0; k >= 0 && n <= 16; n++) {
        const csg_material *l = &mats[k];
        all_clear = all_clear && pigment_transparent(l, maps);
        *reflect = *reflect || l->reflection[0] > 0 || l->reflection[1] > 0 || l->reflection[2] > 0;
        k = l->under - 1;
    }
    *transparent = all_clear;
}

/* The material bits of the materials primitives use (a sky pigment is a
 * material too, but no surface shows it). */
static uint32_t material_features(const csg_blob_header *h, const csg_prim *prims,
                                  const csg_material *mats, const csg_map_color *maps)
{
    uint32_t f = 0;
    for (int32_t i = 0; i < h->prim_count; i++) {
        bool transparent, reflect;
        material_bits(mats, prims[i].material, maps, 0, &transparent, &reflect);
        if (reflect)
            f |= CSG_FEAT_REFLECT;
        if (transparent)
            f |= CSG_FEAT_TRANSPARENT;
    }
    return f;
}

/* The kinds and features of a blob whose arrays are in range (called on
 * the flattener's output and after the validator's other checks). */
void BLOB_SCAN(const void *bytes, uint32_t *kinds, uint32_t *features)
{
    const csg_blob_header *h = bytes;
    const csg_prim *prims = blob_at(bytes, h->off_prims);
    const csg_root *roots = blob_at(bytes, h->off_roots);
    const csg_node *nodes = blob_at(bytes, h->off_nodes);
    const csg_flat_light *lights = blob_at(bytes, h->off_lights);
    uint32_t k = 0, f = 0;
    for (int32_t i = 0; i < h->prim_count; i++) {
        k |= 1u << prims[i].kind;
        f |= (prims[i].flags & CSG_PF_XFORM) ? CSG_FEAT_XFORM : 0u;
        f |= (prims[i].flags & CSG_PF_NO_SHADOW) ? CSG_FEAT_NO_SHADOW : 0u;
    }
    for (int32_t r = 0; r < h->root_count; r++) {
        const csg_node *n = &nodes[roots[r].first_node];
        if (roots[r].node_count > 1 || (prims[n->prim].flags & CSG_PF_INVERT))
            f |= CSG_FEAT_CSG;
    }
    for (int32_t i = 0; i < h->light_count; i++)
        f |= lights[i].shadowless ? CSG_FEAT_SHADOWLESS : 0u;
    f |= material_features(h, prims, blob_at(bytes, h->off_materials),
                           blob_at(bytes, h->off_maps));
    *kinds = k;
    *features = f;
}

/* The header's feature set is the one its arrays have: code specialised
 * on it may rely on it. */
static bool features_valid(const void *bytes)
{
    const csg_blob_header *h = bytes;
    uint32_t kinds, features;
    BLOB_SCAN(bytes, &kinds, &features);
    return h->kinds == kinds && h->features == features;
}

bool BLOB_VALID(const void *bytes, size_t blob_size)
{
    const csg_blob_header *h = bytes;
    if (h->real_size != sizeof(real) || h->total_size != blob_size || h->width <= 0 ||
        h->height <= 0 || h->max_depth < 1 || h->spp < 1 || h->spp > CSG_MAX_SPP ||
        h->max_stack < 0 || h->max_stack > CSG_STACK_MAX)
        return false;
    if (!array_fits(h->off_prims, h->prim_count, sizeof(csg_prim), blob_size) ||
        !array_fits(h->off_coefs, h->coef_count, sizeof(real), blob_size) ||
        h->curve_count > CSG_CURVE_MAX ||
        !array_fits(h->off_curves, h->curve_count, sizeof(csg_curve), blob_size) ||
        !array_fits(h->off_nodes, h->node_count, sizeof(csg_node), blob_size) ||
        !array_fits(h->off_roots, h->root_count, sizeof(csg_root), blob_size) ||
        !array_fits(h->off_bvh, h->bvh_count, sizeof(csg_bvh_node), blob_size) ||
        h->wide_count < 0 || h->wide_bvh_count < 0 || h->wide_item_count < 0 ||
        !array_fits(h->off_wide, h->wide_count, sizeof(csg_wide), blob_size) ||
        !array_fits(h->off_wide_bvh, h->wide_bvh_count, sizeof(csg_bvh_node), blob_size) ||
        !array_fits(h->off_wide_items, h->wide_item_count, sizeof(int32_t), blob_size) ||
        !array_fits(h->off_camera, 1, sizeof(csg_camera), blob_size) ||
        !array_fits(h->off_materials, h->material_count, sizeof(csg_material), blob_size) ||
        !array_fits(h->off_lights, h->light_count, sizeof(csg_flat_light), blob_size) ||
        !array_fits(h->off_shading, 1, sizeof(csg_shading), blob_size) ||
        !array_fits(h->off_maps, h->map_count, sizeof(csg_map_color), blob_size))
        return false;
    const csg_camera *cam = blob_at(bytes, h->off_camera);
    if (cam->projection < 0 || cam->projection >= CSG_CAMERA_PROJECTIONS)
        return false;
    const csg_shading *sh = blob_at(bytes, h->off_shading);
    if (sh->output < CSG_OUTPUT_SRGB || sh->output > CSG_OUTPUT_DIRECT ||
        (sh->output == CSG_OUTPUT_POWER &&
         (!(sh->output_gamma > R(0.0)) || sh->output_gamma == CSG_R_INF)))
        return false;
    if (sh->fog_count < 0 || sh->fog_count > CSG_FLAT_FOGS || sh->camera_solid < 0)
        return false;
    for (int32_t i = 0; i < sh->fog_count; i++)
        if ((sh->fogs[i].kind != 1 && sh->fogs[i].kind != 2) || sh->fogs[i].noise_gen < 1 ||
            sh->fogs[i].noise_gen > 3 || sh->fogs[i].octaves < 1 || sh->fogs[i].octaves > 10)
            return false;
    const csg_flat_light *lights = blob_at(bytes, h->off_lights);
    for (int32_t i = 0; i < h->light_count; i++)
        if (lights[i].kind < 0 || lights[i].kind > 2 ||
            (lights[i].area && (lights[i].size1 < 1 || lights[i].size2 < 1 ||
                                lights[i].size1 > 65536 / lights[i].size2)))
            return false;
    if (sh->max_rays < 1 || h->sky_count < 0 || (h->sky_count > 0 && (sh->sky_first < 0 ||
                                                   sh->sky_first > h->material_count - h->sky_count)))
        return false;
    return prims_valid(h, blob_at(bytes, h->off_prims)) &&
           materials_valid(h, blob_at(bytes, h->off_materials)) &&
           roots_valid(h, blob_at(bytes, h->off_roots), blob_at(bytes, h->off_nodes),
                       blob_at(bytes, h->off_wide), blob_at(bytes, h->off_prims)) &&
           wide_valid(h, blob_at(bytes, h->off_wide), blob_at(bytes, h->off_wide_bvh),
                      blob_at(bytes, h->off_wide_items)) &&
           bvh_valid(h, blob_at(bytes, h->off_bvh)) && features_valid(bytes);
}

#ifndef CSG_DOUBLE
bool csg_blob_valid_double(const void *bytes, size_t blob_size);

bool csg_blob_valid(const void *bytes, size_t blob_size)
{
    if (!bytes || blob_size < sizeof(csg_blob_header))
        return false;
    const csg_blob_header *h = bytes;
    if (h->magic != CSG_BLOB_MAGIC)
        return false;
    if (h->real_size == 4)
        return csg_blob_valid_float(bytes, blob_size);
    return h->real_size == 8 && csg_blob_valid_double(bytes, blob_size);
}

void csg_blob_free(csg_blob *b)
{
    free(b->bytes);
    b->bytes = NULL;
    b->size = 0;
}
#endif
