/*
 * test_stats.c — the stats JSON writer (host/stats.c): the output parses as
 * JSON (a small strict recursive-descent parser below), holds every field
 * benchmarks read with the values given, escapes strings, turns non-finite
 * numbers into null, and the file is written whole (temporary + rename);
 * the phases add up to wall_s (stats_phase_sum) and the tile log is one
 * valid JSON object a line, one line an item.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../host/stats.h"

/* ---- a strict JSON parser: validates, finds members ---------------------- */

static const char *js_ws(const char *p)
{
    while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r')
        p++;
    return p;
}

static const char *js_value(const char *p);

/* A string; its decoded text (ASCII and \uXXXX < 0x80 only) into out. */
static const char *js_string(const char *p, char *out, size_t n)
{
    size_t k = 0;
    if (!p || *p != '"')
        return NULL;
    for (p++; *p != '"'; p++) {
        char c = *p;
        if ((unsigned char)c < 0x20)
            return NULL;
        if (c == '\\') {
            p++;
            if (*p == 'u') {
                unsigned v;
                if (sscanf(p + 1, "%4x", &v) != 1)
                    return NULL;
                c = (char)v;
                p += 4;
            } else if (*p == 'n') {
                c = '\n';
            } else if (*p == '"' || *p == '\\' || *p == '/') {
                c = *p;
            } else {
                return NULL;
            }
        }
        if (out && k + 1 < n)
            out[k++] = c;
    }
    if (out)
        out[k] = '\0';
    return p + 1;
}

static const char *js_number(const char *p)
{
    const char *start = p;
    if (*p == '-')
        p++;
    if (*p < '0' || *p > '9')
        return NULL;
    while ((*p >= '0' && *p <= '9') || *p == '.' || *p == 'e' || *p == 'E' || *p == '+' ||
           *p == '-')
        p++;
    char *end;
    strtod(start, &end);
    return end == p ? p : NULL;
}

static const char *js_container(const char *p, char open, char close, bool keyed)
{
    if (*p != open)
        return NULL;
    p = js_ws(p + 1);
    if (*p == close)
        return p + 1;
    for (;;) {
        if (keyed) {
            p = js_string(p, NULL, 0);
            if (!p || *(p = js_ws(p)) != ':')
                return NULL;
            p = js_ws(p + 1);
        }
        p = js_value(p);
        if (!p)
            return NULL;
        p = js_ws(p);
        if (*p == close)
            return p + 1;
        if (*p != ',')
            return NULL;
        p = js_ws(p + 1);
    }
}

static const char *js_value(const char *p)
{
    p = js_ws(p);
    switch (*p) {
    case '{': return js_container(p, '{', '}', true);
    case '[': return js_container(p, '[', ']', false);
    case '"': return js_string(p, NULL, 0);
    case 't': return strncmp(p, "true", 4) ? NULL : p + 4;
    case 'f': return strncmp(p, "false", 5) ? NULL : p + 5;
    case 'n': return strncmp(p, "null", 4) ? NULL : p + 4;
    default: return js_number(p);
    }
}

/* The whole text is one JSON value. */
static bool js_valid(const char *text)
{
    const char *end = js_value(text);
    return end && *js_ws(end) == '\0';
}

/* The value of member `key` of the object at obj, or NULL. */
static const char *js_member(const char *obj, const char *key)
{
    char name[128];
    if (!obj || !js_value(obj))
        return NULL; /* not a whole valid value: nothing to find */
    const char *p = js_ws(obj);
    if (*p != '{')
        return NULL;
    p = js_ws(p + 1);
    while (*p == '"') {
        p = js_string(p, name, sizeof name);
        p = js_ws(js_ws(p) + 1); /* past ':' */
        if (!strcmp(name, key))
            return p;
        p = js_ws(js_value(p));
        if (*p != ',')
            return NULL;
        p = js_ws(p + 1);
    }
    return NULL;
}

/* Element i of the array at arr, or NULL. */
static const char *js_element(const char *arr, int i)
{
    if (!arr || !js_value(arr))
        return NULL;
    const char *p = js_ws(arr);
    if (*p != '[')
        return NULL;
    p = js_ws(p + 1);
    for (int k = 0; *p != ']'; k++) {
        if (k == i)
            return p;
        p = js_ws(js_value(p));
        if (*p == ',')
            p = js_ws(p + 1);
    }
    return NULL;
}

