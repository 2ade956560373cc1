/*
 * tile_sim.h — the measured cost of any rectangle of an image, for the
 * simulated build (make sim: the same master and worker built with SMPI,
 * each tile's tracing replaced by its measured seconds).
 *
 * A cost map is a tile log of a real render reduced to a regular grid of
 * cells (bench/sim/costmap.py): per cell, the worker seconds, the primary
 * hits and the scheduler's estimate, each as a density per pixel of the
 * recorded image.  A rectangle of an image of any size is mapped onto the
 * recorded one by scaling its edges, and the densities are integrated over
 * the covered area, divided by the area one target pixel covers: a pixel
 * of a larger image costs what a pixel of the recorded one cost (the rays
 * a pixel casts do not depend on the resolution).
 */
#ifndef SIM_TILE_SIM_H
#define SIM_TILE_SIM_H

#include <stdbool.h>

#include "../workers/engine.h"

typedef struct {
    int width, height;     /* the recorded image                        */
    int cell;              /* cell edge in recorded pixels              */
    int cols, rows;        /* cells                                     */
    double pass_s;         /* the recorded OpenCL pass (0: homo)        */
    double *density;       /* [3 * (row * cols + col)]: seconds, hits,
                              estimate, each per recorded pixel         */
} sim_costs;

typedef struct {
    double seconds, hits, estimate;
} sim_cost;

/* Reads a cost map; false with a message on stderr. */
bool sim_costs_load(const char *path, sim_costs *c);
void sim_costs_free(sim_costs *c);

/* What rectangle r of a width x height image costs. */
sim_cost sim_costs_rect(const sim_costs *c, int width, int height, tile_rect r);

/* The map named by $CSGSIM_COSTS, loaded once per process (the simulated
 * ranks run one at a time in one process); NULL when it cannot be read. */
const sim_costs *sim_costs_shared(void);

/* The map named by environment variable `name`, loaded the first time
 * (*state 0; then 1 loaded, -1 unset, empty or unreadable) into *map;
 * NULL unless loaded. */
const sim_costs *sim_costs_from_env(const char *name, sim_costs *map, int *state);

/* What a tile rendered whole costs (no records: homo, or hetero's fill):
 * the map named by $CSGSIM_FILL_COSTS (a homo map), else the shared one. */
const sim_costs *sim_costs_render(void);

/* The positive number in environment variable `name` (bench/simulate.sh
 * sets them), or `fallback` when it is unset or not one. */
double sim_env_number(const char *name, double fallback);

/* Flops a simulated host does per measured second (the platform files
 * declare this speed, so simulated compute = measured seconds). */
#define SIM_HOST_FLOPS 1e9

#endif
