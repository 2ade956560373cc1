/*
 * render.c — the render driver: one render_request, any mode, any number
 * of ranks (render.h).
 *
 * Steps, on the process that owns the image (rank 0, or the only one):
 *   0. claim the outputs: every output path checked, the output's lock
 *      taken (output/claim.h), before any file is made;
 *   1. parse the scene and flatten it in the requested precision (an image
 *      of more than TILES_MAX tiles refused); share the status and the
 *      blob with the workers (master.c);
 *   2. hetero: the primary pass (pass/pass.h), its device opened while the
 *      scene was read, begun now or once the program is built;
 *   3. the tile phase, through the workers (master_run_tiles) or, without
 *      workers, in this process: the scheduler (schedule.h) is fed the
 *      tiles whose rows the pass made final, and the fill's whole tiles
 *      meanwhile (feed.h); homo and serial queue every tile at once;
 *   4. the image (img_write_rgb), the stats JSON, the tile log, one
 *      summary line;
 *   5. STOP with the final status to every worker (master_end).
 * Serial mode is step 3 in-process over all tiles.
 *
 * Timing: marks on one clock (render_marks) cut the render into
 * consecutive phases, so the phases of the stats add up to wall_s
 * exactly (stats.h): setup | OpenCL set-up + compile | the pass alone |
 * pass and tiles at once (pipelined) | tiles alone | write.
 *
 * Invariants: every mode produces the same pixels, because every item goes
 * through the one tile_run_rect (workers/tile.h), on a worker or here, from
 * the same record (hetero: the OpenCL record; the others: the engine's
 * trace_primary), and degenerate tiles get exactly what shade gives a
 * missed primary ray (engine->miss_rgb).  Every failure prints one message
 * here (workers never print) and goes through the one cleanup path; no
 * image is written unless every tile succeeded.
 */
#include "render.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../comm/mpi_link.h"
#include "../comm/protocol.h"
#include "../csg/flatten.h"
#include "../csg/load.h"
#include "../csg/precision.h"
#include "../workers/tile.h"
#include "../workers/worker.h"
#include "feed.h"
#include "master.h"
#include "memory.h"
#include "output/claim.h"
#include "output/file_atomic.h"
#include "output/image.h"
#include "output/journal.h"
#include "output/stream.h"
#include "output/user_files.h"
#include "pass/cl_cache.h"
#include "pass/pass.h"
#include "progress.h"
#include "schedule.h"
#include "signals.h"
#include "stats.h"
#include "store.h"

/* Everything one render owns; freed in render_free. */
typedef struct {
    claim *claim;          /* the output's lock (NULL: no output file)   */
    csg_blob blob;
    float *image;          /* width * height * 3                        */
    stats_worker *workers; /* one per worker (or one for this process)  */
    sched sched;           /* the work items                             */
    pass *pass;            /* hetero: the primary pass (render_run's)    */
    feed feed;             /* what the scheduler is fed                  */
    journal *journal;      /* the finished tiles, for --resume (NULL:
                              no output file)                           */
    img_stream *stream;    /* the image file, written as its bands are
                              final (NULL: no output file, or given to
                              render_write)                             */
    link_idle idle;        /* the master's wait; the pass wakes it       */
    bool idle_ready;
    memory_prefault prefault; /* the image's pages, faulted in meanwhile */
    size_t prefault_bytes; /* the image's bytes to fault in (0: none)    */
    bool helpers;          /* the journal's writer, the prefault, the store
                              thread started (render_start_helpers)      */
    int store_threads;     /* threads to store the workers' 8-bit results
                              (--store-threads, auto: store_threads_auto;
                              0: none wanted)                           */
    store *store;          /* they (store.h; NULL: none)                 */
    csg_pager pager;       /* --scene-memory without workers: rank 0's
                              own tiles read the scene through it       */
    bool paged_local;
} render_state;

/* The marks that cut a render into its phases (stats.h). */
typedef struct {
    double start;     /* render_job began                                */
    double loaded;    /* scene parsed, flattened, shared                 */
    double cl_ready;  /* OpenCL opened (hetero), else = loaded           */
    double tiles_end; /* the last result in (or the tile phase gave up)  */
    double written;   /* the image written                               */
} render_marks;

static void render_free(render_state *rs)
{
    pass_free(rs->pass); /* (before the wake-up it calls goes) */
    if (rs->idle_ready)
        link_idle_free(&rs->idle);
    csg_blob_free(&rs->blob);
    memory_prefault_join(&rs->prefault);
    store_stop(rs->store);
    img_stream_abort(rs->stream); /* (a render that failed: no file) */
    free(rs->image);
    free(rs->workers);
    sched_free(&rs->sched);
}

static const char *render_mode_name(enum render_mode m)
{
    return m == MODE_SERIAL ? "serial" : m == MODE_HOMO ? "homo" : "hetero";
}

static enum sched_policy render_policy(const render_request *req)
{
    if (req->schedule >= 0 && req->schedule < SCHED_POLICIES)
        return (enum sched_policy)req->schedule;
    if (req->mode == MODE_HETERO)
        return SCHED_COST;
    /* paged workers: neighbouring tiles on one worker find their pages
     * cached (bench/PAGING.md: 64 simulated workers, 69.5 -> 77.9 %) */
    return req->mode == MODE_HOMO && req->scene_memory_mb > 0 ? SCHED_REGION : SCHED_RASTER;
}

/* The engine of the request's precision; auto decides from the scene
 * (csg/precision.h) and leaves its reason in st->precision_why. */
static const engine *render_engine(const render_request *req, const csg_scene *s,
                                   render_stats *st)
{
    if (req->precision == PREC_AUTO) {
        bool need = csg_needs_double(s, st->width, st->height, st->precision_why,
                                     sizeof st->precision_why);
        return need ? &engine_double : &engine_float;
    }
    return req->precision == PREC_DOUBLE ? &engine_double : &engine_float;
}

