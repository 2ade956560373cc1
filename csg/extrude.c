/*
 * extrude.c — an extruded outline split into trapezoids (extrude.h), and
 * the flattening of Bezier curves.
 *
 * Algorithm: the vertical trapezoidal decomposition.  The distinct vertex
 * heights cut the plane into slabs; no edge starts or ends inside a slab,
 * so the edges that cross a slab do not change order within it (outlines
 * whose edges cross each other excepted: a slab then is cut by the order
 * at its middle, which is what even-odd means there up to the crossing).
 * Sorted by their x at the slab's middle, edges 0-1, 2-3, ... bound the
 * inside (even-odd).  A piece whose two edges are the same as those of a
 * piece of the slab below grows upwards instead of starting anew, so an
 * outline of V vertices gives O(V) pieces, not O(V^2).
 *
 * Exactness: each side line is computed once per edge (its unit normal
 * and offset, in double) and stored the same way in every piece on that
 * edge; adjacent slabs share their cut height.  So wherever a ray leaves
 * one piece into another it meets the very same plane from both sides.
 *
 * Cost: O(slabs * edges) time, which is fine for glyphs and prisms
 * (hundreds of edges); the caller bounds the outline's size.
 */
#include "extrude.h"

#include <math.h>
#include <stdlib.h>

/* An edge of the outline that is not horizontal, lower end first. */
typedef struct {
    double x0, y0, x1, y1;
    double n[3]; /* its line: n . (x, y) = c, n pointing to +x (inside of a left side) */
    int from;    /* the outline's point it starts from (csg_trapezoid.edge) */
} edge;

typedef struct {
    double x;
    int e;
} edge_at;

static int by_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int by_x(const void *a, const void *b)
{
    const edge_at *p = a, *q = b;
    if (p->x != q->x)
        return (p->x > q->x) - (p->x < q->x);
    return (p->e > q->e) - (p->e < q->e);
}

static edge make_edge(dvec3 a, dvec3 b, int from)
{
    if (a.y > b.y) {
        dvec3 t = a;
        a = b;
        b = t;
    }
    edge e = {a.x, a.y, b.x, b.y, {0, 0, 0}, from};
    double dx = b.x - a.x, dy = b.y - a.y, len = sqrt(dx * dx + dy * dy);
    e.n[0] = dy / len;
    e.n[1] = -dx / len;
    e.n[2] = e.n[0] * a.x + e.n[1] * a.y;
    return e;
}

/* The edges, their count, or -1 when out of memory. */
static int collect_edges(const dvec3 *pts, const int *ends, int contours, edge **out)
{
    int total = contours > 0 ? ends[contours - 1] : 0;
    edge *es = malloc((size_t)(total > 0 ? total : 1) * sizeof *es);
    if (!es)
        return -1;
    int n = 0, start = 0;
    for (int k = 0; k < contours; start = ends[k], k++) {
        int count = ends[k] - start;
        for (int i = 0; count >= 3 && i < count; i++) {
            dvec3 a = pts[start + i], b = pts[start + (i + 1) % count];
            if (a.y != b.y)
                es[n++] = make_edge(a, b, start + i);
        }
    }
    *out = es;
    return n;
}

/* The distinct heights of the edges' ends, sorted; their count. */
static int slab_heights(const edge *es, int n, double *ys)
{
    for (int i = 0; i < n; i++) {
        ys[2 * i] = es[i].y0;
        ys[2 * i + 1] = es[i].y1;
    }
    qsort(ys, (size_t)(2 * n), sizeof *ys, by_double);
    int m = 0;
    for (int i = 0; i < 2 * n; i++)
        if (m == 0 || ys[i] != ys[m - 1])
            ys[m++] = ys[i];
    return m;
}

static csg_trapezoid piece_of(const edge *left, const edge *right, double y_lo, double y_hi)
{
    csg_trapezoid t;
    for (int i = 0; i < 3; i++) {
        t.side[0][i] = left->n[i];
        t.side[1][i] = -right->n[i]; /* the right side's inside is towards -x */
    }
    t.y_lo = y_lo;
    t.y_hi = y_hi;
    t.edge[0] = left->from;
    t.edge[1] = right->from;
    return t;
}

/* A piece open in a slab: its index and its two edges. */
typedef struct {
    int piece, left, right;
} open_piece;

/* The x of edge e at height y. */
static double edge_x(const edge *e, double y)
{
    return e->x0 + (y - e->y0) * (e->x1 - e->x0) / (e->y1 - e->y0);
}

/* Appends a piece to *ts (capacity *cap); false when out of memory. */
static bool push_piece(csg_trapezoid **ts, int *count, int *cap, csg_trapezoid t)
{
    if (*count == *cap) {
        csg_trapezoid *g = realloc(*ts, (size_t)(*cap ? 2 * *cap : 16) * sizeof *g);
        if (!g)
            return false;
        *ts = g;
        *cap = *cap ? 2 * *cap : 16;
    }
    (*ts)[(*count)++] = t;
    return true;
}

int csg_extrude_split(const dvec3 *pts, const int *ends, int contours, csg_trapezoid **out)
{
    *out = NULL;
    edge *es = NULL;
    int n = collect_edges(pts, ends, contours, &es);
    if (n < 0)
        return -1;
    size_t slots = (size_t)n + 1;
    double *ys = malloc(2 * slots * sizeof *ys);
    edge_at *cross = malloc(slots * sizeof *cross);
    open_piece *below = malloc(slots * sizeof *below), *here = malloc(slots * sizeof *here);
    csg_trapezoid *ts = NULL;
    int count = 0, cap = 0, below_n = 0;
    bool ok = ys && cross && below && here;
    int m = ok ? slab_heights(es, n, ys) : 0;
    for (int j = 0; ok && j + 1 < m; j++) {
        double lo = ys[j], hi = ys[j + 1], mid = 0.5 * (lo + hi);
        int k = 0;
        for (int i = 0; i < n; i++)
            if (es[i].y0 <= lo && es[i].y1 >= hi)
                cross[k++] = (edge_at){edge_x(&es[i], mid), i};
        qsort(cross, (size_t)k, sizeof *cross, by_x);
        int here_n = 0;
        for (int i = 0; ok && i + 1 < k; i += 2) {
            open_piece o = {-1, cross[i].e, cross[i + 1].e};
            for (int q = 0; q < below_n && o.piece < 0; q++)
                if (below[q].left == o.left && below[q].right == o.right)
                    o.piece = below[q].piece;
            if (o.piece >= 0) {
                ts[o.piece].y_hi = hi;
            } else {
                o.piece = count;
                ok = push_piece(&ts, &count, &cap, piece_of(&es[o.left], &es[o.right], lo, hi));
            }
            here[here_n++] = o;
        }
        open_piece *swap = below;
        below = here;
        here = swap;
        below_n = here_n;
    }
    free(es);
    free(ys);
    free(cross);
    free(below);
    free(here);
    if (!ok) {
        free(ts);
        return -1;
    }
    *out = ts;
    return count;
}

int csg_curve_segments(double second_derivative_max, double tol)
{
    if (!(second_derivative_max > 0) || !(tol > 0))
        return 1;
    double n = ceil(sqrt(second_derivative_max / (8 * tol)));
    return n < 1 ? 1 : n > 1024 ? 1024 : (int)n;
}
