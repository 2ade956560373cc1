/*
 * parser.c — recursive-descent parser of the scene language
 * (scenes/LANGUAGE.md) into the scene tree of scene.h: the statement and
 * object grammar, the camera, and the entry points of parser.h.  Tokens
 * come from source.c, which runs the directives (directives.c,
 * declare.c) wherever they appear; values and expressions are read by
 * expr.c, textures by texture.c (parse_internal.h lists what each
 * provides).
 *
 * Objects: while parsing, an object's xform is its LOCAL transform (relative
 * to the enclosing CSG object); a finished CSG object owns its children.
 * `object { NAME }` deep-copies the declared tree.  When the whole file has
 * been read, compose_world() turns every local transform into the complete
 * object -> world transform, top-down, in one pass.
 *
 * Textures and interiors live in growable tables (scene->textures ...).  A
 * modifier edits the object's own entry when the entry was created while
 * parsing this very object statement (index >= the table size when the
 * statement began) and belongs to that object alone, and otherwise appends
 * a modified copy (copy-on-write): entries shared by copies of a declared
 * object are never edited.  A transform of an object also moves the
 * patterned pigments given so far to it and to its children (POV-Ray
 * transforms an object's textures with it): each gets a transformed copy of
 * its entry.  A top-level object with no texture gets the default texture
 * (#default) in force when its statement ends, as in POV-Ray.
 *
 * The camera: POV-Ray 3.5+ applies look_at, angle, the orthographic sizing
 * and the transforms in a fixed order at the end of the statement
 * (camera_setup.h); a scene with #version below 3.5 gets the old
 * item-by-item behaviour.
 *
 * Invariants and limits: every node records the height of its tree
 * (pnode.height), kept <= CSG_PARSE_MAX_NESTING, so the copy and the final
 * pass recurse at most that deep; p->nodes <= CSG_PARSE_MAX_OBJECTS.  Every
 * allocation that outlives the parse is in the scene's arena; the growable
 * tables and the symbol table are malloc'd, the tables copied into the arena
 * at the end (one cleanup path frees them whatever happens).
 */
#include "parser.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../camera_setup.h"
#include "../device/flat.h"
#include "parse_internal.h"

/* A tree node with the height of its subtree (1 for a primitive). */
typedef struct {
    csg_object obj; /* first member: a csg_object * converts back */
    int height;
} pnode;

/* ---- memory ---------------------------------------------------------------- */

bool lang_oom(parser *p)
{
    csg_error_plain(p->d, "out of memory");
    return false;
}

void *lang_alloc(parser *p, size_t size)
{
    void *m = csg_arena_alloc(p->s->arena, size ? size : 1);
    if (!m)
        lang_oom(p);
    return m;
}

char *lang_strndup(parser *p, const char *text, size_t len)
{
    char *c = lang_alloc(p, len + 1);
    if (c)
        memcpy(c, text, len);
    return c;
}

bool lang_vec_push(parser *p, vec *v, size_t elem, const void *item)
{
    if (v->count == v->cap) {
        if (v->cap > INT_MAX / 4)
            return lang_oom(p);
        int cap = v->cap ? v->cap * 2 : 16;
        void *data = realloc(v->data, (size_t)cap * elem);
        if (!data)
            return lang_oom(p);
        v->data = data;
        v->cap = cap;
    }
    memcpy((char *)v->data + (size_t)v->count * elem, item, elem);
    v->count++;
    return true;
}

/* Vectors of at least this many bytes are handed to the arena rather than
 * copied (a scene of 10^5 textured spheres: a 90 MB copy, its zeroing and
 * page faults, about a tenth of the whole render, issue #39). */
#define VEC_ADOPT_BYTES 65536

/* The first `count` items of v, in the arena: a small v copied, a big one
 * trimmed and adopted (v is then empty). */
static void *vec_to_arena(parser *p, vec *v, size_t elem)
{
    size_t bytes = (size_t)v->count * elem;
    if (bytes >= VEC_ADOPT_BYTES) {
        void *trimmed = realloc(v->data, bytes); /* a shrink: fails only to move */
        v->data = trimmed ? trimmed : v->data;
        void *data = v->data;
        if (!csg_arena_adopt(p->s->arena, data)) {
            lang_oom(p);
            return NULL;
        }
        *v = (vec){0};
        return data;
    }
    void *m = lang_alloc(p, bytes);
    if (m && v->count)
        memcpy(m, v->data, bytes);
    return m;
}

/* ---- tokens ------------------------------------------------------------------ */

static void skip_comma(parser *p, bool *ok)
{
    if (lang_is_punct(p, ','))
        *ok = lang_next(p);
}

/* ---- objects ---------------------------------------------------------------- */

/* The object kind a keyword opens (CSG_OBJECT_KINDS: the keyword of each
 * kind is CSG_KW_<ID>); -1 for any other word. */
static int kind_of_keyword(enum csg_kw kw)
{
    switch (kw) {
#define PARSE_KIND_OF(ID, name)                                                                    \
    case CSG_KW_##ID:                                                                              \
        return CSG_OBJ_##ID;
        CSG_OBJECT_KINDS(PARSE_KIND_OF, PARSE_KIND_OF)
    case CSG_KW_QUARTIC: /* poly of order 4 and 3 (POV-Ray's Parse_Poly) */
    case CSG_KW_CUBIC:
        return CSG_OBJ_POLY;
    default:
        return -1;
    }
}

bool lang_is_object_start(parser *p)
{
    const csg_token *t = lang_tok(p);
    return t->kind == CSG_TOK_WORD &&
           (kind_of_keyword(t->kw) >= 0 || t->kw == CSG_KW_OBJECT || t->kw == CSG_KW_TEXT);
}

static int height_of(const csg_object *o)
{
    return ((const pnode *)(const void *)o)->height;
}

static pnode *new_node(parser *p, enum csg_object_kind kind, csg_loc loc)
{
    if (p->nodes >= CSG_PARSE_MAX_OBJECTS) {
        csg_error(p->d, loc, "scene too large: more than %ld objects", (long)CSG_PARSE_MAX_OBJECTS);
        return NULL;
    }
    pnode *n = lang_alloc(p, sizeof *n);
    if (!n)
        return NULL;
    p->nodes++;
    n->obj.kind = kind;
    n->obj.loc = loc;
    csg_xform_identity(&n->obj.xform);
    n->obj.texture = -1;
    n->obj.interior = -1;
    n->height = 1;
    return n;
}

csg_object *lang_new_object(parser *p, enum csg_object_kind kind, csg_loc loc)
{
    pnode *n = new_node(p, kind, loc);
    return n ? &n->obj : NULL;
}

static bool copy_list(parser *p, csg_object *const *src, int count, csg_loc loc,
                      csg_object ***out);

/* A deep copy of a declared tree (its height is bounded, so is the recursion). */
static pnode *copy_tree(parser *p, const csg_object *src, csg_loc loc)
{
    pnode *n = new_node(p, src->kind, loc);
    if (!n)
        return NULL;
    n->obj = *src;
    n->height = height_of(src);
    if (src->child_count > 0) {
        n->obj.children = lang_alloc(p, (size_t)src->child_count * sizeof *n->obj.children);
        if (!n->obj.children)
            return NULL;
        for (int i = 0; i < src->child_count; i++) {
            pnode *c = copy_tree(p, src->children[i], loc);
            if (!c)
                return NULL;
            n->obj.children[i] = &c->obj;
        }
    }
    if (!copy_list(p, src->clips, src->clip_count, loc, &n->obj.clips))
        return NULL;
    if (src->bound_is_clip)
        n->obj.bounds = n->obj.clips;
    else if (!copy_list(p, src->bounds, src->bound_count, loc, &n->obj.bounds))
        return NULL;
    return n;
}

/* A deep copy of a clip or bound list. */
static bool copy_list(parser *p, csg_object *const *src, int count, csg_loc loc,
                      csg_object ***out)
{
    if (count <= 0)
        return true;
    *out = lang_alloc(p, (size_t)count * sizeof **out);
    if (!*out)
        return false;
    for (int i = 0; i < count; i++) {
        pnode *c = copy_tree(p, src[i], loc);
        if (!c)
            return false;
        (*out)[i] = &c->obj;
    }
    return true;
}

static const char *object_name(enum csg_kw kw)
{
    if (kw == CSG_KW_TEXT)
        return "text";
    if (kw == CSG_KW_QUARTIC || kw == CSG_KW_CUBIC)
        return kw == CSG_KW_QUARTIC ? "quartic" : "cubic";
    int kind = kind_of_keyword(kw);
    return kind >= 0 ? csg_object_kind_name(kind) : "object";
}