static double js_num(const char *obj, const char *key)
{
    const char *v = js_member(obj, key);
    assert_non_null(v);
    return strtod(v, NULL);
}

/* ---- fixtures --------------------------------------------------------------- */

typedef struct {
    render_stats s;
    stats_worker w[2];
    char *json;   /* stats_print_json output */
} fixture;

static char *print_json(const render_stats *s)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    assert_non_null(f);
    stats_print_json(f, s);
    fclose(f);
    return buf;
}

static int setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    render_stats *s = &fx->s;
    s->mode = "hetero";
    s->precision = "float";
    snprintf(s->device, sizeof s->device, "pthread-cpu");
    s->width = 64;
    s->height = 48;
    s->tile = 16;
    s->ranks = 3;
    s->schedule = "cost";
    s->in_flight = 2;
    s->wall_s = 1.5;
    s->setup_s = 0.01;
    s->cl_setup_s = 0.0625;
    s->compile_s = 0.25;
    s->primary_s = 0.125;
    s->pipelined_s = 0.0;
    s->secondary_s = 1.0;
    s->write_s = 0.05;
    s->wall_s = s->setup_s + s->cl_setup_s + s->compile_s + s->primary_s + s->pipelined_s +
                s->secondary_s + s->write_s;
    s->pass_s = 0.125;
    s->tile_phase_s = 1.0;
    s->tail_s = 0.03125;
    s->busy_fraction = 0.625;
    s->estimate_spearman = 0.875;
    s->slices = 3;
    s->items_sent = 10;
    s->tiles_total = 12;
    s->tiles_sent = 7;
    s->tiles_degenerate = 5;
    s->pixels = 3072;
    s->pixels_hit = 768;
    s->max_rays = 4096;
    s->rays = (ray_counts){ 3072, 500, 40, 3, 2, 0 };
    s->bytes_sent = 123456;
    s->bytes_received = 654321;
    s->blob_bytes = 4096;
    fx->w[0] = (stats_worker){ 1, 4, 400, { 0, 300, 30, 1, 0, 0 }, 0.5, 6, {0} };
    fx->w[1] = (stats_worker){ 2, 3, 368, { 0, 200, 10, 2, 2, 0 }, 0.75, 4, {0} };
    s->worker_count = 2;
    s->workers = fx->w;
    *state = fx;
    return 0;
}

static int teardown(void **state)
{
    fixture *fx = *state;
    free(fx->json);
    free(fx);
    return 0;
}

/* ---- tests ------------------------------------------------------------------ */

static void test_parses_with_every_field(void **state)
{
    fixture *fx = *state;
    fx->json = print_json(&fx->s);
    assert_true(js_valid(fx->json));
    const char *need[] = { "mode", "precision", "width", "height", "tile", "ranks", "wall_s",
                           "primary_s", "secondary_s", "compile_s", "tiles_total", "tiles_sent",
                           "tiles_degenerate", "occupancy", "rays", "bytes_sent", "workers" };
    for (size_t i = 0; i < sizeof need / sizeof *need; i++) {
        if (!js_member(fx->json, need[i]))
            fail_msg("missing field %s", need[i]);
    }
    const char *rays = js_member(fx->json, "rays");
    const char *ray_keys[] = { "primary", "shadow", "reflected", "refracted" };
    for (size_t i = 0; i < 4; i++)
        assert_non_null(js_member(rays, ray_keys[i]));
}

static void test_values(void **state)
{
    fixture *fx = *state;
    char mode[32];
    fx->json = print_json(&fx->s);
    assert_non_null(js_string(js_member(fx->json, "mode"), mode, sizeof mode));
    assert_string_equal(mode, "hetero");
    assert_true(js_num(fx->json, "width") == 64.0);
    assert_true(js_num(fx->json, "ranks") == 3.0);
    assert_true(js_num(fx->json, "wall_s") == fx->s.wall_s);
    assert_true(js_num(fx->json, "compile_s") == 0.25);
    assert_true(js_num(fx->json, "tiles_sent") == 7.0);
    assert_true(js_num(fx->json, "tiles_degenerate") == 5.0);
    assert_true(js_num(fx->json, "occupancy") == 0.25);
    assert_true(js_num(fx->json, "bytes_sent") == 123456.0);
    const char *rays = js_member(fx->json, "rays");
    assert_true(js_num(rays, "primary") == 3072.0);
    assert_true(js_num(rays, "refracted") == 3.0);
    assert_true(js_num(rays, "total") == 3072.0 + 500 + 40 + 3);
    assert_true(js_num(fx->json, "max_rays_per_pixel") == 4096.0);
    assert_true(js_num(fx->json, "pixels_over_budget") == 2.0);
    assert_true(js_num(fx->json, "tail_s") == 0.03125);
    assert_true(js_num(fx->json, "busy_fraction") == 0.625);
    assert_true(js_num(fx->json, "estimate_spearman") == 0.875);
    assert_true(js_num(fx->json, "items_sent") == 10.0);
    char policy[32];
    assert_non_null(js_string(js_member(fx->json, "schedule"), policy, sizeof policy));
    assert_string_equal(policy, "cost");
}

