/*
 * test_kinds.c — every kind of the object table (CSG_OBJECT_KINDS, scene.h)
 * and of the primitive table (CSG_PRIM_KINDS, device/flat.h) is handled by
 * every stage.  The compiler already refuses a kind whose per-stage
 * function is missing; this catches what it cannot see:
 *   - a kind with no name, or two kinds with one name;
 *   - a keyword the lexer does not know (its table is written by hand);
 *   - a shape kind that some stage handles wrongly: a sample of each goes
 *     through parse -> summary -> precision -> flatten (both precisions) ->
 *     blob validation -> a primary ray -> export -> parse again;
 *   - an operator kind that does not parse or export.
 * A kind added to a table without a sample here fails test_samples_cover.
 *
 * The same for the tables of patterns and waves (csg/device/patterns.h),
 * whose rows need no sample: each row's keyword is a keyword of the lexer
 * and parses to its row, every pattern and wave flattens to its own id in
 * the blob (no map between the two), and export writes it back; and the
 * other side of "no default": a blob holding a pattern or a wave outside
 * the tables is refused by csg_blob_valid, so no worker evaluates one.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "../csg/export_pov.h"
#include "../csg/flatten.h"
#include "../csg/lang/lexer.h"
#include "../csg/lang/parser.h"
#include "../csg/precision.h"
#include "../csg/summary.h"
#include "../workers/engine.h"

/* One statement of each kind, in front of the camera at the origin. */
static const char *const samples[CSG_OBJ_KIND_COUNT] = {
    [CSG_OBJ_SPHERE] = "sphere { <0, 0, 5>, 1 }",
    [CSG_OBJ_BOX] = "box { <-1, -1, 4>, <1, 1, 6> }",
    [CSG_OBJ_CYLINDER] = "cylinder { <0, -1, 5>, <0, 1, 5>, 1 }",
    [CSG_OBJ_CONE] = "cone { <0, -1, 5>, 1, <0, 1, 5>, 0.5 }",
    [CSG_OBJ_PLANE] = "plane { <0, 0, -1>, -5 }",
    [CSG_OBJ_TORUS] = "torus { 1, 0.4 sturm translate <0, 0, 5> }",
    [CSG_OBJ_QUADRIC] = "quadric { <1, 1, 1>, <0, 0, 0>, <0, 0, 0>, -1 translate <0, 0, 5> }",
    /* (x^2 + y^2 + z^2)^2 - 1: the unit sphere as a quartic */
    [CSG_OBJ_POLY] = "poly { 4, <1, 0, 0, 0, 2, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, "
                     "0, 0, 2, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, -1> sturm translate <0, 0, 5> }",
    [CSG_OBJ_TRIANGLE] = "triangle { <-1, -1, 5>, <1, -1, 5>, <0, 1, 5> }",
    [CSG_OBJ_SMOOTH_TRIANGLE] = "smooth_triangle { <-1, -1, 5>, <0, 0, -1>, <1, -1, 5>, "
                                "<0.1, 0, -1>, <0, 1, 5>, <0, 0.1, -1> }",
    [CSG_OBJ_POLYGON] = "polygon { 5, <-1, -1, 5>, <1, -1, 5>, <1, 1, 5>, <0, 0.5, 5>, "
                        "<-1, 1, 5> }",
    [CSG_OBJ_MESH] = "mesh { triangle { <-1, -1, 5>, <1, -1, 5>, <0, 1, 5> } "
                     "smooth_triangle { <-1, 1, 6>, <0, 0, -1>, <1, 1, 6>, <0, 0, -1>, "
                     "<0, -1, 6>, <0, 0, -1> } }",
    [CSG_OBJ_PRISM] = "prism { linear_spline -1, 1, 5, <-1, 4>, <1, 4>, <0.5, 6>, <-0.5, 5>, "
                      "<-1, 4> }",
    [CSG_OBJ_UNION] = "union { sphere { <0, 0, 5>, 1 } box { <-1, -1, 4>, <1, 1, 6> } }",
    [CSG_OBJ_INTERSECTION] = "intersection { sphere { <0, 0, 5>, 1 } box { <-1, -1, 4>, <1, 1, 6> } }",
    [CSG_OBJ_DIFFERENCE] = "difference { box { <-1, -1, 4>, <1, 1, 6> } sphere { <0, 0, 3>, 1 } }",
    [CSG_OBJ_MERGE] = "merge { sphere { <0, 0, 5>, 1 } box { <-1, -1, 4>, <1, 1, 6> } }",
};

