/*
 * spec.h — what the code is compiled for: every primitive kind and all the
 * CSG machinery (the default: C, the tests, a general OpenCL program), or
 * only what one scene uses (an OpenCL program built for its feature set,
 * flat.h: csg_blob_header.kinds / .features; host/pass/ocl.c passes the
 * options, csg/features.c writes them).
 *
 * Options (all absent: everything compiled):
 *   -DCSG_SPECIALISED      the kinds are listed: only the kinds with
 *   -DCSG_HAS_<KIND>       (SPHERE, BOX, ... as in CSG_PRIM_KINDS) are;
 *   -DCSG_NO_CSG           every root is one uncomplemented primitive:
 *                          no interval list is ever built.
 * Each becomes a 0/1 constant below, tested in plain `if`s, so the
 * compiler drops the dead code and the live code is the general code
 * unchanged: a specialised program gives the general one's bits.  The
 * blob validator makes sure a blob's header tells its feature set truly;
 * the OpenCL host refuses a blob outside its program's set (ocl.c).
 *
 * Only what pays is specialised (bench/spec_pass.sh, bench/SPEED.md): the
 * kinds and CSG.  Leaving the transform code out of a scene without
 * transforms was measured too (0.97-1.03x) and dropped: it would only
 * double the programs to build.
 */
#ifndef CSG_SPEC_H
#define CSG_SPEC_H

#ifdef CSG_SPECIALISED
#ifdef CSG_HAS_SPHERE
#define CSG_USE_SPHERE 1
#else
#define CSG_USE_SPHERE 0
#endif
#ifdef CSG_HAS_BOX
#define CSG_USE_BOX 1
#else
#define CSG_USE_BOX 0
#endif
#ifdef CSG_HAS_CONE
#define CSG_USE_CONE 1
#else
#define CSG_USE_CONE 0
#endif
#ifdef CSG_HAS_PLANE
#define CSG_USE_PLANE 1
#else
#define CSG_USE_PLANE 0
#endif
#ifdef CSG_HAS_TRAPEZOID
#define CSG_USE_TRAPEZOID 1
#else
#define CSG_USE_TRAPEZOID 0
#endif
#ifdef CSG_HAS_CONIC_TRAPEZOID
#define CSG_USE_CONIC_TRAPEZOID 1
#else
#define CSG_USE_CONIC_TRAPEZOID 0
#endif
#ifdef CSG_HAS_TORUS
#define CSG_USE_TORUS 1
#else
#define CSG_USE_TORUS 0
#endif
#ifdef CSG_HAS_QUADRIC
#define CSG_USE_QUADRIC 1
#else
#define CSG_USE_QUADRIC 0
#endif
#ifdef CSG_HAS_POLY
#define CSG_USE_POLY 1
#else
#define CSG_USE_POLY 0
#endif
#ifdef CSG_HAS_TRIANGLE
#define CSG_USE_TRIANGLE 1
#else
#define CSG_USE_TRIANGLE 0
#endif
#ifdef CSG_HAS_SMOOTH_TRIANGLE
#define CSG_USE_SMOOTH_TRIANGLE 1
#else
#define CSG_USE_SMOOTH_TRIANGLE 0
#endif
#ifdef CSG_HAS_FLAT_BOX
#define CSG_USE_FLAT_BOX 1
#else
#define CSG_USE_FLAT_BOX 0
#endif
#else /* every kind */
#define CSG_USE_SPHERE 1
#define CSG_USE_BOX 1
#define CSG_USE_CONE 1
#define CSG_USE_PLANE 1
#define CSG_USE_TRAPEZOID 1
#define CSG_USE_CONIC_TRAPEZOID 1
#define CSG_USE_TORUS 1
#define CSG_USE_QUADRIC 1
#define CSG_USE_POLY 1
#define CSG_USE_TRIANGLE 1
#define CSG_USE_SMOOTH_TRIANGLE 1
#define CSG_USE_FLAT_BOX 1
#endif

/* A kind of flat.h's table (its ID) is compiled in; a kind added to the
 * table without a CSG_USE_<ID> above does not compile. */
#define CSG_USES_KIND(ID) CSG_USE_##ID

/* Roots may need interval lists (programs, complemented leaves). */
#ifdef CSG_NO_CSG
#define CSG_USE_CSG 0
#else
#define CSG_USE_CSG 1
#endif

#endif
