/*
 * test_tile_sim.c — the cost maps of the simulated build
 * (sim/tile_sim.c):
 *   - a map read back gives each recorded tile its own totals;
 *   - any rectangle's cost is the area integral of the densities (a
 *     rectangle across cells, a partial cell);
 *   - an image twice the size costs four times as much in total (a pixel
 *     costs what the recorded pixel under it cost), a rectangle of it what
 *     the recorded area under it cost, times four;
 *   - malformed files are refused.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cells_back),
        cmocka_unit_test(test_scaled),
        cmocka_unit_test(test_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
