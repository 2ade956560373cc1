/*
 * test_pager.c — a worker's scene in pages (workers/pager.h), in process,
 * the pages fetched from the whole blob by a counting callback:
 *   - the plan: pages cover the BVH's subtrees with their roots, programs
 *     and primitives; their ranges and the resident part never overlap
 *     and add up to the blob; roots and primitives ascend page by page;
 *   - the pager's address space holds the resident part, and a page's
 *     bytes once it is needed (by node, root or primitive), equal to the
 *     blob's;
 *   - LRU keeps the pages used last and evicts the oldest between items;
 *     a page used in the current item is pinned, the budget then exceeded
 *     (and counted); FIFO evicts in fetch order;
 *   - an image rendered through the pager at a budget of the resident part
 *     and two pages is the in-memory one, bit for bit, with the primary
 *     rays' pages prefetched and on demand only;
 *   - a malformed plan (two pages of one top too) and a budget below the
 *     resident part are refused; 3000 mutants of a plan's head are refused
 *     or open and close cleanly;
 *   - homes (--page-home spread): a worker's share is its run of the
 *     pages (the pages in W runs, in order), fetched once when first
 *     needed (by the worker, to answer another, or by the background
 *     fill), then held outside the cache (never evicted, never fetched
 *     again), packed for other workers (its own pages only); a fetch takes
 *     its own pages first, then the others sorted by their home's rank,
 *     one run a home; a page the fill is bringing is waited for, not
 *     fetched; the share's fit in the budget.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../csg/flatten.h"
#include "../csg/lang/parser.h"
#include "../workers/engine.h"
#include "fuzz_rng.h"
#include "../workers/pager.h"
#include "../workers/tile.h"

typedef struct {
    const void *blob;
    const pager_plan *plan;
    int calls;
} source;

static bool fetch_from(void *arg, const int32_t *pages, int n, unsigned char *out, size_t bytes)
{
    source *s = arg;
    size_t at = 0;
    s->calls++;
    for (int i = 0; i < n; i++) {
        pager_pack_page(s->blob, &s->plan->pages[pages[i]], out + at);
        at += s->plan->pages[pages[i]].bytes;
    }
    return at == bytes;
}

/* A grid of n x n small spheres of one texture: many roots, few materials. */
static void grid_blob(int n, csg_blob *b)
{
    size_t cap = 256 + (size_t)n * n * 64;
    char *text = malloc(cap);
    assert_non_null(text);
    size_t len = (size_t)snprintf(text, cap,
                                  "camera { location <0, 0, -30> look_at <0, 0, 0> }\n"
                                  "light_source { <10, 20, -30> rgb 1 }\n"
                                  "#declare T = texture { pigment { rgb <1, 0.5, 0.2> } }\n");
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            len += (size_t)snprintf(text + len, cap - len,
                                    "sphere { <%d, %d, 0>, 0.45 texture { T } }\n", i - n / 2,
                                    j - n / 2);
    csg_scene s;
    csg_diag d = {0};
    if (!csg_parse_string("grid.pov", text, len, &s, &d))
        fail_msg("parse: %s", d.message);
    csg_flatten_opts o = {48, 40, 0, -1, 1, 0};
    if (!engine_float.flatten(&s, &o, b, &d))
        fail_msg("flatten: %s", d.message);
    csg_scene_free(&s);
    free(text);
}

static int range_order(const void *x, const void *y)
{
    const pager_range *a = x, *b = y;
    return a->off < b->off ? -1 : a->off > b->off;
}

static void test_plan(void **state)
{
    (void)state;
    csg_blob b;
    grid_blob(32, &b);
    pager_plan plan;
    const char *why = NULL;
    assert_true(pager_plan_make(b.bytes, 16384, &plan, &why));
    assert_true(plan.page_count >= 12);
    const csg_blob_header *h = (const csg_blob_header *)b.bytes;
    pager_range *all = malloc((size_t)plan.page_count * PAGER_RANGES * sizeof *all);
    size_t n = 0;
    uint64_t paged = 0;
    int32_t roots = 0, prims = 0;
    for (int32_t i = 0; i < plan.page_count; i++) {
        const pager_page *pg = &plan.pages[i];
        assert_int_equal(pg->root_first, roots); /* (the roots, in order, none missed) */
        assert_int_equal(pg->prim_first, prims);
        roots += pg->root_count;
        prims += pg->prim_count;
        paged += pg->bytes;
        for (int r = 0; r < PAGER_RANGES; r++)
            if (pg->range[r].len > 0)
                all[n++] = pg->range[r];
    }
    assert_int_equal(roots, h->root_count - h->linear_roots);
    assert_int_equal(prims, h->prim_count);
    qsort(all, n, sizeof *all, range_order);
    for (size_t i = 1; i < n; i++) /* disjoint */
        assert_true(all[i - 1].off + all[i - 1].len <= all[i].off);
    assert_int_equal(plan.resident_bytes + paged, h->total_size);
    assert_true(plan.resident_bytes < h->total_size / 2);
    free(all);
    pager_plan_free(&plan);
    csg_blob_free(&b);
}

