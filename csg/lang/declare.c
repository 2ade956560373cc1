/*
 * declare.c — what names hold: #declare, #local, #undef, #default, the
 * right-hand values (rvalues) they and macro arguments take, arrays, the
 * lookups of names, and declarations that use a construct csgtrace does
 * not implement.
 *
 *   #declare NAME = RVALUE [;]     #local NAME = RVALUE [;]
 *   #declare NAME[i]... = RVALUE [;]              (an element of an array)
 *   RVALUE := object | pigment {} | finish {} | texture {} | interior {}
 *           | color_map {} | camera {} | array[N]...[{ INITIALISERS }]
 *           | STRING | COLOR | EXPRESSION | IDENTIFIER (a copy)
 *   #undef NAME          #default { texture {} | pigment {} | finish {} }
 *
 * A float, vector or colour must be ended by ';' (as POV-Ray 3.7
 * requires); after the others the ';' is optional, and looked for without
 * running what follows (a raw peek), so a run of declarations is a loop.
 *
 * Unsupported constructs in declarations: POV-Ray's standard include files
 * declare much that csgtrace does not model (normals, functions, other
 * patterns ...).  When a declaration's value fails on such a construct
 * (lang_unsupported, or the use of a name that is itself unusable), the
 * error is not reported: the parse state goes back to where the value
 * began (frames, blocks, scopes and nesting opened since are closed), the
 * value's text is skipped by its shape (skip_rvalue), and the name is bound
 * to SYM_UNSUPPORTED, which remembers the construct and both places.  Using
 * the name later is the error, naming all of it.
 *
 * Arrays: up to 5 dimensions, at most CSG_PARSE_MAX_ARRAY elements; the
 * first element set decides the kind of all of them; an element read
 * before it is set is an error.  Subscripts are truncated like POV-Ray's
 * (k = (int)(f + 1e-10)).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../camera_setup.h"
#include "parse_internal.h"

/* ---- data ------------------------------------------------------------------------ */

static void array_free(lang_array *a)
{
    if (!a)
        return;
    for (long i = 0; i < a->total && a->elems; i++) {
        if (a->elems[i]) {
            lang_datum_free(a->elems[i]);
            free(a->elems[i]);
        }
    }
    free(a->elems);
    free(a);
}

void lang_datum_free(datum *d)
{
    if (d->kind == SYM_STRING)
        free(d->u.str);
    else if (d->kind == SYM_ARRAY)
        array_free(d->u.array);
    d->kind = SYM_VALUE;
}

static lang_array *array_new(parser *p, int dims, const int *size, long total)
{
    lang_array *a = calloc(1, sizeof *a);
    datum **elems = calloc((size_t)total, sizeof *elems);
    if (!a || !elems) {
        free(a);
        free(elems);
        lang_oom(p);
        return NULL;
    }
    a->dims = dims;
    memcpy(a->size, size, sizeof a->size);
    a->total = total;
    a->type = SYM_UNSUPPORTED;
    a->elems = elems;
    return a;
}

bool lang_datum_copy(parser *p, datum *dst, const datum *src)
{
    *dst = *src;
    if (src->kind == SYM_STRING) {
        dst->u.str = strdup(src->u.str);
        return dst->u.str ? true : (dst->kind = SYM_VALUE, lang_oom(p));
    }
    if (src->kind != SYM_ARRAY)
        return true;
    const lang_array *s = src->u.array;
    lang_array *a = array_new(p, s->dims, s->size, s->total);
    dst->kind = SYM_VALUE;
    if (!a)
        return false;
    a->type = s->type;
    for (long i = 0; i < s->total; i++) {
        if (!s->elems[i])
            continue;
        a->elems[i] = malloc(sizeof *a->elems[i]);
        if (!a->elems[i] || !lang_datum_copy(p, a->elems[i], s->elems[i])) {
            free(a->elems[i]);
            a->elems[i] = NULL;
            array_free(a);
            return p->d->failed ? false : lang_oom(p);
        }
    }
    dst->kind = SYM_ARRAY;
    dst->u.array = a;
    return true;
}

/* ---- names ------------------------------------------------------------------------ */

