/*
 * worker.c — a worker rank of the tile protocol (comm/protocol.h).
 *
 * Algorithm: take part in the setup broadcast; take the blob (this node's one
 * copy, validated once: comm/mpi_link.h, link_scene) and set
 * up a tile runner for it (workers/tile.h); send READY (or FAIL with the
 * reason); then answer every TILE with one RESULT (tile_run_rect over the
 * rectangle of each of its parts, the parts' answers in one message) or
 * one FAIL, first in first out, until STOP, whose status is returned.
 *
 * Two items in flight (protocol.h): the master sends the next TILE while
 * this one is computed.  Before each item the worker takes every message
 * already waiting (without waiting: a large TILE is delivered only once it
 * is taken), so the next item is here when this one ends; it waits (poll,
 * then nap) only with nothing queued.  A RESULT goes in the background
 * (link_isend) from one of PROTO_IN_FLIGHT buffers, so the worker starts
 * the next item at once; a buffer is reused only once its send is done.
 * A RESULT over MPI's eager limit (a tile of 64, a batch, floats) moves on
 * only while this rank calls MPI, so the worker does between bands of an
 * item and between the parts of a batch (link_progress: worker_progress,
 * workers/tile.h); the master has it while the next item is computed.
 *
 * With --scene-memory (the setup's scene_memory) the broadcast is the
 * scene's resident part and its page plan, not the blob: the worker reads
 * the scene through its pager (workers/pager.h), which asks rank 0 for a
 * page when a ray needs one and waits for it (comm/mpi_link.h,
 * link_page_fetch); a fetch that fails fails the item.
 *
 * The master's death ends the worker at once (mpi_link.h: its watchdog), so
 * no worker outlives it.
 *
 * Invariants: the worker never prints (the master reports once; the one
 * exception is the line of a worker whose master died) and never
 * exits on its own after the setup: even when it failed it keeps answering
 * until STOP, so that the master can drain and nobody blocks.  No message
 * larger than the largest TILE is ever taken (link_recv's limit), and a
 * tile message is checked against the tile it claims before any byte of
 * it is used.  Every send is done before the worker returns.
 */
#include "worker.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../comm/mpi_link.h"
#include "../comm/protocol.h"
#include "../comm/relay.h"
#include "../comm/test_hooks.h"
#include "pager.h"
#include "tile.h"

/* Messages taken and not yet answered: the items in flight and a STOP. */
#define WORKER_QUEUE (PROTO_IN_FLIGHT + 1)
#define WORKER_FILL_BYTES ((uint64_t)256 << 10) /* a home's share asked of rank 0 in these */
#define WORKER_FILL_PAGES 256
#define WORKER_FILL_NAP_NS 10000L

typedef struct {
    int rank;
    const char *page_trace; /* $CSGTRACE_PAGE_TRACE (pager.h), or NULL */
    int parent;           /* the rank TILEs come from: 0 or a relay   */
    int tiles_done;
    char failure[PROTO_FAIL_TEXT]; /* "" or why this worker cannot work */
    link_scene scene;     /* the blob: this rank's, or its node's one
                             copy, mapped (comm/mpi_link.h)            */
    struct {              /* --page-home spread: the share filled in the
                             background, an ask of rank 0 at a time */
        link_page_async *ask;
        int32_t pages[WORKER_FILL_PAGES];
        int count;
        unsigned char *bytes;
        size_t cap;
        bool begun, ended;
        unsigned asks_ended;   /* (worker_fill_wait's)                    */
    } fill;
    csg_pager pager;      /* --scene-memory: the scene in pages, its
                             resident part from the broadcast          */
    bool paged;
    const void *blob;     /* what the runner reads: the scene's bytes or
                             the pager's address space                 */
    tile_runner runner;   /* set up once the blob is valid            */
    link_msg queue[WORKER_QUEUE]; /* messages from the master, in order */
    bool stop_queued;             /* the STOP is in the queue: what comes
                                     after it is the next render's (under
                                     --enable-recovery its scene comes as
                                     plain messages: link_bcast)          */
    int head, queued;     /* the oldest, and how many                 */
    size_t in_limit;      /* the largest message it may send us       */
    int batch;            /* parts in one TILE at most (the setup's)  */
    int pixels;           /* enum pixels_format asked for (the setup's) */
    float *rgb;           /* PIXELS_RGB8(Z): a part's floats, converted */
    uint8_t *rgb8;        /* PIXELS_RGB8Z: a part's bytes, to compress */
    pixels_zstream *compressor; /* PIXELS_RGB8Z: kept between parts   */
    char *out[PROTO_IN_FLIGHT];     /* RESULTs: one part at first,    */
    size_t out_cap[PROTO_IN_FLIGHT]; /* grown to a batch's bytes       */
    link_req out_req[PROTO_IN_FLIGHT]; /* their sends                 */
    int out_next;         /* the buffer of the next RESULT            */
} worker_state;

