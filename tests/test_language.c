/*
 * test_language.c — the scene language beyond single statements: the
 * directives run at the token level (#if ... #end, #while, #for, #switch,
 * #macro, #local scopes, #undef, #default), arrays, strings, the built-in
 * functions (POV-Ray's numbers, seed/rand's exact sequence), image_width,
 * image_height and clock, the camera's fixed order, patterns, declarations
 * that use unsupported constructs, the limits, and the front end's
 * reliability (byte-order mark, long messages, what #include reads, the
 * macro/include chain in messages, content of non-scene files never shown).
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

#include "../csg/device/flat.h"
#include "../csg/lang/parser.h"

/* ---- helpers ------------------------------------------------------------- */

static csg_parse_options quiet(void)
{
    csg_parse_options o;
    csg_parse_options_default(&o);
    o.no_default_library = true; /* colors.inc: the built-in one */
    return o;
}

static void parse_ok_opts(const char *text, const csg_parse_options *o, csg_scene *s)
{
    csg_diag d;
    memset(&d, 0, sizeof d);
    if (!csg_parse_string_opts("t.pov", text, strlen(text), o, s, &d))
        fail_msg("unexpected parse error: %s\n--- input:\n%s", d.message, text);
}

static void parse_ok(const char *text, csg_scene *s)
{
    csg_parse_options o = quiet();
    parse_ok_opts(text, &o, s);
}

/* The message of a failing parse (static buffer). */
static const char *parse_fail_opts(const char *text, const csg_parse_options *o)
{
    static csg_diag d;
    csg_scene s;
    memset(&d, 0, sizeof d);
    if (csg_parse_string_opts("t.pov", text, strlen(text), o, &s, &d)) {
        csg_scene_free(&s);
        fail_msg("parse succeeded, expected a failure:\n%s", text);
    }
    assert_null(s.arena);
    return d.message;
}

static void parse_err(const char *text, const char *message)
{
    csg_parse_options o = quiet();
    assert_string_equal(parse_fail_opts(text, &o), message);
}

#define EPS 1e-12
static void assert_near(double a, double b)
{
    if (!(fabs(a - b) <= EPS * (1 + fabs(b))))
        fail_msg("%.17g != %.17g", a, b);
}

/* The radii of the scene's top-level objects, in order. */
static void assert_radii(const char *text, const double *want, int n)
{
    csg_scene s;
    parse_ok(text, &s);
    if (s.object_count != n)
        fail_msg("%d objects, expected %d:\n%s", s.object_count, n, text);
    for (int i = 0; i < n; i++)
        assert_near(s.objects[i]->r0, want[i]);
    csg_scene_free(&s);
}

/* ---- fog and light sources ------------------------------------------------ */

static void test_fog_and_lights(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("fog { fog_type 2 distance 5 color rgbf <1, 0.5, 0.2, 0.3> fog_offset 1 fog_alt 2 "
             "turbulence 0.5 octaves 20 up <0, 2, 0> rotate 90 * x translate 3 }\n"
             "fog { 7 rgb 1 }\nsphere { 0, 1 hollow } box { 0, 1 hollow off }",
             &s);
    assert_int_equal(s.fog_count, 2);
    assert_int_equal(s.fogs[0].kind, CSG_FOG_GROUND);
    assert_near(s.fogs[0].distance, 5);
    assert_near(s.fogs[0].rgbft[3], 0.3);
    assert_near(s.fogs[0].offset, 1);
    assert_near(s.fogs[0].alt, 2);
    assert_int_equal(s.fogs[0].turb.octaves, 10); /* clamped, as POV-Ray */
    assert_true(s.fogs[0].turb.on);
    /* up: turned by the rotation, not moved by the translation; kept at
     * its length (the flattener makes it a unit vector) */
    assert_near(s.fogs[0].up.x, 0);
    assert_near(s.fogs[0].up.y, 0);
    assert_near(s.fogs[0].up.z, 2);
    assert_int_equal(s.fogs[1].kind, CSG_FOG_CONSTANT);
    assert_near(s.fogs[1].distance, 7);
    assert_int_equal(s.objects[0]->hollow, 1);
    assert_int_equal(s.objects[1]->hollow, 2);
    csg_scene_free(&s);
    parse_ok("light_source { <0, 5, 0>, 1 spotlight point_at <0, 0, 0> radius 60 falloff 90 "
             "tightness 3 fade_distance 2 fade_power 1 translate x }\n"
             "light_source { 0, 1 area_light x, z, 3, 4 adaptive 2 circular orient "
             "looks_like { sphere { 0, 0.1 } } }",
             &s);
    assert_int_equal(s.light_count, 2);
    assert_int_equal(s.lights[0].kind, CSG_LIGHT_SPOT);
    assert_near(s.lights[0].radius, cos(60 * M_PI / 180)); /* kept as cosines */
    assert_near(s.lights[0].falloff, cos(90 * M_PI / 180));
    assert_near(s.lights[0].point_at.x, 1); /* moved with the light */
    assert_near(s.lights[0].position.x, 1);
    assert_true(s.lights[1].area);
    assert_int_equal(s.lights[1].size1, 3);
    assert_int_equal(s.lights[1].size2, 4);
    assert_int_equal(s.lights[1].adaptive, 2);
    assert_int_equal(s.object_count, 1); /* the looks_like object, shadowless */
    assert_true(s.objects[0]->no_shadow);
    csg_scene_free(&s);
    parse_err("fog { fog_type 3 }", "t.pov:1:16: error: fog_type must be 1 (constant) or 2 (ground), got 3");
    parse_err("fog { fog_type 2 distance 3 }",
              "t.pov:1:1: error: a ground fog (fog_type 2) needs fog_alt other than 0");
    parse_err("fog { up 0 }", "t.pov:1:1: error: fog up vector must not be zero");
    parse_err("fog { distance 1 media }",
              "t.pov:1:18: error: unsupported: 'media' is not in csgtrace's language (see scenes/LANGUAGE.md)");
    parse_err("light_source { 0, 1 radius 3 }",
              "t.pov:1:21: error: 'radius' needs a spotlight or a cylinder light");
    parse_err("light_source { 0, 1 point_at x }",
              "t.pov:1:21: error: 'point_at' needs a spotlight, a cylinder or a parallel light");
    parse_ok("light_source { 0, 1 area_light x, z, 2, 2 jitter }", &s);
    assert_true(s.lights[0].jitter);
    csg_scene_free(&s);
    parse_err("light_source { 0, 1 area_light x, z, 0, 2 }",
              "t.pov:1:38: error: area_light sizes must be whole numbers from 1 up, at most 65536 points, got 0 and 2");
    parse_err("light_source { 0, 1 area_light x, z, 1, 3 circular }",
              "t.pov:1:1: error: a circular area light must have more than 1 point per axis");
    parse_err("light_source { 0, 1 media_attenuation }",
              "t.pov:1:21: error: unsupported: 'media_attenuation on' is not in csgtrace's language (see scenes/LANGUAGE.md)");
    parse_ok("light_source { 0, 1 media_attenuation off media_interaction }", &s);
    csg_scene_free(&s);
    parse_ok("sphere { 0, 1 interior { ior 1.5 fade_distance 2 fade_power 1001 "
             "fade_colour rgb <0.5, 0.25, 1> } }",
             &s);
    const csg_interior *in = &s.interiors[s.objects[0]->interior];
    assert_near(in->ior, 1.5);
    assert_near(in->fade_distance, 2);
    assert_near(in->fade_power, 1001);
    assert_near(in->fade_color[1], 0.25);
    csg_scene_free(&s);
}

/* ---- conditionals -------------------------------------------------------------- */

static void test_conditionals(void **state)
{
    (void)state;
    static const double a[] = {1, 3, 5, 6, 8, 9};
    assert_radii("#declare A = 2;\n"
                 "#if (A = 2) sphere { 0, 1 } #else sphere { 0, 2 } #end\n"
                 "#if (A > 5) sphere { 0, 2 } #elseif (A < 1) sphere { 0, 4 } #elseif (A) sphere { 0, 3 }"
                 " #else sphere { 0, 4 } #end\n"
                 "#ifdef (A) sphere { 0, 5 } #end #ifndef (B) sphere { 0, 6 } #end\n"
                 "#ifdef (B) #if (1) sphere { 0, 7 } #end #else sphere { 0, 8 } #end\n"
                 "sphere { 0, #if (A = 2) 9 #else 10 #end }\n", a, 6);
    /* directives anywhere tokens may be: inside blocks and expressions */
    csg_scene s;
    parse_ok("union { #declare R = 0.5; sphere { 0, R } #if (1) sphere { x, R * 2 } #end\n"
             "  #local T = 3; translate T * y }\n", &s);
    assert_int_equal(s.objects[0]->child_count, 2);
    assert_near(s.objects[0]->children[1]->r0, 1);
    assert_near(s.objects[0]->xform.m[1][3], 3);
    csg_scene_free(&s);
}

/* ---- loops and switch ------------------------------------------------------------ */

static void test_loops(void **state)
{
    (void)state;
    static const double a[] = {1, 2, 3, 10, 8, 6, 0.5, 1};
    assert_radii("#declare I = 1; #while (I <= 3) sphere { 0, I } #declare I = I + 1; #end\n"
                 "#for (J, 10, 5, -2) sphere { 0, J } #end\n"
                 "#for (K, 0.5, 1, 0.5) sphere { 0, K } #end\n"
                 "#for (K, 1, 0) sphere { 0, 99 } #end\n", a, 8);
    static const double b[] = {1, 2, 4, 5};
    assert_radii("#declare I = 0;\n"
                 "#while (1) #declare I = I + 1; #if (I = 3) #break #end sphere { 0, I } #end\n"
                 "#for (K, 4, 100) #if (K > 5) #break #end sphere { 0, K } #end\n", b, 4);
    /* #switch: the first match, falling through to #break; #range; #else */
    static const double c[] = {2, 3, 7, 9};
    assert_radii("#switch (2)\n"
                 "  #case (1) sphere { 0, 1 } #break\n"
                 "  #case (2) sphere { 0, 2 }\n"
                 "  #case (3) sphere { 0, 3 } #break\n"
                 "  #else sphere { 0, 4 }\n"
                 "#end\n"
                 "#switch (5.5) #range (1, 5) sphere { 0, 6 } #break #range (5, 6) sphere { 0, 7 } #end\n"
                 "#switch (100) #case (1) sphere { 0, 8 } #else sphere { 0, 9 } #end\n", c, 4);
}

/* ---- macros and scopes ----------------------------------------------------------------- */

static void test_macros(void **state)
{
    (void)state;
    static const double a[] = {120, 2, 3, 0.25, 7, 1};
    assert_radii("#macro Fact(N) #if (N <= 1) 1 #else N * Fact(N - 1) #end #end\n"
                 "sphere { 0, Fact(5) }\n"
                 "#macro Ball(P, R) sphere { P, R } #end\n"
                 "Ball(x, 2)\n"
                 "#declare G = 1;\n"
                 "#macro SetG(V) #declare G = V; #local L = 99; #end\n"
                 "SetG(3) sphere { 0, G }\n"
                 "#ifdef (L) sphere { 0, 100 } #end\n"
                 "#macro Half(V) (V / 2) #end\n"
                 "sphere { 0, Half(Half(1)) }\n"
                 "#declare X = 5;\n"
                 "#macro Shadow(X) #local X = X + 2; X #end\n"
                 "sphere { 0, Shadow(X) }\n"
                 "#macro Early() 1 #break 2 #end\n"
                 "sphere { 0, Early() }\n", a, 6);
    /* a macro's #local does not outlive the call; parameters neither */
    parse_err("#macro M(P) #local Q = 1; #end M(2)\nsphere { 0, Q }",
              "t.pov:2:13: error: undeclared identifier 'Q'");
    parse_err("#macro M(A, B) A #end\nsphere { 0, M(1) }",
              "t.pov:2:16: error: macro 'M' expects 2 arguments, got 1");
}

