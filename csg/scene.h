/*
 * scene.h — the scene as the parser builds it: a tree of CSG objects with
 * their transforms and textures, in double precision, on the host only.
 *
 * Stages: csg_parse_file() (csg/lang/parser.c) fills a csg_scene; csg_flatten()
 * (csg/flatten.c) turns it into the flat arrays of flat.h in the chosen
 * precision.  Every object remembers where it was written so the stages
 * after parsing can still point at the source in their messages.
 *
 * Memory: all nodes, strings and arrays of one scene live in the scene's
 * arena and are freed together by csg_scene_free().
 */
#ifndef CSG_SCENE_H
#define CSG_SCENE_H

#include <stdbool.h>
#include <stddef.h>

#include "device/patterns.h"
#include "diag.h"

typedef struct {
    double x, y, z;
} dvec3;

/* An affine transform, object -> world: p' = m[0..2][0..2] p + m[0..2][3]. */
typedef struct {
    double m[3][4];
} csg_xform;

/* The table of object kinds, the one list every stage expands:
 *   LEAF(ID, name)  a shape (its parameters: csg_object below)
 *   CSG(ID, name)   an operator over the children
 * ID names the enum value CSG_OBJ_<ID>; `name` is the scene-language
 * keyword and the suffix of each stage's function for that kind:
 * flatten_<name> (csg/flatten.c), feature_<name> (csg/precision.c),
 * export_<name> (csg/export_pov.c).  Those stages dispatch by expanding
 * this list, so a kind added here and not handled there is a compile
 * error (an undeclared function), never a silent fallback.  The device
 * side has its own table of primitive kinds (device/flat.h): a shape may
 * become one of those (a cylinder is a cone) or several. */
#define CSG_OBJECT_KINDS(LEAF, CSG)         \
    LEAF(SPHERE, sphere)                    \
    LEAF(BOX, box)                          \
    LEAF(CYLINDER, cylinder)                \
    LEAF(CONE, cone)                        \
    LEAF(PLANE, plane)                      \
    LEAF(TORUS, torus)                      \
    LEAF(QUADRIC, quadric)                  \
    LEAF(POLY, poly)                        \
    LEAF(TRIANGLE, triangle)                \
    LEAF(SMOOTH_TRIANGLE, smooth_triangle)  \
    LEAF(POLYGON, polygon)                  \
    LEAF(MESH, mesh)                        \
    LEAF(PRISM, prism)                      \
    CSG(UNION, union)                       \
    CSG(INTERSECTION, intersection)         \
    CSG(DIFFERENCE, difference) /* first child minus every other child */ \
    CSG(MERGE, merge)

/* Expansion helpers for the table: the enum, and lists that skip a role. */
#define CSG_KIND_ENUM(ID, name) CSG_OBJ_##ID,
#define CSG_KIND_NONE(ID, name)

enum csg_object_kind { CSG_OBJECT_KINDS(CSG_KIND_ENUM, CSG_KIND_ENUM) CSG_OBJ_KIND_COUNT };

/* The keyword of a kind ("sphere", "union", ...); NULL out of range. */
const char *csg_object_kind_name(int kind);
/* The value at p of a poly of the given order and coefficients (csg_object:
 * POV-Ray's term order), and, unless grad is NULL, its gradient. */
double csg_poly_value(int order, const double *coef, dvec3 p, dvec3 *grad);
/* A shape (true) or an operator (false); false out of range. */
bool csg_object_is_leaf(int kind);

/* Pigment patterns and waves (POV-Ray 3.7's semantics, evaluated by the C
 * workers: workers/pigment.c): the pattern gives a value at a point of
 * pattern space, the wave shapes it, the colour map turns it into a
 * colour.  Both sets are the tables of device/patterns.h (enum csg_pattern,
 * enum csg_wave), whose ids the blob keeps as they are. */

/* The keyword of a pattern ("checker", ...; "plain" for a plain colour,
 * which has none) or of a wave without its "_wave" ("ramp", ...); NULL
 * out of range. */
const char *csg_pattern_name(int pattern);
const char *csg_wave_name(int wave);
/* POV-Ray's default wave of a pattern (ramp out of range). */
enum csg_wave csg_pattern_wave(enum csg_pattern pattern);
/* The pattern's value depends on the noise generator (false out of range). */
bool csg_pattern_reads_noise(enum csg_pattern pattern);
/* The entries a block pattern lists after its keyword, whose values are
 * their indices (POV-Ray's Parse_Blend_List: checker and brick 2, hexagon
 * 3); 0 for every other pattern. */
