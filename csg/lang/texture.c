/*
 * texture.c — pigments (plain colours, checker, gradient, the noise
 * patterns and the simple shapes, with their colour or pigment maps,
 * waves and turbulence), colour maps, finishes, textures, interiors, and
 * the transforms that objects, lights, cameras and pigments share.
 *
 *   pigment { [PIGMENT_ID] [PATTERN | COLOR] { MODIFIER } }
 *     PATTERN  checker [COLOR [,] [COLOR]] | checker pigment {} [,] [pigment {}]
 *              | gradient VECTOR | bozo | spotted | bumps | wood | marble | granite
 *              | agate | wrinkles | radial | onion | leopard | planar | boxed | cylindrical
 *              | crackle
 *     MODIFIER color_map { ... } | pigment_map { [F PIGMENT_BODY] ... } | frequency F
 *              | phase F | ramp_wave | triangle_wave | sine_wave | scallop_wave
 *              | cubic_wave | poly_wave [F] | turbulence VECTOR | octaves N | omega F
 *              | lambda F | agate_turb F | noise_generator N | form VECTOR | metric F
 *              | offset F | solid | quick_color COLOR
 *              | TRANSFORM
 *   color_map { COLOR_MAP_ID | [F COLOR] ... | [F, F COLOR COLOR] ... }
 *   texture { [TEXTURE_ID] [PIGMENT_ID] [FINISH_ID] { pigment {} | finish {} | TRANSFORM } }
 *
 * The pattern and wave keywords are those of the tables of
 * csg/device/patterns.h (the lexer's CSG_KW_PATTERN and CSG_KW_WAVE), with
 * their default waves; what a pattern takes beyond the common modifiers,
 * and its default map, are this file's.
 *
 * POV-Ray 3.7's semantics: a pigment starts from its identifier or from
 * the current one; checker keeps the colours given (blue and green by
 * default) as a two-entry map; gradient normalises its vector and starts
 * with the black-to-white map; the other patterns start with POV-Ray's
 * default map of each (pigment.cpp) and wood and marble with the triangle
 * wave; a colour map keeps its entries in order, merging an entry equal
 * to the one before; a pigment map's entries are pigment bodies, each
 * starting from the default pigment.  Turbulence settings switch the
 * classic turbulence on (agate always has it).  The transforms of a pigment
 * (and of a texture, and of the objects it is given to afterwards,
 * parser.c) compose into its xform, pattern space -> world.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "parse_internal.h"

/* ---- transforms ------------------------------------------------------------ */

bool lang_is_transform(parser *p)
{
    return lang_is_kw(p, CSG_KW_TRANSLATE) || lang_is_kw(p, CSG_KW_ROTATE) ||
           lang_is_kw(p, CSG_KW_SCALE) || lang_is_kw(p, CSG_KW_MATRIX) ||
           lang_is_kw(p, CSG_KW_TRANSFORM);
}

/* matrix <m00, m01, m02, m10, ..., m32>: POV-Ray's row-vector form,
 * p' = p M, applied after the transforms before it. */
static bool parse_matrix(parser *p, csg_xform *x)
{
    if (!lang_next(p))
        return false;
    csg_loc open = lang_tok(p)->loc;
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
                csg_error(p->d, lang_tok(p)->loc, "matrix needs 12 numbers separated by ','");
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

/* transform { [inverse] STEP | TRANSFORM_ID | transform ... } as POV-Ray's
 * Parse_Transform_Block: the steps compose in order; inverse, anywhere in
 * the block, inverts the whole of it. */
static bool parse_transform_block(parser *p, csg_xform *block)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_expect_open(p, "transform"))
        return false;
    bool inverse = false;
    for (;;) {
        if (lang_is_kw(p, CSG_KW_INVERSE)) {
            inverse = true;
            if (!lang_next(p))
                return false;
        } else if (lang_is_transform(p) || lang_names(p, SYM_TRANSFORM)) {
            if (!lang_parse_transform(p, block))
                return false;
        } else {
            break;
        }
    }
    if (!lang_is_punct(p, '}'))
        return lang_expected_close(p, '}', "transform", open);
    if (inverse) {
        csg_xform inv;
        if (!csg_xform_invert(block, &inv)) {
            csg_error(p->d, open, "transform: the inverse of a singular transform");
            return false;
        }
        *block = inv;
    }
    return lang_next(p);
}

/* transform TRANSFORM_ID | transform { ... }, or a declared transform's
 * bare name inside a transform block: composed after *x. */
static bool parse_transform_value(parser *p, csg_xform *x)
{
    csg_xform t;
    if (lang_is_kw(p, CSG_KW_TRANSFORM) && !lang_next(p))
        return false;
    if (lang_is_ident(p)) {
        const datum *d;
        if (!lang_lookup(p, SYM_TRANSFORM, "a transform", &d))
            return false;
        t = d->u.transform;
    } else {
        csg_xform_identity(&t);
        if (!parse_transform_block(p, &t))
            return false;
    }
    csg_xform_then(x, &t, x);
    return true;
}

bool lang_parse_transform(parser *p, csg_xform *x)
{
    enum csg_kw kw = lang_tok(p)->kw;
    p->transform_at = lang_tok(p)->loc;
    csg_loc at;
    dvec3 v;
    if (kw == CSG_KW_MATRIX)
        return parse_matrix(p, x);
    if (kw == CSG_KW_TRANSFORM || kw == CSG_KW_NONE)
        return parse_transform_value(p, x);
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

/* Can a pattern be evaluated through x: every entry finite, no axis
 * collapsed to a zero column (each step was accepted, but a product of
 * them may overflow or underflow to that). */
static bool xform_usable(const csg_xform *x)
{
    if (!csg_xform_finite(x))
        return false;
    for (int col = 0; col < 3; col++)
        if (x->m[0][col] == 0 && x->m[1][col] == 0 && x->m[2][col] == 0)
            return false;
    return true;
}

bool lang_pigment_transform(parser *p, csg_pigment *pig, const csg_xform *x)
{
    csg_xform_then(&pig->xform, x, &pig->xform);
    if (xform_usable(&pig->xform))
        return true;
    csg_error(p->d, p->transform_at,
              "the pattern's transformation overflows or collapses an axis here (an entry "
              "is not finite, or an axis is scaled to 0)");
    return false;
}

/* A transform of the current token applied to a pigment. */
static bool transform_pigment(parser *p, csg_pigment *pig)
{
    csg_xform x;
    csg_xform_identity(&x);
    return lang_parse_transform(p, &x) && lang_pigment_transform(p, pig, &x);
}

/* ---- colour maps ---------------------------------------------------------------- */

/* Appends an entry, merging it with an equal last one (POV-Ray). */
static bool map_add(parser *p, csg_map_entry *e, int *n, const csg_map_entry *add, csg_loc at)
{
    if (*n > 0 && memcmp(&e[*n - 1], add, sizeof *add) == 0)
        return true;
    if (*n == CSG_MAP_MAX) {
        csg_error(p->d, at, "a color_map has at most %d entries", CSG_MAP_MAX);
        return false;
    }
    e[(*n)++] = *add;
    return true;
}

/* [F COLOR] or [F, F COLOR COLOR] (the old two-colour form). */
static bool parse_map_entry(parser *p, csg_map_entry *e, int *n)
{
    csg_loc open = lang_tok(p)->loc;
    csg_map_entry a, b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    if (!lang_enter(p, open) || !lang_next(p) || !lang_parse_float(p, &a.value, NULL))
        return false;
    if (lang_is_punct(p, ',') && !lang_next(p))
        return false;
    bool two = false;
    if (!lang_is_kw(p, CSG_KW_COLOR) && !lang_is_color_item(p) && lang_is_expr_start(p)) {
        value v; /* a float: the old form; a colour expression: the colour */
        if (!lang_parse_full_expr(p, &v))
            return false;
        if (v.dim == 1) {
            two = true;
            b.value = v.v[0];
            if (!lang_parse_color(p, a.rgbft) || !lang_parse_color(p, b.rgbft))
                return false;
        } else if (v.dim == 5) {
            memcpy(a.rgbft, v.v, sizeof a.rgbft);
        } else {
            csg_error(p->d, open, "a color expected in the color_map entry, got %s",
                      lang_dim_name(v.dim));
            return false;
        }
    } else if (!lang_parse_color(p, a.rgbft)) {
        return false;
    }
    if (!lang_is_punct(p, ']'))
        return lang_expected_close(p, ']', "[", open);
    lang_leave(p);
    return map_add(p, e, n, &a, open) && (!two || map_add(p, e, n, &b, open)) && lang_next(p);
}

static bool save_map(parser *p, const csg_map_entry *e, int n, lang_color_map *out)
{
    csg_map_entry *copy = lang_alloc(p, (size_t)n * sizeof *copy);
    if (!copy)
        return false;
    memcpy(copy, e, (size_t)n * sizeof *copy);
    out->count = n;
    out->entries = copy;
    return true;
}

bool lang_parse_color_map(parser *p, lang_color_map *out)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !lang_expect_open(p, "color_map"))
        return false;
    if (lang_names(p, SYM_COLOR_MAP)) {
        const datum *d;
        if (!lang_lookup(p, SYM_COLOR_MAP, "a color_map", &d))
            return false;
        *out = d->u.cmap;
    } else {
        csg_map_entry e[CSG_MAP_MAX];
        int n = 0;
        while (lang_is_punct(p, '['))
            if (!parse_map_entry(p, e, &n))
                return false;
        if (n == 0)
            return lang_expected(p, "'[' expected (a color_map entry)");
        if (!save_map(p, e, n, out))
            return false;
    }
    if (!lang_is_punct(p, '}'))
        return lang_expected_close(p, '}', "color_map", open);
    return lang_next(p);
}

