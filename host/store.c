/*
 * store.c — the store threads (store.h).
 *
 * Each thread is a lane: one producer (rank 0's main thread) and one
 * consumer (the lane's thread) share the lane's ring of STORE_RING_BYTES.
 * Positions are byte counts since the start that only grow: `head` is
 * what the producer has written, `tail` what the consumer has stored; a
 * record is a header and the part's bytes, padded to STORE_ALIGN, and a
 * header of width 0 marks the ring's end (the next record starts again at
 * offset 0).  The producer publishes a record by moving head on (release),
 * the consumer frees it by moving tail on once its pixels are in the image
 * (pixels_store_bytes_rect makes its stores visible first), so a tile is
 * complete in the image when every lane's tail has passed that lane's head
 * of the moment the tile was complete (store_after).  Parts are disjoint
 * rectangles, so the lanes never write the same pixel; a part goes to the
 * lane with the fewest bytes waiting.
 *
 * An idle consumer sleeps on its lane's condition variable for
 * STORE_POLL_NS at most.  The producer wakes it at once only when it must
 * not wait that long (its ring a quarter full, store_drain), and only when
 * it said it sleeps: `sleeping` and `head` are sequentially consistent, so
 * either the consumer sees the new head before it waits, or the producer
 * sees `sleeping` and signals under the mutex the consumer holds until it
 * waits.
 */
#include "store.h"

#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../comm/deadline.h"
#include "../comm/pixels.h"
#include "../comm/pixels_z.h"

#define STORE_WAIT_NS 20000L               /* store_finished's naps      */
/* An idle consumer looks again this often unless woken: waking it for
 * every part (a futex call) cost the main loop 3.4 us a part with one
 * worker; the journal and the end of the tile phase are all that wait
 * for it, and store_drain wakes it. */
#define STORE_POLL_NS 1000000L

typedef struct {
    int32_t x, y, width, height; /* width 0: the ring's end */
    uint32_t bytes;
    int32_t compressed;          /* 1: the bytes are a Zstandard frame */
    int32_t tag;                 /* the caller's (store_corrupt)       */
    uint8_t pad[STORE_ALIGN - 7 * sizeof(int32_t)];
} store_record;
_Static_assert(sizeof(store_record) == STORE_ALIGN, "a header is one STORE_ALIGN");
_Static_assert(STORE_RING_BYTES % STORE_ALIGN == 0, "a ring's end always has room for a header");

typedef struct store_lane {
    struct store *owner;
    uint8_t *ring;
    _Atomic uint64_t head, tail;
    atomic_int sleeping;
    pthread_mutex_t mutex;
    pthread_cond_t wake;
    pthread_t thread;
    pixels_zstream *decompressor; /* the thread's, made on its first
                                     compressed part                 */
    uint8_t *unpacked;        /* that part decompressed               */
    size_t unpacked_cap;
} store_lane;

struct store {
    float *image;
    int width;
    atomic_int stop;
    atomic_int corrupt; /* the tag + 1 of the first part that did not
                           decompress to its rectangle; 0: none          */
    int lanes;
    store_lane *lane[STORE_THREADS_MAX];
    /* main thread only: the tiles store_after deferred, oldest first, and
     * each lane's head when the tile was complete (`lanes` a tile) */
    int *pending;
    uint64_t *pending_at;
    int pending_first, pending_count, tiles;
    int last; /* the lane of the last part queued */
};

static size_t store_record_size(uint32_t bytes)
{
    return (sizeof(store_record) + bytes + STORE_ALIGN - 1) / STORE_ALIGN * STORE_ALIGN;
}

/* The consumer, with nothing to do at `at`: sleeps until it is woken or
 * STORE_POLL_NS have passed; false once stopped with nothing left. */
