/*
 * options.h — every option of the command line, in one table: its
 * spellings, its value, the field of cli_args it sets, its range or
 * choices, the commands that take it, and its line of help.  Parsing,
 * the usage text and the check that an option applies to the command
 * given all derive from it (cli.c); an option is added by one row here.
 *
 * X(name, alias, value, kind, field, lo, hi, choices, commands, help):
 *   name, alias  its spellings (alias NULL: none)
 *   value        what the usage shows for its value (NULL: none)
 *   kind         how the value is read (enum cli_kind) and the field's type
 *   field        the member of cli_args it sets
 *   lo, hi       the range of a number
 *   choices      the words a choice (or a set) takes, NULL-ended
 *   commands     CLI_ON_* bits: where it may be given
 *   help         one line for --help
 * A spelling may have one row per group of commands (gen's --width sets
 * its own field); the first row that names the command given is used.
 */
#ifndef HOST_OPTIONS_H
#define HOST_OPTIONS_H

/* How an option's value is read, and the type of its field. */
enum cli_kind {
    CLI_FLAG,    /* no value: true                          bool          */
    CLI_SET,     /* no value: lo                            int (enum)    */
    CLI_TEXT,    /* the text itself                         const char *  */
    CLI_PATH,    /* a file's name: the text, never empty    const char *  */
    CLI_INT,     /* a whole number in [lo, hi]              int           */
    CLI_INT_AUTO, /* "auto" (0) or a whole number in [lo, hi]  int        */
    CLI_U64,     /* a whole number in [lo, hi]              uint64_t      */
    CLI_REAL,    /* a real number in [lo, hi]               double        */
    CLI_CHOICE,  /* one of the choices: its index           int (enum)    */
    CLI_SWITCH,  /* one of two choices: the second's        bool          */
    CLI_BITS,    /* choices, comma-separated: 1 << index each  unsigned   */
    CLI_FOLDER   /* a folder, repeatable: appended to the library list   */
};

#define CLI_ON_RENDER (1u << CMD_RENDER)
#define CLI_ON_COMPARE (1u << CMD_COMPARE)
#define CLI_ON_CHECK (1u << CMD_CHECK)
#define CLI_ON_EXPORT (1u << CMD_EXPORT)
#define CLI_ON_GEN (1u << CMD_GEN)
#define CLI_ON_RENDERS (CLI_ON_RENDER | CLI_ON_COMPARE)
#define CLI_ON_SCENES (CLI_ON_RENDERS | CLI_ON_CHECK | CLI_ON_EXPORT)

