/*
 * pixels_z.c — 8-bit results compressed on the wire (pixels_z.h), with
 * Zstandard: level 1, a checksum a frame, the contexts reused.
 */
#include "pixels_z.h"

#include <stdlib.h>
#include <zstd.h>

#define PIXELS_Z_LEVEL 1

struct pixels_zstream {
    ZSTD_CCtx *c; /* one of the two */
    ZSTD_DCtx *d;
};

pixels_zstream *pixels_compressor_new(void)
{
    pixels_zstream *s = calloc(1, sizeof *s);
    if (s && (!(s->c = ZSTD_createCCtx()) ||
              ZSTD_isError(ZSTD_CCtx_setParameter(s->c, ZSTD_c_compressionLevel,
                                                  PIXELS_Z_LEVEL)) ||
              ZSTD_isError(ZSTD_CCtx_setParameter(s->c, ZSTD_c_checksumFlag, 1)))) {
        pixels_zstream_free(s);
        return NULL;
    }
    return s;
}

pixels_zstream *pixels_decompressor_new(void)
{
    pixels_zstream *s = calloc(1, sizeof *s);
    if (s && !(s->d = ZSTD_createDCtx())) {
        free(s);
        return NULL;
    }
    return s;
}

void pixels_zstream_free(pixels_zstream *s)
{
    if (!s)
        return;
    ZSTD_freeCCtx(s->c);
    ZSTD_freeDCtx(s->d);
    free(s);
}

size_t pixels_compress_bound(size_t bytes)
{
    return ZSTD_COMPRESSBOUND(bytes);
}

size_t pixels_compress(pixels_zstream *s, const uint8_t *in, size_t bytes, uint8_t *out)
{
    if (!s || !s->c)
        return 0;
    size_t len = ZSTD_compress2(s->c, out, pixels_compress_bound(bytes), in, bytes);
    return ZSTD_isError(len) ? 0 : len;
}

bool pixels_decompress(pixels_zstream *s, const uint8_t *in, size_t in_bytes, uint8_t *out,
                       size_t bytes)
{
    if (!s || !s->d || in_bytes == 0)
        return false;
    /* one frame, all of `in`: a second frame after it would be taken too */
    if (ZSTD_findFrameCompressedSize(in, in_bytes) != in_bytes)
        return false;
    size_t len = ZSTD_decompressDCtx(s->d, out, bytes, in, in_bytes);
    return !ZSTD_isError(len) && len == bytes;
}
