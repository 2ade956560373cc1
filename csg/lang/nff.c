/*
 * nff.c — the Neutral File Format (Eric Haines' SPD scenes) into the scene
 * tree (nff.h); scenes/LANGUAGE.md, "NFF scenes", is its reference.
 *
 * Algorithm.  One pass over whitespace-separated tokens (so an entity's
 * numbers may sit on its line or on the next ones; `#` starts a comment
 * to the end of its line).  The first token of an entity must be a whole
 * keyword (`from` is not `f`, `pp` is not `p`).  Each entity becomes:
 *   v  the camera (right-handed: right = dir x up, true up = right x dir;
 *      the image plane spans 2 tan(angle / 2) across), the scene's image
 *      size (resolution) and near plane (hither);
 *   b  the background;   l  a point light;
 *   f  the current texture and interior (identical `f` lines share one);
 *   s  a sphere;   c  an open cone, or cylinder when the radii are equal;
 *   p  a polygon (3 vertices: a triangle), one-sided unless the material
 *      transmits;   pp a smooth triangle (more vertices: a mesh of smooth
 *      triangles, split as a polygon), two-sided.
 *      Consecutive triangles (p 3, or pp 3) of one material are one run:
 *      a mesh of them (one of them: a triangle), its vertices in one
 *      array, each triangle's location kept (csg_object.piece_locs).  It
 *      flattens to the very primitives and roots the triangles would
 *      (a top-level mesh is a root a triangle) and takes ~90 bytes a
 *      triangle where an object each took ~330: tetra11, 4 194 304 of
 *      them, is one mesh.
 * At the end every light gets the intensity sqrt(n) / (2n) of n lights
 * (the SPD's suggestion) unless it gave a colour, and ambient_light the
 * same value.
 *
 * Invariants: every message is one `file:line:col: error:` line at the
 * token concerned (end of file: its last position); every count read from
 * the file is bounded (CSG_NFF_MAX_*) before memory is taken for it, so
 * no input crashes or hangs the reader.  Everything that outlives the
 * parse is in the scene's arena; the growable tables are malloc'd and
 * freed on every path.
 */
#include "nff.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../camera_setup.h"
#include "../polygon.h"
#include "decimal.h"

typedef struct {
    void *data;
    int count, cap;
} nff_vec;

typedef struct {
    double f[8]; /* R G B Kd Ks Shine T ior, as written */
} nff_material;

typedef struct {
    const char *name;   /* the file, for locations (arena copy)       */
    const char *src;    /* the text, len bytes                         */
    size_t len, pos;
    int line, col;      /* of src[pos]                                 */
    const char *tok;    /* the current token: tok_len bytes            */
    size_t tok_len;
    csg_loc tok_loc;
    csg_scene *s;
    csg_diag *d;
    nff_vec objects;    /* csg_object *                                */
    nff_vec lights;     /* csg_light                                   */
    nff_vec materials;  /* nff_material: one texture and interior each */
    struct {
        csg_object *o;  /* the run of triangles being read, or NULL    */
        bool smooth;    /* of pp 3 (normals kept), else of p 3          */
        nff_vec verts;  /* dvec3, 3 a triangle                          */
        nff_vec normals; /* dvec3, 3 a triangle (smooth)                */
        nff_vec locs;   /* csg_loc, 1 a triangle                        */
    } run;
    int material;       /* the current one; -1 before the first `f`   */
    bool has_view;
    long entities;
} nff_reader;

/* ---- memory ---------------------------------------------------------------- */

static bool nff_oom(nff_reader *r)
{
    csg_error_plain(r->d, "out of memory");
    return false;
}

static void *nff_alloc(nff_reader *r, size_t size)
{
    void *m = csg_arena_alloc(r->s->arena, size ? size : 1);
    if (!m)
        nff_oom(r);
    return m;
}

static bool nff_push(nff_reader *r, nff_vec *v, size_t elem, const void *item)
{
    if (v->count == v->cap) {
        int cap = v->cap ? v->cap * 2 : 64;
        void *data = v->cap < (1 << 28) ? realloc(v->data, (size_t)cap * elem) : NULL;
        if (!data)
            return nff_oom(r);
        v->data = data;
        v->cap = cap;
    }
    memcpy((char *)v->data + (size_t)v->count * elem, item, elem);
    v->count++;
    return true;
}

