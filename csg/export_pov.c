/*
 * export_pov.c — writes a scene tree back as POV-Ray 3.7 SDL.
 *
 * Algorithm: one depth-first walk of each top-level object.  The scene tree
 * stores in every node its COMPLETE object -> world transform (the parents'
 * transforms included), so:
 *   - a primitive is written with its own full transform as `matrix <...>`;
 *   - a CSG node is written with no transform at all.
 * The union / intersection / difference / merge of the transformed children
 * is the transformed CSG (and `inverse` commutes with any invertible
 * transform), so POV-Ray sees exactly the geometry csgtrace sees.
 * Textures are resolved on the way down (index -1: the parent's) and
 * written on the primitives only; a top-level object with none gets
 * POV-Ray's default texture written out explicitly.  Interiors are written
 * where the source gave them (POV-Ray then applies its own inheritance).
 *
 * POV-Ray's `matrix <a..l>` maps the row vector [x y z 1] by a 4x3 matrix:
 * x' = a x + d y + g z + j, so it is the transpose of csg_xform's m[3][4].
 *
 * Numbers are written with the fewest digits that read back to the same
 * double (15, else 17), so the export loses nothing.
 *
 * Invariant: nothing is written for a node before its kind and its texture
 * and interior indices have been checked, and every error leaves d filled.
 */
#include "export_pov.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "camera_setup.h"

#define EXPORT_MAX_DEPTH 1000 /* deeper trees are refused, not recursed into */
/* A CSG node this deep in the statement being written is declared before
 * it (#declare CSG_Export_N = ...) and written as object { CSG_Export_N }:
 * a leaf's texture adds braces the source may not have had (it inherited
 * or took the default), and the parser takes at most CSG_PARSE_MAX_NESTING
 * levels of them in one statement.  The tree's height is unchanged
 * (object { } copies the declared tree). */
#define EXPORT_HOIST_DEPTH 48

typedef struct {
    const csg_scene *s;
    FILE *out;      /* where the current statement goes                  */
    FILE *top;      /* the file: where declarations go, before it        */
    int *declared;  /* declarations written so far                       */
    int base;       /* the current statement's depth in its object tree  */
    bool flat;
    csg_diag *d;
    bool *unexportable; /* a transform the language cannot state was met   */
    bool in_clip;   /* writing a clipped_by / bounded_by object: no texture
                       nor interior (POV-Ray refuses a textured one)      */
    int inside;     /* the inherited interior_texture (1 + its index; 0:
                       none), written at the leaves with their texture    */
} exporter;

/* ---- numbers and vectors ---------------------------------------------------- */

static void put_num(FILE *out, double v)
{
    char buf[40];
    if (v == 0) {
        fputs("0", out); /* also for -0 */
        return;
    }
    snprintf(buf, sizeof buf, "%.15g", v);
    if (strtod(buf, NULL) != v)
        snprintf(buf, sizeof buf, "%.17g", v);
    fputs(buf, out);
}

/* A keyword (with its spaces) and its number. */
static void put_field(FILE *out, const char *key, double v)
{
    fputs(key, out);
    put_num(out, v);
}

static void put_vec(FILE *out, const double *v, int n)
{
    fputc('<', out);
    for (int i = 0; i < n; i++) {
        if (i)
            fputs(", ", out);
        put_num(out, v[i]);
    }
    fputc('>', out);
}

static void put_dvec(FILE *out, dvec3 v)
{
    double a[3] = {v.x, v.y, v.z};
    put_vec(out, a, 3);
}

static void indent(FILE *out, int depth)
{
    for (int i = 0; i < depth; i++)
        fputs("    ", out);
}

/* ---- global statements ------------------------------------------------------- */

static void write_globals(const exporter *e)
{
    const csg_globals *g = &e->s->globals;
    FILE *out = e->out;
    static const double one[3] = {1, 1, 1};
    /* the scene's gamma handling (a flat export is always linear: the
     * cross-check compares linear colours) */
    fputs("global_settings {\n", out);
    if (e->flat || g->gamma_kind == CSG_GAMMA_POWER) {
        put_field(out, "    assumed_gamma ", e->flat ? 1.0 : g->assumed_gamma);
        fputc('\n', out);
    } else if (g->gamma_kind == CSG_GAMMA_SRGB) {
        fputs("    assumed_gamma srgb\n", out);
    } else if (csg_version_v37(e->s)) {
        fputs("    assumed_gamma 1\n", out);
    } /* else POV-Ray's legacy mode: no assumed_gamma before 3.7 */
    fputs("    max_trace_level ", out);
    fprintf(out, "%d", e->flat ? 1 : g->max_trace_level);
    put_field(out, "\n    adc_bailout ", g->adc_bailout);
    if (g->number_of_waves != 10)
        fprintf(out, "\n    number_of_waves %d", g->number_of_waves);
    if (g->noise_generator != 0) /* (irid's turbulence reads it) */
        fprintf(out, "\n    noise_generator %d", g->noise_generator);
    if (g->irid_wavelength[0] != (double)0.70f || g->irid_wavelength[1] != (double)0.52f ||
        g->irid_wavelength[2] != (double)0.48f) {
        fputs("\n    irid_wavelength rgb ", out);
        put_vec(out, g->irid_wavelength, 3);
    }
    fputs("\n    ambient_light rgb ", out);
    put_vec(out, e->flat ? one : g->ambient_light, 3);
    fputs("\n}\n\n", out);
}

