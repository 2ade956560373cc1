/*
 * ocl.c — the OpenCL host side of the data-parallel phase (see ocl.h):
 * device choice, program build, the primary pass in slices, tile counts.
 *
 * Algorithm.  ocl_open picks one device (an explicit "P:D" or a name
 * substring from the options, else the first device of the first platform
 * that has one) and builds the program from the source embedded in the
 * program at build time (simd_kernels/primary.cl with its includes
 * inlined: tools/embed_kernels.py, so no source tree is read at run time)
 * with correctly rounded divide/sqrt and, for the double build,
 * -DCSG_DOUBLE.  The kernel variant (ocl_pick_kernel) is a -D too: the packet
 * kernel (-DCSG_PACKET=W -DCSG_PACKET_COLS=C, W twice the device's preferred
 * vector width of `real`) on CPU devices, the one-ray kernel elsewhere,
 * unless the caller says otherwise; both are the
 * same kernel name with the same arguments, only the grid differs (a
 * work-item a record, or a work-item a packet of C x W/C records).
 * Nothing that relaxes math is ever passed.  PoCL keeps the
 * compiled program in its cache (POCL_CACHE_DIR, default ~/.cache/pocl), so
 * only the first build of a given source + options (so of each variant) is
 * slow; compile_s
 * reports the build either way, apart from primary_s.
 *
 * The pass (ocl_pass_begin) uploads the whole flat blob as one read-only
 * buffer (the kernels rebuild __global pointers from the array offsets),
 * then walks the image in slices of rows: as many as the caller asks for
 * (a few tile rows when the master pipelines, host/render.c) and at most
 * what the device allows (max allocation, a share of the global memory,
 * and opt->max_slice_bytes or else 256 MiB).  A slice is a whole number of
 * tile rows whenever one tile row fits; otherwise it is a run of pixel
 * rows inside a tile row.  Per slice: the packet kernel's culling cells
 * it needs (ocl_cells_upto: the candidate roots of each 16 x 16 pixels,
 * found on the host as a C worker finds a tile's, written ahead of the
 * kernel), csg_primary (a work-item a record, or a packet of records),
 * csg_tile_hits (a work-item a tile touched by the slice), then
 * non-blocking reads of the records straight into the caller's arrays at
 * the slice's first row and of the slice's tile counts into a host array
 * of its own.  Every slice is enqueued at once on the in-order queue and
 * flushed, so the device works through them while the caller's thread is
 * free (the master serves its workers); the last read of a slice carries
 * an event, and an event callback tells the caller (notify) when it
 * completes.  ocl_pass_rows then checks the events in order on the
 * caller's thread and adds each completed slice's tile counts to
 * tile_hits.  The counts are integer sums, so the result does not depend
 * on the slicing.  ocl_primary_pass is the same pass, waited for whole.
 *
 * Invariants.  Every OpenCL call is checked and a failure is reported with
 * the call and the error's name (ocl_error_name); every object is released
 * on the one cleanup path of each function.  No globals.
 */
#define CL_TARGET_OPENCL_VERSION 120
#include "ocl.h"

#include <CL/cl.h>
#include <ctype.h>
#include <stdatomic.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../../csg/device/flat.h"
#include "../../csg/flatten.h"
#include "../../workers/engine.h"
#include "cl_cache.h"
#include "../../comm/test_hooks.h"

/* The program's source, all its includes inlined (tools/embed_kernels.py,
 * generated into the build folder by the Makefile). */
extern const char csg_kernel_source[];

#define OCL_MAX_PLATFORMS 16
/* Default cap on a slice's device buffers.  A CPU device's "device memory"
 * is a second copy in host memory, so whole-image buffers would double the
 * footprint of a large image; 256 MiB slices still hold 32 M pixels, far
 * more parallelism than any device needs, and cost one launch each. */
#define OCL_DEFAULT_SLICE_BYTES ((uint64_t)256 << 20)
/* The least records of a slice on a device that is not a CPU.  A GPU
 * needs hundreds of thousands of work-items in flight to be busy, and each
 * slice costs launches, reads and the master's turn to top the queue up.
 * Measured on an H200, 4096x4096 (bench/GPU.md, bench/gpu_pass.sh): the
 * pass took 0.222 s in 128 slices of a tile row, 0.188 s in 16 (2^20
 * records), 0.132 s in 4 (2^22), the kernel alone 0.018 s.  A CPU device
 * keeps one tile row: it shares the cores with the workers, and each
 * slice's tiles go out sooner. */
#define OCL_DEVICE_SLICE_RECORDS ((uint64_t)1 << 22)
/* Slices of a pass on the queue beyond the last complete one: enough to
 * keep the device busy between two polls of the master, few enough that
 * ocl_pass_limit stops the pass soon (host/render.c's fill). */
#define OCL_PASS_WINDOW 3
#define OCL_MAX_DEVICES 64
#define OCL_PLATFORM_NOT_FOUND_KHR (-1001) /* cl_khr_icd: no platform installed */

struct ocl_ctx {
    cl_device_id device;
    cl_context context;
    cl_command_queue queue;
    cl_program program;
    cl_kernel k_primary;    /* csg_primary: a record a pixel        */
    cl_kernel k_tiles;      /* csg_tile_hits: a count a tile        */
    cl_kernel k_layout;     /* csg_layout: the layout probe         */
    cl_kernel k_shadows;    /* csg_shadows: a record's shadow answers */
    size_t group_primary;   /* work-group width (dim 0) of csg_primary   */
    enum ocl_kernel kernel; /* SCALAR or PACKET: the variant built       */
    int packet, packet_cols; /* PACKET: rays a work-item, and the
                                packet's width in records (the rest are
                                rows): the grid of csg_primary          */
    size_t group_tiles;     /* and of csg_tile_hits                      */
    size_t group_shadows;   /* and of csg_shadows                        */
    int use_double;         /* the program was built with CSG_DOUBLE */
    csg_features features;  /* what the program handles (spec.h): the
                               scene's kinds and CSG bit, or all       */
    cl_ulong max_alloc;     /* CL_DEVICE_MAX_MEM_ALLOC_SIZE          */
    cl_ulong global_mem;    /* CL_DEVICE_GLOBAL_MEM_SIZE             */
    cl_uint compute_units;  /* CL_DEVICE_MAX_COMPUTE_UNITS           */
    bool cpu;               /* CL_DEVICE_TYPE_CPU                    */
    bool unified;           /* CL_DEVICE_HOST_UNIFIED_MEMORY: the device
                               works in host memory (CPUs, integrated
                               GPUs), so records can be written in place */
    size_t base_align;      /* CL_DEVICE_MEM_BASE_ADDR_ALIGN, in bytes   */
    bool profiling;         /* the queue times its commands (a pass's
                               device times: ocl_pass_profile)            */
    bool copy_buffers;      /* ocl_options.copy_buffers                   */
    uint64_t slice_records; /* the least records of a pass's slice
                               (ocl_options.slice_records, or the
                               device's default)                         */
    size_t max_slice_bytes; /* 0: no limit beyond the device's       */
    const char *source;     /* the program's source (ocl_options)     */
    const char *cache_dir;  /* compiled programs kept here (NULL: none) */
};

/* ---- errors -------------------------------------------------------------- */

typedef struct {
    int32_t code;
    const char *name;
} ocl_err_entry;

static const ocl_err_entry ocl_errors[] = {
    {0, "CL_SUCCESS"},
    {-1, "CL_DEVICE_NOT_FOUND"},
    {-2, "CL_DEVICE_NOT_AVAILABLE"},
    {-3, "CL_COMPILER_NOT_AVAILABLE"},
    {-4, "CL_MEM_OBJECT_ALLOCATION_FAILURE"},
    {-5, "CL_OUT_OF_RESOURCES"},
    {-6, "CL_OUT_OF_HOST_MEMORY"},
    {-7, "CL_PROFILING_INFO_NOT_AVAILABLE"},
    {-8, "CL_MEM_COPY_OVERLAP"},
    {-9, "CL_IMAGE_FORMAT_MISMATCH"},
    {-10, "CL_IMAGE_FORMAT_NOT_SUPPORTED"},
    {-11, "CL_BUILD_PROGRAM_FAILURE"},
    {-12, "CL_MAP_FAILURE"},
    {-13, "CL_MISALIGNED_SUB_BUFFER_OFFSET"},
    {-14, "CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST"},
    {-15, "CL_COMPILE_PROGRAM_FAILURE"},
    {-16, "CL_LINKER_NOT_AVAILABLE"},
    {-17, "CL_LINK_PROGRAM_FAILURE"},
    {-18, "CL_DEVICE_PARTITION_FAILED"},
    {-19, "CL_KERNEL_ARG_INFO_NOT_AVAILABLE"},
    {-30, "CL_INVALID_VALUE"},
    {-31, "CL_INVALID_DEVICE_TYPE"},
    {-32, "CL_INVALID_PLATFORM"},
    {-33, "CL_INVALID_DEVICE"},
    {-34, "CL_INVALID_CONTEXT"},
    {-35, "CL_INVALID_QUEUE_PROPERTIES"},
    {-36, "CL_INVALID_COMMAND_QUEUE"},
    {-37, "CL_INVALID_HOST_PTR"},
    {-38, "CL_INVALID_MEM_OBJECT"},
    {-39, "CL_INVALID_IMAGE_FORMAT_DESCRIPTOR"},
    {-40, "CL_INVALID_IMAGE_SIZE"},
    {-41, "CL_INVALID_SAMPLER"},
    {-42, "CL_INVALID_BINARY"},
    {-43, "CL_INVALID_BUILD_OPTIONS"},
    {-44, "CL_INVALID_PROGRAM"},
    {-45, "CL_INVALID_PROGRAM_EXECUTABLE"},
    {-46, "CL_INVALID_KERNEL_NAME"},
    {-47, "CL_INVALID_KERNEL_DEFINITION"},
    {-48, "CL_INVALID_KERNEL"},
    {-49, "CL_INVALID_ARG_INDEX"},
    {-50, "CL_INVALID_ARG_VALUE"},
    {-51, "CL_INVALID_ARG_SIZE"},
    {-52, "CL_INVALID_KERNEL_ARGS"},
    {-53, "CL_INVALID_WORK_DIMENSION"},
    {-54, "CL_INVALID_WORK_GROUP_SIZE"},
    {-55, "CL_INVALID_WORK_ITEM_SIZE"},
    {-56, "CL_INVALID_GLOBAL_OFFSET"},
    {-57, "CL_INVALID_EVENT_WAIT_LIST"},
    {-58, "CL_INVALID_EVENT"},
    {-59, "CL_INVALID_OPERATION"},
    {-60, "CL_INVALID_GL_OBJECT"},
    {-61, "CL_INVALID_BUFFER_SIZE"},
    {-62, "CL_INVALID_MIP_LEVEL"},
    {-63, "CL_INVALID_GLOBAL_WORK_SIZE"},
    {-64, "CL_INVALID_PROPERTY"},
    {-65, "CL_INVALID_IMAGE_DESCRIPTOR"},
    {-66, "CL_INVALID_COMPILER_OPTIONS"},
    {-67, "CL_INVALID_LINKER_OPTIONS"},
    {-68, "CL_INVALID_DEVICE_PARTITION_COUNT"},
    {-69, "CL_INVALID_PIPE_SIZE"},
    {-70, "CL_INVALID_DEVICE_QUEUE"},
    {-71, "CL_INVALID_SPEC_ID"},
    {-72, "CL_MAX_SIZE_RESTRICTION_EXCEEDED"},
    {-1001, "CL_PLATFORM_NOT_FOUND_KHR"},
};

