/*
 * nap_cost.c — what a nap that runs out costs the napping thread in CPU
 * time: the semaphore wait with a deadline of comm/mpi_link.c's idle wait
 * (sem_clockwait on CLOCK_MONOTONIC, timer slack 1 us as mpi_link.c sets
 * it), NAPS times a round, ROUNDS rounds; printed per nap length: the
 * median CPU and wall microseconds a nap with their range.  The simulated
 * build charges a rank this CPU time after each of its naps (bench/
 * simulate.sh --nap-us).
 *
 *   build/bench/nap_cost ROUNDS NAPS NS...
 */
#include <semaphore.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/prctl.h>
#include <time.h>

#include "../comm/deadline.h"
#include "timing.h"

int main(int argc, char **argv)
{
    int rounds = 0, naps = 0, lengths = argc - 3;
    if (argc < 4 || !bench_parse_int(argv[1], 1, 99, &rounds) ||
        !bench_parse_int(argv[2], 1, 1000000, &naps)) {
        fprintf(stderr, "usage: nap_cost ROUNDS(1..99) NAPS NS...\n");
        return 2;
    }
    prctl(PR_SET_TIMERSLACK, 1000UL); /* (mpi_link.c's LINK_NAP_MIN_NS) */
    sem_t never;
    sem_init(&never, 0, 0);
    double *cpu = malloc((size_t)rounds * sizeof *cpu), *wall = malloc((size_t)rounds * sizeof *wall);
    if (!cpu || !wall)
        return 1;
    printf("nap_ns,cpu_us_median,cpu_us_min,cpu_us_max,wall_us_median\n");
    for (int l = 0; l < lengths; l++) {
        int ns = 0;
        if (!bench_parse_int(argv[3 + l], 1, 100000000, &ns)) {
            fprintf(stderr, "nap_cost: NS 1..100000000\n");
            return 2;
        }
        for (int r = 0; r < rounds; r++) {
            double c0 = bench_clock_s(CLOCK_THREAD_CPUTIME_ID), w0 = bench_now_s();
            for (int i = 0; i < naps; i++) {
                struct timespec until = deadline_after_ns(ns);
                sem_clockwait(&never, CLOCK_MONOTONIC, &until);
            }
            cpu[r] = (bench_clock_s(CLOCK_THREAD_CPUTIME_ID) - c0) / naps * 1e6;
            wall[r] = (bench_now_s() - w0) / naps * 1e6;
        }
        double c = bench_median(cpu, rounds); /* (sorts cpu) */
        printf("%d,%.2f,%.2f,%.2f,%.2f\n", ns, c, cpu[0], cpu[rounds - 1], bench_median(wall, rounds));
    }
    free(cpu);
    free(wall);
    return 0;
}