static void write_camera(const exporter *e)
{
    csg_camera_src cam;
    if (e->s->has_camera)
        cam = e->s->camera;
    else
        csg_camera_default(&cam);
    FILE *out = e->out;
    static const char *const types[] = {
        [CSG_PROJ_PERSPECTIVE] = "perspective",   [CSG_PROJ_ORTHOGRAPHIC] = "orthographic",
        [CSG_PROJ_CYLINDER_1] = "cylinder 1",     [CSG_PROJ_CYLINDER_2] = "cylinder 2",
        [CSG_PROJ_CYLINDER_3] = "cylinder 3",     [CSG_PROJ_CYLINDER_4] = "cylinder 4",
        [CSG_PROJ_ULTRA_WIDE_ANGLE] = "ultra_wide_angle", [CSG_PROJ_PANORAMIC] = "panoramic",
        [CSG_PROJ_SPHERICAL] = "spherical",
    };
    fprintf(out, "camera {\n    %s\n    location ", types[cam.projection]);
    put_dvec(out, cam.location);
    fputs("\n    direction ", out);
    put_dvec(out, cam.direction);
    fputs("\n    right ", out);
    put_dvec(out, cam.right);
    fputs("\n    up ", out);
    put_dvec(out, cam.up);
    if (!csg_camera_planar(&cam)) { /* (its angles, as they are: no direction change) */
        fputs("\n    angle ", out);
        put_num(out, cam.projection == CSG_PROJ_SPHERICAL ? cam.h_angle : cam.angle);
        if (cam.projection == CSG_PROJ_SPHERICAL) {
            fputs(", ", out);
            put_num(out, cam.v_angle);
        }
    }
    fputs("\n}\n\n", out);
}

static void write_matrix(const exporter *e, FILE *out, const csg_xform *x, int depth);
static void write_pigment(const exporter *e, const csg_pigment *pig, int depth);

/* sky_sphere { pigment {}... emission rgb <> matrix <the sky's> } */
static void write_sky(const exporter *e)
{
    const csg_sky *sky = &e->s->sky;
    FILE *out = e->out;
    if (sky->count == 0)
        return;
    fputs("sky_sphere {\n", out);
    for (int i = 0; i < sky->count; i++) {
        indent(out, 1);
        write_pigment(e, &sky->pigments[i], 1);
        fputc('\n', out);
    }
    fputs("    emission rgb ", out);
    put_vec(out, sky->emission, 3);
    fputc('\n', out);
    write_matrix(e, out, &sky->xform, 1);
    fputs("}\n\n", out);
}

/* The angle in degrees whose cosine, as the parser computes it, is c: the
 * shortest decimal that gives c back, else the neighbour of acos's value
 * that does (acos(cos(a)) is not always a, and a re-parsed export must
 * hold the very cosine), else acos's value. */
static double spot_degrees(double c)
{
    double a = acos(c) * 180 / M_PI;
    for (int digits = 1; digits <= 17; digits++) {
        char text[40];
        snprintf(text, sizeof text, "%.*g", digits, a);
        double d = strtod(text, NULL);
        if (cos(d * M_PI / 180) == c)
            return d;
    }
    double up = a, down = a;
    for (int step = 0; step < 64; step++) {
        up = nextafter(up, INFINITY);
        down = nextafter(down, -INFINITY);
        if (cos(up * M_PI / 180) == c)
            return up;
        if (cos(down * M_PI / 180) == c)
            return down;
    }
    return a;
}

/* A light with its kind's items (every transform already applied; a
 * spotlight's radius and falloff are kept as cosines). */
static void write_light(FILE *out, const csg_light *l)
{
    static const char *const kinds[] = {"", " spotlight", " cylinder"};
    fputs("light_source { ", out);
    put_dvec(out, l->position);
    fputs(" color rgb ", out);
    put_vec(out, l->color, 3);
    fputs(kinds[l->kind], out);
    if (l->parallel)
        fputs(" parallel", out);
    if (l->kind != CSG_LIGHT_POINT || l->parallel) {
        fputs(" point_at ", out);
        put_dvec(out, l->point_at);
    }
    if (l->kind != CSG_LIGHT_POINT) {
        bool spot = l->kind == CSG_LIGHT_SPOT;
        put_field(out, " radius ", spot ? spot_degrees(l->radius) : l->radius);
        put_field(out, " falloff ", spot ? spot_degrees(l->falloff) : l->falloff);
        put_field(out, " tightness ", l->tightness);
    }
    if (l->fade_distance != 0 || l->fade_power != 0) {
        put_field(out, " fade_distance ", l->fade_distance);
        put_field(out, " fade_power ", l->fade_power);
    }
    if (l->area) {
        fputs(" area_light ", out);
        put_dvec(out, l->axis1);
        fputs(", ", out);
        put_dvec(out, l->axis2);
        fprintf(out, ", %d, %d adaptive %d%s%s%s", l->size1, l->size2, l->adaptive,
                l->circular ? " circular" : "", l->orient ? " orient" : "",
                l->jitter ? " jitter" : "");
    }
    fputs(l->shadowless ? " shadowless }\n" : " }\n", out);
}

