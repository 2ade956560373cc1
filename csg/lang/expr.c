/*
 * expr.c — values and expressions of the scene language: floats, vectors
 * and colours, evaluated as they are read (POV-Ray 3.7's grammar).
 *
 *   full    := logical [ '?' full ':' full ]
 *   logical := relation { ('&' | '|') relation }
 *   relation:= STRING_EXPR op STRING_EXPR
 *            | sum { ('<' | '<=' | '=' | '!=' | '>=' | '>') sum }
 *   sum     := product { ('+' | '-') product }         (lang_parse_expr)
 *   product := unary { ('*' | '/') unary }
 *   unary   := { '-' | '+' | '!' } primary [ '.' component ]
 *   primary := NUMBER | '(' full ')' | '<' sum {[','] sum} '>' | constant
 *            | function '(' ... ')' | IDENTIFIER [ '[' full ']' ... ]
 *
 * Algorithm: precedence climbing as in Lua's subexpr for the binary
 * operators (all left-associative; priorities: ?: 1 below & |, then the
 * comparisons, + -, * /); unary operators are collected iteratively and
 * applied innermost first.  A binary operator combines its operands with
 * POV-Ray's promotion rules (a float stands for a vector of the other's
 * size, the shorter vector is padded with zeros); comparisons and & | work
 * component-wise and give 0 or 1; '=' and '!=' compare within 1e-10, as
 * POV-Ray does.  Dividing by zero and results that are not finite are
 * errors at the operator.  Colours are values too: `color`, rgb ... and a
 * colour expression give the five components rgbft.
 *
 * Invariants: a value has dim 1 (a float) or 2..5 (a vector) and its
 * components past dim are 0 (colour promotion relies on it).  The recursion
 * is bounded: parse_binary nests at most once per priority level, and the
 * only other ways down, '(' '<' and a function's arguments, enter one level
 * of p->nesting (lang_enter), which never exceeds CSG_PARSE_MAX_NESTING.
 */
#include "expr.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parse_internal.h"

#define LANG_EPSILON 1e-10 /* POV-Ray's EPSILON: truth and equality */

/* ---- values ----------------------------------------------------------------- */

const char *lang_dim_name(int dim)
{
    static const char *const names[] = {"?", "a float", "a 2-component vector",
                                        "a 3-component vector", "a 4-component vector",
                                        "a 5-component vector"};
    return dim >= 1 && dim <= 5 ? names[dim] : names[0];
}

bool lang_truth(double v)
{
    return fabs(v) > LANG_EPSILON;
}

bool lang_check_finite(parser *p, const value *v, csg_loc at)
{
    for (int i = 0; i < v->dim; i++) {
        if (!isfinite(v->v[i])) {
            csg_error(p->d, at, "arithmetic overflow: the result is not a finite number");
            return false;
        }
    }
    return true;
}

static value make_float(double f)
{
    value v = {1, {f, 0, 0, 0, 0}};
    return v;
}

bool lang_is_expr_start(parser *p)
{
    const csg_token *t = lang_tok(p);
    if (t->kind == CSG_TOK_NUMBER)
        return true;
    if (t->kind == CSG_TOK_PUNCT)
        return t->punct == '<' || t->punct == '(' || t->punct == '-' || t->punct == '+' ||
               t->punct == '!';
    if (t->kind != CSG_TOK_WORD)
        return false;
    switch (t->kw) {
    case CSG_KW_NONE: case CSG_KW_PI: case CSG_KW_X: case CSG_KW_Y: case CSG_KW_Z:
    case CSG_KW_T: case CSG_KW_U: case CSG_KW_V: case CSG_KW_TRUE: case CSG_KW_FALSE:
    case CSG_KW_CLOCK: case CSG_KW_CLOCK_ON: case CSG_KW_FRAME_NUMBER:
    case CSG_KW_VERSION:
        return true;
    default:
        return lang_is_builtin(t->kw);
    }
}

/* An expression that must be a float ("<what>, got a 3-component vector"
 * otherwise); *at (if not NULL): where it starts. */
static bool parse_float_expected(parser *p, const char *what, double *out, csg_loc *at)
{
    csg_loc start = lang_tok(p)->loc;
    value v;
    if (!lang_parse_expr(p, &v))
        return false;
    if (v.dim != 1) {
        csg_error(p->d, start, "%s, got %s", what, lang_dim_name(v.dim));
        return false;
    }
    *out = v.v[0];
    if (at)
        *at = start;
    return true;
}

/* '<' sum {[','] sum} '>' with 2 to 5 float components (the commas are
 * optional, as in POV-Ray). */