const char *ocl_error_name(int32_t err)
{
    for (size_t i = 0; i < sizeof ocl_errors / sizeof ocl_errors[0]; i++)
        if (ocl_errors[i].code == err)
            return ocl_errors[i].name;
    return "CL_UNKNOWN_ERROR";
}

/* Reports "OpenCL: <what>: <name> (<code>)"; returns false. */
static bool ocl_fail(csg_diag *d, const char *what, cl_int err)
{
    csg_error_plain(d, "OpenCL: %s failed: %s (%d)", what, ocl_error_name(err), (int)err);
    return false;
}

static double ocl_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* ---- device choice -------------------------------------------------------- */

typedef struct {
    cl_platform_id platforms[OCL_MAX_PLATFORMS];
    cl_uint platform_count;
    cl_device_id devices[OCL_MAX_PLATFORMS][OCL_MAX_DEVICES];
    cl_uint device_count[OCL_MAX_PLATFORMS];
} ocl_inventory;

static bool ocl_list_devices(ocl_inventory *inv, csg_diag *d)
{
    cl_int err = clGetPlatformIDs(OCL_MAX_PLATFORMS, inv->platforms, &inv->platform_count);
    if (err == OCL_PLATFORM_NOT_FOUND_KHR || (err == CL_SUCCESS && inv->platform_count == 0)) {
        csg_error_plain(d, "OpenCL: no platform found (is an ICD such as pocl-opencl-icd "
                           "installed?)");
        return false;
    }
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clGetPlatformIDs", err);
    if (inv->platform_count > OCL_MAX_PLATFORMS)
        inv->platform_count = OCL_MAX_PLATFORMS;
    for (cl_uint p = 0; p < inv->platform_count; p++) {
        cl_uint n = 0;
        err = clGetDeviceIDs(inv->platforms[p], CL_DEVICE_TYPE_ALL, OCL_MAX_DEVICES,
                             inv->devices[p], &n);
        if (err == CL_DEVICE_NOT_FOUND)
            n = 0;
        else if (err != CL_SUCCESS)
            return ocl_fail(d, "clGetDeviceIDs", err);
        inv->device_count[p] = n > OCL_MAX_DEVICES ? OCL_MAX_DEVICES : n;
    }
    return true;
}

static void ocl_device_name(cl_device_id dev, char *buf, size_t size)
{
    if (clGetDeviceInfo(dev, CL_DEVICE_NAME, size, buf, NULL) != CL_SUCCESS)
        snprintf(buf, size, "(unnamed device)");
    buf[size - 1] = '\0';
}

/* Case-insensitive substring test. */
static bool ocl_contains(const char *hay, const char *needle)
{
    size_t n = strlen(needle);
    for (; *hay; hay++) {
        size_t i = 0;
        while (i < n && hay[i] &&
               tolower((unsigned char)hay[i]) == tolower((unsigned char)needle[i]))
            i++;
        if (i == n)
            return true;
    }
    return n == 0;
}

/* "P:D" with two decimal indices. */
static bool ocl_parse_index(const char *s, unsigned *p, unsigned *dv)
{
    char *end;
    if (!isdigit((unsigned char)s[0]))
        return false;
    errno = 0;
    unsigned long a = strtoul(s, &end, 10);
    if (errno || *end != ':' || !isdigit((unsigned char)end[1]))
        return false;
    unsigned long b = strtoul(end + 1, &end, 10);
    if (errno || *end != '\0' || a > UINT_MAX || b > UINT_MAX)
        return false;
    *p = (unsigned)a;
    *dv = (unsigned)b;
    return true;
}

/* "0:0 name, 0:1 name, ..." for error messages. */
static void ocl_describe_devices(const ocl_inventory *inv, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (cl_uint p = 0; p < inv->platform_count; p++)
        for (cl_uint i = 0; i < inv->device_count[p]; i++) {
            char name[128];
            ocl_device_name(inv->devices[p][i], name, sizeof name);
            int n = snprintf(buf + used, size - used, "%s%u:%u \"%s\"", used ? ", " : "",
                             (unsigned)p, (unsigned)i, name);
            if (n < 0 || (size_t)n >= size - used)
                return;
            used += (size_t)n;
        }
    if (used == 0)
        snprintf(buf, size, "none");
}

static bool ocl_pick_device(const char *sel, cl_device_id *out, csg_diag *d)
{
    ocl_inventory inv;
    if (!ocl_list_devices(&inv, d))
        return false;
    unsigned pi, di;
    if (sel && ocl_parse_index(sel, &pi, &di)) {
        if (pi < inv.platform_count && di < inv.device_count[pi]) {
            *out = inv.devices[pi][di];
            return true;
        }
    } else {
        for (cl_uint p = 0; p < inv.platform_count; p++)
            for (cl_uint i = 0; i < inv.device_count[p]; i++) {
                char name[256];
                ocl_device_name(inv.devices[p][i], name, sizeof name);
                if (!sel || ocl_contains(name, sel)) {
                    *out = inv.devices[p][i];
                    return true;
                }
            }
    }
    char list[700];
    ocl_describe_devices(&inv, list, sizeof list);
    if (sel)
        csg_error_plain(d, "OpenCL: no device matches \"%s\" (give \"P:D\" or part of a "
                           "name; devices: %s)", sel, list);
    else
        csg_error_plain(d, "OpenCL: no device found on any platform");
    return false;
}

/* ---- device properties ------------------------------------------------------ */

static bool ocl_has_extension(cl_device_id dev, const char *ext, csg_diag *d)
{
    size_t size = 0;
    cl_int err = clGetDeviceInfo(dev, CL_DEVICE_EXTENSIONS, 0, NULL, &size);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clGetDeviceInfo(CL_DEVICE_EXTENSIONS)", err);
    char *list = malloc(size + 1);
    if (!list) {
        csg_error_plain(d, "out of memory");
        return false;
    }
    err = clGetDeviceInfo(dev, CL_DEVICE_EXTENSIONS, size, list, NULL);
    if (err != CL_SUCCESS) {
        free(list);
        return ocl_fail(d, "clGetDeviceInfo(CL_DEVICE_EXTENSIONS)", err);
    }
    list[size] = '\0';
    bool found = false;
    size_t n = strlen(ext);
    for (char *tok = list; *tok;) {
        while (*tok == ' ')
            tok++;
        size_t len = strcspn(tok, " ");
        if (len == n && strncmp(tok, ext, n) == 0)
            found = true;
        tok += len;
    }
    free(list);
    return found;
}

/* The device can run the requested build exactly as the C side computes. */
static bool ocl_check_device(ocl_ctx *c, const char *name, csg_diag *d)
{
    cl_int err = clGetDeviceInfo(c->device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof c->max_alloc,
                                 &c->max_alloc, NULL);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clGetDeviceInfo(CL_DEVICE_MAX_MEM_ALLOC_SIZE)", err);
    /* tests: CSGTRACE_TEST_CL_MAX_ALLOC=N makes the device's buffers N
     * bytes at most, as on a GPU too small for the scene */
    long long cap = test_hook_number(TEST_CL_MAX_ALLOC, LLONG_MAX);
    if (cap > 0 && (cl_ulong)cap < c->max_alloc)
        c->max_alloc = (cl_ulong)cap;
    err = clGetDeviceInfo(c->device, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof c->global_mem,
                          &c->global_mem, NULL);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clGetDeviceInfo(CL_DEVICE_GLOBAL_MEM_SIZE)", err);
    err = clGetDeviceInfo(c->device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof c->compute_units,
                          &c->compute_units, NULL);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clGetDeviceInfo(CL_DEVICE_MAX_COMPUTE_UNITS)", err);
    cl_device_type type = 0;
    err = clGetDeviceInfo(c->device, CL_DEVICE_TYPE, sizeof type, &type, NULL);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clGetDeviceInfo(CL_DEVICE_TYPE)", err);
    c->cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
    cl_bool unified = CL_FALSE;
    cl_uint align_bits = 0;
    err = clGetDeviceInfo(c->device, CL_DEVICE_HOST_UNIFIED_MEMORY, sizeof unified, &unified,
                          NULL);
    if (err == CL_SUCCESS) /* (deprecated by OpenCL 2.0: an error is "no") */
        err = clGetDeviceInfo(c->device, CL_DEVICE_MEM_BASE_ADDR_ALIGN, sizeof align_bits,
                              &align_bits, NULL);
    c->unified = err == CL_SUCCESS && unified && align_bits >= 8;
    c->base_align = align_bits / 8;
    cl_device_fp_config fp = 0;
    err = clGetDeviceInfo(c->device, CL_DEVICE_SINGLE_FP_CONFIG, sizeof fp, &fp, NULL);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clGetDeviceInfo(CL_DEVICE_SINGLE_FP_CONFIG)", err);
    if (!c->use_double && !(fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT)) {
        csg_error_plain(d, "OpenCL: device \"%s\" has no correctly rounded float divide and "
                           "sqrt, so its records could not match the C side; use "
                           "--precision double or another device", name);
        return false;
    }
    if (c->use_double) {
        csg_diag probe = {0};
        bool fp64 = ocl_has_extension(c->device, "cl_khr_fp64", &probe);
        if (probe.failed) {
            *d = probe;
            return false;
        }
        if (!fp64) {
            csg_error_plain(d, "OpenCL: device \"%s\" does not support double precision "
                               "(no cl_khr_fp64); use --precision float or another device",
                            name);
            return false;
        }
    }
    return true;
}

