/*
 * master.c — rank 0 of the tile protocol described in host/protocol.h.
 *
 * Algorithm (self-scheduling, as in Tachyon and the classic examples):
 *   1. broadcast the status, then the blob in chunks;
 *   2. receive one handshake (READY or FAIL) from every worker;
 *   3. give every worker one tile, then answer each RESULT with the next
 *      tile to the rank that returned it, until the tiles run out; then
 *      drain the outstanding results;
 *   4. STOP(status) to every worker (master_end).
 * A FAIL (or a malformed answer) ends the sending of tiles; the outstanding
 * tiles are still drained so that no rank blocks in a send, then every
 * worker gets STOP(1).  Nothing is ever MPI_Abort'ed for bad input: the
 * only MPI_Abort (code 1) is a rank running out of memory for a message
 * it must receive.
 *
 * Invariants: holding[r] is the tile rank r is working on (-1: none), so
 * a worker holds at most one tile and STOP only goes to idle workers; the
 * bytes counters count every message's whole size.
 */
#include "master.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "protocol.h"

bool master_launched_by_mpirun(void)
{
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMI_SIZE") || getenv("PMIX_RANK");
}

static void master_finalize_at_exit(void)
{
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized)
        MPI_Finalize();
}

bool master_mpi_start(int *rank, int *size)
{
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
        if (MPI_Init(NULL, NULL) != MPI_SUCCESS)
            return false;
        atexit(master_finalize_at_exit);
    }
    return MPI_Comm_rank(MPI_COMM_WORLD, rank) == MPI_SUCCESS &&
           MPI_Comm_size(MPI_COMM_WORLD, size) == MPI_SUCCESS;
}

void master_begin(master_session *m, int ranks)
{
    memset(m, 0, sizeof *m);
    m->workers = ranks > 1 ? ranks - 1 : 0;
}

void master_share_scene(master_session *m, int status, int mode, int tile, const csg_blob *blob)
{
    if (m->workers == 0 || m->shared)
        return;
    proto_setup setup = { status, mode, tile, 0, status == 0 ? blob->size : 0 };
    MPI_Bcast(&setup, (int)sizeof setup, MPI_BYTE, 0, MPI_COMM_WORLD);
    m->bytes_sent += (uint64_t)m->workers * sizeof setup;
    m->shared = true;
    if (status != 0) {
        m->greeted = m->stopped = true; /* the workers exit at once */
        return;
    }
    for (size_t off = 0; off < blob->size; off += PROTO_BCAST_CHUNK) {
        size_t n = blob->size - off < PROTO_BCAST_CHUNK ? blob->size - off : PROTO_BCAST_CHUNK;
        MPI_Bcast((char *)blob->bytes + off, (int)n, MPI_BYTE, 0, MPI_COMM_WORLD);
    }
    m->bytes_sent += (uint64_t)m->workers * blob->size;
}

/* ---- receiving ------------------------------------------------------------ */

typedef struct {
    char *data;
    size_t cap;
    size_t len;  /* bytes of the last message */
    int source;
    int tag;
} master_msg;

/* Probes until a message from any worker is there.  Not MPI_Probe: a
 * blocked MPI_Probe spins on a core, which the workers (more ranks than
 * cores) or the OpenCL pass need; so poll, then sleep with a back-off
 * capped at MASTER_NAP_MAX_NS (a small delay next to a tile's work). */
#define MASTER_SPINS 200
#define MASTER_NAP_MAX_NS 200000L
static void master_wait(MPI_Status *st)
{
    long nap = 1000;
    for (int spins = 0;; spins++) {
        int flag = 0;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, st);
        if (flag)
            return;
        if (spins < MASTER_SPINS)
            continue;
        struct timespec ts = { 0, nap };
        nanosleep(&ts, NULL);
        nap = nap * 2 < MASTER_NAP_MAX_NS ? nap * 2 : MASTER_NAP_MAX_NS;
    }
}

