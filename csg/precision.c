/*
 * precision.c — the `--precision auto` criterion: does the scene need
 * double, or does float render it to within a fraction of a pixel?
 *
 * Model.  A hit point computed in float is off by about
 *     err = CSG_PREC_ULPS * 2^-24 * M
 * where M is the largest coordinate magnitude the computation handles: the
 * camera's distance from the origin, and the object's (its bounding
 * sphere's centre plus radius).  Float's rounding is relative, so a scene
 * uniformly scaled keeps err proportional to everything else; what breaks
 * float is a scene whose coordinates are large against what must be
 * resolved: a small object or a near camera far from the origin.
 *
 * For every primitive (leaves of every CSG tree, subtracted ones too;
 * each triangle of a mesh apart, as it is traced):
 *   - its world bounding sphere (centre c, radius R), its smallest feature
 *     size F (sphere radius, shortest box edge, min(cone radius, height),
 *     shortest edge of a triangle or polygon, scaled by the
 *     transform's smallest column norm); planes have no F;
 *   - its distance D from the camera: to the surface for a sphere or a
 *     plane, else to the bounding sphere (from inside: to the nearest
 *     face of the local box, times the smallest scale), a lower bound;
 *   - the pixel footprint there, D * alpha, with alpha the angle of one
 *     pixel (|right| / width or |up| / height over |direction|, smaller).
 * The scene needs double when for some primitive
 *     err > CSG_PREC_PIXEL_FRACTION * D * alpha    (1/8 of a pixel), or
 *     err > CSG_PREC_FEATURE_FRACTION * F          (1e-3 of the feature).
 * Also double whenever a coordinate magnitude exceeds 2^60 or a feature is
 * below 2^-60: intersection code squares them, and float's squares
 * overflow beyond about 1.8e19 (underflow into denormals below 1e-19).
 * The deciding primitive is the one with the largest ratio of err to the
 * smaller allowance; `why` names it with the numbers.
 *
 * Invariants: reads the scene only; recursion depth is the CSG depth,
 * bounded by the parser (CSG_PARSE_MAX_NESTING).
 */
#include "precision.h"

#include <float.h>
#include <math.h>
#include <stdio.h>

#include "camera_setup.h"

typedef struct {
    dvec3 cam;            /* camera location                       */
    double alpha;         /* angle of one pixel (radians, approx)  */
    double worst;         /* largest err / allowance seen          */
    const csg_object *at; /* the primitive that gave it            */
    csg_loc at_loc;       /* where it was written (a mesh: its triangle) */
    double err, allow_px, allow_feat, dist, mag;
} prec_walk;

static double len3(dvec3 v) { return sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }
static dvec3 sub3(dvec3 a, dvec3 b) { return (dvec3){a.x - b.x, a.y - b.y, a.z - b.z}; }

static dvec3 xf_point(const csg_xform *x, dvec3 p)
{
    return (dvec3){x->m[0][0] * p.x + x->m[0][1] * p.y + x->m[0][2] * p.z + x->m[0][3],
                   x->m[1][0] * p.x + x->m[1][1] * p.y + x->m[1][2] * p.z + x->m[1][3],
                   x->m[2][0] * p.x + x->m[2][1] * p.y + x->m[2][2] * p.z + x->m[2][3]};
}

/* Smallest and largest column norm of the linear part: how much the
 * transform shrinks or stretches (exact for rotations and axis scales). */
static void xf_scales(const csg_xform *x, double *smin, double *smax)
{
    *smin = HUGE_VAL;
    *smax = 0.0;
    for (int j = 0; j < 3; j++) {
        double n = sqrt(x->m[0][j] * x->m[0][j] + x->m[1][j] * x->m[1][j] +
                        x->m[2][j] * x->m[2][j]);
        *smin = fmin(*smin, n);
        *smax = fmax(*smax, n);
    }
}

/* Distance from local point p to the surface of the local box lo..hi
 * (outside: Euclidean; inside: to the nearest face). */
static double box_distance(dvec3 p, dvec3 lo, dvec3 hi)
{
    double q[3] = {p.x, p.y, p.z}, l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
    double out = 0.0, in = HUGE_VAL;
    bool inside = true;
    for (int i = 0; i < 3; i++) {
        double d = fmax(l[i] - q[i], q[i] - h[i]);
        if (d > 0.0) {
            out += d * d;
            inside = false;
        }
        in = fmin(in, fmin(q[i] - l[i], h[i] - q[i]));
    }
    return inside ? in : sqrt(out);
}