/* ---- kernel variant ----------------------------------------------------------- */

bool ocl_kernel_parse(const char *name, enum ocl_kernel *out)
{
    static const char *const names[] = {"auto", "scalar", "packet"};
    for (int i = 0; i < 3; i++)
        if (name && strcmp(name, names[i]) == 0) {
            *out = (enum ocl_kernel)i;
            return true;
        }
    return false;
}

/* AUTO becomes $CSGTRACE_CL_KERNEL when set, else packet on a CPU device
 * (PoCL turns OpenCL vectors into SIMD code, not a one-ray walk), scalar
 * on any other.  A packet is $CSGTRACE_CL_PACKET rays when set (2, 4, 8 or
 * 16: tests, or a device whose preferred width misleads), else twice the
 * device's preferred vector width of `real` (rounded down to 4, 8 or 16;
 * at least 4, at most 16), a block of 4 records by W / 4 rows (2 by W / 2
 * for W < 8).  Twice: a packet of two registers a value gives each step
 * two independent chains and halves the walk's scalar work a ray (on
 * AVX2, float16 over float8: 1.08-1.20x the rays per CPU-second, double8
 * over double4 1.14-1.26x, bench/SPEED.md; untried on AVX-512, where
 * only the double build changes, double8 -> double16). */
static bool ocl_pick_kernel(ocl_ctx *c, enum ocl_kernel want, int packet, csg_diag *d)
{
    if (want == OCL_KERNEL_AUTO)
        want = c->cpu ? OCL_KERNEL_PACKET : OCL_KERNEL_SCALAR;
    c->kernel = want;
    if (want != OCL_KERNEL_PACKET)
        return true;
    cl_uint width = 0;
    cl_device_info what = c->use_double ? CL_DEVICE_PREFERRED_VECTOR_WIDTH_DOUBLE
                                        : CL_DEVICE_PREFERRED_VECTOR_WIDTH_FLOAT;
    cl_int err = clGetDeviceInfo(c->device, what, sizeof width, &width, NULL);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clGetDeviceInfo(CL_DEVICE_PREFERRED_VECTOR_WIDTH)", err);
    c->packet = 4;
    while (c->packet < 16 && (cl_uint)c->packet <= width)
        c->packet *= 2;
    if (packet != 0) {
        if (packet != 2 && packet != 4 && packet != 8 && packet != 16) {
            csg_error_plain(d, "the packet kernel's width must be 2, 4, 8 or 16, not %d", packet);
            return false;
        }
        c->packet = packet;
    }
    c->packet_cols = c->packet >= 8 ? 4 : 2;
    return true;
}

/* "scalar" or "packet 16 (4x4)". */
static void ocl_kernel_name(const ocl_ctx *c, char *buf, size_t size)
{
    if (c->kernel == OCL_KERNEL_PACKET)
        snprintf(buf, size, "packet %d (%dx%d)", c->packet, c->packet_cols,
                 c->packet / c->packet_cols);
    else
        snprintf(buf, size, "scalar");
}

/* ---- program ------------------------------------------------------------------ */

static void ocl_print_build_log(cl_program prog, cl_device_id dev, const char *name)
{
    size_t size = 0;
    if (clGetProgramBuildInfo(prog, dev, CL_PROGRAM_BUILD_LOG, 0, NULL, &size) != CL_SUCCESS)
        return;
    char *log = malloc(size + 1);
    if (!log)
        return;
    if (clGetProgramBuildInfo(prog, dev, CL_PROGRAM_BUILD_LOG, size, log, NULL) == CL_SUCCESS) {
        log[size] = '\0';
        fprintf(stderr, "csgtrace: OpenCL build log of simd_kernels/primary.cl on \"%s\":\n%s\n",
                name, log);
    }
    free(log);
}

/* Work-groups of OCL_GROUP_WIDTH x 1 work-items, or what the kernel allows. */
#define OCL_GROUP_WIDTH 64
static cl_int ocl_group_width(cl_kernel k, cl_device_id dev, size_t *out)
{
    size_t max = 0;
    cl_int err = clGetKernelWorkGroupInfo(k, dev, CL_KERNEL_WORK_GROUP_SIZE, sizeof max, &max,
                                          NULL);
    *out = max < OCL_GROUP_WIDTH ? (max ? max : 1) : OCL_GROUP_WIDTH;
    return err;
}

static void ocl_release_program(ocl_ctx *c)
{
    cl_kernel *ks[] = {&c->k_primary, &c->k_tiles, &c->k_layout, &c->k_shadows};
    for (size_t i = 0; i < sizeof ks / sizeof ks[0]; i++) {
        if (*ks[i])
            clReleaseKernel(*ks[i]);
        *ks[i] = NULL;
    }
    if (c->program)
        clReleaseProgram(c->program);
    c->program = NULL;
}

/* The device, its driver and OpenCL version: what a cached binary was
 * compiled for (cl_cache.h). */
static bool ocl_device_identity(cl_device_id dev, char *out, size_t size)
{
    const cl_device_info what[] = {CL_DEVICE_NAME, CL_DRIVER_VERSION, CL_DEVICE_VERSION};
    size_t at = 0;
    for (size_t i = 0; i < sizeof what / sizeof what[0]; i++) {
        size_t got = 0;
        if (at + 1 >= size ||
            clGetDeviceInfo(dev, what[i], size - at - 1, out + at, &got) != CL_SUCCESS || !got)
            return false;
        at += got; /* (got counts the NUL, which becomes the separator) */
        out[at - 1] = '\n';
    }
    out[at] = '\0';
    return true;
}

/* The program from the binary cached under `key`, built with `options`;
 * false (nothing kept) when there is none or OpenCL refuses it. */
static bool ocl_build_cached(ocl_ctx *c, const cl_cache_key_t *key, const char *options)
{
    size_t size = 0;
    unsigned char *bin = cl_cache_load(c->cache_dir, key, &size);
    if (!bin)
        return false;
    cl_int err, status = CL_SUCCESS;
    const unsigned char *bins[1] = {bin};
    cl_program prog = clCreateProgramWithBinary(c->context, 1, &c->device, &size, bins, &status,
                                                &err);
    free(bin);
    if (err == CL_SUCCESS && status == CL_SUCCESS &&
        clBuildProgram(prog, 1, &c->device, options, NULL, NULL) == CL_SUCCESS) {
        c->program = prog;
        return true;
    }
    if (prog)
        clReleaseProgram(prog);
    return false;
}

/* c->program's binary into the cache under `key` (best effort). */
static void ocl_cache_program(const ocl_ctx *c, const cl_cache_key_t *key)
{
    size_t size = 0;
    if (clGetProgramInfo(c->program, CL_PROGRAM_BINARY_SIZES, sizeof size, &size, NULL) !=
            CL_SUCCESS ||
        size == 0)
        return;
    unsigned char *bin = malloc(size);
    unsigned char *bins[1] = {bin};
    if (bin && clGetProgramInfo(c->program, CL_PROGRAM_BINARIES, sizeof bins, bins, NULL) ==
                   CL_SUCCESS)
        cl_cache_store(c->cache_dir, key, bin, size);
    free(bin);
}

/* The program from its source, built with `options`. */
static bool ocl_build_source(ocl_ctx *c, const char *name, const char *options, csg_diag *d)
{
    cl_int err;
    const char *srcs[1] = {c->source};
    c->program = clCreateProgramWithSource(c->context, 1, srcs, NULL, &err);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clCreateProgramWithSource", err);
    err = clBuildProgram(c->program, 1, &c->device, options, NULL, NULL);
    if (err != CL_SUCCESS) {
        ocl_print_build_log(c->program, c->device, name);
        csg_error_plain(d, "OpenCL: building the primary kernel (%s) failed: %s (%d); the build "
                        "log is above", options, ocl_error_name(err), (int)err);
        return false;
    }
    return true;
}

/* The kernels of the built program and their work-group widths. */
static bool ocl_create_kernels(ocl_ctx *c, csg_diag *d)
{
    struct {
        cl_kernel *k;
        const char *name;
    } kernels[] = {{&c->k_primary, "csg_primary"},
                   {&c->k_tiles, "csg_tile_hits"},
                   {&c->k_layout, "csg_layout"},
                   {&c->k_shadows, "csg_shadows"}};
    cl_int err;
    for (size_t i = 0; i < sizeof kernels / sizeof kernels[0]; i++) {
        *kernels[i].k = clCreateKernel(c->program, kernels[i].name, &err);
        if (err != CL_SUCCESS) {
            csg_error_plain(d, "OpenCL: clCreateKernel(%s) failed: %s (%d)", kernels[i].name,
                            ocl_error_name(err), (int)err);
            return false;
        }
    }
    err = ocl_group_width(c->k_primary, c->device, &c->group_primary);
    if (err == CL_SUCCESS)
        err = ocl_group_width(c->k_tiles, c->device, &c->group_tiles);
    if (err == CL_SUCCESS)
        err = ocl_group_width(c->k_shadows, c->device, &c->group_shadows);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clGetKernelWorkGroupInfo(CL_KERNEL_WORK_GROUP_SIZE)", err);
    return true;
}

/* Builds the program for c->features (the -D options of spec.h; none
 * for the general program): from the cached binary of the same sources,
 * options and device when there is one (cl_cache.h), else from source
 * (and then cached). */
