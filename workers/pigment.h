/*
 * pigment.h — the colour of a material's pigment at a hit point
 * (workers/pigment.c), compiled once per precision like shade.c: the C
 * workers evaluate patterns from the hit record, so every mode (serial,
 * homo, hetero) gets the same bits.
 */
#ifndef WORKERS_PIGMENT_H
#define WORKERS_PIGMENT_H

#include "../csg/device/flat.h"
#include "../csg/device/vec.h"

#ifdef CSG_DOUBLE
#define PIGMENT_AT pigment_at_double
#else
#define PIGMENT_AT pigment_at_float
#endif

/* A pigment's colour at one point: rgb, filter, transmit. */
typedef struct {
    vec3 color;
    real filter, transmit;
} pigment_color;

/* The pigment of material m (one of the blob's materials, mats) at world
 * point p on surface `surf` (a packed surface id of prims; prims NULL or
 * surf CSG_SURF_NONE: a point on no surface, a sky direction): the plain
 * colour, or the pattern through the colour map or the pigment map (maps:
 * the blob's map entries; a pigment map's pigments are materials of mats).
 * err bounds the rounding of p (0 for an exact point): a checker boundary
 * within it counts as crossed, as POV-Ray's exact point on the boundary
 * does. */
pigment_color PIGMENT_AT(const csg_material *mats, const csg_material *m,
                         const csg_map_color *maps, const csg_prim *prims, csg_u32 surf, vec3 p,
                         real err);

#endif
