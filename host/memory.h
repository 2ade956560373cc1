/*
 * memory.h — what a render holds at its peak on the process that owns the
 * image, estimated before anything is allocated, and what this process may
 * still allocate: a render that cannot fit says so up front with the
 * figures, instead of growing until the kernel kills it.
 */
#ifndef HOST_MEMORY_H
#define HOST_MEMORY_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint64_t image;   /* the float RGB image                             */
    uint64_t records; /* hetero: the hit records (t and surface id)      */
    uint64_t device;  /* hetero: the OpenCL pass's record buffers, one
                         slice's (reused from slice to slice)            */
    uint64_t writer;  /* what the encoder holds (memory.c)              */
    uint64_t tiles;   /* the master's bookkeeping of the tiles, from the
                         tile phase to the end (memory_tile_bytes a
                         tile: --tile 1 makes it the largest part)       */
    uint64_t total;   /* the peak: the image, the tiles, the records
                         (tile phase) and the writer, which encodes
                         during the tile phase (every format)            */
} render_memory;

/* The master's bookkeeping of one tile, in bytes (memory.c lists it);
 * `hetero` adds the pass's. */
uint64_t memory_tile_bytes(bool hetero);

/* Rows of the image the encoder holds at a time, as bytes, for the
 * module's 8-bit formats (host/output/image_oiio.cpp, display_strip_rows);
 * a PPM's band at most (host/output/stream.c). */
#define MEMORY_WRITER_STRIP_ROWS 64

/* The image's pages faulted in by a thread of their own, in address
 * order, while the render goes on (madvise MADV_POPULATE_WRITE: the
 * contents are never touched, so the master may store into them
 * meanwhile).  Without it the master takes a page fault each 4 KiB of
 * each row it first stores: a 32x32 tile's rows, 32 faults, in the loop
 * that answers the workers (2048x2048, one worker: over half of the
 * master's time storing pixels).  Images under 8 MiB, and kernels without
 * MADV_POPULATE_WRITE (before 5.14), go without. */
typedef struct {
    pthread_t thread;
    bool running;
    char *start;
    size_t len;
} memory_prefault;

void memory_prefault_start(memory_prefault *p, void *image, size_t bytes);
/* The image's memory (free() frees it), NULL when there is none.  From
 * MEMORY_PREFAULT_MIN bytes on it is aligned to 2 MiB and asks for
 * transparent huge pages (madvise MADV_HUGEPAGE: Debian's kernels give
 * them on request only).  A 32x32 part is 32 rows of the image, each on a
 * 4 KiB page of its own, and the parts of a batch lie across the image:
 * with small pages the store threads took a TLB miss a row (bench/
 * store_threads.c: 3.2 ns a pixel in scattered order against 1.8 in
 * raster order; 2.1 with huge pages). */
void *memory_image_alloc(size_t bytes);
/* Waits for the thread (if any); safe to call again. */
void memory_prefault_join(memory_prefault *p);

/* The peak of a render of width x height pixels in tiles of `tile`, at
 * `spp` samples, `real_size` bytes a real; `slice_rows` > 0 (hetero) adds
 * the hit records and the OpenCL buffers of a slice of that many rows;
 * `out_path` (NULL: none) tells the encoder's depth by its extension. */
render_memory render_memory_need(int width, int height, int tile, int spp, size_t real_size,
                                 int slice_rows, const char *out_path);

/* The bytes this process may still allocate: the least of the machine's
 * MemAvailable and what RLIMIT_AS and RLIMIT_DATA leave; false when none of
 * them can be read (then nothing is known and nothing is refused). */
bool memory_available(uint64_t *bytes);

/* Formats `bytes` as "1.23 GiB" (or MiB, KiB) into buf. */
const char *memory_format(uint64_t bytes, char *buf, size_t size);

#endif
