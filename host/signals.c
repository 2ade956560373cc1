/*
 * signals.c — a clean stop on every signal that would end the process
 * (signals.h).
 *
 * The handler may run on any thread (PoCL's and OpenImageIO's threads do
 * not block signals), so it only reads and sets two atomic flags and, when
 * no file is being renamed into place, removes the render's temporary
 * files, writes one line and _exits: everything it calls is
 * async-signal-safe.  Two signals at once (on two threads): the second
 * waits for the first's _exit.
 */
#include "signals.h"

#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <string.h>
#include <unistd.h>

/* The signals handled, what the line calls each, and whether it is
 * handled even when ignored at the start.  Every asynchronous signal whose
 * default is to end the process; not the faults (SIGSEGV, SIGBUS, SIGFPE,
 * SIGILL, SIGABRT, SIGTRAP, SIGSYS: a bug's, whose core dump is worth
 * more, and the sanitizers' own), SIGXFSZ (ignored: a write that meets
 * the limit fails, and says so), SIGKILL and SIGSTOP (they cannot be
 * caught) nor the real-time ones (left to the libraries: Open MPI, PoCL).
 * SIGINT and SIGTERM are handled always (a shell starts a background job
 * with SIGINT ignored, and the tests stop one so); the others only when
 * their action is the default one at the start: one ignored (nohup's
 * SIGHUP, a shell's or Open MPI's SIGPIPE) stays ignored, one a library
 * handles (a profiler's SIGPROF) stays its. */
#define SIGNALS(X)                                                                             \
    X(SIGINT, "interrupted (SIGINT)", true)                                                    \
    X(SIGTERM, "terminated (SIGTERM)", true)                                                   \
    X(SIGHUP, "hung up (SIGHUP)", false)                                                       \
    X(SIGQUIT, "quit (SIGQUIT)", false)                                                        \
    X(SIGPIPE, "broken pipe (SIGPIPE)", false)                                                 \
    X(SIGALRM, "alarm clock (SIGALRM)", false)                                                 \
    X(SIGUSR1, "user signal 1 (SIGUSR1)", false)                                               \
    X(SIGUSR2, "user signal 2 (SIGUSR2)", false)                                               \
    X(SIGXCPU, "CPU time limit exceeded (SIGXCPU)", false)                                     \
    X(SIGVTALRM, "virtual timer expired (SIGVTALRM)", false)                                   \
    X(SIGPROF, "profiling timer expired (SIGPROF)", false)                                     \
    X(SIGIO, "I/O possible (SIGIO)", false)                                                    \
    X(SIGPWR, "power failure (SIGPWR)", false)                                                 \
    X(SIGSTKFLT, "stack fault (SIGSTKFLT)", false)

static atomic_flag ending = ATOMIC_FLAG_INIT; /* a handler is ending it */
static atomic_int holding; /* a file write is under way            */
static atomic_int pending; /* the signal that came during it, or 0 */
static atomic_int finished; /* the outputs are written and kept     */
static atomic_int journal_tiles;  /* tiles in the journal              */
static atomic_int journal_ready;  /* journal_path is complete         */
static char journal_path[4096];   /* the journal (set before the tile
                                     phase, cleared after it)           */
static atomic_int temporary_ready; /* temporary_path is complete      */
static char temporary_path[4096];  /* a file being written, to remove   */
static atomic_int lock_ready;      /* lock_path is complete            */
static char lock_path[4096];       /* the output's lock, to remove      */

/* write(2) of a string; the result is of no use in a handler. */
static void say(const char *s)
{
    ssize_t w = write(STDERR_FILENO, s, strlen(s));
    (void)w;
}

/* n in decimal (async-signal-safe). */
static void say_count(int n)
{
    char digits[16];
    int i = (int)sizeof digits - 1;
    digits[i] = '\0';
    do {
        digits[--i] = (char)('0' + n % 10);
        n /= 10;
    } while (n > 0 && i > 0);
    say(digits + i);
}

/* What the line calls signal sig. */
static const char *signal_words(int sig)
{
#define SIGNAL_WORDS(id, words, always)                                                        \
    if (sig == id)                                                                             \
        return words;
    SIGNALS(SIGNAL_WORDS)
#undef SIGNAL_WORDS
    return "stopped by a signal";
}

static void say_and_exit(int sig)
{
    if (atomic_flag_test_and_set(&ending))
        for (;;)
            pause(); /* (another thread's handler is ending the process) */
    if (atomic_load(&temporary_ready))
        unlink(temporary_path); /* (an unfinished image's: never left behind) */
    if (atomic_load(&lock_ready))
        unlink(lock_path); /* (held by this process until it ends) */
    int tiles = atomic_load(&journal_tiles);
    bool journal = atomic_load(&journal_ready);
    if (atomic_load(&finished)) {
        if (journal)
            unlink(journal_path); /* (a finished render's: of no use) */
        say("csgtrace: ");
        say(signal_words(sig));
        say(" after the render had finished: its files are kept\n");
        _exit(128 + sig);
    }
    say("csgtrace: ");
    say(signal_words(sig));
    say(": the render stopped, ");
    if (journal && tiles > 0) {
        say("no image written; ");
        say_count(tiles);
        say(" finished tiles are kept in ");
        say(journal_path);
        say(": the same command with --resume goes on from them\n");
    } else {
        if (journal)
            unlink(journal_path); /* (nothing in it yet) */
        say("no file written\n");
    }
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

/* The handler for sig, unless it is not always handled and its action now
 * is not the default (SIGNALS). */
static void signals_handle(int sig, bool always)
{
    struct sigaction sa, now;
    if (!always && (sigaction(sig, NULL, &now) != 0 || now.sa_handler != SIG_DFL))
        return;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, NULL);
}

void signals_install(void)
{
#define SIGNAL_HANDLE(id, words, always) signals_handle(id, always);
    SIGNALS(SIGNAL_HANDLE)
#undef SIGNAL_HANDLE
}

void signals_ignore_file_limit(void)
{
    signal(SIGXFSZ, SIG_IGN);
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

/* path into the handler's buffer (cut: none), `ready` set once it is
 * complete, so the handler never sees half a name. */
static void signals_name(atomic_int *ready, char *buf, size_t size, const char *path)
{
    atomic_store(ready, 0);
    if (path && strlen(path) < size) {
        memcpy(buf, path, strlen(path) + 1);
        atomic_store(ready, 1);
    }
}

void signals_finished(void)
{
    atomic_store(&finished, 1);
}

void signals_journal(const char *path, int tiles)
{
    atomic_store(&journal_ready, 0);
    atomic_store(&journal_tiles, tiles);
    signals_name(&journal_ready, journal_path, sizeof journal_path, path);
}

void signals_journal_tiles(int tiles)
{
    atomic_store(&journal_tiles, tiles);
}

void signals_temporary(const char *path)
{
    signals_name(&temporary_ready, temporary_path, sizeof temporary_path, path);
}

void signals_lock(const char *path)
{
    signals_name(&lock_ready, lock_path, sizeof lock_path, path);
}
