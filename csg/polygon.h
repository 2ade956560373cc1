/*
 * polygon.h — a planar polygon split into triangles (host side, double).
 */
#ifndef CSG_POLYGON_H
#define CSG_POLYGON_H

#include "scene.h"

/* Splits the planar, simple polygon v[0..n) (convex or concave, either
 * winding) into triangles, written as index triples into tri[] (room for
 * 3 * (n - 2)), each with the polygon's own winding; triangles of zero
 * area are left out.  Returns their count, or -1 when n < 3, the polygon
 * has no area, or memory runs out. */
int csg_polygon_triangulate(const dvec3 *v, int n, int *tri);

/* The Newell normal of v[0..n) (not normalised; zero when it has no area). */
dvec3 csg_polygon_normal(const dvec3 *v, int n);

#endif
