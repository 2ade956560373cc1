/*
 * deadline.h — "ns nanoseconds from now" on CLOCK_MONOTONIC, the clock of
 * every timed wait of rank 0's threads (the master's naps, the journal's
 * writer, the store thread).
 */
#ifndef COMM_DEADLINE_H
#define COMM_DEADLINE_H

#include <time.h>

static inline struct timespec deadline_after_ns(long ns)
{
    struct timespec until;
    clock_gettime(CLOCK_MONOTONIC, &until);
    until.tv_sec += ns / 1000000000L;
    until.tv_nsec += ns % 1000000000L;
    if (until.tv_nsec >= 1000000000L) {
        until.tv_sec++;
        until.tv_nsec -= 1000000000L;
    }
    return until;
}

#endif
