/*
 * journal.c — the finished tiles of a render, kept for --resume
 * (journal.h).
 */
#include "journal.h"

#include <errno.h>
#include <elf.h>
#include <fcntl.h>
#include <pthread.h>
#include <semaphore.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "../../csg/flatten.h"
#include "../../comm/deadline.h"
#include "file_atomic.h"
#include "hash.h"
#include "../../comm/pixels.h"
#include "../exit_status.h"
#include "../signals.h"
#include "../version.h"

#define JOURNAL_FORMAT "csgtrace journal 3" /* 2: word-wise checksums;
                                               3: 8-bit records */
#define JOURNAL_HEADER_MAX 4096      /* bytes of the text header, at most  */
#define JOURNAL_TILE_MAGIC 0x454c4954u /* "TILE" (little-endian)          */
#define JOURNAL_SYNC_S 1.0           /* fdatasync at most this often      */
#define JOURNAL_POLL_S 0.001         /* the writer looks for tiles so often */

/* The fixed part of a tile record; then width * height * 3 values in
 * `pixels` (enum pixels_format: floats, or the 8-bit file's bytes), then
 * the checksum (uint64) of both.  For an 8-bit output a tile is written in
 * the file's bytes (pixels_to_rgb8): a quarter of the floats' bytes, and
 * resumed as pixels_linear_of of them, which the writer turns back into
 * the very bytes (comm/pixels.h). */
typedef struct {
    uint32_t magic, tile;
    uint32_t x, y, width, height;
    uint32_t hits, pixels;
} journal_record;

/* One line of the header: what the journal was written for. */
typedef struct {
    const char *key;  /* the header's word                      */
    const char *what; /* for the message when it differs        */
    char value[96];
} journal_field;

enum { JF_BUILD, JF_SIZE, JF_TILE, JF_SAMPLES, JF_PRECISION, JF_DEPTH, JF_RAYS, JF_SCENE,
       JF_PIXELS, JF_COUNT };

/* Appending the records and forcing them to the disk: a thread of its
 * own, so that the master only queues a finished tile's index.  Both were
 * the master's: per 32x32 tile of a 2048x2048 render, 14-21 us of writes
 * and 35 us of fdatasync on average (one a second, ~70 ms each of a growing
 * file, during which no worker got an answer).  The queue has a slot a
 * tile (each is finished once); `queued` publishes the slots (and, before
 * them, the tile's pixels and hits) to the writer.
 *
 * Nothing is appended before `begin` (journal_open's after_s on): a render
 * that ends first writes no record, and one stopped first keeps what was
 * queued (journal_close).  The records cost CPU the workers want (the
 * writer shares the cores they fill): the SPD frames, 0.02-0.7 s of
 * tiles, traced 2.5 % faster in homo and hetero without them
 * (bench/SPD-notes.md), for a journal no one resumes from. */
typedef struct {
    pthread_t thread;
    sem_t wake;          /* posted by journal_close                    */
    bool running;
    atomic_bool stop;    /* journal_close: write what is queued, end   */
    atomic_bool finished; /* ...unless the render finished: the journal
                            goes, its last records are of no use       */
    int *queue;          /* [tiles]: finished tiles, in order          */
    atomic_int queued;   /* slots filled (the master's)                */
    int taken;           /* slots written (the writer's, or the
                            master's while no writer runs)             */
    const float *image;  /* the master's image (set before the first)  */
    int synced;          /* records forced to the disk                 */
    double begin;        /* journal_clock(): no record before it       */
} journal_writer;

struct journal {
    int fd;
    char *path;
    int tiles;
    tile_grid g;
    bool *resumed;    /* [tile]                                   */
    uint32_t *hits;   /* [tile]: resumed, or summed as items come */
    int resumed_count;
    atomic_int written; /* tiles in the file                      */
    atomic_bool broken; /* a write failed: no more records        */
    double synced;    /* when data was last forced to the disk    */
    unsigned char *record; /* one record: journal_record, the
                              pixels, the checksum (one write)     */
    float *buf;       /* its pixels                               */
    size_t buf_size;  /* their room, in bytes                     */
    int pixels;       /* the output's format (pixels_format_for)  */
    uint8_t *bytes;   /* a tile's bytes, converted                */
    journal_writer writer;
};