/* What the includes of the scene are checked against: no output may
 * overwrite one (the scene itself is checked by the command line). */
typedef struct {
    const render_request *req;
    csg_diag clash; /* the first output that names an include */
    char **paths;   /* every include read (malloc'd): no file the scene
                       writes may replace one (render_write_user_files) */
    int count, cap;
} render_includes;

/* Keeps the include's path; an out-of-memory is a clash (the render stops). */
static void render_keep_include(render_includes *ri, const char *path)
{
    if (ri->count == ri->cap) {
        int cap = ri->cap ? 2 * ri->cap : 16;
        char **grown = realloc(ri->paths, (size_t)cap * sizeof *grown);
        if (!grown) {
            csg_error_plain(&ri->clash, "out of memory for the names of the includes");
            return;
        }
        ri->paths = grown;
        ri->cap = cap;
    }
    if ((ri->paths[ri->count] = strdup(path)) != NULL)
        ri->count++;
    else
        csg_error_plain(&ri->clash, "out of memory for the names of the includes");
}

static void render_includes_free(render_includes *ri)
{
    for (int i = 0; i < ri->count; i++)
        free(ri->paths[i]);
    free(ri->paths);
}

/* The files the scene wrote (#write), beside the output once the scene
 * is read (none without an output): 0, or 2 / 1 with d filled. */
static int render_write_user_files(const render_request *req, const csg_scene *s,
                                   const render_includes *ri, csg_diag *d)
{
    if (!req->out_path || s->written_count == 0)
        return EXIT_OK;
    char journal_path[PATH_MAX + sizeof JOURNAL_SUFFIX];
    char lock_path[PATH_MAX + sizeof CLAIM_LOCK_SUFFIX];
    journal_name(req->out_path, journal_path, sizeof journal_path);
    claim_lock_name(req->out_path, lock_path, sizeof lock_path);
    const char **taken = malloc((size_t)(ri->count + 6) * sizeof *taken);
    if (!taken) {
        csg_error_plain(d, "out of memory for the scene's files");
        return EXIT_FAILURE_RUN;
    }
    const char *outputs[] = {req->scene_path, req->out_path, req->stats_path, req->tile_log_path,
                             journal_path, lock_path};
    memcpy(taken, outputs, sizeof outputs);
    for (int i = 0; i < ri->count; i++)
        taken[6 + i] = ri->paths[i];
    int status = user_files_write(s, req->out_path, taken, ri->count + 6, d);
    free(taken);
    return status;
}

static void render_check_include(void *arg, const char *path)
{
    render_includes *ri = arg;
    const render_request *req = ri->req;
    render_keep_include(ri, path);
    const char *names[] = {"the output (-o)", "the stats (--stats)", "the tile log (--tile-log)",
                           "the output's journal", "the output's lock"};
    char journal_path[PATH_MAX + sizeof JOURNAL_SUFFIX] = "";
    char lock_path[PATH_MAX + sizeof CLAIM_LOCK_SUFFIX] = "";
    if (req->out_path) {
        journal_name(req->out_path, journal_path, sizeof journal_path);
        claim_lock_name(req->out_path, lock_path, sizeof lock_path);
    }
    const char *paths[] = {req->out_path, req->stats_path, req->tile_log_path,
                           req->out_path ? journal_path : NULL, req->out_path ? lock_path : NULL};
    for (int i = 0; i < 5 && !ri->clash.failed; i++)
        if (paths[i] && file_same(paths[i], path))
            csg_error_plain(&ri->clash, "%s is '%s', a file the scene includes: refusing to "
                            "overwrite it", names[i], path);
}

/* Every output checked (claim_check_output), then the lock of the image's,
 * before any file of the render is made (and before the scene is read: a
 * second render of the output stops at once); 0 or 1 with d filled. */
static int render_claim(const render_request *req, claim **c, csg_diag *d)
{
    const char *what[] = {"the output (-o)", "the stats (--stats)", "the tile log (--tile-log)",
                          "the output's journal"};
    char journal_path[PATH_MAX + sizeof JOURNAL_SUFFIX] = "";
    if (req->out_path)
        journal_name(req->out_path, journal_path, sizeof journal_path);
    const char *paths[] = {req->out_path, req->stats_path, req->tile_log_path,
                           req->out_path ? journal_path : NULL};
    *c = NULL;
    for (int i = 0; i < 4; i++)
        if (paths[i] && !claim_check_output(paths[i], what[i], d))
            return EXIT_FAILURE_RUN;
    *c = req->out_path ? claim_take(req->out_path, d) : NULL;
    return req->out_path && !*c ? EXIT_FAILURE_RUN : EXIT_OK;
}

/* The image cut into at most TILES_MAX tiles (comm/tiles.h: past it the
 * counts overflow int); false with d filled (a bad request: exit 2). */
static bool render_tiles_fit(const render_stats *st, csg_diag *d)
{
    uint64_t tiles = tiles_wide(st->width, st->height, st->tile);
    if (tiles <= TILES_MAX)
        return true;
    csg_error_plain(d, "a %dx%d image in tiles of %dx%d pixels is %llu tiles, more than a render "
                    "may have (%d): use a larger --tile", st->width, st->height, st->tile, st->tile,
                    (unsigned long long)tiles, TILES_MAX);
    return false;
}

