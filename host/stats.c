/*
 * stats.c — the statistics of a render as one JSON object (see stats.h for
 * the fields), the tile log (JSON lines) and one summary line.
 *
 * The writer is a plain fprintf sequence: numbers with %.9g (a non-finite
 * double, which JSON cannot hold, becomes null), strings escaped.  Each
 * file is written under a mkstemp name in the destination's folder,
 * flushed and renamed over `path`, so a reader never sees half a file.
 */
#include "stats.h"

#include "output/file_atomic.h"
#include "pass/estimate.h"
#include "../workers/pager.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

double stats_occupancy(const render_stats *s)
{
    double samples = (double)s->pixels * (double)(s->spp > 0 ? s->spp : 1);
    return samples > 0 ? (double)s->pixels_hit / samples : 0.0;
}

double stats_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

double stats_thread_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

double stats_phase_sum(const render_stats *s)
{
    return s->setup_s + s->cl_setup_s + s->compile_s + s->primary_s + s->pipelined_s +
           s->secondary_s + s->write_s;
}

void stats_add_rays(ray_counts *a, const ray_counts *b)
{
    a->primary += b->primary;
    a->shadow += b->shadow;
    a->reflected += b->reflected;
    a->refracted += b->refracted;
    a->over_budget += b->over_budget;
    a->shadow_answered += b->shadow_answered;
}

static void stats_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; p++) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}

static void stats_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.9g", v);
    else
        fputs("null", f);
}

static void stats_rays(FILE *f, const ray_counts *r)
{
    fprintf(f,
            "{\"primary\": %llu, \"shadow\": %llu, \"reflected\": %llu, \"refracted\": %llu, "
            "\"total\": %llu, \"shadow_answered\": %llu}",
            (unsigned long long)r->primary, (unsigned long long)r->shadow,
            (unsigned long long)r->reflected, (unsigned long long)r->refracted,
            (unsigned long long)ray_counts_total(r), (unsigned long long)r->shadow_answered);
}

/* "  "key": value,\n" for a double. */
static void stats_field(FILE *f, const char *key, double v)
{
    fprintf(f, "  \"%s\": ", key);
    stats_number(f, v);
    fputs(",\n", f);
}

/* A page_counts as a JSON object, on one line. */
static void stats_paging(FILE *f, const page_counts *c)
{
    fprintf(f, "{\"touches\": %llu, \"faults\": %llu, \"requests\": %llu, \"pages\": %llu, "
               "\"prefetched\": %llu, \"evictions\": %llu, \"bytes\": %llu, "
               "\"peak_bytes\": %llu, \"over_budget_bytes\": %llu, \"memory_peak_bytes\": %llu, "
               "\"served\": %llu, \"served_bytes\": %llu, \"rerouted\": %llu, \"hit_rate\": ",
            (unsigned long long)c->touches, (unsigned long long)c->faults,
            (unsigned long long)c->requests, (unsigned long long)c->pages,
            (unsigned long long)c->prefetched, (unsigned long long)c->evictions,
            (unsigned long long)c->bytes, (unsigned long long)c->peak_bytes,
            (unsigned long long)c->over_bytes, (unsigned long long)c->memory_bytes,
            (unsigned long long)c->served, (unsigned long long)c->served_bytes,
            (unsigned long long)c->rerouted);
    stats_number(f, c->touches > 0 ? 1.0 - (double)c->pages / (double)c->touches : 1.0);
    fputs(", \"wait_s\": ", f);
    stats_number(f, c->wait_s);
    fputs(", \"install_s\": ", f);
    stats_number(f, c->install_s);
    fputc('}', f);
}

