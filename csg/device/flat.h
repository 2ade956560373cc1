/*
 * flat.h — the flat scene: plain arrays of fixed-width scalars, no pointers.
 *
 * This is what crosses every boundary: it is broadcast to the MPI workers
 * as bytes and uploaded to the OpenCL device as buffers.  The same struct
 * definitions compile as C11 and OpenCL C (see portable.h): every field is a
 * fixed-width integer (csg_i32, csg_u32, csg_u64) or `real`, integers first
 * and each run of fields a multiple of the next one's alignment, so there
 * is no padding and the layout is identical on both sides
 * (CSG_LAYOUT_FIELDS at the end; tests/test_layout checks it on PoCL).
 *
 * The CSG tree of a scene becomes a list of roots.  Each root is a small
 * program in reverse Polish notation over the node array: OP_PRIM pushes the
 * interval list of one primitive, OP_UNION / OP_INTERSECT pop two and push
 * their combination.  Differences and `inverse` were pushed down to the
 * leaves by the flattener (A - B = A ∩ ¬B, De Morgan), so a primitive may be
 * complemented (CSG_PF_INVERT) but no other set operator exists.  POV-Ray's
 * clipped_by is an intersection whose clip primitives have no surface
 * (CSG_PF_CLIP); its bounded_by gates a list's surfaces (CSG_OP_BOUND).
 */
#ifndef CSG_FLAT_H
#define CSG_FLAT_H

#include "patterns.h"
#include "portable.h"

/* The table of primitive kinds the tracers know, X(ID, name), in the
 * order of their values in a blob.  intersect.h dispatches through
 * csg_<name>_span and csg_<name>_normal and the blob validator accepts
 * exactly these kinds, so a kind added here without its functions is a
 * compile error on both sides (C and OpenCL C), never a silent fallback.
 * Parameters p[] of each kind:
 *   sphere  p[0..2] centre, p[3] radius
 *   box     p[0..2] min corner, p[3..5] max corner
 *   cone    local frame: axis +z from z=0 to z=p[2]; p[0] radius at z=0,
 *           p[1] radius at z=p[2]; a cylinder is a cone with p[0] == p[1]
 *   plane   p[0..2] unit normal, p[3] distance: inside is dot(n, x) < d
 *   trapezoid  one convex piece of an extruded outline (a prism, a glyph
 *           of text: csg/extrude.h splits the outline): always under
 *           CSG_PF_XFORM, in a local frame where the extrusion runs from
 *           z = 0 to z = 1; inside is n_a . (x, y) >= c_a, n_b . (x, y)
 *           >= c_b (the two sides, unit normals pointing in: p[0..2] and
 *           p[3..5] = n.x, n.y, c), p[6] <= y <= p[7] and 0 <= z <= 1.
 *           The pieces of one outline share the very same side lines and
 *           slab heights, so a ray leaves one where it enters the next at
 *           the same t, and their union merges them exactly.  A piece whose
 *           sides are chords of a curve (a prism's spline, a glyph's
 *           Bezier) keeps the curve in the curve table (csg_curve,
 *           CSG_PRIM_CURVE: its flags), for its shading normal
 *   conic_trapezoid  the same piece of a prism's conic_sweep: the outline
 *           scaled by the height, the apex at the origin, in a frame
 *           scaled so the top is z = 1: inside is x >= p[0] y + p[1] z,
 *           x <= p[2] y + p[3] z, p[4] z <= y <= p[5] z, p[6] <= z <= 1
 *           (every wall a plane through the apex: a convex piece); its
 *           curve as a trapezoid's
 *   torus   local frame: the ring in the xz plane around +y (POV-Ray's);
 *           p[0] major radius R, p[1] minor radius r, p[2] the piece, 0 or
 *           1: the first or the second interval of the line inside the
 *           torus (the flattener emits both pieces, joined by union, and
 *           never a piece alone as a root: see below)
 *   quadric in world space (never CSG_PF_XFORM: the flattener transforms
 *           the quadric itself, as POV-Ray does): p[0..9] the coefficients
 *           A..J of A x^2 + B y^2 + C z^2 + D xy + E xz + F yz + G x + H y
 *           + I z + J, inside where it is <= 0 (POV-Ray's); p[10] the
 *           piece, 0 or 1, as the torus's (a line meets it in at most two
 *           intervals, the outer ones maybe unbounded)
 *   poly    POV-Ray's poly (quartic, cubic): a polynomial of order p[0]
 *           (2 .. CSG_POLY_ORDER_MAX) in x, y, z in its local frame
 *           (CSG_PF_XFORM when transformed), inside where it is < 0; p[1]
 *           the piece, 0 .. p[0] / 2 (a line meets it in at most p[0] / 2
 *           + 1 intervals, the outer ones maybe unbounded); its
 *           coefficients are (p[0] + 1)(p[0] + 2)(p[0] + 3) / 6 reals in
 *           the blob's coefficient table, POV-Ray's term order (x^n, x^(n-1)
 *           y, x^(n-1) z, x^(n-1), ..., the constant last): p[2] * 4096 +
 *           p[3] reals on from p itself (csg_poly_coefs; the flattener
 *           writes that offset, the blob validator checks that it lands in
 *           the table, flat.h's blob section below)
 *   triangle         p[0..2], p[3..5], p[6..8] the vertices v0, v1, v2 in
 *                    world space (never CSG_PF_XFORM); its front is the
 *                    side (v1 - v0) x (v2 - v0) points to
 *   smooth_triangle  the same, and p[9..11], p[12..14], p[15..17] the
 *                    vertex normals n0, n1, n2, interpolated at the hit
 *   flat_box         a box (the same p[0..5]) with lo == hi on at least one
 *                    axis: a sheet with no inside, seen from both sides, as
 *                    POV-Ray renders a box of zero thickness; its crossing
 *                    is on the face of its (first) flat axis that looks at
 *                    the ray
 * p[] is a payload of CSG_PRIM_REALS reals; a kind under a transform
 * (CSG_PF_XFORM) keeps its world -> local matrix in the last 12, named
 * inv[] (so such a kind has p[0..7] for itself).
 *
 * The one assumption every stage shares lives in csg_<name>_span: a
 * primitive is a convex solid, so the line of a ray meets it in AT MOST
 * ONE interval [t0, t1] with t0 < t1 (a plane: a half-line); the interval
 * lists (intersect.h), the complement, the shadow test and the flattener's
 * CSG_MAX_SPANS bound all build on it.  A primitive that breaks it must
 * say how it fits:
 *   - non-convex (a torus): split it into pieces joined by union in the
 *     flattener, each leaf still giving one interval; a torus's piece k
 *     is the k-th interval of the line inside the whole torus (a line
 *     meets a torus in at most two), so the union of its pieces is the
 *     torus and their complements' intersection its complement.  A
 *     torus root is therefore always a CSG program, which the packet
 *     kernel evaluates through the one-ray code (packet.h): the torus
 *     test exists for one ray only (its root solver, poly_solve.h, is
 *     not lane-generic);
 *   - not a solid (a triangle, a polygon, an open mesh: surfaces with no
 *     inside): it has no interval at all.  Those are CSG_SURFACE_KINDS:
 *     their csg_<name>_span reports a crossing of the surface as t0 == t1
 *     (s0 == s1 its side), which the interval lists carry as a zero-length
 *     EVENT beside their intervals (intersect.h), never as an interval.
 *     CSG follows POV-Ray's meaning, a surface having no inside: its
 *     solid set is empty (the complement: the whole line), and an event
 *     survives a union where it is not strictly inside the other operand
 *     (like merge: the renderer evaluates nested unions as solids) and an
 *     intersection where it is inside the other operand's closed set.  So
 *     intersection { triangle sphere } is the part of the triangle inside
 *     the sphere, difference { triangle sphere } the part outside, and
 *     difference { sphere triangle } the whole sphere (tests/test_csg.c).
 *     A box of zero thickness is such a surface (flat_box): POV-Ray's own
 *     box test accepts an entry equal to the exit, and its inside test,
 *     closed, holds nothing but the sheet itself. */
