/*
 * mpi_link.h — the message link between the master (rank 0) and the workers:
 * the one module that talks to MPI (only mpi_link.c includes mpi.h).
 *
 * Everything the tile protocol (protocol.h) needs and nothing more: start
 * MPI when launched by mpirun, send one message (blocking, or in the
 * background: link_isend), wait for or poll for one message of a bounded
 * size, broadcast the scene in chunks, and the idle wait of an event loop
 * (link_idle: poll, then nap, woken early by link_wake from any thread).
 * Without mpirun no MPI call is ever made and MPI is never initialised
 * (link_idle alone touches no MPI).
 *
 * Errors return: MPI's error handler is set to return codes, so a call
 * that fails reports LINK_ERROR to its caller instead of killing the job.
 *
 * Liveness: launched with `mpirun --enable-recovery`, the job outlives a
 * worker that dies; the master learns it from link_peer_lost (a watchdog
 * socket per worker, mpi_link.c), and no wait of this module outlives the peer
 * it waits on (LINK_LOST).  A worker exits by itself as soon as the master
 * is gone.
 */
#ifndef COMM_MPI_LINK_H
#define COMM_MPI_LINK_H

#include <semaphore.h>
#include <sched.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

enum { LINK_MASTER = 0, LINK_ANY_SOURCE = -1 };

/* True when the process was started by mpirun (Open MPI's
 * OMPI_COMM_WORLD_SIZE, or PMI_SIZE / PMIX_RANK of other launchers). */
bool link_launched_by_mpirun(void);

/* MPI_Init once per process (MPI_Finalize then runs at exit, so that a
 * program may render several times in one job); this rank and the number
 * of ranks.  false when MPI cannot start. */
bool link_start(int *rank, int *size);
/* The ranks are threads of one process (the simulated build, SMPI:
 * sim/main.c calls it first): no process to watch (no watchdog sockets),
 * no CPU to bind a worker to. */
void link_ranks_are_threads(void);

