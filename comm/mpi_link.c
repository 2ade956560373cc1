/*
 * mpi_link.c — the MPI side of mpi_link.h, written once for the master and the
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
 *
 * Liveness (a dead worker does not end the render; Open MPI 4.1 has no
 * ULFM): launched with `mpirun --enable-recovery`, the job outlives a rank
 * that dies, and MPI's error handler returns codes; but a call that waits
 * on a dead peer may never return.  So every worker opens a TCP "watchdog"
 * connection to rank 0 at start (rank 0 listens on any port and
 * broadcasts its host name, the port and a random token; a worker
 * connects and sends the token and its rank).  The kernel closes a socket
 * when its process dies, however it dies, so EOF on rank r's socket means
 * rank r is gone: link_peer_lost, on any transport and host.  Nothing in
 * this module ever waits inside MPI for a peer that may be dead: receives
 * are MPI_Irecv + MPI_Test, sends MPI_Isend + MPI_Test, and a wait gives up
 * (LINK_LOST) once the peer is lost, leaving the request and its buffer to
 * MPI.  The other way round, a worker's watchdog thread blocks on its
 * socket: EOF means the master is gone (or wrote it off: link_forget), and
 * the worker exits at once, so no rank outlives its master.
 *
 * Under --enable-recovery mpirun exits 0 whatever the ranks return (tried
 * here, also with orte_abort_on_non_zero_status, also after MPI_Abort): a
 * rank whose job failed SIGTERMs its parent when that is mpirun, which
 * then ends the job and exits 1 (link_exit_status, link_fail_job).
 * MPI_Finalize with a dead rank hangs about a third of the time unless
 * Open MPI finalizes asynchronously (OMPI_MCA_async_mpi_finalize, set
 * before MPI_Init unless the user set it).
 */
#include "mpi_link.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <mpi.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/random.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include "deadline.h"
#include "test_hooks.h"

#define LINK_SPINS 200
#define LINK_NAP_MIN_NS 1000L
#define LINK_SLICE_NS 100000ULL /* the shortest slice Linux grants a fair task */
#define LINK_BCAST_CHUNK 65536
#define LINK_ACCEPT_S 10     /* how long rank 0 waits for the watchdogs   */
#define LINK_END_GRACE_S 5   /* a stopping worker's time to exit alone    */
#define LINK_BYE_QUIET 'q'   /* the last byte to a watchdog: see there  */
#define LINK_BYE_EXIT 'e' /* the master exits in order */

_Static_assert(sizeof(MPI_Request) <= sizeof(((link_req *)0)->impl),
               "link_req must hold an MPI_Request");

static bool link_model_legacy(void); /* (the protocol model: see there) */
static void link_page_serve_turn(void); /* (pages: see there) */

/* Pages of the scene: see link_page_fetch below. */
#define LINK_TAG_PAGE_ASK 32001
#define LINK_TAG_PAGE 32002
#define LINK_PAGE_NAP_NS 10000L /* a worker waiting for a page naps at most this */
#define LINK_PAGE_SERVE_NAP_NS 50000L /* a home (link_page_server) naps at most this */
#define LINK_PAGE_SENDS 64 /* answers in flight at once (one a worker at most) */

/* --page-home spread: this worker's answers to the others (link_page_server). */
static struct {
    link_page_pack pack;
    void (*poll)(void *arg);
    void *arg;
    bool serving;  /* (within it: no second turn from its own sends' waits) */
    bool held;     /* its own pages asked of rank 0 (link_page_fetch): no
                      answers until they are in (and installed), or it
                      would fetch them again to answer */
    bool *suspect; /* a home asked no more (LINK_PAGE_HOME_WAIT_NS), by rank */
    uint64_t rerouted; /* asks sent to rank 0 instead (link_page_rerouted) */
} link_server;


bool link_launched_by_mpirun(void)
{
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMI_SIZE") || getenv("PMIX_RANK");
}

/* ---- liveness: the watchdog sockets ------------------------------------------ */

/* What rank 0 broadcasts: where to connect, and the token to show. */
typedef struct {
    char host[256];
    int32_t port;      /* 0: no watchdog (rank 0 could not listen)       */
    int32_t pad;
    uint64_t token;
} link_watch_addr;

/* What a worker sends first on its watchdog connection. */
typedef struct {
    uint64_t token;    /* link_watch_addr.token: the job's, not a stranger's */
    int32_t rank;
    int32_t pid;       /* its process id (link_kill_stopped)              */
} link_watch_hello;

/* The one liveness state of this process (MPI's own state is per process
 * too): rank 0 holds a socket per worker, a worker its socket to rank 0. */
static struct {
    int rank, size;
    int *fd;              /* rank 0: [r] rank r's socket, -1: none/lost */
    int *pid;             /* rank 0: [r] rank r's process id, as it said */
    bool *gone;           /* rank 0: [r] rank r was lost or written off
                             (link_peer_lost stays true for it)          */
    bool watched;         /* every rank: the watchdogs are up            */
    int master_fd;        /* a worker: its socket to rank 0             */
    atomic_int ending;    /* a worker: STOP came (its status + 1), or the
                             process exits (-1)                          */
    int status;           /* rank 0: the job's status (link_exit_status) */
    MPI_Comm bcast_comm;  /* the scene's chunks sent as messages (under
                             --enable-recovery: link_bcast) apart from
                             the protocol's, which are matched eagerly  */
    /* One copy of the scene per node (link_scene_*): */
    bool node_share;      /* on: the ranks of a node are found and their
                             leaders have a communicator of their own   */
    MPI_Comm leaders;     /* the node leaders (a node's lowest rank; rank
                             0 is the first), MPI_COMM_NULL elsewhere   */
    int node_rank;        /* this rank's place on its node (0: leader)  */
    int node_size;        /* ranks on this node                          */
    int *node_ranks;      /* their MPI_COMM_WORLD ranks, leader first    */
    int *leader_ranks;    /* a leader: every leader's MPI_COMM_WORLD rank */
    int leader_count;     /* (the master's first)                         */
    int *leader_of;       /* [r]: rank r's node leader (every rank's)     */
    double link_bps;      /* rank 0: bytes a second to another node, as
                             measured at start (link_probe); 0: none    */
} link_w = {0, 1, NULL, NULL, NULL, false, -1, 0, 0, MPI_COMM_NULL, false, MPI_COMM_NULL, 0, 1,
            NULL, NULL, 0, NULL, 0.0};

static int link_listen(link_watch_addr *a)
{
    struct sockaddr_in sa = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_ANY)};
    socklen_t len = sizeof sa;
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0 || bind(fd, (struct sockaddr *)&sa, sizeof sa) != 0 || listen(fd, 1024) != 0 ||
        getsockname(fd, (struct sockaddr *)&sa, &len) != 0 ||
        gethostname(a->host, sizeof a->host - 1) != 0 ||
        getrandom(&a->token, sizeof a->token, 0) != (ssize_t)sizeof a->token) {
        if (fd >= 0)
            close(fd);
        a->port = 0;
        return -1;
    }
    a->port = ntohs(sa.sin_port);
    return fd;
}

/* One connection: its token and rank, checked; false to close it. */
static bool link_greet_watch(int c, uint64_t token)
{
    link_watch_hello hello;
    struct pollfd p = {c, POLLIN, 0};
    if (poll(&p, 1, 1000) != 1 || recv(c, &hello, sizeof hello, MSG_WAITALL) != sizeof hello)
        return false;
    if (hello.token != token || hello.rank < 1 || hello.rank >= link_w.size ||
        link_w.fd[hello.rank] >= 0)
        return false;
    link_w.fd[hello.rank] = c;
    link_w.pid[hello.rank] = hello.pid;
    return true;
}

/* Rank 0: every worker's connection, for at most LINK_ACCEPT_S (a worker
 * that never connects stays unwatched: only the item timeout sees it). */
static void link_accept_all(int lfd, uint64_t token)
{
    int want = link_w.size - 1;
    time_t until = time(NULL) + LINK_ACCEPT_S;
    while (want > 0 && time(NULL) < until) {
        struct pollfd p = {lfd, POLLIN, 0};
        if (poll(&p, 1, 100) != 1)
            continue;
        int c = accept4(lfd, NULL, NULL, SOCK_CLOEXEC);
        if (c >= 0 && link_greet_watch(c, token))
            want--;
        else if (c >= 0)
            close(c);
    }
}

/* Fails the job as mpirun reports it: under --enable-recovery mpirun
 * exits 0 whatever the ranks return, so the parent, if it is mpirun
 * (on this host), is sent SIGTERM: it ends the job and exits 1. */
void link_fail_job(void)
{
    const char *rec = getenv("OMPI_MCA_orte_enable_recovery");
    char path[64], comm[32] = "";
    if (!rec || strcmp(rec, "1") != 0)
        return; /* mpirun reports the ranks' status itself */
    snprintf(path, sizeof path, "/proc/%d/comm", (int)getppid());
    FILE *f = fopen(path, "r");
    if (f) {
        if (!fgets(comm, sizeof comm, f))
            comm[0] = '\0';
        fclose(f);
    }
    if (strncmp(comm, "mpirun", 6) == 0 || strncmp(comm, "orterun", 7) == 0)
        kill(getppid(), SIGTERM);
}

/* /proc/PID/NAME read into buf (NUL-terminated; empty when it cannot be
 * read); its length. */
static size_t link_proc_read(const char *pid, const char *name, char *buf, size_t size)
{
    char path[64];
    snprintf(path, sizeof path, "/proc/%s/%s", pid, name);
    FILE *f = fopen(path, "r");
    size_t n = f ? fread(buf, 1, size - 1, f) : 0;
    if (f)
        fclose(f);
    buf[n] = '\0';
    return n;
}

