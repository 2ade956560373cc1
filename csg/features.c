/*
 * features.c — feature sets (features.h): their OpenCL build options and
 * their one-line description.  The per-kind names come from flat.h's
 * table (CSG_PRIM_KINDS), so a new kind is named and gets its
 * -DCSG_HAS_<KIND> without an edit here.
 */
#include "features.h"

#include <stdio.h>
#include <string.h>

#include "device/flat.h"
#include "flatten.h"

#define FEAT_KIND_NAME(ID, name) #name,
#define FEAT_KIND_MACRO(ID, name) "CSG_HAS_" #ID,
static const char *const feat_kind_names[CSG_PRIM_KIND_COUNT] = {CSG_PRIM_KINDS(FEAT_KIND_NAME)};
static const char *const feat_kind_macros[CSG_PRIM_KIND_COUNT] = {
    CSG_PRIM_KINDS(FEAT_KIND_MACRO)};

#define FEAT_ALL_KINDS ((1u << CSG_PRIM_KIND_COUNT) - 1u)
#define FEAT_SPECIALISED ((uint32_t)CSG_FEAT_CSG)

csg_features csg_features_all(void)
{
    csg_features f = {FEAT_ALL_KINDS, CSG_FEAT_ALL};
    return f;
}

csg_features csg_blob_features(const void *blob)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    csg_features f = {h->kinds, h->features};
    return f;
}

bool csg_features_cover(csg_features have, csg_features need)
{
    return (need.kinds & ~have.kinds) == 0 && (need.uses & ~have.uses) == 0;
}

csg_features csg_features_specialised(csg_features f)
{
    csg_features g = {f.kinds & FEAT_ALL_KINDS, f.uses & FEAT_SPECIALISED};
    return g;
}

/* Appends text at *at; false once it no longer fits. */
static bool feat_append(char *buf, size_t size, size_t *at, const char *text)
{
    int n = snprintf(buf + *at, size - *at, "%s", text);
    if (n < 0 || (size_t)n >= size - *at)
        return false;
    *at += (size_t)n;
    return true;
}

bool csg_features_cl_options(csg_features f, char *buf, size_t size)
{
    size_t at = 0;
    bool ok = size > 0;
    if (ok)
        buf[0] = '\0';
    f = csg_features_specialised(f);
    if ((f.kinds & FEAT_ALL_KINDS) == FEAT_ALL_KINDS && f.uses == FEAT_SPECIALISED)
        return ok; /* the general program */
    ok = ok && feat_append(buf, size, &at, " -DCSG_SPECIALISED");
    for (int k = 0; k < CSG_PRIM_KIND_COUNT; k++)
        if (f.kinds & (1u << k)) {
            ok = ok && feat_append(buf, size, &at, " -D") &&
                 feat_append(buf, size, &at, feat_kind_macros[k]);
        }
    if (!(f.uses & CSG_FEAT_CSG))
        ok = ok && feat_append(buf, size, &at, " -DCSG_NO_CSG");
    return ok;
}

/* The specialised part of f ("sphere box; csg"), appended at *at. */
static bool feat_append_program(csg_features f, char *buf, size_t size, size_t *at)
{
    bool ok = true, any = false;
    for (int k = 0; k < CSG_PRIM_KIND_COUNT; k++)
        if (f.kinds & (1u << k)) {
            ok = ok && feat_append(buf, size, at, any ? " " : "") &&
                 feat_append(buf, size, at, feat_kind_names[k]);
            any = true;
        }
    if (!any)
        ok = ok && feat_append(buf, size, at, "no primitives");
    return ok && feat_append(buf, size, at, f.uses & CSG_FEAT_CSG ? "; csg" : "; no csg");
}

bool csg_features_program_name(csg_features f, char *buf, size_t size)
{
    size_t at = 0;
    if (size == 0)
        return false;
    buf[0] = '\0';
    f = csg_features_specialised(f);
    if (f.kinds == FEAT_ALL_KINDS && f.uses == FEAT_SPECIALISED)
        return feat_append(buf, size, &at, "general");
    return feat_append_program(f, buf, size, &at);
}

bool csg_features_describe(csg_features f, char *buf, size_t size)
{
    size_t at = 0;
    bool ok = size > 0;
    if (ok)
        buf[0] = '\0';
    ok = ok && feat_append_program(f, buf, size, &at);
    ok = ok && feat_append(buf, size, &at,
                           f.uses & CSG_FEAT_XFORM ? " (the scene also: transforms"
                                                   : " (the scene also: no transforms");
    ok = ok && feat_append(buf, size, &at,
                           f.uses & CSG_FEAT_TRANSPARENT ? "; transparent" : "; opaque");
    ok = ok && feat_append(buf, size, &at,
                           f.uses & CSG_FEAT_REFLECT ? "; reflective" : "; no reflection");
    if (f.uses & CSG_FEAT_NO_SHADOW)
        ok = ok && feat_append(buf, size, &at, "; no_shadow objects");
    if (f.uses & CSG_FEAT_SHADOWLESS)
        ok = ok && feat_append(buf, size, &at, "; shadowless lights");
    return ok && feat_append(buf, size, &at, ")");
}
