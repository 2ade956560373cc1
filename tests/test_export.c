/*
 * test_export.c — csg_export_pov on a scene tree built by hand: the CSG
 * structure, transforms as POV-Ray matrices (transposed, leaves only),
 * texture inheritance, open / inverse / no_shadow, the camera, and the
 * flat version used by the POV-Ray cross-check; and that whatever the
 * parser accepts exports to SDL it accepts again, the same scene (#39).
 */
#include <glob.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../csg/camera_setup.h"
#include "../csg/export_pov.h"
#include "../csg/load.h"
#include "../csg/scene.h"

/* ---- a small scene ------------------------------------------------------------- */

static csg_object *new_object(csg_scene *s, enum csg_object_kind kind, int line)
{
    csg_object *o = csg_arena_alloc(s->arena, sizeof *o);
    assert_non_null(o);
    o->kind = kind;
    o->loc = (csg_loc){"t.pov", line, 1};
    csg_xform_identity(&o->xform);
    o->texture = -1;
    o->interior = -1;
    return o;
}

static void add_children(csg_scene *s, csg_object *parent, csg_object **kids, int n)
{
    parent->children = csg_arena_alloc(s->arena, (size_t)n * sizeof *parent->children);
    assert_non_null(parent->children);
    for (int i = 0; i < n; i++)
        parent->children[i] = kids[i];
    parent->child_count = n;
}

/*
 * union {                        texture 0 (red, phong 0.5), translate <1, 2, 3>
 *     sphere { <0, 0, 0>, 1.5 }  no texture: inherits red
 *     cone { ... open inverse }  texture 1 (green, filter 0.25), rotate 90 about z
 * }
 * plane { y, -1 no_shadow }      no texture anywhere: POV-Ray's default
 */
static void build_scene(csg_scene *s)
{
    csg_scene_init(s);
    s->arena = csg_arena_new();
    assert_non_null(s->arena);
    s->path = "t.pov";

    s->texture_count = 2;
    s->textures = csg_arena_alloc(s->arena, 2 * sizeof *s->textures);
    csg_texture_default(&s->textures[0]);
    s->textures[0].pigment.rgbft[0] = 1;
    s->textures[0].finish.phong = 0.5;
    csg_texture_default(&s->textures[1]);
    s->textures[1].pigment.rgbft[1] = 1;
    s->textures[1].pigment.rgbft[3] = 0.25;
    s->interior_count = 1;
    s->interiors = csg_arena_alloc(s->arena, sizeof *s->interiors);
    s->interiors[0].ior = 1.5;

    s->has_camera = true;
    csg_camera_default(&s->camera);
    s->camera.location = (dvec3){0, 0, -5};
    s->light_count = 1;
    s->lights = csg_arena_alloc(s->arena, sizeof *s->lights);
    s->lights[0].position = (dvec3){10, 20, -30};
    s->lights[0].color[0] = s->lights[0].color[1] = s->lights[0].color[2] = 1;
    s->lights[0].shadowless = true;
    s->background[2] = 0.5;

    csg_xform t;
    csg_xform_identity(&t);
    csg_xform_translate(&t, (dvec3){1, 2, 3});

    csg_object *u = new_object(s, CSG_OBJ_UNION, 1);
    u->texture = 0;
    u->interior = 0;
    u->xform = t;
    csg_object *sph = new_object(s, CSG_OBJ_SPHERE, 2);
    sph->r0 = 1.5;
    sph->xform = t; /* complete transform: the union's */
    csg_object *cone = new_object(s, CSG_OBJ_CONE, 3);
    cone->a = (dvec3){0, 0, 0};
    cone->r0 = 1;
    cone->b = (dvec3){0, 2, 0};
    cone->r1 = 0.25;
    cone->open = true;
    cone->inverse = true;
    cone->texture = 1;
    csg_xform_identity(&cone->xform);
    csg_xform_rotate(&cone->xform, (dvec3){0, 0, 90});
    csg_xform_then(&cone->xform, &t, &cone->xform);
    csg_object *kids[2] = {sph, cone};
    add_children(s, u, kids, 2);

    csg_object *pl = new_object(s, CSG_OBJ_PLANE, 5);
    pl->a = (dvec3){0, 1, 0};
    pl->r0 = -1;
    pl->no_shadow = true;

    s->object_count = 2;
    s->objects = csg_arena_alloc(s->arena, 2 * sizeof *s->objects);
    s->objects[0] = u;
    s->objects[1] = pl;
}

