/*
 * schedule.c — the work-item schedulers of schedule.h.
 *
 * Ready tiles wait in one structure per policy: a FIFO (raster), a binary
 * max-heap on (estimate, then the lower tile number) (cost, tail), or one
 * FIFO per worker threaded through next_of (static).  The tail policy
 * splits at sched_next time: it pops a whole tile, appends its quarters to
 * `items` (each with its own estimate) and serves them from `front` before
 * anything else.
 *
 * Invariants: a whole tile is in at most one ready structure, and only
 * once; every item handed out gets order = dispatched++; tile_left[t]
 * counts the items of tile t not yet done (1, or 4 once split into
 * quarters, less the one already sent), so sched_done can say when a tile
 * is complete.  Out of memory while splitting, the tile is sent whole.
 * Requeued items (a lost worker's) wait in `again`, first out first; the
 * static queue of a lost worker is served to any worker whose own is
 * empty.
 */
#include "schedule.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const sched_names[SCHED_POLICIES] = {"raster", "cost", "static", "tail",
                                                        "region"};

const char *sched_policy_name(enum sched_policy p)
{
    return p >= 0 && p < SCHED_POLICIES ? sched_names[p] : "?";
}

bool sched_init(sched *s, enum sched_policy p, int workers, int in_flight, int tiles,
                sched_estimate_fn estimate, void *estimate_arg)
{
    memset(s, 0, sizeof *s);
    s->policy = p;
    s->workers = workers > 0 ? workers : 1;
    s->in_flight = in_flight > 0 ? in_flight : 1;
    s->batch_floor = 1;
    s->estimate = estimate;
    s->estimate_arg = estimate_arg;
    s->tiles = tiles;
    s->fill_front = tiles;
    size_t n = (size_t)(tiles > 0 ? tiles : 1), w = (size_t)s->workers;
    s->cap = tiles > 0 ? tiles : 1;
    s->items = malloc((size_t)s->cap * sizeof *s->items);
    s->fifo = malloc(n * sizeof *s->fifo);
    s->heap = malloc(n * sizeof *s->heap);
    s->next_of = malloc(n * sizeof *s->next_of);
    s->tile_left = calloc(n, sizeof *s->tile_left);
    s->first = malloc(w * sizeof *s->first);
    s->last = malloc(w * sizeof *s->last);
    s->queued = calloc(w, sizeof *s->queued);
    s->released = calloc(w, sizeof *s->released);
    if (!s->items || !s->fifo || !s->heap || !s->next_of || !s->tile_left || !s->first ||
        !s->last || !s->queued || !s->released)
        return false;
    for (size_t i = 0; i < w; i++)
        s->first[i] = s->last[i] = -1;
    return true;
}

void sched_free(sched *s)
{
    free(s->items);
    free(s->fifo);
    free(s->heap);
    free(s->next_of);
    free(s->tile_left);
    free(s->first);
    free(s->last);
    free(s->queued);
    free(s->again);
    free(s->released);
    memset(s, 0, sizeof *s);
}

/* ---- items ----------------------------------------------------------------- */

/* Room for `more` items beyond s->count; false when out of memory. */
static bool sched_reserve(sched *s, int more)
{
    if (s->count + more <= s->cap)
        return true;
    int cap = s->cap * 2 > s->count + more ? s->cap * 2 : s->count + more;
    sched_item *grown = realloc(s->items, (size_t)cap * sizeof *grown);
    if (!grown)
        return false;
    s->items = grown;
    s->cap = cap;
    return true;
}

/* A new item for rectangle r of tile `tile`; -1 when out of memory.  Its
 * estimate is asked for when `estimated` (and estimates exist). */
static int sched_new_item(sched *s, int tile, tile_rect r, int piece, bool skipped,
                          bool estimated)
{
    if (!sched_reserve(s, 1))
        return -1;
    sched_item *it = &s->items[s->count];
    memset(it, 0, sizeof *it);
    it->rect = r;
    it->tile = tile;
    it->piece = piece;
    it->skipped = skipped;
    it->estimate = s->estimate && estimated ? s->estimate(s->estimate_arg, r) : -1.0;
    it->order = -1;
    it->worker = -1;
    return s->count++;
}

