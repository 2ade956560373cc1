/*
 * cli.c — parsing of `csgtrace COMMAND ARGS...` (see cli_usage) through
 * the one table of options (options.h): each value is checked for range
 * and form here, and each option for the command it is given to, so the
 * stages after it can trust the request.
 */
#include "cli.h"

#include <limits.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../comm/protocol.h"
#include "../csg/flatten.h"
#include "../csg/numbers.h"
#include "../workers/pager.h"
#include "options.h"
#include "output/claim.h"
#include "output/file_atomic.h"
#include "output/journal.h"
#include "schedule.h"
#include "store.h"

/* The words of the choices (options.h), in the order of their enums. */
static const char *const cli_modes[] = {"serial", "homo", "hetero", NULL};
static const char *const cli_precisions[] = {"float", "double", "auto", NULL};
static const char *const cli_schedules[] = {"raster", "cost", "static", "tail", "region", NULL};
static const char *const cli_kernels[] = {"auto", "scalar", "packet", NULL}; /* enum ocl_kernel */
static const char *const cli_fill[] = {"on", "off", NULL};     /* no_fill: "off"        */
static const char *const cli_compress[] = {"auto", "on", "off", NULL}; /* enum render_compress */
static const char *const cli_records[] = {"auto", "send", "retrace", NULL}; /* render_records */
static const char *const cli_page_policies[] = {"lru", "fifo", NULL}; /* enum pager_policy */
static const char *const cli_page_homes[] = {"auto", "master", "spread", NULL}; /* enum pager_home */
static const char *const cli_page_prefetch[] = {"off", "on", "shadows", NULL}; /* enum pager_prefetch */
static const char *const cli_page_fetch[] = {"get", "ask", NULL}; /* enum pager_fetch_mode */
static const char *const cli_pass[] = {"auto", "always", NULL}; /* pass_always: "always" */
static const char *const cli_simd[] = {"primary", "shadows", NULL}; /* simd_shadows: "shadows" */
static const char *const cli_materials[] = {"opaque", "reflective", "transparent", NULL};

typedef struct {
    const char *name, *alias, *value;
    enum cli_kind kind;
    size_t offset;        /* of the field in cli_args                  */
    size_t size;          /* of the field: checked against the kind    */
    double lo, hi;
    const char *const *choices;
    unsigned commands;    /* CLI_ON_* bits                             */
    const char *help;
} cli_option;

static const cli_option cli_options[] = {
#define CLI_ROW(name, alias, value, kind, field, lo, hi, choices, commands, help)             \
    {name, alias, value, kind, offsetof(cli_args, field), sizeof(((cli_args *)0)->field), lo,  \
     hi, choices, commands, help},
    CLI_OPTIONS(CLI_ROW)
#undef CLI_ROW
};
enum { CLI_OPTION_COUNT = sizeof cli_options / sizeof cli_options[0] };

/* The size of the field each kind writes (the table's rows are checked
 * against it: a row whose field has another size does not compile). */
#define CLI_KIND_SIZE(kind)                                                                    \
    ((kind) == CLI_FLAG || (kind) == CLI_SWITCH ? sizeof(bool)                                 \
     : (kind) == CLI_TEXT || (kind) == CLI_PATH ? sizeof(const char *)                         \
     : (kind) == CLI_U64                        ? sizeof(uint64_t)                             \
     : (kind) == CLI_REAL                       ? sizeof(double)                               \
     : (kind) == CLI_FOLDER                     ? sizeof(((cli_args *)0)->library)             \
                                                : sizeof(int))
#define CLI_CHECK(name, alias, value, kind, field, lo, hi, choices, commands, help)           \
    _Static_assert(sizeof(((cli_args *)0)->field) == CLI_KIND_SIZE(kind),                      \
                   name " sets a field of another type than its kind writes");
CLI_OPTIONS(CLI_CHECK)
#undef CLI_CHECK

