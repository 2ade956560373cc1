/*
 * test_ocl.c — the OpenCL primary pass (host/pass/ocl.c, simd_kernels/primary.cl)
 * gives exactly the C records, in both kernel variants (one ray a
 * work-item, and a packet of rays in OpenCL vectors a work-item): for every
 * record, t has the same bits and surf the same id as csg_sample_ray +
 * csg_trace_nearest run in C, in the same precision; the tile counts equal
 * a C count; slicing changes nothing.
 *
 * Scenes are built by hand in a precision-neutral description (sc_scene,
 * doubles), then packed into a flat blob (csg/flatten.h layout) in this
 * file's precision: it is compiled as is (float) and, through
 * tests/test_ocl_double.c, with -DCSG_DOUBLE.  Hand-built blobs have no
 * BVH; random scenes written as POV-Ray text go through the parser and the
 * flattener (a BVH, transforms, CSG, ties, several samples a pixel).
 *
 * One OpenCL context per variant is opened in the group setup and shared
 * by every test (a PoCL build takes seconds when its cache is cold).
 */

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "../csg/device/camera.h"
#include "../csg/device/shadow.h"
#include "../csg/flatten.h"
#include "../csg/lang/parser.h"
#include "../host/pass/ocl.h"
#include "../workers/engine.h"

/* ---- precision-neutral scene description ----------------------------------- */

#define SC_MAX_PRIMS 512
#define SC_MAX_NODES 1024
#define SC_MAX_ROOTS 512

typedef struct {
    int kind, flags;
    double p[8];
    double inv[12];
} sc_prim;

typedef struct {
    int op, prim;
} sc_node;

typedef struct {
    int first, count, depth;
    double lo[3], hi[3];
} sc_root;

typedef struct {
    sc_prim prims[SC_MAX_PRIMS];
    sc_node nodes[SC_MAX_NODES];
    sc_root roots[SC_MAX_ROOTS];
    int np, nn, nr;
    int open_root;   /* index of the root being built, -1 none */
    int open_depth;  /* its current stack height             */
    double cam[12];  /* location, direction, right, up       */
    int width, height;
} sc_scene;

static sc_scene *sc_new(int width, int height)
{
    sc_scene *s = calloc(1, sizeof *s);
    assert_non_null(s);
    s->open_root = -1;
    s->width = width;
    s->height = height;
    double cam[12] = {0, 0.5, -6, 0, 0, 1, (double)width / (double)height, 0, 0, 0, 1, 0};
    memcpy(s->cam, cam, sizeof cam);
    return s;
}

static int sc_prim_add(sc_scene *s, int kind, int flags, const double *p, int np)
{
    assert_true(s->np < SC_MAX_PRIMS);
    sc_prim *q = &s->prims[s->np];
    q->kind = kind;
    q->flags = flags;
    for (int i = 0; i < np; i++)
        q->p[i] = p[i];
    return s->np++;
}

/* World -> local of "rotate by `deg` degrees about axis (0 x, 1 y, 2 z),
 * then translate by t": local = R^T (w - t). */
static void sc_prim_xform(sc_scene *s, int prim, int axis, double deg, double tx, double ty,
                          double tz)
{
    double a = deg * 3.14159265358979323846 / 180.0, c = cos(a), sn = sin(a);
    double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    int i = (axis + 1) % 3, j = (axis + 2) % 3;
    r[i][i] = c;
    r[i][j] = -sn;
    r[j][i] = sn;
    r[j][j] = c;
    double t[3] = {tx, ty, tz};
    sc_prim *q = &s->prims[prim];
    for (int row = 0; row < 3; row++) {
        double off = 0;
        for (int col = 0; col < 3; col++) {
            q->inv[row * 4 + col] = r[col][row]; /* the transpose */
            off -= r[col][row] * t[col];
        }
        q->inv[row * 4 + 3] = off;
    }
    q->flags |= CSG_PF_XFORM;
}

static void sc_begin(sc_scene *s)
{
    assert_true(s->nr < SC_MAX_ROOTS && s->open_root < 0);
    sc_root *r = &s->roots[s->nr];
    r->first = s->nn;
    r->count = 0;
    r->depth = 0;
    for (int a = 0; a < 3; a++) {
        r->lo[a] = -INFINITY;
        r->hi[a] = INFINITY;
    }
    s->open_root = s->nr++;
    s->open_depth = 0;
}

static void sc_node_add(sc_scene *s, int op, int prim)
{
    assert_true(s->nn < SC_MAX_NODES && s->open_root >= 0);
    sc_root *r = &s->roots[s->open_root];
    s->nodes[s->nn].op = op;
    s->nodes[s->nn].prim = prim;
    s->nn++;
    r->count++;
    s->open_depth += op == CSG_OP_PRIM ? 1 : -1;
    assert_true(s->open_depth >= 1 && s->open_depth <= CSG_STACK_MAX);
    if (s->open_depth > r->depth)
        r->depth = s->open_depth;
}

static void sc_leaf(sc_scene *s, int prim) { sc_node_add(s, CSG_OP_PRIM, prim); }
static void sc_op(sc_scene *s, int op) { sc_node_add(s, op, -1); }

static void sc_end(sc_scene *s)
{
    assert_int_equal(s->open_depth, 1);
    s->open_root = -1;
}

static void sc_end_box(sc_scene *s, const double lo[3], const double hi[3])
{
    sc_root *r = &s->roots[s->open_root];
    memcpy(r->lo, lo, sizeof r->lo);
    memcpy(r->hi, hi, sizeof r->hi);
    sc_end(s);
}

/* A root made of one primitive. */
static int sc_solo(sc_scene *s, int kind, int flags, const double *p, int np)
{
    int i = sc_prim_add(s, kind, flags, p, np);
    sc_begin(s);
    sc_leaf(s, i);
    sc_end(s);
    return i;
}

static void sc_sphere(sc_scene *s, double x, double y, double z, double r, int bounded)
{
    double p[4] = {x, y, z, r};
    int i = sc_prim_add(s, CSG_PRIM_SPHERE, 0, p, 4);
    sc_begin(s);
    sc_leaf(s, i);
    if (bounded) {
        double lo[3] = {x - r, y - r, z - r}, hi[3] = {x + r, y + r, z + r};
        sc_end_box(s, lo, hi);
    } else {
        sc_end(s);
    }
}

/* ---- precision-dependent part, compiled twice ------------------------------------ */

typedef struct {
    void *(*make_blob)(const sc_scene *s, size_t *size);
    /* C records of the whole image and C tile counts */
    void (*reference)(const void *blob, void *t, uint32_t *surf);
    size_t real_size;
    const char *name;
} precision_ops;

static size_t align64(size_t n) { return (n + 63) & ~(size_t)63; }

/* The sizes come from the structs of this file's precision. */
static void blob_header(const sc_scene *s, csg_blob_header *h, uint32_t real_size,
                        size_t prim_size, size_t root_size, size_t camera_size,
                        size_t material_size, size_t shading_size)
{
    memset(h, 0, sizeof *h);
    h->magic = CSG_BLOB_MAGIC;
    h->real_size = real_size;
    h->width = s->width;
    h->height = s->height;
    h->max_depth = 1;
    h->prim_count = s->np;
    h->node_count = s->nn;
    h->root_count = s->nr;
    h->linear_roots = s->nr; /* hand-built scenes have no BVH */
    h->material_count = 1;   /* every primitive uses material 0 */
    h->spp = 1;
    h->max_stack = 1;
    for (int i = 0; i < s->nr; i++)
        if (s->roots[i].depth > h->max_stack)
            h->max_stack = s->roots[i].depth;
    size_t off = align64(sizeof *h);
    h->off_prims = off;
    off = align64(off + (size_t)s->np * prim_size);
    h->off_nodes = off;
    off = align64(off + (size_t)s->nn * sizeof(csg_node));
    h->off_roots = off;
    off = align64(off + (size_t)s->nr * root_size);
    h->off_materials = off;
    off = align64(off + material_size);
    h->off_lights = off;
    h->off_bvh = off;
    h->off_camera = off;
    off = align64(off + camera_size);
    h->off_shading = off;
    h->total_size = off + shading_size;
}

static void *make_blob(const sc_scene *s, size_t *size);
static void reference(const void *blob, void *t, uint32_t *surf);

#ifdef CSG_DOUBLE
static const precision_ops prec = {make_blob, reference, 8, "double"};
#else
static const precision_ops prec = {make_blob, reference, 4, "float"};
#endif

/* ---- the comparison ----------------------------------------------------------------- */

/* The kernel variants every comparison runs. */
#define VARIANTS 2
static const enum ocl_kernel variant_kernel[VARIANTS] = {OCL_KERNEL_SCALAR, OCL_KERNEL_PACKET};

typedef struct {
    ocl_ctx *ctx[VARIANTS]; /* built for this file's precision, per variant */
} fixture;

static double real_at(const void *t, size_t i, size_t rs)
{
    if (rs == 4) {
        float f;
        memcpy(&f, (const char *)t + i * 4, 4);
        return (double)f;
    }
    double x;
    memcpy(&x, (const char *)t + i * 8, 8);
    return x;
}

/* Tile counts of records (spp a pixel, side by side). */
static void c_tile_hits(const uint32_t *surf, int w, int h, int spp, int tile, uint32_t *hits)
{
    int tx = (w + tile - 1) / tile, ty = (h + tile - 1) / tile;
    memset(hits, 0, (size_t)tx * (size_t)ty * sizeof *hits);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w * spp; x++)
            if (surf[(size_t)y * (size_t)w * (size_t)spp + (size_t)x] != CSG_SURF_NONE)
                hits[(y / tile) * tx + x / spp / tile]++;
}

/* Runs the pass on ctx over a blob and compares with C: records bit for
 * bit, tile counts for `tile`.  Returns the number of records that hit. */
