/*
 * expr.c — values and expressions of the scene language: floats, vectors
 * and colours, evaluated as they are read.
 *
 * Algorithm: precedence climbing as in Lua's subexpr: binary operators by
 * priority ('+' '-' 1, '*' '/' 2, all left-associative) over unary (any
 * number of signs, taken iteratively) over primary (number, '(' expr ')',
 * vector literal, constant, declared identifier).  Values are computed as
 * they are read: a binary operator combines its operands with POV-Ray's
 * promotion rules (a float stands for a vector of the other's size, the
 * shorter vector is padded with zeros); dividing by zero and results that
 * are not finite are errors at the operator.
 * Colours are values too: `color`, rgb ... and a colour expression give
 * the five components rgbft.
 *
 * Invariants: a value has dim 1 (a float) or 2..5 (a vector) and its
 * components past dim are 0 (colour promotion relies on it).  The recursion
 * is bounded: parse_binary nests at most once per priority level, and the
 * only other way down, '(' and '<', enters one level of p->nesting
 * (lang_enter), which never exceeds CSG_PARSE_MAX_NESTING.
 */
#include "expr.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "parse_internal.h"

/* ---- expressions ------------------------------------------------------------ */

static const char *dim_name(int dim)
{
    static const char *const names[] = {"?", "a float", "a 2-component vector",
                                        "a 3-component vector", "a 4-component vector",
                                        "a 5-component vector"};
    return dim >= 1 && dim <= 5 ? names[dim] : names[0];
}

bool lang_is_expr_start(const parser *p)
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

/* An expression that must be a float ("<what>, got a 3-component vector"
 * otherwise); *at (if not NULL): where it starts. */
static bool parse_float_expected(parser *p, const char *what, double *out, csg_loc *at)
{
    csg_loc start = p->tok.loc;
    value v;
    if (!lang_parse_expr(p, &v))
        return false;
    if (v.dim != 1) {
        csg_error(p->d, start, "%s, got %s", what, dim_name(v.dim));
        return false;
    }
    *out = v.v[0];
    if (at)
        *at = start;
    return true;
}

/* '<' expr ',' expr ... '>' with 2 to 5 float components. */
static bool parse_vector_literal(parser *p, value *out)
{
    csg_loc open = p->tok.loc;
    if (!lang_enter(p, open) || !lang_next(p))
        return false;
    out->dim = 0;
    for (;;) {
        csg_loc at;
        double c;
        if (!parse_float_expected(p, "a float expected as a vector component", &c, &at))
            return false;
        if (out->dim == 5) {
            csg_error(p->d, at, "a vector has at most 5 components");
            return false;
        }
        out->v[out->dim++] = c;
        if (!lang_is_punct(p, ','))
            break;
        if (!lang_next(p))
            return false;
    }
    if (!lang_is_punct(p, '>'))
        return lang_expected_close(p, '>', "<", open);
    if (out->dim < 2) {
        csg_error(p->d, open, "a vector needs at least 2 components");
        return false;
    }
    for (int i = out->dim; i < 5; i++)
        out->v[i] = 0;
    lang_leave(p);
    return lang_next(p);
}

static bool parse_primary(parser *p, value *out)
{
    const csg_token *t = &p->tok;
    if (t->kind == CSG_TOK_NUMBER) {
        *out = make_float(t->number);
        return lang_next(p);
    }
    if (lang_is_punct(p, '(')) {
        csg_loc open = t->loc;
        if (!lang_enter(p, open) || !lang_next(p) || !lang_parse_expr(p, out))
            return false;
        if (!lang_is_punct(p, ')'))
            return lang_expected_close(p, ')', "(", open);
        lang_leave(p);
        return lang_next(p);
    }
    if (lang_is_punct(p, '<'))
        return parse_vector_literal(p, out);
    if (t->kind == CSG_TOK_WORD) {
        switch (t->kw) {
        case CSG_KW_PI: *out = make_float(M_PI); return lang_next(p);
        case CSG_KW_TRUE: *out = make_float(1); return lang_next(p);
        case CSG_KW_FALSE: *out = make_float(0); return lang_next(p);
        case CSG_KW_X: *out = make_vec3(1, 0, 0); return lang_next(p);
        case CSG_KW_Y: *out = make_vec3(0, 1, 0); return lang_next(p);
        case CSG_KW_Z: *out = make_vec3(0, 0, 1); return lang_next(p);
        case CSG_KW_NONE: {
            symbol *sym;
            if (!lang_lookup(p, SYM_VALUE, "a float, vector or color", &sym))
                return false;
            *out = sym->val;
            return true;
        }
        default:
            break;
        }
    }
    return lang_expected(p, "an expression expected");
}

