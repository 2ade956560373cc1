/*
 * pager.h — a worker's scene below a memory budget: VM_pRAY's object
 * paging (Badouel and Priol), on the flat blob (csg/device/flat.h).
 *
 * The blob's BVH is cut into pages: a page is a subtree of the BVH that
 * fits the page size, with everything only it reaches — its nodes below
 * its top, the roots of its leaves, their CSG programs and primitives.
 * The flattener lays all four out in the BVH's depth-first order (a
 * subtree's nodes, its leaves' roots, their programs and primitives are
 * each one run of their array), so a page is four byte ranges of the
 * blob.  The rest — the header, the BVH above the pages, the unbounded
 * roots, materials, lights, wide runs, the coefficient table — is the
 * resident part, which every worker holds.
 *
 * A worker maps the whole blob's size as virtual memory (no byte of it
 * used until written), writes the resident part at its offsets, and
 * writes a page at its own offsets when a ray first needs it: the engine's
 * code indexes the arrays as always and never learns what is paged.  What
 * it must do is say where it is going: the BVH walks name each node they
 * enter (csg_view.pager, CSG_PAGE_ENTER in intersect.h), and code that
 * reaches a root or a primitive by its index (a record's hit, the shadow
 * cache) names that.  A page not here is fetched (the fetch callback:
 * from rank 0 over MPI, or from a full copy in this process) before the
 * walk goes on.
 *
 * Pages live in an LRU cache (or FIFO: --page-policy) within the budget.
 * A page used during the current work item (an epoch) is pinned: a hit's
 * primitive stays where the shading will read it.  So the budget holds
 * between items; within one, an item whose pages do not fit goes over it
 * (counted: over_bytes), and its end evicts down to the budget.
 * Evicted bytes go back to the kernel (madvise MADV_DONTNEED) whole 4 KiB
 * pages at a time: a memory page shared by two cache pages is freed with
 * the second.
 *
 * Exact by construction: a page's bytes are the blob's, so an image is the
 * in-memory render's bit for bit at every budget.  The plan is computed
 * by rank 0 from its whole blob (pager_plan_make) and travels with the
 * resident part (pager_pack_resident); the workers trust rank 0's
 * validation of the whole blob.
 */
#ifndef WORKERS_PAGER_H
#define WORKERS_PAGER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "../comm/tiles.h"
#include "../csg/device/flat.h"

/* The four byte ranges of a page: BVH nodes, roots, program nodes,
 * primitives. */
enum { PAGER_RANGES = 4 };

typedef struct {
    uint64_t off, len;
} pager_range;

typedef struct {
    int32_t node;       /* the BVH node whose subtree this is: entering it
                           needs the page                               */
    int32_t root_first; /* its roots: root_first .. + root_count       */
    int32_t root_count;
    int32_t prim_first; /* its primitives: prim_first .. + prim_count  */
    int32_t prim_count;
    int32_t pad;
    pager_range range[PAGER_RANGES];
    uint64_t bytes;     /* the ranges' total                          */
} pager_page;

/* The plan: the pages (in the BVH's depth-first order: their roots and
 * primitives ascend) and what stays resident. */
typedef struct {
    uint64_t total_size;   /* the blob's bytes                           */
    uint64_t page_bytes;   /* the page size aimed at                     */
    uint64_t resident_bytes; /* the resident part's bytes                */
    int32_t page_count;
    int32_t bvh_count;     /* the blob's BVH nodes                       */
    pager_page *pages;
    int32_t *by_node;      /* a worker's: page indices ordered by their
                              node (not the pages' order: a pair's second
                              node comes before the first one's subtree) */
} pager_plan;

/* The plan of a valid blob with pages of about page_bytes; false with the
 * reason in why when the blob's layout does not allow paging or memory
 * is short. */
bool pager_plan_make(const void *blob, uint64_t page_bytes, pager_plan *plan, const char **why);
void pager_plan_free(pager_plan *plan);

/* The blob's BVH laid out for pages of about page_bytes (rank 0, before
 * pager_plan_make with the same size): the nodes above the pages first,
 * then each page's subtree, so that the resident part is one run of the
 * array; the same tree, the same images.  False (why) as the plan. */
bool pager_relayout(void *blob, uint64_t page_bytes, const char **why);

