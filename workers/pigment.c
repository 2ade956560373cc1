/*
 * pigment.c — POV-Ray 3.7's pigment patterns at a hit point (see
 * pigment.h), in double whatever the build's `real`.
 *
 * Algorithm, as POV-Ray's Compute_Pigment and Evaluate_TPat do it:
 *   1. the hit point is put exactly on its surface when that surface is
 *      flat (a plane, a box face, a cone cap): moved along the face's
 *      normal by its signed distance, so a pattern boundary lying on the
 *      face (a checker on plane { y, 0 }) is not crossed by the rounding
 *      of the point (POV-Ray's own 1e-10 bias does the rest);
 *   2. world -> pattern space by the material's matrix (the inverse of the
 *      pigment's transforms and those of its object after it);
 *   3. classic turbulence (POV-Ray's Warp_EPoint): for every pattern but
 *      wood and marble, which use it themselves, the point moves by the
 *      vector turbulence (noise.c) times the amount;
 *   4. the pattern's value: checker, the parity of floor(x + 1e-10) +
 *      floor(y + 1e-10) + floor(z + 1e-10) (0 or 1), POV-Ray's bias alone:
 *      a bias as wide as the point's rounding (tried before) put every
 *      point within it below a boundary in the upper cell, a band of wrong
 *      cells wherever a far, aliased checker's samples fall near its
 *      boundaries (the metals sample scenes: 98.8 % agreement, 99.75 %
 *      without), while the points POV-Ray finds exactly on a boundary are
 *      mostly on a flat face, which step 1 puts there exactly;
 *      gradient, dot(q, g), taken modulo 1 above 1;
 *      bozo (and spotted), POV-Ray's noise; granite, six octaves of
 *      |1 - 2 noise| (at most 0.5 each) at 4q; marble, x + turbulence;
 *      wood, the distance from the z axis of (x, y) moved by cycloids of
 *      the vector turbulence; agate, a cycloid of its turbulence and z,
 *      to the power 0.77; crackle, the three nearest cube points weighted
 *      by its form; the simple shapes (pattern.cpp);
 *   5. the wave: value * frequency + phase modulo 1.00001 (POV-Ray's
 *      constant) unless the frequency is 0 (a checker's), then wrapped
 *      into [0, 1) when negative, then shaped (ramp, triangle, sine,
 *      scallop, cubic, poly: Evaluate_TPat);
 *   6. the colour map (or the pigment map, whose entries are materials
 *      evaluated from step 2 on at q, POV-Ray's Compute_Pigment): the
 *      first entry whose value is >= the value, and
 *      linear interpolation from the entry before it (at or past the last
 *      entry: the last colour).
 *
 * Steps 3 to 5 follow the tables of csg/device/patterns.h: each pattern's
 * value is pattern_<name>, each wave wave_<name>, and the switches that
 * call them are the tables expanded, with no default case.  A material
 * whose pattern or wave is outside the tables never reaches them:
 * csg_blob_valid (csg/blob.c) refuses its blob before any worker, local
 * or remote, reads it (host/render.c, workers/worker.c, comm/relay.c).
 */
#include "pigment.h"

#include "noise.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>

#define PATTERN_EPSILON 1e-10 /* POV-Ray's EPSILON */

