/*
 * tile.c — tile geometry and tile_run, the one path from a tile to its
 * pixels (tile.h).
 *
 * tile_run: homo and serial trace the tile's primary rays into the
 * runner's scratch records (engine->trace_primary); hetero hands in the
 * records of the OpenCL pass.  Either way the pixels then come from
 * engine->shade over those records, and the hit count from the records'
 * surface ids, so a pixel depends on nothing but its record — which is
 * why a tile may be split into pieces (tile_run_rect over any rectangle
 * inside it) without changing a bit of the image.
 */
#include "tile.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

tile_grid tile_grid_of(const void *blob, int tile)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    tile_grid g = {h->width, h->height, tile, h->spp, h->real_size, 0};
    g.pixels_max = (size_t)(tile < h->width ? tile : h->width) *
                   (size_t)(tile < h->height ? tile : h->height);
    return g;
}

int tile_columns(const tile_grid *g)
{
    return (g->width + g->tile - 1) / g->tile;
}

int tile_count(const tile_grid *g)
{
    return tile_columns(g) * ((g->height + g->tile - 1) / g->tile);
}

tile_rect tile_rect_of(const tile_grid *g, int index)
{
    int columns = tile_columns(g);
    tile_rect r = {index % columns * g->tile, index / columns * g->tile, g->tile, g->tile};
    if (r.x + r.width > g->width)
        r.width = g->width - r.x;
    if (r.y + r.height > g->height)
        r.height = g->height - r.y;
    return r;
}

bool tile_rect_in_tile(const tile_grid *g, int index, tile_rect r)
{
    if (index < 0 || index >= tile_count(g))
        return false;
    tile_rect t = tile_rect_of(g, index);
    return r.width > 0 && r.height > 0 && r.x >= t.x && r.y >= t.y &&
           r.width <= t.x + t.width - r.x && r.height <= t.y + t.height - r.y;
}

size_t tile_records_bytes(const tile_grid *g, size_t pixels)
{
    return pixels * (size_t)g->spp * (g->real_size + sizeof(uint32_t));
}

void tile_pack_records(const tile_grid *g, const void *t_image, const uint32_t *surf_image,
                       tile_rect r, void *out)
{
    size_t rs = g->real_size, spp = (size_t)g->spp;
    size_t line = (size_t)r.width * spp, n = line * (size_t)r.height;
    uint32_t *surf_out = (uint32_t *)((char *)out + n * rs);
    for (int row = 0; row < r.height; row++) {
        size_t src = ((size_t)(r.y + row) * (size_t)g->width + (size_t)r.x) * spp;
        size_t dst = (size_t)row * line;
        memcpy((char *)out + dst * rs, (const char *)t_image + src * rs, line * rs);
        memcpy(surf_out + dst, surf_image + src, line * sizeof *surf_out);
    }
}

void tile_store_rgb(float *image, int image_width, tile_rect r, const float *rgb)
{
    for (int row = 0; row < r.height; row++) {
        size_t dst = ((size_t)(r.y + row) * (size_t)image_width + (size_t)r.x) * 3;
        memcpy(image + dst, rgb + (size_t)row * (size_t)r.width * 3,
               (size_t)r.width * 3 * sizeof *rgb);
    }
}

bool tile_runner_init(tile_runner *tr, const void *blob, int tile)
{
    tr->grid = tile_grid_of(blob, tile);
    tr->eng = engine_for_blob(blob);
    tr->blob = blob;
    tr->records = malloc(tile_records_bytes(&tr->grid, tr->grid.pixels_max));
    return tr->records != NULL;
}

void tile_runner_free(tile_runner *tr)
{
    free(tr->records);
    tr->records = NULL;
}

#ifndef CSG_SIM /* (the simulated build's: tile_sim.c) */
static double tile_clock(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* (the CPU clock read inside the wall clock's span: cpu_s <= busy_s) */
void tile_time_start(tile_timer *t)
{
    t->wall = tile_clock(CLOCK_MONOTONIC);
    t->cpu = tile_clock(CLOCK_THREAD_CPUTIME_ID);
}

void tile_time_stop(const tile_timer *t, tile_result *res)
{
    res->cpu_s = tile_clock(CLOCK_THREAD_CPUTIME_ID) - t->cpu;
    res->busy_s = tile_clock(CLOCK_MONOTONIC) - t->wall;
}
#endif

void tile_run(tile_runner *tr, int index, const void *records, float *rgb, tile_result *res)
{
    tile_run_rect(tr, tile_rect_of(&tr->grid, index), records, rgb, res);
}

#ifndef CSG_SIM /* the simulated build's is in tile_sim.c */
void tile_run_rect(tile_runner *tr, tile_rect r, const void *records, float *rgb,
                   tile_result *res)
{
    size_t n = (size_t)r.width * (size_t)r.height * (size_t)tr->grid.spp; /* records */
    size_t t_bytes = n * tr->grid.real_size;
    memset(res, 0, sizeof *res);
    if (!records) {
        records = tr->records;
        tr->eng->trace_primary(tr->blob, r, tr->records,
                               (uint32_t *)(void *)((char *)tr->records + t_bytes), &res->rays);
    }
    const uint32_t *surf = (const uint32_t *)(const void *)((const char *)records + t_bytes);
    tr->eng->shade(tr->blob, r, records, surf, rgb, &res->rays);
    for (size_t i = 0; i < n; i++)
        res->hits += surf[i] != CSG_SURF_NONE;
}
#endif
