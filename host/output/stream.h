/*
 * stream.h — the image file written while the image is rendered.
 *
 * The image is cut into bands of IMG_STREAM_ROWS (64) rows.  Once every
 * tile over a band is final in the image (img_stream_tile), a thread of the stream's
 * own encodes the band into its file's bytes, compressed, and the bands
 * are written to a temporary file beside the output in their order as
 * they are ready; what is left when the last tile is in (img_stream_
 * finish) is a tail: the bands not encoded yet, by as many threads as the
 * caller gives (the workers are idle by then), the file's end, the rename.
 *
 * PNG and PPM are streamed.  PNG: each band's rows are filtered without
 * the band above (its first row Sub, the others Up; every filter chosen a
 * row at a zlib level when one is set: img_settings.png_level) and
 * compressed as a raw deflate stream of its own ended on a byte boundary
 * (Z_SYNC_FLUSH; the last band Z_FINISH), so bands are encoded in any
 * order and in parallel, and the file's bytes depend on its pixels alone:
 * not on that order, the tile size or the mode (a serial render's PNG is
 * a parallel one's, byte for byte); the zlib
 * header, the bands' deflate streams, their Adler-32 combined, in IDAT
 * chunks.  PPM: each band's bytes at its place.  Every other format goes
 * to the image module's writer (image.h: img_module_open), its bands' rows
 * handed over by one thread in file order, each once it and every band
 * above it are final: rendered top down, the file grows as the bands
 * complete; in another order (hetero's cost order) a band waits for the
 * bands above it.
 *
 * The pixels are read from the caller's float image (3 a pixel, linear),
 * converted by comm/pixels.h (the module: as its whole-image writer
 * converts them): the file is img_write_rgb's pixel for pixel.
 * Nothing is ever left under the output's name unless the stream
 * finished; the temporary file is named to the signal handler
 * (host/signals.h), which removes it when a signal ends the render.
 */
#ifndef OUTPUT_STREAM_H
#define OUTPUT_STREAM_H

#include <stdbool.h>
#include <stddef.h>

#include "../../comm/tiles.h"

typedef struct img_stream img_stream;

/* A stream of `path`'s image, `image` (grid's width x height, final tile
 * by tile of the grid), its temporary file made and begun.  NULL with the
 * message in err when it cannot be made. */
img_stream *img_stream_open(const char *path, const float *image, const tile_grid *grid,
                            char *err, size_t err_size);

/* The encoder thread started (apart from img_stream_open: a render
 * starts its threads once the OpenCL driver is loaded, host/render.c);
 * without it, img_stream_finish encodes every band. */
void img_stream_start(img_stream *s);

/* Tile `tile` is final in the image (computed, filled, resumed; each once):
 * its band goes to the encoder when it was the band's last.  The caller's
 * thread only (the master's). */
void img_stream_tile(img_stream *s, int tile);

/* Signals held (host/signals.h: signals_hold) from just before the
 * finished file is renamed over the output, for the caller to release
 * once its other outputs are written too (a render's stats and tile log);
 * until then a signal removes the temporary file at once, however long
 * the encoding of the tail or the module's write would take. */
void img_stream_hold_signals(img_stream *s);

/* What a stream did (the render's stats). */
typedef struct {
    int bands;         /* bands of the image                               */
    int bands_early;   /* of them, encoded before img_stream_finish        */
    double cpu_s;      /* the encoder threads' CPU seconds                 */
} img_stream_report;

/* Every tile is final: the bands left encoded by `threads` threads (0:
 * one a CPU this process may use), the file completed and renamed over
 * the output; the stream freed, *r filled.  false with the message in err
 * (nothing left under the output's name). */
bool img_stream_finish(img_stream *s, int threads, img_stream_report *r, char *err,
                       size_t err_size);

/* The render failed: the temporary file removed, the stream freed. */
void img_stream_abort(img_stream *s);

#endif