static bool ocl_build(ocl_ctx *c, const char *name, csg_diag *d)
{
    char options[520];
    char variant[64] = "", spec[256];
    if (c->kernel == OCL_KERNEL_PACKET)
        snprintf(variant, sizeof variant, " -DCSG_PACKET=%d -DCSG_PACKET_COLS=%d", c->packet,
                 c->packet_cols);
    if (!csg_features_cl_options(c->features, spec, sizeof spec)) {
        csg_error_plain(d, "OpenCL: the feature options do not fit");
        return false;
    }
    snprintf(options, sizeof options, "-cl-std=CL1.2 -cl-fp32-correctly-rounded-divide-sqrt%s%s%s",
             c->use_double ? " -DCSG_DOUBLE" : "", variant, spec);
    char identity[1024], why[PATH_MAX + 96];
    if (c->cache_dir && !cl_cache_usable(c->cache_dir, why, sizeof why)) {
        if (why[0]) /* (once a context: it is not tried again) */
            fprintf(stderr, "csgtrace: warning: the OpenCL program cache is not used: %s\n",
                    why);
        c->cache_dir = NULL;
    }
    bool cacheable = c->cache_dir && ocl_device_identity(c->device, identity, sizeof identity);
    cl_cache_key_t key = {{0}};
    if (cacheable)
        key = cl_cache_key(c->source, options, identity);
    if (!(cacheable && ocl_build_cached(c, &key, options))) {
        if (!ocl_build_source(c, name, options, d))
            return false;
        if (cacheable)
            ocl_cache_program(c, &key);
    }
    return ocl_create_kernels(c, d);
}

/* ---- kernel arguments ----------------------------------------------------------- */

static bool ocl_arg(cl_kernel k, const char *kname, cl_uint i, size_t size, const void *v,
                    csg_diag *d)
{
    cl_int err = clSetKernelArg(k, i, size, v);
    if (err == CL_SUCCESS)
        return true;
    csg_error_plain(d, "OpenCL: clSetKernelArg(%s, %u) failed: %s (%d)", kname, (unsigned)i,
                    ocl_error_name(err), (int)err);
    return false;
}

/* ---- the primary pass ----------------------------------------------------------------- */

/* The blob is the flattener's, but the device trusts every index in it:
 * the same validation a worker applies (csg/blob.c), after a precision
 * check that names the mismatch. */
static bool ocl_check_blob(const ocl_ctx *c, const csg_blob_header *h, int tile, csg_diag *d)
{
    uint32_t rs = c->use_double ? 8 : 4;
    if (h->magic == CSG_BLOB_MAGIC && h->real_size != rs && (h->real_size == 4 || h->real_size == 8)) {
        csg_error_plain(d, "OpenCL primary pass: the scene is in %s but the program was built "
                           "for %s", h->real_size == 8 ? "double" : "float",
                        c->use_double ? "double" : "float");
        return false;
    }
    if (tile <= 0 || !csg_blob_valid(h, (size_t)h->total_size)) {
        csg_error_plain(d, "OpenCL primary pass: not a valid scene blob, or tile %d", tile);
        return false;
    }
    if (h->total_size > c->max_alloc) { /* (one buffer: the kernel reads it whole) */
        char name[256];
        ocl_device_name(c->device, name, sizeof name);
        csg_error_plain(d, "OpenCL: the flattened scene, %llu bytes, is larger than device "
                           "\"%s\"'s largest buffer, %llu bytes (CL_DEVICE_MAX_MEM_ALLOC_SIZE)",
                        (unsigned long long)h->total_size, name,
                        (unsigned long long)c->max_alloc);
        return false;
    }
    return true;
}

/* Rows of one slice: as many as the device, the options and `want` (> 0)
 * allow (at least c->slice_records' worth, memory allowing: none asked on
 * a CPU by default, OCL_DEVICE_SLICE_RECORDS on any other device), a whole
 * number of tile rows when at least one fits, and at least one row. */
static int ocl_slice_rows(const ocl_ctx *c, const csg_blob_header *h, int tile, int want)
{
    uint64_t w = (uint64_t)h->width * (uint64_t)h->spp, rs = h->real_size; /* records a row */
    uint64_t row_bytes = w * (rs + 4);
    uint64_t rows = c->max_alloc / (w * rs); /* the t buffer is the larger one */
    uint64_t share = c->global_mem / 2;
    share = share > h->total_size ? share - h->total_size : 0;
    if (share / row_bytes < rows)
        rows = share / row_bytes;
    uint64_t cap = c->max_slice_bytes ? (uint64_t)c->max_slice_bytes : OCL_DEFAULT_SLICE_BYTES;
    if (cap / row_bytes < rows)
        rows = cap / row_bytes;
    uint64_t least = (c->slice_records + w - 1) / w; /* rows, whole tile rows */
    least = (least + (uint64_t)tile - 1) / (uint64_t)tile * (uint64_t)tile;
    if (want > 0 && (uint64_t)want < rows)
        rows = (uint64_t)want > least ? (uint64_t)want : (least < rows ? least : rows);
    if (rows >= (uint64_t)tile)
        rows -= rows % (uint64_t)tile;
    if (rows < 1)
        rows = 1;
    if (rows > (uint64_t)h->height)
        rows = (uint64_t)h->height;
    return (int)rows;
}

/* A slice's record arrays, in the order of csg_shadows' arguments 3..6:
 * t (a real a record), surf, and the shadow answers known and lit (a word
 * each; absent without them). */
enum { OCL_REC_T, OCL_REC_SURF, OCL_REC_KNOWN, OCL_REC_LIT, OCL_RECS };

typedef struct {
    cl_mem m[OCL_RECS]; /* (known, lit: NULL when no answers are asked) */
} ocl_records;

typedef struct {
    cl_mem blob, hits, cells;
    ocl_records rec; /* a slice's records on the device (copied out), or, in
                        place, the caller's whole arrays (USE_HOST_PTR) */
} ocl_pass_buffers;

static void ocl_release_records(ocl_records *r)
{
    for (int i = 0; i < OCL_RECS; i++)
        if (r->m[i])
            clReleaseMemObject(r->m[i]);
}

static void ocl_release_buffers(ocl_pass_buffers *b)
{
    cl_mem *all[] = {&b->blob, &b->hits, &b->cells};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (*all[i])
            clReleaseMemObject(*all[i]);
    ocl_release_records(&b->rec);
}

static bool ocl_create_buffer(ocl_ctx *c, cl_mem_flags flags, size_t size, void *host,
                              cl_mem *out, const char *what, csg_diag *d)
{
    cl_int err;
    *out = clCreateBuffer(c->context, flags, size, host, &err);
    if (err == CL_SUCCESS)
        return true;
    csg_error_plain(d, "OpenCL: clCreateBuffer(%s, %zu bytes) failed: %s (%d)", what, size,
                    ocl_error_name(err), (int)err);
    return false;
}

/* A buffer the kernels only read, over host memory that stays as it is
 * while they may (the scene, records given back): used in place on a
 * device that works in host memory, nothing copied; copied in elsewhere. */
static bool ocl_input_buffer(ocl_ctx *c, size_t size, const void *host, cl_mem *out,
                             const char *what, csg_diag *d)
{
    cl_mem_flags how = c->unified && !c->copy_buffers ? CL_MEM_USE_HOST_PTR : CL_MEM_COPY_HOST_PTR;
    return ocl_create_buffer(c, CL_MEM_READ_ONLY | how, size, (void *)host, out, what, d);
}

/* ---- the packet kernel's culling cells ----------------------------------------------
 * The packet kernel culls as the C worker does (workers/frustum.h): the
 * image in square cells of `edge` pixels, each with the bounded roots the
 * primary rays of its pixels may meet (engine->rect_candidates, nearest
 * box first), stored as its count (-1: no list, walk the BVH) then `cap`
 * slots; a packet inside one cell tries its cell's roots instead of
 * walking the BVH (primary.cl: pk_cell_list).  The cell rows are computed
 * on the host as the slices that need them are enqueued, and written to
 * the device ahead of those slices on the in-order queue.  Edge 0: no
 * cells (the one-ray kernel walks the BVH).  The host's cost is one BVH
 * walk a block of OCL_CELL_BLOCK x OCL_CELL_BLOCK cells, then a box test
 * a cell and block candidate.  Edges 8, 16, 32 with caps 16, 32, 64 were
 * measured within the noise of this shared machine at N = 10 .. 10^4
 * random spheres (bench/results/primary_pass); 16 and 32 sit in the
 * middle. */
#define OCL_CELL_EDGE 16
#define OCL_CELL_CAP 32
#define OCL_CELL_BLOCK 4 /* cells a block's side: one BVH walk a block */
#define OCL_CELL_MAX_BYTES ((size_t)32 << 20) /* larger images: larger cells */

typedef struct {
    cl_int edge, cap;
    int cols, rows, rows_done; /* the grid; rows computed and enqueued */
    int32_t *host;             /* cols * rows * (1 + cap) entries      */
} ocl_cells;

static size_t ocl_cell_ints(const ocl_cells *cl) { return (size_t)(1 + cl->cap); }

/* The grid of an image of width x height for the kernel variant kind
 * (host array only; false: out of memory). */
static bool ocl_cells_alloc(ocl_cells *cl, enum ocl_kernel kind, int width, int height)
{
    memset(cl, 0, sizeof *cl);
    if (kind != OCL_KERNEL_PACKET)
        return (cl->host = calloc(1, sizeof *cl->host)) != NULL; /* (a buffer to bind) */
    cl->cap = OCL_CELL_CAP;
    for (cl->edge = OCL_CELL_EDGE;; cl->edge *= 2) {
        cl->cols = (width + cl->edge - 1) / cl->edge;
        cl->rows = (height + cl->edge - 1) / cl->edge;
        if ((size_t)cl->cols * (size_t)cl->rows * ocl_cell_ints(cl) * sizeof(int32_t) <=
            OCL_CELL_MAX_BYTES)
            break;
    }
    cl->host = malloc((size_t)cl->cols * (size_t)cl->rows * ocl_cell_ints(cl) * sizeof(int32_t));
    return cl->host != NULL;
}

