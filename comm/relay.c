/*
 * relay.c — a relay rank (relay.h; the protocol: protocol.h).
 *
 * Algorithm, an event loop like the master's (master.c):
 *   1. handshake: one READY or FAIL from every worker of the group, then
 *      one to rank 0 (READY, or the first FAIL: the relay's own or a
 *      worker's);
 *   2. until STOP: take every message waiting (rank 0's TILEs: their parts
 *      queued; the workers' answers: each part's RESULT part kept with its
 *      TILE); deal the queued parts to the workers with room, one level of
 *      PROTO_IN_FLIGHT at a time, each message an even share of the queue
 *      (at least one part); answer each of rank 0's TILEs once every part
 *      of it is answered, whatever came before it (rank 0 finds it by its
 *      first part: protocol.h), the oldest first; with nothing to do, the idle
 *      wait (poll, then nap: a quarter of the mean item time, at most
 *      LINK_NAP_MAX_NS);
 *   3. STOP: passed to every worker of the group, then the relay returns
 *      its status.
 * A TILE that breaks the protocol, a worker's FAIL or a malformed answer
 * makes the parts concerned fail: their TILE is answered with FAIL (the
 * first reason), as a worker answers, and rank 0 stops and drains.
 *
 * Invariants: at most PROTO_RELAY_IN_FLIGHT TILEs of rank 0 are held, a
 * slot each until answered (rank 0 sends no more), so the queue never
 * holds more than their parts;
 * a worker holds at most PROTO_IN_FLIGHT messages, answered oldest first;
 * every part is answered exactly once; a send buffer is reused only once
 * its send is done.
 */
#include "relay.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/flatten.h"
#include "mpi_link.h"

#define RELAY_SPINS 50
#define RELAY_NAP_MIN_NS 2000L
/* A worker's message: its share of the queue over this many rounds of
 * every worker's in-flight messages (guided, so the last go one a message). */
#define RELAY_SPREAD 2

typedef struct {
    int slot, part; /* part `part` of the TILE in ring slot `slot` */
} relay_part;

/* One TILE of rank 0, held until every part of it is answered. */
typedef struct {
    bool held;                       /* the slot holds a TILE              */
    long order;                      /* TILEs that came before it          */
    link_msg in;
    int parts;
    size_t at[PROTO_BATCH_MAX];      /* each part's offset in in.data      */
    size_t bytes[PROTO_BATCH_MAX];   /* its length                          */
    size_t pixels[PROTO_BATCH_MAX];  /* its rectangle's pixels              */
    char *answer[PROTO_BATCH_MAX];   /* its RESULT part once answered      */
    size_t answer_len[PROTO_BATCH_MAX];
    int answered;
    bool failed;                     /* answered with `fail`                */
    proto_fail fail;
    char *out;                       /* the answer to rank 0, and its send */
    size_t out_cap;
    link_req out_req;
} relay_tile;

typedef struct {
    int rank;
    relay_part held[PROTO_IN_FLIGHT][PROTO_BATCH_MAX]; /* messages, ring */
    int count[PROTO_IN_FLIGHT];
    int head, n;
    char *buf[PROTO_IN_FLIGHT];
    size_t cap[PROTO_IN_FLIGHT];
    link_req req[PROTO_IN_FLIGHT];
    bool dead;                 /* broke the protocol: nothing more to it */
} relay_worker;

typedef struct {
    int rank, relays, batch, pixels;
    tile_grid grid;
    relay_tile ring[PROTO_RELAY_IN_FLIGHT]; /* rank 0's TILEs, a slot each */
    int n;                     /* slots held                            */
    long arrived;              /* TILEs taken so far                    */
    relay_part queue[PROTO_RELAY_IN_FLIGHT * PROTO_BATCH_MAX]; /* not dealt */
    int q_head, q_n;
    relay_worker *w;
    int group;                 /* workers in the group                  */
    int live;                  /* of them, not written off              */
    double busy_s;             /* their items' seconds so far           */
    long items;
    int scene_shared;          /* workers of the group that read their
                                  node's one copy of the scene (READY)  */
} relay_state;

