/*
 * bvh_build.c — the BVH over the bounded roots (bvh_build.h).
 *
 * Binned SAH (Wald, "On fast Construction of SAH-based Bounding Volume
 * Hierarchies", 2007): at each node the box centres are binned along each
 * axis and the split between two bins that minimises
 *   BVH_TRAVERSAL_COST + (area(L) * n(L) + area(R) * n(R)) / area(node)
 * (one root test costs 1) is taken, unless a leaf, costing n, is no
 * dearer and n <= BVH_MAX_LEAF.  Centres that all coincide on every axis
 * cannot be binned: such a set is halved in index order.  Below depth
 * BVH_MEDIAN_DEPTH every split halves the set (median of the centres
 * along the widest axis), so the depth stays below
 * BVH_MEDIAN_DEPTH + log2(CSG_MAX_PRIMS) + 1 < CSG_BVH_STACK whatever the
 * scene.  Everything is computed in double in a fixed order with total
 * orders for ties: the same scene gives the same tree on every run.
 *
 * Speed (a million triangles and more, the SPD's tetra10 and up): each
 * item carries its box, so a node's passes read its items in order; one
 * pass bins the three axes at once; a node's box is its parent's bins'
 * union on its side (exact: a union of finite boxes is a min and a max).
 * The top levels' two halves are built by two threads, each into a tree
 * of its own numbered from 0, then spliced where the one-thread build
 * would have numbered them: a node's children are a pair, and the whole
 * left subtree is numbered before the right one, so a subtree's
 * descendants are one run of numbers.
 */
#include "bvh_build.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define BVH_BINS 32
#define BVH_MAX_LEAF 4
#define BVH_TRAVERSAL_COST 1.0
#define BVH_MEDIAN_DEPTH 32
#define BVH_FEW 32 /* nodes of at most this many: bvh_sah_few */
/* The halves of a split of at least this many roots are built by two
 * threads (a thread's start costs about 50 us: a few hundred roots' build),
 * down to BVH_THREAD_LEVELS levels (2^levels threads at most). */
#define BVH_THREAD_MIN 8192
#define BVH_THREAD_LEVELS 3

typedef struct {
    dbox box;   /* the root's world box */
    double key; /* the centre along the axis being sorted on */
    int root;
} bvh_item;

/* A tree being built: node 0 its root, its descendants from 1 in the
 * order the one-thread build numbers them.  Its leaves fill order[placed..]
 * (the array is shared: every subtree has a run of its own). */
typedef struct {
    bvh_build_node *nodes;
    int count, cap;
    int *order;
    int placed;
    int thread_levels; /* levels of splits below this tree's root that may
                          still build their halves apart */
} bvh_tree;

/* A split: items[0..left) and the rest, the axis, each side's box. */
typedef struct {
    int left, axis;
    dbox lbox, rbox;
} bvh_cut;

/* *box = box_union(*box, *b) for the finite boxes of the bounded roots,
 * branch-free and in place (a minsd and a maxsd a bound; dbox.h's NaN-aware
 * union by value made the binning twice as slow); on finite operands the
 * two agree to the bit, ties included. */
static inline void grow_box(dbox *box, const dbox *b)
{
    for (int i = 0; i < 3; i++) {
        box->lo[i] = box->lo[i] < b->lo[i] ? box->lo[i] : b->lo[i];
        box->hi[i] = box->hi[i] > b->hi[i] ? box->hi[i] : b->hi[i];
    }
}

static double centre(const bvh_item *it, int axis)
{
    return 0.5 * (it->box.lo[axis] + it->box.hi[axis]);
}

