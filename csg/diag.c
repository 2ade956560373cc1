/*
 * diag.c — formatting of the one-line error messages (see diag.h).
 *
 * The reason is formatted first, on its own; the prefix "file:line:col:
 * error: " then takes the room left.  A file name too long for that room
 * keeps its head and its tail around "...", so neither the position nor
 * the reason is ever cut (a reason longer than the whole buffer, which no
 * stage writes, is the only thing that can be).  A control character in
 * either (a scene's string quoted in the reason: `#include "a\nb"`) is
 * written as an escape, so a message is always one line.
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

/* text into out (size bytes), its control characters escaped (\n, \r,
 * \t, else \xNN): a message stays one line, whatever it quotes. */
static void diag_escape(const char *text, char *out, size_t size)
{
    size_t n = 0;
    for (const unsigned char *c = (const unsigned char *)text; *c && n + 5 < size; c++) {
        if (*c >= 0x20 && *c != 0x7f) {
            out[n++] = (char)*c;
            continue;
        }
        char e = *c == '\n' ? 'n' : *c == '\r' ? 'r' : *c == '\t' ? 't' : 0;
        n += (size_t)(e ? snprintf(out + n, size - n, "\\%c", e)
                        : snprintf(out + n, size - n, "\\x%02x", *c));
    }
    out[n] = '\0';
}

/* Appends text to d->message at *n, cut at the buffer's end. */
static void diag_append(csg_diag *d, size_t *n, const char *text)
{
    size_t len = strlen(text), room = sizeof d->message - 1 - *n;
    if (len > room)
        len = room;
    memcpy(d->message + *n, text, len);
    *n += len;
    d->message[*n] = '\0';
}

#define DIAG_PLAIN_PREFIX "csgtrace: error: " /* csg_error_plain's */

static void diag_vformat(csg_diag *d, const char *file, const csg_loc *loc, const char *fmt,
                         va_list ap)
{
    if (d->failed)
        return; /* the first error is the one the user needs */
    char raw[CSG_DIAG_MAX], reason[CSG_DIAG_MAX], file_esc[CSG_DIAG_MAX];
    vsnprintf(raw, sizeof raw, fmt, ap);
    diag_escape(raw, reason, sizeof reason);
    if (file) {
        diag_escape(file, file_esc, sizeof file_esc);
        file = file_esc;
    }
    size_t n = 0;
    d->message[0] = '\0';
    if (!loc) {
        diag_append(d, &n, DIAG_PLAIN_PREFIX);
    } else {
        char numbers[48], name[CSG_DIAG_MAX];
        snprintf(numbers, sizeof numbers, ":%d:%d: error: ", loc->line, loc->col);
        size_t fixed = strlen(reason) + strlen(numbers);
        diag_short_name(file, name, fixed + 16 < sizeof d->message ? sizeof d->message - fixed : 16);
        diag_append(d, &n, name);
        diag_append(d, &n, numbers);
    }
    diag_append(d, &n, reason);
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

const char *csg_diag_reason(const csg_diag *d)
{
    size_t n = sizeof DIAG_PLAIN_PREFIX - 1;
    return strncmp(d->message, DIAG_PLAIN_PREFIX, n) == 0 ? d->message + n : d->message;
}
