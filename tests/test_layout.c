/*
 * test_layout.c — the structs of csg/device/flat.h that the device reads
 * have the same layout in C and in OpenCL C, in both precisions.
 *
 * The probe kernel csg_layout (simd_kernels/primary.cl) writes sizeof and
 * offsetof of every entry of CSG_LAYOUT_FIELDS (csg/device/flat.h); this
 * file expands the same list with the C compiler
 * in its precision and compares entry by entry.  It is compiled as is
 * (float) and, through tests/test_layout_double.c, with -DCSG_DOUBLE.  The
 * program is built through host/pass/ocl.c, so the probe runs in the very
 * program the renderer uses.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "../csg/device/camera.h"
#include "../host/pass/ocl.h"

#define LAYOUT_CAP 128

#define C_SIZE(T) out[n++] = (int32_t)sizeof(T);
#define C_FIELD(T, f) out[n++] = (int32_t)offsetof(T, f);

static const char *const layout_names[] = {
#define NAME_SIZE(T) "sizeof(" #T ")",
#define NAME_FIELD(T, f) "offsetof(" #T ", " #f ")",
    CSG_LAYOUT_FIELDS(NAME_SIZE, NAME_FIELD)};

static int c_layout(int32_t *out)
{
    int n = 0;
    CSG_LAYOUT_FIELDS(C_SIZE, C_FIELD)
    return n;
}

static void check_layout(int use_double)
{
    int32_t expect[LAYOUT_CAP], got[LAYOUT_CAP];
    int n_expect = c_layout(expect);
    assert_int_equal(n_expect, (int)(sizeof layout_names / sizeof layout_names[0]));

    ocl_options opt = {.device = NULL, .use_double = use_double, .max_slice_bytes = 0};
    ocl_timing timing = {0};
    csg_diag d = {0};
    ocl_ctx *ctx = NULL;
    if (!ocl_open(&opt, &ctx, &timing, &d))
        fail_msg("ocl_open: %s", d.message);
    int n_got = 0;
    bool ok = ocl_probe_layout(ctx, got, LAYOUT_CAP, &n_got, &d);
    ocl_close(ctx);
    if (!ok)
        fail_msg("probe: %s", d.message);
    assert_int_equal(n_got, n_expect);
    int bad = 0;
    for (int i = 0; i < n_expect; i++)
        if (got[i] != expect[i]) {
            print_error("%s %s: C %d, OpenCL %d\n", use_double ? "double" : "float",
                        layout_names[i], (int)expect[i], (int)got[i]);
            bad++;
        }
    assert_int_equal(bad, 0);
}

static void test_layout(void **state)
{
    (void)state;
    check_layout(sizeof(real) == 8);
}

/* The probe itself can fail: a too small output reports an error. */
static void test_probe_cap(void **state)
{
    (void)state;
    ocl_options opt = {0};
    ocl_timing timing = {0};
    csg_diag d = {0};
    ocl_ctx *ctx = NULL;
    if (!ocl_open(&opt, &ctx, &timing, &d))
        fail_msg("ocl_open: %s", d.message);
    int32_t small[4];
    int n = -1;
    bool ok = ocl_probe_layout(ctx, small, 4, &n, &d);
    ocl_close(ctx);
    assert_false(ok);
    assert_int_equal(n, 0);
    assert_true(d.failed);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layout),
        cmocka_unit_test(test_probe_cap),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