static size_t ocl_cells_bytes(const ocl_cells *cl)
{
    return cl->edge ? (size_t)cl->cols * (size_t)cl->rows * ocl_cell_ints(cl) * sizeof(int32_t)
                    : sizeof(int32_t);
}

/* The pixels of cell (cx, cy) .. (cx + n - 1, cy + n - 1), inside the image. */
static tile_rect ocl_cells_rect(const ocl_cells *cl, const csg_blob_header *h, int cx, int cy,
                                int n)
{
    int x = cx * cl->edge, y = cy * cl->edge, e = n * cl->edge;
    tile_rect r = {x, y, h->width - x < e ? h->width - x : e, h->height - y < e ? h->height - y : e};
    return r;
}

/* The cells of block (bx, by), OCL_CELL_BLOCK cells square: the block's
 * candidates found once by a walk of the BVH, then each cell's among them
 * (a cell's pyramid lies in its block's), or each cell's own walk when
 * the block has too many. */
static void ocl_cells_block(ocl_cells *cl, const csg_blob_header *h, const void *blob,
                            const engine *e, int bx, int by)
{
    int32_t block[ENGINE_CANDIDATES_MAX];
    int cx0 = bx * OCL_CELL_BLOCK, cy0 = by * OCL_CELL_BLOCK;
    int32_t nb = e->rect_candidates(blob, ocl_cells_rect(cl, h, cx0, cy0, OCL_CELL_BLOCK), NULL,
                                    0, block, ENGINE_CANDIDATES_MAX);
    for (int cy = cy0; cy < cy0 + OCL_CELL_BLOCK && cy < cl->rows; cy++)
        for (int cx = cx0; cx < cx0 + OCL_CELL_BLOCK && cx < cl->cols; cx++) {
            int32_t *entry = cl->host + ((size_t)cy * (size_t)cl->cols + (size_t)cx) *
                                            ocl_cell_ints(cl);
            tile_rect r = ocl_cells_rect(cl, h, cx, cy, 1);
            entry[0] = e->rect_candidates(blob, r, nb >= 0 ? block : NULL, nb, entry + 1,
                                          cl->cap);
        }
}

/* The cells of image rows up to y_last computed (whole blocks) and written
 * to the device (non-blocking: cl->host lives until the pass ends). */
static bool ocl_cells_upto(ocl_ctx *c, ocl_cells *cl, cl_mem buf, const void *blob,
                           int y_last, csg_diag *d)
{
    if (!cl->edge)
        return true;
    const csg_blob_header *h = csg_blob_hdr(blob);
    int first = cl->rows_done, by_last = y_last / cl->edge / OCL_CELL_BLOCK;
    if (by_last * OCL_CELL_BLOCK < first)
        return true;
    const engine *e = engine_for_blob(blob);
    for (int by = first / OCL_CELL_BLOCK; by <= by_last; by++)
        for (int bx = 0; bx * OCL_CELL_BLOCK < cl->cols; bx++)
            ocl_cells_block(cl, h, blob, e, bx, by);
    int last = (by_last + 1) * OCL_CELL_BLOCK;
    cl->rows_done = last < cl->rows ? last : cl->rows;
    size_t row_ints = (size_t)cl->cols * ocl_cell_ints(cl);
    size_t off = (size_t)first * row_ints, n = (size_t)(cl->rows_done - first) * row_ints;
    cl_int err = clEnqueueWriteBuffer(c->queue, buf, CL_FALSE, off * sizeof(int32_t),
                                      n * sizeof(int32_t), cl->host + off, 0, NULL, NULL);
    return err == CL_SUCCESS || ocl_fail(d, "clEnqueueWriteBuffer(cells)", err);
}

/* The NDRange of csg_shadows over `rows` rows of record_width records: a
 * work-item a record, or a packet (the packet program: csg_primary's
 * grid), padded to whole work-groups of c->group_shadows. */
static void ocl_shadow_grid(const ocl_ctx *c, cl_int record_width, cl_int rows, size_t grid[2])
{
    size_t x = (size_t)record_width, y = (size_t)rows, g = c->group_shadows;
    if (c->kernel == OCL_KERNEL_PACKET) {
        size_t pc = (size_t)c->packet_cols, pr = (size_t)(c->packet / c->packet_cols);
        x = (x + pc - 1) / pc;
        y = (y + pr - 1) / pr;
    }
    grid[0] = (x + g - 1) / g * g;
    grid[1] = y;
}

/* The shadow answers of a slice's records (csg_shadows after csg_primary on
 * the in-order queue) into rec's known and lit. */
static bool ocl_run_shadows(ocl_ctx *c, cl_mem blob, const ocl_records *rec, cl_int y0,
                            cl_int rows, cl_int record_width, cl_event *done, csg_diag *d)
{
    const char *k = "csg_shadows";
    bool ok = ocl_arg(c->k_shadows, k, 0, sizeof(cl_mem), &blob, d) &&
              ocl_arg(c->k_shadows, k, 1, sizeof(cl_int), &y0, d) &&
              ocl_arg(c->k_shadows, k, 2, sizeof(cl_int), &rows, d);
    for (int i = 0; ok && i < OCL_RECS; i++)
        ok = ocl_arg(c->k_shadows, k, (cl_uint)(3 + i), sizeof(cl_mem), &rec->m[i], d);
    if (!ok)
        return false;
    size_t grid[2];
    ocl_shadow_grid(c, record_width, rows, grid);
    size_t local[2] = {c->group_shadows, 1};
    cl_int err = clEnqueueNDRangeKernel(c->queue, c->k_shadows, 2, NULL, grid, local, 0, NULL,
                                        done);
    return err == CL_SUCCESS || ocl_fail(d, "clEnqueueNDRangeKernel(csg_shadows)", err);
}

/* One slice's kernels: rows y0 .. y0 + rows - 1 traced into rec (their
 * shadow answers too when rec has them), its tile counts into b->hits;
 * marks (NULL: none) gets the events of the first and the last. */
static bool ocl_run_slice(ocl_ctx *c, const csg_blob_header *h, int tile, int y0, int rows,
                          ocl_pass_buffers *b, const ocl_records *rec, const ocl_cells *cells,
                          cl_event marks[2], csg_diag *d)
{
    cl_int cy0 = y0, crows = rows, ctile = tile, record_width = h->width * h->spp;
    cl_int tiles_x = (h->width + tile - 1) / tile;
    int ty0 = y0 / tile;
    cl_int tile_rows = (y0 + rows - 1) / tile - ty0 + 1; /* tile rows the slice touches */
    const char *kp = "csg_primary", *kt = "csg_tile_hits";
    bool ok = ocl_arg(c->k_primary, kp, 0, sizeof(cl_mem), &b->blob, d) &&
              ocl_arg(c->k_primary, kp, 1, sizeof(cl_int), &cy0, d) &&
              ocl_arg(c->k_primary, kp, 2, sizeof(cl_int), &crows, d) &&
              ocl_arg(c->k_primary, kp, 3, sizeof(cl_mem), &rec->m[OCL_REC_T], d) &&
              ocl_arg(c->k_primary, kp, 4, sizeof(cl_mem), &rec->m[OCL_REC_SURF], d) &&
              ocl_arg(c->k_primary, kp, 5, sizeof(cl_mem), &b->cells, d) &&
              ocl_arg(c->k_primary, kp, 6, sizeof(cl_int), &cells->edge, d) &&
              ocl_arg(c->k_primary, kp, 7, sizeof(cl_int), &cells->cap, d) &&
              ocl_arg(c->k_tiles, kt, 0, sizeof(cl_mem), &b->blob, d) &&
              ocl_arg(c->k_tiles, kt, 1, sizeof(cl_mem), &rec->m[OCL_REC_SURF], d) &&
              ocl_arg(c->k_tiles, kt, 2, sizeof(cl_int), &cy0, d) &&
              ocl_arg(c->k_tiles, kt, 3, sizeof(cl_int), &crows, d) &&
              ocl_arg(c->k_tiles, kt, 4, sizeof(cl_int), &ctile, d) &&
              ocl_arg(c->k_tiles, kt, 5, sizeof(cl_mem), &b->hits, d);
    if (!ok)
        return false;
    size_t gp = c->group_primary, gt = c->group_tiles;
    size_t items_x = (size_t)record_width, items_y = (size_t)rows; /* a work-item a record */
    if (c->kernel == OCL_KERNEL_PACKET) { /* a work-item a packet */
        size_t pc = (size_t)c->packet_cols, pr = (size_t)(c->packet / c->packet_cols);
        items_x = (items_x + pc - 1) / pc;
        items_y = (items_y + pr - 1) / pr;
    }
    size_t pix[2] = {(items_x + gp - 1) / gp * gp, items_y};
    size_t pix_group[2] = {gp, 1};
    size_t tiles[2] = {((size_t)tiles_x + gt - 1) / gt * gt, (size_t)tile_rows};
    size_t tiles_group[2] = {gt, 1};
    bool shadows = rec->m[OCL_REC_KNOWN] != NULL;
    cl_int err = clEnqueueNDRangeKernel(c->queue, c->k_primary, 2, NULL, pix, pix_group, 0, NULL,
                                        marks ? &marks[0] : NULL);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clEnqueueNDRangeKernel(csg_primary)", err);
    err = clEnqueueNDRangeKernel(c->queue, c->k_tiles, 2, NULL, tiles, tiles_group, 0, NULL,
                                 marks && !shadows ? &marks[1] : NULL);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clEnqueueNDRangeKernel(csg_tile_hits)", err);
    return !shadows ||
           ocl_run_shadows(c, b->blob, rec, cy0, crows, record_width, marks ? &marks[1] : NULL, d);
}

/* ---- the pass, in the background ------------------------------------------------ */

/* In place, a slice's regions of the caller's arrays: the sub-buffers its
 * kernels write, and the mappings through which the caller reads them
 * (kept until the pass ends). */
typedef struct {
    ocl_records sub;
    void *mapped[OCL_RECS];
} ocl_slice_mem;

