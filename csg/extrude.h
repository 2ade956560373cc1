/*
 * extrude.h — an outline extruded along z (POV-Ray's prism, each glyph of
 * its text) split into convex pieces the tracers know (flat.h's
 * trapezoid), and the flattening of the outline's curves into polylines.
 */
#ifndef CSG_EXTRUDE_H
#define CSG_EXTRUDE_H

#include "scene.h"

/* One convex piece: y_lo <= y <= y_hi between two sides, each the
 * half-plane n . (x, y) >= c, side[k] = {n.x, n.y, c}, n a unit vector
 * pointing in.  Pieces on the same edge of the outline have the same
 * side, bit for bit. */
typedef struct {
    double side[2][3];
    double y_lo, y_hi;
    int edge[2]; /* the outline's edge of each side: the index of the point
                    it starts from (to the next point of its polyline) */
} csg_trapezoid;

/* The pieces of the closed polylines pts[0 .. ends[0]), pts[ends[0] ..
 * ends[1]), ... (x, y of each point; z is not read), inside by the
 * even-odd rule (a point is inside when a ray from it crosses the outline
 * an odd number of times: POV-Ray's rule for prisms and glyphs).  The
 * outline is cut into horizontal slabs at every vertex height; in each
 * slab the edges crossing it, sorted by x, bound the inside in pairs; a
 * pair that continues from the slab below with the same two edges extends
 * that piece.  Returns the count (0: no area) and *out (malloc'd, the
 * caller frees it), or -1 when out of memory. */
int csg_extrude_split(const dvec3 *pts, const int *ends, int contours, csg_trapezoid **out);

/* The most edges an outline may have (the split takes time slabs x edges,
 * up to their square: 20000 edges take about a second). */
#define CSG_EXTRUDE_MAX_EDGES 20000

/* How closely the curves of an outline are followed (csg_curve_*): at
 * most this share of the outline's size (an em for a glyph) off the curve. */
#define CSG_CURVE_TOLERANCE 1e-4

/* The segments a curve needs to stay within `tol` of itself when its
 * second derivative is at most `second_derivative_max` (in length): the
 * chord of a piece of parameter length h is at most max|B''| h^2 / 8 off
 * the curve, so n = ceil(sqrt(max|B''| / (8 tol))), from 1 to 1024. */
int csg_curve_segments(double second_derivative_max, double tol);

#endif