static double box_half_area(const dbox *b)
{
    double d[3];
    for (int a = 0; a < 3; a++)
        d[a] = b->hi[a] - b->lo[a];
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* The bin of an item's centre.  The clamps come before the conversion: a
 * spread of a few subnormals makes the scale infinite, and an int from an
 * infinity or a NaN is undefined (a NaN, 0 * inf, goes to bin 0). */
static int bvh_bin(const bvh_item *it, int axis, double lo, double scale)
{
    double b = (centre(it, axis) - lo) * scale;
    if (!(b >= 0))
        return 0;
    return b >= BVH_BINS ? BVH_BINS - 1 : (int)b;
}

static dbox items_box(const bvh_item *items, int n)
{
    dbox box = box_empty();
    for (int i = 0; i < n; i++)
        grow_box(&box, &items[i].box);
    return box;
}

/* The axes along which the centres spread, and bvh_bin's origin and
 * scale on each. */
typedef struct {
    bool used[3];
    double lo[3], scale[3];
} bvh_axes;

static void bvh_axes_of(bvh_axes *ax, const dbox *centres)
{
    for (int a = 0; a < 3; a++) {
        double extent = centres->hi[a] - centres->lo[a];
        ax->used[a] = extent > 0;
        ax->lo[a] = centres->lo[a];
        ax->scale[a] = ax->used[a] ? BVH_BINS / extent : 0;
    }
}

/* The best split so far: its cost, axis and first bin of the right part. */
typedef struct {
    double cost;
    int axis, bin;
    bool found;
} bvh_best;

/* The split at `bin` on `axis`, its left part `left` (of left_n items) and
 * its right part's area times its items `right_cost`, taken if cheaper. */
static void bvh_consider(bvh_best *best, double area, const dbox *left, int left_n,
                         double right_cost, int axis, int bin)
{
    double cost = BVH_TRAVERSAL_COST + (box_half_area(left) * left_n + right_cost) / area;
    if (cost < best->cost)
        *best = (bvh_best){cost, axis, bin, true};
}

/* The bins of the three axes, filled in one pass over the items. */
typedef struct {
    int count[3][BVH_BINS];
    dbox bounds[3][BVH_BINS];
} bvh_bins;

static void bvh_fill_bins(bvh_bins *bins, const bvh_axes *ax, const bvh_item *items, int n)
{
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < BVH_BINS; b++) {
            bins->count[a][b] = 0;
            bins->bounds[a][b] = box_empty();
        }
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            if (!ax->used[a])
                continue;
            int b = bvh_bin(&items[i], a, ax->lo[a], ax->scale[a]);
            bins->count[a][b]++;
            grow_box(&bins->bounds[a][b], &items[i].box);
        }
}

/* The SAH split of n items from their bins (see bvh_best). */
static void bvh_sah_bins(bvh_best *best, const bvh_bins *bins, const bvh_axes *ax, int n,
                         double area)
{
    for (int a = 0; a < 3; a++) {
        if (!ax->used[a])
            continue;
        /* right-to-left sweep: the cost of the right part of each split */
        double right_cost[BVH_BINS];
        dbox acc = box_empty();
        int acc_n = 0;
        for (int b = BVH_BINS - 1; b > 0; b--) {
            acc = box_union(acc, bins->bounds[a][b]);
            acc_n += bins->count[a][b];
            right_cost[b] = acc_n ? box_half_area(&acc) * acc_n : 0;
        }
        acc = box_empty();
        acc_n = 0;
        for (int b = 1; b < BVH_BINS; b++) {
            acc = box_union(acc, bins->bounds[a][b - 1]);
            acc_n += bins->count[a][b - 1];
            if (acc_n != 0 && acc_n != n)
                bvh_consider(best, area, &acc, acc_n, right_cost[b], a, b);
        }
    }
}

/* at[0..n): 0..n-1 ordered by bin[], stably.  An insertion sort for a
 * few items; above BVH_FEW_SORT a counting sort over the BVH_BINS bins
 * (the insertion sort's quadratic moves were 7 % of a build). */
