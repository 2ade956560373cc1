/*
 * compress_tiles.c — what --compress costs (comm/pixels_z.h): reads an
 * 8-bit render (binary PPM: `csgtrace render SCENE -o IMAGE.ppm`), cuts it
 * into TILE x TILE tiles as the workers' parts, and times, ROUNDS times,
 * a worker's compress of every tile and rank 0's decompress of every stream,
 * each on this thread's CPU clock.  Prints the bytes before and after, and
 * per way the median nanoseconds a raw byte with the rounds' range: the
 * simulation's $CSGSIM_COMPRESS_S and $CSGSIM_MASTER_DECOMPRESS_S
 * (bench/simulate.sh --compress-ns, --decompress-ns).
 *
 *   build/bench/compress_tiles IMAGE.ppm [TILE [ROUNDS]]   (32, 5)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../comm/pixels_z.h"
#include "timing.h"

/* A binary PPM of 8-bit samples: its pixels (3 bytes each), or NULL. */
static uint8_t *read_ppm(const char *path, int *w, int *h)
{
    FILE *f = fopen(path, "rb");
    int maxval = 0;
    uint8_t *px = NULL;
    if (f && fscanf(f, "P6 %d %d %d", w, h, &maxval) == 3 && maxval == 255 && *w > 0 &&
        *h > 0 && *w <= 65536 && *h <= 65536 && fgetc(f) != EOF) {
        size_t n = (size_t)*w * (size_t)*h * 3;
        px = malloc(n);
        if (px && fread(px, 1, n, f) != n) {
            free(px);
            px = NULL;
        }
    }
    if (f)
        fclose(f);
    return px;
}

int main(int argc, char **argv)
{
    int w = 0, h = 0, tile = argc > 2 ? atoi(argv[2]) : 32, rounds = argc > 3 ? atoi(argv[3]) : 5;
    uint8_t *img = argc > 1 ? read_ppm(argv[1], &w, &h) : NULL;
    if (!img || tile < 1 || tile > 4096 || rounds < 1 || rounds > 1000) {
        fprintf(stderr, "usage: compress_tiles IMAGE.ppm [TILE [ROUNDS]] (a binary 8-bit PPM)\n");
        return 2;
    }
    int cols = (w + tile - 1) / tile, rows = (h + tile - 1) / tile, tiles = cols * rows;
    size_t most = (size_t)tile * (size_t)tile * 3, room = pixels_compress_bound(most);
    uint8_t *raw = malloc(most), *back = malloc(most), *z = malloc((size_t)tiles * room);
    size_t *len = calloc((size_t)tiles, sizeof *len), *raw_len = calloc((size_t)tiles, sizeof *len);
    double *comp_t = calloc((size_t)rounds, sizeof *comp_t);
    double *decomp_t = calloc((size_t)rounds, sizeof *decomp_t);
    pixels_zstream *comp = pixels_compressor_new(), *decomp = pixels_decompressor_new();
    if (!raw || !back || !z || !len || !raw_len || !comp_t || !decomp_t || !comp || !decomp)
        return 3;
    size_t total_raw = 0, total_z = 0;
    for (int r = 0; r < rounds; r++) {
        double t0 = bench_clock_s(CLOCK_THREAD_CPUTIME_ID), cut = 0;
        for (int k = 0; k < tiles; k++) { /* (the cutting timed apart, taken off) */
            int x = k % cols * tile, y = k / cols * tile;
            int tw = w - x < tile ? w - x : tile, th = h - y < tile ? h - y : tile;
            double c0 = bench_clock_s(CLOCK_THREAD_CPUTIME_ID);
            for (int row = 0; row < th; row++)
                memcpy(raw + (size_t)row * (size_t)tw * 3,
                       img + ((size_t)(y + row) * (size_t)w + (size_t)x) * 3, (size_t)tw * 3);
            cut += bench_clock_s(CLOCK_THREAD_CPUTIME_ID) - c0;
            raw_len[k] = (size_t)tw * (size_t)th * 3;
            len[k] = pixels_compress(comp, raw, raw_len[k], z + (size_t)k * room);
            if (len[k] == 0)
                return 4;
        }
        comp_t[r] = bench_clock_s(CLOCK_THREAD_CPUTIME_ID) - t0 - cut;
        t0 = bench_clock_s(CLOCK_THREAD_CPUTIME_ID);
        for (int k = 0; k < tiles; k++)
            if (!pixels_decompress(decomp, z + (size_t)k * room, len[k], back, raw_len[k]))
                return 5;
        decomp_t[r] = bench_clock_s(CLOCK_THREAD_CPUTIME_ID) - t0;
    }
    for (int k = 0; k < tiles; k++) {
        total_raw += raw_len[k];
        total_z += len[k];
    }
    double cmin = comp_t[0], dmin = decomp_t[0], cmax = comp_t[0], dmax = decomp_t[0];
    for (int r = 1; r < rounds; r++) {
        cmin = comp_t[r] < cmin ? comp_t[r] : cmin;
        cmax = comp_t[r] > cmax ? comp_t[r] : cmax;
        dmin = decomp_t[r] < dmin ? decomp_t[r] : dmin;
        dmax = decomp_t[r] > dmax ? decomp_t[r] : dmax;
    }
    double cmed = bench_median(comp_t, rounds), dmed = bench_median(decomp_t, rounds);
    double per = 1e9 / (double)total_raw;
    printf("%dx%d, %d tiles of %d: %zu bytes -> %zu compressed (%.2fx)\n", w, h, tiles, tile,
           total_raw, total_z, (double)total_raw / (double)total_z);
    printf("compress: %.3f ns a byte (%.3f-%.3f), %d rounds\n", cmed * per, cmin * per, cmax * per,
           rounds);
    printf("decompress: %.3f ns a byte (%.3f-%.3f)\n", dmed * per, dmin * per, dmax * per);
    return 0;
}