bool lang_use_unsupported(parser *p, const lang_unusable *why, csg_loc at)
{
    if (p->d->failed)
        return false;
    csg_error(p->d, at,
              "unsupported: '%s' (declared at %s:%d:%d) needs %s (%s:%d:%d), which is not in "
              "csgtrace's language (see scenes/LANGUAGE.md)",
              why->name, why->declared_at.file, why->declared_at.line, why->declared_at.col,
              why->construct, why->construct_at.file, why->construct_at.line,
              why->construct_at.col);
    p->unsupported = true;
    p->why = *why;
    return false;
}

/* '[' FLOAT ']' ...: one subscript per dimension of the array `name`; the
 * array is looked up again after them (they may have changed it). */
bool lang_element_slot(parser *p, const csg_token *name, datum ***slot)
{
    symbol *sym = lang_sym_find(p, name->text, name->len);
    int dims = sym && sym->d.kind == SYM_ARRAY ? sym->d.u.array->dims : 0;
    double sub[5];
    for (int i = 0; i < dims; i++) {
        csg_loc open = lang_tok(p)->loc;
        if (!lang_expect_punct(p, '[', "(a subscript of every dimension of the array)") ||
            !lang_enter(p, open) || !lang_parse_float(p, &sub[i], NULL))
            return false;
        if (!lang_is_punct(p, ']'))
            return lang_expected_close(p, ']', "[", open);
        lang_leave(p);
        if (!lang_next(p))
            return false;
    }
    sym = lang_sym_find(p, name->text, name->len);
    if (!sym || sym->d.kind != SYM_ARRAY || sym->d.u.array->dims != dims || dims == 0) {
        csg_error(p->d, name->loc, "'%.*s' is not an array (any more)",
                  (int)(name->len > 40 ? 40 : name->len), name->text);
        return false;
    }
    lang_array *a = sym->d.u.array;
    long index = 0;
    for (int i = 0; i < dims; i++) {
        double k = floor(sub[i] + 1e-10);
        if (!(k >= 0 && k < a->size[i])) {
            csg_error(p->d, name->loc, "subscript %g of '%.*s' out of range (0 to %d)", sub[i],
                      (int)(name->len > 40 ? 40 : name->len), name->text, a->size[i] - 1);
            return false;
        }
        index = index * a->size[i] + (long)k;
    }
    *slot = &a->elems[index];
    return true;
}

bool lang_lookup(parser *p, enum sym_kind want, const char *want_name, const datum **out)
{
    const csg_token *t = lang_tok(p);
    csg_token name = *t;
    symbol *sym = t->kind == CSG_TOK_WORD ? lang_sym_find(p, t->text, t->len) : NULL;
    int n = (int)(name.len > 40 ? 40 : name.len);
    if (!sym) {
        csg_error(p->d, name.loc, "undeclared identifier '%.*s'", n, name.text);
        return false;
    }
    if (!lang_next(p))
        return false;
    const datum *d = &sym->d;
    if (d->kind == SYM_ARRAY && want != SYM_ARRAY && lang_raw_peek_punct(p, '[')) {
        datum **slot;
        if (!lang_element_slot(p, &name, &slot))
            return false;
        if (!*slot) {
            csg_error(p->d, name.loc, "element of array '%.*s' used before it is set", n,
                      name.text);
            return false;
        }
        d = *slot;
    }
    if (d->kind == SYM_UNSUPPORTED)
        return lang_use_unsupported(p, d->u.why, name.loc);
    if (d->kind != want) {
        csg_error(p->d, name.loc, "'%.*s' is %s, not %s", n, name.text, lang_kind_name(d),
                  want_name);
        return false;
    }
    *out = d;
    return true;
}

