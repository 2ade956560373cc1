/*
 * diag.c — formatting of the one-line error messages (see diag.h).
 */
#include "diag.h"

#include <stdarg.h>
#include <stdio.h>

static void diag_vformat(csg_diag *d, const char *prefix, const char *fmt, va_list ap)
{
    if (d->failed)
        return; /* the first error is the one the user needs */
    int n = snprintf(d->message, sizeof d->message, "%s", prefix);
    if (n < 0 || (size_t)n >= sizeof d->message)
        n = 0;
    vsnprintf(d->message + n, sizeof d->message - (size_t)n, fmt, ap);
    d->failed = 1;
}

void csg_error(csg_diag *d, csg_loc loc, const char *fmt, ...)
{
    char prefix[512];
    snprintf(prefix, sizeof prefix, "%s:%d:%d: error: ", loc.file ? loc.file : "<input>",
             loc.line, loc.col);
    va_list ap;
    va_start(ap, fmt);
    diag_vformat(d, prefix, fmt, ap);
    va_end(ap);
}

void csg_error_plain(csg_diag *d, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    diag_vformat(d, "csgtrace: error: ", fmt, ap);
    va_end(ap);
}