int csg_pattern_blocks(int pattern);

/* crackle's settings (POV-Ray's defaults: form <-1, 1, 0>, metric 2,
 * offset 0, not solid). */
typedef struct {
    dvec3 form;      /* weights of the distances to the 3 nearest points */
    double metric;   /* the distance's exponent                          */
    double offset;   /* added to every distance                          */
    bool solid;      /* each cell one noise value instead                */
} csg_crackle;

/* POV-Ray's classic turbulence of a pattern (turbulence, octaves, omega,
 * lambda): fractal noise that displaces the point (bozo, spotted, granite,
 * agate, checker, gradient) or that the pattern uses itself (wood,
 * marble, agate). */
typedef struct {
    bool on;         /* given (agate always has it)                 */
    dvec3 amount;    /* turbulence: 0 by default                    */
    int octaves;     /* 6 (1 to 10)                                 */
    double omega;    /* 0.5: each octave's weight, times the last   */
    double lambda;   /* 2: each octave's frequency, times the last  */
} csg_turb;

/* One entry of a colour map: from `value` on, the colour rgbft (POV-Ray
 * interpolates linearly between consecutive entries). */
typedef struct {
    double value;
    double rgbft[5];
} csg_map_entry;

#define CSG_MAP_MAX 256 /* entries of a colour map (POV-Ray's limit)     */

typedef struct csg_pigment_entry csg_pigment_entry;

/* POV-Ray's pigment: red, green, blue, filter, transmit, or a pattern
 * with its colour map or its pigment map. */
typedef struct csg_pigment {
    double rgbft[5];          /* the colour of a plain pigment              */
    enum csg_pattern pattern; /* device/patterns.h                          */
    dvec3 gradient;           /* gradient: its unit vector                  */
    double frequency, phase;  /* POV-Ray's wave: value * frequency + phase  */
    enum csg_wave wave;       /* device/patterns.h; exponent: poly_wave's   */
    double exponent;
    int noise_generator;      /* 1, 2 or 3; 0: the scene's (csg_noise_of)   */
    csg_turb turb;
    double agate_turb;        /* agate: the weight of its turbulence (1)    */
    csg_crackle crackle;
    double control0, control1; /* quilted: its cubic's controls (1, 1)      */
    dvec3 brick_size;         /* brick: a brick and its mortar (<8, 3, 4.5>) */
    double mortar;            /* brick: the mortar's width, POV-Ray's float
                                 of the given less 2e-10 (0.5f)             */
    int arms;                 /* spiral1, spiral2: the number of arms       */
    const struct csg_pigment *pattern_pigment; /* pigment_pattern: the pigment
                                 whose grey is the value (the scene's arena) */
    csg_xform xform;          /* pattern space -> world (the pigment's own
                                 transforms, then those of the object after
                                 the pigment was given)                     */
    int map_count;            /* entries of map (checker: 2)                */
    const csg_map_entry *map; /* the scene's arena; shared, never written   */
    int pmap_count;           /* > 0: a pigment_map of so many entries, in
                                 place of the colour map                    */
    const csg_pigment_entry *pmap; /* the scene's arena, like map           */
} csg_pigment;

/* One entry of a pigment map: from `value` on, the pigment (evaluated at
 * the point of the pattern that holds the map: its transforms and
 * turbulence apply first, POV-Ray's Compute_Pigment). */
struct csg_pigment_entry {
    double value;
    csg_pigment pigment;
};

