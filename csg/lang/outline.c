/*
 * outline.c — the two shapes made of an outline extruded along an axis:
 * POV-Ray's prism (its splines, linear_sweep) and text (TrueType glyphs
 * read through FreeType).  Both become CSG_OBJ_PRISM objects (scene.h):
 * closed polylines in the xy plane between two heights along z; the
 * curves are flattened here, within CSG_CURVE_TOLERANCE of the outline's
 * size (an em for a glyph), so every later stage (flattening, export)
 * sees polylines only; the edges on a curve (a prism's spline, a glyph's
 * Bezier) keep its segment (edge_curves), for the normals of the walls
 * (POV-Ray's Prism::Normal, and its TrueType normal: the same rule).
 *
 * prism: POV-Ray 3.7's rules (its Parse_Prism and Compute_Prism): the
 * points are read as 2D vectors; a sub-outline closes where a segment ends
 * on its first point (linear: P[0]; quadratic and cubic: P[1], the first
 * control point being the tangent's); quadratic and cubic splines
 * interpolate P[i+1] .. P[i+2] from P[i] .. P[i+3]; a Bezier spline takes
 * 4 points a segment.  The outline lies in POV-Ray's xz plane and is swept
 * along y between the heights (conic_sweep: the outline scaled by the
 * height, from the apex at the origin): the object's transform starts with
 * the swap of y and z (csg_prism_pov_frame).  `open` is refused, and a
 * conic sweep below height 0.
 *
 * text: POV-Ray 3.7's placement (TrueType::ProcessNewTTF): one prism a
 * glyph, in units of the em, from z = 0 to the thickness; the first glyph
 * starts at x = 0 (its left edge), every other one at the previous pen
 * position plus its left side bearing and the 'kern' table's pair value
 * (at least -1 em); the pen moves by the advance plus the kerning, and
 * then by the offset vector (its x and y).  The text is the union of the
 * glyphs, turned by POV-Ray's <0.001, 0.001, 0.001> degrees before its
 * modifiers.  Fonts are looked up as #include files are, also with ".ttf"
 * added; they are only read.
 */
#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../extrude.h"
#include "parse_internal.h"

/* The closed polylines of an outline being built. */
typedef struct {
    vec pts;    /* dvec3, z 0 */
    vec curves; /* csg_outline_curve: the edge from each point to the next */
    vec ends;   /* int: where each closed polyline ends in pts */
    bool curved; /* some edge is a piece of a curve (not a linear spline's) */
} outline;

static void outline_free(outline *o)
{
    free(o->pts.data);
    free(o->curves.data);
    free(o->ends.data);
}

/* A point, and the curve its edge to the next point follows (NULL: a
 * straight edge). */
static bool outline_point(parser *p, outline *o, double x, double y, const csg_outline_curve *c)
{
    dvec3 v = {x, y, 0};
    csg_outline_curve straight = {{0, 0}, {0, 0}, {0, 0}, {0, 0}, 0, 0};
    o->curved = o->curved || c;
    return lang_vec_push(p, &o->pts, sizeof v, &v) &&
           lang_vec_push(p, &o->curves, sizeof straight, c ? c : &straight);
}

/* Closes the polyline being built (dropping a last point equal to its
 * first: the edge before it then ends on the first point, where it
 * ended); one of fewer than 3 points is dropped. */
static bool outline_close(parser *p, outline *o)
{
    int start = o->ends.count ? ((int *)o->ends.data)[o->ends.count - 1] : 0;
    dvec3 *v = o->pts.data;
    if (o->pts.count - start > 1 && v[o->pts.count - 1].x == v[start].x &&
        v[o->pts.count - 1].y == v[start].y)
        o->pts.count--;
    if (o->pts.count - start < 3)
        o->pts.count = start;
    o->curves.count = o->pts.count;
    if (o->pts.count == start)
        return true;
    int end = o->pts.count;
    return lang_vec_push(p, &o->ends, sizeof end, &end);
}