/* ---- pigments --------------------------------------------------------------------- */

/* ---- the block patterns ---------------------------------------------------------
 * checker, brick and hexagon (POV-Ray's Parse_Blend_List): a list of
 * colours, pigments or textures after the keyword, entry i at value i
 * (the pattern's values are these integers), those not given POV-Ray's
 * default colours (pigment.cpp's Check_, Brick_ and Hex_Default_Map) or
 * the default pigment or texture; not waved (frequency 0). */

static const csg_map_entry checker_colors[2] = {{0, {0, 0, 1, 0, 0}}, {1, {0, 1, 0, 0, 0}}};
static const csg_map_entry brick_colors[2] = {{0, {0.5, 0.5, 0.5, 0, 0}},
                                              {1, {0.6, 0.15, 0.15, 0, 0}}};
static const csg_map_entry hexagon_colors[3] = {
    {0, {0, 0, 1, 0, 0}}, {1, {0, 1, 0, 0, 0}}, {2, {1, 0, 0, 0, 0}}};

/* The default colours of a block pattern, count of them (its list's
 * length); NULL for the other patterns. */
static const csg_map_entry *block_colors(int pattern, int *count)
{
    *count = csg_pattern_blocks(pattern);
    if (pattern == CSG_PATTERN_CHECKER)
        return checker_colors;
    if (pattern == CSG_PATTERN_BRICK)
        return brick_colors;
    return pattern == CSG_PATTERN_HEXAGON ? hexagon_colors : NULL;
}

static bool is_block_pattern(int pattern)
{
    return csg_pattern_blocks(pattern) > 0;
}

bool lang_single_float(parser *p, double v, csg_loc at, const char *what, double *out)
{
    if (!(fabs(v) <= (double)FLT_MAX)) {
        csg_error(p->d, at, "%s out of range, got %g", what, v);
        return false;
    }
    *out = (double)(float)v;
    return true;
}

/* brick's mortar as POV-Ray keeps it: the width less 2 EPSILON, in a
 * float (SNGL). */
static bool brick_mortar(parser *p, double width, csg_loc at, double *mortar)
{
    return lang_single_float(p, width - 2e-10, at, "mortar", mortar);
}

/* The keyword of a block pattern (the current token) read: its pattern,
 * not waved, and brick's size and mortar unless the pigment was a brick
 * already (POV-Ray keeps a brick identifier's); its default colours. */
static bool block_pattern_start(parser *p, csg_pigment *pig, int pattern)
{
    int count;
    const csg_map_entry *colors = block_colors(pattern, &count);
    if (pattern == CSG_PATTERN_BRICK && pig->pattern != CSG_PATTERN_BRICK) {
        pig->brick_size = (dvec3){8.0, 3.0, 4.5};
        if (!brick_mortar(p, 0.5, lang_tok(p)->loc, &pig->mortar))
            return false;
    }
    pig->pattern = (enum csg_pattern)pattern;
    pig->frequency = 0;
    pig->map = colors;
    pig->map_count = count;
    pig->pmap_count = 0;
    return lang_next(p);
}

/* PATTERN pigment {..} [,] [pigment {..}] ...: a pigment map of `count`
 * entries, 0, 1, .., those not given the default pigment. */
static bool parse_block_pigments(parser *p, csg_pigment *pig, int count)
{
    csg_pigment_entry *e = lang_alloc(p, (size_t)count * sizeof *e);
    if (!e)
        return false;
    for (int i = 0; i < count; i++) {
        e[i].value = i;
        e[i].pigment = p->default_texture.pigment;
    }
    for (int i = 0; i < count && lang_is_kw(p, CSG_KW_PIGMENT); i++)
        if (!lang_parse_pigment(p, &e[i].pigment) || (lang_is_punct(p, ',') && !lang_next(p)))
            return false;
    pig->pmap = e;
    pig->pmap_count = count;
    return true;
}

/* checker, brick or hexagon in a pigment: [COLOR [,] COLOR ..] or
 * pigment {..} [,] [pigment {..}] ... */
static bool parse_block_pattern(parser *p, csg_pigment *pig, int pattern)
{
    if (!block_pattern_start(p, pig, pattern))
        return false;
    csg_map_entry e[3];
    int count = pig->map_count;
    memcpy(e, pig->map, (size_t)count * sizeof e[0]);
    if (lang_is_kw(p, CSG_KW_PIGMENT) && !parse_block_pigments(p, pig, count))
        return false;
    for (int i = 0; i < count && lang_is_color_start(p) && !lang_names(p, SYM_PIGMENT); i++)
        if (!lang_parse_color(p, e[i].rgbft) || (lang_is_punct(p, ',') && !lang_next(p)))
            return false;
    lang_color_map m;
    if (!save_map(p, e, count, &m))
        return false;
    pig->map = m.entries;
    return true;
}

/* spiral1 N, spiral2 N: the number of arms (POV-Ray's short, truncated),
 * the triangle wave, the black-to-white map. */
static bool parse_spiral(parser *p, csg_pigment *pig, int pattern)
{
    static const csg_map_entry gray[2] = {{0, {0, 0, 0, 0, 0}}, {1, {1, 1, 1, 0, 0}}};
    double arms;
    csg_loc at;
    if (!lang_next(p) || !lang_parse_float(p, &arms, &at))
        return false;
    if (!(arms > -32769.0 && arms < 32768.0)) {
        csg_error(p->d, at, "the number of arms must be from -32768 to 32767, got %g", arms);
        return false;
    }
    pig->pattern = (enum csg_pattern)pattern;
    pig->arms = (int)arms;
    pig->wave = CSG_WAVE_TRIANGLE;
    pig->map = gray;
    pig->map_count = 2;
    return true;
}

/* gradient VECTOR: the unit vector, the black-to-white map. */
static bool parse_gradient(parser *p, csg_pigment *pig)
{
    static const csg_map_entry gray[2] = {{0, {0, 0, 0, 0, 0}}, {1, {1, 1, 1, 0, 0}}};
    csg_loc at;
    dvec3 g;
    if (!lang_next(p) || !lang_parse_vector(p, &g, &at))
        return false;
    double len = sqrt(g.x * g.x + g.y * g.y + g.z * g.z);
    if (!(len > 0) || !isfinite(len)) {
        csg_error(p->d, at, "gradient needs a non-zero vector");
        return false;
    }
    pig->pattern = CSG_PATTERN_GRADIENT;
    pig->gradient = (dvec3){g.x / len, g.y / len, g.z / len};
    pig->map_count = 2;
    pig->map = gray;
    return true;
}

