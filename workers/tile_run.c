/*
 * tile_run.c — tile_run_rect, the one path from a rectangle of a tile to
 * its pixels, and the clocks that time it (tile.h).
 *
 * tile_run_rect: homo and serial trace the rectangle's primary rays into
 * the runner's scratch records (engine->trace_primary); hetero hands in
 * the records of the OpenCL pass.  Either way the pixels then come from
 * engine->shade over those records, and the hit count from the records'
 * surface ids, so a pixel depends on nothing but its record — which is
 * why a tile may be split into pieces (any rectangle inside it) without
 * changing a bit of the image.
 *
 * The simulated build (make sim) links sim/tile_run.c instead: the same
 * functions, the rectangle's measured cost executed on a simulated host.
 */
#include "tile.h"
#include "../comm/pixels_z.h"

#include "pager.h"

#include <string.h>
#include <time.h>

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

/* Rows y0 .. y0 + rows - 1 of rectangle r (r.width * spp records a row):
 * traced first (homo, serial: into the runner's scratch records, which
 * `records` then is), then shaded from `records` into the rectangle's
 * pixels at that row. */
static void tile_run_band(tile_runner *tr, tile_rect r, int y0, int rows, bool trace,
                          const void *records, const void *answers, float *rgb,
                          tile_result *res)
{
    size_t n = (size_t)r.width * (size_t)r.height * (size_t)tr->grid.spp, rs = tr->grid.real_size;
    size_t first = (size_t)y0 * (size_t)r.width * (size_t)tr->grid.spp; /* its first record */
    tile_rect band = {r.x, r.y + y0, r.width, rows};
    if (trace)
        tr->eng->trace_primary(tr->blob, band, (char *)tr->records + first * rs,
                               (uint32_t *)(void *)((char *)tr->records + n * rs) + first,
                               &res->rays);
    const uint32_t *surf = (const uint32_t *)(const void *)((const char *)records + n * rs);
    const uint32_t *known = answers, *lit = known ? known + n : NULL;
    tr->eng->shade_answered(tr->blob, band, (const char *)records + first * rs, surf + first,
                            known ? known + first : NULL, lit ? lit + first : NULL,
                            rgb + (size_t)y0 * (size_t)r.width * 3, &res->rays);
}

void tile_run_rect(tile_runner *tr, tile_rect r, const void *records, float *rgb,
                   tile_result *res)
{
    tile_run_rect_answered(tr, r, records, NULL, rgb, res);
}

void tile_run_rect_answered(tile_runner *tr, tile_rect r, const void *records,
                            const void *answers, float *rgb, tile_result *res)
{
    size_t n = (size_t)r.width * (size_t)r.height * (size_t)tr->grid.spp; /* records */
    bool trace = !records;
    memset(res, 0, sizeof *res);
    csg_pager *pager = pager_for(tr->blob);
    pager_stats before = {0};
    if (pager) {
        before = pager->stats;
        if (!trace && pager->prefetch) /* (the records' hits: their pages in one request) */
            pager_prefetch_hits(pager, (const uint32_t *)(const void *)((const char *)records +
                                                                        n * tr->grid.real_size),
                                n);
    }
    if (trace)
        records = tr->records;
    int rows = tile_band_rows(tr, r);
    for (int y0 = 0; y0 < r.height; y0 += rows) {
        if (y0 > 0)
            tr->progress(tr->progress_arg);
        tile_run_band(tr, r, y0, r.height - y0 < rows ? r.height - y0 : rows, trace, records,
                      answers, rgb, res);
    }
    const uint32_t *surf =
        (const uint32_t *)(const void *)((const char *)records + n * tr->grid.real_size);
    for (size_t i = 0; i < n; i++)
        res->hits += surf[i] != CSG_SURF_NONE;
    if (pager) {
        pager_trace_item(pager, trace ? 'T' : 'S', r.x, r.y, r.width, r.height);
        pager_item_end(pager);
        res->paging = page_counts_since(&before, &pager->stats);
        res->page_failed = pager->failed;
    }
}

size_t tile_compress_rgb8(tile_runner *tr, tile_rect r, pixels_zstream *z, const uint8_t *rgb8,
                          uint8_t *out)
{
    (void)tr;
    return pixels_compress(z, rgb8, (size_t)r.width * (size_t)r.height * 3, out);
}
