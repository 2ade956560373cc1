/*
 * file_atomic.c — a whole file written through a temporary one beside it
 * (file_atomic.h).
 */
#include "file_atomic.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
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

/* ---- a file named once complete (file_temp) ---------------------------------- */

#define TEMP_SUFFIX ".tmp.XXXXXX"

/* "PATH.tmp.XXXXXX", malloc'd; NULL when out of memory. */
static char *temp_template(const char *path)
{
    size_t n = strlen(path) + sizeof TEMP_SUFFIX;
    char *name = malloc(n);
    if (name)
        snprintf(name, n, "%s" TEMP_SUFFIX, path);
    return name;
}

/* Six random letters and digits over the template's X's, as mkstemp
 * draws them. */
static void temp_draw(char *name)
{
    static const char letters[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    unsigned char r[6];
    if (getrandom(r, sizeof r, GRND_NONBLOCK) != (ssize_t)sizeof r) {
        struct timespec ts; /* (no entropy yet: the clock and the pid will do) */
        clock_gettime(CLOCK_MONOTONIC, &ts);
        unsigned long x = (unsigned long)ts.tv_nsec ^ ((unsigned long)getpid() << 16);
        for (size_t i = 0; i < sizeof r; i++, x = x * 6364136223846793005ul + 1442695040888963407ul)
            r[i] = (unsigned char)(x >> 33);
    }
    char *x = name + strlen(name) - sizeof r;
    for (size_t i = 0; i < sizeof r; i++)
        x[i] = letters[r[i] % (sizeof letters - 1)];
}

/* /proc's name of descriptor fd, through which an unnamed file is linked. */
static void temp_proc_name(int fd, char *buf, size_t size)
{
    snprintf(buf, size, "/proc/self/fd/%d", fd);
}

/* The folder part of path, malloc'd ("." when it has none). */
static char *temp_folder(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        return strdup(".");
    if (slash == path)
        return strdup("/");
    return strndup(path, (size_t)(slash - path));
}

static void temp_clear(file_temp *t)
{
    free(t->name);
    free(t->path);
    t->fd = -1;
    t->name = NULL;
    t->path = NULL;
}

void file_temp_discard(file_temp *t)
{
    int e = errno;
    if (t->fd >= 0)
        close(t->fd);
    if (t->name)
        unlink(t->name);
    temp_clear(t);
    errno = e;
}

bool file_temp_open_named(file_temp *t, const char *path, mode_t mode)
{
    t->fd = -1;
    t->name = temp_template(path);
    t->path = strdup(path);
    if (!t->name || !t->path) {
        temp_clear(t);
        errno = ENOMEM;
        return false;
    }
    t->fd = mkstemp(t->name);
    if (t->fd < 0) { /* (nothing was created under the name) */
        int e = errno;
        temp_clear(t);
        errno = e;
        return false;
    }
    if (fchmod(t->fd, mode) != 0) {
        file_temp_discard(t);
        return false;
    }
    return true;
}

bool file_temp_open(file_temp *t, const char *path, mode_t mode)
{
    t->fd = -1;
    t->name = NULL;
    t->path = strdup(path);
    char *folder = temp_folder(path);
    if (t->path && folder) {
        /* (O_RDWR as mkstemp's; /proc must be there to link it later) */
        t->fd = open(folder, O_TMPFILE | O_RDWR, mode);
        char proc[64];
        if (t->fd >= 0) {
            temp_proc_name(t->fd, proc, sizeof proc);
            if (access(proc, F_OK) == 0 && fchmod(t->fd, mode) == 0) {
                free(folder);
                return true;
            }
        }
    }
    free(folder);
    if (t->fd >= 0)
        close(t->fd);
    temp_clear(t);
    return file_temp_open_named(t, path, mode);
}

bool file_temp_name(file_temp *t)
{
    if (t->name)
        return true;
    if (t->fd < 0) {
        errno = EBADF;
        return false;
    }
    char *name = temp_template(t->path);
    if (!name) {
        errno = ENOMEM;
        return false;
    }
    char proc[64];
    temp_proc_name(t->fd, proc, sizeof proc);
    for (int tries = 0; tries < 100; tries++) {
        temp_draw(name);
        if (linkat(AT_FDCWD, proc, AT_FDCWD, name, AT_SYMLINK_FOLLOW) == 0) {
            t->name = name;
            return true;
        }
        if (errno != EEXIST)
            break;
    }
    int e = errno;
    free(name);
    errno = e;
    return false;
}

bool file_temp_commit(file_temp *t)
{
    bool ok = file_temp_name(t);
    int e = errno;
    if (close(t->fd) != 0 && ok) {
        ok = false;
        e = errno;
    }
    t->fd = -1;
    if (ok && rename(t->name, t->path) != 0) {
        ok = false;
        e = errno;
    }
    if (!ok) {
        file_temp_discard(t);
        errno = e;
        return false;
    }
    temp_clear(t);
    return true;
}

int file_temp_publish(file_temp *t)
{
    if (!file_temp_name(t) || rename(t->name, t->path) != 0) {
        file_temp_discard(t);
        return -1;
    }
    int fd = t->fd;
    t->fd = -1;
    temp_clear(t);
    return fd;
}

/* ---- whole files ------------------------------------------------------------ */

bool file_write_atomic_checked(const char *path, file_writer write, void *arg, char *err,
                               size_t err_size)
{
    file_temp t;
    FILE *f = NULL;
    err[0] = '\0';
    if (!file_temp_open(&t, path, file_default_mode()))
        goto fail;
    int fd = dup(t.fd); /* (f's own: t's stays open to be named) */
    if (fd < 0 || !(f = fdopen(fd, "w"))) {
        if (fd >= 0)
            close(fd);
        goto fail;
    }
    if (!write(f, arg, err, err_size) || fflush(f) != 0 || ferror(f))
        goto fail;
    int closed = fclose(f);
    f = NULL;
    if (closed != 0 || !file_temp_commit(&t))
        goto fail;
    return true;

fail:
    if (!err[0]) {
        char why[160];
        snprintf(err, err_size, "csgtrace: error: cannot write %s: %s", path,
                 file_strerror(errno, why, sizeof why));
    }
    if (f)
        fclose(f);
    file_temp_discard(&t); /* (harmless once committed or never opened) */
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
