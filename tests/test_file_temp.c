/*
 * test_file_temp.c — host/output/file_atomic.h's files named once
 * complete: unnamed while written where the file system allows it (a
 * process killed with SIGKILL leaves nothing), else under a mkstemp name;
 * committed over an existing target, published with the descriptor kept,
 * discarded without a trace; whole files through file_write_atomic.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../host/output/file_atomic.h"

static char dir[64];
static char target[128];

static int setup(void **state)
{
    (void)state;
    strcpy(dir, "/tmp/csgtrace-test-file-temp-XXXXXX");
    if (!mkdtemp(dir))
        return -1;
    snprintf(target, sizeof target, "%s/out.txt", dir);
    return 0;
}

/* Empties the folder and removes it. */
static int teardown(void **state)
{
    (void)state;
    DIR *d = opendir(dir);
    struct dirent *e;
    char path[400];
    while (d && (e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            unlink(path);
        }
    if (d)
        closedir(d);
    return rmdir(dir);
}

/* The folder's entries: how many, and the first one's name into first. */
static int entries(char *first, size_t size)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && n++ == 0 && first)
            snprintf(first, size, "%s", e->d_name);
    closedir(d);
    return n;
}

/* The whole of `path` into buf (NUL-terminated); its length, -1: none. */
static long contents(const char *path, char *buf, size_t size)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    size_t n = fread(buf, 1, size - 1, f);
    buf[n] = '\0';
    fclose(f);
    return (long)n;
}

static void write_text(int fd, const char *text)
{
    assert_true(file_write_all(fd, text, strlen(text)));
}

/* Does this folder's file system have unnamed files (O_TMPFILE)? */
static bool unnamed_files(void)
{
    int fd = open(dir, O_TMPFILE | O_WRONLY, 0600);
    if (fd < 0)
        return false;
    close(fd);
    return true;
}

static void test_unnamed_until_committed(void **state)
{
    (void)state;
    if (!unnamed_files())
        skip();
    file_temp t;
    assert_true(file_temp_open(&t, target, 0640));
    assert_null(t.name);
    write_text(t.fd, "an image");
    assert_int_equal(entries(NULL, 0), 0); /* nothing to see while written */
    assert_true(file_temp_commit(&t));
    assert_int_equal(t.fd, -1);
    char name[256], buf[64];
    assert_int_equal(entries(name, sizeof name), 1);
    assert_string_equal(name, "out.txt");
    assert_int_equal(contents(target, buf, sizeof buf), 8);
    assert_string_equal(buf, "an image");
    struct stat st;
    assert_int_equal(stat(target, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0640); /* (fchmod: no umask) */
    assert_int_equal(st.st_nlink, 1);
}

/* Named for the moment before the rename: the name is the mkstemp kind,
 * beside the target, and goes with the rename. */
static void test_named_before_the_rename(void **state)
{
    (void)state;
    file_temp t;
    assert_true(file_temp_open(&t, target, 0600));
    write_text(t.fd, "x");
    assert_true(file_temp_name(&t));
    assert_non_null(t.name);
    char name[256];
    assert_int_equal(entries(name, sizeof name), 1);
    assert_int_equal(strncmp(name, "out.txt.tmp.", 12), 0);
    assert_int_equal(strlen(name), strlen("out.txt.tmp.XXXXXX"));
    assert_true(file_temp_name(&t)); /* (once named, the same name) */
    assert_true(file_temp_commit(&t));
    assert_int_equal(entries(name, sizeof name), 1);
    assert_string_equal(name, "out.txt");
}

static void test_commit_replaces_the_target(void **state)
{
    (void)state;
    FILE *f = fopen(target, "w");
    assert_non_null(f);
    fputs("the old one, longer", f);
    fclose(f);
    for (int named = 0; named < 2; named++) {
        char before[64], buf[64];
        assert_true(contents(target, before, sizeof before) > 0);
        file_temp t;
        assert_true(named ? file_temp_open_named(&t, target, 0644)
                          : file_temp_open(&t, target, 0644));
        write_text(t.fd, named ? "newer" : "new");
        contents(target, buf, sizeof buf);
        assert_string_equal(buf, before); /* the old one meanwhile */
        assert_true(file_temp_commit(&t));
        assert_int_equal(entries(NULL, 0), 1);
        contents(target, buf, sizeof buf);
        assert_string_equal(buf, named ? "newer" : "new");
    }
}

/* The fallback: a mkstemp name from the start, the target untouched. */
static void test_named_fallback(void **state)
{
    (void)state;
    file_temp t;
    assert_true(file_temp_open_named(&t, target, 0600));
    assert_non_null(t.name);
    char name[256];
    assert_int_equal(entries(name, sizeof name), 1);
    assert_int_equal(strncmp(name, "out.txt.tmp.", 12), 0);
    assert_int_equal(access(target, F_OK), -1);
    write_text(t.fd, "y");
    assert_true(file_temp_commit(&t));
    assert_int_equal(entries(name, sizeof name), 1);
    assert_string_equal(name, "out.txt");
}

static void test_discard_leaves_nothing(void **state)
{
    (void)state;
    for (int how = 0; how < 3; how++) { /* unnamed, unnamed then named, named */
        file_temp t;
        assert_true(how == 2 ? file_temp_open_named(&t, target, 0600)
                             : file_temp_open(&t, target, 0600));
        write_text(t.fd, "z");
        if (how == 1)
            assert_true(file_temp_name(&t));
        file_temp_discard(&t);
        assert_int_equal(t.fd, -1);
        assert_null(t.name);
        assert_null(t.path);
        assert_int_equal(entries(NULL, 0), 0);
        file_temp_discard(&t); /* (twice: nothing) */
    }
}

/* Published: in place, and the descriptor still writes into it. */
static void test_publish_keeps_the_descriptor(void **state)
{
    (void)state;
    file_temp t;
    assert_true(file_temp_open(&t, target, 0600));
    write_text(t.fd, "head;");
    int fd = file_temp_publish(&t);
    assert_true(fd >= 0);
    assert_int_equal(t.fd, -1);
    write_text(fd, "records");
    close(fd);
    char buf[64];
    contents(target, buf, sizeof buf);
    assert_string_equal(buf, "head;records");
    assert_int_equal(entries(NULL, 0), 1);
}

/* No folder: false with its errno, nothing made, t holding nothing. */
static void test_no_folder(void **state)
{
    (void)state;
    char path[200];
    snprintf(path, sizeof path, "%s/none/out.txt", dir);
    file_temp t;
    errno = 0;
    assert_false(file_temp_open(&t, path, 0600));
    assert_int_equal(errno, ENOENT);
    assert_int_equal(t.fd, -1);
    assert_null(t.name);
    assert_null(t.path);
    file_temp_discard(&t);
    assert_int_equal(entries(NULL, 0), 0);
}

/* A process killed with SIGKILL while it writes leaves nothing behind
 * (no handler runs): what O_TMPFILE is for. */
static void test_killed_writer_leaves_nothing(void **state)
{
    (void)state;
    if (!unnamed_files())
        skip();
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        file_temp t;
        if (!file_temp_open(&t, target, 0600) || !file_write_all(t.fd, "half", 4))
            _exit(1);
        raise(SIGKILL);
        _exit(2); /* (not reached) */
    }
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFSIGNALED(status));
    assert_int_equal(WTERMSIG(status), SIGKILL);
    assert_int_equal(entries(NULL, 0), 0);
}