/* Statements that reach a primitive kind no sample above reaches: a box
 * of zero thickness is a flat_box (a sheet), a conic prism's pieces are
 * conic trapezoids. */
static const struct {
    enum csg_object_kind kind;
    const char *text;
} more_samples[] = {
    {CSG_OBJ_BOX, "box { <-1, -1, 5>, <1, 1, 5> }"},
    /* the unit sphere as a cubic (no cubic term: its degree drops) */
    {CSG_OBJ_POLY, "cubic { <0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1> "
                   "translate <0, 0, 5> }"},
    {CSG_OBJ_PRISM, "prism { conic_sweep linear_spline 0.5, 1, 4, <-1, 4>, <1, 4>, <0, 6>, "
                    "<-1, 4> translate <0, -0.75, 0> }"},
};

#define CAMERA "camera { location <0, 0, 0> look_at <0, 0, 1> }\n"

static void test_samples_cover(void **state)
{
    (void)state;
    for (int k = 0; k < CSG_OBJ_KIND_COUNT; k++) {
        if (!samples[k])
            fail_msg("no sample for object kind %d (%s)", k, csg_object_kind_name(k));
        /* the sample is written with the kind's own keyword */
        size_t n = strlen(csg_object_kind_name(k));
        assert_memory_equal(samples[k], csg_object_kind_name(k), n);
    }
}

static void test_names(void **state)
{
    (void)state;
    for (int k = 0; k < CSG_OBJ_KIND_COUNT; k++) {
        assert_non_null(csg_object_kind_name(k));
        for (int j = 0; j < k; j++)
            assert_string_not_equal(csg_object_kind_name(j), csg_object_kind_name(k));
    }
    assert_null(csg_object_kind_name(-1));
    assert_null(csg_object_kind_name(CSG_OBJ_KIND_COUNT));
    assert_false(csg_object_is_leaf(-1));
    assert_false(csg_object_is_leaf(CSG_OBJ_KIND_COUNT));
}

static void parse_ok(const char *text, csg_scene *s)
{
    csg_diag d = {0};
    csg_scene_init(s);
    if (!csg_parse_string("kinds.pov", text, strlen(text), s, &d))
        fail_msg("parse of <%s> failed: %s", text, d.message);
}

/* The one top-level object of a sample parses to its kind. */
static void test_parse_each(void **state)
{
    (void)state;
    char text[512];
    for (int k = 0; k < CSG_OBJ_KIND_COUNT; k++) {
        snprintf(text, sizeof text, CAMERA "%s\n", samples[k]);
        csg_scene s;
        parse_ok(text, &s);
        assert_int_equal(s.object_count, 1);
        assert_int_equal(s.objects[0]->kind, k);
        assert_int_equal(csg_object_is_leaf(k), s.objects[0]->child_count == 0);
        csg_scene_free(&s);
    }
}

/* Flattened in both precisions: a valid blob whose primitives are all of
 * known kinds, and whose centre ray hits the object. */