static const struct {
    const char *name;
    enum cli_command cmd;
} commands[] = {{"render", CMD_RENDER}, {"compare", CMD_COMPARE}, {"check", CMD_CHECK},
                {"export", CMD_EXPORT}, {"gen", CMD_GEN},         {"help", CMD_HELP},
                {"--help", CMD_HELP},   {"-h", CMD_HELP},         {"--version", CMD_VERSION}};

/* The commands' names in `mask`, comma-separated, into buf. */
static void cli_command_names(unsigned mask, char *buf, size_t size)
{
    buf[0] = '\0';
    for (int c = CMD_RENDER; c <= CMD_GEN; c++) {
        if (!(mask & (1u << c)))
            continue;
        size_t used = strlen(buf);
        snprintf(buf + used, size - used, "%s%s", used ? ", " : "", commands[c].name);
    }
}

void cli_usage(FILE *out)
{
    fputs("usage:\n"
          "  csgtrace render  SCENE -o OUT [options]      render an image\n"
          "  csgtrace compare SCENE [-o PREFIX] [options] homo and hetero, interleaved: "
          "the table\n"
          "  csgtrace check   SCENE [options]             parse, validate, summarise\n"
          "  csgtrace export  SCENE -o OUT.pov [options]  the parsed scene as POV-Ray SDL\n"
          "  csgtrace gen spheres -o OUT.pov [options]    a random-sphere scene\n"
          "  csgtrace help | --help | --version\n"
          "Run the parallel modes under mpirun: mpirun -np K csgtrace render ...\n"
          "options (the commands that take each):\n",
          out);
    for (int i = 0; i < CLI_OPTION_COUNT; i++) {
        const cli_option *o = &cli_options[i];
        char spell[64], on[64];
        snprintf(spell, sizeof spell, "%s%s%s%s%s", o->name, o->alias ? ", " : "",
                 o->alias ? o->alias : "", o->value ? " " : "", o->value ? o->value : "");
        cli_command_names(o->commands, on, sizeof on);
        if (strlen(spell) > 33) /* (a long spelling: its help on the next line) */
            fprintf(out, "  %s\n  %-34s %s [%s]\n", spell, "", o->help, on);
        else
            fprintf(out, "  %-34s %s [%s]\n", spell, o->help, on);
    }
}

/* ---- values ------------------------------------------------------------------- */

static bool cli_int(const cli_option *o, const char *s, long long *out, csg_diag *d)
{
    if (number_whole(s, (long long)o->lo, (long long)o->hi, out))
        return true;
    csg_error_plain(d, "%s expects a whole number from %.0f to %.0f, got '%s'", o->name, o->lo,
                    o->hi, s);
    return false;
}

/* The index of `s` among o's choices, or -1 with d filled. */
static int cli_choice(const cli_option *o, const char *s, csg_diag *d)
{
    char list[256] = "";
    for (int i = 0; o->choices[i]; i++) {
        if (strcmp(s, o->choices[i]) == 0)
            return i;
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", o->choices[i]);
    }
    csg_error_plain(d, "%s expects one of %s, got '%s'", o->name, list, s);
    return -1;
}

/* The comma-separated choices of s as bits (1 << index each). */
static bool cli_bits(const cli_option *o, const char *s, unsigned *out, csg_diag *d)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", s);
    *out = 0;
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok;
         tok = strtok_r(NULL, ",", &save)) {
        int i = cli_choice(o, tok, d);
        if (i < 0)
            return false;
        *out |= 1u << i;
    }
    if (*out == 0) {
        csg_error_plain(d, "%s needs at least one of its kinds", o->name);
        return false;
    }
    return true;
}

/* Option o's value `val` (NULL for a kind that takes none) into its
 * field of a. */
