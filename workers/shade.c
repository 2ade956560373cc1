/*
 * shade.c — the CPU side of the renderer, compiled once per precision:
 * primary hit records for a tile (the same shared code the OpenCL kernel
 * runs) and Whitted shading from those records.
 *
 * Shading follows POV-Ray 3.7's classic model where it is reasonable
 * (scenes/LANGUAGE.md lists the differences):
 *   colour = opacity * (ambient * pigment * ambient_light
 *                       + sum over lights: diffuse * cos * pigment * light)
 *          + highlights (phong, Blinn specular) * light (none from a
 *            shadowless light, as in POV-Ray)
 *          + reflection * trace(reflected ray)
 *          + (filter * pigment + transmit) * trace(refracted ray)
 * where opacity = 1 - filter - transmit, the light reaching a point is
 * the light's colour times the transmittance of every surface between
 * (shadow rays: each filtering/transmitting surface multiplies by
 * filter * pigment + transmit, an opaque one blocks), and a secondary ray
 * is traced only while the trace level is below max_depth and its weight
 * in the pixel is at least adc_bailout.  A ray that leaves the scene sees
 * the background, or the sky_sphere's pigments at its direction.  Patterned
 * pigments are evaluated at the hit point (pigment.c).  Total internal reflection traces
 * the reflected ray instead, faded but not filtered (POV-Ray's TraceRefractionRay).
 *
 * Secondary rays start at the hit point moved off the surface by a few
 * units in the last place along the normal (Wächter and Binder, "A Fast and
 * Robust Method for Avoiding Self-Intersection", Ray Tracing Gems ch. 6),
 * towards the side the new ray leaves to, and at least by the rounding the
 * ray that found the point carried (csg/device/offset.h), so no fixed epsilon
 * is needed at any scale.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../comm/pixels.h"
#include "../csg/device/camera.h"
#include "../csg/device/shadow.h"
#include "engine.h"
#include "frustum.h"
#include "noise.h"
#include "noise.h"
#include "../csg/device/offset.h"
#include "pager.h"
#include "pigment.h"

#ifdef CSG_DOUBLE
#define ENGINE_SYM(name) name##_double
#else
#define ENGINE_SYM(name) name##_float
#endif

typedef struct {
    const csg_blob_header *hdr;
    csg_view view;
    const csg_material *mats;
    const csg_map_color *maps; /* the colour maps of patterned pigments */
    const csg_flat_light *lights;
    const csg_camera *cam;
    vec3 ambient_light;
    vec3 background;
    real bailout;
    const csg_material *sky; /* the sky_sphere's pigments (sky_count)   */
    csg_i32 sky_count, sky_v37;
    vec3 sky_emission;
    csg_i32 max_rays;        /* reflected and refracted rays a pixel may trace */
    csg_i32 output;          /* enum csg_output_gamma: the pixel's way to the file */
    float output_gamma;
    const csg_flat_fog *fogs;
    csg_i32 fog_count;
    csg_i32 camera_solid;    /* non-hollow objects around the camera        */
    csg_i32 noise_gen;       /* the scene's noise generator (irid's)        */
    double irid_wavelength[3];
} shade_ctx;

_Static_assert((int)CSG_OUTPUT_SRGB == (int)PIXELS_GAMMA_SRGB &&
                   (int)CSG_OUTPUT_POWER == (int)PIXELS_GAMMA_POWER &&
                   (int)CSG_OUTPUT_DIRECT == (int)PIXELS_GAMMA_DIRECT,
               "the output gamma modes of flat.h and pixels.h");

/* The rays of one pixel: the tile's counts, and what is left of the
 * pixel's budget (a ray it cannot pay for is not traced: the order of the
 * ray tree is fixed, so every mode drops the same rays). */
typedef struct {
    ray_counts *rays;
    csg_i32 left;
    bool refused; /* a ray was not traced for want of budget */
    csg_i32 *blockers; /* the shadow cache of the tile (shadow_slot) */
    uint64_t rng_key;   /* the pixel's sample: its random stream (pixel_random) */
    uint64_t rng_drawn; /* numbers drawn from it so far                          */
    csg_u32 shadow_known; /* the primary hit's shadow answers from its record   */
    csg_u32 shadow_lit;   /* (csg/device/shadow.h: csg_shadow_masks); 0: none   */
    int continued;      /* continued rays (same ior) now nested: at
                           SHADE_MAX_CONTINUED the next one takes a level  */
} ray_tally;

/* Continued rays nested at most (each a C stack frame of trace_ray; past
 * it a ray through a same-ior surface takes a trace level again). */
#define SHADE_MAX_CONTINUED 256

/* ---- randomness ----------------------------------------------------------------
 * POV-Ray draws crand's grain and an area light's jitter from a generator
 * per render thread, so its images change from run to run.  Ours are a
 * function of the image alone: each primary sample (pixel x, y, sample s)
 * owns a stream, the n-th number of which is a hash of (x, y, s, n), and
 * the ray tree of a sample is walked in a fixed order.  So every mode,
 * tile size, rank count, batch and resume draws the same numbers for the
 * same pixel: the images stay byte-identical. */

/* splitmix64's finaliser: a bijection of 64 bits that mixes every bit. */
static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
    return z ^ (z >> 31);
}

/* The stream of sample s of pixel (x, y) (image coordinates). */
static uint64_t sample_stream(int x, int y, int s)
{
    uint64_t k = ((uint64_t)(uint32_t)y << 32) | (uint32_t)x;
    return mix64(mix64(k) ^ ((uint64_t)(uint32_t)s * UINT64_C(0x9e3779b97f4a7c15)));
}

/* The next number of the sample's stream, uniform in [0, 1) (53 bits). */
static double pixel_random(ray_tally *t)
{
    uint64_t h = mix64(t->rng_key + ++t->rng_drawn * UINT64_C(0x9e3779b97f4a7c15));
    return (double)(h >> 11) * (1.0 / 9007199254740992.0);
}

/* The shadow cache (POV-Ray's light buffer idea): for each light and
 * trace level, the last root found to block that light, tried first by
 * the next shadow ray of the same light and level.  Exact: a shadow ray
 * returns "nothing passes" as soon as any root on its segment lets nothing
 * through, and a root that does so is one the full walk would reach (its
 * box passed, so did every BVH box around it), so trying it first changes
 * which root is found, never the answer.  -1: no root cached (a cached
 * root that fails to block is dropped: most shadow rays of a sparse scene
 * reach their light, and a stale root would cost every one a test). */
#define SHADOW_CACHE_SLOTS 256

/* The cache slot of light i at trace level `level`, NULL beyond the cache. */
static csg_i32 *shadow_slot(const shade_ctx *c, ray_tally *t, csg_i32 i, int level)
{
    size_t k = (size_t)level * (size_t)c->hdr->light_count + (size_t)i;
    return k < SHADOW_CACHE_SLOTS ? &t->blockers[k] : NULL;
}

static bool ray_spend(ray_tally *t)
{
    if (t->left <= 0) {
        t->refused = true;
        return false;
    }
    t->left--;
    return true;
}

static shade_ctx ctx_of(const void *blob)
{
    const unsigned char *b = blob;
    shade_ctx c;
    c.hdr = blob;
    c.view = csg_blob_view(b);
    c.view.pager = pager_for(blob);
    c.view.page_tops = c.view.pager ? pager_page_tops(c.view.pager) : NULL;
    c.mats = (const csg_material *)(b + c.hdr->off_materials);
    c.maps = (const csg_map_color *)(b + c.hdr->off_maps);
    c.lights = (const csg_flat_light *)(b + c.hdr->off_lights);
    c.cam = csg_blob_camera(b);
    const csg_shading *sh = (const csg_shading *)(b + c.hdr->off_shading);
    c.ambient_light = v3_load(sh->ambient_light);
    c.background = v3_load(sh->background);
    c.bailout = sh->adc_bailout;
    c.sky = c.mats + sh->sky_first;
    c.sky_count = c.hdr->sky_count;
    c.sky_v37 = sh->sky_v37;
    c.sky_emission = v3_load(sh->sky_emission);
    c.max_rays = sh->max_rays;
    c.output = sh->output;
    c.output_gamma = (float)sh->output_gamma;
    c.fogs = sh->fogs;
    c.fog_count = sh->fog_count;
    c.camera_solid = sh->camera_solid;
    c.noise_gen = sh->noise_gen;
    for (int i = 0; i < 3; i++)
        c.irid_wavelength[i] = (double)sh->irid_wavelength[i];
    return c;
}

/* ---- shadows ------------------------------------------------------------------ */

static real max3(vec3 v) { return r_fmax(v.x, r_fmax(v.y, v.z)); }

#define SHADE_MAX_DEPTH 16 /* texture_maps nested, and layers of one texture */

static vec3 grey3(real v) { return v3(v, v, v); }

#define FOG_BOUND_HUGE 2.0e10 /* POV-Ray's BOUND_HUGE: a ray that hits nothing */

/* POV-Ray's ComputeConstantFogColour and ComputeGroundFogColour: the
 * fraction of light that crosses `width` of fog f along r. */
