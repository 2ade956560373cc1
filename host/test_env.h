/*
 * test_env.h — the test hooks' numbers from the environment
 * (CSGTRACE_TEST_*: render.c, ocl.c), read one way.
 */
#ifndef HOST_TEST_ENV_H
#define HOST_TEST_ENV_H

#include <stdlib.h>

/* $name as a whole number from 1 to below `bound`; 0 when unset or
 * anything else. */
static inline long long test_env_number(const char *name, long long bound)
{
    const char *v = getenv(name);
    char *end;
    long long n = v ? strtoll(v, &end, 10) : 0;
    return v && end != v && !*end && n > 0 && n < bound ? n : 0;
}

#endif
