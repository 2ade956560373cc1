/*
 * pass.c — hetero's primary pass as one render drives it (pass.h).
 *
 * The device thread.  OpenCL's device, context and queue do not depend
 * on the scene, so a thread opens them while the scene is read, flattened
 * and sent (ocl_open_device); the program, which does, is built after.
 * With the fill the same thread goes on to build the program once the
 * master has the scene (`go`, with `build_here` set), while the workers
 * render: no second thread is created, because pthread_create waits for
 * the dynamic loader's lock, which the device's opening holds while it
 * loads PoCL's drivers and LLVM (~30 ms here: the master sent its first
 * tile only then).  Without the fill (or when the render ends before it
 * needs the program) the master posts `go` with nothing to build and
 * joins it.  A context kept across renders (compare) has no device
 * thread: its program is built on a thread of its own.
 *
 * --pass auto (the default, with the fill): once the scene is loaded the
 * thread first guesses the work of the frame's primary rays from a sparse
 * sample of its pixels (pass_guess_work, while the workers render the
 * fill's first tiles), and the device is opened only when the guess is at
 * least PASS_PAYS_S; else the fill renders every tile and the device is
 * never opened.  Primary rays are what the pass takes off the workers;
 * the device costs a fixed set-up and compile, while the pass, on the
 * cores the workers use (PoCL), saves about half of what it takes.  The
 * rule's measurements, and the rules tried before it, are in
 * bench/SPD-notes.md ("The pass decided on the frame's primary rays").
 *
 * Give-up: under --pass auto a device (or program, or pass) that cannot
 * be had does not fail the render: one warning, and the fill renders
 * every tile, as when the guess says the pass does not pay (whether the
 * device works must not decide whether a frame renders: a small frame
 * never opens it).  With --pass always, --fill off or a device named, it
 * is an error.
 *
 * Invariants: the ocl_pass is ended before its arrays or the wake-up it
 * calls are freed; the device thread is joined before the pass is freed;
 * a context the caller keeps (cfg.keep) is never closed here.
 */
#include "pass.h"

#include <errno.h>
#include <pthread.h>
#include <semaphore.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../../comm/test_hooks.h"
#include "../../csg/flatten.h"
#include "../../csg/numbers.h"
#include "../../workers/tile.h"
#include "../memory.h"
#include "../stats.h"
#include "estimate.h"

/* Records a slice of the pipelined pass holds at least: one tile row, or
 * more when a tile row is smaller (each slice costs two launches). */
#define PASS_SLICE_MIN_RECORDS 2048

/* --pass auto: the guessed CPU seconds of the frame's primary rays from
 * which the pass pays.  The device costs a fixed ~0.08 s on this
 * project's 2-core machine (set-up 0.067-0.078 s, compile 0.008-0.013 s)
 * and the pass, on the workers' cores, saves about half of what it
 * takes. */
#define PASS_PAYS_S 0.16
#define PASS_GUESS_BLOCK 4   /* the guess traces blocks of 4 x 4 pixels, */
#define PASS_GUESS_STRIDE 64 /* one in every 64 x 64                    */

/* Why (and whether) the device was opened: the stats' cl_open. */
enum pass_cl_open { CL_OPEN_NONE, CL_OPEN_START, CL_OPEN_WORK, CL_OPEN_NEVER };

static const char *pass_cl_open_name(int why)
{
    static const char *const names[] = {"never", "start", "work", "never"};
    return names[why];
}

