/*
 * test_parser.c — the scene language: every valid construct checked in the
 * resulting tree (transforms composed, POV-Ray's rotate sense, promotion,
 * declared copies, texture inheritance, colors.inc), every error path with
 * its exact message and position, #include through temporary files, the
 * nesting limits and the summary.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../csg/lang/lexer.h"
#include "../csg/lang/parser.h"
#include "summary_text.h"

/* ---- helpers ------------------------------------------------------------- */

static void parse_ok(const char *text, csg_scene *s)
{
    csg_diag d;
    memset(&d, 0, sizeof d);
    bool ok = csg_parse_string("t.pov", text, strlen(text), s, &d);
    if (!ok)
        fail_msg("unexpected parse error: %s\n--- input:\n%s", d.message, text);
}

static void parse_err(const char *text, const char *message)
{
    csg_scene s;
    csg_diag d;
    memset(&d, 0, sizeof d);
    bool ok = csg_parse_string("t.pov", text, strlen(text), &s, &d);
    if (ok) {
        csg_scene_free(&s);
        fail_msg("parse succeeded, expected: %s\n--- input:\n%s", message, text);
    }
    assert_string_equal(d.message, message);
    assert_null(s.arena);
    assert_int_equal(s.object_count, 0);
}

#define EPS 1e-12
static void assert_near(double a, double b)
{
    if (!(fabs(a - b) <= EPS * (1 + fabs(b))))
        fail_msg("%.17g != %.17g", a, b);
}

/* p' = xform(p) */
static dvec3 apply(const csg_xform *x, dvec3 p)
{
    return (dvec3){x->m[0][0] * p.x + x->m[0][1] * p.y + x->m[0][2] * p.z + x->m[0][3],
                   x->m[1][0] * p.x + x->m[1][1] * p.y + x->m[1][2] * p.z + x->m[1][3],
                   x->m[2][0] * p.x + x->m[2][1] * p.y + x->m[2][2] * p.z + x->m[2][3]};
}

static void assert_vec(dvec3 v, double x, double y, double z)
{
    assert_near(v.x, x);
    assert_near(v.y, y);
    assert_near(v.z, z);
}

static const csg_texture *tex_of(const csg_scene *s, const csg_object *o)
{
    assert_true(o->texture >= 0 && o->texture < s->texture_count);
    return &s->textures[o->texture];
}

/* ---- primitives ------------------------------------------------------------- */

/* A vector may end in one comma after its 2nd to 4th component, as POV-Ray
 * takes it (its float4.pov sample writes <0.2,0.1,0.5,>). */
static void test_vector_trailing_comma(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("sphere { <1, 2, 3,>, 0.5 }\n"
             "sphere { <4, 5,>, 1 }\n", &s);
    assert_int_equal(s.object_count, 2);
    assert_vec(s.objects[0]->a, 1, 2, 3);
    assert_vec(s.objects[1]->a, 4, 5, 0);
    csg_scene_free(&s);
}

static void test_primitives(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("sphere { <1, 2, 3>, 0.5 }\n"
             "box { <1, -1, 2>, <-1, 1, 0> }\n"
             "cylinder { 0, 2*y, .25 open }\n"
             "cone { <0,0,0>, 1, <0,3,0>, 0 }\n"
             "plane { <0, 2, 0>, 1 }\n"
             "sphere { 0 1 }\n", &s);
    assert_int_equal(s.object_count, 6);
    csg_object **o = s.objects;
    assert_int_equal(o[0]->kind, CSG_OBJ_SPHERE);
    assert_vec(o[0]->a, 1, 2, 3);
    assert_near(o[0]->r0, 0.5);
    assert_int_equal(o[0]->loc.line, 1);
    assert_int_equal(o[0]->loc.col, 1);
    assert_string_equal(o[0]->loc.file, "t.pov");
    assert_int_equal(o[1]->kind, CSG_OBJ_BOX); /* corners ordered min / max */
    assert_vec(o[1]->a, -1, -1, 0);
    assert_vec(o[1]->b, 1, 1, 2);
    assert_int_equal(o[2]->kind, CSG_OBJ_CYLINDER);
    assert_vec(o[2]->b, 0, 2, 0);
    assert_near(o[2]->r0, 0.25);
    assert_true(o[2]->open);
    assert_int_equal(o[3]->kind, CSG_OBJ_CONE);
    assert_near(o[3]->r0, 1);
    assert_near(o[3]->r1, 0);
    assert_false(o[3]->open);
    assert_int_equal(o[4]->kind, CSG_OBJ_PLANE); /* unit normal, distance kept */
    assert_vec(o[4]->a, 0, 1, 0);
    assert_near(o[4]->r0, 1);
    assert_near(o[5]->r0, 1); /* commas are optional, as in POV-Ray */
    for (int i = 0; i < 6; i++) {
        assert_int_equal(o[i]->child_count, 0);
        assert_true(o[i]->texture >= 0); /* top level: a default texture */
        assert_true(o[i]->interior >= 0);
        assert_near(s.interiors[o[i]->interior].ior, 1);
    }
    const csg_texture *t = tex_of(&s, o[0]);
    assert_near(t->pigment.rgbft[0], 0);
    assert_near(t->finish.diffuse, 0.6);
    assert_near(t->finish.ambient[1], 0.1);
    assert_near(t->finish.phong_size, 40);
    csg_scene_free(&s);
}

/* A box whose corners share a coordinate is a sheet, as in POV-Ray: it
 * parses, corners ordered, the shared coordinate kept (flat on one axis,
 * two, or all three). */
static void test_flat_boxes(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("box { 0, <1,0,1> }\n"
             "box { <2, 1, -1>, <-2, 1, 3> }\n"
             "box { <0, 5, 0>, <0, -5, 0> }\n"
             "box { 1, 1 }\n", &s);
    assert_int_equal(s.object_count, 4);
    csg_object **o = s.objects;
    for (int i = 0; i < 4; i++)
        assert_int_equal(o[i]->kind, CSG_OBJ_BOX);
    assert_vec(o[0]->a, 0, 0, 0);
    assert_vec(o[0]->b, 1, 0, 1);
    assert_vec(o[1]->a, -2, 1, -1);
    assert_vec(o[1]->b, 2, 1, 3);
    assert_vec(o[2]->a, 0, -5, 0);
    assert_vec(o[2]->b, 0, 5, 0);
    assert_vec(o[3]->a, 1, 1, 1);
    assert_vec(o[3]->b, 1, 1, 1);
    csg_scene_free(&s);
}

/* ---- expressions and promotion ------------------------------------------------ */