static void *nff_to_arena(nff_reader *r, const nff_vec *v, size_t elem)
{
    void *m = nff_alloc(r, (size_t)v->count * elem);
    if (m && v->count)
        memcpy(m, v->data, (size_t)v->count * elem);
    return m;
}

/* ---- tokens ------------------------------------------------------------------ */

static void nff_advance(nff_reader *r)
{
    if (r->src[r->pos] == '\n') {
        r->line++;
        r->col = 1;
    } else {
        r->col++;
    }
    r->pos++;
}

/* The next token into r->tok (tok_len 0 at the end of the text). */
static void nff_next(nff_reader *r)
{
    for (;;) {
        while (r->pos < r->len && isspace((unsigned char)r->src[r->pos]))
            nff_advance(r);
        if (r->pos < r->len && r->src[r->pos] == '#') {
            while (r->pos < r->len && r->src[r->pos] != '\n')
                nff_advance(r);
            continue;
        }
        break;
    }
    r->tok = r->src + r->pos;
    r->tok_loc = (csg_loc){r->name, r->line, r->col};
    while (r->pos < r->len && !isspace((unsigned char)r->src[r->pos]) && r->src[r->pos] != '#')
        nff_advance(r);
    r->tok_len = (size_t)(r->src + r->pos - r->tok);
}

static bool nff_at_end(const nff_reader *r) { return r->tok_len == 0; }

static bool nff_is(const nff_reader *r, const char *word)
{
    size_t n = strlen(word);
    return r->tok_len == n && memcmp(r->tok, word, n) == 0;
}

/* "<what> expected, got 'tok'" at the current token. */
static bool nff_expected(nff_reader *r, const char *what)
{
    if (nff_at_end(r))
        csg_error(r->d, r->tok_loc, "%s expected, got end of file", what);
    else
        csg_error(r->d, r->tok_loc, "%s expected, got '%.*s'", what,
                  (int)(r->tok_len > 40 ? 40 : r->tok_len), r->tok);
    return false;
}

/* The current token as a finite number, strtod's (decimal.h first, the
 * same value faster); false for anything else. */
static bool nff_token_number(const nff_reader *r, double *v)
{
    char buf[64];
    if (r->tok_len >= sizeof buf)
        return false;
    if (csg_decimal_fast(r->tok, r->tok_len, v))
        return true;
    memcpy(buf, r->tok, r->tok_len);
    buf[r->tok_len] = '\0';
    char *end;
    *v = strtod(buf, &end);
    return end == buf + r->tok_len && isfinite(*v) &&
           (buf[0] == '-' || buf[0] == '+' || buf[0] == '.' || isdigit((unsigned char)buf[0]));
}

/* The current token as a finite number; consumes it. */
static bool nff_number(nff_reader *r, const char *what, double *out, csg_loc *at)
{
    double v;
    if (nff_at_end(r) || !nff_token_number(r, &v))
        return nff_expected(r, what);
    if (at)
        *at = r->tok_loc;
    *out = v;
    nff_next(r);
    return true;
}

static bool nff_numbers(nff_reader *r, const char *what, double *out, int n)
{
    for (int i = 0; i < n; i++)
        if (!nff_number(r, what, &out[i], NULL))
            return false;
    return true;
}

static bool nff_point(nff_reader *r, const char *what, dvec3 *p)
{
    double v[3];
    if (!nff_numbers(r, what, v, 3))
        return false;
    *p = (dvec3){v[0], v[1], v[2]};
    return true;
}

/* A whole number in [lo, hi]. */
static bool nff_count(nff_reader *r, const char *what, long lo, long hi, long *out)
{
    double v;
    csg_loc at;
    if (!nff_number(r, what, &v, &at))
        return false;
    if (!(v >= (double)lo && v <= (double)hi && v == floor(v))) {
        csg_error(r->d, at, "%s must be a whole number from %ld to %ld, got %g", what, lo, hi, v);
        return false;
    }
    *out = (long)v;
    return true;
}