/* A pager over b whose budget holds the resident part and `room` of its
 * largest pages, fetching from b (s's counter). */
static void open_pager(const csg_blob *b, pager_plan *plan, int room, enum pager_policy policy,
                       source *s, csg_pager *p)
{
    const char *why = NULL;
    assert_true(pager_plan_make(b->bytes, 16384, plan, &why));
    uint64_t largest = 0;
    for (int32_t i = 0; i < plan->page_count; i++)
        largest = plan->pages[i].bytes > largest ? plan->pages[i].bytes : largest;
    size_t len = 0;
    void *packed = pager_pack_resident(b->bytes, plan, &len);
    assert_non_null(packed);
    *s = (source){b->bytes, plan, 0};
    assert_true(pager_open(p, packed, len, plan->resident_bytes + (uint64_t)room * largest, policy,
                           fetch_from, s, &why));
    free(packed);
}

/* A 32 x 32 grid's blob and a pager over it (open_pager). */
typedef struct {
    csg_blob b;
    pager_plan plan;
    source s;
    csg_pager p;
} paged_grid;

static void paged_grid_open(paged_grid *g, int room, enum pager_policy policy)
{
    grid_blob(32, &g->b);
    open_pager(&g->b, &g->plan, room, policy, &g->s, &g->p);
}

static void paged_grid_close(paged_grid *g)
{
    pager_close(&g->p);
    pager_plan_free(&g->plan);
    csg_blob_free(&g->b);
}

static bool page_bytes_equal(const csg_pager *p, const csg_blob *b, int32_t i)
{
    for (int r = 0; r < PAGER_RANGES; r++) {
        const pager_range *rg = &p->plan.pages[i].range[r];
        if (memcmp(p->base + rg->off, (const unsigned char *)b->bytes + rg->off, rg->len) != 0)
            return false;
    }
    return true;
}

static void test_lru_and_pinning(void **state)
{
    (void)state;
    paged_grid g;
    csg_pager *p = &g.p;
    paged_grid_open(&g, 3, PAGER_LRU);
    assert_int_equal(memcmp(p->base, g.b.bytes, sizeof(csg_blob_header)), 0);
    /* items of one page each: 0, 1, 2, then 0 again (kept: LRU), then 3 */
    int32_t order[] = {0, 1, 2, 0, 3};
    for (int k = 0; k < 5; k++) {
        pager_need_page(p, order[k]);
        assert_true(p->here[order[k]]);
        assert_true(page_bytes_equal(p, &g.b, order[k]));
        pager_item_end(p);
    }
    assert_int_equal(g.s.calls, 4); /* 0 came back from the cache */
    assert_false(p->here[1]);       /* the least recently used went */
    assert_true(p->here[0] && p->here[2] && p->here[3]);
    assert_true(p->used <= p->budget);
    /* a root's and a primitive's pages, by their indices */
    const pager_page *last = &p->plan.pages[p->plan.page_count - 1];
    pager_need_root(p, last->root_first + last->root_count - 1);
    pager_need_prim(p, last->prim_first);
    assert_true(p->here[p->plan.page_count - 1]);
    pager_item_end(p);
    /* one item naming five pages: all pinned, the budget exceeded */
    for (int32_t i = 4; i < 9; i++)
        pager_need_page(p, i);
    for (int32_t i = 4; i < 9; i++)
        assert_true(p->here[i]);
    assert_true(p->used > p->budget);
    assert_true(p->stats.over_bytes > 0);
    pager_item_end(p); /* evicted down to the budget */
    assert_true(p->used <= p->budget);
    assert_true(p->stats.evictions > 0);
    paged_grid_close(&g);

    paged_grid_open(&g, 3, PAGER_FIFO);
    for (int k = 0; k < 5; k++) { /* the same uses: FIFO drops 0, fetched first */
        pager_need_page(p, order[k]);
        pager_item_end(p);
    }
    assert_false(p->here[0]);
    assert_true(p->here[1] && p->here[2] && p->here[3]);
    paged_grid_close(&g);
}

