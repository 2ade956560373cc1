/*
 * test_hooks.h — the test hooks, behind one seam (Lua's ltests.h in
 * spirit): numbers the tests put in the environment to make a render
 * fail, hang or take a path it would not take by itself.
 *
 * They exist only in a test build (-DCSG_TEST_HOOKS: the test programs,
 * build/csgtrace-test and every ASan program; Makefile).  In the program
 * that is installed every hook is the constant "unset", so its branch
 * compiles away and no CSGTRACE_TEST_* variable is ever read.
 */
#ifndef COMM_TEST_HOOKS_H
#define COMM_TEST_HOOKS_H

#include <stdbool.h>

/* The hooks: X(id, environment variable, what it does). */
#define TEST_HOOKS(X)                                                                          \
    X(TEST_FAIL_WORKER, "CSGTRACE_TEST_FAIL_WORKER",                                           \
      "worker R answers its first item with FAIL")                                             \
    X(TEST_KILL_RANK, "CSGTRACE_TEST_KILL_RANK",                                               \
      "rank R (or every worker: 'workers') SIGKILLs itself (test_hook_kill)")                   \
    X(TEST_KILL_AT, "CSGTRACE_TEST_KILL_AT",                                                   \
      "at that moment: item (default), send, scene, ready")                                    \
    X(TEST_KILL_AFTER, "CSGTRACE_TEST_KILL_AFTER",                                             \
      "after so many of them (default 2)")                                                     \
    X(TEST_HANG, "CSGTRACE_TEST_HANG",                                                         \
      "set: it hangs there instead of dying ('stop': the process stops, SIGSTOP)")             \
    X(TEST_HANG_S, "CSGTRACE_TEST_HANG_S",                                                     \
      "the master's backstop for a silent worker, in seconds (default 10)")                    \
    X(TEST_CL_DELAY_MS, "CSGTRACE_TEST_CL_DELAY_MS",                                           \
      "the OpenCL program's build takes that much longer")                                     \
    X(TEST_CL_MAX_ALLOC, "CSGTRACE_TEST_CL_MAX_ALLOC",                                         \
      "the device's largest buffer, in bytes, pretended")                                      \
    X(TEST_FILL_TILES, "CSGTRACE_TEST_FILL_TILES",                                             \
      "the fill claims at most so many tiles while a pass may come")                           \
    X(TEST_PASS_PAYS_MS, "CSGTRACE_TEST_PASS_PAYS_MS",                                         \
      "--pass auto's threshold, in ms of guessed primary-ray work")                           \
    X(TEST_NODE_RANKS, "CSGTRACE_TEST_NODE_RANKS",                                             \
      "one machine pretends nodes of N consecutive ranks (the scene's copy a node)")            \
    X(TEST_LINK_MBPS, "CSGTRACE_TEST_LINK_MBPS",                                               \
      "the link between nodes measured at start pretended that many MB/s")                      \
    X(TEST_SLOW_WORKER, "CSGTRACE_TEST_SLOW_WORKER",                                           \
      "worker R takes 20 ms longer over each message of work (a costly part)")

enum test_hook {
#define TEST_HOOK_ID(id, name, what) id,
    TEST_HOOKS(TEST_HOOK_ID)
#undef TEST_HOOK_ID
        TEST_HOOK_COUNT
};

#ifdef CSG_TEST_HOOKS
/* The hook's text (NULL: unset). */
const char *test_hook_text(enum test_hook h);
/* The hook as a whole number from 1 to below `bound`; 0 when unset or
 * anything else. */
long long test_hook_number(enum test_hook h, long long bound);
/* To kill a rank mid-render the way a crash or the OOM killer would
 * (tests/e2e_survive.sh): with CSGTRACE_TEST_KILL_RANK set to a rank (0:
 * the master) or to "workers" (every worker), that rank SIGKILLs itself at
 * `moment` once it has `done` == CSGTRACE_TEST_KILL_AFTER (default 2)
 * items: moment "item" (the default of CSGTRACE_TEST_KILL_AT): a worker
 * about to compute an item, after `done` answered; the master after
 * `done` results received; "send": a worker that has just begun sending
 * its answer to item `done` (counted from 0); "ready": a worker before its
 * handshake (done 0); "scene": a worker between the setup and the scene
 * of the broadcast (done 0).  With CSGTRACE_TEST_HANG set too, it hangs
 * instead (this thread waits for ever; "stop": the whole process stops,
 * as SIGSTOP or Ctrl-Z would stop it). */
void test_hook_kill(int rank, const char *moment, int done);
#else
static inline const char *test_hook_text(enum test_hook h)
{
    (void)h;
    return 0;
}
static inline long long test_hook_number(enum test_hook h, long long bound)
{
    (void)h;
    (void)bound;
    return 0;
}
static inline void test_hook_kill(int rank, const char *moment, int done)
{
    (void)rank;
    (void)moment;
    (void)done;
}
#endif

#endif
