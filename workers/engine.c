/*
 * engine.c — the engine table of one precision (compiled twice, see the
 * Makefile): the flattener and the CPU tracing/shading entry points.
 */
#include "engine.h"

#ifdef CSG_DOUBLE
#define ENGINE_SYM(name) name##_double
#define ENGINE_NAME "double"
#define ENGINE_REAL_SIZE 8
#else
#define ENGINE_SYM(name) name##_float
#define ENGINE_NAME "float"
#define ENGINE_REAL_SIZE 4
#endif

void ENGINE_SYM(engine_trace_primary)(const void *blob, tile_rect rect, void *t_out,
                                      uint32_t *surf_out, ray_counts *rays);
void ENGINE_SYM(engine_shade)(const void *blob, tile_rect rect, const void *t,
                              const uint32_t *surf, float *rgb_out, ray_counts *rays);
void ENGINE_SYM(engine_shade_answered)(const void *blob, tile_rect rect, const void *t,
                                       const uint32_t *surf, const uint32_t *known,
                                       const uint32_t *lit, float *rgb_out, ray_counts *rays);
void ENGINE_SYM(engine_miss_rgb)(const void *blob, float rgb[3]);
bool ENGINE_SYM(engine_rect_misses)(const void *blob, tile_rect rect, int32_t *met);
int32_t ENGINE_SYM(engine_rect_candidates)(const void *blob, tile_rect rect,
                                           const int32_t *from, int32_t from_n, int32_t *roots,
                                           int32_t cap);
int ENGINE_SYM(engine_surface_classes)(const void *blob, uint8_t *class_out);

const engine ENGINE_SYM(engine) = {
    .name = ENGINE_NAME,
    .real_size = ENGINE_REAL_SIZE,
    .flatten = ENGINE_SYM(csg_flatten),
    .trace_primary = ENGINE_SYM(engine_trace_primary),
    .shade = ENGINE_SYM(engine_shade),
    .shade_answered = ENGINE_SYM(engine_shade_answered),
    .miss_rgb = ENGINE_SYM(engine_miss_rgb),
    .rect_misses = ENGINE_SYM(engine_rect_misses),
    .rect_candidates = ENGINE_SYM(engine_rect_candidates),
    .surface_classes = ENGINE_SYM(engine_surface_classes),
};
