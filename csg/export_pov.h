/*
 * export_pov.h — a parsed scene (scene.h) written back as POV-Ray 3.7 SDL.
 *
 * The output renders in POV-Ray with the same geometry and camera as
 * csgtrace sees it: every vector resolved (no look_at, no #declare), every
 * primitive with its complete object -> world transform as a `matrix`,
 * textures resolved (inheritance applied) on the primitives.
 *
 * flat = true writes the "object colour" version used by the geometry
 * cross-check (tests/crosscheck_povray.sh): every surface shows exactly
 * its pigment's rgb (finish { ambient 1 diffuse 0 }, ambient_light 1,
 * max_trace_level 1, no filter / transmit, no interiors), so a POV-Ray
 * render and a csgtrace render can be compared pixel by pixel.
 */
#ifndef CSG_EXPORT_POV_H
#define CSG_EXPORT_POV_H

#include <stdbool.h>
#include <stdio.h>

#include "diag.h"
#include "scene.h"

/* Writes s to out; false (d filled) on a malformed tree or a write error. */
bool csg_export_pov(const csg_scene *s, FILE *out, bool flat, csg_diag *d);

#endif
