/*
 * test_engine.c — the flattener and the CPU engine on scene trees built by
 * hand (no parser involved): flattening rules (dissolved unions, De Morgan,
 * operand order, limits), shading against analytic values, and the
 * invariants every mode relies on (a tile renders the same pixels whatever
 * the tiling; records + shade == render).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <math.h>

#include "../csg/device/camera.h"
#include "../csg/device/flat.h"
#include "../csg/flatten.h"
#include "../csg/precision.h"
#include "../workers/engine.h"
#include "../workers/tile.h"

/* ---- building trees ---------------------------------------------------------- */

static csg_object *obj_new(csg_scene *s, enum csg_object_kind kind)
{
    csg_object *o = csg_arena_alloc(s->arena, sizeof *o);
    assert_non_null(o);
    o->kind = kind;
    o->texture = -1;
    o->interior = -1;
    o->loc = (csg_loc){"hand.pov", 1, 1};
    csg_xform_identity(&o->xform);
    return o;
}

static csg_object *sphere(csg_scene *s, double x, double y, double z, double r)
{
    csg_object *o = obj_new(s, CSG_OBJ_SPHERE);
    o->a = (dvec3){x, y, z};
    o->r0 = r;
    return o;
}

static csg_object *csg(csg_scene *s, enum csg_object_kind kind, int n, ...)
{
    csg_object *o = obj_new(s, kind);
    o->children = csg_arena_alloc(s->arena, (size_t)n * sizeof(csg_object *));
    va_list ap;
    va_start(ap, n);
    for (int i = 0; i < n; i++)
        o->children[i] = va_arg(ap, csg_object *);
    va_end(ap);
    o->child_count = n;
    return o;
}

static void add_top(csg_scene *s, csg_object *o)
{
    csg_object **objs = csg_arena_alloc(s->arena, (size_t)(s->object_count + 1) * sizeof *objs);
    if (s->object_count)
        memcpy(objs, s->objects, (size_t)s->object_count * sizeof *objs);
    objs[s->object_count++] = o;
    s->objects = objs;
}

static int add_texture(csg_scene *s, double r, double g, double b)
{
    csg_texture *t = csg_arena_alloc(s->arena, (size_t)(s->texture_count + 1) * sizeof *t);
    if (s->texture_count)
        memcpy(t, s->textures, (size_t)s->texture_count * sizeof *t);
    csg_texture_default(&t[s->texture_count]);
    t[s->texture_count].pigment.rgbft[0] = r;
    t[s->texture_count].pigment.rgbft[1] = g;
    t[s->texture_count].pigment.rgbft[2] = b;
    s->textures = t;
    return s->texture_count++;
}

static void scene_new(csg_scene *s)
{
    csg_scene_init(s);
    s->arena = csg_arena_new();
    assert_non_null(s->arena);
    s->has_camera = true;
    s->camera.location = (dvec3){0, 0, -5};
    s->camera.direction = (dvec3){0, 0, 1};
    s->camera.up = (dvec3){0, 1, 0};
    s->camera.right = (dvec3){1.33, 0, 0};
    s->camera.sky = (dvec3){0, 1, 0};
    s->background[0] = 0.25;
    s->background[1] = 0.5;
    s->background[2] = 0.75;
}

static const csg_blob_header *flatten_ok(const engine *e, csg_scene *s, int w, int h, csg_blob *b)
{
    csg_flatten_opts o = {w, h, 0, -1, 1, 0};
    csg_diag d = {0};
    bool ok = e->flatten(s, &o, b, &d);
    if (!ok)
        fail_msg("flatten failed: %s", d.message);
    assert_true(csg_blob_valid(b->bytes, b->size));
    return csg_blob_hdr(b->bytes);
}

/* The whole image, tile by tile, through tile_run (workers/tile.h). */
static float *render_all(const engine *e, const void *blob, int w, int h, int tile)
{
    tile_runner tr;
    assert_true(tile_runner_init(&tr, blob, tile));
    assert_ptr_equal(tr.eng, e);
    float *rgb = calloc((size_t)w * h * 3, sizeof(float));
    float *trgb = calloc((size_t)tile * tile * 3, sizeof(float));
    assert_true(rgb && trgb);
    uint64_t primary = 0;
    for (int i = 0; i < tile_count(&tr.grid); i++) {
        tile_result res;
        tile_run(&tr, i, NULL, trgb, &res);
        tile_store_rgb(rgb, w, tile_rect_of(&tr.grid, i), trgb);
        primary += res.rays.primary;
    }
    assert_int_equal(primary, (uint64_t)w * h);
    free(trgb);
    tile_runner_free(&tr);
    return rgb;
}

/* Renders the blob in tiles of `tile` and asserts the very pixels of ref. */
static void assert_renders(const engine *e, const void *blob, int w, int h, int tile,
                           const float *ref)
{
    float *img = render_all(e, blob, w, h, tile);
    assert_memory_equal(ref, img, (size_t)w * h * 3 * sizeof(float));
    free(img);
}

/* ---- tests --------------------------------------------------------------------- */