/* Step 1: 0, or 2 (bad scene) / 1 (other failure) with d filled. */
static int render_load(const render_request *req, csg_blob *blob, render_stats *st, csg_diag *d)
{
    csg_flatten_opts o = {0, 0, req->depth, req->threshold, req->spp, req->max_rays};
    csg_scene s;
    int status = 0;
    csg_parse_options po;
    if (req->parse)
        po = *req->parse;
    else
        csg_parse_options_default(&po);
    render_includes ri = {req, {{0}, 0}, NULL, 0, 0};
    po.on_include = render_check_include;
    po.on_include_arg = &ri;
    /* What the scene sees; a POV-Ray scene has no size of its own */
    po.image_width = req->width > 0 ? req->width : CSG_DEFAULT_WIDTH;
    po.image_height = req->height > 0 ? req->height : CSG_DEFAULT_HEIGHT;
    csg_scene_init(&s);
    bool ok = csg_load_file(req->scene_path, &po, &s, d);
    if (ok && ri.clash.failed) {
        *d = ri.clash;
        csg_scene_free(&s);
        render_includes_free(&ri);
        return EXIT_BAD_INPUT;
    }
    status = ok ? render_write_user_files(req, &s, &ri, d) : 0;
    render_includes_free(&ri);
    if (status != EXIT_OK) {
        csg_scene_free(&s);
        return status;
    }
    if (ok) { /* the size asked for, else the scene's (NFF's resolution) */
        csg_image_size(&s, req->width, req->height, &st->width, &st->height);
        st->pixels = (uint64_t)st->width * (uint64_t)st->height;
        o.width = st->width;
        o.height = st->height;
    }
    if (ok && !render_tiles_fit(st, d)) {
        csg_scene_free(&s);
        return EXIT_BAD_INPUT;
    }
    if (!ok || !render_engine(req, &s, st)->flatten(&s, &o, blob, d)) {
        if (!d->failed)
            csg_error_plain(d, "%s: cannot load the scene", req->scene_path);
        status = EXIT_BAD_INPUT;
    } else if (!csg_blob_valid(blob->bytes, blob->size)) {
        csg_error_plain(d, "internal error: the flattened scene is not valid");
        status = EXIT_FAILURE_RUN;
    } else {
        st->precision = csg_blob_hdr(blob->bytes)->real_size == 8 ? "double" : "float";
    }
    csg_scene_free(&s);
    return status;
}

/* ---- step 2: the pass's configuration --------------------------------------- */

/* The environment's settings of the request (none when it has none). */
static const csg_config *render_env(const render_request *req)
{
    static const csg_config none;
    return req->env ? req->env : &none;
}

/* The pass's configuration from the request and the environment; false
 * with d filled when a setting is invalid (reported before any tile:
 * the device may never be opened, a bad setting is still an error). */
static bool render_pass_config(const render_request *req, pass_config *cfg, csg_diag *d)
{
    const csg_config *env = render_env(req);
    bool fill_used = !req->no_fill && render_policy(req) != SCHED_STATIC; /* (a static
                                                         schedule has no fill) */
    memset(cfg, 0, sizeof *cfg);
    cfg->device = req->cl_device ? req->cl_device : env->cl_device;
    cfg->kernel = (enum ocl_kernel)req->cl_kernel;
    cfg->fill = !req->no_fill;
    cfg->shadows = req->simd_shadows;
    cfg->automatic = pass_is_automatic(fill_used, req->pass_always, cfg->device, req->cl_keep);
    cfg->keep = req->cl_keep;
    if (!cl_cache_dir(env->cl_cache, env->xdg_cache_home, env->home, cfg->cache_dir,
                      sizeof cfg->cache_dir))
        cfg->cache_dir[0] = '\0';
    return pass_settings(env, cfg, d);
}

/* ---- step 3: the tile phase ------------------------------------------------------ */

/* Step 3 without workers: every item in this process, through the very
 * tile_run_rect a worker calls, as the pass makes tiles ready (or the
 * items left when every worker was lost); counted in `self`. */
static int render_local_tiles(master_job *job, stats_worker *self, csg_diag *d)
{
    tile_runner tr;
    bool ready = tile_runner_init(&tr, job->local_blob ? job->local_blob : job->blob,
                                  job->grid.tile);
    size_t answers_at = tile_records_bytes(&job->grid, job->grid.pixels_max);
    void *records = job->t ? malloc(answers_at + tile_answers_bytes(&job->grid,
                                                                    job->grid.pixels_max))
                           : NULL;
    float *rgb = malloc(job->grid.pixels_max * 3 * sizeof *rgb);
    int status = EXIT_FAILURE_RUN;
    if (!ready || !rgb || (job->t && !records)) {
        csg_error_plain(d, "out of memory for tiles of %zu pixels", job->grid.pixels_max);
        goto fail;
    }
    self->rank = 0;
    for (;;) {
        if (!job->sched->closed && job->feed(job, false, d) < 0)
            goto fail;
        double now = stats_clock();
        int item = sched_next(job->sched, 0, now);
        if (item < 0 && job->fill && (item = job->fill(job, now, d)) == -2)
            goto fail;
        if (item < 0) {
            if (job->sched->closed) /* finished (one worker gets every item) */
                break;
            if (job->feed(job, true, d) < 0) /* the next slice */
                goto fail;
            continue;
        }
        if (job->t_first == 0)
            job->t_first = now;
        tile_rect r = job->sched->items[item].rect;
        int work = master_work(job, item);
        tile_result res;
        tile_timer timer;
        void *answers = NULL;
        if (work != PROTO_WORK_RENDER)
            tile_pack_records(&job->grid, job->t, job->surf, r, records);
        if (work == PROTO_WORK_SHADE_ANSWERED) {
            answers = (char *)records + answers_at;
            tile_pack_answers(&job->grid, job->known, job->lit, r, answers);
        }
        tile_time_start(&timer);
        tile_run_rect_answered(&tr, r, work != PROTO_WORK_RENDER ? records : NULL, answers, rgb,
                               &res);
        tile_time_stop(&timer, &res);
        tile_store_rgb(job->image, job->grid.width, r, rgb);
        master_job_count(job, self, 0, item, &res, stats_clock());
    }
    status = EXIT_OK;
fail:
    tile_runner_free(&tr);
    free(records);
    free(rgb);
    return status;
}

