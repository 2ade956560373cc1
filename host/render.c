/*
 * render.c — the render driver: one render_request, any mode, any number
 * of ranks (render.h).
 *
 * Steps, on the process that owns the image (rank 0, or the only one):
 *   1. parse the scene and flatten it in the requested precision; share the
 *      status and the blob with the workers (master.c);
 *   2. hetero: open OpenCL (or reuse the caller's context) and start the
 *      primary pass in the background, in slices of a few tile rows
 *      (RENDER_SLICE_MIN_RECORDS), giving a hit record per pixel and a hit
 *      count per tile;
 *   3. the tile phase, through the workers (master_run_tiles) or, without
 *      workers, in this process: the scheduler (schedule.h) is fed the
 *      tiles of every completed slice as the pass goes on (render_feed):
 *      tiles without hits are filled here with the background and never
 *      sent, the others are queued with their estimated cost
 *      (estimate.h); homo and serial queue every tile at once;
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
 * missed primary ray (engine->miss_rgb).  A tile reaches the scheduler
 * only once the slices over all its rows are complete.  The pass is ended
 * (ocl_pass_end) before its arrays or the wake-up it calls are freed.
 * Every failure prints one message here (workers never print) and goes
 * through the one cleanup path; no image is written unless every tile
 * succeeded.
 */
#include "render.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <semaphore.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../csg/flatten.h"
#include "../csg/load.h"
#include "../csg/precision.h"
#include "../workers/tile.h"
#include "../workers/worker.h"
#include "estimate.h"
#include "file_atomic.h"
#include "image.h"
#include "journal.h"
#include "link.h"
#include "master.h"
#include "memory.h"
#include "ocl.h"
#include "progress.h"
#include "protocol.h"
#include "schedule.h"
#include "signals.h"
#include "stats.h"
#include "store.h"
#include "test_env.h"

/* Records a slice of the pipelined pass holds at least: one tile row, or
 * more when a tile row is smaller (each slice costs two launches). */
#define RENDER_SLICE_MIN_RECORDS 2048

/* Hetero: OpenCL's device, context and queue do not depend on the scene,
 * so a thread opens them while the scene is read, flattened and sent
 * (ocl_open_device); the program, which does, is built after
 * (render_open_cl).  On a small frame the set-up was a tenth of the
 * render, paid before the pass could start.
 *
 * With the fill the same thread goes on to build the program once the
 * master has the scene (`go`, with `build` set), while the workers render:
 * no second thread is created, because pthread_create waits for the
 * dynamic loader's lock, which the device's opening holds while it loads
 * PoCL's drivers and LLVM (~30 ms here: the master sent its first tile
 * only then).  Without the fill (or when the render ends before it needs
 * the program) the master posts `go` with no build and joins it.
 *
 * --pass auto (the default, with the fill): once the scene is loaded the
 * thread first guesses the work of the frame's primary rays from a sparse
 * sample of its pixels (render_guess_work, while the workers render the
 * fill's first tiles), and the device is opened only when the guess is at
 * least RENDER_PASS_PAYS_S; else the fill renders every tile and the
 * device is never opened.  Primary rays are what the pass takes off the
 * workers, and the device costs a fixed ~0.08 s here (cl_setup_s
 * 0.067-0.078, compile_s 0.008-0.013) while the pass, on the same cores,
 * saves about half of what it takes: it pays from ~0.16 s of primary
 * rays.  A guess of the whole frame's work (the rule until 2026-11-27,
 * from 0.6 s) opened the device on frames of many secondary rays, where
 * it does not pay (gears2, gears4, rings4: guessed 0.59-0.85 s, 1.07-1.09x
 * homo's frame when opened, their primary rays 11-18 % of the rays), and
 * more often on a slower day (bench/SPD-notes.md).  Where the device is the CPU
 * the workers already fill (PoCL, as here), its opening alone costs ~26 ms
 * of CPU (loading LLVM) and the program ~10 ms more: more than the pass
 * saves on a frame of 0.05-0.2 s (bench/SPD.md).  Opening it while the
 * master reads the scene instead slowed the reading by more than the
 * opening's own CPU (tetra8: 0.42 -> 0.47 s, with the workers napping);
 * guessing from the fill's first tiles failed (they are the image's
 * bottom rows: 0.05 s guessed for the teapots' 0.25-0.32 s). */
#define RENDER_PASS_PAYS_S 0.16 /* (guessed seconds of primary rays: gears
                                   0.06-0.10, rings4 0.09-0.12, mount6_t6
                                   0.12-0.19, rings7 0.14-0.20, rings4_t1
                                   0.16-0.32) */
#define RENDER_GUESS_BLOCK 4   /* the guess traces blocks of 4 x 4 pixels, */
#define RENDER_GUESS_STRIDE 64 /* one in every 64 x 64                    */

/* A guess block's edge from `at`: RENDER_GUESS_BLOCK, or less where the
 * image or the tile ends (a rectangle lies inside one tile). */
static int render_guess_edge(int at, int size, int tile)
{
    int edge = RENDER_GUESS_BLOCK;
    edge = tile - at % tile < edge ? tile - at % tile : edge;
    return size - at < edge ? size - at : edge;
}

/* What the guess has traced: pixels, thread CPU seconds, rays. */
typedef struct {
    double pixels, cpu;
    uint64_t primary, rays;
} render_guess_sample;

/* The blocks of one stage of the guess, traced: stage 0 every other one
 * across and down (1/1024 of the image), stage 1 the others; added to
 * *sample.  False when *stop came first. */
static bool render_guess_stage(tile_runner *tr, int tile, int stage, const atomic_bool *stop,
                               render_guess_sample *sample)
{
    int w = tr->grid.width, h = tr->grid.height, step = RENDER_GUESS_STRIDE;
    int x0 = w > step / 4 ? step / 4 : w / 2, y0 = h > step / 4 ? step / 4 : h / 2;
    float rgb[RENDER_GUESS_BLOCK * RENDER_GUESS_BLOCK * 3];
    double cpu0 = stats_thread_cpu();
    for (int y = y0, iy = 0; y < h; y += step, iy++) {
        if (atomic_load(stop))
            return false;
        for (int x = x0, ix = 0; x < w; x += step, ix++) {
            if ((ix % 2 == 0 && iy % 2 == 0) != (stage == 0))
                continue;
            tile_rect r = {x, y, render_guess_edge(x, w, tile), render_guess_edge(y, h, tile)};
            tile_result res;
            tile_run_rect(tr, r, NULL, rgb, &res);
            sample->pixels += (double)r.width * (double)r.height;
            sample->primary += res.rays.primary;
            sample->rays += ray_counts_total(&res.rays);
        }
    }
    sample->cpu += stats_thread_cpu() - cpu0;
    return true;
}

/* The CPU seconds of the frame's primary rays the sample says: its
 * seconds a pixel over the whole image, times the primary rays' share of
 * its rays (0 when it traced none). */
