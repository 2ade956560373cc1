/*
 * stream.c — the image file written while the image is rendered
 * (stream.h).
 *
 * The master's thread counts each band's tiles down (img_stream_tile) and
 * queues a band once its last tile is final.  Encoder threads take queued
 * bands, encode each into a buffer of its own (any order, any number at
 * once), and whichever thread finishes the band next in file order writes
 * the run of encoded bands from there (one writer at a time), so the file
 * grows in order while the bands are encoded out of it (a PPM band has
 * its place: it is written at once, by the thread that encoded it; the
 * image module's formats encode nothing ahead: the writer hands the run's
 * rows to the module, which encodes them as it writes).  img_stream_finish
 * adds threads for what is left, waits until every band is written, ends
 * the file and renames it over the output.
 *
 * Invariants: a band is encoded once, after every tile over it is final
 * (the queue's mutex orders the master's pixels before the encoder's
 * reads); its bytes depend on its rows alone (no filter reads the band
 * above, each deflate stream starts empty), so the file does not depend
 * on the order bands complete in; the output's name is touched only by the
 * final rename.
 */
#include "stream.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/stat.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zlib.h>

#include "../../comm/pixels.h"
#include "../signals.h"
#include "file_atomic.h"
#include "image.h"

#define STREAM_THREADS_MAX 64
#define STREAM_IDAT_MAX ((size_t)1 << 20) /* bytes of one IDAT chunk, at most */

/* PPM and PFM bands have their place in the file (rows of a fixed size):
 * "placed" kinds, written by any thread as soon as encoded. */
enum stream_kind { STREAM_PNG, STREAM_PPM, STREAM_PFM, STREAM_MODULE };

/* One band's encoded bytes, until they are written. */
typedef struct {
    unsigned char *bytes;
    size_t len;
    uint32_t adler;  /* PNG: Adler-32 of its filtered rows            */
    size_t raw;      /* PNG: bytes of its filtered rows               */
    bool encoded;
} stream_band;

struct img_stream {
    enum stream_kind kind;
    char *path;
    file_temp file;      /* the image until it is renamed over path  */
    const float *image;
    tile_grid grid;
    int bands, columns;
    int *tiles_left;     /* [bands]: tiles not final (the master's)   */
    int png_level;       /* -1: Sub/Up, run-length; else every filter */
    long header;         /* PPM, PFM: bytes before the first row      */
    size_t pixel_bytes;  /* PPM 3, PFM 12: a pixel's bytes in the file */
    pthread_mutex_t lock;
    pthread_cond_t cond; /* a band queued, encoded or written; stop   */
    int *queue, queue_head, queue_tail;
    stream_band *band;
    int next_write;      /* PNG: the next band in file order          */
    int written;         /* bands in the file                         */
    bool writing;        /* a thread writes bands now                 */
    bool stop;           /* no band is queued any more                */
    bool failed;
    int error;           /* errno of the first failure                */
    uint32_t adler;      /* PNG: of the bands written                 */
    pthread_t thread[STREAM_THREADS_MAX];
    int threads;
    int encoded_early;   /* bands encoded before img_stream_finish    */
    bool finishing;
    bool hold;           /* img_stream_hold_signals: hold at the rename */
    double cpu_s;        /* the encoder threads', summed at their end */
    img_module_file *module; /* STREAM_MODULE: the module's writer     */
    char module_err[512];    /* its first message (the one writer's)   */
};

/* ---- the file ------------------------------------------------------------------- */

static void stream_fail(img_stream *s, int error)
{
    if (!s->failed)
        s->error = error ? error : EIO;
    s->failed = true;
}

static void stream_put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

/* A PNG chunk of `len` bytes of data. */
static bool stream_chunk(int fd, const char *type, const unsigned char *data, size_t len)
{
    unsigned char head[8], tail[4];
    stream_put32(head, (uint32_t)len);
    memcpy(head + 4, type, 4);
    uLong crc = crc32(crc32(0, NULL, 0), (const Bytef *)type, 4);
    if (len)
        crc = crc32(crc, data, (uInt)len);
    stream_put32(tail, (uint32_t)crc);
    return file_write_all(fd, head, 8) && (len == 0 || file_write_all(fd, data, len)) &&
           file_write_all(fd, tail, 4);
}

/* The zlib header of csgtrace's level (6 under its run-length strategy,
 * as zlib writes it) and strategy: the compression level's two bits. */
