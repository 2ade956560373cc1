/*
 * summary_text.h — what `csgtrace check` prints of a scene
 * (csg_print_summary), as a string the caller frees; NULL when out of
 * memory.  Shared by the tests that read it (test_parser.c, test_nff.c).
 */
#ifndef TESTS_SUMMARY_TEXT_H
#define TESTS_SUMMARY_TEXT_H

#include <stdio.h>

#include "../csg/summary.h"

static inline char *summary_text(const csg_scene *s)
{
    char *buf = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&buf, &size);
    if (!f)
        return NULL;
    csg_print_summary(s, f);
    fclose(f);
    return buf;
}

#endif
