/*
 * stats.h — what one render measured, and its JSON file (--stats), the
 * one thing benchmarks read (they never scrape the human-oriented output).
 *
 * JSON fields (one object):
 *   mode, precision, device    strings ("" device: no OpenCL pass)
 *   width, height, tile, ranks (ranks: MPI processes, 1 without mpirun)
 *   wall_s        the whole render: parse .. image written
 *   setup_s       parse + flatten + broadcast of the scene
 *   compile_s     OpenCL program build (hetero; 0 otherwise)
 *   primary_s     the separate primary pass (hetero: OpenCL upload +
 *                 kernels + download; 0 in serial/homo, where primary rays
 *                 are traced inside the tile phase)
 *   secondary_s   the tile phase: first tile out .. last result in
 *   write_s       image file writing
 *   tiles_total   tiles of the image
 *   tiles_degenerate  tiles no primary ray hit (hetero: filled with the
 *                 background by the master, never sent; 0 otherwise)
 *   tiles_sent    tiles_total - tiles_degenerate: the tiles of the tile
 *                 phase (sent to workers, or done in-process without any)
 *   spp           primary samples a pixel
 *   pixels, pixels_hit, occupancy (pixels_hit / (pixels * spp)):
 *                 pixels_hit counts the primary samples that hit (the
 *                 pixels, when spp = 1)
 *   rays          {primary, shadow, reflected, refracted, total}
 *   bytes_sent    bytes the master sent to workers (the scene broadcast
 *                 counted once per worker + the tile messages)
 *   bytes_received bytes the master received from workers
 *   blob_bytes    size of the flattened scene
 *   workers       [{rank, tiles, busy_s, hits, rays{...}}] one per rank
 *                 that rendered tiles (rank 0 alone without workers)
 */
#ifndef HOST_STATS_H
#define HOST_STATS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "../workers/engine.h"

typedef struct {
    int rank;
    uint64_t tiles;
    uint64_t hits;   /* pixels of its tiles whose primary ray hit */
    ray_counts rays;
    double busy_s;   /* time spent rendering its tiles             */
} stats_worker;

typedef struct render_stats {
    const char *mode;       /* "serial", "homo", "hetero"            */
    const char *precision;  /* "float", "double" (what ran)          */
    char precision_why[256]; /* --precision auto: why, else ""       */
    char device[256];       /* OpenCL device name, "" if none        */
    int width, height, tile, ranks, spp;
    double wall_s, setup_s, compile_s, primary_s, secondary_s, write_s;
    int tiles_total, tiles_sent, tiles_degenerate;
    uint64_t pixels, pixels_hit;
    ray_counts rays;
    uint64_t bytes_sent, bytes_received, blob_bytes;
    int worker_count;
    stats_worker *workers;  /* worker_count entries (not owned)      */
} render_stats;

/* Share of primary samples that hit something. */
double stats_occupancy(const render_stats *s);

/* Monotonic seconds, for every timing of a render. */
double stats_clock(void);

/* Adds b to a. */
void stats_add_rays(ray_counts *a, const ray_counts *b);

/* The JSON object, pretty-printed, ending with a newline. */
void stats_print_json(FILE *f, const render_stats *s);

/* Writes the JSON to `path` through a temporary file in the same folder
 * renamed when complete; false with a message in err otherwise. */
bool stats_write_json(const char *path, const render_stats *s, char *err, size_t err_size);

/* One short line for people: mode, size, ranks, wall time, tiles. */
void stats_print_summary(FILE *f, const render_stats *s);

#endif
