/*
 * progress.c — the progress bar of progress.h.
 *
 * The bar is redrawn in place with a carriage return; the estimate is the
 * elapsed time scaled by the tiles left over the tiles done (tiles cost
 * about the same on average).  progress_end erases the line (ANSI "erase
 * line"), which is safe because the bar is only drawn on a terminal.
 */
#include "progress.h"

#include <stdio.h>
#include <unistd.h>

#include "stats.h"

#define PROGRESS_WIDTH 30
#define PROGRESS_PERIOD_S 0.1

static void progress_draw(progress_bar *p, double now)
{
    char bar[PROGRESS_WIDTH + 1];
    int filled = p->total > 0 ? (int)((long long)p->done * PROGRESS_WIDTH / p->total) : 0;
    for (int i = 0; i < PROGRESS_WIDTH; i++)
        bar[i] = i < filled ? '#' : '.';
    bar[PROGRESS_WIDTH] = '\0';
    double elapsed = now - p->start;
    fprintf(stderr, "\r[%s] %d/%d tiles  %.1fs", bar, p->done, p->total, elapsed);
    if (p->done > 0 && p->done < p->total)
        fprintf(stderr, "  ~%.1fs left",
                elapsed * (double)(p->total - p->done) / (double)p->done);
    fputs("\033[K", stderr);
    fflush(stderr);
    p->last_draw = now;
}

void progress_begin(progress_bar *p, int total, int wanted)
{
    p->enabled = wanted == 2 || (wanted == 1 && isatty(STDERR_FILENO));
    p->total = total;
    p->done = 0;
    p->start = stats_clock();
    p->last_draw = p->start;
    if (p->enabled)
        progress_draw(p, p->start);
}

void progress_step(progress_bar *p)
{
    p->done++;
    if (!p->enabled)
        return;
    double now = stats_clock();
    if (p->done == p->total || now - p->last_draw >= PROGRESS_PERIOD_S)
        progress_draw(p, now);
}

void progress_end(progress_bar *p)
{
    if (p->enabled) {
        fputs("\r\033[K", stderr);
        fflush(stderr);
    }
    p->enabled = false;
}