#define CSG_SOLID_KINDS(X)                                                                         \
    X(SPHERE, sphere) X(BOX, box) X(CONE, cone) X(PLANE, plane) X(TRAPEZOID, trapezoid)      \
        X(CONIC_TRAPEZOID, conic_trapezoid) X(TORUS, torus) X(QUADRIC, quadric)    \
        X(POLY, poly)
#define CSG_SURFACE_KINDS(X)                                                                       \
    X(TRIANGLE, triangle) X(SMOOTH_TRIANGLE, smooth_triangle) X(FLAT_BOX, flat_box)
#define CSG_PRIM_KINDS(X) CSG_SOLID_KINDS(X) CSG_SURFACE_KINDS(X)

/* What this compilation handles of the table and of the CSG machinery
 * (all of it unless an OpenCL program is specialised on a scene). */
#include "spec.h"

#define CSG_PRIM_ENUM(ID, name) CSG_PRIM_##ID,
enum csg_prim_kind { CSG_PRIM_KINDS(CSG_PRIM_ENUM) CSG_PRIM_KIND_COUNT };

/* Surface kinds come after every solid kind. */
#define CSG_PRIM_COUNT_ONE(ID, name) +1
#define CSG_PRIM_FIRST_SURFACE (0 CSG_SOLID_KINDS(CSG_PRIM_COUNT_ONE))
#define CSG_PRIM_IS_SURFACE(kind) ((kind) >= CSG_PRIM_FIRST_SURFACE)
/* Some surface kind is compiled in (spec.h). */
#define CSG_PRIM_USE_OR(ID, name) || CSG_USES_KIND(ID)
#define CSG_USE_SURFACES (0 CSG_SURFACE_KINDS(CSG_PRIM_USE_OR))

