/*
 * builtins.c — the built-in functions of POV-Ray 3.7's expressions that
 * csgtrace implements: float functions (abs ... tanh, min, max, select,
 * seed, rand, ...), vector functions (vlength, vdot, vnormalize, vcross,
 * vrotate, vaxis_rotate), functions of strings (strlen, strcmp, val, asc)
 * and of names (defined, dimensions, dimension_size).
 *
 * Arguments follow POV-Ray's forms: f(x) takes a full expression in
 * parentheses; f(a, b) and the lists of min/max take sums (the commas are
 * optional, as in POV-Ray).  Domain errors are errors (sqrt of a negative,
 * log of a non-positive, pow(0, 0), atan2(0, 0)); acos and asin clamp their
 * argument to [-1, 1] as POV-Ray does; int() and div() of a value out of
 * the int range are errors (POV-Ray's cast would be undefined).
 *
 * seed(n) opens a random stream and returns its number; rand(s) advances
 * stream s by POV-Ray's generator: next = next * 1812433253 + 12345 (mod
 * 2^32), result next / (2^32 - 1), so random scenes place objects exactly
 * where POV-Ray does.
 */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parse_internal.h"

enum arity { ONE, TWO, LIST };

typedef struct {
    enum csg_kw kw;
    const char *name;
    enum arity arity;
} builtin;

static const builtin builtins[] = {
    {CSG_KW_ABS, "abs", ONE},       {CSG_KW_ACOS, "acos", ONE},     {CSG_KW_ACOSH, "acosh", ONE},
    {CSG_KW_ASIN, "asin", ONE},     {CSG_KW_ASINH, "asinh", ONE},   {CSG_KW_ATAN, "atan", ONE},
    {CSG_KW_ATAN2, "atan2", TWO},   {CSG_KW_ATANH, "atanh", ONE},   {CSG_KW_CEIL, "ceil", ONE},
    {CSG_KW_COS, "cos", ONE},       {CSG_KW_COSH, "cosh", ONE},     {CSG_KW_DEGREES, "degrees", ONE},
    {CSG_KW_DIV, "div", TWO},       {CSG_KW_EXP, "exp", ONE},       {CSG_KW_FLOOR, "floor", ONE},
    {CSG_KW_INT, "int", ONE},       {CSG_KW_LN, "ln", ONE},         {CSG_KW_LOG, "log", ONE},
    {CSG_KW_MAX, "max", LIST},      {CSG_KW_MIN, "min", LIST},      {CSG_KW_MOD, "mod", TWO},
    {CSG_KW_POW, "pow", TWO},       {CSG_KW_RADIANS, "radians", ONE},
    {CSG_KW_SELECT, "select", LIST}, {CSG_KW_SIN, "sin", ONE},      {CSG_KW_SINH, "sinh", ONE},
    {CSG_KW_SQR, "sqr", ONE},       {CSG_KW_SQRT, "sqrt", ONE},     {CSG_KW_TAN, "tan", ONE},
    {CSG_KW_TANH, "tanh", ONE},     {CSG_KW_SEED, "seed", ONE},     {CSG_KW_RAND, "rand", ONE},
    {CSG_KW_BITWISE_AND, "bitwise_and", LIST}, {CSG_KW_BITWISE_OR, "bitwise_or", LIST},
    {CSG_KW_BITWISE_XOR, "bitwise_xor", LIST},
};

static const builtin *find_builtin(int kw)
{
    for (size_t i = 0; i < sizeof builtins / sizeof builtins[0]; i++)
        if ((int)builtins[i].kw == kw)
            return &builtins[i];
    return NULL;
}

bool lang_is_builtin(int kw)
{
    switch (kw) {
    case CSG_KW_VDOT: case CSG_KW_VLENGTH: case CSG_KW_VCROSS: case CSG_KW_VNORMALIZE:
    case CSG_KW_VROTATE: case CSG_KW_VAXIS_ROTATE: case CSG_KW_STRLEN: case CSG_KW_STRCMP:
    case CSG_KW_VAL: case CSG_KW_ASC: case CSG_KW_DEFINED: case CSG_KW_DIMENSIONS:
    case CSG_KW_DIMENSION_SIZE: case CSG_KW_FILE_EXISTS:
        return true;
    default:
        return find_builtin(kw) != NULL;
    }
}

