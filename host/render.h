/*
 * render.h — one render as the command line asked for it, and the driver
 * that runs it in any mode (serial, homo, hetero) on any number of ranks.
 */
#ifndef HOST_RENDER_H
#define HOST_RENDER_H

#include <stdbool.h>

#include "../csg/lang/parser.h"
#include "config.h"
#include "exit_status.h"

struct ocl_ctx;
struct render_stats;

enum render_mode { MODE_SERIAL, MODE_HOMO, MODE_HETERO };
#define RENDER_DEFAULT_TILE 32 /* tile edge in pixels, when not given */
/* The progress bar: never, when stderr is a terminal (mpirun forwards it
 * through a pipe, so ranks never see one), or always (--progress). */
enum progress_mode { PROGRESS_OFF, PROGRESS_TTY, PROGRESS_ON };
/* auto: double only when float's rounding could show (csg/precision.h). */
enum render_precision { PREC_FLOAT, PREC_DOUBLE, PREC_AUTO };
/* --compress: 8-bit results compressed on the wire (comm/pixels_z.h) when
 * the ranks span more than one node (a network between them: a gigabit
 * link is the bound there, bench/SCALE.md), always, or never. */
enum render_compress { COMPRESS_AUTO, COMPRESS_ON, COMPRESS_OFF };
/* --hit-records: hetero sends the workers the pass's records with their
 * tiles, or none (retrace: they trace the primary rays of the tiles with
 * hits; records are 8-12 bytes a pixel: a slow link's bound), or decides
 * by the link, as --compress (auto). */
enum render_records { RECORDS_AUTO, RECORDS_SEND, RECORDS_RETRACE };

typedef struct {
    const char *scene_path;
    const char *out_path;     /* NULL: render, write nothing (compare) */
    const char *stats_path;   /* NULL: no JSON                       */
    const char *tile_log_path; /* NULL: no tile log (--tile-log)     */
    const char *cl_device;    /* NULL: env's cl_device, or the first */
    enum render_mode mode;
    enum render_precision precision;
    int width, height;        /* 0: the scene's (NFF), else 320 x 240 */
    int tile;                 /* <= 0: RENDER_DEFAULT_TILE           */
    int spp;                  /* primary samples a pixel, default 1  */
    int max_rays;             /* reflected and refracted rays a pixel
                                 may trace; <= 0: CSG_RAYS_PER_SAMPLE
                                 a sample                              */
    int depth;                /* <= 0: the scene's max_trace_level   */
    double threshold;         /* < 0: the scene's adc_bailout        */
    enum progress_mode progress; /* the bar on stderr                */
    bool resume;              /* go on from out_path's journal (host/
                                 journal.h); else a new one replaces it */
    bool simd_shadows;        /* --simd shadows: the hetero pass answers
                                 the primary hits' shadow rays too    */
    int cl_kernel;            /* enum ocl_kernel (host/pass/ocl.h): 0 auto,
                                 1 scalar, 2 packet                    */
    int schedule;             /* enum sched_policy (host/schedule.h);
                                 < 0: the mode's default (hetero: cost,
                                 else raster)                          */
    bool no_fill;             /* --fill off: hetero workers only shade
                                 what the pass traced (the paper's
                                 scheme); on: while no tile is ready
                                 they render tiles whole from the
                                 bottom (host/schedule.h)              */
    bool pass_always;         /* --pass always: hetero opens the OpenCL
                                 device at once, whatever the frame; auto
                                 (with the fill): only once the frame
                                 shows it pays (host/render.c)         */
    int batch;                /* work items in one message at most
                                 (--batch); 0: auto (host/schedule.h)  */
    int pieces;               /* the items a tile goes as (--pieces: 1,
                                 4, 16, 64); 0: auto (host/schedule.h) */
    int relays;               /* --relays: ranks 1 .. relays are relays,
                                 masters of groups of workers
                                 (comm/relay.h); 0: none               */
    double scene_memory_mb;   /* --scene-memory: each worker's scene within
                                 this many MB (workers/pager.h); 0: whole */
    int page_policy;          /* --page-policy: enum pager_policy        */
    int page_home;            /* --page-home: enum pager_home            */
    int page_kb;              /* --page-size: KiB a page aims at; 0: auto
                                 (pager_page_bytes_for the budget)        */
    int page_prefetch;        /* --page-prefetch: enum pager_prefetch     */
    int page_fetch;           /* --page-fetch: enum pager_fetch_mode      */
    int compress;             /* --compress: enum render_compress        */
    int hit_records;          /* --hit-records: enum render_records      */
    int store_threads;        /* --store-threads: rank 0's threads that
                                 store 8-bit results (host/store.h);
                                 <= 0: one                             */
    const csg_config *env;    /* the environment's settings (config.h,
                                 read once at start); NULL: none        */
    const csg_parse_options *parse; /* clock, library folders, messages;
                                       NULL: the defaults (image_width and
                                       image_height are always the render's) */
    /* For callers that run several renders in one job (compare); NULL in
     * a plain render.  Used on the master only. */
    struct ocl_ctx **cl_keep; /* hetero: reuse *cl_keep, or open it and
                                 leave it there (the caller closes it):
                                 only the first render pays the build   */
    struct render_stats *stats_out; /* a copy of the render's statistics
                                       (its `workers` left NULL)         */
    float **image_out;        /* receives the image (malloc'd, RGB)     */
} render_request;

/* Runs one render (host/render.c) and returns the exit status.
 * Without mpirun (no OMPI_COMM_WORLD_SIZE) MPI is never initialised and
 * everything runs in this process; under mpirun every rank calls it: rank 0
 * is the master (reads the scene, assembles and writes the image, prints
 * the one summary line or the one error message, writes the stats), the
 * other ranks are workers and return the master's status.  It may be called
 * several times in one run (MPI is finalised at exit). */
int render_run(const render_request *req);

/* This process's rank: 0 without mpirun (MPI is then never touched) and on
 * the master; -1 when MPI cannot start.  For commands that print more than
 * render_run does (compare): only rank 0 should. */
int render_rank(void);

#endif