/* The page size for a budget: a 512th of it, within 16 .. 128 KiB
 * (bench/PAGING.md: larger pages move more bytes than they save faults). */
uint64_t pager_page_bytes_for(uint64_t budget);

/* The resident part and the plan in one buffer (malloc'd, *len bytes), as
 * rank 0 sends it; NULL when out of memory. */
void *pager_pack_resident(const void *blob, const pager_plan *plan, size_t *len);

/* A page's bytes packed (its ranges one after the other) into out. */
void pager_pack_page(const void *blob, const pager_page *page, unsigned char *out);

/* pages[0 .. n) of `plan` packed one after the other from blob (an
 * answer to an ask) into *out (malloc'd): their bytes, or 0 (*out NULL
 * when a page is out of the plan or memory is short). */
size_t pager_pack_pages(const void *blob, const pager_plan *plan, const int32_t *pages, int n,
                        unsigned char **out);
/* Where pages come from: the pages `pages[0 .. n)` packed one after the
 * other into out (bytes: their total); false when it failed. */
typedef bool (*pager_fetch)(void *arg, const int32_t *pages, int n, unsigned char *out,
                            size_t bytes);
/* Where pages come from, one-sided (--page-fetch get): the blob's byte
 * ranges ranges[0 .. n) written at base + their offsets, from rank 0's
 * memory window (comm/mpi_link.h, link_page_get) or its own copy, with
 * no work of rank 0's and no copy through a buffer; false when it failed. */
typedef bool (*pager_fetch_into)(void *arg, const pager_range *ranges, int n, unsigned char *base);
/* --page-fetch: get (one-sided, where the MPI library opens rank 0's blob
 * as a window; else as ask) or ask (a request rank 0 answers). */
enum pager_fetch_mode { PAGER_FETCH_GET = 0, PAGER_FETCH_ASK = 1 };

enum pager_policy { PAGER_LRU = 0, PAGER_FIFO = 1 };
/* --page-prefetch (proto_setup.page_prefetch): none (every page on
 * demand), an item's pages before its rays (csg_pager.prefetch), and
 * those of its primary hits' shadow rays too (prefetch_shadows). */
enum pager_prefetch { PAGER_PREFETCH_OFF = 0, PAGER_PREFETCH_ON = 1, PAGER_PREFETCH_SHADOWS = 2 };
/* Who serves a page (--page-home): rank 0 alone, or its home, a worker
 * (VM_pRAY's owners): the pages in W runs, in order, worker w the home of
 * the w-th (pager_home_of: an item's pages, neighbours in the BVH's
 * order, mostly have one or two homes, so a fetch asks few), which holds
 * them for the whole render, outside its cache.  auto: spread from
 * PAGER_HOME_AUTO_WORKERS workers on, where a worker's share fits, when
 * the pages are asked for (host/master.c: read one-sided, rank 0 serves)
 * (pager_homes_fit), else rank 0 (pager_homes_for; bench/PAGING.md: below
 * that rank 0 has time to spare, and a home's answers cost more). */
enum pager_home { PAGER_HOME_AUTO = 0, PAGER_HOME_MASTER = 1, PAGER_HOME_SPREAD = 2 };
#define PAGER_HOME_AUTO_WORKERS 128

/* The pager's counts since it opened: the very counts a work item's
 * result carries (comm/tiles.h), the sums then taken over items. */
typedef page_counts pager_stats;

/* The page trace: the pages each item named, in the order it first named
 * them, written one line an item (pager_trace_item) — what the simulated
 * build replays (sim/page_trace.h) to model the page traffic of any
 * number of workers.  The list of the current item: a page a prefetch
 * named is stored as -1 - page. */
typedef struct {
    FILE *file;
    int32_t *named;
    int count, cap;
} pager_trace;

/* csg_pager.here: a page absent, cached, held as this worker's own (a
 * home's, outside the cache), or coming in its home's background fill
 * (asked of rank 0, not here yet). */