/* An argument that is one identifier alone is passed by reference (POV-Ray
 * 3.7's Parse_RValue): #declare, #local or an element's #declare of the
 * parameter changes the caller's variable; an expression is a copy.  A
 * declaration that ends a macro's body binds in the macro's scope (the
 * look for an optional ';' closed it first: languages/macros/macro2.pov). */
static void test_macro_reference(void **state)
{
    (void)state;
    static const double a[] = {3, 7, 7, 7, 2};
    assert_radii("#declare C = 1;\n"
                 "#macro Inc(V) #declare V = V + 1; #end\n"
                 "Inc(C) Inc(C) Inc(C + 0) sphere { 0, C }\n"
                 "#declare X = 5;\n"
                 "#macro Shadow(X) #local X = X + 2; X #end\n"
                 "sphere { 0, Shadow(X) } sphere { 0, X }\n"
                 "#declare A = array[2] {1, 2}\n"
                 "#macro SetA(B) #declare B[1] = 7; #end\n"
                 "SetA(A) sphere { 0, A[1] }\n"
                 "#declare T = sphere { 0, 1 }\n"
                 "#macro Grow(S) #declare S = sphere { 0, 2 } #end\n"
                 "Grow(T) object { T }\n", a, 5);
    parse_err("#macro M() #local Q = sphere { 0, 1 } #end M()\nobject { Q }",
              "t.pov:2:10: error: undeclared identifier 'Q'");
}

/* ---- arrays ------------------------------------------------------------------------------ */

static void test_arrays(void **state)
{
    (void)state;
    static const double a[] = {2, 4, 6, 3, 2, 3, 1};
    assert_radii("#declare A = array[3] {2, 4, 6};\n"
                 "#for (I, 0, 2) sphere { 0, A[I] } #end\n"
                 "#declare M = array[2][3] { {1, 2, 3}, {4, 5, 6} };\n"
                 "sphere { 0, M[0][2] }\n"
                 "sphere { 0, dimensions(M) } sphere { 0, dimension_size(M, 2) }\n"
                 "#declare O = array[2];\n"
                 "#declare O[1] = sphere { 0, 1 }\n"
                 "#ifdef (O[0]) sphere { 0, 9 } #end\n"
                 "object { O[1] }\n", a, 7);
    parse_err("#declare A = array[2];\nsphere { 0, A[1] }",
              "t.pov:2:13: error: element of array 'A' used before it is set");
    parse_err("#declare A = array[2] {1, 2};\nsphere { 0, A[2] }",
              "t.pov:2:13: error: subscript 2 of 'A' out of range (0 to 1)");
    parse_err("#declare A = array[2] {1};",
              "t.pov:1:25: error: array initialiser: 2 elements expected, got 1");
    parse_err("#declare A = array[2] {1, sphere { 0, 1 }};",
              "t.pov:1:27: error: an array holds one kind of element: this one is an object, the "
              "array's are not");
}

/* ---- strings -------------------------------------------------------------------------------- */

static void test_strings(void **state)
{
    (void)state;
    static const double a[] = {7, 1, 3, 65, 1, 1e-9, 2.5};
    assert_radii("#declare S = concat(\"ab\", str(3.14159, 0, 2), chr(65));\n" /* ab3.14A */
                 "sphere { 0, strlen(S) }\n"
                 "sphere { 0, (S = \"ab3.14A\") }\n"
                 "sphere { 0, strlen(substr(S, 2, 3)) }\n"
                 "sphere { 0, asc(strupr(\"a\")) }\n"
                 "sphere { 0, (strcmp(\"a\", \"b\") < 0) }\n"
                 "sphere { 0, (\"x\" != \"x\") + 1e-9 }\n"
                 "sphere { 0, val(\"2.5\") }\n", a, 7);
    /* #include of a computed name */
    char dir[] = "/tmp/csg_lang_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[256], text[512];
    snprintf(path, sizeof path, "%s/part2.inc", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs("sphere { 0, 42 }\n", f);
    fclose(f);
    snprintf(text, sizeof text, "#declare N = 2;\n#include concat(\"%s/part\", str(N, 0, 0), \".inc\")\n",
             dir);
    csg_scene s;
    parse_ok(text, &s);
    assert_near(s.objects[0]->r0, 42);
    csg_scene_free(&s);
    unlink(path);
    rmdir(dir);
}

/* ---- functions -------------------------------------------------------------------------------- */

static double value_of(const char *expr)
{
    char text[512];
    snprintf(text, sizeof text, "#declare V = %s;\nsphere { 0, 1 + 0 * V translate V * x }", expr);
    csg_scene s;
    parse_ok(text, &s);
    double v = s.objects[0]->xform.m[0][3];
    csg_scene_free(&s);
    return v;
}

static void test_functions(void **state)
{
    (void)state;
    assert_near(value_of("atan2(1, 2)"), atan2(1, 2));
    assert_near(value_of("mod(-7, 3)"), -1);
    assert_near(value_of("div(-7, 2)"), -3);
    assert_near(value_of("int(-2.5)"), -2);
    assert_near(value_of("floor(-2.5) + ceil(2.1)"), 0);
    assert_near(value_of("pow(2, 10) + sqrt(16) + abs(-1)"), 1029);
    assert_near(value_of("min(3, 1, 2) + max(3, 1, 2)"), 4);
    assert_near(value_of("select(-1, 1, 2, 3) + select(0, 1, 2, 3) * 10 + select(1, 1, 2) * 100"), 221);
    assert_near(value_of("degrees(pi) + radians(180)"), 180 + M_PI);
    assert_near(value_of("vlength(<3, 4, 0>) + vdot(x, <2, 3, 4>)"), 7);
    assert_near(value_of("vcross(x, y).z + vnormalize(<0, 0, 9>).z"), 2);
    assert_near(value_of("vrotate(x, <0, 0, 90>).y"), 1);
    assert_near(value_of("vaxis_rotate(x, z, 90).y"), 1);
    assert_near(value_of("exp(1) + log(100) + ln(1)"), exp(1) + 2);
    assert_near(value_of("(1 < 2) + (2 <= 2) + (3 = 3) + (3 != 3) + !0 + (1 & 0) + (0 | 1)"), 5);
    assert_near(value_of("(1 ? 2 : 3) + (0 ? 4 : 5)"), 7);
    assert_near(value_of("<1, 2, 3>.y + <4, 5, 6>.blue + <1, 2, 3, 4, 5>.transmit"), 13);
    assert_near(value_of("bitwise_and(6, 3) + bitwise_or(4, 1) + bitwise_xor(5, 1)"), 11);
    /* seed and rand: POV-Ray 3.7's numbers (its #debug output) */
    assert_true(fabs(value_of("rand(seed(42))") - 0.723583) < 5e-7);
    csg_scene s;
    parse_ok("#declare R = seed(42); #declare A = rand(R); #declare B = rand(R);\n"
             "#declare S = seed(-7); #declare C = rand(S);\n"
             "sphere { <A, B, C>, 1 }", &s);
    assert_true(fabs(s.objects[0]->a.x - 0.723583) < 5e-7);
    assert_true(fabs(s.objects[0]->a.y - 0.329979) < 5e-7);
    assert_true(fabs(s.objects[0]->a.z - 0.046072868) < 5e-10);
    csg_scene_free(&s);
    parse_err("sphere { 0, sqrt(-1) }", "t.pov:1:13: error: 'sqrt' is not defined for -1");
    parse_err("sphere { 0, rand(3) }",
              "t.pov:1:13: error: rand: 3 is not a random stream made by seed()");
}

/* ---- what the scene sees of the render ----------------------------------------------------- */

static void test_image_and_clock(void **state)
{
    (void)state;
    csg_parse_options o = quiet();
    o.image_width = 640;
    o.image_height = 480;
    o.clock = 0.25;
    csg_scene s;
    parse_ok_opts("camera { right x * image_width / image_height }\n"
                  "sphere { 0, clock * 4 }\n", &o, &s);
    assert_near(s.camera.right.x, 640.0 / 480.0);
    assert_near(s.objects[0]->r0, 1);
    csg_scene_free(&s);
    parse_ok("sphere { 0, image_width / image_height * 3 + clock }", &s); /* 320x240, 0 */
    assert_near(s.objects[0]->r0, 4);
    csg_scene_free(&s);
    /* one frame: clock_on and frame_number are 0 */
    parse_ok("#if (clock_on | frame_number != 0) sphere { 0, 2 } #else sphere { 0, 3 } #end", &s);
    assert_near(s.objects[0]->r0, 3);
    csg_scene_free(&s);
}

/* bounded_by: parsed (its objects, nested CSG too) and kept beside the object */
static void test_bounded_by(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare B = box { -2, 2 }\n"
             "sphere { 0, 1 bounded_by { object { B } } translate x }\n"
             "union { sphere { 0, 1 } sphere { x, 1 }\n"
             "  bounded_by { intersection { box { -3, 3 } sphere { 0, 4 } } } }\n", &s);
    assert_int_equal(s.object_count, 2);
    assert_int_equal(s.objects[0]->kind, CSG_OBJ_SPHERE);
    assert_near(s.objects[0]->xform.m[0][3], 1);
    assert_int_equal(s.objects[1]->child_count, 2);
    csg_scene_free(&s);
}

/* A declared object's bare name stands for a copy wherever an object may
 * (POV-Ray's Parse_Object takes an OBJECT_ID): a statement, a CSG child,
 * an array element, looks_like; any other name there is still an error. */
static void test_bare_object_names(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare A = sphere { 0, 2 }\n"
             "#declare Arr = array[2] { A, sphere { 0, 3 } }\n"
             "A\n"
             "Arr[1]\n"
             "union { A Arr[1] translate x }\n"
             "light_source { 0, 1 looks_like { A } }\n", &s);
    assert_int_equal(s.object_count, 4);
    assert_near(s.objects[0]->r0, 2);
    assert_near(s.objects[1]->r0, 3);
    assert_int_equal(s.objects[2]->child_count, 2);
    assert_near(s.objects[2]->children[0]->r0, 2);
    assert_near(s.objects[2]->xform.m[0][3], 1);
    assert_true(s.objects[3]->no_shadow); /* looks_like's copy of A */
    assert_near(s.objects[3]->r0, 2);
    csg_scene_free(&s);
    parse_err("#declare F = 3;\nunion { sphere { 0, 1 } F }\n",
              "t.pov:2:25: error: '}' expected (to close 'union' at 2:1), got 'F'");
    parse_err("#declare F = 3;\nF\n", "t.pov:2:1: error: an object or a statement expected, got 'F'");
}

/* transform { ... [inverse] } and transform NAME, as POV-Ray's
 * Parse_Transform: steps compose in order, inverse inverts the block. */
static void test_transform_blocks(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare T = transform { translate <1, 2, 3> rotate 90 * y }\n"
             "#declare U = transform { T inverse }\n"
             "#declare V = transform T\n"
             "sphere { 0, 1 transform T transform U }\n"
             "sphere { 0, 1 transform { V translate x } }\n"
             "sphere { 0, 1 transform { inverse translate <0, 0, 5> } }\n", &s);
    assert_int_equal(s.object_count, 3);
    for (int i = 0; i < 3; i++) /* T then its inverse: the identity */
        for (int j = 0; j < 4; j++)
            assert_true(fabs(s.objects[0]->xform.m[i][j] - (i == j)) < 1e-15);
    /* <0,0,0> -> translate <1,2,3> -> rotate 90 y: <3, 2, -1> -> + x */
    assert_true(fabs(s.objects[1]->xform.m[0][3] - 4) < 1e-15);
    assert_true(fabs(s.objects[1]->xform.m[1][3] - 2) < 1e-15);
    assert_true(fabs(s.objects[1]->xform.m[2][3] + 1) < 1e-15);
    assert_near(s.objects[2]->xform.m[2][3], -5);
    csg_scene_free(&s);
    parse_err("#declare F = 3;\nsphere { 0, 1 transform F }\n",
              "t.pov:2:25: error: 'F' is a float, not a transform");
    parse_err("sphere { 0, 1 transform { translate x sphere { 0, 1 } } }\n",
              "t.pov:1:39: error: '}' expected (to close 'transform' at 1:25), got 'sphere'");
}