/* A pattern's or a fog's turbulence, when it has one. */
static void write_turbulence(FILE *out, const csg_turb *t)
{
    if (!t->on)
        return;
    fputs(" turbulence ", out);
    put_dvec(out, t->amount);
    fprintf(out, " octaves %d omega ", t->octaves);
    put_num(out, t->omega);
    put_field(out, " lambda ", t->lambda);
}

static void write_fog(FILE *out, const csg_fog *f)
{
    fprintf(out, "fog { fog_type %d distance ", f->kind);
    put_num(out, f->distance);
    fputs(" color rgbft ", out);
    put_vec(out, f->rgbft, 5);
    write_turbulence(out, &f->turb);
    put_field(out, " turb_depth ", f->turb_depth);
    put_field(out, " fog_offset ", f->offset);
    put_field(out, " fog_alt ", f->alt);
    fputs(" up ", out);
    put_dvec(out, f->up);
    fputs(" }\n", out);
}

static void write_background_and_lights(const exporter *e)
{
    FILE *out = e->out;
    if (e->flat) {
        fputs("background { color rgb ", out);
        put_vec(out, e->s->background, 3);
    } else {
        fputs("background { color rgbft ", out);
        put_vec(out, e->s->background, 5);
    }
    fputs(" }\n\n", out);
    write_sky(e);
    for (int i = 0; i < e->s->light_count; i++)
        write_light(out, &e->s->lights[i]);
    if (e->s->light_count)
        fputc('\n', out);
    if (!e->flat)
        for (int i = 0; i < e->s->fog_count; i++)
            write_fog(out, &e->s->fogs[i]);
}

/* ---- objects ------------------------------------------------------------------- */

/* A colour: rgb (flat: no filter or transmit) or rgbft. */
static void put_color(const exporter *e, const double *rgbft)
{
    fputs(e->flat ? "color rgb " : "color rgbft ", e->out);
    put_vec(e->out, rgbft, e->flat ? 3 : 5);
}

static void write_pigment_map(const exporter *e, const csg_pigment *pig, int depth);

/* The colour map entries. */
static void write_map(const exporter *e, const csg_pigment *pig)
{
    fputs(" color_map {", e->out);
    for (int i = 0; i < pig->map_count; i++) {
        fputs(" [", e->out);
        put_num(e->out, pig->map[i].value);
        fputc(' ', e->out);
        put_color(e, pig->map[i].rgbft);
        fputc(']', e->out);
    }
    fputs(" }", e->out);
}

static void write_pigment_body(const exporter *e, const csg_pigment *pig, int depth);

/* A pattern's keyword and what it takes before its modifiers: gradient's
 * vector, the spirals' number of arms, pigment_pattern's pigment. */
static void write_pattern_name(const exporter *e, const csg_pigment *pig, int depth)
{
    FILE *out = e->out;
    fputs(csg_pattern_name(pig->pattern), out);
    if (pig->pattern == CSG_PATTERN_PIGMENT_PATTERN) {
        fputs(" { ", out);
        write_pigment_body(e, pig->pattern_pigment, depth + 1);
        fputs(pig->pattern_pigment->pattern == CSG_PATTERN_PLAIN ? " }" : "}", out);
    }
    if (pig->pattern == CSG_PATTERN_GRADIENT) {
        fputc(' ', out);
        put_dvec(out, pig->gradient);
    }
    if (pig->pattern == CSG_PATTERN_SPIRAL1 || pig->pattern == CSG_PATTERN_SPIRAL2)
        fprintf(out, " %d", pig->arms);
}

/* The pattern keyword, its name in the table (device/patterns.h; spotted
 * and bumps are written as bozo with their map), with the block patterns'
 * colours or pigments (checker, brick, hexagon) and gradient's vector. */
static void write_pattern_kind(const exporter *e, const csg_pigment *pig, int depth)
{
    if (csg_pattern_blocks(pig->pattern) > 0) {
        fputs(csg_pattern_name(pig->pattern), e->out);
        for (int i = 0; i < pig->pmap_count; i++) {
            fputc(' ', e->out);
            write_pigment(e, &pig->pmap[i].pigment, depth + 1);
        }
        for (int i = 0; i < pig->map_count && pig->pmap_count == 0; i++) {
            fputs(i ? ", " : " ", e->out);
            put_color(e, pig->map[i].rgbft);
        }
        return;
    }
    write_pattern_name(e, pig, depth);
    if (pig->pmap_count > 0)
        write_pigment_map(e, pig, depth);
    else
        write_map(e, pig);
}

