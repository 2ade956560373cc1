/*
 * scene.c — the scene tree's support: defaults (POV-Ray 3.7's), affine
 * transforms in double, the arena that owns a scene's memory, and the
 * names and roles of the object kinds (CSG_OBJECT_KINDS), of the patterns
 * and of the waves (device/patterns.h).
 */
#include "scene.h"

#include "device/flat.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void csg_finish_default(csg_finish *f)
{
    memset(f, 0, sizeof *f);
    f->ambient[0] = f->ambient[1] = f->ambient[2] = 0.1;
    f->diffuse = 0.6;
    f->brilliance = 1;
    f->roughness = 0.05;
    f->phong_size = 40;
    f->reflection_falloff = 1;
    f->reflection_exponent = 1;
}

void csg_pigment_default(csg_pigment *p)
{
    memset(p, 0, sizeof *p); /* POV-Ray's default pigment is black */
    p->frequency = 1.0;
    p->exponent = 1.0;
    p->turb.octaves = 6; /* POV-Ray's classic turbulence defaults */
    p->turb.omega = 0.5;
    p->turb.lambda = 2.0;
    p->agate_turb = 1.0;
    p->control0 = p->control1 = 1.0;
    csg_xform_identity(&p->xform);
}

void csg_normal_default(csg_normal *n)
{
    memset(n, 0, sizeof *n);
    n->kind = CSG_NORMAL_PATTERN;
    csg_pigment_default(&n->pattern);
    n->amount = 0.5;
    n->accuracy = 0.02;
}

int csg_noise_of(const csg_scene *s, const csg_pigment *pig)
{
    if (pig->noise_generator)
        return pig->noise_generator;
    if (s->globals.noise_generator)
        return s->globals.noise_generator;
    return s->version < 3.5 ? 1 : 2;
}

int csg_version_int(double v)
{
    double x = v * 100 + 0.5; /* (any #version reads: clamped into int first) */
    return x >= (double)INT_MAX ? INT_MAX : x > (double)INT_MIN ? (int)x : INT_MIN;
}

bool csg_version_v37(const csg_scene *s)
{
    return !s->version_implied && csg_version_int(s->version) >= 370;
}

int csg_output_gamma(const csg_scene *s, double *gamma)
{
    *gamma = 1.0;
    switch (s->globals.gamma_kind) {
    case CSG_GAMMA_SRGB:
        return CSG_OUTPUT_DIRECT;
    case CSG_GAMMA_POWER: {
        /* POV-Ray's PowerLawGammaCurve keeps 1/G as a float and takes a
         * curve within 1 % of neutral for the neutral one */
        float enc = 1.0f / (float)s->globals.assumed_gamma;
        if (fabs(1.0 - (double)enc) <= 0.01)
            return CSG_OUTPUT_SRGB;
        *gamma = s->globals.assumed_gamma;
        return CSG_OUTPUT_POWER;
    }
    default:
        return csg_version_v37(s) ? CSG_OUTPUT_SRGB : CSG_OUTPUT_DIRECT;
    }
}

void csg_texture_default(csg_texture *t)
{
    memset(t, 0, sizeof *t);
    csg_pigment_default(&t->pigment);
    csg_finish_default(&t->finish);
    csg_normal_default(&t->normal);
}

void csg_globals_default(csg_globals *g)
{
    g->gamma_kind = CSG_GAMMA_UNSET;
    g->assumed_gamma = 1.0;
    g->max_trace_level = 5;
    g->adc_bailout = 1.0 / 255.0;
    g->ambient_light[0] = g->ambient_light[1] = g->ambient_light[2] = 1.0;
    g->noise_generator = 0;
    g->number_of_waves = 10;
    g->irid_wavelength[0] = (double)0.70f; /* POV-Ray's RGBColour(0.70, 0.52, 0.48) */
    g->irid_wavelength[1] = (double)0.52f;
    g->irid_wavelength[2] = (double)0.48f;
}

void csg_xform_identity(csg_xform *x)
{
    memset(x, 0, sizeof *x);
    x->m[0][0] = x->m[1][1] = x->m[2][2] = 1.0;
}

void csg_xform_then(const csg_xform *a, const csg_xform *b, csg_xform *out)
{
    csg_xform r;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 4; j++) {
            double s = j == 3 ? b->m[i][3] : 0.0;
            for (int k = 0; k < 3; k++)
                s += b->m[i][k] * a->m[k][j];
            r.m[i][j] = s;
        }
    }
    *out = r;
}

bool csg_xform_finite(const csg_xform *x)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            if (!isfinite(x->m[i][j]))
                return false;
    return true;
}