/* clipped_by: its objects in the object's frame (transforms before it do
 * not move them, later ones and the parents' do: POV-Ray's
 * Transform_Object), several lists append, the transforms inside the
 * braces apply to every object of the list, a declared object's copy
 * copies its clips, and the linked forms share one list. */
static void test_clipped_by(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare C = sphere { 0, 1 translate y clipped_by { plane { y, 0 } } }\n"
             "union { sphere { 0, 1 translate 5 * x\n"
             "                 clipped_by { box { -1, 1 } sphere { 0, 2 } scale 2 }\n"
             "                 clipped_by { plane { x, 0 } } translate z }\n"
             "        translate y }\n"
             "object { C translate 3 * z }\n"
             "box { -1, 1 clipped_by { sphere { 0, 1.2 } } bounded_by { clipped_by } }\n"
             "box { -1, 1 bounded_by { sphere { 0, 1.2 } } clipped_by { bounded_by } }\n"
             "box { -1, 1 bounded_by { sphere { 0, 3 } } }\n"
             "sphere { 0, 1 bounded_by { sphere { 0, 2 clipped_by { plane { y, 0 } } } scale 2 }\n"
             "         translate x }\n", &s);
    assert_int_equal(s.object_count, 6);
    /* a bound's own clip moves with it: inside the braces and after */
    assert_near(s.objects[5]->bounds[0]->clips[0]->xform.m[0][0], 2);
    assert_near(s.objects[5]->bounds[0]->clips[0]->xform.m[0][3], 1);
    const csg_object *o = s.objects[0]->children[0];
    assert_int_equal(o->clip_count, 3);
    assert_int_equal(o->clips[0]->kind, CSG_OBJ_BOX);
    assert_int_equal(o->clips[1]->kind, CSG_OBJ_SPHERE);
    assert_int_equal(o->clips[2]->kind, CSG_OBJ_PLANE);
    assert_near(o->xform.m[0][3], 5);                 /* the sphere: 5 x + z + y */
    assert_near(o->clips[0]->xform.m[0][0], 2);       /* scale 2 inside the braces */
    assert_near(o->clips[1]->xform.m[0][0], 2);
    assert_near(o->clips[2]->xform.m[0][0], 1);
    for (int i = 0; i < 3; i++) {                     /* translate z, then the union's y */
        assert_near(o->clips[i]->xform.m[0][3], 0);
        assert_near(o->clips[i]->xform.m[1][3], 1);
        assert_near(o->clips[i]->xform.m[2][3], 1);
    }
    o = s.objects[1]; /* the declared copy: its clip copied, moved by 3 z */
    assert_int_equal(o->clip_count, 1);
    assert_near(o->xform.m[1][3], 1);
    assert_near(o->clips[0]->xform.m[1][3], 0);
    assert_near(o->clips[0]->xform.m[2][3], 3);
    for (int i = 2; i <= 3; i++) { /* linked either way: one list */
        assert_true(s.objects[i]->bound_is_clip);
        assert_int_equal(s.objects[i]->clip_count, 1);
        assert_ptr_equal(s.objects[i]->bounds, s.objects[i]->clips);
    }
    assert_int_equal(s.objects[4]->clip_count, 0); /* a bound alone clips nothing */
    assert_int_equal(s.objects[4]->bound_count, 1);
    assert_false(s.objects[4]->bound_is_clip);
    csg_scene_free(&s);
}

/* ---- #default, #undef, #version, #debug, #error -------------------------------------------- */

static void test_default_and_messages(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("sphere { 0, 1 }\n"
             "#default { finish { ambient 0.3 } pigment { rgb x } }\n"
             "sphere { 0, 1 }\n"
             "#declare F = finish { diffuse 0.2 }\n"
             "sphere { 0, 1 finish { F } }\n"
             "default { finish { ambient 0.5 } }\n"
             "sphere { 0, 1 texture { pigment { rgb y } } }\n", &s);
    assert_near(s.textures[s.objects[0]->texture].finish.ambient[0], 0.1);
    assert_near(s.textures[s.objects[1]->texture].finish.ambient[0], 0.3);
    assert_near(s.textures[s.objects[1]->texture].pigment.rgbft[0], 1);
    assert_near(s.textures[s.objects[2]->texture].finish.ambient[0], 0.3); /* from #default */
    assert_near(s.textures[s.objects[2]->texture].finish.diffuse, 0.2);
    assert_near(s.textures[s.objects[3]->texture].finish.ambient[0], 0.5);
    assert_near(s.textures[s.objects[3]->texture].pigment.rgbft[1], 1);
    csg_scene_free(&s);
    parse_err("#declare A = 1;\n#undef A\nsphere { 0, A }",
              "t.pov:3:13: error: undeclared identifier 'A'");
    parse_err("#declare N = 3;\n  #error concat(\"stop at \", str(N, 0, 0))",
              "t.pov:2:3: error: #error: stop at 3");
    /* #debug writes to the messages stream */
    char *buf = NULL;
    size_t size = 0;
    csg_parse_options o = quiet();
    o.messages = open_memstream(&buf, &size);
    assert_non_null(o.messages);
    parse_ok_opts("#debug concat(\"a\", \"b\\n\") #warning \"w\"\nsphere { 0, 1 }", &o, &s);
    fclose(o.messages);
    assert_string_equal(buf, "ab\nt.pov:1:27: warning: w\n");
    free(buf);
    csg_scene_free(&s);
}

/* ---- the camera: POV-Ray's fixed order --------------------------------------------------------- */

static void test_camera_order(void **state)
{
    (void)state;
    csg_scene a, b, c;
    /* since 3.5 the order does not matter: right after look_at is applied before it */
    parse_ok("camera { location <3, 4, -7> look_at 0 right x * 4 / 3 up y angle 55 }", &a);
    parse_ok("camera { angle 55 up y right x * 4 / 3 look_at 0 location <3, 4, -7> }", &b);
    for (int i = 0; i < 3; i++) {
        double *pa = &a.camera.right.x, *pb = &b.camera.right.x;
        double *da = &a.camera.direction.x, *db = &b.camera.direction.x;
        assert_near(pa[i], pb[i]);
        assert_near(da[i], db[i]);
    }
    assert_true(fabs(a.camera.right.z) > 0.1); /* turned by look_at */
    /* #version 3.1: item by item, as POV-Ray did then */
    parse_ok("#version 3.1;\ncamera { location <3, 4, -7> look_at 0 right x * 4 / 3 }", &c);
    assert_near(c.camera.right.x, 4.0 / 3.0);
    assert_near(c.camera.right.z, 0);
    csg_scene_free(&a);
    csg_scene_free(&b);
    csg_scene_free(&c);
    /* orthographic: right and up sized by |look_at - location| / |direction| */
    parse_ok("camera { orthographic location <0, 0, -10> look_at 0 }", &a);
    assert_int_equal(a.camera.projection, CSG_PROJ_ORTHOGRAPHIC);
    assert_near(a.camera.right.x, 13.3);
    assert_near(a.camera.up.y, 10);
    csg_scene_free(&a);
    parse_ok("camera { orthographic up 4 * y right 4 * x location <0, 0, -10> look_at 0 }", &a);
    assert_near(a.camera.right.x, 4);
    csg_scene_free(&a);
    /* looking down the sky: POV-Ray keeps the right vector, up = direction x right */
    parse_ok("camera { location 6 * y look_at 0 }", &a);
    assert_near(a.camera.right.x, 1.33);
    assert_near(a.camera.direction.y, -1);
    assert_near(a.camera.up.z, 1);
    csg_scene_free(&a);
    /* the bent cameras: the angle is kept as it is (direction's length
     * unchanged), spherical's vertical angle is half the horizontal one
     * unless given, POV-Ray's defaults 90 / 360 / 180 */
    static const struct {
        const char *text;
        int projection;
        double angle, h, v;
    } bent[] = {
        {"camera { cylinder 1 angle 100 look_at z }", CSG_PROJ_CYLINDER_1, 100, 360, 180},
        {"camera { cylinder 4 }", CSG_PROJ_CYLINDER_4, 90, 360, 180},
        {"camera { ultra_wide_angle angle 170 }", CSG_PROJ_ULTRA_WIDE_ANGLE, 170, 360, 180},
        {"camera { panoramic }", CSG_PROJ_PANORAMIC, 90, 360, 180},
        {"camera { spherical angle 300 }", CSG_PROJ_SPHERICAL, 300, 300, 150},
        {"camera { spherical angle 300, 120 location y }", CSG_PROJ_SPHERICAL, 300, 300, 120},
        {"camera { spherical angle 200 100 }", CSG_PROJ_SPHERICAL, 200, 200, 100},
        {"#version 3.1;\ncamera { cylinder 2 angle 30 }", CSG_PROJ_CYLINDER_2, 30, 360, 180},
    };
    for (size_t i = 0; i < sizeof bent / sizeof bent[0]; i++) {
        parse_ok(bent[i].text, &a);
        assert_int_equal(a.camera.projection, bent[i].projection);
        assert_near(a.camera.angle, bent[i].angle);
        assert_near(a.camera.h_angle, bent[i].h);
        assert_near(a.camera.v_angle, bent[i].v);
        assert_near(a.camera.direction.z, 1);
        csg_scene_free(&a);
    }
    /* a declared camera's copy takes its transforms only: an orthographic
     * one is not sized a second time (POV-Ray's only_mods) */
    parse_ok("camera { orthographic angle 15 location <20, 20, -20> right x * 4 / 3 look_at y }",
             &a);
    parse_ok("#declare C = camera { orthographic angle 15 location <20, 20, -20> right x * 4 / 3 "
             "look_at y }\ncamera { C }",
             &b);
    parse_ok("#declare C = camera { orthographic angle 15 location <20, 20, -20> right x * 4 / 3 "
             "look_at y }\ncamera { C translate 2 * x }",
             &c);
    for (int i = 0; i < 3; i++) {
        double *ra = &a.camera.right.x, *rb = &b.camera.right.x, *rc = &c.camera.right.x;
        double *ua = &a.camera.up.x, *ub = &b.camera.up.x;
        assert_near(ra[i], rb[i]);
        assert_near(ra[i], rc[i]);
        assert_near(ua[i], ub[i]);
    }
    assert_near(c.camera.location.x, 22);
    csg_scene_free(&a);
    csg_scene_free(&b);
    csg_scene_free(&c);
    /* up parallel to direction (handedness 0): POV-Ray turns right round */
    parse_ok("camera { location <-10, 10, -10> up z look_at 0 }", &a);
    assert_near(a.camera.right.x, -1.33 * sqrt(0.5));
    assert_near(a.camera.right.z, 1.33 * sqrt(0.5));
    csg_scene_free(&a);
    parse_err("camera { cylinder 5 }",
              "t.pov:1:19: error: invalid cylinder camera type 5: the types are 1 to 4");
    parse_err("camera { cylinder 1 angle -3 }",
              "t.pov:1:27: error: a camera's angle must not be negative, got -3");
    parse_err("camera { spherical angle 10, -3 }",
              "t.pov:1:30: error: a camera's vertical angle must not be negative, got -3");
    parse_err("camera { fisheye }", "t.pov:1:10: error: unsupported: 'fisheye' is not in "
                                     "csgtrace's language (see scenes/LANGUAGE.md)");
}

