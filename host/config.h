/*
 * config.h — the settings csgtrace takes from its environment, read once
 * at start (main, on every rank) into one struct that travels with the
 * request.  No other file reads a CSGTRACE_* variable; the test hooks are
 * apart (comm/test_hooks.h), and so are the launcher's own variables
 * (Open MPI's, read by comm/mpi_link.c).  A value is checked where it is
 * used, so a setting that a command does not use cannot fail it.
 */
#ifndef HOST_CONFIG_H
#define HOST_CONFIG_H

#include <stdio.h>

/* The variables: X(field, name, what it sets). */
#define CONFIG_VARIABLES(X)                                                                    \
    X(cl_device, "CSGTRACE_CL_DEVICE", "the OpenCL device when --cl-device is not given")      \
    X(cl_kernel, "CSGTRACE_CL_KERNEL", "the primary kernel when --cl-kernel is auto: "         \
                                       "auto, scalar or packet")                               \
    X(cl_packet, "CSGTRACE_CL_PACKET", "the packet kernel's width: 2, 4, 8 or 16")            \
    X(cl_slice, "CSGTRACE_CL_SLICE", "the least hit records of a slice of the OpenCL pass, "  \
                                     "in whole tile rows (default: a tile row on a CPU "      \
                                     "device, 4194304 on a GPU)")                             \
    X(cl_specialise, "CSGTRACE_CL_SPECIALISE",                                                 \
      "0: build the general OpenCL program, not one for the scene's features")                 \
    X(cl_cache, "CSGTRACE_CL_CACHE", "the folder of compiled OpenCL programs; off: none "      \
                                     "(default $XDG_CACHE_HOME/csgtrace, ~/.cache/csgtrace)")  \
    X(library_path, "CSGTRACE_LIBRARY_PATH",                                                   \
      "':'-separated folders #include searches after --library-path")                         \
    X(image_module, "CSGTRACE_IMAGE_MODULE", "the OpenImageIO module's path")                  \
    X(image_writer, "CSGTRACE_IMAGE_WRITER", "oiio: OpenImageIO writes PNG and PPM too")       \
    X(png_level, "CSGTRACE_PNG_LEVEL", "0 to 9: PNG at that zlib level, every filter")         \
    X(worker_bind, "CSGTRACE_WORKER_BIND", "off: workers never bind themselves to a CPU")      \
    X(page_trace, "CSGTRACE_PAGE_TRACE", "with --scene-memory: each rank writes the pages "    \
                                         "its items named to this file name + .RANK")

typedef struct {
#define CONFIG_FIELD(field, name, what) const char *field;
    CONFIG_VARIABLES(CONFIG_FIELD)
#undef CONFIG_FIELD
    const char *xdg_cache_home; /* $XDG_CACHE_HOME, $HOME: where the      */
    const char *home;           /* program cache goes by default          */
} csg_config;

/* Every variable of the table (NULL: unset or empty). */
void config_read(csg_config *c);

/* The table for --help: one line a variable. */
void config_usage(FILE *out);

#endif