/* Every phase is printed, and the printed phases add up to wall_s. */
static void test_phases_add_up(void **state)
{
    fixture *fx = *state;
    const char *phases[] = { "setup_s", "cl_setup_s", "compile_s", "primary_s", "pipelined_s",
                             "secondary_s", "write_s" };
    fx->s.pipelined_s = 0.5; /* an overlap, accounted once */
    fx->s.secondary_s = 0.5;
    fx->json = print_json(&fx->s);
    double sum = 0;
    for (size_t i = 0; i < sizeof phases / sizeof *phases; i++)
        sum += js_num(fx->json, phases[i]);
    assert_true(fabs(sum - js_num(fx->json, "wall_s")) < 1e-9);
    assert_true(fabs(stats_phase_sum(&fx->s) - fx->s.wall_s) < 1e-12);
    const char *derived[] = { "pass_s", "pass_kernel_s", "pass_copy_s", "pass_device_s", "tile_phase_s", "tail_s", "busy_fraction",
                              "estimate_spearman", "slices", "in_flight", "master_cpu_s", "master_results_s",
                              "relay_depth", "pieces", "store_threads", "store_cpu_s", "pass_work_s", "guess_cpu_s",
                              "cull_s", "tiles_culled" };
    for (size_t i = 0; i < sizeof derived / sizeof *derived; i++)
        if (!js_member(fx->json, derived[i]))
            fail_msg("missing field %s", derived[i]);
}

/* The tile log: one valid object a line, skipped tiles with null times. */
static void test_tile_log(void **state)
{
    (void)state;
    sched s;
    tile_rect a = { 0, 0, 16, 16 }, b = { 16, 0, 16, 16 };
    assert_true(sched_init(&s, SCHED_RASTER, 2, 2, 2, NULL, NULL));
    assert_true(sched_skip(&s, 0, a));
    assert_true(sched_add(&s, 1, b));
    sched_close(&s);
    int item = sched_next(&s, 0, 10.5);
    assert_int_equal(item, 1);
    s.items[item].worker = 2;
    s.items[item].done_s = 10.75;
    s.items[item].busy_s = 0.125;
    s.items[item].cpu_s = 0.0625;
    char dir[] = "/tmp/test_stats.XXXXXX", path[256], err[256] = "", line[1024];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/log.jsonl", dir);
    assert_true(stats_write_tile_log(path, &s, 10.0, err, sizeof err));
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    int lines = 0;
    while (fgets(line, sizeof line, f)) {
        assert_true(js_valid(line));
        if (lines == 0) {
            assert_int_equal(strncmp(js_member(line, "skipped"), "true", 4), 0);
            assert_int_equal(strncmp(js_member(line, "sent_s"), "null", 4), 0);
        } else {
            assert_true(js_num(line, "tile") == 1.0 && js_num(line, "x") == 16.0);
            assert_true(js_num(line, "worker") == 2.0 && js_num(line, "order") == 0.0);
            assert_true(js_num(line, "sent_s") == 0.5 && js_num(line, "done_s") == 0.75);
            assert_true(js_num(line, "seconds") == 0.125 && js_num(line, "cpu_s") == 0.0625);
            assert_int_equal(strncmp(js_member(line, "estimate"), "null", 4), 0);
        }
        lines++;
    }
    fclose(f);
    assert_int_equal(lines, 2);
    unlink(path);
    rmdir(dir);
    sched_free(&s);
}

