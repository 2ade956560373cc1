/*
 * schedule.h — which work item goes to which worker next (--schedule).
 *
 * Tiles become ready as the OpenCL pass finishes the slices over them
 * (hetero; homo and serial: all at once) and are handed to the scheduler
 * with sched_add; degenerate ones with sched_skip (kept for the tile log,
 * never sent).  Whenever a worker has room for another item the master
 * asks sched_next for one.  Policies:
 *   raster  first ready, first sent (row-major): the paper's
 *           self-scheduling, homo's default;
 *   cost    the largest estimate among the ready tiles first (longest
 *           processing time first, which shortens the tail): hetero's
 *           default; without estimates (homo) it is raster;
 *   static  the k-th tile added goes to worker k mod W, whoever is idle:
 *           the interleaved static assignment, for contrast;
 *   region  each worker owns a band of the image, tile t of T going to
 *           worker t x W / T, and takes its own tiles in raster order; a
 *           worker whose band is empty takes the last tile of the band
 *           with the most left (work stealing from a static start, at the
 *           far end of the victim's band).  Neighbouring tiles go to the
 *           same worker, so the pages of the scene one tile fetched serve
 *           the next (--scene-memory: a cache of pages per worker);
 *           batches are runs of neighbours, cut by count.
 *   tail    cost (or raster) order, but once every tile is known and at
 *           most SCHED_TAIL_TILES_PER_SLOT x (workers x in-flight) whole
 *           tiles are left, each tile sent is split into its four
 *           quarters, so the last workers finish within a quarter tile of
 *           each other (VM_pRAY's small work items, at the end only).
 *
 * Pieces (--pieces, sched_cut): with raster, cost and tail a tile may go
 * as 4, 16 or 64 pieces from the start, each an item of its own with its
 * own estimate, queued as tiles are: the tile (its culling, the journal,
 * the image's bands) stays the unit of the image, the item becomes
 * smaller.  When the workers are many, a frame has few tiles a worker and
 * the costliest tiles (the spheres' rims: 10 ms against a 0.35 ms median
 * at 4096x4096) make the tail, which no order that does not know the costs
 * avoids; auto (sched_pieces_auto) cuts tiles in 4 from
 * SCHED_PIECES_WORKERS workers on where a worker would have fewer than
 * SCHED_PIECES_ITEMS tiles but SCHED_PIECES_FEWEST at least, unless the
 * results go compressed (bench/SCALE.md, *tiles cut into pieces* and
 * *relays answer as their TILEs end*: with fewer, rank 0's work on four
 * parts a tile outweighs the tail they shorten).  Static and region keep
 * whole tiles.
 *
 * Batches (--batch): the master may hand a worker several items in one
 * message (sched_next_batch).  sched_batch_limit says how many at most
 * (auto: 1 unless the workers are many).  How many the next message
 * takes follows guided self-scheduling: a batch is its share of what is
 * left (ready, and the tiles the pass has not reached yet, extrapolated
 * from those it has) spread over every worker's in-flight messages, so
 * batches are large while much is left and 1 near the end (and once tail
 * splits): the tail stays fine-grained.  With estimates (hetero, every
 * policy but static) a batch is cut by cost: it costs at most its share
 * of the estimate left over one such round (SCHED_BATCH_SPREAD_COST), or
 * the largest tile's estimate when that is more, so the costliest tiles go
 * alone and cheap ones together.  Without (homo, the fill's whole tiles) a
 * batch is cut by count, over SCHED_BATCH_SPREAD rounds: a count says
 * nothing of the cost, so its batches stay smaller.  Fewer messages is
 * what many workers need (bench/SCALE.md: at 256 workers the master's
 * messages bound the render).  A batch only takes tiles that are ready.  A raster batch
 * takes every (ready / size)-th ready tile, not a run of neighbours:
 * neighbouring tiles cost alike, and a batch of expensive neighbours
 * would make the tail.
 *
 * Fill (hetero, --fill on): while nothing is ready and the pass has not
 * reached every tile, a worker with room gets a whole tile from the
 * bottom of the image up, which it renders from scratch (its primary rays
 * too: PROTO_WORK_RENDER), so no worker waits for the OpenCL set-up or
 * pass.  The tiles claimed that way are the fill's: the feed offers the
 * pass's tiles only above them (sched_fill_front), and the pass stops
 * there.  A fill item has no estimate; it is cut into pieces as the
 * others are (sched_cut), never split by tail.
 *
 * A worker that is lost (its process died) hands its items back
 * (sched_requeue): they go out again before anything else, to whoever
 * asks; sched_release gives a lost worker's static share to the others.
 *
 * Every item records where it went and what it cost (the tile log,
 * host/stats.h).  Items are referred to by their index in `items`, which
 * only grows (pieces are appended), so an index stays valid.
 */
#ifndef HOST_SCHEDULE_H
#define HOST_SCHEDULE_H

#include <stdbool.h>
#include <stdint.h>

#include "../workers/tile.h"

