/*
 * lexer.c — the scene language's tokens (see lexer.h).
 *
 * Algorithm: a hand-written scanner over one buffer.  Whitespace and
 * comments are skipped first: `//` to the end of the line and slash-star ... star-slash
 * block comments, which nest as in POV-Ray (a depth counter, no recursion).
 * Words are looked up by binary search in a table sorted by byte order
 * (kw_table; test_parser checks that every row is found): every reserved
 * word of POV-Ray 3.7 is there, so a word csgtrace does not implement is
 * named as unsupported rather than taken for an identifier.  The pattern
 * and wave keywords csgtrace implements are not: they come from the
 * tables of csg/device/patterns.h (CSG_KW_PATTERN, CSG_KW_WAVE; the parser
 * asks csg_pattern_keyword and csg_wave_keyword which one), so a row added
 * there is a keyword with no edit here.  Operators are one character, or
 * two for <= >= != (csg_token.punct).  A UTF-8 byte-order mark before the
 * first character is skipped.  A number is scanned to its extent by the
 * grammar digits [. digits] [e [+-] digits] (or . digits ...), then
 * converted on a bounded copy (decimal.h, else strtod: the same value),
 * so strtod's own extensions (hex, inf, nan) can never be reached.
 *
 * Invariants: pos <= len; line/col always describe src[pos]; every token
 * records where it starts; the scanner never reads past len.
 */
#include "lexer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../device/patterns.h"
#include "decimal.h"

typedef struct {
    const char *name;
    enum csg_kw kw;
} kw_entry;

/* POV-Ray 3.7's reserved words (477; those that are only directives are
 * in directive_table, the 23 pattern and wave keywords csgtrace implements
 * in the tables of device/patterns.h: pattern_words, wave_words below),
 * sorted by byte order (LC_ALL=C sort): binary search below. */
