/*
 * store.c — the store thread (store.h).
 *
 * One producer (rank 0's main thread) and one consumer (the thread) share
 * a ring of STORE_RING_BYTES.  Positions are byte counts since the start
 * that only grow: `head` is what the producer has written, `tail` what the
 * consumer has stored; a record is a header and the part's bytes, padded
 * to STORE_ALIGN, and a header of width 0 marks the ring's end (the next
 * record starts again at offset 0).  The producer publishes a record by
 * moving head on (release), the consumer frees it by moving tail on once
 * its pixels are in the image (pixels_store_bytes_rect makes its stores
 * visible first), so a tile is complete in the image when tail has passed
 * the head of the moment the tile was complete (store_after).
 *
 * An idle consumer sleeps on a condition variable for STORE_POLL_NS at
 * most.  The producer wakes it at once only when it must not wait that
 * long (the ring a quarter full, store_drain), and only when it said it
 * sleeps: `sleeping` and `head` are sequentially consistent, so either the
 * consumer sees the new head before it waits, or the producer sees
 * `sleeping` and signals under the mutex the consumer holds until it
 * waits.
 */
#include "store.h"

#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "deadline.h"
#include "pixels.h"

#define STORE_WAIT_NS 20000L               /* store_finished's naps      */
/* An idle consumer looks again this often unless woken: waking it for
 * every part (a futex call) cost the main loop 3.4 us a part with one
 * worker; the journal and the end of the tile phase are all that wait
 * for it, and store_drain wakes it. */
#define STORE_POLL_NS 1000000L

typedef struct {
    int32_t x, y, width, height; /* width 0: the ring's end */
    uint32_t bytes;
    uint8_t pad[STORE_ALIGN - 5 * sizeof(int32_t)];
} store_record;
_Static_assert(sizeof(store_record) == STORE_ALIGN, "a header is one STORE_ALIGN");
_Static_assert(STORE_RING_BYTES % STORE_ALIGN == 0, "a ring's end always has room for a header");

struct store {
    float *image;
    int width;
    uint8_t *ring;
    _Atomic uint64_t head, tail;
    atomic_int sleeping, stop;
    pthread_mutex_t mutex;
    pthread_cond_t wake;
    pthread_t thread;
    /* main thread only: the tiles store_after deferred, oldest first */
    int *pending;
    uint64_t *pending_at; /* head when the tile was complete */
    int pending_first, pending_count, tiles;
};

static size_t store_record_size(uint32_t bytes)
{
    return (sizeof(store_record) + bytes + STORE_ALIGN - 1) / STORE_ALIGN * STORE_ALIGN;
}

/* The consumer, with nothing to do at `at`: sleeps until it is woken or
 * STORE_POLL_NS have passed; false once stopped with nothing left. */
static bool store_wait_work(store *s, uint64_t at)
{
    if (atomic_load(&s->head) != at)
        return true;
    pthread_mutex_lock(&s->mutex);
    atomic_store(&s->sleeping, 1);
    if (atomic_load(&s->head) == at && !atomic_load(&s->stop)) {
        struct timespec until = deadline_after_ns(STORE_POLL_NS);
        pthread_cond_timedwait(&s->wake, &s->mutex, &until);
    }
    atomic_store(&s->sleeping, 0);
    pthread_mutex_unlock(&s->mutex);
    return atomic_load(&s->head) != at || !atomic_load(&s->stop);
}

/* The consumer woken now, if it sleeps. */
static void store_wake(store *s)
{
    if (atomic_load(&s->sleeping)) {
        pthread_mutex_lock(&s->mutex);
        pthread_cond_signal(&s->wake);
        pthread_mutex_unlock(&s->mutex);
    }
}

static void *store_run(void *arg)
{
    store *s = arg;
    uint64_t at = atomic_load_explicit(&s->tail, memory_order_relaxed);
    while (store_wait_work(s, at)) {
        uint64_t head = atomic_load_explicit(&s->head, memory_order_acquire);
        while (at != head) {
            size_t offset = (size_t)(at % STORE_RING_BYTES);
            store_record rec;
            memcpy(&rec, s->ring + offset, sizeof rec);
            if (rec.width == 0) { /* the ring's end */
                at += STORE_RING_BYTES - offset;
            } else {
                pixels_store_bytes_rect(s->image, s->width, rec.x, rec.y, rec.width, rec.height,
                                        s->ring + offset + sizeof rec);
                at += store_record_size(rec.bytes);
            }
            atomic_store_explicit(&s->tail, at, memory_order_release);
        }
    }
    return NULL;
}

