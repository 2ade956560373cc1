/*
 * test_tile_sim.c — the cost maps of the simulated build
 * (sim/tile_sim.c):
 *   - a map read back gives each recorded tile its own totals;
 *   - any rectangle's cost is the area integral of the densities (a
 *     rectangle across cells, a partial cell);
 *   - an image twice the size costs four times as much in total (a pixel
 *     costs what the recorded pixel under it cost), a rectangle of it what
 *     the recorded area under it cost, times four;
 *   - malformed files are refused;
 *   - page traces (sim/page_trace.c): an item's pages read back in their
 *     order, a prefetch's marks kept; a rectangle no item had gets the
 *     union of the items it overlaps, each page once, prefetched if any
 *     item prefetched it; several files; malformed lines refused with
 *     their file:line.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../sim/page_trace.h"
#include "../sim/tile_sim.h"

/* `text` in a new temporary file; its path (valid until the next call). */
static const char *write_map(const char *text)
{
    static char path[] = "/tmp/test_tile_sim_XXXXXX";
    snprintf(path, sizeof path, "/tmp/test_tile_sim_XXXXXX");
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    fputs(text, f);
    fclose(f);
    return path;
}

static void near(double got, double want)
{
    if (fabs(got - want) > 1e-12) {
        print_error("got %.17g, expected %.17g\n", got, want);
        fail();
    }
}

/* A 4 x 2 image of 2-pixel cells: cell 0 = 8 s, 4 hits, estimate 100;
 * cell 1 = 4 s. */
static const char *MAP = "csgsim-costs 1 4 2 2 0.5\n8 4 100\n4 0 0\n";

static void test_cells_back(void **state)
{
    (void)state;
    sim_costs c;
    const char *path = write_map(MAP);
    assert_true(sim_costs_load(path, &c));
    remove(path);
    assert_int_equal(c.cols, 2);
    assert_int_equal(c.rows, 1);
    near(c.pass_s, 0.5);
    sim_cost a = sim_costs_rect(&c, 4, 2, (tile_rect){0, 0, 2, 2});
    near(a.seconds, 8);
    near(a.hits, 4);
    near(a.estimate, 100);
    near(sim_costs_rect(&c, 4, 2, (tile_rect){2, 0, 2, 2}).seconds, 4);
    /* across the two cells: half of each */
    near(sim_costs_rect(&c, 4, 2, (tile_rect){1, 0, 2, 2}).seconds, 6);
    /* one pixel */
    near(sim_costs_rect(&c, 4, 2, (tile_rect){3, 1, 1, 1}).seconds, 1);
    sim_costs_free(&c);
}

static void test_scaled(void **state)
{
    (void)state;
    sim_costs c;
    const char *path = write_map(MAP);
    assert_true(sim_costs_load(path, &c));
    remove(path);
    near(sim_costs_rect(&c, 8, 4, (tile_rect){0, 0, 8, 4}).seconds, 4 * 12);
    near(sim_costs_rect(&c, 8, 4, (tile_rect){0, 0, 4, 4}).seconds, 4 * 8);
    near(sim_costs_rect(&c, 8, 4, (tile_rect){0, 0, 1, 1}).seconds, 2);
    sim_costs_free(&c);
}

static void test_refused(void **state)
{
    (void)state;
    const char *bad[] = {"csgsim-costs 2 4 2 2 0\n8 4 1\n4 0 0\n",
                         "csgsim-costs 1 4 2 2 0\n8 4 1\n",
                         "csgsim-costs 1 0 2 2 0\n", "hello\n"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        sim_costs c;
        const char *path = write_map(bad[i]);
        assert_false(sim_costs_load(path, &c));
        remove(path);
    }
    sim_costs c;
    assert_false(sim_costs_load("/nonexistent/map", &c));
}

static void test_trace_pages(void **state)
{
    (void)state;
    page_trace t;
    char err[256];
    char a[64], b[64];
    snprintf(a, sizeof a, "%s", write_map("T 0 0 8 8 3 5 -3 7\nT 8 0 8 8 2 7 -6\n"));
    snprintf(b, sizeof b, "%s", write_map("S 0 0 8 8 1 -10\nT 0 8 8 8 0\n"));
    char both[160];
    snprintf(both, sizeof both, "%s:%s", a, b);
    assert_true(page_trace_load(&t, both, err, sizeof err));
    assert_int_equal(t.item_count, 4);
    assert_int_equal(t.page_max, 9);
    int32_t *pages;
    bool exact;
    assert_int_equal(page_trace_pages(&t, 'T', 0, 0, 8, 8, &pages, &exact), 3);
    assert_true(exact);
    assert_int_equal(pages[0], 5);
    assert_int_equal(pages[1], -3); /* page 2, prefetched */
    assert_int_equal(pages[2], 7);
    free(pages);
    assert_int_equal(page_trace_pages(&t, 'S', 0, 0, 8, 8, &pages, &exact), 1);
    assert_int_equal(pages[0], -10);
    free(pages);
    /* half of each of the two first tiles: pages 2, 5 and 7 once each; 5,
     * named on demand by one and prefetched by the other, prefetched */
    assert_int_equal(page_trace_pages(&t, 'T', 4, 0, 8, 4, &pages, &exact), 3);
    assert_false(exact);
    assert_int_equal(pages[0], -3);
    assert_int_equal(pages[1], -6);
    assert_int_equal(pages[2], 7);
    free(pages);
    assert_int_equal(page_trace_pages(&t, 'T', 0, 8, 8, 8, &pages, &exact), 0);
    assert_true(exact);
    assert_int_equal(page_trace_pages(&t, 'T', 100, 100, 8, 8, &pages, &exact), 0);
    assert_false(exact);
    page_trace_free(&t);
    remove(a);
    remove(b);
}

static void test_trace_refused(void **state)
{
    (void)state;
    const char *bad[] = {"T 0 0 8 8 2 1\n", "T 0 0 8 8 1 1 2\n", "X 0 0 8 8 0\n",
                         "T 0 0 0 8 0\n", "T -1 0 8 8 0\n", "T 0 0 8 8 1 z\n", "T\n"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        page_trace t;
        char err[256];
        char path[64];
        snprintf(path, sizeof path, "%s", write_map(bad[i]));
        assert_false(page_trace_load(&t, path, err, sizeof err));
        assert_non_null(strstr(err, ":1: "));
        remove(path);
    }
    page_trace t;
    char err[256];
    assert_false(page_trace_load(&t, "/nonexistent/trace", err, sizeof err));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cells_back),
        cmocka_unit_test(test_scaled),
        cmocka_unit_test(test_refused),
        cmocka_unit_test(test_trace_pages),
        cmocka_unit_test(test_trace_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