/* The noise settings, all explicit (the generator resolved: the scene's
 * #version or global_settings would not travel with the pigment), and
 * the wave unless it and the pattern's default are both ramp. */
static void write_noise(const exporter *e, const csg_pigment *pig)
{
    FILE *out = e->out;
    write_turbulence(out, &pig->turb);
    if (pig->pattern == CSG_PATTERN_AGATE) {
        put_field(out, " agate_turb ", pig->agate_turb);
    }
    if (pig->pattern == CSG_PATTERN_CRACKLE) {
        fputs(" form ", out);
        put_dvec(out, pig->crackle.form);
        put_field(out, " metric ", pig->crackle.metric);
        put_field(out, " offset ", pig->crackle.offset);
        if (pig->crackle.solid)
            fputs(" solid", out);
    }
    if (pig->pattern == CSG_PATTERN_QUILTED) {
        put_field(out, " control0 ", pig->control0);
        put_field(out, " control1 ", pig->control1);
    }
    if (pig->pattern == CSG_PATTERN_BRICK) { /* (the mortar as given: POV-Ray takes
                                                2e-10 off again) */
        fputs(" brick_size ", out);
        put_dvec(out, pig->brick_size);
        put_field(out, " mortar ", pig->mortar + 2e-10);
    }
    if (pig->turb.on || csg_pattern_reads_noise(pig->pattern))
        fprintf(out, " noise_generator %d", csg_noise_of(e->s, pig));
    if (pig->wave != CSG_WAVE_RAMP || csg_pattern_wave(pig->pattern) != CSG_WAVE_RAMP)
        fprintf(out, " %s_wave", csg_wave_name(pig->wave));
    if (pig->wave == CSG_WAVE_POLY) {
        fputc(' ', out);
        put_num(out, pig->exponent);
    }
}

/* The body of a pigment (what its braces hold), at `depth`. */
static void write_pigment_body(const exporter *e, const csg_pigment *pig, int depth)
{
    FILE *out = e->out;
    if (pig->pattern == CSG_PATTERN_PLAIN) {
        put_color(e, pig->rgbft);
        return;
    }
    write_pattern_kind(e, pig, depth);
    write_noise(e, pig);
    put_field(out, " frequency ", pig->frequency);
    put_field(out, " phase ", pig->phase);
    fputc('\n', out);
    write_matrix(e, out, &pig->xform, depth + 1);
    indent(out, depth);
}

/* pigment_map { [F BODY] ... }: each entry's body with its own matrix
 * (relative to the pattern holding the map, as POV-Ray reads it). */
static void write_pigment_map(const exporter *e, const csg_pigment *pig, int depth)
{
    fputs(" pigment_map {\n", e->out);
    for (int i = 0; i < pig->pmap_count; i++) {
        indent(e->out, depth + 1);
        fputc('[', e->out);
        put_num(e->out, pig->pmap[i].value);
        fputc(' ', e->out);
        write_pigment_body(e, &pig->pmap[i].pigment, depth + 1);
        fputs("]\n", e->out);
    }
    indent(e->out, depth);
    fputs("}", e->out);
}

/* pigment { ... }: a plain colour, or the pattern with its colour map,
 * noise settings, wave and complete pattern -> world matrix (written
 * after the object's own matrix, so POV-Ray applies it alone; POV-Ray
 * applies a pattern's transforms before its turbulence whatever their
 * order, as csgtrace does). */
static void write_pigment(const exporter *e, const csg_pigment *pig, int depth)
{
    fputs("pigment { ", e->out);
    write_pigment_body(e, pig, depth);
    fputs(pig->pattern == CSG_PATTERN_PLAIN ? " }" : "}", e->out);
}

/* normal { ... }: its kind (a normal-only pattern) or its pattern, the
 * amount, the pattern's settings and its complete matrix. */
static void write_normal(const exporter *e, const csg_normal *n, int depth)
{
    FILE *out = e->out;
    static const char *const kinds[] = {
#define EXPORT_NORMAL_NAME(ID, name) [CSG_NORMAL_##ID] = #name,
        CSG_NORMALS(EXPORT_NORMAL_NAME)
#undef EXPORT_NORMAL_NAME
    };
    const csg_pigment *pig = &n->pattern;
    indent(out, depth);
    fputs("normal { ", out);
    if (n->kind != CSG_NORMAL_PATTERN)
        fputs(kinds[n->kind], out);
    else
        write_pattern_name(e, pig, depth);
    fputc(' ', out);
    put_num(out, n->amount);
    write_noise(e, pig);
    put_field(out, " frequency ", pig->frequency);
    put_field(out, " phase ", pig->phase);
    put_field(out, " accuracy ", n->accuracy);
    if (n->no_bump_scale)
        fputs(" no_bump_scale", out);
    fputc('\n', out);
    write_matrix(e, out, &pig->xform, depth + 1);
    indent(out, depth);
    fputs("}\n", out);
}

static void write_texture_body(const exporter *e, const csg_texture *t, int depth);

