/*
 * tile_run.c — the simulated build's tile (make sim: smpicc, SMPI): the
 * same functions as workers/tile_run.c, which this file replaces at link
 * time, the one seam between the traced and the simulated tile.
 * tile_run_rect executes the rectangle's measured seconds on the
 * simulated host (smpi_execute_flops at SIM_HOST_FLOPS), band by band as
 * the traced one runs, progress between bands included; its pixels are
 * black, its hits come from the map.  With --scene-memory, the pages the
 * real item named (the trace, page_trace.h) are named through the
 * worker's own pager as it goes: fetched from rank 0 by the real
 * requests when not cached, each byte installed at the measured cost.
 * And the master's own costs (charges.h), charged where a real master
 * spends them.
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include <simgrid/actor.h>
#include <simgrid/engine.h>
#include <smpi/smpi.h>

#include "../comm/pixels.h"
#include "../comm/pixels_z.h"
#include "../host/store.h"
#include "../workers/pager.h"
#include "../workers/tile.h"
#include "charges.h"
#include "page_trace.h"
#include "tile_sim.h"

typedef struct {
    double message_s, part_s, pixel_s, store_s, page_s, decompress_s;
    int store_threads;
    /* simulated time each store thread is busy until */
    double store_until[STORE_THREADS_MAX];
} sim_master_costs;

/* (the master is one rank: one set) */
static sim_master_costs *sim_master(void)
{
    static sim_master_costs m;
    static bool loaded;
    if (!loaded) {
        loaded = true;
        m.message_s = sim_env_number("CSGSIM_MASTER_MESSAGE_S", 0);
        m.part_s = sim_env_number("CSGSIM_MASTER_PART_S", 0);
        m.pixel_s = sim_env_number("CSGSIM_MASTER_PIXEL_S", 0);
        m.store_s = sim_env_number("CSGSIM_MASTER_STORE_S", 0);
        m.page_s = sim_env_number("CSGSIM_MASTER_PAGE_S", 0);
        m.decompress_s = sim_env_number("CSGSIM_MASTER_DECOMPRESS_S", 0);
        /* (0: --store-threads auto, for $CSGSIM_WORKERS workers, as the
         * render chooses them) */
        double threads = sim_env_number("CSGSIM_MASTER_STORE_THREADS", 0);
        if (threads < 1)
            threads = store_threads_auto((int)sim_env_number("CSGSIM_WORKERS", 1));
        m.store_threads = threads > STORE_THREADS_MAX ? STORE_THREADS_MAX : (int)threads;
    }
    return &m;
}

int sim_master_store_threads(void)
{
    return sim_master()->store_threads;
}

void sim_charge_master_message(void)
{
    double s = sim_master()->message_s;
    if (s > 0)
        smpi_execute_flops(s * SIM_HOST_FLOPS);
}

void sim_charge_master_part(size_t pixels, int format, size_t compressed)
{
    sim_master_costs *m = sim_master();
    double s = m->part_s + (double)pixels * m->pixel_s;
    /* what a store thread does with the part: store it, decompressed first */
    double thread_s =
        (double)pixels * (m->store_s + (format == PIXELS_RGB8Z ? 3 * m->decompress_s : 0));
    if (pixels_is_rgb8(format) && thread_s > 0) {
        /* the thread with the least waiting (store.c: its ring's bytes not
         * stored yet), each on a core of its own */
        double now = simgrid_get_clock();
        int k = 0;
        for (int i = 1; i < m->store_threads; i++)
            if (m->store_until[i] < m->store_until[k])
                k = i;
        double start = m->store_until[k] > now ? m->store_until[k] : now;
        /* the bytes a part takes in the ring, and those not stored yet */
        double bytes = format == PIXELS_RGB8Z ? (double)compressed : (double)pixels * 3;
        double waiting = (start - now) / thread_s * (bytes + STORE_ALIGN);
        if (waiting + bytes + STORE_ALIGN <= (double)STORE_RING_BYTES)
            m->store_until[k] = start + thread_s;
        else
            s += thread_s; /* every ring is full */
    }
    if (s > 0)
        smpi_execute_flops(s * SIM_HOST_FLOPS);
}

void sim_charge_master_pages(uint64_t bytes)
{
    double s = (double)bytes * sim_master()->page_s;
    if (s > 0)
        smpi_execute_flops(s * SIM_HOST_FLOPS);
}

void sim_charge_worker_serve(uint64_t bytes)
{
    static double page_s = -1; /* (a rank's own: SMPI privatizes it) */
    if (page_s < 0)
        page_s = sim_env_number("CSGSIM_MASTER_PAGE_S", 0);
    double s = (double)bytes * page_s;
    if (s > 0)
        smpi_execute_flops(s * SIM_HOST_FLOPS);
}

void sim_master_store_drain(void)
{
    const sim_master_costs *m = sim_master();
    double last = 0;
    for (int k = 0; k < m->store_threads; k++)
        last = m->store_until[k] > last ? m->store_until[k] : last;
    double left = last - simgrid_get_clock();
    if (left > 0)
        sg_actor_sleep_for(left);
}

