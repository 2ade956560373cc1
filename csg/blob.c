/*
 * blob.c — validation and release of a flat-scene blob (flatten.h), in
 * either precision.  A blob that arrives over MPI is checked here before a
 * worker reads a single array through it: magic, precision, counts, and
 * that every array lies inside the received bytes.
 */
#include "flatten.h"
#include "flat.h"

#include <stdlib.h>

/* Sizes of the shared structs per precision; flatten.c checks these
 * formulas against sizeof at compile time in both builds. */
static uint64_t prim_size(uint32_t rs) { return 16u + 20u * rs; }
static uint64_t root_size(uint32_t rs) { return 16u + 6u * rs; }
static uint64_t material_size(uint32_t rs) { return 17u * rs; }
static uint64_t light_size(uint32_t rs) { return 6u * rs + 8u; }
static uint64_t camera_size(uint32_t rs) { return 12u * rs; }

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
    if (h->max_stack < 0 || h->max_stack > CSG_STACK_MAX)
        return false;
    uint32_t rs = h->real_size;
    return array_fits(h->off_prims, h->prim_count, prim_size(rs), blob_size) &&
           array_fits(h->off_nodes, h->node_count, 8, blob_size) &&
           array_fits(h->off_roots, h->root_count, root_size(rs), blob_size) &&
           array_fits(h->off_materials, h->material_count, material_size(rs), blob_size) &&
           array_fits(h->off_lights, h->light_count, light_size(rs), blob_size) &&
           array_fits(h->off_camera, 1, camera_size(rs), blob_size);
}

void csg_blob_free(csg_blob *b)
{
    free(b->bytes);
    b->bytes = NULL;
    b->size = 0;
}
