/*
 * test_surfaces.c — triangles, polygons and meshes (surfaces, not solids):
 * the watertight triangle test (no ray through a shared edge or vertex
 * escapes between the triangles), one-sided backs (invisible, but still
 * in the lists for shadows), the CSG meaning of surfaces (POV-Ray's: a
 * surface has no inside), concave polygons (ear clipping, not a fan), the
 * split itself, and smooth normals.  Compiled per precision (real = float
 * here, double in test_surfaces_double.c); scenes go through the loader
 * and the flattener of the same precision, rays through the shared code.
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

#include "../csg/device/intersect.h"
#include "../csg/flatten.h"
#include "../csg/load.h"
#include "../csg/polygon.h"
#include "../workers/engine.h"
#include "flat_scene.h"


static csg_ray ray(double ox, double oy, double oz, double tx, double ty, double tz)
{
    csg_ray r;
    r.o = v3((real)ox, (real)oy, (real)oz);
    r.d = v3_normalize(v3((real)(tx - ox), (real)(ty - oy), (real)(tz - oz)));
    return r;
}

static csg_hit nearest(const csg_blob *b, csg_ray r)
{
    return csg_trace_nearest(csg_blob_view(b->bytes), r, R(0.0), CSG_R_INF);
}

static int hit_kind(const csg_blob *b, csg_hit h)
{
    if (h.surf == CSG_SURF_NONE)
        return -1;
    return csg_blob_view(b->bytes).prims[CSG_SURF_PRIM(h.surf)].kind;
}

static double lattice_z(int x, int y) { return 10 + 0.37 * sin(1.3 * x + 0.7 * y * y); }

/* The height of the mesh below at (x, y): the triangle of its cell. */
static double mesh_z(double x, double y)
{
    int i = (int)floor(x), j = (int)floor(y);
    double u = x - i, v = y - j;
    double z00 = lattice_z(i, j), z10 = lattice_z(i + 1, j), z01 = lattice_z(i, j + 1);
    double z11 = lattice_z(i + 1, j + 1);
    return u >= v ? z00 + u * (z10 - z00) + v * (z11 - z10) : z00 + v * (z01 - z00) + u * (z11 - z01);
}

/* A 6 x 6 grid of quads (72 triangles) over a bumpy height field: every
 * ray aimed at a shared edge, a shared vertex or anywhere inside hits. */
static void test_watertight(void **state)
{
    (void)state;
    char *text = malloc(65536);
    assert_non_null(text);
    size_t n = (size_t)sprintf(text, "mesh {\n");
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) {
            double z[4];
            for (int k = 0; k < 4; k++)
                z[k] = lattice_z(i + (k & 1), j + (k >> 1));
            n += (size_t)sprintf(text + n,
                                 "triangle { <%d, %d, %.17g>, <%d, %d, %.17g>, <%d, %d, %.17g> }\n"
                                 "triangle { <%d, %d, %.17g>, <%d, %d, %.17g>, <%d, %d, %.17g> }\n",
                                 i, j, z[0], i + 1, j, z[1], i + 1, j + 1, z[3], i, j, z[0],
                                 i + 1, j + 1, z[3], i, j + 1, z[2]);
        }
    sprintf(text + n, "}\n");
    csg_blob b = flat_scene("grid.pov", text);
    free(text);
    int misses = 0, rays = 0;
    /* aimed at lattice points (vertices), edge points and interiors */
    for (int a = 1; a < 6 * 16; a++)
        for (int c = 1; c < 6 * 16; c++) {
            double x = a / 16.0, y = c / 16.0;
            csg_hit h = nearest(&b, ray(3.01, 2.97, 0, x, y, mesh_z(x, y)));
            misses += h.surf == CSG_SURF_NONE;
            rays++;
        }
    /* the diagonals from straight above (their edge functions are 0) */
    for (int a = 1; a < 6 * 32; a++) {
        double x = a / 32.0;
        csg_hit h = nearest(&b, ray(x, x, 0, x, x, 10));
        misses += h.surf == CSG_SURF_NONE;
        rays++;
    }
    if (misses)
        fail_msg("%d of %d rays slipped through the mesh", misses, rays);
    csg_blob_free(&b);
}

#define NFF_VIEW "v\nfrom 0 0 -5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0\nresolution 4 4\n"

