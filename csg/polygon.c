/*
 * polygon.c — splitting a planar polygon into triangles.
 *
 * Algorithm.  The polygon is projected on the coordinate plane its Newell
 * normal is most perpendicular to, oriented so it runs counter-clockwise
 * there.  A convex polygon (no reflex corner) is cut into a fan from
 * vertex 0.  Otherwise ears are clipped (Meisters' two-ears theorem): a
 * convex corner (prev, cur, next) whose triangle holds no other remaining
 * vertex is cut off, the one with the shortest diagonal first, until three
 * vertices remain.  A fan from vertex 0 is wrong for a concave polygon (a
 * gear face of the SPD: 144 vertices): its triangles would cover the
 * notches between the teeth.  The shortest-diagonal order keeps the
 * triangles compact, so that few of their boxes overlap any point of the
 * face (clip_ears).  The cost is O(n^2) for the polygons met in practice.
 * A polygon that is not simple may leave no ear: a corner is cut anyway,
 * so the loop always ends.
 *
 * Invariants: every triangle is written in the polygon's own order
 * (prev, cur, next), so it keeps the polygon's winding and front side,
 * and uses the polygon's own vertices (no new points): neighbouring
 * triangles share exact vertices, so the watertight triangle test leaves
 * no crack between them.
 */
#include "polygon.h"

#include <math.h>
#include <stdlib.h>

dvec3 csg_polygon_normal(const dvec3 *v, int n)
{
    dvec3 nn = {0, 0, 0};
    for (int i = 0; i < n; i++) {
        const dvec3 *a = &v[i], *b = &v[(i + 1) % n];
        nn.x += (a->y - b->y) * (a->z + b->z);
        nn.y += (a->z - b->z) * (a->x + b->x);
        nn.z += (a->x - b->x) * (a->y + b->y);
    }
    return nn;
}

typedef struct {
    double x, y;
} pt2;