/* ---- checksums and the program's identity ------------------------------------ */


static double journal_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The header fields of this render (to out_path: its pixel format says
 * what the records' floats are: the workers' own ("float"), or the
 * stand-ins of the 8-bit file's bytes ("rgb8", comm/pixels.h), which only
 * an 8-bit file may be written from). */
static void journal_fields(const char *out_path, const void *blob, const tile_grid *g,
                           journal_field *f)
{
    static const char *keys[JF_COUNT][2] = {
        {"build", "the program (another build of csgtrace wrote it)"},
        {"size", "the image size"},
        {"tile", "the tile size (--tile)"},
        {"samples", "the samples a pixel"},
        {"precision", "the precision"},
        {"depth", "the trace depth"},
        {"max-rays", "the ray budget (--max-rays-per-pixel)"},
        {"scene", "the scene (it, an include or an option it depends on changed)"},
        {"pixels", "the pixel format of the output (8-bit or float file)"}};
    const csg_blob_header *h = csg_blob_hdr(blob);
    const csg_shading *sh = (const csg_shading *)((const char *)blob + h->off_shading);
    for (int i = 0; i < JF_COUNT; i++) {
        f[i].key = keys[i][0];
        f[i].what = keys[i][1];
    }
    snprintf(f[JF_BUILD].value, sizeof f[0].value, "%s %016llx", CSGTRACE_VERSION,
             (unsigned long long)version_build_hash());
    snprintf(f[JF_SIZE].value, sizeof f[0].value, "%dx%d", g->width, g->height);
    snprintf(f[JF_TILE].value, sizeof f[0].value, "%d", g->tile);
    snprintf(f[JF_SAMPLES].value, sizeof f[0].value, "%d", g->spp);
    snprintf(f[JF_PRECISION].value, sizeof f[0].value, "%s",
             h->real_size == 8 ? "double" : "float");
    snprintf(f[JF_DEPTH].value, sizeof f[0].value, "%d", (int)h->max_depth);
    snprintf(f[JF_RAYS].value, sizeof f[0].value, "%d", (int)sh->max_rays);
    snprintf(f[JF_SCENE].value, sizeof f[0].value, "%016llx",
             (unsigned long long)fnv1a_words(FNV_BASIS, blob, (size_t)h->total_size));
    snprintf(f[JF_PIXELS].value, sizeof f[0].value, "%s",
             pixels_format_name(pixels_format_for(out_path)));
}

/* ---- the header ------------------------------------------------------------------ */

static size_t journal_header_text(const journal_field *f, char *out, size_t size)
{
    size_t n = (size_t)snprintf(out, size, "%s\n", JOURNAL_FORMAT);
    for (int i = 0; i < JF_COUNT && n < size; i++)
        n += (size_t)snprintf(out + n, size - n, "%s %s\n", f[i].key, f[i].value);
    if (n < size)
        n += (size_t)snprintf(out + n, size - n, ".\n");
    return n;
}

/* Reads the header of the journal at fd and checks it names this render;
 * its length in *len.  0, or 2 with d filled. */
