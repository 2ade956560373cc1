/*
 * test_bvh_build.c — csg/bvh_build.c, the BVH over the bounded roots: the
 * tree is the one its definition gives (a plain binned SAH, written out
 * below as the reference: every node's BVH_BINS bins on each axis, its box
 * a union over its items, one thread), node for node and bit for bit,
 * whatever the number of threads; and it is a BVH (every root once, in
 * leaves that tile the order, boxes that hold their contents).
 *
 * The inputs reach every path: the few-item search and the bins, the
 * halves built by threads (sets of tens of thousands), centres that
 * coincide (halved in index order), flat boxes, grids whose centres fall
 * on bin edges, a geometric run that the SAH peels one box at a time,
 * deeper than the median depth, and centres a few subnormals apart.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/bvh_build.h"
#include "fuzz_rng.h"

/* ---- the reference: the definition, plainly ------------------------------- */

#define REF_BINS 32
#define REF_MAX_LEAF 4
#define REF_MEDIAN_DEPTH 32

typedef struct {
    const dbox *boxes;
    int *order;
    int placed;
    bvh_build_node *nodes;
    int count;
} ref_tree;

static double ref_centre(const dbox *b, int a)
{
    return 0.5 * (b->lo[a] + b->hi[a]);
}

static double ref_area(const dbox *b)
{
    double d[3];
    for (int a = 0; a < 3; a++)
        d[a] = b->hi[a] - b->lo[a];
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

static int ref_bin(double c, double lo, double scale)
{
    double b = (c - lo) * scale; /* (clamped before the conversion: NaN to 0) */
    return !(b >= 0) ? 0 : b >= REF_BINS ? REF_BINS - 1 : (int)b;
}

static const dbox *ref_sort_boxes;
static int ref_sort_axis;

static int ref_cmp(const void *x, const void *y)
{
    int i = *(const int *)x, j = *(const int *)y;
    double a = ref_centre(&ref_sort_boxes[i], ref_sort_axis);
    double b = ref_centre(&ref_sort_boxes[j], ref_sort_axis);
    return a != b ? (a < b ? -1 : 1) : i - j;
}

/* Splits roots[0..n) (indices into the boxes) or says they make a leaf. */
static bool ref_split(const ref_tree *t, int *roots, int n, int depth, const dbox *box,
                      int *left, int *axis)
{
    if (n <= 1)
        return false;
    dbox c = box_empty();
    for (int i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            c.lo[a] = box_min(c.lo[a], ref_centre(&t->boxes[roots[i]], a));
            c.hi[a] = box_max(c.hi[a], ref_centre(&t->boxes[roots[i]], a));
        }
    if (depth < REF_MEDIAN_DEPTH) {
        double best = n <= REF_MAX_LEAF ? n : HUGE_VAL, scale_of[3];
        int best_bin = -1;
        for (int a = 0; a < 3; a++) {
            double extent = c.hi[a] - c.lo[a];
            if (!(extent > 0))
                continue;
            double scale = REF_BINS / extent;
            scale_of[a] = scale;
            int count[REF_BINS] = {0};
            dbox bounds[REF_BINS];
            for (int b = 0; b < REF_BINS; b++)
                bounds[b] = box_empty();
            for (int i = 0; i < n; i++) {
                int b = ref_bin(ref_centre(&t->boxes[roots[i]], a), c.lo[a], scale);
                count[b]++;
                bounds[b] = box_union(bounds[b], t->boxes[roots[i]]);
            }
            double right_cost[REF_BINS]; /* right to left: each split's right part */
            dbox acc = box_empty();
            int acc_n = 0;
            for (int b = REF_BINS - 1; b > 0; b--) {
                acc = box_union(acc, bounds[b]);
                acc_n += count[b];
                right_cost[b] = acc_n ? ref_area(&acc) * acc_n : 0;
            }
            acc = box_empty();
            acc_n = 0;
            for (int b = 1; b < REF_BINS; b++) {
                acc = box_union(acc, bounds[b - 1]);
                acc_n += count[b - 1];
                if (acc_n == 0 || acc_n == n)
                    continue;
                double cost = 1.0 + (ref_area(&acc) * acc_n + right_cost[b]) / ref_area(box);
                if (cost < best) {
                    best = cost;
                    *axis = a;
                    best_bin = b;
                }
            }
        }
        if (best_bin >= 0) {
            int *tmp = malloc((size_t)n * sizeof *tmp), l = 0, r = 0;
            assert_non_null(tmp);
            for (int i = 0; i < n; i++) {
                double ce = ref_centre(&t->boxes[roots[i]], *axis);
                if (ref_bin(ce, c.lo[*axis], scale_of[*axis]) < best_bin)
                    roots[l++] = roots[i];
                else
                    tmp[r++] = roots[i];
            }
            memcpy(roots + l, tmp, (size_t)r * sizeof *tmp);
            free(tmp);
            *left = l;
            return true;
        }
        if (n <= REF_MAX_LEAF)
            return false;
    }
    *axis = 0;
    for (int a = 1; a < 3; a++)
        if (c.hi[a] - c.lo[a] > c.hi[*axis] - c.lo[*axis])
            *axis = a;
    ref_sort_boxes = t->boxes;
    ref_sort_axis = *axis;
    qsort(roots, (size_t)n, sizeof *roots, ref_cmp);
    *left = n / 2;
    return true;
}

static void ref_node(ref_tree *t, int k, int *roots, int n, int depth)
{
    dbox box = box_empty();
    for (int i = 0; i < n; i++)
        box = box_union(box, t->boxes[roots[i]]);
    int left, axis;
    if (!ref_split(t, roots, n, depth, &box, &left, &axis)) {
        t->nodes[k] = (bvh_build_node){box, t->placed, n};
        for (int i = 0; i < n; i++)
            t->order[t->placed++] = roots[i];
        return;
    }
    int c = t->count;
    t->count += 2;
    t->nodes[k] = (bvh_build_node){box, c, -1 - axis};
    ref_node(t, c, roots, left, depth + 1);
    ref_node(t, c + 1, roots + left, n - left, depth + 1);
}

static void ref_build(const dbox *boxes, const int *bounded, int n, int *order, int at,
                      bvh_build_node *nodes, int *count)
{
    int *roots = malloc((size_t)n * sizeof *roots);
    assert_non_null(roots);
    memcpy(roots, bounded, (size_t)n * sizeof *roots);
    ref_tree t = {boxes, order, at, nodes, 2};
    dbox box = box_empty();
    for (int i = 0; i < n; i++)
        box = box_union(box, boxes[roots[i]]);
    int left, axis;
    if (ref_split(&t, roots, n, 0, &box, &left, &axis)) {
        ref_node(&t, 0, roots, left, 1);
        ref_node(&t, 1, roots + left, n - left, 1);
    } else {
        ref_node(&t, 0, roots, n, 1);
        nodes[1] = (bvh_build_node){box_empty(), t.placed, 0};
    }
    *count = t.count;
    free(roots);
}

/* ---- checks ---------------------------------------------------------------- */

static bool box_holds(const dbox *outer, const dbox *inner)
{
    for (int a = 0; a < 3; a++)
        if (inner->lo[a] < outer->lo[a] || inner->hi[a] > outer->hi[a])
            return false;
    return true;
}

/* A BVH over roots bounded[0..n) placed from `at`. */
static void check_is_bvh(const dbox *boxes, const int *bounded, int n, const int *order, int at,
                         const bvh_build_node *nodes, int count, int universe)
{
    char *seen = calloc((size_t)universe, 1), *covered = calloc((size_t)n + 1, 1);
    assert_non_null(seen);
    assert_non_null(covered);
    for (int i = 0; i < n; i++)
        seen[bounded[i]] = 1;
    for (int i = 0; i < n; i++) { /* order: a permutation of the roots */
        assert_true(order[at + i] >= 0 && order[at + i] < universe);
        assert_int_equal(seen[order[at + i]], 1);
        seen[order[at + i]] = 2;
    }
    assert_true(count >= 2 && count % 2 == 0);
    for (int k = 0; k < count; k++) {
        const bvh_build_node *node = &nodes[k];
        if (node->count >= 0) {
            assert_true(node->first >= at && node->first + node->count <= at + n);
            for (int i = 0; i < node->count; i++) {
                assert_false(covered[node->first - at + i]);
                covered[node->first - at + i] = 1;
                assert_true(box_holds(&node->box, &boxes[order[node->first + i]]));
            }
        } else {
            assert_true(node->count >= -3);
            assert_true(node->first > k && node->first + 1 < count);
            assert_true(box_holds(&node->box, &nodes[node->first].box));
            assert_true(box_holds(&node->box, &nodes[node->first + 1].box));
        }
    }
    for (int i = 0; i < n; i++)
        assert_true(covered[i]);
    free(seen);
    free(covered);
}

/* bvh_build over boxes[bounded[i]] equals the reference with 1, 2 and 8
 * threads, and is a BVH. */
static void check_boxes(const dbox *boxes, int universe, const int *bounded, int n)
{
    int at = 3; /* (unbounded roots would come first) */
    int *want_order = calloc((size_t)(n + at), sizeof *want_order);
    bvh_build_node *want = calloc((size_t)(2 * n + 2), sizeof *want);
    assert_non_null(want_order);
    assert_non_null(want);
    int want_count = 0;
    ref_build(boxes, bounded, n, want_order, at, want, &want_count);
    const int threads[] = {1, 2, 8};
    for (size_t t = 0; t < sizeof threads / sizeof *threads; t++) {
        int *order = calloc((size_t)(n + at), sizeof *order);
        assert_non_null(order);
        bvh_build_node *nodes = NULL;
        int count = 0;
        assert_true(bvh_build(boxes, bounded, n, order, at, threads[t], &nodes, &count));
        assert_int_equal(count, want_count);
        assert_memory_equal(order + at, want_order + at, (size_t)n * sizeof *order);
        for (int k = 0; k < count; k++) {
            if (nodes[k].first != want[k].first || nodes[k].count != want[k].count ||
                memcmp(&nodes[k].box, &want[k].box, sizeof(dbox)) != 0)
                fail_msg("%d roots, %d threads: node %d differs from the reference "
                         "(first %d/%d, count %d/%d)",
                         n, threads[t], k, nodes[k].first, want[k].first, nodes[k].count,
                         want[k].count);
        }
        check_is_bvh(boxes, bounded, n, order, at, nodes, count, universe);
        free(nodes);
        free(order);
    }
    free(want_order);
    free(want);
}

/* Every root bounded, in order. */
static void check_all(const dbox *boxes, int n)
{
    int *bounded = malloc((size_t)n * sizeof *bounded);
    assert_non_null(bounded);
    for (int i = 0; i < n; i++)
        bounded[i] = i;
    check_boxes(boxes, n, bounded, n);
    free(bounded);
}

static double uniform(uint64_t *rng)
{
    return (double)(rng_next(rng) >> 11) / 9007199254740992.0;
}

static dbox cube(double x, double y, double z, double half)
{
    return (dbox){{x - half, y - half, z - half}, {x + half, y + half, z + half}};
}

/* ---- the cases -------------------------------------------------------------- */

/* Random boxes of every size of set: the few-item search, the bins, and
 * (20 000 and 70 000) the halves built apart. */
static void test_random_sets(void **state)
{
    (void)state;
    const int sizes[] = {1, 2, 3, 4, 5, 7, 16, 31, 32, 33, 64, 100, 1000, 20000, 70000};
    uint64_t rng = 0xb0c5b01d2026ull;
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
        int n = sizes[s];
        dbox *boxes = malloc((size_t)n * sizeof *boxes);
        assert_non_null(boxes);
        for (int i = 0; i < n; i++) {
            double size = uniform(&rng) < 0.05 ? 0.5 : 0.01 * uniform(&rng);
            boxes[i] = cube(uniform(&rng) * 10 - 5, uniform(&rng) * 2, uniform(&rng) - 3, size);
        }
        check_all(boxes, n);
        free(boxes);
    }
}

