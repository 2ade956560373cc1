/*
 * tile_run.c — the simulated build's tile (make sim: smpicc, SMPI): the
 * same functions as workers/tile_run.c, which this file replaces at link
 * time, the one seam between the traced and the simulated tile.
 * tile_run_rect executes the rectangle's measured seconds on the
 * simulated host (smpi_execute_flops at SIM_HOST_FLOPS), band by band as
 * the traced one runs, progress between bands included; its pixels are
 * black, its hits come from the map.  And the master's own costs
 * (charges.h), charged where a real master spends them.
 */
#include <string.h>

#include <simgrid/actor.h>
#include <simgrid/engine.h>
#include <smpi/smpi.h>

#include "../host/store.h"
#include "../workers/tile.h"
#include "charges.h"
#include "tile_sim.h"

typedef struct {
    double message_s, part_s, pixel_s, store_s;
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
        double threads = sim_env_number("CSGSIM_MASTER_STORE_THREADS", 1);
        m.store_threads = threads > STORE_THREADS_MAX ? STORE_THREADS_MAX : (int)threads;
    }
    return &m;
}

void sim_charge_master_message(void)
{
    double s = sim_master()->message_s;
    if (s > 0)
        smpi_execute_flops(s * SIM_HOST_FLOPS);
}

void sim_charge_master_part(size_t pixels, bool rgb8)
{
    sim_master_costs *m = sim_master();
    double s = m->part_s + (double)pixels * m->pixel_s;
    if (rgb8 && m->store_s > 0) {
        /* the thread with the least waiting (store.c: its ring's bytes not
         * stored yet), each on a core of its own */
        double now = simgrid_get_clock();
        int k = 0;
        for (int i = 1; i < m->store_threads; i++)
            if (m->store_until[i] < m->store_until[k])
                k = i;
        double start = m->store_until[k] > now ? m->store_until[k] : now;
        double waiting = (start - now) / m->store_s * 3; /* bytes not stored yet */
        if (waiting + (double)pixels * 3 + STORE_ALIGN <= (double)STORE_RING_BYTES)
            m->store_until[k] = start + (double)pixels * m->store_s;
        else
            s += (double)pixels * m->store_s; /* every ring is full */
    }
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

void tile_run_rect(tile_runner *tr, tile_rect r, const void *records, float *rgb,
                   tile_result *res)
{
    /* shaded from records (hetero), or rendered whole (homo; hetero's fill) */
    const sim_costs *c = records ? sim_costs_shared() : sim_costs_render();
    sim_cost cost = {0, 0, 0};
    if (c)
        cost = sim_costs_rect(c, tr->grid.width, tr->grid.height, r);
    memset(res, 0, sizeof *res);
    memset(rgb, 0, (size_t)r.width * (size_t)r.height * 3 * sizeof *rgb);
    res->hits = (uint32_t)(cost.hits + 0.5);
    res->busy_s = cost.seconds;
    res->cpu_s = cost.seconds;
    /* in the bands of workers/tile_run.c, this rank's transfers moved on
     * between them as there (tile_runner.progress) */
    int rows = tile_band_rows(tr, r);
    for (int y0 = 0; y0 < r.height; y0 += rows) {
        int band = r.height - y0 < rows ? r.height - y0 : rows;
        if (y0 > 0)
            tr->progress(tr->progress_arg);
        smpi_execute_flops(cost.seconds * band / r.height * SIM_HOST_FLOPS);
    }
}

/* (the simulated costs do not tell the shadow answers apart) */
void tile_run_rect_answered(tile_runner *tr, tile_rect r, const void *records,
                            const void *answers, float *rgb, tile_result *res)
{
    (void)answers;
    tile_run_rect(tr, r, records, rgb, res);
}