static size_t check_blob(ocl_ctx *ctx, const precision_ops *ops, const void *blob, int tile)
{
    const csg_blob_header *bh = blob;
    int width = bh->width, height = bh->height, spp = bh->spp;
    size_t n = (size_t)width * (size_t)height * (size_t)spp, rs = ops->real_size;
    void *t_ref = malloc(n * rs), *t_cl = malloc(n * rs);
    uint32_t *s_ref = malloc(n * 4), *s_cl = malloc(n * 4);
    int tx = (width + tile - 1) / tile, ty = (height + tile - 1) / tile;
    uint32_t *h_ref = malloc((size_t)tx * (size_t)ty * 4), *h_cl = malloc((size_t)tx * (size_t)ty * 4);
    assert_true(t_ref && t_cl && s_ref && s_cl && h_ref && h_cl);
    memset(t_cl, 0xA5, n * rs);
    memset(s_cl, 0xA5, n * 4);
    memset(h_cl, 0xA5, (size_t)tx * (size_t)ty * 4);

    ops->reference(blob, t_ref, s_ref);
    c_tile_hits(s_ref, width, height, spp, tile, h_ref);
    ocl_timing timing = {0};
    csg_diag d = {0};
    if (!ocl_primary_pass(ctx, blob, tile, t_cl, s_cl, h_cl, &timing, &d))
        fail_msg("ocl_primary_pass: %s", d.message);

    size_t bad = 0, hits = 0;
    for (size_t i = 0; i < n; i++) {
        hits += s_ref[i] != CSG_SURF_NONE;
        if (memcmp((char *)t_ref + i * rs, (char *)t_cl + i * rs, rs) == 0 && s_ref[i] == s_cl[i])
            continue;
        if (bad++ < 5)
            print_error("%s %dx%d spp %d record (%zu, %zu): C t=%.17g surf=%u, OpenCL t=%.17g "
                        "surf=%u\n",
                        ops->name, width, height, spp, i % ((size_t)width * (size_t)spp),
                        i / ((size_t)width * (size_t)spp), real_at(t_ref, i, rs),
                        (unsigned)s_ref[i], real_at(t_cl, i, rs), (unsigned)s_cl[i]);
    }
    size_t bad_tiles = 0;
    for (size_t i = 0; i < (size_t)tx * (size_t)ty; i++)
        if (h_ref[i] != h_cl[i] && bad_tiles++ < 5)
            print_error("%s tile %zu (size %d): C %u hits, OpenCL %u\n", ops->name, i, tile,
                        (unsigned)h_ref[i], (unsigned)h_cl[i]);
    free(t_ref);
    free(t_cl);
    free(s_ref);
    free(s_cl);
    free(h_ref);
    free(h_cl);
    assert_int_equal(bad, 0);
    assert_int_equal(bad_tiles, 0);
    return hits;
}

/* check_blob on the hand-built scene s. */
static size_t check_pass(ocl_ctx *ctx, const precision_ops *ops, const sc_scene *s, int tile)
{
    size_t size = 0;
    void *blob = ops->make_blob(s, &size);
    assert_non_null(blob);
    size_t hits = check_blob(ctx, ops, blob, tile);
    free(blob);
    return hits;
}

/* ocl_open_kernel(kernel) with the default options, the context closed. */
static bool open_variant(enum ocl_kernel kernel, ocl_timing *timing, csg_diag *d)
{
    ocl_options opt = {0};
    ocl_ctx *ctx = NULL;
    bool ok = ocl_open_kernel(&opt, kernel, &ctx, timing, d);
    ocl_close(ctx);
    return ok;
}

/* Both precisions, three image sizes; the scene must hit somewhere (and
 * miss somewhere, unless it encloses the camera) at 100 x 37, else the
 * comparison would prove little. */
static void check_scene_all(void **state, void (*build)(sc_scene *s), bool encloses)
{
    fixture *fx = *state;
    static const int sizes[3][2] = {{1, 1}, {33, 17}, {100, 37}};
    for (int k = 0; k < 3; k++)
        for (int v = 0; v < VARIANTS; v++) {
            sc_scene *s = sc_new(sizes[k][0], sizes[k][1]);
            build(s);
            size_t hits = check_pass(fx->ctx[v], &prec, s, 8);
            if (k == 2) {
                assert_true(hits > 0);
                assert_true(encloses || hits < (size_t)s->width * (size_t)s->height);
            }
            free(s);
        }
}

/* ---- scenes ----------------------------------------------------------------------- */

static void build_spheres(sc_scene *s)
{
    sc_sphere(s, 0, 0.5, 0, 1, 1);
    sc_sphere(s, 1.2, 0.3, 0.5, 0.8, 1);   /* overlaps the first */
    sc_sphere(s, -2, -0.5, 2, 0.7, 0);     /* unbounded root box */
    sc_sphere(s, 0.4, 1.4, -3, 0.05, 1);   /* small and near     */
    sc_sphere(s, 0, 0.5, -6, 30, 1);       /* the camera is inside: seen from within */
}

static void build_spheres_outside(sc_scene *s)
{
    sc_sphere(s, 0, 0.5, 0, 1, 1);
    sc_sphere(s, 1.2, 0.3, 0.5, 0.8, 1);
    sc_sphere(s, -2, -0.5, 2, 0.7, 0);
    sc_sphere(s, 0.4, 1.4, -3, 0.05, 1);
}

static void build_boxes(sc_scene *s)
{
    double a[6] = {-1, -1, -1, 0.5, 0.2, 1};
    sc_solo(s, CSG_PRIM_BOX, 0, a, 6);
    double b[6] = {-0.5, -0.5, -0.5, 0.5, 0.5, 0.5};
    int i = sc_solo(s, CSG_PRIM_BOX, 0, b, 6);
    sc_prim_xform(s, i, 1, 35, 1.6, 1.0, 0.5);
    double c[6] = {-3, -2, 3, 3, -1.5, 4}; /* a flat slab behind */
    int j = sc_solo(s, CSG_PRIM_BOX, 0, c, 6);
    sc_prim_xform(s, j, 2, 20, 0, 0, 0);
}

/* Boxes of zero thickness (sheets, CSG_PRIM_FLAT_BOX): flat in z, in x
 * and in y, the last at the camera's height (the middle row of an image
 * with an odd height runs in its plane); turned; a sheet cut by a sphere
 * (intersection) and with a hole (difference: the sphere complemented);
 * a solid box with a complemented sheet (the sheet inside it); a box
 * flat in two axes (a segment). */
static void build_flat_boxes(sc_scene *s)
{
    double fz[6] = {-2.5, -1, 0, -1, 1, 0};
    sc_solo(s, CSG_PRIM_FLAT_BOX, 0, fz, 6);
    double fx[6] = {0, -0.5, -0.5, 0, 0.5, 0.5};
    int i = sc_solo(s, CSG_PRIM_FLAT_BOX, 0, fx, 6);
    sc_prim_xform(s, i, 1, 50, -0.6, 0.3, 0.5);
    double fy[6] = {-4, 0.5, 1, 4, 0.5, 5};
    sc_solo(s, CSG_PRIM_FLAT_BOX, 0, fy, 6);
    double disc[6] = {0.3, -0.3, -0.2, 1.9, -0.3, 0.6}, ball[4] = {1.1, -0.3, 0.2, 0.6};
    double sheet[6] = {-1, -1, 0, 1, 1, 0}, hole[4] = {0, 0, 0, 0.4};
    int id = sc_prim_add(s, CSG_PRIM_FLAT_BOX, 0, disc, 6);
    int ib = sc_prim_add(s, CSG_PRIM_SPHERE, 0, ball, 4);
    sc_begin(s);
    sc_leaf(s, id);
    sc_leaf(s, ib);
    sc_op(s, CSG_OP_INTERSECT);
    sc_end(s);
    int is = sc_prim_add(s, CSG_PRIM_FLAT_BOX, 0, sheet, 6);
    sc_prim_xform(s, is, 0, -30, 2.2, 1.2, 1);
    int ih = sc_prim_add(s, CSG_PRIM_SPHERE, CSG_PF_INVERT, hole, 4);
    sc_prim_xform(s, ih, 0, -30, 2.2, 1.2, 1);
    sc_begin(s);
    sc_leaf(s, is);
    sc_leaf(s, ih);
    sc_op(s, CSG_OP_INTERSECT);
    sc_end(s);
    double solid[6] = {-3, 1.2, -1, -2, 2, 0}, cut[6] = {-4, 1.6, -2, -1, 1.6, 1};
    int jb = sc_prim_add(s, CSG_PRIM_BOX, 0, solid, 6);
    int jc = sc_prim_add(s, CSG_PRIM_FLAT_BOX, CSG_PF_INVERT, cut, 6);
    sc_begin(s);
    sc_leaf(s, jb);
    sc_leaf(s, jc);
    sc_op(s, CSG_OP_INTERSECT);
    sc_end(s);
    double segment[6] = {-3, -0.5, 2, 3, -0.5, 2};
    sc_solo(s, CSG_PRIM_FLAT_BOX, 0, segment, 6);
}

static void build_cones(sc_scene *s)
{
    double cone[3] = {0.8, 0.2, 1.5};
    int i = sc_solo(s, CSG_PRIM_CONE, 0, cone, 3);
    sc_prim_xform(s, i, 0, -90, -1.2, -0.5, 0.5); /* axis up */
    double cyl[3] = {0.4, 0.4, 2.0};
    int j = sc_solo(s, CSG_PRIM_CONE, 0, cyl, 3);
    sc_prim_xform(s, j, 1, 60, 0.5, 0.8, 0);
    double open[3] = {0.5, 0.5, 1.2};
    int k = sc_solo(s, CSG_PRIM_CONE, CSG_PF_OPEN, open, 3);
    sc_prim_xform(s, k, 0, 30, 1.5, -0.6, -0.5); /* inside visible through the open end */
    double apex[3] = {0.6, 0.0, 1.0};            /* a pointed cone */
    int m = sc_solo(s, CSG_PRIM_CONE, 0, apex, 3);
    sc_prim_xform(s, m, 2, 0, -2.2, 1.2, 1);
}

