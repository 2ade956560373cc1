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

/* Pages faulted in by a thread of their own while the render goes on
 * (madvise MADV_POPULATE_WRITE: the contents are never touched, so the
 * master may store into them, or a device write them, meanwhile).
 *
 * - The image, in address order.  Without it the master takes a page
 *   fault each 4 KiB of each row it first stores: a 32x32 tile's rows, 32
 *   faults, in the loop that answers the workers (2048x2048, one worker:
 *   over half of the master's time storing pixels).
 * - The hit records of hetero's pass (host/pass/pass.c), its arrays a
 *   step of each in turn, so that the first slices' records are resident
 *   first.  Fresh, their 134 MB at 4096x4096 took 65-100 ms of page
 *   faults touched in small pages on this machine's core (34-44 ms
 *   through MADV_POPULATE_WRITE), where the H200's kernel took 18 ms for
 *   the whole frame: the driver's copies into the arrays (a discrete GPU)
 *   took them, after each slice's kernels.
 *
 * Ranges of under 8 MiB in all, and kernels without MADV_POPULATE_WRITE
 * (before 5.14), go without. */
#define MEMORY_PREFAULT_RANGES 4

typedef struct {
    pthread_t thread;
    bool running;
    int count;
    char *start[MEMORY_PREFAULT_RANGES];
    size_t len[MEMORY_PREFAULT_RANGES];
} memory_prefault;

void memory_prefault_start(memory_prefault *p, void *image, size_t bytes);
/* The same over up to MEMORY_PREFAULT_RANGES arrays at once (NULL ones
 * skipped), the same fraction of each a step. */
void memory_prefault_start_arrays(memory_prefault *p, void *const *arrays, const size_t *bytes,
                                  int count);
/* Large arrays' memory (free() frees it), NULL when there is none: the
 * image, the hit records.  Always aligned to a page (4 KiB: what an
 * OpenCL device asks of the host memory it writes in place, host/pass/
 * ocl.h).  `huge`, from MEMORY_PREFAULT_MIN bytes on: aligned to 2 MiB
 * and in transparent huge pages (madvise MADV_HUGEPAGE: Debian's kernels
 * give them on request only).  The image asks for them: a 32x32 part is
 * 32 rows of the image, each on a 4 KiB page of its own, and the parts
 * of a batch lie across the image: with small pages the store threads
 * took a TLB miss a row (bench/store_threads.c: 3.2 ns a pixel in
 * scattered order against 1.8 in raster order; 2.1 with huge pages).
 * The hit records do not: written in order by a device's threads, they
 * gain no TLB reach, and PoCL's pass over huge pages was no faster in
 * two interleaved runs at 4096x4096 on 2 cores (0.33 / 0.44 s against
 * 0.22 / 0.30 s in small pages: a 2 MiB page zeroed at a fault stalls
 * every thread that writes it). */
void *memory_pages_alloc(size_t bytes, bool huge);
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