static bool same_point(dvec3 a, dvec3 b)
{
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

static bool parse_sphere(parser *p, csg_object *o)
{
    csg_loc at;
    bool ok = lang_parse_vector(p, &o->a, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !lang_parse_float(p, &o->r0, &at))
        return false;
    if (!(o->r0 > 0)) {
        csg_error(p->d, at, "sphere radius must be > 0, got %g", o->r0);
        return false;
    }
    return true;
}

static bool parse_box(parser *p, csg_object *o)
{
    bool ok = lang_parse_vector(p, &o->a, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !lang_parse_vector(p, &o->b, NULL))
        return false;
    /* corners in any order; equal on an axis: a sheet, as in POV-Ray */
    double lo[3] = {o->a.x, o->a.y, o->a.z}, hi[3] = {o->b.x, o->b.y, o->b.z};
    for (int i = 0; i < 3; i++) {
        if (lo[i] > hi[i]) {
            double t = lo[i];
            lo[i] = hi[i];
            hi[i] = t;
        }
    }
    o->a = (dvec3){lo[0], lo[1], lo[2]};
    o->b = (dvec3){hi[0], hi[1], hi[2]};
    return true;
}

static bool parse_cylinder(parser *p, csg_object *o)
{
    csg_loc at;
    bool ok = lang_parse_vector(p, &o->a, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (ok)
        ok = lang_parse_vector(p, &o->b, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !lang_parse_float(p, &o->r0, &at))
        return false;
    o->r1 = o->r0;
    if (!(o->r0 > 0)) {
        csg_error(p->d, at, "cylinder radius must be > 0, got %g", o->r0);
        return false;
    }
    if (same_point(o->a, o->b)) {
        csg_error(p->d, o->loc, "cylinder base and cap are the same point");
        return false;
    }
    return true;
}

static bool parse_cone(parser *p, csg_object *o)
{
    csg_loc at0, at1;
    bool ok = lang_parse_vector(p, &o->a, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (ok)
        ok = lang_parse_float(p, &o->r0, &at0);
    if (ok)
        skip_comma(p, &ok);
    if (ok)
        ok = lang_parse_vector(p, &o->b, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !lang_parse_float(p, &o->r1, &at1))
        return false;
    if (o->r0 < 0 || o->r1 < 0) {
        csg_error(p->d, o->r0 < 0 ? at0 : at1, "cone radius must be >= 0, got %g",
                  o->r0 < 0 ? o->r0 : o->r1);
        return false;
    }
    if (o->r0 == 0 && o->r1 == 0) {
        csg_error(p->d, o->loc, "cone radii are both 0");
        return false;
    }
    if (same_point(o->a, o->b)) {
        csg_error(p->d, o->loc, "cone base and cap are the same point");
        return false;
    }
    return true;
}

/* torus { R, r [union | merge | difference | intersection] }: POV-Ray's
 * rules.  A negative radius stands for its magnitude and inverts the
 * torus (POV-Ray warns and does the same).  The spindle modes matter only
 * where R < r (a spindle torus): there only union, the default, is
 * implemented (the quartic's own solid); intersection makes any torus a
 * spindle one in POV-Ray and is refused. */
static bool parse_torus(parser *p, csg_object *o)
{
    csg_loc at0, at1;
    bool ok = lang_parse_float(p, &o->r0, &at0);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !lang_parse_float(p, &o->r1, &at1))
        return false;
    if (o->r0 < 0 || o->r1 < 0) {
        o->inverse = (o->r0 < 0) != (o->r1 < 0);
        o->r0 = fabs(o->r0);
        o->r1 = fabs(o->r1);
    }
    if (!(o->r0 > 0) || !(o->r1 > 0) || !isfinite(o->r0) || !isfinite(o->r1)) {
        csg_error(p->d, !(o->r0 > 0) || !isfinite(o->r0) ? at0 : at1,
                  "torus radii must be non-zero finite numbers, got %g and %g", o->r0, o->r1);
        return false;
    }
    const csg_token *t = lang_tok(p);
    bool mode = lang_is_kw(p, CSG_KW_UNION) || lang_is_kw(p, CSG_KW_MERGE) ||
                lang_is_kw(p, CSG_KW_DIFFERENCE) || lang_is_kw(p, CSG_KW_INTERSECTION);
    if (mode && (lang_is_kw(p, CSG_KW_INTERSECTION) ||
                 (o->r0 < o->r1 && !lang_is_kw(p, CSG_KW_UNION)))) {
        csg_error(p->d, t->loc, "the spindle torus mode '%.*s' is not supported (only union, "
                                "the default)", (int)t->len, t->text);
        return false;
    }
    return !mode || lang_next(p);
}

/* quadric { <A, B, C>, <D, E, F>, <G, H, I>, J } (POV-Ray's order: the
 * squares, then xy, xz, yz, then x, y, z, then the constant). */
static bool parse_quadric(parser *p, csg_object *o)
{
    dvec3 v[3];
    bool ok = true;
    for (int k = 0; k < 3 && ok; k++) {
        ok = lang_parse_vector(p, &v[k], NULL);
        if (ok)
            skip_comma(p, &ok);
    }
    if (!ok || !lang_parse_float(p, &o->coef[9], NULL))
        return false;
    for (int k = 0; k < 3; k++) {
        o->coef[3 * k] = v[k].x;
        o->coef[3 * k + 1] = v[k].y;
        o->coef[3 * k + 2] = v[k].z;
    }
    for (int k = 0; k < 10; k++)
        if (!isfinite(o->coef[k])) {
            csg_error(p->d, o->loc, "quadric coefficients must be finite numbers");
            return false;
        }
    return true;
}

/* The terms of a poly of order n: (n + 1)(n + 2)(n + 3) / 6. */
static int poly_terms(int order)
{
    return (order + 1) * (order + 2) * (order + 3) / 6;
}

/* poly { ORDER, <c0, c1, ...> }, quartic { <35 coefficients> }, cubic {
 * <20 coefficients> } (POV-Ray's Parse_Poly and Parse_Coeffs: the order
 * from 2 on, the coefficients in angle brackets, each a float, the commas
 * optional).  Orders beyond CSG_POLY_ORDER_MAX are refused (POV-Ray 3.7
 * takes up to 35; its samples use 3 to 5). */
static bool parse_poly(parser *p, csg_object *o)
{
    if (o->poly_order == 0) {
        double order;
        csg_loc at;
        bool ok = lang_parse_float(p, &order, &at);
        if (ok)
            skip_comma(p, &ok);
        if (!ok)
            return false;
        if (!(order >= 2 && order < CSG_POLY_ORDER_MAX + 1)) { /* (POV-Ray: (int)order) */
            csg_error(p->d, at, "the order of a poly must be 2 to %d, got %g", CSG_POLY_ORDER_MAX,
                      order);
            return false;
        }
        o->poly_order = (int)order;
    }
    int terms = poly_terms(o->poly_order);
    double *c = lang_alloc(p, (size_t)terms * sizeof *c);
    csg_loc open = lang_tok(p)->loc;
    if (!c)
        return false;
    if (!lang_is_punct(p, '<')) {
        csg_error(p->d, open, "'<' expected (the %d coefficients of a poly of order %d)", terms,
                  o->poly_order);
        return false;
    }
    if (!lang_enter(p, open) || !lang_next(p))
        return false;
    for (int k = 0; k < terms; k++) {
        bool ok = true;
        if (k > 0)
            skip_comma(p, &ok);
        csg_loc at = lang_tok(p)->loc;
        if (!ok || (k > 0 && lang_is_punct(p, '>'))) {
            if (ok)
                csg_error(p->d, at, "a poly of order %d has %d coefficients, got %d",
                          o->poly_order, terms, k);
            return false;
        }
        if (!lang_parse_float(p, &c[k], &at))
            return false;
        if (!isfinite(c[k])) {
            csg_error(p->d, at, "poly coefficients must be finite numbers");
            return false;
        }
    }
    if (!lang_is_punct(p, '>'))
        return lang_expected_close(p, '>', "<", open);
    lang_leave(p);
    o->poly_coef = c;
    return lang_next(p);
}

static bool parse_plane(parser *p, csg_object *o)
{
    csg_loc at;
    bool ok = lang_parse_vector(p, &o->a, &at);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !lang_parse_float(p, &o->r0, NULL))
        return false;
    double len = sqrt(o->a.x * o->a.x + o->a.y * o->a.y + o->a.z * o->a.z);
    if (!(len > 0) || !isfinite(len)) {
        csg_error(p->d, at, "plane normal must be a non-zero finite vector");
        return false;
    }
    o->a = (dvec3){o->a.x / len, o->a.y / len, o->a.z / len};
    return true;
}

/* ---- surfaces: triangle, smooth_triangle, polygon, mesh ---------------------- */

/* n vectors separated by optional commas into out[0..n); `normals`: every
 * odd one is a normal (smooth_triangle), stored in nout. */
static bool parse_points(parser *p, dvec3 *out, dvec3 *nout, int n)
{
    bool ok = true;
    for (int i = 0; ok && i < n; i++) {
        if (i > 0)
            skip_comma(p, &ok);
        if (ok)
            ok = lang_parse_vector(p, &out[i], NULL);
        if (ok && nout) {
            skip_comma(p, &ok);
            ok = ok && lang_parse_vector(p, &nout[i], NULL);
        }
    }
    return ok;
}

static bool parse_triangle(parser *p, csg_object *o)
{
    o->verts = lang_alloc(p, 3 * sizeof *o->verts);
    o->vert_count = 3;
    return o->verts && parse_points(p, o->verts, NULL, 3);
}

static bool parse_smooth_triangle(parser *p, csg_object *o)
{
    o->verts = lang_alloc(p, 3 * sizeof *o->verts);
    o->normals = lang_alloc(p, 3 * sizeof *o->normals);
    o->vert_count = 3;
    return o->verts && o->normals && parse_points(p, o->verts, o->normals, 3);
}

/* polygon { N, V1, ..., VN }: one outline (a closing copy of the first
 * vertex at the end is dropped, as POV-Ray closes it anyway). */
static bool parse_polygon(parser *p, csg_object *o)
{
    csg_loc at;
    double n;
    bool ok = lang_parse_float(p, &n, &at);
    if (ok)
        skip_comma(p, &ok);
    if (!ok)
        return false;
    if (!(n >= 3 && n <= 1000000 && n == floor(n))) {
        csg_error(p->d, at, "polygon needs a whole number of vertices from 3 to 1000000, got %g", n);
        return false;
    }
    o->vert_count = (int)n;
    o->verts = lang_alloc(p, (size_t)o->vert_count * sizeof *o->verts);
    if (!o->verts || !parse_points(p, o->verts, NULL, o->vert_count))
        return false;
    for (int i = 1; i + 1 < o->vert_count; i++) {
        if (same_point(o->verts[i], o->verts[0])) {
            csg_error(p->d, o->loc, "polygon with several outlines (vertex %d closes the first): "
                      "unsupported", i + 1);
            return false;
        }
    }
    if (o->vert_count > 3 && same_point(o->verts[o->vert_count - 1], o->verts[0]))
        o->vert_count--;
    return true;
}

static bool parse_prism(parser *p, csg_object *o) { return lang_parse_prism(p, o); }

/* mesh { (triangle { A, B, C } | smooth_triangle { A, NA, B, NB, C, NC })+ ... } */
static bool parse_mesh(parser *p, csg_object *o)
{
    vec verts = {0}, normals = {0};
    bool ok = true, smooth = false;
    while (ok && (lang_is_kw(p, CSG_KW_TRIANGLE) || lang_is_kw(p, CSG_KW_SMOOTH_TRIANGLE))) {
        bool is_smooth = lang_is_kw(p, CSG_KW_SMOOTH_TRIANGLE);
        const char *name = is_smooth ? "smooth_triangle" : "triangle";
        csg_loc open = p->tok.loc;
        dvec3 v[3], nv[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
        ok = lang_next(p) && lang_expect_open(p, name) &&
             parse_points(p, v, is_smooth ? nv : NULL, 3);
        if (ok && !lang_is_punct(p, '}'))
            ok = lang_expected_close(p, '}', name, open);
        ok = ok && lang_next(p);
        smooth = smooth || is_smooth;
        for (int k = 0; ok && k < 3; k++)
            ok = lang_vec_push(p, &verts, sizeof v[k], &v[k]) &&
                 lang_vec_push(p, &normals, sizeof nv[k], &nv[k]);
    }
    if (ok && verts.count == 0)
        ok = lang_expected(p, "a triangle or smooth_triangle expected inside 'mesh'");
    if (ok) {
        o->vert_count = verts.count;
        o->verts = vec_to_arena(p, &verts, sizeof(dvec3));
        o->normals = smooth ? vec_to_arena(p, &normals, sizeof(dvec3)) : NULL;
        ok = o->verts && (!smooth || o->normals);
    }
    free(verts.data);
    free(normals.data);
    return ok;
}

/* Called when the statement of o, begun with the textures table at `mark`
 * entries, is over and no open statement edits o's entry any more (a CSG
 * object's own modifiers come after its children and edit its own entry
 * only): when o's entry is the last one, made by that statement, and
 * equals the entry before it, o takes that one and the last is dropped.
 * Siblings written with the same pigment so share one entry instead of
 * having one each (a box minus 10^5 such spheres: 90 MB of entries, a
 * tenth of the render, issue #39).  The entry before is never edited
 * again: only an open statement may edit an entry, its own object's, and
 * none of those has its entry yet (copy-on-write, see the top comment). */
static void share_equal_texture(parser *p, csg_object *o, int mark)
{
    int last = p->textures.count - 1;
    const csg_texture *t = p->textures.data;
    if (o->texture != last || last < mark || last < 1 ||
        memcmp(&t[last], &t[last - 1], sizeof *t) != 0)
        return;
    o->texture = last - 1;
    p->textures.count = last;
}

/* The children of a CSG object, up to the first token that is not an object. */
static bool parse_children(parser *p, pnode *n, const char *name)
{
    int base = p->stack.count;
    while (lang_is_object(p)) {
        csg_object *child;
        int mark = p->textures.count;
        if (!lang_parse_object(p, &child) || !lang_vec_push(p, &p->stack, sizeof child, &child))
            return false;
        share_equal_texture(p, child, mark);
    }
    if (lang_is_kw(p, CSG_KW_LIGHT_SOURCE))
        return lang_unsupported(p, "a 'light_source' inside an object", p->tok.loc);
    int count = p->stack.count - base;
    if (count == 0) {
        char what[64];
        snprintf(what, sizeof what, "an object expected inside '%s'", name);
        return lang_expected(p, what);
    }
    csg_object **kids = lang_alloc(p, (size_t)count * sizeof *kids);
    if (!kids)
        return false;
    memcpy(kids, (csg_object **)p->stack.data + base, (size_t)count * sizeof *kids);
    p->stack.count = base;
    n->obj.children = kids;
    n->obj.child_count = count;
    for (int i = 0; i < count; i++)
        if (height_of(kids[i]) + 1 > n->height)
            n->height = height_of(kids[i]) + 1;
    if (n->height > CSG_PARSE_MAX_NESTING) {
        csg_error(p->d, n->obj.loc, "CSG tree deeper than %d levels", CSG_PARSE_MAX_NESTING);
        return false;
    }
    return true;
}

/* object { OBJECT_ID | OBJECT  ... }: the base object, a fresh copy. */
static pnode *parse_object_base(parser *p, csg_loc loc)
{
    if (lang_is_object_start(p)) {
        csg_object *inner;
        if (!lang_parse_object(p, &inner))
            return NULL;
        return (pnode *)(void *)inner;
    }
    if (!lang_is_ident(p)) {
        lang_expected(p, "an object identifier expected inside 'object'");
        return NULL;
    }
    const datum *d;
    if (!lang_lookup(p, SYM_OBJECT, "an object", &d))
        return NULL;
    return copy_tree(p, d->u.object, loc);
}

/* The object's own texture entry (copy-on-write, see the top comment). */
static csg_texture *own_texture(parser *p, csg_object *o, int mark)
{
    if (o->texture < mark) {
        csg_texture t = o->texture >= 0 ? ((csg_texture *)p->textures.data)[o->texture]
                                        : p->default_texture;
        if (!lang_vec_push(p, &p->textures, sizeof t, &t))
            return NULL;
        o->texture = p->textures.count - 1;
    }
    return (csg_texture *)p->textures.data + o->texture;
}

static csg_interior *own_interior(parser *p, csg_object *o, int mark)
{
    if (o->interior < mark) {
        csg_interior in = {1.0, 0, 0, {0, 0, 0}};
        if (o->interior >= 0)
            in = ((csg_interior *)p->interiors.data)[o->interior];
        if (!lang_vec_push(p, &p->interiors, sizeof in, &in))
            return NULL;
        o->interior = p->interiors.count - 1;
    }
    return (csg_interior *)p->interiors.data + o->interior;
}

/* pigment { }, normal { }, finish { } or texture { } on o: edits its own
 * texture entry.  As in POV-Ray, pigment, normal and finish edit the top
 * layer (an object with a texture_map gets a new default layer over it,
 * which is an error there); a texture { } is layered over the object's
 * texture (Link_Textures), or is its texture when it has none. */
static bool parse_texture_modifier(parser *p, csg_object *o, int tex_mark)
{
    csg_loc at = lang_tok(p)->loc;
    enum csg_kw kw = lang_tok(p)->kw;
    bool had = o->texture >= 0;
    csg_texture *own = own_texture(p, o, tex_mark);
    if (!own)
        return false;
    csg_texture t = *own;
    bool ok;
    if (kw == CSG_KW_TEXTURE) {
        csg_texture top;
        ok = lang_parse_texture(p, &top) && lang_texture_link(p, had ? &t : NULL, &top, &t, at);
    } else if (t.tmap_count > 0) {
        csg_error(p->d, at, "cannot layer over a patterned texture (texture_map): '%s' on an "
                            "object whose texture is one", kw == CSG_KW_PIGMENT ? "pigment"
                                                         : kw == CSG_KW_NORMAL ? "normal"
                                                                               : "finish");
        return false;
    } else {
        ok = kw == CSG_KW_PIGMENT  ? lang_parse_pigment(p, &t.pigment)
             : kw == CSG_KW_NORMAL ? lang_parse_normal(p, &t.normal)
                                   : lang_parse_finish(p, &t.finish);
    }
    if (!ok)
        return false;
    ((csg_texture *)p->textures.data)[o->texture] = t;
    return true;
}

/* material { } on o: its texture layered over o's (the material's own
 * layers starting from o's texture), its interior replacing o's. */
static bool parse_material_modifier(parser *p, csg_object *o, int tex_mark, int int_mark)
{
    lang_material m;
    memset(&m, 0, sizeof m);
    if (o->texture >= 0) {
        m.has_texture = true;
        m.texture = ((csg_texture *)p->textures.data)[o->texture];
    }
    if (o->interior >= 0) {
        m.has_interior = true;
        m.interior = ((csg_interior *)p->interiors.data)[o->interior];
    }
    if (!lang_parse_material(p, &m))
        return false;
    if (m.has_texture) {
        csg_texture *own = own_texture(p, o, tex_mark);
        if (!own)
            return false;
        *own = m.texture;
    }
    if (m.has_interior) {
        csg_interior *own = own_interior(p, o, int_mark);
        if (!own)
            return false;
        *own = m.interior;
    }
    return true;
}

/* interior_texture { TEXTURE_BODY } on o: a new entry of its own, layered
 * over the one o had (POV-Ray's Link_Textures, as for texture { }). */
static bool parse_interior_texture(parser *p, csg_object *o)
{
    csg_loc at = lang_tok(p)->loc;
    csg_texture top, t;
    const csg_texture *had =
        o->interior_texture > 0 ? (csg_texture *)p->textures.data + o->interior_texture - 1 : NULL;
    csg_texture under;
    if (had)
        under = *had; /* (the vector may move on the push below) */
    if (!lang_parse_texture(p, &top) || !lang_texture_link(p, had ? &under : NULL, &top, &t, at) ||
        !lang_vec_push(p, &p->textures, sizeof t, &t))
        return false;
    o->interior_texture = p->textures.count; /* (1 + its index) */
    return true;
}

/* interior { } on o: edits its own interior entry. */
static bool parse_interior_modifier(parser *p, csg_object *o, int int_mark)
{
    csg_interior *own = own_interior(p, o, int_mark);
    if (!own)
        return false;
    csg_interior in = *own;
    if (!lang_parse_interior(p, &in))
        return false;
    ((csg_interior *)p->interiors.data)[o->interior] = in;
    return true;
}

/* The patterned pigments of o's tree move with the transform x: every
 * node with one gets a transformed copy of its entry (they may be shared
 * with a declared object or its other copies). */
static bool transform_textures(parser *p, csg_object *o, const csg_xform *x)
{
    if (o->interior_texture > 0) {
        const csg_texture *t = (csg_texture *)p->textures.data + o->interior_texture - 1;
        if (lang_texture_patterned(t)) {
            csg_texture moved = *t;
            if (!lang_texture_transform(p, &moved, x) ||
                !lang_vec_push(p, &p->textures, sizeof moved, &moved))
                return false;
            o->interior_texture = p->textures.count;
        }
    }
    if (o->texture >= 0) {
        const csg_texture *t = (csg_texture *)p->textures.data + o->texture;
        if (lang_texture_patterned(t)) {
            csg_texture moved = *t;
            if (!lang_texture_transform(p, &moved, x) ||
                !lang_vec_push(p, &p->textures, sizeof moved, &moved))
                return false;
            o->texture = p->textures.count - 1;
        }
    }
    for (int i = 0; i < o->child_count; i++)
        if (!transform_textures(p, o->children[i], x))
            return false;
    return true;
}

static void transform_clips(csg_object *o, const csg_xform *x);

/* c, a clip or bound, moved by x with its own clips and bounds. */
static void transform_in_frame(csg_object *c, const csg_xform *x)
{
    csg_xform_then(&c->xform, x, &c->xform);
    transform_clips(c, x);
}

/* x applied to o's clips and bounds too (POV-Ray's Transform_Object), and
 * to theirs: they share o's frame, its parent's (compose_world).  (The
 * depth is the parser's nesting bound.) */
static void transform_clips(csg_object *o, const csg_xform *x)
{
    for (int i = 0; i < o->clip_count; i++)
        transform_in_frame(o->clips[i], x);
    for (int i = 0; i < o->bound_count && !o->bound_is_clip; i++)
        transform_in_frame(o->bounds[i], x);
}

bool lang_object_transform(parser *p, csg_object *o, const csg_xform *x)
{
    csg_xform_then(&o->xform, x, &o->xform);
    transform_clips(o, x);
    return transform_textures(p, o, x);
}

/* A transform modifier on o: its local transform, and its textures. */
static bool parse_object_transform(parser *p, csg_object *o)
{
    csg_xform x;
    csg_xform_identity(&x);
    if (!lang_parse_transform(p, &x))
        return false;
    csg_xform_then(&o->xform, &x, &o->xform);
    transform_clips(o, &x);
    return transform_textures(p, o, &x);
}

/* inverse, no_shadow, open or hollow [BOOL] on o (the object `name`). */
static bool parse_flag(parser *p, csg_object *o, const char *name)
{
    switch (lang_tok(p)->kw) {
    case CSG_KW_INVERSE:
        o->inverse = !o->inverse;
        break;
    case CSG_KW_NO_SHADOW:
        o->no_shadow = true;
        break;
    case CSG_KW_HOLLOW: { /* fog fills a hollow object's inside (media too, in POV-Ray) */
        double f = 1;
        if (!lang_next(p))
            return false;
        if (lang_is_expr_start(p) && !lang_parse_float(p, &f, NULL))
            return false;
        o->hollow = f > 0 ? 1 : 2;
        return true;
    }
    case CSG_KW_STURM: { /* sturm [BOOL]: the roots of a torus or a poly always come
                            from a Sturm sequence (csg/device/poly_solve.h) */
        double f = 1;
        if (o->kind != CSG_OBJ_TORUS && o->kind != CSG_OBJ_POLY) {
            csg_error(p->d, p->tok.loc,
                      "'sturm' applies only to torus, poly, quartic and cubic, not to '%s'", name);
            return false;
        }
        if (!lang_next(p))
            return false;
        return !lang_is_expr_start(p) || lang_parse_float(p, &f, NULL);
    }
    default: /* CSG_KW_OPEN */
        if (o->kind != CSG_OBJ_CYLINDER && o->kind != CSG_OBJ_CONE) {
            csg_error(p->d, p->tok.loc, "'open' applies only to cylinder and cone, not to '%s'",
                      name);
            return false;
        }
        o->open = true;
        break;
    }
    return lang_next(p);
}

static bool is_flag(parser *p)
{
    return lang_is_kw(p, CSG_KW_INVERSE) || lang_is_kw(p, CSG_KW_NO_SHADOW) ||
           lang_is_kw(p, CSG_KW_OPEN) || lang_is_kw(p, CSG_KW_HOLLOW) ||
           lang_is_kw(p, CSG_KW_STURM);
}

/* Does o's tree carry a texture (POV-Ray's TEXTURED_OBJECT, "possibly in
 * children")? */
static bool has_texture(const csg_object *o)
{
    if (o->texture >= 0)
        return true;
    for (int i = 0; i < o->child_count; i++)
        if (has_texture(o->children[i]))
            return true;
    return false;
}

/* The objects of clipped_by { } or bounded_by { } (POV-Ray's
 * Parse_Bound_Clip): at least one, none textured, then transforms that
 * apply to all of them; each in o's frame (its parent's: o's transforms so
 * far do not move it, its later ones do, transform_clips).  The list is
 * appended to *list. */
static bool parse_bound_clip(parser *p, csg_object *o, const char *name, csg_loc at,
                             csg_object ***list, int *count)
{
    int base = p->stack.count;
    while (lang_is_object(p)) {
        csg_object *c;
        csg_loc c_at = p->tok.loc;
        if (!lang_parse_object(p, &c) || !lang_vec_push(p, &p->stack, sizeof c, &c))
            return false;
        if (has_texture(c)) {
            csg_error(p->d, c_at, "illegal texture in '%s' (its objects have no surface)", name);
            return false;
        }
        if (height_of(c) + 1 > ((pnode *)(void *)o)->height)
            ((pnode *)(void *)o)->height = height_of(c) + 1;
    }
    int n = p->stack.count - base;
    if (n == 0)
        return lang_expected(p, "an object expected");
    csg_object **objs = (csg_object **)p->stack.data + base;
    while (lang_is_transform(p)) {
        csg_xform x;
        csg_xform_identity(&x);
        if (!lang_parse_transform(p, &x))
            return false;
        for (int i = 0; i < n; i++)
            transform_in_frame(objs[i], &x);
    }
    if (!lang_is_punct(p, '}'))
        return lang_expected_close(p, '}', name, at);
    csg_object **all = lang_alloc(p, (size_t)(*count + n) * sizeof *all);
    if (!all)
        return false;
    if (*count > 0)
        memcpy(all, *list, (size_t)*count * sizeof *all);
    for (int i = 0; i < n; i++)
        all[*count + i] = objs[i];
    p->stack.count = base;
    *list = all;
    *count += n;
    if (((pnode *)(void *)o)->height > CSG_PARSE_MAX_NESTING) {
        csg_error(p->d, o->loc, "CSG tree deeper than %d levels", CSG_PARSE_MAX_NESTING);
        return false;
    }
    return lang_next(p);
}

/* bounded_by { OBJECT... } or bounded_by { clipped_by }, and clipped_by
 * { OBJECT... } or clipped_by { bounded_by }: POV-Ray's Parse_Object_Mods,
 * its errors included.  Linked, the bound is the clip (bound_is_clip). */
static bool parse_bound_or_clip(parser *p, csg_object *o)
{
    bool clip = lang_is_kw(p, CSG_KW_CLIPPED_BY);
    const char *name = clip ? "clipped_by" : "bounded_by";
    csg_loc at = p->tok.loc;
    if (!lang_next(p) || !lang_expect_open(p, name))
        return false;
    int own = clip ? o->clip_count : o->bound_count;
    if (own > 0 && o->bound_is_clip) {
        csg_error(p->d, at, clip ? "cannot add clips after linking bounds and clips"
                                 : "cannot add bounds after linking bounds and clips");
        return false;
    }
    if (lang_is_kw(p, clip ? CSG_KW_BOUNDED_BY : CSG_KW_CLIPPED_BY)) {
        if (own > 0) {
            csg_error(p->d, at, clip ? "cannot link bounds with previous clips"
                                     : "cannot link clips with previous bounds");
            return false;
        }
        if (clip) {
            o->clips = o->bounds;
            o->clip_count = o->bound_count;
        } else {
            o->bounds = o->clips;
            o->bound_count = o->clip_count;
        }
        o->bound_is_clip = o->clip_count > 0; /* (linking nothing is nothing) */
        if (!lang_next(p))
            return false;
        if (!lang_is_punct(p, '}'))
            return lang_expected_close(p, '}', name, at);
        return lang_next(p);
    }
    return clip ? parse_bound_clip(p, o, name, at, &o->clips, &o->clip_count)
                : parse_bound_clip(p, o, name, at, &o->bounds, &o->bound_count);
}

/* Modifiers up to and including the closing brace. */
static bool parse_modifiers(parser *p, csg_object *o, const char *name, csg_loc open, int tex_mark,
                            int int_mark)
{
    for (;;) {
        if (lang_is_punct(p, '}')) {
            if (o->interior_texture > 0 && o->texture < 0) { /* (POV-Ray's rule) */
                csg_error(p->d, open, "interior_texture needs a texture on the %s itself", name);
                return false;
            }
            return lang_next(p);
        }
        bool ok;
        if (lang_is_transform(p))
            ok = parse_object_transform(p, o);
        else if (lang_is_kw(p, CSG_KW_PIGMENT) || lang_is_kw(p, CSG_KW_FINISH) ||
                 lang_is_kw(p, CSG_KW_TEXTURE) || lang_is_kw(p, CSG_KW_NORMAL))
            ok = parse_texture_modifier(p, o, tex_mark);
        else if (lang_is_kw(p, CSG_KW_MATERIAL))
            ok = parse_material_modifier(p, o, tex_mark, int_mark);
        else if (lang_is_kw(p, CSG_KW_INTERIOR))
            ok = parse_interior_modifier(p, o, int_mark);
        else if (lang_is_kw(p, CSG_KW_INTERIOR_TEXTURE))
            ok = parse_interior_texture(p, o);
        else if (is_flag(p))
            ok = parse_flag(p, o, name);
        else if (lang_is_kw(p, CSG_KW_BOUNDED_BY) || lang_is_kw(p, CSG_KW_CLIPPED_BY))
            ok = parse_bound_or_clip(p, o);
        else
            return lang_expected_close(p, '}', name, open);
        if (!ok)
            return false;
    }
}

/* What follows the brace of a new object: a shape's parameters (one
 * parse_<name> a shape kind) or an operator's children. */
static bool parse_body(parser *p, pnode *n, const char *name)
{
    switch (n->obj.kind) {
#define PARSE_SHAPE(ID, name_)                                                                     \
    case CSG_OBJ_##ID:                                                                             \
        return parse_##name_(p, &n->obj);
#define PARSE_OPERATOR(ID, name_)                                                                  \
    case CSG_OBJ_##ID:                                                                             \
        return parse_children(p, n, name);
        CSG_OBJECT_KINDS(PARSE_SHAPE, PARSE_OPERATOR)
    default:
        return false;
    }
}

/* Any object statement; the current token is its keyword. */
/* A declared object's bare name where an object stands: a fresh copy, as
 * `object { NAME }` without modifiers (POV-Ray's Parse_Object takes an
 * OBJECT_ID there: a statement, a CSG child, looks_like). */
static bool parse_object_name(parser *p, csg_object **out)
{
    csg_loc loc = lang_tok(p)->loc;
    const datum *d;
    if (!lang_lookup(p, SYM_OBJECT, "an object", &d))
        return false;
    pnode *n = copy_tree(p, d->u.object, loc);
    if (!n)
        return false;
    *out = &n->obj;
    return true;
}

bool lang_is_object(parser *p)
{
    return lang_is_object_start(p) || lang_names(p, SYM_OBJECT);
}

bool lang_parse_object(parser *p, csg_object **out)
{
    if (lang_is_ident(p))
        return parse_object_name(p, out);
    const csg_token *t = lang_tok(p);
    csg_loc loc = t->loc;
    enum csg_kw kw = t->kw;
    const char *name = object_name(kw);
    int tex_mark = p->textures.count, int_mark = p->interiors.count;
    if (!lang_enter(p, loc) || !lang_next(p) || !lang_expect_open(p, name))
        return false;
    int kind = kind_of_keyword(kw);
    pnode *n;
    bool ok;
    if (kw == CSG_KW_TEXT) { /* the union of its glyphs, each a prism */
        n = new_node(p, CSG_OBJ_UNION, loc);
        ok = n && lang_parse_text(p, &n->obj);
        if (ok)
            n->height = 2;
    } else {
        n = kind >= 0 ? new_node(p, (enum csg_object_kind)kind, loc) : parse_object_base(p, loc);
        if (n && kind == CSG_OBJ_POLY) /* poly reads its order */
            n->obj.poly_order = kw == CSG_KW_QUARTIC ? 4 : kw == CSG_KW_CUBIC ? 3 : 0;
        ok = n && (kind < 0 || parse_body(p, n, name));
    }
    if (!ok || !parse_modifiers(p, &n->obj, name, loc, tex_mark, int_mark))
        return false;
    lang_leave(p);
    *out = &n->obj;
    return true;
}

/* ---- the camera ------------------------------------------------------------------ */

/* cylinder N (1 to 4), ultra_wide_angle, panoramic, spherical: POV-Ray's
 * Parse_Camera. */
static bool parse_camera_type(parser *p, csg_camera_src *c, enum csg_kw kw)
{
    csg_loc at = p->tok.loc;
    if (!lang_next(p))
        return false;
    if (kw == CSG_KW_CYLINDER) {
        double n;
        if (!lang_parse_float(p, &n, &at))
            return false;
        if (!(n >= 1 && n < 5)) { /* (POV-Ray: (int)n) */
            csg_error(p->d, at, "invalid cylinder camera type %g: the types are 1 to 4", n);
            return false;
        }
        c->projection = CSG_PROJ_CYLINDER_1 + ((int)n - 1);
        return true;
    }
    c->projection = kw == CSG_KW_ULTRA_WIDE_ANGLE ? CSG_PROJ_ULTRA_WIDE_ANGLE
                    : kw == CSG_KW_PANORAMIC      ? CSG_PROJ_PANORAMIC
                                                  : CSG_PROJ_SPHERICAL;
    return true;
}

/* angle of a camera that is not planar: A (cylinder, ultra_wide_angle,
 * panoramic: kept), or H [, V] (spherical: V is H / 2 unless given);
 * POV-Ray refuses negative angles. */
static bool parse_camera_angles(parser *p, csg_camera_src *c, csg_camera_mods *m, csg_loc at)
{
    double f;
    csg_loc fat;
    if (!lang_next(p) || !lang_parse_float(p, &f, &fat))
        return false;
    if (!(f >= 0)) {
        csg_error(p->d, fat, "a camera's angle must not be negative, got %g", f);
        return false;
    }
    m->has_angle = true;
    m->angle = f;
    m->angle_loc = at;
    c->angle = f;
    if (c->projection != CSG_PROJ_SPHERICAL)
        return true;
    c->h_angle = f;
    c->v_angle = f * 0.5;
    bool comma = lang_is_punct(p, ',');
    if (comma && !lang_next(p))
        return false;
    if (!comma && lang_tok(p)->kind != CSG_TOK_NUMBER)
        return true;
    if (!lang_parse_float(p, &f, &fat))
        return false;
    if (!(f >= 0)) {
        csg_error(p->d, fat, "a camera's vertical angle must not be negative, got %g", f);
        return false;
    }
    c->v_angle = f;
    return true;
}

/* One camera item; *m collects what POV-Ray 3.5+ applies at the end, or
 * (old: #version < 3.5) everything is applied at once. */
static bool parse_camera_item(parser *p, csg_camera_src *c, csg_camera_mods *m, bool old)
{
    enum csg_kw kw = lang_tok(p)->kw;
    csg_loc at = p->tok.loc;
    dvec3 v;
    if (kw == CSG_KW_PERSPECTIVE || kw == CSG_KW_ORTHOGRAPHIC) {
        c->projection = kw == CSG_KW_PERSPECTIVE ? CSG_PROJ_PERSPECTIVE : CSG_PROJ_ORTHOGRAPHIC;
        if (old && kw == CSG_KW_ORTHOGRAPHIC)
            csg_camera_orthographic_size(c);
        return lang_next(p);
    }
    if (kw == CSG_KW_CYLINDER || kw == CSG_KW_ULTRA_WIDE_ANGLE || kw == CSG_KW_PANORAMIC ||
        kw == CSG_KW_SPHERICAL)
        return parse_camera_type(p, c, kw);
    if (kw == CSG_KW_ANGLE && !csg_camera_planar(c))
        return parse_camera_angles(p, c, m, at);
    if (kw == CSG_KW_ANGLE) { /* orthographic: the angle may be left out */
        double f = 0;
        if (!lang_next(p))
            return false;
        bool bare = c->projection == CSG_PROJ_ORTHOGRAPHIC && !lang_is_expr_start(p);
        if (!bare && !lang_parse_float(p, &f, NULL))
            return false;
        m->has_angle = true;
        m->angle = f;
        m->angle_loc = at;
        return !old || c->projection != CSG_PROJ_PERSPECTIVE || csg_camera_angle(c, f, at, p->d);
    }
    if (lang_is_transform(p)) {
        csg_xform x;
        csg_xform_identity(&x);
        if (!lang_parse_transform(p, &x))
            return false;
        if (old)
            csg_camera_transform(c, &x);
        csg_xform_then(&m->xform, &x, &m->xform);
        m->has_xform = !old;
        return true;
    }
    if (!lang_next(p) || !lang_parse_vector(p, &v, NULL))
        return false;
    switch (kw) {
    case CSG_KW_LOCATION: c->location = v; break;
    case CSG_KW_DIRECTION: c->direction = v; break;
    case CSG_KW_UP: c->up = v; m->has_up = true; break;
    case CSG_KW_RIGHT: c->right = v; m->has_right = true; break;
    case CSG_KW_SKY: c->sky = v; break;
    default: /* CSG_KW_LOOK_AT */
        if (old)
            return csg_camera_look_at(c, v, at, p->d);
        m->has_look_at = true;
        m->look_at = v;
        m->look_at_loc = at;
        break;
    }
    return true;
}

static bool is_camera_item(parser *p)
{
    switch (lang_tok(p)->kind == CSG_TOK_WORD ? p->tok.kw : CSG_KW_NONE) {
    case CSG_KW_CYLINDER: case CSG_KW_ULTRA_WIDE_ANGLE: case CSG_KW_PANORAMIC:
    case CSG_KW_SPHERICAL:
    case CSG_KW_PERSPECTIVE: case CSG_KW_ORTHOGRAPHIC: case CSG_KW_ANGLE: case CSG_KW_LOCATION:
    case CSG_KW_LOOK_AT: case CSG_KW_DIRECTION: case CSG_KW_UP: case CSG_KW_RIGHT: case CSG_KW_SKY:
        return true;
    default:
        return lang_is_transform(p);
    }
}

/* camera { [CAMERA_ID] ITEMS }: a camera identifier takes transforms only
 * (POV-Ray 3.5+). */
bool lang_parse_camera(parser *p, csg_camera_src *c)
{
    csg_loc open = lang_tok(p)->loc;
    bool old = p->version < 3.5, from_id = false;
    csg_camera_mods m;
    csg_camera_mods_init(&m);
    if (!lang_next(p) || !lang_expect_open(p, "camera"))
        return false;
    if (lang_names(p, SYM_CAMERA)) {
        const datum *d;
        if (!lang_lookup(p, SYM_CAMERA, "a camera", &d))
            return false;
        *c = d->u.camera;
        from_id = !old;
    }
    c->loc = open;
    while (!lang_is_punct(p, '}')) {
        if (!is_camera_item(p) || (from_id && !lang_is_transform(p)))
            return lang_expected_close(p, '}', "camera", open);
        if (!parse_camera_item(p, c, &m, old))
            return false;
    }
    if (from_id) { /* POV-Ray: a declared camera's copy takes its transforms only (its
                    * look_at, angle and orthographic sizing were applied once already) */
        if (m.has_xform)
            csg_camera_transform(c, &m.xform);
        return lang_next(p);
    }
    return (old || csg_camera_apply(c, &m, p->d)) && lang_next(p);
}

/* ---- statements ---------------------------------------------------------------- */

static bool parse_camera_statement(parser *p)
{
    csg_camera_src c;
    csg_camera_default(&c);
    if (!lang_parse_camera(p, &c))
        return false;
    p->s->camera = c;
    p->s->has_camera = true;
    return true;
}

static int default_texture_entry(parser *p);

/* One float item of a light (tightness, radius, falloff, fade_distance,
 * fade_power); the spotlight and cylinder ones need that kind (POV-Ray's
 * Not_With). */
static bool parse_light_float(parser *p, csg_light *l)
{
    enum csg_kw kw = lang_tok(p)->kw;
    csg_loc at = lang_tok(p)->loc;
    bool shaped = kw == CSG_KW_TIGHTNESS || kw == CSG_KW_RADIUS || kw == CSG_KW_FALLOFF;
    if (shaped && l->kind == CSG_LIGHT_POINT) {
        csg_error(p->d, at, "'%.*s' needs a spotlight or a cylinder light", (int)lang_tok(p)->len,
                  lang_tok(p)->text);
        return false;
    }
    double f;
    if (!lang_next(p) || !lang_parse_float(p, &f, NULL))
        return false;
    switch (kw) {
    case CSG_KW_TIGHTNESS: l->tightness = f; break;
    case CSG_KW_RADIUS: l->radius = l->kind == CSG_LIGHT_SPOT ? cos(f * M_PI / 180) : f; break;
    case CSG_KW_FALLOFF: l->falloff = l->kind == CSG_LIGHT_SPOT ? cos(f * M_PI / 180) : f; break;
    case CSG_KW_FADE_DISTANCE: l->fade_distance = f; break;
    default: l->fade_power = f; break;
    }
    return true;
}

/* area_light AXIS1, AXIS2, SIZE1, SIZE2 (sizes truncated, >= 1). */
static bool parse_area_light(parser *p, csg_light *l)
{
    bool ok = true;
    double s1, s2;
    csg_loc at1, at2;
    if (!lang_next(p) || !lang_parse_vector(p, &l->axis1, NULL))
        return false;
    skip_comma(p, &ok);
    if (!ok || !lang_parse_vector(p, &l->axis2, NULL))
        return false;
    skip_comma(p, &ok);
    if (!ok || !lang_parse_float(p, &s1, &at1))
        return false;
    skip_comma(p, &ok);
    if (!ok || !lang_parse_float(p, &s2, &at2))
        return false;
    if (!(s1 >= 1 && s1 < 1e6) || !(s2 >= 1 && s2 < 1e6) || (int)s1 * (int)s2 > 65536) {
        csg_error(p->d, (s1 >= 1 && s1 < 1e6) ? at2 : at1,
                  "area_light sizes must be whole numbers from 1 up, at most 65536 points, got %g "
                  "and %g", s1, s2);
        return false;
    }
    l->area = true;
    l->size1 = (int)s1;
    l->size2 = (int)s2;
    return true;
}

/* looks_like { OBJECT }: an object at the light (translated to it, moved
 * by the light's later transforms) that casts no shadow. */
static bool parse_looks_like(parser *p, const csg_light *l, csg_object **out)
{
    csg_loc open = lang_tok(p)->loc;
    if (*out) {
        csg_error(p->d, open, "only one looks_like allowed per light_source");
        return false;
    }
    if (!lang_next(p) || !lang_expect_open(p, "looks_like"))
        return false;
    if (!lang_is_object(p))
        return lang_expected(p, "an object expected inside 'looks_like'");
    csg_object *o;
    if (!lang_parse_object(p, &o))
        return false;
    if (!lang_is_punct(p, '}'))
        return lang_expected_close(p, '}', "looks_like", open);
    csg_xform t;
    csg_xform_identity(&t);
    csg_xform_translate(&t, l->position);
    if (!lang_object_transform(p, o, &t))
        return false;
    o->no_shadow = true;
    *out = o;
    return lang_next(p);
}

static bool parse_light(parser *p)
{
    csg_light l;
    memset(&l, 0, sizeof l);
    l.loc = lang_tok(p)->loc;
    l.point_at = (dvec3){0, 0, 1};
    l.axis1 = (dvec3){0, 0, 1};
    l.axis2 = (dvec3){0, 1, 0};
    l.adaptive = 100;
    csg_object *looks = NULL;
    csg_xform x;
    csg_xform_identity(&x);
    bool ok = lang_next(p) && lang_expect_open(p, "light_source") &&
              lang_parse_vector(p, &l.position, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok)
        return false;
    if (!lang_is_color_start(p))
        return lang_expected(p, "a color expected for the light_source");
    if (!lang_parse_rgb(p, l.color))
        return false;
    for (;;) {
        if (lang_is_punct(p, '}'))
            break;
        enum csg_kw kw = lang_tok(p)->kw;
        bool flag = false;
        if (lang_tok(p)->kind != CSG_TOK_WORD)
            kw = CSG_KW_NONE;
        switch (kw) {
        case CSG_KW_TRANSLATE: case CSG_KW_ROTATE: case CSG_KW_SCALE: case CSG_KW_MATRIX:
        case CSG_KW_TRANSFORM: {
            csg_xform t;
            csg_xform_identity(&t);
            if (!lang_parse_transform(p, &t))
                return false;
            csg_xform_then(&x, &t, &x);
            if (looks && !lang_object_transform(p, looks, &t))
                return false;
            continue;
        }
        case CSG_KW_SHADOWLESS: l.shadowless = true; flag = true; break;
        case CSG_KW_SPOTLIGHT: /* POV-Ray's defaults: radius 30, falloff 45 degrees */
            l.kind = CSG_LIGHT_SPOT;
            l.radius = cos(30 * M_PI / 180);
            l.falloff = cos(45 * M_PI / 180);
            l.tightness = 0;
            flag = true;
            break;
        case CSG_KW_CYLINDER:
            l.kind = CSG_LIGHT_CYLINDER;
            l.radius = 0.75;
            l.falloff = 1;
            l.tightness = 0;
            l.parallel = true;
            flag = true;
            break;
        case CSG_KW_PARALLEL: l.parallel = true; flag = true; break;
        case CSG_KW_JITTER: l.jitter = true; flag = true; break;
        case CSG_KW_CIRCULAR: l.circular = true; flag = true; break;
        case CSG_KW_ORIENT: l.orient = true; flag = true; break;
        case CSG_KW_POINT_AT:
            if (l.kind == CSG_LIGHT_POINT && !l.parallel) {
                csg_error(p->d, lang_tok(p)->loc,
                          "'point_at' needs a spotlight, a cylinder or a parallel light");
                return false;
            }
            if (!lang_next(p) || !lang_parse_vector(p, &l.point_at, NULL))
                return false;
            continue;
        case CSG_KW_TIGHTNESS: case CSG_KW_RADIUS: case CSG_KW_FALLOFF: case CSG_KW_FADE_DISTANCE:
        case CSG_KW_FADE_POWER:
            if (!parse_light_float(p, &l))
                return false;
            continue;
        case CSG_KW_AREA_LIGHT:
            if (!parse_area_light(p, &l))
                return false;
            continue;
        case CSG_KW_ADAPTIVE: {
            double f;
            if (!lang_next(p) || !lang_parse_float(p, &f, NULL))
                return false;
            l.adaptive = f < 0 ? 0 : f > 100 ? 100 : (int)f;
            continue;
        }
        case CSG_KW_MEDIA_ATTENUATION: case CSG_KW_MEDIA_INTERACTION: {
            double f = 1;
            csg_loc at = lang_tok(p)->loc;
            if (!lang_next(p) || (lang_is_expr_start(p) && !lang_parse_float(p, &f, NULL)))
                return false;
            /* POV-Ray fogs a shadow ray piece by piece between the
             * transparent surfaces it crosses (the turbulence and the
             * transmit floor per piece): not done yet */
            if (kw == CSG_KW_MEDIA_ATTENUATION && f > 0)
                return lang_unsupported(p, "'media_attenuation on'", at);
            continue;
        }
        case CSG_KW_LOOKS_LIKE:
            if (!parse_looks_like(p, &l, &looks))
                return false;
            continue;
        default:
            return lang_expected_close(p, '}', "light_source", l.loc);
        }
        if (flag && !lang_next(p))
            return false;
    }
    if (l.area && l.circular && (l.size1 <= 1 || l.size2 <= 1)) {
        csg_error(p->d, l.loc, "a circular area light must have more than 1 point per axis");
        return false;
    }
    dvec3 q = l.position, a = l.point_at;
    l.position = (dvec3){x.m[0][0] * q.x + x.m[0][1] * q.y + x.m[0][2] * q.z + x.m[0][3],
                         x.m[1][0] * q.x + x.m[1][1] * q.y + x.m[1][2] * q.z + x.m[1][3],
                         x.m[2][0] * q.x + x.m[2][1] * q.y + x.m[2][2] * q.z + x.m[2][3]};
    l.point_at = (dvec3){x.m[0][0] * a.x + x.m[0][1] * a.y + x.m[0][2] * a.z + x.m[0][3],
                         x.m[1][0] * a.x + x.m[1][1] * a.y + x.m[1][2] * a.z + x.m[1][3],
                         x.m[2][0] * a.x + x.m[2][1] * a.y + x.m[2][2] * a.z + x.m[2][3]};
    for (int k = 0; k < 2; k++) {
        dvec3 *v = k ? &l.axis2 : &l.axis1, d = *v;
        *v = (dvec3){x.m[0][0] * d.x + x.m[0][1] * d.y + x.m[0][2] * d.z,
                     x.m[1][0] * d.x + x.m[1][1] * d.y + x.m[1][2] * d.z,
                     x.m[2][0] * d.x + x.m[2][1] * d.y + x.m[2][2] * d.z};
    }
    if (looks) {
        if (looks->texture < 0 && (looks->texture = default_texture_entry(p)) < 0)
            return false;
        if (!lang_vec_push(p, &p->objects, sizeof looks, &looks))
            return false;
    }
    return lang_vec_push(p, &p->lights, sizeof l, &l) && lang_next(p);
}

/* A fog's up, turned by its transforms: finite and not 0 (a ground fog
 * measures heights along it). */
static bool fog_up_usable(dvec3 u)
{
    return isfinite(u.x) && isfinite(u.y) && isfinite(u.z) && (u.x != 0 || u.y != 0 || u.z != 0);
}

/* fog { fog_type I distance F COLOR turbulence V octaves I omega F lambda F
 * turb_depth F fog_offset F fog_alt F up V TRANSFORMS }: POV-Ray's
 * Parse_Fog (the transforms turn `up`; a translate does nothing). */
static bool parse_fog(parser *p)
{
    csg_loc open = lang_tok(p)->loc;
    if (p->s->fog_count == CSG_FOG_MAX) {
        csg_error(p->d, open, "a scene has at most %d fogs", CSG_FOG_MAX);
        return false;
    }
    if (!lang_next(p) || !lang_expect_open(p, "fog"))
        return false;
    csg_fog f;
    memset(&f, 0, sizeof f);
    f.kind = CSG_FOG_CONSTANT;
    f.up = (dvec3){0, 1, 0};
    f.turb.octaves = 6;
    f.turb.omega = 0.5;
    f.turb.lambda = 2.0;
    f.turb_depth = 0.5;
    for (;;) {
        if (lang_is_punct(p, '}'))
            break;
        enum csg_kw kw = lang_tok(p)->kind == CSG_TOK_WORD ? lang_tok(p)->kw : CSG_KW_NONE;
        csg_loc at = lang_tok(p)->loc;
        double v;
        bool ok = true;
        if (lang_is_color_start(p) && (kw == CSG_KW_COLOR || lang_is_color_item(p))) {
            ok = lang_parse_color(p, f.rgbft);
        } else if (kw == CSG_KW_UP) {
            ok = lang_next(p) && lang_parse_vector(p, &f.up, NULL);
        } else if (kw == CSG_KW_TURBULENCE) {
            f.turb.on = true;
            ok = lang_next(p) && lang_parse_vector(p, &f.turb.amount, NULL);
        } else if (kw == CSG_KW_ROTATE || kw == CSG_KW_SCALE || kw == CSG_KW_MATRIX ||
                   kw == CSG_KW_TRANSLATE || kw == CSG_KW_TRANSFORM) {
            csg_xform x;
            csg_xform_identity(&x);
            ok = lang_parse_transform(p, &x);
            dvec3 u = f.up;
            if (kw != CSG_KW_TRANSLATE)
                f.up = (dvec3){x.m[0][0] * u.x + x.m[0][1] * u.y + x.m[0][2] * u.z,
                               x.m[1][0] * u.x + x.m[1][1] * u.y + x.m[1][2] * u.z,
                               x.m[2][0] * u.x + x.m[2][1] * u.y + x.m[2][2] * u.z};
            if (ok && !fog_up_usable(f.up)) {
                csg_error(p->d, at, "the fog's up vector overflows or collapses to 0 here");
                return false;
            }
        } else if (kw == CSG_KW_FOG_TYPE || kw == CSG_KW_DISTANCE || kw == CSG_KW_OCTAVES ||
                   kw == CSG_KW_OMEGA || kw == CSG_KW_LAMBDA || kw == CSG_KW_TURB_DEPTH ||
                   kw == CSG_KW_FOG_OFFSET || kw == CSG_KW_FOG_ALT) {
            if (!lang_next(p) || !lang_parse_float(p, &v, &at))
                return false;
            switch (kw) {
            case CSG_KW_FOG_TYPE:
                if (!(v == 1 || v == 2)) {
                    csg_error(p->d, at, "fog_type must be 1 (constant) or 2 (ground), got %g", v);
                    return false;
                }
                f.kind = (int)v;
                break;
            case CSG_KW_DISTANCE: f.distance = v; break;
            case CSG_KW_OCTAVES:
                f.turb.on = true;
                f.turb.octaves = v < 1 ? 1 : v > 10 ? 10 : (int)v; /* POV-Ray clamps */
                break;
            case CSG_KW_OMEGA: f.turb.on = true; f.turb.omega = v; break;
            case CSG_KW_LAMBDA: f.turb.on = true; f.turb.lambda = v; break;
            case CSG_KW_TURB_DEPTH: f.turb_depth = v; break;
            case CSG_KW_FOG_OFFSET: f.offset = v; break;
            default: f.alt = v; break;
            }
        } else if (lang_is_expr_start(p)) { /* POV-Ray: a bare float is the distance,
                                               * a colour (Blue + Gray70) the colour */
            value e;
            ok = lang_parse_expr(p, &e);
            if (ok && e.dim == 1) {
                f.distance = e.v[0];
            } else if (ok && e.dim >= 3) {
                for (int i = 0; i < 5; i++)
                    f.rgbft[i] = e.v[i];
            } else if (ok) {
                csg_error(p->d, at, "a fog's distance or colour expected, got %s",
                          lang_dim_name(e.dim));
                return false;
            }
        } else {
            return lang_expected_close(p, '}', "fog", open);
        }
        if (!ok)
            return false;
    }
    double len = sqrt(f.up.x * f.up.x + f.up.y * f.up.y + f.up.z * f.up.z);
    if (!(len > 0)) {
        csg_error(p->d, open, "fog up vector must not be zero");
        return false;
    }
    if (!isfinite(len)) { /* (the flattener divides by it) */
        csg_error(p->d, open, "fog up vector is too long: its length overflows");
        return false;
    }
    /* (kept as given: the flattener normalises it, so an exported scene,
     * its up already of length 1, re-parses to the same numbers) */
    if (f.kind == CSG_FOG_GROUND && f.alt == 0) {
        csg_error(p->d, open, "a ground fog (fog_type 2) needs fog_alt other than 0");
        return false;
    }
    p->s->fogs[p->s->fog_count++] = f;
    return lang_next(p);
}

static bool parse_background(parser *p)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !lang_expect_open(p, "background"))
        return false;
    if (!lang_is_color_start(p))
        return lang_expected(p, "a color expected inside 'background'");
    if (!lang_parse_color(p, p->s->background))
        return false;
    if (!lang_is_punct(p, '}'))
        return lang_expected_close(p, '}', "background", open);
    return lang_next(p);
}

