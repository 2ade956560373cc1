/*
 * compare.c — the homogeneous versus heterogeneous comparison.
 *
 * Within one MPI job: one warm-up render per mode, then R rounds of one
 * homo and one hetero render, interleaved (homo, hetero, homo, hetero
 * ...), so a disturbance of the shared machine hits both modes alike
 * rather than all the runs of one.  The OpenCL program is built once, in
 * the warm-up, and kept (render_request.cl_keep), so no timed hetero run
 * pays for compilation or OpenCL set-up.  Every rank runs this same loop:
 * on the workers each render_run is one round of the worker protocol, so
 * the sequence stays in step with the master's.  The master then checks
 * that the last homo and hetero images are equal bit for bit and prints
 * one table (medians with min-max of every phase), the advantage
 * (homo - hetero) / homo of the median wall times, and the paired
 * advantage: the median (min-max) over the rounds of each round's own
 * (homo - hetero) / homo, the figure to trust when the machine is shared.
 */
#include "compare.h"

#include "output/file_atomic.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "output/image.h"
#include "../comm/mpi_link.h"
#include "pass/ocl.h"
#include "render.h"
#include "stats.h"

enum { COMPARE_MODES = 2 };
static const enum render_mode compare_modes[COMPARE_MODES] = {MODE_HOMO, MODE_HETERO};

typedef struct {
    render_stats *runs[COMPARE_MODES]; /* repeat entries each         */
    float *image[COMPARE_MODES];       /* the last image of each mode  */
    int repeat;
} compare_results;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct {
    double median, min, max;
} spread;

/* Median, min and max of n values (sorted in place). */
static spread spread_sorted(double *v, int n)
{
    qsort(v, (size_t)n, sizeof v[0], cmp_double);
    spread s = {n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]), v[0], v[n - 1]};
    return s;
}

/* Median, min and max of one field over the runs of a mode. */
static spread spread_of(const render_stats *runs, int n, size_t offset)
{
    double v[n];
    for (int i = 0; i < n; i++)
        memcpy(&v[i], (const char *)&runs[i] + offset, sizeof v[i]);
    return spread_sorted(v, n);
}

static void free_results(compare_results *r)
{
    for (int m = 0; m < COMPARE_MODES; m++) {
        free(r->runs[m]);
        free(r->image[m]);
    }
}

/* One render of mode m into r (round i: 0 is the warm-up, not kept). */
static int compare_render_one(const cli_args *a, compare_results *r, ocl_ctx **cl, int m, int i)
{
    render_request req = a->req;
    render_stats st;
    req.mode = compare_modes[m];
    req.out_path = NULL;
    req.stats_path = NULL;
    req.tile_log_path = NULL;
    req.progress = PROGRESS_OFF;
    req.cl_keep = cl;
    req.stats_out = &st;
    req.image_out = i == r->repeat ? &r->image[m] : NULL;
    int status = render_run(&req);
    if (status == EXIT_OK && i > 0)
        r->runs[m][i - 1] = st;
    return status;
}

/* The renders, the modes interleaved round by round; on failure the
 * status of the failed render. */
static int compare_render_all(const cli_args *a, compare_results *r, ocl_ctx **cl)
{
    for (int m = 0; m < COMPARE_MODES; m++) {
        r->runs[m] = calloc((size_t)r->repeat, sizeof *r->runs[m]);
        if (!r->runs[m]) {
            fprintf(stderr, "csgtrace: error: out of memory\n");
            return EXIT_FAILURE_RUN;
        }
    }
    for (int i = 0; i <= r->repeat; i++) /* i == 0: the warm-ups */
        for (int m = 0; m < COMPARE_MODES; m++) {
            int status = compare_render_one(a, r, cl, m, i);
            if (status != EXIT_OK)
                return status;
        }
    return EXIT_OK;
}

/* The advantage of every round, (homo - hetero) / homo in %, into adv. */
static spread paired_advantage(const compare_results *r, double *adv)
{
    for (int i = 0; i < r->repeat; i++) {
        double h = r->runs[0][i].wall_s, x = r->runs[1][i].wall_s;
        adv[i] = h > 0 ? 100.0 * (h - x) / h : 0.0;
    }
    double sorted[r->repeat];
    memcpy(sorted, adv, sizeof sorted);
    return spread_sorted(sorted, r->repeat);
}

/* One row: the median (min-max) of a field per mode; unit "s" or "%"
 * (the field is a fraction, printed in %). */
static void print_row(const char *label, const compare_results *r, size_t offset,
                      const char *unit)
{
    printf("%-22s", label);
    for (int m = 0; m < COMPARE_MODES; m++) {
        spread s = spread_of(r->runs[m], r->repeat, offset);
        double k = unit[0] == '%' ? 100.0 : 1.0;
        char cell[64];
        snprintf(cell, sizeof cell, "%.4f %s (%.4f-%.4f)", k * s.median, unit, k * s.min,
                 k * s.max);
        printf("  %-30s", cell);
    }
    printf("\n");
}

