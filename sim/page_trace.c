/*
 * page_trace.c — reading the page traces of real renders (page_trace.h).
 */
#include "page_trace.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bool grow(void **array, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return true;
    size_t cap2 = *cap ? *cap : 64;
    while (cap2 < need)
        cap2 *= 2;
    void *grown = realloc(*array, cap2 * size);
    if (!grown)
        return false;
    *array = grown;
    *cap = cap2;
    return true;
}

/* The next integer of a line at *at, within lo .. hi; false if none. */
static bool next_int(char **at, long lo, long hi, int32_t *out)
{
    char *end;
    errno = 0;
    long v = strtol(*at, &end, 10);
    if (end == *at || errno || v < lo || v > hi)
        return false;
    *at = end;
    *out = (int32_t)v;
    return true;
}

/* One line into t; false when malformed or out of memory (why). */
static bool parse_line(page_trace *t, char *line, const char **why)
{
    page_trace_item it = {0, 0, 0, 0, 0, t->page_count, 0};
    *why = "malformed line (KIND X Y W H N PAGE...)";
    if ((line[0] != 'T' && line[0] != 'S') || line[1] != ' ')
        return false;
    it.kind = line[0];
    char *at = line + 1;
    if (!next_int(&at, 0, INT32_MAX, &it.x) || !next_int(&at, 0, INT32_MAX, &it.y) ||
        !next_int(&at, 1, INT32_MAX, &it.w) || !next_int(&at, 1, INT32_MAX, &it.h) ||
        !next_int(&at, 0, INT32_MAX, &it.count))
        return false;
    for (int32_t k = 0; k < it.count; k++) {
        int32_t page;
        if (!next_int(&at, INT32_MIN + 1, INT32_MAX, &page))
            return false;
        *why = "out of memory";
        if (!grow((void **)&t->pages, &t->page_cap, t->page_count + 1, sizeof *t->pages))
            return false;
        t->pages[t->page_count++] = page;
        int32_t index = page_trace_page(page);
        t->page_max = index > t->page_max ? index : t->page_max;
        *why = "malformed line (KIND X Y W H N PAGE...)";
    }
    while (*at == ' ' || *at == '\n' || *at == '\r')
        at++;
    if (*at)
        return false;
    *why = "out of memory";
    if (!grow((void **)&t->items, &t->item_cap, t->item_count + 1, sizeof *t->items))
        return false;
    t->items[t->item_count++] = it;
    return true;
}

static bool load_file(page_trace *t, const char *path, char *err, size_t err_size)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(err, err_size, "%s: %s", path, strerror(errno));
        return false;
    }
    char *line = NULL;
    size_t cap = 0;
    long number = 0;
    const char *why = NULL;
    bool ok = true;
    while (ok && getline(&line, &cap, f) >= 0) {
        number++;
        ok = parse_line(t, line, &why);
    }
    if (!ok)
        snprintf(err, err_size, "%s:%ld: %s", path, number, why);
    free(line);
    fclose(f);
    return ok;
}

static int item_order(const void *a, const void *b)
{
    const page_trace_item *p = a, *q = b;
    if (p->kind != q->kind)
        return p->kind < q->kind ? -1 : 1;
    if (p->y != q->y)
        return p->y < q->y ? -1 : 1;
    if (p->x != q->x)
        return p->x < q->x ? -1 : 1;
    if (p->w != q->w)
        return p->w < q->w ? -1 : 1;
    return p->h < q->h ? -1 : p->h > q->h;
}

bool page_trace_load(page_trace *t, const char *paths, char *err, size_t err_size)
{
    memset(t, 0, sizeof *t);
    t->page_max = -1;
    char *copy = strdup(paths);
    bool ok = copy != NULL;
    if (!ok)
        snprintf(err, err_size, "out of memory");
    for (char *save = NULL, *path = copy ? strtok_r(copy, ":", &save) : NULL; ok && path;
         path = strtok_r(NULL, ":", &save))
        ok = load_file(t, path, err, err_size);
    free(copy);
    if (ok && t->item_count > 0)
        qsort(t->items, t->item_count, sizeof *t->items, item_order);
    if (!ok)
        page_trace_free(t);
    return ok;
}

void page_trace_free(page_trace *t)
{
    free(t->items);
    free(t->pages);
    memset(t, 0, sizeof *t);
    t->page_max = -1;
}

static int page_order(const void *a, const void *b)
{
    int32_t p = *(const int32_t *)a, q = *(const int32_t *)b;
    int32_t i = page_trace_page(p), j = page_trace_page(q);
    if (i != j)
        return i < j ? -1 : 1;
    return page_trace_prefetched(p) == page_trace_prefetched(q) ? 0
           : page_trace_prefetched(p)                          ? -1 /* (a prefetch's first) */
                                                               : 1;
}

/* The union of list[0 .. n): each page once, a prefetch's mark kept. */
static int32_t page_union(int32_t *list, int32_t n)
{
    qsort(list, (size_t)n, sizeof *list, page_order);
    int32_t kept = 0;
    for (int32_t k = 0; k < n; k++)
        if (kept == 0 || page_trace_page(list[k]) != page_trace_page(list[kept - 1]))
            list[kept++] = list[k];
    return kept;
}

const page_trace_item *page_trace_find(const page_trace *t, char kind, int32_t x, int32_t y,
                                       int32_t w, int32_t h)
{
    page_trace_item key = {kind, x, y, w, h, 0, 0};
    return t->item_count ? bsearch(&key, t->items, t->item_count, sizeof key, item_order) : NULL;
}

int32_t page_trace_pages(const page_trace *t, char kind, int32_t x, int32_t y, int32_t w,
                         int32_t h, int32_t **out, bool *exact)
{
    *out = NULL;
    *exact = false;
    const page_trace_item *hit = page_trace_find(t, kind, x, y, w, h);
    size_t total = 0;
    if (hit) {
        *exact = true;
        total = (size_t)hit->count;
    } else {
        for (size_t i = 0; i < t->item_count; i++) {
            const page_trace_item *it = &t->items[i];
            if (it->kind == kind && it->x < x + w && x < it->x + it->w && it->y < y + h &&
                y < it->y + it->h)
                total += (size_t)it->count;
        }
    }
    if (total == 0)
        return 0;
    if (total > INT32_MAX || !(*out = malloc(total * sizeof **out)))
        return -1;
    if (hit) {
        memcpy(*out, t->pages + hit->first, total * sizeof **out);
        return (int32_t)total;
    }
    size_t n = 0;
    for (size_t i = 0; i < t->item_count; i++) {
        const page_trace_item *it = &t->items[i];
        if (it->kind == kind && it->x < x + w && x < it->x + it->w && it->y < y + h &&
            y < it->y + it->h) {
            memcpy(*out + n, t->pages + it->first, (size_t)it->count * sizeof **out);
            n += (size_t)it->count;
        }
    }
    return page_union(*out, (int32_t)n);
}

const page_trace *page_trace_shared(void)
{
    static page_trace t;
    static bool loaded, ok;
    if (!loaded) {
        loaded = true;
        const char *paths = getenv("CSGSIM_PAGES");
        char err[512];
        ok = paths && *paths && page_trace_load(&t, paths, err, sizeof err);
        if (paths && *paths && !ok)
            fprintf(stderr, "csgsim: CSGSIM_PAGES: %s\n", err);
    }
    return ok ? &t : NULL;
}