static size_t ocl_rec_size(const csg_blob_header *h, int i)
{
    return i == OCL_REC_T ? (size_t)h->real_size : sizeof(uint32_t);
}

struct ocl_pass {
    ocl_ctx *c;
    const csg_blob_header *h;
    const void *blob;         /* the scene (h is its header)              */
    int tile, rows, slices;   /* rows a slice (the last may be shorter)   */
    int enqueued, done;       /* slices enqueued; complete and counted    */
    int needed;               /* slices the caller needs (ocl_pass_limit)  */
    void *out[OCL_RECS];      /* the caller's arrays the slices fill (the
                                 shadow answers' NULL: none asked)        */
    bool in_place;            /* the kernels write them (ocl_pass_in_place) */
    size_t tiles_x, stride;   /* counts a slice may hold                  */
    ocl_pass_buffers b;
    ocl_slice_mem *mem;       /* in place: each slice's regions           */
    ocl_cells cells;          /* the packet kernel's culling cells        */
    uint32_t *host_hits;      /* slice k's counts at k * stride           */
    uint32_t *tile_hits;      /* the caller's                             */
    cl_event *events;         /* the last read of each slice              */
    cl_event (*marks)[2];     /* each slice's first and last kernel (a
                                 queue that times its commands; else NULL) */
    void (*notify)(void *);
    void *notify_arg;
    atomic_int callbacks;     /* registered and not yet run               */
    double t0, t_end;         /* begin; the last slice seen complete      */
};

static void CL_CALLBACK ocl_slice_done(cl_event e, cl_int status, void *arg)
{
    (void)e;
    (void)status;
    ocl_pass *p = arg;
    if (p->notify)
        p->notify(p->notify_arg);
    atomic_fetch_sub(&p->callbacks, 1);
}

/* Whether the kernels can write the records straight into the caller's
 * arrays, nothing copied: a device that works in host memory (a CPU, an
 * integrated GPU; not told to copy), every array and every slice's start
 * aligned as a sub-buffer must be, and each array within the device's
 * largest buffer.  (A discrete GPU keeps device buffers and copies out:
 * a host array there would be read across the bus at every access.) */
static bool ocl_pass_in_place(const ocl_pass *p)
{
    const ocl_ctx *c = p->c;
    if (!c->unified || c->copy_buffers)
        return false;
    size_t row = (size_t)p->h->width * (size_t)p->h->spp;
    for (int i = 0; i < OCL_RECS; i++) {
        size_t size = ocl_rec_size(p->h, i);
        if (p->out[i] && ((uintptr_t)p->out[i] % c->base_align != 0 ||
                          row * (size_t)p->rows * size % c->base_align != 0 ||
                          row * (size_t)p->h->height * size > c->max_alloc))
            return false;
    }
    return true;
}

/* The record buffers: a slice's on the device, or, in place, one over
 * each of the caller's whole arrays. */
static bool ocl_pass_records(ocl_pass *p, csg_diag *d)
{
    static const char *const names[OCL_RECS] = {"t", "surf", "known", "lit"};
    const csg_blob_header *h = p->h;
    size_t n = (size_t)h->width * (size_t)h->spp * (size_t)(p->in_place ? h->height : p->rows);
    cl_mem_flags flags = CL_MEM_READ_WRITE | (p->in_place ? CL_MEM_USE_HOST_PTR : 0);
    for (int i = 0; i < OCL_RECS; i++)
        if (p->out[i] && !ocl_create_buffer(p->c, flags, n * ocl_rec_size(h, i),
                                            p->in_place ? p->out[i] : NULL, &p->b.rec.m[i],
                                            names[i], d))
            return false;
    return true;
}

/* The buffers, the per-slice arrays and the slicing of a new pass. */
static bool ocl_pass_alloc(ocl_pass *p, const void *blob, int want, csg_diag *d)
{
    ocl_ctx *c = p->c;
    const csg_blob_header *h = p->h;
    int tile = p->tile;
    p->tiles_x = (size_t)((h->width + tile - 1) / tile);
    size_t tiles_y = (size_t)((h->height + tile - 1) / tile);
    p->rows = ocl_slice_rows(c, h, tile, want);
    p->slices = (h->height + p->rows - 1) / p->rows;
    p->needed = p->slices;
    p->in_place = ocl_pass_in_place(p);
    size_t tile_rows = (size_t)(p->rows + tile - 1) / (size_t)tile + 1; /* touched by a slice */
    if (tile_rows > tiles_y)
        tile_rows = tiles_y;
    p->stride = p->tiles_x * tile_rows;
    p->host_hits = malloc((size_t)p->slices * p->stride * sizeof(uint32_t));
    p->events = calloc((size_t)p->slices, sizeof *p->events);
    p->mem = p->in_place ? calloc((size_t)p->slices, sizeof *p->mem) : NULL;
    p->marks = c->profiling ? calloc((size_t)p->slices, sizeof *p->marks) : NULL;
    if (!p->host_hits || !p->events || (p->in_place && !p->mem) || (c->profiling && !p->marks) ||
        !ocl_cells_alloc(&p->cells, c->kernel, h->width, h->height)) {
        csg_error_plain(d, "out of memory");
        return false;
    }
    return ocl_input_buffer(c, (size_t)h->total_size, blob, &p->b.blob, "scene", d) &&
           ocl_pass_records(p, d) &&
           ocl_create_buffer(c, CL_MEM_WRITE_ONLY, p->stride * sizeof(uint32_t), NULL, &p->b.hits,
                             "tile hits", d) &&
           ocl_create_buffer(c, CL_MEM_READ_ONLY, ocl_cells_bytes(&p->cells), NULL, &p->b.cells,
                             "cells", d);
}

/* Where slice k (records first .. first + n - 1) writes: the pass's
 * device buffers, or, in place, its own regions of the caller's arrays. */
static bool ocl_slice_records(ocl_pass *p, int k, size_t first, size_t n, ocl_records *rec,
                              csg_diag *d)
{
    if (!p->in_place) {
        *rec = p->b.rec;
        return true;
    }
    ocl_slice_mem *m = &p->mem[k];
    for (int i = 0; i < OCL_RECS; i++) {
        if (!p->b.rec.m[i])
            continue;
        size_t size = ocl_rec_size(p->h, i);
        cl_buffer_region region = {first * size, n * size};
        cl_int err;
        m->sub.m[i] = clCreateSubBuffer(p->b.rec.m[i], CL_MEM_READ_WRITE,
                                        CL_BUFFER_CREATE_TYPE_REGION, &region, &err);
        if (err != CL_SUCCESS)
            return ocl_fail(d, "clCreateSubBuffer(records)", err);
    }
    *rec = m->sub;
    return true;
}

/* Slice k's records where the caller reads them, after its kernels on the
 * in-order queue: read out of the device buffers, or, in place, mapped
 * (a buffer over host memory maps at that memory: OpenCL's rule for
 * CL_MEM_USE_HOST_PTR, so the device's writes are all the caller needs). */
static bool ocl_slice_download(ocl_pass *p, int k, size_t first, size_t n, csg_diag *d)
{
    for (int i = 0; i < OCL_RECS; i++) {
        if (!p->b.rec.m[i])
            continue;
        size_t size = ocl_rec_size(p->h, i);
        char *dst = (char *)p->out[i] + first * size;
        cl_int err;
        if (!p->in_place) {
            err = clEnqueueReadBuffer(p->c->queue, p->b.rec.m[i], CL_FALSE, 0, n * size, dst, 0,
                                      NULL, NULL);
            if (err != CL_SUCCESS)
                return ocl_fail(d, "clEnqueueReadBuffer(records)", err);
            continue;
        }
        void *at = clEnqueueMapBuffer(p->c->queue, p->b.rec.m[i], CL_FALSE, CL_MAP_READ,
                                      first * size, n * size, 0, NULL, NULL, &err);
        if (err != CL_SUCCESS)
            return ocl_fail(d, "clEnqueueMapBuffer(records)", err);
        p->mem[k].mapped[i] = at;
        if (at != dst) {
            csg_error_plain(d, "OpenCL: the device mapped its records away from the host "
                               "memory they were created over (CL_MEM_USE_HOST_PTR)");
            return false;
        }
    }
    return true;
}

/* Slice k on the queue (its kernels, its records to the caller, its tile
 * counts) with its completion callback on the last. */
static bool ocl_pass_enqueue_slice(ocl_pass *p, int k, csg_diag *d)
{
    const csg_blob_header *h = p->h;
    int y0 = k * p->rows, n = h->height - y0 < p->rows ? h->height - y0 : p->rows;
    size_t row = (size_t)h->width * (size_t)h->spp;
    size_t first = row * (size_t)y0, count = row * (size_t)n;
    size_t nt = p->tiles_x * (size_t)((y0 + n - 1) / p->tile - y0 / p->tile + 1);
    ocl_records rec;
    if (!ocl_cells_upto(p->c, &p->cells, p->b.cells, p->blob, y0 + n - 1, d) ||
        !ocl_slice_records(p, k, first, count, &rec, d) ||
        !ocl_run_slice(p->c, h, p->tile, y0, n, &p->b, &rec, &p->cells,
                       p->marks ? p->marks[k] : NULL, d) ||
        !ocl_slice_download(p, k, first, count, d))
        return false;
    cl_int err = clEnqueueReadBuffer(p->c->queue, p->b.hits, CL_FALSE, 0, nt * sizeof(uint32_t),
                                     p->host_hits + (size_t)k * p->stride, 0, NULL,
                                     &p->events[k]);
    if (err != CL_SUCCESS)
        return ocl_fail(d, "clEnqueueReadBuffer(tile hits)", err);
    p->enqueued++;
    atomic_fetch_add(&p->callbacks, 1);
    err = clSetEventCallback(p->events[k], CL_COMPLETE, ocl_slice_done, p);
    if (err != CL_SUCCESS) {
        atomic_fetch_sub(&p->callbacks, 1);
        return ocl_fail(d, "clSetEventCallback", err);
    }
    return true;
}

/* The queue topped up to OCL_PASS_WINDOW slices beyond the last complete
 * one (every needed slice: `all`), flushed when something went on it.
 * The window is what lets ocl_pass_limit stop the pass: a slice on the
 * queue cannot be taken back. */
