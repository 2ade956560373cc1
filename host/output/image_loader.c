/*
 * image_loader.c — the image API (image.h) as every program links it: PNG
 * and PPM files are written by csgtrace itself (stream.h, also for a whole
 * image at once); for every other call the first one loads the
 * OpenImageIO module (image_module.h), and every call forwards to it.
 * `csgtrace check`, the MPI workers and a render to PNG or PPM never map
 * OpenImageIO and its ~270 libraries.
 *
 * Where the module is looked for, first found wins (DIR: the running
 * program's folder, /proc/self/exe):
 *   1. img_settings.module ($CSGTRACE_IMAGE_MODULE), a path (then nothing
 *      else is tried);
 *   2. DIR/csgtrace-image.so (the build folder, or a copied program);
 *   3. DIR/../lib/csgtrace/csgtrace-image.so (make install's layout);
 *   4. DIR/../csgtrace-image.so (the test and bench programs, a folder
 *      below their build's).
 * A missing or unusable module makes every call return false with one
 * message saying which file and why; nothing is retried.
 *
 * The loaded table and the settings are process state by nature
 * (dlopen's is too): one static record, the settings given once at start
 * (img_configure), the module loaded once under pthread_once, never
 * unloaded.
 */
#include "image.h"

#include <dlfcn.h>
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../../comm/pixels.h"
#include "../signals.h"
#include "file_atomic.h"
#include "image_module.h"
#include "stream.h"

typedef struct {
    pthread_once_t once;
    const img_module *mod; /* NULL when loading failed */
    char error[4096 + 1024]; /* why, when mod is NULL (a path and a reason) */
    img_settings settings;
} img_loader;

static img_loader loader = {PTHREAD_ONCE_INIT, NULL, "", {NULL, false, -1}};

void img_configure(const img_settings *s)
{
    loader.settings = *s;
}

img_settings img_settings_now(void)
{
    return loader.settings;
}

img_format img_format_of(const char *path)
{
    static const char *const png[] = {"png"}, *const netpbm[] = {"ppm", "pnm", "pgm"},
                             *const pfm[] = {"pfm"};
    if (!path || loader.settings.module_writes_all)
        return IMG_FORMAT_MODULE;
    if (pixels_extension_in(path, png, 1))
        return IMG_FORMAT_PNG;
    if (pixels_extension_in(path, netpbm, sizeof netpbm / sizeof netpbm[0]))
        return IMG_FORMAT_PPM;
    if (pixels_extension_in(path, pfm, 1))
        return IMG_FORMAT_PFM;
    return IMG_FORMAT_MODULE;
}

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
    static const char *const beside[] = {"", "../lib/csgtrace/", "../"};
    const char *given = loader.settings.module;
    if (given) {
        if (snprintf(path, size, "%s", given) < (int)size)
            return true; /* dlopen says what is wrong with it */
        snprintf(loader.error, sizeof loader.error, "CSGTRACE_IMAGE_MODULE is too long");
        return false;
    }
    char dir[4096], sub[4096 + 32];
    program_dir(dir, sizeof dir);
    for (size_t i = 0; i < sizeof beside / sizeof beside[0]; i++) {
        snprintf(sub, sizeof sub, "%s%s", dir, beside[i]);
        if (existing(path, size, sub, IMG_MODULE_FILE))
            return true;
    }
    snprintf(loader.error, sizeof loader.error,
             "the image module %s is missing (looked in %s, its lib/csgtrace/ and its parent); "
             "run make, or set CSGTRACE_IMAGE_MODULE to its path",
             IMG_MODULE_FILE, dir[0] ? dir : "the program's folder");
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

/* A new, empty file beside `path` for the module to write the image into:
 * DIR/.BASE.XXXXXX.EXT with six random characters, created with O_CREAT |
 * O_EXCL (mkstemps), so no name can be guessed and planted in advance, and
 * no link already there is ever followed; the extension stays last, as
 * OpenImageIO picks the format by it; fopen's mode.  malloc'd, or NULL
 * with errno set. */
static char *module_temporary(const char *path)
{
    const char *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    const char *ext = dot ? dot : "";
    size_t n = strlen(path) + 16;
    char *tmp = malloc(n);
    if (!tmp)
        return NULL;
    snprintf(tmp, n, "%.*s.%s.XXXXXX%s", (int)(base - path), path, base, ext);
    int fd = mkstemps(tmp, (int)strlen(ext));
    if (fd >= 0 && fchmod(fd, file_default_mode()) == 0 && close(fd) == 0)
        return tmp;
    int e = errno;
    if (fd >= 0) {
        close(fd);
        unlink(tmp);
    }
    free(tmp);
    errno = e;
    return NULL;
}

/* The module's message for a failed write, with the file-size limit when
 * the file met it (OpenImageIO's formats say only that a write failed). */