static int journal_check_header(int fd, const char *path, const journal_field *f, size_t *len,
                                csg_diag *d)
{
    char buf[JOURNAL_HEADER_MAX + 1];
    ssize_t n = pread(fd, buf, JOURNAL_HEADER_MAX, 0);
    buf[n > 0 ? n : 0] = '\0';
    char *end = n > 0 ? strstr(buf, "\n.\n") : NULL;
    size_t format = strlen(JOURNAL_FORMAT);
    if (!end || strncmp(buf, JOURNAL_FORMAT, format) != 0 || buf[format] != '\n') {
        csg_error_plain(d, "%s is not a csgtrace journal: refusing to resume from it (render "
                        "without --resume to start over)", path);
        return EXIT_BAD_INPUT;
    }
    end[1] = '\0';
    *len = (size_t)(end + 3 - buf);
    char *line = buf + format + 1;
    for (int i = 0; i < JF_COUNT; i++) {
        char *nl = strchr(line, '\n');
        size_t k = strlen(f[i].key);
        const char *got = "(none)";
        if (nl) {
            *nl = '\0';
            if (strncmp(line, f[i].key, k) == 0 && line[k] == ' ')
                got = line + k + 1;
        }
        if (strcmp(got, f[i].value) != 0) {
            csg_error_plain(d, "%s was written for another render: %s differs (the journal's "
                            "%s: '%.100s', this render's: '%s'); render without --resume to "
                            "start over", path, f[i].what, f[i].key, got, f[i].value);
            return EXIT_BAD_INPUT;
        }
        line = nl ? nl + 1 : line;
    }
    return EXIT_OK;
}

/* ---- records ---------------------------------------------------------------------- */

static size_t journal_pixel_bytes(tile_rect r, int pixels)
{
    return (size_t)r.width * (size_t)r.height * pixels_bytes(pixels);
}

/* A record's header names a tile of this grid, in this render's pixel
 * format, with that tile's rectangle: then its size is known (*bytes: its
 * pixels' bytes). */
static bool journal_record_fits(const journal *j, const journal_record *rec, size_t *bytes)
{
    if (rec->magic != JOURNAL_TILE_MAGIC || rec->tile >= (uint32_t)j->tiles ||
        (int)rec->pixels != j->pixels)
        return false;
    tile_rect r = tile_rect_of(&j->g, (int)rec->tile);
    *bytes = journal_pixel_bytes(r, j->pixels);
    return rec->x == (uint32_t)r.x && rec->y == (uint32_t)r.y &&
           rec->width == (uint32_t)r.width && rec->height == (uint32_t)r.height;
}

enum { RECORD_NONE = -1, RECORD_DAMAGED = 0, RECORD_VALID = 1 };

/* The record at `at`, *next after it: RECORD_VALID (its tile into the
 * image, unless it is there already), RECORD_DAMAGED (whole, its header
 * sound, so its size is known, but its checksum fails: a flipped byte in
 * its hits or pixels) or RECORD_NONE (no whole record of this grid starts
 * here: a damaged header, a torn end). */
static int journal_read_one(journal *j, off_t at, float *image, off_t *next)
{
    journal_record rec;
    uint64_t sum;
    size_t bytes;
    if (pread(j->fd, &rec, sizeof rec, at) != (ssize_t)sizeof rec ||
        !journal_record_fits(j, &rec, &bytes) ||
        pread(j->fd, j->buf, bytes, at + (off_t)sizeof rec) != (ssize_t)bytes ||
        pread(j->fd, &sum, sizeof sum, at + (off_t)(sizeof rec + bytes)) != (ssize_t)sizeof sum)
        return RECORD_NONE;
    *next = at + (off_t)(sizeof rec + bytes + sizeof sum);
    if (sum != fnv1a_words(fnv1a_words(FNV_BASIS, &rec, sizeof rec), j->buf, bytes))
        return RECORD_DAMAGED;
    if (j->resumed[rec.tile])
        return RECORD_VALID; /* (a tile twice: the first kept) */
    tile_rect r = tile_rect_of(&j->g, (int)rec.tile);
    if (j->pixels == PIXELS_RGB8)
        pixels_store_bytes_rect(image, j->g.width, r.x, r.y, r.width, r.height,
                                (const uint8_t *)j->buf);
    else
        tile_store_rgb(image, j->g.width, r, j->buf);
    j->resumed[rec.tile] = true;
    j->hits[rec.tile] = rec.hits;
    j->resumed_count++;
    return RECORD_VALID;
}

