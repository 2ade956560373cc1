/*
 * test_fuzz_parser.c — a deterministic mutation fuzzer for the scene parser.
 *
 * From a corpus of valid scenes, FUZZ_RUNS inputs are derived with a fixed
 * seed (xorshift64*): byte flips, byte insertions of interesting characters,
 * token-sized deletions and duplications, splices of two corpus entries,
 * truncations, and deep nesting (braces, parentheses, comments); the corpus
 * and the inserted words cover the directives (#if, #while, #for, #switch,
 * #macro and calls, arrays, strings), patterns and the camera.  Every input
 * goes through csg_parse_string_opts (the built-in colors.inc, a token
 * budget of 20000 so runaway loops end fast); the call must either succeed (and then the
 * tree is walked, so ASan sees every node) or fail with a message of the
 * form `^.+:[0-9]+:[0-9]+: error: `.  Under ASan + UBSan (make test) any
 * memory error aborts the run.  Same seed, same inputs: a failure replays.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/lang/parser.h"
#include "fuzz_rng.h"

#define FUZZ_RUNS 20000
#define FUZZ_SEED 0x5eed2024cafef00dull
#define MAX_INPUT 65536

static const char *const corpus[] = {
    "#version 3.7;\n#include \"colors.inc\"\n"
    "global_settings { assumed_gamma 1.0 max_trace_level 8 adc_bailout 0.01 ambient_light White }\n"
    "camera { perspective location <0, 2, -6> look_at <0, 0.5, 0> angle 50 }\n"
    "light_source { <5, 10, -5>, color White }\n"
    "light_source {<1,2,3> rgb 1 shadowless translate x}\n"
    "background { color rgb <0.1, 0.1, 0.2> }\n"
    "plane { y, -1 pigment { Gray50 } finish { reflection 0.2 } }\n",

    "#declare R = 0.5;\n"
    "#declare Glass = texture { pigment { rgbf <1,1,1,0.9> } finish { phong 1 reflection 0.1 } }\n"
    "#declare Thing = difference {\n  box { -1, 1 }\n  sphere { 0, 1.3 pigment { rgb x } }\n"
    "  cylinder { -2*x, 2*x, R open }\n  texture { Glass }\n}\n"
    "object { Thing translate y rotate <0, 30, 0> }\n"
    "object { Thing scale 0.5 translate -2*x }\n",

    "union { sphere { <0,0,0>, 1 } cone { 0, 1, y, 0 open } pigment { color red 1 green 0.5 }\n"
    "  interior { ior 1.5 } scale 2 inverse no_shadow }\n"
    "merge { sphere { 0, 1 } sphere { x, 1 } }\n"
    "intersection { box { <-1,-1,-1>, <1,1,1> } sphere { 0, 1.4 } rotate 45*y }\n",

    "/* block /* nested */ comment */\n// line comment\n"
    "#declare F = finish { ambient 0.2 diffuse 0.7 specular 0.5 roughness 0.01 phong_size 60 }\n"
    "#declare P = pigment { colour rgbft <1, 0.5, 0.25, 0.1, 0.2> };\n"
    "#declare I = interior { ior 1.33 }\n"
    "#declare V = <1, 2, 3> * 2 - (x + y) / 4;\n"
    "sphere { V, pi / 4 pigment { P } finish { F } interior { I } }\n"
    "camera { location <0, 0, -10> right x up y direction 2*z sky y look_at <0, 0, 0> }\n",

    "#include \"colors.inc\"\n"
    "#declare A = union { sphere { 0, 1 } box { 0, 1 pigment { Red } } translate y }\n"
    "#declare B = union { object { A } object { A translate x } };\n"
    "#declare C = union { object { B } object { B translate z } };\n"
    "object { C pigment { Blue } }\n"
    "difference { object { C } cylinder { -5*y, 5*y, 0.3 } }\n",

    "#declare I = 0;\n"
    "#while (I < 4)\n  #if (mod(I, 2) = 0) sphere { <I, 0, 0>, 0.4 } #else box { I, I + 0.5 } #end\n"
    "  #declare I = I + 1;\n#end\n"
    "#for (J, 0, 3, 1.5) cone { 0, 1, y * (J + 1), 0 } #end\n"
    "#switch (I) #case (4) sphere { 0, 2 } #break #range (0, 3) sphere { 0, 3 } #else plane { y, 0 } #end\n",

    "#macro Ball(P, R) sphere { P, R pigment { checker rgb 1 rgb 0 scale R } } #end\n"
    "#macro Twice(V) (V * 2) #end\n"
    "#macro Row(N) #local K = 0; union { #while (K < N) Ball(<K, 0, 0>, Twice(0.2)) "
    "#local K = K + 1; #end } #end\n"
    "object { Row(3) rotate 30 * y }\n"
    "#ifdef (Ball) #undef Ball #end\n"
    "#declare S = concat(\"a\", str(1.5, 0, 2), chr(66));\n"
    "#if (strlen(S) > 2 & S != \"x\") sphere { 0, strlen(S) } #end\n",

    "#declare A = array[3] { 1, 2, 3 };\n"
    "#declare M = array[2][2] { { x, y }, { z, <1, 1, 1> } };\n"
    "#declare R = seed(7);\n"
    "#for (I, 0, 2) sphere { M[mod(I, 2)][1] * A[I], rand(R) + 0.1 } #end\n"
    "#declare P = pigment { gradient y color_map { [0 rgb x] [0.5 rgb y] [1 rgb z] } frequency 2 }\n"
    "box { -1, 1 pigment { P translate y } rotate <10, 20, 30> }\n"
    "camera { orthographic location <0, 2, -5> look_at 0 right x * image_width / image_height angle 30 }\n"
    "#declare T = texture { pigment { rgb 1 } normal { bumps 0.5 } }\n"
    "#default { finish { ambient 0.2 } }\n"
    "sphere { 0, (1 < 2 ? 1 : 2) + vlength(vcross(x, y)) }\n",

    "global_settings { noise_generator 1 }\n"
    "#declare W = pigment { wood turbulence <0.1, 0.2, 0> octaves 3 omega 0.6 lambda 2.5 }\n"
    "plane { y, 0 pigment { W scale 0.3 rotate 90 * x } }\n"
    "sphere { 0, 1 pigment { marble turbulence 1 sine_wave noise_generator 3 } }\n"
    "box { -1, 1 pigment { gradient y pigment_map { [0 granite] [0.5 agate agate_turb 0.4]\n"
    "  [1 checker pigment { bozo } pigment { spotted poly_wave 2 }] } } }\n"
    "sphere { 2 * x, 1 pigment { wrinkles scallop_wave frequency 2 phase 0.3 } }\n"
    "sphere { -2 * x, 1 pigment { radial cubic_wave quick_color rgb 1 } }\n"
    "sphere { 3 * y, 1 pigment { onion triangle_wave color_map { [0 rgb 1] [1 rgb 0] } } }\n",
};