static bool cli_set(const cli_option *o, const char *val, cli_args *a, csg_diag *d)
{
    void *field = (char *)a + o->offset;
    long long n;
    int i;
    switch (o->kind) {
    case CLI_FLAG:
        *(bool *)field = true;
        return true;
    case CLI_SET:
        *(int *)field = (int)o->lo;
        return true;
    case CLI_PATH:
        if (!val[0]) { /* (else a library's message about no file name, exit 1) */
            csg_error_plain(d, "%s needs a file name, got an empty one", o->name);
            return false;
        }
        *(const char **)field = val;
        return true;
    case CLI_TEXT:
        *(const char **)field = val;
        return true;
    case CLI_INT_AUTO:
    case CLI_INT:
        n = 0; /* ("auto") */
        if (!(o->kind == CLI_INT_AUTO && strcmp(val, "auto") == 0) && !cli_int(o, val, &n, d))
            return false;
        *(int *)field = (int)n;
        return true;
    case CLI_U64:
        if (!cli_int(o, val, &n, d))
            return false;
        *(uint64_t *)field = (uint64_t)n;
        return true;
    case CLI_REAL:
        if (number_real(val, o->lo, o->hi, (double *)field))
            return true;
        csg_error_plain(d, "%s expects a number from %g to %g, got '%s'", o->name, o->lo, o->hi,
                        val);
        return false;
    case CLI_CHOICE:
    case CLI_SWITCH:
        if ((i = cli_choice(o, val, d)) < 0)
            return false;
        if (o->kind == CLI_SWITCH)
            *(bool *)field = i == 1;
        else
            *(int *)field = i;
        return true;
    case CLI_BITS:
        return cli_bits(o, val, (unsigned *)field, d);
    case CLI_FOLDER:
        if (a->parse.library_path_count == CLI_MAX_LIBRARY) {
            csg_error_plain(d, "at most %d --library-path options", CLI_MAX_LIBRARY);
            return false;
        }
        a->library[a->parse.library_path_count++] = val;
        return true;
    }
    return false;
}

/* The row for spelling `opt` given to command `cmd`: the first that
 * takes it there; NULL with d filled when none does. */
static const cli_option *cli_find(const char *opt, enum cli_command cmd, csg_diag *d)
{
    const cli_option *named = NULL;
    for (int i = 0; i < CLI_OPTION_COUNT; i++) {
        const cli_option *o = &cli_options[i];
        if (strcmp(opt, o->name) != 0 && !(o->alias && strcmp(opt, o->alias) == 0))
            continue;
        if (o->commands & (1u << cmd))
            return o;
        named = named ? named : o;
    }
    if (!named) {
        csg_error_plain(d, "unknown option '%s' (see csgtrace --help)", opt);
        return NULL;
    }
    char on[64];
    unsigned all = 0;
    for (int i = 0; i < CLI_OPTION_COUNT; i++)
        if (strcmp(opt, cli_options[i].name) == 0 ||
            (cli_options[i].alias && strcmp(opt, cli_options[i].alias) == 0))
            all |= cli_options[i].commands;
    cli_command_names(all, on, sizeof on);
    csg_error_plain(d, "%s does not apply to %s (only to %s)", opt, commands[cmd].name, on);
    return NULL;
}

/* One option and its value (argv[*i + 1]); false on a bad one. */
static bool parse_option(cli_args *a, int argc, char **argv, int *i, csg_diag *d)
{
    const cli_option *o = cli_find(argv[*i], a->command, d);
    if (!o)
        return false;
    if (o->kind == CLI_FLAG || o->kind == CLI_SET)
        return cli_set(o, NULL, a, d);
    if (*i + 1 >= argc) {
        csg_error_plain(d, "%s needs a value", argv[*i]);
        return false;
    }
    (*i)++;
    return cli_set(o, argv[*i], a, d);
}

/* ---- the whole line ----------------------------------------------------------------- */

/* No output may overwrite the scene or another output: a mistyped -o or
 * --stats would silently replace it. */