/* assumed_gamma F | srgb: POV-Ray's working gamma.  The first one counts;
 * POV-Ray ignores a later one (with a warning, as here). */
static bool parse_assumed_gamma(parser *p, csg_globals *g)
{
    csg_loc at = lang_tok(p)->loc;
    int kind = CSG_GAMMA_SRGB;
    double f = 1.0;
    if (lang_is_kw(p, CSG_KW_SRGB)) {
        if (!lang_next(p))
            return false;
    } else {
        if (!lang_parse_float(p, &f, &at))
            return false;
        if (!(f > 0)) {
            csg_error(p->d, at, "assumed_gamma must be > 0, got %g", f);
            return false;
        }
        kind = CSG_GAMMA_POWER;
    }
    if (g->gamma_kind != CSG_GAMMA_UNSET) {
        if (p->opt.messages)
            fprintf(p->opt.messages, "%s:%d:%d: warning: a second assumed_gamma is ignored, "
                                     "as in POV-Ray\n", at.file, at.line, at.col);
        return true;
    }
    g->gamma_kind = kind;
    g->assumed_gamma = f;
    return true;
}

static bool parse_global_settings(parser *p)
{
    csg_loc open = lang_tok(p)->loc;
    csg_globals *g = &p->s->globals;
    if (!lang_next(p) || !lang_expect_open(p, "global_settings"))
        return false;
    for (;;) {
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        enum csg_kw kw = lang_tok(p)->kind == CSG_TOK_WORD ? p->tok.kw : CSG_KW_NONE;
        csg_loc at;
        double f;
        switch (kw) {
        case CSG_KW_AMBIENT_LIGHT:
            if (!lang_next(p) || !lang_parse_rgb(p, g->ambient_light))
                return false;
            continue;
        case CSG_KW_ASSUMED_GAMMA:
            if (!lang_next(p) || !parse_assumed_gamma(p, g))
                return false;
            continue;
        case CSG_KW_IRID_WAVELENGTH: /* a colour, kept in floats as POV-Ray's */
            at = lang_tok(p)->loc;
            if (!lang_next(p) || !lang_parse_rgb(p, g->irid_wavelength))
                return false;
            for (int i = 0; i < 3; i++)
                if (!lang_single_float(p, g->irid_wavelength[i], at, "irid_wavelength",
                                       &g->irid_wavelength[i]))
                    return false;
            continue;
        case CSG_KW_MAX_TRACE_LEVEL: case CSG_KW_ADC_BAILOUT:
        case CSG_KW_NOISE_GENERATOR: case CSG_KW_NUMBER_OF_WAVES:
            if (!lang_next(p) || !lang_parse_float(p, &f, &at))
                return false;
            break;
        default:
            return lang_expected_close(p, '}', "global_settings", open);
        }
        if (kw == CSG_KW_NUMBER_OF_WAVES) {
            if (!(f >= 1 && f <= CSG_MAX_WAVES)) { /* POV-Ray: changed to 1 below 1 */
                csg_error(p->d, at, "number_of_waves must be from 1 to %d, got %g", CSG_MAX_WAVES, f);
                return false;
            }
            g->number_of_waves = (int)f;
        } else if (kw == CSG_KW_NOISE_GENERATOR) {
            if (!(f == 1 || f == 2 || f == 3)) { /* POV-Ray: 1, 2 or 3 here */
                csg_error(p->d, at, "noise_generator must be 1, 2 or 3, got %g", f);
                return false;
            }
            g->noise_generator = (int)f;
        } else if (kw == CSG_KW_ADC_BAILOUT) {
            if (!(f >= 0 && f <= 1)) {
                csg_error(p->d, at, "adc_bailout must be between 0 and 1, got %g", f);
                return false;
            }
            g->adc_bailout = f;
        } else {
            if (!(f >= 1 && f <= 256 && f == floor(f))) {
                csg_error(p->d, at, "max_trace_level must be an integer from 1 to 256, got %g", f);
                return false;
            }
            g->max_trace_level = (int)f;
        }
    }
}