static void test_expressions(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare A = 2*(3+4)/7 - -1;\n"     /* 3 */
             "#declare B = 1e-3 + .5 + 2.;\n"     /* 2.501 */
             "#declare V = -<1, 2, 3> * 2 + x;\n" /* <-1, -4, -6> */
             "#declare W = (y + z) / 4;\n"        /* <0, .25, .25> */
             "#declare P = pi;\n"
             "#declare T = true + off;\n"
             "sphere { V, A }\n"
             "sphere { W, B }\n"
             "sphere { 2 * x * 3, P / T }\n"
             "sphere { <1, 2, 3> + 1, 1 }\n", &s);
    assert_vec(s.objects[0]->a, -1, -4, -6);
    assert_near(s.objects[0]->r0, 3);
    assert_vec(s.objects[1]->a, 0, 0.25, 0.25);
    assert_near(s.objects[1]->r0, 2.501);
    assert_vec(s.objects[2]->a, 6, 0, 0);
    assert_near(s.objects[2]->r0, M_PI);
    assert_vec(s.objects[3]->a, 2, 3, 4);
    csg_scene_free(&s);
}

static void test_promotion(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("camera { location <0, 0, -5> look_at 0 }\n"
             "sphere { 1, 1 scale 2 translate 1 }\n"
             "sphere { 0, 1 pigment { color rgb 0.5 } }\n"
             "sphere { 0, 1 pigment { color 0.5 } }\n"
             "sphere { 0, 1 pigment { rgbf 0.25 } }\n"
             "sphere { 0, 1 pigment { <1, 0, 0> } }\n", &s);
    assert_vec(s.objects[0]->a, 1, 1, 1); /* float promoted to <1,1,1> */
    assert_vec(apply(&s.objects[0]->xform, (dvec3){1, 1, 1}), 3, 3, 3);
    const double *c = tex_of(&s, s.objects[1])->pigment.rgbft;
    assert_near(c[0], 0.5);
    assert_near(c[2], 0.5);
    assert_near(c[3], 0);
    assert_near(c[4], 0);
    c = tex_of(&s, s.objects[2])->pigment.rgbft; /* POV-Ray: all five components */
    for (int i = 0; i < 5; i++)
        assert_near(c[i], 0.5);
    c = tex_of(&s, s.objects[3])->pigment.rgbft;
    for (int i = 0; i < 4; i++)
        assert_near(c[i], 0.25);
    assert_near(c[4], 0);
    c = tex_of(&s, s.objects[4])->pigment.rgbft;
    assert_near(c[0], 1);
    assert_near(c[1], 0);
    assert_near(c[3], 0);
    assert_vec(s.camera.direction, 0, 0, 1);
    csg_scene_free(&s);
}

/* ---- colours --------------------------------------------------------------------- */

static void test_colors(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#include \"colors.inc\"\n"
             "#declare C = colour red 0.2 green 0.4 blue 0.6 filter 0.1 transmit 0.3;\n"
             "#declare D = rgbt <0.1, 0.2, 0.3, 0.4>;\n"
             "#declare E = rgbft <1, 2, 3, 4, 5> * 0.5;\n"
             "#declare G = Red * 0.5 + Blue;\n"
             "sphere { 0, 1 pigment { Gray50 } }\n"
             "sphere { 0, 1 pigment { color Clear } }\n"
             "sphere { 0, 1 pigment { SlateBlue } }\n"
             "sphere { 0, 1 pigment { C } }\n"
             "sphere { 0, 1 pigment { D } }\n"
             "sphere { 0, 1 pigment { E } }\n"
             "sphere { 0, 1 pigment { G } }\n"
             "sphere { 0, 1 pigment { color White green 0 filter 0.5 } }\n"
             "sphere { 0, 1 pigment { NeonPink } }\n", &s);
    const double expect[][5] = {
        {0.5, 0.5, 0.5, 0, 0},  {1, 1, 1, 1, 0},         {0, 0.498039, 1.0, 0, 0},
        {0.2, 0.4, 0.6, 0.1, 0.3}, {0.1, 0.2, 0.3, 0, 0.4}, {0.5, 1, 1.5, 2, 2.5},
        {0.5, 0, 1, 0, 0},      {1, 0, 1, 0.5, 0},       {1.00, 0.43, 0.78, 0, 0}};
    assert_int_equal(s.object_count, 9);
    for (int i = 0; i < 9; i++)
        for (int k = 0; k < 5; k++)
            assert_near(tex_of(&s, s.objects[i])->pigment.rgbft[k], expect[i][k]);
    csg_scene_free(&s);

    /* every built-in name comes back with its value */
    assert_true(csg_builtin_color_count() > 100);
    double c[5];
    const char *prev = "";
    for (int i = 0; i < csg_builtin_color_count(); i++) {
        const char *name = csg_builtin_color_at(i, c);
        assert_non_null(name);
        assert_true(strcmp(prev, name) < 0);
        prev = name;
    }
    assert_null(csg_builtin_color_at(csg_builtin_color_count(), c));
}

/* ---- transforms -------------------------------------------------------------------- */

static void test_transform_order(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("sphere { 0, 1 translate x scale 2 }\n"
             "sphere { 0, 1 scale 2 translate x }\n"
             "sphere { 0, 1 rotate 90*y }\n"
             "sphere { 0, 1 rotate <0, 0, 90> }\n"
             "sphere { 0, 1 rotate <90, 0, 0> }\n"
             "sphere { 0, 1 rotate <90, 90, 0> }\n"
             "sphere { 0, 1 scale <1, 2, -3> }\n"
             "sphere { 0, 1 translate x matrix <0,1,0, -1,0,0, 0,0,1, 5,6,7> }\n", &s);
    csg_object **o = s.objects;
    assert_vec(apply(&o[0]->xform, (dvec3){0, 0, 0}), 2, 0, 0);
    assert_vec(apply(&o[1]->xform, (dvec3){0, 0, 0}), 1, 0, 0);
    /* POV-Ray's left-handed sense: rotate y*90 takes +x to -z, z*90 takes
     * +x to +y, x*90 takes +y to +z; x first, then y. */
    assert_vec(apply(&o[2]->xform, (dvec3){1, 0, 0}), 0, 0, -1);
    assert_vec(apply(&o[3]->xform, (dvec3){1, 0, 0}), 0, 1, 0);
    assert_vec(apply(&o[4]->xform, (dvec3){0, 1, 0}), 0, 0, 1);
    assert_vec(apply(&o[5]->xform, (dvec3){0, 1, 0}), 1, 0, 0);
    assert_vec(apply(&o[6]->xform, (dvec3){1, 1, 1}), 1, 2, -3);
    /* matrix, POV-Ray's rows: p' = p M, after the translate: (1,0,0) is
     * translated to (2,0,0), then x' = -y + 5, y' = x + 6, z' = z + 7 */
    assert_vec(apply(&o[7]->xform, (dvec3){0, 0, 0}), 5, 7, 7);
    assert_vec(apply(&o[7]->xform, (dvec3){0, 1, 0}), 4, 7, 7);
    csg_scene_free(&s);
}

