/*
 * store.h — threads of rank 0's that write the received 8-bit tile parts
 * into the float image, so that the master's own loop only checks a part,
 * copies its bytes into a ring and goes back to the workers.
 *
 * Turning a byte into the float the image keeps (pixels.h) and writing 12
 * bytes of image a pixel was most of rank 0's work on a result (bench/
 * SCALE.md, "the master's own work"), and the master's work on results is
 * what bounds the simulated 256-worker cluster.  A thread does it on
 * another core; with several (--store-threads, where rank 0's node has
 * the cores), each has a ring of its own and a part goes to the one with
 * the least waiting.
 *
 * Use (master.c, from rank 0's main thread only):
 *   s = store_start(image, width, tiles, n); NULL: store every part yourself
 *   store_queue(s, rect, bytes)              false: no room, store it yourself
 *   store_queue_compressed(s, rect, z, n, tag)
 *                                            the same, the thread decompressing
 *   store_corrupt(s)                         the tag of a part that did not
 *                                            decompress (the render has failed)
 *   store_after(s, tile)                     the tile is complete: true when
 *                                            every byte queued so far is in
 *                                            the image (journal it now), else
 *                                            store_finished gives it back once so
 *   store_finished(s, &tile, wait)           a tile whose bytes are all stored
 *   store_drain(s)                           every queued part in the image
 *   store_stop(s)                            every queued part stored, then
 *                                            the thread is gone
 * A tile is handed to the journal (which reads its pixels from the image)
 * only once it is in the image: that is what store_after and
 * store_finished are for.
 */
#ifndef HOST_STORE_H
#define HOST_STORE_H

#include <stdbool.h>
#include <stdint.h>

#include "../workers/tile.h"

/* A thread's ring: ~2600 parts of 32x32 (a record: its STORE_ALIGN-byte
 * header and its bytes, padded to STORE_ALIGN). */
#define STORE_RING_BYTES ((size_t)8 << 20)
#define STORE_ALIGN 32
#define STORE_THREADS_MAX 8
/* --store-threads auto: a thread for every so many workers.  A thread
 * stores 185 to 300 M pixels a second (5.4 ns a pixel with 16 parts a
 * RESULT in 4 KiB pages, 3.3 with huge pages: bench/SCALE.md), and a
 * worker on the paper's scene returns about 1.2 M a second (the node's
 * 15 workers, 2048x2048 and 4096x4096): one thread keeps up with 150-250
 * such workers, 64 with workers two to four times faster. */
#define STORE_WORKERS_A_THREAD 64

typedef struct store store;

/* The store threads of --store-threads auto for `workers` workers (the
 * relays not counted): one for every STORE_WORKERS_A_THREAD, 1 to
 * STORE_THREADS_MAX. */
int store_threads_auto(int workers);

/* `threads` store threads (1..STORE_THREADS_MAX; as many as start) for an
 * image `width` pixels wide of `tiles` tiles; NULL (out of memory, no
 * thread): the caller stores every part itself. */
store *store_start(float *image, int width, int tiles, int threads);
/* The threads running (0 for NULL). */
int store_threads(const store *s);
/* The CPU seconds the threads have taken so far, all together (0 for
 * NULL). */
double store_cpu_s(const store *s);
/* Rectangle r's packed 8-bit values (3 a pixel) copied into a ring, to
 * be stored; false when no ring has room for them (nothing queued). */
bool store_queue(store *s, tile_rect r, const uint8_t *rgb8);
/* Rectangle r's compressed 8-bit values (a Zstandard frame of `bytes`,
 * PIXELS_RGB8Z: comm/pixels_z.h) copied into a ring, to be decompressed by
 * the thread, off rank 0's loop, then stored; `tag` (>= 0) is the
 * caller's name for the part.  False when no ring has room for them
 * (nothing queued). */
bool store_queue_compressed(store *s, tile_rect r, const uint8_t *z, size_t bytes, int32_t tag);
/* The tag of the first compressed part that did not decompress to exactly
 * its rectangle (a worker's corrupt answer: nothing of it stored), or -1
 * when none has so far.  From then on no tile is ever complete (store_after
 * and store_finished give none), so none reaches the journal or the
 * file. */
int32_t store_corrupt(const store *s);
/* Tile `tile` is complete (every part of it queued or stored): true when
 * all that was queued is already in the image, else false and the tile is
 * given back by store_finished once it is.  Each tile at most once. */
bool store_after(store *s, int tile);
/* A tile of store_after's whose bytes are now all in the image, into
 * *tile; with `wait`, waits for the thread while some is pending.  False
 * when none (is left). */
bool store_finished(store *s, int *tile, bool wait);
/* Returns once every part queued is in the image. */
void store_drain(store *s);
/* Every queued part stored, the thread joined, everything freed. */
void store_stop(store *s);

#endif