/* A texture_map texture's body: the pattern, its settings, the entries
 * (each body relative to the pattern holding the map) and its matrix;
 * a block pattern as POV-Ray writes it, its textures after the keyword. */
static void write_texture_map(const exporter *e, const csg_texture *t, int depth)
{
    FILE *out = e->out;
    const csg_pigment *pig = &t->pigment;
    indent(out, depth);
    if (csg_pattern_blocks(pig->pattern) > 0) {
        fprintf(out, "%s\n", csg_pattern_name(pig->pattern));
        for (int i = 0; i < t->tmap_count; i++) {
            indent(out, depth);
            fputs("texture {\n", out);
            write_texture_body(e, &t->tmap[i].texture, depth + 1);
            indent(out, depth);
            fputs("}\n", out);
        }
    } else {
        write_pattern_name(e, pig, depth);
        fputc('\n', out);
        indent(out, depth);
        fputs("texture_map {\n", out);
        for (int i = 0; i < t->tmap_count; i++) {
            indent(out, depth + 1);
            fputc('[', out);
            put_num(out, t->tmap[i].value);
            fputc('\n', out);
            write_texture_body(e, &t->tmap[i].texture, depth + 2);
            indent(out, depth + 1);
            fputs("]\n", out);
        }
        indent(out, depth);
        fputs("}\n", out);
    }
    indent(out, depth);
    write_noise(e, pig);
    put_field(out, " frequency ", pig->frequency);
    put_field(out, " phase ", pig->phase);
    fputc('\n', out);
    write_matrix(e, out, &pig->xform, depth);
}

/* What a texture's braces hold: one plain layer (pigment, normal,
 * finish) or a texture_map. */
static void write_texture_body(const exporter *e, const csg_texture *t, int depth)
{
    FILE *out = e->out;
    if (t->tmap_count > 0) {
        write_texture_map(e, t, depth);
        return;
    }
    indent(out, depth);
    write_pigment(e, &t->pigment, depth);
    fputs("\n", out);
    if (e->flat) {
        indent(out, depth);
        fputs("finish { ambient 1 diffuse 0 }\n", out);
        return;
    }
    if (t->normal.on)
        write_normal(e, &t->normal, depth);
    const csg_finish *f = &t->finish;
    indent(out, depth);
    fputs("finish { ambient rgb ", out);
    put_vec(out, f->ambient, 3);
    put_field(out, " diffuse ", f->diffuse);
    put_field(out, " brilliance ", f->brilliance);
    put_field(out, " specular ", f->specular);
    put_field(out, " roughness ", f->roughness);
    put_field(out, " phong ", f->phong);
    put_field(out, " phong_size ", f->phong_size);
    put_field(out, " metallic ", f->metallic);
    if (f->crand != 0)
        put_field(out, " crand ", f->crand);
    if (f->irid != 0) {
        put_field(out, " irid { ", f->irid);
        put_field(out, " thickness ", f->irid_thickness);
        put_field(out, " turbulence ", f->irid_turbulence);
        fputs(" }", out);
    }
    if (f->reflection_variable) {
        fputs(" reflection { rgb ", out);
        put_vec(out, f->reflection_min, 3);
        fputs(", rgb ", out);
        put_vec(out, f->reflection, 3);
        put_field(out, " falloff ", f->reflection_falloff);
        put_field(out, " exponent ", f->reflection_exponent);
        put_field(out, " metallic ", f->reflection_metallic);
        fputs(f->reflection_fresnel ? " fresnel on }" : " fresnel off }", out);
        if (f->conserve_energy)
            fputs(" conserve_energy", out);
    } else {
        fputs(" reflection rgb ", out);
        put_vec(out, f->reflection, 3);
    }
    fputs(" }\n", out);
}

/* texture { } for each layer, the bottom one first (POV-Ray puts the
 * last written on top). */
static void write_texture_as(const exporter *e, const csg_texture *t, int depth,
                             const char *keyword)
{
    FILE *out = e->out;
    const csg_texture *layers[64];
    int n = 0;
    for (const csg_texture *l = t; l && n < 64; l = l->under)
        layers[n++] = l;
    for (int i = n - 1; i >= 0; i--) {
        indent(out, depth);
        fprintf(out, "%s {\n", keyword);
        write_texture_body(e, layers[i], depth + 1);
        indent(out, depth);
        fputs("}\n", out);
    }
}

static void write_texture(const exporter *e, const csg_texture *t, int depth)
{
    write_texture_as(e, t, depth, "texture");
}

/* A transform the parser would refuse as `matrix` (its determinant
 * underflows to 0, as scale 1e-300 makes it) as `scale <2^e..>` and the
 * matrix with each axis divided by its power of two: both steps exact, so
 * the parser composes the same doubles back.  False when that does not
 * help either (then the matrix is written as it is). */