/* The default texture in force now, as an entry of the table (one entry
 * for each #default state). */
static int default_texture_entry(parser *p)
{
    const csg_texture *t = p->textures.data;
    if (p->default_entry >= 0 &&
        memcmp(&t[p->default_entry], &p->default_texture, sizeof p->default_texture) == 0)
        return p->default_entry;
    if (!lang_vec_push(p, &p->textures, sizeof p->default_texture, &p->default_texture))
        return -1;
    return p->default_entry = p->textures.count - 1;
}

/* A top-level object: it gets the default texture now when it has none. */
static bool parse_top_object(parser *p)
{
    csg_object *o;
    int mark = p->textures.count;
    if (!lang_parse_object(p, &o))
        return false;
    share_equal_texture(p, o, mark);
    if (o->texture < 0 && (o->texture = default_texture_entry(p)) < 0)
        return false;
    return lang_vec_push(p, &p->objects, sizeof o, &o);
}

static bool parse_statement(parser *p)
{
    if (lang_is_object(p))
        return parse_top_object(p);
    if (p->tok.kind == CSG_TOK_WORD) {
        switch (p->tok.kw) {
        case CSG_KW_DEFAULT: return lang_next(p) && lang_default(p, p->tok.loc); /* no '#' */
        case CSG_KW_CAMERA: return parse_camera_statement(p);
        case CSG_KW_LIGHT_SOURCE: return parse_light(p);
        case CSG_KW_BACKGROUND: return parse_background(p);
        case CSG_KW_FOG: return parse_fog(p);
        case CSG_KW_SKY_SPHERE: return lang_parse_sky_sphere(p, &p->s->sky);
        case CSG_KW_GLOBAL_SETTINGS: return parse_global_settings(p);
        default: break;
        }
    }
    return lang_expected(p, "an object or a statement expected");
}

