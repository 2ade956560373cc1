/*
 * test_nff.c — the NFF reader (csg/lang/nff.c) and the loader that picks
 * it (csg/load.c): every entity and what it becomes in the scene tree,
 * the view, the shading values, the sidedness rule, the image size, and
 * every error message with its position; then a seeded mutation fuzzer:
 * NFF_FUZZ_RUNS inputs derived from a small corpus (byte flips, token
 * deletions, duplications, truncations, huge counts), each of which must
 * parse (and then flatten, so the polygon split meets garbage too) or fail
 * with one `file:line:col: error:` line.  Same seed, same inputs.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <regex.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/flatten.h"
#include "../csg/lang/nff.h"
#include "../csg/load.h"
#include "../csg/precision.h"
#include "summary_text.h"
#include "../workers/engine.h"
#include "fuzz_rng.h"

#define NFF_FUZZ_RUNS 6000
#define NFF_FUZZ_SEED 0x5eedcafe2024beefull

static const char *const scene_text =
    "b 0.1 0.2 0.3\n"
    "v\nfrom 0 -5 1\nat 0 0 1\nup 0 0 1\nangle 45\nhither 0.25\nresolution 64 32\n"
    "l 1 2 3\nl 4 5 6\nl 7 8 9 0.5 0.5 0.5\nl 1 1 1\n"
    "f 1 0 0 0.5 0.25 30 0 0\n"
    "s 0 0 1 0.5\n"
    "c 1 0 0 0.2 1 0 1 0.2\n"
    "c\n2 0 0 0.3\n2 0 1 0.1\n"
    "f 0 1 0 0.8 0 100000 0.5 1.5\n"
    "p 3\n0 0 0\n1 0 0\n0 1 0\n"
    "f 1 0 0 0.5 0.25 30 0 0\n"
    "p 4 -1 -1 0 1 -1 0 1 1 0 -1 1 0\n"
    "pp 3\n0 0 2 0 0 1\n1 0 2 0 0 1\n0 1 2 0 0 1\n"
    "pp 4\n0 0 3 0 0 1\n1 0 3 0 0 1\n1 1 3 0 0 1\n0 1 3 0 0 1\n";

static void parse_ok(const char *text, csg_scene *s)
{
    csg_diag d = {0};
    if (!csg_load_string("t.nff", text, strlen(text), NULL, s, &d))
        fail_msg("parse failed: %s", d.message);
}

static void test_entities(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok(scene_text, &s);
    assert_int_equal(s.object_count, 7);
    static const int kinds[7] = {CSG_OBJ_SPHERE, CSG_OBJ_CYLINDER, CSG_OBJ_CONE,
                                 CSG_OBJ_TRIANGLE, CSG_OBJ_POLYGON, CSG_OBJ_SMOOTH_TRIANGLE,
                                 CSG_OBJ_MESH};
    for (int i = 0; i < 7; i++)
        assert_int_equal(s.objects[i]->kind, kinds[i]);
    /* cones: open, the numbers on one line or on three */
    assert_true(s.objects[1]->open && s.objects[2]->open);
    assert_true(s.objects[2]->r0 == 0.3 && s.objects[2]->r1 == 0.1 && s.objects[2]->b.z == 1);
    /* sidedness: p one-sided unless it transmits; pp two-sided */
    assert_false(s.objects[3]->one_sided); /* T 0.5 */
    assert_true(s.objects[4]->one_sided);
    assert_false(s.objects[5]->one_sided || s.objects[6]->one_sided);
    assert_int_equal(s.objects[4]->vert_count, 4);
    assert_int_equal(s.objects[6]->vert_count, 6); /* 2 smooth triangles */
    assert_non_null(s.objects[6]->normals);
    /* identical f lines share one texture */
    assert_int_equal(s.texture_count, 2);
    assert_int_equal(s.objects[0]->texture, s.objects[4]->texture);
    assert_int_equal(s.background[2] == 0.3, 1);
    csg_scene_free(&s);
}

