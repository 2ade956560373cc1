/*
 * patterns.h — the pigment patterns and the waves (POV-Ray 3.7's that
 * csgtrace implements), each a closed set kept as ONE X-macro table.
 *
 * Every stage expands these tables instead of listing the sets again: the
 * enums below are the ids of the scene (csg/scene.h, csg_pigment) and of
 * the blob alike (flat.h, csg_material: the flattener copies the id), the
 * lexer and the parser recognise the keywords (csg/lang/lexer.c,
 * texture.c), the blob validator refuses an id outside them (csg/blob.c),
 * export writes their names (csg/export_pov.c), and the C workers
 * dispatch to pattern_<name> and wave_<name> (workers/pigment.c), so a
 * row without its evaluation function is a compile error, and no stage
 * has a "default" that would take an unknown id for another one.
 *
 * A new pattern is a PATTERN row and its pattern_<name>; a new wave an X
 * row and its wave_<name>.  Only what the tables cannot say is written
 * elsewhere: the parameters a pattern takes and its own default map
 * (csg/lang/texture.c, written back by csg/export_pov.c).
 *
 * The order of the rows is the ids' order, which a blob holds as plain
 * integers: append new rows, never reorder (a blob's bytes would change).
 * Preprocessor and plain enums only: this header compiles as C11 and as
 * OpenCL C (the kernel includes it through flat.h, never reads it).
 */
#ifndef CSG_PATTERNS_H
#define CSG_PATTERNS_H

/* The waves, X(ID, name): CSG_WAVE_<ID>, whose keyword is <name>_wave and
 * whose shaping of a pattern's value v in [0, 1) is wave_<name>
 * (workers/pigment.c).  poly_wave's exponent is the parser's
 * (csg/lang/texture.c). */
#define CSG_WAVES(X)                                                                               \
    X(RAMP, ramp)         /* v                                          */                         \
    X(TRIANGLE, triangle) /* up and back down (wood's and marble's)     */                         \
    X(SINE, sine)         /* (1 + sin 2 pi v) / 2                       */                         \
    X(SCALLOP, scallop)   /* |sin pi v|                                 */                         \
    X(CUBIC, cubic)       /* 3v^2 - 2v^3                                */                         \
    X(POLY, poly)         /* v^exponent                                 */

/* The count is no enumerator, so that a switch over the enum lists the
 * rows and nothing else (-Wswitch: a row left out is an error). */
#define CSG_WAVE_ENUM(ID, name) CSG_WAVE_##ID,
#define CSG_WAVE_ONE(ID, name) +1
enum csg_wave { CSG_WAVES(CSG_WAVE_ENUM) };
#define CSG_WAVE_COUNT (0 CSG_WAVES(CSG_WAVE_ONE))

/* The patterns, COLOR(...) or PATTERN(ID, name, wave, noise, warp):
 *   ID     CSG_PATTERN_<ID>
 *   name   the keyword (COLOR: none, a plain pigment is written as its
 *          colour), the name export writes, and the suffix of its value,
 *          pattern_<name> (workers/pigment.c)
 *   wave   POV-Ray's default wave, CSG_WAVE_<wave>
 *   noise  1: the value depends on the noise generator (export writes
 *          noise_generator even without turbulence)
 *   warp   1: classic turbulence moves the point before the pattern
 *          (POV-Ray's Warp_EPoint); 0: the pattern reads it itself
 * What a pattern takes beyond the modifiers every pattern takes (checker's
 * colours, gradient's vector, agate_turb, crackle's form) and its default
 * colour map are the parser's (csg/lang/texture.c). */
