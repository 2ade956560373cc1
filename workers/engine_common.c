/*
 * engine_common.c — the precision-independent helpers of engine.h.
 */
#include "engine.h"

const engine *engine_for_blob(const void *blob)
{
    return csg_blob_hdr(blob)->real_size == 8 ? &engine_double : &engine_float;
}