static double render_guess_primary(const render_guess_sample *sample, double area)
{
    if (!(sample->pixels > 0) || sample->rays == 0)
        return 0;
    return sample->cpu * (area / sample->pixels) * ((double)sample->primary / (double)sample->rays);
}

/* The CPU seconds a frame's primary rays will take on the workers,
 * guessed from blocks of RENDER_GUESS_BLOCK x RENDER_GUESS_BLOCK pixels,
 * one in every RENDER_GUESS_STRIDE x RENDER_GUESS_STRIDE (1/256 of the
 * image), traced and shaded on this thread (the tiles' seconds, weighed by
 * the primary rays' share of the rays: render_guess_primary); 0 when out
 * of memory.  A small rectangle
 * costs more a pixel than a tile (its culling and set-up are shared by
 * fewer rays): on the SPD scenes the guess was 1.1-1.9x the tiles' CPU
 * with blocks of 4 x 4, 1.9-7.4x with single pixels.  A quarter of the
 * blocks first: a guess from them under 2/3 of `pays`, or at least 1.5
 * times it, is the answer; the rest (three times the work: up to 2.6 ms a
 * frame, all of it hetero's own) only refines a guess near `pays`, where
 * the pass about breaks even.  (The whole guess was 0.63-1.10x the
 * quarter's on 25 SPD files, 1.33-1.53x on rings7; 3 runs each.)  It stops
 * (0) once *stop holds: a render that ends first does not wait for it. */
static double render_guess_work(const void *blob, int tile, double pays, const atomic_bool *stop)
{
    tile_runner tr;
    if (!tile_runner_init(&tr, blob, tile))
        return 0;
    double area = (double)tr.grid.width * (double)tr.grid.height;
    render_guess_sample sample = {0, 0, 0, 0};
    bool done = render_guess_stage(&tr, tile, 0, stop, &sample);
    double quarter = render_guess_primary(&sample, area);
    if (done && quarter >= pays * 2 / 3 && quarter < pays * 1.5)
        done = render_guess_stage(&tr, tile, 1, stop, &sample);
    tile_runner_free(&tr);
    return done ? render_guess_primary(&sample, area) : 0;
}

static long render_test_env(const char *name);

/* The guessed primary-ray work from which the pass pays: RENDER_PASS_PAYS_S (tests:
 * CSGTRACE_TEST_PASS_PAYS_MS). */
static double render_pass_pays_s(void)
{
    double pays = render_test_env("CSGTRACE_TEST_PASS_PAYS_MS") * 1e-3;
    return pays > 0 ? pays : RENDER_PASS_PAYS_S;
}

/* Why (and whether) the device was opened: the stats' cl_open. */
enum render_cl_open { CL_OPEN_NONE, CL_OPEN_START, CL_OPEN_WORK, CL_OPEN_NEVER };

static const char *render_cl_open_name(int why)
{
    static const char *const names[] = {"never", "start", "work", "never"};
    return names[why];
}

struct render_cl_build;
typedef struct {
    pthread_t thread;
    bool started;          /* the thread runs, or ran and is not joined */
    const char *device;
    ocl_ctx *ctx;          /* its result (NULL: failed, d says why)     */
    ocl_timing tm;
    csg_diag d;
    sem_t open;            /* posted once `why` is set by the master     */
    atomic_int why;        /* enum render_cl_open: set once              */
    atomic_bool opening;   /* the thread is inside ocl_open_device       */
    const void *guess_blob; /* --pass auto: the scene to guess the work of
                              (set before `open` is first posted)        */
    int guess_tile;
    double work_s;         /* the guess (render_guess_work) and its...    */
    double guess_cpu_s;    /* ...thread CPU seconds, once...              */
    atomic_bool guessed;   /* ...this is set                             */
    atomic_bool ending;    /* the render is over: the guess stops        */
    sem_t go;              /* posted once, when `build` is decided      */
    struct render_cl_build *build; /* the program to build next (NULL: none) */
} render_cl_early;

static void *render_cl_build_run(void *arg);

/* The device wanted for `why` (CL_OPEN_NEVER: not at all), unless it was
 * said already. */
static void render_cl_early_want(render_cl_early *e, int why)
{
    int none = CL_OPEN_NONE;
    if (e && e->started && atomic_compare_exchange_strong(&e->why, &none, why))
        sem_post(&e->open);
}

/* The scene is loaded: the thread is to guess its work (--pass auto). */
static void render_cl_early_guess(render_cl_early *e, const void *blob, int tile)
{
    if (!e || !e->started)
        return;
    e->guess_blob = blob;
    e->guess_tile = tile;
    sem_post(&e->open);
}

/* The thread's guess of the work (render_cl_early_guess); false: none yet. */
static bool render_cl_early_guessed(render_cl_early *e, double *work_s)
{
    if (!e || !atomic_load(&e->guessed))
        return false;
    *work_s = e->work_s;
    return true;
}

/* The CPU seconds the thread's guess took (0: none finished). */
static double render_cl_early_guess_cpu(render_cl_early *e)
{
    return e && atomic_load(&e->guessed) ? e->guess_cpu_s : 0;
}

static void *render_cl_early_run(void *arg)
{
    render_cl_early *e = arg;
    while (sem_wait(&e->open) != 0 && errno == EINTR)
        continue;
    if (atomic_load(&e->why) == CL_OPEN_NONE && e->guess_blob) { /* --pass auto */
        double cpu0 = stats_thread_cpu();
        e->work_s = render_guess_work(e->guess_blob, e->guess_tile, render_pass_pays_s(),
                                      &e->ending);
        e->guess_cpu_s = stats_thread_cpu() - cpu0;
        atomic_store(&e->guessed, true);
        while (sem_wait(&e->open) != 0 && errno == EINTR) /* the word: WORK or NEVER */
            continue;
    }
    if (atomic_load(&e->why) != CL_OPEN_NEVER) {
        atomic_store(&e->opening, true);
        ocl_open_device(e->device, &e->ctx, &e->tm, &e->d);
        atomic_store(&e->opening, false);
    }
    while (sem_wait(&e->go) != 0 && errno == EINTR)
        continue;
    if (e->build)
        render_cl_build_run(e->build);
    return NULL;
}

static enum sched_policy render_policy(const render_request *req)
{
    if (req->schedule >= 0 && req->schedule < SCHED_POLICIES)
        return (enum sched_policy)req->schedule;
    return req->mode == MODE_HETERO ? SCHED_COST : SCHED_RASTER;
}

/* The OpenCL device asked for: --cl-device, else $CSGTRACE_CL_DEVICE
 * (NULL: the default one). */
static const char *render_cl_device(const render_request *req)
{
    return req->cl_device ? req->cl_device : getenv("CSGTRACE_CL_DEVICE");
}

/* Does --pass auto apply?  Hetero with the fill (which the static
 * schedule has not), no --pass always, no device named (--cl-device,
 * $CSGTRACE_CL_DEVICE: the user asked for that one, and a name that
 * matches none is an error whatever the frame), and no context kept
 * across renders (opened once for all of them). */