/* A segment ((A t + B) t + C) t + D, t in [0, 1): its points before the
 * end, as many as keep it within tol (|B''| <= max(|2B|, |6A + 2B|)),
 * each edge with its piece of the curve unless the segment is straight
 * (a linear spline's: A = B = 0). */
static bool outline_segment(parser *p, outline *o, const double a[2], const double b[2],
                            const double c[2], const double d[2], double tol)
{
    double m0 = 2 * hypot(b[0], b[1]);
    double m1 = hypot(6 * a[0] + 2 * b[0], 6 * a[1] + 2 * b[1]);
    int n = csg_curve_segments(m0 > m1 ? m0 : m1, tol);
    bool straight = a[0] == 0 && a[1] == 0 && b[0] == 0 && b[1] == 0;
    bool ok = true;
    for (int k = 0; ok && k < n; k++) {
        double t = (double)k / n;
        csg_outline_curve piece = {{a[0], a[1]}, {b[0], b[1]}, {c[0], c[1]}, {d[0], d[1]},
                                   t, (double)(k + 1) / n};
        ok = outline_point(p, o, ((a[0] * t + b[0]) * t + c[0]) * t + d[0],
                           ((a[1] * t + b[1]) * t + c[1]) * t + d[1], straight ? NULL : &piece);
    }
    return ok;
}

/* Moves the outline into object o (arena copies). */
static bool outline_to_object(parser *p, outline *ol, csg_object *o)
{
    o->vert_count = ol->pts.count;
    o->contour_count = ol->ends.count;
    o->verts = lang_alloc(p, (size_t)(ol->pts.count ? ol->pts.count : 1) * sizeof(dvec3));
    int *ends = lang_alloc(p, (size_t)(ol->ends.count ? ol->ends.count : 1) * sizeof(int));
    if (!o->verts || !ends)
        return false;
    if (ol->pts.count)
        memcpy(o->verts, ol->pts.data, (size_t)ol->pts.count * sizeof(dvec3));
    if (ol->ends.count)
        memcpy(ends, ol->ends.data, (size_t)ol->ends.count * sizeof(int));
    o->contour_ends = ends;
    o->edge_curves = NULL;
    if (ol->curved && ol->pts.count) {
        size_t bytes = (size_t)ol->pts.count * sizeof(csg_outline_curve);
        csg_outline_curve *curves = lang_alloc(p, bytes);
        if (!curves)
            return false;
        memcpy(curves, ol->curves.data, bytes);
        o->edge_curves = curves;
    }
    return true;
}

/* ---- prism --------------------------------------------------------------------- */

enum spline { SPLINE_LINEAR, SPLINE_QUADRATIC, SPLINE_CUBIC, SPLINE_BEZIER };

#define PRISM_EPSILON 1e-10 /* POV-Ray's: points this close are the same */

static bool near_point(const double *a, const double *b)
{
    return fabs(a[0] - b[0]) < PRISM_EPSILON && fabs(a[1] - b[1]) < PRISM_EPSILON;
}

/* The power-basis coefficients of segment i (Compute_Prism's). */
static void spline_segment(enum spline kind, const double (*P)[2], int i, double A[2], double B[2],
                           double C[2], double D[2])
{
    for (int k = 0; k < 2; k++) {
        double p0 = P[i][k], p1 = P[i + 1][k], p2 = 0, p3 = 0;
        if (kind != SPLINE_LINEAR)
            p2 = P[i + 2][k];
        if (kind == SPLINE_CUBIC || kind == SPLINE_BEZIER)
            p3 = P[i + 3][k];
        switch (kind) {
        case SPLINE_LINEAR:
            A[k] = 0, B[k] = 0, C[k] = p1 - p0, D[k] = p0;
            break;
        case SPLINE_QUADRATIC:
            A[k] = 0, B[k] = 0.5 * p0 - p1 + 0.5 * p2, C[k] = -0.5 * p0 + 0.5 * p2, D[k] = p1;
            break;
        case SPLINE_CUBIC:
            A[k] = -0.5 * p0 + 1.5 * p1 - 1.5 * p2 + 0.5 * p3;
            B[k] = p0 - 2.5 * p1 + 2.0 * p2 - 0.5 * p3;
            C[k] = -0.5 * p0 + 0.5 * p2;
            D[k] = p1;
            break;
        default: /* Bezier */
            A[k] = p3 - 3.0 * p2 + 3.0 * p1 - p0;
            B[k] = 3.0 * p2 - 6.0 * p1 + 3.0 * p0;
            C[k] = 3.0 * p1 - 3.0 * p0;
            D[k] = p0;
            break;
        }
    }
}