static const kw_entry kw_table[] = {
    {"aa_level", CSG_KW_UNSUPPORTED},
    {"aa_threshold", CSG_KW_UNSUPPORTED},
    {"abs", CSG_KW_ABS},
    {"absorption", CSG_KW_UNSUPPORTED},
    {"accuracy", CSG_KW_ACCURACY},
    {"acos", CSG_KW_ACOS},
    {"acosh", CSG_KW_ACOSH},
    {"adaptive", CSG_KW_ADAPTIVE},
    {"adc_bailout", CSG_KW_ADC_BAILOUT},
    {"agate_turb", CSG_KW_AGATE_TURB},
    {"albedo", CSG_KW_UNSUPPORTED},
    {"all", CSG_KW_UNSUPPORTED},
    {"all_intersections", CSG_KW_UNSUPPORTED},
    {"alpha", CSG_KW_UNSUPPORTED},
    {"altitude", CSG_KW_UNSUPPORTED},
    {"always_sample", CSG_KW_UNSUPPORTED},
    {"ambient", CSG_KW_AMBIENT},
    {"ambient_light", CSG_KW_AMBIENT_LIGHT},
    {"angle", CSG_KW_ANGLE},
    {"anisotropy", CSG_KW_UNSUPPORTED},
    {"aoi", CSG_KW_UNSUPPORTED},
    {"aperture", CSG_KW_UNSUPPORTED},
    {"append", CSG_KW_UNSUPPORTED},
    {"arc_angle", CSG_KW_UNSUPPORTED},
    {"area_illumination", CSG_KW_UNSUPPORTED},
    {"area_light", CSG_KW_AREA_LIGHT},
    {"array", CSG_KW_ARRAY},
    {"asc", CSG_KW_ASC},
    {"ascii", CSG_KW_UNSUPPORTED},
    {"asin", CSG_KW_ASIN},
    {"asinh", CSG_KW_ASINH},
    {"assumed_gamma", CSG_KW_ASSUMED_GAMMA},
    {"atan", CSG_KW_ATAN},
    {"atan2", CSG_KW_ATAN2},
    {"atanh", CSG_KW_ATANH},
    {"autostop", CSG_KW_UNSUPPORTED},
    {"b_spline", CSG_KW_UNSUPPORTED},
    {"background", CSG_KW_BACKGROUND},
    {"bezier_spline", CSG_KW_BEZIER_SPLINE},
    {"bicubic_patch", CSG_KW_UNSUPPORTED},
    {"bitwise_and", CSG_KW_BITWISE_AND},
    {"bitwise_or", CSG_KW_BITWISE_OR},
    {"bitwise_xor", CSG_KW_BITWISE_XOR},
    {"black_hole", CSG_KW_UNSUPPORTED},
    {"blob", CSG_KW_UNSUPPORTED},
    {"blue", CSG_KW_BLUE},
    {"blur_samples", CSG_KW_UNSUPPORTED},
    {"bmp", CSG_KW_UNSUPPORTED},
    {"bokeh", CSG_KW_UNSUPPORTED},
    {"bounded_by", CSG_KW_BOUNDED_BY},
    {"box", CSG_KW_BOX},
    {"brick_size", CSG_KW_BRICK_SIZE},
    {"brightness", CSG_KW_UNSUPPORTED},
    {"brilliance", CSG_KW_BRILLIANCE},
    {"bump_map", CSG_KW_UNSUPPORTED},
    {"bump_size", CSG_KW_BUMP_SIZE},
    {"camera", CSG_KW_CAMERA},
    {"caustics", CSG_KW_UNSUPPORTED},
    {"ceil", CSG_KW_CEIL},
    {"cells", CSG_KW_UNSUPPORTED},
    {"charset", CSG_KW_UNSUPPORTED},
    {"chr", CSG_KW_CHR},
    {"circular", CSG_KW_CIRCULAR},
    {"clipped_by", CSG_KW_CLIPPED_BY},
    {"clock", CSG_KW_CLOCK},
    {"clock_on", CSG_KW_CLOCK_ON},
    {"collect", CSG_KW_UNSUPPORTED},
    {"color", CSG_KW_COLOR},
    {"color_map", CSG_KW_COLOR_MAP},
    {"colour", CSG_KW_COLOR},
    {"colour_map", CSG_KW_COLOR_MAP},
    {"component", CSG_KW_UNSUPPORTED},
    {"composite", CSG_KW_UNSUPPORTED},
    {"concat", CSG_KW_CONCAT},
    {"cone", CSG_KW_CONE},
    {"confidence", CSG_KW_UNSUPPORTED},
    {"conic_sweep", CSG_KW_CONIC_SWEEP},
    {"conserve_energy", CSG_KW_CONSERVE_ENERGY},
    {"contained_by", CSG_KW_UNSUPPORTED},
    {"control0", CSG_KW_CONTROL0},
    {"control1", CSG_KW_CONTROL1},
    {"coords", CSG_KW_UNSUPPORTED},
    {"cos", CSG_KW_COS},
    {"cosh", CSG_KW_COSH},
    {"count", CSG_KW_UNSUPPORTED},
    {"crand", CSG_KW_CRAND},
    {"cube", CSG_KW_UNSUPPORTED},
    {"cubic", CSG_KW_CUBIC},
    {"cubic_spline", CSG_KW_CUBIC_SPLINE},
    {"cutaway_textures", CSG_KW_UNSUPPORTED},
    {"cylinder", CSG_KW_CYLINDER},
    {"datetime", CSG_KW_UNSUPPORTED},
    {"default", CSG_KW_DEFAULT}, /* POV-Ray takes `default { }` without '#' */
    {"defined", CSG_KW_DEFINED},
    {"degrees", CSG_KW_DEGREES},
    {"density", CSG_KW_UNSUPPORTED},
    {"density_file", CSG_KW_UNSUPPORTED},
    {"density_map", CSG_KW_UNSUPPORTED},
    {"dents", CSG_KW_UNSUPPORTED},
    {"deprecated", CSG_KW_UNSUPPORTED},
    {"df3", CSG_KW_UNSUPPORTED},
    {"difference", CSG_KW_DIFFERENCE},
    {"diffuse", CSG_KW_DIFFUSE},
    {"dimension_size", CSG_KW_DIMENSION_SIZE},
    {"dimensions", CSG_KW_DIMENSIONS},
    {"direction", CSG_KW_DIRECTION},
    {"disc", CSG_KW_UNSUPPORTED},
    {"dispersion", CSG_KW_UNSUPPORTED},
    {"dispersion_samples", CSG_KW_UNSUPPORTED},
    {"dist_exp", CSG_KW_UNSUPPORTED},
    {"distance", CSG_KW_DISTANCE},
    {"distance_maximum", CSG_KW_UNSUPPORTED},
    {"div", CSG_KW_DIV},
    {"double_illuminate", CSG_KW_UNSUPPORTED},
    {"dtag", CSG_KW_UNSUPPORTED},
    {"eccentricity", CSG_KW_UNSUPPORTED},
    {"emission", CSG_KW_EMISSION},
    {"error_bound", CSG_KW_UNSUPPORTED},
    {"evaluate", CSG_KW_UNSUPPORTED},
    {"exp", CSG_KW_EXP},
    {"expand_thresholds", CSG_KW_UNSUPPORTED},
    {"exponent", CSG_KW_EXPONENT},
    {"exr", CSG_KW_UNSUPPORTED},
    {"exterior", CSG_KW_UNSUPPORTED},
    {"extinction", CSG_KW_UNSUPPORTED},
    {"face_indices", CSG_KW_UNSUPPORTED},
    {"facets", CSG_KW_UNSUPPORTED},
    {"fade_color", CSG_KW_FADE_COLOR},
    {"fade_colour", CSG_KW_FADE_COLOR},
    {"fade_distance", CSG_KW_FADE_DISTANCE},
    {"fade_power", CSG_KW_FADE_POWER},
    {"falloff", CSG_KW_FALLOFF},
    {"falloff_angle", CSG_KW_UNSUPPORTED},
    {"false", CSG_KW_FALSE},
    {"file_exists", CSG_KW_FILE_EXISTS},
    {"filter", CSG_KW_FILTER},
    {"finish", CSG_KW_FINISH},
    {"fisheye", CSG_KW_UNSUPPORTED},
    {"flatness", CSG_KW_UNSUPPORTED},
    {"flip", CSG_KW_UNSUPPORTED},
    {"floor", CSG_KW_FLOOR},
    {"focal_point", CSG_KW_UNSUPPORTED},
    {"fog", CSG_KW_FOG},
    {"fog_alt", CSG_KW_FOG_ALT},
    {"fog_offset", CSG_KW_FOG_OFFSET},
    {"fog_type", CSG_KW_FOG_TYPE},
    {"form", CSG_KW_FORM},
    {"frame_number", CSG_KW_FRAME_NUMBER},
    {"frequency", CSG_KW_FREQUENCY},
    {"fresnel", CSG_KW_FRESNEL},
    {"function", CSG_KW_UNSUPPORTED},
    {"gamma", CSG_KW_UNSUPPORTED},
    {"gather", CSG_KW_UNSUPPORTED},
    {"gif", CSG_KW_UNSUPPORTED},
    {"global", CSG_KW_UNSUPPORTED},
    {"global_lights", CSG_KW_UNSUPPORTED},
    {"global_settings", CSG_KW_GLOBAL_SETTINGS},
    {"gray", CSG_KW_GRAY},
    {"gray_threshold", CSG_KW_UNSUPPORTED},
    {"green", CSG_KW_GREEN},
    {"hdr", CSG_KW_UNSUPPORTED},
    {"height_field", CSG_KW_UNSUPPORTED},
    {"hf_gray_16", CSG_KW_UNSUPPORTED},
    {"hierarchy", CSG_KW_UNSUPPORTED},
    {"hollow", CSG_KW_HOLLOW},
    {"hypercomplex", CSG_KW_UNSUPPORTED},
    {"iff", CSG_KW_UNSUPPORTED},
    {"image_map", CSG_KW_UNSUPPORTED},
    {"image_pattern", CSG_KW_UNSUPPORTED},
    {"importance", CSG_KW_UNSUPPORTED},
    {"inside", CSG_KW_UNSUPPORTED},
    {"inside_vector", CSG_KW_UNSUPPORTED},
    {"int", CSG_KW_INT},
    {"interior", CSG_KW_INTERIOR},
    {"interior_texture", CSG_KW_INTERIOR_TEXTURE},
    {"internal", CSG_KW_UNSUPPORTED},
    {"interpolate", CSG_KW_UNSUPPORTED},
    {"intersection", CSG_KW_INTERSECTION},
    {"intervals", CSG_KW_UNSUPPORTED},
    {"inverse", CSG_KW_INVERSE},
    {"ior", CSG_KW_IOR},
    {"irid", CSG_KW_IRID},
    {"irid_wavelength", CSG_KW_IRID_WAVELENGTH},
    {"isosurface", CSG_KW_UNSUPPORTED},
    {"jitter", CSG_KW_JITTER},
    {"jpeg", CSG_KW_UNSUPPORTED},
    {"julia", CSG_KW_UNSUPPORTED},
    {"julia_fractal", CSG_KW_UNSUPPORTED},
    {"lambda", CSG_KW_LAMBDA},
    {"lathe", CSG_KW_UNSUPPORTED},
    {"light_group", CSG_KW_UNSUPPORTED},
    {"light_source", CSG_KW_LIGHT_SOURCE},
    {"linear_spline", CSG_KW_LINEAR_SPLINE},
    {"linear_sweep", CSG_KW_LINEAR_SWEEP},
    {"ln", CSG_KW_LN},
    {"load_file", CSG_KW_UNSUPPORTED},
    {"location", CSG_KW_LOCATION},
    {"log", CSG_KW_LOG},
    {"look_at", CSG_KW_LOOK_AT},
    {"looks_like", CSG_KW_LOOKS_LIKE},
    {"low_error_factor", CSG_KW_UNSUPPORTED},
    {"magnet", CSG_KW_UNSUPPORTED},
    {"major_radius", CSG_KW_UNSUPPORTED},
    {"mandel", CSG_KW_UNSUPPORTED},
    {"map_type", CSG_KW_UNSUPPORTED},
    {"material", CSG_KW_MATERIAL},
    {"material_map", CSG_KW_UNSUPPORTED},
    {"matrix", CSG_KW_MATRIX},
    {"max", CSG_KW_MAX},
    {"max_extent", CSG_KW_UNSUPPORTED},
    {"max_gradient", CSG_KW_UNSUPPORTED},
    {"max_intersections", CSG_KW_UNSUPPORTED},
    {"max_iteration", CSG_KW_UNSUPPORTED},
    {"max_sample", CSG_KW_UNSUPPORTED},
    {"max_trace", CSG_KW_UNSUPPORTED},
    {"max_trace_level", CSG_KW_MAX_TRACE_LEVEL},
    {"maximum_reuse", CSG_KW_UNSUPPORTED},
    {"media", CSG_KW_UNSUPPORTED},
    {"media_attenuation", CSG_KW_MEDIA_ATTENUATION},
    {"media_interaction", CSG_KW_MEDIA_INTERACTION},
    {"merge", CSG_KW_MERGE},
    {"mesh", CSG_KW_MESH},
    {"mesh2", CSG_KW_UNSUPPORTED},
    {"mesh_camera", CSG_KW_UNSUPPORTED},
    {"metallic", CSG_KW_METALLIC},
    {"method", CSG_KW_UNSUPPORTED},
    {"metric", CSG_KW_METRIC},
    {"min", CSG_KW_MIN},
    {"min_extent", CSG_KW_UNSUPPORTED},
    {"minimum_reuse", CSG_KW_UNSUPPORTED},
    {"mm_per_unit", CSG_KW_UNSUPPORTED},
    {"mod", CSG_KW_MOD},
    {"mortar", CSG_KW_MORTAR},
    {"natural_spline", CSG_KW_UNSUPPORTED},
    {"nearest_count", CSG_KW_UNSUPPORTED},
    {"no", CSG_KW_FALSE},
    {"no_bump_scale", CSG_KW_NO_BUMP_SCALE},
    {"no_image", CSG_KW_UNSUPPORTED},
    {"no_radiosity", CSG_KW_UNSUPPORTED},
    {"no_reflection", CSG_KW_UNSUPPORTED},
    {"no_shadow", CSG_KW_NO_SHADOW},
    {"noise_generator", CSG_KW_NOISE_GENERATOR},
    {"normal", CSG_KW_NORMAL},
    {"normal_indices", CSG_KW_UNSUPPORTED},
    {"normal_map", CSG_KW_UNSUPPORTED},
    {"normal_vectors", CSG_KW_UNSUPPORTED},
    {"now", CSG_KW_UNSUPPORTED},
    {"number_of_sides", CSG_KW_UNSUPPORTED},
    {"number_of_tiles", CSG_KW_UNSUPPORTED},
    {"number_of_waves", CSG_KW_NUMBER_OF_WAVES},
    {"object", CSG_KW_OBJECT},
    {"octaves", CSG_KW_OCTAVES},
    {"off", CSG_KW_FALSE},
    {"offset", CSG_KW_OFFSET},
    {"omega", CSG_KW_OMEGA},
    {"omnimax", CSG_KW_UNSUPPORTED},
    {"on", CSG_KW_TRUE},
    {"once", CSG_KW_UNSUPPORTED},
    {"open", CSG_KW_OPEN},
    {"orient", CSG_KW_ORIENT},
    {"orientation", CSG_KW_UNSUPPORTED},
    {"orthographic", CSG_KW_ORTHOGRAPHIC},
    {"ovus", CSG_KW_UNSUPPORTED},
    {"panoramic", CSG_KW_PANORAMIC},
    {"parallel", CSG_KW_PARALLEL},
    {"parametric", CSG_KW_UNSUPPORTED},
    {"pass_through", CSG_KW_UNSUPPORTED},
    {"pattern", CSG_KW_UNSUPPORTED},
    {"pavement", CSG_KW_UNSUPPORTED},
    {"perspective", CSG_KW_PERSPECTIVE},
    {"pgm", CSG_KW_UNSUPPORTED},
    {"phase", CSG_KW_PHASE},
    {"phong", CSG_KW_PHONG},
    {"phong_size", CSG_KW_PHONG_SIZE},
    {"photons", CSG_KW_UNSUPPORTED},
    {"pi", CSG_KW_PI},
    {"pigment", CSG_KW_PIGMENT},
    {"pigment_map", CSG_KW_PIGMENT_MAP},
    {"plane", CSG_KW_PLANE},
    {"png", CSG_KW_UNSUPPORTED},
    {"point_at", CSG_KW_POINT_AT},
    {"poly", CSG_KW_POLY},
    {"polygon", CSG_KW_POLYGON},
    {"polynomial", CSG_KW_UNSUPPORTED},
    {"pot", CSG_KW_UNSUPPORTED},
    {"pow", CSG_KW_POW},
    {"ppm", CSG_KW_UNSUPPORTED},
    {"precision", CSG_KW_UNSUPPORTED},
    {"precompute", CSG_KW_UNSUPPORTED},
    {"premultiplied", CSG_KW_UNSUPPORTED},
    {"pretrace_end", CSG_KW_UNSUPPORTED},
    {"pretrace_start", CSG_KW_UNSUPPORTED},
    {"prism", CSG_KW_PRISM},
    {"prod", CSG_KW_UNSUPPORTED},
    {"projected_through", CSG_KW_UNSUPPORTED},
    {"pwr", CSG_KW_UNSUPPORTED},
    {"quadratic_spline", CSG_KW_QUADRATIC_SPLINE},
    {"quadric", CSG_KW_QUADRIC},
    {"quartic", CSG_KW_QUARTIC},
    {"quaternion", CSG_KW_UNSUPPORTED},
    {"quick_color", CSG_KW_QUICK_COLOR},
    {"quick_colour", CSG_KW_QUICK_COLOR},
    {"quilted", CSG_KW_UNSUPPORTED},
    {"radians", CSG_KW_RADIANS},
    {"radiosity", CSG_KW_UNSUPPORTED},
    {"radius", CSG_KW_RADIUS},
    {"rainbow", CSG_KW_UNSUPPORTED},
    {"rand", CSG_KW_RAND},
    {"ratio", CSG_KW_UNSUPPORTED},
    {"reciprocal", CSG_KW_UNSUPPORTED},
    {"recursion_limit", CSG_KW_UNSUPPORTED},
    {"red", CSG_KW_RED},
    {"reflection", CSG_KW_REFLECTION},
    {"reflection_exponent", CSG_KW_REFLECTION_EXPONENT},
    {"refraction", CSG_KW_UNSUPPORTED},
    {"repeat", CSG_KW_UNSUPPORTED},
    {"rgb", CSG_KW_RGB},
    {"rgbf", CSG_KW_RGBF},
    {"rgbft", CSG_KW_RGBFT},
    {"rgbt", CSG_KW_RGBT},
    {"right", CSG_KW_RIGHT},
    {"ripples", CSG_KW_UNSUPPORTED},
    {"rotate", CSG_KW_ROTATE},
    {"roughness", CSG_KW_ROUGHNESS},
    {"samples", CSG_KW_UNSUPPORTED},
    {"save_file", CSG_KW_UNSUPPORTED},
    {"sblue", CSG_KW_UNSUPPORTED},
    {"scale", CSG_KW_SCALE},
    {"scattering", CSG_KW_UNSUPPORTED},
    {"seed", CSG_KW_SEED},
    {"select", CSG_KW_SELECT},
    {"sgreen", CSG_KW_UNSUPPORTED},
    {"shadowless", CSG_KW_SHADOWLESS},
    {"sin", CSG_KW_SIN},
    {"sinh", CSG_KW_SINH},
    {"sint16be", CSG_KW_UNSUPPORTED},
    {"sint16le", CSG_KW_UNSUPPORTED},
    {"sint32be", CSG_KW_UNSUPPORTED},
    {"sint32le", CSG_KW_UNSUPPORTED},
    {"sint8", CSG_KW_UNSUPPORTED},
    {"size", CSG_KW_UNSUPPORTED},
    {"sky", CSG_KW_SKY},
    {"sky_sphere", CSG_KW_SKY_SPHERE},
    {"slice", CSG_KW_UNSUPPORTED},
    {"slope", CSG_KW_UNSUPPORTED},
    {"slope_map", CSG_KW_UNSUPPORTED},
    {"smooth", CSG_KW_UNSUPPORTED},
    {"smooth_triangle", CSG_KW_SMOOTH_TRIANGLE},
    {"solid", CSG_KW_SOLID},
    {"sor", CSG_KW_UNSUPPORTED},
    {"spacing", CSG_KW_UNSUPPORTED},
    {"specular", CSG_KW_SPECULAR},
    {"sphere", CSG_KW_SPHERE},
    {"sphere_sweep", CSG_KW_UNSUPPORTED},
    {"spherical", CSG_KW_SPHERICAL},
    {"spline", CSG_KW_UNSUPPORTED},
    {"split_union", CSG_KW_UNSUPPORTED},
    {"spotlight", CSG_KW_SPOTLIGHT},
    {"sqr", CSG_KW_SQR},
    {"sqrt", CSG_KW_SQRT},
    {"square", CSG_KW_UNSUPPORTED},
    {"sred", CSG_KW_UNSUPPORTED},
    {"srgb", CSG_KW_SRGB},
    {"srgbf", CSG_KW_SRGBF},
    {"srgbft", CSG_KW_SRGBFT},
    {"srgbt", CSG_KW_SRGBT},
    {"steps", CSG_KW_UNSUPPORTED},
    {"str", CSG_KW_STR},
    {"strcmp", CSG_KW_STRCMP},
    {"strength", CSG_KW_UNSUPPORTED},
    {"strlen", CSG_KW_STRLEN},
    {"strlwr", CSG_KW_STRLWR},
    {"strupr", CSG_KW_STRUPR},
    {"sturm", CSG_KW_STURM},
    {"substr", CSG_KW_SUBSTR},
    {"subsurface", CSG_KW_UNSUPPORTED},
    {"sum", CSG_KW_UNSUPPORTED},
    {"superellipsoid", CSG_KW_UNSUPPORTED},
    {"sys", CSG_KW_UNSUPPORTED},
    {"t", CSG_KW_T},
    {"tan", CSG_KW_TAN},
    {"tanh", CSG_KW_TANH},
    {"target", CSG_KW_UNSUPPORTED},
    {"text", CSG_KW_TEXT},
    {"texture", CSG_KW_TEXTURE},
    {"texture_list", CSG_KW_UNSUPPORTED},
    {"texture_map", CSG_KW_TEXTURE_MAP},
    {"tga", CSG_KW_UNSUPPORTED},
    {"thickness", CSG_KW_THICKNESS},
    {"threshold", CSG_KW_UNSUPPORTED},
    {"tiff", CSG_KW_UNSUPPORTED},
    {"tightness", CSG_KW_TIGHTNESS},
    {"tile2", CSG_KW_UNSUPPORTED},
    {"tiles", CSG_KW_UNSUPPORTED},
    {"tiling", CSG_KW_UNSUPPORTED},
    {"tolerance", CSG_KW_UNSUPPORTED},
    {"toroidal", CSG_KW_UNSUPPORTED},
    {"torus", CSG_KW_TORUS},
    {"trace", CSG_KW_UNSUPPORTED},
    {"transform", CSG_KW_TRANSFORM},
    {"translate", CSG_KW_TRANSLATE},
    {"translucency", CSG_KW_UNSUPPORTED},
    {"transmit", CSG_KW_TRANSMIT},
    {"triangle", CSG_KW_TRIANGLE},
    {"triangular", CSG_KW_UNSUPPORTED},
    {"true", CSG_KW_TRUE},
    {"ttf", CSG_KW_TTF},
    {"turb_depth", CSG_KW_TURB_DEPTH},
    {"turbulence", CSG_KW_TURBULENCE},
    {"type", CSG_KW_UNSUPPORTED},
    {"u", CSG_KW_U},
    {"u_steps", CSG_KW_UNSUPPORTED},
    {"uint16be", CSG_KW_UNSUPPORTED},
    {"uint16le", CSG_KW_UNSUPPORTED},
    {"uint8", CSG_KW_UNSUPPORTED},
    {"ultra_wide_angle", CSG_KW_ULTRA_WIDE_ANGLE},
    {"union", CSG_KW_UNION},
    {"up", CSG_KW_UP},
    {"use_alpha", CSG_KW_UNSUPPORTED},
    {"use_color", CSG_KW_UNSUPPORTED},
    {"use_colour", CSG_KW_UNSUPPORTED},
    {"use_index", CSG_KW_UNSUPPORTED},
    {"utf8", CSG_KW_UNSUPPORTED},
    {"uv_indices", CSG_KW_UNSUPPORTED},
    {"uv_mapping", CSG_KW_UNSUPPORTED},
    {"uv_vectors", CSG_KW_UNSUPPORTED},
    {"v", CSG_KW_V},
    {"v_steps", CSG_KW_UNSUPPORTED},
    {"val", CSG_KW_VAL},
    {"variance", CSG_KW_UNSUPPORTED},
    {"vaxis_rotate", CSG_KW_VAXIS_ROTATE},
    {"vcross", CSG_KW_VCROSS},
    {"vdot", CSG_KW_VDOT},
    {"version", CSG_KW_VERSION},
    {"vertex_vectors", CSG_KW_UNSUPPORTED},
    {"vlength", CSG_KW_VLENGTH},
    {"vnormalize", CSG_KW_VNORMALIZE},
    {"vrotate", CSG_KW_VROTATE},
    {"vstr", CSG_KW_VSTR},
    {"vturbulence", CSG_KW_UNSUPPORTED},
    {"warp", CSG_KW_UNSUPPORTED},
    {"water_level", CSG_KW_UNSUPPORTED},
    {"waves", CSG_KW_UNSUPPORTED},
    {"width", CSG_KW_UNSUPPORTED},
    {"x", CSG_KW_X},
    {"xyz", CSG_KW_UNSUPPORTED},
    {"y", CSG_KW_Y},
    {"yes", CSG_KW_TRUE},
    {"z", CSG_KW_Z},
};