/* A fetch that checks its pages come sorted by home (of `homes_of`) and
 * keeps them in `fetched`. */
static csg_pager *homes_of;
static int32_t fetched[4096];
static int fetched_count;

static bool fetch_by_home(void *arg, const int32_t *pages, int n, unsigned char *out, size_t bytes)
{
    for (int k = 0; k < n; k++) {
        if (homes_of && k > 0 && pager_home_rank(homes_of, pages[k]) < pager_home_rank(homes_of, pages[k - 1]))
            return false;
        if (fetched_count < 4096)
            fetched[fetched_count++] = pages[k];
    }
    return fetch_from(arg, pages, n, out, bytes);
}

enum { W = 3, RANK = 2 }; /* test_homes: 3 homes, this worker the second */

/* Page i's home by the rule (pager.h): the pages in W runs, in order. */
static int expected_home(int32_t i, int32_t pages)
{
    return 1 + (int)((int64_t)i * W / pages);
}

/* The background fill's pages, answered by the blob (pager.fill_wait). */
static int32_t filling[64];
static int filling_count;
static const csg_blob *filling_blob;

static void fill_from_blob(void *arg)
{
    source *s = arg;
    unsigned char *bytes = NULL;
    pager_pack_pages(filling_blob->bytes, s->plan, filling, filling_count, &bytes);
    assert_non_null(bytes);
    pager_home_fill(homes_of, filling, filling_count, bytes);
    free(bytes);
    filling_count = 0;
}