/* ---- the cost heap ----------------------------------------------------------- */

static bool sched_before(const sched *s, int a, int b)
{
    const sched_item *x = &s->items[a], *y = &s->items[b];
    return x->estimate != y->estimate ? x->estimate > y->estimate : x->tile < y->tile;
}

static void sched_swap(int *v, int i, int j)
{
    int t = v[i];
    v[i] = v[j];
    v[j] = t;
}

static void sched_heap_push(sched *s, int item)
{
    s->ready_estimate += s->items[item].estimate;
    int i = s->heap_n++;
    s->heap[i] = item;
    while (i > 0 && sched_before(s, s->heap[i], s->heap[(i - 1) / 2])) {
        sched_swap(s->heap, i, (i - 1) / 2);
        i = (i - 1) / 2;
    }
}

static int sched_heap_pop(sched *s)
{
    int top = s->heap[0];
    s->ready_estimate = s->heap_n > 1 ? s->ready_estimate - s->items[top].estimate : 0.0;
    s->heap[0] = s->heap[--s->heap_n];
    for (int i = 0;;) {
        int l = 2 * i + 1, r = l + 1, best = i;
        if (l < s->heap_n && sched_before(s, s->heap[l], s->heap[best]))
            best = l;
        if (r < s->heap_n && sched_before(s, s->heap[r], s->heap[best]))
            best = r;
        if (best == i)
            break;
        sched_swap(s->heap, i, best);
        i = best;
    }
    return top;
}

/* ---- adding ------------------------------------------------------------------- */

/* An item's estimate as the sums count it (unknown, < 0: nothing). */
static double sched_estimate_of(const sched *s, int item)
{
    return s->items[item].estimate > 0 ? s->items[item].estimate : 0.0;
}

static bool sched_by_cost(const sched *s)
{
    return (s->policy == SCHED_COST || s->policy == SCHED_TAIL) && s->estimate;
}

/* Each worker has its own queue of tiles (static, region). */
static bool sched_queues(const sched *s)
{
    return s->policy == SCHED_STATIC || s->policy == SCHED_REGION;
}

/* The worker whose queue tile `tile` joins: static, the k-th tile added
 * to worker k mod W; region, the band of the image it lies in. */
static int sched_owner(const sched *s, int tile)
{
    if (s->policy == SCHED_STATIC)
        return s->added % s->workers;
    int w = s->tiles > 0 ? (int)((long long)tile * s->workers / s->tiles) : 0;
    return w < 0 ? 0 : w >= s->workers ? s->workers - 1 : w;
}

/* Item `item` into the policy's ready structure, its estimate counted. */
static void sched_queue(sched *s, int item)
{
    if (sched_queues(s)) {
        int w = sched_owner(s, s->items[item].tile);
        s->next_of[item] = -1;
        if (s->last[w] >= 0)
            s->next_of[s->last[w]] = item;
        else
            s->first[w] = item;
        s->last[w] = item;
        s->queued[w]++;
        s->in_queues++;
    } else if (sched_by_cost(s)) {
        sched_heap_push(s, item);
    } else {
        s->fifo[s->fifo_n++] = item;
        s->ready_estimate += sched_estimate_of(s, item);
    }
    double e = sched_estimate_of(s, item);
    s->added_estimate += e;
    s->max_estimate = e > s->max_estimate ? e : s->max_estimate;
    s->added_items++;
}

/* The i-th of n cuts of the span [at, at + len): ceil(len i / n) on. */
static int sched_cut_at(int at, int len, int i, int n)
{
    return at + (len * i + n - 1) / n;
}

/* The pieces of tile `tile` (rectangle r), c x c of them less the empty
 * ones, numbered from 1 row by row, made into out[]: each with its own
 * estimate, or marked a fill item (rendered whole: no records, no
 * estimate); how many, 0 when memory runs out (then none is made). */