static void flatten_and_hit(const engine *e, const csg_scene *s, int k, unsigned *prim_kinds)
{
    csg_flatten_opts o = {3, 3, 1, -1, 1, 0};
    csg_diag d = {0};
    csg_blob b;
    if (!e->flatten(s, &o, &b, &d))
        fail_msg("%s: flatten (%s) failed: %s", csg_object_kind_name(k), e->name, d.message);
    assert_true(csg_blob_valid(b.bytes, b.size));
    const csg_blob_header *h = csg_blob_hdr(b.bytes);
    assert_true(h->prim_count >= 1);
    const csg_prim *prims = (const csg_prim *)(const void *)((const char *)b.bytes + h->off_prims);
    for (int i = 0; e->real_size == sizeof(real) && i < h->prim_count; i++)
        *prim_kinds |= 1u << prims[i].kind; /* (this file's csg_prim is the float one) */
    char t[9 * 8];
    uint32_t surf[9];
    ray_counts rays = {0};
    tile_rect all = {0, 0, 3, 3};
    e->trace_primary(b.bytes, all, t, surf, &rays);
    if (surf[4] == 0)
        fail_msg("%s (%s): the centre ray misses", csg_object_kind_name(k), e->name);
    csg_blob_free(&b);
}

static void test_pipeline_each(void **state)
{
    (void)state;
    char text[512];
    unsigned prim_kinds = 0;
    for (int k = 0; k < CSG_OBJ_KIND_COUNT; k++) {
        snprintf(text, sizeof text, CAMERA "%s\n", samples[k]);
        csg_scene s;
        parse_ok(text, &s);
        FILE *sink = fopen("/dev/null", "w");
        assert_non_null(sink);
        csg_print_summary(&s, sink);
        fclose(sink);
        char why[256];
        assert_false(csg_needs_double(&s, 3, 3, why, sizeof why)); /* a unit scene */
        flatten_and_hit(&engine_float, &s, k, &prim_kinds);
        flatten_and_hit(&engine_double, &s, k, &prim_kinds);
        csg_scene_free(&s);
    }
    for (size_t m = 0; m < sizeof more_samples / sizeof more_samples[0]; m++) {
        snprintf(text, sizeof text, CAMERA "%s\n", more_samples[m].text);
        csg_scene s;
        parse_ok(text, &s);
        assert_int_equal(s.objects[0]->kind, more_samples[m].kind);
        char why[256];
        assert_false(csg_needs_double(&s, 3, 3, why, sizeof why)); /* a unit scene */
        flatten_and_hit(&engine_float, &s, more_samples[m].kind, &prim_kinds);
        flatten_and_hit(&engine_double, &s, more_samples[m].kind, &prim_kinds);
        csg_scene_free(&s);
    }
    /* the samples reach every primitive kind the tracers know */
    assert_int_equal(prim_kinds, (1u << CSG_PRIM_KIND_COUNT) - 1);
}

/* Exported and parsed again: the same kinds, in the same tree shape. */
static void same_shape(const csg_object *a, const csg_object *b)
{
    assert_int_equal(a->kind, b->kind);
    assert_int_equal(a->child_count, b->child_count);
    for (int i = 0; i < a->child_count; i++)
        same_shape(a->children[i], b->children[i]);
}

static void test_export_each(void **state)
{
    (void)state;
    char text[512];
    for (int k = 0; k < CSG_OBJ_KIND_COUNT; k++) {
        snprintf(text, sizeof text, CAMERA "%s\n", samples[k]);
        csg_scene s, back;
        parse_ok(text, &s);
        char *out = NULL;
        size_t len = 0;
        FILE *f = open_memstream(&out, &len);
        assert_non_null(f);
        csg_diag d = {0};
        if (!csg_export_pov(&s, f, false, &d))
            fail_msg("%s: export failed: %s", csg_object_kind_name(k), d.message);
        fclose(f);
        parse_ok(out, &back);
        assert_int_equal(back.object_count, 1);
        same_shape(s.objects[0], back.objects[0]);
        free(out);
        csg_scene_free(&back);
        csg_scene_free(&s);
    }
}

/* ---- the tables of patterns and waves ---------------------------------------- */

