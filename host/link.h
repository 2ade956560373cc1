/*
 * link.h — the message link between the master (rank 0) and the workers:
 * the one module that talks to MPI (only link.c includes mpi.h).
 *
 * Everything the tile protocol (protocol.h) needs and nothing more: start
 * MPI when launched by mpirun, send one message, wait for and receive one
 * message of a bounded size, broadcast the scene in chunks.  Without mpirun
 * none of it is ever called and MPI is never initialised.
 *
 * Errors return: MPI's error handler is set to return codes, so a call
 * that fails reports LINK_ERROR to its caller instead of killing the job.
 */
#ifndef HOST_LINK_H
#define HOST_LINK_H

#include <stdbool.h>
#include <stddef.h>

enum { LINK_MASTER = 0, LINK_ANY_SOURCE = -1 };

/* True when the process was started by mpirun (Open MPI's
 * OMPI_COMM_WORLD_SIZE, or PMI_SIZE / PMIX_RANK of other launchers). */
bool link_launched_by_mpirun(void);

/* MPI_Init once per process (MPI_Finalize then runs at exit, so that a
 * program may render several times in one job); this rank and the number
 * of ranks.  false when MPI cannot start. */
bool link_start(int *rank, int *size);

typedef enum {
    LINK_OK = 0,
    LINK_TOO_BIG, /* the message exceeds the limit: NOT received (source,
                     tag and len say what it is); it stays at the head
                     of the queue, so the job can only end: report it,
                     then link_abort                                    */
    LINK_ERROR    /* MPI failed                                        */
} link_status;

/* A received message; data is malloc'd and grows to the limit asked for,
 * never to what a sender claims. */
typedef struct {
    char *data;
    size_t cap;
    size_t len;  /* bytes of the last message */
    int source;
    int tag;
} link_msg;

/* Waits for the next message from `source` (a rank or LINK_ANY_SOURCE) and
 * receives it if it holds at most `limit` bytes.  Out of memory for it, the
 * job is aborted (exit 1, one message): MPI can only take a message whole.  The wait polls, then
 * naps with a short back-off, rather than spinning in MPI: the ranks may
 * outnumber the cores, and the OpenCL pass needs them. */
link_status link_recv(link_msg *m, int source, size_t limit);
void link_msg_free(link_msg *m);

/* One message of `len` bytes to `dest`. */
link_status link_send(int dest, int tag, const void *data, size_t len);

/* MPI_Bcast of `size` bytes from the master, in chunks (no int overflow,
 * and a rank short of memory can still take part: data NULL receives into
 * a sink). */
link_status link_bcast(void *data, size_t size);

/* Ends every rank of the job with `code` (a rank that cannot go on). */
void link_abort(int code);

#endif
