/*
 * master.h — rank 0's side of the tile protocol (protocol.h): the scene
 * broadcast, self-scheduled tiles, the final STOP (through link.h).
 *
 * Use (render.c):
 *   master_begin(&m, ranks);                 ranks 1: every call below is a
 *   master_share_scene(&m, status, ...);     no-op, MPI is never touched
 *   master_run_tiles(&m, &job, &d);          handshake + tiles + drain
 *   master_end(&m, status);                  STOP(status) to every worker
 * master_end must be called on every path once master_begin was: it is
 * what lets the workers exit (with the master's status).
 */
#ifndef HOST_MASTER_H
#define HOST_MASTER_H

#include <stdbool.h>
#include <stdint.h>

#include "../csg/flatten.h"
#include "../workers/tile.h"
#include "progress.h"
#include "stats.h"

typedef struct {
    int workers;              /* ranks - 1                                */
    bool shared;              /* the setup broadcast happened             */
    bool greeted;             /* every worker's handshake was received    */
    bool setup_failed;        /* a worker failed its setup                */
    bool stopped;             /* the workers were told to exit            */
    bool link_broken;         /* a message could not be received: the job
                                 can only be aborted (master_end does)    */
    uint64_t bytes_sent;      /* to workers: scene + tiles + stops        */
    uint64_t bytes_received;  /* from workers                             */
} master_session;

/* One tile phase: what to do and where the results go. */
typedef struct {
    const void *blob;         /* flattened scene (already validated)      */
    tile_grid grid;           /* the image's tiles                        */
    const void *t;            /* hetero: whole-image records (the blob's  */
    const uint32_t *surf;     /*   real, uint32); t NULL: homo            */
    const int *todo;          /* tile indices, sent in this order         */
    int todo_count;
    float *image;             /* width * height * 3: results stored here  */
    progress_bar *progress;   /* stepped once a tile                      */
    /* Results, added to: */
    stats_worker *workers;    /* [r - 1] is rank r (master_run_tiles)     */
    uint64_t pixels_hit;
    ray_counts rays;
} master_job;

void master_begin(master_session *m, int ranks);

/* Broadcasts the status, then (status 0) the blob. */
void master_share_scene(master_session *m, int status, int tile, const csg_blob *blob);

/* Handshake, then every tile of job->todo through the workers; false with
 * d filled (one message) when a worker failed: no more tiles are sent, the
 * outstanding ones are drained. */
bool master_run_tiles(master_session *m, master_job *job, csg_diag *d);

/* Adds one tile's result to the job and to the stats of the rank that
 * computed it (a worker, or the master's local path). */
void master_job_count(master_job *job, stats_worker *w, const tile_result *res);

/* STOP(status) to every worker (broadcasting the status first if the scene
 * was never shared, receiving the handshake if it was not yet). */
void master_end(master_session *m, int status);

#endif