static void test_pattern_names(void **state)
{
    (void)state;
    for (int k = 0; k < CSG_PATTERN_COUNT; k++) {
        assert_non_null(csg_pattern_name(k));
        for (int j = 0; j < k; j++)
            assert_string_not_equal(csg_pattern_name(j), csg_pattern_name(k));
    }
    for (int w = 0; w < CSG_WAVE_COUNT; w++) {
        assert_non_null(csg_wave_name(w));
        for (int j = 0; j < w; j++)
            assert_string_not_equal(csg_wave_name(j), csg_wave_name(w));
    }
    assert_null(csg_pattern_name(-1));
    assert_null(csg_pattern_name(CSG_PATTERN_COUNT));
    assert_null(csg_wave_name(-1));
    assert_null(csg_wave_name(CSG_WAVE_COUNT));
    /* the ids a blob holds: appended rows keep them */
    assert_int_equal(CSG_PATTERN_PLAIN, 0);
    assert_int_equal(CSG_PATTERN_CRACKLE, 15);
    assert_int_equal(CSG_WAVE_POLY, 5);
}

static void assert_pattern_word(const char *word, int pattern, bool alias)
{
    bool is_alias = !alias;
    assert_int_equal(csg_keyword(word, strlen(word), false), CSG_KW_PATTERN);
    assert_int_equal(csg_pattern_keyword(word, strlen(word), &is_alias), pattern);
    assert_int_equal(is_alias, alias);
}

/* Every pattern's name is a pattern keyword (plain's is none: an
 * identifier), every alias too, every wave's <name>_wave a wave keyword. */
static void test_pattern_keywords(void **state)
{
    (void)state;
    for (int k = 0; k < CSG_PATTERN_COUNT; k++) {
        const char *name = csg_pattern_name(k);
        if (k == CSG_PATTERN_PLAIN) {
            assert_int_equal(csg_keyword(name, strlen(name), false), CSG_KW_NONE);
            assert_int_equal(csg_pattern_keyword(name, strlen(name), NULL), -1);
        } else {
            assert_pattern_word(name, k, false);
        }
    }
#define KINDS_ALIAS(word, ID) assert_pattern_word(#word, CSG_PATTERN_##ID, true);
    CSG_PATTERN_ALIASES(KINDS_ALIAS)
#undef KINDS_ALIAS
    for (int w = 0; w < CSG_WAVE_COUNT; w++) {
        char word[64];
        snprintf(word, sizeof word, "%s_wave", csg_wave_name(w));
        assert_int_equal(csg_keyword(word, strlen(word), false), CSG_KW_WAVE);
        assert_int_equal(csg_wave_keyword(word, strlen(word)), w);
    }
    assert_int_equal(csg_wave_keyword("ramp", 4), -1);
    assert_int_equal(csg_pattern_keyword("bozo_", 5, NULL), -1);
}

/* A sphere with `pigment { BODY }` in front of the camera. */
static void parse_pigment(const char *body, csg_scene *s)
{
    char text[512];
    snprintf(text, sizeof text, CAMERA "sphere { <0, 0, 5>, 1 pigment { %s } }\n", body);
    parse_ok(text, s);
}

static const csg_pigment *pigment_of(const csg_scene *s)
{
    return &s->textures[s->objects[0]->texture].pigment;
}

/* The blob's materials (this file's csg_material is the float one). */
static csg_material *blob_materials(const csg_blob *b)
{
    const csg_blob_header *h = csg_blob_hdr(b->bytes);
    assert_int_equal(h->real_size, sizeof(real));
    return (csg_material *)(void *)((char *)b->bytes + h->off_materials);
}

/* s flattened (float): its primitive's material has this pattern and
 * wave (wave < 0: not looked at), and the blob is valid. */
