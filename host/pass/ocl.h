/*
 * ocl.h — the data-parallel phase: every primary ray of the image in one
 * OpenCL pass (simd_kernels/primary.cl, built from the shared csg/ code),
 * plus the number of hits per tile.
 */
#ifndef PASS_OCL_H
#define PASS_OCL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../../csg/diag.h"
#include "../../csg/features.h"

typedef struct ocl_ctx ocl_ctx; /* struct ocl_ctx is named in render.h */

/* The most records ocl_options.slice_records may ask ($CSGTRACE_CL_SLICE). */
#define OCL_SLICE_RECORDS_MAX (1LL << 30)

typedef struct {
    const char *device;  /* "P:D" (platform and device index), a substring
                            of the device name, or NULL for the first
                            device (--cl-device, $CSGTRACE_CL_DEVICE)  */
    int use_double;      /* build the double kernel (needs cl_khr_fp64)    */
    size_t max_slice_bytes; /* device bytes of one slice's records; 0: fit
                               the device, at most 256 MiB; tests force
                               small slices with tiny values             */
    const csg_features *features; /* build the program for these only
                               (csg_blob_features of the scene to come);
                               NULL: the general program, any scene      */
    int packet;          /* the packet kernel's width in rays: 2, 4, 8 or
                            16; 0: twice the device's preferred vector
                            width ($CSGTRACE_CL_PACKET)                  */
    const char *cache_dir; /* compiled programs kept in this folder
                              (cl_cache.h); NULL: none                   */
    const char *source;  /* the program's source; NULL: the one embedded
                            in the program (tests give a broken one)     */
    size_t slice_records; /* a background pass's slices hold at least so
                            many records, in whole tile rows (memory
                            allowing); 0: the device's default, none on a
                            CPU (the caller's rows), 2^22 on any other
                            device (ocl.c: OCL_DEVICE_SLICE_RECORDS)      */
    int copy_buffers;    /* the pass's buffers are the device's own, the
                            scene copied in and the records copied out,
                            even where the device works in host memory
                            and could use them in place (tests and the
                            harness: both ways)                           */
} ocl_options;

/* The primary kernel's variant (simd_kernels/primary.cl): one ray a
 * work-item (GPUs), or a packet of rays in OpenCL vectors a work-item
 * (CPUs: simd_kernels/packet.h).  Both give the same records. */
enum ocl_kernel {
    OCL_KERNEL_AUTO,   /* packet on a CPU device, scalar otherwise       */
    OCL_KERNEL_SCALAR,
    OCL_KERNEL_PACKET
};

typedef struct {
    double setup_s;      /* ocl_open apart from compile_s: platform and
                            device choice, context, queue                */
    double compile_s;    /* program build (or PoCL cache load) and one
                            warm-up launch (PoCL's per-work-group-size
                            compile), so primary_s holds no compilation */
    double primary_s;    /* the pass: buffers, upload, kernels, download
                            (begin .. the last slice seen complete)      */
    int slices;          /* passes the image needed                       */
    double device_kernel_s; /* the last pass on the device's clock (0:
                            the queue does not time commands): its
                            slices' kernels, ...                         */
    double device_copy_s;   /* ...their records' copies (mappings in
                            place) and tile counts after them, ...       */
    double device_span_s;   /* ...and the first slice's start to the last
                            one's end: the rest of it the device waited
                            for the host to enqueue                      */
    int compute_units;   /* CL_DEVICE_MAX_COMPUTE_UNITS (cores of a CPU)   */
    bool cpu_device;     /* the device is a CPU (CL_DEVICE_TYPE_CPU)      */
    bool records_in_place; /* the last pass's kernels wrote their records
                            straight into the caller's arrays (a device
                            in host memory, arrays aligned for it: see
                            ocl_pass_begin); false: copied out of device
                            buffers                                      */
    char kernel[32];     /* the variant built: "scalar", "packet 16 (4x4)" */
    char device_name[256];
} ocl_timing;

/* Picks the device, builds the program with the kernel variant `kernel`;
 * false with d filled on failure (the build log goes to stderr). */
bool ocl_open_kernel(const ocl_options *opt, enum ocl_kernel kernel, ocl_ctx **out,
                     ocl_timing *timing, csg_diag *d);

/* ocl_open_kernel in two halves, so the first can run while the scene is
 * read (render.c): the device (opt->device's rule), its context and
 * queue; then, on that context, the checks that depend on the scene
 * (cl_khr_fp64 for double), the kernel variant and the program.  After a
 * failed ocl_open_program the caller closes the context. */
bool ocl_open_device(const char *device, ocl_ctx **out, ocl_timing *timing, csg_diag *d);
bool ocl_open_program(ocl_ctx *c, const ocl_options *opt, enum ocl_kernel kernel,
                      ocl_timing *timing, csg_diag *d);

/* Makes the context's program able to run scenes that use `need`: kept
 * when it already covers them (csg_features_cover), else rebuilt for
 * exactly `need` (the time added to timing->compile_s).  A pass refuses
 * a blob its program does not cover. */