/* The master's helper threads: the journal's writer and, with workers,
 * the image's page faulting (serial: the faults are a sliver of its
 * tiles' work) and the store thread of the 8-bit results (store.h; until
 * it runs, the loop stores them).  In hetero with the fill only once the
 * pass is quiet (pass_quiet): a thread created while PoCL loads waits for
 * the dynamic loader's lock (up to ~25 ms: the first tiles went out ~8 ms
 * later on small frames). */
static void render_start_helpers(render_state *rs, master_job *job)
{
    if (rs->helpers)
        return;
    rs->helpers = true;
    journal_start_writer(rs->journal);
    if (rs->prefault_bytes > 0)
        memory_prefault_start(&rs->prefault, rs->image, rs->prefault_bytes);
    if (rs->store_threads > 0)
        rs->store = store_start(rs->image, job->grid.width, tile_count(&job->grid),
                                rs->store_threads);
    job->store = rs->store;
    img_stream_start(rs->stream);
}

/* master_job.feed: the helpers started once they may be, and the tiles
 * ready (feed.h). */
static int render_feed(master_job *job, bool wait, csg_diag *d)
{
    render_state *rs = job->feed_arg;
    if (!rs->helpers && pass_quiet(rs->pass))
        render_start_helpers(rs, job);
    return feed_tiles(&rs->feed, job, wait, d);
}

/* master_job.fill: the fill's next tile (feed.h). */
static int render_fill(master_job *job, double now, csg_diag *d)
{
    render_state *rs = job->feed_arg;
    return feed_fill(&rs->feed, job, now, d);
}

/* d filled with the image writer's message err about `out`: its own
 * ("csgtrace: error: ..."), the module's ("OUT: ..."), or anything else
 * (named after the output). */
static void render_write_error(const char *out, const char *err, csg_diag *d)
{
    size_t named = strlen(out);
    if (strstr(err, "error:"))
        snprintf(d->message, sizeof d->message, "%s", err);
    else if (strncmp(err, out, named) == 0 && err[named] == ':')
        csg_error_plain(d, "%s", err);
    else
        csg_error_plain(d, "%s: %s", out, err[0] ? err : "cannot write the image");
    d->failed = 1;
}

/* Step 4: the image file; 0 or 1 with d filled. */
static int render_write(const render_request *req, render_state *rs, render_stats *st,
                        csg_diag *d)
{
    char err[512] = "";
    if (!rs->stream)
        return EXIT_OK;
    /* A signal during the encoding of the tail or the module's write
     * removes the temporary file and stops at once; from the rename on it
     * waits until the stats are written too (render_job releases it). */
    img_stream_hold_signals(rs->stream);
    img_stream_report report;
    bool ok = img_stream_finish(rs->stream, 0, &report, err, sizeof err);
    rs->stream = NULL;
    st->write_bands = report.bands;
    st->write_bands_early = report.bands_early;
    st->write_cpu_s = report.cpu_s;
    if (ok)
        return EXIT_OK;
    render_write_error(req->out_path, err, d);
    return EXIT_FAILURE_RUN;
}

static void render_stats_init(const render_request *req, int ranks, render_stats *st)
{
    memset(st, 0, sizeof *st);
    st->mode = render_mode_name(req->mode);
    st->schedule = sched_policy_name(render_policy(req));
    st->cl_open = req->mode == MODE_HETERO ? "start" : "none";
    st->precision = req->precision == PREC_DOUBLE ? "double" : "float";
    st->width = req->width;
    st->height = req->height;
    st->tile = req->tile > 0 ? req->tile : RENDER_DEFAULT_TILE;
    st->ranks = ranks;
    st->spp = req->spp > 0 ? req->spp : 1;
    st->max_rays = req->max_rays > 0 ? req->max_rays : st->spp * CSG_RAYS_PER_SAMPLE;
    st->pixels = (uint64_t)req->width * (uint64_t)req->height;
    st->estimate_spearman = (double)NAN;
}

/* The phases (consecutive marks, stats.h) and the tile-phase figures. */
static void render_account(const render_state *rs, const master_job *job,
                           const render_marks *mk, const pass_report *pr, render_stats *st)
{
    bool began = pr->start > 0;
    double pass_end = began && rs->feed.closed_at > 0 ? rs->feed.closed_at : mk->tiles_end;
    double first = job->t_first > 0 ? job->t_first : mk->tiles_end;
    /* With the fill the OpenCL set-up ends when the pass begins, the tile
     * phase may have begun before: the marks stay in order */
    double cl_ready = pr->built_meanwhile ? (began ? pr->start : mk->loaded) : mk->cl_ready;
    double t3 = began ? (first < pass_end ? first : pass_end) : cl_ready;
    t3 = t3 > cl_ready ? t3 : cl_ready;
    double t4 = began ? pass_end : cl_ready;
    st->setup_s = mk->loaded - mk->start;
    /* (no pass: the build only overlapped the tiles, no phase of its own) */
    st->compile_s = !pr->built_meanwhile || began ? pr->tm.compile_s : 0.0;
    st->cl_setup_s = cl_ready - mk->loaded - st->compile_s;
    st->primary_s = t3 - cl_ready;
    st->pipelined_s = t4 - t3;
    st->secondary_s = mk->tiles_end - t4;
    st->write_s = mk->written - mk->tiles_end;
    st->wall_s = mk->written - mk->start;
    st->pass_s = began ? pass_end - pr->start : 0.0;
    st->slices = pr->tm.slices;
    st->pass_kernel_s = began ? pr->tm.device_kernel_s : 0.0;
    st->pass_copy_s = began ? pr->tm.device_copy_s : 0.0;
    st->pass_device_s = began ? pr->tm.device_span_s : 0.0;
    st->cl_records_in_place = pr->tm.records_in_place;
    stats_tile_figures(st, &rs->sched, job->t_first, job->t_last, job->busy_s);
    st->tiles_resumed = journal_tiles_resumed(rs->journal);
    st->tiles_culled = rs->feed.tiles_culled;
}

