/*
 * fuzz_rng.h — the seeded generator of the mutation fuzzers
 * (test_fuzz_parser.c, test_nff.c): xorshift64*, so the same seed gives
 * the same inputs and a failure replays.
 */
#ifndef TESTS_FUZZ_RNG_H
#define TESTS_FUZZ_RNG_H

#include <stddef.h>
#include <stdint.h>

static uint64_t rng_next(uint64_t *s)
{
    uint64_t x = *s;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    *s = x;
    return x * 2685821657736338717ull;
}

/* Uniform enough in [0, n); 0 when n is 0. */
static size_t rng_below(uint64_t *s, size_t n)
{
    return n ? (size_t)(rng_next(s) % n) : 0;
}

#endif