static void build_planes(sc_scene *s)
{
    double floor[4] = {0, 1, 0, -1}; /* y < -1 */
    sc_solo(s, CSG_PRIM_PLANE, 0, floor, 4);
    double n = 1.0 / sqrt(2.0);
    double tilted[4] = {n, 0, -n, -3};
    sc_solo(s, CSG_PRIM_PLANE, 0, tilted, 4);
    sc_sphere(s, 0, 0, 0, 0.9, 1);
    double sky[4] = {0, -1, 0, -4}; /* y > 4, camera outside */
    sc_solo(s, CSG_PRIM_PLANE, 0, sky, 4);
}

static void build_csg(sc_scene *s)
{
    /* union of two spheres */
    double a[4] = {-1.5, 1, 0, 0.8}, b[4] = {-0.9, 1.2, 0.2, 0.7};
    int ia = sc_prim_add(s, CSG_PRIM_SPHERE, 0, a, 4), ib = sc_prim_add(s, CSG_PRIM_SPHERE, 0, b, 4);
    sc_begin(s);
    sc_leaf(s, ia);
    sc_leaf(s, ib);
    sc_op(s, CSG_OP_UNION);
    sc_end(s);
    /* intersection of a sphere and a box */
    double c[4] = {1.2, 1, 0, 1}, box[6] = {0.5, 0.2, -0.6, 2.0, 1.6, 0.6};
    int ic = sc_prim_add(s, CSG_PRIM_SPHERE, 0, c, 4);
    int ibox = sc_prim_add(s, CSG_PRIM_BOX, 0, box, 6);
    sc_begin(s);
    sc_leaf(s, ic);
    sc_leaf(s, ibox);
    sc_op(s, CSG_OP_INTERSECT);
    sc_end(s);
    /* difference: box minus a sphere minus a cylinder (inverted leaves) */
    double e[6] = {-1, -1.5, -0.5, 1, -0.2, 0.5}, f[4] = {0, -0.5, -0.6, 0.6};
    double cyl[3] = {0.25, 0.25, 3};
    int ie = sc_prim_add(s, CSG_PRIM_BOX, 0, e, 6);
    int jf = sc_prim_add(s, CSG_PRIM_SPHERE, CSG_PF_INVERT, f, 4);
    int kc = sc_prim_add(s, CSG_PRIM_CONE, CSG_PF_INVERT, cyl, 3);
    sc_prim_xform(s, kc, 1, 90, -1.5, -0.9, 0);
    sc_begin(s);
    sc_leaf(s, ie);
    sc_leaf(s, jf);
    sc_op(s, CSG_OP_INTERSECT);
    sc_leaf(s, kc);
    sc_op(s, CSG_OP_INTERSECT);
    double lo[3] = {-1, -1.5, -0.5}, hi[3] = {1, -0.2, 0.5};
    sc_end_box(s, lo, hi);
    /* a deeper program: (A ∪ B) ∩ ¬(C ∪ D) with D a plane, depth 3 */
    double g[4] = {2.2, -0.8, 0, 0.7}, h2[4] = {2.6, -0.5, 0.3, 0.6};
    double k2[4] = {2.4, -0.6, -0.6, 0.4}, pl[4] = {0, 1, 0, -1.0};
    int ig = sc_prim_add(s, CSG_PRIM_SPHERE, 0, g, 4);
    int ih = sc_prim_add(s, CSG_PRIM_SPHERE, 0, h2, 4);
    int ik = sc_prim_add(s, CSG_PRIM_SPHERE, CSG_PF_INVERT, k2, 4);
    int ip = sc_prim_add(s, CSG_PRIM_PLANE, CSG_PF_INVERT, pl, 4);
    sc_begin(s);
    sc_leaf(s, ig);
    sc_leaf(s, ih);
    sc_op(s, CSG_OP_UNION);
    sc_leaf(s, ik);
    sc_leaf(s, ip);
    sc_op(s, CSG_OP_INTERSECT); /* ¬C ∩ ¬D = ¬(C ∪ D) */
    sc_op(s, CSG_OP_INTERSECT);
    sc_end(s);
    /* an inverted leaf alone: everything outside a big sphere around the
     * camera is solid, seen from inside */
    double big[4] = {0, 0.5, -6, 40};
    sc_solo(s, CSG_PRIM_SPHERE, CSG_PF_INVERT, big, 4);
}

/* A small deterministic generator (no libc rand: same numbers everywhere). */
static double lcg(uint64_t *st)
{
    *st = *st * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*st >> 11) / 9007199254740992.0;
}

static void build_random(sc_scene *s)
{
    uint64_t st = 12345;
    for (int i = 0; i < 300; i++) {
        double x = lcg(&st) * 8 - 4, y = lcg(&st) * 5 - 2, z = lcg(&st) * 10;
        double r = 0.02 + lcg(&st) * 0.3;
        sc_sphere(s, x, y, z, r, 1);
    }
}

static void build_empty(sc_scene *s) { (void)s; }

/* ---- random scenes through the parser and the flattener ---------------------------- */

/* Appends printf-style text to a growing buffer. */
typedef struct {
    char *text;
    size_t len, cap;
} sdl_buf;

static void sdl(sdl_buf *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    assert_true(n >= 0);
    if (b->len + (size_t)n + 1 > b->cap) {
        b->cap = (b->len + (size_t)n + 1) * 2;
        b->text = realloc(b->text, b->cap);
        assert_non_null(b->text);
    }
    va_start(ap, fmt);
    vsnprintf(b->text + b->len, b->cap - b->len, fmt, ap);
    va_end(ap);
    b->len += (size_t)n;
}

static double rnd(uint64_t *st, double lo, double hi) { return lo + (hi - lo) * lcg(st); }

/* One random primitive, as POV-Ray SDL, around (cx, cy, cz). */
static void sdl_prim(sdl_buf *b, uint64_t *st, double cx, double cy, double cz, double size)
{
    double r = size * rnd(st, 0.3, 1.0);
    switch ((int)(lcg(st) * 4)) {
    case 0:
        sdl(b, "sphere { <%.6f, %.6f, %.6f>, %.6f }\n", cx, cy, cz, r);
        break;
    case 1:
        sdl(b, "box { <%.6f, %.6f, %.6f>, <%.6f, %.6f, %.6f> rotate <%.1f, %.1f, %.1f> "
               "translate <%.6f, %.6f, %.6f> }\n",
            -r, -r * rnd(st, 0.3, 1), -r, r * rnd(st, 0.3, 1), r, r, rnd(st, 0, 90),
            rnd(st, 0, 90), rnd(st, 0, 90), cx, cy, cz);
        break;
    case 2:
        sdl(b, "cone { <%.6f, %.6f, %.6f>, %.6f, <%.6f, %.6f, %.6f>, %.6f%s }\n", cx, cy - r, cz,
            r * rnd(st, 0.2, 0.8), cx + rnd(st, -r, r), cy + r, cz, r * rnd(st, 0, 0.5),
            lcg(st) < 0.3 ? " open" : "");
        break;
    default:
        sdl(b, "cylinder { <%.6f, %.6f, %.6f>, <%.6f, %.6f, %.6f>, %.6f scale <1, %.3f, 1> }\n",
            cx - r, cy, cz, cx + r, cy + rnd(st, -r, r), cz + rnd(st, -r, r), r * 0.4,
            rnd(st, 0.5, 1.5));
        break;
    }
}

/* A random scene: primitives, CSG objects (union, intersection,
 * difference, inverse), planes, duplicated objects (coincident surfaces:
 * ties the nearest-hit rule must break the same way), transforms. */
static char *random_sdl(uint64_t seed, int objects)
{
    uint64_t st = seed * 7919 + 17;
    sdl_buf b = {NULL, 0, 0};
    sdl(&b, "camera { location <%.3f, 1.5, -9> look_at <0, 0, 0> }\n", rnd(&st, -1, 1));
    sdl(&b, "light_source { <5, 10, -5> color rgb 1 }\n");
    if (lcg(&st) < 0.6)
        sdl(&b, "plane { <%.3f, 1, %.3f>, -2.5 }\n", rnd(&st, -0.3, 0.3), rnd(&st, -0.3, 0.3));
    for (int i = 0; i < objects; i++) {
        double cx = rnd(&st, -4, 4), cy = rnd(&st, -2, 2), cz = rnd(&st, -1, 6);
        double size = rnd(&st, 0.2, 0.9);
        size_t mark = b.len;
        double kind = lcg(&st);
        if (kind < 0.6) {
            sdl_prim(&b, &st, cx, cy, cz, size);
        } else {
            static const char *const ops[] = {"union", "intersection", "difference", "merge"};
            sdl(&b, "%s {\n", ops[(int)(lcg(&st) * 4)]);
            int n = 2 + (int)(lcg(&st) * 2);
            for (int k = 0; k < n; k++)
                sdl_prim(&b, &st, cx + rnd(&st, -0.4, 0.4), cy + rnd(&st, -0.4, 0.4),
                         cz + rnd(&st, -0.4, 0.4), size);
            sdl(&b, "%s rotate <0, %.1f, 0> }\n", lcg(&st) < 0.1 ? "inverse" : "",
                rnd(&st, 0, 180));
        }
        if (lcg(&st) < 0.1) { /* the same object again */
            size_t len = b.len - mark;
            char *copy = malloc(len + 1);
            assert_non_null(copy);
            memcpy(copy, b.text + mark, len);
            copy[len] = '\0';
            sdl(&b, "%s", copy);
            free(copy);
        }
    }
    return b.text;
}

/* The blob of scene text `text` (named `name` in messages) in this
 * file's precision. */
static csg_blob text_blob(const char *name, const char *text, int width, int height, int spp)
{
    csg_scene sc;
    csg_diag d = {0};
    csg_blob blob = {NULL, 0};
    csg_scene_init(&sc);
    csg_flatten_opts o = {width, height, 0, -1, spp, 0};
#ifdef CSG_DOUBLE
    bool ok = csg_parse_string(name, text, strlen(text), &sc, &d) &&
              csg_flatten_double(&sc, &o, &blob, &d);
#else
    bool ok = csg_parse_string(name, text, strlen(text), &sc, &d) &&
              csg_flatten_float(&sc, &o, &blob, &d);
#endif
    csg_scene_free(&sc);
    if (!ok)
        fail_msg("%s: %s\n%s", name, d.message, text);
    return blob;
}

