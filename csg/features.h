/*
 * features.h — what a scene uses (device/flat.h: csg_blob_header.kinds and
 * .features, recorded by the flattener, checked by the blob validator) and
 * what code specialised on it looks like: the -D options of the OpenCL
 * program (host/ocl.c; csg/device/spec.h reads them) and the line
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

/* The set code is specialised on for a scene that uses f: f's kinds and
 * its CSG and transform bits (the ones the OpenCL program removes code
 * for); the material bits are kept apart (they only describe the scene). */
csg_features csg_features_geometry(csg_features f);

/* The OpenCL build options of the program specialised on f (geometry
 * bits only), e.g. " -DCSG_SPECIALISED -DCSG_HAS_SPHERE -DCSG_NO_CSG
 * -DCSG_NO_TRANSFORM"; "" for the general program (f covers everything).
 * False when buf is too small. */
bool csg_features_cl_options(csg_features f, char *buf, size_t size);

/* One line without the newline, e.g. "sphere box; no csg; no transforms;
 * opaque; no reflection" (check's "specialised:" line).  False when buf
 * is too small. */
bool csg_features_describe(csg_features f, char *buf, size_t size);

#endif