#define CSG_PATTERNS(COLOR, PATTERN)                                                               \
    COLOR(PLAIN, plain, RAMP, 0, 0)               /* one colour: rgbft                 */          \
    PATTERN(CHECKER, checker, RAMP, 0, 1)         /* parity of floor x+floor y+floor z */          \
    PATTERN(GRADIENT, gradient, RAMP, 0, 1)       /* dot(point, vector), into [0, 1)   */          \
    PATTERN(BOZO, bozo, RAMP, 1, 1)               /* POV-Ray's solid noise             */          \
    PATTERN(WOOD, wood, TRIANGLE, 1, 0)           /* distance from the z axis          */          \
    PATTERN(MARBLE, marble, TRIANGLE, 1, 0)       /* x plus turbulence                 */          \
    PATTERN(GRANITE, granite, RAMP, 1, 1)         /* six octaves of |noise|            */          \
    PATTERN(AGATE, agate, RAMP, 1, 1)             /* a cycloid of turbulence and z     */          \
    PATTERN(WRINKLES, wrinkles, RAMP, 1, 1)       /* ten octaves of noise, halved      */          \
    PATTERN(RADIAL, radial, RAMP, 0, 1)           /* turns about y from -z             */          \
    PATTERN(ONION, onion, RAMP, 0, 1)             /* distance from 0, modulo 1         */          \
    PATTERN(LEOPARD, leopard, RAMP, 0, 1)         /* ((sin x + sin y + sin z) / 3)^2   */          \
    PATTERN(PLANAR, planar, RAMP, 0, 1)           /* 1 - |y|, 0 beyond 1               */          \
    PATTERN(BOXED, boxed, RAMP, 0, 1)             /* 1 - max |coordinate|, 0 beyond 1  */          \
    PATTERN(CYLINDRICAL, cylindrical, RAMP, 0, 1) /* 1 - distance from y, 0 beyond 1   */          \
    PATTERN(CRACKLE, crackle, RAMP, 1, 1)         /* Worley's cells                    */          \
    PATTERN(DENTS, dents, RAMP, 1, 1)             /* noise cubed                       */          \
    PATTERN(RIPPLES, ripples, RAMP, 0, 1)         /* cycloids of the distance to POV-Ray's
                                                     wave sources                      */          \
    PATTERN(WAVES, waves, RAMP, 0, 1)             /* ripples of their own frequencies  */          \
    PATTERN(QUILTED, quilted, RAMP, 0, 1)         /* a cubic of the distance from each
                                                     cell's centre                     */          \
    PATTERN(AVERAGE, average, RAMP, 0, 1)         /* no value (0): the pigment_map's
                                                     entries weighted by their values  */          \
    PATTERN(BRICK, brick, RAMP, 0, 1)             /* 0 in the mortar, 1 in a brick     */          \
    PATTERN(HEXAGON, hexagon, RAMP, 0, 1)         /* 0, 1 or 2: three hexagons in xz   */          \
    PATTERN(SPIRAL1, spiral1, TRIANGLE, 0, 1)     /* z + distance from z + arms * turn */          \
    PATTERN(SPIRAL2, spiral2, TRIANGLE, 0, 1)     /* spiral1's, triangled, plus the
                                                     distance's triangle               */          \
    PATTERN(PIGMENT_PATTERN, pigment_pattern, RAMP, 0, 1) /* its pigment's grey            */

/* Other keywords of a pattern above, ALIAS(word, ID): POV-Ray's spotted
 * and bumps are bozo's noise under another name (and, as pigments,
 * POV-Ray's black-to-white default map: csg/lang/texture.c). */
#define CSG_PATTERN_ALIASES(ALIAS) ALIAS(spotted, BOZO) ALIAS(bumps, BOZO)

/* Expansion helpers: the enum, a role left out, the count (no enumerator,
 * as for the waves). */
#define CSG_PATTERN_ENUM(ID, name, wave, noise, warp) CSG_PATTERN_##ID,
#define CSG_PATTERN_NONE(ID, name, wave, noise, warp)
#define CSG_PATTERN_ONE(ID, name, wave, noise, warp) +1
enum csg_pattern { CSG_PATTERNS(CSG_PATTERN_ENUM, CSG_PATTERN_ENUM) };
#define CSG_PATTERN_COUNT (0 CSG_PATTERNS(CSG_PATTERN_ONE, CSG_PATTERN_ONE))

/* The normals, X(ID, name): how a normal { } perturbs the surface normal
 * (POV-Ray's Perturb_Normal), CSG_NORMAL_<ID>, evaluated by normal_<name>
 * (workers/pigment.c).  PATTERN is any pattern of the table above, its
 * slope sampled at four points (POV-Ray's pyramid); the others are
 * POV-Ray's normal-only patterns, named by the pattern keyword they are
 * written with (bumps, dents, ripples, waves, wrinkles, quilted). */
#define CSG_NORMALS(X)                                                                             \
    X(PATTERN, pattern)   /* the pattern's slope                       */                         \
    X(BUMPS, bumps)       /* the vector noise (DNoise)                 */                         \
    X(DENTS, dents)       /* DNoise times noise cubed                  */                         \
    X(RIPPLES, ripples)   /* cycloids around the wave sources          */                         \
    X(WAVES, waves)       /* ripples of their own frequencies          */                         \
    X(WRINKLES, wrinkles) /* ten octaves of |DNoise|                   */                         \
    X(QUILTED, quilted)   /* a cubic of the distance to the cell centre */

/* The kinds of light_source (POV-Ray's Light_Type), as the scene and the
 * blob keep them (csg_light.kind, csg_flat_light.kind). */
enum csg_light_kind { CSG_LIGHT_POINT = 0, CSG_LIGHT_SPOT = 1, CSG_LIGHT_CYLINDER = 2 };

#define CSG_NORMAL_ENUM(ID, name) CSG_NORMAL_##ID,
#define CSG_NORMAL_ONE(ID, name) +1
enum csg_normal_kind { CSG_NORMALS(CSG_NORMAL_ENUM) };
#define CSG_NORMAL_COUNT (0 CSG_NORMALS(CSG_NORMAL_ONE))

#endif
