/*
 * parser.c — recursive-descent parser of the scene language
 * (scenes/LANGUAGE.md) into the scene tree of scene.h.
 *
 * Algorithm: one token of lookahead (p->tok) over the lexer of the file
 * being read; #include pushes a new lexer (the old one is saved on the C
 * stack) and reads the included file's statements in place.  Expressions
 * are evaluated as they are parsed into a `value` (a float, or a vector of
 * 2..5 components: colours are 5-component vectors rgbft).
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
 * Invariants and limits: p->nesting counts the objects, parentheses and
 * vector literals open around the current token and never exceeds
 * CSG_PARSE_MAX_NESTING; every node records the height of its tree
 * (pnode.height), kept <= CSG_PARSE_MAX_NESTING, so the copy and the final
 * pass recurse at most that deep; p->nodes <= CSG_PARSE_MAX_OBJECTS.  Every
 * allocation that outlives the parse is in the scene's arena; the growable
 * tables are malloc'd and copied into the arena at the end (one cleanup path
 * frees them whatever happens).
 */
#include "parser.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../camera_setup.h"
#include "lexer.h"

/* ---- values and symbols ------------------------------------------------- */

typedef struct {
    int dim;        /* 1: float; 2..5: vector (colours: 5, rgbft) */
    double v[5];
} value;

enum sym_kind { SYM_VALUE, SYM_PIGMENT, SYM_FINISH, SYM_TEXTURE, SYM_INTERIOR, SYM_OBJECT };

typedef struct {
    const char *name; /* arena copy, len bytes */
    size_t len;
    enum sym_kind kind;
    value val;
    csg_pigment pigment;
    csg_finish finish;
    csg_texture texture;
    csg_interior interior;
    csg_object *object; /* a tree that is never in the scene: used by copy */
} symbol;

/* A tree node with the height of its subtree (1 for a primitive). */
typedef struct {
    csg_object obj; /* first member: a csg_object * converts back */
    int height;
} pnode;

/* A growable malloc'd array. */
typedef struct {
    void *data;
    int count, cap;
} vec;

typedef struct {
    csg_scene *s;
    csg_diag *d;
    csg_lexer lx;       /* the file being read                            */
    csg_token tok;      /* the current token (one of lookahead)           */
    int nesting;        /* see the invariants above                       */
    int include_depth;  /* files open around the current one              */
    const char *include_stack[CSG_PARSE_MAX_INCLUDE + 1]; /* real paths   */
    symbol **syms;      /* open addressing hash table, sym_cap a power of 2 */
    size_t sym_cap, sym_count;
    vec textures;       /* csg_texture                                    */
    vec interiors;      /* csg_interior                                   */
    vec lights;         /* csg_light                                      */
    vec objects;        /* csg_object *: the top-level objects            */
    vec stack;          /* csg_object *: children of the open CSG objects */
    long nodes;         /* tree nodes created                             */
} parser;

/* ---- errors --------------------------------------------------------------- */

static bool oom(parser *p)
{
    csg_error_plain(p->d, "out of memory");
    return false;
}

static bool is_unsupported(const csg_token *t)
{
    return (t->kind == CSG_TOK_WORD || t->kind == CSG_TOK_DIRECTIVE) && t->kw == CSG_KW_UNSUPPORTED;
}

static bool unsupported(parser *p)
{
    char what[64];
    csg_token_describe(&p->tok, what, sizeof what);
    csg_error(p->d, p->tok.loc,
              "unsupported: %s is not in csgtrace's language (see scenes/LANGUAGE.md)", what);
    return false;
}

/* "<what expected ...>, got <token>" — or the unsupported-word message. */
static bool expected(parser *p, const char *what)
{
    if (is_unsupported(&p->tok))
        return unsupported(p);
    char got[64];
    csg_token_describe(&p->tok, got, sizeof got);
    csg_error(p->d, p->tok.loc, "%s, got %s", what, got);
    return false;
}

/* "'}' expected (to close 'union' at 12:3), got 'sphere'" */
static bool expected_close(parser *p, char closer, const char *opener, csg_loc at)
{
    if (is_unsupported(&p->tok))
        return unsupported(p);
    char got[64];
    csg_token_describe(&p->tok, got, sizeof got);
    csg_error(p->d, p->tok.loc, "'%c' expected (to close '%s' at %d:%d), got %s", closer, opener,
              at.line, at.col, got);
    return false;
}

/* ---- memory ----------------------------------------------------------------- */

static void *palloc(parser *p, size_t size)
{
    void *m = csg_arena_alloc(p->s->arena, size ? size : 1);
    if (!m)
        oom(p);
    return m;
}

static char *pstrndup(parser *p, const char *text, size_t len)
{
    char *c = palloc(p, len + 1);
    if (c)
        memcpy(c, text, len);
    return c;
}

