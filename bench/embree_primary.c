/*
 * embree_primary.c — the Embree reference for primary rays, for the
 * benchmarks only (never linked into csgtrace; needs Debian's
 * libembree-dev, Embree 3).
 *
 *   build/bench/embree_primary SPHERES.txt [--repeat R]
 *
 * SPHERES.txt is what `build/bench/primary_rays SCENE --export-spheres`
 * writes: the image size, the camera and the spheres exactly as csgtrace's
 * blob holds them.  The rays are built with csgtrace's own camera code
 * (csg/device/camera.h, header only), so both programs trace the same
 * rays at the same spheres; the spheres become one Embree geometry of type
 * RTC_GEOMETRY_TYPE_SPHERE_POINT (Embree's analytic ray/sphere test) in a
 * scene built with the default quality, and each ray goes through
 * rtcIntersect1, one ray at a time on the calling thread (one core; the
 * device is created with threads=1, so the build uses one thread too).
 * The image is traced once untimed and then R times timed, in rows.
 * Prints one JSON object:
 *   {"spheres", "rays", "hits", "repeat", "build_s", "best_s",
 *    "median_s", "max_s", "mrays_per_s"}   (mrays_per_s from median_s)
 * The input is read with a strict format (every number checked), so a
 * malformed file is refused rather than half-read: exit 2.
 */
#include <embree3/rtcore.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "timing.h"
#include "../csg/device/camera.h"

static int bad(const char *what)
{
    fprintf(stderr, "embree_primary: %s\n", what);
    return 2;
}

static bool read_floats(FILE *f, float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (fscanf(f, "%f", &v[i]) != 1 || !isfinite(v[i]))
            return false;
    return true;
}

/* One pass: every pixel's centre ray; returns the hits. */
static long trace_image(RTCScene scene, const csg_camera *cam, int w, int h)
{
    long hits = 0;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            csg_ray r = csg_primary_ray(cam, w, h, x, y);
            struct RTCRayHit rh;
            rh.ray.org_x = r.o.x;
            rh.ray.org_y = r.o.y;
            rh.ray.org_z = r.o.z;
            rh.ray.dir_x = r.d.x;
            rh.ray.dir_y = r.d.y;
            rh.ray.dir_z = r.d.z;
            rh.ray.tnear = 0.0f;
            rh.ray.tfar = INFINITY;
            rh.ray.time = 0.0f;
            rh.ray.mask = 0xffffffffu;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    }
    return hits;
}

int main(int argc, char **argv)
{
    int repeat = 5;
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--repeat") && i + 1 < argc) {
            char *end;
            long v = strtol(argv[++i], &end, 10);
            if (*end || v < 1 || v > 1000)
                return bad("--repeat takes 1 to 1000");
            repeat = (int)v;
        } else if (argv[i][0] != '-' && !path) {
            path = argv[i];
        } else {
            return bad("usage: embree_primary SPHERES.txt [--repeat R]");
        }
    }
    if (!path)
        return bad("usage: embree_primary SPHERES.txt [--repeat R]");
    FILE *f = fopen(path, "r");
    if (!f)
        return bad("cannot open the spheres file");
    int version, w, h, n;
    csg_camera cam;
    memset(&cam, 0, sizeof cam); /* perspective, rays from the location (no hither):
                                    the only cameras primary_rays exports */
    float cv[12];
    if (fscanf(f, "csgtrace-spheres %d image %d %d camera", &version, &w, &h) != 3 ||
        version != 1 || w < 1 || h < 1 || w > 32768 || h > 32768 || !read_floats(f, cv, 12) ||
        fscanf(f, " spheres %d", &n) != 1 || n < 1 || n > 100000000) {
        fclose(f);
        return bad("malformed header (expected what primary_rays --export-spheres writes)");
    }
    for (int k = 0; k < 3; k++) {
        cam.location[k] = cv[k];
        cam.direction[k] = cv[3 + k];
        cam.right[k] = cv[6 + k];
        cam.up[k] = cv[9 + k];
    }
    RTCDevice dev = rtcNewDevice("threads=1");
    if (!dev) {
        fclose(f);
        fprintf(stderr, "embree_primary: rtcNewDevice failed (%d)\n", (int)rtcGetDeviceError(NULL));
        return 1;
    }
    RTCScene scene = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                       4 * sizeof(float), (size_t)n);
    for (int i = 0; i < n; i++) {
        if (!read_floats(f, v + 4 * (size_t)i, 4) || !(v[4 * (size_t)i + 3] > 0.0f)) {
            fclose(f);
            return bad("malformed sphere line");
        }
    }
    fclose(f);
    double t0 = bench_now_s();
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    double build_s = bench_now_s() - t0;
    if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) {
        fprintf(stderr, "embree_primary: the scene build failed\n");
        return 1;
    }
    double *times = malloc((size_t)repeat * sizeof *times);
    if (!times)
        return 1;
    long hits = trace_image(scene, &cam, w, h); /* warm-up */
    for (int r = 0; r < repeat; r++) {
        t0 = bench_now_s();
        long again = trace_image(scene, &cam, w, h);
        times[r] = bench_now_s() - t0;
        if (again != hits) {
            fprintf(stderr, "embree_primary: the passes disagree\n");
            return 1;
        }
    }
    double median = bench_median(times, repeat);
    double rays = (double)w * (double)h;
    printf("{\"spheres\": %d, \"rays\": %.0f, \"hits\": %ld, \"repeat\": %d, \"build_s\": %.6f, "
           "\"best_s\": %.6f, \"median_s\": %.6f, \"max_s\": %.6f, \"mrays_per_s\": %.4f}\n",
           n, rays, hits, repeat, build_s, times[0], median, times[repeat - 1],
           rays / median / 1e6);
    free(times);
    rtcReleaseScene(scene);
    rtcReleaseDevice(dev);
    return 0;
}
