/*
 * render.c — the render driver: one render_request, any mode, any number
 * of ranks (render.h).
 *
 * Steps, on the process that owns the image (rank 0, or the only one):
 *   1. parse the scene and flatten it in the requested precision; share the
 *      status and the blob with the workers (master.c);
 *   2. hetero: the OpenCL primary pass over the whole image (ocl.h), giving
 *      a hit record per pixel and a hit count per tile; tiles without hits
 *      are filled here with the background and never sent;
 *   3. the tile phase: every other tile, row-major, through the workers
 *      (master_run_tiles) or, without workers, in this process;
 *   4. the image (img_write_rgb), the stats JSON, one summary line;
 *   5. STOP with the final status to every worker (master_end).
 * Serial mode is step 3 in-process over all tiles.
 *
 * Invariants: every mode produces the same pixels, because every tile goes
 * through the one tile_run (workers/tile.h), on a worker or here, from the
 * same record (hetero: the OpenCL record; the others: the engine's
 * trace_primary), and degenerate tiles get exactly what shade gives a
 * missed primary ray (engine->miss_rgb).  Every failure prints one message here (workers never
 * print) and goes through the one cleanup path; no image is written unless
 * every tile succeeded.
 */
#include "render.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/flatten.h"
#include "../csg/lang/parser.h"
#include "../csg/precision.h"
#include "../workers/tile.h"
#include "../workers/worker.h"
#include "image.h"
#include "link.h"
#include "master.h"
#include "ocl.h"
#include "progress.h"
#include "stats.h"

/* Everything one render owns; freed in render_free. */
typedef struct {
    csg_blob blob;
    float *image;          /* width * height * 3                        */
    void *t;               /* hetero: the OpenCL records                */
    uint32_t *surf;
    uint32_t *tile_hits;   /* hetero: hits per tile                      */
    int *todo;             /* tiles of the tile phase                    */
    stats_worker *workers; /* one per worker (or one for this process)  */
} render_state;

static void render_free(render_state *rs)
{
    csg_blob_free(&rs->blob);
    free(rs->image);
    free(rs->t);
    free(rs->surf);
    free(rs->tile_hits);
    free(rs->todo);
    free(rs->workers);
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
        bool need = csg_needs_double(s, req->width, req->height, st->precision_why,
                                     sizeof st->precision_why);
        return need ? &engine_double : &engine_float;
    }
    return req->precision == PREC_DOUBLE ? &engine_double : &engine_float;
}