/* The fields of /proc/PID/stat after the command's name ("pid (comm)
 * state ppid ..."), in buf; NULL when it cannot be read. */
static const char *link_proc_stat(const char *pid, char *buf, size_t size)
{
    link_proc_read(pid, "stat", buf, size);
    const char *end = strrchr(buf, ')');
    return end ? end + 1 : NULL;
}

/* The MPI rank of process `pid` if it is a child of `parent`, else -1. */
static int link_sibling_rank(const char *pid, pid_t parent)
{
    char buf[4096];
    int rank = -1;
    const char *fields = link_proc_stat(pid, buf, sizeof buf);
    int ppid = -1;
    if (!fields || sscanf(fields, " %*c %d", &ppid) != 1 || ppid != (int)parent)
        return -1;
    size_t n = link_proc_read(pid, "environ", buf, sizeof buf);
    for (size_t i = 0; i < n; i += strlen(buf + i) + 1)
        if (strncmp(buf + i, "OMPI_COMM_WORLD_RANK=", 21) == 0)
            rank = atoi(buf + i + 21);
    return rank; /* (an exited one has no environ left: -1) */
}

/* How many other ranks of this job run under the same parent; *lowest:
 * the lowest of their ranks. */
static int link_siblings(int *lowest)
{
    DIR *d = opendir("/proc");
    struct dirent *e;
    int n = 0;
    *lowest = INT_MAX;
    while (d && (e = readdir(d))) {
        if (e->d_name[0] < '0' || e->d_name[0] > '9' || atoi(e->d_name) == (int)getpid())
            continue;
        int r = link_sibling_rank(e->d_name, getppid());
        if (r >= 0) {
            n++;
            *lowest = r < *lowest ? r : *lowest;
        }
    }
    if (d)
        closedir(d);
    return n;
}

/* A worker whose master is gone: the lowest-ranked worker left waits for
 * the others to exit (mpirun, killed while ranks still run, leaves their
 * shared memory behind), then fails the job (link_fail_job). */
static void link_worker_fail_job(void)
{
    for (int i = 0; i < LINK_END_GRACE_S * 10; i++) {
        int lowest;
        if (link_siblings(&lowest) == 0)
            break;
        if (lowest < link_w.rank)
            return; /* that one will */
        struct timespec ts = {0, 100000000L};
        nanosleep(&ts, NULL);
    }
    link_fail_job();
}

/* A worker's watchdog: blocks on the socket to rank 0, then acts on the
 * last byte before EOF.  LINK_BYE_QUIET: the master goes on without this
 * worker (link_forget), or ends the job (link_abort): exit quietly.  LINK_BYE_EXIT, or a STOP came:
 * the master ended in order: the process gets LINK_END_GRACE_S to end on
 * its own (its STOP may still be on the way).  EOF alone: the master is
 * gone: exit now. */
static void *link_watchdog(void *arg)
{
    char c, last = 0;
    (void)arg;
    while (read(link_w.master_fd, &c, 1) > 0)
        last = c;
    int ending = atomic_load(&link_w.ending);
    if (ending < 0)
        return NULL; /* the process is exiting anyway */
    if (last == LINK_BYE_QUIET)
        _exit(1);
    if (ending > 0 || last == LINK_BYE_EXIT) {
        sleep(LINK_END_GRACE_S);
        _exit(ending > 0 ? ending - 1 : 1);
    }
    fprintf(stderr, "csgtrace: error: worker %d: the master is gone; exiting\n", link_w.rank);
    link_worker_fail_job();
    _exit(1);
}

static void link_watch_connect(const link_watch_addr *a)
{
    struct addrinfo hints = {.ai_family = AF_INET, .ai_socktype = SOCK_STREAM}, *ai = NULL;
    char port[16];
    link_watch_hello hello = {a->token, link_w.rank, (int32_t)getpid()};
    snprintf(port, sizeof port, "%d", (int)a->port);
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0 || getaddrinfo(a->host, port, &hints, &ai) != 0 ||
        connect(fd, ai->ai_addr, ai->ai_addrlen) != 0 ||
        send(fd, &hello, sizeof hello, MSG_NOSIGNAL) != (ssize_t)sizeof hello) {
        if (fd >= 0)
            close(fd); /* unwatched: the master may still time it out */
        fd = -1;
    }
    if (ai)
        freeaddrinfo(ai);
    link_w.master_fd = fd;
    pthread_t th;
    if (fd >= 0 && pthread_create(&th, NULL, link_watchdog, NULL) == 0)
        pthread_detach(th);
}

/* The ranks are threads of one process (link_ranks_are_threads): there is
 * no process to watch, no watchdog socket, no CPU of a rank's own. */
static bool link_threads;

void link_ranks_are_threads(void)
{
    link_threads = true;
}

/* Rank 0 watches its parent, mpirun (or the local daemon): when it dies
 * (kill -9 of mpirun), nothing else tells this process, which would go on
 * rendering, unseen, for as long as the render lasts.  It is sent SIGTERM
 * instead: the render stops as if the user had stopped it (host/signals.h:
 * the journal kept, one line), and the workers follow it (their
 * watchdogs).  A poll, not PR_SET_PDEATHSIG: that fires when the parent's
 * forking *thread* ends, which need not be the parent's end. */
#define LINK_PARENT_POLL_NS 250000000L

static void *link_parent_watch(void *arg)
{
    pid_t parent = (pid_t)(intptr_t)arg;
    struct timespec nap = {0, LINK_PARENT_POLL_NS};
    while (getppid() == parent)
        nanosleep(&nap, NULL);
    kill(getpid(), SIGTERM);
    return NULL;
}

static void link_parent_watch_start(void)
{
    pthread_t th;
    if (!link_threads &&
        pthread_create(&th, NULL, link_parent_watch, (void *)(intptr_t)getppid()) == 0)
        pthread_detach(th);
}

/* Every rank, once after MPI_Init: the watchdog sockets set up. */
static void link_watch_start(void)
{
    link_watch_addr a;
    int lfd = -1;
    memset(&a, 0, sizeof a);
    if (link_w.rank == 0) {
        link_w.fd = malloc((size_t)link_w.size * sizeof *link_w.fd);
        link_w.gone = calloc((size_t)link_w.size, sizeof *link_w.gone);
        link_w.pid = calloc((size_t)link_w.size, sizeof *link_w.pid);
        if (!link_w.gone || !link_w.pid) {
            free(link_w.fd);
            link_w.fd = NULL;
        }
        for (int r = 0; link_w.fd && r < link_w.size; r++)
            link_w.fd[r] = -1;
        if (link_w.fd && link_w.size > 1 && !link_threads)
            lfd = link_listen(&a);
    }
    if (MPI_Bcast(&a, sizeof a, MPI_BYTE, 0, MPI_COMM_WORLD) != MPI_SUCCESS || a.port == 0)
        return;
    link_w.watched = true;
    if (link_w.rank != 0)
        link_watch_connect(&a);
    else
        link_accept_all(lfd, a.token);
    if (lfd >= 0)
        close(lfd);
}

bool link_peer_gone_before(int rank)
{
    return link_w.gone && rank >= 1 && rank < link_w.size && link_w.gone[rank];
}

bool link_peer_lost(int rank)
{
    if (!link_w.fd || rank < 1 || rank >= link_w.size)
        return false;
    if (link_w.gone[rank])
        return true;
    if (link_w.fd[rank] < 0)
        return false;
    struct pollfd p = {link_w.fd[rank], POLLIN, 0};
    char c;
    if (poll(&p, 1, 0) <= 0 || recv(p.fd, &c, 1, MSG_DONTWAIT) > 0)
        return false; /* (a worker never writes after its hello) */
    link_forget(rank);
    return true;
}

/* One byte to rank r's watchdog before its socket closes (link_watchdog). */
static void link_bye(int rank, char why)
{
    send(link_w.fd[rank], &why, 1, MSG_NOSIGNAL | MSG_DONTWAIT);
}

/* Is process `pid` stopped (SIGSTOP, SIGTSTP, a debugger)?  Its state in
 * /proc/PID/stat: 'T' or 't'. */
static bool link_process_stopped(int pid)
{
    char id[24], buf[512];
    snprintf(id, sizeof id, "%d", pid);
    const char *fields = link_proc_stat(id, buf, sizeof buf);
    char state = 0;
    return fields && sscanf(fields, " %c", &state) == 1 && (state == 'T' || state == 't');
}

/* A worker written off that is stopped cannot exit by its watchdog, and
 * mpirun waits for it for ever: the master SIGKILLs it, when it is a
 * process of this host (a child of the master's own parent, mpirun, that
 * says it is rank r: never a stranger with a reused id).  On another host
 * nothing reaches it: mpirun waits until it is continued or killed
 * there. */
static void link_kill_stopped(int rank)
{
    char pid[16];
    if (link_threads || link_w.pid[rank] <= 0)
        return;
    snprintf(pid, sizeof pid, "%d", link_w.pid[rank]);
    if (link_process_stopped(link_w.pid[rank]) && link_sibling_rank(pid, getppid()) == rank)
        kill(link_w.pid[rank], SIGKILL);
}

void link_forget(int rank)
{
    if (!link_w.fd || rank < 1 || rank >= link_w.size || link_w.fd[rank] < 0)
        return;
    link_bye(rank, LINK_BYE_QUIET);
    close(link_w.fd[rank]); /* the worker's watchdog sees EOF and exits */
    link_w.fd[rank] = -1;
    link_w.gone[rank] = true;
    link_kill_stopped(rank); /* (unless it cannot: stopped) */
}

void link_ending(int status)
{
    atomic_store(&link_w.ending, status < 0 ? 0 : status + 1);
}