static bool render_pass_auto(const render_request *req)
{
    const char *named = render_cl_device(req);
    return req->mode == MODE_HETERO && !req->no_fill && render_policy(req) != SCHED_STATIC &&
           !req->pass_always && !req->cl_keep && !(named && *named);
}

static void render_cl_early_start(render_cl_early *e, const render_request *req)
{
    if (req->mode != MODE_HETERO || req->cl_keep)
        return; /* (a kept context is the caller's) */
    e->device = render_cl_device(req);
    bool wait_for_word = render_pass_auto(req); /* (else: opened at once) */
    atomic_init(&e->why, wait_for_word ? CL_OPEN_NONE : CL_OPEN_START);
    atomic_init(&e->opening, false);
    atomic_init(&e->guessed, false);
    atomic_init(&e->ending, false);
    if (sem_init(&e->go, 0, 0) != 0)
        return;
    if (sem_init(&e->open, 0, wait_for_word ? 0 : 1) != 0) {
        sem_destroy(&e->go);
        return;
    }
    e->started = pthread_create(&e->thread, NULL, render_cl_early_run, e) == 0;
    if (!e->started) {
        sem_destroy(&e->go);
        sem_destroy(&e->open);
    }
}

/* The thread's context (NULL, d filled: it failed), taken over; on the
 * thread itself, or once it is joined. */
static ocl_ctx *render_cl_early_result(render_cl_early *e, ocl_timing *tm, csg_diag *d)
{
    *tm = e->tm;
    if (!e->ctx)
        *d = e->d;
    ocl_ctx *c = e->ctx;
    e->ctx = NULL;
    return c;
}

/* The thread joined (it was started, and told to build or not). */
static void render_cl_early_join(render_cl_early *e)
{
    pthread_join(e->thread, NULL);
    sem_destroy(&e->go);
    sem_destroy(&e->open);
    e->started = false;
}

/* The thread's context once it is done, told to build nothing (NULL, d
 * filled: it failed). */
static ocl_ctx *render_cl_early_take(render_cl_early *e, ocl_timing *tm, csg_diag *d)
{
    atomic_store(&e->ending, true);
    render_cl_early_want(e, CL_OPEN_NEVER); /* (not opened yet: never needed) */
    e->build = NULL;
    sem_post(&e->go);
    render_cl_early_join(e);
    return render_cl_early_result(e, tm, d);
}

/* Hetero with the fill: the program is built on the device thread's
 * context (render_open_cl), by that thread (or by a new one when there is
 * none: a kept context), while the workers already render fill tiles; the
 * feed begins the pass once it is done. */
typedef struct render_cl_build {
    pthread_t thread;
    bool begun;            /* render_cl_build_start was called           */
    bool started;          /* the thread runs, or ran and is not joined */
    bool joined;           /* and its result taken                      */
    bool on_early;         /* the thread is the device thread (early)    */
    atomic_bool done;      /* the thread has its result                 */
    bool ok;
    const render_request *req;
    struct render_state *rs;
    link_idle *wake;       /* woken when done (NULL: nobody naps)        */
    csg_diag d;
} render_cl_build;

/* The thread joined (if it runs) and the context it opened closed,
 * unless taken. */
static void render_cl_early_drop(render_cl_early *e)
{
    ocl_timing ignored;
    csg_diag none;
    /* (joined already: a build on the thread that failed before taking
     * the context left it there) */
    ocl_close(e->started ? render_cl_early_take(e, &ignored, &none)
                         : render_cl_early_result(e, &ignored, &none));
}

/* Everything one render owns; freed in render_free. */
typedef struct render_state {
    csg_blob blob;
    float *image;          /* width * height * 3                        */
    void *t;               /* hetero: the OpenCL records                */
    uint32_t *surf;
    uint32_t *tile_hits;   /* hetero: hits per tile                      */
    stats_worker *workers; /* one per worker (or one for this process)  */
    sched sched;           /* the work items                             */
    estimator est;         /* hetero: the items' estimated costs         */
    ocl_ctx *ctx;          /* hetero: OpenCL, owned unless req->cl_keep  */
    bool own_ctx;
    ocl_pass *pass;        /* hetero: the pass, until ended              */
    ocl_timing tm;
    render_cl_early *early; /* hetero: the context opened meanwhile
                              (render_run's: started before MPI_Init) */
    render_cl_build build; /* hetero with the fill: the program, meanwhile */
    const render_request *req;
    bool pass_auto;        /* --pass auto applies (render_pass_auto)      */
    bool pass_waits;       /* and undecided: the fill renders until
                              render_pass_decide has rank 0's guess     */
    bool pass_failed;      /* and the device could not be had: the fill
                              renders every tile (render_pass_give_up)  */
    double pass_work_s;    /* the guess of the frame's work (0: none)    */
    int tiles_culled;      /* fill tiles proven degenerate (render_culled) */
    int32_t cull_met;      /* the object the last fill tile's check met
                              (engine->rect_misses; -1: none)          */
    double cull_s;         /* the master's seconds in those checks       */
    journal *journal;      /* the finished tiles, for --resume (NULL:
                              no output file)                           */
    link_idle idle;        /* the master's wait; the pass wakes it       */
    bool idle_ready;
    bool wake_master;      /* the pass's slices wake the master's naps   */
    int fill_max;          /* tests: the fill claims at most this (0: no limit) */
    int tiles_offered;     /* tiles handed to the scheduler, from the top
                              (the fill's start below them: schedule.h) */
    float bg[3];           /* what a degenerate tile is filled with      */
    double pass_start, pass_end; /* stats_clock(); pass_end 0: not over  */
    memory_prefault prefault; /* the image's pages, faulted in meanwhile */
    size_t prefault_bytes; /* the image's bytes to fault in (0: none)    */
    bool helpers;          /* the journal's writer, the prefault, the store
                              thread started (render_start_helpers)      */
    int store_threads;     /* threads to store the workers' 8-bit results
                              (--store-threads; 0: none wanted)         */
    store *store;          /* they (store.h; NULL: none)                 */
} render_state;

/* The marks that cut a render into its phases (stats.h). */
typedef struct {
    double start;     /* render_job began                                */
    double loaded;    /* scene parsed, flattened, shared                 */
    double cl_ready;  /* OpenCL opened (hetero), else = loaded           */
    double tiles_end; /* the last result in (or the tile phase gave up)  */
    double written;   /* the image written                               */
} render_marks;

static void render_cl_build_join(render_state *rs);

static void render_free(render_state *rs)
{
    render_cl_build_join(rs); /* (it may still be building: its context) */
    if (rs->pass) { /* before its arrays and its wake-up go */
        csg_diag ignored = {{0}, 0};
        ocl_pass_end(rs->pass, NULL, &ignored);
    }
    if (rs->own_ctx)
        ocl_close(rs->ctx);
    if (rs->early) /* a render that failed before it needed it */
        render_cl_early_drop(rs->early);
    if (rs->idle_ready)
        link_idle_free(&rs->idle);
    csg_blob_free(&rs->blob);
    memory_prefault_join(&rs->prefault);
    store_stop(rs->store);
    free(rs->image);
    free(rs->t);
    free(rs->surf);
    free(rs->tile_hits);
    free(rs->workers);
    sched_free(&rs->sched);
    estimator_free(&rs->est);
}

