/*
 * load.c — scene files by format (load.h): the extension picks the
 * reader, and the image size follows what was asked, else the scene.
 */
#include "load.h"

#include <string.h>
#include <strings.h>

#include "lang/nff.h"
#include "lang/parser.h"

bool csg_is_nff(const char *name)
{
    size_t n = name ? strlen(name) : 0;
    return n >= 4 && strcasecmp(name + n - 4, ".nff") == 0;
}

/* NFF has no directives, includes or clock: the options do not apply. */
static bool nff_text(const char *name, const char *text, size_t len, const csg_parse_options *o,
                     csg_scene *s, csg_diag *d)
{
    (void)o;
    return csg_nff_parse_string(name, text, len, s, d);
}

static csg_text_parser parser_for(const char *name)
{
    return csg_is_nff(name) ? nff_text : csg_parse_string_opts;
}

bool csg_load_string(const char *name, const char *text, size_t len, const csg_parse_options *o,
                     csg_scene *s, csg_diag *d)
{
    return parser_for(name)(name, text, len, o, s, d);
}

bool csg_load_file(const char *path, const csg_parse_options *o, csg_scene *s, csg_diag *d)
{
    return csg_parse_file_as(path, o, s, d, parser_for(path));
}

void csg_image_size(const csg_scene *s, int want_width, int want_height, int *width, int *height)
{
    int w = want_width, h = want_height;
    if (s->width > 0 && s->height > 0) {
        if (!w && !h) {
            w = s->width;
            h = s->height;
        } else if (!w) {
            w = (int)((double)h * s->width / s->height + 0.5);
        } else if (!h) {
            h = (int)((double)w * s->height / s->width + 0.5);
        }
    }
    *width = w > 0 ? w : CSG_DEFAULT_WIDTH;
    *height = h > 0 ? h : CSG_DEFAULT_HEIGHT;
}