static void stream_zlib_header(int level, unsigned char out[2])
{
    int flevel = level < 0 ? 2 : level <= 1 ? 0 : level <= 5 ? 1 : level == 6 ? 2 : 3;
    unsigned cmf = 0x78, flg = (unsigned)flevel << 6;
    flg += 31 - (cmf * 256 + flg) % 31;
    out[0] = (unsigned char)cmf;
    out[1] = (unsigned char)flg;
}

static bool stream_png_head(img_stream *s)
{
    static const unsigned char signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    unsigned char ihdr[13] = {0}, offs[9] = {0}, zhead[2];
    stream_put32(ihdr, (uint32_t)s->grid.width);
    stream_put32(ihdr + 4, (uint32_t)s->grid.height);
    ihdr[8] = 8; /* bits a sample */
    ihdr[9] = 2; /* RGB */
    stream_zlib_header(s->png_level, zhead);
    return file_write_all(s->file.fd, signature, sizeof signature) &&
           stream_chunk(s->file.fd, "IHDR", ihdr, sizeof ihdr) &&
           stream_chunk(s->file.fd, "oFFs", offs, sizeof offs) && /* (0, 0 pixels: as before) */
           stream_chunk(s->file.fd, "IDAT", zhead, sizeof zhead);
}

static bool stream_png_tail(img_stream *s)
{
    unsigned char adler[4];
    stream_put32(adler, s->adler);
    return stream_chunk(s->file.fd, "IDAT", adler, sizeof adler) &&
           stream_chunk(s->file.fd, "IEND", NULL, 0);
}

static bool stream_placed(const img_stream *s)
{
    return s->kind == STREAM_PPM || s->kind == STREAM_PFM;
}

/* Rows y0 .. y1 - 1 of band b. */
static void stream_rows(const img_stream *s, int b, int *y0, int *y1)
{
    *y0 = b * IMG_STREAM_ROWS;
    *y1 = *y0 + IMG_STREAM_ROWS < s->grid.height ? *y0 + IMG_STREAM_ROWS : s->grid.height;
}

/* The first file row of band b: PPM's rows run top down, PFM's bottom up. */
static off_t stream_band_file_row(const img_stream *s, int b)
{
    int y0, y1;
    stream_rows(s, b, &y0, &y1);
    return s->kind == STREAM_PFM ? (off_t)(s->grid.height - y1) : (off_t)y0;
}

/* The rows of bands b0 .. b1 - 1 handed to the module's writer (they are
 * its next). */
static bool stream_write_module(img_stream *s, int b0, int b1)
{
    int y0, y1, last_y0;
    stream_rows(s, b0, &y0, &y1);
    stream_rows(s, b1 - 1, &last_y0, &y1);
    char err[sizeof s->module_err];
    if (img_module_rows(s->module, y0, y1, s->image + (size_t)y0 * (size_t)s->grid.width * 3, err,
                        sizeof err))
        return true;
    if (!s->module_err[0]) /* (the first failure's: set by the one writer) */
        snprintf(s->module_err, sizeof s->module_err, "%s", err);
    return false;
}

/* Band b's bytes to the file: a placed kind's at its place, by any
 * thread; a PNG's next, by the one writer (stream_write_ready). */
static bool stream_write_band(img_stream *s, int b, const stream_band *band)
{
    if (stream_placed(s)) {
        off_t at = (off_t)s->header + stream_band_file_row(s, b) * (off_t)s->grid.width *
                                          (off_t)s->pixel_bytes;
        for (size_t done = 0; done < band->len;) {
            ssize_t n = pwrite(s->file.fd, band->bytes + done, band->len - done, at + (off_t)done);
            if (n < 0 && errno == EINTR)
                continue;
            if (n <= 0)
                return false;
            done += (size_t)n;
        }
        return true;
    }
    for (size_t at = 0; at < band->len; at += STREAM_IDAT_MAX)
        if (!stream_chunk(s->file.fd, "IDAT", band->bytes + at,
                          band->len - at < STREAM_IDAT_MAX ? band->len - at : STREAM_IDAT_MAX))
            return false;
    return true;
}

/* ---- encoding a band --------------------------------------------------------- */