static const kw_entry directive_table[] = {
    {"break", CSG_KW_BREAK},
    {"case", CSG_KW_CASE},
    {"debug", CSG_KW_DEBUG},
    {"declare", CSG_KW_DECLARE},
    {"default", CSG_KW_DEFAULT},
    {"else", CSG_KW_ELSE},
    {"elseif", CSG_KW_ELSEIF},
    {"end", CSG_KW_END},
    {"error", CSG_KW_ERROR},
    {"fclose", CSG_KW_FCLOSE},
    {"fopen", CSG_KW_FOPEN},
    {"for", CSG_KW_FOR},
    {"if", CSG_KW_IF},
    {"ifdef", CSG_KW_IFDEF},
    {"ifndef", CSG_KW_IFNDEF},
    {"include", CSG_KW_INCLUDE},
    {"local", CSG_KW_LOCAL},
    {"macro", CSG_KW_MACRO},
    {"range", CSG_KW_RANGE},
    {"read", CSG_KW_READ},
    {"render", CSG_KW_UNSUPPORTED},
    {"statistics", CSG_KW_UNSUPPORTED},
    {"switch", CSG_KW_SWITCH},
    {"undef", CSG_KW_UNDEF},
    {"version", CSG_KW_VERSION},
    {"warning", CSG_KW_WARNING},
    {"while", CSG_KW_WHILE},
    {"write", CSG_KW_WRITE},
};

