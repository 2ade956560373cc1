/*
 * cost.c — what the master needs to estimate a tile's cost from its hit
 * records, read from the blob in its own precision (compiled twice, like
 * shade.c: engine_surface_classes_float / _double, reached through the
 * engine table, so the host code, compiled once, never reads a `real`).
 *
 * A primary hit costs one shading point: a shadow ray per light that casts
 * shadows (shadowless lights need none), then, below max_trace_level, a
 * reflected ray if the material reflects and a refracted ray if it lets
 * light through (filter or transmit) — the same tests shade.c applies
 * before it traces them.  So a primitive's class (ENGINE_CLASS_*) and the
 * number of shadow lights are what the estimate needs (host/pass/estimate.h).
 */
#include "engine.h"

#ifdef CSG_DOUBLE
#define ENGINE_SYM(name) name##_double
#else
#define ENGINE_SYM(name) name##_float
#endif

int ENGINE_SYM(engine_surface_classes)(const void *blob, uint8_t *class_out);

static bool cost_reflects(const csg_material *m)
{
    return m->reflection[0] > R(0.0) || m->reflection[1] > R(0.0) || m->reflection[2] > R(0.0);
}

static bool cost_transmits(const csg_material *m)
{
    return m->filter > R(0.0) || m->transmit > R(0.0);
}

int ENGINE_SYM(engine_surface_classes)(const void *blob, uint8_t *class_out)
{
    const unsigned char *b = blob;
    const csg_blob_header *h = blob;
    const csg_prim *prims = (const csg_prim *)(const void *)(b + h->off_prims);
    const csg_material *mats = (const csg_material *)(const void *)(b + h->off_materials);
    const csg_flat_light *lights = (const csg_flat_light *)(const void *)(b + h->off_lights);
    for (csg_i32 i = 0; i < h->prim_count; i++) {
        const csg_material *m = &mats[prims[i].material];
        class_out[i] = (uint8_t)((cost_reflects(m) ? ENGINE_CLASS_REFLECTIVE : 0) |
                                 (cost_transmits(m) ? ENGINE_CLASS_TRANSPARENT : 0));
    }
    int shadow_lights = 0;
    for (csg_i32 i = 0; i < h->light_count; i++)
        shadow_lights += !lights[i].shadowless;
    return shadow_lights;
}