/* The points each segment needs beyond its first (Compute_Prism's i1,
 * i2, i3) and how far a closing segment skips. */
static int spline_reach(enum spline kind)
{
    return kind == SPLINE_LINEAR ? 1 : kind == SPLINE_QUADRATIC ? 2 : 3;
}

static bool too_few_points(parser *p, csg_loc at)
{
    csg_error(p->d, at, "too few points in prism: an outline is not closed or lacks its control "
                        "points");
    return false;
}

/* A prism POV-Ray would not close (it ignores one, with a warning). */
static bool not_closed(parser *p, csg_loc at)
{
    csg_error(p->d, at, "prism not closed: an outline does not end on its first point");
    return false;
}

/* The outline of points P[0 .. n) as Compute_Prism walks it: a segment
 * at each i, and after one that ends on the outline's first point (a
 * Bezier spline: that is followed by a jump) the next outline. */
static bool prism_outline(parser *p, enum spline kind, const double (*P)[2], int n, outline *ol,
                          csg_loc at)
{
    double lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 2; k++)
            lo[k] = fmin(lo[k], P[i][k]), hi[k] = fmax(hi[k], P[i][k]);
    double tol = CSG_CURVE_TOLERANCE * fmax(hi[0] - lo[0], hi[1] - lo[1]);
    int reach = spline_reach(kind);
    const double *first = kind == SPLINE_LINEAR || kind == SPLINE_BEZIER ? P[0] : P[1];
    bool ok = true, pending = false;
    for (int i = 0; ok && i < n - 1; i++) {
        if (i + reach >= n)
            return too_few_points(p, at);
        double A[2], B[2], C[2], D[2];
        spline_segment(kind, P, i, A, B, C, D);
        ok = outline_segment(p, ol, A, B, C, D, tol);
        pending = true;
        if (kind == SPLINE_BEZIER) {
            const double *end = P[i + 3];
            i += 3;
            if (i + 1 >= n || !near_point(P[i + 1], end)) {
                if (!near_point(end, first))
                    return not_closed(p, at);
                ok = ok && outline_close(p, ol);
                pending = false;
                if (i + 1 < n)
                    first = P[i + 1];
            }
            continue;
        }
        const double *end = kind == SPLINE_LINEAR ? P[i + 1] : P[i + 2];
        if (near_point(end, first)) {
            ok = ok && outline_close(p, ol);
            pending = false;
            i += reach;
            int f = kind == SPLINE_LINEAR ? i + 1 : i + 2;
            if (f < n)
                first = P[f];
        }
    }
    if (ok && pending) {
        if (kind != SPLINE_LINEAR)
            return not_closed(p, at);
        ok = outline_close(p, ol); /* POV-Ray closes a linear one (with a warning) */
    }
    return ok;
}