static bool store_wait_work(store_lane *l, uint64_t at)
{
    if (atomic_load(&l->head) != at)
        return true;
    pthread_mutex_lock(&l->mutex);
    atomic_store(&l->sleeping, 1);
    if (atomic_load(&l->head) == at && !atomic_load(&l->owner->stop)) {
        struct timespec until = deadline_after_ns(STORE_POLL_NS);
        pthread_cond_timedwait(&l->wake, &l->mutex, &until);
    }
    atomic_store(&l->sleeping, 0);
    pthread_mutex_unlock(&l->mutex);
    return atomic_load(&l->head) != at || !atomic_load(&l->owner->stop);
}

/* The lane's consumer woken now, if it sleeps. */
static void store_wake(store_lane *l)
{
    if (atomic_load(&l->sleeping)) {
        pthread_mutex_lock(&l->mutex);
        pthread_cond_signal(&l->wake);
        pthread_mutex_unlock(&l->mutex);
    }
}

/* A record's pixels into the image, decompressed first when compressed;
 * false when they do not decompress to its rectangle (nothing stored). */
static bool store_record_pixels(store_lane *l, const store_record *rec, const uint8_t *bytes)
{
    const store *s = l->owner;
    if (rec->compressed) {
        size_t need = (size_t)rec->width * (size_t)rec->height * 3;
        if (!l->decompressor)
            l->decompressor = pixels_decompressor_new();
        if (need > l->unpacked_cap) {
            free(l->unpacked);
            l->unpacked = malloc(need);
            l->unpacked_cap = l->unpacked ? need : 0;
        }
        if (!l->decompressor || !l->unpacked ||
            !pixels_decompress(l->decompressor, bytes, rec->bytes, l->unpacked, need))
            return false;
        bytes = l->unpacked;
    }
    pixels_store_bytes_rect(s->image, s->width, rec->x, rec->y, rec->width, rec->height, bytes);
    return true;
}

static void *store_run(void *arg)
{
    store_lane *l = arg;
    uint64_t at = atomic_load_explicit(&l->tail, memory_order_relaxed);
    while (store_wait_work(l, at)) {
        uint64_t head = atomic_load_explicit(&l->head, memory_order_acquire);
        while (at != head) {
            size_t offset = (size_t)(at % STORE_RING_BYTES);
            store_record rec;
            memcpy(&rec, l->ring + offset, sizeof rec);
            if (rec.width == 0) { /* the ring's end */
                at += STORE_RING_BYTES - offset;
            } else {
                if (!store_record_pixels(l, &rec, l->ring + offset + sizeof rec)) {
                    int none = 0; /* (the first one is reported; set before the tail moves) */
                    atomic_compare_exchange_strong(&l->owner->corrupt, &none, rec.tag + 1);
                }
                at += store_record_size(rec.bytes);
            }
            atomic_store_explicit(&l->tail, at, memory_order_release);
        }
    }
    return NULL;
}

/* A lane of s with its thread running; NULL when out of memory or
 * threads. */
static store_lane *store_lane_start(store *s)
{
    store_lane *l = calloc(1, sizeof *l);
    if (!l)
        return NULL;
    l->owner = s;
    l->ring = malloc(STORE_RING_BYTES);
    pthread_condattr_t attr;
    bool ok = l->ring && pthread_condattr_init(&attr) == 0;
    if (ok) {
        ok = pthread_condattr_setclock(&attr, CLOCK_MONOTONIC) == 0 &&
             pthread_cond_init(&l->wake, &attr) == 0;
        pthread_condattr_destroy(&attr);
    }
    if (ok && pthread_mutex_init(&l->mutex, NULL) != 0) {
        pthread_cond_destroy(&l->wake);
        ok = false;
    }
    if (ok) { /* the thread takes no signal: they stay the main thread's (signals.c) */
        sigset_t all, old;
        sigfillset(&all);
        pthread_sigmask(SIG_BLOCK, &all, &old);
        ok = pthread_create(&l->thread, NULL, store_run, l) == 0;
        pthread_sigmask(SIG_SETMASK, &old, NULL);
        if (!ok) {
            pthread_cond_destroy(&l->wake);
            pthread_mutex_destroy(&l->mutex);
        }
    }
    if (!ok) {
        free(l->ring);
        free(l);
        return NULL;
    }
    return l;
}

