/*
 * stats.h — what one render measured, and its JSON file (--stats), the
 * one thing benchmarks read (they never scrape the human-oriented output).
 *
 * JSON fields (one object):
 *   mode, precision, device    strings ("" device: no OpenCL pass)
 *   cl_program    what the OpenCL program was built for: "general", or
 *                 the scene's kinds and CSG ("sphere plane; no csg":
 *                 csg/features.h); "" without an OpenCL pass
 *   schedule      the scheduler (--schedule: raster, cost, static, tail)
 *   cl_open       hetero: when the OpenCL device was opened: "start" (at
 *                 once: --pass always, --fill off, --schedule static, a
 *                 device named by --cl-device), "work" (--pass auto:
 *                 once the first tiles said the rest pays for the pass),
 *                 "never" (--pass auto: the workers rendered every tile),
 *                 "failed" (--pass auto: the device or its program could
 *                 not be had, or the scene did not fit its buffers; one
 *                 warning said why, and the workers rendered every tile
 *                 left: host/pass/pass.c); "none"
 *                 in homo and serial
 *   width, height, tile, ranks (ranks: MPI processes, 1 without mpirun)
 *   in_flight     work items a worker holds at once (protocol.h)
 *   relays        ranks that relay (--relays; 0: rank 0 deals to every worker)
 *   relay_depth   batches rank 0 keeps at each relay (comm/protocol.h:
 *                 proto_relay_depth: 16 in raster order, 8 where the order
 *                 knows the costs, more for groups over 16 workers; 0
 *                 without relays)
 *   pieces        the work items a tile went as (--pieces, host/schedule.h:
 *                 1, or 4, 16, 64 where the workers are many)
 *   store_threads rank 0's threads that stored the workers' 8-bit results
 *                 (--store-threads, host/store.h; 0: none ran, the loop
 *                 stored every result: float output, serial, one rank)
 *
 *   Phases: consecutive intervals of one clock, so that
 *     wall_s = setup_s + cl_setup_s + compile_s + primary_s + pipelined_s
 *              + secondary_s + write_s
 *   (to rounding; stats_phase_sum).  Overlap is a phase of its own:
 *   wall_s        the whole render: parse .. image written
 *   setup_s       parse + flatten + broadcast of the scene
 *   cl_setup_s    OpenCL platform and device choice, context, queue
 *                 (hetero, when the render opens OpenCL; 0 otherwise):
 *                 a thread opens them while the image module loads and
 *                 the scene is read (render.c), so this is only what is left of that
 *                 after setup_s; with the fill, until the pass begins
 *                 (the program built meanwhile included)
 *   compile_s     OpenCL program build or cache load + warm-up launch
 *                 (same condition)
 *   primary_s     the OpenCL pass alone: from its start until the first
 *                 work item goes out (or the pass ends, if sooner): the
 *                 workers wait (hetero; 0 in serial/homo, where primary
 *                 rays are traced inside the tile phase)
 *   pipelined_s   the pass and the tile phase at once: first item out ..
 *                 the last slice complete (hetero; 0 otherwise)
 *   secondary_s   the tile phase after the pass: the end of the pass (or
 *                 of the set-up) .. the last result in
 *   write_s       image file writing
 *   Derived (not phases):
 *   pass_s        the OpenCL pass: its start .. its last slice complete
 *   pass_kernel_s, pass_copy_s, pass_device_s  the same pass on the
 *                 device's own clock (0 where its queue times nothing):
 *                 its kernels, the copies of their records to the host
 *                 after them (mappings where written in place), and its
 *                 first kernel's start .. its last copy's end; what the
 *                 span holds beyond the two the device waited for the
 *                 host, and what pass_s holds beyond the span the host
 *                 spent before the first kernel (buffers, the scene's
 *                 upload) and after the last copy (seeing it complete)
 *   tile_phase_s  first item out .. last result in (pipelined_s +
 *                 secondary_s, less any wait before the first item)
 *   tail_s        the last result in - the first worker going idle for
 *                 good (its last result in; a worker that got nothing:
 *                 the first item out); 0 with one worker
 *   busy_fraction sum of the workers' busy_s / (workers x tile_phase_s)
 *   estimate_spearman  Spearman's rank correlation of the items'
 *                 estimated costs with the workers' seconds on them
 *                 (hetero; null without estimates or with < 3 items)
 *   master_cpu_s  CPU seconds of the master's own thread during the tile
 *                 phase (its event loop: polls, naps, packing, storing;
 *                 OpenCL's threads not included): what it takes from the
 *                 workers when the ranks outnumber the cores
 *   master_results_s  seconds the master spent taking the workers' results
 *                 in (checking them, storing their pixels in the image,
 *                 appending finished tiles to the journal) within the
 *                 tile phase (to the last result's arrival), MPI aside:
 *                 the work a result costs it, which bounds how many
 *                 workers one master can keep busy (bench/SCALE.md)
 *   pass_work_s   hetero, --pass auto: the CPU seconds the frame's
 *                 primary rays were guessed to take on the workers (what
 *                 the pass takes off them): the seconds of blocks of 4 x 4
 *                 pixels, one in 64 x 64 (a quarter of them when theirs
 *                 is under 2/3 of the threshold or over 1.5 times it),
 *                 traced on rank 0 while the workers began, over the
 *                 image, times the primary rays' share of their rays; the
 *                 device is opened when that is at least 0.16 s
 *                 (host/pass/pass.c); 0 when there was no guess
 *   guess_cpu_s   hetero, --pass auto: the CPU seconds that guess took on
 *                 rank 0 (0 when none was done before the tiles were):
 *                 with cull_s, what hetero spends that homo does not
 *                 while its device stays closed
 *   cull_s        hetero with the fill: the master's seconds in the checks
 *                 of tiles_culled (one a fill tile)
 *   store_cpu_s   CPU seconds of rank 0's store threads, all together
 *                 (store_threads; 0 when none ran): storing the workers'
 *                 8-bit results into the image, off the master's loop
 *   slices        OpenCL slices of the pass (0 without one)
 *   cl_records    where the pass's kernels wrote the hit records: "in
 *                 place" (a device in host memory, a CPU: straight into
 *                 the master's arrays), "copied" (out of device buffers,
 *                 a discrete GPU); "" without a pass
 *   write_bands   the image's bands (rows of tiles), each encoded once the
 *                 tiles over it are final, while the tiles go on
 *                 (host/output/stream.h; the image module's formats in
 *                 order, from the top); 0 when there is none
 *   write_bands_early  of them, taken by the encoder before the last tile
 *                 was in (the rest are write_s's work)
 *   write_cpu_s   the CPU seconds of the image's encoder threads (for the
 *                 module's formats, what its writer thread encoded, not
 *                 the pools' threads of the finish)
 *
 *   tiles_total   tiles of the image
 *   tiles_degenerate  tiles no primary ray hit (hetero: filled with the
 *                 background by the master, never sent; 0 otherwise)
 *   tiles_culled  hetero with the fill: of tiles_degenerate, those the
 *                 master proved degenerate before any pass, by the frustum
 *                 culling of the workers' primary rays (engine.h
 *                 rect_misses): no object may meet any ray of the tile
 *   tiles_resumed tiles taken from the journal of an interrupted run
 *                 (--resume, host/output/journal.h): never rendered again
 *   tiles_rendered = tiles_sent (the name --resume users look for)
 *   tiles_filled  hetero: of tiles_sent, those the fill gave workers to
 *                 render whole (primary rays too) while no tile of the
 *                 pass was ready (--fill, host/schedule.h); 0 otherwise.
 *                 With the fill, cl_setup_s and compile_s may overlap
 *                 the tile phase: the workers render fill tiles meanwhile
 *                 (primary_s is then 0)
 *   tiles_sent    tiles_total - tiles_degenerate - tiles_resumed: the
 *                 tiles of the tile phase (sent to workers, or done
 *                 in-process without any)
 *   items_sent    work items sent: tiles_sent, plus 3 for each tile the
 *                 tail scheduler split into quarters, plus items_reassigned
 *   batch         work items one message may carry at most (--batch; 1
 *                 without workers)
 *   tile_messages TILE messages the master sent (items_sent when batch
 *                 is 1; 0 without workers)
 *   answers_early of their answers, those of a relay that came before the
 *                 answer to a TILE sent earlier (a relay answers each
 *                 TILE as soon as its parts are done: comm/protocol.h)
 *   workers_lost  workers lost during the render (their process died, or
 *                 they hung: host/master.c); the render went on without
 *                 them
 *   items_reassigned  items a lost worker held, sent again to others (or
 *                 done by the master once every worker was lost)
 *   spp           primary samples a pixel
 *   pixels, pixels_hit, occupancy (pixels_hit / (pixels * spp)):
 *                 pixels_hit counts the primary samples that hit (the
 *                 pixels, when spp = 1)
 *   max_rays_per_pixel  the reflected and refracted rays a pixel may
 *                 trace (--max-rays-per-pixel; default 4096 a sample)
 *   pixels_over_budget  pixels that met it: their deepest reflections
 *                 and refractions were not traced (0 in any usual scene)
 *   rays          {primary, shadow, reflected, refracted, total}
 *   bytes_sent    bytes the master sent to workers (the scene counted once
 *                 per copy sent: once per node leader other than rank 0,
 *                 or, without one copy a node, once per worker; + the
 *                 tile messages)
 *   bytes_received bytes the master received from workers
 *   result_pixels what the workers' RESULTs carried a pixel: "rgb8" (the
 *                 8-bit file's bytes: the output is PNG, JPEG, TIFF, ...;
 *                 comm/pixels.h), "rgb8z" (those compressed: --compress,
 *                 comm/pixels_z.h), "float" (EXR or no file), "none" (no
 *                 workers)
 *   link_mbps     MB/s between rank 0's node and another, measured at
 *                 start (comm/mpi_link.h); 0: one node, or not measured
 *   hit_records   hetero: "send" (the pass's records go with the tiles)
 *                 or "retrace" (--hit-records retrace); else "none"
 *   blob_bytes    size of the flattened scene
 *   scene_shared_ranks   ranks (the master included) that read their
 *                 node's one copy of the blob in place (comm/mpi_link.h:
 *                 link_scene): a node then holds it once
 *   scene_private_ranks  ranks that hold a copy of their own (the rest:
 *                 serial, the simulated build, CSGTRACE_NODE_SCENE=off, a
 *                 rank alone on its node); each holds blob_bytes
 *   memory_estimate  bytes the process that owns the image was estimated
 *                 to hold at its peak before it allocated any
 *                 (host/memory.h: the image, the encoder, the tiles'
 *                 bookkeeping, the hit records), what it checked against
 *                 what it may allocate
 *   workers       [{rank, tiles, items, busy_s, busy_fraction, hits,
 *                 rays{...}}] one per rank that rendered tiles (rank 0
 *                 alone without workers; rank 0 last when every worker
 *                 was lost and the master finished the render); tiles: tiles it completed (a
 *                 split tile counts for the rank that returned its last
 *                 piece), items: work items it computed, busy_fraction:
 *                 busy_s / tile_phase_s
 *
 * The tile log (--tile-log FILE, stats_write_tile_log): JSON lines, one
 * object a work item plus one a degenerate tile, in item order:
 *   {"tile", "piece" (0 whole, 1-4 a quarter), "x", "y", "width",
 *    "height", "skipped" (degenerate), "resumed" (from the journal),
 *    "fill" (rendered whole by the fill, hetero), "estimate" (ray casts, null if
 *    unknown), "hits", "worker" (rank; 0 the master), "order" (dispatch
 *    order, null if skipped), "sent_s", "done_s" (seconds since the render
 *    began, null if skipped), "seconds" (the worker's time on it), "cpu_s"
 *    (of it, the CPU time of the worker's thread: "seconds" less any time a
 *    shared core spent elsewhere; what bench/sim/costmap.py maps)}
 * The pieces of a tile partition it; every tile appears once whole or as
 * its pieces.
 */
