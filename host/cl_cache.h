/*
 * cl_cache.h — compiled OpenCL programs kept on disk between runs.
 *
 * Why: PoCL caches what it compiles, but to find its cache entry for a
 * program given as source it first runs Clang's preprocessor over the
 * source, our headers and OpenCL's own opencl-c.h: 65 ms of every hetero
 * render's set-up on this machine (POCL_DEBUG=all timestamps around
 * pocl_llvm_build_program), while the whole render of a small scene takes
 * 0.1-0.3 s.  A program built from the binary PoCL hands back
 * (CL_PROGRAM_BINARIES) skips the preprocessor.
 *
 * The key of a program is FNV-1a over everything its binary depends on:
 * the build options (kernel variant, precision, the scene's feature -D
 * options), the device's name and driver and OpenCL versions, and the
 * bytes of every file of the kernel sources (simd_kernels/ and
 * csg/device/, read in name order).  A file is named by its key; its
 * header repeats the key and the payload's size and FNV-1a, checked before
 * the payload is handed to OpenCL: a stale, torn or foreign file is
 * ignored (and replaced after the build from source).  Files are written
 * through mkstemp + rename, so a reader never sees half of one.
 *
 * Where: $CSGTRACE_CL_CACHE (a folder; "off" disables the cache), else
 * $XDG_CACHE_HOME/csgtrace, else $HOME/.cache/csgtrace.  Every failure to
 * read or write the cache is silent: the program is then built from
 * source, as without the cache.
 */
#ifndef HOST_CL_CACHE_H
#define HOST_CL_CACHE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The key of a program built with `options` for `device` (a text naming
 * the device and its driver) from the sources under `source_dir`; false
 * when a source cannot be read (no caching then). */
bool cl_cache_key(const char *source_dir, const char *options, const char *device,
                  uint64_t *key);

/* The payload cached under `key` (malloc'ed, *size bytes), or NULL. */
void *cl_cache_load(uint64_t key, size_t *size);

/* Keeps `size` bytes under `key`; quietly does nothing when it cannot. */
void cl_cache_store(uint64_t key, const void *payload, size_t size);

#endif