bool lang_parse_statements(parser *p)
{
    while (lang_tok(p)->kind != CSG_TOK_EOF)
        if (!parse_statement(p))
            return false;
    return !p->d->failed;
}

/* ---- the end of the parse ------------------------------------------------------ */

static void compose_world(csg_object *o, const csg_xform *parent)
{
    if (parent)
        csg_xform_then(&o->xform, parent, &o->xform);
    for (int i = 0; i < o->child_count; i++)
        compose_world(o->children[i], &o->xform);
    /* clips and bounds are in o's frame, its parent's (transform_clips) */
    for (int i = 0; i < o->clip_count; i++)
        compose_world(o->clips[i], parent);
    for (int i = 0; i < o->bound_count && !o->bound_is_clip; i++)
        compose_world(o->bounds[i], parent);
}

static bool finish_scene(parser *p)
{
    csg_scene *s = p->s;
    csg_object **top = p->objects.data;
    for (int i = 0; i < p->objects.count; i++) {
        compose_world(top[i], NULL);
        if (top[i]->interior < 0) {
            csg_interior in = {1.0, 0, 0, {0, 0, 0}};
            if (!lang_vec_push(p, &p->interiors, sizeof in, &in))
                return false;
            top[i]->interior = p->interiors.count - 1;
            for (int j = i + 1; j < p->objects.count; j++)
                if (top[j]->interior < 0)
                    top[j]->interior = top[i]->interior;
        }
    }
    s->version = p->version;
    s->object_count = p->objects.count; /* before vec_to_arena, which may empty them */
    s->texture_count = p->textures.count;
    s->interior_count = p->interiors.count;
    s->light_count = p->lights.count;
    s->objects = vec_to_arena(p, &p->objects, sizeof(csg_object *));
    s->textures = vec_to_arena(p, &p->textures, sizeof(csg_texture));
    s->interiors = vec_to_arena(p, &p->interiors, sizeof(csg_interior));
    s->lights = vec_to_arena(p, &p->lights, sizeof(csg_light));
    return s->objects && s->textures && s->interiors && s->lights && lang_files_to_scene(p);
}