#ifndef HOST_STATS_H
#define HOST_STATS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "../workers/engine.h"
#include "schedule.h"

typedef struct {
    int rank;
    uint64_t tiles;
    uint64_t hits;   /* pixels of its tiles whose primary ray hit */
    ray_counts rays;
    double busy_s;   /* time spent rendering its tiles             */
    uint64_t items;  /* work items it computed (pieces included)  */
    page_counts paging; /* its scene paging (--scene-memory)       */
} stats_worker;

typedef struct render_stats {
    const char *mode;       /* "serial", "homo", "hetero"            */
    const char *precision;  /* "float", "double" (what ran)          */
    const char *schedule;   /* sched_policy_name                      */
    const char *cl_open;    /* hetero: when the OpenCL device opened   */
    const char *result_pixels; /* pixels_format_name, or "none"       */
    const char *hit_records;   /* "send", "retrace" or "none"           */
    double link_mbps;          /* between nodes, measured at start (0)  */
    char precision_why[256]; /* --precision auto: why, else ""       */
    char device[256];       /* OpenCL device name, "" if none        */
    char cl_program[128];   /* csg_features_program_name, "" if none */
    int width, height, tile, ranks, spp, in_flight;
    int max_rays;           /* the ray budget of a pixel             */
    double wall_s, setup_s, compile_s, primary_s, secondary_s, write_s;
    double cl_setup_s, pipelined_s;               /* phases (above)     */
    double pass_s, tile_phase_s, tail_s;          /* derived            */
    double pass_kernel_s, pass_copy_s, pass_device_s; /* (below)         */
    double busy_fraction, estimate_spearman;
    double master_cpu_s, master_results_s;        /* (below)            */
    double store_cpu_s;                           /* (below)            */
    double pass_work_s, guess_cpu_s, cull_s;      /* (below)            */
    int tiles_total, tiles_sent, tiles_degenerate, tiles_culled, items_sent, slices;
    bool cl_records_in_place; /* (read with slices > 0) */
    int tiles_resumed;        /* taken from the journal (--resume)        */
    int tiles_filled;         /* rendered whole while the pass ran (fill) */
    int workers_lost, items_reassigned; /* a dead worker's items go on  */
    int batch;                                    /* (above)            */
    int relays;               /* ranks 1 .. relays relay (--relays): not in
                                 `workers` of the JSON                     */
    int relay_depth;          /* batches each relay holds at most (0: none) */
    int pieces;               /* items a tile went as (--pieces)         */
    int store_threads;        /* rank 0's store threads that ran          */
    int write_bands, write_bands_early; /* the image's bands, and those
                                 encoded before the last tile was in     */
    double write_cpu_s;       /* the image encoder threads' CPU seconds    */
    uint64_t tile_messages, answers_early;
    uint64_t pixels, pixels_hit;
    ray_counts rays;
    uint64_t bytes_sent, bytes_received, blob_bytes;
    int scene_shared_ranks, scene_private_ranks; /* (see above) */
    /* --scene-memory (workers/pager.h): the budget, the plan, the
     * workers' paging summed (paging.peak_bytes: the largest worker's) */
    uint64_t scene_memory, page_bytes, resident_bytes;
    int page_count;
    const char *page_policy;
    int page_prefetch; /* enum pager_prefetch */
    uint64_t page_asks;       /* requests rank 0 answered               */
    uint64_t page_bytes_served; /* their bytes                          */
    int page_homes;           /* > 0: the workers were the pages' homes */
    const char *page_fetch;   /* "get" (one-sided) or "ask"              */
    page_counts paging;
    uint64_t memory_estimate; /* host/memory.h: render_memory_need's total */
    int worker_count;       /* ranks - 1 (the relays' entries first)  */
    stats_worker *workers;  /* worker_count entries (not owned)      */
} render_stats;