bool lang_parse_prism(parser *p, csg_object *o)
{
    enum spline kind = SPLINE_LINEAR;
    for (;;) {
        enum csg_kw kw = lang_tok(p)->kw;
        if (lang_tok(p)->kind != CSG_TOK_WORD)
            break;
        if (kw == CSG_KW_CONIC_SWEEP || kw == CSG_KW_LINEAR_SWEEP)
            o->conic = kw == CSG_KW_CONIC_SWEEP;
        else if (kw == CSG_KW_LINEAR_SPLINE || kw == CSG_KW_QUADRATIC_SPLINE ||
            kw == CSG_KW_CUBIC_SPLINE || kw == CSG_KW_BEZIER_SPLINE)
            kind = kw == CSG_KW_LINEAR_SPLINE      ? SPLINE_LINEAR
                   : kw == CSG_KW_QUADRATIC_SPLINE ? SPLINE_QUADRATIC
                   : kw == CSG_KW_CUBIC_SPLINE     ? SPLINE_CUBIC
                                                   : SPLINE_BEZIER;
        else
            break;
        if (!lang_next(p))
            return false;
    }
    double h1, h2, count;
    csg_loc at, h_at;
    bool ok = lang_parse_float(p, &h1, NULL);
    if (ok && lang_is_punct(p, ','))
        ok = lang_next(p);
    ok = ok && lang_parse_float(p, &h2, &h_at);
    if (ok && h1 == h2) {
        csg_error(p->d, h_at, "prism heights are equal (%g): it has no volume", h1);
        return false;
    }
    if (ok && o->conic && fmin(h1, h2) < 0)
        return lang_unsupported(p, "a conic_sweep prism with a height below 0 (its apex "
                                   "inside)", h_at);
    if (ok && lang_is_punct(p, ','))
        ok = lang_next(p);
    ok = ok && lang_parse_float(p, &count, &at);
    if (!ok)
        return false;
    static const int least[] = {3, 5, 6, 4};
    if (!(count >= least[kind] && count <= 1000000) ||
        (kind == SPLINE_BEZIER && fmod(floor(count), 4) != 0)) {
        csg_error(p->d, at, "prism with %s splines needs %s points (at most 1000000), got %g",
                  kind == SPLINE_LINEAR      ? "linear"
                  : kind == SPLINE_QUADRATIC ? "quadratic"
                  : kind == SPLINE_CUBIC     ? "cubic"
                                             : "Bezier",
                  kind == SPLINE_LINEAR      ? "at least 3"
                  : kind == SPLINE_QUADRATIC ? "at least 5"
                  : kind == SPLINE_CUBIC     ? "at least 6"
                                             : "4 a segment",
                  count);
        return false;
    }
    int n = (int)count;
    double(*P)[2] = malloc((size_t)n * sizeof *P);
    if (!P)
        return lang_oom(p);
    for (int i = 0; ok && i < n; i++) {
        if (lang_is_punct(p, ','))
            ok = lang_next(p);
        value v;
        csg_loc vat = lang_tok(p)->loc;
        ok = ok && lang_parse_expr(p, &v) && lang_check_finite(p, &v, vat);
        if (ok) { /* a float f is the point <f, f> (POV-Ray's UV vector) */
            P[i][0] = v.v[0];
            P[i][1] = v.dim < 2 ? v.v[0] : v.v[1];
        }
    }
    if (ok && lang_is_punct(p, ','))
        ok = lang_next(p);
    if (ok && lang_is_kw(p, CSG_KW_OPEN)) {
        free(P);
        return lang_unsupported(p, "'open' on a prism", p->tok.loc);
    }
    if (ok && lang_is_kw(p, CSG_KW_STURM)) /* a root solver's choice: the pieces are exact */
        ok = lang_next(p);
    outline ol = {{0}, {0}, {0}, false};
    ok = ok && prism_outline(p, kind, (const double(*)[2])P, n, &ol, o->loc) &&
         outline_to_object(p, &ol, o);
    free(P);
    outline_free(&ol);
    if (!ok)
        return false;
    o->r0 = fmin(h1, h2);
    o->r1 = fmax(h1, h2);
    csg_prism_pov_frame(&o->xform);
    return true;
}

/* ---- text ---------------------------------------------------------------------- */

/* FreeType's outline walk into an outline: font units scaled by `scale`
 * and moved by (dx, dy) (the glyph's place, in font units). */