#define MAX_NUMBER_CHARS 256

/* a[0..alen) (no NUL in it) against the string b in byte order, a prefix
 * first: one pass, no strlen (the binary search's inner loop, run for
 * every word of a scene). */
static int word_cmp(const char *a, size_t alen, const char *b)
{
    for (size_t i = 0; i < alen; i++) {
        int d = (unsigned char)a[i] - (unsigned char)b[i];
        if (d != 0)
            return d; /* (b ended first: a[i] - '\0' > 0) */
    }
    return b[alen] != '\0' ? -1 : 0;
}

static enum csg_kw table_lookup(const kw_entry *t, size_t n, const char *text, size_t len)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        int c = word_cmp(text, len, t[mid].name);
        if (c == 0)
            return t[mid].kw;
        if (c < 0)
            hi = mid;
        else
            lo = mid + 1;
    }
    return CSG_KW_NONE;
}

/* The pattern keywords: each PATTERN row of CSG_PATTERNS by its name, and
 * each alias (device/patterns.h). */
static const struct {
    const char *word;
    enum csg_pattern pattern;
    bool alias;
} pattern_words[] = {
#define LEX_PATTERN_WORD(ID, name, wave, noise, warp) {#name, CSG_PATTERN_##ID, false},
#define LEX_PATTERN_ALIAS(word, ID) {#word, CSG_PATTERN_##ID, true},
    CSG_PATTERNS(CSG_PATTERN_NONE, LEX_PATTERN_WORD) CSG_PATTERN_ALIASES(LEX_PATTERN_ALIAS)
#undef LEX_PATTERN_WORD
#undef LEX_PATTERN_ALIAS
};

