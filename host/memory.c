/*
 * memory.c — the render's peak memory against what the process may still
 * allocate (memory.h).
 */
#include "memory.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <sys/resource.h>

/* 8-bit formats get a byte copy of the image, the others a float one. */
static uint64_t writer_bytes_per_pixel(const char *out_path)
{
    static const char *const eight_bit[] = {".png", ".jpg", ".jpeg", ".ppm", ".pnm",
                                            ".bmp", ".tga", ".gif",  ".webp"};
    const char *dot = out_path ? strrchr(out_path, '.') : NULL;
    if (!out_path)
        return 0;
    for (size_t i = 0; dot && i < sizeof eight_bit / sizeof eight_bit[0]; i++)
        if (strcasecmp(dot, eight_bit[i]) == 0)
            return 3;
    return 3 * sizeof(float);
}

render_memory render_memory_need(uint64_t pixels, int spp, size_t real_size, bool hetero,
                                 const char *out_path)
{
    render_memory m = {0};
    m.image = pixels * 3 * sizeof(float);
    if (hetero) {
        m.records = pixels * (uint64_t)(spp > 0 ? spp : 1) * (real_size + sizeof(uint32_t));
        m.device = m.records;
    }
    m.writer = pixels * writer_bytes_per_pixel(out_path);
    m.total = m.image + m.records + m.device + m.writer;
    return m;
}

/* A "Name:   N kB" line of a /proc file, in bytes; false when absent. */
static bool proc_kib(const char *path, const char *name, uint64_t *bytes)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return false;
    char line[256];
    size_t n = strlen(name);
    bool found = false;
    unsigned long long kib = 0;
    while (!found && fgets(line, sizeof line, f))
        found = strncmp(line, name, n) == 0 && line[n] == ':' &&
                sscanf(line + n + 1, "%llu", &kib) == 1;
    fclose(f);
    *bytes = (uint64_t)kib * 1024;
    return found;
}

/* What a resource limit leaves above the process's current use. */
static void limit_left(int resource, const char *status_name, uint64_t *least, bool *known)
{
    struct rlimit rl;
    uint64_t used;
    if (getrlimit(resource, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY ||
        !proc_kib("/proc/self/status", status_name, &used))
        return;
    uint64_t left = (uint64_t)rl.rlim_cur > used ? (uint64_t)rl.rlim_cur - used : 0;
    if (!*known || left < *least)
        *least = left;
    *known = true;
}

bool memory_available(uint64_t *bytes)
{
    bool known = proc_kib("/proc/meminfo", "MemAvailable", bytes);
    limit_left(RLIMIT_AS, "VmSize", bytes, &known);
    limit_left(RLIMIT_DATA, "VmData", bytes, &known);
    return known;
}

const char *memory_format(uint64_t bytes, char *buf, size_t size)
{
    static const char *const units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
    double v = (double)bytes;
    int u = 0;
    while (v >= 1024 && u < 4) {
        v /= 1024;
        u++;
    }
    snprintf(buf, size, u ? "%.2f %s" : "%.0f %s", v, units[u]);
    return buf;
}
