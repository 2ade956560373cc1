/*
 * test_cl_cache.c — the OpenCL program cache's checks without a device
 * (host/pass/cl_cache.h; e2e_hetero.sh renders through it): an entry is
 * stored and read back; whatever else is found under an entry's name — a
 * FIFO, a link, a torn, re-keyed, foreign or damaged file, one of another
 * owner — is a miss (never a blocked open), and the next store replaces
 * it atomically; the folder is made 0700, and one that others may write
 * or another user owns is not used, with the reason.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../host/pass/cl_cache.h"

#define HEADER_BYTES 88 /* magic 16, key 32, size 8, SHA-256 32 (cl_cache.c) */

static char dir[64];
static char path[PATH_MAX];
static const char payload[] = "not really a binary, but bytes all the same";

static void on_alarm(int sig)
{
    (void)sig;
    static const char msg[] = "cl_cache_load blocked\n";
    (void)!write(2, msg, sizeof msg - 1);
    _exit(1);
}

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/csg_clc_XXXXXX");
    assert_non_null(mkdtemp(dir));
    signal(SIGALRM, on_alarm);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    DIR *d = opendir(dir);
    if (d) {
        struct dirent *e;
        char p[PATH_MAX];
        while ((e = readdir(d)))
            if (e->d_name[0] != '.') {
                snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
                unlink(p);
            }
        closedir(d);
    }
    rmdir(dir);
    return 0;
}

static cl_cache_key_t key_of(const char *options)
{
    return cl_cache_key("__kernel void k(void) {}", options, "device driver 1.0");
}

/* The entry's file name: the only .clbin in dir. */
static void entry_path(void)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    path[0] = '\0';
    while ((e = readdir(d)))
        if (strstr(e->d_name, ".clbin")) {
            assert_true(path[0] == '\0'); /* one entry, no temporary left */
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        } else {
            assert_true(e->d_name[0] == '.');
        }
    closedir(d);
    assert_true(path[0] != '\0');
}

/* A miss, found without blocking. */
static void assert_miss(const cl_cache_key_t *key)
{
    size_t size = 0;
    alarm(5);
    void *got = cl_cache_load(dir, key, &size);
    alarm(0);
    assert_null(got);
}

static void assert_hit(const cl_cache_key_t *key)
{
    size_t size = 0;
    char *got = cl_cache_load(dir, key, &size);
    assert_non_null(got);
    assert_int_equal(size, sizeof payload);
    assert_memory_equal(got, payload, sizeof payload);
    free(got);
}

static long file_bytes(const char *p, char *buf, size_t size)
{
    FILE *f = fopen(p, "rb");
    assert_non_null(f);
    long n = (long)fread(buf, 1, size, f);
    fclose(f);
    return n;
}

static void put_bytes(const char *p, const char *buf, long n)
{
    unlink(p);
    FILE *f = fopen(p, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(buf, 1, (size_t)n, f), (size_t)n);
    fclose(f);
}

static void test_round_trip_and_keys(void **state)
{
    (void)state;
    cl_cache_key_t a = key_of("-DA"), b = key_of("-DB");
    assert_memory_not_equal(a.bytes, b.bytes, sizeof a.bytes);
    cl_cache_key_t c = cl_cache_key("__kernel void k(void) {}", "-DA", "device driver 1.1");
    assert_memory_not_equal(a.bytes, c.bytes, sizeof a.bytes); /* the driver is in the key */
    assert_miss(&a);
    cl_cache_store(dir, &a, payload, sizeof payload);
    entry_path();
    assert_hit(&a);
    assert_miss(&b);
    char why[256];
    assert_true(cl_cache_usable(dir, why, sizeof why));
}

/* A FIFO or a device where the entry should be: a miss at once (the old
 * cache opened it for reading and blocked for ever); a link: a miss. */
static void test_not_regular_files(void **state)
{
    (void)state;
    cl_cache_key_t a = key_of("-DA");
    cl_cache_store(dir, &a, payload, sizeof payload);
    entry_path();
    char real[PATH_MAX + 8];
    snprintf(real, sizeof real, "%s.real", path);
    assert_int_equal(rename(path, real), 0);
    assert_int_equal(mkfifo(path, 0600), 0);
    assert_miss(&a);
    unlink(path);
    assert_int_equal(symlink(real, path), 0); /* a valid entry, through a link */
    assert_miss(&a);
    unlink(path);
    assert_int_equal(symlink("/dev/zero", path), 0);
    assert_miss(&a);
    unlink(path);
    unlink(real);
    /* the next store replaces whatever was there */
    assert_int_equal(mkfifo(path, 0600), 0);
    cl_cache_store(dir, &a, payload, sizeof payload);
    struct stat st;
    assert_int_equal(lstat(path, &st), 0);
    assert_true(S_ISREG(st.st_mode));
    assert_hit(&a);
}

