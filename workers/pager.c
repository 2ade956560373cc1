/*
 * pager.c — the plan of a blob's pages (rank 0) and a worker's cache of
 * them (pager.h).
 *
 * The plan reads the blob's integers only (a BVH node's first and count, a
 * root's program, a program node's primitive: the first fields of their
 * structs in both precisions), the arrays' strides from the header's
 * real_size, so this file is compiled once for both precisions.
 */
#include "pager.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#define PAGER_MAGIC 0x50475231u /* "PGR1" */
#define OS_PAGE ((uint64_t)4096)
#define HOME_FETCH_BYTES ((uint64_t)8 << 20) /* a home's pages fetched in requests of this */

/* The bits set in x (without -mpopcnt GCC's builtin is a library call). */
static inline int popcount64(uint64_t x)
{
    x -= (x >> 1) & 0x5555555555555555u;
    x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fu;
    return (int)((x * 0x0101010101010101u) >> 56);
}

/* csg_pager.here: where a page is. */
static bool present(const csg_pager *p, int32_t i)
{
    return p->here[i] == PAGE_CACHED || p->here[i] == PAGE_HOME;
}

/* ---- the blob's arrays, by stride ------------------------------------------------ */

typedef struct {
    const unsigned char *b;
    const csg_blob_header *h;
    uint64_t bvh_size, root_size, node_size, prim_size;
} blob_arrays;

static blob_arrays arrays_of(const void *blob)
{
    blob_arrays a;
    a.b = blob;
    a.h = blob;
    uint64_t r = a.h->real_size;
    a.bvh_size = 8 + 6 * r;   /* csg_bvh_node: first, count, box[6]        */
    a.root_size = 16 + 6 * r; /* csg_root: four integers, lo[3], hi[3]      */
    a.node_size = 8;          /* csg_node: op, prim                        */
    a.prim_size = 16 + CSG_PRIM_REALS * r; /* csg_prim: four integers, p[] */
    return a;
}

static int32_t int_at(const unsigned char *p, int field)
{
    int32_t v;
    memcpy(&v, p + 4 * field, sizeof v);
    return v;
}

static int32_t bvh_first(const blob_arrays *a, int32_t k)
{
    return int_at(a->b + a->h->off_bvh + (uint64_t)k * a->bvh_size, 0);
}

static int32_t bvh_count(const blob_arrays *a, int32_t k)
{
    return int_at(a->b + a->h->off_bvh + (uint64_t)k * a->bvh_size, 1);
}

static int32_t root_first_node(const blob_arrays *a, int32_t i)
{
    return int_at(a->b + a->h->off_roots + (uint64_t)i * a->root_size, 0);
}

static int32_t root_node_count(const blob_arrays *a, int32_t i)
{
    return int_at(a->b + a->h->off_roots + (uint64_t)i * a->root_size, 1);
}

/* ---- the plan --------------------------------------------------------------------- */

/* What a subtree holds: its nodes below its top (end - below .. end when
 * `whole`: one run of the array), its leaves' roots (root_lo .. root_hi),
 * and their bytes with their programs and primitives. */
typedef struct {
    int32_t end, root_lo, root_hi, below;
    uint64_t bytes;
    bool whole;
} subtree;

/* The primitives of roots lo .. hi - 1: prim_lo[lo] .. prim_hi[hi - 1]
 * (a root's primitives are the PRIM nodes of its program, laid out in
 * the roots' order by the flattener). */
static bool root_prims(const blob_arrays *a, int32_t *prim_lo, int32_t *prim_hi)
{
    const csg_blob_header *h = a->h;
    int32_t next = 0;
    for (int32_t i = 0; i < h->root_count; i++) {
        int32_t first = root_first_node(a, i), count = root_node_count(a, i);
        prim_lo[i] = next;
        for (int32_t k = first; k < first + count; k++) {
            const unsigned char *node = a->b + h->off_nodes + (uint64_t)k * a->node_size;
            if (int_at(node, 0) != CSG_OP_PRIM)
                continue;
            if (int_at(node, 1) != next)
                return false; /* (not in the roots' order) */
            next++;
        }
        prim_hi[i] = next;
    }
    return next == h->prim_count;
}

static uint64_t roots_bytes(const blob_arrays *a, const int32_t *prim_lo, const int32_t *prim_hi,
                            int32_t lo, int32_t hi)
{
    if (hi <= lo)
        return 0;
    int32_t n0 = root_first_node(a, lo), n1 = root_first_node(a, hi - 1) + root_node_count(a, hi - 1);
    return (uint64_t)(hi - lo) * a->root_size + (uint64_t)(n1 - n0) * a->node_size +
           (uint64_t)(prim_hi[hi - 1] - prim_lo[lo]) * a->prim_size;
}

/* Each node's subtree, children before parents (they come after them in
 * the array); false when the tree or its leaves' roots are not in the
 * order pager.h relies on.  A subtree whose nodes are not one run (above
 * the pages once pager_relayout moved them) is not `whole`: no page. */
static bool subtrees(const blob_arrays *a, const int32_t *prim_lo, const int32_t *prim_hi,
                     subtree *s)
{
    int32_t n = a->h->bvh_count;
    for (int32_t k = n - 1; k >= 0; k--) {
        int32_t first = bvh_first(a, k), count = bvh_count(a, k);
        if (count >= 0) { /* a leaf: no nodes below */
            s[k] = (subtree){0, count > 0 ? first : 0, count > 0 ? first + count : 0, 0, 0, true};
            s[k].bytes = roots_bytes(a, prim_lo, prim_hi, s[k].root_lo, s[k].root_hi);
            continue;
        }
        if (first <= k || first + 1 >= n)
            return false;
        const subtree *l = &s[first], *r = &s[first + 1];
        subtree t;
        t.below = 2 + l->below + r->below;
        t.end = first + 2;
        t.whole = l->whole && r->whole;
        if (l->below > 0) {
            t.whole = t.whole && first + 2 == l->end - l->below;
            t.end = l->end;
        }
        if (r->below > 0) {
            t.whole = t.whole && t.end == r->end - r->below;
            t.end = r->end;
        }
        bool l_empty = l->root_hi <= l->root_lo, r_empty = r->root_hi <= r->root_lo;
        if (!l_empty && !r_empty && l->root_hi != r->root_lo)
            return false;
        t.root_lo = l_empty ? r->root_lo : l->root_lo;
        t.root_hi = r_empty ? l->root_hi : r->root_hi;
        t.bytes = (uint64_t)t.below * a->bvh_size +
                  roots_bytes(a, prim_lo, prim_hi, t.root_lo, t.root_hi);
        s[k] = t;
    }
    return true;
}