static const char *render_mode_name(enum render_mode m)
{
    return m == MODE_SERIAL ? "serial" : m == MODE_HOMO ? "homo" : "hetero";
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
} render_includes;

static void render_check_include(void *arg, const char *path)
{
    render_includes *ri = arg;
    const render_request *req = ri->req;
    const char *names[] = {"the output (-o)", "the stats (--stats)", "the tile log (--tile-log)",
                           "the output's journal"};
    char journal_path[PATH_MAX + sizeof JOURNAL_SUFFIX] = "";
    if (req->out_path)
        journal_name(req->out_path, journal_path, sizeof journal_path);
    const char *paths[] = {req->out_path, req->stats_path, req->tile_log_path,
                           req->out_path ? journal_path : NULL};
    for (int i = 0; i < 4 && !ri->clash.failed; i++)
        if (paths[i] && file_same(paths[i], path))
            csg_error_plain(&ri->clash, "%s is '%s', a file the scene includes: refusing to "
                            "overwrite it", names[i], path);
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
    render_includes ri = {req, {{0}, 0}};
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
        return EXIT_BAD_INPUT;
    }
    if (ok) { /* the size asked for, else the scene's (NFF's resolution) */
        csg_image_size(&s, req->width, req->height, &st->width, &st->height);
        st->pixels = (uint64_t)st->width * (uint64_t)st->height;
        o.width = st->width;
        o.height = st->height;
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

/* ---- step 2: the OpenCL pass, in the background --------------------------- */

/* The feature set to build the program for: the scene's (the loaded
 * blob's), or every feature when $CSGTRACE_CL_SPECIALISE is 0 (the
 * general program: benchmarks, and the tests that compare the two). */
static bool render_cl_features(const void *blob, csg_features *out, csg_diag *d)
{
    const char *env = getenv("CSGTRACE_CL_SPECIALISE");
    if (env && *env && strcmp(env, "0") != 0 && strcmp(env, "1") != 0) {
        csg_error_plain(d, "CSGTRACE_CL_SPECIALISE must be 0 or 1, not \"%s\"", env);
        return false;
    }
    *out = env && strcmp(env, "0") == 0 ? csg_features_all() : csg_blob_features(blob);
    return true;
}

/* The caller's context, or a new one (kept for the caller when it asks);
 * its program is specialised on the scene, which is loaded by now (a kept
 * context is rebuilt only when its program lacks some of the scene's
 * features). */
static bool render_open_cl(const render_request *req, render_state *rs, csg_diag *d)
{
    const csg_blob_header *h = csg_blob_hdr(rs->blob.bytes);
    const char *device = render_cl_device(req);
    csg_features features;
    if (!render_cl_features(rs->blob.bytes, &features, d))
        return false;
    ocl_options opt = {device, h->real_size == 8, 0, &features};
    rs->ctx = req->cl_keep ? *req->cl_keep : NULL;
    if (!rs->ctx && rs->early && rs->early->started) {
        rs->ctx = rs->build.on_early ? render_cl_early_result(rs->early, &rs->tm, d)
                                     : render_cl_early_take(rs->early, &rs->tm, d);
        rs->own_ctx = true; /* (closed by render_free, also when the build fails) */
        return rs->ctx && ocl_open_program(rs->ctx, &opt, (enum ocl_kernel)req->cl_kernel,
                                           &rs->tm, d);
    }
    if (!rs->ctx && !ocl_open_kernel(&opt, (enum ocl_kernel)req->cl_kernel, &rs->ctx, &rs->tm, d))
        return false;
    if (req->cl_keep && !ocl_specialise(rs->ctx, features, &rs->tm, d))
        return false;
    if (req->cl_keep)
        *req->cl_keep = rs->ctx; /* the caller closes it */
    else
        rs->own_ctx = true;
    return true;
}

static void render_wake(void *idle)
{
    link_wake(idle);
}

static double render_estimate(void *est, tile_rect r)
{
    return estimate_rect(est, r);
}

/* Slice rows of the pipelined pass: whole tile rows, enough records. */
static int render_slice_rows(const tile_grid *g)
{
    size_t row = (size_t)g->width * (size_t)g->spp * (size_t)g->tile; /* records a tile row */
    size_t tile_rows = (RENDER_SLICE_MIN_RECORDS + row - 1) / row;
    size_t rows = tile_rows * (size_t)g->tile;
    return rows < (size_t)g->height ? (int)rows : g->height;
}

/* The record arrays and the estimator; 0 or 1. */
static int render_alloc_records(render_state *rs, const tile_grid *g, csg_diag *d)
{
    size_t n = (size_t)g->width * (size_t)g->height * (size_t)g->spp; /* records */
    rs->t = malloc(n * g->real_size);
    rs->surf = malloc(n * sizeof *rs->surf);
    rs->tile_hits = calloc((size_t)tile_count(g), sizeof *rs->tile_hits);
    if (!rs->t || !rs->surf || !rs->tile_hits) {
        csg_error_plain(d, "out of memory for the hit records of %zu pixels", n);
        return EXIT_FAILURE_RUN;
    }
    return EXIT_OK;
}

static int render_pass_abandon(render_state *rs, csg_diag *d);

/* The pass started (on the context render_open_cl gave), and the
 * estimator its tiles' costs come from (only now: the fill's tiles have
 * none, and its set-up, a walk over every primitive, kept the first fill
 * tiles waiting on large scenes); 0 or 1. */
static int render_begin_pass(render_state *rs, const tile_grid *g, csg_diag *d)
{
    rs->pass_start = stats_clock();
    if (!estimator_init(&rs->est, rs->blob.bytes, g, rs->surf)) {
        csg_error_plain(d, "out of memory for the costs of %d primitives",
                        csg_blob_hdr(rs->blob.bytes)->prim_count);
        return EXIT_FAILURE_RUN;
    }
    if (!ocl_pass_begin(rs->ctx, rs->blob.bytes, g->tile, render_slice_rows(g), rs->t, rs->surf,
                        rs->tile_hits, rs->wake_master ? render_wake : NULL, &rs->idle,
                        &rs->pass, d)) {
        if (!d->failed)
            csg_error_plain(d, "the OpenCL primary pass failed");
        return render_pass_abandon(rs, d) == 0 ? EXIT_OK : EXIT_FAILURE_RUN;
    }
    return EXIT_OK;
}

/* ---- the program built meanwhile (the fill) ------------------------------------- */

/* A test hook's number from the environment (0 when unset or bad). */
static long render_test_env(const char *name)
{
    return (long)test_env_number(name, 1000000);
}

static void *render_cl_build_run(void *arg)
{
    render_cl_build *b = arg;
    /* Tests: CSGTRACE_TEST_CL_DELAY_MS makes the build that much slower,
     * so that the fill certainly has the workers first */
    long delay_ms = render_test_env("CSGTRACE_TEST_CL_DELAY_MS");
    if (delay_ms > 0)
        nanosleep(&(struct timespec){delay_ms / 1000, delay_ms % 1000 * 1000000L}, NULL);
    b->ok = render_open_cl(b->req, b->rs, &b->d);
    atomic_store(&b->done, true);
    if (b->wake)
        link_wake(b->wake);
    return NULL;
}

/* The thread started (or, if it cannot be, the build done here); 0 or 1. */
static int render_cl_build_start(render_state *rs, const render_request *req, csg_diag *d)
{
    render_cl_build *b = &rs->build;
    memset(&b->d, 0, sizeof b->d);
    b->begun = true;
    b->req = req;
    b->rs = rs;
    b->wake = rs->wake_master ? &rs->idle : NULL;
    atomic_init(&b->done, false);
    render_cl_early *e = rs->early;
    if (e && e->started) { /* (the device thread goes on: see render_cl_early) */
        b->on_early = b->started = true;
        b->thread = e->thread;
        e->build = b;
        sem_post(&e->go);
    } else {
        b->started = pthread_create(&b->thread, NULL, render_cl_build_run, b) == 0;
    }
    if (!b->started)
        render_cl_build_run(b);
    b->joined = !b->started;
    if (!b->started && !b->ok) {
        *d = b->d;
        return EXIT_FAILURE_RUN;
    }
    return EXIT_OK;
}

static void render_cl_build_join(render_state *rs)
{
    if (rs->build.started && !rs->build.joined) {
        if (rs->build.on_early)
            render_cl_early_join(rs->early);
        else
            pthread_join(rs->build.thread, NULL);
        rs->build.joined = true;
    }
}

/* The program is there (waiting for it with `wait`): 1; still being
 * built: 0; the build failed: -1 with d filled. */
static int render_cl_build_ready(render_state *rs, bool wait, csg_diag *d)
{
    render_cl_build *b = &rs->build;
    if (!b->joined && !wait && !atomic_load(&b->done))
        return 0;
    render_cl_build_join(rs);
    if (!b->ok) {
        *d = b->d;
        return -1;
    }
    return 1;
}

/* ---- step 3: feeding the scheduler -------------------------------------------- */

/* Rows from the top the pass must trace: those of the tiles above the
 * fill's (all of them without the fill). */
static int render_rows_needed(const render_state *rs, const tile_grid *g)
{
    int front = sched_fill_front(&rs->sched);
    if (front <= 0)
        return 0;
    tile_rect last = tile_rect_of(g, front - 1);
    return last.y + last.height;
}

/* --pass auto, once rank 0's guess of the work is in (waiting for it with
 * `wait`): the program's build begun when the guess says the pass pays
 * (RENDER_PASS_PAYS_S), else never (the fill renders every tile); 0, or
 * -1 with d filled. */
static int render_pass_decide(render_state *rs, bool wait, csg_diag *d)
{
    if (!rs->pass_waits)
        return 0;
    if (!rs->early || !rs->early->started) { /* (no thread to guess: never) */
        rs->pass_waits = false;
        return 0;
    }
    while (!render_cl_early_guessed(rs->early, &rs->pass_work_s)) {
        if (!wait)
            return 0;
        nanosleep(&(struct timespec){0, 100000L}, NULL); /* (a guess takes ~1/256 of
                                                            the frame's work) */
    }
    rs->pass_waits = false; /* (decided: once) */
    if (rs->pass_work_s < render_pass_pays_s())
        return 0;
    render_cl_early_want(rs->early, CL_OPEN_WORK);
    return render_cl_build_start(rs, rs->req, d) == EXIT_OK ? 0 : -1;
}

/* The device (or its program) d says could not be had: under --pass
 * auto the render goes on without it, the fill rendering every tile, as
 * when the guess says the pass does not pay (whether the device works
 * must not decide whether a frame renders: a small frame never opens
 * it), and says so once; 0.  Else -1, d kept: the pass was asked for. */
static int render_pass_give_up(render_state *rs, csg_diag *d)
{
    csg_features features;
    csg_diag bad = {{0}, 0};
    if (!rs->pass_auto ||
        !render_cl_features(rs->blob.bytes, &features, &bad)) /* (an option's fault: d's) */
        return -1;
    fprintf(stderr, "csgtrace: warning: %s: the render goes on without the OpenCL pass "
                    "(--pass auto), its workers rendering every tile\n", csg_diag_reason(d));
    memset(d, 0, sizeof *d);
    rs->pass_failed = true;
    return 0;
}

/* The pass d says could not start (a scene larger than the device's
 * buffers, say): under --pass auto given up as a device that cannot be
 * had (render_pass_give_up), what it enqueued waited for; 0.  Else -1. */
static int render_pass_abandon(render_state *rs, csg_diag *d)
{
    if (!rs->pass_auto)
        return -1;
    if (rs->pass) {
        csg_diag ignored = {{0}, 0};
        ocl_pass_end(rs->pass, NULL, &ignored);
        rs->pass = NULL;
    }
    rs->pass_start = 0; /* (no pass in the phases: render_account) */
    return render_pass_give_up(rs, d);
}

/* Rows from the top whose records are final (homo, serial: every row);
 * 0 while the program is being built, the pass started once it is (and
 * only if some rows still need it); -1 with d filled on a failure. */
static int render_pass_rows(render_state *rs, const tile_grid *g, bool wait, csg_diag *d)
{
    if (!rs->t)
        return g->height;
    int need = render_rows_needed(rs, g);
    if (!rs->pass) {
        if (need == 0 || rs->pass_failed)
            return 0; /* the fill took every tile, or takes them: no pass */
        if (render_pass_decide(rs, wait, d) < 0)
            return render_pass_give_up(rs, d);
        if (!rs->build.begun)
            return 0; /* (--pass auto: not yet decided, or never: the fill's) */
        int ready = render_cl_build_ready(rs, wait, d);
        if (ready < 0)
            return render_pass_give_up(rs, d);
        if (ready == 0)
            return 0;
        if (render_begin_pass(rs, g, d) != EXIT_OK)
            return -1;
        if (rs->pass_failed)
            return 0; /* (given up: the fill takes the rest) */
    }
    ocl_pass_limit(rs->pass, need);
    return ocl_pass_rows(rs->pass, wait, d);
}

/* A degenerate tile's pixels need no ray when there is no sky_sphere
 * (what a missed ray sees would then depend on its direction). */
static bool render_misses_are_background(const render_state *rs)
{
    return csg_blob_hdr(rs->blob.bytes)->sky_count == 0;
}

/* Degenerate rectangle r: the background throughout, by the master. */
static void render_fill_background(render_state *rs, master_job *job, tile_rect r)
{
    for (int y = r.y; y < r.y + r.height; y++)
        for (int x = r.x; x < r.x + r.width; x++)
            memcpy(rs->image + ((size_t)y * (size_t)job->grid.width + (size_t)x) * 3, rs->bg,
                   sizeof rs->bg);
    if (job->progress)
        progress_step(job->progress);
}

/* Tile `i`: queued; or taken from the journal (--resume: its pixels are
 * in the image already); or (the pass saw no hit in it) filled with the
 * background and logged. */
static bool render_offer_tile(render_state *rs, master_job *job, int i)
{
    tile_rect r = tile_rect_of(&job->grid, i);
    if (journal_resumed(rs->journal, i)) {
        if (!job->t)
            job->pixels_hit += journal_resumed_hits(rs->journal, i);
        return sched_resume(&rs->sched, i, r);
    }
    if (rs->tile_hits && rs->tile_hits[i] == 0 && render_misses_are_background(rs)) {
        render_fill_background(rs, job, r);
        return sched_skip(&rs->sched, i, r);
    }
    return sched_add(&rs->sched, i, r);
}

/* The master's helper threads: the journal's writer and, with workers,
 * the image's page faulting (serial: the faults are a sliver of its
 * tiles' work) and the store thread of the 8-bit results (store.h; until
 * it runs, the loop stores them).  In hetero with the fill only once the OpenCL program is
 * built: a thread created while PoCL loads waits for the dynamic loader's
 * lock (up to ~25 ms: the first tiles went out ~8 ms later on small
 * frames). */
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
}

