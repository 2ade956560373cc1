/*
 * flatten.h — the scene tree (scene.h) turned into one contiguous blob of
 * plain arrays in the chosen precision: what the master broadcasts to the
 * workers as bytes, and what the OpenCL host uploads.
 *
 * Blob layout: a csg_blob_header, then the arrays at the byte offsets it
 * records (each 64-byte aligned): prims (csg_prim), nodes (csg_node), roots
 * (csg_root), the BVH over roots (csg_bvh_node), materials (csg_material), lights (csg_flat_light), and one
 * csg_camera.  csg_prim / csg_node / csg_root / csg_camera are the shared
 * structs of flat.h in the blob's precision (header.real_size 4 or 8).
 */
#ifndef CSG_FLATTEN_H
#define CSG_FLATTEN_H

#include <stddef.h>
#include <stdint.h>

#include "diag.h"
#include "scene.h"

#define CSG_BLOB_MAGIC 0x43534731u /* "CSG1" */
#define CSG_MAX_SPP 1024          /* samples a pixel, at most          */

typedef struct {
    uint32_t magic;
    uint32_t real_size;      /* 4: float build, 8: double build         */
    int32_t width, height;   /* the image                               */
    int32_t max_depth;       /* max_trace_level: 1 = primary rays only  */
    int32_t prim_count, node_count, root_count, material_count, light_count;
    int32_t max_stack;       /* deepest root program, <= CSG_STACK_MAX   */
    int32_t linear_roots;    /* roots 0 .. linear_roots-1: unbounded, tested
                                one by one; the rest hang in the BVH      */
    int32_t bvh_count;       /* BVH nodes (0: no bounded root)            */
    int32_t spp;             /* primary samples a pixel (>= 1): the hit
                                records hold width * spp records a row,
                                the samples of a pixel side by side     */
    double adc_bailout;      /* rays weighing less are not traced        */
    double background[5];    /* rgbft                                    */
    double ambient_light[3];
    uint64_t off_prims, off_nodes, off_roots, off_bvh, off_materials, off_lights, off_camera;
    uint64_t total_size;     /* bytes of the whole blob                  */
} csg_blob_header;

typedef struct {
    void *bytes;  /* malloc'd, starts with csg_blob_header */
    size_t size;
} csg_blob;

/* What the command line may override; 0 / negative: the scene's value. */
typedef struct {
    int width, height;  /* required, > 0 */
    int max_depth;      /* <= 0: global_settings max_trace_level       */
    double bailout;     /* < 0: global_settings adc_bailout            */
    int spp;            /* samples a pixel; <= 0: 1                   */
} csg_flatten_opts;

/* One per precision; false (with d filled) when the scene cannot be
 * flattened: degenerate shapes, a CSG program deeper than CSG_STACK_MAX,
 * more than CSG_MAX_PRIMS primitives, out of memory. */
bool csg_flatten_float(const csg_scene *s, const csg_flatten_opts *o, csg_blob *out, csg_diag *d);
bool csg_flatten_double(const csg_scene *s, const csg_flatten_opts *o, csg_blob *out, csg_diag *d);

/* Checks the magic, the sizes and every offset against blob_size: a blob
 * received over the network is validated before any worker trusts it. */
bool csg_blob_valid(const void *bytes, size_t blob_size);
void csg_blob_free(csg_blob *b);

static inline const csg_blob_header *csg_blob_hdr(const void *bytes)
{
    return (const csg_blob_header *)bytes;
}

#endif
