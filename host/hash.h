/*
 * hash.h — FNV-1a, 64 bits: the checksum of the journal's records and the
 * identities of what a file on disk must match (a journal's render, a
 * cached OpenCL program's source).  Not cryptographic: it catches torn
 * writes and stale files, not an attacker who can write the files anyway.
 */
#ifndef HOST_HASH_H
#define HOST_HASH_H

#include <stddef.h>
#include <stdint.h>

#define FNV_BASIS 0xcbf29ce484222325ull

static inline uint64_t fnv1a(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++) {
        h ^= b[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

#endif