enum csg_prim_flags {
    CSG_PF_XFORM = 1,     /* inv[] maps world to local coordinates           */
    CSG_PF_OPEN = 2,      /* cone/cylinder without caps: caps are invisible  */
    CSG_PF_INVERT = 4,    /* the leaf is complemented (inverse, difference)  */
    CSG_PF_NO_SHADOW = 8, /* casts no shadow                                 */
    CSG_PF_ONE_SIDED = 16, /* surface kinds: the back is invisible to the rays
                             that look (primary, reflected, refracted); it
                             still casts shadows (CSG_SURF_HIDDEN)          */
    CSG_PF_HOLLOW = 32,   /* hollow: fog fills its inside (C workers only)  */
    CSG_PF_CLIP = 64,     /* a clipped_by object's: its solid cuts the
                             object, its surfaces are never intersections
                             (CSG_SURF_NONE: no ray sees them or stops on
                             them; csg/flatten.c, emit_tree)            */
    CSG_PF_BOUND = 128    /* a bounded_by object's (CSG_OP_BOUND): its list
                             is evaluated on [tmin, inf)                 */
};

/* The bits of csg_prim.flags above the flags: a trapezoid piece whose
 * sides are chords of a prism's spline (csg_curve) keeps 1 + the index
 * of its curve in the blob's curve table there; 0: no curve. */
#define CSG_PF_CURVE_SHIFT 8
#define CSG_CURVE_MAX ((1 << 23) - 1) /* curves a blob may have (flags stay >= 0) */
#define CSG_PRIM_CURVE(p) ((csg_i32)((p)->flags >> CSG_PF_CURVE_SHIFT) - 1)

/* Surface sub-indices, per kind. */
enum csg_surface {
    CSG_SURF_SPHERE = 0,
    CSG_SURF_BOX_NEG_X = 0, /* box faces: 2*axis + (1 if the + face)         */
    CSG_SURF_CONE_SIDE = 0,
    CSG_SURF_CONE_BASE = 1, /* the z = 0 cap                                 */
    CSG_SURF_CONE_TOP = 2,  /* the z = h cap                                 */
    CSG_SURF_PLANE = 0,
    CSG_SURF_TRAP_SIDE_A = 0, /* trapezoid: its two sides, then 2 + the face
                                 of the y slab, 4 + the face of the z slab,
                                 as a box's faces (2 * axis + (1 if +))    */
    CSG_SURF_TRAP_SIDE_B = 1,
    CSG_SURF_TORUS = 0,
    CSG_SURF_QUADRIC = 0,
    CSG_SURF_POLY = 0,
    CSG_SURF_TRI_FRONT = 0, /* triangles: the ray meets the front side       */
    CSG_SURF_TRI_BACK = 1,  /* ... the back side                             */
    CSG_SURF_HIDDEN = 7     /* any kind: a surface that blocks light but that
                               no looking ray sees (a one-sided back)        */
};

#define CSG_PRIM_REALS 20 /* the payload of a primitive */
#define CSG_POLY_ORDER_MAX 7 /* a poly's order, at most (POV-Ray's samples: 3 to 5) */
#define CSG_POLY_OFFSET_UNIT 4096 /* a poly's offset to its coefficients is
                                     p[2] * this + p[3]: two reals, each an
                                     integer exact in float            */

typedef struct {
    csg_i32 kind;     /* enum csg_prim_kind                               */
    csg_i32 flags;    /* enum csg_prim_flags                              */
    csg_i32 material; /* index into the material table (host side only)   */
    csg_i32 root;     /* the root (top-level object) this primitive is in */
    union {           /* the payload, read per kind (CSG_PRIM_KINDS above) */
        real p[CSG_PRIM_REALS];
        struct {
            real p_own[8]; /* p[0..7]: a transformed kind's own parameters */
            real inv[12];  /* world -> local, row-major 3x4: l = M[:, 0:3] w + M[:, 3] */
        };
    };
} csg_prim;

/* One side of a trapezoid piece as a piece of its curve (a prism's
 * spline, a glyph's Bezier): the side's chord runs from parameter u0 to
 * u1 of the segment ((A u + B) u + C) u + D (POV-Ray's Compute_Prism
 * coefficients, a glyph's Bezier in the power basis; x then y of the
 * outline's plane, the piece's local x and y).  The piece's surface is the
 * chord's plane (so hits and the CSG are those of the chords), but its
 * shading normal is the curve's where the ray meets the curve, as
 * POV-Ray's Prism::Normal (intersect.h: csg_surface_shading_normal).
 * u0 == u1: a straight side, the chord's own normal. */
typedef struct {
    real a[2], b[2], c[2], d[2];
    real u0, u1;
} csg_curve_side;

/* The curve of a trapezoid piece (CSG_PRIM_CURVE): its two sides, as the
 * piece's (CSG_SURF_TRAP_SIDE_A, _B). */