static int sched_make_pieces(sched *s, int tile, tile_rect r, int c, bool fill, int *out)
{
    int n = 0;
    if (!sched_reserve(s, c * c)) /* (before any piece exists) */
        return 0;
    for (int j = 0; j < c; j++)
        for (int i = 0; i < c; i++) {
            int x0 = sched_cut_at(r.x, r.width, i, c), x1 = sched_cut_at(r.x, r.width, i + 1, c);
            int y0 = sched_cut_at(r.y, r.height, j, c), y1 = sched_cut_at(r.y, r.height, j + 1, c);
            if (x1 > x0 && y1 > y0) {
                out[n] = sched_new_item(s, tile, (tile_rect){x0, y0, x1 - x0, y1 - y0},
                                        j * c + i + 1, false, !fill);
                s->items[out[n++]].fill = fill;
            }
        }
    s->tile_left[tile] = n;
    return n;
}

/* Tile item `item` replaced by its pieces, each queued; false (nothing
 * made) when memory runs out. */
static bool sched_queue_pieces(sched *s, int item)
{
    int made[SCHED_PIECES_MAX];
    int n = sched_make_pieces(s, s->items[item].tile, s->items[item].rect, s->cuts, false,
                              made);
    for (int k = 0; k < n; k++)
        sched_queue(s, made[k]);
    if (n > 0)
        s->items[item].split = true;
    return n > 0;
}

bool sched_add(sched *s, int tile, tile_rect r)
{
    bool cut = s->cuts > 1;
    int item = sched_new_item(s, tile, r, 0, false, !cut);
    if (item < 0)
        return false;
    s->tile_left[tile] = 1;
    if (!cut || !sched_queue_pieces(s, item)) {
        if (cut && s->estimate) /* (out of memory for the pieces: the tile goes whole) */
            s->items[item].estimate = s->estimate(s->estimate_arg, r);
        sched_queue(s, item);
    }
    s->added++;
    s->known++;
    return true;
}

bool sched_cut(sched *s, int pieces)
{
    int c = 1;
    while (c * c < pieces)
        c *= 2;
    if (c <= 1 || sched_queues(s))
        return true; /* (static, region: whole tiles) */
    size_t n = (size_t)s->tiles * (size_t)(c * c);
    int *fifo = realloc(s->fifo, n * sizeof *fifo);
    if (fifo)
        s->fifo = fifo;
    int *heap = fifo ? realloc(s->heap, n * sizeof *heap) : NULL;
    if (heap)
        s->heap = heap;
    if (!heap)
        return false;
    s->cuts = c;
    return true;
}

int sched_pieces_auto(int requested, int workers, int tiles, int tile_edge, bool compressed)
{
    int c = 1;
    if (requested > 0) {
        while (c * c < requested && 2 * c <= tile_edge) /* (pieces of a pixel at least) */
            c *= 2;
        return c * c;
    }
    if (workers < SCHED_PIECES_WORKERS || compressed)
        return 1;
    /* (one cut at most: 16 pieces a tile at 1024 workers, 262 144 items a
     * frame, keep rank 0 busy 88 % of the frame on their parts; and none
     * where a worker has few tiles: rank 0's own work on each part, 0.2
     * us, then outweighs the tail the quarters shorten) */
    bool cut = (double)tiles < (double)SCHED_PIECES_ITEMS * workers &&
               (double)tiles >= (double)SCHED_PIECES_FEWEST * workers &&
               tile_edge / 2 >= SCHED_PIECE_MIN;
    return cut ? 4 : 1;
}

bool sched_skip(sched *s, int tile, tile_rect r)
{
    s->known++;
    return sched_new_item(s, tile, r, 0, true, false) >= 0;
}

bool sched_resume(sched *s, int tile, tile_rect r)
{
    int item = sched_new_item(s, tile, r, 0, true, false);
    if (item >= 0)
        s->items[item].resumed = true;
    return item >= 0;
}

void sched_close(sched *s)
{
    s->closed = true;
}

/* ---- handing out ----------------------------------------------------------------- */

