/*
 * test_claim.c — the lock of a render's output (host/output/claim.h): a
 * second claim of one output is refused while the first holds it, naming
 * the lock and the holder's process; released, the lock file is gone and
 * the output may be claimed again; a lock file left by a killed render is
 * taken over; a lock name that is a link (symbolic or hard) or no regular
 * file is refused, and the file it leads to is left as it was.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>

#include "../host/output/claim.h"

typedef struct {
    char dir[64], out[96], lock[112], other[112];
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    snprintf(f->dir, sizeof f->dir, "/tmp/csgtrace-claim-XXXXXX");
    if (!f || !mkdtemp(f->dir))
        return -1;
    snprintf(f->out, sizeof f->out, "%s/out.png", f->dir);
    claim_lock_name(f->out, f->lock, sizeof f->lock);
    snprintf(f->other, sizeof f->other, "%s/other", f->dir);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    unlink(f->lock);
    unlink(f->other);
    rmdir(f->dir);
    free(f);
    return 0;
}

static void test_second_claim_is_refused(void **state)
{
    fixture *f = *state;
    csg_diag d = {{0}, 0};
    claim *c = claim_take(f->out, &d);
    assert_non_null(c);
    assert_int_equal(access(f->lock, F_OK), 0);
    pid_t pid = fork(); /* (flock is per open file: another process claims) */
    if (pid == 0) {
        csg_diag d2 = {{0}, 0};
        char want[512];
        snprintf(want, sizeof want,
                 "%s is in use by another render (process %ld holds its lock %s)", f->out,
                 (long)getppid(), f->lock);
        _exit(claim_take(f->out, &d2) == NULL && strstr(d2.message, want) ? 0 : 1);
    }
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    claim_release(c);
    assert_int_not_equal(access(f->lock, F_OK), 0); /* (removed) */
    c = claim_take(f->out, &d);
    assert_non_null(c);
    claim_release(c);
}

/* A lock file whose holder was killed (no lock on it any more). */
static void test_stale_lock_is_taken_over(void **state)
{
    fixture *f = *state;
    FILE *stale = fopen(f->lock, "w");
    assert_non_null(stale);
    fputs("99999999\n", stale);
    fclose(stale);
    csg_diag d = {{0}, 0};
    claim *c = claim_take(f->out, &d);
    assert_non_null(c);
    claim_release(c);
}

/* The lock is written into (the holder's id): never through a link. */
static void test_links_are_refused(void **state)
{
    fixture *f = *state;
    FILE *other = fopen(f->other, "w");
    assert_non_null(other);
    fputs("precious\n", other);
    fclose(other);
    csg_diag d = {{0}, 0};
    assert_int_equal(symlink(f->other, f->lock), 0);
    assert_null(claim_take(f->out, &d));
    assert_non_null(strstr(d.message, "is a symbolic link"));
    unlink(f->lock);
    assert_int_equal(link(f->other, f->lock), 0);
    memset(&d, 0, sizeof d);
    assert_null(claim_take(f->out, &d));
    assert_non_null(strstr(d.message, "has other names"));
    unlink(f->lock);
    assert_int_equal(mkfifo(f->lock, 0600), 0);
    memset(&d, 0, sizeof d);
    assert_null(claim_take(f->out, &d));
    assert_non_null(strstr(d.message, "is not a regular file"));
    char buf[16] = "";
    other = fopen(f->other, "r");
    assert_non_null(other);
    assert_non_null(fgets(buf, sizeof buf, other));
    fclose(other);
    assert_string_equal(buf, "precious\n");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_second_claim_is_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_stale_lock_is_taken_over, setup, teardown),
        cmocka_unit_test_setup_teardown(test_links_are_refused, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