/* A one-sided NFF polygon: seen from the front, invisible from behind,
 * yet its crossing stays in the list (a shadow ray sees it). */
static void test_one_sided(void **state)
{
    (void)state;
    /* counter-clockwise seen from -z: its front faces the camera at z = -5 */
    csg_blob b = flat_scene("t.nff", NFF_VIEW "f 1 1 1 1 0 0 0 0\np 3\n-1 -1 0\n0 1 0\n1 -1 0\n");
    csg_hit front = nearest(&b, ray(0, 0, -5, 0, 0, 0));
    assert_int_equal(hit_kind(&b, front), CSG_PRIM_TRIANGLE);
    assert_true(fabs((double)front.t - 5) < 1e-5);
    csg_ray back = ray(0, 0, 5, 0, 0, 0);
    assert_int_equal(nearest(&b, back).surf, CSG_SURF_NONE);
    csg_view v = csg_blob_view(b.bytes);
    csg_spans l;
    csg_root_spans(v, 0, back, R(0.0), CSG_R_INF, &l);
    assert_int_equal(l.n, 0);
    assert_int_equal(l.ne, 1);
    assert_int_equal(CSG_SURF_SUB(l.se[0]), CSG_SURF_HIDDEN);
    csg_blob_free(&b);
    /* transmitting: two-sided */
    b = flat_scene("t.nff", NFF_VIEW "f 1 1 1 1 0 0 0.5 1.2\np 3\n-1 -1 0\n0 1 0\n1 -1 0\n");
    assert_int_equal(hit_kind(&b, nearest(&b, back)), CSG_PRIM_TRIANGLE);
    csg_blob_free(&b);
}

#define TRI "triangle { <-2, -2, 0>, <2, -2, 0>, <0, 2, 0> }"
#define BALL "sphere { <0, 0, 0>, 1 }"

/* A surface in CSG: no inside (POV-Ray's meaning, flat.h). */
static void test_csg_meaning(void **state)
{
    (void)state;
    csg_ray centre = ray(0, 0, -5, 0, 0, 0);      /* through the sphere */
    csg_ray outside = ray(1.5, -1.5, -5, 1.5, -1.5, 0); /* the triangle, outside it */
    /* intersection: the triangle's part inside the sphere, no sphere */
    csg_blob b = flat_scene("t.pov", "intersection { " TRI " " BALL " }");
    csg_hit h = nearest(&b, centre);
    assert_int_equal(hit_kind(&b, h), CSG_PRIM_TRIANGLE);
    assert_true(fabs((double)h.t - 5) < 1e-5);
    assert_int_equal(nearest(&b, outside).surf, CSG_SURF_NONE);
    csg_blob_free(&b);
    /* difference triangle - sphere: the part outside */
    b = flat_scene("t.pov", "difference { " TRI " " BALL " }");
    assert_int_equal(nearest(&b, centre).surf, CSG_SURF_NONE);
    assert_int_equal(hit_kind(&b, nearest(&b, outside)), CSG_PRIM_TRIANGLE);
    csg_blob_free(&b);
    /* difference sphere - triangle: the whole sphere */
    b = flat_scene("t.pov", "difference { " BALL " " TRI " }");
    h = nearest(&b, centre);
    assert_int_equal(hit_kind(&b, h), CSG_PRIM_SPHERE);
    assert_true(fabs((double)h.t - 4) < 1e-5);
    assert_int_equal(nearest(&b, outside).surf, CSG_SURF_NONE);
    csg_blob_free(&b);
    /* union nested in an intersection: a solid, the triangle hidden inside */
    b = flat_scene("t.pov", "intersection { union { " TRI " " BALL " } box { -3, 3 } }");
    h = nearest(&b, centre);
    assert_int_equal(hit_kind(&b, h), CSG_PRIM_SPHERE);
    csg_blob_free(&b);
    /* two surfaces intersect in nothing */
    b = flat_scene("t.pov", "intersection { " TRI " " TRI " }");
    assert_int_equal(nearest(&b, centre).surf, CSG_SURF_NONE);
    csg_blob_free(&b);
}