/* Share of primary samples that hit something. */
double stats_occupancy(const render_stats *s);

/* Monotonic seconds, for every timing of a render. */
double stats_clock(void);
/* CPU seconds of the calling thread. */
double stats_thread_cpu(void);

/* The sum of the phases, which equals wall_s (the header). */
double stats_phase_sum(const render_stats *s);

/* Adds b to a. */
void stats_add_rays(ray_counts *a, const ray_counts *b);

/* The JSON object, pretty-printed, ending with a newline. */
void stats_print_json(FILE *f, const render_stats *s);

/* Writes the JSON to `path` through a temporary file in the same folder
 * renamed when complete; false with a message in err otherwise. */
bool stats_write_json(const char *path, const render_stats *s, char *err, size_t err_size);

/* The tile log of the items of `s` (JSON lines, the header), times
 * relative to t0, written like the JSON; false with a message in err. */
bool stats_write_tile_log(const char *path, const sched *s, double t0, char *err,
                          size_t err_size);

/* The figures of a tile phase from its scheduler's items (s), the first
 * item out and the last result in (stats_clock(); t_first 0: none) and
 * the workers' busy seconds: tile_phase_s, busy_fraction, tail_s,
 * estimate_spearman, tiles_sent, tiles_degenerate, tiles_filled,
 * items_sent, items_reassigned (worker_count and relays set before). */
void stats_tile_figures(render_stats *st, const sched *s, double t_first, double t_last,
                        double busy_s);

/* One short line for people: mode, size, ranks, wall time, tiles. */
void stats_print_summary(FILE *f, const render_stats *s);

#endif