static void test_csg_world_transforms(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("union {\n"
             "  sphere { 0, 1 translate x }\n"
             "  difference { box { -1, 1 } sphere { 0, 1 scale 0.5 } translate y }\n"
             "  scale 2\n"
             "  translate z\n"
             "}\n", &s);
    assert_int_equal(s.object_count, 1);
    const csg_object *u = s.objects[0];
    assert_int_equal(u->kind, CSG_OBJ_UNION);
    assert_int_equal(u->child_count, 2);
    assert_vec(apply(&u->xform, (dvec3){0, 0, 0}), 0, 0, 1);
    /* the child's xform is its full object -> world transform */
    assert_vec(apply(&u->children[0]->xform, (dvec3){0, 0, 0}), 2, 0, 1);
    const csg_object *d = u->children[1];
    assert_int_equal(d->kind, CSG_OBJ_DIFFERENCE);
    assert_vec(apply(&d->xform, (dvec3){0, 0, 0}), 0, 2, 1);
    assert_vec(apply(&d->children[0]->xform, (dvec3){1, 1, 1}), 2, 4, 3);
    assert_vec(apply(&d->children[1]->xform, (dvec3){1, 0, 0}), 1, 2, 1);
    csg_scene_free(&s);
}

/* ---- declared objects, textures, interiors ----------------------------------------- */

static void test_declared_copies(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare A = union { sphere { 0, 1 } box { 0, 1 pigment { rgb x } } translate y }\n"
             "object { A translate x pigment { rgb z } }\n"
             "object { A }\n"
             "#declare B = object { A scale 2 };\n"
             "object { B }\n"
             "#local A = sphere { 0, 3 }\n"
             "object { A }\n"
             "object { sphere { 0, 1 } translate x }\n", &s);
    assert_int_equal(s.object_count, 5);
    csg_object **o = s.objects;
    assert_vec(apply(&o[0]->xform, (dvec3){0, 0, 0}), 1, 1, 0);
    assert_vec(apply(&o[1]->xform, (dvec3){0, 0, 0}), 0, 1, 0); /* declared one untouched */
    assert_vec(apply(&o[2]->xform, (dvec3){0, 0, 0}), 0, 2, 0);
    assert_vec(apply(&o[2]->children[0]->xform, (dvec3){1, 0, 0}), 2, 2, 0);
    assert_int_equal(o[3]->kind, CSG_OBJ_SPHERE); /* redeclared */
    assert_near(o[3]->r0, 3);
    assert_vec(apply(&o[4]->xform, (dvec3){0, 0, 0}), 1, 0, 0);
    /* copies are distinct nodes */
    assert_ptr_not_equal(o[0]->children[0], o[1]->children[0]);
    /* textures: the pigment on the copy did not reach the other copy */
    assert_near(tex_of(&s, o[0])->pigment.rgbft[2], 1);
    assert_near(tex_of(&s, o[1])->pigment.rgbft[2], 0);
    /* the children: sphere inherits (-1), box has its own red */
    assert_int_equal(o[0]->children[0]->texture, -1);
    assert_near(tex_of(&s, o[0]->children[1])->pigment.rgbft[0], 1);
    assert_int_equal(o[0]->children[1]->texture, o[1]->children[1]->texture);
    assert_int_equal(o[0]->children[0]->interior, -1);
    csg_scene_free(&s);
}

static void test_textures(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare F = finish { phong 0.9 phong_size 60 metallic 0.5 }\n"
             "#declare P = pigment { rgb <0, 1, 0> }\n"
             "#declare T = texture { pigment { P } finish { F specular 0.3 } }\n"
             "#declare I = interior { ior 1.33 }\n"
             "sphere { 0, 1 pigment { rgb 1 } finish { ambient 0.2 diffuse 0.7 brilliance 3 specular 0.5\n"
             "  roughness 0.01 reflection 0.25 metallic } }\n"
             "sphere { 0, 1 texture { T } pigment { rgbf <1, 0, 0, 0.5> } }\n"
             "sphere { 0, 1 finish { F ambient rgb <0.1, 0.2, 0.3> reflection { <0.1, 0.2, 0.3> } } }\n"
             "sphere { 0, 1 interior { I } interior { ior 2 } }\n"
             "sphere { 0, 1 pigment { rgb x } texture { pigment { P } } }\n", &s);
    csg_object **o = s.objects;
    const csg_texture *t = tex_of(&s, o[0]);
    assert_near(t->pigment.rgbft[1], 1);
    assert_near(t->finish.ambient[2], 0.2);
    assert_near(t->finish.diffuse, 0.7);
    assert_near(t->finish.brilliance, 3);
    assert_near(t->finish.metallic, 1);
    assert_near(t->finish.specular, 0.5);
    assert_near(t->finish.roughness, 0.01);
    assert_near(t->finish.reflection[0], 0.25);
    t = tex_of(&s, o[1]);
    assert_near(t->pigment.rgbft[0], 1);
    assert_near(t->pigment.rgbft[3], 0.5);
    assert_near(t->finish.phong, 0.9);
    assert_near(t->finish.phong_size, 60);
    assert_near(t->finish.metallic, 0.5);
    assert_near(t->finish.specular, 0.3);
    t = tex_of(&s, o[2]);
    assert_near(t->finish.phong, 0.9);
    assert_near(t->finish.ambient[1], 0.2);
    assert_near(t->finish.reflection[2], 0.3);
    assert_near(t->finish.diffuse, 0.6);
    assert_near(s.interiors[o[3]->interior].ior, 2);
    t = tex_of(&s, o[4]); /* texture {} replaces the whole texture */
    assert_near(t->pigment.rgbft[0], 0);
    assert_near(t->pigment.rgbft[1], 1);
    csg_scene_free(&s);
}

static void test_csg_inheritance(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("merge { sphere { 0, 1 } sphere { x, 1 pigment { rgb 1 } interior { ior 1.5 } }\n"
             "  cylinder { 0, y, 1 } inverse no_shadow pigment { rgb y } }\n"
             "intersection { sphere { 0, 1 inverse } plane { y, 0 } }\n", &s);
    const csg_object *m = s.objects[0];
    assert_int_equal(m->kind, CSG_OBJ_MERGE);
    assert_true(m->inverse);
    assert_true(m->no_shadow);
    assert_int_equal(m->children[0]->texture, -1);
    assert_int_equal(m->children[2]->texture, -1);
    assert_near(tex_of(&s, m->children[1])->pigment.rgbft[0], 1);
    assert_near(s.interiors[m->children[1]->interior].ior, 1.5);
    assert_int_equal(m->children[0]->interior, -1);
    assert_near(tex_of(&s, m)->pigment.rgbft[1], 1);
    const csg_object *i = s.objects[1];
    assert_true(i->children[0]->inverse);
    assert_false(i->inverse);
    assert_true(i->texture >= 0); /* top level: default texture */
    assert_near(tex_of(&s, i)->pigment.rgbft[0], 0);
    csg_scene_free(&s);
}

/* Siblings written with the same texture share one entry (issue #39: a box
 * minus 10^5 such spheres kept 10^5 entries); a copy's modifier and a
 * transform still never reach the shared entry. */