enum pager_page_state { PAGE_ABSENT = 0, PAGE_CACHED = 1, PAGE_HOME = 2, PAGE_COMING = 3 };
typedef struct csg_pager {
    unsigned char *base;   /* the blob's address space: what the engine reads */
    size_t map_bytes;
    pager_plan plan;
    uint64_t budget;       /* bytes: the resident part and the cache      */
    uint64_t used;         /* the resident part and the cached pages'     */
    enum pager_policy policy;
    pager_fetch fetch;
    pager_fetch_into fetch_into; /* set: pages from rank 0 come this way
                              (--page-fetch get); homes still ask       */
    void *fetch_arg;
    pager_range *spans;    /* a one-sided fetch's ranges                 */
    size_t spans_cap;
    pager_range *runs;     /* runs of memory pages to advise (off, len:
                              in memory pages; pager.c, runs_advise)     */
    size_t runs_n, runs_cap;
    uint32_t epoch;        /* the current item's number                   */
    uint32_t *stamp;       /* a page's last item (pinned when = epoch)     */
    uint8_t *here;         /* where a page is: enum pager_page_state      */
    int32_t *prev, *next;  /* the cache's order, oldest first: head, tail  */
    int32_t head, tail;
    uint64_t *is_page_node; /* a bit a BVH node: entering it needs a page */
    int32_t *top_rank;      /* [w]: the bits set in is_page_node[0 .. w),
                               so a top's place in plan.by_node is its
                               rank: no search on the walks' path */
    uint16_t *refs;        /* a 4 KiB memory page's users (the resident
                              part counts once, for ever)                */
    uint64_t mapped;       /* memory pages in use (refs > 0)             */
    unsigned char *buffer; /* a fetch's bytes                             */
    size_t buffer_cap;
    int32_t homes;         /* --page-home spread: the W workers that hold
                              the pages (pager_home_rank; 0: every page
                              from rank 0)                              */
    int32_t *home_count;   /* homes + 1 counters (fetch_pages' sort)     */
    int32_t *fetch_order;  /* a fetch's pages, sorted by home            */
    int32_t self;          /* this worker's rank among the homes        */
    int32_t fill_next;     /* pager_home_fill_next's next page (0: none yet) */
    void (*fill_wait)(void *fetch_arg); /* waits for the background fill's
                              current ask to end (NULL: none)            */
    uint64_t home_bytes;   /* the pages held here as their home          */
    bool serving;          /* fetching its own pages to answer another
                              worker (pager_pack_homes), maybe while its
                              own fetch waits                            */
    unsigned char *serve_buffer; /* that fetch's bytes                  */
    size_t serve_buffer_cap;
    bool failed;           /* a fetch failed: the image cannot be trusted */
    bool prefetch;         /* an item's pages named before its rays need
                              them, fetched in one request: a homo item's
                              primary rays' (frustum.h), a hetero item's
                              hit records' (tile_run.c); off: on demand  */
    bool prefetch_shadows; /* and, once its primary hits are known, the
                              pages their shadow rays to the point
                              lights will enter (workers/shade.c)       */
    bool prefetching;      /* pages named now are a prefetch's           */
    pager_trace trace;     /* file NULL: not traced                      */
    struct csg_pager *next_open; /* the process's open pagers (pager_for) */
    pager_stats stats;
} csg_pager;

/* The worker's side, from the packed resident part: false (with why) when
 * it is malformed, the budget is below the resident part, or memory is
 * short.  Open until pager_close (pager_for finds it: a process may hold
 * several, the simulated build's ranks). */
bool pager_open(csg_pager *p, const void *packed, size_t len, uint64_t budget,
                enum pager_policy policy, pager_fetch fetch, void *fetch_arg, const char **why);
void pager_close(csg_pager *p);

/* The open pager whose address space `blob` is, else NULL. */
csg_pager *pager_for(const void *blob);

/* --page-home spread: the largest share of the plan's paged bytes that
 * one of `homes` workers holds as their home. */
uint64_t pager_home_share(const pager_plan *plan, int32_t homes);
/* Does that share fit two thirds of what `budget` leaves beside the
 * resident part (a third at least the cache's)? */
bool pager_homes_fit(const pager_plan *plan, int32_t homes, uint64_t budget);
/* The homes for `workers` by the choice `home` (enum pager_home): workers,
 * or 0 (rank 0 serves); -1 for spread where a share does not fit. */
