/*
 * main.c — the driver of the simulated build (make sim; bench/simulate.sh).
 *
 * Built with smpicc and run by smpirun on a platform file: rank 0 runs the
 * project's own master (host/master.c, scheduler host/schedule.c, link
 * comm/mpi_link.c), ranks 1.. the project's own worker loop (workers/worker.c);
 * only tile_run_rect differs (sim/tile_run.c: the measured seconds of
 * the rectangle, from the cost map in $CSGSIM_COSTS, executed on the
 * simulated host).  The scene is loaded and flattened for real, so the
 * broadcast carries the real blob; hetero tiles carry their hit records
 * (zeros of the real size), results the real pixels' bytes.
 *
 * Hetero: the OpenCL pass is a duration (the map's pass_s scaled by the
 * pixel count), done by a device beside the master: the feed releases the
 * tile rows a pipelined pass would have finished by now (rows in
 * proportion to the time elapsed), tiles without hits are skipped, the
 * others queued with the map's estimate.  Homo: every tile at once.
 *
 * The fill (csgtrace --fill, host/schedule.h) is on in hetero unless
 * --fill off: while no tile of the pass is ready, a worker renders a whole
 * tile from the bottom up, at the cost of the homo map in
 * $CSGSIM_FILL_COSTS (bench/simulate.sh records it; without it, the
 * hetero map's cost); the pass stops where the fill's tiles begin.
 * serial_s stays the work of the scheme without the fill (every tile with
 * hits shaded, the whole pass), so efficiencies with and without the fill
 * compare as their makespans do.
 *
 * Open MPI's large-message protocol (mpi_link.h: link_model_protocol):
 * $CSGSIM_EAGER_BYTES, the eager limit (0 or unset: SMPI's own protocol,
 * which needs no progress from either side); $CSGSIM_LEGACY_RUNTIME=1
 * replays the runtime before 2026-11-28 (each message received whole, no
 * progress while a rank computes) for the validation against the node.
 *
 * $CSGSIM_PASS_DELAY_S: the device's set-up before its first slice (the
 * node's NVIDIA driver: cl_setup_s 0.13 s), which the fill fills.
 *
 * $CSGSIM_PASS_SCALE multiplies the pass (a faster device, hypothetically);
 * $CSGSIM_PASS_RATE (Mrays/s, one primary ray a pixel) replaces it by a
 * measured device rate: pass_s = width x height / rate (bench/GPU.md).
 *
 * --scene-memory MB (and --page-size KB, --page-policy lru|fifo,
 * --page-prefetch on|off, as csgtrace's): each worker holds the scene in
 * pages within MB megabytes, rank 0 serves the pages, or (--page-home)
 * their home workers do (the real plan, the real requests and answers); each item names the pages its real one
 * named, from the page traces in $CSGSIM_PAGES (sim/page_trace.h:
 * recorded by a real render of the same scene, size and page size with
 * $CSGTRACE_PAGE_TRACE), through the worker's real cache.  What a real
 * worker spends installing a fetched page (copies, the kernel's faults)
 * is $CSGSIM_PAGE_INSTALL_S seconds a byte on its host; rank 0's packing,
 * $CSGSIM_MASTER_PAGE_S (bench/sim/paging.sh measures both), and a home
 * worker's the same when it answers another.  A paged item's seconds are
 * the map's times $CSGSIM_PAGED_COST_SCALE (default 1: what paging adds to
 * the tracing itself, the shadow rays' prefetch walks).
 *
 *   csgsim SCENE --mode homo|hetero --width W --height H --tile T
 *          --schedule raster|cost|static|tail|region [--batch N] [--pieces N]
 *          [--pixels rgb8|rgb8z|float]
 *          [--hit-records send|retrace]
 *          [--scene-memory MB [--page-size KB] [--page-policy P] [--page-prefetch on|off]
 *           [--page-home auto|master|spread]]
 *          --stats FILE.json
 * --pixels: what the workers' RESULTs carry a pixel (comm/pixels.h): rgb8
 * (default: what a render to an 8-bit file such as PNG sends) or float
 * (EXR; every render before 2026-11-25) or rgb8z (rgb8 compressed,
 * --compress: each part's bytes those of the map $CSGSIM_WIRE_BYTES, its
 * compress $CSGSIM_COMPRESS_S seconds a byte of 3 x pixels on the worker,
 * its decompress $CSGSIM_MASTER_DECOMPRESS_S on rank 0).
 * writes makespan_s (scene broadcast to the last STOP), serial_s (every
 * item's seconds, plus the pass in hetero), efficiency and master_busy
 * (1 - the simulated seconds the master napped / makespan: its polls
 * count as busy), and where the workers' time went: work_s (their items'
 * seconds; more than serial_s with the fill, whose whole tiles cost
 * more than shading), ramp_s (until the last worker had its first item),
 * tail_s (from the moment the first worker's last result came in to the
 * end), bytes_sent and bytes_received (the master's).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/load.h"
#include "tile_sim.h"
#include "../workers/worker.h"
#include "../comm/mpi_link.h"
#include "../host/master.h"
#include "../comm/protocol.h"
#include "charges.h"
#include "page_trace.h"
#include "stubs.h"

typedef struct {
    const char *scene, *stats, *mode_name;
    bool hetero;
    int width, height, tile, policy;
    int batch;               /* --batch: 0 auto (master.h)               */
    int pieces;              /* --pieces: 0 auto (schedule.h)            */
    int relays;              /* --relays: ranks 1 .. relays relay (0)    */
    int pixels;              /* --pixels: enum pixels_format             */
    bool fill;               /* --fill on|off (hetero)                    */
    double scene_memory_mb;  /* --scene-memory (0: the whole scene)       */
    int page_kb;             /* --page-size (0: auto)                     */
    int page_policy;         /* --page-policy: enum pager_policy          */
    bool page_prefetch;      /* --page-prefetch on|off                    */
    int page_home;           /* --page-home: enum pager_home              */
    int page_fetch;          /* --page-fetch: enum pager_fetch_mode       */
    bool retrace;            /* --hit-records retrace (hetero): no records
                                sent, the workers' tiles cost the fill
                                map's (whole tiles)                     */
} sim_args;

