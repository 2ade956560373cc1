/*
 * cl_cache.c — compiled OpenCL programs on disk (cl_cache.h).
 *
 * An entry: a header (magic, the whole key, the payload's size, SHA-256 of
 * key and payload) and the payload, the driver's binary.  SHA-256 is
 * Nettle's.
 */
#include "cl_cache.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <nettle/sha2.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../output/file_atomic.h"

/* A cached binary larger than this is not ours. */
#define CL_CACHE_MAX_BYTES ((size_t)256 << 20)

#define CL_CACHE_MAGIC "csgtrace-cl-2\n"

typedef struct {
    char magic[16];                          /* CL_CACHE_MAGIC, zero-padded */
    uint8_t key[CL_CACHE_KEY_BYTES];          /* the file's name, whole      */
    uint64_t size;                           /* payload bytes that follow   */
    uint8_t digest[SHA256_DIGEST_SIZE];      /* SHA-256(key, payload)       */
} cl_cache_header;

bool cl_cache_dir(const char *setting, const char *xdg_cache_home, const char *home, char *out,
                  size_t size)
{
    int n;
    if (setting && *setting)
        n = strcmp(setting, "off") == 0 ? -1 : snprintf(out, size, "%s", setting);
    else if (xdg_cache_home && *xdg_cache_home == '/')
        n = snprintf(out, size, "%s/csgtrace", xdg_cache_home);
    else if (home && *home == '/')
        n = snprintf(out, size, "%s/.cache/csgtrace", home);
    else
        n = -1;
    return n > 0 && (size_t)n < size;
}

/* mkdir -p, each new folder private. */
static void cl_cache_make_dir(const char *dir)
{
    char parent[PATH_MAX];
    if ((size_t)snprintf(parent, sizeof parent, "%s", dir) >= sizeof parent)
        return;
    for (char *s = parent + 1; *s; s++) {
        if (*s != '/')
            continue;
        *s = '\0';
        mkdir(parent, 0700);
        *s = '/';
    }
    mkdir(parent, 0700);
}

bool cl_cache_usable(const char *dir, char *why, size_t why_size)
{
    struct stat st;
    why[0] = '\0';
    if (stat(dir, &st) != 0) {
        cl_cache_make_dir(dir);
        if (stat(dir, &st) != 0)
            return false;
    }
    if (!S_ISDIR(st.st_mode))
        snprintf(why, why_size, "%s is not a folder", dir);
    else if (st.st_uid != geteuid())
        snprintf(why, why_size, "%s belongs to user %u, not to this one (%u)", dir,
                 (unsigned)st.st_uid, (unsigned)geteuid());
    else if (st.st_mode & (S_IWGRP | S_IWOTH))
        snprintf(why, why_size, "others may write in %s (mode %03o)", dir,
                 (unsigned)(st.st_mode & 0777));
    return why[0] == '\0';
}

static void cl_cache_hash_text(struct sha256_ctx *h, const char *text)
{
    sha256_update(h, strlen(text) + 1, (const uint8_t *)text); /* (the NUL ends each) */
}

cl_cache_key_t cl_cache_key(const char *source, const char *options, const char *device)
{
    struct sha256_ctx h;
    cl_cache_key_t key;
    sha256_init(&h);
    cl_cache_hash_text(&h, CL_CACHE_MAGIC);
    cl_cache_hash_text(&h, options);
    cl_cache_hash_text(&h, device);
    cl_cache_hash_text(&h, source);
    sha256_digest(&h, sizeof key.bytes, key.bytes);
    return key;
}

/* SHA-256 of the key and the payload: what an entry's header must carry. */
static void cl_cache_digest(const cl_cache_key_t *key, const void *payload, size_t size,
                            uint8_t out[SHA256_DIGEST_SIZE])
{
    struct sha256_ctx h;
    sha256_init(&h);
    sha256_update(&h, sizeof key->bytes, key->bytes);
    sha256_update(&h, size, payload);
    sha256_digest(&h, SHA256_DIGEST_SIZE, out);
}

/* dir/<the key's first 16 bytes in hex>.clbin */
static bool cl_cache_path(const char *dir, const cl_cache_key_t *key, char *out, size_t size)
{
    char name[2 * 16 + 1];
    for (int i = 0; i < 16; i++)
        snprintf(name + 2 * i, 3, "%02x", key->bytes[i]);
    return (size_t)snprintf(out, size, "%s/%s.clbin", dir, name) < size;
}

/* The whole of `size` bytes from fd; false on a short read. */
static bool cl_cache_read_all(int fd, void *buf, size_t size)
{
    for (size_t got = 0; got < size;) {
        ssize_t n = read(fd, (char *)buf + got, size - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        got += (size_t)n;
    }
    return true;
}

void *cl_cache_load(const char *dir, const cl_cache_key_t *key, size_t *size)
{
    char path[PATH_MAX];
    if (!dir || !cl_cache_path(dir, key, path, sizeof path))
        return NULL;
    /* (not blocking on a FIFO, not following a link: what it is is checked
     * on the open file itself) */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0)
        return NULL;
    cl_cache_header h;
    struct stat st;
    void *payload = NULL;
    uint8_t digest[SHA256_DIGEST_SIZE];
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_uid == geteuid() &&
        cl_cache_read_all(fd, &h, sizeof h) &&
        memcmp(h.magic, CL_CACHE_MAGIC, sizeof CL_CACHE_MAGIC) == 0 &&
        memcmp(h.key, key->bytes, sizeof h.key) == 0 && h.size > 0 &&
        h.size <= CL_CACHE_MAX_BYTES && (uint64_t)st.st_size == sizeof h + h.size &&
        (payload = malloc(h.size)) && cl_cache_read_all(fd, payload, h.size)) {
        cl_cache_digest(key, payload, h.size, digest);
        if (memcmp(digest, h.digest, sizeof digest) == 0) {
            *size = h.size;
            close(fd);
            return payload;
        }
    }
    free(payload);
    close(fd);
    return NULL;
}

void cl_cache_store(const char *dir, const cl_cache_key_t *key, const void *payload, size_t size)
{
    char path[PATH_MAX];
    file_temp t;
    if (!dir || size == 0 || size > CL_CACHE_MAX_BYTES ||
        !cl_cache_path(dir, key, path, sizeof path) || !file_temp_open(&t, path, 0600))
        return;
    cl_cache_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, CL_CACHE_MAGIC, sizeof CL_CACHE_MAGIC);
    memcpy(h.key, key->bytes, sizeof h.key);
    h.size = size;
    cl_cache_digest(key, payload, size, h.digest);
    if (file_write_all(t.fd, &h, sizeof h) && file_write_all(t.fd, payload, size))
        file_temp_commit(&t);
    else
        file_temp_discard(&t);
}