static bool outputs_distinct(const cli_args *a, csg_diag *d)
{
    const char *names[] = {"the scene", "the output (-o)", "the stats (--stats)",
                           "the tile log (--tile-log)", "the output's journal",
                           "the output's lock"};
    char journal_path[PATH_MAX + sizeof JOURNAL_SUFFIX];
    char lock_path[PATH_MAX + sizeof CLAIM_LOCK_SUFFIX];
    bool renders = a->command == CMD_RENDER && a->out_path;
    if (renders) {
        journal_name(a->out_path, journal_path, sizeof journal_path);
        claim_lock_name(a->out_path, lock_path, sizeof lock_path);
    }
    const char *paths[] = {a->req.scene_path, a->out_path, a->req.stats_path,
                           a->req.tile_log_path, renders ? journal_path : NULL,
                           renders ? lock_path : NULL};
    for (int i = 1; i < 6; i++)
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

static void cli_defaults(cli_args *a)
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
    a->req.page_prefetch = PAGER_PREFETCH_ON;
    a->repeat = 3;
    a->gen.count = -1; /* (required) */
    a->gen.occupancy = -1;
    a->gen.width = 384;
    a->gen.height = 384;
    a->gen.materials = GEN_OPAQUE | GEN_REFLECTIVE | GEN_TRANSPARENT;
    csg_parse_options_default(&a->parse);
    a->parse.library_paths = a->library;
    a->parse.messages = stderr; /* #debug and #warning */
    a->req.parse = &a->parse;
}

/* The command's positional argument (the scene; gen: "spheres"). */
static bool cli_positional(cli_args *a, const char *arg, csg_diag *d)
{
    if (a->req.scene_path) {
        csg_error_plain(d, "unexpected argument '%s'", arg);
        return false;
    }
    a->req.scene_path = arg;
    return true;
}

/* What each command needs once every option is read. */
static bool cli_complete(cli_args *a, bool seed_given, csg_diag *d)
{
    if (a->command == CMD_GEN) {
        if (!a->req.scene_path || strcmp(a->req.scene_path, "spheres") != 0) {
            csg_error_plain(d, "gen: only 'gen spheres' exists");
            return false;
        }
        a->req.scene_path = NULL;
        a->gen.out_path = a->out_path;
        if (a->gen.count < 0 || a->gen.occupancy < 0 || !seed_given || !a->out_path) {
            csg_error_plain(d, "gen spheres needs --count N --occupancy F --seed S -o FILE");
            return false;
        }
        return true;
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
    /* (--simd shadows' answers travel with the records) */
    if (a->req.hit_records == RECORDS_RETRACE && a->req.simd_shadows) {
        csg_error_plain(d, "--hit-records retrace sends no records: --simd shadows has no way "
                           "to the workers");
        return false;
    }
    if (a->req.pieces > 0 && (a->req.pieces & (a->req.pieces - 1) || a->req.pieces & 0xaaaaaaaa)) {
        csg_error_plain(d, "--pieces: 1, 4, 16, 64 or auto, got %d", a->req.pieces);
        return false;
    }
    if (a->req.pieces > 1 && (a->req.schedule == SCHED_STATIC || a->req.schedule == SCHED_REGION)) {
        csg_error_plain(d, "--pieces %d: the %s schedule sends whole tiles", a->req.pieces,
                        sched_policy_name((enum sched_policy)a->req.schedule));
        return false;
    }
    if (!outputs_distinct(a, d) || !library_from_env(a, d))
        return false;
    a->parse.image_width = a->req.width;
    a->parse.image_height = a->req.height;
    return true;
}

bool cli_parse(int argc, char **argv, cli_args *a, csg_diag *d)
{
    cli_defaults(a);
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
    if (a->command == CMD_HELP || a->command == CMD_VERSION)
        return true;
    bool seed_given = false;
    for (int i = 2; i < argc; i++) {
        bool option = argv[i][0] == '-' && argv[i][1] != '\0';
        seed_given |= option && strcmp(argv[i], "--seed") == 0;
        if (!(option ? parse_option(a, argc, argv, &i, d) : cli_positional(a, argv[i], d)))
            return false;
    }
    return cli_complete(a, seed_given, d);
}