static void test_equal_textures_shared(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare U = union { sphere { 0, 1 pigment { rgb x } } sphere { x, 1 pigment { rgb x } }\n"
             "  sphere { y, 1 pigment { rgb z } } }\n"
             "object { U pigment { rgb y } }\n"
             "object { U }\n"
             "union { sphere { 0, 1 pigment { checker rgb x rgb z } }\n"
             "  sphere { x, 1 pigment { checker rgb x rgb z } } translate 2*x }\n"
             "sphere { 0, 1 pigment { rgb x } }\n"
             "sphere { x, 1 pigment { rgb x } }\n", &s);
    assert_int_equal(s.object_count, 5);
    csg_object **o = s.objects;
    const csg_object *const *u = (const csg_object *const *)o[1]->children;
    assert_int_equal(u[0]->texture, u[1]->texture);
    assert_int_not_equal(u[1]->texture, u[2]->texture);
    assert_near(tex_of(&s, u[1])->pigment.rgbft[0], 1);
    assert_near(tex_of(&s, u[2])->pigment.rgbft[2], 1);
    /* the pigment on the other copy went to that copy's union alone */
    assert_near(tex_of(&s, o[0])->pigment.rgbft[1], 1);
    assert_int_equal(o[0]->children[1]->texture, u[1]->texture);
    assert_near(tex_of(&s, u[0])->pigment.rgbft[1], 0);
    /* the translate gave each patterned child a moved copy of its own */
    const csg_object *const *c = (const csg_object *const *)o[2]->children;
    assert_int_not_equal(c[0]->texture, c[1]->texture);
    /* top-level objects too */
    assert_int_equal(o[3]->texture, o[4]->texture);
    assert_int_not_equal(o[3]->texture, u[0]->texture); /* (not adjacent: not shared) */
    csg_scene_free(&s);
}

/* ---- statements ------------------------------------------------------------------ */

static void test_statements(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#version 3.7;\n"
             "global_settings { assumed_gamma 2.2 max_trace_level 7 adc_bailout 0.01\n"
             "  ambient_light rgb <0.5, 0.6, 0.7> }\n"
             "background { color rgbt <0.1, 0.2, 0.3, 0.4> }\n"
             "light_source { <1, 2, 3>, color rgb <1, 0.5, 0.25> }\n"
             "light_source {<1,2,3> rgb 1 shadowless translate x}\n"
             "camera { perspective location <0, 0, -10> right x up y direction 2*z sky y\n"
             "  look_at <0, 0, 0> angle 90 }\n", &s);
    assert_near(s.globals.assumed_gamma, 2.2);
    assert_int_equal(s.globals.max_trace_level, 7);
    assert_near(s.globals.adc_bailout, 0.01);
    assert_near(s.globals.ambient_light[2], 0.7);
    assert_near(s.background[2], 0.3);
    assert_near(s.background[4], 0.4);
    assert_int_equal(s.light_count, 2);
    assert_vec(s.lights[0].position, 1, 2, 3);
    assert_near(s.lights[0].color[1], 0.5);
    assert_false(s.lights[0].shadowless);
    assert_vec(s.lights[1].position, 2, 2, 3);
    assert_true(s.lights[1].shadowless);
    assert_int_equal(s.lights[1].loc.line, 6);
    assert_true(s.has_camera);
    assert_vec(s.camera.location, 0, 0, -10);
    assert_vec(s.camera.direction, 0, 0, 0.5); /* angle 90: |right| / 2 / tan 45 */
    assert_vec(s.camera.right, 1, 0, 0);
    assert_vec(s.camera.up, 0, 1, 0);
    assert_int_equal(s.object_count, 0);
    csg_scene_free(&s);

    parse_ok("// nothing but a comment /* and */\n/* a /* nested */ comment */", &s);
    assert_false(s.has_camera);
    assert_vec(s.camera.right, 1.33, 0, 0);
    assert_int_equal(s.globals.max_trace_level, 5);
    assert_int_equal(s.light_count, 0);
    csg_scene_free(&s);
}

/* ---- errors ------------------------------------------------------------------------ */

typedef struct {
    const char *text, *message;
} err_case;