/* The seconds are the map's (tile_run_rect below), not this host's; and
 * no clock is read: SMPI takes over clock_gettime, and reading it in each
 * worker's part moved the simulated makespan by 3 % (256 workers, 16
 * relays: 0.0722 -> 0.0698 s). */
void tile_time_start(tile_timer *t)
{
    t->wall = t->cpu = 0;
}

void tile_time_stop(const tile_timer *t, tile_result *res)
{
    (void)t;
    (void)res;
}

/* An item's replay of the pages its real one named: the prefetched ones
 * (the prefetch on) in one request before its seconds, the others named
 * one by one, evenly over its seconds, the first at its start. */
typedef struct {
    csg_pager *pager;   /* NULL: not paged                              */
    pager_stats before; /* its counts when the item began               */
    int32_t *demand;    /* the pages named on demand, in order          */
    int32_t demand_count, next;
    double install_s;   /* a byte's install, $CSGSIM_PAGE_INSTALL_S     */
} sim_pages;

/* The page named (or the pages prefetched) by `name`, each fetched byte
 * installed at its measured cost. */
static void sim_fetch(sim_pages *sp, void (*name)(csg_pager *, const int32_t *, size_t),
                      const int32_t *pages, size_t n)
{
    uint64_t bytes = sp->pager->stats.bytes;
    name(sp->pager, pages, n);
    double s = (double)(sp->pager->stats.bytes - bytes) * sp->install_s;
    if (s > 0)
        smpi_execute_flops(s * SIM_HOST_FLOPS);
}

static void sim_need_page(csg_pager *p, const int32_t *page, size_t n)
{
    (void)n;
    pager_need_page(p, *page);
}

/* The item's pages looked up in the trace, its prefetch done. */
static void sim_pages_begin(sim_pages *sp, tile_runner *tr, tile_rect r, bool traced)
{
    memset(sp, 0, sizeof *sp);
    const page_trace *t = page_trace_shared();
    sp->pager = pager_for(tr->blob);
    if (!sp->pager)
        return;
    sp->before = sp->pager->stats;
    sp->install_s = sim_env_number("CSGSIM_PAGE_INSTALL_S", 0);
    int32_t *pages = NULL;
    bool exact; /* (sim/main.c counts the tiles the trace has) */
    int32_t count = t ? page_trace_pages(t, traced ? 'T' : 'S', r.x, r.y, r.width, r.height,
                                         &pages, &exact)
                      : 0;
    int32_t *ahead = count > 0 ? malloc((size_t)count * sizeof *ahead) : NULL;
    sp->demand = count > 0 ? malloc((size_t)count * sizeof *sp->demand) : NULL;
    if (count < 0 || (count > 0 && (!ahead || !sp->demand))) {
        sp->pager->failed = true; /* (out of memory: the run's result void) */
        count = 0;
    }
    size_t ahead_count = 0;
    for (int32_t k = 0; k < count; k++) {
        if (page_trace_prefetched(pages[k]) && sp->pager->prefetch)
            ahead[ahead_count++] = page_trace_page(pages[k]);
        else
            sp->demand[sp->demand_count++] = page_trace_page(pages[k]);
    }
    if (ahead_count > 0)
        sim_fetch(sp, pager_prefetch_pages, ahead, ahead_count);
    free(ahead);
    free(pages);
}

/* `seconds` of compute from `from` on, of the item's `total`, the demand
 * pages due on the way named where they fall. */
static void sim_compute(sim_pages *sp, double from, double seconds, double total)
{
    double at = from, end = from + seconds;
    for (; sp->next < sp->demand_count; sp->next++) {
        double due = total * sp->next / sp->demand_count;
        if (due > end)
            break;
        if (due > at) {
            smpi_execute_flops((due - at) * SIM_HOST_FLOPS);
            at = due;
        }
        sim_fetch(sp, sim_need_page, &sp->demand[sp->next], 1);
    }
    if (end > at)
        smpi_execute_flops((end - at) * SIM_HOST_FLOPS);
}

static void sim_pages_end(sim_pages *sp, tile_rect r, bool traced, tile_result *res)
{
    if (!sp->pager)
        return;
    pager_trace_item(sp->pager, traced ? 'T' : 'S', r.x, r.y, r.width, r.height);
    pager_item_end(sp->pager);
    res->paging = page_counts_since(&sp->before, &sp->pager->stats);
    res->page_failed = sp->pager->failed;
    free(sp->demand);
}

/* Every item's compute on its worker, one CSV line each (rank, rectangle,
 * start and end in simulated seconds), appended to $CSGSIM_WORK_LOG when
 * it is set: the item log's times are rank 0's (when it sent the item,
 * when it had the result), these the worker's.  Appended, because each
 * simulated rank has its own copy of these statics (SMPI privatises
 * them) and opens the file for itself; bench/simulate.sh starts it. */
static void sim_work_log(tile_rect r, double start, double end)
{
    static FILE *f;
    static bool opened;
    if (!opened) {
        opened = true;
        const char *path = getenv("CSGSIM_WORK_LOG");
        f = path && path[0] ? fopen(path, "a") : NULL;
    }
    if (!f)
        return;
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    fprintf(f, "%d,%d,%d,%d,%d,%.9f,%.9f\n", rank, r.x, r.y, r.width, r.height, start, end);
    fflush(f);
}

