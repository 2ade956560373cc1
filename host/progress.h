/*
 * progress.h — a one-line progress bar on stderr while the tiles come
 * back: tiles done / total, elapsed time, an estimate of the time left.
 * Drawn only when asked for and stderr is a terminal; silent otherwise.
 */
#ifndef HOST_PROGRESS_H
#define HOST_PROGRESS_H

#include <stdbool.h>

typedef struct {
    bool enabled;     /* wanted and stderr is a terminal      */
    int total;        /* tiles to do                          */
    int done;         /* tiles done so far                    */
    double start;     /* stats_clock() at progress_begin      */
    double last_draw; /* stats_clock() of the last redraw     */
} progress_bar;

/* wanted: 0 never, 1 when stderr is a terminal, 2 always. */
void progress_begin(progress_bar *p, int total, int wanted);
/* One more tile done; redraws at most ten times a second (and at the end). */
void progress_step(progress_bar *p);
/* Erases the bar, so that what follows starts on a clean line. */
void progress_end(progress_bar *p);

#endif
