/*
 * vec.h — three-component vectors of `real`, shared by C and OpenCL C:
 * the one-ray compilation of vec_lanes.h (vec3, v3_add, v3_dot, r_fmin,
 * r_fmax, ...; see lanes.h).
 */
#ifndef CSG_VEC_H
#define CSG_VEC_H

#include "portable.h"

#include "vec_lanes.h"

#endif
