/*
 * master.c — rank 0 of the tile protocol described in protocol.h.
 *
 * Algorithm (demand-driven self-scheduling, as in Tachyon and the classic
 * examples, kept PROTO_IN_FLIGHT deep):
 *   1. broadcast the status, then the blob (with --scene-memory: the
 *      blob's resident part and its page plan, workers/pager.h);
 *   2. receive one handshake (READY or FAIL) from every worker;
 *   3. an event loop until every item is answered: feed the scheduler
 *      (the tiles of the OpenCL slices completed since the last turn),
 *      answer every page a paged worker asks for (its ray waits on it),
 *      fill every live worker up to PROTO_IN_FLIGHT messages (first one
 *      each, then the second, so the items at the head of the order go to
 *      idle workers; a message carries the items of sched_next_batch: one
 *      unless the workers are many and much is left), take every message
 *      waiting; only when a turn found nothing to do, the idle wait
 *      (link_idle: poll, then nap; the pass's completion callback ends a
 *      nap at once);
 *   4. STOP(status) to every worker (master_end).
 * A FAIL or a failed feed ends the sending of items; the outstanding ones
 * are still drained so that no rank blocks in a send, then every worker
 * gets STOP(1).  A worker whose answer breaks the protocol (size, tile,
 * tag) is written off: its outstanding items are not waited for, its
 * pending sends are left to MPI.  Nothing is ever aborted for bad input:
 * the only abort (code 1) is a message too large to take (mpi_link.c).
 *
 * A dead worker does not end the render: a worker whose process is gone
 * (link_peer_lost: its watchdog socket closed; or its message cut off:
 * LINK_LOST), or that holds its oldest item longer than
 * max(MASTER_HANG_MEANS x the mean item time, MASTER_HANG_MIN_S) (hung:
 * its socket is closed, which makes it exit), is lost: written off like
 * a protocol breaker, but its items go back to the scheduler
 * (sched_requeue) and out to the others, and whatever it still sends is
 * dropped.  Lost workers are looked for in every turn that found nothing
 * to do.  When none is left, master_run_tiles returns with the scheduler
 * unfinished and the caller renders the rest in-process.
 *
 * The nap cap follows the work: a quarter of the mean item time so far
 * (MASTER_NAP_*), so a result that lands during a nap waits less than a
 * quarter of what the worker's second item gives it; the master checks
 * the feed and the messages before every nap and never naps after a turn
 * that did something.  With more ranks than cores a nap's end must also
 * get a core: the master asks the OS for a short time slice
 * (link_respond_quickly), so it preempts a busy worker at once instead of
 * waiting for the worker's slice to run out (measured on 2 cores, homo
 * 384x384: workers busy 88-90 % of the tile phase without it, 93-95 % with).
 *
 * Relays (--relays K, relay.h): rank 0 then deals only to ranks 1 .. K
 * (m->children), each holding up to master_depth batches (PROTO_RELAY_*)
 * sized for its group (the scheduler counts K consumers and keeps a floor:
 * sched_batch_floor); a part of a relay's RESULT names the worker that
 * computed it, and its stats go to that worker.  Rank 0 still watches
 * every process: a relay whose process or any worker's is gone, or whose
 * oldest batch is overdue, is lost with its whole group (their watchdog
 * sockets closed), its batches requeued.
 *
 * Invariants: workers[r] holds the batches of items rank r computes, at
 * most the job's depth, each in a slot with its send buffer and request
 * (a slot is reused once its batch is answered, so its send is done); an
 * answer has one part per item, in order, and belongs to the oldest batch
 * of a worker, or of a relay to the batch its first part names (a relay
 * answers as its batches end, protocol.h); STOP only
 * goes once no live worker holds an item; a send buffer is reused or
 * freed only when its send is done; no message larger than the largest
 * RESULT is taken (link_recv's limit); the bytes counters count every
 * message's whole size.
 */
#include "master.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exit_status.h"
#include "memory.h"
#include "output/journal.h"
#include "output/stream.h"
#include "../comm/mpi_link.h"
#include "../comm/protocol.h"
#include "../comm/test_hooks.h"
#include "store.h"

#define MASTER_NAP_FIRST_NS 50000L  /* before any item came back            */
#define MASTER_NAP_MIN_NS 2000L
#define MASTER_PAGE_NAP_NS 10000L /* paging: an ASK waits half a nap on average */
#define MASTER_SPINS 50

void master_begin(master_session *m, int ranks)
{
    memset(m, 0, sizeof *m);
    m->workers = ranks > 1 ? ranks - 1 : 0;
    m->children = m->workers;
    m->lost = m->workers > 0 ? calloc((size_t)m->workers + 1, sizeof *m->lost) : NULL;
    m->lost_before = m->lost ? calloc((size_t)m->workers + 1, sizeof *m->lost_before) : NULL;
    for (int r = 1; m->lost_before && r <= m->workers; r++)
        m->lost_before[r] = link_peer_gone_before(r);
}

/* The workers of rank r's group: a relay's, none for a worker. */
static int master_group_size(const master_session *m, int r)
{
    return r >= 1 && r <= m->relays ? proto_group(r, m->workers + 1, m->relays) : 0;
}