static double dot3d(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The plane of a flat sub-surface, in local coordinates: n . l = dist;
 * false for a curved one. */
static bool face_plane(const csg_prim *pr, int sub, double n[3], double *dist)
{
    n[0] = n[1] = n[2] = 0;
    switch (pr->kind) {
    case CSG_PRIM_PLANE:
        for (int i = 0; i < 3; i++)
            n[i] = (double)pr->p[i];
        *dist = (double)pr->p[3];
        return true;
    case CSG_PRIM_BOX:
    case CSG_PRIM_FLAT_BOX:
        n[sub >> 1] = 1;
        *dist = (double)pr->p[(sub & 1) ? 3 + (sub >> 1) : sub >> 1];
        return true;
    case CSG_PRIM_CONE:
        if (sub == CSG_SURF_CONE_SIDE)
            return false;
        n[2] = 1;
        *dist = sub == CSG_SURF_CONE_TOP ? (double)pr->p[2] : 0.0;
        return true;
    default:
        return false;
    }
}

/* Step 1: w moved onto its flat face, if it has one. */
static void onto_surface(const csg_prim *prims, csg_u32 surf, double w[3])
{
    const csg_prim *pr = &prims[CSG_SURF_PRIM(surf)];
    double n[3], dist, f, g[3];
    if (!face_plane(pr, CSG_SURF_SUB(surf), n, &dist))
        return;
    if (pr->flags & CSG_PF_XFORM) { /* f(w) = n . (M w + t) - dist, grad M^T n */
        double l[3];
        for (int i = 0; i < 3; i++)
            l[i] = (double)pr->inv[4 * i] * w[0] + (double)pr->inv[4 * i + 1] * w[1] +
                   (double)pr->inv[4 * i + 2] * w[2] + (double)pr->inv[4 * i + 3];
        f = dot3d(n, l) - dist;
        for (int j = 0; j < 3; j++)
            g[j] = n[0] * (double)pr->inv[j] + n[1] * (double)pr->inv[4 + j] +
                   n[2] * (double)pr->inv[8 + j];
    } else {
        f = dot3d(n, w) - dist;
        g[0] = n[0], g[1] = n[1], g[2] = n[2];
    }
    double gg = dot3d(g, g);
    if (gg > 0)
        for (int i = 0; i < 3; i++)
            w[i] -= f * g[i] / gg;
}

/* ---- step 3: classic turbulence ------------------------------------------ */

static noise_turb turb_of(const csg_material *m)
{
    noise_turb t = {m->octaves, (double)m->omega, (double)m->lambda};
    return t;
}

static void turbulence_warp(const csg_material *m, double q[3])
{
    noise_turb t = turb_of(m);
    double d[3];
    noise_vector_turbulence(q, &t, d);
    for (int i = 0; i < 3; i++)
        q[i] += d[i] * (double)m->turbulence[i];
}

/* The turbulence moves the point before m's pattern: the table's warp
 * column (device/patterns.h), 0 for the patterns that read it themselves. */
static bool turbulence_moves(const csg_material *m)
{
#define PIGMENT_WARP(ID, name, wave, noise, warp) [CSG_PATTERN_##ID] = warp,
    static const bool warps[CSG_PATTERN_COUNT] = {CSG_PATTERNS(PIGMENT_WARP, PIGMENT_WARP)};
#undef PIGMENT_WARP
    return warps[m->pattern];
}

/* ---- step 4: the patterns' values ------------------------------------------
 * pattern_<name> for each PATTERN row of CSG_PATTERNS (device/patterns.h),
 * with one signature: the material, the point in pattern space, and the
 * bias that puts a point on a cell boundary in the upper cell (checker's). */

static double pattern_checker(const csg_material *m, const double q[3], double bias)
{
    (void)m;
    double sum = floor(q[0] + bias) + floor(q[1] + bias) + floor(q[2] + bias);
    return fmod(sum, 2.0) != 0.0 ? 1.0 : 0.0;
}

static double pattern_gradient(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double g[3] = {(double)m->gradient[0], (double)m->gradient[1], (double)m->gradient[2]};
    double r = dot3d(q, g);
    return r > 1.0 ? fmod(r, 1.0) : r;
}

static double pattern_bozo(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    return noise_value(q, m->noise_gen);
}

static double pattern_granite(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    int gen = m->noise_gen;
    double sum = 0.0, freq = 1.0;
    double p4[3] = {q[0] * 4.0, q[1] * 4.0, q[2] * 4.0};
    for (int i = 0; i < 6; freq *= 2.0, i++) {
        double p[3] = {p4[0] * freq, p4[1] * freq, p4[2] * freq}, t;
        if (gen == 1) {
            t = fabs(0.5 - noise_value(p, gen));
        } else {
            t = fabs(1.0 - 2.0 * noise_value(p, gen));
            t = t > 0.5 ? 0.5 : t;
        }
        sum += t / freq;
    }
    return sum;
}

static double pattern_marble(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double turb = 0.0;
    if (m->turb_on) {
        noise_turb t = turb_of(m);
        turb = (double)m->turbulence[0] * noise_turbulence(q, &t, m->noise_gen);
    }
    return q[0] + turb;
}

static double pattern_wood(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double x = 0.0, y = 0.0;
    if (m->turb_on) {
        noise_turb t = turb_of(m);
        double d[3];
        noise_vector_turbulence(q, &t, d);
        x = noise_cycloidal((q[0] + d[0]) * (double)m->turbulence[0]);
        y = noise_cycloidal((q[1] + d[1]) * (double)m->turbulence[1]);
    }
    x += q[0];
    y += q[1];
    return sqrt(x * x + y * y + 0.0 * 0.0);
}

static double pattern_agate(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    noise_turb t = turb_of(m);
    double turb = (double)m->agate_turb * noise_turbulence(q, &t, m->noise_gen);
    double v = 0.5 * (noise_cycloidal(1.3 * turb + 1.1 * q[2]) + 1.0);
    if (v < 0.0)
        return 0.0;
    return pow(v < 1.0 ? v : 1.0, 0.77);
}

/* POV-Ray's wrinkles: nine more octaves of noise after the first, each
 * (for generators 2 and 3) stretched to 2 n - 0.5 and clamped. */
static double pattern_wrinkles(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    int gen = m->noise_gen;
    double lambda = 2.0, omega = 0.5, value;
    if (gen > 1) {
        double n = noise_value(q, gen) * 2.0 - 0.5;
        value = n < 0.0 ? 0.0 : n > 1.0 ? 1.0 : n;
    } else {
        value = noise_value(q, gen);
    }
    for (int i = 1; i < 10; i++) {
        double p[3] = {q[0] * lambda, q[1] * lambda, q[2] * lambda};
        if (gen > 1) {
            double n = noise_value(p, gen) * 2.0 - 0.5;
            value += omega * (n < 0.0 ? 0.0 : n > 1.0 ? 1.0 : n);
        } else {
            value += omega * noise_value(p, gen);
        }
        lambda *= 2.0;
        omega *= 0.5;
    }
    return value / 2.0;
}

static double pattern_dents(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double n = noise_value(q, m->noise_gen);
    return n * n * n;
}

/* q minus wave source i, its length (1 when 0, as POV-Ray), the source's
 * frequency. */
static double wave_offset(int i, const double q[3], double d[3], double *frequency)
{
    double src[3];
    noise_wave(i, src, frequency);
    for (int k = 0; k < 3; k++)
        d[k] = q[k] - src[k];
    double length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return length == 0.0 ? 1.0 : length;
}

/* ripples and waves read the frequency and phase themselves, and
 * Evaluate_TPat waves the result with them again (wave()), as POV-Ray. */
static double pattern_ripples(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double scalar = 0.0;
    for (int i = 0; i < m->number_of_waves; i++) {
        double d[3], f;
        double length = wave_offset(i, q, d, &f);
        scalar += noise_cycloidal(length * (double)m->frequency + (double)m->phase);
    }
    return 0.5 * (1.0 + scalar / (double)m->number_of_waves);
}

static double pattern_waves(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double scalar = 0.0;
    for (int i = 0; i < m->number_of_waves; i++) {
        double d[3], f;
        double length = wave_offset(i, q, d, &f);
        scalar += noise_cycloidal(length * (double)m->frequency * f + (double)m->phase) / f;
    }
    return 0.2 * (2.5 + scalar / (double)m->number_of_waves);
}

/* POV-Ray's quilt_cubic (INV_SQRT_3_4 = 1 / sqrt(3/4)). */
static double quilt_cubic(double t, double p1, double p2)
{
    double it = 1 - t, itsqrd = it * it, tsqrd = t * t, tcubed = t * tsqrd;
    return (tcubed + 3.0 * t * itsqrd * p1 + 3.0 * tsqrd * it * p2) * 1.15470053837925152902;
}

/* The point's offset from its cell's centre, scaled by quilt_cubic. */
static void quilted_vector(const csg_material *m, const double q[3], double v[3])
{
    for (int k = 0; k < 3; k++)
        v[k] = q[k] - floor(q[k]) - 0.5;
    double t = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    t = quilt_cubic(t, (double)m->quilt_control[0], (double)m->quilt_control[1]);
    for (int k = 0; k < 3; k++)
        v[k] *= t;
}

static double pattern_quilted(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double v[3];
    quilted_vector(m, q, v);
    return (fabs(v[0]) + fabs(v[1]) + fabs(v[2])) / 3.0;
}

/* POV-Ray's CLIP_DENSITY: 1 - r within [0, 1], 1 below, 0 above. */
static double clip_density(double r)
{
    return r < 0.0 ? 1.0 : r > 1.0 ? 0.0 : 1.0 - r;
}

static double pattern_radial(const csg_material *m, const double q[3], double bias)
{
    (void)m, (void)bias;
    if (fabs(q[0]) < 0.001 && fabs(q[2]) < 0.001)
        return 0.25;
    return 0.25 + (atan2(q[0], q[2]) + M_PI) / (2.0 * M_PI);
}

static double pattern_onion(const csg_material *m, const double q[3], double bias)
{
    (void)m, (void)bias;
    return fmod(sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]), 1.0);
}