static void test_background_only(void **state)
{
    (void)state;
    const engine *engines[2] = {&engine_float, &engine_double};
    for (int k = 0; k < 2; k++) {
        csg_scene s;
        scene_new(&s);
        csg_blob b;
        const csg_blob_header *h = flatten_ok(engines[k], &s, 7, 5, &b);
        assert_int_equal(h->root_count, 0);
        assert_int_equal(h->real_size, engines[k]->real_size);
        assert_ptr_equal(engine_for_blob(b.bytes), engines[k]);
        float *rgb = render_all(engines[k], b.bytes, 7, 5, 4);
        for (int i = 0; i < 7 * 5; i++) {
            assert_true(rgb[3 * i] == 0.25f && rgb[3 * i + 1] == 0.5f && rgb[3 * i + 2] == 0.75f);
        }
        free(rgb);
        csg_blob_free(&b);
        csg_scene_free(&s);
    }
}

/* A red unit sphere at the origin with finish *f (NULL: the default), one
 * white light at `light`, 9x9 pixels in double: the centre pixel (the
 * sphere's nearest point, normal -z) into c, the corner into corner. */
static void red_sphere_pixels(const csg_finish *f, dvec3 light_at, float c[3], float corner[3])
{
    csg_scene s;
    scene_new(&s);
    csg_object *o = sphere(&s, 0, 0, 0, 1);
    o->texture = add_texture(&s, 1, 0, 0);
    if (f)
        s.textures[o->texture].finish = *f;
    add_top(&s, o);
    csg_light light = {.position = light_at, .color = {1, 1, 1}, .loc = {"hand.pov", 1, 1}};
    s.lights = &light;
    s.light_count = 1;
    csg_blob b;
    flatten_ok(&engine_double, &s, 9, 9, &b);
    float *rgb = render_all(&engine_double, b.bytes, 9, 9, 32);
    memcpy(c, &rgb[3 * (4 * 9 + 4)], 3 * sizeof(float));
    memcpy(corner, rgb, 3 * sizeof(float));
    free(rgb);
    csg_blob_free(&b);
    s.lights = NULL;
    csg_scene_free(&s);
}

/* Ambient-only red sphere, light behind the camera: the centre pixel is
 * ambient * pigment + diffuse * cos * pigment with cos = 1 exactly. */
static void test_lit_sphere_centre(void **state)
{
    (void)state;
    float c[3], corner[3];
    red_sphere_pixels(NULL, (dvec3){0, 0, -100}, c, corner);
    assert_true(fabs((double)c[0] - 0.7) < 1e-4);
    assert_true(c[1] == 0.0f);
    /* a corner misses: background */
    assert_true(corner[0] == 0.25f);
}

/* brilliance raises the diffuse cosine to its power; metallic tints the
 * highlight by the pigment, fully where the surface faces the light
 * (POV-Ray's Fresnel curve is 0 there). */
static void test_brilliance_metallic(void **state)
{
    (void)state;
    csg_finish f;
    csg_finish_default(&f);
    f.brilliance = 2;
    float c[3], corner[3];
    /* the light 60 degrees off the normal: cos^2 = 0.25 */
    red_sphere_pixels(&f, (dvec3){1000 * sin(M_PI / 3), 0, -1 - 1000 * cos(M_PI / 3)}, c, corner);
    assert_true(fabs((double)c[0] - (0.1 + 0.6 * 0.25)) < 1e-4);
    csg_finish_default(&f);
    f.phong = 0.5;
    f.phong_size = 1;
    red_sphere_pixels(&f, (dvec3){0, 0, -100}, c, corner);
    assert_true(fabs((double)c[1] - 0.5) < 1e-4); /* a white highlight */
    f.metallic = 1;
    red_sphere_pixels(&f, (dvec3){0, 0, -100}, c, corner);
    assert_true(fabs((double)c[0] - 1.2) < 1e-4);  /* a red one */
    assert_true(fabs((double)c[1]) < 1e-6);
}

/* The same pixels whatever the tile size, in both precisions. */
static void test_tiling_invariance(void **state)
{
    (void)state;
    csg_scene s;
    scene_new(&s);
    add_top(&s, csg(&s, CSG_OBJ_DIFFERENCE, 2, sphere(&s, 0, 0, 0, 1.5), sphere(&s, 0.8, 0.5, -1, 0.9)));
    add_top(&s, sphere(&s, -1.5, -0.5, 1, 0.7));
    csg_light light = {.position = {3, 4, -6}, .color = {1, 1, 1}, .loc = {"hand.pov", 1, 1}};
    s.lights = &light;
    s.light_count = 1;
    const engine *engines[2] = {&engine_float, &engine_double};
    for (int k = 0; k < 2; k++) {
        csg_blob b;
        flatten_ok(engines[k], &s, 37, 23, &b);
        float *ref = render_all(engines[k], b.bytes, 37, 23, 64);
        int tiles[] = {1, 5, 16};
        for (size_t i = 0; i < sizeof tiles / sizeof tiles[0]; i++)
            assert_renders(engines[k], b.bytes, 37, 23, tiles[i], ref);
        free(ref);
        csg_blob_free(&b);
    }
    s.lights = NULL;
    csg_scene_free(&s);
}

/* A jittered area light over a sphere with crand (POV-Ray's randomness,
 * ours a hash of the pixel: workers/shade.c): the same pixels whatever the
 * tiling and run after run, in both precisions; the grain only darkens
 * (POV-Ray subtracts it from the diffuse term), and both change the
 * image. */
