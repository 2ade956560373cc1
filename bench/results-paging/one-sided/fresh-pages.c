/* fresh-pages.c: what a fresh memory page costs this machine, against
 * copying into memory pages that are kept (bench/PAGING.md, *Not done*).
 *
 * A 40 MiB anonymous mapping, as the pager maps a scene; 20 000 times a
 * random chunk is filled from a source copy while another chunk is given
 * back, as a fetch and an eviction do:
 *   mode 0: MADV_POPULATE_WRITE, copy, MADV_DONTNEED (the pager's way);
 *   mode 1: copy (faulting the pages in), MADV_DONTNEED;
 *   mode 2: copy into a budget's worth of chunks that are kept (what
 *           reusing evicted memory pages could cost at best).
 *
 *   cc -O2 -o /tmp/fresh-pages fresh-pages.c
 *   for c in 4 16 64; do for m in 0 1 2; do /tmp/fresh-pages $c $m; done; done
 */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: fresh-pages CHUNK_KIB MODE(0|1|2)\n");
        return 2;
    }
    size_t total = (size_t)40 << 20, chunk = (size_t)atoi(argv[1]) * 1024, budget = 1310000;
    int mode = atoi(argv[2]);
    if (chunk == 0 || chunk > budget || mode < 0 || mode > 2) {
        fprintf(stderr, "fresh-pages: chunk 1 to 1279 KiB, mode 0, 1 or 2\n");
        return 2;
    }
    unsigned char *src = malloc(total);
    unsigned char *map = mmap(NULL, total, PROT_READ | PROT_WRITE,
                              MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (!src || map == MAP_FAILED)
        return 1;
    memset(src, 7, total);
    size_t chunks = total / chunk, kept = budget / chunk, bytes = 0;
    srand(1);
    double t0 = now();
    for (int it = 0; it < 20000; it++) {
        size_t c = (size_t)rand() % chunks, gone = (c + chunks / 2) % chunks;
        unsigned char *to = mode == 2 ? map + ((size_t)it % kept) * chunk : map + c * chunk;
#ifdef MADV_POPULATE_WRITE
        if (mode == 0)
            madvise(to, chunk, MADV_POPULATE_WRITE);
#endif
        memcpy(to, src + c * chunk, chunk);
        if (mode != 2)
            madvise(map + gone * chunk, chunk, MADV_DONTNEED);
        bytes += chunk;
    }
    double t = now() - t0;
    printf("chunk %zu KiB, mode %d: %.3f ns a byte, %.2f us a 4 KiB page\n", chunk / 1024, mode,
           t * 1e9 / (double)bytes, t * 1e6 / ((double)bytes / 4096.0));
    return 0;
}
