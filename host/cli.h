/*
 * cli.h — the command line (docs/cli.md) parsed into plain data; main.c
 * only dispatches.  Bad arguments are bad input: exit status 2.  The
 * options are one table (options.h).
 */
#ifndef HOST_CLI_H
#define HOST_CLI_H

#include <stdbool.h>
#include <stdio.h>

#include "../csg/diag.h"
#include "gen.h"
#include "render.h"

#define CLI_MAX_LIBRARY 64 /* --library-path options */
#define CLI_RELAYS_MAX 4096 /* --relays: a relay per 2 workers at most anyway */

enum cli_command { CMD_RENDER, CMD_COMPARE, CMD_CHECK, CMD_EXPORT, CMD_GEN, CMD_HELP, CMD_VERSION };

typedef struct {
    enum cli_command command;
    csg_config env;       /* the environment's settings (config.h)          */
    render_request req;   /* render, compare; check and export use scene_path */
    gen_options gen;      /* gen spheres                                    */
    bool flat;            /* export --flat                                    */
    const char *out_path; /* -o: render, export, gen; compare's PREFIX       */
    int repeat;           /* compare --repeat                                 */
    csg_parse_options parse; /* --clock, --library-path (req.parse points here) */
    const char *library[CLI_MAX_LIBRARY]; /* --library-path DIR, in order, then
                                             $CSGTRACE_LIBRARY_PATH's folders */
    char library_env[4096];  /* $CSGTRACE_LIBRARY_PATH, cut at its ':'s      */
} cli_args;

/* Fills *a from argv and the environment's settings (read once here:
 * config.h); false with d filled (a usage error) otherwise. */
bool cli_parse(int argc, char **argv, cli_args *a, csg_diag *d);
/* The usage, every option of the table with its line of help. */
void cli_usage(FILE *out);

#endif