static float *random_scene_render(const engine *e, bool jitter, double crand, int tile)
{
    csg_scene s;
    scene_new(&s);
    csg_object *big = sphere(&s, 0, 0, 2, 1.6);
    big->texture = add_texture(&s, 0.9, 0.8, 0.7);
    s.textures[big->texture].finish.crand = crand;
    add_top(&s, big);
    add_top(&s, sphere(&s, 0.6, 0.7, 0.1, 0.45));
    csg_light light = {.position = {3, 4, -6}, .color = {1, 1, 1}, .area = true,
                       .axis1 = {2, 0, 0}, .axis2 = {0, 2, 0}, .size1 = 4, .size2 = 4,
                       .adaptive = 1, .jitter = jitter, .loc = {"hand.pov", 1, 1}};
    s.lights = &light;
    s.light_count = 1;
    csg_blob b;
    flatten_ok(e, &s, 33, 25, &b);
    float *img = render_all(e, b.bytes, 33, 25, tile);
    csg_blob_free(&b);
    s.lights = NULL;
    csg_scene_free(&s);
    return img;
}

static void test_random_determinism(void **state)
{
    (void)state;
    const size_t n = 33 * 25 * 3;
    const engine *engines[2] = {&engine_float, &engine_double};
    for (int k = 0; k < 2; k++) {
        float *ref = random_scene_render(engines[k], true, 0.3, 64);
        int tiles[] = {1, 5, 16, 64};
        for (size_t i = 0; i < sizeof tiles / sizeof tiles[0]; i++) {
            float *img = random_scene_render(engines[k], true, 0.3, tiles[i]);
            assert_memory_equal(ref, img, n * sizeof(float));
            free(img);
        }
        float *plain = random_scene_render(engines[k], false, 0.0, 16);
        float *grain = random_scene_render(engines[k], false, 0.3, 16);
        float *jitter = random_scene_render(engines[k], true, 0.0, 16);
        size_t darker = 0, moved = 0;
        for (size_t i = 0; i < n; i++) {
            assert_true(isfinite(ref[i]));
            assert_true(grain[i] <= plain[i]);
            darker += grain[i] < plain[i];
            moved += jitter[i] != plain[i];
        }
        assert_true(darker > n / 10); /* the big sphere is lit over much of the image */
        assert_true(moved > 0);       /* the penumbra of the small sphere */
        free(plain);
        free(grain);
        free(jitter);
        free(ref);
    }
}

/* crand's grain as POV-Ray's ComputeDiffuseColour makes it: a white wall
 * facing the camera and a far light behind it (cos 1), ambient 0, diffuse
 * 0.7, crand 0.3: each pixel is 0.7 - 0.3 U, U uniform in [0, 1) (POV-Ray
 * 3.7 gave min 0.320, mean 0.439, sd 0.0688 where that law gives 0.32, 0.44,
 * 0.0693, on a pigment of 0.8: measured in #38's work). */
static void test_crand_law(void **state)
{
    (void)state;
    csg_scene s;
    scene_new(&s);
    csg_object *wall = obj_new(&s, CSG_OBJ_PLANE);
    wall->a = (dvec3){0, 0, -1};
    wall->r0 = -2; /* the plane z = 2 */
    wall->texture = add_texture(&s, 1, 1, 1);
    csg_finish *f = &s.textures[wall->texture].finish;
    f->ambient[0] = f->ambient[1] = f->ambient[2] = 0;
    f->diffuse = 0.7;
    f->crand = 0.3;
    add_top(&s, wall);
    csg_light light = {.position = {0, 0, -1e7}, .color = {1, 1, 1}, .loc = {"hand.pov", 1, 1}};
    s.lights = &light;
    s.light_count = 1;
    csg_blob b;
    flatten_ok(&engine_double, &s, 40, 30, &b);
    float *img = render_all(&engine_double, b.bytes, 40, 30, 16);
    const int n = 40 * 30;
    double sum = 0, sum2 = 0, lo = 1, hi = 0;
    for (int i = 0; i < n; i++) {
        double v = (double)img[3 * i];
        assert_true(img[3 * i + 1] == img[3 * i] && img[3 * i + 2] == img[3 * i]);
        sum += v;
        sum2 += v * v;
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
    }
    double mean = sum / n, sd = sqrt(sum2 / n - mean * mean);
    assert_true(lo >= 0.4 - 1e-6 && lo < 0.41);
    assert_true(hi <= 0.7 + 1e-6 && hi > 0.69);
    assert_true(fabs(mean - 0.55) < 0.01);
    assert_true(fabs(sd - 0.3 / sqrt(12.0)) < 0.005);
    free(img);
    csg_blob_free(&b);
    s.lights = NULL;
    csg_scene_free(&s);
}