void link_exit_status(int status)
{
    if (status != 0) /* the first failure of the job stands */
        link_w.status = link_w.status ? link_w.status : status;
}

/* MPI_Finalize once (at exit, or sooner: link_finish), after telling every
 * watched worker goodbye; a failed job fails mpirun too (link_fail_job). */
void link_finish(void)
{
    int finalized = 0;
    atomic_store(&link_w.ending, -1); /* the master's EOF is expected now */
    for (int r = 1; link_w.fd && r < link_w.size; r++)
        if (link_w.fd[r] >= 0)
            link_bye(r, LINK_BYE_EXIT); /* (a STOP may still be on its way) */
    MPI_Finalized(&finalized);
    if (!finalized)
        MPI_Finalize();
    if (link_w.rank == 0 && link_w.status != 0)
        link_fail_job();
}

static void link_node_start(void); /* (the scene's sharing: below) */
static void link_probe(void);

bool link_start(int *rank, int *size)
{
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) {
        setenv("OMPI_MCA_async_mpi_finalize", "1", 0); /* (the header) */
        if (MPI_Init(NULL, NULL) != MPI_SUCCESS)
            return false;
        atexit(link_finish);
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
        if (MPI_Comm_rank(MPI_COMM_WORLD, &link_w.rank) != MPI_SUCCESS ||
            MPI_Comm_size(MPI_COMM_WORLD, &link_w.size) != MPI_SUCCESS ||
            MPI_Comm_dup(MPI_COMM_WORLD, &link_w.bcast_comm) != MPI_SUCCESS)
            return false;
        MPI_Comm_set_errhandler(link_w.bcast_comm, MPI_ERRORS_RETURN);
        /* A nap's deadline is late by the timer slack, 50 us by default:
         * more than most naps, and more than a cheap tile, which a worker
         * then waits out for its next TILE (1 worker, 384x384, tile 16:
         * 41 -> 21 us between tiles, the tile phase -9 %).  Threads
         * started later (PoCL's) inherit it. */
        prctl(PR_SET_TIMERSLACK, (unsigned long)LINK_NAP_MIN_NS);
        link_watch_start();
        link_node_start();
        if (link_w.rank == 0)
            link_parent_watch_start();
    }
    *rank = link_w.rank;
    *size = link_w.size;
    return true;
}

/* ---- where a worker runs ------------------------------------------------- */

int link_worker_cpu(const char *setting, const char *binding, const char *local_rank,
                    const char *local_size, const cpu_set_t *allowed)
{
    if ((setting && strcmp(setting, "off") == 0) || !binding || strcmp(binding, "none") != 0 ||
        !local_rank || !local_size)
        return -1;
    int cpus = CPU_COUNT(allowed), at = atoi(local_rank);
    if (cpus < 2 || atoi(local_size) <= cpus || at < 0)
        return -1; /* (a core for every rank: the OS spreads them) */
    int nth = at % cpus;
    for (int cpu = 0; cpu < CPU_SETSIZE; cpu++)
        if (CPU_ISSET(cpu, allowed) && nth-- == 0)
            return cpu;
    return -1;
}