/* Unary signs (any number, iteratively) then a primary. */
static bool parse_unary(parser *p, value *out)
{
    bool negate = false;
    while (lang_is_punct(p, '-') || lang_is_punct(p, '+')) {
        if (p->tok.punct == '-')
            negate = !negate;
        if (!lang_next(p))
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

/* The priority of the current token as a binary operator (higher binds
 * tighter); 0 when it is none. */
static int binary_priority(const parser *p)
{
    if (p->tok.kind != CSG_TOK_PUNCT)
        return 0;
    switch (p->tok.punct) {
    case '+': case '-': return 1;
    case '*': case '/': return 2;
    default: return 0;
    }
}

/* unary (op unary)* over the operators of priority > limit, left to right:
 * the right operand of op takes the operators that bind tighter than op. */
static bool parse_binary(parser *p, int limit, value *out)
{
    if (!parse_unary(p, out))
        return false;
    for (int prio = binary_priority(p); prio > limit; prio = binary_priority(p)) {
        char op = p->tok.punct;
        csg_loc at = p->tok.loc;
        value rhs;
        if (!lang_next(p) || !parse_binary(p, prio, &rhs) || !combine(p, out, &rhs, op, at))
            return false;
    }
    return true;
}

bool lang_parse_expr(parser *p, value *out)
{
    return parse_binary(p, 0, out);
}

bool lang_parse_float(parser *p, double *out, csg_loc *at)
{
    return parse_float_expected(p, "a float expected", out, at);
}

/* A 3-vector; a float is promoted to <f, f, f>. */
bool lang_parse_vector(parser *p, dvec3 *out, csg_loc *at)
{
    csg_loc start = p->tok.loc;
    value v;
    if (!lang_parse_expr(p, &v))
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

bool lang_is_color_item(const parser *p)
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

bool lang_is_color_start(const parser *p)
{
    return lang_is_kw(p, CSG_KW_COLOR) || lang_is_color_item(p) || lang_is_expr_start(p);
}

/* rgb / rgbf / rgbt / rgbft E: a float fills every component it sets. */
static bool parse_color_vector(parser *p, enum csg_kw kw, double c[5])
{
    static const int need[] = {3, 4, 4, 5}; /* rgb rgbf rgbt rgbft */
    int k = kw == CSG_KW_RGB ? 0 : kw == CSG_KW_RGBF ? 1 : kw == CSG_KW_RGBT ? 2 : 3;
    char name[8];
    snprintf(name, sizeof name, "%.*s", (int)p->tok.len, p->tok.text);
    if (!lang_next(p))
        return false;
    csg_loc start = p->tok.loc;
    value v;
    if (!lang_parse_expr(p, &v))
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
bool lang_parse_color(parser *p, double c[5])
{
    memset(c, 0, 5 * sizeof c[0]);
    bool keyword = lang_is_kw(p, CSG_KW_COLOR);
    if (keyword && !lang_next(p))
        return false;
    if (lang_is_expr_start(p)) {
        csg_loc start = p->tok.loc;
        value v;
        if (!lang_parse_expr(p, &v))
            return false;
        if (v.dim == 2) {
            csg_error(p->d, start, "a color expected, got %s", dim_name(v.dim));
            return false;
        }
        for (int i = 0; i < 5; i++)
            c[i] = v.dim == 1 ? v.v[0] : v.v[i];
    } else if (!lang_is_color_item(p)) {
        return lang_expected(p, keyword ? "a color expected after 'color'" : "a color expected");
    }
    while (lang_is_color_item(p)) {
        enum csg_kw kw = p->tok.kw;
        if (kw == CSG_KW_RGB || kw == CSG_KW_RGBF || kw == CSG_KW_RGBT || kw == CSG_KW_RGBFT) {
            if (!parse_color_vector(p, kw, c))
                return false;
            continue;
        }
        int i = kw == CSG_KW_RED ? 0 : kw == CSG_KW_GREEN ? 1 : kw == CSG_KW_BLUE ? 2
              : kw == CSG_KW_FILTER ? 3 : 4;
        if (!lang_next(p) || !lang_parse_float(p, &c[i], NULL))
            return false;
    }
    return true;
}

bool lang_parse_rgb(parser *p, double rgb[3])
{
    double c[5];
    if (!lang_parse_color(p, c))
        return false;
    memcpy(rgb, c, 3 * sizeof c[0]);
    return true;
}