/* PNG's Paeth predictor. */
static int stream_paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/* Row x filtered with `type` (0 None .. 4 Paeth) against the row above
 * (prev; NULL: none, for None and Sub only) into out[0 .. n] (the type
 * byte first); the sum of the filtered bytes as signed, which libpng's
 * choice among filters minimises. */
static long stream_filter(int type, const unsigned char *x, const unsigned char *prev, size_t n,
                          unsigned char *out)
{
    long sum = 0;
    out[0] = (unsigned char)type;
    for (size_t i = 0; i < n; i++) {
        int a = i >= 3 ? x[i - 3] : 0, b = prev ? prev[i] : 0;
        int c = prev && i >= 3 ? prev[i - 3] : 0;
        int pred = type == 1 ? a : type == 2 ? b : type == 3 ? (a + b) / 2
                   : type == 4 ? stream_paeth(a, b, c) : 0;
        unsigned char v = (unsigned char)(x[i] - pred);
        out[i + 1] = v;
        sum += v < 128 ? v : 256 - v;
    }
    return sum;
}

/* Row x of a band, filtered into out: the first row of a band Sub (no row
 * above it in the band), the others Up; with a level set, the filter of
 * the smallest sum among those that may be used. */
static void stream_png_row(const img_stream *s, const unsigned char *x, const unsigned char *prev,
                           size_t n, unsigned char *out, unsigned char *trial)
{
    if (s->png_level < 0) {
        stream_filter(prev ? 2 : 1, x, prev, n, out);
        return;
    }
    long best = -1;
    for (int type = 0; type <= (prev ? 4 : 1); type++) {
        long sum = stream_filter(type, x, prev, n, trial);
        if (best < 0 || sum < best) {
            best = sum;
            memcpy(out, trial, n + 1);
        }
    }
}

/* PFM's floats: little-endian (its header's scale is negative), whatever
 * the machine's order. */
static void stream_put_float_le(unsigned char *p, float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(u >> (8 * i));
}

/* A PFM band: its rows bottom up, each pixel's linear floats as they are. */
static bool stream_encode_pfm(const img_stream *s, int y0, int y1, stream_band *band)
{
    size_t n = (size_t)s->grid.width * 3, rows = (size_t)(y1 - y0);
    band->len = n * rows * 4;
    band->bytes = malloc(band->len);
    if (!band->bytes)
        return false;
    for (size_t r = 0; r < rows; r++) {
        const float *row = s->image + ((size_t)y1 - 1 - r) * n;
        for (size_t i = 0; i < n; i++)
            stream_put_float_le(band->bytes + (r * n + i) * 4, row[i]);
    }
    return true;
}

/* Band b encoded into *band; false when out of memory. */
static bool stream_encode(img_stream *s, int b, stream_band *band)
{
    if (s->kind == STREAM_MODULE)
        return true; /* (the module encodes the rows as they are written) */
    int y0, y1;
    stream_rows(s, b, &y0, &y1);
    size_t n = (size_t)s->grid.width * 3, rows = (size_t)(y1 - y0);
    if (s->kind == STREAM_PFM)
        return stream_encode_pfm(s, y0, y1, band);
    if (s->kind == STREAM_PPM) {
        band->len = n * rows;
        band->bytes = malloc(band->len);
        if (!band->bytes)
            return false;
        for (size_t r = 0; r < rows; r++)
            pixels_to_rgb8(s->image + ((size_t)y0 + r) * n, n, band->bytes + r * n);
        return true;
    }
    z_stream z;
    memset(&z, 0, sizeof z);
    int level = s->png_level < 0 ? 6 : s->png_level;
    int strategy = s->png_level < 0 ? Z_RLE : Z_DEFAULT_STRATEGY;
    unsigned char *rgb = malloc(2 * n), *filtered = malloc(2 * (n + 1));
    bool ok = rgb && filtered && deflateInit2(&z, level, Z_DEFLATED, -15, 8, strategy) == Z_OK;
    band->raw = rows * (n + 1);
    size_t cap = ok ? deflateBound(&z, band->raw) + 16 : 0;
    band->bytes = ok ? malloc(cap) : NULL;
    ok = ok && band->bytes;
    band->adler = (uint32_t)adler32(0, NULL, 0);
    z.next_out = band->bytes;
    z.avail_out = (uInt)cap;
    for (size_t r = 0; ok && r < rows; r++) {
        unsigned char *x = rgb + (r % 2) * n, *prev = r > 0 ? rgb + ((r + 1) % 2) * n : NULL;
        pixels_to_rgb8(s->image + ((size_t)y0 + r) * n, n, x);
        stream_png_row(s, x, prev, n, filtered, filtered + n + 1);
        band->adler = (uint32_t)adler32(band->adler, filtered, (uInt)(n + 1));
        z.next_in = filtered;
        z.avail_in = (uInt)(n + 1);
        bool last = r + 1 == rows;
        int flush = !last ? Z_NO_FLUSH : b + 1 == s->bands ? Z_FINISH : Z_SYNC_FLUSH;
        int rc = deflate(&z, flush);
        ok = rc == Z_OK || rc == Z_STREAM_END;
    }
    band->len = cap - z.avail_out;
    if (rgb && filtered)
        deflateEnd(&z);
    free(rgb);
    free(filtered);
    return ok;
}

