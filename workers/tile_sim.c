/*
 * tile_sim.c — cost maps (tile_sim.h) and, in the simulated build only
 * (-DCSG_SIM, make sim), tile_run_rect: the rectangle's measured seconds
 * are executed on the simulated host (smpi_execute_flops at
 * SIM_HOST_FLOPS), its pixels are black, its hits come from the map.
 * workers/tile.c leaves tile_run_rect out of that build: this is the one
 * seam between the traced and the simulated tile.
 *
 * File format (text): "csgsim-costs 1", then "width height cell pass_s",
 * then cols * rows lines "seconds hits estimate" per cell, row-major, each
 * the cell's total (the reader turns them into densities).
 */
#include "tile_sim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tile.h"

static bool sim_costs_cells(FILE *f, sim_costs *c)
{
    size_t n = (size_t)c->cols * (size_t)c->rows;
    c->density = calloc(n * 3, sizeof *c->density);
    if (!c->density)
        return false;
    for (size_t i = 0; i < n; i++) {
        int col = (int)(i % (size_t)c->cols), row = (int)(i / (size_t)c->cols);
        int w = c->width - col * c->cell < c->cell ? c->width - col * c->cell : c->cell;
        int h = c->height - row * c->cell < c->cell ? c->height - row * c->cell : c->cell;
        double *d = &c->density[3 * i];
        if (fscanf(f, "%lf %lf %lf", &d[0], &d[1], &d[2]) != 3)
            return false;
        for (int k = 0; k < 3; k++)
            d[k] /= (double)w * (double)h;
    }
    return true;
}

bool sim_costs_load(const char *path, sim_costs *c)
{
    memset(c, 0, sizeof *c);
    FILE *f = path ? fopen(path, "r") : NULL;
    int version = 0;
    bool ok = f && fscanf(f, "csgsim-costs %d %d %d %d %lf", &version, &c->width, &c->height,
                          &c->cell, &c->pass_s) == 5 &&
              version == 1 && c->width > 0 && c->height > 0 && c->cell > 0 &&
              c->width <= 65536 && c->height <= 65536 && c->pass_s >= 0;
    if (ok) {
        c->cols = (c->width + c->cell - 1) / c->cell;
        c->rows = (c->height + c->cell - 1) / c->cell;
        ok = sim_costs_cells(f, c);
    }
    if (f)
        fclose(f);
    if (!ok) {
        fprintf(stderr, "%s: not a readable cost map\n", path ? path : "$CSGSIM_COSTS");
        sim_costs_free(c);
    }
    return ok;
}

void sim_costs_free(sim_costs *c)
{
    free(c->density);
    c->density = NULL;
}

static double sim_min(double a, double b)
{
    return a < b ? a : b;
}

static double sim_max(double a, double b)
{
    return a > b ? a : b;
}

sim_cost sim_costs_rect(const sim_costs *c, int width, int height, tile_rect r)
{
    double sx = (double)c->width / width, sy = (double)c->height / height;
    double x0 = r.x * sx, x1 = (r.x + r.width) * sx, y0 = r.y * sy, y1 = (r.y + r.height) * sy;
    int c0 = (int)(x0 / c->cell), r0 = (int)(y0 / c->cell);
    double acc[3] = {0, 0, 0};
    for (int row = r0; row < c->rows && row * c->cell < y1; row++) {
        double h = sim_min(y1, (row + 1) * c->cell) - sim_max(y0, row * c->cell);
        for (int col = c0; col < c->cols && col * c->cell < x1; col++) {
            double w = sim_min(x1, (col + 1) * c->cell) - sim_max(x0, col * c->cell);
            const double *d = &c->density[3 * ((size_t)row * (size_t)c->cols + (size_t)col)];
            for (int k = 0; k < 3; k++)
                acc[k] += d[k] * w * h;
        }
    }
    double area = sx * sy; /* recorded pixels a target pixel covers */
    sim_cost out = {acc[0] / area, acc[1] / area, acc[2] / area};
    return out;
}

const sim_costs *sim_costs_shared(void)
{
    static sim_costs map;
    static int state; /* 0 not tried, 1 loaded, -1 failed */
    if (state == 0)
        state = sim_costs_load(getenv("CSGSIM_COSTS"), &map) ? 1 : -1;
    return state == 1 ? &map : NULL;
}

const sim_costs *sim_costs_render(void)
{
    static sim_costs map;
    static int state; /* 0 not tried, 1 loaded, -1 failed or unset */
    const char *path = state == 0 ? getenv("CSGSIM_FILL_COSTS") : NULL;
    if (state == 0)
        state = path && *path && sim_costs_load(path, &map) ? 1 : -1;
    return state == 1 ? &map : sim_costs_shared();
}

double sim_env_number(const char *name, double fallback)
{
    const char *text = getenv(name);
    char *end;
    double x = text ? strtod(text, &end) : 0;
    return text && end != text && !*end && x > 0 ? x : fallback;
}

#ifdef CSG_SIM
#include <simgrid/actor.h>
#include <simgrid/engine.h>
#include <smpi/smpi.h>

#include "../host/store.h"

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
    smpi_execute_flops(cost.seconds * SIM_HOST_FLOPS);
}
#endif
