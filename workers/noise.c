/*
 * noise.c — POV-Ray 3.7's solid noise (texture.cpp: Noise, DNoise,
 * Turbulence, DTurbulence, cycloidal, Triangle_Wave), rewritten from its
 * description so that every value is the same double POV-Ray computes.
 *
 * Generators 1 and 2 (POV-Ray's default since 3.5): the lattice noise of
 * Robert Skinner after Ken Perlin.  The point's integer cell (x >= 0:
 * (int)x, else (int)(x - (1 - 1e-10)), POV-Ray's "range fix") indexes a
 * 4096-entry permutation hash twice per corner; the hash picks an entry
 * of RTable (267 fixed random numbers, each followed by its half), whose
 * entries make the corner's linear function; the eight corners are mixed
 * by the cubic s-curve 3t^2 - 2t^3.  Generator 1 shifts the sum by 0.5,
 * generator 2 maps POV-Ray's measured range [-1.05242, 0.988997] onto
 * [0, 1]; both clamp.  Generator 3: Perlin's gradient noise over 2048
 * gradients on the unit sphere and a permutation, both drawn from
 * POV-Ray's generator next = next * 1812433253 + 12345 (low 32 bits), as
 * is the hash.  The order of every sum and product is POV-Ray's: the
 * patterns built on it are compared with POV-Ray's renders pixel by pixel.
 *
 * Crackle's random points (IntPickInCube): the cube's corner hashed
 * three times (Hash3d) indexes POV-Ray's PatternRands, the first values of
 * Boost's mt19937 (default seed 5489) through uniform_real [0, 1), that is
 * each 32-bit output / 2^32.
 *
 * The tables are constant data computed on first use (a few thousand
 * steps of that generator); the workers are single-threaded processes, so
 * the one static below is written once and only read after.
 */
#include "noise.h"

#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>

#define NOISE_EPSILON 1e-10            /* POV-Ray's EPSILON */
#define NOISE_MIN_CELL (-10000)        /* POV-Ray's MINX, MINY, MINZ */
#define HASH_SIZE 4096
#define SOLID_ENTRIES 2048             /* POV-Ray's NoiseEntries */
#define SOLID_ROLLOVER 10000000.023157213
#define TWO_PI 6.283185307179586476925286766560
#define PATTERN_RANDS (HASH_SIZE + 2)  /* the PatternRands crackle reads */

/* POV-Ray's RTable: the even entries; each odd one is half the entry
 * before it (Initialize_Noise). */
