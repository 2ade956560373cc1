/*
 * estimate.c — tile cost estimates from hit records and Spearman's rank
 * correlation (estimate.h).
 *
 * estimate_rect walks the rectangle's records once: a record's surface id
 * gives its primitive (CSG_SURF_PRIM), the primitive its class, the class
 * the cost of the hit (precomputed per class in estimator_init).  Precision
 * plays no part: only the uint32 surface ids are read.
 *
 * estimate_spearman ranks both sides (sorting an index array; a run of
 * equal values gets the mean of its ranks) and returns Pearson's
 * correlation of the ranks, which is Spearman's rho with ties handled.
 */
#include "estimate.h"

#include <math.h>
#include <stdlib.h>

#include "../../workers/engine.h"

bool estimator_init(estimator *e, const void *blob, const tile_grid *g, const uint32_t *surf)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    e->grid = *g;
    e->surf = surf;
    e->prim_count = h->prim_count;
    e->prim_class = calloc((size_t)(h->prim_count > 0 ? h->prim_count : 1), 1);
    if (!e->prim_class)
        return false;
    int lights = engine_for_blob(blob)->surface_classes(blob, e->prim_class);
    double point = 1.0 + lights; /* the hit and its shadow rays */
    bool deeper = h->max_depth > 1;
    for (int c = 0; c < 4; c++) {
        double points = 1.0;
        if (deeper && (c & ENGINE_CLASS_REFLECTIVE))
            points += ESTIMATE_REFLECT;
        if (deeper && (c & ENGINE_CLASS_TRANSPARENT))
            points += ESTIMATE_REFRACT;
        e->hit_cost[c] = points * point;
    }
    return true;
}

void estimator_free(estimator *e)
{
    free(e->prim_class);
    e->prim_class = NULL;
}

double estimate_rect(const estimator *e, tile_rect r)
{
    const tile_grid *g = &e->grid;
    size_t spp = (size_t)g->spp, line = (size_t)r.width * spp;
    double cost = 0.0;
    for (int row = 0; row < r.height; row++) {
        const uint32_t *s = e->surf + ((size_t)(r.y + row) * (size_t)g->width + (size_t)r.x) * spp;
        for (size_t i = 0; i < line; i++) {
            int prim = CSG_SURF_PRIM(s[i]);
            if (s[i] == CSG_SURF_NONE || prim < 0 || prim >= e->prim_count)
                cost += ESTIMATE_MISS;
            else
                cost += e->hit_cost[e->prim_class[prim] & 3];
        }
    }
    return cost;
}

/* ---- Spearman ------------------------------------------------------------- */

static int estimate_cmp(const void *a, const void *b, void *keys)
{
    const double *v = keys;
    double x = v[*(const int *)a], y = v[*(const int *)b];
    return x < y ? -1 : x > y;
}

/* rank[i] of v[i], 1-based, ties averaged; false when out of memory. */
static bool estimate_ranks(const double *v, int n, double *rank)
{
    int *order = malloc((size_t)n * sizeof *order);
    if (!order)
        return false;
    for (int i = 0; i < n; i++)
        order[i] = i;
    qsort_r(order, (size_t)n, sizeof *order, estimate_cmp, (void *)v);
    for (int i = 0; i < n;) {
        int j = i;
        while (j + 1 < n && v[order[j + 1]] == v[order[i]])
            j++;
        for (int k = i; k <= j; k++)
            rank[order[k]] = 0.5 * (double)(i + j) + 1.0;
        i = j + 1;
    }
    free(order);
    return true;
}

static double estimate_pearson(const double *x, const double *y, int n)
{
    double mx = 0, my = 0, sxy = 0, sxx = 0, syy = 0;
    for (int i = 0; i < n; i++) {
        mx += x[i];
        my += y[i];
    }
    mx /= n;
    my /= n;
    for (int i = 0; i < n; i++) {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
        syy += (y[i] - my) * (y[i] - my);
    }
    return sxx > 0 && syy > 0 ? sxy / sqrt(sxx * syy) : (double)NAN;
}

double estimate_spearman(const double *x, const double *y, int n)
{
    if (n < 3)
        return (double)NAN;
    double *rx = malloc((size_t)n * sizeof *rx), *ry = malloc((size_t)n * sizeof *ry);
    double rho = (double)NAN;
    if (rx && ry && estimate_ranks(x, n, rx) && estimate_ranks(y, n, ry))
        rho = estimate_pearson(rx, ry, n);
    free(rx);
    free(ry);
    return rho;
}
