/*
 * cl_cache.c — compiled OpenCL programs on disk (cl_cache.h).
 */
#include "cl_cache.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "file_atomic.h"
#include "hash.h"

/* A cached binary larger than this is not ours. */
#define CL_CACHE_MAX_BYTES ((size_t)256 << 20)

#define CL_CACHE_MAGIC "csgtrace-cl-1\n"

typedef struct {
    char magic[16];   /* CL_CACHE_MAGIC, zero-padded        */
    uint64_t key;     /* the file's name, repeated          */
    uint64_t size;    /* payload bytes that follow          */
    uint64_t sum;     /* FNV-1a of the payload              */
} cl_cache_header;

/* ---- the key ---------------------------------------------------------------------- */

static int cl_cache_by_name(const struct dirent **a, const struct dirent **b)
{
    return strcmp((*a)->d_name, (*b)->d_name);
}

static int cl_cache_source_file(const struct dirent *e)
{
    size_t n = strlen(e->d_name);
    return n > 2 && (strcmp(e->d_name + n - 2, ".h") == 0 ||
                     (n > 3 && strcmp(e->d_name + n - 3, ".cl") == 0));
}

/* h, extended with the name and bytes of every .h/.cl file of `dir`. */
static bool cl_cache_hash_dir(const char *dir, uint64_t *h)
{
    struct dirent **names;
    int n = scandir(dir, &names, cl_cache_source_file, cl_cache_by_name);
    if (n < 0)
        return false;
    bool ok = true;
    for (int i = 0; i < n; i++) {
        char path[PATH_MAX];
        FILE *f = NULL;
        if (ok && (size_t)snprintf(path, sizeof path, "%s/%s", dir, names[i]->d_name) <
                      sizeof path)
            f = fopen(path, "rb");
        ok = ok && f;
        *h = fnv1a(*h, names[i]->d_name, strlen(names[i]->d_name) + 1);
        unsigned char buf[1 << 14];
        size_t got;
        while (f && (got = fread(buf, 1, sizeof buf, f)) > 0)
            *h = fnv1a(*h, buf, got);
        ok = ok && !ferror(f);
        if (f)
            fclose(f);
        free(names[i]);
    }
    free(names);
    return ok;
}

bool cl_cache_key(const char *source_dir, const char *options, const char *device,
                  uint64_t *key)
{
    static const char *const dirs[] = {"simd_kernels", "csg/device"};
    uint64_t h = fnv1a(FNV_BASIS, CL_CACHE_MAGIC, sizeof CL_CACHE_MAGIC);
    h = fnv1a(h, options, strlen(options) + 1);
    h = fnv1a(h, device, strlen(device) + 1);
    for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
        char path[PATH_MAX];
        if ((size_t)snprintf(path, sizeof path, "%s/%s", source_dir, dirs[i]) >= sizeof path ||
            !cl_cache_hash_dir(path, &h))
            return false;
    }
    *key = h;
    return true;
}

/* ---- the files -------------------------------------------------------------------- */

/* The cache folder (not created), or false when the cache is off. */
static bool cl_cache_dir(char *out, size_t size)
{
    const char *own = getenv("CSGTRACE_CL_CACHE");
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    int n;
    if (own && *own)
        n = strcmp(own, "off") == 0 ? -1 : snprintf(out, size, "%s", own);
    else if (xdg && *xdg == '/')
        n = snprintf(out, size, "%s/csgtrace", xdg);
    else if (home && *home == '/')
        n = snprintf(out, size, "%s/.cache/csgtrace", home);
    else
        n = -1;
    return n > 0 && (size_t)n < size;
}

static bool cl_cache_path(uint64_t key, char *out, size_t size)
{
    char dir[PATH_MAX];
    return cl_cache_dir(dir, sizeof dir) &&
           (size_t)snprintf(out, size, "%s/%016llx.clbin", dir, (unsigned long long)key) < size;
}

void *cl_cache_load(uint64_t key, size_t *size)
{
    char path[PATH_MAX];
    if (!cl_cache_path(key, path, sizeof path))
        return NULL;
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd < 0)
        return NULL;
    cl_cache_header h;
    struct stat st;
    void *payload = NULL;
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && read(fd, &h, sizeof h) == sizeof h &&
        memcmp(h.magic, CL_CACHE_MAGIC, sizeof CL_CACHE_MAGIC) == 0 && h.key == key &&
        h.size > 0 && h.size <= CL_CACHE_MAX_BYTES &&
        (uint64_t)st.st_size == sizeof h + h.size && (payload = malloc(h.size)) &&
        read(fd, payload, h.size) == (ssize_t)h.size &&
        fnv1a(FNV_BASIS, payload, h.size) == h.sum) {
        *size = h.size;
        close(fd);
        return payload;
    }
    free(payload);
    close(fd);
    return NULL;
}

void cl_cache_store(uint64_t key, const void *payload, size_t size)
{
    char dir[PATH_MAX], path[PATH_MAX], tmp[PATH_MAX + 16];
    if (size == 0 || size > CL_CACHE_MAX_BYTES || !cl_cache_dir(dir, sizeof dir) ||
        !cl_cache_path(key, path, sizeof path) ||
        (size_t)snprintf(tmp, sizeof tmp, "%s.tmp.XXXXXX", path) >= sizeof tmp)
        return;
    char parent[PATH_MAX];
    snprintf(parent, sizeof parent, "%s", dir);
    for (char *s = parent + 1; *s; s++) { /* mkdir -p, private */
        if (*s != '/')
            continue;
        *s = '\0';
        mkdir(parent, 0700);
        *s = '/';
    }
    mkdir(parent, 0700);
    int fd = mkstemp(tmp);
    if (fd < 0)
        return;
    cl_cache_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, CL_CACHE_MAGIC, sizeof CL_CACHE_MAGIC);
    h.key = key;
    h.size = size;
    h.sum = fnv1a(FNV_BASIS, payload, size);
    bool ok = file_write_all(fd, &h, sizeof h) && file_write_all(fd, payload, size);
    ok = close(fd) == 0 && ok;
    if (!ok || rename(tmp, path) != 0)
        unlink(tmp);
}