/* Whole tiles ready and not yet sent (static: every worker's). */
static int sched_waiting(const sched *s)
{
    int again = s->again_n - s->again_head + (s->fill_pieces_n - s->fill_pieces_head);
    if (sched_queues(s))
        return again + s->in_queues;
    return again + s->heap_n + (s->fifo_n - s->fifo_head);
}

int sched_ready(const sched *s)
{
    return sched_waiting(s) + (s->front_n - s->front_head);
}

/* Splits whole tile `item` into its quarters, queued in `front`; false
 * (the tile goes whole) when it cannot be split or memory runs out. */
static bool sched_split(sched *s, int item)
{
    tile_rect r = s->items[item].rect;
    int n = r.width * r.height < 2 ? 0 : sched_make_pieces(s, s->items[item].tile, r, 2, false,
                                                           s->front);
    if (n == 0)
        return false;
    s->items[item].split = true;
    s->front_head = 0;
    s->front_n = n;
    return true;
}

/* Static: the head of worker w's queue, or -1. */
static int sched_pop_static(sched *s, int w)
{
    int item = s->first[w];
    if (item >= 0) {
        s->first[w] = s->next_of[item];
        if (s->first[w] < 0)
            s->last[w] = -1;
        s->queued[w]--;
        s->in_queues--;
    }
    return item;
}

/* Region: the last tile of the longest queue other than w's (the far end
 * of the band whose owner will reach it last), or -1. */
static int sched_steal(sched *s, int w)
{
    int victim = -1;
    for (int v = 0; v < s->workers; v++)
        if (v != w && s->queued[v] > 0 && (victim < 0 || s->queued[v] > s->queued[victim]))
            victim = v;
    if (victim < 0)
        return -1;
    int item = s->last[victim], before = -1;
    for (int i = s->first[victim]; i != item; i = s->next_of[i])
        before = i;
    if (before < 0)
        s->first[victim] = -1;
    else
        s->next_of[before] = -1;
    s->last[victim] = before;
    s->queued[victim]--;
    s->in_queues--;
    s->stolen++;
    return item;
}

/* Static: worker w's queue, then a lost worker's. */
static int sched_pop_static_any(sched *s, int w)
{
    int item = sched_pop_static(s, w);
    for (int v = 0; item < 0 && v < s->workers; v++)
        if (s->released[v])
            item = sched_pop_static(s, v);
    return item;
}

/* The next whole tile in policy order for worker w, or -1. */
static int sched_pop(sched *s, int w)
{
    if (s->policy == SCHED_STATIC)
        return sched_pop_static_any(s, w);
    if (s->policy == SCHED_REGION) {
        int item = sched_pop_static(s, w);
        return item >= 0 ? item : sched_steal(s, w);
    }
    if (s->heap_n > 0)
        return sched_heap_pop(s);
    if (s->fifo_head == s->fifo_n)
        return -1;
    int item = s->fifo[s->fifo_head++];
    s->ready_estimate =
        s->fifo_head < s->fifo_n ? s->ready_estimate - sched_estimate_of(s, item) : 0.0;
    return item;
}

static bool sched_in_tail(const sched *s)
{
    return s->policy == SCHED_TAIL && s->closed &&
           sched_waiting(s) <= SCHED_TAIL_TILES_PER_SLOT * s->workers * s->in_flight;
}

/* Tail: tiles are being split (or the split begins with the next one):
 * one piece a message. */
static bool sched_splitting(const sched *s)
{
    return sched_in_tail(s) || s->front_head < s->front_n;
}

/* Item `item` handed out now: its dispatch order and time. */
static void sched_mark_sent(sched *s, int item, double now)
{
    s->items[item].order = s->dispatched++;
    s->items[item].sent_s = now;
}