typedef struct {
    const sim_costs *costs;
    sched s;
    double pass_s, pass_t0;  /* the pass: its duration, its start       */
    int tiles_offered;       /* tiles given to the scheduler, from the top */
    double serial_s;         /* the items' seconds, the pass included   */
    bool hetero;
    int width, height;
    int pieces;              /* the items a tile went as (--pieces)      */
} sim_run;

static bool sim_int(const char *text, int lo, int hi, int *out)
{
    char *end;
    long v = strtol(text, &end, 10);
    if (end == text || *end || v < lo || v > hi)
        return false;
    *out = (int)v;
    return true;
}

static bool sim_policy(const char *text, int *out)
{
    for (int p = 0; p < SCHED_POLICIES; p++)
        if (strcmp(text, sched_policy_name((enum sched_policy)p)) == 0) {
            *out = p;
            return true;
        }
    return false;
}

static bool sim_option(sim_args *a, const char *key, const char *v)
{
    if (strcmp(key, "--mode") == 0) {
        a->hetero = strcmp(v, "hetero") == 0;
        a->mode_name = a->hetero ? "hetero" : "homo";
        return a->hetero || strcmp(v, "homo") == 0;
    }
    if (strcmp(key, "--width") == 0)
        return sim_int(v, 1, 16384, &a->width);
    if (strcmp(key, "--height") == 0)
        return sim_int(v, 1, 16384, &a->height);
    if (strcmp(key, "--tile") == 0)
        return sim_int(v, 1, 4096, &a->tile);
    if (strcmp(key, "--schedule") == 0)
        return sim_policy(v, &a->policy);
    if (strcmp(key, "--batch") == 0)
        return sim_int(v, 1, PROTO_BATCH_MAX, &a->batch);
    if (strcmp(key, "--relays") == 0)
        return sim_int(v, 0, 4096, &a->relays);
    if (strcmp(key, "--pieces") == 0)
        return sim_int(v, 1, SCHED_PIECES_MAX, &a->pieces);
    if (strcmp(key, "--pixels") == 0) {
        a->pixels = strcmp(v, "float") == 0 ? PIXELS_FLOAT
                    : strcmp(v, "rgb8z") == 0 ? PIXELS_RGB8Z
                                              : PIXELS_RGB8;
        return strcmp(v, "float") == 0 || strcmp(v, "rgb8") == 0 || strcmp(v, "rgb8z") == 0;
    }
    if (strcmp(key, "--hit-records") == 0) {
        a->retrace = strcmp(v, "retrace") == 0;
        return a->retrace || strcmp(v, "send") == 0;
    }
    if (strcmp(key, "--fill") == 0) {
        a->fill = strcmp(v, "on") == 0;
        return a->fill || strcmp(v, "off") == 0;
    }
    if (strcmp(key, "--scene-memory") == 0) {
        char *end;
        a->scene_memory_mb = strtod(v, &end);
        return end != v && !*end && a->scene_memory_mb >= 0.001 && a->scene_memory_mb <= 1e9;
    }
    if (strcmp(key, "--page-size") == 0)
        return sim_int(v, 1, 1 << 20, &a->page_kb);
    if (strcmp(key, "--page-policy") == 0) {
        a->page_policy = strcmp(v, "fifo") == 0 ? PAGER_FIFO : PAGER_LRU;
        return strcmp(v, "fifo") == 0 || strcmp(v, "lru") == 0;
    }
    if (strcmp(key, "--page-home") == 0) {
        a->page_home = strcmp(v, "spread") == 0   ? PAGER_HOME_SPREAD
                       : strcmp(v, "master") == 0 ? PAGER_HOME_MASTER
                                                  : PAGER_HOME_AUTO;
        return a->page_home != PAGER_HOME_AUTO || strcmp(v, "auto") == 0;
    }
    if (strcmp(key, "--page-prefetch") == 0) {
        a->page_prefetch = strcmp(v, "on") == 0;
        return a->page_prefetch || strcmp(v, "off") == 0;
    }
    if (strcmp(key, "--page-fetch") == 0) {
        a->page_fetch = strcmp(v, "ask") == 0 ? PAGER_FETCH_ASK : PAGER_FETCH_GET;
        return strcmp(v, "ask") == 0 || strcmp(v, "get") == 0;
    }
    if (strcmp(key, "--stats") == 0) {
        a->stats = v;
        return true;
    }
    return false;
}