/* Damaged, torn, foreign and re-keyed entries: misses, then replaced. */
static void test_damaged_entries(void **state)
{
    (void)state;
    cl_cache_key_t a = key_of("-DA"), b = key_of("-DB");
    cl_cache_store(dir, &a, payload, sizeof payload);
    entry_path();
    char good[512], bad[512], pa[PATH_MAX];
    long n = file_bytes(path, good, sizeof good);
    assert_int_equal(n, HEADER_BYTES + (long)sizeof payload);
    snprintf(pa, sizeof pa, "%s", path);
    /* one payload byte changed, the header as it was */
    memcpy(bad, good, (size_t)n);
    bad[HEADER_BYTES + 3] ^= 1;
    put_bytes(pa, bad, n);
    assert_miss(&a);
    cl_cache_store(dir, &a, payload, sizeof payload);
    assert_hit(&a);
    /* torn */
    put_bytes(pa, good, n - 5);
    assert_miss(&a);
    put_bytes(pa, good, HEADER_BYTES - 1);
    assert_miss(&a);
    /* another program's entry under this name (its header names its key) */
    cl_cache_store(dir, &b, payload, sizeof payload);
    char pb[PATH_MAX], other[512];
    DIR *d = opendir(dir);
    struct dirent *e;
    pb[0] = '\0';
    while ((e = readdir(d)))
        if (strstr(e->d_name, ".clbin") && strcmp(strrchr(pa, '/') + 1, e->d_name) != 0)
            snprintf(pb, sizeof pb, "%s/%s", dir, e->d_name);
    closedir(d);
    assert_true(pb[0] != '\0');
    long m = file_bytes(pb, other, sizeof other);
    put_bytes(pa, other, m);
    assert_miss(&a);
    /* the same, re-keyed to this name: the digest (of the key and the
     * payload) no longer holds */
    memcpy(other + 16, a.bytes, sizeof a.bytes);
    put_bytes(pa, other, m);
    assert_miss(&a);
    /* re-keyed and its payload's old-style checksum (FNV-1a, which the
     * cache once trusted) recomputed: still a miss */
    memcpy(bad, good, (size_t)n);
    bad[HEADER_BYTES] ^= 0x55;
    uint64_t h = 0xcbf29ce484222325ull;
    for (long i = HEADER_BYTES; i < n; i++)
        h = (h ^ (unsigned char)bad[i]) * 0x100000001b3ull;
    memcpy(bad + 56, &h, sizeof h);
    put_bytes(pa, bad, n);
    assert_miss(&a);
    /* rebuilt: the store replaces it, no temporary left */
    cl_cache_store(dir, &a, payload, sizeof payload);
    assert_hit(&a);
    unlink(pb);
    entry_path();
}

/* The folder: made private; one that others may write, or that another
 * user owns, is not used (and says why). */
static void test_folder(void **state)
{
    (void)state;
    char sub[128], why[512];
    snprintf(sub, sizeof sub, "%s/a", dir);
    char made[160];
    snprintf(made, sizeof made, "%s/b", sub);
    assert_true(cl_cache_usable(made, why, sizeof why));
    struct stat st;
    assert_int_equal(stat(made, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0700);
    assert_int_equal(chmod(made, 0770), 0);
    assert_false(cl_cache_usable(made, why, sizeof why));
    assert_non_null(strstr(why, "others may write in"));
    assert_int_equal(chmod(made, 0702), 0);
    assert_false(cl_cache_usable(made, why, sizeof why));
    assert_int_equal(chmod(made, 0700), 0);
    if (geteuid() == 0) { /* (as root: another owner can be made) */
        assert_int_equal(chown(made, 65534, 65534), 0);
        assert_false(cl_cache_usable(made, why, sizeof why));
        assert_non_null(strstr(why, "belongs to user 65534"));
    }
    rmdir(made);
    rmdir(sub);
    char file[160];
    snprintf(file, sizeof file, "%s/plain", dir);
    put_bytes(file, "x", 1);
    assert_false(cl_cache_usable(file, why, sizeof why));
    assert_non_null(strstr(why, "is not a folder"));
    unlink(file);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_round_trip_and_keys, setup, teardown),
        cmocka_unit_test_setup_teardown(test_not_regular_files, setup, teardown),
        cmocka_unit_test_setup_teardown(test_damaged_entries, setup, teardown),
        cmocka_unit_test_setup_teardown(test_folder, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