static double fog_attenuation(const csg_flat_fog *f, csg_ray r, double width)
{
    double o[3] = {(double)r.o.x, (double)r.o.y, (double)r.o.z};
    double d[3] = {(double)r.d.x, (double)r.d.y, (double)r.d.z};
    double distance = (double)f->distance, density = 1.0, mid[3];
    if (f->kind == 2) {
        double up[3] = {(double)f->up[0], (double)f->up[1], (double)f->up[2]};
        double p2[3] = {o[0] + d[0] * width, o[1] + d[1] * width, o[2] + d[2] * width};
        double y1 = o[0] * up[0] + o[1] * up[1] + o[2] * up[2];
        double y2 = p2[0] * up[0] + p2[1] * up[1] + p2[2] * up[2];
        double start = (y1 - (double)f->offset) / (double)f->alt;
        double end = (y2 - (double)f->offset) / (double)f->alt;
        if (start <= 0.0)
            density = end <= 0.0 ? 1.0 : (atan(end) - start) / (end - start);
        else if (end <= 0.0)
            density = (atan(start) - end) / (start - end);
        else if (fabs(start - end) > 1e-10)
            density = (atan(start) - atan(end)) / (start - end);
        else
            density = 1.0 / (start * start + 1.0);
        for (int k = 0; k < 3; k++)
            mid[k] = (o[k] + p2[k]) * 0.5;
    } else {
        for (int k = 0; k < 3; k++)
            mid[k] = o[k] + width / 2.0 * d[k];
    }
    if (f->turb_on) {
        for (int k = 0; k < 3; k++)
            mid[k] *= (double)f->turbulence[k];
        double kk = exp(-width / distance);
        noise_turb t = {f->octaves, (double)f->omega, (double)f->lambda};
        double turb = noise_turbulence(mid, &t, f->noise_gen) * (double)f->turb_depth;
        width *= 1.0 - kk * (turb < 1.0 ? turb : 1.0);
    }
    return exp(-width * density / distance);
}

/* POV-Ray's ComputeFog: col seen through every fog over `depth` along r
 * (a shadow ray only loses light, it gains none of the fog's colour). */
static vec3 apply_fog(const shade_ctx *c, csg_ray r, double depth, vec3 col, bool shadow)
{
    double att_sum[3] = {1.0, 1.0, 1.0}, col_sum[3] = {0.0, 0.0, 0.0};
    for (csg_i32 i = 0; i < c->fog_count; i++) {
        const csg_flat_fog *f = &c->fogs[i];
        if (!(fabs((double)f->distance) > 1e-10))
            continue;
        double att = fog_attenuation(f, r, depth);
        double filter = (double)f->rgbft[3], transmit = (double)f->rgbft[4];
        if (att < transmit)
            att = transmit;
        for (int k = 0; k < 3; k++) {
            att_sum[k] *= att * ((1.0 - filter) + filter * (double)f->rgbft[k]);
            if (!shadow)
                col_sum[k] += (1.0 - att) * (double)f->rgbft[k];
        }
    }
    return v3((real)(col_sum[0] + att_sum[0] * (double)col.x),
              (real)(col_sum[1] + att_sum[1] * (double)col.y),
              (real)(col_sum[2] + att_sum[2] * (double)col.z));
}

/* What texture material m lets through at w (a surface point, or a point
 * of the space of the texture_map holding m): POV-Ray's
 * ComputeShadowTexture, the product of every layer's filter * pigment +
 * transmit, or the blend of a texture_map's entries. */
static vec3 texture_filter(const shade_ctx *c, const csg_material *m, const double w[3],
                           double err, int depth)
{
    if (m->tmap && m->pattern == CSG_PATTERN_AVERAGE) {
        double q[3], q_err, total = 0.0;
        int prev, cur;
        PIGMENT_TMAP(c->mats, m, c->maps, w, err, q, &q_err, &prev, &cur);
        vec3 sum = grey3(R(0.0));
        for (int i = 0; depth < SHADE_MAX_DEPTH && i < m->map_count; i++) {
            real weight = c->maps[m->map_first + i].value;
            vec3 one = texture_filter(c, &c->mats[m->sub_first + i], q, q_err, depth + 1);
            sum = v3_add(sum, v3_scale(one, weight));
            total += (double)weight;
        }
        return total != 0.0 ? v3_scale(sum, (real)(1.0 / total)) : grey3(R(0.0));
    }
    if (m->tmap) {
        double q[3], q_err;
        int prev, cur;
        double f = PIGMENT_TMAP(c->mats, m, c->maps, w, err, q, &q_err, &prev, &cur);
        if (depth >= SHADE_MAX_DEPTH)
            return grey3(R(0.0));
        vec3 a = texture_filter(c, &c->mats[m->sub_first + cur], q, q_err, depth + 1);
        if (prev == cur)
            return a;
        vec3 b = texture_filter(c, &c->mats[m->sub_first + prev], q, q_err, depth + 1);
        return v3_add(v3_scale(a, (real)f), v3_scale(b, (real)(1.0 - f)));
    }
    vec3 pass = grey3(R(1.0));
    for (int k = 0; m && k < SHADE_MAX_DEPTH; k++) {
        pigment_color pc = PIGMENT_EVAL(c->mats, m, c->maps, w, err);
        pass = v3_mul(pass, v3_add(v3_scale(pc.color, pc.filter), grey3(pc.transmit)));
        m = m->under > 0 ? &c->mats[m->under - 1] : NULL;
    }
    return pass;
}

/* POV-Ray's distance attenuation inside an interior (fade_distance,
 * fade_power, fade_color) over `depth`: exponential from a fade_power of
 * 1000 on, else 1 / (1 + (depth / fade_distance)^fade_power) towards the
 * fade colour. */
static vec3 fade(const csg_material *m, real depth)
{
    vec3 fc = v3_load(m->fade_color);
    double d = (double)depth / (double)m->fade_distance;
    if (m->fade_power >= R(1000.0))
        return v3((real)exp(-(1.0 - (double)fc.x) * d), (real)exp(-(1.0 - (double)fc.y) * d),
                  (real)exp(-(1.0 - (double)fc.z) * d));
    double att = 1.0 + pow(d, (double)m->fade_power);
    return v3((real)((double)fc.x + (1.0 - (double)fc.x) / att),
              (real)((double)fc.y + (1.0 - (double)fc.y) / att),
              (real)((double)fc.z + (1.0 - (double)fc.z) / att));
}

/* Whether interior fading applies to light through m (POV-Ray's
 * ComputeShadowTexture: fade_power > 0 as well as a fade_distance). */
static bool fades_shadow(const csg_material *m)
{
    return m->fade_power > R(0.0) && r_fabs(m->fade_distance) > R(1e-10);
}

/* A shadow ray leaving a solid through surface s (NONE: it does not leave
 * it before the light) after `depth` inside: *pass faded by its interior;
 * false once nothing passes. */
static bool shadow_fade(const shade_ctx *c, csg_u32 s, real depth, vec3 *pass)
{
    if (s == CSG_SURF_NONE)
        return true;
    const csg_prim *prim = &c->view.prims[CSG_SURF_PRIM(s)];
    const csg_material *m = &c->mats[prim->material];
    if ((prim->flags & CSG_PF_NO_SHADOW) || !fades_shadow(m))
        return true;
    *pass = v3_mul(*pass, fade(m, depth));
    return max3(*pass) > R(0.0);
}

/* POV-Ray's interior_texture (Trace's normaldirection): where a ray of
 * direction d meets the surface whose outward normal is n (the solid's:
 * a complemented primitive's reversed, as POV-Ray reverses an inverted
 * object's) from inside, material m's inside material; else m. */
static const csg_material *seen_material(const shade_ctx *c, const csg_material *m, vec3 n, vec3 d)
{
    return m->inside > 0 && v3_dot(n, d) > R(0.0) ? &c->mats[m->inside - 1] : m;
}

/* Multiplies *pass by what surface s, met at ts along r, lets through on
 * the way to the light `dist` away (its pigment there); false once nothing
 * passes. */
static bool surface_transmittance(const shade_ctx *c, csg_ray r, csg_u32 s, real ts, real dist,
                                  vec3 *pass)
{
    if (s == CSG_SURF_NONE || !(ts > R(0.0)) || !(ts < dist))
        return true;
    const csg_prim *prim = &c->view.prims[CSG_SURF_PRIM(s)];
    if (prim->flags & CSG_PF_NO_SHADOW)
        return true;
    const csg_material *m = &c->mats[prim->material];
    if (m->inside > 0) {
        vec3 n = csg_surface_normal(c->view.prims, s, v3_add(r.o, v3_scale(r.d, ts)));
        m = seen_material(c, m, n, r.d);
    }
    real err = OFFSET_ERR_ULPS * OFFSET_UNIT_ROUNDOFF * offset_magnitude(r.o, r.d, ts);
    if (m->tmap || m->under > 0) { /* a texture_map or layers */
        double w[3];
        PIGMENT_SURFACE_POINT(c->view.prims, s, v3_add(r.o, v3_scale(r.d, ts)), w);
        vec3 f = texture_filter(c, m, w, (double)err, 0);
        if (max3(f) <= R(0.0))
            return false;
        *pass = v3_mul(*pass, f);
        return true;
    }
    pigment_color pc =
        PIGMENT_AT(c->mats, m, c->maps, c->view.prims, s, v3_add(r.o, v3_scale(r.d, ts)), err);
    if (pc.filter <= R(0.0) && pc.transmit <= R(0.0))
        return false;
    *pass = v3_mul(*pass, v3_add(v3_scale(pc.color, pc.filter),
                                 v3(pc.transmit, pc.transmit, pc.transmit)));
    return true;
}

/* Multiplies *pass by what the uncomplemented solid primitive `leaf`, a
 * root by itself, lets through on (0, dist): exactly what root_transmittance
 * does with its one-interval list (csg_leaf_spans, csg_spans_push on a list
 * whose limit is dist), without building the list. */
