/*
 * gen.h — `csgtrace gen spheres`: random-sphere scenes with a chosen screen
 * occupancy, as in the paper's test scenes.
 */
#ifndef HOST_GEN_H
#define HOST_GEN_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "../csg/diag.h"

enum { GEN_OPAQUE = 1, GEN_REFLECTIVE = 2, GEN_TRANSPARENT = 4 };

/* What the command line asked for (host/options.h: gen's rows). */
typedef struct {
    int count;          /* spheres, >= 1                              */
    double occupancy;   /* wanted fraction of pixels hit, 0 .. 1      */
    uint64_t seed;
    int width, height;  /* the image the occupancy is measured for    */
    unsigned materials; /* GEN_* bits to draw from                    */
    const char *out_path;
} gen_options;

typedef struct {
    double occupancy;   /* measured on the written scene               */
    double scale;       /* the radius scale the search settled on      */
    int evaluations;    /* primary passes the search ran               */
} gen_result;

/* Writes the scene; false with d filled (exit 2 for d->failed from bad
 * options, 1 otherwise). */
bool gen_spheres(const gen_options *o, gen_result *r, csg_diag *d);

#endif
