/*
 * decimal.h — a plain decimal number to the nearest double, without strtod
 * when that is exact.
 *
 * Scene files hold mostly short decimals ("0.288675", "-12.5e2"), and
 * strtod's arbitrary-precision path was 14 % of reading tetra8.nff.  For
 * such a number, with at most 19 significant digits whose value w is at
 * most 2^53 and a decimal exponent e with |e| <= 22, both w and 10^|e| are
 * doubles exactly, so one multiplication or division, correctly rounded
 * by IEEE 754, gives the double nearest w x 10^e: strtod's own result, to
 * the bit (Clinger's fast path, "How to read floating point numbers
 * accurately", PLDI 1990; it needs double arithmetic without excess
 * precision, FLT_EVAL_METHOD 0, as on x86-64).  Anything else (more
 * digits, a larger exponent, hexadecimal, inf, nan, stray characters) is
 * left to the caller's strtod: csg_decimal_fast says false.
 */
#ifndef CSG_LANG_DECIMAL_H
#define CSG_LANG_DECIMAL_H

#include <float.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "csg_decimal_fast needs double arithmetic without excess precision"
#endif

/* s[0 .. len) as [+-] digits [. digits] [(e|E) [+-] digits], at least one
 * digit before the exponent, into *out when that is exact (above). */
static inline bool csg_decimal_fast(const char *s, size_t len, double *out)
{
    static const double tens[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                    1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                    1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    size_t i = 0;
    bool negative = false;
    if (i < len && (s[i] == '+' || s[i] == '-'))
        negative = s[i++] == '-';
    uint64_t w = 0;
    int significant = 0, scale = 0, digits = 0;
    bool point = false;
    for (; i < len; i++) {
        char c = s[i];
        if (c == '.' && !point) {
            point = true;
            continue;
        }
        if (c < '0' || c > '9')
            break;
        digits++;
        scale -= point; /* (a digit after the point: one tenth more) */
        if (w == 0 && c == '0')
            continue; /* a leading zero: no significant digit */
        if (++significant > 19)
            return false;
        w = w * 10 + (uint64_t)(c - '0');
    }
    if (digits == 0)
        return false;
    if (i < len && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        bool minus = false;
        if (i < len && (s[i] == '+' || s[i] == '-'))
            minus = s[i++] == '-';
        if (i == len)
            return false;
        int e = 0;
        for (; i < len && s[i] >= '0' && s[i] <= '9'; i++)
            if ((e = e * 10 + (s[i] - '0')) > 1000)
                return false; /* (far outside the fast path anyway) */
        scale += minus ? -e : e;
    }
    if (i != len || w > (UINT64_C(1) << 53))
        return false;
    double v = (double)w;
    if (w != 0) {
        if (scale < -22 || scale > 22)
            return false;
        v = scale < 0 ? v / tens[-scale] : v * tens[scale];
    }
    *out = negative ? -v : v;
    return true;
}

#endif
