/*
 * worker.h — ranks 1 .. K-1: the worker side of the tile protocol
 * (comm/protocol.h).  A worker needs nothing from the command line: the scene,
 * the tile size and the work come from the master.
 */
#ifndef WORKERS_WORKER_H
#define WORKERS_WORKER_H
#include <stdint.h>

/* Runs the worker loop of rank `rank` (MPI already started) until the
 * master's STOP; returns the exit status the master decided (0, 1, 2).
 * `bind`: $CSGTRACE_WORKER_BIND (comm/mpi_link.h: link_bind_worker);
 * `page_trace`: $CSGTRACE_PAGE_TRACE (pager.h: pager_trace_open), or NULL.
 *
 * Test hook (comm/test_hooks.h): CSGTRACE_TEST_FAIL_WORKER=<rank> makes
 * that worker answer its first tile with a FAIL ("injected failure"). */
int worker_run(int rank, const char *bind, const char *page_trace);
/* The simulated build: what answering another worker's page ask costs
 * this one (its bytes packed), charged to its simulated host. */
void worker_set_serve_cost(void (*charge)(uint64_t bytes));

#endif