/* A concave polygon: the notch is empty (a fan from vertex 0 fills it). */
static void test_concave_polygon(void **state)
{
    (void)state;
    csg_blob b = flat_scene("t.pov", "polygon { 6, <0, 0, 0>, <4, 0, 0>, <4, 4, 0>, <2, 1, 0>, "
                               "<0, 4, 0>, <0, 0, 0> }");
    assert_int_equal(csg_blob_hdr(b.bytes)->prim_count, 3);
    assert_int_equal(nearest(&b, ray(2, 2, -5, 2, 2, 0)).surf, CSG_SURF_NONE); /* the notch */
    assert_int_not_equal(nearest(&b, ray(2, 0.5, -5, 2, 0.5, 0)).surf, CSG_SURF_NONE);
    assert_int_not_equal(nearest(&b, ray(3.5, 3, -5, 3.5, 3, 0)).surf, CSG_SURF_NONE);
    csg_blob_free(&b);
}

static double tri_area(const dvec3 *v, const int *t)
{
    double ax = v[t[1]].x - v[t[0]].x, ay = v[t[1]].y - v[t[0]].y;
    double bx = v[t[2]].x - v[t[0]].x, by = v[t[2]].y - v[t[0]].y;
    return 0.5 * (ax * by - ay * bx);
}

enum { GEAR_N = 144 };

/* A gear outline of GEAR_N vertices (GEAR_N / 4 teeth): vertices 4k + 2
 * and 4k + 3 on the tips (radius 1), the others in the notches (0.8). */
static void gear_outline(dvec3 *v)
{
    for (int i = 0; i < GEAR_N; i++) {
        double a = 2 * M_PI * i / GEAR_N, r = (i / 2) % 2 ? 1.0 : 0.8;
        v[i] = (dvec3){r * cos(a), r * sin(a), 0};
    }
}

static double box_area(const dvec3 *v, const int *t)
{
    double lx = v[t[0]].x, hx = lx, ly = v[t[0]].y, hy = ly;
    for (int k = 1; k < 3; k++) {
        lx = fmin(lx, v[t[k]].x);
        hx = fmax(hx, v[t[k]].x);
        ly = fmin(ly, v[t[k]].y);
        hy = fmax(hy, v[t[k]].y);
    }
    return (hx - lx) * (hy - ly);
}

/* The split of a 144-vertex gear outline (36 teeth): n - 2 triangles,
 * each counter-clockwise, covering exactly the polygon's area; and
 * compact, the shortest diagonal cut first: their boxes cover the face a
 * few times over (the order that cut the next ear left slivers across the
 * whole face: 22 times here, 29 on the SPD gear, and every box over a
 * point costs a ray there a test). */
