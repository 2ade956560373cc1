/*
 * link.c — the MPI side of link.h, written once for the master and the
 * workers.
 *
 * Waiting: MPI_Iprobe in a loop, LINK_SPINS times at once, then with naps
 * that double up to LINK_NAP_MAX_NS.  A blocked MPI_Probe would spin on a
 * core for as long as the peer is busy — a core the other ranks (more
 * ranks than cores) or the OpenCL pass need; the nap is small next to a
 * tile's work.
 *
 * Bounded receive: the size is known from the probe before any byte is
 * taken, and a message over the caller's limit is not received at all, so
 * a peer can never make this rank allocate what it claims.  It cannot be
 * drained either: a truncated receive is no way out (Open MPI 4.1's
 * shared-memory single copy writes the whole message past the end of the
 * smaller buffer: seen here, heap corruption), so the caller reports it
 * and ends the job (link_abort).
 */
#include "link.h"

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define LINK_SPINS 200
#define LINK_NAP_MAX_NS 200000L
#define LINK_BCAST_CHUNK 65536

bool link_launched_by_mpirun(void)
{
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMI_SIZE") || getenv("PMIX_RANK");
}

static void link_finalize_at_exit(void)
{
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized)
        MPI_Finalize();
}

bool link_start(int *rank, int *size)
{
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
        if (MPI_Init(NULL, NULL) != MPI_SUCCESS)
            return false;
        atexit(link_finalize_at_exit);
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    }
    return MPI_Comm_rank(MPI_COMM_WORLD, rank) == MPI_SUCCESS &&
           MPI_Comm_size(MPI_COMM_WORLD, size) == MPI_SUCCESS;
}

static link_status link_wait(int source, MPI_Status *st)
{
    long nap = 1000;
    for (int spins = 0;; spins++) {
        int flag = 0;
        if (MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, st) != MPI_SUCCESS)
            return LINK_ERROR;
        if (flag)
            return LINK_OK;
        if (spins < LINK_SPINS)
            continue;
        struct timespec ts = {0, nap};
        nanosleep(&ts, NULL);
        nap = nap * 2 < LINK_NAP_MAX_NS ? nap * 2 : LINK_NAP_MAX_NS;
    }
}

/* m->data holds at least `need` bytes (+1 for a terminating NUL). */
static bool link_reserve(link_msg *m, size_t need)
{
    if (need + 1 <= m->cap)
        return true;
    char *p = realloc(m->data, need + 1);
    if (!p)
        return false;
    m->data = p;
    m->cap = need + 1;
    return true;
}

link_status link_recv(link_msg *m, int source, size_t limit)
{
    MPI_Status st;
    int count = 0;
    if (link_wait(source == LINK_ANY_SOURCE ? MPI_ANY_SOURCE : source, &st) != LINK_OK ||
        MPI_Get_count(&st, MPI_BYTE, &count) != MPI_SUCCESS || count < 0)
        return LINK_ERROR;
    m->len = (size_t)count;
    m->source = st.MPI_SOURCE;
    m->tag = st.MPI_TAG;
    if ((size_t)count > limit)
        return LINK_TOO_BIG; /* left where it is: see link.h */
    if (!link_reserve(m, (size_t)count)) {
        /* A message can only be received whole: nothing else to do. */
        int rank = -1;
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        fprintf(stderr, "csgtrace: error: rank %d: out of memory for a %d-byte message\n", rank,
                count);
        link_abort(1);
    }
    if (MPI_Recv(m->data, count, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE) != MPI_SUCCESS)
        return LINK_ERROR;
    m->data[count] = '\0';
    return LINK_OK;
}

void link_msg_free(link_msg *m)
{
    free(m->data);
    memset(m, 0, sizeof *m);
}

link_status link_send(int dest, int tag, const void *data, size_t len)
{
    return MPI_Send(data, (int)len, MPI_BYTE, dest, tag, MPI_COMM_WORLD) == MPI_SUCCESS
               ? LINK_OK
               : LINK_ERROR;
}

link_status link_bcast(void *data, size_t size)
{
    char sink[LINK_BCAST_CHUNK]; /* where a rank without memory receives */
    link_status status = LINK_OK;
    for (size_t off = 0; off < size; off += LINK_BCAST_CHUNK) {
        size_t n = size - off < LINK_BCAST_CHUNK ? size - off : LINK_BCAST_CHUNK;
        if (MPI_Bcast(data ? (char *)data + off : sink, (int)n, MPI_BYTE, LINK_MASTER,
                      MPI_COMM_WORLD) != MPI_SUCCESS)
            status = LINK_ERROR; /* every chunk still goes: the others wait for it */
    }
    return status;
}

void link_abort(int code)
{
    MPI_Abort(MPI_COMM_WORLD, code);
}