/* POV-Ray's default colour maps of the noise patterns (pigment.cpp);
 * spotted and granite take the black-to-white one. */
static const csg_map_entry gray_map[2] = {{0, {0, 0, 0, 0, 0}}, {1, {1, 1, 1, 0, 0}}};
static const csg_map_entry bozo_map[6] = {
    {0.4, {1, 1, 1, 0, 0}}, {0.4, {0, 1, 0, 0, 0}}, {0.6, {0, 1, 0, 0, 0}},
    {0.6, {0, 0, 1, 0, 0}}, {0.8, {0, 0, 1, 0, 0}}, {0.8, {1, 0, 0, 0, 0}}};
static const csg_map_entry wood_map[2] = {{0.6, {0.666, 0.312, 0.2, 0, 0}},
                                          {0.6, {0.4, 0.1333, 0.066, 0, 0}}};
static const csg_map_entry marble_map[3] = {
    {0.0, {0.9, 0.8, 0.8, 0, 0}}, {0.9, {0.9, 0.08, 0.08, 0, 0}}, {0.9, {0, 0, 0, 0, 0}}};
static const csg_map_entry radial_map[4] = {
    {0.0, {0, 1, 1, 0, 0}}, {0.333, {1, 1, 0, 0, 0}}, {0.666, {1, 0, 1, 0, 0}}, {1.0, {0, 1, 1, 0, 0}}};
static const csg_map_entry agate_map[6] = {
    {0.0, {1, 1, 1, 0, 0}},      {0.5, {0.95, 0.75, 0.5, 0, 0}}, {0.5, {0.9, 0.7, 0.5, 0, 0}},
    {0.6, {0.9, 0.7, 0.4, 0, 0}}, {0.6, {1, 0.7, 0.4, 0, 0}},    {1.0, {0.6, 0.3, 0, 0, 0}}};

/* POV-Ray's default map of a pattern given by its own keyword, where it is
 * not gray_map (POV-Ray's for every other pattern, and for the aliases
 * spotted and bumps: CSG_PATTERN_ALIASES). */
static const struct {
    const csg_map_entry *map;
    int count;
} own_maps[CSG_PATTERN_COUNT] = {
    [CSG_PATTERN_BOZO] = {bozo_map, 6},   [CSG_PATTERN_WOOD] = {wood_map, 2},
    [CSG_PATTERN_MARBLE] = {marble_map, 3}, [CSG_PATTERN_AGATE] = {agate_map, 6},
    [CSG_PATTERN_RADIAL] = {radial_map, 4},
};

/* A pattern keyword but checker and gradient (which take parameters
 * first): its pattern, POV-Ray's default map and wave (the table's: wood
 * and marble have the triangle wave), agate's turbulence (always on) and
 * crackle's settings. */
static bool parse_bare_pattern(parser *p, csg_pigment *pig, enum csg_pattern pattern, bool alias)
{
    pig->pattern = pattern;
    pig->map = gray_map;
    pig->map_count = 2;
    if (!alias && own_maps[pattern].map) {
        pig->map = own_maps[pattern].map;
        pig->map_count = own_maps[pattern].count;
    }
    if (csg_pattern_wave(pattern) != CSG_WAVE_RAMP) /* else the wave given before stays */
        pig->wave = csg_pattern_wave(pattern);
    if (pig->pattern == CSG_PATTERN_AGATE) {
        pig->turb.on = true;
        pig->agate_turb = 1.0;
    }
    if (pig->pattern == CSG_PATTERN_QUILTED) { /* POV-Ray: not waved, controls 1 and 1 */
        pig->frequency = 0;
        pig->control0 = pig->control1 = 1.0;
    }
    if (pig->pattern == CSG_PATTERN_CRACKLE) {
        pig->crackle.form = (dvec3){-1, 1, 0};
        pig->crackle.metric = 2;
        pig->crackle.offset = 0;
        pig->crackle.solid = false;
    }
    return lang_next(p);
}

static bool parse_pigment_block(parser *p, csg_pigment *pig, const char *name);

/* pigment_pattern { PIGMENT_BODY }: the value is the grey of the pigment
 * (POV-Ray's Create_Pigment: it starts black, not from the default
 * pigment), evaluated at the pattern's point; the black-to-white map. */
static bool parse_pigment_pattern(parser *p, csg_pigment *pig)
{
    static const csg_map_entry gray[2] = {{0, {0, 0, 0, 0, 0}}, {1, {1, 1, 1, 0, 0}}};
    csg_pigment *inner = lang_alloc(p, sizeof *inner);
    if (!inner)
        return false;
    csg_pigment_default(inner);
    if (!parse_pigment_block(p, inner, "pigment_pattern"))
        return false;
    pig->pattern = CSG_PATTERN_PIGMENT_PATTERN;
    pig->pattern_pigment = inner;
    pig->map = gray;
    pig->map_count = 2;
    return true;
}

/* A pattern keyword (CSG_KW_PATTERN: the lexer found it in the table, so
 * csg_pattern_keyword names a pattern of it) and what follows it. */
static bool parse_pattern_keyword(parser *p, csg_pigment *pig)
{
    bool alias = false;
    int pattern = csg_pattern_keyword(lang_tok(p)->text, lang_tok(p)->len, &alias);
    if (is_block_pattern(pattern))
        return parse_block_pattern(p, pig, pattern);
    if (pattern == CSG_PATTERN_SPIRAL1 || pattern == CSG_PATTERN_SPIRAL2)
        return parse_spiral(p, pig, pattern);
    if (pattern == CSG_PATTERN_GRADIENT)
        return parse_gradient(p, pig);
    if (pattern == CSG_PATTERN_PIGMENT_PATTERN)
        return parse_pigment_pattern(p, pig);
    return parse_bare_pattern(p, pig, (enum csg_pattern)pattern, alias);
}

/* What comes first: a pattern or a colour (or neither). */
static bool parse_pattern(parser *p, csg_pigment *pig)
{
    if (lang_is_kw(p, CSG_KW_PATTERN))
        return parse_pattern_keyword(p, pig);
    if (lang_is_punct(p, '}') || !lang_is_color_start(p))
        return true;
    double c[5];
    if (!lang_parse_color(p, c))
        return false;
    csg_pigment_default(pig); /* a plain colour: nothing of a pattern is left */
    memcpy(pig->rgbft, c, sizeof c);
    return true;
}

/* The wave keywords: POV-Ray's shape of the value (poly_wave's exponent
 * is optional: it keeps the one before, 1 at first). */
static bool parse_wave(parser *p, csg_pigment *pig)
{
    /* CSG_KW_WAVE: the lexer found the word in the table of waves */
    pig->wave = (enum csg_wave)csg_wave_keyword(lang_tok(p)->text, lang_tok(p)->len);
    if (!lang_next(p))
        return false;
    if (pig->wave == CSG_WAVE_POLY && lang_is_expr_start(p))
        return lang_parse_float(p, &pig->exponent, NULL);
    return true;
}

/* turbulence VECTOR, octaves N, omega F, lambda F, agate_turb F,
 * noise_generator N: POV-Ray's classic turbulence and noise settings.
 * POV-Ray clamps octaves into 1..10 silently; a value outside is refused
 * here instead (it is a scene error, not a setting). */