/* The blob of a random scene in this file's precision. */
static csg_blob random_blob(uint64_t seed, int objects, int width, int height, int spp)
{
    char *text = random_sdl(seed, objects);
    char name[64];
    snprintf(name, sizeof name, "random scene %llu", (unsigned long long)seed);
    csg_blob blob = text_blob(name, text, width, height, spp);
    free(text);
    return blob;
}

/* The blob of the scene file `path` (relative to the source tree), or of
 * the scene text `text` when given. */
static csg_blob file_blob(const char *path, const char *text, int width, int height)
{
    const char *full = path; /* (the tests run in the source tree: tests/run.sh) */
    csg_scene sc;
    csg_diag d = {0};
    csg_blob blob = {NULL, 0};
    csg_scene_init(&sc);
    csg_flatten_opts o = {width, height, 0, -1, 1, 0};
    bool ok = text ? csg_parse_string(path, text, strlen(text), &sc, &d)
                   : csg_parse_file(full, &sc, &d);
#ifdef CSG_DOUBLE
    ok = ok && csg_flatten_double(&sc, &o, &blob, &d);
#else
    ok = ok && csg_flatten_float(&sc, &o, &blob, &d);
#endif
    csg_scene_free(&sc);
    if (!ok)
        fail_msg("%s: %s", full, d.message);
    return blob;
}

/* Both variants of the program specialised on the blob's feature set
 * (csg/device/spec.h) give the C records, as the general program does. */
static void check_specialised(void **state, const void *blob, const char *what)
{
    fixture *fx = *state;
    csg_features f = csg_blob_features(blob);
    ocl_options opt = {.use_double = prec.real_size == 8, .features = &f};
    for (int v = 0; v < VARIANTS; v++) {
        ocl_ctx *ctx = NULL;
        ocl_timing timing = {0};
        csg_diag d = {0};
        if (!ocl_open_kernel(&opt, variant_kernel[v], &ctx, &timing, &d))
            fail_msg("%s: the specialised program: %s", what, d.message);
        csg_features built = ocl_features(ctx), spec = csg_features_specialised(f);
        assert_int_equal(built.kinds, spec.kinds);
        assert_int_equal(built.uses, spec.uses);
        check_blob(ctx, &prec, blob, 8);
        check_blob(fx->ctx[v], &prec, blob, 8);
        ocl_close(ctx);
    }
}

/* Scenes of every kind: the example scenes (CSG, transforms, each solid
 * kind, a sphere-and-plane scene without either), triangles and a mesh,
 * and hand-built scenes of one kind each. */
static void test_specialised(void **state)
{
    static const char *const files[] = {"scenes/spheres_grid.pov", "scenes/primitives.pov",
                                        "scenes/csg_ops.pov", "scenes/glass.pov"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        csg_blob blob = file_blob(files[i], NULL, 40, 30);
        check_specialised(state, blob.bytes, files[i]);
        csg_blob_free(&blob);
    }
    static const char mesh[] =
        "camera { location <0.3, 0.4, -3> look_at <0.3, 0.3, 0> }\n"
        "mesh { triangle { <-1, -1, 0>, <1, -1, 0>, <0, 1, 0.5> }\n"
        "  smooth_triangle { <1, -1, 0>, <0, 0, -1>, <1.5, 1, 0>, <0, 0.3, -1>,\n"
        "                    <0, 1, 0.5>, <0.2, 0, -1> } }\n";
    csg_blob tris = file_blob("mesh.pov", mesh, 40, 30);
    assert_int_equal(csg_blob_features(tris.bytes).kinds,
                     (1u << CSG_PRIM_TRIANGLE) | (1u << CSG_PRIM_SMOOTH_TRIANGLE));
    check_specialised(state, tris.bytes, "a mesh");
    csg_blob_free(&tris);
    void (*builds[])(sc_scene *) = {build_boxes, build_cones, build_planes};
    for (size_t i = 0; i < sizeof builds / sizeof builds[0]; i++) {
        sc_scene *s = sc_new(40, 30);
        builds[i](s);
        size_t size;
        void *blob = prec.make_blob(s, &size);
        check_specialised(state, blob, "a hand-built scene");
        free(blob);
        free(s);
    }
}

/* A program specialised on spheres refuses a scene with a box, with a
 * message; ocl_specialise rebuilds it for the box, and it then gives the
 * C records; a scene it covers needs no rebuild. */
static void test_specialised_refuses(void **state)
{
    (void)state;
    sc_scene *spheres = sc_new(16, 12), *boxes = sc_new(16, 12);
    build_spheres(spheres);
    build_boxes(boxes);
    size_t size;
    void *bs = prec.make_blob(spheres, &size), *bb = prec.make_blob(boxes, &size);
    csg_features f = csg_blob_features(bs);
    ocl_options opt = {.use_double = prec.real_size == 8, .features = &f};
    ocl_ctx *ctx = NULL;
    ocl_timing timing = {0};
    csg_diag d = {0};
    if (!ocl_open_kernel(&opt, OCL_KERNEL_PACKET, &ctx, &timing, &d))
        fail_msg("ocl_open: %s", d.message);
    double t[16 * 12];
    uint32_t surf[16 * 12], hits[4];
    assert_false(ocl_primary_pass(ctx, bb, 8, t, surf, hits, &timing, &d));
    assert_non_null(strstr(d.message, "specialised"));
    csg_diag d2 = {0};
    timing.compile_s = 0;
    assert_true(ocl_specialise(ctx, csg_blob_features(bb), &timing, &d2));
    assert_true(timing.compile_s > 0);
    check_blob(ctx, &prec, bb, 8);
    csg_features built = ocl_features(ctx);
    assert_true(csg_features_cover(built, csg_features_specialised(csg_blob_features(bb))));
    ocl_close(ctx);
    free(bs);
    free(bb);
    free(spheres);
    free(boxes);
}

/* ---- tests -------------------------------------------------------------------------- */

static void test_spheres(void **state) { check_scene_all(state, build_spheres, true); }
static void test_boxes(void **state) { check_scene_all(state, build_boxes, false); }
static void test_cones(void **state) { check_scene_all(state, build_cones, false); }
static void test_flat_boxes(void **state) { check_scene_all(state, build_flat_boxes, false); }
static void test_planes(void **state) { check_scene_all(state, build_planes, false); }
static void test_csg(void **state) { check_scene_all(state, build_csg, true); }
static void test_spheres_outside(void **state)
{
    check_scene_all(state, build_spheres_outside, false);
}
static void test_random_spheres(void **state) { check_scene_all(state, build_random, false); }

/* Random scenes through the flattener (a BVH over the bounded roots, CSG,
 * transforms, planes, ties), one and several samples a pixel, image sizes
 * that cut packets: both variants give the C records. */
static void test_random_flattened(void **state)
{
    fixture *fx = *state;
    static const struct {
        int objects, width, height, spp;
    } cases[] = {{12, 61, 37, 1}, {40, 64, 48, 1}, {120, 53, 29, 1},
                 {25, 31, 19, 3}, {25, 26, 17, 4}, {60, 40, 30, 2}};
    int with_bvh = 0;
    for (uint64_t seed = 1; seed <= 4; seed++)
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            csg_blob blob = random_blob(seed * 31 + c, cases[c].objects, cases[c].width,
                                        cases[c].height, cases[c].spp);
            with_bvh += csg_blob_hdr(blob.bytes)->bvh_count > 1;
            size_t total = (size_t)cases[c].width * (size_t)cases[c].height * (size_t)cases[c].spp;
            for (int v = 0; v < VARIANTS; v++) {
                size_t hits = check_blob(fx->ctx[v], &prec, blob.bytes, 8);
                assert_true(hits > 0 && hits < total);
            }
            csg_blob_free(&blob);
        }
    assert_true(with_bvh > 0);
}

/* Sheets (boxes of zero thickness) through the parser and the flattener:
 * in world space and under transforms, as CSG operands, in a BVH, several
 * samples a pixel: both variants give the C records, and the sheets are
 * seen (the same scene without them hits fewer records). */
static const char flat_sdl[] =
    "camera { location <0.3, 1.5, -9> look_at <0, 0, 0> }\n"
    "box { <-5, -2, -3>, <5, -2, 9> }\n"
    "box { <-3, -1, 0>, <-1, 1, 0> }\n"
    "box { <0, -1, -1>, <0, 1, 1> rotate y * 60 translate <-0.5, 0, 2> }\n"
    "box { <1, 1, 0>, <2, 2, 0> matrix <1, 0.3, 0, 0, 1, 0, 0.4, 0, 1, 0, 0, 0> scale <1.5, 1, 2> }\n"
    "intersection { box { <-1, 0, 0>, <1, 0, 2> } sphere { <0, 0, 1>, 0.8 } translate <2, -1, 0> }\n"
    "difference { box { -1, <1, 1, -1> } sphere { <0, 0, -1>, 0.5 } rotate x * -25 translate <3, 1, 3> }\n"
    "difference { box { -0.5, 0.5 } box { <-1, 0, -1>, <1, 0, 1> } translate <0, 2, 1> }\n"
    "merge { sphere { 0, 0.4 } box { <-0.7, -0.7, 0>, <0.7, 0.7, 0> } translate <-3, 2.2, 1> }\n"
    "union { sphere { 0, 0.3 } box { <-0.6, 0, -0.6>, <0.6, 0, 0.6> } translate <0.5, -1.5, -2> }\n";

/* Prisms and text (trapezoid pieces, CSG_PRIM_TRAPEZOID and
 * CSG_PRIM_CONIC_TRAPEZOID): glyphs seen from the side and at a slant
 * (rays along the pieces' shared walls and slab heights), prisms of the
 * splines and sweeps, a text in a difference; every
 * record equals C's in both variants, the general and the specialised
 * program. */
