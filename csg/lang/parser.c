/*
 * parser.c — recursive-descent parser of the scene language
 * (scenes/LANGUAGE.md) into the scene tree of scene.h: the statement and
 * object grammar, and the entry points of parser.h.  Values and
 * expressions are read by expr.c, names by symbols.c, files and #include by
 * source.c (parse_internal.h lists what each provides).
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
 * statement began), and otherwise appends a modified copy (copy-on-write):
 * entries shared by copies of a declared object are never edited.
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

#include "../camera_setup.h"
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

static bool vec_push(parser *p, vec *v, size_t elem, const void *item)
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

/* Copies the first `count` items of v into the arena. */
static void *vec_to_arena(parser *p, const vec *v, size_t elem)
{
    void *m = lang_alloc(p, (size_t)v->count * elem);
    if (m && v->count)
        memcpy(m, v->data, (size_t)v->count * elem);
    return m;
}

/* ---- tokens ------------------------------------------------------------------ */

static void skip_comma(parser *p, bool *ok)
{
    if (lang_is_punct(p, ','))
        *ok = lang_next(p);
}

/* ---- pigment, finish, texture, interior ------------------------------------ */

/* pigment { [PIGMENT_ID] [COLOR] }, editing *pig. */
static bool parse_pigment(parser *p, csg_pigment *pig)
{
    csg_loc open = p->tok.loc;
    if (!lang_next(p) || !lang_expect_open(p, "pigment"))
        return false;
    symbol *sym = lang_peek_sym(p, SYM_PIGMENT);
    if (sym) {
        *pig = sym->pigment;
        if (!lang_next(p))
            return false;
    }
    if (!lang_is_punct(p, '}') && !lang_parse_color(p, pig->rgbft))
        return false;
    if (!lang_is_punct(p, '}'))
        return lang_expected_close(p, '}', "pigment", open);
    return lang_next(p);
}

static bool parse_finish(parser *p, csg_finish *f)
{
    csg_loc open = p->tok.loc;
    if (!lang_next(p) || !lang_expect_open(p, "finish"))
        return false;
    symbol *sym = lang_peek_sym(p, SYM_FINISH);
    if (sym) {
        *f = sym->finish;
        if (!lang_next(p))
            return false;
    }
    for (;;) {
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        if (p->tok.kind != CSG_TOK_WORD)
            return lang_expected_close(p, '}', "finish", open);
        enum csg_kw kw = p->tok.kw;
        double *target = NULL;
        switch (kw) {
        case CSG_KW_AMBIENT:
            if (!lang_next(p) || !lang_parse_rgb(p, f->ambient))
                return false;
            continue;
        case CSG_KW_REFLECTION:
            if (!lang_next(p) || !lang_parse_rgb(p, f->reflection))
                return false;
            continue;
        case CSG_KW_DIFFUSE: target = &f->diffuse; break;
        case CSG_KW_SPECULAR: target = &f->specular; break;
        case CSG_KW_ROUGHNESS: target = &f->roughness; break;
        case CSG_KW_PHONG: target = &f->phong; break;
        case CSG_KW_PHONG_SIZE: target = &f->phong_size; break;
        default:
            return lang_expected_close(p, '}', "finish", open);
        }
        csg_loc at;
        if (!lang_next(p) || !lang_parse_float(p, target, &at))
            return false;
        if (kw == CSG_KW_ROUGHNESS && !(*target > 0)) {
            csg_error(p->d, at, "roughness must be > 0, got %g", *target);
            return false;
        }
        if (kw == CSG_KW_PHONG_SIZE && *target < 0) {
            csg_error(p->d, at, "phong_size must be >= 0, got %g", *target);
            return false;
        }
    }
}

/* texture { [TEXTURE_ID] (pigment {..} | finish {..})* }; starts from
 * POV-Ray's default texture and replaces *t. */
