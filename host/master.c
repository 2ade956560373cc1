/*
 * master.c — rank 0 of the tile protocol described in protocol.h.
 *
 * Algorithm (self-scheduling, as in Tachyon and the classic examples):
 *   1. broadcast the status, then the blob;
 *   2. receive one handshake (READY or FAIL) from every worker;
 *   3. give every worker one tile, then answer each RESULT with the next
 *      tile to the rank that returned it, until the tiles run out; then
 *      drain the outstanding results;
 *   4. STOP(status) to every worker (master_end).
 * A FAIL (or a malformed answer) ends the sending of tiles; the outstanding
 * tiles are still drained so that no rank blocks in a send, then every
 * worker gets STOP(1).  Nothing is ever aborted for bad input: the only
 * abort (code 1) is a rank running out of memory for a message it must
 * receive (link.c).
 *
 * Invariants: holding[r] is the tile rank r is working on (-1: none), so
 * a worker holds at most one tile and STOP only goes to idle workers; no
 * message larger than the largest RESULT is taken (link_recv's limit); the
 * bytes counters count every message's whole size.
 */
#include "master.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "link.h"
#include "protocol.h"

void master_begin(master_session *m, int ranks)
{
    memset(m, 0, sizeof *m);
    m->workers = ranks > 1 ? ranks - 1 : 0;
}

void master_share_scene(master_session *m, int status, int tile, const csg_blob *blob)
{
    if (m->workers == 0 || m->shared)
        return;
    proto_setup setup = {status, tile, status == 0 ? blob->size : 0};
    link_bcast(&setup, sizeof setup);
    m->bytes_sent += (uint64_t)m->workers * sizeof setup;
    m->shared = true;
    if (status != 0) {
        m->greeted = m->stopped = true; /* the workers exit at once */
        return;
    }
    link_bcast(blob->bytes, blob->size);
    m->bytes_sent += (uint64_t)m->workers * blob->size;
}

/* ---- receiving ------------------------------------------------------------ */

/* The next message from any worker, at most `limit` bytes; false with d
 * filled when it was larger or the link failed. */