static bool split_scale(const csg_xform *x, double scale[3], csg_xform *rest)
{
    csg_xform inv;
    if (csg_xform_invert(x, &inv))
        return false;
    *rest = *x;
    for (int col = 0; col < 3; col++) {
        double big = 0;
        for (int row = 0; row < 3; row++)
            big = fmax(big, fabs(x->m[row][col]));
        int e = 0;
        if (big > 0 && isfinite(big))
            frexp(big, &e);
        scale[col] = ldexp(1.0, e);
        for (int row = 0; row < 3; row++)
            rest->m[row][col] = ldexp(x->m[row][col], -e);
    }
    return csg_xform_invert(rest, &inv);
}

/* A transform that overflowed (an entry not finite) or collapsed an axis
 * (singular even as split_scale writes it) has no SDL the parser takes
 * back: the export fails (e->unexportable) rather than write it. */
static void write_matrix(const exporter *e, FILE *out, const csg_xform *x, int depth)
{
    double m[12], scale[3];
    csg_xform rest, inv;
    if (!csg_xform_finite(x))
        *e->unexportable = true;
    if (split_scale(x, scale, &rest)) {
        indent(out, depth);
        fputs("scale ", out);
        put_vec(out, scale, 3);
        fputc('\n', out);
        x = &rest;
    } else if (!csg_xform_invert(x, &inv)) {
        *e->unexportable = true;
    }
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 3; row++)
            m[col * 3 + row] = x->m[row][col];
    indent(out, depth);
    fputs("matrix ", out);
    put_vec(out, m, 12);
    fputc('\n', out);
}

/* The shape's own parameters, one function a shape kind (CSG_OBJECT_KINDS). */
static void export_sphere(FILE *out, const csg_object *o)
{
    put_dvec(out, o->a);
    put_field(out, ", ", o->r0);
}

static void export_box(FILE *out, const csg_object *o)
{
    put_dvec(out, o->a);
    fputs(", ", out);
    put_dvec(out, o->b);
}

static void export_cylinder(FILE *out, const csg_object *o)
{
    export_box(out, o); /* the two end points */
    put_field(out, ", ", o->r0);
    if (o->open)
        fputs(" open", out);
}

static void export_cone(FILE *out, const csg_object *o)
{
    put_dvec(out, o->a);
    put_field(out, ", ", o->r0);
    fputs(", ", out);
    put_dvec(out, o->b);
    put_field(out, ", ", o->r1);
    if (o->open)
        fputs(" open", out);
}

static void export_plane(FILE *out, const csg_object *o)
{
    export_sphere(out, o); /* normal, distance */
}

static void export_torus(FILE *out, const csg_object *o)
{
    put_field(out, "", o->r0);
    put_field(out, ", ", o->r1);
}

static void export_quadric(FILE *out, const csg_object *o)
{
    for (int k = 0; k < 3; k++) {
        put_dvec(out, (dvec3){o->coef[3 * k], o->coef[3 * k + 1], o->coef[3 * k + 2]});
        fputs(", ", out);
    }
    put_field(out, "", o->coef[9]);
}

/* poly { ORDER, <coefficients> } (a quartic or a cubic too). */
static void export_poly(FILE *out, const csg_object *o)
{
    int terms = (o->poly_order + 1) * (o->poly_order + 2) * (o->poly_order + 3) / 6;
    fprintf(out, "%d, <", o->poly_order);
    for (int k = 0; k < terms; k++)
        put_field(out, k ? ", " : "", o->poly_coef[k]);
    fputc('>', out);
}

/* Surfaces: vertices (and normals) as POV-Ray writes them. */
static void put_points(FILE *out, const dvec3 *v, const dvec3 *n, int first, int count)
{
    for (int i = first; i < first + count; i++) {
        if (i > first)
            fputs(", ", out);
        put_dvec(out, v[i]);
        if (n) {
            fputs(", ", out);
            put_dvec(out, n[i]);
        }
    }
}

static void export_triangle(FILE *out, const csg_object *o)
{
    put_points(out, o->verts, NULL, 0, 3);
}

static void export_smooth_triangle(FILE *out, const csg_object *o)
{
    put_points(out, o->verts, o->normals, 0, 3);
}

/* POV-Ray's polygon decides inside by crossings, like ours by ear
 * clipping; it wants the outline closed by the first vertex again. */
static void export_polygon(FILE *out, const csg_object *o)
{
    fprintf(out, "%d, ", o->vert_count + 1);
    put_points(out, o->verts, NULL, 0, o->vert_count);
    fputs(", ", out);
    put_dvec(out, o->verts[0]);
}

/* A mesh's triangles, one a line; a flat one (zero normals) as triangle. */
static void export_mesh(FILE *out, const csg_object *o)
{
    for (int k = 0; k + 2 < o->vert_count; k += 3) {
        const dvec3 *n = o->normals ? o->normals + k : NULL;
        bool smooth = false;
        for (int i = 0; n && i < 3; i++)
            smooth = smooth || n[i].x != 0 || n[i].y != 0 || n[i].z != 0;
        fputs(smooth ? "\n    smooth_triangle { " : "\n    triangle { ", out);
        put_points(out, o->verts, smooth ? o->normals : NULL, k, 3);
        fputs(" }", out);
    }
}

