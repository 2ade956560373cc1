/*
 * estimate.h — what a work item will cost, told by its hit records before
 * any worker starts (hetero mode), and how well that told the truth.
 *
 * The model counts ray casts.  A sample that missed costs
 * ESTIMATE_MISS (the worker only writes the background).  A hit is one
 * shading point: one cast for the point itself plus one shadow ray per
 * light that casts shadows; below max_trace_level a reflective material
 * adds ESTIMATE_REFLECT more shading points (the reflected ray and what it
 * finds), a transparent one ESTIMATE_REFRACT (into the object, out of it,
 * and on).  The weights only need to rank the tiles (the scheduler sorts by
 * them; the benchmarks judge them by Spearman's rank correlation with the
 * measured seconds), so they are round numbers, checked against measured
 * tiles (bench/RESULTS.md).
 */
#ifndef PASS_ESTIMATE_H
#define PASS_ESTIMATE_H

#include <stdbool.h>
#include <stdint.h>

#include "../../workers/tile.h"

#define ESTIMATE_MISS 0.05
#define ESTIMATE_REFLECT 1.0
#define ESTIMATE_REFRACT 2.0

typedef struct {
    tile_grid grid;         /* (a copy: the caller's may be a local)       */
    const uint32_t *surf;   /* whole-image surface ids (the OpenCL pass)   */
    uint8_t *prim_class;    /* ENGINE_CLASS_* a primitive (workers/engine.h) */
    int prim_count;
    double hit_cost[4];     /* the cost of a hit, by class                 */
} estimator;

/* Reads the scene's materials and lights (through the engine table); false
 * when out of memory.  surf must outlive the estimator. */
bool estimator_init(estimator *e, const void *blob, const tile_grid *g, const uint32_t *surf);
void estimator_free(estimator *e);

/* The estimated cost of rectangle r, in ray casts; its records must be
 * final (the OpenCL slices over it are done). */
double estimate_rect(const estimator *e, tile_rect r);

/* Spearman's rank correlation of x and y (n pairs; ties get their mean
 * rank); NaN when n < 3 or either side is constant. */
double estimate_spearman(const double *x, const double *y, int n);

#endif
