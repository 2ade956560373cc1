/*
 * main.c — csgtrace's entry point: parse the command line, dispatch.
 * The stages live elsewhere: csg/ (language, geometry), host/render.c (the
 * modes and MPI), workers/ (tracing and shading).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/export_pov.h"
#include "../csg/device/flat.h"
#include "../csg/flatten.h"
#include "../csg/features.h"
#include "../csg/load.h"
#include "../csg/numbers.h"
#include "../csg/precision.h"
#include "../csg/summary.h"
#include "cli.h"
#include "compare.h"
#include "output/image.h"
#include "render.h"
#include "signals.h"
#include "version.h"

static int fail(const csg_diag *d, int status)
{
    fprintf(stderr, "%s\n", d->message);
    return status;
}

/* check: parse, validate by flattening (as a render would), summarise. */
static int run_check(const cli_args *a)
{
    csg_diag d = {0};
    csg_scene s;
    int width, height;
    if (!csg_load_file(a->req.scene_path, &a->parse, &s, &d))
        return fail(&d, EXIT_BAD_INPUT);
    csg_image_size(&s, a->req.width, a->req.height, &width, &height);
    csg_flatten_opts fo = {width, height, 0, -1, 1, 0};
    csg_blob blob;
    if (!csg_flatten_double(&s, &fo, &blob, &d)) {
        csg_scene_free(&s);
        return fail(&d, EXIT_BAD_INPUT);
    }
    csg_print_summary(&s, stdout);
    char why[256];
    csg_needs_double(&s, width, height, why, sizeof why);
    printf("--precision auto at %dx%d: %s\n", width, height, why);
    const csg_blob_header *h = csg_blob_hdr(blob.bytes);
    printf("flat scene: %d primitives in %d roots, %d CSG nodes, %d materials; "
           "deepest program needs %d interval lists (limit %d)\n",
           h->prim_count, h->root_count, h->node_count, h->material_count, h->max_stack,
           CSG_STACK_MAX);
    char spec[256];
    csg_features_describe(csg_blob_features(blob.bytes), spec, sizeof spec);
    printf("specialised: %s\n", spec);
    csg_blob_free(&blob);
    csg_scene_free(&s);
    return EXIT_OK;
}

/* export: the parsed scene back as POV-Ray SDL (--flat: geometry and
 * colours only, for the cross-check against POV-Ray). */
static int run_export(const cli_args *a)
{
    csg_diag d = {0};
    csg_scene s;
    if (!csg_load_file(a->req.scene_path, &a->parse, &s, &d))
        return fail(&d, EXIT_BAD_INPUT);
    int status = EXIT_OK;
    FILE *out = fopen(a->out_path, "w");
    if (!out) {
        perror(a->out_path);
        status = EXIT_FAILURE_RUN;
    } else {
        bool ok = csg_export_pov(&s, out, a->flat, &d);
        if (fclose(out) != 0 || !ok) {
            if (d.failed)
                fprintf(stderr, "%s\n", d.message);
            else
                perror(a->out_path);
            remove(a->out_path);
            status = d.failed ? EXIT_BAD_INPUT : EXIT_FAILURE_RUN;
        }
    }
    csg_scene_free(&s);
    return status;
}

/* gen spheres: a random-sphere scene with a measured occupancy. */
static int run_gen(const cli_args *a)
{
    csg_diag d = {0};
    const gen_options o = a->gen;
    gen_result r;
    if (!gen_spheres(&o, &r, &d))
        return fail(&d, EXIT_FAILURE_RUN);
    printf("%s: %d spheres, occupancy %.2f%% at %dx%d (target %.2f%%), radius scale %.4g, "
           "%d primary passes\n",
           o.out_path, o.count, 100 * r.occupancy, o.width, o.height, 100 * o.occupancy, r.scale,
           r.evaluations);
    return EXIT_OK;
}

/* The image settings of the environment (config.h), given to the image
 * layer once; a PNG level that is not 0 to 9 is ignored with a warning. */
static void configure_images(const csg_config *env)
{
    long long level = -1;
    if (env->png_level && !number_whole(env->png_level, 0, 9, &level)) {
        fprintf(stderr, "csgtrace: warning: CSGTRACE_PNG_LEVEL=%s is not 0 to 9; ignored\n",
                env->png_level);
        level = -1;
    }
    img_settings s = {env->image_module,
                      env->image_writer && strcmp(env->image_writer, "oiio") == 0, (int)level};
    img_configure(&s);
}

int main(int argc, char **argv)
{
    cli_args a;
    csg_diag d = {0};
    signals_ignore_file_limit(); /* (every command, every rank: EFBIG, said) */
    if (!cli_parse(argc, argv, &a, &d))
        return fail(&d, EXIT_BAD_INPUT);
    configure_images(&a.env);
    switch (a.command) {
    case CMD_HELP:
        cli_usage(stdout);
        config_usage(stdout);
        return EXIT_OK;
    case CMD_VERSION:
        printf("csgtrace %s (build %016llx)\n", CSGTRACE_VERSION,
               (unsigned long long)version_build_hash());
        return EXIT_OK;
    case CMD_CHECK:
        return run_check(&a);
    case CMD_EXPORT:
        return run_export(&a);
    case CMD_GEN:
        return run_gen(&a);
    case CMD_COMPARE:
        return compare_run(&a);
    case CMD_RENDER:
        return render_run(&a.req);
    default:
        cli_usage(stderr);
        return EXIT_BAD_INPUT;
    }
}
