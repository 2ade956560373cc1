/*
 * summary.c — the scene summary printed by `csgtrace check`.
 *
 * One walk over the tree counts the objects by kind, the CSG depth (a
 * top-level primitive has depth 1), the inverted / open / no_shadow flags
 * and marks the texture and interior table entries that are reachable.  The
 * recursion is bounded by the parser's CSG_PARSE_MAX_NESTING.
 */
#include "summary.h"

#include <stdbool.h>
#include <stdlib.h>

typedef struct {
    long by_kind[CSG_OBJ_KIND_COUNT];
    long inverted, open, no_shadow;
    long mesh_triangles;
    long clipped, bounded, linked; /* objects with clipped_by, bounded_by, both one list */
    int max_depth;
    bool *texture_used;  /* texture_count entries, or NULL */
    bool *interior_used; /* interior_count entries, or NULL */
} tally;

static void walk(const csg_scene *s, const csg_object *o, int depth, tally *t)
{
    t->by_kind[o->kind]++;
    t->inverted += o->inverse;
    t->open += o->open;
    t->no_shadow += o->no_shadow;
    t->clipped += o->clip_count > 0;
    t->bounded += o->bound_count > 0;
    t->linked += o->bound_is_clip;
    if (o->kind == CSG_OBJ_MESH)
        t->mesh_triangles += o->vert_count / 3;
    if (depth > t->max_depth)
        t->max_depth = depth;
    if (t->texture_used && o->texture >= 0 && o->texture < s->texture_count)
        t->texture_used[o->texture] = true;
    if (t->interior_used && o->interior >= 0 && o->interior < s->interior_count)
        t->interior_used[o->interior] = true;
    for (int i = 0; i < o->child_count; i++)
        walk(s, o->children[i], depth + 1, t);
}

static int count_true(const bool *b, int n)
{
    int c = 0;
    for (int i = 0; b && i < n; i++)
        c += b[i];
    return c;
}

static void print_vec(FILE *out, const char *label, dvec3 v)
{
    fprintf(out, "  %-10s <%g, %g, %g>\n", label, v.x, v.y, v.z);
}

void csg_print_summary(const csg_scene *s, FILE *out)
{
    tally t = {{0}, 0, 0, 0, 0, 0, 0, 0, 0, NULL, NULL};
    t.texture_used = s->texture_count > 0 ? calloc((size_t)s->texture_count, sizeof(bool)) : NULL;
    t.interior_used =
        s->interior_count > 0 ? calloc((size_t)s->interior_count, sizeof(bool)) : NULL;
    for (int i = 0; i < s->object_count; i++)
        walk(s, s->objects[i], 1, &t);

    long prims = 0, csg = 0;
    for (int k = 0; k < CSG_OBJ_KIND_COUNT; k++)
        *(csg_object_is_leaf(k) ? &prims : &csg) += t.by_kind[k];

    fprintf(out, "scene: %s\n", s->path ? s->path : "<input>");
    fprintf(out, "objects: %d top-level, %ld primitives, %ld CSG operations, CSG depth %d\n",
            s->object_count, prims, csg, t.max_depth);
    fprintf(out, " ");
    for (int k = 0; k < CSG_OBJ_KIND_COUNT; k++)
        if (t.by_kind[k]) {
            fprintf(out, " %s %ld", csg_object_kind_name(k), t.by_kind[k]);
            if (k == CSG_OBJ_MESH)
                fprintf(out, " (%ld triangles)", t.mesh_triangles);
        }
    fprintf(out, "%s\n", prims + csg ? "" : " (none)");
    if (t.inverted || t.open || t.no_shadow)
        fprintf(out, "  inverse %ld, open %ld, no_shadow %ld\n", t.inverted, t.open, t.no_shadow);
    if (t.clipped || t.bounded) /* (their objects are not counted above) */
        fprintf(out, "  clipped_by on %ld, bounded_by on %ld (%ld linked to the clip)\n", t.clipped,
                t.bounded, t.linked);
    int shadowless = 0;
    for (int i = 0; i < s->light_count; i++)
        shadowless += s->lights[i].shadowless;
    fprintf(out, "lights: %d (%d shadowless)\n", s->light_count, shadowless);
    int reflective = 0, transparent = 0;
    for (int i = 0; i < s->texture_count; i++) {
        if (!t.texture_used || !t.texture_used[i])
            continue;
        const csg_texture *x = &s->textures[i];
        reflective += x->finish.reflection[0] > 0 || x->finish.reflection[1] > 0 ||
                      x->finish.reflection[2] > 0;
        transparent += x->pigment.rgbft[3] > 0 || x->pigment.rgbft[4] > 0;
    }
    fprintf(out, "textures: %d used (%d reflective, %d transparent); interiors: %d used\n",
            count_true(t.texture_used, s->texture_count), reflective, transparent,
            count_true(t.interior_used, s->interior_count));
    if (s->has_camera) {
        fprintf(out, "camera: written at %d:%d\n", s->camera.loc.line, s->camera.loc.col);
    } else {
        fprintf(out, "camera: none given (POV-Ray's default)\n");
    }
    print_vec(out, "location", s->camera.location);
    print_vec(out, "direction", s->camera.direction);
    print_vec(out, "up", s->camera.up);
    print_vec(out, "right", s->camera.right);
    fprintf(out, "background: rgbft <%g, %g, %g, %g, %g>\n", s->background[0], s->background[1],
            s->background[2], s->background[3], s->background[4]);
    fprintf(out, "global_settings: assumed_gamma %g, max_trace_level %d, adc_bailout %g, "
                 "ambient_light <%g, %g, %g>\n",
            s->globals.assumed_gamma, s->globals.max_trace_level, s->globals.adc_bailout,
            s->globals.ambient_light[0], s->globals.ambient_light[1], s->globals.ambient_light[2]);
    free(t.texture_used);
    free(t.interior_used);
}
