/*
 * test_signals.c — host/signals.c in a child process each: a signal during
 * the render stops it with "no file written" (exit 143); one during a
 * write waits for its end, then removes the file written; one after the
 * render finished (signals_finished, as when mpirun ends the job after
 * rank 0 wrote its image) says the files are kept, and keeps them; SIGHUP
 * stops it too (exit 129), unless ignored at the start (nohup); a
 * temporary file being written is removed at once.
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

enum when { DURING_RENDER, DURING_WRITE, AFTER_FINISH, OTHER_SIGNAL, TEMPORARY, IGNORED };

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
        /* (nohup), or as a terminal would start it whatever started the
         * suite (under nohup every SIGHUP would stay ignored) */
        signal(SIGHUP, when == IGNORED ? SIG_IGN : SIG_DFL);
        signals_install();
        if (when == OTHER_SIGNAL || when == IGNORED) {
            raise(SIGHUP);
            _exit(0);
        }
        if (when == TEMPORARY) { /* (an image being written: no hold) */
            signals_temporary(file);
            raise(SIGUSR1);
            _exit(0);
        }
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

/* Every signal that would end the process is handled like SIGTERM, with
 * its own words and exit 128 + it (SIGHUP once killed it, leaving the
 * image's temporary file). */
static void test_other_signals_stop_the_render(void **state)
{
    (void)state;
    char err[512];
    assert_int_equal(run_child(OTHER_SIGNAL, NULL, err, sizeof err), 128 + SIGHUP);
    assert_non_null(strstr(err, "csgtrace: hung up (SIGHUP): the render stopped, no file written"));
}

/* ... unless it was ignored at the start (nohup): it stays ignored. */
static void test_ignored_signals_stay_ignored(void **state)
{
    (void)state;
    char err[512];
    assert_int_equal(run_child(IGNORED, NULL, err, sizeof err), 0);
    assert_string_equal(err, "");
}

/* A temporary file being written goes with the signal, at once. */
static void test_signal_removes_the_temporary_file(void **state)
{
    (void)state;
    char file[34], err[512];
    temp_file(file);
    assert_int_equal(run_child(TEMPORARY, file, err, sizeof err), 128 + SIGUSR1);
    assert_non_null(strstr(err, "(SIGUSR1): the render stopped, no file written"));
    assert_int_not_equal(access(file, F_OK), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_signal_during_render),
        cmocka_unit_test(test_signal_during_write_removes_the_file),
        cmocka_unit_test(test_signal_after_finish_keeps_the_files),
        cmocka_unit_test(test_other_signals_stop_the_render),
        cmocka_unit_test(test_ignored_signals_stay_ignored),
        cmocka_unit_test(test_signal_removes_the_temporary_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