/* A link to another node slower than this, measured at start, is slow:
 * --compress auto compresses the 8-bit results and --hit-records auto
 * sends no records over it.  It is about what rank 0's store thread takes
 * in when it decompresses and stores (1.8 + 1.1 ns a byte, bench/
 * SCALE.md, *Results on a slow link*): below it the results wait on the
 * wire, and compressed ones arrive ten times faster; above it the thread
 * would be the slower, and the workers' 1 % is spent for nothing.  The
 * records, 8 bytes a pixel where a compressed result is 0.3, cost rank
 * 0's link more there than the primary rays cost the workers (gigabit
 * Ethernet: 125 MB/s, slow; InfiniBand: not). */
#define RENDER_SLOW_LINK_BPS 300e6

/* Do the ranks span nodes behind a slow link? */
static bool render_link_slow(void)
{
    double bps = link_between_nodes_bps();
    return link_spans_nodes() && bps > 0 && bps < RENDER_SLOW_LINK_BPS;
}

/* What the workers answer in: an 8-bit file's bytes (compressed as
 * --compress asks), or floats. */
static int render_result_pixels(const render_request *req)
{
    int format = pixels_format_for(req->out_path);
    bool compress = req->compress == COMPRESS_ON ||
                    (req->compress == COMPRESS_AUTO && render_link_slow());
    return format == PIXELS_RGB8 && compress ? PIXELS_RGB8Z : format;
}

/* Does hetero send the workers no records (--hit-records)?  Never with
 * --simd shadows, whose answers travel with them. */
static bool render_retraces(const render_request *req)
{
    return req->hit_records == RECORDS_RETRACE ||
           (req->hit_records == RECORDS_AUTO && !req->simd_shadows && render_link_slow());
}

/* Everything the tile phase needs, the pass started; 0 or the failure. */
static int render_prepare(const render_request *req, master_session *ms, render_state *rs,
                          render_stats *st, render_marks *mk, master_job *job, csg_diag *d)
{
    tile_grid grid = tile_grid_of(rs->blob.bytes, st->tile);
    bool use_workers = ms->workers > 0 && req->mode != MODE_SERIAL;
    bool hetero = req->mode == MODE_HETERO, fill = hetero && !req->no_fill;
    st->tiles_total = tile_count(&grid);
    st->worker_count = use_workers ? ms->workers : 1;
    st->in_flight = use_workers ? PROTO_IN_FLIGHT : 1;
    st->relays = use_workers ? ms->relays : 0;
    pass_config cfg;
    if (hetero && !render_pass_config(req, &cfg, d)) /* (before any tile: the device
                                                      may never be opened) */
        return EXIT_FAILURE_RUN;
    if (hetero && pass_open(rs->pass, rs->blob.bytes, d) != EXIT_OK) /* (fill: meanwhile) */
        return EXIT_FAILURE_RUN;
    mk->cl_ready = stats_clock();
    rs->image = memory_pages_alloc(st->pixels * 3 * sizeof *rs->image, true);
    rs->workers = calloc((size_t)st->worker_count + 1, sizeof *rs->workers); /* (+ the
                                                   master, should every worker be lost) */
    rs->idle_ready = use_workers && master_idle_init(&rs->idle);
    if (!rs->image || !rs->workers || (use_workers && !rs->idle_ready) ||
        !sched_init(&rs->sched, render_policy(req), use_workers ? ms->children : 1, st->in_flight,
                    st->tiles_total, hetero ? pass_estimate : NULL, rs->pass)) {
        csg_error_plain(d, "out of memory for a %dx%d image", st->width, st->height);
        return EXIT_FAILURE_RUN;
    }
    st->pieces = use_workers ? sched_pieces_auto(req->pieces, ms->workers - ms->relays,
                                                 st->tiles_total, st->tile,
                                                 ms->pixels == PIXELS_RGB8Z)
                             : 1;
    if (!sched_cut(&rs->sched, st->pieces)) {
        csg_error_plain(d, "out of memory for a %dx%d image", st->width, st->height);
        return EXIT_FAILURE_RUN;
    }
    if (use_workers)
        st->relay_depth = master_relay_floor(ms, &rs->sched);
    if (req->out_path) {
        int status = journal_open(req->out_path, rs->blob.bytes, &grid, req->resume, rs->image,
                                  JOURNAL_AFTER_S, &rs->journal, d);
        if (status != EXIT_OK)
            return status;
    }
    if (req->out_path) { /* (the image written as its bands are final) */
        char err[512] = "";
        rs->stream = img_stream_open(req->out_path, rs->image, &grid, err, sizeof err);
        if (!rs->stream) {
            render_write_error(req->out_path, err, d);
            return EXIT_FAILURE_RUN;
        }
    }
    feed_init(&rs->feed, &rs->sched, rs->journal, rs->stream, rs->pass, rs->image,
              rs->blob.bytes);
    rs->prefault_bytes = use_workers ? st->pixels * 3 * sizeof *rs->image : 0;
    if (use_workers && pixels_format_for(req->out_path) == PIXELS_RGB8)
        rs->store_threads = req->store_threads > 0 ? req->store_threads
                                                   : store_threads_auto(ms->workers - ms->relays);
    job->journal = rs->journal;
    job->stream = rs->stream;
    job->blob = rs->blob.bytes;
    job->grid = grid;
    job->sched = &rs->sched;
    job->feed = render_feed;
    job->feed_arg = rs;
    job->idle = rs->idle_ready ? &rs->idle : NULL;
    job->image = rs->image;
    job->workers = rs->workers;
    if (!fill) /* (hetero with the fill: once the pass is quiet, render_feed) */
        render_start_helpers(rs, job);
    if (!hetero)
        return render_feed(job, false, d) < 0 ? EXIT_FAILURE_RUN : EXIT_OK; /* every tile */
    if (fill) {
        sched_fill_enable(&rs->sched);
        job->fill = render_fill;
    }
    int status = pass_prepare(rs->pass, &grid, use_workers ? &rs->idle : NULL, d);
    job->t = pass_t(rs->pass);
    job->retrace = render_retraces(req);
    job->surf = pass_surf(rs->pass);
    job->known = pass_known(rs->pass);
    job->lit = pass_lit(rs->pass);
    return status;
}