#define CORPUS_SIZE ((int)(sizeof corpus / sizeof corpus[0]))


typedef struct {
    char *data;
    size_t len;
} buffer;

static void buf_insert(buffer *b, size_t at, const char *text, size_t n)
{
    if (b->len + n > MAX_INPUT)
        return;
    memmove(b->data + at + n, b->data + at, b->len - at);
    memcpy(b->data + at, text, n);
    b->len += n;
}

static void buf_delete(buffer *b, size_t at, size_t n)
{
    if (at + n > b->len)
        n = b->len - at;
    memmove(b->data + at, b->data + at + n, b->len - at - n);
    b->len -= n;
}

/* The extent of the "token" at `at`: a run of word characters or one char. */
static size_t token_len(const buffer *b, size_t at)
{
    size_t n = 1;
    if (isalnum((unsigned char)b->data[at]) || b->data[at] == '_' || b->data[at] == '.')
        while (at + n < b->len &&
               (isalnum((unsigned char)b->data[at + n]) || b->data[at + n] == '_' ||
                b->data[at + n] == '.'))
            n++;
    return n;
}

static void mutate_once(buffer *b, uint64_t *rng)
{
    static const char interesting[] = "{}<>(),;+-*/=#\"\\\n\0\xff 0.e9";
    static const char *const words[] = {
        "union { ", "}", "sphere { 0, 1 }", "object { A }", "pigment { ", "<", ">", "(", ")",
        "#declare A = ", "#include \"colors.inc\"", "1e308", "/0", "-", "torus", "/*", "*/",
        "\"", "scale 0", "cone { 0, 0, y, 0 }", "box { 0, 0 }", "#include \"nowhere.inc\"",
        "rgbft", "color", "1e-400", "#local", "object", "difference {", "inverse", ",",
        "#if (", "#else", "#elseif (0)", "#end", "#while (1)", "#while (I < 3)", "#for (I, 0, 9)",
        "#switch (1)", "#case (1)", "#range (0, 2)", "#break", "#macro M(A) ", "M(", "Row(", "Ball(0,",
        "#declare A = array[", "[", "]", "[1]", "#undef ", "#ifdef (", "#include concat(", "#error \"e\"",
        "concat(", "str(", "?", ":", "&", "|", "!", "!=", "<=", ".x", "checker", "gradient x",
        "color_map { [0 rgb 1] }", "seed(", "rand(R)", "#default {", "#declare T = texture { normal {",
        "orthographic", "clock", "image_width", "\xef\xbb\xbf"};
    size_t at = rng_below(rng, b->len + 1);
    switch (rng_below(rng, 8)) {
    case 0: /* flip a byte */
        if (at < b->len)
            b->data[at] = (char)(b->data[at] ^ (1u << rng_below(rng, 8)));
        break;
    case 1: /* insert an interesting byte */
        buf_insert(b, at, &interesting[rng_below(rng, sizeof interesting - 1)], 1);
        break;
    case 2: /* delete a token */
        if (at < b->len)
            buf_delete(b, at, token_len(b, at));
        break;
    case 3: { /* duplicate a token */
        if (at < b->len) {
            size_t n = token_len(b, at);
            char tmp[256];
            if (n > sizeof tmp)
                n = sizeof tmp;
            memcpy(tmp, b->data + at, n);
            buf_insert(b, at, tmp, n);
        }
        break;
    }
    case 4: { /* insert a word */
        const char *w = words[rng_below(rng, sizeof words / sizeof words[0])];
        buf_insert(b, at, w, strlen(w));
        break;
    }
    case 5: /* truncate */
        b->len = at;
        break;
    case 6: { /* splice the tail of another corpus entry */
        const char *other = corpus[rng_below(rng, CORPUS_SIZE)];
        size_t olen = strlen(other), from = rng_below(rng, olen);
        b->len = at;
        buf_insert(b, at, other + from, olen - from);
        break;
    }
    default: { /* deep nesting */
        static const char *const open[] = {"union { ", "(", "/*", "<", "object { "};
        static const char *const close[] = {" }", ")", "*/", ">", " }"};
        size_t k = rng_below(rng, 5), depth = 1 + rng_below(rng, 400);
        for (size_t i = 0; i < depth; i++)
            buf_insert(b, at, open[k], strlen(open[k]));
        if (rng_below(rng, 2)) {
            size_t end = at + depth * strlen(open[k]);
            for (size_t i = 0; i < depth; i++)
                buf_insert(b, end, close[k], strlen(close[k]));
        }
        break;
    }
    }
}