static double cross2(pt2 a, pt2 b, pt2 c)
{
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/* p inside or on the triangle a, b, c (counter-clockwise). */
static bool in_triangle(pt2 p, pt2 a, pt2 b, pt2 c)
{
    return cross2(a, b, p) >= 0 && cross2(b, c, p) >= 0 && cross2(c, a, p) >= 0;
}

static void emit(int *tri, int *count, int a, int b, int c, const pt2 *q)
{
    if (cross2(q[a], q[b], q[c]) == 0)
        return; /* no area */
    tri[3 * *count] = a;
    tri[3 * *count + 1] = b;
    tri[3 * *count + 2] = c;
    (*count)++;
}

/* The remaining ring: a doubly linked list over the polygon's vertices. */
typedef struct {
    int *prev, *next;
    bool *ear;     /* the corner is an ear (false may be stale: see clip_ears) */
    double *diag;  /* its diagonal's squared length (prev to next) */
} ring;

/* The corner at vertex b of the remaining ring (m vertices) is an ear:
 * convex, and its triangle holds no other remaining vertex. */
static bool is_ear(const pt2 *q, const ring *g, int m, int b)
{
    int a = g->prev[b], c = g->next[b];
    if (!(cross2(q[a], q[b], q[c]) > 0))
        return false;
    for (int j = 0, x = g->next[c]; j < m - 3; j++, x = g->next[x]) {
        if ((q[x].x == q[a].x && q[x].y == q[a].y) || (q[x].x == q[b].x && q[x].y == q[b].y) ||
            (q[x].x == q[c].x && q[x].y == q[c].y))
            continue; /* a repeated vertex */
        if (in_triangle(q[x], q[a], q[b], q[c]))
            return false;
    }
    return true;
}

static void classify(const pt2 *q, ring *g, int m, int b)
{
    pt2 a = q[g->prev[b]], c = q[g->next[b]];
    g->ear[b] = is_ear(q, g, m, b);
    g->diag[b] = (c.x - a.x) * (c.x - a.x) + (c.y - a.y) * (c.y - a.y);
}

/* The flagged ear with the shortest diagonal (the lower vertex on a tie),
 * -1 when none is flagged; the walk starts at `start`. */
static int best_ear(const ring *g, int m, int start)
{
    int best = -1;
    for (int j = 0, x = start; j < m; j++, x = g->next[x]) {
        if (g->ear[x] && (best < 0 || g->diag[x] < g->diag[best] ||
                          (g->diag[x] == g->diag[best] && x < best)))
            best = x;
    }
    return best;
}

/* Cuts the ear with the shortest diagonal first.  A short diagonal makes a
 * compact triangle: a gear's teeth go first, then its rim in rounds that
 * halve it, and the triangles' boxes cover the polygon about twice over
 * instead of 29 times (the old cut-the-next-ear order left long slivers
 * across the whole face; every one of them a ray near the face had to
 * test).  Cutting b changes the corners at its neighbours only; a corner
 * elsewhere can only become an ear (one vertex fewer may lie in its
 * triangle), so its flag may be a stale false: the flags are rebuilt when
 * none is set.  No ear at all (not simple): the corner at `start` is cut
 * anyway, so the loop always ends. */
static int clip_ears(const pt2 *q, int n, ring *g, int *tri)
{
    int count = 0, m = n, start = 0;
    for (int i = 0; i < n; i++) {
        g->prev[i] = (i + n - 1) % n;
        g->next[i] = (i + 1) % n;
    }
    for (int i = 0; i < n; i++)
        classify(q, g, m, i);
    while (m > 3) {
        int b = best_ear(g, m, start);
        for (int j = 0, x = start; b < 0 && j < m; j++, x = g->next[x])
            classify(q, g, m, x);
        if (b < 0)
            b = best_ear(g, m, start);
        if (b < 0)
            b = start;
        int a = g->prev[b], c = g->next[b];
        emit(tri, &count, a, b, c, q);
        g->next[a] = c;
        g->prev[c] = a;
        m--;
        start = a;
        classify(q, g, m, a);
        classify(q, g, m, c);
    }
    emit(tri, &count, g->prev[start], start, g->next[start], q);
    return count;
}

int csg_polygon_triangulate(const dvec3 *v, int n, int *tri)
{
    if (n < 3)
        return -1;
    dvec3 nn = csg_polygon_normal(v, n);
    double ax = fabs(nn.x), ay = fabs(nn.y), az = fabs(nn.z);
    if (!(ax + ay + az > 0))
        return -1;
    int drop = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
    double sign = (drop == 0 ? nn.x : drop == 1 ? nn.y : nn.z) > 0 ? 1.0 : -1.0;
    pt2 *q = malloc((size_t)n * sizeof *q);
    ring g = {malloc((size_t)n * sizeof *g.prev), malloc((size_t)n * sizeof *g.next),
              malloc((size_t)n * sizeof *g.ear), malloc((size_t)n * sizeof *g.diag)};
    int count = -1;
    if (!q || !g.prev || !g.next || !g.ear || !g.diag)
        goto out;
    bool convex = true;
    for (int i = 0; i < n; i++) { /* (u, w) counter-clockwise seen along the normal */
        const dvec3 *p = &v[i];
        q[i] = drop == 0 ? (pt2){p->y, sign * p->z}
               : drop == 1 ? (pt2){p->z, sign * p->x}
                           : (pt2){p->x, sign * p->y};
    }
    for (int i = 0; i < n && convex; i++)
        convex = cross2(q[i], q[(i + 1) % n], q[(i + 2) % n]) >= 0;
    count = 0;
    if (convex) {
        for (int i = 1; i + 1 < n; i++)
            emit(tri, &count, 0, i, i + 1, q);
    } else {
        count = clip_ears(q, n, &g, tri);
    }
out:
    free(q);
    free(g.prev);
    free(g.next);
    free(g.ear);
    free(g.diag);
    return count;
}