#define JOURNAL_SCAN_BYTES 65536 /* read at a time looking for a record */

/* The first valid record after a damaged header, from `at` on to `size`:
 * every place the magic number appears is tried (a valid record's checksum
 * covers its header too, so pixels that happen to hold the magic are not
 * taken for one).  Its offset, its tile read (*next after it), or -1. */
static off_t journal_find_record(journal *j, off_t at, off_t size, float *image, off_t *next)
{
    static const uint32_t magic = JOURNAL_TILE_MAGIC;
    unsigned char buf[JOURNAL_SCAN_BYTES];
    while (at + (off_t)sizeof(journal_record) <= size) {
        ssize_t n = pread(j->fd, buf, sizeof buf, at);
        if (n < (ssize_t)sizeof magic)
            return -1;
        for (ssize_t i = 0; i + (ssize_t)sizeof magic <= n; i++)
            if (memcmp(buf + i, &magic, sizeof magic) == 0 &&
                journal_read_one(j, at + i, image, next) == RECORD_VALID)
                return at + i;
        at += n - (ssize_t)sizeof magic + 1; /* (a magic across the edge: read again) */
    }
    return -1;
}

/* Reads the records after the header (at `at`) into the image.  A damaged
 * record is skipped, its tile rendered again, the valid ones after it kept:
 * one whose header is sound by its size, one whose header is not by
 * looking for the next valid record.  Returns the offset after the last
 * valid record (what follows it is a torn end); *bad: the bytes of the
 * records skipped before it. */
static off_t journal_read_records(journal *j, off_t at, float *image, off_t *bad)
{
    struct stat st;
    off_t size = fstat(j->fd, &st) == 0 ? st.st_size : 0, end = at, next = at;
    *bad = 0;
    while (at < size) {
        int got = journal_read_one(j, at, image, &next);
        if (got == RECORD_NONE) {
            off_t found = journal_find_record(j, at + 1, size, image, &next);
            if (found < 0)
                break;
            got = RECORD_VALID;
            at = found;
        }
        if (got == RECORD_VALID) {
            *bad += at - end;
            end = next;
        }
        at = next;
    }
    return end;
}

/* ---- appending -------------------------------------------------------------------- */

/* Tile `tile`'s record, its pixels read from the image, appended; false
 * (the journal broken, said once) when it cannot be. */
static bool journal_append(journal *j, int tile, const float *image)
{
    tile_rect r = tile_rect_of(&j->g, tile);
    journal_record rec = {JOURNAL_TILE_MAGIC, (uint32_t)tile, (uint32_t)r.x, (uint32_t)r.y,
                          (uint32_t)r.width, (uint32_t)r.height, j->hits[tile],
                          (uint32_t)j->pixels};
    for (int y = 0; y < r.height; y++) /* the tile's rows, packed */
        memcpy(j->buf + (size_t)y * (size_t)r.width * 3,
               image + ((size_t)(r.y + y) * (size_t)j->g.width + (size_t)r.x) * 3,
               (size_t)r.width * 3 * sizeof(float));
    size_t values = (size_t)r.width * (size_t)r.height * 3;
    if (j->pixels == PIXELS_RGB8) {
        pixels_to_rgb8(j->buf, values, j->bytes);
        memcpy(j->buf, j->bytes, values);
    }
    size_t bytes = journal_pixel_bytes(r, (int)rec.pixels);
    uint64_t sum = fnv1a_words(fnv1a_words(FNV_BASIS, &rec, sizeof rec), j->buf, bytes);
    memcpy(j->record, &rec, sizeof rec);
    memcpy(j->record + sizeof rec + bytes, &sum, sizeof sum);
    if (!file_write_all(j->fd, j->record, sizeof rec + bytes + sizeof sum)) {
        char why[160];
        fprintf(stderr, "csgtrace: warning: cannot write the journal %s (%s): the render goes "
                        "on, but --resume will not find the tiles after this one\n",
                j->path, file_strerror(errno, why, sizeof why));
        atomic_store(&j->broken, true);
        return false;
    }
    signals_journal_tiles(atomic_fetch_add(&j->written, 1) + 1);
    return true;
}