struct pass {
    pass_config cfg;
    /* the device thread */
    pthread_t thread;
    bool thread_running;   /* started, and not joined                   */
    ocl_ctx *opened;       /* its result (NULL: failed, opened_d says why) */
    ocl_timing opened_tm;
    csg_diag opened_d;
    sem_t open;            /* posted once `why` is set by the master,
                              and once the scene is there to guess     */
    atomic_int why;        /* enum pass_cl_open: set once              */
    atomic_bool opening;   /* the thread is inside ocl_open_device     */
    const void *guess_blob; /* --pass auto: the scene to guess the work of
                              (set before `open` is first posted)      */
    double work_s;         /* the guess (pass_guess_work) and its...    */
    double guess_cpu_s;    /* ...thread CPU seconds, once...            */
    atomic_bool guessed;   /* ...this is set                           */
    atomic_bool ending;    /* the render is over: the guess stops      */
    sem_t go;              /* posted once, when build_here is decided  */
    bool build_here;       /* the thread builds the program next       */
    /* the program's build, meanwhile (the fill) */
    pthread_t build_thread; /* a thread of its own (no device thread)   */
    bool build_begun;      /* pass_build_start was called              */
    bool build_started;    /* a thread builds, or built and is not joined */
    bool build_joined;     /* and its result taken                     */
    bool build_on_device_thread;
    atomic_bool build_done; /* the building thread has its result      */
    bool build_ok;
    csg_diag build_d;
    /* the scene and the pass */
    const void *blob;
    tile_grid grid;
    link_idle *wake;       /* woken by slices and the build (NULL: none) */
    ocl_ctx *ctx;          /* the context of the pass                   */
    bool own_ctx;          /* closed by pass_free                       */
    ocl_timing tm;
    ocl_pass *run;         /* the pass, until ended                     */
    void *t;               /* the records of the whole image            */
    uint32_t *surf;
    uint32_t *known, *lit; /* their shadow answers (--simd shadows; NULL) */
    memory_prefault records_prefault; /* their pages, faulted in meanwhile */
    uint32_t *tile_hits;   /* hits per tile                             */
    estimator est;         /* the items' estimated costs (from surf)    */
    bool est_ready;
    bool waits;            /* --pass auto, undecided                   */
    bool failed;           /* given up: the fill renders every tile     */
    double start;          /* stats_clock() when the pass began (0: never) */
};

/* ---- the guess (--pass auto) ------------------------------------------------ */

/* A guess block's edge from `at`: PASS_GUESS_BLOCK, or less where the
 * image or the tile ends (a rectangle lies inside one tile). */
static int pass_guess_edge(int at, int size, int tile)
{
    int edge = PASS_GUESS_BLOCK;
    edge = tile - at % tile < edge ? tile - at % tile : edge;
    return size - at < edge ? size - at : edge;
}

/* What the guess has traced: pixels, thread CPU seconds, rays. */
typedef struct {
    double pixels, cpu;
    uint64_t primary, rays;
} pass_guess_sample;

/* The blocks of one stage of the guess, traced: stage 0 every other one
 * across and down (1/1024 of the image), stage 1 the others; added to
 * *sample.  False when *stop came first. */
