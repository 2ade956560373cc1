/*
 * image_direct.c — PNG (libpng) and binary PPM written without OpenImageIO
 * (image_direct.h).
 *
 * Each row is encoded to bytes (pixels_srgb_byte, the conversion the
 * workers use for 8-bit results, equal to OpenImageIO's) into one row
 * buffer and handed to the encoder: the writer holds 3 bytes a pixel of one
 * row, never a copy of the image.
 *
 * The PNG is the one the image module wrote: IHDR (8-bit RGB), an oFFs of
 * 0,0 pixels, IDAT in libpng's 8 KiB chunks, IEND; no gAMA/sRGB chunk (the
 * module wrote none either: viewers take 8-bit PNG as sRGB), the same
 * filter, strategy and level.

 */
#include "image_direct.h"

#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "file_atomic.h"
#include "../../comm/pixels.h"

img_direct_format img_direct_format_of(const char *path, bool module_writes_all)
{
    if (!path || module_writes_all)
        return IMG_DIRECT_NONE;
    static const char *const png[] = {"png"}, *const netpbm[] = {"ppm", "pnm", "pgm"};
    if (pixels_extension_in(path, png, 1))
        return IMG_DIRECT_PNG;
    if (pixels_extension_in(path, netpbm, sizeof netpbm / sizeof netpbm[0]))
        return IMG_DIRECT_PPM;
    return IMG_DIRECT_NONE;
}

img_png_options img_png_options_for(int level)
{
    if (level >= 0 && level <= 9)
        return (img_png_options){level, Z_DEFAULT_STRATEGY, PNG_ALL_FILTERS};
    /* Measured (bench/NOTES-README.md, the PNG settings): a quarter of the time of zlib
     * level 6 with every filter, for files 6 to 25 % larger.  The level is
     * only written in the zlib header under Z_RLE: 6 as the module did. */
    return (img_png_options){6, Z_RLE, PNG_FILTER_UP};
}

/* What a writer needs, and what it found. */
typedef struct {
    const float *rgb;
    int width, height;
    img_png_options png;
    const char *path;
    unsigned char *row; /* 3 * width bytes */
} direct_job;

/* Row y's bytes into job->row. */
static void encode_row(direct_job *job, int y)
{
    size_t n = (size_t)job->width * 3;
    pixels_to_rgb8(job->rgb + n * (size_t)y, n, job->row);
}

static bool write_ppm(FILE *f, void *arg, char *err, size_t err_size)
{
    (void)err;
    (void)err_size;
    direct_job *job = arg;
    size_t n = (size_t)job->width * 3;
    if (fprintf(f, "P6\n%d %d\n255\n", job->width, job->height) < 0)
        return false;
    for (int y = 0; y < job->height; y++) {
        encode_row(job, y);
        if (fwrite(job->row, 1, n, f) != n)
            return false;
    }
    return true;
}

/* libpng's errors end in a longjmp to encode_png's setjmp; the
 * message goes to the caller's err first. */
typedef struct {
    char *err;
    size_t err_size;
    const char *path;
} png_failure;

static void on_png_error(png_structp png, png_const_charp msg)
{
    png_failure *fail = png_get_error_ptr(png);
    snprintf(fail->err, fail->err_size, "csgtrace: error: cannot write %s: %s", fail->path, msg);
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* none arises for an 8-bit RGB image without text */
}

/* The header and every row, between png_write_info and png_write_end.
 * Apart from png_write so that nothing of its frame is changed after
 * setjmp (no volatile needed). */
static bool encode_png(png_structp png, png_infop info, direct_job *job)
{
    if (setjmp(png_jmpbuf(png)))
        return false;
    png_set_compression_level(png, job->png.level);
    png_set_compression_strategy(png, job->png.strategy);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, job->png.filters);
    png_set_IHDR(png, info, (png_uint_32)job->width, (png_uint_32)job->height, 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_set_oFFs(png, info, 0, 0, PNG_OFFSET_PIXEL);
    png_write_info(png, info);
    for (int y = 0; y < job->height; y++) {
        encode_row(job, y);
        png_write_row(png, job->row);
    }
    png_write_end(png, NULL);
    return true;
}

static bool write_png(FILE *f, void *arg, char *err, size_t err_size)
{
    direct_job *job = arg;
    png_failure fail = {err, err_size, job->path};
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &fail, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    bool ok = info != NULL;
    if (ok) {
        png_init_io(png, f);
        ok = encode_png(png, info, job);
    } else {
        snprintf(err, err_size, "csgtrace: error: cannot write %s: out of memory", job->path);
    }
    png_destroy_write_struct(&png, &info);
    return ok;
}

bool img_direct_write(const char *path, img_direct_format format, const float *rgb, int width,
                      int height, const img_png_options *png, char *err, size_t err_size)
{
    direct_job job = {rgb, width, height, png ? *png : img_png_options_for(-1), path, NULL};
    if (width <= 0 || height <= 0) {
        snprintf(err, err_size, "csgtrace: error: cannot write %s: an image of %dx%d pixels",
                 path, width, height);
        return false;
    }
    job.row = malloc((size_t)width * 3);
    if (!job.row) {
        snprintf(err, err_size, "csgtrace: error: cannot write %s: out of memory", path);
        return false;
    }
    bool ok = file_write_atomic_checked(path, format == IMG_DIRECT_PNG ? write_png : write_ppm,
                                        &job, err, err_size);
    free(job.row);
    return ok;
}