/* The helpers may be created: no thread loads PoCL now (the program is
 * built, or, --pass auto, the device is not being opened). */
static bool render_helpers_may_start(const render_state *rs)
{
    if (rs->build.started || !rs->pass_auto)
        return atomic_load(&rs->build.done);
    return !rs->early || !atomic_load(&rs->early->opening);
}

/* master_job.feed: the tiles whose rows the pass completed go to the
 * scheduler, down to the fill's; homo and serial give every tile at once. */
static int render_feed(master_job *job, bool wait, csg_diag *d)
{
    render_state *rs = job->feed_arg;
    if (!rs->helpers && render_helpers_may_start(rs))
        render_start_helpers(rs, job);
    const tile_grid *g = &job->grid;
    int rows = render_pass_rows(rs, g, wait, d), known = 0;
    if (rows < 0)
        return -1;
    for (; rs->tiles_offered < sched_fill_front(&rs->sched); rs->tiles_offered++, known++) {
        tile_rect r = tile_rect_of(g, rs->tiles_offered);
        if (r.y + r.height > rows)
            break;
        if (!render_offer_tile(rs, job, rs->tiles_offered)) {
            csg_error_plain(d, "out of memory for the work items");
            return -1;
        }
    }
    if (rs->tiles_offered >= sched_fill_front(&rs->sched) && !rs->sched.closed) {
        sched_close(&rs->sched);
        rs->pass_end = stats_clock();
    }
    return known;
}

