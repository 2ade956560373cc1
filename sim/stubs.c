/*
 * stubs.c — what cannot run under SMPI, replaced at link time for the
 * simulated build (make sim) only.
 *
 * The ranks of an SMPI job are simulated processes that take turns in one
 * OS process; a real blocking call would stop every one of them, and real
 * time means nothing there.  mpi_link.c's idle wait naps on a semaphore with a
 * deadline (sem_clockwait): linked with -Wl,--wrap=sem_clockwait, the nap
 * becomes a simulated sleep (nanosleep is SMPI's here, as clock_gettime
 * is), ended early by a post found when it ends (nothing posts in the
 * simulation: the OpenCL pass is a duration, sim/main.c).
 *
 * The simulated seconds the watched wait (the master's) napped are summed,
 * so the driver can report the share of the makespan the master was busy.
 *
 * A nap that ran out costs its rank CPU time as well: the timer, the
 * wake-up and the switch back, $CSGSIM_NAP_CPU_S seconds (bench/
 * simulate.sh --nap-us; default 0).  Measured here, a semaphore wait with
 * a 20-50 us deadline takes its thread 6.4-7.1 us of CPU (bench/SCALE.md,
 * sixth section); on a shared core (bench/sim/local.xml) that is time the
 * other ranks do not get.
 */
#include "stubs.h"

#include <errno.h>
#include <time.h>

#include <smpi/smpi.h>

#include "tile_sim.h"

/* CSGSIM_NAP_CPU_S, read once (every rank the same) */
static double sim_nap_cpu_s(void)
{
    static double seconds = -1;
    if (seconds < 0)
        seconds = sim_env_number("CSGSIM_NAP_CPU_S", 0);
    return seconds;
}

typedef struct {
    const sem_t *watched; /* the master's wake semaphore                 */
    double napped_s;      /* simulated seconds it napped                  */
} sim_naps;

static sim_naps *sim_naps_state(void)
{
    static sim_naps naps; /* one per process: the master is one rank */
    return &naps;
}

void sim_watch_naps(const sem_t *wake)
{
    sim_naps_state()->watched = wake;
    sim_naps_state()->napped_s = 0;
}

double sim_napped_s(void)
{
    return sim_naps_state()->napped_s;
}

static double sim_seconds(const struct timespec *t)
{
    return (double)t->tv_sec + (double)t->tv_nsec * 1e-9;
}

int __wrap_sem_clockwait(sem_t *sem, clockid_t clock, const struct timespec *until);

int __wrap_sem_clockwait(sem_t *sem, clockid_t clock, const struct timespec *until)
{
    if (sem_trywait(sem) == 0)
        return 0;
    struct timespec now;
    clock_gettime(clock, &now);
    double nap = sim_seconds(until) - sim_seconds(&now);
    if (nap > 0) {
        struct timespec ts = {(time_t)nap, (long)((nap - (double)(time_t)nap) * 1e9)};
        nanosleep(&ts, NULL);
        if (sem == sim_naps_state()->watched)
            sim_naps_state()->napped_s += nap;
        if (sim_nap_cpu_s() > 0)
            smpi_execute_flops(sim_nap_cpu_s() * SIM_HOST_FLOPS);
    }
    if (sem_trywait(sem) == 0)
        return 0;
    errno = ETIMEDOUT;
    return -1;
}

/* mpi_link.c finalizes MPI at exit; under SMPI the ranks are gone by then (the
 * driver calls link_finish on every rank), so nothing is registered
 * (linked with -Wl,--wrap=atexit; the driver's own code registers none). */
int __wrap_atexit(void (*fn)(void));

int __wrap_atexit(void (*fn)(void))
{
    (void)fn;
    return 0;
}
