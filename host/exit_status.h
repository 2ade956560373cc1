/*
 * exit_status.h — the program's exit statuses (docs/architecture.md): what
 * every command returns, and what every MPI rank of a render ends with.
 */
#ifndef HOST_EXIT_STATUS_H
#define HOST_EXIT_STATUS_H

enum {
    EXIT_OK = 0,          /* success                                       */
    EXIT_FAILURE_RUN = 1, /* any other failure (a worker, a file, memory)   */
    EXIT_BAD_INPUT = 2    /* bad input: the scene or the arguments, with one
                             line `file:line:col: error: ...`            */
};

#endif
