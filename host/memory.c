/*
 * memory.c — the render's peak memory against what the process may still
 * allocate (memory.h).
 */
#include "memory.h"
#include "output/image.h"
#include "schedule.h"
#include "../comm/pixels.h"
#include "../comm/tiles.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

/* What the encoder holds beside the image while the tiles are rendered
 * (every format is written band by band meanwhile): a PNG's encoded bands until they are written in
 * order (at worst, an image that does not compress, every band but the
 * first: 3 bytes a pixel); a PPM's band on each encoder thread, written at
 * once (one band of every CPU's, at most MEMORY_WRITER_STRIP_ROWS rows);
 * the module's formats, handed a band at a time in order by one thread: a
 * strip of 8-bit bytes, or a band of floats in the format's buffers
 * (OpenEXR's line buffers) and as many bytes again for their compressed
 * copy, at most. */
static uint64_t memory_writer(uint64_t width, uint64_t height, const char *out_path)
{
    uint64_t row = width * 3 * sizeof(float);
    uint64_t rows = height < MEMORY_WRITER_STRIP_ROWS ? height : MEMORY_WRITER_STRIP_ROWS;
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    if (!out_path)
        return 0;
    switch (img_format_of(out_path)) {
    case IMG_FORMAT_PNG:
        return width * height * 3;
    case IMG_FORMAT_PPM:
        return rows * width * 3 * (uint64_t)(cpus > 0 ? cpus : 1);
    case IMG_FORMAT_PFM:
        return rows * row * (uint64_t)(cpus > 0 ? cpus : 1);
    case IMG_FORMAT_MODULE:
        break;
    }
    return pixels_format_for(out_path) == PIXELS_RGB8 ? rows * width * 3 : 2 * rows * row;
}

/* What the master keeps a tile, allocated for every tile at the start of
 * the tile phase (or at its end) and held to the end of the render:
 *   the scheduler (host/schedule.h): the tile's item, and its slots in the
 *     FIFO, the heap, the static queues and the items left a tile;
 *   the journal (host/output/journal.c): resumed, hits, the writer's queue;
 *   the store (host/store.c): a tile's pending count and one thread's slot;
 *   the stats (host/stats.c): the correlation's estimate and seconds an
 *     item, at the end;
 *   hetero, the pass (host/pass/): its hits a tile, and the correlation's
 *     ranks (two doubles and an int an item).
 * Measured (PNG, serial): --tile 1 at 2000x2000, 4 M tiles, peaked at
 * 458 MB against 52 MB at --tile 32, ~101 bytes a tile resident (the heap,
 * the static queues and the correlation's arrays are allocated, not
 * touched); this counts what is allocated, 137 bytes (161 in hetero),
 * since an address-space limit counts that. */
uint64_t memory_tile_bytes(bool hetero)
{
    uint64_t bytes = sizeof(sched_item) + 4 * sizeof(int) +     /* the scheduler */
                     sizeof(bool) + sizeof(uint32_t) + sizeof(int) + /* the journal */
                     2 * sizeof(int) +                           /* the store     */
                     2 * sizeof(double);                         /* the stats     */
    if (hetero)
        bytes += sizeof(uint32_t) + 2 * sizeof(double) + sizeof(int); /* the pass */
    return bytes;
}

render_memory render_memory_need(int width, int height, int tile, int spp, size_t real_size,
                                 int slice_rows, const char *out_path)
{
    render_memory m = {0};
    uint64_t w = (uint64_t)(width > 0 ? width : 0), h = (uint64_t)(height > 0 ? height : 0);
    uint64_t record = (uint64_t)(spp > 0 ? spp : 1) * (real_size + sizeof(uint32_t));
    m.image = w * h * 3 * sizeof(float);
    m.tiles = tiles_wide(width, height, tile) * memory_tile_bytes(slice_rows > 0);
    if (slice_rows > 0) {
        m.records = w * h * record;
        m.device = w * (uint64_t)(slice_rows < height ? slice_rows : height) * record;
    }
    m.writer = memory_writer(w, h, out_path);
    m.total = m.image + m.tiles + m.records + m.device + m.writer;
    return m;
}

/* A "Name:   N kB" line of a /proc file, in bytes; false when absent. */
static bool proc_kib(const char *path, const char *name, uint64_t *bytes)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return false;
    char line[256];
    size_t n = strlen(name);
    bool found = false;
    unsigned long long kib = 0;
    while (!found && fgets(line, sizeof line, f))
        found = strncmp(line, name, n) == 0 && line[n] == ':' &&
                sscanf(line + n + 1, "%llu", &kib) == 1;
    fclose(f);
    *bytes = (uint64_t)kib * 1024;
    return found;
}

