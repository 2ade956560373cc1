/*
 * feed.h — what the master's scheduler is fed during one render's tile
 * phase (master_job.feed and master_job.fill, host/master.h): the tiles
 * whose rows the pass made final (hetero; every tile at once in homo and
 * serial), and the fill's whole tiles from the bottom while none is.
 *
 * A tile offered is queued; or, resumed, taken from the journal (its
 * pixels are in the image already); or, degenerate (the pass saw no hit
 * in it, or the fill's culling proves no ray of it meets an object),
 * filled here with the background and never sent.  A tile reaches the
 * scheduler only once every slice over its rows is complete.
 */
#ifndef HOST_FEED_H
#define HOST_FEED_H

#include <stdbool.h>
#include <stdint.h>

#include "master.h"
#include "pass/pass.h"

typedef struct {
    sched *sched;          /* the work items                            */
    struct journal *journal; /* --resume's finished tiles (NULL: none)   */
    struct img_stream *stream; /* the image file, told each tile made final
                                  here (NULL: none)                      */
    pass *pass;            /* hetero's pass (NULL: every row is ready)  */
    float *image;          /* where degenerate tiles are filled         */
    float bg[3];           /* with what: what a missed ray shades to     */
    const void *blob;
    bool misses_are_background; /* no sky_sphere: a degenerate tile's
                                   pixels need no ray                    */
    int fill_max;          /* tests: the fill claims at most this while a
                              pass may come (0: no limit)                */
    int tiles_offered;     /* tiles handed to the scheduler, from the top
                              (the fill's start below them: schedule.h) */
    int tiles_culled;      /* fill tiles proven degenerate (feed_culled)  */
    int32_t cull_met;      /* the object the last fill tile's check met
                              (engine->rect_misses; -1: none)          */
    double cull_s;         /* the master's seconds in those checks       */
    double closed_at;      /* stats_clock() when the last tile was
                              offered (0: not yet)                      */
} feed;

/* A feed for one render (sched, image, blob: the render's). */
void feed_init(feed *f, sched *s, struct journal *j, struct img_stream *stream, pass *p,
               float *image, const void *blob);

/* master_job.feed's work: the tiles whose rows are ready to the
 * scheduler, down to the fill's; how many became known, or -1 with d
 * filled. */
int feed_tiles(feed *f, master_job *job, bool wait, csg_diag *d);

/* master_job.fill's work: the last tile nobody has, to be rendered
 * whole; the item, -1 when the pass has reached every tile left, -2 with
 * d filled (out of memory, or the OpenCL build could not begin). */
int feed_fill(feed *f, master_job *job, double now, csg_diag *d);

#endif