int sched_next(sched *s, int w, double now)
{
    int item = -1;
    if (s->again_head < s->again_n) {
        item = s->again[s->again_head++];
    } else if (s->fill_pieces_head < s->fill_pieces_n) {
        item = s->fill_pieces[s->fill_pieces_head++];
    } else if (s->front_head < s->front_n) {
        item = s->front[s->front_head++];
    } else {
        bool tail = sched_in_tail(s);
        item = sched_pop(s, w < 0 || w >= s->workers ? 0 : w);
        if (item >= 0 && tail && s->items[item].piece == 0 && sched_split(s, item))
            item = s->front[s->front_head++];
    }
    if (item >= 0)
        sched_mark_sent(s, item, now);
    return item;
}

bool sched_requeue(sched *s, int item)
{
    if (s->again_n == s->again_cap) {
        int cap = s->again_cap ? s->again_cap * 2 : 8;
        int *grown = realloc(s->again, (size_t)cap * sizeof *grown);
        if (!grown)
            return false;
        s->again = grown;
        s->again_cap = cap;
    }
    s->again[s->again_n++] = item;
    s->items[item].worker = -1;
    s->requeued++;
    return true;
}

void sched_release(sched *s, int w)
{
    if (w >= 0 && w < s->workers)
        s->released[w] = true;
}

bool sched_finished(const sched *s)
{
    return s->closed && s->front_head >= s->front_n && sched_waiting(s) == 0;
}

int sched_batch_limit(int requested, int workers, int max)
{
    int limit = requested > 0                     ? requested
                : workers >= SCHED_BATCH_WORKERS ? SCHED_BATCH_AUTO
                                                  : 1;
    return limit < 1 ? 1 : limit > max ? max : limit;
}

/* The tiles' costs are estimated (hetero's records): batches are cut by
 * their cost (sched_next_batch), not their count. */
static bool sched_budgeted(const sched *s)
{
    return s->estimate && !sched_queues(s);
}

/* Messages in one spread of what is left over every worker: with
 * estimates, one round (a batch is its share of the estimated cost, so
 * costly tiles go in small batches); by count (homo, the fill),
 * SCHED_BATCH_SPREAD rounds, since a count says nothing of the cost. */
static int sched_round(const sched *s, bool by_cost)
{
    return s->workers * s->in_flight * (by_cost ? SCHED_BATCH_SPREAD_COST : SCHED_BATCH_SPREAD);
}

/* Tiles not known yet (the pass has not reached them, the fill has not
 * claimed them), counted as `per_tile` each (what a known tile adds on
 * average, skipped ones 0). */
static double sched_unknown(const sched *s, double per_tile_total)
{
    int unknown = s->closed || s->known == 0 ? 0 : s->fill_front - s->known;
    return unknown > 0 ? unknown * per_tile_total / s->known : 0.0;
}

/* `left` spread over `round` messages, rounded up, within floor .. limit. */
static int sched_share(double left, int round, int floor, int limit)
{
    double b = ceil(left / round);
    return b < floor ? (floor < limit ? floor : limit) : b > limit ? limit : (int)b;
}

void sched_batch_floor(sched *s, int floor, int slots)
{
    s->batch_floor = floor > 1 && slots > 0 ? floor : 1;
    s->floor_slots = slots > 0 ? slots : 0;
}

/* The floor of a batch with `left` items to go (sched_batch_floor). */
static int sched_floor(const sched *s, double left)
{
    if (s->batch_floor <= 1)
        return 1;
    double spread = ceil(left / s->floor_slots);
    return spread < 1 ? 1 : spread < s->batch_floor ? (int)spread : s->batch_floor;
}

/* Items left: ready, and those of the tiles not known yet. */
static double sched_items_left(const sched *s)
{
    return sched_waiting(s) + sched_unknown(s, s->added_items);
}

int sched_batch(const sched *s, int limit)
{
    if (limit <= 1 || sched_splitting(s))
        return 1; /* (tail: the last tiles go as single quarters) */
    double left = sched_items_left(s);
    return sched_share(left, sched_round(s, sched_budgeted(s)), sched_floor(s, left), limit);
}

/* Raster: the next `want` tiles of the FIFO become every (ready / want)-th
 * one, so a batch spreads over the image instead of taking a run of
 * neighbours (whose costs go together). */