static bool leaf_transmittance(const shade_ctx *c, csg_i32 leaf, csg_ray r, real dist, vec3 *pass)
{
    const csg_prim *p = &c->view.prims[leaf];
    real t0, t1;
    csg_i32 s0, s1;
    if (!csg_prim_span(p, r, &t0, &t1, &s0, &s1))
        return true;
    csg_u32 e0 = t0 < R(0.0) ? CSG_SURF_NONE : csg_surf_of(leaf, s0, 0u, p->flags);
    csg_u32 e1 = csg_surf_of(leaf, s1, 0u, p->flags);
    real start = r_fmax(t0, R(0.0)), end = t1;
    if (end > dist) {
        end = dist;
        e1 = CSG_SURF_NONE;
    }
    if (!(start < end))
        return true;
    return surface_transmittance(c, r, e0, start, dist, pass) &&
           surface_transmittance(c, r, e1, end, dist, pass) &&
           shadow_fade(c, e1, end - start, pass);
}

/* Multiplies *pass by what root i lets through between the shading point
 * and the light: every interval end and every surface event (the hidden
 * back of a one-sided surface too); false once nothing passes.  Its box is
 * tested first when test_box (a BVH leaf of one root has just tested the
 * same box). */
static bool root_transmittance(const shade_ctx *c, csg_i32 i, csg_ray r, const csg_box_ray *br,
                               int test_box, real dist, vec3 *pass)
{
    const csg_root *rt = &c->view.roots[i];
    real t_enter;
    if (rt->flags & CSG_ROOT_NO_SHADOW)
        return true;
    if (test_box && !csg_box_hit(rt->lo, rt->hi, br, R(0.0), dist, &t_enter))
        return true;
    if (rt->flags & CSG_ROOT_OPAQUE) /* any visible boundary blocks: the first will do */
        return !csg_shadow_opaque_blocks(c->view, i, r, dist);
    if (rt->node_count == 1) {
        csg_i32 leaf = c->view.nodes[rt->first_node].prim;
        const csg_prim *p = &c->view.prims[leaf];
        if (!(p->flags & CSG_PF_INVERT) && !CSG_PRIM_IS_SURFACE(p->kind))
            return leaf_transmittance(c, leaf, r, dist, pass);
    }
    csg_spans spans;
    csg_root_spans(c->view, i, r, R(0.0), dist, &spans);
    for (csg_i32 k = 0; k < spans.n; k++)
        if (!surface_transmittance(c, r, spans.s0[k], spans.t0[k], dist, pass) ||
            !surface_transmittance(c, r, spans.s1[k], spans.t1[k], dist, pass) ||
            (spans.t1[k] > R(0.0) && spans.t1[k] < dist &&
             !shadow_fade(c, spans.s1[k], spans.t1[k] - r_fmax(spans.t0[k], R(0.0)), pass)))
            return false;
    for (csg_i32 k = 0; k < spans.ne; k++)
        if (!surface_transmittance(c, r, spans.se[k], spans.te[k], dist, pass))
            return false;
    return true;
}

/* What fraction of the light passes from p (already offset) to the light
 * `dist` away along unit direction l: every root the segment may cross,
 * the unbounded ones and then those the BVH leads to, in the walk's
 * order (fixed for a given ray); it stops at the first opaque blocker. */
static vec3 light_transmittance(const shade_ctx *c, vec3 p, vec3 l, real dist, csg_i32 *blocker)
{
    dist = csg_shadow_reach(dist); /* POV-Ray's SHADOW_TOLERANCE (shadow.h) */
    vec3 pass = v3(R(1.0), R(1.0), R(1.0));
    const vec3 none = v3(R(0.0), R(0.0), R(0.0));
    csg_ray r;
    r.o = p;
    r.d = l;
    csg_box_ray br = csg_box_ray_of(r);
    if (blocker && *blocker >= 0) { /* the shadow cache: its root behind its box */
        vec3 ignored = pass;
        CSG_PAGE_ROOT(c->view, *blocker);
        if (!root_transmittance(c, *blocker, r, &br, 1, dist, &ignored))
            return none;
        *blocker = -1; /* stale: not tried again until a walk finds a blocker */
    }
    csg_i32 found = -1;
    for (csg_i32 i = 0; i < c->view.root_count && found < 0; i++)
        if (!root_transmittance(c, i, r, &br, 1, dist, &pass))
            found = i;
    csg_bvh_walk w;
    csg_bvh_walk_start(&w, c->view);
    csg_i32 k;
    while (found < 0 && (k = csg_bvh_next_leaf(c->view, &br, R(0.0), dist, &w)) >= 0) {
        const csg_bvh_node *n = &c->view.bvh[k];
        for (csg_i32 i = n->first; i < n->first + n->count && found < 0; i++)
            if (!root_transmittance(c, i, r, &br, n->count > 1, dist, &pass))
                found = i;
    }
    if (found < 0)
        return pass;
    if (blocker)
        *blocker = found;
    return none;
}

/* ---- the sky ---------------------------------------------------------------------- */

/* What a ray along unit direction d that leaves the scene sees: the
 * background, or POV-Ray's sky_sphere over it (its layers from the last
 * written, mixed by their filter and transmit as POV-Ray 3.7 does, or as
 * POV-Ray did before 3.7 for older scenes: trace.cpp, ComputeSky). */
static vec3 sky_color(const shade_ctx *c, vec3 d)
{
    if (c->sky_count == 0)
        return c->background;
    vec3 col = v3(R(0.0), R(0.0), R(0.0)), fil = v3(R(1.0), R(1.0), R(1.0));
    real fil_f = R(1.0), fil_t = R(1.0), trans = R(1.0);
    for (csg_i32 i = c->sky_count - 1; i >= 0; i--) {
        pigment_color pc = PIGMENT_AT(c->mats, &c->sky[i], c->maps, NULL, CSG_SURF_NONE, d, R(0.0));
        real opacity = R(1.0) - pc.filter - pc.transmit;
        if (c->sky_v37) {
            col = v3_add(col, v3_mul(v3_scale(pc.color, opacity), v3_mul(fil, c->sky_emission)));
            fil = v3_mul(fil, v3_add(v3_scale(pc.color, pc.filter),
                                     v3(pc.transmit, pc.transmit, pc.transmit)));
        } else {
            col = v3_add(col, v3_scale(pc.color, trans * opacity));
            fil = v3_mul(fil, pc.color);
            fil_f *= pc.filter;
            fil_t *= pc.transmit;
            trans = r_fabs(fil_f) + r_fabs(fil_t);
        }
    }
    if (c->sky_v37)
        return v3_add(col, v3_mul(c->background, fil));
    vec3 through = v3_add(v3_scale(fil, fil_f), v3(fil_t, fil_t, fil_t));
    return v3_add(v3_mul(col, c->sky_emission), v3_mul(c->background, through));
}

/* ---- Whitted ------------------------------------------------------------------- */


/* base^e for a highlight: base in (0, 1].  A whole exponent up to 4096
 * (phong_size, 1 / roughness: usually whole) by squaring, a few roundings
 * instead of a libm call; once the running power drops below 2^-64 the
 * rest can only make it smaller and it is taken as 0 (no denormal
 * arithmetic; the highlight is then below 2^-64 of the light). */
static real power(real base, real e)
{
    if (e >= R(0.0) && e <= R(4096.0) && e == (real)(int)e) {
        int n = (int)e;
        real result = R(1.0), x = base;
        for (;;) {
            if (n & 1)
                result *= x;
            n >>= 1;
            if (n == 0)
                return result;
            if (x < R(5.421010862427522e-20)) /* 2^-64 */
                return R(0.0);
            x *= x;
        }
    }
#ifdef CSG_DOUBLE
    return pow(base, e);
#else
    return powf(base, e);
#endif
}

/* The colour of a highlight: the light's, or with `metallic` tinted by the
 * pigment by POV-Ray's empirical Fresnel curve of the angle to the light
 * (full tint facing it, none at grazing). */
static vec3 highlight_color(const csg_material *m, vec3 pig, real cosl, vec3 light)
{
    if (!(m->metallic > R(0.0)))
        return light;
#ifdef CSG_DOUBLE
    real x = acos(r_fmin(cosl, R(1.0))) / (R(0.5) * R(M_PI));
#else
    real x = acosf(r_fmin(cosl, R(1.0))) / (R(0.5) * R(M_PI));
#endif
    real f = R(0.014567225) / ((x - R(1.12)) * (x - R(1.12))) - R(0.011612903);
    real k = m->metallic * (R(1.0) - r_fmin(R(1.0), r_fmax(R(0.0), f)));
    vec3 tint = v3(R(1.0) + k * (pig.x - R(1.0)), R(1.0) + k * (pig.y - R(1.0)),
                   R(1.0) + k * (pig.z - R(1.0)));
    return v3_mul(light, tint);
}

static vec3 trace_ray(const shade_ctx *c, csg_ray r, int level, real weight, int solid,
                      ray_tally *tally);

/* POV-Ray's FresnelR: the reflectance of unpolarised light at cosine
 * cos_i, n the relative index of refraction (1: total reflection when no
 * ray is transmitted). */
static double fresnel_r(double cos_i, double n)
{
    double sqrg = n * n + cos_i * cos_i - 1.0;
    if (sqrg <= 0.0)
        return 1.0;
    double g = sqrt(sqrg), gpc = g + cos_i, gmc = g - cos_i;
    double r1 = cos_i * gpc - 1.0, r2 = cos_i * gmc + 1.0;
    return 0.5 * (gmc * gmc) / (gpc * gpc) * (1.0 + (r1 * r1) / (r2 * r2));
}

