/*
 * diag.h — source locations and the one-line error every stage reports:
 *   file:line:col: error: message
 * A stage that fails fills a csg_diag and returns a failure status; the
 * caller prints the message once and exits with status 2 (bad input).
 */
#ifndef CSG_DIAG_H
#define CSG_DIAG_H

typedef struct {
    const char *file; /* path as the user or the #include named it */
    int line;         /* 1-based */
    int col;          /* 1-based, in bytes */
} csg_loc;

/* The room for one message: a file name of PATH_MAX bytes and a reason of
 * as much again fit whole; a longer file name is shortened in its middle
 * so the reason always survives (csg_error). */
#define CSG_DIAG_MAX 8192

typedef struct {
    char message[CSG_DIAG_MAX]; /* the whole line, without a trailing newline */
    int failed;
} csg_diag;

/* Formats "file:line:col: error: <fmt ...>" into d (first error wins). */
void csg_error(csg_diag *d, csg_loc loc, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* An error with no source position ("csgtrace: error: ..."). */
void csg_error_plain(csg_diag *d, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* What a csg_error_plain said, without its "csgtrace: error: " (to say
 * it again as a warning); d's whole message otherwise. */
const char *csg_diag_reason(const csg_diag *d);

#endif