/* difference -> intersection with a complemented leaf; a dissolved union. */
static void test_flatten_programs(void **state)
{
    (void)state;
    csg_scene s;
    scene_new(&s);
    add_top(&s, csg(&s, CSG_OBJ_UNION, 2, sphere(&s, 0, 0, 0, 1), sphere(&s, 3, 0, 0, 1)));
    add_top(&s, csg(&s, CSG_OBJ_DIFFERENCE, 2, sphere(&s, 0, 0, 0, 1), sphere(&s, 1, 0, 0, 1)));
    csg_blob b;
    const csg_blob_header *h = flatten_ok(&engine_float, &s, 4, 4, &b);
    assert_int_equal(h->root_count, 3); /* the union dissolved into two roots */
    const csg_node *nodes = (const csg_node *)((const char *)b.bytes + h->off_nodes);
    const csg_prim *prims = (const csg_prim *)((const char *)b.bytes + h->off_prims);
    const csg_root *roots = (const csg_root *)((const char *)b.bytes + h->off_roots);
    int diff = -1; /* the BVH reorders roots: find the difference's */
    for (int i = 0; i < h->root_count; i++)
        if (roots[i].node_count == 3)
            diff = i;
    assert_true(diff >= 0);
    assert_int_equal(nodes[roots[diff].first_node + 2].op, CSG_OP_INTERSECT);
    int second = nodes[roots[diff].first_node + 1].prim;
    assert_true(prims[second].flags & CSG_PF_INVERT);
    int first = nodes[roots[diff].first_node].prim;
    assert_false(prims[first].flags & CSG_PF_INVERT);
    assert_int_equal(h->max_stack, 2);
    csg_blob_free(&b);

    /* an inverted union is not dissolved: it becomes ¬a ∩ ¬b */
    csg_scene t;
    scene_new(&t);
    csg_object *u = csg(&t, CSG_OBJ_UNION, 2, sphere(&t, 0, 0, 0, 1), sphere(&t, 3, 0, 0, 1));
    u->inverse = true;
    add_top(&t, u);
    h = flatten_ok(&engine_float, &t, 4, 4, &b);
    nodes = (const csg_node *)((const char *)b.bytes + h->off_nodes);
    prims = (const csg_prim *)((const char *)b.bytes + h->off_prims);
    assert_int_equal(h->root_count, 1);
    assert_int_equal(nodes[2].op, CSG_OP_INTERSECT);
    assert_true(prims[0].flags & CSG_PF_INVERT);
    assert_true(prims[1].flags & CSG_PF_INVERT);
    csg_blob_free(&b);
    csg_scene_free(&t);
    csg_scene_free(&s);
}

/* A balanced tree needing more lists than the evaluator has is refused
 * with the location of its root. */
static csg_object *balanced(csg_scene *s, int depth)
{
    if (depth == 0)
        return sphere(s, 0, 0, 0, 1);
    return csg(s, CSG_OBJ_INTERSECTION, 2, balanced(s, depth - 1), balanced(s, depth - 1));
}

static void test_flatten_stack_limit(void **state)
{
    (void)state;
    csg_scene s;
    scene_new(&s);
    add_top(&s, balanced(&s, CSG_STACK_MAX - 1)); /* needs CSG_STACK_MAX lists: fine */
    csg_blob b;
    const csg_blob_header *h = flatten_ok(&engine_float, &s, 2, 2, &b);
    assert_int_equal(h->max_stack, CSG_STACK_MAX);
    csg_blob_free(&b);
    csg_scene_free(&s);

    scene_new(&s);
    csg_object *deep = balanced(&s, CSG_STACK_MAX);
    deep->loc = (csg_loc){"deep.pov", 7, 3};
    add_top(&s, deep);
    csg_flatten_opts o = {2, 2, 0, -1, 1, 0};
    csg_diag d = {0};
    assert_false(csg_flatten_float(&s, &o, &b, &d));
    assert_non_null(strstr(d.message, "deep.pov:7:3: error: CSG tree too complex"));
    assert_null(b.bytes);
    csg_scene_free(&s);
}

static void test_flatten_degenerate(void **state)
{
    (void)state;
    csg_scene s;
    scene_new(&s);
    csg_object *o = sphere(&s, 0, 0, 0, 1);
    o->xform.m[1][1] = 0; /* scale y by 0: singular */
    add_top(&s, o);
    csg_blob b;
    csg_flatten_opts opts = {2, 2, 0, -1, 1, 0};
    csg_diag d = {0};
    assert_false(csg_flatten_double(&s, &opts, &b, &d));
    assert_non_null(strstr(d.message, "hand.pov:1:1: error: "));
    csg_scene_free(&s);
}

/* A corrupted or truncated blob is rejected before anyone reads it. */
static void test_blob_validation(void **state)
{
    (void)state;
    csg_scene s;
    scene_new(&s);
    add_top(&s, sphere(&s, 0, 0, 0, 1));
    csg_blob b;
    flatten_ok(&engine_float, &s, 3, 3, &b);
    assert_true(csg_blob_valid(b.bytes, b.size));
    assert_false(csg_blob_valid(b.bytes, b.size - 1));
    csg_blob_header *h = b.bytes;
    h->prim_count = 1 << 30;
    assert_false(csg_blob_valid(b.bytes, b.size));
    h->prim_count = 1;
    /* the feature set: code specialised on it relies on it (spec.h) */
    assert_int_equal(h->kinds, 1u << CSG_PRIM_SPHERE);
    assert_int_equal(h->features & (CSG_FEAT_CSG | CSG_FEAT_XFORM), 0);
    h->kinds = 1u << CSG_PRIM_BOX; /* a header that lies about its kinds */
    assert_false(csg_blob_valid(b.bytes, b.size));
    h->kinds = 1u << CSG_PRIM_SPHERE;
    h->features ^= CSG_FEAT_CSG; /* ... or its features */
    assert_false(csg_blob_valid(b.bytes, b.size));
    h->features ^= CSG_FEAT_CSG;
    assert_true(csg_blob_valid(b.bytes, b.size));
    h->magic = 0;
    assert_false(csg_blob_valid(b.bytes, b.size));
    csg_blob_free(&b);
    csg_scene_free(&s);
}

