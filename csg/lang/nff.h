/*
 * nff.h — Eric Haines' Neutral File Format (the SPD benchmark scenes) read
 * into the scene tree of scene.h.  scenes/LANGUAGE.md ("NFF scenes") says
 * what each entity becomes and where the meaning differs.
 */
#ifndef CSG_NFF_H
#define CSG_NFF_H

#include <stdbool.h>
#include <stddef.h>

#include "../diag.h"
#include "../scene.h"

/* Entities one file may hold (objects, lights, materials together), and
 * vertices one polygon may have: bounds on the memory a file can ask for
 * (an entity's object takes about 300 bytes while the scene lives; the
 * SPD's tetra12 has 16 777 216 triangles, a third of the bound). */
#define CSG_NFF_MAX_ENTITIES (1L << 26)
#define CSG_NFF_MAX_VERTICES 1000000

/* Parses NFF text; `name` is used in messages.  On failure returns false,
 * d holds the one-line message "file:line:col: error: ..." and *s is left
 * empty (freed). */
bool csg_nff_parse_string(const char *name, const char *text, size_t len, csg_scene *s,
                          csg_diag *d);

#endif