static bool master_recv(master_session *m, link_msg *msg, size_t limit, csg_diag *d)
{
    link_status got = link_recv(msg, LINK_ANY_SOURCE, limit);
    if (got == LINK_ERROR) {
        csg_error_plain(d, "master: receiving from the workers failed");
        return false;
    }
    m->bytes_received += (uint64_t)msg->len;
    if (got == LINK_TOO_BIG) {
        csg_error_plain(d, "worker %d: a %zu-byte message (tag %d), larger than any answer "
                           "(%zu bytes): the job is ended",
                        msg->source, msg->len, msg->tag, limit);
        m->link_broken = true; /* the message cannot be drained */
        return false;
    }
    return true;
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

static void master_report_fail(const link_msg *msg, csg_diag *d)
{
    int tile;
    char text[PROTO_FAIL_TEXT];
    master_fail_text(msg, &tile, text, sizeof text);
    if (tile >= 0)
        csg_error_plain(d, "worker %d failed on tile %d: %s", msg->source, tile, text);
    else
        csg_error_plain(d, "worker %d failed: %s", msg->source, text);
}

/* Step 2: one READY or FAIL from every worker. */
static void master_greet(master_session *m, link_msg *msg, csg_diag *d)
{
    for (int i = 0; i < m->workers && !m->link_broken; i++) {
        if (!master_recv(m, msg, sizeof(proto_fail), d)) {
            m->setup_failed = true;
            break;
        }
        if (msg->tag == PROTO_TAG_READY)
            continue;
        m->setup_failed = true;
        if (msg->tag == PROTO_TAG_FAIL)
            master_report_fail(msg, d);
        else
            csg_error_plain(d, "worker %d: unexpected message (tag %d) at start-up", msg->source,
                            msg->tag);
    }
    m->greeted = true;
}

/* ---- sending ------------------------------------------------------------ */

static void master_send_tile(master_session *m, const master_job *job, char *out, int worker,
                             int index)
{
    const tile_grid *g = &job->grid;
    tile_rect r = tile_rect_of(g, index);
    proto_tile h = {index, job->t ? PROTO_WORK_SHADE : PROTO_WORK_RENDER, r.x, r.y, r.width,
                    r.height};
    size_t len = sizeof h;
    memcpy(out, &h, sizeof h);
    if (job->t) {
        tile_pack_records(g, job->t, job->surf, r, out + sizeof h);
        len += tile_records_bytes(g, (size_t)r.width * (size_t)r.height);
    }
    link_send(worker, PROTO_TAG_TILE, out, len);
    m->bytes_sent += len;
}

/* A RESULT from a worker that holds `index`: checked, stored, counted. */
static bool master_take_result(master_job *job, const link_msg *msg, int index, csg_diag *d)
{
    tile_rect r = tile_rect_of(&job->grid, index);
    size_t n = (size_t)r.width * (size_t)r.height;
    proto_result h;
    if (msg->len != sizeof h + n * 3 * sizeof(float)) {
        csg_error_plain(d, "worker %d: result of tile %d has %zu bytes, expected %zu",
                        msg->source, index, msg->len, sizeof h + n * 3 * sizeof(float));
        return false;
    }
    memcpy(&h, msg->data, sizeof h);
    if (h.index != index || h.hits > n * (size_t)job->grid.spp) {
        csg_error_plain(d, "worker %d: result for tile %d does not match tile %d sent",
                        msg->source, (int)h.index, index);
        return false;
    }
    /* msg->data is malloc'd and sizeof h a multiple of 8: floats aligned */
    tile_store_rgb(job->image, job->grid.width, r, (const float *)(const void *)(msg->data + sizeof h));
    tile_result res = {h.hits, {h.primary, h.shadow, h.reflected, h.refracted}, h.busy_s};
    master_job_count(job, &job->workers[msg->source - 1], &res);
    return true;
}

/* Step 3 once the handshake is done: false with d filled on a failure. */
static bool master_deal(master_session *m, master_job *job, char *out, int *holding, csg_diag *d)
{
    link_msg msg = {NULL, 0, 0, 0, 0};
    size_t limit = proto_master_limit(job->grid.pixels_max);
    int next = 0, outstanding = 0;
    bool failed = false;
    for (int r = 1; r <= m->workers; r++) {
        holding[r] = -1;
        if (next < job->todo_count) {
            holding[r] = job->todo[next++];
            master_send_tile(m, job, out, r, holding[r]);
            outstanding++;
        }
    }
    while (outstanding > 0) {
        if (!master_recv(m, &msg, limit, d)) {
            failed = true;
            break; /* nothing can be drained past that message */
        }
        int src = msg.source;
        if (src < 1 || src > m->workers || holding[src] < 0) {
            if (!failed)
                csg_error_plain(d, "unexpected message (tag %d) from rank %d", msg.tag, src);
            failed = true;
            continue;
        }
        int index = holding[src];
        holding[src] = -1;
        outstanding--;
        if (failed)
            continue; /* draining: the first failure is the one reported */
        if (msg.tag == PROTO_TAG_RESULT && master_take_result(job, &msg, index, d)) {
            if (job->progress)
                progress_step(job->progress);
        } else {
            if (msg.tag == PROTO_TAG_FAIL)
                master_report_fail(&msg, d);
            else if (msg.tag != PROTO_TAG_RESULT)
                csg_error_plain(d, "worker %d: unexpected message (tag %d)", src, msg.tag);
            failed = true;
        }
        if (!failed && next < job->todo_count) { /* self-scheduling: next tile */
            holding[src] = job->todo[next++];
            master_send_tile(m, job, out, src, holding[src]);
            outstanding++;
        }
    }
    link_msg_free(&msg);
    return !failed;
}

bool master_run_tiles(master_session *m, master_job *job, csg_diag *d)
{
    char *out = malloc(proto_worker_limit(&job->grid)); /* the largest TILE */
    int *holding = malloc(sizeof *holding * (size_t)(m->workers + 1));
    bool ok = false;
    for (int r = 1; r <= m->workers; r++)
        job->workers[r - 1].rank = r;
    if (!out || !holding) {
        csg_error_plain(d, "master: out of memory");
    } else {
        if (!m->greeted) {
            link_msg msg = {NULL, 0, 0, 0, 0};
            master_greet(m, &msg, d);
            link_msg_free(&msg);
        }
        ok = !m->setup_failed && master_deal(m, job, out, holding, d);
    }
    free(out);
    free(holding);
    return ok;
}

void master_job_count(master_job *job, stats_worker *w, const tile_result *res)
{
    w->tiles++;
    w->hits += res->hits;
    w->busy_s += res->busy_s;
    stats_add_rays(&w->rays, &res->rays);
    stats_add_rays(&job->rays, &res->rays);
    if (!job->t) /* (hetero counts them from the OpenCL tile hits) */
        job->pixels_hit += res->hits;
}

void master_end(master_session *m, int status)
{
    if (m->workers == 0)
        return;
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
        proto_stop stop = {status, 0};
        for (int r = 1; r <= m->workers; r++)
            link_send(r, PROTO_TAG_STOP, &stop, sizeof stop);
        m->bytes_sent += (uint64_t)m->workers * sizeof stop;
        m->stopped = true;
    }
}