static bool parse_vector_literal(parser *p, value *out)
{
    csg_loc open = lang_tok(p)->loc;
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
        if (lang_is_punct(p, ',')) {
            if (!lang_next(p))
                return false;
            if (lang_is_punct(p, '>') && out->dim >= 2 && out->dim <= 4)
                break; /* POV-Ray takes one comma after the 2nd to 4th component */
        } else if (lang_is_punct(p, '>') || !lang_is_expr_start(p)) {
            break;
        }
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

/* The constants: pi, true/yes/on, false/no/off, x y z t u v, clock,
 * clock_on, frame_number, version. */
static bool parse_constant(parser *p, enum csg_kw kw, value *out)
{
    static const double unit[][5] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 0, 1}, {1, 0}, {0, 1}};
    memset(out, 0, sizeof *out);
    out->dim = 1;
    switch (kw) {
    case CSG_KW_PI: out->v[0] = M_PI; break;
    case CSG_KW_TRUE: out->v[0] = 1; break;
    case CSG_KW_FALSE: out->v[0] = 0; break;
    case CSG_KW_CLOCK: out->v[0] = p->opt.clock; break;
    case CSG_KW_CLOCK_ON: case CSG_KW_FRAME_NUMBER: /* one frame, never an animation */
        out->v[0] = 0;
        break;
    case CSG_KW_VERSION: out->v[0] = p->version; break;
    default: {
        int k = kw == CSG_KW_X ? 0 : kw == CSG_KW_Y ? 1 : kw == CSG_KW_Z ? 2
              : kw == CSG_KW_T ? 3 : kw == CSG_KW_U ? 4 : 5;
        out->dim = k < 3 ? 3 : k == 3 ? 4 : 2;
        memcpy(out->v, unit[k], sizeof unit[k]);
        break;
    }
    }
    return lang_next(p);
}

static bool parse_primary(parser *p, value *out)
{
    const csg_token *t = lang_tok(p);
    if (t->kind == CSG_TOK_NUMBER) {
        *out = make_float(t->number);
        return lang_next(p);
    }
    if (lang_is_punct(p, '(')) {
        csg_loc open = t->loc;
        if (!lang_enter(p, open) || !lang_next(p) || !lang_parse_full_expr(p, out))
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
        case CSG_KW_PI: case CSG_KW_TRUE: case CSG_KW_FALSE: case CSG_KW_X: case CSG_KW_Y:
        case CSG_KW_Z: case CSG_KW_T: case CSG_KW_U: case CSG_KW_V: case CSG_KW_CLOCK:
        case CSG_KW_CLOCK_ON: case CSG_KW_FRAME_NUMBER: case CSG_KW_VERSION:
            return parse_constant(p, t->kw, out);
        case CSG_KW_NONE: {
            const datum *d;
            if (!lang_lookup(p, SYM_VALUE, "a float, vector or color", &d))
                return false;
            *out = d->u.val;
            return true;
        }
        default:
            if (lang_is_builtin(t->kw))
                return lang_parse_builtin(p, out);
            break;
        }
    }
    return lang_expected(p, "an expression expected");
}

/* The component a word after '.' selects (x y z t u v red green blue filter
 * transmit); -1 for gray, -2 for none. */
static int component_of(const csg_token *t)
{
    if (t->kind != CSG_TOK_WORD)
        return -2;
    switch (t->kw) {
    case CSG_KW_X: case CSG_KW_U: case CSG_KW_RED: return 0;
    case CSG_KW_Y: case CSG_KW_V: case CSG_KW_GREEN: return 1;
    case CSG_KW_Z: case CSG_KW_BLUE: return 2;
    case CSG_KW_T: case CSG_KW_FILTER: return 3;
    case CSG_KW_TRANSMIT: return 4;
    case CSG_KW_GRAY: return -1;
    default: return -2;
    }
}

/* value '.' component: one component as a float (.gray: POV-Ray's grey). */
static bool parse_postfix(parser *p, value *v)
{
    while (lang_is_punct(p, '.')) {
        csg_loc at = lang_tok(p)->loc;
        if (!lang_next(p))
            return false;
        int k = component_of(lang_tok(p));
        if (k == -2)
            return lang_expected(p, "x, y, z, t, u, v or a color component expected after '.'");
        if (k == -1) {
            *v = make_float(0.297 * v->v[0] + 0.589 * v->v[1] + 0.114 * v->v[2]);
        } else if (k >= v->dim && !(v->dim == 1 && k == 0)) {
            csg_error(p->d, at, "'.' selects component %d of %s", k + 1, lang_dim_name(v->dim));
            return false;
        } else {
            *v = make_float(v->v[k]);
        }
        if (!lang_next(p))
            return false;
    }
    return true;
}

