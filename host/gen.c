/*
 * gen.c — random-sphere scenes with a target screen occupancy.
 *
 * The spheres (centres, base radii, colours, materials) are drawn once from
 * a seeded generator (splitmix64: same seed, same file).  The occupancy —
 * the fraction of pixels whose primary ray hits a sphere at the given image
 * size — grows monotonically with a common scale s applied to every radius
 * (each sphere only grows), so the scale is found by bisection: double s
 * until the occupancy passes the target, then halve the bracket until the
 * measured occupancy is within 0.25 percentage points of it (or the bracket
 * no longer changes a pixel).  Each measurement parses the exact text that
 * will be written and traces its primary rays with the renderer's own C
 * primary pass (the same code as the OpenCL kernel), so the figure is the
 * scene's own.  Radii are capped below the distance to the camera so no
 * sphere ever swallows the eye.
 */
#include "gen.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../csg/flatten.h"
#include "../csg/load.h"
#include "output/file_atomic.h"
#include "../workers/engine.h"

#define GEN_CAMERA_Z (-10.0)

typedef struct {
    double x, y, z, r, red, green, blue;
    unsigned material;
} gen_sphere;

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double uniform(uint64_t *state, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(splitmix64(state) >> 11) * 0x1.0p-53);
}

static unsigned pick_material(uint64_t *state, unsigned allowed)
{
    unsigned kinds[3];
    int n = 0;
    for (unsigned bit = 1; bit <= GEN_TRANSPARENT; bit <<= 1)
        if (allowed & bit)
            kinds[n++] = bit;
    return kinds[splitmix64(state) % (uint64_t)n];
}

static void draw_spheres(const gen_options *o, gen_sphere *s)
{
    uint64_t state = o->seed;
    double aspect = (double)o->width / o->height;
    for (int i = 0; i < o->count; i++) {
        s[i].x = uniform(&state, -4.5 * aspect, 4.5 * aspect);
        s[i].y = uniform(&state, -4.5, 4.5);
        s[i].z = uniform(&state, -3.0, 6.0);
        s[i].r = uniform(&state, 0.3, 1.0);
        s[i].red = uniform(&state, 0.2, 1.0);
        s[i].green = uniform(&state, 0.2, 1.0);
        s[i].blue = uniform(&state, 0.2, 1.0);
        s[i].material = pick_material(&state, o->materials);
    }
}

static double radius_at(const gen_sphere *s, double scale)
{
    double cap = 0.9 * (s->z - GEN_CAMERA_Z);
    double r = s->r * scale;
    return r < cap ? r : cap;
}

/* The scene text at a given radius scale; malloc'd, NULL when out of memory. */
static char *scene_text(const gen_options *o, const gen_sphere *s, double scale, size_t *len)
{
    char *buf = NULL;
    FILE *f = open_memstream(&buf, len);
    if (!f)
        return NULL;
    fprintf(f,
            "// csgtrace gen spheres --count %d --occupancy %.4f --seed %llu --width %d "
            "--height %d\n// Framed for %dx%d. Valid POV-Ray 3.7 too.\n#version 3.7;\n"
            "global_settings { assumed_gamma 1.0 max_trace_level 5 }\n"
            "camera {\n  location <0, 0, %.1f>\n  direction z\n  up y\n  right x * %.17g\n"
            "  look_at <0, 0, 0>\n}\n"
            "light_source { <-20, 30, -40> color rgb <1, 1, 1> }\n"
            "light_source { <25, 10, -30> color rgb <0.4, 0.4, 0.45> }\n"
            "background { color rgb <0.05, 0.07, 0.12> }\n",
            o->count, o->occupancy, (unsigned long long)o->seed, o->width, o->height, o->width,
            o->height, GEN_CAMERA_Z, (double)o->width / o->height);
    for (int i = 0; i < o->count; i++) {
        const gen_sphere *p = &s[i];
        fprintf(f, "sphere { <%.6f, %.6f, %.6f>, %.6f\n", p->x, p->y, p->z, radius_at(p, scale));
        if (p->material == GEN_TRANSPARENT)
            fprintf(f,
                    "  pigment { color rgbf <%.4f, %.4f, %.4f, 0.85> }\n"
                    "  finish { ambient 0 diffuse 0.1 phong 0.9 phong_size 80 reflection 0.1 }\n"
                    "  interior { ior 1.5 }\n}\n",
                    p->red, p->green, p->blue);
        else if (p->material == GEN_REFLECTIVE)
            fprintf(f,
                    "  pigment { color rgb <%.4f, %.4f, %.4f> }\n"
                    "  finish { ambient 0.1 diffuse 0.4 phong 0.8 reflection 0.5 }\n}\n",
                    p->red, p->green, p->blue);
        else
            fprintf(f,
                    "  pigment { color rgb <%.4f, %.4f, %.4f> }\n"
                    "  finish { ambient 0.1 diffuse 0.7 phong 0.4 }\n}\n",
                    p->red, p->green, p->blue);
    }
    if (fclose(f) != 0) {
        free(buf);
        return NULL;
    }
    return buf;
}

