/*
 * strings.c — string expressions, where POV-Ray 3.7's language uses them
 * (#include of a computed name, #debug, #warning, #error, string
 * declarations, comparisons and the functions of strings):
 *
 *   STRING := "literal" | IDENTIFIER | concat(S, S, ...) | str(F, W, P)
 *           | chr(F) | substr(S, F, F) | strupr(S) | strlwr(S) | vstr(...)
 *
 * A string expression never reads a token after its end (no operator
 * follows a string), so `#include "a.inc"` switches files before the next
 * token is read.  Literals take POV-Ray's escapes (\n \t \r \a \b \f \v
 * \\ \" \'); a backslash before any other character is kept.  str() formats
 * as POV-Ray does: width W (< 0: padded with zeros), P decimals (< 0: 6).
 * Every string is malloc'd, NUL-terminated and at most CSG_PARSE_MAX_STRING
 * bytes.
 */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parse_internal.h"

bool lang_is_string_start(parser *p)
{
    const csg_token *t = lang_tok(p);
    if (t->kind == CSG_TOK_STRING)
        return true;
    if (t->kind != CSG_TOK_WORD)
        return false;
    switch (t->kw) {
    case CSG_KW_CONCAT: case CSG_KW_STR: case CSG_KW_CHR: case CSG_KW_SUBSTR:
    case CSG_KW_STRUPR: case CSG_KW_STRLWR: case CSG_KW_VSTR:
        return true;
    case CSG_KW_NONE:
        return lang_names(p, SYM_STRING);
    default:
        return false;
    }
}

static char *too_long(parser *p, csg_loc at)
{
    csg_error(p->d, at, "string longer than %ld bytes", CSG_PARSE_MAX_STRING);
    return NULL;
}

static char *dup_bytes(parser *p, const char *s, size_t n, csg_loc at)
{
    if (n > (size_t)CSG_PARSE_MAX_STRING)
        return too_long(p, at);
    char *r = malloc(n + 1);
    if (!r) {
        lang_oom(p);
        return NULL;
    }
    memcpy(r, s, n);
    r[n] = '\0';
    return r;
}

/* The literal's text with its escapes replaced. */
char *lang_string_literal(parser *p, const csg_token *t)
{
    char *r = dup_bytes(p, t->text, t->len, t->loc);
    if (!r)
        return NULL;
    static const char from[] = "ntrabfv\\\"'", to[] = "\n\t\r\a\b\f\v\\\"'";
    size_t w = 0;
    for (size_t i = 0; i < t->len; i++) {
        const char *k = t->text[i] == '\\' && i + 1 < t->len ? strchr(from, t->text[i + 1]) : NULL;
        if (k && *k) {
            r[w++] = to[k - from];
            i++;
        } else {
            r[w++] = t->text[i];
        }
    }
    r[w] = '\0';
    return r;
}

/* '(' after a function's name. */
static bool open_paren(parser *p, csg_loc *open)
{
    if (!lang_next(p))
        return false;
    *open = lang_tok(p)->loc;
    if (!lang_is_punct(p, '('))
        return lang_expected(p, "'(' expected after the function's name");
    return lang_enter(p, *open) && lang_next(p);
}

static bool close_paren(parser *p, csg_loc open)
{
    if (!lang_is_punct(p, ')'))
        return lang_expected_close(p, ')', "(", open);
    lang_leave(p);
    return lang_next(p);
}

static bool comma(parser *p)
{
    return !lang_is_punct(p, ',') || lang_next(p);
}

/* concat(S, S, ...) */
static char *parse_concat(parser *p, csg_loc at)
{
    csg_loc open;
    if (!open_paren(p, &open))
        return NULL;
    char *acc = dup_bytes(p, "", 0, at);
    while (acc && !lang_is_punct(p, ')')) {
        char *s = NULL;
        if (!lang_parse_string(p, &s) || !comma(p)) {
            free(s);
            free(acc);
            return NULL;
        }
        size_t a = strlen(acc), b = strlen(s);
        char *both = a + b > (size_t)CSG_PARSE_MAX_STRING ? too_long(p, at) : realloc(acc, a + b + 1);
        if (both)
            memcpy(both + a, s, b + 1);
        else
            free(acc);
        free(s);
        acc = both;
        if (!acc && !p->d->failed)
            lang_oom(p);
    }
    if (acc && !close_paren(p, open)) {
        free(acc);
        return NULL;
    }
    return acc;
}

/* str(F, W, P): POV-Ray's printf format. */
static char *parse_str(parser *p, csg_loc at)
{
    csg_loc open;
    double f, w, d;
    if (!open_paren(p, &open) || !lang_parse_float(p, &f, NULL) || !comma(p) ||
        !lang_parse_float(p, &w, NULL) || !comma(p) || !lang_parse_float(p, &d, NULL) ||
        !close_paren(p, open))
        return NULL;
    if (!(w > -100 && w < 100 && d < 100)) {
        csg_error(p->d, at, "str: width and precision must be below 100");
        return NULL;
    }
    int width = (int)w, prec = (int)d;
    char fmt[32], out[512];
    int n = snprintf(fmt, sizeof fmt, "%%%s%d", width < 0 ? "0" : "", width < 0 ? -width : width);
    if (width == 0)
        n = snprintf(fmt, sizeof fmt, "%%");
    if (prec >= 0)
        n += snprintf(fmt + n, sizeof fmt - (size_t)n, ".%d", prec);
    snprintf(fmt + n, sizeof fmt - (size_t)n, "f");
    if (snprintf(out, sizeof out, fmt, f) >= (int)sizeof out) {
        fmt[strlen(fmt) - 1] = 'g';
        snprintf(out, sizeof out, fmt, f);
    }
    return dup_bytes(p, out, strlen(out), at);
}