bool ocl_specialise(ocl_ctx *ctx, csg_features need, ocl_timing *timing, csg_diag *d);

/* The feature set the context's program was built for (everything for
 * the general program). */
csg_features ocl_features(const ocl_ctx *ctx);
/* Whether the device is the host's CPU (CL_DEVICE_TYPE_CPU: PoCL's). */
bool ocl_cpu_device(const ocl_ctx *ctx);

/* ocl_open_kernel with OCL_KERNEL_AUTO. */
bool ocl_open(const ocl_options *opt, ocl_ctx **out, ocl_timing *timing, csg_diag *d);

/* "auto", "scalar", "packet" -> *out; false for anything else. */
bool ocl_kernel_parse(const char *name, enum ocl_kernel *out);

/* Traces the primary rays of the whole image of `blob` (its header holds
 * width and height).  t_out: real[w*h] (the blob's precision), surf_out:
 * uint32[w*h], row-major; tile_hits: uint32[tiles_x * tiles_y], the number
 * of pixels of each tile (row-major over tiles of `tile` x `tile`) whose
 * primary ray hit something.  Returns when the pass is over. */
bool ocl_primary_pass(ocl_ctx *ctx, const void *blob, int tile, void *t_out, uint32_t *surf_out,
                      uint32_t *tile_hits, ocl_timing *timing, csg_diag *d);

/* The same pass in the background, for a caller with other work (the
 * master serving its workers): ocl_pass_begin puts the first slices of
 * `slice_rows` rows (0: as many as the device allows; the device may
 * allow fewer, and slices of at least ocl_options.slice_records records
 * make them more) on the queue and returns at once; every ocl_pass_rows
 * call tops the queue up (a few slices beyond the last complete one,
 * so call it often: the master does in every turn); notify(notify_arg), if given, is
 * called from an OpenCL thread whenever a slice completes (keep it short
 * and thread-safe: a wake-up).  ocl_pass_rows says how many rows from the
 * top have final records and final tile counts (slices complete in
 * order); with `wait` it first blocks until one more slice completes;
 * -1 with d filled when the pass failed.  ocl_pass_end waits for what was
 * enqueued, fills timing (primary_s, slices, device_name) and frees the
 * pass; it must be called once ocl_pass_begin set *out (even when it
 * failed) and before the output arrays are freed; it returns whether
 * every needed slice completed (ocl_pass_limit).  known_out and lit_out
 * (both or neither; NULL: none): each slice's shadow answers too (the
 * csg_shadows kernel, as ocl_shadow_answers), in the records' order. */
typedef struct ocl_pass ocl_pass;
/* Records in page-aligned host memory (memory_pages_alloc, host/memory.h)
 * on a device that works in host memory (a CPU, an integrated GPU): the
 * pass's kernels write them in place, nothing copied
 * (timing->records_in_place).  Any other array works too, through a
 * copy. */
bool ocl_pass_begin(ocl_ctx *ctx, const void *blob, int tile, int slice_rows, void *t_out,
                    uint32_t *surf_out, uint32_t *known_out, uint32_t *lit_out,
                    uint32_t *tile_hits, void (*notify)(void *), void *notify_arg,
                    ocl_pass **out, csg_diag *d);
int ocl_pass_rows(ocl_pass *p, bool wait, csg_diag *d);
/* Only the top `rows` rows are needed (the rest was rendered otherwise:
 * render.c's fill): no slice below them goes on the queue any more, and
 * the pass is whole once they are complete.  Only ever lowers. */
void ocl_pass_limit(ocl_pass *p, int rows);
bool ocl_pass_end(ocl_pass *p, ocl_timing *timing, csg_diag *d);

/* The shadow answers of a whole image's primary records (t_image, surf_image:
 * what ocl_primary_pass gives, width * spp records a row) into known_out[]
 * and lit_out[] (a word each a record: csg/device/shadow.h,
 * csg_shadow_masks; engine->shade_answered takes them), in one launch of
 * csg_shadows (a work-item a record in the one-ray program, a packet in
 * the packet program: the walk in OpenCL vectors, packet.h).  *seconds
 * (may be NULL): buffers, kernel, download. */
bool ocl_shadow_answers(ocl_ctx *ctx, const void *blob, const void *t_image,
                        const uint32_t *surf_image, uint32_t *known_out, uint32_t *lit_out,
                        double *seconds, csg_diag *d);

void ocl_close(ocl_ctx *ctx);

/* The layout probe (kernel csg_layout): out[0 .. *count) receives the
 * device's sizeof / offsetof list of CSG_LAYOUT_FIELDS (csg/device/flat.h) in the
 * context's precision (tests/test_layout.c compares it with the C side). */
bool ocl_probe_layout(ocl_ctx *ctx, int32_t *out, int cap, int *count, csg_diag *d);

/* "CL_INVALID_VALUE" for -30, ...; "CL_UNKNOWN_ERROR" for codes it does
 * not know.  (A cl_int.) */
const char *ocl_error_name(int32_t err);

#endif