static bool vec_push(parser *p, vec *v, size_t elem, const void *item)
{
    if (v->count == v->cap) {
        if (v->cap > INT_MAX / 4)
            return oom(p);
        int cap = v->cap ? v->cap * 2 : 16;
        void *data = realloc(v->data, (size_t)cap * elem);
        if (!data)
            return oom(p);
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
    void *m = palloc(p, (size_t)v->count * elem);
    if (m && v->count)
        memcpy(m, v->data, (size_t)v->count * elem);
    return m;
}

/* ---- tokens ------------------------------------------------------------------ */

static bool next(parser *p)
{
    return csg_lexer_next(&p->lx, &p->tok, p->d);
}

static bool is_punct(const parser *p, char c)
{
    return p->tok.kind == CSG_TOK_PUNCT && p->tok.punct == c;
}

static bool is_kw(const parser *p, enum csg_kw kw)
{
    return p->tok.kind == CSG_TOK_WORD && p->tok.kw == kw;
}

static bool is_ident(const parser *p)
{
    return p->tok.kind == CSG_TOK_WORD && p->tok.kw == CSG_KW_NONE;
}

static void skip_comma(parser *p, bool *ok)
{
    if (is_punct(p, ','))
        *ok = next(p);
}

/* Consumes "{" after the keyword `name`. */
static bool expect_open(parser *p, const char *name)
{
    if (!is_punct(p, '{')) {
        char what[64];
        snprintf(what, sizeof what, "'{' expected after '%s'", name);
        return expected(p, what);
    }
    return next(p);
}

static bool enter(parser *p, csg_loc loc)
{
    if (++p->nesting > CSG_PARSE_MAX_NESTING) {
        csg_error(p->d, loc, "nesting deeper than %d levels", CSG_PARSE_MAX_NESTING);
        return false;
    }
    return true;
}

static void leave(parser *p)
{
    p->nesting--;
}

/* ---- symbols --------------------------------------------------------------- */

static uint64_t hash_name(const char *s, size_t len)
{
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < len; i++)
        h = (h ^ (unsigned char)s[i]) * 1099511628211ull;
    return h;
}

static symbol **sym_slot(symbol **table, size_t cap, const char *name, size_t len)
{
    size_t i = (size_t)hash_name(name, len) & (cap - 1);
    while (table[i] && !(table[i]->len == len && memcmp(table[i]->name, name, len) == 0))
        i = (i + 1) & (cap - 1);
    return &table[i];
}

static symbol *sym_find(const parser *p, const char *name, size_t len)
{
    if (!p->sym_cap)
        return NULL;
    return *sym_slot(p->syms, p->sym_cap, name, len);
}

/* The symbol `name`, created (zeroed, kind SYM_VALUE) when new. */
static symbol *sym_define(parser *p, const char *name, size_t len)
{
    if ((p->sym_count + 1) * 2 > p->sym_cap) {
        size_t cap = p->sym_cap ? p->sym_cap * 2 : 256;
        symbol **table = calloc(cap, sizeof *table);
        if (!table) {
            oom(p);
            return NULL;
        }
        for (size_t i = 0; i < p->sym_cap; i++)
            if (p->syms[i])
                *sym_slot(table, cap, p->syms[i]->name, p->syms[i]->len) = p->syms[i];
        free(p->syms);
        p->syms = table;
        p->sym_cap = cap;
    }
    symbol **slot = sym_slot(p->syms, p->sym_cap, name, len);
    if (!*slot) {
        symbol *sym = palloc(p, sizeof *sym);
        char *copy = pstrndup(p, name, len);
        if (!sym || !copy)
            return NULL;
        sym->name = copy;
        sym->len = len;
        *slot = sym;
        p->sym_count++;
    }
    return *slot;
}

static const char *sym_kind_name(const symbol *sym)
{
    switch (sym->kind) {
    case SYM_VALUE:
        return sym->val.dim == 1 ? "a float" : sym->val.dim == 5 ? "a color" : "a vector";
    case SYM_PIGMENT: return "a pigment";
    case SYM_FINISH: return "a finish";
    case SYM_TEXTURE: return "a texture";
    case SYM_INTERIOR: return "an interior";
    case SYM_OBJECT: return "an object";
    }
    return "?";
}

/* The declared symbol named by the current identifier, of kind `want`. */
static bool lookup(parser *p, enum sym_kind want, const char *want_name, symbol **out)
{
    symbol *sym = sym_find(p, p->tok.text, p->tok.len);
    if (!sym) {
        csg_error(p->d, p->tok.loc, "undeclared identifier '%.*s'", (int)p->tok.len, p->tok.text);
        return false;
    }
    if (sym->kind != want) {
        csg_error(p->d, p->tok.loc, "'%.*s' is %s, not %s", (int)p->tok.len, p->tok.text,
                  sym_kind_name(sym), want_name);
        return false;
    }
    *out = sym;
    return next(p);
}

/* The current identifier's symbol when it is declared with kind `kind`. */
static symbol *peek_sym(const parser *p, enum sym_kind kind)
{
    if (!is_ident(p))
        return NULL;
    symbol *sym = sym_find(p, p->tok.text, p->tok.len);
    return sym && sym->kind == kind ? sym : NULL;
}

/* ---- expressions ------------------------------------------------------------ */

static bool parse_expr(parser *p, value *out);

static const char *dim_name(int dim)
{
    static const char *const names[] = {"?", "a float", "a 2-component vector",
                                        "a 3-component vector", "a 4-component vector",
                                        "a 5-component vector"};
    return dim >= 1 && dim <= 5 ? names[dim] : names[0];
}

static bool is_expr_start(const parser *p)
{
    const csg_token *t = &p->tok;
    if (t->kind == CSG_TOK_NUMBER)
        return true;
    if (t->kind == CSG_TOK_PUNCT)
        return t->punct == '<' || t->punct == '(' || t->punct == '-' || t->punct == '+';
    if (t->kind != CSG_TOK_WORD)
        return false;
    switch (t->kw) {
    case CSG_KW_NONE: case CSG_KW_PI: case CSG_KW_X: case CSG_KW_Y: case CSG_KW_Z:
    case CSG_KW_TRUE: case CSG_KW_FALSE:
        return true;
    default:
        return false;
    }
}

static value make_float(double f)
{
    value v = {1, {f, 0, 0, 0, 0}};
    return v;
}

static value make_vec3(double a, double b, double c)
{
    value v = {3, {a, b, c, 0, 0}};
    return v;
}