/* fdatasync when JOURNAL_SYNC_S has passed since the last look and there
 * is something new; either way the next look is JOURNAL_SYNC_S on (else a
 * second with no new tile would leave the writer no time to wait). */
static void journal_sync_due(journal *j)
{
    double now = journal_clock();
    if (now - j->synced < JOURNAL_SYNC_S)
        return;
    int written = atomic_load(&j->written);
    if (written != j->writer.synced) {
        fdatasync(j->fd);
        j->writer.synced = written;
    }
    j->synced = now;
}

/* Waits JOURNAL_POLL_S, or less until the next sync is due, or until
 * journal_close posts.  (The master does not post a queued tile: a post
 * to a sleeping thread is a system call, and a context switch on a busy
 * core, on every tile.) */
static void journal_writer_wait(journal *j)
{
    double left = j->synced + JOURNAL_SYNC_S - journal_clock();
    left = left < JOURNAL_POLL_S ? left : JOURNAL_POLL_S;
    struct timespec until = deadline_after_ns(left > 0 ? (long)(left * 1e9) : 0);
    while (sem_clockwait(&j->writer.wake, CLOCK_MONOTONIC, &until) != 0 && errno == EINTR)
        continue;
}

/* The queued tiles not yet appended, appended (stopping if the journal
 * breaks). */
static void journal_append_queued(journal *j)
{
    journal_writer *w = &j->writer;
    int queued = atomic_load_explicit(&w->queued, memory_order_acquire);
    while (w->taken < queued && !atomic_load(&j->broken))
        journal_append(j, w->queue[w->taken++], w->image);
}

/* Sleeps until `begin`, or until journal_close posts. */
static void journal_writer_hold(journal *j)
{
    journal_writer *w = &j->writer;
    for (double left; !atomic_load(&w->stop) && (left = w->begin - journal_clock()) > 0;) {
        struct timespec until = deadline_after_ns((long)(left * 1e9));
        if (sem_clockwait(&w->wake, CLOCK_MONOTONIC, &until) == 0)
            break; /* (journal_close's one post: `stop` is set) */
    }
}

static void *journal_writer_run(void *arg)
{
    journal *j = arg;
    journal_writer *w = &j->writer;
    journal_writer_hold(j);
    for (;;) {
        bool stop = atomic_load(&w->stop); /* (read first: what was queued before it is written) */
        if (stop && atomic_load(&w->finished))
            return NULL;
        journal_append_queued(j);
        if (stop)
            return NULL;
        journal_sync_due(j);
        journal_writer_wait(j);
    }
}

void journal_start_writer(journal *j)
{
    if (!j || j->writer.running || atomic_load(&j->broken))
        return;
    journal_writer *w = &j->writer;
    w->synced = atomic_load(&j->written);
    if (sem_init(&w->wake, 0, 0) != 0)
        return;
    w->running = pthread_create(&w->thread, NULL, journal_writer_run, j) == 0;
    if (!w->running)
        sem_destroy(&w->wake);
}

/* Every queued tile appended (none when `finished`), the writer gone. */
static void journal_writer_stop(journal *j, bool finished)
{
    journal_writer *w = &j->writer;
    if (!w->running) {
        if (!finished) /* (the tiles queued before `begin`) */
            journal_append_queued(j);
        return;
    }
    atomic_store(&w->finished, finished);
    atomic_store(&w->stop, true);
    sem_post(&w->wake);
    pthread_join(w->thread, NULL);
    sem_destroy(&w->wake);
    w->running = false;
}