int32_t pager_homes_for(int home, int32_t workers, const pager_plan *plan, uint64_t budget);
/* The rank that serves page i: its home, or rank 0 (homes 0). */
static inline int pager_home_of(int32_t page, int32_t page_count, int32_t homes)
{
    return 1 + (int)((int64_t)page * homes / page_count);
}
static inline int pager_home_rank(const csg_pager *p, int32_t page)
{
    return p->homes > 0 ? pager_home_of(page, p->plan.page_count, p->homes) : 0;
}
/* The worker of rank `rank` is the home of its share of the pages, of
 * `homes` workers, from now on: each is fetched once (from rank 0: the
 * fetch callback asks rank 0 for a page whose home is the asker itself),
 * when this worker or another first needs it, and kept outside the cache,
 * never evicted; every other page then comes from its home.  False when
 * memory is short. */
bool pager_take_homes(csg_pager *p, int32_t homes, int rank);
/* The filling of a home's share in the background (in large asks of
 * rank 0, rather than a page at a time when first needed): the next of
 * its own pages not here, in page order, up to `max` of them and about
 * max_bytes (*bytes: theirs); how many (0: the share is all here). */
int pager_home_fill_next(csg_pager *p, int32_t *pages, int max, uint64_t max_bytes, uint64_t *bytes);
/* Those pages (marked coming until then: a fetch of one waits for the
 * fill, p->fill_wait, rather than ask for it again); their answer (the
 * bytes packed at `bytes`) written into place;
 * a page that came meanwhile is left as it is.  Counted as pages and
 * bytes fetched (no request: a background one). */
void pager_home_fill(csg_pager *p, const int32_t *pages, int n, const unsigned char *bytes);
/* Their ask failed: not coming (fetched when needed). */
void pager_home_fill_failed(csg_pager *p, const int32_t *pages, int n);
/* An answer to another worker: pages[0 .. n), each one whose home this is
 * (fetched from rank 0 first if it is not here yet), packed into *out
 * (malloc'd): its bytes, or 0 (*out NULL) when one's home is elsewhere, a
 * fetch failed or memory is short.  Counted as served. */
size_t pager_pack_homes(csg_pager *p, const int32_t *pages, int n, unsigned char **out);
/* A work item ends: the pages it used, pinned until now, may go; the
 * cache evicted down to the budget. */
void pager_item_end(csg_pager *p);

/* The page of BVH node k (a page's top), of root i, of primitive j, here
 * (fetched if it was not).  The node form is the walks', once they found
 * k's bit set (CSG_PAGE_ENTER tests it inline: most nodes are no page's
 * top). */
void pager_need_page(csg_pager *p, int32_t page);
void pager_need_node(csg_pager *p, int32_t k);
static inline bool pager_is_page_top(const csg_pager *p, int32_t k)
{
    return (p->is_page_node[(uint32_t)k >> 6] & ((uint64_t)1 << ((uint32_t)k & 63u))) != 0;
}
/* The page tops' bits, for the walks to test inline (csg_view.page_tops,
 * CSG_PAGE_ENTER in intersect.h): one call a top, none for other nodes. */
static inline const uint64_t *pager_page_tops(const csg_pager *p)
{
    return p->is_page_node;
}
void pager_need_root(csg_pager *p, int32_t root);
void pager_need_prim(csg_pager *p, int32_t prim);

/* The pages of the primitives of surfaces surf[0 .. n) (a hetero item's
 * hit records: the primary pass as the prefetcher) fetched in one
 * request; CSG_SURF_NONE skipped. */
void pager_prefetch_hits(csg_pager *p, const uint32_t *surf, size_t n);
/* The pages whose tops are BVH nodes nodes[0 .. n), fetched in one
 * request (a homo item's primary rays: workers/frustum.h). */
void pager_prefetch_nodes(csg_pager *p, const int32_t *nodes, size_t n);
/* Pages pages[0 .. n) by their index, fetched in one request (a traced
 * prefetch replayed: sim/tile_run.c). */
void pager_prefetch_pages(csg_pager *p, const int32_t *pages, size_t n);

/* The trace written to `name` with ".RANK" appended ($CSGTRACE_PAGE_TRACE,
 * host/config.h; a serial render's: rank 0); NULL name: none.  False when
 * the file cannot be created. */
bool pager_trace_open(csg_pager *p, const char *name, int rank);
/* The current item's line (before pager_item_end): its kind ('T' traced
 * whole, 'S' shaded from records), its rectangle, the pages it named:
 *   KIND X Y W H N PAGE...   (a prefetched page as -1 - page)
 * A write that fails closes the trace (the file ends short). */
void pager_trace_item(csg_pager *p, char kind, int x, int y, int w, int h);

#endif