/* '<' expr ',' expr ... '>' with 2 to 5 float components. */
static bool parse_vector_literal(parser *p, value *out)
{
    csg_loc open = p->tok.loc;
    if (!enter(p, open) || !next(p))
        return false;
    out->dim = 0;
    for (;;) {
        csg_loc at = p->tok.loc;
        value c;
        if (!parse_expr(p, &c))
            return false;
        if (c.dim != 1) {
            csg_error(p->d, at, "a float expected as a vector component, got %s", dim_name(c.dim));
            return false;
        }
        if (out->dim == 5) {
            csg_error(p->d, at, "a vector has at most 5 components");
            return false;
        }
        out->v[out->dim++] = c.v[0];
        if (!is_punct(p, ','))
            break;
        if (!next(p))
            return false;
    }
    if (!is_punct(p, '>'))
        return expected_close(p, '>', "<", open);
    if (out->dim < 2) {
        csg_error(p->d, open, "a vector needs at least 2 components");
        return false;
    }
    for (int i = out->dim; i < 5; i++)
        out->v[i] = 0;
    leave(p);
    return next(p);
}

static bool parse_primary(parser *p, value *out)
{
    const csg_token *t = &p->tok;
    if (t->kind == CSG_TOK_NUMBER) {
        *out = make_float(t->number);
        return next(p);
    }
    if (is_punct(p, '(')) {
        csg_loc open = t->loc;
        if (!enter(p, open) || !next(p) || !parse_expr(p, out))
            return false;
        if (!is_punct(p, ')'))
            return expected_close(p, ')', "(", open);
        leave(p);
        return next(p);
    }
    if (is_punct(p, '<'))
        return parse_vector_literal(p, out);
    if (t->kind == CSG_TOK_WORD) {
        switch (t->kw) {
        case CSG_KW_PI: *out = make_float(M_PI); return next(p);
        case CSG_KW_TRUE: *out = make_float(1); return next(p);
        case CSG_KW_FALSE: *out = make_float(0); return next(p);
        case CSG_KW_X: *out = make_vec3(1, 0, 0); return next(p);
        case CSG_KW_Y: *out = make_vec3(0, 1, 0); return next(p);
        case CSG_KW_Z: *out = make_vec3(0, 0, 1); return next(p);
        case CSG_KW_NONE: {
            symbol *sym;
            if (!lookup(p, SYM_VALUE, "a float, vector or color", &sym))
                return false;
            *out = sym->val;
            return true;
        }
        default:
            break;
        }
    }
    return expected(p, "an expression expected");
}

/* Unary signs (any number, iteratively) then a primary. */
static bool parse_unary(parser *p, value *out)
{
    bool negate = false;
    while (is_punct(p, '-') || is_punct(p, '+')) {
        if (p->tok.punct == '-')
            negate = !negate;
        if (!next(p))
            return false;
    }
    if (!parse_primary(p, out))
        return false;
    if (negate)
        for (int i = 0; i < out->dim; i++)
            out->v[i] = -out->v[i];
    return true;
}

/* a op b, a float promoted to the other operand's size, the shorter
 * vector padded with zeros (POV-Ray's promotion rules). */
static bool combine(parser *p, value *a, const value *b, char op, csg_loc at)
{
    int dim = a->dim > b->dim ? a->dim : b->dim;
    double x[5], y[5];
    for (int i = 0; i < 5; i++) {
        x[i] = a->dim == 1 ? a->v[0] : (i < a->dim ? a->v[i] : 0);
        y[i] = b->dim == 1 ? b->v[0] : (i < b->dim ? b->v[i] : 0);
    }
    for (int i = 0; i < dim; i++) {
        switch (op) {
        case '+': x[i] += y[i]; break;
        case '-': x[i] -= y[i]; break;
        case '*': x[i] *= y[i]; break;
        default:
            if (y[i] == 0) {
                csg_error(p->d, at, "division by zero");
                return false;
            }
            x[i] /= y[i];
            break;
        }
        if (!isfinite(x[i])) {
            csg_error(p->d, at, "arithmetic overflow: the result is not a finite number");
            return false;
        }
    }
    a->dim = dim;
    for (int i = 0; i < 5; i++)
        a->v[i] = i < dim ? x[i] : 0;
    return true;
}

static bool parse_term(parser *p, value *out)
{
    if (!parse_unary(p, out))
        return false;
    while (is_punct(p, '*') || is_punct(p, '/')) {
        char op = p->tok.punct;
        csg_loc at = p->tok.loc;
        value rhs;
        if (!next(p) || !parse_unary(p, &rhs) || !combine(p, out, &rhs, op, at))
            return false;
    }
    return true;
}

static bool parse_expr(parser *p, value *out)
{
    if (!parse_term(p, out))
        return false;
    while (is_punct(p, '+') || is_punct(p, '-')) {
        char op = p->tok.punct;
        csg_loc at = p->tok.loc;
        value rhs;
        if (!next(p) || !parse_term(p, &rhs) || !combine(p, out, &rhs, op, at))
            return false;
    }
    return true;
}

static bool parse_float(parser *p, double *out, csg_loc *at)
{
    csg_loc start = p->tok.loc;
    value v;
    if (!parse_expr(p, &v))
        return false;
    if (v.dim != 1) {
        csg_error(p->d, start, "a float expected, got %s", dim_name(v.dim));
        return false;
    }
    *out = v.v[0];
    if (at)
        *at = start;
    return true;
}

/* A 3-vector; a float is promoted to <f, f, f>. */
static bool parse_vector(parser *p, dvec3 *out, csg_loc *at)
{
    csg_loc start = p->tok.loc;
    value v;
    if (!parse_expr(p, &v))
        return false;
    if (v.dim == 1) {
        v.v[1] = v.v[2] = v.v[0];
    } else if (v.dim != 3) {
        csg_error(p->d, start, "a 3-component vector expected, got %s", dim_name(v.dim));
        return false;
    }
    *out = (dvec3){v.v[0], v.v[1], v.v[2]};
    if (at)
        *at = start;
    return true;
}