bool lang_names(parser *p, enum sym_kind kind)
{
    const csg_token *t = lang_tok(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return false;
    symbol *sym = lang_sym_find(p, t->text, t->len);
    if (!sym)
        return false;
    const datum *d = &sym->d;
    if (d->kind == SYM_ARRAY) /* an element: the array's kind and a subscript */
        return (d->u.array->type == kind || d->u.array->type == SYM_UNSUPPORTED) &&
               lang_raw_peek_punct(p, '[');
    return d->kind == kind || d->kind == SYM_UNSUPPORTED;
}

/* ---- arrays ------------------------------------------------------------------------- */

/* Stores *d (taken over) as element `index` of a, checking its kind. */
static bool array_set(parser *p, lang_array *a, long index, datum *d, csg_loc at)
{
    if (a->type != SYM_UNSUPPORTED && d->kind != a->type && d->kind != SYM_UNSUPPORTED) {
        csg_error(p->d, at, "an array holds one kind of element: this one is %s, the array's "
                  "are not", lang_kind_name(d));
        lang_datum_free(d);
        return false;
    }
    if (a->type == SYM_UNSUPPORTED)
        a->type = d->kind;
    if (!a->elems[index] && !(a->elems[index] = malloc(sizeof *a->elems[index]))) {
        lang_datum_free(d);
        return lang_oom(p);
    }
    else if (a->elems[index])
        lang_datum_free(a->elems[index]);
    *a->elems[index] = *d;
    return true;
}

/* '{' element {','} ... '}' for dimension `dim`, from flat index `base`. */
static bool parse_initializer(parser *p, lang_array *a, int dim, long base)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_expect_punct(p, '{', "(an array initialiser)") || !lang_enter(p, open))
        return false;
    long stride = 1;
    for (int i = dim + 1; i < a->dims; i++)
        stride *= a->size[i];
    for (int i = 0; i < a->size[dim]; i++) {
        if (lang_is_punct(p, '}')) {
            csg_error(p->d, lang_tok(p)->loc, "array initialiser: %d elements expected, got %d",
                      a->size[dim], i);
            return false;
        }
        bool ok;
        if (dim + 1 < a->dims) {
            ok = parse_initializer(p, a, dim + 1, base + i * stride);
        } else {
            datum d;
            bool semi;
            csg_loc at = lang_tok(p)->loc;
            ok = lang_parse_rvalue(p, &d, &semi);
            if (!ok)
                lang_datum_free(&d); /* what it made before it failed */
            ok = ok && array_set(p, a, base + i, &d, at);
        }
        if (!ok || (lang_is_punct(p, ',') && !lang_next(p)))
            return false;
    }
    if (!lang_is_punct(p, '}'))
        return lang_expected_close(p, '}', "{", open);
    lang_leave(p);
    return lang_next(p);
}

/* array[N]... [{ ... }] */
static bool parse_array(parser *p, datum *out)
{
    csg_loc at = lang_tok(p)->loc;
    int dims = 0, size[5] = {0};
    long total = 1;
    if (!lang_next(p))
        return false;
    while (lang_is_punct(p, '[')) {
        csg_loc open = lang_tok(p)->loc;
        double n;
        if (dims == 5) {
            csg_error(p->d, open, "an array has at most 5 dimensions");
            return false;
        }
        if (!lang_next(p) || !lang_parse_float(p, &n, NULL))
            return false;
        if (!(n >= 1 && n <= (double)CSG_PARSE_MAX_ARRAY) ||
            (total *= (long)(n + 1e-10)) > CSG_PARSE_MAX_ARRAY) {
            csg_error(p->d, open, "an array has 1 to %ld elements", CSG_PARSE_MAX_ARRAY);
            return false;
        }
        size[dims++] = (int)(n + 1e-10);
        if (!lang_is_punct(p, ']'))
            return lang_expected_close(p, ']', "[", open);
        if (!lang_next(p))
            return false;
        if (lang_tok_raw(p)->kind != CSG_TOK_PUNCT || p->tok.punct != '[')
            break;
    }
    if (dims == 0)
        return lang_expected(p, "'[' expected after 'array'");
    lang_array *a = array_new(p, dims, size, total);
    if (!a)
        return false;
    out->kind = SYM_ARRAY;
    out->u.array = a;
    const csg_token *t = lang_tok_raw(p);
    (void)at;
    return !(t->kind == CSG_TOK_PUNCT && t->punct == '{') || parse_initializer(p, a, 0, 0);
}

/* ---- rvalues --------------------------------------------------------------------------- */

