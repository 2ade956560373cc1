/*
 * signals.h — SIGINT and SIGTERM during a render: the process that owns
 * the image stops at once with one line and exit 130 or 143, except while
 * it writes a file (the image, the stats, the tile log), which it finishes
 * (and removes again when the render stops there) so that no half-written
 * or temporary file is ever left behind.  Under mpirun the signal reaches
 * every rank (mpirun forwards SIGTERM); the workers end by it.
 */
#ifndef HOST_SIGNALS_H
#define HOST_SIGNALS_H

#include <stdbool.h>

/* SIGXFSZ ignored, in every process (main): a write past the file-size
 * limit (`ulimit -f`) then fails with EFBIG, which the writer reports with
 * the limit (host/output/file_atomic.h: file_strerror), instead of the
 * signal killing the process with no word and a half-written file. */
void signals_ignore_file_limit(void);

/* Installs the handlers (once per process). */
void signals_install(void);

/* A file write begins / ends: a signal in between waits for its end. */
void signals_hold(void);
/* Ends the hold; a signal that came meanwhile stops the process now, after
 * removing the files of `written` (n paths, NULL entries skipped: the
 * outputs just completed). */
void signals_release(const char *const *written, int n);

/* The render's outputs are written and kept: a signal from now on (one
 * mpirun sends every rank when another rank aborts the job, say) stops the
 * process with a line that says so, instead of "no file written". */
void signals_finished(void);

/* A temporary file being written (an image streamed while it renders:
 * host/output/stream.h): a signal that ends the process removes it.  NULL:
 * none any more. */
void signals_temporary(const char *path);

/* The render's lock (host/output/claim.h): a signal that ends the process
 * removes it (the lock itself ends with the process).  NULL: none. */
void signals_lock(const char *path);

/* The journal of the render (host/output/journal.h), holding `tiles` finished
 * tiles; a signal's line then says how to resume (or, when it holds none,
 * removes it).  NULL: no journal. */
void signals_journal(const char *path, int tiles);
void signals_journal_tiles(int tiles);

#endif
