/*
 * link.c — the MPI side of link.h, written once for the master and the
 * workers.
 *
 * Waiting (link_idle): the caller polls, LINK_SPINS times at once, then
 * with naps that double up to a cap (LINK_NAP_MAX_NS for a blocking
 * receive; an event loop sets its own).  A blocked MPI_Probe would spin on
 * a core for as long as the peer is busy — a core the other ranks (more
 * ranks than cores) or the OpenCL pass need; the nap is small next to a
 * tile's work.  A nap is a wait on a semaphore with a deadline
 * (sem_clockwait on CLOCK_MONOTONIC), so link_wake ends it at once.
 *
 * Sending in the background (link_isend): a message over the transport's
 * eager limit (a tile's hit records, a tile's pixels) is only delivered
 * once the receiver takes it; MPI_Send would hold the sender that long, so
 * the master and the workers use MPI_Isend and test the request later.
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

#include <errno.h>
#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#define LINK_SPINS 200
#define LINK_NAP_MIN_NS 1000L
#define LINK_SLICE_NS 100000ULL /* the shortest slice Linux grants a fair task */
#define LINK_BCAST_CHUNK 65536

_Static_assert(sizeof(MPI_Request) <= sizeof(((link_req *)0)->impl),
               "link_req must hold an MPI_Request");

bool link_launched_by_mpirun(void)
{
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMI_SIZE") || getenv("PMIX_RANK");
}

void link_finish(void)
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
        atexit(link_finish);
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    }
    return MPI_Comm_rank(MPI_COMM_WORLD, rank) == MPI_SUCCESS &&
           MPI_Comm_size(MPI_COMM_WORLD, size) == MPI_SUCCESS;
}

/* ---- the idle wait ------------------------------------------------------ */

bool link_idle_init(link_idle *w, long nap_max_ns, int spin_steps)
{
    memset(w, 0, sizeof *w);
    w->nap_max_ns = nap_max_ns;
    w->spin_steps = spin_steps;
    w->ready = sem_init(&w->wake, 0, 0) == 0;
    link_idle_reset(w);
    return w->ready;
}

void link_idle_free(link_idle *w)
{
    if (w->ready)
        sem_destroy(&w->wake);
    w->ready = false;
}

void link_idle_reset(link_idle *w)
{
    w->spins = w->spin_steps;
    w->nap_ns = LINK_NAP_MIN_NS;
}

void link_wake(link_idle *w)
{
    if (w->ready)
        sem_post(&w->wake);
}

/* Takes every pending wake-up; true if there was one. */
static bool link_idle_woken(link_idle *w)
{
    bool woken = false;
    while (w->ready && sem_trywait(&w->wake) == 0)
        woken = true;
    return woken;
}

void link_idle_step(link_idle *w)
{
    if (link_idle_woken(w)) {
        link_idle_reset(w); /* something happened: poll again at once */
        return;
    }
    if (w->spins > 0) {
        w->spins--;
        return;
    }
    long nap = w->nap_ns < w->nap_max_ns ? w->nap_ns : w->nap_max_ns;
    if (w->ready) {
        struct timespec until;
        clock_gettime(CLOCK_MONOTONIC, &until);
        until.tv_nsec += nap;
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        int rc;
        while ((rc = sem_clockwait(&w->wake, CLOCK_MONOTONIC, &until)) != 0 && errno == EINTR)
            continue;
        if (rc == 0) {
            link_idle_woken(w);
            link_idle_reset(w);
            return;
        }
    } else {
        struct timespec ts = {0, nap};
        nanosleep(&ts, NULL);
    }
    w->nap_ns = nap * 2 < w->nap_max_ns ? nap * 2 : w->nap_max_ns;
}

/* ---- the scheduler slice -------------------------------------------------- */

/* The kernel's struct sched_attr, first version (48 bytes): glibc has no
 * wrapper, and <linux/sched/types.h> clashes with <sched.h>. */
