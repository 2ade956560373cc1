/*
 * precision.h — the criterion behind `--precision auto`: can float's
 * rounding reach a visible fraction of a pixel, or of the scene's
 * smallest feature?  Decided on the host from the parsed scene (double),
 * before flattening.  bench/ACCURACY.md documents and measures it.
 */
#ifndef CSG_PRECISION_H
#define CSG_PRECISION_H

#include <stdbool.h>
#include <stddef.h>

#include "scene.h"

/* float's unit roundoff (2^-24) times this: the error of a hit point,
 * relative to the largest coordinate magnitude involved. */
#define CSG_PREC_ULPS 4.0
/* Need double when that error exceeds this fraction of the pixel's
 * footprint at the object's distance ... */
#define CSG_PREC_PIXEL_FRACTION 0.125
/* ... or this fraction of the object's smallest feature. */
#define CSG_PREC_FEATURE_FRACTION 1e-3

/* Beyond these, squares leave float's range: always double. */
#define CSG_PREC_MAX_MAG 1.152921504606846976e18 /* 2^60 */
#define CSG_PREC_MIN_FEATURE 8.673617379884035472e-19 /* 2^-60 */

/* True when the scene, rendered at width x height, needs double.  `why`
 * (may be NULL) receives one line naming the deciding object and the
 * numbers: "double: sphere at scene.pov:3:1: ...", or "float: ...". */
bool csg_needs_double(const csg_scene *s, int width, int height, char *why, size_t why_size);

#endif
