/*
 * signals.h — a signal that ends a render: SIGINT, SIGTERM, and every other
 * asynchronous signal whose default is to end the process (SIGHUP,
 * SIGQUIT, SIGPIPE, SIGALRM, SIGUSR1, SIGUSR2, SIGXCPU, SIGVTALRM, SIGPROF,
 * SIGIO, SIGPWR, SIGSTKFLT; the list and why: signals.c).  The process that
 * owns the image stops at once with one line and exit 128 + the signal
 * (130 SIGINT, 143 SIGTERM, 129 SIGHUP ...), removing the temporary file
 * being written (the image's, streamed or the module's), so that no
 * half-written or temporary file is ever left behind.  From the moment the
 * image is renamed into place until the stats and the tile log are written
 * too, a signal waits for them, then removes them all.  Under mpirun the
 * signal reaches every rank (mpirun forwards SIGTERM); the workers end by
 * it.
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

/* A file is renamed into place (the image; then the stats, the tile log)
 * / they are all in place: a signal in between waits for the end. */
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
 * host/output/stream.h; the module's, host/output/image_loader.c): a signal
 * that ends the process removes it, at once, however long the write would
 * take (mpirun kills a rank that outlives its SIGTERM by a few seconds).
 * NULL: none any more. */
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
