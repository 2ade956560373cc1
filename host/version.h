/*
 * version.h — the program's version (csgtrace --version; the journal's
 * header names it with a hash of the build, host/output/journal.c).
 */
#ifndef HOST_VERSION_H
#define HOST_VERSION_H

#define CSGTRACE_VERSION "0.1"

#endif
