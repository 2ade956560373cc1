/*
 * user_files.h — the files a scene wrote (#fopen ... write|append, #write:
 * csg_scene.written, kept in memory by the parse), written by a render
 * into its output's folder once the scene is read: on rank 0 only, once
 * per render; check, export and compare write none.
 *
 * The rules are the outputs' (claim.h): a file already at the name must
 * be a regular file, no link (a replaced file is written to a temporary
 * one and renamed over it: file_atomic.h), the folder must exist and be
 * writable; a name with folders (sub/x.txt) needs them to exist, none of
 * them a symbolic link; an appended file (first opened with append) is
 * opened O_APPEND | O_NOFOLLOW | O_NONBLOCK and must be this user's plain
 * file with one name (file_unfit).  A written file may not be the scene,
 * one of its includes or an output of the render (exit 2).
 */
#ifndef OUTPUT_USER_FILES_H
#define OUTPUT_USER_FILES_H

#include "../../csg/diag.h"
#include "../../csg/scene.h"

/* Writes every file of s->written beside out_path; `taken`: the paths no
 * file may replace (count of them).  Returns 0, or with d filled 2 (a
 * file would replace a taken one) or 1 (a file cannot be written). */
int user_files_write(const csg_scene *s, const char *out_path, const char *const *taken,
                     int taken_count, csg_diag *d);

#endif