static void test_view(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok(scene_text, &s);
    assert_int_equal(s.width, 64);
    assert_int_equal(s.height, 32);
    assert_true(s.hither == 0.25);
    assert_true(s.has_camera);
    /* right-handed: looking +y with z up, right is +x; the plane spans
     * 2 tan(22.5 deg) across and half that up (64 x 32) */
    double span = 2 * tan(22.5 * M_PI / 180);
    assert_true(fabs(s.camera.right.x - span) < 1e-12 && fabs(s.camera.up.z - span / 2) < 1e-12);
    assert_true(fabs(s.camera.direction.y - 1) < 1e-12);
    int w, h;
    csg_image_size(&s, 0, 0, &w, &h);
    assert_true(w == 64 && h == 32);
    csg_image_size(&s, 128, 0, &w, &h);
    assert_true(w == 128 && h == 64);
    csg_image_size(&s, 10, 20, &w, &h);
    assert_true(w == 10 && h == 20);
    csg_scene_free(&s);
}

static void test_shading(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok(scene_text, &s);
    assert_int_equal(s.light_count, 4);
    assert_true(s.lights[0].color[0] == sqrt(4.0) / 8); /* sqrt(n) / (2n) */
    assert_true(s.lights[2].color[0] == 0.5);           /* its own colour */
    assert_true(s.globals.ambient_light[1] == 0.25);
    const csg_texture *t = &s.textures[s.objects[0]->texture];
    assert_true(t->finish.diffuse == 0.5 && t->finish.phong == 0.25 &&
                t->finish.reflection[0] == 0.25 && t->finish.phong_size == 30);
    const csg_texture *g = &s.textures[s.objects[3]->texture]; /* T 0.5: Kd / (1 - T) */
    assert_true(g->pigment.rgbft[4] == 0.5 && g->finish.diffuse == 1.6);
    assert_true(s.interiors[s.objects[3]->interior].ior == 1.5);
    assert_true(s.interiors[s.objects[0]->interior].ior == 1.0); /* opaque: ior unused */
    csg_scene_free(&s);
}

/* The whole scene flattens in both precisions, the polygon and the patch
 * split into triangles. */
static void test_flatten(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok(scene_text, &s);
    csg_flatten_opts o = {8, 8, 0, -1, 1, 0};
    const engine *e[2] = {&engine_float, &engine_double};
    for (int k = 0; k < 2; k++) {
        csg_blob b;
        csg_diag d = {0};
        if (!e[k]->flatten(&s, &o, &b, &d))
            fail_msg("flatten: %s", d.message);
        assert_true(csg_blob_valid(b.bytes, b.size));
        /* 1 + 2 + 1 + 2 (square) + 1 + 2 (patch) = 9 primitives */
        assert_int_equal(csg_blob_hdr(b.bytes)->prim_count, 9);
        csg_blob_free(&b);
    }
    csg_scene_free(&s);
}

/* ---- runs of triangles ------------------------------------------------------ */

/* Lines: 1-7 the view, 8 f, 9-11 a run of 3, 12 s, 13 a run of 1, 14 f,
 * 15-16 a run of 2, 17-18 smooth ones (another run), 19 the same f again
 * (the same material: the run goes on), 20 a third smooth one, 21 a flat
 * one (a run of 1); line 10's triangle has an edge of 1e-7. */
