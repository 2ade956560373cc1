/*
 * lexer.h — tokens of the scene language (scenes/LANGUAGE.md).
 *
 * The lexer walks one source buffer (a file or an #include) and hands out
 * one token at a time with its file:line:col.  A UTF-8 byte-order mark at
 * the start of the buffer is skipped.  Keywords are classified here
 * (enum csg_kw) so the parser switches on integers; words that are POV-Ray
 * keywords csgtrace does not implement come back as CSG_KW_UNSUPPORTED so
 * the parser can name them in its message.
 */
#ifndef CSG_LEXER_H
#define CSG_LEXER_H

#include <stdbool.h>
#include <stddef.h>

#include "../diag.h"

enum csg_tok_kind {
    CSG_TOK_EOF,
    CSG_TOK_NUMBER,    /* number: a finite double                        */
    CSG_TOK_STRING,    /* text/len: the contents between the quotes      */
    CSG_TOK_WORD,      /* identifier or keyword (kw)                     */
    CSG_TOK_DIRECTIVE, /* '#' word: text/len the word after '#', kw      */
    CSG_TOK_PUNCT,     /* punct: one of { } < > ( ) [ ] , ; + - * / = ! & | ? : .
                          or one of the two-character operators below      */
    CSG_TOK_ERROR      /* stands for the current token after an error: it
                          matches nothing, so every parse step fails       */
};

/* The two-character operators, as csg_token.punct. */
enum { CSG_P_LE = 0x100, CSG_P_GE, CSG_P_NE };