static bool sim_parse(int argc, char **argv, sim_args *a)
{
    *a = (sim_args){NULL, NULL, "homo", false, 384, 384, 32, -1, 0, 0, 0, PIXELS_RGB8, true,
                    0, 0, PAGER_LRU, true, PAGER_HOME_AUTO, PAGER_FETCH_GET, false};
    for (int i = 1; i < argc; i++) {
        if (argv[i][0] != '-' && !a->scene)
            a->scene = argv[i];
        else if (i + 1 >= argc || !sim_option(a, argv[i], argv[i + 1]))
            return false;
        else
            i++;
    }
    if (a->policy < 0)
        a->policy = a->hetero ? SCHED_COST : SCHED_RASTER;
    return a->scene && a->stats;
}

static bool sim_load(const sim_args *a, csg_blob *blob)
{
    csg_scene s;
    csg_diag d = {{0}, 0};
    csg_flatten_opts o = {a->width, a->height, 0, -1, 1, 0};
    csg_scene_init(&s);
    bool ok = csg_load_file(a->scene, NULL, &s, &d) && engine_float.flatten(&s, &o, blob, &d) &&
              csg_blob_valid(blob->bytes, blob->size);
    if (!ok)
        fprintf(stderr, "%s\n", d.failed ? d.message : "csgsim: cannot load the scene");
    csg_scene_free(&s);
    return ok;
}

static sim_cost sim_rect_cost(const sim_run *run, tile_rect r)
{
    return sim_costs_rect(run->costs, run->width, run->height, r);
}

static double sim_estimate(void *arg, tile_rect r)
{
    return sim_rect_cost(arg, r).estimate;
}

/* master_job.feed: the tiles of the rows the pass has finished by now,
 * down to the fill's. */