typedef struct {
    parser *p;
    outline *ol;
    double scale, dx, dy, tol; /* tol in font units */
    double x, y;               /* the pen, font units */
    bool started, ok;
} glyph_walk;

static bool walk_point(glyph_walk *w, double x, double y)
{
    return outline_point(w->p, w->ol, (x + w->dx) * w->scale, (y + w->dy) * w->scale, NULL);
}

static int walk_move(const FT_Vector *to, void *user)
{
    glyph_walk *w = user;
    if (w->started)
        w->ok = w->ok && outline_close(w->p, w->ol);
    w->started = true;
    w->x = to->x;
    w->y = to->y;
    w->ok = w->ok && walk_point(w, w->x, w->y);
    return w->ok ? 0 : 1;
}

static int walk_line(const FT_Vector *to, void *user)
{
    glyph_walk *w = user;
    w->x = to->x;
    w->y = to->y;
    w->ok = w->ok && walk_point(w, w->x, w->y);
    return w->ok ? 0 : 1;
}

/* A Bezier curve from the pen: the points after its start, its end
 * included (the power basis as the prism's segments), each edge with its
 * piece of the curve (in the outline's units: POV-Ray's TrueType normal is
 * the curve's where the ray meets it, as a prism's), the edge from the
 * pen, already in the outline, too. */
static int walk_curve(glyph_walk *w, const double A[2], const double B[2], const double C[2],
                      const double D[2], double end_x, double end_y)
{
    double m0 = 2 * hypot(B[0], B[1]), m1 = hypot(6 * A[0] + 2 * B[0], 6 * A[1] + 2 * B[1]);
    int n = csg_curve_segments(m0 > m1 ? m0 : m1, w->tol);
    double shift[2] = {w->dx, w->dy};
    csg_outline_curve piece;
    for (int k = 0; k < 2; k++) {
        piece.a[k] = A[k] * w->scale;
        piece.b[k] = B[k] * w->scale;
        piece.c[k] = C[k] * w->scale;
        piece.d[k] = (D[k] + shift[k]) * w->scale;
    }
    bool straight = A[0] == 0 && A[1] == 0 && B[0] == 0 && B[1] == 0;
    if (!straight && w->ol->curves.count > 0) {
        piece.u0 = 0;
        piece.u1 = 1.0 / n;
        ((csg_outline_curve *)w->ol->curves.data)[w->ol->curves.count - 1] = piece;
        w->ol->curved = true;
    }
    for (int k = 1; w->ok && k < n; k++) {
        double t = (double)k / n;
        piece.u0 = t;
        piece.u1 = (double)(k + 1) / n;
        double x = ((A[0] * t + B[0]) * t + C[0]) * t + D[0];
        double y = ((A[1] * t + B[1]) * t + C[1]) * t + D[1];
        w->ok = outline_point(w->p, w->ol, (x + w->dx) * w->scale, (y + w->dy) * w->scale,
                              straight ? NULL : &piece);
    }
    w->x = end_x;
    w->y = end_y;
    w->ok = w->ok && walk_point(w, end_x, end_y);
    return w->ok ? 0 : 1;
}

static int walk_conic(const FT_Vector *c, const FT_Vector *to, void *user)
{
    glyph_walk *w = user;
    double p0[2] = {w->x, w->y}, p1[2] = {(double)c->x, (double)c->y},
           p2[2] = {(double)to->x, (double)to->y};
    double A[2], B[2], C[2], D[2];
    for (int k = 0; k < 2; k++) {
        A[k] = 0;
        B[k] = p0[k] - 2 * p1[k] + p2[k];
        C[k] = 2 * (p1[k] - p0[k]);
        D[k] = p0[k];
    }
    return walk_curve(w, A, B, C, D, p2[0], p2[1]);
}

