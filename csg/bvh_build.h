/*
 * bvh_build.h — the BVH over the bounded roots of a flattened scene, built
 * from their world boxes in double (binned SAH, csg/bvh_build.c).  The
 * flattener (csg/flatten.c) stores its boxes in the blob's precision.
 */
#ifndef CSG_BVH_BUILD_H
#define CSG_BVH_BUILD_H

#include <stdbool.h>

#include "dbox.h"

/* A node of the built tree, as csg_bvh_node but with its box in double. */
typedef struct {
    dbox box;
    int first; /* inner: its first child (the second follows); leaf: the
                  place of its first root in the leaf order              */
    int count; /* leaf: its roots (0: the empty leaf); inner: -1 - the
                  axis it was split on                                   */
} bvh_build_node;

/* Builds the tree over the n >= 1 roots bounded[0..n), root r's box being
 * boxes[r] (finite), into *nodes (malloc'd, *count of them): nodes 0 and
 * 1 are the top pair, the two halves of the first split (or a leaf of
 * every root and the empty leaf); a node's children are allocated in pairs
 * in depth-first order.  order[at + i] receives the roots in leaf order.
 * The tree depends on the boxes alone (the same scene gives the same tree
 * whatever the machine and however many threads built it: `threads`, at
 * most, this one included; 0: one a CPU, up to 8).  False when out of
 * memory (*nodes NULL). */
bool bvh_build(const dbox *boxes, const int *bounded, int n, int *order, int at, int threads,
               bvh_build_node **nodes, int *count);

#endif