/* POV-Ray 3.7 finish; the defaults are POV-Ray's (csg_finish_default). */
typedef struct {
    double ambient[3];    /* 0.1                                     */
    double diffuse;       /* 0.6                                     */
    double brilliance;    /* 1: diffuse * cos^brilliance             */
    double specular;      /* 0 (Blinn highlight)                     */
    double roughness;     /* 0.05                                    */
    double phong;         /* 0                                       */
    double phong_size;    /* 40                                      */
    double metallic;      /* 0: highlights tinted by the pigment     */
    double crand;         /* 0: POV-Ray's graininess: each light's diffuse
                             term less a random fraction of it      */
    double reflection[3]; /* 0; reflection { MIN, MAX }: MAX          */
    /* POV-Ray's variable reflection (reflection { MIN [, MAX] fresnel
     * falloff exponent metallic }, reflection_exponent, conserve_energy):
     * read only when reflection_variable */
    bool reflection_variable;
    double reflection_min[3]; /* the reflection facing the ray          */
    double reflection_falloff; /* (1 - cos)^falloff blends MIN to MAX  */
    double reflection_exponent; /* the reflected colour ^ (1 / it)       */
    double reflection_metallic; /* the reflection tinted by the pigment  */
    bool reflection_fresnel;  /* MIN to MAX by the Fresnel reflectance   */
    bool conserve_energy;     /* what is reflected is not transmitted    */
    /* POV-Ray's iridescence, irid { amount thickness F turbulence V }: each
     * light's diffuse and highlights times 1 + amount cos(the film's phase
     * / the wavelength), colour by colour; single-precision values, as
     * POV-Ray keeps them (0: none) */
    double irid;
    double irid_thickness;
    double irid_turbulence;   /* V's x: the film's thickness varies by it */
} csg_finish;

/* POV-Ray's normal { }: a pattern that perturbs the surface normal
 * (Perturb_Normal): `kind` (device/patterns.h, CSG_NORMALS) says how;
 * CSG_NORMAL_PATTERN samples the slope of `pattern`'s value, the others
 * are POV-Ray's normal-only patterns.  `pattern` holds what every pattern
 * has (its transforms in xform, turbulence, frequency, phase, wave, noise
 * generator, quilted's controls); no colour map. */
typedef struct {
    bool on;             /* a normal was given                           */
    int kind;            /* enum csg_normal_kind                         */
    csg_pigment pattern; /* the pattern's fields                         */
    double amount;       /* bump_size (POV-Ray's default 0.5)            */
    double accuracy;     /* the pattern slope's sample distance (0.02)   */
    bool no_bump_scale;  /* the perturbation is not normalised on the way
                            into and out of pattern space                */
} csg_normal;

typedef struct csg_texture csg_texture;
typedef struct csg_texture_entry csg_texture_entry;

/* POV-Ray's texture: a plain texture (pigment, normal, finish), the top of
 * a list of layers (texture { } texture { }: `under` is the layer below,
 * the last written on top), or a texture_map (a pattern, in `pigment`'s
 * pattern fields, choosing between the textures of `tmap`).  The layers
 * and entries live in the scene's arena, shared, never written: a texture
 * is copied by value and a change copies what it changes. */
struct csg_texture {
    csg_pigment pigment;
    csg_finish finish;
    csg_normal normal;
    const csg_texture *under; /* the layer below (NULL: none)            */
    int tmap_count;           /* > 0: a texture_map of so many entries   */
    const csg_texture_entry *tmap;
};

/* One entry of a texture_map: from `value` on, the texture (evaluated at
 * the point of the map's pattern, after its transforms and turbulence). */
struct csg_texture_entry {
    double value;
    csg_texture texture;
};

typedef struct {
    double ior;           /* 1                                              */
    double fade_distance; /* light through the inside fades (0: none)       */
    double fade_power;
    double fade_color[3]; /* what is left far inside (0: black)             */
} csg_interior;

/* An edge of a prism's outline as a piece of its curve: the chord from
 * parameter u0 to u1 of the segment ((A u + B) u + C) u + D (a spline's:
 * POV-Ray's Compute_Prism coefficients; a glyph's Bezier, in the text's
 * units; x then y of the outline's plane), so that the side's normal can
 * be the curve's (Prism::Normal, TrueType's); u0 == u1: a straight edge
 * (a linear spline's, a glyph's line), whose chord is exact. */
typedef struct {
    double a[2], b[2], c[2], d[2];
    double u0, u1;
} csg_outline_curve;