/* (s->stop set, lanes told) */
static void store_lane_join(store_lane *l)
{
    pthread_join(l->thread, NULL);
    pthread_cond_destroy(&l->wake);
    pthread_mutex_destroy(&l->mutex);
    pixels_zstream_free(l->decompressor);
    free(l->unpacked);
    free(l->ring);
    free(l);
}

static void store_free(store *s)
{
    free(s->pending);
    free(s->pending_at);
    free(s);
}

int store_threads_auto(int workers)
{
    int n = (workers + STORE_WORKERS_A_THREAD - 1) / STORE_WORKERS_A_THREAD;
    return n < 1 ? 1 : n > STORE_THREADS_MAX ? STORE_THREADS_MAX : n;
}

store *store_start(float *image, int width, int tiles, int threads)
{
    store *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->image = image;
    s->width = width;
    s->tiles = tiles > 0 ? tiles : 1;
    int want = threads < 1 ? 1 : threads > STORE_THREADS_MAX ? STORE_THREADS_MAX : threads;
    s->pending = malloc((size_t)s->tiles * sizeof *s->pending);
    s->pending_at = malloc((size_t)s->tiles * (size_t)want * sizeof *s->pending_at);
    if (!s->pending || !s->pending_at) {
        store_free(s);
        return NULL;
    }
    /* as many lanes as start (at least one) */
    while (s->lanes < want && (s->lane[s->lanes] = store_lane_start(s)))
        s->lanes++;
    if (s->lanes == 0) {
        store_free(s);
        return NULL;
    }
    return s;
}

int store_threads(const store *s)
{
    return s ? s->lanes : 0;
}

