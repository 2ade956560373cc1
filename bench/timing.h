/*
 * timing.h — what the benchmark helpers share (bench/primary_rays.c,
 * bench/primary_pass.c, bench/embree_primary.c, bench/store_threads.c,
 * bench/nap_cost.c): the clocks, the median and
 * the options they have in common; header only, so the Embree helper needs
 * nothing of csgtrace's objects.
 */
#ifndef BENCH_TIMING_H
#define BENCH_TIMING_H

#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Seconds on `clock` (CLOCK_THREAD_CPUTIME_ID: this thread's CPU time). */
static inline double bench_clock_s(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static inline double bench_now_s(void)
{
    return bench_clock_s(CLOCK_MONOTONIC);
}

static int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Sorts t[0..n) (n >= 1) and returns its median. */
static inline double bench_median(double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, bench_cmp_double);
    return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

/* A whole number of lo..hi in s, nothing else. */
static inline bool bench_parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi)
        return false;
    *out = (int)v;
    return true;
}

/* The options every helper takes. */
typedef struct {
    int width, height, repeat;
    bool dbl; /* --precision double */
} bench_options;

/* argv[*i] when it is one of the common options with a valid value (then
 * *i moves past the value); false otherwise, *i unchanged. */
static inline bool bench_common_option(int argc, char **argv, int *i, bench_options *o)
{
    const char *a = argv[*i], *v = *i + 1 < argc ? argv[*i + 1] : NULL;
    bool ok = false;
    if (!v)
        return false;
    if (!strcmp(a, "--width"))
        ok = bench_parse_int(v, 1, 1 << 15, &o->width);
    else if (!strcmp(a, "--height"))
        ok = bench_parse_int(v, 1, 1 << 15, &o->height);
    else if (!strcmp(a, "--repeat"))
        ok = bench_parse_int(v, 1, 1000, &o->repeat);
    else if (!strcmp(a, "--precision") && (!strcmp(v, "float") || !strcmp(v, "double")))
        ok = (o->dbl = !strcmp(v, "double"), true);
    if (ok)
        (*i)++;
    return ok;
}

#endif