/* Rank r is lost (it died or hung): one line on stderr, once a job. */
static void master_mark_lost(master_session *m, int r, int items, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static void master_mark_lost(master_session *m, int r, int items, const char *fmt, ...)
{
    char why[160];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    link_forget(r);
    if (m->lost)
        m->lost[r] = true;
    m->workers_lost++;
    int group = 0;
    for (int k = 0; k < master_group_size(m, r); k++) {
        int j = proto_member(r, k, m->relays);
        link_forget(j); /* (a relay goes with its group: they exit) */
        group += m->lost && !m->lost[j];
        if (m->lost)
            m->lost[j] = true;
    }
    m->workers_lost += group;
    if (m->lost_before && m->lost_before[r])
        return; /* reported by the render that lost it */
    if (r <= m->relays)
        fprintf(stderr, "csgtrace: relay %d and its %d workers lost (%s): %d item%s handed to "
                        "the others\n", r, group, why, items, items == 1 ? "" : "s");
    else
        fprintf(stderr, "csgtrace: worker %d lost (%s): %d item%s handed to the others\n", r,
                why, items, items == 1 ? "" : "s");
    fflush(stderr);
}

static bool master_is_lost(const master_session *m, int r)
{
    return m->lost && r >= 1 && r <= m->workers && m->lost[r];
}

/* Rank r's process is gone, or (a relay) one of its group's (never true
 * without the lost table). */
static bool master_peer_gone(const master_session *m, int r)
{
    if (!m->lost || m->lost[r])
        return false;
    if (link_peer_lost(r))
        return true;
    for (int k = 0; k < master_group_size(m, r); k++)
        if (link_peer_lost(proto_member(r, k, m->relays)))
            return true;
    return false;
}

/* Every page request waiting, answered (link_page_serve's packer). */
static size_t master_pack_pages(void *arg, const int32_t *pages, int n, unsigned char **out)
{
    master_session *m = arg;
    size_t bytes = pager_pack_pages(m->page_blob, &m->plan, pages, n, out);
    if (m->costs)
        m->costs->pages(bytes);
    m->page_bytes_served += bytes;
    return bytes;
}

static bool master_serve_pages(master_session *m)
{
    if (!m->page_blob)
        return false;
    int served = link_page_serve(master_pack_pages, m);
    m->page_asks += (uint64_t)served;
    return served > 0;
}

/* Pages read one-sided (--page-fetch get) where they can be: not under
 * --enable-recovery, where a rank may be gone before the window's
 * collective creation. */
static bool master_pages_one_sided(const master_session *m)
{
    return m->page_fetch == PAGER_FETCH_GET && !link_survives_loss();
}

int master_plan_pages(master_session *m, void *blob, size_t size, uint64_t budget,
                      uint64_t page_bytes, int policy, int prefetch, int home, csg_diag *d)
{
    const char *why = NULL;
    uint64_t page = page_bytes > 0 ? page_bytes : pager_page_bytes_for(budget);
    bool laid_out = pager_relayout(blob, page, &why);
    if (laid_out && !csg_blob_valid(blob, size)) {
        laid_out = false; /* (a bug: the same tree, renumbered) */
        why = "the BVH laid out for paging is not valid";
    }
    if (!laid_out || !pager_plan_make(blob, page, &m->plan, &why)) {
        csg_error_plain(d, "--scene-memory: %s", why);
        return EXIT_FAILURE_RUN;
    }
    if (m->plan.resident_bytes > budget) {
        char need[32], have[32];
        csg_error_plain(d, "--scene-memory %s is below the scene's resident part, %s (its "
                           "header, the top of its BVH, materials and lights)",
                        memory_format(budget, have, sizeof have),
                        memory_format(m->plan.resident_bytes, need, sizeof need));
        return EXIT_BAD_INPUT;
    }
    /* (auto: homes serve only asks; one-sided reads leave rank 0 idle, and
     * at 256 simulated workers beat homes, bench/PAGING.md) */
    if (home == PAGER_HOME_AUTO && master_pages_one_sided(m))
        home = PAGER_HOME_MASTER;
    int32_t homes = pager_homes_for(home, m->workers, &m->plan, budget);
    if (homes < 0) {
        char share[32], have[32];
        csg_error_plain(d, "--page-home spread: a worker's share of the pages, %s, does not fit in "
                           "two thirds of what --scene-memory %s leaves beside the resident part "
                           "(more workers, or a larger budget)",
                        memory_format(pager_home_share(&m->plan, m->workers > 0 ? m->workers : 1),
                                      share, sizeof share),
                        memory_format(budget, have, sizeof have));
        return EXIT_BAD_INPUT;
    }
    m->page_homes = homes;
    m->scene_memory = budget;
    m->page_policy = policy;
    m->page_prefetch = prefetch;
    return EXIT_OK;
}

void master_share_scene(master_session *m, int status, int tile, csg_blob *blob)
{
    if (m->workers == 0 || m->shared)
        return;
    if (m->relays < 0 || m->relays >= m->workers)
        m->relays = 0; /* (the command line refuses these) */
    m->children = m->relays > 0 ? m->relays : m->workers;
    /* a relay's batches feed a group: auto is as large as they go */
    m->batch = m->relays > 0 && m->batch == 0
                   ? PROTO_BATCH_MAX
                   : sched_batch_limit(m->batch, m->workers, PROTO_BATCH_MAX);
    if (status == 0) /* (a batch's RESULT within PROTO_BATCH_BYTES) */
        m->batch = proto_batch_fit(m->batch, tile_grid_of(blob->bytes, tile).pixels_max);
    size_t packed_size = 0;
    void *packed = NULL;
    if (status == 0 && m->scene_memory > 0) { /* (the plan: render.c's, checked) */
        packed = pager_pack_resident(blob->bytes, &m->plan, &packed_size);
        if (!packed)
            status = EXIT_FAILURE_RUN; /* (the workers exit at once) */
    }
    proto_setup setup = {status, tile, status == 0 ? blob->size : 0, m->batch, m->pixels,
                         m->relays, m->workers + 1, 0, m->page_policy, m->page_prefetch,
                         0, 0};
    if (packed) {
        setup.blob_size = packed_size;
        setup.scene_memory = m->scene_memory;
        setup.page_homes = m->page_homes;
        /* (homes answer their own pages) */
        setup.page_fetch =
            master_pages_one_sided(m) && m->page_homes == 0 ? PAGER_FETCH_GET : PAGER_FETCH_ASK;
    }
    link_bcast_idle(&setup, sizeof setup);
    m->bytes_sent += (uint64_t)m->workers * sizeof setup;
    m->shared = true;
    if (status != 0) {
        m->greeted = m->stopped = true; /* the workers exit at once */
        return;
    }
    if (packed) { /* each worker: the resident part; pages on demand */
        link_bcast(packed, packed_size);
        m->bytes_sent += (uint64_t)m->workers * packed_size;
        free(packed);
        m->page_blob = blob->bytes;
        if (setup.page_fetch == PAGER_FETCH_GET)
            m->page_window = link_page_window(blob->bytes, blob->size);
        return;
    }
    link_scene_send(&m->scene, blob->bytes, blob->size, csg_blob_valid);
    m->bytes_sent += (uint64_t)m->scene.copies_sent * blob->size; /* (once a node) */
    if (m->scene.shared) { /* the node's copy is the master's from now on */
        free(blob->bytes);
        blob->bytes = m->scene.bytes;
    }
}

void master_release_scene(master_session *m, csg_blob *blob)
{
    pager_plan_free(&m->plan);
    m->page_blob = NULL;
    if (blob->bytes && blob->bytes == link_page_window_blob()) {
        link_page_window_hold(blob->bytes); /* (read one-sided: see there) */
        blob->bytes = NULL;
    }
    if (m->scene.shared)
        blob->bytes = NULL;
    link_scene_free(&m->scene);
}

/* ---- receiving ------------------------------------------------------------ */

/* A receive that gave no message, reported; a message too large to take
 * leaves the job unable to go on (link_broken: master_end aborts). */
static void master_recv_failed(master_session *m, const link_msg *msg, link_status got,
                               size_t limit, csg_diag *d)
{
    if (got != LINK_TOO_BIG) {
        csg_error_plain(d, "master: receiving from the workers failed");
        return;
    }
    m->bytes_received += (uint64_t)msg->len;
    csg_error_plain(d, "worker %d: a %zu-byte message (tag %d), larger than any answer "
                       "(%zu bytes): the job is ended",
                    msg->source, msg->len, msg->tag, limit);
    m->link_broken = true; /* the message cannot be drained */
}

/* The text of a FAIL message, NUL-terminated whatever was sent. */
static void master_fail_text(const link_msg *msg, int *tile, char *text, size_t size)
{
    proto_fail f;
    memset(&f, 0, sizeof f);
    memcpy(&f, msg->data, msg->len < sizeof f ? msg->len : sizeof f);
    f.text[PROTO_FAIL_TEXT - 1] = '\0';
    *tile = msg->len >= sizeof f ? f.index : -1;
    snprintf(text, size, "%s", f.text[0] ? f.text : "no reason given");
}

static void master_report_fail(const master_session *m, const link_msg *msg, csg_diag *d)
{
    int tile;
    char text[PROTO_FAIL_TEXT];
    master_fail_text(msg, &tile, text, sizeof text);
    if (msg->source <= m->relays) /* (a relay's text names the worker itself) */
        csg_error_plain(d, "%s", text);
    else if (tile >= 0)
        csg_error_plain(d, "worker %d failed on tile %d: %s", msg->source, tile, text);
    else
        csg_error_plain(d, "worker %d failed: %s", msg->source, text);
}

/* Rank r (a relay: or one of its group) waits for the scene from its
 * node's leader, which is gone: it would wait for ever (comm/mpi_link.h:
 * link_node_leader).  That leader, or 0. */
static int master_leader_gone(const master_session *m, int r)
{
    for (int k = -1; k < master_group_size(m, r); k++) {
        int who = k < 0 ? r : proto_member(r, k, m->relays);
        int leader = link_node_leader(who);
        if (leader != who && leader > 0 && link_peer_lost(leader))
            return leader;
    }
    return 0;
}

/* The workers that died before their handshake, or whose node's leader
 * did; how many. */
static int master_greeters_lost(master_session *m, const bool *greeted)
{
    int n = 0;
    for (int r = 1; r <= m->children; r++) {
        int leader = 0;
        if (greeted[r] || (m->lost && m->lost[r]))
            continue;
        if (master_peer_gone(m, r)) {
            master_mark_lost(m, r, 0, "its process is gone");
            n++;
        } else if ((leader = master_leader_gone(m, r)) > 0) {
            master_mark_lost(m, r, 0, "its node's leader, rank %d, is gone: no scene", leader);
            n++;
        }
    }
    return n;
}

/* A handshake message taken: READY, or the setup failed. */
static void master_greeting(master_session *m, const link_msg *msg, csg_diag *d)
{
    m->bytes_received += (uint64_t)msg->len;
    if (msg->tag == PROTO_TAG_READY) {
        m->scene_shared += proto_ready_scene_shared(msg->data, msg->len);
        return;
    }
    m->setup_failed = true;
    if (msg->tag == PROTO_TAG_FAIL)
        master_report_fail(m, msg, d);
    else
        csg_error_plain(d, "worker %d: unexpected message (tag %d) at start-up", msg->source,
                        msg->tag);
}

/* Step 2: one READY or FAIL from every worker that is not lost. */
static void master_greet(master_session *m, link_msg *msg, csg_diag *d)
{
    bool *greeted = calloc((size_t)m->workers + 1, sizeof *greeted);
    link_idle idle;
    link_idle_init(&idle, LINK_NAP_MAX_NS, MASTER_SPINS);
    for (int left = m->children; greeted && left > 0 && !m->link_broken;) {
        link_status got = link_try_recv(msg, LINK_ANY_SOURCE, sizeof(proto_fail));
        if (got == LINK_NONE) {
            left -= master_greeters_lost(m, greeted);
            link_idle_step(&idle);
        } else if (got == LINK_LOST || master_is_lost(m, msg->source)) {
            if (!master_is_lost(m, msg->source)) { /* (a lost one's last words: dropped) */
                left -= !greeted[msg->source];
                master_mark_lost(m, msg->source, 0, "its process is gone");
            }
        } else if (got != LINK_OK) {
            master_recv_failed(m, msg, got, sizeof(proto_fail), d);
            m->setup_failed = true;
            break;
        } else {
            greeted[msg->source] = true;
            left--;
            master_greeting(m, msg, d);
        }
    }
    if (!greeted)
        csg_error_plain(d, "master: out of memory");
    m->setup_failed |= !greeted;
    link_idle_free(&idle);
    free(greeted);
    m->greeted = true;
}

/* ---- the workers' items ------------------------------------------------ */

/* A worker holding its oldest item longer than this is taken for hung:
 * MASTER_HANG_MEANS x the mean item time, at least MASTER_HANG_MIN_S
 * (generous: a live worker written off costs its items twice and the
 * worker itself; on a loaded machine, or with the costliest tiles first,
 * a live one can take seconds). */
#define MASTER_HANG_MEANS 10.0
#define MASTER_HANG_MIN_S 10.0

typedef struct {
    int item[PROTO_DEPTH_MAX][PROTO_BATCH_MAX]; /* held batches, a slot each */
    int count[PROTO_DEPTH_MAX];    /* items in each; 0: the slot is free   */
    long order[PROTO_DEPTH_MAX];   /* when each was sent (sends before it) */
    long sends;                    /* batches sent so far                  */
    int n;                         /* slots held (the job's depth at most) */
    char *buf[PROTO_DEPTH_MAX];    /* the TILE of slot k                   */
    size_t cap[PROTO_DEPTH_MAX];   /* its bytes (grown to the batch's)     */
    link_req req[PROTO_DEPTH_MAX]; /* and its send                        */
    bool dead;                     /* written off: nothing more expected   */
    double since;                  /* stats_clock(): the oldest item began  */
} master_worker;

typedef struct {
    master_session *m;
    master_job *job;
    master_worker *w;        /* [1 .. workers]                            */
    int outstanding;         /* batches held by live workers               */
    bool failed;             /* no more items go out; draining             */
    bool broken;             /* nothing can be received any more           */
    double checked;          /* stats_clock() of the last liveness check   */
    pixels_zstream *decompressor; /* PIXELS_RGB8Z without the store thread */
    uint8_t *unpacked;       /* a part decompressed there (pixels_max x 3) */
    int depth;               /* batches a child holds at most: master_depth */
} master_loop;

/* Batches a child holds at most in a job scheduled by s: a worker
 * PROTO_IN_FLIGHT; a relay proto_relay_depth for the largest group and
 * the order (comm/protocol.h says why). */
static int master_depth(const master_session *m, const sched *s)
{
    if (m->relays <= 0)
        return PROTO_IN_FLIGHT;
    return proto_relay_depth(proto_group(1, m->workers + 1, m->relays), s->estimate != NULL);
}

static void master_lose(master_loop *L, int r, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

bool master_idle_init(link_idle *idle)
{
    link_respond_quickly();
    return link_idle_init(idle, MASTER_NAP_FIRST_NS, MASTER_SPINS);
}

bool master_shades(const master_job *job, int item)
{
    return job->t && !job->retrace && !job->sched->items[item].fill;
}

int master_work(const master_job *job, int item)
{
    if (!master_shades(job, item))
        return PROTO_WORK_RENDER;
    return job->known ? PROTO_WORK_SHADE_ANSWERED : PROTO_WORK_SHADE;
}

/* One part of a TILE: item `item`'s header (and records) at `out`; its
 * bytes. */
static size_t master_pack_item(const master_job *job, int item, char *out)
{
    const tile_grid *g = &job->grid;
    const sched_item *it = &job->sched->items[item];
    tile_rect rect = it->rect;
    int work = master_work(job, item);
    size_t n = (size_t)rect.width * (size_t)rect.height;
    proto_tile h = {it->tile, work, rect.x, rect.y, rect.width, rect.height};
    memcpy(out, &h, sizeof h);
    if (work != PROTO_WORK_RENDER)
        tile_pack_records(g, job->t, job->surf, rect, out + sizeof h);
    if (work == PROTO_WORK_SHADE_ANSWERED)
        tile_pack_answers(g, job->known, job->lit, rect,
                          out + sizeof h + tile_records_bytes(g, n));
    return proto_tile_part(g, work, n);
}

/* The bytes of the TILE for items[0 .. k - 1]. */
static size_t master_tile_bytes(const master_job *job, const int *items, int k)
{
    size_t len = 0;
    for (int i = 0; i < k; i++) {
        tile_rect r = job->sched->items[items[i]].rect;
        len = proto_align(len) + proto_tile_part(&job->grid, master_work(job, items[i]),
                                                 (size_t)r.width * (size_t)r.height);
    }
    return len;
}

/* A free slot of w (one is: w->n < the depth). */
static int master_free_slot(const master_loop *L, const master_worker *w)
{
    int k = 0;
    while (k < L->depth - 1 && w->count[k] > 0)
        k++;
    return k;
}

/* The slot of w's oldest batch (w->n > 0). */
static int master_oldest_slot(const master_loop *L, const master_worker *w)
{
    int oldest = -1;
    for (int k = 0; k < L->depth; k++)
        if (w->count[k] > 0 && (oldest < 0 || w->order[k] < w->order[oldest]))
            oldest = k;
    return oldest;
}

/* Items items[0 .. k - 1] to rank r in one TILE. */
static bool master_send_batch(master_loop *L, int r, const int *items, int k, csg_diag *d)
{
    master_worker *w = &L->w[r];
    int pos = master_free_slot(L, w);
    if (!proto_buffer(&w->buf[pos], &w->cap[pos], master_tile_bytes(L->job, items, k))) {
        csg_error_plain(d, "master: out of memory");
        return false;
    }
    size_t len = 0;
    for (int i = 0; i < k; i++) {
        size_t at = proto_align(len);
        memset(w->buf[pos] + len, 0, at - len); /* the padding between parts */
        len = at + master_pack_item(L->job, items[i], w->buf[pos] + at);
        w->item[pos][i] = items[i]; /* held from now on: a lost worker hands it back */
    }
    w->count[pos] = k;
    w->order[pos] = w->sends++;
    if (w->n++ == 0)
        w->since = stats_clock();
    L->outstanding++;
    if (link_isend(r, PROTO_TAG_TILE, w->buf[pos], len, &w->req[pos]) != LINK_OK) {
        if (master_peer_gone(L->m, r)) {
            master_lose(L, r, "its process is gone");
            return true;
        }
        csg_error_plain(d, "master: sending a tile to worker %d failed", r);
        return false;
    }
    L->m->bytes_sent += len;
    L->m->tile_messages++;
    return true;
}

/* Room at rank r for one more batch: a free slot, whose send buffer is
 * free too (its TILE was answered, so the send is done, unless the worker
 * died). */
static bool master_room(master_loop *L, int r, int depth)
{
    master_worker *w = &L->w[r];
    if (w->dead || w->n >= depth)
        return false;
    link_req *q = &w->req[master_free_slot(L, w)];
    if (q->active && link_req_wait(q) == LINK_LOST) {
        master_lose(L, r, "its process is gone");
        return false;
    }
    return true;
}

/* Nothing (more) ready: fill items for one message into items[], at most
 * `room` (as many as a batch of ready items would hold: guided by what is
 * left, so the last ones go alone); how many (L->failed when out of
 * memory). */
static int master_fill_batch(master_loop *L, double now, int *items, int room, csg_diag *d)
{
    int want = sched_fill_batch(L->job->sched, L->m->batch), k = 0;
    want = want < room ? want : room;
    for (; k < want; k++) {
        int item = sched_next_fill_piece(L->job->sched, now); /* (the claimed tile's, cut) */
        if (item < 0)
            item = L->job->fill(L->job, now, d);
        if (item < 0) {
            L->failed |= item == -2;
            break;
        }
        items[k] = item;
    }
    return k;
}

/* Every live worker filled up to PROTO_IN_FLIGHT batches, one level at
 * a time; true when something was sent. */
static bool master_dispatch(master_loop *L, csg_diag *d)
{
    bool sent = false;
    for (int depth = 1; depth <= L->depth && !L->failed; depth++) {
        for (int r = 1; r <= L->m->children && !L->failed; r++) {
            if (!master_room(L, r, depth))
                continue;
            double now = stats_clock();
            int items[PROTO_BATCH_MAX];
            int k = sched_next_batch(L->job->sched, r - 1, now, L->m->batch, items);
            /* the pass's ready tiles ran out before the batch was full: the
             * fill's top it up (else a pass slower than the workers keeps
             * their stocks at what it trickles while the fill waits:
             * bench/SCALE.md, *tiles cut into pieces*) */
            if (k < L->m->batch && L->job->fill && sched_ready(L->job->sched) == 0)
                k += master_fill_batch(L, now, items + k, L->m->batch - k, d);
            if (k == 0)
                continue;
            if (L->job->t_first == 0)
                L->job->t_first = now;
            if (!master_send_batch(L, r, items, k, d))
                L->failed = true;
            sent = true;
        }
    }
    return sent;
}

/* Rank r broke the protocol: expect nothing more from it. */
static void master_write_off(master_loop *L, int r)
{
    L->outstanding -= L->w[r].n;
    L->w[r].n = 0;
    memset(L->w[r].count, 0, sizeof L->w[r].count);
    L->w[r].dead = true;
}

/* Rank r is lost: written off, its items back to the scheduler (oldest
 * first), its static share to the others. */
static void master_lose(master_loop *L, int r, const char *fmt, ...)
{
    master_worker *w = &L->w[r];
    char why[128];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    int held = 0;
    for (int k = 0; k < L->depth; k++)
        held += w->count[k];
    master_mark_lost(L->m, r, held, "%s", why);
    while (w->n > 0 && !L->failed) { /* (oldest first) */
        int pos = master_oldest_slot(L, w);
        for (int i = 0; i < w->count[pos] && !L->failed; i++)
            if (!sched_requeue(L->job->sched, w->item[pos][i]))
                L->failed = true; /* (out of memory: the render cannot end well) */
        w->count[pos] = 0;
        w->n--;
        L->outstanding--;
    }
    sched_release(L->job->sched, r - 1);
    master_write_off(L, r);
}

/* The oldest item's time limit, 0 before any item came back (the test
 * hook CSGTRACE_TEST_HANG_S sets the floor: the tests' silent workers are
 * written off sooner). */
static double master_hang_limit(const master_job *job)
{
    if (job->items_done == 0)
        return 0.0;
    double mean = job->busy_s / job->items_done;
    long long floor_s = test_hook_number(TEST_HANG_S, 3601);
    double least = floor_s > 0 ? (double)floor_s : MASTER_HANG_MIN_S;
    return mean * MASTER_HANG_MEANS > least ? mean * MASTER_HANG_MEANS : least;
}

/* How many items' time worker w's oldest batch may take: its items one
 * after the other, or at a relay, spread over its group (each worker has
 * one more item ahead of them). */
static double master_hang_items(const master_loop *L, int r, const master_worker *w)
{
    const master_session *m = L->m;
    int items = w->count[master_oldest_slot(L, w)];
    if (m->relays == 0)
        return items;
    int group = master_group_size(m, r);
    return (items + group - 1) / (group > 0 ? group : 1) + PROTO_IN_FLIGHT;
}

/* Liveness is checked at most this often while idle: a check polls every
 * worker's watchdog socket, a system call each (one worker: a fifth of
 * rank 0's samples went there; 256 workers: ~80 us an idle step, in the
 * way of the next answer).  A lost worker is still seen within 2 ms. */
#define MASTER_CHECK_EVERY_S 0.002

/* Every live worker that died or hung, lost; how many live ones are left. */
static int master_check_workers(master_loop *L)
{
    double now = stats_clock(), limit = master_hang_limit(L->job);
    int live = 0;
    for (int r = 1; r <= L->m->children; r++) {
        master_worker *w = &L->w[r];
        if (w->dead)
            continue;
        if (master_peer_gone(L->m, r))
            master_lose(L, r, "its process is gone");
        else if (limit > 0 && w->n > 0 && now - w->since > limit * master_hang_items(L, r, w))
            master_lose(L, r, "no answer for %.1f s", now - w->since);
        else
            live++;
    }
    return live;
}

/* The sends of every worker done (or, for one written off or a broken
 * link, left to MPI with their buffers), the buffers freed. */
static void master_close_sends(master_loop *L)
{
    for (int r = 1; r <= L->m->children; r++) {
        for (int k = 0; k < PROTO_DEPTH_MAX; k++) {
            link_req *q = &L->w[r].req[k];
            if (!link_req_done(q) && (L->w[r].dead || L->broken)) {
                link_req_abandon(q); /* its buffer stays MPI's */
                continue;
            }
            if (link_req_wait(q) == LINK_OK) /* (LINK_LOST: MPI's too) */
                free(L->w[r].buf[k]);
        }
    }
}

/* ---- answers ---------------------------------------------------------------- */

/* The bytes of the RESULT for items[0 .. k - 1], each part in the
 * session's pixel format; false with d filled when a part's header names
 * another. */
static bool master_result_bytes(const master_job *job, const link_msg *msg, const int *items,
                                int k, int session, size_t *len, csg_diag *d)
{
    *len = 0;
    for (int i = 0; i < k; i++) {
        tile_rect r = job->sched->items[items[i]].rect;
        size_t n = (size_t)r.width * (size_t)r.height;
        size_t at = proto_align(*len);
        proto_result h = {.pixels = session}; /* (cut off: the least it can be) */
        if (at <= msg->len && proto_result_read(msg->data + at, msg->len - at, &h) > 0) {
            if (h.pixels != session) {
                csg_error_plain(d, "worker %d: result of tile %d in another pixel format",
                                msg->source, job->sched->items[items[i]].tile);
                return false;
            }
        }
        size_t part = proto_result_part_of(&h, n, session);
        if (part == 0) {
            csg_error_plain(d, "worker %d: result of tile %d: %u compressed bytes for %zu pixels",
                            msg->source, job->sched->items[items[i]].tile, (unsigned)h.payload, n);
            return false;
        }
        *len = at + part;
    }
    return true;
}

/* A PIXELS_RGB8Z part's `in_bytes` decompressed into L->unpacked: exactly
 * `bytes` bytes, or false (the context and the buffer made on first use). */
static bool master_decompress(master_loop *L, const uint8_t *in, size_t in_bytes, size_t bytes)
{
    if (!L->decompressor) {
        L->decompressor = pixels_decompressor_new();
        L->unpacked = malloc(L->job->grid.pixels_max * 3);
    }
    return L->decompressor && L->unpacked && bytes <= L->job->grid.pixels_max * 3 &&
           pixels_decompress(L->decompressor, in, in_bytes, L->unpacked, bytes);
}

/* Rectangle r's 8-bit bytes into the image: queued for the store thread,
 * or stored here (no thread, or its ring full). */
static void master_store_bytes(master_job *job, tile_rect r, const uint8_t *rgb8)
{
    if (!job->store || !store_queue(job->store, r, rgb8))
        pixels_store_bytes_rect(job->image, job->grid.width, r.x, r.y, r.width, r.height, rgb8);
}

/* Worker `by`'s part for item `item` did not decompress to its rectangle:
 * the render's error (false). */
static bool master_corrupt_part(const master_job *job, int by, int item, csg_diag *d)
{
    csg_error_plain(d, "worker %d: result of tile %d: its compressed pixels are corrupt", by,
                    job->sched->items[item].tile);
    return false;
}

/* A compressed part the store thread could not decompress (its tag is the
 * item): the render failed, its worker written off as for any bad
 * answer; false then. */
static bool master_check_stored(master_loop *L, csg_diag *d)
{
    int32_t item = store_corrupt(L->job->store);
    if (item < 0 || L->failed)
        return item < 0;
    int by = L->job->sched->items[item].worker; /* (counted when it was queued) */
    master_corrupt_part(L->job, by, item, d);
    L->failed = true;
    int child = L->m->relays > 0 && by > L->m->relays ? proto_parent(by, L->m->relays) : by;
    if (child >= 1 && child <= L->m->children && !L->w[child].dead)
        master_write_off(L, child);
    return false;
}

/* Part `part` of a RESULT (its size already checked) for item `item`:
 * checked, stored, counted. */
static bool master_take_part(master_loop *L, const link_msg *msg, const char *part, int item,
                             csg_diag *d)
{
    master_job *job = L->job;
    const master_session *m = L->m;
    const sched_item *it = &job->sched->items[item];
    tile_rect r = it->rect;
    size_t n = (size_t)r.width * (size_t)r.height;
    proto_result h = {0};
    size_t head = proto_result_read(part, SIZE_MAX, &h); /* (its size checked) */
    /* a relay's part names its worker (one of the relay's group) */
    int by = m->relays > 0 && h.rank > m->relays && h.rank <= m->workers &&
                     proto_parent(h.rank, m->relays) == msg->source
                 ? h.rank
                 : msg->source;
    if (h.index != it->tile || h.hits > n * (size_t)job->grid.spp) {
        csg_error_plain(d, "worker %d: result for tile %d does not match tile %d sent", by,
                        (int)h.index, it->tile);
        return false;
    }
    if (h.x != r.x || h.y != r.y) {
        csg_error_plain(d, "worker %d: result for tile %d at %d,%d, sent at %d,%d", by,
                        (int)h.index, (int)h.x, (int)h.y, r.x, r.y);
        return false;
    }
    /* msg->data is malloc'd, parts start 8-byte aligned and a header's
     * bytes are a multiple of 8: floats aligned */
    const char *pixels = part + head;
    if (h.pixels == PIXELS_RGB8Z) {
        job->sched->items[item].wire_bytes = h.payload;
        /* the store thread decompresses it (store_corrupt says if it cannot) */
        bool queued = job->store && store_queue_compressed(job->store, r, (const uint8_t *)pixels,
                                                           h.payload, item);
        if (!queued && !master_decompress(L, (const uint8_t *)pixels, h.payload, n * 3))
            return master_corrupt_part(job, by, item, d);
        if (!queued) /* (no thread, or its ring full) */
            master_store_bytes(job, r, L->unpacked);
    } else if (!pixels_is_rgb8(h.pixels)) {
        tile_store_rgb(job->image, job->grid.width, r, (const float *)(const void *)pixels);
    } else {
        master_store_bytes(job, r, (const uint8_t *)pixels);
    }
    tile_result res = {h.hits, {h.primary, h.shadow, h.reflected, h.refracted, h.over_budget,
                                 h.shadow_answered},
                       h.busy_s, h.cpu_s, h.paging, false};
    master_job_count(job, &job->workers[by - 1], by, item, &res, stats_clock());
    if (m->costs) /* (the simulated build: what a real master took) */
        m->costs->part(n, h.pixels, h.payload);
    return true;
}

/* A RESULT for items[0 .. k - 1] of the job, its parts in the session's
 * pixel format `session`: checked, stored, counted. */
static bool master_take_result(master_loop *L, const link_msg *msg, const int *items, int k,
                               csg_diag *d)
{
    master_job *job = L->job;
    const master_session *m = L->m;
    int session = m->pixels;
    size_t expected;
    if (!master_result_bytes(job, msg, items, k, session, &expected, d))
        return false;
    if (msg->len != expected) {
        csg_error_plain(d, "worker %d: result of tile %d has %zu bytes, expected %zu",
                        msg->source, job->sched->items[items[0]].tile, msg->len, expected);
        return false;
    }
    if (m->costs)
        m->costs->message();
    size_t at = 0;
    for (int i = 0; i < k; i++) {
        if (!master_take_part(L, msg, msg->data + at, items[i], d))
            return false;
        tile_rect r = job->sched->items[items[i]].rect;
        proto_result h = {0};
        proto_result_read(msg->data + at, msg->len - at, &h); /* (master_result_bytes checked) */
        size_t n = (size_t)r.width * (size_t)r.height;
        at = proto_align(at + proto_result_part_of(&h, n, session));
    }
    return true;
}

/* The slot of rank src's batch that msg answers: a relay's RESULT names
 * it by its first part (tile and rectangle, read into *h: relays answer
 * as their batches end), anything else answers the oldest; -1 when the
 * part names none of the relay's batches (a relay breaking the protocol). */
static int master_answered_slot(const master_loop *L, int src, const link_msg *msg,
                                proto_result *h)
{
    const master_worker *w = &L->w[src];
    if (L->m->relays == 0 || L->failed || msg->tag != PROTO_TAG_RESULT ||
        proto_result_read(msg->data, msg->len, h) == 0)
        return master_oldest_slot(L, w);
    for (int k = 0; k < L->depth; k++) {
        if (w->count[k] == 0)
            continue;
        const sched_item *first = &L->job->sched->items[w->item[k][0]];
        if (first->tile == h->index && first->rect.x == h->x && first->rect.y == h->y)
            return k;
    }
    return -1;
}

/* One message from a worker, taken: the answer to one of its batches
 * (master_answered_slot). */
static void master_answer(master_loop *L, const link_msg *msg, csg_diag *d)
{
    int src = msg->source;
    if (master_is_lost(L->m, src))
        return; /* sent before it died: its items went to the others */
    if (src < 1 || src > L->m->children || L->w[src].dead || L->w[src].n == 0) {
        if (!L->failed)
            csg_error_plain(d, "unexpected message (tag %d) from rank %d", msg->tag, src);
        L->failed = true;
        if (src >= 1 && src <= L->m->children)
            master_write_off(L, src);
        return;
    }
    master_worker *w = &L->w[src];
    proto_result h;
    int slot = master_answered_slot(L, src, msg, &h);
    if (slot < 0) {
        csg_error_plain(d, "relay %d: result for tile %d at %d,%d, none of its tiles sent", src,
                        (int)h.index, (int)h.x, (int)h.y);
        L->failed = true;
        master_write_off(L, src);
        return;
    }
    if (slot != master_oldest_slot(L, w))
        L->m->answers_early++; /* (a relay's: a costly part held back no other) */
    const int *items = w->item[slot];
    int k = w->count[slot];
    w->count[slot] = 0;
    w->n--;
    w->since = stats_clock(); /* the next item's turn */
    L->outstanding--;
    csg_diag ignored = {{0}, 0};
    csg_diag *report = L->failed ? &ignored : d; /* the first failure is the one reported */
    if (msg->tag == PROTO_TAG_FAIL) {
        master_report_fail(L->m, msg, report); /* it still answers its other items */
        L->failed = true;
        return;
    }
    bool ok = msg->tag == PROTO_TAG_RESULT;
    if (!ok)
        csg_error_plain(report, "worker %d: unexpected message (tag %d)", src, msg->tag);
    else if (L->failed)
        ok = msg->len >= PROTO_RESULT_HEAD_MIN; /* draining: an answer, not stored */
    else
        ok = master_take_result(L, msg, items, k, d);
    if (!ok) {
        L->failed = true;
        master_write_off(L, src);
    }
    test_hook_kill(0, "item", L->job->items_done);
}

/* An answer's seconds, t0 to t1, added to the master's time taking
 * results in, as far as they fall in the tile phase: none before the
 * first item out; those after the latest result's arrival (t_last, the
 * tile phase's end so far) kept apart too, since the tile phase may end
 * there: the last result's own storing and the answers after it belong to
 * the phase that follows (a master preempted there once took more
 * "results" time than the tile phase lasted). */
static void master_results_time(master_job *job, double t0, double t1, double t_last_before)
{
    if (job->t_first == 0)
        return;
    t0 = t0 > job->t_first ? t0 : job->t_first;
    job->results_s += t1 - t0;
    if (job->t_last != t_last_before) /* a result: the tile phase lasts to here */
        job->results_past_s = t1 - job->t_last;
    else
        job->results_past_s += t1 - t0;
}

/* Every message waiting, taken and answered; true when there was one. */
static bool master_receive(master_loop *L, link_msg *msg, size_t limit, csg_diag *d)
{
    bool any = false;
    /* At most a message a child a turn, then back to the loop, which
     * hands out again: draining every waiting answer first left the
     * children without work while their answers queued (simulated, 256
     * workers, hetero's fill of cheap tiles: 4096 items out at once, the
     * next sent 1.3 ms later; bench/SCALE.md).  A turn of the dispatch
     * checks each child's depth, so a message a child keeps its share of
     * the loop small. */
    for (int taken = 0; !L->broken && taken < L->m->children; taken++) {
        link_status got = link_try_recv(msg, LINK_ANY_SOURCE, limit);
        if (got == LINK_NONE)
            break;
        any = true;
        if (got == LINK_LOST) { /* it died in the middle of a message */
            if (!master_is_lost(L->m, msg->source))
                master_lose(L, msg->source, "its process is gone");
            continue;
        }
        if (got != LINK_OK) {
            csg_diag ignored = {{0}, 0};
            master_recv_failed(L->m, msg, got, limit, L->failed ? &ignored : d);
            L->failed = L->broken = true; /* nothing can be drained past it */
            break;
        }
        L->m->bytes_received += (uint64_t)msg->len;
        double t0 = stats_clock(), t_last = L->job->t_last;
        master_answer(L, msg, d);
        master_results_time(L->job, t0, stats_clock(), t_last);
    }
    return any;
}

/* ---- the loop ------------------------------------------------------------------- */

static bool master_feed(master_loop *L, csg_diag *d)
{
    master_job *job = L->job;
    if (L->failed || job->sched->closed || !job->feed)
        return false;
    int known = job->feed(job, false, d);
    if (known < 0)
        L->failed = true;
    return known != 0;
}

/* A quarter of the mean item time so far, within bounds. */
static long master_nap_cap(const master_job *job)
{
    if (job->items_done == 0)
        return MASTER_NAP_FIRST_NS;
    long quarter = (long)(job->busy_s / job->items_done * 0.25e9);
    return quarter < MASTER_NAP_MIN_NS   ? MASTER_NAP_MIN_NS
           : quarter > LINK_NAP_MAX_NS   ? LINK_NAP_MAX_NS
                                         : quarter;
}

static bool master_done(const master_loop *L)
{
    return L->broken || (L->outstanding == 0 && (L->failed || sched_finished(L->job->sched)));
}

/* Tile `tile` is final in the image: to the journal and to the image's
 * stream (host/output/stream.h). */
static void master_tile_final(master_job *job, int tile)
{
    journal_tile_done(job->journal, tile, job->image);
    img_stream_tile(job->stream, tile);
}

/* The complete tiles the store thread has put in the image since the
 * last call, final; with `wait`, every one, once stored. */
static void master_tiles_stored(master_job *job, bool wait)
{
    int tile;
    while (job->store && store_finished(job->store, &tile, wait))
        master_tile_final(job, tile);
}

/* Step 3 once the handshake is done: false with d filled on a failure. */
static bool master_deal(master_loop *L, link_idle *idle, csg_diag *d)
{
    link_msg msg = {NULL, 0, 0, 0, 0};
    size_t limit = proto_master_limit(L->job->grid.pixels_max, L->m->batch);
    while (!master_done(L)) {
        bool worked = master_feed(L, d);
        worked |= master_serve_pages(L->m); /* (a worker's ray waits for it) */
        worked |= master_dispatch(L, d);
        worked |= master_receive(L, &msg, limit, d);
        if (L->job->store)
            master_check_stored(L, d);
        master_tiles_stored(L->job, false);
        if (worked) {
            link_idle_reset(idle);
            continue;
        }
        double now = stats_clock();
        if (now - L->checked >= MASTER_CHECK_EVERY_S) {
            L->checked = now;
            if (master_check_workers(L) == 0)
                break; /* every worker lost: the caller does the rest */
        }
        idle->nap_max_ns = master_nap_cap(L->job);
        if (L->m->page_blob && idle->nap_max_ns > MASTER_PAGE_NAP_NS)
            idle->nap_max_ns = MASTER_PAGE_NAP_NS; /* (a worker's ray waits on each ASK) */
        link_idle_step(idle);
    }
    link_msg_free(&msg);
    return !L->failed;
}

bool master_run_tiles(master_session *m, master_job *job, csg_diag *d)
{
    master_loop L = {m, job, calloc((size_t)m->workers + 1, sizeof *L.w), 0, false, false, 0.0,
                     NULL, NULL, master_depth(m, job->sched)};
    link_idle own;
    link_idle *idle = job->idle ? job->idle : &own;
    bool ok = false;
    if (!job->idle)
        master_idle_init(&own);
    for (int r = 1; r <= m->workers; r++)
        job->workers[r - 1].rank = r;
    if (!L.w) {
        csg_error_plain(d, "master: out of memory");
    } else {
        if (!m->greeted) {
            link_msg msg = {NULL, 0, 0, 0, 0};
            master_greet(m, &msg, d);
            link_msg_free(&msg);
        }
        for (int r = 1; r <= m->children; r++)
            L.w[r].dead = master_is_lost(m, r); /* (lost before the handshake) */
        ok = !m->setup_failed && master_deal(&L, idle, d);
        master_close_sends(&L);
    }
    if (m->costs)
        m->costs->drain();
    if (job->store) { /* the image whole before the caller reads it */
        store_drain(job->store);
        if (L.w)
            ok = master_check_stored(&L, d) && ok;
        master_tiles_stored(job, true);
    }
    if (!job->idle)
        link_idle_free(&own);
    pixels_zstream_free(L.decompressor);
    free(L.unpacked);
    free(L.w);
    return ok;
}

int master_relay_floor(const master_session *m, sched *s)
{
    if (m->relays <= 0)
        return 0;
    int depth = master_depth(m, s); /* (each relay's group kept fed) */
    sched_batch_floor(s, proto_relay_batch_floor(m->workers + 1, m->relays, depth),
                      m->relays * depth);
    return depth;
}

void master_job_count(master_job *job, stats_worker *w, int rank, int item,
                      const tile_result *res, double now)
{
    sched_item *it = &job->sched->items[item];
    it->worker = rank;
    it->done_s = now;
    it->busy_s = res->busy_s;
    it->cpu_s = res->cpu_s;
    it->hits = res->hits;
    it->page_faults = (uint32_t)res->paging.faults;
    it->page_wait_s = res->paging.wait_s;
    page_counts_add(&w->paging, &res->paging);
    page_counts_add(&job->paging, &res->paging);
    w->items++;
    w->hits += res->hits;
    w->busy_s += res->busy_s;
    stats_add_rays(&w->rays, &res->rays);
    stats_add_rays(&job->rays, &res->rays);
    job->busy_s += res->busy_s;
    job->items_done++;
    job->t_last = now;
    if (!job->t || it->fill) /* (hetero counts its others from the OpenCL tile hits) */
        job->pixels_hit += res->hits;
    journal_add_hits(job->journal, it->tile, res->hits);
    if (sched_done(job->sched, item)) { /* its tile is complete */
        if (!job->store || store_after(job->store, it->tile)) /* (else once it is stored) */
            master_tile_final(job, it->tile);
        w->tiles++;
        if (job->progress)
            progress_step(job->progress);
    }
}

/* STOP(status) to rank r, unless it is lost first. */
static void master_stop(master_session *m, int r, int status)
{
    proto_stop *stop = malloc(sizeof *stop); /* (a send to a dead rank keeps it) */
    link_req req;
    if (!stop)
        return; /* (the worker exits when this process does) */
    stop->status = status;
    stop->pad = 0;
    if (link_isend(r, PROTO_TAG_STOP, stop, sizeof *stop, &req) != LINK_OK ||
        link_req_wait(&req) == LINK_OK)
        free(stop);
    m->bytes_sent += sizeof *stop;
}

static void master_stop_all(master_session *m, int status)
{
    if (m->link_broken) /* its message was reported: no rank can go on */
        link_abort(status ? status : 1);
    if (!m->shared) {
        master_share_scene(m, status ? status : 1, 0, NULL);
        return;
    }
    if (!m->greeted) {
        link_msg msg = {NULL, 0, 0, 0, 0};
        csg_diag ignored = {{0}, 0};
        master_greet(m, &msg, &ignored); /* the master already failed: its message stands */
        link_msg_free(&msg);
    }
    if (!m->stopped) {
        for (int r = 1; r <= m->children; r++) /* (a relay passes it on) */
            if (!master_is_lost(m, r))
                master_stop(m, r, status);
        m->stopped = true;
    }
}

void master_end(master_session *m, int status)
{
    if (m->workers > 0)
        master_stop_all(m, status);
    free(m->lost);
    free(m->lost_before);
    m->lost = NULL;
    m->lost_before = NULL;
}