/* The wave keywords: <name>_wave for each row of CSG_WAVES. */
#define LEX_WAVE_WORD(ID, name) [CSG_WAVE_##ID] = #name "_wave",
static const char *const wave_words[CSG_WAVE_COUNT] = {CSG_WAVES(LEX_WAVE_WORD)};
#undef LEX_WAVE_WORD

static bool word_is(const char *text, size_t len, const char *word)
{
    return strlen(word) == len && memcmp(text, word, len) == 0;
}

int csg_pattern_keyword(const char *text, size_t len, bool *alias)
{
    for (size_t i = 0; i < sizeof pattern_words / sizeof pattern_words[0]; i++)
        if (word_is(text, len, pattern_words[i].word)) {
            if (alias)
                *alias = pattern_words[i].alias;
            return (int)pattern_words[i].pattern;
        }
    return -1;
}

int csg_wave_keyword(const char *text, size_t len)
{
    for (int w = 0; w < CSG_WAVE_COUNT; w++)
        if (word_is(text, len, wave_words[w]))
            return w;
    return -1;
}

/* kw_table first: a word it implements is that keyword; else a pattern or
 * wave of the tables (so a row added there takes over a word kw_table
 * still calls unsupported); else what kw_table says (unsupported or an
 * identifier).  So only the words kw_table does not implement, mostly
 * identifiers, pay for the scan of the pattern tables. */
