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

#include <stdbool.h>

#ifdef CSG_DOUBLE
#define PIGMENT_AT pigment_at_double
#define PIGMENT_SURFACE_POINT pigment_surface_point_double
#define PIGMENT_EVAL pigment_eval_double
#define PIGMENT_TMAP pigment_tmap_double
#define PIGMENT_NORMAL pigment_normal_double
#define PIGMENT_WARP_NORMAL pigment_warp_normal_double
#define PIGMENT_UNWARP_NORMAL pigment_unwarp_normal_double
#else
#define PIGMENT_AT pigment_at_float
#define PIGMENT_SURFACE_POINT pigment_surface_point_float
#define PIGMENT_EVAL pigment_eval_float
#define PIGMENT_TMAP pigment_tmap_float
#define PIGMENT_NORMAL pigment_normal_float
#define PIGMENT_WARP_NORMAL pigment_warp_normal_float
#define PIGMENT_UNWARP_NORMAL pigment_unwarp_normal_float
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
 * err bounds the rounding of p (0 for an exact point), carried through the
 * maps to their pattern spaces; no pattern reads it now (checker's cells
 * take POV-Ray's own bias alone: pigment.c, step 4). */
pigment_color PIGMENT_AT(const csg_material *mats, const csg_material *m,
                         const csg_map_color *maps, const csg_prim *prims, csg_u32 surf, vec3 p,
                         real err);

/* The point patterns are evaluated at for world point p on surface surf
 * (prims NULL or surf CSG_SURF_NONE: p itself): on its face when flat. */
void PIGMENT_SURFACE_POINT(const csg_prim *prims, csg_u32 surf, vec3 p, double w[3]);
/* The pigment of m at w: a surface point (PIGMENT_SURFACE_POINT), or a
 * point of the pattern space of the texture_map holding m; err its
 * rounding bound. */
pigment_color PIGMENT_EVAL(const csg_material *mats, const csg_material *m,
                           const csg_map_color *maps, const double w[3], double err);
/* A texture_map material m at w: the point of its pattern space q (with
 * its rounding q_err) where its entries are evaluated, the entries *prev
 * and *cur around its pattern's value, and the fraction of the way from
 * prev to cur (POV-Ray's Search_Blend_Map). */
double PIGMENT_TMAP(const csg_material *mats, const csg_material *m, const csg_map_color *maps,
                    const double w[3], double err, double q[3], double *q_err, int *prev,
                    int *cur);
/* POV-Ray's Perturb_Normal: the unit normal n (world, or the space of the
 * texture_map holding the normal's texture), perturbed by the normal
 * material nm (of the blob's mats and maps) at w, back into that space
 * (unit length). */
void PIGMENT_NORMAL(const csg_material *mats, const csg_map_color *maps, const csg_material *nm,
                    const double w[3], double n[3]);
/* POV-Ray's Warp_Normal and UnWarp_Normal through pattern material m's
 * transform (normalised before and after when scale). */
void PIGMENT_WARP_NORMAL(const csg_material *m, double n[3], bool scale);
void PIGMENT_UNWARP_NORMAL(const csg_material *m, double n[3], bool scale);

#endif
