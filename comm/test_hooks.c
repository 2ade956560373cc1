/*
 * test_hooks.c — the test hooks read from the environment (test_hooks.h);
 * empty unless built with -DCSG_TEST_HOOKS.
 */
#include "test_hooks.h"

#ifdef CSG_TEST_HOOKS
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../csg/numbers.h"

const char *test_hook_text(enum test_hook h)
{
    static const char *const names[] = {
#define TEST_HOOK_NAME(id, name, what) name,
        TEST_HOOKS(TEST_HOOK_NAME)
#undef TEST_HOOK_NAME
    };
    return h >= 0 && h < TEST_HOOK_COUNT ? getenv(names[h]) : NULL;
}

long long test_hook_number(enum test_hook h, long long bound)
{
    long long n = 0;
    return number_whole(test_hook_text(h), 1, bound - 1, &n) ? n : 0;
}

void test_hook_kill(int rank, const char *moment, int done)
{
    const char *who = test_hook_text(TEST_KILL_RANK);
    if (!who || (strcmp(who, "workers") == 0 ? rank == 0 : atoi(who) != rank || !*who))
        return;
    const char *at = test_hook_text(TEST_KILL_AT);
    const char *after = test_hook_text(TEST_KILL_AFTER);
    if (strcmp(at ? at : "item", moment) != 0 || done != (after ? atoi(after) : 2))
        return;
    const char *hang = test_hook_text(TEST_HANG);
    if (hang && strcmp(hang, "stop") == 0)
        raise(SIGSTOP);
    while (hang)
        pause();
    raise(SIGKILL);
}
#endif