int link_bind_worker(const char *setting)
{
    cpu_set_t allowed, one;
    if (link_threads || sched_getaffinity(0, sizeof allowed, &allowed) != 0)
        return -1;
    int cpu = link_worker_cpu(setting,
                              getenv("OMPI_MCA_hwloc_base_binding_policy"),
                              getenv("OMPI_COMM_WORLD_LOCAL_RANK"),
                              getenv("OMPI_COMM_WORLD_LOCAL_SIZE"), &allowed);
    CPU_ZERO(&one);
    if (cpu >= 0)
        CPU_SET(cpu, &one);
    return cpu >= 0 && sched_setaffinity(0, sizeof one, &one) == 0 ? cpu : -1;
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
    link_page_serve_turn(); /* (a home answers whenever it waits) */
    if (link_idle_woken(w)) {
        link_idle_reset(w); /* something happened: poll again at once */
        return;
    }
    if (w->spins > 0) {
        w->spins--;
        return;
    }
    long nap = w->nap_ns < w->nap_max_ns ? w->nap_ns : w->nap_max_ns;
    if (link_server.pack && nap > LINK_PAGE_SERVE_NAP_NS)
        nap = LINK_PAGE_SERVE_NAP_NS; /* (another worker's ray may wait on this one) */
    if (link_receiving() && !link_model_legacy()) /* bytes on their way: a yield */
        nap = LINK_NAP_MIN_NS;
    if (w->ready) {
        struct timespec until = deadline_after_ns(nap);
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

/* ---- Open MPI's large-message protocol, modelled (the simulated build) --------- */

/* SMPI moves a message whatever its ranks do meanwhile; Open MPI moves a
 * message over its eager limit only while both ranks call into MPI (ob1's
 * rendezvous: the first fragment is matched by the receiver, which
 * answers; the sender sends the rest when it next makes progress).  With
 * link_model_protocol that is played here, for the simulation to show
 * what the node showed (bench/SCALE.md, "The protocol modelled"): a large
 * message is an RTS on the protocol's communicator, a clear-to-send on a
 * communicator of the model's own when the receiver matches it
 * (link_in_post), and the payload, sent by the sender's next call into
 * this module after that (link_model_step). */
#define LINK_TAG_RTS 32001     /* (above protocol.h's tags)            */
#define LINK_TAG_CTS 32002
#define LINK_MODEL_TAGS 0xFFFFF /* a payload's tag: its number, modulo */

/* What a probe found: a message's tag and size, and its number in the
 * model when only its RTS has come (0: the message itself). */
typedef struct {
    int32_t tag;
    uint32_t id;
    uint64_t len;
} link_envelope;

typedef struct link_model_send {
    struct link_model_send *next;
    link_envelope rts;      /* (sent from here: it lives as long as the send) */
    MPI_Request rts_rq, payload_rq;
    const void *data;
    int dest;
    bool cleared;           /* the payload is on its way                */
} link_model_send;

static struct {
    size_t eager;           /* 0: off                                   */
    bool legacy;
    MPI_Comm comm;          /* clear-to-sends and payloads              */
    link_model_send *sends; /* the sends not done                       */
    uint32_t next_id;
} link_model = {0, false, MPI_COMM_NULL, NULL, 0};

void link_model_protocol(size_t eager_bytes, bool legacy)
{
    if (eager_bytes && link_model.comm == MPI_COMM_NULL)
        MPI_Comm_dup(MPI_COMM_WORLD, &link_model.comm); /* (every rank: collective) */
    link_model.eager = eager_bytes;
    link_model.legacy = legacy;
}

static bool link_model_legacy(void)
{
    return link_model.legacy;
}

static bool link_model_rendezvous(MPI_Comm comm, size_t len)
{
    return link_model.eager && comm == MPI_COMM_WORLD && len > link_model.eager;
}

static link_status link_model_isend(int dest, int tag, const void *data, size_t len,
                                    link_req *req)
{
    link_model_send *s = calloc(1, sizeof *s);
    if (!s)
        return LINK_ERROR;
    s->rts = (link_envelope){tag, ++link_model.next_id, len};
    s->rts.id = s->rts.id ? s->rts.id : ++link_model.next_id; /* (0 is "none") */
    s->data = data;
    s->dest = dest;
    if (MPI_Isend(&s->rts, sizeof s->rts, MPI_BYTE, dest, LINK_TAG_RTS, MPI_COMM_WORLD,
                  &s->rts_rq) != MPI_SUCCESS) {
        free(s);
        return LINK_ERROR;
    }
    s->next = link_model.sends;
    link_model.sends = s;
    req->modelled = s->rts.id;
    req->active = true;
    return LINK_OK;
}

/* The sender's side of any call into this module: the payloads cleared
 * since the last one go. */
static void link_model_step(void)
{
    while (link_model.eager) {
        int flag = 0;
        uint32_t id = 0;
        MPI_Status st;
        if (MPI_Iprobe(MPI_ANY_SOURCE, LINK_TAG_CTS, link_model.comm, &flag, &st) !=
                MPI_SUCCESS ||
            !flag)
            return;
        MPI_Recv(&id, sizeof id, MPI_BYTE, st.MPI_SOURCE, LINK_TAG_CTS, link_model.comm,
                 MPI_STATUS_IGNORE);
        for (link_model_send *s = link_model.sends; s; s = s->next)
            if (s->rts.id == id && s->dest == st.MPI_SOURCE && !s->cleared) {
                MPI_Isend(s->data, (int)s->rts.len, MPI_BYTE, s->dest, (int)(id & LINK_MODEL_TAGS),
                          link_model.comm, &s->payload_rq);
                s->cleared = true;
                break;
            }
    }
}

/* Send number `id` is through (its record freed then). */
static bool link_model_done(uint32_t id)
{
    link_model_step();
    for (link_model_send **p = &link_model.sends; *p; p = &(*p)->next) {
        link_model_send *s = *p;
        int flag = 0;
        if (s->rts.id != id)
            continue;
        if (!s->cleared || MPI_Test(&s->payload_rq, &flag, MPI_STATUS_IGNORE) != MPI_SUCCESS ||
            !flag)
            return false;
        MPI_Wait(&s->rts_rq, MPI_STATUS_IGNORE); /* (matched before the clear-to-send) */
        *p = s->next;
        free(s);
        return true;
    }
    return true;
}

/* The message a probe of MPI_COMM_WORLD found: its own envelope, or the
 * one its RTS announces (the RTS taken). */
static link_status link_envelope_of(const MPI_Status *st, link_envelope *e)
{
    int count = 0;
    if (link_model.eager && st->MPI_TAG == LINK_TAG_RTS)
        return MPI_Recv(e, sizeof *e, MPI_BYTE, st->MPI_SOURCE, LINK_TAG_RTS, MPI_COMM_WORLD,
                        MPI_STATUS_IGNORE) == MPI_SUCCESS
                   ? LINK_OK
                   : LINK_ERROR;
    if (MPI_Get_count(st, MPI_BYTE, &count) != MPI_SUCCESS || count < 0)
        return LINK_ERROR;
    *e = (link_envelope){st->MPI_TAG, 0, (uint64_t)count};
    return LINK_OK;
}

/* Receiving in the background.  A message is matched as soon as a probe
 * sees it (MPI_Iprobe, then MPI_Irecv of its source and tag, which takes
 * that very message out of MPI's queue: nothing else receives on this
 * communicator, and a rank's messages are matched in order; MPI_Improbe
 * would say it more directly, but SimGrid's SMPI lacks it) and received
 * into a buffer of its own while the caller goes on; it is handed out once
 * all its bytes are in, the
 * oldest of its source first (messages from one rank stay in their
 * order).  So this rank never waits inside a receive for a peer that is
 * computing, and while it polls, the peer's large message goes on
 * whenever the peer makes progress (link_progress): with Open MPI's
 * shared memory and no single-copy support, or over a network, a message
 * over the eager limit moves in fragments that need both sides to call
 * MPI (docs/parallel.md, "Progress"). */
typedef struct {
    MPI_Request rq;
    link_msg msg;      /* its buffer, size, source and tag            */
    uint64_t order;    /* when it was matched                          */
    bool done;         /* every byte is in                             */
} link_incoming;

static struct {
    link_incoming *slot; /* [count] matched, not handed out yet, in the
                            order they were matched                    */
    int count, cap;
    uint64_t next_order;
    uint32_t *seen;      /* by source rank: == pass when a scan has met
                            one of its slots (the first is its oldest)  */
    uint32_t pass;
    int ranks;           /* seen's length                              */
} link_in;

/* The slots that may still hand out (or lose) a message of `source`. */
static bool link_in_matches(const link_incoming *in, int source)
{
    return source == MPI_ANY_SOURCE || in->msg.source == source;
}

/* A new slot for a message of `count` bytes, its buffer reserved (out of
 * memory, the job is aborted: a message can only be received whole). */
static link_incoming *link_in_slot(size_t count)
{
    if (link_in.count == link_in.cap) {
        int cap = link_in.cap ? 2 * link_in.cap : 8;
        link_incoming *grown = realloc(link_in.slot, (size_t)cap * sizeof *grown);
        if (!grown) {
            fprintf(stderr, "csgtrace: error: rank %d: out of memory for a receive\n",
                    link_w.rank);
            link_abort(1);
        }
        link_in.slot = grown;
        link_in.cap = cap;
    }
    link_incoming *in = &link_in.slot[link_in.count];
    memset(in, 0, sizeof *in);
    if (!link_reserve(&in->msg, count)) {
        fprintf(stderr, "csgtrace: error: rank %d: out of memory for a %zu-byte message\n",
                link_w.rank, count);
        link_abort(1);
    }
    return in;
}

/* The receive of the message a probe found posted into `in`: the message
 * itself (the oldest of its source and tag, the one probed, as nothing
 * else receives on this communicator), or, modelled, its payload, cleared
 * to come. */
static link_status link_in_post(link_incoming *in, const MPI_Status *st, const link_envelope *e)
{
    int count = (int)e->len;
    if (!e->id)
        return MPI_Irecv(in->msg.data, count, MPI_BYTE, st->MPI_SOURCE, st->MPI_TAG,
                         MPI_COMM_WORLD, &in->rq) == MPI_SUCCESS
                   ? LINK_OK
                   : LINK_ERROR;
    uint32_t id = e->id;
    if (MPI_Irecv(in->msg.data, count, MPI_BYTE, st->MPI_SOURCE, (int)(id & LINK_MODEL_TAGS),
                  link_model.comm, &in->rq) != MPI_SUCCESS)
        return LINK_ERROR;
    return MPI_Send(&id, sizeof id, MPI_BYTE, st->MPI_SOURCE, LINK_TAG_CTS, link_model.comm) ==
                   MPI_SUCCESS
               ? LINK_OK
               : LINK_ERROR;
}

/* Every message waiting from `source` matched and its receive posted; a
 * message over `limit` is not received (LINK_TOO_BIG, *big says which):
 * see mpi_link.h. */
static link_status link_in_match(int source, size_t limit, link_msg *big)
{
    for (;;) {
        int flag = 0;
        MPI_Status st;
        link_envelope e;
        if (MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st) != MPI_SUCCESS)
            return LINK_ERROR;
        if (!flag)
            return LINK_OK;
        if (link_envelope_of(&st, &e) != LINK_OK)
            return LINK_ERROR;
        if (e.len > limit) { /* (never received: the job ends) */
            big->len = (size_t)e.len;
            big->source = st.MPI_SOURCE;
            big->tag = e.tag;
            return LINK_TOO_BIG;
        }
        link_incoming *in = link_in_slot((size_t)e.len);
        in->msg.len = (size_t)e.len;
        in->msg.source = st.MPI_SOURCE;
        in->msg.tag = e.tag;
        in->order = link_in.next_order++;
        if (link_in_post(in, &st, &e) != LINK_OK) {
            link_msg_free(&in->msg);
            return LINK_ERROR;
        }
        link_in.count++;
    }
}

/* A new scan of the slots (link_in_first); false without the marks (out
 * of memory): link_in_first then looks back over the slots instead, as it
 * does for a source beyond the marks. */
static bool link_in_scan(void)
{
    if (!link_in.seen && link_w.size > 0) {
        link_in.seen = calloc((size_t)link_w.size, sizeof *link_in.seen);
        link_in.ranks = link_in.seen ? link_w.size : 0;
    }
    if (++link_in.pass == 0) { /* (wrapped: the old marks cleared) */
        if (link_in.seen)
            memset(link_in.seen, 0, (size_t)link_in.ranks * sizeof *link_in.seen);
        link_in.pass = 1;
    }
    return link_in.seen != NULL;
}

/* Slot i, met in a scan in the slots' order: the oldest of its source not
 * handed out yet? */
static bool link_in_first(int i, bool marked)
{
    int src = link_in.slot[i].msg.source;
    if (marked && src >= 0 && src < link_in.ranks) {
        bool first = link_in.seen[src] != link_in.pass;
        link_in.seen[src] = link_in.pass;
        return first;
    }
    for (int k = 0; k < i; k++) /* (the slots are in their order) */
        if (link_in.slot[k].msg.source == src)
            return false;
    return true;
}

/* The receives posted, tested: each done or not; with `oldest`, only the
 * oldest of each source, the one that can be handed out next (a rank with
 * a thousand messages on their way, rank 0 at the end of a frame of 1024
 * workers, otherwise tests each of them at every turn: bench/SCALE.md). */
static link_status link_in_test_some(bool oldest)
{
    bool marked = oldest && link_in_scan();
    for (int i = 0; i < link_in.count; i++) {
        link_incoming *in = &link_in.slot[i];
        int flag = 0;
        if (oldest && !link_in_first(i, marked))
            continue;
        if (!in->done && MPI_Test(&in->rq, &flag, MPI_STATUS_IGNORE) != MPI_SUCCESS)
            return LINK_ERROR;
        in->done = in->done || flag;
    }
    return LINK_OK;
}

static link_status link_in_test(void)
{
    return link_in_test_some(false);
}

/* Slot i removed, the others kept in their order. */
static void link_in_remove(int i)
{
    memmove(&link_in.slot[i], &link_in.slot[i + 1],
            (size_t)(link_in.count - i - 1) * sizeof *link_in.slot);
    link_in.count--;
}

/* Slot i handed out into m (m's old buffer dropped), the slot removed. */
static void link_in_take(int i, link_msg *m)
{
    link_incoming *in = &link_in.slot[i];
    free(m->data);
    *m = in->msg;
    m->data[m->len] = '\0';
    link_in_remove(i);
}

/* The oldest message of `source` whose bytes are all in (its source's
 * older ones handed out first), into m: LINK_OK; LINK_LOST when the
 * oldest one's sender died first (m->source says who; the request and its
 * buffer are left to MPI); LINK_NONE when none is complete.  One pass over
 * the slots, which are in the order they were matched: the first of each
 * source met is its oldest, the first such one complete the answer. */
static link_status link_in_next(int source, link_msg *m)
{
    bool marked = link_in_scan();
    int best = -1;
    for (int i = 0; i < link_in.count && best < 0; i++) {
        const link_incoming *in = &link_in.slot[i];
        if (link_in_first(i, marked) && link_in_matches(in, source) &&
            (in->done || link_peer_lost(in->msg.source)))
            best = i;
    }
    if (best < 0)
        return LINK_NONE;
    if (link_in.slot[best].done) {
        link_in_take(best, m);
        return LINK_OK;
    }
    m->source = link_in.slot[best].msg.source; /* (lost: the buffer is MPI's) */
    link_in_remove(best);
    return LINK_LOST;
}

/* Receives into data on `comm` without ever blocking in MPI (a peer that
 * dies in the middle of a large message never completes it, on TCP);
 * LINK_LOST when the peer is gone first: the request stays MPI's.  For the
 * scene's chunks (link_bcast), which nothing else receives meanwhile. */
/* link_recv_on, its naps at most nap_max_ns. */
static link_status link_recv_within(MPI_Comm comm, char *data, int count, int source, int tag,
                                    long nap_max_ns)
{
    MPI_Request rq;
    MPI_Status st;
    link_idle w;
    link_status status = LINK_OK;
    if (MPI_Irecv(data, count, MPI_BYTE, source, tag, comm, &rq) != MPI_SUCCESS)
        return LINK_ERROR;
    link_idle_init(&w, nap_max_ns, LINK_SPINS);
    for (;;) {
        int flag = 0, got = -1;
        if (MPI_Test(&rq, &flag, &st) != MPI_SUCCESS)
            status = LINK_ERROR;
        if (flag && (MPI_Get_count(&st, MPI_BYTE, &got) != MPI_SUCCESS || got != count))
            status = LINK_ERROR; /* (a shorter message than the chunk) */
        if (flag || status != LINK_OK)
            break;
        if (link_peer_lost(source)) {
            status = LINK_LOST;
            break;
        }
        link_idle_step(&w);
    }
    link_idle_free(&w);
    return status;
}

static link_status link_recv_on(MPI_Comm comm, char *data, int count, int source, int tag)
{
    return link_recv_within(comm, data, count, source, tag, LINK_NAP_MAX_NS);
}

static int link_source(int source)
{
    return source == LINK_ANY_SOURCE ? MPI_ANY_SOURCE : source;
}

/* The model's legacy receive: every matched message waited for whole,
 * polling, then napping with a doubling nap (the receive before
 * 2026-11-28: a probe, then the message's receive to its end). */
static link_status link_model_whole(void)
{
    link_idle w;
    link_status status = LINK_OK;
    link_idle_init(&w, LINK_NAP_MAX_NS, LINK_SPINS);
    for (;;) {
        link_model_step();
        if (link_in_test() != LINK_OK)
            status = LINK_ERROR;
        if (status != LINK_OK || !link_receiving())
            break;
        link_idle_step(&w);
    }
    link_idle_free(&w);
    return status;
}

/* One turn of receiving: what waits from `source` matched, the receives
 * tested, the next complete message handed out (link_in_next). */
static link_status link_in_turn(int source, size_t limit, link_msg *m)
{
    link_model_step();
    link_status got = link_in_match(source, limit, m);
    if (got == LINK_OK)
        got = link_model.legacy ? link_model_whole() : link_in_test_some(true);
    return got == LINK_OK ? link_in_next(source, m) : got;
}

link_status link_try_recv(link_msg *m, int source, size_t limit)
{
    return link_in_turn(link_source(source), limit, m);
}

link_status link_recv(link_msg *m, int source, size_t limit)
{
    link_idle w;
    link_status got;
    link_idle_init(&w, LINK_NAP_MAX_NS, LINK_SPINS);
    while ((got = link_in_turn(link_source(source), limit, m)) == LINK_NONE)
        link_idle_step(&w);
    link_idle_free(&w);
    return got;
}

bool link_receiving(void)
{
    for (int i = 0; i < link_in.count; i++)
        if (!link_in.slot[i].done)
            return true;
    return false;
}

void link_progress(void)
{
    int flag;
    MPI_Status st;
    if (link_model.legacy)
        return;
    link_model_step();
    /* (any call into MPI moves Open MPI's pending transfers on; a probe
     * that takes nothing is the cheapest) */
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
    link_in_test();
    link_page_serve_turn();
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

static link_status link_isend_on(MPI_Comm comm, int dest, int tag, const void *data, size_t len,
                                 link_req *req)
{
    req->active = false;
    req->peer = dest;
    req->modelled = 0;
    if (link_model_rendezvous(comm, len))
        return link_model_isend(dest, tag, data, len, req);
    if (MPI_Isend(data, (int)len, MPI_BYTE, dest, tag, comm, link_req_mpi(req)) != MPI_SUCCESS)
        return LINK_ERROR;
    req->active = true;
    return LINK_OK;
}

link_status link_isend(int dest, int tag, const void *data, size_t len, link_req *req)
{
    return link_isend_on(MPI_COMM_WORLD, dest, tag, data, len, req);
}

bool link_req_done(link_req *req)
{
    int flag = 1;
    if (!req->active)
        return true;
    if (req->modelled) {
        req->active = !link_model_done(req->modelled);
        req->modelled = req->active ? req->modelled : 0;
        return !req->active;
    }
    if (MPI_Test(link_req_mpi(req), &flag, MPI_STATUS_IGNORE) != MPI_SUCCESS)
        flag = 1; /* an error ends the request too: its bytes are free */
    if (flag)
        req->active = false;
    return flag != 0;
}

link_status link_req_wait(link_req *req)
{
    link_idle w;
    link_status status = LINK_OK;
    link_idle_init(&w, LINK_NAP_MAX_NS, LINK_SPINS);
    while (!link_req_done(req)) {
        if (link_peer_lost(req->peer)) {
            link_req_abandon(req);
            status = LINK_LOST;
            break;
        }
        link_idle_step(&w);
    }
    link_idle_free(&w);
    return status;
}

void link_req_abandon(link_req *req)
{
    if (req->active && !req->modelled) /* (a modelled one stays the model's) */
        MPI_Request_free(link_req_mpi(req));
    req->active = false;
}

/* Under --enable-recovery a worker may die at any time, also while the
 * scene is broadcast, and MPI_Bcast would then wait for ever (on the
 * master, or on the ranks below the dead one in the tree).  There the
 * master sends every chunk to each worker itself, with background sends
 * it gives up on when the worker is lost (link_req_wait), and the workers
 * receive them as plain messages: W copies through the master's link
 * instead of a tree's log2(W) rounds, the price of surviving. */
#define LINK_TAG_BCAST 32000 /* (above protocol.h's tags) */

static bool link_bcast_direct(void)
{
    const char *rec = getenv("OMPI_MCA_orte_enable_recovery");
    return link_w.watched && rec && strcmp(rec, "1") == 0;
}

bool link_survives_loss(void)
{
    return link_bcast_direct();
}

/* The chunks to ranks to[0 .. n-1] (to NULL: every worker). */
static link_status link_bcast_send(const void *data, size_t size, const int *to, int n_to)
{
    int n_dest = to ? n_to : link_w.size - 1;
    link_req *req = calloc((size_t)n_dest + 1, sizeof *req);
    if (!req)
        return LINK_ERROR;
    link_status status = LINK_OK;
    for (size_t off = 0; off < size || off == 0; off += LINK_BCAST_CHUNK) {
        size_t n = size - off < LINK_BCAST_CHUNK ? size - off : LINK_BCAST_CHUNK;
        for (int i = 0; i < n_dest; i++) {
            int r = to ? to[i] : i + 1;
            if (!link_peer_lost(r) && link_isend_on(link_w.bcast_comm, r, LINK_TAG_BCAST,
                                                    (const char *)data + off, n,
                                                    &req[i]) != LINK_OK)
                status = LINK_ERROR;
        }
        for (int i = 0; i < n_dest; i++)
            if (req[i].active)
                link_req_wait(&req[i]); /* (LINK_LOST: that worker is skipped from now) */
        if (size == 0)
            break;
    }
    free(req);
    return status;
}

static link_status link_bcast_receive(void *data, size_t size)
{
    char *sink = data ? NULL : malloc(LINK_BCAST_CHUNK); /* (no memory for the scene) */
    link_status status = LINK_OK;
    for (size_t off = 0; status == LINK_OK && (off < size || off == 0); off += LINK_BCAST_CHUNK) {
        size_t n = size - off < LINK_BCAST_CHUNK ? size - off : LINK_BCAST_CHUNK;
        char *into = data ? (char *)data + off : sink;
        status = into || n == 0 ? link_recv_on(link_w.bcast_comm, into, (int)n, LINK_MASTER,
                                               LINK_TAG_BCAST)
                                : LINK_ERROR;
        if (size == 0)
            break;
    }
    free(sink);
    return status;
}

/* MPI_Bcast in chunks over `comm`, whose rank 0 is the master. */
static link_status link_bcast_on(MPI_Comm comm, void *data, size_t size)
{
    char sink[LINK_BCAST_CHUNK]; /* where a rank without memory receives */
    link_status status = LINK_OK;
    for (size_t off = 0; off < size; off += LINK_BCAST_CHUNK) {
        size_t n = size - off < LINK_BCAST_CHUNK ? size - off : LINK_BCAST_CHUNK;
        if (MPI_Bcast(data ? (char *)data + off : sink, (int)n, MPI_BYTE, LINK_MASTER, comm) !=
            MPI_SUCCESS)
            status = LINK_ERROR; /* every chunk still goes: the others wait for it */
    }
    return status;
}

link_status link_bcast(void *data, size_t size)
{
    if (link_bcast_direct())
        return link_w.rank == 0 ? link_bcast_send(data, size, NULL, 0)
                                : link_bcast_receive(data, size);
    return link_bcast_on(MPI_COMM_WORLD, data, size);
}

link_status link_bcast_idle(void *data, size_t size)
{
    if (link_bcast_direct() || size > LINK_BCAST_CHUNK)
        return link_bcast(data, size);
    link_req req = {.active = false, .peer = LINK_MASTER};
    if (MPI_Ibcast(data, (int)size, MPI_BYTE, LINK_MASTER, MPI_COMM_WORLD, link_req_mpi(&req)) !=
        MPI_SUCCESS)
        return LINK_ERROR;
    req.active = true;
    return link_req_wait(&req);
}

/* ---- the scene: one copy per node ---------------------------------------------
 *
 * Why a memfd rather than MPI_Win_allocate_shared: a window is freed by a
 * collective call (MPI_Win_free) over the node's ranks, which would wait
 * for ever on a worker that died or was stopped (the job must survive
 * both: e2e_survive.sh, e2e_signals.sh).  A memfd needs no one's help to
 * go: each rank unmaps its own view, and the kernel frees the pages with
 * the last mapping, however the ranks end.  It has no name to leak either
 * (a killed leader leaves nothing in /dev/shm).  The other ranks of the
 * node open it through the leader's /proc/PID/fd/N, which the leader keeps
 * open until its render ends: by then every live rank of the node has
 * greeted the master, so has mapped the copy.  The copy's pages are
 * reserved (fallocate) before a byte is written: short of memory, the
 * leader learns it there, not from a SIGBUS later.
 *
 * The MPI side: MPI_Comm_split_type(MPI_COMM_TYPE_SHARED) once at start
 * (every rank alive then), the node's ranks gathered, and a communicator
 * of the leaders, over which the scene is broadcast (or, under
 * --enable-recovery, sent to each leader: link_bcast_direct).  A leader
 * tells its node with one small message each (eager: the send completes
 * without the receiver, so a dead rank holds nobody up). */
#define LINK_TAG_SCENE 32001 /* (above protocol.h's tags) */
#define LINK_TAG_PROBE 32002

/* Every rank, once after MPI_Init (collective). */
static void link_node_start(void)
{
    const char *setting = getenv("CSGTRACE_NODE_SCENE");
    MPI_Comm node = MPI_COMM_NULL, leaders = MPI_COMM_NULL;
    int node_rank = 0, node_size = 1, leader_count = 0, ok = 1;
    if (link_threads || (setting && strcmp(setting, "off") == 0))
        return; /* (the same for every rank: the environment is the job's) */
    /* (tests: nodes of N consecutive ranks pretended, so that leaders
     * other than rank 0 and a rank alone on its node happen on one machine) */
    long long pretend = test_hook_number(TEST_NODE_RANKS, 1 << 20);
    if ((pretend > 0 ? MPI_Comm_split(MPI_COMM_WORLD, (int)(link_w.rank / pretend), link_w.rank,
                                      &node)
                     : MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, link_w.rank,
                                           MPI_INFO_NULL, &node)) != MPI_SUCCESS ||
        MPI_Comm_rank(node, &node_rank) != MPI_SUCCESS ||
        MPI_Comm_size(node, &node_size) != MPI_SUCCESS)
        ok = 0;
    int *ranks = ok ? malloc((size_t)node_size * sizeof *ranks) : NULL;
    if (!ranks || MPI_Allgather(&link_w.rank, 1, MPI_INT, ranks, 1, MPI_INT, node) != MPI_SUCCESS)
        ok = 0;
    /* the leaders: each node's lowest rank (the key), so the master leads its own */
    if (MPI_Comm_split(MPI_COMM_WORLD, ok && node_rank == 0 ? 0 : MPI_UNDEFINED, link_w.rank,
                       &leaders) != MPI_SUCCESS)
        ok = 0;
    int *leader_ranks = NULL;
    if (leaders != MPI_COMM_NULL) {
        if (MPI_Comm_size(leaders, &leader_count) != MPI_SUCCESS ||
            !(leader_ranks = malloc((size_t)leader_count * sizeof *leader_ranks)) ||
            MPI_Allgather(&link_w.rank, 1, MPI_INT, leader_ranks, 1, MPI_INT, leaders) !=
                MPI_SUCCESS)
            ok = 0;
    }
    int my_leader = ok ? ranks[0] : link_w.rank;
    int *leader_of = malloc((size_t)link_w.size * sizeof *leader_of);
    if (!leader_of) { /* (a few bytes a rank: the collective cannot be skipped) */
        fprintf(stderr, "csgtrace: error: rank %d: out of memory at start\n", link_w.rank);
        link_abort(1);
    }
    if (MPI_Allgather(&my_leader, 1, MPI_INT, leader_of, 1, MPI_INT, MPI_COMM_WORLD) !=
        MPI_SUCCESS)
        ok = 0;
    if (MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD) != MPI_SUCCESS)
        ok = 0; /* (every rank shares, or none) */
    if (node != MPI_COMM_NULL)
        MPI_Comm_free(&node);
    if (!ok) {
        free(ranks);
        free(leader_ranks);
        free(leader_of);
        if (leaders != MPI_COMM_NULL)
            MPI_Comm_free(&leaders);
        return;
    }
    MPI_Comm_set_errhandler(leaders == MPI_COMM_NULL ? MPI_COMM_WORLD : leaders,
                            MPI_ERRORS_RETURN);
    link_w.node_share = true;
    link_w.leaders = leaders;
    link_w.node_rank = node_rank;
    link_w.node_size = node_size;
    link_w.node_ranks = ranks;
    link_w.leader_ranks = leader_ranks;
    link_w.leader_count = leader_count;
    link_w.leader_of = leader_of;
    link_probe();
}

