/*
 * protocol.h — the master/worker tile protocol, in this one place.  The
 * master (master.c) owns it; the worker side is workers/worker.c; both
 * move bytes through mpi_link.h only.
 *
 * Ranks of MPI_COMM_WORLD: 0 is the master, 1 .. K-1 are workers.  Every
 * message is ONE message of bytes: a fixed-size header struct of this
 * file, followed by its payload when it has one.  The receiver knows the
 * largest message it can be sent (proto_*_limit) and refuses a larger one
 * before taking a byte of it (link_recv), then checks the size against
 * the header.
 *
 * 1. Setup (broadcasts, every rank, from the master):
 *      proto_setup                       status first: 0 go on; otherwise
 *                                        every rank exits with it (2: the
 *                                        scene is bad, 1: other failure)
 *      blob bytes                        only when status == 0: blob_size
 *                                        bytes, once per node: to the node
 *                                        leaders, whose ranks then map
 *                                        the leader's copy (link_scene)
 *    The node's leader validates the bytes (csg_blob_valid) for its node;
 *    a worker picks engine_for_blob and allocates its tile buffers
 *    (workers/tile.h: tile_runner).
 * 2. Handshake: every worker sends the master exactly one message,
 *      PROTO_TAG_READY (proto_ready)  or  PROTO_TAG_FAIL (proto_fail).
 * 3. Work (demand-driven: each worker is kept PROTO_IN_FLIGHT messages
 *    of work ahead, so it never waits on the master between two; the
 *    master's scheduler, host/schedule.h, decides which items go next and
 *    how many go in one message, 1 .. proto_setup.batch):
 *      master -> worker  PROTO_TAG_TILE    k >= 1 parts, each:
 *                          proto_tile: a rectangle inside tile `index`
 *                          (the whole tile, or a piece of it)
 *                          [PROTO_WORK_SHADE: the rectangle's packed hit
 *                           records, tiles.h (tile_pack_records);
 *                           PROTO_WORK_SHADE_ANSWERED: then their shadow
 *                           answers (tile_pack_answers)]
 *      worker -> master  PROTO_TAG_RESULT  k parts, in the TILE's order,
 *                                          each proto_result (its
 *                                          paging counts only with
 *                                          PROTO_RESULT_PAGING:
 *                                          proto_result_head) + the n
 *                                          pixels in proto_result.pixels:
 *                                          rgb[3 n] float, or (when the
 *                                          setup's pixels is RGB8) the
 *                                          3 n bytes of the 8-bit file
 *                                          (comm/pixels.h), or (RGB8Z)
 *                                          those bytes compressed, one
 *                                          Zstandard frame of
 *                                          proto_result.payload bytes
 *                                          (comm/pixels_z.h)
 *                   or   PROTO_TAG_FAIL    proto_fail (for the whole TILE)
 *    Parts follow one another, each starting 8-byte aligned (zero bytes
 *    pad the one before; nothing follows the last): a TILE of one part
 *    is exactly the single item's header and payload.  k <= batch, the
 *    limit broadcast in the setup (1: one item a message).
 *    Every TILE gets exactly one answer.  A worker answers first in,
 *    first out, and holds at most PROTO_IN_FLIGHT; a relay answers each
 *    TILE once all its parts are answered, in whatever order they end
 *    (else one costly part would hold back every TILE after it, and with
 *    them rank 0's room to send the group more: bench/SCALE.md, *relays
 *    answer as their TILEs end*).  The master finds the TILE an answer
 *    belongs to by its first part (proto_result's index, x and y), a FAIL
 *    by its oldest.
 *    Large messages go in the background on both sides (link_isend): the
 *    master never waits on a busy worker, a worker never on the master.
 *    A worker whose answer breaks the protocol (wrong size, tile or tag)
 *    is written off: the master expects nothing more from it.  A worker
 *    whose process dies (or that hangs) is lost: written off too, its
 *    items sent again to the others, whatever it sent before dying
 *    dropped (host/master.c; liveness: comm/mpi_link.h).
 * 4. End: master -> every worker not lost PROTO_TAG_STOP (proto_stop), sent
 *    only when no live worker holds an item (results drained).  The worker exits with
 *    proto_stop.status, so every rank ends with the master's status.
 *
 * Relays (--relays K > 0, for many workers: bench/SCALE.md): ranks 1 .. K
 * are relays, a second level of masters (comm/relay.h); every other
 * worker rank r belongs to relay proto_parent(r, K) and speaks the
 * protocol above with it instead of rank 0.  To rank 0 a relay is one
 * worker that holds up to PROTO_RELAY_IN_FLIGHT TILEs and answers each
 * with one RESULT (or FAIL), as soon as every part of it is done, so not
 * always in order (step 3); each part of its RESULT names in
 * proto_result.rank the worker that computed it.  The
 * setup broadcast still goes to every rank, and rank 0 still watches
 * every rank's process (mpi_link.h): a relay or any worker of its group lost
 * loses the whole group at once.
 *
 * Tiles are numbered as in tiles.h (tile_rect_of).  Headers hold
 * fixed-width fields only, each a multiple of 8 bytes, so a payload that
 * follows starts 8-byte aligned.  The ranks must share one byte order (the
 * blob is sent as bytes too).
 */