/* Fraction of pixels hit, from the primary pass of the parsed text. */
static bool measure(const gen_options *o, const char *text, size_t len, double *occ, csg_diag *d)
{
    csg_scene s;
    if (!csg_load_string("<generated>", text, len, NULL, &s, d))
        return false;
    csg_flatten_opts fo = {o->width, o->height, 1, -1, 1, 0};
    csg_blob blob;
    bool ok = csg_flatten_float(&s, &fo, &blob, d);
    csg_scene_free(&s);
    if (!ok)
        return false;
    size_t n = (size_t)o->width * (size_t)o->height;
    float *t = malloc(n * sizeof *t);
    uint32_t *surf = malloc(n * sizeof *surf);
    if (!t || !surf) {
        free(t);
        free(surf);
        csg_blob_free(&blob);
        csg_error_plain(d, "out of memory measuring the occupancy");
        return false;
    }
    ray_counts rays = {0};
    tile_rect all = {0, 0, o->width, o->height};
    engine_float.trace_primary(blob.bytes, all, t, surf, &rays);
    size_t hits = 0;
    for (size_t i = 0; i < n; i++)
        hits += surf[i] != 0;
    *occ = (double)hits / (double)n;
    free(t);
    free(surf);
    csg_blob_free(&blob);
    return true;
}

typedef struct {
    const char *text;
    size_t len;
} gen_text;

static void print_text(FILE *f, const void *arg)
{
    const gen_text *t = arg;
    fwrite(t->text, 1, t->len, f);
}

static bool write_file(const char *path, const char *text, size_t len, csg_diag *d)
{
    gen_text t = {text, len};
    char err[1024];
    if (file_write_atomic(path, print_text, &t, err, sizeof err))
        return true;
    csg_error_plain(d, "%s", err + strlen("csgtrace: error: "));
    return false;
}

/* Measures the scene at `scale`; keeps the text of the best so far. */
typedef struct {
    const gen_options *o;
    const gen_sphere *spheres;
    char *best_text;
    size_t best_len;
    double best_occ, best_scale;
    int evaluations;
} gen_search;

static bool try_scale(gen_search *g, double scale, double *occ, csg_diag *d)
{
    size_t len;
    char *text = scene_text(g->o, g->spheres, scale, &len);
    if (!text) {
        csg_error_plain(d, "out of memory writing the scene");
        return false;
    }
    if (!measure(g->o, text, len, occ, d)) {
        free(text);
        return false;
    }
    g->evaluations++;
    if (!g->best_text || fabs(*occ - g->o->occupancy) < fabs(g->best_occ - g->o->occupancy)) {
        free(g->best_text);
        g->best_text = text;
        g->best_len = len;
        g->best_occ = *occ;
        g->best_scale = scale;
    } else {
        free(text);
    }
    return true;
}

bool gen_spheres(const gen_options *o, gen_result *r, csg_diag *d)
{
    gen_sphere *spheres = calloc((size_t)o->count, sizeof *spheres);
    if (!spheres) {
        csg_error_plain(d, "out of memory");
        return false;
    }
    draw_spheres(o, spheres);
    gen_search g = {o, spheres, NULL, 0, 0, 0, 0};
    const double tolerance = 0.0025;
    double lo = 0, hi = 1, occ = 0;
    bool ok = try_scale(&g, hi, &occ, d);
    while (ok && occ < o->occupancy && hi < 1024) {
        lo = hi;
        hi *= 2;
        ok = try_scale(&g, hi, &occ, d);
    }
    for (int i = 0; ok && i < 60 && fabs(g.best_occ - o->occupancy) > tolerance; i++) {
        double mid = 0.5 * (lo + hi);
        if (mid == lo || mid == hi)
            break;
        ok = try_scale(&g, mid, &occ, d);
        if (occ < o->occupancy)
            lo = mid;
        else
            hi = mid;
    }
    if (ok && fabs(g.best_occ - o->occupancy) > 0.01) {
        csg_error_plain(d, "gen spheres: cannot reach occupancy %.2f%% with %d spheres at %dx%d "
                           "(closest: %.2f%%)",
                        100 * o->occupancy, o->count, o->width, o->height, 100 * g.best_occ);
        ok = false;
    }
    if (ok)
        ok = write_file(o->out_path, g.best_text, g.best_len, d);
    if (ok) {
        r->occupancy = g.best_occ;
        r->scale = g.best_scale;
        r->evaluations = g.evaluations;
    }
    free(g.best_text);
    free(spheres);
    return ok;
}

/* ---- arguments ---------------------------------------------------------------- */

static bool want_value(int i, int argc, const char *opt, csg_diag *d)
{
    if (i + 1 < argc)
        return true;
    csg_error_plain(d, "%s needs a value", opt);
    return false;
}