/* The export as one malloc'd string; NULL when csg_export_pov failed. */
static char *export_text(const csg_scene *s, bool flat, csg_diag *d)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    assert_non_null(f);
    bool ok = csg_export_pov(s, f, flat, d);
    fclose(f);
    if (!ok) {
        free(buf);
        return NULL;
    }
    return buf;
}

static void assert_contains(const char *text, const char *needle)
{
    if (!strstr(text, needle))
        fail_msg("expected \"%s\" in:\n%s", needle, text);
}

static void assert_lacks(const char *text, const char *needle)
{
    if (strstr(text, needle))
        fail_msg("did not expect \"%s\" in:\n%s", needle, text);
}

static int count(const char *text, const char *needle)
{
    int n = 0;
    for (const char *p = strstr(text, needle); p; p = strstr(p + 1, needle))
        n++;
    return n;
}

/* ---- tests ------------------------------------------------------------------------ */

static void test_structure(void **state)
{
    (void)state;
    csg_scene s;
    build_scene(&s);
    csg_diag d = {0};
    char *t = export_text(&s, false, &d);
    assert_non_null(t);
    assert_contains(t, "#version 3.7;");
    assert_contains(t, "union {\n    sphere { <0, 0, 0>, 1.5\n");
    assert_contains(t, "    cone { <0, 0, 0>, 1, <0, 2, 0>, 0.25 open\n");
    assert_contains(t, "plane { <0, 1, 0>, -1\n");
    /* the union carries no matrix; its children carry the complete one */
    assert_int_equal(count(t, "matrix"), 3);
    assert_contains(t, "matrix <1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 2, 3>");
    /* rotate 90 about z sends x to y: POV-Ray's first row is the image of x */
    assert_contains(t, "matrix <0, 1, 0, -1, 0, 0, 0, 0, 1, 1, 2, 3>");
    assert_contains(t, "        inverse\n");
    assert_contains(t, "    no_shadow\n");
    assert_int_equal(count(t, "inverse"), 1);
    assert_contains(t, "interior { ior 1.5 }");
    free(t);
    csg_scene_free(&s);
}

static void test_textures_resolved(void **state)
{
    (void)state;
    csg_scene s;
    build_scene(&s);
    csg_diag d = {0};
    char *t = export_text(&s, false, &d);
    assert_non_null(t);
    /* the sphere inherits the union's red; the cone keeps its green */
    const char *sph = strstr(t, "sphere {");
    const char *cone = strstr(t, "cone {");
    const char *pl = strstr(t, "plane {");
    assert_non_null(sph);
    assert_non_null(cone);
    assert_non_null(pl);
    const char *red = strstr(sph, "pigment { color rgbft <1, 0, 0, 0, 0> }");
    assert_non_null(red);
    assert_true(red < cone);
    assert_contains(t, "finish { ambient rgb <0.1, 0.1, 0.1> diffuse 0.6 brilliance 1 specular 0 "
                       "roughness 0.05 phong 0.5 phong_size 40 metallic 0 reflection rgb <0, 0, 0> }");
    const char *green = strstr(cone, "pigment { color rgbft <0, 1, 0, 0.25, 0> }");
    assert_non_null(green);
    assert_true(green < pl);
    /* the plane has no texture anywhere: POV-Ray's default, written out */
    assert_contains(pl, "pigment { color rgbft <0, 0, 0, 0, 0> }");
    assert_contains(pl, "phong 0 phong_size 40");
    assert_int_equal(count(t, "texture {"), 3);
    free(t);
    csg_scene_free(&s);
}

static void test_camera_lights_globals(void **state)
{
    (void)state;
    csg_scene s;
    build_scene(&s);
    s.globals.max_trace_level = 7;
    csg_diag d = {0};
    char *t = export_text(&s, false, &d);
    assert_non_null(t);
    assert_contains(t, "camera {\n    perspective\n    location <0, 0, -5>\n"
                       "    direction <0, 0, 1>\n    right <1.33, 0, 0>\n    up <0, 1, 0>\n}");
    assert_lacks(t, "look_at");
    assert_contains(t, "light_source { <10, 20, -30> color rgb <1, 1, 1> shadowless }");
    assert_contains(t, "background { color rgbft <0, 0, 0.5, 0, 0> }");
    assert_contains(t, "assumed_gamma 1\n");
    assert_contains(t, "max_trace_level 7\n");
    free(t);
    csg_scene_free(&s);
}