enum csg_kw {
    CSG_KW_NONE = 0,    /* a plain identifier                             */
    CSG_KW_UNSUPPORTED, /* a POV-Ray word csgtrace does not implement     */
    /* objects */
    CSG_KW_SPHERE, CSG_KW_BOX, CSG_KW_CYLINDER, CSG_KW_CONE, CSG_KW_PLANE, CSG_KW_TORUS,
    CSG_KW_QUADRIC, CSG_KW_POLY, CSG_KW_QUARTIC, CSG_KW_CUBIC,
    CSG_KW_TRIANGLE, CSG_KW_SMOOTH_TRIANGLE, CSG_KW_POLYGON, CSG_KW_MESH, CSG_KW_PRISM,
    CSG_KW_TEXT,
    /* prism and text items */
    CSG_KW_LINEAR_SPLINE, CSG_KW_QUADRATIC_SPLINE, CSG_KW_CUBIC_SPLINE, CSG_KW_BEZIER_SPLINE,
    CSG_KW_LINEAR_SWEEP, CSG_KW_CONIC_SWEEP, CSG_KW_TTF,
    CSG_KW_UNION, CSG_KW_INTERSECTION, CSG_KW_DIFFERENCE, CSG_KW_MERGE,
    CSG_KW_OBJECT,
    /* statements */
    CSG_KW_CAMERA, CSG_KW_LIGHT_SOURCE, CSG_KW_BACKGROUND, CSG_KW_GLOBAL_SETTINGS,
    CSG_KW_SKY_SPHERE, CSG_KW_EMISSION,
    /* camera items */
    CSG_KW_PERSPECTIVE, CSG_KW_ORTHOGRAPHIC, CSG_KW_LOCATION, CSG_KW_LOOK_AT,
    CSG_KW_DIRECTION, CSG_KW_UP, CSG_KW_RIGHT, CSG_KW_SKY, CSG_KW_ANGLE,
    CSG_KW_ULTRA_WIDE_ANGLE, CSG_KW_PANORAMIC, CSG_KW_SPHERICAL,
    /* global settings */
    CSG_KW_ASSUMED_GAMMA, CSG_KW_MAX_TRACE_LEVEL, CSG_KW_ADC_BAILOUT,
    CSG_KW_AMBIENT_LIGHT,
    /* light */
    CSG_KW_SHADOWLESS, CSG_KW_SPOTLIGHT, CSG_KW_POINT_AT, CSG_KW_TIGHTNESS, CSG_KW_RADIUS,
    CSG_KW_FALLOFF, CSG_KW_FADE_DISTANCE, CSG_KW_FADE_POWER, CSG_KW_FADE_COLOR,
    CSG_KW_PARALLEL, CSG_KW_AREA_LIGHT, CSG_KW_ADAPTIVE, CSG_KW_JITTER, CSG_KW_CIRCULAR,
    CSG_KW_ORIENT, CSG_KW_LOOKS_LIKE, CSG_KW_MEDIA_ATTENUATION, CSG_KW_MEDIA_INTERACTION,
    /* fog */
    CSG_KW_FOG, CSG_KW_DISTANCE, CSG_KW_FOG_TYPE, CSG_KW_FOG_ALT, CSG_KW_FOG_OFFSET,
    CSG_KW_TURB_DEPTH,
    /* colours */
    CSG_KW_COLOR, CSG_KW_RGB, CSG_KW_RGBF, CSG_KW_RGBT, CSG_KW_RGBFT,
    CSG_KW_SRGB, CSG_KW_SRGBF, CSG_KW_SRGBT, CSG_KW_SRGBFT,
    CSG_KW_RED, CSG_KW_GREEN, CSG_KW_BLUE, CSG_KW_FILTER, CSG_KW_TRANSMIT,
    CSG_KW_GRAY,
    /* modifiers */
    CSG_KW_PIGMENT, CSG_KW_FINISH, CSG_KW_TEXTURE, CSG_KW_INTERIOR, CSG_KW_NORMAL,
    CSG_KW_INTERIOR_TEXTURE,
    CSG_KW_MATERIAL, CSG_KW_TEXTURE_MAP, CSG_KW_BUMP_SIZE, CSG_KW_ACCURACY,
    CSG_KW_NO_BUMP_SCALE, CSG_KW_CONTROL0, CSG_KW_CONTROL1, CSG_KW_NUMBER_OF_WAVES,
    CSG_KW_TRANSLATE, CSG_KW_ROTATE, CSG_KW_SCALE, CSG_KW_MATRIX, CSG_KW_TRANSFORM,
    CSG_KW_INVERSE,
    CSG_KW_NO_SHADOW, CSG_KW_OPEN, CSG_KW_HOLLOW, CSG_KW_STURM,
    /* pigment patterns and waves (which one: csg_pattern_keyword,
       csg_wave_keyword below), and their modifiers */
    CSG_KW_PATTERN, CSG_KW_WAVE, CSG_KW_COLOR_MAP, CSG_KW_FREQUENCY, CSG_KW_PHASE,
    CSG_KW_AGATE_TURB, CSG_KW_TURBULENCE, CSG_KW_OCTAVES, CSG_KW_OMEGA,
    CSG_KW_LAMBDA, CSG_KW_NOISE_GENERATOR, CSG_KW_PIGMENT_MAP, CSG_KW_QUICK_COLOR,
    CSG_KW_FORM, CSG_KW_METRIC, CSG_KW_OFFSET, CSG_KW_SOLID, CSG_KW_BRICK_SIZE, CSG_KW_MORTAR,
    /* finish / interior items */
    CSG_KW_AMBIENT, CSG_KW_DIFFUSE, CSG_KW_SPECULAR, CSG_KW_ROUGHNESS,
    CSG_KW_PHONG, CSG_KW_PHONG_SIZE, CSG_KW_BRILLIANCE, CSG_KW_METALLIC, CSG_KW_BOUNDED_BY,
    CSG_KW_CLIPPED_BY,
    CSG_KW_CLOCK_ON, CSG_KW_FRAME_NUMBER, CSG_KW_REFLECTION, CSG_KW_IOR,
    CSG_KW_CONSERVE_ENERGY, CSG_KW_EXPONENT, CSG_KW_FRESNEL, CSG_KW_REFLECTION_EXPONENT,
    CSG_KW_CRAND, CSG_KW_IRID, CSG_KW_THICKNESS, CSG_KW_IRID_WAVELENGTH,
    /* constants */
    CSG_KW_PI, CSG_KW_X, CSG_KW_Y, CSG_KW_Z, CSG_KW_T, CSG_KW_U, CSG_KW_V,
    CSG_KW_TRUE, CSG_KW_FALSE, CSG_KW_CLOCK, CSG_KW_VERSION,
    /* float functions */
    CSG_KW_ABS, CSG_KW_ACOS, CSG_KW_ACOSH, CSG_KW_ASIN, CSG_KW_ASINH, CSG_KW_ATAN,
    CSG_KW_ATAN2, CSG_KW_ATANH, CSG_KW_CEIL, CSG_KW_COS, CSG_KW_COSH, CSG_KW_DEGREES,
    CSG_KW_DIV, CSG_KW_EXP, CSG_KW_FLOOR, CSG_KW_INT, CSG_KW_LN, CSG_KW_LOG, CSG_KW_MAX,
    CSG_KW_MIN, CSG_KW_MOD, CSG_KW_POW, CSG_KW_RADIANS, CSG_KW_SELECT, CSG_KW_SIN,
    CSG_KW_SINH, CSG_KW_SQR, CSG_KW_SQRT, CSG_KW_TAN, CSG_KW_TANH, CSG_KW_SEED, CSG_KW_RAND,
    CSG_KW_VDOT, CSG_KW_VLENGTH, CSG_KW_STRLEN, CSG_KW_STRCMP, CSG_KW_VAL, CSG_KW_ASC,
    CSG_KW_DEFINED, CSG_KW_DIMENSIONS, CSG_KW_DIMENSION_SIZE, CSG_KW_BITWISE_AND,
    CSG_KW_BITWISE_OR, CSG_KW_BITWISE_XOR, CSG_KW_FILE_EXISTS,
    /* vector functions */
    CSG_KW_VAXIS_ROTATE, CSG_KW_VCROSS, CSG_KW_VNORMALIZE, CSG_KW_VROTATE,
    /* string functions */
    CSG_KW_CONCAT, CSG_KW_STR, CSG_KW_CHR, CSG_KW_SUBSTR, CSG_KW_STRUPR, CSG_KW_STRLWR,
    CSG_KW_VSTR,
    /* arrays */
    CSG_KW_ARRAY,
    /* directives (after '#'): #declare #local #include #version above the
     * rest; 'version' is also the word CSG_KW_VERSION */
    CSG_KW_DECLARE, CSG_KW_LOCAL, CSG_KW_INCLUDE, CSG_KW_UNDEF, CSG_KW_DEFAULT,
    CSG_KW_IF, CSG_KW_IFDEF, CSG_KW_IFNDEF, CSG_KW_ELSE, CSG_KW_ELSEIF, CSG_KW_END,
    CSG_KW_WHILE, CSG_KW_FOR, CSG_KW_SWITCH, CSG_KW_CASE, CSG_KW_RANGE, CSG_KW_BREAK,
    CSG_KW_MACRO, CSG_KW_DEBUG, CSG_KW_WARNING, CSG_KW_ERROR,
    CSG_KW_FOPEN, CSG_KW_FCLOSE, CSG_KW_READ, CSG_KW_WRITE
};