int link_node_leader(int rank)
{
    return link_w.leader_of && rank >= 0 && rank < link_w.size ? link_w.leader_of[rank] : rank;
}

/* The link between rank 0's node and another, measured once at start
 * when the job spans nodes: rank 0 and the lowest rank on another node
 * send each other LINK_PROBE_BYTES, 1 + LINK_PROBE_TIMED times; the first
 * exchange opens the connection (Open MPI's TCP connects lazily), the
 * others are timed and the fastest is the link's (one exchange read 127
 * and 350 MB/s on two runs over the same 10 Gbit/s-shaped veth of a loaded
 * 2-core machine: a rank descheduled for a moment, not the link).  Each
 * exchange is two transfers of 1 MiB: 17 ms on gigabit Ethernet, well
 * under one on InfiniBand.  The other ranks take no part. */
#define LINK_PROBE_BYTES ((size_t)1 << 20)
#define LINK_PROBE_TIMED 3

/* The lowest rank on another node than rank 0's; -1 when none (or the
 * nodes were not found). */
static int link_other_node_rank(void)
{
    for (int r = 1; link_w.leader_of && r < link_w.size; r++)
        if (link_w.leader_of[r] != link_w.leader_of[0])
            return r;
    return -1;
}

static void link_probe(void)
{
    int partner = link_other_node_rank();
    if (partner < 0 || (link_w.rank != 0 && link_w.rank != partner))
        return;
    char *buf = calloc(1, LINK_PROBE_BYTES);
    int other = link_w.rank == 0 ? partner : 0;
    for (int round = 0; buf && round <= LINK_PROBE_TIMED; round++) {
        double t0 = MPI_Wtime();
        bool ok = link_w.rank == 0
                      ? MPI_Send(buf, (int)LINK_PROBE_BYTES, MPI_BYTE, other, LINK_TAG_PROBE,
                                 MPI_COMM_WORLD) == MPI_SUCCESS &&
                            MPI_Recv(buf, (int)LINK_PROBE_BYTES, MPI_BYTE, other, LINK_TAG_PROBE,
                                     MPI_COMM_WORLD, MPI_STATUS_IGNORE) == MPI_SUCCESS
                      : MPI_Recv(buf, (int)LINK_PROBE_BYTES, MPI_BYTE, other, LINK_TAG_PROBE,
                                 MPI_COMM_WORLD, MPI_STATUS_IGNORE) == MPI_SUCCESS &&
                            MPI_Send(buf, (int)LINK_PROBE_BYTES, MPI_BYTE, other, LINK_TAG_PROBE,
                                     MPI_COMM_WORLD) == MPI_SUCCESS;
        if (!ok)
            break;
        double t = MPI_Wtime() - t0, bps = t > 0 ? 2.0 * (double)LINK_PROBE_BYTES / t : 0;
        if (round > 0 && link_w.rank == 0 && bps > link_w.link_bps)
            link_w.link_bps = bps;
    }
    free(buf);
    long long pretend = test_hook_number(TEST_LINK_MBPS, 1 << 20); /* (tests only) */
    if (pretend > 0 && link_w.rank == 0)
        link_w.link_bps = (double)pretend * 1e6;
}

