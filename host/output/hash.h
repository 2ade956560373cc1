/*
 * hash.h — FNV-1a, 64 bits: the checksum of the journal's records and the
 * identities of what a journal must match (its render, the program's
 * build).  Not cryptographic: it catches torn writes and stale files, not
 * an attacker who can write the files anyway (the OpenCL program cache,
 * which hands binaries to the driver, uses SHA-256: pass/cl_cache.h).
 */
#ifndef OUTPUT_HASH_H
#define OUTPUT_HASH_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

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

/* The same walk taken 8 bytes a step (then the last bytes one by one):
 * the journal sums every tile inside the tile phase, and byte by byte it
 * cost ~3 % of a light scene's trace time.  Each step is a bijection of
 * h, so one damaged word always changes the sum; the fold (h >> 29)
 * carries the high bits down, which a multiply alone never does.  Not
 * FNV-1a's value: a format that stores it says which one it uses. */
static inline uint64_t fnv1a_words(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        memcpy(&w, b + i, sizeof w);
        h = (h ^ w) * 0x100000001b3ull;
        h ^= h >> 29;
    }
    return fnv1a(h, b + i, n - i);
}

#endif