typedef struct {
    csg_curve_side side[2];
} csg_curve;

/* CSG_OP_WIDE marks a wide run: the nodes after it are pair_count pairs
 * (PRIM p_j, OP) with one OP, folding p_0, p_1, ... into the list on top
 * of the stack, each p_j a leaf that is the identity of OP when the ray
 * misses its box: complemented under INTERSECT (the whole line), plain
 * under UNION (nothing).  The run's own BVH (csg_wide) finds the leaves a
 * ray meets; folding only those, in the run's order, gives the very same
 * list (the other steps copy it unchanged: csg_spans_union and
 * csg_spans_intersect with an identity operand push the same spans and
 * events).  The evaluator may also skip the marker and fold the pairs one
 * by one, as without it (issue #39). */
/* CSG_OP_BOUND pops a bound's list B and gates the list A below it, POV-Ray's
 * Ray_In_Bound for an object with bounded_by: A keeps its solid, and its
 * surfaces only when the ray meets the bound or starts inside it, i.e.
 * when B, evaluated on [tmin, inf) whatever the query's tmax (its
 * primitives carry CSG_PF_BOUND), has a surface (the cut of the bound's
 * own clip is none) or starts at tmin; else every boundary of A becomes
 * CSG_SURF_NONE (intersect.h, csg_spans_met, csg_spans_gate). */
enum csg_op {
    CSG_OP_PRIM = 0, CSG_OP_UNION = 1, CSG_OP_INTERSECT = 2, CSG_OP_WIDE = 3, CSG_OP_BOUND = 4
};

typedef struct {
    csg_i32 op;   /* enum csg_op                                 */
    csg_i32 prim; /* primitive index, for CSG_OP_PRIM; the wide run
                     (csg_wide), for CSG_OP_WIDE; else -1        */
} csg_node;

/* A wide run's hierarchy: nodes wide_bvh[bvh_first .. + bvh_count) laid
 * out as the root BVH's (pairs of siblings, children after their parent,
 * bvh_first and bvh_first + 1 the top pair), their child and leaf indices
 * absolute; a leaf holds wide_items[first .. + count), each the index j of
 * a pair of the run (0 .. pair_count - 1), its box that of p_j's
 * primitive (uncomplemented). */
typedef struct {
    csg_i32 pair_count;
    csg_i32 bvh_first;
    csg_i32 bvh_count;
    csg_i32 item_first; /* the run's items: wide_items[item_first .. + pair_count) */
} csg_wide;

#define CSG_WIDE_MIN 16  /* the flattener marks runs of at least this many pairs */
#define CSG_WIDE_HITS 128 /* a ray meeting more leaves of a run folds them all,
                            one by one (the result is the same)              */

/* What shadow rays may skip in a root (csg_root.flags): a root whose
 * primitives are all no_shadow casts no shadow; one whose primitives all
 * cast shadows and are all opaque (no filter, no transmit) blocks the
 * light at its first visible boundary, so a shadow ray needs only that
 * (any-hit), not the whole interval list. */
enum csg_root_flags {
    CSG_ROOT_NO_SHADOW = 1,
    CSG_ROOT_OPAQUE = 2
};

typedef struct {
    csg_i32 first_node; /* its program: nodes[first_node .. +node_count) */
    csg_i32 node_count;
    csg_i32 stack_depth; /* span lists its program needs at once       */
    csg_i32 flags;       /* enum csg_root_flags                          */
    real lo[3];          /* world bounding box; +-inf when unbounded      */
    real hi[3];
} csg_root;

/* A bounding volume hierarchy over the bounded roots (unbounded ones, such
 * as planes, are tested one by one before it), built by binned SAH
 * (csg/flatten.c).  Nodes come in pairs of siblings, stored side by side
 * so that a walk tests both boxes at once (64 bytes in float: one cache
 * line): nodes 0 and 1 are the top pair (the whole tree's own box is never
 * needed), and an interior node's children are nodes first and first + 1,
 * both after it.  A leaf holds roots first .. first + count - 1; count 0
 * is the empty leaf that completes the top pair when the whole tree is one
 * leaf (its box is empty: lo = +inf, hi = -inf, which no ray meets).
 * In float a node is 32 bytes, a pair one 64-byte cache line. */
typedef struct {
    csg_i32 first; /* leaf: first root; interior: index of the first child   */
    csg_i32 count; /* leaf: number of roots (>= 0); interior: -1 - split axis */
    real box[6];   /* lo x, y, z, then hi x, y, z: one array, so that a walk
                      picks each axis' near and far plane by index
                      (csg_box_ray.near_i, far_i in intersect.h)           */
} csg_bvh_node;

#define CSG_BVH_STACK 64 /* the flattener keeps the tree shallower than this */

/* The camera's projection (csg_camera.projection): POV-Ray's types, in
 * the order of csg/scene.h's enum csg_projection. */