/* ---- patterns ----------------------------------------------------------------------------------- */

static void test_patterns(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare CM = color_map { [0 rgb 1] [0.5 rgb x] [0.5 rgb x] [1 rgb 0] }\n"
             "sphere { 0, 1 pigment { checker rgb 1 rgb 0 } }\n"
             "sphere { 0, 1 pigment { checker } }\n"
             "sphere { 0, 1 pigment { gradient 2 * y color_map { CM } frequency 2 phase 0.1 } }\n"
             "sphere { 0, 1 pigment { gradient x scale 2 } translate z }\n"
             "sphere { 0, 1 translate z pigment { gradient x } }\n"
             "#declare P = pigment { checker rgb 1 rgb 0 }\n"
             "union { sphere { 0, 1 pigment { P } } scale 3 }\n", &s);
    const csg_pigment *p = &s.textures[s.objects[0]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_CHECKER);
    assert_int_equal(p->map_count, 2);
    assert_near(p->map[0].rgbft[0], 1);
    assert_near(p->map[1].rgbft[0], 0);
    p = &s.textures[s.objects[1]->texture].pigment; /* POV-Ray's blue and green */
    assert_near(p->map[0].rgbft[2], 1);
    assert_near(p->map[1].rgbft[1], 1);
    p = &s.textures[s.objects[2]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_GRADIENT);
    assert_near(p->gradient.y, 1); /* normalised */
    assert_int_equal(p->map_count, 3); /* the repeated entry merged */
    assert_near(p->frequency, 2);
    assert_near(p->phase, 0.1);
    /* the object's transforms after the pigment move it; those before do not */
    p = &s.textures[s.objects[3]->texture].pigment;
    assert_near(p->xform.m[0][0], 2);
    assert_near(p->xform.m[2][3], 1);
    p = &s.textures[s.objects[4]->texture].pigment;
    assert_near(p->xform.m[2][3], 0);
    /* a CSG child's pigment moves with its parent */
    const csg_object *child = s.objects[5]->children[0];
    assert_near(s.textures[child->texture].pigment.xform.m[1][1], 3);
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 pigment { checker color_map { [0 rgb 1] } } }",
              "t.pov:1:33: error: a color_map needs a pattern that takes one "
              "(any but checker, brick and hexagon)");
}

/* normal { }, layered textures, texture_map, material: POV-Ray's
 * parse (Parse_Tnormal, Link_Textures, Parse_Texture, Parse_Material). */
static void test_normals_and_layers(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare A = texture { pigment { rgb x } }\n"
             "#declare B = texture { pigment { rgbt <0, 1, 0, 0.5> } normal { bumps 0.4 scale 2 } }\n"
             "#declare L = texture { A } texture { B }\n"
             "sphere { 0, 1 texture { L } }\n"
             "sphere { 0, 1 texture { A } texture { B } pigment { rgb z } }\n"
             "sphere { 0, 1 texture { gradient y texture_map { [0 A] [0.5 L] [1 pigment { rgb 1 }] } } }\n"
             "sphere { 0, 1 normal { granite bump_size 0.3 accuracy 0.05 } }\n"
             "sphere { 0, 1 material { texture { A } interior { ior 1.5 } } }\n"
             "#default { normal { dents, 0.7 } }\n"
             "sphere { 0, 1 }\n", &s);
    const csg_texture *t = &s.textures[s.objects[0]->texture];
    assert_non_null(t->under); /* B over A: the last written on top */
    assert_near(t->pigment.rgbft[4], 0.5);
    assert_true(t->normal.on);
    assert_int_equal(t->normal.kind, CSG_NORMAL_BUMPS);
    assert_near(t->normal.amount, 0.4);
    assert_near(t->normal.pattern.xform.m[0][0], 2);
    assert_near(t->under->pigment.rgbft[0], 1);
    assert_null(t->under->under);
    t = &s.textures[s.objects[1]->texture]; /* the pigment edits the top layer */
    assert_near(t->pigment.rgbft[2], 1);
    assert_near(t->under->pigment.rgbft[0], 1);
    t = &s.textures[s.objects[2]->texture];
    assert_int_equal(t->tmap_count, 3);
    assert_int_equal(t->pigment.pattern, CSG_PATTERN_GRADIENT);
    assert_non_null(t->tmap[1].texture.under);
    assert_near(t->tmap[2].texture.pigment.rgbft[1], 1);
    t = &s.textures[s.objects[3]->texture];
    assert_int_equal(t->normal.kind, CSG_NORMAL_PATTERN);
    assert_int_equal(t->normal.pattern.pattern, CSG_PATTERN_GRANITE);
    assert_near(t->normal.amount, 0.3);
    assert_near(t->normal.accuracy, 0.05);
    assert_near(s.interiors[s.objects[4]->interior].ior, 1.5);
    assert_near(s.textures[s.objects[4]->texture].pigment.rgbft[0], 1);
    t = &s.textures[s.objects[5]->texture]; /* the default texture's normal */
    assert_int_equal(t->normal.kind, CSG_NORMAL_DENTS);
    assert_near(t->normal.amount, 0.7);
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 normal { scale 2 } }",
              "t.pov:1:15: error: a normal needs a pattern (bumps, dents, ripples, waves, ...)");
    parse_err("sphere { 0, 1 normal { checker normal { bumps } } }",
              "t.pov:1:24: error: unsupported: a list of normals after checker, brick or hexagon "
              "is not in csgtrace's language (see scenes/LANGUAGE.md)");
    parse_err("sphere { 0, 1 texture { bozo } }",
              "t.pov:1:15: error: a patterned texture needs a texture_map");
    parse_err("#declare M = texture { bozo texture_map { [0 pigment { rgb 1 }] } }\n"
              "sphere { 0, 1 texture { M } texture { pigment { rgb 1 } } }",
              "t.pov:2:29: error: cannot layer over a patterned texture (texture_map)");
    parse_err("sphere { 0, 1 pigment { quilted control0 0.5 } normal { bumps control1 2 } }",
              "t.pov:1:63: error: 'control1' needs the quilted pattern");
}

/* POV-Ray 3.7's gamma and version rules (parse.cpp, tokenize.cpp): a
 * scene that reads no #version is 3.62 for them, and without assumed_gamma
 * it is in the legacy mode (no gamma handling); the first assumed_gamma
 * counts; srgb colours are decoded into the working gamma and need
 * assumed_gamma before them. */
static int output_of(const char *text, double *gamma)
{
    csg_scene s;
    parse_ok(text, &s);
    int mode = csg_output_gamma(&s, gamma);
    csg_scene_free(&s);
    return mode;
}

static void test_gamma_and_version(void **state)
{
    (void)state;
    double g;
    assert_int_equal(output_of("sphere { 0, 1 }", &g), CSG_OUTPUT_DIRECT);
    assert_int_equal(output_of("#version 3.7; sphere { 0, 1 }", &g), CSG_OUTPUT_SRGB);
    assert_int_equal(output_of("#version 3.6; sphere { 0, 1 }", &g), CSG_OUTPUT_DIRECT);
    /* the last #version counts, and 3.695 is 370 to POV-Ray */
    assert_int_equal(output_of("#version 3.7; #version 3.5; sphere { 0, 1 }", &g),
                     CSG_OUTPUT_DIRECT);
    assert_int_equal(output_of("#version 3.695; sphere { 0, 1 }", &g), CSG_OUTPUT_SRGB);
    /* reading `version` (3.7 until set) sets nothing */
    assert_int_equal(output_of("#declare V = version; sphere { 0, V }", &g), CSG_OUTPUT_DIRECT);
    assert_int_equal(output_of("#declare V = version; #version V; sphere { 0, 1 }", &g),
                     CSG_OUTPUT_SRGB);
    assert_int_equal(output_of("global_settings { assumed_gamma 1 } sphere { 0, 1 }", &g),
                     CSG_OUTPUT_SRGB);
    assert_int_equal(output_of("#version 3.6; global_settings { assumed_gamma 2.2 }", &g),
                     CSG_OUTPUT_POWER);
    assert_near(g, 2.2);
    /* within 1 % of 1 is POV-Ray's neutral curve */
    assert_int_equal(output_of("global_settings { assumed_gamma 1.005 }", &g), CSG_OUTPUT_SRGB);
    assert_int_equal(output_of("#version 3.7; global_settings { assumed_gamma srgb }", &g),
                     CSG_OUTPUT_DIRECT);
    assert_int_equal(output_of("global_settings { assumed_gamma 2.2 } "
                               "global_settings { assumed_gamma 1 }", &g), CSG_OUTPUT_POWER);
    csg_scene s;
    parse_ok("#version 3.7; global_settings { assumed_gamma 1 }\n"
             "#declare A = srgb <0.5, 0.04, 1>;\n"
             "#declare B = srgbft <0.5, 0.5, 0.5, 0.25, 0.5>;\n"
             "sphere { 0, 1 pigment { color A } }\n"
             "sphere { 0, 1 pigment { color B } }\n", &s);
    const csg_pigment *p = &s.textures[s.objects[0]->texture].pigment;
    assert_true(fabs(p->rgbft[0] - 0.21404114) < 1e-6);
    assert_true(fabs(p->rgbft[1] - 0.04 / 12.92) < 1e-7);
    assert_true(p->rgbft[2] == 1.0);
    p = &s.textures[s.objects[1]->texture].pigment;
    assert_near(p->rgbft[3], 0.25); /* filter and transmit as they are */
    assert_near(p->rgbft[4], 0.5);
    assert_true(csg_version_v37(&s));
    csg_scene_free(&s);
    parse_ok("#version 3.7; global_settings { assumed_gamma 2 }\n"
             "sphere { 0, 1 pigment { srgb 0.5 } }\n", &s);
    p = &s.textures[s.objects[0]->texture].pigment;
    assert_true(fabs(p->rgbft[0] - sqrt(0.21404114)) < 1e-6);
    csg_scene_free(&s);
    parse_err("#version 3.7; sphere { 0, 1 pigment { srgb 0.5 } }",
              "t.pov:1:39: error: 'srgb' colors need assumed_gamma set before them "
              "(in global_settings), as in POV-Ray");
    parse_err("global_settings { assumed_gamma 0 }",
              "t.pov:1:33: error: assumed_gamma must be > 0, got 0");
}

/* The noise patterns: POV-Ray's defaults (maps, waves, turbulence), the
 * modifiers, the noise generator of the pigment, of global_settings and
 * of #version, and the errors of each keyword at its place. */
/* brick, hexagon, spiral1 and spiral2 (POV-Ray's Parse_Pattern and
 * Parse_Blend_List): the block patterns' lists of colours, pigments or
 * textures at values 0, 1, 2, their defaults, unwaved; brick's size and
 * mortar (a float, less 2e-10), kept by a brick identifier; the spirals'
 * arms and triangle wave; and their errors. */