enum csg_kw csg_keyword(const char *text, size_t len, bool directive)
{
    if (directive)
        return table_lookup(directive_table, sizeof directive_table / sizeof directive_table[0],
                            text, len);
    enum csg_kw kw = table_lookup(kw_table, sizeof kw_table / sizeof kw_table[0], text, len);
    if (kw != CSG_KW_NONE && kw != CSG_KW_UNSUPPORTED)
        return kw;
    if (csg_pattern_keyword(text, len, NULL) >= 0)
        return CSG_KW_PATTERN;
    if (csg_wave_keyword(text, len) >= 0)
        return CSG_KW_WAVE;
    return kw;
}

void csg_lexer_init(csg_lexer *lx, const char *file, const char *src, size_t len)
{
    lx->file = file;
    lx->src = src;
    lx->len = len;
    lx->pos = 0;
    lx->line = 1;
    lx->col = 1;
    if (len >= 3 && memcmp(src, "\xef\xbb\xbf", 3) == 0)
        lx->pos = 3; /* a UTF-8 byte-order mark: not a character of the scene */
}

static int peek(const csg_lexer *lx, size_t ahead)
{
    return lx->pos + ahead < lx->len ? (unsigned char)lx->src[lx->pos + ahead] : -1;
}

static void bump(csg_lexer *lx)
{
    if (lx->src[lx->pos] == '\n') {
        lx->line++;
        lx->col = 1;
    } else {
        lx->col++;
    }
    lx->pos++;
}