typedef struct csg_object csg_object;
struct csg_object {
    enum csg_object_kind kind;
    csg_loc loc;          /* where the object's keyword was written          */
    /* Shape parameters, in object space (before `xform`):
     *   sphere:   centre a, radius r0
     *   box:      corners a, b
     *   cylinder: base a, cap b, radius r0
     *   cone:     base a, base radius r0, cap b, cap radius r1
     *   plane:    normal a, distance r0
     *   prism:    an outline in the xy plane extruded along z from r0 to
     *             r1 (r0 < r1), or swept from the apex (`conic`): POV-Ray's
     *             prism (its xz outline swept
     *             along y is this under the transform that swaps y and z,
     *             kept in xform) and each glyph of its text
     *   torus:    major radius r0, minor radius r1 (around the y axis)
     *   quadric:  coef[0..9] = A..J of A x^2 + B y^2 + C z^2 + D xy + E xz
     *             + F yz + G x + H y + I z + J (inside where <= 0)
     *   poly:     (quartic, cubic) poly_coef[0 .. terms) the coefficients
     *             of a polynomial of order poly_order in POV-Ray's term
     *             order (x^n, x^(n-1) y, x^(n-1) z, x^(n-1), x^(n-2) y^2,
     *             ..., the constant last), terms = (n+1)(n+2)(n+3)/6;
     *             inside where it is < 0                                 */
    dvec3 a, b;
    double r0, r1;
    double coef[10];
    const double *poly_coef;
    int poly_order;
    /*   triangle: verts[0..2]; smooth_triangle: verts[0..2], normals[0..2]
     *   polygon:  verts[0 .. vert_count)  (planar, simple, maybe concave)
     *   mesh:     triangle k is verts[3k .. 3k+2], vert_count = 3 * count;
     *             normals NULL, or 3 a triangle (all zero: a flat one)
     * Triangles, polygons and meshes are surfaces, not solids (flat.h says
     * what CSG makes of them); a mesh or polygon may become several
     * primitives.                                                       */
    dvec3 *verts;
    dvec3 *normals;
    const int *contour_ends; /* prism: its closed polylines are verts[0 ..
                                  contour_ends[0]), [contour_ends[0] ..
                                  contour_ends[1]), ... (x, y; z is 0)    */
    int contour_count;
    const csg_outline_curve *edge_curves; /* prism: edge_curves[i] is the
                                  edge from verts[i] to the next vertex of
                                  its polyline (the first after the last);
                                  NULL: every edge is straight            */
    const csg_loc *piece_locs; /* mesh: where each triangle was written (an
                                  NFF file's run of triangles), or NULL: loc */
    int vert_count;
    bool one_sided;       /* surfaces: the back is invisible to looking rays */
    bool open;            /* cylinder / cone: no caps                        */
    bool conic;           /* prism: conic_sweep (the outline scaled by the
                             height, from the apex at z = 0; r0 >= 0)     */
    bool inverse;         /* `inverse`: the complement of the solid          */
    bool no_shadow;
    int hollow;           /* hollow [BOOL]: 1 hollow, 2 `hollow off`; 0 not
                             said (inherited; not hollow at the top, as
                             POV-Ray): only fog cares (its inside)            */
    csg_xform xform;      /* object -> world, every transform applied        */
    int texture;          /* index into csg_scene.textures; -1: inherited    */
    int interior;         /* index into csg_scene.interiors; -1: inherited   */
    int interior_texture; /* 1 + index into csg_scene.textures: what a ray
                             meeting the surface from inside sees (POV-Ray's
                             interior_texture); 0: inherited, or none (so
                             that a zeroed object has none)               */
    csg_object **children; /* CSG operands, in source order                  */
    int child_count;
    /* POV-Ray's object modifiers clipped_by and bounded_by, their objects
     * under the object's transform like children (xform: their own then
     * the object's).  clipped_by: the object is what of it lies inside
     * every clip (POV-Ray's Point_In_Clip; also its inside, Inside_Object),
     * and the clips' own surfaces are never seen nor cast shadows.
     * bounded_by: a speed hint (Ray_In_Bound), kept for the exporter;
     * bound_is_clip: bounded_by { clipped_by } or clipped_by { bounded_by }
     * (POV-Ray's Bound == Clip): bounds is then clips itself.          */
    csg_object **clips;
    int clip_count;
    csg_object **bounds;
    int bound_count;
    bool bound_is_clip;
};

/* POV-Ray's camera types (csg/device/camera_lanes.h traces them). */
enum csg_projection {
    CSG_PROJ_PERSPECTIVE, CSG_PROJ_ORTHOGRAPHIC,
    CSG_PROJ_CYLINDER_1, CSG_PROJ_CYLINDER_2, CSG_PROJ_CYLINDER_3, CSG_PROJ_CYLINDER_4,
    CSG_PROJ_ULTRA_WIDE_ANGLE, CSG_PROJ_PANORAMIC, CSG_PROJ_SPHERICAL
};