static bool parse_texture(parser *p, csg_texture *t)
{
    csg_loc open = p->tok.loc;
    if (!lang_next(p) || !lang_expect_open(p, "texture"))
        return false;
    csg_texture_default(t);
    symbol *sym = lang_peek_sym(p, SYM_TEXTURE);
    if (sym) {
        *t = sym->texture;
        if (!lang_next(p))
            return false;
    }
    for (;;) {
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        if (lang_is_kw(p, CSG_KW_PIGMENT)) {
            if (!parse_pigment(p, &t->pigment))
                return false;
        } else if (lang_is_kw(p, CSG_KW_FINISH)) {
            if (!parse_finish(p, &t->finish))
                return false;
        } else {
            return lang_expected_close(p, '}', "texture", open);
        }
    }
}

static bool parse_interior(parser *p, csg_interior *in)
{
    csg_loc open = p->tok.loc;
    if (!lang_next(p) || !lang_expect_open(p, "interior"))
        return false;
    symbol *sym = lang_peek_sym(p, SYM_INTERIOR);
    if (sym) {
        *in = sym->interior;
        if (!lang_next(p))
            return false;
    }
    for (;;) {
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        if (!lang_is_kw(p, CSG_KW_IOR))
            return lang_expected_close(p, '}', "interior", open);
        csg_loc at;
        if (!lang_next(p) || !lang_parse_float(p, &in->ior, &at))
            return false;
        if (!(in->ior > 0)) {
            csg_error(p->d, at, "ior must be > 0, got %g", in->ior);
            return false;
        }
    }
}

/* ---- objects ---------------------------------------------------------------- */

static bool parse_object(parser *p, csg_object **out);

/* The object kind a keyword opens (CSG_OBJECT_KINDS: the keyword of each
 * kind is CSG_KW_<ID>); -1 for any other word. */
static int kind_of_keyword(enum csg_kw kw)
{
    switch (kw) {
#define PARSE_KIND_OF(ID, name)                                                                    \
    case CSG_KW_##ID:                                                                              \
        return CSG_OBJ_##ID;
        CSG_OBJECT_KINDS(PARSE_KIND_OF, PARSE_KIND_OF)
    default:
        return -1;
    }
}

static bool is_object_start(const parser *p)
{
    return p->tok.kind == CSG_TOK_WORD &&
           (kind_of_keyword(p->tok.kw) >= 0 || p->tok.kw == CSG_KW_OBJECT);
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
    return n;
}

