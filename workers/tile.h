/*
 * tile.h — the one function that computes the pixels of a tile (where
 * tiles lie: comm/tiles.h).  A worker rank (worker.c) and the master's
 * local path (host/render.c, no workers) both call tile_run, so every mode
 * gives the same pixels by construction, not by two copies kept in step.
 */
#ifndef WORKERS_TILE_H
#define WORKERS_TILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "engine.h"

/* What tile_run needs for any tile of one image: the scene, and scratch
 * records for the largest tile (homo: the primary rays it traces). */
typedef struct {
    tile_grid grid;
    const engine *eng;
    const void *blob;
    void *records;      /* tile_records_bytes(pixels_max) of scratch    */
    /* Called between bands of TILE_BAND_PIXELS of a rectangle (NULL: the
     * rectangle in one piece): a worker's large answer, sent in the
     * background, moves on only when its rank calls MPI, so it is called
     * there while the next item is computed (comm/mpi_link.h,
     * link_progress).  A band's pixels are the rectangle's pixels there:
     * each depends on its record alone (tile_run.c). */
    void (*progress)(void *arg);
    void *progress_arg;
    int band_pixels;    /* a band's pixels, about: TILE_BAND_PIXELS, or
                           TILE_BAND_PIXELS_HOME on a worker that answers
                           other workers' page asks between bands (their
                           rays wait on it: workers/pager.h, homes)     */
} tile_runner;

/* Pixels of a band of rows, about (tile_runner.progress): whole rows of
 * the rectangle, at least one. */
#define TILE_BAND_PIXELS 1024
#define TILE_BAND_PIXELS_HOME 64

/* The rows of rectangle r a band holds (all of them without a hook); the
 * simulated build's tile_run_rect cuts its cost the same way. */
static inline int tile_band_rows(const tile_runner *tr, tile_rect r)
{
    if (!tr->progress)
        return r.height;
    int rows = (tr->band_pixels > 0 ? tr->band_pixels : TILE_BAND_PIXELS) / (r.width * tr->grid.spp);
    return rows < 1 ? 1 : rows;
}

/* False when out of memory (no progress hook: set it after). */
bool tile_runner_init(tile_runner *tr, const void *blob, int tile);
void tile_runner_free(tile_runner *tr);

typedef struct {
    uint32_t hits;   /* primary samples that hit something              */
    ray_counts rays; /* rays traced (primary ones too, in homo)          */
    double busy_s;   /* seconds the work took (tile_time_stop)           */
    double cpu_s;    /* of them, the CPU time of its thread: the work    *
                      * without the time a shared core was elsewhere     */
    page_counts paging; /* its scene paging (workers/pager.h)            */
    bool page_failed;   /* a page could not be fetched: the pixels are
                           not to be trusted                             */
} tile_result;

/* The clocks of a piece of work on one thread: tile_time_stop puts the
 * seconds since tile_time_start into res->busy_s and that thread's CPU
 * seconds into res->cpu_s.  tile_run_rect leaves them 0: its callers time
 * what they count as the tile's work (a worker: the tile and its
 * conversion to the file's bytes).  The simulated build's read no clock
 * and leave res alone: there tile_run_rect sets the cost map's seconds. */
typedef struct {
    double wall, cpu;
} tile_timer;
void tile_time_start(tile_timer *t);
void tile_time_stop(const tile_timer *t, tile_result *res);

/* The RGB of rectangle r (inside one tile: tile_rect_in_tile; 3 floats a
 * pixel, r.width wide, linear) into rgb: shaded from its packed hit records
 * `records` (hetero), or, when records is NULL, tracing its primary rays
 * first (homo, serial). */
void tile_run_rect(tile_runner *tr, tile_rect r, const void *records, float *rgb,
                   tile_result *res);
/* tile_run_rect with the records' shadow answers (tiles.h:
 * tile_pack_answers; NULL: none), which shading takes instead of tracing
 * the primary hits' shadow rays (engine->shade_answered): the same pixels. */
void tile_run_rect_answered(tile_runner *tr, tile_rect r, const void *records,
                            const void *answers, float *rgb, tile_result *res);
/* Rectangle r's 8-bit pixels (rgb8: 3 bytes a pixel) compressed by z into
 * out (room for pixels_compress_bound of them, comm/pixels_z.h): the
 * frame's bytes, 0 on failure.  Here because it is the tile's work that
 * the simulated build replaces (sim/tile_run.c: a frame of the measured
 * size, at the measured cost). */
struct pixels_zstream;
size_t tile_compress_rgb8(tile_runner *tr, tile_rect r, struct pixels_zstream *z,
                          const uint8_t *rgb8, uint8_t *out);
/* tile_run_rect over the whole of tile `index`. */
void tile_run(tile_runner *tr, int index, const void *records, float *rgb, tile_result *res);

#endif
