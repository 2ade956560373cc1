/*
 * summary.h — `csgtrace check`: a one-screen description of a parsed scene
 * (objects by kind, CSG depth, lights, textures and interiors in use,
 * camera, background, global settings).  Independent of the image size.
 */
#ifndef CSG_SUMMARY_H
#define CSG_SUMMARY_H

#include <stdio.h>

#include "scene.h"

void csg_print_summary(const csg_scene *s, FILE *out);

#endif