/* Only some roots bounded (the others unbounded, placed first): the tree
 * over the bounded ones, by their numbers. */
static void test_some_roots_bounded(void **state)
{
    (void)state;
    int universe = 3000, n = 0;
    dbox *boxes = malloc((size_t)universe * sizeof *boxes);
    int *bounded = malloc((size_t)universe * sizeof *bounded);
    assert_non_null(boxes);
    assert_non_null(bounded);
    uint64_t rng = 42;
    for (int i = 0; i < universe; i++) {
        boxes[i] = cube(uniform(&rng), uniform(&rng), uniform(&rng), 0.001);
        if (i % 3 != 1)
            bounded[n++] = i;
    }
    check_boxes(boxes, universe, bounded, n);
    free(boxes);
    free(bounded);
}

/* A regular grid (centres on bin edges, many ties), flat boxes (a
 * triangle mesh in a plane), and 40 000 of them: the halves apart. */
static void test_grids_and_flat_boxes(void **state)
{
    (void)state;
    int side = 200, n = side * side;
    dbox *boxes = malloc((size_t)n * sizeof *boxes);
    assert_non_null(boxes);
    for (int i = 0; i < n; i++) {
        double x = i % side, y = i / side;
        boxes[i] = (dbox){{x, y, 0}, {x + 1, y + (i & 1 ? 1 : 0.5), 0}};
    }
    check_all(boxes, n);
    for (int i = 0; i < 4096; i++) /* a cubic grid */
        boxes[i] = cube(i % 16, (i / 16) % 16, i / 256, 0.25);
    check_all(boxes, 4096);
    free(boxes);
}