/* ---- the threads ----------------------------------------------------------------- */

/* The run of encoded bands from next_write written, by this thread alone;
 * called and returning with the lock held.  The module is handed every
 * band of the run that is final at once (one call: OpenEXR compresses
 * its chunks of 16 rows in parallel on its threads), a PNG's bands one by
 * one. */
static void stream_write_ready(img_stream *s)
{
    if (s->writing)
        return; /* (the writer will take this band too) */
    s->writing = true;
    while (s->next_write < s->bands && s->band[s->next_write].encoded) {
        int b = s->next_write, end = b + 1;
        while (s->kind == STREAM_MODULE && end < s->bands && s->band[end].encoded)
            end++;
        stream_band band = s->band[b];
        pthread_mutex_unlock(&s->lock);
        bool ok = s->failed || (s->kind == STREAM_MODULE ? stream_write_module(s, b, end)
                                                         : stream_write_band(s, b, &band));
        int error = errno;
        pthread_mutex_lock(&s->lock);
        if (!ok)
            stream_fail(s, error);
        if (s->kind == STREAM_PNG)
            s->adler = (uint32_t)adler32_combine(s->adler, band.adler, (z_off_t)band.raw);
        free(band.bytes);
        s->band[b].bytes = NULL;
        s->written += end - b;
        s->next_write = end;
    }
    s->writing = false;
    pthread_cond_broadcast(&s->cond);
}

static double stream_thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void *stream_encoder(void *arg)
{
    img_stream *s = arg;
    double cpu0 = stream_thread_cpu();
    pthread_mutex_lock(&s->lock);
    for (;;) {
        while (s->queue_head == s->queue_tail && !s->stop)
            pthread_cond_wait(&s->cond, &s->lock);
        if (s->queue_head == s->queue_tail)
            break;
        int b = s->queue[s->queue_head++];
        pthread_mutex_unlock(&s->lock);
        stream_band band = {NULL, 0, 0, 0, false};
        bool ok = stream_encode(s, b, &band);
        int error = ok ? 0 : ENOMEM;
        if (ok && stream_placed(s)) { /* (its place is known: written now) */
            ok = stream_write_band(s, b, &band);
            error = ok ? 0 : errno;
            free(band.bytes);
            band.bytes = NULL;
        }
        pthread_mutex_lock(&s->lock);
        if (!ok)
            stream_fail(s, error);
        s->encoded_early += !s->finishing;
        if (stream_placed(s)) {
            s->written++;
        } else {
            band.encoded = true;
            s->band[b] = band;
            stream_write_ready(s); /* (in file order, from the next one on) */
        }
    }
    s->cpu_s += stream_thread_cpu() - cpu0;
    pthread_mutex_unlock(&s->lock);
    return NULL;
}

/* One more encoder thread (false: none could be made). */
static bool stream_add_thread(img_stream *s)
{
    if (s->threads == STREAM_THREADS_MAX ||
        pthread_create(&s->thread[s->threads], NULL, stream_encoder, s) != 0)
        return false;
    s->threads++;
    return true;
}

/* ---- the calls of stream.h --------------------------------------------------- */

/* The bands b0 .. b1 over the rows of tile row ty. */
static void stream_bands_of(const img_stream *s, int ty, int *b0, int *b1)
{
    int y0 = ty * s->grid.tile;
    int y1 = y0 + s->grid.tile < s->grid.height ? y0 + s->grid.tile : s->grid.height;
    *b0 = y0 / IMG_STREAM_ROWS;
    *b1 = (y1 - 1) / IMG_STREAM_ROWS;
}