/* ---- the failed parse's message ------------------------------------------------- */

/* An error inside a file that is not a scene file never shows its text:
 * the reason becomes a generic one, the position stays. */
static void hide_content(parser *p)
{
    const frame *fr = p->frames.data;
    for (int i = p->frames.count - 1; i >= 1; i--) {
        const char *file = fr[i].lx.file;
        size_t n = strlen(file);
        if (fr[i].kind != FRAME_FILE || !fr[i].hidden || strncmp(p->d->message, file, n) != 0 ||
            p->d->message[n] != ':')
            continue;
        char *reason = strstr(p->d->message + n, ": error: ");
        if (reason)
            snprintf(reason, sizeof p->d->message - (size_t)(reason - p->d->message),
                     ": error: '%s' is not a scene file (it has no .pov, .inc, .mcr or .map "
                     "name): its content is not shown", file);
        return;
    }
}

/* The message of a failed parse: hidden content, then the chain of macro
 * calls and includes that led to the error. */
static void finish_message(parser *p)
{
    if (!p->d->failed) {
        csg_error_plain(p->d, "internal error: the parse failed without a message");
        return;
    }
    if (p->frames.count <= 1 || strncmp(p->d->message, "csgtrace: ", 10) == 0)
        return;
    hide_content(p);
    char chain[2048];
    lang_frame_chain(p, chain, sizeof chain);
    size_t n = strlen(p->d->message);
    snprintf(p->d->message + n, sizeof p->d->message - n, "%s", chain);
}

