/*
 * parser.h — the scene language (scenes/LANGUAGE.md) read into the scene
 * tree of scene.h.
 *
 * What the tree holds after a successful parse:
 *   - every object's xform is its complete object -> world transform (the
 *     transforms of all enclosing CSG objects composed in), so a leaf can be
 *     used on its own;
 *   - texture / interior are indices into the scene's tables; -1 only on a
 *     CSG child that has none of its own (it inherits from the nearest
 *     enclosing object that has one); a top-level object always has >= 0;
 *   - box corners are ordered (a = min, b = max); a plane's normal is a unit
 *     vector (POV-Ray normalises it and keeps the distance as written);
 *   - the camera is the last camera statement (has_camera false: none).
 */
#ifndef CSG_PARSER_H
#define CSG_PARSER_H

#include <stdbool.h>
#include <stddef.h>

#include "../diag.h"
#include "../scene.h"

/* Braces, objects, parentheses and vectors nested inside each other, and
 * the depth of the resulting CSG tree (through declared objects too). */
#define CSG_PARSE_MAX_NESTING 128
/* #include files open inside each other. */
#define CSG_PARSE_MAX_INCLUDE 32
/* Objects (tree nodes) created in one parse, copies of declared objects
 * included: bounds the memory a small file can ask for. */
#define CSG_PARSE_MAX_OBJECTS (1L << 22)

/* Parses a scene file. On failure returns false, d holds the one-line message
   "file:line:col: error: ..." and *s is left empty (freed). */
bool csg_parse_file(const char *path, csg_scene *s, csg_diag *d);
/* A reader of scene text (csg_parse_string, csg_nff_parse_string). */
typedef bool (*csg_text_parser)(const char *name, const char *text, size_t len, csg_scene *s,
                                csg_diag *d);
/* Reads the file `path` and parses it with `parse` (csg_parse_file is
   csg_parse_file_as(path, s, d, csg_parse_string)); the same contract. */
bool csg_parse_file_as(const char *path, csg_scene *s, csg_diag *d, csg_text_parser parse);
/* Same from memory (tests, fuzzing); `name` is used in messages and #include
   paths are resolved relative to the directory of `name`. */
bool csg_parse_string(const char *name, const char *text, size_t len, csg_scene *s, csg_diag *d);

/* The built-in colors.inc (colors.c): the number of colours, and the name
 * and rgbft value of the i-th one (NULL when i is out of range). */
int csg_builtin_color_count(void);
const char *csg_builtin_color_at(int i, double rgbft[5]);

#endif
