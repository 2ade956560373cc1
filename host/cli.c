/*
 * cli.c — parsing of `csgtrace COMMAND ARGS...` (see cli_usage).
 * Every option is checked for range and form here, so the stages after it
 * can trust the request.
 */
#include "cli.h"

#include "../csg/flatten.h"
#include "../csg/numbers.h"
#include "../comm/protocol.h"
#include "schedule.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "output/file_atomic.h"

#define CLI_RELAYS_MAX 4096 /* --relays: a relay per 2 workers at most anyway */
#include "output/journal.h"
#include "store.h"

void cli_usage(FILE *out)
{
    fputs("usage:\n"
          "  csgtrace render  SCENE -o OUT [--mode serial|homo|hetero] [--width W] [--height H]\n"
          "                   [--tile N] [--depth D] [--threshold W] [--spp N]\n"
          "                   [--precision float|double|auto] [--max-rays-per-pixel N]\n"
          "                   [--schedule raster|cost|static|tail] [--batch N|auto] [--relays K]\n"
          "                   [--store-threads N]\n"
          "                   [--tile-log FILE.jsonl]\n"
          "                   [--stats FILE.json] [--cl-device SEL] [--cl-kernel auto|scalar|packet]\n"
          "                   [--fill on|off] [--pass auto|always]\n"
          "                   [--progress|--no-progress] [--clock F] [--library-path DIR]...\n"
          "                   [--resume]  (go on from OUT.journal, an interrupted render's)\n"
          "  csgtrace compare SCENE [-o PREFIX] [--repeat R] [same options as render]\n"
          "  csgtrace check   SCENE [--width W] [--height H] [--clock F] [--library-path DIR]...\n"
          "  csgtrace gen spheres --count N --occupancy F --seed S [--width W --height H]\n"
          "                   [--materials opaque,reflective,transparent] -o scene.pov\n"
          "  csgtrace export  SCENE -o OUT.pov [--flat] [same scene options as check]\n"
          "  csgtrace help | --help | --version\n"
          "Run the parallel modes under mpirun: mpirun -np K build/csgtrace render ...\n"
          "Image format follows OUT's extension (png, exr, tif, ppm, ...).\n"
          "#include looks in the including file's folder, the scene's, each --library-path\n"
          "DIR, $CSGTRACE_LIBRARY_PATH (':'-separated) and POV-Ray's include folder.\n",
          out);
}

static bool parse_int(const char *opt, const char *s, int lo, int hi, int *out, csg_diag *d)
{
    long long v;
    if (!number_whole(s, lo, hi, &v)) {
        csg_error_plain(d, "%s expects a whole number from %d to %d, got '%s'", opt, lo, hi,
                        s ? s : "");
        return false;
    }
    *out = (int)v;
    return true;
}

static bool parse_real(const char *opt, const char *s, double lo, double hi, double *out,
                       csg_diag *d)
{
    if (!number_real(s, lo, hi, out)) {
        csg_error_plain(d, "%s expects a number from %g to %g, got '%s'", opt, lo, hi, s ? s : "");
        return false;
    }
    return true;
}

static bool parse_choice(const char *opt, const char *s, const char *const *names, int n,
                         int *out, csg_diag *d)
{
    for (int i = 0; s && i < n; i++) {
        if (strcmp(s, names[i]) == 0) {
            *out = i;
            return true;
        }
    }
    char list[256] = "";
    for (int i = 0; i < n; i++) {
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", names[i]);
    }
    csg_error_plain(d, "%s expects one of %s, got '%s'", opt, list, s ? s : "");
    return false;
}

static const struct {
    const char *name;
    enum cli_command cmd;
} commands[] = {{"render", CMD_RENDER}, {"compare", CMD_COMPARE}, {"check", CMD_CHECK}, {"export", CMD_EXPORT},
                {"gen", CMD_GEN},       {"help", CMD_HELP},
                {"--help", CMD_HELP},   {"-h", CMD_HELP},         {"--version", CMD_VERSION}};