static int sim_feed(master_job *job, bool wait, csg_diag *d)
{
    (void)wait;
    sim_run *run = job->feed_arg;
    const tile_grid *g = &job->grid;
    int known = 0, front = sched_fill_front(&run->s);
    double done = run->pass_s > 0 ? (stats_clock() - run->pass_t0) / run->pass_s : 1;
    double rows = done >= 1 ? g->height : done * g->height;
    for (; run->tiles_offered < front; run->tiles_offered++, known++) {
        int i = run->tiles_offered;
        tile_rect r = tile_rect_of(g, i);
        if (r.y + r.height > rows)
            break;
        bool skip = run->hetero && sim_rect_cost(run, r).hits < 0.5;
        if (!(skip ? sched_skip(&run->s, i, r) : sched_add(&run->s, i, r))) {
            csg_error_plain(d, "csgsim: out of memory for the work items");
            return -1;
        }
    }
    if (run->tiles_offered >= front && !run->s.closed)
        sched_close(&run->s);
    return known;
}

/* master_job.fill: the last tile nobody has (render.c's render_fill). */
static int sim_fill(master_job *job, double now, csg_diag *d)
{
    sim_run *run = job->feed_arg;
    int tile = sched_fill_claim(&run->s, run->tiles_offered);
    if (tile < 0)
        return -1;
    int item = sched_next_fill(&run->s, now, tile, tile_rect_of(&job->grid, tile));
    if (item < 0)
        csg_error_plain(d, "csgsim: out of memory for the work items");
    return item < 0 ? -2 : item;
}

/* The work of the scheme without the fill: every tile (hetero: with
 * hits) at the map's cost, plus the whole pass. */
static double sim_serial_s(const sim_run *run, const tile_grid *g)
{
    double sum = run->pass_s;
    for (int i = 0; i < tile_count(g); i++) {
        sim_cost c = sim_rect_cost(run, tile_rect_of(g, i));
        sum += run->hetero && c.hits < 0.5 ? 0 : c.seconds;
    }
    return sum;
}

typedef struct {
    double makespan_s, napped_s;
    int items, batch;
    int filled;              /* tiles the fill gave workers whole        */
    uint64_t messages;       /* TILE messages                            */
    uint64_t bytes_received; /* by the master, from the workers          */
    uint64_t bytes_sent;     /* by the master: TILEs (with their records) */
    double work_s;           /* the workers' seconds on their items       */
    double ramp_s;           /* until the last worker had its first item  */
    double tail_s;           /* from the first worker's last result on    */
    page_counts paging;      /* the workers' paging, all items            */
    uint64_t page_asks;      /* page requests rank 0 answered             */
    uint64_t page_bytes_served; /* their bytes                            */
    int page_homes;          /* > 0: the workers were the pages' homes    */
    int32_t page_count;      /* the plan's pages (0: not paged)           */
    uint64_t page_bytes, resident_bytes, budget;
    bool page_window;        /* the workers read rank 0's pages one-sided */
    uint64_t answers_early;  /* relays' answers that overtook an older one */
} sim_result;

/* Where the workers' time went: their items' seconds, how long the last
 * of them waited for its first item, how early the first ran dry. */
static void sim_timeline(const sched *s, int workers, double t0, double end, sim_result *r)
{
    double *first = calloc((size_t)workers + 1, sizeof *first);
    double *last = calloc((size_t)workers + 1, sizeof *last);
    r->work_s = 0;
    for (int i = 0; first && last && i < s->count; i++) {
        const sched_item *it = &s->items[i];
        if (it->order < 0 || it->worker < 1 || it->worker > workers)
            continue;
        r->work_s += it->busy_s;
        if (first[it->worker] == 0 || it->sent_s < first[it->worker])
            first[it->worker] = it->sent_s;
        if (it->done_s > last[it->worker])
            last[it->worker] = it->done_s;
    }
    double ramp = 0, dry = end;
    for (int w = 1; first && last && w <= workers; w++) {
        ramp = first[w] - t0 > ramp ? first[w] - t0 : ramp;
        dry = last[w] > 0 && last[w] < dry ? last[w] : dry;
    }
    r->ramp_s = ramp;
    r->tail_s = end - dry;
    free(first);
    free(last);
}

/* Every item handed out, one CSV line each, into $CSGSIM_ITEM_LOG when it
 * is set (times from t0): what ends last, and why (bench/SCALE.md). */
static void sim_item_log(const sched *s, double t0)
{
    const char *path = getenv("CSGSIM_ITEM_LOG");
    FILE *f = path && path[0] ? fopen(path, "w") : NULL;
    if (!f)
        return;
    fputs("tile,piece,fill,worker,estimate,busy_s,sent_s,done_s\n", f);
    for (int i = 0; i < s->count; i++) {
        const sched_item *it = &s->items[i];
        if (it->order >= 0)
            fprintf(f, "%d,%d,%d,%d,%.6g,%.9g,%.9g,%.9g\n", it->tile, it->piece, it->fill,
                    it->worker, it->estimate, it->busy_s, it->sent_s - t0, it->done_s - t0);
    }
    fclose(f);
}