/* Tests: the fill has claimed its CSGTRACE_TEST_FILL_TILES; the cap holds
 * while a pass may come, not once it never will. */
static bool render_fill_capped(const render_state *rs)
{
    return rs->fill_max > 0 && rs->sched.filled >= rs->fill_max &&
           (rs->pass_waits || rs->build.begun) && !rs->pass_failed;
}

/* Is fill tile r degenerate, proven without the pass?  The frustum
 * culling the workers' primary rays use (engine->rect_misses) finds no
 * object any ray of the tile may meet.  On the SPD files this is where
 * hetero gains without opening its device: homo sends such a tile and a
 * worker traces its misses (tetra2: 158 of 256 tiles, 14 % of the tiles'
 * CPU); hetero fills it here, as it fills the pass's degenerate tiles. */
static bool render_culled(render_state *rs, tile_rect r)
{
    if (!render_misses_are_background(rs))
        return false;
    double t0 = stats_clock(); /* (not the thread's CPU clock: a system call) */
    bool misses = engine_for_blob(rs->blob.bytes)->rect_misses(rs->blob.bytes, r, &rs->cull_met);
    rs->cull_s += stats_clock() - t0;
    return misses;
}

/* master_job.fill: the last tile nobody has, to be rendered whole (a
 * resumed one is taken from the journal instead, a culled one filled with
 * the background: render_culled); the item, -1 when the
 * pass has reached every tile left, -2 with d filled (out of memory, or
 * the OpenCL build could not begin). */
static int render_fill(master_job *job, double now, csg_diag *d)
{
    render_state *rs = job->feed_arg;
    if (render_pass_decide(rs, false, d) < 0 && render_pass_give_up(rs, d) < 0)
        return -2;
    for (int tile; !render_fill_capped(rs) &&
                   (tile = sched_fill_claim(&rs->sched, rs->tiles_offered)) >= 0;) {
        tile_rect r = tile_rect_of(&job->grid, tile);
        int item = -1;
        if (journal_resumed(rs->journal, tile)) { /* (the pass does not count its hits) */
            job->pixels_hit += journal_resumed_hits(rs->journal, tile);
            if (sched_resume(&rs->sched, tile, r))
                continue;
        } else if (render_culled(rs, r)) {
            render_fill_background(rs, job, r);
            rs->tiles_culled++;
            /* (its primary rays counted as serial counts them: trace_primary
             * counts a rectangle its culling empties, traced or not) */
            job->rays.primary += (uint64_t)r.width * (uint64_t)r.height * (uint64_t)job->grid.spp;
            if (sched_fill_skip(&rs->sched, tile, r))
                continue;
        } else if ((item = sched_next_fill(&rs->sched, now, tile, r)) >= 0) {
            return item;
        }
        csg_error_plain(d, "out of memory for the work items");
        return -2;
    }
    return -1;
}

/* Step 3 without workers: every item in this process, through the very
 * tile_run_rect a worker calls, as the pass makes tiles ready (or the
 * items left when every worker was lost); counted in `self`. */