static bool parse_noise_modifier(parser *p, csg_pigment *pig)
{
    enum csg_kw kw = lang_tok(p)->kw;
    csg_loc at;
    double f;
    if (!lang_next(p))
        return false;
    if (kw == CSG_KW_TURBULENCE) {
        pig->turb.on = true;
        return lang_parse_vector(p, &pig->turb.amount, &at);
    }
    if (!lang_parse_float(p, &f, &at))
        return false;
    switch (kw) {
    case CSG_KW_OCTAVES:
        if (!(f >= 1 && f < 11)) {
            csg_error(p->d, at, "octaves must be from 1 to 10, got %g", f);
            return false;
        }
        pig->turb.on = true;
        pig->turb.octaves = (int)f; /* POV-Ray truncates */
        return true;
    case CSG_KW_OMEGA: pig->turb.on = true; pig->turb.omega = f; return true;
    case CSG_KW_LAMBDA: pig->turb.on = true; pig->turb.lambda = f; return true;
    case CSG_KW_AGATE_TURB:
        if (pig->pattern != CSG_PATTERN_AGATE) {
            csg_error(p->d, at, "agate_turb needs the agate pattern");
            return false;
        }
        pig->agate_turb = f;
        return true;
    default: /* noise_generator */
        if (!(f == 0 || f == 1 || f == 2 || f == 3)) {
            csg_error(p->d, at, "noise_generator must be 0, 1, 2 or 3, got %g", f);
            return false;
        }
        pig->noise_generator |= (int)f; /* POV-Ray ORs it into the pattern's flags:
                                           1 then 2 gives 3 */
        return true;
    }
}

/* crackle's modifiers: form VECTOR, metric F (a vector's x, as POV-Ray
 * reads it), offset F, solid. */
static bool parse_crackle_modifier(parser *p, csg_pigment *pig)
{
    enum csg_kw kw = lang_tok(p)->kw;
    csg_loc at = lang_tok(p)->loc;
    if (pig->pattern != CSG_PATTERN_CRACKLE) {
        csg_error(p->d, at, "'%.*s' needs the crackle pattern", (int)lang_tok(p)->len,
                  lang_tok(p)->text);
        return false;
    }
    if (!lang_next(p))
        return false;
    dvec3 v;
    switch (kw) {
    case CSG_KW_SOLID: pig->crackle.solid = true; return true;
    case CSG_KW_FORM: return lang_parse_vector(p, &pig->crackle.form, NULL);
    case CSG_KW_OFFSET: return lang_parse_float(p, &pig->crackle.offset, NULL);
    default: /* metric */
        if (!lang_parse_vector(p, &v, &at))
            return false;
        if (!(v.x > 0)) {
            csg_error(p->d, at, "metric must be > 0, got %g", v.x);
            return false;
        }
        pig->crackle.metric = v.x;
        return true;
    }
}

static bool is_crackle_modifier(parser *p)
{
    return lang_is_kw(p, CSG_KW_FORM) || lang_is_kw(p, CSG_KW_METRIC) ||
           lang_is_kw(p, CSG_KW_OFFSET) || lang_is_kw(p, CSG_KW_SOLID);
}

/* brick's modifiers: brick_size VECTOR, mortar F. */
static bool parse_brick_modifier(parser *p, csg_pigment *pig)
{
    enum csg_kw kw = lang_tok(p)->kw;
    csg_loc at = lang_tok(p)->loc;
    if (pig->pattern != CSG_PATTERN_BRICK) {
        csg_error(p->d, at, "'%.*s' needs the brick pattern", (int)lang_tok(p)->len,
                  lang_tok(p)->text);
        return false;
    }
    if (!lang_next(p))
        return false;
    if (kw == CSG_KW_BRICK_SIZE)
        return lang_parse_vector(p, &pig->brick_size, NULL);
    double width;
    return lang_parse_float(p, &width, &at) && brick_mortar(p, width, at, &pig->mortar);
}

static bool is_brick_modifier(parser *p)
{
    return lang_is_kw(p, CSG_KW_BRICK_SIZE) || lang_is_kw(p, CSG_KW_MORTAR);
}

static bool is_noise_modifier(parser *p)
{
    return lang_is_kw(p, CSG_KW_TURBULENCE) || lang_is_kw(p, CSG_KW_OCTAVES) ||
           lang_is_kw(p, CSG_KW_OMEGA) || lang_is_kw(p, CSG_KW_LAMBDA) ||
           lang_is_kw(p, CSG_KW_AGATE_TURB) || lang_is_kw(p, CSG_KW_NOISE_GENERATOR);
}

static bool parse_pigment_map(parser *p, csg_pigment *pig);
static bool parse_quilted_modifier(parser *p, csg_pigment *pig);

/* POV-Ray's Parse_Pattern: an average pigment averages its pigment_map,
 * so it must have one (its end at `at`). */
static bool average_has_map(parser *p, const csg_pigment *pig, csg_loc at)
{
    if (pig->pattern != CSG_PATTERN_AVERAGE || pig->pmap_count > 0)
        return true;
    csg_error(p->d, at, "average needs a pigment_map");
    return false;
}

/* The modifiers after the pattern, up to `closer` ('}' of a pigment, ']'
 * of a pigment map's entry), which is consumed. */
static bool parse_pigment_modifiers(parser *p, csg_pigment *pig, int closer, csg_loc open)
{
    for (;;) {
        if (lang_is_punct(p, closer))
            return average_has_map(p, pig, lang_tok(p)->loc) && lang_next(p);
        bool ok;
        csg_loc at = lang_tok(p)->loc;
        if (lang_is_transform(p)) {
            ok = transform_pigment(p, pig);
        } else if (lang_is_kw(p, CSG_KW_COLOR_MAP)) {
            lang_color_map m;
            if (pig->pattern == CSG_PATTERN_PLAIN || is_block_pattern(pig->pattern)) {
                csg_error(p->d, at, "a color_map needs a pattern that takes one "
                                    "(any but checker, brick and hexagon)");
                return false;
            }
            if (pig->pattern == CSG_PATTERN_AVERAGE) { /* (POV-Ray's rule) */
                csg_error(p->d, at, "average takes a pigment_map, not a color_map");
                return false;
            }
            ok = lang_parse_color_map(p, &m);
            pig->map_count = m.count;
            pig->map = m.entries;
            pig->pmap_count = 0; /* POV-Ray: the last map given counts */
        } else if (lang_is_kw(p, CSG_KW_PIGMENT_MAP)) {
            ok = parse_pigment_map(p, pig);
        } else if (lang_is_kw(p, CSG_KW_FREQUENCY) || lang_is_kw(p, CSG_KW_PHASE)) {
            double *f = lang_is_kw(p, CSG_KW_FREQUENCY) ? &pig->frequency : &pig->phase;
            ok = lang_next(p) && lang_parse_float(p, f, NULL);
        } else if (lang_is_kw(p, CSG_KW_WAVE)) {
            ok = parse_wave(p, pig);
        } else if (is_noise_modifier(p)) {
            ok = parse_noise_modifier(p, pig);
        } else if (is_crackle_modifier(p)) {
            ok = parse_crackle_modifier(p, pig);
        } else if (is_brick_modifier(p)) {
            ok = parse_brick_modifier(p, pig);
        } else if (lang_is_kw(p, CSG_KW_CONTROL0) || lang_is_kw(p, CSG_KW_CONTROL1)) {
            ok = parse_quilted_modifier(p, pig);
        } else if (lang_is_kw(p, CSG_KW_QUICK_COLOR)) {
            double ignored[5]; /* POV-Ray uses it only below quality 6 (+Q5) */
            ok = lang_next(p) && lang_parse_color(p, ignored);
        } else if (lang_is_kw(p, CSG_KW_SPHERICAL)) { /* (a camera's word too) */
            return lang_unsupported(p, "'spherical'", p->tok.loc);
        } else {
            return lang_expected_close(p, closer, closer == '}' ? "pigment" : "[", open);
        }
        if (!ok)
            return false;
    }
}

/* A map entry's value; in the map of an average, its weight, which may be
 * left out: 1 (POV-Ray's Parse_Blend_Map, Allow_Float(1.0)).  There the
 * entry's body may start at once: with a pattern or colour keyword, or
 * with the name of a pigment, texture, normal, finish or material. */
static bool parse_map_value(parser *p, bool average, double *out)
{
    if (average && (!lang_is_expr_start(p) || lang_names(p, SYM_PIGMENT) ||
                    lang_names(p, SYM_TEXTURE) || lang_names(p, SYM_NORMAL) ||
                    lang_names(p, SYM_FINISH) || lang_names(p, SYM_MATERIAL))) {
        *out = 1.0;
        return true;
    }
    return lang_parse_float(p, out, NULL);
}

/* [F [,] PIGMENT_BODY]: the body starts from the default pigment, as in
 * POV-Ray (#default), and ends at ']' (F optional in an average's map). */