/* A poly's coefficients: once an object in the blob's table (its pieces
 * share them), reached by an offset from the primitive that the validator
 * holds to the table; an order, a piece or an offset out of range, or not
 * a whole number, is refused. */
static void test_poly_blob_validation(void **state)
{
    (void)state;
    static const double sphere4[35] = {1, 0, 0, 0, 2, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                       0, 0, 1, 0, 0, 2, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, -1};
    csg_scene s;
    scene_new(&s);
    csg_object *o = obj_new(&s, CSG_OBJ_POLY);
    o->poly_order = 4;
    o->poly_coef = sphere4;
    add_top(&s, o);
    add_top(&s, sphere(&s, 3, 0, 0, 1));
    csg_blob b;
    const csg_blob_header *h = flatten_ok(&engine_float, &s, 8, 8, &b);
    assert_int_equal(h->coef_count, 35);
    assert_true(csg_blob_valid(b.bytes, b.size));
    csg_prim *prims = (csg_prim *)(void *)((char *)b.bytes + h->off_prims);
    int polys = 0;
    for (int i = 0; i < h->prim_count; i++) {
        if (prims[i].kind != CSG_PRIM_POLY)
            continue;
        polys++;
        const float *c = prims[i].p + (int)prims[i].p[2] * CSG_POLY_OFFSET_UNIT + (int)prims[i].p[3];
        assert_true(c[0] == 1.0f && c[4] == 2.0f && c[34] == -1.0f); /* the table's */
        static const struct {
            int k;
            float v;
        } bad[] = {{0, 8.0f}, {0, 1.0f}, {0, 4.5f}, {1, 3.0f}, {1, -1.0f}, {2, -1.0f},
                   {3, 4096.0f}, {3, 0.5f}, {3, 1e30f}};
        for (size_t j = 0; j < sizeof bad / sizeof bad[0]; j++) {
            float keep = prims[i].p[bad[j].k];
            prims[i].p[bad[j].k] = bad[j].v;
            assert_false(csg_blob_valid(b.bytes, b.size));
            prims[i].p[bad[j].k] = keep;
        }
        prims[i].p[3] += 1.0f; /* the last term past the table */
        assert_false(csg_blob_valid(b.bytes, b.size));
        prims[i].p[3] -= 2.0f; /* before it: the primitives' bytes */
        assert_false(csg_blob_valid(b.bytes, b.size));
        prims[i].p[3] += 1.0f;
        assert_true(csg_blob_valid(b.bytes, b.size));
    }
    assert_int_equal(polys, 3);
    csg_blob_free(&b);
    csg_scene_free(&s);
}

/* A poly coefficient beyond float's range (the fuzzer's 4.4e51): the
 * float flattener refuses it with a message that names it, --precision
 * auto takes double for it, and the double build flattens it. */
static void test_poly_coefficient_range(void **state)
{
    (void)state;
    static const double huge2[10] = {1, 0, 0, 0, 1, 0, 0, 1, 0, -4.4e51};
    csg_scene s;
    scene_new(&s);
    csg_object *o = obj_new(&s, CSG_OBJ_POLY);
    o->poly_order = 2;
    o->poly_coef = huge2;
    add_top(&s, o);
    csg_flatten_opts fo = {8, 8, 0, -1, 1, 0};
    csg_diag d = {0};
    csg_blob b;
    assert_false(engine_float.flatten(&s, &fo, &b, &d));
    assert_non_null(strstr(d.message, "the poly's coefficient 10 (-4.4e+51) is beyond the range "
                                      "of single precision"));
    char why[512];
    assert_true(csg_needs_double(&s, 8, 8, why, sizeof why));
    flatten_ok(&engine_double, &s, 8, 8, &b);
    csg_blob_free(&b);
    csg_scene_free(&s);
}

/* The BVH finds exactly the hits a plain loop over every root finds: 300
 * spheres and a plane, every pixel's record compared bit for bit. */
static void test_bvh_matches_linear(void **state)
{
    (void)state;
    csg_scene s;
    scene_new(&s);
    uint64_t seed = 12345;
    for (int i = 0; i < 300; i++) {
        double v[4];
        for (int k = 0; k < 4; k++) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            v[k] = (double)(seed >> 11) * 0x1.0p-53;
        }
        add_top(&s, sphere(&s, 8 * v[0] - 4, 6 * v[1] - 3, 6 * v[2], 0.05 + 0.4 * v[3]));
    }
    csg_object *floor = obj_new(&s, CSG_OBJ_PLANE);
    floor->a = (dvec3){0, 1, 0};
    floor->r0 = -3.2;
    add_top(&s, floor);
    csg_blob b;
    const csg_blob_header *h = flatten_ok(&engine_float, &s, 64, 48, &b);
    assert_int_equal(h->linear_roots, 1);
    assert_true(h->bvh_count >= 150);
    const char *bytes = b.bytes;
    csg_view bvh = csg_blob_view((const csg_u8 *)bytes);
    csg_view linear = bvh;
    linear.root_count = h->root_count;
    linear.bvh_count = 0;
    const csg_camera *cam = (const csg_camera *)(bytes + h->off_camera);
    int hits = 0;
    for (int y = 0; y < 48; y++) {
        for (int x = 0; x < 64; x++) {
            csg_ray r = csg_primary_ray(cam, 64, 48, x, y);
            csg_hit a = csg_trace_nearest(bvh, r, 0.0f, CSG_R_INF);
            csg_hit c = csg_trace_nearest(linear, r, 0.0f, CSG_R_INF);
            assert_int_equal(a.surf, c.surf);
            assert_memory_equal(&a.t, &c.t, sizeof a.t);
            hits += a.surf != 0;
        }
    }
    assert_true(hits > 64 * 48 / 4); /* the scene is not trivially empty */
    csg_blob_free(&b);
    csg_scene_free(&s);
}