static const char *object_name(enum csg_kw kw)
{
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
    double lo[3] = {o->a.x, o->a.y, o->a.z}, hi[3] = {o->b.x, o->b.y, o->b.z};
    for (int i = 0; i < 3; i++) {
        if (lo[i] == hi[i]) {
            csg_error(p->d, o->loc, "box is flat: both corners have %c = %g", "xyz"[i], lo[i]);
            return false;
        }
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
            ok = vec_push(p, &verts, sizeof v[k], &v[k]) &&
                 vec_push(p, &normals, sizeof nv[k], &nv[k]);
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

/* The children of a CSG object, up to the first token that is not an object. */
static bool parse_children(parser *p, pnode *n, const char *name)
{
    int base = p->stack.count;
    while (is_object_start(p)) {
        csg_object *child;
        if (!parse_object(p, &child) || !vec_push(p, &p->stack, sizeof child, &child))
            return false;
    }
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
    if (is_object_start(p)) {
        csg_object *inner;
        if (!parse_object(p, &inner))
            return NULL;
        return (pnode *)(void *)inner;
    }
    if (!lang_is_ident(p)) {
        lang_expected(p, "an object identifier expected inside 'object'");
        return NULL;
    }
    symbol *sym;
    if (!lang_lookup(p, SYM_OBJECT, "an object", &sym))
        return NULL;
    return copy_tree(p, sym->object, loc);
}

/* The object's own texture entry (copy-on-write, see the top comment). */
static csg_texture *own_texture(parser *p, csg_object *o, int mark)
{
    if (o->texture < mark) {
        csg_texture t;
        if (o->texture >= 0)
            t = ((csg_texture *)p->textures.data)[o->texture];
        else
            csg_texture_default(&t);
        if (!vec_push(p, &p->textures, sizeof t, &t))
            return NULL;
        o->texture = p->textures.count - 1;
    }
    return (csg_texture *)p->textures.data + o->texture;
}

static csg_interior *own_interior(parser *p, csg_object *o, int mark)
{
    if (o->interior < mark) {
        csg_interior in = {1.0};
        if (o->interior >= 0)
            in = ((csg_interior *)p->interiors.data)[o->interior];
        if (!vec_push(p, &p->interiors, sizeof in, &in))
            return NULL;
        o->interior = p->interiors.count - 1;
    }
    return (csg_interior *)p->interiors.data + o->interior;
}

/* matrix <m00, m01, m02, m10, ..., m32>: POV-Ray's row-vector form,
 * p' = p M, applied after the transforms before it. */
static bool parse_matrix(parser *p, csg_xform *x)
{
    if (!lang_next(p))
        return false;
    csg_loc open = p->tok.loc;
    if (!lang_is_punct(p, '<')) {
        csg_error(p->d, open, "'<' expected after 'matrix'");
        return false;
    }
    if (!lang_enter(p, open) || !lang_next(p))
        return false;
    double m[12];
    for (int i = 0; i < 12; i++) {
        csg_loc at;
        if (!lang_parse_float(p, &m[i], &at))
            return false;
        if (i < 11) {
            if (!lang_is_punct(p, ',')) {
                csg_error(p->d, p->tok.loc, "matrix needs 12 numbers separated by ','");
                return false;
            }
            if (!lang_next(p))
                return false;
        }
    }
    if (!lang_is_punct(p, '>'))
        return lang_expected_close(p, '>', "<", open);
    lang_leave(p);
    csg_xform t;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            t.m[i][j] = m[3 * j + i]; /* column j of ours is row j of POV-Ray's */
    csg_xform inv;
    if (!csg_xform_invert(&t, &inv)) {
        csg_error(p->d, open, "matrix is singular");
        return false;
    }
    csg_xform_then(x, &t, x);
    return lang_next(p);
}

/* Transforms (translate V, rotate V, scale V|F, matrix <...>), shared by
 * objects and lights. */
static bool parse_transform(parser *p, csg_xform *x)
{
    enum csg_kw kw = p->tok.kw;
    csg_loc at;
    dvec3 v;
    if (kw == CSG_KW_MATRIX)
        return parse_matrix(p, x);
    if (!lang_next(p) || !lang_parse_vector(p, &v, &at))
        return false;
    if (kw == CSG_KW_TRANSLATE) {
        csg_xform_translate(x, v);
    } else if (kw == CSG_KW_ROTATE) {
        csg_xform_rotate(x, v);
    } else {
        if (v.x == 0 || v.y == 0 || v.z == 0) {
            csg_error(p->d, at, "scale by zero");
            return false;
        }
        csg_xform_scale(x, v);
    }
    return true;
}

static bool is_transform(const parser *p)
{
    return lang_is_kw(p, CSG_KW_TRANSLATE) || lang_is_kw(p, CSG_KW_ROTATE) ||
           lang_is_kw(p, CSG_KW_SCALE) || lang_is_kw(p, CSG_KW_MATRIX);
}

/* pigment { }, finish { } or texture { } on o: edits its own texture entry. */
static bool parse_texture_modifier(parser *p, csg_object *o, int tex_mark)
{
    csg_texture *own = own_texture(p, o, tex_mark);
    if (!own)
        return false;
    csg_texture t = *own;
    bool ok = p->tok.kw == CSG_KW_PIGMENT  ? parse_pigment(p, &t.pigment)
              : p->tok.kw == CSG_KW_FINISH ? parse_finish(p, &t.finish)
                                           : parse_texture(p, &t);
    if (!ok)
        return false;
    ((csg_texture *)p->textures.data)[o->texture] = t;
    return true;
}

/* interior { } on o: edits its own interior entry. */
static bool parse_interior_modifier(parser *p, csg_object *o, int int_mark)
{
    csg_interior *own = own_interior(p, o, int_mark);
    if (!own)
        return false;
    csg_interior in = *own;
    if (!parse_interior(p, &in))
        return false;
    ((csg_interior *)p->interiors.data)[o->interior] = in;
    return true;
}

/* inverse, no_shadow or open on o (the object `name`). */
static bool parse_flag(parser *p, csg_object *o, const char *name)
{
    switch (p->tok.kw) {
    case CSG_KW_INVERSE:
        o->inverse = !o->inverse;
        break;
    case CSG_KW_NO_SHADOW:
        o->no_shadow = true;
        break;
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

/* Modifiers up to and including the closing brace. */
static bool parse_modifiers(parser *p, csg_object *o, const char *name, csg_loc open, int tex_mark,
                            int int_mark)
{
    for (;;) {
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        bool ok;
        if (is_transform(p))
            ok = parse_transform(p, &o->xform);
        else if (lang_is_kw(p, CSG_KW_PIGMENT) || lang_is_kw(p, CSG_KW_FINISH) ||
                 lang_is_kw(p, CSG_KW_TEXTURE))
            ok = parse_texture_modifier(p, o, tex_mark);
        else if (lang_is_kw(p, CSG_KW_INTERIOR))
            ok = parse_interior_modifier(p, o, int_mark);
        else if (lang_is_kw(p, CSG_KW_INVERSE) || lang_is_kw(p, CSG_KW_NO_SHADOW) ||
                 lang_is_kw(p, CSG_KW_OPEN))
            ok = parse_flag(p, o, name);
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
static bool parse_object(parser *p, csg_object **out)
{
    csg_loc loc = p->tok.loc;
    enum csg_kw kw = p->tok.kw;
    const char *name = object_name(kw);
    int tex_mark = p->textures.count, int_mark = p->interiors.count;
    if (!lang_enter(p, loc) || !lang_next(p) || !lang_expect_open(p, name))
        return false;
    int kind = kind_of_keyword(kw);
    pnode *n = kind >= 0 ? new_node(p, (enum csg_object_kind)kind, loc) : parse_object_base(p, loc);
    bool ok = n && (kind < 0 || parse_body(p, n, name));
    if (!ok || !parse_modifiers(p, &n->obj, name, loc, tex_mark, int_mark))
        return false;
    lang_leave(p);
    *out = &n->obj;
    return true;
}

/* ---- statements ---------------------------------------------------------------- */

static bool parse_camera(parser *p)
{
    csg_loc open = p->tok.loc;
    csg_camera_src c;
    csg_camera_default(&c);
    c.loc = open;
    if (!lang_next(p) || !lang_expect_open(p, "camera"))
        return false;
    for (;;) {
        if (lang_is_punct(p, '}'))
            break;
        if (p->tok.kind != CSG_TOK_WORD)
            return lang_expected_close(p, '}', "camera", open);
        enum csg_kw kw = p->tok.kw;
        csg_loc at = p->tok.loc;
        dvec3 v;
        double f;
        switch (kw) {
        case CSG_KW_PERSPECTIVE:
            if (!lang_next(p))
                return false;
            continue;
        case CSG_KW_ANGLE:
            if (!lang_next(p) || !lang_parse_float(p, &f, NULL) ||
                !csg_camera_angle(&c, f, at, p->d))
                return false;
            continue;
        case CSG_KW_LOCATION: case CSG_KW_LOOK_AT: case CSG_KW_DIRECTION:
        case CSG_KW_UP: case CSG_KW_RIGHT: case CSG_KW_SKY:
            if (!lang_next(p) || !lang_parse_vector(p, &v, NULL))
                return false;
            break;
        default:
            return lang_expected_close(p, '}', "camera", open);
        }
        switch (kw) {
        case CSG_KW_LOCATION: c.location = v; break;
        case CSG_KW_DIRECTION: c.direction = v; break;
        case CSG_KW_UP: c.up = v; break;
        case CSG_KW_RIGHT: c.right = v; break;
        case CSG_KW_SKY: c.sky = v; break;
        default:
            if (!csg_camera_look_at(&c, v, at, p->d))
                return false;
            break;
        }
    }
    p->s->camera = c;
    p->s->has_camera = true;
    return lang_next(p);
}

static bool parse_light(parser *p)
{
    csg_light l;
    memset(&l, 0, sizeof l);
    l.loc = p->tok.loc;
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
        if (is_transform(p)) {
            if (!parse_transform(p, &x))
                return false;
        } else if (lang_is_kw(p, CSG_KW_SHADOWLESS)) {
            l.shadowless = true;
            if (!lang_next(p))
                return false;
        } else {
            return lang_expected_close(p, '}', "light_source", l.loc);
        }
    }
    dvec3 q = l.position;
    l.position = (dvec3){x.m[0][0] * q.x + x.m[0][1] * q.y + x.m[0][2] * q.z + x.m[0][3],
                         x.m[1][0] * q.x + x.m[1][1] * q.y + x.m[1][2] * q.z + x.m[1][3],
                         x.m[2][0] * q.x + x.m[2][1] * q.y + x.m[2][2] * q.z + x.m[2][3]};
    return vec_push(p, &p->lights, sizeof l, &l) && lang_next(p);
}

static bool parse_background(parser *p)
{
    csg_loc open = p->tok.loc;
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

static bool parse_global_settings(parser *p)
{
    csg_loc open = p->tok.loc;
    csg_globals *g = &p->s->globals;
    if (!lang_next(p) || !lang_expect_open(p, "global_settings"))
        return false;
    for (;;) {
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        enum csg_kw kw = p->tok.kind == CSG_TOK_WORD ? p->tok.kw : CSG_KW_NONE;
        csg_loc at;
        double f;
        switch (kw) {
        case CSG_KW_AMBIENT_LIGHT:
            if (!lang_next(p) || !lang_parse_rgb(p, g->ambient_light))
                return false;
            continue;
        case CSG_KW_ASSUMED_GAMMA: case CSG_KW_MAX_TRACE_LEVEL: case CSG_KW_ADC_BAILOUT:
            if (!lang_next(p) || !lang_parse_float(p, &f, &at))
                return false;
            break;
        default:
            return lang_expected_close(p, '}', "global_settings", open);
        }
        if (kw == CSG_KW_ASSUMED_GAMMA) {
            if (!(f > 0)) {
                csg_error(p->d, at, "assumed_gamma must be > 0, got %g", f);
                return false;
            }
            g->assumed_gamma = f;
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

/* ---- directives ----------------------------------------------------------------- */

/* The directive's word in messages: at most 15 characters. */
#define DIRECTIVE_NAME 16

/* '#declare NAME =' or '#local NAME =': *name is the identifier, directive
 * the word after '#'; the current token is then the one after '='. */
static bool parse_declare_head(parser *p, char directive[DIRECTIVE_NAME], csg_token *name)
{
    snprintf(directive, DIRECTIVE_NAME, "%.*s", (int)(p->tok.len < 15 ? p->tok.len : 15),
             p->tok.text);
    if (!lang_next(p))
        return false;
    if (!lang_is_ident(p)) {
        char what[64];
        snprintf(what, sizeof what, "an identifier expected after '#%s'", directive);
        return lang_expected(p, what);
    }
    *name = p->tok;
    if (!lang_next(p))
        return false;
    if (!lang_is_punct(p, '=')) {
        char what[80];
        snprintf(what, sizeof what, "'=' expected after '#%s %.*s'", directive,
                 (int)(name->len > 40 ? 40 : name->len), name->text);
        return lang_expected(p, what);
    }
    return lang_next(p);
}

/* What a #declare binds, into *def (zeroed); *needs_semicolon for a value
 * or colour, which a ';' must end. */
static bool parse_declared(parser *p, symbol *def, bool *needs_semicolon)
{
    if (is_object_start(p)) {
        def->kind = SYM_OBJECT;
        return parse_object(p, &def->object);
    }
    if (lang_is_kw(p, CSG_KW_PIGMENT)) {
        def->kind = SYM_PIGMENT;
        return parse_pigment(p, &def->pigment);
    }
    if (lang_is_kw(p, CSG_KW_FINISH)) {
        def->kind = SYM_FINISH;
        csg_finish_default(&def->finish);
        return parse_finish(p, &def->finish);
    }
    if (lang_is_kw(p, CSG_KW_TEXTURE)) {
        def->kind = SYM_TEXTURE;
        return parse_texture(p, &def->texture);
    }
    if (lang_is_kw(p, CSG_KW_INTERIOR)) {
        def->kind = SYM_INTERIOR;
        def->interior.ior = 1.0;
        return parse_interior(p, &def->interior);
    }
    def->kind = SYM_VALUE;
    *needs_semicolon = true;
    if (lang_is_kw(p, CSG_KW_COLOR) || lang_is_color_item(p)) {
        def->val.dim = 5;
        return lang_parse_color(p, def->val.v);
    }
    if (lang_is_expr_start(p))
        return lang_parse_expr(p, &def->val);
    return lang_expected(p,
                         "a value, color, pigment, finish, texture, interior or object expected");
}

/* #declare NAME = ... and #local NAME = ... (one scope: the same). */
static bool parse_declare(parser *p)
{
    csg_loc at = p->tok.loc;
    char directive[DIRECTIVE_NAME];
    csg_token name = {0};
    if (!parse_declare_head(p, directive, &name))
        return false;
    symbol def;
    memset(&def, 0, sizeof def);
    bool needs_semicolon = false;
    if (!parse_declared(p, &def, &needs_semicolon))
        return false;
    if (needs_semicolon) {
        if (!lang_expect_semicolon(p, directive, at))
            return false;
    } else if (lang_is_punct(p, ';') && !lang_next(p)) {
        return false;
    }
    return lang_sym_set(p, name.text, name.len, &def);
}

static bool parse_version(parser *p)
{
    csg_loc at = p->tok.loc;
    double v;
    if (!lang_next(p) || !lang_parse_float(p, &v, NULL))
        return false;
    return lang_expect_semicolon(p, "version", at);
}

static bool parse_statement(parser *p)
{
    if (p->tok.kind == CSG_TOK_DIRECTIVE) {
        switch (p->tok.kw) {
        case CSG_KW_DECLARE:
        case CSG_KW_LOCAL:
            return parse_declare(p);
        case CSG_KW_INCLUDE:
            return lang_parse_include(p);
        case CSG_KW_VERSION:
            return parse_version(p);
        default:
            return lang_expected(p, "a statement expected");
        }
    }
    if (is_object_start(p)) {
        csg_object *o;
        return parse_object(p, &o) && vec_push(p, &p->objects, sizeof o, &o);
    }
    if (p->tok.kind == CSG_TOK_WORD) {
        switch (p->tok.kw) {
        case CSG_KW_CAMERA: return parse_camera(p);
        case CSG_KW_LIGHT_SOURCE: return parse_light(p);
        case CSG_KW_BACKGROUND: return parse_background(p);
        case CSG_KW_GLOBAL_SETTINGS: return parse_global_settings(p);
        default: break;
        }
    }
    return lang_expected(p, "an object or a statement expected");
}

bool lang_parse_statements(parser *p)
{
    while (p->tok.kind != CSG_TOK_EOF)
        if (!parse_statement(p))
            return false;
    return true;
}

/* ---- the end of the parse ------------------------------------------------------ */

static void compose_world(csg_object *o, const csg_xform *parent)
{
    if (parent)
        csg_xform_then(&o->xform, parent, &o->xform);
    for (int i = 0; i < o->child_count; i++)
        compose_world(o->children[i], &o->xform);
}

static bool finish_scene(parser *p)
{
    csg_scene *s = p->s;
    csg_object **top = p->objects.data;
    for (int i = 0; i < p->objects.count; i++) {
        compose_world(top[i], NULL);
        if (top[i]->texture < 0) {
            csg_texture t;
            csg_texture_default(&t);
            if (!vec_push(p, &p->textures, sizeof t, &t))
                return false;
            top[i]->texture = p->textures.count - 1;
            for (int j = i + 1; j < p->objects.count; j++)
                if (top[j]->texture < 0)
                    top[j]->texture = top[i]->texture;
        }
        if (top[i]->interior < 0) {
            csg_interior in = {1.0};
            if (!vec_push(p, &p->interiors, sizeof in, &in))
                return false;
            top[i]->interior = p->interiors.count - 1;
            for (int j = i + 1; j < p->objects.count; j++)
                if (top[j]->interior < 0)
                    top[j]->interior = top[i]->interior;
        }
    }
    s->objects = vec_to_arena(p, &p->objects, sizeof(csg_object *));
    s->textures = vec_to_arena(p, &p->textures, sizeof(csg_texture));
    s->interiors = vec_to_arena(p, &p->interiors, sizeof(csg_interior));
    s->lights = vec_to_arena(p, &p->lights, sizeof(csg_light));
    if (!s->objects || !s->textures || !s->interiors || !s->lights)
        return false;
    s->object_count = p->objects.count;
    s->texture_count = p->textures.count;
    s->interior_count = p->interiors.count;
    s->light_count = p->lights.count;
    return true;
}

bool csg_parse_string(const char *name, const char *text, size_t len, csg_scene *s, csg_diag *d)
{
    parser p;
    memset(&p, 0, sizeof p);
    p.s = s;
    p.d = d;
    csg_scene_init(s);
    csg_camera_default(&s->camera);
    s->arena = csg_arena_new();
    bool ok = false;
    if (!s->arena) {
        lang_oom(&p);
        goto fail;
    }
    if (!name)
        name = "<input>";
    char *path = lang_strndup(&p, name, strlen(name));
    char *copy = lang_strndup(&p, text ? text : "", text ? len : 0);
    if (!path || !copy)
        goto fail;
    s->path = path;
    ok = lang_parse_main(&p, path, copy, text ? len : 0) && finish_scene(&p);
fail:
    lang_symbols_free(&p);
    free(p.textures.data);
    free(p.interiors.data);
    free(p.lights.data);
    free(p.objects.data);
    free(p.stack.data);
    if (!ok) {
        if (!d->failed)
            csg_error_plain(d, "internal error: the parse failed without a message");
        csg_scene_free(s);
        csg_scene_init(s);
    }
    return ok;
}

bool csg_parse_file_as(const char *path, csg_scene *s, csg_diag *d, csg_text_parser parse)
{
    size_t len = 0;
    int err = 0;
    char *text = lang_read_file(path, &len, &err);
    if (!text) {
        csg_scene_init(s);
        csg_error_plain(d, "cannot read scene '%s': %s", path, strerror(err));
        return false;
    }
    bool ok = parse(path, text, len, s, d);
    free(text);
    return ok;
}

bool csg_parse_file(const char *path, csg_scene *s, csg_diag *d)
{
    return csg_parse_file_as(path, s, d, csg_parse_string);
}