static void test_homes(void **state)
{
    (void)state;
    paged_grid g;
    grid_blob(32, &g.b);
    const char *why = NULL;
    assert_true(pager_plan_make(g.b.bytes, 16384, &g.plan, &why));
    int32_t P = g.plan.page_count;
    assert_true(P >= 3 * W);
    uint64_t share[W + 1] = {0};
    for (int32_t i = 0; i < P; i++)
        share[expected_home(i, P)] += g.plan.pages[i].bytes;
    uint64_t most = share[1] > share[2] ? share[1] : share[2];
    most = share[3] > most ? share[3] : most;
    assert_int_equal(pager_home_share(&g.plan, W), most);
    /* the share in two thirds of what the budget leaves, a third the cache's */
    uint64_t budget = g.plan.resident_bytes + most / 2 * 3 + 64;
    assert_true(pager_homes_fit(&g.plan, W, budget));
    assert_false(pager_homes_fit(&g.plan, W, g.plan.resident_bytes + most));
    assert_false(pager_homes_fit(&g.plan, 0, budget));
    /* the choice: spread where asked and it fits (else refused: -1); auto
     * from PAGER_HOME_AUTO_WORKERS on; master never */
    int32_t many = PAGER_HOME_AUTO_WORKERS;
    uint64_t roomy = g.plan.resident_bytes + pager_home_share(&g.plan, many) * 3 / 2 + 64;
    assert_int_equal(pager_homes_for(PAGER_HOME_SPREAD, W, &g.plan, budget), W);
    assert_int_equal(pager_homes_for(PAGER_HOME_SPREAD, W, &g.plan, g.plan.resident_bytes + most), -1);
    assert_int_equal(pager_homes_for(PAGER_HOME_AUTO, W, &g.plan, budget), 0);
    assert_int_equal(pager_homes_for(PAGER_HOME_AUTO, many, &g.plan, roomy), many);
    assert_int_equal(pager_homes_for(PAGER_HOME_AUTO, many, &g.plan, g.plan.resident_bytes), 0);
    assert_int_equal(pager_homes_for(PAGER_HOME_MASTER, many, &g.plan, roomy), 0);

    size_t len = 0;
    void *packed = pager_pack_resident(g.b.bytes, &g.plan, &len);
    assert_non_null(packed);
    g.s = (source){g.b.bytes, &g.plan, 0};
    csg_pager *p = &g.p;
    assert_true(pager_open(p, packed, len, budget, PAGER_LRU, fetch_by_home, &g.s, &why));
    free(packed);
    homes_of = p;
    fetched_count = 0;
    assert_true(pager_take_homes(p, W, RANK));
    assert_int_equal(g.s.calls, 0); /* (each when first needed) */
    int32_t first = -1, count = 0; /* this worker's run of pages */
    for (int32_t i = 0; i < P; i++) {
        assert_int_equal(pager_home_rank(p, i), expected_home(i, P));
        if (expected_home(i, P) == RANK) {
            first = first < 0 ? i : first;
            count++;
        }
    }
    assert_true(count >= 3);

    /* a first use: the own pages in a first fetch, held as homes (before
     * the others' homes are waited on); the others in a second, sorted by
     * home, cached */
    int32_t mixed[] = {P - 1, first, 0, first + 1, P - 2, 1, first + 2, 2, P - 3};
    pager_prefetch_pages(p, mixed, 9);
    assert_int_equal(g.s.calls, 2);
    assert_int_equal(fetched_count, 9);
    for (int k = 0; k < 9; k++)
        assert_int_equal(expected_home(fetched[k], P) == RANK, k < 3);
    assert_int_equal(p->home_bytes, g.plan.pages[first].bytes + g.plan.pages[first + 1].bytes +
                                        g.plan.pages[first + 2].bytes);
    pager_item_end(p);
    /* the own pages are never fetched again; the others may be */
    int32_t own3[] = {first, first + 1, first + 2};
    fetched_count = 0;
    pager_prefetch_pages(p, own3, 3);
    assert_int_equal(fetched_count, 0);
    pager_item_end(p);
    /* every page named, an item each: the cache evicts, the homes stay */
    for (int32_t i = 0; i < P; i++) {
        pager_need_page(p, i);
        pager_item_end(p);
    }
    assert_false(p->failed);
    assert_true(p->stats.evictions > 0);
    assert_true(p->used <= p->budget);
    for (int32_t i = first; i < first + count; i++) {
        assert_int_equal(p->here[i], PAGE_HOME);
        assert_true(page_bytes_equal(p, &g.b, i));
    }
    assert_int_equal(p->home_bytes, share[RANK]);

    /* answers to other workers: the own pages only, the blob's bytes */
    int32_t own[] = {first, first + 1}, other[] = {0};
    unsigned char *out = NULL, *want = NULL;
    size_t bytes = pager_pack_homes(p, own, 2, &out);
    assert_int_equal(bytes, pager_pack_pages(g.b.bytes, &g.plan, own, 2, &want));
    assert_non_null(out);
    assert_memory_equal(out, want, bytes);
    assert_int_equal(p->stats.served, 1);
    assert_int_equal(p->stats.served_bytes, bytes);
    free(out);
    free(want);
    assert_int_equal(pager_pack_homes(p, other, 1, &out), 0);
    assert_null(out);
    pager_close(p);

    /* an answer for an own page not here yet: fetched first, then held */
    packed = pager_pack_resident(g.b.bytes, &g.plan, &len);
    assert_true(pager_open(p, packed, len, budget, PAGER_LRU, fetch_by_home, &g.s, &why));
    homes_of = p;
    assert_true(pager_take_homes(p, W, RANK));
    int32_t fresh[] = {first + count - 1};
    bytes = pager_pack_homes(p, fresh, 1, &out);
    assert_int_equal(bytes, g.plan.pages[fresh[0]].bytes);
    assert_true(p->here[fresh[0]]);
    assert_true(page_bytes_equal(p, &g.b, fresh[0]));
    assert_false(p->serving);
    free(out);
    pager_close(p);

    /* the background fill: the run of own pages in order, within the
     * bytes asked for; a page of it needed meanwhile waits for the fill
     * (no fetch of its own); a failed ask leaves its pages to be fetched */
    assert_true(pager_open(p, packed, len, budget, PAGER_LRU, fetch_by_home, &g.s, &why));
    free(packed);
    homes_of = p;
    assert_true(pager_take_homes(p, W, RANK));
    p->fill_wait = fill_from_blob;
    filling_blob = &g.b;
    uint64_t fill_bytes = 0, two = g.plan.pages[first].bytes + g.plan.pages[first + 1].bytes;
    filling_count = pager_home_fill_next(p, filling, 64, two, &fill_bytes);
    assert_int_equal(filling_count, 2);
    assert_int_equal(filling[0], first);
    assert_int_equal(filling[1], first + 1);
    assert_int_equal(fill_bytes, two);
    assert_int_equal(p->here[first], PAGE_COMING);
    assert_int_equal(p->here[first + 1], PAGE_COMING);
    int calls = g.s.calls;
    pager_need_page(p, first + 1);
    assert_int_equal(g.s.calls, calls); /* the fill brought it */
    assert_int_equal(filling_count, 0);
    assert_int_equal(p->here[first], PAGE_HOME);
    assert_true(page_bytes_equal(p, &g.b, first) && page_bytes_equal(p, &g.b, first + 1));
    pager_item_end(p);
    filling_count = pager_home_fill_next(p, filling, 1, 1, &fill_bytes);
    assert_int_equal(filling_count, 1);
    assert_int_equal(filling[0], first + 2);
    pager_home_fill_failed(p, filling, filling_count);
    assert_int_equal(p->here[first + 2], PAGE_ABSENT);
    filling_count = 0;
    pager_need_page(p, first + 2);
    assert_int_equal(g.s.calls, calls + 1); /* (fetched after all) */
    assert_true(page_bytes_equal(p, &g.b, first + 2));
    assert_false(p->failed);
    homes_of = NULL;
    paged_grid_close(&g);
}