static void test_block_and_spiral_patterns(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare B = pigment { brick brick_size <1, 2, 3> mortar 0.3 }\n"
             "sphere { 0, 1 pigment { brick } }\n"
             "sphere { 0, 1 pigment { B brick rgb 1 } }\n"
             "sphere { 0, 1 pigment { hexagon rgb 0.1, rgb 0.2 } }\n"
             "sphere { 0, 1 pigment { hexagon pigment { rgb 1 } pigment { bozo } } }\n"
             "sphere { 0, 1 pigment { spiral1 5.9 } normal { spiral2 -3, 0.7 } }\n"
             "sphere { 0, 1 texture { brick texture { pigment { rgb 1 } } } }\n",
             &s);
    const csg_pigment *p = &s.textures[s.objects[0]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_BRICK);
    assert_near(p->frequency, 0); /* POV-Ray: a block pattern is not waved */
    assert_near(p->brick_size.x, 8), assert_near(p->brick_size.y, 3);
    assert_near(p->brick_size.z, 4.5);
    assert_near(p->mortar, 0.5); /* (float)(0.5 - 2e-10) */
    assert_int_equal(p->map_count, 2);
    assert_near(p->map[0].rgbft[0], 0.5), assert_near(p->map[1].rgbft[1], 0.15);
    p = &s.textures[s.objects[1]->texture].pigment; /* B's size and mortar kept */
    assert_near(p->brick_size.z, 3);
    assert_near(p->mortar, (double)(float)(0.3 - 2e-10));
    assert_near(p->map[0].rgbft[0], 1), assert_near(p->map[1].rgbft[0], 0.6);
    p = &s.textures[s.objects[2]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_HEXAGON);
    assert_int_equal(p->map_count, 3);
    assert_near(p->map[1].rgbft[0], 0.2), assert_near(p->map[2].value, 2);
    assert_near(p->map[2].rgbft[0], 1); /* POV-Ray's third: red */
    p = &s.textures[s.objects[3]->texture].pigment;
    assert_int_equal(p->pmap_count, 3);
    assert_int_equal(p->pmap[1].pigment.pattern, CSG_PATTERN_BOZO);
    assert_near(p->pmap[2].value, 2);
    const csg_texture *t = &s.textures[s.objects[4]->texture];
    assert_int_equal(t->pigment.pattern, CSG_PATTERN_SPIRAL1);
    assert_int_equal(t->pigment.arms, 5); /* truncated, as POV-Ray's short */
    assert_int_equal(t->pigment.wave, CSG_WAVE_TRIANGLE);
    assert_int_equal(t->normal.pattern.pattern, CSG_PATTERN_SPIRAL2);
    assert_int_equal(t->normal.pattern.arms, -3);
    assert_near(t->normal.amount, 0.7);
    t = &s.textures[s.objects[5]->texture];
    assert_int_equal(t->pigment.pattern, CSG_PATTERN_BRICK);
    assert_int_equal(t->tmap_count, 2);
    assert_near(t->tmap[1].value, 1);
    csg_scene_free(&s);
    parse_ok("sphere { 0, 1 normal { hexagon 1.6 scale 2 } }", &s);
    const csg_normal *n = &s.textures[s.objects[0]->texture].normal;
    assert_int_equal(n->pattern.pattern, CSG_PATTERN_HEXAGON);
    assert_near(n->amount, 1.6);
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 pigment { bozo mortar 0.2 } }",
              "t.pov:1:30: error: 'mortar' needs the brick pattern");
    parse_err("sphere { 0, 1 normal { hexagon brick_size 2 } }",
              "t.pov:1:32: error: 'brick_size' needs the brick pattern");
    parse_err("sphere { 0, 1 pigment { brick mortar 1e300 } }",
              "t.pov:1:38: error: mortar out of range, got 1e+300");
    parse_err("sphere { 0, 1 pigment { spiral1 } }",
              "t.pov:1:33: error: an expression expected, got '}'");
    parse_err("sphere { 0, 1 pigment { spiral2 40000 } }",
              "t.pov:1:33: error: the number of arms must be from -32768 to 32767, got 40000");
    parse_err("sphere { 0, 1 pigment { hexagon color_map { [0 rgb 1] } } }",
              "t.pov:1:33: error: a color_map needs a pattern that takes one "
              "(any but checker, brick and hexagon)");
    parse_err("sphere { 0, 1 texture { brick texture_map { [0 pigment { rgb 1 }] } } }",
              "t.pov:1:31: error: a texture_map needs a pattern that takes one "
              "(any but checker, brick and hexagon)");
}

/* interior_texture { }: an entry of its own (1 + its index), layered by a
 * second one, moved by the transforms after it with its object, on a
 * declared object's copy; POV-Ray's rule: the object needs a texture. */
static void test_interior_texture(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare O = sphere { 0, 1 texture { pigment { rgb 1 } }\n"
             "                       interior_texture { pigment { rgb <1, 0, 0> } } }\n"
             "object { O interior_texture { pigment { bozo } } translate x }\n"
             "union { sphere { 0, 1 } sphere { x, 1 } pigment { rgb 0.5 }\n"
             "        interior_texture { finish { phong 1 } } }\n",
             &s);
    const csg_object *o = s.objects[0];
    assert_true(o->interior_texture > 0);
    const csg_texture *t = &s.textures[o->interior_texture - 1];
    assert_int_equal(t->pigment.pattern, CSG_PATTERN_BOZO); /* the top layer */
    assert_near(t->pigment.xform.m[0][3], 1);               /* moved with the object */
    assert_non_null(t->under);
    assert_near(t->under->pigment.rgbft[0], 1);
    o = s.objects[1];
    assert_true(o->interior_texture > 0);
    assert_near(s.textures[o->interior_texture - 1].finish.phong, 1);
    assert_int_equal(o->children[0]->interior_texture, 0); /* inherited (flatten.c) */
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 interior_texture { pigment { rgb 1 } } }",
              "t.pov:1:1: error: interior_texture needs a texture on the sphere itself");
    parse_err("sphere { 0, 1 pigment { rgb 1 } interior_texture pigment { rgb 1 } }",
              "t.pov:1:50: error: '{' expected after 'texture', got 'pigment'");
}

/* pigment_pattern { PIGMENT_BODY }: the pigment (black to start with, as
 * POV-Ray's Create_Pigment, or an identifier's) kept apart; the
 * black-to-white map; in a normal with its amount; errors. */
static void test_pigment_pattern(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#default { pigment { rgb 1 } }\n"
             "#declare P = pigment { bozo scale 2 }\n"
             "sphere { 0, 1 pigment { pigment_pattern { P translate x }\n"
             "                        color_map { [0 rgb 1] [1 rgb 0] } } }\n"
             "sphere { 0, 1 pigment { pigment_pattern { } } normal { pigment_pattern { P } 3 } }\n",
             &s);
    const csg_pigment *p = &s.textures[s.objects[0]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_PIGMENT_PATTERN);
    assert_int_equal(p->pattern_pigment->pattern, CSG_PATTERN_BOZO);
    assert_near(p->pattern_pigment->xform.m[0][3], 1);
    assert_near(p->map[0].rgbft[0], 1);
    const csg_texture *t = &s.textures[s.objects[1]->texture];
    assert_int_equal(t->pigment.pattern_pigment->pattern, CSG_PATTERN_PLAIN);
    assert_near(t->pigment.pattern_pigment->rgbft[0], 0); /* black, not the default */
    assert_near(t->pigment.map[1].rgbft[0], 1);
    assert_int_equal(t->normal.pattern.pattern, CSG_PATTERN_PIGMENT_PATTERN);
    assert_near(t->normal.amount, 3);
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 pigment { pigment_pattern bozo } }",
              "t.pov:1:41: error: '{' expected after 'pigment_pattern', got 'bozo'");
    parse_err("sphere { 0, 1 pigment { pigment_pattern { bozo phong 1 } } }",
              "t.pov:1:48: error: '}' expected (to close 'pigment' at 1:25), got 'phong'");
}

/* finish { irid { } } and global_settings { irid_wavelength }: POV-Ray's
 * values in single precision, defaults, the turbulence vector's x; flattened
 * into the material and the shading; errors. */
static void test_irid(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("global_settings { irid_wavelength rgb <0.25, 0.18, 0.14> noise_generator 3 }\n"
             "sphere { 0, 1 finish { irid { 0.3 thickness 0.7 turbulence <0.6, 2, 3> } } }\n"
             "sphere { 0, 1 finish { irid { 0.5 } } }\n", &s);
    assert_near(s.globals.irid_wavelength[0], (double)0.25f);
    assert_near(s.globals.irid_wavelength[2], (double)0.14f);
    const csg_finish *f = &s.textures[s.objects[0]->texture].finish;
    assert_near(f->irid, (double)0.3f);
    assert_near(f->irid_thickness, (double)0.7f);
    assert_near(f->irid_turbulence, (double)0.6f);
    f = &s.textures[s.objects[1]->texture].finish;
    assert_near(f->irid, 0.5);
    assert_near(f->irid_thickness, 0), assert_near(f->irid_turbulence, 0);
    csg_scene_free(&s);
    parse_ok("sphere { 0, 1 }", &s); /* POV-Ray's default wavelengths */
    assert_near(s.globals.irid_wavelength[1], (double)0.52f);
    assert_near(s.textures[s.objects[0]->texture].finish.irid, 0);
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 finish { irid { 0.3 phong 1 } } }",
              "t.pov:1:35: error: '}' expected (to close 'irid' at 1:24), got 'phong'");
    parse_err("sphere { 0, 1 finish { irid { 1e39 } } }",
              "t.pov:1:31: error: irid out of range, got 1e+39");
    parse_err("sphere { 0, 1 finish { irid 0.3 } }",
              "t.pov:1:29: error: '{' expected after 'irid', got '0.3'");
}