double link_between_nodes_bps(void)
{
    return link_w.link_bps;
}

bool link_spans_nodes(void)
{
    return link_other_node_rank() >= 0;
}

static void link_scene_clear(link_scene *s, size_t size)
{
    memset(s, 0, sizeof *s);
    s->size = size;
    s->fd = -1;
}

/* A new shared copy of `size` bytes, writable (the leader's). */
static bool link_scene_map_new(link_scene *s)
{
    size_t len = s->size ? s->size : 1;
    int fd = memfd_create("csgtrace-scene", MFD_CLOEXEC);
    void *p = MAP_FAILED;
    if (fd >= 0 && fallocate(fd, 0, 0, (off_t)len) == 0)
        p = mmap(NULL, len, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (p == MAP_FAILED) {
        if (fd >= 0)
            close(fd);
        return false;
    }
    s->bytes = p;
    s->fd = fd;
    s->shared = true;
    return true;
}

/* The scene's bytes from the master to every node leader. */
static link_status link_bcast_leaders(void *data, size_t size)
{
    if (link_bcast_direct())
        return link_w.rank == 0 ? link_bcast_send(data, size, link_w.leader_ranks + 1,
                                                  link_w.leader_count - 1)
                                : link_bcast_receive(data, size);
    return link_bcast_on(link_w.leaders, data, size);
}

/* A leader: the copy checked, read-only from now on; its node told where
 * it is (or that it has none: pid 0) and whether it passed. */
static void link_scene_tell_node(link_scene *s)
{
    if (s->shared)
        mprotect(s->bytes, s->size ? s->size : 1, PROT_READ);
    s->notice.valid = s->valid;
    s->notice.pid = s->shared ? (int32_t)getpid() : 0;
    s->notice.fd = s->fd;
    s->notice.size = s->size;
    for (int i = 1; i < link_w.node_size; i++) {
        link_req req;
        if (link_isend_on(link_w.bcast_comm, link_w.node_ranks[i], LINK_TAG_SCENE, &s->notice,
                          sizeof s->notice, &req) == LINK_OK)
            link_req_abandon(&req); /* (eager: it completes by itself) */
    }
}

/* Not a leader: the leader's word, then its copy mapped read-only. */
static link_status link_scene_map_leaders(link_scene *s)
{
    link_status status = link_recv_on(link_w.bcast_comm, (char *)&s->notice, sizeof s->notice,
                                      link_w.node_ranks[0], LINK_TAG_SCENE);
    if (status != LINK_OK)
        return status;
    if (s->notice.pid <= 0 || s->notice.size != s->size)
        return LINK_ERROR; /* (the leader has no copy) */
    char path[64];
    snprintf(path, sizeof path, "/proc/%d/fd/%d", (int)s->notice.pid, (int)s->notice.fd);
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return LINK_ERROR;
    void *p = mmap(NULL, s->size ? s->size : 1, PROT_READ, MAP_SHARED, fd, 0);
    close(fd); /* (the mapping keeps the copy) */
    if (p == MAP_FAILED)
        return LINK_ERROR;
    s->bytes = p;
    s->shared = true;
    s->valid = s->notice.valid != 0;
    return LINK_OK;
}

link_status link_scene_send(link_scene *s, const void *bytes, size_t size,
                            link_scene_check check)
{
    link_scene_clear(s, size);
    s->valid = check(bytes, size);
    s->bytes = (void *)bytes; /* (the caller's, until a shared copy is made) */
    s->copies_sent = link_w.node_share ? link_w.leader_count - 1 : link_w.size - 1;
    if (!link_w.node_share)
        return link_bcast(s->bytes, size);
    if (link_w.node_size > 1 && link_scene_map_new(s))
        memcpy(s->bytes, bytes, size);
    else
        s->bytes = (void *)bytes;
    link_status status = link_bcast_leaders((void *)bytes, size);
    link_scene_tell_node(s);
    return status;
}

link_status link_scene_receive(link_scene *s, size_t size, link_scene_check check)
{
    link_scene_clear(s, size);
    if (link_w.node_share && link_w.node_rank > 0)
        return link_scene_map_leaders(s);
    link_status status;
    if (link_w.node_share) { /* a node's leader */
        if (link_w.node_size == 1 || !link_scene_map_new(s))
            s->owned = (s->bytes = malloc(size ? size : 1)) != NULL;
        status = link_bcast_leaders(s->bytes, size);
    } else {
        s->owned = (s->bytes = malloc(size ? size : 1)) != NULL;
        status = link_bcast(s->bytes, size);
    }
    s->valid = status == LINK_OK && s->bytes && check(s->bytes, size);
    if (link_w.node_share)
        link_scene_tell_node(s);
    return status;
}

void link_scene_free(link_scene *s)
{
    if (s->shared)
        munmap(s->bytes, s->size ? s->size : 1);
    else if (s->owned)
        free(s->bytes);
    if (s->shared && s->fd >= 0)
        close(s->fd);
    link_scene_clear(s, 0);
}

void link_abort(int code)
{
    for (int r = 1; link_w.fd && r < link_w.size; r++)
        if (link_w.fd[r] >= 0)
            link_bye(r, LINK_BYE_QUIET); /* (this rank reported why) */
    link_fail_job();
    MPI_Abort(MPI_COMM_WORLD, code);
}

/* ---- pages of the scene (workers/pager.h) ---------------------------------------
 *
 * A worker below its scene budget asks rank 0 for pages: an ASK (the page
 * numbers) and the answer (their bytes, packed), on the broadcast's
 * communicator, apart from the protocol's messages, which the workers
 * match eagerly by source (a page's bytes must not be taken for a TILE).
 * The worker waits for the answer (its ray needs it); rank 0 answers in its
 * loop (link_page_serve) with background sends that it gives up on when
 * the worker is lost. */
static struct {
    link_req req[LINK_PAGE_SENDS];
    unsigned char *data[LINK_PAGE_SENDS];
    int32_t *ask;
    int ask_cap;
} link_pages;

uint64_t link_page_rerouted(void)
{
    return link_server.rerouted;
}

void link_page_server(link_page_pack pack, void (*poll)(void *arg), void *arg)
{
    link_server.pack = pack;
    link_server.poll = poll;
    link_server.arg = arg;
    if (!pack) {
        free(link_server.suspect);
        link_server.suspect = NULL;
    }
}

/* The asks of other workers waiting here answered (a home's turn). */
static void link_page_serve_turn(void)
{
    if (!link_server.pack || link_server.serving || link_server.held)
        return;
    link_server.serving = true;
    if (link_server.poll)
        link_server.poll(link_server.arg);
    link_page_serve(link_server.pack, link_server.arg);
    link_server.serving = false;
}

static long long link_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

/* One ask on its way: the page list sent from a copy (MPI may read it
 * after the fetch returns when its home is given up on), the answer's
 * receive posted: from rank 0 into the caller's buffer; from a home into
 * one of its own, copied over once whole (a home that dies halfway
 * through its answer leaves the receive for ever unfinished: that buffer
 * is then left to MPI, and the caller's is written by rank 0's answer
 * alone). */
typedef struct {
    MPI_Request ask, answer;
    int32_t *copy;
    unsigned char *bytes; /* a home's answer (NULL: rank 0's, into out) */
    int rank;
    bool answered;
    bool broken; /* MPI failed on a home's answer (it died: --enable-recovery) */
} link_page_wait;

#define LINK_PAGE_CANCEL_NS 1000000000LL /* a cancelled answer's end, waited at most */

static bool link_page_post(const link_page_ask *a, int rank, link_page_wait *w)
{
    w->rank = rank;
    w->answered = false;
    w->copy = malloc((size_t)a->n * sizeof *w->copy);
    if (!w->copy)
        return false;
    memcpy(w->copy, a->pages, (size_t)a->n * sizeof *w->copy);
    if (MPI_Isend(w->copy, a->n * (int)sizeof *w->copy, MPI_BYTE, rank, LINK_TAG_PAGE_ASK,
                  link_w.bcast_comm, &w->ask) != MPI_SUCCESS) {
        free(w->copy);
        w->copy = NULL;
        return false;
    }
    w->bytes = rank != LINK_MASTER ? malloc(a->bytes ? a->bytes : 1) : NULL;
    if ((rank != LINK_MASTER && !w->bytes) ||
        MPI_Irecv(w->bytes ? w->bytes : a->out, (int)a->bytes, MPI_BYTE, rank, LINK_TAG_PAGE,
                  link_w.bcast_comm, &w->answer) != MPI_SUCCESS) {
        w->answered = true; /* (nothing to wait for: the fetch fails) */
        return false;
    }
    return true;
}

/* The answer in: a home's copied into place, its buffer freed. */
static void link_page_take(const link_page_ask *a, link_page_wait *w)
{
    w->answered = true;
    if (w->bytes) {
        memcpy(a->out, w->bytes, a->bytes);
        free(w->bytes);
        w->bytes = NULL;
    }
}

/* Is asks[k]'s answer in (whole: *ok false when not)? */
static bool link_page_answered(const link_page_ask *a, link_page_wait *w, bool *ok)
{
    int flag = 0, got = -1;
    MPI_Status st;
    if (w->answered)
        return true;
    if (MPI_Test(&w->answer, &flag, &st) != MPI_SUCCESS) {
        if (w->rank != LINK_MASTER) { /* (rank 0 is asked instead) */
            w->broken = true;
            return false;
        }
        *ok = false;
        return true;
    }
    if (flag && (MPI_Get_count(&st, MPI_BYTE, &got) != MPI_SUCCESS || (size_t)got != a->bytes))
        *ok = false;
    if (flag)
        link_page_take(a, w);
    return w->answered;
}

/* A home silent for LINK_PAGE_HOME_WAIT_NS: its answer's receive
 * cancelled (unless it came meanwhile), the ask sent to rank 0, that home
 * never asked again (a late answer of its would match no receive). */
static bool link_page_give_up(const link_page_ask *a, link_page_wait *w, bool *ok)
{
    int cancelled = w->broken, done = w->broken; /* (a failed receive is MPI's no more) */
    MPI_Status st;
    if (!w->broken && MPI_Cancel(&w->answer) != MPI_SUCCESS)
        return false;
    for (long long until = link_now_ns() + LINK_PAGE_CANCEL_NS; !done && link_now_ns() < until;)
        if (MPI_Test(&w->answer, &done, &st) != MPI_SUCCESS)
            done = cancelled = 1; /* (failed: MPI's no more) */
        else if (done && MPI_Test_cancelled(&st, &cancelled) != MPI_SUCCESS)
            return false;
    if (done && !cancelled) { /* (it came after all) */
        int got = -1;
        *ok = *ok && MPI_Get_count(&st, MPI_BYTE, &got) == MPI_SUCCESS && (size_t)got == a->bytes;
        link_page_take(a, w);
        return true;
    }
    if (!done) /* (matched, and its sender gone halfway: left to MPI, with its buffer) */
        MPI_Request_free(&w->answer);
    else
        free(w->bytes);
    w->bytes = NULL;
    if (!link_server.suspect)
        link_server.suspect = calloc((size_t)link_w.size, sizeof *link_server.suspect);
    if (link_server.suspect)
        link_server.suspect[w->rank] = true;
    MPI_Request_free(&w->ask); /* (its copy is MPI's until then: kept) */
    w->broken = false;
    link_server.rerouted++;
    return link_page_post(a, LINK_MASTER, w);
}

bool link_page_fetch(const link_page_ask *asks, int n)
{
    link_page_wait *w = n > 0 ? calloc((size_t)n, sizeof *w) : NULL;
    bool ok = w != NULL;
    for (int k = 0; ok && k < n; k++) {
        int rank = asks[k].rank;
        if (asks[k].bytes > INT_MAX || asks[k].n <= 0 || rank < 0 || rank >= link_w.size)
            ok = false;
        else if (link_server.suspect && link_server.suspect[rank])
            rank = LINK_MASTER, link_server.rerouted++;
        ok = ok && link_page_post(&asks[k], rank, &w[k]);
        if (!ok)
            n = k + (w[k].copy != NULL); /* (what was posted is still waited for) */
    }
    /* (short naps: the answers are tens of microseconds away, and the ray
     * cannot go on without them) */
    link_idle idle;
    link_idle_init(&idle, LINK_PAGE_NAP_NS, LINK_SPINS);
    long long since = link_now_ns();
    bool outer = !link_server.serving;
    for (int left = n; left > 0;) {
        left = 0;
        int from_master = 0;
        for (int k = 0; k < n; k++) {
            bool in = link_page_answered(&asks[k], &w[k], &ok);
            left += !in;
            from_master += !in && w[k].rank == LINK_MASTER;
        }
        if (outer) /* (rank 0 answers whatever this rank does) */
            link_server.held = from_master > 0;
        if (left == 0)
            break;
        bool late = link_now_ns() - since > LINK_PAGE_HOME_WAIT_NS;
        for (int k = 0; k < n; k++)
            if (!w[k].answered && w[k].rank != LINK_MASTER && (late || w[k].broken) &&
                !link_page_give_up(&asks[k], &w[k], &ok))
                ok = false, w[k].answered = true; /* (MPI failed: the fetch fails) */
        if (late)
            since = link_now_ns();
        link_idle_step(&idle);
    }
    if (outer)
        link_server.held = false;
    for (int k = 0; k < n; k++) { /* the asks' sends: done once answered */
        int flag = 0;
        while (w[k].copy && MPI_Test(&w[k].ask, &flag, MPI_STATUS_IGNORE) == MPI_SUCCESS && !flag)
            link_idle_step(&idle);
        if (flag)
            free(w[k].copy);
        else if (w[k].copy && MPI_Request_free(&w[k].ask) != MPI_SUCCESS)
            ok = false; /* (MPI failed: its copy kept for it) */
    }
    link_idle_free(&idle);
    free(w);
    return ok;
}

struct link_page_async {
    link_page_ask ask;
    link_page_wait wait;
};

link_page_async *link_page_fetch_start(const link_page_ask *ask)
{
    link_page_async *a = malloc(sizeof *a);
    if (!a)
        return NULL;
    a->ask = *ask;
    memset(&a->wait, 0, sizeof a->wait);
    if (ask->bytes > INT_MAX || ask->n <= 0 || ask->rank < 0 || ask->rank >= link_w.size ||
        !link_page_post(&a->ask, ask->rank, &a->wait)) {
        free(a); /* (a failed post: nothing of it is MPI's but a copy, kept) */
        return NULL;
    }
    return a;
}

int link_page_fetch_test(link_page_async *a)
{
    bool ok = true;
    int flag = 0;
    if (!link_page_answered(&a->ask, &a->wait, &ok))
        return 0;
    if (MPI_Test(&a->wait.ask, &flag, MPI_STATUS_IGNORE) != MPI_SUCCESS)
        ok = false;
    else if (!flag)
        return 0; /* (its ask's send: done at the next call) */
    free(a->wait.copy);
    free(a);
    return ok ? 1 : -1;
}

void link_page_fetch_cancel(link_page_async *a)
{
    MPI_Status st;
    if (MPI_Cancel(&a->wait.answer) == MPI_SUCCESS)
        MPI_Wait(&a->wait.answer, &st);
    MPI_Request_free(&a->wait.ask); /* (its copy is MPI's until then: kept) */
    free(a);
}

/* The sends done (or given up on: the worker is lost) freed; a free slot,
 * or -1. */
static int link_page_slot(void)
{
    int free_slot = -1;
    for (int i = 0; i < LINK_PAGE_SENDS; i++) {
        link_req *r = &link_pages.req[i];
        if (r->active) {
            if (link_req_done(r)) {
                free(link_pages.data[i]);
            } else if (link_peer_lost(r->peer)) {
                link_req_abandon(r); /* (MPI may still read its bytes: left to it) */
            } else {
                continue;
            }
            link_pages.data[i] = NULL;
        }
        if (free_slot < 0)
            free_slot = i;
    }
    return free_slot;
}

int link_page_serve(link_page_pack pack, void *arg)
{
    int served = 0;
    for (;;) {
        int flag = 0, len = 0;
        MPI_Status st;
        if (MPI_Iprobe(MPI_ANY_SOURCE, LINK_TAG_PAGE_ASK, link_w.bcast_comm, &flag, &st) !=
                MPI_SUCCESS ||
            !flag || MPI_Get_count(&st, MPI_BYTE, &len) != MPI_SUCCESS)
            return served;
        int slot = link_page_slot();
        if (slot < 0)
            return served; /* (the next call: once a send is done) */
        int n = len / (int)sizeof(int32_t);
        if (n > link_pages.ask_cap) {
            int32_t *grown = realloc(link_pages.ask, (size_t)n * sizeof *grown);
            if (!grown)
                return served;
            link_pages.ask = grown;
            link_pages.ask_cap = n;
        }
        if (MPI_Recv(link_pages.ask, len, MPI_BYTE, st.MPI_SOURCE, LINK_TAG_PAGE_ASK,
                     link_w.bcast_comm, MPI_STATUS_IGNORE) != MPI_SUCCESS)
            return served;
        unsigned char *bytes = NULL;
        size_t size = n > 0 && len == n * (int)sizeof(int32_t)
                          ? pack(arg, link_pages.ask, n, &bytes)
                          : 0;
        /* (an ask that cannot be answered gets an empty answer: the
         * worker's receive fails on its length and its item fails) */
        link_pages.data[slot] = bytes;
        if (link_isend_on(link_w.bcast_comm, st.MPI_SOURCE, LINK_TAG_PAGE,
                          bytes ? bytes : (void *)"", bytes ? size : 0,
                          &link_pages.req[slot]) != LINK_OK) {
            free(bytes);
            link_pages.data[slot] = NULL;
        }
        served++;
    }
}

/* ---- one-sided pages (link_page_window) ----------------------------------------- */

static struct {
    MPI_Win win;
    bool open;        /* this rank may read rank 0's blob through it */
    const void *blob; /* rank 0's blob it exposes                    */
    void *held;       /* that blob, the link's once its render ended  */
} link_window = {MPI_WIN_NULL, false, NULL, NULL};

bool link_page_window(void *blob, size_t size)
{
    if (link_window.win != MPI_WIN_NULL) { /* (a render's before: every rank is past it) */
        if (link_window.open)
            MPI_Win_unlock_all(link_window.win);
        MPI_Win_free(&link_window.win);
        free(link_window.held);
        link_window.open = false;
        link_window.blob = link_window.held = NULL;
    }
    MPI_Win win = MPI_WIN_NULL;
    int made = MPI_Win_create(link_w.rank == LINK_MASTER ? blob : NULL,
                              link_w.rank == LINK_MASTER ? (MPI_Aint)size : 0, 1, MPI_INFO_NULL,
                              link_w.bcast_comm, &win) == MPI_SUCCESS,
        all = 0;
    if (MPI_Allreduce(&made, &all, 1, MPI_INT, MPI_MIN, link_w.bcast_comm) != MPI_SUCCESS)
        all = 0;
    if (!all) { /* (every rank made it or the job's MPI is broken: none is used) */
        if (made)
            MPI_Win_free(&win);
        return false;
    }
    MPI_Win_set_errhandler(win, MPI_ERRORS_RETURN);
    link_window.win = win;
    if (link_w.rank == LINK_MASTER) {
        link_window.blob = blob;
        return true;
    }
    link_window.open = MPI_Win_lock_all(MPI_MODE_NOCHECK, win) == MPI_SUCCESS;
    return link_window.open;
}

const void *link_page_window_blob(void)
{
    return link_window.blob;
}

void link_page_window_hold(void *blob)
{
    link_window.held = blob;
}

/* One get for the whole list: the same byte ranges on both sides (an
 * hindexed type over the blob's offsets, from base here and from the
 * window's start there), so the library moves them as one transfer (one
 * message, or one vector of cross-memory reads) rather than one each. */
bool link_page_get(void *base, const uint64_t *off, const uint64_t *len, int n)
{
    if (!link_window.open || n <= 0)
        return link_window.open && n == 0;
    MPI_Aint *disp = malloc((size_t)n * sizeof *disp);
    int *count = malloc((size_t)n * sizeof *count);
    MPI_Datatype ranges = MPI_DATATYPE_NULL;
    bool ok = disp && count;
    for (int k = 0; ok && k < n; k++) {
        ok = len[k] <= INT_MAX && off[k] <= (uint64_t)PTRDIFF_MAX;
        disp[k] = (MPI_Aint)off[k];
        count[k] = (int)len[k];
    }
    ok = ok && MPI_Type_create_hindexed(n, count, disp, MPI_BYTE, &ranges) == MPI_SUCCESS &&
         MPI_Type_commit(&ranges) == MPI_SUCCESS &&
         MPI_Get(base, 1, ranges, LINK_MASTER, 0, 1, ranges, link_window.win) == MPI_SUCCESS &&
         MPI_Win_flush(LINK_MASTER, link_window.win) == MPI_SUCCESS;
    if (ranges != MPI_DATATYPE_NULL)
        MPI_Type_free(&ranges);
    free(disp);
    free(count);
    if (!ok && disp && count)
        link_window.open = false; /* (MPI failed: for good) */
    return ok;
}