static csg_loc here(const csg_lexer *lx)
{
    return (csg_loc){lx->file, lx->line, lx->col};
}

static bool is_digit(int c) { return c >= '0' && c <= '9'; }
static bool is_word_start(int c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
static bool is_word(int c) { return is_word_start(c) || is_digit(c); }

/* The operators' characters (lex_punct). */
static const bool punct_char[256] = {
    ['{'] = true, ['}'] = true, ['<'] = true, ['>'] = true, ['('] = true, [')'] = true,
    ['['] = true, [']'] = true, [','] = true, [';'] = true, ['+'] = true, ['-'] = true,
    ['*'] = true, ['/'] = true, ['='] = true, ['!'] = true, ['&'] = true, ['|'] = true,
    ['?'] = true, [':'] = true, ['.'] = true,
};

/* bump() over the run of word characters (or digits) from pos: none is a
 * newline, so the column moves by the run's length and the line stays. */
static void bump_word(csg_lexer *lx)
{
    size_t start = lx->pos;
    while (lx->pos < lx->len && is_word((unsigned char)lx->src[lx->pos]))
        lx->pos++;
    lx->col += (int)(lx->pos - start);
}

static void bump_digits(csg_lexer *lx)
{
    size_t start = lx->pos;
    while (lx->pos < lx->len && is_digit((unsigned char)lx->src[lx->pos]))
        lx->pos++;
    lx->col += (int)(lx->pos - start);
}

/* Skips blanks and comments; false on an unterminated block comment. */
static bool skip_space(csg_lexer *lx, csg_diag *d)
{
    for (;;) {
        int c = peek(lx, 0);
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v') {
            bump(lx);
        } else if (c == '/' && peek(lx, 1) == '/') {
            while (lx->pos < lx->len && lx->src[lx->pos] != '\n')
                bump(lx);
        } else if (c == '/' && peek(lx, 1) == '*') {
            csg_loc open = here(lx);
            long depth = 0;
            do {
                if (lx->pos >= lx->len) {
                    csg_error(d, open, "unterminated comment");
                    return false;
                }
                if (peek(lx, 0) == '/' && peek(lx, 1) == '*') {
                    depth++;
                    bump(lx);
                } else if (peek(lx, 0) == '*' && peek(lx, 1) == '/') {
                    depth--;
                    bump(lx);
                }
                bump(lx);
            } while (depth > 0);
        } else {
            return true;
        }
    }
}