/* The grid's tiles (hetero: those with hits) the page trace has no item
 * of the mode's kind for (their pages are then the union of the items
 * they overlap: another tile size; none: a trace of another render). */
static int sim_trace_missing(const sim_args *a, const sim_run *run)
{
    const page_trace *t = page_trace_shared();
    int missing = 0;
    for (int y = 0; t && y < a->height; y += a->tile)
        for (int x = 0; x < a->width; x += a->tile) {
            int w = a->width - x < a->tile ? a->width - x : a->tile;
            int h = a->height - y < a->tile ? a->height - y : a->tile;
            if (run->hetero && sim_rect_cost(run, (tile_rect){x, y, w, h}).hits < 0.5)
                continue; /* (skipped: no item) */
            missing += !page_trace_find(t, run->hetero ? 'S' : 'T', x, y, w, h);
        }
    return missing;
}

static bool sim_write(const sim_args *a, const sim_run *run, int workers, const sim_result *r)
{
    FILE *f = fopen(a->stats, "w");
    if (!f)
        return false;
    double serial = run->serial_s;
    fprintf(f, "{\"workers\": %d, \"mode\": \"%s\", \"schedule\": \"%s\", \"tile\": %d, "
               "\"width\": %d, \"height\": %d, \"items\": %d, \"pass_s\": %.9g, "
               "\"makespan_s\": %.9g, \"serial_s\": %.9g, \"efficiency\": %.6f, "
               "\"master_busy\": %.6f, \"batch\": %d, \"tile_messages\": %llu, "
               "\"result_pixels\": \"%s\", \"bytes_received\": %llu, \"bytes_sent\": %llu, "
               "\"fill\": %s, \"tiles_filled\": %d, \"work_s\": %.9g, \"ramp_s\": %.9g, "
               "\"tail_s\": %.9g, \"relays\": %d, \"efficiency_ranks\": %.6f, \"pieces\": %d, "
               "\"answers_early\": %llu, \"store_threads\": %d",
            workers, a->mode_name, sched_policy_name((enum sched_policy)a->policy), a->tile,
            a->width, a->height, r->items, run->pass_s, r->makespan_s, serial,
            serial / (workers * r->makespan_s), 1 - r->napped_s / r->makespan_s, r->batch,
            (unsigned long long)r->messages, pixels_format_name(a->pixels),
            (unsigned long long)r->bytes_received, (unsigned long long)r->bytes_sent,
            a->fill && run->hetero ? "true" : "false",
            r->filled, r->work_s, r->ramp_s, r->tail_s, a->relays,
            serial / ((workers + a->relays) * r->makespan_s), run->pieces,
            (unsigned long long)r->answers_early, sim_master_store_threads());
    if (r->page_count > 0) {
        const page_counts *p = &r->paging;
        int missing = sim_trace_missing(a, run);
        fprintf(f, ", \"scene_memory\": {\"budget_bytes\": %llu, \"page_bytes\": %llu, "
                   "\"pages\": %d, \"resident_bytes\": %llu, \"policy\": \"%s\", "
                   "\"prefetch\": %s, \"fetch\": \"%s\", \"asks_answered\": %llu, "
                   "\"bytes_served\": %llu, "
                   "\"homes\": %d, \"trace_tiles_missing\": %d}, "
                   "\"paging\": {\"touches\": %llu, "
                   "\"faults\": %llu, \"requests\": %llu, \"pages\": %llu, "
                   "\"prefetched\": %llu, \"evictions\": %llu, \"bytes\": %llu, "
                   "\"served\": %llu, \"served_bytes\": %llu, "
                   "\"peak_bytes\": %llu, \"wait_s\": %.9g}",
                (unsigned long long)r->budget, (unsigned long long)r->page_bytes, r->page_count,
                (unsigned long long)r->resident_bytes, a->page_policy == PAGER_FIFO ? "fifo" : "lru",
                a->page_prefetch ? "true" : "false", r->page_window ? "get" : "ask",
                (unsigned long long)r->page_asks,
                (unsigned long long)r->page_bytes_served, r->page_homes, missing,
                (unsigned long long)p->touches, (unsigned long long)p->faults,
                (unsigned long long)p->requests, (unsigned long long)p->pages,
                (unsigned long long)p->prefetched, (unsigned long long)p->evictions,
                (unsigned long long)p->bytes, (unsigned long long)p->served,
                (unsigned long long)p->served_bytes, (unsigned long long)p->peak_bytes, p->wait_s);
    }
    fputs("}\n", f);
    return fclose(f) == 0;
}