bool csg_xform_invert(const csg_xform *x, csg_xform *inv)
{
    const double(*m)[4] = x->m;
    double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    if (!(fabs(det) > 0) || !isfinite(det))
        return false;
    double id = 1.0 / det;
    csg_xform r;
    r.m[0][0] = c00 * id;
    r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * id;
    r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * id;
    r.m[1][0] = c01 * id;
    r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * id;
    r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * id;
    r.m[2][0] = c02 * id;
    r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * id;
    r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * id;
    for (int i = 0; i < 3; i++)
        r.m[i][3] = -(r.m[i][0] * m[0][3] + r.m[i][1] * m[1][3] + r.m[i][2] * m[2][3]);
    *inv = r;
    return true;
}

void csg_xform_translate(csg_xform *x, dvec3 t)
{
    x->m[0][3] += t.x;
    x->m[1][3] += t.y;
    x->m[2][3] += t.z;
}

void csg_xform_scale(csg_xform *x, dvec3 s)
{
    double f[3] = {s.x, s.y, s.z};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            x->m[i][j] *= f[i];
}

/* Rotation by `deg` degrees about one axis, POV-Ray's (left-handed) sense.
 * Multiples of 90 degrees are exact, so `rotate 90*y` leaves no 6e-17. */
static void rotation_about(int axis, double deg, csg_xform *r)
{
    double s, c;
    double q = fmod(deg, 360.0);
    if (q < 0)
        q += 360.0;
    if (q == 0) {
        s = 0; c = 1;
    } else if (q == 90) {
        s = 1; c = 0;
    } else if (q == 180) {
        s = 0; c = -1;
    } else if (q == 270) {
        s = -1; c = 0;
    } else {
        double rad = deg * M_PI / 180.0;
        s = sin(rad);
        c = cos(rad);
    }
    csg_xform_identity(r);
    int i = (axis + 1) % 3, j = (axis + 2) % 3;
    r->m[i][i] = c;
    r->m[i][j] = -s;
    r->m[j][i] = s;
    r->m[j][j] = c;
}

void csg_prism_pov_frame(csg_xform *x)
{
    csg_xform swap;
    memset(&swap, 0, sizeof swap);
    swap.m[0][0] = 1;
    swap.m[1][2] = 1;
    swap.m[2][1] = 1;
    csg_xform_then(&swap, x, x);
}

void csg_xform_rotate(csg_xform *x, dvec3 degrees)
{
    double d[3] = {degrees.x, degrees.y, degrees.z};
    for (int axis = 0; axis < 3; axis++) {
        if (d[axis] == 0)
            continue;
        csg_xform r;
        rotation_about(axis, d[axis], &r);
        csg_xform_then(x, &r, x);
    }
}

/* ---- arena ---------------------------------------------------------------- */

typedef struct arena_block {
    struct arena_block *next;
    size_t used, size;
    _Alignas(16) unsigned char data[];
} arena_block;

typedef struct arena_adopted {
    struct arena_adopted *next;
    void *block;
} arena_adopted;

struct csg_arena {
    arena_block *head;
    arena_adopted *adopted; /* (the list's nodes are in the blocks) */
};

csg_arena *csg_arena_new(void)
{
    return calloc(1, sizeof(csg_arena));
}

void *csg_arena_alloc(csg_arena *a, size_t size)
{
    size = (size + 15u) & ~(size_t)15u;
    if (!a->head || a->head->size - a->head->used < size) {
        size_t cap = size > 65536 ? size : 65536;
        arena_block *b = malloc(sizeof *b + cap);
        if (!b)
            return NULL;
        b->next = a->head;
        b->used = 0;
        b->size = cap;
        a->head = b;
    }
    void *p = a->head->data + a->head->used;
    a->head->used += size;
    memset(p, 0, size);
    return p;
}

bool csg_arena_adopt(csg_arena *a, void *block)
{
    arena_adopted *node = csg_arena_alloc(a, sizeof *node);
    if (!node)
        return false;
    node->block = block;
    node->next = a->adopted;
    a->adopted = node;
    return true;
}

void csg_arena_free(csg_arena *a)
{
    if (!a)
        return;
    for (arena_adopted *n = a->adopted; n; n = n->next)
        free(n->block);
    for (arena_block *b = a->head, *next; b; b = next) {
        next = b->next;
        free(b);
    }
    free(a);
}

csg_loc csg_piece_loc(const csg_object *o, int piece)
{
    return o->piece_locs ? o->piece_locs[piece] : o->loc;
}

void csg_scene_init(csg_scene *s)
{
    memset(s, 0, sizeof *s);
    csg_globals_default(&s->globals);
    s->version = 3.7;
    s->background[0] = s->background[1] = s->background[2] = 0.0;
}