/* chr(F) */
static char *parse_chr(parser *p, csg_loc at)
{
    double c;
    if (!lang_next(p) || !lang_parse_float_param(p, &c))
        return NULL;
    if (!(c >= 1 && c <= 255)) {
        csg_error(p->d, at, "chr: %g is not a character code from 1 to 255", c);
        return NULL;
    }
    char s[2] = {(char)(unsigned char)(int)c, '\0'};
    return dup_bytes(p, s, 1, at);
}

/* substr(S, START, LENGTH): START counts from 1. */
static char *parse_substr(parser *p, csg_loc at)
{
    csg_loc open;
    char *s = NULL;
    double start, len;
    if (!open_paren(p, &open) || !lang_parse_string(p, &s) || !comma(p) ||
        !lang_parse_float(p, &start, NULL) || !comma(p) || !lang_parse_float(p, &len, NULL) ||
        !close_paren(p, open)) {
        free(s);
        return NULL;
    }
    size_t n = strlen(s);
    char *r = NULL;
    if (!(start >= 1 && len >= 0 && start - 1 + len <= (double)n))
        csg_error(p->d, at, "substr: characters %g to %g of a string of %zu", start,
                  start + len - 1, n);
    else
        r = dup_bytes(p, s + (size_t)start - 1, (size_t)len, at);
    free(s);
    return r;
}

/* strupr(S), strlwr(S) */
static char *parse_case(parser *p, bool upper)
{
    csg_loc open;
    char *s = NULL;
    if (!open_paren(p, &open) || !lang_parse_string(p, &s) || !close_paren(p, open)) {
        free(s);
        return NULL;
    }
    for (char *c = s; *c; c++)
        *c = (char)(upper ? toupper((unsigned char)*c) : tolower((unsigned char)*c));
    return s;
}

/* vstr(N, V, SEP, W, P): the first N components of V, each formatted like
 * str(), joined by SEP. */
static char *parse_vstr(parser *p, csg_loc at)
{
    csg_loc open;
    double n, w, d;
    value v;
    char *sep = NULL;
    if (!open_paren(p, &open) || !lang_parse_float(p, &n, NULL) || !comma(p) ||
        !lang_parse_expr(p, &v) || !comma(p) || !lang_parse_string(p, &sep) || !comma(p) ||
        !lang_parse_float(p, &w, NULL) || !comma(p) || !lang_parse_float(p, &d, NULL) ||
        !close_paren(p, open)) {
        free(sep);
        return NULL;
    }
    char out[2048] = "";
    size_t used = 0;
    int count = n < 1 ? 1 : n > 5 ? 5 : (int)n;
    int prec = d < 0 ? 6 : d > 60 ? 60 : (int)d, width = w > 60 ? 60 : w < -60 ? -60 : (int)w;
    for (int i = 0; i < count && used < sizeof out; i++) {
        double c = v.dim == 1 ? v.v[0] : i < v.dim ? v.v[i] : 0;
        used += (size_t)snprintf(out + used, sizeof out - used, "%s%0*.*f", i ? sep : "",
                                 width < 0 ? -width : width, prec, c);
    }
    free(sep);
    return dup_bytes(p, out, strlen(out), at);
}

bool lang_parse_string(parser *p, char **out)
{
    const csg_token *t = lang_tok(p);
    csg_loc at = t->loc;
    *out = NULL;
    if (t->kind == CSG_TOK_STRING) {
        *out = lang_string_literal(p, t);
        return *out && lang_next(p);
    }
    if (t->kind == CSG_TOK_WORD && t->kw == CSG_KW_NONE) {
        const datum *d;
        if (!lang_lookup(p, SYM_STRING, "a string", &d))
            return false;
        *out = dup_bytes(p, d->u.str, strlen(d->u.str), at);
        return *out != NULL;
    }
    switch (t->kind == CSG_TOK_WORD ? t->kw : CSG_KW_NONE) {
    case CSG_KW_CONCAT: *out = parse_concat(p, at); break;
    case CSG_KW_STR: *out = parse_str(p, at); break;
    case CSG_KW_CHR: *out = parse_chr(p, at); break;
    case CSG_KW_SUBSTR: *out = parse_substr(p, at); break;
    case CSG_KW_STRUPR: *out = parse_case(p, true); break;
    case CSG_KW_STRLWR: *out = parse_case(p, false); break;
    case CSG_KW_VSTR: *out = parse_vstr(p, at); break;
    default: return lang_expected(p, "a string expected");
    }
    return *out != NULL;
}