static pager_page page_of_subtree(const blob_arrays *a, const int32_t *prim_lo,
                                  const int32_t *prim_hi, int32_t k, const subtree *t)
{
    const csg_blob_header *h = a->h;
    pager_page pg;
    memset(&pg, 0, sizeof pg);
    pg.node = k;
    pg.root_first = t->root_lo;
    pg.root_count = t->root_hi - t->root_lo;
    int32_t first = bvh_first(a, k);
    if (t->below > 0)
        pg.range[0] = (pager_range){h->off_bvh + (uint64_t)first * a->bvh_size,
                                    (uint64_t)t->below * a->bvh_size};
    if (pg.root_count > 0) {
        int32_t lo = t->root_lo, hi = t->root_hi;
        int32_t n0 = root_first_node(a, lo), n1 = root_first_node(a, hi - 1) + root_node_count(a, hi - 1);
        pg.prim_first = prim_lo[lo];
        pg.prim_count = prim_hi[hi - 1] - prim_lo[lo];
        pg.range[1] = (pager_range){h->off_roots + (uint64_t)lo * a->root_size,
                                    (uint64_t)(hi - lo) * a->root_size};
        pg.range[2] = (pager_range){h->off_nodes + (uint64_t)n0 * a->node_size,
                                    (uint64_t)(n1 - n0) * a->node_size};
        pg.range[3] = (pager_range){h->off_prims + (uint64_t)pg.prim_first * a->prim_size,
                                    (uint64_t)pg.prim_count * a->prim_size};
    }
    for (int i = 0; i < PAGER_RANGES; i++)
        pg.bytes += pg.range[i].len;
    return pg;
}

/* The pages: the largest subtrees within page_bytes (a leaf beyond it is
 * a page of its own), top down, first child first: the depth-first order. */
static bool choose_pages(const blob_arrays *a, const int32_t *prim_lo, const int32_t *prim_hi,
                         const subtree *s, uint64_t page_bytes, pager_plan *plan)
{
    int32_t n = a->h->bvh_count, cap = 64, top = 0;
    int32_t *stack = malloc((size_t)(CSG_BVH_STACK + 2) * 2 * sizeof *stack);
    plan->pages = malloc((size_t)cap * sizeof *plan->pages);
    if (!stack || !plan->pages) {
        free(stack);
        return false;
    }
    if (n > 0) {
        stack[top++] = 1;
        stack[top++] = 0;
    }
    while (top > 0) {
        int32_t k = stack[--top];
        const subtree *t = &s[k];
        if (t->bytes == 0)
            continue; /* (the empty leaf) */
        if ((t->bytes > page_bytes || !t->whole) && bvh_count(a, k) < 0) {
            int32_t first = bvh_first(a, k);
            if (top + 2 > 2 * (CSG_BVH_STACK + 2))
                break;
            stack[top++] = first + 1;
            stack[top++] = first;
            continue;
        }
        if (plan->page_count == cap) {
            cap *= 2;
            pager_page *grown = realloc(plan->pages, (size_t)cap * sizeof *grown);
            if (!grown) {
                free(stack);
                return false;
            }
            plan->pages = grown;
        }
        plan->pages[plan->page_count++] = page_of_subtree(a, prim_lo, prim_hi, k, t);
    }
    free(stack);
    return top == 0;
}

/* ---- the BVH laid out for paging ----------------------------------------------------
 * The flattener stores the BVH depth first, a pair's subtrees after it, so
 * the pairs above the pages lie between the pages' subtrees: each would
 * hold a memory page of the resident part among pages that come and go
 * (a 16 KiB-page plan of tetra10: 1 MB of resident nodes on 16 MB of
 * memory pages).  pager_relayout moves them first: the pairs above the
 * pages, in their order, then each page's subtree, in the pages' order,
 * the children indices renumbered.  Pairs stay pairs, in their order, and
 * every box and leaf is the same, so a walk visits the same nodes in the
 * same order: the images do not change. */

static void bvh_set_first(const blob_arrays *a, unsigned char *bvh, int32_t k, int32_t first)
{
    memcpy(bvh + (uint64_t)k * a->bvh_size, &first, sizeof first);
}

/* The new index of every node (map), the pairs above the pages first. */
static bool relayout_map(const blob_arrays *a, const subtree *s, const pager_plan *plan,
                         int32_t *map)
{
    int32_t n = a->h->bvh_count, next = 0;
    unsigned char *below = calloc((size_t)n, 1); /* a node inside a page's subtree */
    if (!below)
        return false;
    for (int32_t i = 0; i < plan->page_count; i++) {
        int32_t k = plan->pages[i].node;
        for (int32_t j = s[k].end - s[k].below; j < s[k].end; j++)
            below[j] = 1;
    }
    unsigned char *pair = calloc((size_t)n, 1); /* a pair starts here */
    if (!pair) {
        free(below);
        return false;
    }
    pair[0] = 1;
    for (int32_t k = 0; k < n; k++)
        if (bvh_count(a, k) < 0)
            pair[bvh_first(a, k)] = 1;
    for (int32_t k = 0; k < n; k++) /* the pairs above the pages, in order */
        if (pair[k] && !below[k]) {
            map[k] = next++;
            map[k + 1] = next++;
        }
    free(pair);
    for (int32_t i = 0; i < plan->page_count; i++) { /* each page's subtree, whole */
        int32_t k = plan->pages[i].node;
        for (int32_t j = s[k].end - s[k].below; j < s[k].end; j++)
            map[j] = next++;
    }
    free(below);
    return next == n;
}

bool pager_relayout(void *blob, uint64_t page_bytes, const char **why)
{
    blob_arrays a = arrays_of(blob);
    int32_t n = a.h->bvh_count;
    pager_plan plan;
    if (n == 0)
        return true;
    if (!pager_plan_make(blob, page_bytes, &plan, why))
        return false;
    size_t roots = (size_t)a.h->root_count + 1;
    int32_t *prim_lo = malloc(roots * sizeof *prim_lo), *prim_hi = malloc(roots * sizeof *prim_hi);
    int32_t *map = malloc((size_t)n * sizeof *map);
    subtree *s = malloc((size_t)n * sizeof *s);
    unsigned char *old = malloc((size_t)n * a.bvh_size);
    bool ok = prim_lo && prim_hi && map && s && old && root_prims(&a, prim_lo, prim_hi) &&
              subtrees(&a, prim_lo, prim_hi, s) && relayout_map(&a, s, &plan, map);
    *why = "out of memory to lay out the scene's BVH for paging";
    if (ok) {
        unsigned char *bvh = (unsigned char *)blob + a.h->off_bvh;
        memcpy(old, bvh, (size_t)n * a.bvh_size);
        for (int32_t k = 0; k < n; k++) {
            memcpy(bvh + (uint64_t)map[k] * a.bvh_size, old + (uint64_t)k * a.bvh_size, a.bvh_size);
            int32_t first, count;
            memcpy(&first, old + (uint64_t)k * a.bvh_size, sizeof first);
            memcpy(&count, old + (uint64_t)k * a.bvh_size + 4, sizeof count);
            if (count < 0)
                bvh_set_first(&a, bvh, map[k], map[first]);
        }
    }
    free(prim_lo);
    free(prim_hi);
    free(map);
    free(s);
    free(old);
    pager_plan_free(&plan);
    return ok;
}