/* ---- colours ---------------------------------------------------------------- */

static bool is_color_item(const parser *p)
{
    if (p->tok.kind != CSG_TOK_WORD)
        return false;
    switch (p->tok.kw) {
    case CSG_KW_RGB: case CSG_KW_RGBF: case CSG_KW_RGBT: case CSG_KW_RGBFT:
    case CSG_KW_RED: case CSG_KW_GREEN: case CSG_KW_BLUE: case CSG_KW_FILTER:
    case CSG_KW_TRANSMIT:
        return true;
    default:
        return false;
    }
}

static bool is_color_start(const parser *p)
{
    return is_kw(p, CSG_KW_COLOR) || is_color_item(p) || is_expr_start(p);
}

/* rgb / rgbf / rgbt / rgbft E: a float fills every component it sets. */
static bool parse_color_vector(parser *p, enum csg_kw kw, double c[5])
{
    static const int need[] = {3, 4, 4, 5}; /* rgb rgbf rgbt rgbft */
    int k = kw == CSG_KW_RGB ? 0 : kw == CSG_KW_RGBF ? 1 : kw == CSG_KW_RGBT ? 2 : 3;
    char name[8];
    snprintf(name, sizeof name, "%.*s", (int)p->tok.len, p->tok.text);
    if (!next(p))
        return false;
    csg_loc start = p->tok.loc;
    value v;
    if (!parse_expr(p, &v))
        return false;
    if (v.dim != 1 && v.dim < need[k]) {
        csg_error(p->d, start, "'%s' needs a float or a %d-component vector, got %s", name,
                  need[k], dim_name(v.dim));
        return false;
    }
    double w[5];
    for (int i = 0; i < need[k]; i++)
        w[i] = v.dim == 1 ? v.v[0] : v.v[i];
    c[0] = w[0];
    c[1] = w[1];
    c[2] = w[2];
    if (k == 1)
        c[3] = w[3];
    else if (k == 2)
        c[4] = w[3];
    else if (k == 3) {
        c[3] = w[3];
        c[4] = w[4];
    }
    return true;
}

/* COLOR: ['color'|'colour'] then items; the first item may be an
 * expression (a float sets all five components, as in POV-Ray; a 3-, 4- or
 * 5-vector sets rgb, rgbf or rgbft).  Starts from all zeros. */
static bool parse_color(parser *p, double c[5])
{
    memset(c, 0, 5 * sizeof c[0]);
    bool keyword = is_kw(p, CSG_KW_COLOR);
    if (keyword && !next(p))
        return false;
    if (is_expr_start(p)) {
        csg_loc start = p->tok.loc;
        value v;
        if (!parse_expr(p, &v))
            return false;
        if (v.dim == 2) {
            csg_error(p->d, start, "a color expected, got %s", dim_name(v.dim));
            return false;
        }
        for (int i = 0; i < 5; i++)
            c[i] = v.dim == 1 ? v.v[0] : v.v[i];
    } else if (!is_color_item(p)) {
        return expected(p, keyword ? "a color expected after 'color'" : "a color expected");
    }
    while (is_color_item(p)) {
        enum csg_kw kw = p->tok.kw;
        if (kw == CSG_KW_RGB || kw == CSG_KW_RGBF || kw == CSG_KW_RGBT || kw == CSG_KW_RGBFT) {
            if (!parse_color_vector(p, kw, c))
                return false;
            continue;
        }
        int i = kw == CSG_KW_RED ? 0 : kw == CSG_KW_GREEN ? 1 : kw == CSG_KW_BLUE ? 2
              : kw == CSG_KW_FILTER ? 3 : 4;
        if (!next(p) || !parse_float(p, &c[i], NULL))
            return false;
    }
    return true;
}

static bool parse_rgb(parser *p, double rgb[3])
{
    double c[5];
    if (!parse_color(p, c))
        return false;
    memcpy(rgb, c, 3 * sizeof c[0]);
    return true;
}

/* ---- pigment, finish, texture, interior ------------------------------------ */

/* pigment { [PIGMENT_ID] [COLOR] }, editing *pig. */
static bool parse_pigment(parser *p, csg_pigment *pig)
{
    csg_loc open = p->tok.loc;
    if (!next(p) || !expect_open(p, "pigment"))
        return false;
    symbol *sym = peek_sym(p, SYM_PIGMENT);
    if (sym) {
        *pig = sym->pigment;
        if (!next(p))
            return false;
    }
    if (!is_punct(p, '}') && !parse_color(p, pig->rgbft))
        return false;
    if (!is_punct(p, '}'))
        return expected_close(p, '}', "pigment", open);
    return next(p);
}

