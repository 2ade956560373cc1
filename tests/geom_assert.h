/*
 * geom_assert.h — the assertions the geometry tests share: closeness of
 * scalars and vectors with the value, the expectation and the tolerance in
 * the failure message, and a ray constructor.  Included by test files that
 * already include cmocka.h, math.h and csg/device/intersect.h (in either
 * precision: EPS is the precision's machine epsilon).
 */
#ifndef TESTS_GEOM_ASSERT_H
#define TESTS_GEOM_ASSERT_H

#include <float.h>

#ifdef CSG_DOUBLE
#define EPS ((double)DBL_EPSILON)
#else
#define EPS ((double)FLT_EPSILON)
#endif

#define NEAR(a, b, tol) near_at((double)(a), (double)(b), (double)(tol), #a, __FILE__, __LINE__)

static void near_at(double got, double want, double tol, const char *what, const char *file,
                    int line)
{
    if (!(fabs(got - want) <= tol)) {
        print_error("%s = %.17g, expected %.17g (tolerance %.3g)\n", what, got, want, tol);
        _fail(file, line);
    }
}

#define NEAR_V(v, ex, ey, ez, tol) \
    near_v_at((v), (double)(ex), (double)(ey), (double)(ez), (double)(tol), #v, __FILE__, __LINE__)

static void near_v_at(vec3 v, double ex, double ey, double ez, double tol, const char *what,
                      const char *file, int line)
{
    if (!(fabs((double)v.x - ex) <= tol && fabs((double)v.y - ey) <= tol &&
          fabs((double)v.z - ez) <= tol)) {
        print_error("%s = (%.17g, %.17g, %.17g), expected (%.17g, %.17g, %.17g) (tolerance %.3g)\n",
                    what, (double)v.x, (double)v.y, (double)v.z, ex, ey, ez, tol);
        _fail(file, line);
    }
}

static csg_ray ray(real ox, real oy, real oz, real dx, real dy, real dz)
{
    csg_ray r;
    r.o = v3(ox, oy, oz);
    r.d = v3(dx, dy, dz);
    return r;
}

#endif