static void stats_workers(FILE *f, const render_stats *s)
{
    fputs("  \"workers\": [", f);
    for (int i = s->relays; i < s->worker_count; i++) {
        const stats_worker *w = &s->workers[i];
        fprintf(f, "%s\n    {\"rank\": %d, \"tiles\": %llu, \"items\": %llu, \"hits\": %llu, "
                   "\"busy_s\": ",
                i > s->relays ? "," : "", w->rank, (unsigned long long)w->tiles,
                (unsigned long long)w->items, (unsigned long long)w->hits);
        stats_number(f, w->busy_s);
        fputs(", \"busy_fraction\": ", f);
        stats_number(f, s->tile_phase_s > 0 ? w->busy_s / s->tile_phase_s : 0.0);
        fputs(", \"rays\": ", f);
        stats_rays(f, &w->rays);
        if (s->scene_memory > 0) {
            fputs(", \"paging\": ", f);
            stats_paging(f, &w->paging);
        }
        fputc('}', f);
    }
    fputs(s->worker_count > s->relays ? "\n  ]\n" : "]\n", f);
}

/* The phases (they add up to wall_s) and the figures derived from them,
 * in the order they are printed. */
#define STATS_TIMES(X)                                                                  \
    X(wall_s) X(setup_s) X(cl_setup_s) X(compile_s) X(primary_s) X(pipelined_s)      \
    X(secondary_s) X(write_s) X(pass_s) X(pass_kernel_s) X(pass_copy_s)              \
    X(pass_device_s) X(tile_phase_s) X(tail_s) X(busy_fraction)                      \
    X(estimate_spearman) X(master_cpu_s) X(master_results_s) X(store_cpu_s)     \
    X(pass_work_s) X(guess_cpu_s) X(cull_s) X(write_cpu_s)

static void stats_phases(FILE *f, const render_stats *s)
{
#define STATS_TIME_FIELD(name) stats_field(f, #name, s->name);
    STATS_TIMES(STATS_TIME_FIELD)
#undef STATS_TIME_FIELD
}