static double pattern_leopard(const csg_material *m, const double q[3], double bias)
{
    (void)m, (void)bias;
    double v = (sin(q[0]) + sin(q[1]) + sin(q[2])) / 3.0;
    return v * v;
}

static double pattern_planar(const csg_material *m, const double q[3], double bias)
{
    (void)m, (void)bias;
    return clip_density(fabs(q[1]));
}

static double pattern_boxed(const csg_material *m, const double q[3], double bias)
{
    (void)m, (void)bias;
    double a = fabs(q[0]), b = fabs(q[1]), c = fabs(q[2]);
    return clip_density(a > (b > c ? b : c) ? a : (b > c ? b : c));
}

static double pattern_cylindrical(const csg_material *m, const double q[3], double bias)
{
    (void)m, (void)bias;
    return clip_density(sqrt(q[0] * q[0] + q[2] * q[2]));
}

/* POV-Ray's crackle distance of d (a point minus q) by the metric. */
static double crackle_distance(const double d[3], double metric)
{
    if (metric == 2.0)
        return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (metric == 1.0)
        return fabs(d[0]) + fabs(d[1]) + fabs(d[2]);
    return pow(fabs(d[0]), metric) + pow(fabs(d[1]), metric) + pow(fabs(d[2]), metric);
}

/* The 81 cubes around a point's cube that can hold its nearest random
 * points: offsets -2..2 with at most one of them +-2 (POV-Ray's order). */
static int crackle_cubes(int cubes[81][3])
{
    int n = 0;
    for (int x = -2; x <= 2; x++)
        for (int y = -2; y <= 2; y++)
            for (int z = -2; z <= 2; z++)
                if ((abs(x) == 2) + (abs(y) == 2) + (abs(z) == 2) <= 1) {
                    cubes[n][0] = x, cubes[n][1] = y, cubes[n][2] = z;
                    n++;
                }
    return n;
}

/* POV-Ray's cube of coordinate c, (int)floor(c - EPSILON), with c clamped
 * first (NaN to the low end) so that the conversion and the neighbours'
 * cells (+-2) stay inside int: far from the origin C leaves both
 * undefined. */
static int crackle_cell(double c)
{
    const double lim = 2147483000.0;
    c -= PATTERN_EPSILON;
    c = c > lim ? lim : c >= -lim ? c : -lim;
    return (int)floor(c);
}

