/*
 * test_decimal.c — csg/lang/decimal.h, the readers' fast path from a
 * decimal to a double: wherever it answers, its value is strtod's to the
 * bit (seeded random decimals of every shape: 1 to 21 significant digits,
 * leading and trailing zeros, the point anywhere or absent, exponents
 * -40 .. 40, signs; and the edges: 2^53 and its neighbours, 10^22 and
 * 10^23, zeros and negative zeros), it answers the common short decimals
 * (or it would not speed anything), and it refuses what strtod reads but
 * the fast path cannot, or what is no plain decimal at all.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/lang/decimal.h"
#include "fuzz_rng.h"

#define DECIMAL_RUNS 400000
#define DECIMAL_SEED 0xdec1a1f00d2026ull

/* The fast path on s: if it answers, the answer is strtod's, bit for bit
 * (signed zeros included); returns whether it answered. */
static bool agrees_with_strtod(const char *s)
{
    double fast;
    if (!csg_decimal_fast(s, strlen(s), &fast))
        return false;
    char *end;
    double slow = strtod(s, &end);
    if (*end != '\0' || memcmp(&fast, &slow, sizeof fast) != 0)
        fail_msg("'%s': fast %.17g, strtod %.17g", s, fast, slow);
    return true;
}

static void test_edges(void **state)
{
    (void)state;
    static const char *const answered[] = {
        "0", "-0", "+0", "0.0", "-0.000", "0e5", "-0e-7", ".5", "5.", "-.25", "1", "10", "0.1",
        "0.288675", "-12.5e2", "1e22", "1e-22", "9007199254740992", "9007199254740991",
        "4.503599627370496e15", "12345678901234e-10", "0.000001", "1.00000000000000",
        "3.14159265358979", "2.5E+3", "7e0",
    };
    for (size_t i = 0; i < sizeof answered / sizeof *answered; i++)
        if (!agrees_with_strtod(answered[i]))
            fail_msg("'%s' should take the fast path", answered[i]);
    static const char *const left_to_strtod[] = {
        "9007199254740993",     /* 2^53 + 1: not a double exactly          */
        "1e23",                 /* 10^23: not a double exactly             */
        "1e-23", "12345678901234567890", "1.0000000000000000000", /* 20 digits */
        "123456789012345678e-10", "1.000000000000000000", /* over 2^53 */
        "0x10", "inf", "nan", "", "+", "-", ".", "e5", "1e", "1e+", "1e5x", "1.2.3", "--1",
        "1 ", " 1", "1e99999",
    };
    for (size_t i = 0; i < sizeof left_to_strtod / sizeof *left_to_strtod; i++)
        if (agrees_with_strtod(left_to_strtod[i]))
            fail_msg("'%s' should be left to strtod", left_to_strtod[i]);
}

/* A random decimal of some shape into buf. */
static void random_decimal(uint64_t *rng, char *buf, size_t cap)
{
    size_t n = 0;
    int r = (int)rng_below(rng, 4);
    if (r == 0)
        buf[n++] = '-';
    else if (r == 1)
        buf[n++] = '+';
    int zeros = (int)rng_below(rng, 4) == 0 ? (int)rng_below(rng, 6) : 0;
    int digits = 1 + (int)rng_below(rng, 21);
    int total = zeros + digits, point = (int)rng_below(rng, (size_t)total + 2) - 1;
    for (int i = 0; i < total && n + 3 < cap; i++) {
        if (i == point)
            buf[n++] = '.';
        buf[n++] = i < zeros ? '0' : (char)('0' + rng_below(rng, 10));
    }
    if (point == total && n + 1 < cap)
        buf[n++] = '.';
    if (rng_below(rng, 2) == 0)
        n += (size_t)snprintf(buf + n, cap - n, "%s%d", rng_below(rng, 2) ? "e" : "E",
                              (int)rng_below(rng, 81) - 40);
    buf[n] = '\0';
}

static void test_random_decimals_equal_strtod(void **state)
{
    (void)state;
    uint64_t rng = DECIMAL_SEED;
    char buf[64];
    long answered = 0;
    for (long i = 0; i < DECIMAL_RUNS; i++) {
        random_decimal(&rng, buf, sizeof buf);
        answered += agrees_with_strtod(buf);
    }
    /* about half the shapes fit the fast path; none may disagree */
    assert_true(answered > DECIMAL_RUNS / 4);
    assert_true(answered < DECIMAL_RUNS);
}

/* What scene files hold: up to 7 significant digits, small exponents. */
static void test_scene_numbers_take_the_fast_path(void **state)
{
    (void)state;
    uint64_t rng = DECIMAL_SEED + 1;
    char buf[64];
    for (int i = 0; i < 100000; i++) {
        double v = ((double)rng_below(&rng, 20000001) - 10000000) / 10000.0;
        snprintf(buf, sizeof buf, "%.*f", (int)rng_below(&rng, 7), v);
        if (!agrees_with_strtod(buf))
            fail_msg("'%s' should take the fast path", buf);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_edges),
        cmocka_unit_test(test_random_decimals_equal_strtod),
        cmocka_unit_test(test_scene_numbers_take_the_fast_path),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