/* Step 3 through the workers; when every worker was lost, the rest here
 * (the master's share then shows as rank 0 in the stats). */
static int render_by_workers(master_session *ms, master_job *job, render_stats *st,
                             csg_diag *d)
{
    if (!master_run_tiles(ms, job, d))
        return EXIT_FAILURE_RUN;
    if (sched_finished(job->sched) && job->sched->closed)
        return EXIT_OK;
    fprintf(stderr, "csgtrace: every worker was lost: the master renders the rest itself\n");
    return render_local_tiles(job, &job->workers[st->worker_count++], d);
}

/* Steps 2 to 4, once the scene is shared; 0 or the failure status. */
static int render_image(const render_request *req, master_session *ms, render_state *rs,
                        render_stats *st, render_marks *mk, csg_diag *d)
{
    progress_bar bar;
    master_job job;
    memset(&job, 0, sizeof job);
    mk->cl_ready = mk->loaded;
    int status = render_prepare(req, ms, rs, st, mk, &job, d);
    job.local_blob = rs->paged_local ? rs->pager.base : NULL;
    pass_report pr;
    memset(&pr, 0, sizeof pr);
    if (status != EXIT_OK)
        return status;
    job.progress = &bar;
    /* (the bar counts the tiles of this run: not those resumed) */
    progress_begin(&bar, st->tiles_total - journal_tiles_resumed(rs->journal),
                   (int)req->progress);
    double cpu0 = stats_thread_cpu();
    if (ms->workers > 0 && req->mode != MODE_SERIAL)
        status = render_by_workers(ms, &job, st, d);
    else
        status = render_local_tiles(&job, &rs->workers[0], d);
    progress_end(&bar);
    mk->tiles_end = stats_clock();
    st->master_cpu_s = stats_thread_cpu() - cpu0;
    st->master_results_s =
        job.results_s > job.results_past_s ? job.results_s - job.results_past_s : 0.0;
    st->store_threads = store_threads(rs->store);
    st->store_cpu_s = store_cpu_s(rs->store);
    st->cull_s = rs->feed.cull_s;
    if (rs->pass) {
        status = pass_end(rs->pass, status, &pr, d);
        st->pass_work_s = pr.work_s;
        st->guess_cpu_s = pr.guess_cpu_s;
        if (pr.cl_open)
            st->cl_open = pr.cl_open;
    }
    if (pr.traced) {
        snprintf(st->device, sizeof st->device, "%s", pr.tm.device_name);
        snprintf(st->cl_program, sizeof st->cl_program, "%s", pr.program);
        /* (the fill's tiles: counted from their results) */
        job.pixels_hit += pass_hits(rs->pass, sched_fill_front(&rs->sched));
        job.rays.primary = st->pixels * (uint64_t)job.grid.spp;
    }
    st->pixels_hit = job.pixels_hit;
    st->rays = job.rays;
    st->paging = job.paging;
    st->workers = rs->workers;
    pass_drop_records(rs->pass); /* (the writer's peak does not hold them) */
    job.t = NULL;
    job.surf = NULL;
    job.known = NULL;
    job.lit = NULL;
    if (status == EXIT_OK)
        status = render_write(req, rs, st, d);
    mk->written = stats_clock();
    render_account(rs, &job, mk, &pr, st);
    return status;
}

/* The one message of a failed render. */
static void render_report(const csg_diag *d)
{
    fprintf(stderr, "%s\n", d->message[0] ? d->message : "csgtrace: error: render failed");
    fflush(stderr);
}

/* The stats JSON and the tile log, asked for; 0 or 1 with d filled. */
static int render_outputs(const render_request *req, const render_state *rs,
                          const render_stats *st, double t0, csg_diag *d)
{
    char err[1024];
    if ((req->stats_path && !stats_write_json(req->stats_path, st, err, sizeof err)) ||
        (req->tile_log_path &&
         !stats_write_tile_log(req->tile_log_path, &rs->sched, t0, err, sizeof err))) {
        snprintf(d->message, sizeof d->message, "%s", err);
        d->failed = 1;
        return EXIT_FAILURE_RUN;
    }
    return EXIT_OK;
}

/* One line when pixels met their ray budget: the image is not what an
 * unbounded trace would give there. */
static void render_warn_budget(const render_stats *st)
{
    if (st->rays.over_budget == 0)
        return;
    fprintf(stderr,
            "csgtrace: warning: %llu pixels met their ray budget (%d reflected and refracted "
            "rays a pixel); their deepest rays were not traced (--max-rays-per-pixel)\n",
            (unsigned long long)st->rays.over_budget, st->max_rays);
}

/* Refuses, with the figures, a render whose peak memory this process
 * cannot have (before any of it is allocated); the estimate into the
 * stats. */