/* IDENTIFIER of any kind but a value: a copy of what it holds. */
static bool copy_named(parser *p, datum *out)
{
    const csg_token *t = lang_tok(p);
    symbol *sym = lang_sym_find(p, t->text, t->len);
    enum sym_kind want = sym->d.kind;
    if (want == SYM_ARRAY && sym->d.u.array->type != SYM_UNSUPPORTED) {
        csg_token name = *t;
        if (!lang_next(p))
            return false;
        if (lang_raw_peek_punct(p, '[')) { /* an element */
            datum **slot;
            if (!lang_element_slot(p, &name, &slot))
                return false;
            if (!*slot) {
                csg_error(p->d, name.loc, "element of array '%.*s' used before it is set",
                          (int)(name.len > 40 ? 40 : name.len), name.text);
                return false;
            }
            if ((*slot)->kind == SYM_UNSUPPORTED)
                return lang_use_unsupported(p, (*slot)->u.why, name.loc);
            return lang_datum_copy(p, out, *slot);
        }
        sym = lang_sym_find(p, name.text, name.len);
        return lang_datum_copy(p, out, &sym->d);
    }
    const datum *d;
    return lang_lookup(p, want, lang_kind_name(&sym->d), &d) && lang_datum_copy(p, out, d);
}

/* Whether the current identifier holds something other than a value
 * (an array of values included: its elements are read by copy_named). */
static bool names_non_value(parser *p)
{
    const csg_token *t = lang_tok(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return false;
    symbol *sym = lang_sym_find(p, t->text, t->len);
    if (!sym || sym->d.kind == SYM_VALUE)
        return false;
    return sym->d.kind != SYM_ARRAY || sym->d.u.array->type != SYM_VALUE ||
           !lang_raw_peek_punct(p, '[');
}

/* The structured kinds: a keyword and its block. */
static bool parse_block_rvalue(parser *p, datum *out)
{
    switch (lang_tok(p)->kw) {
    case CSG_KW_PIGMENT:
        out->kind = SYM_PIGMENT;
        out->u.pigment = p->default_texture.pigment;
        return lang_parse_pigment(p, &out->u.pigment);
    case CSG_KW_FINISH:
        out->kind = SYM_FINISH;
        out->u.finish = p->default_texture.finish;
        return lang_parse_finish(p, &out->u.finish);
    case CSG_KW_TEXTURE: {
        out->kind = SYM_TEXTURE;
        if (!lang_parse_texture(p, &out->u.texture))
            return false;
        for (;;) { /* another texture: a layer over those before (POV-Ray) */
            const csg_token *t = lang_tok_raw(p);
            if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_TEXTURE)
                return true;
            csg_loc at = t->loc;
            csg_texture top, under = out->u.texture;
            if (!lang_parse_texture(p, &top) ||
                !lang_texture_link(p, &under, &top, &out->u.texture, at))
                return false;
        }
    }
    case CSG_KW_NORMAL:
        out->kind = SYM_NORMAL;
        out->u.normal = p->default_texture.normal;
        return lang_parse_normal(p, &out->u.normal);
    case CSG_KW_MATERIAL: {
        lang_material *m = lang_alloc(p, sizeof *m);
        out->kind = SYM_MATERIAL;
        out->u.material = m;
        return m && lang_parse_material(p, m);
    }
    case CSG_KW_INTERIOR:
        out->kind = SYM_INTERIOR;
        out->u.interior.ior = 1.0;
        return lang_parse_interior(p, &out->u.interior);
    case CSG_KW_COLOR_MAP:
        out->kind = SYM_COLOR_MAP;
        return lang_parse_color_map(p, &out->u.cmap);
    case CSG_KW_CAMERA:
        out->kind = SYM_CAMERA;
        csg_camera_default(&out->u.camera);
        return lang_parse_camera(p, &out->u.camera);
    case CSG_KW_SKY_SPHERE: {
        csg_sky *sky = lang_alloc(p, sizeof *sky);
        out->kind = SYM_SKY;
        out->u.sky = sky;
        return sky && lang_parse_sky_sphere(p, sky);
    }
    default: /* CSG_KW_ARRAY */
        return parse_array(p, out);
    }
}