enum sched_policy {
    SCHED_RASTER,
    SCHED_COST,
    SCHED_STATIC,
    SCHED_TAIL,
    SCHED_REGION,
    SCHED_POLICIES
};

#define SCHED_TAIL_TILES_PER_SLOT 2
#define SCHED_BATCH_WORKERS 32 /* auto: batches from this many workers on  */
#define SCHED_BATCH_AUTO 8     /* auto: at most this many items a message   */
#define SCHED_BATCH_SPREAD 4      /* rounds, batches cut by count       */
#define SCHED_BATCH_SPREAD_COST 2 /* rounds, batches cut by estimates   */
#define SCHED_PIECES_WORKERS 128  /* auto: tiles cut from this many workers on */
#define SCHED_PIECES_ITEMS 128    /* auto: ...in 4 when a worker has fewer tiles */
#define SCHED_PIECES_FEWEST 32    /* auto: ...but this many at least         */
#define SCHED_PIECE_MIN 8         /* auto: a quarter's edge at least (pixels) */
#define SCHED_PIECES_MAX 64       /* --pieces: 1, 4, 16 or 64               */

typedef struct {
    tile_rect rect;
    int tile;          /* the tile the rectangle lies in                 */
    int piece;         /* 0: the whole tile; 1 .. 4: a quarter of it (tail),
                          1 .. cuts^2: a piece of it (sched_cut)       */
    bool skipped;      /* degenerate: filled by the master, never sent   */
    bool split;        /* replaced by its pieces: never sent             */
    bool resumed;      /* skipped: its pixels came from the journal of an
                          earlier run (--resume), not from the background */
    bool fill;         /* claimed by the fill: rendered whole, no records */
    uint32_t wire_bytes; /* its pixels' bytes on the wire when compressed
                            (--compress; 0: sent as they are; where the
                            bools leave 4 bytes before the double)     */
    double estimate;   /* estimated ray casts; < 0: unknown (homo)       */
    int order;         /* dispatch order from 0; -1: not sent            */
    int worker;        /* the rank that computed it (0: the master)      */
    double sent_s;     /* stats_clock() when it was sent / started       */
    double done_s;     /* when its result was in                         */
    double busy_s;     /* the worker's seconds on it                     */
    double cpu_s;      /* of them, the CPU time of the worker's thread   */
    uint32_t hits;     /* primary samples that hit                       */
    uint32_t page_faults; /* pages of the scene it waited for (--scene-memory) */
    double page_wait_s;   /* and the seconds it waited                  */
} sched_item;

/* The estimated cost of a rectangle whose records are final. */
typedef double (*sched_estimate_fn)(void *arg, tile_rect r);

typedef struct {
    enum sched_policy policy;
    int workers, in_flight;
    sched_estimate_fn estimate; /* NULL: no estimates                    */
    void *estimate_arg;
    sched_item *items;
    int count, cap;
    int tiles;          /* tiles of the image                            */
    int *fifo;          /* raster order: ready tiles, fifo_head .. fifo_n */
    int fifo_head, fifo_n;
    int *heap;          /* cost order: a max-heap of ready tiles          */
    int heap_n;
    double ready_estimate; /* the ready tiles' estimates (heap or FIFO) */
    int known;          /* tiles added or skipped so far                  */
    double added_estimate; /* the estimates of every tile added          */
    double max_estimate;   /* the largest of them                        */
    int *next_of;       /* static, region: the next item of the same worker */
    int *first, *last;  /* static, region: each worker's queue (-1: empty) */
    int *queued;        /* static, region: each worker's queue's length   */
    int stolen;         /* region: tiles taken from another's band       */
    int added;          /* tiles added (not skipped), for static         */
    int added_items;    /* items queued for them (a cut tile's pieces)   */
    int cuts;           /* a tile added goes as cuts x cuts pieces (1: whole) */
    int front[4];       /* tail: the pieces of the tile being split       */
    int front_head, front_n;
    int *tile_left;     /* items of each tile not yet done                */
    int dispatched;     /* items handed out (a requeued one twice)       */
    int *again;         /* requeued items, again_head .. again_n          */
    int again_head, again_n, again_cap;
    int requeued;       /* items handed back by lost workers             */
    int in_queues;      /* static, region: tiles in the queues, all told
                           (not added - taken: the fill's items are added
                           and never queued)                             */
    bool *released;     /* static: [w] lost, its queue open to all       */
    bool closed;        /* every tile was added or skipped                */
    bool fill;          /* the fill is on (sched_fill_enable)             */
    int fill_front;     /* the fill's tiles: this index and every later  */
    int fill_pieces[SCHED_PIECES_MAX]; /* the pieces of the tile the fill
                           claimed last, not yet handed out (cut tiles)   */
    int fill_pieces_head, fill_pieces_n;
    int filled;         /* tiles the fill claimed                        */
    int batch_floor;    /* a batch takes at least this many items when
                           they are ready (1; a relay's group: more)...  */
    int floor_slots;    /* ...but no more than what is left spread over
                           this many messages (0: no floor)              */
} sched;