static void module_write_failed(const char *tmp, char *err, size_t err_size)
{
    struct stat st;
    struct rlimit rl;
    size_t used = strlen(err);
    if (getrlimit(RLIMIT_FSIZE, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
        stat(tmp, &st) == 0 && (rlim_t)st.st_size >= rl.rlim_cur && used < err_size)
        snprintf(err + used, err_size - used,
                 " (the file met the file-size limit (ulimit -f) of %llu bytes)",
                 (unsigned long long)rl.rlim_cur);
}

struct img_module_file {
    const img_module *m;
    void *file; /* the module's handle */
    char *tmp;  /* the temporary file beside the target */
    char *path; /* the target */
};

static void module_file_free(img_module_file *f)
{
    free(f->tmp);
    free(f->path);
    free(f);
}

img_module_file *img_module_open(const char *path, int width, int height, char *err,
                                 size_t err_size)
{
    const img_module *m = module_or_error(path, err, err_size);
    if (!m)
        return NULL;
    img_module_file *f = calloc(1, sizeof *f);
    char *target = strdup(path), *tmp = NULL;
    errno = ENOMEM;
    if (f && target)
        tmp = module_temporary(path); /* (errno when it cannot) */
    if (!tmp) {
        char why[160];
        snprintf(err, err_size, "csgtrace: error: cannot write %s: %s", path,
                 file_strerror(errno, why, sizeof why));
        free(target);
        free(f);
        return NULL;
    }
    *f = (img_module_file){m, NULL, tmp, target};
    signals_temporary(tmp); /* (a signal now removes it, however long the write) */
    err[0] = '\0';
    f->file = m->open_file(path, tmp, width, height, loader.settings.png_level, err, err_size);
    if (!f->file) {
        module_write_failed(tmp, err, err_size);
        unlink(tmp);
        signals_temporary(NULL);
        module_file_free(f);
        return NULL;
    }
    return f;
}

bool img_module_rows(img_module_file *f, int y0, int y1, const float *rgb, char *err,
                     size_t err_size)
{
    err[0] = '\0';
    if (f->m->write_rows(f->file, y0, y1, rgb, err, err_size))
        return true;
    module_write_failed(f->tmp, err, err_size);
    return false;
}

bool img_module_close(img_module_file *f, bool hold, char *err, size_t err_size)
{
    err[0] = '\0';
    bool ok = f->m->close_file(f->file, err, err_size);
    if (!ok)
        module_write_failed(f->tmp, err, err_size);
    if (ok && hold)
        signals_hold(); /* (from the rename on, a signal waits for the caller's release) */
    if (ok && rename(f->tmp, f->path) != 0) {
        snprintf(err, err_size, "csgtrace: error: cannot write %s: %s", f->path, strerror(errno));
        ok = false;
    }
    if (!ok)
        unlink(f->tmp);
    signals_temporary(NULL);
    module_file_free(f);
    return ok;
}

void img_module_abort(img_module_file *f)
{
    if (!f)
        return;
    char ignored[64];
    f->m->close_file(f->file, ignored, sizeof ignored);
    unlink(f->tmp);
    signals_temporary(NULL);
    module_file_free(f);
}

bool img_module_write(const char *path, const float *rgb, int width, int height, bool hold,
                      char *err, size_t err_size)
{
    img_module_file *f = img_module_open(path, width, height, err, err_size);
    if (!f)
        return false;
    if (!img_module_rows(f, 0, height, rgb, err, err_size)) {
        img_module_abort(f);
        return false;
    }
    return img_module_close(f, hold, err, err_size);
}

bool img_module_write_rgb(const char *path, const float *rgb, int width, int height, char *err,
                          size_t err_size)
{
    return img_module_write(path, rgb, width, height, false, err, err_size);
}

bool img_write_rgb(const char *path, const float *rgb, int width, int height, char *err,
                   size_t err_size)
{
    if (width <= 0 || height <= 0) {
        snprintf(err, err_size, "csgtrace: error: cannot write %s: an image of %dx%d pixels",
                 path, width, height);
        return false;
    }
    if (img_format_of(path) == IMG_FORMAT_MODULE)
        return img_module_write_rgb(path, rgb, width, height, err, err_size);
    /* (PNG, PPM, PFM: a stream of bands of 64 rows, every band final at once,
     * encoded on every CPU) */
    tile_grid g = {width, height, IMG_STREAM_ROWS, 1, sizeof(float), 0};
    img_stream *s = img_stream_open(path, rgb, &g, err, err_size);
    if (!s)
        return false;
    for (int t = 0; t < tile_count(&g); t++)
        img_stream_tile(s, t);
    img_stream_report r;
    return img_stream_finish(s, 0, &r, err, err_size);
}

bool img_can_write(const char *path, char *err, size_t err_size)
{
    if (img_format_of(path) != IMG_FORMAT_MODULE)
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