bool lang_parse_rvalue(parser *p, datum *out, bool *needs_semicolon)
{
    memset(out, 0, sizeof *out);
    *needs_semicolon = false;
    const csg_token *t = lang_tok(p);
    if (lang_is_object_start(p)) {
        out->kind = SYM_OBJECT;
        return lang_parse_object(p, &out->u.object);
    }
    if (t->kind == CSG_TOK_WORD) {
        switch (t->kw) {
        case CSG_KW_PIGMENT: case CSG_KW_FINISH: case CSG_KW_TEXTURE: case CSG_KW_INTERIOR:
        case CSG_KW_NORMAL: case CSG_KW_MATERIAL: case CSG_KW_COLOR_MAP: case CSG_KW_CAMERA: case CSG_KW_ARRAY: case CSG_KW_SKY_SPHERE:
            return parse_block_rvalue(p, out);
        case CSG_KW_TRANSFORM:
            out->kind = SYM_TRANSFORM;
            csg_xform_identity(&out->u.transform);
            return lang_parse_transform(p, &out->u.transform);
        case CSG_KW_LIGHT_SOURCE:
            return lang_unsupported(p, "a declared 'light_source'", t->loc);
        default:
            break;
        }
    }
    if (lang_is_string_start(p)) {
        out->kind = SYM_STRING;
        return lang_parse_string(p, &out->u.str);
    }
    if (names_non_value(p))
        return copy_named(p, out);
    out->kind = SYM_VALUE;
    *needs_semicolon = true;
    if (lang_is_kw(p, CSG_KW_COLOR) || lang_is_color_item(p)) {
        out->u.val.dim = 5;
        return lang_parse_color(p, out->u.val.v);
    }
    if (lang_is_expr_start(p))
        return lang_parse_expr(p, &out->u.val);
    return lang_expected(p,
                         "a value, color, pigment, finish, texture, interior or object expected");
}

/* ---- declarations that use unsupported constructs -------------------------------- */

/* Where the value of a declaration began, to go back there. */
typedef struct {
    int frames, conds, nesting, stack, include_depth, macro_depth;
    csg_lexer rhs;
} checkpoint;

static checkpoint checkpoint_here(parser *p)
{
    checkpoint c = {p->frames.count, p->conds.count, p->nesting, p->stack.count,
                    p->include_depth, p->macro_depth, lang_frame(p)->lx};
    return c;
}

static bool continues_rvalue(const csg_token *t)
{
    if (t->kind == CSG_TOK_PUNCT)
        return strchr("+-*/.<>=!&|?:,", t->punct < 128 ? t->punct : 'x') != NULL ||
               t->punct >= CSG_P_LE;
    return t->kind == CSG_TOK_WORD &&
           (t->kw == CSG_KW_TEXTURE || t->kw == CSG_KW_RED || t->kw == CSG_KW_GREEN ||
            t->kw == CSG_KW_BLUE || t->kw == CSG_KW_FILTER || t->kw == CSG_KW_TRANSMIT ||
            t->kw == CSG_KW_RGB || t->kw == CSG_KW_RGBF || t->kw == CSG_KW_RGBT ||
            t->kw == CSG_KW_RGBFT || t->kw == CSG_KW_SRGB || t->kw == CSG_KW_SRGBF ||
            t->kw == CSG_KW_SRGBT || t->kw == CSG_KW_SRGBFT || t->kw == CSG_KW_UNSUPPORTED);
}

/* Whether t may follow a block { } that ends a value: another layer of
 * a texture, or the ';'. */
static bool continues_block(const csg_token *t)
{
    return (t->kind == CSG_TOK_WORD && t->kw == CSG_KW_TEXTURE) ||
           (t->kind == CSG_TOK_PUNCT && t->punct == ';');
}

/* Skips the text of a value by its shape, raw tokens of the current frame:
 * operands, groups ( ) [ ] { } balanced, operators between them; it ends at
 * a ';' (consumed), a directive, a closing bracket it did not open, a token
 * that cannot go on after an operand, or anything but another texture
 * after a { } block (not consumed). */