#define BVH_FEW_SORT 12
static void bvh_by_bin(const int *bin, int n, int *at)
{
    if (n <= BVH_FEW_SORT) {
        for (int i = 0; i < n; i++) {
            int j = i;
            for (; j > 0 && bin[at[j - 1]] > bin[i]; j--)
                at[j] = at[j - 1];
            at[j] = i;
        }
        return;
    }
    int start[BVH_BINS + 1] = {0};
    for (int i = 0; i < n; i++)
        start[bin[i] + 1]++;
    for (int b = 1; b <= BVH_BINS; b++)
        start[b] += start[b - 1];
    for (int i = 0; i < n; i++)
        at[start[bin[i]]++] = i;
}

/* The same split as bvh_sah_bins for n <= BVH_FEW items, from the bins
 * they occupy rather than all BVH_BINS of each axis (whose set-up and
 * sweeps cost more than the binning below a few dozen items: half the
 * nodes of a big scene hold 2 or 3).  An empty bin changes no cost: the
 * positions between two occupied bins all make the same partition at the
 * same cost, the first of which bvh_sah_bins takes; this takes the last,
 * which partitions the same. */
static void bvh_sah_few(bvh_best *best, const bvh_item *items, int n, const bvh_axes *ax,
                        double area)
{
    for (int a = 0; a < 3; a++) {
        if (!ax->used[a])
            continue;
        int bin[BVH_FEW], at[BVH_FEW]; /* at: the items by bin, stably */
        for (int i = 0; i < n; i++)
            bin[i] = bvh_bin(&items[i], a, ax->lo[a], ax->scale[a]);
        bvh_by_bin(bin, n, at);
        double right_cost[BVH_FEW];
        dbox acc = box_empty();
        for (int j = n - 1; j > 0; j--) {
            grow_box(&acc, &items[at[j]].box);
            right_cost[j] = box_half_area(&acc) * (n - j);
        }
        acc = box_empty();
        for (int j = 1; j < n; j++) {
            grow_box(&acc, &items[at[j - 1]].box);
            if (bin[at[j]] != bin[at[j - 1]])
                bvh_consider(best, area, &acc, j, right_cost[j], a, bin[at[j]]);
        }
    }
}

static int bvh_item_cmp(const void *a, const void *b)
{
    const bvh_item *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return x->root - y->root; /* a total order: the tree is the same everywhere */
}

/* Halves items[0..n) along the widest spread of centres (in index order
 * if none). */
static void bvh_halve(bvh_item *items, int n, const dbox *centres, bvh_cut *cut)
{
    cut->axis = 0;
    for (int a = 1; a < 3; a++)
        if (centres->hi[a] - centres->lo[a] > centres->hi[cut->axis] - centres->lo[cut->axis])
            cut->axis = a;
    for (int i = 0; i < n; i++)
        items[i].key = centre(&items[i], cut->axis);
    qsort(items, (size_t)n, sizeof *items, bvh_item_cmp);
    cut->left = n / 2;
    cut->lbox = items_box(items, cut->left);
    cut->rbox = items_box(items + cut->left, n - cut->left);
}

/* Splits items[0..n), in a node of box `box`, in two parts (the cut);
 * false when they make a leaf.  tmp: room for n items. */