/* ---- entry points ------------------------------------------------------------------ */

void csg_parse_options_default(csg_parse_options *o)
{
    memset(o, 0, sizeof *o);
    o->image_width = 320;
    o->image_height = 240;
}

static void parser_free(parser *p)
{
    lang_symbols_free(p);
    lang_rand_free(p);
    lang_files_free(p);
    free(p->frames.data);
    free(p->conds.data);
    free(p->textures.data);
    free(p->interiors.data);
    free(p->lights.data);
    free(p->objects.data);
    free(p->stack.data);
}

static bool parser_init(parser *p, const csg_parse_options *o, csg_scene *s, csg_diag *d)
{
    memset(p, 0, sizeof *p);
    p->s = s;
    p->d = d;
    if (o)
        p->opt = *o;
    else
        csg_parse_options_default(&p->opt);
    if (p->opt.image_width <= 0 || p->opt.image_height <= 0) {
        p->opt.image_width = 320;
        p->opt.image_height = 240;
    }
    if (p->opt.max_tokens <= 0)
        p->opt.max_tokens = CSG_PARSE_MAX_TOKENS;
    p->version = 3.7;
    p->default_entry = -1;
    csg_texture_default(&p->default_texture);
    csg_scene_init(s);
    s->version_implied = true; /* until a #version is read (POV-Ray: 3.62) */
    csg_camera_default(&s->camera);
    s->arena = csg_arena_new();
    if (!s->arena)
        return lang_oom(p);
    return lang_scope_push(p) && lang_declare_predefined(p);
}