/* The reflection of a layer with POV-Ray's variable reflection (its
 * ComputeReflectivity and ComputeMetallic) at cosine cosi between the ray
 * and the layer's normal: from MIN facing the ray to MAX at grazing, by
 * (1 - cos)^falloff or by the Fresnel reflectance (n: the relative index
 * of refraction), tinted by the pigment with metallic; *wmax: what the
 * ray's weight is scaled by (the larger of MIN's and MAX's channels, or
 * the Fresnel reflection's). */
static vec3 variable_reflection(const csg_material *m, vec3 pig, real cosi, real n, real *wmax)
{
    vec3 rmax = v3_load(m->reflection), rmin = v3_load(m->reflection_min), refl;
    real frac;
    if (m->reflection_fresnel) {
        frac = (real)fresnel_r((double)cosi, (double)n);
        refl = v3_add(v3_scale(rmax, frac), v3_scale(rmin, R(1.0) - frac));
        *wmax = max3(refl);
    } else {
        *wmax = r_fmax(max3(rmax), max3(rmin));
        real fall = m->reflection_falloff;
        frac = r_fabs(fall - R(1.0)) > R(1e-10) ? power(R(1.0) - cosi, fall) : R(1.0) - cosi;
        refl = r_fabs(frac) < R(1e-10)            ? rmin
               : r_fabs(frac - R(1.0)) < R(1e-10) ? rmax
                   : v3_add(v3_scale(rmax, frac), v3_scale(rmin, R(1.0) - frac));
    }
    if (m->reflection_metallic != R(0.0)) {
#ifdef CSG_DOUBLE
        real x = fabs(acos(r_fmin(r_fmax(cosi, R(-1.0)), R(1.0)))) / (R(0.5) * R(M_PI));
#else
        real x = fabsf(acosf(r_fmin(r_fmax(cosi, R(-1.0)), R(1.0)))) / (R(0.5) * R(M_PI));
#endif
        real f = R(0.014567225) / ((x - R(1.12)) * (x - R(1.12))) - R(0.011612903);
        real k = m->reflection_metallic * (R(1.0) - r_fmin(R(1.0), r_fmax(R(0.0), f)));
        refl = v3_mul(refl, v3(R(1.0) + k * (pig.x - R(1.0)), R(1.0) + k * (pig.y - R(1.0)),
                               R(1.0) + k * (pig.z - R(1.0))));
    }
    return refl;
}

/* A reflected colour to the power 1 / exponent (POV-Ray's
 * reflection_exponent), channel by channel. */
static vec3 reflection_power(vec3 col, real exponent)
{
    if (exponent == R(1.0))
        return col;
    real e = R(1.0) / exponent;
    return v3(col.x > R(0.0) ? power(col.x, e) : R(0.0), col.y > R(0.0) ? power(col.y, e) : R(0.0),
              col.z > R(0.0) ? power(col.z, e) : R(0.0));
}

/* What every texture shading a hit shares: the ray, the point, its
 * normals, where secondary rays start, and the light reaching the point
 * from each light (a shadow ray traced once for all the layers and
 * texture_map entries). */
#define SHADE_LIGHT_CACHE 32
typedef struct {
    csg_ray r;
    vec3 p;
    vec3 nf;       /* the surface normal facing the ray (POV-Ray's rawnormal) */
    vec3 ngf;      /* the geometric normal on the ray's side                   */
    int entering;
    real mag;      /* the offset scale of secondary rays                       */
    vec3 above;    /* where reflected and shadow rays start                    */
    double w[3];   /* the point the patterns are evaluated at                  */
    double err;    /* its rounding bound                                       */
    int level;
    int solid;     /* non-hollow objects the ray is inside (no fog there)      */
    real depth;    /* the hit's distance along the ray                         */
    int prim_solid; /* 1: the object hit is not hollow                         */
    csg_u32 light_done; /* bit i: light i's light is in light[i]               */
    vec3 light[SHADE_LIGHT_CACHE];
} hit_info;

/* POV-Ray's cubic_spline: 0 below low, 1 from high, a smooth step between. */
static double cubic_spline(double low, double high, double pos)
{
    if (pos < low)
        return 0.0;
    if (pos >= high)
        return 1.0;
    pos = (pos - low) / (high - low);
    return (3 - 2 * pos) * pos * pos;
}

/* POV-Ray's ComputeOneWhiteLightRay: the unit direction *l from point o to
 * light lt (its centre moved by `jitter`) and how far the shadow ray goes;
 * a plain point light is the line to its position. */
static void light_ray(const csg_flat_light *lt, vec3 o, vec3 jitter, vec3 *l, real *dist)
{
    csg_light_ray(lt, o, v3_add(v3_load(lt->position), jitter), l, dist);
}

/* POV-Ray's Attenuate_Light: a spotlight's cone, a cylinder light's
 * radius, the fade with distance (dist: the shadow ray's length; o the
 * point lit). */
static double light_attenuation(const csg_flat_light *lt, vec3 o, vec3 l, real dist)
{
    double att = 1.0;
    if (lt->kind == CSG_LIGHT_SPOT) {
        double costheta = (double)v3_dot(l, v3_load(lt->direction));
        if (dist > R(0.0))
            costheta = -costheta;
        if (!(costheta > 0.0))
            return 0.0;
        att = pow(costheta, (double)lt->tightness);
        if (lt->radius > R(0.0) && costheta < (double)lt->radius)
            att *= cubic_spline((double)lt->falloff, (double)lt->radius, costheta);
    } else if (lt->kind == CSG_LIGHT_CYLINDER) {
        vec3 dir = v3_load(lt->direction);
        vec3 v1 = v3_sub(o, v3_load(lt->position));
        real k = v3_dot(v1, dir);
        if (!(k > R(0.0)))
            return 0.0;
        double len = (double)v3_length(v3_sub(v1, v3_scale(dir, k)));
        if (!(len < (double)lt->falloff))
            return 0.0;
        double d = 1.0 - len / (double)lt->falloff;
        att = pow(d, (double)lt->tightness);
        if (lt->radius > R(0.0) && len > (double)lt->radius)
            att *= cubic_spline(0.0, 1.0 - (double)lt->radius / (double)lt->falloff, d);
    }
    if (att > 0.0 && lt->fade_power > R(0.0) && fabs((double)lt->fade_distance) > 1e-10)
        att *= 2.0 / (1.0 + pow((double)dist / (double)lt->fade_distance, (double)lt->fade_power));
    return att;
}

/* A plain point light: no attenuation (the arithmetic of csgtrace before
 * spotlights, kept bit for bit). */
static bool light_plain(const csg_flat_light *lt)
{
    return lt->kind == CSG_LIGHT_POINT && !lt->parallel && !lt->area &&
           !(lt->fade_power > R(0.0) && fabs((double)lt->fade_distance) > 1e-10);
}

static vec3 grey3(real v);
static vec3 apply_fog(const shade_ctx *c, csg_ray r, double depth, vec3 col, bool shadow);

/* What light lt lets reach p through the scene from the point of the
 * area light (i, j) of its grid (POV-Ray's TraceAreaLightSubsetShadowRay
 * corner): the colour times the transmittance of the shadow ray. */
static vec3 area_sample(const shade_ctx *c, const csg_flat_light *lt, vec3 p, vec3 a1, vec3 a2,
                        int u, int v, vec3 color, csg_i32 *blocker, ray_tally *tally)
{
    double ju = (double)u, jv = (double)v;
    if (lt->jitter) { /* anywhere in the point's cell (POV-Ray: +-0.5 of a step) */
        ju += pixel_random(tally) - 0.5;
        jv += pixel_random(tally) - 0.5;
    }
    vec3 ja, jb;
    if (lt->circular) {
        ju = ju / (double)(lt->size1 - 1) - 0.5 + 0.001;
        jv = jv / (double)(lt->size2 - 1) - 0.5 + 0.001;
        double sf = fabs(ju) > fabs(jv) ? fabs(ju) : fabs(jv);
        sf /= sqrt(ju * ju + jv * jv);
        ju *= sf;
        jv *= sf;
        ja = v3_scale(a1, (real)ju);
        jb = v3_scale(a2, (real)jv);
    } else {
        ja = lt->size1 > 1 ? v3_scale(a1, (real)(ju / (double)(lt->size1 - 1) - 0.5)) : grey3(R(0.0));
        jb = lt->size2 > 1 ? v3_scale(a2, (real)(jv / (double)(lt->size2 - 1) - 0.5)) : grey3(R(0.0));
    }
    vec3 l;
    real dist;
    light_ray(lt, p, v3_add(ja, jb), &l, &dist);
    return v3_mul(color, light_transmittance(c, p, l, dist, blocker));
}

/* The samples of an area light's grid, computed once each (the grid is
 * at most 65536 points: sampled lazily into `grid`, NULL entries first). */
typedef struct {
    vec3 *color;
    unsigned char *done;
} area_grid;

static vec3 area_corner(const shade_ctx *c, const csg_flat_light *lt, vec3 p, vec3 a1, vec3 a2,
                        int u, int v, vec3 color, area_grid *g, csg_i32 *blocker, ray_tally *tally)
{
    size_t k = (size_t)u * (size_t)lt->size2 + (size_t)v;
    if (!g->done[k]) {
        tally->rays->shadow++;
        g->color[k] = area_sample(c, lt, p, a1, a2, u, v, color, blocker, tally);
        g->done[k] = 1;
    }
    return g->color[k];
}

static real colour_distance(vec3 a, vec3 b)
{
    return r_fabs(a.x - b.x) + r_fabs(a.y - b.y) + r_fabs(a.z - b.z);
}

