/*
 * image.h — image files.  PNG and PPM are written by the program itself
 * (host/output/stream.c, zlib; while the render runs); every other format, and all reading and
 * comparing, go through OpenImageIO, in the module csgtrace-image.so
 * (host/output/image_oiio.cpp, the one C++ file, which turns every exception into
 * a status), loaded by the first call that needs it (host/output/image_loader.c):
 * a process that writes only PNG or PPM, or no image at all, never loads
 * OpenImageIO.  When the module cannot be loaded those calls return false
 * with one message naming the file and the reason.
 */
#ifndef OUTPUT_IMAGE_H
#define OUTPUT_IMAGE_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The image settings of the environment (host/config.h), taken once at
 * start (main); until then the defaults (all zero but png_level -1). */
typedef struct {
    const char *module;     /* $CSGTRACE_IMAGE_MODULE: the module's path
                               (NULL: looked for, image_loader.c)        */
    bool module_writes_all; /* $CSGTRACE_IMAGE_WRITER=oiio: PNG and PPM
                               through the module too                    */
    int png_level;          /* $CSGTRACE_PNG_LEVEL: 0 to 9, zlib's level
                               with every filter; -1: csgtrace's PNG (Up
                               filter, run-length strategy)              */
} img_settings;
void img_configure(const img_settings *s);
img_settings img_settings_now(void);

/* Who writes a file of `path`'s extension: csgtrace itself (PNG, PPM,
 * PFM), or the OpenImageIO module; a render streams either band by band
 * (stream.h).  PFM (the
 * Portable Float Map: linear floats, rows bottom up) is csgtrace's own:
 * OpenImageIO reads it but has no writer for it. */
typedef enum { IMG_FORMAT_PNG, IMG_FORMAT_PPM, IMG_FORMAT_PFM, IMG_FORMAT_MODULE } img_format;
img_format img_format_of(const char *path);

/* The rows of a band when a whole image is written at once. */
#define IMG_STREAM_ROWS 64

/* Writes RGB float pixels (3 a pixel, linear) to `path`, the format chosen
 * by the extension (PNG and PPM without the module, encoded on every CPU
 * this process may use).  8-bit formats get
 * each value's byte of comm/pixels.h (clamped to [0, 1], the sRGB curve,
 * as POV-Ray 3.7 writes PNG with assumed_gamma 1), whoever writes them;
 * float formats (exr, hdr, pfm) get them linear.  The file is
 * written under a temporary name in the same folder and renamed when
 * complete: a failure never leaves a partial file under `path`.
 * false with a message in err on failure. */
bool img_write_rgb(const char *path, const float *rgb, int width, int height, char *err,
                   size_t err_size);

/* The module's writer alone (a format of IMG_FORMAT_MODULE). */
bool img_module_write_rgb(const char *path, const float *rgb, int width, int height, char *err,
                          size_t err_size);
/* The same; `hold`: signals held (host/signals.h: signals_hold) from just
 * before the finished file is renamed over `path`, for the caller to
 * release once its other outputs are in place too (a render's image, its
 * stats, its tile log).  Until then a signal removes the temporary file at
 * once. */
bool img_module_write(const char *path, const float *rgb, int width, int height, bool hold,
                      char *err, size_t err_size);

/* The module's writer a run of rows at a time (host/output/stream.c):
 * img_module_open makes the temporary file beside `path` (named to the
 * signal handler) and opens the format's writer on it; img_module_rows
 * hands it rows y0 .. y1 - 1 (rgb: row y0's first value), every row once
 * and in order; img_module_close completes the file and renames it over
 * `path` (`hold` as img_module_write's); img_module_abort removes it.
 * Each false or NULL with the message in err; close and abort free f. */
typedef struct img_module_file img_module_file;
img_module_file *img_module_open(const char *path, int width, int height, char *err,
                                 size_t err_size);
bool img_module_rows(img_module_file *f, int y0, int y1, const float *rgb, char *err,
                     size_t err_size);
bool img_module_close(img_module_file *f, bool hold, char *err, size_t err_size);
void img_module_abort(img_module_file *f);

/* Is there a writer for the format of `path` (its extension)?  A render
 * asks before it starts, not after its last tile: for a format of the
 * module this loads it (OpenImageIO's ~270 libraries, ~0.2 s) before the
 * timed work, and learns at once when it is missing; PNG and PPM need no
 * module.  false with the message img_write_rgb would give. */
bool img_can_write(const char *path, char *err, size_t err_size);
/* Reads any image OpenImageIO knows as float RGB (malloc'd, 3 a pixel). */
bool img_read_rgb(const char *path, float **rgb, int *width, int *height, char *err,
                  size_t err_size);

/* OpenImageIO's ImageBufAlgo::compare of two files, plus the size check it
 * does not do. */
typedef struct {
    bool same_size;
    double rmse, psnr, max_error;
    long pixels_over; /* pixels whose difference exceeds `threshold` */
} img_compare_result;
bool img_compare_files(const char *a, const char *b, double threshold, img_compare_result *r,
                       char *err, size_t err_size);

#ifdef __cplusplus
}
#endif

#endif
