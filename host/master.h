/*
 * master.h — rank 0's side of the tile protocol (protocol.h): the scene
 * broadcast, the work items of the scheduler (schedule.h) kept
 * PROTO_IN_FLIGHT deep at every worker while the OpenCL pass still
 * produces them, the final STOP (through mpi_link.h).
 *
 * Use (render.c):
 *   master_begin(&m, ranks);                 ranks 1: every call below is a
 *   master_share_scene(&m, status, ...);     no-op, MPI is never touched
 *   master_run_tiles(&m, &job, &d);          handshake + items + drain
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
#include "../comm/mpi_link.h"
#include "../workers/pager.h"
#include "progress.h"
#include "schedule.h"
#include "stats.h"

/* What the master's own work on the results costs where that is
 * simulated (make sim: sim/main.c sets it after master_begin, sim/
 * charges.h); NULL in a real render, where the work is simply done. */
typedef struct {
    void (*message)(void);                /* a RESULT taken in            */
    /* one of its parts stored, in enum pixels_format (compressed: its
     * `compressed` bytes) */
    void (*part)(size_t pixels, int format, size_t compressed);
    void (*drain)(void);                  /* the tile phase's end: the
                                             store threads' backlog       */
    void (*pages)(uint64_t bytes);        /* pages packed for a worker    */
} master_costs;

typedef struct {
    int workers;              /* ranks - 1                                */
    int relays;               /* ranks 1 .. relays are relays (--relays):
                                 set before master_share_scene; 0: none  */
    int children;             /* rank 0 deals to ranks 1 .. children: the
                                 relays, or every worker                 */
    bool shared;              /* the setup broadcast happened             */
    bool greeted;             /* every worker's handshake was received    */
    bool setup_failed;        /* a worker failed its setup                */
    bool stopped;             /* the workers were told to exit            */
    bool link_broken;         /* a message could not be received: the job
                                 can only be aborted (master_end does)    */
    bool *lost_before;        /* [r]: rank r was lost in an earlier render
                                 of this job (compare): not reported again */
    bool *lost;               /* [r]: rank r's process is gone (NULL:
                                 out of memory, nobody is ever lost)      */
    int workers_lost;         /* how many                                 */
    int batch;                /* items in one TILE at most: set before
                                 master_share_scene (0: auto, --batch),
                                 the limit in force after it              */
    int pixels;               /* enum pixels_format the workers answer in:
                                 set before master_share_scene (host/
                                 pixels.h: pixels_format_for the output)  */
    uint64_t tile_messages;   /* TILE messages sent                       */
    uint64_t answers_early;   /* relays' answers to a TILE sent after
                                 one still held (comm/protocol.h)         */
    uint64_t bytes_sent;      /* to workers: scene + tiles + stops        */
    uint64_t bytes_received;  /* from workers                             */
    const master_costs *costs; /* the simulated build's (NULL: none)      */
    link_scene scene;         /* the master's view of the scene once shared:
                                 its node's one copy when one was made    */
    int scene_shared;         /* worker and relay ranks that said (READY)
                                 they read their node's one copy in place */
    /* --scene-memory (workers/pager.h), set before master_share_scene: */
    uint64_t scene_memory;    /* > 0: each worker's scene budget, bytes   */
    int page_policy;          /* enum pager_policy                        */
    int page_prefetch;        /* enum pager_prefetch: an item's pages
                                 fetched before its rays (and its shadow
                                 rays')                                  */
    int page_homes;           /* > 0: the workers are the pages' homes
                                 (proto_setup.page_homes); 0: rank 0     */
    int page_fetch;           /* enum pager_fetch_mode asked for          */
    bool page_window;         /* rank 0's blob is open as a window: the
                                 workers read pages one-sided           */
    pager_plan plan;          /* the pages, once shared; served from blob  */
    const void *page_blob;    /* the scene the pages are served from      */
    uint64_t page_asks;       /* page requests answered                   */
    uint64_t page_bytes_served; /* their bytes                            */
} master_session;