#ifndef COMM_PROTOCOL_H
#define COMM_PROTOCOL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "tiles.h"
#include "pixels.h"
#include "pixels_z.h"

enum proto_tag {
    PROTO_TAG_READY = 1, /* worker: set up, waiting for tiles  */
    PROTO_TAG_TILE,      /* master: render / shade this tile    */
    PROTO_TAG_RESULT,    /* worker: the tile's pixels           */
    PROTO_TAG_FAIL,      /* worker: cannot go on (text)         */
    PROTO_TAG_STOP       /* master: exit with this status       */
};

/* What a TILE asks for. */
enum proto_work {
    PROTO_WORK_RENDER = 0, /* homo: trace the primary rays and shade   */
    PROTO_WORK_SHADE = 1,  /* hetero: shade from the records sent       */
    PROTO_WORK_SHADE_ANSWERED = 2 /* hetero --simd shadows: the records,
                              then their shadow answers (tile_pack_answers) */
};

typedef struct {
    int32_t status;     /* 0: the blob follows; else exit status      */
    int32_t tile;       /* tile edge in pixels                         */
    uint64_t blob_size; /* bytes of the blob broadcast next            */
    int32_t batch;      /* parts in one TILE at most: 1 .. PROTO_BATCH_MAX */
    int32_t pixels;     /* enum pixels_format of the RESULTs: RGB8 when
                           the output is an 8-bit file                 */
    int32_t relays;     /* ranks 1 .. relays are relays (0: none)      */
    int32_t ranks;      /* of the job, rank 0 included                 */
    uint64_t scene_memory; /* > 0: each worker holds the scene within
                              this many bytes (workers/pager.h): the
                              broadcast is the resident part and the
                              page plan, blob_size bytes of it          */
    int32_t page_policy;   /* enum pager_policy                         */
    int32_t page_prefetch; /* enum pager_prefetch (workers/pager.h): 1 an
                              item's pages fetched in one request before
                              its rays, 2 its shadow rays' too          */
    int32_t page_homes;    /* > 0: the pages' homes are the workers
                              (--page-home spread, workers/pager.h): each
                              holds its share and answers the others'
                              asks; 0: rank 0 serves every page         */
    int32_t page_fetch;    /* enum pager_fetch_mode: GET, every rank opens
                              rank 0's blob as a window once the resident
                              part is in (link_page_window)             */
} proto_setup;

/* The largest batch (--batch), and the most bytes a batch's RESULT may
 * take (a batch of one may take more). */
#define PROTO_BATCH_MAX 32
#define PROTO_BATCH_BYTES ((size_t)2 << 20)