static int walk_cubic(const FT_Vector *c0, const FT_Vector *c1, const FT_Vector *to, void *user)
{
    glyph_walk *w = user;
    double P[4][2] = {{w->x, w->y},
                      {(double)c0->x, (double)c0->y},
                      {(double)c1->x, (double)c1->y},
                      {(double)to->x, (double)to->y}};
    double A[2], B[2], C[2], D[2];
    spline_segment(SPLINE_BEZIER, (const double(*)[2])P, 0, A, B, C, D);
    return walk_curve(w, A, B, C, D, P[3][0], P[3][1]);
}

/* The font file: as an #include file is found, then with ".ttf" added
 * (POV-Ray's font lookup). */
static char *find_font(parser *p, const char *name, csg_loc at)
{
    bool searched;
    char *path = lang_find_file(p, name, &searched);
    if (path && lang_file_exists(path))
        return path;
    size_t len = strlen(name);
    char *with = malloc(len + 5);
    if (!with) {
        lang_oom(p);
        return NULL;
    }
    memcpy(with, name, len);
    memcpy(with + len, ".ttf", 5);
    char *other = lang_find_file(p, with, &searched);
    free(with);
    if (other && lang_file_exists(other))
        return other;
    csg_error(p->d, at, "cannot read font file '%s': no such file%s", name,
              searched ? " (nor found in the library folders)" : "");
    return NULL;
}

/* The glyph of code point `c`, placed (font units) at (dx, dy), appended
 * to the union `text` as a prism of thickness `depth`. */
static bool add_glyph(parser *p, FT_Face face, FT_UInt gi, double dx, double dy, double depth,
                      csg_object *text, vec *kids, csg_loc at)
{
    FT_Outline *fo = &face->glyph->outline;
    if (fo->n_contours <= 0)
        return true; /* a space: nothing to see */
    outline ol = {{0}, {0}, {0}, false};
    glyph_walk w = {p, &ol, 1.0 / face->units_per_EM, dx, dy,
                    CSG_CURVE_TOLERANCE * face->units_per_EM, 0, 0, false, true};
    FT_Outline_Funcs funcs = {walk_move, walk_line, walk_conic, walk_cubic, 0, 0};
    int err = FT_Outline_Decompose(fo, &funcs, &w);
    bool ok = w.ok && err == 0 && (!w.started || outline_close(p, &ol));
    if (!ok && w.ok)
        csg_error(p->d, at, "glyph %u of the font cannot be read (FreeType error %d)", gi, err);
    csg_object *g = ok && ol.ends.count > 0 ? lang_new_object(p, CSG_OBJ_PRISM, text->loc) : NULL;
    if (g) {
        ok = outline_to_object(p, &ol, g) && lang_vec_push(p, kids, sizeof g, &g);
        g->r0 = fmin(0, depth);
        g->r1 = fmax(0, depth);
    }
    outline_free(&ol);
    return ok && (ol.ends.count == 0 || g != NULL);
}

/* The glyph index, advance, left side bearing and left edge (font units)
 * of code point c, its outline loaded into face->glyph. */
static bool load_glyph(parser *p, FT_Face face, unsigned long c, FT_UInt *gi, double *advance,
                       double *lsb, double *x_min, csg_loc at)
{
    *gi = FT_Get_Char_Index(face, c);
    int err = FT_Load_Glyph(face, *gi, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP);
    if (err) {
        csg_error(p->d, at, "glyph %u of the font cannot be loaded (FreeType error %d)", *gi, err);
        return false;
    }
    *advance = (double)face->glyph->metrics.horiAdvance;
    *lsb = (double)face->glyph->metrics.horiBearingX;
    FT_BBox box = {0, 0, 0, 0};
    if (face->glyph->outline.n_points > 0)
        FT_Outline_Get_CBox(&face->glyph->outline, &box);
    *x_min = (double)box.xMin;
    return true;
}