static value fval(double f)
{
    value v = {1, {f, 0, 0, 0, 0}};
    return v;
}

static value vval(double x, double y, double z)
{
    value v = {3, {x, y, z, 0, 0}};
    return v;
}

/* ---- argument lists ------------------------------------------------------------- */

/* '(' after the function's name; enters one level of nesting. */
static bool open_args(parser *p, csg_loc *open)
{
    if (!lang_next(p))
        return false;
    *open = lang_tok(p)->loc;
    if (!lang_is_punct(p, '('))
        return lang_expected(p, "'(' expected after the function's name");
    return lang_enter(p, *open) && lang_next(p);
}

static bool close_args(parser *p, csg_loc open)
{
    if (!lang_is_punct(p, ')'))
        return lang_expected_close(p, ')', "(", open);
    lang_leave(p);
    return lang_next(p);
}

/* An optional ',' between arguments (POV-Ray's Parse_Comma). */
static bool skip_comma(parser *p)
{
    return !lang_is_punct(p, ',') || lang_next(p);
}

/* Up to `max` floats separated by optional commas; *n how many. */
static bool float_list(parser *p, double *vals, int max, int min, const char *name, int *n)
{
    *n = 0;
    for (;;) {
        csg_loc at = lang_tok(p)->loc;
        if (*n == max) {
            csg_error(p->d, at, "'%s' takes at most %d arguments", name, max);
            return false;
        }
        if (!lang_parse_float(p, &vals[(*n)++], NULL) || !skip_comma(p))
            return false;
        if (lang_is_punct(p, ')'))
            break;
    }
    if (*n < min) {
        csg_error(p->d, lang_tok(p)->loc, "'%s' needs at least %d arguments, got %d", name, min,
                  *n);
        return false;
    }
    return true;
}

/* ---- float functions ------------------------------------------------------------ */

static bool domain(parser *p, csg_loc at, const char *name, double x)
{
    csg_error(p->d, at, "'%s' is not defined for %g", name, x);
    return false;
}

/* (double)(int)x, POV-Ray's int(): an error outside the int range. */
static bool to_int(parser *p, csg_loc at, const char *name, double x, double *out)
{
    if (!(x > (double)INT_MIN - 1 && x < (double)INT_MAX + 1))
        return domain(p, at, name, x);
    *out = (double)(int)x;
    return true;
}

static bool apply_one(parser *p, enum csg_kw kw, double x, csg_loc at, double *r);

static bool rand_value(parser *p, double x, csg_loc at, double *r)
{
    long s = (long)x;
    if (!(x >= 0 && x < (double)p->rand_streams.count)) {
        csg_error(p->d, at, "rand: %g is not a random stream made by seed()", x);
        return false;
    }
    unsigned int *next = (unsigned int *)p->rand_streams.data + s;
    *next = (unsigned int)(*next * 1812433253u + 12345u);
    *r = (double)(*next & 0xFFFFFFFFu) / (double)0xFFFFFFFFu;
    return true;
}

static bool seed_value(parser *p, double x, csg_loc at, double *r)
{
    double i;
    if (!to_int(p, at, "seed", x, &i))
        return false;
    unsigned int s = (unsigned int)(int)i;
    if (!lang_vec_push(p, &p->rand_streams, sizeof s, &s))
        return false;
    *r = p->rand_streams.count - 1;
    return true;
}

