/*
 * claim.c — the lock of a render's output (claim.h).
 *
 * Taking it: open OUT.lock (created if absent, never through a link),
 * check it is a plain file of this user's with one name (else writing the
 * process id into it would write into whatever file it is linked to),
 * flock it without waiting, then check that the name still leads to the
 * locked inode: a holder removes the file before it lets go, so a render
 * that opened the name just before may lock an inode no name leads to any
 * more; it tries again (a few times: each try means another render ended
 * or began meanwhile).
 *
 * Checking an output: lstat, never following a link; the folder's
 * permission with faccessat(AT_EACCESS), the effective ids' (a read-only
 * mount says EROFS).  No file is made to find out.
 */
#include "claim.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../signals.h"
#include "file_atomic.h"

#define CLAIM_TRIES 8

struct claim {
    int fd;     /* the lock file, flocked          */
    char *path; /* OUT.lock                        */
};

/* What a file that is not a regular one is, for the message. */
static const char *claim_kind(mode_t mode)
{
    return S_ISLNK(mode)    ? "a symbolic link"
           : S_ISDIR(mode)  ? "a folder"
           : S_ISFIFO(mode) ? "a FIFO"
           : S_ISCHR(mode)  ? "a character device"
           : S_ISBLK(mode)  ? "a block device"
           : S_ISSOCK(mode) ? "a socket"
                            : "not a regular file";
}

bool claim_check_output(const char *path, const char *what, csg_diag *d)
{
    struct stat st;
    if (lstat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        csg_error_plain(d, "%s '%s' is %s: refusing to replace it with a file%s", what, path,
                        claim_kind(st.st_mode),
                        S_ISLNK(st.st_mode) ? " (name the file it leads to instead)" : "");
        return false;
    }
    const char *slash = strrchr(path, '/');
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%.*s", slash ? (slash == path ? 1 : (int)(slash - path)) : 1,
             slash ? path : ".");
    int err = stat(dir, &st) != 0                                       ? errno
              : !S_ISDIR(st.st_mode)                                    ? ENOTDIR
              : faccessat(AT_FDCWD, dir, W_OK | X_OK, AT_EACCESS) != 0 ? errno
                                                                        : 0;
    if (err)
        csg_error_plain(d, "cannot write %s '%s': its folder %s: %s", what, path, dir,
                        strerror(err));
    return err == 0;
}

void claim_lock_name(const char *out_path, char *buf, size_t size)
{
    snprintf(buf, size, "%s%s", out_path, CLAIM_LOCK_SUFFIX);
}

/* The lock is held by another render: says so, naming it (and its
 * process, when it wrote its id already). */
static void claim_busy(int fd, const char *out_path, const char *path, csg_diag *d)
{
    char buf[32];
    ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
    buf[n > 0 ? n : 0] = '\0';
    long pid = strtol(buf, NULL, 10);
    if (pid > 0)
        csg_error_plain(d, "%s is in use by another render (process %ld holds its lock %s): "
                        "wait for it to end, or stop it", out_path, pid, path);
    else
        csg_error_plain(d, "%s is in use by another render (it holds the lock %s): wait for it "
                        "to end, or stop it", out_path, path);
}

/* One try: the lock file's descriptor, locked, the name still its own;
 * -1 with d filled on a failure, -2 to try again. */
static int claim_try(const char *out_path, const char *path, csg_diag *d)
{
    struct stat st, now;
    if (lstat(path, &st) == 0 && (S_ISLNK(st.st_mode) || !S_ISREG(st.st_mode))) {
        csg_error_plain(d, "%s %s: refusing to use it as the lock of %s", path,
                        S_ISLNK(st.st_mode) ? "is a symbolic link" : "is not a regular file",
                        out_path);
        return -1;
    }
    int fd = open(path, O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC,
                  file_default_mode());
    if (fd < 0) {
        csg_error_plain(d, "cannot create the lock %s of %s: %s", path, out_path,
                        strerror(errno));
        return -1;
    }
    const char *unfit = fstat(fd, &st) == 0 ? file_unfit(&st) : strerror(errno);
    if (unfit[0]) {
        csg_error_plain(d, "%s %s: refusing to use it as the lock of %s", path, unfit, out_path);
    } else if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        if (errno == EWOULDBLOCK)
            claim_busy(fd, out_path, path, d);
        else
            csg_error_plain(d, "cannot lock %s: %s", path, strerror(errno));
    } else if (lstat(path, &now) == 0 && now.st_dev == st.st_dev && now.st_ino == st.st_ino) {
        return fd;
    } else {
        close(fd); /* (its holder removed it as it ended: a new one) */
        return -2;
    }
    close(fd);
    return -1;
}

/* This process's id in the lock, for the message of a render refused. */
static void claim_sign(int fd)
{
    char buf[32];
    int n = snprintf(buf, sizeof buf, "%ld\n", (long)getpid());
    if (ftruncate(fd, 0) == 0) /* (it fails: the message names the lock alone) */
        n = (int)pwrite(fd, buf, (size_t)n, 0);
}

claim *claim_take(const char *out_path, csg_diag *d)
{
    size_t size = strlen(out_path) + sizeof CLAIM_LOCK_SUFFIX;
    claim *c = calloc(1, sizeof *c);
    char *path = malloc(size);
    if (!c || !path) {
        csg_error_plain(d, "out of memory for the lock of %s", out_path);
        free(c);
        free(path);
        return NULL;
    }
    claim_lock_name(out_path, path, size);
    int fd = -2;
    for (int i = 0; i < CLAIM_TRIES && fd == -2; i++)
        fd = claim_try(out_path, path, d);
    if (fd == -2)
        csg_error_plain(d, "cannot lock %s: it keeps being replaced", path);
    if (fd < 0) {
        free(c);
        free(path);
        return NULL;
    }
    signals_lock(path); /* (a signal that ends the render removes it) */
    claim_sign(fd);
    c->fd = fd;
    c->path = path;
    return c;
}

void claim_release(claim *c)
{
    if (!c)
        return;
    signals_lock(NULL);
    unlink(c->path); /* (before the lock goes with the descriptor) */
    close(c->fd);
    free(c->path);
    free(c);
}