enum csg_camera_projection {
    CSG_CAMERA_PERSPECTIVE = 0, CSG_CAMERA_ORTHOGRAPHIC = 1,
    CSG_CAMERA_CYLINDER_1 = 2, CSG_CAMERA_CYLINDER_2 = 3, CSG_CAMERA_CYLINDER_3 = 4,
    CSG_CAMERA_CYLINDER_4 = 5, CSG_CAMERA_ULTRA_WIDE_ANGLE = 6, CSG_CAMERA_PANORAMIC = 7,
    CSG_CAMERA_SPHERICAL = 8,
    CSG_CAMERA_PROJECTIONS = 9
};

/* The camera after POV-Ray's camera statement was applied (see
 * csg/camera_setup.c): the primary ray of pixel (x, y) of a W x H image is
 * direction + x0 * right + y0 * up, normalised, from location
 * (perspective), or direction, normalised, from location + x0 * right +
 * y0 * up (orthographic); camera.h. */
typedef struct {
    csg_i32 projection; /* enum csg_camera_projection                   */
    csg_i32 pad;
    real location[3];
    real direction[3];
    real right[3];
    real up[3];
    real hither;  /* > 0: rays start on the near plane this far along the
                     view direction (NFF's hither); 0: at location        */
    real kx, ky;  /* the other cameras: what x0 and y0 (-0.5 .. 0.5) are
                     multiplied by (an angle's radians, or a length);
                     their direction, right and up are unit vectors but
                     for the panoramic and spherical cameras' (POV-Ray's
                     SetupCamera): camera_lanes.h                        */
} csg_camera;

/* What becomes of a pixel's colour on its way to an 8-bit file (POV-Ray
 * 3.7's gamma handling, csg_shading.output; csg/scene.h,
 * csg_output_gamma): the workers store the linear value whose sRGB byte
 * (comm/pixels.h) is POV-Ray's (comm/pixels.h, pixels_scene_linear). */
enum csg_output_gamma {
    CSG_OUTPUT_SRGB = 0,  /* the colour is linear: stored as it is        */
    CSG_OUTPUT_POWER = 1, /* assumed_gamma G: colour^G                    */
    CSG_OUTPUT_DIRECT = 2 /* the colour is the byte's fraction (POV-Ray's
                             legacy mode, assumed_gamma srgb)             */
};

/* One fog of the scene (POV-Ray's FOG): C workers only. */
typedef struct {
    csg_i32 kind;          /* 1 constant, 2 ground (csg/scene.h, enum csg_fog_kind) */
    csg_i32 turb_on;       /* its turbulence given (1) or not (0)       */
    csg_i32 octaves;
    csg_i32 noise_gen;     /* the scene's noise generator (1 to 3)      */
    real distance;
    real rgbft[5];
    real up[3];            /* ground fog: unit vector                   */
    real offset, alt;
    real turbulence[3];
    real omega, lambda, turb_depth;
} csg_flat_fog;

#define CSG_FLAT_FOGS 8 /* fogs of a scene (csg/scene.h: CSG_FOG_MAX) */

/* The scene-wide shading values (global_settings, background, the
 * sky_sphere, the fogs): C workers only, like the materials and the
 * lights.  Integers first: their offsets are the same in both precisions
 * (host/feed.c reads fog_count from a blob of either). */
typedef struct {
    csg_i32 sky_first;     /* the sky_sphere's pigments: materials
                              sky_first .. + header.sky_count            */
    csg_i32 sky_v37;       /* POV-Ray 3.7's rules (1: the scene's last
                              #version is 3.7 or more): its mix of sky and
                              background, a transparent surface's
                              opacity; 0: those before 3.7              */
    csg_i32 max_rays;      /* reflected and refracted rays a pixel may
                              trace (>= 1); the rest are not traced      */
    csg_i32 output;        /* enum csg_output_gamma                      */
    csg_i32 fog_count;     /* fogs[0 .. fog_count) (<= CSG_FLAT_FOGS)   */
    csg_i32 camera_solid;  /* non-hollow objects around the camera: no fog
                              on the primary rays while > 0             */
    csg_i32 noise_gen;     /* the scene's noise generator (irid's)     */
    csg_i32 pad;
    real output_gamma;     /* CSG_OUTPUT_POWER's G (1 otherwise)        */
    real background[3];    /* what a ray that hits nothing sees (with the
                              sky: behind it)                            */
    real ambient_light[3];
    real adc_bailout;      /* rays weighing less are not traced        */
    real sky_emission[3];
    real irid_wavelength[3]; /* irid's wavelengths, red, green, blue     */
    csg_flat_fog fogs[CSG_FLAT_FOGS];
} csg_shading;

/* One entry of a colour map (the blob's maps array). */
typedef struct {
    real value;
    real rgbft[5];
} csg_map_color;