/* One option with its value (argv[*i + 1]); false on a bad one. */
static bool parse_option(cli_args *a, int argc, char **argv, int *i, csg_diag *d)
{
    static const char *const modes[] = {"serial", "homo", "hetero"};
    static const char *const precisions[] = {"float", "double", "auto"};
    static const char *const schedules[] = {"raster", "cost", "static", "tail"};
    static const char *const kernels[] = {"auto", "scalar", "packet"};
    static const char *const switches[] = {"on", "off"};
    static const char *const passes[] = {"auto", "always"};
    const char *opt = argv[*i];
    render_request *r = &a->req;
    if (strcmp(opt, "--flat") == 0) {
        a->flat = true;
        return true;
    }
    if (strcmp(opt, "--resume") == 0) {
        r->resume = true;
        return true;
    }
    if (strcmp(opt, "--progress") == 0 || strcmp(opt, "--no-progress") == 0) {
        r->progress = opt[2] == 'p' ? PROGRESS_ON : PROGRESS_OFF;
        return true;
    }
    const char *val = *i + 1 < argc ? argv[*i + 1] : NULL;
    if (!val) {
        csg_error_plain(d, "%s needs a value", opt);
        return false;
    }
    (*i)++;
    int choice;
    if (strcmp(opt, "-o") == 0 || strcmp(opt, "--output") == 0) {
        a->out_path = val;
        return true;
    }
    if (strcmp(opt, "--stats") == 0) {
        r->stats_path = val;
        return true;
    }
    if (strcmp(opt, "--tile-log") == 0) {
        r->tile_log_path = val;
        return true;
    }
    if (strcmp(opt, "--schedule") == 0)
        return parse_choice(opt, val, schedules, SCHED_POLICIES, &r->schedule, d);
    if (strcmp(opt, "--batch") == 0) {
        r->batch = 0;
        return strcmp(val, "auto") == 0 || parse_int(opt, val, 1, PROTO_BATCH_MAX, &r->batch, d);
    }
    if (strcmp(opt, "--relays") == 0)
        return parse_int(opt, val, 0, CLI_RELAYS_MAX, &r->relays, d);
    if (strcmp(opt, "--store-threads") == 0)
        return parse_int(opt, val, 1, STORE_THREADS_MAX, &r->store_threads, d);
    if (strcmp(opt, "--cl-device") == 0) {
        r->cl_device = val;
        return true;
    }
    if (strcmp(opt, "--library-path") == 0) {
        if (a->parse.library_path_count == CLI_MAX_LIBRARY) {
            csg_error_plain(d, "at most %d --library-path options", CLI_MAX_LIBRARY);
            return false;
        }
        a->library[a->parse.library_path_count++] = val;
        return true;
    }
    if (strcmp(opt, "--clock") == 0)
        return parse_real(opt, val, -1e30, 1e30, &a->parse.clock, d);
    if (strcmp(opt, "--cl-kernel") == 0) /* enum ocl_kernel's order */
        return parse_choice(opt, val, kernels, 3, &r->cl_kernel, d);
    if (strcmp(opt, "--width") == 0)
        return parse_int(opt, val, 1, 65536, &r->width, d);
    if (strcmp(opt, "--height") == 0)
        return parse_int(opt, val, 1, 65536, &r->height, d);
    if (strcmp(opt, "--tile") == 0)
        return parse_int(opt, val, 1, 65536, &r->tile, d);
    if (strcmp(opt, "--spp") == 0)
        return parse_int(opt, val, 1, CSG_MAX_SPP, &r->spp, d);
    if (strcmp(opt, "--max-rays-per-pixel") == 0)
        return parse_int(opt, val, 1, CSG_MAX_RAYS_PER_PIXEL, &r->max_rays, d);
    if (strcmp(opt, "--depth") == 0)
        return parse_int(opt, val, 1, 256, &r->depth, d);
    if (strcmp(opt, "--repeat") == 0)
        return parse_int(opt, val, 1, 1000, &a->repeat, d);
    if (strcmp(opt, "--threshold") == 0)
        return parse_real(opt, val, 0.0, 1.0, &r->threshold, d);
    if (strcmp(opt, "--mode") == 0) {
        if (!parse_choice(opt, val, modes, 3, &choice, d))
            return false;
        r->mode = (enum render_mode)choice;
        return true;
    }
    if (strcmp(opt, "--fill") == 0) {
        if (!parse_choice(opt, val, switches, 2, &choice, d))
            return false;
        r->no_fill = choice == 1;
        return true;
    }
    if (strcmp(opt, "--pass") == 0) {
        if (!parse_choice(opt, val, passes, 2, &choice, d))
            return false;
        r->pass_always = choice == 1;
        return true;
    }
    if (strcmp(opt, "--precision") == 0) {
        if (!parse_choice(opt, val, precisions, 3, &choice, d))
            return false;
        r->precision = (enum render_precision)choice;
        return true;
    }
    (*i)--;
    csg_error_plain(d, "unknown option '%s' (see csgtrace --help)", opt);
    return false;
}