typedef struct {
    uint32_t size, sched_policy;
    uint64_t sched_flags;
    int32_t sched_nice;
    uint32_t sched_priority;
    uint64_t sched_runtime, sched_deadline, sched_period;
} link_sched_attr;

void link_respond_quickly(void)
{
#ifdef SYS_sched_setattr
    link_sched_attr a;
    memset(&a, 0, sizeof a);
    a.size = sizeof a;
    a.sched_policy = 0; /* SCHED_OTHER */
    a.sched_nice = getpriority(PRIO_PROCESS, 0);
    a.sched_runtime = LINK_SLICE_NS;
    syscall(SYS_sched_setattr, 0, &a, 0); /* older kernels: no such slice, no harm */
#endif
}

/* ---- receiving ------------------------------------------------------------ */

static link_status link_wait(int source, MPI_Status *st)
{
    link_idle w;
    link_status status = LINK_OK;
    link_idle_init(&w, LINK_NAP_MAX_NS, LINK_SPINS);
    for (;;) {
        int flag = 0;
        if (MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, st) != MPI_SUCCESS) {
            status = LINK_ERROR;
            break;
        }
        if (flag)
            break;
        link_idle_step(&w);
    }
    link_idle_free(&w);
    return status;
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

/* Receives the message `st` describes (probed, not yet taken). */
static link_status link_take(link_msg *m, const MPI_Status *st, size_t limit)
{
    int count = 0;
    if (MPI_Get_count(st, MPI_BYTE, &count) != MPI_SUCCESS || count < 0)
        return LINK_ERROR;
    m->len = (size_t)count;
    m->source = st->MPI_SOURCE;
    m->tag = st->MPI_TAG;
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
    if (MPI_Recv(m->data, count, MPI_BYTE, st->MPI_SOURCE, st->MPI_TAG, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE) != MPI_SUCCESS)
        return LINK_ERROR;
    m->data[count] = '\0';
    return LINK_OK;
}

static int link_source(int source)
{
    return source == LINK_ANY_SOURCE ? MPI_ANY_SOURCE : source;
}

link_status link_recv(link_msg *m, int source, size_t limit)
{
    MPI_Status st;
    if (link_wait(link_source(source), &st) != LINK_OK)
        return LINK_ERROR;
    return link_take(m, &st, limit);
}

link_status link_try_recv(link_msg *m, int source, size_t limit)
{
    MPI_Status st;
    int flag = 0;
    if (MPI_Iprobe(link_source(source), MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st) != MPI_SUCCESS)
        return LINK_ERROR;
    return flag ? link_take(m, &st, limit) : LINK_NONE;
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

/* ---- sending in the background ---------------------------------------------- */

static MPI_Request *link_req_mpi(link_req *req)
{
    return (MPI_Request *)(void *)req->impl.bytes;
}

link_status link_isend(int dest, int tag, const void *data, size_t len, link_req *req)
{
    req->active = false;
    if (MPI_Isend(data, (int)len, MPI_BYTE, dest, tag, MPI_COMM_WORLD, link_req_mpi(req)) !=
        MPI_SUCCESS)
        return LINK_ERROR;
    req->active = true;
    return LINK_OK;
}

bool link_req_done(link_req *req)
{
    int flag = 1;
    if (!req->active)
        return true;
    if (MPI_Test(link_req_mpi(req), &flag, MPI_STATUS_IGNORE) != MPI_SUCCESS)
        flag = 1; /* an error ends the request too: its bytes are free */
    if (flag)
        req->active = false;
    return flag != 0;
}

link_status link_req_wait(link_req *req)
{
    link_idle w;
    link_idle_init(&w, LINK_NAP_MAX_NS, LINK_SPINS);
    while (!link_req_done(req))
        link_idle_step(&w);
    link_idle_free(&w);
    return LINK_OK;
}

void link_req_abandon(link_req *req)
{
    if (req->active)
        MPI_Request_free(link_req_mpi(req));
    req->active = false;
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