/* POV-Ray's TraceAreaLightSubsetShadowRay: the four corners of the
 * region (u1, v1) - (u2, v2), subdivided while its level is below
 * `adaptive` or its corners differ by more than 0.1, averaged. */
static vec3 area_region(const shade_ctx *c, const csg_flat_light *lt, vec3 p, vec3 a1, vec3 a2,
                        int u1, int v1, int u2, int v2, int level, vec3 color, area_grid *g,
                        csg_i32 *blocker, ray_tally *tally)
{
    vec3 s[4];
    const int us[4] = {u1, u2, u1, u2}, vs[4] = {v1, v1, v2, v2};
    for (int i = 0; i < 4; i++)
        s[i] = area_corner(c, lt, p, a1, a2, us[i], vs[i], color, g, blocker, tally);
    if ((u2 - u1 > 1 || v2 - v1 > 1) &&
        (level < lt->adaptive || colour_distance(s[0], s[1]) > R(0.1) ||
         colour_distance(s[1], s[3]) > R(0.1) || colour_distance(s[3], s[2]) > R(0.1) ||
         colour_distance(s[2], s[0]) > R(0.1))) {
        int um = (u1 + u2) / 2, vm = (v1 + v2) / 2; /* floor; ceil is +1 when odd */
        int uc = (u1 + u2 + 1) / 2, vc = (v1 + v2 + 1) / 2;
        s[0] = area_region(c, lt, p, a1, a2, u1, v1, um, vm, level + 1, color, g, blocker, tally);
        s[1] = area_region(c, lt, p, a1, a2, uc, v1, u2, vm, level + 1, color, g, blocker, tally);
        s[2] = area_region(c, lt, p, a1, a2, u1, vc, um, v2, level + 1, color, g, blocker, tally);
        s[3] = area_region(c, lt, p, a1, a2, uc, vc, u2, v2, level + 1, color, g, blocker, tally);
    }
    return v3_scale(v3_add(v3_add(s[0], s[1]), v3_add(s[2], s[3])), R(0.25));
}

/* An area light's shadows (POV-Ray's TraceAreaLightShadowRay, `orient`
 * turning its axes to face p; `jitter` moves each point of the grid
 * within its cell by the sample's random stream: pixel_random). */
static vec3 area_light(const shade_ctx *c, const csg_flat_light *lt, vec3 p, vec3 color,
                       csg_i32 *blocker, ray_tally *tally)
{
    vec3 a1 = v3_load(lt->axis1), a2 = v3_load(lt->axis2);
    if (lt->orient) {
        vec3 l;
        real dist;
        light_ray(lt, p, grey3(R(0.0)), &l, &dist);
        real len1 = v3_length(a1);
        vec3 t = r_fabs(r_fabs(l.z) - R(1.0)) < R(0.01) ? v3(R(0.0), R(1.0), R(0.0))
                                                        : v3(R(0.0), R(0.0), R(1.0));
        a1 = v3_normalize(v3_cross(l, t));
        a2 = v3_normalize(v3_cross(l, a1));
        a1 = v3_scale(a1, len1);
        a2 = v3_scale(a2, len1);
    }
    size_t n = (size_t)lt->size1 * (size_t)lt->size2;
    vec3 small_color[64];
    unsigned char small_done[64] = {0};
    area_grid g = {small_color, small_done};
    if (n > 64) {
        g.color = malloc(n * sizeof *g.color);
        g.done = calloc(n, 1);
        if (!g.color || !g.done) { /* out of memory: the centre's shadow alone */
            free(g.color);
            free(g.done);
            vec3 l;
            real dist;
            light_ray(lt, p, grey3(R(0.0)), &l, &dist);
            return v3_mul(color, light_transmittance(c, p, l, dist, blocker));
        }
    }
    vec3 out = area_region(c, lt, p, a1, a2, 0, 0, lt->size1 - 1, lt->size2 - 1, 0, color, &g,
                           blocker, tally);
    if (n > 64) {
        free(g.color);
        free(g.done);
    }
    return out;
}

/* The light of light i reaching the point along l, `dist` away (already
 * attenuated in `light`): through every surface between (an area light:
 * its grid's average), or black. */
static vec3 light_at(const shade_ctx *c, hit_info *hi, csg_i32 i, vec3 l, real dist, vec3 light,
                     ray_tally *tally)
{
    const csg_flat_light *lt = &c->lights[i];
    if (lt->shadowless)
        return light;
    if (i < SHADE_LIGHT_CACHE && (hi->light_done & (1u << i)))
        return hi->light[i];
    csg_i32 *slot = shadow_slot(c, tally, i, hi->level);
    if (lt->area) {
        light = area_light(c, lt, hi->above, light, slot, tally);
    } else if (hi->level == 1 && i < CSG_SHADOW_LIGHTS && ((tally->shadow_known >> i) & 1u)) {
        /* the record's answer (shadow.h): what light_transmittance finds */
        tally->rays->shadow_answered++;
        vec3 pass = grey3(((tally->shadow_lit >> i) & 1u) ? R(1.0) : R(0.0));
        light = v3_mul(light, pass);
    } else {
        tally->rays->shadow++;
        light = v3_mul(light, light_transmittance(c, hi->above, l, dist, slot));
    }
    if (lt->media_attenuation && c->fog_count > 0 && hi->solid == 0) {
        csg_ray sr;
        sr.o = hi->above;
        sr.d = l;
        light = apply_fog(c, sr, (double)dist, light, true);
    }
    if (i < SHADE_LIGHT_CACHE) {
        hi->light[i] = light;
        hi->light_done |= 1u << i;
    }
    return light;
}

/* POV-Ray's ComputeIridColour: what a thin film (irid) makes of one
 * light's diffuse and highlights, colour by colour 1 + irid cos(phase /
 * wavelength), the phase 2 pi thickness (|cos| to the light + |cos| to the
 * eye); the thickness varies by turbulence (five octaves of the scene's
 * noise at the hit point p, into 1 +- turbulence). */
static vec3 irid_factor(const shade_ctx *c, const csg_material *m, vec3 l, vec3 eye, vec3 nl,
                        vec3 p)
{
    double thickness = (double)m->irid_thickness;
    if (m->irid_turbulence != R(0.0)) {
        noise_turb turb = {5, 0.5, 2.0};
        double q[3] = {(double)p.x, (double)p.y, (double)p.z};
        double noise = 2.0 * noise_turbulence(q, &turb, c->noise_gen) - 1.0;
        thickness *= 1.0 + noise * (double)m->irid_turbulence;
    }
    double n[3] = {(double)nl.x, (double)nl.y, (double)nl.z};
    double cos_light = fabs(n[0] * (double)l.x + n[1] * (double)l.y + n[2] * (double)l.z);
    double cos_eye = fabs(n[0] * (double)eye.x + n[1] * (double)eye.y + n[2] * (double)eye.z);
    double interference = 2.0 * M_PI * thickness * (cos_light + cos_eye);
    double irid = (double)m->irid, f[3];
    for (int i = 0; i < 3; i++)
        f[i] = 1.0 + irid * cos(interference / c->irid_wavelength[i]);
    return v3((real)f[0], (real)f[1], (real)f[2]);
}

/* One layer's own light (POV-Ray's ambient, diffuse and highlights of
 * the layer with pigment pig, normal nl; phong_dir: the eye reflected
 * about nl): *surface, dimmed by the opacity by the caller, and
 * *highlight, which is not (crand's grain with it). */
static void layer_light(const shade_ctx *c, hit_info *hi, const csg_material *m, vec3 pig,
                        vec3 nl, vec3 phong_dir, ray_tally *tally, vec3 *surface_out,
                        vec3 *highlight_out)
{
    vec3 surface = v3_mul(v3_mul(v3_load(m->ambient), pig), c->ambient_light);
    vec3 highlight = v3(R(0.0), R(0.0), R(0.0));
    for (csg_i32 i = 0; i < c->hdr->light_count; i++) {
        const csg_flat_light *lt = &c->lights[i];
        vec3 l, light = v3_load(lt->color);
        real dist;
        if (!csg_light_line(lt, hi->above, &l, &dist)) /* the line the device uses too */
            continue;
        if (!light_plain(lt)) { /* POV-Ray: no light at all (outside a spotlight's cone) skips it */
            light = v3_scale(light, (real)light_attenuation(lt, hi->above, l, dist));
            if (r_fabs(light.x) < R(1e-10) && r_fabs(light.y) < R(1e-10) &&
                r_fabs(light.z) < R(1e-10))
                continue;
        }
        real cosl = v3_dot(nl, l);
        if (cosl <= R(0.0))
            continue;
        light = light_at(c, hi, i, l, dist, light, tally);
        if (!lt->shadowless && max3(light) <= R(0.0))
            continue;
        /* irid scales every term of this light (1 without irid: the same bits) */
        vec3 irid = m->irid > R(0.0) ? irid_factor(c, m, l, hi->r.d, nl, hi->p) : grey3(R(1.0));
        real lambert = m->brilliance == R(1.0) ? cosl : power(cosl, m->brilliance);
        surface = v3_add(surface, v3_mul(v3_scale(v3_mul(pig, light), m->diffuse * lambert), irid));
        if (m->crand > R(0.0) && m->diffuse > R(0.0)) /* POV-Ray's ComputeDiffuseColour:
            the grain leaves the diffuse intensity after its opacity: not dimmed */
            highlight = v3_sub(highlight, v3_mul(v3_scale(v3_mul(pig, light),
                                                          (real)pixel_random(tally) * m->crand),
                                                 irid));
        if (lt->shadowless) /* POV-Ray gives a fill light (shadowless) no
            highlights (ComputeOneLightRay: Light_Type != FILL_LIGHT_SOURCE) */
            continue;
        vec3 hl = v3_mul(highlight_color(m, pig, cosl, light), irid);
        if (m->phong > R(0.0)) {
            real cr = v3_dot(phong_dir, l);
            if (cr > R(0.0))
                highlight = v3_add(highlight, v3_scale(hl, m->phong * power(cr, m->phong_size)));
        }
        if (m->specular > R(0.0) && m->roughness > R(0.0)) {
            vec3 half = v3_normalize(v3_sub(l, hi->r.d));
            real ch = v3_dot(nl, half);
            if (ch > R(0.0))
                highlight = v3_add(highlight,
                                   v3_scale(hl, m->specular * power(ch, R(1.0) / m->roughness)));
        }
    }
    *surface_out = surface;
    *highlight_out = highlight;
}