static int render_memory_check(const render_request *req, const csg_blob *blob,
                               render_stats *st, csg_diag *d)
{
    uint64_t avail;
    tile_grid grid = tile_grid_of(blob->bytes, st->tile);
    int slice_rows = req->mode == MODE_HETERO ? pass_slice_rows(&grid) : 0;
    /* (--simd shadows: a record carries its shadow answers too, two more
     * words beside its t: counted with it) */
    size_t record_extra = req->mode == MODE_HETERO && req->simd_shadows ? 2 * sizeof(uint32_t) : 0;
    render_memory need = render_memory_need(st->width, st->height, st->tile, st->spp,
                                            csg_blob_hdr(blob->bytes)->real_size + record_extra,
                                            slice_rows, req->out_path);
    st->memory_estimate = need.total;
    if (!memory_available(&avail) || need.total <= avail)
        return EXIT_OK;
    char total[32], image[32], writer[32], records[32], tiles[32], left[32], why[96] = "";
    if (need.records)
        snprintf(why, sizeof why, ", the hit records of the OpenCL pass %s",
                 memory_format(need.records + need.device, records, sizeof records));
    csg_error_plain(d,
                    "a %dx%d render in %s mode needs about %s of memory (the image %s, its "
                    "encoding %s%s, the tiles' bookkeeping %s); this process may allocate %s",
                    st->width, st->height, render_mode_name(req->mode),
                    memory_format(need.total, total, sizeof total),
                    memory_format(need.image, image, sizeof image),
                    memory_format(need.writer, writer, sizeof writer), why,
                    memory_format(need.tiles, tiles, sizeof tiles),
                    memory_format(avail, left, sizeof left));
    return EXIT_FAILURE_RUN;
}

/* pager_fetch without workers: the pages from the whole scene, here (its
 * bytes where they are now: under mpirun a serial render's scene moves
 * into the node's shared copy once the workers are told). */
static bool render_fetch_local(void *arg, const int32_t *pages, int n, unsigned char *out,
                               size_t bytes)
{
    const render_state *rs = arg;
    size_t at = 0;
    for (int i = 0; i < n; i++) {
        const pager_page *pg = &rs->pager.plan.pages[pages[i]];
        if (pg->bytes > bytes - at)
            return false;
        pager_pack_page(rs->blob.bytes, pg, out + at);
        at += pg->bytes;
    }
    return at == bytes;
}

/* pager_fetch_into without workers: the ranges copied from rank 0's own
 * blob straight into place (what a worker's one-sided read does). */
static bool render_get_local(void *arg, const pager_range *ranges, int n, unsigned char *base)
{
    const render_state *rs = arg;
    for (int k = 0; k < n; k++) {
        if (ranges[k].off > rs->blob.size || ranges[k].len > rs->blob.size - ranges[k].off)
            return false;
        memcpy(base + ranges[k].off, rs->blob.bytes + ranges[k].off, ranges[k].len);
    }
    return true;
}

/* --scene-memory: the page plan (rank 0 validated the blob when it loaded
 * it), checked against the budget; without workers, rank 0's own pager
 * over it.  0, or the failure with d filled. */
static int render_plan_pages(const render_request *req, master_session *ms, render_state *rs,
                             render_stats *st, csg_diag *d)
{
    uint64_t budget = (uint64_t)(req->scene_memory_mb * 1e6);
    bool local = ms->workers == 0 || req->mode == MODE_SERIAL;
    const char *why = NULL;
    if (!local && req->relays > 0) {
        csg_error_plain(d, "--scene-memory does not apply with --relays (the relays would "
                           "need the whole scene)");
        return EXIT_BAD_INPUT;
    }
    uint64_t page = req->page_kb > 0 ? (uint64_t)req->page_kb << 10 : 0;
    ms->page_fetch = req->page_fetch;
    int status = master_plan_pages(ms, rs->blob.bytes, rs->blob.size, budget, page,
                                   req->page_policy, req->page_prefetch,
                                   local ? PAGER_HOME_MASTER : req->page_home, d);
    if (status != EXIT_OK)
        return status;
    st->scene_memory = budget;
    st->page_bytes = ms->plan.page_bytes;
    st->page_count = ms->plan.page_count;
    st->resident_bytes = ms->plan.resident_bytes;
    st->page_policy = req->page_policy == PAGER_FIFO ? "fifo" : "lru";
    st->page_prefetch = ms->page_prefetch;
    st->page_homes = ms->page_homes;
    st->page_fetch = local && req->page_fetch == PAGER_FETCH_GET ? "get" : "ask";
    if (!local)
        return EXIT_OK;
    size_t size = 0;
    void *packed = pager_pack_resident(rs->blob.bytes, &ms->plan, &size);
    bool opened = packed && pager_open(&rs->pager, packed, size, budget,
                                       (enum pager_policy)req->page_policy, render_fetch_local,
                                       rs, &why);
    free(packed);
    if (!opened) {
        csg_error_plain(d, "--scene-memory: %s", packed ? why : "out of memory");
        return EXIT_FAILURE_RUN;
    }
    rs->paged_local = true;
    if (req->page_fetch == PAGER_FETCH_GET)
        rs->pager.fetch_into = render_get_local;
    rs->pager.prefetch = req->page_prefetch != PAGER_PREFETCH_OFF;
    rs->pager.prefetch_shadows = req->page_prefetch == PAGER_PREFETCH_SHADOWS;
    if (!pager_trace_open(&rs->pager, render_env(req)->page_trace, 0)) {
        csg_error_plain(d, "--scene-memory: cannot write the page trace ($CSGTRACE_PAGE_TRACE)");
        return EXIT_FAILURE_RUN;
    }
    ms->scene_memory = 0; /* (no workers to tell) */
    return EXIT_OK;
}

/* The whole render on the process that owns the image; `p`: hetero's
 * pass, its device being opened (NULL otherwise), taken over. */
