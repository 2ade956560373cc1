/*
 * expr.h — values and the expressions that compute them (expr.c, with the
 * built-in functions in builtins.c); internal to the front end in
 * csg/lang, whose public interface is parser.h.
 *
 * A value is a float or a vector of 2 to 5 components; colours are
 * 5-component vectors rgbft.  Every function reads from the current token
 * of `p` (parse_internal.h) and, on failure, returns false with the message
 * in p->d.
 *
 * Two levels, as in POV-Ray: lang_parse_expr is its Parse_Float (sums and
 * products of factors: what object parameters, vector components and
 * declared values use), lang_parse_full_expr its Parse_Express (with
 * comparisons, & | and ?:, inside parentheses and for directives).
 */
#ifndef CSG_LANG_EXPR_H
#define CSG_LANG_EXPR_H

#include <stdbool.h>

#include "../diag.h"
#include "../scene.h"

typedef struct parser parser; /* the parse state: parse_internal.h */

typedef struct {
    int dim;        /* 1: float; 2..5: vector (colours: 5, rgbft) */
    double v[5];
} value;

/* True when the current token can begin an expression. */
bool lang_is_expr_start(parser *p);
/* + - * / over signed factors, evaluated as it is read. */
bool lang_parse_expr(parser *p, value *out);
/* An expression with comparisons, & | ! and ?: as well. */
bool lang_parse_full_expr(parser *p, value *out);
/* An expression that must be a float; *at (if not NULL): where it starts. */
bool lang_parse_float(parser *p, double *out, csg_loc *at);
/* A 3-vector; a float is promoted to <f, f, f>. */
bool lang_parse_vector(parser *p, dvec3 *out, csg_loc *at);
/* '(' full expression ')' that must be a float (#if, #while, functions). */
bool lang_parse_float_param(parser *p, double *out);
/* POV-Ray's truth: |v| > 1e-10. */
bool lang_truth(double v);
/* A value that is not a finite number is an error at `at`. */
bool lang_check_finite(parser *p, const value *v, csg_loc at);
/* "a float", "a 3-component vector", ... */
const char *lang_dim_name(int dim);

/* builtins.c: the keyword of a built-in function or constant; its value,
 * the current token being the keyword. */
bool lang_is_builtin(int kw);
bool lang_parse_builtin(parser *p, value *out);
/* seed() and rand(): POV-Ray's streams, the same numbers. */
void lang_rand_free(parser *p);

/* The current token is rgb, rgbf, rgbt, rgbft, red, green, blue, filter or
 * transmit. */
bool lang_is_color_item(parser *p);
/* The current token can begin a colour: 'color', a colour item, an expression. */
bool lang_is_color_start(parser *p);
/* A colour, rgbft (see expr.c); the rgb part only for parse_rgb. */
bool lang_parse_color(parser *p, double c[5]);
bool lang_parse_rgb(parser *p, double rgb[3]);

#endif