typedef struct {
    int32_t status;       /* 0 */
    int32_t scene_shared; /* ranks behind this READY (a worker: itself; a
                             relay: itself and its group) that read their
                             node's one copy of the scene in place
                             (comm/mpi_link.h: link_scene)              */
} proto_ready;

/* proto_ready.scene_shared of a READY's bytes (0 when it is short). */
static inline int proto_ready_scene_shared(const char *data, size_t len)
{
    proto_ready r = {0, 0};
    if (len >= sizeof r)
        memcpy(&r, data, sizeof r);
    return r.scene_shared;
}

/* Work items a worker holds at most: the one it computes and the next. */
#define PROTO_IN_FLIGHT 2
/* TILEs a relay holds at most: its group's work while parts of them are
 * computed.  How many rank 0 keeps there (proto_relay_depth) depends on
 * the order of the work and on the group: without estimates (homo,
 * raster) a TILE a worker of the group, at least PROTO_RELAY_DEPTH; with
 * them (hetero, the costly tiles first) one for two workers, at least
 * PROTO_RELAY_DEPTH_COST.  Simulated on InfiniBand (bench/SCALE.md): at
 * 256 workers (groups of 16, four runs each, *the results' headers*) a
 * depth of 16 against 8 gave homo 82.0 % against 78.5 % and hetero
 * 78.1 % against 84.1 %: a deeper queue hides rank 0's answer behind
 * more work, but commits the costly tiles to a group early, and the
 * groups' stocks end uneven; at 1024 (groups of 32, *relays answer as
 * their TILEs end*) 16 TILEs were 16 items a worker, and the groups ran
 * dry waiting for rank 0: 32 and 16 instead. */
#define PROTO_RELAY_IN_FLIGHT 32
#define PROTO_RELAY_DEPTH 16
#define PROTO_RELAY_DEPTH_COST 8
#define PROTO_DEPTH_MAX PROTO_RELAY_IN_FLIGHT
/* The TILEs rank 0 keeps at a relay of `group` workers, the order of the
 * work knowing costs or not (see PROTO_RELAY_IN_FLIGHT). */
static inline int proto_relay_depth(int group, int costs)
{
    int least = costs ? PROTO_RELAY_DEPTH_COST : PROTO_RELAY_DEPTH;
    int want = costs ? group / 2 : group;
    return want < least ? least : want > 2 * least ? 2 * least : want;
}

/* The rank rank r takes its TILEs from: 0, or its relay when there are
 * `relays` (the workers dealt round-robin over them). */
static inline int proto_parent(int r, int relays)
{
    return relays > 0 && r > relays ? 1 + (r - relays - 1) % relays : 0;
}

/* The j-th worker (j = 0, 1, ...) of relay `relay`: proto_parent's inverse. */
static inline int proto_member(int relay, int j, int relays)
{
    return relays + relay + j * relays;
}

/* How many workers relay `relay` has in a job of `ranks` (relay 1 has the
 * most). */
static inline int proto_group(int relay, int ranks, int relays)
{
    int first = proto_member(relay, 0, relays);
    return first < ranks ? (ranks - 1 - first) / relays + 1 : 0;
}

/* The fewest items in a TILE to a relay (schedule.h's sched_batch_floor),
 * with `ranks` - 1 workers of which `relays` relay, each holding `depth`
 * TILEs: enough to keep each worker of the largest group PROTO_IN_FLIGHT
 * items deep. */
static inline int proto_relay_batch_floor(int ranks, int relays, int depth)
{
    int group = proto_group(1, ranks, relays);
    return (2 * PROTO_IN_FLIGHT * group + depth - 1) / depth;
}

typedef struct {
    int32_t index;          /* tile number, row-major                  */
    int32_t work;           /* enum proto_work                         */
    int32_t x, y;           /* top-left pixel of the rectangle         */
    int32_t width, height;  /* its pixels: inside tile `index`         */
} proto_tile;

