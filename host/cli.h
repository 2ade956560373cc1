/*
 * cli.h — the command line (DESIGN.md's contract) parsed into plain data;
 * main.c only dispatches.  Bad arguments are bad input: exit status 2.
 */
#ifndef HOST_CLI_H
#define HOST_CLI_H

#include <stdbool.h>
#include <stdio.h>

#include "../csg/diag.h"
#include "render.h"

#define CLI_MAX_LIBRARY 64 /* --library-path options */

enum cli_command { CMD_RENDER, CMD_COMPARE, CMD_CHECK, CMD_EXPORT, CMD_GEN, CMD_HELP, CMD_VERSION };

typedef struct {
    enum cli_command command;
    csg_config env;       /* the environment's settings (config.h)          */
    render_request req;   /* render, compare; check and export use scene_path */
    bool flat;            /* export --flat                                    */
    const char *out_path; /* export -o, compare -o PREFIX                     */
    int repeat;           /* compare --repeat                                 */
    csg_parse_options parse; /* --clock, --library-path (req.parse points here) */
    const char *library[CLI_MAX_LIBRARY]; /* --library-path DIR, in order, then
                                             $CSGTRACE_LIBRARY_PATH's folders */
    char library_env[4096];  /* $CSGTRACE_LIBRARY_PATH, cut at its ':'s      */
} cli_args;

/* Fills *a from argv and the environment's settings (read once here:
 * config.h); false with d filled (a usage error) otherwise. */
bool cli_parse(int argc, char **argv, cli_args *a, csg_diag *d);
void cli_usage(FILE *out);

#endif