static bool apply_one(parser *p, enum csg_kw kw, double x, csg_loc at, double *r)
{
    switch (kw) {
    case CSG_KW_ABS: *r = fabs(x); break;
    case CSG_KW_ACOS: *r = acos(x > 1 ? 1 : x < -1 ? -1 : x); break;
    case CSG_KW_ASIN: *r = asin(x > 1 ? 1 : x < -1 ? -1 : x); break;
    case CSG_KW_ACOSH: *r = acosh(x); break;
    case CSG_KW_ASINH: *r = asinh(x); break;
    case CSG_KW_ATAN: *r = atan(x); break;
    case CSG_KW_ATANH: *r = atanh(x); break;
    case CSG_KW_CEIL: *r = ceil(x); break;
    case CSG_KW_COS: *r = cos(x); break;
    case CSG_KW_COSH: *r = cosh(x); break;
    case CSG_KW_DEGREES: *r = x / (M_PI / 180.0); break;
    case CSG_KW_EXP: *r = exp(x); break;
    case CSG_KW_FLOOR: *r = floor(x); break;
    case CSG_KW_INT: return to_int(p, at, "int", x, r);
    case CSG_KW_LN:
        if (x <= 0)
            return domain(p, at, "ln", x);
        *r = log(x);
        break;
    case CSG_KW_LOG:
        if (x <= 0)
            return domain(p, at, "log", x);
        *r = log10(x);
        break;
    case CSG_KW_RADIANS: *r = x * (M_PI / 180.0); break;
    case CSG_KW_SIN: *r = sin(x); break;
    case CSG_KW_SINH: *r = sinh(x); break;
    case CSG_KW_SQR: *r = x * x; break;
    case CSG_KW_SQRT:
        if (x < 0)
            return domain(p, at, "sqrt", x);
        *r = sqrt(x);
        break;
    case CSG_KW_TAN: *r = tan(x); break;
    case CSG_KW_TANH: *r = tanh(x); break;
    case CSG_KW_SEED: return seed_value(p, x, at, r);
    default: return rand_value(p, x, at, r); /* CSG_KW_RAND */
    }
    return true;
}

static bool apply_two(parser *p, enum csg_kw kw, double a, double b, csg_loc at, double *r)
{
    switch (kw) {
    case CSG_KW_ATAN2:
        if (!lang_truth(a) && !lang_truth(b)) {
            csg_error(p->d, at, "'atan2' is not defined for (0, 0)");
            return false;
        }
        *r = atan2(a, b);
        return true;
    case CSG_KW_DIV:
        if (b == 0) {
            csg_error(p->d, at, "division by zero");
            return false;
        }
        return to_int(p, at, "div", a / b, r);
    case CSG_KW_MOD:
        if (b == 0) {
            csg_error(p->d, at, "division by zero");
            return false;
        }
        *r = fmod(a, b);
        return true;
    default: /* CSG_KW_POW */
        if (a == 0 && b == 0) {
            csg_error(p->d, at, "'pow' is not defined for (0, 0)");
            return false;
        }
        *r = pow(a, b);
        return true;
    }
}

/* min, max, select, bitwise_*: over the list. */
static bool apply_list(parser *p, enum csg_kw kw, const double *v, int n, csg_loc at, double *r)
{
    if (kw == CSG_KW_SELECT) {
        *r = v[0] < 0 ? v[1] : (v[0] == 0 || n == 3) ? v[2] : v[3];
        return true;
    }
    if (kw == CSG_KW_MIN || kw == CSG_KW_MAX) {
        *r = v[0];
        for (int i = 1; i < n; i++)
            *r = kw == CSG_KW_MIN ? fmin(*r, v[i]) : fmax(*r, v[i]);
        return true;
    }
    double acc;
    if (!to_int(p, at, "bitwise", v[0], &acc))
        return false;
    int bits = (int)acc;
    for (int i = 1; i < n; i++) {
        double x;
        if (!to_int(p, at, "bitwise", v[i], &x))
            return false;
        bits = kw == CSG_KW_BITWISE_AND ? bits & (int)x : kw == CSG_KW_BITWISE_OR ? bits | (int)x
                                                                               : bits ^ (int)x;
    }
    *r = bits;
    return true;
}