/* What the criterion needs of one shape, in its own (object) space: a box
 * around it and its smallest feature; a plane is unbounded and has no
 * feature.  One function a shape kind (CSG_OBJECT_KINDS). */
typedef struct {
    bool bounded;
    dvec3 lo, hi;
    double feature;
} prec_extent;

static prec_extent feature_sphere(const csg_object *o)
{
    prec_extent x = {true, {o->a.x - o->r0, o->a.y - o->r0, o->a.z - o->r0},
                     {o->a.x + o->r0, o->a.y + o->r0, o->a.z + o->r0}, o->r0};
    return x;
}

/* The shortest edge that is not zero: a box of zero thickness (a sheet)
 * has the feature of its rectangle (none for a segment or a point). */
static prec_extent feature_box(const csg_object *o)
{
    prec_extent x = {true, o->a, o->b, HUGE_VAL};
    double edge[3] = {o->b.x - o->a.x, o->b.y - o->a.y, o->b.z - o->a.z};
    for (int i = 0; i < 3; i++)
        if (edge[i] > 0)
            x.feature = fmin(x.feature, edge[i]);
    return x;
}

/* cylinder, cone: the box around the axis segment */
static prec_extent feature_axial(const csg_object *o, double r)
{
    prec_extent x = {true,
                     {fmin(o->a.x, o->b.x) - r, fmin(o->a.y, o->b.y) - r, fmin(o->a.z, o->b.z) - r},
                     {fmax(o->a.x, o->b.x) + r, fmax(o->a.y, o->b.y) + r, fmax(o->a.z, o->b.z) + r},
                     fmin(r, len3(sub3(o->b, o->a)))};
    return x;
}

static prec_extent feature_cylinder(const csg_object *o) { return feature_axial(o, o->r0); }
static prec_extent feature_cone(const csg_object *o) { return feature_axial(o, fmax(o->r0, o->r1)); }

/* A torus: its box; the feature is the minor radius. */
static prec_extent feature_torus(const csg_object *o)
{
    double s = o->r0 + o->r1;
    prec_extent x = {true, {-s, -o->r1, -s}, {s, o->r1, s}, o->r1};
    return x;
}

/* A quadric: unbounded, no feature (judged as a plane through its
 * object's origin, at the camera's first-order distance, leaf_plane). */
static prec_extent feature_quadric(const csg_object *o)
{
    (void)o;
    prec_extent x = {false, {0, 0, 0}, {0, 0, 0}, HUGE_VAL};
    return x;
}

/* A poly: the same as a quadric (poly_distance). */
static prec_extent feature_poly(const csg_object *o) { return feature_quadric(o); }

static prec_extent feature_plane(const csg_object *o)
{
    (void)o;
    prec_extent x = {false, {0, 0, 0}, {0, 0, 0}, HUGE_VAL};
    return x;
}

/* Triangles, polygons, a mesh's triangle: the box of the n vertices v;
 * the feature is the shortest edge (of the outline). */
static prec_extent feature_points(const dvec3 *v, int n)
{
    prec_extent x = {true, {HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL},
                     HUGE_VAL};
    for (int i = 0; i < n; i++) {
        x.lo = (dvec3){fmin(x.lo.x, v[i].x), fmin(x.lo.y, v[i].y), fmin(x.lo.z, v[i].z)};
        x.hi = (dvec3){fmax(x.hi.x, v[i].x), fmax(x.hi.y, v[i].y), fmax(x.hi.z, v[i].z)};
        x.feature = fmin(x.feature, len3(sub3(v[(i + 1) % n], v[i])));
    }
    return x;
}

static prec_extent feature_triangle(const csg_object *o) { return feature_points(o->verts, 3); }
static prec_extent feature_smooth_triangle(const csg_object *o)
{
    return feature_points(o->verts, 3);
}
static prec_extent feature_polygon(const csg_object *o)
{
    return feature_points(o->verts, o->vert_count);
}
/* (not called: a mesh is weighed a triangle at a time, leaf_mesh) */
/* A prism: its outline's box between its heights; the feature its
 * shortest edge (the flattened curves' included) or its height. */
