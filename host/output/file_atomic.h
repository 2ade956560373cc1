/*
 * file_atomic.h — a whole file written through a temporary file beside it,
 * renamed over the target once complete: a reader never sees half a file,
 * and a failure leaves the target as it was.  The temporary file is created
 * with mkstemp (O_CREAT | O_EXCL, six random characters: PATH.tmp.XXXXXX),
 * so no name can be guessed and planted in advance, and no link already at
 * a name is ever followed.  Used for every text output (stats, tile logs,
 * compare's JSON, gen's scenes) and the PNG and PPM images
 * (host/output/stream.c, which does the same itself); the other images go the same way in the image
 * module (host/output/image_oiio.cpp).
 */
#ifndef OUTPUT_FILE_ATOMIC_H
#define OUTPUT_FILE_ATOMIC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/types.h>

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