void stats_print_json(FILE *f, const render_stats *s)
{
    fputs("{\n  \"mode\": ", f);
    stats_string(f, s->mode);
    fputs(",\n  \"precision\": ", f);
    stats_string(f, s->precision);
    if (s->precision_why[0]) {
        fputs(",\n  \"precision_auto\": ", f);
        stats_string(f, s->precision_why);
    }
    fputs(",\n  \"device\": ", f);
    stats_string(f, s->device);
    fputs(",\n  \"cl_program\": ", f);
    stats_string(f, s->cl_program);
    fputs(",\n  \"schedule\": ", f);
    stats_string(f, s->schedule);
    fputs(",\n  \"cl_open\": ", f);
    stats_string(f, s->cl_open ? s->cl_open : "none");
    fprintf(f, ",\n  \"width\": %d,\n  \"height\": %d,\n  \"tile\": %d,\n  \"ranks\": %d,\n"
               "  \"spp\": %d,\n  \"in_flight\": %d,\n  \"relays\": %d,\n"
               "  \"relay_depth\": %d,\n  \"pieces\": %d,\n  \"store_threads\": %d,\n",
            s->width, s->height, s->tile, s->ranks, s->spp > 0 ? s->spp : 1, s->in_flight,
            s->relays, s->relay_depth, s->pieces > 0 ? s->pieces : 1, s->store_threads);
    stats_phases(f, s);
    fprintf(f, "  \"tiles_total\": %d,\n  \"tiles_sent\": %d,\n  \"tiles_degenerate\": %d,\n"
               "  \"items_sent\": %d,\n  \"slices\": %d,\n",
            s->tiles_total, s->tiles_sent, s->tiles_degenerate, s->items_sent, s->slices);
    fputs("  \"cl_records\": ", f);
    stats_string(f, s->slices == 0 ? "" : s->cl_records_in_place ? "in place" : "copied");
    fputs(",\n", f);
    fprintf(f,
            "  \"tiles_culled\": %d,\n  \"tiles_resumed\": %d,\n  \"tiles_rendered\": %d,\n"
            "  \"tiles_filled\": %d,\n",
            s->tiles_culled, s->tiles_resumed, s->tiles_sent, s->tiles_filled);
    fprintf(f, "  \"write_bands\": %d,\n  \"write_bands_early\": %d,\n", s->write_bands,
            s->write_bands_early);
    fprintf(f, "  \"batch\": %d,\n  \"tile_messages\": %llu,\n  \"answers_early\": %llu,\n",
            s->batch > 0 ? s->batch : 1, (unsigned long long)s->tile_messages,
            (unsigned long long)s->answers_early);
    fprintf(f, "  \"workers_lost\": %d,\n  \"items_reassigned\": %d,\n", s->workers_lost,
            s->items_reassigned);
    fprintf(f, "  \"pixels\": %llu,\n  \"pixels_hit\": %llu,\n  \"max_rays_per_pixel\": %d,\n"
               "  \"pixels_over_budget\": %llu,\n",
            (unsigned long long)s->pixels, (unsigned long long)s->pixels_hit, s->max_rays,
            (unsigned long long)s->rays.over_budget);
    stats_field(f, "occupancy", stats_occupancy(s));
    fputs("  \"rays\": ", f);
    stats_rays(f, &s->rays);
    fprintf(f, ",\n  \"bytes_sent\": %llu,\n  \"bytes_received\": %llu,\n  \"blob_bytes\": %llu,\n"
               "  \"memory_estimate\": %llu,\n",
            (unsigned long long)s->bytes_sent, (unsigned long long)s->bytes_received,
            (unsigned long long)s->blob_bytes, (unsigned long long)s->memory_estimate);
    fprintf(f, "  \"scene_shared_ranks\": %d,\n  \"scene_private_ranks\": %d,\n",
            s->scene_shared_ranks, s->scene_private_ranks);
    if (s->scene_memory > 0) {
        fprintf(f, "  \"scene_memory\": {\"budget_bytes\": %llu, \"page_bytes\": %llu, "
                   "\"pages\": %d, \"resident_bytes\": %llu, \"policy\": \"%s\", "
                   "\"prefetch\": %s, \"prefetch_shadows\": %s, \"fetch\": \"%s\", "
                   "\"asks_answered\": %llu, \"bytes_served\": %llu, \"homes\": %d},\n"
                   "  \"paging\": ",
                (unsigned long long)s->scene_memory, (unsigned long long)s->page_bytes,
                s->page_count, (unsigned long long)s->resident_bytes,
                s->page_policy ? s->page_policy : "lru",
                s->page_prefetch != PAGER_PREFETCH_OFF ? "true" : "false",
                s->page_prefetch == PAGER_PREFETCH_SHADOWS ? "true" : "false",
                s->page_fetch ? s->page_fetch : "ask", (unsigned long long)s->page_asks,
                (unsigned long long)s->page_bytes_served,
                s->page_homes);
        stats_paging(f, &s->paging);
        fputs(",\n", f);
    }
    fputs("  \"result_pixels\": ", f);
    stats_string(f, s->result_pixels ? s->result_pixels : "none");
    fputs(",\n  \"hit_records\": ", f);
    stats_string(f, s->hit_records ? s->hit_records : "none");
    fputs(",\n  \"link_mbps\": ", f);
    stats_number(f, s->link_mbps);
    fputs(",\n", f);
    stats_workers(f, s);
    fputs("}\n", f);
}

static void stats_print_json_any(FILE *f, const void *s)
{
    stats_print_json(f, s);
}

bool stats_write_json(const char *path, const render_stats *s, char *err, size_t err_size)
{
    return file_write_atomic(path, stats_print_json_any, s, err, err_size);
}

/* ---- the tile log ------------------------------------------------------------ */

typedef struct {
    const sched *s;
    double t0;
} stats_log;

/* `"key": v, ` with v relative to t0, or null. */
static void stats_log_time(FILE *f, const char *key, bool known, double v)
{
    fprintf(f, "\"%s\": ", key);
    if (known)
        stats_number(f, v);
    else
        fputs("null", f);
    fputs(", ", f);
}