/* The master's own work, charged to its simulated host (charges.h). */
static const master_costs sim_master_charges = {sim_charge_master_message,
                                                sim_charge_master_part, sim_master_store_drain,
                                                sim_charge_master_pages};

/* --scene-memory: the real plan (master_plan_pages), and the page trace
 * the items replay, which must be of it.  0, or the exit status with d
 * filled. */
static int sim_plan_pages(const sim_args *a, master_session *m, csg_blob *blob, csg_diag *d)
{
    if (a->scene_memory_mb <= 0)
        return 0;
    m->page_fetch = a->page_fetch;
    int status = master_plan_pages(m, blob->bytes, blob->size,
                                   (uint64_t)(a->scene_memory_mb * 1e6),
                                   (uint64_t)a->page_kb << 10, a->page_policy, a->page_prefetch,
                                   a->page_home, d);
    const page_trace *t = page_trace_shared();
    if (status == 0 && !t) {
        csg_error_plain(d, "csgsim: --scene-memory needs the page traces ($CSGSIM_PAGES)");
        status = 2;
    } else if (status == 0 && t->page_max >= m->plan.page_count) {
        csg_error_plain(d, "csgsim: the page trace names page %d of a plan of %d pages: it "
                           "was recorded with another scene, size or page size",
                        (int)t->page_max, (int)m->plan.page_count);
        status = 2;
    }
    return status;
}

/* The master's whole job: broadcast, tiles, STOP; false on a failure. */
static bool sim_master(const sim_args *a, sim_run *run, csg_blob *blob, int ranks,
                       sim_result *out)
{
    master_session m;
    master_job job;
    link_idle idle;
    csg_diag d = {{0}, 0};
    memset(&job, 0, sizeof job);
    job.grid = tile_grid_of(blob->bytes, a->tile);
    size_t n = (size_t)a->width * (size_t)a->height;
    job.image = calloc(n * 3, sizeof *job.image);
    job.workers = calloc((size_t)ranks, sizeof *job.workers);
    void *t = run->hetero ? calloc(n, job.grid.real_size) : NULL;
    uint32_t *surf = run->hetero ? calloc(n, sizeof *surf) : NULL;
    bool ok = job.image && job.workers && (!run->hetero || (t && surf)) && master_idle_init(&idle) &&
              sched_init(&run->s, (enum sched_policy)a->policy,
                         a->relays > 0 ? a->relays : ranks - 1, PROTO_IN_FLIGHT,
                         tile_count(&job.grid), run->hetero ? sim_estimate : NULL, run);
    if (ok) {
        job = (master_job){.blob = blob->bytes, .grid = job.grid, .t = t, .surf = surf,
                           .sched = &run->s, .feed = sim_feed, .feed_arg = run, .idle = &idle,
                           .image = job.image, .workers = job.workers,
                           .retrace = a->retrace};
        if (run->hetero && a->fill) {
            sched_fill_enable(&run->s);
            job.fill = sim_fill;
        }
        run->serial_s = sim_serial_s(run, &job.grid);
        sim_watch_naps(&idle.wake);
        double t0 = stats_clock();
        master_begin(&m, ranks);
        m.costs = &sim_master_charges;
        m.batch = a->batch;
        m.relays = a->relays;
        m.pixels = a->pixels;
        int status = sim_plan_pages(a, &m, blob, &d);
        master_share_scene(&m, status, a->tile, blob);
        run->pieces = sched_pieces_auto(a->pieces, ranks - 1 - a->relays,
                                        tile_count(&job.grid), a->tile,
                                        a->pixels == PIXELS_RGB8Z);
        bool cut = sched_cut(&run->s, run->pieces);
        master_relay_floor(&m, &run->s);
        run->pass_t0 = stats_clock() + sim_env_number("CSGSIM_PASS_DELAY_S", 0);
        ok = cut && status == 0 && master_run_tiles(&m, &job, &d);
        pager_plan plan = m.plan; /* (its sizes: master_end frees the pages) */
        master_end(&m, ok ? 0 : 1);
        master_release_scene(&m, blob); /* (threads: never shared, the blob stays) */
        *out = (sim_result){stats_clock() - t0, sim_napped_s(), job.items_done, m.batch,
                            run->s.filled, m.tile_messages, m.bytes_received, m.bytes_sent,
                            0, 0, 0, job.paging, m.page_asks, m.page_bytes_served,
                            m.page_homes, plan.page_count, plan.page_bytes, plan.resident_bytes,
                            m.scene_memory, m.page_window, m.answers_early};
        sim_timeline(&run->s, ranks - 1, t0, stats_clock(), out);
        sim_item_log(&run->s, t0);
        link_idle_free(&idle);
        sched_free(&run->s);
    } else { /* out of memory before the start: the workers still need a STOP */
        master_begin(&m, ranks);
        master_end(&m, 1);
    }
    if (d.failed)
        fprintf(stderr, "%s\n", d.message);
    free(job.image);
    free(job.workers);
    free(t);
    free(surf);
    return ok;
}