static bool skip_rvalue(parser *p)
{
    int depth = 0;
    bool after_operand = false, after_block = false;
    for (;;) {
        frame *f = lang_frame(p);
        csg_lexer before = f->lx;
        csg_token t;
        if (!lang_raw_token(p, &t))
            return false;
        bool open = t.kind == CSG_TOK_PUNCT && (t.punct == '(' || t.punct == '[' || t.punct == '{');
        bool close = t.kind == CSG_TOK_PUNCT && (t.punct == ')' || t.punct == ']' || t.punct == '}');
        bool stop = depth == 0 && (t.kind == CSG_TOK_DIRECTIVE || close ||
                                   (after_block && !continues_block(&t)) ||
                                   (after_operand && !open && !continues_rvalue(&t) &&
                                    t.punct != ';'));
        if (t.kind == CSG_TOK_EOF || stop) {
            lang_frame(p)->lx = before;
            return true;
        }
        if (depth == 0 && t.kind == CSG_TOK_PUNCT && t.punct == ';')
            return true;
        depth += open - close;
        if (depth == 0) {
            after_block = close && t.punct == '}';
            after_operand = close || !(t.kind == CSG_TOK_PUNCT && continues_rvalue(&t));
        }
    }
}

/* Goes back to the checkpoint after an unsupported construct, skips the
 * value and binds the name to what made it unusable. */
static bool recover(parser *p, const checkpoint *c, const csg_token *name, csg_loc at,
                    bool local)
{
    lang_unusable *why = lang_alloc(p, sizeof *why);
    if (!why)
        return false;
    *why = p->why;
    why->name = lang_strndup(p, name->text, name->len);
    why->declared_at = at;
    p->d->failed = 0;
    p->d->message[0] = '\0';
    p->unsupported = false;
    while (p->frames.count > c->frames) {
        lang_scope_pop(p);
        p->frames.count--;
    }
    p->conds.count = c->conds;
    p->nesting = c->nesting;
    p->stack.count = c->stack;
    p->include_depth = c->include_depth;
    p->macro_depth = c->macro_depth;
    lang_frame(p)->lx = c->rhs;
    p->tok_ready = false;
    if (!why->name || !skip_rvalue(p))
        return false;
    symbol *sym = local ? lang_sym_local(p, name->text, name->len, name->loc)
                        : lang_sym_declare(p, name->text, name->len, name->loc);
    if (!sym)
        return false;
    datum d;
    memset(&d, 0, sizeof d);
    d.kind = SYM_UNSUPPORTED;
    d.u.why = why;
    lang_sym_assign(sym, &d);
    return true;
}

static bool can_recover(parser *p, const checkpoint *c)
{
    return p->unsupported && p->frames.count >= c->frames &&
           ((frame *)p->frames.data)[c->frames - 1].lx.src == c->rhs.src;
}

/* ---- the directives ------------------------------------------------------------------- */

static bool is_word(const csg_token *t, const char *w)
{
    return t->kind == CSG_TOK_WORD && t->len == strlen(w) && memcmp(t->text, w, t->len) == 0;
}

/* A raw token that must be an identifier (a name being bound), after
 * POV-Ray's optional `deprecated [once] "message"` (accepted, not used). */
static bool expect_name(parser *p, const char *directive, csg_token *name)
{
    const csg_token *t = lang_tok_raw(p);
    if (is_word(t, "deprecated")) {
        char *message = NULL;
        if (!lang_next(p) || (is_word(lang_tok_raw(p), "once") && !lang_next(p)) ||
            !lang_parse_string(p, &message))
            return false;
        free(message);
        t = lang_tok_raw(p);
    }
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE) {
        char what[64];
        snprintf(what, sizeof what, "an identifier expected after '#%s'", directive);
        return lang_expected(p, what);
    }
    *name = *t;
    return lang_next(p);
}

/* The optional ';' after a declaration, looked for without running what
 * follows. */
static bool optional_semicolon(parser *p)
{
    const csg_token *t = lang_tok_raw(p);
    return !(t->kind == CSG_TOK_PUNCT && t->punct == ';') || lang_next(p);
}