uint64_t pager_page_bytes_for(uint64_t budget)
{
    uint64_t b = budget / 512;
    return b < 16384 ? 16384 : b > (128u << 10) ? (128u << 10) : b;
}

bool pager_plan_make(const void *blob, uint64_t page_bytes, pager_plan *plan, const char **why)
{
    blob_arrays a = arrays_of(blob);
    const csg_blob_header *h = a.h;
    memset(plan, 0, sizeof *plan);
    plan->total_size = h->total_size;
    plan->page_bytes = page_bytes;
    plan->bvh_count = h->bvh_count;
    size_t roots = (size_t)h->root_count + 1, nodes = (size_t)h->bvh_count + 1;
    int32_t *prim_lo = malloc(roots * sizeof *prim_lo), *prim_hi = malloc(roots * sizeof *prim_hi);
    subtree *s = malloc(nodes * sizeof *s);
    bool ok = prim_lo && prim_hi && s;
    *why = "out of memory for the scene's page plan";
    if (ok && !(root_prims(&a, prim_lo, prim_hi) && subtrees(&a, prim_lo, prim_hi, s))) {
        ok = false;
        *why = "the scene's layout cannot be paged (not in the BVH's depth-first order)";
    }
    if (ok) {
        ok = choose_pages(&a, prim_lo, prim_hi, s, page_bytes, plan);
        *why = "out of memory for the scene's page plan";
    }
    free(prim_lo);
    free(prim_hi);
    free(s);
    if (!ok) {
        pager_plan_free(plan);
        return false;
    }
    uint64_t paged = 0;
    for (int32_t i = 0; i < plan->page_count; i++)
        paged += plan->pages[i].bytes;
    plan->resident_bytes = plan->total_size - paged;
    return true;
}

void pager_plan_free(pager_plan *plan)
{
    free(plan->pages);
    free(plan->by_node);
    plan->pages = NULL;
    plan->by_node = NULL;
    plan->page_count = 0;
}

/* ---- the resident part, packed ------------------------------------------------------ */

typedef struct {
    uint32_t magic;
    int32_t page_count;
    int32_t bvh_count;
    int32_t range_count;
    uint64_t total_size, page_bytes, resident_bytes;
} pager_wire;

static int range_order(const void *x, const void *y)
{
    const pager_range *a = x, *b = y;
    return a->off < b->off ? -1 : a->off > b->off;
}

/* r[0 .. n) sorted by offset, those that overlap or touch merged into
 * one: how many are left. */
static size_t ranges_merge(pager_range *r, size_t n)
{
    if (n < 2) /* (nothing to sort: r may be NULL, which qsort may not be given) */
        return n;
    qsort(r, n, sizeof *r, range_order);
    size_t merged = 0;
    for (size_t k = 0; k < n; k++) {
        pager_range *last = merged > 0 ? &r[merged - 1] : NULL;
        if (last && r[k].off <= last->off + last->len) {
            uint64_t end = r[k].off + r[k].len;
            last->len = end > last->off + last->len ? end - last->off : last->len;
        } else {
            r[merged++] = r[k];
        }
    }
    return merged;
}

/* The resident ranges: what no page holds, in order (malloc'd; *n). */
static pager_range *resident_ranges(const pager_plan *plan, int32_t *n)
{
    size_t cap = (size_t)plan->page_count * PAGER_RANGES + 1;
    pager_range *paged = malloc(cap * sizeof *paged), *out = malloc((cap + 1) * sizeof *out);
    if (!paged || !out) {
        free(paged);
        free(out);
        return NULL;
    }
    size_t m = 0;
    for (int32_t i = 0; i < plan->page_count; i++)
        for (int r = 0; r < PAGER_RANGES; r++)
            if (plan->pages[i].range[r].len > 0)
                paged[m++] = plan->pages[i].range[r];
    qsort(paged, m, sizeof *paged, range_order);
    uint64_t at = 0;
    int32_t k = 0;
    for (size_t i = 0; i < m; i++) {
        if (paged[i].off > at)
            out[k++] = (pager_range){at, paged[i].off - at};
        at = paged[i].off + paged[i].len;
    }
    if (plan->total_size > at)
        out[k++] = (pager_range){at, plan->total_size - at};
    free(paged);
    *n = k;
    return out;
}

void *pager_pack_resident(const void *blob, const pager_plan *plan, size_t *len)
{
    int32_t n = 0;
    pager_range *res = resident_ranges(plan, &n);
    if (!res)
        return NULL;
    size_t head = sizeof(pager_wire) + (size_t)plan->page_count * sizeof(pager_page) +
                  (size_t)n * sizeof(pager_range);
    *len = head + plan->resident_bytes;
    unsigned char *out = malloc(*len);
    if (out) {
        pager_wire w = {PAGER_MAGIC, plan->page_count, plan->bvh_count, n, plan->total_size,
                        plan->page_bytes, plan->resident_bytes};
        memcpy(out, &w, sizeof w);
        memcpy(out + sizeof w, plan->pages, (size_t)plan->page_count * sizeof(pager_page));
        memcpy(out + head - (size_t)n * sizeof(pager_range), res, (size_t)n * sizeof *res);
        size_t at = head;
        for (int32_t i = 0; i < n; i++) {
            memcpy(out + at, (const unsigned char *)blob + res[i].off, res[i].len);
            at += res[i].len;
        }
    }
    free(res);
    return out;
}

void pager_pack_page(const void *blob, const pager_page *page, unsigned char *out)
{
    for (int r = 0; r < PAGER_RANGES; r++) {
        memcpy(out, (const unsigned char *)blob + page->range[r].off, page->range[r].len);
        out += page->range[r].len;
    }
}

size_t pager_pack_pages(const void *blob, const pager_plan *plan, const int32_t *pages, int n,
                        unsigned char **out)
{
    uint64_t bytes = 0;
    *out = NULL;
    for (int k = 0; k < n; k++) {
        if (pages[k] < 0 || pages[k] >= plan->page_count)
            return 0;
        bytes += plan->pages[pages[k]].bytes;
    }
    *out = malloc(bytes ? bytes : 1);
    if (!*out)
        return 0;
    unsigned char *at = *out;
    for (int k = 0; k < n; k++) {
        pager_pack_page(blob, &plan->pages[pages[k]], at);
        at += plan->pages[pages[k]].bytes;
    }
    return (size_t)bytes;
}

/* ---- the worker's cache ------------------------------------------------------------- */

static csg_pager *pagers_open; /* (a list: the simulated ranks share a process) */