/* The keyword `word` and what follows it. */
static bool nff_keyword(nff_reader *r, const char *word, const char *after)
{
    if (!nff_is(r, word)) {
        if (nff_at_end(r))
            csg_error(r->d, r->tok_loc, "'%s' expected after '%s', got end of file", word, after);
        else
            csg_error(r->d, r->tok_loc, "'%s' expected after '%s', got '%.*s'", word, after,
                      (int)(r->tok_len > 40 ? 40 : r->tok_len), r->tok);
        return false;
    }
    nff_next(r);
    return true;
}

/* ---- the view ------------------------------------------------------------------ */

static dvec3 v3d_sub(dvec3 a, dvec3 b) { return (dvec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static dvec3 v3d_scale(dvec3 a, double k) { return (dvec3){a.x * k, a.y * k, a.z * k}; }
static double v3d_len(dvec3 a) { return sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }
static dvec3 v3d_cross(dvec3 a, dvec3 b)
{
    return (dvec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/* The camera of from/at/up/angle for a w x h image: direction unit, right
 * and up spanning the image plane at distance 1 (right-handed). */
static bool nff_camera(nff_reader *r, dvec3 from, dvec3 at, dvec3 up, double angle, long w,
                       long h, csg_loc loc)
{
    dvec3 dir = v3d_sub(at, from);
    double dl = v3d_len(dir);
    if (!(dl > 0)) {
        csg_error(r->d, loc, "view 'at' equals 'from': no view direction");
        return false;
    }
    dir = v3d_scale(dir, 1 / dl);
    dvec3 right = v3d_cross(dir, up);
    double rl = v3d_len(right);
    if (!(rl > 1e-12 * v3d_len(up))) {
        csg_error(r->d, loc, "view 'up' is parallel to the view direction (or zero)");
        return false;
    }
    right = v3d_scale(right, 1 / rl);
    dvec3 true_up = v3d_cross(right, dir);
    double span = 2 * tan(angle * M_PI / 360.0);
    csg_camera_src *c = &r->s->camera;
    csg_camera_default(c);
    c->location = from;
    c->direction = dir;
    c->right = v3d_scale(right, span);
    c->up = v3d_scale(true_up, span * (double)h / (double)w);
    c->sky = true_up;
    c->loc = loc;
    r->s->has_camera = true;
    return true;
}

/* v, then from, at, up, angle, hither, resolution in this order. */
static bool nff_view(nff_reader *r)
{
    csg_loc loc = r->tok_loc, at_angle, at_hither;
    dvec3 from, at, up;
    double angle, hither;
    long w, h;
    nff_next(r);
    if (!nff_keyword(r, "from", "v") || !nff_point(r, "a number (from x y z)", &from) ||
        !nff_keyword(r, "at", "from") || !nff_point(r, "a number (at x y z)", &at) ||
        !nff_keyword(r, "up", "at") || !nff_point(r, "a number (up x y z)", &up) ||
        !nff_keyword(r, "angle", "up") || !nff_number(r, "a number (angle)", &angle, &at_angle) ||
        !nff_keyword(r, "hither", "angle") ||
        !nff_number(r, "a number (hither)", &hither, &at_hither) ||
        !nff_keyword(r, "resolution", "hither") ||
        !nff_count(r, "resolution width", 1, 65536, &w) ||
        !nff_count(r, "resolution height", 1, 65536, &h))
        return false;
    if (!(angle > 0 && angle < 180)) {
        csg_error(r->d, at_angle, "angle must be between 0 and 180 degrees, got %g", angle);
        return false;
    }
    if (!(hither >= 0)) {
        csg_error(r->d, at_hither, "hither must be >= 0, got %g", hither);
        return false;
    }
    r->s->width = (int)w;
    r->s->height = (int)h;
    r->s->hither = hither;
    r->has_view = true;
    return nff_camera(r, from, at, up, angle, w, h, loc);
}

/* ---- lights, background, materials ------------------------------------------- */

static bool nff_is_number_start(const nff_reader *r)
{
    return !nff_at_end(r) && (isdigit((unsigned char)r->tok[0]) || r->tok[0] == '-' ||
                              r->tok[0] == '+' || r->tok[0] == '.');
}

static bool nff_light(nff_reader *r)
{
    csg_light l;
    memset(&l, 0, sizeof l);
    l.loc = r->tok_loc;
    l.color[0] = -1; /* no colour given: set at the end */
    nff_next(r);
    if (!nff_point(r, "a number (light x y z)", &l.position))
        return false;
    if (nff_is_number_start(r) && !nff_numbers(r, "a number (light r g b)", l.color, 3))
        return false;
    return nff_push(r, &r->lights, sizeof l, &l);
}

static bool nff_background(nff_reader *r)
{
    nff_next(r);
    return nff_numbers(r, "a number (background r g b)", r->s->background, 3);
}

static bool nff_fill(nff_reader *r)
{
    static const char *const names[8] = {"r", "g", "b", "Kd", "Ks", "Shine", "T", "index of refraction"};
    nff_material m;
    csg_loc at[8];
    nff_next(r);
    for (int i = 0; i < 8; i++) {
        char what[64];
        snprintf(what, sizeof what, "a number (fill %s)", names[i]);
        if (!nff_number(r, what, &m.f[i], &at[i]))
            return false;
    }
    for (int i = 4; i < 7; i++) { /* Ks, Shine, T */
        if (m.f[i] < 0) {
            csg_error(r->d, at[i], "%s must be >= 0, got %g", names[i], m.f[i]);
            return false;
        }
    }
    if (m.f[6] > 0 && !(m.f[7] > 0)) {
        csg_error(r->d, at[7], "a transmitting material (T > 0) needs an index of refraction > 0, got %g",
                  m.f[7]);
        return false;
    }
    nff_material *all = r->materials.data;
    for (int i = 0; i < r->materials.count; i++) {
        if (memcmp(all[i].f, m.f, sizeof m.f) == 0) {
            r->material = i;
            return true;
        }
    }
    r->material = r->materials.count;
    return nff_push(r, &r->materials, sizeof m, &m);
}

/* ---- objects ------------------------------------------------------------------- */

/* The current material (before any `f`: NFF's implicit white matte). */
static bool nff_material_set(nff_reader *r)
{
    if (r->material >= 0)
        return true;
    nff_material m = {{1, 1, 1, 1, 0, 0, 0, 1}};
    r->material = r->materials.count;
    return nff_push(r, &r->materials, sizeof m, &m);
}

/* A malloc'd table of `count` elements, shrunk to them and handed to the
 * scene's arena; v emptied.  NULL when out of memory. */
static void *nff_vec_to_arena(nff_reader *r, nff_vec *v, size_t elem)
{
    void *data = realloc(v->data, (size_t)v->count * elem);
    if (!data) /* (a shrink that failed leaves the block as it was) */
        data = v->data;
    if (!csg_arena_adopt(r->s->arena, data)) {
        v->data = data;
        nff_oom(r);
        return NULL;
    }
    memset(v, 0, sizeof *v);
    return data;
}

/* The run of triangles ends: a mesh of them, or (one) a triangle. */
static bool nff_run_close(nff_reader *r)
{
    csg_object *o = r->run.o;
    if (!o)
        return true;
    r->run.o = NULL;
    int triangles = r->run.verts.count / 3;
    bool smooth = r->run.smooth;
    if (triangles == 1) { /* (the tables kept for the next run) */
        o->verts = nff_to_arena(r, &r->run.verts, sizeof(dvec3));
        o->normals = smooth ? nff_to_arena(r, &r->run.normals, sizeof(dvec3)) : NULL;
        r->run.verts.count = r->run.normals.count = r->run.locs.count = 0;
    } else {
        o->kind = CSG_OBJ_MESH;
        o->verts = nff_vec_to_arena(r, &r->run.verts, sizeof(dvec3));
        o->normals = smooth ? nff_vec_to_arena(r, &r->run.normals, sizeof(dvec3)) : NULL;
        o->piece_locs = nff_vec_to_arena(r, &r->run.locs, sizeof(csg_loc));
        if (!o->piece_locs)
            return false;
    }
    o->vert_count = 3 * triangles;
    return o->verts && (o->normals || !smooth);
}

/* A new object of `kind` at loc with the current material, in the list
 * (after the run of triangles before it). */
static csg_object *nff_object(nff_reader *r, enum csg_object_kind kind, csg_loc loc)
{
    if (!nff_material_set(r) || !nff_run_close(r))
        return NULL;
    csg_object *o = nff_alloc(r, sizeof *o);
    if (!o || !nff_push(r, &r->objects, sizeof o, &o))
        return NULL;
    o->kind = kind;
    o->loc = loc;
    csg_xform_identity(&o->xform);
    o->texture = r->material;
    o->interior = r->material;
    return o;
}

static bool nff_transmits(const nff_reader *r)
{
    return ((const nff_material *)r->materials.data)[r->material].f[6] > 0;
}

static bool nff_sphere(nff_reader *r)
{
    csg_loc loc = r->tok_loc, at;
    dvec3 c;
    double rad;
    nff_next(r);
    if (!nff_point(r, "a number (sphere x y z)", &c) ||
        !nff_number(r, "a number (sphere radius)", &rad, &at))
        return false;
    if (!(rad > 0)) {
        csg_error(r->d, at, "sphere radius must be > 0 (a negative one, inside-only, is not "
                  "supported), got %g", rad);
        return false;
    }
    csg_object *o = nff_object(r, CSG_OBJ_SPHERE, loc);
    if (!o)
        return false;
    o->a = c;
    o->r0 = rad;
    return true;
}

static bool nff_cone(nff_reader *r)
{
    csg_loc loc = r->tok_loc, at0, at1;
    dvec3 base, apex;
    double r0, r1;
    nff_next(r);
    if (!nff_point(r, "a number (cone base x y z)", &base) ||
        !nff_number(r, "a number (cone base radius)", &r0, &at0) ||
        !nff_point(r, "a number (cone apex x y z)", &apex) ||
        !nff_number(r, "a number (cone apex radius)", &r1, &at1))
        return false;
    if (r0 < 0 || r1 < 0) {
        csg_error(r->d, r0 < 0 ? at0 : at1, "cone radius must be >= 0 (a negative one, "
                  "inside-only, is not supported), got %g", r0 < 0 ? r0 : r1);
        return false;
    }
    if (!(r0 + r1 > 0) || !(v3d_len(v3d_sub(apex, base)) > 0)) {
        csg_error(r->d, loc, "degenerate cone: both radii 0 or base = apex");
        return false;
    }
    csg_object *o = nff_object(r, r0 == r1 ? CSG_OBJ_CYLINDER : CSG_OBJ_CONE, loc);
    if (!o)
        return false;
    o->a = base;
    o->b = apex;
    o->r0 = r0;
    o->r1 = r1;
    o->open = true;
    return true;
}

/* n vertices (and, of a pp, normals) of a p or pp into v (and nv). */
static bool nff_vertices(nff_reader *r, bool patch, long n, dvec3 *v, dvec3 *nv)
{
    for (long i = 0; i < n; i++) {
        if (!nff_point(r, patch ? "a number (patch vertex x y z)" : "a number (polygon vertex x y z)",
                       &v[i]) ||
            (patch && !nff_point(r, "a number (patch normal x y z)", &nv[i])))
            return false;
    }
    return true;
}

/* The same into new arena arrays (*nv NULL for a p). */
static bool nff_vertices_new(nff_reader *r, bool patch, long n, dvec3 **v, dvec3 **nv)
{
    *v = nff_alloc(r, (size_t)n * sizeof **v);
    *nv = patch ? nff_alloc(r, (size_t)n * sizeof **nv) : NULL;
    return *v && (*nv || !patch) && nff_vertices(r, patch, n, *v, *nv);
}

/* A pp of more than 3 vertices: a mesh of its smooth triangles. */
static bool nff_patch_mesh(nff_reader *r, csg_object *o, const dvec3 *v, const dvec3 *nv, long n)
{
    int *tri = malloc((size_t)(3 * (n - 2)) * sizeof *tri);
    if (!tri)
        return nff_oom(r);
    int count = csg_polygon_triangulate(v, (int)n, tri);
    bool ok = count > 0;
    if (!ok)
        csg_error(r->d, o->loc, "degenerate polygon: its vertices enclose no area");
    if (ok) {
        o->verts = nff_alloc(r, (size_t)(3 * count) * sizeof *o->verts);
        o->normals = nff_alloc(r, (size_t)(3 * count) * sizeof *o->normals);
        ok = o->verts && o->normals;
    }
    for (int k = 0; ok && k < 3 * count; k++) {
        o->verts[k] = v[tri[k]];
        o->normals[k] = nv[tri[k]];
    }
    o->vert_count = 3 * count;
    free(tri);
    return ok;
}

/* A p 3 or pp 3 (its vertices read): the run's next triangle, or the
 * first of a new run (another material, or kind, or an object between). */
static bool nff_triangle(nff_reader *r, bool patch, csg_loc loc, const dvec3 v[3],
                         const dvec3 nv[3])
{
    if (!(v3d_len(csg_polygon_normal(v, 3)) > 0)) {
        csg_error(r->d, loc, "degenerate polygon: its vertices enclose no area");
        return false;
    }
    if (!nff_material_set(r))
        return false;
    if (!r->run.o || r->run.smooth != patch || r->run.o->texture != r->material) {
        csg_object *o = nff_object(r, patch ? CSG_OBJ_SMOOTH_TRIANGLE : CSG_OBJ_TRIANGLE, loc);
        if (!o)
            return false;
        o->one_sided = !patch && !nff_transmits(r);
        r->run.o = o;
        r->run.smooth = patch;
    }
    for (int k = 0; k < 3; k++)
        if (!nff_push(r, &r->run.verts, sizeof v[k], &v[k]) ||
            (patch && !nff_push(r, &r->run.normals, sizeof nv[k], &nv[k])))
            return false;
    return nff_push(r, &r->run.locs, sizeof loc, &loc);
}

/* p n / pp n and the vertices. */
static bool nff_polygon(nff_reader *r)
{
    csg_loc loc = r->tok_loc;
    bool patch = nff_is(r, "pp");
    long n;
    dvec3 *v, *nv;
    nff_next(r);
    if (!nff_count(r, patch ? "patch vertex count" : "polygon vertex count", 3,
                   CSG_NFF_MAX_VERTICES, &n))
        return false;
    if (n == 3) {
        dvec3 tv[3], tn[3];
        return nff_vertices(r, patch, n, tv, tn) && nff_triangle(r, patch, loc, tv, tn);
    }
    if (!nff_vertices_new(r, patch, n, &v, &nv))
        return false;
    csg_object *o = nff_object(r, patch ? CSG_OBJ_MESH : CSG_OBJ_POLYGON, loc);
    if (!o)
        return false;
    o->one_sided = !patch && !nff_transmits(r);
    if (patch)
        return nff_patch_mesh(r, o, v, nv, n);
    o->verts = v;
    o->vert_count = (int)n;
    dvec3 nn = csg_polygon_normal(v, (int)n);
    if (!(v3d_len(nn) > 0)) {
        csg_error(r->d, loc, "degenerate polygon: its vertices enclose no area");
        return false;
    }
    return true;
}

/* ---- the file ---------------------------------------------------------------- */

static bool nff_entity(nff_reader *r)
{
    if (++r->entities > CSG_NFF_MAX_ENTITIES) {
        csg_error(r->d, r->tok_loc, "scene too large: more than %ld entities",
                  (long)CSG_NFF_MAX_ENTITIES);
        return false;
    }
    if (nff_is(r, "v")) {
        if (r->has_view) {
            csg_error(r->d, r->tok_loc, "a second view ('v'): a file has one");
            return false;
        }
        return nff_view(r);
    }
    if (nff_is(r, "b"))
        return nff_background(r);
    if (nff_is(r, "l"))
        return nff_light(r);
    if (nff_is(r, "f"))
        return nff_fill(r);
    if (nff_is(r, "s"))
        return nff_sphere(r);
    if (nff_is(r, "c"))
        return nff_cone(r);
    if (nff_is(r, "p") || nff_is(r, "pp"))
        return nff_polygon(r);
    return nff_expected(r, "an NFF entity (v, b, l, f, c, s, p, pp)");
}

/* A material as a POV-Ray texture: Kd and the ambient term undo the
 * renderer's opacity factor (1 - T), so the local colour is Kd exactly. */
static void nff_texture(const nff_material *m, csg_texture *t, csg_interior *in)
{
    double kd = m->f[3], ks = m->f[4], tr = m->f[6];
    double keep = tr < 1 ? kd / (1 - tr) : kd;
    csg_texture_default(t);
    for (int c = 0; c < 3; c++) {
        t->pigment.rgbft[c] = m->f[c];
        t->finish.ambient[c] = keep;
        t->finish.reflection[c] = ks;
    }
    t->pigment.rgbft[4] = tr;
    t->finish.diffuse = keep;
    t->finish.phong = ks;
    t->finish.phong_size = m->f[5];
    in->ior = tr > 0 ? m->f[7] : 1.0;
}

static bool nff_finish(nff_reader *r)
{
    csg_scene *s = r->s;
    if (!r->has_view) {
        csg_error(r->d, r->tok_loc, "no view ('v') in the file");
        return false;
    }
    if (!nff_run_close(r))
        return false;
    int n = r->lights.count;
    double each = n > 0 ? sqrt((double)n) / (2.0 * n) : 0.5;
    csg_light *l = r->lights.data;
    for (int i = 0; i < n; i++)
        if (l[i].color[0] < 0)
            l[i].color[0] = l[i].color[1] = l[i].color[2] = each;
    s->globals.ambient_light[0] = s->globals.ambient_light[1] = s->globals.ambient_light[2] = each;
    int m = r->materials.count;
    s->textures = nff_alloc(r, (size_t)m * sizeof *s->textures);
    s->interiors = nff_alloc(r, (size_t)m * sizeof *s->interiors);
    if (!s->textures || !s->interiors)
        return false;
    for (int i = 0; i < m; i++)
        nff_texture(&((nff_material *)r->materials.data)[i], &s->textures[i], &s->interiors[i]);
    s->texture_count = s->interior_count = m;
    s->objects = nff_to_arena(r, &r->objects, sizeof(csg_object *));
    s->lights = nff_to_arena(r, &r->lights, sizeof(csg_light));
    if (!s->objects || !s->lights)
        return false;
    s->object_count = r->objects.count;
    s->light_count = n;
    return true;
}

bool csg_nff_parse_string(const char *name, const char *text, size_t len, csg_scene *s,
                          csg_diag *d)
{
    nff_reader r;
    memset(&r, 0, sizeof r);
    r.s = s;
    r.d = d;
    r.material = -1;
    r.line = r.col = 1;
    csg_scene_init(s);
    csg_camera_default(&s->camera);
    s->arena = csg_arena_new();
    bool ok = false;
    if (!s->arena) {
        nff_oom(&r);
        goto done;
    }
    size_t nlen = strlen(name ? name : "<input>");
    char *path = nff_alloc(&r, nlen + 1);
    if (!path)
        goto done;
    memcpy(path, name ? name : "<input>", nlen);
    s->path = path;
    r.name = path;
    r.src = text ? text : ""; /* (read in place, never past len: no copy) */
    r.len = len;
    const char *nul = len ? memchr(text, '\0', len) : NULL;
    if (nul) {
        csg_loc at = {path, 1, 1};
        for (const char *c = text; c < nul; c++)
            at = *c == '\n' ? (csg_loc){path, at.line + 1, 1} : (csg_loc){path, at.line, at.col + 1};
        csg_error(d, at, "a NUL byte: not an NFF text file");
        goto done;
    }
    nff_next(&r);
    ok = true;
    while (ok && !nff_at_end(&r))
        ok = nff_entity(&r);
    ok = ok && nff_finish(&r);
done:
    free(r.objects.data);
    free(r.lights.data);
    free(r.materials.data);
    free(r.run.verts.data); /* (those a mesh took are NULL here) */
    free(r.run.normals.data);
    free(r.run.locs.data);
    if (!ok) {
        if (!d->failed)
            csg_error_plain(d, "internal error: the NFF parse failed without a message");
        csg_scene_free(s);
        csg_scene_init(s);
    }
    return ok;
}