/* The three smallest of the distances s[0..n), in POV-Ray's order of
 * comparisons (which settles ties), into s[0..2]; the index of the
 * smallest. */
static int crackle_nearest(double *s, int n)
{
    int best = 0;
    double t;
    if (s[1] < s[0])
        t = s[0], s[0] = s[1], s[1] = t, best = 1;
    if (s[2] < s[0])
        t = s[0], s[0] = s[2], s[2] = t, best = 2;
    if (s[2] < s[1])
        t = s[1], s[1] = s[2], s[2] = t;
    for (int i = 3; i < n; i++) {
        if (s[i] < s[0]) {
            s[2] = s[1], s[1] = s[0], s[0] = s[i], best = i;
        } else if (s[i] < s[1]) {
            s[2] = s[1], s[1] = s[i];
        } else if (s[i] < s[2]) {
            s[2] = s[i];
        }
    }
    return best;
}

/* POV-Ray's crackle_pattern: the three smallest distances to the random
 * points of the cubes around q, plus the offset, weighted by the form
 * (back from the metric); or, solid, the noise at the nearest point.
 * Clamped to [0, 1]. */
static double pattern_crackle(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    int cubes[81][3], n = crackle_cubes(cubes);
    int fx = crackle_cell(q[0]), fy = crackle_cell(q[1]), fz = crackle_cell(q[2]);
    double metric = (double)m->crackle_metric, s[81], pts[81][3];
    for (int i = 0; i < n; i++) {
        noise_cube_point(fx + cubes[i][0], fy + cubes[i][1], fz + cubes[i][2], pts[i]);
        double d[3] = {pts[i][0] - q[0], pts[i][1] - q[1], pts[i][2] - q[2]};
        s[i] = crackle_distance(d, metric);
    }
    int best = crackle_nearest(s, n);
    double offset = (double)m->crackle_offset, v;
    if (offset != 0.0) {
        double add = metric == 2.0 ? offset * offset : metric == 1.0 ? offset : pow(offset, metric);
        for (int i = 0; i < 3; i++)
            s[i] += add;
    }
    const real *f = m->crackle_form;
    if (m->crackle_solid)
        v = noise_value(pts[best], m->noise_gen);
    else if (metric == 2.0)
        v = (double)f[0] * sqrt(s[0]) + (double)f[1] * sqrt(s[1]) + (double)f[2] * sqrt(s[2]);
    else if (metric == 1.0)
        v = (double)f[0] * s[0] + (double)f[1] * s[1] + (double)f[2] * s[2];
    else
        v = (double)f[0] * pow(s[0], 1.0 / metric) + (double)f[1] * pow(s[1], 1.0 / metric) +
            (double)f[2] * pow(s[2], 1.0 / metric);
    return v < 1.0 ? (v > 0.0 ? v : 0.0) : 1.0;
}

/* average has no value of its own (POV-Ray's AveragePattern: 0); its
 * pigment map is averaged instead (average_color). */
static double pattern_average(const csg_material *m, const double q[3], double bias)
{
    (void)m, (void)q, (void)bias;
    return 0.0;
}

/* x's fraction as POV-Ray's brick takes it, x - (int)x moved into
 * [0, 1): trunc in place of the int cast, equal wherever the cast is
 * defined. */
static double brick_fraction(double x)
{
    double f = x - trunc(x);
    return f < 0.0 ? f + 1.0 : f;
}

/* POV-Ray's brick_pattern: 0 in the mortar, 1 in a brick.  The layers of
 * mortar between the rows (y), then the ends of the bricks (x, every
 * other row shifted by half a brick), then the faces along z the same;
 * the point is moved by the mortar (plus EPSILON) first. */
static double pattern_brick(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double mortar = (double)m->mortar, fudge = PATTERN_EPSILON + mortar;
    double x = q[0] + fudge, y = q[1] + fudge, z = q[2] + fudge;
    double width = (double)m->brick_size[0], height = (double)m->brick_size[1],
           depth = (double)m->brick_size[2];
    if (brick_fraction(y / height) <= mortar / height)
        return 0.0;
    bool odd_row = brick_fraction((y / height) * 0.5) <= 0.5;
    double ends = brick_fraction(odd_row ? x / width : x / width + 0.5);
    if (ends <= mortar / width)
        return 0.0;
    double faces = brick_fraction(odd_row ? z / depth + 0.5 : z / depth);
    return faces <= mortar / depth ? 0.0 : 1.0;
}

/* The hexagon's colour (0, 1 or 2) of a cell (xm, zm) of POV-Ray's 6 x 6
 * grid wholly inside one hexagon (xm 0, 2, 3 or 5). */
static int hexagon_square(int xm, int zm)
{
    static const int edge[6] = {0, 1, 1, 2, 2, 0};   /* xm 0 and 5 */
    static const int middle[6] = {2, 2, 0, 0, 1, 1}; /* xm 2 and 3 */
    return xm == 0 || xm == 5 ? edge[zm] : middle[zm];
}

/* POV-Ray's hexagon_pattern: three hexagons tiling the xz plane, 0, 1 or
 * 2.  The point is folded (|x|; z < 0 moved up by the grid's height, not
 * mirrored), scaled into a 6 x 6 grid of half triangles; cells with
 * xm 1 or 4 are split by a diagonal (the slope read against 1). */