static void test_noise_patterns(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("sphere { 0, 1 pigment { wood } }\n"
             "sphere { 0, 1 pigment { marble turbulence 0.5 octaves 3 omega 0.6 lambda 2.5 } }\n"
             "sphere { 0, 1 pigment { agate agate_turb 0.3 noise_generator 3 } }\n"
             "sphere { 0, 1 pigment { spotted poly_wave 3 } }\n"
             "sphere { 0, 1 pigment { bozo turbulence <1, 2, 3> sine_wave } }\n", &s);
    const csg_pigment *p = &s.textures[s.objects[0]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_WOOD);
    assert_int_equal(p->wave, CSG_WAVE_TRIANGLE); /* POV-Ray's default for wood */
    assert_false(p->turb.on);
    assert_int_equal(p->map_count, 2);
    assert_near(p->map[0].value, 0.6);
    assert_int_equal(csg_noise_of(&s, p), 2); /* #version 3.7 */
    p = &s.textures[s.objects[1]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_MARBLE);
    assert_true(p->turb.on);
    assert_near(p->turb.amount.x, 0.5);
    assert_near(p->turb.amount.z, 0.5); /* a float is a vector */
    assert_int_equal(p->turb.octaves, 3);
    assert_near(p->turb.omega, 0.6);
    assert_near(p->turb.lambda, 2.5);
    p = &s.textures[s.objects[2]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_AGATE);
    assert_true(p->turb.on); /* agate always has its turbulence */
    assert_int_equal(p->turb.octaves, 6);
    assert_near(p->agate_turb, 0.3);
    assert_int_equal(csg_noise_of(&s, p), 3);
    p = &s.textures[s.objects[3]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_BOZO);
    assert_near(p->map[1].rgbft[0], 1); /* spotted: the black-to-white map */
    assert_int_equal(p->wave, CSG_WAVE_POLY);
    assert_near(p->exponent, 3);
    p = &s.textures[s.objects[4]->texture].pigment;
    assert_int_equal(p->map_count, 6); /* bozo's own map */
    assert_near(p->turb.amount.y, 2);
    assert_int_equal(p->wave, CSG_WAVE_SINE);
    csg_scene_free(&s);
    parse_ok("#declare P = pigment { bozo noise_generator 1 }\n"
             "sphere { 0, 1 pigment { P noise_generator 2 } }\n", &s);
    assert_int_equal(csg_noise_of(&s, &s.textures[s.objects[0]->texture].pigment), 3);
    csg_scene_free(&s);
    parse_ok("#version 3.1;\nsphere { 0, 1 pigment { bozo } }\n", &s);
    assert_int_equal(csg_noise_of(&s, &s.textures[s.objects[0]->texture].pigment), 1);
    csg_scene_free(&s);
    parse_ok("#version 3.1;\nglobal_settings { noise_generator 3 }\n"
             "sphere { 0, 1 pigment { granite } }\n", &s);
    assert_int_equal(csg_noise_of(&s, &s.textures[s.objects[0]->texture].pigment), 3);
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 pigment { bozo noise_generator 4 } }",
              "t.pov:1:46: error: noise_generator must be 0, 1, 2 or 3, got 4");
    parse_err("global_settings { noise_generator 0 }",
              "t.pov:1:35: error: noise_generator must be 1, 2 or 3, got 0");
    parse_err("sphere { 0, 1 pigment { wood turbulence 0.2 octaves -2 } }",
              "t.pov:1:53: error: octaves must be from 1 to 10, got -2");
    parse_err("sphere { 0, 1 pigment { wood octaves 11 } }",
              "t.pov:1:38: error: octaves must be from 1 to 10, got 11");
    parse_err("sphere { 0, 1 pigment { bozo agate_turb 0.5 } }",
              "t.pov:1:41: error: agate_turb needs the agate pattern");
    parse_ok("#declare P = pigment { bozo scale 2 }\n"
             "sphere { 0, 1 pigment { gradient y pigment_map { [0 P] [0.5, rgb x] [1 wood "
             "pigment_map { [0 rgb 1] [1 P rotate y] }] } } }\n", &s);
    p = &s.textures[s.objects[0]->texture].pigment;
    assert_int_equal(p->pmap_count, 3);
    assert_int_equal(p->pmap[0].pigment.pattern, CSG_PATTERN_BOZO);
    assert_near(p->pmap[0].pigment.xform.m[0][0], 2);
    assert_int_equal(p->pmap[1].pigment.pattern, CSG_PATTERN_PLAIN);
    assert_near(p->pmap[1].value, 0.5);
    assert_int_equal(p->pmap[2].pigment.pmap_count, 2); /* nested */
    csg_scene_free(&s);
    /* a 2-vector where a vector is expected: POV-Ray's z = 0 */
    parse_ok("sphere { 0, 1 pigment { bozo translate <1, 2> } }\n", &s);
    p = &s.textures[s.objects[0]->texture].pigment;
    assert_near(p->xform.m[1][3], 2);
    assert_near(p->xform.m[2][3], 0);
    csg_scene_free(&s);
    parse_ok("sphere { 0, 1 pigment { crackle } }\n"
             "sphere { 0, 1 pigment { crackle solid metric <1, 5, 5> form x offset 0.5 } }\n", &s);
    p = &s.textures[s.objects[0]->texture].pigment;
    assert_int_equal(p->pattern, CSG_PATTERN_CRACKLE);
    assert_near(p->crackle.form.x, -1); /* POV-Ray's defaults */
    assert_near(p->crackle.form.y, 1);
    assert_near(p->crackle.metric, 2);
    assert_false(p->crackle.solid);
    p = &s.textures[s.objects[1]->texture].pigment;
    assert_true(p->crackle.solid);
    assert_near(p->crackle.metric, 1); /* a vector's x */
    assert_near(p->crackle.form.y, 0);
    assert_near(p->crackle.offset, 0.5);
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 pigment { bozo solid } }",
              "t.pov:1:30: error: 'solid' needs the crackle pattern");
    parse_err("sphere { 0, 1 pigment { crackle metric 0 } }",
              "t.pov:1:40: error: metric must be > 0, got 0");
    parse_err("sphere { 0, 1 pigment { checker pigment_map { [0 rgb 1] } } }",
              "t.pov:1:33: error: a pigment_map needs a pattern that takes one "
              "(any but checker, brick and hexagon)");
    parse_err("sphere { 0, 1 pigment { bozo pigment_map { } } }",
              "t.pov:1:44: error: '[' expected (a pigment_map entry), got '}'");
    parse_err("sphere { 0, 1 pigment { bozo pigment_map { [0 rgb 1 } } }",
              "t.pov:1:53: error: ']' expected (to close '[' at 1:44), got '}'");
    parse_err("sphere { 0, 1 pigment { marble turbulence } }",
              "t.pov:1:43: error: an expression expected, got '}'");
}

/* ---- declarations that use unsupported constructs ----------------------------------------------- */

static void test_unusable_declarations(void **state)
{
    (void)state;
    csg_scene s;
    /* declared and never used: no error */
    parse_ok("#declare T = texture { pigment { rgb 1 } finish { emission 0.3 } }\n"
             "#declare U = texture { T finish { phong 1 } }\n"
             "#declare F = function(x) { x * 2 }\n"
             "#declare N = 5;\n"
             "sphere { 0, N }\n", &s);
    assert_near(s.objects[0]->r0, 5);
    csg_scene_free(&s);
    parse_err("#declare T = texture { pigment { rgb 1 } finish { emission 0.3 } }\n"
              "#declare U = texture { T finish { phong 1 } }\n"
              "sphere { 0, 1 texture { U } }",
              "t.pov:3:25: error: unsupported: 'U' (declared at t.pov:2:1) needs 'emission' "
              "(t.pov:1:51), which is not in csgtrace's language (see scenes/LANGUAGE.md)");
}

/* ---- limits -------------------------------------------------------------------------------------- */

static void test_limits(void **state)
{
    (void)state;
    parse_err("#macro F(N) F(N + 1) #end\nF(0)",
              "t.pov:1:13: error: macro calls nested deeper than 100 (a recursion that never ends?) "
              "(in macro 'F' called at t.pov:1:13 (99 times), in macro 'F' called at t.pov:2:1)");
    csg_parse_options o = quiet();
    o.max_tokens = 10000;
    const char *m = parse_fail_opts("#while (1) #end", &o);
    assert_non_null(strstr(m, "more than 10000 tokens read: a loop that never ends?"));
    /* a macro that calls itself twice: bounded by the token budget */
    m = parse_fail_opts("#macro T(N) #if (N < 60) T(N + 1) T(N + 1) #end #end\nT(0)", &o);
    if (!strstr(m, "tokens read"))
        fail_msg("%s", m);
    char *deep = malloc(300 * 8 + 64);
    assert_non_null(deep);
    deep[0] = '\0';
    for (int i = 0; i < 300; i++)
        strcat(deep, "#if (1) ");
    m = parse_fail_opts(deep, &o);
    assert_non_null(strstr(m, "more than 256 '#if', '#while', '#for' or '#switch' open at once"));
    free(deep);
    parse_err("#if (1) sphere { 0, 1 }",
              "t.pov:1:24: error: '#end' expected (to close '#if' at 1:1), got end of file");
    parse_err("#end", "t.pov:1:1: error: '#end' without a matching '#if', '#while', '#for', "
                      "'#switch' or '#macro'");
    parse_err("#else", "t.pov:1:1: error: '#else' without a matching '#if'");
    parse_err("#break", "t.pov:1:1: error: '#break' outside a loop, a '#switch' or a macro");
    parse_err("#foo", "t.pov:1:1: error: unknown directive '#foo'");
    parse_err("#switch (1) sphere { 0, 1 }",
              "t.pov:1:13: error: '#case' or '#range' expected after '#switch'");
}

/* ---- the front end's reliability --------------------------------------------------------------- */

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void test_reliability(void **state)
{
    (void)state;
    csg_scene s;
    /* a UTF-8 byte-order mark is not a character of the scene */
    parse_ok("\xef\xbb\xbfsphere { 0, 1 }", &s);
    csg_scene_free(&s);
    parse_err("\xef\xbb\xbf  $", "t.pov:1:3: error: unexpected character '$'");
    /* a long file name does not cut the reason */
    char name[3000];
    memset(name, 'a', sizeof name - 5);
    memcpy(name + sizeof name - 5, ".pov", 5);
    csg_diag d;
    memset(&d, 0, sizeof d);
    assert_false(csg_parse_string(name, "sphere { 0, -1 }", 16, &s, &d));
    assert_non_null(strstr(d.message, ":1:13: error: sphere radius must be > 0, got -1"));
    assert_int_equal(strncmp(d.message, name, 100), 0);

    char dir[] = "/tmp/csg_rel_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char fifo[128], text[512], inc[128], want[1024];
    /* #include reads regular files only: a FIFO, a device, a folder refused */
    snprintf(fifo, sizeof fifo, "%s/pipe.inc", dir);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    snprintf(text, sizeof text, "#include \"%s\"", fifo);
    snprintf(want, sizeof want,
             "t.pov:1:1: error: cannot read include file '%s': not a regular file (a FIFO)", fifo);
    parse_err(text, want);
    parse_err("#include \"/dev/zero\"", "t.pov:1:1: error: cannot read include file '/dev/zero': "
                                        "not a regular file (a character device)");
    snprintf(text, sizeof text, "#include \"%s\"", dir);
    snprintf(want, sizeof want,
             "t.pov:1:1: error: cannot read include file '%s': not a regular file (a directory)", dir);
    parse_err(text, want);
    /* a file that is not a scene file: its content is never shown */
    snprintf(inc, sizeof inc, "%s/secret.txt", dir);
    write_text(inc, "root:x:0:0:secret\n");
    snprintf(text, sizeof text, "#include \"%s\"", inc);
    snprintf(want, sizeof want,
             "%s:1:1: error: '%s' is not a scene file (it has no .pov, .inc, .mcr or .map name): "
             "its content is not shown (in '%s' included at t.pov:1:1)", inc, inc, inc);
    parse_err(text, want);
    /* an error inside a macro of an include: the place and the chain */
    snprintf(inc, sizeof inc, "%s/lib.inc", dir);
    write_text(inc, "#macro Ball(R)\n  sphere { 0, R }\n#end\n");
    snprintf(text, sizeof text, "#include \"%s\"\nBall(1)\nBall(-2)", inc);
    snprintf(want, sizeof want,
             "%s:2:15: error: sphere radius must be > 0, got -2 (in macro 'Ball' called at t.pov:3:1)",
             inc);
    parse_err(text, want);
    unlink(inc);
    snprintf(inc, sizeof inc, "%s/secret.txt", dir);
    unlink(inc);
    unlink(fifo);
    rmdir(dir);
}

/* Every value is finite and every conversion to int in range (#39): val()
 * of a text strtod reads as NaN or infinity is an error at the function,
 * as is any function's result that is not finite; dimension_size of a
 * dimension far outside int is 0 (UBSan: no cast out of range). */