typedef struct {
    int32_t index;          /* the tile of the rectangle answered      */
    uint32_t hits;          /* primary samples that hit                */
    int32_t x, y;           /* the rectangle's top-left pixel: with
                               index, which item this part answers (a
                               relay answers its TILEs in any order)   */
    uint64_t primary, shadow, reflected, refracted; /* rays traced    */
    uint64_t over_budget;   /* pixels that met their ray budget        */
    uint64_t shadow_answered; /* shadow rays answered by the records   */
    double busy_s;          /* seconds the worker spent on the part:
                               tracing it and converting its pixels    */
    double cpu_s;           /* of them, its thread's CPU time          */
    int32_t pixels;         /* enum pixels_format of the pixels after  */
    int32_t rank;           /* the worker that computed it (a relay's
                               answer; a worker sends 0: itself)       */
    uint32_t payload;       /* PIXELS_RGB8Z: the compressed bytes after
                               the header (else 0)                     */
    uint32_t flags;         /* PROTO_RESULT_*                          */
    page_counts paging;     /* its scene paging during the part: on the
                               wire only with PROTO_RESULT_PAGING      */
} proto_result;

/* proto_result.flags: the paging counts follow (a worker below a scene
 * budget sends them; without one they would be 120 zero bytes a part,
 * 2 MB of a 4096x4096 frame in tiles of 32). */
#define PROTO_RESULT_PAGING 1u

/* The bytes of a result header on the wire: all of it, or all but its
 * paging counts (a multiple of 8 either way: the pixels stay aligned). */
#define PROTO_RESULT_HEAD_MIN offsetof(proto_result, paging)
static inline size_t proto_result_head(const proto_result *h)
{
    return (h->flags & PROTO_RESULT_PAGING) ? sizeof *h : PROTO_RESULT_HEAD_MIN;
}

/* The header at p, `avail` bytes there, into h (its paging counts zero
 * when they are not sent): its bytes on the wire, 0 when avail is less. */
static inline size_t proto_result_read(const char *p, size_t avail, proto_result *h)
{
    if (avail < PROTO_RESULT_HEAD_MIN)
        return 0;
    memcpy(h, p, PROTO_RESULT_HEAD_MIN);
    size_t head = proto_result_head(h);
    if (avail < head)
        return 0;
    if (head > PROTO_RESULT_HEAD_MIN)
        memcpy(&h->paging, p + PROTO_RESULT_HEAD_MIN, sizeof h->paging);
    else
        memset(&h->paging, 0, sizeof h->paging);
    return head;
}

/* h at p as it goes on the wire: its bytes. */
static inline size_t proto_result_write(char *p, const proto_result *h)
{
    size_t head = proto_result_head(h);
    memcpy(p, h, head);
    return head;
}

#define PROTO_FAIL_TEXT 240
typedef struct {
    int32_t index;               /* the tile that failed; -1: setup    */
    int32_t pad;
    char text[PROTO_FAIL_TEXT];  /* NUL-terminated, one line           */
} proto_fail;

typedef struct {
    int32_t status; /* the exit status of the whole run */
    int32_t pad;
} proto_stop;

/* Where the part after one that ends at `end` begins. */
static inline size_t proto_align(size_t end)
{
    return (end + 7) & ~(size_t)7;
}

/* `batch` parts of at most `part` bytes each, aligned as above. */
static inline size_t proto_batch_bytes(size_t part, int batch)
{
    return (size_t)(batch > 1 ? batch - 1 : 0) * proto_align(part) + part;
}

/* One TILE part: header, and the records (shade) of n pixels. */
static inline size_t proto_tile_part(const tile_grid *g, int work, size_t n)
{
    return sizeof(proto_tile) + (work != PROTO_WORK_RENDER ? tile_records_bytes(g, n) : 0) +
           (work == PROTO_WORK_SHADE_ANSWERED ? tile_answers_bytes(g, n) : 0);
}

/* The TILE part of `data` (len bytes) at offset `at`: its header into h,
 * checked against its tile and the bytes that are there; where it ends,
 * or 0 with the reason in *why. */