static int render_job(const render_request *req, int ranks, pass *p)
{
    /* The image module (when the format needs it) before the clock: loading
     * it is no render time, and a missing one stops the job before any work. */
    char img_err[512];
    bool img_ready = !req->out_path || img_can_write(req->out_path, img_err, sizeof img_err);
    signals_install();
    render_marks mk = {stats_clock(), 0, 0, 0, 0};
    render_state rs;
    render_stats st;
    master_session ms;
    csg_diag d;
    memset(&rs, 0, sizeof rs);
    memset(&d, 0, sizeof d);
    render_stats_init(req, ranks, &st);
    rs.pass = p;
    master_begin(&ms, ranks);

    int status = render_claim(req, &rs.claim, &d);
    if (status == EXIT_OK)
        status = render_load(req, &rs.blob, &st, &d);
    if (status == EXIT_OK)
        status = render_memory_check(req, &rs.blob, &st, &d);
    if (status == EXIT_OK && !img_ready) {
        bool named = strncmp(img_err, req->out_path, strlen(req->out_path)) == 0;
        csg_error_plain(&d, named ? "%s%s" : "%s: %s", named ? "" : req->out_path, img_err);
        status = EXIT_FAILURE_RUN;
    }
    bool reported = status != EXIT_OK;
    if (reported) /* before the workers learn it: they exit at once */
        render_report(&d);
    if (status == EXIT_OK && req->relays > 0 && ms.workers < 2 * req->relays) {
        csg_error_plain(&d, "--relays %d needs at least %d worker ranks (the relays and a "
                            "worker for each): this job has %d (mpirun -np %d or more)",
                        req->relays, 2 * req->relays, ms.workers, 2 * req->relays + 1);
        status = EXIT_BAD_INPUT;
        reported = true;
        render_report(&d);
    }
    if (status == EXIT_OK && req->scene_memory_mb > 0) {
        status = render_plan_pages(req, &ms, &rs, &st, &d);
        if (status != EXIT_OK) {
            reported = true;
            render_report(&d);
        }
    }
    ms.batch = req->batch;
    ms.relays = req->mode == MODE_SERIAL ? 0 : req->relays;
    ms.pixels = render_result_pixels(req); /* 8-bit files: bytes back */
    master_share_scene(&ms, status, st.tile, &rs.blob);
    mk.loaded = stats_clock();
    st.blob_bytes = rs.blob.size;
    if (status == EXIT_OK)
        status = render_image(req, &ms, &rs, &st, &mk, &d);
    st.batch = ms.batch;
    st.result_pixels = ms.workers > 0 ? pixels_format_name(ms.pixels) : "none";
    st.hit_records = req->mode != MODE_HETERO ? "none" : render_retraces(req) ? "retrace" : "send";
    st.link_mbps = link_between_nodes_bps() / 1e6;
    st.tile_messages = ms.tile_messages;
    st.answers_early = ms.answers_early;
    st.bytes_sent = ms.bytes_sent;
    st.bytes_received = ms.bytes_received;
    st.workers_lost = ms.workers_lost;
    st.scene_shared_ranks = ms.scene_shared + (ms.scene.shared ? 1 : 0);
    st.page_asks = ms.page_asks;
    if (ms.page_window)
        st.page_fetch = "get";
    st.page_bytes_served = ms.page_bytes_served;
    st.scene_private_ranks = ms.workers + 1 - st.scene_shared_ranks;

    if (status == EXIT_OK) {
        signals_hold();
        status = render_outputs(req, &rs, &st, mk.start, &d);
        if (status != EXIT_OK && req->out_path) /* a failed render leaves no image */
            unlink(req->out_path);
    }
    const char *written[] = {req->out_path, req->stats_path, req->tile_log_path};
    signals_release(written, status == EXIT_OK ? 3 : 0);
    if (status == EXIT_OK && req->out_path)
        signals_finished(); /* (a later signal: "its files are kept") */
    journal_close(rs.journal, status == EXIT_OK); /* (kept, unless finished) */
    rs.journal = NULL;
    claim_release(rs.claim); /* (the journal's fate settled: another render may go on) */
    rs.claim = NULL;
    if (status == EXIT_OK) {
        if (req->stats_out) {
            *req->stats_out = st;
            req->stats_out->workers = NULL;
            req->stats_out->worker_count = 0;
        }
        if (req->image_out) {
            *req->image_out = rs.image;
            rs.image = NULL;
        }
        if (!req->stats_out) {
            render_warn_budget(&st);
            stats_print_summary(stdout, &st);
        }
        fflush(stdout);
    } else if (!reported) {
        render_report(&d);
    }
    master_end(&ms, status);
    if (rs.paged_local)
        pager_close(&rs.pager);
    pass_free(rs.pass); /* (the device may read the scene in place: ended before it goes) */
    rs.pass = NULL;
    master_release_scene(&ms, &rs.blob);
    render_free(&rs);
    return status;
}

int render_run(const render_request *req)
{
    int rank = 0, size = 1;
    /* (Not during MPI_Init: Open MPI patches memory functions then, and a
     * thread inside PoCL's set-up at that moment is not safe) */
    if (link_launched_by_mpirun() && !link_start(&rank, &size)) {
        fprintf(stderr, "csgtrace: error: MPI cannot start\n");
        return EXIT_FAILURE_RUN;
    }
    if (rank != 0)
        return worker_run(rank, render_env(req)->worker_bind, render_env(req)->page_trace);
    pass *p = NULL;
    pass_config cfg;
    csg_diag ignored = {{0}, 0}; /* (a bad setting: reported by render_prepare) */
    if (req->mode == MODE_HETERO) {
        render_pass_config(req, &cfg, &ignored);
        p = pass_start(&cfg);
    }
    int status = render_job(req, size, p);
    link_exit_status(status); /* (made mpirun's under --enable-recovery) */
    return status;
}

int render_rank(void)
{
    int rank = 0, size = 1;
    if (link_launched_by_mpirun() && !link_start(&rank, &size))
        return -1;
    return rank;
}
