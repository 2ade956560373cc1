/*
 * memory.h — what a render holds at its peak on the process that owns the
 * image, estimated before anything is allocated, and what this process may
 * still allocate: a render that cannot fit says so up front with the
 * figures, instead of growing until the kernel kills it.
 */
#ifndef HOST_MEMORY_H
#define HOST_MEMORY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint64_t image;   /* the float RGB image                             */
    uint64_t records; /* hetero: the hit records (t and surface id)      */
    uint64_t device;  /* hetero: the OpenCL pass's own record buffers    */
    uint64_t writer;  /* the encoder's copy of the image                 */
    uint64_t total;
} render_memory;

/* The peak of a render of `pixels` pixels at `spp` samples, `real_size`
 * bytes a real; `hetero` adds the hit records on both sides of the OpenCL
 * pass; `out_path` (NULL: none) tells the encoder's depth by its extension. */
render_memory render_memory_need(uint64_t pixels, int spp, size_t real_size, bool hetero,
                                 const char *out_path);

/* The bytes this process may still allocate: the least of the machine's
 * MemAvailable and what RLIMIT_AS and RLIMIT_DATA leave; false when none of
 * them can be read (then nothing is known and nothing is refused). */
bool memory_available(uint64_t *bytes);

/* Formats `bytes` as "1.23 GiB" (or MiB, KiB) into buf. */
const char *memory_format(uint64_t bytes, char *buf, size_t size);

#endif