static bool parse_float_function(parser *p, const builtin *b, value *out)
{
    csg_loc at = lang_tok(p)->loc;
    double x, vals[64], r = 0;
    int n = 0;
    if (b->arity == ONE) {
        if (!lang_next(p) || !lang_parse_float_param(p, &x) || !apply_one(p, b->kw, x, at, &r))
            return false;
    } else {
        csg_loc open;
        int max = b->arity == TWO ? 2 : b->kw == CSG_KW_SELECT ? 4 : 64;
        int min = b->arity == TWO ? 2 : b->kw == CSG_KW_SELECT ? 3 : 1;
        if (!open_args(p, &open) || !float_list(p, vals, max, min, b->name, &n) ||
            !close_args(p, open))
            return false;
        bool ok = b->arity == TWO ? apply_two(p, b->kw, vals[0], vals[1], at, &r)
                                  : apply_list(p, b->kw, vals, n, at, &r);
        if (!ok)
            return false;
    }
    *out = fval(r);
    return lang_check_finite(p, out, at);
}

/* ---- vector functions ------------------------------------------------------------ */

/* '(' v [',' w] ')': one or two 3-vectors. */
static bool vector_args(parser *p, dvec3 *a, dvec3 *b, bool two)
{
    csg_loc open;
    if (!open_args(p, &open) || !lang_parse_vector(p, a, NULL))
        return false;
    if (two && (!skip_comma(p) || !lang_parse_vector(p, b, NULL)))
        return false;
    return close_args(p, open);
}