/* Every pixel through tile_run_rect, reading the blob at `blob`. */
static float *render(const void *blob, int w, int h)
{
    tile_runner tr;
    assert_true(tile_runner_init(&tr, blob, 8));
    float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb), *part = malloc(8 * 8 * 3 * sizeof *part);
    for (int ty = 0; ty < h; ty += 8)
        for (int tx = 0; tx < w; tx += 8) {
            tile_rect r = {tx, ty, w - tx < 8 ? w - tx : 8, h - ty < 8 ? h - ty : 8};
            tile_result res;
            tile_run_rect(&tr, r, NULL, part, &res);
            for (int y = 0; y < r.height; y++)
                memcpy(rgb + ((size_t)(ty + y) * w + tx) * 3, part + (size_t)y * r.width * 3,
                       (size_t)r.width * 3 * sizeof *rgb);
        }
    free(part);
    tile_runner_free(&tr);
    return rgb;
}

static void test_image(void **state)
{
    (void)state;
    paged_grid g;
    paged_grid_open(&g, 2, PAGER_LRU);
    float *whole = render(g.b.bytes, 48, 40), *paged = render(g.p.base, 48, 40);
    assert_memory_equal(whole, paged, (size_t)48 * 40 * 3 * sizeof *whole);
    assert_true(g.p.stats.prefetched > 0 && g.p.stats.evictions > 0); /* (the primary rays') */
    uint64_t faults = g.p.stats.faults;
    g.p.prefetch = false; /* on demand only: the same image */
    float *demand = render(g.p.base, 48, 40);
    assert_memory_equal(whole, demand, (size_t)48 * 40 * 3 * sizeof *whole);
    assert_true(g.p.stats.faults > faults);
    assert_false(g.p.failed);
    free(whole);
    free(paged);
    free(demand);
    paged_grid_close(&g);
}

/* pager_fetch_into from s's blob: each range copied into place; the
 * ranges must come sorted, disjoint and not touching (merged). */
static bool get_from(void *arg, const pager_range *ranges, int n, unsigned char *base)
{
    source *s = arg;
    s->calls++;
    for (int k = 0; k < n; k++) {
        if (k > 0 && ranges[k - 1].off + ranges[k - 1].len >= ranges[k].off)
            return false;
        memcpy(base + ranges[k].off, (const unsigned char *)s->blob + ranges[k].off, ranges[k].len);
    }
    return true;
}

static bool refuse_get(void *arg, const pager_range *ranges, int n, unsigned char *base)
{
    (void)arg, (void)ranges, (void)n, (void)base;
    return false;
}

/* Memory pages with a user (pager.refs), counted. */
static uint64_t memory_pages_used(const csg_pager *p)
{
    uint64_t used = 0;
    for (size_t k = 0; k < (p->map_bytes + 4095) / 4096; k++)
        used += p->refs[k] > 0;
    return used;
}

/* --page-fetch get's path (pager.fetch_into): pages read straight into
 * place, their ranges merged into one call a request.  The same image at a
 * budget of two pages (nearly every item evicts: a memory page shared by
 * two pages must be counted once per page, or its release with the first
 * zeroes the second's bytes), each request one call, and the memory pages
 * held those of the pages here; a failed read fails the pager and gives
 * the memory pages back. */