/* No output may overwrite the scene or another output: a mistyped -o or
 * --stats would silently replace it. */
static bool outputs_distinct(const cli_args *a, csg_diag *d)
{
    const char *names[] = {"the scene", "the output (-o)", "the stats (--stats)",
                           "the tile log (--tile-log)", "the output's journal"};
    char journal_path[PATH_MAX + sizeof JOURNAL_SUFFIX];
    bool renders = a->command == CMD_RENDER && a->out_path;
    if (renders)
        journal_name(a->out_path, journal_path, sizeof journal_path);
    const char *paths[] = {a->req.scene_path, a->out_path, a->req.stats_path,
                           a->req.tile_log_path, renders ? journal_path : NULL};
    for (int i = 1; i < 5; i++)
        for (int j = 0; j < i; j++)
            if (paths[i] && paths[j] && file_same(paths[i], paths[j])) {
                csg_error_plain(d, "%s and %s are the same file ('%s'): refusing to overwrite it",
                                names[i], names[j], paths[i]);
                return false;
            }
    return true;
}

/* The folders of $CSGTRACE_LIBRARY_PATH after those of --library-path;
 * false with d filled when they are too many. */
static bool library_from_env(cli_args *a, csg_diag *d)
{
    if (!a->env.library_path)
        return true;
    snprintf(a->library_env, sizeof a->library_env, "%s", a->env.library_path);
    for (char *s = a->library_env, *dir; (dir = strsep(&s, ":")) != NULL;) {
        if (!*dir)
            continue;
        if (a->parse.library_path_count == CLI_MAX_LIBRARY) {
            csg_error_plain(d, "at most %d folders in --library-path and $CSGTRACE_LIBRARY_PATH",
                            CLI_MAX_LIBRARY);
            return false;
        }
        a->library[a->parse.library_path_count++] = dir;
    }
    return true;
}

bool cli_parse(int argc, char **argv, cli_args *a, csg_diag *d)
{
    memset(a, 0, sizeof *a);
    config_read(&a->env);
    a->req.env = &a->env;
    a->req.mode = MODE_SERIAL;
    a->req.precision = PREC_FLOAT;
    a->req.width = 0; /* not given: the scene's size, else 320 x 240 (csg/load.h) */
    a->req.height = 0;
    a->req.tile = RENDER_DEFAULT_TILE;
    a->req.spp = 1;
    a->req.progress = PROGRESS_TTY;
    a->req.threshold = -1;
    a->req.schedule = -1; /* the mode's own */
    a->repeat = 3;
    csg_parse_options_default(&a->parse);
    a->parse.library_paths = a->library;
    a->parse.messages = stderr; /* #debug and #warning */
    a->req.parse = &a->parse;
    if (argc < 2) {
        csg_error_plain(d, "no command given (see csgtrace --help)");
        return false;
    }
    bool known = false;
    for (size_t k = 0; k < sizeof commands / sizeof commands[0]; k++) {
        if (strcmp(argv[1], commands[k].name) == 0) {
            a->command = commands[k].cmd;
            known = true;
        }
    }
    if (!known) {
        csg_error_plain(d, "unknown command '%s' (see csgtrace --help)", argv[1]);
        return false;
    }
    if (a->command == CMD_HELP || a->command == CMD_VERSION || a->command == CMD_GEN)
        return true;
    for (int i = 2; i < argc; i++) {
        if (argv[i][0] == '-' && argv[i][1] != '\0') {
            if (!parse_option(a, argc, argv, &i, d))
                return false;
        } else if (!a->req.scene_path) {
            a->req.scene_path = argv[i];
        } else {
            csg_error_plain(d, "unexpected argument '%s'", argv[i]);
            return false;
        }
    }
    if (!a->req.scene_path) {
        csg_error_plain(d, "no scene file given");
        return false;
    }
    if ((a->command == CMD_RENDER || a->command == CMD_EXPORT) && !a->out_path) {
        csg_error_plain(d, "no output file given (-o OUT)");
        return false;
    }
    if (a->command == CMD_RENDER)
        a->req.out_path = a->out_path;
    else if (a->req.resume) {
        csg_error_plain(d, "--resume goes with render (it continues the render to -o OUT)");
        return false;
    }
    if (!outputs_distinct(a, d) || !library_from_env(a, d))
        return false;
    a->parse.image_width = a->req.width;
    a->parse.image_height = a->req.height;
    return true;
}