double store_cpu_s(const store *s)
{
    double sum = 0;
    for (int k = 0; s && k < s->lanes; k++) {
        clockid_t clock;
        struct timespec ts;
        if (pthread_getcpuclockid(s->lane[k]->thread, &clock) == 0 &&
            clock_gettime(clock, &ts) == 0)
            sum += (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
    }
    return sum;
}

/* Bytes queued in lane l and not stored yet. */
static uint64_t store_lane_waiting(store_lane *l)
{
    return atomic_load_explicit(&l->head, memory_order_relaxed) -
           atomic_load_explicit(&l->tail, memory_order_acquire);
}

/* Record `rec` and its bytes (`need` in all) into lane l: false when it
 * has no room. */
static bool store_lane_queue(store_lane *l, const store_record *rec, size_t need,
                             const uint8_t *bytes)
{
    uint64_t head = atomic_load_explicit(&l->head, memory_order_relaxed);
    uint64_t tail = atomic_load_explicit(&l->tail, memory_order_acquire);
    size_t offset = (size_t)(head % STORE_RING_BYTES), to_end = STORE_RING_BYTES - offset;
    size_t skip = need > to_end ? to_end : 0; /* (to_end is a record size at least) */
    if (need + skip > STORE_RING_BYTES - (size_t)(head - tail))
        return false;
    if (skip) {
        store_record end = {0};
        memcpy(l->ring + offset, &end, sizeof end);
        offset = 0;
    }
    memcpy(l->ring + offset, rec, sizeof *rec);
    memcpy(l->ring + offset + sizeof *rec, bytes, rec->bytes);
    atomic_store(&l->head, head + skip + need); /* (sequentially consistent: see the top) */
    if (head + skip + need - tail > STORE_RING_BYTES / 4)
        store_wake(l); /* (a quarter full: not waiting for its next look) */
    return true;
}

/* Record `rec` and its bytes into the lane with room that waits least. */
static bool store_queue_record(store *s, const store_record *rec, const uint8_t *bytes)
{
    size_t need = store_record_size(rec->bytes);
    if (rec->width <= 0 || rec->height <= 0 || need > STORE_RING_BYTES)
        return false;
    /* the lane with the fewest bytes waiting (ties: the next after the
     * last one used); the next fewest if it is full */
    bool tried[STORE_THREADS_MAX] = {false};
    for (int round = 0; round < s->lanes; round++) {
        int best = -1;
        uint64_t least = 0;
        for (int i = 1; i <= s->lanes; i++) {
            int k = (s->last + i) % s->lanes;
            uint64_t waiting = tried[k] ? 0 : store_lane_waiting(s->lane[k]);
            if (!tried[k] && (best < 0 || waiting < least)) {
                best = k;
                least = waiting;
            }
        }
        if (store_lane_queue(s->lane[best], rec, need, bytes)) {
            s->last = best;
            return true;
        }
        tried[best] = true;
    }
    return false;
}

bool store_queue(store *s, tile_rect r, const uint8_t *rgb8)
{
    store_record rec = {.x = r.x, .y = r.y, .width = r.width, .height = r.height};
    rec.bytes = (uint32_t)((size_t)r.width * (size_t)r.height * 3);
    return store_queue_record(s, &rec, rgb8);
}

bool store_queue_compressed(store *s, tile_rect r, const uint8_t *z, size_t bytes, int32_t tag)
{
    store_record rec = {.x = r.x, .y = r.y, .width = r.width, .height = r.height,
                        .bytes = (uint32_t)bytes, .compressed = 1, .tag = tag};
    return bytes < STORE_RING_BYTES && tag >= 0 && tag < INT32_MAX &&
           store_queue_record(s, &rec, z);
}

int32_t store_corrupt(const store *s)
{
    return s ? atomic_load((atomic_int *)&s->corrupt) - 1 : -1;
}

/* Has every lane's tail reached at[lane]? */
static bool store_reached(store *s, const uint64_t *at)
{
    for (int k = 0; k < s->lanes; k++)
        if (atomic_load_explicit(&s->lane[k]->tail, memory_order_acquire) < at[k])
            return false;
    return true;
}

/* Until every lane's tail reaches at[lane]. */
static void store_wait_for(store *s, const uint64_t *at)
{
    struct timespec nap = {0, STORE_WAIT_NS};
    while (!store_reached(s, at))
        nanosleep(&nap, NULL);
}

bool store_after(store *s, int tile)
{
    uint64_t heads[STORE_THREADS_MAX];
    for (int k = 0; k < s->lanes; k++)
        heads[k] = atomic_load_explicit(&s->lane[k]->head, memory_order_relaxed);
    if (store_reached(s, heads))
        return store_corrupt(s) < 0; /* (a corrupt part: no tile is ever complete) */
    if (s->pending_count >= s->tiles)
        return true; /* (each tile once: never) */
    int slot = (s->pending_first + s->pending_count) % s->tiles;
    s->pending[slot] = tile;
    memcpy(s->pending_at + (size_t)slot * (size_t)s->lanes, heads,
           (size_t)s->lanes * sizeof *heads);
    s->pending_count++;
    return false;
}

bool store_finished(store *s, int *tile, bool wait)
{
    if (s->pending_count == 0)
        return false;
    const uint64_t *at = s->pending_at + (size_t)s->pending_first * (size_t)s->lanes;
    if (!wait && !store_reached(s, at))
        return false;
    store_wait_for(s, at);
    if (store_corrupt(s) >= 0)
        return false;
    *tile = s->pending[s->pending_first];
    s->pending_first = (s->pending_first + 1) % s->tiles;
    s->pending_count--;
    return true;
}

void store_drain(store *s)
{
    uint64_t heads[STORE_THREADS_MAX];
    for (int k = 0; k < s->lanes; k++) {
        heads[k] = atomic_load_explicit(&s->lane[k]->head, memory_order_relaxed);
        store_wake(s->lane[k]);
    }
    store_wait_for(s, heads);
}

void store_stop(store *s)
{
    if (!s)
        return;
    atomic_store(&s->stop, 1);
    for (int k = 0; k < s->lanes; k++) { /* (under the mutex: not lost between its checks) */
        pthread_mutex_lock(&s->lane[k]->mutex);
        pthread_cond_signal(&s->lane[k]->wake);
        pthread_mutex_unlock(&s->lane[k]->mutex);
    }
    for (int k = 0; k < s->lanes; k++)
        store_lane_join(s->lane[k]);
    store_free(s);
}