static void assert_flat_ids(const csg_scene *s, int pattern, int wave)
{
    csg_flatten_opts o = {3, 3, 1, -1, 1, 0};
    csg_diag d = {0};
    csg_blob b;
    if (!engine_float.flatten(s, &o, &b, &d))
        fail_msg("flatten failed: %s", d.message);
    assert_true(csg_blob_valid(b.bytes, b.size));
    const csg_blob_header *h = csg_blob_hdr(b.bytes);
    const csg_prim *prims = (const csg_prim *)(const void *)((const char *)b.bytes + h->off_prims);
    const csg_material *m = &blob_materials(&b)[prims[0].material];
    assert_int_equal(m->pattern, pattern);
    if (wave >= 0)
        assert_int_equal(m->wave, wave);
    csg_blob_free(&b);
}

/* Exported and parsed again: the same pattern and wave. */
static void assert_export_keeps(const csg_scene *s)
{
    char *out = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&out, &len);
    assert_non_null(f);
    csg_diag d = {0};
    if (!csg_export_pov(s, f, false, &d))
        fail_msg("export failed: %s", d.message);
    fclose(f);
    csg_scene back;
    parse_ok(out, &back);
    assert_int_equal(pigment_of(&back)->pattern, pigment_of(s)->pattern);
    assert_int_equal(pigment_of(&back)->wave, pigment_of(s)->wave);
    free(out);
    csg_scene_free(&back);
}

/* Each pattern by its keyword (gradient needs its vector, the spirals
 * their arms, pigment_pattern its pigment): parsed to its
 * row with the table's default wave, flattened to the same id, exported
 * back; each wave likewise. */
static void test_pattern_pipeline(void **state)
{
    (void)state;
    char body[128];
    for (int k = 0; k < CSG_PATTERN_COUNT; k++) {
        if (k == CSG_PATTERN_PLAIN)
            snprintf(body, sizeof body, "rgb <1, 0.5, 0>");
        else
            snprintf(body, sizeof body, "%s%s", csg_pattern_name(k),
                     k == CSG_PATTERN_GRADIENT  ? " y"
                     : k == CSG_PATTERN_AVERAGE ? " pigment_map { [1 rgb 1] }"
                     : k == CSG_PATTERN_SPIRAL1 || k == CSG_PATTERN_SPIRAL2 ? " 3"
                     : k == CSG_PATTERN_PIGMENT_PATTERN ? " { bozo }"
                                                : "");
        csg_scene s;
        parse_pigment(body, &s);
        assert_int_equal(pigment_of(&s)->pattern, k);
        assert_int_equal(pigment_of(&s)->wave, csg_pattern_wave(k));
        assert_flat_ids(&s, k, k == CSG_PATTERN_PLAIN ? -1 : (int)csg_pattern_wave(k));
        assert_export_keeps(&s);
        csg_scene_free(&s);
    }
    for (int w = 0; w < CSG_WAVE_COUNT; w++) {
        snprintf(body, sizeof body, "wood %s_wave", csg_wave_name(w));
        csg_scene s;
        parse_pigment(body, &s);
        assert_int_equal(pigment_of(&s)->wave, w);
        assert_flat_ids(&s, CSG_PATTERN_WOOD, w);
        assert_export_keeps(&s);
        csg_scene_free(&s);
    }
}

/* A pattern or a wave outside the tables: the validator refuses the blob
 * (the workers' dispatch has no default to fall back on). */