static inline size_t proto_tile_part_at(const tile_grid *g, const char *data, size_t len,
                                        size_t at, proto_tile *h, const char **why)
{
    if (at > len || len - at < sizeof *h) {
        *why = "truncated tile message";
        return 0;
    }
    memcpy(h, data + at, sizeof *h);
    tile_rect r = {h->x, h->y, h->width, h->height};
    if (!tile_rect_in_tile(g, h->index, r)) {
        *why = "tile outside the image";
        return 0;
    }
    if (h->work != PROTO_WORK_SHADE && h->work != PROTO_WORK_RENDER &&
        h->work != PROTO_WORK_SHADE_ANSWERED) {
        *why = "malformed tile message";
        return 0;
    }
    size_t part = proto_tile_part(g, h->work, (size_t)r.width * (size_t)r.height);
    if (len - at < part) {
        *why = "malformed tile message";
        return 0;
    }
    return at + part;
}

/* One RESULT part at most: header (with its paging counts) and n pixels
 * in `format` (enum pixels_format; PIXELS_RGB8Z: at most this,
 * proto_result_part_of). */
static inline size_t proto_result_part(size_t n, int format)
{
    return sizeof(proto_result) + n * pixels_bytes(format);
}

/* The bytes of a RESULT part of n pixels in `format` whose header is h:
 * its header's on the wire (proto_result_head) and its pixels', or for
 * PIXELS_RGB8Z its payload, which must be within what n pixels can
 * compress to; 0 when it is not. */
static inline size_t proto_result_part_of(const proto_result *h, size_t n, int format)
{
    if (format != PIXELS_RGB8Z)
        return proto_result_head(h) + n * pixels_bytes(format);
    return h->payload <= pixels_compress_bound(n * 3) ? proto_result_head(h) + h->payload : 0;
}

/* The most bytes a RESULT part of n pixels takes in any format: floats,
 * or, for a part of a few pixels, what compressed bytes can take at worst
 * (a frame's header and checksum: up to 66 bytes for 3). */
static inline size_t proto_result_part_max(size_t n)
{
    size_t floats = proto_result_part(n, PIXELS_FLOAT);
    size_t compressed = sizeof(proto_result) + pixels_compress_bound(n * 3);
    return floats > compressed ? floats : compressed;
}

/* `batch`, lowered so that a RESULT of that many tiles of pixels_max
 * pixels stays within PROTO_BATCH_BYTES; at least 1. */
static inline int proto_batch_fit(int batch, size_t pixels_max)
{
    while (batch > 1 && proto_batch_bytes(proto_result_part_max(pixels_max), batch) >
                            PROTO_BATCH_BYTES)
        batch--;
    return batch;
}

/* The largest message a worker can be sent: a TILE of `batch` parts with
 * the records of the largest tile (a STOP is smaller). */
static inline size_t proto_worker_limit(const tile_grid *g, int batch)
{
    return proto_batch_bytes(proto_tile_part(g, PROTO_WORK_SHADE_ANSWERED, g->pixels_max), batch);
}

/* The largest message the master can be sent: the RESULT of `batch` of
 * the largest tiles (proto_result_part_max: any part may be so large), or
 * a FAIL. */
static inline size_t proto_master_limit(size_t pixels_max, int batch)
{
    size_t result = proto_batch_bytes(proto_result_part_max(pixels_max), batch);
    return result > sizeof(proto_fail) ? result : sizeof(proto_fail);
}

/* *buf (*cap bytes; its send done) holds at least `len` bytes: grown when
 * not (a batch's TILE on the master, its RESULT on a worker); false, the
 * buffer unchanged, when out of memory. */
static inline bool proto_buffer(char **buf, size_t *cap, size_t len)
{
    if (*cap >= len)
        return true;
    char *grown = realloc(*buf, len);
    if (!grown)
        return false;
    *buf = grown;
    *cap = len;
    return true;
}

#endif