/* ---- the SAH BVH ------------------------------------------------------------ */

static double unit_rand(uint64_t *seed)
{
    *seed = *seed * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*seed >> 11) * 0x1.0p-53;
}

/* Walks the tree from the top pair: children after their parent, each
 * bounded root in exactly one leaf, a leaf of one root with exactly that
 * root's box (the walk skips testing it again), no deeper than the walk's
 * stack. */
static void bvh_check(const csg_bvh_node *bvh, const csg_root *roots, int k, int depth, int *seen)
{
    const csg_bvh_node *n = &bvh[k];
    assert_true(depth < CSG_BVH_STACK);
    if (n->count >= 0) {
        for (int i = n->first; i < n->first + n->count; i++)
            seen[i]++;
        if (n->count == 1) {
            assert_memory_equal(n->box, roots[n->first].lo, sizeof roots->lo);
            assert_memory_equal(n->box + 3, roots[n->first].hi, sizeof roots->hi);
        }
        return;
    }
    assert_true(n->first > k);
    bvh_check(bvh, roots, n->first, depth + 1, seen);
    bvh_check(bvh, roots, n->first + 1, depth + 1, seen);
}

/* Random scenes of 1 to 2000 roots, in five layouts (uniform, all at one
 * point, sizes spread over six decades, a line of touching spheres,
 * spheres at scales halving forty times over), with
 * CSG roots and a plane: the tree is well formed and shallow, and the
 * BVH finds exactly the hit a loop over every root finds, for camera rays
 * and for rays from random points in random (sometimes axis-aligned)
 * directions, bit for bit. */
static void test_bvh_sah_random(void **state)
{
    (void)state;
    const int sizes[] = {1, 2, 3, 5, 17, 100, 2000};
    uint64_t seed = 99;
    for (int layout = 0; layout < 5; layout++) {
        for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
            int n = sizes[si];
            csg_scene s;
            scene_new(&s);
            for (int i = 0; i < n; i++) {
                double v[4];
                for (int k = 0; k < 4; k++)
                    v[k] = unit_rand(&seed);
                double x = 8 * v[0] - 4, y = 6 * v[1] - 3, z = 6 * v[2], r = 0.05 + 0.4 * v[3];
                if (layout == 1) { /* every centre the same: no binned split exists */
                    x = 0.5;
                    y = -0.25;
                    z = 1;
                } else if (layout == 2) { /* sizes over six decades */
                    r = pow(10, -6 * v[3]) * 2;
                } else if (layout == 3) { /* a line of touching spheres */
                    x = -4 + 8.0 * i / n;
                    y = 0;
                    z = 2;
                    r = 4.0 / n;
                } else if (layout == 4) { /* nested scales: SAH peels one at a time */
                    x = 4 * pow(0.5, i % 40);
                    y = x / 2;
                    r = x / 8;
                }
                csg_object *o = sphere(&s, x, y, z, r);
                if (i % 7 == 3) /* a CSG root now and then */
                    o = csg(&s, CSG_OBJ_DIFFERENCE, 2, o, sphere(&s, x + r / 2, y, z - r / 2, r / 2));
                add_top(&s, o);
            }
            csg_object *floor = obj_new(&s, CSG_OBJ_PLANE);
            floor->a = (dvec3){0, 1, 0};
            floor->r0 = -3.2;
            add_top(&s, floor);
            csg_blob b;
            const csg_blob_header *h = flatten_ok(&engine_float, &s, 40, 30, &b);
            const char *bytes = b.bytes;
            csg_view bvh = csg_blob_view((const csg_u8 *)bytes);
            assert_int_equal(h->linear_roots, 1);
            assert_true(h->bvh_count >= 2 && h->bvh_count % 2 == 0);
            int *seen = calloc((size_t)h->root_count, sizeof *seen);
            assert_non_null(seen);
            bvh_check(bvh.bvh, bvh.roots, 0, 1, seen);
            bvh_check(bvh.bvh, bvh.roots, 1, 1, seen);
            for (int i = 0; i < h->root_count; i++)
                assert_int_equal(seen[i], i < h->linear_roots ? 0 : 1);
            free(seen);
            csg_view linear = bvh;
            linear.root_count = h->root_count;
            linear.bvh_count = 0;
            const csg_camera *cam = (const csg_camera *)(bytes + h->off_camera);
            for (int k = 0; k < 40 * 30 + 600; k++) {
                csg_ray r;
                if (k < 40 * 30) {
                    r = csg_primary_ray(cam, 40, 30, k % 40, k / 40);
                } else {
                    double v[6];
                    for (int j = 0; j < 6; j++)
                        v[j] = unit_rand(&seed);
                    r.o = v3((real)(8 * v[0] - 4), (real)(6 * v[1] - 3), (real)(6 * v[2]));
                    r.d = v3_normalize(v3((real)(v[3] - 0.5), (real)(v[4] - 0.5), (real)(v[5] - 0.5)));
                    if (k % 5 == 0)
                        r.d = v3(R(0.0), (k & 8) ? R(1.0) : -R(1.0), -R(0.0));
                }
                csg_hit a = csg_trace_nearest(bvh, r, 0.0f, CSG_R_INF);
                csg_hit c = csg_trace_nearest(linear, r, 0.0f, CSG_R_INF);
                assert_int_equal(a.surf, c.surf);
                assert_memory_equal(&a.t, &c.t, sizeof a.t);
            }
            csg_blob_free(&b);
            csg_scene_free(&s);
        }
    }
}

