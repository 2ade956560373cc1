/*
 * signals.c — a clean stop on SIGINT and SIGTERM (signals.h).
 *
 * The handler may run on any thread (PoCL's and OpenImageIO's threads do
 * not block signals), so it only reads and sets two atomic flags and, when
 * no file is being written, writes one line and _exits: everything it calls
 * is async-signal-safe.
 */
#include "signals.h"

#include <signal.h>
#include <stdatomic.h>
#include <string.h>
#include <unistd.h>

static atomic_int holding; /* a file write is under way            */
static atomic_int pending; /* the signal that came during it, or 0 */

static void say_and_exit(int sig)
{
    const char *line = sig == SIGINT
                           ? "csgtrace: interrupted (SIGINT): the render stopped, no file written\n"
                           : "csgtrace: terminated (SIGTERM): the render stopped, no file written\n";
    ssize_t w = write(STDERR_FILENO, line, strlen(line));
    (void)w;
    _exit(128 + sig);
}

static void on_signal(int sig)
{
    if (atomic_load(&holding)) {
        atomic_store(&pending, sig);
        return;
    }
    say_and_exit(sig);
}

void signals_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

void signals_hold(void)
{
    atomic_store(&holding, 1);
}

void signals_release(const char *const *written, int n)
{
    atomic_store(&holding, 0);
    int sig = atomic_load(&pending);
    if (!sig)
        return;
    for (int i = 0; i < n; i++)
        if (written[i])
            unlink(written[i]);
    say_and_exit(sig);
}