static void sched_spread(sched *s, int want)
{
    int head = s->fifo_head, stride = (s->fifo_n - head) / want;
    for (int k = 1; k < want && stride > 1; k++)
        sched_swap(s->fifo, head + k, head + k * stride);
}

/* The estimate of the item sched_next would hand out next (0: none). */
static double sched_peek_estimate(const sched *s)
{
    if (s->again_head < s->again_n)
        return s->items[s->again[s->again_head]].estimate;
    if (s->fill_pieces_head < s->fill_pieces_n)
        return 0.0; /* (a fill item: no estimate) */
    if (s->heap_n > 0)
        return s->items[s->heap[0]].estimate;
    return s->fifo_head < s->fifo_n ? s->items[s->fifo[s->fifo_head]].estimate : 0.0;
}

int sched_next_batch(sched *s, int w, double now, int limit, int *out)
{
    int want = sched_batch(s, limit), k = 0, floor = sched_floor(s, sched_items_left(s));
    bool fresh = s->again_head == s->again_n;
    if (want > 1 && fresh && !sched_by_cost(s) && !sched_queues(s))
        sched_spread(s, want); /* (region: a run of neighbours, on purpose) */
    /* cost: a batch costs at most its share of the estimate left, or the
     * largest tile's when that is more (a worker takes that long on one
     * tile anyway), so the costliest tiles go alone */
    double left = (s->ready_estimate + sched_unknown(s, s->added_estimate)) / sched_round(s, true);
    double budget = !sched_budgeted(s) || want < 2 ? 0.0
                    : left > s->max_estimate     ? left
                                                 : s->max_estimate;
    for (double sum = 0.0; k < want; k++) {
        double next = sched_peek_estimate(s);
        if (k >= floor && budget > 0 && sum + next > budget)
            break;
        if (k > 0 && sched_splitting(s))
            break; /* (the tail began: its pieces go one a message) */
        if ((out[k] = sched_next(s, w, now)) < 0)
            break;
        sum += sched_estimate_of(s, out[k]);
    }
    return k;
}

void sched_fill_enable(sched *s)
{
    s->fill = s->policy != SCHED_STATIC; /* (static: each tile has its worker) */
}

int sched_fill_front(const sched *s)
{
    return s->fill_front;
}

int sched_fill_claim(sched *s, int offered)
{
    if (!s->fill || s->closed || s->fill_front <= offered)
        return -1;
    s->filled++;
    return --s->fill_front;
}

int sched_fill_batch(const sched *s, int limit)
{
    int left = s->fill_front - s->known; /* (unclaimed, not offered yet) */
    return limit <= 1 ? 1 : sched_share(left, sched_round(s, false), sched_floor(s, left), limit);
}

bool sched_fill_skip(sched *s, int tile, tile_rect r)
{
    return sched_new_item(s, tile, r, 0, true, false) >= 0;
}

int sched_next_fill(sched *s, double now, int tile, tile_rect r)
{
    int item = -1;
    if (s->cuts > 1 && s->fill_pieces_head == s->fill_pieces_n) { /* its pieces: the first
                                                           now, the others next */
        s->fill_pieces_n = sched_make_pieces(s, tile, r, s->cuts, true, s->fill_pieces);
        s->fill_pieces_head = s->fill_pieces_n > 0;
        item = s->fill_pieces_n > 0 ? s->fill_pieces[0] : -1;
    }
    if (item < 0) { /* (whole: not cut, or out of memory for the pieces) */
        item = sched_new_item(s, tile, r, 0, false, false); /* (no records to estimate from) */
        if (item < 0)
            return -1;
        s->items[item].fill = true;
        s->tile_left[tile] = 1;
    }
    sched_mark_sent(s, item, now);
    s->added++;
    return item;
}

int sched_next_fill_piece(sched *s, double now)
{
    if (s->fill_pieces_head == s->fill_pieces_n)
        return -1;
    int item = s->fill_pieces[s->fill_pieces_head++];
    sched_mark_sent(s, item, now);
    return item;
}

bool sched_done(sched *s, int item)
{
    return --s->tile_left[s->items[item].tile] == 0;
}
