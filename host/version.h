/*
 * version.h — the program's version and build (csgtrace --version; the
 * journal's header names the build, host/output/journal.c).
 */
#ifndef HOST_VERSION_H
#define HOST_VERSION_H

#include <stdint.h>

#define CSGTRACE_VERSION "0.1"

/* The running program, named: tiles written by another build could differ
 * in their last bit, so a journal names the build that wrote it, and
 * --version prints it.  The hash of its ELF build ID (NT_GNU_BUILD_ID,
 * which the linker derives from the whole output) where it has one; else
 * of its file, read whole once.  0 when neither can be read. */
uint64_t version_build_hash(void);

#endif