static void test_workers(void **state)
{
    fixture *fx = *state;
    fx->json = print_json(&fx->s);
    const char *ws = js_member(fx->json, "workers");
    assert_non_null(ws);
    const char *w1 = js_element(ws, 1);
    assert_non_null(w1);
    assert_null(js_element(ws, 2));
    assert_true(js_num(w1, "rank") == 2.0);
    assert_true(js_num(w1, "tiles") == 3.0);
    assert_true(js_num(w1, "busy_s") == 0.75);
    assert_true(js_num(w1, "items") == 4.0);
    assert_true(js_num(w1, "busy_fraction") == 0.75); /* busy_s / tile_phase_s */
    assert_true(js_num(js_member(w1, "rays"), "shadow") == 200.0);
}

static void test_no_workers(void **state)
{
    fixture *fx = *state;
    fx->s.worker_count = 0;
    fx->json = print_json(&fx->s);
    assert_true(js_valid(fx->json));
    assert_null(js_element(js_member(fx->json, "workers"), 0));
}

static void test_escaping_and_non_finite(void **state)
{
    fixture *fx = *state;
    char device[256];
    snprintf(fx->s.device, sizeof fx->s.device, "a \"quoted\" \\ dev\nice\t");
    fx->s.wall_s = NAN;
    fx->s.primary_s = INFINITY;
    fx->json = print_json(&fx->s);
    assert_true(js_valid(fx->json));
    assert_non_null(js_string(js_member(fx->json, "device"), device, sizeof device));
    assert_string_equal(device, fx->s.device);
    assert_int_equal(strncmp(js_member(fx->json, "wall_s"), "null", 4), 0);
    assert_int_equal(strncmp(js_member(fx->json, "primary_s"), "null", 4), 0);
}

static void test_write_file(void **state)
{
    fixture *fx = *state;
    char dir[] = "/tmp/test_stats.XXXXXX", path[256], err[256] = "";
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/s.json", dir);
    assert_true(stats_write_json(path, &fx->s, err, sizeof err));

    FILE *f = fopen(path, "r");
    assert_non_null(f);
    char buf[8192];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    fx->json = print_json(&fx->s);
    assert_string_equal(buf, fx->json);

    int entries = 0; /* only s.json: the temporary file was renamed */
    DIR *d = opendir(dir);
    for (struct dirent *e; (e = readdir(d));)
        entries += e->d_name[0] != '.';
    closedir(d);
    assert_int_equal(entries, 1);
    unlink(path);
    rmdir(dir);
}

static void test_write_failure(void **state)
{
    fixture *fx = *state;
    char err[256] = "";
    assert_false(stats_write_json("/nonexistent-dir-csgtrace/s.json", &fx->s, err, sizeof err));
    assert_non_null(strstr(err, "error:"));
    assert_non_null(strstr(err, "/nonexistent-dir-csgtrace/s.json"));
}

static void test_summary_line(void **state)
{
    fixture *fx = *state;
    size_t len = 0;
    FILE *f = open_memstream(&fx->json, &len);
    stats_print_summary(f, &fx->s);
    fclose(f);
    assert_non_null(strstr(fx->json, "hetero 64x48"));
    assert_non_null(strstr(fx->json, "ranks=3"));
    assert_non_null(strstr(fx->json, "degenerate=5"));
    assert_true(len > 0);
    assert_ptr_equal(strchr(fx->json, '\n'), fx->json + len - 1); /* one line */
}

static void test_parser_rejects(void **state)
{
    (void)state;
    assert_false(js_valid("{\"a\": 1,}"));
    assert_false(js_valid("{\"a\" 1}"));
    assert_false(js_valid("{\"a\": nan}"));
    assert_false(js_valid("{\"a\": \"x\ny\"}"));
    assert_true(js_valid("{\"a\": [1, -2.5e3, null, {\"b\": true}]}"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_parses_with_every_field, setup, teardown),
        cmocka_unit_test_setup_teardown(test_values, setup, teardown),
        cmocka_unit_test_setup_teardown(test_workers, setup, teardown),
        cmocka_unit_test_setup_teardown(test_phases_add_up, setup, teardown),
        cmocka_unit_test(test_tile_log),
        cmocka_unit_test_setup_teardown(test_no_workers, setup, teardown),
        cmocka_unit_test_setup_teardown(test_escaping_and_non_finite, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_file, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_failure, setup, teardown),
        cmocka_unit_test_setup_teardown(test_summary_line, setup, teardown),
        cmocka_unit_test(test_parser_rejects),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
