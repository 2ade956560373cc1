/*
 * features.h — what a scene uses (device/flat.h: csg_blob_header.kinds and
 * .features, recorded by the flattener, checked by the blob validator) and
 * what code specialised on it looks like: the -D options of the OpenCL
 * program (host/pass/ocl.c; csg/device/spec.h reads them) and the line
 * `csgtrace check` prints.
 */
#ifndef CSG_FEATURES_H
#define CSG_FEATURES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* A feature set: bit 1 << kind of every primitive kind, and the
 * enum csg_feature bits. */
typedef struct {
    uint32_t kinds;
    uint32_t uses;
} csg_features;

/* Everything: what a general (unspecialised) program handles. */
csg_features csg_features_all(void);

/* The set recorded in a (valid) blob's header. */
csg_features csg_blob_features(const void *blob);

/* Code built for `have` can run a scene that uses `need`. */
bool csg_features_cover(csg_features have, csg_features need);

/* The part of f code is specialised on: its kinds and its CSG bit (what
 * the OpenCL program leaves out when unused: csg/device/spec.h).  The
 * other bits only describe the scene: specialising on transforms was
 * measured and did not pay (bench/SPEED.md). */
csg_features csg_features_specialised(csg_features f);

/* The OpenCL build options of the program specialised on f (its
 * specialised part only), e.g. " -DCSG_SPECIALISED -DCSG_HAS_SPHERE
 * -DCSG_NO_CSG"; "" for the general program (every kind, CSG).  False
 * when buf is too small. */
bool csg_features_cl_options(csg_features f, char *buf, size_t size);

/* What a program built for f handles, e.g. "sphere plane; no csg", or
 * "general" (every kind and CSG: the program without -D options).  False
 * when buf is too small. */
bool csg_features_program_name(csg_features f, char *buf, size_t size);

/* One line without the newline: what is specialised, then the scene's
 * other features, e.g. "sphere box; no csg (the scene also: no
 * transforms; opaque; no reflection)" (check's "specialised:" line).
 * False when buf is too small. */
bool csg_features_describe(csg_features f, char *buf, size_t size);

#endif
