/*
 * layout_fields.cl — the list of every shared struct of csg/device/flat.h and each
 * of its fields, as an X-macro.  Included by the probe kernel (primary.cl,
 * through the -I of the build) and by tests/test_layout.c, which expand it
 * the same way, so the device's and the host's sizeof/offsetof lists line
 * up entry by entry.  A new field in flat.h goes here too.
 *
 * CSG_LAYOUT_FIELDS(S, F): S(type) gives the size of a struct, F(type, field)
 * the offset of one field, in this order.
 */
#ifndef CSG_LAYOUT_FIELDS_CL
#define CSG_LAYOUT_FIELDS_CL

#define CSG_LAYOUT_FIELDS(S, F)                                                     \
    S(real)                                                                         \
    S(csg_prim) F(csg_prim, kind) F(csg_prim, flags) F(csg_prim, material)          \
        F(csg_prim, root) F(csg_prim, p) F(csg_prim, inv)                           \
    S(csg_node) F(csg_node, op) F(csg_node, prim)                                   \
    S(csg_root) F(csg_root, first_node) F(csg_root, node_count)                     \
        F(csg_root, stack_depth) F(csg_root, pad) F(csg_root, lo) F(csg_root, hi)   \
    S(csg_camera) F(csg_camera, location) F(csg_camera, direction)                  \
        F(csg_camera, right) F(csg_camera, up)

#endif
