/*
 * file_atomic.c — a whole file written through a temporary one beside it
 * (file_atomic.h).
 */
#include "file_atomic.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* What fopen would give a new file: 0666 less the umask (mkstemp's 0600
 * would hide a render from the other users of a shared folder).  The
 * umask is read by setting it and setting it back at once. */
static mode_t file_default_mode(void)
{
    mode_t mask = umask(077);
    umask(mask);
    return 0666 & ~mask;
}

/* print(f, arg) into `path`, through a temporary file renamed when
 * complete; false with a message in err. */
bool file_write_atomic(const char *path, void (*print)(FILE *, const void *),
                               const void *arg, char *err, size_t err_size)
{
    size_t n = strlen(path) + sizeof ".tmp.XXXXXX";
    char *tmp = malloc(n);
    FILE *f = NULL;
    int fd = -1;
    if (!tmp) {
        snprintf(err, err_size, "csgtrace: error: %s: out of memory", path);
        return false;
    }
    snprintf(tmp, n, "%s.tmp.XXXXXX", path);
    fd = mkstemp(tmp);
    if (fd < 0 || fchmod(fd, file_default_mode()) != 0)
        goto fail;
    f = fdopen(fd, "w");
    if (!f)
        goto fail;
    fd = -1; /* owned by f now */
    print(f, arg);
    if (fflush(f) != 0 || ferror(f))
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
    snprintf(err, err_size, "csgtrace: error: cannot write %s: %s", path, strerror(errno));
    if (f)
        fclose(f);
    if (fd >= 0)
        close(fd);
    unlink(tmp); /* harmless when mkstemp failed: no such file */
    free(tmp);
    return false;
}