static double pattern_hexagon(const csg_material *m, const double q[3], double bias)
{
    (void)m, (void)bias;
    double x = fabs(q[0]), z = q[2];
    z = z < 0.0 ? 5.196152424 - fabs(z) : z;
    double xs = x / 0.5, zs = z / 0.866025404;
    xs -= floor(xs / 6.0) * 6.0;
    zs -= floor(zs / 6.0) * 6.0;
    /* in [0, 6) but where the rounding of a far point says otherwise (POV-Ray's
       int cast of such a point is undefined: cell 0 here) */
    int xm = xs >= 0.0 && xs < 6.0 ? (int)floor(xs) % 6 : 0;
    int zm = zs >= 0.0 && zs < 6.0 ? (int)floor(zs) % 6 : 0;
    if (xm != 1 && xm != 4)
        return hexagon_square(xm, zm);
    double xl = xs - xm, zl = zs - zm;
    if ((xm + zm) % 2 == 1)
        xl = 1.0 - xl;
    if (xl == 0.0)
        xl = 0.0001; /* POV-Ray's */
    static const int below[6] = {0, 2, 1, 0, 2, 1}; /* zl / xl < 1, by zm */
    static const int above[6] = {2, 1, 0, 2, 1, 0};
    return zl / xl < 1.0 ? below[zm] : above[zm];
}

/* POV-Ray's spiral angle: the turn of (x, y) about the z axis in
 * [0, 2 pi), from -y; and the distance from the axis. */
static double spiral_turn(const double q[3], double *rad)
{
    double x = q[0], y = q[1];
    *rad = sqrt(x * x + y * y);
    if (*rad == 0.0)
        return 0.0;
    return x < 0.0 ? 3.0 * 1.57079632679489661923 - asin(y / *rad)
                   : 1.57079632679489661923 + asin(y / *rad);
}

/* spiral1 and spiral2 add their turbulence themselves (POV-Ray's
 * Search_For_Turb: the classic one's x amount times the noise's
 * turbulence), after the classic warp has moved the point. */
static double spiral_turbulence(const csg_material *m, const double q[3])
{
    if (!m->turb_on)
        return 0.0;
    noise_turb t = turb_of(m);
    return (double)m->turbulence[0] * noise_turbulence(q, &t, m->noise_gen);
}

static double pattern_spiral1(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double turb = spiral_turbulence(m, q), rad, phi = spiral_turn(q, &rad);
    return q[2] + rad + (double)m->spiral_arms * phi / 6.283185307179586476925286766560 + turb;
}

static double pattern_spiral2(const csg_material *m, const double q[3], double bias)
{
    (void)bias;
    double turb = spiral_turbulence(m, q), rad, phi = spiral_turn(q, &rad);
    turb = noise_triangle(q[2] + rad +
                          (double)m->spiral_arms * phi / 6.283185307179586476925286766560 + turb);
    return noise_triangle(rad) + turb;
}

/* pigment_pattern's value needs the other materials: pattern_at gives it
 * (its pigment's grey), this is the table's row. */
static double pattern_pigment_pattern(const csg_material *m, const double q[3], double bias)
{
    (void)m, (void)q, (void)bias;
    return 0.0;
}

/* Step 4: the value of m's pattern.  The cases are the table's rows, each
 * its pattern_<name> (a row without one does not compile); there is no
 * default, so -Wswitch names a pattern left out.  Plain never gets here
 * (evaluate() returns its colour first), and no other id reaches a worker:
 * csg_blob_valid refuses a blob with one (csg/blob.c). */
static double pattern_value(const csg_material *m, const double q[3], double bias)
{
    switch ((enum csg_pattern)m->pattern) {
    case CSG_PATTERN_PLAIN:
        break;
#define PIGMENT_PATTERN_CASE(ID, name, wave, noise, warp)                                          \
    case CSG_PATTERN_##ID:                                                                         \
        return pattern_##name(m, q, bias);
        CSG_PATTERNS(CSG_PATTERN_NONE, PIGMENT_PATTERN_CASE)
#undef PIGMENT_PATTERN_CASE
    }
    return 0.0; /* not reached (above) */
}

/* ---- step 5: the waves, wave_<name> for each row of CSG_WAVES ------------ */

static double wave_ramp(const csg_material *m, double v)
{
    (void)m;
    return v;
}

static double wave_triangle(const csg_material *m, double v)
{
    (void)m;
    return noise_triangle(v);
}

static double wave_sine(const csg_material *m, double v)
{
    (void)m;
    return (1.0 + noise_cycloidal(v)) * 0.5;
}

static double wave_scallop(const csg_material *m, double v)
{
    (void)m;
    return fabs(noise_cycloidal(v * 0.5));
}

static double wave_cubic(const csg_material *m, double v)
{
    (void)m;
    return v * v * (-2.0 * v + 3.0);
}

static double wave_poly(const csg_material *m, double v)
{
    return pow(v, (double)m->exponent);
}

/* Step 5: frequency and phase, then m's wave (dispatched like
 * pattern_value: the table's rows, no default, ids checked by
 * csg_blob_valid). */