static void worker_set_failure(worker_state *w, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

static void worker_set_failure(worker_state *w, const char *fmt, ...)
{
    if (w->failure[0])
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->failure, sizeof w->failure, fmt, ap);
    va_end(ap);
}

/* The blob, validated here or by this node's leader; received into a
 * sink when out of memory. */
static void worker_receive_blob(worker_state *w, size_t size)
{
    if (link_scene_receive(&w->scene, size, csg_blob_valid) != LINK_OK)
        worker_set_failure(w, "the scene broadcast failed");
    if (!w->scene.bytes)
        worker_set_failure(w, "out of memory for the scene (%zu bytes)", size);
    else if (!w->scene.valid)
        worker_set_failure(w, "received an invalid scene blob (%zu bytes)", size);
}

/* pager_fetch: pages from rank 0, or from their homes (comm/mpi_link.h):
 * the pager hands them sorted by home, so each run of one home is one
 * ask; a worker's own home pages (pager_take_homes) come from rank 0. */
static bool worker_fetch(void *arg, const int32_t *pages, int n, unsigned char *out, size_t bytes)
{
    worker_state *w = arg;
    link_page_ask one, *asks = w->pager.homes > 0 ? calloc((size_t)n, sizeof *asks) : &one;
    if (!asks)
        return false;
    int count = 0;
    size_t at = 0;
    for (int k = 0; k < n; k++) {
        int rank = pager_home_rank(&w->pager, pages[k]);
        rank = rank == w->rank ? 0 : rank;
        if (count == 0 || asks[count - 1].rank != rank)
            asks[count++] = (link_page_ask){rank, &pages[k], 0, (unsigned char *)out + at, 0};
        asks[count - 1].n++;
        asks[count - 1].bytes += w->pager.plan.pages[pages[k]].bytes;
        at += w->pager.plan.pages[pages[k]].bytes;
    }
    uint64_t rerouted = link_page_rerouted();
    bool ok = at == bytes && link_page_fetch(asks, count);
    w->pager.stats.rerouted += link_page_rerouted() - rerouted;
    if (asks != &one)
        free(asks);
    return ok;
}

static void (*worker_serve_cost)(uint64_t bytes); /* (the simulated build's) */

void worker_set_serve_cost(void (*charge)(uint64_t bytes))
{
    worker_serve_cost = charge;
}

/* pager_fetch_into (--page-fetch get): the ranges read one-sided from
 * rank 0's blob straight into place (comm/mpi_link.h, link_page_get). */
static bool worker_get(void *arg, const pager_range *ranges, int n, unsigned char *base)
{
    (void)arg;
    uint64_t *off = malloc((size_t)(n > 0 ? n : 1) * sizeof *off);
    uint64_t *len = malloc((size_t)(n > 0 ? n : 1) * sizeof *len);
    for (int k = 0; off && len && k < n; k++) {
        off[k] = ranges[k].off;
        len[k] = ranges[k].len;
    }
    bool ok = off && len && link_page_get(base, off, len, n);
    free(off);
    free(len);
    return ok;
}

/* link_page_server's poll: the share's last ask answered, installed, the
 * next sent (a failure ends the fill: the pages come when needed). */