/* ---- rank 0's TILEs ------------------------------------------------------- */

static void relay_fail(relay_tile *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* TILE t fails (the first reason stays). */
static void relay_fail(relay_tile *t, const char *fmt, ...)
{
    if (t->failed)
        return;
    t->failed = true;
    memset(&t->fail, 0, sizeof t->fail);
    t->fail.index = -1;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(t->fail.text, sizeof t->fail.text, fmt, ap);
    va_end(ap);
}

/* The next k queued parts fail (relay_fail: "relay N: why"). */
static void relay_fail_queued(relay_state *s, int k, const char *why)
{
    const int qcap = (int)(sizeof s->queue / sizeof s->queue[0]);
    for (; k > 0 && s->q_n > 0; k--, s->q_n--) {
        relay_tile *t = &s->ring[s->queue[s->q_head].slot];
        relay_fail(t, "relay %d: %s", s->rank, why);
        t->answered++;
        s->q_head = (s->q_head + 1) % qcap;
    }
}

/* With no worker left, every queued part fails. */
static void relay_drain_queue(relay_state *s)
{
    if (s->live == 0)
        relay_fail_queued(s, s->q_n, "no worker left");
}

/* Rank 0's TILE in ring slot `slot`: its parts found and queued, or the
 * TILE failed (nothing queued, answered at once). */
static void relay_take_tile(relay_state *s, int slot)
{
    relay_tile *t = &s->ring[slot];
    t->parts = t->answered = 0;
    t->failed = false;
    size_t at = 0;
    for (;;) {
        const char *why = NULL;
        proto_tile h;
        size_t end = t->parts == s->batch
                         ? 0
                         : proto_tile_part_at(&s->grid, t->in.data, t->in.len, at, &h, &why);
        if (end == 0) {
            relay_fail(t, "relay %d: %s", s->rank,
                       why ? why : "more parts in a tile message than the batch");
            t->parts = 0;
            return;
        }
        t->at[t->parts] = at;
        t->bytes[t->parts] = end - at;
        t->pixels[t->parts] = (size_t)h.width * (size_t)h.height;
        t->answer[t->parts] = NULL;
        t->parts++;
        if (end == t->in.len)
            break;
        at = proto_align(end);
    }
    for (int i = 0; i < t->parts; i++) {
        int q = (s->q_head + s->q_n++) % (int)(sizeof s->queue / sizeof s->queue[0]);
        s->queue[q] = (relay_part){slot, i};
    }
    relay_drain_queue(s);
}

/* The oldest held TILE whose parts are all answered; -1: none. */
static int relay_complete_slot(const relay_state *s)
{
    int found = -1;
    for (int k = 0; k < PROTO_RELAY_IN_FLIGHT; k++) {
        const relay_tile *t = &s->ring[k];
        if (t->held && t->answered == t->parts && (found < 0 || t->order < s->ring[found].order))
            found = k;
    }
    return found;
}

/* The TILEs whose parts are all answered, answered to rank 0 (a RESULT of
 * the parts, or the FAIL), the oldest first; their slots freed. */
static void relay_answer_root(relay_state *s)
{
    int slot;
    while (s->n > 0 && (slot = relay_complete_slot(s)) >= 0) {
        relay_tile *t = &s->ring[slot];
        link_req_wait(&t->out_req); /* (this slot's last answer) */
        size_t len = 0;
        for (int i = 0; !t->failed && i < t->parts; i++)
            len = proto_align(len) + t->answer_len[i];
        if (!t->failed && !proto_buffer(&t->out, &t->out_cap, len))
            relay_fail(t, "relay %d: out of memory for a result", s->rank);
        if (t->failed) {
            if (proto_buffer(&t->out, &t->out_cap, sizeof t->fail)) {
                memcpy(t->out, &t->fail, sizeof t->fail);
                link_isend(LINK_MASTER, PROTO_TAG_FAIL, t->out, sizeof t->fail, &t->out_req);
            } else {
                link_send(LINK_MASTER, PROTO_TAG_FAIL, &t->fail, sizeof t->fail);
            }
        } else {
            size_t at = 0;
            for (int i = 0; i < t->parts; i++) {
                size_t start = proto_align(at);
                memset(t->out + at, 0, start - at); /* the padding between parts */
                memcpy(t->out + start, t->answer[i], t->answer_len[i]);
                at = start + t->answer_len[i];
            }
            link_isend(LINK_MASTER, PROTO_TAG_RESULT, t->out, len, &t->out_req);
        }
        for (int i = 0; i < t->parts; i++) {
            free(t->answer[i]);
            t->answer[i] = NULL;
        }
        t->held = false;
        s->n--;
    }
}

/* ---- the workers ------------------------------------------------------------ */

/* The group's worker of rank r, NULL when r is none of it. */
static relay_worker *relay_member(relay_state *s, int r)
{
    if (!s->w || r <= s->relays || proto_parent(r, s->relays) != s->rank)
        return NULL;
    int j = (r - proto_member(s->rank, 0, s->relays)) / s->relays;
    return j < s->group ? &s->w[j] : NULL;
}

/* Parts in the next message: an even share of the queue over every
 * worker's in-flight messages, at least one, at most the batch. */
static int relay_share(const relay_state *s)
{
    int k = s->q_n / (s->live * PROTO_IN_FLIGHT * RELAY_SPREAD);
    k = k < 1 ? 1 : k > s->batch ? s->batch : k;
    return k < s->q_n ? k : s->q_n;
}

/* The next share of the queue to worker w in one TILE. */
static bool relay_send(relay_state *s, relay_worker *w)
{
    int k = relay_share(s), pos = (w->head + w->n) % PROTO_IN_FLIGHT;
    const int qcap = (int)(sizeof s->queue / sizeof s->queue[0]);
    size_t len = 0;
    for (int i = 0; i < k; i++) {
        relay_part p = s->queue[(s->q_head + i) % qcap];
        len = proto_align(len) + s->ring[p.slot].bytes[p.part];
    }
    link_req_wait(&w->req[pos]); /* (answered: its send is done) */
    if (!proto_buffer(&w->buf[pos], &w->cap[pos], len)) {
        relay_fail_queued(s, k, "out of memory for a worker's tiles");
        return false;
    }
    size_t at = 0;
    for (int i = 0; i < k; i++) {
        relay_part p = s->queue[(s->q_head + i) % qcap];
        const relay_tile *t = &s->ring[p.slot];
        size_t start = proto_align(at);
        memset(w->buf[pos] + at, 0, start - at);
        memcpy(w->buf[pos] + start, t->in.data + t->at[p.part], t->bytes[p.part]);
        at = start + t->bytes[p.part];
        w->held[pos][i] = p;
    }
    s->q_head = (s->q_head + k) % qcap;
    s->q_n -= k;
    w->count[pos] = k;
    w->n++;
    link_isend(w->rank, PROTO_TAG_TILE, w->buf[pos], len, &w->req[pos]);
    return true;
}

/* Every worker filled up to PROTO_IN_FLIGHT messages, one level at a
 * time; true when something was sent. */
static bool relay_deal(relay_state *s)
{
    bool sent = false;
    for (int depth = 1; depth <= PROTO_IN_FLIGHT && s->live > 0; depth++)
        for (int j = 0; j < s->group && s->q_n > 0; j++)
            if (!s->w[j].dead && s->w[j].n < depth && relay_send(s, &s->w[j]))
                sent = true;
    return sent;
}

/* Parts held[from .. k - 1] of a worker's message fail. */
static void relay_fail_parts(relay_state *s, const relay_part *held, int from, int k,
                             const char *text)
{
    for (int i = from; i < k; i++) {
        relay_tile *t = &s->ring[held[i].slot];
        relay_fail(t, "%s", text);
        t->answered++;
    }
}

/* Part p's header. */
static proto_tile relay_part_head(const relay_state *s, relay_part p)
{
    proto_tile h;
    memcpy(&h, s->ring[p.slot].in.data + s->ring[p.slot].at[p.part], sizeof h);
    return h;
}

/* The tile of part p. */
static int relay_tile_index(const relay_state *s, relay_part p)
{
    return relay_part_head(s, p).index;
}

/* Part `i` of worker w's answer, at `at` in msg: kept with its TILE; where
 * the next part starts, 0 when it is malformed. */
static size_t relay_keep_part(relay_state *s, const relay_worker *w, const link_msg *msg,
                              size_t at, relay_part p)
{
    relay_tile *t = &s->ring[p.slot];
    proto_result h = {0};
    if (at > msg->len || proto_result_read(msg->data + at, msg->len - at, &h) == 0)
        return 0;
    proto_tile sent = relay_part_head(s, p);
    if (h.index != sent.index || h.x != sent.x || h.y != sent.y || h.pixels != s->pixels)
        return 0;
    size_t len = proto_result_part_of(&h, t->pixels[p.part], h.pixels);
    if (len == 0 || msg->len - at < len || !(t->answer[p.part] = malloc(len)))
        return 0;
    if (h.rank == 0)
        h.rank = w->rank;
    memcpy(t->answer[p.part], msg->data + at, len);
    proto_result_write(t->answer[p.part], &h); /* (with its rank) */
    t->answer_len[p.part] = len;
    t->answered++;
    s->busy_s += h.busy_s;
    s->items++;
    return at + len;
}

/* A worker's FAIL as rank 0 reports it, naming the worker. */
static void relay_fail_text(const link_msg *msg, char *text, size_t size)
{
    proto_fail f;
    memset(&f, 0, sizeof f);
    memcpy(&f, msg->data, msg->len < sizeof f ? msg->len : sizeof f);
    f.text[sizeof f.text - 1] = '\0';
    /* (its text cut to what fits PROTO_FAIL_TEXT with the prefix) */
    if (f.index >= 0)
        snprintf(text, size, "worker %d failed on tile %d: %.180s", msg->source, (int)f.index,
                 f.text);
    else
        snprintf(text, size, "worker %d failed: %.180s", msg->source, f.text);
}

/* Worker w broke the protocol: the parts it still holds fail (it may
 * never answer them), and so does the queue once no worker is left. */
static void relay_write_off(relay_state *s, relay_worker *w, const char *why)
{
    for (; w->n > 0; w->n--) {
        relay_fail_parts(s, w->held[w->head], 0, w->count[w->head], why);
        w->head = (w->head + 1) % PROTO_IN_FLIGHT;
    }
    w->dead = true;
    s->live--;
    relay_drain_queue(s);
}

/* Worker w's answer to its oldest message. */
static void relay_take_answer(relay_state *s, relay_worker *w, const link_msg *msg)
{
    if (w->n == 0)
        return; /* (nothing held: a stray message, dropped) */
    const relay_part *held = w->held[w->head];
    int k = w->count[w->head];
    w->head = (w->head + 1) % PROTO_IN_FLIGHT;
    w->n--;
    char text[PROTO_FAIL_TEXT];
    if (msg->tag == PROTO_TAG_FAIL) {
        relay_fail_text(msg, text, sizeof text);
        relay_fail_parts(s, held, 0, k, text);
        return;
    }
    size_t at = 0, end = 0;
    for (int i = 0; i < k; i++) {
        end = msg->tag == PROTO_TAG_RESULT ? relay_keep_part(s, w, msg, at, held[i]) : 0;
        if (end == 0) {
            snprintf(text, sizeof text, "worker %d: malformed result for tile %d (tag %d, %zu "
                     "bytes)", w->rank, relay_tile_index(s, held[i]), msg->tag, msg->len);
            relay_fail_parts(s, held, i, k, text);
            relay_write_off(s, w, text);
            return;
        }
        at = proto_align(end);
    }
    if (end != msg->len) {
        snprintf(text, sizeof text, "worker %d: result of %zu bytes, %zu expected", w->rank,
                 msg->len, end);
        relay_fail(&s->ring[held[0].slot], "%s", text);
        relay_write_off(s, w, text);
    }
}

/* ---- set-up, loop, end ---------------------------------------------------- */

/* The group's handshakes; the first failure's text into `why` ("" none). */
static void relay_greet(relay_state *s, link_msg *msg, char *why, size_t size)
{
    for (int left = s->group; left > 0; left--) {
        if (link_recv(msg, LINK_ANY_SOURCE, sizeof(proto_fail)) != LINK_OK) {
            if (!why[0])
                snprintf(why, size, "relay %d: a worker's handshake could not be received",
                         s->rank);
            return; /* (rank 0 sees the lost worker) */
        }
        if (msg->tag == PROTO_TAG_READY)
            s->scene_shared += proto_ready_scene_shared(msg->data, msg->len);
        if (msg->tag == PROTO_TAG_FAIL && !why[0]) {
            relay_fail_text(msg, why, size);
        } else if (msg->tag != PROTO_TAG_READY && !why[0]) {
            snprintf(why, size, "relay %d: unexpected handshake from rank %d", s->rank,
                     msg->source);
        }
    }
}

/* The nap cap: a quarter of the mean item time, within bounds. */
static long relay_nap_cap(const relay_state *s)
{
    if (s->items == 0)
        return RELAY_NAP_MIN_NS;
    long quarter = (long)(s->busy_s / (double)s->items * 0.25e9);
    return quarter < RELAY_NAP_MIN_NS ? RELAY_NAP_MIN_NS
           : quarter > LINK_NAP_MAX_NS ? LINK_NAP_MAX_NS
                                       : quarter;
}

/* Every message waiting, taken; true when there was one.  *stop: rank
 * 0's STOP came (its status). */
static bool relay_receive(relay_state *s, link_msg *msg, size_t limit, int *stop)
{
    bool any = false;
    for (;;) {
        link_status got = link_try_recv(msg, LINK_ANY_SOURCE, limit);
        if (got == LINK_NONE)
            return any;
        if (got == LINK_TOO_BIG) { /* it cannot be drained: the job ends */
            fprintf(stderr, "csgtrace: error: worker %d: a %zu-byte message (tag %d) to relay "
                            "%d, larger than any answer (%zu bytes): the job is ended\n",
                    msg->source, msg->len, msg->tag, s->rank, limit);
            link_abort(1);
        }
        any = true;
        if (got != LINK_OK)
            continue; /* a worker lost mid-message: rank 0 loses the group */
        if (msg->source == LINK_MASTER && msg->tag == PROTO_TAG_STOP) {
            proto_stop st = {1, 0};
            if (msg->len >= sizeof st)
                memcpy(&st, msg->data, sizeof st);
            *stop = st.status;
            return true;
        }
        if (msg->source == LINK_MASTER && s->n < PROTO_RELAY_IN_FLIGHT) {
            int slot = 0;
            while (s->ring[slot].held) /* (one is free: n < PROTO_RELAY_IN_FLIGHT) */
                slot++;
            s->ring[slot].held = true;
            s->ring[slot].order = s->arrived++;
            s->n++;
            link_msg kept = s->ring[slot].in; /* (the buffers swap: no copy) */
            s->ring[slot].in = *msg;
            *msg = kept;
            if (s->ring[slot].in.tag == PROTO_TAG_TILE)
                relay_take_tile(s, slot);
            else {
                s->ring[slot].parts = s->ring[slot].answered = 0;
                s->ring[slot].failed = false;
                relay_fail(&s->ring[slot], "relay %d: unexpected message", s->rank);
            }
            continue;
        }
        relay_worker *w = relay_member(s, msg->source);
        if (w)
            relay_take_answer(s, w, msg);
    }
}

static int relay_serve(relay_state *s, link_msg *msg)
{
    size_t in = proto_worker_limit(&s->grid, s->batch);
    size_t back = proto_master_limit(s->grid.pixels_max, s->batch);
    size_t limit = in > back ? in : back;
    link_idle idle;
    link_idle_init(&idle, RELAY_NAP_MIN_NS, RELAY_SPINS);
    int stop = -1;
    for (;;) {
        bool worked = relay_receive(s, msg, limit, &stop);
        if (stop >= 0)
            break;
        worked |= relay_deal(s);
        relay_answer_root(s);
        if (worked) {
            link_idle_reset(&idle);
            continue;
        }
        idle.nap_max_ns = relay_nap_cap(s);
        link_idle_step(&idle);
    }
    link_idle_free(&idle);
    return stop;
}

/* STOP(status) to every worker of the group; the sends done. */
static void relay_stop(relay_state *s, int status)
{
    proto_stop st = {status, 0};
    for (int j = 0; j < s->group; j++) /* (by rank: s->w may be NULL) */
        link_send(proto_member(s->rank, j, s->relays), PROTO_TAG_STOP, &st, sizeof st);
    link_ending(status);
    for (int i = 0; i < PROTO_RELAY_IN_FLIGHT; i++)
        link_req_wait(&s->ring[i].out_req);
}

/* Worker w's send k done and its buffer freed; one to a worker written
 * off, not done, is left to MPI with its buffer (as the master does). */
static void relay_close_send(relay_worker *w, int k)
{
    link_req *q = &w->req[k];
    if (!link_req_done(q) && w->dead) {
        link_req_abandon(q);
        return;
    }
    if (link_req_wait(q) == LINK_OK) /* (LINK_LOST: MPI's too) */
        free(w->buf[k]);
}

static void relay_free(relay_state *s)
{
    for (int i = 0; i < PROTO_RELAY_IN_FLIGHT; i++) {
        link_msg_free(&s->ring[i].in);
        for (int p = 0; p < PROTO_BATCH_MAX; p++)
            free(s->ring[i].answer[p]);
        if (!s->ring[i].out_req.active)
            free(s->ring[i].out);
    }
    for (int j = 0; s->w && j < s->group; j++)
        for (int k = 0; k < PROTO_IN_FLIGHT; k++)
            relay_close_send(&s->w[j], k);
    free(s->w);
}

int relay_run(int rank, const proto_setup *setup, const link_scene *scene, const char *failure)
{
    const void *blob = scene->bytes;
    relay_state s;
    memset(&s, 0, sizeof s);
    s.rank = rank;
    s.relays = setup->relays;
    s.batch = setup->batch;
    s.pixels = setup->pixels;
    s.group = proto_group(rank, setup->ranks, s.relays);
    s.w = calloc((size_t)(s.group > 0 ? s.group : 1), sizeof *s.w);
    for (int j = 0; s.w && j < s.group; j++)
        s.w[j].rank = proto_member(rank, j, s.relays);
    s.live = s.w ? s.group : 0;
    char why[PROTO_FAIL_TEXT] = "";
    if (failure && failure[0])
        snprintf(why, sizeof why, "%s", failure);
    else if (!blob || !scene->valid) /* (checked once: link_scene_receive) */
        snprintf(why, sizeof why, "relay %d: received an invalid scene blob", rank);
    else if (setup->tile <= 0 || setup->batch < 1 || setup->batch > PROTO_BATCH_MAX)
        snprintf(why, sizeof why, "relay %d: no valid tile or batch size received", rank);
    else if (!s.w || s.group == 0)
        snprintf(why, sizeof why, "relay %d: %s", rank, s.w ? "no workers" : "out of memory");
    if (!why[0])
        s.grid = tile_grid_of(blob, setup->tile);
    link_msg msg = {NULL, 0, 0, 0, 0};
    relay_greet(&s, &msg, why, sizeof why);
    link_respond_quickly();
    if (why[0]) {
        proto_fail f;
        memset(&f, 0, sizeof f);
        f.index = -1;
        snprintf(f.text, sizeof f.text, "%s", why);
        link_send(LINK_MASTER, PROTO_TAG_FAIL, &f, sizeof f);
    } else {
        proto_ready ready = {0, s.scene_shared + scene->shared};
        link_send(LINK_MASTER, PROTO_TAG_READY, &ready, sizeof ready);
    }
    /* A failed relay still answers: every TILE with FAIL, until STOP. */
    int status = relay_serve(&s, &msg);
    relay_stop(&s, status);
    link_msg_free(&msg);
    relay_free(&s);
    return status;
}