static const char *const runs_text =
    "v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0\nresolution 16 16\n"
    "f 1 0 0 1 0 1 0 1\n"
    "p 3 0 0 0 1 0 0 0 0 1\n"
    "p 3 0 0.5 0 1e-7 0.5 0 0 0.5 1\n"
    "p 3 1 0 0 1 0 1 0 0 1\n"
    "s 3 0 0 0.5\n"
    "p 3 -1 0 0 -2 0 0 -1 0 1\n"
    "f 0 1 0 1 0 1 0 1\n"
    "p 3 0 1 0 1 1 0 0 1 1\n"
    "p 3 1 1 0 1 1 1 0 1 1\n"
    "pp 3 0 2 0 0 -1 0 1 2 0 0 -1 0 0 2 1 0 -1 0\n"
    "pp 3 1 2 0 0 -1 0 1 2 1 0 -1 0 0 2 1 0 -1 0\n"
    "f 0 1 0 1 0 1 0 1\n"
    "pp 3 2 2 0 0 -1 0 3 2 0 0 -1 0 2 2 1 0 -1 0\n"
    "p 3 2 3 0 3 3 0 2 3 1\n";

/* The scene with every mesh of a run written out as its triangles, one
 * object each (what the reader made before it kept runs); the objects
 * and the array are malloc'd (free_unpacked). */
static csg_scene unpacked(const csg_scene *s)
{
    csg_scene u = *s;
    int n = 0;
    for (int i = 0; i < s->object_count; i++)
        n += s->objects[i]->piece_locs ? s->objects[i]->vert_count / 3 : 1;
    u.objects = calloc((size_t)n, sizeof *u.objects);
    assert_non_null(u.objects);
    u.object_count = 0;
    for (int i = 0; i < s->object_count; i++) {
        const csg_object *o = s->objects[i];
        int pieces = o->piece_locs ? o->vert_count / 3 : 1;
        for (int k = 0; k < pieces; k++) {
            csg_object *t = malloc(sizeof *t);
            assert_non_null(t);
            *t = *o;
            if (o->piece_locs) {
                t->kind = o->normals ? CSG_OBJ_SMOOTH_TRIANGLE : CSG_OBJ_TRIANGLE;
                t->verts = o->verts + 3 * k;
                t->normals = o->normals ? o->normals + 3 * k : NULL;
                t->vert_count = 3;
                t->piece_locs = NULL;
                t->loc = o->piece_locs[k];
            }
            u.objects[u.object_count++] = t;
        }
    }
    return u;
}

static void free_unpacked(csg_scene *u)
{
    for (int i = 0; i < u->object_count; i++)
        free(u->objects[i]);
    free(u->objects);
}

/* Both scenes flatten to the same bytes, in both precisions. */
static void assert_same_blobs(const csg_scene *a, const csg_scene *b)
{
    csg_flatten_opts o = {16, 16, 0, -1, 1, 0};
    const engine *e[2] = {&engine_float, &engine_double};
    for (int k = 0; k < 2; k++) {
        csg_blob x, y;
        csg_diag d = {0};
        if (!e[k]->flatten(a, &o, &x, &d) || !e[k]->flatten(b, &o, &y, &d))
            fail_msg("flatten: %s", d.message);
        assert_int_equal(x.size, y.size);
        assert_memory_equal(x.bytes, y.bytes, x.size);
        csg_blob_free(&x);
        csg_blob_free(&y);
    }
}

/* Consecutive triangles of one material and kind are one mesh, each
 * triangle's location kept; it flattens to the bytes the triangles as
 * objects of their own would; `check` counts its triangles; the
 * precision report names the triangle, not the run. */
