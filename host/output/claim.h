/*
 * claim.h — a render's claim on its output: one lock per output, taken
 * before the render creates any file, so that two renders of one output
 * never run at once.
 *
 * The lock is an flock on OUT.lock, a file beside the output that is never
 * renamed (the journal is: it is created under a temporary name and
 * renamed into place, so a lock on it protected only the inode the locker
 * had made; two renders started together each made their own journal and
 * both ran).  flock dies with its process, so a render killed with -9
 * leaves no stale lock, only the empty file, which the next render takes
 * over.  The holder writes its process id into it (for the other render's
 * message) and removes it at its end, still holding the lock; a render that
 * locked a name removed meanwhile (the holder's end) sees that the name no
 * longer leads to its inode and tries again.  A signal that ends the
 * render removes it too (host/signals.h).
 *
 * Before the lock, every output path is checked (claim_check_output): a
 * render learns that it cannot write an output before its first tile.
 */
#ifndef OUTPUT_CLAIM_H
#define OUTPUT_CLAIM_H

#include <stdbool.h>
#include <stddef.h>

#include "../../csg/diag.h"

#define CLAIM_LOCK_SUFFIX ".lock"

typedef struct claim claim;

/* One output of the render (`what`, for the message: "the stats
 * (--stats)"), checked before the render makes any file, so that no
 * output is found unwritable after the last tile (when the finished image
 * would go again): an existing one must be a regular file, no link (a
 * render replaces a file by renaming a new one over it, which would
 * replace a FIFO, a device node or a link itself, not write into it), and
 * its folder must exist and be writable by this process.  false with d
 * filled (exit 1). */
bool claim_check_output(const char *path, const char *what, csg_diag *d);

/* OUT's lock file: OUT.lock, into buf (cut to size). */
void claim_lock_name(const char *out_path, char *buf, size_t size);

/* Takes the lock of the render to out_path: the claim, or NULL with d
 * filled (another render holds it: its lock and process named; or the
 * lock cannot be made).  The failure is exit 1. */
claim *claim_take(const char *out_path, csg_diag *d);

/* The render is over: the lock file removed, the lock released (NULL: no
 * claim). */
void claim_release(claim *c);

#endif