static const double rtable_seed[267] = {
    -1, 0.604974, -0.937102, 0.414115, 0.576226, -0.0161593, 0.432334, 0.103685,
    0.590539, 0.0286412, 0.46981, -0.84622, -0.0734112, -0.304097, -0.40206, -0.210132,
    -0.919127, 0.652033, -0.83151, -0.183948, -0.671107, 0.852476, 0.043595, -0.404532,
    0.75494, -0.335653, 0.618433, 0.605707, 0.708583, -0.477195, 0.899474, 0.490623,
    0.221729, -0.400381, -0.853727, -0.932586, 0.659113, 0.961303, 0.325948, -0.750851,
    0.842466, 0.734401, -0.649866, 0.394491, -0.466056, -0.434073, 0.109026, 0.0847028,
    -0.738857, 0.241505, 0.16228, -0.71426, -0.883665, -0.150408, -0.90396, -0.686549,
    -0.785214, 0.488548, 0.0246433, 0.142473, -0.602136, 0.375845, -0.00779736, 0.498955,
    -0.268147, 0.856382, -0.386007, -0.596094, -0.867735, -0.570977, -0.914366, 0.28896,
    0.672206, -0.233783, 0.94815, 0.895262, 0.343252, -0.173388, -0.767971, -0.314748,
    0.824308, -0.342092, 0.721431, -0.24004, -0.63653, 0.553277, 0.376272, 0.158984,
    -0.452659, 0.396323, -0.420676, -0.454154, 0.122179, 0.295857, 0.0664225, -0.202075,
    -0.724788, 0.453513, 0.224567, -0.908812, 0.176349, -0.320516, -0.697139, 0.742702,
    -0.900786, 0.471489, -0.133532, 0.119127, -0.889769, -0.23183, -0.669673, -0.046891,
    -0.803433, -0.966735, 0.475578, -0.652644, 0.0112459, -0.730007, 0.128283, 0.145647,
    -0.619318, 0.272023, 0.392966, 0.646418, -0.0207675, -0.315908, 0.480797, 0.535668,
    -0.250172, -0.83093, -0.653773, -0.443809, 0.119982, -0.897642, 0.89453, 0.165789,
    0.633875, -0.886839, 0.930877, -0.537194, 0.587732, 0.722011, -0.209461, -0.0424659,
    -0.814267, -0.919432, 0.280262, -0.66302, -0.558099, -0.537469, -0.598779, 0.929656,
    -0.170794, -0.537163, 0.312581, 0.959442, 0.722652, 0.499931, 0.175616, -0.534874,
    -0.685115, 0.444999, 0.17171, 0.108202, -0.768704, -0.463828, 0.254231, 0.546014,
    0.869474, 0.875212, -0.944427, 0.130724, -0.110185, 0.312184, -0.33138, -0.629206,
    0.0606546, 0.722866, -0.0979477, 0.821561, 0.0931258, -0.972808, 0.0318151, -0.867033,
    -0.387228, 0.280995, -0.218189, -0.539178, -0.427359, -0.602075, 0.311971, 0.277974,
    0.773159, 0.592493, -0.0331884, -0.630854, -0.269947, 0.339132, 0.581079, 0.209461,
    -0.317433, -0.284993, 0.181323, 0.341634, 0.804959, -0.229572, -0.758907, -0.336721,
    0.605463, -0.991272, -0.0188754, -0.300191, 0.368307, -0.176135, -0.3832, -0.749569,
    0.62356, -0.573938, 0.278309, -0.971313, 0.839994, -0.830686, 0.439078, 0.66128,
    0.694514, 0.0565042, 0.54342, -0.438804, -0.0228428, -0.687068, 0.857267, 0.301991,
    -0.494255, -0.941039, 0.775509, 0.410575, -0.362081, -0.671534, -0.348379, 0.932433,
    0.886442, 0.868681, -0.225666, -0.062211, -0.0976425, -0.641444, -0.848112, 0.724697,
    0.473503, 0.998749, 0.174701, 0.559625, -0.029099, -0.337392, -0.958129, -0.659785,
    0.236042, -0.246937, 0.659449, -0.027512, 0.821897, -0.226215, 0.0181735, 0.500481,
    -0.420127, -0.427878, 0.566186,
};

typedef struct {
    unsigned short hash[2 * HASH_SIZE];        /* a permutation, twice */
    double rtable[2 * 267];
    int perm[2 * (SOLID_ENTRIES + 1)];         /* generator 3 */
    double grad[2 * (SOLID_ENTRIES + 1)][3];
    double rands[PATTERN_RANDS];               /* crackle */
} noise_tables;

static noise_tables tables;
static pthread_once_t tables_once = PTHREAD_ONCE_INIT; /* (rank 0 may trace on two
                                                          threads: host/render.c) */

/* POV-Ray's table generator: next = next * 1812433253 + 12345 in 32 bits,
 * drawing bits 16..30. */
static unsigned draw(uint32_t *next)
{
    *next = *next * 1812433253u + 12345u;
    return (*next >> 16) & 0x7FFFu;
}

static void init_hash(noise_tables *t)
{
    uint32_t next = 0;
    for (int i = 0; i < HASH_SIZE; i++)
        t->hash[i] = (unsigned short)i;
    for (int i = HASH_SIZE - 1; i >= 0; i--) {
        unsigned j = draw(&next) % HASH_SIZE;
        unsigned short tmp = t->hash[i];
        t->hash[i] = t->hash[j];
        t->hash[j] = tmp;
    }
    for (int i = 0; i < HASH_SIZE; i++)
        t->hash[HASH_SIZE + i] = t->hash[i];
    for (int i = 0; i < 267; i++) {
        t->rtable[2 * i] = rtable_seed[i];
        t->rtable[2 * i + 1] = rtable_seed[i] * 0.5;
    }
}

/* Generator 3's gradients (uniform on the unit sphere, by rejection) and
 * permutation (POV-Ray's InitSolidNoise, its odd swap loop included). */
