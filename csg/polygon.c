/*
 * polygon.c — splitting a planar polygon into triangles.
 *
 * Algorithm.  The polygon is projected on the coordinate plane its Newell
 * normal is most perpendicular to, oriented so it runs counter-clockwise
 * there.  A convex polygon (no reflex corner) is cut into a fan from
 * vertex 0.  Otherwise ears are clipped (Meisters' two-ears theorem): a
 * convex corner (prev, cur, next) whose triangle holds no other remaining
 * vertex is cut off, until three vertices remain.  A fan from vertex 0 is
 * wrong for a concave polygon (a gear face of the SPD: 144 vertices): its
 * triangles would cover the notches between the teeth.  Ear clipping is
 * O(n^2) for the polygons met in practice (each search restarts at the
 * last ear).  A polygon that is not simple may leave no ear: the corner
 * at the search position is cut anyway, so the loop always ends.
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

/* The corner at position k of the remaining ring idx[0..m) is an ear. */
static bool is_ear(const pt2 *q, const int *idx, int m, int k)
{
    int a = idx[(k + m - 1) % m], b = idx[k], c = idx[(k + 1) % m];
    if (!(cross2(q[a], q[b], q[c]) > 0))
        return false;
    for (int j = 0; j < m; j++) {
        int x = idx[j];
        if (x == a || x == b || x == c)
            continue;
        if ((q[x].x == q[a].x && q[x].y == q[a].y) || (q[x].x == q[b].x && q[x].y == q[b].y) ||
            (q[x].x == q[c].x && q[x].y == q[c].y))
            continue; /* a repeated vertex */
        if (in_triangle(q[x], q[a], q[b], q[c]))
            return false;
    }
    return true;
}

static int clip_ears(const pt2 *q, int n, int *idx, int *tri)
{
    int count = 0, m = n, k = 0;
    for (int i = 0; i < n; i++)
        idx[i] = i;
    while (m > 3) {
        int tries = 0;
        while (tries < m && !is_ear(q, idx, m, k)) {
            k = (k + 1) % m;
            tries++;
        }
        /* no ear (not simple): cut the corner at k anyway */
        emit(tri, &count, idx[(k + m - 1) % m], idx[k], idx[(k + 1) % m], q);
        for (int j = k; j < m - 1; j++)
            idx[j] = idx[j + 1];
        m--;
        k = k > 0 ? k - 1 : m - 1;
    }
    emit(tri, &count, idx[0], idx[1], idx[2], q);
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
    int *idx = malloc((size_t)n * sizeof *idx);
    if (!q || !idx) {
        free(q);
        free(idx);
        return -1;
    }
    bool convex = true;
    for (int i = 0; i < n; i++) { /* (u, w) counter-clockwise seen along the normal */
        const dvec3 *p = &v[i];
        q[i] = drop == 0 ? (pt2){p->y, sign * p->z}
               : drop == 1 ? (pt2){p->z, sign * p->x}
                           : (pt2){p->x, sign * p->y};
    }
    for (int i = 0; i < n && convex; i++)
        convex = cross2(q[i], q[(i + 1) % n], q[(i + 2) % n]) >= 0;
    int count = 0;
    if (convex) {
        for (int i = 1; i + 1 < n; i++)
            emit(tri, &count, 0, i, i + 1, q);
    } else {
        count = clip_ears(q, n, idx, tri);
    }
    free(q);
    free(idx);
    return count;
}