/* Shading data, used by the C workers only (the kernel never reads it). */
typedef struct {
    csg_i32 pattern;    /* enum csg_pattern (patterns.h)                 */
    csg_i32 map_first;  /* its colour map: maps[map_first .. + map_count) */
    csg_i32 map_count;
    csg_i32 pad;
    real color[3];      /* pigment rgb (CSG_PATTERN_PLAIN)              */
    real filter;        /* pigment filter: light through, tinted         */
    real transmit;      /* pigment transmit: light through, untinted     */
    real ambient[3];
    real diffuse;
    real brilliance;    /* diffuse * cos^brilliance (POV-Ray's)          */
    real specular;      /* Blinn highlight strength                      */
    real roughness;     /* Blinn exponent is 1 / roughness               */
    real phong;
    real phong_size;
    real metallic;      /* highlights tinted by the pigment (POV-Ray's)  */
    real reflection[3];
    real ior;           /* interior: index of refraction                 */
    real gradient[3];   /* CSG_PATTERN_GRADIENT: unit vector             */
    real frequency;     /* POV-Ray's wave: value * frequency + phase     */
    real phase;
    real to_pattern[12]; /* world -> pattern space, row-major 3x4 like
                            csg_prim.inv                                  */
    csg_i32 wave;       /* enum csg_wave (patterns.h)                    */
    csg_i32 noise_gen;  /* POV-Ray's noise generator: 1, 2 or 3         */
    csg_i32 turb_on;    /* classic turbulence given (1) or not (0)       */
    csg_i32 octaves;    /* turbulence: 1 to 10                           */
    real turbulence[3]; /* its amount along x, y, z                      */
    real omega, lambda; /* each octave's weight and frequency factors    */
    real agate_turb;    /* agate: its turbulence's weight                */
    real exponent;      /* poly_wave                                     */
    real crackle_form[3]; /* crackle: its form, metric and offset, and     */
    real crackle_metric, crackle_offset;
    csg_i32 crackle_solid; /* solid (1) or not (0)                          */
    csg_i32 sub_first;  /* > 0: a pigment map: its entries' pigments are
                           materials sub_first .. + map_count (after this
                           one), the maps entries hold their values; 0: a
                           colour map.  With tmap: the entries' textures */
    csg_i32 tmap;       /* 1: a texture_map: the pattern above chooses
                           between the textures sub_first .. + map_count
                           (each a top layer); its own pigment, finish and
                           layers are not used                           */
    csg_i32 under;      /* > 0: a layered texture: the layer below this one
                           is material under - 1; 0: none               */
    csg_i32 normal;     /* > 0: this layer's normal is material normal - 1
                           (its pattern fields and the ones below); 0: none */
    csg_i32 normal_kind; /* a normal's enum csg_normal_kind (patterns.h) */
    csg_i32 no_bump_scale; /* a normal: not normalised through its space  */
    csg_i32 number_of_waves; /* ripples and waves: the wave sources (10)  */
    real bump_size;     /* a normal's amount                             */
    real accuracy;      /* a pattern normal's sample distance            */
    real quilt_control[2]; /* quilted: control0, control1                */
    real from_pattern[9]; /* pattern -> world, the 3x3 part (row-major):
                           the inverse of to_pattern's, for a normal       */
    real fade_distance; /* interior: light through the inside fades (0: no) */
    real fade_power;
    real fade_color[3];
    /* POV-Ray's variable reflection (csg_finish; workers/shade.c):
     * reflection is MAX, used alone when reflection_variable is 0 */
    csg_i32 reflection_variable;
    csg_i32 reflection_fresnel;
    csg_i32 conserve_energy;
    csg_i32 pad2;
    real reflection_min[3];
    real reflection_falloff;
    real reflection_exponent;
    real reflection_metallic;
    real crand;         /* POV-Ray's graininess (0: none; shade.c)       */
    csg_i32 spiral_arms; /* spiral1, spiral2: the number of arms         */
    csg_i32 pattern_pigment; /* pigment_pattern: the material of its pigment
                           (after this one); 0: none                     */
    real brick_size[3]; /* brick: a brick's size along x, y, z           */
    real mortar;        /* brick: the mortar's width                     */
    real irid;          /* iridescence (csg_finish; 0: none)             */
    real irid_thickness;
    real irid_turbulence;
    csg_i32 inside;     /* > 0: where a ray meets the surface from inside
                           (its primitive's own normal against the ray),
                           material inside - 1 is seen (POV-Ray's
                           interior_texture); 0: none                    */
    csg_i32 pad3;
} csg_material;

/* A light (POV-Ray's LightSource): the C workers, and the device's shadow
 * answers (csg/device/shadow.h: position, kind, the flags, direction,
 * point_at). */