/* The next message from any worker, whatever its size. */
static void master_recv(master_session *m, master_msg *msg)
{
    MPI_Status st;
    int count = 0;
    master_wait(&st);
    MPI_Get_count(&st, MPI_BYTE, &count);
    if ((size_t)count + 1 > msg->cap) {
        char *p = realloc(msg->data, (size_t)count + 1);
        if (!p) {
            fprintf(stderr, "csgtrace: error: master: out of memory for a %d-byte message\n",
                    count);
            MPI_Abort(MPI_COMM_WORLD, 1);
        }
        msg->data = p;
        msg->cap = (size_t)count + 1;
    }
    MPI_Recv(msg->data, count, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    msg->data[count] = '\0';
    msg->len = (size_t)count;
    msg->source = st.MPI_SOURCE;
    msg->tag = st.MPI_TAG;
    m->bytes_received += (uint64_t)count;
}

/* The text of a FAIL message, NUL-terminated whatever was sent. */
static void master_fail_text(const master_msg *msg, int *tile, char *text, size_t size)
{
    proto_fail f;
    memset(&f, 0, sizeof f);
    memcpy(&f, msg->data, msg->len < sizeof f ? msg->len : sizeof f);
    f.text[PROTO_FAIL_TEXT - 1] = '\0';
    *tile = msg->len >= sizeof f ? f.index : -1;
    snprintf(text, size, "%s", f.text[0] ? f.text : "no reason given");
}

static void master_report_fail(const master_msg *msg, csg_diag *d)
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
static void master_greet(master_session *m, master_msg *msg, csg_diag *d)
{
    for (int i = 0; i < m->workers; i++) {
        master_recv(m, msg);
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

typedef struct {
    char *data;
    size_t cap;
} master_out;

static void master_send_tile(master_session *m, const master_job *job, master_out *out, int worker,
                             int index)
{
    tile_rect r = proto_tile_rect(index, job->width, job->height, job->tile);
    int spp = csg_blob_hdr(job->blob)->spp;
    size_t n = (size_t)r.width * (size_t)r.height * (size_t)spp; /* records */
    size_t real_size = csg_blob_hdr(job->blob)->real_size;
    proto_tile h = { index, job->t ? PROTO_WORK_SHADE : PROTO_WORK_RENDER, r.x, r.y, r.width,
                     r.height };
    size_t len = sizeof h;
    memcpy(out->data, &h, sizeof h);
    if (job->t) {
        char *t = out->data + sizeof h;
        proto_pack_records(job->t, job->surf, job->width, spp, real_size, r, t,
                           (uint32_t *)(void *)(t + n * real_size));
        len += n * (real_size + sizeof(uint32_t));
    }
    MPI_Send(out->data, (int)len, MPI_BYTE, worker, PROTO_TAG_TILE, MPI_COMM_WORLD);
    m->bytes_sent += len;
}

/* A RESULT from a worker that holds `index`: checked, stored, counted. */
static bool master_take_result(master_job *job, const master_msg *msg, int index, csg_diag *d)
{
    tile_rect r = proto_tile_rect(index, job->width, job->height, job->tile);
    size_t n = (size_t)r.width * (size_t)r.height;
    proto_result h;
    if (msg->len != sizeof h + n * 3 * sizeof(float)) {
        csg_error_plain(d, "worker %d: result of tile %d has %zu bytes, expected %zu",
                        msg->source, index, msg->len, sizeof h + n * 3 * sizeof(float));
        return false;
    }
    memcpy(&h, msg->data, sizeof h);
    if (h.index != index || h.hits > n * (size_t)csg_blob_hdr(job->blob)->spp) {
        csg_error_plain(d, "worker %d: result for tile %d does not match tile %d sent",
                        msg->source, (int)h.index, index);
        return false;
    }
    /* msg->data is malloc'd and sizeof h a multiple of 8: floats aligned */
    const float *rgb = (const float *)(const void *)(msg->data + sizeof h);
    proto_store_rgb(job->image, job->width, r, rgb);
    ray_counts rays = { h.primary, h.shadow, h.reflected, h.refracted };
    stats_worker *w = &job->workers[msg->source - 1];
    w->rank = msg->source;
    w->tiles++;
    w->hits += h.hits;
    w->busy_s += h.busy_s;
    stats_add_rays(&w->rays, &rays);
    stats_add_rays(&job->rays, &rays);
    if (!job->t) /* (hetero counts them from the OpenCL tile hits) */
        job->pixels_hit += h.hits;
    return true;
}

bool master_run_tiles(master_session *m, master_job *job, csg_diag *d)
{
    master_msg msg = { NULL, 0, 0, 0, 0 };
    master_out out = { NULL, 0 };
    int *holding = NULL;
    bool ok = false;
    size_t real_size = csg_blob_hdr(job->blob)->real_size;
    size_t nmax = (size_t)(job->tile < job->width ? job->tile : job->width) *
                  (size_t)(job->tile < job->height ? job->tile : job->height);

    for (int r = 1; r <= m->workers; r++)
        job->workers[r - 1].rank = r;
    out.cap = sizeof(proto_tile) +
              nmax * (size_t)csg_blob_hdr(job->blob)->spp * (real_size + sizeof(uint32_t));
    out.data = malloc(out.cap);
    holding = malloc(sizeof *holding * (size_t)(m->workers + 1));
    if (!out.data || !holding) {
        csg_error_plain(d, "master: out of memory");
        goto fail;
    }
    if (!m->greeted)
        master_greet(m, &msg, d);
    if (m->setup_failed)
        goto fail;

    int next = 0, outstanding = 0;
    bool failed = false;
    for (int r = 1; r <= m->workers; r++) {
        holding[r] = -1;
        if (next < job->todo_count) {
            holding[r] = job->todo[next++];
            master_send_tile(m, job, &out, r, holding[r]);
            outstanding++;
        }
    }
    while (outstanding > 0) {
        master_recv(m, &msg);
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
            master_send_tile(m, job, &out, src, holding[src]);
            outstanding++;
        }
    }
    ok = !failed;

fail:
    free(msg.data);
    free(out.data);
    free(holding);
    return ok;
}

void master_end(master_session *m, int status)
{
    if (m->workers == 0)
        return;
    if (!m->shared) {
        master_share_scene(m, status ? status : 1, 0, 0, NULL);
        return;
    }
    if (!m->greeted) {
        master_msg msg = { NULL, 0, 0, 0, 0 };
        csg_diag ignored = { { 0 }, 0 };
        master_greet(m, &msg, &ignored); /* the master already failed: its message stands */
        free(msg.data);
    }
    if (!m->stopped) {
        proto_stop stop = { status, 0 };
        for (int r = 1; r <= m->workers; r++)
            MPI_Send(&stop, (int)sizeof stop, MPI_BYTE, r, PROTO_TAG_STOP, MPI_COMM_WORLD);
        m->bytes_sent += (uint64_t)m->workers * sizeof stop;
        m->stopped = true;
    }
}