static void worker_fill_step(void *arg)
{
    worker_state *w = arg;
    if (!w->fill.begun || w->fill.ended)
        return;
    if (w->fill.ask) {
        int got = link_page_fetch_test(w->fill.ask);
        if (got == 0)
            return;
        w->fill.ask = NULL;
        w->fill.asks_ended++;
        if (got > 0)
            pager_home_fill(&w->pager, w->fill.pages, w->fill.count, w->fill.bytes);
        else
            pager_home_fill_failed(&w->pager, w->fill.pages, w->fill.count);
        w->fill.ended = got < 0;
    }
    uint64_t bytes = 0;
    w->fill.count = w->fill.ended ? 0 : pager_home_fill_next(&w->pager, w->fill.pages, WORKER_FILL_PAGES,
                                                            WORKER_FILL_BYTES, &bytes);
    if (w->fill.count > 0 && bytes > w->fill.cap) {
        free(w->fill.bytes);
        w->fill.bytes = malloc(bytes);
        w->fill.cap = w->fill.bytes ? bytes : 0;
    }
    link_page_ask ask = {0, w->fill.pages, w->fill.count, w->fill.bytes, bytes};
    w->fill.ask = w->fill.count > 0 && w->fill.bytes ? link_page_fetch_start(&ask) : NULL;
    w->fill.ended = !w->fill.ask;
    if (!w->fill.ask) /* (done, or out of memory: not coming) */
        pager_home_fill_failed(&w->pager, w->fill.pages, w->fill.count);
}

/* pager.fill_wait: the fill's current ask ended (its pages are needed). */
static void worker_fill_wait(void *arg)
{
    worker_state *w = arg;
    unsigned ask = w->fill.asks_ended;
    link_idle idle;
    link_idle_init(&idle, WORKER_FILL_NAP_NS, 0); /* (short naps: a ray waits) */
    while (w->fill.ask && w->fill.asks_ended == ask) {
        worker_fill_step(w);
        if (w->fill.asks_ended == ask)
            link_idle_step(&idle);
    }
    link_idle_free(&idle);
}

/* link_page_pack: another worker's ask, of pages whose home is this one. */
static size_t worker_pack_homes(void *arg, const int32_t *pages, int n, unsigned char **out)
{
    worker_state *w = arg;
    size_t bytes = pager_pack_homes(&w->pager, pages, n, out);
    if (worker_serve_cost)
        worker_serve_cost(bytes);
    return bytes;
}

/* --scene-memory: the resident part and the page plan (the setup's
 * blob_size bytes), broadcast by rank 0, which validated the whole blob;
 * with homes, this worker's share of the pages. */
static void worker_receive_pages(worker_state *w, const proto_setup *setup)
{
    size_t size = (size_t)setup->blob_size;
    void *packed = malloc(size ? size : 1);
    link_status got = link_bcast(packed, size); /* (a NULL buffer takes part: a sink) */
    const char *why = "the scene broadcast failed";
    if (got == LINK_OK && !packed)
        why = "out of memory for the scene's resident part";
    if (got == LINK_OK && packed &&
        pager_open(&w->pager, packed, size, setup->scene_memory,
                   (enum pager_policy)setup->page_policy, worker_fetch, w, &why)) {
        w->paged = true;
        w->blob = w->pager.base;
        w->pager.prefetch = setup->page_prefetch != PAGER_PREFETCH_OFF;
        w->pager.prefetch_shadows = setup->page_prefetch == PAGER_PREFETCH_SHADOWS;
        if (setup->page_homes > 0 && !pager_take_homes(&w->pager, setup->page_homes, w->rank))
            worker_set_failure(w, "out of memory for the table of the scene's page homes");
        else if (setup->page_homes > 0) {
            w->pager.fill_wait = worker_fill_wait;
            link_page_server(worker_pack_homes, worker_fill_step, w); /* (until worker_free) */
        }
        if (!pager_trace_open(&w->pager, w->page_trace, w->rank))
            worker_set_failure(w, "cannot write the page trace ($CSGTRACE_PAGE_TRACE)");
    } else {
        worker_set_failure(w, "%s", why);
    }
    free(packed);
    /* (collective: whether or not this worker's pager opened) */
    if (got == LINK_OK && setup->page_fetch == PAGER_FETCH_GET && link_page_window(NULL, 0) &&
        w->paged)
        w->pager.fetch_into = worker_get;
}

/* tile_runner.progress: between bands of an item, this rank's transfers
 * moved on: its last answer, over MPI's eager limit, goes to the master
 * while the next item is computed, not after it (comm/mpi_link.h). */
static void worker_progress(void *arg)
{
    (void)arg;
    link_progress();
}