/* The stream's kind for `path` under the image settings. */
static enum stream_kind stream_kind_of(const char *path)
{
    switch (img_format_of(path)) {
    case IMG_FORMAT_PNG:
        return STREAM_PNG;
    case IMG_FORMAT_PPM:
        return STREAM_PPM;
    case IMG_FORMAT_PFM:
        return STREAM_PFM;
    case IMG_FORMAT_MODULE:
        break;
    }
    return STREAM_MODULE;
}

static void stream_free(img_stream *s)
{
    file_temp_discard(&s->file); /* (nothing once committed) */
    for (int b = 0; s->band && b < s->bands; b++)
        free(s->band[b].bytes);
    pthread_mutex_destroy(&s->lock);
    pthread_cond_destroy(&s->cond);
    free(s->band);
    free(s->queue);
    free(s->tiles_left);
    free(s->path);
    free(s);
}

/* The file beside the output, unnamed where it can be (file_temp), its
 * head written. */
static bool stream_create(img_stream *s, char *err, size_t err_size)
{
    if (!file_temp_open(&s->file, s->path, file_default_mode())) {
        snprintf(err, err_size, "csgtrace: error: cannot write %s: %s", s->path,
                 strerror(errno));
        return false;
    }
    signals_temporary(s->file.name); /* (a signal now removes it; NULL: unnamed) */
    char head[64];
    int len = s->kind == STREAM_PFM
                  ? snprintf(head, sizeof head, "PF\n%d %d\n-1.0\n", s->grid.width, s->grid.height)
                  : snprintf(head, sizeof head, "P6\n%d %d\n255\n", s->grid.width, s->grid.height);
    s->header = len;
    s->pixel_bytes = s->kind == STREAM_PFM ? 3 * 4 : 3;
    bool ok = s->kind == STREAM_PNG ? stream_png_head(s)
                                    : file_write_all(s->file.fd, head, (size_t)len);
    if (!ok) {
        char why[160];
        snprintf(err, err_size, "csgtrace: error: cannot write %s: %s", s->path,
                 file_strerror(errno, why, sizeof why));
        signals_temporary(NULL);
        file_temp_discard(&s->file);
    }
    return ok;
}

img_stream *img_stream_open(const char *path, const float *image, const tile_grid *grid,
                            char *err, size_t err_size)
{
    img_stream *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, err_size, "csgtrace: error: %s: out of memory", path);
        return NULL;
    }
    s->file.fd = -1;
    s->image = image;
    s->grid = *grid;
    s->columns = tile_columns(grid);
    s->bands = (grid->height + IMG_STREAM_ROWS - 1) / IMG_STREAM_ROWS;
    s->png_level = img_settings_now().png_level;
    s->adler = (uint32_t)adler32(0, NULL, 0);
    s->kind = stream_kind_of(path);
    s->path = strdup(path);
    s->tiles_left = malloc((size_t)s->bands * sizeof *s->tiles_left);
    s->queue = malloc((size_t)s->bands * sizeof *s->queue);
    s->band = calloc((size_t)s->bands, sizeof *s->band);
    pthread_mutex_init(&s->lock, NULL);
    pthread_cond_init(&s->cond, NULL);
    if (!s->path || !s->tiles_left || !s->queue || !s->band) {
        snprintf(err, err_size, "csgtrace: error: %s: out of memory", path);
        stream_free(s);
        return NULL;
    }
    for (int b = 0; b < s->bands; b++)
        s->tiles_left[b] = 0;
    for (int ty = 0; ty * grid->tile < grid->height; ty++) { /* each tile row's bands */
        int b0, b1;
        stream_bands_of(s, ty, &b0, &b1);
        for (int b = b0; b <= b1; b++)
            s->tiles_left[b] += s->columns;
    }
    if (s->kind == STREAM_MODULE)
        s->module = img_module_open(path, grid->width, grid->height, err, err_size);
    if (s->kind == STREAM_MODULE ? !s->module : !stream_create(s, err, err_size)) {
        stream_free(s);
        return NULL;
    }
    return s;
}

void img_stream_start(img_stream *s)
{
    if (s && s->threads == 0)
        stream_add_thread(s); /* (none: img_stream_finish's threads do it all) */
}

