/*
 * image_module.h — the boundary between the image API every program links
 * (host/output/image_loader.c, C) and its implementation over OpenImageIO
 * (host/output/image_oiio.cpp, C++), built as the module csgtrace-image.so and
 * loaded with dlopen by the first image call that needs it.  Only the
 * process that reads an image, or writes one other than PNG or PPM
 * (host/output/stream.c), pays for OpenImageIO (~270 shared libraries).
 *
 * The module exports one symbol, IMG_MODULE_ENTRY, a function returning
 * its table; the loader checks `abi` and `size` before using any entry.
 * Change IMG_MODULE_ABI whenever an entry's meaning or signature changes.
 */
#ifndef OUTPUT_IMAGE_MODULE_H
#define OUTPUT_IMAGE_MODULE_H

#include "image.h"

#ifdef __cplusplus
extern "C" {
#endif

#define IMG_MODULE_ABI 5
#define IMG_MODULE_ENTRY "csgimg_module"     /* the one exported symbol */
#define IMG_MODULE_FILE "csgtrace-image.so"  /* looked for beside the program */

/* The entries have the signatures and contracts of host/output/image.h,
 * but for the writer: open_file opens the image of `path` (its format, its
 * pixel format, the name its messages give; the PNG level of img_settings)
 * on the file `tmp`, an empty file of the same extension the loader made
 * beside it, and writes nothing else: the loader owns the temporary file
 * (names it to the signal handler, reports the file-size limit it met,
 * removes it or renames it over `path`).  write_rows hands it rows y0 ..
 * y1 - 1 (rgb: row y0's first value, 3 floats a pixel, linear), every row
 * once and in order; close_file completes the file and frees the handle,
 * whatever it returns. */
typedef struct {
    int abi;     /* IMG_MODULE_ABI of the module's build */
    size_t size; /* sizeof(img_module) of the module's build */
    void *(*open_file)(const char *path, const char *tmp, int width, int height, int png_level,
                       char *err, size_t err_size);
    bool (*write_rows)(void *file, int y0, int y1, const float *rgb, char *err, size_t err_size);
    bool (*close_file)(void *file, char *err, size_t err_size);
    bool (*read_rgb)(const char *path, float **rgb, int *width, int *height, char *err,
                     size_t err_size);
    bool (*compare_files)(const char *a, const char *b, double threshold, img_compare_result *r,
                          char *err, size_t err_size);
    bool (*can_write)(const char *path, char *err, size_t err_size);
} img_module;

typedef const img_module *(*img_module_entry_fn)(void);

#ifdef __cplusplus
}
#endif

#endif
