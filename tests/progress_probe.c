/*
 * progress_probe.c — who must make MPI progress for a large message to
 * arrive (tests/e2e_progress.sh).  Two ranks:
 *
 *   mpirun -np 2 build/tests/progress_probe progress|none BYTES COMPUTE_MS
 *
 * Rank 1 sends BYTES to rank 0 in the background (link_isend, as a
 * worker sends its answer), then computes for COMPUTE_MS, calling
 * link_progress every millisecond ("progress", as a worker's tile runner
 * does between bands) or never ("none"), then waits for its send.  Rank 0
 * receives it (link_recv, as the master does) and prints the milliseconds
 * from the start until its last byte was in: "received MS".  Over Open
 * MPI's eager limit without single-copy support, the message is done
 * while rank 1 computes only when rank 1 makes progress.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mpi.h>

#include "../comm/mpi_link.h"

static double probe_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* Busy for `ms` milliseconds, calling link_progress every millisecond
 * when asked. */
static void probe_compute(double ms, int progress)
{
    double end = probe_ms() + ms, next = probe_ms() + 1;
    volatile double x = 1;
    while (probe_ms() < end) {
        x = x * 1.0000001 + 1e-9; /* (work, not a sleep: no call into MPI) */
        if (progress && probe_ms() >= next) {
            link_progress();
            next += 1;
        }
    }
}

int main(int argc, char **argv)
{
    int rank = 0, size = 1;
    if (argc != 4 || !link_start(&rank, &size) || size != 2) {
        fprintf(stderr, "usage: mpirun -np 2 progress_probe progress|none BYTES COMPUTE_MS\n");
        return 2;
    }
    int progress = strcmp(argv[1], "progress") == 0;
    size_t bytes = (size_t)atol(argv[2]);
    double compute = atof(argv[3]);
    MPI_Barrier(MPI_COMM_WORLD);
    double t0 = probe_ms();
    if (rank == 1) {
        char *data = malloc(bytes);
        memset(data, 7, bytes);
        link_req req;
        link_isend(0, 1, data, bytes, &req);
        probe_compute(compute, progress);
        link_req_wait(&req);
        free(data);
    } else {
        link_msg m = {NULL, 0, 0, 0, 0};
        link_status got = link_recv(&m, 1, bytes);
        printf("received %.1f ms (%zu bytes, status %d)\n", probe_ms() - t0, m.len, (int)got);
        link_msg_free(&m);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    return 0;
}
