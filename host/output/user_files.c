/*
 * user_files.c — the scene's written files beside the output
 * (user_files.h).
 *
 * Per file: its path (the output's folder + its name, which the parser
 * made relative and free of '..'), the folders on its way checked with
 * lstat (each a folder, none a link), the taken paths compared by file
 * identity (file_same), the output rules (claim_check_output), then the
 * write: atomic for a replaced file, O_APPEND for an appended one.
 */
#include "user_files.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../exit_status.h"
#include "claim.h"
#include "file_atomic.h"

static bool user_file_print(FILE *f, void *arg, char *err, size_t err_size)
{
    (void)err;
    (void)err_size;
    const csg_written_file *w = arg;
    return w->len == 0 || fwrite(w->data, 1, w->len, f) == w->len;
}

/* Every folder of `path` after the first `from` bytes (the output's
 * folder) is a folder, not a link; false with d filled. */
static bool user_file_folders(const char *path, size_t from, csg_diag *d)
{
    char part[PATH_MAX];
    for (const char *s = strchr(path + from, '/'); s; s = strchr(s + 1, '/')) {
        struct stat st;
        snprintf(part, sizeof part, "%.*s", (int)(s - path), path);
        const char *why = lstat(part, &st) != 0  ? "does not exist (csgtrace makes no folder)"
                          : S_ISLNK(st.st_mode)  ? "is a symbolic link (a scene's files are "
                                                   "written through none)"
                          : !S_ISDIR(st.st_mode) ? "is not a folder"
                                                 : NULL;
        if (why) {
            csg_error_plain(d, "cannot write the scene's file '%s': %s %s", path, part, why);
            return false;
        }
    }
    return true;
}

/* An appended file: added to the end of the file at path (made if none). */
static bool user_file_append(const char *path, const csg_written_file *w, csg_diag *d)
{
    int fd = open(path, O_WRONLY | O_APPEND | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC,
                  file_default_mode());
    struct stat st;
    char why[160];
    const char *unfit = fd < 0 || fstat(fd, &st) != 0 ? NULL : file_unfit(&st);
    bool ok = unfit && !unfit[0] && file_write_all(fd, w->data, w->len);
    if (!ok && unfit && unfit[0])
        csg_error_plain(d, "cannot append to the scene's file %s: it %s", path, unfit);
    else if (!ok)
        csg_error_plain(d, "cannot append to the scene's file %s: %s", path,
                        file_strerror(errno, why, sizeof why));
    if (fd >= 0 && close(fd) != 0 && ok) {
        csg_error_plain(d, "cannot append to the scene's file %s: %s", path,
                        file_strerror(errno, why, sizeof why));
        ok = false;
    }
    return ok;
}

int user_files_write(const csg_scene *s, const char *out_path, const char *const *taken,
                     int taken_count, csg_diag *d)
{
    const char *slash = strrchr(out_path, '/');
    int dir = slash ? (int)(slash - out_path + 1) : 0;
    for (int i = 0; i < s->written_count; i++) {
        const csg_written_file *w = &s->written[i];
        char path[PATH_MAX], err[PATH_MAX + 256];
        if (snprintf(path, sizeof path, "%.*s%s", dir, out_path, w->name) >= (int)sizeof path) {
            csg_error_plain(d, "the scene's file '%s' beside %s: the path is too long", w->name,
                            out_path);
            return EXIT_FAILURE_RUN;
        }
        for (int k = 0; k < taken_count; k++) {
            if (taken[k] && file_same(path, taken[k])) {
                csg_error_plain(d, "the scene writes '%s', which would replace %s: refusing",
                                w->name, taken[k]);
                return EXIT_BAD_INPUT;
            }
        }
        if (!user_file_folders(path, (size_t)dir, d) ||
            !claim_check_output(path, "the scene's file", d))
            return EXIT_FAILURE_RUN;
        if (w->append) {
            if (!user_file_append(path, w, d))
                return EXIT_FAILURE_RUN;
        } else if (!file_write_atomic_checked(path, user_file_print, (void *)w, err, sizeof err)) {
            csg_error_plain(d, "%s", strncmp(err, "csgtrace: error: ", 17) == 0 ? err + 17 : err);
            return EXIT_FAILURE_RUN;
        }
    }
    return EXIT_OK;
}