static double wave(const csg_material *m, double v)
{
    if ((double)m->frequency != 0.0)
        v = fmod(v * (double)m->frequency + (double)m->phase, 1.00001);
    if (v < 0.0)
        v -= floor(v);
    switch ((enum csg_wave)m->wave) {
#define PIGMENT_WAVE_CASE(ID, name)                                                                \
    case CSG_WAVE_##ID:                                                                            \
        return wave_##name(m, v);
        CSG_WAVES(PIGMENT_WAVE_CASE)
#undef PIGMENT_WAVE_CASE
    }
    return v; /* not reached (above) */
}

/* ---- step 6: the colour map or the pigment map ----------------------------- */

/* Step 6, POV-Ray's Search_Blend_Map: the entries *prev and *cur around
 * v, and the fraction of the way from prev to cur (0 when they are one). */
static double map_search(const csg_map_color *e, int n, double v, int *prev, int *cur)
{
    *cur = *prev = 0;
    if (v >= (double)e[n - 1].value) {
        *cur = *prev = n - 1;
    } else {
        while (v > (double)e[*cur].value)
            *prev = (*cur)++;
        if (v == (double)e[*cur].value)
            *prev = *cur;
    }
    if (*prev == *cur)
        return 0.0;
    return (v - (double)e[*prev].value) / ((double)e[*cur].value - (double)e[*prev].value);
}

/* a + f (b - a), component by component (POV-Ray's blend of two entries). */
static void blend(double *a, const double *b, double f, int n)
{
    for (int k = 0; k < n; k++)
        a[k] = a[k] + f * (b[k] - a[k]);
}

static pigment_color color_of(const double c[5])
{
    pigment_color pc;
    pc.color = v3((real)c[0], (real)c[1], (real)c[2]);
    pc.filter = (real)c[3];
    pc.transmit = (real)c[4];
    return pc;
}

static void load_color(pigment_color pc, double c[5])
{
    c[0] = (double)pc.color.x, c[1] = (double)pc.color.y, c[2] = (double)pc.color.z;
    c[3] = (double)pc.filter, c[4] = (double)pc.transmit;
}

/* Step 6 with a colour map. */
static pigment_color map_color(const csg_map_color *e, int n, double v)
{
    int cur, prev;
    double f = map_search(e, n, v, &prev, &cur), c[5], next[5];
    for (int k = 0; k < 5; k++) {
        c[k] = (double)e[prev].rgbft[k];
        next[k] = (double)e[cur].rgbft[k];
    }
    if (prev != cur)
        blend(c, next, f, 5);
    else
        for (int k = 0; k < 5; k++)
            c[k] = next[k];
    return color_of(c);
}

/* The largest row sum of |M| (3x3 part): how much M can grow an error. */
static double matrix_norm(const real *m)
{
    double best = 0;
    for (int i = 0; i < 3; i++) {
        double row = fabs((double)m[4 * i]) + fabs((double)m[4 * i + 1]) + fabs((double)m[4 * i + 2]);
        best = row > best ? row : best;
    }
    return best;
}

#define PIGMENT_MAX_DEPTH 64 /* nested pigment maps followed (the parser's
                                nesting limit keeps real scenes far below) */

static pigment_color evaluate(const csg_material *mats, const csg_material *m,
                              const csg_map_color *maps, const double w[3], double err, int depth);

/* Step 4 with the other materials at hand: a pigment_pattern's value is
 * the grey of its pigment at q (POV-Ray's pigment_pattern: the colour in
 * floats, 0.297 r + 0.589 g + 0.114 b, rounded to a float); every other
 * pattern's is pattern_value's. */
static double pattern_at(const csg_material *mats, const csg_material *m,
                         const csg_map_color *maps, const double q[3], double err, int depth)
{
    if (m->pattern != CSG_PATTERN_PIGMENT_PATTERN)
        return pattern_value(m, q, PATTERN_EPSILON);
    if (depth >= PIGMENT_MAX_DEPTH)
        return 0.0;
    pigment_color c = evaluate(mats, &mats[m->pattern_pigment], maps, q, err, depth + 1);
    float r = (float)c.color.x, g = (float)c.color.y, b = (float)c.color.z;
    return (double)(float)(0.297 * (double)r + 0.589 * (double)g + 0.114 * (double)b);
}

/* Step 6 with a pigment map: the entries' pigments at the pattern's
 * point q (POV-Ray's Compute_Pigment hands them the warped point). */
static pigment_color pigment_map_color(const csg_material *mats, const csg_material *m,
                                       const csg_map_color *maps, const double q[3], double err,
                                       double v, int depth)
{
    int cur, prev;
    double f = map_search(maps + m->map_first, m->map_count, v, &prev, &cur), c[5], next[5];
    load_color(evaluate(mats, &mats[m->sub_first + cur], maps, q, err, depth + 1), next);
    if (prev == cur)
        return color_of(next);
    load_color(evaluate(mats, &mats[m->sub_first + prev], maps, q, err, depth + 1), c);
    blend(c, next, f, 5);
    return color_of(c);
}

/* POV-Ray's average pigment (PigmentBlendMap::ComputeAverage): the
 * entries' pigments at the pattern's point q, each weighted by its map
 * value, over the sum of the values (all 0: black, where POV-Ray divides
 * by zero). */