/* Unary operators (any number, collected iteratively, applied innermost
 * first) then a primary and its component selection. */
static bool parse_unary(parser *p, value *out)
{
    char local[64], *ops = local;
    size_t n = 0, cap = sizeof local;
    bool ok = true;
    while (ok && (lang_is_punct(p, '-') || lang_is_punct(p, '+') || lang_is_punct(p, '!'))) {
        if (n == cap) {
            char *more = malloc(cap * 2);
            if (!more) {
                ok = lang_oom(p);
                break;
            }
            memcpy(more, ops, n);
            if (ops != local)
                free(ops);
            ops = more;
            cap *= 2;
        }
        ops[n++] = (char)lang_tok(p)->punct;
        ok = lang_next(p);
    }
    ok = ok && parse_primary(p, out) && parse_postfix(p, out);
    while (ok && n > 0) {
        char op = ops[--n];
        for (int i = 0; i < out->dim; i++)
            out->v[i] = op == '-' ? -out->v[i] : op == '!' ? !lang_truth(out->v[i]) : out->v[i];
    }
    if (ops != local)
        free(ops);
    return ok;
}

/* One component of a op b. */
static bool apply_op(parser *p, int op, double a, double b, double *r, csg_loc at)
{
    switch (op) {
    case '+': *r = a + b; break;
    case '-': *r = a - b; break;
    case '*': *r = a * b; break;
    case '/':
        if (b == 0) {
            csg_error(p->d, at, "division by zero");
            return false;
        }
        *r = a / b;
        break;
    case '<': *r = a < b; break;
    case '>': *r = a > b; break;
    case '=': *r = !lang_truth(a - b); break;
    case CSG_P_NE: *r = lang_truth(a - b); break;
    case CSG_P_LE: *r = a <= b || !lang_truth(a - b); break;
    case CSG_P_GE: *r = a >= b || !lang_truth(a - b); break;
    case '&': *r = lang_truth(a) && lang_truth(b); break;
    default: *r = lang_truth(a) || lang_truth(b); break; /* '|' */
    }
    return true;
}

/* a op b, a float promoted to the other operand's size, the shorter
 * vector padded with zeros (POV-Ray's promotion rules). */
static bool combine(parser *p, value *a, const value *b, int op, csg_loc at)
{
    int dim = a->dim > b->dim ? a->dim : b->dim;
    double x[5], y[5];
    for (int i = 0; i < 5; i++) {
        x[i] = a->dim == 1 ? a->v[0] : (i < a->dim ? a->v[i] : 0);
        y[i] = b->dim == 1 ? b->v[0] : (i < b->dim ? b->v[i] : 0);
    }
    for (int i = 0; i < dim; i++)
        if (!apply_op(p, op, x[i], y[i], &x[i], at))
            return false;
    a->dim = dim;
    for (int i = 0; i < 5; i++)
        a->v[i] = i < dim ? x[i] : 0;
    return lang_check_finite(p, a, at);
}

/* The priority of the current token as a binary operator (higher binds
 * tighter); 0 when it is none, or one `limit_full` excludes. */
static int binary_priority(parser *p, bool full)
{
    const csg_token *t = lang_tok(p);
    if (t->kind != CSG_TOK_PUNCT)
        return 0;
    switch (t->punct) {
    case '*': case '/': return 4;
    case '+': case '-': return 3;
    case '<': case '>': case '=': case CSG_P_NE: case CSG_P_LE: case CSG_P_GE: return full ? 2 : 0;
    case '&': case '|': return full ? 1 : 0;
    default: return 0;
    }
}

static bool parse_binary(parser *p, int limit, bool full, value *out);

/* STRING op STRING: a comparison of two string expressions (0 or 1). */
static bool parse_string_relation(parser *p, value *out)
{
    char *a = NULL, *b = NULL;
    bool ok = lang_parse_string(p, &a);
    int prio = ok ? binary_priority(p, true) : 0;
    if (ok && prio != 2)
        ok = lang_expected(p, "a comparison expected after a string");
    int op = ok ? lang_tok(p)->punct : 0;
    csg_loc at = lang_tok(p)->loc;
    ok = ok && lang_next(p) && lang_parse_string(p, &b);
    if (ok) {
        int c = strcmp(a, b);
        double r;
        ok = apply_op(p, op, c, 0, &r, at);
        *out = make_float(r);
    }
    free(a);
    free(b);
    return ok;
}