static void test_runs(void **state)
{
    (void)state;
    csg_scene s;
    parse_ok(runs_text, &s);
    static const int kinds[6] = {CSG_OBJ_MESH, CSG_OBJ_SPHERE, CSG_OBJ_TRIANGLE,
                                 CSG_OBJ_MESH, CSG_OBJ_MESH,   CSG_OBJ_TRIANGLE};
    static const int verts[6] = {9, 0, 3, 6, 9, 3};
    static const int first_line[6] = {9, 12, 13, 15, 17, 21};
    assert_int_equal(s.object_count, 6);
    for (int i = 0; i < 6; i++) {
        const csg_object *o = s.objects[i];
        assert_int_equal(o->kind, kinds[i]);
        assert_int_equal(o->vert_count, verts[i]);
        assert_int_equal(o->loc.line, first_line[i]);
        assert_true((o->piece_locs != NULL) == (o->kind == CSG_OBJ_MESH));
    }
    assert_true(s.objects[0]->one_sided && !s.objects[4]->one_sided);
    assert_null(s.objects[3]->normals);
    assert_non_null(s.objects[4]->normals);
    assert_true(s.objects[4]->normals[8].y == -1 && s.objects[4]->verts[6].x == 2);
    static const int lines[3] = {17, 18, 20};
    for (int k = 0; k < 3; k++) {
        assert_int_equal(s.objects[4]->piece_locs[k].line, lines[k]);
        assert_int_equal(s.objects[4]->piece_locs[k].col, 1);
        assert_string_equal(s.objects[4]->piece_locs[k].file, "t.nff");
    }
    assert_int_equal(s.objects[0]->texture, s.objects[2]->texture);
    assert_int_equal(s.objects[3]->texture, s.objects[4]->texture);

    csg_scene u = unpacked(&s);
    assert_int_equal(u.object_count, 11);
    assert_same_blobs(&s, &u);
    free_unpacked(&u);

    char why[512];
    csg_needs_double(&s, 16, 16, why, sizeof why);
    if (!strstr(why, ": mesh triangle at t.nff:10:1: "))
        fail_msg("the precision report names <%s>, not line 10's triangle", why);

    char *buf = summary_text(&s);
    assert_non_null(buf);
    if (!strstr(buf, "objects: 6 top-level, 6 primitives") ||
        !strstr(buf, "sphere 1 triangle 2 mesh 3 (8 triangles)"))
        fail_msg("summary:\n%s", buf);
    free(buf);
    csg_scene_free(&s);
}

/* A run big enough for a BVH of many levels (4 000 random triangles, a
 * sphere amid them) flattens to the same bytes as its triangles. */
static void test_run_bvh(void **state)
{
    (void)state;
    enum { TRIANGLES = 4000 };
    size_t cap = 200 + (size_t)TRIANGLES * 120, len = 0;
    char *text = malloc(cap);
    assert_non_null(text);
    len += (size_t)snprintf(text + len, cap - len, "%s",
                            "v\nfrom 0 -30 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0\n"
                            "resolution 32 32\nf 0.5 0.5 1 1 0 1 0 1\n");
    uint64_t rng = 0x7e7a2024u;
    for (int i = 0; i < TRIANGLES; i++) {
        if (i == TRIANGLES / 2)
            len += (size_t)snprintf(text + len, cap - len, "s 0 0 0 1\n");
        double c[3], v[9];
        for (int a = 0; a < 3; a++)
            c[a] = 20.0 * ((double)rng_below(&rng, 100000) / 100000.0 - 0.5);
        for (int a = 0; a < 9; a++)
            v[a] = c[a % 3] + (double)rng_below(&rng, 1000) / 1000.0;
        len += (size_t)snprintf(text + len, cap - len, "p 3 %.6f %.6f %.6f %.6f %.6f %.6f "
                                "%.6f %.6f %.6f\n", v[0], v[1], v[2], v[3], v[4], v[5], v[6],
                                v[7], v[8]);
    }
    csg_scene s;
    csg_diag d = {0};
    if (!csg_load_string("t.nff", text, len, NULL, &s, &d))
        fail_msg("parse failed: %s", d.message);
    assert_int_equal(s.object_count, 3);
    assert_int_equal(s.objects[0]->vert_count + s.objects[2]->vert_count, 3 * TRIANGLES);
    csg_scene u = unpacked(&s);
    assert_int_equal(u.object_count, TRIANGLES + 1);
    assert_same_blobs(&s, &u);
    free_unpacked(&u);
    csg_scene_free(&s);
    free(text);
}

