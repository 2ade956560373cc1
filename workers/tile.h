/*
 * tile.h — one tile of the image: where it lies, and the one function that
 * computes its pixels.  A worker rank (worker.c) and the master's local
 * path (host/render.c, no workers) both call tile_run, so every mode gives
 * the same pixels by construction, not by two copies kept in step.
 *
 * Tiles are tile x tile pixels (the last column and row smaller), numbered
 * row-major over the grid of tiles: index = ty * columns + tx.  A work
 * item is a rectangle within one tile: the whole tile, or a piece of it
 * (the tail scheduler splits the last tiles, host/schedule.h); a pixel
 * depends only on its own record, so any split gives the same pixels.
 *
 * Hit records of a tile (hetero: from the OpenCL pass) are packed tile-wise:
 * t[n] of the blob's real then surf[n] of uint32, n = pixels * spp,
 * row-major, the spp samples of a pixel side by side (engine.h).
 */
#ifndef WORKERS_TILE_H
#define WORKERS_TILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "engine.h"

/* The tiles of one image of one scene. */
typedef struct {
    int width, height;  /* the image                                   */
    int tile;           /* tile edge in pixels (> 0)                   */
    int spp;            /* hit records a pixel                         */
    size_t real_size;   /* bytes of a record's t                       */
    size_t pixels_max;  /* pixels of the largest tile                  */
} tile_grid;

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

/* The records of tile `r` out of whole-image arrays (t_image: the blob's
 * real; width * spp records a row) into `out`, packed tile-wise. */
void tile_pack_records(const tile_grid *g, const void *t_image, const uint32_t *surf_image,
                       tile_rect r, void *out);

/* The tile's RGB (3 floats a pixel, r.width wide) into the image. */
void tile_store_rgb(float *image, int image_width, tile_rect r, const float *rgb);

/* What tile_run needs for any tile of one image: the scene, and scratch
 * records for the largest tile (homo: the primary rays it traces). */
typedef struct {
    tile_grid grid;
    const engine *eng;
    const void *blob;
    void *records;      /* tile_records_bytes(pixels_max) of scratch    */
} tile_runner;

/* False when out of memory. */
bool tile_runner_init(tile_runner *tr, const void *blob, int tile);
void tile_runner_free(tile_runner *tr);

typedef struct {
    uint32_t hits;   /* primary samples that hit something              */
    ray_counts rays; /* rays traced (primary ones too, in homo)          */
    double busy_s;   /* seconds the work took (tile_time_stop)           */
    double cpu_s;    /* of them, the CPU time of its thread: the work    *
                      * without the time a shared core was elsewhere     */
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
/* tile_run_rect over the whole of tile `index`. */
void tile_run(tile_runner *tr, int index, const void *records, float *rgb, tile_result *res);

#endif
