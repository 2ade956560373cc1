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
 *   - the camera is the last camera statement (has_camera false: none);
 *   - a patterned pigment's xform is its complete pattern -> world
 *     transform.
 */
#ifndef CSG_PARSER_H
#define CSG_PARSER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "../diag.h"
#include "../scene.h"

/* Braces, objects, parentheses, vectors and directives nested inside each
 * other, and the depth of the resulting CSG tree (through declared objects
 * too). */
#define CSG_PARSE_MAX_NESTING 128
/* #include files open inside each other. */
#define CSG_PARSE_MAX_INCLUDE 32
/* Objects (tree nodes) created in one parse, copies of declared objects
 * included: bounds the memory a small file can ask for. */
#define CSG_PARSE_MAX_OBJECTS (1L << 22)

/* Macro calls open inside each other (POV-Ray allows about 100). */
#define CSG_PARSE_MAX_MACRO_DEPTH 100
/* Directive blocks (#if, #while, #for, #switch) open inside each other. */
#define CSG_PARSE_MAX_CONDS 256
/* Tokens read in one parse, the ones skipped and re-read by loops and
 * macro calls included: bounds the time a loop that never ends can take. */
#define CSG_PARSE_MAX_TOKENS 100000000L
/* Bytes of a scene or include file (only regular files are read): the
 * most whose every line and column (bytes) an int of csg_loc can count.
 * A file is read whole, so what it costs is its own size; the SPD scenes
 * scaled up (tetra11: 4 194 304 triangles) take 0.4 GB. */
#define CSG_PARSE_MAX_FILE 2147483647L /* INT_MAX (source.c checks it) */
/* Elements of one array, and bytes of one string. */
#define CSG_PARSE_MAX_ARRAY (1L << 22)
#define CSG_PARSE_MAX_STRING (1L << 20)
/* Bytes of the files a scene writes (#write: kept in memory until the
 * parse ends), all together; bytes of the files open for reading (#fopen
 * ... read: each a copy), all together; files open at once. */
#define CSG_PARSE_MAX_WRITTEN (64L << 20)
#define CSG_PARSE_MAX_DATA (64L << 20)
#define CSG_PARSE_MAX_OPEN_FILES 256

/* What the scene can see of the render, and where #include looks. */
typedef struct {
    int image_width, image_height; /* image_width, image_height; <= 0: 320 x 240 */
    double clock;                  /* clock (--clock); 0 by default             */
    const char *const *library_paths; /* folders searched by #include after the
                                         including file's and the scene's (the
                                         command line's: --library-path, then
                                         $CSGTRACE_LIBRARY_PATH's)              */
    int library_path_count;
    bool no_default_library;       /* do not add POV-Ray's include folder    */
    long max_tokens;               /* <= 0: CSG_PARSE_MAX_TOKENS               */
    FILE *messages;                /* #debug and #warning text; NULL: dropped  */
    /* Called with the path of every file an #include reads (render.c
     * refuses outputs that would overwrite one); NULL: not called. */
    void (*on_include)(void *arg, const char *path);
    void *on_include_arg;
} csg_parse_options;

/* The defaults: 320 x 240, clock 0, the default library, no messages. */
void csg_parse_options_default(csg_parse_options *o);
/* The default library folders, searched last (POV-Ray's include folder
 * when it exists): the i-th, NULL past the end. */
const char *csg_default_library(int i);

/* Parses a scene file. On failure returns false, d holds the one-line message
   "file:line:col: error: ..." and *s is left empty (freed).  o NULL: the
   defaults. */
bool csg_parse_file_opts(const char *path, const csg_parse_options *o, csg_scene *s,
                         csg_diag *d);
bool csg_parse_file(const char *path, csg_scene *s, csg_diag *d);
/* A reader of scene text (csg_parse_string_opts; NFF's through csg/load.c). */
typedef bool (*csg_text_parser)(const char *name, const char *text, size_t len,
                                const csg_parse_options *o, csg_scene *s, csg_diag *d);
/* Reads the file `path` (a regular file of at most CSG_PARSE_MAX_FILE bytes)
   and parses it with `parse` (csg_parse_file_opts is
   csg_parse_file_as(path, o, s, d, csg_parse_string_opts)); the same contract. */
bool csg_parse_file_as(const char *path, const csg_parse_options *o, csg_scene *s, csg_diag *d,
                       csg_text_parser parse);
/* Same from memory (tests, fuzzing); `name` is used in messages and #include
   paths are resolved relative to the directory of `name`. */
bool csg_parse_string_opts(const char *name, const char *text, size_t len,
                           const csg_parse_options *o, csg_scene *s, csg_diag *d);
bool csg_parse_string(const char *name, const char *text, size_t len, csg_scene *s, csg_diag *d);

/* The built-in colors.inc (colors.c): the number of colours, and the name
 * and rgbft value of the i-th one (NULL when i is out of range). */
int csg_builtin_color_count(void);
const char *csg_builtin_color_at(int i, double rgbft[5]);

#endif