static bool parse_pigment_entry(parser *p, csg_pigment_entry *e, bool average)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !parse_map_value(p, average, &e->value))
        return false;
    if (lang_is_punct(p, ',') && !lang_next(p))
        return false;
    e->pigment = p->default_texture.pigment;
    if (lang_names(p, SYM_PIGMENT)) {
        const datum *d;
        if (!lang_lookup(p, SYM_PIGMENT, "a pigment", &d))
            return false;
        e->pigment = d->u.pigment;
    }
    return parse_pattern(p, &e->pigment) && parse_pigment_modifiers(p, &e->pigment, ']', open);
}

/* The entries of a pigment map up to its '}' into *out (malloc'd, *n of
 * them); false on an error (*out still to be freed). */
static bool parse_pigment_entries(parser *p, csg_pigment_entry **out, int *n, bool average)
{
    int cap = 0;
    while (lang_is_punct(p, '[')) {
        if (*n == CSG_MAP_MAX) {
            csg_error(p->d, lang_tok(p)->loc, "a pigment_map has at most %d entries", CSG_MAP_MAX);
            return false;
        }
        if (*n == cap) {
            cap = cap ? 2 * cap : 8;
            csg_pigment_entry *grown = realloc(*out, (size_t)cap * sizeof *grown);
            if (!grown)
                return lang_oom(p);
            *out = grown;
        }
        if (!parse_pigment_entry(p, &(*out)[(*n)++], average))
            return false;
    }
    return *n > 0 || lang_expected(p, "'[' expected (a pigment_map entry)");
}

/* pigment_map { [F PIGMENT_BODY] ... }: the map's entries are pigments. */
static bool parse_pigment_map(parser *p, csg_pigment *pig)
{
    csg_loc open = lang_tok(p)->loc;
    if (pig->pattern == CSG_PATTERN_PLAIN || is_block_pattern(pig->pattern)) {
        csg_error(p->d, open, "a pigment_map needs a pattern that takes one "
                              "(any but checker, brick and hexagon)");
        return false;
    }
    if (!lang_enter(p, open) || !lang_next(p) || !lang_expect_open(p, "pigment_map"))
        return false;
    csg_pigment_entry *e = NULL, *copy = NULL;
    int n = 0;
    bool ok = parse_pigment_entries(p, &e, &n, pig->pattern == CSG_PATTERN_AVERAGE);
    if (ok && !lang_is_punct(p, '}'))
        ok = lang_expected_close(p, '}', "pigment_map", open);
    if (ok && (copy = lang_alloc(p, (size_t)n * sizeof *copy)) == NULL)
        ok = false;
    if (ok) {
        memcpy(copy, e, (size_t)n * sizeof *copy);
        pig->pmap = copy;
        pig->pmap_count = n;
        lang_leave(p);
        ok = lang_next(p);
    }
    free(e);
    return ok;
}

/* NAME { [PIGMENT_ID] [PATTERN | COLOR] MODIFIERS }, editing *pig (the
 * current token is NAME: pigment, or pigment_pattern). */
static bool parse_pigment_block(parser *p, csg_pigment *pig, const char *name)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !lang_expect_open(p, name))
        return false;
    if (lang_names(p, SYM_PIGMENT)) {
        const datum *d;
        if (!lang_lookup(p, SYM_PIGMENT, "a pigment", &d))
            return false;
        *pig = d->u.pigment;
    }
    return parse_pattern(p, pig) && parse_pigment_modifiers(p, pig, '}', open);
}

/* pigment { [PIGMENT_ID] [PATTERN | COLOR] MODIFIERS }, editing *pig. */
bool lang_parse_pigment(parser *p, csg_pigment *pig)
{
    return parse_pigment_block(p, pig, "pigment");
}

/* ---- sky_sphere ------------------------------------------------------------------- */

bool lang_parse_sky_sphere(parser *p, csg_sky *sky)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !lang_expect_open(p, "sky_sphere"))
        return false;
    memset(sky, 0, sizeof *sky);
    sky->emission[0] = sky->emission[1] = sky->emission[2] = 1;
    csg_xform_identity(&sky->xform);
    if (lang_names(p, SYM_SKY)) {
        const datum *d;
        if (!lang_lookup(p, SYM_SKY, "a sky_sphere", &d))
            return false;
        *sky = *d->u.sky;
    }
    for (;;) {
        bool ok;
        csg_loc at = lang_tok(p)->loc;
        if (lang_is_punct(p, '}'))
            break;
        if (lang_is_kw(p, CSG_KW_PIGMENT)) {
            if (sky->count == CSG_SKY_MAX) {
                csg_error(p->d, at, "a sky_sphere has at most %d pigments", CSG_SKY_MAX);
                return false;
            }
            csg_pigment_default(&sky->pigments[sky->count]); /* POV-Ray: a new pigment */
            ok = lang_parse_pigment(p, &sky->pigments[sky->count++]);
        } else if (lang_is_kw(p, CSG_KW_EMISSION)) {
            ok = lang_next(p) && lang_parse_rgb(p, sky->emission);
        } else if (lang_is_transform(p)) {
            ok = lang_parse_transform(p, &sky->xform);
            if (ok && !xform_usable(&sky->xform)) {
                csg_error(p->d, at,
                          "the sky_sphere's transformation overflows or collapses an axis here (an "
                          "entry is not finite, or an axis is scaled to 0)");
                return false;
            }
        } else {
            return lang_expected_close(p, '}', "sky_sphere", open);
        }
        if (!ok)
            return false;
    }
    if (sky->count == 0) {
        csg_error(p->d, open, "a sky_sphere needs a pigment");
        return false;
    }
    return lang_next(p);
}

/* ---- finish, texture, interior ---------------------------------------------------- */

/* One option of a reflection block: fresnel [B], falloff F, exponent F
 * (> 0), metallic [F]; false with nothing read when the token is none. */
static bool parse_reflection_option(parser *p, csg_finish *f, bool *ok)
{
    enum csg_kw kw = lang_tok(p)->kind == CSG_TOK_WORD ? lang_tok(p)->kw : CSG_KW_NONE;
    if (kw != CSG_KW_FRESNEL && kw != CSG_KW_FALLOFF && kw != CSG_KW_EXPONENT &&
        kw != CSG_KW_METALLIC)
        return false;
    double v = 1;
    csg_loc at;
    bool optional = kw == CSG_KW_FRESNEL || kw == CSG_KW_METALLIC;
    *ok = lang_next(p) && ((optional && !lang_is_expr_start(p)) || lang_parse_float(p, &v, &at));
    if (!*ok)
        return true;
    if (kw == CSG_KW_EXPONENT && !(v > 0)) { /* (POV-Ray divides by it) */
        csg_error(p->d, at, "reflection exponent must be > 0, got %g", v);
        *ok = false;
    }
    switch (kw) {
    case CSG_KW_FRESNEL: f->reflection_fresnel = (int)v != 0; break; /* (POV-Ray's cast) */
    case CSG_KW_FALLOFF: f->reflection_falloff = v; break;
    case CSG_KW_EXPONENT: f->reflection_exponent = v; break;
    default: f->reflection_metallic = v; break;
    }
    return true;
}

/* reflection COLOR (MIN = MAX, falloff 1, no fresnel), or POV-Ray 3.5's
 * block: reflection { MIN [,] [MAX] OPTIONS } (MAX = MIN when not given);
 * POV-Ray's Parse_Finish. */
static bool parse_reflection(parser *p, csg_finish *f)
{
    csg_loc open = p->tok.loc;
    if (!lang_next(p))
        return false;
    if (!lang_is_punct(p, '{')) {
        if (!lang_parse_rgb(p, f->reflection))
            return false;
        memcpy(f->reflection_min, f->reflection, sizeof f->reflection);
        f->reflection_falloff = 1;
        f->reflection_fresnel = false;
        return true;
    }
    if (!lang_next(p) || !lang_parse_rgb(p, f->reflection_min))
        return false;
    if (lang_is_punct(p, ',') && !lang_next(p))
        return false;
    if (lang_is_color_start(p) || (lang_is_expr_start(p) && !lang_is_punct(p, '}'))) {
        if (!lang_parse_rgb(p, f->reflection))
            return false;
    } else {
        memcpy(f->reflection, f->reflection_min, sizeof f->reflection);
    }
    for (bool ok = true; parse_reflection_option(p, f, &ok);)
        if (!ok)
            return false;
    if (!lang_is_punct(p, '}'))
        return lang_expected_close(p, '}', "reflection", open);
    return lang_next(p);
}