/* What a resource limit leaves above the process's current use. */
static void limit_left(int resource, const char *status_name, uint64_t *least, bool *known)
{
    struct rlimit rl;
    uint64_t used;
    if (getrlimit(resource, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY ||
        !proc_kib("/proc/self/status", status_name, &used))
        return;
    uint64_t left = (uint64_t)rl.rlim_cur > used ? (uint64_t)rl.rlim_cur - used : 0;
    if (!*known || left < *least)
        *least = left;
    *known = true;
}

bool memory_available(uint64_t *bytes)
{
    bool known = proc_kib("/proc/meminfo", "MemAvailable", bytes);
    limit_left(RLIMIT_AS, "VmSize", bytes, &known);
    limit_left(RLIMIT_DATA, "VmData", bytes, &known);
    return known;
}

const char *memory_format(uint64_t bytes, char *buf, size_t size)
{
    static const char *const units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
    double v = (double)bytes;
    int u = 0;
    while (v >= 1024 && u < 4) {
        v /= 1024;
        u++;
    }
    snprintf(buf, size, u ? "%.2f %s" : "%.0f %s", v, units[u]);
    return buf;
}

/* ---- the image's pages, faulted in meanwhile -------------------------------- */

#define MEMORY_PREFAULT_MIN ((size_t)8 << 20)
#define MEMORY_PREFAULT_STEP ((size_t)1 << 20) /* a madvise call at a time */
#define MEMORY_SMALL_ALIGN ((size_t)4096) /* a small page on x86-64 (memory_pages_alloc) */

static size_t memory_page_size(void)
{
    long page = sysconf(_SC_PAGESIZE);
    return page > 0 ? (size_t)page : MEMORY_SMALL_ALIGN;
}

/* Step by step, MEMORY_PREFAULT_STEP of the longest range and the same
 * fraction of every other, in turn (whole pages: the ranges start and end
 * on one, memory_prefault_start_arrays). */
static void *memory_prefault_run(void *arg)
{
#ifdef MADV_POPULATE_WRITE
    memory_prefault *p = arg;
    size_t page = memory_page_size(), longest = 0;
    for (int i = 0; i < p->count; i++)
        longest = p->len[i] > longest ? p->len[i] : longest;
    size_t steps = (longest + MEMORY_PREFAULT_STEP - 1) / MEMORY_PREFAULT_STEP;
    for (size_t k = 0; k < steps; k++)
        for (int i = 0; i < p->count; i++) {
            size_t chunk = ((p->len[i] + steps - 1) / steps + page - 1) / page * page;
            size_t from = k * chunk, to = from + chunk < p->len[i] ? from + chunk : p->len[i];
            if (to > from && madvise(p->start[i] + from, to - from, MADV_POPULATE_WRITE) != 0)
                return NULL; /* (an older kernel: EINVAL; the stores fault as before) */
        }
#else
    (void)arg;
#endif
    return NULL;
}

#define MEMORY_HUGE_PAGE ((size_t)2 << 20)

void *memory_pages_alloc(size_t bytes, bool huge)
{
    size_t align = !huge || bytes < MEMORY_PREFAULT_MIN ? MEMORY_SMALL_ALIGN : MEMORY_HUGE_PAGE;
    size_t whole = (bytes + align - 1) / align * align;
    void *p = aligned_alloc(align, whole ? whole : align);
#ifdef MADV_HUGEPAGE
    if (p && align == MEMORY_HUGE_PAGE)
        madvise(p, whole, MADV_HUGEPAGE); /* (a request: small pages if refused) */
#endif
    return p;
}

void memory_prefault_start_arrays(memory_prefault *p, void *const *arrays, const size_t *bytes,
                                  int count)
{
    memset(p, 0, sizeof *p);
    uintptr_t page = (uintptr_t)memory_page_size();
    size_t total = 0;
    for (int i = 0; i < count && i < MEMORY_PREFAULT_RANGES; i++) {
        if (!arrays[i])
            continue;
        uintptr_t first = ((uintptr_t)arrays[i] + page - 1) / page * page;
        uintptr_t end = ((uintptr_t)arrays[i] + bytes[i]) / page * page;
        if (end <= first)
            continue;
        p->start[p->count] = (char *)first;
        p->len[p->count++] = end - first;
        total += end - first;
    }
    if (total >= MEMORY_PREFAULT_MIN)
        p->running = pthread_create(&p->thread, NULL, memory_prefault_run, p) == 0;
}

void memory_prefault_start(memory_prefault *p, void *image, size_t bytes)
{
    memory_prefault_start_arrays(p, &image, &bytes, 1);
}

void memory_prefault_join(memory_prefault *p)
{
    if (p->running)
        pthread_join(p->thread, NULL);
    p->running = false;
}
