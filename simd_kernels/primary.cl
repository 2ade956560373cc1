/*
 * primary.cl — the data-parallel phase of the heterogeneous mode: one
 * work-item per pixel traces the primary ray with the very functions the C
 * workers use (csg/device/camera.h, csg/device/intersect.h), then one
 * work-item per tile counts the pixels whose ray hit something.
 *
 * Built by host/ocl.c with -I <source>/csg/device -I <source>/simd_kernels
 * -cl-fp32-correctly-rounded-divide-sqrt (and -DCSG_DOUBLE for the double
 * build); portable.h turns FP_CONTRACT off.  Nothing here does arithmetic
 * on `real` of its own: every bit of a record comes from the shared code,
 * which is why the records equal the C records bit for bit.
 *
 * The scene arrives as the flat blob (csg/device/flat.h) in one buffer;
 * the kernels find its arrays and the image size through the blob's header
 * (csg_blob_view, csg_blob_camera), as the C workers do.  The image is
 * processed in slices of rows (the host picks them to fit the device):
 * rows y0 .. y0 + rows - 1, stored from row 0 of the slice buffers.  The host pads the grids to whole work-groups of a
 * size it chooses (PoCL's own choice, the whole grid as one group, makes
 * every work-item's private span lists live at once and overflows its
 * stack), so both kernels first drop the work-items outside the image.
 *
 * Tile counts need no atomics: csg_tile_hits runs after csg_primary on the
 * same in-order queue, one work-item per (tile column, tile row touched by
 * the slice), and counts the slice's rows of its tile serially; the host
 * adds the per-slice counts (a tile cut by a slice boundary is counted in
 * two slices).  The result is deterministic.
 */
#include "camera.h"

__kernel void csg_primary(__global const uchar *blob, int y0, int rows, __global real *t_out,
                          __global uint *surf_out)
{
    __global const csg_blob_header *h = (__global const csg_blob_header *)blob;
    int width = h->width, spp = h->spp;
    int col = (int)get_global_id(0); /* one work-item a sample: width * spp a row */
    int row = (int)get_global_id(1);
    if (col >= width * spp || row >= rows) /* the grid is padded to whole work-groups */
        return;
    int x = col / spp, s = col % spp;
    csg_ray r = csg_sample_ray(csg_blob_camera(blob), width, h->height, x, y0 + row, spp, s);
    csg_hit hit = csg_trace_nearest(csg_blob_view(blob), r, R(0.0), CSG_R_INF);

    size_t i = (size_t)row * (size_t)width * (size_t)spp + (size_t)col;
    t_out[i] = hit.t;
    surf_out[i] = hit.surf;
}

/* hits[k * tiles_x + tx]: samples with surf != 0 in tile (tx, y0 / tile + k),
 * restricted to the slice's rows y0 .. y0 + rows - 1; a row holds
 * width * spp records and a tile is tile * spp records wide. */
__kernel void csg_tile_hits(__global const uchar *blob, __global const uint *surf, int y0,
                            int rows, int tile, __global uint *hits)
{
    __global const csg_blob_header *h = (__global const csg_blob_header *)blob;
    int width = h->width * h->spp, spp = h->spp;
    int tiles_x = (h->width + tile - 1) / tile;
    int tile_rows = (y0 + rows - 1) / tile - y0 / tile + 1;
    int tx = (int)get_global_id(0);
    int k = (int)get_global_id(1);
    if (tx >= tiles_x || k >= tile_rows)
        return;
    int ty = y0 / tile + k;
    int ya = max(y0, ty * tile);
    int yb = min(y0 + rows, ty * tile + tile);
    int xa = tx * tile * spp;
    int xb = min(width, xa + tile * spp);
    uint n = 0u;
    for (int y = ya; y < yb; y++) {
        __global const uint *line = surf + (size_t)(y - y0) * (size_t)width;
        for (int x = xa; x < xb; x++)
            n += line[x] != CSG_SURF_NONE ? 1u : 0u;
    }
    hits[(size_t)k * (size_t)tiles_x + (size_t)tx] = n;
}

/* The layout probe: out[0] = number of entries, then sizeof / offsetof of
 * every entry of CSG_LAYOUT_FIELDS (flat.h), in order (tests/test_layout.c);
 * nothing is written at or beyond out[cap]. */
#define CSG_PROBE_PUT(v)                                                           \
    {                                                                              \
        if (n < cap)                                                               \
            out[n] = (v);                                                          \
        n++;                                                                       \
    }
#define CSG_PROBE_SIZE(T) CSG_PROBE_PUT((int)sizeof(T))
#define CSG_PROBE_FIELD(T, f)                                                      \
    {                                                                              \
        T s;                                                                       \
        CSG_PROBE_PUT((int)((__private char *)&s.f - (__private char *)&s))        \
    }

__kernel void csg_layout(__global int *out, int cap)
{
    if (get_global_id(0) != 0 || cap < 1)
        return;
    int n = 1;
    CSG_LAYOUT_FIELDS(CSG_PROBE_SIZE, CSG_PROBE_FIELD)
    out[0] = n - 1;
}
