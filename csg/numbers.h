/*
 * numbers.h — a number written as text (an option's value, a setting of
 * the environment) read one way everywhere: the whole text, in range, or
 * nothing.  (The scene language reads its own numbers: lang/decimal.h.)
 */
#ifndef CSG_NUMBERS_H
#define CSG_NUMBERS_H

#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>

/* The whole number `text` spells (decimal, optional sign), when it lies
 * in [lo, hi]: *out set, true; else false, *out untouched. */
static inline bool number_whole(const char *text, long long lo, long long hi, long long *out)
{
    char *end;
    if (!text)
        return false;
    errno = 0;
    long long v = strtoll(text, &end, 10);
    if (errno || end == text || *end || v < lo || v > hi)
        return false;
    *out = v;
    return true;
}

/* The real number `text` spells, finite and in [lo, hi]: *out set, true;
 * else false, *out untouched. */
static inline bool number_real(const char *text, double lo, double hi, double *out)
{
    char *end;
    if (!text)
        return false;
    errno = 0;
    double v = strtod(text, &end);
    if (errno || end == text || *end || !(v >= lo && v <= hi))
        return false;
    *out = v;
    return true;
}

#endif