static void test_in_place(void **state)
{
    (void)state;
    paged_grid g;
    paged_grid_open(&g, 2, PAGER_LRU);
    g.p.fetch_into = get_from;
    float *whole = render(g.b.bytes, 48, 40), *paged = render(g.p.base, 48, 40);
    assert_memory_equal(whole, paged, (size_t)48 * 40 * 3 * sizeof *whole);
    assert_false(g.p.failed);
    assert_true(g.p.stats.evictions > 0 && g.p.stats.requests > 0);
    assert_int_equal(g.s.calls, (int)g.p.stats.requests);
    assert_int_equal(memory_pages_used(&g.p), g.p.mapped);
    for (int32_t i = 0; i < g.p.plan.page_count; i++)
        if (g.p.here[i])
            assert_true(page_bytes_equal(&g.p, &g.b, i));
    int32_t absent = 0;
    while (absent < g.p.plan.page_count && g.p.here[absent])
        absent++;
    assert_true(absent < g.p.plan.page_count);
    g.p.fetch_into = refuse_get;
    g.p.budget = UINT64_MAX; /* (no eviction: the memory pages held stay as they are) */
    uint64_t mapped = g.p.mapped;
    pager_need_page(&g.p, absent);
    assert_true(g.p.failed);
    assert_false(g.p.here[absent]);
    assert_int_equal(g.p.mapped, mapped);
    assert_int_equal(memory_pages_used(&g.p), mapped);
    free(whole);
    free(paged);
    paged_grid_close(&g);
}

/* Memory pages a pager over b holds for the resident part alone. */
static uint64_t resident_memory(const csg_blob *b)
{
    pager_plan plan;
    const char *why = NULL;
    assert_true(pager_plan_make(b->bytes, 16384, &plan, &why));
    size_t len = 0;
    void *packed = pager_pack_resident(b->bytes, &plan, &len);
    source s = {b->bytes, &plan, 0};
    csg_pager p;
    assert_true(pager_open(&p, packed, len, plan.resident_bytes, PAGER_LRU, fetch_from, &s, &why));
    uint64_t bytes = p.mapped * 4096;
    free(packed);
    pager_close(&p);
    pager_plan_free(&plan);
    return bytes;
}

/* The BVH laid out for paging: still a valid blob, the same image bit for
 * bit, and its resident nodes one run, so that the resident part holds
 * a few memory pages more than its bytes (each array's first and last),
 * not one a pair of pages as in the flattener's layout. */
static void test_relayout(void **state)
{
    (void)state;
    csg_blob b;
    grid_blob(64, &b);
    float *before = render(b.bytes, 48, 40);
    uint64_t scattered = resident_memory(&b);
    const char *why = NULL;
    assert_true(pager_relayout(b.bytes, 16384, &why));
    assert_true(csg_blob_valid(b.bytes, b.size));
    float *after = render(b.bytes, 48, 40);
    assert_memory_equal(before, after, (size_t)48 * 40 * 3 * sizeof *before);
    pager_plan plan;
    assert_true(pager_plan_make(b.bytes, 16384, &plan, &why));
    uint64_t laid_out = resident_memory(&b);
    assert_true(laid_out < plan.resident_bytes + 24 * 4096);
    assert_true(laid_out < scattered);
    pager_plan_free(&plan);
    free(before);
    free(after);
    csg_blob_free(&b);
}

/* The fixture of the wire's tests: a 16 x 16 grid's blob, its plan of
 * 16 KiB pages, and the plan packed as it goes over the wire. */
typedef struct {
    csg_blob b;
    pager_plan plan;
    unsigned char *packed;
    size_t len;
} wire_fixture;

static int wire_setup(void **state)
{
    wire_fixture *f = calloc(1, sizeof *f);
    const char *why = NULL;
    if (!f)
        return -1;
    grid_blob(16, &f->b);
    if (!pager_plan_make(f->b.bytes, 16384, &f->plan, &why))
        return -1;
    f->packed = pager_pack_resident(f->b.bytes, &f->plan, &f->len);
    *state = f;
    return f->packed ? 0 : -1;
}

static int wire_teardown(void **state)
{
    wire_fixture *f = *state;
    free(f->packed);
    pager_plan_free(&f->plan);
    csg_blob_free(&f->b);
    free(f);
    return 0;
}