static double dot3(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/* vaxis_rotate(V, AXIS, DEGREES): POV-Ray's axis rotation, row vectors. */
static bool axis_rotate(parser *p, value *out)
{
    csg_loc open;
    dvec3 v, axis;
    double deg;
    if (!open_args(p, &open) || !lang_parse_vector(p, &v, NULL) || !skip_comma(p) ||
        !lang_parse_vector(p, &axis, NULL) || !skip_comma(p) ||
        !lang_parse_float(p, &deg, NULL) || !close_args(p, open))
        return false;
    double len = sqrt(dot3(axis, axis));
    if (!(len > 0)) {
        csg_error(p->d, open, "vaxis_rotate: the axis is a zero vector");
        return false;
    }
    double a[3] = {axis.x / len, axis.y / len, axis.z / len}, c = cos(deg * M_PI / 180.0),
           s = sin(deg * M_PI / 180.0), m[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            m[i][j] = a[i] * a[j] * (1 - c) + (i == j ? c : 0);
    m[0][1] += a[2] * s, m[0][2] -= a[1] * s, m[1][0] -= a[2] * s;
    m[1][2] += a[0] * s, m[2][0] += a[1] * s, m[2][1] -= a[0] * s;
    double in[3] = {v.x, v.y, v.z}, r[3];
    for (int j = 0; j < 3; j++)
        r[j] = in[0] * m[0][j] + in[1] * m[1][j] + in[2] * m[2][j];
    *out = vval(r[0], r[1], r[2]);
    return true;
}

static bool parse_vector_function(parser *p, enum csg_kw kw, value *out)
{
    dvec3 a, b = {0, 0, 0};
    if (kw == CSG_KW_VAXIS_ROTATE)
        return axis_rotate(p, out);
    if (!vector_args(p, &a, &b, kw != CSG_KW_VLENGTH && kw != CSG_KW_VNORMALIZE))
        return false;
    double len = sqrt(dot3(a, a));
    switch (kw) {
    case CSG_KW_VLENGTH: *out = fval(len); break;
    case CSG_KW_VDOT: *out = fval(dot3(a, b)); break;
    case CSG_KW_VNORMALIZE: *out = len > 0 ? vval(a.x / len, a.y / len, a.z / len) : vval(0, 0, 0);
        break;
    case CSG_KW_VCROSS:
        *out = vval(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
        break;
    default: { /* CSG_KW_VROTATE: POV-Ray's rotate <x, y, z> of the point */
        csg_xform x;
        csg_xform_identity(&x);
        csg_xform_rotate(&x, b);
        *out = vval(dot3((dvec3){x.m[0][0], x.m[0][1], x.m[0][2]}, a),
                    dot3((dvec3){x.m[1][0], x.m[1][1], x.m[1][2]}, a),
                    dot3((dvec3){x.m[2][0], x.m[2][1], x.m[2][2]}, a));
        break;
    }
    }
    return true;
}

/* ---- functions of strings and names ---------------------------------------------- */

static bool parse_string_function(parser *p, enum csg_kw kw, value *out)
{
    csg_loc at = lang_tok(p)->loc, open;
    char *a = NULL, *b = NULL;
    bool ok = open_args(p, &open) && lang_parse_string(p, &a);
    if (ok && kw == CSG_KW_STRCMP)
        ok = skip_comma(p) && lang_parse_string(p, &b);
    ok = ok && close_args(p, open);
    if (ok) {
        double r = kw == CSG_KW_STRLEN   ? (double)strlen(a)
                 : kw == CSG_KW_STRCMP ? (double)strcmp(a, b)
                 : kw == CSG_KW_ASC    ? (double)(unsigned char)a[0]
                                         : atof(a); /* CSG_KW_VAL */
        *out = fval(r);
        if (!isfinite(r)) { /* (strtod reads nan, inf and 1e999 too) */
            csg_error(p->d, at, "val(\"%.40s\"): not a finite number", a);
            ok = false;
        }
    }
    free(a);
    free(b);
    return ok;
}

/* defined(NAME), dimensions(ARRAY), dimension_size(ARRAY, N). */
static bool parse_name_function(parser *p, enum csg_kw kw, value *out)
{
    csg_loc open;
    if (!open_args(p, &open))
        return false;
    const csg_token *t = lang_tok_raw(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return lang_expected(p, "an identifier expected");
    symbol *sym = lang_sym_find(p, t->text, t->len);
    if (kw == CSG_KW_DEFINED) {
        *out = fval(sym != NULL);
        return lang_next(p) && close_args(p, open);
    }
    if (!sym || sym->d.kind != SYM_ARRAY) {
        csg_error(p->d, t->loc, "an array expected, got '%.*s'", (int)(t->len > 40 ? 40 : t->len),
                  t->text);
        return false;
    }
    int dims = sym->d.u.array->dims, size[5];
    memcpy(size, sym->d.u.array->size, sizeof size);
    double n = 0;
    if (!lang_next(p))
        return false;
    if (kw == CSG_KW_DIMENSION_SIZE && (!skip_comma(p) || !lang_parse_float(p, &n, NULL)))
        return false;
    int i = n >= 1 && n < dims + 1 ? (int)n - 1 : -1; /* (range first: then the cast) */
    *out = fval(kw == CSG_KW_DIMENSIONS ? dims : i >= 0 ? size[i] : 0);
    return close_args(p, open);
}

static bool parse_any_builtin(parser *p, enum csg_kw kw, value *out)
{
    const builtin *b = find_builtin(kw);
    if (b)
        return parse_float_function(p, b, out);
    switch (kw) {
    case CSG_KW_STRLEN: case CSG_KW_STRCMP: case CSG_KW_VAL: case CSG_KW_ASC:
        return parse_string_function(p, kw, out);
    case CSG_KW_DEFINED: case CSG_KW_DIMENSIONS: case CSG_KW_DIMENSION_SIZE:
        return parse_name_function(p, kw, out);
    case CSG_KW_FILE_EXISTS: {
        double found = 0;
        *out = fval(0);
        return lang_parse_file_exists(p, &found) && (*out = fval(found), true);
    }
    default:
        return parse_vector_function(p, kw, out);
    }
}

/* Every function's result obeys the language's rule for values: not
 * finite is an error (val("nan"), val("inf"), val("1e999"), vcross of
 * huge vectors), at the function's name. */
bool lang_parse_builtin(parser *p, value *out)
{
    const csg_token *t = lang_tok(p);
    csg_loc at = t->loc;
    return parse_any_builtin(p, t->kw, out) && lang_check_finite(p, out, at);
}

void lang_rand_free(parser *p)
{
    free(p->rand_streams.data);
    p->rand_streams.data = NULL;
    p->rand_streams.count = p->rand_streams.cap = 0;
}
