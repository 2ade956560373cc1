/*
 * csg_double.h — the shared geometry headers of csg/ a second time, in the
 * double build, inside a translation unit that already holds the float
 * build (tests only: the test programs are compiled once, in float, but the
 * OpenCL tests compare against C in both precisions).
 *
 * Every identifier the headers declare gets a `dbl_` prefix through a macro,
 * so the double copy does not collide with the float one; the code itself is
 * the very same source text.  After this header, `real`, `csg_prim`,
 * `csg_trace_nearest` ... name the double versions: include it after every
 * function that uses the float ones.  When csg/ grows a new function or
 * type, the compiler reports the collision here: add the name below.
 */
#ifndef TESTS_CSG_DOUBLE_H
#define TESTS_CSG_DOUBLE_H

#ifndef CSG_CAMERA_H
#error "include csg/camera.h (the float build) first"
#endif
#ifdef CSG_DOUBLE
#error "csg_double.h is for a float translation unit"
#endif

#undef CSG_PORTABLE_H
#undef CSG_VEC_H
#undef CSG_FLAT_H
#undef CSG_INTERSECT_H
#undef CSG_CAMERA_H
#undef R
#undef r_sqrt
#undef r_fabs
#undef r_fmin
#undef r_fmax
#define CSG_DOUBLE 1

/* types */
#define real dbl_real
#define vec3 dbl_vec3
#define csg_prim dbl_csg_prim
#define csg_node dbl_csg_node
#define csg_root dbl_csg_root
#define csg_camera dbl_csg_camera
#define csg_material dbl_csg_material
#define csg_flat_light dbl_csg_flat_light
#define csg_ray dbl_csg_ray
#define csg_spans dbl_csg_spans
#define csg_view dbl_csg_view
#define csg_hit dbl_csg_hit
/* enums */
#define csg_prim_kind dbl_csg_prim_kind
#define csg_prim_flags dbl_csg_prim_flags
#define csg_surface dbl_csg_surface
#define csg_op dbl_csg_op
#define CSG_PRIM_SPHERE dbl_CSG_PRIM_SPHERE
#define CSG_PRIM_BOX dbl_CSG_PRIM_BOX
#define CSG_PRIM_CONE dbl_CSG_PRIM_CONE
#define CSG_PRIM_PLANE dbl_CSG_PRIM_PLANE
#define CSG_PF_XFORM dbl_CSG_PF_XFORM
#define CSG_PF_OPEN dbl_CSG_PF_OPEN
#define CSG_PF_INVERT dbl_CSG_PF_INVERT
#define CSG_PF_NO_SHADOW dbl_CSG_PF_NO_SHADOW
#define CSG_SURF_SPHERE dbl_CSG_SURF_SPHERE
#define CSG_SURF_BOX_NEG_X dbl_CSG_SURF_BOX_NEG_X
#define CSG_SURF_CONE_SIDE dbl_CSG_SURF_CONE_SIDE
#define CSG_SURF_CONE_BASE dbl_CSG_SURF_CONE_BASE
#define CSG_SURF_CONE_TOP dbl_CSG_SURF_CONE_TOP
#define CSG_SURF_PLANE dbl_CSG_SURF_PLANE
#define CSG_OP_PRIM dbl_CSG_OP_PRIM
#define CSG_OP_UNION dbl_CSG_OP_UNION
#define CSG_OP_INTERSECT dbl_CSG_OP_INTERSECT
/* functions */
#define v3 dbl_v3
#define v3_add dbl_v3_add
#define v3_sub dbl_v3_sub
#define v3_mul dbl_v3_mul
#define v3_scale dbl_v3_scale
#define v3_neg dbl_v3_neg
#define v3_dot dbl_v3_dot
#define v3_cross dbl_v3_cross
#define v3_length dbl_v3_length
#define v3_normalize dbl_v3_normalize
#define v3_madd dbl_v3_madd
#define v3_load dbl_v3_load
#define csg_xform_point dbl_csg_xform_point
#define csg_xform_vector dbl_csg_xform_vector
#define csg_xform_normal dbl_csg_xform_normal
#define csg_ray_to_local dbl_csg_ray_to_local
#define csg_sphere_span dbl_csg_sphere_span
#define csg_slab dbl_csg_slab
#define csg_box_span dbl_csg_box_span
#define csg_cone_span dbl_csg_cone_span
#define csg_plane_span dbl_csg_plane_span
#define csg_prim_span dbl_csg_prim_span
#define csg_spans_clear dbl_csg_spans_clear
#define csg_spans_push dbl_csg_spans_push
#define csg_surf_of dbl_csg_surf_of
#define csg_leaf_spans dbl_csg_leaf_spans
#define csg_spans_union dbl_csg_spans_union
#define csg_spans_intersect dbl_csg_spans_intersect
#define csg_spans_copy dbl_csg_spans_copy
#define csg_box_overlaps dbl_csg_box_overlaps
#define csg_aabb_overlaps dbl_csg_aabb_overlaps
#define csg_try_root dbl_csg_try_root
#define csg_bvh_node dbl_csg_bvh_node
#define csg_root_spans dbl_csg_root_spans
#define csg_first_boundary dbl_csg_first_boundary
#define csg_trace_nearest dbl_csg_trace_nearest
#define csg_local_normal dbl_csg_local_normal
#define csg_surface_normal dbl_csg_surface_normal
#define csg_primary_ray dbl_csg_primary_ray
#define csg_camera_ray dbl_csg_camera_ray
#define csg_sample_ray dbl_csg_sample_ray
#define csg_sample_offset dbl_csg_sample_offset

#include "../csg/camera.h"

#endif