/* $CSGSIM_PASS_SCALE: a factor on the recorded pass (bench/simulate.sh
 * --pass-scale), 1 when unset or not a positive number. */
static double sim_pass_scale(void)
{
    return sim_env_number("CSGSIM_PASS_SCALE", 1);
}

/* $CSGSIM_PASS_RATE in rays a second (bench/simulate.sh --pass-rate, in
 * Mrays/s), 0 when unset or not a positive number. */
static double sim_pass_rate(void)
{
    return sim_env_number("CSGSIM_PASS_RATE", 0) * 1e6;
}

/* The pass's duration at the simulated size: the measured rate when one
 * is given, else the map's pass scaled by the pixel count (and the
 * factor). */
static double sim_pass_seconds(const sim_costs *c, int width, int height)
{
    double pixels = (double)width * height, rate = sim_pass_rate();
    if (rate > 0)
        return pixels / rate;
    return sim_pass_scale() * c->pass_s * pixels / ((double)c->width * c->height);
}

int main(int argc, char **argv)
{
    int rank = 0, ranks = 1;
    link_ranks_are_threads(); /* (SMPI's ranks share this process) */
    if (!link_start(&rank, &ranks))
        return 1;
    link_model_protocol((size_t)sim_env_number("CSGSIM_EAGER_BYTES", 0),
                        sim_env_number("CSGSIM_LEGACY_RUNTIME", 0) > 0);
    if (rank != 0) {
        worker_set_serve_cost(sim_charge_worker_serve);
        int status = worker_run(rank, NULL, NULL);
        link_finish();
        return status;
    }
    sim_args a;
    csg_blob blob = {NULL, 0};
    sim_run run;
    sim_result res;
    memset(&run, 0, sizeof run);
    run.costs = sim_costs_shared();
    if (!sim_parse(argc, argv, &a) || ranks < 2 || ranks < 1 + 2 * a.relays || !run.costs) {
        fprintf(stderr, "usage: smpirun -np K csgsim SCENE --mode homo|hetero --width W "
                        "--height H --tile T --schedule S --stats FILE (CSGSIM_COSTS=map)\n");
        master_session m;
        master_begin(&m, ranks);
        master_end(&m, 2);
        link_finish();
        return 2;
    }
    bool loaded = sim_load(&a, &blob), ok = loaded;
    run.hetero = a.hetero;
    run.width = a.width;
    run.height = a.height;
    run.pass_s = a.hetero ? sim_pass_seconds(run.costs, a.width, a.height) : 0;
    ok = ok && sim_master(&a, &run, &blob, ranks, &res) && sim_write(&a, &run, ranks - 1 - a.relays, &res);
    if (!loaded) { /* (the workers still wait for a setup; not blob.bytes: a
                    * window's blob is the link's after the render) */
        master_session m;
        master_begin(&m, ranks);
        master_end(&m, 2);
    }
    csg_blob_free(&blob);
    link_finish();
    return ok ? 0 : 1;
}