static prec_extent feature_prism(const csg_object *o)
{
    prec_extent x = feature_points(o->verts, 0);
    int start = 0;
    for (int k = 0; k < o->contour_count; start = o->contour_ends[k], k++) {
        int n = o->contour_ends[k] - start;
        for (int i = 0; i < n; i++) {
            dvec3 v = o->verts[start + i], w = o->verts[start + (i + 1) % n];
            x.lo = (dvec3){fmin(x.lo.x, v.x), fmin(x.lo.y, v.y), o->r0};
            x.hi = (dvec3){fmax(x.hi.x, v.x), fmax(x.hi.y, v.y), o->r1};
            double len = len3(sub3(w, v));
            if (len > 0)
                x.feature = fmin(x.feature, len);
        }
    }
    x.feature = fmin(x.feature, o->r1 - o->r0);
    if (o->conic) { /* the outline at height 1, scaled by the height */
        x.lo = (dvec3){fmin(x.lo.x, x.lo.x * o->r1), fmin(x.lo.y, x.lo.y * o->r1), o->r0};
        x.hi = (dvec3){fmax(x.hi.x, x.hi.x * o->r1), fmax(x.hi.y, x.hi.y * o->r1), o->r1};
        x.feature *= o->r0 > 0 ? fmin(1, o->r0) : 1;
    }
    return x;
}

static prec_extent feature_mesh(const csg_object *o) { return feature_points(o->verts, 0); }

/* The distance of point l from quadric c's surface, to first order:
 * |f(l)| / |grad f(l)| (|f| where the gradient vanishes). */
static double quadric_distance(const double *c, dvec3 l)
{
    double f = l.x * (c[0] * l.x + c[3] * l.y + c[6]) + l.y * (c[1] * l.y + c[5] * l.z + c[7]) +
               l.z * (c[2] * l.z + c[4] * l.x + c[8]) + c[9];
    dvec3 g = {2 * c[0] * l.x + c[3] * l.y + c[4] * l.z + c[6],
               c[3] * l.x + 2 * c[1] * l.y + c[5] * l.z + c[7],
               c[4] * l.x + c[5] * l.y + 2 * c[2] * l.z + c[8]};
    double gl = len3(g);
    return gl > 0 ? fabs(f) / gl : fabs(f);
}

/* Whether every coefficient of o (when a poly) is finite in float. */
static bool poly_fits_float(const csg_object *o)
{
    if (o->kind != CSG_OBJ_POLY)
        return true;
    int n = o->poly_order, terms = (n + 1) * (n + 2) * (n + 3) / 6;
    for (int k = 0; k < terms; k++)
        if (!(fabs(o->poly_coef[k]) <= (double)FLT_MAX))
            return false;
    return true;
}

/* The same for a poly: |f(l)| / |grad f(l)|. */
static double poly_distance(const csg_object *o, dvec3 l)
{
    dvec3 g;
    double f = csg_poly_value(o->poly_order, o->poly_coef, l, &g);
    double gl = len3(g);
    return gl > 0 ? fabs(f) / gl : fabs(f);
}

/* A plane: its point nearest the local origin, the camera's distance (a
 * quadric, a poly: its object's origin, quadric_distance, poly_distance). */
static bool leaf_plane(const prec_walk *w, const csg_object *o, double smin, double *mag,
                       double *dist)
{
    dvec3 p0 = xf_point(&o->xform, (dvec3){o->a.x * o->r0, o->a.y * o->r0, o->a.z * o->r0});
    csg_xform inv;
    if (!csg_xform_invert(&o->xform, &inv))
        return false;
    dvec3 lc = xf_point(&inv, w->cam);
    double side = o->kind == CSG_OBJ_QUADRIC ? quadric_distance(o->coef, lc)
                  : o->kind == CSG_OBJ_POLY  ? poly_distance(o, lc)
                                             : o->a.x * lc.x + o->a.y * lc.y + o->a.z * lc.z - o->r0;
    *mag = fmax(*mag, len3(p0));
    *dist = fabs(side) * smin;
    return true;
}

/* A bounded shape: its world bounding sphere, the camera's distance. */
static bool leaf_bounded(const prec_walk *w, const csg_object *o, const prec_extent *x,
                         double smin, double smax, double *mag, double *dist)
{
    dvec3 centre = {0.5 * (x->lo.x + x->hi.x), 0.5 * (x->lo.y + x->hi.y),
                    0.5 * (x->lo.z + x->hi.z)};
    double radius = 0.5 * len3(sub3(x->hi, x->lo)) * smax;
    dvec3 wc = xf_point(&o->xform, centre);
    *mag = fmax(*mag, len3(wc) + radius);
    csg_xform inv;
    if (!csg_xform_invert(&o->xform, &inv))
        return false;
    dvec3 lc = xf_point(&inv, w->cam);
    if (o->kind == CSG_OBJ_SPHERE) /* exact: to the surface */
        *dist = fabs(len3(sub3(lc, o->a)) - o->r0) * smin;
    else if (len3(sub3(w->cam, wc)) > radius)
        *dist = len3(sub3(w->cam, wc)) - radius;
    else
        *dist = box_distance(lc, x->lo, x->hi) * smin;
    return true;
}

