/*
 * journal.h — the finished tiles of a render to a file, kept beside the
 * output (OUT.journal) while it renders, so that an interrupted render goes
 * on from them (--resume) instead of starting over.
 *
 * The file: a text header naming the render (the program's build, the
 * image size, tile edge, samples, precision, depth, ray budget, a hash
 * of the flattened scene: everything a pixel depends on, and the output's
 * pixel format: for an 8-bit file the floats kept stand for its bytes,
 * comm/pixels.h, and are refused for a float file), then one binary
 * record a finished tile, appended (write(2), no stdio buffer) as soon as
 * the tile's last result is in: its index and rectangle, its primary hits,
 * its pixels and an FNV-1a checksum over all of it.  The pixels are the
 * RGB floats, or, for an 8-bit output, the file's bytes (a quarter of
 * the size; resumed as the floats the master keeps for those bytes, so
 * the file is the same).  The master only
 * queues the tile; a thread of the journal's own, which looks every
 * millisecond, appends the records and forces them to the disk, so
 * neither is in the way of the workers' answers.  The first record waits
 * JOURNAL_AFTER_S: a render that ends sooner (the SPD frames, the
 * examples) never pays for a journal, and one stopped sooner keeps what it
 * had queued when it stops by itself (an error, a lost rank), but not when
 * a signal or kill -9 ends it.  Every record has a size known from its
 * tile, so a damaged one (a flipped byte) is skipped, its tile rendered
 * again, and the valid records after it are kept (after a damaged header
 * the reader looks for the next valid record); a record cut short ends the
 * journal there (it is cut off before the next append); a process killed
 * after JOURNAL_AFTER_S loses at most the tiles in flight and those of the
 * last millisecond, queued and not yet appended (the count a signal's
 * message gives is of those appended).  Data is forced to the disk
 * (fdatasync) at most once a second: a power failure may cost the last
 * second.
 *
 * The journal is created through an exclusive temporary file renamed into
 * place (never following a link), and removed once the image and the
 * stats are written.  Two renders never write one journal: the output's
 * lock (claim.h), taken before the journal is opened, keeps the second
 * out (a lock on the journal itself held only the inode its render made:
 * two renders started together each renamed their own into place).  A
 * render without --resume replaces an earlier journal (never opening it:
 * a read-only one too); with --resume one written for another render (any
 * field of the header differs) is refused, saying what differs, and so is
 * one that is not this user's plain file with one name (opened
 * O_NOFOLLOW: never written through a link, symbolic or hard).
 *
 * Resumed tiles are bit-identical to rendered ones: every mode computes the
 * same pixels (render.c), so a journal of a homo render may be resumed in
 * hetero mode and the other way round.
 */
#ifndef OUTPUT_JOURNAL_H
#define OUTPUT_JOURNAL_H

#include <stdbool.h>
#include <stdint.h>

#include "../../csg/diag.h"
#include "../../workers/tile.h"

#define JOURNAL_SUFFIX ".journal"
/* Seconds from journal_open to the first record (render.c's): a second's
 * work is all a render stopped before it loses. */
#define JOURNAL_AFTER_S 1.0

typedef struct journal journal;

/* OUT's journal: OUT.journal, into buf (cut to size). */
void journal_name(const char *out_path, char *buf, size_t size);

/* Opens the journal of the render of `blob` (validated) to `out_path` in
 * tiles of g.  resume: the valid tiles of an existing journal are copied
 * into `image` (g->width x g->height RGB floats) and marked resumed; no
 * journal there is no error (the render starts from the beginning, saying
 * so).  No record is appended before after_s seconds have passed
 * (JOURNAL_AFTER_S for a render; 0: from the first tile).  Returns 0,
 * EXIT_BAD_INPUT (2: the journal belongs to another render) or 1 (cannot
 * create; with --resume, not a plain file of this user's with one name),
 * with d filled. */
int journal_open(const char *out_path, const void *blob, const tile_grid *g, bool resume,
                 float *image, double after_s, journal **out, csg_diag *d);

/* Was tile `tile` taken from the journal?  (false for a NULL journal) */
bool journal_resumed(const journal *j, int tile);
int journal_tiles_resumed(const journal *j);
/* The primary hits of a resumed tile. */
uint32_t journal_resumed_hits(const journal *j, int tile);

/* From now on a thread of the journal's own appends the records and syncs
 * them (until then, and if it cannot be started, journal_tile_done does,
 * once after_s has passed: before, both only queue the tile).
 * Not at journal_open: creating a thread waits for the dynamic loader's
 * lock, which PoCL's loading holds for ~25 ms in hetero (host/render.c
 * starts it once the OpenCL program is built). */
void journal_start_writer(journal *j);

/* A work item of `tile` came in with `hits` primary hits. */
void journal_add_hits(journal *j, int tile, uint32_t hits);
/* Tile `tile` is complete in `image`: its record is appended (queued
 * until after_s has passed).  A failed write (disk full) prints one
 * warning and ends the journaling; the render goes on. */
void journal_tile_done(journal *j, int tile, const float *image);

/* The render ended: finished, the journal is removed (the tiles queued
 * and not yet appended never are); else every queued tile is appended,
 * after_s or not, and the journal is kept (when it holds any tile) for
 * --resume, and one line says so. */
void journal_close(journal *j, bool finished);

#endif