static void test_extrusions(void **state)
{
    fixture *fx = *state;
    static const char sdl[] =
        "camera { location <1.2, 1.0, -2.6> look_at <1.1, 0.3, 0> angle 55 }\n"
        "difference { text { ttf \"cyrvetic.ttf\" \"Bag\" 0.5, <0.05, 0.02, 0> }\n"
        "  cylinder { <-1, 0.35, 0.25>, <3, 0.35, 0.25>, 0.12 } }\n"
        "text { ttf \"timrom.ttf\" \"AVo%\" 0.2, 0 scale 0.5 rotate <10, -40, 0>\n"
        "  translate <1.2, 0.8, 0.3> }\n"
        "prism { quadratic_spline 0, 0.3, 6, <1, 0>, <0, -1>, <-1, 0>, <0, 1>, <0, -1>, <-1, 0>\n"
        "  scale 0.3 translate <2.2, 0, -0.5> }\n"
        "prism { bezier_spline 0, 0.2, 8, <0, 0>, <1, 0>, <1, 1>, <0, 1>, <0, 1>, <-1, 1>,\n"
        "  <-1, 0>, <0, 0> scale 0.4 translate <0, 0, -0.8> }\n"
        "prism { conic_sweep linear_spline 0.25, 1, 5, <-1, -1>, <1, -1>, <0.5, 1>, <-0.5, 0.5>,\n"
        "  <-1, -1> rotate 180*x scale 0.4 translate <0.4, 1.2, -0.5> }\n";
    csg_blob blob = text_blob("extrusions.pov", sdl, 64, 48, 1);
    const csg_blob_header *h = csg_blob_hdr(blob.bytes);
    const csg_prim *prims = (const csg_prim *)(const void *)((const char *)blob.bytes +
                                                             h->off_prims);
    int pieces = 0;
    for (int i = 0; i < h->prim_count; i++)
        pieces += prims[i].kind == CSG_PRIM_TRAPEZOID ||
                  prims[i].kind == CSG_PRIM_CONIC_TRAPEZOID;
    assert_true(pieces > 100);
    for (int v = 0; v < VARIANTS; v++)
        assert_true(check_blob(fx->ctx[v], &prec, blob.bytes, 8) > 64 * 48 / 10);
    check_specialised(state, blob.bytes, "prisms and text");
    csg_blob_free(&blob);
}

static void test_flat_boxes_flattened(void **state)
{
    fixture *fx = *state;
    static const int cases[][3] = {{61, 37, 1}, {40, 30, 3}};
    /* the same camera without any sheet: only the one solid box */
    static const char solid_sdl[] = "camera { location <0.3, 1.5, -9> look_at <0, 0, 0> }\n"
                                    "box { -0.5, 0.5 translate <0, 2, 1> }\n";
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        csg_blob blob = text_blob("flat.pov", flat_sdl, cases[c][0], cases[c][1], cases[c][2]);
        csg_blob solid = text_blob("flat.pov", solid_sdl, cases[c][0], cases[c][1], cases[c][2]);
        const csg_blob_header *h = csg_blob_hdr(blob.bytes);
        const csg_prim *prims = (const csg_prim *)(const void *)((const char *)blob.bytes +
                                                                 h->off_prims);
        int flat = 0;
        for (int i = 0; i < h->prim_count; i++)
            flat += prims[i].kind == CSG_PRIM_FLAT_BOX;
        assert_int_equal(flat, 9);
        for (int v = 0; v < VARIANTS; v++) {
            size_t hits = check_blob(fx->ctx[v], &prec, blob.bytes, 8);
            size_t without = check_blob(fx->ctx[v], &prec, solid.bytes, 8);
            assert_true(hits > without);
        }
        csg_blob_free(&blob);
        csg_blob_free(&solid);
    }
}

/* Tori (tests/povray/torus.pov: turned, sheared, thin and far, a spindle
 * one, as CSG operands): the OpenCL records are the C ones, in both
 * variants (the packet kernel meets a torus only in CSG programs, which
 * it evaluates through the one-ray code) and in the program specialised
 * on the scene. */
/* The records of the scene in `path` (its primitives of `kind`: `pieces`),
 * both variants, two sizes; also the program specialised on the scene's
 * kinds when `specialised` (a PoCL build of each variant: seconds). */
static void check_pieces_file(void **state, const char *path, int kind, int pieces,
                              bool specialised)
{
    fixture *fx = *state;
    static const int cases[][2] = {{61, 37}, {96, 72}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        csg_blob blob = file_blob(path, NULL, cases[c][0], cases[c][1]);
        const csg_blob_header *h = csg_blob_hdr(blob.bytes);
        const csg_prim *prims = (const csg_prim *)(const void *)((const char *)blob.bytes +
                                                                 h->off_prims);
        int found = 0;
        for (int i = 0; i < h->prim_count; i++)
            found += prims[i].kind == kind;
        assert_int_equal(found, pieces);
        for (int v = 0; v < VARIANTS; v++)
            assert_true(check_blob(fx->ctx[v], &prec, blob.bytes, 8) > 0);
        if (c == 0 && specialised)
            check_specialised(state, blob.bytes, path);
        csg_blob_free(&blob);
    }
}

static void test_torus_flattened(void **state)
{
    /* two pieces a torus; the specialised program is the one with double
       arithmetic in a float build (poly_solve.h) */
    check_pieces_file(state, "tests/povray/torus.pov", CSG_PRIM_TORUS, 2 * 10, true);
}

/* Quadrics (tests/povray/quadric.pov: closed, unbounded, cut, in CSG),
 * the same way: two pieces each, evaluated by the one-ray code. */
static void test_quadric_flattened(void **state)
{
    check_pieces_file(state, "tests/povray/quadric.pov", CSG_PRIM_QUADRIC, 2 * 7, false);
}

/* Polys (tests/povray/poly.pov: orders 2 to 5, bounded and unbounded,
 * cut by boxes, inverse, in CSG): order / 2 + 1 pieces each, their
 * coefficients in the blob's table, through the general program only (a
 * specialised build costs make test a PoCL compile a precision: ~4 s of
 * CPU each, measured; the torus's test builds the specialised program
 * whose double arithmetic a float build enables the same way). */
static void test_poly_flattened(void **state)
{
    check_pieces_file(state, "tests/povray/poly.pov", CSG_PRIM_POLY, 3 + 2 + 3 + 3 + 2 + 3, false);
}

/* clipped_by (tests/povray/clipped_by.pov: clips of every role, in CSG,
 * complemented objects, linked bounds): the clips' primitives (flagged
 * CSG_PF_CLIP, surfaces that are never hits) give the C records on both
 * variants.  (Not the specialised program: a specialisation removes no
 * code of the clip's or the bound's, and each costs seconds of PoCL.) */
static void check_modifier_file(void **state, const char *path, int flag, int flagged)
{
    fixture *fx = *state;
    csg_blob blob = file_blob(path, NULL, 61, 37);
    const csg_blob_header *h = csg_blob_hdr(blob.bytes);
    const csg_prim *prims = (const csg_prim *)(const void *)((const char *)blob.bytes +
                                                             h->off_prims);
    int found = 0;
    for (int i = 0; i < h->prim_count; i++)
        found += (prims[i].flags & flag) != 0;
    assert_int_equal(found, flagged);
    for (int v = 0; v < VARIANTS; v++)
        assert_true(check_blob(fx->ctx[v], &prec, blob.bytes, 8) > 0);
    csg_blob_free(&blob);
}

static void test_clipped_flattened(void **state)
{
    /* (12: the clipped union's plane cuts each of its two children, one
       root each) */
    check_modifier_file(state, "tests/povray/clipped_by.pov", CSG_PF_CLIP, 12);
}

/* bounded_by (tests/povray/bounded_by.pov: bounds that do not enclose
 * their objects, CSG_OP_BOUND gates, a removed bound's box): the same. */
static void test_bounded_flattened(void **state)
{
    check_modifier_file(state, "tests/povray/bounded_by.pov", CSG_PF_BOUND, 11);
}

/* Every packet width a device may ask for ($CSGTRACE_CL_PACKET: 2 x 1,
 * 2 x 2, 4 x 2, 4 x 4 records), on a random scene with several samples a
 * pixel, an image that cuts packets and slices of a few rows. */
static void test_packet_widths(void **state)
{
    (void)state;
    static const int widths[] = {2, 4, 8, 16};
    csg_blob blob = random_blob(7, 40, 37, 21, 3);
    for (size_t w = 0; w < sizeof widths / sizeof widths[0]; w++) {
        ocl_options opt = {.device = NULL, .use_double = prec.real_size == 8,
                           .max_slice_bytes = 37 * 3 * 12 * 5, .packet = widths[w]};
        ocl_timing timing = {0};
        csg_diag d = {0};
        ocl_ctx *ctx = NULL;
        bool ok = ocl_open_kernel(&opt, OCL_KERNEL_PACKET, &ctx, &timing, &d);
        if (!ok)
            fail_msg("ocl_open (packet %d): %s", widths[w], d.message);
        char want[16];
        snprintf(want, sizeof want, "packet %d ", widths[w]);
        assert_memory_equal(timing.kernel, want, strlen(want));
        check_blob(ctx, &prec, blob.bytes, 6);
        ocl_close(ctx);
    }
    csg_blob_free(&blob);
    ocl_timing timing = {0};
    csg_diag d = {0};
    ocl_options bad = {.packet = 3};
    ocl_ctx *ctx = NULL;
    assert_false(ocl_open_kernel(&bad, OCL_KERNEL_PACKET, &ctx, &timing, &d));
    assert_null(ctx);
    assert_non_null(strstr(d.message, "2, 4, 8 or 16, not 3"));
}

