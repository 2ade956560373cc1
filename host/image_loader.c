/*
 * image_loader.c — the image API (image.h) as every program links it: PNG
 * and PPM files are written here (image_direct.h); for every other call
 * the first one loads the OpenImageIO module (image_module.h), and every
 * call forwards to it.
 * `csgtrace check`, the MPI workers and a render to PNG or PPM never map
 * OpenImageIO and its ~270 libraries.
 *
 * Where the module is looked for, first found wins:
 *   1. $CSGTRACE_IMAGE_MODULE, a path (then nothing else is tried);
 *   2. csgtrace-image.so beside the running program (/proc/self/exe);
 *   3. the build folder this object was compiled for (CSG_IMAGE_MODULE_BUILT),
 *      which lets the test programs of build/tests find build/'s module.
 * A missing or unusable module makes every call return false with one
 * message saying which file and why; nothing is retried.
 *
 * The loaded table is process state by nature (dlopen's is too): one
 * static record, filled once under pthread_once, never unloaded.
 */
#include "image.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image_direct.h"
#include "image_module.h"

typedef struct {
    pthread_once_t once;
    const img_module *mod; /* NULL when loading failed */
    char error[4096 + 1024]; /* why, when mod is NULL (a path and a reason) */
} img_loader;

static img_loader loader = {PTHREAD_ONCE_INIT, NULL, ""};

/* The folder of the running program, with its trailing '/'; "" if unknown. */
static void program_dir(char *dir, size_t size)
{
    ssize_t n = readlink("/proc/self/exe", dir, size - 1);
    dir[n > 0 ? n : 0] = '\0';
    char *slash = strrchr(dir, '/');
    if (slash)
        slash[1] = '\0';
    else
        dir[0] = '\0';
}

/* DIR + FILE into path; true when it fits and names an existing file. */
static bool existing(char *path, size_t size, const char *dir, const char *file)
{
    int n = snprintf(path, size, "%s%s", dir, file);
    return n > 0 && (size_t)n < size && access(path, F_OK) == 0;
}

/* The module's path by the search order above; false (with loader.error)
 * when no candidate exists. */
static bool module_path(char *path, size_t size)
{
    const char *env = getenv(IMG_MODULE_ENV);
    if (env && env[0]) {
        if (snprintf(path, size, "%s", env) < (int)size)
            return true; /* dlopen says what is wrong with it */
        snprintf(loader.error, sizeof loader.error, "%s is too long", IMG_MODULE_ENV);
        return false;
    }
    char dir[4096];
    program_dir(dir, sizeof dir);
    if (existing(path, size, dir, IMG_MODULE_FILE))
        return true;
#ifdef CSG_IMAGE_MODULE_BUILT
    if (existing(path, size, "", CSG_IMAGE_MODULE_BUILT))
        return true;
    const char *also = " and at " CSG_IMAGE_MODULE_BUILT;
#else
    const char *also = "";
#endif
    snprintf(loader.error, sizeof loader.error,
             "the image module %s is missing (looked in %s%s); run make, or set %s to its path",
             IMG_MODULE_FILE, dir[0] ? dir : "the program's folder", also, IMG_MODULE_ENV);
    return false;
}

static void load_module(void)
{
    char path[4096];
    if (!module_path(path, sizeof path))
        return;
    /* Lazy: of the functions of ~270 libraries, bind only those called
     * (the module itself is linked with -z defs, so none is missing). */
    void *h = dlopen(path, RTLD_LAZY | RTLD_LOCAL);
    if (!h) {
        snprintf(loader.error, sizeof loader.error, "cannot load the image module: %s", dlerror());
        return;
    }
    img_module_entry_fn entry = (img_module_entry_fn)dlsym(h, IMG_MODULE_ENTRY);
    const img_module *m = entry ? entry() : NULL;
    if (!m) {
        snprintf(loader.error, sizeof loader.error,
                 "%s is not a csgtrace image module (no %s)", path, IMG_MODULE_ENTRY);
    } else if (m->abi != IMG_MODULE_ABI || m->size != sizeof *m) {
        snprintf(loader.error, sizeof loader.error,
                 "the image module %s has interface %d (%zu bytes), this program needs %d (%zu); "
                 "rebuild both with make",
                 path, m->abi, m->size, IMG_MODULE_ABI, sizeof *m);
    } else {
        loader.mod = m;
        return;
    }
    dlclose(h);
}

/* The module, or NULL with the reason in err (prefixed with `subject`). */
static const img_module *module_or_error(const char *subject, char *err, size_t err_size)
{
    pthread_once(&loader.once, load_module);
    if (!loader.mod && err && err_size)
        snprintf(err, err_size, "%s%s%s", subject ? subject : "", subject ? ": " : "",
                 loader.error);
    return loader.mod;
}

bool img_write_rgb(const char *path, const float *rgb, int width, int height, char *err,
                   size_t err_size)
{
    img_direct_format direct = img_direct_format_of(path);
    if (direct != IMG_DIRECT_NONE) {
        img_direct_status s =
            img_direct_write(path, direct, rgb, width, height, NULL, err, err_size);
        if (s != IMG_DIRECT_AMBIGUOUS)
            return s == IMG_DIRECT_WRITTEN;
    }
    const img_module *m = module_or_error(path, err, err_size);
    return m && m->write_rgb(path, rgb, width, height, err, err_size);
}

bool img_can_write(const char *path, char *err, size_t err_size)
{
    if (img_direct_format_of(path) != IMG_DIRECT_NONE)
        return true;
    const img_module *m = module_or_error(path, err, err_size);
    return m && m->can_write(path, err, err_size);
}

bool img_read_rgb(const char *path, float **rgb, int *width, int *height, char *err,
                  size_t err_size)
{
    *rgb = NULL;
    const img_module *m = module_or_error(path, err, err_size);
    return m && m->read_rgb(path, rgb, width, height, err, err_size);
}

bool img_compare_files(const char *a, const char *b, double threshold, img_compare_result *r,
                       char *err, size_t err_size)
{
    const img_module *m = module_or_error(NULL, err, err_size);
    return m && m->compare_files(a, b, threshold, r, err, err_size);
}
