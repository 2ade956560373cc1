/*
 * cli.c — parsing of `csgtrace COMMAND ARGS...` (see cli_usage).
 * Every option is checked for range and form here, so the stages after it
 * can trust the request.
 */
#include "cli.h"

#include "../csg/flatten.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

void cli_usage(FILE *out)
{
    fputs("usage:\n"
          "  csgtrace render  SCENE -o OUT [--mode serial|homo|hetero] [--width W] [--height H]\n"
          "                   [--tile N] [--depth D] [--threshold W] [--spp N]\n"
          "                   [--precision float|double|auto]\n"
          "                   [--stats FILE.json] [--cl-device SEL] [--cl-kernel auto|scalar|packet]\n"
          "                   [--progress|--no-progress]\n"
          "  csgtrace compare SCENE [-o PREFIX] [--repeat R] [same options as render]\n"
          "  csgtrace check   SCENE\n"
          "  csgtrace gen spheres --count N --occupancy F --seed S [--width W --height H]\n"
          "                   [--materials opaque,reflective,transparent] -o scene.pov\n"
          "  csgtrace export  SCENE -o OUT.pov [--flat]\n"
          "  csgtrace help | --help | --version\n"
          "Run the parallel modes under mpirun: mpirun -np K build/csgtrace render ...\n"
          "Image format follows OUT's extension (png, exr, tif, ppm, ...).\n",
          out);
}

static bool parse_int(const char *opt, const char *s, int lo, int hi, int *out, csg_diag *d)
{
    char *end;
    errno = 0;
    long v = s ? strtol(s, &end, 10) : 0;
    if (!s || errno || end == s || *end || v < lo || v > hi) {
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
    char *end;
    errno = 0;
    double v = s ? strtod(s, &end) : 0;
    if (!s || errno || end == s || *end || !(v >= lo && v <= hi)) {
        csg_error_plain(d, "%s expects a number from %g to %g, got '%s'", opt, lo, hi, s ? s : "");
        return false;
    }
    *out = v;
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
    csg_error_plain(d, "%s expects one of %s%s%s%s%s, got '%s'", opt, names[0], n > 1 ? ", " : "",
                    n > 1 ? names[1] : "", n > 2 ? ", " : "", n > 2 ? names[2] : "", s ? s : "");
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
    static const char *const kernels[] = {"auto", "scalar", "packet"};
    const char *opt = argv[*i];
    render_request *r = &a->req;
    if (strcmp(opt, "--flat") == 0) {
        a->flat = true;
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
    if (strcmp(opt, "--cl-device") == 0) {
        r->cl_device = val;
        return true;
    }
    if (strcmp(opt, "--cl-kernel") == 0) {
        /* The OpenCL kernel variant reaches ocl_open (host/ocl.c) as
         * $CSGTRACE_CL_KERNEL, which the option overrides: only this
         * process (the master: rank 0 runs the OpenCL pass) reads it. */
        if (!parse_choice(opt, val, kernels, 3, &choice, d))
            return false;
        if (setenv("CSGTRACE_CL_KERNEL", val, 1) != 0) {
            csg_error_plain(d, "--cl-kernel: cannot set CSGTRACE_CL_KERNEL");
            return false;
        }
        return true;
    }
    if (strcmp(opt, "--width") == 0)
        return parse_int(opt, val, 1, 65536, &r->width, d);
    if (strcmp(opt, "--height") == 0)
        return parse_int(opt, val, 1, 65536, &r->height, d);
    if (strcmp(opt, "--tile") == 0)
        return parse_int(opt, val, 1, 65536, &r->tile, d);
    if (strcmp(opt, "--spp") == 0)
        return parse_int(opt, val, 1, CSG_MAX_SPP, &r->spp, d);
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

bool cli_parse(int argc, char **argv, cli_args *a, csg_diag *d)
{
    memset(a, 0, sizeof *a);
    a->req.mode = MODE_SERIAL;
    a->req.precision = PREC_FLOAT;
    a->req.width = 320;
    a->req.height = 240;
    a->req.tile = RENDER_DEFAULT_TILE;
    a->req.spp = 1;
    a->req.progress = PROGRESS_TTY;
    a->req.threshold = -1;
    a->repeat = 3;
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
    return true;
}