/* unary (op unary)* over the operators of priority > limit, left to right:
 * the right operand of op takes the operators that bind tighter than op. */
static bool parse_binary(parser *p, int limit, bool full, value *out)
{
    if (full && limit < 2 && lang_is_string_start(p)) {
        if (!parse_string_relation(p, out))
            return false;
    } else if (!parse_unary(p, out)) {
        return false;
    }
    for (int prio = binary_priority(p, full); prio > limit; prio = binary_priority(p, full)) {
        int op = lang_tok(p)->punct;
        csg_loc at = lang_tok(p)->loc;
        value rhs;
        if (!lang_next(p) || !parse_binary(p, prio, full, &rhs) || !combine(p, out, &rhs, op, at))
            return false;
    }
    return true;
}

bool lang_parse_expr(parser *p, value *out)
{
    return parse_binary(p, 0, false, out);
}

bool lang_parse_full_expr(parser *p, value *out)
{
    csg_loc at = lang_tok(p)->loc;
    if (!parse_binary(p, 0, true, out))
        return false;
    if (!lang_is_punct(p, '?'))
        return true;
    if (out->dim != 1) {
        csg_error(p->d, at, "the condition before '?' must be a float, got %s",
                  lang_dim_name(out->dim));
        return false;
    }
    bool holds = lang_truth(out->v[0]);
    value a, b;
    csg_loc q = lang_tok(p)->loc;
    if (!lang_enter(p, q) || !lang_next(p) || !lang_parse_full_expr(p, &a))
        return false;
    if (!lang_is_punct(p, ':'))
        return lang_expected(p, "':' expected after '?' and its value");
    if (!lang_next(p) || !lang_parse_full_expr(p, &b))
        return false;
    lang_leave(p);
    *out = holds ? a : b;
    return true;
}

bool lang_parse_float(parser *p, double *out, csg_loc *at)
{
    return parse_float_expected(p, "a float expected", out, at);
}

bool lang_parse_float_param(parser *p, double *out)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_is_punct(p, '('))
        return lang_expected(p, "'(' expected");
    value v;
    if (!lang_enter(p, open) || !lang_next(p) || !lang_parse_full_expr(p, &v))
        return false;
    if (v.dim != 1) {
        csg_error(p->d, open, "a float expected, got %s", lang_dim_name(v.dim));
        return false;
    }
    if (!lang_is_punct(p, ')'))
        return lang_expected_close(p, ')', "(", open);
    lang_leave(p);
    *out = v.v[0];
    return lang_next(p);
}

/* A 3-vector; a float is promoted to <f, f, f>, a 2-vector to <u, v, 0>
 * (POV-Ray's Parse_Vector fills the terms it is not given with 0). */
bool lang_parse_vector(parser *p, dvec3 *out, csg_loc *at)
{
    csg_loc start = lang_tok(p)->loc;
    value v;
    if (!lang_parse_expr(p, &v))
        return false;
    if (v.dim == 1) {
        v.v[1] = v.v[2] = v.v[0];
    } else if (v.dim == 2) {
        v.v[2] = 0.0;
    } else if (v.dim != 3) {
        csg_error(p->d, start, "a 3-component vector expected, got %s", lang_dim_name(v.dim));
        return false;
    }
    *out = (dvec3){v.v[0], v.v[1], v.v[2]};
    if (at)
        *at = start;
    return true;
}

/* ---- colours ---------------------------------------------------------------- */

bool lang_is_color_item(parser *p)
{
    const csg_token *t = lang_tok(p);
    if (t->kind != CSG_TOK_WORD)
        return false;
    switch (t->kw) {
    case CSG_KW_RGB: case CSG_KW_RGBF: case CSG_KW_RGBT: case CSG_KW_RGBFT:
    case CSG_KW_SRGB: case CSG_KW_SRGBF: case CSG_KW_SRGBT: case CSG_KW_SRGBFT:
    case CSG_KW_RED: case CSG_KW_GREEN: case CSG_KW_BLUE: case CSG_KW_FILTER:
    case CSG_KW_TRANSMIT:
        return true;
    default:
        return false;
    }
}

bool lang_is_color_start(parser *p)
{
    return lang_is_kw(p, CSG_KW_COLOR) || lang_is_color_item(p) || lang_is_expr_start(p);
}