static int render_local_tiles(master_job *job, stats_worker *self, csg_diag *d)
{
    tile_runner tr;
    bool ready = tile_runner_init(&tr, job->blob, job->grid.tile);
    void *records = job->t ? malloc(tile_records_bytes(&job->grid, job->grid.pixels_max)) : NULL;
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
        bool shade = master_shades(job, item);
        tile_result res;
        tile_timer timer;
        if (shade)
            tile_pack_records(&job->grid, job->t, job->surf, r, records);
        tile_time_start(&timer);
        tile_run_rect(&tr, r, shade ? records : NULL, rgb, &res);
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

/* Step 4: the image file; 0 or 1 with d filled. */
static int render_write(const render_request *req, const render_state *rs,
                        const render_stats *st, csg_diag *d)
{
    char err[512] = "";
    if (!req->out_path)
        return EXIT_OK;
    signals_hold(); /* until the stats are written too (render_job) */
    if (img_write_rgb(req->out_path, rs->image, st->width, st->height, err, sizeof err))
        return EXIT_OK;
    if (strstr(err, "error:"))
        snprintf(d->message, sizeof d->message, "%s", err);
    else
        csg_error_plain(d, "%s: %s", req->out_path, err[0] ? err : "cannot write the image");
    d->failed = 1;
    return EXIT_FAILURE_RUN;
}

static void render_stats_init(const render_request *req, int ranks, render_stats *st)
{
    memset(st, 0, sizeof *st);
    st->mode = render_mode_name(req->mode);
    st->schedule = sched_policy_name(render_policy(req));
    st->cl_open = req->mode == MODE_HETERO ? render_cl_open_name(CL_OPEN_START) : "none";
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

/* ---- the figures of the tile phase ---------------------------------------------- */

/* The last result in minus the first worker idle for good. */
static double render_tail(const sched *s, int first, int workers, double t_first, double t_last)
{
    double *last = calloc((size_t)workers + 1, sizeof *last);
    double first_idle = t_last;
    if (workers < 2 || t_first == 0 || !last) {
        free(last);
        return 0.0;
    }
    for (int i = 0; i < s->count; i++) {
        const sched_item *it = &s->items[i];
        if (it->worker >= 1 && it->worker <= workers && it->done_s > last[it->worker])
            last[it->worker] = it->done_s;
    }
    for (int r = first; r <= workers; r++) { /* (relays compute nothing) */
        double idle = last[r] > 0 ? last[r] : t_first;
        if (idle < first_idle)
            first_idle = idle;
    }
    free(last);
    return t_last - first_idle;
}

/* Spearman's rho of the sent items' estimates and seconds. */
static double render_spearman(const sched *s)
{
    double *x = malloc((size_t)s->count * sizeof *x), *y = malloc((size_t)s->count * sizeof *y);
    int n = 0;
    for (int i = 0; x && y && i < s->count; i++) {
        const sched_item *it = &s->items[i];
        if (!it->skipped && !it->split && it->order >= 0 && it->estimate >= 0) {
            x[n] = it->estimate;
            y[n++] = it->busy_s;
        }
    }
    double rho = x && y ? estimate_spearman(x, y, n) : (double)NAN;
    free(x);
    free(y);
    return rho;
}

/* Degenerate tiles (skipped, not resumed). */
static int render_skipped(const sched *s)
{
    int n = 0;
    for (int i = 0; i < s->count; i++)
        n += s->items[i].skipped && !s->items[i].resumed;
    return n;
}

/* Tiles the fill claimed and workers rendered whole. */
static int render_filled(const sched *s)
{
    int n = 0;
    for (int i = 0; i < s->count; i++)
        n += s->items[i].fill;
    return n;
}

/* The phases (consecutive marks, stats.h) and the tile-phase figures. */
static void render_account(const render_state *rs, const master_job *job,
                           const render_marks *mk, render_stats *st)
{
    bool pass = rs->pass_start > 0;
    double pass_end = pass && rs->pass_end > 0 ? rs->pass_end : mk->tiles_end;
    double first = job->t_first > 0 ? job->t_first : mk->tiles_end;
    /* With the fill the OpenCL set-up ends when the pass begins, the tile
     * phase may have begun before: the marks stay in order */
    double cl_ready = rs->build.started ? (pass ? rs->pass_start : mk->loaded) : mk->cl_ready;
    double t3 = pass ? (first < pass_end ? first : pass_end) : cl_ready;
    t3 = t3 > cl_ready ? t3 : cl_ready;
    double t4 = pass ? pass_end : cl_ready;
    st->setup_s = mk->loaded - mk->start;
    /* (no pass: the build only overlapped the tiles, no phase of its own) */
    st->compile_s = !rs->build.started || pass ? rs->tm.compile_s : 0.0;
    st->cl_setup_s = cl_ready - mk->loaded - st->compile_s;
    st->primary_s = t3 - cl_ready;
    st->pipelined_s = t4 - t3;
    st->secondary_s = mk->tiles_end - t4;
    st->write_s = mk->written - mk->tiles_end;
    st->wall_s = mk->written - mk->start;
    st->pass_s = pass ? pass_end - rs->pass_start : 0.0;
    st->slices = rs->tm.slices;
    st->tile_phase_s = job->t_first > 0 ? job->t_last - job->t_first : 0.0;
    double span = st->tile_phase_s * (double)(st->worker_count - st->relays);
    st->busy_fraction = span > 0 ? job->busy_s / span : 0.0;
    st->tail_s = render_tail(&rs->sched, st->relays + 1,
                             st->worker_count > 1 ? st->worker_count : 0,
                             job->t_first, job->t_last);
    st->estimate_spearman = render_spearman(&rs->sched);
    st->tiles_sent = rs->sched.added;
    st->tiles_resumed = journal_tiles_resumed(rs->journal);
    st->tiles_degenerate = render_skipped(&rs->sched);
    st->tiles_culled = rs->tiles_culled;
    st->tiles_filled = render_filled(&rs->sched);
    st->items_sent = rs->sched.dispatched;
    st->items_reassigned = rs->sched.requeued;
}

/* ---- steps 2 and 3 ------------------------------------------------------------------ */

/* The OpenCL settings of the environment are valid (the kernel variant,
 * the specialisation), device or not; false with d filled. */
static bool render_cl_settings_ok(const render_request *req, const render_state *rs,
                                  csg_diag *d)
{
    enum ocl_kernel kernel = (enum ocl_kernel)req->cl_kernel;
    csg_features features;
    return ocl_kernel_from_env(&kernel, d) && render_cl_features(rs->blob.bytes, &features, d);
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
    if (hetero && !render_cl_settings_ok(req, rs, d)) /* (before any tile: the device
                                                        may never be opened) */
        return EXIT_FAILURE_RUN;
    if (hetero && !fill && !render_open_cl(req, rs, d)) /* (fill: meanwhile) */
        return EXIT_FAILURE_RUN;
    mk->cl_ready = stats_clock();
    rs->image = memory_image_alloc(st->pixels * 3 * sizeof *rs->image);
    rs->workers = calloc((size_t)st->worker_count + 1, sizeof *rs->workers); /* (+ the
                                                   master, should every worker be lost) */
    rs->idle_ready = use_workers && master_idle_init(&rs->idle);
    if (!rs->image || !rs->workers || (use_workers && !rs->idle_ready) ||
        !sched_init(&rs->sched, render_policy(req), use_workers ? ms->children : 1, st->in_flight,
                    st->tiles_total, hetero ? render_estimate : NULL, &rs->est)) {
        csg_error_plain(d, "out of memory for a %dx%d image", st->width, st->height);
        return EXIT_FAILURE_RUN;
    }
    if (use_workers)
        master_relay_floor(ms, &rs->sched);
    engine_for_blob(rs->blob.bytes)->miss_rgb(rs->blob.bytes, rs->bg);
    if (req->out_path) {
        int status = journal_open(req->out_path, rs->blob.bytes, &grid, req->resume, rs->image,
                                  JOURNAL_AFTER_S, &rs->journal, d);
        if (status != EXIT_OK)
            return status;
    }
    rs->prefault_bytes = use_workers ? st->pixels * 3 * sizeof *rs->image : 0;
    if (use_workers && pixels_format_for(req->out_path) == PIXELS_RGB8)
        rs->store_threads = req->store_threads > 0 ? req->store_threads : 1;
    job->journal = rs->journal;
    job->blob = rs->blob.bytes;
    job->grid = grid;
    job->sched = &rs->sched;
    job->feed = render_feed;
    job->feed_arg = rs;
    job->idle = rs->idle_ready ? &rs->idle : NULL;
    job->image = rs->image;
    job->workers = rs->workers;
    if (!fill) /* (hetero with the fill: once the program is built, render_feed) */
        render_start_helpers(rs, job);
    if (hetero) {
        int status = render_alloc_records(rs, &grid, d);
        job->t = rs->t;
        job->surf = rs->surf;
        rs->wake_master = use_workers;
        if (status != EXIT_OK || !fill)
            return status != EXIT_OK ? status : render_begin_pass(rs, &grid, d);
        sched_fill_enable(&rs->sched);
        job->fill = render_fill;
        rs->fill_max = (int)render_test_env("CSGTRACE_TEST_FILL_TILES"); /* (tests) */
        rs->cull_met = -1;
        rs->req = req;
        rs->pass_auto = render_pass_auto(req);
        rs->pass_waits = rs->pass_auto;
        if (!rs->pass_auto)
            return render_cl_build_start(rs, req, d);
        render_cl_early_guess(rs->early, rs->blob.bytes, st->tile);
        return EXIT_OK;
    }
    return render_feed(job, false, d) < 0 ? EXIT_FAILURE_RUN : EXIT_OK; /* every tile */
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

/* Hetero, once the pass is ended and every tile is in: the hit records
 * are freed before the image is written, so the writer's peak does not
 * hold them (host/memory.c). */
static void render_drop_records(render_state *rs, master_job *job)
{
    free(rs->t);
    free(rs->surf);
    rs->t = NULL;
    rs->surf = NULL;
    job->t = NULL;
    job->surf = NULL;
    estimator_free(&rs->est); /* (it reads surf) */
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
    st->master_results_s = job.results_s;
    st->store_threads = store_threads(rs->store);
    st->store_cpu_s = store_cpu_s(rs->store);
    st->pass_work_s = rs->pass_work_s;
    st->guess_cpu_s = render_cl_early_guess_cpu(rs->early);
    st->cull_s = rs->cull_s;
    int why = rs->early ? atomic_load(&rs->early->why) : CL_OPEN_NONE; /* (read before the
                                                  thread is told: none yet is never) */
    if (status == EXIT_OK && !rs->pass && rs->build.started && !rs->pass_failed &&
        render_cl_build_ready(rs, true, d) < 0 && /* (the fill took every tile: still, */
        render_pass_give_up(rs, d) < 0)           /* a bad OpenCL option is an error) */
        status = EXIT_FAILURE_RUN;
    if (rs->pass_auto && rs->early)
        st->cl_open = rs->pass_failed ? "failed" : render_cl_open_name(why);
    if (rs->pass) {
        bool whole = ocl_pass_end(rs->pass, &rs->tm, status == EXIT_OK ? d : &(csg_diag){{0}, 0});
        rs->pass = NULL;
        snprintf(st->device, sizeof st->device, "%s", rs->tm.device_name);
        csg_features_program_name(ocl_features(rs->ctx), st->cl_program,
                                  sizeof st->cl_program);
        if (!whole && status == EXIT_OK) {
            if (!d->failed)
                csg_error_plain(d, "the OpenCL primary pass failed");
            status = EXIT_FAILURE_RUN;
        }
        for (int i = 0; i < sched_fill_front(&rs->sched); i++) /* (the fill's: counted */
            job.pixels_hit += rs->tile_hits[i];                /* from their results) */
        job.rays.primary = st->pixels * (uint64_t)job.grid.spp;
    }
    st->pixels_hit = job.pixels_hit;
    st->rays = job.rays;
    st->workers = rs->workers;
    render_drop_records(rs, &job);
    if (status == EXIT_OK)
        status = render_write(req, rs, st, d);
    mk->written = stats_clock();
    render_account(rs, &job, mk, st);
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
 * cannot have (before any of it is allocated). */
static int render_memory_check(const render_request *req, const csg_blob *blob,
                               const render_stats *st, csg_diag *d)
{
    uint64_t avail;
    tile_grid grid = tile_grid_of(blob->bytes, st->tile);
    int slice_rows = req->mode == MODE_HETERO ? render_slice_rows(&grid) : 0;
    render_memory need = render_memory_need(st->width, st->height, st->spp,
                                            csg_blob_hdr(blob->bytes)->real_size, slice_rows,
                                            req->out_path);
    if (!memory_available(&avail) || need.total <= avail)
        return EXIT_OK;
    char total[32], image[32], writer[32], records[32], left[32], why[96] = "";
    if (need.records)
        snprintf(why, sizeof why, ", the hit records of the OpenCL pass %s",
                 memory_format(need.records + need.device, records, sizeof records));
    csg_error_plain(d,
                    "a %dx%d render in %s mode needs about %s of memory (the image %s, its "
                    "encoding %s%s); this process may allocate %s",
                    st->width, st->height, render_mode_name(req->mode),
                    memory_format(need.total, total, sizeof total),
                    memory_format(need.image, image, sizeof image),
                    memory_format(need.writer, writer, sizeof writer), why,
                    memory_format(avail, left, sizeof left));
    return EXIT_FAILURE_RUN;
}

/* The whole render on the process that owns the image; `early`: the
 * OpenCL device being opened (hetero), taken over. */
static int render_job(const render_request *req, int ranks, render_cl_early *early)
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
    rs.early = early;
    master_begin(&ms, ranks);

    int status = render_load(req, &rs.blob, &st, &d);
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
    ms.batch = req->batch;
    ms.relays = req->mode == MODE_SERIAL ? 0 : req->relays;
    ms.pixels = pixels_format_for(req->out_path); /* 8-bit files: bytes back */
    master_share_scene(&ms, status, st.tile, &rs.blob);
    mk.loaded = stats_clock();
    st.blob_bytes = rs.blob.size;
    if (status == EXIT_OK)
        status = render_image(req, &ms, &rs, &st, &mk, &d);
    st.batch = ms.batch;
    st.result_pixels = ms.workers > 0 ? pixels_format_name(ms.pixels) : "none";
    st.tile_messages = ms.tile_messages;
    st.bytes_sent = ms.bytes_sent;
    st.bytes_received = ms.bytes_received;
    st.workers_lost = ms.workers_lost;

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
    render_free(&rs);
    return status;
}

int render_run(const render_request *req)
{
    int rank = 0, size = 1;
    render_cl_early early;
    memset(&early, 0, sizeof early);
    /* (Not during MPI_Init: Open MPI patches memory functions then, and a
     * thread inside PoCL's set-up at that moment is not safe) */
    if (link_launched_by_mpirun() && !link_start(&rank, &size)) {
        fprintf(stderr, "csgtrace: error: MPI cannot start\n");
        return EXIT_FAILURE_RUN;
    }
    if (rank != 0)
        return worker_run(rank);
    render_cl_early_start(&early, req);
    int status = render_job(req, size, &early);
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