/* ---- shadow rays ---------------------------------------------------------------- */

/* csg_root.flags of root i in a blob of either precision (this file's
 * csg_root is the float one: 4 integers, then 6 reals). */
static csg_i32 *root_flags(char *bytes, const csg_blob_header *h, int i)
{
    size_t stride = 4 * sizeof(csg_i32) + 6 * (size_t)h->real_size;
    return (csg_i32 *)(void *)(bytes + h->off_roots + (size_t)i * stride) + 3;
}

/* The shadow shortcuts change no pixel: a scene of opaque CSG, a
 * transparent sphere, a no_shadow one, a top-level polygon and a no_shadow
 * mesh (a root a triangle, flagged as add_root flags one) renders exactly
 * the same with the
 * root flags as with every flag cleared (the full interval list on every
 * root, and no shadow cache: it keeps opaque roots only), in both
 * precisions; so it does in tiles of one pixel (the shadow cache starts
 * empty at every pixel) as in tiles of 16 (it carries over); and the
 * flags say what the roots are. */
static void test_shadow_flags(void **state)
{
    (void)state;
    csg_scene s;
    scene_new(&s);
    int red = add_texture(&s, 1, 0.2, 0.2);
    int glass = add_texture(&s, 0.6, 0.9, 0.7);
    int cloud = add_texture(&s, 0.9, 0.9, 0.9);
    s.textures[glass].pigment.rgbft[3] = 0.7;  /* filter */
    s.textures[cloud].pigment.rgbft[4] = 0.25; /* transmit */
    csg_object *cut = csg(&s, CSG_OBJ_DIFFERENCE, 2, sphere(&s, 0, 0, 1, 1.2),
                          sphere(&s, -0.6, 0.6, 0.2, 0.8));
    cut->texture = red;
    add_top(&s, cut);
    csg_object *ball = sphere(&s, 1.2, 1.1, -0.4, 0.5);
    add_top(&s, ball);
    csg_object *lens = sphere(&s, -1.4, 1.0, -0.5, 0.6);
    lens->texture = glass;
    add_top(&s, lens);
    csg_object *puff = csg(&s, CSG_OBJ_INTERSECTION, 2, sphere(&s, 1.5, -1, 0, 0.8),
                           sphere(&s, 1.9, -1, 0, 0.8));
    puff->texture = cloud;
    add_top(&s, puff);
    csg_object *ghost = sphere(&s, -1.5, -1.2, -0.8, 0.5);
    ghost->no_shadow = true;
    add_top(&s, ghost);
    csg_object *floor = obj_new(&s, CSG_OBJ_PLANE);
    floor->a = (dvec3){0, 1, 0};
    floor->r0 = -1.6;
    add_top(&s, floor);
    /* surfaces of several triangles at the top level: a root a piece */
    csg_object *tile = obj_new(&s, CSG_OBJ_POLYGON); /* two-sided, opaque */
    tile->verts = csg_arena_alloc(s.arena, 4 * sizeof *tile->verts);
    tile->verts[0] = (dvec3){-1, -1.2, -1};
    tile->verts[1] = (dvec3){0, -1.2, -1};
    tile->verts[2] = (dvec3){0, -1.2, 0};
    tile->verts[3] = (dvec3){-1, -1.2, 0};
    tile->vert_count = 4;
    add_top(&s, tile);
    csg_object *veil = obj_new(&s, CSG_OBJ_MESH); /* casts no shadow */
    veil->verts = csg_arena_alloc(s.arena, 6 * sizeof *veil->verts);
    const dvec3 veil_verts[6] = {{0.5, -1.3, -1.2}, {1.2, -1.3, -1.2}, {1.2, -1.3, -0.5},
                                 {0.5, -1.3, -1.2}, {1.2, -1.3, -0.5}, {0.5, -1.3, -0.5}};
    memcpy(veil->verts, veil_verts, sizeof veil_verts);
    veil->vert_count = 6;
    veil->no_shadow = true;
    add_top(&s, veil);
    csg_light lights[2] = {{.position = {3, 6, -6}, .color = {1, 1, 1}, .loc = {"hand.pov", 1, 1}},
                           {.position = {-4, 2, -3}, .color = {0.5, 0.4, 0.3},
                            .loc = {"hand.pov", 1, 1}}};
    s.lights = lights;
    s.light_count = 2;
    const engine *engines[2] = {&engine_float, &engine_double};
    for (int e = 0; e < 2; e++) {
        csg_blob b;
        const csg_blob_header *h = flatten_ok(engines[e], &s, 48, 36, &b);
        char *bytes = b.bytes;
        int opaque = 0, none = 0;
        for (int i = 0; i < h->root_count; i++) {
            opaque += (*root_flags(bytes, h, i) & CSG_ROOT_OPAQUE) != 0;
            none += (*root_flags(bytes, h, i) & CSG_ROOT_NO_SHADOW) != 0;
        }
        /* the cut sphere, the ball, the floor and the tile's two pieces */
        assert_int_equal(opaque, 5);
        assert_int_equal(none, 3); /* the ghost and the veil's two triangles */
        float *with = render_all(engines[e], bytes, 48, 36, 16);
        assert_renders(engines[e], bytes, 48, 36, 1, with);
        for (int i = 0; i < h->root_count; i++)
            *root_flags(bytes, h, i) = 0;
        assert_renders(engines[e], bytes, 48, 36, 16, with);
        free(with);
        csg_blob_free(&b);
    }
    s.lights = NULL;
    csg_scene_free(&s);
}