/* The same with slices of a few rows (cutting packets and tiles). */
static void test_random_forced_slices(void **state)
{
    (void)state;
    csg_blob blob = random_blob(99, 50, 45, 23, 2);
    for (int v = 0; v < VARIANTS; v++) {
        ocl_options opt = {.device = NULL, .use_double = prec.real_size == 8,
                           .max_slice_bytes = 45 * 2 * 12 * 3};
        ocl_timing timing = {0};
        csg_diag d = {0};
        ocl_ctx *ctx = NULL;
        if (!ocl_open_kernel(&opt, variant_kernel[v], &ctx, &timing, &d))
            fail_msg("ocl_open: %s", d.message);
        check_blob(ctx, &prec, blob.bytes, 5);
        ocl_close(ctx);
    }
    csg_blob_free(&blob);
}

static void test_tile_sizes(void **state)
{
    fixture *fx = *state;
    static const int tiles[] = {1, 7, 32, 101, 1000};
    for (size_t k = 0; k < sizeof tiles / sizeof tiles[0]; k++)
        for (int v = 0; v < VARIANTS; v++) {
            sc_scene *s = sc_new(100, 37);
            build_spheres_outside(s);
            check_pass(fx->ctx[v], &prec, s, tiles[k]);
            free(s);
        }
}

/* Tiny slices (down to one row, and slices that cut tiles) give the same
 * records and counts as the C reference, hence as one slice. */
static void test_forced_slices(void **state)
{
    (void)state;
    static const size_t limits[] = {1, 100 * 12 * 3, 100 * 12 * 8};
    for (size_t k = 0; k < sizeof limits / sizeof limits[0]; k++)
        for (int v = 0; v < VARIANTS; v++) {
            ocl_options opt = {.device = NULL, .use_double = prec.real_size == 8,
                               .max_slice_bytes = limits[k]};
            ocl_timing timing = {0};
            csg_diag d = {0};
            ocl_ctx *ctx = NULL;
            if (!ocl_open_kernel(&opt, variant_kernel[v], &ctx, &timing, &d))
                fail_msg("ocl_open: %s", d.message);
            sc_scene *s = sc_new(100, 37);
            build_random(s);
            check_pass(ctx, &prec, s, 7);
            /* and the slicing did happen */
            size_t size;
            void *blob = prec.make_blob(s, &size);
            size_t n = 100 * 37;
            void *t = malloc(n * 8);
            uint32_t *surf = malloc(n * 4), hits[15 * 6];
            assert_true(t && surf);
            bool ok = ocl_primary_pass(ctx, blob, 7, t, surf, hits, &timing, &d);
            free(blob);
            free(t);
            free(surf);
            free(s);
            ocl_close(ctx);
            assert_true(ok);
            assert_true(timing.slices > 1);
        }
}

static void test_empty_scene(void **state)
{
    fixture *fx = *state;
    for (int v = 0; v < VARIANTS; v++) {
        const precision_ops *ops = &prec;
        sc_scene *s = sc_new(33, 17);
        build_empty(s);
        size_t size, n = 33 * 17;
        void *blob = ops->make_blob(s, &size);
        void *t = malloc(n * 8);
        uint32_t *surf = malloc(n * 4), hits[5 * 3];
        assert_true(blob && t && surf);
        memset(surf, 0xFF, n * 4);
        memset(hits, 0xFF, sizeof hits);
        ocl_timing timing = {0};
        csg_diag d = {0};
        if (!ocl_primary_pass(fx->ctx[v], blob, 7, t, surf, hits, &timing, &d))
            fail_msg("ocl_primary_pass: %s", d.message);
        for (size_t i = 0; i < n; i++) {
            assert_int_equal(surf[i], CSG_SURF_NONE);
            assert_true(isinf(real_at(t, i, ops->real_size)));
        }
        for (size_t i = 0; i < 15; i++)
            assert_int_equal(hits[i], 0);
        free(blob);
        free(t);
        free(surf);
        free(s);
    }
}

static void test_bad_device(void **state)
{
    (void)state;
    static const char *const sels[] = {"no-such-device-xyz", "7:3"};
    for (size_t k = 0; k < 2; k++) {
        ocl_options opt = {.device = sels[k], .use_double = 0, .max_slice_bytes = 0};
        ocl_timing timing = {0};
        csg_diag d = {0};
        ocl_ctx *ctx = (ocl_ctx *)&d; /* must be reset to NULL */
        assert_false(ocl_open(&opt, &ctx, &timing, &d));
        assert_null(ctx);
        assert_true(d.failed);
        assert_non_null(strstr(d.message, sels[k]));
        assert_non_null(strstr(d.message, "no device matches"));
    }
}

/* The device selector "0:0" and a name substring both work. */
static void test_device_selectors(void **state)
{
    (void)state;
    ocl_timing timing = {0};
    csg_diag d = {0};
    ocl_ctx *ctx = NULL;
    ocl_options opt = {.device = "0:0", .use_double = 0, .max_slice_bytes = 0};
    if (!ocl_open(&opt, &ctx, &timing, &d))
        fail_msg("ocl_open(0:0): %s", d.message);
    ocl_close(ctx);
    char part[8];
    snprintf(part, sizeof part, "%.5s", timing.device_name);
    opt.device = part;
    if (!ocl_open(&opt, &ctx, &timing, &d))
        fail_msg("ocl_open(%s): %s", part, d.message);
    ocl_close(ctx);
}

/* The variant: explicit, from $CSGTRACE_CL_KERNEL, by device type (PoCL's
 * is a CPU: packet); a bad value is refused with a message naming it. */
/* ---- the shadow answers (#36 item 3) ---------------------------------------------- */

/* A scene for every path of the shadow answers: opaque blockers (a CSG
 * union too), a transparent one and a no_shadow one; a point light (0), a
 * spotlight (1), a cylinder light (2), a parallel light (3), an area light
 * (4), a shadowless light (5), a point light that fades (6), and 30 dim point
 * lights, so lights 32 .. 36 lie beyond the records' masks. */
static char *shadow_sdl(void)
{
    sdl_buf b = {NULL, 0, 0};
    sdl(&b, "camera { location <0, 3, -8> look_at <0, 0.5, 0> }\n"
            "plane { y, 0 pigment { color rgb 1 } }\n"
            "sphere { <-1.5, 1, 0>, 1 pigment { color rgb <1, 0.2, 0.2> } }\n"
            "sphere { <1.5, 1, 0>, 1 pigment { color rgbf <0.5, 0.5, 1, 0.8> } }\n"
            "box { <-0.5, 0, -2.5>, <0.5, 2, -2> pigment { color rgb 1 } no_shadow }\n"
            "union { sphere { <0, 2.5, 1>, 0.5 } sphere { <0.6, 2.5, 1>, 0.5 }\n"
            "        pigment { color rgb <0, 1, 0> } }\n"
            "light_source { <-5, 8, -5> color rgb 0.5 }\n"
            "light_source { <5, 8, -5> color rgb 0.5 spotlight point_at <0, 0, 0>\n"
            "               radius 15 falloff 25 }\n"
            "light_source { <0, 10, 0> color rgb 0.3 cylinder point_at <0, 0, 0>\n"
            "               radius 2 falloff 4 }\n"
            "light_source { <3, 6, 5> color rgb 0.3 parallel point_at <0, 0, 0> }\n"
            "light_source { <0, 8, -6> color rgb 0.3 area_light <1, 0, 0>, <0, 0, 1>, 2, 2 }\n"
            "light_source { <-3, 5, 2> color rgb 0.3 shadowless }\n"
            "light_source { <2, 4, -3> color rgb 0.3 fade_distance 3 fade_power 2 }\n");
    for (int i = 0; i < 30; i++)
        sdl(&b, "light_source { <%d, 6, %d> color rgb 0.02 }\n", i % 6 - 3, i / 6 - 2);
    return b.text;
}

/* Per light: records answered lit, answered blocked. */
typedef struct {
    size_t lit[CSG_SHADOW_LIGHTS], blocked[CSG_SHADOW_LIGHTS];
} shadow_tally;

static void shadow_count(const uint32_t *known, const uint32_t *lit, size_t n, shadow_tally *st)
{
    memset(st, 0, sizeof *st);
    for (size_t i = 0; i < n; i++)
        for (int l = 0; l < CSG_SHADOW_LIGHTS; l++)
            if ((known[i] >> l) & 1u) {
                if ((lit[i] >> l) & 1u)
                    st->lit[l]++;
                else
                    st->blocked[l]++;
            }
}

/* The device's answers for the records of each kernel variant equal the C
 * answers (the same shadow.h) bit for bit, and the worker's pixels with
 * them equal its pixels without them, bit for bit, with every answer taken
 * in place of a shadow ray; answers turned over change the pixels (they
 * are used); the lights the device must not answer are left unknown. */