static bool bvh_split(bvh_item *items, int n, int depth, const dbox *box, bvh_item *tmp,
                      bvh_cut *cut)
{
    if (n <= 1)
        return false;
    dbox centres = box_empty();
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            double c = centre(&items[i], a);
            centres.lo[a] = box_min(centres.lo[a], c);
            centres.hi[a] = box_max(centres.hi[a], c);
        }
    if (depth < BVH_MEDIAN_DEPTH) {
        bvh_axes ax;
        bvh_axes_of(&ax, &centres);
        bvh_best best = {n <= BVH_MAX_LEAF ? (double)n : HUGE_VAL, 0, 0, false};
        double area = box_half_area(box);
        bvh_bins bins;
        bool few = n <= BVH_FEW;
        if (few) {
            bvh_sah_few(&best, items, n, &ax, area);
        } else {
            bvh_fill_bins(&bins, &ax, items, n);
            bvh_sah_bins(&best, &bins, &ax, n, area);
        }
        if (best.found) {
            int a = best.axis, l = 0, r = 0;
            for (int i = 0; i < n; i++) { /* a stable partition by bin */
                if (bvh_bin(&items[i], a, ax.lo[a], ax.scale[a]) < best.bin)
                    items[l++] = items[i];
                else
                    tmp[r++] = items[i];
            }
            memcpy(items + l, tmp, (size_t)r * sizeof *items);
            *cut = (bvh_cut){l, a, box_empty(), box_empty()};
            if (few) {
                cut->lbox = items_box(items, l);
                cut->rbox = items_box(items + l, n - l);
            } else {
                for (int b = 0; b < BVH_BINS; b++) {
                    dbox *side = b < best.bin ? &cut->lbox : &cut->rbox;
                    *side = box_union(*side, bins.bounds[a][b]);
                }
            }
            return true;
        }
        if (n <= BVH_MAX_LEAF)
            return false;
    }
    bvh_halve(items, n, &centres, cut);
    return true;
}

/* Two more nodes for t: the first's number, -1 when out of memory. */
static int bvh_take(bvh_tree *t)
{
    if (t->count > t->cap - 2) {
        int cap = t->cap ? t->cap : 64;
        while (cap < t->count + 2)
            cap *= 2;
        bvh_build_node *nodes = realloc(t->nodes, (size_t)cap * sizeof *nodes);
        if (!nodes)
            return -1;
        t->nodes = nodes;
        t->cap = cap;
    }
    t->count += 2;
    return t->count - 2;
}

static bool bvh_children(bvh_tree *t, int c, bvh_item *items, int n, int depth, bvh_item *tmp,
                         const bvh_cut *cut);

/* Fills node k of t with the subtree over items[0..n), whose box is
 * `box`; false when out of memory. */
static bool bvh_subtree(bvh_tree *t, int k, bvh_item *items, int n, int depth, dbox box,
                        bvh_item *tmp)
{
    bvh_cut cut;
    if (!bvh_split(items, n, depth, &box, tmp, &cut)) {
        t->nodes[k] = (bvh_build_node){box, t->placed, n};
        for (int i = 0; i < n; i++)
            t->order[t->placed++] = items[i].root;
        return true;
    }
    int c = bvh_take(t);
    if (c < 0)
        return false;
    t->nodes[k] = (bvh_build_node){box, c, -1 - cut.axis};
    return bvh_children(t, c, items, n, depth + 1, tmp, &cut);
}

/* One half of a split built apart: a tree of its own. */
typedef struct {
    bvh_tree tree;
    bvh_item *items, *tmp;
    int n, depth;
    dbox box;
    bool ok;
} bvh_half;

static void *bvh_half_run(void *arg)
{
    bvh_half *h = arg;
    h->tree.count = 1; /* node 0, the half's root */
    h->tree.cap = 64;
    h->tree.nodes = malloc((size_t)h->tree.cap * sizeof *h->tree.nodes);
    h->ok = h->tree.nodes && bvh_subtree(&h->tree, 0, h->items, h->n, h->depth, h->box, h->tmp);
    return NULL;
}

/* Appends the halves' descendants to t where the one-thread build numbers
 * them, their roots at c and c + 1 (t->count is c + 2). */
static bool bvh_splice(bvh_tree *t, int c, const bvh_tree *left, const bvh_tree *right)
{
    const bvh_tree *half[2] = {left, right};
    int below[2] = {left->count - 1, right->count - 1};
    int need = t->count + below[0] + below[1];
    if (need > t->cap) {
        bvh_build_node *nodes = realloc(t->nodes, (size_t)need * sizeof *nodes);
        if (!nodes)
            return false;
        t->nodes = nodes;
        t->cap = need;
    }
    for (int h = 0; h < 2; h++) {
        /* local node j >= 1 of half h is node shift + j of t */
        int shift = c + 1 + (h ? below[0] : 0);
        for (int j = 0; j < half[h]->count; j++) {
            bvh_build_node node = half[h]->nodes[j];
            if (node.count < 0)
                node.first += shift;
            t->nodes[j ? shift + j : c + h] = node;
        }
    }
    t->count = need;
    return true;
}

