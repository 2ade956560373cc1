/*
 * flatten.h — the scene tree (scene.h) turned into one contiguous blob of
 * plain arrays in the chosen precision: what the master broadcasts to the
 * workers as bytes, and what the OpenCL host uploads.
 *
 * The blob's layout (csg_blob_header and the arrays it locates) is defined
 * once, in device/flat.h; this is the host API that makes and checks it.
 */
#ifndef CSG_FLATTEN_H
#define CSG_FLATTEN_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "device/flat.h"
#include "diag.h"
#include "scene.h"

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
    int max_rays;       /* reflected and refracted rays a pixel may
                           trace; <= 0: CSG_RAYS_PER_SAMPLE * spp      */
} csg_flatten_opts;

/* The default ray budget of a pixel, per sample: a whole tree of depth 12
 * (two rays a hit), far beyond what adc_bailout leaves of any usual scene,
 * yet a bound on the scenes that would double their rays at every level
 * for ever (a mirror around a glass ball at max_trace_level 256). */
#define CSG_RAYS_PER_SAMPLE 4096
/* The largest --max-rays-per-pixel. */
#define CSG_MAX_RAYS_PER_PIXEL (1 << 30)

/* One per precision; false (with d filled) when the scene cannot be
 * flattened: degenerate shapes, a CSG program deeper than CSG_STACK_MAX,
 * more than CSG_MAX_PRIMS primitives, out of memory. */
bool csg_flatten_float(const csg_scene *s, const csg_flatten_opts *o, csg_blob *out, csg_diag *d);
bool csg_flatten_double(const csg_scene *s, const csg_flatten_opts *o, csg_blob *out, csg_diag *d);

/* Checks the magic, the sizes and every offset against blob_size: a blob
 * received over the network is validated before any worker trusts it. */
bool csg_blob_valid(const void *bytes, size_t blob_size);
void csg_blob_free(csg_blob *b);

/* The primitive kinds (bit 1 << kind) and enum csg_feature bits a blob's
 * arrays use, per precision: the flattener stores them in the header and
 * the validator checks the header against them (features.h reads them). */
void csg_blob_scan_features_float(const void *bytes, uint32_t *kinds, uint32_t *features);
void csg_blob_scan_features_double(const void *bytes, uint32_t *kinds, uint32_t *features);

static inline const csg_blob_header *csg_blob_hdr(const void *bytes)
{
    return (const csg_blob_header *)bytes;
}

/* The fogs of a blob of either precision (csg_shading keeps its integers
 * first: fog_count is its fifth, at the same offset in both): a ray that
 * hits nothing sees the fog's colour, not the background. */
static inline int32_t csg_blob_fog_count(const void *bytes)
{
    int32_t n;
    memcpy(&n, (const unsigned char *)bytes + csg_blob_hdr(bytes)->off_shading + 4 * sizeof n,
           sizeof n);
    return n;
}

#endif
