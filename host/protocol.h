/*
 * protocol.h — the master/worker tile protocol, in this one place.
 *
 * Ranks of MPI_COMM_WORLD: 0 is the master, 1 .. K-1 are workers.  Every
 * message is ONE MPI message of MPI_BYTE: a fixed-size header struct of
 * this file, followed by its payload when it has one; the receiver sizes
 * the payload with MPI_Probe + MPI_Get_count and checks it.
 *
 * 1. Setup (collectives, every rank, from the master):
 *      MPI_Bcast(proto_setup)            status first: 0 go on; otherwise
 *                                        every rank exits with it (2: the
 *                                        scene is bad, 1: other failure)
 *      MPI_Bcast(blob bytes)             only when status == 0: blob_size
 *                                        bytes in PROTO_BCAST_CHUNK pieces
 *                                        (no int overflow; a worker short
 *                                        of memory can still take part)
 *    A worker validates the bytes (csg_blob_valid), picks engine_for_blob
 *    and allocates its tile buffers.
 * 2. Handshake: every worker sends the master exactly one message,
 *      PROTO_TAG_READY (proto_ready)  or  PROTO_TAG_FAIL (proto_fail).
 * 3. Tiles (self-scheduling: one tile to each worker, then the next tile to
 *    whoever answers, then drain):
 *      master -> worker  PROTO_TAG_TILE    proto_tile
 *                          [has_records: t[n] (the blob's real) then
 *                           surf[n] (uint32), n = width * height * spp
 *                           (the blob's samples a pixel, side by side),
 *                           row-major within the tile: proto_pack_records]
 *      worker -> master  PROTO_TAG_RESULT  proto_result + rgb[3 n] float
 *                   or   PROTO_TAG_FAIL    proto_fail
 *    Every TILE gets exactly one answer; a worker holds at most one tile.
 * 4. End: master -> every worker PROTO_TAG_STOP (proto_stop), sent only when
 *    that worker holds no tile (results drained).  The worker exits with
 *    proto_stop.status, so every rank ends with the master's status.
 *
 * Tiles: tile x tile pixels (edge tiles smaller), numbered row-major over
 * the grid of tiles, index = ty * tiles_x + tx (proto_tile_rect).
 *
 * Headers hold fixed-width fields only, each a multiple of 8 bytes, so a
 * payload that follows starts 8-byte aligned.  The ranks must share one
 * byte order (the blob is sent as bytes too).
 */
#ifndef WORKERS_PROTOCOL_H
#define WORKERS_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "../workers/engine.h"

enum proto_tag {
    PROTO_TAG_READY = 1, /* worker: set up, waiting for tiles  */
    PROTO_TAG_TILE,      /* master: render / shade this tile    */
    PROTO_TAG_RESULT,    /* worker: the tile's pixels           */
    PROTO_TAG_FAIL,      /* worker: cannot go on (text)         */
    PROTO_TAG_STOP       /* master: exit with this status       */
};

#define PROTO_BCAST_CHUNK 65536

/* What a TILE asks for. */
enum proto_work {
    PROTO_WORK_RENDER = 0, /* homo: trace the primary rays and shade   */
    PROTO_WORK_SHADE = 1   /* hetero: shade from the records sent       */
};

typedef struct {
    int32_t status;     /* 0: the blob follows; else exit status      */
    int32_t mode;       /* enum render_mode, for the record            */
    int32_t tile;       /* tile edge in pixels                         */
    int32_t pad;
    uint64_t blob_size; /* bytes of the blob broadcast next            */
} proto_setup;

typedef struct {
    int32_t status; /* 0 */
    int32_t pad;
} proto_ready;

typedef struct {
    int32_t index;          /* tile number, row-major                  */
    int32_t work;           /* enum proto_work                         */
    int32_t x, y;           /* top-left pixel                          */
    int32_t width, height;  /* pixels of this tile                     */
} proto_tile;

typedef struct {
    int32_t index;          /* the tile answered                       */
    uint32_t hits;          /* pixels whose primary ray hit            */
    uint64_t primary, shadow, reflected, refracted; /* rays traced    */
    double busy_s;          /* seconds the worker spent on the tile    */
} proto_result;

#define PROTO_FAIL_TEXT 240
typedef struct {
    int32_t index;               /* the tile that failed; -1: setup    */
    int32_t pad;
    char text[PROTO_FAIL_TEXT];  /* NUL-terminated, one line           */
} proto_fail;

typedef struct {
    int32_t status; /* the exit status of the whole run */
    int32_t pad;
} proto_stop;

/* ---- tile geometry and packing (shared by master, worker, local path) ---- */

static inline int proto_tiles_x(int width, int tile)
{
    return (width + tile - 1) / tile;
}

static inline int proto_tile_count(int width, int height, int tile)
{
    return proto_tiles_x(width, tile) * proto_tiles_x(height, tile);
}

static inline tile_rect proto_tile_rect(int index, int width, int height, int tile)
{
    int tx = index % proto_tiles_x(width, tile), ty = index / proto_tiles_x(width, tile);
    tile_rect r = { tx * tile, ty * tile, tile, tile };
    if (r.x + r.width > width)
        r.width = width - r.x;
    if (r.y + r.height > height)
        r.height = height - r.y;
    return r;
}

/* The records of `r` out of whole-image arrays (row-major, image_width *
 * spp records a row) into tile arrays (row-major, r.width * spp a row). */
static inline void proto_pack_records(const void *t_image, const uint32_t *surf_image,
                                      int image_width, int spp, size_t real_size, tile_rect r,
                                      void *t_out, uint32_t *surf_out)
{
    size_t line = (size_t)r.width * (size_t)spp;
    for (int row = 0; row < r.height; row++) {
        size_t src = ((size_t)(r.y + row) * (size_t)image_width + (size_t)r.x) * (size_t)spp;
        size_t dst = (size_t)row * line;
        memcpy((char *)t_out + dst * real_size, (const char *)t_image + src * real_size,
               line * real_size);
        memcpy(surf_out + dst, surf_image + src, line * sizeof *surf_out);
    }
}

/* The tile's RGB (3 floats a pixel, r.width wide) into the image. */
static inline void proto_store_rgb(float *image, int image_width, tile_rect r, const float *rgb)
{
    for (int row = 0; row < r.height; row++) {
        size_t dst = ((size_t)(r.y + row) * (size_t)image_width + (size_t)r.x) * 3;
        memcpy(image + dst, rgb + (size_t)row * (size_t)r.width * 3,
               (size_t)r.width * 3 * sizeof *rgb);
    }
}

#endif