static void test_shadow_answers(void **state)
{
    fixture *fx = *state;
    char *text = shadow_sdl();
    csg_blob blob = text_blob("shadow scene", text, 48, 36, 2);
    free(text);
    const csg_blob_header *bh = (const csg_blob_header *)blob.bytes;
    const engine *eng = engine_for_blob(blob.bytes);
    size_t n = (size_t)bh->width * (size_t)bh->height * (size_t)bh->spp, rs = prec.real_size;
    void *t = malloc(n * rs);
    uint32_t *surf = malloc(n * 4), *known = malloc(n * 4), *lit = malloc(n * 4);
    uint32_t *hits = malloc((size_t)bh->width * (size_t)bh->height * 4);
    float *rgb_plain = malloc((size_t)bh->width * (size_t)bh->height * 12);
    float *rgb_answered = malloc((size_t)bh->width * (size_t)bh->height * 12);
    assert_true(t && surf && known && lit && hits && rgb_plain && rgb_answered);
    tile_rect all = {0, 0, bh->width, bh->height};
    const csg_flat_light *lights = (const csg_flat_light *)(const void *)(blob.bytes + bh->off_lights);
    csg_view v = csg_blob_view(blob.bytes);
    for (int var = 0; var < VARIANTS; var++) {
        ocl_timing timing = {0};
        csg_diag d = {0};
        if (!ocl_primary_pass(fx->ctx[var], blob.bytes, 8, t, surf, hits, &timing, &d) ||
            !ocl_shadow_answers(fx->ctx[var], blob.bytes, t, surf, known, lit, NULL, &d))
            fail_msg("%s: %s", prec.name, d.message);
        size_t bad = 0, hit = 0;
        for (size_t i = 0; i < n; i++) {
            int cols = bh->width * bh->spp, col = (int)(i % (size_t)cols), row = (int)(i / (size_t)cols);
            csg_ray r = csg_sample_ray(csg_blob_camera(blob.bytes), bh->width, bh->height,
                                       col / bh->spp, row, bh->spp, col % bh->spp);
            real ti;
            memcpy(&ti, (char *)t + i * rs, rs);
            csg_u32 k_ref, l_ref;
            csg_shadow_masks(v, lights, bh->light_count, r, ti, surf[i], &k_ref, &l_ref);
            hit += surf[i] != CSG_SURF_NONE;
            if ((k_ref != known[i] || l_ref != lit[i]) && bad++ < 5)
                print_error("%s record %zu: C known %08x lit %08x, OpenCL %08x %08x\n", prec.name,
                            i, (unsigned)k_ref, (unsigned)l_ref, (unsigned)known[i],
                            (unsigned)lit[i]);
        }
        assert_int_equal(bad, 0);
        assert_true(hit > n / 2);

        shadow_tally st;
        shadow_count(known, lit, n, &st);
        for (int l = 0; l < 7; l++) /* point, spot, cylinder, parallel, faded: both
                                       answers; area, shadowless: never */
            if (l == 4 || l == 5)
                assert_true(st.lit[l] == 0 && st.blocked[l] == 0);
            else
                assert_true(st.lit[l] > 0 && st.blocked[l] > 0);
        /* the transparent sphere: floor points behind it for light 0 are
         * left unknown, so light 0 is answered on fewer records than hit */
        assert_true(st.lit[0] + st.blocked[0] < hit);

        ray_counts plain = {0}, answered = {0};
        eng->shade(blob.bytes, all, t, surf, rgb_plain, &plain);
        eng->shade_answered(blob.bytes, all, t, surf, known, lit, rgb_answered, &answered);
        assert_memory_equal(rgb_plain, rgb_answered, (size_t)bh->width * (size_t)bh->height * 12);
        assert_true(answered.shadow_answered > 0);
        assert_int_equal(plain.shadow_answered, 0);
        assert_int_equal(plain.shadow, answered.shadow + answered.shadow_answered);
        print_message("# %s %s: %llu of %llu shadow rays answered by the device\n", prec.name,
                      var ? "packet" : "scalar", (unsigned long long)answered.shadow_answered,
                      (unsigned long long)plain.shadow);

        for (size_t i = 0; i < n; i++) /* every answer turned over */
            lit[i] ^= known[i];
        ray_counts wrong = {0};
        eng->shade_answered(blob.bytes, all, t, surf, known, lit, rgb_answered, &wrong);
        assert_true(memcmp(rgb_plain, rgb_answered, (size_t)bh->width * (size_t)bh->height * 12) != 0);
    }
    free(t);
    free(surf);
    free(known);
    free(lit);
    free(hits);
    free(rgb_plain);
    free(rgb_answered);
    csg_blob_free(&blob);
}

/* The device's shadow answers on ctx for blob's records equal the C
 * answers record by record; returns the answers given (known bits). */
static size_t check_shadow_masks(ocl_ctx *ctx, const csg_blob *blob, const char *what)
{
    const csg_blob_header *bh = (const csg_blob_header *)blob->bytes;
    size_t n = (size_t)bh->width * (size_t)bh->height * (size_t)bh->spp, rs = prec.real_size;
    void *t = malloc(n * rs);
    uint32_t *surf = malloc(n * 4), *known = malloc(n * 4), *lit = malloc(n * 4);
    uint32_t *hits = malloc(n * 4);
    assert_true(t && surf && known && lit && hits);
    ocl_timing timing = {0};
    csg_diag d = {0};
    if (!ocl_primary_pass(ctx, blob->bytes, 8, t, surf, hits, &timing, &d) ||
        !ocl_shadow_answers(ctx, blob->bytes, t, surf, known, lit, NULL, &d))
        fail_msg("%s %s: %s", prec.name, what, d.message);
    const csg_flat_light *lights =
        (const csg_flat_light *)(const void *)(blob->bytes + bh->off_lights);
    csg_view v = csg_blob_view(blob->bytes);
    size_t bad = 0, answers = 0;
    int cols = bh->width * bh->spp;
    for (size_t i = 0; i < n; i++) {
        int col = (int)(i % (size_t)cols), row = (int)(i / (size_t)cols);
        csg_ray r = csg_sample_ray(csg_blob_camera(blob->bytes), bh->width, bh->height,
                                   col / bh->spp, row, bh->spp, col % bh->spp);
        real ti;
        memcpy(&ti, (char *)t + i * rs, rs);
        csg_u32 k_ref, l_ref;
        csg_shadow_masks(v, lights, bh->light_count, r, ti, surf[i], &k_ref, &l_ref);
        answers += (size_t)__builtin_popcount(known[i]);
        if ((k_ref != known[i] || l_ref != lit[i]) && bad++ < 5)
            print_error("%s %s (%s) record (%d, %d): C known %08x lit %08x, OpenCL %08x %08x\n",
                        prec.name, what, timing.kernel, col, row, (unsigned)k_ref,
                        (unsigned)l_ref, (unsigned)known[i], (unsigned)lit[i]);
    }
    free(t);
    free(surf);
    free(known);
    free(lit);
    free(hits);
    assert_int_equal(bad, 0);
    return answers;
}

/* Prisms with curved sides (flat.h, csg_curve): the device's shadow
 * answers, which turn each hit's frame to the light by the shading normal
 * (the spline's, csg_surface_shading_normal), equal C's in both variants,
 * and so do the records. */
static void test_curved_shadows(void **state)
{
    fixture *fx = *state;
    static const char sdl[] =
        "camera { location <0.5, 2.5, -4> look_at <0.5, 0.3, 0> }\n"
        "plane { y, 0 pigment { color rgb 1 } }\n"
        "light_source { <-4, 5, -3> color rgb 1 }\n"
        "light_source { <5, 1, -1> color rgb 0.5 }\n"
        "prism { cubic_spline 0, 1, 7, <0, -1>, <1, 0>, <0, 1>, <-1, 0>, <0, -1>, <1, 0>,\n"
        "  <0, 1> scale 0.6 translate <-0.6, 0, 0> }\n"
        "prism { quadratic_spline conic_sweep 0.5, 1, 6, <0, -1>, <1, 0>, <0, 1>, <-1, 0>,\n"
        "  <0, -1>, <1, 0> rotate 180*x scale 0.8 translate <1.2, 0.8, 0> }\n"
        "prism { bezier_spline 0, 0.4, 8, <0, 0>, <1, 0>, <1, 1>, <0, 1>, <0, 1>, <-1, 1>,\n"
        "  <-1, 0>, <0, 0> scale 0.5 translate <0.4, 0, -1.2> }\n";
    csg_blob blob = text_blob("curved.pov", sdl, 64, 48, 1);
    assert_true(csg_blob_hdr(blob.bytes)->curve_count > 100);
    for (int var = 0; var < VARIANTS; var++) {
        assert_true(check_blob(fx->ctx[var], &prec, blob.bytes, 8) > 64 * 48 / 4);
        assert_true(check_shadow_masks(fx->ctx[var], &blob, "curved prisms") > 64 * 48 / 4);
    }
    csg_blob_free(&blob);
}

/* Spheres whose hit frames the packet kernel makes for every lane that
 * met one at once (simd_kernels/primary.cl, pk_sphere_frames; the one-ray
 * code for the rest): a sphere at the origin (points in the near-zero
 * band of the offset, offset.h, beside points outside it), one carved out
 * of a box (its surface flipped), a huge one far off (the box magnitude
 * bound), one scaled unevenly (transformed: the one-ray code), spheres
 * side by side in one packet, lights grazing them; the answers equal
 * C's in both variants. */
static void test_sphere_frame_shadows(void **state)
{
    fixture *fx = *state;
    static const char sdl[] =
        "camera { location <0.3, 1.5, -4> look_at <0, 0.2, 0> }\n"
        "plane { y, -1.2 pigment { color rgb 1 } }\n"
        "sphere { 0, 0.6 pigment { color rgb 1 } }\n"
        "difference { box { <1, -1.2, -0.5>, <2, 0.2, 0.5> } sphere { <1.5, 0.2, 0>, 0.45 }\n"
        "  pigment { color rgb <1, 0.5, 0.2> } }\n"
        "sphere { <0, -1e4, 3e4>, 2.99e4 pigment { color rgb 0.5 } }\n"
        "sphere { <-1.5, 0, 0>, 0.5 scale <1, 2, 1> pigment { color rgb <0.2, 1, 0.2> } }\n"
        "sphere { <-0.7, -0.9, -1.5>, 0.05 } sphere { <-0.6, -0.9, -1.5>, 0.05 }\n"
        "sphere { <-0.65, -0.8, -1.5>, 0.05 }\n"
        "light_source { <-4, 6, -5> color rgb 1 }\n"
        "light_source { <6, 0.3, -1> color rgb 0.5 }\n"
        "light_source { <0, 0.6, 0> color rgb 0.3 }\n";
    csg_blob blob = text_blob("sphere frames", sdl, 96, 72, 1);
    for (int var = 0; var < VARIANTS; var++)
        assert_true(check_shadow_masks(fx->ctx[var], &blob, "sphere frames") > 96 * 72 / 4);
    csg_blob_free(&blob);
}

/* Random scenes of many opaque objects (CSG, planes, a deep BVH): the
 * packet walk of the shadow rays must reach exactly the roots the one-ray
 * walk reaches (a child's box may pass where its parent's did not: a
 * packet that opened the node for other lanes must not test it for this
 * one), so the answers equal C's in both variants. */
static void test_shadow_answers_random(void **state)
{
    fixture *fx = *state;
    for (uint64_t seed = 1; seed <= 2; seed++) {
        csg_blob blob = random_blob(seed, 400, 64, 48, 1);
        for (int var = 0; var < VARIANTS; var++)
            assert_true(check_shadow_masks(fx->ctx[var], &blob, "random scene") > 0);
        csg_blob_free(&blob);
    }
}