const char *sched_policy_name(enum sched_policy p);

/* False when out of memory. */
bool sched_init(sched *s, enum sched_policy p, int workers, int in_flight, int tiles,
                sched_estimate_fn estimate, void *estimate_arg);
void sched_free(sched *s);

/* Every batch takes at least `floor` items (as many as are ready, and
 * within the limit), or what is left over `slots` messages when that is
 * less (so the last items still spread over every relay): the workers are
 * relays (comm/relay.h), each the master of a group that must not run dry
 * while its TILEs are out. */
void sched_batch_floor(sched *s, int floor, int slots);

/* From now on each tile added goes as `pieces` items (1, 4, 16, 64:
 * rounded up to a square of a power of two), before any tile is added;
 * static and region keep whole tiles.  False when out of memory. */
bool sched_cut(sched *s, int pieces);
/* The pieces a tile goes as: `requested` (--pieces N: 1, 4, 16, 64), cut
 * no finer than a pixel on a side (tile edge 2: at most 4), or, for 0
 * (auto), 1 below SCHED_PIECES_WORKERS workers or where the results go
 * `compressed` (a slow link: rank 0's bytes bound the frame, and pieces
 * add headers and compress less), else 4 when whole tiles would give a
 * worker fewer than SCHED_PIECES_ITEMS items but SCHED_PIECES_FEWEST at
 * least and the quarters have edges of SCHED_PIECE_MIN pixels at least.
 * Never 16 or 64 unless asked: at 1024 workers rank 0's work on 16 parts
 * a tile bounds the frame, and with rank 0's measured work a part charged
 * even 4 do (16 tiles a worker: 42.3 % against 55.8 % whole). */
int sched_pieces_auto(int requested, int workers, int tiles, int tile_edge, bool compressed);

/* Tile `tile` (rectangle r) is ready to be sent / is degenerate. */
bool sched_add(sched *s, int tile, tile_rect r);
bool sched_skip(sched *s, int tile, tile_rect r);
/* Tile `tile` was finished by an earlier run (--resume): skipped too. */
bool sched_resume(sched *s, int tile, tile_rect r);
/* No more tiles will come. */
void sched_close(sched *s);

/* The next item for worker `w` (0 .. workers - 1), marked sent (order and
 * sent_s = now), or -1 when none is ready for it now. */
int sched_next(sched *s, int w, double now);
/* Item `item`, handed out to a worker that was lost, is to go out again;
 * false when out of memory. */
bool sched_requeue(sched *s, int item);
/* Worker w (0 .. workers - 1) is lost: static gives its queue (and the
 * tiles added for it later) to whoever asks. */
void sched_release(sched *s, int w);
/* Closed and every item handed out. */
bool sched_finished(const sched *s);
/* Items ready to be handed out now (sched_next would give one). */
int sched_ready(const sched *s);
/* The most items one message may carry: `requested` (--batch N, 1 ..
 * max) or, for 0 (auto), SCHED_BATCH_AUTO from SCHED_BATCH_WORKERS
 * workers on and 1 below. */
int sched_batch_limit(int requested, int workers, int max);
/* How many items the next message may take, 1 .. limit
 * (sched_next_batch may cut it by the estimates). */
int sched_batch(const sched *s, int limit);
/* The items of the next message for worker w, at most `limit`, into
 * out[] (each handed out as by sched_next); how many (0: none ready). */
int sched_next_batch(sched *s, int w, double now, int limit, int *out);
/* The fill on: tiles may be claimed from the last one up (hetero). */
void sched_fill_enable(sched *s);
/* The first tile the fill claimed (s->tiles when none): the feed offers
 * only the tiles before it. */
int sched_fill_front(const sched *s);
/* The fill claims the last unclaimed tile when the feed has offered
 * fewer than `offered` .. that tile: its index, or -1 (the fill is off, or
 * no tile below the feed's front is left).  The caller then queues it
 * with sched_next_fill, or, should it need no rendering (resumed), with
 * sched_resume. */
int sched_fill_claim(sched *s, int offered);
/* How many fill items the next message may take, 1 .. limit: guided as
 * sched_batch, by the tiles neither the fill nor the feed has yet. */
int sched_fill_batch(const sched *s, int limit);
/* Claimed tile `tile` (rectangle r) is degenerate: filled by the master,
 * never sent (skipped, as sched_skip's). */
bool sched_fill_skip(sched *s, int tile, tile_rect r);
/* Claimed tile `tile` (rectangle r) handed out at once as a fill item
 * (marked sent as by sched_next); the item, or -1 when out of memory.
 * A cut tile (sched_cut) goes as its pieces: the first now, the others
 * by sched_next_fill_piece (or sched_next) before any other tile is
 * claimed. */
int sched_next_fill(sched *s, double now, int tile, tile_rect r);
/* The next piece of the tile the fill claimed last, marked sent; -1 when
 * none is left. */
int sched_next_fill_piece(sched *s, double now);
/* Item `item` is done; true when that completes its tile. */
bool sched_done(sched *s, int item);

#endif