/* At a finish's end: POV-Ray's rule (fresnel with MIN = MAX: MIN is 0),
 * and whether the reflection is anything but one colour (the workers'
 * constant path, bit for bit what it always was, is kept for those). */
static void finish_settle(csg_finish *f)
{
    bool same = memcmp(f->reflection, f->reflection_min, sizeof f->reflection) == 0;
    if (f->reflection_fresnel && same) {
        memset(f->reflection_min, 0, sizeof f->reflection_min);
        same = false;
    }
    f->reflection_variable = !same || f->reflection_fresnel || f->reflection_metallic != 0 ||
                             f->reflection_exponent != 1 || f->conserve_energy;
}

/* irid { AMOUNT { thickness F | turbulence VECTOR } } (POV-Ray's
 * Parse_Finish: the vector's x is the turbulence), in floats as POV-Ray. */
static bool parse_irid(parser *p, csg_finish *f)
{
    csg_loc open = lang_tok(p)->loc, at;
    double v;
    if (!lang_next(p) || !lang_expect_open(p, "irid") || !lang_parse_float(p, &v, &at) ||
        !lang_single_float(p, v, at, "irid", &f->irid))
        return false;
    for (;;) {
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        if (lang_is_kw(p, CSG_KW_THICKNESS)) {
            if (!lang_next(p) || !lang_parse_float(p, &v, &at) ||
                !lang_single_float(p, v, at, "thickness", &f->irid_thickness))
                return false;
        } else if (lang_is_kw(p, CSG_KW_TURBULENCE)) {
            dvec3 t;
            if (!lang_next(p) || !lang_parse_vector(p, &t, &at) ||
                !lang_single_float(p, t.x, at, "turbulence", &f->irid_turbulence))
                return false;
        } else {
            return lang_expected_close(p, '}', "irid", open);
        }
    }
}