static bool parse_finish(parser *p, csg_finish *f)
{
    csg_loc open = p->tok.loc;
    if (!next(p) || !expect_open(p, "finish"))
        return false;
    symbol *sym = peek_sym(p, SYM_FINISH);
    if (sym) {
        *f = sym->finish;
        if (!next(p))
            return false;
    }
    for (;;) {
        if (is_punct(p, '}'))
            return next(p);
        if (p->tok.kind != CSG_TOK_WORD)
            return expected_close(p, '}', "finish", open);
        enum csg_kw kw = p->tok.kw;
        double *target = NULL;
        switch (kw) {
        case CSG_KW_AMBIENT:
            if (!next(p) || !parse_rgb(p, f->ambient))
                return false;
            continue;
        case CSG_KW_REFLECTION:
            if (!next(p) || !parse_rgb(p, f->reflection))
                return false;
            continue;
        case CSG_KW_DIFFUSE: target = &f->diffuse; break;
        case CSG_KW_SPECULAR: target = &f->specular; break;
        case CSG_KW_ROUGHNESS: target = &f->roughness; break;
        case CSG_KW_PHONG: target = &f->phong; break;
        case CSG_KW_PHONG_SIZE: target = &f->phong_size; break;
        default:
            return expected_close(p, '}', "finish", open);
        }
        csg_loc at;
        if (!next(p) || !parse_float(p, target, &at))
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
    if (!next(p) || !expect_open(p, "texture"))
        return false;
    csg_texture_default(t);
    symbol *sym = peek_sym(p, SYM_TEXTURE);
    if (sym) {
        *t = sym->texture;
        if (!next(p))
            return false;
    }
    for (;;) {
        if (is_punct(p, '}'))
            return next(p);
        if (is_kw(p, CSG_KW_PIGMENT)) {
            if (!parse_pigment(p, &t->pigment))
                return false;
        } else if (is_kw(p, CSG_KW_FINISH)) {
            if (!parse_finish(p, &t->finish))
                return false;
        } else {
            return expected_close(p, '}', "texture", open);
        }
    }
}

static bool parse_interior(parser *p, csg_interior *in)
{
    csg_loc open = p->tok.loc;
    if (!next(p) || !expect_open(p, "interior"))
        return false;
    symbol *sym = peek_sym(p, SYM_INTERIOR);
    if (sym) {
        *in = sym->interior;
        if (!next(p))
            return false;
    }
    for (;;) {
        if (is_punct(p, '}'))
            return next(p);
        if (!is_kw(p, CSG_KW_IOR))
            return expected_close(p, '}', "interior", open);
        csg_loc at;
        if (!next(p) || !parse_float(p, &in->ior, &at))
            return false;
        if (!(in->ior > 0)) {
            csg_error(p->d, at, "ior must be > 0, got %g", in->ior);
            return false;
        }
    }
}

/* ---- objects ---------------------------------------------------------------- */

static bool parse_object(parser *p, csg_object **out);

static bool is_object_start(const parser *p)
{
    if (p->tok.kind != CSG_TOK_WORD)
        return false;
    switch (p->tok.kw) {
    case CSG_KW_SPHERE: case CSG_KW_BOX: case CSG_KW_CYLINDER: case CSG_KW_CONE:
    case CSG_KW_PLANE: case CSG_KW_UNION: case CSG_KW_INTERSECTION:
    case CSG_KW_DIFFERENCE: case CSG_KW_MERGE: case CSG_KW_OBJECT:
        return true;
    default:
        return false;
    }
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
    pnode *n = palloc(p, sizeof *n);
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
        n->obj.children = palloc(p, (size_t)src->child_count * sizeof *n->obj.children);
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
    switch (kw) {
    case CSG_KW_SPHERE: return "sphere";
    case CSG_KW_BOX: return "box";
    case CSG_KW_CYLINDER: return "cylinder";
    case CSG_KW_CONE: return "cone";
    case CSG_KW_PLANE: return "plane";
    case CSG_KW_UNION: return "union";
    case CSG_KW_INTERSECTION: return "intersection";
    case CSG_KW_DIFFERENCE: return "difference";
    case CSG_KW_MERGE: return "merge";
    default: return "object";
    }
}

static bool same_point(dvec3 a, dvec3 b)
{
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

static bool parse_sphere(parser *p, csg_object *o)
{
    csg_loc at;
    bool ok = parse_vector(p, &o->a, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !parse_float(p, &o->r0, &at))
        return false;
    if (!(o->r0 > 0)) {
        csg_error(p->d, at, "sphere radius must be > 0, got %g", o->r0);
        return false;
    }
    return true;
}

static bool parse_box(parser *p, csg_object *o)
{
    bool ok = parse_vector(p, &o->a, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !parse_vector(p, &o->b, NULL))
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
    bool ok = parse_vector(p, &o->a, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (ok)
        ok = parse_vector(p, &o->b, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !parse_float(p, &o->r0, &at))
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
    bool ok = parse_vector(p, &o->a, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (ok)
        ok = parse_float(p, &o->r0, &at0);
    if (ok)
        skip_comma(p, &ok);
    if (ok)
        ok = parse_vector(p, &o->b, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !parse_float(p, &o->r1, &at1))
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
    bool ok = parse_vector(p, &o->a, &at);
    if (ok)
        skip_comma(p, &ok);
    if (!ok || !parse_float(p, &o->r0, NULL))
        return false;
    double len = sqrt(o->a.x * o->a.x + o->a.y * o->a.y + o->a.z * o->a.z);
    if (!(len > 0) || !isfinite(len)) {
        csg_error(p->d, at, "plane normal must be a non-zero finite vector");
        return false;
    }
    o->a = (dvec3){o->a.x / len, o->a.y / len, o->a.z / len};
    return true;
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
        return expected(p, what);
    }
    csg_object **kids = palloc(p, (size_t)count * sizeof *kids);
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
    if (!is_ident(p)) {
        expected(p, "an object identifier expected inside 'object'");
        return NULL;
    }
    symbol *sym;
    if (!lookup(p, SYM_OBJECT, "an object", &sym))
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
    if (!next(p))
        return false;
    csg_loc open = p->tok.loc;
    if (!is_punct(p, '<')) {
        csg_error(p->d, open, "'<' expected after 'matrix'");
        return false;
    }
    if (!enter(p, open) || !next(p))
        return false;
    double m[12];
    for (int i = 0; i < 12; i++) {
        csg_loc at;
        if (!parse_float(p, &m[i], &at))
            return false;
        if (i < 11) {
            if (!is_punct(p, ',')) {
                csg_error(p->d, p->tok.loc, "matrix needs 12 numbers separated by ','");
                return false;
            }
            if (!next(p))
                return false;
        }
    }
    if (!is_punct(p, '>'))
        return expected_close(p, '>', "<", open);
    leave(p);
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
    return next(p);
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
    if (!next(p) || !parse_vector(p, &v, &at))
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
    return is_kw(p, CSG_KW_TRANSLATE) || is_kw(p, CSG_KW_ROTATE) || is_kw(p, CSG_KW_SCALE) ||
           is_kw(p, CSG_KW_MATRIX);
}

/* Modifiers up to and including the closing brace. */
static bool parse_modifiers(parser *p, csg_object *o, const char *name, csg_loc open, int tex_mark,
                            int int_mark)
{
    for (;;) {
        if (is_punct(p, '}'))
            return next(p);
        if (is_transform(p)) {
            if (!parse_transform(p, &o->xform))
                return false;
            continue;
        }
        if (p->tok.kind != CSG_TOK_WORD)
            return expected_close(p, '}', name, open);
        switch (p->tok.kw) {
        case CSG_KW_PIGMENT:
        case CSG_KW_FINISH:
        case CSG_KW_TEXTURE: {
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
            break;
        }
        case CSG_KW_INTERIOR: {
            csg_interior *own = own_interior(p, o, int_mark);
            if (!own)
                return false;
            csg_interior in = *own;
            if (!parse_interior(p, &in))
                return false;
            ((csg_interior *)p->interiors.data)[o->interior] = in;
            break;
        }
        case CSG_KW_INVERSE:
            o->inverse = !o->inverse;
            if (!next(p))
                return false;
            break;
        case CSG_KW_NO_SHADOW:
            o->no_shadow = true;
            if (!next(p))
                return false;
            break;
        case CSG_KW_OPEN:
            if (o->kind != CSG_OBJ_CYLINDER && o->kind != CSG_OBJ_CONE) {
                csg_error(p->d, p->tok.loc, "'open' applies only to cylinder and cone, not to '%s'",
                          name);
                return false;
            }
            o->open = true;
            if (!next(p))
                return false;
            break;
        default:
            return expected_close(p, '}', name, open);
        }
    }
}

/* Any object statement; the current token is its keyword. */
static bool parse_object(parser *p, csg_object **out)
{
    csg_loc loc = p->tok.loc;
    enum csg_kw kw = p->tok.kw;
    const char *name = object_name(kw);
    int tex_mark = p->textures.count, int_mark = p->interiors.count;
    if (!enter(p, loc) || !next(p) || !expect_open(p, name))
        return false;
    pnode *n = NULL;
    bool ok = false;
    switch (kw) {
    case CSG_KW_SPHERE:
        ok = (n = new_node(p, CSG_OBJ_SPHERE, loc)) && parse_sphere(p, &n->obj);
        break;
    case CSG_KW_BOX:
        ok = (n = new_node(p, CSG_OBJ_BOX, loc)) && parse_box(p, &n->obj);
        break;
    case CSG_KW_CYLINDER:
        ok = (n = new_node(p, CSG_OBJ_CYLINDER, loc)) && parse_cylinder(p, &n->obj);
        break;
    case CSG_KW_CONE:
        ok = (n = new_node(p, CSG_OBJ_CONE, loc)) && parse_cone(p, &n->obj);
        break;
    case CSG_KW_PLANE:
        ok = (n = new_node(p, CSG_OBJ_PLANE, loc)) && parse_plane(p, &n->obj);
        break;
    case CSG_KW_UNION:
        ok = (n = new_node(p, CSG_OBJ_UNION, loc)) && parse_children(p, n, name);
        break;
    case CSG_KW_INTERSECTION:
        ok = (n = new_node(p, CSG_OBJ_INTERSECTION, loc)) && parse_children(p, n, name);
        break;
    case CSG_KW_DIFFERENCE:
        ok = (n = new_node(p, CSG_OBJ_DIFFERENCE, loc)) && parse_children(p, n, name);
        break;
    case CSG_KW_MERGE:
        ok = (n = new_node(p, CSG_OBJ_MERGE, loc)) && parse_children(p, n, name);
        break;
    default:
        ok = (n = parse_object_base(p, loc)) != NULL;
        break;
    }
    if (!ok || !parse_modifiers(p, &n->obj, name, loc, tex_mark, int_mark))
        return false;
    leave(p);
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
    if (!next(p) || !expect_open(p, "camera"))
        return false;
    for (;;) {
        if (is_punct(p, '}'))
            break;
        if (p->tok.kind != CSG_TOK_WORD)
            return expected_close(p, '}', "camera", open);
        enum csg_kw kw = p->tok.kw;
        csg_loc at = p->tok.loc;
        dvec3 v;
        double f;
        switch (kw) {
        case CSG_KW_PERSPECTIVE:
            if (!next(p))
                return false;
            continue;
        case CSG_KW_ANGLE:
            if (!next(p) || !parse_float(p, &f, NULL) || !csg_camera_angle(&c, f, at, p->d))
                return false;
            continue;
        case CSG_KW_LOCATION: case CSG_KW_LOOK_AT: case CSG_KW_DIRECTION:
        case CSG_KW_UP: case CSG_KW_RIGHT: case CSG_KW_SKY:
            if (!next(p) || !parse_vector(p, &v, NULL))
                return false;
            break;
        default:
            return expected_close(p, '}', "camera", open);
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
    return next(p);
}

static bool parse_light(parser *p)
{
    csg_light l;
    memset(&l, 0, sizeof l);
    l.loc = p->tok.loc;
    csg_xform x;
    csg_xform_identity(&x);
    bool ok = next(p) && expect_open(p, "light_source") && parse_vector(p, &l.position, NULL);
    if (ok)
        skip_comma(p, &ok);
    if (!ok)
        return false;
    if (!is_color_start(p))
        return expected(p, "a color expected for the light_source");
    if (!parse_rgb(p, l.color))
        return false;
    for (;;) {
        if (is_punct(p, '}'))
            break;
        if (is_transform(p)) {
            if (!parse_transform(p, &x))
                return false;
        } else if (is_kw(p, CSG_KW_SHADOWLESS)) {
            l.shadowless = true;
            if (!next(p))
                return false;
        } else {
            return expected_close(p, '}', "light_source", l.loc);
        }
    }
    dvec3 q = l.position;
    l.position = (dvec3){x.m[0][0] * q.x + x.m[0][1] * q.y + x.m[0][2] * q.z + x.m[0][3],
                         x.m[1][0] * q.x + x.m[1][1] * q.y + x.m[1][2] * q.z + x.m[1][3],
                         x.m[2][0] * q.x + x.m[2][1] * q.y + x.m[2][2] * q.z + x.m[2][3]};
    return vec_push(p, &p->lights, sizeof l, &l) && next(p);
}

static bool parse_background(parser *p)
{
    csg_loc open = p->tok.loc;
    if (!next(p) || !expect_open(p, "background"))
        return false;
    if (!is_color_start(p))
        return expected(p, "a color expected inside 'background'");
    if (!parse_color(p, p->s->background))
        return false;
    if (!is_punct(p, '}'))
        return expected_close(p, '}', "background", open);
    return next(p);
}

static bool parse_global_settings(parser *p)
{
    csg_loc open = p->tok.loc;
    csg_globals *g = &p->s->globals;
    if (!next(p) || !expect_open(p, "global_settings"))
        return false;
    for (;;) {
        if (is_punct(p, '}'))
            return next(p);
        enum csg_kw kw = p->tok.kind == CSG_TOK_WORD ? p->tok.kw : CSG_KW_NONE;
        csg_loc at;
        double f;
        switch (kw) {
        case CSG_KW_AMBIENT_LIGHT:
            if (!next(p) || !parse_rgb(p, g->ambient_light))
                return false;
            continue;
        case CSG_KW_ASSUMED_GAMMA: case CSG_KW_MAX_TRACE_LEVEL: case CSG_KW_ADC_BAILOUT:
            if (!next(p) || !parse_float(p, &f, &at))
                return false;
            break;
        default:
            return expected_close(p, '}', "global_settings", open);
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

static bool expect_semicolon(parser *p, const char *directive, csg_loc at)
{
    if (!is_punct(p, ';')) {
        if (is_unsupported(&p->tok))
            return unsupported(p);
        char got[64];
        csg_token_describe(&p->tok, got, sizeof got);
        csg_error(p->d, p->tok.loc, "';' expected (to end '#%s' at %d:%d), got %s", directive,
                  at.line, at.col, got);
        return false;
    }
    return next(p);
}

static bool parse_declare(parser *p)
{
    csg_loc at = p->tok.loc;
    char directive[16];
    snprintf(directive, sizeof directive, "%.*s", (int)(p->tok.len < 15 ? p->tok.len : 15),
             p->tok.text);
    if (!next(p))
        return false;
    if (!is_ident(p)) {
        char what[64];
        snprintf(what, sizeof what, "an identifier expected after '#%s'", directive);
        return expected(p, what);
    }
    csg_token name = p->tok;
    if (!next(p))
        return false;
    if (!is_punct(p, '=')) {
        char what[80];
        snprintf(what, sizeof what, "'=' expected after '#%s %.*s'", directive,
                 (int)(name.len > 40 ? 40 : name.len), name.text);
        return expected(p, what);
    }
    if (!next(p))
        return false;
    symbol tmp;
    memset(&tmp, 0, sizeof tmp);
    bool needs_semicolon = false;
    if (is_object_start(p)) {
        tmp.kind = SYM_OBJECT;
        if (!parse_object(p, &tmp.object))
            return false;
    } else if (is_kw(p, CSG_KW_PIGMENT)) {
        tmp.kind = SYM_PIGMENT;
        if (!parse_pigment(p, &tmp.pigment))
            return false;
    } else if (is_kw(p, CSG_KW_FINISH)) {
        tmp.kind = SYM_FINISH;
        csg_finish_default(&tmp.finish);
        if (!parse_finish(p, &tmp.finish))
            return false;
    } else if (is_kw(p, CSG_KW_TEXTURE)) {
        tmp.kind = SYM_TEXTURE;
        if (!parse_texture(p, &tmp.texture))
            return false;
    } else if (is_kw(p, CSG_KW_INTERIOR)) {
        tmp.kind = SYM_INTERIOR;
        tmp.interior.ior = 1.0;
        if (!parse_interior(p, &tmp.interior))
            return false;
    } else if (is_kw(p, CSG_KW_COLOR) || is_color_item(p)) {
        tmp.kind = SYM_VALUE;
        tmp.val.dim = 5;
        if (!parse_color(p, tmp.val.v))
            return false;
        needs_semicolon = true;
    } else if (is_expr_start(p)) {
        tmp.kind = SYM_VALUE;
        if (!parse_expr(p, &tmp.val))
            return false;
        needs_semicolon = true;
    } else {
        return expected(p, "a value, color, pigment, finish, texture, interior or object expected");
    }
    if (needs_semicolon) {
        if (!expect_semicolon(p, directive, at))
            return false;
    } else if (is_punct(p, ';') && !next(p)) {
        return false;
    }
    symbol *sym = sym_define(p, name.text, name.len);
    if (!sym)
        return false;
    const char *keep = sym->name;
    size_t keep_len = sym->len;
    *sym = tmp;
    sym->name = keep;
    sym->len = keep_len;
    return true;
}

static bool parse_version(parser *p)
{
    csg_loc at = p->tok.loc;
    double v;
    if (!next(p) || !parse_float(p, &v, NULL))
        return false;
    return expect_semicolon(p, "version", at);
}

static bool declare_builtin_colors(parser *p)
{
    for (int i = 0; i < csg_builtin_color_count(); i++) {
        double c[5];
        const char *name = csg_builtin_color_at(i, c);
        symbol *sym = sym_define(p, name, strlen(name));
        if (!sym)
            return false;
        sym->kind = SYM_VALUE;
        sym->val.dim = 5;
        memcpy(sym->val.v, c, sizeof c);
    }
    return true;
}

/* Reads a whole file into malloc'd memory. */
static char *read_file(const char *path, size_t *len, int *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        *err = errno;
        return NULL;
    }
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        if (n == cap) {
            char *more = cap > SIZE_MAX / 2 ? NULL : realloc(buf, cap * 2);
            if (!more) {
                free(buf);
                buf = NULL;
                *err = ENOMEM;
                break;
            }
            buf = more;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0) {
            if (ferror(f)) {
                *err = errno ? errno : EIO;
                free(buf);
                buf = NULL;
            }
            break;
        }
    }
    if (!buf && *err == 0)
        *err = ENOMEM;
    fclose(f);
    *len = n;
    return buf;
}

/* The canonical name of a file for cycle detection: its real path when it
 * exists, the path itself otherwise (a csg_parse_string name). */
static const char *canonical(parser *p, const char *path)
{
    char *real = realpath(path, NULL);
    const char *r = pstrndup(p, real ? real : path, strlen(real ? real : path));
    free(real);
    return r;
}

static bool parse_statements(parser *p);

/* Reads `text` as the statements of file `path` (already in the arena). */
static bool parse_source(parser *p, const char *path, const char *text, size_t len)
{
    csg_lexer_init(&p->lx, path, text, len);
    return next(p) && parse_statements(p);
}

static bool parse_include(parser *p)
{
    csg_loc at = p->tok.loc;
    if (!next(p))
        return false;
    if (p->tok.kind != CSG_TOK_STRING)
        return expected(p, "a file name in quotes expected after '#include'");
    csg_token name = p->tok;
    if (name.len == strlen("colors.inc") && memcmp(name.text, "colors.inc", name.len) == 0)
        return declare_builtin_colors(p) && next(p);
    if (memchr(name.text, '\0', name.len) || name.len == 0) {
        csg_error(p->d, at, "#include: invalid file name");
        return false;
    }
    /* the path: relative to the including file's directory */
    const char *cur = p->lx.file;
    const char *slash = strrchr(cur, '/');
    size_t dirlen = (name.text[0] != '/' && slash) ? (size_t)(slash - cur + 1) : 0;
    char *path = palloc(p, dirlen + name.len + 1);
    if (!path)
        return false;
    memcpy(path, cur, dirlen);
    memcpy(path + dirlen, name.text, name.len);
    if (p->include_depth >= CSG_PARSE_MAX_INCLUDE) {
        csg_error(p->d, at, "#include nested deeper than %d files", CSG_PARSE_MAX_INCLUDE);
        return false;
    }
    const char *canon = canonical(p, path);
    if (!canon)
        return false;
    for (int i = 0; i <= p->include_depth; i++) {
        if (strcmp(p->include_stack[i], canon) == 0) {
            csg_error(p->d, at, "#include cycle: '%s' is already being read", path);
            return false;
        }
    }
    size_t len = 0;
    int err = 0;
    char *text = read_file(path, &len, &err);
    if (!text) {
        csg_error(p->d, at, "cannot read include file '%s': %s", path, strerror(err));
        return false;
    }
    char *copy = pstrndup(p, text, len);
    free(text);
    if (!copy)
        return false;
    csg_lexer saved = p->lx;
    p->include_stack[++p->include_depth] = canon;
    if (!parse_source(p, path, copy, len))
        return false;
    p->include_depth--;
    p->lx = saved;
    return next(p);
}

static bool parse_statement(parser *p)
{
    if (p->tok.kind == CSG_TOK_DIRECTIVE) {
        switch (p->tok.kw) {
        case CSG_KW_DECLARE:
        case CSG_KW_LOCAL:
            return parse_declare(p);
        case CSG_KW_INCLUDE:
            return parse_include(p);
        case CSG_KW_VERSION:
            return parse_version(p);
        default:
            return expected(p, "a statement expected");
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
    return expected(p, "an object or a statement expected");
}

static bool parse_statements(parser *p)
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
        oom(&p);
        goto fail;
    }
    if (!name)
        name = "<input>";
    char *path = pstrndup(&p, name, strlen(name));
    char *copy = pstrndup(&p, text ? text : "", text ? len : 0);
    if (!path || !copy)
        goto fail;
    s->path = path;
    p.include_stack[0] = canonical(&p, path);
    if (!p.include_stack[0])
        goto fail;
    ok = parse_source(&p, path, copy, text ? len : 0) && finish_scene(&p);
fail:
    free(p.syms);
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

bool csg_parse_file(const char *path, csg_scene *s, csg_diag *d)
{
    size_t len = 0;
    int err = 0;
    char *text = read_file(path, &len, &err);
    if (!text) {
        csg_scene_init(s);
        csg_error_plain(d, "cannot read scene '%s': %s", path, strerror(err));
        return false;
    }
    bool ok = csg_parse_string(path, text, len, s, d);
    free(text);
    return ok;
}