/* bvh_children with each half built by a thread of its own (the second
 * by this one). */
static bool bvh_children_apart(bvh_tree *t, int c, bvh_item *items, int n, int depth,
                               bvh_item *tmp, const bvh_cut *cut)
{
    int l = cut->left;
    bvh_half half[2] = {
        {{NULL, 0, 0, t->order, t->placed, t->thread_levels - 1}, items, tmp, l, depth,
         cut->lbox, false},
        {{NULL, 0, 0, t->order, t->placed + l, t->thread_levels - 1}, items + l, tmp + l, n - l,
         depth, cut->rbox, false},
    };
    pthread_t thread;
    bool apart = pthread_create(&thread, NULL, bvh_half_run, &half[0]) == 0;
    if (!apart)
        bvh_half_run(&half[0]);
    bvh_half_run(&half[1]);
    if (apart)
        pthread_join(thread, NULL);
    bool ok = half[0].ok && half[1].ok;
    if (ok) {
        ok = bvh_splice(t, c, &half[0].tree, &half[1].tree);
        t->placed += n;
    }
    free(half[0].tree.nodes);
    free(half[1].tree.nodes);
    return ok;
}

/* Builds the halves of `cut` of items[0..n) into nodes c and c + 1 of t. */
static bool bvh_children(bvh_tree *t, int c, bvh_item *items, int n, int depth, bvh_item *tmp,
                         const bvh_cut *cut)
{
    if (t->thread_levels > 0 && n >= BVH_THREAD_MIN)
        return bvh_children_apart(t, c, items, n, depth, tmp, cut);
    int l = cut->left;
    return bvh_subtree(t, c, items, l, depth, cut->lbox, tmp) &&
           bvh_subtree(t, c + 1, items + l, n - l, depth, cut->rbox, tmp);
}

/* Levels of splits whose halves are built apart: log2 of the threads
 * (0: of the CPUs). */
static int bvh_thread_levels(int threads)
{
    long most = threads > 0 ? threads : sysconf(_SC_NPROCESSORS_ONLN);
    int levels = 0;
    while (levels < BVH_THREAD_LEVELS && most >= 2L << levels)
        levels++;
    return levels;
}

static bool bvh_top(bvh_tree *t, bvh_item *items, int n, bvh_item *tmp)
{
    dbox box = items_box(items, n);
    bvh_cut cut;
    if (bvh_split(items, n, 0, &box, tmp, &cut))
        return bvh_children(t, 0, items, n, 1, tmp, &cut);
    t->nodes[0] = (bvh_build_node){box, t->placed, n};
    for (int i = 0; i < n; i++)
        t->order[t->placed++] = items[i].root;
    t->nodes[1] = (bvh_build_node){box_empty(), t->placed, 0};
    return true;
}

bool bvh_build(const dbox *boxes, const int *bounded, int n, int *order, int at, int threads,
               bvh_build_node **nodes, int *count)
{
    bvh_tree t = {NULL, 0, 0, order, at, bvh_thread_levels(threads)};
    bvh_item *items = malloc((size_t)n * sizeof *items);
    bvh_item *tmp = malloc((size_t)n * sizeof *tmp);
    bool ok = items && tmp && bvh_take(&t) == 0;
    if (ok) {
        for (int i = 0; i < n; i++)
            items[i] = (bvh_item){boxes[bounded[i]], 0, bounded[i]};
        ok = bvh_top(&t, items, n, tmp);
    }
    free(items);
    free(tmp);
    if (!ok) {
        free(t.nodes);
        t.nodes = NULL;
        t.count = 0;
    }
    *nodes = t.nodes;
    *count = t.count;
    return ok;
}