void journal_tile_done(journal *j, int tile, const float *image)
{
    if (!j || atomic_load(&j->broken))
        return;
    journal_writer *w = &j->writer;
    int slot = atomic_load_explicit(&w->queued, memory_order_relaxed);
    if (slot >= j->tiles)
        return; /* (a tile finished twice: never; the queue holds each once) */
    if (slot == 0)
        w->image = image; /* (one image a render: set before the writer may read it) */
    w->queue[slot] = tile;
    atomic_store_explicit(&w->queued, slot + 1, memory_order_release);
    if (!w->running && journal_clock() >= w->begin) { /* no writer: the master appends */
        journal_append_queued(j);
        journal_sync_due(j);
    }
}

/* ---- opening ------------------------------------------------------------------------ */

/* --resume: the existing journal, opened without following a link (nor
 * blocking on a FIFO) and checked (file_unfit); -1 with errno ENOENT
 * when there is none, else -1 with d filled. */
static int journal_open_existing(const char *path, csg_diag *d)
{
    int fd = open(path, O_RDWR | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    struct stat st;
    if (fd < 0) {
        if (errno != ENOENT)
            csg_error_plain(d, "cannot open the journal %s: %s", path, strerror(errno));
        return -1;
    }
    const char *unfit = fstat(fd, &st) == 0 ? file_unfit(&st) : strerror(errno);
    if (!unfit[0])
        return fd;
    csg_error_plain(d, "the journal %s %s: refusing to resume from it", path, unfit);
    close(fd);
    errno = EEXIST;
    return -1;
}

/* A new journal holding only the header, created exclusively beside the
 * output and renamed into place (over an earlier one, whatever its mode:
 * starting over replaces it); its descriptor, or -1. */
static int journal_create(const char *path, const journal_field *f, csg_diag *d)
{
    char header[JOURNAL_HEADER_MAX];
    size_t n = journal_header_text(f, header, sizeof header);
    file_temp t;
    int fd = -1;
    if (file_temp_open(&t, path, file_default_mode())) {
        if (file_write_all(t.fd, header, n))
            fd = file_temp_publish(&t);
        else
            file_temp_discard(&t);
    }
    if (fd < 0) {
        char why[160];
        csg_error_plain(d, "cannot create the journal %s: %s", path,
                        file_strerror(errno, why, sizeof why));
    }
    return fd;
}

static journal *journal_alloc(const char *out_path, const tile_grid *g)
{
    journal *j = calloc(1, sizeof *j);
    if (!j)
        return NULL;
    j->fd = -1;
    j->g = *g;
    j->tiles = tile_count(g);
    j->buf_size = g->pixels_max * 3 * sizeof(float);
    size_t path_size = strlen(out_path) + sizeof JOURNAL_SUFFIX;
    j->path = malloc(path_size);
    j->resumed = calloc((size_t)j->tiles, sizeof *j->resumed);
    j->hits = calloc((size_t)j->tiles, sizeof *j->hits);
    j->record = malloc(sizeof(journal_record) + j->buf_size + sizeof(uint64_t));
    j->buf = (float *)(void *)(j->record + sizeof(journal_record)); /* (32 bytes on) */
    j->pixels = pixels_format_for(out_path);
    j->bytes = malloc(g->pixels_max * 3);
    j->writer.queue = malloc((size_t)(j->tiles > 0 ? j->tiles : 1) * sizeof *j->writer.queue);
    if (!j->path || !j->resumed || !j->hits || !j->record || !j->bytes || !j->writer.queue) {
        journal_close(j, true);
        return NULL;
    }
    journal_name(out_path, j->path, path_size);
    return j;
}

/* --resume with a journal at j->fd: its tiles into the image, the file cut
 * after the last good record, ready to append.  0 or 2. */
static int journal_resume(journal *j, const journal_field *f, float *image, csg_diag *d)
{
    size_t header = 0;
    int status = journal_check_header(j->fd, j->path, f, &header, d);
    if (status != EXIT_OK)
        return status;
    off_t bad = 0, end = journal_read_records(j, (off_t)header, image, &bad);
    struct stat st;
    if (fstat(j->fd, &st) == 0 && st.st_size > end)
        bad += st.st_size - end; /* (a torn end: cut off below) */
    if (bad > 0)
        fprintf(stderr, "csgtrace: the journal %s holds %lld bytes that are not a whole, valid "
                        "tile: their tiles are rendered again, the %d valid ones resumed\n",
                j->path, (long long)bad, j->resumed_count);
    if (ftruncate(j->fd, end) != 0 || lseek(j->fd, end, SEEK_SET) != end) {
        csg_error_plain(d, "cannot append to the journal %s: %s", j->path, strerror(errno));
        return EXIT_FAILURE_RUN;
    }
    atomic_store(&j->written, j->resumed_count);
    return EXIT_OK;
}

int journal_open(const char *out_path, const void *blob, const tile_grid *g, bool resume,
                 float *image, double after_s, journal **out, csg_diag *d)
{
    journal_field f[JF_COUNT];
    journal *j = journal_alloc(out_path, g);
    *out = NULL;
    if (!j) {
        csg_error_plain(d, "out of memory for the journal of %s", out_path);
        return EXIT_FAILURE_RUN;
    }
    journal_fields(out_path, blob, g, f);
    /* (without --resume an earlier journal is not opened at all: it is
     * replaced, even read-only; the output's lock keeps other renders out) */
    j->fd = resume ? journal_open_existing(j->path, d) : -1;
    int status = EXIT_OK;
    if (resume && j->fd < 0 && errno != ENOENT) {
        status = EXIT_FAILURE_RUN;
    } else if (j->fd >= 0) {
        status = journal_resume(j, f, image, d);
    } else {
        if (resume)
            fprintf(stderr, "csgtrace: no journal %s to resume from: the render starts from "
                            "the beginning\n", j->path);
        signals_hold(); /* a signal now would leave the temporary file */
        j->fd = journal_create(j->path, f, d);
        signals_journal(j->fd >= 0 ? j->path : NULL, 0);
        signals_release(NULL, 0); /* (a signal that came: the journal goes too) */
        status = j->fd < 0 ? EXIT_FAILURE_RUN : EXIT_OK;
    }
    if (status != EXIT_OK) {
        if (j->fd >= 0) /* (a journal of another render stays as it was) */
            close(j->fd);
        j->fd = -1;
        journal_close(j, false);
        return status;
    }
    j->synced = journal_clock();
    j->writer.begin = j->synced + after_s;
    signals_journal(j->path, atomic_load(&j->written));
    *out = j;
    return EXIT_OK;
}

void journal_name(const char *out_path, char *buf, size_t size)
{
    snprintf(buf, size, "%s%s", out_path, JOURNAL_SUFFIX);
}

/* ---- queries and the end ------------------------------------------------------------ */

bool journal_resumed(const journal *j, int tile)
{
    return j && j->resumed[tile];
}

int journal_tiles_resumed(const journal *j)
{
    return j ? j->resumed_count : 0;
}

uint32_t journal_resumed_hits(const journal *j, int tile)
{
    return journal_resumed(j, tile) ? j->hits[tile] : 0;
}

void journal_add_hits(journal *j, int tile, uint32_t hits)
{
    if (j)
        j->hits[tile] += hits;
}

void journal_close(journal *j, bool finished)
{
    if (!j)
        return;
    journal_writer_stop(j, finished);
    signals_journal(NULL, 0);
    int written = atomic_load(&j->written);
    if (j->fd >= 0) {
        if (finished || written == 0)
            unlink(j->path); /* (before the lock goes with the descriptor) */
        else
            fprintf(stderr, "csgtrace: %d finished tiles are kept in %s: the same command with "
                            "--resume goes on from them\n", written, j->path);
        close(j->fd);
    }
    free(j->path);
    free(j->resumed);
    free(j->hits);
    free(j->record);
    free(j->bytes);
    free(j->writer.queue);
    free(j);
}