static bool lex_number(csg_lexer *lx, csg_token *t, csg_diag *d)
{
    size_t start = lx->pos;
    bump_digits(lx);
    if (peek(lx, 0) == '.') {
        bump(lx);
        bump_digits(lx);
    }
    int e = peek(lx, 0);
    if (e == 'e' || e == 'E') {
        int s = peek(lx, 1);
        size_t k = (s == '+' || s == '-') ? 2 : 1;
        if (is_digit(peek(lx, k))) {
            for (size_t i = 0; i < k; i++)
                bump(lx);
            bump_digits(lx);
        } else {
            bump(lx);
            csg_error(d, t->loc, "malformed number '%.*s': digits expected after the exponent",
                      (int)(lx->pos - start), lx->src + start);
            return false;
        }
    }
    t->len = lx->pos - start;
    if (is_word_start(peek(lx, 0))) {
        csg_error(d, t->loc, "malformed number '%.*s%c'", (int)(t->len > 64 ? 64 : t->len),
                  t->text, peek(lx, 0));
        return false;
    }
    if (t->len > MAX_NUMBER_CHARS) {
        csg_error(d, t->loc, "number too long (more than %d characters)", MAX_NUMBER_CHARS);
        return false;
    }
    char buf[MAX_NUMBER_CHARS + 1];
    memcpy(buf, t->text, t->len);
    buf[t->len] = '\0';
    if (t->len == 1 && buf[0] == '.') {
        csg_error(d, t->loc, "unexpected character '.'");
        return false;
    }
    if (!csg_decimal_fast(buf, t->len, &t->number)) /* (decimal.h: strtod's value, faster) */
        t->number = strtod(buf, NULL);
    if (!isfinite(t->number)) {
        csg_error(d, t->loc, "number out of range: '%s'", buf);
        return false;
    }
    t->kind = CSG_TOK_NUMBER;
    return true;
}

static bool lex_string(csg_lexer *lx, csg_token *t, csg_diag *d)
{
    bump(lx); /* the opening quote */
    size_t start = lx->pos;
    for (;;) {
        int c = peek(lx, 0);
        if (c < 0 || c == '\n' || c == '\0') {
            csg_error(d, t->loc, "unterminated string");
            return false;
        }
        if (c == '"')
            break;
        if (c == '\\' && peek(lx, 1) >= 0 && peek(lx, 1) != '\n')
            bump(lx);
        bump(lx);
    }
    t->kind = CSG_TOK_STRING;
    t->text = lx->src + start;
    t->len = lx->pos - start;
    bump(lx); /* the closing quote */
    return true;
}

/* An operator: one character, or <= >= != as one token. */
static bool lex_punct(csg_lexer *lx, csg_token *t, int c)
{
    bump(lx);
    t->kind = CSG_TOK_PUNCT;
    t->punct = c;
    t->len = 1;
    if (peek(lx, 0) == '=' && (c == '<' || c == '>' || c == '!')) {
        bump(lx);
        t->punct = c == '<' ? CSG_P_LE : c == '>' ? CSG_P_GE : CSG_P_NE;
        t->len = 2;
    }
    return true;
}

/* '#' then its word: a directive.  A '#' followed (after blanks and
 * comments) by anything but a word is ignored, as POV-Ray does; by nothing
 * at all, an error.  *stray: it was ignored, read on. */
static bool lex_directive(csg_lexer *lx, csg_token *t, csg_diag *d, bool *stray)
{
    bump(lx);
    if (!skip_space(lx, d))
        return false;
    const char *w = lx->src + lx->pos;
    bump_word(lx);
    size_t wlen = (size_t)(lx->src + lx->pos - w);
    if (wlen == 0 && peek(lx, 0) < 0) {
        csg_error(d, t->loc, "a directive name expected after '#'");
        return false;
    }
    *stray = wlen == 0;
    t->kind = CSG_TOK_DIRECTIVE;
    t->text = w;
    t->len = wlen;
    t->kw = csg_keyword(w, wlen, true);
    return true;
}

bool csg_lexer_next(csg_lexer *lx, csg_token *t, csg_diag *d)
{
    if (!skip_space(lx, d))
        return false;
    while (peek(lx, 0) == '#') {
        csg_token dir;
        bool stray;
        memset(&dir, 0, sizeof dir);
        dir.loc = here(lx);
        dir.pos = lx->pos;
        if (!lex_directive(lx, &dir, d, &stray))
            return false;
        if (!stray) {
            *t = dir;
            return true;
        }
    }
    memset(t, 0, sizeof *t);
    t->loc = here(lx);
    t->pos = lx->pos;
    t->text = lx->src + lx->pos;
    int c = peek(lx, 0);
    if (c < 0) {
        t->kind = CSG_TOK_EOF;
        return true;
    }
    if (is_digit(c) || (c == '.' && is_digit(peek(lx, 1))))
        return lex_number(lx, t, d);
    if (c == '"')
        return lex_string(lx, t, d);
    if (is_word_start(c)) {
        bump_word(lx);
        t->kind = CSG_TOK_WORD;
        t->len = (size_t)(lx->src + lx->pos - t->text);
        t->kw = csg_keyword(t->text, t->len, false);
        return true;
    }
    if (punct_char[c])
        return lex_punct(lx, t, c);
    if (c >= 0x21 && c < 0x7f)
        csg_error(d, t->loc, "unexpected character '%c'", c);
    else
        csg_error(d, t->loc, "unexpected character (byte 0x%02x)", c);
    return false;
}

void csg_token_describe(const csg_token *t, char *buf, size_t size)
{
    int n = t->len > 40 ? 40 : (int)t->len;
    const char *dots = t->len > 40 ? "..." : "";
    switch (t->kind) {
    case CSG_TOK_EOF:
        snprintf(buf, size, "end of file");
        break;
    case CSG_TOK_ERROR:
        snprintf(buf, size, "an error");
        break;
    case CSG_TOK_STRING:
        snprintf(buf, size, "'\"%.*s%s\"'", n, t->text, dots);
        break;
    case CSG_TOK_DIRECTIVE:
        snprintf(buf, size, "'#%.*s%s'", n, t->text, dots);
        break;
    default:
        snprintf(buf, size, "'%.*s%s'", n, t->text, dots);
        break;
    }
}