/* A prism as POV-Ray's linear prism: each polyline closed by its first
 * point again; its heights along POV-Ray's y (write_object writes the
 * transform with the swap of y and z first: csg_prism_pov_frame). */
static void export_prism(FILE *out, const csg_object *o)
{
    int total = o->vert_count + o->contour_count;
    fputs(o->conic ? "linear_spline conic_sweep " : "linear_spline linear_sweep ", out);
    put_field(out, "", o->r0);
    put_field(out, ", ", o->r1);
    fprintf(out, ", %d", total);
    int start = 0;
    for (int k = 0; k < o->contour_count; start = o->contour_ends[k], k++) {
        for (int i = start; i <= o->contour_ends[k]; i++) {
            dvec3 v = o->verts[i < o->contour_ends[k] ? i : start];
            fputs(",\n    <", out);
            put_field(out, "", v.x);
            put_field(out, ", ", v.y);
            fputc('>', out);
        }
    }
}

/* The shape's own parameters, after the opening brace. */
static void write_shape(FILE *out, const csg_object *o)
{
    switch (o->kind) {
#define EXPORT_SHAPE(ID, name)                                                                     \
    case CSG_OBJ_##ID:                                                                             \
        export_##name(out, o);                                                                     \
        break;
        CSG_OBJECT_KINDS(EXPORT_SHAPE, CSG_KIND_NONE)
    default:
        break;
    }
}

static bool check_node(const exporter *e, const csg_object *o, int depth)
{
    if (!csg_object_kind_name(o->kind)) {
        csg_error(e->d, o->loc, "export: unknown object kind %d", (int)o->kind);
        return false;
    }
    if (e->base + depth > EXPORT_MAX_DEPTH) {
        csg_error(e->d, o->loc, "export: objects nested deeper than %d levels", EXPORT_MAX_DEPTH);
        return false;
    }
    if (o->texture < -1 || o->texture >= e->s->texture_count) {
        csg_error(e->d, o->loc, "export: texture index %d out of range", o->texture);
        return false;
    }
    if (o->interior < -1 || o->interior >= e->s->interior_count) {
        csg_error(e->d, o->loc, "export: interior index %d out of range", o->interior);
        return false;
    }
    if (o->interior_texture < 0 || o->interior_texture > e->s->texture_count) {
        csg_error(e->d, o->loc, "export: interior_texture index %d out of range",
                  o->interior_texture - 1);
        return false;
    }
    if (!csg_object_is_leaf(o->kind) &&
        (o->child_count < 0 || (o->child_count > 0 && !o->children))) {
        csg_error(e->d, o->loc, "export: malformed %s", csg_object_kind_name(o->kind));
        return false;
    }
    return true;
}

static bool write_object(const exporter *e, const csg_object *o, const csg_texture *texture,
                         int depth);

/* Does the tree of o reach deeper than `levels` below it? */
static bool deeper_than(const csg_object *o, int levels)
{
    if (csg_object_is_leaf(o->kind) || o->child_count <= 0 || !o->children)
        return false;
    if (levels <= 0)
        return true;
    for (int i = 0; i < o->child_count; i++)
        if (deeper_than(o->children[i], levels - 1))
            return true;
    return false;
}

/* The statement of o (at `depth` of e's) written into memory first, the
 * declarations its deep nodes need going to e->top meanwhile; then, with
 * `name` NULL, the statement itself to e->top (a top-level object), else
 * `#declare NAME = ` it and `object { NAME }` in its place. */
static bool write_buffered(const exporter *e, const csg_object *o, const csg_texture *texture,
                           int depth, bool declare)
{
    char *text = NULL;
    size_t size = 0;
    FILE *mem = open_memstream(&text, &size);
    if (!mem) {
        csg_error(e->d, o->loc, "export: out of memory");
        return false;
    }
    exporter sub = *e;
    sub.out = mem;
    sub.base = e->base + depth;
    bool ok = write_object(&sub, o, texture, 0);
    ok = fclose(mem) == 0 && ok;
    if (ok && declare) {
        int id = (*e->declared)++;
        fprintf(e->top, "#declare CSG_Export_%d =\n%s\n", id, text);
        indent(e->out, depth);
        fprintf(e->out, "object { CSG_Export_%d }\n", id);
    } else if (ok) {
        fputs(text, e->top);
    }
    free(text);
    return ok;
}

/* `KEYWORD { OBJECT... }` of a clip or bound list, each object in world
 * space: written after the object's own matrix, nothing transforms it
 * again. */
static bool write_list(const exporter *e, const char *keyword, csg_object *const *list,
                       int count, int depth)
{
    exporter sub = *e;
    sub.in_clip = true;
    indent(e->out, depth + 1);
    fprintf(e->out, "%s {\n", keyword);
    for (int i = 0; i < count; i++)
        if (!write_object(&sub, list[i], NULL, depth + 2))
            return false;
    indent(e->out, depth + 1);
    fputs("}\n", e->out);
    return true;
}