static void worker_prepare(worker_state *w, const proto_setup *setup)
{
    if (w->failure[0])
        return;
    if (setup->tile <= 0) {
        worker_set_failure(w, "no valid tile size for the scene received");
        return;
    }
    if (setup->batch < 1 || setup->batch > PROTO_BATCH_MAX) {
        worker_set_failure(w, "no valid batch size received (%d)", (int)setup->batch);
        return;
    }
    bool ok = tile_runner_init(&w->runner, w->blob, setup->tile);
    w->runner.progress = worker_progress; /* (its answers move on meanwhile) */
    if (w->paged && w->pager.homes > 0) /* (others' rays wait on its answers) */
        w->runner.band_pixels = TILE_BAND_PIXELS_HOME;
    const tile_grid *g = &w->runner.grid;
    if (setup->pixels != PIXELS_FLOAT && !pixels_is_rgb8(setup->pixels)) {
        worker_set_failure(w, "no valid pixel format received (%d)", (int)setup->pixels);
        return;
    }
    w->batch = setup->batch;
    w->pixels = setup->pixels;
    w->in_limit = proto_worker_limit(g, w->batch);
    if (pixels_is_rgb8(w->pixels)) {
        w->rgb = malloc(g->pixels_max * 3 * sizeof *w->rgb);
        ok = ok && w->rgb;
    }
    if (w->pixels == PIXELS_RGB8Z) {
        w->rgb8 = malloc(g->pixels_max * 3);
        w->compressor = pixels_compressor_new();
        ok = ok && w->rgb8 && w->compressor;
    }
    for (int i = 0; i < PROTO_IN_FLIGHT; i++) {
        w->out_cap[i] = proto_result_part_max(g->pixels_max);
        w->out[i] = malloc(w->out_cap[i]);
        ok = ok && w->out[i];
    }
    if (!ok)
        worker_set_failure(w, "out of memory for tiles of %zu pixels", g->pixels_max);
}

static void worker_send_fail(const worker_state *w, int index, const char *text)
{
    proto_fail f;
    memset(&f, 0, sizeof f);
    f.index = index;
    snprintf(f.text, sizeof f.text, "%s", text);
    link_send(w->parent, PROTO_TAG_FAIL, &f, sizeof f);
}

/* The rectangle of part h (at `at` in `in`), its answer into `out` (room
 * for proto_result_part_max): the answer's bytes, 0 when its pixels could
 * not be compressed.  PIXELS_RGB8: the bytes of the 8-bit file (comm/pixels.h);
 * PIXELS_RGB8Z: those compressed (comm/pixels_z.h). */
static size_t worker_do_part(worker_state *w, const link_msg *in, size_t at, const proto_tile *h,
                             char *out)
{
    tile_rect r = {h->x, h->y, h->width, h->height};
    size_t n = (size_t)r.width * (size_t)r.height;
    /* hetero: the records follow the header (8-byte aligned) */
    const void *payload = h->work != PROTO_WORK_RENDER ? in->data + at + sizeof *h : NULL;
    const void *answers = h->work == PROTO_WORK_SHADE_ANSWERED /* (after the records) */
                              ? (const char *)payload + tile_records_bytes(&w->runner.grid, n)
                              : NULL;
    const uint32_t flags = w->paged ? PROTO_RESULT_PAGING : 0u;
    float *floats = (float *)(void *)(out + proto_result_head(&(proto_result){.flags = flags}));
    tile_result res;
    tile_timer timer; /* (the part's whole work: the map of bench/sim/costmap.py) */
    tile_time_start(&timer);
    tile_run_rect_answered(&w->runner, r, payload, answers,
                           pixels_is_rgb8(w->pixels) ? w->rgb : floats, &res);
    uint32_t compressed = 0;
    if (w->pixels == PIXELS_RGB8) {
        pixels_to_rgb8(w->rgb, n * 3, (uint8_t *)floats);
    } else if (w->pixels == PIXELS_RGB8Z) {
        pixels_to_rgb8(w->rgb, n * 3, w->rgb8);
        /* (out has room for the worst: proto_result_part_max) */
        compressed = (uint32_t)tile_compress_rgb8(&w->runner, r, w->compressor, w->rgb8,
                                                  (uint8_t *)floats);
        if (compressed == 0)
            return 0;
    }
    tile_time_stop(&timer, &res);
    proto_result head = {.index = h->index,
                         .hits = res.hits,
                         .x = h->x,
                         .y = h->y,
                         .primary = res.rays.primary,
                         .shadow = res.rays.shadow,
                         .reflected = res.rays.reflected,
                         .refracted = res.rays.refracted,
                         .over_budget = res.rays.over_budget,
                         .shadow_answered = res.rays.shadow_answered,
                         .busy_s = res.busy_s,
                         .cpu_s = res.cpu_s,
                         .pixels = w->pixels,
                         .payload = compressed,
                         .flags = flags,
                         .paging = res.paging};
    proto_result_write(out, &head);
    return proto_result_part_of(&head, n, w->pixels);
}