/* Step 1: 0, or 2 (bad scene) / 1 (other failure) with d filled. */
static int render_load(const render_request *req, csg_blob *blob, render_stats *st, csg_diag *d)
{
    csg_flatten_opts o = { req->width, req->height, req->depth, req->threshold, req->spp };
    csg_scene s;
    int status = 0;
    csg_parse_options po;
    if (req->parse)
        po = *req->parse;
    else
        csg_parse_options_default(&po);
    po.image_width = req->width;
    po.image_height = req->height;
    csg_scene_init(&s);
    if (!csg_parse_file_opts(req->scene_path, &po, &s, d) ||
        !render_engine(req, &s, st)->flatten(&s, &o, blob, d)) {
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

/* Step 2 (hetero): records, tile hits and the OpenCL timings. */
static int render_primary(const render_request *req, render_state *rs, int tiles,
                          render_stats *st, csg_diag *d)
{
    const csg_blob_header *h = csg_blob_hdr(rs->blob.bytes);
    size_t n = (size_t)h->width * (size_t)h->height * (size_t)h->spp; /* records */
    const char *device = req->cl_device ? req->cl_device : getenv("CSGTRACE_CL_DEVICE");
    ocl_options opt = { device, h->real_size == 8, 0 };
    ocl_timing tm;
    ocl_ctx *ctx = req->cl_keep ? *req->cl_keep : NULL;
    memset(&tm, 0, sizeof tm);
    rs->t = malloc(n * h->real_size);
    rs->surf = malloc(n * sizeof *rs->surf);
    rs->tile_hits = calloc((size_t)tiles, sizeof *rs->tile_hits);
    if (!rs->t || !rs->surf || !rs->tile_hits) {
        csg_error_plain(d, "out of memory for the hit records of %zu pixels", n);
        return EXIT_FAILURE_RUN;
    }
    bool ok = (ctx || ocl_open(&opt, &ctx, &tm, d)) &&
              ocl_primary_pass(ctx, rs->blob.bytes, st->tile, rs->t, rs->surf, rs->tile_hits,
                               &tm, d);
    if (req->cl_keep)
        *req->cl_keep = ctx; /* the caller closes it */
    else if (ctx)
        ocl_close(ctx);
    st->compile_s = tm.compile_s;
    st->primary_s = tm.primary_s;
    snprintf(st->device, sizeof st->device, "%s", tm.device_name);
    if (!ok) {
        if (!d->failed)
            csg_error_plain(d, "the OpenCL primary pass failed");
        return EXIT_FAILURE_RUN;
    }
    return EXIT_OK;
}

/* The tiles of the tile phase into rs->todo; hetero: the others (none
 * with a sky_sphere) filled with
 * the background (what shade gives a missed primary ray). */
static void render_plan(render_state *rs, render_stats *st, master_job *job)
{
    int tiles = tile_count(&job->grid);
    float bg[3];
    engine_for_blob(rs->blob.bytes)->miss_rgb(rs->blob.bytes, bg);
    /* a sky_sphere: what a missed ray sees depends on its direction */
    bool sky = csg_blob_hdr(rs->blob.bytes)->sky_count > 0;
    int count = 0;
    for (int i = 0; i < tiles; i++) {
        if (!rs->tile_hits || rs->tile_hits[i] > 0 || sky) {
            rs->todo[count++] = i;
            continue;
        }
        tile_rect r = tile_rect_of(&job->grid, i);
        for (int y = r.y; y < r.y + r.height; y++)
            for (int x = r.x; x < r.x + r.width; x++)
                memcpy(rs->image + ((size_t)y * (size_t)st->width + (size_t)x) * 3, bg,
                       sizeof bg);
    }
    st->tiles_sent = count;
    st->tiles_degenerate = tiles - count;
    job->todo = rs->todo;
    job->todo_count = count;
    if (rs->tile_hits) { /* the device traced every primary ray */
        for (int i = 0; i < tiles; i++)
            job->pixels_hit += rs->tile_hits[i];
        job->rays.primary = st->pixels * (uint64_t)job->grid.spp;
    }
}

/* Step 3 without workers: every tile of the job in this process, through
 * the very tile_run a worker calls. */
static int render_local_tiles(master_job *job, csg_diag *d)
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
    job->workers[0].rank = 0;
    for (int k = 0; k < job->todo_count; k++) {
        tile_rect r = tile_rect_of(&job->grid, job->todo[k]);
        tile_result res;
        if (job->t)
            tile_pack_records(&job->grid, job->t, job->surf, r, records);
        tile_run(&tr, job->todo[k], records, rgb, &res);
        tile_store_rgb(job->image, job->grid.width, r, rgb);
        master_job_count(job, &job->workers[0], &res);
        if (job->progress)
            progress_step(job->progress);
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
    st->precision = req->precision == PREC_DOUBLE ? "double" : "float";
    st->width = req->width;
    st->height = req->height;
    st->tile = req->tile > 0 ? req->tile : RENDER_DEFAULT_TILE;
    st->ranks = ranks;
    st->spp = req->spp > 0 ? req->spp : 1;
    st->pixels = (uint64_t)req->width * (uint64_t)req->height;
}

/* Steps 2 to 4, once the scene is shared; 0 or the failure status. */
static int render_image(const render_request *req, master_session *ms, render_state *rs,
                        render_stats *st, csg_diag *d)
{
    tile_grid grid = tile_grid_of(rs->blob.bytes, st->tile);
    int tiles = tile_count(&grid);
    bool use_workers = ms->workers > 0 && req->mode != MODE_SERIAL;
    int status;
    progress_bar bar;
    master_job job;
    memset(&job, 0, sizeof job);
    st->tiles_total = tiles;
    st->worker_count = use_workers ? ms->workers : 1;
    rs->image = malloc(st->pixels * 3 * sizeof *rs->image);
    rs->todo = malloc((size_t)tiles * sizeof *rs->todo);
    rs->workers = calloc((size_t)st->worker_count, sizeof *rs->workers);
    if (!rs->image || !rs->todo || !rs->workers) {
        csg_error_plain(d, "out of memory for a %dx%d image", st->width, st->height);
        return EXIT_FAILURE_RUN;
    }
    if (req->mode == MODE_HETERO && (status = render_primary(req, rs, tiles, st, d)) != EXIT_OK)
        return status;

    job.blob = rs->blob.bytes;
    job.grid = grid;
    job.t = rs->t;
    job.surf = rs->surf;
    job.image = rs->image;
    job.progress = &bar;
    job.workers = rs->workers;
    render_plan(rs, st, &job);

    double t0 = stats_clock();
    progress_begin(&bar, job.todo_count, (int)req->progress);
    if (use_workers)
        status = master_run_tiles(ms, &job, d) ? EXIT_OK : EXIT_FAILURE_RUN;
    else
        status = render_local_tiles(&job, d);
    progress_end(&bar);
    st->secondary_s = stats_clock() - t0;
    st->pixels_hit = job.pixels_hit;
    st->rays = job.rays;
    st->workers = rs->workers;
    if (status != EXIT_OK)
        return status;

    t0 = stats_clock();
    status = render_write(req, rs, st, d);
    st->write_s = stats_clock() - t0;
    return status;
}

/* The one message of a failed render. */
static void render_report(const csg_diag *d)
{
    fprintf(stderr, "%s\n", d->message[0] ? d->message : "csgtrace: error: render failed");
    fflush(stderr);
}

/* The whole render on the process that owns the image. */
static int render_job(const render_request *req, int ranks)
{
    double t0 = stats_clock();
    render_state rs;
    render_stats st;
    master_session ms;
    csg_diag d;
    memset(&rs, 0, sizeof rs);
    memset(&d, 0, sizeof d);
    render_stats_init(req, ranks, &st);
    master_begin(&ms, ranks);

    int status = render_load(req, &rs.blob, &st, &d);
    bool reported = status != EXIT_OK;
    if (reported) /* before the workers learn it: they exit at once */
        render_report(&d);
    master_share_scene(&ms, status, st.tile, &rs.blob);
    st.setup_s = stats_clock() - t0;
    st.blob_bytes = rs.blob.size;
    if (status == EXIT_OK)
        status = render_image(req, &ms, &rs, &st, &d);
    st.wall_s = stats_clock() - t0;
    st.bytes_sent = ms.bytes_sent;
    st.bytes_received = ms.bytes_received;

    if (status == EXIT_OK && req->stats_path) {
        char err[1024];
        if (!stats_write_json(req->stats_path, &st, err, sizeof err)) {
            snprintf(d.message, sizeof d.message, "%s", err);
            d.failed = 1;
            status = EXIT_FAILURE_RUN;
        }
    }
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
        if (!req->stats_out)
            stats_print_summary(stdout, &st);
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
    if (link_launched_by_mpirun() && !link_start(&rank, &size)) {
        fprintf(stderr, "csgtrace: error: MPI cannot start\n");
        return EXIT_FAILURE_RUN;
    }
    if (rank != 0)
        return worker_run(rank);
    return render_job(req, size);
}

int render_rank(void)
{
    int rank = 0, size = 1;
    if (link_launched_by_mpirun() && !link_start(&rank, &size))
        return -1;
    return rank;
}
