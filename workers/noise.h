/*
 * noise.h — POV-Ray 3.7's solid noise and classic turbulence
 * (workers/noise.c), in double, for the pigment patterns (pigment.c).
 * Compiled once: no `real` in sight.
 */
#ifndef WORKERS_NOISE_H
#define WORKERS_NOISE_H

/* POV-Ray's classic turbulence settings (fractal sum of noise octaves). */
typedef struct {
    int octaves;   /* 1 to 10                                       */
    double omega;  /* the weight of each octave, times the last one */
    double lambda; /* the frequency of each octave, times the last  */
} noise_turb;

/* POV-Ray's Noise: a value in [0, 1] at p by noise generator gen (1: the
 * original, 2: range-corrected, 3: Perlin's improved solid noise). */
double noise_value(const double p[3], int gen);

/* POV-Ray's DNoise: a vector-valued noise at p (every generator). */
void noise_vector(const double p[3], double out[3]);

/* POV-Ray's Turbulence: octaves of noise_value summed. */
double noise_turbulence(const double p[3], const noise_turb *t, int gen);

/* POV-Ray's DTurbulence: octaves of noise_vector summed. */
void noise_vector_turbulence(const double p[3], const noise_turb *t, double out[3]);

/* POV-Ray's IntPickInCube: the random point of the unit cube at integer
 * corner (cx, cy, cz) that crackle measures distances to. */
void noise_cube_point(int cx, int cy, int cz, double out[3]);

/* POV-Ray's cycloidal: sin(2 pi v) through the fraction of v. */
double noise_cycloidal(double v);

/* POV-Ray's Triangle_Wave: 0 -> 1 -> 0 over each unit of v. */
double noise_triangle(double v);

/* POV-Ray's wave source i (Initialize_Waves: the vector noise at (i, 0, 0),
 * normalised) and its frequency, for ripples and waves. */
void noise_wave(int i, double source[3], double *frequency);

#endif