/* ^.+:[0-9]+:[0-9]+: error: */
static bool message_ok(const char *m)
{
    const char *e = strstr(m, ": error: ");
    while (e) {
        const char *q = e;
        int digits = 0;
        while (q > m && isdigit((unsigned char)q[-1]))
            q--, digits++;
        if (digits && q > m && q[-1] == ':') {
            const char *r = q - 1;
            int d2 = 0;
            while (r > m && isdigit((unsigned char)r[-1]))
                r--, d2++;
            if (d2 && r > m + 1 && r[-1] == ':')
                return true;
        }
        e = strstr(e + 1, ": error: ");
    }
    return false;
}

static long walk(const csg_object *o, const csg_scene *s)
{
    long n = 1;
    assert_true(o->texture >= -1 && o->texture < s->texture_count);
    assert_true(o->interior >= -1 && o->interior < s->interior_count);
    for (int i = 0; i < o->child_count; i++)
        n += walk(o->children[i], s);
    return n;
}

static void test_message_matcher(void **state)
{
    (void)state;
    assert_true(message_ok("a.pov:1:2: error: x"));
    assert_true(message_ok("/tmp/a b.pov:10:20: error: x"));
    assert_false(message_ok("csgtrace: error: x"));
    assert_false(message_ok(":1:2: error: x"));
    assert_false(message_ok("a.pov:1: error: x"));
}

static void test_fuzz(void **state)
{
    (void)state;
    uint64_t rng = FUZZ_SEED;
    buffer b = {malloc(MAX_INPUT + 1), 0};
    assert_non_null(b.data);
    long accepted = 0, rejected = 0;
    /* the built-in colors.inc, and a small token budget: a mutated loop
     * that never ends is stopped quickly by it (the limit's own test is in
     * test_language) */
    csg_parse_options opts;
    csg_parse_options_default(&opts);
    opts.no_default_library = true;
    opts.max_tokens = 20000;
    for (int run = 0; run < FUZZ_RUNS; run++) {
        const char *seed = corpus[rng_below(&rng, CORPUS_SIZE)];
        b.len = strlen(seed);
        memcpy(b.data, seed, b.len);
        int mutations = 1 + (int)rng_below(&rng, 3);
        for (int i = 0; i < mutations; i++)
            mutate_once(&b, &rng);
        csg_scene s;
        csg_diag d;
        memset(&d, 0, sizeof d);
        if (csg_parse_string_opts("fuzz.pov", b.data, b.len, &opts, &s, &d)) {
            accepted++;
            for (int i = 0; i < s.object_count; i++)
                walk(s.objects[i], &s);
            csg_scene_free(&s);
        } else {
            rejected++;
            if (!message_ok(d.message))
                fail_msg("run %d: malformed message '%s' for input:\n%.*s", run, d.message,
                         (int)b.len, b.data);
            assert_null(s.arena);
        }
    }
    free(b.data);
    print_message("fuzz: %d inputs, %ld accepted, %ld rejected\n", FUZZ_RUNS, accepted, rejected);
    assert_true(accepted > 0 && rejected > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_message_matcher),
        cmocka_unit_test(test_fuzz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