/* The layer's normal: the facing normal perturbed by its normal { }
 * (POV-Ray's Perturb_Normal), through the transforms of the
 * texture_maps holding it (Warp_Normal, UnWarp_Normal). */
static vec3 layer_normal(const shade_ctx *c, const hit_info *hi, const csg_material *layer,
                         const double w[3], const csg_material *const *parents, int np)
{
    double n[3] = {(double)hi->nf.x, (double)hi->nf.y, (double)hi->nf.z};
    for (int i = 0; i < np; i++)
        PIGMENT_WARP_NORMAL(parents[i], n, true);
    PIGMENT_NORMAL(c->mats, c->maps, &c->mats[layer->normal - 1], w, n);
    for (int i = np - 1; i >= 0; i--)
        PIGMENT_UNWARP_NORMAL(parents[i], n, true);
    return v3((real)n[0], (real)n[1], (real)n[2]);
}

/* The mirror direction of the ray about nl; a perturbed normal that sends
 * it below the surface is corrected with the surface's own (POV-Ray's
 * ComputeReflection). */
static vec3 reflect_dir(const hit_info *hi, vec3 nl, bool perturbed)
{
    vec3 d = v3_sub(hi->r.d, v3_scale(nl, R(2.0) * v3_dot(hi->r.d, nl)));
    if (!perturbed)
        return d;
    real n = v3_dot(d, hi->nf);
    if (n < R(0.0)) {
        if (v3_dot(d, nl) < R(0.0))
            d = v3_sub(hi->r.d, v3_scale(hi->nf, R(2.0) * v3_dot(hi->r.d, hi->nf)));
        else
            d = v3_add(d, v3_scale(hi->nf, R(-2.0) * n));
    }
    return d;
}

static vec3 trace_ray(const shade_ctx *c, csg_ray r, int level, real weight, int solid,
                      ray_tally *tally);

/* Two normals alike within POV-Ray's EPSILON in every component. */
static bool same_normal(vec3 a, vec3 b)
{
    return r_fabs(a.x - b.x) <= R(1e-10) && r_fabs(a.y - b.y) <= R(1e-10) &&
           r_fabs(a.z - b.z) <= R(1e-10);
}

/* POV-Ray's ComputeLightedTexture: the layers of texture m, from its top
 * one, at w (a surface point, or a point of the texture_map holding m):
 * each adds its own light through the filter of the layers above it,
 * while enough of them lets light through; then the refracted ray through
 * all of them (or, on total internal reflection, the ray reflected in its
 * stead), then each layer's reflection. */
static vec3 lighted_texture(const shade_ctx *c, hit_info *hi, const csg_material *m,
                            const double w[3], double err, const csg_material *const *parents,
                            int np, real weight, ray_tally *tally)
{
    struct {
        const csg_material *m;
        vec3 normal;  /* the layer's normal (nl)                     */
        vec3 refl_dir;
        real weight;
        vec3 refl;    /* what the layer reflects                     */
        real refl_wt; /* what the ray's weight is scaled by for it   */
    } layers[SHADE_MAX_DEPTH];
    int count = 0;
    vec3 color = v3(R(0.0), R(0.0), R(0.0));
    vec3 fil = grey3(R(1.0)); /* what the layers so far let through */
    vec3 top_normal = hi->nf;
    real trans = R(1.0);
    for (const csg_material *layer = m; layer && count < SHADE_MAX_DEPTH;
         layer = layer->under > 0 ? &c->mats[layer->under - 1] : NULL) {
        if (count > 0 && !(trans > c->bailout))
            break;
        bool perturbed = layer->normal > 0;
        vec3 nl = perturbed ? layer_normal(c, hi, layer, w, parents, np) : hi->nf;
        if (count == 0)
            top_normal = nl;
        pigment_color pc = PIGMENT_EVAL(c->mats, layer, c->maps, w, err);
        vec3 pig = pc.color;
        /* POV-Ray 3.7 dims a transparent surface by 1 - filter - transmit;
         * before 3.7 by 1 - (filter * the pigment's largest channel +
         * transmit), kept for old scenes (trace.cpp, ComputeLightedTexture) */
        real opacity = c->sky_v37 ? r_fmax(R(0.0), R(1.0) - pc.filter - pc.transmit)
                                  : R(1.0) - (pc.filter * max3(pig) + pc.transmit);
        vec3 refl_dir = reflect_dir(hi, nl, perturbed);
        vec3 surface, highlight;
        /* phong reflects the eye about the layer's normal as it is (POV-Ray's
         * ComputePhongColour): not the reflected ray's direction, which a
         * perturbed normal may have turned back above the surface */
        layer_light(c, hi, layer, pig, nl, perturbed ? reflect_dir(hi, nl, false) : refl_dir,
                    tally, &surface, &highlight);
        vec3 own = v3_add(v3_scale(surface, opacity), highlight);
        vec3 through = v3_add(v3_scale(pig, pc.filter), grey3(pc.transmit));
        vec3 refl = v3_load(layer->reflection);
        real refl_wt = max3(refl);
        if (layer->reflection_variable) {
            real n = hi->entering ? m->ior : R(1.0) / m->ior; /* (the relative index) */
            refl = variable_reflection(layer, pig, -v3_dot(hi->r.d, nl), n, &refl_wt);
            if (layer->conserve_energy) /* (POV-Ray: 1 - reflection, at most 1) */
                through = v3_mul(through, v3(r_fmin(R(1.0) - refl.x, R(1.0)),
                                             r_fmin(R(1.0) - refl.y, R(1.0)),
                                             r_fmin(R(1.0) - refl.z, R(1.0))));
        }
        if (count == 0) {
            color = own;
            fil = through;
        } else {
            color = v3_add(color, v3_mul(own, fil));
            fil = v3_mul(fil, through);
        }
        layers[count].m = layer;
        layers[count].normal = nl;
        layers[count].refl_dir = refl_dir;
        layers[count].weight = count == 0 ? weight : weight * trans;
        layers[count].refl = refl;
        layers[count].refl_wt = refl_wt;
        count++;
        trans = r_fmin(R(1.0), r_fabs(R(0.297) * fil.x + R(0.589) * fil.y + R(0.114) * fil.z));
    }
    if (hi->level >= c->hdr->max_depth)
        return color;

    vec3 trans_w = fil;
    bool tir = false;
    if (max3(trans_w) > R(0.0)) {
        real eta = hi->entering ? R(1.0) / m->ior : m->ior;
        real cosi = -v3_dot(hi->r.d, top_normal);
        real k = R(1.0) - eta * eta * (R(1.0) - cosi * cosi);
        bool fading = !hi->entering && r_fabs(m->fade_distance) > R(1e-10);
        if (k < R(0.0)) { /* total internal reflection, as POV-Ray's
            TraceRefractionRay: the ray reflected about the top normal, its
            light not filtered, only faded (attCol), and no reflection about
            that normal besides (below) */
            tir = true;
            real tw = weight * max3(trans_w);
            if (tw >= c->bailout && ray_spend(tally)) {
                csg_ray s;
                s.o = hi->above;
                s.d = v3_normalize(layers[0].refl_dir);
                tally->rays->reflected++;
                vec3 seen = trace_ray(c, s, hi->level + 1, tw, hi->solid, tally);
                color = v3_add(color, fading ? v3_mul(seen, fade(m, hi->depth)) : seen);
            }
        } else {
            real tw = weight * max3(trans_w);
            if (tw >= c->bailout && ray_spend(tally)) {
                csg_ray t;
                /* the same ior on both sides: POV-Ray's continued ray, its
                 * direction as it was and its trace level not raised (a
                 * chain of such surfaces costs one level, not one each) */
                bool continued = r_fabs(eta - R(1.0)) < R(1e-10) &&
                                 tally->continued < SHADE_MAX_CONTINUED;
                t.d = continued ? hi->r.d
                                : v3_normalize(v3_add(v3_scale(hi->r.d, eta),
                                                      v3_scale(top_normal, eta * cosi - r_sqrt(k))));
                t.o = offset_point(hi->p, v3_neg(hi->ngf), hi->mag);
                tally->rays->refracted++;
                /* the ray enters or leaves the object: one non-hollow
                 * object more or less around it (no fog inside those) */
                int solid = hi->entering ? hi->solid + hi->prim_solid
                                         : hi->solid - (hi->solid > 0 ? hi->prim_solid : 0);
                tally->continued += continued;
                vec3 seen = trace_ray(c, t, continued ? hi->level : hi->level + 1, tw, solid, tally);
                tally->continued -= continued;
                if (fading) /* the light crossed the inside: POV-Ray's attCol */
                    seen = v3_mul(seen, fade(m, hi->depth));
                color = v3_add(color, v3_mul(trans_w, seen));
            }
        }
    }
    for (int i = 0; i < count; i++) {
        if (tir && same_normal(layers[i].normal, top_normal))
            continue; /* (POV-Ray: within EPSILON, each component) */
        vec3 lw = layers[i].refl;
        /* (the weight: the constant reflection's own largest channel, as
         * ever; POV-Ray's rule for a variable one) */
        real rw = layers[i].weight *
                  (layers[i].m->reflection_variable ? layers[i].refl_wt : max3(lw));
        if (max3(lw) > R(0.0) && rw >= c->bailout && ray_spend(tally)) {
            csg_ray s;
            s.o = hi->above;
            s.d = v3_normalize(layers[i].refl_dir);
            tally->rays->reflected++;
            vec3 seen = trace_ray(c, s, hi->level + 1, rw, hi->solid, tally);
            if (layers[i].m->reflection_variable)
                seen = reflection_power(seen, layers[i].m->reflection_exponent);
            color = v3_add(color, v3_mul(lw, seen));
        }
    }
    return color;
}

