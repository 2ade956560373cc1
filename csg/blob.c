/*
 * blob.c — validation and release of a flat-scene blob (flatten.h), in
 * either precision.  A blob that arrives over MPI is checked here before a
 * worker reads a single array through it: magic, precision, counts, and
 * that every array lies inside the received bytes.
 */
#include "flatten.h"
#include "device/flat.h"

#include <stdlib.h>

/* Sizes of the shared structs per precision; flatten.c checks these
 * formulas against sizeof at compile time in both builds. */
static uint64_t prim_size(uint32_t rs) { return 16u + 20u * rs; }
static uint64_t root_size(uint32_t rs) { return 16u + 6u * rs; }
static uint64_t material_size(uint32_t rs) { return 17u * rs; }
static uint64_t light_size(uint32_t rs) { return 6u * rs + 8u; }
static uint64_t camera_size(uint32_t rs) { return 12u * rs; }
static uint64_t bvh_size(uint32_t rs) { return 6u * rs + 8u; }

/* The integer fields the tracers index with, read at their fixed offsets
 * (they come before any `real` in each struct, see flat.h). */
static const int32_t *ints_at(const void *bytes, uint64_t off, uint64_t index, uint64_t size)
{
    return (const int32_t *)((const unsigned char *)bytes + off + index * size);
}

/* Every index a worker or kernel will follow stays inside its array, and
 * every root program is well formed (RPN within the stack limit). */
static bool indices_valid(const void *bytes, const csg_blob_header *h)
{
    uint32_t rs = h->real_size;
    for (int32_t i = 0; i < h->prim_count; i++) {
        const int32_t *p = ints_at(bytes, h->off_prims, (uint64_t)i, prim_size(rs));
        if (p[0] < CSG_PRIM_SPHERE || p[0] > CSG_PRIM_PLANE || p[2] < 0 || p[2] >= h->material_count)
            return false;
    }
    for (int32_t r = 0; r < h->root_count; r++) {
        const int32_t *root = ints_at(bytes, h->off_roots, (uint64_t)r, root_size(rs));
        int32_t first = root[0], count = root[1], depth = 0;
        if (first < 0 || count < 1 || first > h->node_count - count)
            return false;
        for (int32_t k = first; k < first + count; k++) {
            const int32_t *n = ints_at(bytes, h->off_nodes, (uint64_t)k, 8);
            if (n[0] == CSG_OP_PRIM) {
                if (n[1] < 0 || n[1] >= h->prim_count || ++depth > CSG_STACK_MAX)
                    return false;
            } else if ((n[0] != CSG_OP_UNION && n[0] != CSG_OP_INTERSECT) || --depth < 1) {
                return false;
            }
        }
        if (depth != 1)
            return false;
    }
    if (h->linear_roots < 0 || h->linear_roots > h->root_count || h->bvh_count < 0)
        return false;
    if (h->bvh_count == 0)
        return h->linear_roots == h->root_count;
    for (int32_t k = 0; k < h->bvh_count; k++) {
        /* first and count follow the six reals of the box */
        const int32_t *n = (const int32_t *)((const unsigned char *)bytes + h->off_bvh +
                                             (uint64_t)k * bvh_size(rs) + 6u * rs);
        if (n[1] > 0) {
            if (n[0] < h->linear_roots || n[0] > h->root_count - n[1])
                return false;
        } else if (n[1] < -3 || n[0] <= k + 1 || n[0] >= h->bvh_count) {
            return false; /* children come after their parent: no cycles */
        }
    }
    return true;
}

static bool array_fits(uint64_t off, int32_t count, uint64_t elem, uint64_t total)
{
    if (count < 0 || off > total)
        return false;
    return (uint64_t)count <= (total - off) / (elem ? elem : 1);
}

bool csg_blob_valid(const void *bytes, size_t blob_size)
{
    if (!bytes || blob_size < sizeof(csg_blob_header))
        return false;
    const csg_blob_header *h = bytes;
    if (h->magic != CSG_BLOB_MAGIC || (h->real_size != 4 && h->real_size != 8))
        return false;
    if (h->total_size != blob_size || h->width <= 0 || h->height <= 0 || h->max_depth < 1)
        return false;
    if (h->spp < 1 || h->spp > CSG_MAX_SPP)
        return false;
    if (h->max_stack < 0 || h->max_stack > CSG_STACK_MAX)
        return false;
    uint32_t rs = h->real_size;
    return array_fits(h->off_prims, h->prim_count, prim_size(rs), blob_size) &&
           array_fits(h->off_nodes, h->node_count, 8, blob_size) &&
           array_fits(h->off_roots, h->root_count, root_size(rs), blob_size) &&
           array_fits(h->off_materials, h->material_count, material_size(rs), blob_size) &&
           array_fits(h->off_lights, h->light_count, light_size(rs), blob_size) &&
           array_fits(h->off_camera, 1, camera_size(rs), blob_size) &&
           array_fits(h->off_bvh, h->bvh_count, bvh_size(rs), blob_size) &&
           indices_valid(bytes, h);
}

void csg_blob_free(csg_blob *b)
{
    free(b->bytes);
    b->bytes = NULL;
    b->size = 0;
}
