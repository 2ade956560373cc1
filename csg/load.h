/*
 * load.h — a scene file into the scene tree, whatever its format: the one
 * place that dispatches on the file name (".nff": Neutral File Format,
 * csg/lang/nff.h; anything else: the POV-Ray subset, csg/lang/parser.h).
 * Every command that reads a scene (render, compare, check, export, gen's
 * measurement) goes through here.
 */
#ifndef CSG_LOAD_H
#define CSG_LOAD_H

#include <stdbool.h>
#include <stddef.h>

#include "diag.h"
#include "lang/parser.h"
#include "scene.h"

/* The default image width and height when none is given and the scene
 * asks for none. */
#define CSG_DEFAULT_WIDTH 320
#define CSG_DEFAULT_HEIGHT 240

/* true when `name` ends in ".nff" (any case). */
bool csg_is_nff(const char *name);
/* Reads and parses a scene file; false with d filled on failure.  o: the
 * POV-Ray reader's options (clock, library folders, messages); NULL: the
 * defaults. */
bool csg_load_file(const char *path, const csg_parse_options *o, csg_scene *s, csg_diag *d);
/* The same from memory; `name` picks the format and names the messages. */
bool csg_load_string(const char *name, const char *text, size_t len, const csg_parse_options *o,
                     csg_scene *s, csg_diag *d);
/* The image size of a render: what was asked (0: not given), else the
 * scene's own (NFF's resolution; the other side kept in its aspect when
 * only one is given), else CSG_DEFAULT_WIDTH x CSG_DEFAULT_HEIGHT. */
void csg_image_size(const csg_scene *s, int want_width, int want_height, int *width, int *height);

#endif