/* The sample pattern: spp = k*k is the grid of cell centres; any other
 * spp puts exactly one sample in every row and every column of the
 * spp x spp grid (stratified both ways); spp = 1 is the pixel centre. */
static void test_sample_pattern(void **state)
{
    (void)state;
    real ox, oy;
    csg_sample_offset(1, 0, &ox, &oy);
    assert_true(ox == 0.5f && oy == 0.5f);
    csg_sample_offset(4, 3, &ox, &oy);
    assert_true(ox == 0.75f && oy == 0.75f);
    for (int spp = 2; spp <= 64; spp++) {
        int k = (int)sqrt((double)spp);
        if (k * k == spp)
            continue;
        char row[64] = {0}, col[64] = {0};
        for (int s = 0; s < spp; s++) {
            csg_sample_offset(spp, s, &ox, &oy);
            assert_true(ox > 0 && ox < 1 && oy > 0 && oy < 1);
            col[(int)(ox * (real)spp)]++;
            row[(int)(oy * (real)spp)]++;
        }
        for (int i = 0; i < spp; i++)
            assert_true(row[i] == 1 && col[i] == 1);
    }
}

/* Materials are interned by (texture, interior) with a 64-bit key: with
 * 65 536 textures and interiors, the pair (65535, 0) once collided with
 * (0, none) in a 32-bit key (UBSan: signed overflow) and a green sphere
 * took the red sphere's material. */
static void test_material_key_limits(void **state)
{
    (void)state;
    csg_scene s;
    scene_new(&s);
    enum { TEXTURES = 65536, INTERIORS = 65536 };
    s.textures = csg_arena_alloc(s.arena, TEXTURES * sizeof *s.textures);
    s.interiors = csg_arena_alloc(s.arena, INTERIORS * sizeof *s.interiors);
    assert_true(s.textures && s.interiors);
    for (int i = 0; i < TEXTURES; i++)
        csg_texture_default(&s.textures[i]);
    for (int i = 0; i < INTERIORS; i++)
        s.interiors[i].ior = 1.0;
    s.texture_count = TEXTURES;
    s.interior_count = INTERIORS;
    s.textures[0].pigment.rgbft[0] = 1;               /* red   */
    s.textures[TEXTURES - 1].pigment.rgbft[1] = 1;    /* green */
    csg_object *red = sphere(&s, -1, 0, 0, 0.5), *green = sphere(&s, 1, 0, 0, 0.5);
    red->texture = 0;
    green->texture = TEXTURES - 1;
    green->interior = 0;
    add_top(&s, red);
    add_top(&s, green);
    csg_blob b;
    const csg_blob_header *h = flatten_ok(&engine_float, &s, 4, 4, &b);
    const csg_prim *prims = (const csg_prim *)((const char *)b.bytes + h->off_prims);
    const csg_material *mats = (const csg_material *)((const char *)b.bytes + h->off_materials);
    assert_int_equal(h->material_count, 2);
    assert_int_equal(h->prim_count, 2);
    for (int i = 0; i < 2; i++) {
        const csg_material *m = &mats[prims[i].material];
        bool is_green = prims[i].p[0] > 0; /* the sphere at x = 1 */
        assert_true(m->color[0] == (is_green ? 0.0f : 1.0f));
        assert_true(m->color[1] == (is_green ? 1.0f : 0.0f));
    }
    csg_blob_free(&b);
    csg_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_background_only),
        cmocka_unit_test(test_lit_sphere_centre),
        cmocka_unit_test(test_brilliance_metallic),
        cmocka_unit_test(test_tiling_invariance),
        cmocka_unit_test(test_random_determinism),
        cmocka_unit_test(test_crand_law),
        cmocka_unit_test(test_flatten_programs),
        cmocka_unit_test(test_flatten_stack_limit),
        cmocka_unit_test(test_flatten_degenerate),
        cmocka_unit_test(test_blob_validation),
        cmocka_unit_test(test_poly_blob_validation),
        cmocka_unit_test(test_poly_coefficient_range),
        cmocka_unit_test(test_bvh_matches_linear),
        cmocka_unit_test(test_bvh_sah_random),
        cmocka_unit_test(test_shadow_flags),
        cmocka_unit_test(test_sample_pattern),
        cmocka_unit_test(test_material_key_limits),
    };
    return cmocka_run_group_tests_name("engine", tests, NULL, NULL);
}
