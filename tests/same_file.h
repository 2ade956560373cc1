/*
 * same_file.h — do two files hold the same bytes?  Shared by the tests
 * that compare written images byte for byte (test_pixels.c, test_image.c).
 */
#ifndef TESTS_SAME_FILE_H
#define TESTS_SAME_FILE_H

#include <stdbool.h>
#include <stdio.h>

static inline bool same_file(const char *a, const char *b)
{
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    bool same = fa && fb;
    while (same) {
        int ca = fgetc(fa), cb = fgetc(fb);
        same = ca == cb;
        if (ca == EOF)
            break;
    }
    if (fa)
        fclose(fa);
    if (fb)
        fclose(fb);
    return same;
}

#endif