/* Every part of TILE `in` computed into RESULT buffer `slot`: the
 * RESULT's length, or 0 with the reason in *why (h: the part that
 * failed). */
static size_t worker_do_parts(worker_state *w, const link_msg *in, proto_tile *h, int slot,
                              const char **why)
{
    size_t at = 0, len = 0;
    for (int k = 0;; k++) {
        if (k == w->batch) {
            *why = "more parts in a tile message than the batch";
            return 0;
        }
        size_t end = proto_tile_part_at(&w->runner.grid, in->data, in->len, at, h, why);
        if (end == 0)
            return 0;
        if (k > 0) {
            link_progress(); /* (the last answer moves on between parts too) */
            test_hook_kill(w->rank, "item", w->tiles_done);
        }
        size_t start = proto_align(len);
        size_t room = start + proto_result_part_max((size_t)h->width * (size_t)h->height);
        if (!proto_buffer(&w->out[slot], &w->out_cap[slot], room)) {
            *why = "out of memory for a batch of tiles";
            return 0;
        }
        memset(w->out[slot] + len, 0, start - len); /* the padding between parts */
        size_t part = worker_do_part(w, in, at, h, w->out[slot] + start);
        if (part == 0) {
            *why = "the tile's pixels could not be compressed";
            return 0;
        }
        len = start + part;
        w->tiles_done++;
        if (w->paged && w->pager.failed) {
            *why = "a page of the scene could not be fetched";
            return 0;
        }
        if (end == in->len)
            return len;
        at = proto_align(end);
    }
}

static void worker_answer_tile(worker_state *w, const link_msg *in)
{
    proto_tile h;
    if (w->failure[0]) {
        worker_send_fail(w, -1, w->failure);
        return;
    }
    if (in->len < sizeof h) {
        worker_send_fail(w, -1, "truncated tile message");
        return;
    }
    memcpy(&h, in->data, sizeof h);
    test_hook_kill(w->rank, "item", w->tiles_done);
    long long fail_rank = test_hook_number(TEST_FAIL_WORKER, 1 << 30); /* (tests only) */
    if (fail_rank > 0 && fail_rank == w->rank && w->tiles_done == 0) {
        worker_send_fail(w, h.index, "internal failure injected by CSGTRACE_TEST_FAIL_WORKER");
        w->tiles_done++;
        return;
    }
    if (test_hook_number(TEST_SLOW_WORKER, 1 << 30) == w->rank) { /* (tests only) */
        struct timespec slow = {0, 20000000L};
        nanosleep(&slow, NULL);
    }
    int slot = w->out_next, first = w->tiles_done;
    link_req_wait(&w->out_req[slot]); /* its last RESULT is delivered */
    const char *why = NULL;
    size_t len = worker_do_parts(w, in, &h, slot, &why);
    if (len == 0) {
        worker_send_fail(w, h.index, why);
        return;
    }
    link_isend(w->parent, PROTO_TAG_RESULT, w->out[slot], len, &w->out_req[slot]);
    if (w->paged && w->pager.homes > 0 && !w->fill.begun) {
        w->fill.begun = true; /* (after its first item: rank 0 has dealt the first ones) */
        worker_fill_step(w);
    }
    for (int i = first; i < w->tiles_done; i++)
        test_hook_kill(w->rank, "send", i);
    w->out_next = (slot + 1) % PROTO_IN_FLIGHT;
}

/* Every RESULT sent is delivered. */
static void worker_flush(worker_state *w)
{
    for (int i = 0; i < PROTO_IN_FLIGHT; i++)
        link_req_wait(&w->out_req[i]);
}