bool lang_parse_finish(parser *p, csg_finish *f)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !lang_expect_open(p, "finish"))
        return false;
    if (lang_names(p, SYM_FINISH)) {
        const datum *d;
        if (!lang_lookup(p, SYM_FINISH, "a finish", &d))
            return false;
        *f = d->u.finish;
    }
    for (;;) {
        if (lang_is_punct(p, '}')) {
            finish_settle(f);
            return lang_next(p);
        }
        if (lang_tok(p)->kind != CSG_TOK_WORD)
            return lang_expected_close(p, '}', "finish", open);
        enum csg_kw kw = p->tok.kw;
        double *target = NULL;
        switch (kw) {
        case CSG_KW_CONSERVE_ENERGY:
            f->conserve_energy = true;
            if (!lang_next(p))
                return false;
            continue;
        case CSG_KW_FRESNEL: /* (the finish's: it also dims what is transmitted) */
            return lang_unsupported(p, "the finish's 'fresnel' (outside a reflection block)",
                                    p->tok.loc);
        case CSG_KW_AMBIENT:
            if (!lang_next(p) || !lang_parse_rgb(p, f->ambient))
                return false;
            continue;
        case CSG_KW_REFLECTION:
            if (!parse_reflection(p, f))
                return false;
            continue;
        case CSG_KW_IRID:
            if (!parse_irid(p, f))
                return false;
            continue;
        case CSG_KW_METALLIC: /* the amount is optional: 1 */
            if (!lang_next(p))
                return false;
            f->metallic = 1;
            if (lang_is_expr_start(p) && !lang_parse_float(p, &f->metallic, NULL))
                return false;
            continue;
        case CSG_KW_EMISSION:
            return lang_unsupported(p, "'emission'", p->tok.loc);
        case CSG_KW_DIFFUSE: target = &f->diffuse; break;
        case CSG_KW_BRILLIANCE: target = &f->brilliance; break;
        case CSG_KW_SPECULAR: target = &f->specular; break;
        case CSG_KW_ROUGHNESS: target = &f->roughness; break;
        case CSG_KW_PHONG: target = &f->phong; break;
        case CSG_KW_PHONG_SIZE: target = &f->phong_size; break;
        case CSG_KW_CRAND: target = &f->crand; break;
        case CSG_KW_REFLECTION_EXPONENT: target = &f->reflection_exponent; break;
        default:
            return lang_expected_close(p, '}', "finish", open);
        }
        csg_loc at;
        if (!lang_next(p) || !lang_parse_float(p, target, &at))
            return false;
        if (kw == CSG_KW_REFLECTION_EXPONENT && !(*target > 0)) {
            csg_error(p->d, at, "reflection_exponent must be > 0, got %g", *target);
            return false;
        }
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

/* ---- normals ---------------------------------------------------------------------- */

/* The keywords of POV-Ray's normal-only patterns (a pattern keyword in a
 * normal): their normal kind, CSG_NORMAL_PATTERN for any other. */
static int normal_kind_of(const csg_token *t)
{
#define NORMAL_WORD(ID, name)                                                                      \
    if (CSG_NORMAL_##ID != CSG_NORMAL_PATTERN && t->len == strlen(#name) &&                        \
        memcmp(t->text, #name, t->len) == 0)                                                       \
        return CSG_NORMAL_##ID;
    CSG_NORMALS(NORMAL_WORD)
#undef NORMAL_WORD
    return CSG_NORMAL_PATTERN;
}

/* quilted's control0 F, control1 F. */
static bool parse_quilted_modifier(parser *p, csg_pigment *pig)
{
    csg_loc at = lang_tok(p)->loc;
    double *c = lang_is_kw(p, CSG_KW_CONTROL0) ? &pig->control0 : &pig->control1;
    if (pig->pattern != CSG_PATTERN_QUILTED) {
        csg_error(p->d, at, "'%.*s' needs the quilted pattern", (int)lang_tok(p)->len,
                  lang_tok(p)->text);
        return false;
    }
    return lang_next(p) && lang_parse_float(p, c, NULL);
}

/* A block pattern in a normal: its values' slope (POV-Ray's
 * Parse_Blend_List finds no list of normals after it; such a list, whose
 * entries are normals, is not supported). */
static bool parse_normal_block(parser *p, csg_normal *n, int pattern)
{
    csg_loc at = lang_tok(p)->loc;
    if (!block_pattern_start(p, &n->pattern, pattern))
        return false;
    if (lang_is_kw(p, CSG_KW_NORMAL))
        return lang_unsupported(p, "a list of normals after checker, brick or hexagon", at);
    return true;
}

/* The pattern of a normal: its keyword, then the optional amount, as
 * POV-Ray's Parse_Pattern reads it (`bumps 0.4`, `bumps, 0.4`). */
static bool parse_normal_pattern(parser *p, csg_normal *n)
{
    csg_loc at = lang_tok(p)->loc;
    int pattern = csg_pattern_keyword(lang_tok(p)->text, lang_tok(p)->len, NULL);
    if (pattern == CSG_PATTERN_AVERAGE) /* (it averages a normal_map) */
        return lang_unsupported(p, "'average' in a normal", at);
    n->kind = normal_kind_of(lang_tok(p));
    if (is_block_pattern(pattern) ? !parse_normal_block(p, n, pattern)
                                  : !parse_pattern_keyword(p, &n->pattern))
        return false;
    if (lang_is_punct(p, ',') && !lang_next(p))
        return false;
    if (lang_is_expr_start(p) && !lang_parse_float(p, &n->amount, NULL))
        return false;
    return true;
}

bool lang_parse_normal(parser *p, csg_normal *n)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !lang_expect_open(p, "normal"))
        return false;
    if (lang_names(p, SYM_NORMAL)) {
        const datum *d;
        if (!lang_lookup(p, SYM_NORMAL, "a normal", &d))
            return false;
        *n = d->u.normal;
    } else if (!n->on) { /* POV-Ray: a copy of the default texture's, or a new one */
        *n = p->default_texture.normal;
        if (!n->on)
            csg_normal_default(n);
    }
    if (lang_is_kw(p, CSG_KW_PATTERN)) {
        if (!parse_normal_pattern(p, n))
            return false;
        n->on = true;
    }
    for (;;) {
        if (lang_is_punct(p, '}'))
            break;
        bool ok;
        if (lang_is_transform(p)) {
            ok = transform_pigment(p, &n->pattern);
        } else if (lang_is_kw(p, CSG_KW_BUMP_SIZE) || lang_is_kw(p, CSG_KW_ACCURACY)) {
            double *f = lang_is_kw(p, CSG_KW_BUMP_SIZE) ? &n->amount : &n->accuracy;
            ok = lang_next(p) && lang_parse_float(p, f, NULL);
        } else if (lang_is_kw(p, CSG_KW_NO_BUMP_SCALE)) {
            double f = 1;
            ok = lang_next(p) && (!lang_is_expr_start(p) || lang_parse_float(p, &f, NULL));
            n->no_bump_scale = f > 0;
        } else if (lang_is_kw(p, CSG_KW_FREQUENCY) || lang_is_kw(p, CSG_KW_PHASE)) {
            double *f = lang_is_kw(p, CSG_KW_FREQUENCY) ? &n->pattern.frequency : &n->pattern.phase;
            ok = lang_next(p) && lang_parse_float(p, f, NULL);
        } else if (lang_is_kw(p, CSG_KW_WAVE)) {
            ok = parse_wave(p, &n->pattern);
        } else if (is_noise_modifier(p)) {
            ok = parse_noise_modifier(p, &n->pattern);
        } else if (is_crackle_modifier(p)) {
            ok = parse_crackle_modifier(p, &n->pattern);
        } else if (is_brick_modifier(p)) {
            ok = parse_brick_modifier(p, &n->pattern);
        } else if (lang_is_kw(p, CSG_KW_CONTROL0) || lang_is_kw(p, CSG_KW_CONTROL1)) {
            ok = parse_quilted_modifier(p, &n->pattern);
        } else if (lang_is_kw(p, CSG_KW_SPHERICAL)) { /* (a camera's word too) */
            return lang_unsupported(p, "'spherical'", p->tok.loc);
        } else {
            return lang_expected_close(p, '}', "normal", open);
        }
        if (!ok)
            return false;
    }
    if (!n->on) { /* POV-Ray: "No normal type given." */
        csg_error(p->d, open, "a normal needs a pattern (bumps, dents, ripples, waves, ...)");
        return false;
    }
    return lang_next(p);
}

/* ---- textures ---------------------------------------------------------------------- */

bool lang_texture_patterned(const csg_texture *t)
{
    for (; t; t = t->under)
        if (t->tmap_count > 0 || t->pigment.pattern != CSG_PATTERN_PLAIN || t->normal.on)
            return true;
    return false;
}

/* t's own layer seen through x (its under layers untouched). */
static bool transform_layer(parser *p, csg_texture *t, const csg_xform *x)
{
    return lang_pigment_transform(p, &t->pigment, x) && /* a texture_map's pattern too */
           (!t->normal.on || lang_pigment_transform(p, &t->normal.pattern, x));
}

bool lang_texture_transform(parser *p, csg_texture *t, const csg_xform *x)
{
    if (!transform_layer(p, t, x))
        return false;
    csg_texture *layer = t;
    while (layer->under) { /* the layers below are shared: copied */
        csg_texture *copy = lang_alloc(p, sizeof *copy);
        if (!copy)
            return false;
        *copy = *layer->under;
        if (!transform_layer(p, copy, x))
            return false;
        layer->under = copy;
        layer = copy;
    }
    return true;
}

bool lang_texture_link(parser *p, const csg_texture *under, const csg_texture *top,
                       csg_texture *out, csg_loc at)
{
    if (!under) {
        *out = *top;
        return true;
    }
    if (under->tmap_count > 0 || (top->tmap_count > 0)) {
        csg_error(p->d, at, "cannot layer %s", under->tmap_count > 0
                                                   ? "over a patterned texture (texture_map)"
                                                   : "a patterned texture (texture_map) over another");
        return false;
    }
    const csg_texture *below = NULL;
    {
        csg_texture *u = lang_alloc(p, sizeof *u);
        if (!u)
            return false;
        *u = *under;
        below = u;
    }
    /* the new layers are copied, the last of them now over `under` */
    *out = *top;
    csg_texture *layer = out;
    while (layer->under) {
        csg_texture *copy = lang_alloc(p, sizeof *copy);
        if (!copy)
            return false;
        *copy = *layer->under;
        layer->under = copy;
        layer = copy;
    }
    layer->under = below;
    return true;
}

/* [TEXTURE_ID] then, for a plain texture, as POV-Ray allows, [PIGMENT_ID]
 * [NORMAL_ID] [FINISH_ID]; *modified: one of them was given. */
static bool parse_texture_ids(parser *p, csg_texture *t, bool *modified)
{
    const datum *d;
    if (lang_names(p, SYM_TEXTURE)) {
        if (!lang_lookup(p, SYM_TEXTURE, "a texture", &d))
            return false;
        *t = d->u.texture;
        *modified = true;
    }
    if (t->tmap_count > 0)
        return true;
    if (lang_names(p, SYM_PIGMENT)) {
        if (!lang_lookup(p, SYM_PIGMENT, "a pigment", &d))
            return false;
        t->pigment = d->u.pigment;
        *modified = true;
    }
    if (lang_names(p, SYM_NORMAL)) {
        if (!lang_lookup(p, SYM_NORMAL, "a normal", &d))
            return false;
        t->normal = d->u.normal;
        *modified = true;
    }
    if (lang_names(p, SYM_FINISH)) {
        if (!lang_lookup(p, SYM_FINISH, "a finish", &d))
            return false;
        t->finish = d->u.finish;
        *modified = true;
    }
    return true;
}

static bool parse_texture_body(parser *p, csg_texture *t, int closer, csg_loc open);

/* [F [,] TEXTURE_BODY]: the body starts from the default texture. */
static bool parse_texture_entry(parser *p, csg_texture_entry *e, bool average)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_enter(p, open) || !lang_next(p) || !parse_map_value(p, average, &e->value))
        return false;
    if (lang_is_punct(p, ',') && !lang_next(p))
        return false;
    e->texture = p->default_texture;
    if (!parse_texture_body(p, &e->texture, ']', open))
        return false;
    lang_leave(p);
    return true;
}

/* texture_map { [F TEXTURE_BODY] ... } into t's entries. */
static bool parse_texture_map(parser *p, csg_texture *t)
{
    csg_loc open = lang_tok(p)->loc;
    if (is_block_pattern(t->pigment.pattern)) {
        csg_error(p->d, open, "a texture_map needs a pattern that takes one "
                              "(any but checker, brick and hexagon)");
        return false;
    }
    if (!lang_enter(p, open) || !lang_next(p) || !lang_expect_open(p, "texture_map"))
        return false;
    csg_texture_entry *e = NULL;
    int n = 0, cap = 0;
    bool ok = true;
    while (ok && lang_is_punct(p, '[')) {
        if (n == CSG_MAP_MAX) {
            csg_error(p->d, lang_tok(p)->loc, "a texture_map has at most %d entries", CSG_MAP_MAX);
            ok = false;
            break;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 8;
            csg_texture_entry *grown = realloc(e, (size_t)cap * sizeof *grown);
            if (!grown) {
                ok = lang_oom(p);
                break;
            }
            e = grown;
        }
        ok = parse_texture_entry(p, &e[n++], t->pigment.pattern == CSG_PATTERN_AVERAGE);
    }
    if (ok && n == 0)
        ok = lang_expected(p, "'[' expected (a texture_map entry)");
    if (ok && !lang_is_punct(p, '}'))
        ok = lang_expected_close(p, '}', "texture_map", open);
    csg_texture_entry *copy = ok ? lang_alloc(p, (size_t)n * sizeof *copy) : NULL;
    if (copy) {
        memcpy(copy, e, (size_t)n * sizeof *copy);
        t->tmap = copy;
        t->tmap_count = n;
        lang_leave(p);
        ok = lang_next(p);
    } else {
        ok = false;
    }
    free(e);
    return ok;
}