static bool ocl_pass_enqueue(ocl_pass *p, bool all, csg_diag *d)
{
    int upto = all ? p->needed : p->done + OCL_PASS_WINDOW;
    if (upto > p->needed)
        upto = p->needed;
    bool more = p->enqueued < upto;
    while (p->enqueued < upto)
        if (!ocl_pass_enqueue_slice(p, p->enqueued, d))
            return false;
    cl_int err = more ? clFlush(p->c->queue) : CL_SUCCESS;
    return err == CL_SUCCESS || ocl_fail(d, "clFlush", err);
}

bool ocl_pass_begin(ocl_ctx *c, const void *blob, int tile, int slice_rows, void *t_out,
                    uint32_t *surf_out, uint32_t *known_out, uint32_t *lit_out,
                    uint32_t *tile_hits, void (*notify)(void *), void *notify_arg,
                    ocl_pass **out, csg_diag *d)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    *out = NULL;
    if (!ocl_check_blob(c, h, tile, d))
        return false;
    if (!csg_features_cover(c->features, csg_features_specialised(csg_blob_features(blob)))) {
        csg_error_plain(d, "OpenCL: the program was specialised for other primitive kinds or "
                           "CSG features than the scene's (ocl_specialise first)");
        return false;
    }
    ocl_pass *p = calloc(1, sizeof *p);
    if (!p) {
        csg_error_plain(d, "out of memory");
        return false;
    }
    p->c = c;
    p->h = h;
    p->blob = blob;
    p->tile = tile;
    p->tile_hits = tile_hits;
    p->notify = notify;
    p->notify_arg = notify_arg;
    p->out[OCL_REC_T] = t_out;
    p->out[OCL_REC_SURF] = surf_out;
    p->out[OCL_REC_KNOWN] = known_out;
    p->out[OCL_REC_LIT] = lit_out;
    atomic_init(&p->callbacks, 0);
    p->t0 = ocl_now();
    bool ok = ocl_pass_alloc(p, blob, slice_rows, d);
    if (ok) {
        memset(tile_hits, 0, p->tiles_x * (size_t)((h->height + tile - 1) / tile) *
                                 sizeof(uint32_t));
        ok = ocl_pass_enqueue(p, false, d);
    }
    *out = p; /* even on failure: ocl_pass_end waits for what was enqueued */
    return ok;
}

/* Slice k is complete: its tile counts into the caller's. */
static void ocl_pass_count(ocl_pass *p, int k)
{
    int y0 = k * p->rows, n = p->h->height - y0 < p->rows ? p->h->height - y0 : p->rows;
    int ty0 = y0 / p->tile, tile_rows = (y0 + n - 1) / p->tile - ty0 + 1;
    uint32_t *dst = p->tile_hits + (size_t)ty0 * p->tiles_x;
    const uint32_t *src = p->host_hits + (size_t)k * p->stride;
    for (size_t i = 0; i < p->tiles_x * (size_t)tile_rows; i++)
        dst[i] += src[i];
}