static void test_flat(void **state)
{
    (void)state;
    csg_scene s;
    build_scene(&s);
    s.globals.ambient_light[0] = 0.3;
    csg_diag d = {0};
    char *t = export_text(&s, true, &d);
    assert_non_null(t);
    assert_int_equal(count(t, "finish { ambient 1 diffuse 0 }"), 3);
    assert_contains(t, "pigment { color rgb <1, 0, 0> }");
    assert_contains(t, "pigment { color rgb <0, 1, 0> }"); /* filter dropped */
    assert_lacks(t, "rgbft");
    assert_lacks(t, "phong");
    assert_lacks(t, "reflection");
    assert_lacks(t, "interior");
    assert_contains(t, "ambient_light rgb <1, 1, 1>");
    assert_contains(t, "max_trace_level 1\n");
    assert_contains(t, "background { color rgb <0, 0, 0.5> }");
    /* geometry unchanged */
    assert_int_equal(count(t, "matrix"), 3);
    assert_contains(t, "inverse");
    assert_contains(t, " open");
    free(t);
    csg_scene_free(&s);
}

static void test_numbers_round_trip(void **state)
{
    (void)state;
    csg_scene s;
    build_scene(&s);
    s.objects[0]->children[0]->r0 = 0.1 + 0.2; /* not 0.3: needs 17 digits */
    s.objects[1]->r0 = -0.0;
    csg_diag d = {0};
    char *t = export_text(&s, false, &d);
    assert_non_null(t);
    assert_contains(t, "sphere { <0, 0, 0>, 0.30000000000000004\n");
    assert_contains(t, "plane { <0, 1, 0>, 0\n");
    free(t);
    csg_scene_free(&s);
}

static void test_bad_texture_index(void **state)
{
    (void)state;
    csg_scene s;
    build_scene(&s);
    s.objects[0]->children[1]->texture = 9;
    csg_diag d = {0};
    char *t = export_text(&s, false, &d);
    assert_null(t);
    assert_true(d.failed);
    assert_non_null(strstr(d.message, "t.pov:3:1: error: "));
    assert_non_null(strstr(d.message, "texture index 9"));
    csg_scene_free(&s);
}

/* ---- export always re-parses (#39) ------------------------------------------------ */

/* The export of a parsed scene parses again, and the scene it reads
 * exports to the same text (but the first line, which names the file):
 * nothing was lost or changed. */
static void assert_reparses(const char *name, csg_scene *s)
{
    csg_diag d = {0};
    char *first = export_text(s, false, &d);
    csg_scene_free(s);
    if (!first)
        fail_msg("%s: export: %s", name, d.message);
    csg_scene again;
    memset(&d, 0, sizeof d);
    if (!csg_load_string("exported.pov", first, strlen(first), NULL, &again, &d))
        fail_msg("%s: the export does not parse: %s", name, d.message);
    char *second = export_text(&again, false, &d);
    csg_scene_free(&again);
    if (!second)
        fail_msg("%s: second export: %s", name, d.message);
    const char *a = strchr(first, '\n'), *b = strchr(second, '\n');
    if (!a || !b || strcmp(a, b) != 0)
        fail_msg("%s: the re-parsed scene exports otherwise", name);
    free(first);
    free(second);
}

static void reparse_text(const char *name, const char *text)
{
    csg_scene s;
    csg_diag d = {0};
    if (!csg_load_string("t.pov", text, strlen(text), NULL, &s, &d))
        fail_msg("%s: %s", name, d.message);
    assert_reparses(name, &s);
}

/* CSG as deep as the parser takes it, with the leaves' textures inherited
 * or default (the export writes them on the leaves: more braces), and
 * with a declared texture at the top. */