typedef struct {
    int projection;       /* enum csg_projection                               */
    double angle;         /* POV-Ray's Angle, degrees (90): the cylinder and
                             ultra_wide_angle cameras' field (perspective and
                             orthographic turn it into direction's length) */
    double h_angle, v_angle; /* spherical: its fields of view (360, 180)     */
    dvec3 location;       /* camera vectors after POV-Ray's rules (camera_setup.c) */
    dvec3 direction;
    dvec3 right;
    dvec3 up;
    dvec3 sky;
    dvec3 look_at;        /* the last look_at (POV-Ray's default <0, 0, 1>):
                             orthographic sizes its view from it            */
    csg_loc loc;
} csg_camera_src;

typedef struct {
    dvec3 position;
    double color[3];
    bool shadowless;
    int kind;             /* enum csg_light_kind                            */
    bool parallel;        /* its rays parallel, along point_at - position   */
    dvec3 point_at;       /* spotlight, cylinder, parallel: <0, 0, 1> by default */
    double tightness;     /* spot/cylinder: the cosine's exponent (0)       */
    double radius;        /* spot: cos(radius angle); cylinder: the radius  */
    double falloff;       /* spot: cos(falloff angle); cylinder: the falloff */
    double fade_distance, fade_power; /* attenuation with distance (0: none) */
    bool area;            /* area_light: a grid of size1 x size2 points     */
    dvec3 axis1, axis2;
    int size1, size2;
    int adaptive;         /* area: subdivision levels always taken (100)    */
    bool jitter, circular, orient;
    bool media_attenuation; /* fog dims its shadow rays                      */
    csg_loc loc;
} csg_light;

/* POV-Ray's fog (a constant fog, or a ground fog whose density falls
 * with the height along `up` above `offset`). */
enum csg_fog_kind { CSG_FOG_CONSTANT = 1, CSG_FOG_GROUND = 2 };
#define CSG_FOG_MAX 8 /* fogs of a scene */
typedef struct {
    int kind;             /* enum csg_fog_kind                              */
    double distance;      /* where 1/e of the light is left                 */
    double rgbft[5];
    dvec3 up;             /* ground fog: unit vector                        */
    double offset, alt;   /* ground fog: its height and fall-off            */
    csg_turb turb;        /* turbulence of its density                      */
    double turb_depth;    /* 0.5                                            */
} csg_fog;

/* How global_settings' assumed_gamma was given (POV-Ray 3.7's working
 * gamma): not at all, as a number, or as the word srgb. */
enum csg_gamma_kind { CSG_GAMMA_UNSET = 0, CSG_GAMMA_POWER = 1, CSG_GAMMA_SRGB = 2 };

typedef struct {
    int gamma_kind;         /* enum csg_gamma_kind: the first assumed_gamma
                               counts, as in POV-Ray (a later one is
                               ignored)                               */
    double assumed_gamma;   /* CSG_GAMMA_POWER's exponent (> 0); 1 when
                               not given                              */
    int max_trace_level;    /* 5                                      */
    double adc_bailout;     /* 1/255                                  */
    double ambient_light[3]; /* 1                                     */
    int noise_generator;    /* 0 when not given: 2 (1 before #version 3.5) */
    int number_of_waves;    /* the wave sources of ripples and waves (10) */
    double irid_wavelength[3]; /* irid's wavelengths (<0.70, 0.52, 0.48>),
                                  single precision as POV-Ray's colours */
} csg_globals;

/* POV-Ray's sky_sphere: what a ray that leaves the scene sees, the
 * pigments evaluated at its direction (layered: the first written is the
 * top layer). */
#define CSG_SKY_MAX 8 /* pigments of a sky_sphere */
typedef struct {
    int count;                        /* 0: no sky sphere                  */
    csg_pigment pigments[CSG_SKY_MAX]; /* pattern space -> direction space:
                                         the sky's transforms included      */
    double emission[3];               /* 1 by default                      */
    csg_xform xform;                  /* the sky's transforms: the pigments
                                         are evaluated at the direction seen
                                         through its inverse, as POV-Ray    */
} csg_sky;

typedef struct csg_arena csg_arena;

/* A file the scene wrote (#fopen NAME "name" write|append ... #write):
 * kept in memory by the parse; a render writes it beside its output. */
typedef struct {
    const char *name;       /* relative, no '..', no empty component   */
    const char *data;       /* len bytes (the arena)                   */
    size_t len;
    bool append;            /* first opened with append: added to the end
                               of a file already there, not replacing it */
} csg_written_file;