static pigment_color average_color(const csg_material *mats, const csg_material *m,
                                   const csg_map_color *maps, const double q[3], double err,
                                   int depth)
{
    double sum[5] = {0, 0, 0, 0, 0}, total = 0.0;
    for (int i = 0; i < m->map_count; i++) {
        double weight = (double)maps[m->map_first + i].value, c[5];
        load_color(evaluate(mats, &mats[m->sub_first + i], maps, q, err, depth + 1), c);
        for (int k = 0; k < 5; k++)
            sum[k] += weight * c[k];
        total += weight;
    }
    for (int k = 0; k < 5; k++)
        sum[k] = total != 0.0 ? sum[k] / total : 0.0;
    return color_of(sum);
}

/* Steps 2 to 6 at the point w (world space, or the space of the pattern
 * whose pigment map holds m), err its rounding bound. */
static pigment_color evaluate(const csg_material *mats, const csg_material *m,
                              const csg_map_color *maps, const double w[3], double err, int depth)
{
    if (m->pattern == CSG_PATTERN_PLAIN) {
        pigment_color pc;
        pc.color = v3_load(m->color);
        pc.filter = m->filter;
        pc.transmit = m->transmit;
        return pc;
    }
    double q[3];
    for (int i = 0; i < 3; i++)
        q[i] = (double)m->to_pattern[4 * i] * w[0] + (double)m->to_pattern[4 * i + 1] * w[1] +
               (double)m->to_pattern[4 * i + 2] * w[2] + (double)m->to_pattern[4 * i + 3];
    if (m->turb_on && turbulence_moves(m))
        turbulence_warp(m, q);
    double q_err = err * matrix_norm(m->to_pattern);
    if (m->pattern == CSG_PATTERN_AVERAGE)
        return depth < PIGMENT_MAX_DEPTH && m->sub_first > 0
                   ? average_color(mats, m, maps, q, q_err, depth)
                   : color_of((const double[5]){0, 0, 0, 0, 0});
    double v = wave(m, pattern_at(mats, m, maps, q, q_err, depth));
    if (m->sub_first > 0 && depth < PIGMENT_MAX_DEPTH)
        return pigment_map_color(mats, m, maps, q, q_err, v, depth);
    return map_color(maps + m->map_first, m->map_count, v);
}

pigment_color PIGMENT_AT(const csg_material *mats, const csg_material *m,
                         const csg_map_color *maps, const csg_prim *prims, csg_u32 surf, vec3 p,
                         real err)
{
    double w[3] = {(double)p.x, (double)p.y, (double)p.z};
    if (m->pattern != CSG_PATTERN_PLAIN && prims && surf != CSG_SURF_NONE)
        onto_surface(prims, surf, w);
    return evaluate(mats, m, maps, w, (double)err, 0);
}

void PIGMENT_SURFACE_POINT(const csg_prim *prims, csg_u32 surf, vec3 p, double w[3])
{
    w[0] = (double)p.x, w[1] = (double)p.y, w[2] = (double)p.z;
    if (prims && surf != CSG_SURF_NONE)
        onto_surface(prims, surf, w);
}

pigment_color PIGMENT_EVAL(const csg_material *mats, const csg_material *m,
                           const csg_map_color *maps, const double w[3], double err)
{
    return evaluate(mats, m, maps, w, err, 0);
}

/* Steps 2 and 3: w (err its rounding) into m's pattern space, moved by
 * its turbulence. */
static void pattern_point(const csg_material *m, const double w[3], double err, double q[3],
                          double *q_err)
{
    for (int i = 0; i < 3; i++)
        q[i] = (double)m->to_pattern[4 * i] * w[0] + (double)m->to_pattern[4 * i + 1] * w[1] +
               (double)m->to_pattern[4 * i + 2] * w[2] + (double)m->to_pattern[4 * i + 3];
    if (m->turb_on && turbulence_moves(m))
        turbulence_warp(m, q);
    *q_err = err * matrix_norm(m->to_pattern);
}

double PIGMENT_TMAP(const csg_material *mats, const csg_material *m, const csg_map_color *maps,
                    const double w[3], double err, double q[3], double *q_err, int *prev,
                    int *cur)
{
    pattern_point(m, w, err, q, q_err);
    double v = wave(m, pattern_at(mats, m, maps, q, *q_err, 0));
    return map_search(maps + m->map_first, m->map_count, v, prev, cur);
}

/* ---- normals: POV-Ray's Perturb_Normal ---------------------------------------
 * normal_<name> for each row of CSG_NORMALS (device/patterns.h): the
 * normal material nm at q (its pattern space, after the turbulence) adds
 * its perturbation to n (pattern space). */

static const double pyramid[4][3] = {{0.942809041, -0.333333333, 0.0},
                                     {-0.471404521, -0.333333333, 0.816496581},
                                     {-0.471404521, -0.333333333, -0.816496581},
                                     {0.0, 1.0, 0.0}};

static void add_scaled(double n[3], double f, const double v[3])
{
    for (int k = 0; k < 3; k++)
        n[k] += f * v[k];
}

/* Any pattern: its value (through its wave) at four points around q,
 * each pushing the normal along its direction. */