static void test_numbers_finite(void **state)
{
    (void)state;
    parse_err("#declare A = val(\"nan\");",
              "t.pov:1:14: error: val(\"nan\"): not a finite number");
    parse_err("#declare A = 1 + val(\"inf\");",
              "t.pov:1:18: error: val(\"inf\"): not a finite number");
    parse_err("sphere { 0, val(\"-infinity\") }",
              "t.pov:1:13: error: val(\"-infinity\"): not a finite number");
    parse_err("light_source { <val(\"NaN\"), 1, 1>, 1 }",
              "t.pov:1:17: error: val(\"NaN\"): not a finite number");
    parse_err("#declare A = val(\"1e999\");",
              "t.pov:1:14: error: val(\"1e999\"): not a finite number");
    parse_err("#declare V = vcross(<1e200, 0, 0>, <0, 1e200, 0>);",
              "t.pov:1:14: error: arithmetic overflow: the result is not a finite number");
    parse_err("#declare V = vlength(<1e200, 1e200, 0>);",
              "t.pov:1:14: error: arithmetic overflow: the result is not a finite number");
    /* a pattern's transform whose product overflows or collapses an axis,
     * at the transform that makes it so (each step alone is accepted) */
    static const char *const patterns[][2] = {
        {"sphere { 0, 1 pigment { checker scale 1e300 scale 1e300 } }", "t.pov:1:45"},
        {"sphere { 0, 1 pigment { checker scale <1e-200, 1, 1> scale <1e-200, 1, 1> } }",
         "t.pov:1:54"},
        {"sphere { 0, 1 normal { bumps scale 1e300 scale 1e300 } }", "t.pov:1:42"},
        {"sphere { 0, 1 pigment { bozo scale 1e300 } scale 1e300 }", "t.pov:1:44"},
    };
    parse_err("sky_sphere { pigment { gradient y } scale 1e300 rotate 30*x scale 1e300 }",
              "t.pov:1:61: error: the sky_sphere's transformation overflows or collapses an axis "
              "here (an entry is not finite, or an axis is scaled to 0)");
    parse_err("sky_sphere { pigment { bozo } scale <1, 1e-200, 1> scale <1, 1e-200, 1> }",
              "t.pov:1:52: error: the sky_sphere's transformation overflows or collapses an axis "
              "here (an entry is not finite, or an axis is scaled to 0)");
    parse_err("fog { distance 3 rgb 1 scale 1e300 scale 1e300 }",
              "t.pov:1:36: error: the fog's up vector overflows or collapses to 0 here");
    parse_err("fog { distance 3 rgb 1 up <1e300, 1e300, 0> }",
              "t.pov:1:1: error: fog up vector is too long: its length overflows");
    for (size_t i = 0; i < sizeof patterns / sizeof patterns[0]; i++) {
        char want[256];
        snprintf(want, sizeof want,
                 "%s: error: the pattern's transformation overflows or collapses an axis here "
                 "(an entry is not finite, or an axis is scaled to 0)",
                 patterns[i][1]);
        parse_err(patterns[i][0], want);
    }
    csg_scene s;
    parse_ok("#declare A = val(\"2.5\");\nsphere { 0, A }", &s);
    assert_near(s.objects[0]->r0, 2.5);
    csg_scene_free(&s);
    /* any #version reads; its int form is clamped (the fuzzer's
     * #version -5555555555 converted out of range) */
    static const char *const versions[] = {"-5555555555", "1e300", "-1e300", "21474836.47"};
    for (size_t i = 0; i < sizeof versions / sizeof versions[0]; i++) {
        char text[128];
        snprintf(text, sizeof text, "#version %s;\nsphere { 0, 1 }", versions[i]);
        parse_ok(text, &s);
        assert_true(csg_version_v37(&s) == (versions[i][0] != '-'));
        csg_scene_free(&s);
    }
    parse_ok("#declare A = array[3][2];\n"
             "#if (dimension_size(A, 1e30) != 0 | dimension_size(A, -2147483648) != 0 |\n"
             "     dimension_size(A, -1e300) != 0 | dimension_size(A, 2147483648) != 0 |\n"
             "     dimension_size(A, 2) != 2 | dimension_size(A, 1.5) != 3)\n"
             "  #error \"dimension_size\"\n#end\nsphere { 0, 1 }",
             &s);
    csg_scene_free(&s);
}

/* POV-Ray's reflection in a finish: one colour (constant: the workers'
 * old path), a block MIN [, MAX] with its options, fresnel with MIN = MAX
 * (MIN becomes 0), the finish-level fresnel refused, exponents > 0. */
static void test_reflection_block(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("sphere { 0, 1 finish { reflection 0.3 } }\n"
             "sphere { 0, 1 finish { reflection { rgb <0.1, 0.2, 0.3> } } }\n"
             "sphere { 0, 1 finish { reflection { 0.1, 0.8 falloff 2 exponent 3 metallic } } }\n"
             "sphere { 0, 1 finish { reflection { 0.5 fresnel on } conserve_energy } }\n"
             "sphere { 0, 1 finish { reflection { 0.1 0.6 metallic 0.25 } reflection 0.4 } }\n"
             "sphere { 0, 1 finish { reflection_exponent 2 } }\n",
             &s);
    const csg_finish *f[6];
    for (int i = 0; i < 6; i++)
        f[i] = &s.textures[s.objects[i]->texture].finish;
    assert_false(f[0]->reflection_variable);
    assert_near(f[0]->reflection[1], 0.3);
    assert_false(f[1]->reflection_variable);
    assert_near(f[1]->reflection[2], 0.3);
    assert_true(f[2]->reflection_variable);
    assert_near(f[2]->reflection_min[0], 0.1);
    assert_near(f[2]->reflection[0], 0.8);
    assert_near(f[2]->reflection_falloff, 2);
    assert_near(f[2]->reflection_exponent, 3);
    assert_near(f[2]->reflection_metallic, 1);
    assert_true(f[3]->reflection_variable && f[3]->reflection_fresnel && f[3]->conserve_energy);
    assert_near(f[3]->reflection_min[0], 0); /* (POV-Ray: fresnel with MIN = MAX) */
    assert_near(f[3]->reflection[0], 0.5);
    assert_true(f[4]->reflection_variable); /* (metallic stays after `reflection 0.4`) */
    assert_near(f[4]->reflection_min[0], 0.4);
    assert_near(f[4]->reflection[0], 0.4);
    assert_true(f[5]->reflection_variable);
    assert_near(f[5]->reflection_exponent, 2);
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 finish { reflection { 0.1, 0.5 exponent 0 } } }",
              "t.pov:1:55: error: reflection exponent must be > 0, got 0");
    parse_err("sphere { 0, 1 finish { reflection_exponent -1 } }",
              "t.pov:1:44: error: reflection_exponent must be > 0, got -1");
    parse_err("sphere { 0, 1 finish { fresnel } }",
              "t.pov:1:24: error: unsupported: the finish's 'fresnel' (outside a reflection block) "
              "is not in csgtrace's language (see scenes/LANGUAGE.md)");
    parse_err("sphere { 0, 1 finish { reflection { 0.1, 0.5 bogus } } }",
              "t.pov:1:46: error: '}' expected (to close 'reflection' at 1:24), got 'bogus'");
}

/* A fog's colour may be any colour expression (POV-Ray's CASE_COLOUR: an
 * identifier, a sum); a bare float stays its distance; `spherical` (a
 * camera's word, and a pattern csgtrace does not have) in a pigment is
 * unsupported, not a syntax error. */
/* crand in a finish (0 by default); average with its pigment_map or
 * texture_map (POV-Ray's rules: a map it must have, no color_map, not in
 * a normal, which would need normal_map). */
static void test_crand_and_average(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("sphere { 0, 1 }\nsphere { 0, 1 finish { crand 0.25 } }", &s);
    assert_near(s.textures[s.objects[0]->texture].finish.crand, 0);
    assert_near(s.textures[s.objects[1]->texture].finish.crand, 0.25);
    csg_scene_free(&s);
    parse_ok("sphere { 0, 1 pigment { average turbulence 0.5 pigment_map { [1 rgb x] "
             "[3 gradient y] } scale 2 } }",
             &s);
    const csg_pigment *pig = &s.textures[s.objects[0]->texture].pigment;
    assert_int_equal(pig->pattern, CSG_PATTERN_AVERAGE);
    assert_int_equal(pig->pmap_count, 2);
    assert_near(pig->pmap[1].value, 3);
    assert_int_equal(pig->pmap[1].pigment.pattern, CSG_PATTERN_GRADIENT);
    assert_true(pig->turb.on);
    csg_scene_free(&s);
    parse_ok("sphere { 0, 1 texture { average texture_map { [1 pigment { rgb 1 }] "
             "[2 pigment { rgb x }] } } }",
             &s);
    const csg_texture *t = &s.textures[s.objects[0]->texture];
    assert_int_equal(t->pigment.pattern, CSG_PATTERN_AVERAGE);
    assert_int_equal(t->tmap_count, 2);
    csg_scene_free(&s);
    /* in an average's map the weight may be left out: 1 (POV-Ray's
     * Allow_Float(1.0)); the entry then starts with its pigment */
    parse_ok("#declare W = 3; #declare P = pigment { rgb y }\n"
             "sphere { 0, 1 pigment { average pigment_map { [gradient y] [W rgb 1] [P] "
             "[rgb x] } } }\n"
             "sphere { 0, 1 texture { average texture_map { [pigment { P }] [2, P] } } }",
             &s);
    pig = &s.textures[s.objects[0]->texture].pigment;
    assert_int_equal(pig->pmap_count, 4);
    assert_near(pig->pmap[0].value, 1);
    assert_int_equal(pig->pmap[0].pigment.pattern, CSG_PATTERN_GRADIENT);
    assert_near(pig->pmap[1].value, 3);
    assert_near(pig->pmap[2].value, 1);
    assert_near(pig->pmap[2].pigment.rgbft[1], 1);
    assert_near(pig->pmap[3].value, 1);
    t = &s.textures[s.objects[1]->texture];
    assert_near(t->tmap[0].value, 1);
    assert_near(t->tmap[1].value, 2);
    csg_scene_free(&s);
    parse_err("sphere { 0, 1 pigment { bozo pigment_map { [rgb 1] } } }",
              "t.pov:1:45: error: an expression expected, got 'rgb'");
    parse_err("sphere { 0, 1 pigment { average } }",
              "t.pov:1:33: error: average needs a pigment_map");
    parse_err("sphere { 0, 1 pigment { average color_map { [0 rgb 1] } } }",
              "t.pov:1:33: error: average takes a pigment_map, not a color_map");
    parse_err("sphere { 0, 1 normal { average } }",
              "t.pov:1:24: error: unsupported: 'average' in a normal is not in csgtrace's "
              "language (see scenes/LANGUAGE.md)");
    parse_err("sphere { 0, 1 texture { average } }",
              "t.pov:1:15: error: a patterned texture needs a texture_map");
    parse_err("sphere { 0, 1 finish { crand } }",
              "t.pov:1:30: error: an expression expected, got '}'");
}

static void test_fog_colour_expression(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok("#declare Blue = rgb <0, 0, 1>;\n#declare Grey = rgb 0.5;\n"
             "fog { Blue + Grey distance 700 }\nfog { 30 rgb 1 }",
             &s);
    assert_int_equal(s.fog_count, 2);
    assert_near(s.fogs[0].rgbft[0], 0.5);
    assert_near(s.fogs[0].rgbft[2], 1.5);
    assert_near(s.fogs[0].distance, 700);
    assert_near(s.fogs[1].distance, 30);
    csg_scene_free(&s);
    /* a message is one line whatever it quotes: a control character in a
     * scene's string (here a file name) is escaped (fuzz finding) */
    parse_err("#include \"no\\nsuch\ttab.inc\"",
              "t.pov:1:1: error: cannot read include file 'no\\nsuch\\ttab.inc': No such file or "
              "directory");
    parse_err("fog { <1, 2> }", "t.pov:1:7: error: a fog's distance or colour expected, got a 2-component vector");
    parse_err("sphere { 0, 1 pigment { spherical } }",
              "t.pov:1:25: error: unsupported: 'spherical' is not in csgtrace's language (see "
              "scenes/LANGUAGE.md)");
}

/* ---- data files: #fopen #read #write #fclose, file_exists ---------------------------------- */

/* A scene parsed as `dir`/t.pov (its folder: where #fopen reads). */
static bool parse_in(const char *dir, const char *text, csg_scene *s, csg_diag *d)
{
    char name[256];
    csg_parse_options o = quiet();
    snprintf(name, sizeof name, "%s/t.pov", dir);
    memset(d, 0, sizeof *d);
    return csg_parse_string_opts(name, text, strlen(text), &o, s, d);
}