static void test_errors(void **state)
{
    (void)state;
    static const err_case cases[] = {
        {"quartic { <1, 2, 3> }", "t.pov:1:19: error: a poly of order 4 has 35 coefficients, got 3"},
        {"cubic { 1, 2 }", "t.pov:1:9: error: '<' expected (the 20 coefficients of a poly of order 3)"},
        {"poly { 8, <1> }", "t.pov:1:8: error: the order of a poly must be 2 to 7, got 8"},
        {"poly { 1, <1> }", "t.pov:1:8: error: the order of a poly must be 2 to 7, got 1"},
        {"poly { 2, <1, 0, 0, 0, 1, 0, 0, 1, 0, -1, 5> }",
         "t.pov:1:41: error: '>' expected (to close '<' at 1:11), got ','"},
        {"torus { 1 }", "t.pov:1:11: error: an expression expected, got '}'"},
        {"torus { 1, 0 }", "t.pov:1:12: error: torus radii must be non-zero finite numbers, got 1 and 0"},
        {"torus { 0, 1 }", "t.pov:1:9: error: torus radii must be non-zero finite numbers, got 0 and 1"},
        {"torus { 0.5, 1 difference }",
         "t.pov:1:16: error: the spindle torus mode 'difference' is not supported (only union, the default)"},
        {"torus { 2, 1 intersection }",
         "t.pov:1:14: error: the spindle torus mode 'intersection' is not supported (only union, the default)"},
        {"quadric { <1, 1, 1>, <0, 0, 0>, -1 }",
         "t.pov:1:36: error: an expression expected, got '}'"},
        {"quadric { <1, 1, 1>, <0, 0, 0>, <0, 0, 0> }",
         "t.pov:1:43: error: an expression expected, got '}'"},
        {"quadric { <1, 1, 1>, <0, 0, 0>, <0, 0, 0>, -1, 2 }",
         "t.pov:1:46: error: '}' expected (to close 'quadric' at 1:1), got ','"},
        {"sphere { 0, 1 sturm }",
         "t.pov:1:15: error: 'sturm' applies only to torus, poly, quartic and cubic, not to 'sphere'"},
        {"union {\n  sphere { 0, 1 }\n  translate x\n  sphere { 0, 1 }\n}",
         "t.pov:4:3: error: '}' expected (to close 'union' at 1:1), got 'sphere'"},
        {"sphere { 0, 1 no_reflection }",
         "t.pov:1:15: error: unsupported: 'no_reflection' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"#render \"x\"",
         "t.pov:1:1: error: unsupported: '#render' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"camera { fisheye }",
         "t.pov:1:10: error: unsupported: 'fisheye' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"sphere { 0, -1 }", "t.pov:1:13: error: sphere radius must be > 0, got -1"},
        {"sphere { 0, 0 }", "t.pov:1:13: error: sphere radius must be > 0, got 0"},
        {"sphere { 0, 1/0 }", "t.pov:1:14: error: division by zero"},
        {"sphere { 0, 1/(2-2) }", "t.pov:1:14: error: division by zero"},
        {"sphere { x/<1,0,1>, 1 }", "t.pov:1:11: error: division by zero"},
        {"sphere { 0, 1e999 }", "t.pov:1:13: error: number out of range: '1e999'"},
        {"sphere { 0, 1e308*10 }",
         "t.pov:1:18: error: arithmetic overflow: the result is not a finite number"},
        {"sphere { 0 1 ", "t.pov:1:14: error: '}' expected (to close 'sphere' at 1:1), got end of file"},
        {"sphere { 0, ", "t.pov:1:13: error: an expression expected, got end of file"},
        {"sphere 0, 1", "t.pov:1:8: error: '{' expected after 'sphere', got '0'"},
        {"sphere { <1,2,3,4>, 1 }",
         "t.pov:1:10: error: a 3-component vector expected, got a 4-component vector"},
        {"sphere { <1>, 1 }", "t.pov:1:10: error: a vector needs at least 2 components"},
        {"sphere { <1,2,3,4,5,6>, 1 }", "t.pov:1:21: error: a vector has at most 5 components"},
        /* one trailing comma after the 2nd to 4th component (POV-Ray's), no more */
        {"sphere { <1,2,3,4,5,>, 1 }", "t.pov:1:21: error: an expression expected, got '>'"},
        {"sphere { <1,>, 1 }", "t.pov:1:13: error: an expression expected, got '>'"},
        {"sphere { <1,2,3,,>, 1 }", "t.pov:1:17: error: an expression expected, got ','"},
        {"sphere { <1,2,3, 1 }", "t.pov:1:20: error: '>' expected (to close '<' at 1:10), got '}'"},
        {"sphere { (1, 1 }", "t.pov:1:12: error: ')' expected (to close '(' at 1:10), got ','"},
        {"sphere { <1,x,3>, 1 }",
         "t.pov:1:13: error: a float expected as a vector component, got a 3-component vector"},
        {"sphere { 0, <1,2,3> }", "t.pov:1:13: error: a float expected, got a 3-component vector"},
        {"text { ttf \"no_such_font.ttf\" \"A\" 1, 0 }", "t.pov:1:8: error: cannot read font file 'no_such_font.ttf': no such file (nor found in the library folders)"},
        {"text { \"timrom.ttf\" \"A\" 1, 0 }", "t.pov:1:8: error: 'ttf' expected inside 'text' (a font file), got '\"timrom.ttf\"'"},
        {"text { ttf \"timrom.ttf\" \" \" 1, 0 }", "t.pov:1:25: error: text with nothing to see: no glyph of the string has an outline"},
        {"prism { 0, 1, 2, <0, 0>, <1, 0> }", "t.pov:1:15: error: prism with linear splines needs at least 3 points (at most 1000000), got 2"},
        {"prism { conic_sweep -1, 1, 4, <0, 0>, <1, 0>, <1, 1>, <0, 0> }",
         "t.pov:1:25: error: unsupported: a conic_sweep prism with a height below 0 (its apex "
         "inside) is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"prism { 0, 1, 4, <0, 0>, <1, 0>, <1, 1>, <0, 0> open }", "t.pov:1:49: error: unsupported: 'open' on a prism is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"prism { bezier_spline 0, 1, 4, <0, 0>, <1, 0>, <1, 1>, <0, 1> }", "t.pov:1:1: error: prism not closed: an outline does not end on its first point"},
        {"prism { cubic_spline 0, 1, 6, <0, 0>, <1, 0>, <1, 1>, <0, 1>, <0, 2>, <3, 3> }", "t.pov:1:1: error: too few points in prism: an outline is not closed or lacks its control points"},
        {"prism { 0, 0, 4, <0, 0>, <1, 0>, <1, 1>, <0, 0> }",
         "t.pov:1:12: error: prism heights are equal (0): it has no volume"},
        {"text { ttf \"timrom.ttf\" \"A\" 0, 0 }",
         "t.pov:1:29: error: text thickness must not be 0"},
        {"cone { 0, 0, y, 0 }", "t.pov:1:1: error: cone radii are both 0"},
        {"cone { 0, -1, y, 0 }", "t.pov:1:11: error: cone radius must be >= 0, got -1"},
        {"cone { 0, 1, y, -2 }", "t.pov:1:17: error: cone radius must be >= 0, got -2"},
        {"cone { y, 1, y, 2 }", "t.pov:1:1: error: cone base and cap are the same point"},
        {"cylinder { 0, 0, 1 }", "t.pov:1:1: error: cylinder base and cap are the same point"},
        {"cylinder { 0, y, -1 }", "t.pov:1:18: error: cylinder radius must be > 0, got -1"},
        {"plane { 0, 1 }", "t.pov:1:9: error: plane normal must be a non-zero finite vector"},
        {"camera { location 0 look_at 0 }",
         "t.pov:1:21: error: camera look_at equals its location: no view direction"},
        {"camera { location <0,0,-1> angle 200 }",
         "t.pov:1:28: error: camera angle must be between 0 and 180 degrees, got 200"},
        {"camera { location <0,0,-1> look_at <0, 0, 0> }\ncamera { foo }",
         "t.pov:2:10: error: '}' expected (to close 'camera' at 2:1), got 'foo'"},
        {"sphere { 0, 1 scale <1,0,1> }", "t.pov:1:21: error: scale by zero"},
        {"sphere { 0, 1 scale 0 }", "t.pov:1:21: error: scale by zero"},
        {"sphere { 0, Foo }", "t.pov:1:13: error: undeclared identifier 'Foo'"},
        {"#declare P = pigment { rgb 1 }\nsphere { 0, P }",
         "t.pov:2:13: error: 'P' is a pigment, not a float, vector or color"},
        {"#declare S = sphere { 0, 1 }\nobject { S } object { P }",
         "t.pov:2:23: error: undeclared identifier 'P'"},
        {"#declare F = 1;\nobject { F }", "t.pov:2:10: error: 'F' is a float, not an object"},
        {"#declare S = sphere { 0, 1 }\nobject { 1 }",
         "t.pov:2:10: error: an object identifier expected inside 'object', got '1'"},
        {"sphere { 0, 1 pigment { Red } }", "t.pov:1:25: error: undeclared identifier 'Red'"},
        {"/* abc", "t.pov:1:1: error: unterminated comment"},
        {"sphere { 0, 1 }\n  /* a /* b */", "t.pov:2:3: error: unterminated comment"},
        {"sphere { 0, 1 } \"abc", "t.pov:1:17: error: unterminated string"},
        {"#include \"abc\ndef\"", "t.pov:1:10: error: unterminated string"},
        {"sphere { 0, 1 $ }", "t.pov:1:15: error: unexpected character '$'"},
        {"sphere { 0, 1 \x01 }", "t.pov:1:15: error: unexpected character (byte 0x01)"},
        {"1.5e", "t.pov:1:1: error: malformed number '1.5e': digits expected after the exponent"},
        {"sphere { 0, 1x }", "t.pov:1:13: error: malformed number '1x'"},
        {"#declare X = 1\nsphere { 0, X }",
         "t.pov:2:1: error: ';' expected (to end '#declare' at 1:1), got 'sphere'"},
        {"#declare X = rgb 1\nsphere { 0, X }",
         "t.pov:2:1: error: ';' expected (to end '#declare' at 1:1), got 'sphere'"},
        {"#declare sphere = 1;",
         "t.pov:1:10: error: an identifier expected after '#declare', got 'sphere'"},
        {"#declare X 1;", "t.pov:1:12: error: '=' expected after '#declare X', got '1'"},
        {"#declare X = ;",
         "t.pov:1:14: error: a value, color, pigment, finish, texture, interior or object expected, got ';'"},
        {"#version 3.7", "t.pov:1:13: error: ';' expected (to end '#version' at 1:1), got end of file"},
        {"#include colors.inc",
         "t.pov:1:10: error: a file name in quotes expected after '#include', got 'colors'"},
        {"#", "t.pov:1:1: error: a directive name expected after '#'"},
        {"union { }", "t.pov:1:9: error: an object expected inside 'union', got '}'"},
        {"difference { sor { 4, <1> } }",
         "t.pov:1:14: error: unsupported: 'sor' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"difference { poly { 4, <1> } }",
         "t.pov:1:26: error: a poly of order 4 has 35 coefficients, got 1"},
        {"sphere { 0, 1 open }",
         "t.pov:1:15: error: 'open' applies only to cylinder and cone, not to 'sphere'"},
        {"global_settings { max_trace_level 2.5 }",
         "t.pov:1:35: error: max_trace_level must be an integer from 1 to 256, got 2.5"},
        {"global_settings { max_trace_level 0 }",
         "t.pov:1:35: error: max_trace_level must be an integer from 1 to 256, got 0"},
        {"global_settings { assumed_gamma 0 }",
         "t.pov:1:33: error: assumed_gamma must be > 0, got 0"},
        {"global_settings { adc_bailout -1 }",
         "t.pov:1:31: error: adc_bailout must be between 0 and 1, got -1"},
        {"global_settings { radiosity { } }",
         "t.pov:1:19: error: unsupported: 'radiosity' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"light_source { <0,0,0> }", "t.pov:1:24: error: a color expected for the light_source, got '}'"},
        {"light_source { 0, 1 projected_through { } }",
         "t.pov:1:21: error: unsupported: 'projected_through' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"background { }", "t.pov:1:14: error: a color expected inside 'background', got '}'"},
        {"background { rgb 1 rgb }",
         "t.pov:1:20: error: '}' expected (to close 'background' at 1:1), got 'rgb'"},
        {"background { rgb }", "t.pov:1:18: error: an expression expected, got '}'"},
        {"background { color }", "t.pov:1:20: error: a color expected after 'color', got '}'"},
        {"background { <1, 2> }", "t.pov:1:14: error: a color expected, got a 2-component vector"},
        {"background { rgbft <1, 2, 3> }",
         "t.pov:1:20: error: 'rgbft' needs a float or a 5-component vector, got a 3-component vector"},
        {"sphere { 0, 1 } }", "t.pov:1:17: error: an object or a statement expected, got '}'"},
        {"pigment { rgb 1 }", "t.pov:1:1: error: an object or a statement expected, got 'pigment'"},
        {"sphere { 0, 1 finish { roughness 0 } }",
         "t.pov:1:34: error: roughness must be > 0, got 0"},
        {"sphere { 0, 1 finish { phong_size -1 } }",
         "t.pov:1:35: error: phong_size must be >= 0, got -1"},
        {"sphere { 0, 1 bounded_by { box { -1, 1 } 2 } }",
         "t.pov:1:42: error: '}' expected (to close 'bounded_by' at 1:15), got '2'"},
        {"camera { right y location 6 * y look_at 0 }",
         "t.pov:1:33: error: camera sky and right are both parallel to the view direction"},
        /* (variable reflection is read since #38's session 3: its errors) */
        {"sphere { 0, 1 finish { reflection { 0.1, 0.5 falloff } } }",
         "t.pov:1:54: error: an expression expected, got '}'"},
        {"sphere { 0, 1 finish { reflection { 0.1 fresnel } fresnel } }",
         "t.pov:1:51: error: unsupported: the finish's 'fresnel' (outside a reflection block) is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"sphere { 0, 1 bounded_by box { -1, 1 } }",
         "t.pov:1:26: error: '{' expected after 'bounded_by', got 'box'"},
        /* clipped_by and bounded_by: POV-Ray's Parse_Object_Mods errors */
        {"sphere { 0, 1 clipped_by { } }", "t.pov:1:28: error: an object expected, got '}'"},
        {"sphere { 0, 1 clipped_by { box { -1, 1 } 2 } }",
         "t.pov:1:42: error: '}' expected (to close 'clipped_by' at 1:15), got '2'"},
        {"sphere { 0, 1 clipped_by { box { -1, 1 pigment { rgb 1 } } } }",
         "t.pov:1:28: error: illegal texture in 'clipped_by' (its objects have no surface)"},
        {"sphere { 0, 1 clipped_by { box { -1, 1 } } bounded_by { clipped_by } "
         "clipped_by { plane { y, 0 } } }",
         "t.pov:1:70: error: cannot add clips after linking bounds and clips"},
        {"sphere { 0, 1 clipped_by { box { -1, 1 } } bounded_by { clipped_by } "
         "bounded_by { plane { y, 0 } } }",
         "t.pov:1:70: error: cannot add bounds after linking bounds and clips"},
        {"sphere { 0, 1 bounded_by { box { -1, 1 } } bounded_by { clipped_by } }",
         "t.pov:1:44: error: cannot link clips with previous bounds"},
        {"sphere { 0, 1 clipped_by { box { -1, 1 } } clipped_by { bounded_by } }",
         "t.pov:1:44: error: cannot link bounds with previous clips"},
        {"sphere { 0, 1 clipped_by { bounded_by box } }",
         "t.pov:1:39: error: '}' expected (to close 'clipped_by' at 1:15), got 'box'"},
        {"sphere { 0, 1 finish { metallic 0.5 emission 0.3 } }",
         "t.pov:1:37: error: unsupported: 'emission' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"sphere { 0, 1 finish { phong 1 ; } }",
         "t.pov:1:32: error: '}' expected (to close 'finish' at 1:15), got ';'"},
        {"sphere { 0, 1 interior { ior 0 } }", "t.pov:1:30: error: ior must be > 0, got 0"},
        {"sphere { 0, 1 texture { tiles { } } }",
         "t.pov:1:25: error: unsupported: 'tiles' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"sphere { 0, 1 pigment { rgb 1 rgb 2 x } }",
         "t.pov:1:31: error: '}' expected (to close 'pigment' at 1:15), got 'rgb'"},
        {"sphere { 0, 1 pigment { tiling 3 } }",
         "t.pov:1:25: error: unsupported: 'tiling' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"sphere { 0, now }",
         "t.pov:1:13: error: unsupported: 'now' is not in csgtrace's language (see scenes/LANGUAGE.md)"},
        {"sphere { 0, 1 transform { scale 0 } }", "t.pov:1:33: error: scale by zero"},
        {"sphere { 0, 1 matrix <1,0,0,0,1,0,0,0,1,0,0> }",
         "t.pov:1:44: error: matrix needs 12 numbers separated by ','"},
        {"sphere { 0, 1 matrix <1,0,0,0,0,0,0,0,1,0,0,0> }",
         "t.pov:1:22: error: matrix is singular"},
        {"#declare Obj = 1;\nObj",
         "t.pov:2:1: error: an object or a statement expected, got 'Obj'"},
        {"; ", "t.pov:1:1: error: an object or a statement expected, got ';'"},
        {"\"string\"", "t.pov:1:1: error: an object or a statement expected, got '\"string\"'"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        parse_err(cases[i].text, cases[i].message);
}

/* NUL bytes inside the buffer are characters like any other: an error. */
static void test_nul_byte(void **state)
{
    (void)state;
    const char text[] = "sphere { 0, 1 }\n\0 sphere { 0, 1 }";
    csg_scene s;
    csg_diag d;
    memset(&d, 0, sizeof d);
    assert_false(csg_parse_string("t.pov", text, sizeof text - 1, &s, &d));
    assert_string_equal(d.message, "t.pov:2:1: error: unexpected character (byte 0x00)");
}

/* ---- limits ------------------------------------------------------------------------ */

static char *repeat(const char *head, int n, const char *middle, const char *tail)
{
    size_t hl = strlen(head), tl = strlen(tail), ml = strlen(middle);
    char *buf = malloc((hl + tl) * (size_t)n + ml + 1);
    assert_non_null(buf);
    char *w = buf;
    for (int i = 0; i < n; i++, w += hl)
        memcpy(w, head, hl);
    memcpy(w, middle, ml);
    w += ml;
    for (int i = 0; i < n; i++, w += tl)
        memcpy(w, tail, tl);
    *w = '\0';
    return buf;
}

static void test_nesting_limits(void **state)
{
    (void)state;
    csg_scene s;
    /* 127 unions around a sphere: 128 levels, the limit, accepted */
    char *text = repeat("union { ", 127, "sphere { 0, 1 }", " }");
    parse_ok(text, &s);
    assert_int_equal(s.object_count, 1);
    csg_scene_free(&s);
    free(text);

    text = repeat("union { ", 128, "sphere { 0, 1 }", " }");
    parse_err(text, "t.pov:1:1025: error: nesting deeper than 128 levels");
    free(text);

    text = repeat("union {\n", 200000, "sphere { 0, 1 }", "}\n");
    parse_err(text, "t.pov:129:1: error: nesting deeper than 128 levels");
    free(text);

    text = repeat("(", 200000, "1", ")");
    char *scene = malloc(strlen(text) + 32);
    assert_non_null(scene);
    sprintf(scene, "sphere { 0, %s }", text);
    parse_err(scene, "t.pov:1:140: error: nesting deeper than 128 levels");
    free(scene);
    free(text);

    /* unary minus is iterative: no limit */
    text = repeat("-", 100000, "1", "");
    scene = malloc(strlen(text) + 32);
    assert_non_null(scene);
    sprintf(scene, "sphere { 0, %s }", text);
    parse_ok(scene, &s);
    assert_near(s.objects[0]->r0, 1);
    csg_scene_free(&s);
    free(scene);
    free(text);

    /* the CSG tree is also bounded when it grows through declared objects */
    size_t cap = 200 * 64;
    char *chain = malloc(cap);
    assert_non_null(chain);
    int n = snprintf(chain, cap, "#declare A = sphere { 0, 1 }\n");
    for (int i = 0; i < 130; i++)
        n += snprintf(chain + n, cap - (size_t)n, "#declare A = union { object { A } }\n");
    parse_err(chain, "t.pov:129:14: error: CSG tree deeper than 128 levels");
    free(chain);

    /* block comments nest to any depth without recursion */
    text = repeat("/*", 100000, " ", "*/");
    parse_ok(text, &s);
    csg_scene_free(&s);
    free(text);
}

/* ---- #include ------------------------------------------------------------------------ */

static void write_file(const char *dir, const char *name, const char *text)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void test_include(void **state)
{
    (void)state;
    char dir[] = "/tmp/csg_parser_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char sub[600];
    snprintf(sub, sizeof sub, "%s/sub", dir);
    assert_int_equal(mkdir(sub, 0700), 0);
    write_file(dir, "main.pov",
               "#include \"colors.inc\"\n"
               "#include \"sub/defs.inc\"\n"
               "object { Ball pigment { Orange } }\n");
    write_file(sub, "defs.inc", "#include \"more.inc\"\n#declare Ball = sphere { 0, R };\n");
    write_file(sub, "more.inc", "#declare R = 2;\n");
    write_file(dir, "cycle.pov", "sphere { 0, 1 }\n  #include \"cycle2.inc\"\n");
    write_file(dir, "cycle2.inc", "\n#include \"cycle.pov\"\n");
    write_file(dir, "missing.pov", "\n\n   #include \"nowhere.inc\"\n");
    write_file(dir, "bad.pov", "#include \"bad.inc\"\n");
    write_file(dir, "bad.inc", "sphere { 0, 1 }\nsphere { 0, -1 }\n");

    char path[700], want[2400];
    csg_scene s;
    csg_diag d;
    memset(&d, 0, sizeof d);
    snprintf(path, sizeof path, "%s/main.pov", dir);
    if (!csg_parse_file(path, &s, &d))
        fail_msg("%s", d.message);
    assert_int_equal(s.object_count, 1);
    assert_near(s.objects[0]->r0, 2);
    assert_near(s.textures[s.objects[0]->texture].pigment.rgbft[1], 0.5);
    assert_string_equal(s.path, path);
    csg_scene_free(&s);

    memset(&d, 0, sizeof d);
    snprintf(path, sizeof path, "%s/cycle.pov", dir);
    assert_false(csg_parse_file(path, &s, &d));
    snprintf(want, sizeof want,
             "%s/cycle2.inc:2:1: error: #include cycle: '%s/cycle.pov' is already being read "
             "(in '%s/cycle2.inc' included at %s/cycle.pov:2:3)", dir, dir, dir, dir);
    assert_string_equal(d.message, want);

    memset(&d, 0, sizeof d);
    snprintf(path, sizeof path, "%s/missing.pov", dir);
    assert_false(csg_parse_file(path, &s, &d));
    snprintf(want, sizeof want,
             "%s:3:4: error: cannot read include file '%s/nowhere.inc': No such file or directory%s",
             path, dir, csg_default_library(0) ? " (nor found in the library folders)" : "");
    assert_string_equal(d.message, want);

    memset(&d, 0, sizeof d);
    snprintf(path, sizeof path, "%s/bad.pov", dir);
    assert_false(csg_parse_file(path, &s, &d));
    snprintf(want, sizeof want,
             "%s/bad.inc:2:13: error: sphere radius must be > 0, got -1 (in '%s/bad.inc' included "
             "at %s/bad.pov:1:1)", dir, dir, dir);
    assert_string_equal(d.message, want);

    memset(&d, 0, sizeof d);
    snprintf(path, sizeof path, "%s/none.pov", dir);
    assert_false(csg_parse_file(path, &s, &d));
    snprintf(want, sizeof want, "csgtrace: error: cannot read scene '%s': No such file or directory",
             path);
    assert_string_equal(d.message, want);

    /* a string's name decides where its includes are looked for */
    char text[] = "#include \"sub/more.inc\"\nsphere { 0, R }";
    snprintf(path, sizeof path, "%s/virtual.pov", dir);
    memset(&d, 0, sizeof d);
    if (!csg_parse_string(path, text, strlen(text), &s, &d))
        fail_msg("%s", d.message);
    assert_near(s.objects[0]->r0, 2);
    csg_scene_free(&s);

    const char *names[] = {"main.pov", "sub/defs.inc", "sub/more.inc", "cycle.pov",
                           "cycle2.inc", "missing.pov", "bad.pov", "bad.inc"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        unlink(path);
    }
    rmdir(sub);
    rmdir(dir);
}

/* ---- the lexer and the summary --------------------------------------------------- */

static void test_keywords(void **state)
{
    (void)state;
    assert_int_equal(csg_keyword("sphere", 6, false), CSG_KW_SPHERE);
    assert_int_equal(csg_keyword("colour", 6, false), CSG_KW_COLOR);
    assert_int_equal(csg_keyword("no", 2, false), CSG_KW_FALSE);
    assert_int_equal(csg_keyword("no_shadow", 9, false), CSG_KW_NO_SHADOW);
    assert_int_equal(csg_keyword("hexagon", 7, false), CSG_KW_PATTERN);
    assert_int_equal(csg_keyword("tiling", 6, false), CSG_KW_UNSUPPORTED);
    assert_int_equal(csg_keyword("ambient", 7, false), CSG_KW_AMBIENT);
    assert_int_equal(csg_keyword("ambient_light", 13, false), CSG_KW_AMBIENT_LIGHT);
    assert_int_equal(csg_keyword("z", 1, false), CSG_KW_Z);
    assert_int_equal(csg_keyword("x", 1, false), CSG_KW_X);
    assert_int_equal(csg_keyword("warp", 4, false), CSG_KW_UNSUPPORTED);
    assert_int_equal(csg_keyword("Sphere", 6, false), CSG_KW_NONE);
    assert_int_equal(csg_keyword("declare", 7, true), CSG_KW_DECLARE);
    assert_int_equal(csg_keyword("fopen", 5, true), CSG_KW_FOPEN);
    assert_int_equal(csg_keyword("statistics", 10, true), CSG_KW_UNSUPPORTED);
    assert_int_equal(csg_keyword("declare", 7, false), CSG_KW_NONE);
    assert_int_equal(csg_keyword("default", 7, false), CSG_KW_DEFAULT);
    assert_int_equal(csg_keyword("defined", 7, false), CSG_KW_DEFINED);
}

/* Every row of the lexer's tables, read from its source, is found by the
 * binary search: a row out of byte order hides itself or a neighbour
 * (`defined` was taken for an identifier that way). */
static void test_keyword_tables_sorted(void **state)
{
    (void)state;
    FILE *f = fopen("csg/lang/lexer.c", "r");
    assert_non_null(f);
    char line[256], word[64], last[64] = "";
    int table = 0, rows = 0; /* 1: kw_table, 2: directive_table */
    while (fgets(line, sizeof line, f)) {
        if (strstr(line, "kw_entry kw_table[]") || strstr(line, "kw_entry directive_table[]")) {
            table = strstr(line, "directive") ? 2 : 1;
            last[0] = '\0';
        } else if (table && strncmp(line, "};", 2) == 0) {
            table = 0;
        } else if (table && sscanf(line, " {\"%63[^\"]\"", word) == 1) {
            if (strcmp(last, word) >= 0)
                fail_msg("lexer.c: '%s' after '%s' (not in byte order)", word, last);
            if (csg_keyword(word, strlen(word), table == 2) == CSG_KW_NONE)
                fail_msg("lexer.c: '%s' is not found", word);
            snprintf(last, sizeof last, "%s", word);
            rows++;
        }
    }
    fclose(f);
    assert_true(rows > 400);
}

static void test_summary(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("camera { location <0, 1, -5> look_at 0 }\n"
             "light_source { <0, 5, -5> rgb 1 }\n"
             "difference { box { -1, 1 } union { sphere { 0, 1.2 } cylinder { -2*x, 2*x, 0.5 } }\n"
             "  pigment { rgbf <1, 1, 1, 0.5> } finish { reflection 0.3 } }\n"
             "plane { y, -1 }\n", &s);
    char *buf = summary_text(&s);
    assert_non_null(buf);
    assert_non_null(strstr(buf, "objects: 2 top-level, 4 primitives, 2 CSG operations, CSG depth 3"));
    assert_non_null(strstr(buf, "sphere 1 box 1 cylinder 1 plane 1 union 1 difference 1"));
    assert_non_null(strstr(buf, "lights: 1 (0 shadowless)"));
    assert_non_null(strstr(buf, "textures: 2 used (1 reflective, 1 transparent); interiors: 1 used"));
    assert_non_null(strstr(buf, "location   <0, 1, -5>"));
    free(buf);
    csg_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_primitives),
        cmocka_unit_test(test_vector_trailing_comma),
        cmocka_unit_test(test_flat_boxes),
        cmocka_unit_test(test_expressions),
        cmocka_unit_test(test_promotion),
        cmocka_unit_test(test_colors),
        cmocka_unit_test(test_transform_order),
        cmocka_unit_test(test_csg_world_transforms),
        cmocka_unit_test(test_declared_copies),
        cmocka_unit_test(test_textures),
        cmocka_unit_test(test_csg_inheritance),
        cmocka_unit_test(test_equal_textures_shared),
        cmocka_unit_test(test_statements),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_nul_byte),
        cmocka_unit_test(test_nesting_limits),
        cmocka_unit_test(test_include),
        cmocka_unit_test(test_keywords),
        cmocka_unit_test(test_keyword_tables_sorted),
        cmocka_unit_test(test_summary),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