/* Centres that all coincide (no binned split: halved in index order),
 * alone and among others. */
static void test_coinciding_centres(void **state)
{
    (void)state;
    dbox boxes[300];
    for (int i = 0; i < 300; i++)
        boxes[i] = cube(1, 2, 3, 0.5 + 0.001 * i);
    check_all(boxes, 300);
    check_all(boxes, 5);
    for (int i = 0; i < 100; i++)
        boxes[i] = cube(i, 0, 0, 0.1);
    check_all(boxes, 300);
}

/* A geometric run, each box half the previous one's distance away: the
 * SAH peels one at a time, deeper than the median depth, where the
 * halving takes over. */
static void test_deep_run(void **state)
{
    (void)state;
    dbox boxes[200];
    for (int i = 0; i < 200; i++) {
        double x = ldexp(1.0, -(i % 100));
        boxes[i] = cube(x, i < 100 ? 0 : 1, 0, x * 1e-3);
    }
    check_all(boxes, 200);
    check_all(boxes, 100);
}

/* Centres a few subnormals apart: the bins' scale is infinite (32 over
 * the spread), so a centre's bin is an infinity or a NaN before it is
 * clamped; UBSan (make test's second build) stops on a conversion of
 * either to int. */
static void test_subnormal_spread(void **state)
{
    (void)state;
    dbox boxes[40];
    for (int i = 0; i < 40; i++) {
        double x = (i % 4) * 4.9e-324; /* 0 and the smallest subnormals */
        boxes[i] = (dbox){{x, i, 0}, {x, i + 0.5, 1}};
    }
    check_all(boxes, 40);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_sets),
        cmocka_unit_test(test_some_roots_bounded),
        cmocka_unit_test(test_grids_and_flat_boxes),
        cmocka_unit_test(test_coinciding_centres),
        cmocka_unit_test(test_deep_run),
        cmocka_unit_test(test_subnormal_spread),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