static void test_split(void **state)
{
    (void)state;
    enum { N = GEAR_N };
    dvec3 v[N];
    gear_outline(v);
    int tri[3 * (N - 2)];
    int count = csg_polygon_triangulate(v, N, tri);
    assert_int_equal(count, N - 2);
    double sum = 0, area = 0, boxes = 0;
    for (int k = 0; k < count; k++) {
        double t = tri_area(v, tri + 3 * k);
        assert_true(t > 0);
        sum += t;
        boxes += box_area(v, tri + 3 * k);
    }
    for (int i = 0; i < N; i++)
        area += 0.5 * (v[i].x * v[(i + 1) % N].y - v[(i + 1) % N].x * v[i].y);
    assert_true(fabs(sum - area) < 1e-12);
    if (!(boxes < 4 * area))
        fail_msg("the triangles' boxes cover the gear %g times over", boxes / area);
    /* clockwise input: triangles clockwise too (the winding is kept) */
    dvec3 w[4] = {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    int t4[6];
    assert_int_equal(csg_polygon_triangulate(w, 4, t4), 2);
    assert_true(tri_area(w, t4) < 0 && tri_area(w, t4 + 3) < 0);
    dvec3 line[3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    assert_int_equal(csg_polygon_triangulate(line, 3, t4), -1);
}

/* The gear as a POV-Ray polygon, flattened: every ray aimed straight at
 * an outline vertex, the middle of a diagonal the split cut (an edge two
 * triangles share), a triangle's centre or a point just inside a tooth
 * tip hits; a ray into a notch between two teeth misses. */
static void test_gear_polygon(void **state)
{
    (void)state;
    dvec3 v[GEAR_N];
    gear_outline(v);
    char *text = malloc(16384);
    assert_non_null(text);
    size_t n = (size_t)sprintf(text, "polygon { %d", GEAR_N + 1);
    for (int i = 0; i <= GEAR_N; i++)
        n += (size_t)sprintf(text + n, ", <%.17g, %.17g, 0>", v[i % GEAR_N].x, v[i % GEAR_N].y);
    sprintf(text + n, " }\n");
    csg_blob b = flat_scene("gear.pov", text);
    free(text);
    int tri[3 * (GEAR_N - 2)];
    int count = csg_polygon_triangulate(v, GEAR_N, tri);
    int misses = 0, rays = 0;
    for (int i = 0; i < GEAR_N; i++, rays++)
        misses += nearest(&b, ray(v[i].x, v[i].y, -5, v[i].x, v[i].y, 0)).surf == CSG_SURF_NONE;
    for (int k = 0; k < count; k++) {
        const int *t = tri + 3 * k;
        double cx = (v[t[0]].x + v[t[1]].x + v[t[2]].x) / 3;
        double cy = (v[t[0]].y + v[t[1]].y + v[t[2]].y) / 3;
        misses += nearest(&b, ray(cx, cy, -5, cx, cy, 0)).surf == CSG_SURF_NONE;
        rays++;
        for (int e = 0; e < 3; e++) {
            int a = t[e], z = t[(e + 1) % 3];
            if ((a + 1) % GEAR_N == z || (z + 1) % GEAR_N == a)
                continue; /* an outline edge */
            double mx = (v[a].x + v[z].x) / 2, my = (v[a].y + v[z].y) / 2;
            misses += nearest(&b, ray(mx, my, -5, mx, my, 0)).surf == CSG_SURF_NONE;
            rays++;
        }
    }
    if (misses)
        fail_msg("%d of %d rays slipped through the gear", misses, rays);
    for (int tooth = 0; tooth < GEAR_N / 4; tooth++) {
        double tip = 2 * M_PI * (4 * tooth + 2.5) / GEAR_N;
        double notch = 2 * M_PI * (4 * tooth + 4.5) / GEAR_N;
        double tx = 0.97 * cos(tip), ty = 0.97 * sin(tip);
        double nx = 0.9 * cos(notch), ny = 0.9 * sin(notch);
        assert_int_not_equal(nearest(&b, ray(tx, ty, -5, tx, ty, 0)).surf, CSG_SURF_NONE);
        assert_int_equal(nearest(&b, ray(nx, ny, -5, nx, ny, 0)).surf, CSG_SURF_NONE);
    }
    csg_blob_free(&b);
}

/* A smooth triangle's normal is its vertex normal at a vertex and their
 * interpolation between. */
static void test_smooth_normal(void **state)
{
    (void)state;
    csg_blob b = flat_scene("t.pov", "smooth_triangle { <0, 0, 0>, <0, 0, -1>, <1, 0, 0>, <1, 0, -1>, "
                               "<0, 1, 0>, <0, 1, -1> }");
    csg_view v = csg_blob_view(b.bytes);
    assert_int_equal(v.prims[0].kind, CSG_PRIM_SMOOTH_TRIANGLE);
    csg_u32 s = CSG_SURF_PACK(0, CSG_SURF_TRI_FRONT, 0);
    vec3 n = csg_surface_normal(v.prims, s, v3(R(1.0), R(0.0), R(0.0)));
    assert_true(fabs((double)n.x - sqrt(0.5)) < 1e-6 && fabs((double)n.z + sqrt(0.5)) < 1e-6);
    n = csg_surface_normal(v.prims, s, v3(R(0.0), R(0.0), R(0.0)));
    assert_true(fabs((double)n.z + 1) < 1e-6);
    vec3 g = csg_surface_geometric_normal(v.prims, s, v3(R(0.5), R(0.0), R(0.0)), n);
    assert_true(fabs((double)g.z - 1) < 1e-6); /* (v1 - v0) x (v2 - v0) = +z */
    csg_blob_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_watertight),     cmocka_unit_test(test_one_sided),
        cmocka_unit_test(test_csg_meaning),    cmocka_unit_test(test_concave_polygon),
        cmocka_unit_test(test_split),          cmocka_unit_test(test_smooth_normal),
        cmocka_unit_test(test_gear_polygon),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