static void test_blob_refuses_unknown(void **state)
{
    (void)state;
    csg_scene s;
    parse_pigment("bozo sine_wave", &s);
    csg_flatten_opts o = {3, 3, 1, -1, 1, 0};
    csg_diag d = {0};
    csg_blob b;
    assert_true(engine_float.flatten(&s, &o, &b, &d));
    csg_material *m = &blob_materials(&b)[0];
    assert_int_equal(m->pattern, CSG_PATTERN_BOZO);
    assert_true(csg_blob_valid(b.bytes, b.size));
    const int bad_patterns[] = {-1, CSG_PATTERN_COUNT, 1000};
    for (size_t i = 0; i < sizeof bad_patterns / sizeof bad_patterns[0]; i++) {
        m->pattern = bad_patterns[i];
        assert_false(csg_blob_valid(b.bytes, b.size));
    }
    m->pattern = CSG_PATTERN_COUNT - 2; /* the last rows are known (the last,
                                           pigment_pattern: below) */
    assert_true(csg_blob_valid(b.bytes, b.size));
    m->pattern = CSG_PATTERN_BOZO;
    const int bad_waves[] = {-1, CSG_WAVE_COUNT, 1000};
    for (size_t i = 0; i < sizeof bad_waves / sizeof bad_waves[0]; i++) {
        m->wave = bad_waves[i];
        assert_false(csg_blob_valid(b.bytes, b.size));
    }
    m->wave = CSG_WAVE_COUNT - 1;
    assert_true(csg_blob_valid(b.bytes, b.size));
    m->pattern_pigment = 1; /* only a pigment_pattern has a pigment */
    assert_false(csg_blob_valid(b.bytes, b.size));
    csg_blob_free(&b);
    csg_scene_free(&s);
    /* an interior_texture: the primitive's own material, whose inside is
       the (interior texture, interior) one, which has none */
    parse_ok(CAMERA "sphere { 0, 1 pigment { rgb 1 } interior_texture { pigment { rgb 0 } } }\n"
                    "sphere { x, 1 pigment { rgb 1 } }\n",
             &s);
    assert_true(engine_float.flatten(&s, &o, &b, &d));
    csg_material *mats = blob_materials(&b);
    const csg_prim *prims =
        (const csg_prim *)(void *)((char *)b.bytes + csg_blob_hdr(b.bytes)->off_prims);
    m = &mats[prims[0].material];
    assert_true(m->inside > 0);
    assert_int_equal(mats[m->inside - 1].inside, 0);
    assert_true(prims[1].material != prims[0].material); /* (the same texture, no inside) */
    assert_int_equal(mats[prims[1].material].inside, 0);
    assert_true(csg_blob_valid(b.bytes, b.size));
    int inside = m->inside;
    m->inside = prims[0].material + 1; /* a chain (itself) */
    assert_false(csg_blob_valid(b.bytes, b.size));
    m->inside = csg_blob_hdr(b.bytes)->material_count + 1;
    assert_false(csg_blob_valid(b.bytes, b.size));
    m->inside = inside;
    csg_blob_free(&b);
    csg_scene_free(&s);
    /* a pigment_pattern's pigment: a later material, inside the table */
    parse_pigment("pigment_pattern { bozo }", &s);
    assert_true(engine_float.flatten(&s, &o, &b, &d));
    m = &blob_materials(&b)[0];
    assert_int_equal(m->pattern, CSG_PATTERN_PIGMENT_PATTERN);
    assert_int_equal(blob_materials(&b)[m->pattern_pigment].pattern, CSG_PATTERN_BOZO);
    assert_true(csg_blob_valid(b.bytes, b.size));
    const int bad_pigments[] = {0, -1, csg_blob_hdr(b.bytes)->material_count};
    for (size_t i = 0; i < sizeof bad_pigments / sizeof bad_pigments[0]; i++) {
        int keep = m->pattern_pigment;
        m->pattern_pigment = bad_pigments[i];
        assert_false(csg_blob_valid(b.bytes, b.size));
        m->pattern_pigment = keep;
    }
    csg_blob_free(&b);
    csg_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_samples_cover), cmocka_unit_test(test_names),
        cmocka_unit_test(test_parse_each),    cmocka_unit_test(test_pipeline_each),
        cmocka_unit_test(test_export_each),   cmocka_unit_test(test_pattern_names),
        cmocka_unit_test(test_pattern_keywords), cmocka_unit_test(test_pattern_pipeline),
        cmocka_unit_test(test_blob_refuses_unknown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