static void init_solid(noise_tables *t)
{
    uint32_t next = 1;
    for (int i = 0; i < SOLID_ENTRIES; i++) {
        double v[3], s;
        do {
            for (int j = 0; j < 3; j++)
                v[j] = (double)((int)(draw(&next) % (SOLID_ENTRIES << 1)) - SOLID_ENTRIES) /
                       (double)SOLID_ENTRIES;
            s = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        } while (s > 1.0 || s < 1.0e-5);
        s = 1.0 / sqrt(s);
        for (int j = 0; j < 3; j++)
            t->grad[i][j] = v[j] * s;
    }
    for (int i = 0; i < SOLID_ENTRIES; i++)
        t->perm[i] = i;
    for (int i = SOLID_ENTRIES; i > 0; i -= 2) { /* perm[SOLID_ENTRIES] is read before set: 0 */
        int k = t->perm[i];
        int j = (int)(draw(&next) % SOLID_ENTRIES);
        t->perm[i] = t->perm[j];
        t->perm[j] = k;
    }
    for (int i = 0; i < SOLID_ENTRIES + 2; i++) {
        t->perm[SOLID_ENTRIES + i] = t->perm[i];
        for (int j = 0; j < 3; j++)
            t->grad[SOLID_ENTRIES + i][j] = t->grad[i][j];
    }
}

/* The first PATTERN_RANDS outputs of the Mersenne Twister MT19937 (seed
 * 5489, the reference generator), each divided by 2^32. */
static void init_rands(noise_tables *t)
{
    uint32_t mt[624];
    mt[0] = 5489u;
    for (int i = 1; i < 624; i++)
        mt[i] = 1812433253u * (mt[i - 1] ^ (mt[i - 1] >> 30)) + (uint32_t)i;
    int next = 624;
    for (int n = 0; n < PATTERN_RANDS; n++) {
        if (next == 624) { /* the twist */
            for (int i = 0; i < 624; i++) {
                uint32_t y = (mt[i] & 0x80000000u) | (mt[(i + 1) % 624] & 0x7fffffffu);
                mt[i] = mt[(i + 397) % 624] ^ (y >> 1) ^ ((y & 1u) ? 0x9908b0dfu : 0u);
            }
            next = 0;
        }
        uint32_t y = mt[next++];
        y ^= y >> 11;
        y ^= (y << 7) & 0x9d2c5680u;
        y ^= (y << 15) & 0xefc60000u;
        y ^= y >> 18;
        t->rands[n] = (double)y / 4294967296.0;
    }
}

static void init_tables(void)
{
    init_hash(&tables);
    init_solid(&tables);
    init_rands(&tables);
}

static const noise_tables *get_tables(void)
{
    pthread_once(&tables_once, init_tables);
    return &tables;
}

static double scurve(double t)
{
    return t * t * (3.0 - 2.0 * t);
}

/* The lattice cell of one coordinate: its hash index (0..4095) and the
 * offset of c in it.  The int conversion is POV-Ray's; coordinates beyond
 * the int range (where C leaves it undefined) are clamped first. */
static int lattice(double c, double *frac)
{
    double lim = 2147483000.0;
    c = c > lim ? lim : c >= -lim ? c : -lim; /* (NaN: -lim) */
    int cell = c >= 0 ? (int)c : (int)(c - (1 - NOISE_EPSILON));
    *frac = c - cell;
    return (int)((unsigned)((long long)cell - NOISE_MIN_CELL) & 0xFFFu);
}

/* One lattice point's setup shared by Noise and DNoise. */
typedef struct {
    int ix, iy, iz;
    double off[2][3]; /* [0]: offsets from the lower corner, [1]: from the upper */
    double s[3], t[3]; /* s-curve weights of the upper and lower corner */
} cell_setup;

static void setup_cell(const double p[3], cell_setup *c)
{
    int *idx[3] = {&c->ix, &c->iy, &c->iz};
    for (int k = 0; k < 3; k++) {
        *idx[k] = lattice(p[k], &c->off[0][k]);
        c->off[1][k] = c->off[0][k] - 1;
        c->s[k] = scurve(c->off[0][k]);
        c->t[k] = 1 - c->s[k];
    }
}