/* The glyphs of `str` into kids, placed as ProcessNewTTF places them. */
static bool lay_out(parser *p, FT_Face face, const char *str, double depth, dvec3 offset,
                    csg_object *text, vec *kids, csg_loc at)
{
    double em = face->units_per_EM;
    double pen_x = 0, pen_y = 0; /* font units */
    FT_UInt prev = 0;
    bool ok = true;
    for (size_t i = 0; ok && str[i]; i++) {
        unsigned long c = (unsigned char)str[i]; /* POV-Ray 3.7: one byte a character */
        FT_UInt gi;
        double advance, lsb, x_min, dx, dy;
        ok = load_glyph(p, face, c, &gi, &advance, &lsb, &x_min, at);
        if (!ok)
            break;
        if (i == 0) {
            dx = -x_min;
            dy = 0;
            pen_x = advance - lsb;
        } else {
            FT_Vector k = {0, 0};
            if (FT_HAS_KERNING(face))
                FT_Get_Kerning(face, prev, gi, FT_KERNING_UNSCALED, &k);
            double kern = fmax((double)k.x, -em);
            dx = pen_x + lsb - x_min + kern;
            dy = pen_y;
            pen_x += advance + kern;
        }
        ok = add_glyph(p, face, gi, dx, dy, depth, text, kids, at);
        pen_x += offset.x * em;
        pen_y += offset.y * em;
        prev = gi;
    }
    return ok;
}

bool lang_parse_text(parser *p, csg_object *text)
{
    csg_loc font_at = lang_tok(p)->loc, str_at;
    if (!lang_is_kw(p, CSG_KW_TTF))
        return lang_expected(p, "'ttf' expected inside 'text' (a font file)");
    char *font = NULL, *str = NULL, *path = NULL;
    double depth = 0;
    dvec3 offset = {0, 0, 0};
    bool ok = lang_next(p) && lang_parse_string(p, &font);
    if (ok && lang_is_punct(p, ','))
        ok = lang_next(p);
    str_at = lang_tok(p)->loc;
    ok = ok && lang_parse_string(p, &str);
    if (ok && lang_is_punct(p, ','))
        ok = lang_next(p);
    csg_loc depth_at;
    ok = ok && lang_parse_float(p, &depth, &depth_at);
    if (ok && depth == 0) {
        csg_error(p->d, depth_at, "text thickness must not be 0");
        ok = false;
    }
    if (ok && lang_is_punct(p, ','))
        ok = lang_next(p);
    ok = ok && lang_parse_vector(p, &offset, NULL);
    if (ok)
        path = find_font(p, font, font_at);
    FT_Library lib = NULL;
    FT_Face face = NULL;
    vec kids = {0};
    if (path) {
        int err = FT_Init_FreeType(&lib);
        if (!err)
            err = FT_New_Face(lib, path, 0, &face);
        if (err)
            csg_error(p->d, font_at, "cannot read font file '%s': not a font FreeType reads "
                                     "(error %d)", path, err);
        ok = !err && lay_out(p, face, str, depth, offset, text, &kids, str_at);
    } else {
        ok = false;
    }
    if (ok && kids.count == 0) {
        csg_error(p->d, str_at, "text with nothing to see: no glyph of the string has an "
                                "outline");
        ok = false;
    }
    if (ok) {
        text->children = lang_alloc(p, (size_t)kids.count * sizeof(csg_object *));
        ok = text->children != NULL;
        if (ok) {
            memcpy(text->children, kids.data, (size_t)kids.count * sizeof(csg_object *));
            text->child_count = kids.count;
        }
    }
    free(kids.data);
    if (face)
        FT_Done_Face(face);
    if (lib)
        FT_Done_FreeType(lib);
    free(font);
    free(str);
    if (!ok)
        return false;
    /* POV-Ray's "tiny rotation [that] should fix cracks in text that lies
     * along an axis", before the text's own modifiers */
    csg_xform turn;
    csg_xform_identity(&turn);
    csg_xform_rotate(&turn, (dvec3){0.001, 0.001, 0.001});
    return lang_object_transform(p, text, &turn);
}