int ocl_pass_rows(ocl_pass *p, bool wait, csg_diag *d)
{
    if (!ocl_pass_enqueue(p, false, d))
        return -1;
    while (p->done < p->enqueued) {
        cl_event e = p->events[p->done];
        cl_int status = CL_QUEUED, err = CL_SUCCESS;
        if (wait)
            err = clWaitForEvents(1, &e);
        if (err == CL_SUCCESS || err == CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
            err = clGetEventInfo(e, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status,
                                 NULL);
        if (err != CL_SUCCESS || status < 0) {
            ocl_fail(d, err != CL_SUCCESS ? "clGetEventInfo(CL_EVENT_COMMAND_EXECUTION_STATUS)"
                                          : "a slice of the primary pass",
                     err != CL_SUCCESS ? err : status);
            return -1;
        }
        if (status != CL_COMPLETE)
            break;
        ocl_pass_count(p, p->done++);
        p->t_end = ocl_now();
        wait = false; /* one more slice was waited for */
        if (!ocl_pass_enqueue(p, false, d)) /* (the device kept busy) */
            return -1;
    }
    int rows = p->done * p->rows;
    return rows < p->h->height ? rows : p->h->height;
}

void ocl_pass_limit(ocl_pass *p, int rows)
{
    int needed = rows <= 0 ? 0 : (rows + p->rows - 1) / p->rows;
    if (needed < p->needed)
        p->needed = needed; /* (slices on the queue beyond it still run) */
}

/* In place, every slice's mappings given back once the queue is done (the
 * caller's arrays keep the records); the first error, if any. */
static cl_int ocl_pass_unmap(ocl_pass *p)
{
    cl_int first = CL_SUCCESS;
    for (int k = 0; p->mem && k < p->slices; k++)
        for (int i = 0; i < OCL_RECS; i++) {
            if (!p->mem[k].mapped[i])
                continue;
            cl_int err = clEnqueueUnmapMemObject(p->c->queue, p->b.rec.m[i],
                                                 p->mem[k].mapped[i], 0, NULL, NULL);
            first = first != CL_SUCCESS ? first : err;
        }
    cl_int err = p->mem ? clFinish(p->c->queue) : CL_SUCCESS;
    return first != CL_SUCCESS ? first : err;
}

/* A command's start or end on the device's clock, in ns (0: unknown). */
static cl_ulong ocl_event_time(cl_event e, cl_profiling_info which)
{
    cl_ulong t = 0;
    if (!e || clGetEventProfilingInfo(e, which, sizeof t, &t, NULL) != CL_SUCCESS)
        return 0;
    return t;
}

/* What the device's clock says of the pass (once the queue is done):
 * each slice's kernels, from the first's start to the last's end; its
 * copies (or mappings) after them, to its last read's end; and the span
 * from the first slice's start to the last's end.  On the in-order queue
 * the rest of the span is the device idle between slices, waiting for
 * the host to enqueue.  All 0 where the queue does not time commands. */
static void ocl_pass_profile(const ocl_pass *p, ocl_timing *timing)
{
    timing->device_kernel_s = timing->device_copy_s = timing->device_span_s = 0.0;
    cl_ulong first = 0, last = 0, kernels = 0, copies = 0;
    for (int k = 0; p->marks && k < p->enqueued; k++) {
        cl_ulong k0 = ocl_event_time(p->marks[k][0], CL_PROFILING_COMMAND_START);
        cl_ulong k1 = ocl_event_time(p->marks[k][1], CL_PROFILING_COMMAND_END);
        cl_ulong r1 = ocl_event_time(p->events[k], CL_PROFILING_COMMAND_END);
        if (!k0 || k1 < k0 || r1 < k1)
            return; /* (a device whose clock says nothing usable) */
        kernels += k1 - k0;
        copies += r1 - k1;
        first = k == 0 || k0 < first ? k0 : first;
        last = r1 > last ? r1 : last;
    }
    timing->device_kernel_s = (double)kernels * 1e-9;
    timing->device_copy_s = (double)copies * 1e-9;
    timing->device_span_s = (double)(last - first) * 1e-9;
}

bool ocl_pass_end(ocl_pass *p, ocl_timing *timing, csg_diag *d)
{
    if (!p)
        return false;
    bool ok = p->done >= p->needed;
    cl_int err = clFinish(p->c->queue); /* no read may still target the caller's arrays */
    if (err != CL_SUCCESS && ok)
        ok = ocl_fail(d, "clFinish", err);
    while (atomic_load(&p->callbacks) > 0) { /* none may run on a freed pass */
        struct timespec ts = {0, 20000};
        nanosleep(&ts, NULL);
    }
    err = ocl_pass_unmap(p);
    if (err != CL_SUCCESS && ok)
        ok = ocl_fail(d, "clEnqueueUnmapMemObject(records)", err);
    if (timing) {
        timing->slices = p->enqueued;
        timing->primary_s = (p->t_end > 0 ? p->t_end : ocl_now()) - p->t0;
        timing->compute_units = (int)p->c->compute_units;
        ocl_kernel_name(p->c, timing->kernel, sizeof timing->kernel);
        ocl_device_name(p->c->device, timing->device_name, sizeof timing->device_name);
        timing->records_in_place = p->in_place;
        ocl_pass_profile(p, timing);
    }
    for (int k = 0; k < p->enqueued; k++) {
        clReleaseEvent(p->events[k]);
        for (int i = 0; p->marks && i < 2; i++)
            if (p->marks[k][i])
                clReleaseEvent(p->marks[k][i]);
    }
    for (int k = 0; p->mem && k < p->slices; k++)
        ocl_release_records(&p->mem[k].sub);
    free(p->mem);
    ocl_release_buffers(&p->b);
    free(p->cells.host);
    free(p->host_hits);
    free(p->events);
    free(p->marks);
    free(p);
    return ok;
}

bool ocl_primary_pass(ocl_ctx *c, const void *blob, int tile, void *t_out, uint32_t *surf_out,
                      uint32_t *tile_hits, ocl_timing *timing, csg_diag *d)
{
    ocl_pass *p;
    bool ok = ocl_pass_begin(c, blob, tile, 0, t_out, surf_out, NULL, NULL, tile_hits, NULL, NULL, &p,
                             d) &&
              ocl_pass_enqueue(p, true, d); /* (nothing to stop it for) */
    int height = csg_blob_hdr(blob)->height, rows = 0;
    while (ok && rows < height)
        ok = (rows = ocl_pass_rows(p, true, d)) >= 0;
    return ocl_pass_end(p, timing, d) && ok;
}

/* ---- opening and closing ---------------------------------------------------------- */

/* PoCL compiles each kernel for its work-group size at the first launch:
 * one launch on a 1 x 1 image of an empty scene moves that into
 * compile_s, out of the first primary_s. */
static bool ocl_warm_up(ocl_ctx *c, csg_diag *d)
{
    csg_scene empty;
    csg_blob blob = {NULL, 0};
    csg_flatten_opts o = {1, 1, 1, -1, 1, 0};
    csg_scene_init(&empty);
    bool ok = c->use_double ? csg_flatten_double(&empty, &o, &blob, d)
                            : csg_flatten_float(&empty, &o, &blob, d);
    csg_scene_free(&empty);
    double t[1];
    uint32_t surf[1], hits[1];
    ocl_timing timing;
    ok = ok && ocl_primary_pass(c, blob.bytes, 1, t, surf, hits, &timing, d);
    csg_blob_free(&blob);
    return ok;
}

bool ocl_cpu_device(const ocl_ctx *c) { return c->cpu; }

csg_features ocl_features(const ocl_ctx *c)
{
    return c->features;
}

bool ocl_specialise(ocl_ctx *c, csg_features need, ocl_timing *timing, csg_diag *d)
{
    if (csg_features_cover(c->features, csg_features_specialised(need)))
        return true;
    double t0 = ocl_now();
    char name[256];
    ocl_device_name(c->device, name, sizeof name);
    ocl_release_program(c);
    c->features = csg_features_specialised(need);
    if (!ocl_build(c, name, d) || !ocl_warm_up(c, d))
        return false;
    if (timing)
        timing->compile_s += ocl_now() - t0;
    return true;
}

bool ocl_open(const ocl_options *opt, ocl_ctx **out, ocl_timing *timing, csg_diag *d)
{
    return ocl_open_kernel(opt, OCL_KERNEL_AUTO, out, timing, d);
}

bool ocl_open_device(const char *device, ocl_ctx **out, ocl_timing *timing, csg_diag *d)
{
    double t_open = ocl_now();
    *out = NULL;
    ocl_ctx *c = calloc(1, sizeof *c);
    if (!c) {
        csg_error_plain(d, "out of memory");
        return false;
    }
    const char *sel = device && *device ? device : NULL;
    if (!ocl_pick_device(sel, &c->device, d))
        goto fail;
    ocl_device_name(c->device, timing->device_name, sizeof timing->device_name);
    cl_int err;
    c->context = clCreateContext(NULL, 1, &c->device, NULL, NULL, &err);
    if (err != CL_SUCCESS) {
        ocl_fail(d, "clCreateContext", err);
        goto fail;
    }
    /* (timed commands, where the device can: what a pass's wall time is
     * made of, ocl_pass_profile) */
    c->queue = clCreateCommandQueue(c->context, c->device, CL_QUEUE_PROFILING_ENABLE, &err);
    c->profiling = err == CL_SUCCESS;
    if (err != CL_SUCCESS)
        c->queue = clCreateCommandQueue(c->context, c->device, 0, &err);
    if (err != CL_SUCCESS) {
        ocl_fail(d, "clCreateCommandQueue", err);
        goto fail;
    }
    timing->setup_s = ocl_now() - t_open;
    *out = c;
    return true;
fail:
    ocl_close(c);
    return false;
}

bool ocl_open_program(ocl_ctx *c, const ocl_options *opt, enum ocl_kernel kernel,
                      ocl_timing *timing, csg_diag *d)
{
    double t_open = ocl_now();
    c->use_double = opt->use_double;
    c->max_slice_bytes = opt->max_slice_bytes;
    c->copy_buffers = opt->copy_buffers;
    c->source = opt->source ? opt->source : csg_kernel_source;
    c->cache_dir = opt->cache_dir;
    c->features = opt->features ? csg_features_specialised(*opt->features)
                                : csg_features_specialised(csg_features_all());
    const char *name = timing->device_name;
    if (!ocl_check_device(c, name, d) || !ocl_pick_kernel(c, kernel, opt->packet, d))
        return false;
    c->slice_records = opt->slice_records ? (uint64_t)opt->slice_records
                       : c->cpu           ? 0
                                          : OCL_DEVICE_SLICE_RECORDS;
    timing->compute_units = (int)c->compute_units;
    timing->cpu_device = c->cpu;
    ocl_kernel_name(c, timing->kernel, sizeof timing->kernel);
    double t0 = ocl_now();
    if (!ocl_build(c, name, d) || !ocl_warm_up(c, d))
        return false;
    timing->compile_s = ocl_now() - t0;
    timing->setup_s += t0 - t_open;
    return true;
}

bool ocl_open_kernel(const ocl_options *opt, enum ocl_kernel kernel, ocl_ctx **out,
                     ocl_timing *timing, csg_diag *d)
{
    if (!ocl_open_device(opt->device, out, timing, d))
        return false;
    if (ocl_open_program(*out, opt, kernel, timing, d))
        return true;
    ocl_close(*out);
    *out = NULL;
    return false;
}

void ocl_close(ocl_ctx *c)
{
    if (!c)
        return;
    ocl_release_program(c);
    if (c->queue)
        clReleaseCommandQueue(c->queue);
    if (c->context)
        clReleaseContext(c->context);
    free(c);
}

bool ocl_probe_layout(ocl_ctx *c, int32_t *out, int cap, int *count, csg_diag *d)
{
    cl_mem buf = NULL;
    bool ok = false;
    size_t one = 1, bytes = (size_t)cap * sizeof(int32_t);
    *count = 0;
    if (cap < 1 || !ocl_create_buffer(c, CL_MEM_WRITE_ONLY, bytes, NULL, &buf, "layout", d))
        goto fail;
    cl_int ccap = cap;
    if (!ocl_arg(c->k_layout, "csg_layout", 0, sizeof(cl_mem), &buf, d) ||
        !ocl_arg(c->k_layout, "csg_layout", 1, sizeof(cl_int), &ccap, d))
        goto fail;
    cl_int err = clEnqueueNDRangeKernel(c->queue, c->k_layout, 1, NULL, &one, NULL, 0, NULL, NULL);
    if (err != CL_SUCCESS) {
        ocl_fail(d, "clEnqueueNDRangeKernel(csg_layout)", err);
        goto fail;
    }
    /* The kernel writes at most cap ints and counts what did not fit. */
    err = clEnqueueReadBuffer(c->queue, buf, CL_TRUE, 0, bytes, out, 0, NULL, NULL);
    if (err != CL_SUCCESS) {
        ocl_fail(d, "clEnqueueReadBuffer(layout)", err);
        goto fail;
    }
    if (out[0] < 0 || out[0] >= cap) {
        csg_error_plain(d, "layout probe: %d entries do not fit %d", (int)out[0], cap);
        goto fail;
    }
    *count = out[0];
    memmove(out, out + 1, (size_t)out[0] * sizeof(int32_t));
    ok = true;
fail:
    if (buf)
        clReleaseMemObject(buf);
    return ok;
}

/* ---- the shadow answers ----------------------------------------------------------- */

/* The buffers of ocl_shadow_answers. */
typedef struct {
    cl_mem blob, t, surf, known, lit;
} ocl_shadow_buffers;

static void ocl_shadow_release(ocl_shadow_buffers *b)
{
    cl_mem *all[] = {&b->blob, &b->t, &b->surf, &b->known, &b->lit};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (*all[i])
            clReleaseMemObject(*all[i]);
}

bool ocl_shadow_answers(ocl_ctx *c, const void *blob, const void *t_image,
                        const uint32_t *surf_image, uint32_t *known_out, uint32_t *lit_out,
                        double *seconds, csg_diag *d)
{
    const csg_blob_header *h = csg_blob_hdr(blob);
    size_t n = (size_t)h->width * (size_t)h->spp * (size_t)h->height;
    ocl_shadow_buffers b = {NULL, NULL, NULL, NULL, NULL};
    cl_int y0 = 0, rows = h->height;
    const char *k = "csg_shadows";
    size_t group = 1;
    double t0 = ocl_now();
    bool ok =
        ocl_input_buffer(c, (size_t)h->total_size, blob, &b.blob, "scene", d) &&
        ocl_input_buffer(c, n * h->real_size, t_image, &b.t, "t", d) &&
        ocl_input_buffer(c, n * sizeof(uint32_t), surf_image, &b.surf, "surf", d) &&
        ocl_create_buffer(c, CL_MEM_WRITE_ONLY, n * sizeof(uint32_t), NULL, &b.known, "known", d) &&
        ocl_create_buffer(c, CL_MEM_WRITE_ONLY, n * sizeof(uint32_t), NULL, &b.lit, "lit", d) &&
        ocl_arg(c->k_shadows, k, 0, sizeof(cl_mem), &b.blob, d) &&
        ocl_arg(c->k_shadows, k, 1, sizeof(cl_int), &y0, d) &&
        ocl_arg(c->k_shadows, k, 2, sizeof(cl_int), &rows, d) &&
        ocl_arg(c->k_shadows, k, 3, sizeof(cl_mem), &b.t, d) &&
        ocl_arg(c->k_shadows, k, 4, sizeof(cl_mem), &b.surf, d) &&
        ocl_arg(c->k_shadows, k, 5, sizeof(cl_mem), &b.known, d) &&
        ocl_arg(c->k_shadows, k, 6, sizeof(cl_mem), &b.lit, d);
    cl_int err = CL_SUCCESS;
    group = c->group_shadows;
    size_t grid[2];
    ocl_shadow_grid(c, (cl_int)((size_t)h->width * (size_t)h->spp), rows, grid);
    size_t local[2] = {group, 1};
    if (ok && (err = clEnqueueNDRangeKernel(c->queue, c->k_shadows, 2, NULL, grid, local, 0, NULL,
                                            NULL)) != CL_SUCCESS)
        ok = ocl_fail(d, "clEnqueueNDRangeKernel(csg_shadows)", err);
    if (ok && (err = clEnqueueReadBuffer(c->queue, b.known, CL_TRUE, 0, n * sizeof(uint32_t),
                                         known_out, 0, NULL, NULL)) != CL_SUCCESS)
        ok = ocl_fail(d, "clEnqueueReadBuffer(known)", err);
    if (ok && (err = clEnqueueReadBuffer(c->queue, b.lit, CL_TRUE, 0, n * sizeof(uint32_t),
                                         lit_out, 0, NULL, NULL)) != CL_SUCCESS)
        ok = ocl_fail(d, "clEnqueueReadBuffer(lit)", err);
    if (seconds)
        *seconds = ocl_now() - t0;
    ocl_shadow_release(&b);
    return ok;
}