/* A block pattern's textures, PATTERN texture {..} [,] [texture {..}] ..:
 * a texture_map of `count` entries, 0, 1, .., those not given the default
 * texture. */
static bool parse_block_textures(parser *p, csg_texture *t, int count)
{
    csg_texture_entry *e = lang_alloc(p, (size_t)count * sizeof *e);
    if (!e)
        return false;
    for (int i = 0; i < count; i++) {
        e[i].value = i;
        e[i].texture = p->default_texture;
    }
    for (int i = 0; i < count && lang_is_kw(p, CSG_KW_TEXTURE); i++)
        if (!lang_parse_texture(p, &e[i].texture) || (lang_is_punct(p, ',') && !lang_next(p)))
            return false;
    t->tmap = e;
    t->tmap_count = count;
    return true;
}

/* A patterned texture: PATTERN, then the pattern's modifiers and its
 * texture_map (checker, brick, hexagon: their textures), up to `closer`. */
static bool parse_texture_pattern(parser *p, csg_texture *t, int closer, csg_loc open)
{
    csg_pigment *pig = &t->pigment;
    csg_pigment_default(pig);
    csg_normal_default(&t->normal);
    t->under = NULL;
    int pattern = csg_pattern_keyword(lang_tok(p)->text, lang_tok(p)->len, NULL);
    if (is_block_pattern(pattern)) { /* (its colours: the pattern's count) */
        if (!block_pattern_start(p, pig, pattern) || !parse_block_textures(p, t, pig->map_count))
            return false;
    } else if (!parse_pattern_keyword(p, pig)) {
        return false;
    }
    for (;;) {
        if (lang_is_punct(p, closer))
            break;
        bool ok;
        if (lang_is_transform(p))
            ok = transform_pigment(p, pig);
        else if (lang_is_kw(p, CSG_KW_TEXTURE_MAP))
            ok = parse_texture_map(p, t);
        else if (lang_is_kw(p, CSG_KW_FREQUENCY) || lang_is_kw(p, CSG_KW_PHASE)) {
            double *f = lang_is_kw(p, CSG_KW_FREQUENCY) ? &pig->frequency : &pig->phase;
            ok = lang_next(p) && lang_parse_float(p, f, NULL);
        } else if (lang_is_kw(p, CSG_KW_WAVE))
            ok = parse_wave(p, pig);
        else if (is_noise_modifier(p))
            ok = parse_noise_modifier(p, pig);
        else if (is_crackle_modifier(p))
            ok = parse_crackle_modifier(p, pig);
        else if (is_brick_modifier(p))
            ok = parse_brick_modifier(p, pig);
        else if (lang_is_kw(p, CSG_KW_CONTROL0) || lang_is_kw(p, CSG_KW_CONTROL1))
            ok = parse_quilted_modifier(p, pig);
        else
            return lang_expected_close(p, closer, closer == '}' ? "texture" : "[", open);
        if (!ok)
            return false;
    }
    if (t->tmap_count == 0) {
        csg_error(p->d, open, "a patterned texture needs a texture_map");
        return false;
    }
    return lang_next(p);
}

/* What a texture { } holds, up to `closer` ('}', or ']' of a texture_map
 * entry), which is consumed; *t starts as the default texture. */
static bool parse_texture_body(parser *p, csg_texture *t, int closer, csg_loc open)
{
    bool modified = false;
    if (!parse_texture_ids(p, t, &modified))
        return false;
    if (!modified && lang_is_kw(p, CSG_KW_PATTERN))
        return parse_texture_pattern(p, t, closer, open);
    for (;;) {
        bool ok;
        if (lang_is_punct(p, closer))
            return lang_next(p);
        if (t->tmap_count > 0 && !lang_is_transform(p))
            return lang_expected_close(p, closer, closer == '}' ? "texture" : "[", open);
        if (lang_is_kw(p, CSG_KW_PIGMENT))
            ok = lang_parse_pigment(p, &t->pigment);
        else if (lang_is_kw(p, CSG_KW_NORMAL))
            ok = lang_parse_normal(p, &t->normal);
        else if (lang_is_kw(p, CSG_KW_FINISH))
            ok = lang_parse_finish(p, &t->finish);
        else if (lang_is_transform(p)) {
            csg_xform x;
            csg_xform_identity(&x);
            ok = lang_parse_transform(p, &x) && lang_texture_transform(p, t, &x);
        } else if (lang_is_kw(p, CSG_KW_PATTERN))
            return lang_unsupported(p, "a pattern after a texture's pigment, normal or finish", p->tok.loc);
        else
            return lang_expected_close(p, closer, closer == '}' ? "texture" : "[", open);
        if (!ok)
            return false;
    }
}

/* texture { [TEXTURE_ID] (pigment {..} | normal {..} | finish {..} |
 * TRANSFORM)* } or texture { PATTERN texture_map {..} ... }; starts from
 * the default texture (#default) and replaces *t. */
bool lang_parse_texture(parser *p, csg_texture *t)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !lang_expect_open(p, "texture"))
        return false;
    *t = p->default_texture;
    return parse_texture_body(p, t, '}', open);
}

bool lang_parse_material(parser *p, lang_material *m)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !lang_expect_open(p, "material"))
        return false;
    if (lang_names(p, SYM_MATERIAL)) {
        const datum *d;
        if (!lang_lookup(p, SYM_MATERIAL, "a material", &d))
            return false;
        *m = *d->u.material;
    }
    for (;;) {
        bool ok;
        csg_loc at = lang_tok(p)->loc;
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        if (lang_is_kw(p, CSG_KW_TEXTURE)) {
            csg_texture t;
            ok = lang_parse_texture(p, &t) &&
                 lang_texture_link(p, m->has_texture ? &m->texture : NULL, &t, &m->texture, at);
            m->has_texture = true;
        } else if (lang_is_kw(p, CSG_KW_INTERIOR)) {
            if (!m->has_interior) {
                m->interior.ior = 1.0;
                m->has_interior = true;
            }
            ok = lang_parse_interior(p, &m->interior);
        } else if (lang_is_transform(p)) {
            csg_xform x;
            csg_xform_identity(&x);
            ok = lang_parse_transform(p, &x) &&
                 (!m->has_texture || lang_texture_transform(p, &m->texture, &x));
        } else {
            return lang_expected_close(p, '}', "material", open);
        }
        if (!ok)
            return false;
    }
}

bool lang_parse_interior(parser *p, csg_interior *in)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_next(p) || !lang_expect_open(p, "interior"))
        return false;
    if (lang_names(p, SYM_INTERIOR)) {
        const datum *d;
        if (!lang_lookup(p, SYM_INTERIOR, "an interior", &d))
            return false;
        *in = d->u.interior;
    }
    for (;;) {
        if (lang_is_punct(p, '}'))
            return lang_next(p);
        csg_loc at;
        if (lang_is_kw(p, CSG_KW_FADE_COLOR)) {
            if (!lang_next(p) || !lang_parse_rgb(p, in->fade_color))
                return false;
            continue;
        }
        if (lang_is_kw(p, CSG_KW_FADE_DISTANCE) || lang_is_kw(p, CSG_KW_FADE_POWER)) {
            double *f = lang_is_kw(p, CSG_KW_FADE_DISTANCE) ? &in->fade_distance : &in->fade_power;
            if (!lang_next(p) || !lang_parse_float(p, f, &at))
                return false;
            continue;
        }
        if (!lang_is_kw(p, CSG_KW_IOR))
            return lang_expected_close(p, '}', "interior", open);
        if (!lang_next(p) || !lang_parse_float(p, &in->ior, &at))
            return false;
        if (!(in->ior > 0)) {
            csg_error(p->d, at, "ior must be > 0, got %g", in->ior);
            return false;
        }
    }
}