static void normal_pattern(const csg_material *mats, const csg_map_color *maps,
                           const csg_material *nm, const double q[3], double n[3])
{
    double delta = (double)nm->accuracy;
    double amount = (double)nm->bump_size * -5.0;
    amount *= 0.02 / delta;
    for (int i = 0; i < 4; i++) {
        double p1[3];
        for (int k = 0; k < 3; k++)
            p1[k] = q[k] + delta * pyramid[i][k];
        double v = wave(nm, pattern_at(mats, nm, maps, p1, 0.0, 0));
        add_scaled(n, v * amount, pyramid[i]);
    }
}

static void normal_bumps(const csg_material *mats, const csg_map_color *maps,
                         const csg_material *nm, const double q[3], double n[3])
{
    (void)mats, (void)maps;
    double d[3];
    noise_vector(q, d);
    add_scaled(n, (double)nm->bump_size, d);
}

static void normal_dents(const csg_material *mats, const csg_map_color *maps,
                         const csg_material *nm, const double q[3], double n[3])
{
    (void)mats, (void)maps;
    double noise = noise_value(q, nm->noise_gen), d[3];
    noise = noise * noise * noise * (double)nm->bump_size;
    noise_vector(q, d);
    add_scaled(n, noise, d);
}

static void normal_ripples(const csg_material *mats, const csg_map_color *maps,
                           const csg_material *nm, const double q[3], double n[3])
{
    (void)mats, (void)maps;
    for (int i = 0; i < nm->number_of_waves; i++) {
        double d[3], f;
        double length = wave_offset(i, q, d, &f);
        double index = length * (double)nm->frequency + (double)nm->phase;
        double scalar = noise_cycloidal(index) * (double)nm->bump_size;
        add_scaled(n, scalar / (length * (double)nm->number_of_waves), d);
    }
}

static void normal_waves(const csg_material *mats, const csg_map_color *maps,
                         const csg_material *nm, const double q[3], double n[3])
{
    (void)mats, (void)maps;
    for (int i = 0; i < nm->number_of_waves; i++) {
        double d[3], f;
        double length = wave_offset(i, q, d, &f);
        double index = length * (double)nm->frequency * f + (double)nm->phase;
        double scalar = noise_cycloidal(index) * (double)nm->bump_size / f;
        add_scaled(n, scalar / (length * (double)nm->number_of_waves), d);
    }
}

static void normal_wrinkles(const csg_material *mats, const csg_map_color *maps,
                            const csg_material *nm, const double q[3], double n[3])
{
    (void)mats, (void)maps;
    double result[3] = {0.0, 0.0, 0.0}, scale = 1.0;
    for (int i = 0; i < 10; scale *= 2.0, i++) {
        double p[3] = {q[0] * scale, q[1] * scale, q[2] * scale}, d[3];
        noise_vector(p, d);
        for (int k = 0; k < 3; k++)
            result[k] += fabs(d[k] / scale);
    }
    add_scaled(n, (double)nm->bump_size, result);
}

static void normal_quilted(const csg_material *mats, const csg_map_color *maps,
                           const csg_material *nm, const double q[3], double n[3])
{
    (void)mats, (void)maps;
    double v[3];
    quilted_vector(nm, q, v);
    add_scaled(n, (double)nm->bump_size, v);
}

static void normalize3(double v[3])
{
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0.0)
        for (int k = 0; k < 3; k++)
            v[k] /= len;
}

void PIGMENT_WARP_NORMAL(const csg_material *m, double n[3], bool scale)
{
    if (scale)
        normalize3(n);
    const real *a = m->from_pattern; /* n_pattern = A^T n (POV-Ray's MInvTransNormal) */
    double t[3];
    for (int j = 0; j < 3; j++)
        t[j] = (double)a[j] * n[0] + (double)a[3 + j] * n[1] + (double)a[6 + j] * n[2];
    for (int k = 0; k < 3; k++)
        n[k] = t[k];
    if (scale)
        normalize3(n);
}

void PIGMENT_UNWARP_NORMAL(const csg_material *m, double n[3], bool scale)
{
    if (scale)
        normalize3(n);
    const real *b = m->to_pattern; /* n_world = B^T n (MTransNormal: the inverse's transpose) */
    double t[3];
    for (int j = 0; j < 3; j++)
        t[j] = (double)b[j] * n[0] + (double)b[4 + j] * n[1] + (double)b[8 + j] * n[2];
    for (int k = 0; k < 3; k++)
        n[k] = t[k];
    if (scale)
        normalize3(n);
}

void PIGMENT_NORMAL(const csg_material *mats, const csg_map_color *maps, const csg_material *nm,
                    const double w[3], double n[3])
{
    bool scale = !nm->no_bump_scale;
    PIGMENT_WARP_NORMAL(nm, n, scale);
    double q[3], q_err;
    pattern_point(nm, w, 0.0, q, &q_err);
    switch ((enum csg_normal_kind)nm->normal_kind) {
#define NORMAL_CASE(ID, name)                                                                      \
    case CSG_NORMAL_##ID:                                                                          \
        normal_##name(mats, maps, nm, q, n);                                                       \
        break;
        CSG_NORMALS(NORMAL_CASE)
#undef NORMAL_CASE
    }
    PIGMENT_UNWARP_NORMAL(nm, n, scale);
    if (!scale)
        normalize3(n);
}
