/*
 * test_signals.c — host/signals.c in a child process each: a signal during
 * the render stops it with "no file written" (exit 143); one during a
 * write waits for its end, then removes the file written; one after the
 * render finished (signals_finished, as when mpirun ends the job after
 * rank 0 wrote its image) says the files are kept, and keeps them.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../host/signals.h"

enum when { DURING_RENDER, DURING_WRITE, AFTER_FINISH };

/* Runs the case in a child; its stderr into err, its exit status back. */
static int run_child(enum when when, const char *file, char *err, size_t cap)
{
    int fds[2];
    assert_int_equal(pipe(fds), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        dup2(fds[1], STDERR_FILENO);
        close(fds[0]);
        signals_install();
        if (when == DURING_WRITE) {
            signals_hold();
            raise(SIGTERM); /* waits for the release */
            FILE *f = fopen(file, "w");
            if (f)
                fclose(f);
            const char *written[] = {file};
            signals_release(written, 1);
        } else {
            if (when == AFTER_FINISH) {
                FILE *f = fopen(file, "w");
                if (f)
                    fclose(f);
                signals_finished();
            }
            raise(SIGTERM);
        }
        _exit(0); /* (not reached) */
    }
    close(fds[1]);
    size_t n = 0;
    ssize_t got;
    while (n + 1 < cap && (got = read(fds[0], err + n, cap - 1 - n)) > 0)
        n += (size_t)got;
    err[n] = '\0';
    close(fds[0]);
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    return WEXITSTATUS(status);
}

static void test_signal_during_render(void **state)
{
    (void)state;
    char err[512];
    assert_int_equal(run_child(DURING_RENDER, NULL, err, sizeof err), 143);
    assert_non_null(strstr(err, "terminated (SIGTERM): the render stopped, no file written"));
}

/* An empty file of our own in /tmp, its name into file. */
static void temp_file(char file[static 34])
{
    strcpy(file, "/tmp/csgtrace-test-signals-XXXXXX");
    int fd = mkstemp(file);
    assert_true(fd >= 0);
    close(fd);
}

static void test_signal_during_write_removes_the_file(void **state)
{
    (void)state;
    char file[34], err[512];
    temp_file(file);
    assert_int_equal(run_child(DURING_WRITE, file, err, sizeof err), 143);
    assert_non_null(strstr(err, "no file written"));
    assert_int_not_equal(access(file, F_OK), 0);
}

static void test_signal_after_finish_keeps_the_files(void **state)
{
    (void)state;
    char file[34], err[512];
    temp_file(file);
    assert_int_equal(run_child(AFTER_FINISH, file, err, sizeof err), 143);
    assert_non_null(strstr(err, "terminated (SIGTERM) after the render had finished: its files "
                                "are kept"));
    assert_null(strstr(err, "no file written"));
    assert_int_equal(access(file, F_OK), 0);
    unlink(file);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_signal_during_render),
        cmocka_unit_test(test_signal_during_write_removes_the_file),
        cmocka_unit_test(test_signal_after_finish_keeps_the_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