void img_stream_hold_signals(img_stream *s)
{
    s->hold = true;
}

void img_stream_tile(img_stream *s, int tile)
{
    if (!s)
        return;
    int b0, b1;
    stream_bands_of(s, tile / s->columns, &b0, &b1);
    for (int b = b0; b <= b1; b++) {
        if (--s->tiles_left[b] != 0)
            continue;
        pthread_mutex_lock(&s->lock);
        s->queue[s->queue_tail++] = b;
        pthread_cond_signal(&s->cond);
        pthread_mutex_unlock(&s->lock);
    }
}

/* The CPUs this process may run on (at least 1). */
static int stream_cpus(void)
{
    cpu_set_t set;
    int n = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 1;
    return n > 0 ? n : 1;
}

/* The file of a PNG, PPM or PFM stream completed (every band written)
 * and renamed over the output; false with the message in err (nothing
 * left under the output's name). */
static bool stream_file_end(img_stream *s, char *err, size_t err_size)
{
    int error = s->failed ? s->error : 0;
    bool ok = !s->failed && s->written == s->bands;
    if (ok && s->kind == STREAM_PNG && !stream_png_tail(s))
        error = errno;
    if (!error && !file_temp_name(&s->file))
        error = errno;
    signals_temporary(s->file.name); /* (named for the moment before its rename) */
    if (!error && s->hold)
        signals_hold(); /* (from the rename on, a signal waits for the caller's release) */
    if (!error && !file_temp_commit(&s->file))
        error = errno;
    ok = !error;
    if (!ok) {
        char why[160];
        snprintf(err, err_size, "csgtrace: error: cannot write %s: %s", s->path,
                 file_strerror(error, why, sizeof why));
        file_temp_discard(&s->file);
    }
    signals_temporary(NULL);
    return ok;
}

/* The same for the module's file: closed and renamed, or removed. */
static bool stream_module_end(img_stream *s, char *err, size_t err_size)
{
    img_module_file *f = s->module;
    s->module = NULL;
    if (!s->failed && s->written == s->bands)
        return img_module_close(f, s->hold, err, err_size);
    char why[160];
    if (s->module_err[0])
        snprintf(err, err_size, "%s", s->module_err);
    else
        snprintf(err, err_size, "csgtrace: error: cannot write %s: %s", s->path,
                 file_strerror(s->error, why, sizeof why));
    img_module_abort(f);
    return false;
}

bool img_stream_finish(img_stream *s, int threads, img_stream_report *r, char *err,
                       size_t err_size)
{
    memset(r, 0, sizeof *r);
    pthread_mutex_lock(&s->lock);
    s->finishing = true;
    int left = s->queue_tail - s->queue_head;
    pthread_mutex_unlock(&s->lock);
    if (threads <= 0)
        threads = stream_cpus();
    if (s->kind == STREAM_MODULE)
        threads = 1; /* (its rows go to one writer in order; the module spreads their work) */
    while (s->threads < threads && s->threads < left && stream_add_thread(s))
        continue; /* (more: the rest encode in parallel) */
    pthread_mutex_lock(&s->lock);
    s->stop = true;
    pthread_cond_broadcast(&s->cond);
    pthread_mutex_unlock(&s->lock);
    if (s->threads == 0)
        stream_encoder(s); /* (no thread could be made: here) */
    for (int t = 0; t < s->threads; t++)
        pthread_join(s->thread[t], NULL);
    bool ok = s->kind == STREAM_MODULE ? stream_module_end(s, err, err_size)
                                       : stream_file_end(s, err, err_size);
    r->bands = s->bands;
    r->bands_early = s->encoded_early;
    r->cpu_s = s->cpu_s;
    stream_free(s);
    return ok;
}

void img_stream_abort(img_stream *s)
{
    if (!s)
        return;
    pthread_mutex_lock(&s->lock);
    s->stop = true;
    s->queue_head = s->queue_tail; /* (nothing more to encode) */
    pthread_cond_broadcast(&s->cond);
    pthread_mutex_unlock(&s->lock);
    for (int t = 0; t < s->threads; t++)
        pthread_join(s->thread[t], NULL);
    if (s->kind == STREAM_MODULE) {
        img_module_abort(s->module);
        s->module = NULL;
    } else {
        file_temp_discard(&s->file);
        signals_temporary(NULL);
    }
    stream_free(s);
}
