/*
 * load.c — scene files by format (load.h): the extension picks the
 * reader, and the image size follows what was asked, else the scene.
 */
#include "load.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "lang/nff.h"
#include "lang/parser.h"

bool csg_is_nff(const char *name)
{
    size_t n = name ? strlen(name) : 0;
    return n >= 4 && strcasecmp(name + n - 4, ".nff") == 0;
}

bool csg_load_string(const char *name, const char *text, size_t len, csg_scene *s, csg_diag *d)
{
    if (csg_is_nff(name))
        return csg_nff_parse_string(name, text, len, s, d);
    return csg_parse_string(name, text, len, s, d);
}

/* The whole file in memory (NUL-terminated); NULL with *err set. */
static char *load_read(const char *path, size_t *len, int *err)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    size_t cap = 0, n = 0;
    if (!f) {
        *err = errno;
        return NULL;
    }
    for (;;) {
        if (cap - n < 65536) {
            cap = cap ? 2 * cap : 1 << 20;
            char *nb = realloc(buf, cap + 1);
            if (!nb) {
                *err = ENOMEM;
                free(buf);
                fclose(f);
                return NULL;
            }
            buf = nb;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0)
            break;
    }
    *err = ferror(f) ? EIO : 0;
    fclose(f);
    if (*err) {
        free(buf);
        return NULL;
    }
    buf[n] = '\0';
    *len = n;
    return buf;
}

bool csg_load_file(const char *path, csg_scene *s, csg_diag *d)
{
    if (!csg_is_nff(path))
        return csg_parse_file(path, s, d);
    size_t len = 0;
    int err = 0;
    char *text = load_read(path, &len, &err);
    if (!text) {
        csg_scene_init(s);
        csg_error_plain(d, "cannot read scene '%s': %s", path, strerror(err));
        return false;
    }
    bool ok = csg_nff_parse_string(path, text, len, s, d);
    free(text);
    return ok;
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