/* One primitive of extent x (written at loc): world bounding sphere,
 * feature size, distance. */
static void leaf_extent(prec_walk *w, const csg_object *o, const prec_extent *xp, csg_loc loc)
{
    prec_extent x = *xp;
    double smin, smax;
    xf_scales(&o->xform, &smin, &smax);
    const double eps = CSG_PREC_ULPS * ldexp(1.0, -24);
    double mag = len3(w->cam), dist;
    bool ok = x.bounded ? leaf_bounded(w, o, &x, smin, smax, &mag, &dist)
                        : leaf_plane(w, o, smin, &mag, &dist);
    if (!ok)
        return;
    double feat = x.bounded ? x.feature * smin : x.feature;
    double err = eps * mag;
    double allow_px = CSG_PREC_PIXEL_FRACTION * dist * w->alpha;
    double allow_feat = CSG_PREC_FEATURE_FRACTION * feat;
    double allow = fmin(allow_px, allow_feat);
    double ratio = allow > 0.0 ? err / allow : HUGE_VAL;
    /* squares of coordinates or features outside float's range, or a
     * poly's coefficient beyond it (the flattener refuses it in float) */
    if (mag > CSG_PREC_MAX_MAG || feat < CSG_PREC_MIN_FEATURE || !poly_fits_float(o))
        ratio = HUGE_VAL;
    if (w->at == NULL || ratio > w->worst) {
        w->worst = ratio;
        w->at = o;
        w->at_loc = loc;
        w->err = err;
        w->allow_px = allow_px;
        w->allow_feat = allow_feat;
        w->dist = dist;
        w->mag = mag;
    }
}

/* A mesh: each triangle apart, as each is traced (its box, not the
 * mesh's, is what a ray meets: a camera inside a terrain's box is not
 * inside any of its triangles). */
static void leaf_mesh(prec_walk *w, const csg_object *o)
{
    for (int k = 0; k + 2 < o->vert_count; k += 3) {
        prec_extent x = feature_points(o->verts + k, 3);
        leaf_extent(w, o, &x, csg_piece_loc(o, k / 3));
    }
}

static void leaf(prec_walk *w, const csg_object *o)
{
    if (o->kind == CSG_OBJ_MESH) {
        leaf_mesh(w, o);
        return;
    }
    prec_extent x;
    switch (o->kind) {
#define PREC_FEATURE(ID, name)                                                                     \
    case CSG_OBJ_##ID:                                                                             \
        x = feature_##name(o);                                                                     \
        break;
        CSG_OBJECT_KINDS(PREC_FEATURE, CSG_KIND_NONE)
    default:
        return;
    }
    leaf_extent(w, o, &x, o->loc);
}

static void walk(prec_walk *w, const csg_object *o)
{
    if (csg_object_is_leaf(o->kind)) {
        leaf(w, o);
        return;
    }
    for (int i = 0; i < o->child_count; i++)
        walk(w, o->children[i]);
}

bool csg_needs_double(const csg_scene *s, int width, int height, char *why, size_t why_size)
{
    csg_camera_src cam;
    if (s->has_camera)
        cam = s->camera;
    else
        csg_camera_default(&cam);
    prec_walk w = {0};
    w.cam = cam.location;
    double dl = len3(cam.direction);
    double ax = len3(cam.right) / (double)(width > 0 ? width : 1);
    double ay = len3(cam.up) / (double)(height > 0 ? height : 1);
    w.alpha = dl > 0.0 ? fmin(ax, ay) / dl : 0.0;
    for (int i = 0; i < s->object_count; i++)
        walk(&w, s->objects[i]);
    bool need = w.at != NULL && w.worst > 1.0;
    if (why && why_size > 0) {
        if (w.at == NULL) {
            snprintf(why, why_size, "float: no object");
        } else {
            const char *what =
                w.at->kind == CSG_OBJ_MESH ? "mesh triangle" : csg_object_kind_name(w.at->kind);
            snprintf(why, why_size,
                     "%s: %s at %s:%d:%d: float error %.3g (2^-24 x %g x |p| %.3g) against "
                     "1/8 pixel = %.3g at distance %.3g, 1e-3 of its feature = %.3g "
                     "(ratio %.3g)",
                     need ? "double" : "float", what,
                     w.at_loc.file ? w.at_loc.file : "?", w.at_loc.line, w.at_loc.col, w.err,
                     CSG_PREC_ULPS, w.mag, w.allow_px, w.dist, w.allow_feat, w.worst);
        }
    }
    return need;
}
