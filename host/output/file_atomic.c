/*
 * file_atomic.c — a whole file written through a temporary one beside it
 * (file_atomic.h).
 */
#include "file_atomic.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

/* The umask is read by setting it and setting it back at once. */
mode_t file_default_mode(void)
{
    mode_t mask = umask(077);
    umask(mask);
    return 0666 & ~mask;
}

const char *file_strerror(int err, char *buf, size_t size)
{
    struct rlimit rl;
    if (err == EFBIG && getrlimit(RLIMIT_FSIZE, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
        snprintf(buf, size, "%s: the file-size limit (ulimit -f) is %llu bytes", strerror(err),
                 (unsigned long long)rl.rlim_cur);
    else
        snprintf(buf, size, "%s", strerror(err));
    return buf;
}

bool file_write_atomic_checked(const char *path, file_writer write, void *arg, char *err,
                               size_t err_size)
{
    size_t n = strlen(path) + sizeof ".tmp.XXXXXX";
    char *tmp = malloc(n);
    FILE *f = NULL;
    int fd = -1;
    if (!tmp) {
        snprintf(err, err_size, "csgtrace: error: %s: out of memory", path);
        return false;
    }
    err[0] = '\0';
    snprintf(tmp, n, "%s.tmp.XXXXXX", path);
    fd = mkstemp(tmp);
    if (fd < 0 || fchmod(fd, file_default_mode()) != 0)
        goto fail;
    f = fdopen(fd, "w");
    if (!f)
        goto fail;
    fd = -1; /* owned by f now */
    if (!write(f, arg, err, err_size) || fflush(f) != 0 || ferror(f))
        goto fail;
    if (fclose(f) != 0) {
        f = NULL;
        goto fail;
    }
    f = NULL;
    if (rename(tmp, path) != 0)
        goto fail;
    free(tmp);
    return true;

fail:
    if (!err[0]) {
        char why[160];
        snprintf(err, err_size, "csgtrace: error: cannot write %s: %s", path,
                 file_strerror(errno, why, sizeof why));
    }
    if (f)
        fclose(f);
    if (fd >= 0)
        close(fd);
    unlink(tmp); /* harmless when mkstemp failed: no such file */
    free(tmp);
    return false;
}

/* file_write_atomic's printer as a file_writer: errors show in ferror. */
typedef struct {
    void (*print)(FILE *, const void *);
    const void *arg;
} printer;

static bool print_all(FILE *f, void *arg, char *err, size_t err_size)
{
    (void)err;
    (void)err_size;
    const printer *p = arg;
    p->print(f, p->arg);
    return true;
}

bool file_write_atomic(const char *path, void (*print)(FILE *, const void *), const void *arg,
                       char *err, size_t err_size)
{
    printer p = {print, arg};
    return file_write_atomic_checked(path, print_all, &p, err, err_size);
}

bool file_same(const char *a, const char *b)
{
    struct stat sa, sb;
    if (stat(a, &sa) == 0 && stat(b, &sb) == 0)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    char ra[PATH_MAX], rb[PATH_MAX];
    const char *ba = strrchr(a, '/'), *bb = strrchr(b, '/');
    char da[PATH_MAX], db[PATH_MAX];
    snprintf(da, sizeof da, "%.*s", ba ? (int)(ba - a) : 1, ba ? a : ".");
    snprintf(db, sizeof db, "%.*s", bb ? (int)(bb - b) : 1, bb ? b : ".");
    if (!realpath(da[0] ? da : "/", ra) || !realpath(db[0] ? db : "/", rb))
        return false;
    return strcmp(ra, rb) == 0 && strcmp(ba ? ba + 1 : a, bb ? bb + 1 : b) == 0;
}

bool file_write_all(int fd, const void *p, size_t n)
{
    const char *b = p;
    while (n > 0) {
        ssize_t w = write(fd, b, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return false;
        b += w;
        n -= (size_t)w;
    }
    return true;
}

const char *file_unfit(const struct stat *st)
{
    if (!S_ISREG(st->st_mode))
        return "is not a regular file";
    if (st->st_uid != geteuid())
        return "belongs to another user";
    if (st->st_nlink != 1)
        return "has other names (hard links)";
    return "";
}