static double pager_clock(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Is the packed plan one this worker can use? */
static bool wire_valid(const pager_wire *w, const pager_page *pages, const pager_range *res,
                       size_t bytes_left)
{
    uint64_t paged = 0, resident = 0;
    for (int32_t i = 0; i < w->page_count; i++) {
        const pager_page *pg = &pages[i];
        if (pg->node < 0 || pg->node >= w->bvh_count ||
            (i > 0 && (pg->root_first < pages[i - 1].root_first + pages[i - 1].root_count ||
                       pg->prim_first < pages[i - 1].prim_first + pages[i - 1].prim_count)))
            return false; /* (roots and primitives ascend: page_search) */
        uint64_t sum = 0;
        for (int r = 0; r < PAGER_RANGES; r++) {
            if (pg->range[r].off > w->total_size || pg->range[r].len > w->total_size - pg->range[r].off)
                return false;
            sum += pg->range[r].len;
        }
        if (sum != pg->bytes)
            return false;
        paged += sum;
    }
    for (int32_t i = 0; i < w->range_count; i++) {
        if (res[i].off > w->total_size || res[i].len > w->total_size - res[i].off)
            return false;
        resident += res[i].len;
    }
    return resident == w->resident_bytes && paged + resident == w->total_size &&
           bytes_left == resident;
}

static void advise(csg_pager *p, uint64_t first, uint64_t count, bool populate);

/* A run of memory pages [first, first + count) noted for advice (to fault
 * in, or to give back: the list holds one kind at a time). */
static void run_note(csg_pager *p, uint64_t first, uint64_t count, bool populate)
{
    if (p->runs_n > 0 && p->runs[p->runs_n - 1].off + p->runs[p->runs_n - 1].len == first) {
        p->runs[p->runs_n - 1].len += count;
        return;
    }
    if (p->runs_n == p->runs_cap) {
        size_t cap = p->runs_cap ? 2 * p->runs_cap : 64;
        pager_range *grown = realloc(p->runs, cap * sizeof *grown);
        if (!grown) { /* (out of memory: advised at once) */
            advise(p, first, count, populate);
            return;
        }
        p->runs = grown;
        p->runs_cap = cap;
    }
    p->runs[p->runs_n++] = (pager_range){first, count};
}

/* The memory pages of range r gain (delta +1) or lose (-1) a user.  The
 * runs of them whose first user comes, or whose last goes, are noted
 * (p->runs) for runs_advise, which faults the first in (MADV_POPULATE_WRITE)
 * or gives the second back (MADV_DONTNEED). */
static void refs_add(csg_pager *p, const pager_range *r, int delta)
{
    if (r->len == 0)
        return;
    uint64_t first = r->off / OS_PAGE, last = (r->off + r->len - 1) / OS_PAGE;
    uint64_t run = 0, run_len = 0;
    for (uint64_t k = first; k <= last; k++) {
        bool comes = p->refs[k] == 0, goes = p->refs[k] + delta == 0;
        p->mapped += comes - goes;
        p->refs[k] = (uint16_t)(p->refs[k] + delta);
        if (delta > 0 ? comes : goes) {
            if (run_len == 0)
                run = k;
            run_len++;
            continue;
        }
        if (run_len > 0)
            run_note(p, run, run_len, delta > 0);
        run_len = 0;
    }
    if (run_len > 0)
        run_note(p, run, run_len, delta > 0);
}

/* The runs noted since the last call advised, sorted and those that touch
 * merged, one call each: a fetch's or an eviction's pages are mostly
 * neighbours in the blob, so their runs of memory pages (four a page, one
 * an array) become a few calls (bench/PAGING.md, *Pages read one-sided*).
 * Faulting in (MADV_POPULATE_WRITE, Linux 5.14) before the bytes are
 * written rather than a fault a 4 KiB page during the copy: tetra10's
 * install 1.255 -> 1.085 ns a byte; a kernel without it refuses the call
 * and the copy faults them in.  Giving back: MADV_DONTNEED. */
static void advise(csg_pager *p, uint64_t first, uint64_t count, bool populate)
{
#ifdef MADV_POPULATE_WRITE
    madvise(p->base + first * OS_PAGE, count * OS_PAGE, populate ? MADV_POPULATE_WRITE : MADV_DONTNEED);
#else
    if (!populate)
        madvise(p->base + first * OS_PAGE, count * OS_PAGE, MADV_DONTNEED);
#endif
}

static void runs_advise(csg_pager *p, bool populate)
{
    size_t n = ranges_merge(p->runs, p->runs_n);
    for (size_t k = 0; k < n; k++)
        advise(p, p->runs[k].off, p->runs[k].len, populate);
    p->runs_n = 0;
}

static bool pager_alloc(csg_pager *p, int32_t pages, int32_t bvh_count)
{
    size_t n = pages > 0 ? (size_t)pages : 1;
    size_t os_pages = (p->map_bytes + OS_PAGE - 1) / OS_PAGE;
    p->stamp = calloc(n, sizeof *p->stamp);
    p->here = calloc(n, sizeof *p->here);
    p->prev = malloc(n * sizeof *p->prev);
    p->next = malloc(n * sizeof *p->next);
    p->is_page_node = calloc(((size_t)bvh_count + 64) / 64, sizeof *p->is_page_node);
    p->top_rank = malloc(((size_t)bvh_count + 64) / 64 * sizeof *p->top_rank);
    p->refs = calloc(os_pages ? os_pages : 1, sizeof *p->refs);
    p->plan.pages = malloc(n * sizeof *p->plan.pages);
    p->plan.by_node = malloc(n * sizeof *p->plan.by_node);
    return p->plan.by_node && p->stamp && p->here && p->prev && p->next && p->is_page_node &&
           p->top_rank && p->refs &&
           p->plan.pages;
}

static const pager_page *by_node_pages; /* (qsort's comparison has no argument) */

static int by_node_order(const void *x, const void *y)
{
    int32_t a = by_node_pages[*(const int32_t *)x].node, b = by_node_pages[*(const int32_t *)y].node;
    return a < b ? -1 : a > b;
}

bool pager_open(csg_pager *p, const void *packed, size_t len, uint64_t budget,
                enum pager_policy policy, pager_fetch fetch, void *fetch_arg, const char **why)
{
    memset(p, 0, sizeof *p);
    p->head = p->tail = -1;
    pager_wire w;
    *why = "a malformed scene plan was received";
    if (len < sizeof w)
        return false;
    memcpy(&w, packed, sizeof w);
    size_t head = sizeof w;
    if (w.magic != PAGER_MAGIC || w.page_count < 0 || w.range_count < 0 || w.bvh_count < 0 ||
        (size_t)w.page_count > (len - head) / sizeof(pager_page))
        return false;
    head += (size_t)w.page_count * sizeof(pager_page);
    if ((size_t)w.range_count > (len - head) / sizeof(pager_range))
        return false;
    const unsigned char *bytes = packed;
    const pager_range *res = (const pager_range *)(const void *)(bytes + head);
    head += (size_t)w.range_count * sizeof(pager_range);
    p->map_bytes = w.total_size;
    *why = "out of memory for the scene's page tables";
    if (!pager_alloc(p, w.page_count, w.bvh_count)) {
        pager_close(p);
        return false;
    }
    memcpy(p->plan.pages, bytes + sizeof w, (size_t)w.page_count * sizeof(pager_page));
    p->plan.page_count = w.page_count;
    p->plan.bvh_count = w.bvh_count;
    p->plan.total_size = w.total_size;
    p->plan.page_bytes = w.page_bytes;
    p->plan.resident_bytes = w.resident_bytes;
    *why = "a malformed scene plan was received";
    if (!wire_valid(&w, p->plan.pages, res, len - head)) {
        pager_close(p);
        return false;
    }
    *why = "--scene-memory is below the scene's resident part";
    if (budget < w.resident_bytes) {
        pager_close(p);
        return false;
    }
    void *map = mmap(NULL, p->map_bytes ? p->map_bytes : 1, PROT_READ | PROT_WRITE,
                     MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    *why = "no address space for the scene";
    if (map == MAP_FAILED) {
        pager_close(p);
        return false;
    }
    p->base = map;
    size_t at = head;
    for (int32_t i = 0; i < w.range_count; i++) {
        memcpy(p->base + res[i].off, bytes + at, res[i].len);
        at += res[i].len;
        if (res[i].len > 0) /* (the resident part: one user, for ever) */
            for (uint64_t k = res[i].off / OS_PAGE; k <= (res[i].off + res[i].len - 1) / OS_PAGE; k++) {
                p->mapped += p->refs[k] == 0;
                p->refs[k] = 1;
            }
    }
    for (int32_t i = 0; i < w.page_count; i++) {
        uint32_t k = (uint32_t)p->plan.pages[i].node;
        p->is_page_node[k >> 6] |= (uint64_t)1 << (k & 63u);
        p->plan.by_node[i] = i;
    }
    by_node_pages = p->plan.pages;
    if (w.page_count > 1)
        qsort(p->plan.by_node, (size_t)w.page_count, sizeof *p->plan.by_node, by_node_order);
    for (int32_t i = 1; i < w.page_count; i++)
        if (p->plan.pages[p->plan.by_node[i]].node == p->plan.pages[p->plan.by_node[i - 1]].node) {
            *why = "a malformed scene plan was received"; /* (two pages of one top) */
            pager_close(p);
            return false;
        }
    for (size_t k = 0, below = 0; k < ((size_t)w.bvh_count + 64) / 64; k++) {
        p->top_rank[k] = (int32_t)below;
        below += (size_t)popcount64(p->is_page_node[k]);
    }
    p->budget = budget;
    p->used = p->stats.peak_bytes = w.resident_bytes;
    p->stats.memory_bytes = p->mapped * OS_PAGE;
    p->policy = policy;
    p->fetch = fetch;
    p->fetch_arg = fetch_arg;
    p->epoch = 1;
    p->prefetch = true;
    p->next_open = pagers_open;
    pagers_open = p;
    return true;
}

void pager_close(csg_pager *p)
{
    for (csg_pager **at = &pagers_open; *at; at = &(*at)->next_open)
        if (*at == p) {
            *at = p->next_open;
            break;
        }
    if (p->trace.file)
        fclose(p->trace.file);
    free(p->trace.named);
    if (p->base)
        munmap(p->base, p->map_bytes ? p->map_bytes : 1);
    free(p->stamp);
    free(p->here);
    free(p->prev);
    free(p->next);
    free(p->is_page_node);
    free(p->top_rank);
    free(p->refs);
    free(p->buffer);
    free(p->home_count);
    free(p->serve_buffer);
    free(p->fetch_order);
    free(p->spans);
    free(p->runs);
    pager_plan_free(&p->plan);
    memset(p, 0, sizeof *p);
}

csg_pager *pager_for(const void *blob)
{
    for (csg_pager *p = pagers_open; p; p = p->next_open)
        if (blob == p->base)
            return p;
    return NULL;
}

/* ---- the cache's order --------------------------------------------------------------- */

static void order_unlink(csg_pager *p, int32_t i)
{
    if (p->prev[i] >= 0)
        p->next[p->prev[i]] = p->next[i];
    else
        p->head = p->next[i];
    if (p->next[i] >= 0)
        p->prev[p->next[i]] = p->prev[i];
    else
        p->tail = p->prev[i];
}

static void order_append(csg_pager *p, int32_t i)
{
    p->prev[i] = p->tail;
    p->next[i] = -1;
    if (p->tail >= 0)
        p->next[p->tail] = i;
    else
        p->head = i;
    p->tail = i;
}

static void evict(csg_pager *p, int32_t i)
{
    order_unlink(p, i);
    p->here[i] = PAGE_ABSENT;
    p->used -= p->plan.pages[i].bytes;
    p->stats.evictions++;
    for (int r = 0; r < PAGER_RANGES; r++)
        refs_add(p, &p->plan.pages[i].range[r], -1);
}

/* Room for `bytes` more within the budget, the oldest unpinned pages
 * evicted first; pinned pages stay (the item goes over the budget). */
static void make_room(csg_pager *p, uint64_t bytes)
{
    int32_t i = p->head;
    if (i < 0 || p->used + bytes <= p->budget)
        return;
    double t0 = pager_clock();
    while (i >= 0 && p->used + bytes > p->budget) {
        int32_t next = p->next[i];
        if (p->stamp[i] != p->epoch)
            evict(p, i);
        else if (p->policy == PAGER_LRU)
            break; /* (LRU: the pinned are the newest, all behind) */
        i = next;
    }
    runs_advise(p, false);
    p->stats.install_s += pager_clock() - t0;
}

/* pages[0 .. n) in the order their homes serve them (p->fetch_order):
 * sorted by home rank, stably (a counting sort); pages itself when every
 * page comes from rank 0. */
static const int32_t *by_home(csg_pager *p, const int32_t *pages, int n)
{
    if (p->homes == 0 || n < 2 || p->serving) /* (serving: all its own, from rank 0) */
        return pages;
    int32_t *count = p->home_count;
    memset(count, 0, ((size_t)p->homes + 1) * sizeof *count);
    for (int k = 0; k < n; k++)
        count[pager_home_rank(p, pages[k])]++;
    for (int32_t h = 0, at = 0; h <= p->homes; h++) {
        int32_t c = count[h];
        count[h] = at;
        at += c;
    }
    for (int k = 0; k < n; k++)
        p->fetch_order[count[pager_home_rank(p, pages[k])]++] = pages[k];
    return p->fetch_order;
}

/* Is page i one this worker holds as its home? */
static bool is_mine(const csg_pager *p, int32_t i)
{
    return p->homes > 0 && pager_home_rank(p, i) == p->self;
}

/* pages[0 .. n), none here, fetched in one request (an ask to each home
 * they have: the fetch callback's), then installed: this worker's own
 * (homes) held for good outside the cache, the others cached.  A page
 * installed meanwhile (a fetch to answer another worker, made while this
 * one waited) is left as it is.  False when the fetch failed or memory is
 * short (p->failed). */
static void install(csg_pager *p, const int32_t *pages, int n, const unsigned char *bytes);
static bool fetch_in_place(csg_pager *p, const int32_t *pages, int n, uint64_t bytes);
static void await_fill(csg_pager *p, const int32_t *pages, int n);

static bool fetch_run(csg_pager *p, const int32_t *pages, int n)
{
    uint64_t bytes = 0;
    for (int k = 0; k < n; k++)
        bytes += p->plan.pages[pages[k]].bytes;
    make_room(p, bytes);
    if (p->fetch_into && !p->serving && p->homes == 0)
        return fetch_in_place(p, pages, n, bytes);
    /* (a fetch made while answering another worker has its own buffer: the
     * one this worker's own fetch waits on is in use) */
    unsigned char **buffer = p->serving ? &p->serve_buffer : &p->buffer;
    size_t *cap = p->serving ? &p->serve_buffer_cap : &p->buffer_cap;
    if (bytes > *cap) {
        unsigned char *grown = realloc(*buffer, bytes);
        if (!grown) {
            p->failed = true;
            return false;
        }
        *buffer = grown;
        *cap = bytes;
    }
    pages = by_home(p, pages, n);
    double t0 = pager_clock();
    bool ok = p->fetch(p->fetch_arg, pages, n, *buffer, bytes);
    p->stats.wait_s += pager_clock() - t0;
    if (!ok) {
        p->failed = true;
        return false;
    }
    p->stats.requests++;
    p->stats.pages += (uint64_t)n;
    p->stats.bytes += bytes;
    install(p, pages, n, *buffer);
    return true;
}

/* Page i, its bytes in place, takes its place: this worker's own (homes)
 * held for good outside the cache, another cached. */
static void page_placed(csg_pager *p, int32_t i)
{
    bool mine = is_mine(p, i);
    p->here[i] = mine ? PAGE_HOME : PAGE_CACHED;
    if (!mine)
        order_append(p, i);
    p->used += p->plan.pages[i].bytes;
    p->home_bytes += mine ? p->plan.pages[i].bytes : 0;
}

/* The peaks after an install. */
static void installed(csg_pager *p)
{
    if (p->used > p->stats.peak_bytes)
        p->stats.peak_bytes = p->used;
    if (p->mapped * OS_PAGE > p->stats.memory_bytes)
        p->stats.memory_bytes = p->mapped * OS_PAGE;
    if (p->used > p->budget && p->used - p->budget > p->stats.over_bytes)
        p->stats.over_bytes = p->used - p->budget;
}

/* The memory pages of those of pages[0 .. n) not here gain (+1) or lose
 * (-1) a user: each page's ranges one by one (a user a range, as evict
 * counts them), then advised in few calls. */
static void pages_refs_add(csg_pager *p, const int32_t *pages, int n, int delta)
{
    for (int k = 0; k < n; k++)
        for (int r = 0; !present(p, pages[k]) && r < PAGER_RANGES; r++)
            refs_add(p, &p->plan.pages[pages[k]].range[r], delta);
    runs_advise(p, delta > 0);
}

/* pages[0 .. n), their bytes packed at `bytes`, written into place; a
 * page here already is left as it is. */
static void install(csg_pager *p, const int32_t *pages, int n, const unsigned char *bytes)
{
    double t0 = pager_clock();
    pages_refs_add(p, pages, n, +1); /* (their fresh memory pages first) */
    const unsigned char *at = bytes;
    for (int k = 0; k < n; k++) {
        const pager_page *pg = &p->plan.pages[pages[k]];
        if (present(p, pages[k])) {
            at += pg->bytes;
            continue;
        }
        for (int r = 0; r < PAGER_RANGES; r++) {
            memcpy(p->base + pg->range[r].off, at, pg->range[r].len);
            at += pg->range[r].len;
        }
        page_placed(p, pages[k]);
    }
    p->stats.install_s += pager_clock() - t0;
    installed(p);
}

/* The byte ranges of pages[0 .. n) in p->spans, by offset, those that
 * touch merged (neighbours in the BVH's order share edges): how many, -1
 * when memory is short. */
static int spans_of(csg_pager *p, const int32_t *pages, int n)
{
    size_t most = (size_t)n * PAGER_RANGES;
    if (most > p->spans_cap) {
        pager_range *grown = realloc(p->spans, most * sizeof *grown);
        if (!grown)
            return -1;
        p->spans = grown;
        p->spans_cap = most;
    }
    size_t count = 0;
    for (int k = 0; k < n; k++)
        for (int r = 0; r < PAGER_RANGES; r++)
            if (p->plan.pages[pages[k]].range[r].len > 0)
                p->spans[count++] = p->plan.pages[pages[k]].range[r];
    return (int)ranges_merge(p->spans, count); /* (disjoint: merged where they touch) */
}

/* fetch_run's one-sided form (p->fetch_into, rank 0 serving): pages[0 ..
 * n), none here, their memory pages mapped, then their bytes written in
 * place by one call (no buffer, no copy of ours, and rank 0 does nothing);
 * a failure gives the memory pages back. */
static bool fetch_in_place(csg_pager *p, const int32_t *pages, int n, uint64_t bytes)
{
    int spans = spans_of(p, pages, n);
    if (spans < 0) {
        p->failed = true;
        return false;
    }
    double t0 = pager_clock();
    pages_refs_add(p, pages, n, +1);
    double t1 = pager_clock();
    bool ok = p->fetch_into(p->fetch_arg, p->spans, spans, p->base);
    double t2 = pager_clock();
    p->stats.wait_s += t2 - t1;
    if (!ok) {
        pages_refs_add(p, pages, n, -1);
        p->failed = true;
        return false;
    }
    p->stats.requests++;
    p->stats.pages += (uint64_t)n;
    p->stats.bytes += bytes;
    for (int k = 0; k < n; k++)
        page_placed(p, pages[k]);
    p->stats.install_s += (t1 - t0) + (pager_clock() - t2);
    installed(p);
    return true;
}

/* fetch_run, this worker's own pages first when there are others too:
 * installed before it waits on other homes, during which it answers their
 * asks and so would otherwise fetch one of its own a second time. */
static bool fetch_pages(csg_pager *p, const int32_t *pages, int n)
{
    if (p->homes > 0 && !p->serving) {
        await_fill(p, pages, n); /* (rather than ask rank 0 for them twice) */
        int left = 0;
        for (int k = 0; k < n; k++)
            left += !present(p, pages[k]);
        if (left == 0)
            return true;
        if (left < n) { /* (the list without what the fill brought) */
            int32_t *rest = malloc((size_t)left * sizeof *rest);
            if (!rest) {
                p->failed = true;
                return false;
            }
            for (int k = 0, m = 0; k < n; k++)
                if (!present(p, pages[k]))
                    rest[m++] = pages[k];
            bool ok = fetch_pages(p, rest, left);
            free(rest);
            return ok;
        }
    }
    int own = 0;
    for (int k = 0; p->homes > 0 && !p->serving && k < n; k++)
        own += is_mine(p, pages[k]);
    if (own == 0 || own == n)
        return fetch_run(p, pages, n);
    int32_t *split = malloc((size_t)n * sizeof *split);
    if (!split) {
        p->failed = true;
        return false;
    }
    for (int k = 0, a = 0, b = own; k < n; k++)
        split[is_mine(p, pages[k]) ? a++ : b++] = pages[k];
    bool ok = fetch_run(p, split, own) && fetch_run(p, split + own, n - own);
    free(split);
    return ok;
}

/* Page i, first named in this item, in the trace's list; out of memory:
 * the trace stops (closed short). */
static void trace_named(csg_pager *p, int32_t i)
{
    pager_trace *t = &p->trace;
    if (t->count == t->cap) {
        int cap = t->cap ? 2 * t->cap : 256;
        int32_t *grown = realloc(t->named, (size_t)cap * sizeof *grown);
        if (!grown) {
            fclose(t->file);
            t->file = NULL;
            return;
        }
        t->named = grown;
        t->cap = cap;
    }
    t->named[t->count++] = p->prefetching ? -1 - i : i;
}

/* Page i named in this item: true when it must be fetched. */
static bool named(csg_pager *p, int32_t i)
{
    if (p->stamp[i] == p->epoch)
        return false;
    p->stamp[i] = p->epoch;
    p->stats.touches++;
    if (p->trace.file)
        trace_named(p, i);
    if (!present(p, i))
        return true;
    if (p->here[i] == PAGE_CACHED && p->policy == PAGER_LRU) { /* the newest from now on */
        order_unlink(p, i);
        order_append(p, i);
    }
    return false;
}

void pager_need_page(csg_pager *p, int32_t page)
{
    if (page < 0 || page >= p->plan.page_count || !named(p, page))
        return;
    p->stats.faults++;
    fetch_pages(p, &page, 1);
}

/* The last page whose field at `offset` (root_first, prim_first, node) is
 * <= v, or -1; pages ascend in each. */
static int32_t page_search(const csg_pager *p, size_t offset, int32_t v)
{
    int32_t lo = 0, hi = p->plan.page_count - 1, found = -1;
    while (lo <= hi) {
        int32_t mid = lo + (hi - lo) / 2;
        int32_t key;
        memcpy(&key, (const char *)&p->plan.pages[mid] + offset, sizeof key);
        if (key <= v) {
            found = mid;
            lo = mid + 1;
        } else {
            hi = mid - 1;
        }
    }
    return found;
}

/* The page whose top is node k, or -1: its rank among the tops (the tops'
 * node numbers do not follow the pages' order; plan.by_node does). */
static int32_t page_of_node(const csg_pager *p, int32_t k)
{
    if (k < 0 || k >= p->plan.bvh_count || !pager_is_page_top(p, k))
        return -1;
    uint32_t word = (uint32_t)k >> 6;
    uint64_t below = ((uint64_t)1 << ((uint32_t)k & 63u)) - 1; /* (the bits before k's) */
    return p->plan.by_node[p->top_rank[word] + popcount64(p->is_page_node[word] & below)];
}

void pager_need_node(csg_pager *p, int32_t k)
{
    int32_t i = page_of_node(p, k);
    if (i >= 0)
        pager_need_page(p, i);
}

static int32_t page_of_root(const csg_pager *p, int32_t root)
{
    int32_t i = page_search(p, offsetof(pager_page, root_first), root);
    return i >= 0 && root < p->plan.pages[i].root_first + p->plan.pages[i].root_count ? i : -1;
}

static int32_t page_of_prim(const csg_pager *p, int32_t prim)
{
    int32_t i = page_search(p, offsetof(pager_page, prim_first), prim);
    return i >= 0 && prim < p->plan.pages[i].prim_first + p->plan.pages[i].prim_count ? i : -1;
}

void pager_need_root(csg_pager *p, int32_t root)
{
    int32_t i = page_of_root(p, root);
    if (i >= 0)
        pager_need_page(p, i);
}

void pager_need_prim(csg_pager *p, int32_t prim)
{
    int32_t i = page_of_prim(p, prim);
    if (i >= 0)
        pager_need_page(p, i);
}

/* The pages of items[0 .. n) (page_at: an item's page, or -1) fetched in
 * one request, those named already in this item left out; counted as
 * prefetched.  Out of memory for the list: fetched on demand. */
static void prefetch(csg_pager *p, const void *items, size_t n,
                     int32_t (*page_at)(const csg_pager *p, const void *items, size_t k))
{
    int32_t *list = malloc((n ? n : 1) * sizeof *list);
    if (!list)
        return;
    int count = 0;
    p->prefetching = true;
    for (size_t k = 0; k < n; k++) {
        int32_t i = page_at(p, items, k);
        if (i >= 0 && i < p->plan.page_count && named(p, i))
            list[count++] = i;
    }
    p->prefetching = false;
    if (count > 0) {
        p->stats.prefetched += (uint64_t)count;
        fetch_pages(p, list, count);
    }
    free(list);
}

static int32_t page_at_node(const csg_pager *p, const void *nodes, size_t k)
{
    return page_of_node(p, ((const int32_t *)nodes)[k]);
}

static int32_t page_at_hit(const csg_pager *p, const void *surf, size_t k)
{
    uint32_t s = ((const uint32_t *)surf)[k];
    return s != CSG_SURF_NONE ? page_of_prim(p, CSG_SURF_PRIM(s)) : -1;
}

void pager_prefetch_nodes(csg_pager *p, const int32_t *nodes, size_t n)
{
    prefetch(p, nodes, n, page_at_node);
}

void pager_prefetch_hits(csg_pager *p, const uint32_t *surf, size_t n)
{
    prefetch(p, surf, n, page_at_hit);
}

static int32_t page_at_index(const csg_pager *p, const void *pages, size_t k)
{
    (void)p;
    return ((const int32_t *)pages)[k];
}

void pager_prefetch_pages(csg_pager *p, const int32_t *pages, size_t n)
{
    prefetch(p, pages, n, page_at_index);
}

bool pager_trace_open(csg_pager *p, const char *name, int rank)
{
    if (!name || !*name)
        return true;
    char path[4096];
    int len = snprintf(path, sizeof path, "%s.%d", name, rank);
    if (p->trace.file)
        fclose(p->trace.file);
    p->trace.file = len > 0 && (size_t)len < sizeof path ? fopen(path, "w") : NULL;
    p->trace.count = 0;
    return p->trace.file != NULL;
}

void pager_trace_item(csg_pager *p, char kind, int x, int y, int w, int h)
{
    pager_trace *t = &p->trace;
    if (!t->file)
        return;
    bool ok = fprintf(t->file, "%c %d %d %d %d %d", kind, x, y, w, h, t->count) > 0;
    for (int k = 0; ok && k < t->count; k++)
        ok = fprintf(t->file, " %d", (int)t->named[k]) > 0;
    ok = ok && fputc('\n', t->file) != EOF;
    t->count = 0;
    if (!ok) {
        fclose(t->file);
        t->file = NULL;
    }
}

void pager_item_end(csg_pager *p)
{
    p->epoch++;
    if (p->epoch == 0) { /* (wrapped: every stamp is old) */
        memset(p->stamp, 0, (size_t)(p->plan.page_count > 0 ? p->plan.page_count : 1) *
                                sizeof *p->stamp);
        p->epoch = 1;
    }
    make_room(p, 0);
}

/* ---- the pages' homes (--page-home spread) -------------------------------------------- */

uint64_t pager_home_share(const pager_plan *plan, int32_t homes)
{
    uint64_t most = 0, share = 0;
    for (int32_t i = 0; homes > 0 && i < plan->page_count; i++) { /* (a home's pages: a run) */
        if (i > 0 && pager_home_of(i, plan->page_count, homes) != pager_home_of(i - 1, plan->page_count, homes))
            share = 0;
        share += plan->pages[i].bytes;
        most = share > most ? share : most;
    }
    return most;
}

bool pager_homes_fit(const pager_plan *plan, int32_t homes, uint64_t budget)
{
    return homes > 0 && budget >= plan->resident_bytes &&
           pager_home_share(plan, homes) <= (budget - plan->resident_bytes) / 3 * 2;
}

int32_t pager_homes_for(int home, int32_t workers, const pager_plan *plan, uint64_t budget)
{
    bool fits = pager_homes_fit(plan, workers, budget);
    if (home == PAGER_HOME_SPREAD)
        return fits ? workers : -1;
    return home == PAGER_HOME_AUTO && workers >= PAGER_HOME_AUTO_WORKERS && fits ? workers : 0;
}

bool pager_take_homes(csg_pager *p, int32_t homes, int rank)
{
    if (homes <= 0 || rank < 1 || rank > homes)
        return false;
    p->home_count = calloc((size_t)homes + 1, sizeof *p->home_count);
    p->fetch_order = malloc((size_t)(p->plan.page_count > 0 ? p->plan.page_count : 1) *
                            sizeof *p->fetch_order);
    if (!p->home_count || !p->fetch_order)
        return false;
    p->homes = homes; /* (from now on a page's home serves it; its own: rank 0) */
    p->self = rank;
    return true;
}

int pager_home_fill_next(csg_pager *p, int32_t *pages, int max, uint64_t max_bytes, uint64_t *bytes)
{
    int n = 0;
    *bytes = 0;
    if (p->homes <= 0)
        return 0;
    int32_t first = (int32_t)(((int64_t)(p->self - 1) * p->plan.page_count + p->homes - 1) / p->homes);
    for (int32_t i = p->fill_next > 0 ? p->fill_next : first;
         i < p->plan.page_count && is_mine(p, i) && n < max; i++) {
        p->fill_next = i + 1;
        if (p->here[i] != PAGE_ABSENT)
            continue;
        if (n > 0 && *bytes + p->plan.pages[i].bytes > max_bytes) {
            p->fill_next = i; /* (the next run's first) */
            break;
        }
        pages[n++] = i;
        *bytes += p->plan.pages[i].bytes;
    }
    for (int k = 0; k < n; k++)
        p->here[pages[k]] = PAGE_COMING;
    return n;
}

void pager_home_fill_failed(csg_pager *p, const int32_t *pages, int n)
{
    for (int k = 0; k < n; k++)
        if (p->here[pages[k]] == PAGE_COMING)
            p->here[pages[k]] = PAGE_ABSENT;
}

/* Any of pages[0 .. n) coming in the background fill: waited for (the
 * fill's current ask, which holds them all). */
static void await_fill(csg_pager *p, const int32_t *pages, int n)
{
    for (int k = 0; k < n; k++)
        if (p->here[pages[k]] == PAGE_COMING) {
            if (p->fill_wait)
                p->fill_wait(p->fetch_arg);
            return;
        }
}

void pager_home_fill(csg_pager *p, const int32_t *pages, int n, const unsigned char *bytes)
{
    uint64_t size = 0;
    for (int k = 0; k < n; k++)
        if (!present(p, pages[k]))
            size += p->plan.pages[pages[k]].bytes;
    make_room(p, size);
    p->stats.pages += (uint64_t)n;
    for (int k = 0; k < n; k++)
        p->stats.bytes += p->plan.pages[pages[k]].bytes;
    install(p, pages, n, bytes);
}

size_t pager_pack_homes(csg_pager *p, const int32_t *pages, int n, unsigned char **out)
{
    *out = NULL;
    int absent = 0;
    for (int k = 0; k < n; k++)
        if (pages[k] < 0 || pages[k] >= p->plan.page_count || !is_mine(p, pages[k]) || p->serving)
            return 0;
    await_fill(p, pages, n);
    for (int k = 0; k < n; k++)
        absent += !present(p, pages[k]);
    if (absent > 0) { /* (its own pages not here yet: from rank 0, once) */
        int32_t *list = malloc((size_t)absent * sizeof *list);
        if (!list)
            return 0;
        int m = 0;
        for (int k = 0; k < n; k++)
            if (!present(p, pages[k]))
                list[m++] = pages[k];
        p->serving = true;
        bool ok = fetch_pages(p, list, m);
        p->serving = false;
        free(list);
        if (!ok)
            return 0;
    }
    size_t bytes = pager_pack_pages(p->base, &p->plan, pages, n, out);
    p->stats.served += *out != NULL;
    p->stats.served_bytes += bytes;
    return bytes;
}

/* ---- the engine's calls (csg/device/intersect.h) -------------------------------------- */

void csg_page_enter(struct csg_pager *p, csg_i32 node)
{
    pager_need_node(p, node); /* (a page's top: CSG_PAGE_ENTER tested its bit) */
}

void csg_page_root(struct csg_pager *p, csg_i32 root)
{
    pager_need_root(p, root);
}

void csg_page_prim(struct csg_pager *p, csg_i32 prim)
{
    pager_need_prim(p, prim);
}
