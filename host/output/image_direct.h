/*
 * image_direct.h — the 8-bit files csgtrace writes without OpenImageIO:
 * PNG through libpng and binary PPM (P6), the formats of nearly every
 * render.  A process that writes only these never loads the image module
 * (host/output/image_module.h) and its ~270 libraries (~0.3 s and ~130 MB of a
 * 384x384 render's 0.4 s and 135 MB).  The files are the very bytes the
 * module wrote (same chunks, filter and zlib settings; tests/e2e_image.sh
 * compares them with cmp); $CSGTRACE_IMAGE_WRITER=oiio sends every format
 * to the module, as before.
 *
 * host/output/image_loader.c routes img_write_rgb and img_can_write here by the
 * extension (img_direct_format_of).
 */
#ifndef OUTPUT_IMAGE_DIRECT_H
#define OUTPUT_IMAGE_DIRECT_H

#include <stdbool.h>
#include <stddef.h>

typedef enum {
    IMG_DIRECT_NONE = 0, /* the module writes it */
    IMG_DIRECT_PNG,
    IMG_DIRECT_PPM /* .ppm, .pnm, .pgm: OpenImageIO wrote RGB P6 for each */
} img_direct_format;

/* The direct format of output `path` by its extension (any case);
 * IMG_DIRECT_NONE for every other format, and for all when the module
 * writes all (img_settings). */
img_direct_format img_direct_format_of(const char *path, bool module_writes_all);

/* How a PNG is compressed (libpng's names and values). */
typedef struct {
    int level;    /* zlib level 0..9                                   */
    int strategy; /* Z_DEFAULT_STRATEGY, Z_FILTERED, Z_RLE, ...        */
    int filters;  /* PNG_FILTER_UP, PNG_ALL_FILTERS (chosen a row), ... */
} img_png_options;

/* csgtrace's PNG compression: the Up filter and zlib's run-length
 * strategy (level -1), or every filter chosen a row at zlib level 0..9,
 * the default strategy (the module's meaning of it too). */
img_png_options img_png_options_for(int level);

/* Writes linear RGB floats (3 a pixel) to `path` as an 8-bit `format`
 * file, encoded with pixels_srgb_byte a row at a time (no copy of the
 * image), through a temporary file renamed when complete.  `png` may be
 * NULL (img_png_options_for(-1)).  false with the message in err (no file
 * left under path nor beside it). */
bool img_direct_write(const char *path, img_direct_format format, const float *rgb, int width,
                      int height, const img_png_options *png, char *err, size_t err_size);

#endif