typedef struct {
    csg_camera_src camera;
    bool has_camera;
    int width, height;      /* the image size the scene asks for; 0: none */
    double hither;          /* primary rays start this far along the view
                               direction (a near plane); 0: none          */
    double background[5];   /* rgbft; black when not given            */
    csg_sky sky;            /* sky_sphere (count 0: none)             */
    csg_fog fogs[CSG_FOG_MAX];
    int fog_count;
    double version;         /* #version at the end (3.7 unless set)     */
    bool version_implied;   /* a POV-Ray scene that read no #version (its
                               own or an include's): POV-Ray's
                               "effective" version is then 3.62
                               (csg_version_v37).  False for scenes made
                               otherwise (NFF, by hand): 3.7's rules */
    csg_globals globals;
    csg_light *lights;
    int light_count;
    csg_object **objects;   /* top-level objects, in source order      */
    int object_count;
    csg_texture *textures;  /* every texture an object uses            */
    int texture_count;
    csg_interior *interiors;
    int interior_count;
    const char *path;       /* the scene file as given                 */
    const csg_written_file *written; /* the files the scene wrote, in the
                               order first opened                      */
    int written_count;
    csg_arena *arena;       /* owns everything above                   */
} csg_scene;

void csg_pigment_default(csg_pigment *p); /* plain black, identity transform */
/* POV-Ray's integer form of a version: (int)(v * 100 + 0.5) (3.62 -> 362). */
int csg_version_int(double v);
/* POV-Ray 3.7's rules apply (its EffectiveLanguageVersion() >= 370): the
 * last #version read is 3.7 or more; a scene that read none is 3.62.
 * Before 3.7: no gamma handling unless assumed_gamma is given, a
 * transparent surface dims by POV-Ray 3.6's formula, the sky and the
 * background mix as they did. */
bool csg_version_v37(const csg_scene *s);
/* What the 8-bit output does with a scene's colours (POV-Ray 3.7's PNG,
 * its default File_Gamma, the sRGB curve): CSG_OUTPUT_SRGB (a linear
 * working space: the colour is encoded with the sRGB curve: assumed_gamma
 * 1, or none in a 3.7 scene), CSG_OUTPUT_POWER (assumed_gamma G: the
 * colour is decoded by the power G first, *gamma = G), CSG_OUTPUT_DIRECT
 * (the colour is the byte's fraction: assumed_gamma srgb, or a scene
 * before 3.7 without assumed_gamma, POV-Ray's legacy mode). */
int csg_output_gamma(const csg_scene *s, double *gamma);
/* The noise generator pigment `pig` of scene `s` uses: its own, or the
 * scene's global_settings one, or POV-Ray's default for the scene's
 * #version (1 before 3.5, then 2). */
int csg_noise_of(const csg_scene *s, const csg_pigment *pig);
void csg_finish_default(csg_finish *f);
void csg_normal_default(csg_normal *n); /* none: on = false, POV-Ray's defaults */
void csg_texture_default(csg_texture *t);
void csg_globals_default(csg_globals *g);
void csg_xform_identity(csg_xform *x);
/* out = a then b (b applied after a); out may alias either. */
void csg_xform_then(const csg_xform *a, const csg_xform *b, csg_xform *out);
/* The inverse of an affine transform; false when it is singular. */
bool csg_xform_invert(const csg_xform *x, csg_xform *inv);
/* Every entry of x finite (a product of accepted steps may overflow). */
bool csg_xform_finite(const csg_xform *x);
void csg_xform_translate(csg_xform *x, dvec3 t);
void csg_xform_scale(csg_xform *x, dvec3 s);
/* POV-Ray's rotate <a, b, c>: degrees about x, then y, then z. */
void csg_xform_rotate(csg_xform *x, dvec3 degrees);
/* x after the swap of y and z: a prism's frame (scene.h, csg_object)
 * from POV-Ray's (its outline in xz, swept along y) and back. */
void csg_prism_pov_frame(csg_xform *x);

/* The arena: every allocation of a scene, freed at once. */
csg_arena *csg_arena_new(void);
void *csg_arena_alloc(csg_arena *a, size_t size); /* zeroed; NULL when out of memory */
/* The arena takes block (malloc'd), freed with it; false (block not
 * taken) when out of memory. */
bool csg_arena_adopt(csg_arena *a, void *block);
void csg_arena_free(csg_arena *a);

/* Where piece `piece` of o was written (csg_object.piece_locs), else o's. */
csg_loc csg_piece_loc(const csg_object *o, int piece);

void csg_scene_init(csg_scene *s);
void csg_scene_free(csg_scene *s);

#endif
