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

#define IMG_MODULE_ABI 4
#define IMG_MODULE_ENTRY "csgimg_module"     /* the one exported symbol */
#define IMG_MODULE_FILE "csgtrace-image.so"  /* looked for beside the program */

/* The entries have the signatures and contracts of host/output/image.h,
 * but for write_rgb: it writes the image of `path` (its format, its pixel
 * format, the name its messages give) into the file `tmp`, an empty file
 * of the same extension the loader made beside it, and nothing else: the
 * loader owns the temporary file (names it to the signal handler, reports
 * the file-size limit it met, removes it or renames it over `path`); the
 * PNG level of img_settings. */
typedef struct {
    int abi;     /* IMG_MODULE_ABI of the module's build */
    size_t size; /* sizeof(img_module) of the module's build */
    bool (*write_rgb)(const char *path, const char *tmp, const float *rgb, int width, int height,
                      int png_level, char *err, size_t err_size);
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