bool csg_parse_string_opts(const char *name, const char *text, size_t len,
                           const csg_parse_options *o, csg_scene *s, csg_diag *d)
{
    parser p;
    bool ok = parser_init(&p, o, s, d);
    if (!name)
        name = "<input>";
    char *path = ok ? lang_strndup(&p, name, strlen(name)) : NULL;
    char *copy = path ? lang_strndup(&p, text ? text : "", text ? len : 0) : NULL;
    if (copy) {
        s->path = path;
        ok = lang_parse_main(&p, path, copy, text ? len : 0) && finish_scene(&p);
    } else {
        ok = false;
    }
    if (!ok)
        finish_message(&p);
    parser_free(&p);
    if (!ok) {
        csg_scene_free(s);
        csg_scene_init(s);
    }
    return ok;
}

bool csg_parse_string(const char *name, const char *text, size_t len, csg_scene *s, csg_diag *d)
{
    return csg_parse_string_opts(name, text, len, NULL, s, d);
}

bool csg_parse_file_as(const char *path, const csg_parse_options *o, csg_scene *s, csg_diag *d,
                       csg_text_parser parse)
{
    size_t len = 0;
    char why[256];
    char *text = lang_read_file(path, &len, why, sizeof why);
    if (!text) {
        csg_scene_init(s);
        csg_error_plain(d, "cannot read scene '%s': %s", path, why);
        return false;
    }
    bool ok = parse(path, text, len, o, s, d);
    free(text);
    return ok;
}

bool csg_parse_file_opts(const char *path, const csg_parse_options *o, csg_scene *s,
                         csg_diag *d)
{
    return csg_parse_file_as(path, o, s, d, csg_parse_string_opts);
}

bool csg_parse_file(const char *path, csg_scene *s, csg_diag *d)
{
    return csg_parse_file_opts(path, NULL, s, d);
}

/* POV-Ray's include folder, where it is installed. */
const char *csg_default_library(int i)
{
    static const char *const povray[] = {"/usr/share/povray-3.7/include",
                                         "/usr/local/share/povray-3.7/include"};
    for (size_t k = 0; k < sizeof povray / sizeof povray[0]; k++) {
        if (access(povray[k], F_OK) == 0 && i-- == 0)
            return povray[k];
    }
    return NULL;
}
