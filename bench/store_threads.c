/*
 * store_threads.c — the store threads' throughput (host/store.h), one
 * against several: the main thread queues every 32x32 part of a SIDE x
 * SIDE image (8-bit bytes, as workers send them to an 8-bit output) as
 * fast as the rings take them, and the threads store them into the float
 * image; a round is one image, timed from the first part queued to the
 * last stored.  Thread counts take turns round by round (1, 2, ..., then
 * again); printed per count: the median ns a pixel with its range, the
 * speed-up of the medians against the first count, and the median CPU
 * time the store threads took a pixel, all of them together (the
 * process's CPU time less the main thread's): what a render's store
 * threads cost, whatever else shares the cores.
 *
 *   build/bench/store_threads SIDE ROUNDS ORDER PAGES COUNT...
 *
 * ORDER: `raster` (tile after tile, as one worker's results come) or
 * `scattered` (every 97th tile: the parts of batches, which lie across the
 * image); PAGES: `huge` (the image from memory_pages_alloc, as a render
 * has it) or `small` (4 KiB pages: the same memory without the request).
 *
 * The main thread never stores a part itself here (master.c does when
 * every ring is full): it naps 20 us and queues again, so that what is
 * timed is the threads.  The image is written once before the rounds
 * (its pages faulted in), as the master's prefault does during a render.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../host/memory.h"
#include "../host/store.h"
#include "timing.h"

enum { PART = 32 };

/* One image's parts through a store of `threads`, every `stride`-th tile
 * (stride prime to the tile count): seconds, and the store threads' CPU
 * seconds into *cpu. */
static double store_round(float *image, int side, const uint8_t *bytes, int threads, int stride,
                          double *cpu)
{
    int tiles = (side / PART) * (side / PART);
    store *s = store_start(image, side, tiles, threads);
    if (!s || store_threads(s) != threads) {
        fprintf(stderr, "store_threads: could not start %d threads\n", threads);
        exit(1);
    }
    struct timespec nap = {0, 20000};
    double process0 = bench_clock_s(CLOCK_PROCESS_CPUTIME_ID);
    double main0 = bench_clock_s(CLOCK_THREAD_CPUTIME_ID);
    double t0 = bench_now_s();
    for (int k = 0; k < tiles; k++) {
        int t = (int)((long)k * stride % tiles);
        tile_rect r = {t % (side / PART) * PART, t / (side / PART) * PART, PART, PART};
        const uint8_t *src = bytes + (size_t)(t % 64) * PART * PART * 3; /* (varied) */
        while (!store_queue(s, r, src))
            nanosleep(&nap, NULL);
    }
    store_drain(s);
    double seconds = bench_now_s() - t0;
    double main_cpu = bench_clock_s(CLOCK_THREAD_CPUTIME_ID) - main0;
    *cpu = bench_clock_s(CLOCK_PROCESS_CPUTIME_ID) - process0 - main_cpu;
    store_stop(s);
    return seconds;
}

int main(int argc, char **argv)
{
    if (argc < 6 || (strcmp(argv[3], "raster") && strcmp(argv[3], "scattered")) ||
        (strcmp(argv[4], "huge") && strcmp(argv[4], "small"))) {
        fprintf(stderr, "usage: store_threads SIDE ROUNDS raster|scattered huge|small COUNT...\n");
        return 2;
    }
    int side = 0, rounds = 0, counts = argc - 5;
    int stride = strcmp(argv[3], "scattered") == 0 ? 97 : 1; /* (97: checked below) */
    bool huge = strcmp(argv[4], "huge") == 0;
    if (!bench_parse_int(argv[1], PART, 16384, &side) || side % PART ||
        !bench_parse_int(argv[2], 1, 99, &rounds)) {
        fprintf(stderr, "store_threads: SIDE a multiple of %d up to 16384, ROUNDS 1..99\n", PART);
        return 2;
    }
    if (stride > 1 && (side / PART) * (side / PART) % stride == 0) {
        fprintf(stderr, "store_threads: scattered needs a tile count prime to %d\n", stride);
        return 2;
    }
    int *threads = malloc((size_t)counts * sizeof *threads);
    double *seconds = malloc((size_t)counts * (size_t)rounds * sizeof *seconds);
    double *cpu = malloc((size_t)counts * (size_t)rounds * sizeof *cpu);
    size_t ibytes = (size_t)side * (size_t)side * 3 * sizeof(float);
    float *image = huge ? memory_pages_alloc(ibytes, true)
                        : aligned_alloc(2u << 20, (ibytes + (2u << 20) - 1) / (2u << 20) * (2u << 20));
    uint8_t *bytes = malloc((size_t)64 * PART * PART * 3);
    if (!threads || !seconds || !cpu || !image || !bytes)
        return 1;
    for (int c = 0; c < counts; c++) {
        if (!bench_parse_int(argv[5 + c], 1, STORE_THREADS_MAX, &threads[c])) {
            fprintf(stderr, "store_threads: COUNT 1..%d\n", STORE_THREADS_MAX);
            return 2;
        }
    }
    for (size_t i = 0; i < (size_t)64 * PART * PART * 3; i++)
        bytes[i] = (uint8_t)(i * 37u + i / 3);
    memset(image, 0, (size_t)side * (size_t)side * 3 * sizeof *image);
    for (int k = 0; k < rounds; k++)
        for (int c = 0; c < counts; c++) {
            size_t at = (size_t)c * (size_t)rounds + (size_t)k;
            seconds[at] = store_round(image, side, bytes, threads[c], stride, &cpu[at]);
        }
    double pixels = (double)side * (double)side, base = 0;
    printf("threads,median_ns_per_pixel,min_ns,max_ns,speedup,threads_cpu_ns_per_pixel\n");
    for (int c = 0; c < counts; c++) {
        double *x = seconds + (size_t)c * (size_t)rounds;
        double median = bench_median(x, rounds); /* (sorts x) */
        if (c == 0)
            base = median;
        double cpu_median = bench_median(cpu + (size_t)c * (size_t)rounds, rounds);
        printf("%d,%.3f,%.3f,%.3f,%.2f,%.3f\n", threads[c], median / pixels * 1e9,
               x[0] / pixels * 1e9, x[rounds - 1] / pixels * 1e9, base / median,
               cpu_median / pixels * 1e9);
    }
    free(threads);
    free(seconds);
    free(cpu);
    free(image);
    free(bytes);
    return 0;
}
