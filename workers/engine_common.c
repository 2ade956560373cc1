/*
 * engine_common.c — the precision-independent helpers of engine.h.
 */
#include "engine.h"

const engine *engine_for_blob(const void *blob)
{
    return csg_blob_hdr(blob)->real_size == 8 ? &engine_double : &engine_float;
}

void engine_render_tile(const engine *e, const void *blob, tile_rect rect, void *scratch_t,
                        uint32_t *scratch_surf, float *rgb_out, ray_counts *rays)
{
    e->trace_primary(blob, rect, scratch_t, scratch_surf, rays);
    e->shade(blob, rect, scratch_t, scratch_surf, rgb_out, rays);
}