static void store_free(store *s)
{
    free(s->ring);
    free(s->pending);
    free(s->pending_at);
    free(s);
}

store *store_start(float *image, int width, int tiles)
{
    store *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->image = image;
    s->width = width;
    s->tiles = tiles > 0 ? tiles : 1;
    s->ring = malloc(STORE_RING_BYTES);
    s->pending = malloc((size_t)s->tiles * sizeof *s->pending);
    s->pending_at = malloc((size_t)s->tiles * sizeof *s->pending_at);
    if (!s->ring || !s->pending || !s->pending_at || pthread_mutex_init(&s->mutex, NULL) != 0) {
        store_free(s);
        return NULL;
    }
    pthread_condattr_t attr;
    bool cond = pthread_condattr_init(&attr) == 0;
    cond = cond && pthread_condattr_setclock(&attr, CLOCK_MONOTONIC) == 0 &&
           pthread_cond_init(&s->wake, &attr) == 0;
    pthread_condattr_destroy(&attr);
    if (!cond) {
        pthread_mutex_destroy(&s->mutex);
        store_free(s);
        return NULL;
    }
    /* the thread takes no signal: they stay the main thread's (signals.c) */
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &old);
    int failed = pthread_create(&s->thread, NULL, store_run, s);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (failed) {
        pthread_cond_destroy(&s->wake);
        pthread_mutex_destroy(&s->mutex);
        store_free(s);
        return NULL;
    }
    return s;
}

bool store_queue(store *s, tile_rect r, const uint8_t *rgb8)
{
    uint32_t bytes = (uint32_t)((size_t)r.width * (size_t)r.height * 3);
    size_t need = store_record_size(bytes);
    uint64_t head = atomic_load_explicit(&s->head, memory_order_relaxed);
    uint64_t tail = atomic_load_explicit(&s->tail, memory_order_acquire);
    size_t offset = (size_t)(head % STORE_RING_BYTES), to_end = STORE_RING_BYTES - offset;
    size_t skip = need > to_end ? to_end : 0; /* (to_end is a record size at least) */
    if (r.width <= 0 || r.height <= 0 || need + skip > STORE_RING_BYTES - (size_t)(head - tail))
        return false;
    if (skip) {
        store_record end = {0};
        memcpy(s->ring + offset, &end, sizeof end);
        offset = 0;
    }
    store_record rec = {.x = r.x, .y = r.y, .width = r.width, .height = r.height, .bytes = bytes};
    memcpy(s->ring + offset, &rec, sizeof rec);
    memcpy(s->ring + offset + sizeof rec, rgb8, bytes);
    atomic_store(&s->head, head + skip + need); /* (sequentially consistent: see the top) */
    if (head + skip + need - tail > STORE_RING_BYTES / 4)
        store_wake(s); /* (a quarter full: not waiting for its next look) */
    return true;
}

/* Until tail reaches `at`. */
static void store_wait_for(store *s, uint64_t at)
{
    struct timespec nap = {0, STORE_WAIT_NS};
    while (atomic_load_explicit(&s->tail, memory_order_acquire) < at)
        nanosleep(&nap, NULL);
}

bool store_after(store *s, int tile)
{
    uint64_t head = atomic_load_explicit(&s->head, memory_order_relaxed);
    if (atomic_load_explicit(&s->tail, memory_order_acquire) == head)
        return true;
    if (s->pending_count >= s->tiles)
        return true; /* (each tile once: never) */
    int slot = (s->pending_first + s->pending_count) % s->tiles;
    s->pending[slot] = tile;
    s->pending_at[slot] = head;
    s->pending_count++;
    return false;
}

bool store_finished(store *s, int *tile, bool wait)
{
    if (s->pending_count == 0)
        return false;
    uint64_t at = s->pending_at[s->pending_first];
    if (!wait && atomic_load_explicit(&s->tail, memory_order_acquire) < at)
        return false;
    store_wait_for(s, at);
    *tile = s->pending[s->pending_first];
    s->pending_first = (s->pending_first + 1) % s->tiles;
    s->pending_count--;
    return true;
}

void store_drain(store *s)
{
    store_wake(s);
    store_wait_for(s, atomic_load_explicit(&s->head, memory_order_relaxed));
}

void store_stop(store *s)
{
    if (!s)
        return;
    pthread_mutex_lock(&s->mutex);
    atomic_store(&s->stop, 1);
    pthread_cond_signal(&s->wake);
    pthread_mutex_unlock(&s->mutex);
    pthread_join(s->thread, NULL);
    pthread_cond_destroy(&s->wake);
    pthread_mutex_destroy(&s->mutex);
    store_free(s);
}
