/*
 * pass.h — hetero's primary pass as one render drives it: the OpenCL
 * device opened on a thread of its own while the scene is read, the
 * `--pass auto` guess and decision, the program built while the fill
 * renders, the pass run in slices (ocl.h), its hit records and tile
 * counts, and the give-up when the device cannot be had.
 *
 * The calls, in a render's order (host/render.c):
 *   pass_start     after MPI starts, before the scene is read: the device
 *                  thread begins opening the device (or, under --pass
 *                  auto, waits for the scene to guess its work first);
 *   pass_prepare   the scene is loaded: the records allocated, and the
 *                  pass begun at once (no fill), its program's build
 *                  begun on the thread (the fill), or the guess asked for
 *                  (--pass auto);
 *   pass_rows      at every turn of the tile phase: rows from the top
 *                  whose records are final, given the rows the fill left
 *                  to the pass; it decides, builds, begins and tops up the
 *                  pass as each becomes possible;
 *   pass_end       every tile in: the pass ended, its figures reported;
 *   pass_free      whatever is left (threads joined, the device closed).
 * A render that is not hetero has no pass (NULL), and every call takes
 * NULL as "no pass".
 */
#ifndef PASS_PASS_H
#define PASS_PASS_H

#include <stdbool.h>
#include <stdint.h>

#include "../../comm/mpi_link.h"
#include "../../comm/tiles.h"
#include "../../csg/diag.h"
#include "../config.h"
#include "../exit_status.h"
#include "ocl.h"

typedef struct pass pass;

typedef struct {
    const char *device;     /* --cl-device, else $CSGTRACE_CL_DEVICE
                               (NULL: the first device)                  */
    enum ocl_kernel kernel; /* --cl-kernel, else $CSGTRACE_CL_KERNEL      */
    bool general;           /* $CSGTRACE_CL_SPECIALISE=0: the general
                               program, not one built for the scene      */
    bool fill;              /* workers render whole tiles while the pass
                               is not ready (--fill on): the program is
                               built on the device thread meanwhile      */
    bool automatic;         /* --pass auto applies (pass_is_automatic)   */
    struct ocl_ctx **keep;  /* compare: reuse *keep, or open it and leave
                               it there (the caller closes it); NULL: the
                               pass owns its context                     */
    bool shadows;           /* --simd shadows: the pass answers the primary
                               hits' shadow rays too (csg_shadows)      */
    int packet;             /* the packet kernel's width ($CSGTRACE_CL_
                               PACKET; 0: the device's)                  */
    long long slice_records; /* the least records of a slice ($CSGTRACE_
                               CL_SLICE; 0: the device's default)        */
    char cache_dir[4096];   /* compiled programs kept here ("": none;
                               pass/cl_cache.h)                          */
} pass_config;

/* The settings of the environment (host/config.h) the pass takes into
 * cfg: the kernel variant when cfg's is auto, the packet's width, the
 * general program, the least records of a slice; false with d filled when
 * one is not valid. */
bool pass_settings(const csg_config *env, pass_config *cfg, csg_diag *d);

/* Does --pass auto apply?  Hetero with the fill (a static schedule has
 * none), no --pass always, no device named (the user asked for that one,
 * and a name that matches none is an error whatever the frame), and no
 * context kept across renders (opened once for all of them). */
bool pass_is_automatic(bool fill, bool always, const char *device, bool keep);

/* The pass of a hetero render, its device thread started (NULL: out of
 * memory, reported at pass_prepare). */
pass *pass_start(const pass_config *cfg);

/* The scene is loaded (blob, validated): without the fill the context
 * and its program are opened now (the fill builds them meanwhile:
 * pass_prepare).  0, or the exit status with d filled (p NULL: out of
 * memory). */
int pass_open(pass *p, const void *blob, csg_diag *d);

/* The tile phase begins: the records of grid g allocated; then the pass
 * begun (no fill), its program's build begun (the fill, no --pass auto),
 * or the guess of the frame's work asked for (--pass auto).  `wake`
 * (NULL: nobody naps) is woken whenever a slice or the build completes.
 * 0, or the exit status with d filled. */
int pass_prepare(pass *p, const tile_grid *g, link_idle *wake, csg_diag *d);

/* Rows from the top whose records are final, the pass needing only the
 * top `need` rows (the fill renders the rest); with `wait`, blocking until
 * one more slice is done (or the program is built, or the guess is in).
 * 0 while the program is being built or the pass is undecided or given
 * up; -1 with d filled when the pass failed. */
int pass_rows(pass *p, int need, bool wait, csg_diag *d);

/* --pass auto: the decision taken if the guess is in, without waiting
 * (the fill's turn); 0, or -1 with d filled when the render must fail. */
int pass_poll(pass *p, csg_diag *d);

/* May a pass still come?  (Undecided, or being built, and not given up.) */
bool pass_may_come(const pass *p);

/* No thread of the pass is loading the OpenCL driver now: a new thread
 * may be created without waiting for the dynamic loader's lock (PoCL's
 * loading holds it ~25 ms). */
bool pass_quiet(const pass *p);

/* The hit records of the whole image and the hits of each tile (NULL
 * without a pass): final for the rows pass_rows said. */
const void *pass_t(const pass *p);
const uint32_t *pass_surf(const pass *p);
/* Their shadow answers (csg/device/shadow.h), with cfg.shadows; else NULL. */
const uint32_t *pass_known(const pass *p);
const uint32_t *pass_lit(const pass *p);
const uint32_t *pass_tile_hits(const pass *p);

/* The scheduler's estimate of rectangle r's cost (host/schedule.h), from
 * its records (pass/estimate.h); the argument is the pass. */
double pass_estimate(void *p, tile_rect r);

/* Rows of one slice of the pipelined pass (the memory estimate's). */
int pass_slice_rows(const tile_grid *g);

/* What the render's stats say of the pass (host/stats.h). */
typedef struct {
    bool traced;         /* the pass ran: its records stood for the
                            primary rays                               */
    double start, end;   /* stats_clock() (0: no pass, or not over)    */
    bool built_meanwhile; /* the program was built while the fill ran  */
    const char *cl_open; /* why the device was opened (NULL: --pass auto
                            did not apply)                             */
    double work_s;       /* --pass auto's guess of the frame's work    */
    double guess_cpu_s;  /* and its CPU seconds                        */
    ocl_timing tm;       /* set-up, compile, slices, device           */
    char program[128];   /* the program's feature set                  */
} pass_report;

/* Every tile is in (status: the tile phase's): the pass ended, the
 * program waited for if it is still being built (a bad option is an
 * error even when the fill took every tile), *r filled; the status, d
 * filled when it became a failure. */
int pass_end(pass *p, int status, pass_report *r, csg_diag *d);

/* The primary hits of the tiles 0 .. tiles-1 by the pass's counts. */
uint64_t pass_hits(const pass *p, int tiles);

/* The records freed (every tile is in: the image writer's peak does not
 * hold them, host/memory.c). */
void pass_drop_records(pass *p);

/* Threads joined, the pass ended, the context closed unless kept. */
void pass_free(pass *p);

#endif