static vec3 texture_colour(const shade_ctx *c, hit_info *hi, const csg_material *m,
                           const double w[3], double err, const csg_material **parents, int np,
                           real weight, ray_tally *tally);

/* POV-Ray's ComputeAverageTextureColours: an average texture's entries,
 * each lit at the map's point q and weighted by its map value, over the
 * sum of the values (all 0: black, where POV-Ray divides by zero). */
static vec3 average_texture(const shade_ctx *c, hit_info *hi, const csg_material *m,
                            const double q[3], double q_err, const csg_material **parents,
                            int np, real weight, ray_tally *tally)
{
    vec3 sum = grey3(R(0.0));
    double total = 0.0;
    for (int i = 0; i < m->map_count; i++) {
        real value = c->maps[m->map_first + i].value;
        vec3 one = texture_colour(c, hi, &c->mats[m->sub_first + i], q, q_err, parents, np,
                                  weight, tally);
        sum = v3_add(sum, v3_scale(one, value));
        total += (double)value;
    }
    return total != 0.0 ? v3_scale(sum, (real)(1.0 / total)) : grey3(R(0.0));
}

/* POV-Ray's ComputeOneTextureColour: a texture_map blends the colours of
 * its entries around its pattern's value (each a texture of its own,
 * evaluated at the point of the map's pattern); a plain texture is lit. */
static vec3 texture_colour(const shade_ctx *c, hit_info *hi, const csg_material *m,
                           const double w[3], double err, const csg_material **parents, int np,
                           real weight, ray_tally *tally)
{
    if (m->tmap && np < SHADE_MAX_DEPTH) {
        double q[3], q_err;
        int prev, cur;
        double f = PIGMENT_TMAP(c->mats, m, c->maps, w, err, q, &q_err, &prev, &cur);
        parents[np] = m;
        if (m->pattern == CSG_PATTERN_AVERAGE)
            return average_texture(c, hi, m, q, q_err, parents, np + 1, weight, tally);
        vec3 a = texture_colour(c, hi, &c->mats[m->sub_first + cur], q, q_err, parents, np + 1,
                                weight, tally);
        if (prev == cur)
            return a;
        vec3 b = texture_colour(c, hi, &c->mats[m->sub_first + prev], q, q_err, parents, np + 1,
                                weight, tally);
        return v3_add(v3_scale(a, (real)f), v3_scale(b, (real)(1.0 - f)));
    }
    return lighted_texture(c, hi, m, w, err, (const csg_material *const *)parents, np, weight,
                           tally);
}

static vec3 shade_hit(const shade_ctx *c, csg_ray r, csg_hit h, int level, real weight, int solid,
                      ray_tally *tally)
{
    CSG_PAGE_PRIM(c->view, CSG_SURF_PRIM(h.surf)); /* (a record's hit: named here) */
    const csg_prim *prim = &c->view.prims[CSG_SURF_PRIM(h.surf)];
    const csg_material *m = &c->mats[prim->material];
    hit_info hi;
    hi.r = r;
    hi.level = level;
    hi.solid = solid;
    hi.prim_solid = !(prim->flags & CSG_PF_HOLLOW) && !CSG_PRIM_IS_SURFACE(prim->kind);
    hi.depth = h.t;
    hi.light_done = 0;
    /* the point, its normals and where secondary rays start: the code the
     * device's shadow kernel runs (shadow.h); the shading normal faces the
     * ray by its own direction, as POV-Ray turns it (ComputeTextureColour
     * flips a smooth triangle's interpolated normal alone) */
    csg_hit_frame f = csg_hit_frame_of(c->view, r, h.t, h.surf);
    m = seen_material(c, m, f.n, r.d);
    hi.p = f.p;
    hi.entering = f.entering;
    hi.nf = v3_dot(f.n, r.d) > R(0.0) ? v3_neg(f.n) : f.n; /* faces the incoming ray */
    hi.ngf = f.ngf;
    hi.mag = f.mag;
    hi.above = f.above;
    PIGMENT_SURFACE_POINT(c->view.prims, h.surf, hi.p, hi.w);
    hi.err = (double)(OFFSET_ERR_ULPS * OFFSET_UNIT_ROUNDOFF * hi.mag);
    const csg_material *parents[SHADE_MAX_DEPTH];
    return texture_colour(c, &hi, m, hi.w, hi.err, parents, 0, weight, tally);
}

/* The fog between the camera and what a primary ray sees (t < 0: it hit
 * nothing), unless the camera is inside a non-hollow object. */
static vec3 primary_fog(const shade_ctx *c, csg_ray r, double t, vec3 col)
{
    if (c->fog_count == 0 || c->camera_solid > 0)
        return col;
    return apply_fog(c, r, t < 0.0 ? FOG_BOUND_HUGE : t, col, false);
}

static vec3 trace_ray(const shade_ctx *c, csg_ray r, int level, real weight, int solid,
                      ray_tally *tally)
{
    csg_hit h = csg_trace_nearest(c->view, r, R(0.0), CSG_R_INF);
    vec3 col = h.surf == CSG_SURF_NONE ? sky_color(c, r.d)
                                       : shade_hit(c, r, h, level, weight, solid, tally);
    if (c->fog_count > 0 && solid == 0)
        col = apply_fog(c, r, h.surf == CSG_SURF_NONE ? FOG_BOUND_HUGE : (double)h.t, col, false);
    return col;
}

/* ---- the engine entry points ----------------------------------------------------- */

void ENGINE_SYM(engine_trace_primary)(const void *blob, tile_rect rect, void *t_out,
                                      uint32_t *surf_out, ray_counts *rays)
{
    shade_ctx c = ctx_of(blob);
    real *t = t_out;
    int spp = c.hdr->spp;
    frustum_roots fr; /* the roots the rectangle's rays may hit (frustum.h) */
    frustum_prefetch_pages(c.view, c.cam, c.hdr->width, c.hdr->height, rect);
    frustum_roots_of(c.view, c.cam, c.hdr->width, c.hdr->height, rect, &fr);
    if (frustum_all_miss(c.view, &fr)) {
        size_t n = (size_t)rect.width * (size_t)rect.height * (size_t)spp;
        for (size_t i = 0; i < n; i++) {
            t[i] = CSG_R_INF;
            surf_out[i] = CSG_SURF_NONE;
        }
        rays->primary += n;
        return;
    }
    for (int y = 0; y < rect.height; y++) {
        for (int x = 0; x < rect.width; x++) {
            for (int s = 0; s < spp; s++) {
                csg_ray r = csg_sample_ray(c.cam, c.hdr->width, c.hdr->height, rect.x + x,
                                           rect.y + y, spp, s);
                csg_hit h = fr.culled ? frustum_trace(c.view, &fr, r)
                                      : csg_trace_nearest(c.view, r, R(0.0), CSG_R_INF);
                size_t i = ((size_t)y * (size_t)rect.width + (size_t)x) * (size_t)spp + (size_t)s;
                t[i] = h.t;
                surf_out[i] = h.surf;
            }
        }
    }
    rays->primary += (uint64_t)rect.width * (uint64_t)rect.height * (uint64_t)spp;
}

/* A colour that reaches a pixel is finite: a NaN or infinity produced by a
 * degenerate configuration becomes black rather than poisoning the image. */
/* A pixel value as the image stores it: NaN and infinities 0, and a
 * double beyond float's range saturated at FLT_MAX (a colour of 1e38 under
 * a bright light must not become an infinite pixel). */
static float finite_or_zero(real v)
{
    if (!isfinite(v))
        return 0.0f;
    if (v > (real)FLT_MAX)
        return FLT_MAX;
    if (v < (real)-FLT_MAX)
        return -FLT_MAX;
    return (float)v;
}

/* A pixel's colour as the image keeps it: finite, then through the
 * scene's output gamma (comm/pixels.h: POV-Ray's bytes in an 8-bit file). */
static void store_rgb(const shade_ctx *c, float *out, vec3 col)
{
    out[0] = finite_or_zero(col.x);
    out[1] = finite_or_zero(col.y);
    out[2] = finite_or_zero(col.z);
    if (c->output != CSG_OUTPUT_SRGB)
        for (int k = 0; k < 3; k++)
            out[k] = pixels_scene_linear(out[k], c->output, c->output_gamma);
}

bool ENGINE_SYM(engine_rect_misses)(const void *blob, tile_rect rect, int32_t *met)
{
    shade_ctx c = ctx_of(blob);
    return frustum_rect_misses(c.view, c.cam, c.hdr->width, c.hdr->height, rect,
                               c.hdr->root_count, met);
}