void tile_run_rect(tile_runner *tr, tile_rect r, const void *records, float *rgb,
                   tile_result *res)
{
    double started = simgrid_get_clock();
    /* shaded from records (hetero), or rendered whole (homo; hetero's fill) */
    bool traced = !records;
    const sim_costs *c = traced ? sim_costs_render() : sim_costs_shared();
    sim_cost cost = {0, 0, 0};
    if (c)
        cost = sim_costs_rect(c, tr->grid.width, tr->grid.height, r);
    if (pager_for(tr->blob)) /* (a paged item's own extra work: its prefetch walks) */
        cost.seconds *= sim_env_number("CSGSIM_PAGED_COST_SCALE", 1);
    memset(res, 0, sizeof *res);
    memset(rgb, 0, (size_t)r.width * (size_t)r.height * 3 * sizeof *rgb);
    res->hits = (uint32_t)(cost.hits + 0.5);
    res->busy_s = cost.seconds;
    res->cpu_s = cost.seconds;
    sim_pages sp;
    sim_pages_begin(&sp, tr, r, traced);
    /* in the bands of workers/tile_run.c, this rank's transfers moved on
     * between them as there (tile_runner.progress) */
    int rows = tile_band_rows(tr, r);
    for (int y0 = 0; y0 < r.height; y0 += rows) {
        int band = r.height - y0 < rows ? r.height - y0 : rows;
        if (y0 > 0)
            tr->progress(tr->progress_arg);
        sim_compute(&sp, cost.seconds * y0 / r.height, cost.seconds * band / r.height,
                    cost.seconds);
    }
    sim_compute(&sp, cost.seconds, 0, cost.seconds); /* (any left, rounding's) */
    sim_pages_end(&sp, r, traced, res);
    sim_work_log(r, started, simgrid_get_clock());
}

/* (the simulated costs do not tell the shadow answers apart) */
void tile_run_rect_answered(tile_runner *tr, tile_rect r, const void *records,
                            const void *answers, float *rgb, tile_result *res)
{
    (void)answers;
    tile_run_rect(tr, r, records, rgb, res);
}

/* The frame of `bytes` bytes whose first `noise` are pseudo-random (they
 * do not compress), the rest black, compressed by z into out: its length
 * (0 on failure). */
static size_t sim_frame(pixels_zstream *z, uint8_t *scratch, size_t bytes, size_t noise,
                        uint8_t *out)
{
    uint32_t x = 2463534242u; /* (xorshift32: the same bytes every time) */
    for (size_t i = 0; i < bytes; i++) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        scratch[i] = i < noise ? (uint8_t)x : 0;
    }
    return pixels_compress(z, scratch, bytes, out);
}

/* The map of a real render's compressed bytes a pixel ($CSGSIM_WIRE_BYTES:
 * a cost map whose seconds are bytes, bench/sim/costmap.py --column
 * wire_bytes), loaded once; NULL when unset. */
static const sim_costs *sim_wire_map(void)
{
    static sim_costs map;
    static int state;
    return sim_costs_from_env("CSGSIM_WIRE_BYTES", &map, &state);
}

/* The simulated tile's pixels are black, which compresses to almost
 * nothing: the part carries instead a frame as long as the real render's
 * part of that rectangle was (the wire map; without one, the black bytes
 * compressed), which decompresses to as many bytes as its pixels have
 * (noise, then black: nobody looks at a simulated image), and its
 * compression costs $CSGSIM_COMPRESS_S seconds a byte of 3 x pixels (the
 * measured rate, bench/compress_tiles.c). */
size_t tile_compress_rgb8(tile_runner *tr, tile_rect r, pixels_zstream *z, const uint8_t *rgb8,
                          uint8_t *out)
{
    size_t bytes = (size_t)r.width * (size_t)r.height * 3;
    double s = (double)bytes * sim_env_number("CSGSIM_COMPRESS_S", 0);
    if (s > 0)
        smpi_execute_flops(s * SIM_HOST_FLOPS);
    const sim_costs *wire = sim_wire_map();
    if (!wire)
        return pixels_compress(z, rgb8, bytes, out);
    double want = sim_costs_rect(wire, tr->grid.width, tr->grid.height, r).seconds;
    uint8_t *scratch = malloc(bytes);
    if (!scratch)
        return 0;
    /* noise costs its bytes and a little: try, then correct */
    size_t least = sim_frame(z, scratch, bytes, 0, out);
    double guess = want - (double)least;
    size_t noise = guess <= 0 ? 0 : guess >= (double)bytes ? bytes : (size_t)guess;
    size_t len = sim_frame(z, scratch, bytes, noise, out);
    if (len > 0 && noise > 0 && (double)len > want) {
        size_t over = (size_t)((double)len - want);
        noise = over < noise ? noise - over : 0;
        len = sim_frame(z, scratch, bytes, noise, out);
    }
    free(scratch);
    return len;
}