void csg_scene_free(csg_scene *s)
{
    csg_arena_free(s->arena);
    s->arena = NULL;
}

/* ---- the table of object kinds ---------------------------------------------- */

#define SCENE_KIND_NAME(ID, name) [CSG_OBJ_##ID] = #name,
static const char *const object_kind_names[CSG_OBJ_KIND_COUNT] = {
    CSG_OBJECT_KINDS(SCENE_KIND_NAME, SCENE_KIND_NAME)};

const char *csg_object_kind_name(int kind)
{
    return kind >= 0 && kind < CSG_OBJ_KIND_COUNT ? object_kind_names[kind] : NULL;
}

double csg_poly_value(int order, const double *coef, dvec3 p, dvec3 *grad)
{
    double px[CSG_POLY_ORDER_MAX + 1] = {1}, py[CSG_POLY_ORDER_MAX + 1] = {1},
           pz[CSG_POLY_ORDER_MAX + 1] = {1};
    if (order > CSG_POLY_ORDER_MAX)
        order = CSG_POLY_ORDER_MAX;
    for (int e = 1; e <= order; e++) {
        px[e] = px[e - 1] * p.x;
        py[e] = py[e - 1] * p.y;
        pz[e] = pz[e - 1] * p.z;
    }
    double v = 0;
    dvec3 g = {0, 0, 0};
    int term = 0;
    for (int i = order; i >= 0; i--)
        for (int j = order - i; j >= 0; j--)
            for (int k = order - i - j; k >= 0; k--) {
                double a = coef[term++];
                v += a * px[i] * py[j] * pz[k];
                g.x += i > 0 ? i * a * px[i - 1] * py[j] * pz[k] : 0;
                g.y += j > 0 ? j * a * px[i] * py[j - 1] * pz[k] : 0;
                g.z += k > 0 ? k * a * px[i] * py[j] * pz[k - 1] : 0;
            }
    if (grad)
        *grad = g;
    return v;
}

bool csg_object_is_leaf(int kind)
{
    switch (kind) {
#define SCENE_KIND_LEAF(ID, name) case CSG_OBJ_##ID:
        CSG_OBJECT_KINDS(SCENE_KIND_LEAF, CSG_KIND_NONE)
        return true;
    default:
        return false;
    }
}

/* ---- the tables of patterns and waves (device/patterns.h) ------------------- */

#define SCENE_PATTERN_NAME(ID, name, wave, noise, warp) [CSG_PATTERN_##ID] = #name,
static const char *const pattern_names[CSG_PATTERN_COUNT] = {
    CSG_PATTERNS(SCENE_PATTERN_NAME, SCENE_PATTERN_NAME)};

#define SCENE_PATTERN_WAVE(ID, name, wave, noise, warp) [CSG_PATTERN_##ID] = CSG_WAVE_##wave,
static const enum csg_wave pattern_waves[CSG_PATTERN_COUNT] = {
    CSG_PATTERNS(SCENE_PATTERN_WAVE, SCENE_PATTERN_WAVE)};

#define SCENE_PATTERN_NOISE(ID, name, wave, noise, warp) [CSG_PATTERN_##ID] = noise,
static const bool pattern_noise[CSG_PATTERN_COUNT] = {
    CSG_PATTERNS(SCENE_PATTERN_NOISE, SCENE_PATTERN_NOISE)};

#define SCENE_WAVE_NAME(ID, name) [CSG_WAVE_##ID] = #name,
static const char *const wave_names[CSG_WAVE_COUNT] = {CSG_WAVES(SCENE_WAVE_NAME)};

const char *csg_pattern_name(int pattern)
{
    return pattern >= 0 && pattern < CSG_PATTERN_COUNT ? pattern_names[pattern] : NULL;
}

const char *csg_wave_name(int wave)
{
    return wave >= 0 && wave < CSG_WAVE_COUNT ? wave_names[wave] : NULL;
}

enum csg_wave csg_pattern_wave(enum csg_pattern pattern)
{
    return (int)pattern >= 0 && pattern < CSG_PATTERN_COUNT ? pattern_waves[pattern] : CSG_WAVE_RAMP;
}

bool csg_pattern_reads_noise(enum csg_pattern pattern)
{
    return (int)pattern >= 0 && pattern < CSG_PATTERN_COUNT && pattern_noise[pattern];
}

int csg_pattern_blocks(int pattern)
{
    if (pattern == CSG_PATTERN_CHECKER || pattern == CSG_PATTERN_BRICK)
        return 2;
    return pattern == CSG_PATTERN_HEXAGON ? 3 : 0;
}