/* Binds the value *d (taken over) to the declaration's target. */
static bool bind_value(parser *p, const csg_token *name, bool local, bool element,
                       const double *subs, datum *d, csg_loc at)
{
    if (element) {
        symbol *sym = lang_sym_find(p, name->text, name->len);
        if (!sym || sym->d.kind != SYM_ARRAY) {
            lang_datum_free(d);
            csg_error(p->d, at, "'%.*s' is not an array (any more)", (int)name->len, name->text);
            return false;
        }
        lang_array *a = sym->d.u.array;
        long index = 0;
        for (int i = 0; i < a->dims; i++)
            index = index * a->size[i] + (long)subs[i];
        return array_set(p, a, index, d, at);
    }
    symbol *sym = local ? lang_sym_local(p, name->text, name->len, name->loc)
                        : lang_sym_declare(p, name->text, name->len, name->loc);
    if (!sym) {
        lang_datum_free(d);
        return false;
    }
    lang_sym_assign(sym, d);
    return true;
}

/* NAME[i]...: the subscripts of the element being declared (checked). */
static bool element_target(parser *p, const csg_token *name, double *subs)
{
    datum **slot;
    if (!lang_element_slot(p, name, &slot))
        return false;
    symbol *sym = lang_sym_find(p, name->text, name->len);
    const lang_array *a = sym->d.u.array;
    long index = slot - a->elems;
    for (int i = a->dims - 1; i >= 0; i--) {
        subs[i] = (double)(index % a->size[i]);
        index /= a->size[i];
    }
    return true;
}

bool lang_declare(parser *p, bool local, csg_loc at)
{
    const char *directive = local ? "local" : "declare";
    csg_token name;
    if (!expect_name(p, directive, &name))
        return false;
    symbol *sym = lang_sym_find(p, name.text, name.len);
    bool element = sym && sym->d.kind == SYM_ARRAY && lang_raw_peek_punct(p, '[');
    double subs[5] = {0};
    if (element && !element_target(p, &name, subs))
        return false;
    if (!lang_is_punct(p, '=')) {
        char what[96];
        snprintf(what, sizeof what, "'=' expected after '#%s %.*s'", directive,
                 (int)(name.len > 40 ? 40 : name.len), name.text);
        return lang_expected(p, what);
    }
    if (!lang_next(p))
        return false;
    checkpoint c = checkpoint_here(p);
    datum d;
    bool semi;
    if (!lang_parse_rvalue(p, &d, &semi)) {
        lang_datum_free(&d);
        return !element && can_recover(p, &c) && recover(p, &c, &name, at, local);
    }
    if (semi && !lang_expect_semicolon(p, directive, at)) {
        lang_datum_free(&d);
        return false;
    }
    /* Bound before looking for an optional ';': that look may read past the
     * end of a macro's body or an include file and close its scope (a
     * parameter or a #local of it then went to the outer scope). */
    return bind_value(p, &name, local, element, subs, &d, at) && (semi || optional_semicolon(p));
}

bool lang_undef(parser *p, csg_loc at)
{
    csg_token name;
    (void)at;
    if (!expect_name(p, "undef", &name))
        return false;
    lang_sym_undef(p, name.text, name.len); /* an unknown name: POV-Ray only warns */
    return true;
}

/* #default { texture {} | pigment {} | finish {} ... } */
bool lang_default(parser *p, csg_loc at)
{
    if (!lang_expect_open(p, "#default"))
        return false;
    csg_texture *t = &p->default_texture;
    for (;;) {
        bool ok;
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        if (lang_is_kw(p, CSG_KW_TEXTURE)) {
            csg_texture nt;
            ok = lang_parse_texture(p, &nt);
            if (ok)
                *t = nt;
        } else if (lang_is_kw(p, CSG_KW_PIGMENT)) {
            ok = lang_parse_pigment(p, &t->pigment);
        } else if (lang_is_kw(p, CSG_KW_FINISH)) {
            ok = lang_parse_finish(p, &t->finish);
        } else if (lang_is_kw(p, CSG_KW_NORMAL)) {
            ok = lang_parse_normal(p, &t->normal);
        } else {
            return lang_expected_close(p, '}', "#default", at);
        }
        if (!ok)
            return false;
    }
}
