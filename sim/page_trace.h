/*
 * page_trace.h — the pages each work item of a real render named, for the
 * simulated build's page traffic (make sim; bench/sim/paging.sh).
 *
 * A render with --scene-memory and $CSGTRACE_PAGE_TRACE set writes, per
 * worker, one line an item (workers/pager.h, pager_trace_item): its kind
 * ('T' traced whole, 'S' shaded from the pass's records), its rectangle
 * and the pages it named, in the order it first named them, a page a
 * prefetch named as -1 - page.  Which pages an item names does not depend
 * on what the worker's cache held, so the simulated workers replay them
 * through their own pagers (the real cache, LRU or FIFO, the real
 * requests to rank 0 over the simulated network) whatever the number of
 * workers and the order their items come in.
 */
#ifndef SIM_PAGE_TRACE_H
#define SIM_PAGE_TRACE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    char kind;              /* 'T' or 'S'                                */
    int32_t x, y, w, h;     /* the item's rectangle                      */
    size_t first;           /* its pages: pages[first .. + count)        */
    int32_t count;
} page_trace_item;

typedef struct {
    page_trace_item *items; /* sorted by kind, y, x once loaded          */
    size_t item_count, item_cap;
    int32_t *pages;         /* every item's, -1 - page for a prefetch's  */
    size_t page_count, page_cap;
    int32_t page_max;       /* the largest page number named (-1: none)  */
} page_trace;

/* A named page of a trace: its number, and whether a prefetch named it. */
static inline int32_t page_trace_page(int32_t named)
{
    return named < 0 ? -1 - named : named;
}
static inline bool page_trace_prefetched(int32_t named)
{
    return named < 0;
}

/* The recorded item of `kind` with exactly rectangle (x, y, w, h), or NULL. */
const page_trace_item *page_trace_find(const page_trace *t, char kind, int32_t x, int32_t y,
                                       int32_t w, int32_t h);

/* The traces in `paths` (separated by ':') into t; false with the reason
 * (file:line) in err on a file that cannot be read or a malformed line. */
bool page_trace_load(page_trace *t, const char *paths, char *err, size_t err_size);
void page_trace_free(page_trace *t);

/* The traces named by $CSGSIM_PAGES (bench/simulate.sh --page-trace),
 * loaded once per process (the simulated ranks share it); NULL when it is
 * unset, or cannot be read (the reason on stderr, once). */
const page_trace *page_trace_shared(void);

/* The pages an item of `kind` over rectangle (x, y, w, h) names, into
 * *out (malloc'd; NULL when none): the recorded item's own when one has
 * that rectangle, else the union of those it overlaps (a part of a split
 * tile, another tile size), each page once, marked a prefetch's if any
 * of them prefetched it.  The count, or -1 when out of memory; *exact:
 * whether one recorded item had the rectangle. */
int32_t page_trace_pages(const page_trace *t, char kind, int32_t x, int32_t y, int32_t w,
                         int32_t h, int32_t **out, bool *exact);

#endif