/* One tile phase: what to do and where the results go. */
typedef struct master_job {
    const void *blob;         /* flattened scene (already validated)      */
    const void *local_blob;   /* what rank 0 renders from when it renders
                                 tiles itself: blob, or a pager's address
                                 space (serial --scene-memory)           */
    tile_grid grid;           /* the image's tiles                        */
    const void *t;            /* hetero: whole-image records (the blob's  */
    const uint32_t *surf;     /*   real, uint32); t NULL: homo            */
    const uint32_t *known;    /* hetero --simd shadows: the records' shadow
                                 answers (csg/device/shadow.h); NULL: none */
    const uint32_t *lit;
    bool retrace;             /* hetero --hit-records retrace: the records
                                 are not sent, the workers trace the
                                 primary rays of the tiles with hits       */
    sched *sched;             /* the work items, in the order to send     */
    /* While sched is not closed: makes the newly ready tiles known to it
     * (sched_add / sched_skip, sched_close after the last); with `wait`,
     * blocks until at least one more is known.  Returns how many became
     * known, or -1 with d filled (the OpenCL pass failed). */
    int (*feed)(struct master_job *job, bool wait, csg_diag *d);
    /* When no item is ready for a worker with room (NULL: never): a tile
     * claimed for it to render whole (schedule.h's fill), handed out;
     * the item, -1 when there is none, -2 with d filled (out of memory).
     * It takes feed_arg too. */
    int (*fill)(struct master_job *job, double now, csg_diag *d);
    void *feed_arg;
    link_idle *idle;          /* the master's idle wait (the feed's
                                 producer wakes it); NULL: its own        */
    float *image;             /* width * height * 3: results stored here  */
    struct store *store;      /* the thread that stores 8-bit results
                                 (store.h; NULL: the loop stores them)    */
    progress_bar *progress;   /* stepped once a tile                      */
    struct journal *journal;  /* each finished tile appended (NULL: none) */
    struct img_stream *stream; /* the image file, told each final tile
                                  (NULL: none)                           */
    /* Results, added to: */
    stats_worker *workers;    /* [r - 1] is rank r (master_run_tiles)     */
    uint64_t pixels_hit;
    ray_counts rays;
    page_counts paging;       /* the workers' scene paging, all items     */
    double busy_s;            /* seconds of every item, all workers       */
    double results_s;         /* the master's seconds taking results in   */
    double results_past_s;    /* of them, those after t_last (not in the
                                 tile phase: the last result's storing,
                                 answers after it)                        */
    int items_done;
    double t_first;           /* stats_clock(): first item out (0: none)  */
    double t_last;            /* the last result in                       */
} master_job;

void master_begin(master_session *m, int ranks);

/* The idle wait master_run_tiles wants (its nap bounds), for a caller that
 * lends it one (master_job.idle) to wake from another thread. */
bool master_idle_init(link_idle *idle);

/* Broadcasts the status, the batch limit (m->batch resolved with
 * sched_batch_limit) and the results' pixel format (m->pixels), then
 * (status 0) the blob, once per node (comm/mpi_link.h: link_scene).  When
 * the master's node got one shared copy, blob->bytes is that copy from
 * now on (read-only; the malloc'd one freed): master_release_scene. */
void master_share_scene(master_session *m, int status, int tile, csg_blob *blob);
/* --scene-memory, before master_share_scene: the blob (valid, `size`
 * bytes) laid out for pages of page_bytes (0: pager_page_bytes_for the
 * budget), its plan in m->plan, the budget checked against the resident
 * part, the session told to share it (policy: enum pager_policy; home:
 * enum pager_home, decided here for the session's workers).  0, or the
 * exit status with d filled. */
int master_plan_pages(master_session *m, void *blob, size_t size, uint64_t budget,
                      uint64_t page_bytes, int policy, int prefetch, int home, csg_diag *d);
/* The master's view of the shared scene gone, blob->bytes NULL then (the
 * caller frees a blob that was not shared, as before). */
void master_release_scene(master_session *m, csg_blob *blob);

/* Handshake, then every item of job->sched through the workers, feeding
 * the scheduler as the tiles become ready; false with d filled (one
 * message) when a worker or the feed failed: no more items are sent, the
 * outstanding ones are drained.  A worker that dies (or holds an item for
 * far longer than items take: MASTER_HANG_*) is lost: one line on stderr,
 * its items go to the others.  True with sched not finished: every worker
 * was lost (the caller does the rest itself). */
bool master_run_tiles(master_session *m, master_job *job, csg_diag *d);

/* With relays (after master_share_scene), the floor of every batch of
 * the scheduler that feeds them (schedule.h: sched_batch_floor), and the
 * batches each relay will hold at most in a job of s (comm/protocol.h:
 * PROTO_RELAY_*); without relays, nothing, and 0. */
int master_relay_floor(const master_session *m, sched *s);

/* Is item `item` shaded from the pass's records (hetero, not a fill
 * tile, the records sent), or rendered whole (its primary rays traced
 * too)? */
bool master_shades(const master_job *job, int item);
/* What item `item` asks of a worker: enum proto_work (comm/protocol.h). */
int master_work(const master_job *job, int item);

/* Item `item` came back from rank `rank` (0: the master's local path)
 * with `res`, at stats_clock() `now`: added to the item, the job, the
 * stats of the rank that computed it (w) and the progress bar. */
void master_job_count(master_job *job, stats_worker *w, int rank, int item,
                      const tile_result *res, double now);

/* STOP(status) to every worker not lost (broadcasting the status first if
 * the scene was never shared, receiving the handshake if it was not yet);
 * frees the session. */
void master_end(master_session *m, int status);

#endif