typedef struct {
    real position[3];
    real color[3];
    csg_i32 shadowless;
    csg_i32 kind;          /* 0 point, 1 spot, 2 cylinder (csg/scene.h)  */
    csg_i32 parallel;
    csg_i32 area;          /* an area light: size1 x size2 points        */
    csg_i32 size1, size2;
    csg_i32 adaptive, jitter, circular, orient;
    csg_i32 media_attenuation; /* fog dims its shadow rays               */
    csg_i32 pad;
    real direction[3];     /* unit, point_at - position (0: none)        */
    real point_at[3];
    real tightness, radius, falloff; /* spot: cosines; cylinder: lengths */
    real fade_distance, fade_power;
    real axis1[3], axis2[3];
} csg_flat_light;

/* A packed surface id: 0 means "no visible surface" (a clipping boundary or
 * the cap of an open cylinder); otherwise
 *   ((primitive + 1) << 4) | (sub-surface << 1) | flip
 * where flip says the outward normal of the solid is the primitive's normal
 * reversed (the surface bounds a complemented primitive). */
#define CSG_SURF_NONE 0u
#define CSG_SURF_PACK(prim, sub, flip) \
    ((((csg_u32)(prim) + 1u) << 4) | ((csg_u32)(sub) << 1) | (csg_u32)(flip))
#define CSG_SURF_PRIM(s) ((csg_i32)((s) >> 4) - 1)
#define CSG_SURF_SUB(s) ((csg_i32)(((s) >> 1) & 7u))
#define CSG_SURF_FLIP(s) ((s) & 1u)
#define CSG_MAX_PRIMS ((1 << 27) - 1)

/* Limits of the CSG evaluator; the flattener rejects scenes beyond them. */
#define CSG_MAX_SPANS 16 /* intervals in one list along one ray   */
#define CSG_MAX_EVENTS 8 /* surface crossings in one list         */
#define CSG_STACK_MAX 8  /* interval lists alive at once          */

/* ---- the blob ----------------------------------------------------------------
 * The flat scene travels as one contiguous blob: this header, then every
 * array at the byte offset the header records (64-byte aligned), in the
 * precision real_size says.  csg/flatten.c writes it, csg/blob.c validates
 * it (the only code that knows the sizes: sizeof, compiled per precision),
 * and the kernel and the workers find their arrays through the header
 * (csg_blob_view in intersect.h).  Integers only, so OpenCL C reads it as
 * it is, whatever the precision. */
#define CSG_BLOB_MAGIC 0x43534733u /* "CSG3" */

/* What a scene uses beyond its primitive kinds (csg_blob_header.features;
 * the kinds are csg_blob_header.kinds, bit 1 << kind).  The flattener
 * records them and the blob validator recomputes them from the arrays and
 * rejects a header that disagrees, so code specialised on a feature set
 * (the OpenCL program: host/pass/ocl.c, features.h) never meets a scene
 * outside it.  A set bit says "some of the scene uses it". */
enum csg_feature {
    CSG_FEAT_CSG = 1,         /* a root needs interval lists: a program of
                                 several nodes, or a complemented leaf     */
    CSG_FEAT_XFORM = 2,       /* a primitive has a transform (CSG_PF_XFORM) */
    CSG_FEAT_REFLECT = 4,     /* a material reflects                       */
    CSG_FEAT_TRANSPARENT = 8, /* a material lets light through (filter or
                                 transmit, in its pigment or colour map)   */
    CSG_FEAT_NO_SHADOW = 16,  /* a primitive casts no shadow               */
    CSG_FEAT_SHADOWLESS = 32, /* a light is shadowless                     */
    CSG_FEAT_ALL = 63
};
#define CSG_MAX_SPP 1024           /* samples a pixel, at most */
#define CSG_MAX_WAVES 100000       /* number_of_waves, at most     */

typedef struct {
    csg_u32 magic;
    csg_u32 real_size;     /* 4: float build, 8: double build           */
    csg_i32 width, height; /* the image                                 */
    csg_i32 spp;           /* primary samples a pixel (>= 1): the hit
                              records hold width * spp records a row, the
                              samples of a pixel side by side            */
    csg_i32 max_depth;     /* max_trace_level: 1 = primary rays only    */
    csg_i32 prim_count, node_count, root_count, bvh_count;
    csg_i32 linear_roots;  /* roots 0 .. linear_roots-1: unbounded, tested
                              one by one; the rest hang in the BVH        */
    csg_i32 material_count, light_count;
    csg_i32 max_stack;     /* deepest root program, <= CSG_STACK_MAX      */
    csg_i32 map_count;     /* colour map entries (workers)               */
    csg_i32 sky_count;     /* sky_sphere pigments: a ray that misses sees
                              a colour of its direction, so no tile is
                              degenerate                                 */
    csg_i32 wide_count;    /* wide runs (csg_wide), their BVH nodes and */
    csg_i32 wide_bvh_count; /* items                                    */
    csg_i32 wide_item_count;
    csg_i32 coef_count;    /* reals in the coefficient table (polys)    */
    csg_i32 curve_count;   /* curves of trapezoid pieces (csg_curve)    */
    csg_i32 pad_count;
    csg_u32 kinds;         /* the primitive kinds present: bit 1 << kind */
    csg_u32 features;      /* enum csg_feature: what else the scene uses */
    csg_u64 off_prims, off_nodes, off_roots, off_bvh, off_camera; /* device */
    csg_u64 off_wide, off_wide_bvh, off_wide_items;              /* device */
    csg_u64 off_coefs;     /* device: the coefficient table, reals, right
                              after the primitives (a poly reaches its
                              coefficients from its own payload, flat.h) */
    csg_u64 off_curves;    /* device: the curve table (csg_curve)       */
    csg_u64 off_materials, off_lights, off_shading, off_maps;    /* workers */
    csg_u64 total_size;    /* bytes of the whole blob                    */
} csg_blob_header;