/* Malformed NFF: one line, file:line:col, at the token concerned. */
static void test_errors(void **state)
{
    (void)state;
    static const char *const cases[][2] = {
        {"x 1 2 3", "t.nff:1:1: error: an NFF entity (v, b, l, f, c, s, p, pp) expected, got 'x'"},
        {"from 1 2 3", "t.nff:1:1: error: an NFF entity (v, b, l, f, c, s, p, pp) expected, got 'from'"},
        {"s 1 2", "t.nff:1:6: error: a number (sphere x y z) expected, got end of file"},
        {"s 1 2 3 abc", "t.nff:1:9: error: a number (sphere radius) expected, got 'abc'"},
        {"s 1 2 3 -1", "t.nff:1:9: error: sphere radius must be > 0"},
        {"s 1 2 3 1e999", "t.nff:1:9: error: a number (sphere radius) expected, got '1e999'"},
        {"p 2\n0 0 0\n1 0 0", "t.nff:1:3: error: polygon vertex count must be a whole number from 3"},
        {"p 99999999999", "t.nff:1:3: error: polygon vertex count must be a whole number"},
        {"p 3\n0 0 0\n1 0 0\n2 0 0", "t.nff:1:1: error: degenerate polygon"},
        {"p 3\n0 0 0\n1 0 0\n", "t.nff:4:1: error: a number (polygon vertex x y z) expected, got end of file"},
        {"c 0 0 0 1 0 0 0 1", "t.nff:1:1: error: degenerate cone"},
        {"f 1 1 1 1 0 0 0.5 0", "t.nff:1:19: error: a transmitting material"},
        {"v\nfrom 0 0 0\nat 0 0 1\nup 0 1 0\nangle 200\nhither 1\nresolution 4 4",
         "t.nff:5:7: error: angle must be between 0 and 180"},
        {"v\nfrom 0 0 0\nat 0 0 1\nup 0 1 0\nangle 45\nhither 1\nresolution 4 0",
         "t.nff:7:14: error: resolution height must be a whole number"},
        {"v\nfrom 0 0 0\nat 0 0 1\nup 0 0 1\nangle 45\nhither 1\nresolution 4 4",
         "t.nff:1:1: error: view 'up' is parallel"},
        {"v\nfrom 0 0 0\nto 0 0 1", "t.nff:3:1: error: 'at' expected after 'from', got 'to'"},
        {"b 0 0 0", "t.nff:1:8: error: no view ('v') in the file"},
        {"s 0 0 0 1 # comment\n\n  q", "t.nff:3:3: error: an NFF entity"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        csg_scene s;
        csg_diag d = {0};
        assert_false(csg_load_string("t.nff", cases[i][0], strlen(cases[i][0]), NULL, &s, &d));
        if (strncmp(d.message, cases[i][1], strlen(cases[i][1])) != 0)
            fail_msg("case %zu: got <%s>, want <%s...>", i, d.message, cases[i][1]);
        assert_null(strchr(d.message, '\n'));
    }
}

static void test_nul_and_extension(void **state)
{
    (void)state;
    static const char text[] = "b 0 0 0\ns 0\0 0 0 1";
    csg_scene s;
    csg_diag d = {0};
    assert_false(csg_load_string("t.nff", text, sizeof text - 1, NULL, &s, &d));
    assert_string_equal(d.message, "t.nff:2:4: error: a NUL byte: not an NFF text file");
    assert_true(csg_is_nff("a/B.NFF") && csg_is_nff("x.nff") && !csg_is_nff("x.pov") &&
                !csg_is_nff("nff") && !csg_is_nff(NULL));
}

/* ---- the fuzzer ------------------------------------------------------------- */

static const char *const extra_corpus =
    "b 0 0 0\nv\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 50\nhither 1\nresolution 8 8\n"
    "l 0 0 10\nf 1 0.6 0.2 1 0 100000 0 0\n"
    "p 8\n1 -0.3 0\n1.6 -0.3 0\n1.6 0.3 0\n1 0.3 0\n0.3 1 0\n-0.3 1 0\n-1 0.3 0\n-1 -0.3 0\n";

#define FUZZ_MAX 8192

/* One mutation of buf[0..*len). */
static void mutate(char *buf, size_t *len, uint64_t *rng)
{
    static const char *const inserts[] = {" ", "\n", "-", "1e30", "pp", "p", "c", "#", "0",
                                          "99999999", "nan", "v", "f", "\t", "-0", "3"};
    size_t n = *len;
    size_t at = rng_below(rng, n + 1);
    switch (rng_below(rng, 5)) {
    case 0: /* flip a byte to a printable or whitespace character */
        if (n)
            buf[rng_below(rng, n)] = (char)(" \n0123456789.-epcsfvbl#x"[rng_below(rng, 24)]);
        break;
    case 1: { /* insert a token */
        const char *t = inserts[rng_below(rng, sizeof inserts / sizeof inserts[0])];
        size_t k = strlen(t);
        if (n + k < FUZZ_MAX) {
            memmove(buf + at + k, buf + at, n - at);
            memcpy(buf + at, t, k);
            *len = n + k;
        }
        break;
    }
    case 2: { /* delete a run */
        size_t k = 1 + rng_below(rng, 12);
        if (at + k > n)
            k = n - at;
        memmove(buf + at, buf + at + k, n - at - k);
        *len = n - k;
        break;
    }
    case 3: { /* duplicate a run */
        size_t k = 1 + rng_below(rng, 40);
        if (at + k > n)
            k = n - at;
        if (n + k < FUZZ_MAX) {
            memmove(buf + at + k, buf + at, n - at);
            *len = n + k;
        }
        break;
    }
    default: /* truncate */
        *len = at;
        break;
    }
}

static void test_fuzz(void **state)
{
    (void)state;
    const char *seeds[2] = {scene_text, extra_corpus};
    regex_t re;
    assert_int_equal(regcomp(&re, "^.+:[0-9]+:[0-9]+: error: |^csgtrace: error: out of memory",
                             REG_EXTENDED | REG_NOSUB), 0);
    uint64_t rng = NFF_FUZZ_SEED;
    char *buf = malloc(FUZZ_MAX);
    assert_non_null(buf);
    int parsed = 0;
    for (int run = 0; run < NFF_FUZZ_RUNS; run++) {
        const char *seed = seeds[rng_below(&rng, 2)];
        size_t len = strlen(seed);
        memcpy(buf, seed, len);
        int steps = 1 + (int)rng_below(&rng, 6);
        for (int k = 0; k < steps; k++)
            mutate(buf, &len, &rng);
        csg_scene s;
        csg_diag d = {0};
        if (csg_load_string("fuzz.nff", buf, len, NULL, &s, &d)) {
            parsed++;
            csg_flatten_opts o = {4, 4, 0, -1, 1, 0};
            csg_blob b;
            csg_diag fd = {0};
            if (engine_float.flatten(&s, &o, &b, &fd))
                csg_blob_free(&b);
            else if (regexec(&re, fd.message, 0, NULL, 0) != 0)
                fail_msg("run %d: flatten message <%s>", run, fd.message);
            csg_scene_free(&s);
        } else if (regexec(&re, d.message, 0, NULL, 0) != 0 || strchr(d.message, '\n')) {
            fail_msg("run %d: message <%s>", run, d.message);
        }
    }
    regfree(&re);
    free(buf);
    print_message("nff fuzz: %d of %d inputs parsed\n", parsed, NFF_FUZZ_RUNS);
    assert_true(parsed > 0); /* the mutations do not all break the file */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_entities), cmocka_unit_test(test_view),
        cmocka_unit_test(test_shading),  cmocka_unit_test(test_flatten),
        cmocka_unit_test(test_errors),   cmocka_unit_test(test_nul_and_extension),
        cmocka_unit_test(test_fuzz),     cmocka_unit_test(test_runs),
        cmocka_unit_test(test_run_bvh),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