static void test_kernel_choice(void **state)
{
    (void)state;
    enum ocl_kernel k;
    assert_true(ocl_kernel_parse("auto", &k) && k == OCL_KERNEL_AUTO);
    assert_true(ocl_kernel_parse("scalar", &k) && k == OCL_KERNEL_SCALAR);
    assert_true(ocl_kernel_parse("packet", &k) && k == OCL_KERNEL_PACKET);
    assert_false(ocl_kernel_parse("vector", &k));
    assert_false(ocl_kernel_parse(NULL, &k));
    /* auto: the packet kernel on a CPU device, the one-ray kernel on any
     * other; an explicit choice is what it says, on any device */
    static const struct {
        enum ocl_kernel want;
        const char *cpu, *other; /* prefix of timing.kernel */
    } cases[] = {{OCL_KERNEL_AUTO, "packet", "scalar"},
                 {OCL_KERNEL_SCALAR, "scalar", "scalar"},
                 {OCL_KERNEL_PACKET, "packet", "packet"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ocl_timing timing = {0};
        csg_diag d = {0};
        if (!open_variant(cases[i].want, &timing, &d))
            fail_msg("ocl_open (kernel %d): %s", (int)cases[i].want, d.message);
        const char *want = timing.cpu_device ? cases[i].cpu : cases[i].other;
        assert_memory_equal(timing.kernel, want, strlen(want));
        assert_true(timing.compute_units >= 1);
    }
}

/* A blob in the other precision, or a bad one, is refused with a message. */
static void test_bad_blob(void **state)
{
    fixture *fx = *state;
    sc_scene *s = sc_new(4, 4);
    build_spheres(s);
    size_t size;
    void *blob = prec.make_blob(s, &size);
    double t[16];
    uint32_t surf[16], hits[1];
    ocl_timing timing = {0};
    csg_diag d = {0};
    csg_blob_header *h = blob;
    h->real_size = prec.real_size == 8 ? 4 : 8; /* claims the other precision */
    assert_false(ocl_primary_pass(fx->ctx[0], blob, 4, t, surf, hits, &timing, &d));
    assert_non_null(strstr(d.message, prec.real_size == 8 ? "in float" : "in double"));
    h->real_size = (uint32_t)prec.real_size;
    h->off_camera = h->total_size;
    d.failed = 0;
    assert_false(ocl_primary_pass(fx->ctx[0], blob, 4, t, surf, hits, &timing, &d));
    assert_true(d.failed);
    free(blob);
    free(s);
}

/* A kernel that does not compile: a clear error, the build log on stderr. */
static void test_build_failure(void **state)
{
    (void)state;
    ocl_options opt = {.source = "__kernel void csg_primary(__global int *o) "
                                 "{ o[0] = undeclared_name; }\n"};
    ocl_timing timing = {0};
    csg_diag d = {0};
    ocl_ctx *ctx = NULL;
    assert_false(ocl_open(&opt, &ctx, &timing, &d));
    assert_null(ctx);
    assert_non_null(strstr(d.message, "CL_BUILD_PROGRAM_FAILURE"));
}

static void test_error_names(void **state)
{
    (void)state;
    assert_string_equal(ocl_error_name(-30), "CL_INVALID_VALUE");
    assert_string_equal(ocl_error_name(-11), "CL_BUILD_PROGRAM_FAILURE");
    assert_string_equal(ocl_error_name(0), "CL_SUCCESS");
    assert_string_equal(ocl_error_name(-12345), "CL_UNKNOWN_ERROR");
}

static int group_setup(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    if (!fx)
        return -1;
    ocl_options opt = {.device = NULL, .use_double = prec.real_size == 8, .max_slice_bytes = 0};
    *state = fx;
    for (int v = 0; v < VARIANTS; v++) {
        ocl_timing timing = {0};
        csg_diag d = {0};
        if (!ocl_open_kernel(&opt, variant_kernel[v], &fx->ctx[v], &timing, &d)) {
            fprintf(stderr, "ocl_open(%s): %s\n", prec.name, d.message);
            while (v-- > 0)
                ocl_close(fx->ctx[v]);
            free(fx);
            return -1;
        }
        fprintf(stderr, "# %s program, %s kernel, on \"%s\": built in %.3f s\n", prec.name,
                timing.kernel, timing.device_name, timing.compile_s);
    }
    return 0;
}

static int group_teardown(void **state)
{
    fixture *fx = *state;
    for (int v = 0; v < VARIANTS; v++)
        ocl_close(fx->ctx[v]);
    free(fx);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
#ifndef CSG_DOUBLE /* the precision-independent ones once, in the float build */
        cmocka_unit_test(test_error_names),
        cmocka_unit_test(test_bad_device),
        cmocka_unit_test(test_device_selectors),
        cmocka_unit_test(test_build_failure),
        cmocka_unit_test(test_kernel_choice),
#endif
        cmocka_unit_test(test_spheres),
        cmocka_unit_test(test_spheres_outside),
        cmocka_unit_test(test_boxes),
        cmocka_unit_test(test_cones),
        cmocka_unit_test(test_flat_boxes),
        cmocka_unit_test(test_flat_boxes_flattened),
        cmocka_unit_test(test_extrusions),
        cmocka_unit_test(test_torus_flattened),
        cmocka_unit_test(test_quadric_flattened),
        cmocka_unit_test(test_poly_flattened),
        cmocka_unit_test(test_clipped_flattened),
        cmocka_unit_test(test_bounded_flattened),
        cmocka_unit_test(test_planes),
        cmocka_unit_test(test_csg),
        cmocka_unit_test(test_random_spheres),
        cmocka_unit_test(test_random_flattened),
        cmocka_unit_test(test_specialised),
        cmocka_unit_test(test_specialised_refuses),
        cmocka_unit_test(test_random_forced_slices),
        cmocka_unit_test(test_packet_widths),
        cmocka_unit_test(test_tile_sizes),
        cmocka_unit_test(test_forced_slices),
        cmocka_unit_test(test_empty_scene),
        cmocka_unit_test(test_bad_blob),
        cmocka_unit_test(test_shadow_answers),
        cmocka_unit_test(test_shadow_answers_random),
        cmocka_unit_test(test_curved_shadows),
        cmocka_unit_test(test_sphere_frame_shadows),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}

/* ---- blob packing and the C reference, in this file's precision ----------------- */

/* The flat blob of s in this precision. */
static void *make_blob(const sc_scene *s, size_t *size)
{
    csg_blob_header h;
    blob_header(s, &h, (uint32_t)sizeof(real), sizeof(csg_prim), sizeof(csg_root),
                sizeof(csg_camera), sizeof(csg_material), sizeof(csg_shading));
    char *b = calloc(1, (size_t)h.total_size);
    assert_non_null(b);
    memcpy(b, &h, sizeof h);
    ((csg_shading *)(void *)(b + h.off_shading))->max_rays = 1; /* primary rays only */
    csg_prim *prims = (csg_prim *)(b + h.off_prims);
    for (int i = 0; i < s->np; i++) {
        prims[i].kind = s->prims[i].kind;
        prims[i].flags = s->prims[i].flags;
        prims[i].material = 0;
        prims[i].root = -1;
        for (int k = 0; k < 8; k++)
            prims[i].p[k] = (real)s->prims[i].p[k];
        for (int k = 0; k < 12; k++)
            prims[i].inv[k] = (real)s->prims[i].inv[k];
    }
    csg_node *nodes = (csg_node *)(b + h.off_nodes);
    for (int i = 0; i < s->nn; i++) {
        nodes[i].op = s->nodes[i].op;
        nodes[i].prim = s->nodes[i].prim;
        if (nodes[i].op == CSG_OP_PRIM) {
            for (int r = 0; r < s->nr; r++)
                if (i >= s->roots[r].first && i < s->roots[r].first + s->roots[r].count)
                    prims[nodes[i].prim].root = r;
        }
    }
    csg_root *roots = (csg_root *)(b + h.off_roots);
    for (int i = 0; i < s->nr; i++) {
        roots[i].first_node = s->roots[i].first;
        roots[i].node_count = s->roots[i].count;
        roots[i].stack_depth = s->roots[i].depth;
        roots[i].flags = 0;
        for (int a = 0; a < 3; a++) {
            roots[i].lo[a] = (real)s->roots[i].lo[a];
            roots[i].hi[a] = (real)s->roots[i].hi[a];
        }
    }
    csg_camera *cam = (csg_camera *)(b + h.off_camera);
    for (int k = 0; k < 3; k++) {
        cam->location[k] = (real)s->cam[k];
        cam->direction[k] = (real)s->cam[3 + k];
        cam->right[k] = (real)s->cam[6 + k];
        cam->up[k] = (real)s->cam[9 + k];
    }
    csg_blob_header *hb = (csg_blob_header *)(void *)b;
#ifdef CSG_DOUBLE
    csg_blob_scan_features_double(b, &hb->kinds, &hb->features);
#else
    csg_blob_scan_features_float(b, &hb->kinds, &hb->features);
#endif
    *size = (size_t)h.total_size;
    return b;
}

/* The C records: exactly what a worker computes for a primary ray. */
static void reference(const void *blob, void *t_out, uint32_t *surf)
{
    const csg_blob_header *h = blob;
    csg_view v = csg_blob_view(blob);
    const csg_camera *cam = csg_blob_camera(blob);
    real *t = t_out;
    for (int y = 0; y < h->height; y++)
        for (int x = 0; x < h->width; x++)
            for (int s = 0; s < h->spp; s++) {
                csg_ray r = csg_sample_ray(cam, h->width, h->height, x, y, h->spp, s);
                csg_hit hit = csg_trace_nearest(v, r, R(0.0), CSG_R_INF);
                size_t i = ((size_t)y * (size_t)h->width + (size_t)x) * (size_t)h->spp + (size_t)s;
                t[i] = hit.t;
                surf[i] = hit.surf;
            }
}
