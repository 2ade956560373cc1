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
 * A binary handed to the driver runs native code in the render, so an
 * entry is trusted only when everything about it checks:
 *   - the key of a program is SHA-256 over everything its binary depends
 *     on: the build options (kernel variant, precision, the scene's
 *     feature -D options), the device's name and driver and OpenCL
 *     versions, and the program's source (the one embedded in the
 *     program); a file is named by its key;
 *   - its header repeats the whole key and carries SHA-256 of the key and
 *     the payload together, checked before the payload is handed to
 *     OpenCL: a stale, torn, re-keyed or foreign file is refused, and the
 *     program is built from source and the entry written again;
 *   - the folder is private to the user (created 0700; an existing one
 *     that another user owns, or that others may write, is not used, with
 *     one warning), an entry is opened without following a link and
 *     without blocking (a FIFO or a device in its place is refused), and
 *     must be a regular file of this user;
 *   - files are written through mkstemp + rename, so a reader never sees
 *     half of one.
 * Every other failure to read or write the cache is silent: the program
 * is then built from source, as without the cache.
 *
 * Where: the folder the caller names (cl_cache_dir: $CSGTRACE_CL_CACHE,
 * "off" for none, else $XDG_CACHE_HOME/csgtrace, else $HOME/.cache/
 * csgtrace).
 */
#ifndef PASS_CL_CACHE_H
#define PASS_CL_CACHE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define CL_CACHE_KEY_BYTES 32 /* SHA-256 */

typedef struct {
    uint8_t bytes[CL_CACHE_KEY_BYTES];
} cl_cache_key_t;

/* The cache's folder for these settings ($CSGTRACE_CL_CACHE, else
 * $XDG_CACHE_HOME, else $HOME: host/config.h) into out; false when the
 * cache is off (or no folder can be named). */
bool cl_cache_dir(const char *setting, const char *xdg_cache_home, const char *home, char *out,
                  size_t size);

/* May folder `dir` hold the cache?  It is created (0700, with its
 * parents) when missing; false when it cannot be, or when it is not a
 * folder private to this user (another owner, or writable by others):
 * then *why says so (for one warning; "" when the folder simply cannot be
 * made, which is silent). */
bool cl_cache_usable(const char *dir, char *why, size_t why_size);

/* The key of a program built from `source` with `options` for `device` (a
 * text naming the device and its driver). */
cl_cache_key_t cl_cache_key(const char *source, const char *options, const char *device);

/* The payload cached in folder `dir` under `key` (malloc'ed, *size
 * bytes), or NULL. */
void *cl_cache_load(const char *dir, const cl_cache_key_t *key, size_t *size);

/* Keeps `size` bytes in `dir` under `key`; quietly does nothing when it
 * cannot. */
void cl_cache_store(const char *dir, const cl_cache_key_t *key, const void *payload, size_t size);

#endif