typedef enum {
    LINK_OK = 0,
    LINK_TOO_BIG, /* the message exceeds the limit: NOT received (source,
                     tag and len say what it is); it stays at the head
                     of the queue, so the job can only end: report it,
                     then link_abort                                    */
    LINK_ERROR,   /* MPI failed                                        */
    LINK_NONE,    /* link_try_recv: no message is waiting              */
    LINK_LOST     /* the peer died before the message was through (its
                     bytes, and the buffer they went to, are MPI's now) */
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
 * job is aborted (exit 1, one message): MPI can only take a message whole.
 * Every message waiting is taken at once and received in the background
 * (mpi_link.c): the wait polls, then naps with a short back-off, rather
 * than spinning in MPI (the ranks may outnumber the cores, and the OpenCL
 * pass needs them), but never naps while bytes are on their way. */
link_status link_recv(link_msg *m, int source, size_t limit);
/* The same without waiting: the next message from `source` whose bytes
 * are all in; LINK_NONE when there is none now (a message may be on its
 * way: link_receiving). */
link_status link_try_recv(link_msg *m, int source, size_t limit);
/* Some message is being received (matched, its bytes not all in): the
 * caller's next poll may bring it, and a nap would hold it back. */
bool link_receiving(void);
/* Moves this rank's transfers on (its large sends, which need the
 * sender's calls into MPI to go on, and its receives), without taking
 * anything: for a rank busy computing, between pieces of its work
 * (workers/tile.h: tile_runner.progress).  A few microseconds. */
void link_progress(void);
void link_msg_free(link_msg *m);

/* The simulated build only (sim/main.c, bench/simulate.sh --eager-bytes):
 * Open MPI's large-message protocol played over SMPI, which by itself
 * moves every message whatever its ranks are doing.  A message of more
 * than `eager_bytes` (0: off) is announced (RTS), and its bytes move only
 * once the receiver has matched it, which sends a clear-to-send back, and
 * the sender has seen that in a later call into this module: so a rank
 * that computes without calling in holds its large sends, as it does on
 * a node without single-copy transfers (docs/parallel.md, "Progress").
 * `legacy`: the runtime before 2026-11-28, for the validation against
 * that day's node runs: a rank receives each matched message whole before
 * it goes on (napping), and link_progress does nothing. */
void link_model_protocol(size_t eager_bytes, bool legacy);

/* One message of `len` bytes to `dest`. */
link_status link_send(int dest, int tag, const void *data, size_t len);

/* A send in the background (MPI_Isend): the sender goes on at once, even
 * when the message is too large to be buffered and the receiver is busy.
 * Its bytes must stay untouched until the request is done. */
typedef struct {
    union {
        void *p;
        long long i;
        unsigned char bytes[16];
    } impl;      /* the MPI_Request (mpi_link.c checks it fits)            */
    bool active; /* started and not yet known to be done               */
    int peer;    /* the receiver                                       */
    uint32_t modelled; /* a send of the protocol model: its number (0: none) */
} link_req;

link_status link_isend(int dest, int tag, const void *data, size_t len, link_req *req);
/* True once the send is done (or none was active); LINK_ERROR aside, a
 * done request is inactive again. */
bool link_req_done(link_req *req);
/* Waits (poll, then nap) until the send is done; LINK_LOST (the request
 * abandoned) when the receiver is lost first (link_peer_lost). */
link_status link_req_wait(link_req *req);
/* Gives up on a send the receiver may never take (a worker written off
 * after breaking the protocol): MPI keeps the request; the caller must
 * neither reuse nor free its bytes. */
void link_req_abandon(link_req *req);

/* The idle wait of an event loop: the caller polls for work and, when
 * there was none, calls link_idle_step, which spins a little, then naps,
 * each nap twice the last up to nap_max_ns.  link_wake (from any thread:
 * it is a sem_post) ends the current nap at once and makes the next step
 * return without napping, so a producer that is not a message (an OpenCL
 * slice completing) is never kept waiting by a nap.  While a message is
 * being received (link_receiving) a nap is the shortest, a yield: its
 * bytes come in as this rank polls.  After useful work the caller calls
 * link_idle_reset, which restarts the spins. */
typedef struct {
    sem_t wake;        /* posted by link_wake                            */
    long nap_ns;       /* the next nap                                   */
    long nap_max_ns;   /* the longest nap; the caller may change it      */
    int spins;         /* steps left before the first nap                */
    int spin_steps;    /* the spins after a reset                        */
    bool ready;        /* wake was initialised                           */
} link_idle;

#define LINK_NAP_MAX_NS 200000L /* a worker with nothing queued, at most */

/* Asks the OS to run this process soon after each wake-up rather than
 * letting a busy process finish its time slice first: on Linux >= 6.12
 * (EEVDF) a short custom slice (sched_setattr), so a nap's end or a wake-up
 * preempts a worker at once; elsewhere it does nothing.  For the master,
 * whose every delay is a worker's wait once the ranks outnumber the cores. */
void link_respond_quickly(void);

bool link_idle_init(link_idle *w, long nap_max_ns, int spin_steps);
void link_idle_free(link_idle *w);
void link_idle_step(link_idle *w);
void link_idle_reset(link_idle *w);
void link_wake(link_idle *w);

/* MPI_Bcast of `size` bytes from the master, in chunks (no int overflow,
 * and a rank short of memory can still take part: data NULL receives into
 * a sink). */
link_status link_bcast(void *data, size_t size);
/* The same for a small message (<= 64 KiB) the others may wait long for
 * (the master reads the scene first): they poll, then nap (link_idle),
 * rather than spin in MPI_Bcast on the cores the master's reading, and
 * hetero's OpenCL set-up meanwhile, could use.  Each round of the
 * broadcast's tree may then cost a nap (LINK_NAP_MAX_NS at most). */
link_status link_bcast_idle(void *data, size_t size);

/* ---- the scene: one copy per node ---------------------------------------------
 *
 * The ranks of a node (MPI_Comm_split_type, MPI_COMM_TYPE_SHARED) read
 * one copy of the scene's bytes in place.  The master sends the bytes once
 * per node, to the node leaders (each node's lowest rank; the master leads
 * its own); a leader receives them into a shared mapping (a memfd), checks
 * them once (`check`, the blob's validation) and tells the other ranks of
 * its node where the copy is and whether it passed; they map it
 * read-only.  The master's own node reads the master's copy, moved into
 * its mapping.  Teardown is no collective call: each rank unmaps its view
 * (link_scene_free) and the kernel frees the copy with its last mapping,
 * so a dead or stopped rank holds nobody up (mpi_link.c).
 * Off (every rank its own copy, through link_bcast): without mpirun, when
 * the ranks are threads (the simulated build), with one rank a node, or
 * with CSGTRACE_NODE_SCENE=off. */
typedef struct {
    void *bytes;   /* the scene (NULL: no memory for it); read-only once
                      link_scene_* returned, unless private             */
    size_t size;
    bool shared;   /* bytes is the node's one copy, mapped              */
    bool valid;    /* `check` passed, here or on the node's leader      */
    bool owned;    /* bytes is this rank's own malloc'd copy             */
    int fd;        /* the copy's memfd (the leader keeps it open for the
                      render, so its node's ranks can open it), or -1   */
    int copies_sent; /* the master: copies of the bytes it sent over MPI
                        (one a node leader, or one a worker when off)  */
    struct {
        int32_t valid, pid, fd, pad;
        uint64_t size;
    } notice;      /* what a leader tells its node (kept until freed:
                      it is sent in the background)                     */
} link_scene;

typedef bool (*link_scene_check)(const void *bytes, size_t size);

/* Master: sends the scene's `size` bytes; *s is its copy from now on (the
 * node's shared copy when one is made: the caller may then free its own).
 * s->valid: `check` passed (the workers of the master's node trust it). */
link_status link_scene_send(link_scene *s, const void *bytes, size_t size,
                            link_scene_check check);
/* Every other rank: the scene of `size` bytes (the setup's), checked. */
link_status link_scene_receive(link_scene *s, size_t size, link_scene_check check);
/* This rank's view of the scene gone (no call into MPI). */
void link_scene_free(link_scene *s);
/* The rank whose copy of the scene rank `rank` reads: its node's leader,
 * or itself (a leader, or no sharing).  For the master's handshake: a
 * rank whose leader died before telling it waits for ever, so it is
 * written off with it (host/master.c). */
int link_node_leader(int rank);
/* Do the job's ranks run on more than one node (by the sharing's split:
 * false when it was not made, CSGTRACE_NODE_SCENE=off or threads)? */
bool link_spans_nodes(void);
/* Rank 0: the bytes a second between its node and another, measured at
 * start when the job spans nodes (1 MiB exchanged, the fastest of three
 * timed exchanges after one that opens the connection); 0 when it does
 * not, or it could not be measured. */
double link_between_nodes_bps(void);

/* Where a worker computes (link_bind_worker).  With more ranks on a node
 * than CPUs, launched unbound (`mpirun --bind-to none`, which rank 0
 * needs so that the OpenCL pass may use every core), Linux often leaves
 * two busy workers on one core for a whole short frame, the master alone
 * on the other: rank 0 polls and naps every few microseconds, too briefly
 * for the idle core to pull a worker over (measured here, 2 cores,
 * tetra2 homo: half of the runs took 0.033 s instead of 0.022 s, rank 0's
 * CPU 0.016 s instead of 0.003 s; placing the workers once, then
 * unbinding them, did not help).  So each worker binds itself to the
 * (local rank mod n)-th of the n CPUs it may use: the workers spread
 * evenly, rank 0 (not a worker) stays unbound.  Only under Open MPI with
 * binding "none" (anything else: the launcher's choice stands), more
 * local ranks than allowed CPUs, and the setting ($CSGTRACE_WORKER_BIND)
 * not "off".
 * The CPU, or -1: left unbound.  Pure: the environment's strings and the
 * allowed set given. */
int link_worker_cpu(const char *setting, const char *binding, const char *local_rank,
                    const char *local_size, const cpu_set_t *allowed);
/* This worker bound to link_worker_cpu's CPU for its environment and
 * `setting`; the CPU, or -1 (left as it was). */
int link_bind_worker(const char *setting);

/* ---- liveness ---------------------------------------------------------------- */

/* Master: true once rank r's process is gone (its watchdog socket closed,
 * however it died; a worker that never connected one is never "lost"
 * here).  Stays true. */
/* Rank r was lost or written off earlier in this job (no polling: what
 * link_peer_lost and link_forget recorded). */
bool link_peer_gone_before(int rank);
bool link_peer_lost(int rank);
/* Master: stops watching rank r and closes its socket, so that worker,
 * if it is still alive (hung), exits at once; one that is stopped
 * (SIGSTOP), which cannot, is SIGKILLed when it runs on this host (on
 * another, mpirun waits for it until it is continued or killed there). */
void link_forget(int rank);
/* Worker: STOP(status) came (status >= 0): from now on the master's exit
 * is expected, and this process is given a few seconds to end by itself
 * before it exits with `status`; -1: a new render, the master's exit is
 * again fatal. */
void link_ending(int status);
/* Master: the job's status.  A non-zero one is made mpirun's too at exit
 * (under --enable-recovery mpirun would report 0: link_fail_job). */
void link_exit_status(int status);
/* Under mpirun --enable-recovery: SIGTERM to the parent mpirun, so that it
 * ends the job and exits 1 (it reports 0 otherwise, whatever the ranks
 * return).  Does nothing otherwise. */
void link_fail_job(void);
/* MPI_Finalize now, if it has not run (else it runs at exit): for a
 * launcher that does not run atexit handlers per rank (SMPI, make sim). */
void link_finish(void);

/* Ends every rank of the job with `code` (a rank that cannot go on). */
void link_abort(int code);

/* Pages of the scene (workers/pager.h).  A worker asks each rank that
 * serves some of the pages it needs (rank 0, or the pages' homes) at once:
 * asks[k]'s pages from asks[k].rank, their bytes packed into its out; it
 * waits for every answer, answering other workers' asks meanwhile (its
 * server, below).  A home that has not answered within
 * LINK_PAGE_HOME_WAIT_NS (gone, or stopped) is asked no more: its pages
 * come from rank 0 from then on.  False when an answer did not come whole.
 * Rank 0, or a worker that holds pages: every ASK waiting answered, its
 * bytes packed by `pack` (malloc'd into *out; their size, 0 when it
 * cannot), sent in the background; returns how many were answered. */
typedef struct {
    int rank;             /* who answers: rank 0, or the pages' home   */
    const int32_t *pages;
    int n;
    unsigned char *out;   /* the answer's bytes, `bytes` of them        */
    size_t bytes;
} link_page_ask;
#define LINK_PAGE_HOME_WAIT_NS 5000000000LL
bool link_page_fetch(const link_page_ask *asks, int n);
/* Asks this rank sent to rank 0 instead of a home, so far. */
uint64_t link_page_rerouted(void);
/* The same for one ask, in the background: started (NULL when it could
 * not be), then tested until it ends: 1 its answer came whole (the handle
 * freed), 0 not yet, -1 it failed (freed).  An ask of rank 0 only (a home's
 * share filled: its answers come in the order of the asks). */
typedef struct link_page_async link_page_async;
link_page_async *link_page_fetch_start(const link_page_ask *ask);
int link_page_fetch_test(link_page_async *a);
/* An ask not ended given up (its answer's receive cancelled), freed. */
void link_page_fetch_cancel(link_page_async *a);
typedef size_t (*link_page_pack)(void *arg, const int32_t *pages, int n, unsigned char **out);
/* A worker that holds pages (--page-home spread): `pack` answers the asks
 * waiting whenever this rank makes progress or waits (link_progress, every
 * wait's idle step), so a home's answer never waits for its own work;
 * `poll` (may be NULL) is called there first (a background fill's turn).
 * Neither while the rank waits for its own pages from rank 0, nor within
 * itself.  NULL pack: none (the worker's end). */
void link_page_server(link_page_pack pack, void (*poll)(void *arg), void *arg);
int link_page_serve(link_page_pack pack, void *arg);

/* The job goes on past a lost rank (--enable-recovery): no collective
 * call after the start (the scene is sent rank by rank). */
bool link_survives_loss(void);

/* One-sided pages (--page-fetch get; VM_pRAY's shared virtual memory):
 * rank 0's blob opened as an MPI memory window on every rank at once
 * (collective: rank 0 with its blob, each worker with NULL, 0), where the
 * library can (Open MPI: osc/rdma over shared memory with cross-memory
 * attach, or an RDMA network); true where this rank may read it: a
 * worker whose window did not open asks (rank 0 answers either way).
 * Not freed at the render's end: MPI_Win_free waits for every rank, which
 * a stopped worker would make wait for ever, and such a worker may still
 * read it.  The next render's window frees it (every rank is there, past
 * the last), else it goes with the job, and with it the blob, which rank 0
 * hands over (link_page_window_hold) rather than free. */
bool link_page_window(void *blob, size_t size);
/* The blob the window exposes (NULL: none), and rank 0 handing it over at
 * its render's end: the link frees it (free) with the window. */
const void *link_page_window_blob(void);
void link_page_window_hold(void *blob);
/* The byte ranges [off[k], off[k] + len[k]) of rank 0's blob, k < n,
 * read to base + off[k], rank 0 taking no part; returns once they are in.
 * False when memory is short or MPI failed (then for good: the fetch
 * fails, as an ask's would). */
bool link_page_get(void *base, const uint64_t *off, const uint64_t *len, int n);

#endif
