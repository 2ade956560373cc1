/*
 * primary.cl — the data-parallel phase of the heterogeneous mode: every
 * primary ray (a record: a sample of a pixel) traced with the very
 * functions the C workers use (csg/device/camera.h, csg/device/intersect.h),
 * then one work-item per tile counts the records whose ray hit something.
 * csg_primary comes in two variants, chosen at build time:
 *   - one ray a work-item (GPUs): csg_trace_nearest itself;
 *   - with -DCSG_PACKET=W, a packet of W rays a work-item in OpenCL
 *     vectors (CPUs, where PoCL turns them into SIMD code): the packet
 *     compilation of the same shared code (simd_kernels/packet.h).
 *
 * Embedded in the program with its includes inlined (tools/
 * embed_kernels.py), built by host/pass/ocl.c with
 * -cl-fp32-correctly-rounded-divide-sqrt (and -DCSG_DOUBLE for the double
 * build); portable.h turns FP_CONTRACT off.  Nothing here does arithmetic
 * on `real` of its own: every bit of a record comes from the shared code,
 * which is why the records equal the C records bit for bit, in both
 * variants.
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
#include "shadow.h"

#ifndef CSG_PACKET
/* One work-item a record (a sample of a pixel): the variant for GPUs. */
__kernel void csg_primary(__global const uchar *blob, int y0, int rows, __global real *t_out,
                          __global uint *surf_out, __global const int *cells, int cell,
                          int cell_cap)
{
    (void)cells; /* (the packet variant's culling) */
    (void)cell;
    (void)cell_cap;
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

/* The shadow answers of the primary hits (#36 item 3): one work-item a
 * record of rows y0 .. y0 + rows - 1 (t, surf: the slice's records, as
 * csg_primary left them), bit i of known[] and lit[] light i's answer
 * (csg_shadow_masks, the code the C worker shades with:
 * csg/device/shadow.h).  Lights are read from the blob's light array.
 * The packet variant below gives the same answers a packet at a time. */
__kernel void csg_shadows(__global const uchar *blob, int y0, int rows,
                          __global const real *t_in, __global const uint *surf_in,
                          __global uint *known_out, __global uint *lit_out)
{
    __global const csg_blob_header *h = (__global const csg_blob_header *)blob;
    int width = h->width, spp = h->spp;
    int col = (int)get_global_id(0);
    int row = (int)get_global_id(1);
    if (col >= width * spp || row >= rows) /* the grid is padded to whole work-groups */
        return;
    size_t i = (size_t)row * (size_t)width * (size_t)spp + (size_t)col;
    csg_u32 known = 0u, lit = 0u;
    if (surf_in[i] != CSG_SURF_NONE) {
        int x = col / spp, s = col % spp;
        csg_ray r = csg_sample_ray(csg_blob_camera(blob), width, h->height, x, y0 + row, spp, s);
        __global const csg_flat_light *lights =
            (__global const csg_flat_light *)(blob + h->off_lights);
        csg_shadow_masks(csg_blob_view(blob), lights, h->light_count, r, t_in[i], surf_in[i],
                         &known, &lit);
    }
    known_out[i] = known;
    lit_out[i] = lit;
}
#else
#include "packet.h"

/* The candidate list of the packet whose first record is column c0 of
 * slice row r0, in *n (-1: none, walk the BVH): the cell of `cell` x
 * `cell` pixels that holds every pixel of the packet, when one does
 * (cells: per cell, row by row over the image, its count then cell_cap
 * roots; cell 0: no cells). */
static __global const int *pk_cell_list(__global const int *cells, int cell, int cell_cap,
                                        int width, int spp, int cols, int y0, int rows, int c0,
                                        int r0, int *n)
{
    *n = -1;
    if (cell <= 0)
        return cells;
    int px0 = c0 / spp, px1 = (min(c0 + CSG_PACKET_COLS, cols) - 1) / spp;
    int py0 = y0 + r0, py1 = y0 + min(r0 + CSG_PACKET_ROWS, rows) - 1;
    if (px0 / cell != px1 / cell || py0 / cell != py1 / cell)
        return cells;
    int cells_x = (width + cell - 1) / cell;
    __global const int *list =
        cells + ((size_t)(py0 / cell) * (size_t)cells_x + (size_t)(px0 / cell)) *
                    (size_t)(1 + cell_cap);
    *n = list[0];
    return list + 1;
}

/* This work-item's packet: its first record's column *c0 and row *r0 in
 * the slice of `rows` rows; false when it lies beyond them (the grid is
 * padded to whole work-groups). */
static inline __attribute__((always_inline)) bool
pk_packet_at(__global const uchar *blob, int rows, int *c0, int *r0)
{
    __global const csg_blob_header *h = (__global const csg_blob_header *)blob;
    *c0 = (int)get_global_id(0) * CSG_PACKET_COLS;
    *r0 = (int)get_global_id(1) * CSG_PACKET_ROWS;
    return *c0 < h->width * h->spp && *r0 < rows;
}

/* The camera rays of the packet at column c0, row r0 of a slice from row
 * y0 of `rows` (packet.h: lane k at (k % COLS, k / COLS)), every lane's
 * what csg_sample_ray gives it; *live: the lanes that are records. */
static inline __attribute__((always_inline)) csg_ray_pk
pk_packet_rays(__global const uchar *blob, int y0, int rows, int c0, int r0, intv *live)
{
    __global const csg_blob_header *h = (__global const csg_blob_header *)blob;
    int width = h->width, spp = h->spp, cols = width * spp;
    intv lane = CSG_PK_LOAD(csg_pk_lane_ids);
    intv dc = lane % CSG_PACKET_COLS;
    intv col = c0 + dc, row = r0 + lane / CSG_PACKET_COLS;
    *live = (col < cols) & (row < rows);
    /* pixel x = col / spp and sample s = col % spp, without a division per
     * lane: from the first column's, carrying at most COLS - 1 times */
    intv x = col, s = (intv)(0);
    if (spp > 1) {
        x = (intv)(c0 / spp);
        s = c0 % spp + dc;
        for (int k = 1; k < CSG_PACKET_COLS; k++) {
            intv wrap = s >= spp;
            s = select(s, s - spp, wrap);
            x = select(x, x + 1, wrap);
        }
    }
    realv ox, oy;
    csg_sample_offset_pk(spp, s, &ox, &oy);
    return csg_camera_ray_pk(csg_blob_camera(blob), width, h->height, x, y0 + row, ox, oy);
}

/* One work-item a packet of CSG_PACKET records, CSG_PACKET_COLS of a row
 * by CSG_PACKET_ROWS rows (packet.h): the variant for CPUs.  Lanes beyond
 * the image trace a finite ray off the image and write nothing.  The
 * packet tries its cell's candidate roots (pk_cell_list), or walks the
 * BVH. */
__kernel void csg_primary(__global const uchar *blob, int y0, int rows, __global real *t_out,
                          __global uint *surf_out, __global const int *cells, int cell,
                          int cell_cap)
{
    __global const csg_blob_header *h = (__global const csg_blob_header *)blob;
    int width = h->width, spp = h->spp, cols = width * spp, c0, r0;
    if (!pk_packet_at(blob, rows, &c0, &r0))
        return;
    intv live;
    csg_ray_pk rays = pk_packet_rays(blob, y0, rows, c0, r0, &live);
    pk_packet pk;
    pk_packet_init(&pk, rays, live);
    int n;
    __global const int *cands =
        pk_cell_list(cells, cell, cell_cap, width, spp, cols, y0, rows, c0, r0, &n);
    csg_hit_pk hit = pk_trace_nearest(csg_blob_view(blob), &pk, cands, n);

    real t[CSG_PACKET];
    lane_uint surf[CSG_PACKET];
    lane_int in[CSG_PACKET];
    CSG_PK_STORE(hit.t, t);
    CSG_PK_STORE(hit.surf, surf);
    if (CSG_PK_ALL(live)) { /* a whole packet: a row of records at a time */
        for (int k = 0; k < CSG_PACKET_ROWS; k++) {
            size_t i = (size_t)(r0 + k) * (size_t)cols + (size_t)c0;
            CSG_PK_ROW_STORE(CSG_PK_ROW_LOAD(t + k * CSG_PACKET_COLS), t_out + i);
            CSG_PK_ROW_STORE(CSG_PK_ROW_UINT(CSG_PK_ROW_LOAD(surf + k * CSG_PACKET_COLS)),
                             surf_out + i);
        }
        return;
    }
    CSG_PK_STORE(live, in);
    for (int k = 0; k < CSG_PACKET; k++) {
        if (!in[k])
            continue;
        size_t i = (size_t)(r0 + k / CSG_PACKET_COLS) * (size_t)cols +
                   (size_t)(c0 + k % CSG_PACKET_COLS);
        t_out[i] = t[k];
        surf_out[i] = (uint)surf[k];
    }
}

/* The hit frames (where the shadow rays start, the normal facing the
 * ray) of the lanes `lanes`, which hit surface s, when s is an
 * untransformed sphere's: csg_hit_frame_of's operations (shadow.h; its
 * normals those of csg_surface_normal, a sphere's geometric and shading
 * normals being the same) on every lane at once (frame_lanes.h), merged
 * into fr for those lanes; 0 and nothing done for any other surface. */
typedef struct {
    vec3_pk above; /* where each lane's shadow rays start             */
    vec3_pk nf;    /* its normal, turned to face the camera ray       */
} pk_frames;

static inline int pk_sphere_frames(csg_view v, csg_ray_pk rays, realv t, intv lanes, uint s,
                                   pk_frames *fr)
{
    __global const csg_prim *p = &v.prims[CSG_SURF_PRIM(s)];
    if (p->kind != CSG_PRIM_SPHERE || (p->flags & CSG_PF_XFORM))
        return 0;
    vec3_pk wp = csg_hit_point_pk(rays, t);
    vec3_pk n = csg_sphere_surface_normal_pk(p->p, s, wp);
    __global const csg_root *root = &v.roots[p->root];
    intv entering;
    vec3_pk ngf;
    realv mag;
    vec3_pk above = csg_frame_offset_pk(rays, t, wp, n,
                                        (realv)offset_box_magnitude(root->lo, root->hi),
                                        &entering, &ngf, &mag);
    intv away = v3_dot_pk(n, rays.d) > R(0.0);
    fr->above = v3_pk(select(fr->above.x, above.x, lanes), select(fr->above.y, above.y, lanes),
                      select(fr->above.z, above.z, lanes));
    fr->nf = v3_pk(select(fr->nf.x, select(n.x, -n.x, away), lanes),
                   select(fr->nf.y, select(n.y, -n.y, away), lanes),
                   select(fr->nf.z, select(n.z, -n.z, away), lanes));
    return 1;
}

/* The shadow answers of a packet of records (the grid of csg_primary's
 * packet variant): the lanes' camera rays at once (pk_packet_rays), the
 * hit frames of the lanes that met one sphere at once (pk_sphere_frames),
 * any other lane's by the one-ray code (shadow.h), then, light by light,
 * every lane's line to the light at once (light_lanes.h) and the walk of
 * the lanes that need it as a packet (pk_shadow_walk); the same answers
 * as csg_shadow_masks. */
__kernel void csg_shadows(__global const uchar *blob, int y0, int rows,
                          __global const real *t_in, __global const uint *surf_in,
                          __global uint *known_out, __global uint *lit_out)
{
    __global const csg_blob_header *h = (__global const csg_blob_header *)blob;
    int cols = h->width * h->spp, c0, r0;
    if (!pk_packet_at(blob, rows, &c0, &r0))
        return;
    csg_view v = csg_blob_view(blob);
    __global const csg_flat_light *lights = (__global const csg_flat_light *)(blob + h->off_lights);
    lane_int hit[CSG_PACKET];
    uint known[CSG_PACKET], lit[CSG_PACKET];
    real tl[CSG_PACKET];
    uint sl[CSG_PACKET];
    lane_int done[CSG_PACKET];
    for (int k = 0; k < CSG_PACKET; k++) {
        int col = c0 + k % CSG_PACKET_COLS, row = r0 + k / CSG_PACKET_COLS;
        known[k] = 0u;
        lit[k] = 0u;
        tl[k] = R(0.0);
        sl[k] = CSG_SURF_NONE;
        done[k] = 0;
        hit[k] = col < cols && row < rows;
        if (!hit[k])
            continue;
        size_t at = (size_t)row * (size_t)cols + (size_t)col;
        sl[k] = surf_in[at];
        tl[k] = t_in[at];
        hit[k] = sl[k] != CSG_SURF_NONE;
    }
    /* The packet's t and surfaces as vectors: a whole packet's read by
     * rows into registers (CSG_PK_ROWS_LOAD), not from the arrays the
     * loop above has just written lane by lane (a wide read of narrow
     * stores waits for them to reach the cache); the frames below stay
     * in registers for the same reason. */
    realv tv;
    CSG_PK_V(uint) sv;
    if (c0 + CSG_PACKET_COLS <= cols && r0 + CSG_PACKET_ROWS <= rows) {
        size_t first = (size_t)r0 * (size_t)cols + (size_t)c0;
        tv = CSG_PK_ROWS_LOAD(realv, t_in + first, (size_t)cols);
        sv = CSG_PK_ROWS_LOAD(CSG_PK_V(uint), surf_in + first, (size_t)cols);
    } else {
        tv = CSG_PK_LOAD(tl);
        sv = CSG_PK_LOAD(sl);
    }
    intv hitv = CSG_PK_TO_INT(sv != (CSG_PK_V(uint))CSG_SURF_NONE); /* (sl: none beyond) */
    /* the lanes' camera rays at once, then each lane's frame: the lanes
     * that hit one untransformed sphere's surface together
     * (pk_sphere_frames), any other lane by the one-ray code */
    intv live;
    csg_ray_pk rays = pk_packet_rays(blob, y0, rows, c0, r0, &live);
    pk_frames fr;
    fr.above = fr.nf = v3_pk((realv)R(0.0), (realv)R(0.0), (realv)R(0.0)); /* (no hit) */
    real ax[CSG_PACKET], ay[CSG_PACKET], az[CSG_PACKET]; /* the one-ray code's frames, */
    real nx[CSG_PACKET], ny[CSG_PACKET], nz[CSG_PACKET];
    lane_int one_ray[CSG_PACKET]; /* in these lanes */
    bool any_one_ray = false;
    for (int k = 0; k < CSG_PACKET; k++) {
        if (!hit[k] || done[k])
            continue;
        intv same = hitv & CSG_PK_TO_INT(sv == (CSG_PK_V(uint))sl[k]);
        if (pk_sphere_frames(v, rays, tv, same, sl[k], &fr)) {
            for (int j = k + 1; j < CSG_PACKET; j++)
                done[j] |= sl[j] == sl[k];
            continue;
        }
        if (!any_one_ray)
            for (int j = 0; j < CSG_PACKET; j++) {
                one_ray[j] = 0;
                ax[j] = ay[j] = az[j] = nx[j] = ny[j] = nz[j] = R(0.0);
            }
        any_one_ray = true;
        /* (its camera ray again by the one-ray code: the same bits as its
         * lane's) */
        int col = c0 + k % CSG_PACKET_COLS;
        csg_ray r = csg_sample_ray(csg_blob_camera(blob), h->width, h->height, col / h->spp,
                                   y0 + r0 + k / CSG_PACKET_COLS, h->spp, col % h->spp);
        csg_hit_frame f = csg_hit_frame_of(v, r, tl[k], sl[k]);
        vec3 nf = v3_dot(f.n, r.d) > R(0.0) ? v3_neg(f.n) : f.n;
        ax[k] = f.above.x;
        ay[k] = f.above.y;
        az[k] = f.above.z;
        nx[k] = nf.x;
        ny[k] = nf.y;
        nz[k] = nf.z;
        one_ray[k] = -1;
    }
    if (any_one_ray) {
        intv m = CSG_PK_LOAD(one_ray);
        fr.above = v3_pk(select(fr.above.x, CSG_PK_LOAD(ax), m),
                         select(fr.above.y, CSG_PK_LOAD(ay), m),
                         select(fr.above.z, CSG_PK_LOAD(az), m));
        fr.nf = v3_pk(select(fr.nf.x, CSG_PK_LOAD(nx), m), select(fr.nf.y, CSG_PK_LOAD(ny), m),
                      select(fr.nf.z, CSG_PK_LOAD(nz), m));
    }
    int n = h->light_count < CSG_SHADOW_LIGHTS ? h->light_count : CSG_SHADOW_LIGHTS;
    for (int i = 0; i < n; i++) {
        __global const csg_flat_light *lt = &lights[i];
        if (!csg_shadow_answerable(lt))
            continue;
        /* every lane's line to the light at once (light_lanes.h): the
         * same operations per lane as csg_shadow_masks' one ray */
        vec3_pk o = fr.above;
        vec3_pk l;
        realv dist;
        intv line = csg_light_line_pk(lt, o, &l, &dist);
        intv okv = hitv & line & (v3_dot_pk(fr.nf, l) > R(0.0));
        /* (a lane that takes no part: a finite ray) */
        l = v3_pk(select((realv)R(0.0), l.x, okv), select((realv)R(0.0), l.y, okv),
                  select((realv)R(1.0), l.z, okv));
        dist = select((realv)R(1.0), dist, okv);
        if (!CSG_PK_ANY(okv))
            continue;
        lane_int ok[CSG_PACKET], blocked[CSG_PACKET], touched[CSG_PACKET];
        CSG_PK_STORE(okv, ok);
        csg_ray_pk r;
        r.o = o;
        r.d = l;
        pk_packet pk;
        pk_packet_init(&pk, r, okv);
        intv b, t;
        pk_shadow_walk(v, &pk, csg_shadow_reach_pk(dist), &b, &t);
        CSG_PK_STORE(b, blocked);
        CSG_PK_STORE(t, touched);
        for (int k = 0; k < CSG_PACKET; k++) {
            if (!ok[k] || (!blocked[k] && touched[k]))
                continue;
            known[k] |= 1u << i;
            if (!blocked[k])
                lit[k] |= 1u << i;
        }
    }
    for (int k = 0; k < CSG_PACKET; k++) {
        int col = c0 + k % CSG_PACKET_COLS, row = r0 + k / CSG_PACKET_COLS;
        if (col >= cols || row >= rows)
            continue;
        size_t i = (size_t)row * (size_t)cols + (size_t)col;
        known_out[i] = known[k];
        lit_out[i] = lit[k];
    }
}
#endif

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