#define CLI_OPTIONS(X)                                                                         \
    X("-o", "--output", "OUT", CLI_PATH, out_path, 0, 0, NULL,                                 \
      CLI_ON_RENDER | CLI_ON_COMPARE | CLI_ON_EXPORT | CLI_ON_GEN,                             \
      "the output: the image (render; its format by the extension), a prefix for both "        \
      "images (compare), the scene (export, gen)")                                             \
    X("--mode", NULL, "serial|homo|hetero", CLI_CHOICE, req.mode, 0, 0, cli_modes,             \
      CLI_ON_RENDER, "one process; workers trace everything; an OpenCL pass then workers "    \
                     "shade (default serial)")                                                 \
    X("--width", NULL, "W", CLI_INT, req.width, 1, 65536, NULL, CLI_ON_SCENES,                 \
      "the image's width (default the scene's, else 320)")                                     \
    X("--height", NULL, "H", CLI_INT, req.height, 1, 65536, NULL, CLI_ON_SCENES,               \
      "the image's height (default the scene's, else 240)")                                    \
    X("--tile", NULL, "N", CLI_INT, req.tile, 1, 65536, NULL, CLI_ON_RENDERS,                  \
      "tile edge in pixels (default 32)")                                                      \
    X("--depth", NULL, "D", CLI_INT, req.depth, 1, 256, NULL, CLI_ON_RENDERS,                  \
      "the deepest trace level (default the scene's max_trace_level, else 5)")                 \
    X("--threshold", NULL, "W", CLI_REAL, req.threshold, 0, 1, NULL, CLI_ON_RENDERS,           \
      "a secondary ray weighing less is not traced (default adc_bailout, else 1/255)")         \
    X("--spp", NULL, "N", CLI_INT, req.spp, 1, CSG_MAX_SPP, NULL, CLI_ON_RENDERS,              \
      "primary samples a pixel, stratified (default 1)")                                       \
    X("--max-rays-per-pixel", NULL, "N", CLI_INT, req.max_rays, 1, CSG_MAX_RAYS_PER_PIXEL,     \
      NULL, CLI_ON_RENDERS, "reflected and refracted rays a pixel may trace "                  \
                            "(default 4096 a sample)")                                          \
    X("--precision", NULL, "float|double|auto", CLI_CHOICE, req.precision, 0, 0,               \
      cli_precisions, CLI_ON_RENDERS, "the kernel's and the workers' real (default float)")    \
    X("--schedule", NULL, "raster|cost|static|tail|region", CLI_CHOICE, req.schedule, 0, 0,           \
      cli_schedules, CLI_ON_RENDERS, "which tile goes next (default raster; hetero cost)")     \
    X("--batch", NULL, "N|auto", CLI_INT_AUTO, req.batch, 1, PROTO_BATCH_MAX, NULL,            \
      CLI_ON_RENDERS, "work items a message may carry (default auto: 8 from 32 workers)")      \
    X("--pieces", NULL, "N|auto", CLI_INT_AUTO, req.pieces, 1, SCHED_PIECES_MAX, NULL,         \
      CLI_ON_RENDERS, "the work items a tile goes as: 1, 4, 16 or 64 (default auto: cut "    \
                      "in 4 from 128 workers with under 128 tiles each, unless compressed)")               \
    X("--relays", NULL, "K", CLI_INT, req.relays, 0, CLI_RELAYS_MAX, NULL, CLI_ON_RENDERS,     \
      "ranks 1..K become masters of groups of workers (default 0)")                            \
    X("--scene-memory", NULL, "MB", CLI_REAL, req.scene_memory_mb, 0.001, 1e9, NULL,         \
      CLI_ON_RENDERS, "each worker holds the scene within MB, paged from rank 0 "             \
                      "(default: the whole scene)")                                            \
    X("--page-size", NULL, "KB|auto", CLI_INT_AUTO, req.page_kb, 4, 65536, NULL,               \
      CLI_ON_RENDERS, "--scene-memory: the size a page aims at, KiB (default auto: a 512th of the budget, 16 to 128)")         \
    X("--page-policy", NULL, "lru|fifo", CLI_CHOICE, req.page_policy, 0, 0, cli_page_policies, \
      CLI_ON_RENDERS, "--scene-memory: the page evicted first (default lru)")                \
    X("--page-home", NULL, "auto|master|spread", CLI_CHOICE, req.page_home, 0, 0, cli_page_homes, \
      CLI_ON_RENDERS, "--scene-memory: who serves the pages: rank 0, or each page's home "   \
                      "worker (default auto: spread from 128 workers where a share fits)")              \
    X("--page-prefetch", NULL, "on|off|shadows", CLI_CHOICE, req.page_prefetch, 0, 0,          \
      cli_page_prefetch, CLI_ON_RENDERS, "--scene-memory: an item's pages fetched in one "    \
      "request before its rays; shadows: its shadow rays' too (default on)")                   \
    X("--page-fetch", NULL, "get|ask", CLI_CHOICE, req.page_fetch, 0, 0, cli_page_fetch,       \
      CLI_ON_RENDERS, "--scene-memory: pages read one-sided from rank 0's memory (get, where "  \
      "MPI opens it as a window) or asked of it (default get)")                                 \
    X("--store-threads", NULL, "N|auto", CLI_INT_AUTO, req.store_threads, 1, STORE_THREADS_MAX, \
      NULL, CLI_ON_RENDERS, "rank 0's threads storing 8-bit results (default auto: one a "    \
      "64 workers)")                                                                           \
    X("--stats", NULL, "FILE.json", CLI_PATH, req.stats_path, 0, 0, NULL, CLI_ON_RENDERS,      \
      "the render's figures as JSON (compare: every run)")                                     \
    X("--tile-log", NULL, "FILE.jsonl", CLI_PATH, req.tile_log_path, 0, 0, NULL,               \
      CLI_ON_RENDER, "one JSON line a work item")                                              \
    X("--cl-device", NULL, "SEL", CLI_TEXT, req.cl_device, 0, 0, NULL, CLI_ON_RENDERS,         \
      "the OpenCL device: P:D or a part of its name (default $CSGTRACE_CL_DEVICE, "            \
      "else the first)")                                                                       \
    X("--cl-kernel", NULL, "auto|scalar|packet", CLI_CHOICE, req.cl_kernel, 0, 0, cli_kernels, \
      CLI_ON_RENDERS, "the primary kernel (auto: packet on a CPU, scalar elsewhere)")          \
    X("--simd", NULL, "primary|shadows", CLI_SWITCH, req.simd_shadows, 0, 0, cli_simd,         \
      CLI_ON_RENDERS, "hetero: the pass traces the primary rays, or their shadow rays too "   \
                      "(default primary)")                                                     \
    X("--compress", NULL, "auto|on|off", CLI_CHOICE, req.compress, 0, 0, cli_compress,         \
      CLI_ON_RENDERS, "8-bit results compressed on their way to rank 0 (default auto: across " \
                      "nodes behind a link under 300 MB/s, measured at start)")                \
    X("--hit-records", NULL, "auto|send|retrace", CLI_CHOICE, req.hit_records, 0, 0,           \
      cli_records, CLI_ON_RENDERS, "hetero: the pass's hits sent with the tiles, or the "       \
      "workers trace the primary rays of the tiles with hits (default auto: retrace across a " \
      "slow link)")                                                                            \
    X("--fill", NULL, "on|off", CLI_SWITCH, req.no_fill, 0, 0, cli_fill, CLI_ON_RENDERS,       \
      "hetero: workers render whole tiles while the pass is not ready (default on)")          \
    X("--pass", NULL, "auto|always", CLI_SWITCH, req.pass_always, 0, 0, cli_pass,              \
      CLI_ON_RENDERS, "hetero: open the device when the frame's guess says it pays, or "      \
                      "always (default auto)")                                                 \
    X("--progress", NULL, NULL, CLI_SET, req.progress, PROGRESS_ON, 0, NULL, CLI_ON_RENDER,    \
      "the progress bar on stderr, even when it is no terminal")                               \
    X("--no-progress", NULL, NULL, CLI_SET, req.progress, PROGRESS_OFF, 0, NULL,               \
      CLI_ON_RENDER, "no progress bar")                                                        \
    X("--resume", NULL, NULL, CLI_FLAG, req.resume, 0, 0, NULL, CLI_ON_RENDER,                 \
      "go on from OUT.journal, an interrupted render's")                                       \
    X("--repeat", NULL, "R", CLI_INT, repeat, 1, 1000, NULL, CLI_ON_COMPARE,                   \
      "timed rounds of each mode (default 3)")                                                 \
    X("--clock", NULL, "F", CLI_REAL, parse.clock, -1e30, 1e30, NULL, CLI_ON_SCENES,           \
      "the scene's clock (default 0)")                                                         \
    X("--library-path", NULL, "DIR", CLI_FOLDER, library, 0, 0, NULL, CLI_ON_SCENES,           \
      "a folder #include searches (repeatable; before $CSGTRACE_LIBRARY_PATH)")                \
    X("--flat", NULL, NULL, CLI_FLAG, flat, 0, 0, NULL, CLI_ON_EXPORT,                         \
      "geometry and colours only (the cross-check against POV-Ray)")                           \
    X("--count", NULL, "N", CLI_INT, gen.count, 1, 1000000, NULL, CLI_ON_GEN,                  \
      "spheres in the scene")                                                                  \
    X("--occupancy", NULL, "F", CLI_REAL, gen.occupancy, 0.001, 0.999, NULL, CLI_ON_GEN,       \
      "the share of pixels their primary rays hit")                                            \
    X("--seed", NULL, "S", CLI_U64, gen.seed, 0, 1000000000000000LL, NULL, CLI_ON_GEN,         \
      "the random seed (the same seed, the same file)")                                        \
    X("--width", NULL, "W", CLI_INT, gen.width, 1, 65536, NULL, CLI_ON_GEN,                    \
      "the image the occupancy is measured at (default 384)")                                  \
    X("--height", NULL, "H", CLI_INT, gen.height, 1, 65536, NULL, CLI_ON_GEN,                  \
      "the image the occupancy is measured at (default 384)")                                                                         \
    X("--materials", NULL, "KINDS", CLI_BITS, gen.materials, 0, 0, cli_materials, CLI_ON_GEN,  \
      "drawn from opaque,reflective,transparent (default all three)")

#endif
