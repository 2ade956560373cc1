/*
 * worker.h — ranks 1 .. K-1: the worker side of the tile protocol
 * (host/protocol.h).  A worker needs nothing from the command line: the scene,
 * the tile size and the work come from the master.
 */
#ifndef WORKERS_WORKER_H
#define WORKERS_WORKER_H

/* Runs the worker loop of rank `rank` (MPI already started) until the
 * master's STOP; returns the exit status the master decided (0, 1, 2).
 *
 * Test hook: CSGTRACE_FAIL_WORKER=<rank> in the environment makes that
 * worker answer its first tile with a FAIL ("injected failure").
 * CSGTRACE_TEST_FLOAT_PARTS=1 makes every worker asked for 8-bit results
 * send every other part as floats, as it does for a part holding a value
 * without a byte of its own (host/pixels.h): the master's way with such
 * parts, tested (tests/e2e_bytes.sh). */
int worker_run(int rank);

#endif
