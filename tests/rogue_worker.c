/*
 * rogue_worker.c — a worker that breaks the tile protocol on purpose, to
 * show the master refuses what it is sent (tests/e2e_mpi.sh).  Launched as
 * rank 1 beside the real master, MPMD style:
 *
 *   mpirun -np 1 build/csgtrace render SCENE -o OUT --mode homo \
 *        : -np 1 build/tests/rogue_worker MODE
 *
 * It takes part in the setup like a worker (setup and blob broadcasts,
 * READY), then answers its first TILE with:
 *   big     a RESULT of 64 MiB, far over any answer the master can be sent
 *   short   a RESULT whose size does not fit the tile
 *   index   a well-sized RESULT for another tile
 *   tag     a message with a tag the protocol does not have
 *   part    (run with --batch N > 1, homo) a well-sized RESULT for every
 *           part of a batched TILE, the last part naming another tile
 *   one     (--batch N > 1) a RESULT for the first part of a batch only
 *   pixels  a RESULT in a pixel format the session did not ask for: 8-bit
 *           to a float (EXR) render, an unknown one (7) to an 8-bit one,
 *           sized for 8-bit pixels
 * and, to a render with --compress on (compressed 8-bit pixels):
 *   zbound  a RESULT whose compressed bytes are more than its pixels could
 *           ever compress to (sent whole: the size matches the header)
 *   zcorrupt  a RESULT whose compressed bytes are not a Zstandard frame
 *   zlong   a RESULT whose stream decompresses to more bytes than its tile
 * Well-sized answers come in the session's pixel format (proto_setup:
 * 3 bytes a pixel to an 8-bit file, 12 to a float one).
 * then waits for STOP and exits 0.  The master must report one error,
 * exit 1 and write no image, without taking the bytes it was not owed.
 * Under a relay (csgtrace render ... --relays K, the rogue a rank above
 * 2K - 1) it speaks to its relay, which must refuse the same answers.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../comm/mpi_link.h"
#include "../comm/protocol.h"

/* The parts of homo TILE `in` (headers only, 8-byte aligned) into
 * t[0 .. n - 1]; n. */
static int rogue_parts(const link_msg *in, proto_tile *t, int cap)
{
    int n = 0;
    for (size_t at = 0; at + sizeof *t <= in->len && n < cap; at = proto_align(at + sizeof *t))
        memcpy(&t[n++], in->data + at, sizeof *t);
    return n;
}

/* Batch modes: a RESULT for the parts of `in` (part: all, the last one
 * for the wrong tile; one: the first only). */
static void rogue_batch_reply(const char *mode, const link_msg *in, int pixels, int parent)
{
    proto_tile t[PROTO_BATCH_MAX];
    int n = rogue_parts(in, t, PROTO_BATCH_MAX);
    if (strcmp(mode, "one") == 0)
        n = 1;
    size_t len = 0;
    for (int i = 0; i < n; i++)
        len = proto_align(len) + proto_result_part((size_t)t[i].width * (size_t)t[i].height, pixels);
    char *msg = calloc(1, len);
    if (!msg)
        exit(3);
    len = 0;
    for (int i = 0; i < n; i++) {
        proto_result r = {.index = t[i].index + (n > 1 && i == n - 1), .x = t[i].x,
                          .y = t[i].y, .pixels = pixels,
                          .flags = PROTO_RESULT_PAGING}; /* (the whole header: allowed) */
        len = proto_align(len);
        memcpy(msg + len, &r, sizeof r);
        len += proto_result_part((size_t)t[i].width * (size_t)t[i].height, pixels);
    }
    link_send(parent, PROTO_TAG_RESULT, msg, len);
    free(msg);
}

/* Compressed modes (the session's pixels PIXELS_RGB8Z): a RESULT whose
 * header's payload and bytes are MODE's. */