static void test_reparse_deep(void **state)
{
    (void)state;
    static const char *const heads[] = {"", "union { ", "merge { "};
    static const char *const tails[] = {"", "pigment { rgb 1 } }", "texture { T } }"};
    for (int k = 0; k < 3; k++) {
        size_t size = 64 * 1024, used = 0;
        char *text = malloc(size);
        assert_non_null(text);
        int depth = k == 0 ? 127 : 126;
        used += (size_t)snprintf(text, size,
                                 "#declare T = texture { pigment { checker rgb 1 rgb 0 } }\n%s",
                                 heads[k]);
        for (int i = 0; i < depth; i++)
            used += (size_t)snprintf(text + used, size - used, "difference { ");
        used += (size_t)snprintf(text + used, size - used, "sphere { 0, 1 } ");
        for (int i = 0; i < depth; i++)
            used += (size_t)snprintf(text + used, size - used, "sphere { 0, 0.5 } } ");
        snprintf(text + used, size - used, "%s\n", tails[k]);
        reparse_text(heads[k][0] ? heads[k] : "127 nested differences", text);
        free(text);
    }
}

/* Transforms whose matrix the parser would call singular (the
 * determinant underflows) though each step was accepted. */
static void test_reparse_tiny_scales(void **state)
{
    (void)state;
    static const char *const scenes[] = {
        "sphere { 0, 1 pigment { checker scale 1e-300 } }",
        "sphere { 0, 1 pigment { bozo scale <1e-300, 1, 1> rotate <10, 20, 30> } }",
        "sphere { 0, 1 pigment { agate scale 1e-200 translate 3 } }",
        "sphere { 0, 1 pigment { checker scale 4.9e-324 } }",
        "sphere { 0, 1 normal { bumps 0.5 scale 1e-300 } }",
    };
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++)
        reparse_text(scenes[i], scenes[i]);
}

/* An object's transform that overflows or collapses an axis: the parser
 * takes each step (the render's flattener refuses the object), but no SDL
 * states the result; the export says so and fails instead of writing what
 * it cannot read back. (A pattern's is refused by the parser: test_language.) */
static void test_unexportable_transforms(void **state)
{
    (void)state;
    static const char *const scenes[] = {
        "sphere { 0, 1 scale 1e300 scale 1e300 }",
        "sphere { 0, 1 scale <1e-200, 1, 1> scale <1e-200, 1, 1> }",
        "union { sphere { 0, 1 } translate 1e308 translate 1e308 }",
    };
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        csg_scene s;
        csg_diag d = {0};
        if (!csg_load_string("t.pov", scenes[i], strlen(scenes[i]), NULL, &s, &d))
            fail_msg("%s: %s", scenes[i], d.message); /* (the parser takes each step) */
        char *text = export_text(&s, false, &d);
        csg_scene_free(&s);
        if (text)
            fail_msg("%s: exported:\n%s", scenes[i], text);
        assert_non_null(strstr(d.message, "overflows or collapses an axis"));
    }
}

/* Every example scene and every scene of the suites. */
static void test_reparse_examples(void **state)
{
    (void)state;
    static const char *const patterns[] = {"scenes/*.pov", "tests/povray/*.pov",
                                           "tests/nff/*.nff"};
    size_t seen = 0;
    for (size_t p = 0; p < sizeof patterns / sizeof patterns[0]; p++) {
        glob_t g;
        if (glob(patterns[p], 0, NULL, &g) != 0)
            continue;
        for (size_t i = 0; i < g.gl_pathc; i++, seen++) {
            csg_scene s;
            csg_diag d = {0};
            if (!csg_load_file(g.gl_pathv[i], NULL, &s, &d))
                fail_msg("%s: %s", g.gl_pathv[i], d.message);
            assert_reparses(g.gl_pathv[i], &s);
        }
        globfree(&g);
    }
    assert_true(seen >= 9); /* (run from the checkout's root) */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_structure),
        cmocka_unit_test(test_textures_resolved),
        cmocka_unit_test(test_camera_lights_globals),
        cmocka_unit_test(test_flat),
        cmocka_unit_test(test_numbers_round_trip),
        cmocka_unit_test(test_bad_texture_index),
        cmocka_unit_test(test_reparse_deep),
        cmocka_unit_test(test_reparse_tiny_scales),
        cmocka_unit_test(test_reparse_examples),
        cmocka_unit_test(test_unexportable_transforms),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