/* The RTable entry of corner (dx, dy, dz) and its weight. */
static const double *corner(const noise_tables *tb, const cell_setup *c, int dx, int dy, int dz,
                            double *weight)
{
    int h = tb->hash[tb->hash[c->ix + dx] ^ (c->iy + dy)];
    *weight = ((dx ? c->s[0] : c->t[0]) * (dy ? c->s[1] : c->t[1])) * (dz ? c->s[2] : c->t[2]);
    return &tb->rtable[(tb->hash[h ^ (c->iz + dz)] & 0xFF) * 2];
}

/* POV-Ray's INCRSUMP: weight * (m[1] + m[2] x + m[4] y + m[6] z). */
static double corner_sum(const double *m, double w, const cell_setup *c, int dx, int dy, int dz)
{
    return w * (m[1] + m[2] * c->off[dx][0] + m[4] * c->off[dy][1] + m[6] * c->off[dz][2]);
}

/* Perlin's gradient noise (generator 3), about [-1, 1]. */
static double solid_noise(const noise_tables *tb, const double p[3])
{
    int b0[3], b1[3];
    double r0[3], r1[3], s[3];
    for (int k = 0; k < 3; k++) {
        double t = p[k] + SOLID_ROLLOVER, lim = 2147483000.0;
        t = t > lim ? lim : t >= -lim ? t : -lim; /* (the int range: see lattice) */
        int it = (int)floor(t);
        b0[k] = it & (SOLID_ENTRIES - 1);
        b1[k] = (b0[k] + 1) & (SOLID_ENTRIES - 1);
        r0[k] = t - it;
        r1[k] = r0[k] - 1.0;
        s[k] = scurve(r0[k]);
    }
    int i = tb->perm[b0[0]], j = tb->perm[b1[0]];
    int b00 = tb->perm[i + b0[1]], b10 = tb->perm[j + b0[1]];
    int b01 = tb->perm[i + b1[1]], b11 = tb->perm[j + b1[1]];
    double face[2];
    for (int z = 0; z < 2; z++) {
        int bz = z ? b1[2] : b0[2];
        double rz = z ? r1[2] : r0[2];
        const double *g00 = tb->grad[b00 + bz], *g10 = tb->grad[b10 + bz];
        const double *g01 = tb->grad[b01 + bz], *g11 = tb->grad[b11 + bz];
        double u = r0[0] * g00[0] + r0[1] * g00[1] + rz * g00[2];
        double v = r1[0] * g10[0] + r0[1] * g10[1] + rz * g10[2];
        double a = u + s[0] * (v - u);
        u = r0[0] * g01[0] + r1[1] * g01[1] + rz * g01[2];
        v = r1[0] * g11[0] + r1[1] * g11[1] + rz * g11[2];
        double b = u + s[0] * (v - u);
        face[z] = a + s[1] * (b - a);
    }
    return face[0] + s[2] * (face[1] - face[0]);
}

static double clamp01(double v)
{
    return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
}