static void worker_free(worker_state *w)
{
    link_scene_free(&w->scene);
    link_page_server(NULL, NULL, NULL);
    if (w->fill.ask)
        link_page_fetch_cancel(w->fill.ask);
    free(w->fill.bytes);
    if (w->paged)
        pager_close(&w->pager);
    free(w->rgb);
    free(w->rgb8);
    pixels_zstream_free(w->compressor);
    tile_runner_free(&w->runner);
    for (int i = 0; i < WORKER_QUEUE; i++)
        link_msg_free(&w->queue[i]);
    for (int i = 0; i < PROTO_IN_FLIGHT; i++)
        if (!w->out_req[i].active) /* (a send MPI still holds: left to it) */
            free(w->out[i]);
}

/* One message from the master onto the queue: waiting for it when the
 * queue is empty, else only if it is already there (LINK_NONE). */
static link_status worker_take(worker_state *w)
{
    /* Before the setup succeeded, only a STOP or a header is of use. */
    size_t limit = w->in_limit > sizeof(proto_tile) ? w->in_limit : sizeof(proto_tile);
    link_msg *m = &w->queue[(w->head + w->queued) % WORKER_QUEUE];
    link_status got = w->queued == 0 ? link_recv(m, w->parent, limit)
                                     : link_try_recv(m, w->parent, limit);
    if (got == LINK_TOO_BIG) { /* it cannot be drained: end the job */
        worker_send_fail(w, -1, "message from the master larger than any tile");
        link_abort(1);
    }
    if (got == LINK_OK) {
        w->queued++;
        w->stop_queued = m->tag == PROTO_TAG_STOP;
    }
    return got;
}

/* Answers the master until STOP; its status. */
static int worker_serve(worker_state *w)
{
    for (;;) {
        while (w->queued < WORKER_QUEUE && !w->stop_queued) { /* what is waiting, now */
            link_status got = worker_take(w);
            if (got == LINK_ERROR)
                return 1; /* the master is gone: nothing to answer */
            if (got == LINK_NONE)
                break;
        }
        const link_msg *m = &w->queue[w->head];
        w->head = (w->head + 1) % WORKER_QUEUE;
        w->queued--;
        if (m->tag == PROTO_TAG_STOP) {
            proto_stop stop = {1, 0}; /* a short STOP still stops, with 1 */
            if (m->len >= sizeof stop)
                memcpy(&stop, m->data, sizeof stop);
            link_ending(stop.status); /* the master may exit from now on */
            worker_flush(w);
            return stop.status;
        }
        if (m->tag == PROTO_TAG_TILE)
            worker_answer_tile(w, m);
        else
            worker_send_fail(w, -1, w->failure[0] ? w->failure : "unexpected message");
    }
}

int worker_run(int rank, const char *bind, const char *page_trace)
{
    worker_state w;
    memset(&w, 0, sizeof w);
    w.rank = rank;
    w.page_trace = page_trace;
    link_ending(-1); /* (a job of several renders: a new one) */

    proto_setup setup;
    if (link_bcast_idle(&setup, sizeof setup) != LINK_OK)
        return 1;
    if (setup.status != 0)
        return setup.status; /* the master reported why */
    test_hook_kill(rank, "scene", 0);
    if (setup.scene_memory > 0) {
        worker_receive_pages(&w, &setup);
    } else {
        worker_receive_blob(&w, (size_t)setup.blob_size);
        w.blob = w.scene.bytes;
    }
    if (rank <= setup.relays && !w.paged) { /* a relay: the master of a group */
        int status = relay_run(rank, &setup, &w.scene, w.failure);
        link_scene_free(&w.scene);
        return status;
    }
    w.parent = proto_parent(rank, setup.relays);
    link_bind_worker(bind); /* (more ranks than cores: one core each, mpi_link.h) */
    worker_prepare(&w, &setup);
    if (w.failure[0]) {
        worker_send_fail(&w, -1, w.failure);
    } else {
        proto_ready ready = {0, w.scene.shared};
        test_hook_kill(rank, "ready", 0);
        link_send(w.parent, PROTO_TAG_READY, &ready, sizeof ready);
    }
    int status = worker_serve(&w);
    worker_free(&w);
    return status;
}