static void test_file_io(void **state)
{
    (void)state;
    csg_scene s;
    /* written, then read back: every kind of value round-trips; the text is
     * POV-Ray 3.7's (%g, "<%g,...> "), kept in memory, in the scene */
    parse_ok("#fopen F \"d.txt\" write\n"
             "#write (F, \"\\\"a\\\\\\\"b\\\",\", 1.5, \",\", <1,2,3>, \",\" -2e-7 \",\" 1/3, \",\",\n"
             "        <0.25, 0.5, 1, 0, 0>, \"\\n\")\n"
             "#fclose F\n"
             "#fopen G \"./d.txt\" read\n"
             "#read (G, S, A, V, B, C, Col)\n"
             "#if (defined(G)) #error \"not closed at its end\" #end\n"
             "#fclose G\n" /* (closed already: accepted, as POV-Ray does) */
             "sphere { 0, strlen(S) } sphere { 0, asc(substr(S, 2, 1)) } sphere { 0, A }\n"
             "sphere { V, V.z } sphere { 0, -B * 1e7 } sphere { 0, C * 3 }\n",
             &s);
    assert_int_equal(s.written_count, 1);
    assert_string_equal(s.written[0].name, "d.txt");
    assert_false(s.written[0].append);
    const char *want = "\"a\\\"b\",1.5,<1,2,3> ,-2e-07,0.333333,<0.25,0.5,1,0,0> \n";
    assert_int_equal(s.written[0].len, strlen(want));
    assert_memory_equal(s.written[0].data, want, strlen(want));
    assert_int_equal(s.object_count, 6);
    assert_near(s.objects[0]->r0, 3);   /* a"b: 3 characters */
    assert_near(s.objects[1]->r0, '"'); /* the escape read back */
    assert_near(s.objects[2]->r0, 1.5);
    assert_near(s.objects[3]->r0, 3);
    assert_near(s.objects[4]->r0, 2);
    assert_near(s.objects[5]->r0, 0.999999);
    csg_scene_free(&s);
    /* #while (defined(F)): every value once; a comma after the last one
     * makes one more #read find nothing (POV-Ray's rule, kept); an empty
     * string first (fuzz finding: UBSan, an offset to a null pointer) */
    assert_radii("#fopen F \"n.txt\" write #write (F, \"1, 2,\\n3\\n\") #fclose F\n"
                 "#fopen F \"n.txt\" read\n"
                 "#while (defined(F)) #read (F, V) sphere { 0, V } #end",
                 (const double[]){1, 2, 3}, 3);
    assert_radii("#fopen F \"n.txt\" write #write (F, \"\", 1, \",\", 2, \",\") #fclose F\n"
                 "#fopen F \"n.txt\" read\n"
                 "#while (defined(F)) #read (F, V) sphere { 0, V } #end",
                 (const double[]){1, 2, 2}, 3);
    /* POV-Ray 3.7 drops the token after a value that no comma follows */
    assert_radii("#fopen F \"n.txt\" write #write (F, \"+-4 5 6, 7\") #fclose F\n"
                 "#fopen F \"n.txt\" read #read (F, A, B, C)\n"
                 "sphere { 0, -A } sphere { 0, B } sphere { 0, C }",
                 (const double[]){4, 6, 7}, 3);
    /* append adds to what the scene wrote; a name first opened with append
     * is appended to the file beside the output */
    parse_ok("#fopen F \"a.txt\" write #write (F, \"x\") #fclose F\n"
             "#fopen F \"a.txt\" append #write (F, \"y\") #fclose F\n"
             "#fopen F \"log.txt\" append #write (F, 7) #fclose F\n"
             "#if (file_exists(\"a.txt\") & !file_exists(\"none.txt\")) sphere { 0, 1 } #end",
             &s);
    assert_int_equal(s.written_count, 2);
    assert_int_equal(s.written[0].len, 2);
    assert_memory_equal(s.written[0].data, "xy", 2);
    assert_false(s.written[0].append);
    assert_true(s.written[1].append);
    assert_int_equal(s.object_count, 1);
    csg_scene_free(&s);

    /* #include of a file the scene wrote reads that text (makestacks.inc) */
    assert_radii("#fopen F \"gen.inc\" write\n"
                 "#write (F, \"#declare R = 2.5;\\nsphere { 0, R }\\n\") #fclose F\n"
                 "#include \"gen.inc\" #include \"./gen.inc\" sphere { 0, R * 2 }",
                 (const double[]){2.5, 2.5, 5}, 3);
    parse_err("#fopen F \"g.inc\" write #write (F, \"#include \\\"g.inc\\\"\") #fclose F\n"
              "#include \"g.inc\"",
              "g.inc:1:1: error: #include cycle: 'g.inc' is already being read (in 'g.inc' "
              "included at t.pov:2:1)");
    /* the files open for reading hold at most CSG_PARSE_MAX_DATA bytes */
    char want_read[256];
    snprintf(want_read, sizeof want_read, "t.pov:3:34: error: #fopen: the files open for reading "
             "would hold more than %ld bytes together", CSG_PARSE_MAX_DATA);
    parse_err("#declare S = \"0123456789abcdef\"; #for (I, 1, 16) #declare S = concat(S, S); #end\n"
              "#fopen F \"big.txt\" write #for (I, 1, 40) #write (F, S) #end #fclose F\n"
              "#fopen A \"big.txt\" read #fopen B \"big.txt\" read",
              want_read);

    /* errors: names that leave the folder, files not open, wrong modes */
    parse_err("#fopen F \"../x.txt\" write",
              "t.pov:1:10: error: '../x.txt' leaves the scene's folder: a scene reads and writes "
              "files only inside it (a relative name without '..')");
    parse_err("#fopen F \"/etc/passwd\" read",
              "t.pov:1:10: error: '/etc/passwd' leaves the scene's folder: a scene reads and "
              "writes files only inside it (a relative name without '..')");
    parse_err("#if (file_exists(\"a/../../b\")) #end",
              "t.pov:1:18: error: 'a/../../b' leaves the scene's folder: a scene reads and writes "
              "files only inside it (a relative name without '..')");
    parse_err("#read (F, X)", "t.pov:1:8: error: 'F' is not an open file (#fopen opens one; "
                              "#fclose, or a #read at its end, closes it)");
    parse_err("#fopen F \"x.txt\" write #fclose F\n#write (F, 1)",
              "t.pov:2:9: error: 'F' is not an open file (#fopen opens one; #fclose, or a #read "
              "at its end, closes it)");
    parse_err("#fopen F \"x.txt\" write #read (F, X)",
              "t.pov:1:31: error: 'F' is open for writing: #read needs a file opened with 'read'");
    parse_err("#fopen F \"x.txt\" write #fopen F \"y.txt\" write",
              "t.pov:1:31: error: 'F' is already a file: #fopen needs a name not in use (#fclose "
              "or #undef it first)");
    parse_err("#fopen F \"x.txt\" wrote", "t.pov:1:18: error: 'read', 'write' or 'append' "
                                          "expected after the file name of '#fopen', got 'wrote'");
    parse_err("#fopen F \"x.txt\" write #write (F, 1) #fclose F\n"
              "#fopen F \"x.txt\" read #write (F, 1)",
              "t.pov:2:31: error: 'F' is open for reading: #write needs a file opened with "
              "'write' or 'append'");
    parse_err("#fopen F \"x.txt\" write #write (F, \"1, <2>\") #fclose F\n"
              "#fopen F \"x.txt\" read #read (F, A, B)",
              "x.txt:1:6: error: a number expected (a vector has 2 to 5 components) in the data "
              "file, got '>'");
    parse_err("#declare P = pigment { rgb 1 }\n"
              "#fopen F \"x.txt\" write #write (F, 1) #fclose F\n"
              "#fopen F \"x.txt\" read #read (F, P)",
              "t.pov:3:33: error: 'P' is a pigment: #read sets a new name, a float, a 3-vector or "
              "a string (as POV-Ray 3.7)");
    parse_err("#fopen F \"x.txt\" read", "t.pov:1:10: error: #fopen: cannot read 'x.txt' in the "
                                         "scene's folder: No such file or directory");
    /* a directive nested in a #write may not close its file */
    parse_err("#macro Shut() #fclose F 1 #end\n#fopen F \"x.txt\" write #write (F, Shut())",
              "t.pov:1:23: error: 'F': a directive inside a #read or #write of a file may not "
              "close that file (in macro 'Shut' called at t.pov:2:35)");
    /* a scene that writes without end stops at the limit, with its figure */
    char want_limit[256];
    snprintf(want_limit, sizeof want_limit, "t.pov:2:48: error: #write: the files this scene "
             "writes would hold more than %ld bytes together (csgtrace keeps them in memory "
             "while it reads the scene)", CSG_PARSE_MAX_WRITTEN);
    parse_err("#declare S = \"0123456789abcdef\"; #for (I, 1, 16) #declare S = concat(S, S); #end\n"
              "#fopen F \"big.txt\" write #while (1) #write (F, S) #end",
              want_limit);

    /* from the scene's folder: regular files only, no link followed, and
     * nothing is ever written there by a parse */
    char dir[] = "/tmp/csg_fio_XXXXXX", path[256], text[512];
    csg_diag d;
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/in.txt", dir);
    write_text(path, "// a comment\n\"s\", 2, <1, 2, 3, 4, 5>\n");
    assert_true(parse_in(dir, "#fopen F \"in.txt\" read #read (F, S, R, C)\n"
                              "#fopen W \"out.txt\" write #write (W, S, R) #fclose W\n"
                              "sphere { 0, R + C.transmit }", &s, &d));
    assert_near(s.objects[0]->r0, 7);
    assert_int_equal(s.written_count, 1);
    csg_scene_free(&s);
    snprintf(path, sizeof path, "%s/out.txt", dir);
    assert_int_equal(access(path, F_OK), -1); /* (kept in memory: check writes nothing) */
    snprintf(path, sizeof path, "%s/link.txt", dir);
    assert_int_equal(symlink("/etc/passwd", path), 0);
    assert_false(parse_in(dir, "#fopen F \"link.txt\" read", &s, &d));
    snprintf(text, sizeof text, "%s/t.pov:1:10: error: #fopen: cannot read 'link.txt' in the "
             "scene's folder: a symbolic link on its path (a scene's files are read through "
             "none), or no folder", dir);
    assert_string_equal(d.message, text);
    assert_false(parse_in(dir, "#if (file_exists(\"link.txt\")) #error \"seen\" #end", &s, &d) &&
                 (csg_scene_free(&s), false));
    unlink(path);
    snprintf(path, sizeof path, "%s/pipe.txt", dir);
    assert_int_equal(mkfifo(path, 0600), 0);
    assert_false(parse_in(dir, "#fopen F \"pipe.txt\" read", &s, &d));
    snprintf(text, sizeof text, "%s/t.pov:1:10: error: #fopen: cannot read 'pipe.txt' in the "
             "scene's folder: not a regular file (a FIFO)", dir);
    assert_string_equal(d.message, text);
    unlink(path);
    snprintf(path, sizeof path, "%s/in.txt", dir);
    unlink(path);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_conditionals),
        cmocka_unit_test(test_loops),
        cmocka_unit_test(test_macros),
        cmocka_unit_test(test_macro_reference),
        cmocka_unit_test(test_arrays),
        cmocka_unit_test(test_strings),
        cmocka_unit_test(test_functions),
        cmocka_unit_test(test_image_and_clock),
        cmocka_unit_test(test_bounded_by),
        cmocka_unit_test(test_bare_object_names),
        cmocka_unit_test(test_transform_blocks),
        cmocka_unit_test(test_clipped_by),
        cmocka_unit_test(test_default_and_messages),
        cmocka_unit_test(test_camera_order),
        cmocka_unit_test(test_patterns),
        cmocka_unit_test(test_gamma_and_version),
        cmocka_unit_test(test_normals_and_layers),
        cmocka_unit_test(test_fog_and_lights),
        cmocka_unit_test(test_noise_patterns),
        cmocka_unit_test(test_unusable_declarations),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_reliability),
        cmocka_unit_test(test_numbers_finite),
        cmocka_unit_test(test_reflection_block),
        cmocka_unit_test(test_fog_colour_expression),
        cmocka_unit_test(test_crand_and_average),
        cmocka_unit_test(test_file_io),
        cmocka_unit_test(test_block_and_spiral_patterns),
        cmocka_unit_test(test_irid),
        cmocka_unit_test(test_pigment_pattern),
        cmocka_unit_test(test_interior_texture),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
