/*
 * worker.c — a worker rank of the tile protocol (protocol.h).
 *
 * Algorithm: take part in the setup broadcast; validate the blob and pick
 * its engine; allocate buffers for the largest tile; send READY (or FAIL
 * with the reason); then answer every TILE with one RESULT (render or
 * shade the tile) or one FAIL, until STOP, whose status is returned.
 *
 * Invariants: the worker never prints (the master reports once) and never
 * exits on its own after the setup: even when it failed it keeps answering
 * until STOP, so that the master can drain and nobody blocks (the one
 * exception, MPI_Abort with code 1 and a message, is having no memory to
 * receive a message: MPI can only take it whole).  Every
 * incoming message is received whatever its size (probe + count), then
 * checked against the tile it claims before any byte of it is used.
 */
#include "worker.h"

#include <mpi.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../host/protocol.h"

typedef struct {
    int rank;
    int fail_rank;        /* CSGTRACE_FAIL_WORKER, 0 when unset      */
    int tiles_done;
    char failure[PROTO_FAIL_TEXT]; /* "" or why this worker cannot work */
    void *blob;
    size_t blob_size;
    const engine *eng;
    int width, height, tile;
    size_t nmax;          /* pixels of the largest tile              */
    int spp;              /* records a pixel (the blob's samples)    */
    void *t;              /* nmax records                            */
    uint32_t *surf;
    char *in;             /* incoming message                        */
    size_t in_cap, in_len;
    char *out;            /* proto_result + nmax * 3 floats          */
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

/* The blob, in PROTO_BCAST_CHUNK pieces; into a sink when out of memory. */
static void worker_receive_blob(worker_state *w, size_t size)
{
    char sink[PROTO_BCAST_CHUNK];
    w->blob = malloc(size ? size : 1);
    w->blob_size = size;
    for (size_t off = 0; off < size; off += PROTO_BCAST_CHUNK) {
        size_t n = size - off < PROTO_BCAST_CHUNK ? size - off : PROTO_BCAST_CHUNK;
        MPI_Bcast(w->blob ? (char *)w->blob + off : sink, (int)n, MPI_BYTE, 0, MPI_COMM_WORLD);
    }
    if (!w->blob)
        worker_set_failure(w, "out of memory for the scene (%zu bytes)", size);
}

static void worker_prepare(worker_state *w, const proto_setup *setup)
{
    if (w->failure[0])
        return;
    if (!csg_blob_valid(w->blob, w->blob_size)) {
        worker_set_failure(w, "received an invalid scene blob (%zu bytes)", w->blob_size);
        return;
    }
    w->eng = engine_for_blob(w->blob);
    const csg_blob_header *h = csg_blob_hdr(w->blob);
    if (!w->eng || setup->tile <= 0 || h->width <= 0 || h->height <= 0) {
        worker_set_failure(w, "no engine or no valid tile for the scene received");
        return;
    }
    w->width = h->width;
    w->height = h->height;
    w->tile = setup->tile;
    w->spp = h->spp;
    w->nmax = (size_t)(w->tile < w->width ? w->tile : w->width) *
              (size_t)(w->tile < w->height ? w->tile : w->height);
    size_t records = w->nmax * (size_t)w->spp;
    w->t = malloc(records * w->eng->real_size);
    w->surf = malloc(records * sizeof *w->surf);
    w->out = malloc(sizeof(proto_result) + w->nmax * 3 * sizeof(float));
    w->in_cap = sizeof(proto_tile) + records * (w->eng->real_size + sizeof(uint32_t));
    w->in = malloc(w->in_cap);
    if (!w->in)
        w->in_cap = 0;
    if (!w->t || !w->surf || !w->out || !w->in)
        worker_set_failure(w, "out of memory for tiles of %zu pixels", w->nmax);
}

static void worker_send_fail(int index, const char *text)
{
    proto_fail f;
    memset(&f, 0, sizeof f);
    f.index = index;
    snprintf(f.text, sizeof f.text, "%s", text);
    MPI_Send(&f, (int)sizeof f, MPI_BYTE, 0, PROTO_TAG_FAIL, MPI_COMM_WORLD);
}

/* Probes until a message from the master is there.  Not MPI_Probe: a
 * blocked probe spins on a core for as long as the master is busy (the
 * OpenCL pass, other workers' tiles), a core that the others need when
 * ranks outnumber cores; so poll, then sleep with a back-off capped at
 * WORKER_NAP_MAX_NS (a small delay next to a tile's work). */
#define WORKER_SPINS 200
#define WORKER_NAP_MAX_NS 200000L
static void worker_wait(MPI_Status *st)
{
    long nap = 1000;
    for (int spins = 0;; spins++) {
        int flag = 0;
        MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, st);
        if (flag)
            return;
        if (spins < WORKER_SPINS)
            continue;
        struct timespec ts = { 0, nap };
        nanosleep(&ts, NULL);
        nap = nap * 2 < WORKER_NAP_MAX_NS ? nap * 2 : WORKER_NAP_MAX_NS;
    }
}