static void print_row_times(const char *label, const compare_results *r, size_t offset)
{
    print_row(label, r, offset, "s");
}

/* Workers busier than this over their tile phase measure the modes; less
 * busy ones measure the runtime (a stall: docs/parallel.md, "Progress"). */
#define COMPARE_BUSY_MIN 0.90

/* Why the advantage is not reported (into why; false), or true: both
 * modes' workers were busy at least COMPARE_BUSY_MIN of their tile phase
 * (the median over the rounds) where the render had workers. */
static bool compare_healthy(const compare_results *r, char *why, size_t size)
{
    const char *names[COMPARE_MODES] = {"homo", "hetero"};
    why[0] = '\0';
    for (int m = 0; m < COMPARE_MODES; m++) {
        double busy = spread_of(r->runs[m], r->repeat, offsetof(render_stats, busy_fraction)).median;
        if (r->runs[m][0].ranks > 1 && busy < COMPARE_BUSY_MIN) {
            snprintf(why, size,
                     "not reported: the %s workers were busy %.1f %% of their tile phase (the "
                     "median; under %.0f %%), so the times measure the runtime's waits, not the "
                     "modes (docs/parallel.md, \"Progress\")",
                     names[m], 100 * busy, 100 * COMPARE_BUSY_MIN);
            return false;
        }
    }
    return true;
}

static void print_table(const cli_args *a, const compare_results *r, bool identical,
                        double advantage, spread paired, const char *withheld)
{
    const render_stats *h = &r->runs[0][0], *x = &r->runs[1][0];
    printf("csgtrace compare %s: %dx%d, tile %d, %d rank%s, %s, %d timed rounds (homo, hetero) "
           "after a warm-up\n",
           a->req.scene_path, h->width, h->height, h->tile, h->ranks, h->ranks == 1 ? "" : "s",
           h->precision, r->repeat);
    printf("%-22s  %-30s  %-30s\n", "", "homo", "hetero");
    print_row_times("wall (median, min-max)", r, offsetof(render_stats, wall_s));
    print_row_times("setup phase", r, offsetof(render_stats, setup_s));
    print_row_times("primary phase (alone)", r, offsetof(render_stats, primary_s));
    print_row_times("pipelined phase", r, offsetof(render_stats, pipelined_s));
    print_row_times("tile phase (after)", r, offsetof(render_stats, secondary_s));
    print_row_times("write phase", r, offsetof(render_stats, write_s));
    print_row_times("OpenCL pass", r, offsetof(render_stats, pass_s));
    print_row_times("tail", r, offsetof(render_stats, tail_s));
    print_row("workers busy", r, offsetof(render_stats, busy_fraction), "%");
    printf("%-22s  %-30s  %-30s\n", "OpenCL device", "-", x->device[0] ? x->device : "-");
    char a_cell[64], b_cell[64];
    snprintf(a_cell, sizeof a_cell, "%d / %d", h->tiles_sent, h->tiles_degenerate);
    snprintf(b_cell, sizeof b_cell, "%d / %d", x->tiles_sent, x->tiles_degenerate);
    printf("%-22s  %-30s  %-30s\n", "tiles sent / skipped", a_cell, b_cell);
    const char *kinds[4] = {"rays primary", "rays shadow", "rays reflected", "rays refracted"};
    for (int k = 0; k < 4; k++) {
        const uint64_t *ra = &h->rays.primary + k, *rb = &x->rays.primary + k;
        snprintf(a_cell, sizeof a_cell, "%llu", (unsigned long long)*ra);
        snprintf(b_cell, sizeof b_cell, "%llu", (unsigned long long)*rb);
        printf("%-22s  %-30s  %-30s\n", kinds[k], a_cell, b_cell);
    }
    printf("%-22s  %.1f%% of pixels hit\n", "occupancy",
           h->pixels ? 100.0 * (double)h->pixels_hit / (double)h->pixels : 0.0);
    printf("%-22s  %s\n", "images", identical ? "identical, bit for bit" : "DIFFERENT");
    printf("schedules: homo %s, hetero %s; hetero estimate vs seconds (Spearman): %.3f\n",
           h->schedule, x->schedule, x->estimate_spearman);
    if (withheld[0]) {
        printf("advantage: %s\n", withheld);
        return;
    }
    printf("advantage (homo - hetero) / homo: %.1f%%\n", advantage);
    printf("advantage paired by round: %.1f%% (%.1f .. %.1f)\n", paired.median, paired.min,
           paired.max);
}

typedef struct {
    const cli_args *a;
    const compare_results *r;
    bool identical;
    double advantage;
    const double *paired;
    const char *withheld; /* "" or why the advantage is not reported */
} compare_json;