static void rogue_compressed_reply(const char *mode, const link_msg *in, int parent)
{
    proto_tile t;
    memcpy(&t, in->data, sizeof t);
    size_t bytes = (size_t)t.width * (size_t)t.height * 3;
    size_t extra = strcmp(mode, "zlong") == 0 ? 64 : 0; /* (decompresses past the tile) */
    size_t room = pixels_compress_bound(bytes + extra) + pixels_compress_bound(bytes) + 64;
    uint8_t *raw = calloc(1, bytes + extra);
    char *msg = calloc(1, sizeof(proto_result) + room);
    pixels_zstream *z = pixels_compressor_new();
    if (!raw || !msg || !z)
        exit(3);
    uint8_t *payload = (uint8_t *)msg + sizeof(proto_result);
    size_t len;
    if (strcmp(mode, "zbound") == 0) {
        len = pixels_compress_bound(bytes) + 8;
    } else if (strcmp(mode, "zcorrupt") == 0) {
        len = 40;
        memset(payload, 0xab, len);
    } else {
        len = pixels_compress(z, raw, bytes + extra, payload);
    }
    proto_result r = {.index = t.index, .x = t.x, .y = t.y, .pixels = PIXELS_RGB8Z,
                      .payload = (uint32_t)len, .flags = PROTO_RESULT_PAGING};
    memcpy(msg, &r, sizeof r);
    link_send(parent, PROTO_TAG_RESULT, msg, sizeof r + len);
    pixels_zstream_free(z);
    free(raw);
    free(msg);
}

/* The reply to the tile in `in` that MODE asks for. */
static void rogue_reply(const char *mode, const link_msg *in, int pixels, int parent)
{
    if (strcmp(mode, "part") == 0 || strcmp(mode, "one") == 0) {
        rogue_batch_reply(mode, in, pixels, parent);
        return;
    }
    if (mode[0] == 'z') {
        rogue_compressed_reply(mode, in, parent);
        return;
    }
    int claimed = pixels;
    if (strcmp(mode, "pixels") == 0) {
        claimed = pixels == PIXELS_FLOAT ? PIXELS_RGB8 : 7;
        pixels = PIXELS_RGB8;
    }
    proto_tile t;
    memcpy(&t, in->data, sizeof t);
    size_t good = proto_result_part((size_t)t.width * (size_t)t.height, pixels);
    size_t len = strcmp(mode, "big") == 0     ? (size_t)64 << 20
                 : strcmp(mode, "short") == 0 ? good - 4
                                              : good;
    char *msg = calloc(1, len);
    if (!msg)
        exit(3);
    proto_result r = {.index = strcmp(mode, "index") == 0 ? t.index + 1 : t.index,
                      .x = t.x, .y = t.y, .pixels = claimed, .flags = PROTO_RESULT_PAGING};
    memcpy(msg, &r, sizeof r);
    link_send(parent, strcmp(mode, "tag") == 0 ? 99 : PROTO_TAG_RESULT, msg, len);
    free(msg);
}

/* The scene's check: a rogue takes whatever comes. */
static bool rogue_accept(const void *bytes, size_t size)
{
    (void)bytes;
    (void)size;
    return true;
}

int main(int argc, char **argv)
{
    int rank, size;
    if (argc != 2 || !link_start(&rank, &size))
        return 2;
    proto_setup setup;
    link_bcast_idle(&setup, sizeof setup);
    if (setup.status != 0)
        return 0;
    link_scene scene; /* (taken as a worker takes it; never read) */
    link_scene_receive(&scene, setup.blob_size, rogue_accept);
    link_scene_free(&scene);
    int parent = proto_parent(rank, setup.relays);
    proto_ready ready = {0, 0};
    link_send(parent, PROTO_TAG_READY, &ready, sizeof ready);
    link_msg in = {NULL, 0, 0, 0, 0};
    for (int answered = 0;;) {
        if (link_recv(&in, parent, (size_t)1 << 30) != LINK_OK)
            return 3;
        if (in.tag == PROTO_TAG_STOP)
            break;
        if (in.tag == PROTO_TAG_TILE && !answered++)
            rogue_reply(argv[1], &in, setup.pixels, parent);
    }
    link_msg_free(&in);
    return 0;
}