static bool write_hello(FILE *f, void *arg, char *err, size_t err_size)
{
    (void)arg;
    (void)err;
    (void)err_size;
    return fputs("hello\n", f) >= 0;
}

static bool write_and_give_up(FILE *f, void *arg, char *err, size_t err_size)
{
    (void)arg;
    fputs("half a file", f);
    snprintf(err, err_size, "gave up");
    return false;
}

/* A whole file: written and renamed; a writer that gives up leaves the
 * target as it was and no temporary file. */
static void test_write_atomic(void **state)
{
    (void)state;
    char err[256], buf[64];
    assert_true(file_write_atomic_checked(target, write_hello, NULL, err, sizeof err));
    contents(target, buf, sizeof buf);
    assert_string_equal(buf, "hello\n");
    assert_false(file_write_atomic_checked(target, write_and_give_up, NULL, err, sizeof err));
    assert_string_equal(err, "gave up");
    contents(target, buf, sizeof buf);
    assert_string_equal(buf, "hello\n");
    assert_int_equal(entries(NULL, 0), 1);
    struct stat st;
    assert_int_equal(stat(target, &st), 0);
    assert_int_equal(st.st_mode & 0777, file_default_mode());
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_unnamed_until_committed, setup, teardown),
        cmocka_unit_test_setup_teardown(test_named_before_the_rename, setup, teardown),
        cmocka_unit_test_setup_teardown(test_commit_replaces_the_target, setup, teardown),
        cmocka_unit_test_setup_teardown(test_named_fallback, setup, teardown),
        cmocka_unit_test_setup_teardown(test_discard_leaves_nothing, setup, teardown),
        cmocka_unit_test_setup_teardown(test_publish_keeps_the_descriptor, setup, teardown),
        cmocka_unit_test_setup_teardown(test_no_folder, setup, teardown),
        cmocka_unit_test_setup_teardown(test_killed_writer_leaves_nothing, setup, teardown),
        cmocka_unit_test_setup_teardown(test_write_atomic, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
