/*
 * pixels_z.h — 8-bit results compressed on their way to rank 0
 * (PIXELS_RGB8Z, comm/pixels.h; --compress, docs/parallel.md).
 *
 * A rendered tile's bytes compress about elevenfold (flat background,
 * smooth shading: 50.3 MB -> 4.6 MB for a 4096x4096 frame of 32x32 tiles,
 * Zstandard level 1), which is what a master behind one gigabit link
 * needs: there the results, not the work, were the frame's bound
 * (bench/SCALE.md).  Zstandard rather than zlib: on those tiles it
 * compresses to 8 % less in 3.3 ns a byte against zlib level 1's 8.6
 * (bench/compress_tiles.c), which is what decides whether it pays on a
 * fast network too.  Each part is one frame, with its checksum, so parts
 * are independent: a relay forwards them untouched and rank 0's store
 * thread decompresses each into its tile.  The contexts are kept between
 * parts (a worker's compressor, a decompressor a store thread).
 */
#ifndef COMM_PIXELS_Z_H
#define COMM_PIXELS_Z_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct pixels_zstream pixels_zstream;

/* A compressor (a worker's) or a decompressor (rank 0's); NULL when out
 * of memory.  Either is freed by pixels_zstream_free (NULL: nothing). */
pixels_zstream *pixels_compressor_new(void);
pixels_zstream *pixels_decompressor_new(void);
void pixels_zstream_free(pixels_zstream *z);

/* The most bytes `bytes` bytes compress to. */
size_t pixels_compress_bound(size_t bytes);

/* `bytes` bytes of `in` compressed into `out` (room for
 * pixels_compress_bound(bytes)): the frame's length, 0 on failure. */
size_t pixels_compress(pixels_zstream *z, const uint8_t *in, size_t bytes, uint8_t *out);

/* A part's frame of `in_bytes` decompressed into exactly `bytes` bytes of
 * `out`: false unless it is one whole frame of exactly that many bytes,
 * ending at its last byte, its checksum right (a corrupt or malicious
 * part never writes past `bytes`). */
bool pixels_decompress(pixels_zstream *z, const uint8_t *in, size_t in_bytes, uint8_t *out,
                       size_t bytes);

#endif