static void print_json(FILE *f, const void *arg)
{
    const compare_json *j = arg;
    const cli_args *a = j->a;
    const compare_results *r = j->r;
    bool identical = j->identical;
    double advantage = j->advantage;
    const double *paired = j->paired;
    fprintf(f, "{\n\"command\": \"compare\",\n\"scene\": \"");
    for (const char *c = a->req.scene_path; *c; c++)
        fprintf(f, (*c == '"' || *c == '\\') ? "\\%c" : "%c", *c);
    fprintf(f, "\",\n\"repeat\": %d,\n\"identical\": %s,\n", r->repeat,
            identical ? "true" : "false");
    if (j->withheld[0]) { /* (no figure: the text says why) */
        fprintf(f, "\"advantage_pct\": null,\n\"advantage_withheld\": \"");
        for (const char *c = j->withheld; *c; c++)
            fprintf(f, (*c == '"' || *c == '\\') ? "\\%c" : "%c", *c);
        fprintf(f, "\",\n\"interleaved\": true,\n\"advantage_paired_pct\": null,\n");
    } else {
        fprintf(f, "\"advantage_pct\": %.6f,\n\"interleaved\": true,\n", advantage);
        fprintf(f, "\"advantage_paired_pct\": [");
        for (int i = 0; i < r->repeat; i++)
            fprintf(f, "%s%.6f", i ? ", " : "", paired[i]);
        fprintf(f, "],\n");
    }
    const char *names[COMPARE_MODES] = {"homo", "hetero"};
    for (int m = 0; m < COMPARE_MODES; m++) {
        fprintf(f, "\"%s\": [\n", names[m]);
        for (int i = 0; i < r->repeat; i++) {
            stats_print_json(f, &r->runs[m][i]);
            if (i + 1 < r->repeat)
                fprintf(f, ",\n");
        }
        fprintf(f, "]%s\n", m + 1 < COMPARE_MODES ? "," : "");
    }
    fprintf(f, "}\n");
}

static bool write_json(const char *path, const cli_args *a, const compare_results *r,
                       bool identical, double advantage, const double *paired,
                       const char *withheld)
{
    compare_json j = {a, r, identical, advantage, paired, withheld};
    char err[1024];
    if (file_write_atomic(path, print_json, &j, err, sizeof err))
        return true;
    fprintf(stderr, "%s\n", err);
    return false;
}

/* PREFIX-homo.png and PREFIX-hetero.png. */
static bool write_images(const char *prefix, const compare_results *r, int w, int h)
{
    const char *names[COMPARE_MODES] = {"homo", "hetero"};
    for (int m = 0; m < COMPARE_MODES; m++) {
        char path[4096], err[512];
        snprintf(path, sizeof path, "%s-%s.png", prefix, names[m]);
        if (!img_write_rgb(path, r->image[m], w, h, err, sizeof err)) {
            fprintf(stderr, "csgtrace: error: %s\n", err);
            return false;
        }
    }
    return true;
}

int compare_run(const cli_args *a)
{
    int rank = render_rank();
    if (rank < 0) {
        fprintf(stderr, "csgtrace: error: MPI cannot start\n");
        return EXIT_FAILURE_RUN;
    }
    compare_results r;
    memset(&r, 0, sizeof r);
    r.repeat = a->repeat;
    ocl_ctx *cl = NULL;
    int status = compare_render_all(a, &r, &cl);
    if (cl)
        ocl_close(cl);
    if (status != EXIT_OK || rank != 0) {
        free_results(&r);
        return status;
    }
    const render_stats *h = &r.runs[0][0];
    size_t bytes = (size_t)h->width * (size_t)h->height * 3 * sizeof(float);
    bool identical = memcmp(r.image[0], r.image[1], bytes) == 0;
    double homo = spread_of(r.runs[0], r.repeat, offsetof(render_stats, wall_s)).median;
    double hetero = spread_of(r.runs[1], r.repeat, offsetof(render_stats, wall_s)).median;
    double advantage = homo > 0 ? 100.0 * (homo - hetero) / homo : 0.0;
    double paired[r.repeat];
    spread pair = paired_advantage(&r, paired);
    char withheld[512];
    compare_healthy(&r, withheld, sizeof withheld);
    print_table(a, &r, identical, advantage, pair, withheld);
    if (a->out_path && !write_images(a->out_path, &r, h->width, h->height))
        status = EXIT_FAILURE_RUN;
    if (a->req.stats_path &&
        !write_json(a->req.stats_path, a, &r, identical, advantage, paired, withheld))
        status = EXIT_FAILURE_RUN; /* write_json said why */
    if (!identical) {
        fprintf(stderr, "csgtrace: error: the homo and hetero images differ: this is a bug\n");
        status = EXIT_FAILURE_RUN;
    }
    free_results(&r);
    link_exit_status(status); /* (made mpirun's under --enable-recovery) */
    return status;
}