typedef struct {
    enum csg_tok_kind kind;
    enum csg_kw kw;     /* CSG_TOK_WORD / CSG_TOK_DIRECTIVE                */
    csg_loc loc;        /* where the token starts                          */
    size_t pos;         /* its first byte in the source (a directive: '#') */
    const char *text;   /* the token's characters in the source (not NUL-terminated) */
    size_t len;
    double number;      /* CSG_TOK_NUMBER                                  */
    int punct;          /* CSG_TOK_PUNCT: the character or CSG_P_*         */
} csg_token;

typedef struct {
    const char *file;   /* for locations; must outlive the tokens          */
    const char *src;    /* the buffer, len bytes (NUL bytes are errors)    */
    size_t len;
    size_t pos;         /* next byte to read                               */
    int line, col;      /* of src[pos]                                     */
} csg_lexer;

void csg_lexer_init(csg_lexer *lx, const char *file, const char *src, size_t len);
/* The next token; false (d filled) on a lexical error: an unterminated
 * comment or string, a malformed or non-finite number, a stray character. */
bool csg_lexer_next(csg_lexer *lx, csg_token *t, csg_diag *d);
/* The keyword of a word, CSG_KW_NONE for an identifier. */
enum csg_kw csg_keyword(const char *text, size_t len, bool directive);
/* The pattern a CSG_KW_PATTERN word names (enum csg_pattern, the table of
 * csg/device/patterns.h), or -1 for another word; *alias (unless NULL):
 * the word is one of CSG_PATTERN_ALIASES, not the pattern's own name. */
int csg_pattern_keyword(const char *text, size_t len, bool *alias);
/* The wave a CSG_KW_WAVE word names (enum csg_wave), or -1. */
int csg_wave_keyword(const char *text, size_t len);
/* Writes a short quoted description of t into buf ("'sphere'", "end of file"). */
void csg_token_describe(const csg_token *t, char *buf, size_t size);

#endif