/* Every struct the device reads and each of its fields, as an X-macro:
 * S(type) stands for a size, F(type, field) for an offset.  The layout
 * probe kernel (simd_kernels/primary.cl) and tests/test_layout.c expand the
 * same list on each side and compare them entry by entry, so a struct the
 * device reads cannot drift between C and OpenCL C unnoticed.  A new field
 * or device-read struct goes here. */
#define CSG_LAYOUT_FIELDS(S, F)                                                            \
    S(real)                                                                                \
    S(csg_blob_header) F(csg_blob_header, magic) F(csg_blob_header, real_size)             \
        F(csg_blob_header, width) F(csg_blob_header, height) F(csg_blob_header, spp)       \
        F(csg_blob_header, max_depth) F(csg_blob_header, prim_count)                       \
        F(csg_blob_header, node_count) F(csg_blob_header, root_count)                      \
        F(csg_blob_header, bvh_count) F(csg_blob_header, linear_roots)                     \
        F(csg_blob_header, material_count) F(csg_blob_header, light_count)                 \
        F(csg_blob_header, max_stack) F(csg_blob_header, map_count)                        \
        F(csg_blob_header, sky_count) F(csg_blob_header, wide_count)                       \
        F(csg_blob_header, wide_bvh_count) F(csg_blob_header, wide_item_count)             \
        F(csg_blob_header, coef_count) F(csg_blob_header, curve_count)                     \
        F(csg_blob_header, pad_count) F(csg_blob_header, kinds)                            \
        F(csg_blob_header, features) F(csg_blob_header, off_prims)                         \
        F(csg_blob_header, off_nodes) F(csg_blob_header, off_roots)                        \
        F(csg_blob_header, off_bvh) F(csg_blob_header, off_camera)                         \
        F(csg_blob_header, off_wide) F(csg_blob_header, off_wide_bvh)                      \
        F(csg_blob_header, off_wide_items) F(csg_blob_header, off_coefs)                   \
        F(csg_blob_header, off_curves)                                                     \
        F(csg_blob_header, off_materials) F(csg_blob_header, off_lights)                   \
        F(csg_blob_header, off_shading) F(csg_blob_header, off_maps)                       \
        F(csg_blob_header, total_size)                                                     \
    S(csg_prim) F(csg_prim, kind) F(csg_prim, flags) F(csg_prim, material)                 \
        F(csg_prim, root) F(csg_prim, p) F(csg_prim, inv)                                  \
    S(csg_node) F(csg_node, op) F(csg_node, prim)                                          \
    S(csg_curve_side) F(csg_curve_side, a) F(csg_curve_side, b) F(csg_curve_side, c)       \
        F(csg_curve_side, d) F(csg_curve_side, u0) F(csg_curve_side, u1)                   \
    S(csg_curve) F(csg_curve, side)                                                        \
    S(csg_wide) F(csg_wide, pair_count) F(csg_wide, bvh_first) F(csg_wide, bvh_count)     \
        F(csg_wide, item_first)                                                            \
    S(csg_root) F(csg_root, first_node) F(csg_root, node_count)                            \
        F(csg_root, stack_depth) F(csg_root, flags) F(csg_root, lo) F(csg_root, hi)        \
    S(csg_bvh_node) F(csg_bvh_node, first) F(csg_bvh_node, count) F(csg_bvh_node, box)     \
    S(csg_camera) F(csg_camera, projection) F(csg_camera, pad) F(csg_camera, location)     \
        F(csg_camera, direction) F(csg_camera, right) F(csg_camera, up) F(csg_camera, hither) \
        F(csg_camera, kx) F(csg_camera, ky)                                               \
    S(csg_flat_light) F(csg_flat_light, position) F(csg_flat_light, color)                 \
        F(csg_flat_light, shadowless) F(csg_flat_light, kind) F(csg_flat_light, parallel)  \
        F(csg_flat_light, area) F(csg_flat_light, media_attenuation)                       \
        F(csg_flat_light, direction) F(csg_flat_light, point_at)                           \
        F(csg_flat_light, fade_power) F(csg_flat_light, axis2)

#endif