double noise_value(const double p[3], int gen)
{
    const noise_tables *tb = get_tables();
    if (gen == 3) /* POV-Ray's correction of the tables' bias */
        return clamp01(0.5 * (1.59 * solid_noise(tb, p) + 0.985));
    static const int order[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                    {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    cell_setup c;
    setup_cell(p, &c);
    double sum = 0.0;
    for (int k = 0; k < 8; k++) {
        double w;
        const double *m = corner(tb, &c, order[k][0], order[k][1], order[k][2], &w);
        double term = corner_sum(m, w, &c, order[k][0], order[k][1], order[k][2]);
        sum = k ? sum + term : term;
    }
    if (gen == 2)
        return clamp01((sum + 1.05242) * 0.48985582);
    return clamp01(sum + 0.5);
}

void noise_vector(const double p[3], double out[3])
{
    const noise_tables *tb = get_tables();
    /* DNoise visits the corners in its own order, and the three
     * components read consecutive RTable windows 8 entries apart. */
    static const int order[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                    {0, 1, 1}, {1, 1, 1}, {1, 0, 1}, {0, 0, 1}};
    cell_setup c;
    setup_cell(p, &c);
    for (int k = 0; k < 8; k++) {
        double w;
        const double *m = corner(tb, &c, order[k][0], order[k][1], order[k][2], &w);
        for (int a = 0; a < 3; a++) {
            double term = corner_sum(m + 8 * a, w, &c, order[k][0], order[k][1], order[k][2]);
            out[a] = k ? out[a] + term : term;
        }
    }
}

double noise_turbulence(const double p[3], const noise_turb *t, int gen)
{
    double value = noise_value(p, gen);
    if (gen > 1)
        value = clamp01(2.0 * value - 0.5);
    double l = t->lambda, o = t->omega;
    for (int i = 2; i <= t->octaves; i++) {
        double q[3] = {p[0] * l, p[1] * l, p[2] * l};
        double n = noise_value(q, gen);
        value += gen > 1 ? o * (2.0 * n - 0.5) : o * n;
        if (i < t->octaves) {
            l *= t->lambda;
            o *= t->omega;
        }
    }
    return value;
}

void noise_vector_turbulence(const double p[3], const noise_turb *t, double out[3])
{
    noise_vector(p, out);
    double l = t->lambda, o = t->omega;
    for (int i = 2; i <= t->octaves; i++) {
        double q[3] = {p[0] * l, p[1] * l, p[2] * l}, v[3];
        noise_vector(q, v);
        for (int a = 0; a < 3; a++)
            out[a] += o * v[a];
        if (i < t->octaves) {
            l *= t->lambda;
            o *= t->omega;
        }
    }
}

void noise_cube_point(int cx, int cy, int cz, double out[3])
{
    const noise_tables *tb = get_tables();
    unsigned a = (unsigned)cx & 0xFFFu, b = (unsigned)cy & 0xFFFu, c = (unsigned)cz & 0xFFFu;
    unsigned seed = tb->hash[tb->hash[tb->hash[a] ^ b] ^ c];
    out[0] = cx + tb->rands[seed];
    out[1] = cy + tb->rands[seed + 1];
    out[2] = cz + tb->rands[seed + 2];
}

/* The fraction goes through * 50000 / 50000 as in POV-Ray (it rounds). */
double noise_cycloidal(double v)
{
    if (v >= 0.0)
        return sin((v - floor(v)) * 50000.0 / 50000.0 * TWO_PI);
    return 0.0 - sin((0.0 - (v + floor(0.0 - v))) * 50000.0 / 50000.0 * TWO_PI);
}

double noise_triangle(double v)
{
    double offset = v >= 0.0 ? v - floor(v) : v + 1.0 + floor(fabs(v));
    return offset >= 0.5 ? 2.0 * (1.0 - offset) : 2.0 * offset;
}

/* POV-Ray's Initialize_Waves, computed once for the first NOISE_WAVES_CACHED
 * sources (number_of_waves is 10 unless a scene says otherwise). */
#define NOISE_WAVES_CACHED 64

typedef struct {
    pthread_once_t once;
    double source[NOISE_WAVES_CACHED][3];
    double frequency[NOISE_WAVES_CACHED];
} wave_table;

static wave_table waves_cache = {PTHREAD_ONCE_INIT, {{0}}, {0}};

static void wave_compute(int i, double source[3])
{
    double p[3] = {(double)i, 0.0, 0.0}, d[3];
    noise_vector(p, d);
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++)
        source[k] = d[k] / len;
}

/* The frequency of source i: POV-Ray's 32-bit generator, stepped i + 1
 * times from -560851967 (int arithmetic that wraps, as POV-Ray's does). */
static double wave_frequency(int i)
{
    uint32_t next = (uint32_t)-560851967;
    for (int k = 0; k <= i; k++)
        next = next * 1812433253u + 12345u;
    return (double)((next >> 16) & 0x7FFFu) * 0.000030518509476 + 0.01;
}

static void init_waves(void)
{
    for (int i = 0; i < NOISE_WAVES_CACHED; i++) {
        wave_compute(i, waves_cache.source[i]);
        waves_cache.frequency[i] = wave_frequency(i);
    }
}

void noise_wave(int i, double source[3], double *frequency)
{
    if (i < NOISE_WAVES_CACHED) {
        pthread_once(&waves_cache.once, init_waves);
        for (int k = 0; k < 3; k++)
            source[k] = waves_cache.source[i][k];
        *frequency = waves_cache.frequency[i];
        return;
    }
    wave_compute(i, source);
    *frequency = wave_frequency(i);
}
