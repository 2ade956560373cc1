/*
 * feed.c — the scheduler's feed during a render's tile phase (feed.h).
 *
 * The fill's culling: a fill tile is degenerate, proven without the
 * pass, when the frustum culling the workers' primary rays use
 * (engine->rect_misses) finds no object any ray of the tile may meet.
 * On the SPD files this is where hetero gains without opening its device:
 * homo sends such a tile and a worker traces its misses (tetra2: 158 of
 * 256 tiles, 14 % of the tiles' CPU); hetero fills it here, as it fills
 * the pass's degenerate tiles.
 */
#include "feed.h"

#include <string.h>

#include "../comm/test_hooks.h"
#include "output/journal.h"
#include "output/stream.h"
#include "progress.h"
#include "stats.h"

void feed_init(feed *f, sched *s, struct journal *j, struct img_stream *stream, pass *p,
               float *image, const void *blob)
{
    memset(f, 0, sizeof *f);
    f->sched = s;
    f->journal = j;
    f->stream = stream;
    f->pass = p;
    f->image = image;
    f->blob = blob;
    /* (what a missed ray sees would depend on its direction under a
     * sky_sphere, and on the fog's turbulence along it) */
    f->misses_are_background = csg_blob_hdr(blob)->sky_count == 0 && csg_blob_fog_count(blob) == 0;
    f->cull_met = -1;
    f->fill_max = (int)test_hook_number(TEST_FILL_TILES, 1000000);
    engine_for_blob(blob)->miss_rgb(blob, f->bg);
}

/* Rows from the top the pass must trace: those of the tiles above the
 * fill's (all of them without the fill). */
static int feed_rows_needed(const feed *f, const tile_grid *g)
{
    int front = sched_fill_front(f->sched);
    if (front <= 0)
        return 0;
    tile_rect last = tile_rect_of(g, front - 1);
    return last.y + last.height;
}

/* Rows from the top whose records are final (homo, serial: every row). */
static int feed_rows_ready(feed *f, const tile_grid *g, bool wait, csg_diag *d)
{
    if (!f->pass)
        return g->height;
    return pass_rows(f->pass, feed_rows_needed(f, g), wait, d);
}

/* Degenerate tile `tile` (rectangle r): the background throughout, by the
 * master; final. */
static void feed_background(feed *f, master_job *job, int tile, tile_rect r)
{
    for (int y = r.y; y < r.y + r.height; y++)
        for (int x = r.x; x < r.x + r.width; x++)
            memcpy(f->image + ((size_t)y * (size_t)job->grid.width + (size_t)x) * 3, f->bg,
                   sizeof f->bg);
    img_stream_tile(f->stream, tile);
    if (job->progress)
        progress_step(job->progress);
}

/* Tile `i`: queued; or taken from the journal (--resume: its pixels are
 * in the image already); or (the pass saw no hit in it) filled with the
 * background and logged. */
static bool feed_offer(feed *f, master_job *job, int i)
{
    tile_rect r = tile_rect_of(&job->grid, i);
    const uint32_t *tile_hits = pass_tile_hits(f->pass);
    if (journal_resumed(f->journal, i)) {
        if (!job->t)
            job->pixels_hit += journal_resumed_hits(f->journal, i);
        img_stream_tile(f->stream, i); /* (its pixels came from the journal) */
        return sched_resume(f->sched, i, r);
    }
    if (tile_hits && tile_hits[i] == 0 && f->misses_are_background) {
        feed_background(f, job, i, r);
        return sched_skip(f->sched, i, r);
    }
    return sched_add(f->sched, i, r);
}

int feed_tiles(feed *f, master_job *job, bool wait, csg_diag *d)
{
    const tile_grid *g = &job->grid;
    int rows = feed_rows_ready(f, g, wait, d), known = 0;
    if (rows < 0)
        return -1;
    for (; f->tiles_offered < sched_fill_front(f->sched); f->tiles_offered++, known++) {
        tile_rect r = tile_rect_of(g, f->tiles_offered);
        if (r.y + r.height > rows)
            break;
        if (!feed_offer(f, job, f->tiles_offered)) {
            csg_error_plain(d, "out of memory for the work items");
            return -1;
        }
    }
    if (f->tiles_offered >= sched_fill_front(f->sched) && !f->sched->closed) {
        sched_close(f->sched);
        f->closed_at = stats_clock();
    }
    return known;
}

/* Tests: the fill has claimed its CSGTRACE_TEST_FILL_TILES; the cap holds
 * while a pass may come, not once it never will. */
static bool feed_fill_capped(const feed *f)
{
    return f->fill_max > 0 && f->sched->filled >= f->fill_max && pass_may_come(f->pass);
}

/* Is fill tile r degenerate, proven without the pass (the top)? */
static bool feed_culled(feed *f, tile_rect r)
{
    if (!f->misses_are_background)
        return false;
    double t0 = stats_clock(); /* (not the thread's CPU clock: a system call) */
    bool misses = engine_for_blob(f->blob)->rect_misses(f->blob, r, &f->cull_met);
    f->cull_s += stats_clock() - t0;
    return misses;
}

int feed_fill(feed *f, master_job *job, double now, csg_diag *d)
{
    if (pass_poll(f->pass, d) < 0)
        return -2;
    for (int tile; !feed_fill_capped(f) && (tile = sched_fill_claim(f->sched, f->tiles_offered)) >= 0;) {
        tile_rect r = tile_rect_of(&job->grid, tile);
        int item = -1;
        if (journal_resumed(f->journal, tile)) { /* (the pass does not count its hits) */
            job->pixels_hit += journal_resumed_hits(f->journal, tile);
            img_stream_tile(f->stream, tile);
            if (sched_resume(f->sched, tile, r))
                continue;
        } else if (feed_culled(f, r)) {
            feed_background(f, job, tile, r);
            f->tiles_culled++;
            /* (its primary rays counted as serial counts them: trace_primary
             * counts a rectangle its culling empties, traced or not) */
            job->rays.primary += (uint64_t)r.width * (uint64_t)r.height * (uint64_t)job->grid.spp;
            if (sched_fill_skip(f->sched, tile, r))
                continue;
        } else if ((item = sched_next_fill(f->sched, now, tile, r)) >= 0) {
            return item;
        }
        csg_error_plain(d, "out of memory for the work items");
        return -2;
    }
    return -1;
}
