/*
 * tile.c — the runner's buffers (tile.h).  The one path
 * from a tile to its pixels, tile_run_rect, and why a tile may be split
 * into pieces without changing a bit of the image: tile_run.c (which the
 * simulated build replaces: sim/tile_run.c).
 */
#include "tile.h"

#include <stdlib.h>
#include <string.h>

bool tile_runner_init(tile_runner *tr, const void *blob, int tile)
{
    tr->grid = tile_grid_of(blob, tile);
    tr->eng = engine_for_blob(blob);
    tr->blob = blob;
    tr->records = malloc(tile_records_bytes(&tr->grid, tr->grid.pixels_max));
    tr->progress = NULL;
    tr->progress_arg = NULL;
    tr->band_pixels = TILE_BAND_PIXELS;
    return tr->records != NULL;
}

void tile_runner_free(tile_runner *tr)
{
    free(tr->records);
    tr->records = NULL;
}

void tile_run(tile_runner *tr, int index, const void *records, float *rgb, tile_result *res)
{
    tile_run_rect(tr, tile_rect_of(&tr->grid, index), records, rgb, res);
}