static void test_refusals(void **state)
{
    wire_fixture *f = *state;
    const pager_plan plan = f->plan;
    unsigned char *packed = f->packed;
    size_t len = f->len;
    const char *why = NULL;
    source s = {f->b.bytes, &f->plan, 0};
    csg_pager p;
    assert_false(pager_open(&p, packed, len, plan.resident_bytes - 1, PAGER_LRU, fetch_from, &s,
                            &why));
    assert_non_null(strstr(why, "below the scene's resident part"));
    assert_false(pager_open(&p, packed, len - 1, plan.resident_bytes, PAGER_LRU, fetch_from, &s,
                            &why)); /* one byte short */
    packed[0] ^= 1u; /* not a plan */
    assert_false(pager_open(&p, packed, len, plan.resident_bytes, PAGER_LRU, fetch_from, &s, &why));
    assert_non_null(strstr(why, "malformed"));
    packed[0] ^= 1u; /* a plan again, but two of its pages with one top (a walk
                        finds a top's page by its rank among the tops) */
    assert_true(plan.page_count >= 2);
    size_t at = 0; /* (the pages follow the plan's header, in the plan's order) */
    while (at + 2 * sizeof(pager_page) <= len &&
           memcmp(packed + at, plan.pages, 2 * sizeof(pager_page)) != 0)
        at++;
    assert_true(at + 2 * sizeof(pager_page) <= len);
    pager_page second = plan.pages[1];
    assert_int_not_equal(plan.pages[0].node, second.node);
    second.node = plan.pages[0].node;
    memcpy(packed + at + sizeof second, &second, sizeof second);
    why = NULL;
    assert_false(pager_open(&p, packed, len, plan.resident_bytes, PAGER_LRU, fetch_from, &s, &why));
    assert_non_null(strstr(why, "malformed"));
}

/* The plan as it comes over the wire, its head (counts, sizes, pages,
 * ranges) mutated a few bytes at a time: every mutant is refused or opens
 * a pager that closes cleanly (ASan's build runs this too), never a crash;
 * and a pager that opens has its pages' tops unique (the walks find a
 * top's page by its rank among them). */
static void test_wire_mutations(void **state)
{
    wire_fixture *f = *state;
    const pager_plan plan = f->plan;
    const unsigned char *packed = f->packed;
    size_t len = f->len;
    const char *why = NULL;
    /* (the head, the pages, the ranges' start: more than the plan's part) */
    size_t head = 64 + (size_t)plan.page_count * sizeof(pager_page) + 64;
    head = head < len ? head : len;
    unsigned char *mutant = malloc(len);
    assert_non_null(mutant);
    source s = {f->b.bytes, &f->plan, 0};
    uint64_t seed = 0x9e3779b97f4a7c15u;
    int opened = 0, refused = 0;
    for (int it = 0; it < 3000; it++) {
        memcpy(mutant, packed, len);
        int flips = 1 + (int)rng_below(&seed, 4);
        for (int k = 0; k < flips; k++)
            mutant[rng_below(&seed, head)] ^= (unsigned char)(1u << rng_below(&seed, 8));
        csg_pager p;
        if (!pager_open(&p, mutant, len, plan.resident_bytes + 4 * 16384, PAGER_LRU, fetch_from, &s,
                        &why)) {
            assert_non_null(why);
            refused++;
            continue;
        }
        for (int32_t i = 1; i < p.plan.page_count; i++)
            assert_int_not_equal(p.plan.pages[p.plan.by_node[i]].node,
                                 p.plan.pages[p.plan.by_node[i - 1]].node);
        opened++;
        pager_close(&p);
    }
    /* (both kinds happen: 190 of 3000 open with this seed) */
    assert_true(refused > 0 && opened > 0);
    free(mutant);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plan),
        cmocka_unit_test(test_lru_and_pinning),
        cmocka_unit_test(test_image),
        cmocka_unit_test(test_in_place),
        cmocka_unit_test(test_relayout),
        cmocka_unit_test_setup_teardown(test_refusals, wire_setup, wire_teardown),
        cmocka_unit_test_setup_teardown(test_wire_mutations, wire_setup, wire_teardown),
        cmocka_unit_test(test_homes),
    };
    return cmocka_run_group_tests_name("pager", tests, NULL, NULL);
}