static bool pass_guess_stage(tile_runner *tr, int tile, int stage, const atomic_bool *stop,
                             pass_guess_sample *sample)
{
    int w = tr->grid.width, h = tr->grid.height, step = PASS_GUESS_STRIDE;
    int x0 = w > step / 4 ? step / 4 : w / 2, y0 = h > step / 4 ? step / 4 : h / 2;
    float rgb[PASS_GUESS_BLOCK * PASS_GUESS_BLOCK * 3];
    double cpu0 = stats_thread_cpu();
    for (int y = y0, iy = 0; y < h; y += step, iy++) {
        if (atomic_load(stop))
            return false;
        for (int x = x0, ix = 0; x < w; x += step, ix++) {
            if ((ix % 2 == 0 && iy % 2 == 0) != (stage == 0))
                continue;
            tile_rect r = {x, y, pass_guess_edge(x, w, tile), pass_guess_edge(y, h, tile)};
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
static double pass_guess_primary(const pass_guess_sample *sample, double area)
{
    if (!(sample->pixels > 0) || sample->rays == 0)
        return 0;
    return sample->cpu * (area / sample->pixels) * ((double)sample->primary / (double)sample->rays);
}

/* The CPU seconds a frame's primary rays will take on the workers,
 * guessed from blocks of PASS_GUESS_BLOCK x PASS_GUESS_BLOCK pixels, one
 * in every PASS_GUESS_STRIDE x PASS_GUESS_STRIDE (1/256 of the image),
 * traced and shaded on this thread (the tiles' seconds, weighed by the
 * primary rays' share of the rays: pass_guess_primary); 0 when out of
 * memory.  A small rectangle costs more a pixel than a tile (its culling
 * and set-up are shared by fewer rays): on the SPD scenes the guess was
 * 1.1-1.9x the tiles' CPU with blocks of 4 x 4, 1.9-7.4x with single
 * pixels.  A quarter of the blocks first: a guess from them under 2/3 of
 * `pays`, or at least 1.5 times it, is the answer; the rest (three times
 * the work: up to 2.6 ms a frame, all of it hetero's own) only refines a
 * guess near `pays`, where the pass about breaks even.  It stops (0) once
 * *stop holds: a render that ends first does not wait for it. */
static double pass_guess_work(const void *blob, int tile, double pays, const atomic_bool *stop)
{
    tile_runner tr;
    if (!tile_runner_init(&tr, blob, tile))
        return 0;
    double area = (double)tr.grid.width * (double)tr.grid.height;
    pass_guess_sample sample = {0, 0, 0, 0};
    bool done = pass_guess_stage(&tr, tile, 0, stop, &sample);
    double quarter = pass_guess_primary(&sample, area);
    if (done && quarter >= pays * 2 / 3 && quarter < pays * 1.5)
        done = pass_guess_stage(&tr, tile, 1, stop, &sample);
    tile_runner_free(&tr);
    return done ? pass_guess_primary(&sample, area) : 0;
}

/* The guessed primary-ray work from which the pass pays: PASS_PAYS_S
 * (tests: CSGTRACE_TEST_PASS_PAYS_MS). */
static double pass_pays_s(void)
{
    double pays = (double)test_hook_number(TEST_PASS_PAYS_MS, 1000000) * 1e-3;
    return pays > 0 ? pays : PASS_PAYS_S;
}

/* ---- the device thread ---------------------------------------------------------- */

static void pass_wait(sem_t *s)
{
    while (sem_wait(s) != 0 && errno == EINTR)
        continue;
}

static void pass_build_run(pass *p);

static void *pass_device_thread(void *arg)
{
    pass *p = arg;
    pass_wait(&p->open);
    if (atomic_load(&p->why) == CL_OPEN_NONE && p->guess_blob) { /* --pass auto */
        double cpu0 = stats_thread_cpu();
        p->work_s = pass_guess_work(p->guess_blob, p->grid.tile, pass_pays_s(), &p->ending);
        p->guess_cpu_s = stats_thread_cpu() - cpu0;
        atomic_store(&p->guessed, true);
        pass_wait(&p->open); /* the word: WORK or NEVER */
    }
    if (atomic_load(&p->why) != CL_OPEN_NEVER) {
        atomic_store(&p->opening, true);
        ocl_open_device(p->cfg.device, &p->opened, &p->opened_tm, &p->opened_d);
        atomic_store(&p->opening, false);
    }
    pass_wait(&p->go);
    if (p->build_here)
        pass_build_run(p);
    return NULL;
}

/* The device wanted for `why` (CL_OPEN_NEVER: not at all), unless it was
 * said already. */
static void pass_want(pass *p, int why)
{
    int none = CL_OPEN_NONE;
    if (p->thread_running && atomic_compare_exchange_strong(&p->why, &none, why))
        sem_post(&p->open);
}

static void pass_thread_start(pass *p)
{
    bool wait_for_word = p->cfg.automatic; /* (else: opened at once) */
    atomic_init(&p->why, wait_for_word ? CL_OPEN_NONE : CL_OPEN_START);
    if (sem_init(&p->go, 0, 0) != 0)
        return;
    if (sem_init(&p->open, 0, wait_for_word ? 0 : 1) != 0) {
        sem_destroy(&p->go);
        return;
    }
    p->thread_running = pthread_create(&p->thread, NULL, pass_device_thread, p) == 0;
    if (!p->thread_running) {
        sem_destroy(&p->go);
        sem_destroy(&p->open);
    }
}

/* The thread's device, taken over (NULL, d filled: it failed); on the
 * thread itself, or once it is joined. */
static ocl_ctx *pass_thread_result(pass *p, csg_diag *d)
{
    p->tm = p->opened_tm;
    if (!p->opened)
        *d = p->opened_d;
    ocl_ctx *c = p->opened;
    p->opened = NULL;
    return c;
}

static void pass_thread_join(pass *p)
{
    pthread_join(p->thread, NULL);
    sem_destroy(&p->go);
    sem_destroy(&p->open);
    p->thread_running = false;
}

/* The thread's device once it is done, told to build nothing (NULL, d
 * filled: it failed). */
static ocl_ctx *pass_thread_take(pass *p, csg_diag *d)
{
    atomic_store(&p->ending, true);
    pass_want(p, CL_OPEN_NEVER); /* (not opened yet: never needed) */
    p->build_here = false;
    sem_post(&p->go);
    pass_thread_join(p);
    return pass_thread_result(p, d);
}

/* ---- the context and its program ---------------------------------------------- */

/* The feature set to build the program for: the scene's, or every
 * feature (the general program: benchmarks, and the tests that compare
 * the two). */
static csg_features pass_features(const pass *p)
{
    return p->cfg.general ? csg_features_all() : csg_blob_features(p->blob);
}

/* The caller's context, or a new one (kept for the caller when it asks);
 * its program is specialised on the scene, which is loaded by now (a kept
 * context is rebuilt only when its program lacks some of the scene's
 * features). */
static bool pass_open_context(pass *p, csg_diag *d)
{
    csg_features features = pass_features(p);
    ocl_options opt = {.device = p->cfg.device,
                       .use_double = csg_blob_hdr(p->blob)->real_size == 8,
                       .features = &features,
                       .packet = p->cfg.packet,
                       .slice_records = (size_t)p->cfg.slice_records,
                       .cache_dir = p->cfg.cache_dir[0] ? p->cfg.cache_dir : NULL};
    p->ctx = p->cfg.keep ? *p->cfg.keep : NULL;
    if (!p->ctx && p->thread_running) {
        p->ctx = p->build_on_device_thread ? pass_thread_result(p, d) : pass_thread_take(p, d);
        p->own_ctx = true; /* (closed by pass_free, also when the build fails) */
        return p->ctx && ocl_open_program(p->ctx, &opt, p->cfg.kernel, &p->tm, d);
    }
    if (!p->ctx && !ocl_open_kernel(&opt, p->cfg.kernel, &p->ctx, &p->tm, d))
        return false;
    if (p->cfg.keep && !ocl_specialise(p->ctx, features, &p->tm, d))
        return false;
    if (p->cfg.keep)
        *p->cfg.keep = p->ctx; /* the caller closes it */
    else
        p->own_ctx = true;
    return true;
}

/* The build on whichever thread does it. */
static void pass_build_run(pass *p)
{
    /* Tests: CSGTRACE_TEST_CL_DELAY_MS makes the build that much slower,
     * so that the fill certainly has the workers first */
    long long delay_ms = test_hook_number(TEST_CL_DELAY_MS, 1000000);
    if (delay_ms > 0)
        nanosleep(&(struct timespec){delay_ms / 1000, delay_ms % 1000 * 1000000L}, NULL);
    p->build_ok = pass_open_context(p, &p->build_d);
    atomic_store(&p->build_done, true);
    if (p->wake)
        link_wake(p->wake);
}

static void *pass_build_thread(void *arg)
{
    pass_build_run(arg);
    return NULL;
}

/* The program's build begun: on the device thread, or on a new one
 * (none: a kept context), or, if none can be created, here; 0 or the
 * exit status with d filled. */
static int pass_build_start(pass *p, csg_diag *d)
{
    memset(&p->build_d, 0, sizeof p->build_d);
    p->build_begun = true;
    atomic_init(&p->build_done, false);
    if (p->thread_running) { /* (the device thread goes on: see the top) */
        p->build_on_device_thread = p->build_started = true;
        p->build_here = true;
        sem_post(&p->go);
    } else {
        p->build_started = pthread_create(&p->build_thread, NULL, pass_build_thread, p) == 0;
    }
    if (!p->build_started)
        pass_build_run(p);
    p->build_joined = !p->build_started;
    if (!p->build_started && !p->build_ok) {
        *d = p->build_d;
        return EXIT_FAILURE_RUN;
    }
    return EXIT_OK;
}

static void pass_build_join(pass *p)
{
    if (p->build_started && !p->build_joined) {
        if (p->build_on_device_thread)
            pass_thread_join(p);
        else
            pthread_join(p->build_thread, NULL);
        p->build_joined = true;
    }
}

/* The program is there (waiting for it with `wait`): 1; still being
 * built: 0; the build failed: -1 with d filled. */
static int pass_build_ready(pass *p, bool wait, csg_diag *d)
{
    if (!p->build_joined && !wait && !atomic_load(&p->build_done))
        return 0;
    pass_build_join(p);
    if (!p->build_ok) {
        *d = p->build_d;
        return -1;
    }
    return 1;
}

/* ---- the decision and the give-up ------------------------------------------- */

/* The device (or its program) d says could not be had: under --pass
 * auto the render goes on without it, and says so once; 0.  Else -1, d
 * kept: the pass was asked for. */
static int pass_give_up(pass *p, csg_diag *d)
{
    if (!p->cfg.automatic)
        return -1;
    fprintf(stderr, "csgtrace: warning: %s: the render goes on without the OpenCL pass "
                    "(--pass auto), its workers rendering every tile\n", csg_diag_reason(d));
    memset(d, 0, sizeof *d);
    p->failed = true;
    return 0;
}

/* The pass d says could not start (a scene larger than the device's
 * buffers, say): under --pass auto given up as a device that cannot be
 * had, what it enqueued waited for; 0.  Else -1. */
static int pass_abandon(pass *p, csg_diag *d)
{
    if (!p->cfg.automatic)
        return -1;
    if (p->run) {
        csg_diag ignored = {{0}, 0};
        ocl_pass_end(p->run, NULL, &ignored);
        p->run = NULL;
    }
    p->start = 0; /* (no pass in the phases) */
    return pass_give_up(p, d);
}

/* --pass auto, once the guess is in (waiting for it with `wait`): the
 * program's build begun when the guess says the pass pays, else never
 * (the fill renders every tile); 0, or -1 with d filled. */
static int pass_decide(pass *p, bool wait, csg_diag *d)
{
    if (!p->waits)
        return 0;
    if (!p->thread_running) { /* (no thread to guess: never) */
        p->waits = false;
        return 0;
    }
    while (!atomic_load(&p->guessed)) {
        if (!wait)
            return 0;
        nanosleep(&(struct timespec){0, 100000L}, NULL); /* (a guess takes ~1/256 of
                                                            the frame's work) */
    }
    p->waits = false; /* (decided: once) */
    if (p->work_s < pass_pays_s())
        return 0;
    pass_want(p, CL_OPEN_WORK);
    return pass_build_start(p, d) == EXIT_OK ? 0 : -1;
}

/* ---- the pass ------------------------------------------------------------------- */

static void pass_wake(void *idle)
{
    link_wake(idle);
}

int pass_slice_rows(const tile_grid *g)
{
    size_t row = (size_t)g->width * (size_t)g->spp * (size_t)g->tile; /* records a tile row */
    size_t tile_rows = (PASS_SLICE_MIN_RECORDS + row - 1) / row;
    size_t rows = tile_rows * (size_t)g->tile;
    return rows < (size_t)g->height ? (int)rows : g->height;
}

/* The bytes of each record array of a grid (t, surf, known, lit). */
static void pass_record_bytes(const tile_grid *g, size_t bytes[4])
{
    size_t n = (size_t)g->width * (size_t)g->height * (size_t)g->spp;
    bytes[0] = n * g->real_size;
    bytes[1] = bytes[2] = bytes[3] = n * sizeof(uint32_t);
}

/* A device that is not the host's CPU (a GPU) has its driver copy each
 * slice's records into the arrays after its kernels, and each fresh page
 * faults there: 134 MB at 4096x4096, 65-100 ms of faults on one core of
 * this machine, against 18 ms of the H200's kernel for the frame.  A
 * thread faults them in meanwhile, while the device traces (host/
 * memory.h).  On a CPU device the kernels' threads are the cores a thread
 * more would take: 2048x2048 on 2 cores, the pass 0.083 s with it, 0.061 s
 * without (5 rounds interleaved, medians; the records then in huge pages). */
static void pass_prefault_records(pass *p)
{
    if (ocl_cpu_device(p->ctx))
        return;
    void *const arrays[] = {p->t, p->surf, p->known, p->lit};
    size_t bytes[4];
    pass_record_bytes(&p->grid, bytes);
    memory_prefault_start_arrays(&p->records_prefault, arrays, bytes, 4);
}

/* The pass begun on the context pass_open_context gave, and the estimator
 * its tiles' costs come from (only now: the fill's tiles have none, and
 * its set-up, a walk over every primitive, kept the first fill tiles
 * waiting on large scenes); 0 or the exit status. */
static int pass_begin(pass *p, csg_diag *d)
{
    p->start = stats_clock();
    p->est_ready = estimator_init(&p->est, p->blob, &p->grid, p->surf);
    if (!p->est_ready) {
        csg_error_plain(d, "out of memory for the costs of %d primitives",
                        csg_blob_hdr(p->blob)->prim_count);
        return EXIT_FAILURE_RUN;
    }
    if (!ocl_pass_begin(p->ctx, p->blob, p->grid.tile, pass_slice_rows(&p->grid), p->t,
                        p->surf, p->known, p->lit, p->tile_hits, p->wake ? pass_wake : NULL, p->wake, &p->run,
                        d)) {
        if (!d->failed)
            csg_error_plain(d, "the OpenCL primary pass failed");
        return pass_abandon(p, d) == 0 ? EXIT_OK : EXIT_FAILURE_RUN;
    }
    pass_prefault_records(p);
    return EXIT_OK;
}

/* ---- the calls of pass.h ---------------------------------------------------- */

bool pass_settings(const csg_config *env, pass_config *cfg, csg_diag *d)
{
    const char *general = env->cl_specialise, *packet = env->cl_packet;
    if (cfg->kernel == OCL_KERNEL_AUTO && env->cl_kernel &&
        !ocl_kernel_parse(env->cl_kernel, &cfg->kernel)) {
        csg_error_plain(d, "CSGTRACE_CL_KERNEL must be auto, scalar or packet, not \"%s\"",
                        env->cl_kernel);
        return false;
    }
    if (general && strcmp(general, "0") != 0 && strcmp(general, "1") != 0) {
        csg_error_plain(d, "CSGTRACE_CL_SPECIALISE must be 0 or 1, not \"%s\"", general);
        return false;
    }
    cfg->general = general && strcmp(general, "0") == 0;
    long long width = 0;
    if (packet && (!number_whole(packet, 2, 16, &width) || (width & (width - 1)) != 0)) {
        csg_error_plain(d, "CSGTRACE_CL_PACKET must be 2, 4, 8 or 16, not \"%s\"", packet);
        return false;
    }
    cfg->packet = (int)width;
    long long records = 0;
    if (env->cl_slice && !number_whole(env->cl_slice, 1, OCL_SLICE_RECORDS_MAX, &records)) {
        csg_error_plain(d, "CSGTRACE_CL_SLICE must be a whole number of records from 1 to %lld, "
                           "not \"%s\"", (long long)OCL_SLICE_RECORDS_MAX, env->cl_slice);
        return false;
    }
    cfg->slice_records = records;
    return true;
}

bool pass_is_automatic(bool fill, bool always, const char *device, bool keep)
{
    return fill && !always && !keep && !(device && *device);
}

pass *pass_start(const pass_config *cfg)
{
    pass *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->cfg = *cfg;
    atomic_init(&p->why, CL_OPEN_NONE);
    atomic_init(&p->opening, false);
    atomic_init(&p->guessed, false);
    atomic_init(&p->ending, false);
    atomic_init(&p->build_done, false);
    if (!cfg->keep) /* (a kept context is the caller's) */
        pass_thread_start(p);
    return p;
}

int pass_open(pass *p, const void *blob, csg_diag *d)
{
    if (!p) {
        csg_error_plain(d, "out of memory for the OpenCL pass");
        return EXIT_FAILURE_RUN;
    }
    p->blob = blob;
    /* (with the fill: meanwhile, pass_prepare) */
    return p->cfg.fill || pass_open_context(p, d) ? EXIT_OK : EXIT_FAILURE_RUN;
}

int pass_prepare(pass *p, const tile_grid *g, link_idle *wake, csg_diag *d)
{
    size_t n = (size_t)g->width * (size_t)g->height * (size_t)g->spp; /* records */
    p->grid = *g;
    p->wake = wake;
    size_t bytes[4];
    pass_record_bytes(g, bytes);
    /* (small pages: written in place where the device can, host/memory.h) */
    p->t = memory_pages_alloc(bytes[0], false);
    p->surf = memory_pages_alloc(bytes[1], false);
    if (p->cfg.shadows) {
        p->known = memory_pages_alloc(bytes[2], false);
        p->lit = memory_pages_alloc(bytes[3], false);
    }
    p->tile_hits = calloc((size_t)tile_count(g), sizeof *p->tile_hits);
    if (!p->t || !p->surf || !p->tile_hits || (p->cfg.shadows && (!p->known || !p->lit))) {
        csg_error_plain(d, "out of memory for the hit records of %zu pixels", n);
        return EXIT_FAILURE_RUN;
    }
    if (!p->cfg.fill)
        return pass_begin(p, d);
    p->waits = p->cfg.automatic;
    if (!p->cfg.automatic)
        return pass_build_start(p, d);
    if (p->thread_running) { /* the thread is to guess the scene's work */
        p->guess_blob = p->blob;
        sem_post(&p->open);
    }
    return EXIT_OK;
}

int pass_rows(pass *p, int need, bool wait, csg_diag *d)
{
    if (!p->run) {
        if (need == 0 || p->failed)
            return 0; /* the fill took every tile, or takes them: no pass */
        if (pass_decide(p, wait, d) < 0)
            return pass_give_up(p, d);
        if (!p->build_begun)
            return 0; /* (--pass auto: not yet decided, or never: the fill's) */
        int ready = pass_build_ready(p, wait, d);
        if (ready < 0)
            return pass_give_up(p, d);
        if (ready == 0)
            return 0;
        if (pass_begin(p, d) != EXIT_OK)
            return -1;
        if (p->failed)
            return 0; /* (given up: the fill takes the rest) */
    }
    ocl_pass_limit(p->run, need);
    return ocl_pass_rows(p->run, wait, d);
}

int pass_poll(pass *p, csg_diag *d)
{
    return pass_decide(p, false, d) < 0 ? pass_give_up(p, d) : 0;
}

bool pass_may_come(const pass *p)
{
    return (p->waits || p->build_begun) && !p->failed;
}

bool pass_quiet(const pass *p)
{
    if (!p)
        return true;
    if (p->build_started || !p->cfg.automatic)
        return atomic_load(&p->build_done);
    return !p->thread_running || !atomic_load(&p->opening);
}

const void *pass_t(const pass *p)
{
    return p ? p->t : NULL;
}

const uint32_t *pass_surf(const pass *p)
{
    return p ? p->surf : NULL;
}

const uint32_t *pass_known(const pass *p)
{
    return p ? p->known : NULL;
}

const uint32_t *pass_lit(const pass *p)
{
    return p ? p->lit : NULL;
}

const uint32_t *pass_tile_hits(const pass *p)
{
    return p ? p->tile_hits : NULL;
}

double pass_estimate(void *p, tile_rect r)
{
    return estimate_rect(&((pass *)p)->est, r);
}

int pass_end(pass *p, int status, pass_report *r, csg_diag *d)
{
    memset(r, 0, sizeof *r);
    r->work_s = p->work_s;
    r->guess_cpu_s = atomic_load(&p->guessed) ? p->guess_cpu_s : 0;
    int why = atomic_load(&p->why); /* (read before the thread is told: none yet is
                                       never) */
    if (status == EXIT_OK && !p->run && p->build_started && !p->failed &&
        pass_build_ready(p, true, d) < 0 && /* (the fill took every tile: still, */
        pass_give_up(p, d) < 0)             /* a bad OpenCL option is an error) */
        status = EXIT_FAILURE_RUN;
    if (p->cfg.automatic)
        r->cl_open = p->failed ? "failed" : pass_cl_open_name(why);
    r->start = p->start;
    r->built_meanwhile = p->build_started;
    if (p->run) {
        bool whole = ocl_pass_end(p->run, &p->tm, status == EXIT_OK ? d : &(csg_diag){{0}, 0});
        p->run = NULL;
        r->traced = true;
        csg_features_program_name(ocl_features(p->ctx), r->program, sizeof r->program);
        if (!whole && status == EXIT_OK) {
            if (!d->failed)
                csg_error_plain(d, "the OpenCL primary pass failed");
            status = EXIT_FAILURE_RUN;
        }
    }
    r->tm = p->tm;
    return status;
}

uint64_t pass_hits(const pass *p, int tiles)
{
    uint64_t hits = 0;
    for (int i = 0; i < tiles; i++)
        hits += p->tile_hits[i];
    return hits;
}

void pass_drop_records(pass *p)
{
    if (!p)
        return;
    if (p->est_ready)
        estimator_free(&p->est); /* (it reads surf) */
    p->est_ready = false;
    memory_prefault_join(&p->records_prefault);
    free(p->t);
    free(p->surf);
    free(p->known);
    free(p->lit);
    p->t = NULL;
    p->surf = NULL;
    p->known = NULL;
    p->lit = NULL;
}

void pass_free(pass *p)
{
    if (!p)
        return;
    pass_build_join(p); /* (it may still be building: its context) */
    if (p->run) { /* before its arrays and its wake-up go */
        csg_diag ignored = {{0}, 0};
        ocl_pass_end(p->run, NULL, &ignored);
    }
    if (p->own_ctx)
        ocl_close(p->ctx);
    csg_diag none;
    /* (a render that failed before it needed the device; joined already:
     * a build on the thread that failed before taking the context left it) */
    ocl_close(p->thread_running ? pass_thread_take(p, &none) : pass_thread_result(p, &none));
    pass_drop_records(p);
    free(p->tile_hits);
    free(p);
}
