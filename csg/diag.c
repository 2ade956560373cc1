/*
 * diag.c — formatting of the one-line error messages (see diag.h).
 *
 * The reason is formatted first, on its own; the prefix "file:line:col:
 * error: " then takes the room left.  A file name too long for that room
 * keeps its head and its tail around "...", so neither the position nor
 * the reason is ever cut (a reason longer than the whole buffer, which no
 * stage writes, is the only thing that can be).
 */
#include "diag.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* The file name in at most `room` bytes (NUL included): its head and tail
 * around "..." when it is longer. */
static void diag_short_name(const char *name, char *out, size_t room)
{
    size_t len = strlen(name);
    if (len < room) {
        memcpy(out, name, len + 1);
        return;
    }
    size_t keep = room > 8 ? room - 4 : 1; /* "..." and the NUL */
    size_t head = keep / 4, tail = keep - head;
    snprintf(out, room, "%.*s...%s", (int)head, name, name + len - tail);
}

static void diag_vformat(csg_diag *d, const char *file, const csg_loc *loc, const char *fmt,
                         va_list ap)
{
    if (d->failed)
        return; /* the first error is the one the user needs */
    char reason[CSG_DIAG_MAX];
    vsnprintf(reason, sizeof reason, fmt, ap);
    if (!loc) {
        snprintf(d->message, sizeof d->message, "csgtrace: error: %s", reason);
    } else {
        char numbers[48];
        int n = snprintf(numbers, sizeof numbers, ":%d:%d: error: ", loc->line, loc->col);
        size_t fixed = strlen(reason) + (size_t)(n > 0 ? n : 0);
        size_t room = fixed + 16 < sizeof d->message ? sizeof d->message - fixed : 16;
        char name[CSG_DIAG_MAX];
        diag_short_name(file, name, room);
        snprintf(d->message, sizeof d->message, "%s%s%s", name, numbers, reason);
    }
    d->failed = 1;
}

void csg_error(csg_diag *d, csg_loc loc, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    diag_vformat(d, loc.file ? loc.file : "<input>", &loc, fmt, ap);
    va_end(ap);
}

void csg_error_plain(csg_diag *d, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    diag_vformat(d, NULL, NULL, fmt, ap);
    va_end(ap);
}
