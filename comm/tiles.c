/*
 * tiles.c — the tile grid of an image (tiles.h).
 */
#include "tiles.h"

#include <string.h>

#include "../csg/flatten.h"

tile_grid tile_grid_of(const void *blob, int tile)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    tile_grid g = {h->width, h->height, tile, h->spp, h->real_size, 0};
    g.pixels_max = (size_t)(tile < h->width ? tile : h->width) *
                   (size_t)(tile < h->height ? tile : h->height);
    return g;
}

uint64_t tiles_wide(int width, int height, int tile)
{
    uint64_t t = (uint64_t)(tile > 0 ? tile : 1);
    return ((uint64_t)width + t - 1) / t * (((uint64_t)height + t - 1) / t);
}

int tile_columns(const tile_grid *g)
{
    return (g->width + g->tile - 1) / g->tile;
}

int tile_count(const tile_grid *g)
{
    return tile_columns(g) * ((g->height + g->tile - 1) / g->tile);
}

tile_rect tile_rect_of(const tile_grid *g, int index)
{
    int columns = tile_columns(g);
    tile_rect r = {index % columns * g->tile, index / columns * g->tile, g->tile, g->tile};
    if (r.x + r.width > g->width)
        r.width = g->width - r.x;
    if (r.y + r.height > g->height)
        r.height = g->height - r.y;
    return r;
}

bool tile_rect_in_tile(const tile_grid *g, int index, tile_rect r)
{
    if (index < 0 || index >= tile_count(g))
        return false;
    tile_rect t = tile_rect_of(g, index);
    return r.width > 0 && r.height > 0 && r.x >= t.x && r.y >= t.y &&
           r.width <= t.x + t.width - r.x && r.height <= t.y + t.height - r.y;
}

size_t tile_records_bytes(const tile_grid *g, size_t pixels)
{
    return pixels * (size_t)g->spp * (g->real_size + sizeof(uint32_t));
}

size_t tile_answers_bytes(const tile_grid *g, size_t pixels)
{
    return pixels * (size_t)g->spp * 2 * sizeof(uint32_t);
}

void tile_pack_answers(const tile_grid *g, const uint32_t *known_image,
                       const uint32_t *lit_image, tile_rect r, void *out)
{
    size_t spp = (size_t)g->spp, line = (size_t)r.width * spp, n = line * (size_t)r.height;
    uint32_t *known = out, *lit = known + n;
    for (int row = 0; row < r.height; row++) {
        size_t src = ((size_t)(r.y + row) * (size_t)g->width + (size_t)r.x) * spp;
        memcpy(known + (size_t)row * line, known_image + src, line * sizeof *known);
        memcpy(lit + (size_t)row * line, lit_image + src, line * sizeof *lit);
    }
}

void tile_pack_records(const tile_grid *g, const void *t_image, const uint32_t *surf_image,
                       tile_rect r, void *out)
{
    size_t rs = g->real_size, spp = (size_t)g->spp;
    size_t line = (size_t)r.width * spp, n = line * (size_t)r.height;
    uint32_t *surf_out = (uint32_t *)((char *)out + n * rs);
    for (int row = 0; row < r.height; row++) {
        size_t src = ((size_t)(r.y + row) * (size_t)g->width + (size_t)r.x) * spp;
        size_t dst = (size_t)row * line;
        memcpy((char *)out + dst * rs, (const char *)t_image + src * rs, line * rs);
        memcpy(surf_out + dst, surf_image + src, line * sizeof *surf_out);
    }
}

void tile_store_rgb(float *image, int image_width, tile_rect r, const float *rgb)
{
    for (int row = 0; row < r.height; row++) {
        size_t dst = ((size_t)(r.y + row) * (size_t)image_width + (size_t)r.x) * 3;
        memcpy(image + dst, rgb + (size_t)row * (size_t)r.width * 3,
               (size_t)r.width * 3 * sizeof *rgb);
    }
}
