/*
 * file_atomic.h — a whole file written through a temporary file beside it,
 * renamed over the target once complete: a reader never sees half a file,
 * and a failure leaves the target as it was (file_temp below).  Used for
 * every text output (stats, tile logs, compare's JSON, gen's scenes), the
 * PNG, PPM and PFM images (host/output/stream.c), the journal's creation
 * and the OpenCL program cache; the other images go the same way in the
 * image module (host/output/image_oiio.cpp), under a name (OpenImageIO
 * opens its files by name).
 */
#ifndef OUTPUT_FILE_ATOMIC_H
#define OUTPUT_FILE_ATOMIC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/types.h>

/* A new file written beside its target and given the target's name only
 * once complete.  Unnamed while it is written (Linux's O_TMPFILE) where the
 * folder's file system allows it, so that a process killed at any moment
 * before then, SIGKILL included (mpirun's, a second after its SIGTERM),
 * leaves nothing behind; else under a mkstemp name, PATH.tmp.XXXXXX
 * (O_CREAT | O_EXCL: no name guessed and planted in advance, no link
 * followed), which a signal handler must then remove. */
typedef struct {
    int fd;     /* open for writing; -1 once closed                          */
    char *name; /* its name while it has one (file_temp_name), else NULL     */
    char *path; /* the target                                                */
} file_temp;

/* Opens t beside `path` with permissions `mode`: unnamed where it can
 * be, else named; false with errno (t holds nothing). */
bool file_temp_open(file_temp *t, const char *path, mode_t mode);
/* The same, always under a mkstemp name (the fallback; tests). */
bool file_temp_open_named(file_temp *t, const char *path, mode_t mode);
/* Gives an unnamed t a name beside its target (a hard link, under a name
 * chosen as mkstemp chooses one) for the short moment before its rename,
 * in which a signal handler must know it; true at once if it has one. */
bool file_temp_name(file_temp *t);
/* Names t if it has no name, closes it and renames it over its target;
 * false with errno and t removed (the target as it was).  t holds
 * nothing after either. */
bool file_temp_commit(file_temp *t);
/* The same, but t's descriptor stays open and is returned (-1: failed). */
int file_temp_publish(file_temp *t);
/* Closes and removes t (nothing left of it); t holds nothing after. */
void file_temp_discard(file_temp *t);

/* print(f, arg) into `path`; false with "csgtrace: error: ..." in err. */
bool file_write_atomic(const char *path, void (*print)(FILE *, const void *), const void *arg,
                       char *err, size_t err_size);

/* write(f, arg, err, err_size) into `path` the same way; write returns
 * false to give up (the temporary file is removed, the target untouched),
 * leaving its message in err, or nothing for the usual "cannot write PATH:
 * strerror(errno)". */
typedef bool (*file_writer)(FILE *f, void *arg, char *err, size_t err_size);
bool file_write_atomic_checked(const char *path, file_writer write, void *arg, char *err,
                               size_t err_size);

/* Writes all n bytes of p to fd, through short writes and EINTR (a
 * signal may cut a write short); false on an error. */
bool file_write_all(int fd, const void *p, size_t n);

/* strerror(err) into buf, and for EFBIG the figure: the file-size limit
 * (RLIMIT_FSIZE, `ulimit -f`) the file met, "File too large: the file-size
 * limit (ulimit -f) is 204800 bytes".  Returns buf. */
const char *file_strerror(int err, char *buf, size_t size);

/* What fopen would give a new file: 0666 less the umask (mkstemp's 0600
 * would hide a render from the other users of a shared folder). */
mode_t file_default_mode(void);

/* Do two paths name the same file?  By device and inode when both exist,
 * else by the resolved folder and the last component (an output not yet
 * written). */
bool file_same(const char *a, const char *b);

/* Why a file that csgtrace appends to, cuts or locks may not be used (""
 * when it may): it must be this user's plain file with no other name
 * (through a hard link a write would land in another file). */
const char *file_unfit(const struct stat *st);

#endif