static void stats_log_item(FILE *f, const sched_item *it, double t0)
{
    fprintf(f, "{\"tile\": %d, \"piece\": %d, \"x\": %d, \"y\": %d, \"width\": %d, "
               "\"height\": %d, \"skipped\": %s, \"resumed\": %s, \"fill\": %s, ",
            it->tile, it->piece, it->rect.x, it->rect.y, it->rect.width, it->rect.height,
            it->skipped ? "true" : "false", it->resumed ? "true" : "false",
            it->fill ? "true" : "false");
    stats_log_time(f, "estimate", it->estimate >= 0, it->estimate);
    fprintf(f, "\"hits\": %u, \"worker\": %d, ", (unsigned)it->hits,
            it->skipped ? 0 : it->worker);
    if (it->skipped)
        fputs("\"order\": null, ", f);
    else
        fprintf(f, "\"order\": %d, ", it->order);
    stats_log_time(f, "sent_s", !it->skipped, it->sent_s - t0);
    stats_log_time(f, "done_s", !it->skipped, it->done_s - t0);
    fputs("\"seconds\": ", f);
    stats_number(f, it->busy_s);
    fputs(", \"cpu_s\": ", f);
    stats_number(f, it->cpu_s);
    fprintf(f, ", \"page_faults\": %u, \"page_wait_s\": ", (unsigned)it->page_faults);
    stats_number(f, it->page_wait_s);
    fprintf(f, ", \"wire_bytes\": %u}\n", (unsigned)it->wire_bytes);
}

static void stats_print_log(FILE *f, const void *arg)
{
    const stats_log *log = arg;
    for (int i = 0; i < log->s->count; i++)
        if (!log->s->items[i].split)
            stats_log_item(f, &log->s->items[i], log->t0);
}

bool stats_write_tile_log(const char *path, const sched *s, double t0, char *err,
                          size_t err_size)
{
    stats_log log = {s, t0};
    return file_write_atomic(path, stats_print_log, &log, err, err_size);
}

void stats_print_summary(FILE *f, const render_stats *s)
{
    fprintf(f, "%s %dx%d %s ranks=%d wall=%.3fs tiles=%d sent=%d degenerate=%d occupancy=%.3f\n",
            s->mode, s->width, s->height, s->precision, s->ranks, s->wall_s, s->tiles_total,
            s->tiles_sent, s->tiles_degenerate,
            stats_occupancy(s));
}

/* ---- the figures of the tile phase ---------------------------------------------- */

/* The last result in minus the first worker idle for good. */
static double stats_tail(const sched *s, int first, int workers, double t_first, double t_last)
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
static double stats_spearman(const sched *s)
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
static int stats_skipped(const sched *s)
{
    int n = 0;
    for (int i = 0; i < s->count; i++)
        n += s->items[i].skipped && !s->items[i].resumed;
    return n;
}

/* Tiles the fill claimed and workers rendered from scratch (whole or cut). */
static int stats_filled(const sched *s)
{
    int n = 0;
    for (int i = 0; i < s->count; i++)
        n += s->items[i].fill && s->items[i].piece <= 1; /* (a cut tile: its first piece) */
    return n;
}

void stats_tile_figures(render_stats *st, const sched *s, double t_first, double t_last,
                        double busy_s)
{
    st->tile_phase_s = t_first > 0 ? t_last - t_first : 0.0;
    double span = st->tile_phase_s * (double)(st->worker_count - st->relays);
    st->busy_fraction = span > 0 ? busy_s / span : 0.0;
    st->tail_s = stats_tail(s, st->relays + 1, st->worker_count > 1 ? st->worker_count : 0,
                            t_first, t_last);
    st->estimate_spearman = stats_spearman(s);
    st->tiles_sent = s->added;
    st->tiles_degenerate = stats_skipped(s);
    st->tiles_filled = stats_filled(s);
    st->items_sent = s->dispatched;
    st->items_reassigned = s->requeued;
}