/* clipped_by { } and bounded_by { } (or bounded_by { clipped_by }). */
static bool write_bounds_and_clips(const exporter *e, const csg_object *o, int depth)
{
    if (o->clip_count > 0 && !write_list(e, "clipped_by", o->clips, o->clip_count, depth))
        return false;
    if (o->bound_is_clip) {
        indent(e->out, depth + 1);
        fputs("bounded_by { clipped_by }\n", e->out);
    } else if (o->bound_count > 0 &&
               !write_list(e, "bounded_by", o->bounds, o->bound_count, depth)) {
        return false;
    }
    return true;
}

/* `texture`: the inherited texture (NULL: none, POV-Ray's default). */
static bool write_object(const exporter *e, const csg_object *o, const csg_texture *texture,
                         int depth)
{
    if (!check_node(e, o, depth))
        return false;
    if (o->interior_texture > 0 && e->inside != o->interior_texture) { /* (inherited below) */
        exporter inner = *e;
        inner.inside = o->interior_texture;
        return write_object(&inner, o, texture, depth);
    }
    if (depth == EXPORT_HOIST_DEPTH && !csg_object_is_leaf(o->kind))
        return write_buffered(e, o, texture, depth, true);
    FILE *out = e->out;
    if (o->texture >= 0)
        texture = &e->s->textures[o->texture];
    indent(out, depth);
    fputs(csg_object_kind_name(o->kind), out);
    fputs(" {", out);
    if (!csg_object_is_leaf(o->kind)) {
        fputc('\n', out);
        for (int i = 0; i < o->child_count; i++)
            if (!write_object(e, o->children[i], texture, depth + 1))
                return false;
    } else {
        fputc(' ', out);
        write_shape(out, o);
        fputc('\n', out);
        csg_xform x = o->xform;
        if (o->kind == CSG_OBJ_PRISM)
            csg_prism_pov_frame(&x);
        write_matrix(e, out, &x, depth + 1);
        csg_texture def;
        if (!texture) {
            csg_texture_default(&def);
            texture = &def;
        }
        if (!e->in_clip)
            write_texture(e, texture, depth + 1);
        if (!e->in_clip && e->inside > 0)
            write_texture_as(e, &e->s->textures[e->inside - 1], depth + 1, "interior_texture");
    }
    if (!write_bounds_and_clips(e, o, depth))
        return false;
    if (!e->flat && !e->in_clip && o->interior >= 0) {
        indent(out, depth + 1);
        const csg_interior *in = &e->s->interiors[o->interior];
        put_field(out, "interior { ior ", in->ior);
        if (in->fade_distance != 0 || in->fade_power != 0) {
            put_field(out, " fade_distance ", in->fade_distance);
            put_field(out, " fade_power ", in->fade_power);
            fputs(" fade_color rgb ", out);
            put_vec(out, in->fade_color, 3);
        }
        fputs(" }\n", out);
    }
    if (o->inverse) {
        indent(out, depth + 1);
        fputs("inverse\n", out);
    }
    if (o->no_shadow) {
        indent(out, depth + 1);
        fputs("no_shadow\n", out);
    }
    if (!e->flat && o->hollow) {
        indent(out, depth + 1);
        fputs(o->hollow == 1 ? "hollow\n" : "hollow off\n", out);
    }
    indent(out, depth);
    fputs("}\n", out);
    return true;
}

/* ---- entry point ------------------------------------------------------------------- */

bool csg_export_pov(const csg_scene *s, FILE *out, bool flat, csg_diag *d)
{
    int declared = 0;
    bool unexportable = false;
    exporter e = {s, out, out, &declared, 0, flat, d, &unexportable, false, 0};
    fprintf(out, "// %s exported by csgtrace%s\n", s->path ? s->path : "scene",
            flat ? " (flat: object colours only, for the geometry cross-check)" : "");
    /* the scene's version where it changes what the export means (the
     * sky's mix, the gamma handling and the opacity before 3.7: a scene
     * that read no #version is POV-Ray's 3.62), never below 3.5 (the
     * camera's fixed order) */
    double v = s->version_implied ? 3.62 : s->version;
    v = v < 3.5 ? 3.5 : v > 3.7 ? 3.7 : v;
    put_field(out, "#version ", v);
    fputs(";\n\n", out);
    write_globals(&e);
    write_camera(&e);
    write_background_and_lights(&e);
    for (int i = 0; i < s->object_count; i++) {
        const csg_object *o = s->objects[i];
        bool deep = deeper_than(o, EXPORT_HOIST_DEPTH); /* (else streamed: a mesh may be big) */
        if (!(deep ? write_buffered(&e, o, NULL, 0, false) : write_object(&e, o, NULL, 0)))
            goto fail;
        fputc('\n', out);
    }
    if (unexportable) {
        csg_error_plain(d, "cannot export the scene: a transformation overflows or collapses an "
                           "axis (its matrix is not finite, or singular), which POV-Ray's "
                           "language cannot state");
        goto fail;
    }
    if (fflush(out) != 0 || ferror(out)) {
        csg_error_plain(d, "cannot write the exported scene");
        goto fail;
    }
    return true;
fail:
    return false;
}
