/*
 * tile_sim.c — cost maps (tile_sim.h): read, scaled to a rectangle of any
 * image.  Built into every program (tests/test_tile_sim.c reads maps);
 * what only the simulated build runs is in sim/tile_run.c.
 *
 * File format (text): "csgsim-costs 1", then "width height cell pass_s",
 * then cols * rows lines "seconds hits estimate" per cell, row-major, each
 * the cell's total (the reader turns them into densities).
 */
#include "tile_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/numbers.h"
#include "../workers/tile.h"

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

const sim_costs *sim_costs_from_env(const char *name, sim_costs *map, int *state)
{
    const char *path = *state == 0 ? getenv(name) : NULL;
    if (*state == 0)
        *state = path && *path && sim_costs_load(path, map) ? 1 : -1;
    return *state == 1 ? map : NULL;
}

const sim_costs *sim_costs_render(void)
{
    static sim_costs map;
    static int state;
    const sim_costs *c = sim_costs_from_env("CSGSIM_FILL_COSTS", &map, &state);
    return c ? c : sim_costs_shared();
}

double sim_env_number(const char *name, double fallback)
{
    double x = 0;
    return number_real(getenv(name), 0, HUGE_VAL, &x) && x > 0 ? x : fallback;
}