static bool is_rgb_keyword(enum csg_kw kw)
{
    return kw == CSG_KW_RGB || kw == CSG_KW_RGBF || kw == CSG_KW_RGBT || kw == CSG_KW_RGBFT ||
           kw == CSG_KW_SRGB || kw == CSG_KW_SRGBF || kw == CSG_KW_SRGBT || kw == CSG_KW_SRGBFT;
}

/* POV-Ray's decoding of an srgb component into the working gamma space
 * (in float, as its colours are): the sRGB curve's inverse, then the
 * working gamma's encoding (TranscodingGammaCurve::Decode; assumed_gamma
 * srgb leaves the value as it is). */
static double srgb_decode(const csg_globals *g, double v)
{
    if (g->gamma_kind == CSG_GAMMA_SRGB)
        return (float)v;
    float x = (float)v;
    float lin = x < 0.04045f ? x / 12.92f : powf((x + 0.055f) / 1.055f, 2.4f);
    float enc = 1.0f / (float)g->assumed_gamma;
    if (fabs(1.0 - (double)enc) <= 0.01) /* a neutral working gamma */
        return lin;
    return powf(lin > 0.0f ? lin : 0.0f, enc);
}

/* rgb / rgbf / rgbt / rgbft E: a float fills every component it sets; the
 * srgb forms decode red, green and blue (an error before assumed_gamma is
 * set, as in POV-Ray). */
static bool parse_color_vector(parser *p, enum csg_kw kw, double c[5])
{
    static const int need[] = {3, 4, 4, 5}; /* rgb rgbf rgbt rgbft */
    bool srgb = kw == CSG_KW_SRGB || kw == CSG_KW_SRGBF || kw == CSG_KW_SRGBT ||
                kw == CSG_KW_SRGBFT;
    int k = kw == CSG_KW_RGB || kw == CSG_KW_SRGB     ? 0
            : kw == CSG_KW_RGBF || kw == CSG_KW_SRGBF ? 1
            : kw == CSG_KW_RGBT || kw == CSG_KW_SRGBT ? 2
                                                      : 3;
    char name[8]; /* (a word: no NUL inside; a copy, not snprintf, on this hot path) */
    size_t name_len = p->tok.len < 7 ? p->tok.len : 7;
    memcpy(name, p->tok.text, name_len);
    name[name_len] = '\0';
    if (srgb && p->s->globals.gamma_kind == CSG_GAMMA_UNSET) {
        csg_error(p->d, p->tok.loc, "'%s' colors need assumed_gamma set before them "
                                    "(in global_settings), as in POV-Ray", name);
        return false;
    }
    if (!lang_next(p))
        return false;
    csg_loc start = lang_tok(p)->loc;
    value v;
    if (!lang_parse_full_expr(p, &v))
        return false;
    if (v.dim != 1 && v.dim < need[k]) {
        csg_error(p->d, start, "'%s' needs a float or a %d-component vector, got %s", name,
                  need[k], lang_dim_name(v.dim));
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
    if (srgb)
        for (int i = 0; i < 3; i++)
            c[i] = srgb_decode(&p->s->globals, c[i]);
    return true;
}

/* COLOR: ['color'|'colour'] then items; the first item may be an
 * expression (a float sets all five components, as in POV-Ray; a 3-, 4- or
 * 5-vector sets rgb, rgbf or rgbft), and rgb, rgbf, rgbt, rgbft are items
 * only in the first place (so `checker rgb 1 rgb 0` is two colours, as in
 * POV-Ray); red, green, blue, filter, transmit may follow anything.
 * Starts from all zeros. */
bool lang_parse_color(parser *p, double c[5])
{
    memset(c, 0, 5 * sizeof c[0]);
    bool keyword = lang_is_kw(p, CSG_KW_COLOR);
    if (keyword && !lang_next(p))
        return false;
    bool started = lang_is_expr_start(p);
    if (started) {
        csg_loc start = lang_tok(p)->loc;
        value v;
        if (!lang_parse_full_expr(p, &v))
            return false;
        if (v.dim == 2) {
            csg_error(p->d, start, "a color expected, got %s", lang_dim_name(v.dim));
            return false;
        }
        for (int i = 0; i < 5; i++)
            c[i] = v.dim == 1 ? v.v[0] : v.v[i];
    } else if (!lang_is_color_item(p)) {
        return lang_expected(p, keyword ? "a color expected after 'color'" : "a color expected");
    }
    for (bool first = !started; lang_is_color_item(p); first = false) {
        enum csg_kw kw = p->tok.kw;
        if (is_rgb_keyword(kw)) {
            if (!first) /* POV-Ray: only as the first item (checker rgb 1 rgb 0) */
                break;
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