/* The next message from the master, whatever its size, into w->in; its tag. */
static int worker_recv(worker_state *w)
{
    MPI_Status st;
    int count = 0;
    worker_wait(&st);
    MPI_Get_count(&st, MPI_BYTE, &count);
    if ((size_t)count > w->in_cap) {
        char *p = realloc(w->in, (size_t)count);
        if (!p) {
            /* A message can only be received whole: nothing else to do. */
            fprintf(stderr, "csgtrace: error: worker %d: out of memory for a %d-byte message\n",
                    w->rank, count);
            MPI_Abort(MPI_COMM_WORLD, 1);
        }
        w->in = p;
        w->in_cap = (size_t)count;
    }
    MPI_Recv(w->in, count, MPI_BYTE, 0, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    w->in_len = (size_t)count;
    return st.MPI_TAG;
}

/* The tile of the message in w->in (header h): pixels into w->out; false
 * with the reason in *why when the message is malformed. */
static bool worker_do_tile(worker_state *w, const proto_tile *h, const char **why)
{
    double t0 = MPI_Wtime();
    tile_rect r = proto_tile_rect(h->index, w->width, w->height, w->tile);
    int tiles = proto_tile_count(w->width, w->height, w->tile);
    if (h->index < 0 || h->index >= tiles || r.x != h->x || r.y != h->y || r.width != h->width ||
        r.height != h->height) {
        *why = "tile outside the image";
        return false;
    }
    size_t n = (size_t)r.width * (size_t)r.height * (size_t)w->spp; /* records */
    size_t records = n * (w->eng->real_size + sizeof(uint32_t));
    ray_counts rays = { 0, 0, 0, 0 };
    float *rgb = (float *)(void *)(w->out + sizeof(proto_result));
    if (h->work == PROTO_WORK_RENDER && w->in_len == sizeof *h) {
        engine_render_tile(w->eng, w->blob, r, w->t, w->surf, rgb, &rays);
    } else if (h->work == PROTO_WORK_SHADE && w->in_len == sizeof *h + records) {
        memcpy(w->t, w->in + sizeof *h, n * w->eng->real_size);
        memcpy(w->surf, w->in + sizeof *h + n * w->eng->real_size, n * sizeof(uint32_t));
        w->eng->shade(w->blob, r, w->t, w->surf, rgb, &rays);
    } else {
        *why = "malformed tile message";
        return false;
    }
    uint32_t hits = 0;
    for (size_t i = 0; i < n; i++)
        hits += w->surf[i] != 0;
    proto_result res = { h->index, hits, rays.primary, rays.shadow, rays.reflected,
                         rays.refracted, MPI_Wtime() - t0 };
    memcpy(w->out, &res, sizeof res);
    return true;
}

static void worker_answer_tile(worker_state *w)
{
    proto_tile h;
    const char *why = NULL;
    if (w->failure[0]) {
        worker_send_fail(-1, w->failure);
        return;
    }
    if (w->in_len < sizeof h) {
        worker_send_fail(-1, "truncated tile message");
        return;
    }
    memcpy(&h, w->in, sizeof h);
    if (w->tiles_done == 0 && w->fail_rank == w->rank) {
        worker_send_fail(h.index, "internal failure injected by CSGTRACE_FAIL_WORKER");
        w->tiles_done++;
        return;
    }
    if (!worker_do_tile(w, &h, &why)) {
        worker_send_fail(h.index, why);
        return;
    }
    size_t n = (size_t)h.width * (size_t)h.height;
    MPI_Send(w->out, (int)(sizeof(proto_result) + n * 3 * sizeof(float)), MPI_BYTE, 0,
             PROTO_TAG_RESULT, MPI_COMM_WORLD);
    w->tiles_done++;
}

static void worker_free(worker_state *w)
{
    free(w->blob);
    free(w->t);
    free(w->surf);
    free(w->in);
    free(w->out);
}

int worker_run(void)
{
    worker_state w;
    memset(&w, 0, sizeof w);
    MPI_Comm_rank(MPI_COMM_WORLD, &w.rank);
    const char *hook = getenv("CSGTRACE_FAIL_WORKER");
    w.fail_rank = hook ? atoi(hook) : 0;

    proto_setup setup;
    MPI_Bcast(&setup, (int)sizeof setup, MPI_BYTE, 0, MPI_COMM_WORLD);
    if (setup.status != 0)
        return setup.status; /* the master reported why */
    worker_receive_blob(&w, (size_t)setup.blob_size);
    worker_prepare(&w, &setup);
    if (w.failure[0]) {
        worker_send_fail(-1, w.failure);
    } else {
        proto_ready ready = { 0, 0 };
        MPI_Send(&ready, (int)sizeof ready, MPI_BYTE, 0, PROTO_TAG_READY, MPI_COMM_WORLD);
    }

    int status = 1;
    for (;;) {
        int tag = worker_recv(&w);
        if (tag == PROTO_TAG_STOP) {
            proto_stop stop = { 1, 0 }; /* a short STOP still stops, with 1 */
            if (w.in_len >= sizeof stop)
                memcpy(&stop, w.in, sizeof stop);
            status = stop.status;
            break;
        }
        if (tag == PROTO_TAG_TILE)
            worker_answer_tile(&w);
        else
            worker_send_fail(-1, w.failure[0] ? w.failure : "unexpected message");
    }
    worker_free(&w);
    return status;
}
