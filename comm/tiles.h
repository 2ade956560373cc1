/*
 * tiles.h — the image cut into tiles: the unit of work every message of
 * the protocol speaks of (protocol.h), and the rectangles the engine
 * renders (workers/engine.h).
 *
 * Tiles are tile x tile pixels (the last column and row smaller), numbered
 * row-major over the grid of tiles: index = ty * columns + tx.  A work
 * item is a rectangle within one tile: the whole tile, or a piece of it
 * (the tail scheduler splits the last tiles, host/schedule.h); a pixel
 * depends only on its own record, so any split gives the same pixels
 * (workers/tile_run.c).
 *
 * Hit records of a tile (hetero: from the OpenCL pass) are packed tile-wise:
 * t[n] of the blob's real then surf[n] of uint32, n = pixels * spp,
 * row-major, the spp samples of a pixel side by side (workers/engine.h).
 */
#ifndef COMM_TILES_H
#define COMM_TILES_H

#include <limits.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    int x, y;          /* top-left pixel */
    int width, height; /* edge tiles are smaller */
} tile_rect;

/* A worker's scene paging during work items (workers/pager.h; all 0
 * without --scene-memory): sums over items, but for the two maxima. */
typedef struct {
    uint64_t touches;     /* pages named, once an item                  */
    uint64_t faults;      /* of them, not there: fetched on demand      */
    uint64_t requests;    /* fetches (a prefetch of several pages: one) */
    uint64_t pages;       /* pages fetched                              */
    uint64_t prefetched;  /* of them, fetched for the hit records       */
    uint64_t evictions;
    uint64_t bytes;       /* bytes fetched                              */
    uint64_t peak_bytes;  /* the most scene memory held (a maximum)     */
    uint64_t over_bytes;  /* the most an item went over the budget (a maximum) */
    uint64_t memory_bytes; /* the most memory pages held (a maximum)   */
    uint64_t served;      /* other workers' requests this one answered
                             (--page-home spread: the pages it holds) */
    uint64_t served_bytes; /* the bytes of those answers              */
    uint64_t rerouted;    /* asks sent to rank 0 instead of a home that
                             did not answer (dead, or stopped)          */
    double wait_s;        /* seconds waiting for pages                  */
    double install_s;     /* seconds making room and copying pages into
                             place (the kernel's faults on fresh memory
                             pages included)                            */
} page_counts;

/* page_counts' sums (every field but the three maxima), one X(field) each:
 * what page_counts_since subtracts and page_counts_add adds. */
#define PAGE_COUNTS_SUMS(X)                                                                        \
    X(touches) X(faults) X(requests) X(pages) X(prefetched) X(evictions) X(bytes) X(served)        \
    X(served_bytes) X(rerouted) X(wait_s) X(install_s)

/* The counts since `before`, the maxima as they are now (an item's). */
static inline page_counts page_counts_since(const page_counts *before, const page_counts *now)
{
    page_counts c = *now;
#define PAGE_COUNTS_SINCE(f) c.f -= before->f;
    PAGE_COUNTS_SUMS(PAGE_COUNTS_SINCE)
#undef PAGE_COUNTS_SINCE
    return c;
}

static inline void page_counts_add(page_counts *sum, const page_counts *c)
{
#define PAGE_COUNTS_ADD(f) sum->f += c->f;
    PAGE_COUNTS_SUMS(PAGE_COUNTS_ADD)
#undef PAGE_COUNTS_ADD
    sum->peak_bytes = c->peak_bytes > sum->peak_bytes ? c->peak_bytes : sum->peak_bytes;
    sum->over_bytes = c->over_bytes > sum->over_bytes ? c->over_bytes : sum->over_bytes;
    sum->memory_bytes = c->memory_bytes > sum->memory_bytes ? c->memory_bytes : sum->memory_bytes;
}

/* The tiles of one image of one scene. */
typedef struct {
    int width, height;  /* the image                                   */
    int tile;           /* tile edge in pixels (> 0)                   */
    int spp;            /* hit records a pixel                         */
    size_t real_size;   /* bytes of a record's t                       */
    size_t pixels_max;  /* pixels of the largest tile                  */
} tile_grid;

/* The most tiles an image may be cut into (--tile 1 at 65536 x 65536 would
 * be 2^32, past int): every count derived from the tiles (items: a tile
 * split in four, requeued; an array's capacity doubled) stays an int, with
 * room.  Checked where the request's size is known (host/render.c), before
 * anything is counted; that many tiles' bookkeeping is already ~18 GB
 * (host/memory.c). */
#define TILES_MAX (INT_MAX / 16)

/* The tiles of a width x height image of tile x tile tiles, counted
 * without overflow (to check against TILES_MAX). */
uint64_t tiles_wide(int width, int height, int tile);

/* The grid of a validated blob's image; tile must be > 0. */
tile_grid tile_grid_of(const void *blob, int tile);
int tile_columns(const tile_grid *g);
int tile_count(const tile_grid *g);
/* The pixels of tile `index` (0 <= index < tile_count). */
tile_rect tile_rect_of(const tile_grid *g, int index);
/* True when r is a non-empty rectangle inside tile `index` of g (index in
 * range): what a worker checks before it touches a byte of a tile message. */
bool tile_rect_in_tile(const tile_grid *g, int index, tile_rect r);
/* Bytes of the packed hit records of a tile of `pixels` pixels. */
size_t tile_records_bytes(const tile_grid *g, size_t pixels);

/* Bytes of the shadow answers that may follow them (--simd shadows): a
 * known and a lit mask a record (csg/device/shadow.h). */
size_t tile_answers_bytes(const tile_grid *g, size_t pixels);

/* The shadow answers of tile `r` out of whole-image arrays (as the records)
 * into `out`: the known masks of its records, then their lit masks. */
void tile_pack_answers(const tile_grid *g, const uint32_t *known_image,
                       const uint32_t *lit_image, tile_rect r, void *out);

/* The records of tile `r` out of whole-image arrays (t_image: the blob's
 * real; width * spp records a row) into `out`, packed tile-wise. */
void tile_pack_records(const tile_grid *g, const void *t_image, const uint32_t *surf_image,
                       tile_rect r, void *out);

/* The tile's RGB (3 floats a pixel, r.width wide) into the image. */
void tile_store_rgb(float *image, int image_width, tile_rect r, const float *rgb);

#endif