int32_t ENGINE_SYM(engine_rect_candidates)(const void *blob, tile_rect rect,
                                           const int32_t *from, int32_t from_n, int32_t *roots,
                                           int32_t cap)
{
    const csg_blob_header *h = blob; /* (no shading: any blob the pass takes) */
    csg_view v = csg_blob_view(blob);
    const csg_camera *cam = csg_blob_camera(blob);
    if (from)
        return frustum_candidates_in(v, cam, h->width, h->height, rect, from, from_n, roots,
                                     cap);
    return frustum_candidates(v, cam, h->width, h->height, rect, roots, cap);
}

void ENGINE_SYM(engine_miss_rgb)(const void *blob, float rgb[3])
{
    shade_ctx c = ctx_of(blob);
    store_rgb(&c, rgb, c.background);
}

/* The cells of space a band's shadow walks started in (prefetch_shadow_pages):
 * a hit in a cell already walked from shares that walk's pages but for a
 * sliver, which faults if a ray needs it.  A cell's edge: an eighth of a
 * page's, were the scene's box cut into equal cubes (tetra9 at 1/32,
 * 768x768, tile 64: 40 faults of the 811 without the walks, for +4.7 %
 * of the tile phase's instructions; every hit walked: none, +11.4 %). */
enum { SHADOW_CELLS = 2048 };
#define SHADOW_CELL_OF_PAGE 0.125
typedef struct {
    double edge;               /* a cell's edge                          */
    uint64_t key[SHADOW_CELLS]; /* a cell's coordinates, hashed; 0: free */
    int used;
} shadow_cells;

/* Is the cell of p new (then marked walked)?  Full: every cell is new. */
static bool shadow_cell_new(shadow_cells *sc, vec3 p)
{
    double q[3] = {floor((double)p.x / sc->edge), floor((double)p.y / sc->edge),
                   floor((double)p.z / sc->edge)};
    if (!(fabs(q[0]) + fabs(q[1]) + fabs(q[2]) < 1e18) || sc->used >= SHADOW_CELLS / 2)
        return true; /* (not finite, or past an integer's range) */
    uint64_t key = 1469598103934665603ull;
    for (int a = 0; a < 3; a++)
        key = (key ^ (uint64_t)(int64_t)q[a]) * 1099511628211ull;
    key |= 1; /* (0 marks a free slot) */
    for (uint32_t h = (uint32_t)(key >> 40) & (SHADOW_CELLS - 1);; h = (h + 1) & (SHADOW_CELLS - 1)) {
        if (sc->key[h] == key)
            return false;
        if (sc->key[h] == 0) {
            sc->key[h] = key;
            sc->used++;
            return true;
        }
    }
}

/* A shadow segment's test of a BVH node: its box met on the segment,
 * a little wider than the shadow ray's own walk tests it. */
typedef struct {
    csg_box_ray br;
    real tmin, tmax;
} shadow_segment;

static bool segment_meets_node(const void *arg, const csg_bvh_node *n)
{
    const shadow_segment *s = arg;
    real t_enter;
    return csg_node_hit(n, &s->br, s->tmin, s->tmax, &t_enter);
}

/* The segment from p to the light `dist` away along unit l walked through
 * the BVH above the pages, the tops of the pages whose boxes it meets
 * onto t. */
static void segment_page_tops(const shade_ctx *c, vec3 p, vec3 l, real dist, page_tops *t)
{
    csg_ray sr;
    sr.o = p;
    sr.d = l;
    shadow_segment s = {csg_box_ray_of(sr), -dist * R(1e-3), dist * R(1.001)};
    page_tops_walk(c->view, segment_meets_node, &s, t);
}

/* Paged (workers/pager.h): the pages the shadow rays of rect's primary
 * hits may enter on their way to each point light, fetched in one request
 * before the shading needs them (the primary rays' pages came with the
 * item's prefetch: frustum.h, tile_run.c).  From one hit of each cell
 * (shadow_cells), the segment to each light is walked through the BVH
 * above the pages, which is resident, down to the tops of the pages whose
 * boxes it meets; not for a light whose answer the record has (known:
 * the device traced that shadow ray).  Parallel and area lights are left
 * to the faults, as are reflected and refracted rays. */
static void prefetch_shadow_pages(const shade_ctx *c, tile_rect rect, const real *t,
                                  const uint32_t *surf, const uint32_t *known)
{
    csg_pager *pager = c->view.pager;
    if (!pager || !pager->prefetch_shadows || c->view.bvh_count == 0)
        return;
    int spp = c->hdr->spp;
    static _Thread_local shadow_cells sc; /* (16 KiB: not on the stack) */
    memset(&sc, 0, sizeof sc);
    const real *b0 = c->view.bvh[0].box, *b1 = c->view.bvh[1].box;
    double diag = 0;
    for (int a = 0; a < 3; a++) {
        double e = fmax((double)b0[a + 3], (double)b1[a + 3]) - fmin((double)b0[a], (double)b1[a]);
        diag += e * e;
    }
    sc.edge = SHADOW_CELL_OF_PAGE * sqrt(diag) / cbrt((double)pager->plan.page_count);
    if (!(sc.edge > 0.0) || !isfinite(sc.edge))
        sc.used = SHADOW_CELLS; /* (every hit walked) */
    page_tops tops;
    page_tops_init(&tops, pager);
    for (int y = 0; y < rect.height; y++)
        for (int x = 0; x < rect.width; x++)
            for (int s = 0; s < spp; s++) {
                size_t k = ((size_t)y * (size_t)rect.width + (size_t)x) * (size_t)spp + (size_t)s;
                if (surf[k] == CSG_SURF_NONE)
                    continue;
                csg_ray r = csg_sample_ray(c->cam, c->hdr->width, c->hdr->height, rect.x + x,
                                           rect.y + y, spp, s);
                vec3 p = v3_add(r.o, v3_scale(r.d, t[k]));
                if (!shadow_cell_new(&sc, p))
                    continue;
                for (int i = 0; i < c->hdr->light_count; i++) {
                    const csg_flat_light *lt = &c->lights[i];
                    bool answered = known && i < CSG_SHADOW_LIGHTS && ((known[k] >> i) & 1u);
                    if (lt->shadowless || lt->parallel || lt->area || answered)
                        continue;
                    vec3 to = v3_sub(v3_load(lt->position), p);
                    real dist = r_sqrt(v3_dot(to, to));
                    if (dist > R(0.0))
                        segment_page_tops(c, p, v3_scale(to, R(1.0) / dist), dist, &tops);
                }
            }
    page_tops_send(&tops);
}

void ENGINE_SYM(engine_shade_answered)(const void *blob, tile_rect rect, const void *t_in,
                                       const uint32_t *surf, const uint32_t *known,
                                       const uint32_t *lit, float *rgb_out, ray_counts *rays)
{
    shade_ctx c = ctx_of(blob);
    const real *t = t_in;
    int spp = c.hdr->spp;
    prefetch_shadow_pages(&c, rect, t, surf, known);
    csg_i32 blockers[SHADOW_CACHE_SLOTS];
    for (int k = 0; k < SHADOW_CACHE_SLOTS; k++)
        blockers[k] = -1;
    for (int y = 0; y < rect.height; y++) {
        for (int x = 0; x < rect.width; x++) {
            int i = y * rect.width + x;
            vec3 col = v3(R(0.0), R(0.0), R(0.0));
            int hits = 0;
            ray_tally tally = {rays, c.max_rays, false, blockers, 0, 0, 0u, 0u, 0};
            for (int s = 0; s < spp; s++) {
                tally.rng_key = sample_stream(rect.x + x, rect.y + y, s);
                tally.rng_drawn = 0;
                size_t k = (size_t)i * (size_t)spp + (size_t)s;
                tally.shadow_known = known ? known[k] : 0u;
                tally.shadow_lit = known ? lit[k] : 0u;
                vec3 one;
                if (surf[k] == CSG_SURF_NONE && c.sky_count == 0 && c.fog_count == 0) {
                    one = c.background; /* sky_color's answer: no ray needed */
                } else {
                    csg_ray r = csg_sample_ray(c.cam, c.hdr->width, c.hdr->height, rect.x + x,
                                               rect.y + y, spp, s);
                    if (surf[k] == CSG_SURF_NONE) {
                        one = sky_color(&c, r.d);
                    } else {
                        csg_hit h;
                        h.t = t[k];
                        h.surf = surf[k];
                        one = shade_hit(&c, r, h, 1, R(1.0) / (real)spp, c.camera_solid, &tally);
                        hits++;
                    }
                    one = primary_fog(&c, r, surf[k] == CSG_SURF_NONE ? -1.0 : (double)t[k], one);
                }
                col = spp == 1 ? one : v3_add(col, one);
            }
            /* A pixel no sample hit is exactly the background, as the
             * master fills the degenerate tiles of the hetero mode (an
             * average of spp equal values need not round back to it);
             * with a sky_sphere no tile is degenerate (render.c). */
            if (hits == 0 && c.sky_count == 0 && c.fog_count == 0)
                col = c.background;
            else if (spp > 1)
                col = v3_scale(col, R(1.0) / (real)spp);
            store_rgb(&c, rgb_out + 3 * i, col);
            rays->over_budget += tally.refused;
        }
    }
}

void ENGINE_SYM(engine_shade)(const void *blob, tile_rect rect, const void *t_in,
                              const uint32_t *surf, float *rgb_out, ray_counts *rays)
{
    ENGINE_SYM(engine_shade_answered)(blob, rect, t_in, surf, NULL, NULL, rgb_out, rays);
}
